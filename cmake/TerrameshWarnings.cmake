# Interface target carrying the project's warning flags; every terramesh target links it PRIVATE.
add_library(terramesh_warnings INTERFACE)
target_compile_options(terramesh_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual>)
install(TARGETS terramesh_warnings EXPORT terrameshTargets)

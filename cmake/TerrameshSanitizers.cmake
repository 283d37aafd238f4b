# Sanitizer and fuzzing builds (docs/reliability.md, "Sanitizers" and "Fuzzing").
#
#   -DTERRAMESH_SANITIZE=address,undefined   every target compiled and linked with these sanitizers
#   -DTERRAMESH_BUILD_FUZZERS=ON             the libFuzzer targets of tests/fuzz (clang only); the
#                                            reader libraries get coverage instrumentation
#
# scripts/test_sanitized.sh configures both with clang. Errors are never recovered from
# (-fno-sanitize-recover=all): the first report aborts the test that triggered it.
set(TERRAMESH_SANITIZE "" CACHE STRING
    "Comma-separated sanitizers for every target, e.g. address,undefined (empty: none)")
set(TERRAMESH_SANITIZE_OPTIMIZE "1" CACHE STRING
    "Optimisation level of sanitizer builds (-O<level>); 1 keeps CGAL-heavy tests within CI's time")
option(TERRAMESH_BUILD_FUZZERS "Build the libFuzzer targets of tests/fuzz (clang only)" OFF)

if(TERRAMESH_BUILD_FUZZERS AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(WARNING "terramesh: TERRAMESH_BUILD_FUZZERS needs clang (libFuzzer); fuzz targets are "
                  "left out (configure with -DCMAKE_CXX_COMPILER=clang++)")
  set(TERRAMESH_BUILD_FUZZERS OFF CACHE BOOL "Build the libFuzzer targets of tests/fuzz (clang only)" FORCE)
endif()

if(TERRAMESH_SANITIZE)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "^(Clang|GNU)$")
    message(FATAL_ERROR "terramesh: TERRAMESH_SANITIZE needs clang or gcc")
  endif()
  string(REPLACE ";" "," terramesh_sanitizers "${TERRAMESH_SANITIZE}")
  # Frame pointers for readable stacks; -O<level> after the build type's flags, so it wins. A
  # report's stack needs only file and line: clang's line tables (the last -g flag wins) compile
  # about 12 % faster than full debug information and link smaller objects.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    set(terramesh_debug_info -gline-tables-only)
  else()
    set(terramesh_debug_info -g)
  endif()
  add_compile_options(-fsanitize=${terramesh_sanitizers} -fno-sanitize-recover=all
                      -fno-omit-frame-pointer ${terramesh_debug_info} -O${TERRAMESH_SANITIZE_OPTIMIZE})
  add_link_options(-fsanitize=${terramesh_sanitizers})
  message(STATUS "terramesh: sanitizers ${terramesh_sanitizers}, -O${TERRAMESH_SANITIZE_OPTIMIZE}")
endif()

# terramesh_sanitizer_ignorelist(SOURCE...)
# Compiles only the given sources with cmake/sanitizer_ignorelist.txt: third-party UBSan reports
# that are undefined behaviour in a library's header but harmless, each entry scoped to one
# function and one check, with its reason there. Only the sources that instantiate the listed
# functions get it (today the tests using CGAL's segment traverser as an oracle); anywhere else
# the same report still aborts. clang only: gcc has no ignorelist and would still report it.
set(TERRAMESH_SANITIZER_IGNORELIST "${CMAKE_CURRENT_LIST_DIR}/sanitizer_ignorelist.txt")
function(terramesh_sanitizer_ignorelist)
  if(TERRAMESH_SANITIZE MATCHES "undefined|enum" AND CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    # ccache 4.7 hashes the ignorelist's path, not its contents: a copy named by its MD5 makes an
    # edited list recompile these sources instead of reusing stale objects.
    file(MD5 "${TERRAMESH_SANITIZER_IGNORELIST}" ignorelist_md5)
    set(ignorelist "${CMAKE_BINARY_DIR}/sanitizer_ignorelist-${ignorelist_md5}.txt")
    configure_file("${TERRAMESH_SANITIZER_IGNORELIST}" "${ignorelist}" COPYONLY)
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS "-fsanitize-ignorelist=${ignorelist}")
  endif()
endfunction()

# ctest script: installs the built tree into a temporary prefix, then configures and builds the
# external consumer (consumer/) against it with find_package(terramesh) and runs it (it meshes a
# tiny stream and fails on an empty mesh). Re-uses the built libraries: only the consumer compiles.
# Variables: BINARY_DIR (the terramesh build tree), CONSUMER_DIR, GENERATOR, CXX_COMPILER.
foreach(variable BINARY_DIR CONSUMER_DIR GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "install_consumer_test: -D${variable}=... is required")
  endif()
endforeach()

string(RANDOM LENGTH 10 suffix)
set(work "$ENV{TMPDIR}")
if(NOT work)
  set(work "/tmp")
endif()
set(work "${work}/terramesh_install_test_${suffix}")
file(REMOVE_RECURSE "${work}")

function(run_step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(NOT result EQUAL 0)
    file(REMOVE_RECURSE "${work}")
    message(FATAL_ERROR "install_consumer_test: ${name} failed (${result}):\n${output}")
  endif()
  message(STATUS "${name}: ok")
  set(step_output "${output}" PARENT_SCOPE)
endfunction()

run_step("install" "${CMAKE_COMMAND}" --install "${BINARY_DIR}" --prefix "${work}/prefix")
foreach(installed include/mesher/mesher.h lib/cmake/terramesh/terrameshConfig.cmake
        lib/cmake/terramesh/terrameshConfigVersion.cmake lib/cmake/terramesh/terrameshTargets.cmake)
  if(NOT EXISTS "${work}/prefix/${installed}")
    file(REMOVE_RECURSE "${work}")
    message(FATAL_ERROR "install_consumer_test: ${installed} was not installed")
  endif()
endforeach()
run_step("configure the consumer" "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${work}/build"
         -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
         "-DCMAKE_PREFIX_PATH=${work}/prefix")
run_step("build the consumer" "${CMAKE_COMMAND}" --build "${work}/build")
run_step("run the consumer" "${work}/build/consumer")
message(STATUS "${step_output}")
if(NOT step_output MATCHES "consumer: [0-9]+ vertices, [1-9][0-9]* faces")
  file(REMOVE_RECURSE "${work}")
  message(FATAL_ERROR "install_consumer_test: unexpected consumer output: ${step_output}")
endif()
# Computing layers alone: a consumer without GDAL and yaml-cpp still configures, links and runs.
run_step("configure the layers-only consumer" "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${work}/build_layers"
         -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
         "-DCMAKE_PREFIX_PATH=${work}/prefix" -DLAYERS_ONLY=ON -DCMAKE_DISABLE_FIND_PACKAGE_GDAL=TRUE
         -DCMAKE_DISABLE_FIND_PACKAGE_yaml-cpp=TRUE)
run_step("build the layers-only consumer" "${CMAKE_COMMAND}" --build "${work}/build_layers")
run_step("run the layers-only consumer" "${work}/build_layers/consumer")
file(REMOVE_RECURSE "${work}")

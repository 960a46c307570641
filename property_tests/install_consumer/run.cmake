# ctest's install_consumer: installs the build tree BUILD into a fresh prefix under WORK, then
# configures, builds and runs the consumer project against that prefix alone; then configures
# it with the qex sources QEX as a subproject.
foreach(var BUILD SOURCE WORK SAMPLE QEX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_consumer: -D${var}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
foreach(f include/qex/qex.h include/qex/verify.h bin/qex)
  if(NOT EXISTS ${WORK}/prefix/${f})
    message(FATAL_ERROR "install_consumer: ${f} was not installed")
  endif()
endforeach()
step(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -G Ninja -DCMAKE_BUILD_TYPE=Release
     -DCMAKE_PREFIX_PATH=${WORK}/prefix -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON)
step(${CMAKE_COMMAND} --build ${WORK}/build)
step(${WORK}/build/consumer ${SAMPLE})
step(${WORK}/build/checker_only)
# As a subproject (configuration only: the libraries' targets exist, the CLI, tests and fuzzers
# do not).
step(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/subproject -G Ninja -DQEX_SOURCE_DIR=${QEX})

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
if(EXISTS ${WORK}/build/eigen_consumer)
  step(${WORK}/build/eigen_consumer ${SAMPLE})
endif()
if(EXISTS ${WORK}/build/c_consumer)
  step(${WORK}/build/c_consumer ${SAMPLE} 54)
endif()
# The installed Python package, imported by the interpreter it was built for (PYTHON, when the
# build has the package), from the prefix's dist-packages.
if(PYTHON)
  file(GLOB_RECURSE init ${WORK}/prefix/__init__.py)
  list(FILTER init INCLUDE REGEX "/dist-packages/qex/__init__\\.py$")
  if(NOT init)
    message(FATAL_ERROR "install_consumer: the Python package was not installed")
  endif()
  get_filename_component(qex_dir ${init} DIRECTORY)
  get_filename_component(site ${qex_dir} DIRECTORY)
  step(${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c
       "import qex\nV, F, UV = qex.read_obj('${SAMPLE}')\nr = qex.extract(V, F, UV)\nprint(r)\nassert r.valid")
endif()
# As a subproject (configuration only: the libraries' targets exist, the CLI, tests and fuzzers
# do not).
step(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/subproject -G Ninja -DQEX_SOURCE_DIR=${QEX})

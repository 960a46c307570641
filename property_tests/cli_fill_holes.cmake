# `qex extract` on a shared map that only the last resort makes valid (MAP:
# decimated-knight_miq_18, a hole round a fold between pinned singularities): by default the mesh
# is written, exit code 0, its report names the filled hole, and `qex check --param` at the
# mesh's grid scale agrees; with --no-fill-holes it ends with exit code 5 and no file. Prints
# "skipped:" (the test's SKIP_REGULAR_EXPRESSION) without the shared maps.
if(NOT EXISTS "${MAP}")
  message("skipped: ${MAP} is absent")
  return()
endif()
file(REMOVE ${WORK}.obj ${WORK}_off.obj)
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}.obj --report ${WORK}.json -q RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}.obj)
  message(FATAL_ERROR "by default: exit code ${rc} (expected 0, and the mesh written): ${err}")
endif()
file(READ ${WORK}.json report)
string(JSON scale GET "${report}" fallback grid_scale)
string(JSON count LENGTH "${report}" explanations)
set(filled 0)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  string(JSON kind GET "${report}" explanations ${i} kind)
  if(kind STREQUAL "HoleFilled")
    math(EXPR filled "${filled} + 1")
  endif()
endforeach()
if(filled EQUAL 0)
  message(FATAL_ERROR "by default: no HoleFilled among the ${count} explanations")
endif()
execute_process(COMMAND ${QEX} check --grid-scale ${scale} --param ${MAP} ${WORK}.obj RESULT_VARIABLE rc
                OUTPUT_VARIABLE verdict)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "qex check --grid-scale ${scale}: exit code ${rc}: ${verdict}")
endif()
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}_off.obj --no-fill-holes -q RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 5 OR EXISTS ${WORK}_off.obj)
  message(FATAL_ERROR "with --no-fill-holes: exit code ${rc} (expected 5, and no file): ${err}")
endif()

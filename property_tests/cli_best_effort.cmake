# `qex extract --best-effort` on a shared map that ends with exit code 5 (MAP: fertility_miq_5,
# which collapses a handle): without the flag no file is written, the report names the collapsed
# handle first and no refinement is tried; with it the mesh closest to valid is written (the
# refined mesh that loses only the handle), exit code 5 still, and `qex check --grid-scale`
# agrees that only the topology is lost. Prints "skipped:" (the test's SKIP_REGULAR_EXPRESSION)
# without the shared maps.
if(NOT EXISTS "${MAP}")
  message("skipped: ${MAP} is absent")
  return()
endif()
file(REMOVE ${WORK}.obj ${WORK}_best.obj)
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}.obj --report ${WORK}.json -q RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 5 OR EXISTS ${WORK}.obj)
  message(FATAL_ERROR "without --best-effort: exit code ${rc} (expected 5, and no file): ${err}")
endif()
file(READ ${WORK}.json report)
string(JSON first GET "${report}" defects 0 kind)
string(JSON tried GET "${report}" fallback refinements_tried)
if(NOT first STREQUAL "MapCollapsesHandle" OR NOT tried EQUAL 0)
  message(FATAL_ERROR "without --best-effort: first defect ${first}, ${tried} refinements tried")
endif()
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}_best.obj --report ${WORK}_best.json --best-effort -q
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 5 OR NOT EXISTS ${WORK}_best.obj OR NOT err MATCHES "BestEffortMesh")
  message(FATAL_ERROR "with --best-effort: exit code ${rc} (expected 5, and the mesh written): ${err}")
endif()
file(READ ${WORK}_best.json report)
string(JSON scale GET "${report}" fallback grid_scale)
string(JSON first GET "${report}" defects 0 kind)
string(JSON violations LENGTH "${report}" check violations)
string(JSON kind GET "${report}" check violations 0 kind)
if(NOT (scale EQUAL 4 OR scale EQUAL 8) OR NOT first STREQUAL "MapCollapsesHandle" OR NOT violations EQUAL 1
   OR NOT kind STREQUAL "EulerMismatch")
  message(FATAL_ERROR "with --best-effort: grid scale ${scale}, first defect ${first}, ${violations} violations (${kind})")
endif()
execute_process(COMMAND ${QEX} check --json --grid-scale ${scale} --param ${MAP} ${WORK}_best.obj RESULT_VARIABLE rc
                OUTPUT_VARIABLE verdict)
string(JSON violations LENGTH "${verdict}" violations)
string(JSON kind GET "${verdict}" violations 0 kind)
if(NOT rc EQUAL 6 OR NOT violations EQUAL 1 OR NOT kind STREQUAL "EulerMismatch")
  message(FATAL_ERROR "qex check: exit code ${rc}, ${violations} violations (${kind})")
endif()

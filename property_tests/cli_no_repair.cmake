# `qex extract --no-repair` on a shared map with fold-overs (MAP: duck_miq_8): the fast,
# uncertified choice starts at the paper's handling. Its report names the as-given rung and no
# repaired triangle, the default's names the repaired rung and some, and `qex check --param`
# accepts the --no-repair mesh (the CLI never writes a mesh its checker rejects). Prints
# "skipped:" (the test's SKIP_REGULAR_EXPRESSION) without the shared maps.
if(NOT EXISTS "${MAP}")
  message("skipped: ${MAP} is absent")
  return()
endif()
foreach(mode default no_repair)
  set(flag "")
  if(mode STREQUAL "no_repair")
    set(flag "--no-repair")
  endif()
  file(REMOVE ${WORK}_${mode}.obj)
  execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}_${mode}.obj --report ${WORK}_${mode}.json ${flag} -q
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}_${mode}.obj)
    message(FATAL_ERROR "${mode}: exit code ${rc} (expected 0, and the mesh written): ${err}")
  endif()
  file(READ ${WORK}_${mode}.json report)
  string(JSON rung_${mode} GET "${report}" fallback rung)
  string(JSON repaired_${mode} GET "${report}" repair repaired_triangles)
endforeach()
if(NOT rung_default STREQUAL "repaired" OR repaired_default EQUAL 0)
  message(FATAL_ERROR "default: rung ${rung_default}, ${repaired_default} repaired triangles (expected the repair)")
endif()
if(NOT rung_no_repair STREQUAL "as-given" OR NOT repaired_no_repair EQUAL 0)
  message(FATAL_ERROR "--no-repair: rung ${rung_no_repair}, ${repaired_no_repair} repaired triangles")
endif()
execute_process(COMMAND ${QEX} check --param ${MAP} ${WORK}_no_repair.obj RESULT_VARIABLE rc OUTPUT_VARIABLE verdict)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "qex check of the --no-repair mesh: exit code ${rc}: ${verdict}")
endif()

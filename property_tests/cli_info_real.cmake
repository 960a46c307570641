# `qex info` on a shared real map MAP against two other judges: its flipped triangles must be
# the exact count `qex check` reports for the map (located mode, on the mesh `qex extract`
# writes), and its singularities as many as the extractor's sanitized map has; `qex check`
# accepts that mesh and names the map's fold-over regions. Prints "skipped:" (the test's
# SKIP_REGULAR_EXPRESSION) without the shared maps.
if(NOT EXISTS "${MAP}")
  message("skipped: ${MAP} is absent")
  return()
endif()
execute_process(COMMAND ${QEX} info ${MAP} --json RESULT_VARIABLE rc OUTPUT_VARIABLE info ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "qex info: exit code ${rc}: ${err}")
endif()
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}.obj --report ${WORK}.json -q RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "qex extract: exit code ${rc}: ${err}")
endif()
file(READ ${WORK}.json report)
string(JSON scale GET "${report}" fallback grid_scale)
execute_process(COMMAND ${QEX} check --json --grid-scale ${scale} --param ${MAP} ${WORK}.obj RESULT_VARIABLE check_rc
                OUTPUT_VARIABLE check)
string(JSON flipped GET "${info}" flipped_triangles)
string(JSON check_flipped GET "${check}" located map_flipped_triangles)
if(NOT flipped EQUAL check_flipped)
  message(FATAL_ERROR "qex info: ${flipped} flipped triangles, qex check: ${check_flipped}")
endif()
# qex's own valid output passes `qex check` against the raw map: where the repair moved the map,
# in the raw map's fold-over regions (named in the verdict), judged on the surface only.
if(NOT check_rc EQUAL 0)
  message(FATAL_ERROR "qex check rejects qex's own valid output (exit code ${check_rc})")
endif()
string(JSON regions LENGTH "${check}" located fold_regions)
if(flipped GREATER 0 AND regions EQUAL 0)
  message(FATAL_ERROR "qex check names no fold-over region on a map with ${flipped} flipped triangles")
endif()
string(JSON singular LENGTH "${info}" singularities)
string(JSON sanitized GET "${info}" sanitized_singularities)
if(NOT singular EQUAL sanitized)
  message(FATAL_ERROR "qex info: ${singular} singularities on the given map, ${sanitized} after sanitization")
endif()
foreach(key euler boundary_loops)
  string(JSON a GET "${info}" ${key})
  string(JSON b GET "${check}" input ${key})
  if(NOT a EQUAL b)
    message(FATAL_ERROR "${key}: qex info ${a}, qex check ${b}")
  endif()
endforeach()
message("${MAP}: ${flipped} flipped triangles, ${singular} singularities, as qex check and the extractor say; "
        "qex check accepts the output (${regions} fold-over regions)")

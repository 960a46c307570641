# `qex extract --certificate` then `qex check --certificate` on a shared map with fold-overs
# (MAP: fandisk): the certificate is written beside the mesh, the mesh is valid on it with fewer
# undecided triangles than on the given map, a certificate of another grid scale is rejected
# (exit code 6, CertificateMismatch), a malformed one refused with its line (exit code 3), and
# --grid-scale with --certificate, or a certificate in the mesh's file, is a bad command line
# (exit code 1). Prints "skipped:" (the test's SKIP_REGULAR_EXPRESSION) without the shared maps.
if(NOT EXISTS "${MAP}")
  message("skipped: ${MAP} is absent")
  return()
endif()
file(REMOVE ${WORK}.obj ${WORK}.cert.obj)
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}.obj --certificate ${WORK}.cert.obj RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}.cert.obj OR NOT out MATCHES "certificate: [1-9][0-9]* repaired triangles")
  message(FATAL_ERROR "extract --certificate: exit code ${rc}: ${out} ${err}")
endif()
execute_process(COMMAND ${QEX} check --param ${MAP} ${WORK}.obj --certificate ${WORK}.cert.obj RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "judged on the certificate" OR NOT out MATCHES "\nVALID")
  message(FATAL_ERROR "check --certificate: exit code ${rc}: ${out}")
endif()
execute_process(COMMAND ${QEX} check --json --param ${MAP} ${WORK}.obj --certificate ${WORK}.cert.obj OUTPUT_VARIABLE on)
execute_process(COMMAND ${QEX} check --json --param ${MAP} ${WORK}.obj OUTPUT_VARIABLE plain)
string(JSON judged GET "${on}" certificate judged_on)
string(JSON und_on GET "${on}" located singularities undecided_triangles)
string(JSON und_plain GET "${plain}" located singularities undecided_triangles)
if(NOT judged OR NOT und_on LESS und_plain)
  message(FATAL_ERROR "check --certificate --json: judged_on ${judged}, undecided ${und_on} (without: ${und_plain})")
endif()
file(READ ${WORK}.cert.obj cert)
string(REPLACE "# grid_scale 1\n" "# grid_scale 2\n" scaled "${cert}")
file(WRITE ${WORK}.scaled.obj "${scaled}")
execute_process(COMMAND ${QEX} check --param ${MAP} ${WORK}.obj --certificate ${WORK}.scaled.obj RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
if(NOT rc EQUAL 6 OR NOT out MATCHES "CertificateMismatch" OR NOT out MATCHES "does not hold")
  message(FATAL_ERROR "a certificate of another grid scale: exit code ${rc}: ${out}")
endif()
string(REPLACE "# qex certificate 1\n" "# qex certificate 9\n" other "${cert}")
file(WRITE ${WORK}.other.obj "${other}")
execute_process(COMMAND ${QEX} check --param ${MAP} ${WORK}.obj --certificate ${WORK}.other.obj RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 3 OR NOT err MATCHES "line 1")
  message(FATAL_ERROR "a malformed certificate: exit code ${rc}: ${err}")
endif()
execute_process(COMMAND ${QEX} check --param ${MAP} ${WORK}.obj --certificate ${WORK}.cert.obj --grid-scale 2
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "--grid-scale with --certificate: exit code ${rc} (expected 1)")
endif()
execute_process(COMMAND ${QEX} extract ${MAP} -o ${WORK}.same.obj --certificate ${WORK}.same.obj -q
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 1 OR EXISTS ${WORK}.same.obj)
  message(FATAL_ERROR "--certificate naming the mesh's file: exit code ${rc} (expected 1, nothing written)")
endif()

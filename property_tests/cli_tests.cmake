# Included by property_tests/CMakeLists.txt.
# The CLI end to end: the README's sample, the oracle on its output, and one exit code per
# failure family (2 file, 3 malformed OBJ, 4 invalid input, 6 rejected by `qex check`).
if(TARGET qex_cli)
  set(sample ${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/valid/cube_n3_k4.obj)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/cli_out)
  file(MAKE_DIRECTORY ${out})
  add_test(NAME cli_extract_sample COMMAND qex_cli extract ${sample} -o ${out}/cube.obj --report ${out}/cube.json)
  add_test(NAME cli_check_own_output COMMAND qex_cli check --param ${sample} ${out}/cube.obj)
  set_tests_properties(cli_check_own_output PROPERTIES DEPENDS cli_extract_sample)
  # Double precision judged as such (--strict), and the JSON verdict with its precision.
  add_test(NAME cli_check_own_output_strict COMMAND qex_cli check --strict --json --param ${sample} ${out}/cube.obj)
  set_tests_properties(cli_check_own_output_strict PROPERTIES DEPENDS cli_extract_sample
                       PASS_REGULAR_EXPRESSION "\"position_digits\": 17")
  # The cube's mesh judged against a torus map: rejected (exit code 6), the Euler characteristic named.
  add_test(NAME cli_check_rejects_other_map
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DIN=${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/valid/torus_n2_k3.obj
                   -DMESH=${out}/cube.obj -DOUT=${out}/r.obj -DEXPECT=6 -DMESSAGE=EulerMismatch
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  set_tests_properties(cli_check_rejects_other_map PROPERTIES DEPENDS cli_extract_sample)
  # Exit codes, a message and no partial output file, asserted by a tiny CMake script.
  foreach(case "missing_file;2;${out}/does_not_exist.obj" "malformed;3;${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/malformed/missing_vt.obj"
                "invalid_input;4;${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/malformed/nonmanifold.obj"
                "inconsistent_seam;4;${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/malformed/inconsistent_seam.obj")
    list(GET case 0 name)
    list(GET case 1 code)
    list(GET case 2 file)
    add_test(NAME cli_exit_code_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DIN=${file} -DOUT=${out}/y.obj -DEXPECT=${code}
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  endforeach()
  # `qex check` against a map that extraction would reject: an error, not a verdict.
  add_test(NAME cli_check_exit_code_invalid_map
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DIN=${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/malformed/nonmanifold.obj
                   -DMESH=${out}/cube.obj -DOUT=${out}/z.obj -DEXPECT=4 -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  set_tests_properties(cli_check_exit_code_invalid_map PROPERTIES DEPENDS cli_extract_sample)
  # `qex layout` of the sample's mesh, judged against its map first: the cube's 6 patches; the JSON
  # and the OBJ with a group per patch; against another map: exit code 6.
  add_test(NAME cli_layout_sample
           COMMAND qex_cli layout ${out}/cube.obj --param ${sample} -o ${out}/cube_layout.json --obj ${out}/cube_patches.obj)
  set_tests_properties(cli_layout_sample PROPERTIES DEPENDS cli_extract_sample
                       PASS_REGULAR_EXPRESSION "layout: 6 patches, 12 separatrices \\(12 HeadOn\\), 8 special vertices")
  add_test(NAME cli_layout_rejects_other_map
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=layout -DIN=${out}/cube.obj
                   "-DEXTRA=--param|${PROJECT_SOURCE_DIR}/corpus/fuzz_obj/valid/torus_n2_k3.obj|-o|${out}/l.json"
                   -DOUT=${out}/l.json -DEXPECT=6 -DMESSAGE=EulerMismatch -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  set_tests_properties(cli_layout_rejects_other_map PROPERTIES DEPENDS cli_extract_sample)
  add_test(NAME cli_draw_layout COMMAND qex_cli draw ${sample} --quads ${out}/cube.obj --layout -o ${out}/cube_layout.svg)
  set_tests_properties(cli_draw_layout PROPERTIES DEPENDS cli_extract_sample)
  # --version names the version and the commit; --help lists every subcommand with an example.
  add_test(NAME cli_version COMMAND qex_cli --version)
  set_tests_properties(cli_version PROPERTIES PASS_REGULAR_EXPRESSION "qex ${PROJECT_VERSION} \\(commit [0-9a-z-]+\\)")
  add_test(NAME cli_help COMMAND qex_cli --help)
  set_tests_properties(cli_help PROPERTIES PASS_REGULAR_EXPRESSION
                       "extract .*check .*info .*draw .*batch .*qex extract .*qex check .*qex info .*qex draw .*qex batch ")

  # `qex info`: the generated maps' known topology, singularities and fold-overs; bad input.
  set(corpus ${PROJECT_SOURCE_DIR}/corpus/fuzz_obj)
  add_test(NAME cli_info_cube
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> "-DARGS=info|${sample}|--json"
                   "-DCHECKS=vertices=98|triangles=192|euler=2|genus=0|components=1|boundary_loops=0|flipped_triangles=0|degenerate_triangles=0|signed_uv_area=54.0|fold_regions.length=0|singularities.length=8|singularities.0.valence=3|singularities.7.valence=3|singularities.0.in_fold=OFF|sanitized_singularities=8"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  add_test(NAME cli_info_annulus
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> "-DARGS=info|${corpus}/valid/annulus_n1_k2.obj|--json"
                   "-DCHECKS=euler=0|boundary_loops=2|genus=0|singularities.length=0|signed_uv_area=12.0"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  add_test(NAME cli_info_torus
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> "-DARGS=info|${corpus}/valid/torus_n2_k3.obj|--json"
                   "-DCHECKS=euler=0|boundary_loops=0|genus=1|singularities.length=0|fold_regions.length=0"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  add_test(NAME cli_info_fold
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> "-DARGS=info|${corpus}/folds/fold_over_grid_point.obj|--json"
                   "-DCHECKS=flipped_triangles=2|fold_regions.length=1|fold_regions.0.triangles.length=2|fold_regions.0.triangle_count=2|fold_regions.0.triangles.0=3|fold_regions.0.uv_area<0|fold_regions.0.grid_box.length=2"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  add_test(NAME cli_info_degenerate
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> "-DARGS=info|${corpus}/degenerate/zero_area.obj|--json"
                   "-DCHECKS=flipped_triangles=0|degenerate_triangles=1|fold_regions.length=1|fold_regions.0.triangles.length=1|fold_regions.0.triangles.0=5"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  # A map the extractor rejects (transitions that do not close) is described, then refused.
  add_test(NAME cli_info_inconsistent_map
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DEXPECT_RC=4
                   "-DARGS=info|${corpus}/merged/00182c1940ef6775c78d82b37b8760e7fa0803e8|--json"
                   "-DCHECKS=error.code=InconsistentMap|error.element=17|triangles>0|euler<3"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  foreach(case "missing_file;2;${out}/does_not_exist.obj" "malformed;3;${corpus}/malformed/missing_vt.obj"
                "invalid_input;4;${corpus}/malformed/nonmanifold.obj")
    list(GET case 0 name)
    list(GET case 1 code)
    list(GET case 2 file)
    add_test(NAME cli_info_exit_code_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=info -DIN=${file} -DEXTRA=--json -DOUT=${out}/none
                     -DEXPECT=${code} -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  endforeach()
  # On shared real maps: flipped triangles as `qex check` counts them, singularities as the
  # extractor's sanitized map has them.
  foreach(map paper/fandisk_param paper/duck_miq_8_param miq/3holes_miq_10_param)
    string(REPLACE "/" "_" name ${map})
    add_test(NAME cli_info_real_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DMAP=${QEX_SHARED_DIR}/meshes/${map}.obj
                     -DWORK=${out}/info_${name} -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_info_real.cmake)
    set_tests_properties(cli_info_real_${name} PROPERTIES SKIP_REGULAR_EXPRESSION "skipped:" TIMEOUT 300)
  endforeach()

  # --best-effort on the shared map that collapses a handle: the mesh closest to valid, exit code 5.
  add_test(NAME cli_extract_best_effort
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DMAP=${QEX_SHARED_DIR}/meshes/miq/fertility_miq_5_param.obj
                   -DWORK=${out}/best_effort -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_best_effort.cmake)
  set_tests_properties(cli_extract_best_effort PROPERTIES SKIP_REGULAR_EXPRESSION "skipped:" TIMEOUT 300)

  # The last resort on the shared map it makes valid, and --no-fill-holes without it.
  add_test(NAME cli_extract_fill_holes
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli>
                   -DMAP=${QEX_SHARED_DIR}/meshes/miq-more/decimated-knight_miq_18_param.obj
                   -DWORK=${out}/fill_holes -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_fill_holes.cmake)
  set_tests_properties(cli_extract_fill_holes PROPERTIES SKIP_REGULAR_EXPRESSION "skipped:" TIMEOUT 300)

  # --no-repair: the paper's handling alone (fast, uncertified), against the certified default.
  add_test(NAME cli_extract_no_repair
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli>
                   -DMAP=${QEX_SHARED_DIR}/meshes/paper/duck_miq_8_param.obj
                   -DWORK=${out}/no_repair -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_no_repair.cmake)
  set_tests_properties(cli_extract_no_repair PROPERTIES SKIP_REGULAR_EXPRESSION "skipped:" TIMEOUT 120)

  # --certificate: extract writes the repaired map beside the mesh, check judges the mesh on it.
  add_test(NAME cli_certificate
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DMAP=${QEX_SHARED_DIR}/meshes/paper/fandisk_param.obj
                   -DWORK=${out}/certificate -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_certificate.cmake)
  set_tests_properties(cli_certificate PROPERTIES SKIP_REGULAR_EXPRESSION "skipped:" TIMEOUT 300)

  # --snap-boundary and --features on a square whose right boundary maps off its iso-line: 2
  # quads as given, 4 once the boundary (or the right edges as features) is snapped.
  set(square ${corpus}/valid/square_off_boundary.obj)
  file(WRITE ${out}/right.features "# the right boundary of square_off_boundary.obj\n6 7\n7 8 # second edge\n\n")
  file(WRITE ${out}/not_an_edge.features "6 8\n")
  file(WRITE ${out}/out_of_range.features "6 7\n7 9\n")
  file(WRITE ${out}/malformed.features "6 7\n7 x\n")
  file(WRITE ${out}/huge_index.features "6 7\n99999999999999999999 7\n")
  file(WRITE ${out}/fraction.features "6 7\n7 8.0\n")
  foreach(case "as_given;;2" "snap_boundary;|--snap-boundary;4" "features;|--features|${out}/right.features;4")
    list(GET case 0 name)
    list(GET case 1 extra)
    list(GET case 2 faces)
    add_test(NAME cli_extract_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DJSON_FILE=${out}/square_${name}.json
                     "-DARGS=extract|${square}|-o|${out}/square_${name}.obj|--report|${out}/square_${name}.json${extra}"
                     "-DCHECKS=check.valid=ON|check.faces=${faces}" -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_json.cmake)
  endforeach()
  foreach(case "not_an_edge;4;not an edge" "out_of_range;4;out of range" "malformed;3;line 2"
               "missing;2;cannot open" "huge_index;3;line 2" "fraction;3;line 2")
    list(GET case 0 name)
    list(GET case 1 code)
    list(GET case 2 message)
    add_test(NAME cli_features_exit_code_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=extract -DIN=${square} "-DMESSAGE=${message}"
                     "-DEXTRA=-o|${out}/f_${name}.obj|--features|${out}/${name}.features" -DOUT=${out}/f_${name}.obj
                     -DEXPECT=${code} -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  endforeach()

  # PLY maps (ASCII, both byte orders) give the very mesh of the OBJ map; a PLY quad mesh out, judged
  # by `qex check`; malformed PLY files: exit code 3, the place named, no output file.
  set(ply ${PROJECT_SOURCE_DIR}/corpus/fuzz_ply)
  foreach(kind ascii le be)
    add_test(NAME cli_extract_ply_${kind}
             COMMAND sh -c "\"$1\" extract \"$2\" -o \"$3\" -q && cmp \"$3\" \"$4\""
                     qex $<TARGET_FILE:qex_cli> ${ply}/valid/cube_n3_k4_${kind}.ply ${out}/cube_from_${kind}.obj ${out}/cube.obj)
    set_tests_properties(cli_extract_ply_${kind} PROPERTIES DEPENDS cli_extract_sample)
  endforeach()
  add_test(NAME cli_extract_to_ply COMMAND qex_cli extract ${sample} -o ${out}/cube.ply -q)
  add_test(NAME cli_check_ply COMMAND qex_cli check --param ${ply}/valid/cube_n3_k4_ascii.ply ${out}/cube.ply)
  set_tests_properties(cli_check_ply PROPERTIES DEPENDS cli_extract_to_ply PASS_REGULAR_EXPRESSION "VALID")
  foreach(case "truncated_binary;3;byte [0-9]+: element face" "index_out_of_range;3;vertex index 99"
               "quad_face;3;face 0 has 4" "no_uvs;3;no UVs" "huge_count;3;cannot fit" "no_end_header;3;header line 11: unknown keyword"
               "bad_number;3;element vertex 3, property y" "empty;3;header line 1: the header ends")
    list(GET case 0 name)
    list(GET case 1 code)
    list(GET case 2 message)
    add_test(NAME cli_ply_exit_code_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DIN=${ply}/malformed/${name}.ply -DOUT=${out}/p_${name}.ply
                     "-DMESSAGE=${message}" -DEXPECT=${code} -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  endforeach()
  # The fuzz finding of issue 35, a 96-digit vertex index (undefined behaviour once): exit code 3
  # from `qex extract` and `qex info`, the place named (corpus/fuzz_ply/regressions/NOTES.md).
  set(finding ${ply}/regressions/ff5b116df7be31e6.ply)
  set(finding_message "byte 385: element face 0, property vertex_index: vertex index 6[.]666666666666667e[+]95 out of range")
  add_test(NAME cli_ply_exit_code_huge_index
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DIN=${finding} -DOUT=${out}/p_huge_index.obj
                   "-DMESSAGE=${finding_message}" -DEXPECT=3 -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  add_test(NAME cli_info_exit_code_huge_index
           COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=info -DIN=${finding} -DEXTRA=--json
                   -DOUT=${out}/none "-DMESSAGE=${finding_message}" -DEXPECT=3
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  # Numbers on the command line: NaN, and values past a range (or past 2^63), refused (exit code
  # 1), neither let through nor saturated.
  foreach(case "uv_tolerance_nan;check;${out}/cube.obj;--param|${sample}|--uv-tolerance|nan;not a finite number"
               "uv_tolerance_huge;check;${out}/cube.obj;--param|${sample}|--uv-tolerance|1e308;not in range"
               "distance_tolerance_nan;check;${out}/cube.obj;--param|${sample}|--distance-tolerance|nan;not a finite"
               "radius_nan;draw;${sample};-o|${out}/radius_nan.svg|--around|3|--radius|nan;not a finite number"
               "around_past_2_63;draw;${sample};-o|${out}/around.svg|--around|99999999999999999999;99999999999999999999")
    list(GET case 0 name)
    list(GET case 1 sub)
    list(GET case 2 file)
    list(GET case 3 extra)
    list(GET case 4 message)
    add_test(NAME cli_option_refused_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=${sub} -DIN=${file} "-DEXTRA=${extra}"
                     -DOUT=${out}/option_${name} "-DMESSAGE=${message}" -DEXPECT=1
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
  endforeach()
  # `qex draw --report R.json`: a defect's index that is no integer (1e96 was undefined behaviour,
  # a string an uncaught exception): exit code 3, the defect named.
  file(WRITE ${out}/report_huge_index.json "{\"defects\": [{\"kind\": \"K\", \"output_face\": 1e96}]}\n")
  file(WRITE ${out}/report_string_index.json "{\"defects\": [{}, {\"input_element\": \"7\"}]}\n")
  foreach(case "huge_index;defect 0: output_face 1e[+]96 is not an index"
               "string_index;defect 1: input_element \"7\" is not an index")
    list(GET case 0 name)
    list(GET case 1 message)
    add_test(NAME cli_draw_report_refused_${name}
             COMMAND ${CMAKE_COMMAND} -DQEX=$<TARGET_FILE:qex_cli> -DSUB=draw -DIN=${sample} "-DMESSAGE=${message}"
                     "-DEXTRA=--quads|${out}/cube.obj|--report|${out}/report_${name}.json|-o|${out}/report_${name}.svg"
                     -DOUT=${out}/report_${name}.svg -DEXPECT=3 -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_exit_code.cmake)
    set_tests_properties(cli_draw_report_refused_${name} PROPERTIES DEPENDS cli_extract_sample)
  endforeach()

  # `qex draw` (PNG through rsvg-convert where installed) and `qex batch` against single runs.
  find_package(Python3 COMPONENTS Interpreter)
  if(Python3_Interpreter_FOUND)
    add_test(NAME cli_draw COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/cli_draw_test.py
                                   $<TARGET_FILE:qex_cli> ${sample} ${out}/draw 8
                                   ${QEX_SHARED_DIR}/meshes/miq-more/face_miq_10_param.obj)
    # `qex check --report R.json --svg R.svg`: the verdict file and its picture, on the sample's
    # output and on a copy with a quad dropped and an edge rotated.
    add_test(NAME cli_check_report COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/cli_check_report_test.py
                                           $<TARGET_FILE:qex_cli> ${sample} ${out}/check_report)
    set(batch_maps ${sample} ${corpus}/valid/torus_n2_k3.obj ${corpus}/valid/annulus_n1_k2.obj ${square}
                   ${corpus}/folds/fold_over_grid_point.obj ${corpus}/malformed/missing_vt.obj)
    foreach(map paper/fandisk_param paper/duck_miq_8_param paper/duck_miq_16_param miq/3holes_miq_5_param)
      list(APPEND batch_maps ${QEX_SHARED_DIR}/meshes/${map}.obj) # left out where absent
    endforeach()
    add_test(NAME cli_batch COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/cli_batch_test.py
                                    $<TARGET_FILE:qex_cli> ${out}/batch ${batch_maps})
    set_tests_properties(cli_batch PROPERTIES TIMEOUT 900)
    # `qex conform`: qex extract right on every known and hostile case (but the named known
    # wrong ones), and qex_broken_extractor's every way of breaking classified as it should be.
    add_test(NAME cli_conform COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/cli_conform_test.py
                                      $<TARGET_FILE:qex_cli> $<TARGET_FILE:qex_broken_extractor> ${out}/conform)
    set_tests_properties(cli_conform PROPERTIES TIMEOUT 300)
  endif()

  # The program's heap policy sets 1 GiB of address space aside; under a limit that denies it,
  # the run goes on without it and writes the same mesh. (Sanitizers reserve far more address
  # space than the limit allows, so their builds skip this.)
  if(NOT QEX_SANITIZE AND NOT QEX_LIBFUZZER)
    add_test(NAME cli_extract_under_address_limit
             COMMAND sh -c "ulimit -v 400000 && \"$1\" extract \"$2\" -o \"$3\" -q && cmp \"$3\" \"$4\""
                     qex $<TARGET_FILE:qex_cli> ${sample} ${out}/cube_limited.obj ${out}/cube.obj)
    set_tests_properties(cli_extract_under_address_limit PROPERTIES DEPENDS cli_extract_sample)
  endif()
endif()

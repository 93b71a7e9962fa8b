# Scene reader (src/scene.c and its files, src/scene_impl.h): the reader checked value by value (test_scene, on 1 and 2 ranks), and
# clothsim refusing each bad scene of tests/bad_input/ with a message that names the file, the line, the key and
# what was expected (expect_error.sh reads the expected text from the "# expect:" lines of each file, and the exit status,
# which every test requires, from its "# status:" line: 2 for a bad scene, 3 for a file that cannot be read, a
# malformed mesh included; measured 2026-11-29: 60 files exit 2, 7 exit 3).

clothsim_add_test_program(test_scene test_scene.c)
clothsim_add_mpi_test(scene_read_1 1 $<TARGET_FILE:test_scene>)
clothsim_add_mpi_test(scene_read_2 2 $<TARGET_FILE:test_scene>)

set(scene_error_tests "")
file(GLOB scene_bad_inputs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/bad_input/*.yaml)
foreach(scene ${scene_bad_inputs})
  get_filename_component(case ${scene} NAME_WE)
  clothsim_add_script_test(scene_bad_${case} expect_error.sh 1 tests/bad_input/${case}.yaml)
  list(APPEND scene_error_tests scene_bad_${case})
endforeach()
# Every rank parses the same bytes, so every rank fails alike and the message is printed once.
clothsim_add_script_test(scene_bad_negative_shear_2ranks expect_error.sh 2 tests/bad_input/negative_shear.yaml)
# Only rank 0 opens the file; the others must fail with it, not wait for it.
clothsim_add_script_test(scene_bad_missing_file expect_error.sh --status 3 1 tests/bad_input/no_such_scene.yaml "cannot read the file (No such file or directory)")
clothsim_add_script_test(scene_bad_missing_file_2ranks expect_error.sh --status 3 2 tests/bad_input/no_such_scene.yaml "cannot read the file (No such file or directory)")
list(APPEND scene_error_tests scene_bad_negative_shear_2ranks scene_bad_missing_file scene_bad_missing_file_2ranks)
set_property(TEST ${scene_error_tests} APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(${scene_error_tests} PROPERTIES TIMEOUT 150)
set_tests_properties(scene_bad_negative_shear_2ranks scene_bad_missing_file_2ranks PROPERTIES PROCESSORS 2)

# A piece rolled onto a cone (wrap: {apex, axis}) sits where the cone's development puts it (tests/drivers/cone_wrap.sh).
clothsim_add_script_test(scene_cone_wrap cone_wrap.sh)
set_tests_properties(scene_cone_wrap PROPERTIES PROCESSORS 1)

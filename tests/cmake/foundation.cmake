# The binary end to end (tests/drivers/check_run_end_to_end.sh: progress line, "Done:", the final checkpoint read
# with h5py, 1 and 2 ranks giving the same positions) and the warning about unused options (src/main.c).
clothsim_add_script_test(run_end_to_end_np1 check_run_end_to_end.sh ${MPIEXEC_EXECUTABLE} 1
                         ${CMAKE_BINARY_DIR}/test-output/end_to_end_np1)
clothsim_add_script_test(run_end_to_end_np2 check_run_end_to_end.sh ${MPIEXEC_EXECUTABLE} 2
                         ${CMAKE_BINARY_DIR}/test-output/end_to_end_np2 ${CMAKE_BINARY_DIR}/test-output/end_to_end_np1)
set_tests_properties(run_end_to_end_np1 PROPERTIES FIXTURES_SETUP end_to_end_np1)
set_tests_properties(run_end_to_end_np2 PROPERTIES FIXTURES_REQUIRED end_to_end_np1 PROCESSORS 2)
clothsim_add_script_test(run_unused_option_warning check_unused_option.sh ${MPIEXEC_EXECUTABLE}
                         ${CMAKE_BINARY_DIR}/test-output/unused_option)
# -help lists every option after the set-up and stops without running or writing (tests/drivers/check_help.sh).
clothsim_add_script_test(run_help check_help.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_BINARY_DIR}/test-output/help)
set_tests_properties(run_help PROPERTIES PROCESSORS 2)
set_tests_properties(run_end_to_end_np1 run_end_to_end_np2 run_unused_option_warning run_help PROPERTIES TIMEOUT 120)

# -gravity_ramp: a freely falling sheet follows the implicit-Euler recurrence of the ramped gravity to round-off
# (measured: 1.7943e-3 m, relative difference 6.3e-14), and a scene with seams refuses the option with a clear message.
clothsim_add_script_test(run_gravity_ramp gravity_ramp.sh)

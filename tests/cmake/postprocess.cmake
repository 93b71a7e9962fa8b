# postprocess/ and the scaling driver of jobs/ on a tiny real run (tests/drivers/postprocess_tools.sh).
foreach(part energy render movie scaling)
  clothsim_add_script_test(postprocess_${part} postprocess_tools.sh ${CMAKE_CURRENT_BINARY_DIR}/postprocess_${part} ${part})
  set_tests_properties(postprocess_${part} PROPERTIES TIMEOUT 90)
endforeach()
set_tests_properties(postprocess_scaling PROPERTIES PROCESSORS 2)
# Contact counts of the output frames against the positions, and postprocess/contacts.py (tests/drivers/check_contacts.sh).
clothsim_add_script_test(postprocess_contacts check_contacts.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/postprocess_contacts)
set_tests_properties(postprocess_contacts PROPERTIES TIMEOUT 120 PROCESSORS 2)

# The performance benchmark's driver and report (jobs/bench.sh, jobs/bench_report.py, build/stream_triad) on a small sheet.
clothsim_add_script_test(bench_driver check_bench.sh ${CMAKE_CURRENT_BINARY_DIR}/bench_driver)

# postprocess/cusick_convergence.py (drape coefficient against grid, jobs/validation.sh) on hand-made trial files.
clothsim_add_script_test(postprocess_cusick_convergence check_cusick_convergence.sh ${CMAKE_CURRENT_BINARY_DIR}/postprocess_cusick_convergence)

# The performance model (jobs/perf_model.py, docs/jobs.md) on its committed calibration runs.
clothsim_add_script_test(perf_model_calibration check_perf_model.sh ${CMAKE_CURRENT_BINARY_DIR}/perf_model_calibration)
set_tests_properties(perf_model_calibration PROPERTIES TIMEOUT 60)

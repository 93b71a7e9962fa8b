# A diverging run stops cleanly with its last good state; a recoverable failure is recovered by halving.
clothsim_add_script_test(divergence_handling robustness.sh)
# A diverging run with self-collision stops like one without it; absurd thicknesses stop with a clear error (no hang).
clothsim_add_script_test(divergence_handling_self_collision robustness_self_collision.sh)
set_tests_properties(divergence_handling_self_collision PROPERTIES TIMEOUT 300)

# A failed step is undone completely, sliders and held contacts included (tests/check_failed_step_rollback.sh, 2 ranks):
# the checkpoint written after a divergence is bit-identical to that of a run stopped at the last good step.
clothsim_add_script_test(failed_step_rollback check_failed_step_rollback.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/failed_step_rollback)
set_tests_properties(failed_step_rollback PROPERTIES PROCESSORS 2)

# A diverging run stops cleanly with its last good state; a recoverable failure is recovered by halving.
clothsim_add_script_test(divergence_handling robustness.sh)
# A diverging run with self-collision stops like one without it; absurd thicknesses stop with a clear error (no hang).
clothsim_add_script_test(divergence_handling_self_collision robustness_self_collision.sh)
set_tests_properties(divergence_handling_self_collision PROPERTIES TIMEOUT 300)

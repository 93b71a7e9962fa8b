# A diverging run stops cleanly with its last good state; a recoverable failure is recovered by halving.
clothsim_add_script_test(divergence_handling robustness.sh)

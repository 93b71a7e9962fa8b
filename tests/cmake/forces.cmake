# Element and system Jacobians against finite differences.
clothsim_add_test_program(test_forces test_forces.c)
clothsim_add_mpi_test(forces_jacobian_fd 1 $<TARGET_FILE:test_forces>)
clothsim_add_test_program(test_system_jacobian test_system_jacobian.c)
foreach(np 1 2 3)
  clothsim_add_mpi_test(system_jacobian_fd_np${np} ${np} $<TARGET_FILE:test_system_jacobian>)
endforeach()
# The Gauss-Newton stiffness assembled from its factors equals the expanded one, filtered by contacts of every kind
# (tests/programs/test_factored_stiffness.c): matrix and right-hand side to 1e-12 relative (measured 2e-18), on 1, 2
# and 3 ranks; and the assembly in place into the assembled matrix (ClothBlockAdder) equals the first one, made
# through MatSetValuesBlockedLocal, bit for bit, for BAIJ and SBAIJ.
clothsim_add_test_program(test_factored_stiffness test_factored_stiffness.c)
foreach(np 1 2 3)
  clothsim_add_mpi_test(factored_stiffness_np${np} ${np} $<TARGET_FILE:test_factored_stiffness>)
  clothsim_add_mpi_test(factored_stiffness_sbaij_np${np} ${np} $<TARGET_FILE:test_factored_stiffness> -matrix_type sbaij)
endforeach()
# Bending along the bias: the thread springs alone give B (cos^4 + sin^4) (B/2 on the bias); with bend_bias = B the
# twist elements make the bending the same in every direction (within 1%).
clothsim_add_test_program(test_bias_bending test_bias_bending.c)
clothsim_add_mpi_test(bias_bending 1 $<TARGET_FILE:test_bias_bending> -scene tests/data/bias_bending.yaml)

# The force plug-in interface (cloth.h, ClothContribution; tests/programs/test_contribution.c): springs to the start positions,
# stiffness omega^2 m, written as a user's contribution. The free sheet displaced rigidly follows backward Euler for one
# harmonic oscillator (40 steps of 10 ms, omega^2 = 400 1/s^2) to 1e-10 m at -ksp_rtol 1e-13 (measured 7.9e-15 m on 1 and
# 2 ranks); the contribution's forces are -omega^2 m u0 to 1e-12 relative and vanish once it is removed.
clothsim_add_test_program(test_contribution test_contribution.c)
# The same springs as one-particle elements added inside the cloth's own pass (add_elements, ClothElementSinkAdd: how seam
# links and hysteresis plug in), with begin_step counted (once per step): forces_contribution_elements_np1/2, the same
# tolerances (measured 7.9e-15 m on 1 and 2 ranks, begin_step 40 calls in 40 steps; 0.8 s and 1.7 s on the loaded machine).
foreach(np 1 2)
  clothsim_add_mpi_test(forces_contribution_np${np} ${np} $<TARGET_FILE:test_contribution> -scene tests/data/free_sheet.yaml -ksp_rtol 1e-13 -tolerance 1e-10)
  clothsim_add_mpi_test(forces_contribution_elements_np${np} ${np} $<TARGET_FILE:test_contribution> -scene tests/data/free_sheet.yaml -ksp_rtol 1e-13 -tolerance 1e-10 -elements)
endforeach()
# The default element stiffness is the closed-form Gauss-Newton form (issue 45): a real-fabric scene's assembly makes
# no per-element LAPACK eigen-decomposition (ClothProjectPSD events in -log_view: 0 by default; 3,066 in the same 3
# steps with -cloth_stiffness projected, which the test also runs so that the count is seen to work).
clothsim_add_script_test(stiffness_default_no_lapack check_stiffness_default.sh ${MPIEXEC_EXECUTABLE})

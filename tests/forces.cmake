# Element and system Jacobians against finite differences.
clothsim_add_test_program(test_forces test_forces.c)
clothsim_add_mpi_test(forces_jacobian_fd 1 $<TARGET_FILE:test_forces>)
clothsim_add_test_program(test_system_jacobian test_system_jacobian.c)
foreach(np 1 2 3)
  clothsim_add_mpi_test(system_jacobian_fd_np${np} ${np} $<TARGET_FILE:test_system_jacobian>)
endforeach()
# Bending along the bias: the thread springs alone give B (cos^4 + sin^4) (B/2 on the bias); with bend_bias = B the
# twist elements make the bending the same in every direction (within 1%).
clothsim_add_test_program(test_bias_bending test_bias_bending.c)
clothsim_add_mpi_test(bias_bending 1 $<TARGET_FILE:test_bias_bending> -scene tests/data/bias_bending.yaml)

# Element and system Jacobians against finite differences.
clothsim_add_test_program(test_forces test_forces.c)
clothsim_add_mpi_test(forces_jacobian_fd 1 $<TARGET_FILE:test_forces>)
clothsim_add_test_program(test_system_jacobian test_system_jacobian.c)
foreach(np 1 2 3)
  clothsim_add_mpi_test(system_jacobian_fd_np${np} ${np} $<TARGET_FILE:test_system_jacobian>)
endforeach()

# Physics of the integrators: static equilibrium, energy conservation, coming to rest.
clothsim_add_test_program(test_run_to_rest test_run_to_rest.c)
clothsim_add_test_program(test_energy_drift test_energy_drift.c)

# Spring-mass: elongation m g / k = 5e-4 * 9.81 / 1000 = 4.905e-6 m (tests/data/spring_mass.yaml);
# the implicit solve is converged to rtol 1e-8, so 1e-5 relative is the check's tolerance.
clothsim_add_mpi_test(spring_mass_elongation 1 $<TARGET_FILE:test_run_to_rest>
  -scene tests/data/spring_mass.yaml -output_dir ${CMAKE_BINARY_DIR}/test-output/spring_mass
  -expect_elongation 4.905e-6 -expect_rtol 1e-5 -progress_seconds 100)

clothsim_add_mpi_test(energy_drift_symplectic 1 $<TARGET_FILE:test_energy_drift>)
clothsim_add_mpi_test(energy_drift_symplectic_np2 2 $<TARGET_FILE:test_energy_drift>)

# The 65 x 65 benchmark sheet released from rest comes to rest under implicit Euler at dt = 1/60 s
# (numerical damping only): after 20 s the kinetic energy (initially 0, at most ~0.2 J) is below 1e-4 J.
clothsim_add_mpi_test(hanging_sheet_rest_implicit 2 $<TARGET_FILE:test_run_to_rest>
  -scene input/hanging_sheet.yaml -dt 0.016666666666666666 -t_final 20 -output_every 0
  -output_dir ${CMAKE_BINARY_DIR}/test-output/rest_implicit -expect_ke_below 1e-4 -progress_seconds 100)
# The damped 17 x 17 sheet comes to rest with each integrator at a stable step of its own.
clothsim_add_mpi_test(hanging_sheet_rest_symplectic 1 $<TARGET_FILE:test_run_to_rest>
  -scene tests/data/hanging_sheet_damped.yaml -integrator symplectic -dt 2e-4 -t_final 3 -output_every 0
  -output_dir ${CMAKE_BINARY_DIR}/test-output/rest_symplectic -expect_ke_below 1e-6 -progress_seconds 100)
clothsim_add_mpi_test(hanging_sheet_rest_explicit 1 $<TARGET_FILE:test_run_to_rest>
  -scene tests/data/hanging_sheet_damped.yaml -integrator explicit -dt 2e-6 -t_final 3 -output_every 0
  -output_dir ${CMAKE_BINARY_DIR}/test-output/rest_explicit -expect_ke_below 1e-6 -progress_seconds 100)

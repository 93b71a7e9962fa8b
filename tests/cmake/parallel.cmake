# Parallel distribution (src/cloth.c, src/partition.c, issue 3), each on 1, 2, 3 and 4 ranks
# (oversubscribed on small machines), for the hanging sheet, a two-piece scene with angle springs and
# (forces) two pieces joined by a seam of 9 to 13 nodes (interpolated seam links):
# - parallel_forces: every interaction evaluated exactly once; forces and energy equal a serial
#   brute-force evaluation of the whole model (test_partition.c);
# - parallel_preallocation: the implicit matrix, BAIJ and SBAIJ, assembled without mallocs and with
#   every preallocated entry used (MatGetInfo, test_preallocation.c).
clothsim_add_test_program(test_partition test_partition.c)
clothsim_add_test_program(test_preallocation test_preallocation.c)
foreach(ranks 1 2 3 4)
  clothsim_add_mpi_test(parallel_forces_sheet_np${ranks} ${ranks} $<TARGET_FILE:test_partition>
                        -scene input/hanging_sheet.yaml -grid 17)
  clothsim_add_mpi_test(parallel_forces_two_pieces_np${ranks} ${ranks} $<TARGET_FILE:test_partition>
                        -scene tests/data/jacobian_two_pieces.yaml)
  clothsim_add_mpi_test(parallel_forces_seams_np${ranks} ${ranks} $<TARGET_FILE:test_partition>
                        -scene tests/data/seam_two_pieces.yaml)
  clothsim_add_mpi_test(parallel_preallocation_sheet_np${ranks} ${ranks} $<TARGET_FILE:test_preallocation>
                        -scene input/hanging_sheet.yaml -grid 17)
  clothsim_add_mpi_test(parallel_preallocation_two_pieces_np${ranks} ${ranks} $<TARGET_FILE:test_preallocation>
                        -scene tests/data/jacobian_two_pieces.yaml)
endforeach()

# Same physics on every rank count: the hanging sheet on 1, 2, 3 and 4 ranks; final positions
# (natural order, from the checkpoints) compared with the 1-rank run.
# Implicit: 17 x 17, 40 steps of 1/240 s, -ksp_rtol 1e-12; measured differences 3.3e-16 m on
# 2, 3 and 4 ranks (33 x 33: up to 1.4e-15 m), tolerance 1e-10 m (CG stops at a different iterate on each rank count:
# at most ~cond(A) 1e-12 |dv| h per step, well below 1e-12 m over 40 steps).
# Symplectic: 33 x 33, 400 steps of 1e-4 s (its stable step at this grid); no solver, so only
# summation order differs: measured up to 6.7e-16 m, tolerance 1e-12 m.
clothsim_add_script_test(parallel_same_physics_implicit check_rank_invariance.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/rank_invariance_implicit implicit 17 40 0.004166666666666667 1e-10 -ksp_rtol 1e-12)
clothsim_add_script_test(parallel_same_physics_symplectic check_rank_invariance.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/rank_invariance_symplectic symplectic 33 400 1e-4 1e-12)
# The same with the seeded start imperfections of -cloth_perturbation (2 mm): each particle's displacement
# depends on its natural index only, so every rank count starts from the same shape: measured up to 2.1e-15 m
# (the perturbed sheet ends 3.3e-3 m from the unperturbed one), tolerance 1e-12 m.
clothsim_add_script_test(parallel_same_physics_perturbed check_rank_invariance.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/rank_invariance_perturbed symplectic 33 400 1e-4 1e-12 -cloth_perturbation 0.002 -cloth_perturbation_seed 7)
set_tests_properties(parallel_same_physics_implicit parallel_same_physics_symplectic parallel_same_physics_perturbed PROPERTIES PROCESSORS 4 TIMEOUT 120)

# Over seconds, rank counts separate (docs/parallel.md, "Rank counts"); what stays close is checked here: the
# sphere drape (33 x 33, 2 s) on 1 and 4 ranks: total energy within 1e-5 relative, particles on a body within 15%,
# drape coefficient within 0.002 (measured with friction inside the implicit step: 1.3e-8 m apart, 89 and 89 on the
# body, 0.3908 both; with the earlier post-solve friction 7.2 mm, 83 and 75, 0.3731 and 0.3738).
# tests/drivers/rank_divergence_contact.sh; jobs/rank_divergence.sh has the full comparison.
clothsim_add_script_test(parallel_rank_divergence_contact rank_divergence_contact.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/rank_divergence_contact)
set_tests_properties(parallel_rank_divergence_contact PROPERTIES PROCESSORS 4 TIMEOUT 180)

# Two simulations side by side on the two halves of MPI_COMM_WORLD (tests/drivers/check_split_comm.sh, 2 ranks): each the
# same as alone, bit for bit (every library object on its own communicator).
clothsim_add_test_program(test_split_comm test_split_comm.c)
clothsim_add_script_test(split_communicator check_split_comm.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/split_communicator)
set_property(TEST split_communicator APPEND PROPERTY ENVIRONMENT "SPLIT=$<TARGET_FILE:test_split_comm>")
set_tests_properties(split_communicator PROPERTIES PROCESSORS 2)

# The parallel partitioner (-cloth_partition ptscotch: PETSc's MatPartitioning with PT-Scotch, every rank given its
# block of rows of the graph; src/partition.c, issue 25) on 2, 3 and 4 ranks:
# - parallel_partitioner_ptscotch_np*: on a 65 x 65 grid graph with the 8-neighbour stencil built by the test itself
#   (tests/programs/test_partitioner.c): the same part[] on every rank, every vertex in a part, no part empty, the largest part
#   at most 1.05 x the mean (PT-Scotch's default imbalance is 1 %; measured 1.0002, 1.0076, 1.0083 on 2, 3, 4 parts)
#   and the edge cut at most 1.1 x METIS's on the same graph (measured 194/202, 321/335, 387/395; contiguous blocks of
#   rows, -partition block, give 582 on 4 parts, 1.47 x METIS, and fail it; so does a gather left out, on 2 ranks);
# - parallel_forces_sheet_ptscotch_np*: the distributed forces and energy on a ptscotch partition equal the serial
#   brute-force evaluation (test_partition.c, as parallel_forces_sheet_np* does for METIS);
# - parallel_same_physics_ptscotch: the implicit hanging sheet on 1-4 ranks partitioned by PT-Scotch ends where the
#   1-rank run ends, within the 1e-10 m of parallel_same_physics_implicit (same case and reasons).
clothsim_add_test_program(test_partitioner test_partitioner.c)
foreach(ranks 2 3 4)
  clothsim_add_mpi_test(parallel_partitioner_ptscotch_np${ranks} ${ranks} $<TARGET_FILE:test_partitioner>
                        -n 65 -partition ptscotch -expect_max_imbalance 1.05 -expect_max_cut_ratio 1.1)
  clothsim_add_mpi_test(parallel_forces_sheet_ptscotch_np${ranks} ${ranks} $<TARGET_FILE:test_partition>
                        -scene input/hanging_sheet.yaml -grid 17 -cloth_partition ptscotch)
endforeach()
clothsim_add_script_test(parallel_same_physics_ptscotch check_rank_invariance.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/rank_invariance_ptscotch implicit 17 40 0.004166666666666667 1e-10 -ksp_rtol 1e-12 -cloth_partition ptscotch)
set_tests_properties(parallel_same_physics_ptscotch PROPERTIES PROCESSORS 4 TIMEOUT 120)

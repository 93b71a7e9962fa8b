# I/O: checkpoints (src/checkpoint.c) and the XDMF + HDF5 output series (src/output.c).
clothsim_add_test_program(test_checkpoint test_checkpoint.c)
clothsim_add_test_program(test_output test_output.c)
clothsim_add_test_program(test_h5_open_agreement test_h5_open_agreement.c)
foreach(ranks 1 2 3)
  # Round trip (also re-read on one rank), pruning, and refusal of damaged or foreign checkpoints.
  clothsim_add_mpi_test(io_checkpoint_np${ranks} ${ranks} $<TARGET_FILE:test_checkpoint>
                        -dir ${CMAKE_CURRENT_BINARY_DIR}/io_checkpoint_np${ranks})
  # Writes series with test_output on RANKS ranks, then opens them with ParaView (pvpython) and h5py.
  clothsim_add_script_test(io_output_xdmf_np${ranks} check_xdmf.sh
                           ${MPIEXEC_EXECUTABLE} ${ranks} $<TARGET_FILE:test_output>
                           ${CMAKE_CURRENT_BINARY_DIR}/io_output_np${ranks})
  set_tests_properties(io_output_xdmf_np${ranks} PROPERTIES PROCESSORS ${ranks})
endforeach()

# The .xdmf rewritten at most every -output_xdmf_seconds, and at checkpoints and the end: the same frame list as a
# rewrite after every frame (tests/drivers/check_xdmf_interval.sh, 2 ranks).
clothsim_add_script_test(io_xdmf_interval check_xdmf_interval.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/io_xdmf_interval)
set_tests_properties(io_xdmf_interval PROPERTIES PROCESSORS 2 TIMEOUT 120)

# An HDF5 open or create that fails on some ranks only (a file deleted between their opens) fails on all, without a
# hang (tests/programs/test_h5_open_agreement.c; Open MPI's ompio hung, src/h5util.h): a hang meets the timeout.
foreach(ranks 2 3)
  clothsim_add_mpi_test(io_open_agreement_np${ranks} ${ranks} $<TARGET_FILE:test_h5_open_agreement>
                        -dir ${CMAKE_CURRENT_BINARY_DIR}/io_open_agreement_np${ranks})
  set_tests_properties(io_open_agreement_np${ranks} PROPERTIES TIMEOUT 60)
endforeach()

# cmake --install into a temporary prefix; the installed jobs/main_job.sbatch runs the main job's scene (the dress on
# the mannequin) for 3 steps from a directory outside the trees, with the installed binary and postprocess tools
# (tests/drivers/install_run.sh; README, "Installing").
clothsim_add_script_test(install_run install_run.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/install_run)
set_tests_properties(install_run PROPERTIES TIMEOUT 120)

# Provenance (tests/drivers/check_provenance.sh, 2 ranks): the series and the checkpoint carry the scene's bytes, its path,
# the options, the code version and the build's git revision.
clothsim_add_script_test(io_provenance check_provenance.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/io_provenance)
set_tests_properties(io_provenance PROPERTIES PROCESSORS 2)

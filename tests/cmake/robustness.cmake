# A diverging run stops cleanly with its last good state; a recoverable failure is recovered by halving.
clothsim_add_script_test(divergence_handling robustness.sh)
# A diverging run with self-collision stops like one without it; absurd thicknesses stop with a clear error (no hang).
clothsim_add_script_test(divergence_handling_self_collision robustness_self_collision.sh)
set_tests_properties(divergence_handling_self_collision PROPERTIES TIMEOUT 300)

# A failed step is undone completely, sliders and held contacts included (tests/drivers/check_failed_step_rollback.sh, 2 ranks):
# the checkpoint written after a divergence is bit-identical to that of a run stopped at the last good step.
clothsim_add_script_test(failed_step_rollback check_failed_step_rollback.sh ${MPIEXEC_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/failed_step_rollback)
set_tests_properties(failed_step_rollback PROPERTIES PROCESSORS 2)

# Bad options and faults (issue 24): clothsim must refuse each with its exit status (src/errors.h: 2 bad input,
# 3 file) and one "ERROR: " line naming the option and what is allowed, without PETSc's traceback (expect_error.sh).
# The bad scenes and meshes of tests/bad_input/ are run by scene.cmake; these give options to a good scene.
# robustness_case(NAME STATUS RANKS SCENE TEXT... -- OPTION...)
set(robustness_cases "")
function(robustness_case name status ranks scene)
  clothsim_add_script_test(robust_${name} expect_error.sh --status ${status} ${ranks} ${scene} ${ARGN})
  set_property(TEST robust_${name} APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
  set_tests_properties(robust_${name} PROPERTIES TIMEOUT 150 PROCESSORS ${ranks} LABELS robustness)
endfunction()
set(sheet input/hanging_sheet.yaml)
# 32-bit overflows and unchecked sizes
robustness_case(t_final_huge 2 1 ${sheet} "-t_final 1e+09 s with -dt 0.00416667 s needs 2.4e+11 steps: expected at most 2147483647 steps" -- -t_final 1e9)
robustness_case(dt_huge 2 1 ${sheet} "-t_final 1 s with -dt 1e+09 s is less than half a step: expected -dt <= -t_final" -- -dt 1e9)
robustness_case(dt_inf 2 1 ${sheet} "option -dt inf: expected a finite number > 0 s" -- -dt inf)
robustness_case(dt_nan 2 2 ${sheet} "option -dt nan: expected a finite number > 0 s" -- -dt nan)
robustness_case(dt_text 2 1 ${sheet} "Input string abc has no numeric value" -- -dt abc)
robustness_case(grid_overflow 2 1 ${sheet} "-grid 65536: the pieces have 4294967296 particles in all: expected at most 715827882" -- -grid 65536)
robustness_case(grid_memory 2 2 ${sheet} "the grids ('sheet' 26000 x 26000) give 676000000 particles" "GB of memory on a node" -- -grid 26000)
robustness_case(steps_beyond_int 2 1 ${sheet} "option -steps 3000000000: expected an integer >= 0 and <= 2147483647" -- -steps 3000000000)
robustness_case(steps_wraps_positive 2 2 ${sheet} "option -steps 5000000000: expected an integer >= 0 and <= 2147483647" -- -steps 5000000000)
robustness_case(checkpoint_every_beyond_int 2 1 ${sheet} "option -checkpoint_every 4294967297: expected an integer >= 0 and <= 2147483647" -- -checkpoint_every 4294967297)
robustness_case(io_timeout_negative 2 1 ${sheet} "option -io_timeout -1: expected a finite number >= 0 and <= 1e+08 s" -- -io_timeout -1)
robustness_case(lag_backoff_too_large 2 1 ${sheet} "-implicit_pc_lag_backoff 21: expected 0 to 20 doublings" -- -grid 129 -implicit_pc_lag_backoff 21)
robustness_case(max_halvings_negative 2 1 ${sheet} "option -integrator_max_halvings -1: expected an integer >= 0 and <= 30" -- -integrator_max_halvings -1)
robustness_case(grid_too_small 2 1 ${sheet} "option -grid 1: expected an integer >= 2" -- -grid 1)
robustness_case(scene_dev_zero 2 1 /dev/zero "scene /dev/zero: the file is larger than 64 MB: expected a YAML scene file")
robustness_case(scene_directory 3 2 tests "scene tests: cannot read the file (Is a directory)")
robustness_case(scene_binary 2 1 tests/data/table.obj "expected a map with keys among")
# paths longer than the buffers PETSc copies them into, which cut them without a word (issue 48: a 5000-character
# -output_dir ended in HDF5's MPI_File_open, exit 76; a -restart that long was named as a missing file)
string(REPEAT "d" 99 long_component)
string(REPEAT "/${long_component}" 50 long_path)
set(long_path ${CMAKE_BINARY_DIR}/test-output/long_path${long_path})
robustness_case(output_dir_too_long 2 1 ${sheet} "option -output_dir ${CMAKE_BINARY_DIR}" "characters): expected a path of at most 3967 characters" -- -output_dir ${long_path})
robustness_case(restart_path_too_long 2 2 ${sheet} "option -restart ${CMAKE_BINARY_DIR}" "characters): expected a path of at most 4095 characters" -- -restart ${long_path}/checkpoint_000001.h5)
# nonsense accepted
robustness_case(checkpoint_keep_negative 2 1 ${sheet} "option -checkpoint_keep -1: expected an integer >= 0" -- -checkpoint_keep -1)
robustness_case(gravity_ramp_inf 2 1 ${sheet} "option -gravity_ramp inf: expected a finite number >= 0 s" -- -gravity_ramp inf)
robustness_case(progress_negative 2 1 ${sheet} "option -progress_seconds -1: expected a finite number >= 0 s" -- -progress_seconds -1)
robustness_case(output_every_negative 2 1 ${sheet} "option -output_every -3: expected an integer >= 0" -- -output_every -3)
robustness_case(output_xdmf_seconds_negative 2 1 ${sheet} "option -output_xdmf_seconds -1: expected a finite number >= 0 and <= 1e+08 s" -- -output_xdmf_seconds -1)
robustness_case(output_dir_empty 2 1 ${sheet} "option -output_dir '': expected a directory name" -- -output_dir '')
robustness_case(collision_cell_nan 2 1 input/sphere_drape.yaml "option -collision_cell_size nan: expected a finite number >= 0 m" -- -collision_cell_size nan)
robustness_case(perturbation_inf 2 1 ${sheet} "option -cloth_perturbation inf: expected a finite number >= 0 m" -- -cloth_perturbation inf)
robustness_case(self_collision_thickness_inf 2 2 ${sheet} "Self-collision thickness" "expected a positive number of at most 50 particle spacings" -- -self_collision -self_collision_thickness inf -self_collision_stiffness 20)
robustness_case(self_collision_thickness_10m 2 1 ${sheet} "Self-collision thickness" "expected a positive number of at most 50 particle spacings" -- -self_collision -self_collision_thickness 10 -self_collision_stiffness 20)
robustness_case(self_collision_stiffness_inf 2 1 ${sheet} "Self-collision needs a positive, finite stiffness" -- -self_collision -self_collision_thickness 0.01 -self_collision_stiffness inf)
# a time step beyond the scene's bound with -steps (issue 48: -dt 1e9 -steps 3 ran and exited 0); its simulated time too
robustness_case(dt_huge_with_steps 2 1 ${sheet} "option -dt 1e+09: expected a finite number > 0 and <= 10 s" -- -dt 1e9 -steps 3)
robustness_case(steps_beyond_final_time_bound 2 1 ${sheet} "-steps 2000000 with a step of 1 s ends the run at t = 2e+06 s: expected at most 1e+06 s of simulated time" -- -dt 1 -steps 2000000)
# a restart told to end before its checkpoint (issue 48: "Done: 0 steps", exit 0, the checkpoint rewritten), on 2 ranks:
# refused, the checkpoint and the series untouched (tests/drivers/restart_before_checkpoint.sh). 6 s, idle machine.
clothsim_add_script_test(robust_restart_ends_before_checkpoint restart_before_checkpoint.sh 2)
set_property(TEST robust_restart_ends_before_checkpoint APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(robust_restart_ends_before_checkpoint PROPERTIES TIMEOUT 200 PROCESSORS 2 LABELS robustness)
# a misspelled or unknown clothsim option is refused before the run, naming the nearest option or its family (issue 48:
# -checkpont_every 5 was listed only after the whole run, which wrote no checkpoint meanwhile)
robustness_case(option_misspelled 2 2 ${sheet} "option -checkpont_every 5 is not an option of clothsim: did you mean -checkpoint_every?" -- -checkpont_every 5)
robustness_case(option_unknown_family 2 1 input/sphere_drape.yaml "option -collision_friction_coefficient 0.3 is not an option of clothsim: expected one of its -collision_ options: -collision_allow_inside, -collision_cell_size" -- -collision_friction_coefficient 0.3)
# restart faults: a directory, a missing file, a file that is not HDF5
robustness_case(restart_directory 3 2 ${sheet} "Checkpoint tests is a directory: expected a file (one of the checkpoint_NNNNNN.h5 in it" -- -restart tests)
robustness_case(restart_missing 3 1 ${sheet} "Checkpoint tests/no_such_checkpoint.h5 does not exist" -- -restart tests/no_such_checkpoint.h5)
robustness_case(restart_not_hdf5 3 1 ${sheet} "Checkpoint tests/data/table.obj cannot be opened as an HDF5 file" -- -restart tests/data/table.obj)

# Provenance of any size (issue 48): a 2.2 MB scene and a 100 kB option run on 2 ranks and restart; their text is in
# /provenance of the series and of the checkpoints, byte for byte (tests/drivers/large_provenance.sh). Before: exit 76
# at output set-up (an HDF5 attribute holds at most 64 kB). 2 s on an idle machine.
clothsim_add_script_test(robust_large_scene large_provenance.sh ${MPIEXEC_EXECUTABLE})
set_tests_properties(robust_large_scene PROPERTIES TIMEOUT 120 PROCESSORS 2 LABELS robustness)

# A flow sequence nested a million levels deep (issue 48) is refused at once naming the file, the line and the limit of
# 32 levels (tests/drivers/deep_nesting.sh writes the 2 MB scene); before, libyaml's scanner, quadratic in the depth,
# did not answer within 120 s. 3 s on an idle machine.
clothsim_add_script_test(robust_yaml_deep_nesting deep_nesting.sh 2)
set_property(TEST robust_yaml_deep_nesting APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(robust_yaml_deep_nesting PROPERTIES TIMEOUT 150 PROCESSORS 2 LABELS robustness)

# Pieces that start inside a body are named at set-up (issue 48: moved to the surface without a word): with
# -collision_allow_inside beyond 5 % of a piece, and below it, each run warns with the count, piece and body; a piece
# outside says nothing (tests/drivers/starting_inside.sh, 2 ranks; the refusal is tests/bad_input/piece_inside_body.yaml).
# 5 s on an idle machine.
clothsim_add_script_test(robust_collision_starting_inside starting_inside.sh 2)
set_property(TEST robust_collision_starting_inside APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(robust_collision_starting_inside PROPERTIES TIMEOUT 150 PROCESSORS 2 LABELS robustness)

# The DXF pattern importer (postprocess/pattern_dxf.py import, issue 48) refuses random bytes, an empty file, a
# directory, a missing file (exit 3), a NaN vertex, a self-crossing outline, millimetres declared as metres and two
# pieces of one name (exit 2) with one "ERROR: pattern_dxf:" line and no traceback, and imports a 100,000-vertex outline
# that clothsim then reads (tests/drivers/pattern_dxf_bad_input.sh). Before: tracebacks, an all-NaN outline and the
# crossing outline reported as success. 25 s on a shared machine (writing and dumping the 100,000 vertices).
clothsim_add_script_test(robust_pattern_dxf_bad_input pattern_dxf_bad_input.sh)
set_tests_properties(robust_pattern_dxf_bad_input PROPERTIES TIMEOUT 150 PROCESSORS 1 LABELS robustness)

# A checkpoint whose string attribute claims 2 MB is refused as corrupt before the reader allocates what the file claims
# (tests/drivers/checkpoint_huge_attribute.sh; issue 48's sweep: read before). 4 s on an idle machine.
clothsim_add_script_test(robust_checkpoint_huge_attribute checkpoint_huge_attribute.sh 2)
set_property(TEST robust_checkpoint_huge_attribute APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(robust_checkpoint_huge_attribute PROPERTIES TIMEOUT 150 PROCESSORS 2 LABELS robustness)

# An outline's grid of 676 million particles is refused by the memory check with the process limited to 1.5 GB: the
# reader's folded-cell check holds two rows of the grid, not all of it (tests/drivers/outline_grid_memory.sh; issue 48's
# sweep: 10.8 GB allocated first, under the limit an allocation failure with a traceback). 12 s on a shared machine.
clothsim_add_script_test(robust_outline_grid_memory outline_grid_memory.sh)
set_property(TEST robust_outline_grid_memory APPEND PROPERTY ENVIRONMENT "MPIEXEC=${MPIEXEC_EXECUTABLE}")
set_tests_properties(robust_outline_grid_memory PROPERTIES TIMEOUT 150 PROCESSORS 1 LABELS robustness)

# A METIS failure on rank 0 is raised on every rank (src/partition.c), on 1 and 2 ranks.
clothsim_add_test_program(test_partition_failure test_partition_failure.c)
clothsim_add_mpi_test(robust_metis_failure_np1 1 $<TARGET_FILE:test_partition_failure>)
clothsim_add_mpi_test(robust_metis_failure_np2 2 $<TARGET_FILE:test_partition_failure>)
set_tests_properties(robust_metis_failure_np1 robust_metis_failure_np2 PROPERTIES TIMEOUT 60)

# An output directory belongs to one run: a new run into used results and a second live run are refused, pruning
# keeps other runs' checkpoints, the lock goes with its holder (tests/drivers/output_dir_ownership.sh).
clothsim_add_script_test(robust_output_dir_ownership output_dir_ownership.sh)
set_tests_properties(robust_output_dir_ownership PROPERTIES TIMEOUT 300 PROCESSORS 2 LABELS robustness)

# A full disk stops the run with exit 3 naming the file and "No space left on device", leaving valid files
# (tests/drivers/full_disk.sh; needs root to mount a small tmpfs, else skipped).
clothsim_add_script_test(robust_full_disk full_disk.sh)
set_tests_properties(robust_full_disk PROPERTIES TIMEOUT 300 PROCESSORS 2 SKIP_RETURN_CODE 77 LABELS robustness)

# A disk that fills inside a checkpoint's HDF5 writes (after the space check): exit 3 naming the temporary file and
# "No space left on device", the file deleted, the earlier checkpoints complete (tests/drivers/checkpoint_write_failure.sh,
# with the fault injector tests/fault/fault_full_disk.c).
add_library(fault_full_disk SHARED ${CMAKE_CURRENT_SOURCE_DIR}/fault/fault_full_disk.c)
target_link_libraries(fault_full_disk PRIVATE ${CMAKE_DL_LIBS})
clothsim_add_script_test(robust_checkpoint_write_failure checkpoint_write_failure.sh $<TARGET_FILE:fault_full_disk>)
set_tests_properties(robust_checkpoint_write_failure PROPERTIES TIMEOUT 200 PROCESSORS 2 LABELS robustness)

# A path longer than Open MPI's ompio opens (244 characters) works: ROMIO is chosen before the first file; the
# files equal a short-path run's, a restart reads them; with OMPI_MCA_io=ompio forced it is refused before the
# first step (tests/drivers/long_path.sh).
clothsim_add_script_test(robust_long_output_path long_path.sh)
set_tests_properties(robust_long_output_path PROPERTIES TIMEOUT 200 PROCESSORS 2 SKIP_RETURN_CODE 77 LABELS robustness)

# User errors end with one message and exit 2 whether raised on every rank or on one (no hang): tests/drivers/error_exit.sh.
clothsim_add_test_program(test_error_exit test_error_exit.c)
clothsim_add_script_test(robust_error_exit error_exit.sh)
set_tests_properties(robust_error_exit PROPERTIES TIMEOUT 200 PROCESSORS 2 LABELS robustness)
# misspelled choices: PETSc's own messages, as one line with exit 2
robustness_case(partition_unknown 2 2 ${sheet} "Unknown option foo for -cloth_partition. Available options: metis block" -- -cloth_partition foo)
robustness_case(ksp_type_unknown 2 1 ${sheet} "Unable to find requested KSP type foo" -- -ksp_type foo -steps 1)
robustness_case(integrator_unknown 2 1 ${sheet} "Unknown integrator 'foo': expected explicit, symplectic, implicit or bdf2" -- -integrator foo)
robustness_case(too_many_ranks 2 5 ${sheet} "4 particles cannot be shared by 5 ranks: expected at most 4 ranks" -- -grid 2)

# Checkpoint and restart of whole runs (issue 4, docs/checkpoint.md), by tests/drivers/check_restart.sh on
# the 11 x 11 hanging sheet, 1/240 s steps, -ksp_rtol 1e-12.
set(CLOTHSIM_RESTART_DIR ${CMAKE_BINARY_DIR}/test-output/restart)

# 200 steps against 100 + restart + 100 on the same ranks: checkpoints (position, velocity, implicit
# warm start) and every frame of the series bit-identical; the strain field against a brute-force
# evaluation (1e-12); the restarted series opened by pvpython's three XDMF readers.
foreach(ranks 1 2)
  clothsim_add_script_test(restart_same_ranks_np${ranks} check_restart.sh ${MPIEXEC_EXECUTABLE}
                           same ${ranks} ${CLOTHSIM_RESTART_DIR}/np${ranks})
  set_tests_properties(restart_same_ranks_np${ranks} PROPERTIES PROCESSORS ${ranks} TIMEOUT 120
                       FIXTURES_SETUP restart_np${ranks})
endforeach()
# Step halving on the same path: -ksp_max_it 50 makes every full step fail (about 58 iterations are
# needed) and be taken as two halves; 40 steps against 20 + restart + 20, still bit-identical.
clothsim_add_script_test(restart_same_ranks_halving_np2 check_restart.sh ${MPIEXEC_EXECUTABLE}
                         same 2 ${CLOTHSIM_RESTART_DIR}/halving_np2 -ksp_max_it 50)
set_tests_properties(restart_same_ranks_halving_np2 PROPERTIES PROCESSORS 2 TIMEOUT 120)
set_property(TEST restart_same_ranks_halving_np2 APPEND PROPERTY ENVIRONMENT STEPS=40)
# With contacts: the sheet draping over the sphere (input/sphere_drape.yaml), 200 steps against
# 100 + restart + 100; at step 100, 5 particles are held on the sphere, whose contact normals (the
# next step's constraints) the checkpoint carries as /state/contact_normal (without them the 17 x 17
# sheet ended 1.3e-3 m off after 80 more steps).
clothsim_add_script_test(restart_same_ranks_contacts_np2 check_restart.sh ${MPIEXEC_EXECUTABLE}
                         same 2 ${CLOTHSIM_RESTART_DIR}/contacts_np2)
set_tests_properties(restart_same_ranks_contacts_np2 PROPERTIES PROCESSORS 2 TIMEOUT 120)
set_property(TEST restart_same_ranks_contacts_np2 APPEND PROPERTY ENVIRONMENT STEPS=200 SCENE=input/sphere_drape.yaml SIDE=1.4 MIN_CONTACTS=5)

# The same three with -integrator bdf2, whose checkpoints carry its history (/state/bdf2_history_rate, _velocity and
# the attribute history_dt): without it the restart's first step would be backward Euler where the uninterrupted run's
# is BDF2. Halving: with -ksp_max_it 40 the full BDF2 steps pass and the BDF1 ones (after a halved step: no history of
# their size) fail and are taken as two BDF2 halves (39 of the 40 steps, 2 of the 79 sub-steps BDF1), so the checkpoint
# at step 20 holds a history of half a step. Measured 2026-11-29: all bit-identical, 13-63 s each on the shared machine.
foreach(case "bdf2;;200" "bdf2_halving;-ksp_max_it;40;40" "bdf2_contacts;;200")
  list(GET case 0 name)
  list(LENGTH case length)
  math(EXPR last "${length} - 1")
  list(GET case ${last} steps)
  set(extra "")
  if(length GREATER 3)
    list(SUBLIST case 1 2 extra)
  endif()
  clothsim_add_script_test(restart_same_ranks_${name}_np2 check_restart.sh ${MPIEXEC_EXECUTABLE}
                           same 2 ${CLOTHSIM_RESTART_DIR}/${name}_np2 -integrator bdf2 ${extra})
  set_tests_properties(restart_same_ranks_${name}_np2 PROPERTIES PROCESSORS 2 TIMEOUT 120)
  set_property(TEST restart_same_ranks_${name}_np2 APPEND PROPERTY ENVIRONMENT STEPS=${steps})
endforeach()
set_property(TEST restart_same_ranks_bdf2_contacts_np2 APPEND PROPERTY ENVIRONMENT SCENE=input/sphere_drape.yaml SIDE=1.4 MIN_CONTACTS=5)

# Written on 1 rank and continued on 2, and the reverse: within 1e-10 m and 1e-8 m/s of the
# uninterrupted run (measured 4e-15 m, 3e-13 m/s).
clothsim_add_script_test(restart_cross_ranks check_restart.sh ${MPIEXEC_EXECUTABLE}
                         cross ${CLOTHSIM_RESTART_DIR}/np1 ${CLOTHSIM_RESTART_DIR}/np2)
set_tests_properties(restart_cross_ranks PROPERTIES PROCESSORS 2 TIMEOUT 120
                     FIXTURES_REQUIRED "restart_np1;restart_np2")

# A truncated checkpoint, one with a flipped byte in its positions, and one of another scene: each
# refused by clothsim -restart with its message.
clothsim_add_script_test(restart_refuse_damaged check_restart.sh ${MPIEXEC_EXECUTABLE}
                         refuse ${CLOTHSIM_RESTART_DIR}/np1 ${CLOTHSIM_RESTART_DIR}/refuse)
set_tests_properties(restart_refuse_damaged PROPERTIES PROCESSORS 2 TIMEOUT 120 FIXTURES_REQUIRED restart_np1)

# A termination signal mid-run: SIGTERM to mpiexec (forwarded by Open MPI), SIGTERM to the ranks
# (what Slurm does), SIGUSR1 to mpiexec: the run stops after its step with a valid checkpoint, from
# which a restart finishes.
foreach(case "TERM;mpiexec" "TERM;ranks" "USR1;mpiexec")
  list(GET case 0 signal)
  list(GET case 1 target)
  clothsim_add_script_test(restart_after_sig${signal}_to_${target} check_restart.sh ${MPIEXEC_EXECUTABLE}
                           signal 2 ${CLOTHSIM_RESTART_DIR}/sig${signal}_${target} ${signal} ${target})
  set_tests_properties(restart_after_sig${signal}_to_${target} PROPERTIES PROCESSORS 2 TIMEOUT 120)
endforeach()
# mpirun answers its own SIGTERM by waiting odls_base_sigkill_timeout (1 s by default), sending SIGTERM
# to the ranks and SIGKILL as long again later; 1 s may be too short for a step and a checkpoint on a
# loaded CI machine, so this test gives them 5 s (docs/checkpoint.md).
set_property(TEST restart_after_sigTERM_to_mpiexec APPEND PROPERTY ENVIRONMENT OMPI_MCA_odls_base_sigkill_timeout=5)

# With the cloth held on a mesh body (the mannequin): 120 steps of tests/data/mannequin_shoulder.yaml on 2 ranks
# against 60 + restart + 60; the held contacts' triangles are found again from the checkpointed contact normals
# (tests/drivers/restart_mesh_contacts.sh).
clothsim_add_script_test(restart_same_ranks_mesh_contacts_np2 restart_mesh_contacts.sh)
set_tests_properties(restart_same_ranks_mesh_contacts_np2 PROPERTIES PROCESSORS 2 TIMEOUT 300)

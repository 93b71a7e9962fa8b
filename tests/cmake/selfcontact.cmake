# Cloth-cloth collisions (src/selfcontact.c, docs/self_collision.md).
clothsim_add_test_program(test_selfcontact_search test_selfcontact_search.c)

# (a) The search finds exactly the brute-force contacts (same pairs, same distances to 1e-14 m) on two 17 x 17 sheets
# folded into 4 stacked panels each, on 1 and 2 ranks: 950 point-triangle and 3,029 edge-edge contacts within 2 cm
# (one triangle per particle and layer, the nearest, and edge pairs whose closest points lie inside both edges).
clothsim_add_mpi_test(selfcontact_search 1 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml)
clothsim_add_mpi_test(selfcontact_search_np2 2 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml)
# (a') The search as the layers move (tests/programs/test_selfcontact_search.c, CheckMotion), each search exactly the
# brute-force contacts: the whole fabric at 10 m/s over a step of 1/240 s gives the same contacts and the same pairs of
# primitives as at rest (the broad phase follows relative motion, not speed); then moved rigidly (30 degrees, 0.5 m);
# the upper piece moved as one 0.75 thickness closer to the lower (1,946 new contacts); every particle moved 0.75
# thickness in its own direction (3,546 new). 1 and 2 ranks.
clothsim_add_mpi_test(selfcontact_motion 1 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml -check_motion)
clothsim_add_mpi_test(selfcontact_motion_np2 2 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml -check_motion)
# The repulsion's stiffness in the assembled implicit system (exact stiffness, h = 1, no damping) against
# central differences of the forces along a random direction, contacts held fixed: relative error below
# 1e-5 (measured 2.6e-8 on 1 rank, 3.2e-9 on 2), the contacts giving most of |K d|; 1 and 2 ranks. Friction between
# the layers is off here: its velocity Jacobian h D also enters A, and A - M = K holds for the stiffness alone.
clothsim_add_mpi_test(selfcontact_jacobian 1 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml -check_jacobian -jacobian_rtol 1e-5 -self_collision_friction 0)
clothsim_add_mpi_test(selfcontact_jacobian_np2 2 $<TARGET_FILE:test_selfcontact_search>
  -scene tests/data/self_contact_crumple.yaml -check_jacobian -jacobian_rtol 1e-5 -self_collision_friction 0)

# (b) No fabric edge crosses a fabric triangle at any output frame (check_self_intersection.py), and 1 and
# 2 ranks end within 1e-6 m (measured: 7e-10 and 2e-10 m). With -self_collision 0 both scenes do pass
# through themselves (measured over the whole scenes: 6463 and 14666 crossings), so the check has teeth.
# The folded sheet at -grid 17 for 1 s (240 steps of 1/240 s): it lands and folds into a pile.
clothsim_add_script_test(selfcontact_folded_sheet check_self_collision.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/selfcontact_folded_sheet input/folded_sheet.yaml 240 1e-6 -grid 17)
# Two 17 x 17 sheets dropped one on the other onto a sphere, 0.75 s (180 steps): both lie on the sphere by then.
clothsim_add_script_test(selfcontact_two_sheets_sphere check_self_collision.sh ${MPIEXEC_EXECUTABLE}
  ${CMAKE_BINARY_DIR}/test-output/selfcontact_two_sheets_sphere input/two_sheets_sphere.yaml 180 1e-6)
set_tests_properties(selfcontact_folded_sheet selfcontact_two_sheets_sphere PROPERTIES PROCESSORS 2)
# (b') A real fabric at scale in miniature (issue 44): input/sheet_drape.yaml, cotton/polyester 1.4 m over a ball on
# the ground, at -grid 49 for 1 s (240 steps of 1/240 s): the edges reach the ground and fold onto themselves. No step
# halved, no fallback solve, at most 130 Krylov iterations a step (measured 97.9 on 1 rank and 99.1 on 2, the small
# sheet's point-block Jacobi), at most 0.5 candidates a particle a search (0.091 and 0.086), at least 40 contacts a
# search (87.0 and 89.3), no edge through a triangle at any of 9 frames, nothing inside the ball or the ground. With the
# exclusion of the former default, the 1-ring (-self_collision_exclude_ring 1), the folds at the sheet's edge cross
# themselves (434 edge-triangle crossings over the frames) and the test fails; with -cloth_stiffness projected (the
# former default) the sheet blows up at step 115 (a particle at 75 m/s, then 5e5 m/s). About 30 s each.
clothsim_add_script_test(selfcontact_drape check_drape.sh ${MPIEXEC_EXECUTABLE} 1 49 240 130 0.5 40)
clothsim_add_script_test(selfcontact_drape_np2 check_drape.sh ${MPIEXEC_EXECUTABLE} 2 49 240 130 0.5 40)
set_tests_properties(selfcontact_drape PROPERTIES TIMEOUT 300)
set_tests_properties(selfcontact_drape_np2 PROPERTIES TIMEOUT 300 PROCESSORS 2)

# (c) Friction between layers (-self_collision_friction, docs/self_collision.md "Friction between layers"): a 0.1 m
# sheet resting on a 0.4 m sheet that lies on a plane tilted by theta, mu 0.3, dt 1/960 s, 0.5 s, 1 rank
# (tests/drivers/self_friction_incline.sh). Stick at 16 degrees (tan 0.287 = 0.96 mu; 12 degrees until the normal force became
# the carried load, 25 Nov 2026, moved nearer the limit where the check has teeth): the top sheet moves at most 0.5 mm
# (measured 0.25 mm; frictionless it would slide 34 cm) and creeps over 0.4-0.5 s at the regularised law's
# eps_v tan / sqrt(mu^2 - tan^2) within 2 % (measured +0.74 %), the lower sheet held still on the plane by static
# friction, at most 1e-5 m/s (measured 0; cloth-cloth friction does not stick: before static friction held on bodies,
# 2026-11-29, the lower sheet crept too and the sum was checked, +0.69 %; with the repulsion as the normal force +4.28 %). Slide at 25 degrees (tan 0.47 > 0.3): the acceleration between 0.2 and 0.4 s
# is g (sin - mu cos) = 1.479 m/s^2 within 1 %, the issue's target (measured 1.472, -0.44 %: the load as N 0.4 % below
# m g cos and the drag's lag, +0.35 %; 10 % allowed before, when it measured -8.4 %). 1.4-1.8 s each on the shared
# machine (35-40 s each when it was loaded).
clothsim_add_script_test(selfcontact_friction_stick self_friction_incline.sh stick 1 16 0.3)
clothsim_add_script_test(selfcontact_friction_slide self_friction_incline.sh slide 1 25 0.3)
# Stack: a third sheet (0.09 m) on the small one at 25 degrees; both slide at g (sin - mu cos) within 1.5 %
# (measured -1.16 % and -0.12 % with issue 44's contacts, -0.76 % and -0.07 % before; the middle sheet's contacts below must carry the top sheet's load as well: with the
# repulsion as the normal force -7.2 % / -2.2 %, without the load sweeps, -self_collision_friction_load_sweeps 0,
# -0.95 % / -1.36 %). 2-5 s on the shared machine.
clothsim_add_script_test(selfcontact_friction_stack self_friction_incline.sh stack 1 25 0.3)

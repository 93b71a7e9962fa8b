# Collisions with rigid bodies (issue 6, docs/collisions.md).
clothsim_add_test_program(test_collision test_collision.c)

# Sphere drape (input/sphere_drape.yaml at 33 x 33, 2 s): at every output frame no particle is closer to the
# sphere's centre than radius + thickness - 1e-6 m, nor below the ground plane's offset (measured: the
# smallest clearance is round-off, about 1e-17 m: particles in contact sit exactly on the offset surface).
clothsim_add_mpi_test(collision_sphere_drape 1 $<TARGET_FILE:clothsim>
  -scene input/sphere_drape.yaml -grid 33 -output_every 12 -progress_seconds 100
  -output_dir ${CMAKE_BINARY_DIR}/test-output/sphere_drape)
add_test(NAME collision_sphere_drape_clearance
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/checkers/check_sphere_clearance.py
    ${CMAKE_BINARY_DIR}/test-output/sphere_drape/sphere_drape.h5
    --center 0 0.3 0 --radius 0.3 --thickness 0.005 --ground 0 --tolerance 1e-6 --min-frames 41)
# A fixture, not DEPENDS (which only orders tests): ctest -R collision_sphere_drape_clearance runs the drape first, and
# the check is not run on an earlier run's file when the drape fails.
set_tests_properties(collision_sphere_drape PROPERTIES FIXTURES_SETUP collision_sphere_drape_output)
set_tests_properties(collision_sphere_drape_clearance PROPERTIES FIXTURES_REQUIRED collision_sphere_drape_output)

# At rest on the sphere: 33 x 33 at dt = 1/120 s for 6 s; the kinetic energy (0.1 J while the sheet lands)
# must fall below 1e-6 J: held contacts and static friction leave no jitter (measured: 6.0e-10 J with
# -collision_friction explicit, 1.0e-7 J with implicit friction, whose stuck particles creep slowly; docs/collisions.md).
clothsim_add_mpi_test(collision_sphere_rest 1 $<TARGET_FILE:test_run_to_rest>
  -scene input/sphere_drape.yaml -grid 33 -dt 0.008333333333333333 -t_final 6 -output_every 0
  -output_dir ${CMAKE_BINARY_DIR}/test-output/sphere_rest -expect_ke_below 1e-6 -progress_seconds 100)

# Mannequin: a 33 x 33 sheet dropped on the shoulders (tests/data/mannequin_shoulders.yaml, 0.5 s, 120 steps).
# On 1 rank every segment searched with the cell grid is searched again by brute force over all 26,756 triangles
# (-collision_verify: any difference in the triangle hit or its parameter stops the run; measured: 162 crossings
# agreed, 6454 before particles stuck by static friction were held still in the solve instead of crossing back
# every step); at the end no particle is inside the body by the winding-number test (measured: 0; 30 particles
# start inside the neck and are pushed out; 63 are in contact at the end).
# The lower bound on verified crossings was 100 (162 measured with -collision_friction explicit); with friction in
# the implicit step (the default since issue 27) 71 crossings happen in these 120 steps (60 in contact at the end,
# 0 inside; why fewer particles cross the surface itself was not analysed). The bound only makes sure that the comparison
# with brute force was exercised on many crossings, so it was 50. Since the friction of a held particle whose slip the
# step could reverse acts as a drag (docs/collisions.md, "The drag where a reversal is possible", 2026-11-27), 45
# crossings happen (71 in contact at the end, 0 inside): fewer particles are thrown back through the surface by their
# neighbours' friction. The bound is 30: the comparison is still exercised on dozens of crossings.
clothsim_add_mpi_test(collision_mannequin 1 $<TARGET_FILE:test_collision>
  -scene tests/data/mannequin_shoulders.yaml -collision_verify -progress_seconds 100
  -expect_inside_at_most 0 -expect_verified_at_least 30 -expect_contacts_at_least 30
  -output_dir ${CMAKE_BINARY_DIR}/test-output/mannequin_np1)
# A sheet dropped on one shoulder (tests/data/mannequin_shoulder.yaml) on 1 and 2 ranks: both end with nothing
# inside and at least 5 particles in contact (measured: 70 and 51). On 2 ranks the per-rank cell grids must find
# exactly what brute force finds: the grid run and a -collision_search brute_force run end bit-identical
# (measured: 0 m). The 1- and 2-rank states are not compared: a sheet landing on a mesh is not deterministic to
# round-off since particles within the thickness of the mesh are contacts (docs/collisions.md): whether a
# landing particle is caught one step earlier or later turns 1e-15 m into 1e-3 m within a few steps (measured:
# 1 rank at -ksp_rtol 1e-5 against 1e-12, 1.5 mm after 24 steps; 1 against 2 ranks, 0.9 mm).
clothsim_add_mpi_test(collision_mannequin_shoulder 1 $<TARGET_FILE:test_collision>
  -scene tests/data/mannequin_shoulder.yaml -progress_seconds 100
  -expect_inside_at_most 0 -expect_contacts_at_least 5
  -output_dir ${CMAKE_BINARY_DIR}/test-output/mannequin_shoulder_np1)
clothsim_add_mpi_test(collision_mannequin_np2 2 $<TARGET_FILE:test_collision>
  -scene tests/data/mannequin_shoulder.yaml -progress_seconds 100
  -expect_inside_at_most 0 -expect_contacts_at_least 5
  -output_dir ${CMAKE_BINARY_DIR}/test-output/mannequin_shoulder_np2)
clothsim_add_mpi_test(collision_mannequin_np2_brute_force 2 $<TARGET_FILE:test_collision>
  -scene tests/data/mannequin_shoulder.yaml -progress_seconds 100 -collision_search brute_force
  -expect_inside_at_most 0 -expect_contacts_at_least 5
  -output_dir ${CMAKE_BINARY_DIR}/test-output/mannequin_shoulder_np2_brute_force)
add_test(NAME collision_mannequin_np2_grid_same_as_brute_force
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/checkers/compare_checkpoints.py
    ${CMAKE_BINARY_DIR}/test-output/mannequin_shoulder_np2/checkpoint_000120.h5
    ${CMAKE_BINARY_DIR}/test-output/mannequin_shoulder_np2_brute_force/checkpoint_000120.h5 --tolerance 0)
set_tests_properties(collision_mannequin_np2 collision_mannequin_np2_brute_force PROPERTIES FIXTURES_SETUP collision_mannequin_np2_checkpoints)
set_tests_properties(collision_mannequin_np2_grid_same_as_brute_force PROPERTIES FIXTURES_REQUIRED collision_mannequin_np2_checkpoints)


# Coulomb friction against a stiff tension: a strip on a table, over a frictionless rounded edge, stays at
# 0.32 of the friction limit and slides off at 1.3 (tests/drivers/friction_strip.sh; about 5 s).
clothsim_add_script_test(collision_friction_strip friction_strip.sh)
set_tests_properties(collision_friction_strip PROPERTIES PROCESSORS 1)

# Friction inside the implicit step (-collision_friction implicit, the default; docs/collisions.md) on a plane tilted
# by theta, against the analytic answers (tests/drivers/friction_incline.sh; no damping, dt 1/240 s, 1 s):
# - a strip of 5 x 2 particles, mu_s 0.5, mu_k 0.3, tan(theta) = 0.45 = 0.9 mu_s (above mu_k: only static friction
#   holds it): static friction holds it still ("Static friction that holds"): at most 0.5 mm moved along the slope in
#   1 s and every particle slower than 1e-5 m/s (0.01 mm/s) over 0.5-1 s and at the end (measured 1e-18 m, 0 m/s;
#   before 2026-11-29, the regularised law alone: 2.04e-4 m moved, creeping at 2.067e-4 m/s);
# - the same strip at tan(theta) = 0.499 = 0.998 mu_s, beyond the largest pull the regularised law resists
#   (0.991 mu_s N at the defaults): held still alike (measured 3e-19 m, 0 m/s; before: it slid off, 0.72 m in 1 s);
# - at 0.9 mu_s with -collision_friction_stick_velocity 0 (no sticking) the regularised law's steady creep
#   eps_v r / sqrt(1 - r^2) = 2.065e-4 m/s (r = 0.9, eps_v = 1e-4 m/s) within 25 % (measured 2.067e-4 m/s);
# - the same strip at tan(theta) = 0.6 = 1.2 mu_s slides with g (sin(theta) - mu_k cos(theta)) = 2.52361 m/s^2
#   within 1 % (measured between 0.5 and 1 s: 2.52361 m/s^2, error below 1e-5 relative);
# - a 13 x 13 sheet of 0.2 x 0.2 m on a plane tilted by 25 degrees (tan = 0.466), 2 ranks: it stays with
#   mu = 0.6 (held still, measured 4e-18 m, 0 m/s; before, creeping at 1.235e-4 m/s) and slides with mu = 0.3 at
#   1.47862 m/s^2 within 1 % (measured 1.47862 m/s^2).
# The old treatment (-collision_friction explicit) passes the strip cases as well (it stops the stuck strip
# exactly: 0 m moved), so they run with it too. The stick tests fail on the code before static friction held
# (it crept at 2.067e-4, 5.05e-4 at 0.98 mu_s, and slid at 0.998 mu_s). About 1-4 s each.
clothsim_add_script_test(collision_friction_incline_stick friction_incline.sh stick 1 5 2 0.04 0.01 24.2277 0.5 0.3)
clothsim_add_script_test(collision_friction_incline_slide friction_incline.sh slide 1 5 2 0.04 0.01 30.9638 0.5 0.3)
clothsim_add_script_test(collision_friction_incline_stick_near_limit friction_incline.sh stick 1 5 2 0.04 0.01 26.5192 0.5 0.3)
clothsim_add_script_test(collision_friction_incline_creep_regularised friction_incline.sh stick 1 5 2 0.04 0.01 24.2277 0.5 0.3 -collision_friction_stick_velocity 0)
# With -integrator bdf2 (docs/model.md section 5; the same friction in the solve, its history filtered by the
# constraints): the held strip slides at the analytic acceleration as with backward Euler (measured 2.52361 m/s^2,
# error below 1e-5) and sticks at 0.998 mu_s (0 m/s). About 1 s each.
clothsim_add_script_test(collision_friction_incline_slide_bdf2 friction_incline.sh slide 1 5 2 0.04 0.01 30.9638 0.5 0.3 -integrator bdf2)
clothsim_add_script_test(collision_friction_incline_stick_bdf2 friction_incline.sh stick 1 5 2 0.04 0.01 26.5192 0.5 0.3 -integrator bdf2)
clothsim_add_script_test(collision_friction_incline_stick_explicit friction_incline.sh stick 1 5 2 0.04 0.01 24.2277 0.5 0.3 -collision_friction explicit)
clothsim_add_script_test(collision_friction_incline_slide_explicit friction_incline.sh slide 1 5 2 0.04 0.01 30.9638 0.5 0.3 -collision_friction explicit)
clothsim_add_script_test(collision_friction_sheet_tilted_stays_np2 friction_incline.sh stick 2 13 13 0.2 0.2 25 0.6 0.6)
clothsim_add_script_test(collision_friction_sheet_tilted_slides_np2 friction_incline.sh slide 2 13 13 0.2 0.2 25 0.3 0.3)
set_tests_properties(collision_friction_sheet_tilted_stays_np2 collision_friction_sheet_tilted_slides_np2 PROPERTIES PROCESSORS 2)

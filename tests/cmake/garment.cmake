# Garment assembly (issue 8): pattern import from DXF.
clothsim_add_script_test(pattern_dxf_round_trip pattern_dxf_round_trip.sh)
# The dress of the main job on a coarser grid (882 particles), 2 ranks, checked against issue 8's targets by
# postprocess/garment_quality.py --check: all pairs sewn below 2 mm, 0 inside, 0 crossings, strain < 0.10,
# kinetic energy < 1e-3 J. Measured 2026-11-24 (cell shear model): 106/106 sewn, 0.12 mm, 0, 0, 0.016, 3.9e-7 J (36 s under load).
# At rest (issue 49): kinetic energy below 8e-6 J, within 10 times the measured 8.358e-7 J (2026-11-29, two runs alike
# to the printed digits; 2 ranks, the only count these tests run). Issue 8's 1e-3 J, the bound before, lies three orders
# above it; garment_coarse.sh refuses to run without --ke-max.
clothsim_add_script_test(garment_dress_coarse garment_coarse.sh input/dress.yaml "26 11=26 6" "4 32=4 16" "33 25=17 13" -- --ke-max 8e-6)
set_tests_properties(garment_dress_coarse PROPERTIES TIMEOUT 1200 LABELS garment)
# The T-shirt (input/tshirt.yaml, written by scripts/tshirt_scenes.py) on a coarser grid: front and back
# 13 x 13, sleeves 11 x 5 (450 particles instead of 1,628), the same pattern and seams (the armpit and the
# sleeve cap's middle stay nodes), checked against the same targets. Measured 2026-11-25: 56/56 sewn, 0.29 mm,
# 0 inside, 0 crossings, strain 0.027, 1.1e-7 J, 100 Krylov its/step (625 steps); 1,259 s wall on a machine
# loaded 15-30 times over by other runs and paused at times (the 1,250-step coarse dress took 36 s when quieter).
# At rest: below 5e-4 J, within 10 times the measured 5.387e-5 J (2026-11-29, two runs alike; 1.1e-7 J before edge
# threads carried their true width).
clothsim_add_script_test(garment_tshirt_coarse garment_coarse.sh input/tshirt.yaml "25 25=13 13" "21 9=11 5" -- --ke-max 5e-4)
set_tests_properties(garment_tshirt_coarse PROPERTIES TIMEOUT 1200 LABELS garment)
# The fitted dress (issue 26): its pattern and scenes are what jobs/dress_fitted_pattern.py drafts from the
# mannequin (tests/drivers/dress_fitted_pattern.sh, 17 s under load); the fold counter of the fine-vs-coarse comparison on
# synthetic hems with known fold counts (postprocess/hem_folds.py --self-test, 14 hems, 0.3 s).
clothsim_add_script_test(dress_fitted_pattern dress_fitted_pattern.sh)
add_test(NAME hem_folds_self_test COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/postprocess/hem_folds.py --self-test)
# The fitted dress at 20 mm (input/dress_fitted_coarse.yaml, 2,646 particles, as jobs/dress_fitted_pattern.py writes
# it), 2 ranks, with the main job's -cloth_stiffness gauss_newton, checked against the same targets at t = 3 s instead
# of 5 s: in the 5 s run the left strap's front end, folded on itself, was kicked now and then until t = 2.7 s
# (a particle's strain up to 0.51 for one frame), and from then on every target held (docs/results.md, "The fitted
# dress"). Measured 2026-11-25 at 3 s (this test): 200/200 sewn, 0.13 mm, 0 inside, 0 crossings, strain 0.017,
# 3.2e-5 J, 296 Krylov its/step (221,811 in 750 steps); 384 s wall on the shared machine at a load of about 10, 71 s
# in the CI run of a fresh clone on the idle machine (2026-11-26, ctest -j2 of the whole suite).
# The kicks were the shoulders' friction carrying held particles through v_t = 0 inside the solve (docs/collisions.md,
# "The drag where a reversal is possible"); since that was fixed (2026-11-27) the frames (every 5 steps) are checked
# too: from t = 1 s on no particle faster than 1 m/s and no link strained beyond 0.10 in any frame. Measured on the
# main job's 5 s run, frames every 5 steps, from t = 1 s: fastest 0.35 m/s, largest strain 0.045 (before the fix:
# 5.97 m/s at t = 3-4 s and 0.265, strain above 0.10 in 7 frames).
# At rest: below 3.5e-4 J, within 10 times the measured 3.597e-5 J (2026-11-29, two runs alike).
clothsim_add_script_test(garment_dress_fitted_coarse garment_coarse.sh input/dress_fitted_coarse.yaml -- --ke-max 3.5e-4)
# Its timeout is 3000 s, not the 1200 s of the other garment tests: in a full ctest -j2 on the shared machine
# (another helper's ctest running too, load about 10) it ran out of 1200 s alone with garment_dress_coarse
# taking 932 s (36 s quiet); the timeout guards against a hung run, it does not time the test.
set_tests_properties(garment_dress_fitted_coarse PROPERTIES TIMEOUT 3000 LABELS garment)
set_property(TEST garment_dress_fitted_coarse APPEND PROPERTY ENVIRONMENT "CLOTHSIM_OPTIONS=-t_final 3 -cloth_stiffness gauss_newton -output_every 5" "FRAMES_SETTLED=--from 1 --max-speed 1 --max-strain 0.10")
# Layering (issue 26): the T-shirt under the dress (input/tshirt_dress.yaml, written by scripts/tshirt_scenes.py) on
# the coarse grids of garment_tshirt_coarse and garment_dress_coarse (1,330 particles instead of 4,106, 162 seam
# pairs), both garments sewn in one run with cloth-cloth contact over all their pieces, checked against the same
# targets; garment_quality.py's crossings cover the pairs within each garment and between the two (quality.json's
# garments and fabric_crossings_between_garments). Measured 2026-11-26 (this test): 162/162 sewn (all by t = 0.144 s),
# 1.06 mm (the straps' seams), 0 inside, 0 crossings (0 in the T-shirt, 0 in the dress, 0
# between them), strain 0.091 (the bodice's top at the straps), 7.7e-5 J, 178 Krylov its/step (111,246 in 625
# steps); 76 s in the idle CI run of 2026-11-26 (204 s on the shared machine at a load of about 11). It fails on the scenes tried before this one
# (docs/results.md, "Layering"): the straps through the T-shirt's back (18 crossings, strain 0.30) at a pull of
# 1000 m/s^2, the skirt's hems crossed (15) at 300, side seams held open by the T-shirt's folds or its sleeves.
# Since edge threads carry their true width (half a spacing, issue 50, 2026-11-29) the bodice's top edge, where each
# strap hangs on 4 edge nodes of this coarse grid, strains 0.102 (0.1018 and 0.1017 in two runs; 0.091 before: the
# links along the edge are half as stiff as before); the strain limit of this test is 0.11 instead of issue 8's 0.10
# (the main job's fitted dress keeps 0.018, and the other targets are unchanged: 0 inside, 0 crossings).
# At rest: below 7.8e-5 J, within 10 times the measured 7.831e-6 J (2026-11-29, two runs alike; 7.7e-5 J on 2026-11-26, before edge
# threads carried their true width).
clothsim_add_script_test(garment_layered_coarse garment_coarse.sh input/tshirt_dress.yaml "25 25=13 13" "21 9=11 5" "26 11=26 6" "4 32=4 16" "33 25=17 13" -- --strain-max 0.11 --ke-max 7.8e-5)
# Its timeout is 3000 s, as the fitted dress's: in a full ctest -j2 on the shared machine (three other helpers' runs
# and test suites, load about 20) it ran out of 1200 s at t = 1.84 s of 2.5, with garment_dress_coarse out of
# 1200 s beside it (36 s quiet); the timeout guards against a hung run, it does not time the test.
set_tests_properties(garment_layered_coarse PROPERTIES TIMEOUT 3000 LABELS garment)

# Each garment test runs clothsim on 2 ranks (tests/drivers/garment_coarse.sh): PROCESSORS 2 keeps ctest -j2 from running
# another test beside it. Two of them side by side put 4 busy-polling MPI ranks on 2 cores: in a CI run of 2026-11-26
# garment_dress_fitted_coarse then took 9 minutes for its first 86 of 750 steps (137 s for all of them alone).
set_tests_properties(garment_dress_coarse garment_tshirt_coarse garment_dress_fitted_coarse garment_layered_coarse PROPERTIES PROCESSORS 2)

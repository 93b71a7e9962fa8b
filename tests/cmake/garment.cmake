# Garment assembly (issue 8): pattern import from DXF.
clothsim_add_script_test(pattern_dxf_round_trip pattern_dxf_round_trip.sh)
# The dress of the main job on a coarser grid (882 particles), 2 ranks, checked against issue 8's targets by
# postprocess/garment_quality.py --check: all pairs sewn below 2 mm, 0 inside, 0 crossings, strain < 0.10,
# kinetic energy < 1e-3 J. Measured 2026-11-24 (cell shear model): 106/106 sewn, 0.12 mm, 0, 0, 0.016, 3.9e-7 J (36 s under load).
clothsim_add_script_test(garment_dress_coarse garment_coarse.sh input/dress.yaml "26 11=26 6" "4 32=4 16" "33 25=17 13")
set_tests_properties(garment_dress_coarse PROPERTIES TIMEOUT 1200 LABELS garment)
# The T-shirt (input/tshirt.yaml, written by scripts/tshirt_scenes.py) on a coarser grid: front and back
# 13 x 13, sleeves 11 x 5 (450 particles instead of 1,628), the same pattern and seams (the armpit and the
# sleeve cap's middle stay nodes), checked against the same targets. Measured 2026-11-25: 56/56 sewn, 0.29 mm,
# 0 inside, 0 crossings, strain 0.027, 1.1e-7 J, 100 Krylov its/step (625 steps); 1,259 s wall on a machine
# loaded 15-30 times over by other runs and paused at times (the 1,250-step coarse dress took 36 s when quieter).
clothsim_add_script_test(garment_tshirt_coarse garment_coarse.sh input/tshirt.yaml "25 25=13 13" "21 9=11 5")
set_tests_properties(garment_tshirt_coarse PROPERTIES TIMEOUT 1200 LABELS garment)
# The fitted dress (issue 26): its pattern and scenes are what jobs/dress_fitted_pattern.py drafts from the
# mannequin (tests/drivers/dress_fitted_pattern.sh, 17 s under load); the fold counter of the fine-vs-coarse comparison on
# synthetic hems with known fold counts (postprocess/hem_folds.py --self-test, 14 hems, 0.3 s).
clothsim_add_script_test(dress_fitted_pattern dress_fitted_pattern.sh)
add_test(NAME hem_folds_self_test COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/postprocess/hem_folds.py --self-test)

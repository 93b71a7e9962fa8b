# Garment assembly (issue 8): pattern import from DXF.
clothsim_add_script_test(pattern_dxf_round_trip pattern_dxf_round_trip.sh)

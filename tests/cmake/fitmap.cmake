# Fit maps (issue 26 item 4, docs/results.md "Fit maps"): contact pressure and membrane stress per particle in
# the XDMF series, checked against answers known without the simulator.

# A sheet at rest on a mesh table (tests/data/sheet_on_table.yaml, 1.5 s, 2 ranks): every particle's pressure
# is the areal mass times g, 0.2 x 9.81 = 1.962 N/m^2, edges and corners included, and all 169 are in contact.
# Tolerance 1e-6 relative: at rest the held contact cancels exactly the weight (measured: 2.4e-15).
clothsim_add_mpi_test(fitmap_sheet_on_table 2 $<TARGET_FILE:clothsim>
  -scene tests/data/sheet_on_table.yaml -progress_seconds 100
  -output_dir ${CMAKE_BINARY_DIR}/test-output/fitmap_sheet_on_table)
add_test(NAME fitmap_pressure_is_weight
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/checkers/check_fit_maps.py pressure
    ${CMAKE_BINARY_DIR}/test-output/fitmap_sheet_on_table/sheet_on_table.h5 --expect 1.962 --rtol 1e-6 --min-contacts 169)
# Fixtures, not DEPENDS (which only orders tests): running a check alone runs its simulation first, and a check is
# not run on an earlier run's series when its simulation fails.
set_tests_properties(fitmap_sheet_on_table PROPERTIES FIXTURES_SETUP fitmap_sheet_on_table_series)
set_tests_properties(fitmap_pressure_is_weight PROPERTIES FIXTURES_REQUIRED fitmap_sheet_on_table_series)

# A sheet hanging from its pinned top row (tests/data/hanging_sheet_stress.yaml, 3 s, 2 ranks, about 7 s): down
# the middle column the stress is the weight per width of the fabric below, rho g (H - (j - 1/2) dv), 0.569 N/m
# at the top. Tolerance 1e-4 N/m (0.02 % of the top value): the weak shear spring coupled the column to the
# edge columns, which were stiffer for their mass, five spacings away (measured: 5.5e-7 N/m); since edge threads own
# half a spacing (issue 50) every column hangs alike, measured 4.6e-12 N/m.
clothsim_add_mpi_test(fitmap_hanging_sheet 2 $<TARGET_FILE:clothsim>
  -scene tests/data/hanging_sheet_stress.yaml -progress_seconds 100
  -output_dir ${CMAKE_BINARY_DIR}/test-output/fitmap_hanging_sheet)
add_test(NAME fitmap_stress_is_weight_below
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/checkers/check_fit_maps.py stress
    ${CMAKE_BINARY_DIR}/test-output/fitmap_hanging_sheet/hanging_sheet_stress.h5
    --grid 11 16 --column 5 --density 0.2 --gravity 9.81 --spacing 0.02 --atol 1e-4)
set_tests_properties(fitmap_hanging_sheet PROPERTIES FIXTURES_SETUP fitmap_hanging_sheet_series)
set_tests_properties(fitmap_stress_is_weight_below PROPERTIES FIXTURES_REQUIRED fitmap_hanging_sheet_series)

# The docs name what the code has (tests/drivers/check_docs_map.sh): every src/*.c and src/*.h is in
# docs/architecture.md's map and every file the map names exists; every option the sources register, and every
# option -help prints in clothsim's own groups (for the fitted dress and the hanging sheet), is in docs/options.md.
# It runs clothsim -help twice (set-up only, under 2 s).
clothsim_add_script_test(docs_map check_docs_map.sh)
set_tests_properties(docs_map PROPERTIES TIMEOUT 60)

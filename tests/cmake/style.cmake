# Code style (issue 49 item 5): the sources as .clang-format formats them, by clang-format --dry-run -Werror
# (tests/drivers/check_clang_format.sh; src/*.c and src/*.h; under 2 s).
clothsim_add_script_test(style_clang_format check_clang_format.sh)
set_tests_properties(style_clang_format PROPERTIES TIMEOUT 60 LABELS style)

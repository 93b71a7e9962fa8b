# Code style (issue 49 item 5): the sources as .clang-format formats them, by clang-format --dry-run -Werror
# (tests/drivers/check_clang_format.sh; src/*.c and src/*.h; one clang-format call over the 85 files, 0.9 s of CPU;
# 9 s wall on the shared machine at a load of 12; TIMEOUT 120 against a hang, not a timing).
clothsim_add_script_test(style_clang_format check_clang_format.sh)
set_tests_properties(style_clang_format PROPERTIES TIMEOUT 120 LABELS style)

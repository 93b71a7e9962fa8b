#!/bin/bash
# The sources are formatted as the repository's .clang-format says: `clang-format --dry-run -Werror` over
# src/*.c and src/*.h (Debian 12's clang-format 14, installed by scripts/install_deps.sh). The test programs in
# tests/programs/ are not checked yet: five of them and tests/fault/fault_full_disk.c drift (2026-11-29).
# Fails with the files that drift and the command that formats them; fails, not skips, without clang-format.
#
#   check_clang_format.sh      (run from the repository root; CLANG_FORMAT: the binary, default clang-format)
set -uo pipefail
clang_format=${CLANG_FORMAT:-clang-format}
command -v "$clang_format" > /dev/null || { echo "FAIL: $clang_format not found (bash scripts/install_deps.sh installs it)"; exit 1; }
[[ -f .clang-format ]] || { echo "FAIL: no .clang-format in $(pwd): run from the repository root"; exit 1; }
shopt -s nullglob
files=(src/*.c src/*.h)
[[ ${#files[@]} -gt 0 ]] || { echo "FAIL: no src/*.c or src/*.h under $(pwd)"; exit 1; }
drift=()
if ! "$clang_format" --dry-run -Werror --style=file "${files[@]}" > /dev/null 2>&1; then
  for file in "${files[@]}"; do
    "$clang_format" --dry-run -Werror --style=file "$file" > /dev/null 2>&1 || drift+=("$file")
  done
  [[ ${#drift[@]} -gt 0 ]] || drift=("(clang-format failed on all the files at once but on none alone)")
fi
if [[ ${#drift[@]} -gt 0 ]]; then
  echo "FAIL: ${#drift[@]} of ${#files[@]} files are not formatted as .clang-format says: ${drift[*]}"
  "$clang_format" --dry-run -Werror --style=file "${drift[@]}" 2>&1 | head -40
  echo "Format them with: $clang_format -i ${drift[*]}"
  exit 1
fi
echo "PASS: ${#files[@]} files formatted as .clang-format says ($("$clang_format" --version))"

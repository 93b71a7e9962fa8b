#!/bin/bash
# A scene whose gravity is a flow sequence nested a million levels deep ([[[...]]], 2 MB) is refused at once, naming the
# file, the line and the limit (src/scene_reader.c, SceneCheckNesting), by tests/drivers/expect_error.sh. Before, it
# did not answer within 120 s: libyaml's scanner takes time quadratic in the depth of flow collections (8.7 s for
# 40,000 levels), and clothsim handed it the whole file.
#
#   deep_nesting.sh RANKS
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
scene=$dir/deep_gravity.yaml
{
  sed -n '/^gravity:/q;p' input/hanging_sheet.yaml
  printf 'gravity: '
  head -c 1000000 /dev/zero | tr '\0' '['
  head -c 1000000 /dev/zero | tr '\0' ']'
  printf '\n'
  sed -n '/^gravity:/,$p' input/hanging_sheet.yaml | tail -n +2
} > "$scene"
grep -q "^gravity: \[\[\[" "$scene" || { echo "FAIL: the scene was not written"; exit 1; }
bash "$tests/drivers/expect_error.sh" --status 2 "$1" "$scene" "line 13: lists and maps nested more than 32 levels deep: expected at most 32 levels"

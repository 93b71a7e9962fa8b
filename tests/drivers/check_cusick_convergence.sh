#!/bin/bash
# postprocess/cusick_convergence.py on hand-made trial files (no simulation): the table's means, standard
# deviations and errors against values worked out by hand, a fabric spread over two directories, the picture,
# and the refusals (a run found twice, a fabric with no runs, a malformed --measured).
# Usage: check_cusick_convergence.sh WORKDIR
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$1
py=/usr/bin/python3
tool=$root/postprocess/cusick_convergence.py
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work/a" "$work/b"
put() { # put DIR PRESET GRID TRIAL DC FOLDS
  echo "{\"drape_coefficient\": $5, \"folds\": $6, \"max_speed\": 1e-6}" > "$work/$1/cusick_$2_$3_t$4.json"
}
put a fab 49 1 0.30 8; put a fab 49 2 0.26 9; put a fab 49 3 0.28 9   # mean 0.28, sd 0.02
put b fab 97 1 0.21 10; put b fab 97 2 0.23 11                       # mean 0.22, sd 0.014142
put b other 97 1 0.50 6                                              # not asked for: ignored
$py "$tool" --measured fab=0.25 --out "$work/c.png" "$work/a" "$work/b" > "$work/table.md"
cat "$work/table.md"
grep -qF "| fab (0.250) | 49 | 6.25 | 0.300 (8), 0.260 (9), 0.280 (9) | 0.280 | 0.020 | +0.030 |" "$work/table.md" || fail "grid 49 row"
grep -qF "| fab (0.250) | 97 | 3.12 | 0.210 (10), 0.230 (11) | 0.220 | 0.014 | -0.030 |" "$work/table.md" || fail "grid 97 row"
! grep -q other "$work/table.md" || fail "a fabric not asked for is in the table"
$py "$tool" --measured other=- "$work/b" > "$work/unmeasured.md"   # a fabric without a measured value
grep -qF "| other (-) | 97 | 3.12 | 0.500 (6) | 0.500 | 0.000 | - |" "$work/unmeasured.md" || fail "row of a fabric without a measured value"
[ "$(head -c 4 "$work/c.png" | tail -c 3)" = PNG ] || fail "no PNG written"
put a fab 97 2 0.22 11
if $py "$tool" --measured fab=0.25 "$work/a" "$work/b" > "$work/dup.log" 2>&1; then fail "a run found twice was accepted"; fi
grep -q "grid 97, trial 2 found twice" "$work/dup.log" || fail "message for a run found twice: $(cat "$work/dup.log")"
if $py "$tool" --measured none=0.3 "$work/b" > "$work/none.log" 2>&1; then fail "a fabric with no runs was accepted"; fi
grep -q "no trial runs of none" "$work/none.log" || fail "message for no runs: $(cat "$work/none.log")"
if $py "$tool" --measured fab "$work/b" > "$work/bad.log" 2>&1; then fail "--measured without a value was accepted"; fi
grep -q "wants PRESET=DC" "$work/bad.log" || fail "message for a bad --measured: $(cat "$work/bad.log")"
echo "cusick_convergence.py: table, picture and refusals as expected"

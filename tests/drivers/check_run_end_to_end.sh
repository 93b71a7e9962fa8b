#!/bin/bash
# End-to-end run of the binary: the hanging sheet at -grid 9 for 24 steps of 1/240 s on RANKS ranks,
# then checks the printed progress line and "Done:" and the final checkpoint with h5py
# (check_final_checkpoint.py, Debian's /usr/bin/python3 or $PYTHON).
#
#   check_run_end_to_end.sh MPIEXEC RANKS DIR [REFERENCE_DIR]
#
# REFERENCE_DIR: the directory of the same run on another number of ranks; positions must agree.
set -euo pipefail
mpiexec=$1 ranks=$2 dir=$3 reference=${4:-}
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
tests=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-/usr/bin/python3}

rm -rf "$dir"
mkdir -p "$dir"
# -progress_seconds 0: a progress line after every step, so the last one is certain to be there.
"$mpiexec" -n "$ranks" "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 24 \
  -output_dir "$dir" -progress_seconds 0 >"$dir/stdout.txt" 2>"$dir/stderr.txt" || {
  echo "FAIL: clothsim exited with status $?"; cat "$dir/stdout.txt" "$dir/stderr.txt"; exit 1; }

fail() { echo "FAIL: $1"; echo "---- stdout ----"; cat "$dir/stdout.txt"; echo "---- stderr ----"; cat "$dir/stderr.txt"; exit 1; }
grep -qE '^step +24/24 +t = 0\.10000 s +wall [0-9.]+ s +KSP its [0-9]+ .*ETA' "$dir/stdout.txt" ||
  fail "no progress line for step 24/24 at t = 0.10000 s"
grep -q '^Done: 24 steps' "$dir/stdout.txt" || fail "no 'Done: 24 steps' line"
! grep -qE "never used|ERROR" "$dir/stderr.txt" || fail "clothsim reported an error or unused options on stderr"
[[ -f "$dir/checkpoint_000024.h5" ]] || fail "no final checkpoint $dir/checkpoint_000024.h5"

# 9 x 9 = 81 particles; pins: particles 0 and 8 (the corners of the edge z = 0), at (0,1,0) and (1,1,0).
compare=()
[[ -z "$reference" ]] || compare=(--compare "$reference/checkpoint_000024.h5" --atol 1e-6)
"$python" "$tests/checkers/check_final_checkpoint.py" "$dir/checkpoint_000024.h5" --particles 81 --step 24 --time 0.1 \
  --pins 0,8 --pin-positions "0,1,0;1,1,0" "${compare[@]}" || fail "the final checkpoint is not as expected"

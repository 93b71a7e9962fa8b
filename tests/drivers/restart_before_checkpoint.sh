#!/bin/bash
# A restart told to end before its checkpoint is refused before it touches the output (src/run.c, ClothRunCheckEnd):
# after 20 steps of the 9 x 9 sheet, -restart checkpoint_000020.h5 with -t_final 0.01 (step 2) and with -steps 10
# must exit 2 with one ERROR line naming what set the end, both steps and the checkpoint, and leave the checkpoint and
# the series byte for byte as they were. Before (issue 48) both printed "Done: 0 steps", exited 0 and rewrote the
# checkpoint. A restart that ends exactly at its checkpoint (-steps 20) still runs no step and exits 0.
#
#   restart_before_checkpoint.sh RANKS
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
mpiexec=${MPIEXEC:-mpiexec}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
sheet=(input/hanging_sheet.yaml)
"$mpiexec" -n "$1" "$CLOTHSIM" -scene "${sheet[0]}" -grid 9 -steps 20 -output_dir "$out/run" > "$out/log" 2>&1 || { tail "$out/log"; fail "the first run failed"; }
ckpt=$out/run/checkpoint_000020.h5
cp -p "$ckpt" "$out/checkpoint.copy"
cp -p "$out/run/hanging_sheet.h5" "$out/series.copy"
expect=(--status 2 "$1" "${sheet[0]}")
bash "$tests/drivers/expect_error.sh" "${expect[@]}" "-t_final 0.01 s ends the run at step 2 (t = 0.00833333 s), before step 20 (t = 0.0833333 s) of checkpoint $ckpt" "-steps >= 20; or -t_final >= 0.0833333 s" \
  -- -grid 9 -restart "$ckpt" -t_final 0.01 -output_dir "$out/run"
bash "$tests/drivers/expect_error.sh" "${expect[@]}" "-steps 10 ends the run at step 10 (t = 0.0416667 s), before step 20" -- -grid 9 -restart "$ckpt" -steps 10 -output_dir "$out/run"
cmp -s "$ckpt" "$out/checkpoint.copy" || fail "the refused restarts rewrote $ckpt"
cmp -s "$out/run/hanging_sheet.h5" "$out/series.copy" || fail "the refused restarts changed the series"
[ "$(ls "$out/run"/checkpoint_*.h5)" == "$ckpt" ] || fail "the refused restarts wrote checkpoints: $(ls "$out/run")"
"$mpiexec" -n "$1" "$CLOTHSIM" -scene "${sheet[0]}" -grid 9 -restart "$ckpt" -steps 20 -output_dir "$out/run" > "$out/log" 2>&1 || { tail "$out/log"; fail "the restart at its end failed"; }
grep -q '^Done: 0 steps' "$out/log" || fail "the restart at its end ran steps"
echo "PASS: restarts ending before checkpoint step 20 refused, the checkpoint and the series untouched; -steps 20 runs no step"

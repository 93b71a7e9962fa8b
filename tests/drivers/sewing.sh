#!/usr/bin/env bash
# Sewing two pieces (tests/data/seam_two_pieces.yaml): a clamped piece and a free one 5 cm away, 9
# against 13 nodes along the seam.
#  1. With bending across the seam: every one of the 13 pairs is sewn (gap under 2 mm) before gravity
#     comes on; at the end the widest gap is under 2 mm and the free piece droops like a cantilever:
#     its far edge ends less than 0.12 m below the seam (measured 0.100 m; bending length
#     (B/W)^(1/3) = 0.15 m for its 0.2 m).
#  2. Without it (bend: false) the seam is a hinge: the free piece hangs straight down, its far edge
#     more than 0.19 m below the seam (measured 0.19998 m of 0.2 m).
#  3. The sewn state is part of the checkpoint: 40 steps (mid-pull) + restart + 80 steps equal 120
#     uninterrupted steps bit for bit, on 2 ranks.
set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=tests/data/seam_two_pieces.yaml
sed 's/    bend: true/    bend: false/' "$scene" > "$out/hinge.yaml"

drop() { # drop OUTPUT_DIR: how far the free piece's far edge lies below the seam, m
  /usr/bin/python3 - "$1" <<'PY'
import glob, sys, h5py
f = sorted(glob.glob(sys.argv[1] + "/checkpoint_*.h5"))[-1]
x = h5py.File(f, "r")["/state/position"][:]
free, fixed = x[81:].reshape(13, 9, 3), x[:81].reshape(9, 9, 3)
print("%.6f" % (fixed[:, 8, 1].mean() - free[:, 8, 1].mean()))
PY
}

for case in seam hinge; do
  sc=$scene; [ $case = hinge ] && sc=$out/hinge.yaml
  mpiexec -n 1 "$CLOTHSIM" -scene "$sc" -output_dir "$out/$case" -progress_seconds 0 -output_every 0 > "$out/$case.log" 2>&1 || { tail "$out/$case.log"; fail "$case run failed"; }
  grep -q 'Sewing: all 13 seam pairs sewn' "$out/$case.log" || fail "$case: not every pair was sewn"
  last=$(grep '^step' "$out/$case.log" | tail -1)
  gap=$(echo "$last" | sed -n 's/.*widest gap \([0-9.]*\) mm.*/\1/p')
  awk -v g="$gap" 'BEGIN { exit !(g < 2.0) }' || fail "$case: widest gap $gap mm at the end"
  d=$(drop "$out/$case")
  echo "$case: all 13 pairs sewn, widest gap $gap mm at the end, free edge $d m below the seam"
  eval "drop_$case=$d"
done
awk -v d="$drop_seam" 'BEGIN { exit !(d < 0.12) }' || fail "with seam bending the free piece drops $drop_seam m (expected < 0.12 m)"
awk -v d="$drop_hinge" 'BEGIN { exit !(d > 0.19) }' || fail "without seam bending the free piece drops $drop_hinge m (expected > 0.19 m)"

mpiexec -n 2 "$CLOTHSIM" -scene "$scene" -output_dir "$out/whole" -steps 120 -progress_seconds 100 > "$out/whole.log" 2>&1 || fail "uninterrupted run failed"
mpiexec -n 2 "$CLOTHSIM" -scene "$scene" -output_dir "$out/parts" -steps 40 -progress_seconds 100 > "$out/part1.log" 2>&1 || fail "first part failed"
grep -q 'Sewing: all' "$out/part1.log" && fail "the first part already finished sewing: the restart would not test the pull phase"
mpiexec -n 2 "$CLOTHSIM" -scene "$scene" -output_dir "$out/parts" -steps 120 -restart "$out/parts/checkpoint_000040.h5" -progress_seconds 100 > "$out/part2.log" 2>&1 || { tail "$out/part2.log"; fail "restart failed"; }
/usr/bin/python3 tests/checkers/compare_restart.py "$out/whole/checkpoint_000120.h5" "$out/parts/checkpoint_000120.h5" || fail "restart differs"
/usr/bin/python3 - "$out/whole/checkpoint_000120.h5" "$out/parts/checkpoint_000120.h5" <<'PY' || fail "sewn state differs"
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r")["/state/seams_sewn"][:] for p in sys.argv[1:])
assert np.array_equal(a, b) and a.sum() > 0, (a.sum(), b.sum())
print("sewn state equal after the restart")
PY
echo "sewing: 3 passed, 0 failed"

#!/bin/bash
# -gravity_ramp: gravity rises linearly over the given time. The sphere-drape sheet (9 x 9, damping 1 1/s) falls
# for 24 steps of 1/240 s with a 1 s ramp, well above the sphere: it translates as a whole (no link stretches),
# so every particle's drop must equal the implicit-Euler recurrence (1 + h c) v' = v + h g min(1, t'/ramp),
# x' = x + h v' to round-off (relative 1e-9; -ksp_rtol 1e-12); without the ramp it would be 27 times larger. A seamed scene
# refuses the option (its sewing phases switch gravity themselves).
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
out=${CLOTHSIM_BUILD:-build}/test-output/gravity_ramp
rm -rf "$out"
mkdir -p "$out"
mpiexec -n 2 "$CLOTHSIM" -scene input/sphere_drape.yaml -grid 9 -steps 24 -gravity_ramp 1 -ksp_rtol 1e-12 -output_every 0 -output_dir "$out" > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; exit 1; }
/usr/bin/python3 - "$out/checkpoint_000024.h5" <<'PY'
import sys
import h5py
import numpy as np
h, c, g, ramp, steps, y0 = 1 / 240, 1.0, 9.81, 1.0, 24, 0.7
v = y = 0.0
for n in range(1, steps + 1):
    v = (v + h * g * min(1.0, n * h / ramp)) / (1 + h * c)
    y += h * v
drop = 0.7 - h5py.File(sys.argv[1], "r")["state/position"][:, 1]
err = np.abs(drop - y).max() / y
print(f"gravity ramp: drop after {steps} steps {drop.mean():.9e} m (recurrence {y:.9e} m), largest relative difference {err:.1e}")
if err > 1e-9:
    sys.exit("FAIL: the sheet's drop does not follow the ramped gravity")
PY
if mpiexec -n 1 "$CLOTHSIM" -scene tests/data/seam_two_pieces.yaml -steps 2 -gravity_ramp 1 -output_dir "$out/seam" > "$out/seam.log" 2>&1; then
  echo "FAIL: -gravity_ramp accepted on a scene with seams"
  exit 1
fi
grep -q "gravity_ramp cannot be used with seams" "$out/seam.log" || { echo "FAIL: no clear message"; tail -5 "$out/seam.log"; exit 1; }
echo "gravity ramp: drop as expected; refused with seams"

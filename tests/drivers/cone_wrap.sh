#!/usr/bin/env bash
# A piece rolled onto a cone (wrap: {apex, axis}; tests/data/cone_wrap.yaml): at t = 0 every particle is
# where the cone's development puts it, to 1e-12 m: at its flat distance rho from the apex, at the angle
# phi / sin(alpha) around the axis (phi its angle from the touching line in the plane), so the placement
# keeps all lengths measured from the apex and along the circles. Measured: 1.1e-16 m.
#   bash tests/drivers/cone_wrap.sh        (CLOTHSIM: the binary)
set -eu
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
tests=$(cd "$(dirname "$0")/.." && pwd)
mpiexec -n 1 "$CLOTHSIM" -scene "$tests/data/cone_wrap.yaml" -output_dir "$out" -progress_seconds 100 > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; echo "FAIL: the run failed"; exit 1; }
/usr/bin/python3 - "$out/cone_wrap.h5" <<'PY'
import sys
import h5py
import numpy as np
s = 0.3
c = np.sqrt(1 - s * s)
with h5py.File(sys.argv[1], "r") as f:
    x = f["frames/000000/position"][...].reshape(-1, 3)
i, j = np.meshgrid(np.arange(9), np.arange(7))
u, v = 0.05 * i.ravel(), 0.05 * j.ravel()              # grid nodes, row by row
rho = np.hypot(u - 0.2, v - 0.5)
theta = np.arctan2(-(u - 0.2), 0.5 - v) / s           # e2 = -x, the touching line g0 = -v_axis
expected = np.stack([-rho * s * np.sin(theta), 0.5 - rho * c, rho * s * np.cos(theta)], axis=1)
error = np.abs(x - expected).max()
print(f"cone_wrap: largest distance from the cone development {error:.2e} m over {len(x)} particles (at most 1e-12)")
sys.exit(0 if error <= 1e-12 else 1)
PY

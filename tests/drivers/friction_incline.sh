#!/usr/bin/env bash
# Coulomb friction on an inclined plane against its analytic answers (docs/collisions.md, "Friction inside the
# implicit step"). A cloth piece (a strip of a few particles, or a sheet) lies at rest on a plane tilted by theta
# about z, no damping, gravity 9.81 m/s^2, dt 1/240 s, 1 s; checkpoints every 0.1 s.
#   stick: tan(theta) < mu_s: the mean displacement along the slope over the 1 s stays below TOL_STICK, and every
#          particle's speed along the slope, at the end and on average over 0.5-1 s, stays below 1e-5 m/s (0.01 mm/s:
#          static friction holds it still). With -collision_friction_stick_velocity 0 (implicit friction without
#          sticking, the regularised law alone) the particles instead creep at the law's steady speed
#          eps_v r / sqrt(1 - r^2), r = tan(theta) / mu_s, within 25 % (the end velocity, mean over particles);
#   slide: tan(theta) > mu_s: the acceleration along the slope between 0.5 s and 1 s (mean velocity difference)
#          is g (sin(theta) - mu_k cos(theta)) within 1 %.
#
#   friction_incline.sh CASE NP GRID_U GRID_V SIZE_U SIZE_V THETA_DEG MU_S MU_K [clothsim options...]
#     CASE stick|slide; NP ranks; the piece has GRID_U x GRID_V particles over SIZE_U (along the slope) x SIZE_V m.
#   (CLOTHSIM: the binary; TOL_STICK in m, default 5e-4)
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
case=$1 np=$2 nu=$3 nv=$4 su=$5 sv=$6 theta=$7 mus=$8 muk=$9
shift 9
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The plane through the origin with outward normal n = (-sin, cos, 0); the piece's u axis runs up the slope,
# (cos, sin, 0); it starts at the plane's thickness (2 mm) along n.
read -r s c <<< "$(/usr/bin/python3 -c "import math; t = math.radians($theta); print(f'{math.sin(t):.15f} {math.cos(t):.15f}')")"
cat > "$out/incline.yaml" <<YAML
name: incline
gravity: [0, -9.81, 0]
fabrics:
  cloth: {density: 0.15, stretch: 1000, shear: 500, bend: 2, damping: 0}
pieces:
  - name: piece
    fabric: cloth
    grid: [$nu, $nv]
    size: [$su, $sv]
    origin: [$(/usr/bin/python3 -c "print(f'{-0.002 * $s}, {0.002 * $c}')"), 0]
    u_axis: [$c, $s, 0]
    v_axis: [0, 0, 1]
    mass: uniform
bodies:
  - name: slope
    type: plane
    point: [0, 0, 0]
    normal: [-$s, $c, 0]
    friction: {static: $mus, kinetic: $muk}
    thickness: 0.002
run:
  integrator: implicit
  dt: 0.004166666666666667
  t_final: 1.0
YAML
mpiexec -n "$np" "$CLOTHSIM" -scene "$out/incline.yaml" -output_dir "$out/run" -output_every 0 -checkpoint_every 24 \
  -checkpoint_keep 0 -progress_seconds 100 "$@" > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; echo "FAIL: the run failed"; exit 1; }
eps=$(/usr/bin/python3 - "$@" <<'PY'
import sys
args = sys.argv[1:]
print(args[args.index("-collision_friction_velocity") + 1] if "-collision_friction_velocity" in args else "1e-4")
PY
)
regularised=$(/usr/bin/python3 - "$@" <<'PY'
import sys
args = sys.argv[1:]
explicit = "explicit" in args
no_stick = "-collision_friction_stick_velocity" in args and float(args[args.index("-collision_friction_stick_velocity") + 1]) == 0
print(1 if no_stick and not explicit else 0)
PY
)
/usr/bin/python3 - "$out/run" "$case" "$theta" "$mus" "$muk" "$eps" "$regularised" "${TOL_STICK:-5e-4}" "$su" <<'PY'
import math
import sys
import h5py
import numpy as np
run, case, theta, mus, muk, eps, regularised, tol, su = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:10])
t = math.radians(theta)
down = np.array([-math.cos(t), -math.sin(t), 0.0])  # along the slope, downhill
def state(step):
    with h5py.File(f"{run}/checkpoint_{step:06d}.h5", "r") as f:
        return f["/state/position"][:].reshape(-1, 3) @ down, f["/state/velocity"][:].reshape(-1, 3) @ down
x0 = -su / 2  # the mean start position along the slope: the piece's u axis runs uphill from the origin
x5, v5 = state(120)
x10, v10 = state(240)
g = 9.81
if case == "stick":
    moved = float(np.mean(x10 - x0))
    r = math.tan(t) / mus
    creep = eps * r / math.sqrt(1 - r * r)
    speed = max(float(np.max(np.abs(v10))), float(np.max(np.abs(x10 - x5))) / 0.5)
    print(f"stick: tan(theta)/mu_s = {r:.3f}; moved {moved:.3e} m along the slope in 1 s (at most {tol:g} m); "
          f"end velocity {np.mean(v10):.3e} m/s, fastest particle over 0.5-1 s {speed:.3e} m/s "
          f"(regularised creep eps_v r/sqrt(1-r^2) = {creep:.3e} m/s)")
    ok = abs(moved) <= tol
    if regularised:
        ok = ok and abs(np.mean(v10) - creep) <= 0.25 * creep
    else:
        print(f"stick: held still: fastest {speed:.3e} m/s, at most 1e-5 m/s")
        ok = ok and speed <= 1e-5
else:
    a = float(np.mean(v10 - v5)) / 0.5
    exact = g * (math.sin(t) - muk * math.cos(t))
    print(f"slide: acceleration {a:.5f} m/s^2, analytic g (sin - mu_k cos) = {exact:.5f} m/s^2, "
          f"error {100 * (a - exact) / exact:+.3f} % (at most 1 %)")
    ok = abs(a - exact) <= 0.01 * exact
print("friction_incline:", "passed" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY

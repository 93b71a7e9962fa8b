#!/usr/bin/env bash
# Coulomb friction between cloth layers (docs/self_collision.md, "Friction between layers") against its analytic
# answers. A large sheet lies on a plane tilted by theta about z (its friction 1.0 holds it); a small sheet rests on
# it, self-collision thickness 5 mm above, no damping, gravity 9.81 m/s^2, dt 1/960 s, 0.5 s, checkpoints every 0.1 s.
#   stick: tan(theta) < mu: the small sheet's mean displacement along the slope over the 0.5 s stays below 0.5 mm
#          (without friction it would slide 0.5 g sin(theta) t^2, 34 cm at 16 degrees), and its creep over 0.4-0.5 s
#          (mean velocity) is the regularised law's between the layers, eps_v tan / sqrt(mu^2 - tan^2), within TOL_CREEP
#          (relative, default 0.02: measured +0.88 % at 16 degrees), while the lower sheet, held by the plane's static
#          friction, moves at most 1e-5 m/s (cloth-cloth friction has no sticking: its creep is the regularised law's;
#          before static friction held on bodies, 2026-11-29, the lower sheet crept too, at eps_v tan / sqrt(1 - tan^2),
#          and the sum was checked: +0.69 %);
#   slide: tan(theta) > mu: its acceleration along the slope between 0.2 s and 0.4 s (mean velocity difference) is
#          g (sin(theta) - mu cos(theta)) within TOL_SLIDE (relative, default 0.01, the issue's target: measured
#          -0.44 % at mu 0.3 and -0.11 % at mu 0.15, 1 and 2 ranks; -8.4 % and -4.3 % before, when 0.10 was allowed;
#          docs/self_collision.md, "Friction between layers").
#
#   stack: as slide, with a third sheet (0.09 m) resting on the small one: both slide with that acceleration within
#          TOL_SLIDE (default 0.015 for this case: measured -1.16 % for the middle sheet and -0.12 % for the top one,
#          which slides on it; the middle sheet's contacts below carry the top sheet's load too, as 647 contacts a
#          search of which 474 are edge pairs since the contacts of a layer are its nearest points and crossing edges,
#          issue 44; -0.76 % and -0.07 % with every particle-triangle pair in range before; with the repulsion as the
#          normal force -7.2 % and -2.2 %).
#
#   self_friction_incline.sh CASE NP THETA_DEG MU [clothsim options...]
#   (CLOTHSIM: the binary; KEEP=1 keeps the run's directory, printed first)
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
case=$1 np=$2 theta=$3 mu=$4
shift 4
eps=1e-4 # eps_v of both friction laws, m/s (their defaults)
out=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$out"' EXIT
# The plane through the origin with outward normal n = (-sin, cos, 0); the pieces' u axes run up the slope,
# (cos, sin, 0). The large sheet (0.4 x 0.2 m, 21 x 11) starts at the plane's thickness (2 mm) along n, the small one
# (0.1 x 0.1 m, 8 x 8, from 0.26 m up the slope) one self-collision thickness (5 mm) above it. The two grids' spacings
# (20 and 14.3 mm) are incommensurate: with equal spacings every particle of the small sheet crossed a grid line of the
# other at once, and the contacts switching together (point over two triangles, parallel edges) jolted the sheet.
read -r s c <<< "$(/usr/bin/python3 -c "import math; t = math.radians($theta); print(f'{math.sin(t):.15f} {math.cos(t):.15f}')")"
origin() { /usr/bin/python3 -c "s, c = $s, $c; u, h, z = $1, $2, $3; print(f'[{u * c - h * s:.15f}, {u * s + h * c:.15f}, {z}]')"; }
# A piece of the scene: piece NAME NU NV SIDE U H Z (a square of SIDE m, its corner U up the slope and H above the
# plane, at z = Z), lying on the slope.
piece() {
  printf '  - name: %s\n    fabric: cloth\n    grid: [%s, %s]\n    size: [%s, %s]\n    origin: %s\n    u_axis: [%s, %s, 0]\n    v_axis: [0, 0, 1]\n    mass: uniform\n' \
    "$1" "$2" "$3" "$4" "$5" "$(origin "$6" "$7" "$8")" "$c" "$s"
}
# stack: a third sheet (0.09 m, 7 x 7, 15 mm spacing) one thickness above the small one, on its middle
stack_piece=""
[ "$case" = stack ] && stack_piece=$(piece top 7 7 0.09 0.09 0.265 0.012 -0.045)
cat > "$out/incline.yaml" <<YAML
name: self_incline
gravity: [0, -9.81, 0]
fabrics:
  cloth: {density: 0.15, stretch: 1000, shear: 500, bend: 2, damping: 0}
pieces:
$(piece under 21 11 0.4 0.2 0 0.002 -0.1)
$(piece over 8 8 0.1 0.1 0.26 0.007 -0.05)
$stack_piece
bodies:
  - name: slope
    type: plane
    point: [0, 0, 0]
    normal: [-$s, $c, 0]
    friction: {static: 1.0, kinetic: 1.0}
    thickness: 0.002
self_collision:
  enabled: true
  thickness: 0.005
  stiffness: 20
run:
  integrator: implicit
  dt: 0.0010416666666666667
  t_final: 0.5
YAML
echo "run in $out"
mpiexec -n "$np" "$CLOTHSIM" -scene "$out/incline.yaml" -output_dir "$out/run" -output_every 0 -checkpoint_every 96 \
  -checkpoint_keep 0 -progress_seconds 100 -self_collision_friction -self_collision_friction_coefficient "$mu" \
  -self_collision_friction_velocity "$eps" -collision_friction_velocity "$eps" -self_collision_view "$@" > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; echo "FAIL: the run failed"; exit 1; }
grep -A3 "^Self-collision" "$out/run.log" || true
/usr/bin/python3 - "$out/run" "$case" "$theta" "$mu" "${TOL_SLIDE:-$([ "$case" = stack ] && echo 0.015 || echo 0.01)}" "${TOL_CREEP:-0.02}" "$eps" <<'PY'
import math
import sys
import h5py
import numpy as np
run, case, theta, mu, tol, tol_creep, eps = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:8])
t = math.radians(theta)
down = np.array([-math.cos(t), -math.sin(t), 0.0])  # along the slope, downhill
over = slice(21 * 11, 21 * 11 + 64)  # the small sheet's particles (natural order: piece by piece)
def state(step, sheet=over):
    with h5py.File(f"{run}/checkpoint_{step:06d}.h5", "r") as f:
        x = f["/state/position"][:].reshape(-1, 3)[sheet]
        v = f["/state/velocity"][:].reshape(-1, 3)[sheet]
    return x @ down, v @ down
x0 = -(0.26 + 0.05) * math.cos(t) * math.cos(t) - (0.26 + 0.05) * math.sin(t) * math.sin(t) + 0.007 * 0.0
x2, v2 = state(192)
x4, v4 = state(384)
x5, v5 = state(480)
g = 9.81
if case == "stick":
    moved = float(np.mean(x5)) - x0
    # the regularised law's creep u, from mu N u / sqrt(u^2 + eps^2) = F_t with F_t / N = tan(theta): the top sheet's on
    # the lower one (the lower one sticks to the plane, friction 1.0); by 0.4 s it has settled to it
    tn = math.tan(t)
    creep_exact = eps * tn / math.sqrt(mu * mu - tn * tn)
    creep = float(np.mean(x5 - x4)) / 0.1
    under = slice(0, 21 * 11)
    under_speed = float(np.max(np.abs(state(480, under)[0] - state(384, under)[0]))) / 0.1
    print(f"stick: tan(theta) = {tn:.4f} < mu = {mu}; the sheet on top moved {moved:.3e} m along the slope in 0.5 s "
          f"(at most 5e-4 m; frictionless: {0.5 * g * math.sin(t) * 0.25:.3f} m); creep over 0.4-0.5 s {creep:.4e} m/s, "
          f"regularised law {creep_exact:.4e} m/s, error {100 * (creep - creep_exact) / creep_exact:+.2f} % (at most {100 * tol_creep:g} %)")
    print(f"stick: the lower sheet on the plane: fastest particle over 0.4-0.5 s {under_speed:.3e} m/s (at most 1e-5 m/s)")
    ok = abs(moved) <= 5e-4 and abs(creep - creep_exact) <= tol_creep * creep_exact and under_speed <= 1e-5
else:
    exact = g * (math.sin(t) - mu * math.cos(t))
    ok = True
    # stack: the two upper sheets slide together, at the same analytic acceleration (the middle one carries both)
    for name, sheet in [("", over)] + ([("top ", slice(21 * 11 + 64, 21 * 11 + 64 + 49))] if case == "stack" else []):
        a = float(np.mean(state(384, sheet)[1] - state(192, sheet)[1])) / 0.2
        print(f"{case}: {name}tan(theta) = {math.tan(t):.4f} > mu = {mu}; acceleration {a:.5f} m/s^2, analytic g (sin - mu cos) = {exact:.5f} m/s^2, "
              f"error {100 * (a - exact) / exact:+.3f} % (at most {100 * tol:g} %)")
        ok = ok and abs(a - exact) <= tol * exact
print("self_friction_incline:", "passed" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY

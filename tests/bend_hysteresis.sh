#!/bin/bash
# Bending hysteresis (forces.h, the friction element beside each thread-bending spring) on a clamped strip loaded
# quasi-statically (tests/data/hysteresis_cantilever.yaml, 2 ranks):
# - tip deflection against the integral of the loading branch M = B K + HB (small deflection, the clamp's last
#   bending spring acting over half a segment behind it, so the lever is L + h/2): within 1 % with HB and
#   without it (measured -0.16 % and -0.24 %; hysteresis cuts the deflection from 5.15 to 2.98 mm);
# - 400 steps + restart + 400 steps bit-identical to 800 (the sliders are in the checkpoint as bend_slider);
# - bend_hysteresis with the link bending model is refused with a clear message; bend_hysteresis_ratio (2HB/B)
#   sets HB = ratio B / 2.
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
out=${CLOTHSIM_BUILD:-build}/test-output/bend_hysteresis
rm -rf "$out"
mkdir -p "$out"
scene=tests/data/hysteresis_cantilever.yaml
sed 's/^    bend_hysteresis: .*/    bend_hysteresis: 0/' "$scene" > "$out/elastic.yaml"
sed 's/^    bend_model: angle/    bend_model: link/' "$scene" > "$out/link.yaml"
run() { # run DIR SCENE ARGS...
  local dir=$1 sc=$2
  shift 2
  mpiexec -n 2 "$CLOTHSIM" -scene "$sc" -gravity_ramp 2 -ksp_rtol 1e-12 -output_dir "$out/$dir" "$@" > "$out/$dir.log" 2>&1 || { tail -20 "$out/$dir.log"; exit 1; }
}
run full "$scene"
run elastic "$out/elastic.yaml"
run split "$scene" -steps 400
run split "$scene" -restart "$out/split/checkpoint_000400.h5"
/usr/bin/python3 tests/compare_restart.py "$out/full/checkpoint_000800.h5" "$out/split/checkpoint_000800.h5"
/usr/bin/python3 - "$out/full/checkpoint_000800.h5" "$out/elastic/checkpoint_000800.h5" <<'PY'
import sys
import h5py
import numpy as np
from scipy.integrate import quad
rho, g, B, ratio = 0.2, 9.81, 5e-3, 10.0  # ratio: CLOTH_HYSTERESIS_STIFFNESS
L = 0.1 + 0.0025 / 2


def deflection(HB):
    """Tip deflection of the loading branch: K = M / ((1 + ratio) B) while the slider sticks, (M - HB) / B after."""
    stick = (1 + ratio) / ratio * HB  # the moment at which the friction element's spring reaches HB
    M = lambda u: rho * g * u * u / 2
    K = lambda u: M(u) / ((1 + ratio) * B) if M(u) <= stick else (M(u) - HB) / B
    u_slide = min(L, np.sqrt(2 * stick / (rho * g)))
    return quad(lambda u: K(u) * u, 0, u_slide)[0] + quad(lambda u: K(u) * u, u_slide, L)[0]


failed = False
for path, HB in zip(sys.argv[1:], (2.4525e-3, 0.0)):
    y = h5py.File(path, "r")["state/position"][:, 1].reshape(3, 42)
    tip, expected = 0.5 - y[:, 41].mean(), deflection(HB)
    err = tip / expected - 1
    print(f"HB {HB:.4e} N m/m: tip deflection {tip * 1e3:.4f} mm, loading branch {expected * 1e3:.4f} mm, relative {err:+.4f}")
    failed |= abs(err) > 0.01
if failed:
    sys.exit("FAIL: tip deflection off the loading branch by more than 1 %")
PY
if mpiexec -n 1 "$CLOTHSIM" -scene "$out/link.yaml" -steps 1 -output_dir "$out/link" > "$out/link.log" 2>&1; then
  echo "FAIL: bend_hysteresis accepted with the link bending model"
  exit 1
fi
grep -q "bending hysteresis needs bend_model: angle" "$out/link.log" || { echo "FAIL: no clear message"; tail -5 "$out/link.log"; exit 1; }
# bend_hysteresis_ratio = 2HB/B: 0.981 1/m of B = 5e-3 N m is the same HB = 2.4525e-3 N m/m in both directions
sed 's/^    bend_hysteresis: .*/    bend_hysteresis_ratio: 0.981/' "$scene" > "$out/ratio.yaml"
mpiexec -n 1 "$CLOTHSIM" -scene "$out/ratio.yaml" -steps 1 -output_dir "$out/ratio" > "$out/ratio.log" 2>&1 || { tail -5 "$out/ratio.log"; exit 1; }
grep -q "bending friction HB 0.0024525/0.0024525 N m/m" "$out/ratio.log" || { echo "FAIL: bend_hysteresis_ratio 0.981 1/m did not give HB 0.0024525 N m/m"; grep fabric "$out/ratio.log"; exit 1; }
echo "bend hysteresis: loading branch and restart as expected; refused with link bending"

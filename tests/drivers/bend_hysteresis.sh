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
source tests/drivers/hysteresis_runs.sh
scene=tests/data/hysteresis_cantilever.yaml
hysteresis_runs "${CLOTHSIM_BUILD:-build}/test-output/bend_hysteresis" "$scene" bend_hysteresis 2 800
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
hysteresis_refused "$scene" 's/^    bend_model: angle/    bend_model: link/' "bending hysteresis needs bend_model: angle"
# bend_hysteresis_ratio = 2HB/B: 0.981 1/m of B = 5e-3 N m is the same HB = 2.4525e-3 N m/m in both directions
hysteresis_setup_says "$scene" 's/^    bend_hysteresis: .*/    bend_hysteresis_ratio: 0.981/' "bending friction HB 0.0024525/0.0024525 N m/m"
echo "bend hysteresis: loading branch and restart as expected; refused with link bending"

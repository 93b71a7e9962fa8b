#!/bin/bash
# The multilevel implicit solve (src/preconditioner.c), on the hanging sheet, 24 steps of 1/240 s, 1 rank:
# 1. GAMG's Krylov iterations per step stay bounded and flat in the sheet's size: at most 16 per step at 65 x 65 and
#    at 129 x 129 (measured 10.6 and 8.8), and the 129 count at most 1.5 times the 65 one (measured 0.83; point-block
#    Jacobi's grows 2x from 65 to 129: 147 and 293 per step over a second, docs/performance.md).
# 2. It solves the same system: GAMG and point-block Jacobi, both to rtol 1e-9, end within 1e-8 m (measured 1.4e-11 m).
# 3. The default preconditioner is point-block Jacobi below -implicit_pc_multilevel_min_particles and GAMG from it on.
# 4. A restart from a checkpoint continues bit for bit with GAMG (the hierarchy is rebuilt at every checkpoint, as a
#    restart rebuilds it), with the coarse levels lagged over steps (-implicit_pc_lag_ratio 1.2, the default): the
#    65 x 65 run must have lagged steps (measured: 3 rebuilt, 2 refreshed, 19 lagged; 11.2 and 8.9 its/step), so that the restart covers them.
# Usage: check_multilevel_solver.sh MPIEXEC WORKDIR      (CLOTHSIM: the binary)
set -euo pipefail
mpiexec=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
run() { # run NAME OPTIONS...: the log in $work/NAME.log, the results in $work/NAME
  local name=$1
  shift
  "$mpiexec" -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -steps 24 -output_every 0 -output_dir "$work/$name" "$@" > "$work/$name.log" 2>&1 ||
    { cat "$work/$name.log"; fail "run $name failed"; }
  grep -E "^Implicit system|^Done" "$work/$name.log"
}
its_per_step() { sed -n 's/^Done: 24 steps (24 sub-steps), \([0-9]*\) Krylov iterations.*/\1/p' "$work/$1.log" | awk '{ printf "%.2f", $1 / 24 }'; }

run gamg_65 -grid 65 -pc_type gamg -checkpoint_every 12 -checkpoint_keep 0 -integrator_view
lagged=$(sed -n 's/^Preconditioner kept between solves.* \([0-9]*\) lagged$/\1/p' "$work/gamg_65.log")
echo "GAMG at 65 x 65: $(grep -o '[0-9]* rebuilt.*lagged' "$work/gamg_65.log")"
[ -n "$lagged" ] && [ "$lagged" -gt 0 ] || fail "no lagged steps in the 65 x 65 GAMG run (-implicit_pc_lag_ratio default 1.2): '$lagged'"
run gamg_129 -grid 129 -implicit_pc_multilevel_min_particles 10000
its65=$(its_per_step gamg_65) its129=$(its_per_step gamg_129)
[ -n "$its65" ] && [ -n "$its129" ] || fail "a run took halved sub-steps (no 'Done: 24 steps (24 sub-steps)' line)"
echo "GAMG Krylov iterations per step: $its65 at 65 x 65, $its129 at 129 x 129"
awk -v a="$its65" -v b="$its129" 'BEGIN { exit !(a <= 16 && b <= 16 && b <= 1.5 * a) }' ||
  fail "iterations per step $its65 (65) and $its129 (129): expected at most 16 each and the 129 count at most 1.5 x the 65 one"
grep -q "preconditioner gamg" "$work/gamg_129.log" || fail "129 x 129 with -implicit_pc_multilevel_min_particles 10000 did not default to GAMG"

run default_65 -grid 65 -ksp_rtol 1e-9
grep -q "preconditioner pbjacobi" "$work/default_65.log" || fail "65 x 65 (4225 particles) did not default to point-block Jacobi"
run gamg_65_tight -grid 65 -pc_type gamg -ksp_rtol 1e-9
/usr/bin/python3 - "$work/gamg_65_tight/checkpoint_000024.h5" "$work/default_65/checkpoint_000024.h5" <<'PY'
import sys
import h5py
import numpy as np
a, b = (h5py.File(p, "r")["/state/position"][...] for p in sys.argv[1:3])
diff = float(np.abs(a - b).max())
print(f"largest position difference GAMG vs point-block Jacobi (rtol 1e-9), 24 steps: {diff:.3e} m")
sys.exit(0 if diff < 1e-8 else f"FAIL: {diff:.3e} m >= 1e-8 m")
PY

run gamg_65_restart -grid 65 -pc_type gamg -restart "$work/gamg_65/checkpoint_000012.h5"
/usr/bin/python3 tests/compare_checkpoints.py "$work/gamg_65/checkpoint_000024.h5" "$work/gamg_65_restart/checkpoint_000024.h5" --tolerance 0 ||
  fail "GAMG: 12 steps + restart + 12 steps differ from 24 steps"

#!/bin/bash
# A failed step is undone completely (src/integrator.c SaveInternalState / RestoreInternalState): a sheet with
# bending and shear hysteresis on a sphere (tests/data/rollback_drape.yaml), its Krylov solver capped at 38
# iterations, fails at step 20 (measured with friction inside the implicit step, which needs fewer iterations:
# 40 no longer fails; with the post-solve friction 40 failed at step 45; since 2026-11-27, with the friction's drag
# where a step could reverse a slip, the last good state is step 30) with 81 particles held on the sphere; a
# failing step is halved twice and its first halves may succeed before the last fails. The checkpoint written after
# the failure must be the state the run had after step 44: every dataset (position, velocity, contact normals, both
# slider families) bit-identical to the checkpoint of a run stopped at step 44.
# Usage: check_failed_step_rollback.sh MPIEXEC WORKDIR      (CLOTHSIM: the binary)
set -euo pipefail
mpiexec=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
common=(-scene tests/data/rollback_drape.yaml -ksp_max_it 38 -integrator_max_halvings 2 -progress_seconds 100)
"$mpiexec" -n 2 "$CLOTHSIM" "${common[@]}" -output_dir "$work/diverged" > "$work/diverged.log" 2>&1 && fail "the run did not diverge"
msg=$(grep -m1 'failed even with the step halved' "$work/diverged.log") || { tail -20 "$work/diverged.log"; fail "no divergence message"; }
good=$(echo "$msg" | sed -n 's/.*last good state (step \([0-9]*\)).*/\1/p')
ckpt=$(echo "$msg" | sed -n 's/.*is in \(.*checkpoint_[0-9]*\.h5\).*/\1/p')
[ -n "$good" ] && [ -f "$ckpt" ] || fail "no last good checkpoint named: $msg"
echo "diverged after step $good; the checkpoint written then: $ckpt"
"$mpiexec" -n 2 "$CLOTHSIM" "${common[@]}" -steps "$good" -output_dir "$work/stopped" > "$work/stopped.log" 2>&1 ||
  { tail -20 "$work/stopped.log"; fail "the run stopped at step $good failed"; }
/usr/bin/python3 - "$ckpt" "$(printf '%s/stopped/checkpoint_%06d.h5' "$work" "$good")" <<'PY'
import sys
import h5py
import numpy as np
a, b = (h5py.File(p, "r")["state"] for p in sys.argv[1:3])
names = sorted(a.keys())
wanted = {"position", "velocity", "contact_normal", "bend_slider", "shear_slider"}
if not wanted <= set(names) or set(names) != set(b.keys()):
    sys.exit(f"FAIL: datasets {names} and {sorted(b.keys())}, expected at least {sorted(wanted)} in both")
held = int(np.count_nonzero(np.linalg.norm(b["contact_normal"][...].reshape(-1, 3), axis=1)))
if held == 0:
    sys.exit("FAIL: no contact is held at the last good step: the test no longer exercises the contacts")
bad = [n for n in names if not np.array_equal(a[n][...], b[n][...])]
print(f"{len(names)} datasets compared ({', '.join(names)}); {held} particles in contact")
sys.exit(f"FAIL: not the state of step {a.attrs.get('step', '?')}: {bad} differ" if bad else 0)
PY

#!/usr/bin/env bash
# A diverging run must stop cleanly: explicit Euler at dt = 0.01 s on the 9 x 9 hanging sheet grows
# without bound and overflows to a non-finite state near step 126. With -integrator_max_halvings 2
# the run must (1) exit non-zero, (2) say which step failed, the smallest step tried (0.0025 s) and
# where the last good state is, and (3) leave that checkpoint, complete and readable, with the step
# it names. A recoverable failure must recover: the implicit solver limited to 25 Krylov iterations
# fails at dt = 1/60 s but succeeds on halved steps, so the run finishes with "(step reduced)".
set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

log="$out/diverge.log"
mpiexec -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -integrator explicit -dt 0.01 -t_final 5 \
  -integrator_max_halvings 2 -output_dir "$out/diverge" -progress_seconds 100 >"$log" 2>&1 && fail "diverging run exited 0"
msg=$(grep -m1 'failed even with the step halved down to' "$log") || { cat "$log"; fail "no divergence message"; }
echo "$msg" | grep -q '(the state became non-finite (NaN or Inf))' || fail "the message does not say why the step failed (explicit Euler: a non-finite state)"
echo "$msg"
echo "$msg" | grep -q 'halved down to 0.0025 s' || fail "smallest step not reported as 0.0025 s"
ckpt=$(echo "$msg" | sed -n 's/.*is in \(.*checkpoint_[0-9]*\.h5\).*/\1/p')
good=$(echo "$msg" | sed -n 's/.*last good state (step \([0-9]*\)).*/\1/p')
[ -f "$ckpt" ] || fail "checkpoint $ckpt named in the message does not exist"
/usr/bin/python3 - "$ckpt" "$good" <<'PY' || fail "checkpoint not valid"
import sys, h5py, numpy as np
f = h5py.File(sys.argv[1], "r")
s = f["/state"]
assert int(s.attrs["complete"]) == 1, "no end marker"
assert int(s.attrs["step"]) == int(sys.argv[2]), (int(s.attrs["step"]), sys.argv[2])
x = s["position"][:]
assert x.shape == (81, 3) and np.all(np.isfinite(x)), "bad positions"
print("checkpoint at step", int(s.attrs["step"]), "is complete and finite")
PY

log="$out/recover.log"
mpiexec -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 17 -dt 0.016666666666666666 -t_final 0.5 \
  -ksp_max_it 25 -output_dir "$out/recover" -progress_seconds 0 >"$log" 2>&1 || { tail -20 "$log"; fail "recoverable run failed"; }
grep -q '(step reduced)' "$log" || fail "no step was reduced: the test no longer exercises recovery"
grep -q '^Done: 30 steps' "$log" || fail "run did not finish its 30 steps"
echo "recovered: $(grep -c '(step reduced)' "$log") steps reduced, $(grep '^Done' "$log" | cut -c1-80)"
echo "robustness: 2 passed, 0 failed"

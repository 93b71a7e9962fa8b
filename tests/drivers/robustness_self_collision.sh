#!/usr/bin/env bash
# Self-collision must not turn a diverging run into a hang (issue 24, class 1): its cell grid grew its cells
# until their count was small enough, for ever when a coordinate was infinite. Each run is killed after 60 s,
# so a regression fails rather than hangs.
# (1) Symplectic Euler at dt = 0.01 s on the 9 x 9 hanging sheet with self-collision on diverges (near step 77);
#     the run must stop as it does without self-collision: non-zero exit, the divergence message naming the
#     last good checkpoint, which exists.
# (2) A finite but absurd thickness (1e308 m) makes the searched region overflow: a clear error at the first
#     step, naming the particle, not a hang.
# (3) A non-finite thickness is refused at set-up.
set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
run() { # run LOG ARGS...: clothsim on 1 rank, killed after 60 s; returns clothsim's status
  local log=$1
  shift
  timeout -s KILL 60 mpiexec -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -progress_seconds 100 \
    -self_collision 1 -self_collision_stiffness 20 "$@" >"$log" 2>&1
}

run "$out/diverge.log" -integrator symplectic -dt 0.01 -t_final 5 -integrator_max_halvings 2 -self_collision_thickness 0.01 \
  -output_dir "$out/diverge"
status=$?
[ $status -ne 137 ] || fail "diverging run with self-collision hung (killed after 60 s)"
[ $status -ne 0 ] || fail "diverging run with self-collision exited 0"
msg=$(grep -m1 'failed even with the step halved down to' "$out/diverge.log") || { tail -20 "$out/diverge.log"; fail "no divergence message"; }
ckpt=$(echo "$msg" | sed -n 's/.*is in \(.*checkpoint_[0-9]*\.h5\).*/\1/p')
[ -f "$ckpt" ] || fail "checkpoint '$ckpt' named in the message does not exist"
echo "diverged with self-collision: ${msg#*ERROR: }"

run "$out/huge.log" -steps 3 -self_collision_thickness 1e308 -output_dir "$out/huge"
status=$?
[ $status -ne 137 ] || fail "thickness 1e308 hung (killed after 60 s)"
[ $status -ne 0 ] || fail "thickness 1e308 exited 0"
# refused at set-up (at most 50 particle spacings); the cell grid's own guard for regions too large to grid is
# checked by geometry_kernels
grep -q 'Self-collision thickness (scene self_collision: thickness, or -self_collision_thickness) 1e+308 m: expected a positive number of at most 50 particle spacings' "$out/huge.log" || { tail -20 "$out/huge.log"; fail "thickness 1e308: not refused"; }

run "$out/inf.log" -steps 3 -self_collision_thickness inf -output_dir "$out/inf"
status=$?
[ $status -ne 137 ] || fail "thickness inf hung (killed after 60 s)"
[ $status -ne 0 ] || fail "thickness inf exited 0"
grep -q 'Self-collision thickness (scene self_collision: thickness, or -self_collision_thickness) inf.* m: expected a positive number' "$out/inf.log" || { tail -20 "$out/inf.log"; fail "thickness inf: not refused"; }
echo "robustness_self_collision: 3 passed, 0 failed"

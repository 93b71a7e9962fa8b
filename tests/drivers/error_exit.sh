#!/usr/bin/env bash
# User errors end the run with one message and exit status 2, never a hang (src/errors.c, tests/programs/test_error_exit.c):
# - raised on every rank (a collective error): the message once, from rank 0, without PETSc's traceback;
# - raised on one rank while the others wait in a barrier: that rank's message and the run aborted within about
#   10 s (the handler's wait for the others), not hanging until a batch job's time limit.
set -u
fail() { echo "FAIL: $*"; echo "$log"; exit 1; }
program=$CLOTHSIM_BUILD/tests/test_error_exit
for ranks in 1 2; do
  log=$(timeout 60 mpiexec -n "$ranks" "$program" -fail all 2>&1)
  status=$?
  [ "$status" -eq 2 ] || fail "-fail all on $ranks rank(s): exit status $status, expected 2"
  [ "$(grep -c '^ERROR: test user error raised by every rank$' <<<"$log")" -eq 1 ] || fail "-fail all on $ranks rank(s): the message is not there exactly once"
  grep -q "PETSC ERROR" <<<"$log" && fail "PETSc's traceback printed for a user error"
  echo "every rank failed on $ranks rank(s): exit 2, one message"
done
start=$(date +%s)
log=$(timeout 60 mpiexec -n 2 "$program" -fail one 2>&1)
status=$?
elapsed=$(( $(date +%s) - start ))
[ "$status" -ne 124 ] || fail "an error on one rank hung the run"
[ "$status" -eq 2 ] || fail "-fail one: exit status $status, expected 2"
grep -q '^ERROR: test user error raised by the last rank alone$' <<<"$log" || fail "-fail one: no message"
echo "one rank failed: exit 2 after ${elapsed} s, with its message"

#!/usr/bin/env bash
# A disk that fills inside a checkpoint's HDF5 writes (issue 24, item 5), after the free-space check passed (as when
# another job writes at the same time): tests/fault/fault_full_disk.c (LD_PRELOAD, path in $1) gives the temporary
# checkpoint files of each process a budget of 200,000 bytes over the ranks (each writes its share), so that with the 33 x 33 sheet the checkpoint of step
# 30 fails part-way with ENOSPC (measured; those of steps 0, 10 and 20 fit, the file of one is 86,304 bytes). On 1
# and 2 ranks clothsim must stop with exit status 3 and one ERROR line naming the temporary file and "No space left
# on device", delete that file (no .tmp left), and keep the two checkpoints before it (steps 10 and 20,
# -checkpoint_keep 2) complete; a restart from the newest must run on.
set -u
fail() { echo "FAIL: $*"; exit 1; }
fault=${1:?usage: checkpoint_write_failure.sh LIBFAULT_FULL_DISK.so}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
unset PETSC_OPTIONS
for np in 1 2; do
  dir=$out/np$np
  log=$(CLOTH_FAULT_DISK_BYTES=$((200000 / np)) mpiexec -n $np -x LD_PRELOAD="$fault" -x CLOTH_FAULT_DISK_BYTES "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 33 -steps 100 \
    -checkpoint_every 10 -checkpoint_keep 2 -output_every 1000 -progress_seconds 100 -output_dir "$dir" 2>&1)
  status=$?
  [ "$status" -eq 3 ] || { echo "$log" | tail -20; fail "$np rank(s): exit status $status, expected 3"; }
  [ "$(grep -c "^ERROR: " <<<"$log")" -eq 1 ] || { echo "$log" | tail -20; fail "$np rank(s): not exactly one ERROR line"; }
  grep -q "PETSC ERROR" <<<"$log" && fail "$np rank(s): PETSc's traceback printed for a full disk"
  msg=$(grep "^ERROR: " <<<"$log")
  echo "$np rank(s): $msg"
  grep -q "^ERROR: Cannot write checkpoint $dir/.checkpoint_000030.h5.tmp: .*(No space left on device); it was deleted" <<<"$msg" || fail "$np rank(s): the message names no file, another checkpoint, or lacks the OS reason"
  leftovers=$(ls -A "$dir" | grep '\.tmp$')
  [ -z "$leftovers" ] || fail "$np rank(s): temporary files left: $leftovers"
  /usr/bin/python3 - "$dir" <<'PY' || fail "$np rank(s): the checkpoints before the failure are not complete"
import glob, sys, h5py
names = sorted(glob.glob(sys.argv[1] + "/checkpoint_*.h5"))
steps = [int(h5py.File(n, "r")["/state"].attrs["step"]) for n in names]
assert steps == [10, 20], steps
for n in names:
    assert int(h5py.File(n, "r")["/state"].attrs["complete"]) == 1, n
print("  checkpoints of steps", steps, "complete")
PY
  log=$(mpiexec -n $np "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 33 -steps 30 -output_dir "$dir" -checkpoint_every 10 -output_every 1000 -progress_seconds 100 \
    -restart "$dir/checkpoint_000020.h5" 2>&1) || { echo "$log" | tail -5; fail "$np rank(s): the restart from the newest checkpoint failed"; }
  grep -q "^Done: 10 steps" <<<"$log" || { echo "$log" | tail; fail "$np rank(s): the restart did not run its 10 steps"; }
done
echo "checkpoint write failure: refused cleanly on 1 and 2 ranks"

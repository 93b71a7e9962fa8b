#!/usr/bin/env bash
# A full disk (issue 24, item 5): on a 3 MB tmpfs the 17 x 17 sheet, writing a frame and a checkpoint every step,
# fills the file system. clothsim must stop with exit status 3 and one message naming the file it could not write
# and "No space left on device", before writing anything half: the series' .xdmf stays valid XML, the newest
# checkpoint stays complete, and no temporary file is left behind.
# Needs root (mount -t tmpfs); exit status 77 (ctest: skipped) otherwise.
set -u
unset PETSC_OPTIONS
fail() { echo "FAIL: $*"; exit 1; }
disk=$(mktemp -d)
mount -t tmpfs -o size=3m tmpfs "$disk" 2>/dev/null || { rmdir "$disk"; echo "cannot mount a tmpfs here (not root?): skipped"; exit 77; }
trap 'umount "$disk"; rmdir "$disk"' EXIT

mpiexec -n 2 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 17 -steps 100000 -output_every 1 -checkpoint_every 1 -progress_seconds 100 \
  -output_dir "$disk/run" > "$disk/../full_disk.$$.log" 2>&1
status=$?
log=$(cat "$disk/../full_disk.$$.log"); rm -f "$disk/../full_disk.$$.log"
[ "$status" -eq 3 ] || { echo "$log" | tail -20; fail "exit status $status, expected 3"; }
msg=$(grep "^ERROR: " <<<"$log") || { echo "$log" | tail -20; fail "no ERROR line"; }
[ "$(grep -c "^ERROR: " <<<"$log")" -eq 1 ] || fail "more than one ERROR line"
grep -q "PETSC ERROR" <<<"$log" && fail "PETSc's traceback printed for a full disk"
echo "$msg"
grep -q "Cannot write .*$disk/run.*No space left on device" <<<"$msg" || fail "the message names no file or lacks 'No space left on device'"
/usr/bin/python3 - "$disk/run" <<'PY' || fail "the files left are not valid"
import glob, sys, xml.etree.ElementTree as ET, h5py
d = sys.argv[1]
frames = len(ET.parse(d + "/hanging_sheet.xdmf").getroot().findall(".//Time"))
ckpts = sorted(glob.glob(d + "/checkpoint_*.h5"))
assert ckpts, "no checkpoint"
s = h5py.File(ckpts[-1], "r")["/state"]
assert int(s.attrs["complete"]) == 1
leftovers = glob.glob(d + "/*.tmp") + glob.glob(d + "/.*.tmp")
assert not leftovers, leftovers
print(f"the .xdmf parses ({frames} frames), {ckpts[-1].split('/')[-1]} is complete, no temporary file left")
PY
echo "full disk: refused cleanly"

#!/usr/bin/env bash
# Long output paths (issue 24, item 2): Open MPI 4's default MPI-IO component, ompio, aborts the whole run ("buffer
# overflow detected") on a file name of more than 244 characters, which used to happen at the final checkpoint,
# after all the computing. clothsim now chooses Open MPI's ROMIO component (romio321) before its first file
# (src/h5util.h). On 1 and 2 ranks, a run into a 256-character file name must finish, write a series
# and checkpoints whose positions are bit for bit those of the same run into a short directory, and continue from
# its checkpoint with -restart (a long path read too). A user who forces ompio (OMPI_MCA_io=ompio) gets a
# refusal before the first step, exit status 3, naming the path and the way out.
set -u
fail() { echo "FAIL: $*"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
unset PETSC_OPTIONS
if [ -n "${OMPI_MCA_io:-}" ] || ! mpiexec --version 2>/dev/null | grep -qE "Open MPI|OpenRTE"; then echo "not Open MPI with its default MPI-IO: skipped"; exit 77; fi
long=$out/$(printf 'long_directory_name_%.0s' $(seq 1 11))
run() { mpiexec -n "$1" "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 4 -checkpoint_every 2 -progress_seconds 100 "${@:2}" 2>&1; }

for np in 1 2; do
  log=$(run $np -output_dir "$long/np$np") || { echo "$log" | tail; fail "$np rank(s): the run into a long path failed"; }
  grep -q "^Done: 4 steps" <<<"$log" || { echo "$log" | tail; fail "$np rank(s): the run into a long path did not finish"; }
  log=$(run $np -output_dir "$out/short$np") || { echo "$log" | tail; fail "$np rank(s): the run into a short path failed"; }
  /usr/bin/python3 - "$long/np$np" "$out/short$np" <<'PY' || fail "$np rank(s): the long-path files differ from the short-path ones"
import sys, h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
for name in ["checkpoint_000004.h5"]:
    x, y = h5py.File(f"{a}/{name}", "r")["/state/position"][:], h5py.File(f"{b}/{name}", "r")["/state/position"][:]
    assert np.array_equal(x, y), name
x, y = h5py.File(f"{a}/hanging_sheet.h5", "r"), h5py.File(f"{b}/hanging_sheet.h5", "r")
assert sorted(x["frames"]) == sorted(y["frames"]), (list(x["frames"]), list(y["frames"]))
print(f"  {len(a) + len('/.checkpoint_000000.h5.tmp')}-character names: checkpoint positions and frames {sorted(x['frames'])} as with a short path")
PY
  log=$(mpiexec -n $np "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 6 -progress_seconds 100 -output_dir "$long/np$np" -restart "$long/np$np/checkpoint_000004.h5" 2>&1)
  grep -q "^Done: 2 steps" <<<"$log" || { echo "$log" | tail; fail "$np rank(s): the restart from a long path failed"; }
  echo "$np rank(s): long path run, compared and restarted"
done

log=$(OMPI_MCA_io=ompio run 1 -output_dir "$long/ompio")
status=$?
[ "$status" -eq 3 ] || { echo "$log" | tail; fail "with OMPI_MCA_io=ompio: exit status $status, expected 3"; }
grep -q "^ERROR: HDF5 file $long/ompio/.checkpoint_000000.h5.tmp: the path has [0-9]* characters; Open MPI's MPI-IO component ompio aborts on more than 244, and OMPI_MCA_io chooses it" <<<"$log" || { echo "$log" | tail; fail "no clear message"; }
grep -q "^step" <<<"$log" && fail "the run computed steps before refusing the path"
echo "with OMPI_MCA_io=ompio: refused before the first step"

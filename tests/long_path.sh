#!/usr/bin/env bash
# Long output paths (issue 24, item 2): Open MPI 4's ompio aborts the whole run ("buffer overflow detected") on a
# file name of more than 244 characters, which used to happen at the final checkpoint, after all the computing.
# clothsim must refuse such an -output_dir before its first step, with exit status 3 and the way out; with
# OMPI_MCA_io=romio321 (no limit) the same run must work.
set -u
fail() { echo "FAIL: $*"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
dir=$out/$(printf 'long_directory_name_%.0s' $(seq 1 11))
run() { mpiexec -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 2 -progress_seconds 100 -output_dir "$dir" "$@" 2>&1; }
if [ -n "${OMPI_MCA_io:-}" ] || ! mpiexec --version 2>/dev/null | grep -qE "Open MPI|OpenRTE"; then echo "not Open MPI with its default MPI-IO: skipped"; exit 77; fi

log=$(run)
status=$?
[ "$status" -eq 3 ] || { echo "$log" | tail; fail "exit status $status, expected 3"; }
grep -q "^ERROR: HDF5 file $dir/.checkpoint_000000.h5.tmp: the path has [0-9]* characters; Open MPI's MPI-IO (ompio) aborts on more than 244" <<<"$log" || { echo "$log" | tail; fail "no clear message"; }
grep -q "^step" <<<"$log" && fail "the run computed steps before refusing the path"
echo "refused before the first step: $(grep ^ERROR <<<"$log" | cut -c1-60)..."
log=$(OMPI_MCA_io=romio321 run)
grep -q "^Done: 2 steps" <<<"$log" || { echo "$log" | tail; fail "the run with OMPI_MCA_io=romio321 failed"; }
echo "with OMPI_MCA_io=romio321 the run works"

#!/bin/bash
# -help lists the options of the run after its set-up and stops without running or writing (src/run.c): in an output
# directory that holds an earlier run's results (which a run would refuse), on 2 ranks, for a sheet large enough for
# the multigrid, the listing must name the run's, the preconditioner's and PETSc's options, the status be 0 and
# the directory be left exactly as it was.
#
#   check_help.sh MPIEXEC DIR
set -euo pipefail
mpiexec=$1 dir=$2
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
fail() { echo "FAIL: $*"; exit 1; }
unset PETSC_OPTIONS # the test environment's -output_overwrite
rm -rf "$dir"
"$mpiexec" -n 1 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 2 -output_dir "$dir" > /dev/null 2>&1 || fail "the first run failed"
before=$(ls -l --time-style=+%s.%N "$dir")
output=$("$mpiexec" -n 2 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 129 -help -output_dir "$dir" 2>&1) || { echo "$output" | tail; fail "-help exited with an error"; }
for option in -io_timeout -checkpoint_every -implicit_pc_lag_backoff -implicit_pc_grid_ratio -ksp_rtol -cloth_stiffness; do
  grep -q -- "^ *$option " <<<"$output" || fail "-help does not list $option"
done
grep -q "^-help: the options of this run are listed above .*; nothing was run or written$" <<<"$output" || { echo "$output" | tail -3; fail "no closing line"; }
grep -q "^Running\|^step\|^ERROR" <<<"$output" && fail "-help ran steps or refused the directory"
[ "$(ls -l --time-style=+%s.%N "$dir")" == "$before" ] || fail "-help changed the output directory"
echo "-help: $(grep -c '^ *-' <<<"$output") option lines, nothing run, the directory untouched"

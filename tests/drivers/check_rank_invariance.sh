#!/bin/bash
# Same physics on every rank count: runs the hanging sheet (-grid GRID) with INTEGRATOR on 1, 2, 3
# and 4 ranks (oversubscribed) and compares each final checkpoint (natural order) with the 1-rank one
# through check_final_checkpoint.py (h5py; Debian's /usr/bin/python3 or $PYTHON).
#
#   check_rank_invariance.sh MPIEXEC DIR INTEGRATOR GRID STEPS DT ATOL [clothsim options...]
#
# The ranks differ only in floating-point summation order (ghost sums, dot products) and, for the
# implicit integrator, in where the Krylov solver stops; ATOL (metres) bounds both.
set -euo pipefail
mpiexec=$1 dir=$2 integrator=$3 grid=$4 steps=$5 dt=$6 atol=$7
shift 7
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
tests=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-/usr/bin/python3}
checkpoint=$(printf 'checkpoint_%06d.h5' "$steps")
time=$("$python" -c "print(repr($steps * $dt))")

rm -rf "$dir"
for ranks in 1 2 3 4; do
  out=$dir/np$ranks
  mkdir -p "$out"
  "$mpiexec" -n "$ranks" "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid "$grid" -integrator "$integrator" \
    -steps "$steps" -dt "$dt" -output_every 0 -progress_seconds 1000 -output_dir "$out" "$@" \
    >"$out/stdout.txt" 2>"$out/stderr.txt" || {
    echo "FAIL: clothsim on $ranks rank(s) exited with status $?"; cat "$out/stdout.txt" "$out/stderr.txt"; exit 1; }
  if grep -qE "never used|ERROR" "$out/stderr.txt"; then
    echo "FAIL: clothsim on $ranks rank(s) reported an error or unused options"; cat "$out/stderr.txt"; exit 1
  fi
  compare=()
  [[ $ranks == 1 ]] || compare=(--compare "$dir/np1/$checkpoint" --atol "$atol")
  echo "$ranks rank(s): $(grep -E '^Partition' "$out/stdout.txt" || echo 'no partition line (1 rank)')"
  "$python" "$tests/checkers/check_final_checkpoint.py" "$out/$checkpoint" --particles $((grid * grid)) --step "$steps" \
    --time "$time" "${compare[@]}"
done

#!/bin/bash
# Cloth-cloth collisions end to end: runs SCENE on 1 and 2 ranks, checks that at every output frame no
# fabric edge crosses a fabric triangle (check_self_intersection.py), and that the two runs end within
# ATOL metres of each other (compare_checkpoints.py; h5py from Debian's /usr/bin/python3 or $PYTHON).
#
#   check_self_collision.sh MPIEXEC DIR SCENE STEPS ATOL [clothsim options...]
set -euo pipefail
mpiexec=$1 dir=$2 scene=$3 steps=$4 atol=$5
shift 5
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
tests=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-/usr/bin/python3}
name=$(basename "$scene" .yaml)
checkpoint=$(printf 'checkpoint_%06d.h5' "$steps")

rm -rf "$dir"
for ranks in 1 2; do
  out=$dir/np$ranks
  mkdir -p "$out"
  "$mpiexec" -n "$ranks" "$CLOTHSIM" -scene "$scene" -steps "$steps" -output_dir "$out" -progress_seconds 1000 \
    -self_collision_view "$@" >"$out/stdout.txt" 2>"$out/stderr.txt" || {
    echo "FAIL: clothsim on $ranks rank(s) exited with status $?"; cat "$out/stdout.txt" "$out/stderr.txt"; exit 1; }
  if grep -qE "never used|ERROR" "$out/stderr.txt"; then
    echo "FAIL: clothsim on $ranks rank(s) reported an error or unused options"; cat "$out/stderr.txt"; exit 1
  fi
  grep -E "^Self-collision|searches" "$out/stdout.txt" | sed "s/^/np$ranks: /"
  "$python" "$tests/checkers/check_self_intersection.py" "$out/$name.h5" --min-frames 5 || {
    echo "FAIL: the fabric passes through itself on $ranks rank(s)"; exit 1; }
done
"$python" "$tests/checkers/compare_checkpoints.py" "$dir/np1/$checkpoint" "$dir/np2/$checkpoint" --tolerance "$atol" || {
  echo "FAIL: 1 and 2 ranks end differently"; exit 1; }

#!/bin/bash
# A real fabric draped over a ball on the floor, folding onto itself (input/sheet_drape.yaml at -grid GRID), on NP
# ranks: the run must end without a halved step and without a solve redone by the fallback solver, with at most
# MAX_ITS Krylov iterations a step and at most MAX_CANDIDATES self-contact candidates a particle per search (the
# broad phase follows the geometry, not the speed), at least MIN_CONTACTS cloth-cloth contacts a search (the check
# has something to test), no fabric edge through a fabric triangle at any frame (check_self_intersection.py) and no
# particle inside the ball or the ground (check_sphere_clearance.py).
#
#   check_drape.sh MPIEXEC NP GRID STEPS MAX_ITS MAX_CANDIDATES MIN_CONTACTS [clothsim options...]
set -euo pipefail
mpiexec=$1 np=$2 grid=$3 steps=$4 max_its=$5 max_candidates=$6 min_contacts=$7
shift 7
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
tests=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-/usr/bin/python3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

"$mpiexec" -n "$np" "$CLOTHSIM" -scene input/sheet_drape.yaml -grid "$grid" -steps "$steps" -output_every $((steps / 8)) \
  -output_dir "$out/run" -progress_seconds 1000 -self_collision_view "$@" >"$out/stdout.txt" 2>"$out/stderr.txt" || {
  echo "FAIL: clothsim exited with status $?"; cat "$out/stdout.txt" "$out/stderr.txt"; exit 1; }
if grep -qE "never used|ERROR" "$out/stderr.txt"; then
  echo "FAIL: clothsim reported an error or unused options"; cat "$out/stderr.txt"; exit 1
fi
grep -E "^Done|searches|candidates|broad phase|breakdowns" "$out/stdout.txt"
"$python" - "$out/stdout.txt" "$steps" "$max_its" "$max_candidates" "$min_contacts" "$grid" <<'PY'
import re
import sys

text = open(sys.argv[1]).read()
steps, max_its, max_candidates, min_contacts, grid = int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
done = re.search(r"^Done: (\d+) steps \((\d+) sub-steps\), (\d+) Krylov iterations", text, re.M)
contacts = re.search(r"searches, ([\d.]+) contacts per search", text)
candidates = re.search(r"candidates \(.*\): found \d+ times, ([\d.]+) per search \(([\d.]+) per particle\)", text)
fallbacks = re.search(r"Preconditioner breakdowns: (\d+) solves", text)
failures = []
if not (done and contacts and candidates):
    sys.exit("check_drape: FAILED: the run printed no Done line or no self-collision statistics")
taken, substeps, its = int(done.group(1)), int(done.group(2)), int(done.group(3))
per_step = its / max(taken, 1)
print(f"check_drape: {taken} steps, {substeps - taken} halved, {its / taken:.1f} Krylov iterations a step (at most {max_its}), "
      f"{float(candidates.group(2)):.4f} candidates a particle a search (at most {max_candidates}), {contacts.group(1)} contacts a search (at least {min_contacts}), "
      f"{int(fallbacks.group(1)) if fallbacks else 0} fallback solves")
if taken != steps:
    failures.append(f"{taken} steps taken, {steps} asked")
if substeps != taken:
    failures.append(f"{substeps - taken} steps halved")
if fallbacks and int(fallbacks.group(1)) > 0:
    failures.append(f"{fallbacks.group(1)} solves redone by the fallback solver")
if per_step > max_its:
    failures.append(f"{per_step:.1f} Krylov iterations a step")
if float(candidates.group(2)) > max_candidates:
    failures.append(f"{candidates.group(2)} candidates a particle")
if float(contacts.group(1)) < min_contacts:
    failures.append(f"only {contacts.group(1)} contacts a search: the drape has not folded onto itself")
if failures:
    sys.exit("check_drape: FAILED: " + "; ".join(failures))
PY
"$python" "$tests/checkers/check_self_intersection.py" "$out/run/sheet_drape.h5" --min-frames 5 || { echo "FAIL: the fabric passes through itself"; exit 1; }
"$python" "$tests/checkers/check_sphere_clearance.py" "$out/run/sheet_drape.h5" --center 0 0.3 0 --radius 0.3 --thickness 0.005 \
  --tolerance 0.001 --ground 0 --min-frames 5 || { echo "FAIL: particles inside the ball or the ground"; exit 1; }

#!/bin/bash
# Bad-input test: runs clothsim on a scene that must be refused and checks the refusal.
#
#   expect_error.sh RANKS SCENE [TEXT...]
#
# Runs "$CLOTHSIM -scene SCENE" on RANKS ranks (mpiexec, or $MPIEXEC) and passes when it exits with a
# non-zero code, without a crash, and its output (stdout + stderr) contains "scene SCENE" (every message names
# the file), each TEXT given, and each "# expect: TEXT" line of SCENE (one per line, taken literally).
# The error must be reported once, not once per rank.
set -u
if [[ $# -lt 2 ]]; then
  echo "usage: $0 RANKS SCENE [TEXT...]" >&2
  exit 2
fi
ranks=$1
scene=$2
shift 2
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
mpiexec=${MPIEXEC:-mpiexec}

expected=("scene $scene" "$@")
if [[ -f $scene ]]; then
  while IFS= read -r line; do expected+=("$line"); done < <(sed -n 's/^# expect: //p' "$scene")
fi

output=$(timeout 120 "$mpiexec" -n "$ranks" "$CLOTHSIM" -scene "$scene" 2>&1)
status=$?

fail() {
  echo "FAIL ($scene on $ranks rank(s), exit code $status): $1"
  echo "---- output ----"
  echo "$output"
  exit 1
}

[[ $status -ne 0 ]] || fail "clothsim accepted a bad scene"
[[ $status -ne 124 ]] || fail "clothsim hung (killed after 120 s)"
if grep -qE "Caught signal|Segmentation|core dumped" <<<"$output"; then fail "clothsim crashed instead of refusing the scene"; fi
for text in "${expected[@]}"; do
  grep -qF -- "$text" <<<"$output" || fail "the output lacks: $text"
done
count=$(grep -cF -- "ERROR: scene $scene" <<<"$output")
[[ $count -eq 1 ]] || fail "the message appears $count times, expected once"
echo "PASS: $scene refused on $ranks rank(s) with: $(grep -F -- "ERROR: scene $scene" <<<"$output")"

#!/bin/bash
# Bad-input test: runs clothsim on a scene (and options) that must be refused and checks the refusal.
#
#   expect_error.sh [--status N] RANKS SCENE [TEXT...] [-- OPTION...]
#
# Runs "$CLOTHSIM -scene SCENE OPTION..." on RANKS ranks (mpiexec, or $MPIEXEC) and passes when it exits with the
# status N (2 bad input, 3 file, 4 diverged; see src/errors.h), without a crash, and its output (stdout + stderr) contains each TEXT given and each
# "# expect: TEXT" line of SCENE (one per line, taken literally). An OPTION '' stands for the empty string. Without options the message must also name "scene SCENE" (every message about a scene
# names the file). The error must be reported once, not once per rank, as one "ERROR: " line without PETSc's
# traceback. Unless OPTION sets -output_dir, the run writes into a fresh temporary directory.
# The status is required: N is --status N or, without it, the line "# status: N" of SCENE (the files of tests/bad_input/
# have it, at their end where it moves no line number that a message names). Without either the test fails: a
# refusal with the wrong status (a crash's, an abort's, a file error's for a bad value) is not a pass.
set -u
status_expected=""
if [[ ${1:-} == --status ]]; then
  status_expected=$2
  shift 2
fi
if [[ $# -lt 2 ]]; then
  echo "usage: $0 [--status N] RANKS SCENE [TEXT...] [-- OPTION...]" >&2
  exit 2
fi
ranks=$1
scene=$2
shift 2
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
mpiexec=${MPIEXEC:-mpiexec}

expected=()
options=()
while [[ $# -gt 0 ]]; do
  if [[ $1 == -- ]]; then
    shift
    options=("$@")
    break
  fi
  expected+=("$1")
  shift
done
scene_only=1
[[ ${#options[@]} -eq 0 ]] || scene_only=0
[[ $scene_only -eq 0 ]] || expected+=("scene $scene")
for i in "${!options[@]}"; do [[ ${options[$i]} != "''" ]] || options[$i]=""; done
if [[ -f $scene ]]; then
  while IFS= read -r line; do expected+=("$line"); done < <(sed -n 's/^# expect: //p' "$scene")
  [[ -n $status_expected ]] || status_expected=$(sed -n 's/^# status: *\([0-9][0-9]*\) *$/\1/p' "$scene")
fi
if ! [[ $status_expected =~ ^[0-9]+$ ]]; then
  echo "FAIL ($scene on $ranks rank(s)): no expected exit status: give --status N or a line '# status: N' in the scene (got '$status_expected')"
  exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[[ " ${options[*]-} " == *" -output_dir "* ]] || options+=(-output_dir "$tmp/out")

# stdout and stderr captured apart: mpiexec forwards the two streams separately, and one merged stream can splice a
# line of one into a line of the other on a loaded machine (seen: "ERROR: " not at the start of its line)
timeout 120 "$mpiexec" -n "$ranks" "$CLOTHSIM" -scene "$scene" "${options[@]}" > "$tmp/stdout" 2> "$tmp/stderr"
status=$?
output=$(cat "$tmp/stdout" "$tmp/stderr")

fail() {
  echo "FAIL ($scene ${options[*]} on $ranks rank(s), exit code $status): $1"
  echo "---- output ----"
  echo "$output"
  exit 1
}

[[ $status -ne 0 ]] || fail "clothsim accepted a bad input"
[[ $status -ne 124 ]] || fail "clothsim hung (killed after 120 s)"
if grep -qE "Caught signal|Segmentation|core dumped" <<<"$output"; then fail "clothsim crashed instead of refusing the input"; fi
[[ $status -eq $status_expected ]] || fail "exit status $status, expected $status_expected"
for text in "${expected[@]}"; do
  grep -qF -- "$text" <<<"$output" || fail "the output lacks: $text"
done
if [[ $scene_only -eq 1 ]]; then
  count=$(grep -cF -- "ERROR: scene $scene" <<<"$output")
  [[ $count -eq 1 ]] || fail "the message appears $count times, expected once"
fi
count=$(grep -c "^ERROR: " "$tmp/stderr")
[[ $count -eq 1 ]] || fail "$count lines start with 'ERROR: ', expected one message"
if grep -q "PETSC ERROR" <<<"$output"; then fail "PETSc's traceback was printed for a user error"; fi
echo "PASS: $scene ${options[*]} refused on $ranks rank(s), exit $status, with: $(grep "^ERROR: " "$tmp/stderr")"

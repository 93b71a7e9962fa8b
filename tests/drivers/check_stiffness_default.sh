#!/usr/bin/env bash
# A real-fabric scene's implicit assembly by default uses the closed-form (Gauss-Newton) element stiffness: no element
# goes through the per-element LAPACK eigen-decomposition of -cloth_stiffness projected (issue 45). The calls are
# counted, not timed: every ClothProjectPSD call is one event of -log_view. The default run of input/sheet_drape.yaml
# (cotton/polyester, -grid 17, 3 steps) must have none; the same run with -cloth_stiffness projected must have at least
# one per angle and twist element and step (so the count is seen when it happens).
#
#   check_stiffness_default.sh MPIEXEC
set -euo pipefail
mpiexec=$1
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
count() { # the ClothProjectPSD count of a -log_view, 0 when the event never ran
  awk '$1 == "ClothProjectPSD" { n = $2 } END { print n + 0 }' "$1"
}
for form in default projected; do
  extra=()
  [ "$form" = projected ] && extra=(-cloth_stiffness projected)
  "$mpiexec" -n 1 "$CLOTHSIM" -scene input/sheet_drape.yaml -grid 17 -steps 3 -self_collision 0 -output_every 0 \
    -output_dir "$out/$form" -log_view "${extra[@]}" >"$out/$form.log" 2>&1 || { cat "$out/$form.log"; echo "FAIL: the $form run failed"; exit 1; }
  grep -q '^Done: 3 steps' "$out/$form.log" || { cat "$out/$form.log"; echo "FAIL: the $form run did not finish its 3 steps"; exit 1; }
done
default=$(count "$out/default.log") projected=$(count "$out/projected.log")
echo "ClothProjectPSD calls in 3 steps: $default by default, $projected with -cloth_stiffness projected"
[ "$projected" -ge 3 ] || { echo "FAIL: -cloth_stiffness projected made $projected LAPACK projections: the count does not see them"; exit 1; }
[ "$default" -eq 0 ] || { echo "FAIL: the default assembly made $default per-element LAPACK projections"; exit 1; }
echo "check_stiffness_default: passed"

#!/bin/bash
# Cusick drape at reduced resolutions: runs input/cusick_drape.yaml for each preset given, at two grid sizes,
# and checks with postprocess/cusick_drape.py that (1) the drape coefficient changes by less than DC_TOL
# between the two resolutions and (2) the presets' drape coefficients follow the order of their bending
# lengths (a stiffer fabric drapes less: larger DC).
#
#   validation_cusick.sh "N1 N2" DC_TOL PRESET...   (presets in increasing bending length)
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
grids=($1)
tol=$2
shift 2
out=${CLOTHSIM_BUILD:-build}/test-output/cusick_ci
mkdir -p "$out"
py=/usr/bin/python3
declare -A dc
for preset in "$@"; do
  sed "s/preset: cotton_polyester .*/preset: $preset/" input/cusick_drape.yaml > "$out/cusick_$preset.yaml"
  for n in "${grids[@]}"; do
    dir="$out/${preset}_$n"
    mpiexec -n 1 "$CLOTHSIM" -scene "$out/cusick_$preset.yaml" -grid "$n" -dt 0.02 -t_final 4 -output_every 0 -output_dir "$dir" -implicit_mat_type aij -pc_type cholesky -progress_seconds 100 > "$dir.log" 2>&1 || { tail -20 "$dir.log"; exit 1; }
    dc[$preset,$n]=$($py postprocess/cusick_drape.py "$(ls "$dir"/checkpoint_*.h5 | tail -1)" --scene "$out/cusick_$preset.yaml" --grid "$n" --json | $py -c 'import json,sys; print(json.load(sys.stdin)["drape_coefficient"])')
    echo "$preset grid $n: DC ${dc[$preset,$n]}"
  done
  $py - "${dc[$preset,${grids[0]}]}" "${dc[$preset,${grids[1]}]}" "$tol" "$preset" <<'PY'
import sys
a, b, tol = map(float, sys.argv[1:4])
if abs(a - b) > tol:
    sys.exit(f"FAIL: {sys.argv[4]}: DC {a:.3f} and {b:.3f} at the two resolutions differ by more than {tol}")
PY
done
previous=""
for preset in "$@"; do
  n=${grids[1]}
  if [[ -n $previous ]]; then
    $py -c "import sys; sys.exit(0 if ${dc[$preset,$n]} > ${dc[$previous,$n]} else 'FAIL: DC of $preset (${dc[$preset,$n]}) not above that of $previous (${dc[$previous,$n]}), though its bending length is larger')"
  fi
  previous=$preset
done
echo "cusick drape: resolution and ordering checks passed"

#!/usr/bin/env bash
# The main job's dress (input/dress.yaml) on a coarser grid, assembled on 2 ranks, checked against the
# targets of issue 8 by postprocess/garment_quality.py --check (seams closed below 2 mm, nothing inside
# the body, no fabric through fabric, link strain, at rest). The coarse scene is input/dress.yaml with
# only its pieces' grids changed (bodice 26 x 6, straps 4 x 16, skirt 17 x 13: 882 particles instead of
# 2,478), written here so that it cannot drift from the main job's. The bodice keeps its 25 cells across
# the top so that each strap end (4 nodes) still meets 4 bodice nodes (the shoulder seams' from/to).
#   bash tests/garment_coarse.sh [EXTRA garment_quality.py ARGS]        (CLOTHSIM: the binary)
set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
here=$(cd "$(dirname "$0")/.." && pwd)
sed -e 's/grid: \[26, 11\]/grid: [26, 6]/' -e 's/grid: \[4, 32\]/grid: [4, 16]/' -e 's/grid: \[33, 25\]/grid: [17, 13]/' \
    -e "s#file: mannequin/#file: $here/input/mannequin/#" "$here/input/dress.yaml" > "$out/dress.yaml"
[ "$(grep -c 'grid: \[\(26, 6\|4, 16\|17, 13\)\]' "$out/dress.yaml")" = 6 ] || { echo "FAIL: input/dress.yaml's grids changed: update $0"; exit 1; }
mpiexec -n 2 "$CLOTHSIM" -scene "$out/dress.yaml" -output_dir "$out/run" -output_every 0 -progress_seconds 30 > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; echo "FAIL: the run failed"; exit 1; }
grep -A12 "^Widest seam pairs" "$out/run.log"
/usr/bin/python3 "$here/postprocess/garment_quality.py" "$out/run" --name dress --check --worst 5 --scene "$out/dress.yaml" "$@"

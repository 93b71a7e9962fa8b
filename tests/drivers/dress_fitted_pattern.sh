#!/bin/bash
# The fitted dress's pattern and scenes are what jobs/dress_fitted_pattern.py makes from the mannequin: drafting
# again from the mesh's measurements gives the committed input/dress_fitted_pattern.dxf's outlines (within 1e-9 m,
# read back by postprocess/pattern_dxf.py import), and the scenes written again from the committed DXF are the
# committed input/dress_fitted.yaml (8 mm), input/dress_fitted_middle.yaml (12 mm) and
# input/dress_fitted_coarse.yaml (20 mm), byte for byte. About 15 s (the measurement cuts the mesh 120 times).
set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cd "$(dirname "$0")/../.." || exit 1
fail() { echo "FAIL: $*"; exit 1; }
py=/usr/bin/python3
$py jobs/dress_fitted_pattern.py draft -o "$out/pattern.dxf" || fail "drafting the pattern"
$py postprocess/pattern_dxf.py import "$out/pattern.dxf" -o "$out/drafted.yaml" 2> /dev/null || fail "importing the drafted pattern"
$py postprocess/pattern_dxf.py import input/dress_fitted_pattern.dxf -o "$out/committed.yaml" 2> /dev/null || fail "importing input/dress_fitted_pattern.dxf"
$py - "$out/drafted.yaml" "$out/committed.yaml" <<'PY' || fail "the drafted pattern differs from input/dress_fitted_pattern.dxf"
import sys, yaml, numpy as np
a, b = ({p["name"]: p["boundaries"] for p in yaml.safe_load(open(f))["pieces"]} for f in sys.argv[1:3])
assert a.keys() == b.keys(), (sorted(a), sorted(b))
worst = max(float(np.max(np.abs(np.array(a[n][s]) - np.array(b[n][s])))) for n in a for s in ("bottom", "right", "top", "left"))
print(f"dress_fitted_pattern: {len(a)} pieces drafted again, largest outline difference {worst:.1e} m")
assert worst <= 1e-9
PY
for scene in "0.008 dress_fitted.yaml dress_fitted" "0.012 dress_fitted_middle.yaml dress_fitted_middle" "0.02 dress_fitted_coarse.yaml dress_fitted_coarse"; do
  read -r h file name <<< "$scene"
  $py jobs/dress_fitted_pattern.py scene "$h" "$out/$file" --name "$name" || fail "writing $file"
  cmp "$out/$file" "input/$file" || { diff "$out/$file" "input/$file" | head; fail "input/$file is not what jobs/dress_fitted_pattern.py writes"; }
done
echo "PASS: the fitted dress's pattern and its three scenes are what jobs/dress_fitted_pattern.py makes"

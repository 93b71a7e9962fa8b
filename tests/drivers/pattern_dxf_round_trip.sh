#!/usr/bin/env bash
# The DXF pattern tool (postprocess/pattern_dxf.py) on the dress: the committed sample
# input/dress_pattern.dxf imports to exactly the outlines of input/dress.yaml (within 1e-9 m), and a
# fresh export in centimetres round-trips to the same outlines.
set -eu
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
/usr/bin/python3 postprocess/pattern_dxf.py import input/dress_pattern.dxf -o "$out/from_sample.yaml"
/usr/bin/python3 postprocess/pattern_dxf.py export input/dress.yaml -o "$out/dress_cm.dxf" --units cm
/usr/bin/python3 postprocess/pattern_dxf.py import "$out/dress_cm.dxf" -o "$out/from_cm.yaml"
/usr/bin/python3 - "$out/from_sample.yaml" "$out/from_cm.yaml" <<'PY'
import sys, yaml, numpy as np
scene = {p["name"]: p for p in yaml.safe_load(open("input/dress.yaml"))["pieces"]}
for path in sys.argv[1:]:
    pieces = yaml.safe_load(open(path))["pieces"]
    assert sorted(p["name"] for p in pieces) == sorted(scene), (path, [p["name"] for p in pieces])
    worst = 0.0
    for p in pieces:
        s = scene[p["name"]]
        want = s["boundaries"] if "boundaries" in s else None
        if want is None:
            su, sv = s["size"]
            want = {"bottom": [[0, 0], [su, 0]], "right": [[su, 0], [su, sv]], "top": [[0, sv], [su, sv]], "left": [[0, 0], [0, sv]]}
        for side in ("bottom", "right", "top", "left"):
            a, b = np.array(p["boundaries"][side], float), np.array(want[side], float)
            assert a.shape == b.shape, (path, p["name"], side, a.shape, b.shape)
            worst = max(worst, float(np.abs(a - b).max()))
    assert worst < 1e-9, (path, worst)
    print(f"{path}: {len(pieces)} pieces, outlines equal to the scene's within {worst:.1e} m")
PY
echo "pattern_dxf: 2 passed, 0 failed"

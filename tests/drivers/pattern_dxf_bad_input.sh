#!/bin/bash
# The DXF pattern importer (postprocess/pattern_dxf.py import) refuses what it cannot use with one line,
# "ERROR: pattern_dxf: ...", and clothsim's exit statuses (3: the file cannot be read, 2: the pattern cannot be used),
# never a Python traceback, and never reports success for an outline clothsim would refuse: random bytes, an empty
# file, a directory and a missing file (3); a NaN vertex, a self-crossing outline, a pattern in mm declared as metres
# ($INSUNITS 6: 1500 m), two pieces of one name (2). Before (issue 48) the first three ended in a traceback, the NaN
# became an all-NaN outline reported as success and the crossing outline passed through. A 100,000-vertex outline
# imports, and clothsim reads the piece (its arc-length boundaries) without complaint.
set -u
py=/usr/bin/python3
tool=postprocess/pattern_dxf.py
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
"$py" - "$out" <<'PY' || fail "writing the test patterns"
import math, sys
import ezdxf
out = sys.argv[1]
def pattern(path, pieces, units=4):
    """pieces: (name, closed outline, four turn points); a grain line along x."""
    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = units
    for name, ring, corners in pieces:
        block = doc.blocks.new(name=name.replace(" ", "_") + str(len(doc.blocks)))
        block.add_lwpolyline(ring, close=True, dxfattribs={"layer": "1"})
        for c in corners:
            block.add_point(c, dxfattribs={"layer": "2"})
        block.add_line((0, 0), (1, 0), dxfattribs={"layer": "7"})
        block.add_text("Piece Name: " + name, dxfattribs={"layer": "1"})
        doc.modelspace().add_blockref(block.name, (0, 0))
    doc.saveas(f"{out}/{path}")
square = [(0, 0), (300, 0), (300, 200), (0, 200)]
pattern("nan.dxf", [("panel", [(0, 0), (300, 0), (300, float("nan")), (0, 200)], square)])
pattern("crossing.dxf", [("bow", [(0, 0), (300, 0), (0, 200), (300, 200)], square)])
pattern("metres.dxf", [("panel", [(0, 0), (1500, 0), (1500, 200), (0, 200)], [(0, 0), (1500, 0), (1500, 200), (0, 200)])], units=6)
pattern("twice.dxf", [("panel", square, square), ("panel", square, square)])
n = 100000
ring = [(100 + 100 * math.cos(2 * math.pi * k / n), 100 + 100 * math.sin(2 * math.pi * k / n)) for k in range(n)]
pattern("disc.dxf", [("disc", ring, [ring[0], ring[n // 4], ring[n // 2], ring[3 * n // 4]])])
PY
head -c 4096 /dev/urandom > "$out/random.dxf"
: > "$out/empty.dxf"
mkdir "$out/folder.dxf"
passed=0
# refused STATUS FILE TEXT: the import of FILE exits STATUS with one ERROR line containing TEXT and no traceback
refused() {
  local status=$1 file=$2 text=$3 got
  "$py" "$tool" import "$file" -o "$out/pieces.yaml" > "$out/stdout" 2> "$out/stderr"
  got=$?
  [ "$got" -eq "$status" ] || { cat "$out/stderr"; fail "$file: exit status $got, expected $status"; }
  grep -q Traceback "$out/stderr" && { cat "$out/stderr"; fail "$file: a traceback"; }
  [ "$(grep -c '^ERROR: pattern_dxf: ' "$out/stderr")" -eq 1 ] || { cat "$out/stderr"; fail "$file: not one ERROR line"; }
  grep -qF -- "$text" "$out/stderr" || { cat "$out/stderr"; fail "$file: the message lacks: $text"; }
  [ ! -e "$out/pieces.yaml" ] || fail "$file: an output was written"
  echo "refused (exit $got): $(cat "$out/stderr")"
  passed=$((passed + 1))
}
refused 3 "$out/random.dxf" "$out/random.dxf: not a DXF file: expected a DXF pattern file"
refused 3 "$out/empty.dxf" "$out/empty.dxf: not a DXF file"
refused 3 "$out/folder.dxf" "$out/folder.dxf: cannot read the file (Is a directory)"
refused 3 "$out/missing.dxf" "$out/missing.dxf: cannot read the file (No such file or directory)"
refused 2 "$out/nan.dxf" "piece panel: vertex 2 is (300.0, nan): expected finite coordinates"
refused 2 "$out/crossing.dxf" "piece bow: its outline (layer 1) crosses itself: edge 1 (300, 0)-(0, 200) meets edge 3 (300, 200)-(0, 0)"
refused 2 "$out/metres.dxf" "piece panel: its bottom boundary reaches 1500 m: expected at most 1000 m, clothsim's bound"
refused 2 "$out/twice.dxf" "two pieces are called panel"
"$py" "$tool" import "$out/disc.dxf" -o "$out/disc.yaml" 2> "$out/stderr" || { cat "$out/stderr"; fail "the 100,000-vertex outline was refused"; }
{ printf 'fabrics: {net: {density: 0.2, stretch: 1000}}\n'; sed 's/^- name: disc$/- name: disc\n  fabric: net\n  grid: [9, 9]/' "$out/disc.yaml"; } > "$out/disc_scene.yaml"
grep -q "grid: \[9, 9\]" "$out/disc_scene.yaml" || fail "the scene of the disc was not written"
if [ -n "${CLOTHSIM:-}" ]; then
  "$CLOTHSIM" -scene "$out/disc_scene.yaml" -help -output_dir "$out/run" > "$out/run.log" 2>&1 || { tail -3 "$out/run.log"; fail "clothsim refused the imported 100,000-vertex outline"; }
  grep -q "outline from 4 boundaries (25001/25001/25001/25001 vertices)" "$out/run.log" || { grep piece "$out/run.log"; fail "clothsim did not read the four boundaries"; }
fi
echo "pattern_dxf bad input: $passed refused as expected; a 100,000-vertex outline imported and read by clothsim"

#!/bin/bash
# Contact records of the output frames and postprocess/contacts.py, on two sheets dropped onto a sphere
# (input/two_sheets_sphere.yaml, 2 x 17 x 17 particles, 0.4 s, a frame every 6 steps: 17 frames) on
# 2 ranks: tests/checkers/check_contacts.py checks every frame's body contacts against the positions (particles
# within the contact distance of the sphere or the ground), the cloth-cloth counts against their field,
# when contacts begin, and the tool's table; then the tool's PNG.
# Usage: check_contacts.sh MPIEXEC WORKDIR      (CLOTHSIM: the binary)
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
root=$(cd "$tests/.." && pwd)
mpiexec=$1 work=$2
py=/usr/bin/python3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"

scene=$root/input/two_sheets_sphere.yaml
"$mpiexec" -n 2 "$CLOTHSIM" -scene "$scene" -t_final 0.4 -output_every 6 -output_dir "$work/run" > "$work/run.log" 2>&1 ||
  { cat "$work/run.log"; fail "clothsim run failed"; }

$py "$root/postprocess/contacts.py" --help | grep -q "body_contacts" || fail "contacts.py --help"
$py "$root/postprocess/contacts.py" "$work/run/two_sheets_sphere.xdmf" --out "$work/contacts.png" --csv "$work/contacts.csv" \
  > "$work/contacts.log" || { cat "$work/contacts.log"; fail "contacts.py"; }
cat "$work/contacts.log"
rows=$(($(wc -l < "$work/contacts.csv") - 1))
[ "$rows" = 17 ] || fail "contacts.csv has $rows rows, expected 17 (frames at steps 0, 6, ..., 96)"
# The lower sheet starts 0.1 m above the sphere's top: it falls the 0.0925 m to the contact distance
# (1.5 x the 5 mm thickness) in sqrt(2 x 0.0925 / 9.81) = 0.137 s, so the frames at 0 ... 0.125 s have no
# contact and those from 0.15 s on have some; the sheets start 5 cm apart and fall together, so they
# cannot touch before the lower one has landed.
$py "$tests/checkers/check_contacts.py" "$work/run/two_sheets_sphere.h5" "$scene" "$work/contacts.csv" \
  --body-free-until 0.125 --body-contact-from 0.15 --self-free-until 0.15 || fail "contact records"
$py -c 'import struct, sys; d = open(sys.argv[1], "rb").read(24); assert d[:8] == b"\x89PNG\r\n\x1a\n"; assert struct.unpack(">II", d[16:24]) == (700, 600), struct.unpack(">II", d[16:24])' \
  "$work/contacts.png" || fail "contacts.png is not a 700 x 600 PNG"
echo PASS

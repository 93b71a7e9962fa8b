#!/bin/bash
# Writes the output series of test_output on RANKS ranks, then opens each with ParaView (pvpython,
# through check_xdmf.py), also after moving the folder (the .xdmf must use relative paths).
# Usage: check_xdmf.sh MPIEXEC RANKS TEST_OUTPUT DIR     (PVPYTHON overrides /usr/bin/pvpython)
set -euo pipefail
mpiexec=$1 ranks=$2 program=$3 dir=$4
tests=$(cd "$(dirname "$0")/.." && pwd)
pvpython=${PVPYTHON:-/usr/bin/pvpython}
if [ ! -x "$pvpython" ]; then
  echo "check_xdmf.sh: $pvpython not found: install paraview and python3-paraview (scripts/install_deps.sh)" >&2
  exit 1
fi

rm -rf "$dir" "$dir.moved"
"$mpiexec" -n "$ranks" "$program" -dir "$dir"

check() { "$pvpython" "$tests/checkers/check_xdmf.py" --counts-are-step "$@"; }
# 17 particles and 7 quads in two pieces; x of particle 0 is shift + 1/8 (see test_output.c).
check "$dir/sheet.xdmf" --points 17 --cells 7 --times 0,0.05,0.1 --fabric-x0 0.125
# Restarted at t = 0.2: frames 0.1 and 0.2 kept, the old 0.3 replaced by the new one (shift 1000).
check "$dir/restart.xdmf" --points 17 --cells 7 --times 0.1,0.2,0.3 --fabric-x0 1000.125
# The fabric plus a static mesh of 4 points and 2 triangles in every frame.
check "$dir/scene.xdmf" --points 21 --cells 9 --times 0,0.5 --fabric-x0 0.125
check "$dir/fresh.xdmf" --points 17 --cells 7 --times 0.7 --fabric-x0 0.125
mv "$dir" "$dir.moved"
check "$dir.moved/scene.xdmf" --points 21 --cells 9 --times 0,0.5 --readers Xdmf3ReaderS

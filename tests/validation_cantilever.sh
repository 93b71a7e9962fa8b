#!/bin/bash
# Peirce cantilever (ASTM D1388) at a reduced resolution: writes the strip scene for the given presets,
# runs it, and checks every bending length 0.5093 l* against (B/W)^(1/3) within 10%.
#
#   validation_cantilever.sh PRESET...      (CLOTHSIM and CLOTHSIM_BUILD set by ctest)
set -eu
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
out=${CLOTHSIM_BUILD:-build}/test-output/cantilever_ci
mkdir -p "$out"
py=/usr/bin/python3
$py postprocess/cantilever.py scene --presets "$@" --count 6 --lmin 0.012 --lmax 0.05 --segments 16 -o "$out/cantilever.yaml"
# one rank with a direct (Cholesky) factorisation: the strips are small, and the stiff tensile links
# against the soft bending make CG + point-block Jacobi need ~1000 iterations per step
mpiexec -n 1 "$CLOTHSIM" -scene "$out/cantilever.yaml" -output_dir "$out" -output_every 0 -pc_type cholesky -progress_seconds 100 > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; exit 1; }
$py postprocess/cantilever.py measure "$(ls "$out"/checkpoint_*.h5 | tail -1)" --scene "$out/cantilever.yaml" --log "$out/run.log" --tolerance 0.10 --check

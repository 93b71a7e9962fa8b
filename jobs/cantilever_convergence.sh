#!/bin/bash
# Grid convergence of the cantilever (docs/validation.md, section 4): polyester strips (both directions, 5 overhangs
# of 2.6-4.0 cm that bracket l* of both) at 15, 30, 60 and 120 segments along the overhang, each bending length
# against the exact heavy elastica (postprocess/elastica.py); writes OUT/convergence.md (table with the observed
# order) and OUT/cantilever_convergence.png. 6 s of damped fall (at 3 s the 120-segment strips still move at 3e-5 m/s
# and read 0.03% of c short; at 6 s every strip is below 2e-8 m/s). About 2 minutes on one core.
#
#   bash jobs/cantilever_convergence.sh [BUILD_DIR] [OUT_DIR]        (defaults: build, output/cantilever_convergence)
#   CANTILEVER_SEGMENTS="15 30" CANTILEVER_PRESETS="polyester denim" bash jobs/cantilever_convergence.sh
#
# One rank, PETSc's Cholesky on the AIJ matrix (-implicit_mat_type aij -pc_type cholesky): Cholesky on the default
# block (BAIJ) matrix fails from 60 segments on (docs/validation.md, "Solver").
#SBATCH --job-name=clothsim-cantilever-convergence
#SBATCH --ntasks=1
set -eu
build=${1:-build}
out=${2:-output/cantilever_convergence}
py=/usr/bin/python3
segments=(${CANTILEVER_SEGMENTS:-15 30 60 120})
presets=(${CANTILEVER_PRESETS:-polyester})
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[[ -x $build/clothsim ]] || { echo "no clothsim binary in $build (build first: bash scripts/build.sh)" >&2; exit 1; }
mkdir -p "$out"
for n in "${segments[@]}"; do
  echo "cantilever, $n segments"
  $py postprocess/cantilever.py scene --presets "${presets[@]}" --count 5 --lmin 0.026 --lmax 0.040 --segments "$n" --t-final 6 -o "$out/cantilever_$n.yaml"
  mpiexec -n 1 --bind-to none "$build/clothsim" -scene "$out/cantilever_$n.yaml" -output_dir "$out/run_$n" -output_every 0 \
    -implicit_mat_type aij -pc_type cholesky -progress_seconds 600 > "$out/cantilever_$n.log" 2>&1 || { tail -20 "$out/cantilever_$n.log"; exit 1; }
  $py postprocess/cantilever.py measure "$(ls "$out/run_$n"/checkpoint_*.h5 | tail -1)" --scene "$out/cantilever_$n.yaml" \
    --log "$out/cantilever_$n.log" --json > "$out/cantilever_$n.json"
done
$py postprocess/cantilever.py convergence $(for n in "${segments[@]}"; do echo "$out/cantilever_$n.json"; done) --out "$out/cantilever_convergence.png" > "$out/convergence.md"
cat "$out/convergence.md"

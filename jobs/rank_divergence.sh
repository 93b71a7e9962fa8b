#!/bin/bash
# How far the same scene drifts apart on 1, 2 and 4 ranks (docs/parallel.md, "Rank counts: what agrees and what
# does not"): three cases, each run on every rank count with checkpoints along the way, compared with
# postprocess/rank_divergence.py (largest particle distance to the 1-rank run at every checkpoint; final energies,
# body contact count, drape coefficient). 4 ranks run oversubscribed on a 2-core machine. About 2 minutes.
#
#   bash jobs/rank_divergence.sh [BUILD_DIR] [OUT_DIR]        (defaults: build, output/rank_divergence)
#   RANKS="1 2 3 4 8" bash jobs/rank_divergence.sh             (other rank counts; the first is the reference)
#
# smooth:   input/hanging_sheet.yaml -grid 65 with damping 1 1/s, implicit (the default CG + point-block Jacobi,
#           rtol 1e-5), 2 s; checkpoints every 0.2 s
# contact:  input/sphere_drape.yaml -grid 33 (a sphere and the ground, friction), implicit, 2 s; frames and
#           checkpoints every 0.2 s; drape coefficient of the sheet over the sphere: support disc r = 0.3 m (the
#           sphere's shadow), specimen r = 0.78987 m (the flat 1.4 m square's area)
# undamped: input/hanging_sheet.yaml -grid 33 as it is (no damping), symplectic Euler, dt 1e-4 s, 1 s;
#           checkpoints every 0.1 s
set -eu
build=${1:-build}
out=${2:-output/rank_divergence}
py=/usr/bin/python3
ranks=(${RANKS:-1 2 4})
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[[ -x $build/clothsim ]] || { echo "no clothsim binary in $build (build first: bash scripts/build.sh)" >&2; exit 1; }
rm -rf "$out"
mkdir -p "$out"
sed 's/^    damping: 0 .*/    damping: 1.0/' input/hanging_sheet.yaml > "$out/hanging_damped.yaml"
grep -q "damping: 1.0" "$out/hanging_damped.yaml" || { echo "could not set the damping of the hanging sheet" >&2; exit 1; }

run_case() { # run_case NAME CLOTHSIM-ARGS...: the case on every rank count, $out/NAME/npP and npP.log
  local name=$1
  shift
  for p in "${ranks[@]}"; do
    echo "$name on $p rank(s)"
    mkdir -p "$out/$name"
    mpiexec -n "$p" --oversubscribe "$build/clothsim" "$@" -output_dir "$out/$name/np$p" -checkpoint_keep 0 \
      -monitor_energy -progress_seconds 600 > "$out/$name/np$p.log" 2>&1 || { tail -20 "$out/$name/np$p.log"; exit 1; }
  done
}
specs() { for p in "${ranks[@]}"; do echo "$p=$out/$1/np$p"; done; }

run_case smooth -scene "$out/hanging_damped.yaml" -grid 65 -t_final 2 -output_every 0 -checkpoint_every 48
run_case contact -scene input/sphere_drape.yaml -grid 33 -t_final 2 -output_every 48 -checkpoint_every 48
run_case undamped -scene input/hanging_sheet.yaml -grid 33 -integrator symplectic -dt 1e-4 -t_final 1 -output_every 0 -checkpoint_every 1000
{
  $py postprocess/rank_divergence.py --label smooth $(specs smooth) --json "$out/smooth.json"
  $py postprocess/rank_divergence.py --label contact $(specs contact) --json "$out/contact.json" \
    --scene input/sphere_drape.yaml --grid 33 --drape 0.3 0.78987
  $py postprocess/rank_divergence.py --label undamped $(specs undamped) --json "$out/undamped.json"
} | tee "$out/summary.txt"

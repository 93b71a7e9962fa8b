#!/bin/bash
# The fitted dress (issue 26, docs/results.md "The fitted dress") at one or more resolutions of the same pattern,
# each on 2 ranks, followed by its quality, pictures and movie (jobs/garment_outputs.sh), and the fine-vs-coarse
# comparison of the hem: its mean and lowest height and its fold count (postprocess/hem_folds.py) at the same
# simulated times in every run, as a table (output/dress_fitted_hem.csv).
#
#   bash jobs/dress_fitted.sh                       # the fine dress: input/dress_fitted.yaml (8 mm, 14,950 particles)
#   bash jobs/dress_fitted.sh coarse middle fine    # 20 mm (2,610), 12 mm (6,732) and 8 mm, then the hem table
#   RUN=0 bash jobs/dress_fitted.sh coarse middle fine   # the table only, from the runs already in output/
#
# Settings (environment variables, defaults in brackets):
#   RUN           1: run the simulations; 0: only the table from existing output       [1]
#   RESTART       1: continue each run from its newest checkpoint (a run stopped by a time limit)   [0]
#   TIMES         the simulated times of the hem table, s            [0.2 0.4 0.6 1 2 5]
#   RANKS         MPI ranks                                         [2]
#   RENDER, MOVIE those of jobs/garment_outputs.sh                  [1, 1]
# The implicit solve uses the solver's default preconditioner for garments, seam-block Jacobi (point-block Jacobi
# with each sewn pair in one block, src/seam_blocks.c) below 40,000 particles: GAMG from 5,000 on (-implicit_pc_multilevel_min_particles 5000, tried on 2026-11-26) broke down on
# the middle dress (an indefinite preconditioner) in 269 of its first 310 steps, each solve then done again by the
# fallback solver (362 Krylov its/step in all).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
RUN=${RUN:-1} RESTART=${RESTART:-0} RANKS=${RANKS:-2}
TIMES=${TIMES:-0.2 0.4 0.6 1 2 5}
levels=("$@")
[ ${#levels[@]} -gt 0 ] || levels=(fine)
scene_of() {
  case $1 in
    fine) echo input/dress_fitted.yaml ;;
    middle) echo input/dress_fitted_middle.yaml ;;
    coarse) echo input/dress_fitted_coarse.yaml ;;
    *) echo "dress_fitted.sh: unknown resolution '$1': expected coarse, middle or fine" >&2; return 1 ;;
  esac
}
name_of() { basename "$1" .yaml; }
for level in "${levels[@]}"; do scene_of "$level" > /dev/null || exit 2; done

if [ "$RUN" = 1 ]; then
  for level in "${levels[@]}"; do
    scene=$(scene_of "$level") name=$(name_of "$scene")
    out=output/$name
    options=(-scene "$scene" -output_dir "$out" -cloth_stiffness gauss_newton
             -checkpoint_every 100 -progress_seconds 60)
    last=$(ls "$out"/checkpoint_*.h5 2> /dev/null | tail -n 1)
    if [ "$RESTART" = 1 ] && [ -n "$last" ]; then
      options+=(-restart "$last")
    else
      options+=(-output_overwrite)
    fi
    RANKS=$RANKS bash jobs/garment_run.sh "dress_fitted: $level" "$out" "$name" "${options[@]}" || exit 1
  done
fi

# The hem at the same simulated times in every run (a run that has not reached a time is left out of its row).
table=output/dress_fitted_hem.csv
mkdir -p output
echo "resolution,particles,time_s,hem_height_mean_m,hem_height_min_m,folds" > "$table"
for level in "${levels[@]}"; do
  scene=$(scene_of "$level") name=$(name_of "$scene")
  series=output/$name/$name.h5
  [ -f "$series" ] || { echo "dress_fitted: no $series (RUN=1 makes it)"; continue; }
  for t in $TIMES; do
    /usr/bin/python3 postprocess/hem_folds.py "$series" --scene "$scene" --time "$t" --json "output/$name/hem_$t.json" > /dev/null || continue
    /usr/bin/python3 - "$level" "$scene" "$t" "output/$name/hem_$t.json" >> "$table" <<'PY'
import json, sys, yaml
level, scene, t, path = sys.argv[1:5]
r = json.load(open(path))
if abs(r["time"] - float(t)) <= 0.021:  # the run reached t (frames every 0.1 s or finer)
    particles = sum(p["grid"][0] * p["grid"][1] for p in yaml.safe_load(open(scene))["pieces"])
    print(f"{level},{particles},{r['time']:g},{r['hem_height_mean']},{r['hem_height_min']},{r['folds']}")
PY
  done
done
column -s, -t < "$table"
echo "dress_fitted: the table is in $table"

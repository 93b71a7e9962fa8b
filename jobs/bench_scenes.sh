#!/usr/bin/env bash
# The scenes' benchmark: each RUNS entry "SCENE GRID RANKS STEPS [TAG [options...]]" is one clothsim run with -log_view,
# -memory_view and -self_collision_view, its log kept in jobs/results/bench/logs/, one row in
# jobs/results/bench/scenes.csv (jobs/bench_table.py) and the table in docs/performance.md regenerated. Before the runs,
# each scene and rank count is run at -grid 9 for one step, and its peak memory is kept as that configuration's
# baseline (the processes' libraries and buffers, which do not grow with the fabric). Keep the machine otherwise idle.
#
#   bash jobs/bench_scenes.sh                                        # the default RUNS below
#   RUNS="sheet_drape 129 2 360" bash jobs/bench_scenes.sh           # one run
#
# Environment: RUNS (newline-separated entries), BUILD_DIR (build), OUT_DIR (jobs/results/bench), MARKDOWN
# (docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
out=${OUT_DIR:-jobs/results/bench}
markdown=${MARKDOWN:-docs/performance.md}
default_runs="sheet_drape 129 2 360 drape
sheet_drape 129 2 360 drape_no_self -self_collision 0
sheet_drape 257 2 360 drape
sheet_drape 257 2 360 drape_no_self -self_collision 0
sheet_drape 513 2 120 drape
sheet_drape 1025 2 120 drape"
runs=${RUNS:-$default_runs}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$out/logs"
stamp=$(date -u +%Y%m%dT%H%M%SZ)

# the baselines: each scene and rank count at -grid 9 for one step
baselines=$(while read -r scene grid ranks rest; do [[ -n ${scene:-} ]] && echo "$scene 9 $ranks 1 baseline"; done <<< "$runs" | sort -u)
runs="$baselines
$runs"
while read -r scene grid ranks steps tag extra; do
  [[ -n ${scene:-} ]] || continue
  tag=${tag:-default}
  log=$out/logs/${tag}_${scene}_grid_${grid}_np_${ranks}_steps_${steps}_${stamp}.log
  dir=$(mktemp -d)
  command="mpiexec -n $ranks $build_dir/clothsim -scene input/$scene.yaml -grid $grid -steps $steps -output_every 0 -log_view -memory_view -self_collision_view ${extra:-}"
  echo "== $command"
  # shellcheck disable=SC2086
  mpiexec -n "$ranks" "$build_dir/clothsim" -scene "input/$scene.yaml" -grid "$grid" -steps "$steps" -output_every 0 -progress_seconds 60 \
    -output_dir "$dir" -log_view -memory_view -self_collision_view ${extra:-} </dev/null >"$log" 2>&1 || { echo "bench_scenes: the run failed, see $log"; tail -5 "$log"; }
  dt=$(sed -n 's/^  run defaults.* dt \([0-9.e+-]*\) s.*/\1/p' "$log" | head -1)
  /usr/bin/python3 jobs/bench_table.py add --log "$log" --scene "$scene" --grid "$grid" --ranks "$ranks" --tag "$tag" --csv "$out/scenes.csv" \
    --t-final "$(/usr/bin/python3 -c "print(round($steps * ${dt:-0}, 4))")" --command "$command" || true
  rm -rf "$dir"
done <<< "$runs"
/usr/bin/python3 jobs/bench_table.py report --csv "$out/scenes.csv" --markdown "$markdown"

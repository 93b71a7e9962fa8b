#!/usr/bin/env bash
# The performance benchmark (issue 10): the hanging sheet (input/hanging_sheet.yaml: 1 m square, 0.2 kg/m^2,
# pinned at two corners, released from rest, implicit, dt = 1/240 s) at several sizes on 1 and 2 ranks, the
# machine's memory bandwidth measured in the same run (build/stream_triad, a STREAM-style triad), and
# optionally peer simulators (not part of clothsim: PEERS_DIR) on the same scene. One table: CSV, PNG and markdown.
#
#   bash jobs/bench.sh                                   # everything below with its defaults
#   GRIDS="65 129" RANKS_LIST=1 PEERS= bash jobs/bench.sh   # a quick subset
#
# Environment:
#   BUILD_DIR   (build)         clothsim and stream_triad are taken from here
#   GRIDS       (65 129 257 513) particles per side
#   RANKS_LIST  (1 2)
#   T_FINAL     (1)             simulated seconds (240 steps); T_FINAL_<grid> overrides per grid, e.g.
#                               T_FINAL_513=0.1: runs shorter than 1 s cover only the start of the fall,
#                               where CG needs fewer iterations, and cannot be compared with the peers' sag
#   PEERS       (empty: none)   peers to run, e.g. "blender newton taichi warp", through PEERS_DIR/run_all.sh;
#   PEERS_DIR   (none)          the peer simulators' drivers (run_all.sh, setup.sh, which makes their virtual
#                               environments); they are not part of this repository
#   PEER_GRIDS  (65)            sizes for the peers (129 takes Taichi about 8 minutes)
#   EXTRA                       more clothsim options (e.g. "-pc_type pbjacobi -implicit_mat_type baij")
#   TAG         (default)       a name for this configuration, kept in the CSV
#   OUT_DIR     (jobs/results/bench), MARKDOWN (docs/performance.md): where the results and the table go
# Results: jobs/results/bench/bench.csv (appended; one row per run, clothsim and peers), runs' logs beside it,
# bench.png, and the table in docs/performance.md (jobs/bench_report.py). Keep the machine otherwise idle.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
grids=${GRIDS:-65 129 257 513}
ranks_list=${RANKS_LIST:-1 2}
peers=${PEERS-}
peer_grids=${PEER_GRIDS:-65}
tag=${TAG:-default}
out=${OUT_DIR:-jobs/results/bench}
markdown=${MARKDOWN:-docs/performance.md}
peer_dir=${PEERS_DIR:-}
# Checked before the runs, not after them.
if [[ -n $peers ]]; then
  [[ -n $peer_dir && -f $peer_dir/run_all.sh ]] || { echo "bench.sh: PEERS=$peers needs PEERS_DIR, a folder with the peers' run_all.sh (PEERS_DIR='$peer_dir')" >&2; exit 1; }
  peer_dir=$(cd "$peer_dir" && pwd)
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$out"
stamp=$(date -u +%Y%m%dT%H%M%SZ)

# Bandwidth first, on as many ranks as the runs use: the roofline of each run is computed with it.
for ranks in $ranks_list; do
  mpiexec -n "$ranks" "$build_dir/stream_triad" -n 16777216 -repeats 20 | tee -a "$out/stream_${stamp}.log"
done

for grid in $grids; do
  var=T_FINAL_$grid
  t_final=${!var:-${T_FINAL:-1}}
  for ranks in $ranks_list; do
    log=$out/clothsim_${tag}_grid_${grid}_np_${ranks}_${stamp}.log
    echo "== clothsim grid $grid, $ranks rank(s), t_final $t_final: $log"
    # shellcheck disable=SC2086
    mpiexec -n "$ranks" "$build_dir/clothsim" -scene input/hanging_sheet.yaml -grid "$grid" -dt 0.004166666666666667 \
      -t_final "$t_final" -output_every 0 -progress_seconds 60 -output_dir "$out/run_${grid}_${ranks}" -output_overwrite \
      -log_view -memory_view ${EXTRA:-} >"$log" 2>&1
    /usr/bin/python3 jobs/bench_report.py clothsim --log "$log" --grid "$grid" --ranks "$ranks" --tag "$tag" \
      --stream "$out/stream_${stamp}.log" --checkpoint-dir "$out/run_${grid}_${ranks}" --csv "$out/bench.csv" \
      --command "mpiexec -n $ranks $build_dir/clothsim -scene input/hanging_sheet.yaml -grid $grid -dt 0.004166666666666667 -t_final $t_final -output_every 0 -log_view -memory_view ${EXTRA:-}"
    rm -rf "$out/run_${grid}_${ranks}"
  done
done

if [[ -n $peers ]]; then
  peer_out=$(cd "$out" && pwd)/peers_${stamp}.jsonl
  (cd "$peer_dir" && NS="$peer_grids" ONLY="$peers" OUT="$peer_out" bash run_all.sh)
  /usr/bin/python3 jobs/bench_report.py peers --jsonl "$peer_out" --csv "$out/bench.csv"
fi
/usr/bin/python3 jobs/bench_report.py report --csv "$out/bench.csv" --png "$out/bench.png" --markdown "$markdown"

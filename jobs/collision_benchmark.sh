#!/bin/bash
# Collision cost on the mannequin (docs/collisions.md): a sheet dropped on the shoulders
# (tests/data/mannequin_shoulders.yaml) at n x n particles, n = 33, 65, 129, with the per-rank cell grid and
# with brute force over all 26,756 triangles; STEPS steps of the implicit integrator on RANKS ranks.
# Prints one line per run: n, search, time steps (s), ClothCollision (s), per step (ms), share of the step.
#
#   jobs/collision_benchmark.sh [BUILD_DIR] [STEPS] [RANKS]
set -eu
build=${1:-build}
steps=${2:-60}
ranks=${3:-1}
out=${TMPDIR:-/tmp}/collision_benchmark
mkdir -p "$out"
printf "%5s %12s %14s %16s %12s %8s\n" n search "time steps/s" "ClothCollision/s" "per step/ms" share
for n in 33 65 129; do
  for search in grid brute_force; do
    log="$out/n${n}_${search}.log"
    mpiexec -n "$ranks" "$build/clothsim" -scene tests/data/mannequin_shoulders.yaml -grid "$n" -steps "$steps" \
      -collision_search "$search" -output_every 0 -output_dir "$out/n${n}_${search}" -output_overwrite -progress_seconds 1000 -log_view > "$log" 2>&1
    stage=$(awk '/^ *2: +Time steps:/ {print $4}' "$log")
    coll=$(awk '$1 == "ClothCollision" {print $4; exit}' "$log")
    awk -v n="$n" -v s="$search" -v st="$stage" -v c="$coll" -v k="$steps" \
      'BEGIN {printf "%5d %12s %14.3f %16.3f %12.2f %7.1f%%\n", n, s, st, c, 1000 * c / k, 100 * c / st}'
  done
done

#!/usr/bin/env bash
# The implicit solver study (issue 22) in one command, side by side in one session on the hanging sheet
# (jobs/bench.sh: 1 m square, pinned at two corners, dt = 1/240 s):
#   earlier_default  CG + point-block Jacobi on the BAIJ matrix at every size (the default until 2026-11-25);
#   default          today's default: point-block Jacobi below 2,500 particles, the pattern-grid multigrid (SBAIJ
#                    from 10,000 particles) from 2,500 on (the sheet has no seams);
# both over the full simulated second at 65 and 129 and over the first 0.1 s (24 steps) at 257 and 513, where the
# old default would take hours; then the default alone over the full second at 257 and 513 and over 24 steps at
# 1025 (LARGE_GRID); and, when PEERS_DIR names the peer simulators' drivers and Newton's environment exists there
# (its setup.sh newton), Newton's four solvers at 65 and 129. Last the main job (the dress, 2 ranks) with the
# projected and with the Gauss-Newton element stiffness (jobs/results/bench/dress_*.log, -log_view). Writes
# jobs/results/bench/bench.csv (appended), bench.png and the table in docs/performance.md. Keep the machine
# otherwise idle: it takes about an hour on 2 cores (56 min on 2026-11-27; the full second of 513 x 513 on 1 rank alone 14 min).
#
#   bash jobs/bench_solver.sh
#   GRIDS="65 129" RANKS_LIST=1 FULL_GRIDS= LARGE_GRID= bash jobs/bench_solver.sh     # a quick subset
#
# Environment: GRIDS (65 129 257 513), RANKS_LIST (1 2), T_FINAL_<grid> (257 and 513: 0.1 s = 24 steps; others the
# full second), FULL_GRIDS (257 513: the default again over the full second; empty: skip), LARGE_GRID (1025: the
# default alone, 1 and 2 ranks, 24 steps; empty: skip), WITH_GAMG (1: GAMG forced at every size as a third tag).
set -euo pipefail
cd "$(dirname "$0")/.."
export GRIDS=${GRIDS:-65 129 257 513} RANKS_LIST=${RANKS_LIST:-1 2}
export T_FINAL_257=${T_FINAL_257:-0.1} T_FINAL_513=${T_FINAL_513:-0.1} T_FINAL_1025=${T_FINAL_1025:-0.1}
full=${FULL_GRIDS-257 513}
large=${LARGE_GRID-1025}
peers=
[[ -n ${PEERS_DIR:-} && -x $PEERS_DIR/.venv-newton/bin/python ]] && peers=newton

PEERS= TAG=earlier_default EXTRA="-pc_type pbjacobi -implicit_mat_type baij" bash jobs/bench.sh
PEERS=$peers PEER_GRIDS="65 129" TAG=default EXTRA= bash jobs/bench.sh
if [[ ${WITH_GAMG:-0} == 1 ]]; then
  PEERS= TAG=gamg EXTRA="-pc_type gamg" bash jobs/bench.sh
fi
for grid in $full; do
  GRIDS=$grid PEERS= TAG=default EXTRA= env "T_FINAL_$grid=1" bash jobs/bench.sh
done
if [[ -n $large ]]; then
  GRIDS=$large PEERS= TAG=default EXTRA= bash jobs/bench.sh
fi

# The main job's two stiffness forms: wall time, Krylov iterations and the Jacobian assembly's share (-log_view).
for form in projected gauss_newton; do
  log=jobs/results/bench/dress_${form}_$(date -u +%Y%m%dT%H%M%SZ).log
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpiexec -n 2 "${BUILD_DIR:-build}/clothsim" -scene input/dress_fitted_coarse.yaml \
    -cloth_stiffness "$form" -output_overwrite -output_every 5 -output_dir "jobs/results/bench/runs/dress_$form" -progress_seconds 60 -log_view > "$log" 2>&1
  echo "dress, -cloth_stiffness $form: $(grep '^Done' "$log" | cut -c1-90); $(grep -E '^ClothJacobian ' "$log" | awk '{print "assembly " $4 " s"}')"
  rm -rf "jobs/results/bench/runs/dress_$form"
done

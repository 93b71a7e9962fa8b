#!/bin/bash
# One run of the at-scale study (issue 25, docs/performance.md "At scale"): the hanging sheet of GRID x GRID particles
# on RANKS ranks for STEPS steps with a frame and a checkpoint, profiled by -log_view (with PETSc's memory columns,
# -log_view_memory, which need PETSc's allocation tracking) and -memory_view, under /usr/bin/time -v (the
# peak resident set of rank 0's process). -log_view_memory needs PETSc's tracked malloc: -malloc_dump turns it on
# without -malloc_debug's check of the whole heap at every call (same bytes, 257 x 257: peak 5365 against 5349 B
# per particle; a 1025 x 1025 run with -malloc_debug was stopped unfinished after 37 minutes). The load average (uptime) before and after goes into the log, as the
# machine is shared: compare counts (flops, messages, bytes, iterations) rather than times.
#
#   jobs/at_scale.sh GRID RANKS [TAG [clothsim options...]]      e.g.  jobs/at_scale.sh 1025 2
#   STEPS=1 (default) OUT=jobs/results/at_scale/runs CLOTHSIM=build/clothsim MPIEXEC=mpiexec
#   MALLOC_LOG=0: without -log_view_memory -malloc_dump, whose tracking adds to the resident set (a production run's
#   memory: 257 x 257 on 1 rank, 525 MB with it for 1 step, 397 MB without for the 24 steps of the issue 22 benchmark)
#
# Writes OUT/grid<GRID>_np<RANKS>[_TAG].log (clothsim's output and the load) and .time (/usr/bin/time -v);
# jobs/at_scale_report.py reads them. The run's series and checkpoints go to a temporary directory, removed after,
# or to KEEP_OUTPUT=DIR, kept (e.g. for a restart on another rank count).
set -euo pipefail
grid=$1 ranks=$2 tag=${3:-}
shift $(($# < 3 ? $# : 3))
cd "$(dirname "$0")/.."
out=${OUT:-jobs/results/at_scale/runs}
steps=${STEPS:-1}
clothsim=${CLOTHSIM:-build/clothsim}
mkdir -p "$out"
name=grid${grid}_np${ranks}${tag:+_$tag}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/at_scale.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
run=${KEEP_OUTPUT:-$tmp/run}
malloc_log="-log_view_memory -malloc_dump"
[[ ${MALLOC_LOG:-1} == 0 ]] && malloc_log=
{
  echo "# at_scale: grid $grid ranks $ranks steps $steps tag '${tag}' options: $*"
  echo "# date $(date -u +%Y-%m-%dT%H:%M:%SZ) uptime before: $(uptime)"
} >"$out/$name.log"
/usr/bin/time -v -o "$out/$name.time" "${MPIEXEC:-mpiexec}" -n "$ranks" "$clothsim" -scene input/hanging_sheet.yaml \
  -grid "$grid" -steps "$steps" -output_every "$steps" -checkpoint_every 0 -output_dir "$run" \
  -log_view -memory_view $malloc_log "$@" >>"$out/$name.log" 2>&1
ls -l "$run" >>"$out/$name.log"
echo "# uptime after: $(uptime)" >>"$out/$name.log"
echo "$out/$name.log"

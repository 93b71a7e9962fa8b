#!/usr/bin/env bash
# Benchmark of the implicit integrator on the hanging sheet (input/hanging_sheet.yaml): 1 s at dt = 1/240 s
# for each grid size and rank count. A measurement, not a test (the 257 x 257 runs take many minutes).
#
#   bash jobs/bench_implicit.sh
#
# Environment: CLOTHSIM (build/clothsim), GRIDS ("65 129 257"), RANKS_LIST ("1 2"), T_FINAL (1; shorter
# runs cover only the start of the fall, where the solver needs fewer iterations per step), EXTRA (more clothsim options).
# Per run it records, from clothsim's own output:
#   particle-steps/s     particles x steps / wall time of the time loop ("Done: ... s wall")
#   KSP its/step         Krylov iterations of the run / steps
#   memory/particle      PETSc -memory_view "Maximum (over computational time) process memory", summed over
#                        ranks (resident set size, so it includes MPI's and the libraries' own memory)
#   jacobian/solve/forces s   -log_view max-over-ranks time of ClothJacobian (assembly of the matrix),
#                        ClothSolve (the KSP solve) and ClothForces, summed over the log stages (ClothForces
#                        stays 0 here: the implicit step computes forces and matrix together in ClothJacobian)
#   cpu_s                user + system CPU seconds of all ranks (/usr/bin/time, when installed): on a shared,
#                        overloaded machine wall times stretch, CPU times much less
#   load                 the 1-minute load average when the run started (above the core count: wall times are inflated)
# Results: jobs/results/bench_implicit.csv (appended), jobs/results/bench_implicit/grid_N_np_P_t_T.log, and the
# table of the whole CSV in docs/foundation.md (jobs/bench_table.py).
set -euo pipefail
cd "$(dirname "$0")/.."
clothsim=${CLOTHSIM:-build/clothsim}
grids=${GRIDS:-65 129 257}
ranks_list=${RANKS_LIST:-1 2}
t_final=${T_FINAL:-1}
results=jobs/results
logs=$results/bench_implicit
csv=$results/bench_implicit.csv
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$logs"
[[ -f $csv ]] || echo "grid,particles,ranks,steps,wall_s,particle_steps_per_s,ksp_its_per_step,memory_bytes_per_particle,jacobian_s,solve_s,forces_s,cpu_s,load,date,host" >"$csv"

for grid in $grids; do
  for ranks in $ranks_list; do
    log=$logs/grid_${grid}_np_${ranks}_t_${t_final}.log
    echo "== grid $grid on $ranks rank(s): $log"
    timer=()
    [[ -x /usr/bin/time ]] && timer=(/usr/bin/time -f "cpu_seconds %U %S" -o "$log.time")
    load=$(cut -d' ' -f1 /proc/loadavg)
    # shellcheck disable=SC2086
    "${timer[@]}" mpiexec -n "$ranks" "$clothsim" -scene input/hanging_sheet.yaml -grid "$grid" -dt 0.004166666666666667 \
      -t_final "$t_final" -output_every 0 -progress_seconds 30 -output_dir "$logs/output_${grid}_${ranks}" \
      -log_view -memory_view ${EXTRA:-} >"$log" 2>&1
    rm -rf "$logs/output_${grid}_${ranks}"
    row=$(/usr/bin/python3 - "$log" "$grid" "$ranks" "$load" <<'PY'
import os, re, sys
log, grid, ranks, load = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
text = open(log).read()
done = re.search(r"^Done: (\d+) steps \((\d+) sub-steps\), (\d+) Krylov iterations, ([0-9.]+) s wall", text, re.M)
steps, its, wall = int(done.group(1)), int(done.group(3)), float(done.group(4))
particles = grid * grid
memory = float(re.search(r"Maximum \(over computational time\) process memory:\s+total\s+(\S+)", text).group(1))
def event(name):
    # "-log_view" event lines: name, count, count ratio, max time, time ratio, ...; one line per stage.
    return sum(float(m.group(1)) for m in re.finditer(rf"^{name}\s+\d+\s+\S+\s+(\S+)", text, re.M))
cpu = ""
if os.path.exists(log + ".time"):
    user, system = re.search(r"cpu_seconds (\S+) (\S+)", open(log + ".time").read()).groups()
    cpu = f"{float(user) + float(system):.2f}"
print(f"{grid},{particles},{ranks},{steps},{wall:.2f},{particles * steps / wall:.4g},{its / steps:.1f},"
      f"{memory / particles:.0f},{event('ClothJacobian'):.3f},{event('ClothSolve'):.3f},{event('ClothForces'):.3f},{cpu},{load}")
PY
)
    echo "$row,$(date -u +%FT%TZ),$(hostname -s)" | tee -a "$csv"
  done
done
/usr/bin/python3 jobs/bench_table.py "$csv" docs/foundation.md

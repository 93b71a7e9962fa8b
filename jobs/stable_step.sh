#!/usr/bin/env bash
# The largest stable time step of each integrator on the hanging sheet, by bisection on dt.
# A measurement, not a test: minutes to tens of minutes. Results: jobs/results/stable_step.csv,
# logs in jobs/results/stable_step/. "Stable" is defined in jobs/stable_step_judge.py (1 s simulated,
# no step reduction, finite, energy gain < 1 % of M g L, max |x| < 3 m).
#
#   bash jobs/stable_step.sh                       # the cases below
#   bash jobs/stable_step.sh SCENE GRID INTEGRATOR GUESS [...]   # chosen cases, four words each
#
# Environment: CLOTHSIM (default build/clothsim), RANKS (1), STABLE_ENERGY_FRACTION (0.01; "inf" drops the
# energy criterion, CSV=... then names another results file), RATIO (1.1: bisection stops when the
# unstable / stable bracket is below it), DT_MAX (0.25 s), DT_MIN (1e-8 s), PROBE_TIMEOUT (900 s per run;
# a case whose run takes longer is recorded as not measured).
set -euo pipefail
cd "$(dirname "$0")/.."
clothsim=${CLOTHSIM:-build/clothsim}
ranks=${RANKS:-1}
ratio=${RATIO:-1.1}
dt_max=${DT_MAX:-0.25}
dt_min=${DT_MIN:-1e-8}
probe_timeout=${PROBE_TIMEOUT:-900}
results=jobs/results
logs=$results/stable_step
csv=${CSV:-$results/stable_step.csv}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$logs"
[[ -f $csv ]] || echo "scene,grid,integrator,stable_dt,unstable_dt,reason_at_unstable,probes,date" >"$csv"

U=input/hanging_sheet.yaml
D=tests/data/hanging_sheet_damped.yaml
# scene grid integrator first-guess-dt. Explicit Euler on the undamped 65 x 65 sheet is left out: the
# energy of a mode of frequency w grows by exp(dt w^2 T) over T, so a bounded 1 s needs dt ~ 1e-7 s
# (10^7 steps), and already 33 x 33 needs more than 15 minutes per probe; the smaller grids and the
# damped scene show its behaviour at affordable cost.
default_cases=(
  "$U" 65 implicit 0.01    "$U" 65 symplectic 1e-4
  "$U" 33 implicit 0.01    "$U" 33 symplectic 3e-4
  "$U" 17 implicit 0.01    "$U" 17 symplectic 5e-4    "$U" 17 explicit 1e-6
  "$U" 9  implicit 0.01    "$U" 9  symplectic 1e-3    "$U" 9  explicit 1e-5
  "$D" 65 implicit 0.01    "$D" 65 symplectic 1e-4
  "$D" 17 implicit 0.01    "$D" 17 symplectic 5e-4    "$D" 17 explicit 1e-6
  "$D" 9  implicit 0.01    "$D" 9  symplectic 1e-3    "$D" 9  explicit 1e-5
)
cases=("$@")
[[ ${#cases[@]} -gt 0 ]] || cases=("${default_cases[@]}")

# probe SCENE GRID INTEGRATOR DT: runs 1 s and prints the judgement ("stable ..." or "unstable: ...").
probe() {
  local scene=$1 grid=$2 integrator=$3 dt=$4
  local name dir every status=0
  name=$(basename "$scene" .yaml)_${grid}_${integrator}
  dir=$logs/$name/dt_$dt
  every=$(awk -v dt="$dt" 'BEGIN { k = int(0.01 / dt + 0.5); print (k < 1 ? 1 : k) }')
  rm -rf "$dir"
  mkdir -p "$dir"
  timeout "$probe_timeout" mpiexec -n "$ranks" "$clothsim" -scene "$scene" -grid "$grid" -integrator "$integrator" -dt "$dt" -t_final 1 \
    -output_every "$every" -monitor_energy -progress_seconds 1e9 -output_dir "$dir" >"$dir/log.txt" 2>&1 || status=$?
  local verdict
  verdict=$(/usr/bin/python3 jobs/stable_step_judge.py "$dir/log.txt" "$dir/$(sed -n 's/^name: *//p' "$scene").h5" "$status")
  rm -f "$dir"/*.h5 "$dir"/*.xdmf # keep only the log: the series of many probes would fill the disk
  echo "$verdict"
}

mul() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4g", a * b }'; }
geomean() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4g", sqrt(a * b) }'; }
wider() { awk -v a="$1" -v b="$2" -v r="$ratio" 'BEGIN { exit !(b / a > r) }'; }
above() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a > b) }'; }

for ((c = 0; c < ${#cases[@]}; c += 4)); do
  scene=${cases[c]} grid=${cases[c + 1]} integrator=${cases[c + 2]} dt=${cases[c + 3]}
  stable="" unstable="" reason="" probes=0
  echo "== $scene -grid $grid -integrator $integrator"
  # Bracket: from the guess, by factors of 4, up to a stable and an unstable step.
  while [[ -z $stable || -z $unstable ]]; do
    verdict=$(probe "$scene" "$grid" "$integrator" "$dt"); probes=$((probes + 1))
    echo "   dt $dt: $verdict"
    if [[ $verdict == timeout* ]]; then reason=$verdict; break; fi
    if [[ $verdict == stable* ]]; then
      stable=$dt
      [[ -n $unstable ]] && break
      if ! above "$dt_max" "$dt"; then unstable="none<=$dt_max"; break; fi
      dt=$(mul "$dt" 4)
      if above "$dt" "$dt_max"; then dt=$dt_max; fi
    else
      unstable=$dt reason=${verdict#unstable: }
      [[ -n $stable ]] && break
      if ! above "$dt" "$dt_min"; then stable="none>=$dt_min"; break; fi
      dt=$(mul "$dt" 0.25)
      if above "$dt_min" "$dt"; then dt=$dt_min; fi
    fi
  done
  # Bisection (geometric) until unstable / stable < RATIO.
  if [[ -n $stable && -n $unstable && $stable != none* && $unstable != none* ]]; then
    while wider "$stable" "$unstable"; do
      dt=$(geomean "$stable" "$unstable")
      verdict=$(probe "$scene" "$grid" "$integrator" "$dt"); probes=$((probes + 1))
      echo "   dt $dt: $verdict"
      if [[ $verdict == timeout* ]]; then reason="bisection stopped: $verdict"; break; fi
      if [[ $verdict == stable* ]]; then stable=$dt; else unstable=$dt reason=${verdict#unstable: }; fi
    done
  fi
  echo "   largest stable dt: $stable (unstable at $unstable: $reason)"
  echo "$(basename "$scene" .yaml),$grid,$integrator,$stable,$unstable,\"$reason\",$probes,$(date -u +%FT%TZ)" >>"$csv"
done

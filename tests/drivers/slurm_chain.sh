#!/bin/bash
# The restart chain of jobs/ under a real Slurm: starts slurmctld + slurmd on localhost (tests/drivers/slurm_cluster.sh),
# runs the large sheet uninterrupted (mpirun, no Slurm) as the reference, then submits the same run as a
# chain (jobs/chain.sh jobs/large_sheet.sbatch). As soon as the first job has written its first checkpoint
# the test sends it what Slurm sends at --signal time (scancel --signal=TERM --batch: SIGTERM to the batch
# shell only); the batch script must pass it on to the ranks, which checkpoint and stop; the dependent job
# restarts from the newest checkpoint and finishes. Checks: at least two jobs ran, the first was stopped by
# the signal and the second restarted, and the final state equals the reference's to CHAIN_TOLERANCE
# (default 0: bit for bit, the same rank count on both sides).
# Exit status 77 (ctest: skipped) with the reason when Slurm cannot run here.
#
# Usage: slurm_chain.sh [WORKDIR]     environment: CLOTHSIM (binary), RANKS (2), CHAIN_TOLERANCE (0),
#        SLURM_CHAIN_MODE=timeout: no scancel: the jobs get --time=1 and --signal=B:TERM@50 and a longer
#        run, so that Slurm itself signals them (takes several minutes; not run by ctest).
set -uo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
root=$(cd "$tests/.." && pwd)
work=${1:-${CLOTHSIM_BUILD:-$root/build}/tests/slurm_chain}
CLOTHSIM=${CLOTHSIM:-$root/build/clothsim}
RANKS=${RANKS:-2}
CHAIN_TOLERANCE=${CHAIN_TOLERANCE:-0}
mode=${SLURM_CHAIN_MODE:-signal}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Ranks that wait yield the core: on a shared (busy) test machine this halves the wall time.
export OMPI_MCA_mpi_yield_when_idle=${OMPI_MCA_mpi_yield_when_idle:-1}

fail() { echo "FAIL: $*"; exit 1; }
[ -x "$CLOTHSIM" ] || fail "no clothsim binary at $CLOTHSIM (set CLOTHSIM)"
rm -rf "$work"
mkdir -p "$work"
# shellcheck source=tests/drivers/slurm_cluster.sh
source "$tests/drivers/slurm_cluster.sh"
trap 'slurm_cluster_stop' EXIT
slurm_cluster_start "$work/slurm" || exit 77

# The run: a large_sheet.sbatch run of ~800 particles per rank (41 x 41 on 2 ranks).
export CLOTHSIM CLOTHSIM_ROOT=$root RANKS PYTHON=/usr/bin/python3
export PARTICLES_PER_RANK=$((1681 / RANKS)) STEPS=120 CHECKPOINT_EVERY=5 OUTPUT_EVERY=40 CHECKPOINT_KEEP=3
export CLOTHSIM_OPTIONS="-progress_seconds 1"
sbatch_args=(--ntasks="$RANKS" --time=5 --job-name=chain_test)
if [ "$mode" = timeout ]; then
  export STEPS=2400 CHECKPOINT_EVERY=50
  export CHAIN_SIGNAL=B:TERM@50
  sbatch_args=(--ntasks="$RANKS" --time=1 --job-name=chain_test)
fi
grid=$(awk -v p="$PARTICLES_PER_RANK" -v r="$RANKS" 'BEGIN { n = int(sqrt(p * r) + 0.5); if (n % 2 == 0) n++; print n }')

echo "== reference: $grid x $grid, $STEPS steps on $RANKS ranks, uninterrupted"
mpirun -n "$RANKS" "$CLOTHSIM" -scene "$root/input/hanging_sheet.yaml" -grid "$grid" -steps "$STEPS" \
  -output_every "$OUTPUT_EVERY" -output_dir "$work/reference" > "$work/reference.log" 2>&1 ||
  { tail -n 20 "$work/reference.log"; fail "reference run failed"; }
tail -n 1 "$work/reference.log"

echo "== chain: jobs/chain.sh jobs/large_sheet.sbatch ${sbatch_args[*]}"
export OUTPUT_DIR=$work/chain CHAIN_LOG_DIR=$work/logs
first=$(cd "$root" && jobs/chain.sh jobs/large_sheet.sbatch "${sbatch_args[@]}") || fail "chain.sh failed"
echo "first job: $first"

job_state() { scontrol -o show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'; }
deadline=$((SECONDS + 170))
[ "$mode" = timeout ] && deadline=$((SECONDS + 1200))
if [ "$mode" = signal ]; then
  # Wait until the first job has written a checkpoint, then signal its batch shell as Slurm would.
  while [ $SECONDS -lt $deadline ]; do
    ls "$OUTPUT_DIR"/checkpoint_*.h5 > /dev/null 2>&1 && break
    st=$(job_state "$first")
    case "$st" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL) fail "job $first ended ($st) before its first checkpoint: $(cat "$work"/logs/*-"$first".out)" ;; esac
    sleep 0.1
  done
  scancel --signal=TERM --batch "$first" || fail "scancel --signal=TERM --batch $first failed"
  echo "sent SIGTERM to the batch shell of job $first after $(ls "$OUTPUT_DIR"/checkpoint_*.h5 | head -n 1 | xargs basename)"
fi
# Wait for the chain to drain.
while [ $SECONDS -lt $deadline ] && [ -n "$(squeue -h -o %i)" ]; do sleep 0.5; done
[ -z "$(squeue -h -o %i)" ] || { squeue; fail "the chain did not finish in time"; }

echo "== jobs (jobcomp log):"
sed -n 's/.*JobId=\([0-9]*\).*Name=\([^ ]*\).*JobState=\([A-Z_]*\).*/  job \1 \2 \3/p' "$work/slurm/jobcomp.log"
logs=("$work"/logs/chain_test-*.out)
echo "logs: ${#logs[@]}"
for f in "${logs[@]}"; do echo "--- $f"; grep -E '^\[job|Restarting|^Stopped|Done:|ERROR|rror' "$f"; done
[ "${#logs[@]}" -ge 2 ] || fail "only ${#logs[@]} job(s) ran: no restart happened"
grep -q "^Stopped by" "$work/logs/chain_test-$first.out" ||
  fail "job $first was not stopped by the signal (did the batch script pass it on to the ranks?)"
grep -l "Restarting from" "${logs[@]}" > /dev/null || fail "no job restarted from a checkpoint"
if grep -q "FAILED" "$work/slurm/jobcomp.log"; then fail "a job of the chain failed"; fi

echo "== final state against the reference (tolerance $CHAIN_TOLERANCE)"
final=$(printf '%s\n' "$OUTPUT_DIR"/checkpoint_*.h5 | sort | tail -n 1)
/usr/bin/python3 - "$final" "$work/reference/checkpoint_$(printf %06d "$STEPS").h5" "$STEPS" "$CHAIN_TOLERANCE" <<'PY' || fail "final state differs"
import sys, h5py, numpy as np
final, ref, steps, tol = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
with h5py.File(final, "r") as a, h5py.File(ref, "r") as b:
    sa, sb = a["state"], b["state"]
    assert int(sa.attrs["step"]) == steps, f"{final}: step {int(sa.attrs['step'])}, expected {steps}"
    assert abs(float(sa.attrs["time"]) - float(sb.attrs["time"])) <= 1e-12, "times differ"
    dx = np.max(np.abs(sa["position"][...] - sb["position"][...]))
    dv = np.max(np.abs(sa["velocity"][...] - sb["velocity"][...]))
print(f"{final} vs {ref}: step {steps}, max |dx| = {dx:.3e} m, max |dv| = {dv:.3e} m/s")
sys.exit(0 if dx <= tol and dv <= tol else 1)
PY
echo "PASS"

# shellcheck shell=bash
# Shared by the batch scripts in jobs/ (sourced, not run): starts clothsim under mpirun, passes the
# scheduler's termination signal on to it, restarts from the newest checkpoint, and keeps a restart
# chain going (see jobs/chain.sh and docs/jobs.md).
#
# Settings (environment; the batch scripts give their own defaults):
#   CLOTHSIM_ROOT     the clothsim source tree (default: the directory sbatch was called from)
#   CLOTHSIM          the binary (default: $CLOTHSIM_ROOT/build/clothsim; in an installed copy, where
#                     CLOTHSIM_ROOT is PREFIX/share/clothsim, PREFIX/bin/clothsim)
#   MPIEXEC           the MPI launcher (default: mpirun)
#   MPIEXEC_FLAGS     extra launcher flags, e.g. "--bind-to core" (default: none)
#   RANKS             MPI ranks (default: $SLURM_NTASKS, else 1)
#   PYTHON            a Python 3 with h5py and PyYAML (default: python3)
#   RESTART           auto: continue from the newest DIR/checkpoint_NNNNNN.h5 if there is one (default);
#                     none: always start from t = 0; or a checkpoint file
#   CHAIN             1: this job is a link of a restart chain: it submits its successor (see below)
#   CHAIN_SCRIPT      the batch script the successor runs (set by chain.sh)
#   CHAIN_SBATCH_ARGS sbatch options for the successor (set by chain.sh; word-split)
#   CHAIN_LINK        number of this link, 1 for the first job (set by chain.sh)
#   CHAIN_MAX_LINKS   submit no link past this number (default 20)
#
# Why the signal dance: Slurm's --signal=B:TERM@T signals only the batch shell. bash runs a trap only
# when the command it waits for returns, so mpirun runs in the background and the script waits for it;
# the trap then sends SIGUSR1 to mpirun, which Open MPI passes on to every rank (mpirun would answer a
# SIGTERM of its own by killing the ranks after a few seconds). clothsim treats SIGUSR1 like SIGTERM:
# it finishes its step, writes DIR/checkpoint_NNNNNN.h5 and exits with status 0.

CLOTHSIM_ROOT=${CLOTHSIM_ROOT:-${SLURM_SUBMIT_DIR:-$PWD}}
if [ -z "${CLOTHSIM:-}" ]; then
  CLOTHSIM=$CLOTHSIM_ROOT/build/clothsim
  # an installed copy (cmake --install build --prefix PREFIX): CLOTHSIM_ROOT=PREFIX/share/clothsim
  [ -x "$CLOTHSIM" ] || [ ! -x "$CLOTHSIM_ROOT/../../bin/clothsim" ] || CLOTHSIM=$(cd "$CLOTHSIM_ROOT/../../bin" && pwd)/clothsim
fi
MPIEXEC=${MPIEXEC:-mpirun}
MPIEXEC_FLAGS=${MPIEXEC_FLAGS:-}
RANKS=${RANKS:-${SLURM_NTASKS:-1}}
PYTHON=${PYTHON:-python3}
RESTART=${RESTART:-auto}
CHAIN=${CHAIN:-0}
CHAIN_LINK=${CHAIN_LINK:-1}
CHAIN_MAX_LINKS=${CHAIN_MAX_LINKS:-20}

job_log() { echo "[job ${SLURM_JOB_ID:-local} $(date -u +%H:%M:%S)] $*"; }

# newest_checkpoint DIR: prints the checkpoint of DIR with the highest step, or nothing.
newest_checkpoint() {
  local f
  f=$(ls -1 "$1"/checkpoint_[0-9][0-9][0-9][0-9][0-9][0-9].h5 2>/dev/null | sort | tail -n 1)
  [ -n "$f" ] && echo "$f"
  return 0
}

# checkpoint_step FILE: prints the step attribute of /state (h5dump, else Python's h5py).
checkpoint_step() {
  local s=""
  if command -v h5dump > /dev/null; then
    s=$(h5dump -a /state/step "$1" 2>/dev/null | sed -n 's/^ *(0): *\([0-9-]*\).*/\1/p' | head -n 1)
  fi
  if [ -z "$s" ]; then
    s=$("$PYTHON" -c 'import sys, h5py; print(int(h5py.File(sys.argv[1], "r")["state"].attrs["step"]))' "$1" 2>/dev/null)
  fi
  [ -n "$s" ] || { echo "checkpoint_step: cannot read /state/step of $1 (need h5dump or h5py)" >&2; return 1; }
  echo "$s"
}

# run_forwarding COMMAND...: runs COMMAND in the background; SIGTERM/SIGUSR1/SIGINT to this shell send
# SIGUSR1 to it. Returns its exit status. Sets JOB_SIGNALLED=1 if a signal came.
JOB_SIGNALLED=0
run_forwarding() {
  local pid rc
  "$@" &
  pid=$!
  trap 'JOB_SIGNALLED=1; job_log "termination signal: asking clothsim (mpirun $pid) to checkpoint and stop"; kill -USR1 '"$pid"' 2>/dev/null' TERM USR1 INT
  while :; do
    wait "$pid"
    rc=$?
    # wait returns > 128 when a trapped signal interrupts it: the command is still running.
    if [ "$rc" -gt 128 ] && kill -0 "$pid" 2>/dev/null; then continue; fi
    break
  done
  trap - TERM USR1 INT
  return "$rc"
}

# clothsim_job OUTPUT_DIR STEPS CLOTHSIM_OPTIONS...: runs clothsim with -output_dir OUTPUT_DIR -steps STEPS
# and the options, restarting from the newest checkpoint (RESTART=auto) and, with CHAIN=1, submitting the
# next link of the chain first and cancelling it when the run is done. Exit status: 0 when the run is done
# or was stopped by a signal after a checkpoint; else clothsim's.
clothsim_job() {
  local dir=$1 steps=$2 ckpt step0=0 step1 next="" rc restart_opt=()
  shift 2
  mkdir -p "$dir"
  case "$RESTART" in
    auto) ckpt=$(newest_checkpoint "$dir") ;;
    none | "") ckpt="" ;;
    *) ckpt=$RESTART ;;
  esac
  if [ -n "$ckpt" ]; then
    step0=$(checkpoint_step "$ckpt") || return 1
    if [ "$step0" -ge "$steps" ]; then
      job_log "run already done: $ckpt is at step $step0 of $steps"
      return 0
    fi
    restart_opt=(-restart "$ckpt")
    job_log "restarting from $ckpt (step $step0 of $steps)"
  fi
  if [ "$CHAIN" = 1 ]; then
    if [ "$CHAIN_LINK" -lt "$CHAIN_MAX_LINKS" ]; then
      # shellcheck disable=SC2086
      next=$(CHAIN_LINK=$((CHAIN_LINK + 1)) sbatch --parsable --dependency=afterany:"$SLURM_JOB_ID" \
               --export=ALL $CHAIN_SBATCH_ARGS "$CHAIN_SCRIPT") || { job_log "cannot submit the next link"; return 1; }
      next=${next%%;*}
      job_log "chain link $CHAIN_LINK; next link $((CHAIN_LINK + 1)) is job $next (starts after this one ends)"
    else
      job_log "chain link $CHAIN_LINK is the last one allowed (CHAIN_MAX_LINKS=$CHAIN_MAX_LINKS)"
    fi
  fi
  job_log "$MPIEXEC -n $RANKS $MPIEXEC_FLAGS $CLOTHSIM $* -output_dir $dir -steps $steps ${restart_opt[*]}"
  # shellcheck disable=SC2086
  run_forwarding "$MPIEXEC" -n "$RANKS" $MPIEXEC_FLAGS "$CLOTHSIM" "$@" -output_dir "$dir" -steps "$steps" "${restart_opt[@]}"
  rc=$?
  ckpt=$(newest_checkpoint "$dir")
  step1=-1
  [ -n "$ckpt" ] && { step1=$(checkpoint_step "$ckpt") || step1=-1; }
  if [ "$step1" -ge "$steps" ]; then
    job_log "run done: $ckpt is at step $step1 of $steps"
    [ -n "$next" ] && scancel "$next" && job_log "cancelled link $next: nothing left to do"
    return 0
  fi
  if [ "$rc" -ne 0 ] && [ "$JOB_SIGNALLED" = 0 ]; then
    job_log "clothsim failed (status $rc) at step $step1 of $steps"
    [ -n "$next" ] && scancel "$next" && job_log "cancelled link $next: the run failed, not restarting it"
    return "$rc"
  fi
  job_log "stopped at step $step1 of $steps (checkpoint $ckpt)${next:+; job $next continues}"
  return 0
}

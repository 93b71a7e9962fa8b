#!/bin/bash
# Runs a clothsim batch script as a restart chain: submits its first job; every job of the chain, when it
# starts and the run is not done yet, submits the next one with --dependency=afterany:<its own id>, asks
# Slurm for SIGTERM before its time limit (--signal), writes a checkpoint when it comes and ends; the next
# job restarts from the newest checkpoint. When the final step is reached (the newest checkpoint's step
# attribute equals STEPS), the job that got there cancels the link it had submitted, and the chain ends.
#
#   jobs/chain.sh [SCRIPT] [SBATCH OPTIONS...]      from the clothsim tree; prints the first job id
#   jobs/chain.sh jobs/large_sheet.sbatch --ntasks=64 --time=1:00:00
#   PARTICLES_PER_RANK=20000 STEPS=5000 jobs/chain.sh jobs/large_sheet.sbatch --ntasks=8 --time=30
#
# SCRIPT defaults to jobs/large_sheet.sbatch. The script's own settings come from the environment
# (see the script): sbatch passes the whole environment on to every job of the chain (--export=ALL).
# Settings of the chain (environment, defaults in brackets):
#   CHAIN_SIGNAL      the --signal option of every job; with B: the batch shell gets it     [B:TERM@120]
#   CHAIN_MAX_LINKS   never more jobs than this, in case a run cannot progress             [20]
#   CHAIN_LOG_DIR     where the jobs' logs go (%x-%j.out; the directory must exist)   [output/jobs]
# Slurm delivers --signal up to a minute late (it checks every 30 s), so keep the lead time above ~90 s
# plus the time of one step and one checkpoint. A job that did not finish its checkpoint in time is ended
# as TIMEOUT; the chain goes on from the previous checkpoint.
set -euo pipefail
script=${1:-jobs/large_sheet.sbatch}
[ $# -gt 0 ] && shift
[ -f "$script" ] || { echo "chain.sh: no batch script $script (run from the clothsim tree)" >&2; exit 1; }
command -v sbatch > /dev/null || { echo "chain.sh: sbatch not found: is Slurm installed and SLURM_CONF set?" >&2; exit 1; }
CHAIN_SIGNAL=${CHAIN_SIGNAL:-B:TERM@120}
CHAIN_LOG_DIR=${CHAIN_LOG_DIR:-output/jobs}
mkdir -p "$CHAIN_LOG_DIR"
export CLOTHSIM_ROOT=${CLOTHSIM_ROOT:-$PWD}
export CHAIN=1 CHAIN_LINK=1 CHAIN_MAX_LINKS=${CHAIN_MAX_LINKS:-20}
export CHAIN_SCRIPT
CHAIN_SCRIPT=$(cd "$(dirname "$script")" && pwd)/$(basename "$script")
export CHAIN_SBATCH_ARGS="--signal=$CHAIN_SIGNAL --chdir=$CLOTHSIM_ROOT --output=$CHAIN_LOG_DIR/%x-%j.out $*"
# shellcheck disable=SC2086
id=$(sbatch --parsable --export=ALL $CHAIN_SBATCH_ARGS "$CHAIN_SCRIPT")
echo "${id%%;*}"

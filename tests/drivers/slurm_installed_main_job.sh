#!/bin/bash
# The installed copy under a real Slurm (tests/drivers/slurm_cluster.sh starts slurmctld + slurmd on localhost): cmake
# --install into a temporary prefix, then, from a directory outside the trees, `sbatch --wait
# PREFIX/share/clothsim/jobs/main_job.sbatch` with CLOTHSIM_ROOT=PREFIX/share/clothsim (CLOTHSIM unset) and
# STEPS=3: the job must run the main job of scripts/run_main.sh (input/dress_fitted_coarse.yaml on the script's 2 tasks) with
# PREFIX/bin/clothsim, write output/dress_fitted_coarse in the submit directory (not in the installed tree) and run the garment
# quality tool. Exit status 77 (ctest: skipped) when Slurm cannot run here.
#
# Usage: slurm_installed_main_job.sh WORKDIR     (CLOTHSIM_BUILD set by ctest)
set -uo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
work=$1
: "${CLOTHSIM_BUILD:?set CLOTHSIM_BUILD to the build directory}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_mpi_yield_when_idle=${OMPI_MCA_mpi_yield_when_idle:-1}
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work/submit"
# shellcheck source=tests/drivers/slurm_cluster.sh
source "$tests/drivers/slurm_cluster.sh"
trap 'slurm_cluster_stop' EXIT
slurm_cluster_start "$work/slurm" || exit 77

prefix=$work/prefix
share=$prefix/share/clothsim
cmake --install "$CLOTHSIM_BUILD" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }
cd "$work/submit" || fail "cd"
unset CLOTHSIM
CLOTHSIM_ROOT=$share STEPS=3 RENDER=0 PYTHON=/usr/bin/python3 timeout 150 sbatch --wait --output="$work/job.out" \
  "$share/jobs/main_job.sbatch" > "$work/sbatch.out" 2>&1 || { cat "$work/sbatch.out" "$work/job.out"; fail "the job failed"; }
cat "$work/job.out" | grep -E '^\[job|Done:|Garment quality'
grep -q "mpirun -n 2 *$prefix/bin/clothsim -scene input/dress_fitted_coarse.yaml" "$work/job.out" || fail "the job did not run the installed binary on input/dress_fitted_coarse.yaml with 2 ranks"
grep -q "run done: .*checkpoint_000003.h5 is at step 3 of 3" "$work/job.out" || fail "the run did not reach step 3"
[ -f "$work/submit/output/dress_fitted_coarse/quality.json" ] || fail "no output/dress_fitted_coarse/quality.json in the submit directory"
grep -q "fabric crossings counted in frame 000003" "$work/job.out" || fail "garment_quality.py did not run"
[ ! -e "$share/output" ] || fail "the job wrote into the installed tree"
echo "PASS: the installed main_job.sbatch ran the fitted dress on 2 ranks under Slurm"

#!/bin/bash
# One garment run and what follows it, the one copy that jobs/tshirt.sh and jobs/dress_fitted.sh call: clothsim on
# RANKS ranks with the given options, its wall time, then jobs/garment_outputs.sh (quality, pictures, movie).
#
#   bash jobs/garment_run.sh TAG OUTPUT_DIR NAME CLOTHSIM_OPTIONS...
#
# TAG names the run in messages; the options must write to OUTPUT_DIR (-output_dir), whose series is NAME.xdmf.
# Settings (environment variables, defaults in brackets):
#   RANKS         MPI ranks                                         [2]
#   RENDER, MOVIE those of jobs/garment_outputs.sh                  [1, 1]
set -uo pipefail
[ $# -ge 3 ] || { echo "usage: bash jobs/garment_run.sh TAG OUTPUT_DIR NAME CLOTHSIM_OPTIONS..." >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tag=$1 out=$2 name=$3
shift 3
RANKS=${RANKS:-2}
echo "$tag: mpiexec -n $RANKS build/clothsim $*"
start=$(date +%s)
mpiexec -n "$RANKS" build/clothsim "$@" || { echo "$tag: the run failed"; exit 1; }
echo "$tag: $(($(date +%s) - start)) s wall on $RANKS ranks"
bash jobs/garment_outputs.sh "$out" "$name"

#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to results: installs what is missing, builds, runs the main job,
# and says where the results are and how to look at them.
#
#   bash scripts/run_main.sh         (BUILD_DIR=... builds and runs from another build directory)
set -euo pipefail

# The main job: the hanging-sheet benchmark (input/hanging_sheet.yaml, 65 x 65, 1 s) on 2 ranks.
# Switch the scene (and options) here; results go to output/NAME (NAME from the scene's "name:") or -output_dir.
MAIN_JOB=(mpiexec -n 2 build/clothsim -scene input/hanging_sheet.yaml)

cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh

# Open MPI refuses to run as root without these; the third allows more ranks than cores.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

build_dir=${BUILD_DIR:-build}
job=()
scene="" output_dir=""
for ((i = 0; i < ${#MAIN_JOB[@]}; i++)); do
  word=${MAIN_JOB[i]}
  [[ $word == build/clothsim ]] && word=$build_dir/clothsim
  [[ $i -gt 0 && ${MAIN_JOB[i - 1]} == -scene ]] && scene=$word
  [[ $i -gt 0 && ${MAIN_JOB[i - 1]} == -output_dir ]] && output_dir=$word
  job+=("$word")
done
name=$(sed -n 's/^name: *\([A-Za-z0-9_.-]*\).*/\1/p' "$scene" | head -n 1)
name=${name:-$(basename "$scene" .yaml)}
output_dir=${output_dir:-output/$name}

echo "run_main: ${job[*]}"
"${job[@]}"

cat <<MSG

Results in $output_dir:
  $name.xdmf + $name.h5        time series (positions, velocities, quads) for ParaView
  checkpoint_NNNNNN.h5         the final state (continue with -restart FILE)
Open in ParaView:    paraview $output_dir/$name.xdmf     (reader: "Xdmf3 Reader S" or "XDMF Reader")
Without a display:   xvfb-run -a pvpython -c "from paraview.simple import *; r = Xdmf3ReaderS(FileName='$output_dir/$name.xdmf'); r.UpdatePipeline(); print(r.TimestepValues)"
Inspect the data:    h5ls -r $output_dir/$name.h5
MSG

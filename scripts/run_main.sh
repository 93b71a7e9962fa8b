#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to results: installs what is missing, builds, runs the main job,
# and says where the results are and how to look at them.
#
#   bash scripts/run_main.sh
set -euo pipefail

# The main job: the hanging-sheet benchmark (input/hanging_sheet.yaml) on 2 ranks, 1 s simulated.
MAIN_SCENE=input/hanging_sheet.yaml
MAIN_RANKS=2
MAIN_OPTIONS=()

cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh

# Open MPI refuses to run as root without these; the second allows more ranks than cores.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

build_dir=${BUILD_DIR:-build}
name=$(sed -n 's/^name: *\([A-Za-z0-9_.-]*\).*/\1/p' "$MAIN_SCENE" | head -n 1)
output_dir=output/$name
echo "run_main: mpiexec -n $MAIN_RANKS $build_dir/clothsim -scene $MAIN_SCENE ${MAIN_OPTIONS[*]:-}"
mpiexec -n "$MAIN_RANKS" "$build_dir/clothsim" -scene "$MAIN_SCENE" -output_dir "$output_dir" "${MAIN_OPTIONS[@]}"

cat <<MSG

Results in $PWD/$output_dir:
  $name.xdmf + $name.h5        time series (positions, velocities, quads) for ParaView
  checkpoint_NNNNNN.h5         the final state (restart with -restart FILE)
Open in ParaView:    paraview $output_dir/$name.xdmf     (choose the "Xdmf3 Reader S" or "XDMF Reader")
Without a display:   pvpython, e.g.  xvfb-run -a pvpython -c "from paraview.simple import *; r = Xdmf3ReaderS(FileName='$output_dir/$name.xdmf'); print(r.TimestepValues)"
Inspect the data:    h5ls -r $output_dir/$name.h5
MSG

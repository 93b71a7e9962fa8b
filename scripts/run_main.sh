#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to results: installs what is missing, builds, runs the main job,
# and says where the results are and how to look at them.
#
#   bash scripts/run_main.sh         (BUILD_DIR=... builds and runs from another build directory)
set -euo pipefail

# The main job: the dress assembled on the mannequin (input/dress.yaml) on 2 ranks, about 27 s on two
# idle cores. Switch the scene (and options) here; results go to output/NAME (NAME from the scene's
# "name:") or -output_dir. For a garment (a scene with seams) the run writes quality.json, and this
# script completes it and renders front, side and back views beside the XDMF. -output_overwrite: each
# run of this script replaces the previous results (clothsim refuses that otherwise). -cloth_stiffness
# gauss_newton: the closed-form element stiffness, 2.1x faster here (docs/performance.md).
MAIN_JOB=(mpiexec -n 2 build/clothsim -scene input/dress.yaml -output_overwrite -cloth_stiffness gauss_newton)

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

if [ -f "$output_dir/quality.json" ]; then
  /usr/bin/python3 postprocess/garment_quality.py "$output_dir" --name "$name" || true
  for view in front side back; do
    # Rendering needs an X server (ParaView 5.11's pvpython crashes with --force-offscreen-rendering): a virtual one.
    xvfb-run -a /usr/bin/pvpython postprocess/render.py "$output_dir/$name.xdmf" --frame -1 --view "$view" \
      --size 800x1100 --out "$output_dir/${name}_$view.png" || echo "run_main: the $view render failed (is xvfb installed?)"
  done
fi

cat <<MSG

Results in $output_dir:
  $name.xdmf + $name.h5        time series (positions, velocities, quads) for ParaView
  checkpoint_NNNNNN.h5         the final state (continue with -restart FILE)
  quality.json, ${name}_front.png, _side.png, _back.png   for a garment: its measured quality and renders
Open in ParaView:    paraview $output_dir/$name.xdmf     (reader: "Xdmf3 Reader S" or "XDMF Reader")
Without a display:   xvfb-run -a pvpython -c "from paraview.simple import *; r = Xdmf3ReaderS(FileName='$output_dir/$name.xdmf'); r.UpdatePipeline(); print(r.TimestepValues)"
Inspect the data:    h5ls -r $output_dir/$name.h5
MSG

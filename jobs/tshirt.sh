#!/bin/bash
# The T-shirt with set-in sleeves (input/tshirt.yaml) and the T-shirt under a dress (input/tshirt_dress.yaml),
# issue 26 (docs/results.md, "A T-shirt with set-in sleeves" and "Layering"), each on 2 ranks with the main job's
# options, followed by its quality, pictures and movie (jobs/garment_outputs.sh). Both scenes are written by
# scripts/tshirt_scenes.py.
#
#   bash jobs/tshirt.sh                  # the T-shirt and the layered scene, one after the other
#   bash jobs/tshirt.sh tshirt           # the T-shirt only (1,628 particles)
#   bash jobs/tshirt.sh layered          # the T-shirt under the dress only (4,106 particles)
#
# Settings (environment variables, defaults in brackets):
#   RANKS         MPI ranks                                         [2]
#   RENDER, MOVIE those of jobs/garment_outputs.sh                  [1, 1]
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
RANKS=${RANKS:-2}
garments=("$@")
[ ${#garments[@]} -gt 0 ] || garments=(tshirt layered)
scene_of() {
  case $1 in
    tshirt) echo input/tshirt.yaml ;;
    layered) echo input/tshirt_dress.yaml ;;
    *) echo "tshirt.sh: unknown garment '$1': expected tshirt or layered" >&2; return 1 ;;
  esac
}
for garment in "${garments[@]}"; do scene_of "$garment" > /dev/null || exit 2; done

for garment in "${garments[@]}"; do
  scene=$(scene_of "$garment") name=$(basename "$(scene_of "$garment")" .yaml)
  out=output/$name
  # -output_every 5: a frame every 0.02 s, for the movie of the assembly (as scripts/run_main.sh).
  options=(-scene "$scene" -output_dir "$out" -output_overwrite -cloth_stiffness gauss_newton -output_every 5 -progress_seconds 30)
  RANKS=$RANKS bash jobs/garment_run.sh "tshirt: $garment" "$out" "$name" "${options[@]}" || exit 1
done

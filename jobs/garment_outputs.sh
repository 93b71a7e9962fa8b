#!/bin/bash
# What a garment run is followed by, the one copy that scripts/run_main.sh and jobs/main_job.sbatch both call:
# the garment's quality (postprocess/garment_quality.py completes quality.json and checks it against the
# targets), renders of the last frame shaded as cloth (front, side, back), its fit maps (strain and pressure on
# the body, front and back) and a movie of the assembly (the first 1.2 s: the pull, the sewing, the garment
# settling). A miss or a failed picture is reported, not fatal: the run's results stay.
#
#   bash jobs/garment_outputs.sh OUTPUT_DIR NAME        (OUTPUT_DIR/NAME.xdmf and OUTPUT_DIR/quality.json)
#
# Settings (environment variables, defaults in brackets):
#   PYTHON        a Python 3 with numpy, h5py and PyYAML      [/usr/bin/python3]
#   PVPYTHON      ParaView's Python                          [pvpython on PATH, else /usr/bin/pvpython]
#   RENDER        1: the stills and the movie; 0: the quality only   [1]
#   RENDER_SIZE   the stills' size, WIDTHxHEIGHT              [800x1100]
#   MOVIE         1: the movie (needs xvfb-run and ffmpeg, often missing on a compute node)   [1]
#   GARMENT_OUTPUTS_CHECK  1: the quality as always, but no pictures: parse every picture command's arguments with
#                 the tool's own parser (render.py's and movie.py's parse_args) and print the commands; exit 1 when
#                 one does not parse (tests/drivers/install_run.sh checks the installed main_job.sbatch this way)   [0]
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: bash jobs/garment_outputs.sh OUTPUT_DIR NAME" >&2; exit 2; }
output_dir=$1 name=$2
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
PYTHON=${PYTHON:-/usr/bin/python3}
PVPYTHON=${PVPYTHON:-$(command -v pvpython || echo /usr/bin/pvpython)}
RENDER=${RENDER:-1}
RENDER_SIZE=${RENDER_SIZE:-800x1100}
MOVIE=${MOVIE:-1}
check=${GARMENT_OUTPUTS_CHECK:-0}
xdmf=$output_dir/$name.xdmf
say() { echo "garment_outputs: $*"; }
[ -f "$output_dir/quality.json" ] || { say "no $output_dir/quality.json: not a garment run, nothing to do"; exit 0; }

parse_failures=0
parses() {  # parses TOOL ARGS...: the tool's own argument parser accepts ARGS (check mode)
  local tool=$1
  shift
  say "$tool $*"
  "$PYTHON" -c 'import sys; sys.path.insert(0, sys.argv[1]); __import__(sys.argv[2]).parse_args(sys.argv[3:])' \
    "$root/postprocess" "$tool" "$@" < /dev/null || { say "the $tool arguments above do not parse"; parse_failures=$((parse_failures + 1)); }
}

# Rendering needs an X server: postprocess/pvpython_xvfb.sh starts a virtual one (and tries again when another X
# server takes its display number), or uses the display there is when xvfb-run is missing.
render() {  # render VIEW COLOUR OUT.png
  local args=("$xdmf" --frame -1 --view "$1" --color-by "$2" --size "$RENDER_SIZE" --out "$3")
  [ "$check" = 1 ] && { parses render "${args[@]}"; return; }
  if PVPYTHON=$PVPYTHON bash "$root/postprocess/pvpython_xvfb.sh" "$root/postprocess/render.py" "${args[@]}" > "$3.log" 2>&1; then
    tail -n 1 "$3.log"
    rm -f "$3.log"
  else
    say "the $2 render from the $1 failed (is ParaView installed, with xvfb?), see $3.log"
  fi
}

"$PYTHON" "$root/postprocess/garment_quality.py" "$output_dir" --name "$name" || say "the garment misses a quality target (see above)"
[ "$RENDER" = 1 ] || exit 0
# The garment shaded as cloth (a colour per fabric, the seams drawn), then its fit maps: strain and the pressure on the body.
for view in front side back; do
  render "$view" fabric "$output_dir/${name}_$view.png"
done
for map in strain pressure; do
  for view in front back; do
    render "$view" "$map" "$output_dir/${name}_${map}_$view.png"
  done
done
if [ "$MOVIE" = 1 ]; then
  # The movie of the assembly: the frames of the first 1.2 s (61 at a frame every 0.02 s), 640x480 at 12 per
  # second, about a minute and a half on two cores for the dress.
  movie=("$xdmf" --out "$output_dir/$name.mp4" --frames 61 --t-max 1.2 --size 640x480 --view iso)
  if [ "$check" = 1 ]; then
    parses movie "${movie[@]}"
  else
    PVPYTHON=$PVPYTHON "$PYTHON" "$root/postprocess/movie.py" "${movie[@]}" < /dev/null || say "the movie failed (are xvfb and ffmpeg installed?)"
  fi
fi
[ "$parse_failures" = 0 ] || { say "$parse_failures picture command(s) do not parse"; exit 1; }
exit 0

#!/bin/bash
# The postprocess tools on a tiny real run: postprocess/energy.py (energies against clothsim's own
# -monitor_energy values and m g h at t = 0), postprocess/render.py (a PNG of the requested size), the
# pictures of a garment (render.py shaded as cloth and coloured by a fit map, postprocess/movie.py's MP4), and
# the scaling driver jobs/scaling.py (its table), each also with --help.
# Usage: postprocess_tools.sh WORKDIR [energy|render|movie|scaling]...      (CLOTHSIM: the binary)
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
root=$(cd "$tests/.." && pwd)
work=$1
shift
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(energy render movie scaling)
CLOTHSIM=${CLOTHSIM:-$root/build/clothsim}
py=/usr/bin/python3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"

# The run: a 9 x 9 hanging sheet (total mass 0.2 kg at height 1 m), 24 steps, a frame every 6: 5 frames.
run() {
  [ -f "$work/run/hanging_sheet.xdmf" ] && return 0
  "$CLOTHSIM" -scene "$root/input/hanging_sheet.yaml" -grid 9 -steps 24 -output_every 6 -monitor_energy \
    -output_dir "$work/run" > "$work/run.log" 2>&1 || { cat "$work/run.log"; fail "clothsim run failed"; }
}

png_size() {  # prints WIDTH HEIGHT of a PNG (from its IHDR chunk)
  $py -c 'import struct, sys; d = open(sys.argv[1], "rb").read(24); assert d[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"; print(*struct.unpack(">II", d[16:24]))' "$1"
}

for part in "${parts[@]}"; do
  case $part in
  energy)
    run
    $py "$root/postprocess/energy.py" --help | grep -q "kinetic energy" || fail "energy.py --help"
    $py "$root/postprocess/energy.py" "$work/run/hanging_sheet.xdmf" --scene "$root/input/hanging_sheet.yaml" --grid 9 \
      --log "$work/run.log" --out "$work/energy.png" --csv "$work/energy.csv"
    $py - "$work/energy.csv" "$work/run.log" <<'PY' || fail "energy.py numbers"
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 5, f"{len(rows)} frames, expected 5"
assert [int(r["step"]) for r in rows] == [0, 6, 12, 18, 24], [r["step"] for r in rows]
mgh = 0.2 * 9.81 * 1.0
g0, k0 = float(rows[0]["gravity"]), float(rows[0]["kinetic"])
assert abs(g0 - mgh) <= 1e-9 * mgh, f"gravitational energy at t = 0: {g0!r}, expected m g h = {mgh!r}"
assert k0 == 0.0 and float(rows[0]["max_strain"]) == 0.0 and float(rows[0]["min_strain"]) == 0.0
log = {int(m.group(1)): (float(m.group(2)), float(m.group(3)))
       for m in re.finditer(r"energy at step\s+(\d+): kinetic (\S+) J, gravity (\S+) J", open(sys.argv[2]).read())}
worst = 0.0
for r in rows:
    k, g = log[int(r["step"])]
    for mine, theirs in ((float(r["kinetic"]), k), (float(r["gravity"]), g)):
        worst = max(worst, abs(mine - theirs) / max(abs(theirs), 1e-12))
assert worst <= 1e-8, f"energy.py and clothsim -monitor_energy differ by {worst:.2e} (relative)"
assert float(rows[-1]["kinetic"]) > 0 and float(rows[-1]["max_strain"]) > 0
print(f"energy.py: 5 frames; E_grav(0) = {g0!r} J (m g h = {mgh!r}); kinetic and gravitational energy "
      f"agree with clothsim -monitor_energy to {worst:.1e} (relative)")
PY
    [ "$(png_size "$work/energy.png")" = "700 600" ] || fail "energy.png size $(png_size "$work/energy.png")"
    ;;
  render)
    run
    pv=/usr/bin/pvpython
    [ -x "$pv" ] && command -v xvfb-run > /dev/null || fail "pvpython or xvfb-run missing: install paraview python3-paraview xvfb xauth (scripts/install_deps.sh)"
    "$pv" "$root/postprocess/render.py" --help | grep -q -- "--view" || fail "render.py --help"
    for view in front side; do
      PVPYTHON=$pv bash "$root/postprocess/pvpython_xvfb.sh" "$root/postprocess/render.py" "$work/run/hanging_sheet.xdmf" --frame -1 --view "$view" \
        --size 320x240 --out "$work/render_$view.png" > "$work/render_$view.log" 2>&1
      grep -q "render.py: " "$work/render_$view.log" || { cat "$work/render_$view.log"; fail "render.py --view $view"; }
      grep -q "t = 0.1 s (frame 4 of 5), 81 points, 64 cells" "$work/render_$view.log" || { cat "$work/render_$view.log"; fail "render.py drew the wrong frame or mesh"; }
      [ "$(png_size "$work/render_$view.png")" = "320 240" ] || fail "render_$view.png is $(png_size "$work/render_$view.png"), expected 320 240"
    done
    # Not all white: the sheet is in the picture.
    $py - "$work/render_front.png" <<'PY' || fail "render_front.png is blank"
import sys, matplotlib.image as im
a = im.imread(sys.argv[1])
frac = (a[..., :3].min(axis=2) < 0.9).mean()
assert frac > 0.02, f"only {frac:.3f} of the pixels are not white"
print(f"render.py: 320x240 PNGs, {frac:.2f} of the front view drawn")
PY
    ;;
  movie)
    run
    command -v ffprobe > /dev/null || fail "ffprobe missing: install ffmpeg (scripts/install_deps.sh)"
    $py "$root/postprocess/movie.py" --help | grep -q -- "--frames" || fail "movie.py --help"
    # All 5 frames of the series (asked for 60: a series with fewer gives them all), 320x240.
    $py "$root/postprocess/movie.py" "$work/run/hanging_sheet.xdmf" --out "$work/movie.mp4" --frames 60 --size 320x240 \
      --view front > "$work/movie.log" 2>&1 || { cat "$work/movie.log"; fail "movie.py"; }
    cat "$work/movie.log"
    got=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames,width,height -of csv=p=0 "$work/movie.mp4")
    [ "$got" = "320,240,5" ] || fail "movie.mp4: width,height,frames = $got, expected 320,240,5"
    # Stills: shaded as cloth and coloured by the strain map; each draws the sheet (not the empty white
    # image), and the two differ (the map is not the cloth colour).
    for colour in fabric strain; do
      PVPYTHON=/usr/bin/pvpython bash "$root/postprocess/pvpython_xvfb.sh" "$root/postprocess/render.py" "$work/run/hanging_sheet.xdmf" \
        --frame -1 --view iso --color-by $colour --size 320x240 --no-label --out "$work/still_$colour.png" > "$work/still_$colour.log" 2>&1
      [ -f "$work/still_$colour.png" ] || { cat "$work/still_$colour.log"; fail "render.py --color-by $colour"; }
    done
    $py - "$work/still_fabric.png" "$work/still_strain.png" <<'PY' || fail "the stills are blank or alike"
import sys, matplotlib.image as im
a, b = (im.imread(path)[..., :3] for path in sys.argv[1:3])
drawn = [float((x.min(axis=2) < 0.9).mean()) for x in (a, b)]
assert min(drawn) > 0.02, f"fractions of pixels drawn (not white) {drawn}: an empty image"
differ = float((abs(a - b).max(axis=2) > 0.1).mean())
assert differ > 0.02, f"the cloth and strain renders differ on only {differ:.3f} of the pixels"
print(f"render.py: stills draw {drawn[0]:.2f} and {drawn[1]:.2f} of the view, differ on {differ:.2f} of it")
PY
    ;;
  scaling)
    $py "$root/jobs/scaling.py" --help | grep -q "strong" || fail "scaling.py --help"
    $py "$root/jobs/scaling.py" --ranks 1 2 --strong-grid 9 --strong-steps 5 --weak-particles 40 --weak-steps 5 \
      --clothsim "$CLOTHSIM" --cores 1 --out "$work/scaling" > "$work/scaling.log" 2>&1 || { cat "$work/scaling.log"; fail "scaling.py"; }
    $py - "$work/scaling/scaling.csv" <<'PY' || fail "scaling.csv"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
got = [(r["study"], int(r["ranks"]), int(r["grid"]), r["oversubscribed"]) for r in rows]
assert got == [("strong", 1, 9, "no"), ("strong", 2, 9, "yes"), ("weak", 1, 7, "no"), ("weak", 2, 9, "yes")], got
for r in rows:
    assert int(r["steps"]) == 5 and float(r["time_per_step_s"]) > 0 and float(r["krylov_per_step"]) > 0, r
    if r["ranks"] == "1":
        assert float(r["speedup"]) == 1.0 and float(r["efficiency"]) == 1.0, r
print("scaling.py: 4 cases, table complete")
PY
    [ -s "$work/scaling/scaling.png" ] || fail "no scaling.png"
    ;;
  *) fail "unknown part $part" ;;
  esac
done
echo PASS

#!/usr/bin/python3
"""An MP4 movie of a clothsim XDMF series: postprocess/render.py draws the frames with ParaView (pvpython under a
virtual X server, one process for all of them, one camera), Debian's ffmpeg encodes them (H.264, yuv420p, which
every player takes).

  /usr/bin/python3 postprocess/movie.py output/dress/dress.xdmf --out output/dress/dress.mp4
  /usr/bin/python3 postprocess/movie.py OUT.xdmf --out strain.mp4 --frames 30 --color-by strain --range 0 0.05

--frames N draws N frames spread evenly over the series (over its frames up to --t-max; all of them when
there are no more), shown at --fps
frames per second; --view, --color-by, --range and --zoom go to render.py (see its --help). Prints the
frames drawn and the wall time of each stage. Needs pvpython, xvfb-run and ffmpeg (scripts/install_deps.sh).
"""
import argparse
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("xdmf", help="NAME.xdmf written by clothsim")
    p.add_argument("--out", required=True, help="the MP4 to write")
    p.add_argument("--frames", type=int, default=60, help="frames of the movie (default 60)")
    p.add_argument("--fps", type=int, default=12, help="frames per second (default 12)")
    p.add_argument("--size", default="640x480", help="WIDTHxHEIGHT, both even (default 640x480)")
    p.add_argument("--view", default="iso", help="render.py camera (default iso)")
    p.add_argument("--color-by", default="fabric", help="render.py fabric colouring (default fabric: shaded as cloth)")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"), help="render.py colour range of a fit map")
    p.add_argument("--zoom", type=float, default=1.0, help="render.py camera zoom (default 1)")
    p.add_argument("--t-max", type=float, help="only the frames up to this time, s (default: all)")
    args = p.parse_args(argv)
    try:
        w, h = (int(v) for v in args.size.lower().split("x"))
        assert w > 0 and h > 0 and w % 2 == 0 and h % 2 == 0
    except (ValueError, AssertionError):
        p.error(f"--size must be WIDTHxHEIGHT with both even (H.264 in yuv420p), e.g. 640x480, got {args.size}")
    if args.frames < 1 or args.fps < 1:
        p.error("--frames and --fps must be at least 1")
    for tool in ("xvfb-run", "ffmpeg"):
        if shutil.which(tool) is None:
            p.error(f"{tool} is missing: bash scripts/install_deps.sh installs it")
    if not os.path.exists(args.xdmf):
        p.error(f"{args.xdmf} not found")
    return args


def render_frames(args, folder):
    """Runs render.py --sequence under a virtual X server of its own (pvpython_xvfb.sh)."""
    command = ["bash", os.path.join(HERE, "pvpython_xvfb.sh"), os.path.join(HERE, "render.py"), args.xdmf,
               "--sequence", str(args.frames), "--out", os.path.join(folder, "frame_%04d.png"), "--size", args.size,
               "--view", args.view, "--color-by", args.color_by, "--zoom", str(args.zoom)]
    if args.range:
        command += ["--range"] + [str(v) for v in args.range]
    if args.t_max is not None:
        command += ["--t-max", str(args.t_max)]
    run = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"movie.py: render.py failed:\n{run.stdout}{run.stderr}")
    return sorted(glob.glob(os.path.join(folder, "frame_*.png")))


def main(argv):
    args = parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="clothsim_movie_") as folder:
        start = time.time()
        frames = render_frames(args, folder)
        rendered = time.time()
        encode = ["ffmpeg", "-y", "-loglevel", "error", "-framerate", str(args.fps), "-i", os.path.join(folder, "frame_%04d.png"),
                  "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "23", args.out]
        run = subprocess.run(encode, stdin=subprocess.DEVNULL, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"movie.py: ffmpeg failed:\n{run.stderr}")
        done = time.time()
    print(f"movie.py: {args.out}: {len(frames)} frames at {args.fps} fps, {args.size}, view {args.view}, "
          f"colour {args.color_by}; rendering {rendered - start:.1f} s, encoding {done - rendered:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])

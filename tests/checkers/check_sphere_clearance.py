"""Checks a sphere drape series: at every frame of NAME.h5, no particle is closer to the sphere's centre
than radius + thickness - tolerance, and none is below the ground plane y = ground + thickness - tolerance.

  /usr/bin/python3 tests/checkers/check_sphere_clearance.py SERIES.h5 --center X Y Z --radius R --thickness T
      --tolerance TOL [--ground Y] --min-frames N
Prints the smallest clearance found (distance - radius - thickness; negative means inside the offset
surface) and exits non-zero when a frame violates the tolerance."""
import argparse
import sys

import h5py
import numpy as np

parser = argparse.ArgumentParser()
parser.add_argument("h5")
parser.add_argument("--center", type=float, nargs=3, required=True)
parser.add_argument("--radius", type=float, required=True)
parser.add_argument("--thickness", type=float, required=True)
parser.add_argument("--tolerance", type=float, required=True)
parser.add_argument("--ground", type=float, default=None)
parser.add_argument("--min-frames", type=int, required=True)
args = parser.parse_args()

worst_sphere, worst_ground, where = np.inf, np.inf, None
with h5py.File(args.h5, "r") as f:
    frames = sorted(f["frames"].keys())
    if len(frames) < args.min_frames:
        sys.exit(f"check_sphere_clearance: FAILED: {len(frames)} frames, expected at least {args.min_frames}")
    for name in frames:
        x = f["frames"][name]["position"][...].reshape(-1, 3)
        clearance = np.linalg.norm(x - np.array(args.center), axis=1) - args.radius - args.thickness
        if clearance.min() < worst_sphere:
            worst_sphere, where = clearance.min(), name
        if args.ground is not None:
            worst_ground = min(worst_ground, (x[:, 1] - args.ground - args.thickness).min())
print(f"{len(frames)} frames; smallest sphere clearance {worst_sphere:.3e} m (frame {where}); smallest ground clearance {worst_ground:.3e} m; tolerance {args.tolerance:g} m")
if worst_sphere < -args.tolerance or worst_ground < -args.tolerance:
    sys.exit("check_sphere_clearance: FAILED: a particle is inside the offset surface by more than the tolerance")

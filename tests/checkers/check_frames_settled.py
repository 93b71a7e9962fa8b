#!/usr/bin/python3
"""Checks that a garment stays settled between its checkpoints: no transient in any frame of a series.

  check_frames_settled.py SERIES.h5 --from T [--max-speed V] [--max-strain S]

For every frame at time >= T: the fastest particle moves at most V m/s and the largest link strain of the
frame's strain field is at most S. garment_quality.py checks the final state only; a strap kicked now and then
between frames of a settling garment (docs/collisions.md, "Stops, not reversals") passes that check and fails
this one. Prints the worst frame of each measure; exits non-zero with a message when a bound is exceeded.
"""
import argparse
import sys

import h5py
import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("series")
    parser.add_argument("--from", dest="start", type=float, required=True, help="first simulated time checked, s")
    parser.add_argument("--max-speed", type=float, default=0.5, help="m/s")
    parser.add_argument("--max-strain", type=float, default=0.10)
    args = parser.parse_args()
    worst_speed, worst_strain, checked = (0.0, None), (0.0, None), 0
    with h5py.File(args.series, "r") as f:
        for name, frame in f["frames"].items():
            t = float(frame.attrs["time"])
            if t < args.start - 1e-12:
                continue
            checked += 1
            speed = float(np.max(np.linalg.norm(frame["velocity"][:], axis=1)))
            strain = float(np.max(frame["strain"][:]))
            if speed > worst_speed[0]:
                worst_speed = (speed, t)
            if strain > worst_strain[0]:
                worst_strain = (strain, t)
    if checked == 0:
        sys.exit(f"FAIL: {args.series} has no frame at t >= {args.start} s")
    print(f"{checked} frames from t = {args.start} s: fastest particle {worst_speed[0]:.4g} m/s (t = {worst_speed[1]} s), "
          f"largest strain {worst_strain[0]:.4g} (t = {worst_strain[1]} s)")
    failed = []
    if worst_speed[0] > args.max_speed:
        failed.append(f"a particle moved at {worst_speed[0]:.4g} m/s at t = {worst_speed[1]} s (allowed {args.max_speed})")
    if worst_strain[0] > args.max_strain:
        failed.append(f"a link strained {worst_strain[0]:.4g} at t = {worst_strain[1]} s (allowed {args.max_strain})")
    if failed:
        sys.exit("FAIL: " + "; ".join(failed))
    print("PASS")


if __name__ == "__main__":
    main()

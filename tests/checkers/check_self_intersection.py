"""Checks that the fabric never passes through itself: at every frame of an XDMF/HDF5 series written by
clothsim, no fabric edge crosses a fabric triangle.

  /usr/bin/python3 tests/checkers/check_self_intersection.py OUTPUT.h5 --min-frames K

The edge-triangle test is postprocess/fabric_crossings.py's (the one postprocess/garment_quality.py uses).
Prints per-frame counts; exits non-zero on any crossing or on fewer than K frames."""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postprocess"))
from fabric_crossings import crossings, primitives  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("h5")
    parser.add_argument("--min-frames", type=int, required=True)
    args = parser.parse_args()
    with h5py.File(args.h5, "r") as f:
        quads = f["topology/quads"][...].astype(np.int64)
        tris, edges = primitives(quads)
        names = sorted(f["frames"].keys(), key=int)
        total = 0
        for name in names:
            x = f["frames"][name]["position"][...]
            n, examples = crossings(x, tris, edges)
            total += n
            if n:
                print(f"frame {name}: {n} edge-triangle crossings, e.g. (edge, triangle) {examples}")
    print(f"{len(names)} frames, {len(tris)} triangles, {len(edges)} edges: {total} edge-triangle crossings")
    if len(names) < args.min_frames:
        sys.exit(f"check_self_intersection: FAILED: only {len(names)} frames (expected at least {args.min_frames})")
    if total:
        sys.exit("check_self_intersection: FAILED: the fabric passes through itself")


if __name__ == "__main__":
    main()

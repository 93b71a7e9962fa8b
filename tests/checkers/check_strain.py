#!/usr/bin/python3
"""Recomputes the strain field of a series of a one-piece square sheet by brute force and compares.

  check_strain.py SERIES.h5 --grid N --side L [--atol 1e-12]

For every frame: the strain of particle (i, j) (index j N + i) must be the largest
(|x_k - x_p| - h) / h over its grid neighbours k = (i +- 1, j), (i, j +- 1), h = L / (N - 1) the rest
length of the stretch links of a flat square sheet, within --atol. Checks the distributed evaluation
(links on the rank of their lowest particle, MAX over ghosts, scatter to natural order) against
numpy. Exits non-zero with a message on the first failed check.
"""
import argparse
import sys

import h5py
import numpy as np


def brute_force_strain(position, n, h):
    x = position.reshape(n, n, 3)  # [j, i, component]
    strain = np.full((n, n), -np.inf)
    for axis in (0, 1):
        length = np.linalg.norm(np.diff(x, axis=axis), axis=2)
        s = (length - h) / h
        lo = [slice(None), slice(None)]
        hi = [slice(None), slice(None)]
        lo[axis], hi[axis] = slice(0, n - 1), slice(1, n)
        strain[tuple(lo)] = np.maximum(strain[tuple(lo)], s)
        strain[tuple(hi)] = np.maximum(strain[tuple(hi)], s)
    return strain.reshape(-1, 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("series")
    parser.add_argument("--grid", type=int, required=True)
    parser.add_argument("--side", type=float, required=True)
    parser.add_argument("--atol", type=float, default=1e-12)
    args = parser.parse_args()
    h = args.side / (args.grid - 1)
    worst, largest = 0.0, 0.0
    with h5py.File(args.series, "r") as f:
        for name, frame in sorted(f["frames"].items()):
            expected = brute_force_strain(frame["position"][...], args.grid, h)
            found = frame["strain"][...]
            if found.shape != expected.shape:
                print(f"check_strain: FAILED: /frames/{name}/strain has shape {found.shape}, expected {expected.shape}")
                sys.exit(1)
            diff = float(np.abs(found - expected).max())
            worst, largest = max(worst, diff), max(largest, float(expected.max()))
            if not diff <= args.atol:
                print(f"check_strain: FAILED: /frames/{name}/strain differs from the brute force by {diff:.3e} (tolerance {args.atol:.1e})")
                sys.exit(1)
        print(f"check_strain: {len(f['frames'])} frames, strain within {worst:.3e} of the brute force (largest strain {largest:.4f})")


if __name__ == "__main__":
    main()

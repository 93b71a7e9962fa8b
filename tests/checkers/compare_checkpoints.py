"""Compares the final states of two runs of the same scene (e.g. on 1 and on 2 ranks).

  /usr/bin/python3 tests/checkers/compare_checkpoints.py A.h5 B.h5 --tolerance TOL
Both checkpoints hold /state/position and /state/velocity in global particle order; passes when the step is
the same and the largest position difference is at most TOL metres. Prints the largest differences."""
import argparse
import sys

import h5py
import numpy as np

parser = argparse.ArgumentParser()
parser.add_argument("a")
parser.add_argument("b")
parser.add_argument("--tolerance", type=float, required=True)
args = parser.parse_args()

with h5py.File(args.a, "r") as fa, h5py.File(args.b, "r") as fb:
    step_a, step_b = int(fa["state"].attrs["step"]), int(fb["state"].attrs["step"])
    xa, xb = fa["state/position"][...], fb["state/position"][...]
    va, vb = fa["state/velocity"][...], fb["state/velocity"][...]
if step_a != step_b or xa.shape != xb.shape:
    sys.exit(f"compare_checkpoints: FAILED: step {step_a} vs {step_b}, shape {xa.shape} vs {xb.shape}")
dx = np.abs(xa - xb).max()
dv = np.abs(va - vb).max()
print(f"step {step_a}: largest position difference {dx:.3e} m, velocity difference {dv:.3e} m/s (tolerance {args.tolerance:g} m)")
if not dx <= args.tolerance:
    sys.exit("compare_checkpoints: FAILED: the runs differ by more than the tolerance")

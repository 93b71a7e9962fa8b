#!/usr/bin/python3
"""Checks a clothsim final checkpoint against the layout of docs/checkpoint.md, with h5py.

  check_final_checkpoint.py FILE --particles N --step S --time T [--pins I,J,...] [--compare OTHER --atol A]

/state/position and /state/velocity: shape (N, 3), float64, finite; attributes step (int64) and
time (float64) on /state. --pins: particles (global order) that must still sit where they started,
bit for bit (pins are constraints). --compare: a checkpoint of the same run on another number of
ranks; positions must agree within --atol metres (the Krylov tolerance makes them differ slightly).
"""
import argparse
import sys

import h5py
import numpy as np


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read_state(path):
    with h5py.File(path, "r") as f:
        if "state" not in f:
            fail(f"{path} has no /state group")
        state = f["state"]
        for name in ("position", "velocity"):
            if name not in state:
                fail(f"{path} lacks /state/{name}")
        position, velocity = state["position"], state["velocity"]
        info = {
            "position_dtype": position.dtype,
            "velocity_dtype": velocity.dtype,
            "position": position[()],
            "velocity": velocity[()],
            "attrs": {k: state.attrs[k] for k in ("step", "time") if k in state.attrs},
            "step_dtype": state.attrs["step"].dtype if "step" in state.attrs else None,
        }
    return info


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("file")
    parser.add_argument("--particles", type=int, required=True)
    parser.add_argument("--step", type=int, required=True)
    parser.add_argument("--time", type=float, required=True)
    parser.add_argument("--pins", default="")
    parser.add_argument("--pin-positions", default="", help="x,y,z;x,y,z;... start positions of --pins")
    parser.add_argument("--compare")
    parser.add_argument("--atol", type=float, default=1e-6)
    args = parser.parse_args()

    s = read_state(args.file)
    for name in ("position", "velocity"):
        a = s[name]
        if a.shape != (args.particles, 3):
            fail(f"/state/{name} has shape {a.shape}, expected ({args.particles}, 3)")
        if s[name + "_dtype"] != np.float64:
            fail(f"/state/{name} is {s[name + '_dtype']}, expected float64")
        if not np.all(np.isfinite(a)):
            fail(f"/state/{name} has non-finite values")
    if "step" not in s["attrs"] or "time" not in s["attrs"]:
        fail(f"/state lacks the step or time attribute (has {sorted(s['attrs'])})")
    if s["step_dtype"] != np.int64:
        fail(f"/state step attribute is {s['step_dtype']}, expected int64")
    step, time = int(s["attrs"]["step"]), float(s["attrs"]["time"])
    if step != args.step:
        fail(f"step attribute {step}, expected {args.step}")
    if abs(time - args.time) > 1e-12 * max(1.0, abs(args.time)):
        fail(f"time attribute {time!r}, expected {args.time!r} (tolerance 1e-12)")

    if args.pins:
        pins = [int(i) for i in args.pins.split(",")]
        starts = [[float(c) for c in p.split(",")] for p in args.pin_positions.split(";")]
        for i, start in zip(pins, starts):
            if not np.array_equal(s["position"][i], np.array(start)):
                fail(f"pinned particle {i} moved: {s['position'][i]} instead of {start}")
            if np.any(s["velocity"][i] != 0.0):
                fail(f"pinned particle {i} has velocity {s['velocity'][i]}")

    if args.compare:
        other = read_state(args.compare)["position"]
        if other.shape != s["position"].shape:
            fail(f"{args.compare} has shape {other.shape}, {args.file} {s['position'].shape}")
        diff = float(np.max(np.abs(other - s["position"])))
        if diff > args.atol:
            fail(f"positions differ from {args.compare} by up to {diff:.3e} m (tolerance {args.atol:g} m)")
        print(f"positions agree with {args.compare} within {diff:.3e} m (tolerance {args.atol:g} m)")

    print(f"PASS: {args.file}: position/velocity ({args.particles}, 3) float64, step {step}, time {time:.6f} s, "
          f"lowest y {s['position'][:, 1].min():.6f} m")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Compares a restarted run with an uninterrupted one: their checkpoints and output series, with h5py.

  compare_restart.py A.h5 B.h5 [--atol-position X --atol-velocity V] [--series SA.h5 SB.h5]

Checks that the /state attributes step, time, dt, integrator, scene_fingerprint and nparticles are
equal and that /state/position, /state/velocity (and /state/implicit_dv, contact_normal, seams_sewn,
bend_slider, shear_slider, bdf2_history_rate and bdf2_history_velocity when A has them, and the attribute
history_dt) are equal:
bit for bit by default (a restart on the same ranks), or within the given absolute tolerances
(another rank count; implicit_dv, a solver iterate, is then not compared). With --series, the two
XDMF series files must hold the same frames (steps and times) with bit-identical datasets.
Prints the largest differences found; exits non-zero with a message on the first failed check.
"""
import argparse
import sys

import h5py
import numpy as np


def fail(message):
    print("compare_restart: FAILED: " + message)
    sys.exit(1)


def differences(a, b, name):
    if a.shape != b.shape or a.dtype != b.dtype:
        fail(f"{name}: {a.dtype} {a.shape} against {b.dtype} {b.shape}")
    identical = np.array_equal(a.view(np.uint8), b.view(np.uint8))
    return identical, float(np.abs(a - b).max()) if a.size else 0.0


def compare_checkpoints(path_a, path_b, atol):
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        sa, sb = fa["state"], fb["state"]
        for key in ("step", "time", "dt", "integrator", "scene_fingerprint", "nparticles"):
            if sa.attrs[key] != sb.attrs[key]:
                fail(f"/state attribute {key}: {sa.attrs[key]!r} in {path_a}, {sb.attrs[key]!r} in {path_b}")
        names = ["position", "velocity"]
        if atol is None:
            names += [name for name in ("implicit_dv", "contact_normal", "seams_sewn", "bend_slider", "shear_slider",
                                        "bdf2_history_rate", "bdf2_history_velocity") if name in sa]
            if sa.attrs.get("history_dt") != sb.attrs.get("history_dt"):
                fail(f"/state attribute history_dt: {sa.attrs.get('history_dt')!r} in {path_a}, {sb.attrs.get('history_dt')!r} in {path_b}")
        for name in names:
            if name not in sb:
                fail(f"{path_b} lacks /state/{name}")
            identical, diff = differences(sa[name][...], sb[name][...], name)
            print(f"/state/{name}: {'bit-identical' if identical else f'max |difference| {diff:.3e}'}")
            if atol is None and not identical:
                fail(f"/state/{name} differs between {path_a} and {path_b} (max {diff:.3e}); expected bit-identical")
            if atol is not None and not diff <= atol[name]:
                fail(f"/state/{name} differs by {diff:.3e} between {path_a} and {path_b}; tolerance {atol[name]:.1e}")


def frames(f):
    return {name: (int(g.attrs["step"]), float(g.attrs["time"])) for name, g in f["frames"].items()}


def compare_series(path_a, path_b):
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        if frames(fa) != frames(fb):
            fail(f"frames differ: {sorted(frames(fa).values())} in {path_a}, {sorted(frames(fb).values())} in {path_b}")
        for name in fa["frames"]:
            ga, gb = fa["frames"][name], fb["frames"][name]
            if sorted(ga) != sorted(gb):
                fail(f"frame {name}: datasets {sorted(ga)} in {path_a}, {sorted(gb)} in {path_b}")
            for dataset in ga:
                identical, diff = differences(ga[dataset][...], gb[dataset][...], f"{name}/{dataset}")
                if not identical:
                    fail(f"/frames/{name}/{dataset} differs (max {diff:.3e}) between {path_a} and {path_b}")
        print(f"series: {len(fa['frames'])} frames, steps, times and datasets bit-identical")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--atol-position", type=float, help="tolerance on positions, m (default: bit-identical)")
    parser.add_argument("--atol-velocity", type=float, help="tolerance on velocities, m/s")
    parser.add_argument("--series", nargs=2, metavar=("SA", "SB"), help="output series (NAME.h5) to compare frame by frame")
    args = parser.parse_args()
    atol = None
    if args.atol_position is not None:
        atol = {"position": args.atol_position, "velocity": args.atol_velocity}
    compare_checkpoints(args.a, args.b, atol)
    if args.series:
        compare_series(*args.series)


if __name__ == "__main__":
    main()

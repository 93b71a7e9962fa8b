#!/usr/bin/python3
"""Hem height and fold count of a skirt: the numbers that say whether a fine garment converged.

  /usr/bin/python3 postprocess/hem_folds.py OUTPUT.h5|checkpoint.h5 --scene SCENE.yaml [--pieces skirt_front,skirt_back]
         [--depth 0.01] [--json OUT.json]
  /usr/bin/python3 postprocess/hem_folds.py --self-test

The hem is the bottom row (j = 0) of the skirt pieces, joined in scene order into one closed chain (a skirt's
panels follow each other around the body, each running the same way, as input/dress_fitted.yaml's do). Heights
are along -gravity. Folds are counted in the plane normal to gravity, where the hem of a skirt falling in folds
is a wavy closed curve: its radius about its centroid waves. The smooth part of the radius (Fourier modes 0 to 2 of radius against
angle: the hem's mean size and an oval, as the hips are not round) is removed, and the fold count is the number
of peaks of what remains, along the hem, whose prominence (a crest's height above the higher of the troughs that
separate it from a higher crest) exceeds --depth (default 1 cm): shallower crests merge into a fold, and an oval
hem without folds has none. The count depends
on the cloth's shape, not on the particle spacing, so long as the spacing resolves a fold; a hem with more
folds than it has 4 particles per fold is under-resolved.

Prints and (--json) writes: hem_particles, hem_height_mean, hem_height_min, hem_height_max (m), folds, and
fold_depths (the folds' prominences, m, largest first).
--self-test: synthetic hems r(phi) = R (1 + e cos 2 phi) + A cos(k phi) with known k, an oval (e) and
sub-threshold noise, sampled at coarse to fine spacings: the count must be k for every one, 0 for an oval
without folds and for ripples shallower than --depth; exit 1 otherwise."""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def peak_prominences(values):
    """Topographic prominences of the local maxima of a cyclic sequence: a peak's height above the higher of
    the two lowest points that separate it from a higher peak on either side (the highest: above the lowest)."""
    n = len(values)
    start = int(np.argmax(values))
    v = np.roll(values, -start)
    out = []
    for i in range(n):
        if not (v[i] > v[i - 1] and v[i] >= v[(i + 1) % n]):
            continue
        if i == 0:
            out.append(float(v[0] - v.min()))
            continue
        left = v[:i + 1]
        higher = np.nonzero(left[:-1] > v[i])[0]
        left_min = left[higher[-1]:].min()
        right = np.append(v[i:], v[0])
        higher = np.nonzero(right[1:] > v[i])[0]
        right_min = right[:higher[0] + 2].min()
        out.append(float(v[i] - max(left_min, right_min)))
    return out


def count_folds(chain, depth):
    """Folds of a closed 2-D chain (M, 2): the peaks of its radius about its centroid, less the radius's smooth
    part (the Fourier modes 0 to 2 of radius against angle: a round or oval hem without folds), whose
    prominence exceeds depth; and those prominences, largest first."""
    d = chain - chain.mean(axis=0)
    phi = np.arctan2(d[:, 1], d[:, 0])
    r = np.hypot(d[:, 0], d[:, 1])
    modes = np.column_stack([np.ones_like(phi), np.cos(phi), np.sin(phi), np.cos(2 * phi), np.sin(2 * phi)])
    residual = r - modes @ np.linalg.lstsq(modes, r, rcond=None)[0]
    deep = sorted((p for p in peak_prominences(residual) if p > depth), reverse=True)
    return len(deep), deep


def hem_chain(positions, scene, pieces):
    """The hem particles (M, 3): row j = 0 of each named piece, in scene order."""
    import cloth_state
    grids = {name: (nu, nv, offset) for name, nu, nv, offset in cloth_state.piece_grids(scene)}
    rows = []
    for name in pieces:
        if name not in grids:
            sys.exit(f"hem_folds: piece '{name}' is not in the scene (pieces: {', '.join(grids)})")
        nu, nv, offset = grids[name]
        rows.append(cloth_state.piece_positions(positions, nu, nv, offset)[0])
    return np.vstack(rows)


def measure(hem, gravity, depth):
    """Hem height (along -gravity) and folds (in the plane normal to gravity) of hem points (M, 3)."""
    g = np.asarray(gravity, dtype=float)
    g /= np.linalg.norm(g)
    helper = np.array([1.0, 0, 0]) if abs(g[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(g, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(g, e1)
    height = -hem @ g
    folds, deep = count_folds(np.column_stack([hem @ e1, hem @ e2]), depth)
    return {"hem_particles": int(len(hem)), "hem_height_mean": round(float(height.mean()), 5),
            "hem_height_min": round(float(height.min()), 5), "hem_height_max": round(float(height.max()), 5),
            "folds": folds, "fold_depths": [round(d, 4) for d in deep]}


def synthetic_hem(samples, folds, amplitude, oval=0.15, radius=0.4, noise=0.0, seed=0):
    """A closed hem of `samples` points: r = radius (1 + oval cos 2 phi) + amplitude cos(folds phi + phase),
    with uneven spacing and noise of the given size, in the horizontal plane of a y-up scene."""
    rng = np.random.default_rng(seed)
    phi = (np.arange(samples) + rng.uniform(-0.3, 0.3, samples)) * 2 * math.pi / samples  # evenly, jittered
    r = radius * (1 + oval * np.cos(2 * phi)) + amplitude * np.cos(folds * phi + rng.uniform(0, 2 * math.pi))
    r += noise * rng.uniform(-1, 1, samples)
    return np.column_stack([r * np.cos(phi), np.full(samples, -0.3), r * np.sin(phi)])


def self_test(depth):
    cases = []
    for k in (5, 8, 12):
        for samples in (4 * k, 100, 200, 800):  # 4 samples per fold (coarse) to 160 (fine)
            cases.append((f"{k} folds of 2 cm, {samples} samples", synthetic_hem(samples, k, 0.02, noise=0.1 * depth, seed=samples + k), k))
    cases.append(("an oval without folds, 400 samples", synthetic_hem(400, 8, 0.0, oval=0.2, noise=0.1 * depth), 0))
    cases.append(("ripples of 0.2 depth, 400 samples", synthetic_hem(400, 30, 0.1 * depth), 0))
    failed = 0
    for name, hem, expected in cases:
        got = measure(hem, [0, -9.81, 0], depth)["folds"]
        ok = got == expected
        failed += not ok
        print(f"hem_folds self-test: {name}: {got} folds, expected {expected}: {'ok' if ok else 'FAIL'}")
    print(f"hem_folds self-test: {len(cases) - failed} passed, {failed} failed")
    return failed == 0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("state", nargs="?", help="a checkpoint, or an output series NAME.h5 / NAME.xdmf (its last frame)")
    parser.add_argument("--scene", help="the run's scene (piece grids, gravity)")
    parser.add_argument("--pieces", default="skirt_front,skirt_back", help="the skirt pieces, comma-separated, in the hem's order")
    parser.add_argument("--depth", type=float, default=0.01, help="a fold's least prominence (crest above trough, radially), m (default 0.01)")
    parser.add_argument("--time", type=float, help="of a series: the frame nearest this time, s (default: the last frame)")
    parser.add_argument("--json", help="also write the numbers to this JSON file")
    parser.add_argument("--self-test", action="store_true", help="check the fold count on synthetic hems")
    args = parser.parse_args()
    if args.depth <= 0:
        parser.error(f"--depth must be > 0 m, got {args.depth}")
    if args.self_test:
        sys.exit(0 if self_test(args.depth) else 1)
    if not args.state or not args.scene:
        parser.error("give a checkpoint or series and --scene (or --self-test)")
    import cloth_state
    path = cloth_state.series_h5(args.state) if args.state.endswith(".xdmf") else args.state
    scene = cloth_state.read_scene(args.scene)
    if args.time is not None:
        frames = cloth_state.read_series(path, datasets=("position",))[0]
        frame = min(frames, key=lambda f: abs(f["time"] - args.time))
        positions, when = frame["position"], frame["time"]
    else:
        positions, when = cloth_state.read_positions(path), None
    hem = hem_chain(positions, scene, args.pieces.split(","))
    result = measure(hem, scene.get("gravity", [0, -9.81, 0]), args.depth)
    if when is not None:
        result["time"] = when
        path += f" at t = {when:g} s"
    print(f"hem_folds: {path}: {result['hem_particles']} hem particles, height mean {result['hem_height_mean']:.4f} m, "
          f"min {result['hem_height_min']:.4f} m; {result['folds']} folds deeper than {args.depth * 1000:.0f} mm "
          f"(depths {', '.join(f'{d * 1000:.0f}' for d in result['fold_depths'])} mm)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()

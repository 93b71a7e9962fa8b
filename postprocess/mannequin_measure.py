#!/usr/bin/python3
"""The mannequin's body measurements from its mesh, as a pattern maker takes them with a tape.

  /usr/bin/python3 postprocess/mannequin_measure.py [input/mannequin/makehuman_body.obj] [--scale 0.1] [--json]

The mesh is cut by horizontal planes (y up) every 5 mm; at each height the section's closed loops are joined
from the cut edges of the faces, and the torso is the loop around the body's middle axis (x = 0, the arms and
legs are other loops or lie beside it). A tape measure bridges the hollows, so a girth is the perimeter of the
torso loop's convex hull. Reported, in metres of the scene frame (the mesh times --scale):
  bust   the largest girth between the armpits and the shoulders' foot (bust_y, its height)
  waist  the smallest girth between the bust and the hips (waist_y)
  hips   the largest girth below the waist, above the crotch (hips_y)
  and at each of these heights the torso's front and back (its largest and smallest z), its half-width (largest
  |x|) and the centre of its hull (x, z): the pattern (jobs/dress_fitted_pattern.py) places and sizes pieces
  from them. The crotch is the highest section where the middle axis lies outside every loop (two legs)."""
import argparse
import json
import math
import sys

import numpy as np


def read_obj(path, scale):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:]])
    if not vertices or not faces:
        sys.exit(f"mannequin_measure: {path}: no vertices or faces (expected a Wavefront OBJ mesh)")
    return np.array(vertices) * scale, faces


def section_loops(vertices, faces, y):
    """The closed loops (lists of (x, z) points) where the plane at height y cuts the mesh."""
    edges = {}
    above = vertices[:, 1] > y
    for face in faces:
        cut = []
        for a, b in zip(face, face[1:] + face[:1]):
            if above[a] != above[b]:
                t = (y - vertices[a, 1]) / (vertices[b, 1] - vertices[a, 1])
                cut.append((min(a, b), max(a, b), vertices[a, [0, 2]] + t * (vertices[b, [0, 2]] - vertices[a, [0, 2]])))
        for k in range(0, len(cut) - 1, 2):  # a convex face is cut once; a quad can in principle be cut twice
            p, q = cut[k], cut[k + 1]
            edges.setdefault((p[0], p[1]), []).append(((q[0], q[1]), p[2], q[2]))
            edges.setdefault((q[0], q[1]), []).append(((p[0], p[1]), q[2], p[2]))
    loops, seen = [], set()
    for start in edges:
        if start in seen:
            continue
        loop, node, prev = [], start, None
        while node not in seen:
            seen.add(node)
            nxt = [e for e in edges[node] if e[0] != prev] or edges[node]
            loop.append(nxt[0][1])
            prev, node = node, nxt[0][0]
        if len(loop) >= 3:
            loops.append(np.array(loop))
    return loops


def inside(loop, x, z):
    """Whether (x, z) lies inside the closed polygon (even-odd rule)."""
    xs, zs = loop[:, 0], loop[:, 1]
    xn, zn = np.roll(xs, -1), np.roll(zs, -1)
    crosses = (zs > z) != (zn > z)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = xs + (z - zs) * (xn - xs) / (zn - zs)
    return bool(np.count_nonzero(crosses & (xc > x)) % 2)


def convex_hull(points):
    """Andrew's monotone chain, counter-clockwise."""
    pts = sorted(map(tuple, points))
    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1]) - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0]) <= 0:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def torso_section(vertices, faces, y):
    """The torso's hull at height y (the loop around x = 0), or None when x = 0 lies outside every loop."""
    loops = section_loops(vertices, faces, y)
    for loop in sorted(loops, key=lambda l: -len(l)):
        z_mid = 0.5 * (loop[:, 1].min() + loop[:, 1].max())
        if loop[:, 0].min() < 0 < loop[:, 0].max() and inside(loop, 0.0, z_mid):
            return convex_hull(loop)
    return None


def girth(hull):
    return float(np.sum(np.linalg.norm(hull - np.roll(hull, -1, axis=0), axis=1)))


def measure(vertices, faces, step=0.005):
    top = vertices[:, 1].max()
    heights = np.arange(top - 0.30, vertices[:, 1].min(), -step)  # from below the neck down
    sections = []
    for y in heights:
        hull = torso_section(vertices, faces, y)
        if hull is None:  # two legs: the crotch
            break
        sections.append((float(y), hull))
    if len(sections) < 20:
        sys.exit("mannequin_measure: found no torso (a loop around x = 0) below the neck")
    ys = np.array([s[0] for s in sections])
    g = np.array([girth(s[1]) for s in sections])
    width = np.array([np.abs(s[1][:, 0]).max() for s in sections])
    # the armpits: going down from the shoulders the arms leave the torso loop, which narrows abruptly
    drop = np.argmax(width[:-1] - width[1:] > 0.03) + 1 if np.any(width[:-1] - width[1:] > 0.03) else 0
    bust = drop + int(np.argmax(g[drop:drop + int(0.15 / step)]))
    below = np.arange(bust, len(g))
    hips = int(below[np.argmax(g[below] * (ys[below] < ys[bust] - 0.2))])
    waist = bust + int(np.argmin(g[bust:hips + 1]))
    out = {"crotch_y": round(float(ys[-1]) - step, 4)}
    for name, k in (("bust", bust), ("waist", waist), ("hips", hips)):
        hull = sections[k][1]
        out[name] = round(girth(hull), 4)
        out[name + "_y"] = round(float(ys[k]), 4)
        out[name + "_front_z"] = round(float(hull[:, 1].max()), 4)
        out[name + "_back_z"] = round(float(hull[:, 1].min()), 4)
        out[name + "_half_width"] = round(float(np.abs(hull[:, 0]).max()), 4)
        out[name + "_centre"] = [round(float(0.5 * (hull[:, 0].min() + hull[:, 0].max())), 4), round(float(0.5 * (hull[:, 1].min() + hull[:, 1].max())), 4)]
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mesh", nargs="?", default="input/mannequin/makehuman_body.obj")
    parser.add_argument("--scale", type=float, default=0.1, help="mesh units to metres (the scene's body scale)")
    parser.add_argument("--json", action="store_true", help="print the measurements as JSON")
    args = parser.parse_args()
    vertices, faces = read_obj(args.mesh, args.scale)
    m = measure(vertices, faces)
    if args.json:
        print(json.dumps(m, indent=1))
        return
    for name in ("bust", "waist", "hips"):
        print(f"{name:5s} girth {m[name]:.3f} m at y = {m[name + '_y']:.3f} m (front z = {m[name + '_front_z']:.3f}, "
              f"back z = {m[name + '_back_z']:.3f}, half-width {m[name + '_half_width']:.3f})")
    print(f"crotch at y = {m['crotch_y']:.3f} m")


if __name__ == "__main__":
    main()

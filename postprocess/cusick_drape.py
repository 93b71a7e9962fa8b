#!/usr/bin/python3
"""Drape coefficient of a Cusick drape test (BS 5058) from a clothsim checkpoint.

DC = (A_shadow - A_disc) / (A_specimen - A_disc), A_shadow the area of the fabric's vertical projection
(onto the plane normal to gravity), A_disc = pi r_support^2, A_specimen = pi r_specimen^2 (the flat
specimen). A_shadow is measured by rasterising every grid cell (two triangles) of the draped piece on a
fine pixel grid, which counts overlapping folds once; the shoelace area of the projected outer boundary
ring is printed too as a cross-check. A piece cut to a disc (cut_disc, a square grid) counts only its kept cells
(those whose centre lies in the disc, as src/pattern.c keeps them) and its outline is the kept cells' edge nodes.

    /usr/bin/python3 postprocess/cusick_drape.py output/cusick_drape/checkpoint_000400.h5 \\
        --scene input/cusick_drape.yaml [--grid N] [--json]
"""
import argparse
import json
import math
import sys

import numpy as np

import cloth_state


def triangle_raster_area(points2d, triangles, pixel):
    """Area covered by the union of 2D triangles, counted on a pixel grid of side `pixel` (m)."""
    lo = points2d.min(axis=0) - pixel
    hi = points2d.max(axis=0) + pixel
    shape = np.ceil((hi - lo) / pixel).astype(int)
    covered = np.zeros(shape, dtype=bool)
    for tri in triangles:
        a, b, c = points2d[tri]
        tmin = np.floor((np.minimum(np.minimum(a, b), c) - lo) / pixel).astype(int)
        tmax = np.ceil((np.maximum(np.maximum(a, b), c) - lo) / pixel).astype(int)
        xs = lo[0] + (np.arange(tmin[0], tmax[0]) + 0.5) * pixel
        ys = lo[1] + (np.arange(tmin[1], tmax[1]) + 0.5) * pixel
        px, py = np.meshgrid(xs, ys, indexing="ij")
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if det == 0:
            continue
        l1 = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / det
        l2 = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / det
        inside = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        covered[tmin[0]:tmax[0], tmin[1]:tmax[1]] |= inside
    return covered.sum() * pixel * pixel


def kept_cells(piece, nu, nv):
    """(nv - 1, nu - 1) booleans, [j, i] for cell (i, j): every cell, or for a rectangle cut to a disc (cut_disc) the
    cells whose centre lies within it (PatternCellKept in src/pattern.c)."""
    kept = np.ones((nv - 1, nu - 1), dtype=bool)
    cut = piece.get("cut_disc")
    if cut:
        if "size" not in piece:
            raise ValueError(f"piece '{piece.get('name', '')}': cut_disc is measured here on rectangles (size) only")
        su, sv = piece["size"]
        cu = (np.arange(nu - 1) + 0.5) * su / (nu - 1)
        cv = (np.arange(nv - 1) + 0.5) * sv / (nv - 1)
        kept = (cu[None, :] - cut["center"][0]) ** 2 + (cv[:, None] - cut["center"][1]) ** 2 <= cut["radius"] ** 2
    return kept


def grid_triangles(nu, nv, kept=None):
    """Two triangles per (kept) cell, in the piece's node numbering."""
    tris = []
    for j in range(nv - 1):
        for i in range(nu - 1):
            if kept is not None and not kept[j, i]:
                continue
            a, b, c, d = j * nu + i, j * nu + i + 1, (j + 1) * nu + i + 1, (j + 1) * nu + i
            tris += [(a, b, c), (a, c, d)]
    return np.array(tris)


def edge_nodes(kept):
    """Nodes of the kept cells' outline: corners of 1 to 3 kept cells (of a cut piece)."""
    nv, nu = kept.shape[0] + 1, kept.shape[1] + 1
    count = np.zeros((nv, nu), dtype=int)
    for dj in (0, 1):
        for di in (0, 1):
            count[dj:dj + nv - 1, di:di + nu - 1] += kept
    j, i = np.nonzero((count > 0) & (count < 4))
    return j * nu + i


def boundary_ring(nu, nv):
    """Indices of the outline, counter-clockwise: bottom, right, top reversed, left reversed."""
    ring = [i for i in range(nu)]
    ring += [j * nu + nu - 1 for j in range(1, nv)]
    ring += [(nv - 1) * nu + i for i in range(nu - 2, -1, -1)]
    ring += [j * nu for j in range(nv - 2, 0, -1)]
    return np.array(ring)


def shoelace(p):
    return 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))


def count_folds(ring2d, centre, prominence=2e-3):
    """Number of folds (drape 'nodes'): local maxima of the outline's distance from the centre, going round
    the outline, that stand at least `prominence` (m) above the lowest point within 1/16 turn either side."""
    d = ring2d - centre
    return count_profile_folds(np.hypot(d[:, 0], d[:, 1])[np.argsort(np.arctan2(d[:, 1], d[:, 0]))], prominence)


def count_cut_folds(ring2d, centre, flat_radius, support_radius, specimen_radius, prominence=2e-3):
    """count_folds for the staircase outline of a cut grid: each node's overhang beyond the support disc, in
    projection, scaled by the specimen's overhang over the node's flat one (the staircase's steps, up to a cell
    across, divide out: r -> r_s + (r - r_s) (R - r_s) / (r_flat - r_s)); nodes at one angle (an inner and an outer
    corner of a step) count once. The flat cut disc has 0 folds from 33 nodes on."""
    d = ring2d - centre
    theta = np.arctan2(d[:, 1], d[:, 0])
    r = support_radius + (np.hypot(d[:, 0], d[:, 1]) - support_radius) * (specimen_radius - support_radius) / (flat_radius - support_radius)
    _, first = np.unique(np.round(theta, 9), return_index=True)  # sorted by angle
    return count_profile_folds(r[first], prominence)


def count_profile_folds(r, prominence):
    """Folds of a closed radial profile r (in angle order): see count_folds."""
    n, near, wide = len(r), max(1, len(r) // 40), max(2, len(r) // 16)
    folds = 0
    for k in range(n):
        window = [r[(k + o) % n] for o in range(-near, near + 1)]
        around = [r[(k + o) % n] for o in range(-wide, wide + 1)]
        if r[k] == max(window) and r[k] > r[(k - 1) % n] - 1e-15 and r[k] - min(around) > prominence:
            folds += 1
    return folds


def measure(checkpoint, scene_path, grid=None, piece_index=0, support_radius=0.09, specimen_radius=0.15, pixel=5e-4):
    scene = cloth_state.read_scene(scene_path)
    x = cloth_state.read_positions(checkpoint)
    name, nu, nv, offset = cloth_state.piece_grids(scene, grid)[piece_index]
    piece = scene["pieces"][piece_index]
    p = x[offset:offset + nu * nv]
    e1, e2, _ = cloth_state.projection_basis(scene)
    p2 = np.stack([p @ e1, p @ e2], axis=1)
    kept = kept_cells(piece, nu, nv)
    a_shadow = triangle_raster_area(p2, grid_triangles(nu, nv, kept), pixel)
    if "cut_disc" in piece:  # the outline's nodes, in order of their angle around the kept nodes' centre
        nodes = np.unique(grid_triangles(nu, nv, kept))
        pinned_centre = p2[nodes].mean(axis=0)
        edge = edge_nodes(kept)
        su, sv = piece["size"]
        flat = np.hypot(edge % nu * su / (nu - 1) - piece["cut_disc"]["center"][0], edge // nu * sv / (nv - 1) - piece["cut_disc"]["center"][1])
        folds = count_cut_folds(p2[edge], pinned_centre, flat, support_radius, specimen_radius)
        d = p2[edge] - pinned_centre
        ring = p2[edge][np.argsort(np.arctan2(d[:, 1], d[:, 0]))]
    else:
        ring = p2[boundary_ring(nu, nv)]
        pinned_centre = p2.mean(axis=0)
        folds = count_folds(ring, pinned_centre)
    a_ring = shoelace(ring)
    a_disc, a_specimen = math.pi * support_radius ** 2, math.pi * specimen_radius ** 2
    return {
        "piece": name, "grid": [nu, nv],
        "fabric": scene["pieces"][piece_index]["fabric"],
        "A_shadow_cm2": a_shadow * 1e4, "A_ring_cm2": a_ring * 1e4,
        "A_disc_cm2": a_disc * 1e4, "A_specimen_cm2": a_specimen * 1e4,
        "drape_coefficient": (a_shadow - a_disc) / (a_specimen - a_disc),
        "drape_coefficient_ring": (a_ring - a_disc) / (a_specimen - a_disc),
        "folds": folds,
        "max_speed": cloth_state.read_speed(checkpoint),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("checkpoint", help="clothsim checkpoint (checkpoint_NNNNNN.h5) or XDMF .h5 series")
    parser.add_argument("--scene", required=True, help="the scene file the run used")
    parser.add_argument("--grid", type=int, help="the run's -grid N, if it was given")
    parser.add_argument("--piece", type=int, default=0, help="index of the specimen piece (default 0)")
    parser.add_argument("--support-radius", type=float, default=0.09, help="support disc radius, m (default 0.09)")
    parser.add_argument("--specimen-radius", type=float, default=0.15, help="flat specimen radius, m (default 0.15)")
    parser.add_argument("--pixel", type=float, default=5e-4, help="raster pixel size, m (default 5e-4)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    args = parser.parse_args()
    r = measure(args.checkpoint, args.scene, args.grid, args.piece, args.support_radius, args.specimen_radius, args.pixel)
    if args.json:
        json.dump(r, sys.stdout)
        print()
    else:
        print(f"{r['piece']} ({r['fabric']}, grid {r['grid'][0]}x{r['grid'][1]}): A_shadow {r['A_shadow_cm2']:.1f} cm^2 "
              f"(outline ring {r['A_ring_cm2']:.1f}), DC {r['drape_coefficient']:.3f} (ring {r['drape_coefficient_ring']:.3f}), {r['folds']} folds, "
              f"max speed {r['max_speed']:.2e} m/s")


if __name__ == "__main__":
    main()

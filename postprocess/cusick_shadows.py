#!/usr/bin/python3
"""Shadows of Cusick drape runs side by side: each panel is the draped specimen seen from above (its
vertical projection, the area the drape coefficient measures), with the support disc and the flat specimen's
outline, titled with the drape coefficient (postprocess/cusick_drape.py) and, when given, the measured one.

    /usr/bin/python3 postprocess/cusick_shadows.py --out shadows.png \\
        --run "M1 polyester twill" output/validation/cusick_petrak_m1_polyester_twill_65/checkpoint_000400.h5 \\
              output/validation/cusick_petrak_m1_polyester_twill.yaml 65 0.223  [--run ...]

Each --run takes LABEL CHECKPOINT SCENE GRID MEASURED_DC (GRID 0: the scene's own grid; MEASURED_DC -:
none).
"""
import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np

import cloth_state
import cusick_drape


def draw_shadow(ax, label, checkpoint, scene_path, grid, measured):
    scene = cloth_state.read_scene(scene_path)
    result = cusick_drape.measure(checkpoint, scene_path, grid or None)
    x = cloth_state.read_positions(checkpoint)
    _, nu, nv, offset = cloth_state.piece_grids(scene, grid or None)[0]
    e1, e2, _ = cloth_state.projection_basis(scene)
    p = x[offset:offset + nu * nv]
    p2 = np.stack([p @ e1, p @ e2], axis=1) * 100  # cm
    triangles = cusick_drape.grid_triangles(nu, nv, cusick_drape.kept_cells(scene["pieces"][0], nu, nv))
    centre = p2[np.unique(triangles)].mean(axis=0)
    p2 -= centre
    ax.add_collection(PolyCollection(p2[triangles], facecolors="0.35", edgecolors="0.35", linewidths=0.3))
    for radius, style in ((15, "--"), (9, "-")):
        t = np.linspace(0, 2 * math.pi, 200)
        ax.plot(radius * np.cos(t), radius * np.sin(t), style, color="tab:red", lw=0.8)
    ax.set_xlim(-16, 16)
    ax.set_ylim(-16, 16)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    title = f"{label}\nDC {result['drape_coefficient']:.3f}, {result['folds']} folds"
    if measured != "-":
        title += f" (measured {float(measured):.3f})"
    ax.set_title(title, fontsize=9)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--run", nargs=5, action="append", required=True, metavar=("LABEL", "CHECKPOINT", "SCENE", "GRID", "MEASURED"),
                        help="one panel; repeatable")
    parser.add_argument("--columns", type=int, default=3, help="panels per row (default 3)")
    parser.add_argument("--out", required=True, help="the PNG to write")
    args = parser.parse_args()
    rows = math.ceil(len(args.run) / args.columns)
    fig, axes = plt.subplots(rows, args.columns, figsize=(3.2 * args.columns, 3.4 * rows), squeeze=False)
    for ax in axes.flat[len(args.run):]:
        ax.axis("off")
    for ax, (label, checkpoint, scene, grid, measured) in zip(axes.flat, args.run):
        draw_shadow(ax, label, checkpoint, scene, int(grid), measured)
    fig.suptitle("Cusick drape seen from above: support disc (solid), flat specimen (dashed)", fontsize=10)
    cloth_state.save_figure(fig, args.out)
    print(f"cusick_shadows: wrote {args.out}")


if __name__ == "__main__":
    main()

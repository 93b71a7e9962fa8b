#!/usr/bin/python3
"""Pattern pieces between garment CAD (DXF, AAMA/ASTM D6673 style) and clothsim scenes.

  /usr/bin/python3 postprocess/pattern_dxf.py import PATTERN.dxf [-o pieces.yaml]
  /usr/bin/python3 postprocess/pattern_dxf.py export SCENE.yaml -o PATTERN.dxf [--units mm]

import: every piece of the DXF becomes a clothsim piece outline (the `boundaries:` of docs/scene_format.md).
As in AAMA/ASTM D6673 files, a piece is a BLOCK inserted in model space holding its boundary as a closed
polyline on layer 1, its turn points (corners) as POINTs on layer 2, its grain line as a LINE on layer 7
and its name in a TEXT "Piece Name: NAME" (the block name otherwise). clothsim meshes a piece from four
boundaries, so the piece must have exactly four turn points; the outline is split there into bottom,
right, top and left, turned so that the grain line (the warp) runs along u, and moved so that its
lowest-left corner is at (0, 0). Units follow $INSUNITS (mm, cm, m or inches) and are converted to metres.
The output lists pieces with name and boundaries; add fabric, grid and placement to use them.

export: writes the outlines of a scene's pieces (those given by `boundaries:` or `size:`) as such a DXF,
for CAD systems and for the round trip test (tests/cmake/garment.cmake). Uses ezdxf (Debian: python3-ezdxf)."""
import argparse
import math
import sys

import ezdxf
import numpy as np
import yaml

UNIT_TO_METRES = {1: 0.0254, 4: 0.001, 5: 0.01, 6: 1.0}  # $INSUNITS: inches, mm, cm, m
SIDES = ("bottom", "right", "top", "left")


def piece_outline(piece):
    """The four boundaries of a scene piece as lists of (u, v) points, in scene order (bottom, right, top, left)."""
    if "boundaries" in piece:
        b = piece["boundaries"]
        for side in SIDES:
            if not isinstance(b[side], list) or not all(isinstance(p, list) and len(p) == 2 for p in b[side]):
                sys.exit(f"pattern_dxf: piece {piece['name']}: boundary {side} is not a list of [u, v] points (arcs cannot be exported)")
        return [np.array(b[side], dtype=float) for side in SIDES]
    su, sv = piece["size"]
    return [np.array(p, dtype=float) for p in ([[0, 0], [su, 0]], [[su, 0], [su, sv]], [[0, sv], [su, sv]], [[0, 0], [0, sv]])]


def closed_ring(bottom, right, top, left):
    """The outline counter-clockwise from the bottom-left corner, and the indices of the four corners."""
    ring = list(bottom) + list(right[1:]) + list(top[::-1][1:]) + list(left[::-1][1:-1])
    corners = [0, len(bottom) - 1, len(bottom) + len(right) - 2, len(bottom) + len(right) + len(top) - 3]
    return np.array(ring), corners


def export(args):
    with open(args.scene) as f:
        scene = yaml.safe_load(f)
    scale = {"m": 1.0, "cm": 100.0, "mm": 1000.0}[args.units]
    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = {"m": 6, "cm": 5, "mm": 4}[args.units]
    for layer in ("1", "2", "7"):
        doc.layers.add(layer)
    msp = doc.modelspace()
    offset = 0.0
    for piece in scene["pieces"]:
        ring, corners = closed_ring(*piece_outline(piece))
        block = doc.blocks.new(name=piece["name"])
        block.add_lwpolyline([tuple(p * scale) for p in ring], close=True, dxfattribs={"layer": "1"})
        for c in corners:
            block.add_point(tuple(ring[c] * scale), dxfattribs={"layer": "2"})
        lo, hi = ring.min(axis=0), ring.max(axis=0)
        mid = 0.5 * (lo + hi)
        block.add_line(((lo[0] + 0.1 * (hi[0] - lo[0])) * scale, mid[1] * scale), ((hi[0] - 0.1 * (hi[0] - lo[0])) * scale, mid[1] * scale), dxfattribs={"layer": "7"})
        block.add_text("Piece Name: " + piece["name"], dxfattribs={"layer": "1", "height": 0.01 * scale}).set_pos((mid[0] * scale, (mid[1] + 0.05 * (hi[1] - lo[1])) * scale))
        msp.add_blockref(piece["name"], (offset * scale, 0))
        offset += (hi[0] - lo[0]) + 0.05
    doc.saveas(args.output)
    print(f"pattern_dxf: wrote {len(scene['pieces'])} pieces to {args.output} ({args.units})")


def split_outline(name, ring, corners, grain):
    """Four boundaries from a closed outline and its four corners, with the grain along u, in metres."""
    area = 0.5 * np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    if area < 0:  # make it counter-clockwise
        ring = ring[::-1]
    angle = math.atan2(grain[1], grain[0])
    rot = np.array([[math.cos(-angle), -math.sin(-angle)], [math.sin(-angle), math.cos(-angle)]])
    ring = ring @ rot.T
    idx = []
    for c in corners:
        c = rot @ c
        d = np.linalg.norm(ring - c, axis=1)
        if d.min() > 1e-6 * max(1.0, np.abs(ring).max()):
            sys.exit(f"pattern_dxf: piece {name}: turn point {c} is not a vertex of its boundary")
        idx.append(int(d.argmin()))
    start = min(idx, key=lambda i: ring[i, 0] + ring[i, 1])  # the bottom-left corner
    ring = np.roll(ring, -start, axis=0)
    idx = sorted((i - start) % len(ring) for i in idx)
    ring = np.vstack([ring, ring[:1]])
    paths = [ring[idx[k]: (idx[k + 1] if k < 3 else len(ring) - 1) + 1] for k in range(4)]
    bottom, right, top, left = paths[0], paths[1], paths[2][::-1], paths[3][::-1]
    origin = bottom[0].copy()
    return {side: [[round(float(u - origin[0]), 9), round(float(v - origin[1]), 9)] for u, v in path] for side, path in zip(SIDES, (bottom, right, top, left))}


def entities_of_piece(block):
    outline, points, grain, name = None, [], None, block.name
    for e in block:
        layer = e.dxf.layer
        if e.dxftype() == "LWPOLYLINE" and layer == "1" and e.closed:
            outline = np.array([(p[0], p[1]) for p in e.get_points("xy")])
        elif e.dxftype() == "POLYLINE" and layer == "1" and e.is_closed:
            outline = np.array([(v.dxf.location[0], v.dxf.location[1]) for v in e.vertices])
        elif e.dxftype() == "POINT" and layer == "2":
            points.append(np.array([e.dxf.location.x, e.dxf.location.y]))
        elif e.dxftype() == "LINE" and layer == "7":
            grain = np.array([e.dxf.end.x - e.dxf.start.x, e.dxf.end.y - e.dxf.start.y])
        elif e.dxftype() == "TEXT" and e.dxf.text.startswith("Piece Name:"):
            name = e.dxf.text.split(":", 1)[1].strip()
    return outline, points, grain, name


def import_(args):
    doc = ezdxf.readfile(args.dxf)
    scale = UNIT_TO_METRES.get(doc.header.get("$INSUNITS", 4), 0.001)
    pieces = []
    for insert in doc.modelspace().query("INSERT"):
        outline, points, grain, name = entities_of_piece(doc.blocks.get(insert.dxf.name))
        if outline is None:
            continue
        if len(points) != 4:
            sys.exit(f"pattern_dxf: {args.dxf}: piece {name} has {len(points)} turn points on layer 2, expected 4 (the corners between bottom, right, top and left)")
        if grain is None:
            grain = np.array([1.0, 0.0])
        pieces.append({"name": name, "boundaries": split_outline(name, outline * scale, [p * scale for p in points], grain)})
    if not pieces:
        sys.exit(f"pattern_dxf: {args.dxf}: no piece (a block with a closed polyline on layer 1) found")
    text = yaml.safe_dump({"pieces": pieces}, default_flow_style=None, sort_keys=False)
    if args.output:
        with open(args.output, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    print(f"pattern_dxf: {len(pieces)} pieces from {args.dxf}", file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("import", help="DXF pattern -> piece outlines (YAML)")
    p.add_argument("dxf")
    p.add_argument("-o", "--output")
    p.set_defaults(run=import_)
    p = sub.add_parser("export", help="scene pieces -> DXF pattern")
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--units", choices=("m", "cm", "mm"), default="mm")
    p.set_defaults(run=export)
    args = parser.parse_args()
    args.run(args)


if __name__ == "__main__":
    main()

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
for CAD systems and for the round trip test (tests/cmake/garment.cmake). Uses ezdxf (Debian: python3-ezdxf).

Errors end the tool with one line on stderr, "ERROR: pattern_dxf: ...", naming the file, the piece and what is wrong,
and clothsim's exit statuses (README "Errors and exit status"): 3 when a file cannot be read or written (missing, a
directory, not DXF: random bytes, an empty file), 2 when the pattern in it cannot be used: a vertex, turn point or
grain line that is not finite, an outline that crosses or touches itself, turn points that are not four vertices of
it, an outline beyond clothsim's bound of 1000 m (a wrong $INSUNITS), two pieces of one name. Piece names become
clothsim names (letters, digits and _ . + -): other characters turn into '_', with a note on stderr. The pieces
written are checked as clothsim reads them (finite, within the bound, four boundaries of positive length that meet
at the corners), so that clothsim accepts the outlines it is given. tests/drivers/pattern_dxf_bad_input.sh."""
import argparse
import math
import os
import re
import sys

import ezdxf
import numpy as np
import yaml

UNIT_TO_METRES = {1: 0.0254, 4: 0.001, 5: 0.01, 6: 1.0}  # $INSUNITS: inches, mm, cm, m
SIDES = ("bottom", "right", "top", "left")
EXIT_INPUT, EXIT_FILE = 2, 3  # clothsim's exit statuses (src/errors.h): bad input, a file that cannot be used
MAX_COORDINATE = 1000.0  # m: clothsim refuses outline coordinates beyond (docs/scene_format.md, "Upper bounds")
NAME_LEN = 63  # clothsim's longest name (CLOTH_NAME_LEN - 1)


class PatternError(Exception):
    """A refusal: its exit status and its one-line message."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


def read_dxf(path):
    """The DXF document of path; a file that cannot be read or is not DXF is refused (EXIT_FILE)."""
    what = "expected a DXF pattern file (AAMA/ASTM D6673 style)"
    if os.path.isdir(path):
        raise PatternError(EXIT_FILE, f"{path}: cannot read the file (Is a directory): {what}")
    try:
        return ezdxf.readfile(path)
    except OSError as e:  # missing, unreadable; ezdxf raises it too for what is not DXF (random bytes, empty)
        problem = f"cannot read the file ({e.strerror})" if e.strerror else "not a DXF file"
        raise PatternError(EXIT_FILE, f"{path}: {problem}: {what}") from None
    except (ezdxf.DXFError, UnicodeDecodeError, ValueError) as e:  # DXF-like text that is broken
        raise PatternError(EXIT_FILE, f"{path}: not a readable DXF file ({e}): {what}") from None


def piece_outline(piece):
    """The four boundaries of a scene piece as lists of (u, v) points, in scene order (bottom, right, top, left)."""
    if "boundaries" in piece:
        b = piece["boundaries"]
        for side in SIDES:
            if not isinstance(b.get(side), list) or not all(isinstance(p, list) and len(p) == 2 for p in b[side]):
                raise PatternError(EXIT_INPUT, f"piece {piece['name']}: boundary {side} is not a list of [u, v] points: expected polylines (arcs cannot be exported)")
        return [np.array(b[side], dtype=float) for side in SIDES]
    su, sv = piece["size"]
    return [np.array(p, dtype=float) for p in ([[0, 0], [su, 0]], [[su, 0], [su, sv]], [[0, sv], [su, sv]], [[0, 0], [0, sv]])]


def closed_ring(bottom, right, top, left):
    """The outline counter-clockwise from the bottom-left corner, and the indices of the four corners."""
    ring = list(bottom) + list(right[1:]) + list(top[::-1][1:]) + list(left[::-1][1:-1])
    corners = [0, len(bottom) - 1, len(bottom) + len(right) - 2, len(bottom) + len(right) + len(top) - 3]
    return np.array(ring), corners


def read_scene(path):
    """The pieces of a clothsim scene file; a file that cannot be read (EXIT_FILE) or is no scene (EXIT_INPUT) is refused."""
    try:
        with open(path) as f:
            scene = yaml.safe_load(f)
    except OSError as e:
        raise PatternError(EXIT_FILE, f"{path}: cannot read the file ({e.strerror}): expected a clothsim scene") from None
    except (yaml.YAMLError, RecursionError, UnicodeDecodeError) as e:  # RecursionError: lists nested thousands deep
        raise PatternError(EXIT_INPUT, f"{path}: not a YAML scene ({type(e).__name__}): expected a clothsim scene") from None
    if not isinstance(scene, dict) or not isinstance(scene.get("pieces"), list) or not all(isinstance(p, dict) and "name" in p for p in scene["pieces"]):
        raise PatternError(EXIT_INPUT, f"{path}: no list of pieces with names: expected a clothsim scene (docs/scene_format.md)")
    return scene


def export(args):
    scene = read_scene(args.scene)
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
        d = np.linalg.norm(ring - rot @ c, axis=1)
        if d.min() > 1e-6 * max(1.0, np.abs(ring).max()):
            raise PatternError(EXIT_INPUT, f"piece {name}: turn point ({c[0]:g}, {c[1]:g}) m is not a vertex of its outline: expected the four corners on it")
        idx.append(int(d.argmin()))
    start = min(idx, key=lambda i: ring[i, 0] + ring[i, 1])  # the bottom-left corner
    ring = np.roll(ring, -start, axis=0)
    idx = sorted((i - start) % len(ring) for i in idx)
    if len(set(idx)) != 4:
        raise PatternError(EXIT_INPUT, f"piece {name}: two of its turn points are the same vertex of its outline: expected four distinct corners")
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


def segments_meet(a, b, c, d):
    """Per row, whether segment a-b and segment c-d have a point in common (crossing, touching or overlapping)."""
    def orient(p, q, r):
        return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])

    def within(p, q, r):  # r in the box of p-q (on the segment when collinear)
        return np.all((np.minimum(p, q) <= r) & (r <= np.maximum(p, q)), axis=1)

    d1, d2, d3, d4 = orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d)
    proper = (np.sign(d1) * np.sign(d2) < 0) & (np.sign(d3) * np.sign(d4) < 0)
    return proper | ((d1 == 0) & within(c, d, a)) | ((d2 == 0) & within(c, d, b)) | ((d3 == 0) & within(a, b, c)) | ((d4 == 0) & within(a, b, d))


def candidate_pairs(lo, hi):
    """Pairs (i, j), i < j, of segments whose boxes [lo, hi] share a cell of a uniform grid of cells the size of a
    typical segment (coarser when long segments would cover too many): a superset of the pairs that meet, in time
    about linear in the number of segments of an outline."""
    n = len(lo)
    extent = float(np.max(hi - lo.min(axis=0)))
    cell = max(float(np.median(np.max(hi - lo, axis=1))), 1e-9 * extent, 1e-300)
    while True:
        c0, c1 = np.floor((lo - lo.min(axis=0)) / cell).astype(np.int64), np.floor((hi - lo.min(axis=0)) / cell).astype(np.int64)
        width = c1 - c0 + 1
        counts = width[:, 0] * width[:, 1]
        if counts.sum() <= 64 * n + 1024:
            break
        cell *= 2  # a few long segments cover many cells: coarser cells
    seg = np.repeat(np.arange(n), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    cx = np.repeat(c0[:, 0], counts) + local % np.repeat(width[:, 0], counts)
    cy = np.repeat(c0[:, 1], counts) + local // np.repeat(width[:, 0], counts)
    order = np.lexsort((seg, cy, cx))
    key, seg = cx[order] * (int(c1[:, 1].max()) + 1) + cy[order], seg[order]
    pairs, d = [np.empty((0, 2), dtype=np.int64)], 1
    while d < len(key) and np.any(same := key[:-d] == key[d:]):  # entries d apart in one cell
        k = np.flatnonzero(same)
        pairs.append(np.column_stack((seg[k], seg[k + d])))
        d += 1
    return np.unique(np.sort(np.vstack(pairs), axis=1), axis=0)


def check_simple(path, name, ring):
    """Refuses an outline (closed, consecutive vertices distinct) that crosses or touches itself: clothsim would mesh
    it into folded cells and name a cell, not the outline."""
    a, b = ring, np.roll(ring, -1, axis=0)
    pairs = candidate_pairs(np.minimum(a, b), np.maximum(a, b))
    i, j = pairs[:, 0], pairs[:, 1]
    keep = (j - i > 1) & ~((i == 0) & (j == len(ring) - 1))  # edges that share a vertex meet there
    i, j = i[keep], j[keep]
    meet = np.flatnonzero(segments_meet(a[i], b[i], a[j], b[j]))
    if meet.size:
        k = meet[np.lexsort((j[meet], i[meet]))[0]]
        p, q = (f"({a[e][0]:g}, {a[e][1]:g})-({b[e][0]:g}, {b[e][1]:g})" for e in (i[k], j[k]))
        raise PatternError(EXIT_INPUT, f"{path}: piece {name}: its outline (layer 1) crosses itself: edge {i[k]} {p} meets edge {j[k]} {q} (file units): expected a simple closed outline")


def piece_outline_checked(path, name, outline, points, grain):
    """The outline as a closed ring of distinct consecutive vertices, checked: finite, at least 4 vertices, simple."""
    for what, values in (("vertex", outline), ("turn point", np.array(points)), ("grain line", np.array([grain]))):
        bad = np.flatnonzero(~np.all(np.isfinite(values.reshape(len(values), -1)), axis=1))
        if bad.size:
            v = values[bad[0]]
            raise PatternError(EXIT_INPUT, f"{path}: piece {name}: {what} {bad[0]} is ({v[0]}, {v[1]}): expected finite coordinates")
    ring = outline[np.any(outline != np.roll(outline, 1, axis=0), axis=1)]  # repeated vertices (a closing one) once
    if len(ring) < 4:
        raise PatternError(EXIT_INPUT, f"{path}: piece {name}: its outline has {len(ring)} distinct vertices: expected at least 4 (its corners)")
    check_simple(path, name, ring)
    return ring


def clothsim_name(name):
    """name as clothsim accepts it (letters, digits and _ . + -, not starting with '.', at most 63 characters)."""
    fixed = re.sub(r"[^A-Za-z0-9_.+-]", "_", name)[:NAME_LEN]
    fixed = "_" + fixed[1:] if fixed.startswith(".") else fixed
    if fixed != name:
        print(f"pattern_dxf: piece '{name}' is called '{fixed}' (clothsim names: letters, digits and _ . + -, at most {NAME_LEN} characters)", file=sys.stderr)
    return fixed or "_"


def check_piece(path, piece):
    """The piece as clothsim reads it: finite coordinates within MAX_COORDINATE, boundaries of positive length."""
    for side in SIDES:
        b = np.array(piece["boundaries"][side], dtype=float)
        if len(b) < 2 or not np.all(np.isfinite(b)) or np.abs(b).max() > MAX_COORDINATE:
            raise PatternError(EXIT_INPUT, f"{path}: piece {piece['name']}: its {side} boundary reaches {np.abs(b).max():g} m: expected at most {MAX_COORDINATE:g} m, clothsim's bound (is $INSUNITS the file's unit?)")
        if not np.linalg.norm(b[1:] - b[:-1], axis=1).sum() > 0:
            raise PatternError(EXIT_INPUT, f"{path}: piece {piece['name']}: its {side} boundary has zero length: expected four corners apart")


def import_(args):
    doc = read_dxf(args.dxf)
    scale = UNIT_TO_METRES.get(doc.header.get("$INSUNITS", 4), 0.001)
    pieces = []
    for insert in doc.modelspace().query("INSERT"):
        outline, points, grain, name = entities_of_piece(doc.blocks.get(insert.dxf.name))
        if outline is None:
            continue
        name = clothsim_name(name)
        if len(points) != 4:
            raise PatternError(EXIT_INPUT, f"{args.dxf}: piece {name} has {len(points)} turn points on layer 2: expected 4 (the corners between bottom, right, top and left)")
        if grain is None:
            grain = np.array([1.0, 0.0])
        ring = piece_outline_checked(args.dxf, name, outline, points, grain)
        if name in (p["name"] for p in pieces):
            raise PatternError(EXIT_INPUT, f"{args.dxf}: two pieces are called {name}: expected a name per piece (TEXT 'Piece Name: NAME')")
        pieces.append({"name": name, "boundaries": split_outline(name, ring * scale, [p * scale for p in points], grain)})
        check_piece(args.dxf, pieces[-1])
    if not pieces:
        raise PatternError(EXIT_INPUT, f"{args.dxf}: no piece (a block with a closed polyline on layer 1) found")
    text = yaml.safe_dump({"pieces": pieces}, default_flow_style=None, sort_keys=False)
    if args.output:
        try:
            with open(args.output + ".tmp", "w") as f:
                f.write(text)
            os.replace(args.output + ".tmp", args.output)
        except OSError as e:
            raise PatternError(EXIT_FILE, f"{args.output}: cannot write the file ({e.strerror})") from None
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
    try:
        args.run(args)
    except PatternError as e:
        print(f"ERROR: pattern_dxf: {e}", file=sys.stderr)
        sys.exit(e.status)
    except ezdxf.DXFError as e:  # a DXF whose entities ezdxf cannot read
        print(f"ERROR: pattern_dxf: {getattr(args, 'dxf', '')}: not a readable DXF pattern ({e})", file=sys.stderr)
        sys.exit(EXIT_FILE)


if __name__ == "__main__":
    main()

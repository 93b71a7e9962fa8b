#!/usr/bin/python3
"""The fitted dress's pattern, drafted from the mannequin's measurements, and its scenes at any resolution.

  /usr/bin/python3 jobs/dress_fitted_pattern.py draft            # writes input/dress_fitted_pattern.dxf
  /usr/bin/python3 jobs/dress_fitted_pattern.py scene H OUT.yaml [--name NAME] [--t-final T]
                                                                  # the scene, particles about H metres apart

draft: measures the mannequin (postprocess/mannequin_measure.py: torso girths every 4 cm from the waist seam
at y = 0.24 m to the bodice top at y = 0.40 m) and drafts, in the pattern plane (u around the body, along the
warp; v up):
  - a princess-line bodice of six panels (centre front, two side fronts, centre back, two side backs), each
    at every height as wide as its share of the girth plus ease (4 cm at the waist, 5 cm at the top); the
    princess and side seams are polylines through those heights, so sewing the panels together closes the
    darts between them (1.4 cm at the top down to nothing at the waist... as measured) and shapes the bodice to
    the bust and waist;
  - a flared skirt of two panels, each a sector of an annulus (a half-circle skirt in all, 0.55 m long):
    its waist arc is the bodice's waist, its hem arc 0.95 m per panel, 2.6 times the waist, so that the hem
    has far more cloth than the hips and falls in folds;
  - two shoulder straps (as input/dress.yaml's).
  The outlines go to input/dress_fitted_pattern.dxf (AAMA style, postprocess/pattern_dxf.py export, mm).
scene: reads the pieces back from that DXF (postprocess/pattern_dxf.py import, so the scene is what the DXF
holds), gives each a grid of about H between particles, places it around the mannequin (bodice panels rolled
onto a cylinder around the torso, skirt panels onto a cone, straps over the shoulders) and writes the seams:
the six vertical bodice seams (four princess, two side), the skirt's two side seams, six waist seams (each
skirt panel's waist to the three bodice panels above it, by arc length, the skirt node at each junction sewn to
both panels) and the straps' four ends (onto whole cells of the side panels' tops, which are divided for it)."""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "postprocess"))
import mannequin_measure  # noqa: E402

DXF = os.path.join(ROOT, "input", "dress_fitted_pattern.dxf")
WAIST_Y, TOP_Y = 0.24, 0.40           # the waist seam and the bodice top (the straps of input/dress.yaml fit there)
LEVELS = np.linspace(WAIST_Y, TOP_Y, 5)
EASE_WAIST, EASE_TOP = 0.04, 0.07     # m of girth beyond the body's (the straps lift the top towards the armpits)
CENTRE_WAIST, CENTRE_TOP = 0.12, 0.14  # width of the centre front and centre back panels
SKIRT_LENGTH, SKIRT_HEM = 0.55, 0.95  # per panel: hem arc length
AXIS_Z = 0.06                         # the torso's middle (z) at the waist, mannequin_measure: -0.024 to 0.148
BODICE_RADIUS = 0.20                  # the cylinder the bodice panels start on (input/dress.yaml's)
SKIRT_WAIST_RADIUS = 0.16             # the cone the skirt panels start on: radius at the waist
STRAP = (0.054, 0.54)                 # strap width and length
STRAP_ARC = (0.081, 0.135)            # where a strap meets the bodice top: arc from the centre front / back
BODICE = ("centre_front", "side_front_right", "side_back_right", "centre_back", "side_back_left", "side_front_left")


def panel_widths(girths):
    """Widths of the centre and side panels at each level: front and back halves alike."""
    t = (LEVELS - WAIST_Y) / (TOP_Y - WAIST_Y)
    girth = girths + EASE_WAIST + t * (EASE_TOP - EASE_WAIST)
    centre = CENTRE_WAIST + t * (CENTRE_TOP - CENTRE_WAIST)
    side = 0.5 * (0.5 * girth - centre)
    return centre, side


def bodice_panel(widths):
    """A symmetric panel as wide as `widths` at the levels: straight waist and top, polyline sides."""
    v = LEVELS - WAIST_Y
    half = 0.5 * np.asarray(widths)
    return {"bottom": [[-half[0], 0.0], [half[0], 0.0]], "right": [[h, y] for h, y in zip(half, v)],
            "top": [[-half[-1], v[-1]], [half[-1], v[-1]]], "left": [[-h, y] for h, y in zip(half, v)]}


def skirt_panel(waist, segments=24):
    """A sector of an annulus, apex at (0, 0) above: waist arc of length `waist`, hem arc SKIRT_HEM."""
    angle = (SKIRT_HEM - waist) / SKIRT_LENGTH
    r_waist = waist / angle
    r_hem = r_waist + SKIRT_LENGTH
    t = np.linspace(-0.5 * angle, 0.5 * angle, segments + 1)
    arc = lambda r: [[r * math.sin(a), -r * math.cos(a)] for a in t]  # noqa: E731
    hem, top = arc(r_hem), arc(r_waist)
    return {"bottom": hem, "right": [hem[-1], top[-1]], "top": top, "left": [hem[0], top[0]]}


def rounded(outline):
    return {side: [[round(float(u), 9), round(float(v), 9)] for u, v in pts] for side, pts in outline.items()}


def draft(args):
    vertices, faces = mannequin_measure.read_obj(os.path.join(ROOT, "input/mannequin/makehuman_body.obj"), 0.1)
    girths = np.array([mannequin_measure.girth(mannequin_measure.torso_section(vertices, faces, y)) for y in LEVELS])
    centre, side = panel_widths(girths)
    print("dress_fitted_pattern: torso girth " + ", ".join(f"{g:.3f} m at y = {y:.2f}" for g, y in zip(girths, LEVELS)))
    print("dress_fitted_pattern: centre panels " + ", ".join(f"{w:.3f}" for w in centre) + " m, side panels " + ", ".join(f"{w:.3f}" for w in side) + " m (waist to top)")
    pieces = [{"name": name, "boundaries": rounded(bodice_panel(centre if name.startswith("centre") else side))} for name in BODICE]
    waist = float(centre[0] + 2 * side[0])
    pieces += [{"name": name, "boundaries": rounded(skirt_panel(waist))} for name in ("skirt_front", "skirt_back")]
    pieces += [{"name": name, "size": list(STRAP)} for name in ("strap_right", "strap_left")]
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump({"pieces": pieces}, f)
    try:
        subprocess.run([sys.executable, os.path.join(ROOT, "postprocess/pattern_dxf.py"), "export", f.name, "-o", args.output, "--units", "mm"], check=True)
    finally:
        os.unlink(f.name)


def length(points):
    p = np.asarray(points, dtype=float)
    return float(np.sum(np.linalg.norm(p[1:] - p[:-1], axis=1)))


def read_pattern(path):
    out = subprocess.run([sys.executable, os.path.join(ROOT, "postprocess/pattern_dxf.py"), "import", path], check=True, capture_output=True, text=True)
    return {p["name"]: p["boundaries"] for p in yaml.safe_load(out.stdout)["pieces"]}


def grid(b, h):
    """Nodes across (u) from the mean of waist and top, along v from the longer side: about h apart."""
    nu = max(4, int(round(0.5 * (length(b["bottom"]) + length(b["top"])) / h)) + 1)
    nv = max(4, int(round(max(length(b["left"]), length(b["right"])) / h)) + 1)
    return [nu, nv]


def strap_cells(h):
    """Cells of a side panel's top a strap's end spans: about h wide each."""
    return max(1, round(STRAP[0] / h))


def bodice_grid(name, b, h):
    """grid(), except that a side panel's top is divided so that a strap's end (STRAP[0] wide) spans a whole
    number of its cells: a seam joins whole stretches between nodes, so a strap sewn onto a stretch of other
    length is eased onto it (the coarse dress's side panels were stretched 10 % at the top, 54 mm of strap on
    43 mm of bodice)."""
    nu, nv = grid(b, h)
    if name.startswith("side"):
        nu = max(4, round(strap_cells(h) * length(b["top"]) / STRAP[0])) + 1
    return [nu, nv]


def vec(x):
    return [round(float(c), 9) for c in x]


def scene(args):
    pat = read_pattern(args.pattern)
    h = args.spacing
    width = {name: (length(pat[name]["bottom"]), length(pat[name]["top"])) for name in BODICE}
    mean = [0.5 * sum(width[name]) for name in BODICE]
    gap = (2 * math.pi * BODICE_RADIUS - sum(mean)) / len(BODICE)
    pieces, angle = [], 0.0
    for k, name in enumerate(BODICE):  # around the body by increasing angle from the front (+z) towards +x
        if k:
            angle += (0.5 * mean[k - 1] + gap + 0.5 * mean[k]) / BODICE_RADIUS
        b = pat[name]
        n = np.array([math.sin(angle), 0.0, math.cos(angle)])
        u = np.array([math.cos(angle), 0.0, -math.sin(angle)])
        touch = np.array([0.0, WAIST_Y, AXIS_Z]) + BODICE_RADIUS * n
        centre_u = 0.5 * (b["bottom"][0][0] + b["bottom"][-1][0])
        pieces.append({"name": name, "fabric": "poplin", "grid": bodice_grid(name, b, h), "boundaries": b, "origin": vec(touch - centre_u * u),
                       "u_axis": vec(u), "v_axis": [0, 1, 0], "wrap": {"axis_point": [0, 0, AXIS_Z], "axis": [0, 1, 0]}})
    for name, angle in (("skirt_front", 0.0), ("skirt_back", math.pi)):
        b = pat[name]
        r_waist = math.hypot(*(np.array(b["top"][0]) - np.array(b["top"][-1]))) / 2  # placeholder, replaced below
        # the apex: where the straight sides meet, in the piece's frame
        p0, p1 = np.array(b["left"][0]), np.array(b["left"][-1])
        q0, q1 = np.array(b["right"][0]), np.array(b["right"][-1])
        m = np.array([p1 - p0, q0 - q1]).T
        s = np.linalg.solve(m, q0 - p0)
        apex2 = p0 + s[0] * (p1 - p0)
        r_waist = float(np.linalg.norm(np.array(b["top"][0]) - apex2))
        sin_a = SKIRT_WAIST_RADIUS / r_waist
        cos_a = math.sqrt(1 - sin_a ** 2)
        apex = np.array([0.0, WAIST_Y + r_waist * cos_a, AXIS_Z])
        u = np.array([math.cos(angle), 0.0, -math.sin(angle)])
        v = np.array([-sin_a * math.sin(angle), cos_a, -sin_a * math.cos(angle)])
        pieces.append({"name": name, "fabric": "poplin", "grid": grid(b, h), "boundaries": b,
                       "origin": vec(apex - apex2[0] * u - apex2[1] * v), "u_axis": vec(u), "v_axis": vec(v),
                       "wrap": {"apex": vec(apex), "axis": [0, -1, 0]}})
    for name, x in (("strap_right", 0.073), ("strap_left", -0.127)):  # as input/dress.yaml: arched over the shoulders
        b = pat[name]
        nu = max(4, int(round(STRAP[0] / h)) + 1)
        nv = int(round(STRAP[1] / h)) + 1
        pieces.append({"name": name, "fabric": "poplin", "grid": [nu, nv], "boundaries": b, "origin": [x, 0.60, 0.315],
                       "u_axis": [1, 0, 0], "v_axis": [0, 0, -1], "wrap": {"axis_point": [0, 0.40, 0.05], "axis": [1, 0, 0]}})
    seams = []
    for k, name in enumerate(BODICE):
        nxt = BODICE[(k + 1) % len(BODICE)]
        seams.append({"name": f"{name}_to_{nxt}", "a": {"piece": name, "side": "right"}, "b": {"piece": nxt, "side": "left"}})
    seams.append({"name": "skirt_side_right", "a": {"piece": "skirt_front", "side": "right"}, "b": {"piece": "skirt_back", "side": "left"}})
    seams.append({"name": "skirt_side_left", "a": {"piece": "skirt_back", "side": "right"}, "b": {"piece": "skirt_front", "side": "left"}})
    # Each waist seam takes the skirt's top nodes within its share of the waist (by the bodice panels' widths).
    # Where two panels meet, the skirt node nearest to the junction must belong to both seams, so that it is
    # sewn to both panels' corners (which the princess or side seam sews together): otherwise one seam ends a
    # node short and the junction pulls two skirt nodes a cell apart onto one point (the coarse dress's 2.6 mm
    # gaps). So the junction is moved to that node and each seam's stretch reaches a quarter cell past it
    # (a node is selected by its arc-length fraction, which is k / (nu - 1) only to the polyline's accuracy).
    for skirt, above in (("skirt_front", ("side_front_left", "centre_front", "side_front_right")), ("skirt_back", ("side_back_right", "centre_back", "side_back_left"))):
        cells = grid(pat[skirt], h)[0] - 1
        total = sum(width[p][0] for p in above)
        junctions = [0.0]
        for p in above:
            junctions.append(junctions[-1] + width[p][0] / total)
        nodes = [round(f * cells) for f in junctions]
        for p, lo, hi in zip(above, nodes[:-1], nodes[1:]):
            start, end = max(0.0, (lo - 0.25) / cells), min(1.0, (hi + 0.25) / cells)
            seams.append({"name": f"waist_{p}", "a": {"piece": skirt, "side": "top", "from": round(start, 6), "to": round(end, 6)}, "b": {"piece": p, "side": "bottom"}, "bend": False})
    # a strap's end at arc d from the centre front (back) lies on the side panel's top at fraction (d - centre/2) / side;
    # it is sewn onto the strap_cells() cells from the node nearest to its first edge, each stretch reaching a quarter
    # cell past its end nodes (as the waist seams')
    centre_top, side_top = width["centre_front"][1], width["side_front_right"][1]
    cells = bodice_grid("side", pat["side_front_right"], h)[0] - 1
    first = round((STRAP_ARC[0] - 0.5 * centre_top) / side_top * cells)
    last = first + strap_cells(h)
    if not 0 < first < last < cells:
        sys.exit(f"dress_fitted_pattern: the straps (arc {STRAP_ARC} m from the centre) miss the side panels' tops")
    f = [(first - 0.25) / cells, (last + 0.25) / cells]
    fr = lambda x: round(x, 6)  # noqa: E731
    seams += [
        {"name": "shoulder_right_front", "a": {"piece": "strap_right", "side": "bottom"}, "b": {"piece": "side_front_right", "side": "top", "from": fr(f[0]), "to": fr(f[1])}},
        {"name": "shoulder_right_back", "a": {"piece": "strap_right", "side": "top"}, "b": {"piece": "side_back_right", "side": "top", "from": fr(1 - f[0]), "to": fr(1 - f[1])}},
        {"name": "shoulder_left_front", "a": {"piece": "strap_left", "side": "bottom"}, "b": {"piece": "side_front_left", "side": "top", "from": fr(1 - f[1]), "to": fr(1 - f[0])}},
        {"name": "shoulder_left_back", "a": {"piece": "strap_left", "side": "top"}, "b": {"piece": "side_back_left", "side": "top", "from": fr(f[1]), "to": fr(f[0])}},
    ]
    count = sum(p["grid"][0] * p["grid"][1] for p in pieces)
    doc = {"name": args.name, "gravity": [0, -9.81, 0],
           "fabrics": {"poplin": {"preset": "cotton_polyester", "damping": 2.0}},
           "pieces": pieces, "seams": seams,
           "sewing": {"pull_acceleration": 1000, "pull_radius": 0.005, "sewn_stiffness": 5000, "tolerance": 0.012, "max_time": 3.5, "pull_friction": 0},
           "bodies": [{"name": "mannequin", "type": "mesh", "file": "mannequin/makehuman_body.obj", "scale": 0.1, "friction": {"static": 0.6, "kinetic": 0.4}, "thickness": 0.004}],
           "self_collision": {"enabled": True, "thickness": round(min(0.006, 0.75 * h), 6), "stiffness": 20},
           "run": {"integrator": "implicit", "dt": args.dt, "t_final": args.t_final, "output_every": args.output_every}}
    header = (f"# The fitted dress (issue 26), {count} particles about {h * 1000:.0f} mm apart: written by\n"
              f"#   /usr/bin/python3 jobs/dress_fitted_pattern.py scene {h} input/{os.path.basename(args.output)} --name {args.name}"
              f"{'' if args.t_final == 5.0 else f' --t-final {args.t_final}'}\n"
              "# from the pattern input/dress_fitted_pattern.dxf (drafted from the mannequin's measurements by\n"
              "# jobs/dress_fitted_pattern.py draft): a princess-line bodice of six panels, a half-circle skirt of two, two straps.\n"
              "# Do not edit by hand: change the pattern or the script and write it again (docs/results.md, \"The fitted dress\").\n")
    with open(args.output, "w") as f:
        f.write(header + yaml.safe_dump(doc, default_flow_style=None, sort_keys=False, width=200))
    print(f"dress_fitted_pattern: {args.output}: {len(pieces)} pieces, {count} particles, {len(seams)} seams")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("draft", help="measure the mannequin and write the pattern DXF")
    p.add_argument("-o", "--output", default=DXF)
    p.set_defaults(run=draft)
    p = sub.add_parser("scene", help="the scene from the pattern at a particle spacing")
    p.add_argument("spacing", type=float, help="metres between particles (about)")
    p.add_argument("output")
    p.add_argument("--pattern", default=DXF)
    p.add_argument("--name", default="dress_fitted")
    p.add_argument("--dt", type=float, default=0.004)
    p.add_argument("--t-final", type=float, default=5.0)
    p.add_argument("--output-every", type=int, default=25)
    p.set_defaults(run=scene)
    args = parser.parse_args()
    if args.command == "scene" and not 0.002 <= args.spacing <= 0.05:
        sys.exit(f"dress_fitted_pattern: spacing {args.spacing} m: expected 0.002 to 0.05 m")
    args.run(args)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Writes the T-shirt scenes: input/tshirt.yaml (a T-shirt with set-in sleeves on the mannequin) and
input/tshirt_dress.yaml (that T-shirt under the main job's dress, graded to go over it, both sewn in one run).

  /usr/bin/python3 scripts/tshirt_scenes.py            (from the repository's root)

The pattern (metres; u across, v up, as in docs/scene_format.md):
  front, back   0.46 m wide at the hem and the chest (the mannequin's chest is 0.81 m round at y = 0.40), the
                side seam 0.308 m up to the armpit, then an armhole scooped 4 cm in (0.22 m long), the top 0.38
                m across with a neckline 4 cm deep between two shoulder seams of 1/6 of the top (6.6 cm);
  sleeves       0.40 m round (the upper arm is 0.09-0.12 m across), 0.06 m long under the arm, with a cap
                v = 0.06 + A (1 - cos(2 pi u / 0.40)) whose height 2A is chosen so that the cap is 5 % longer
                than the armhole it is sewn into (0.462 against 2 x 0.22 m): the ease of a set-in sleeve.
The left side boundary of the front is 0.528 m long; the armpit is at 7/12 of it (0.308 m), a node of the
25-node and of the 13-node side, so the side seam and the armhole meet at a node on the scene's grid and on
the coarse test's.

Placement (the arrangement of the founding paper: each piece near the body part it belongs to): front and
back rolled onto a cylinder of radius 0.19 m around the vertical axis through (0, 0, 0.05), the hem at
y = 0.092; each sleeve rolled onto a cylinder of radius 0.075 m around its arm's axis, which runs from the
shoulder (-0.17, 0.52, 0.0) towards the elbow (-0.30, 0.36, 0.03) (the right arm mirrored in x; measured on
input/mannequin: the upper arm's cross-sections are 0.035-0.047 m in radius from 0.075 m below the shoulder
on), the sleeve's middle on the top of the arm and its underarm edges 0.09 m down the arm, where they clear
the torso. In tshirt_dress.yaml the dress's pieces are placed outside the T-shirt's: the bodice on a cylinder
of radius 0.22 m (0.20 in input/dress.yaml), the straps arched at 0.28 m (0.20) and the skirt panels on a
cone of half-angle asin(0.375) (asin(0.2787)) with its waist at y = 0.24, so that no piece starts through
another. The dress is input/dress.yaml's (grids, seams, straps) made to be worn over the T-shirt, as a
pinafore is: one size up (the bodice's and the skirt's widths times 1.15: 0.97 m round at the waist, 1.04 m
at the top, against the T-shirt's 0.92 m; input/dress.yaml's 0.84-0.90 m bodice held 8 cm of T-shirt in folds
that stood between its side seams' edges, 54 mm open) and its armholes cut 5 cm deeper at the side seams (with
input/dress.yaml's straight top the side seams' top corners met the T-shirt's sleeves under the arms: sewn,
they were torn 63 mm apart again by the sleeve between them).
"""
import math
import os

import numpy as np
import yaml

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

# The body pieces (front = back).
WIDTH, SCOOP_TOP, SIDE, ARMHOLE, HEM_Y, SHOULDER, NECK_DIP = 0.46, 0.04, 0.308, 0.22, 0.092, 0.067, 0.04
SCOOP = np.array([[0, 0], [0.025, 0.015], [0.037, 0.04], [0.04, 0.07]])  # inward, up from the armpit
BODY_RADIUS, BODY_AXIS_Z = 0.19, 0.05
# The sleeves.
SLEEVE_ROUND, EASE, UNDERARM, SLEEVE_RADIUS, UNDERARM_T = 0.40, 1.05, 0.06, 0.075, 0.09
SHOULDER_POINT, ELBOW = np.array([-0.17, 0.52, 0.0]), np.array([-0.30, 0.36, 0.03])
GRIDS = {"body": [25, 25], "sleeve": [21, 9]}
# The dress over the T-shirt: one size up (every width of the bodice and the skirt times DRESS_GRADE), its
# armholes cut ARMHOLE_DROP deeper at the side seams, its bodice's hem (and the skirt's waist) at DRESS_WAIST_Y.
DRESS_GRADE, ARMHOLE_DROP, DRESS_WAIST_Y = 1.15, 0.05, 0.24
# The layered scene's pull (m/s^2; the T-shirt's alone is 1000): at 1000 the straps, flung down over the T-shirt's
# back, passed through it in the first 0.06 s.
LAYERED_PULL = 500


def polyline_length(points):
    return float(np.sum(np.linalg.norm(np.diff(np.asarray(points, float), axis=0), axis=1)))


def body_outline():
    """bottom, right, top, left of the front (and back) and the seam fractions: the armpit on the sides,
    the shoulder's end on the top."""
    height = SIDE + SCOOP[-1, 1] + ARMHOLE - polyline_length(SCOOP)
    right = [[WIDTH, 0], [WIDTH, SIDE]] + [[WIDTH - du, SIDE + dv] for du, dv in SCOOP[1:]] + [[WIDTH - SCOOP_TOP, height]]
    left = [[0, 0], [0, SIDE]] + [[du, SIDE + dv] for du, dv in SCOOP[1:]] + [[SCOOP_TOP, height]]
    mid = WIDTH / 2
    top = [[SCOOP_TOP, height], [SCOOP_TOP + SHOULDER, height], [mid - 0.06, height - 0.5 * NECK_DIP],
           [mid - 0.03, height - 0.9 * NECK_DIP], [mid, height - NECK_DIP], [mid + 0.03, height - 0.9 * NECK_DIP],
           [mid + 0.06, height - 0.5 * NECK_DIP], [WIDTH - SCOOP_TOP - SHOULDER, height], [WIDTH - SCOOP_TOP, height]]
    armpit = SIDE / polyline_length(right)
    shoulder = SHOULDER / polyline_length(top)
    return {"bottom": [[0, 0], [WIDTH, 0]], "right": right, "top": top, "left": left}, armpit, shoulder


def sleeve_outline():
    """The sleeve with its cap 5 % longer than the armhole (bisection on the cap height)."""
    def cap(amplitude, n):
        u = np.linspace(0, SLEEVE_ROUND, n)
        return np.column_stack([u, UNDERARM + amplitude * (1 - np.cos(2 * np.pi * u / SLEEVE_ROUND))])
    low, high = 0.0, 0.2
    for _ in range(60):
        amplitude = 0.5 * (low + high)
        low, high = (amplitude, high) if polyline_length(cap(amplitude, 2001)) < EASE * 2 * ARMHOLE else (low, amplitude)
    top = [[round(float(u), 6), round(float(v), 6)] for u, v in cap(low, 17)]
    return {"bottom": [[0, 0], [SLEEVE_ROUND, 0]], "right": [[SLEEVE_ROUND, 0], [SLEEVE_ROUND, UNDERARM]], "top": top,
            "left": [[0, 0], [0, UNDERARM]]}


def rounded(v):
    return [round(float(x), 6) + 0.0 for x in v]


def sleeve_placement(mirror):
    """origin, u_axis, v_axis, wrap of a sleeve: v down the arm's axis towards the shoulder, u across the top
    of the arm from its front to its back, the piece's middle on the top of the arm."""
    along = (ELBOW - SHOULDER_POINT) / np.linalg.norm(ELBOW - SHOULDER_POINT)
    up = np.array([0.0, 1.0, 0.0]) - along[1] * along
    up /= np.linalg.norm(up)
    across = np.cross(up, along)
    across *= -1 if across[2] > 0 else 1
    hem_on_axis = SHOULDER_POINT + (UNDERARM_T + UNDERARM) * along
    origin = hem_on_axis + SLEEVE_RADIUS * up - 0.5 * SLEEVE_ROUND * across
    m = np.array([-1.0, 1.0, 1.0]) if mirror else np.ones(3)
    return {"origin": rounded(origin * m), "u_axis": rounded(across * m), "v_axis": rounded(-along * m),
            "wrap": {"axis_point": rounded(hem_on_axis * m), "axis": rounded(along * m)}}


def tshirt():
    body, armpit, shoulder = body_outline()
    sleeve = sleeve_outline()
    pieces = []
    for name, x, z, u in (("front", -WIDTH / 2, BODY_AXIS_Z + BODY_RADIUS, 1), ("back", WIDTH / 2, BODY_AXIS_Z - BODY_RADIUS, -1)):
        pieces.append({"name": name, "fabric": "shirting", "grid": GRIDS["body"], "boundaries": body,
                       "origin": [x, HEM_Y, z], "u_axis": [u, 0, 0], "v_axis": [0, 1, 0],
                       "wrap": {"axis_point": [0, 0, BODY_AXIS_Z], "axis": [0, 1, 0]}})
    for side, mirror in (("left", False), ("right", True)):
        pieces.append(dict({"name": "sleeve_" + side, "fabric": "shirting", "grid": GRIDS["sleeve"], "boundaries": sleeve},
                           **sleeve_placement(mirror)))
    # The armpit node is shared by the side seam and the armhole: each stretch reaches 0.01 past it.
    a_lo, a_hi, sh, sh_back = round(armpit - 0.01, 4), round(armpit + 0.01, 4), round(shoulder, 4), round(1 - shoulder, 4)
    s = lambda piece, side, lo=0, hi=1: {"piece": piece, "side": side, "from": lo, "to": hi}  # noqa: E731
    seams = [
        {"name": "side_left", "a": s("front", "left", 0, a_hi), "b": s("back", "right", 0, a_hi)},
        {"name": "side_right", "a": s("front", "right", 0, a_hi), "b": s("back", "left", 0, a_hi)},
        {"name": "shoulder_left", "a": s("front", "top", 0, sh), "b": s("back", "top", 1, sh_back)},
        {"name": "shoulder_right", "a": s("front", "top", 1, sh_back), "b": s("back", "top", 0, sh)},
        {"name": "armhole_left_front", "a": s("sleeve_left", "top", 0, 0.5), "b": s("front", "left", a_lo, 1)},
        {"name": "armhole_left_back", "a": s("sleeve_left", "top", 1, 0.5), "b": s("back", "right", a_lo, 1)},
        {"name": "armhole_right_front", "a": s("sleeve_right", "top", 0, 0.5), "b": s("front", "right", a_lo, 1)},
        {"name": "armhole_right_back", "a": s("sleeve_right", "top", 1, 0.5), "b": s("back", "left", a_lo, 1)},
        {"name": "underarm_left", "a": s("sleeve_left", "left"), "b": s("sleeve_left", "right")},
        {"name": "underarm_right", "a": s("sleeve_right", "left"), "b": s("sleeve_right", "right")},
    ]
    return {
        "name": "tshirt", "gravity": [0, -9.81, 0],
        "fabrics": {"shirting": {"preset": "cotton_polyester", "damping": 2.0}},
        "pieces": pieces, "seams": seams,
        # tolerance 12 mm: at 5 mm (the dress's) the four pairs of the armholes' front and back lower thirds
        # stay 6-11 mm apart in the hollow between arm and chest, held there by the body's 4 mm contact shell
        # on either side; once sewn, the stiff spring draws them out of it together (0.3 mm).
        "sewing": {"pull_acceleration": 1000, "pull_radius": 0.005, "sewn_stiffness": 5000, "tolerance": 0.012,
                   "max_time": 3.5, "pull_friction": 0},
        "bodies": [{"name": "mannequin", "type": "mesh", "file": "mannequin/makehuman_body.obj", "scale": 0.1,
                    "friction": {"static": 0.6, "kinetic": 0.4}, "thickness": 0.004}],
        "self_collision": {"enabled": True, "thickness": 0.006, "stiffness": 20},
        "run": {"integrator": "implicit", "dt": 0.004, "t_final": 2.5, "output_every": 25},
    }


def deeper_armholes(outline):
    """A bodice's outline with its top ARMHOLE_DROP lower at both side seams: the side seams shortened, the top
    curving down to them from the inner 3/4 of its width, where the straps are sewn."""
    (u0, v0), (u1, _) = outline["left"][-1], outline["right"][-1]
    top_v = v0 - ARMHOLE_DROP
    scale = top_v / v0
    left_end, right_end = [outline["left"][0][0] + scale * (u0 - outline["left"][0][0]), top_v], \
        [outline["right"][0][0] + scale * (u1 - outline["right"][0][0]), top_v]
    width = u1 - u0
    curve = [[u0 + width * f, v0 - ARMHOLE_DROP * (1 - f / 0.15) ** 2] for f in (0.0375, 0.075, 0.1125, 0.15)]
    top = [left_end] + curve + [[u1 - (u - u0), v] for u, v in reversed(curve)] + [right_end]
    return dict(outline, left=[outline["left"][0], left_end], right=[outline["right"][0], right_end], top=top)


def dress_outside(dress):
    """input/dress.yaml's pieces placed outside the T-shirt's (see the module's docstring)."""
    bodice_radius, strap_radius, sin_alpha = 0.22, 0.28, 0.375
    cos_alpha = math.sqrt(1 - sin_alpha**2)
    apex_y = DRESS_WAIST_Y + 0.6 * cos_alpha  # the skirt's waist 0.6 m (slant) from its apex, at the bodice's hem
    for p in dress["pieces"]:
        front = p["name"].endswith("front")
        if not p["name"].startswith("strap"):
            p["boundaries"] = {side: [[DRESS_GRADE * u, v] for u, v in line] for side, line in p["boundaries"].items()}
        if p["name"].startswith("bodice"):
            p["boundaries"] = deeper_armholes(p["boundaries"])
        half = 0.21 * DRESS_GRADE
        if p["name"].startswith("bodice"):
            p["origin"] = [-half if front else half, DRESS_WAIST_Y, BODY_AXIS_Z + (bodice_radius if front else -bodice_radius)]
            p["wrap"] = {"axis_point": [0, 0, BODY_AXIS_Z], "axis": [0, 1, 0]}
        elif p["name"].startswith("strap"):
            p["origin"] = [p["origin"][0], 0.40 + strap_radius, BODY_AXIS_Z + 0.27]
            p["wrap"] = {"axis_point": [0, 0.40, BODY_AXIS_Z], "axis": [1, 0, 0]}
        elif p["name"].startswith("skirt"):
            s = -1 if front else 1
            p["v_axis"] = rounded([0, cos_alpha, s * sin_alpha])
            p["origin"] = rounded([-2 * half if front else 2 * half, apex_y - 1.2 * cos_alpha, BODY_AXIS_Z - 1.2 * s * sin_alpha])
            p["wrap"] = {"apex": rounded([0, apex_y, BODY_AXIS_Z]), "axis": [0, -1, 0]}
    return dress


class FlowListDumper(yaml.SafeDumper):
    pass


FlowListDumper.add_representer(
    list, lambda d, data: d.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=all(not isinstance(x, dict) for x in data)))


def plain(o):
    """The scene with numpy numbers as Python floats (rounded to 1e-6 m), which yaml writes."""
    if isinstance(o, dict):
        return {k: plain(v) for k, v in o.items()}
    if isinstance(o, list):
        return [plain(v) for v in o]
    if isinstance(o, (float, np.floating)):
        return round(float(o), 6) + 0.0
    return o


def write(path, scene, header):
    text = yaml.dump(plain(scene), Dumper=FlowListDumper, sort_keys=False, width=250)
    with open(path, "w") as f:
        f.write(header + text)


def main():
    doc = "# Written by scripts/tshirt_scenes.py (the pattern and its placement are explained there); edit that, not this.\n"
    shirt = tshirt()
    write(os.path.join(ROOT, "input", "tshirt.yaml"), shirt,
          "# A T-shirt with set-in sleeves sewn onto the mannequin: front, back and two sleeves, ten seams (sides,\n"
          "# shoulders, the armholes with the sleeve caps eased in, the sleeves' underarm seams).\n" + doc +
          "#   mpiexec -n 2 build/clothsim -scene input/tshirt.yaml\n")
    with open(os.path.join(ROOT, "input", "dress.yaml")) as f:
        dress = dress_outside(yaml.safe_load(f))
    both = dict(shirt, name="tshirt_dress")
    both["fabrics"] = dict(shirt["fabrics"], **dress["fabrics"])
    both["pieces"] = shirt["pieces"] + dress["pieces"]
    both["seams"] = shirt["seams"] + dress["seams"]
    both["sewing"] = dict(shirt["sewing"], pull_acceleration=LAYERED_PULL)
    write(os.path.join(ROOT, "input", "tshirt_dress.yaml"), both,
          "# Layering: the T-shirt of input/tshirt.yaml under the dress of input/dress.yaml (one size up, deeper\n"
          "# armholes, to go over the T-shirt), both sewn in one run;\n"
          "# cloth-cloth contact (self_collision, over all pieces of both) keeps the layers apart.\n" + doc +
          "#   mpiexec -n 2 build/clothsim -scene input/tshirt_dress.yaml\n")


if __name__ == "__main__":
    main()

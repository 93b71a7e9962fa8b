#!/usr/bin/python3
"""Peirce cantilever bending test (ASTM D1388) for clothsim: write the scene, measure the bending length.

A strip (2.5 cm wide) lies on a table with an overhang l beyond the edge; the part on the table is
clamped flat (its particles are pinned: the table and the weight of the fabric on it hold that part
flat). The tip sags under gravity; at equilibrium the chord from the table edge to the tip makes the
angle theta below the horizontal. ASTM D1388 finds the overhang l* at which theta = 41.5 degrees and
reports the bending length c = l* / 2. For a fabric of bending rigidity B (N m) and areal weight
W = density g (N/m^2) the exact heavy elastica of a clamped inextensible strip (postprocess/elastica.py)
gives theta = 41.5 degrees at l* = 2.00035 c with c = (B / W)^(1/3), i.e. c = 0.49991 l*. (Peirce's closed
form c = l* (cos(theta/2) / (8 tan theta))^(1/3) = 0.5093 l*, which this tool used before, approximates the
elastica and reads 1.9% high.)

Instead of bisecting l with one run per trial, one scene holds strips of several overhangs for every
fabric and direction (pieces do not interact). Each strip's tip angle is turned into the bending length
of the exact elastica with that angle at that overhang, c(l) = l / (L/c)(theta) (postprocess/elastica.py);
c(l) is interpolated linearly in theta to 41.5 degrees between the two strips that bracket it, and
l* = 2.00035 c. (c(l) varies only through the discretisation error, so the interpolation adds almost none.)

  scene:   write the YAML scene (strips named FABRIC_DIRECTION_LMM, DIRECTION warp or weft)
  measure: read the final checkpoint and the run's log (clothsim prints each fabric's density and
           bending rigidity), print simulated and theoretical bending lengths, optionally check them

    /usr/bin/python3 postprocess/cantilever.py scene --presets denim polyester -o input/cantilever.yaml
    mpiexec -n 1 build/clothsim -scene input/cantilever.yaml | tee cantilever.log
    /usr/bin/python3 postprocess/cantilever.py measure output/cantilever/checkpoint_*.h5 \\
        --scene input/cantilever.yaml --log cantilever.log [--tolerance 0.10]
"""
import argparse
import json
import math
import re
import sys

import numpy as np

import cloth_state
import elastica

THETA = elastica.ASTM_ANGLE  # degrees, ASTM D1388
PEIRCE = elastica.peirce_ratio(THETA)  # 0.5093: Peirce's approximate c / l*, for comparison only
WIDTH = 0.025  # m, ASTM D1388 strip width
ACROSS = 3     # nodes across the strip


def strip_piece(fabric, direction, overhang, segments, table_segments, z):
    """One strip: along x from x = -table length to x = overhang, table edge at x = 0, at height y = 0."""
    h = overhang / segments
    table = table_segments * h
    length_nodes = table_segments + segments + 1
    along_u = direction == "warp"  # warp threads run along u (i): a warp strip bends its warp threads
    piece = {
        "name": f"{fabric}_{direction}_{overhang * 1e3:.2f}".replace(".", "p"),
        "fabric": fabric,
        "grid": [length_nodes, ACROSS] if along_u else [ACROSS, length_nodes],
        "size": [table + overhang, WIDTH] if along_u else [WIDTH, table + overhang],
        "origin": [-table, 0.0, z],
        "u_axis": [1, 0, 0] if along_u else [0, 0, 1],
        "v_axis": [0, 0, 1] if along_u else [1, 0, 0],
        # the clamped table part, with a quarter segment of slack so that the edge node is included
        "pin_box": {"min": [-1e-6, -1e-6], "max": [table + 0.25 * h, WIDTH + 1e-6]} if along_u
        else {"min": [-1e-6, -1e-6], "max": [WIDTH + 1e-6, table + 0.25 * h]},
    }
    return piece


def flow(value):
    """YAML flow text of a small structure (lists/dicts of numbers and names)."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(flow(v) for v in value) + "]"
    if isinstance(value, float):
        return repr(round(value, 12))
    return str(value)


def write_scene(args, out):
    overhangs = np.geomspace(args.lmin, args.lmax, args.count)
    lines = [
        "# Peirce cantilever bending test (ASTM D1388), written by postprocess/cantilever.py:",
        "#   /usr/bin/python3 postprocess/cantilever.py scene " + " ".join(sys.argv[2:]),
        "# Strips FABRIC_DIRECTION_L (L: overhang in mm, 'p' for the point), 2.5 cm wide, clamped on the table",
        "# (x < 0), overhang along +x; the tip angle at rest gives the bending length (docs/validation.md).",
        "name: cantilever",
        "gravity: [0, -9.81, 0]",
        "fabrics:",
    ]
    for fabric in args.presets:
        lines += [f"  {fabric}:", f"    preset: {fabric}", f"    damping: {args.damping}"]
    lines.append("pieces:")
    z = 0.0
    for fabric in args.presets:
        for direction in ("warp", "weft"):
            for overhang in overhangs:
                piece = strip_piece(fabric, direction, float(overhang), args.segments, args.table_segments, z)
                lines.append("  - " + "\n    ".join(f"{k}: {flow(v)}" for k, v in piece.items()))
                z += 2 * WIDTH
    lines += ["run:", "  integrator: implicit", f"  dt: {args.dt}", f"  t_final: {args.t_final}", "  output_every: 10", ""]
    out.write("\n".join(lines))


def fabric_values(log_path):
    """{fabric: (density, bend_warp, bend_weft)} from the scene summary clothsim prints."""
    pattern = re.compile(r"fabric '([^']+)':.*?density ([0-9.eE+-]+) kg/m\^2.*?bend ([0-9.eE+-]+)/([0-9.eE+-]+) N m")
    values = {}
    with open(log_path) as f:
        for line in f:
            m = pattern.search(line)
            if m:
                values[m.group(1)] = tuple(float(m.group(k)) for k in (2, 3, 4))
    if not values:
        raise SystemExit(f"{log_path}: no fabric summary lines (expected clothsim's scene summary with angle bending)")
    return values


def tip_angle(p, along_u):
    """Tip angle (degrees below the horizontal) of a strip's final positions p (nv, nu, 3)."""
    rows = p if along_u else np.transpose(p, (1, 0, 2))  # rows[across, along]
    xs0 = rows[:, :, 0].mean(axis=0)
    edge = int(np.argmin(np.abs(xs0)))  # the node at the table edge, x = 0
    tip = rows[:, -1, :].mean(axis=0)
    base = rows[:, edge, :].mean(axis=0)
    return math.degrees(math.atan2(base[1] - tip[1], tip[0] - base[0]))


def crossing(ls, thetas):
    """Overhang where theta(l) = 41.5 degrees, by log-log interpolation between bracketing points."""
    order = np.argsort(ls)
    ls, thetas = np.asarray(ls)[order], np.asarray(thetas)[order]
    for k in range(len(ls) - 1):
        if thetas[k] <= THETA <= thetas[k + 1]:
            t = (math.log(THETA) - math.log(thetas[k])) / (math.log(thetas[k + 1]) - math.log(thetas[k]))
            return math.exp(math.log(ls[k]) + t * (math.log(ls[k + 1]) - math.log(ls[k])))
    return None


def elastica_length(thetas, cs):
    """Bending length at 41.5 degrees: the strips' elastica lengths c(l) interpolated linearly in theta between
    the two strips (ordered by theta) that bracket 41.5 degrees; None if none do."""
    order = np.argsort(thetas)
    thetas, cs = np.asarray(thetas)[order], np.asarray(cs)[order]
    for k in range(len(thetas) - 1):
        if thetas[k] <= THETA <= thetas[k + 1]:
            t = (THETA - thetas[k]) / (thetas[k + 1] - thetas[k]) if thetas[k + 1] > thetas[k] else 0.0
            return float(cs[k] + t * (cs[k + 1] - cs[k]))
    return None


def measure(args):
    scene = cloth_state.read_scene(args.scene)
    x = cloth_state.read_positions(args.checkpoint)
    g = float(np.linalg.norm(scene.get("gravity", [0, -9.81, 0])))
    values = fabric_values(args.log)
    ratio = elastica.ratio_at(THETA)  # l* / c of the exact elastica, 2.00035
    curves = {}
    for (name, nu, nv, offset), piece in zip(cloth_state.piece_grids(scene), scene["pieces"]):
        fabric, direction = piece["fabric"], ("warp" if piece["u_axis"] == [1, 0, 0] else "weft")
        overhang = piece["size"][0 if direction == "warp" else 1] - abs(piece["origin"][0])
        theta = tip_angle(cloth_state.piece_positions(x, nu, nv, offset), direction == "warp")
        curves.setdefault((fabric, direction), []).append((overhang, theta))
    results, ok = [], True
    for (fabric, direction), pts in curves.items():
        density, bend_warp, bend_weft = values[fabric]
        bend = bend_warp if direction == "warp" else bend_weft
        c_theory = (bend / (density * g)) ** (1 / 3)
        pts.sort()
        # every strip's own elastica bending length (only strips whose angle the elastica solver covers)
        strips = [(l, t, elastica.bending_length(l, t)) for l, t in pts if 0 < t < 70]
        c_sim = elastica_length([s[1] for s in strips], [s[2] for s in strips])
        l_star = ratio * c_sim if c_sim else None
        err = (c_sim - c_theory) / c_theory if c_sim else None
        good = err is not None and abs(err - args.expect_error) <= args.tolerance
        ok = ok and good
        l_loglog = crossing([p[0] for p in pts], [p[1] for p in pts])
        results.append({"fabric": fabric, "direction": direction, "B_Nm": bend, "density": density,
                        "c_theory_cm": 100 * c_theory, "overhang_cm": 100 * l_star if l_star else None,
                        "c_sim_cm": 100 * c_sim if c_sim else None, "error": err,
                        "c_peirce_cm": 100 * PEIRCE * l_loglog if l_loglog else None,
                        "angles": [(round(100 * l, 3), round(t, 2)) for l, t in pts],
                        "strip_errors": [(round(100 * l, 4), round(t, 4), (c / c_theory - 1)) for l, t, c in strips]})
    return results, ok


def convergence(args):
    """Error of c against the segment count from `measure --json` files (one per resolution): a Markdown table
    with the observed order between successive resolutions, and a log-log picture."""
    rows = {}
    for path in args.files:
        m = re.search(r"(\d+)\.json$", path)
        if not m:
            raise SystemExit(f"{path}: the file name must end in the segment count, e.g. cantilever_30.json")
        with open(path) as f:
            for r in json.load(f):
                rows.setdefault((r["fabric"], r["direction"]), {})[int(m.group(1))] = r
    print("| fabric | direction | c = (B/W)^(1/3), cm | segments | l* at 41.5 deg, cm | c (exact elastica), cm | error | observed order |")
    print("|---|---|---|---|---|---|---|---|")
    curves = {}
    for (fabric, direction), by_n in rows.items():
        previous = None
        for n in sorted(by_n):
            r = by_n[n]
            err = r["error"]
            order = "-"
            if previous and err and previous[1] and err * previous[1] > 0:
                order = f"{math.log(abs(previous[1] / err)) / math.log(n / previous[0]):.2f}"
            lst = f"{r['overhang_cm']:.3f}" if r["overhang_cm"] else "-"
            sim = f"{r['c_sim_cm']:.4f}" if r["c_sim_cm"] else "not bracketed"
            e = f"{100 * err:+.2f}%" if err is not None else "-"
            print(f"| {fabric} | {direction} | {r['c_theory_cm']:.3f} | {n} | {lst} | {sim} | {e} | {order} |")
            previous = (n, err)
            if err is not None:
                curves.setdefault(f"{fabric} {direction}", []).append((n, abs(err)))
    if args.out:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5.5, 4))
        for label, pts in curves.items():
            ax.loglog([p[0] for p in pts], [100 * p[1] for p in pts], "o-", label=label)
        ns = sorted({p[0] for pts in curves.values() for p in pts})
        if ns and curves:
            ref = max(p[1] for pts in curves.values() for p in pts if p[0] == ns[0])
            ax.loglog(ns, [100 * ref * ns[0] / n for n in ns], "k--", lw=0.8, label="first order (1/N)")
        from matplotlib.ticker import FixedLocator, NullLocator, ScalarFormatter

        ax.xaxis.set_major_locator(FixedLocator(ns))
        ax.xaxis.set_minor_locator(NullLocator())
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.yaxis.set_major_formatter(ScalarFormatter())
        ax.yaxis.set_minor_formatter(ScalarFormatter())
        ax.set_xlabel("segments along the overhang N")
        ax.set_ylabel("|error of c| against the exact elastica, %")
        ax.set_title("Cantilever (ASTM D1388): grid convergence")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.out, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    s = sub.add_parser("scene", help="write the cantilever scene")
    s.add_argument("--presets", nargs="+", default=["denim", "cotton_polyester", "polyester", "cotton_knit"], help="fabric presets")
    s.add_argument("--lmin", type=float, default=0.016, help="shortest overhang, m (default 0.016)")
    s.add_argument("--lmax", type=float, default=0.05, help="longest overhang, m (default 0.05)")
    s.add_argument("--count", type=int, default=7, help="overhangs per fabric and direction, geometric (default 7)")
    s.add_argument("--segments", type=int, default=20, help="segments along the overhang (default 20)")
    s.add_argument("--table-segments", type=int, default=3, help="segments clamped on the table (default 3)")
    s.add_argument("--damping", type=float, default=5.0, help="damping rate, 1/s (default 5)")
    s.add_argument("--dt", type=float, default=0.02, help="time step, s (default 0.02)")
    s.add_argument("--t-final", type=float, default=3.0, help="simulated time, s (default 3)")
    s.add_argument("-o", "--output", help="output file (default stdout)")
    m = sub.add_parser("measure", help="measure the bending lengths from a finished run")
    m.add_argument("checkpoint", help="final checkpoint of the run")
    m.add_argument("--scene", required=True, help="the scene the run used")
    m.add_argument("--log", required=True, help="the run's standard output (holds the fabric summary)")
    m.add_argument("--tolerance", type=float, default=0.10, help="relative tolerance on c (default 0.10)")
    m.add_argument("--expect-error", type=float, default=0.0,
                   help="expected relative error of c (the discretisation's, from the convergence study); the check "
                        "asks |error - this| <= tolerance (default 0)")
    m.add_argument("--check", action="store_true", help="exit with status 1 unless every bending length is within the tolerance")
    m.add_argument("--json", action="store_true", help="print JSON")
    v = sub.add_parser("convergence", help="error against the segment count from measure --json files")
    v.add_argument("files", nargs="+", help="measure --json outputs, named ..._N.json with N the segment count")
    v.add_argument("--out", help="picture of |error| against N (PNG)")
    args = parser.parse_args()
    if args.command == "convergence":
        convergence(args)
        return
    if args.command == "scene":
        if args.output:
            with open(args.output, "w") as out:
                write_scene(args, out)
        else:
            write_scene(args, sys.stdout)
        return
    results, ok = measure(args)
    if args.json:
        json.dump(results, sys.stdout, indent=1)
        print()
    else:
        width = max([18] + [len(r["fabric"]) for r in results])
        print(f"{'fabric':{width}s} {'dir':5s} {'c=(B/W)^1/3':>12s} {'l* (41.5deg)':>13s} {'c (elastica)':>12s} {'error':>7s}")
        for r in results:
            sim = f"{r['c_sim_cm']:.3f} cm" if r["c_sim_cm"] else "not bracketed"
            lst = f"{r['overhang_cm']:.3f} cm" if r["overhang_cm"] else "-"
            err = f"{100 * r['error']:+.2f}%" if r["error"] is not None else "-"
            print(f"{r['fabric']:{width}s} {r['direction']:5s} {r['c_theory_cm']:9.3f} cm {lst:>13s} {sim:>12s} {err:>7s}")
            print("    (overhang cm, tip angle deg): " + ", ".join(f"({l}, {t})" for l, t in r["angles"]))
    if args.check and not ok:
        print(f"FAILED: a bending length's error against (B/W)^(1/3) is not {100 * args.expect_error:+.2f}% +- {100 * args.tolerance:.2f}% or 41.5 deg was not bracketed", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()

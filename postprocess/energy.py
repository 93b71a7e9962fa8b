#!/usr/bin/python3
"""Energy and strain against time from a clothsim XDMF series (NAME.h5 next to NAME.xdmf).

For every frame /frames/NNNNNN of the series it computes
  kinetic energy        1/2 sum m_i |v_i|^2                                      (J)
  gravitational energy  -sum m_i g . x_i  (zero at the origin: m g h for a sheet at height h)  (J)
  link strain           |x_b - x_a| / |X_b - X_a| - 1 over the edges of the fabric's quads
                        (the structural threads), largest stretch and largest compression
where the rest lengths |X_b - X_a| come from the first frame (step 0: pattern pieces start flat and
unstretched) and the particle masses m_i are those of the simulator (src/model.c): with the scene's
`mass: area` (the default) each particle carries density x a quarter of the area of each of its quads,
with `mass: uniform` density x piece area / particle count; gravity and densities come from the scene
(--scene, YAML) or --gravity / --density.

The elastic energy needs the fabric model itself: run clothsim with -monitor_energy, save its output and
pass it with --log; the simulator's own kinetic, gravitational, elastic and total energy are then read
from its "energy at step N" lines and drawn too (they use the same zero of gravitational energy).

Writes a PNG (two panels: energies, strain) and, with --csv, a table; prints the table's first and last
rows. Example:

  build/clothsim -scene input/hanging_sheet.yaml -grid 33 -monitor_energy | tee run.log
  postprocess/energy.py output/hanging_sheet/hanging_sheet.xdmf --scene input/hanging_sheet.yaml \\
      --grid 33 --log run.log --out energy.png --csv energy.csv
"""
import argparse
import os
import re
import sys

import numpy as np

from cloth_state import finish_axis, piece_grids, read_series, save_figure, series_h5, write_csv


def quad_areas(x, quads):
    """Area of each (planar or nearly planar) quad: half the norm of the cross product of its diagonals."""
    d1 = x[quads[:, 2]] - x[quads[:, 0]]
    d2 = x[quads[:, 3]] - x[quads[:, 1]]
    return 0.5 * np.linalg.norm(np.cross(d1, d2), axis=1)


def piece_ranges(scene, nparticles, grid):
    """[(first, count, piece dict)] of the scene's pieces (the numbering of cloth_state.piece_grids); grid
    overrides one-piece grid scenes (-grid N). None when a piece's grid is unknown or the counts do not add
    up to nparticles."""
    try:
        grids = piece_grids(scene, grid)
    except (KeyError, TypeError):
        return None
    if not grids or grids[-1][3] + grids[-1][1] * grids[-1][2] != nparticles:
        return None
    return [(offset, nu * nv, piece) for (_, nu, nv, offset), piece in zip(grids, scene["pieces"])]


def particle_masses(rest, quads, scene, density, grid):
    """Masses of the particles as src/model.c lumps them (see the module doc)."""
    n = rest.shape[0]
    area = quad_areas(rest, quads)
    fabrics = (scene or {}).get("fabrics", {}) or {}
    pieces = piece_ranges(scene, n, grid) if scene else None
    if pieces is None:
        if scene and scene.get("pieces"):
            print(f"energy.py: the scene's pieces do not add up to the {n} particles of the series "
                  f"(set --grid N as given to clothsim); using --density and area lumping", file=sys.stderr)
        if density is None:
            raise SystemExit("energy.py: need the particle masses: give --scene (and --grid) or --density")
        mass = np.zeros(n)
        np.add.at(mass, quads.ravel(), np.repeat(0.25 * area * density, 4))
        return mass
    mass = np.zeros(n)
    owner = np.zeros(n, dtype=np.int64)
    for k, (first, count, _) in enumerate(pieces):
        owner[first:first + count] = k
    qpiece = owner[quads[:, 0]]
    for k, (first, count, piece) in enumerate(pieces):
        rho = density
        if rho is None:
            fabric = fabrics.get(piece.get("fabric"), {}) or {}
            if "density" not in fabric:
                raise SystemExit(f"energy.py: fabric '{piece.get('fabric')}' of piece '{piece.get('name')}' has no density "
                                 "in the scene (a preset?): give --density KG_PER_M2")
            rho = float(fabric["density"])
        mine = qpiece == k
        if piece.get("mass", "area") == "uniform":
            mass[first:first + count] = rho * area[mine].sum() / count
        else:
            np.add.at(mass, quads[mine].ravel(), np.repeat(0.25 * area[mine] * rho, 4))
    return mass


def unique_edges(quads):
    e = np.concatenate([quads[:, [0, 1]], quads[:, [1, 2]], quads[:, [2, 3]], quads[:, [3, 0]]])
    e.sort(axis=1)
    return np.unique(e, axis=0)


ENERGY_LINE = re.compile(r"energy at step\s+(\d+):\s*kinetic\s+(\S+) J, gravity\s+(\S+) J, elastic\s+(\S+) J, total\s+(\S+) J")


def read_log(path):
    """{step: (kinetic, gravity, elastic, total)} from clothsim -monitor_energy output."""
    out = {}
    with open(path, errors="replace") as f:
        for line in f:
            m = ENERGY_LINE.search(line)
            if m:
                out[int(m.group(1))] = tuple(float(m.group(k)) for k in range(2, 6))
    if not out:
        print(f"energy.py: no 'energy at step' lines in {path} (run clothsim with -monitor_energy)", file=sys.stderr)
    return out


def analyse(frames, quads, mass, gravity):
    rest = frames[0]["position"]
    edges = unique_edges(quads)
    rest_len = np.linalg.norm(rest[edges[:, 1]] - rest[edges[:, 0]], axis=1)
    rows = []
    for frame in frames:
        step, time, x, v = frame["step"], frame["time"], frame["position"], frame["velocity"]
        length = np.linalg.norm(x[edges[:, 1]] - x[edges[:, 0]], axis=1)
        strain = length / rest_len - 1.0
        rows.append({
            "step": step, "time": time,
            "kinetic": 0.5 * float(np.sum(mass * np.sum(v * v, axis=1))),
            "gravity": -float(np.sum(mass * (x @ gravity))),
            "max_strain": float(strain.max()), "min_strain": float(strain.min()),
            "mean_abs_strain": float(np.mean(np.abs(strain))),
        })
    return rows


def plot(rows, log, out, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.array([r["time"] for r in rows])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    ax1.plot(t, [r["kinetic"] for r in rows], "o-", ms=3, label="kinetic")
    g0 = rows[0]["gravity"]
    ax1.plot(t, [r["gravity"] - g0 for r in rows], "s-", ms=3, label=f"gravitational - {g0:.4g} J")
    if log:
        steps = sorted(log)
        dt = rows[-1]["time"] / rows[-1]["step"] if rows[-1]["step"] else 0.0
        tl = np.array(steps) * dt
        ax1.plot(tl, [log[s][2] for s in steps], "^-", ms=3, label="elastic (clothsim)")
        ax1.plot(tl, [log[s][3] - g0 for s in steps], "k--", lw=1, label=f"total (clothsim) - {g0:.4g} J")
    finish_axis(ax1, "energy, J", title=title)
    ax2.plot(t, 100 * np.array([r["max_strain"] for r in rows]), "o-", ms=3, label="largest stretch")
    ax2.plot(t, 100 * np.array([r["min_strain"] for r in rows]), "s-", ms=3, label="largest compression")
    ax2.plot(t, 100 * np.array([r["mean_abs_strain"] for r in rows]), "-", label="mean |strain|")
    finish_axis(ax2, "link strain, %", xlabel="time, s")
    save_figure(fig, out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("series", help="NAME.xdmf (or NAME.h5) written by clothsim")
    p.add_argument("--scene", help="the scene YAML of the run: gravity, densities, mass distribution")
    p.add_argument("--grid", type=int, help="the run's -grid N, if it was given")
    p.add_argument("--density", type=float, help="areal density, kg/m^2, for every piece (overrides the scene)")
    p.add_argument("--gravity", type=float, nargs=3, metavar=("GX", "GY", "GZ"),
                   help="gravity, m/s^2 (default: the scene's, else 0 -9.81 0)")
    p.add_argument("--log", help="clothsim output of a -monitor_energy run: adds its elastic and total energy")
    p.add_argument("--out", default="energy.png", help="the PNG to write (default energy.png)")
    p.add_argument("--csv", help="also write the table here")
    args = p.parse_args(argv)

    h5 = series_h5(args.series)
    frames, quads = read_series(h5)
    scene = None
    if args.scene:
        import yaml
        with open(args.scene) as f:
            scene = yaml.safe_load(f) or {}
    gravity = np.array(args.gravity if args.gravity else (scene or {}).get("gravity", [0.0, -9.81, 0.0]), float)
    if frames[0]["step"] != 0:
        print(f"energy.py: the first frame is step {frames[0]['step']}, not 0: strains are relative to it", file=sys.stderr)
    mass = particle_masses(frames[0]["position"], quads, scene, args.density, args.grid)
    rows = analyse(frames, quads, mass, gravity)
    log = read_log(args.log) if args.log else None

    if args.csv:
        write_csv(args.csv, rows)
    plot(rows, log, args.out, f"{os.path.basename(args.series)}: {len(mass)} particles, mass {mass.sum():.6g} kg")
    print(f"{len(rows)} frames, {len(mass)} particles, total mass {mass.sum():.9g} kg")
    print(f"{'step':>7} {'time/s':>10} {'kinetic/J':>14} {'gravity/J':>14} {'max strain':>11} {'min strain':>11}")
    for r in (rows[0], rows[-1]) if len(rows) > 1 else rows:
        print(f"{r['step']:7d} {r['time']:10.5f} {r['kinetic']:14.8e} {r['gravity']:14.8e} "
              f"{r['max_strain']:11.3e} {r['min_strain']:11.3e}")
    print(f"wrote {args.out}" + (f" and {args.csv}" if args.csv else ""))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Contact counts and link strain against time from a clothsim XDMF series (NAME.h5 next to NAME.xdmf).

For every frame /frames/NNNNNN of the series it reads what clothsim recorded at that step
(docs/checkpoint.md "XDMF series"):
  body_contacts           particles in contact with a rigid body (sphere, plane, mesh) in the frame's
                          step: moved onto the surface, or within the contact slop of it (for spheres
                          and planes: closer than 1.5 x the body's thickness), summed over the ranks
  self_contacts           cloth-cloth contacts of the step's last search: point-triangle and edge-edge
                          pairs within the self-collision thickness plus their travel over the step
  self_contact_particles  particles taking part in one or more of those contacts
and from the per-particle strain dataset (for each particle the largest relative elongation of its
stretch links, the warp and weft threads to its grid neighbours):
  max_strain              the largest link stretch of the frame (the same as energy.py's max_strain)
  mean_strain             the mean over the particles of their largest link stretch
Runs without bodies or without self-collision record zero counts.

Writes a PNG (two panels: contact counts, strain) and, with --csv, a table; prints the frames where
contacts first appear and the last frame. Example:

  mpiexec -n 2 build/clothsim -scene input/two_sheets_sphere.yaml -output_dir out/two_sheets
  postprocess/contacts.py out/two_sheets/two_sheets_sphere.xdmf --out contacts.png --csv contacts.csv
"""
import argparse
import os

import numpy as np

from cloth_state import finish_axis, read_series, save_figure, series_h5, write_csv

COUNTS = ("body_contacts", "self_contacts", "self_contact_particles")


def analyse(frames):
    """One row per frame: step, time, the three counts, max_strain and mean_strain."""
    rows = []
    for frame in frames:
        strain = frame["strain"].ravel()
        row = {"step": frame["step"], "time": frame["time"]}
        row.update({c: int(frame[c]) for c in COUNTS})
        row.update({"max_strain": float(strain.max()), "mean_strain": float(strain.mean())})
        rows.append(row)
    return rows


def first_frame_with(rows, count):
    """The first row whose count is above zero, or None."""
    return next((r for r in rows if r[count] > 0), None)


def plot(rows, out, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.array([r["time"] for r in rows])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    ax1.plot(t, [r["body_contacts"] for r in rows], "o-", ms=3, label="particles on a body")
    ax1.plot(t, [r["self_contact_particles"] for r in rows], "s-", ms=3, label="particles in cloth-cloth contact")
    ax1.plot(t, [r["self_contacts"] for r in rows], "^--", ms=3, label="cloth-cloth contacts (pairs)")
    finish_axis(ax1, "count", title=title)
    ax2.plot(t, 100 * np.array([r["max_strain"] for r in rows]), "o-", ms=3, label="largest link stretch")
    ax2.plot(t, 100 * np.array([r["mean_strain"] for r in rows]), "s-", ms=3, label="mean over particles of their largest")
    finish_axis(ax2, "link strain, %", xlabel="time, s")
    save_figure(fig, out)


def report(rows):
    print(f"{len(rows)} frames")
    print(f"{'step':>7} {'time/s':>10} {'body':>6} {'self pairs':>10} {'self part.':>10} {'max strain':>11} {'mean strain':>11}")
    shown = [first_frame_with(rows, "body_contacts"), first_frame_with(rows, "self_contacts"), rows[-1]]
    for r in sorted({id(r): r for r in shown if r is not None}.values(), key=lambda r: r["step"]):
        print(f"{r['step']:7d} {r['time']:10.5f} {r['body_contacts']:6d} {r['self_contacts']:10d} "
              f"{r['self_contact_particles']:10d} {r['max_strain']:11.3e} {r['mean_strain']:11.3e}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("series", help="NAME.xdmf (or NAME.h5) written by clothsim")
    p.add_argument("--out", default="contacts.png", help="the PNG to write (default contacts.png)")
    p.add_argument("--csv", help="also write the table here")
    args = p.parse_args(argv)

    frames, _ = read_series(series_h5(args.series), datasets=("strain",), attributes=COUNTS)
    rows = analyse(frames)
    if args.csv:
        write_csv(args.csv, rows)
    plot(rows, args.out, f"{os.path.basename(args.series)}: {frames[0]['strain'].shape[0]} particles")
    report(rows)
    print(f"wrote {args.out}" + (f" and {args.csv}" if args.csv else ""))


if __name__ == "__main__":
    main()

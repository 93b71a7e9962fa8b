#!/usr/bin/python3
"""Checks the fit maps of the last frame of a series against answers known without the simulator.

  check_fit_maps.py pressure SERIES.h5 --expect P --rtol R --min-contacts N
      every particle's contact pressure is P (N/m^2) within relative R, and at least N particles are in
      contact with a body (a sheet at rest on a flat table: P = areal mass x g)
  check_fit_maps.py stress SERIES.h5 --grid NU NV --column I --density RHO --gravity G --spacing DV --atol A
      down column I of a sheet hanging from its pinned top row (j = 0), the stress of particle (I, j) is
      the weight per unit width of the fabric below its upper link, RHO G (H - (j - 1/2) DV) for j >= 1
      and RHO G (H - DV/2) for j = 0 (H = (NV - 1) DV: the last row carries half a cell), within A N/m

Exits non-zero with a FAIL: line when a check fails."""
import argparse
import sys

import h5py
import numpy as np


def last_frame(path):
    with h5py.File(path, "r") as f:
        name = sorted(f["/frames"].keys())[-1]
        g = f["/frames/" + name]
        return name, {k: g[k][...] for k in g.keys()}, dict(g.attrs)


def check_pressure(args):
    name, fields, attrs = last_frame(args.series)
    p = fields["pressure"].ravel()
    worst = np.max(np.abs(p - args.expect)) / args.expect
    print(f"frame {name}: {len(p)} particles, pressure {p.min():.9g} .. {p.max():.9g} N/m^2 (expected {args.expect:g}), "
          f"largest relative deviation {worst:.3e}, {attrs['body_contacts']} in contact")
    ok = worst <= args.rtol and attrs["body_contacts"] >= args.min_contacts
    return ok


def check_stress(args):
    name, fields, _ = last_frame(args.series)
    nu, nv = args.grid
    s = fields["stress"].reshape(nv, nu)[:, args.column]
    height = (nv - 1) * args.spacing
    above = height - (np.arange(nv) - 0.5) * args.spacing
    above[0] = height - 0.5 * args.spacing
    expect = args.density * args.gravity * above
    worst = np.max(np.abs(s - expect))
    print(f"frame {name}: column {args.column}, stress at the top {s[0]:.6g} N/m (expected {expect[0]:.6g}), "
          f"largest deviation down the column {worst:.3e} N/m")
    return worst <= args.atol


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="what", required=True)
    p = sub.add_parser("pressure")
    p.add_argument("series")
    p.add_argument("--expect", type=float, required=True)
    p.add_argument("--rtol", type=float, required=True)
    p.add_argument("--min-contacts", type=int, required=True)
    s = sub.add_parser("stress")
    s.add_argument("series")
    s.add_argument("--grid", type=int, nargs=2, required=True)
    s.add_argument("--column", type=int, required=True)
    s.add_argument("--density", type=float, required=True)
    s.add_argument("--gravity", type=float, required=True)
    s.add_argument("--spacing", type=float, required=True)
    s.add_argument("--atol", type=float, required=True)
    args = parser.parse_args()
    ok = check_pressure(args) if args.what == "pressure" else check_stress(args)
    if not ok:
        print(f"FAIL: the {args.what} map differs from the expected values beyond the tolerance")
        sys.exit(1)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Completes and checks the quality record of an assembled garment.

  /usr/bin/python3 postprocess/garment_quality.py OUTPUT_DIR [--name dress] [--check]

clothsim writes OUTPUT_DIR/quality.json at the end of a run with seams (src/quality.h): the widest seam
gap, particles inside the body, the largest link strain, the kinetic energy, wall time and ranks. This
tool adds `fabric_crossings`: the number of fabric edges crossing fabric triangles in the last frame of
OUTPUT_DIR/NAME.h5, by the edge-triangle test of tests/check_self_intersection.py (the same test the
self-collision tests use), and rewrites the file.

With --check it also exits non-zero unless the garment meets the targets of issue 8: every seam closed
(max_seam_gap_m < 0.002, all pairs sewn), no particle inside the body, no fabric crossing, max_link_strain
< 0.10 and kinetic_energy_j below --ke-max (default 1e-3 J: at rest)."""
import argparse
import json
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from check_self_intersection import crossings, primitives  # noqa: E402


def last_frame_crossings(h5path):
    with h5py.File(h5path, "r") as f:
        quads = f["/topology/quads"][:].astype(np.int64)
        frames = sorted(f["/frames"].keys())
        x = f["/frames/" + frames[-1] + "/position"][:]
    tris, edges = primitives(quads)
    count, _ = crossings(x, tris, edges)
    return count, frames[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output_dir")
    parser.add_argument("--name", default="dress", help="scene name: the series is OUTPUT_DIR/NAME.h5 (default dress)")
    parser.add_argument("--check", action="store_true", help="fail unless the targets of issue 8 are met")
    parser.add_argument("--ke-max", type=float, default=1e-3, help="kinetic energy (J) below which the garment is at rest")
    args = parser.parse_args()
    qpath = os.path.join(args.output_dir, "quality.json")
    with open(qpath) as f:
        quality = json.load(f)
    quality["fabric_crossings"], frame = last_frame_crossings(os.path.join(args.output_dir, args.name + ".h5"))
    with open(qpath, "w") as f:
        json.dump(quality, f, indent=2)
        f.write("\n")
    print(json.dumps(quality, indent=2))
    print(f"fabric crossings counted in frame {frame}")
    if not args.check:
        return 0
    failures = []
    if not (quality["max_seam_gap_m"] < 0.002 and quality["sewn_pairs"] == quality["seam_pairs"]):
        failures.append(f"seams not closed: widest gap {quality['max_seam_gap_m']} m, {quality['sewn_pairs']}/{quality['seam_pairs']} sewn")
    if quality["particles_inside_body"] != 0:
        failures.append(f"{quality['particles_inside_body']} particles inside the body")
    if quality["fabric_crossings"] != 0:
        failures.append(f"{quality['fabric_crossings']} fabric edges cross fabric triangles")
    if not quality["max_link_strain"] < 0.10:
        failures.append(f"max link strain {quality['max_link_strain']} >= 0.10")
    if not quality["kinetic_energy_j"] < args.ke_max:
        failures.append(f"kinetic energy {quality['kinetic_energy_j']} J >= {args.ke_max} J: not at rest")
    for message in failures:
        print("garment_quality: FAILED: " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Completes and checks the quality record of an assembled garment.

  /usr/bin/python3 postprocess/garment_quality.py OUTPUT_DIR [--name dress] [--check]

clothsim writes OUTPUT_DIR/quality.json at the end of a run with seams (src/quality.h): the widest seam
gap, particles inside the body, the largest link strain, the kinetic energy, wall time and ranks. This
tool adds `fabric_crossings`: the number of fabric edges crossing fabric triangles in the last frame of
OUTPUT_DIR/NAME.h5, by the edge-triangle test of fabric_crossings.py (the same test the
self-collision tests use), and rewrites the file. Sewn pairs are held by stiff links, not merged, so
the particles a seam link joins (quality.json's seam_links: a node and the one or two nodes of the
point it is sewn to), and two particles both joined to a third (where seams meet), count as one
particle: an edge and a triangle that meet at a sewn point are the seam itself, as two cells of one
piece meet at their shared particle; the simulation's contact exclusion (src/sewing.h) is the same
relation. `fabric_crossings_unjoined` is the count without this, for reference.

A run may sew several garments at once (a T-shirt under a dress): a garment is a set of pieces joined by
seams (the pieces in fit_maps, in scene order, whose particles seam_links join, and the pieces joined to
those). `garments` lists each one's pieces and its own crossings (edge and triangle both in it), and
`fabric_crossings_between_garments` counts the crossings of an edge of one garment through a triangle of
another: fabric_crossings is their sum.

With --check it also exits non-zero unless the garment meets the targets of issue 8: every seam closed
(max_seam_gap_m < 0.002, all pairs sewn), no particle inside the body, no fabric crossing, max_link_strain
below --strain-max (default 0.10) and kinetic_energy_j below --ke-max (default 1e-3 J: at rest); and unless the summary of the fit maps
that clothsim wrote (fit_maps: per piece the maximum and 95th percentile of strain, stress and pressure)
agrees with numpy's maximum and percentile of the same fields in the last frame (the final state) to 1e-6
relative (the JSON's 7 significant digits): two implementations of the one summary.

With --worst N it lists where the garment falls short in that frame: the N most strained particles and
N of the crossings, each particle named "piece (i, j)" from the pieces' grids in --scene (the run's own
output lists the widest seam pairs the same way)."""
import argparse
import collections
import json
import os
import sys

import h5py
import numpy as np

from fabric_crossings import crossings, primitives
from cloth_state import particle_name, piece_grids, read_scene


def joined_pairs(seam_links, n):
    """Codes a * n + b (both orders) of the particle pairs that count as one particle: the node and the
    other side's nodes of every seam link, and two particles joined to a common third."""
    partners = collections.defaultdict(set)
    for link in seam_links:
        for other in link[1:]:
            partners[link[0]].add(other)
            partners[other].add(link[0])
    codes = set()
    for a, direct in partners.items():
        reach = set(direct)
        for b in direct:
            reach |= partners[b]
        reach.discard(a)
        codes.update(a * n + b for b in reach)
    return np.array(sorted(codes), dtype=np.int64)


def garment_of_particles(fit_maps, seam_links):
    """The pieces of each garment (pieces joined by seams, in scene order) and each particle's garment number;
    None without fit_maps (no piece sizes)."""
    sizes = [summary["particles"] for summary in fit_maps.values()]
    if not sizes:
        return None, None
    piece = np.repeat(np.arange(len(sizes)), sizes)
    root = list(range(len(sizes)))

    def find(i):
        while root[i] != i:
            i = root[i]
        return i

    for link in seam_links:
        for other in link[1:]:
            a, b = find(int(piece[link[0]])), find(int(piece[other]))
            root[max(a, b)] = min(a, b)
    roots = sorted({find(i) for i in range(len(sizes))})
    names = list(fit_maps)
    pieces = [[names[i] for i in range(len(sizes)) if find(i) == r] for r in roots]
    number = np.array([roots.index(find(i)) for i in range(len(sizes))])
    return pieces, number[piece]


def crossings_by_garment(hits, pieces, garment):
    """The garments' records (pieces, their own crossings) and the number of crossings between garments."""
    own = collections.Counter()
    between = 0
    for edge, tri in hits:
        a, b = garment[edge[0]], garment[tri[0]]
        if a == b:
            own[a] += 1
        else:
            between += 1
    return [{"pieces": names, "fabric_crossings": own[g]} for g, names in enumerate(pieces)], between


def last_frame_crossings(h5path, seam_links=(), examples=0):
    """The crossings of the last frame (sewn points joined, and without that), the frame's name, up to
    `examples` crossings and the strain field."""
    with h5py.File(h5path, "r") as f:
        quads = f["/topology/quads"][:].astype(np.int64)
        frames = sorted(f["/frames"].keys())
        x = f["/frames/" + frames[-1] + "/position"][:]
        strain = f["/frames/" + frames[-1] + "/strain"][:].ravel()
    tris, edges = primitives(quads)
    count, hits = crossings(x, tris, edges, examples, joined_pairs(seam_links, len(x)))
    unjoined, _ = crossings(x, tris, edges, 0)
    return count, unjoined, frames[-1], hits, strain


def particle_namer(scene_path):
    """A function naming a particle "piece (i, j)" from the scene's pieces (cloth_state.piece_grids); without a
    scene, by its number."""
    if not scene_path:
        return str
    grids = piece_grids(read_scene(scene_path))
    return lambda g: particle_name(grids, g)


def report_worst(n, hits, strain, name):
    print(f"{n} most strained particles:")
    for g in np.argsort(-strain)[:n]:
        print(f"  {strain[g]:.4f}  {name(int(g))}")
    pieces = collections.Counter()
    for edge, tri in hits:
        pieces[(name(edge[0]).split(" (")[0], name(tri[0]).split(" (")[0])] += 1
    print(f"crossings listed: {len(hits)}, by (edge piece, triangle piece): {dict(pieces)}")
    for edge, tri in hits[:n]:
        print(f"  edge {' - '.join(name(p) for p in edge)}  through triangle {', '.join(name(p) for p in tri)}")


def fit_map_deviation(h5path, fit_maps):
    """The largest relative difference between quality.json's fit_maps and numpy's maximum and 95th percentile
    (linear, numpy's default) of the fields of the last frame, piece by piece in the scene's order."""
    with h5py.File(h5path, "r") as f:
        frame = f["/frames/" + sorted(f["/frames"].keys())[-1]]
        fields = {name: frame[name][:].ravel() for name in ("strain", "stress", "pressure")}
    keys = {"strain": "strain", "stress": "stress_n_per_m", "pressure": "pressure_pa"}
    worst, first = 0.0, 0
    for summary in fit_maps.values():
        last = first + summary["particles"]
        for field, key in keys.items():
            values = fields[field][first:last]
            for mine, theirs in ((summary[key + "_max"], values.max()), (summary[key + "_p95"], np.percentile(values, 95))):
                worst = max(worst, abs(mine - theirs) / max(abs(theirs), 1e-12))
        first = last
    if first != len(fields["strain"]):
        return float("inf")
    return worst


def quality_json(quality):
    """The record as indented JSON, with seam_links (a long list of short lists) on one line."""
    text = json.dumps({key: value for key, value in quality.items() if key != "seam_links"}, indent=2)
    if "seam_links" in quality:
        text = text[:-2] + ',\n  "seam_links": ' + json.dumps(quality["seam_links"]) + "\n}"
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output_dir")
    parser.add_argument("--name", default="dress", help="scene name: the series is OUTPUT_DIR/NAME.h5 (default dress)")
    parser.add_argument("--check", action="store_true", help="fail unless the targets of issue 8 are met")
    parser.add_argument("--ke-max", type=float, default=1e-3, help="kinetic energy (J) below which the garment is at rest")
    parser.add_argument("--strain-max", type=float, default=0.10, help="largest link strain allowed (default 0.10, issue 8's target)")
    parser.add_argument("--worst", type=int, default=0, metavar="N", help="list the N most strained particles and N crossings")
    parser.add_argument("--scene", help="the run's scene file, to name particles by piece and grid node in --worst")
    args = parser.parse_args()
    qpath = os.path.join(args.output_dir, "quality.json")
    with open(qpath) as f:
        quality = json.load(f)
    h5path = os.path.join(args.output_dir, args.name + ".h5")
    pieces, garment = garment_of_particles(quality.get("fit_maps", {}), quality.get("seam_links", ()))
    listed = 10**9 if args.worst or pieces else 0
    count, unjoined, frame, hits, strain = last_frame_crossings(h5path, quality.get("seam_links", ()), listed)
    quality["fabric_crossings"], quality["fabric_crossings_unjoined"] = count, unjoined
    if pieces:
        quality["garments"], quality["fabric_crossings_between_garments"] = crossings_by_garment(hits, pieces, garment)
    with open(qpath, "w") as f:
        f.write(quality_json(quality) + "\n")
    print(json.dumps({key: value for key, value in quality.items() if key != "seam_links"}, indent=2))
    print(f"fabric crossings counted in frame {frame}")
    if args.worst:
        report_worst(args.worst, hits, strain, particle_namer(args.scene))
    if not args.check:
        return 0
    failures = []
    if not (quality["max_seam_gap_m"] < 0.002 and quality["sewn_pairs"] == quality["seam_pairs"]):
        failures.append(f"seams not closed: widest gap {quality['max_seam_gap_m']} m, {quality['sewn_pairs']}/{quality['seam_pairs']} sewn")
    if quality["particles_inside_body"] != 0:
        failures.append(f"{quality['particles_inside_body']} particles inside the body")
    if quality["fabric_crossings"] != 0:
        failures.append(f"{quality['fabric_crossings']} fabric edges cross fabric triangles")
    if not quality["max_link_strain"] < args.strain_max:
        failures.append(f"max link strain {quality['max_link_strain']} >= {args.strain_max}")
    if not quality["kinetic_energy_j"] < args.ke_max:
        failures.append(f"kinetic energy {quality['kinetic_energy_j']} J >= {args.ke_max} J: not at rest")
    deviation = fit_map_deviation(h5path, quality.get("fit_maps", {}))
    print(f"fit_maps against numpy on frame {frame}: largest relative difference {deviation:.2e}")
    if not deviation <= 1e-6:  # the JSON holds 7 significant digits (%.6e): 5e-7 relative
        failures.append(f"fit_maps differ from the last frame's fields by {deviation:.2e} (relative)")
    for message in failures:
        print("garment_quality: FAILED: " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

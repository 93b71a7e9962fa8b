#!/usr/bin/python3
"""Checks the contact records of a clothsim series against the frames' own positions, and the table
that postprocess/contacts.py made of it.

Usage: check_contacts.py SERIES.h5 SCENE.yaml CONTACTS.csv --body-free-until T --body-contact-from T
                         --self-free-until T

Bodies: the scene's spheres and planes (analytic: distances computed here from the positions). A particle
is in contact with a body when, after the collision pass of the step, it lies closer to the surface than
the contact distance D = thickness + slop, slop = max(thickness / 2, 1e-5 m) (src/collision_response.c:
CollisionContactSlop); the pass puts particles closer than the thickness back onto it and leaves the others where
they are. So in every frame:
  - a particle not marked in contact (body_contact 0) is at D or farther from every body (exactly: the
    collision pass did not touch it);
  - a marked particle (1 or 2) is at the thickness or farther from every body (1e-9 m round-off) and
    closer than D + BAND to one of them: the pass's friction correction moves a held particle
    tangentially, which on a sphere of radius R lifts it by about s^2 / 2R (s the tangential move,
    a few mm: a few micrometres), BAND = 0.1 mm;
  - body_contacts equals the particles marked, and the particles closer than D (the independent count)
    within the marked particles in that band (reported; at most 2 or 5 % of the contacts).
Self-contacts: self_contacts x 4 = the sum of the self_contact field (each contact has four particles,
each counted once; a check that every contact is counted by exactly one rank), self_contact_particles
the particles with a non-zero entry.
Time line: no body contact up to --body-free-until, contacts in every frame from --body-contact-from; no
cloth-cloth contact up to --self-free-until, some in the last frame.
CSV: one row per frame with the same counts, max_strain and mean_strain of the strain field.
"""
import argparse
import csv
import sys

import h5py
import numpy as np
import yaml

BAND = 1e-4           # m, see above
ROUNDOFF = 1e-9       # m


def fail(message):
    print(f"check_contacts: FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def body_margins(scene, x):
    """(distance - D) and (distance - thickness) to each analytic body, shape (bodies, N)."""
    margins, clearances = [], []
    for body in scene.get("bodies", []):
        thickness = float(body.get("thickness", 0.0))
        if body["type"] == "sphere":
            d = np.linalg.norm(x - np.asarray(body["center"], float), axis=1) - float(body["radius"])
        elif body["type"] == "plane":
            n = np.asarray(body["normal"], float)
            d = (x - np.asarray(body["point"], float)) @ (n / np.linalg.norm(n))
        else:
            fail(f"body '{body['name']}' is a {body['type']}: this check knows spheres and planes only")
        margins.append(d - (thickness + max(0.5 * thickness, 1e-5)))
        clearances.append(d - thickness)
    check(margins, "the scene has no bodies")
    return np.array(margins), np.array(clearances)


def check_frame(name, g, scene):
    """Checks one frame group; returns (time, body_contacts, independent count, marked in the band, self_contacts)."""
    x = g["position"][...]
    state = g["body_contact"][...].ravel()
    self_field = g["self_contact"][...].ravel()
    counts = {k: int(g.attrs[k]) for k in ("body_contacts", "self_contacts", "self_contact_particles")}
    check(set(np.unique(state)) <= {0.0, 1.0, 2.0}, f"frame {name}: body_contact values {np.unique(state)}, expected 0, 1, 2")
    marked = state > 0
    check(counts["body_contacts"] == marked.sum(), f"frame {name}: body_contacts = {counts['body_contacts']}, {marked.sum()} particles marked")
    margins, clearances = body_margins(scene, x)
    nearest = margins.min(axis=0)
    free_too_close = np.nonzero(~marked & (nearest < -ROUNDOFF))[0]
    check(len(free_too_close) == 0, f"frame {name}: particles {free_too_close[:10]} are not marked in contact but closer than the "
          f"contact distance (by {-nearest[free_too_close[:10]]} m)")
    inside = np.nonzero(marked & (clearances.min(axis=0) < -ROUNDOFF))[0]
    check(len(inside) == 0, f"frame {name}: particles {inside[:10]} marked in contact lie inside a body's thickness")
    far = np.nonzero(marked & (nearest >= BAND))[0]
    check(len(far) == 0, f"frame {name}: particles {far[:10]} marked in contact lie {nearest[far[:10]]} m beyond the contact distance")
    independent = int((nearest < 0).sum())
    in_band = int((marked & (nearest >= 0)).sum())
    check(counts["body_contacts"] - independent == in_band and in_band <= max(2, 0.05 * counts["body_contacts"]),
          f"frame {name}: body_contacts = {counts['body_contacts']}, {independent} particles closer than the contact distance, "
          f"{in_band} marked ones in the {BAND} m band beyond it")
    check(abs(self_field.sum() - 4 * counts["self_contacts"]) < 0.5,
          f"frame {name}: the self_contact field sums to {self_field.sum()}, 4 x self_contacts = {4 * counts['self_contacts']}")
    check(counts["self_contact_particles"] == (self_field > 0).sum(),
          f"frame {name}: self_contact_particles = {counts['self_contact_particles']}, {(self_field > 0).sum()} non-zero entries")
    return float(g.attrs["time"]), counts, independent, in_band, g["strain"][...].ravel()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("h5")
    p.add_argument("scene")
    p.add_argument("csv")
    p.add_argument("--body-free-until", type=float, required=True)
    p.add_argument("--body-contact-from", type=float, required=True)
    p.add_argument("--self-free-until", type=float, required=True)
    args = p.parse_args()
    with open(args.scene) as f:
        scene = yaml.safe_load(f)
    with h5py.File(args.h5, "r") as f:
        frames = [check_frame(name, f["frames"][name], scene) for name in sorted(f["frames"], key=int)]
    rows = list(csv.DictReader(open(args.csv)))
    check(len(rows) == len(frames), f"{args.csv} has {len(rows)} rows, the series {len(frames)} frames")
    for row, (time, counts, _, _, strain) in zip(rows, frames):
        check(abs(float(row["time"]) - time) <= 1e-12 and all(int(row[k]) == v for k, v in counts.items())
              and float(row["max_strain"]) == strain.max() and abs(float(row["mean_strain"]) - strain.mean()) <= 1e-15,
              f"{args.csv} row {row} differs from the frame at t = {time}: {counts}, strain max {strain.max()!r} mean {strain.mean()!r}")
    for time, counts, independent, in_band, _ in frames:
        if time <= args.body_free_until:
            check(counts["body_contacts"] == 0, f"t = {time}: {counts['body_contacts']} body contacts, expected none before the sheet lands")
        if time >= args.body_contact_from:
            check(counts["body_contacts"] > 0, f"t = {time}: no body contacts after the sheet has landed")
        if time <= args.self_free_until:
            check(counts["self_contacts"] == 0, f"t = {time}: {counts['self_contacts']} cloth-cloth contacts, expected none yet")
    check(frames[-1][1]["self_contacts"] > 0, "no cloth-cloth contacts in the last frame")
    print(f"check_contacts: {len(frames)} frames; body contacts per frame (recorded / closer than the contact distance / "
          f"marked in the 0.1 mm band):")
    for time, counts, independent, in_band, _ in frames:
        print(f"  t = {time:.4f} s: {counts['body_contacts']:4d} / {independent:4d} / {in_band}   "
              f"self-contacts {counts['self_contacts']:4d} ({counts['self_contact_particles']} particles)")


if __name__ == "__main__":
    main()

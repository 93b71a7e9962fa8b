#!/usr/bin/python3
"""How far runs of one scene on different rank counts drift apart, and which quantities stay close.

Each run is a directory with its checkpoints (-checkpoint_every K -checkpoint_keep 0, global particle order)
and, next to it, DIR.log, the run's standard output with -monitor_energy. The first run given is the reference.
For every checkpoint step all runs have it prints the largest particle distance |x_P - x_ref| (Euclidean, over
all particles); at the last one the energies clothsim printed (kinetic, gravitational, elastic, total), the
particles in contact with a body (the last output frame's body_contacts, if the run wrote frames) and, with
--drape, a drape coefficient: the vertical projection's area (postprocess/cusick_drape.py) with a support disc
and a specimen of the given radii, (A - pi r_s^2) / (pi r_f^2 - pi r_s^2).

    /usr/bin/python3 postprocess/rank_divergence.py --label "contact" 1=out/np1 2=out/np2 4=out/np4 \\
        [--scene input/sphere_drape.yaml --grid 33 --drape 0.3 0.78987] [--json] [--check-...]

--check-energy R, --check-contacts R, --check-drape D: exit 1 unless every run's final total energy is within R
(relative) of the reference's, its body contact count within R (relative), its drape coefficient within D.
"""
import argparse
import glob
import json
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cloth_state  # noqa: E402

ENERGY = re.compile(r"energy at step (\d+): kinetic ([-0-9.eE+]+) J, gravity ([-0-9.eE+]+) J, elastic ([-0-9.eE+]+) J, "
                    r"total ([-0-9.eE+]+) J")


def checkpoints(directory):
    """{step: path} of a run's checkpoints."""
    out = {}
    for path in glob.glob(os.path.join(directory, "checkpoint_*.h5")):
        out[int(re.search(r"checkpoint_(\d+)\.h5$", path).group(1))] = path
    return out


def positions(path):
    with h5py.File(path, "r") as f:
        return np.asarray(f["state/position"][...]).reshape(-1, 3)


def final_energy(log):
    """(step, kinetic, gravity, elastic, total) of the last energy line of the log, or None."""
    last = None
    with open(log) as f:
        for line in f:
            m = ENERGY.search(line)
            if m:
                last = (int(m.group(1)),) + tuple(float(m.group(k)) for k in range(2, 6))
    return last


def final_contacts(directory):
    """body_contacts of the last output frame of the run's series, or None without frames."""
    series = [p for p in glob.glob(os.path.join(directory, "*.h5")) if not os.path.basename(p).startswith("checkpoint_")]
    if not series:
        return None
    frames, _ = cloth_state.read_series(series[0], datasets=(), attributes=("body_contacts",))
    return int(frames[-1]["body_contacts"]) if frames else None


def drape(path, scene, grid, support, specimen):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import cusick_drape

    return cusick_drape.measure(path, scene, grid, support_radius=support, specimen_radius=specimen)["drape_coefficient"]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", help="RANKS=DIR, the first the reference")
    p.add_argument("--label", default="run", help="name of the case in the output")
    p.add_argument("--scene", help="the scene (for --drape)")
    p.add_argument("--grid", type=int, help="the runs' -grid N (for --drape)")
    p.add_argument("--drape", type=float, nargs=2, metavar=("SUPPORT_R", "SPECIMEN_R"), help="drape coefficient with these radii, m")
    p.add_argument("--json", help="also write the results here")
    p.add_argument("--check-energy", type=float, help="relative tolerance on the final total energy")
    p.add_argument("--check-contacts", type=float, help="relative tolerance on the final body contact count")
    p.add_argument("--check-drape", type=float, help="absolute tolerance on the drape coefficient")
    args = p.parse_args()
    runs = []
    for spec in args.runs:
        ranks, _, directory = spec.partition("=")
        if not directory:
            sys.exit(f"rank_divergence: '{spec}' is not RANKS=DIR")
        runs.append((int(ranks), directory.rstrip("/")))
    cps = [checkpoints(d) for _, d in runs]
    steps = sorted(set.intersection(*(set(c) for c in cps)))
    if not steps:
        sys.exit("rank_divergence: no checkpoint step common to all runs")
    ref = {s: positions(cps[0][s]) for s in steps}
    result = {"label": args.label, "steps": steps, "runs": []}
    print(f"{args.label}: largest particle distance to the {runs[0][0]}-rank run, m")
    print("step     " + "".join(f"{r:>12d} ranks" for r, _ in runs[1:]))
    dist = {r: [] for r, _ in runs[1:]}
    for s in steps:
        row = f"{s:<8d} "
        for (r, _), c in zip(runs[1:], cps[1:]):
            d = float(np.linalg.norm(positions(c[s]) - ref[s], axis=1).max())
            dist[r].append(d)
            row += f"{d:18.3e}"
        print(row)
    failures = []
    for (r, d), c in zip(runs, cps):
        e = final_energy(d + ".log")
        contacts = final_contacts(d)
        dc = drape(c[steps[-1]], args.scene, args.grid, *args.drape) if args.drape else None
        result["runs"].append({"ranks": r, "distance": dist.get(r), "energy": e, "body_contacts": contacts, "drape_coefficient": dc})
    base = result["runs"][0]
    print(f"at step {steps[-1]}: ranks, energies kinetic / gravity / elastic / total (J), body contacts, drape coefficient")
    for run in result["runs"]:
        e = run["energy"]
        energies = " / ".join(f"{v:.6g}" for v in e[1:]) if e else "-"
        print(f"{run['ranks']:3d}  {energies}  {run['body_contacts'] if run['body_contacts'] is not None else '-'}  "
              + (f"{run['drape_coefficient']:.4f}" if run["drape_coefficient"] is not None else "-"))
        if run is base:
            continue
        if args.check_energy is not None:
            rel = abs(e[4] - base["energy"][4]) / abs(base["energy"][4])
            if not rel <= args.check_energy:
                failures.append(f"{run['ranks']} ranks: total energy differs by {rel:.2e} (tolerance {args.check_energy:g})")
        if args.check_contacts is not None:
            rel = abs(run["body_contacts"] - base["body_contacts"]) / max(1, base["body_contacts"])
            if not rel <= args.check_contacts:
                failures.append(f"{run['ranks']} ranks: {run['body_contacts']} body contacts against {base['body_contacts']} (tolerance {args.check_contacts:g})")
        if args.check_drape is not None:
            diff = abs(run["drape_coefficient"] - base["drape_coefficient"])
            if not diff <= args.check_drape:
                failures.append(f"{run['ranks']} ranks: drape coefficient differs by {diff:.4f} (tolerance {args.check_drape:g})")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    for msg in failures:
        print("FAILED:", msg)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

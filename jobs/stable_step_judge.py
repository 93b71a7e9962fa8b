#!/usr/bin/python3
"""Judges one run of jobs/stable_step.sh: prints "stable ...", "unstable: REASON" or "timeout ...".

  stable_step_judge.py LOG H5 EXIT_STATUS

A run of the hanging sheet over 1 s counts as stable when all of these hold:
  1. clothsim exited with status 0 and printed "Done:" (no failed step);
  2. no step was reduced: sub-steps == steps in the "Done:" line (the integrator halves a step whose
     Krylov solve diverged or whose state became non-finite);
  3. every energy line (-monitor_energy, one per frame, about 100 frames) is finite and the total
     energy never exceeds its initial value by more than 1 % of M g L (M = total mass, L = 1 m):
     the physical energy cannot grow, so a larger gain is the integrator's instability;
  4. every position in every frame of the XDMF series is finite and within 3 m of the origin
     (the 1 m sheet hangs from pins at y = 1 m; 3 m is far past any physical stretch).
"""
import math
import os
import re
import sys

import h5py
import numpy as np

GRAVITY = 9.81
LENGTH = 1.0
MAX_RADIUS = 3.0
# STABLE_ENERGY_FRACTION=inf drops criterion 3 ("bounded" instead of "stable": see docs/foundation.md).
ENERGY_FRACTION = float(os.environ.get("STABLE_ENERGY_FRACTION", "0.01"))


def reason_unstable(log_path, h5_path, status):
    text = open(log_path, errors="replace").read()
    if status != 0:
        failed = re.search(r"Step (\d+) failed", text)
        if failed:
            return f"step {failed.group(1)} failed even after halving (exit status {status})"
        return f"exit status {status}"
    done = re.search(r"^Done: (\d+) steps \((\d+) sub-steps\)", text, re.M)
    if not done:
        return "no Done: line"
    if int(done.group(2)) != int(done.group(1)):
        return f"step reduced ({done.group(2)} sub-steps for {done.group(1)} steps)"
    mass = re.search(r"density ([0-9.eE+-]+) kg/m\^2", text)
    size = re.search(r"size ([0-9.eE+-]+) x ([0-9.eE+-]+) m", text)
    total_mass = float(mass.group(1)) * float(size.group(1)) * float(size.group(2))
    totals = [float(t) for t in re.findall(r"total (\S+) J", text)]
    if not totals:
        return "no energy lines (-monitor_energy)"
    if not all(math.isfinite(t) for t in totals):
        return "non-finite energy"
    gain = max(totals) - totals[0]
    bound = ENERGY_FRACTION * total_mass * GRAVITY * LENGTH
    if gain > bound:
        return f"energy gain {gain:.3e} J > {bound:.3e} J"
    radius = 0.0
    with h5py.File(h5_path, "r") as f:
        for frame in f["frames"].values():
            x = frame["position"][()]
            if not np.all(np.isfinite(x)):
                return "non-finite position"
            radius = max(radius, float(np.max(np.linalg.norm(x, axis=1))))
    if radius > MAX_RADIUS:
        return f"max |x| {radius:.3g} m > {MAX_RADIUS} m"
    print(f"stable (energy gain {gain:.2e} J, max |x| {radius:.3f} m)")
    return None


if __name__ == "__main__":
    status = int(sys.argv[3])
    if status == 124:
        print("timeout (the probe took longer than PROBE_TIMEOUT)")
    else:
        reason = reason_unstable(sys.argv[1], sys.argv[2], status)
        if reason:
            print("unstable: " + reason)

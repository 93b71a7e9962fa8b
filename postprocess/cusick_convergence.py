#!/usr/bin/python3
"""Drape coefficient against grid resolution, from the trial runs of jobs/validation.sh: for each fabric, every
trial's drape coefficient and the trials' mean at every grid found, with the measured value and the +-0.10
target band. Prints the same numbers as a Markdown table.

    /usr/bin/python3 postprocess/cusick_convergence.py --out convergence.png \\
        --measured petrak_m1_polyester_twill=0.223 [--measured ...] OUT_DIR [OUT_DIR ...]

Reads OUT_DIR/cusick_PRESET_N_tK.json (written by jobs/validation.sh with VALIDATION_TRIALS) for the presets
given with --measured (PRESET=- for a fabric without a measured value); runs of one fabric may be spread over several directories (one per grid, say), but a
(fabric, grid, trial) found twice is an error, so that no run is counted twice.
"""
import argparse
import glob
import json
import os
import re
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def collect(directories, presets):
    """{preset: {grid: {trial: result}}} from the trial JSON files of the given directories."""
    runs = {p: {} for p in presets}
    pattern = re.compile(r"cusick_(.+)_(\d+)_t(\d+)\.json$")
    for directory in directories:
        for path in sorted(glob.glob(os.path.join(directory, "cusick_*_t*.json"))):
            m = pattern.search(os.path.basename(path))
            if not m or m.group(1) not in runs:
                continue
            preset, grid, trial = m.group(1), int(m.group(2)), int(m.group(3))
            per_grid = runs[preset].setdefault(grid, {})
            if trial in per_grid:
                sys.exit(f"cusick_convergence: {preset}, grid {grid}, trial {trial} found twice (second: {path})")
            with open(path) as f:
                per_grid[trial] = json.load(f)
    return runs


def table(runs, measured):
    lines = ["| fabric (measured) | grid | spacing, mm | trials: DC (folds) | mean | sd | error of the mean |",
             "|---|---|---|---|---|---|---|"]
    for preset, per_grid in runs.items():
        for grid in sorted(per_grid):
            trials = per_grid[grid]
            dcs = [trials[t]["drape_coefficient"] for t in sorted(trials)]
            cells = ", ".join(f"{trials[t]['drape_coefficient']:.3f} ({trials[t]['folds']})" for t in sorted(trials))
            sd = statistics.stdev(dcs) if len(dcs) > 1 else 0.0
            mean = statistics.mean(dcs)
            m = measured[preset]
            shown, error = (f"{m:.3f}", f"{mean - m:+.3f}") if m is not None else ("-", "-")
            lines.append(f"| {preset} ({shown}) | {grid} | {300 / (grid - 1):.2f} | {cells} | {mean:.3f} | {sd:.3f} | {error} |")
    return "\n".join(lines)


def plot(runs, measured, out):
    fig, axes = plt.subplots(1, len(runs), figsize=(4.5 * len(runs), 4), squeeze=False)
    for ax, (preset, per_grid) in zip(axes[0], runs.items()):
        grids = sorted(per_grid)
        for grid in grids:
            dcs = [r["drape_coefficient"] for r in per_grid[grid].values()]
            ax.plot([grid] * len(dcs), dcs, "o", color="0.6", ms=4)
        means = [statistics.mean(r["drape_coefficient"] for r in per_grid[g].values()) for g in grids]
        ax.plot(grids, means, "-s", color="tab:blue", label="simulated: trials (grey), mean")
        m = measured[preset]
        if m is not None:
            ax.axhline(m, color="tab:red", label=f"measured {m:.3f}")
            ax.axhspan(m - 0.10, m + 0.10, color="tab:red", alpha=0.08, label="target +-0.10")
        lo, hi = ax.get_ylim()
        if hi - lo < 0.2:  # at least the target band's width, so that a change of 0.003 does not look like a trend
            mid = 0.5 * (lo + hi)
            ax.set_ylim(mid - 0.1, mid + 0.1)
        ax.set_xlabel("nodes per boundary (30 cm disc)")
        ax.set_ylabel("drape coefficient")
        ax.set_title(preset.replace("petrak_", ""), fontsize=10)
        ax.set_xticks(grids)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("directories", nargs="+", help="output directories of jobs/validation.sh trial runs")
    parser.add_argument("--measured", action="append", required=True, metavar="PRESET=DC",
                        help="a fabric to show and its measured drape coefficient, - if none (repeat for more)")
    parser.add_argument("--out", help="PNG to write (default: only the table)")
    args = parser.parse_args()
    measured = {}
    for pair in args.measured:
        preset, _, value = pair.partition("=")
        try:
            measured[preset] = None if value == "-" else float(value)
        except ValueError:
            sys.exit(f"cusick_convergence: --measured wants PRESET=DC, got '{pair}'")
    runs = collect(args.directories, list(measured))
    empty = [p for p, g in runs.items() if not g]
    if empty:
        sys.exit(f"cusick_convergence: no trial runs of {', '.join(empty)} in {', '.join(args.directories)}")
    print(table(runs, measured))
    if args.out:
        plot(runs, measured, args.out)


if __name__ == "__main__":
    main()

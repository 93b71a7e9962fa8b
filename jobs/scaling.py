#!/usr/bin/python3
"""Strong and weak scaling of clothsim on the hanging sheet (input/hanging_sheet.yaml, -grid N).

  strong: one sheet (--strong-grid N x N particles) on each of --ranks;
  weak:   about --weak-particles particles per rank: n = round(sqrt(P * ranks)), made odd.

Each case is one run `mpiexec -n R build/clothsim -scene input/hanging_sheet.yaml -grid N -steps S
-output_every 0 -log_view`, started directly (default) or as a Slurm job (--sbatch: `sbatch --wait
--ntasks=R`, Slurm configured). The time per step is the wall time of clothsim's "Time steps" log stage
(-log_view, max over ranks) divided by the steps; Krylov iterations per step come from its "Done:" line,
and the time per Krylov iteration (stage time / iterations) separates the parallel cost from the growth
of the iteration count with the sheet size.
Strong: speedup = T(1 rank) / T(R), efficiency = speedup / R. Weak: efficiency = T(1) / T(R) per step,
speedup = R x efficiency (scaled speedup). A rank count above the cores of the machine is marked
"oversubscribed" (its numbers are not a scaling result). The load average before each run is recorded:
on a shared machine other work falsifies the times.

Writes OUT/scaling.csv, OUT/scaling.png (time per step and efficiency against ranks) and OUT/runs/*.log.

  jobs/scaling.py --ranks 1 2 4 --strong-grid 129 --strong-steps 100 --weak-particles 8000 --weak-steps 50
  jobs/scaling.py --ranks 1 2 4 8 16 --sbatch --sbatch-args "--time=30 --partition=short" --out scaling_run
"""
import argparse
import csv
import datetime
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAGE = re.compile(r"^\s*\d+:\s+Time steps:\s+([0-9.eE+-]+)")
LOAD_LINE = "# scaling.py: load average before the run:"
DONE = re.compile(r"Done:\s+(\d+) steps \((\d+) sub-steps\),\s+(\d+) Krylov iterations,\s+([0-9.]+) s wall")


def weak_grid(particles, ranks):
    n = int(math.floor(math.sqrt(particles * ranks) + 0.5))
    return n + 1 if n % 2 == 0 else n


def run_case(args, kind, ranks, grid, steps):
    os.makedirs(os.path.join(args.out, "runs"), exist_ok=True)
    tag = f"{kind}_np{ranks}_n{grid}"
    log = os.path.join(args.out, "runs", tag + ".log")
    outdir = os.path.join(args.out, "runs", tag)
    clothsim = [args.clothsim, "-scene", os.path.join(ROOT, "input/hanging_sheet.yaml"), "-grid", str(grid),
                "-steps", str(steps), "-output_every", "0", "-output_dir", outdir, "-log_view",
                "-progress_seconds", "10"] + shlex.split(args.options)
    load = os.getloadavg()[0]
    start = time.time()
    reused = False
    if args.reuse and os.path.exists(log) and DONE.search(open(log, errors="replace").read()):
        print(f"  reusing {log}", flush=True)
        m = re.search(re.escape(LOAD_LINE) + r" ([0-9.]+)", open(log, errors="replace").read())
        load = float(m.group(1)) if m else float("nan")
        reused = True
    elif args.sbatch:
        wrap = " ".join(shlex.quote(w) for w in [args.mpiexec, "-n", str(ranks)] + clothsim)
        cmd = ["sbatch", "--wait", f"--ntasks={ranks}", f"--job-name=scaling_{tag}", f"--output={os.path.abspath(log)}",
               f"--chdir={ROOT}"] + shlex.split(args.sbatch_args) + ["--wrap", wrap]
        print("  " + " ".join(shlex.quote(c) for c in cmd), flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    else:
        cmd = [args.mpiexec, "-n", str(ranks)] + shlex.split(args.mpiexec_flags) + clothsim
        print("  " + " ".join(shlex.quote(c) for c in cmd), flush=True)
        with open(log, "w") as f:
            f.write(f"{LOAD_LINE} {load:.2f}\n# {' '.join(shlex.quote(c) for c in cmd)}\n")
            f.flush()
            subprocess.run(cmd, check=True, stdout=f, stderr=subprocess.STDOUT)
    wall = time.time() - start
    text = open(log, errors="replace").read()
    stage = [float(m.group(1)) for m in map(STAGE.match, text.splitlines()) if m]
    done = DONE.search(text)
    if not stage or not done:
        sys.exit(f"scaling.py: no 'Time steps' stage or 'Done:' line in {log}: did the run fail?")
    nsteps, substeps, krylov = int(done.group(1)), int(done.group(2)), int(done.group(3))
    if reused:
        wall = float(done.group(4))  # the stepping wall time of the Done: line
    if not args.keep_output:
        shutil.rmtree(outdir, ignore_errors=True)
    return {
        "study": kind, "ranks": ranks, "oversubscribed": "yes" if ranks > args.cores else "no",
        "grid": grid, "particles": grid * grid, "particles_per_rank": grid * grid // ranks, "steps": nsteps,
        "time_steps_stage_s": stage[0], "time_per_step_s": stage[0] / nsteps,
        "krylov_per_step": krylov / nsteps, "time_per_krylov_ms": 1e3 * stage[0] / max(krylov, 1), "substeps": substeps, "run_wall_s": round(wall, 2),
        "load_before": round(load, 2), "log": os.path.relpath(log, args.out),
    }


def add_speedup(rows):
    for kind in ("strong", "weak"):
        sel = [r for r in rows if r["study"] == kind]
        base = next((r for r in sel if r["ranks"] == 1), None)
        for r in sel:
            if base is None:
                r["speedup"] = r["efficiency"] = float("nan")
            elif kind == "strong":
                r["speedup"] = base["time_per_step_s"] / r["time_per_step_s"]
                r["efficiency"] = r["speedup"] / r["ranks"]
            else:
                r["efficiency"] = base["time_per_step_s"] / r["time_per_step_s"]
                r["speedup"] = r["efficiency"] * r["ranks"]


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for kind, marker in (("strong", "o"), ("weak", "s")):
        sel = sorted((r for r in rows if r["study"] == kind), key=lambda r: r["ranks"])
        if not sel:
            continue
        ranks = [r["ranks"] for r in sel]
        line, = axes[0].plot(ranks, [r["time_per_step_s"] for r in sel], marker + "-", label=f"{kind}")
        axes[1].plot(ranks, [r["efficiency"] for r in sel], marker + "-", color=line.get_color(), label=kind)
        over = [r for r in sel if r["oversubscribed"] == "yes"]
        if over:
            axes[0].plot([r["ranks"] for r in over], [r["time_per_step_s"] for r in over], marker, ms=12,
                         mfc="none", color="red", label="oversubscribed" if kind == "strong" else None)
            axes[1].plot([r["ranks"] for r in over], [r["efficiency"] for r in over], marker, ms=12, mfc="none", color="red")
        if kind == "strong" and sel[0]["ranks"] == 1:
            axes[0].plot(ranks, [sel[0]["time_per_step_s"] / p for p in ranks], "k:", lw=1, label="ideal strong")
    axes[0].set_xscale("log", base=2)
    axes[0].set_yscale("log")
    axes[0].set_xlabel("MPI ranks")
    axes[0].set_ylabel("wall time per step, s")
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3, which="both")
    axes[1].axhline(1.0, color="k", lw=1, ls=":")
    axes[1].set_xscale("log", base=2)
    axes[1].set_xlabel("MPI ranks")
    axes[1].set_ylabel("parallel efficiency")
    axes[1].set_ylim(0, 1.2)
    axes[1].legend(fontsize=8)
    axes[1].grid(alpha=0.3)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4], help="rank counts (default 1 2 4)")
    p.add_argument("--strong-ranks", type=int, nargs="+", help="rank counts of the strong study (default --ranks)")
    p.add_argument("--weak-ranks", type=int, nargs="+", help="rank counts of the weak study (default --ranks)")
    p.add_argument("--study", choices=["strong", "weak", "both"], default="both")
    p.add_argument("--strong-grid", type=int, default=129, help="strong scaling: particles per side (default 129)")
    p.add_argument("--strong-steps", type=int, default=100, help="strong scaling: steps (default 100)")
    p.add_argument("--weak-particles", type=int, default=8000, help="weak scaling: particles per rank (default 8000)")
    p.add_argument("--weak-steps", type=int, default=50, help="weak scaling: steps (default 50)")
    p.add_argument("--clothsim", default=os.path.join(ROOT, "build", "clothsim"), help="the binary (default build/clothsim)")
    p.add_argument("--mpiexec", default="mpiexec", help="MPI launcher (default mpiexec)")
    p.add_argument("--mpiexec-flags", default="", help="extra launcher flags, e.g. '--bind-to core'")
    p.add_argument("--options", default="", help="extra clothsim / PETSc options for every run")
    p.add_argument("--cores", type=int, default=os.cpu_count(), help="cores of a node; more ranks are marked oversubscribed")
    p.add_argument("--sbatch", action="store_true", help="run each case as a Slurm job (sbatch --wait)")
    p.add_argument("--sbatch-args", default="", help="more sbatch options, e.g. '--time=30 --exclusive'")
    p.add_argument("--reuse", action="store_true", help="take the numbers of a case from its log in OUT/runs if that run finished")
    p.add_argument("--keep-output", action="store_true", help="keep each run's XDMF and checkpoints (default: delete them, keep the logs)")
    p.add_argument("--out", default=os.path.join(ROOT, "jobs", "results", "scaling"), help="output directory (default jobs/results/scaling)")
    args = p.parse_args()
    if not os.access(args.clothsim, os.X_OK):
        sys.exit(f"scaling.py: no clothsim binary at {args.clothsim} (--clothsim)")
    os.makedirs(args.out, exist_ok=True)

    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    rows = []
    for kind in ("strong", "weak"):
        if args.study not in (kind, "both"):
            continue
        for ranks in (args.strong_ranks if kind == "strong" else args.weak_ranks) or args.ranks:
            grid = args.strong_grid if kind == "strong" else weak_grid(args.weak_particles, ranks)
            steps = args.strong_steps if kind == "strong" else args.weak_steps
            print(f"{kind}: {ranks} ranks, {grid} x {grid} particles, {steps} steps", flush=True)
            r = run_case(args, kind, ranks, grid, steps)
            print(f"  {r['time_per_step_s']:.4f} s/step, {r['krylov_per_step']:.1f} Krylov its/step, load {r['load_before']}", flush=True)
            rows.append(r)
    add_speedup(rows)
    fields = ["study", "ranks", "oversubscribed", "grid", "particles", "particles_per_rank", "steps",
              "time_steps_stage_s", "time_per_step_s", "speedup", "efficiency", "krylov_per_step", "time_per_krylov_ms", "substeps",
              "run_wall_s", "load_before", "log"]
    csv_path = os.path.join(args.out, "scaling.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in fields})
    plot(rows, os.path.join(args.out, "scaling.png"),
         f"clothsim hanging sheet, {started}, {args.cores} cores; red rings: oversubscribed")
    print(f"{'study':6} {'ranks':>5} {'over':>4} {'particles':>9} {'steps':>5} {'s/step':>9} {'speedup':>7} {'eff':>5} {'KSP/step':>8} {'load':>5}")
    for r in rows:
        print(f"{r['study']:6} {r['ranks']:5d} {r['oversubscribed']:>4} {r['particles']:9d} {r['steps']:5d} "
              f"{r['time_per_step_s']:9.4f} {r['speedup']:7.2f} {r['efficiency']:5.2f} {r['krylov_per_step']:8.1f} {r['load_before']:5.1f}")
    print(f"wrote {csv_path} and {os.path.join(args.out, 'scaling.png')} (started {started})")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Tables of the at-scale study (issue 25) from the runs of jobs/at_scale.sh.

Reads OUT/runs/grid<N>_np<R>[_TAG].log (clothsim's -log_view -log_view_memory -memory_view output, the load
average, the listing of the output directory) and .time (/usr/bin/time -v) and writes
  OUT/setup.csv   the set-up phases' times (log stages "Setup: NAME", average over the ranks) and the first step
  OUT/memory.csv  peak memory per particle and what each part keeps (PETSc's Malloc column: bytes allocated and
                  kept during the event, summed over the ranks; RMI: the increase of the resident set during it)
  OUT/io.csv      the frame and checkpoint written in the time steps: bytes (the files' sizes) and time (the
                  ClothOutput / ClothCheckpoint events, max over the ranks) -> bytes/s
and prints the three as Markdown tables (docs/performance.md, "At scale").

    jobs/at_scale_report.py [--out jobs/results/at_scale] [--tag TAG]
    jobs/at_scale_report.py --partition      (OUT/partition.csv: edge cut, imbalance and time of each partitioner)
"""
import argparse
import csv
import glob
import os
import re
import sys

PHASES = ["scene", "meshing", "graph", "partition", "distribute", "bodies", "matrix", "output"]
STAGE = re.compile(r"^\s*(\d+):\s+(.+?):\s+([0-9.eE+-]+)\s+[0-9.]+%")
EVENT_STAGE = re.compile(r"^--- Event Stage (\d+): (.+)$")
# name, count, ratio, time max, ratio, flop max, ratio, messages, average length, reductions, ...
EVENT = re.compile(r"^(\S.*?)\s+(\d+) +([0-9.]+) ([0-9.eE+-]+) +([0-9.]+) ([0-9.eE+-]+) +([0-9.]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) (.*)$")


def parse_log(path):
    run = {"stages": {}, "events": {}, "files": {}}
    stage_names = {}
    current = None
    with open(path) as f:
        lines = f.read().splitlines()
    for line in lines:
        if line.startswith("# at_scale:"):
            m = re.search(r"grid (\d+) ranks (\d+) steps (\d+)", line)
            run["grid"], run["ranks"], run["steps"] = (int(x) for x in m.groups())
        elif line.startswith("# date"):
            run["date"] = line.split()[2]
            run["load_before"] = float(re.search(r"load average: ([0-9.]+)", line).group(1))
        elif line.startswith("# uptime after"):
            run["load_after"] = float(re.search(r"load average: ([0-9.]+)", line).group(1))
        elif line.startswith("Maximum (over computational time) process memory:"):
            run["rss_total"] = float(line.split("total")[1].split()[0])
            run["rss_max"] = float(line.split("max")[2].split()[0]) if line.count("max") > 1 else None
        elif line.startswith("Maximum (over computational time) space PetscMalloc()ed:"):
            run["malloc_total"] = float(line.split("total")[1].split()[0])
        elif "Partition (" in line and "edge cut" in line:
            m = re.search(r"Partition \((\w+), \d+ rank\(s\)\): edge cut (\d+) of (\d+) .*owned particles (\d+)\.\.(\d+) \(imbalance ([0-9.]+)\)", line)
            if m:
                run["partitioner"], run["edge_cut"], run["edges"] = m.group(1), int(m.group(2)), int(m.group(3))
                run["imbalance"] = float(m.group(6))
        elif line.startswith("Done:"):
            run["krylov"] = int(re.search(r"(\d+) Krylov", line).group(1))
        elif line.startswith("Object Type"):
            current = "done"
        m = STAGE.match(line)
        if m and current is None:
            stage_names[int(m.group(1))] = m.group(2).strip()
            run["stages"][m.group(2).strip()] = float(m.group(3))
        m = EVENT_STAGE.match(line)
        if m and current != "done":
            current = m.group(2).strip()
            continue
        if "Malloc Mbytes" in line:
            run["memory_columns"] = True
        if current and current != "done":
            m = EVENT.match(line)
            if m:
                mem = m.group(11).split()[-4:] if run.get("memory_columns") else ["0"] * 4
                run["events"][(current, m.group(1).strip())] = {
                    "count": int(m.group(2)), "time": float(m.group(4)), "flop": float(m.group(6)),
                    "messages": float(m.group(8)), "avglen": float(m.group(9)), "reductions": float(m.group(10)),
                    "malloc_mb": float(mem[0]), "emalloc_mb": float(mem[1]), "mmalloc_mb": float(mem[2]),
                    "rmi_mb": float(mem[3])}
        m = re.match(r"^-\S+\s+\d+\s+\S+\s+\S+\s+(\d+) .* (\S+)$", line)
        if m:
            run["files"][m.group(2)] = int(m.group(1))
    timef = path[:-4] + ".time"
    if os.path.exists(timef):
        with open(timef) as f:
            t = f.read()
        run["rss_largest_process"] = 1024.0 * float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1))
        run["wall"] = t and re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", t).group(1)
    run["name"] = os.path.basename(path)[:-4]
    run["particles"] = run["grid"] ** 2
    return run


def event(run, stage, name, key):
    e = run["events"].get((stage, name))
    return e[key] if e else 0.0


def setup_row(run):
    row = {"run": run["name"], "particles": run["particles"], "ranks": run["ranks"], "load_before": run["load_before"]}
    total = run["stages"].get("Setup", 0.0)
    for p in PHASES:
        row[p + "_s"] = run["stages"].get("Setup: " + p, 0.0)
        total += row[p + "_s"]
    row["setup_total_s"] = total
    row["first_step_s"] = run["stages"].get("Time steps", 0.0)
    return row


def memory_row(run):
    n = run["particles"]
    row = {"run": run["name"], "particles": n, "ranks": run["ranks"], "load_before": run["load_before"],
           "rss_total_bytes_per_particle": run["rss_total"] / n,
           "malloc_peak_bytes_per_particle": run.get("malloc_total", 0.0) / n}
    for p in PHASES:
        row[p + "_B_per_particle"] = 1e6 * event(run, "Setup: " + p, "SetUp_" + p, "malloc_mb") / n
        row[p + "_resident_B_per_particle"] = 1e6 * event(run, "Setup: " + p, "SetUp_" + p, "rmi_mb") / n
    steps = "Time steps"
    row["aij_copy_B_per_particle"] = 1e6 * event(run, steps, "MatConvert", "malloc_mb") / n
    row["gamg_hierarchy_B_per_particle"] = 1e6 * event(run, steps, "PCSetUp", "malloc_mb") / n
    # GAMG's own events, per level: "PCGAMG Gal lNN" the Galerkin product, "PCGAMG Opt lNN" the smoothed prolongator
    levels = sorted({name[-3:] for (stage, name) in run["events"] if stage == steps and name.startswith("PCGAMG Gal l")})
    row["gamg_finest_galerkin_B_per_particle"] = 1e6 * event(run, steps, "PCGAMG Gal l00", "malloc_mb") / n
    row["gamg_finest_galerkin_transient_B_per_particle"] = 1e6 * event(run, steps, "PCGAMG Gal l00", "emalloc_mb") / n
    row["gamg_finest_prolongator_B_per_particle"] = 1e6 * event(run, steps, "PCGAMG Opt l00", "malloc_mb") / n
    row["gamg_coarser_levels_B_per_particle"] = 1e6 * sum(event(run, steps, "PCGAMG " + kind + " " + level, "malloc_mb") for level in levels[1:] for kind in ("Gal", "Opt")) / n
    row["gamg_smoothers_B_per_particle"] = 1e6 * event(run, steps, "KSPSetUp", "malloc_mb") / n
    # the pattern-grid multigrid's Galerkin products (src/preconditioner.c, MatPtAP outside PCSetUp; GAMG's are above)
    row["grid_galerkin_B_per_particle"] = 1e6 * (event(run, steps, "MatPtAPSymbolic", "malloc_mb") + event(run, steps, "MatPtAPNumeric", "malloc_mb")) / n
    row["grid_galerkin_transient_B_per_particle"] = 1e6 * event(run, steps, "MatPtAPSymbolic", "emalloc_mb") / n
    # its finest product of the block matrix itself (src/block_ptap.c: the symbolic and numeric parts, one event)
    row["grid_block_galerkin_B_per_particle"] = 1e6 * (event(run, steps, "ClothBlockPtAPSym", "malloc_mb") + event(run, steps, "ClothBlockPtAPNum", "malloc_mb")) / n
    row["grid_block_galerkin_transient_B_per_particle"] = 1e6 * event(run, steps, "ClothBlockPtAPSym", "emalloc_mb") / n
    row["solve_total_B_per_particle"] = 1e6 * event(run, steps, "ClothSolve", "malloc_mb") / n
    row["solve_peak_B_per_particle"] = 1e6 * event(run, steps, "ClothSolve", "mmalloc_mb") / n
    row["solve_resident_B_per_particle"] = 1e6 * event(run, steps, "ClothSolve", "rmi_mb") / n
    row["largest_process_rss_B_per_particle"] = run.get("rss_largest_process", 0) / n
    return row


def io_row(run):
    n = run["particles"]
    frame_bytes = 72 * n  # a frame: position, velocity (3 doubles each), strain, body_contact, self_contact
    ckpt = [v for k, v in run["files"].items() if k.startswith("checkpoint_")]
    t_frame = event(run, "Time steps", "ClothOutput", "time")
    t_ckpt = event(run, "Main Stage", "ClothCheckpoint", "time")
    return {"run": run["name"], "particles": n, "ranks": run["ranks"], "load_before": run["load_before"],
            "frame_bytes": frame_bytes, "frame_s": t_frame, "frame_MB_per_s": frame_bytes / t_frame / 1e6 if t_frame else 0,
            "checkpoint_bytes": ckpt[0] if ckpt else 0, "checkpoint_s": t_ckpt,
            "checkpoint_MB_per_s": ckpt[0] / t_ckpt / 1e6 if ckpt and t_ckpt else 0}


def partition_row(run):
    return {"run": run["name"], "particles": run["particles"], "ranks": run["ranks"], "load_before": run["load_before"],
            "partitioner": run.get("partitioner", "-"), "edge_cut": run.get("edge_cut", 0), "edges": run.get("edges", 0),
            "imbalance": run.get("imbalance", 0.0), "partition_s": run["stages"].get("Setup: partition", 0.0),
            "partition_event_s": event(run, "Setup: partition", "ClothPartition", "time"),
            "setup_total_s": setup_row(run)["setup_total_s"]}


def write(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def markdown(rows, title):
    keys = list(rows[0].keys())
    print(f"\n{title}\n")
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for r in rows:
        print("| " + " | ".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="jobs/results/at_scale")
    ap.add_argument("--tag", default="", help="only the runs of this tag (default: untagged runs)")
    ap.add_argument("--partition", action="store_true", help="the partitioner comparison: the runs tagged part_*")
    args = ap.parse_args()
    logs = []
    for path in glob.glob(os.path.join(args.out, "runs", "*.log")):
        m = re.match(r"grid\d+_np\d+(?:_(.+))?\.log$", os.path.basename(path))
        wanted = (m.group(1) or "").startswith("part_") if m and args.partition else m and (m.group(1) or "") == args.tag
        if wanted:
            with open(path) as f:
                if "# uptime after" in f.read():  # finished
                    logs.append(path)
    if not logs:
        sys.exit(f"at_scale_report.py: no runs in {args.out}/runs (run jobs/at_scale.sh first)")
    runs = sorted((parse_log(p) for p in logs), key=lambda r: (r["particles"], r["ranks"], r["name"]))
    if args.partition:
        rows = [partition_row(r) for r in runs]
        write(rows, os.path.join(args.out, "partition.csv"))
        markdown(rows, "Partitioners (-cloth_partition), symplectic set-up and 1 step")
        return
    for rows, name, title in (([setup_row(r) for r in runs], "setup.csv", "Set-up phases, s (log stages, average over the ranks)"),
                              ([memory_row(r) for r in runs], "memory.csv", "Memory, bytes per particle"),
                              ([io_row(r) for r in runs], "io.csv", "Frame and checkpoint writes")):
        write(rows, os.path.join(args.out, (args.tag + "_" if args.tag else "") + name))
        markdown(rows, title)


if __name__ == "__main__":
    main()

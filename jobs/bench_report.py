#!/usr/bin/env python3
"""Measures and tabulates the hanging-sheet benchmark of jobs/bench.sh.

  bench_report.py clothsim --log LOG --grid N --ranks P --stream STREAM_LOG --checkpoint-dir DIR --csv CSV
      one clothsim run (-log_view -memory_view output) -> one CSV row: particle-steps/s, Krylov iterations per
      step, memory per particle, the bytes the run had to move (model below), the bandwidth roofline and the
      fraction of it achieved, and the physics at the end (lowest point, free-edge middle) from the checkpoint
  bench_report.py peers --jsonl RESULTS --csv CSV
      the JSON lines of the peers' run_all.sh (jobs/bench.sh, PEERS_DIR) -> CSV rows
  bench_report.py report --csv CSV --png PNG --markdown MD
      the whole CSV as a plot and as a markdown table between the markers
      <!-- bench table begin --> / <!-- bench table end --> of MD, with the ratios to the peers

Bytes model (the least memory traffic each operation needs, 8-byte scalars, 4-byte indices; V = one vector of
3N scalars): MatMult streams the stored matrix blocks (72 bytes of values + 4 of column index each) and
reads x and writes y (2V); MatSolve (ICC(0): a factor with the matrix's own pattern) streams the factor
twice (forward and backward) and 2V; MatCholFctrNum reads the matrix and writes the factor; a point-block
Jacobi PCApply reads N inverse blocks and 2V; VecTDot/VecDot 2V, VecNorm V, VecAXPY/VecAYPX/VecWAXPY 3V,
VecAXPBYPCZ 4V, VecCopy 2V, VecSet V, VecScale 2V; the assembly (ClothJacobian) writes the matrix once.
Counts come from -log_view (summed over the log stages; the largest count over ranks). The roofline time is
bytes / bandwidth, the bandwidth the STREAM triad of the same bench run on the same number of ranks; the
achieved fraction is roofline time / wall time of the stepping loop.
"""
import argparse
import csv
import json
import os
import re
import socket
import sys
import time

FIELDS = ["tag", "simulator", "integrator", "grid", "particles", "ranks_or_threads", "dt", "steps", "substeps",
          "pc_fallbacks", "preconditioner", "wall_s", "particle_steps_per_s", "krylov_its_per_step", "memory_bytes_per_particle", "stored_blocks",
          "model_bytes_per_step", "bandwidth_GBps", "roofline_fraction", "min_y", "free_edge_mid_x",
          "free_edge_mid_y", "free_edge_mid_z", "date", "host", "command"]
BLOCK_BYTES = 9 * 8 + 4

BEGIN = "<!-- bench table begin -->"
END = "<!-- bench table end -->"


def event_counts(text):
    """Count (max over ranks) of each -log_view event, summed over the stages."""
    counts = {}
    for m in re.finditer(r"^(\w+)\s+(\d+) (\d\.\d) (\d\.\d{4}e[+-]\d\d) ", text, re.M):
        counts[m.group(1)] = counts.get(m.group(1), 0) + int(m.group(2))
    return counts


def model_bytes(counts, particles, blocks):
    vec = 3 * particles * 8
    mat = blocks * BLOCK_BYTES + particles * 4
    per_vector_passes = {"VecTDot": 2, "VecDot": 2, "VecNorm": 1, "VecAXPY": 3, "VecAYPX": 3, "VecWAXPY": 3,
                         "VecAXPBYPCZ": 4, "VecCopy": 2, "VecSet": 1, "VecScale": 2}
    total = counts.get("MatMult", 0) * (mat + 2 * vec)
    total += counts.get("MatSolve", 0) * (2 * mat + 2 * vec)
    total += counts.get("MatCholFctrNum", 0) * 2 * mat
    if counts.get("MatSolve", 0) == 0:  # point-block or point Jacobi: the inverse diagonal blocks
        total += counts.get("PCApply", 0) * (particles * 72 + 2 * vec)
    total += counts.get("ClothJacobian", 0) * mat
    total += sum(counts.get(name, 0) * passes * vec for name, passes in per_vector_passes.items())
    return total


def stream_bandwidth(path, ranks):
    for line in open(path):
        m = re.match(r"stream_triad ranks (\d+) .* bandwidth_GBps (\S+)", line)
        if m and int(m.group(1)) == ranks:
            return float(m.group(2))
    raise SystemExit(f"{path}: no triad measured on {ranks} rank(s)")


def final_physics(checkpoint, grid):
    import h5py
    with h5py.File(checkpoint, "r") as f:
        x = f["/state/position"][...]
    probe = x[(grid - 1) * grid + (grid - 1) // 2]  # common.py free_edge_mid: k = (n-1) n + (n-1)/2
    return float(x[:, 1].min()), [float(c) for c in probe]


def append_rows(path, rows):
    new = not os.path.exists(path)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        for row in rows:
            w.writerow(row)
            print(",".join(str(row.get(k, "")) for k in FIELDS[:16]))


def cmd_clothsim(a):
    text = open(a.log).read()
    done = re.search(r"^Done: (\d+) steps \((\d+) sub-steps\), (\d+) Krylov iterations, ([0-9.]+) s wall\..*checkpoint (\S+)",
                     text, re.M)
    if not done:
        raise SystemExit(f"{a.log}: the run did not finish (no 'Done:' line)")
    steps, its, wall, checkpoint = int(done.group(1)), int(done.group(3)), float(done.group(4)), done.group(5)
    substeps = int(done.group(2))  # more than steps: steps were halved
    fallback = re.search(r"^Preconditioner breakdowns: (\d+) solves redone", text, re.M)
    system = re.search(r"^Implicit system: \S+, (\d+) stored .*preconditioner (\S+)", text, re.M)
    blocks, preconditioner = int(system.group(1)), system.group(2)
    memory = float(re.search(r"Maximum \(over computational time\) process memory:\s+total\s+(\S+)", text).group(1))
    particles = a.grid * a.grid
    dt = float(re.search(r"steps of (\S+) s from step", text).group(1))
    # The byte model counts every MatMult as one pass over the fine matrix: not valid for a multilevel
    # preconditioner, whose smoothers multiply by the coarse matrices too; no roofline fraction for those.
    single_level = preconditioner not in ("gamg", "ml", "hypre", "mg")
    nbytes = model_bytes(event_counts(text), particles, blocks) if single_level else None
    bandwidth = stream_bandwidth(a.stream, a.ranks)
    min_y, probe = final_physics(checkpoint, a.grid)
    append_rows(a.csv, [{
        "tag": a.tag, "simulator": "clothsim", "integrator": "implicit", "grid": a.grid, "particles": particles,
        "ranks_or_threads": a.ranks, "dt": dt, "steps": steps, "substeps": substeps,
        "pc_fallbacks": int(fallback.group(1)) if fallback else 0, "preconditioner": preconditioner, "wall_s": f"{wall:.3f}",
        "particle_steps_per_s": f"{particles * steps / wall:.4g}", "krylov_its_per_step": f"{its / steps:.1f}",
        "memory_bytes_per_particle": f"{memory / particles:.0f}", "stored_blocks": blocks,
        "model_bytes_per_step": f"{nbytes / steps:.4g}" if nbytes else "", "bandwidth_GBps": f"{bandwidth:.3f}",
        "roofline_fraction": f"{nbytes / (bandwidth * 1e9) / wall:.3f}" if nbytes else "", "min_y": f"{min_y:.4f}",
        "free_edge_mid_x": f"{probe[0]:.4f}", "free_edge_mid_y": f"{probe[1]:.4f}", "free_edge_mid_z": f"{probe[2]:.4f}",
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "host": socket.gethostname(), "command": a.command}])


def cmd_peers(a):
    rows = []
    for line in open(a.jsonl):
        r = json.loads(line)
        if "failed" in r:
            print(f"peer {r['peer']} {r.get('args', '')}: {r['failed']}", file=sys.stderr)
            continue
        threads = r.get("threads", "")
        cpus = r.get("cpus_allowed", "")
        rows.append({
            "tag": "peer", "simulator": r["peer"], "integrator": r["integrator"], "grid": r["n"],
            "particles": r["particles"], "ranks_or_threads": f"{threads}/{cpus}", "dt": r["dt"], "steps": r["steps"],
            "wall_s": r["wall_s"], "particle_steps_per_s": f"{r['particle_steps_per_s']:.4g}",
            "krylov_its_per_step": r.get("cg_iters_mean", ""), "min_y": f"{r['min_y']:.4f}",
            "free_edge_mid_x": f"{r['free_edge_mid'][0]:.4f}", "free_edge_mid_y": f"{r['free_edge_mid'][1]:.4f}",
            "free_edge_mid_z": f"{r['free_edge_mid'][2]:.4f}", "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "host": socket.gethostname(), "command": f"{r['peer']}_sheet.py --n {r['n']} (the peers' run_all.sh)"})
    append_rows(a.csv, rows)


def cpus_of(row):
    """CPUs a row used: clothsim ranks, or the peer's allowed CPUs."""
    value = str(row["ranks_or_threads"])
    return int(value.split("/")[-1]) if "/" in value else int(value)


def comparable(peer, ours):
    """Same physics within 5 %: the sag (1 m - lowest point) and the free-edge middle's height."""
    sag_ours, sag_peer = 1 - float(ours["min_y"]), 1 - float(peer["min_y"])
    return abs(sag_peer - sag_ours) <= 0.05 * abs(sag_ours) and \
        abs(float(peer["free_edge_mid_z"]) - float(ours["free_edge_mid_z"])) <= 0.05 * abs(float(ours["free_edge_mid_z"]))


def ratios(rows):
    """Per grid and CPU count: clothsim's best full-length run against the fastest peer with the same physics."""
    lines = []
    ours = [r for r in rows if r["simulator"] == "clothsim" and abs(float(r["dt"]) * int(r["steps"]) - 1.0) < 1e-6]
    peers = [r for r in rows if r["tag"] == "peer"]
    for key in sorted({(int(r["grid"]), cpus_of(r)) for r in ours}):
        mine = max((r for r in ours if (int(r["grid"]), cpus_of(r)) == key), key=lambda r: float(r["particle_steps_per_s"]))
        same = [p for p in peers if (int(p["grid"]), cpus_of(p)) == key and abs(float(p["dt"]) - float(mine["dt"])) < 1e-6 * float(mine["dt"])]
        if not same:
            continue
        good = [p for p in same if comparable(p, mine)]
        fastest = max(same, key=lambda r: float(r["particle_steps_per_s"]))
        text = f"- {key[0]} x {key[0]} on {key[1]} CPU(s): clothsim ({mine['tag']}) {float(mine['particle_steps_per_s']):.3g} particle-steps/s"
        if good:
            best = max(good, key=lambda r: float(r["particle_steps_per_s"]))
            text += (f"; fastest peer with the same sag and free edge (within 5 %): {best['simulator']} {best['integrator']} "
                     f"{float(best['particle_steps_per_s']):.3g}, ratio {float(mine['particle_steps_per_s']) / float(best['particle_steps_per_s']):.2f}")
        if fastest not in good:
            text += (f"; fastest peer overall: {fastest['simulator']} {fastest['integrator']} {float(fastest['particle_steps_per_s']):.3g} "
                     f"(ratio {float(mine['particle_steps_per_s']) / float(fastest['particle_steps_per_s']):.2f}), but its lowest point is "
                     f"{fastest['min_y']} m against clothsim's {mine['min_y']} m")
        lines.append(text)
    for grid in sorted({int(r["grid"]) for r in ours}):
        one = [r for r in ours if int(r["grid"]) == grid and cpus_of(r) == 1]
        two = [r for r in ours if int(r["grid"]) == grid and cpus_of(r) == 2]
        for r1 in one:
            for r2 in two:
                if r1["tag"] == r2["tag"]:
                    lines.append(f"- {grid} x {grid} ({r1['tag']}): speed-up on 2 ranks {float(r1['wall_s']) / float(r2['wall_s']):.2f}")
    lines += speedups_over_baseline(rows)
    return lines


def speedups_over_baseline(rows, baseline="earlier_default"):
    """Per grid, ranks and step count: each configuration's wall time against the baseline tag's, same run length."""
    lines = []
    mine = [r for r in rows if r["simulator"] == "clothsim"]
    for r in mine:
        if r["tag"] == baseline:
            continue
        base = [b for b in mine if b["tag"] == baseline and (b["grid"], b["ranks_or_threads"], b["steps"]) == (r["grid"], r["ranks_or_threads"], r["steps"])]
        if base:
            b = base[-1]
            lines.append(f"- {r['grid']} x {r['grid']}, {r['ranks_or_threads']} rank(s), {r['steps']} steps: {r['tag']} ({r.get('preconditioner', '')}, "
                         f"{r['krylov_its_per_step']} its/step) {float(b['wall_s']) / float(r['wall_s']):.2f}x faster than {baseline} "
                         f"({b['krylov_its_per_step']} its/step)")
    return lines


def cmd_report(a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = list(csv.DictReader(open(a.csv)))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for sim, integ, cpus in sorted({(r["simulator"], r["integrator"], cpus_of(r)) for r in rows}):
        sel = sorted((r for r in rows if (r["simulator"], r["integrator"], cpus_of(r)) == (sim, integ, cpus)), key=lambda r: int(r["particles"]))
        for tag in sorted({r["tag"] for r in sel}):
            tsel = [r for r in sel if r["tag"] == tag]
            label = f"{sim} {integ} ({tag}), {cpus} CPU" if sim == "clothsim" else f"{sim} {integ}, {cpus} CPU"
            left.plot([int(r["particles"]) for r in tsel], [float(r["particle_steps_per_s"]) for r in tsel],
                      "o-" if sim == "clothsim" else "s--", label=label)
            if sim == "clothsim":
                right.plot([int(r["particles"]) for r in tsel], [float(r["krylov_its_per_step"]) for r in tsel], "o-", label=label)
    for ax in (left, right):
        ax.set_xscale("log")
        ax.set_xlabel("particles")
        ax.grid(True, which="both", alpha=0.3)
    left.set_yscale("log")
    left.set_ylabel("particle-steps per second")
    left.set_title("hanging sheet, dt = 1/240 s")
    left.legend(fontsize=6)
    right.set_yscale("log")
    right.set_ylabel("Krylov iterations per step")
    right.set_title("iterations per step (flat: a multilevel preconditioner)")
    right.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    cols = ["tag", "simulator", "integrator", "preconditioner", "grid", "ranks_or_threads", "steps", "substeps", "pc_fallbacks",
            "wall_s", "particle_steps_per_s", "krylov_its_per_step", "memory_bytes_per_particle", "bandwidth_GBps", "roofline_fraction", "min_y", "free_edge_mid_z", "date"]
    table = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    table += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for r in rows]
    block = "\n".join([BEGIN, *table, "", *ratios(rows), END])
    text = open(a.markdown).read() if os.path.exists(a.markdown) else f"# Performance\n\n{BEGIN}\n{END}\n"
    if BEGIN not in text:
        text += f"\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    open(a.markdown, "w").write(head + block + rest.split(END, 1)[1])
    print("\n".join(ratios(rows)))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    c = sub.add_parser("clothsim")
    for name in ("--log", "--stream", "--checkpoint-dir", "--csv", "--command"):
        c.add_argument(name, required=name != "--command", default="")
    c.add_argument("--grid", type=int, required=True)
    c.add_argument("--ranks", type=int, required=True)
    c.add_argument("--tag", default="default")
    q = sub.add_parser("peers")
    q.add_argument("--jsonl", required=True)
    q.add_argument("--csv", required=True)
    r = sub.add_parser("report")
    r.add_argument("--csv", required=True)
    r.add_argument("--png", required=True)
    r.add_argument("--markdown", required=True)
    a = p.parse_args()
    {"clothsim": cmd_clothsim, "peers": cmd_peers, "report": cmd_report}[a.what](a)


if __name__ == "__main__":
    main()

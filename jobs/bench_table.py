#!/usr/bin/env python3
"""The scenes' benchmark table (jobs/bench_scenes.sh): one row per clothsim run, read from its log, and the tables
in docs/performance.md.

  bench_table.py add --log LOG --scene NAME --grid N --ranks P --tag TAG --csv CSV --command CMD
      one run (-log_view -memory_view, and -self_collision_view with self-collision) -> one CSV row
  bench_table.py report --csv CSV --markdown MD
      the CSV's newest row of each (tag, scene, grid, ranks, steps) as markdown tables between the markers
      <!-- scenes table begin --> and <!-- scenes table end --> of MD

A row: steps taken and halved (sub-steps beyond the steps), solves redone by the fallback solver, wall seconds of the
time stepping (the Done line), Krylov iterations a step, the peak resident memory of all ranks together
(-memory_view's "Maximum (over computational time) process memory", total) and per particle, the share of the
time stepping spent in contact work (the events ClothCollision, ClothSelfCollision and ClothSelfCoupling of the stage
"Time steps", largest over ranks, over that stage's time), in assembling the implicit system (ClothJacobian) and in
the Krylov solves (KSPSolve), and with self-collision its contacts and candidates a search.
"""
import argparse
import csv
import os
import re
import socket
import sys
import time

FIELDS = ["tag", "scene", "grid", "particles", "ranks", "steps", "t_final", "halved", "fallbacks", "wall_s", "its_per_step",
          "peak_bytes", "peak_bytes_per_particle", "contact_share", "assembly_share", "solve_share", "contacts_per_search",
          "candidates_per_particle", "date", "host", "command"]
BEGIN, END = "<!-- scenes table begin -->", "<!-- scenes table end -->"


def stage_events(text, stage):
    """{event: max time over ranks} of one -log_view stage."""
    m = re.search(r"^--- Event Stage \d+: " + re.escape(stage) + r"\n(.*?)(?=^--- Event Stage|\Z)", text, re.M | re.S)
    if not m:
        return {}
    events = {}
    for line in m.group(1).splitlines():
        f = line.split()
        if len(f) > 4 and re.match(r"^\d\.\d{4}e[+-]\d\d$", f[3]):
            events[f[0]] = events.get(f[0], 0.0) + float(f[3])
    return events


def stage_time(text, stage):
    m = re.search(r"^\s*\d+:\s+" + re.escape(stage) + r": (\S+)", text, re.M)
    return float(m.group(1)) if m else None


def parse(log):
    text = open(log).read()
    row = {}
    done = re.search(r"^Done: (\d+) steps \((\d+) sub-steps\), (\d+) Krylov iterations, ([\d.]+) s wall", text, re.M)
    if not done:
        sys.exit(f"bench_table: {log}: no Done line (the run failed)")
    steps, substeps, its, wall = int(done.group(1)), int(done.group(2)), int(done.group(3)), float(done.group(4))
    particles = re.search(r"^Scene .*: \d+ pieces?, (\d+) particles", text, re.M)
    memory = re.search(r"Maximum \(over computational time\) process memory:\s+total (\S+)", text)
    fallbacks = re.search(r"Preconditioner breakdowns: (\d+) solves", text)
    contacts = re.search(r"searches, ([\d.]+) contacts per search", text)
    candidates = re.search(r"found \d+ times, [\d.]+ per search \(([\d.]+) per particle\)", text)
    events, stepping = stage_events(text, "Time steps"), stage_time(text, "Time steps")
    row.update(steps=steps, halved=substeps - steps, fallbacks=int(fallbacks.group(1)) if fallbacks else 0, wall_s=f"{wall:.2f}",
               its_per_step=f"{its / max(steps, 1):.1f}", particles=int(particles.group(1)) if particles else "")
    if memory and particles:
        peak = float(memory.group(1))
        row.update(peak_bytes=f"{peak:.0f}", peak_bytes_per_particle=f"{peak / int(particles.group(1)):.0f}")
    if events and stepping:
        contact = sum(events.get(e, 0.0) for e in ("ClothCollision", "ClothSelfCollision", "ClothSelfCoupling"))
        row.update(contact_share=f"{contact / stepping:.3f}", assembly_share=f"{events.get('ClothJacobian', 0.0) / stepping:.3f}",
                   solve_share=f"{events.get('KSPSolve', 0.0) / stepping:.3f}")
    if contacts:
        row["contacts_per_search"] = contacts.group(1)
    if candidates:
        row["candidates_per_particle"] = candidates.group(1)
    return row


def add(args):
    row = parse(args.log)
    row.update(tag=args.tag, scene=args.scene, grid=args.grid, ranks=args.ranks, t_final=args.t_final, date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
               host=socket.gethostname(), command=args.command)
    new = not os.path.exists(args.csv)
    with open(args.csv, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerow({k: row.get(k, "") for k in FIELDS})
    print(", ".join(f"{k} {row.get(k, '')}" for k in ("scene", "grid", "ranks", "steps", "halved", "fallbacks", "wall_s", "its_per_step",
                                                      "peak_bytes_per_particle", "contact_share", "candidates_per_particle")))


def kb(value):
    return f"{float(value) / 1024:.2f}" if value not in (None, "") else "-"


def percent(value):
    return f"{100 * float(value):.0f} %" if value else "-"


def report(args):
    rows = list(csv.DictReader(open(args.csv)))
    newest = {}
    for r in rows:
        newest[(r["tag"], r["scene"], int(r["grid"]), int(r["ranks"]), int(r["steps"]))] = r
    baseline = {(k[1], k[3]): float(r["peak_bytes"]) for k, r in newest.items() if k[0] == "baseline" and r["peak_bytes"]}
    lines = ["| scene | tag | grid | ranks | steps (simulated s) | wall s | Krylov its/step | halved | fallback solves | peak memory, KB/particle (above the baseline) | contact work | assembly | candidates/particle |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(newest, key=lambda k: (k[1], k[0], k[2], k[3], k[4])):
        r = newest[key]
        if key[0] == "baseline":
            continue
        above = (float(r["peak_bytes"]) - baseline[(key[1], key[3])]) / int(r["particles"]) if r["peak_bytes"] and (key[1], key[3]) in baseline else None
        lines.append(f"| {r['scene']} | {r['tag']} | {r['grid']} | {r['ranks']} | {r['steps']} ({r['t_final']}) | {r['wall_s']} | {r['its_per_step']} | {r['halved']} | "
                     f"{r['fallbacks']} | {kb(r['peak_bytes_per_particle'])} ({kb(above) if above is not None else '-'}) | {percent(r['contact_share'])} | {percent(r['assembly_share'])} | "
                     f"{r['candidates_per_particle'] or '-'} |")
    if baseline:
        lines.append("")
        lines.append("Baselines (-grid 9, one step: the processes' libraries and buffers), MB over all ranks: " +
                     ", ".join(f"{s} on {p} rank(s) {b / 2**20:.0f}" for (s, p), b in sorted(baseline.items())) + ".")
    table = "\n".join(lines) + "\n"
    md = open(args.markdown).read()
    if BEGIN not in md or END not in md:
        sys.exit(f"bench_table: {args.markdown} has no {BEGIN} ... {END} markers")
    head, rest = md.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    open(args.markdown, "w").write(head + BEGIN + "\n" + table + END + tail)
    print(f"bench_table: {len(newest)} rows into {args.markdown}")


def main():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="what", required=True)
    a = sub.add_parser("add")
    for name in ("log", "scene", "grid", "ranks", "tag", "csv", "command", "t_final"):
        a.add_argument("--" + name.replace("_", "-"), dest=name, required=name != "t_final", default="")
    r = sub.add_parser("report")
    r.add_argument("--csv", required=True)
    r.add_argument("--markdown", required=True)
    args = parser.parse_args()
    add(args) if args.what == "add" else report(args)


if __name__ == "__main__":
    main()

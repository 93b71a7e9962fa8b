#!/usr/bin/python3
"""Renders jobs/results/bench_implicit.csv as a markdown table into docs/foundation.md, between the lines
<!-- bench_implicit table begin --> and <!-- bench_implicit table end --> (written by jobs/bench_implicit.sh).

  bench_table.py [CSV] [MARKDOWN]
"""
import csv
import sys

BEGIN = "<!-- bench_implicit table begin -->"
END = "<!-- bench_implicit table end -->"


def table(rows):
    lines = [
        "| grid | particles | ranks | steps | wall s | particle-steps/s (wall) | particle-steps/CPU-s | KSP its/step "
        "| memory/particle | assembly (ClothJacobian) s | solve (ClothSolve) s | solve share | load |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        particles, steps = int(r["particles"]), int(r["steps"])
        jacobian, solve = float(r["jacobian_s"]), float(r["solve_s"])
        per_cpu = f"{particles * steps / float(r['cpu_s']):.3g}" if r["cpu_s"] else "n/a"
        share = f"{100 * solve / (jacobian + solve):.0f} %" if jacobian + solve > 0 else "n/a"
        lines.append(
            f"| {r['grid']} | {particles} | {r['ranks']} | {steps} | {float(r['wall_s']):.1f} "
            f"| {float(r['particle_steps_per_s']):.3g} | {per_cpu} | {r['ksp_its_per_step']} "
            f"| {float(r['memory_bytes_per_particle']) / 1024:.1f} KiB | {jacobian:.2f} | {solve:.2f} | {share} | {r['load']} |")
    return "\n".join(lines)


def main():
    csv_path = sys.argv[1] if len(sys.argv) > 1 else "jobs/results/bench_implicit.csv"
    md_path = sys.argv[2] if len(sys.argv) > 2 else "docs/foundation.md"
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    text = open(md_path).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"bench_table.py: {md_path} lacks the lines {BEGIN} and {END}")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    open(md_path, "w").write(head + BEGIN + "\n" + table(rows) + "\n" + END + tail)
    print(f"bench_table.py: {len(rows)} rows from {csv_path} into {md_path}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Performance model of the implicit hanging sheet (issue 25 item 4), calibrated on this machine, projected to 1024 ranks.

Two multilevel solvers (--solver): "grid", the default of large sheets (the pattern-grid multigrid: every level on all
P ranks, the coarsest, at most GRID_COARSE_PARTICLES particles, factored and solved redundantly on every rank), and
"gamg" (its earlier default, calibrated on the issue 22 benchmark's logs).

Time per step on P ranks for N particles (all terms per rank and per step):

  T(N, P) = T_compute + T_halo + T_reduce
  T_compute = f N / P / r                      f: flop per particle-step, r: flop/s of one rank (measured, 1 rank)
  T_halo    = m(N, P) alpha + b(N, P) / beta_rank
      m = mu nb(P) L(N) / L(N0)                messages: mu per neighbour rank per step (measured at 4 and 8 ranks),
                                               nb(P) = min(P - 1, NB_MAX (1 - 1/sqrt(P))) neighbours, proportional to the
                                               multigrid levels L
      b = kappa 4 sqrt(N / P)                  bytes: kappa per particle of a part's perimeter (measured at 4 and 8 ranks)
  T_reduce  = R(N) 2 ceil(log2 P) alpha        R: global reductions per step (measured; grows with the levels), each a
                                               recursive-doubling allreduce of a few words
  L(N) = 1 + ceil(log(3 N / COARSE_EQ) / log(q))  GAMG levels: q the measured coarsening ratio per level
        = 1 + ceil(log(N / GRID_COARSE_PARTICLES) / log(q))  pattern-grid levels (q = 16 at the default ratio 4)
  beta_rank = beta_node / RANKS_PER_NODE
  grid only: T_coarse = V (min(P - 1, n_c) alpha + 24 n_c / beta_rank)  the redundant coarse solve gathers the coarsest
                                               level's n_c particles from the ranks that own them, V V-cycles a step
                                               (the Krylov iterations + 1)

GAMG's coarse levels: a level of n_l = 3 N / q^l equations runs on min(P, n_l / PROCESS_EQ_LIMIT) ranks
(-pc_gamg_process_eq_limit, PETSc's default 50); its compute (the fraction (complexity - 1) of the flops, spread over the
levels as rho^l) is divided by those ranks instead of P, and its messages are counted in m through L. The pattern grid's
coarse levels stay on all ranks (a rank owns the coarse particles that sit on its fine ones), min(P, n_l) of them busy;
its coarsest level is solved whole on every rank.

Iterations: the pattern-grid multigrid's iterates do not depend on the partition, so strong scaling keeps the
calibration's iterations per step; they grow with the sheet as it wrinkles (ITS_FULL_SECOND, measured over the full
second), which the weak-scaling rows "weak, iterations growing" carry as a factor on every term.

Inputs (read from the logs, not typed in):
  --compute-log  a 1-rank -log_view of the sheet on an idle machine: r = flop / time of the "Time steps" stage, f = flop
                 per particle-step, the Krylov iterations per step, the pattern-grid levels (default: 257 x 257, 24 steps,
                 jobs/results/at_scale/calibration, made by jobs/at_scale.sh as below)
  --count-logs   -log_view of the same sheet on 2, 4, 8 ranks (oversubscribed: only their counts are used) with
                 -cloth_view_partition: messages, bytes and reductions per step, neighbour ranks per rank
  --check-log    a 2-rank -log_view on the idle machine: measured time per step against the model's
Assumed: alpha (1.5 us), beta_node (12 GB/s), RANKS_PER_NODE (32), NB_MAX (6: a part inside a 2-D partition of a sheet); for
GAMG q and the operator complexity (measured by -info :pc at 257 x 257: 198147 -> 10587 -> 2196 -> 315 -> 39 equations,
1.104), for the pattern grid q and the complexity from the compute log's levels.

The calibration runs (the default logs; idle machine for the first two, 4 and 8 ranks oversubscribed: counts only):
    OUT=jobs/results/at_scale/calibration MALLOC_LOG=0 STEPS=24 jobs/at_scale.sh 257 1 compute
    OUT=jobs/results/at_scale/calibration MALLOC_LOG=0 STEPS=24 jobs/at_scale.sh 257 2 check
    for r in 2 4 8; do OUT=jobs/results/at_scale/calibration MALLOC_LOG=0 STEPS=6 jobs/at_scale.sh 257 $r counts -cloth_view_partition; done
  and for --solver gamg the same count runs with the tag counts_gamg and -pc_type gamg.

    jobs/perf_model.py [--solver grid|gamg] [--count-logs LOG ...] [--out docs/figures/perf_model.png] [--csv jobs/results/at_scale/perf_model.csv]
"""
import argparse
import csv
import glob
import math
import re
import sys

ALPHA = 1.5e-6  # s, latency per message (and per step of an allreduce)
BETA_NODE = 12e9  # bytes/s per node
RANKS_PER_NODE = 32
NB_MAX = 6
COARSE_EQ = 50  # -pc_gamg_coarse_eq_limit (PETSc default)
PROCESS_EQ_LIMIT = 50  # -pc_gamg_process_eq_limit (PETSc default)
LEVEL_SIZES_257 = [198147, 10587, 2196, 315, 39]  # GAMG, -info :pc, 257 x 257, 1 rank
OPERATOR_COMPLEXITY = 1.10416
GRID_COARSE_PARTICLES = 1000  # -implicit_pc_grid_coarse_particles (src/preconditioner.c)
# Krylov iterations a step of the pattern-grid multigrid over the full simulated second (docs/performance.md, "Refreshed
# every step from 40,000 particles"): 257 x 257 (1 rank, refreshed every step) and 513 x 513 (2 ranks, the default)
ITS_FULL_SECOND = {257 * 257: 18.6, 513 * 513: 33.2}


def parse(path):
    """The "Time steps" stage (time, flop total, messages total, average message length, reductions), the steps, the
    Krylov iterations, the particles and the neighbour ranks of each rank (-cloth_view_partition)."""
    run = {"path": path, "neighbours": []}
    try:
        f = open(path)
    except OSError as e:
        print(f"perf_model.py: skipping {path}: {e.strerror}", file=sys.stderr)
        return None
    with f:
        for line in f:
            m = re.match(r"^\s*2:\s+Time steps:\s+(\S+)\s+\S+\s+(\S+)\s+\S+\s+(\S+)\s+\S+\s+(\S+)\s+\S+\s+(\S+)", line)
            if m:
                run["time"], run["flop"], run["messages"], run["avglen"], run["reductions"] = (float(x) for x in m.groups())
            m = re.match(r"^Done: (\d+) steps .*?, (\d+) Krylov iterations", line)
            if m:
                run["steps"], run["krylov"] = int(m.group(1)), int(m.group(2))
            m = re.search(r"(\d+) particles", line)
            if m and "particles" not in run and line.startswith("Scene"):
                run["particles"] = int(m.group(1))
            m = re.search(r"ghosts \d+ from (\d+) rank\(s\)", line)
            if m:
                run["neighbours"].append(int(m.group(1)))
            m = re.search(r" with (\d+) processors?,", line)
            if m:
                run["ranks"] = int(m.group(1))
            m = re.match(r"^\s+level (\d+): (\d+) particles", line)
            if m:
                run.setdefault("grid_levels", {})[int(m.group(1))] = int(m.group(2))
    for k in ("time", "steps", "particles", "ranks"):
        if k not in run:
            print(f"perf_model.py: skipping {path}: no {k} (a -log_view of a finished clothsim run expected)", file=sys.stderr)
            return None
    return run


def neighbours(p):
    """Neighbour ranks of a part of a 2-D sheet: NB_MAX inside, fewer for the parts on the sheet's edge (a fraction
    about 1/sqrt(P) of them); measured 1, 2.5, 3.25 at 2, 4, 8 ranks (the model: 1, 3.0, 3.9)."""
    return min(p - 1, NB_MAX * (1 - 1 / math.sqrt(p)))


class Model:
    def __init__(self, compute, counts, solver):
        self.solver = solver
        if solver == "grid":
            if "grid_levels" not in compute:
                sys.exit(f"perf_model.py: {compute['path']} lists no pattern-grid levels (was it run with the pattern-grid multigrid?)")
            sizes = [compute["grid_levels"][k] for k in sorted(compute["grid_levels"], reverse=True)]
            complexity = sum(sizes) / sizes[0]
        else:
            sizes, complexity = LEVEL_SIZES_257, OPERATOR_COMPLEXITY
        self.q = (sizes[0] / sizes[-1]) ** (1.0 / (len(sizes) - 1))
        self.complexity = complexity
        # rho: the fraction of the flops on level l is rho^l, so that they sum to the operator complexity
        self.rho = 1 - 1 / complexity
        self.n0 = compute["particles"]
        self.l0 = self.levels(self.n0)
        self.r = compute["flop"] / compute["time"]
        self.f = compute["flop"] / compute["steps"] / self.n0
        self.its = compute["krylov"] / compute["steps"]
        mus, kappas, reds = [], [], []
        for c in counts:
            p, steps = c["ranks"], c["steps"]
            # neighbour ranks per rank from -cloth_view_partition, which lists the ranks a rank takes ghosts from: only the
            # side of a boundary that evaluates the interactions has ghosts, so each neighbouring pair is listed once
            nb = 2 * sum(c["neighbours"]) / p if c["neighbours"] else min(p - 1, 2)
            c["nb"] = nb
            c["m"] = c["messages"] / p / steps
            c["b"] = c["messages"] * c["avglen"] / p / steps
            c["R"] = c["reductions"] / steps
            if p >= 4 or len(counts) == 1:
                mus.append(c["m"] / nb)
                kappas.append(c["b"] / (4 * math.sqrt(c["particles"] / p)))
            reds.append(c["R"])
        self.mu = sum(mus) / len(mus)
        self.kappa = sum(kappas) / len(kappas)
        self.R0 = sum(reds) / len(reds)
        self.counts = counts

    def levels(self, n_particles):
        if self.solver == "grid":
            return 1 + max(0, math.ceil(math.log(n_particles / GRID_COARSE_PARTICLES) / math.log(self.q)))
        return 1 + math.ceil(math.log(3 * n_particles / COARSE_EQ) / math.log(self.q))

    def active_ranks(self, n, l, lv, p):
        """Ranks busy on level l (0 finest) of lv: GAMG gathers a coarse level onto fewer ranks, the pattern grid keeps
        it on all (one particle at least per busy rank) and solves its coarsest level whole on every rank."""
        if self.solver == "grid":
            return 1 if l == lv - 1 else max(1, min(p, int(n / self.q ** l)))
        return max(1, min(p, int(3 * n / self.q ** l / PROCESS_EQ_LIMIT)))

    def terms(self, n, p, its_factor=1.0):
        """Seconds per step of each term; its_factor scales the iterations (and so every term) against the calibration's."""
        lv = self.levels(n)
        # compute: the fine level on P ranks, the coarse ones as active_ranks says
        fine = self.f * n / self.complexity
        t_compute = fine / p / self.r
        for l in range(1, lv):
            t_compute += fine * self.rho ** l / self.active_ranks(n, l, lv, p) / self.r
        t = {"compute": t_compute, "halo_latency": 0.0, "halo_bandwidth": 0.0, "reductions": 0.0, "coarse_gather": 0.0}
        if p > 1:
            m = self.mu * neighbours(p) * lv / self.l0
            b = self.kappa * 4 * math.sqrt(n / p)
            beta_rank = BETA_NODE / min(p, RANKS_PER_NODE)
            t["halo_latency"] = m * ALPHA
            t["halo_bandwidth"] = b / beta_rank
            t["reductions"] = self.R0 * lv / self.l0 * 2 * math.ceil(math.log2(p)) * ALPHA
            if self.solver == "grid":
                n_c = n / self.q ** (lv - 1)
                t["coarse_gather"] = (self.its + 1) * (min(p - 1, n_c) * ALPHA + 24 * n_c / beta_rank)
        t = {k: v * its_factor for k, v in t.items()}
        t["levels"] = lv
        return t

    def time(self, n, p, its_factor=1.0):
        t = self.terms(n, p, its_factor)
        return sum(v for k, v in t.items() if k != "levels")

    def its_factor(self, n):
        """Iterations a step over the full second at n particles against the calibration run's: a power law through the
        measured ITS_FULL_SECOND (pattern grid only)."""
        (n1, i1), (n2, i2) = sorted(ITS_FULL_SECOND.items())
        gamma = math.log(i2 / i1) / math.log(n2 / n1)
        return i1 * (n / n1) ** gamma / self.its


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--solver", choices=("grid", "gamg"), default="grid")
    ap.add_argument("--compute-log")
    ap.add_argument("--check-log")
    ap.add_argument("--count-logs", nargs="+")
    ap.add_argument("--out")
    ap.add_argument("--csv")
    args = ap.parse_args()
    calib = "jobs/results/at_scale/calibration"
    if args.solver == "grid":
        defaults = {"compute_log": f"{calib}/grid257_np1_compute.log", "check_log": f"{calib}/grid257_np2_check.log",
                    "count_logs": sorted(glob.glob(f"{calib}/grid257_np[248]_counts.log")), "out": "docs/figures/perf_model.png",
                    "csv": "jobs/results/at_scale/perf_model.csv"}
    else:  # the issue 22 benchmark's logs (GAMG was the default then) and count runs with -pc_type gamg
        defaults = {"compute_log": "jobs/results/bench/clothsim_default_grid_257_np_1_20261125T153740Z.log",
                    "check_log": "jobs/results/bench/clothsim_default_grid_257_np_2_20261125T153740Z.log",
                    "count_logs": sorted(glob.glob(f"{calib}/grid257_np[248]_counts_gamg.log")),
                    "out": "docs/figures/perf_model_gamg.png", "csv": "jobs/results/at_scale/perf_model_gamg.csv"}
    for k, v in defaults.items():
        if getattr(args, k) is None:
            setattr(args, k, v)
    if not args.count_logs:
        sys.exit(f"perf_model.py: no count logs (run: for r in 2 4 8; do OUT={calib} MALLOC_LOG=0 STEPS=6 jobs/at_scale.sh 257 $r counts"
                 f"{'' if args.solver == 'grid' else '_gamg'} -cloth_view_partition{'' if args.solver == 'grid' else ' -pc_type gamg'}; done)")
    counts = [c for c in (parse(p) for p in args.count_logs) if c]
    compute = parse(args.compute_log)
    if not counts or not compute:
        sys.exit("perf_model.py: no usable compute or count log")
    model = Model(compute, counts, args.solver)
    print(f"Calibration: r = {model.r / 1e9:.3f} Gflop/s per rank, f = {model.f:.4g} flop per particle-step, "
          f"{model.its:.2f} Krylov its/step ({args.compute_log})")
    print(f"  {args.solver}: coarsening ratio q = {model.q:.2f}, operator complexity {model.complexity:.3f}, levels at N0 = {model.n0}: {model.l0}; mu = {model.mu:.1f} messages per "
          f"neighbour per step, kappa = {model.kappa:.1f} bytes per perimeter particle per step, R = {model.R0:.1f} reductions per step")
    print("\nCounts per rank and step (measured | model):")
    print("| ranks | neighbours (mean) | messages | model | bytes | model | reductions | Krylov its/step |")
    print("|---|---|---|---|---|---|---|---|")
    for c in model.counts:
        p, n = c["ranks"], c["particles"]
        lv = model.levels(n)
        m_model = model.mu * neighbours(p) * lv / model.l0 if p > 1 else 0
        b_model = model.kappa * 4 * math.sqrt(n / p)
        print(f"| {p} | {c['nb']:.2f} | {c['m']:.0f} | {m_model:.0f} | {c['b']:.3g} | {b_model:.3g} | {c['R']:.0f} | {c['krylov'] / c['steps']:.2f} |")
    check = parse(args.check_log)
    if not check:
        sys.exit("perf_model.py: no usable check log")
    t_meas = check["time"] / check["steps"]
    t_mod = model.time(check["particles"], check["ranks"])
    t1 = model.time(model.n0, 1)
    print(f"\nCheck: {check['particles']} particles on {check['ranks']} ranks, measured {t_meas:.4f} s/step, model {t_mod:.4f} s/step "
          f"(1 rank: measured {model.f * model.n0 / model.r:.4f}, model {t1:.4f})")

    ranks = [2 ** k for k in range(0, 11)]
    rows = []
    for n in (1e7, 1e8):
        for p in ranks:
            t = model.terms(n, p)
            rows.append({"study": "strong", "particles": n, "ranks": p, "seconds_per_step": model.time(n, p), **t})
    weak_studies = [("weak", False)] + ([("weak, iterations growing", True)] if args.solver == "grid" else [])
    for study, growing in weak_studies:
        for per_rank in (1e7 / 1024, 1e8 / 1024):
            for p in ranks:
                n = per_rank * p
                factor = model.its_factor(n) if growing else 1.0
                t = model.terms(n, p, factor)
                rows.append({"study": study, "particles": n, "ranks": p, "seconds_per_step": model.time(n, p, factor), **t})
    for r in rows:
        if r["study"] == "strong":
            ref = next(x for x in rows if x["study"] == "strong" and x["particles"] == r["particles"] and x["ranks"] == 32)
            r["efficiency_vs_32"] = ref["seconds_per_step"] * 32 / (r["seconds_per_step"] * r["ranks"])
        else:
            ref = next(x for x in rows if x["study"] == r["study"] and abs(x["particles"] / x["ranks"] - r["particles"] / r["ranks"]) < 1 and x["ranks"] == 1)
            r["efficiency_vs_32"] = ref["seconds_per_step"] / r["seconds_per_step"]
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("\nPredicted (s per step; efficiency: strong against 32 ranks, weak against 1 rank):")
    print("| study | particles | ranks | s/step | compute, s | halo latency, ms | halo bandwidth, ms | reductions, ms | coarse gather, ms | levels | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if r["ranks"] in (1, 32, 128, 256, 1024) and not (r["study"] == "strong" and r["ranks"] == 1) and not (r["study"] != "strong" and r["ranks"] in (128, 256)):
            print(f"| {r['study']} | {r['particles']:.3g} | {r['ranks']} | {r['seconds_per_step']:.3g} | {r['compute']:.3g} | {1e3 * r['halo_latency']:.2f} | "
                  f"{1e3 * r['halo_bandwidth']:.2f} | {1e3 * r['reductions']:.2f} | {1e3 * r['coarse_gather']:.2f} | {r['levels']} | {r['efficiency_vs_32']:.2f} |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    for n, style in ((1e7, "-o"), (1e8, "-s")):
        sel = [r for r in rows if r["study"] == "strong" and r["particles"] == n]
        ax[0].loglog([r["ranks"] for r in sel], [r["seconds_per_step"] for r in sel], style, label=f"{n:.0e} particles")
        big = [r for r in sel if r["ranks"] >= 32]
        ax[1].semilogx([r["ranks"] for r in big], [r["efficiency_vs_32"] for r in big], style, label=f"strong, {n:.0e}")
    for study, _ in weak_studies:
        for per_rank, style in ((1e7 / 1024, "--o" if study == "weak" else ":o"), (1e8 / 1024, "--s" if study == "weak" else ":s")):
            sel = [r for r in rows if r["study"] == study and abs(r["particles"] / r["ranks"] - per_rank) < 1]
            ax[1].semilogx([r["ranks"] for r in sel], [r["efficiency_vs_32"] for r in sel], style, label=f"{study}, {per_rank:.3g}/rank")
    ax[1].axhline(0.7, color="grey", lw=0.8)
    sel = [r for r in rows if r["study"] == "strong" and r["particles"] == 1e7]
    bottom = [0.0] * len(sel)
    for term in ("compute", "halo_latency", "halo_bandwidth", "reductions", "coarse_gather"):
        vals = [r[term] / r["seconds_per_step"] for r in sel]
        ax[2].bar([str(r["ranks"]) for r in sel], vals, bottom=bottom, label=term)
        bottom = [a + b for a, b in zip(bottom, vals)]
    ax[2].set_ylim(0.6, 1.0)
    ax[0].set(xlabel="ranks", ylabel="s per step", title="strong scaling (model)")
    ax[1].set(xlabel="ranks", ylabel="efficiency", title="strong (vs 32 ranks) and weak (vs 1 rank)", ylim=(0, 1.1))
    ax[2].set(xlabel="ranks", ylabel="share of the step (from 0.6)", title="1e7 particles: where the step goes")
    for a in ax:
        a.legend(fontsize=8)
    solver = "pattern-grid multigrid" if args.solver == "grid" else "GAMG"
    fig.suptitle(f"clothsim implicit sheet, {solver}: alpha {ALPHA * 1e6:.1f} us, {BETA_NODE / 1e9:.0f} GB/s per node of {RANKS_PER_NODE} ranks, "
                 f"{model.r / 1e9:.2f} Gflop/s per rank (measured)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=90)
    print(f"\nWrote {args.out} and {args.csv}")


if __name__ == "__main__":
    main()

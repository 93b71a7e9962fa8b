#!/bin/bash
# jobs/bench.sh end to end on a small sheet (17 x 17, 12 steps, 1 and 2 ranks, no peers), into a work
# folder: the triad must report a bandwidth, every run a CSV row whose figures agree with the run's own
# log (steps, Krylov iterations per step, particle-steps/s from the Done line), a positive modelled
# traffic and roofline fraction, the free-edge probe from the checkpoint, and the report its PNG and table.
# Usage: check_bench.sh WORKDIR      (CLOTHSIM_BUILD: the build folder)
set -euo pipefail
work=$1
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
OUT_DIR=$work MARKDOWN=$work/performance.md BUILD_DIR=$CLOTHSIM_BUILD GRIDS=17 RANKS_LIST="1 2" PEERS= T_FINAL=0.05 TAG=ctest \
  bash jobs/bench.sh > "$work/bench.log" 2>&1 || { cat "$work/bench.log"; fail "jobs/bench.sh failed"; }
cat "$work/bench.log"
[ -s "$work/bench.png" ] || fail "no bench.png"
grep -q "<!-- bench table begin -->" "$work/performance.md" || fail "no table in performance.md"
/usr/bin/python3 - "$work" <<'PY'
import csv, glob, re, sys
work = sys.argv[1]
rows = list(csv.DictReader(open(f"{work}/bench.csv")))
assert len(rows) == 2, f"expected 2 rows, got {len(rows)}"
for r in rows:
    log = glob.glob(f"{work}/clothsim_ctest_grid_17_np_{r['ranks_or_threads']}_*.log")[0]
    done = re.search(r"^Done: (\d+) steps \(\d+ sub-steps\), (\d+) Krylov iterations, ([0-9.]+) s wall", open(log).read(), re.M)
    steps, its, wall = int(done.group(1)), int(done.group(2)), float(done.group(3))
    assert int(r["steps"]) == steps == 12, r
    assert abs(float(r["krylov_its_per_step"]) - its / steps) < 0.06, (r["krylov_its_per_step"], its / steps)
    assert abs(float(r["particle_steps_per_s"]) / (289 * steps / wall) - 1) < 1e-3, r
    assert float(r["bandwidth_GBps"]) > 0.1 and float(r["model_bytes_per_step"]) > 0 and float(r["roofline_fraction"]) > 0, r
    # 17 x 17 at 0.05 s: the free-edge middle has fallen 0.5 g t^2 = 1.2 cm at most, and stays at x = 0.5
    assert abs(float(r["free_edge_mid_x"]) - 0.5) < 1e-6 and 0.985 < float(r["free_edge_mid_y"]) < 1.0, r
    print(f"ranks {r['ranks_or_threads']}: {r['particle_steps_per_s']} particle-steps/s, {r['krylov_its_per_step']} its/step, "
          f"roofline {r['roofline_fraction']}, free edge y {r['free_edge_mid_y']}: consistent with {log}")
PY

#!/usr/bin/env python3
"""Counted scaling runs: the 2-D and 3-D dam breaks and the seed's coupled tanks (2-D rectangular, 3-D
baffled) on 1, 2, 4, 8, 16, 32 and 64 ranks, oversubscribed (not timed: the counts do not depend on the
cores), each for a few steps. Prints per rank the owned particles and ghosts, the pairs with ghosts, the
ranks it sends to, the messages, bytes and collectives per step, and the load imbalance (summary.json's
"parallel", src/solver/parallelstats.c), and keeps every run's summary.json in --out for the model
(bench/scaling_model.py).

    /usr/bin/python3 bench/bench_scaling.py [--ranks 1,2,4,8,16,32,64] [--cases dam2d,dam3d,seed2d,baffled3d]
                                            [--out bench-scaling]

The cases (their resolution is the counted runs', not the projections'):
  dam2d      the 2-D dam break of bench_dam_break.py at its resolution (dx = 0.01 m, 20,000 particles), 40 steps
  dam3d      the 3-D dam break of bench_dam_break_3d.py at dx = 0.05 m (32,000 particles: the bench's 310,675 on 64
             oversubscribed ranks would need about 2.5 GB and far longer), 6 steps
  seed2d     cases/coupled_rectangular.opts at dx = 2 mm (5,250 particles), 40 steps, with the numerics that hold
             through the slams at the seed's resolutions (SLAMS below: the density diffusion split off, CFL 0.8)
  baffled3d  cases/coupled_baffled_3d.opts at dx = 5 mm (8,400 particles), 4 steps
  seed2d_thin, baffled3d_thin  (not by default) seed2d and baffled3d with -fs_series_interval 1000: the
             collectives a step with the time-series rows thinned out (scaling_model.py reads them)
  seed2d_slosh  (not by default) the seed's tank at dx = 2 mm for 1 s (the release and the slams): how far the load
             imbalance drifts as the liquid moves, the cuts following it (--cases seed2d_slosh --ranks 2,8);
             seed2d_slosh_1.1, seed2d_slosh_1.05: the same with -fs_rebalance_threshold 1.1 and 1.05 (the default
             1.2), and seed2d_slosh_5mm the same at dx = 5 mm (the scenario of 2026-12-05)

With --timed it times instead, on 1 and 2 ranks (--repeats times, the load noted): the seed's tank at L/dx = 2000
(dx = 0.35 mm, 172,000 particles, 20 steps) and the 3-D baffled tank 0.1 m wide at dx = 2.5 mm (134,400
particles, 3 steps): the per-core cost of a particle-step the model starts from.

A run whose summary.json is already in --out is not made again (an interrupted count continues).
"""
import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# the numerics the seed's tanks hold their slams with at dx <= 1 mm (validate.py's SEED_CONVERGENCE_NUMERICS and
# seed_slams; docs/performance.md): (a) of the model is projected with them
SLAMS = ["-fs_delta_split", "-fs_cfl", "0.8", "-fs_max_density_variation", "0.95", "-fs_walls_bounce_distance", "0.3"]
RECT = ["-options_file", str(ROOT / "cases/coupled_rectangular.opts")]

CASES = {
    "dam2d": ["-fs_case", "dam_break", "-fs_dx", "0.01", "-ts_max_steps", "40"],
    "dam3d": ["-fs_case", "dam_break", "-fs_dim", "3", "-fs_dx", "0.05", "-ts_max_steps", "6"],
    "seed2d": RECT + SLAMS + ["-fs_dx", "0.002", "-ts_max_steps", "40"],
    "baffled3d": ["-options_file", str(ROOT / "cases/coupled_baffled_3d.opts"), "-fs_dx", "0.005", "-ts_max_steps", "4"],
    # the coupled tanks with the time-series rows thinned out (not by default): the collectives the model's
    # "rows thinned" scenario takes
    "seed2d_thin": RECT + SLAMS + ["-fs_dx", "0.002", "-ts_max_steps", "40", "-fs_series_interval", "1000"],
    "baffled3d_thin": ["-options_file", str(ROOT / "cases/coupled_baffled_3d.opts"), "-fs_dx", "0.005", "-ts_max_steps",
                       "4", "-fs_series_interval", "1000"],
    # the imbalance over a sloshing second, the cuts following the liquid (not in the default --cases)
    "seed2d_slosh": RECT + SLAMS + ["-fs_dx", "0.002", "-ts_max_time", "1"],
    "seed2d_slosh_1.1": RECT + SLAMS + ["-fs_dx", "0.002", "-ts_max_time", "1", "-fs_rebalance_threshold", "1.1"],
    "seed2d_slosh_1.05": RECT + SLAMS + ["-fs_dx", "0.002", "-ts_max_time", "1", "-fs_rebalance_threshold", "1.05"],
    "seed2d_slosh_5mm": RECT + ["-fs_dx", "0.005", "-ts_max_time", "1"],
}


# the timed runs (--timed): the projections' cases themselves, (a) at its resolution, (b) at 2.5 mm, a few steps
TIMED = {
    "seed2d_L2000": RECT + SLAMS + ["-fs_dx", "0.00035", "-ts_max_steps", "20"],
    "baffled3d_w01": ["-options_file", str(ROOT / "cases/coupled_baffled_3d.opts"), "-fs_tank_width", "0.1",
                      "-fs_dx", "0.0025", "-ts_max_steps", "3"],
}


def timed(exe, ranks, repeats, out):
    """Times the TIMED cases on each rank count (FSStep of -log_view: the steps without set-up and output), with
    the machine's load before each run; prints the seconds per particle-step on one core."""
    from benchutil import run_logged
    for case, args in TIMED.items():
        for rep in range(repeats):
            for nr in ranks:
                load = open("/proc/loadavg").read().split()[0]
                s, t = run_logged(exe, nr, args + ["-fs_output_interval", "0"], out / f"timed-{case}-np{nr}-{rep}",
                                  ["FSStep", "FSRHS", "FSHalo", "FSWalls"])
                w = t.get("FSStep", s["wall_time"])
                print(f"{case:14s} {nr} rank(s), run {rep + 1}: {s['particles']} particles, {s['steps']} steps, "
                      f"{w:8.2f} s, {w / s['steps']:.4f} s/step, {w * nr / (s['particles'] * s['steps']):.3e} core-s per "
                      f"particle-step (load before: {load})", flush=True)


def run(exe, case, nranks, outdir):
    """Runs one counted run (no snapshots) and returns its summary.json (the one already there, if any)."""
    if (outdir / "summary.json").exists():
        return json.load(open(outdir / "summary.json"))
    outdir.mkdir(parents=True, exist_ok=True)
    cmd = [str(exe)] + CASES[case] + ["-fs_output_interval", "0", "-fs_output_dir", str(outdir), "-fs_progress", "0"]
    if nranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(nranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    with open(outdir / "log.txt", "w") as log:
        subprocess.run(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, check=True)
    return json.load(open(outdir / "summary.json"))


def table(case, results):
    """The per-rank table of one case: for each rank count the mean and the largest over the ranks."""
    print(f"\n{case}: {results[min(results)]['particles']} particles")
    print("ranks  grid      owned mean/max    ghosts mean/max   ghosts/owned  share of pairs w/ ghosts  send ranks"
          "  msgs/step  kB/step  coll/step  imbalance (owned end, pairs over steps)")
    for nr in sorted(results):
        p = results[nr]["parallel"]
        n = len(p["owned"])
        mean = lambda k: sum(p[k]) / n
        print(f"{nr:5d}  {'x'.join(str(int(g)) for g in p['grid']):8s} {mean('owned'):8.0f} {max(p['owned']):7.0f}"
              f"   {mean('ghosts'):7.0f} {max(p['ghosts']):7.0f}   {mean('ghosts') / mean('owned'):10.3f}"
              f"   {mean('pairs_with_ghosts') / max(mean('pairs'), 1):22.3f}   {mean('send_ranks'):4.1f} {max(p['send_ranks']):3.0f}"
              f"  {mean('messages_per_step'):8.1f}  {mean('bytes_per_step') / 1e3:7.1f}  {max(p['collectives_per_step']):8.1f}"
              f"   {p['imbalance_owned_end']:.3f}, {p['imbalance_pairs']:.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", default="1,2,4,8,16,32,64")
    ap.add_argument("--cases", default="dam2d,dam3d,seed2d,baffled3d")
    ap.add_argument("--out", default="bench-scaling", help="where the runs' summaries are kept")
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    ap.add_argument("--table-only", action="store_true", help="print the tables of the runs already in --out")
    ap.add_argument("--timed", action="store_true", help="time the projections' cases on 1 and 2 ranks instead")
    ap.add_argument("--repeats", type=int, default=2)
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    out = Path(a.out)
    if a.timed:
        timed(exe, [1, 2], a.repeats, out)
        return 0
    for case in a.cases.split(","):
        results = {}
        for nr in [int(r) for r in a.ranks.split(",")]:
            d = out / case / f"np{nr}"
            if a.table_only:
                if (d / "summary.json").exists():
                    results[nr] = json.load(open(d / "summary.json"))
                continue
            results[nr] = run(exe, case, nr, d)
            print(f"  {case} on {nr} ranks: {results[nr]['steps']} steps", file=sys.stderr, flush=True)
        if results:
            table(case, results)
    print("\nper step: over the counted steps (rebuilds and migrations included); send ranks: the other ranks a rank's"
          " halo sends to (mean, largest); msgs and kB: sent by a rank (mean); coll: collectives a rank took part in"
          " (largest); imbalance: largest over mean")


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Benchmark of the solver with walls: the 2-D dam break of Martin & Moyce's proportions used by other
SPH codes' examples (a 1 m wide, 2 m high water column in a 4 m wide tank, dx = 0.01 m: 20,000
particles), 0.1 s of physical time with the case's own stable time step (RK4, CFL 2.0), the full
delta-LES-SPH right-hand side with boundary-integral walls, on 1 and 2 ranks. Prints the wall time,
particle-steps per second, the 1 -> 2 rank efficiency and the share of the step in neighbour search,
halo exchange, walls (gamma, wall lists, wall pressure), wall terms, the first pass and the fluid
terms (PETSc -log_view with flexslosh's events), and the surge front at the end.

    /usr/bin/python3 bench/bench_dam_break.py [--dx 0.01] [--time 0.1] [--ranks 1,2] [--rounds 1] [--side-by-side] [-- options]

With --rounds N the rank counts run N times, interleaved, and the fastest run of each is reported (one run's
time on a shared machine varies by up to a fifth). --side-by-side runs, in each round, two 1-rank runs at once as well:
the 1-rank run's time alone over theirs is the machine's own 1 -> 2 core efficiency, the ceiling of a 2-rank
run's.
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

from benchutil import print_memory, run_logged, run_rounds, step_time

ROOT = Path(__file__).resolve().parents[1]
EVENTS = ["FSStep", "FSRHS", "FSNeighbours", "FSHalo", "FSWalls", "FSWallPass", "FSFirstPass", "FSPairPass",
          "FSMigrate", "FSOutput"]
SHARES = [("neighbour search", "FSNeighbours"), ("halo exchange", "FSHalo"), ("walls: gamma, lists, p_wall", "FSWalls"),
          ("wall terms", "FSWallPass"), ("first pass (L, grad rho, D)", "FSFirstPass"), ("fluid terms", "FSPairPass"),
          ("migration", "FSMigrate")]


def run(exe, nranks, dx, tfinal, outdir, extra):
    args = ["-fs_case", "dam_break", "-fs_dx", repr(dx), "-ts_max_time", repr(tfinal), "-fs_output_interval", "0"] + extra
    summary, times = run_logged(exe, nranks, args, outdir, EVENTS)
    front = None
    with open(Path(outdir) / "timeseries.csv") as f:
        head = f.readline().strip().split(",")
        last = f.readlines()[-1].strip().split(",")
        front = float(last[head.index("front_position")])
    return summary, times, front


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--time", type=float, default=0.1, help="physical time simulated")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--rounds", type=int, default=1, help="runs of each rank count, interleaved; the fastest is reported")
    ap.add_argument("--side-by-side", action="store_true",
                    help="each round also runs two 1-rank runs at once: the machine's own 1 -> 2 core efficiency")
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    ap.add_argument("extra", nargs="*", help="more flexslosh options (after --)")
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    print(f"flexslosh benchmark: dam break 1 x 2 m column in a 4 m tank, dx = {a.dx}, {a.time} s, RK4, delta-LES-SPH + boundary integrals")

    def run_one(nr):
        with tempfile.TemporaryDirectory() as d:
            return run(exe, nr, a.dx, a.time, d, a.extra)

    ranks = [int(r) for r in a.ranks.split(",")]
    results = run_rounds(run_one, ranks, a.rounds, a.side_by_side)
    for nr in ranks:
        s, t, front = results[nr]
        wall = step_time(results[nr])
        print(f"\n{nr} rank(s): {s['particles']} particles, {s['steps']} steps, {s['rhs_evaluations']} RHS evaluations")
        print(f"  wall time of the steps        {wall:10.3f} s   (whole run with set-up and output {s['wall_time']:.3f} s)")
        print(f"  particle-steps per second     {s['particles'] * s['steps'] / wall:12.4g}")
        print(f"  pair visits per second        {s['pair_visits'] / wall:12.4g}   ({s['pair_visits'] / wall / nr:.4g} per core)")
        print(f"  peak memory per particle      {s['peak_memory_bytes_per_particle']:10.0f} bytes")
        print_memory(s)
        print(f"  surge front at the end        {front:10.4f} m")
        tot = t.get("FSStep", 0.0)
        if tot:
            for label, ev in SHARES:
                print(f"  share of the step: {label:28s} {100 * t.get(ev, 0) / tot:6.1f} %")
    if 1 in results and 2 in results:
        w1, w2 = step_time(results[1]), step_time(results[2])
        print(f"\nparallel efficiency 1 -> 2 ranks: {100 * w1 / (2 * w2):.1f} %" + (" (the fastest runs)" if a.rounds > 1 else ""))


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Benchmark of the solver in 3-D with triangle-mesh walls: Martin & Moyce's dam break (a column 1 m
wide, 2 m high and 2 m across, at the end of a tank 4 m long, 3 m high and 2 m across; dx = 0.0235 m:
about 310,000 particles), a fixed physical time (0.02 s) with the case's own stable time step (RK4,
CFL 2.0), the full delta-LES-SPH right-hand side with boundary-integral walls (elements of edge h),
on 1 and 2 ranks. Prints what bench_dam_break.py prints for the 2-D dam break: particles, steps, wall
time, particle-steps per second, pair visits per second per core, the shares of the step's phases, the
peak memory per particle, and the 1 -> 2 rank efficiency.

    /usr/bin/python3 bench/bench_dam_break_3d.py [--dx 0.0235] [--time 0.02] [--ranks 1,2] [--rounds 1] [--side-by-side] [-- options]

With --rounds N the rank counts run N times, interleaved, and the fastest run of each is reported (one run's
time on a shared machine varies by up to a fifth). --side-by-side runs, in each round, two 1-rank runs at once as well:
the 1-rank run's time alone over theirs is the machine's own 1 -> 2 core efficiency, the ceiling of a 2-rank
run's.

h/dx = 2 as in 2-D (the seed's): a particle has about 4/3 pi (2h/dx)^3 = 268 neighbours within the
support in 3-D (the candidate lists, with the skin, about 520), against about 50 in 2-D.
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

from bench_dam_break import EVENTS, SHARES
from benchutil import print_memory, run_logged, run_rounds, step_time

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.0235)
    ap.add_argument("--time", type=float, default=0.02, help="physical time simulated")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--rounds", type=int, default=1, help="runs of each rank count, interleaved; the fastest is reported")
    ap.add_argument("--side-by-side", action="store_true",
                    help="each round also runs two 1-rank runs at once: the machine's own 1 -> 2 core efficiency")
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    ap.add_argument("extra", nargs="*", help="more flexslosh options (after --)")
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    print(f"flexslosh benchmark: 3-D dam break, 1 x 2 x 2 m column in a 4 x 3 x 2 m tank, dx = {a.dx}, {a.time} s, "
          "RK4, delta-LES-SPH + boundary integrals on triangles")

    def run_one(nr):
        with tempfile.TemporaryDirectory() as d:
            args = ["-fs_case", "dam_break", "-fs_dim", "3", "-fs_dx", repr(a.dx), "-ts_max_time", repr(a.time),
                    "-fs_output_interval", "0"] + a.extra
            return run_logged(exe, nr, args, d, EVENTS)

    ranks = [int(r) for r in a.ranks.split(",")]
    results = run_rounds(run_one, ranks, a.rounds, a.side_by_side)
    for nr in ranks:
        s, t = results[nr]
        wall = step_time(results[nr])
        print(f"\n{nr} rank(s): {s['particles']} particles, {s['steps']} steps, {s['rhs_evaluations']} RHS evaluations")
        print(f"  wall time of the steps        {wall:10.3f} s   (whole run with set-up and output {s['wall_time']:.3f} s)")
        print(f"  particle-steps per second     {s['particles'] * s['steps'] / wall:12.4g}")
        print(f"  pair visits per second        {s['pair_visits'] / wall:12.4g}   ({s['pair_visits'] / wall / nr:.4g} per core)")
        print(f"  peak memory per particle      {s['peak_memory_bytes_per_particle']:10.0f} bytes")
        if nr > 1:
            par = s["parallel"]
            print(f"  largest rank over the mean    {par['imbalance_work_end']:10.3f} of the work at the end "
                  f"(-fs_balance), {par['imbalance_owned_end']:.3f} of the particles")
        print_memory(s)
        tot = t.get("FSStep", 0.0)
        if tot:
            for label, ev in SHARES:
                print(f"  share of the step: {label:28s} {100 * t.get(ev, 0) / tot:6.1f} %")
    if 1 in results and 2 in results:
        w1, w2 = step_time(results[1]), step_time(results[2])
        print(f"\nparallel efficiency 1 -> 2 ranks: {100 * w1 / (2 * w2):.1f} %" + (" (the fastest runs)" if a.rounds > 1 else ""))


if __name__ == "__main__":
    sys.exit(main())

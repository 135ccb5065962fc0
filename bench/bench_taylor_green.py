#!/usr/bin/env python3
"""Benchmark of the core solver: the 2-D Taylor-Green case with the full delta-LES-SPH right-hand side
(continuity, delta, pressure, viscosity, les_viscosity) at about 100k particles, a fixed number of
steps, on 1 and 2 ranks. Prints particles, steps, wall time, particle-steps per second, neighbour-pair
visits per second (all passes counted), peak memory per particle, the 1 -> 2 rank parallel efficiency,
and where the time goes (from -log_view events).

    /usr/bin/python3 bench/bench_taylor_green.py [--n 316] [--steps 20] [--ranks 1,2]
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]
EVENTS = ["FSStep", "FSRHS", "FSNeighbours", "FSHalo", "FSFirstPass", "FSPairPass", "FSMigrate", "FSOutput", "TSStep"]


def run(exe, nranks, n, steps, terms, outdir):
    args = ["-fs_case", "taylor_green", "-fs_dx", repr(1.0 / n), "-ts_max_steps", str(steps), "-ts_max_time", "100",
            "-fs_terms", terms, "-fs_output_interval", "0"]
    return run_logged(exe, nranks, args, outdir, EVENTS)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=316, help="particles per side (316 -> 99856 particles)")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--terms", default="continuity,delta,pressure,viscosity,les_viscosity")
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    results = {}
    print(f"flexslosh benchmark: Taylor-Green 2-D, {a.n}x{a.n} particles, {a.steps} RK4 steps, terms {a.terms}")
    for nr in [int(r) for r in a.ranks.split(",")]:
        with tempfile.TemporaryDirectory() as d:
            s, t = run(exe, nr, a.n, a.steps, a.terms, d)
        results[nr] = (s, t)
        wall = t.get("FSStep", s["wall_time"])
        pv = s["pair_visits"]
        print(f"\n{nr} rank(s): {s['particles']} particles, {s['steps']} steps, {s['rhs_evaluations']} RHS evaluations")
        print(f"  wall time of the steps        {wall:10.3f} s   (whole run with set-up and output {s['wall_time']:.3f} s)")
        print(f"  particle-steps per second     {s['particles'] * s['steps'] / wall:12.4g}")
        print(f"  pair visits per second        {pv / wall:12.4g}   ({pv / wall / nr:.4g} per core; first pass and pair pass)")
        print(f"  peak memory per particle      {s['peak_memory_bytes_per_particle']:10.0f} bytes (all ranks, whole process)")
        tot = t.get("FSStep", 0.0)
        if tot:
            for ev in ["FSNeighbours", "FSHalo", "FSFirstPass", "FSPairPass", "FSMigrate"]:
                print(f"  share of the step in {ev:13s} {100 * t.get(ev, 0) / tot:6.1f} %")
            print(f"  output (outside the steps)    {t.get('FSOutput', 0):10.3f} s")
    if 1 in results and 2 in results:
        w1 = results[1][1].get("FSStep", results[1][0]["wall_time"])
        w2 = results[2][1].get("FSStep", results[2][0]["wall_time"])
        print(f"\nparallel efficiency 1 -> 2 ranks: {100 * w1 / (2 * w2):.1f} %")


if __name__ == "__main__":
    sys.exit(main())

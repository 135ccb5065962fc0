#!/usr/bin/env python3
"""Benchmark of the coupled tank on the beam (cases/coupled_rectangular.opts: the seed's rectangular tank,
50 % fill, released from 0.04 m, at dx = 2 mm: 5,250 particles, on the mass-spring-damper or modal beam) for a fixed number of steps on 1 and
2 ranks: particle-steps per second, and the cost of the coupling per step (the FSCoupling event:
predicted tank motion, reaction loads, structure rates, inertial accelerations; FSStructure: the
structure model itself) against the whole step.

    /usr/bin/python3 bench/bench_coupled.py [--steps 200] [--ranks 1,2] [--structure msd] [--dx 0.002]
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]
EVENTS = ["FSStep", "FSCoupling", "FSStructure", "FSPairPass", "FSFirstPass", "FSWalls"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--structure", default="msd")
    ap.add_argument("--dx", type=float, default=0.002, help="particle spacing (the case file's default is a coarse 5 mm)")
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    print(f"flexslosh benchmark: coupled rectangular tank ({a.structure}), {a.steps} RK4 steps")
    for nr in [int(r) for r in a.ranks.split(",")]:
        with tempfile.TemporaryDirectory() as d:
            args = ["-options_file", ROOT / "cases" / "coupled_rectangular.opts", "-fs_structure", a.structure, "-fs_dx", a.dx,
                    "-ts_max_steps", a.steps, "-fs_output_interval", 0]
            s, t = run_logged(exe, nr, args, d, EVENTS)
        wall = t.get("FSStep", s["wall_time"])
        print(f"\n{nr} rank(s): {s['particles']} particles, {s['steps']} steps")
        print(f"  wall time of the steps        {wall:10.3f} s")
        print(f"  particle-steps per second     {s['particles'] * s['steps'] / wall:12.4g}")
        print(f"  coupling per step             {1e3 * t.get('FSCoupling', 0) / s['steps']:10.4f} ms"
              f"   ({100 * t.get('FSCoupling', 0) / wall:.2f} % of the step; structure model {100 * t.get('FSStructure', 0) / wall:.2f} %)")


if __name__ == "__main__":
    sys.exit(main())

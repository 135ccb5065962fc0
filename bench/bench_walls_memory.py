#!/usr/bin/env python3
"""The wall mesh's memory per rank against the rank count, every element on every rank (-fs_walls_distribute false)
against the distributed mesh (the default: each rank holds the elements near its part of the domain): the 3-D dam break with fine wall
elements (at least 200,000 of them), a few steps on 1, 2, 4 and 8 ranks (oversubscribed where the cores are fewer).
Printed per rank count and mode: the elements' memory per rank (summary.json's walls_elements over the ranks), the
particles' wall lists per rank, the peak resident memory per rank (the libraries' shared pages counted once), and the
wall time of the run (set-up included; meaningful only on a quiet machine with a core a rank).

    /usr/bin/python3 bench/bench_walls_memory.py [--ranks 1,2,4,8] [--all-ranks 1,2,4,8] [--element 0.15] [--steps 2]
                                                 [-- options]

--all-ranks: the rank counts at which the run with every element on every rank is measured too (its elements'
memory per rank is the one-rank figure at any count; its set-up computes every element's Shepard factor on every
rank, slow when oversubscribed).
"""
import argparse
import os
import tempfile
import time
from pathlib import Path

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", default="1,2,4,8")
    ap.add_argument("--all-ranks", default=None, help="rank counts measured with every element on every rank too "
                    "(default: all of --ranks)")
    ap.add_argument("--element", type=float, default=0.15, help="-fs_walls_element_size (in h; 0.15: 228,000 elements)")
    ap.add_argument("--steps", type=int, default=2)
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    ap.add_argument("extra", nargs="*", help="more flexslosh options (after --)")
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    args = ["-options_file", ROOT / "cases" / "dam_break_3d.opts", "-ts_max_steps", a.steps, "-fs_output_interval",
            "0", "-fs_walls_element_size", a.element] + a.extra
    print(f"flexslosh wall-mesh memory: 3-D dam break, -fs_walls_element_size {a.element}, {a.steps} steps")
    print(f"{'ranks':>5} {'mode':>12} {'elements':>9} {'elements/rank':>14} {'lists/rank':>11} {'peak/rank':>10} "
          f"{'wall':>7}")
    allranks = [int(r) for r in (a.all_ranks or a.ranks).split(",")]
    for nr in [int(r) for r in a.ranks.split(",")]:
        for mode, extra in (("all", ["-fs_walls_distribute", "false"]), ("distributed", ["-fs_walls_distribute"])):
            if (nr == 1 and mode == "distributed") or (mode == "all" and nr not in allranks):
                continue
            with tempfile.TemporaryDirectory() as d:
                t0 = time.perf_counter()
                s, _ = run_logged(exe, nr, args + extra, d, [])
                wall = time.perf_counter() - t0
            mem = s["memory"]
            peak = mem.get("peak_resident_shared_once", mem["peak_resident"])
            print(f"{nr:5d} {mode:>12} {s.get('wall_elements', 0):9d} {mem['walls_elements'] / nr / 2**20:11.1f} MiB "
                  f"{mem['walls_lists'] / nr / 2**20:7.1f} MiB {peak / nr / 2**20:6.1f} MiB {wall:6.1f} s", flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Set-up benchmark (issue 33 item 6): what a 3-D tank of about 300,000 particles costs before its first step,
with the lattice fill and with the relaxed packing (-fs_fill_packing relaxed, docs/walls.md), against what a
step and a simulated second of the same tank cost.

The tank: a box 0.3 x 0.2 x 0.15 m turned 30 degrees about the vertical axis (no wall along the axes, so `auto`
relaxes it), written as an STL here, half full; dx = 2.5 mm gives about 288,000 particles. Each run is timed by
-log_view: FSFillPacking (the relaxation), the whole set-up (the process's wall and CPU time with -ts_max_steps 0,
libraries' start and output included) and, from
a run of a few steps, the seconds a step; the set-up's share of a typical run is its time over the time of one
simulated second (steps per second at the acoustic limit times the seconds a step).

    /usr/bin/python3 bench/bench_setup.py [--dx 0.0025] [--ranks 1,2] [--steps 5] [--build build]

Runs back to back on a quiet machine (the CPU column, the processes' user and system time over all ranks, is
the figure to read when the machine is shared); the relaxed packing is not cached between runs (each run writes its own
cache in a fresh folder).
"""
import argparse
import math
import os
import tempfile
import time
from pathlib import Path

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]
L, H, W, ANGLE = 0.3, 0.2, 0.15, 30.0


def turned_box_stl(path):
    """An ASCII STL of the box L x H x W turned ANGLE degrees about the vertical (y) axis through its centre,
    its triangles wound so that their normals point out."""
    c, s = math.cos(math.radians(ANGLE)), math.sin(math.radians(ANGLE))

    def v(x, y, z):
        x, z = x - L / 2, z - W / 2
        return (L / 2 + c * x + s * z, y, W / 2 - s * x + c * z)

    corners = [v(x, y, z) for x in (0, L) for y in (0, H) for z in (0, W)]  # index: 4 ix + 2 iy + iz
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]  # out-facing quads
    lines = ["solid turned_box"]
    for a, b, cc, d in faces:
        for tri in ((a, b, cc), (a, cc, d)):
            p = [corners[k] for k in tri]
            u = [p[1][k] - p[0][k] for k in range(3)]
            w = [p[2][k] - p[0][k] for k in range(3)]
            n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
            r = math.sqrt(sum(x * x for x in n))
            lines.append("  facet normal %.9g %.9g %.9g\n    outer loop" % tuple(x / r for x in n))
            lines += ["      vertex %.9g %.9g %.9g" % q for q in p]
            lines.append("    endloop\n  endfacet")
    lines.append("endsolid turned_box")
    Path(path).write_text("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.0025)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--steps", type=int, default=5, help="steps of the run that times a step")
    ap.add_argument("--build", default=str(ROOT / "build"))
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    print(f"set-up of a turned box {L} x {H} x {W} m (30 degrees about the vertical), half full, dx = {a.dx * 1e3:g} mm")
    print(f"{'ranks':>5} {'packing':>8} {'particles':>10} {'set-up (s)':>11} {'CPU (s)':>8} {'packing (s)':>12} "
          f"{'step (s)':>9} {'steps / s':>10} {'1 s of run (s)':>15} {'set-up share':>13}")
    with tempfile.TemporaryDirectory() as d:
        stl = Path(d) / "turned_box.stl"
        turned_box_stl(stl)
        base = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", stl, "-fs_fill", 0.5,
                "-fs_dx", a.dx, "-fs_output_interval", 0]
        for nranks in (int(r) for r in a.ranks.split(",")):
            for packing in ("lattice", "relaxed"):
                with tempfile.TemporaryDirectory() as out:
                    args = base + ["-fs_fill_packing", packing, "-fs_fill_packing_cache", Path(out) / "cache"]
                    cpu, wall = os.times(), time.perf_counter()
                    setup, t0 = run_logged(exe, nranks, args + ["-ts_max_steps", 0], Path(out) / "setup", ["FSFillPacking"])
                    wall = time.perf_counter() - wall  # the whole process: summary.json's wall_time starts after set-up
                    cpu = sum(getattr(os.times(), k) - getattr(cpu, k) for k in ("children_user", "children_system"))
                    run, t1 = run_logged(exe, nranks, args + ["-ts_max_steps", a.steps], Path(out) / "steps", ["FSStep"])
                step = t1.get("FSStep", run["wall_time"] - setup["wall_time"]) / max(run["steps"], 1)
                per_second = 1.0 / run["last_dt"]
                second = step * per_second
                print(f"{nranks:5d} {packing:>8} {setup['particles']:10,d} {wall:11.1f} {cpu:8.1f} "
                      f"{t0.get('FSFillPacking', 0.0):12.1f} {step:9.3f} {per_second:10,.0f} {second:15,.0f} "
                      f"{wall / second:13.2%}")


if __name__ == "__main__":
    main()

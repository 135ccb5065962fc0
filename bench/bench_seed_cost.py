#!/usr/bin/env python3
"""Cost per simulated second of the seed's 50 % tank (cases/coupled_rectangular.opts) at several
resolutions: particles, steps per simulated second and their ratio to the acoustic limit's (CFL 1), what
limited the steps (timeseries.csv's dt_limit), the split density diffusion's RKL2 stages, and wall time per
simulated second, over the first --time seconds after the release (the first slam is at about 0.085 s).

Each resolution runs once per variant, back to back: "stages" is the case file's own setting (the density
diffusion in RK4's stages, its limit on the step), "split" adds -fs_delta_split -fs_cfl 0.8
-fs_walls_bounce_distance 0.3 (the diffusion advanced after each step by RKL2, docs/performance.md, "The density
diffusion split off"; the wider bounce holds the slams' floor jets at the longer step, dx <= 1 mm).

    /usr/bin/python3 bench/bench_seed_cost.py [--dx 0.005,0.002,0.001,0.0007] [--time 0.1] [--ranks 1]
        [--variants stages,split] [-- extra options]

Options after `--` go to every run. At dx <= 1 mm the first slam compresses the liquid by 0.3-0.45 with
c0 = 20 m/s, so the runs here take -fs_max_density_variation 0.95 (docs/performance.md, "What stops the
seed's tank at dx = 1 mm").
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]
VARIANTS = {"stages": [], "split": ["-fs_delta_split", "-fs_cfl", 0.8, "-fs_walls_bounce_distance", 0.3]}
C0, H_OVER_DX = 20.0, 2.0  # the case's c0 and h/dx


def acoustic_steps(dx, umax_mean, time):
    """The steps the acoustic limit alone takes at CFL 1: h/(c0 + |u|max), with the run's mean largest speed."""
    return time * (C0 + umax_mean) / (H_OVER_DX * dx)


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[: argv.index("--")] if "--" in argv else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", default="0.005,0.002,0.001,0.0007", help="particle spacings (m), comma separated")
    ap.add_argument("--time", type=float, default=0.1, help="simulated time of each run (s)")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--variants", default="stages,split", help="comma separated: " + ", ".join(VARIANTS))
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    a = ap.parse_args(argv)
    exe = Path(a.build) / "flexslosh"
    print(f"flexslosh benchmark: the seed's 50 % tank, {a.time} s after the release, {a.ranks} rank(s) {' '.join(extra)}")
    print(f"{'dx (mm)':>8} {'variant':>7} {'particles':>10} {'steps':>7} {'steps/s_sim':>12} {'x acoustic':>10}"
          f" {'RKL2 stages':>11} {'wall (s)':>9} {'wall/s_sim':>11}  limits (share of steps)")
    for dx in [float(v) for v in a.dx.split(",")]:
        for variant in a.variants.split(","):
            with tempfile.TemporaryDirectory() as d:
                args = ["-options_file", ROOT / "cases" / "coupled_rectangular.opts", "-fs_dx", dx, "-ts_max_time",
                        a.time, "-fs_output_interval", 0, "-fs_max_density_variation", 0.95] + VARIANTS[variant] + extra
                s, t = run_logged(exe, a.ranks, args, d, ["FSStep"])
                umax = np.genfromtxt(Path(d) / "timeseries.csv", delimiter=",", names=True)["max_velocity"].mean()
            wall = t.get("FSStep", s["wall_time"])
            lim = {k: v for k, v in s["dt_limit_steps"].items() if v}
            shares = ", ".join(f"{k} {100 * v / s['steps']:.0f} %" for k, v in sorted(lim.items(), key=lambda kv: -kv[1]))
            st = s.get("split_stages")
            stages = f"{st['total'] / s['steps']:.1f} (<={st['max']})" if st else "-"
            print(f"{1e3 * dx:8.1f} {variant:>7} {s['particles']:10d} {s['steps']:7d} {s['steps'] / a.time:12.0f}"
                  f" {s['steps'] / acoustic_steps(dx, umax, a.time):10.2f} {stages:>11} {wall:9.1f} {wall / a.time:11.1f}"
                  f"  {shares}")


if __name__ == "__main__":
    sys.exit(main())

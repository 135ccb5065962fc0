#!/usr/bin/env python3
"""Cost per simulated second of the seed's 50 % tank (cases/coupled_rectangular.opts) at several
resolutions: particles, steps per simulated second, what limited the steps (timeseries.csv's
dt_limit), wall time per simulated second, over the first --time seconds after the release (the
first slams are at about 0.1 and 0.25 s, where delta-LES's density diffusion takes the step down).

    /usr/bin/python3 bench/bench_seed_cost.py [--dx 0.005,0.002] [--time 0.3] [--ranks 1] [-- extra options]

Options after `--` go to every run (e.g. `-- -fs_delta_max 0.5` to compare a cap on delta_i).
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[: argv.index("--")] if "--" in argv else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", default="0.005,0.002", help="particle spacings (m), comma separated")
    ap.add_argument("--time", type=float, default=0.3, help="simulated time of each run (s)")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    a = ap.parse_args(argv)
    exe = Path(a.build) / "flexslosh"
    print(f"flexslosh benchmark: the seed's 50 % tank, {a.time} s after the release, {a.ranks} rank(s) {' '.join(extra)}")
    print(f"{'dx (mm)':>8} {'particles':>10} {'steps':>7} {'steps/s_sim':>12} {'wall (s)':>9} {'wall/s_sim':>11}"
          f" {'Mpart-steps/s':>14}  limits (share of steps)")
    for dx in [float(v) for v in a.dx.split(",")]:
        with tempfile.TemporaryDirectory() as d:
            args = ["-options_file", ROOT / "cases" / "coupled_rectangular.opts", "-fs_dx", dx, "-ts_max_time", a.time,
                    "-fs_output_interval", 0] + extra
            s, t = run_logged(exe, a.ranks, args, d, ["FSStep"])
        wall = t.get("FSStep", s["wall_time"])
        lim = {k: v for k, v in s["dt_limit_steps"].items() if v}
        shares = ", ".join(f"{k} {100 * v / s['steps']:.0f} %" for k, v in sorted(lim.items(), key=lambda kv: -kv[1]))
        print(f"{1e3 * dx:8.1f} {s['particles']:10d} {s['steps']:7d} {s['steps'] / a.time:12.0f} {wall:9.1f}"
              f" {wall / a.time:11.1f} {s['particles'] * s['steps'] / wall / 1e6:14.3f}  {shares}")


if __name__ == "__main__":
    sys.exit(main())

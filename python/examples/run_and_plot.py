"""Run a small dam break from Python and plot one particle field to a PNG.

    build/venv/bin/python3 python/examples/run_and_plot.py [--tiny] [--out DIR] [--field pressure]

The run is driven step by step through flexslosh.Solver; the field is gathered to rank 0 sorted by
particle id (also under mpirun -n 2). The figures of the paper are flexslosh.figures' job: this
plot is a plain scatter of the particles.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the checkout's package

from flexslosh import Solver  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="a very coarse, short run (the test suite's)")
    parser.add_argument("--out", default="output/run_and_plot", help="output directory (default %(default)s)")
    parser.add_argument("--field", default="pressure", choices=Solver.FIELDS, help="the field to plot (default %(default)s)")
    args = parser.parse_args(argv)
    out = Path(args.out)
    options = {"fs_case": "dam_break", "fs_dam_width": 1.0, "fs_dx": 0.1 if args.tiny else 0.04,
               "ts_max_time": 0.1 if args.tiny else 0.5, "fs_output_dir": out, "fs_progress": False}
    with Solver(options) as solver:
        solver.run()
        x = solver.positions(gather=True)
        values = solver.field(args.field, gather=True)
        t, steps = solver.time, solver.step_number
    if x is None:  # not rank 0
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4))
    sc = ax.scatter(x[:, 0], x[:, 1], c=values if values.ndim == 1 else (values ** 2).sum(axis=1) ** 0.5, s=8, cmap="viridis")
    fig.colorbar(sc, ax=ax, label=args.field)
    ax.set_aspect("equal")
    ax.set_title(f"dam break, t = {t:.3f} s ({steps} steps, {len(x)} particles)")
    png = out / f"{args.field}.png"
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()

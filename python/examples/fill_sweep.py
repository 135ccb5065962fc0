"""Damping of the coupled rectangular tank on the beam against the fill level: a sweep of
cases/coupled_rectangular.opts over -fs_fill, the damping ratio per cycle of the tip's free decay.

    build/venv/bin/python3 python/examples/fill_sweep.py [--tiny] [--out DIR]
    mpirun -n 4 build/venv/bin/python3 python/examples/fill_sweep.py     # the fills spread over the ranks

Every fill carries the same payload (liquid + ballast, -fs_beam_payload_mass in the options file), so
the difference between the fills is the liquid's sloshing. Writes <out>/damping.csv.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the checkout's package

REPO = Path(__file__).resolve().parents[2]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="two fills, coarse and short (the test suite's)")
    parser.add_argument("--out", default="output/fill_sweep", help="output directory (default %(default)s)")
    args = parser.parse_args(argv)
    from mpi4py import MPI

    from flexslosh.sweep import format_table, sweep

    # 0: the empty tank, the payload all ballast (the solid mass); the case file's dx = 5 mm and 3 s
    fills = (0.0, 0.3, 0.6) if args.tiny else (0.0, 0.2, 0.35, 0.5, 0.65, 0.8)
    base = {"options_file": str(REPO / "cases" / "coupled_rectangular.opts"), "fs_output": False, "fs_progress": False}
    if args.tiny:
        base.update(fs_dx=0.006, ts_max_time=0.25)
    comm = MPI.COMM_WORLD if MPI.COMM_WORLD.Get_size() > 1 else None
    table = sweep([{"fs_fill": f} for f in fills], base, comm=comm, output_root=args.out)
    if table is None:  # not rank 0
        return
    print(format_table(table, ["fs_fill", "cycle", "amplitude", "period", "zeta"]))
    print(f"wrote {Path(args.out) / 'damping.csv'}")


if __name__ == "__main__":
    main()

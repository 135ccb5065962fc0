"""The swayed rectangular tank's effective mass against linear potential theory: describing functions at
half and 1.5 times the first sloshing frequency (flexslosh.equivalent, docs/equivalent.md).

    build/venv/bin/python3 python/examples/sway_mass.py [--tiny] [--out DIR]
    mpirun -n 2 build/venv/bin/python3 python/examples/sway_mass.py     # the two frequencies on two ranks

Writes <out>/equivalent.csv, equivalent.json and equivalent_maps.png, and prints each point's m_eff / m
beside the theory's.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the checkout's package


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="coarse and short (the test suite's): dx = L/5, 2 cycles")
    parser.add_argument("--out", default="output/sway_mass", help="output directory (default %(default)s)")
    args = parser.parse_args(argv)
    from mpi4py import MPI

    from flexslosh import equivalent as eq

    length, depth = 0.2, 0.1
    w1 = eq.rectangular_modes(length, depth)[0][0]
    ratios = (0.5, 1.5)
    base = {"fs_case": "tank", "fs_tank_shape": "rectangular", "fs_tank_length": length, "fs_tank_height": 2 * depth,
            "fs_fill": 0.5, "fs_c0": 10, "fs_relax_time": 0.25, "fs_dx": 0.04 if args.tiny else 0.01}
    rows = eq.grid(None, "sway", [0.5], [0.005 * length], [r * w1 / (2 * 3.141592653589793) for r in ratios],
                   base_options=base, output_root=args.out, comm=MPI.COMM_WORLD, figures=not args.tiny,
                   ramp_cycles=1 if args.tiny else 6, cycles_max=2 if args.tiny else 8,
                   settle=1 if args.tiny else 3, tol=0.02, progress=None if args.tiny else print)
    if rows is not None:
        for r in rows:
            theory = eq.rectangular_sway_mass(length, depth, r["omega"])
            print(f"omega/omega_1 {r['omega'] / w1:.2f}: m_eff/m {r['m_eff_ratio']:.4f} (theory {theory:.4f}), "
                  f"c_eq/(m omega) {r['c_eq_nd']:.2e}, settled {r['settled']}")
        print(f"wrote {Path(args.out) / 'equivalent.csv'}")


if __name__ == "__main__":
    main()

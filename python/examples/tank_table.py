"""From a tank's CAD file and a range of fills to the table a structural model takes: the liquid's effective mass
and equivalent damping against the motion's amplitude, at frequencies chosen around each fill's first sloshing
frequency (docs/equivalent.md, "From a CAD tank to a structural model's table").

    build/venv/bin/python3 python/examples/tank_table.py --stl bay.stl --scale mm --fills 0.3,0.5 \\
        --direction sway --amplitudes 0.005,0.02 --frequency-ratios 0.5,0.8,1.2 -fs_dx 0.004
    mpirun -n 4 build/venv/bin/python3 python/examples/tank_table.py ...   # the points spread over the ranks
    build/venv/bin/python3 python/examples/tank_table.py --tiny            # the test suite's: a box, coarse, short

Per fill: the liquid's length L along the motion and its depth h at rest (flexslosh.modes.tank_geometry), the first
sloshing frequency of that rectangle, omega_1^2 = g (pi/L) tanh(pi h/L) (with --measure-modes: measured by a free
decay, flexslosh.modes.sloshing_modes), the grid of amplitudes (sway, surge: fractions of L; heave: Gamma =
A omega^2 / g) x frequencies (ratios of f_1). Writes <out>/fill_<F>/ (each fill's grid, resumed when interrupted)
and <out>/equivalent.csv, .json (all fills' rows); in heave with one frequency, also <out>/liquid_table_<F>.txt,
the reduced model's table (-fs_msd_liquid_table). Options not listed go to the solver (-fs_dx, -fs_c0, ...).
"""
import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the checkout's package
REPO = Path(__file__).resolve().parents[2]


def numbers(text):
    return [float(v) for v in text.split(",") if v.strip()]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--options-file", default=str(REPO / "cases" / "own_tank.opts"),
                        help="the settings (default cases/own_tank.opts: a 3-D STL tank held at rest)")
    parser.add_argument("--stl", help="the tank's STL (-fs_tank_stl; default the options file's)")
    parser.add_argument("--scale", help="the STL's unit (-fs_tank_stl_scale: mm, cm, in or a factor)")
    parser.add_argument("--fills", type=numbers, default=[0.3, 0.5], help="fill levels (default 0.3,0.5)")
    parser.add_argument("--direction", default="sway", choices=["sway", "surge", "heave"])
    parser.add_argument("--amplitudes", type=numbers, default=[0.005, 0.02],
                        help="sway, surge: A / L; heave: Gamma = A omega^2 / g (default 0.005,0.02)")
    parser.add_argument("--frequency-ratios", type=numbers, default=[0.5, 0.8, 1.2],
                        help="the forcing frequencies over each fill's first sloshing frequency (default 0.5,0.8,1.2)")
    parser.add_argument("--measure-modes", action="store_true",
                        help="measure f_1 by a free decay (flexslosh.modes) instead of the rectangle's estimate")
    parser.add_argument("--cycles", type=int, default=12, help="at most this many cycles after the ramp (12)")
    parser.add_argument("--out", default="output/tank_table", help="output directory (default %(default)s)")
    parser.add_argument("--tiny", action="store_true",
                        help="the test suite's run: the 60 x 60 x 30 mm box, dx 7.5 mm, one fill, two cycles")
    args, rest = parser.parse_known_args(argv)
    from mpi4py import MPI

    from flexslosh import equivalent as eq
    from flexslosh import modes

    base = eq.petsc_options(rest)
    if args.stl:
        base["fs_tank_stl"] = args.stl
    if args.scale:
        base["fs_tank_stl_scale"] = args.scale
    if args.tiny:
        base.update({"fs_tank_stl": str(REPO / "cases" / "data" / "box_60x60x30mm.stl"),
                     "fs_dx": 0.0075, "fs_fill_packing": "lattice", "fs_relax_time": 0.05})
        args.fills, args.amplitudes, args.frequency_ratios, args.cycles = [0.5], [0.02], [0.8], 2
    comm = MPI.COMM_WORLD
    out = Path(args.out)
    axis = {"sway": "x", "surge": "z", "heave": "x"}[args.direction]
    all_rows = []
    for fill in args.fills:
        opts = dict(base, fs_fill=fill, fs_output_dir=str(out / f"fill_{fill:g}" / "setup"))
        geo = modes.tank_geometry(opts, args.options_file, direction=axis, comm=comm)
        if args.measure_modes:
            res = modes.sloshing_modes(opts, args.options_file, direction=axis, output_dir=out / f"fill_{fill:g}" / "modes",
                                       comm=comm, progress=print if comm.Get_rank() == 0 else None)
            f1 = res.frequencies[0]
        else:
            k = math.pi / geo["length"]
            f1 = math.sqrt(eq.G * k * math.tanh(k * geo["depth"])) / (2 * math.pi)
        freqs = [r * f1 for r in args.frequency_ratios]
        if args.direction == "heave":
            amps = [[g * eq.G / (2 * math.pi * f) ** 2 for f in freqs] for g in args.amplitudes]
        else:
            amps = [[a * geo["length"]] * len(freqs) for a in args.amplitudes]
        if comm.Get_rank() == 0:
            print(f"fill {fill:g}: liquid {geo['length']:.4g} m long, {geo['depth']:.4g} m deep, f_1 {f1:.4g} Hz"
                  f"{' (measured)' if args.measure_modes else ' (rectangle)'}; forcing at {', '.join(f'{f:.4g}' for f in freqs)} Hz",
                  flush=True)
        rows = []
        for j, f in enumerate(freqs):  # the amplitude in m depends on the frequency in heave: a grid per frequency
            r = eq.grid(args.options_file, args.direction, [fill], [a[j] for a in amps], [f], base,
                        out / f"fill_{fill:g}" / f"f_{args.frequency_ratios[j]:g}", comm=comm, figures=False,
                        ramp_cycles=1 if args.tiny else 6, cycles_max=args.cycles, settle=1 if args.tiny else 3,
                        tol=0.5 if args.tiny else 0.01, progress=None if args.tiny else print)
            rows += r or []
        if comm.Get_rank() == 0:
            all_rows += rows
            if args.direction == "heave" and len(freqs) == 1:
                try:
                    print("reduced model's table:", eq.write_liquid_table(rows, out / f"liquid_table_{fill:g}.txt"))
                except ValueError as e:
                    print(f"no reduced model's table for fill {fill:g}: {e}")
    if comm.Get_rank() == 0:
        csv_path, _ = eq.write_table(all_rows, out)
        if not args.tiny:
            eq.plot_maps(all_rows, out / "equivalent_maps.png")
        for r in all_rows:
            print(f"fill {r['fill']:g} f {r['frequency']:.4g} Hz A {r['amplitude']:.4g}: settled {r['settled']}, "
                  f"m_eff/M {r['m_eff_ratio']:.4f}, c_eq/(M omega) {r['c_eq_nd']:.3e}")
        print(f"wrote {csv_path}")


if __name__ == "__main__":
    main()

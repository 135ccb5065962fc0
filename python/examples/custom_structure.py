"""A structure model written in Python: the tank on a hardening (Duffing) spring,

    m w'' + c w' + K w (1 + (w/w_ref)^2) = F,

registered as "duffing" and run dry (-fs_case beam) next to the linear built-in msd with the same
mass and stiffness: the hardening spring's period shortens with the amplitude, the damping per cycle
shows it.

    build/venv/bin/python3 python/examples/custom_structure.py [--tiny] [--out DIR]

Options of the model: -duffing_w_ref (m, default 0.05); the mass, stiffness and damping come from the
-fs_beam_* options as for msd.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the checkout's package

import flexslosh  # noqa: E402
from flexslosh.structure import MassSpringDamper  # noqa: E402


class Duffing(MassSpringDamper):
    """msd's mass, stiffness and damping (its setup reads them) with a cubic term in the spring."""

    columns = ("spring_force",)

    def setup(self, ctx):
        super().setup(ctx)
        self.w_ref = ctx.options.getReal("duffing_w_ref", 0.05)
        self.min_period = self.min_period / (1 + (self.preload / self.w_ref) ** 2) ** 0.5  # the stiffest state

    def spring(self, w):
        return self.K * w * (1 + (w / self.w_ref) ** 2)

    def rhs(self, t, y, loads):
        return [y[1], (loads.force[1] - self.c * y[1] - self.spring(y[0])) / self.m]

    def energy(self, y):
        w = y[0]
        return (0.5 * self.m * y[1] ** 2, 0.5 * self.K * w * w * (1 + 0.5 * (w / self.w_ref) ** 2), self.c * y[1] ** 2)

    def column_values(self, t, y, ydot):
        return [self.spring(y[0])]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="a short run (the test suite's)")
    parser.add_argument("--out", default="output/custom_structure", help="output directory (default %(default)s)")
    args = parser.parse_args(argv)
    from flexslosh.sweep import format_table, sweep

    flexslosh.register_structure("duffing", Duffing, "tank on a hardening spring (python/examples/custom_structure.py)")
    base = {"fs_case": "beam", "fs_beam_tank_mass": 5.0, "fs_beam_ballast_mass": 3.36, "fs_beam_preload": 0.04,
            "ts_max_time": 0.6 if args.tiny else 3.0, "fs_progress": False}
    table = sweep([{"fs_structure": "msd"}, {"fs_structure": "duffing"}], base, output_root=args.out)
    if table is None:
        return
    print(format_table(table, ["fs_structure", "cycle", "amplitude", "period", "zeta"]))
    print(f"wrote {Path(args.out) / 'damping.csv'}; timeseries.csv of the duffing run has the column spring_force")


if __name__ == "__main__":
    main()

"""The MPI half of test_python_api.py, and the runs both halves share.

    mpirun --oversubscribe -n 2 /usr/bin/python3 tests/python/python_api_mpi.py OUT

runs on 2 ranks: a few Taylor-Green steps and a few steps of the coupled tank, with the built-in msd
and with its Python twin (fields gathered to rank 0), a bad option and a Python structure that raises on
rank 0 (the exception's message on every rank), the beam sweep spread over the ranks and a describing
function (flexslosh.equivalent.describe) on both ranks; rank 0 writes OUT/mpi.npz. test_python_api.py runs the same on 1 rank and compares.
"""
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))

import flexslosh  # noqa: E402
from flexslosh import Solver  # noqa: E402
from flexslosh.solver import FlexsloshError  # noqa: E402
from flexslosh.sweep import sweep  # noqa: E402

QUIET = {"fs_output": False, "fs_progress": False}
TG = dict(QUIET, fs_case="taylor_green", fs_dx=0.05)
TANK = dict(QUIET, fs_dx=0.01)  # with cases/coupled_rectangular.opts: 210 particles, msd coupled
TANK_FILE = REPO / "cases" / "coupled_rectangular.opts"
PYTANK = dict(TANK, fs_structure="pymsd")  # flexslosh.structure.MassSpringDamper, registered as pymsd
FIELDS = ("position", "velocity", "density", "pressure", "strain_rate", "turbulent_viscosity")
BAD = dict(TG, fs_dx=-1)
SWEEP_BASE = dict(QUIET, fs_case="beam", fs_beam_tank_mass=5.0, fs_beam_ballast_mass=3.36, fs_beam_preload=0.04, ts_max_time=0.5)
SWEEP_CASES = [{"fs_structure": s, "fs_beam_damping": z} for s in ("msd", "modal") for z in (0.01, 0.03)]


def run_fields(options, nsteps, options_file=None):
    """nsteps steps, then every field gathered (rank 0, by id), the times, the energy and the wall loads."""
    with Solver(options, options_file=options_file) as s:
        s.step(nsteps)
        res = {f: s.field(f, gather=True) for f in FIELDS}
        res["id"] = s.ids(gather=True)
        ts = s.ts
        res["times"] = np.array([s.time, ts.getTime(), s.step_number, ts.getStepNumber()])
        energy = s.energy()
        res["energy"] = np.array(list(energy.values()))
        loads = s.wall_loads()
        res["loads"] = np.array([np.r_[v["force"], v["moment"]] for v in loads.values()])
        res["structure"] = s.structure_state()
    return res


def bad_option_message():
    try:
        Solver(BAD)
    except FlexsloshError as e:
        return str(e)
    return ""


class FailingMSD(flexslosh.structure.MassSpringDamper):
    """The Python msd whose right-hand side raises once t > 0.05 (on rank 0, where structures live)."""

    def rhs(self, t, y, loads):
        if t > 0.05:
            raise ValueError(f"the spring broke at t = {t:.3f}")
        return super().rhs(t, y, loads)


def failing_structure_message():
    """The error every rank gets when the Python structure fails on rank 0 (no rank left waiting)."""
    try:
        with Solver(dict(QUIET, fs_case="beam", fs_structure="pybreak", fs_beam_preload=0.01, ts_max_time=0.2)) as s:
            s.run()
    except FlexsloshError as e:
        return str(e)
    return ""


HEAVE = dict(fs_progress=False, fs_case="tank", fs_tank_shape="rectangular", fs_tank_length=0.2, fs_tank_height=0.2, fs_fill=0.5,
             fs_dx=0.02, fs_c0=10, fs_relax_time=0.05)


def describe_heave(out, comm=None):
    """A heave describing function (Gamma = 0.5 at 1.5 Hz, 3 cycles after a one-period ramp) on comm: per cycle
    m_eff, c_eq, E_d and the higher harmonics' share, and whether it settled."""
    from flexslosh import equivalent as eq

    f = 1.5
    d = eq.describe(dict(HEAVE, fs_output_dir=str(Path(out) / "heave")), "heave", 0.5 * 9.81 / (2 * np.pi * f) ** 2, f,
                    ramp_cycles=1, cycles_max=3, settle=2, tol=0.05, comm=comm, progress=None)
    return np.array([[c.m_eff, c.c_eq, c.energy, c.higher] for c in d.cycles]), d.settled_from


def main(out):
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    data = {}
    flexslosh.register_structure("pymsd", flexslosh.structure.MassSpringDamper)
    for name, opts, n, f in (("tg", TG, 3, None), ("tank", TANK, 5, TANK_FILE), ("pytank", PYTANK, 5, TANK_FILE)):
        for k, v in run_fields(opts, n, f).items():
            data[f"{name}_{k}"] = v
    messages = comm.gather(bad_option_message(), root=0)
    flexslosh.register_structure("pybreak", FailingMSD)
    failures = comm.gather(failing_structure_message(), root=0)
    table = sweep(SWEEP_CASES, SWEEP_BASE, comm=comm, output_root=Path(out) / "sweep")
    heave, settled_from = describe_heave(out, comm)
    heaves = comm.gather((heave, settled_from), root=0)
    if comm.Get_rank() == 0:
        data["nranks"] = comm.Get_size()
        data["bad_messages"] = np.array(messages)
        data["failure_messages"] = np.array(failures)
        data["sweep"] = table
        data["heave"] = heave
        data["heave_same_on_every_rank"] = all(np.array_equal(h, heave) and sf == settled_from for h, sf in heaves)
        data["heave_settled_from"] = -1 if settled_from is None else settled_from
        np.savez(Path(out) / "mpi.npz", **data)


if __name__ == "__main__":
    main(sys.argv[1])

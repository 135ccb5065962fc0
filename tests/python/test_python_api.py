"""The Python driver (issue 6): flexslosh.Solver over the C core's PETSc objects, Python structure models
in the C registry, sweeps, the examples. Runs on 1 rank in this process; the 2-rank half runs
python_api_mpi.py under mpirun as a subprocess and is compared here."""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, mpirun_bin, read_series, read_snapshot, snapshot_files
import python_api_mpi as M

import flexslosh
from flexslosh import Solver
from flexslosh.solver import FlexsloshError
from flexslosh.structure import MassSpringDamper
from flexslosh.sweep import sweep

QUIET = M.QUIET
BEAM = dict(QUIET, fs_case="beam", fs_beam_tank_mass=5.0, fs_beam_ballast_mass=3.36, fs_beam_preload=0.04)


def _env():
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    return env


def _python(args, nranks=1, timeout=120, cwd=None):
    cmd = [sys.executable] + [str(a) for a in args]
    if nranks > 1:
        cmd = [mpirun_bin(), "--oversubscribe", "-n", str(nranks), sys.executable, "-m", "mpi4py"] + cmd[1:]
    proc = subprocess.run(cmd, env=_env(), cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stdout[-4000:]}"
    return proc


def tip_history(structure, options, options_file=None):
    """The tip displacement after every step of a run with the given structure."""
    with Solver(dict(options, fs_structure=structure), options_file=options_file) as s:
        rec = [(s.time, s.tank_motion()["disp"][1])]
        s.run(callback=lambda s: rec.append((s.time, s.tank_motion()["disp"][1])))
    return np.array(rec)


@pytest.fixture(scope="module", autouse=True)
def pymsd():
    flexslosh.register_structure("pymsd", MassSpringDamper)


# ------------------------------------------------------------------ the package


def test_import_is_light():
    """import flexslosh initializes neither MPI nor PETSc."""
    code = "import sys, flexslosh; print(sorted(m for m in ('petsc4py.PETSc', 'mpi4py.MPI') if m in sys.modules))"
    assert _python(["-c", code]).stdout.strip() == "[]"


def test_missing_library_is_a_clear_error(tmp_path):
    env = dict(_env(), FLEXSLOSH_BUILD=str(tmp_path))
    proc = subprocess.run([sys.executable, "-c", "import flexslosh; flexslosh.Solver()"], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=60)
    assert proc.returncode != 0
    assert f"libflexslosh.so not found at {tmp_path}/libflexslosh.so" in proc.stdout
    assert "FLEXSLOSH_BUILD" in proc.stdout


# ------------------------------------------------------------------ TS, DMSwarm, fields


def test_ts_and_swarm_are_the_solvers_objects():
    from petsc4py import PETSc

    s = Solver(M.TG).set_up()
    ts, sw = s.ts, s.swarm
    assert isinstance(ts, PETSc.TS) and isinstance(sw, PETSc.DMSwarm)
    assert ts.getType() == "rk4lean"  # the default integrator: classical RK4 in three vectors
    assert ts.getRefCount() == 2  # the C solver's reference and the wrapper's
    assert s.ts is ts  # one wrapper per object
    s.step(3)
    assert s.step_number == ts.getStepNumber() == 3
    assert s.time == ts.getTime() > 0
    assert sw.getLocalSize() == s.local_size == 400
    x = sw.getField("position").reshape(-1, 2).copy()
    sw.restoreField("position")
    assert np.array_equal(x, s.positions())
    # the wrapped TS drives the run: a shorter final time through it stops run() there
    ts.setMaxTime(2 * s.time)
    s.run()
    assert s.time == pytest.approx(ts.getMaxTime(), rel=1e-14) and s.step_number > 3
    s.destroy()
    assert ts.handle == 0 and sw.handle == 0  # the wrappers' references went with the solver
    s.destroy()  # idempotent


def test_fields_equal_the_snapshot(tmp_path):
    """The fields at the end of a run are those of its last snapshot (same evaluation of the derived ones)."""
    with Solver(dict(M.TG, fs_output=True, fs_output_dir=tmp_path, ts_max_steps=4)) as s:
        s.run()
        got = {f: s.field(f, gather=True) for f in M.FIELDS}
        ids = s.ids(gather=True)
    snap = read_snapshot(snapshot_files(tmp_path)[-1])
    assert np.array_equal(snap["id"], ids)
    for f in M.FIELDS:
        assert np.array_equal(snap[f], got[f]), f
    assert got["turbulent_viscosity"].max() > 0 and got["strain_rate"].max() > 0
    with Solver(M.TG) as s, pytest.raises(FlexsloshError, match='Unknown particle field "nosuch"'):
        s.field("nosuch")


def test_energy_and_wall_loads_equal_the_csv_files(tmp_path):
    """(step, not run: run's last snapshot evaluates the right-hand side at the final state, the series
    has the loads of the step's last stage)"""
    with Solver(dict(M.TANK, fs_output=True, fs_output_dir=tmp_path), options_file=M.TANK_FILE) as s:
        s.step(5)
        energy, loads, motion, state = s.energy(), s.wall_loads(), s.tank_motion(), s.structure_state()
    csv = read_series(tmp_path)
    with open(tmp_path / "energy.csv") as fp:
        names = fp.readline().strip().split(",")
        last = np.array(fp.readlines()[-1].split(","), dtype=float)
    assert names[1:] == list(energy)
    np.testing.assert_allclose(last[1:], list(energy.values()), rtol=1e-9, atol=1e-12 * abs(energy["E_total"]))
    assert list(loads) == ["tank"]
    np.testing.assert_allclose([loads["tank"]["force"][0], loads["tank"]["force"][1], loads["tank"]["moment"][2]],
                               [csv[f"wall_tank_{c}"][-1] for c in ("force_x", "force_y", "moment")], rtol=1e-9)
    assert motion["disp"][1] == pytest.approx(csv["tip_displacement"][-1], rel=1e-9) == state[0]


def test_options_dict_file_and_restore(tmp_path):
    from petsc4py import PETSc

    opts = PETSc.Options()
    f = tmp_path / "tg.opts"
    f.write_text("-fs_case taylor_green\n-fs_dx 0.1\n-fs_output 0\n")
    with Solver(options_file=f) as s:
        assert s.set_up().local_size == 100
    with Solver({"-fs_dx": 0.05, "fs_progress": False}, options_file=f) as s:  # the dict wins over the file
        assert s.set_up().local_size == 400
        assert s.options.getString("fs_dx") == "0.05" and s.options.getBool("fs_progress") is False
        assert not opts.hasName("fs_dx") and not opts.hasName("fs_case")  # the solver's own database, not PETSc's
    with Solver(dict(M.TG, fs_terms=["continuity", "pressure"])) as s:  # a list as a comma-separated value
        s.step()
        assert s.energy()["work_alpha"] == 0 and s.field("turbulent_viscosity").max() == 0



def test_options_file_including_itself_is_refused(tmp_path):
    """PETSc follows -options_file inside an options file without a limit (a stack overflow on a cycle): the
    chain is checked before PETSc reads it, directly and through another file."""
    a, b = tmp_path / "a.opts", tmp_path / "b.opts"
    a.write_text(f"-fs_case taylor_green\n-options_file {b}  # the other one\n")
    b.write_text(f"# back to the first\n-options_file {a}\n")
    with pytest.raises(ValueError, match=rf'options file "{a}" includes itself: -options_file {a} -> '
                                         rf"-options_file {b} -> -options_file {a}"):
        Solver(options_file=a)
    b.write_text("-fs_dx 0.1\n# -options_file a.opts (a comment)\n")
    with Solver(options_file=a) as s:  # no cycle: the chain is read by PETSc
        assert s.set_up().local_size == 100
    b.write_bytes(b"\xef\xbb\xbf-fs_dx 0.1\n")  # a byte-order mark, which PETSc took for part of "-fs_dx", invisibly
    with pytest.raises(ValueError, match=rf'options file "{b}" starts with the bytes EF BB BF, a UTF-8 byte-order mark'):
        Solver(options_file=a)

def test_bad_options_raise_petsc_messages():
    with pytest.raises(FlexsloshError, match='Unknown case "nosuch" given to -fs_case'):
        Solver({"fs_case": "nosuch"})
    with pytest.raises(RuntimeError, match="-fs_dx -1 is out of range: expected a positive number") as err:
        Solver(M.BAD)
    assert err.value.ierr == 63 and err.value.call == "FSSolverSetFromOptions"
    with pytest.raises(FlexsloshError, match='Unknown structure "nosuch" given to -fs_structure'):
        Solver(dict(BEAM, fs_structure="nosuch"))
    with pytest.raises(FileNotFoundError):
        Solver(options_file="/nonexistent.opts")
    from petsc4py import PETSc

    assert not PETSc.Options().hasName("fs_case") and not PETSc.Options().hasName("fs_dx")  # taken out again
    with Solver(M.TG) as s:  # the errors left PETSc usable
        s.step()


# ------------------------------------------------------------------ Python structures


def test_python_msd_equals_builtin_dry_beam():
    """1 s of the dry beam's free decay (303 RK4 steps): the Python msd's tip history is the C msd's."""
    opts = dict(BEAM, ts_max_time=1.0)
    a, b = tip_history("msd", opts), tip_history("pymsd", opts)
    assert len(a) == len(b) > 300
    assert np.abs(a - b).max() <= 1e-12 * np.abs(a[:, 1]).max()


def test_python_msd_equals_builtin_coupled_tank():
    """40 steps of the coupled rectangular tank at dx = 5 mm (840 particles): the same to round-off."""
    opts = dict(QUIET, fs_dx=0.005, ts_max_steps=40)
    a, b = tip_history("msd", opts, M.TANK_FILE), tip_history("pymsd", opts, M.TANK_FILE)
    assert len(a) == len(b) == 41
    moved = np.abs(a[:, 1] - a[0, 1]).max()
    assert moved > 1e-4 and np.abs(a - b).max() <= 1e-10 * np.abs(a[:, 1]).max()


class _Oscillator(flexslosh.Structure):
    """w'' = -w, with a time-series column and energies."""

    ndof, min_period, columns = 2, 2 * np.pi, ("w2",)

    def initial_state(self):
        return [1.0, 0.0]

    def rhs(self, t, y, loads):
        return [y[1], -y[0]]

    def motion(self, y, ydot):
        return flexslosh.TankMotion(disp=(0, y[0], 0), vel=(0, y[1], 0), acc=(0, ydot[1], 0))

    def energy(self, y):
        return (0.5 * y[1] ** 2, 0.5 * y[0] ** 2, 0.0)

    def column_values(self, t, y, ydot):
        return [y[0] ** 2]


def test_python_structure_columns_energy_and_errors(tmp_path):
    flexslosh.register_structure("pyosc", _Oscillator)
    with Solver(dict(QUIET, fs_case="beam", fs_structure="pyosc", fs_output=True, fs_output_dir=tmp_path, ts_max_time=np.pi)) as s:
        s.run()
        e = s.energy()
        assert s.structure_state()[0] == pytest.approx(-1, abs=1e-5)
    csv = read_series(tmp_path)
    np.testing.assert_allclose(csv["w2"], csv["tip_displacement"] ** 2, rtol=1e-9)
    assert e["E_struct_kin"] + e["E_struct_elastic"] == pytest.approx(0.5, rel=1e-5)  # RK4 at 50 steps a period

    class Failing(_Oscillator):
        def rhs(self, t, y, loads):
            if t > 1:
                raise ValueError(f"no stiffness left at t = {t:.3f}")
            return super().rhs(t, y, loads)

    class WrongSize(_Oscillator):
        def initial_state(self):
            return [1.0]

    flexslosh.register_structure("pyfail", Failing)
    flexslosh.register_structure("pysize", WrongSize)
    with Solver(dict(QUIET, fs_case="beam", fs_structure="pyfail")) as s:
        with pytest.raises(FlexsloshError, match="Structure pyfail: its rhs callback failed: ValueError: no stiffness left at t = 1.0"):
            s.run()
        assert 0.8 < s.time < 1  # the time of the step that failed: the TS did not advance
    with pytest.raises(FlexsloshError, match=r"its initial callback failed: ValueError: initial_state\(\) returned 1 values, expected 2"):
        Solver(dict(QUIET, fs_case="beam", fs_structure="pysize")).set_up()


def test_python_structure_returning_none_or_words():
    """What a structure's callback returned, named: None (a forgotten return, reported as "returned 1 values"
    before, numpy making None one NaN), or something that is not numbers."""
    class NoReturn(_Oscillator):
        def rhs(self, t, y, loads):
            super().rhs(t, y, loads)

    class Words(_Oscillator):
        def initial_state(self):
            return "1 0"

    flexslosh.register_structure("pynone", NoReturn)
    flexslosh.register_structure("pywords", Words)
    with Solver(dict(QUIET, fs_case="beam", fs_structure="pynone")) as s:
        with pytest.raises(FlexsloshError, match=r"its rhs callback failed: TypeError: rhs\(\) returned None, expected a "
                                                 r"sequence of 2 numbers \(a missing return statement\?\)"):
            s.run()
    with pytest.raises(FlexsloshError, match=r"TypeError: initial_state\(\) returned str '1 0', expected a sequence of 2 "
                                             r"numbers"):
        Solver(dict(QUIET, fs_case="beam", fs_structure="pywords")).set_up()


# ------------------------------------------------------------------ sweeps and 2 ranks


@pytest.fixture(scope="module")
def two_ranks(tmp_path_factory):
    out = tmp_path_factory.mktemp("mpi")
    _python([REPO_ROOT / "tests" / "python" / "python_api_mpi.py", out], nranks=2)
    return dict(np.load(out / "mpi.npz")), out


@pytest.mark.parametrize("name", ["tg", "tank", "pytank"])
def test_two_ranks_fields_equal_one_rank(two_ranks, name):
    """Fields gathered on 2 ranks, sorted by id, equal those of 1 rank after a few steps; the wrapped TS's
    time and step number are the solver's on both. pytank: the Python msd on 2 ranks (its DOFs on rank 0)
    against the C msd on 1 rank."""
    par, _ = two_ranks
    opts, n, f = {"tg": (M.TG, 3, None), "tank": (M.TANK, 5, M.TANK_FILE), "pytank": (M.TANK, 5, M.TANK_FILE)}[name]
    one = M.run_fields(opts, n, f)
    assert par["nranks"] == 2
    assert np.array_equal(par[f"{name}_id"], one["id"]) and np.array_equal(one["id"], np.arange(len(one["id"])))
    assert np.array_equal(par[f"{name}_times"], one["times"]) and one["times"][0] == one["times"][1]
    for field in M.FIELDS:
        a, b = par[f"{name}_{field}"], one[field]
        assert np.abs(a - b).max() <= 1e-10 * max(np.abs(b).max(), 1e-300), field
    np.testing.assert_allclose(par[f"{name}_energy"], one["energy"], rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(par[f"{name}_loads"], one["loads"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(par[f"{name}_structure"], one["structure"], rtol=1e-10)


def test_two_ranks_bad_option_raises_on_every_rank(two_ranks):
    par, _ = two_ranks
    assert list(par["bad_messages"]) == ["FSSolverSetFromOptions: -fs_dx -1 is out of range: expected a positive number (PETSc error 63)"] * 2


def test_two_ranks_python_structure_failure_stops_every_rank(two_ranks):
    """A Python structure's exception on rank 0 (where structure routines run) is an error on both ranks:
    the other rank is not left waiting in the next collective."""
    par, _ = two_ranks
    msgs = list(par["failure_messages"])
    assert len(msgs) == 2
    assert "Structure pybreak: its rhs callback failed: ValueError: the spring broke at t = 0.05" in msgs[0]
    assert "Structure pybreak: its right-hand side failed on rank 0, where the structure lives" in msgs[1]
    assert "ValueError: the spring broke at t = 0.05" in msgs[1]


def test_describe_on_two_ranks_equals_one_rank(two_ranks, tmp_path):
    """flexslosh.equivalent.describe with the run over 2 ranks: every rank gets the same description, and its cycles
    (m_eff, c_eq, E_d, the higher harmonics) are the 1-rank run's to round-off; the liquid is carried (m_eff/m near 1)."""
    par, _ = two_ranks
    one, settled_from = M.describe_heave(tmp_path)
    assert bool(par["heave_same_on_every_rank"])
    assert int(par["heave_settled_from"]) == (-1 if settled_from is None else settled_from)
    np.testing.assert_allclose(par["heave"], one, rtol=1e-7, atol=1e-9 * np.abs(one).max())
    assert len(one) == 3


def test_sweep_over_two_ranks_equals_sequence(two_ranks, tmp_path):
    par, out = two_ranks
    seq = sweep(M.SWEEP_CASES, M.SWEEP_BASE, output_root=tmp_path)
    assert seq.dtype.names == ("case", "fs_structure", "fs_beam_damping", "cycle", "time", "amplitude", "period", "delta", "zeta")
    assert np.array_equal(par["sweep"], seq)
    assert (tmp_path / "damping.csv").read_text() == (out / "sweep" / "damping.csv").read_text()
    assert sorted(set(seq["case"])) == [0, 1, 2, 3] and (seq["cycle"] >= 1).any()
    # the damping ratio of the decay is the one asked for (cycles after the first)
    later = seq[seq["cycle"] >= 1]
    np.testing.assert_allclose(later["zeta"], later["fs_beam_damping"], rtol=0.02)


# ------------------------------------------------------------------ examples


@pytest.mark.parametrize("example", ["run_and_plot", "fill_sweep", "custom_structure", "sway_mass", "tank_table"])
def test_examples_run_tiny(example, tmp_path):
    proc = _python([REPO_ROOT / "python" / "examples" / f"{example}.py", "--tiny", "--out", tmp_path], cwd=tmp_path)
    assert "wrote" in proc.stdout
    if example == "run_and_plot":
        assert (tmp_path / "pressure.png").stat().st_size > 1000
    elif example == "sway_mass":
        assert len((tmp_path / "equivalent.csv").read_text().splitlines()) == 3
    elif example == "tank_table":  # the box's liquid 60 x 30 mm: f_1 from the rectangle, the forcing at 0.8 of it
        assert "liquid 0.06 m long, 0.03 m deep, f_1 3.454 Hz (rectangle); forcing at 2.764 Hz" in proc.stdout
        assert len((tmp_path / "equivalent.csv").read_text().splitlines()) == 2
    else:
        with open(tmp_path / "damping.csv") as fp:
            assert len(fp.readlines()) >= 3


# ------------------------------------------------------------------ plug-ins


def test_plugin_from_options_dict():
    """A -dll_append among a Solver's options loads the plug-in (FSLoadPlugins), so its term runs: the
    drag term removes kinetic energy at 2 k times the drag-free decay's rate; a library without the
    entry point named after it is an error."""
    from conftest import plugin_path

    energies = {}
    for name, extra in (("drag", dict(dll_append=plugin_path(), fs_terms="continuity,delta,pressure,viscosity,drag",
                                      fs_drag_rate=2.0)),
                        ("nodrag", dict(fs_terms="continuity,delta,pressure,viscosity"))):
        with Solver(dict(M.TG, ts_max_steps=5, **extra)) as s:
            s.run()
            e = s.energy()
            energies[name] = (e["E_kin"], s.time)
    (e_drag, t), (e_free, _) = energies["drag"], energies["nodrag"]
    assert np.log(e_free / e_drag) == pytest.approx(2 * 2.0 * t, rel=0.02)
    with pytest.raises(FlexsloshError, match="has no entry point PetscDLLibraryRegister_fsnothing"):
        bad = build_dir() / "libfsnothing.so"
        bad.write_bytes((build_dir() / "libfsspring.so").read_bytes())
        try:
            Solver(dict(M.TG, dll_append=bad))
        finally:
            bad.unlink()


def test_energy_before_the_first_step():
    """energy() after set_up and before any step: the initial energies are the current state's, so the
    residuals are zero and the liquid's energy is the sum of its parts; the run then starts from the same
    values (the budget after 3 steps is the one of a run that did not ask)."""
    final = []
    for ask in (True, False):
        with Solver(dict(M.TANK, ts_max_steps=3), options_file=M.TANK_FILE) as s:
            s.set_up()
            if ask:
                e0 = s.energy()
                assert e0["residual_liquid"] == 0 and e0["residual_total"] == 0
                assert e0["E_liquid"] == pytest.approx(e0["E_kin"] + e0["E_pot"] + e0["E_comp"], rel=1e-12)
                assert e0["E_pot"] != 0
            s.run()
            final.append(s.energy())
    assert final[0] == final[1]
    assert abs(final[0]["residual_liquid"]) < 0.01 * abs(final[0]["work_ext"])  # the release's jolt, RK4's error


def test_stepping_from_python_writes_what_the_binary_writes(tmp_path):
    """Solver.run(callback=...), run() and step() open the output before their first step, as the binary does: the
    coupled tank's timeseries.csv and energy.csv byte for byte the binary's (step 0's row, each step once, the
    energy budget's reference at step 0) and the snapshots at the same times."""
    opts = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-ts_max_time", 0.012,
            "-fs_output_interval", 0.005]
    from conftest import run_flexslosh
    run_flexslosh(opts + ["-fs_output_dir", tmp_path / "binary"])
    with Solver(dict(fs_progress=False, ts_max_time=0.012, fs_output_interval=0.005, fs_output_dir=str(tmp_path / "callback")),
                options_file=str(REPO_ROOT / "cases" / "coupled_rectangular.opts")) as s:
        s.run(callback=lambda s: None)
    with Solver(dict(fs_progress=False, ts_max_time=0.012, fs_output_interval=0.005, fs_output_dir=str(tmp_path / "steps")),
                options_file=str(REPO_ROOT / "cases" / "coupled_rectangular.opts")) as s:
        s.step(3)
        s.run()
    with Solver(dict(fs_progress=False, ts_max_time=0.012, fs_output_interval=0.005, fs_output_dir=str(tmp_path / "run")),
                options_file=str(REPO_ROOT / "cases" / "coupled_rectangular.opts")) as s:
        s.run()  # the steps one call at a time (Ctrl-C between them), the same output
    for name in ("callback", "steps", "run"):
        for csv in ("timeseries.csv", "energy.csv"):
            assert (tmp_path / name / csv).read_bytes() == (tmp_path / "binary" / csv).read_bytes(), (name, csv)
        times = [read_snapshot(f).attrs["time"] for f in snapshot_files(tmp_path / name)]
        assert times == [read_snapshot(f).attrs["time"] for f in snapshot_files(tmp_path / "binary")]
        assert times[0] == 0

"""Time integrators (-ts_type) and the conservation properties of the periodic Taylor-Green run."""
import numpy as np
import pytest

from conftest import REPO_ROOT, TG, read_series, read_summary, run_flexslosh

# at dx = 0.02 the acoustic step is 1.45e-3; the delta term's bound is 1.13e-3 with -fs_cfl_viscous's coefficient
# 0.125 (35 steps to T_END: two acoustic, then the delta's) and 1.70e-3 with RK4's 0.1875 (28 acoustic steps)
T_END = 0.04
INTEGRATORS = {
    "rk4": [],  # the default, rk4lean: classical RK4 in three vectors
    "rk4tsrk": ["-ts_type", "rk", "-ts_rk_type", "4"],  # the same method as PETSc's TSRK keeps it
    "ssp": ["-ts_type", "ssp"],
    "rk5dp": ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "basic"],
}
STAGES = {"rk4": 4, "rk4tsrk": 4, "ssp": 5, "rk5dp": 7}  # right-hand sides per step (ssp: default rks2 with 5 stages)
STEPS = {"rk4": 28, "rk4tsrk": 28, "ssp": 35, "rk5dp": 35}  # measured


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = {}
    for name, extra in INTEGRATORS.items():
        d = tmp_path_factory.mktemp(name)
        run_flexslosh(TG + ["-ts_max_time", T_END, "-fs_output_dir", d] + extra, cwd=d)
        out[name] = d
    return out


@pytest.mark.parametrize("name", list(INTEGRATORS))
def test_integrator_runs(runs, name):
    s = read_series(runs[name])
    summ = read_summary(runs[name])
    assert s["time"][-1] == pytest.approx(T_END, rel=1e-12)
    assert summ["steps"] == STEPS[name]
    # each step evaluates the right-hand side once per stage (the snapshots may add one each)
    assert STAGES[name] * summ["steps"] <= summ["rhs_evaluations"] <= STAGES[name] * summ["steps"] + 2
    assert np.all(np.diff(s["time"]) > 0)
    assert np.all(np.diff(s["kinetic_energy"]) < 0)  # the vortex decays monotonically


@pytest.mark.parametrize("name", ["ssp", "rk5dp"])
def test_integrators_agree(runs, name):
    ref = read_series(runs["rk4"])["kinetic_energy"][-1]
    ke = read_series(runs[name])["kinetic_energy"][-1]
    # the integrators differ by their truncation error only (measured: ssp -2.7e-7, rk5dp 2.0e-9 relative)
    assert ke == pytest.approx(ref, rel=5e-7)


def test_rk4lean_is_tsrks_rk4_in_three_vectors(runs):
    """The default integrator (rk4lean) and PETSc's TSRK with the classical RK4 tableau are one method summed
    in another order: the time series agree to round-off (measured: bit for bit here; 3e-11 relative after 262
    steps of a coarse dam break, where the walls amplify the round-off), and rk4lean's state-sized vectors are
    3 (state, stage with its rate written over it, sum) where TSRK's are 9."""
    lean, tsrk = read_series(runs["rk4"]), read_series(runs["rk4tsrk"])
    assert list(lean["step"]) == list(tsrk["step"])
    for col in ("time", "kinetic_energy", "mass"):
        scale = np.abs(tsrk[col]).max()
        assert np.abs(lean[col] - tsrk[col]).max() <= 1e-12 * scale, col
    mem_lean, mem_tsrk = read_summary(runs["rk4"])["memory"], read_summary(runs["rk4tsrk"])["memory"]
    assert mem_lean["ts_vectors"] * 9 == mem_tsrk["ts_vectors"] * 3


def test_rk4lean_in_place_is_the_same_method(tmp_path):
    """rk4lean writes each stage's rate over the stage (three vectors) because the solver's right-hand side reads
    all of its state, the particles and the structure's DOFs, before it writes a rate; with
    -ts_rk4lean_in_place false it keeps the rate apart (four vectors). The same arithmetic either way: the seed's
    coupled tank (walls, beam, energy budget; 40 steps at dx = 1 cm) writes the same time series and energy
    budget to the last digit."""
    common = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_dx", 0.01, "-ts_max_steps", 40,
              "-fs_output_interval", 0]
    three = run_flexslosh(common + ["-fs_output_dir", tmp_path / "three", "-fs_view"], cwd=tmp_path).stdout
    four = run_flexslosh(common + ["-fs_output_dir", tmp_path / "four", "-fs_view", "-ts_rk4lean_in_place", "false"],
                         cwd=tmp_path).stdout
    assert "in 3 vectors" in three and "in 4 vectors" in four  # -fs_view (before the set-up) says which
    for f in ("timeseries.csv", "energy.csv"):
        assert (tmp_path / "three" / f).read_text() == (tmp_path / "four" / f).read_text(), f
    assert np.ptp(read_series(tmp_path / "three")["tip_displacement"]) > 1e-4  # the beam moved
    three, four = read_summary(tmp_path / "three")["memory"], read_summary(tmp_path / "four")["memory"]
    assert three["ts_vectors"] * 4 == four["ts_vectors"] * 3  # U, Y, S against U, Y, K, S


@pytest.mark.parametrize("name", ["rk4", "rk5dp"])
def test_dt_column_is_the_step_taken(runs, name):
    s = read_series(runs[name])
    assert np.allclose(s["dt"][1:], np.diff(s["time"]), rtol=1e-8, atol=0)


def test_conservation_100_steps(tmp_path):
    d = tmp_path / "out"
    run_flexslosh(TG + ["-ts_max_steps", "100", "-fs_output_dir", d], cwd=tmp_path)
    s = read_series(d)
    assert s["step"][-1] == 100
    mass = s["mass"]
    assert mass[0] == pytest.approx(1.0, rel=1e-12)  # rho0 L^2 (the density starts at rho0 + p/c0^2, mean rho0)
    assert np.abs(mass / mass[0] - 1).max() < 1e-12
    U = 1.0
    bound = 1e-12 * mass[0] * U
    for comp in ("momentum_x", "momentum_y"):
        assert np.abs(s[comp]).max() < bound, f"{comp} reaches {np.abs(s[comp]).max():.3g}"
    # the energy decays at the viscous rate, 16 pi^2 nu = 1.58 per unit time, plus what the default terms
    # add at L/dx = 50 over these 100 steps (t = 0.12): measured 1.80 (+14 %; the delta-LES viscosity is
    # about 8 % of nu here, and cases/taylor_green.opts' terms give 1.67)
    rate = -np.polyfit(s["time"], np.log(s["kinetic_energy"]), 1)[0]
    assert 1.75 < rate < 1.85, rate


def test_series_interval_writes_every_nth_row_and_the_last(tmp_path):
    """-fs_series_interval 4: the rows of steps 0, 4, 8 and the last (10) only, each the same as the every-step
    run's row of that step (the interval changes what is written, not the run)."""
    every, sparse = tmp_path / "every", tmp_path / "sparse"
    run_flexslosh(TG + ["-ts_max_steps", "10", "-fs_output_dir", every], cwd=tmp_path)
    run_flexslosh(TG + ["-ts_max_steps", "10", "-fs_series_interval", "4", "-fs_output_dir", sparse], cwd=tmp_path)
    a, b = read_series(every), read_series(sparse)
    assert list(b["step"]) == [0, 4, 8, 10]
    rows = np.searchsorted(a["step"], b["step"])
    for c in ("time", "kinetic_energy", "mass", "momentum_x"):
        assert np.array_equal(a[c][rows], b[c]), c

"""Physics validation of the fluid terms on flows with exact solutions (issue: core solver, item 9).

Taylor-Green vortex (2-D, periodic, Re = 100): kinetic energy ~ exp(-16 pi^2 t U/(L Re)).
Periodic shear flow (3-D): kinetic energy ~ exp(-8 pi^2 nu t / L^2).
"""
import numpy as np
import pytest

from conftest import read_series, run_flexslosh

RE = 100.0
EXACT_RATE = -16 * np.pi**2 / RE  # d ln(E_k)/dt for U = L = 1
CASE = ["-options_file", "cases/taylor_green.opts", "-fs_output_interval", "0"]


def decay_rate(series, tmin=0.0):
    """Least-squares slope of ln(E_k) against time for t >= tmin."""
    t, ek = series["time"], series["kinetic_energy"]
    keep = t >= tmin
    return np.polyfit(t[keep], np.log(ek[keep] / ek[0]), 1)[0]


@pytest.fixture(scope="module")
def tg_runs(tmp_path_factory):
    """The Taylor-Green case (laminar viscosity, delta diffusion, shifting) at L/dx = 25 and 50 to t = 1."""
    from conftest import REPO_ROOT

    out = {}
    for n in (25, 50):
        d = tmp_path_factory.mktemp(f"tg{n}")
        run_flexslosh(CASE + ["-fs_dx", 1.0 / n, "-fs_output_dir", d], cwd=REPO_ROOT, timeout=300)
        out[n] = read_series(d)
    return out


def test_taylor_green_decay_rate_converges(tg_runs):
    err = {n: abs(decay_rate(s) / EXACT_RATE - 1) for n, s in tg_runs.items()}
    assert err[50] < 0.05, f"decay rate error {err[50]:.3%} at L/dx = 50"
    assert err[50] < 0.5 * err[25], f"no convergence: error {err[25]:.3%} at L/dx = 25, {err[50]:.3%} at 50"
    # the energy itself at t U/L = 1 (0.206 of the initial energy)
    s = tg_runs[50]
    ratio = s["kinetic_energy"][-1] / s["kinetic_energy"][0]
    assert s["time"][-1] == pytest.approx(1.0, abs=1e-12)
    assert ratio == pytest.approx(np.exp(EXACT_RATE), rel=0.03)
    # the time series carries the exact solution alongside
    assert s["kinetic_energy_exact"][-1] / s["kinetic_energy_exact"][0] == pytest.approx(np.exp(EXACT_RATE), rel=1e-9)


def test_taylor_green_conserves_mass_and_momentum(tg_runs):
    s = tg_runs[50]
    mass = s["mass"]
    assert np.abs(mass / mass[0] - 1).max() < 1e-13
    for comp in ("momentum_x", "momentum_y"):
        # U = 1, total mass 1: momentum must stay at round-off
        assert np.abs(s[comp]).max() < 1e-12


def test_taylor_green_density_stays_close(tg_runs):
    """Weak compressibility: |rho/rho0 - 1| stays of order Ma^2 (c0 = 10 U)."""
    assert tg_runs[50]["max_density_variation"].max() < 0.02


def test_les_viscosity_vanishes_with_resolution(tmp_path):
    """The delta-LES turbulent viscosity nu_t = (C_alpha 2h)^2 ||D|| adds dissipation that must shrink
    roughly as h^2 on this laminar flow: compare the extra decay over the laminar run at two resolutions."""
    from conftest import REPO_ROOT

    extra = {}
    for n in (25, 50):
        rates = []
        for terms in ("continuity,delta,pressure,viscosity,shifting", "continuity,delta,pressure,viscosity,les_viscosity,shifting"):
            d = tmp_path / f"les{n}_{len(terms)}"
            run_flexslosh(CASE + ["-fs_dx", 1.0 / n, "-fs_terms", terms, "-ts_max_time", 0.1, "-fs_output_dir", d], cwd=REPO_ROOT)
            rates.append(decay_rate(read_series(d)))
        extra[n] = rates[1] - rates[0]
    assert extra[25] < 0 and extra[50] < 0, f"the LES viscosity must dissipate: {extra}"
    assert 2.5 < extra[25] / extra[50] < 6.0, f"LES extra dissipation should fall about 4x when h halves: {extra}"


def test_shear_flow_3d(tmp_path):
    """The 3-D path: a periodic shear flow in a 16^3 box decays at the exact viscous rate."""
    from conftest import REPO_ROOT

    run_flexslosh(["-fs_case", "shear", "-fs_dim", 3, "-fs_dx", 1.0 / 16, "-ts_max_time", 0.15,
                   "-fs_terms", "continuity,delta,pressure,viscosity", "-fs_output_dir", tmp_path], cwd=REPO_ROOT, timeout=300)
    s = read_series(tmp_path)
    rate = decay_rate(s)
    exact = -8 * np.pi**2 / 100.0
    assert rate == pytest.approx(exact, rel=0.06)
    assert np.abs(s["momentum_y"]).max() < 1e-12 and np.abs(s["momentum_z"]).max() < 1e-12

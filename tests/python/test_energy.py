"""The energy budget (seed Eqs. 31-40), energy.csv: every power that changes the liquid's or the
structure's energy is integrated with the state, so the residuals are the integrator's quadrature
error only: tiny, and shrinking at the integrator's order (RK4: ~16x per halving of dt) when dt is
refined. Residuals are relative to the initial mechanical energy (docs/validation.md), the coupled
run's total relative to the structure's initial (elastic) energy.

Measured (RK4; docs/decisions.md "Energy budget"):
  tank at rest, dx 0.005, 0.2 s, CFL 0.4        residual 1.3e-7  (CFL 0.8: 1.9e-6)
  Taylor-Green, dx 0.05, t = 1                  residual 5e-8
  dam break, dx 0.05, 0.3 s, CFL 1.0 / 0.5      residual 2.7e-5 / 1.2e-6
  coupled msd free decay, 0.3 s, CFL 1.0 / 0.5  total 8.7e-5 / 4.2e-6, liquid 3.4e-4 / 1.6e-5 (of E_liquid)
"""
import shutil

import numpy as np
import pytest

from conftest import REPO_ROOT, read_series, run_flexslosh

COLUMNS = ["step", "time", "E_kin", "E_pot", "E_comp", "E_liquid", "work_delta", "work_alpha", "work_wall", "work_ext",
           "work_relax", "residual_liquid", "E_struct_kin", "E_struct_elastic", "work_struct_damping", "work_coupling",
           "work_motion", "work_bounce", "work_bounce_total", "E_liquid_abs", "E_total", "residual_total"]


def read_energy(directory):
    with open(directory / "energy.csv") as fp:
        header = fp.readline().strip().split(",")
        rows = [line.strip().split(",") for line in fp if line.strip()]
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    cols = {name: data[:, k] for k, name in enumerate(header)}
    cols["step"] = cols["step"].astype(np.int64)
    cols["header"] = header
    return cols


def run(tmp_path, name, args, nranks=1):
    out = tmp_path / name
    run_flexslosh(list(args) + ["-fs_output_interval", "0", "-fs_output_dir", out], nranks=nranks, cwd=tmp_path)
    return read_energy(out)


def mech0(e):
    return e["E_kin"][0] + e["E_pot"][0]


TANK = ["-fs_case", "tank", "-fs_dx", "0.005", "-ts_max_time", "0.2"]


def test_tank_at_rest(tmp_path):
    e = run(tmp_path, "tank", TANK + ["-fs_cfl", "0.4"])
    assert e["header"] == COLUMNS
    E0 = mech0(e)
    assert E0 > 1 and e["E_kin"][0] == 0
    # the residual is the integrator's error: 1.3e-7 of the initial energy (1.9e-6 at CFL 0.8)
    assert np.abs(e["residual_liquid"]).max() < 1e-6 * E0
    # the liquid settles: the potential energy it loses goes out through the walls (renormalization)
    assert e["E_pot"][-1] < e["E_pot"][0] and e["work_wall"][-1] < 0
    assert np.abs(e["work_wall"][-1] - (e["E_liquid"][-1] - e["E_liquid"][0])) < 0.2 * np.abs(e["work_wall"][-1])
    # no structure, no coupling: the total is the liquid's
    for c in ("work_ext", "E_struct_kin", "E_struct_elastic", "work_struct_damping", "work_coupling"):
        assert np.all(e[c] == 0), c
    assert np.allclose(e["E_total"], e["E_liquid"], rtol=1e-14, atol=0)
    assert np.allclose(e["residual_total"], e["residual_liquid"], rtol=1e-12, atol=1e-14 * E0)
    # energy.csv has a row per step, like timeseries.csv
    s = read_series(tmp_path / "tank")
    assert np.array_equal(s["step"], e["step"]) and np.allclose(s["time"], e["time"])


def test_taylor_green(tmp_path):
    """No walls, no gravity: continuity and pressure exchange energy exactly; the dissipation (delta and
    viscosity) is the kinetic energy lost, less the compressibility energy gained."""
    e = run(tmp_path, "tg", ["-options_file", REPO_ROOT / "cases" / "taylor_green.opts", "-fs_dx", "0.05"])
    s = read_series(tmp_path / "tg")
    E0 = mech0(e)
    assert e["time"][-1] == pytest.approx(1.0)
    assert np.abs(e["residual_liquid"]).max() < 1e-6 * E0  # measured 5e-8
    assert np.all(e["E_pot"] == 0)
    assert np.abs(e["work_wall"]).max() < 1e-12 * E0
    assert np.abs(s["dissipated_continuity"] + s["dissipated_pressure"]).max() < 1e-12 * E0
    assert np.abs(s["dissipated_pressure"]).max() > 1e-4 * E0  # each is not zero: they exchange energy
    loss = e["E_kin"][0] - e["E_kin"][-1]
    dissipated = -(e["work_delta"][-1] + e["work_alpha"][-1])
    assert dissipated > 0 and e["work_delta"][-1] < 0 and e["work_alpha"][-1] < 0
    assert loss == pytest.approx(dissipated + e["E_comp"][-1] - e["E_comp"][0], abs=1e-6 * E0)
    assert dissipated == pytest.approx(loss, rel=0.06)
    assert np.allclose(e["E_kin"], s["kinetic_energy"], rtol=1e-9)


def test_dam_break_dt(tmp_path):
    DB = ["-fs_case", "dam_break", "-fs_dx", "0.05", "-ts_max_time", "0.3"]
    r = {}
    for cfl in ("1.0", "0.5"):
        e = run(tmp_path, "db" + cfl, DB + ["-fs_cfl", cfl])
        r[cfl] = np.abs(e["residual_liquid"]).max() / mech0(e)
        assert e["E_kin"][-1] > 0.1 * mech0(e)  # the column is collapsing
        assert e["work_delta"][-1] < 0 and e["work_alpha"][-1] < 0
    assert r["1.0"] < 1e-4  # measured 2.7e-5
    assert r["0.5"] < r["1.0"] / 8  # RK4: measured 22x


def test_coupled_free_decay_dt(tmp_path):
    """The beam (msd) released from a preload with the liquid: the whole system's energy (liquid in the
    absolute frame, structure, potential of the static loads) changes only by the dissipations, the
    coupling's error power (reported, a few per cent) and the bounces: the residual is small and shrinks
    with dt."""
    CP = ["-fs_case", "tank", "-fs_structure", "msd", "-fs_dx", "0.005", "-fs_beam_preload", "0.01", "-ts_max_time", "0.3"]
    r, rl = {}, {}
    for cfl in ("1.0", "0.5"):
        e = run(tmp_path, "cp" + cfl, CP + ["-fs_cfl", cfl])
        Es = e["E_struct_elastic"][0]
        assert Es > 0.1 and e["E_struct_kin"][0] == 0
        assert np.all(np.diff(e["work_struct_damping"]) <= 0) and e["work_struct_damping"][-1] < -0.1 * Es
        assert np.abs(e["work_ext"]).max() > 0
        assert np.abs(e["work_coupling"][-1]) < 0.1 * Es  # measured 3 %
        r[cfl] = np.abs(e["residual_total"]).max() / Es
        rl[cfl] = np.abs(e["residual_liquid"]).max() / np.abs(e["E_liquid"][0])
    assert r["1.0"] < 1e-3  # measured 8.7e-5
    assert r["0.5"] < r["1.0"] / 5  # measured 20x
    assert rl["0.5"] < rl["1.0"] / 5  # measured 20x


def test_restart(tmp_path):
    """On restart energy.csv keeps the rows before the checkpoint's step; the budget continues exactly
    (its initial energies and integrals are in the checkpoint)."""
    args = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-ts_max_steps", "20", "-fs_checkpoint_interval", "10"]
    a = tmp_path / "a"
    run_flexslosh(args + ["-fs_output_interval", "0", "-fs_output_dir", a], cwd=tmp_path)
    b = tmp_path / "b"
    shutil.copytree(a, b)
    run_flexslosh(args + ["-fs_output_interval", "0", "-fs_output_dir", b, "-fs_restart", b / "checkpoint_000010.h5"], cwd=tmp_path)
    ea, eb = read_energy(a), read_energy(b)
    assert list(eb["step"]) == list(range(21))
    for c in COLUMNS[1:]:
        assert np.allclose(ea[c], eb[c], rtol=1e-10, atol=1e-14), c

"""The liquid's describing functions from forced motion (flexslosh.equivalent, docs/equivalent.md): the analysis
on signals of known content, the settling criterion, the grid's resumption and table, and the exact limits: the
heaved tank below Gamma = 1 carries its liquid rigidly (m_eff = m within 1 %, no dissipation), and the swayed
rectangular tank follows linear potential theory: below its first sloshing frequency within 3 % at dx = L/20,
closer than at L/10, above it within 3 % at L/28, closer than at L/20, and a 3-D box below it within 3 % at L/10.

Measured (2-D tank 0.2 m x 0.1 m deep, c0 = 10 m/s): heave Gamma = 0.5 at 1.5 Hz, dx = 1 cm: m_eff/m = 1.0027;
sway at 0.5 omega_1, A/L = 0.005: m_eff/m = 1.12 (dx = 2 cm), 1.151 (1 cm) against 1.1596.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, mpirun_bin

from flexslosh import equivalent as eq

L, H = 0.2, 0.1
TANK = {"fs_case": "tank", "fs_tank_shape": "rectangular", "fs_tank_length": L, "fs_tank_height": 2 * H, "fs_fill": 0.5,
        "fs_c0": 10, "fs_relax_time": 0.25}


def test_rectangular_modes_match_the_closed_forms():
    """omega_1^2 = g pi/L tanh(pi h/L); the sloshing masses sum to the whole liquid in shallow water (all of it
    sloshes) and to 5 % in deep water (h = 5 L); the quasi-static tank carries its liquid rigidly."""
    w, m = eq.rectangular_modes(L, H, 3)
    assert w[0] == pytest.approx(math.sqrt(9.81 * math.pi / L * math.tanh(math.pi * H / L)), rel=1e-12)
    assert m[0] == pytest.approx(8 * math.tanh(math.pi * H / L) / (math.pi**3 * H / L), rel=1e-12)
    assert eq.rectangular_modes(1.0, 1e-4, 400)[1].sum() == pytest.approx(1.0, abs=1e-3)
    # deep: tanh = 1, sum 8 L/(pi^3 h) sum_odd 1/n^3 = 8 L/(pi^3 h) (7/8) zeta(3)
    assert eq.rectangular_modes(1.0, 5.0, 4000)[1].sum() == pytest.approx(8 / (np.pi**3 * 5) * 7 / 8 * 1.2020569, rel=1e-5)
    assert eq.rectangular_sway_mass(L, H, 1e-3 * w[0]) == pytest.approx(1.0, abs=1e-6)
    # far above every mode the sloshing masses stay behind: m_eff -> m (1 - sum m_n)
    assert eq.rectangular_sway_mass(L, H, 1e3 * w[0], n=400) == pytest.approx(1 - eq.rectangular_modes(L, H, 400)[1].sum(), abs=1e-4)


def synthetic(m_eff=2.5, c=0.3, A=0.01, omega=6.0, free=None, t_end=12.0, dt=1e-3):
    t = np.arange(0, t_end, dt)
    x, v, a = A * np.sin(omega * t), A * omega * np.cos(omega * t), -A * omega**2 * np.sin(omega * t)
    F = 3.0 + m_eff * a + c * v + 0.05 * np.sin(3 * omega * t + 0.4)
    if free is not None:
        F = F + 0.2 * np.sin(free * t + 1.0)
    work = np.concatenate([[0], np.cumsum(0.5 * (F[1:] * v[1:] + F[:-1] * v[:-1]) * dt)])
    return t, F, work


def test_analysis_recovers_mass_damping_and_harmonics():
    omega, A = 6.0, 0.01
    t, F, work = synthetic(A=A, omega=omega)
    cycles = eq.analyse_cycles(t, F, work, A, omega, start=2 * np.pi / omega)
    assert len(cycles) == int((t[-1] - 2 * np.pi / omega) / (2 * np.pi / omega))
    for c in cycles:
        assert c.m_eff == pytest.approx(2.5, rel=1e-5)
        assert c.c_eq == pytest.approx(0.3, rel=1e-4)  # E_d = pi c omega A^2
        assert c.energy_work == pytest.approx(c.energy, rel=1e-4)
        assert c.force_mean == pytest.approx(3.0, rel=1e-5)
        rms1 = math.hypot(2.5 * A * omega**2, 0.3 * A * omega) / math.sqrt(2)
        assert c.higher == pytest.approx(0.05 / math.sqrt(2) / rms1, rel=1e-3)
    assert eq.settled_window(cycles, A) == 0


def test_free_oscillation_is_fitted_out():
    """A free oscillation at 2/3 of the forcing (the start's sloshing above the first mode) spoils one cycle's
    Fourier coefficients; fitted near the given frequency, it leaves the forced response."""
    omega, A, free = 6.0, 0.01, 6.0 / 1.5 * 1.03
    t, F, _ = synthetic(A=A, omega=omega, free=free)
    plain = eq.analyse_cycles(t, F, None, A, omega, 0.0)
    fitted = eq.analyse_cycles(t, F, None, A, omega, 0.0, free=6.0 / 1.5)
    assert max(abs(c.m_eff - 2.5) for c in plain) > 0.05
    assert max(abs(c.m_eff - 2.5) for c in fitted) < 2e-3 * 2.5
    assert max(abs(c.c_eq - 0.3) for c in fitted) < 0.02 * 0.3
    assert eq.settled_window(plain, A) is None  # the plain analysis never settles: reported as such


def test_growing_response_is_not_settled():
    omega, A = 6.0, 0.01
    t = np.arange(0, 20, 1e-3)
    F = -(1 + 0.05 * t) * A * omega**2 * np.sin(omega * t)  # the first harmonic grows 5 %/s: never periodic
    cycles = eq.analyse_cycles(t, F, None, A, omega, 0.0)
    assert eq.settled_window(cycles, A, tol=0.01, settle=3) is None
    assert eq.settled_window(cycles, A, tol=0.2, settle=3) == 0


def test_dissipation_growing_from_nothing_is_not_settled():
    """A rigidly carried liquid (F = m a) whose dissipation grows 1.5-fold per cycle from a loss angle of 1e-5 (a
    Faraday wave growing from noise): its changes measured against pi A |F_1| stay below 1e-3, the growth shows."""
    omega, A, m = 6.0, 0.01, 2.0
    period = 2 * np.pi / omega
    t = np.arange(0, 10 * period, 1e-3)
    c = 1e-5 * m * omega * 1.5 ** (t / period)  # c_eq / (m omega) 1e-5 growing x 1.5 per cycle
    F = -m * A * omega**2 * np.sin(omega * t) + c * A * omega * np.cos(omega * t)
    cycles = eq.analyse_cycles(t, F, None, A, omega, 0.0)
    assert max(eq._change(a, b, A) for a, b in zip(cycles[:6], cycles[1:6])) < 1e-3
    assert eq.settled_window(cycles[:6], A, tol=0.01, settle=3) is None
    assert eq.settled_window(cycles[:6], A, tol=0.01, settle=3, growth=0.6) == 0  # growth below 60 %/cycle allowed


def test_faraday_modes_of_a_heaved_rectangle():
    """omega_k^2 = g k tanh(k h): heaved at twice a mode's frequency, that mode is unstable at any Gamma and its
    neighbours only inside the tongue; the seed's tank (0.7 m, 30 mm) at 5.7 Hz, Gamma = 0.5: modes 8-10, the
    mode 9 within 1.7 % of half the forcing; the test tank below at 1.5 Hz: none; a square box: the 2-D modes
    along both sides and the diagonal ones."""
    k3 = 3 * np.pi / 0.5
    w3 = math.sqrt(9.81 * k3 * math.tanh(k3 * 0.1))
    assert [m for m, _ in eq.faraday_modes([0.5], 0.1, 2 * w3, 1e-3)] == [(3,)]
    assert eq.faraday_modes([0.5], 0.1, 2 * w3 * 1.01, 1e-3) == []
    seed = eq.faraday_modes([0.7], 0.03, 2 * np.pi * 5.7, 0.5)
    assert [m for m, _ in seed] == [(8,), (9,), (10,)]
    assert seed[1][1] / (np.pi * 5.7) == pytest.approx(1.017, abs=1e-3)
    assert eq.faraday_modes([L], H, 2 * np.pi * 1.5, 0.5) == []
    box = [m for m, _ in eq.faraday_modes([0.5, 0.5], 0.1, 2 * w3, 1e-3)]
    assert sorted(box) == [(0, 3), (3, 0)]
    k = np.pi * math.hypot(2 / 0.5, 1 / 0.4)
    box = [m for m, _ in eq.faraday_modes([0.5, 0.4], 0.1, 2 * math.sqrt(9.81 * k * math.tanh(k * 0.1)), 1e-3)]
    assert box == [(2, 1)]


def rigid_description(direction, amplitude, frequency):
    """What describe returns for a liquid of 2 kg carried rigidly (synthetic loads, settled): a stand-in for the runs."""
    omega = 2 * np.pi * frequency
    t, F, work = synthetic(m_eff=2.0, A=amplitude, omega=omega, t_end=6 * 2 * np.pi / omega)
    d = eq.Description(direction, amplitude, frequency, 2.0, 2.0, 0.2, 0.01, 2, settle=3)
    d.cycles = eq.analyse_cycles(t, F, work, amplitude, omega, 0.0)
    d.settled_from = eq.settled_window(d.cycles, amplitude)
    return d


def test_grid_resumes_and_writes_the_table(tmp_path, monkeypatch):
    """A grid point whose record is complete is not run again; the table carries units and one row per point."""
    calls = []

    def fake(options, direction, amplitude, frequency, **kw):
        calls.append((options.get("fs_fill"), amplitude, frequency))
        return rigid_description(direction, amplitude, frequency)

    monkeypatch.setattr(eq, "describe", fake)
    args = (None, "heave", [0.3, 0.5], [0.001, 0.002], [1.0, 2.0])
    rows = eq.grid(*args, base_options=TANK, output_root=tmp_path, figures=False, progress=None)
    assert len(rows) == 8 and len(calls) == 8
    os.remove(tmp_path / "points" / "point_0005.json")
    (tmp_path / "points" / "point_0002.json").write_text('{"complete": false}')  # interrupted while writing
    calls.clear()
    rows = eq.grid(*args, base_options=TANK, output_root=tmp_path, figures=True, progress=None)
    assert sorted(calls) == sorted([(0.3, 0.002, 1.0), (0.5, 0.001, 2.0)])
    header = (tmp_path / "equivalent.csv").read_text().splitlines()[0].split(",")
    assert "m_eff[kg or kg m^2]" in header and "frequency[Hz]" in header and "revision[-]" in header
    table = json.loads((tmp_path / "equivalent.json").read_text())
    assert table["units"]["c_eq"] == "N s/m or N m s/rad" and len(table["rows"]) == 8
    for r in rows:
        assert r["settled"] and r["m_eff_ratio"] == pytest.approx(1.0, rel=1e-5)
        assert r["nondim_amplitude"] == pytest.approx(r["amplitude"] * r["omega"]**2 / 9.81)
    assert (tmp_path / "equivalent_maps.png").stat().st_size > 1000
    # other parameters for the same point: run again
    calls.clear()
    eq.grid(None, "heave", [0.3], [0.001], [1.5], base_options=TANK, output_root=tmp_path, figures=False, progress=None)
    assert calls == [(0.3, 0.001, 1.5)]


def test_command_passes_the_free_oscillation(tmp_path, monkeypatch):
    """--free f (Hz) reaches describe as the free oscillation's angular frequency 2 pi f; a non-positive one is named."""
    seen = []

    def fake(options, direction, amplitude, frequency, **kw):
        seen.append(kw.get("free"))
        return rigid_description(direction, amplitude, frequency)

    monkeypatch.setattr(eq, "describe", fake)
    common = ["--direction", "sway", "--amplitude", "0.001", "--frequency", "2.8", "--no-figures", "-fs_case", "tank"]
    assert eq.main(common + ["--free", "1.9", "--out", str(tmp_path / "a")]) == 0
    assert eq.main(common + ["--out", str(tmp_path / "b")]) == 0
    assert seen == [pytest.approx(2 * np.pi * 1.9), None]
    with pytest.raises(SystemExit) as e:
        eq.main(common + ["--free", "-1", "--out", str(tmp_path / "c")])
    assert e.value.code == 2


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="direction 'yaw'"):
        eq.describe(TANK, "yaw", 0.01, 1.0)
    with pytest.raises(ValueError, match="frequency -1"):
        eq.describe(TANK, "heave", 0.01, -1.0)
    with pytest.raises(ValueError, match="roll.*point"):
        eq.describe(dict(TANK, fs_dx=0.04, fs_output_dir="/tmp/unused"), "roll", 0.01, 1.0)
    with pytest.raises(ValueError, match="-fs_output False: the describing function reads the run's timeseries.csv"):
        eq.describe(dict(TANK, fs_output=False), "heave", 0.01, 1.0)
    with pytest.raises(ValueError, match="-fs_motion_y_sines is set"):
        eq.describe(dict(TANK, fs_dx=0.04, fs_motion_y_sines="0.01,1,0"), "sway", 0.01, 1.0)


def test_heave_below_gamma_one_carries_the_liquid_rigidly(tmp_path):
    """Gamma = A omega^2/g = 0.5: the liquid moves with the tank, F = m (g + a): m_eff = m within 1 % (the weakly
    compressible liquid adds (omega/omega_a)^2 = 0.4 %, docs/equivalent.md) and no energy is lost (the loss
    angle's E_d / (pi A F_1) below 1e-3), E_d from the loads equal to work_motion's."""
    f = 1.5
    A = 0.5 * 9.81 / (2 * np.pi * f) ** 2
    d = eq.describe(dict(TANK, fs_dx=0.01, fs_output_dir=str(tmp_path / "heave")), "heave", A, f, ramp_cycles=2,
                    cycles_max=5, settle=3, tol=0.01, progress=None)
    assert d.settled
    s = d.summary()
    assert s["m_eff"] / d.liquid_mass == pytest.approx(1.0, abs=0.01)
    first = s["m_eff"] * A * d.omega**2
    assert abs(s["energy"]) / (np.pi * A * first) < 1e-3
    assert s["energy_work"] == pytest.approx(s["energy"], abs=1e-3 * np.pi * A * first)
    assert s["higher"] < 0.02
    assert d.faraday == []  # no sloshing mode near half the forcing: the criterion may stop the run early


def test_heave_in_a_faraday_tongue_runs_all_its_cycles(tmp_path):
    """The seed's tank heaved at 5.7 Hz, Gamma = 0.5 (dx = 1 cm): its flat surface is unstable (mode 9), so the
    run is not stopped while the wave is still too small to show (the plain criterion settled it after 4 cycles
    at a loss angle of 3e-4, a tenth of a percent of the saturated wave's): it goes all its cycles."""
    A = 0.5 * 9.81 / (2 * np.pi * 5.7) ** 2
    opts = {"fs_dx": 0.01, "fs_c0": 20, "fs_relax_time": 0.1, "fs_output_dir": str(tmp_path / "heave")}
    d = eq.describe(opts, "heave", A, 5.7, options_file=str(REPO_ROOT / "cases" / "tank_rectangular.opts"),
                    ramp_cycles=3, cycles_max=6, settle=3, tol=0.01, progress=None)
    assert [m for m, _ in d.faraday] == [(8,), (9,), (10,)]
    assert len(d.cycles) == 6
    assert eq.settled_window(d.cycles, A, 0.01, 3) == 0  # what the plain criterion said
    assert d.settled_from in (None, 2)  # judged on the last four cycles alone


def test_sway_below_the_first_mode_follows_potential_theory(tmp_path):
    """A/L = 0.005 at half the first sloshing frequency (its ramp over 4 periods leaves 0.5 % of a free
    oscillation, docs/equivalent.md): m_eff within 3 % of the liquid's mass of linear potential theory at
    dx = L/20, closer than at L/10."""
    w1 = eq.rectangular_modes(L, H)[0][0]
    omega = 0.5 * w1
    exact = eq.rectangular_sway_mass(L, H, omega)
    err = {}
    for dx in (0.02, 0.01):
        d = eq.describe(dict(TANK, fs_dx=dx, fs_output_dir=str(tmp_path / f"sway{dx}")), "sway", 0.005 * L,
                        omega / (2 * np.pi), ramp_cycles=4, cycles_max=5, settle=2, tol=0.03, progress=None)
        assert d.settled or dx == 0.02  # the coarsest run's cycles change by more than 3 %: its last four
        cycles = d.settled_cycles() or d.cycles[1:]
        err[dx] = np.mean([c.m_eff for c in cycles]) / d.liquid_mass - exact
    assert abs(err[0.01]) < 0.03, err
    assert abs(err[0.01]) < abs(err[0.02]), err


def test_sway_above_the_first_mode_converges(tmp_path):
    """At 1.5 omega_1 the liquid feels lighter than its mass (theory 0.194 m), the small difference of the rigid and
    the sloshing masses, which a 1 % error in the SPH's frequencies moves by 0.016 m: the mean of the cycles after the
    first (they beat with the free oscillation the ramp leaves, fitted out at omega_1) within 3 % of m at dx = L/28,
    closer than at L/20 (measured: 0.2486 and 0.2131, +5.4 and +1.9 % of m; 0.1967 at L/40)."""
    w1 = eq.rectangular_modes(L, H)[0][0]
    omega = 1.5 * w1
    exact = eq.rectangular_sway_mass(L, H, omega)
    err = {}
    for dx in (0.01, 0.00707):
        d = eq.describe(dict(TANK, fs_dx=dx, fs_output_dir=str(tmp_path / f"sway{dx}")), "sway", 0.005 * L,
                        omega / (2 * np.pi), ramp_cycles=6, cycles_max=8, settle=2, tol=0.03, free=w1, progress=None)
        assert len(d.cycles) == 8 and not d.settled  # the beat: never within 3 % from one cycle to the next
        err[dx] = np.mean([c.m_eff for c in d.cycles[1:]]) / d.liquid_mass - exact
    assert abs(err[0.00707]) < 0.03, err
    assert abs(err[0.00707]) < 0.5 * abs(err[0.01]), err


def test_sway_of_a_3d_box_follows_potential_theory(tmp_path):
    """The 3-D box 0.1 m wide (its modes along x are the 2-D ones) at 0.5 omega_1, A / L = 0.02 (at 0.005 the liquid's
    own motion at rest, 0.01 sqrt(g H), is larger than the tank's and the cycles scatter by 5 %): m_eff within 3 % of
    m at dx = L/10, 250 particles (measured 1.1346 against 1.1596, -2.5 %)."""
    w1 = eq.rectangular_modes(L, H)[0][0]
    omega = 0.5 * w1
    d = eq.describe(dict(TANK, fs_dim=3, fs_tank_width=0.1, fs_dx=0.02, fs_output_dir=str(tmp_path / "sway3d")), "sway",
                    0.02 * L, omega / (2 * np.pi), ramp_cycles=4, cycles_max=5, settle=2, tol=0.03, progress=None)
    assert d.dim == 3 and d.settled
    m = d.summary()["m_eff_ratio"]
    assert abs(m - eq.rectangular_sway_mass(L, H, omega)) < 0.03, m


def test_grid_on_two_ranks_equals_one(tmp_path):
    """The command line spreads the points over the ranks (each run alone on its rank): the table is the same."""
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    args = ["-m", "flexslosh.equivalent", "--direction", "heave", "--amplitude", "0.005", "--frequency", "2,3",
            "--ramp-cycles", "1", "--cycles", "3", "--settle", "2", "--tol", "0.05", "--no-figures",
            "-fs_case", "tank", "-fs_tank_shape", "rectangular", "-fs_tank_length", "0.2", "-fs_tank_height", "0.2",
            "-fs_fill", "0.5", "-fs_dx", "0.04", "-fs_c0", "10"]
    tables = []
    for n in (1, 2):
        out = tmp_path / f"n{n}"
        cmd = [sys.executable] + args + ["--out", str(out)]
        if n > 1:
            cmd = [mpirun_bin(), "--oversubscribe", "-n", str(n), sys.executable] + args + ["--out", str(out), "--mpi"]
        proc = subprocess.run(cmd, env=env, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=120)
        assert proc.returncode == 0, proc.stdout[-3000:]
        assert "point 2/2 (rank %d)" % (n - 1) in proc.stdout  # one progress line per run, from its rank
        rows = json.loads((out / "equivalent.json").read_text())["rows"]
        tables.append([{k: v for k, v in r.items() if k != "output_dir"} for r in rows])
    assert tables[0] == tables[1]

"""Pressure probes and wave gauges (-fs_probes, probes.csv, FSSolverGetProbes / Solver.probes()).

Measured (dx = 0.003 m, h/dx = 2, the hydrostatic tank of cases/hydrostatic.opts at t = 0.15 s):
  probes in the liquid, deeper than 2h: -0.09 %, -0.37 %, -0.09 % of rho0 g (H - y); the probe 5 mm under
  the surface (its support cut by the surface) +4.8 % of rho0 g (H - y) = +0.81 % of rho0 g H;
  on the floor (the wall pressure): -0.95 % of rho0 g H (the same with a diameter);
  the gauge in the middle 0.01 dx below H, at the side wall 0.14 dx below H (dx/4 = 0.75 mm);
  1 and 2 ranks: 4e-11 of the columns' scale (the CSV's 11 digits).
Standing wave (h/dx = 20, to two periods): the gauge at x = 0 fitted with A exp(-lam t/2) sin(w t + phi) + c
(lam the exact viscous mode's decay, test_standing_wave.py): amplitude -1.9 %, period +0.1 % of linear
theory, offset c = -0.09 dx (the gauges at walls read about 0.1 dx low).
"""
import os
import re

import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, read_series, run_flexslosh
from flexslosh.waves import exact_viscous_mode
from test_standing_wave import H as SW_H, K as SW_K, NU as SW_NU

RHO0, G, H, DX = 1000.0, 9.81, 0.03, 0.003
TANK = ["-fs_case", "tank", "-fs_tank_length", 0.2, "-fs_dx", DX, "-fs_relax_time", 0.1, "-fs_delta_min", 0.1,
        "-fs_delta_hydrostatic", "-fs_output_interval", 0]
PROBES = """# the hydrostatic tank: 0.2 m x 0.06 m, liquid 0.03 m deep
probe mid 0.1 0.015
probe left 0.05 0.01    # a comment
probe right 0.15 0.015
probe top 0.1 0.025
probe floor 0.1 0.0
probe floorD 0.07 0.0 diameter 0.012

gauge centre 0.1 0 0.1 0.06
gauge side 0 0 0 0.06
"""


def read_probes(directory):
    """probes.csv as a dict column name -> array."""
    path = directory / "probes.csv"
    with open(path) as fp:
        header = fp.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, k] for k, name in enumerate(header)}


@pytest.fixture(scope="module")
def hydrostatic(tmp_path_factory):
    d = tmp_path_factory.mktemp("hydro")
    (d / "probes.txt").write_text(PROBES)
    run_flexslosh(TANK + ["-ts_max_time", 0.15, "-fs_probes", "probes.txt", "-fs_output_dir", "out"], cwd=d)
    return read_probes(d / "out"), d


def test_hydrostatic_probes_and_gauges(hydrostatic):
    P, d = hydrostatic
    assert list(P)[:5] == ["step", "time", "mid_pressure[Pa]", "mid_velocity_x[m/s]", "mid_velocity_y[m/s]"]
    assert "centre_elevation[m]" in P and "side_elevation[m]" in P
    assert np.array_equal(P["step"], read_series(d / "out")["step"])  # every step, step 0 first
    for name, y in (("mid", 0.015), ("left", 0.01), ("right", 0.015)):
        p = P[f"{name}_pressure[Pa]"][-1]
        assert p == pytest.approx(RHO0 * G * (H - y), rel=0.004), name
    # near the surface the support is cut: within 1 % of rho0 g H
    assert abs(P["top_pressure[Pa]"][-1] - RHO0 * G * (H - 0.025)) < 0.01 * RHO0 * G * H
    for name in ("floor", "floorD"):
        assert P[f"{name}_pressure[Pa]"][-1] == pytest.approx(RHO0 * G * H, rel=0.01), name
    for name in ("centre", "side"):
        assert abs(P[f"{name}_elevation[m]"][-1] - H) < DX / 4, name
    assert abs(P["side_elevation[m]"][0] - H) < 0.01 * DX  # at rest on the lattice: the gamma correction
    for c in ("mid_velocity_x[m/s]", "mid_velocity_y[m/s]", "floor_velocity_y[m/s]"):
        assert np.abs(P[c]).max() < 0.01 * np.sqrt(G * H)


def test_one_and_two_ranks_agree(tmp_path):
    (tmp_path / "probes.txt").write_text(PROBES)
    for n in (1, 2):
        run_flexslosh(TANK + ["-ts_max_steps", 60, "-fs_probes", "probes.txt", "-fs_output_dir", f"r{n}"], nranks=n,
                      cwd=tmp_path)
    a, b = read_probes(tmp_path / "r1"), read_probes(tmp_path / "r2")
    assert list(a) == list(b)
    vel = max(np.abs(a[c]).max() for c in a if "velocity" in c)
    for c in a:
        scale = RHO0 * G * H if "pressure" in c else vel if "velocity" in c else H if "elevation" in c else 1
        assert np.abs(a[c] - b[c]).max() <= 1e-10 * scale, c


def test_standing_wave_gauge_follows_linear_theory(tmp_path):
    omega0 = np.sqrt(SW_K * np.tanh(SW_K * SW_H))
    A, T = 0.05 * SW_H, 2 * np.pi / omega0
    (tmp_path / "sw.txt").write_text("gauge wall 0 0 0 1.5\n")
    run_flexslosh(["-fs_case", "standing_wave", "-fs_dx", 0.05, "-ts_max_time", 2 * T, "-fs_output_interval", 0,
                   "-fs_probes", "sw.txt", "-fs_output_dir", "out"], cwd=tmp_path)
    P = read_probes(tmp_path / "out")
    t, eta = P["time"], P["wall_elevation[m]"] - SW_H
    _, lam = exact_viscous_mode(SW_K, SW_H, SW_NU)  # the laminar decay of the mode (energy rate)
    env = np.exp(-0.5 * lam * t)

    def fit(w):
        M = np.c_[env * np.sin(w * t), env * np.cos(w * t), np.ones_like(t)]
        coef, res, *_ = np.linalg.lstsq(M, eta, rcond=None)
        return np.sum((M @ coef - eta) ** 2), coef

    ws = np.linspace(0.9 * omega0, 1.1 * omega0, 2001)
    w = ws[np.argmin([fit(x)[0] for x in ws])]
    _, (a, b, c) = fit(w)
    assert np.hypot(a, b) == pytest.approx(A, rel=0.10)
    assert 2 * np.pi / w == pytest.approx(T, rel=0.02)
    assert abs(c) < 0.05 / 4  # the mean level within dx/4


def test_three_dimensional_probe_and_gauge(tmp_path):
    (tmp_path / "p.txt").write_text("probe c 0.03 0.01 0.015\ngauge g 0.03 0 0.015 0.03 0.06 0.015\n")
    run_flexslosh(["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_length", 0.06, "-fs_tank_width", 0.03, "-fs_dx", 0.005,
                   "-ts_max_steps", 5, "-fs_probes", "p.txt", "-fs_output_dir", "out"], cwd=tmp_path)
    P = read_probes(tmp_path / "out")
    assert list(P) == ["step", "time", "c_pressure[Pa]", "c_velocity_x[m/s]", "c_velocity_y[m/s]",
                       "c_velocity_z[m/s]", "g_elevation[m]"]
    assert len(P["step"]) == 6
    assert P["c_pressure[Pa]"][0] == pytest.approx(RHO0 * G * (H - 0.01), rel=0.01)
    assert np.all(np.abs(P["c_pressure[Pa]"] - RHO0 * G * (H - 0.01)) < 0.2 * RHO0 * G * H)
    assert np.all(np.abs(P["g_elevation[m]"] - H) < 0.005 / 4)


@pytest.mark.parametrize("text,line,what", [
    ("probe a 0.1 0.01\nprobe b 0.1\n", 2, "expected \"probe NAME x y [diameter D] [cutoff HZ]"),
    ("probe a 0.1 0.01\n\n# c\nprobe a 0.1 0.02\n", 4, "duplicate name \"a\""),
    ("gauge g 0.1 0.0 0.1 0.0\n", 1, "zero length"),
    ("probe far 0.5 0.01\n", 1, "outside the domain: its x = 0.5 is not in"),
    ("probe a 0.1 0.01\nprobe high 0.1 0.02 0.07\n", 2, "expected \"probe NAME x y [diameter D]"),
    ("probe a 0.1 0.01\nprobe lid 0.1 0.07\n", 2, "probe \"lid\" at (0.1, 0.07) is not in the liquid region: it lies "
                                                  "outside the tank's walls (their bounding box); the nearest wall, "
                                                  "\"tank\", is 0.01 m away"),
    ("gauge g 0.1 0.01 0.1 0.075\n", 1, "gauge \"g\" (its end) at (0.1, 0.075) is not in the liquid region"),
    ("gauge g 0 0 0\n", 1, "expected \"gauge NAME x0 y0 x1 y1\""),
    ("sensor s 0 0\n", 1, "unknown item \"sensor\""),
    ("probe a 0.1 0.01 diameter -1\n", 1, "a positive diameter"),
])
def test_bad_probe_files(tmp_path, text, line, what):
    (tmp_path / "bad.txt").write_text(text)
    proc = run_flexslosh(TANK + ["-ts_max_steps", 1, "-fs_probes", "bad.txt", "-fs_output_dir", "out"], cwd=tmp_path,
                         check=False)
    assert proc.returncode != 0
    assert f"bad.txt:{line}:" in proc.stdout and what in proc.stdout, proc.stdout[-2000:]


BAFFLED = ["-fs_case", "tank", "-fs_tank_shape", "baffled", "-fs_tank_compartments", 2, "-ts_max_steps", 0,
           "-fs_output_interval", 0, "-fs_output_dir", "out"]


@pytest.mark.parametrize("dx,text,what", [
    # the baffle of the 2-compartment tank spans x = 0.1 .. 0.105, up to 0.045
    (0.003, "probe inrib 0.1025 0.01\n", "probe \"inrib\" at (0.1025, 0.01) is not in the liquid region: it lies beyond "
                                         "the tank's walls or inside a wall's thickness"),
    (0.012, "probe inrib 0.1025 0.01\n", "probe \"inrib\" lies inside the thickness of a wall, within dx/2 = 0.006 of "
                                         "two opposite faces"),
])
def test_probe_inside_a_baffle_is_an_error(tmp_path, dx, text, what):
    """A probe inside a baffle's thickness read 0 Pa or a mix of both compartments: an error naming the line."""
    (tmp_path / "p.txt").write_text("probe ok 0.05 0.01\n" + text)
    proc = run_flexslosh(BAFFLED + ["-fs_dx", dx, "-fs_probes", "p.txt"], cwd=tmp_path, check=False)
    assert proc.returncode != 0
    assert "p.txt:2: " + what in proc.stdout, proc.stdout[-2000:]


def test_wall_probe_reads_its_own_side_of_a_baffle(tmp_path):
    """Liquid 0.03 m deep left of the baffle, 0.01 m right of it: a probe with a diameter on each face of the baffle
    averages the wall pressure of its own face only (the baffle's back faces the other compartment): the means of
    rho g (H - y) over the face y in [0, 0.015] (220.7 Pa left; 32.7 Pa right, where the face is wetted up to 0.01),
    measured 220.7 and 32.1 Pa. Before, both read a mix of the two (159.9 and 132.2 Pa). A probe on a wall without a diameter is warned about, with its element's size."""
    (tmp_path / "p.txt").write_text("probe left 0.1 0.005 diameter 0.02\nprobe right 0.105 0.005 diameter 0.02\n"
                                    "probe bare 0.1 0.005\n")
    proc = run_flexslosh(BAFFLED + ["-fs_dx", DX, "-fs_probes", "p.txt", "-fs_liquid_box",
                                    "0,0.1,0,0.03,0.105,0.205,0,0.01"], cwd=tmp_path)
    P = read_probes(tmp_path / "out")
    assert P["left_pressure[Pa]"][0] == pytest.approx(RHO0 * G * (0.03 - 0.0075), rel=0.01)
    # right: wetted up to 0.01 of the face's 0.015, dry above
    assert abs(P["right_pressure[Pa]"][0] - RHO0 * G * 0.01**2 / 2 / 0.015) < 0.005 * RHO0 * G * 0.03
    assert P["bare_pressure[Pa]"][0] == pytest.approx(RHO0 * G * (0.03 - 0.005), rel=0.03)
    assert re.search(r"Warning: p\.txt: 1 probe\(s\) on a wall without a diameter \(the first: \"bare\", line 3\): "
                     r"each reads the wall pressure of its nearest wall element alone, on average a segment 0\.00\d+ m "
                     r"long \(1 dx\)", proc.stdout), proc.stdout[-2000:]


def test_probe_inside_an_stl_obstacle_is_an_error(tmp_path):
    """3-D: a probe inside a post standing in an STL tank (a solid of its own) or outside the tank's box."""
    from test_walls_3d import ascii_stl, box_facets
    (tmp_path / "t.stl").write_text(ascii_stl({"tank": box_facets((0, 0, 0), (0.06, 0.06, 0.03)),
                                               "post": box_facets((0.025, 0.01, 0.01), (0.035, 0.05, 0.02))}))
    args = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "t.stl", "-fs_dx", 0.005,
            "-ts_max_steps", 0, "-fs_output_interval", 0, "-fs_output_dir", "out", "-fs_probes", "p.txt"]
    for text, what in (("probe inpost 0.03 0.02 0.015\n", "probe \"inpost\" at (0.03, 0.02, 0.015) is not in the liquid "
                                                          "region: it lies beyond the tank's walls or inside a wall's "
                                                          "thickness (a baffle, a rib, an obstacle); the nearest wall, "
                                                          "\"post\", is 0.005 m away"),
                       ("probe out 0.03 0.02 0.04\n", "probe \"out\" at (0.03, 0.02, 0.04) is not in the liquid region: "
                                                      "it lies outside the tank's walls")):
        (tmp_path / "p.txt").write_text("probe fine 0.01 0.01 0.015\n" + text)
        proc = run_flexslosh(args, cwd=tmp_path, check=False)
        assert proc.returncode != 0 and "p.txt:2: " + what in proc.stdout, proc.stdout[-2000:]
    (tmp_path / "p.txt").write_text("probe fine 0.01 0.01 0.015\nprobe face 0.025 0.02 0.015 diameter 0.006\n")
    run_flexslosh(args, cwd=tmp_path)


def test_python_probes_equal_the_csv(tmp_path):
    from flexslosh import Solver

    (tmp_path / "p.txt").write_text(PROBES)
    opts = {"-fs_case": "tank", "-fs_tank_length": 0.2, "-fs_dx": DX, "-fs_output_dir": tmp_path / "out",
            "-fs_probes": tmp_path / "p.txt", "-fs_output_interval": 0, "-fs_progress": 0}
    with Solver(opts) as s:
        s.step(3)
        values = s.probes()
    P = read_probes(tmp_path / "out")
    assert list(values) == ["mid", "left", "right", "top", "floor", "floorD", "centre", "side"]
    np.testing.assert_allclose(values["mid"], [P[f"mid_{c}"][-1] for c in ("pressure[Pa]", "velocity_x[m/s]",
                                                                           "velocity_y[m/s]")], rtol=1e-9, atol=1e-12)
    assert isinstance(values["side"], float)
    assert values["side"] == pytest.approx(P["side_elevation[m]"][-1], rel=1e-9)
    assert values["floor"][0] == pytest.approx(P["floor_pressure[Pa]"][-1], rel=1e-9)


def test_restart_continues_probes_csv(tmp_path):
    """A run restarted from its checkpoint at step 20 cuts probes.csv after that step and appends the
    same rows as the uninterrupted run's (the probes.csv of a restart in place has no duplicate rows)."""
    (tmp_path / "probes.txt").write_text(PROBES)
    args = TANK + ["-ts_max_steps", 40, "-fs_probes", "probes.txt"]
    run_flexslosh(args + ["-fs_checkpoint_interval", 20, "-fs_output_dir", "a"], cwd=tmp_path)
    full = read_probes(tmp_path / "a")
    run_flexslosh(args + ["-fs_restart", tmp_path / "a" / "checkpoint_000020.h5", "-fs_output_dir", "a"],
                  cwd=tmp_path)
    again = read_probes(tmp_path / "a")
    assert list(again["step"]) == list(range(41))
    for c in full:
        assert np.array_equal(full[c], again[c]), c


def test_probes_figure(tmp_path):
    """python3 -m flexslosh.plot draws probes.png for a run with probes: the pressures and the gauges."""
    import subprocess
    import sys

    from flexslosh.output import read_run

    (tmp_path / "probes.txt").write_text(PROBES)
    run_flexslosh(TANK + ["-ts_max_steps", 10, "-fs_probes", "probes.txt", "-fs_output_dir", "o"], cwd=tmp_path)
    run = read_run(tmp_path / "o")
    assert run.column("mid_pressure[Pa]", "probes").shape == (11,)
    env = dict(os.environ, PYTHONPATH=str(REPO_ROOT / "python"))
    proc = subprocess.run([sys.executable, "-m", "flexslosh.plot", str(tmp_path / "o")], env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout
    png = tmp_path / "o" / "probes.png"
    assert str(png) in proc.stdout and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

"""Probes that read like the sensor (-fs_probes: diameter, cutoff, order, rate; src/monitor/impls/probes/sensor.c).

The face: a wall probe with a diameter averages the boundary integrals' wall pressure (one value per element) over
its face, each element weighted by its exact overlap with the face. In a hydrostatic tank the reading is the face
average of rho0 g (H - y)^+: the value at the centre for a face under the surface, and a non-trivial average for a
face across the surface. Measured (2-D, dx = 3 mm, H = 30 mm, t = 0.15 s): a 31 mm face across the surface
-0.45 % of its exact 43.1 Pa, a 13.1 mm face under it -0.3 %; the previous centroid pick (the elements whose
centroid lies within D/2) read 36.8 Pa there, -15 %. 3-D (dx = 4 mm, the first sample): a 16 mm disc centred on
the surface +2.2 % of 16.7 Pa, one 3 mm lower -1.8 % of 34.8 Pa, a 12 mm disc under the surface -0.9 %.

The time response: the filtered column of a run (variable steps) equals the exact response of the filter
(first order with a sample-and-hold, second-order Butterworth) to the raw column taken linear between samples,
computed here independently with the matrix exponential of the augmented system (x, u, du/dt): 1e-9.
The filters' exactness against closed-form solutions (steps, ramps, sines) is tests/c/monitor/test_sensor.c.
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

from conftest import run_flexslosh
from test_probes import read_probes

RHO0, G, H, DX = 1000.0, 9.81, 0.03, 0.003
TANK = ["-fs_case", "tank", "-fs_tank_length", 0.2, "-fs_dx", DX, "-fs_relax_time", 0.1, "-fs_delta_min", 0.1,
        "-fs_delta_hydrostatic", "-fs_output_interval", 0]
PROBES = """# wall sensors of finite size on the left wall, and two sensors with a time response
probe straddle 0 0.029 diameter 0.031
probe deep 0 0.0125 diameter 0.0131
probe f1 0 0.015 cutoff 40 rate 2500
probe f2 0.1 0.015 order 2 cutoff 40
""" + "".join(f"probe w{k} 0 {0.0015 + 0.003 * k:.4f}\n" for k in range(20))  # the left wall's elements, [3k, 3k+3] mm


def face_average_2d(yc, D):
    """The average of rho0 g (H - y)^+ over the segment [yc - D/2, yc + D/2]."""
    lo, hi = yc - D / 2, min(yc + D / 2, H)
    return RHO0 * G * (0.5 * (H - lo) ** 2 - 0.5 * (H - hi) ** 2) / D if hi > lo else 0.0


def face_average_3d(yc, R):
    """The average of rho0 g (H - y)^+ over a disc of radius R centred at height yc on a vertical wall."""
    d = H - yc
    val = quad(lambda s: (d - s) * 2 * np.sqrt(R * R - s * s), -R, min(d, R))[0] if d > -R else 0.0
    return RHO0 * G * val / (np.pi * R * R)


def filter_reference(t, u, fc, order, rate=0.0):
    """The exact response, from rest at u[0], of the low-pass (first order or Butterworth) to u linear between
    the samples, read at each sample time, or held at the last instant k/rate with a rate."""
    w = 2 * np.pi * fc
    A, B = (np.array([[-w]]), np.array([w])) if order == 1 else \
        (np.array([[0, 1], [-w * w, -np.sqrt(2) * w]]), np.array([0, w * w]))
    n = A.shape[0]
    M = np.zeros((n + 2, n + 2))
    M[:n, :n], M[:n, n], M[n, n + 1] = A, B, 1

    def advance(x, u0, s, h):
        z = expm(M * h) @ np.r_[x, u0, s]
        return z[:n]

    x = np.r_[u[0], np.zeros(n - 1)]
    out, held, k = [u[0]], u[0], np.floor(t[0] * rate) + 1
    for i in range(1, len(t)):
        s, tc, uc = (u[i] - u[i - 1]) / (t[i] - t[i - 1]), t[i - 1], u[i - 1]
        while rate > 0 and k / rate <= t[i]:
            x = advance(x, uc, s, k / rate - tc)
            uc, tc, held, k = uc + s * (k / rate - tc), k / rate, x[0], k + 1
        x = advance(x, uc, s, t[i] - tc)
        out.append(held if rate > 0 else x[0])
    return np.array(out)


@pytest.fixture(scope="module")
def hydrostatic(tmp_path_factory):
    d = tmp_path_factory.mktemp("sensor")
    (d / "probes.txt").write_text(PROBES)
    run_flexslosh(TANK + ["-ts_max_time", 0.15, "-fs_probes", "probes.txt", "-fs_output_dir", "out"], cwd=d)
    return read_probes(d / "out")


def test_face_average_in_a_hydrostatic_tank(hydrostatic):
    """The reading is the exact overlap-weighted average of the elements' wall pressures (read by point probes at
    their centroids), and the face average of the hydrostatic pressure within the wall pressure's own error."""
    P = hydrostatic
    wall = np.array([P[f"w{k}_pressure[Pa]"] for k in range(20)])
    for name, yc, D in (("straddle", 0.029, 0.031), ("deep", 0.0125, 0.0131)):
        lo, hi = yc - D / 2, yc + D / 2
        overlap = np.array([max(0.0, min(hi, 0.003 * (k + 1)) - max(lo, 0.003 * k)) for k in range(20)])
        np.testing.assert_allclose(P[f"{name}_pressure[Pa]"], overlap @ wall / D, rtol=1e-9, atol=1e-9 * RHO0 * G * H)
    assert face_average_2d(0.029, 0.031) == pytest.approx(43.08, abs=0.01)
    assert P["straddle_pressure[Pa]"][-1] == pytest.approx(face_average_2d(0.029, 0.031), rel=0.02)
    assert P["deep_pressure[Pa]"][-1] == pytest.approx(RHO0 * G * (H - 0.0125), rel=0.025)


def test_filtered_column_is_the_filter_of_the_raw_column(hydrostatic):
    P = hydrostatic
    t = P["time"]
    assert np.ptp(np.diff(t)) > 0.5 * np.diff(t).max()  # the steps vary
    names = list(P)
    for name in ("f1", "f2"):  # the raw columns keep their names and places, the reading follows the velocity
        i = names.index(f"{name}_pressure[Pa]")
        assert names[i:i + 4] == [f"{name}_pressure[Pa]", f"{name}_velocity_x[m/s]", f"{name}_velocity_y[m/s]",
                                  f"{name}_pressure_filtered[Pa]"]
    assert "straddle_pressure_filtered[Pa]" not in P
    raw1, raw2 = P["f1_pressure[Pa]"], P["f2_pressure[Pa]"]
    ref1, ref2 = filter_reference(t, raw1, 40, 1, rate=2500), filter_reference(t, raw2, 40, 2)
    scale = RHO0 * G * H
    assert np.abs(P["f1_pressure_filtered[Pa]"] - ref1).max() < 1e-9 * scale
    assert np.abs(P["f2_pressure_filtered[Pa]"] - ref2).max() < 1e-9 * scale
    assert np.abs(raw2 - ref2).max() > 1e-4 * scale  # the filter does something here


def test_three_dimensional_disc_across_the_surface(tmp_path):
    (tmp_path / "p.txt").write_text("probe deep 0 0.012 0.015 diameter 0.012\n"
                                    "probe half 0 0.03 0.015 diameter 0.016\n"
                                    "probe off 0 0.027 0.015 diameter 0.016 cutoff 100\n")
    args = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_length", 0.06, "-fs_tank_width", 0.03, "-fs_dx", 0.004,
            "-fs_c0", 8, "-fs_delta_hydrostatic", "-fs_output_interval", 0, "-ts_max_steps", 3, "-fs_probes", "p.txt"]
    for n in (1, 2):
        run_flexslosh(args + ["-fs_output_dir", f"r{n}"], nranks=n, cwd=tmp_path)
    P, Q = read_probes(tmp_path / "r1"), read_probes(tmp_path / "r2")
    assert P["deep_pressure[Pa]"][0] == pytest.approx(RHO0 * G * (H - 0.012), rel=0.02)
    assert P["half_pressure[Pa]"][0] == pytest.approx(face_average_3d(0.03, 0.008), rel=0.04)
    assert P["off_pressure[Pa]"][0] == pytest.approx(face_average_3d(0.027, 0.008), rel=0.04)
    assert list(P) == list(Q)
    for c in P:
        assert np.abs(P[c] - Q[c]).max() <= 1e-10 * (RHO0 * G * H if "pressure" in c else 1), c


def test_two_ranks_read_as_one(tmp_path):
    (tmp_path / "probes.txt").write_text(PROBES)
    for n in (1, 2):
        run_flexslosh(TANK + ["-ts_max_steps", 40, "-fs_probes", "probes.txt", "-fs_output_dir", f"r{n}"], nranks=n,
                      cwd=tmp_path)
    a, b = read_probes(tmp_path / "r1"), read_probes(tmp_path / "r2")
    assert list(a) == list(b)
    for c in a:
        if "pressure" in c:
            assert np.abs(a[c] - b[c]).max() <= 1e-10 * RHO0 * G * H, c


def test_linear_standing_wave_at_a_finite_sensor(tmp_path):
    """The standing wave (nondimensional: rho0 g = 1, depth 1, k = pi/2): at the wall the linear pressure is
    (1 - y) + eta(t) cosh(k y)/cosh(k); a sensor over y in [0, 1] reads (1 - 0.5) + eta cosh(k/2)/cosh(k)
    sinh(k/2)/(k/2), 13 % above the point value at its centre. Regressed on the wall gauge's eta over the first
    0.9 period (h/dx = 20): measured +2.2 % (the point probes on the wall read 2-4 % high as well), intercept
    -0.3 %."""
    (tmp_path / "sw.txt").write_text("gauge wall 0 0 0 1.5\nprobe F 0 0.5 diameter 1.0\n")
    run_flexslosh(["-fs_case", "standing_wave", "-fs_dx", 0.05, "-ts_max_time", 4.5, "-fs_output_interval", 0,
                   "-fs_probes", "sw.txt", "-fs_output_dir", "out"], cwd=tmp_path)
    P = read_probes(tmp_path / "out")
    k, eta = np.pi / 2, P["wall_elevation[m]"] - 1
    (c0, c1), *_ = np.linalg.lstsq(np.c_[np.ones_like(eta), eta], P["F_pressure[Pa]"], rcond=None)
    face = np.cosh(k / 2) / np.cosh(k) * np.sinh(k / 2) / (k / 2)
    assert c1 == pytest.approx(face, rel=0.05)
    assert c0 == pytest.approx(0.5, rel=0.01)


@pytest.mark.parametrize("text,what", [
    ("probe a 0.1 0.01 size 3\n", "unknown keyword \"size\": expected diameter, cutoff, order or rate"),
    ("probe a 0.1 0.01 order 3\n", "\"order\" needs 1 or 2, got \"3\""),
    ("probe a 0.1 0.01 cutoff\n", "\"cutoff\" needs a positive cut-off frequency (Hz), got \"nothing\""),
    ("probe a 0.1 0.01 rate 0\n", "\"rate\" needs a positive sampling rate (Hz), got \"0\""),
    ("probe a 0.1 0.01 cutoff 5 cutoff 6\n", "\"cutoff\" given twice"),
])
def test_bad_sensor_keywords(tmp_path, text, what):
    (tmp_path / "bad.txt").write_text(text)
    proc = run_flexslosh(TANK + ["-ts_max_steps", 1, "-fs_probes", "bad.txt", "-fs_output_dir", "out"], cwd=tmp_path,
                         check=False)
    assert proc.returncode != 0
    assert "bad.txt:1: probe \"a\": " + what in proc.stdout, proc.stdout[-2000:]


def test_python_probes_give_the_reading(tmp_path):
    """Solver.probes(): a probe with a sensor's time response has its reading last, as in probes.csv."""
    from flexslosh import Solver

    (tmp_path / "p.txt").write_text("probe f 0 0.015 cutoff 40 rate 2500\nprobe g 0.1 0.015\n")
    opts = {"-fs_case": "tank", "-fs_tank_length": 0.2, "-fs_dx": DX, "-fs_output_dir": tmp_path / "out",
            "-fs_probes": tmp_path / "p.txt", "-fs_output_interval": 0, "-fs_progress": 0}
    with Solver(opts) as s:
        s.step(5)
        values = s.probes()
    P = read_probes(tmp_path / "out")
    assert values["f"].shape == (4,) and values["g"].shape == (3,)
    np.testing.assert_allclose(values["f"], [P[f"f_{c}"][-1] for c in ("pressure[Pa]", "velocity_x[m/s]",
                                                                     "velocity_y[m/s]", "pressure_filtered[Pa]")],
                               rtol=1e-9, atol=1e-12)

"""The prescribed motion of the tank (-fs_structure prescribed, docs/motion.md): the liquid's response
against exact and linear-theory answers, the time-series files, bad input, ranks and restarts.

Measured (2-D, coarse): the uniformly accelerated tank's free surface at tan(theta) = a/g within 0.2 %,
the tank rolled to 10 degrees within 0.2 %, the forced response at the wall within 1.3 % of linear
potential theory, residual_total below 1e-6 of the motion's work.
"""
import numpy as np
import pytest

from conftest import (assert_no_crash, last_snapshot, petsc_error_message, read_series, rel_max_diff,
                      run_flexslosh)

G = 9.81


def tank(length, height, fill, dx):
    return ["-fs_case", "tank", "-fs_tank_shape", "rectangular", "-fs_tank_length", length, "-fs_tank_height", height,
            "-fs_fill", fill, "-fs_dx", dx, "-fs_c0", 10, "-fs_structure", "prescribed", "-fs_output_interval", 0]


def read_csv(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


def gauges(tmp_path, lines):
    f = tmp_path / "gauges.txt"
    f.write_text("".join(f"gauge {name} {x} 0 {x} {top}\n" for name, x, top in lines))
    return f


def settled_slope(tmp_path, motion):
    """The free surface's slope (left minus right gauge over their distance) averaged over the last
    sloshing period of a 0.2 m tank, 4.8 cm deep, relaxed while the motion ramps in."""
    g = gauges(tmp_path, [("left", 0.02, 0.12), ("right", 0.18, 0.12)])
    out = tmp_path / "o"
    run_flexslosh(tank(0.2, 0.12, 0.4, 0.004) + motion + [
        "-fs_motion_ramp", 1.0, "-fs_relax_time", 3.0, "-ts_max_time", 3.0, "-fs_probes", g, "-fs_probe_interval", 10,
        "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    p = read_csv(out / "probes.csv")
    last = p["time"] > 3.0 - 0.63  # the first mode's period
    slope = (p["left_elevationm"] - p["right_elevationm"]) / 0.16
    return slope[last].mean(), out


def test_uniform_acceleration_tilts_the_surface(tmp_path):
    """A tank accelerated at a = g/5 along x: the liquid at rest in the tank, its surface at tan = a/g."""
    slope, out = settled_slope(tmp_path, ["-fs_motion_x_poly", f"0,0,{0.2 * G}"])
    print(f"uniform acceleration: slope {slope:.5f}, error {slope / 0.2 - 1:+.2%}")
    assert slope == pytest.approx(0.2, rel=0.01)
    s = read_series(out)
    assert s["motion_disp_x"][-1] == pytest.approx(0.2 * G * (3.0**2 / 2 - 3.0 * 0.5 + 1.0 / 7), rel=1e-9)
    e = read_csv(out / "energy.csv")
    assert np.abs(e["residual_total"]).max() < 1e-5 * e["work_motion"][-1]


def test_rolled_tank_holds_a_level_surface(tmp_path):
    """A tank rolled to 10 degrees and held: the liquid at rest relative to the walls, its surface level
    in the absolute frame, so tilted by -10 degrees in the tank."""
    slope, out = settled_slope(tmp_path, ["-fs_motion_roll_poly", 10])
    print(f"rolled: slope {slope:.5f}, error {slope / np.tan(np.radians(10)) - 1:+.2%}")
    assert slope == pytest.approx(np.tan(np.radians(10)), rel=0.01)
    s = read_series(out)
    assert s["motion_angle"][-1] == pytest.approx(np.radians(10), rel=1e-12)
    assert s["max_velocity"][-1] < 0.02  # 0.013 m/s measured, against sqrt(g h) = 0.69 m/s


def wall_amplitude(length, depth, A, W, nmodes=400):
    """Linear potential theory: the steady amplitude at a wall of a 2-D tank shaken as A sin(W t)
    (docs/motion.md): A W^2/g sum over odd n of 4L/(n pi)^2 w_n^2/(w_n^2 - W^2)."""
    n = np.arange(1, 2 * nmodes, 2)
    k = n * np.pi / length
    w2 = G * k * np.tanh(k * depth)
    return A * W**2 / G * np.sum(4 * length / (n * np.pi)**2 * w2 / (w2 - W**2))


def test_shaken_tank_follows_linear_theory(tmp_path):
    """A 0.2 m tank, 0.1 m deep, shaken along x at 0.6 times its first frequency, 13 mm amplitude:
    the wall elevation's steady part at the forcing frequency within 5 % of linear theory (the free
    sloshing the start leaves is fitted apart, its frequency searched near the first mode's)."""
    L, h, A = 0.2, 0.1, 0.013
    w1 = np.sqrt(G * np.pi / L * np.tanh(np.pi * h / L))
    W = 0.6 * w1
    g = gauges(tmp_path, [("left", 0, 0.2), ("right", L, 0.2)])
    out = tmp_path / "o"
    run_flexslosh(tank(L, 0.2, 0.5, 0.005) + [
        "-fs_motion_x_sines", f"{A},{2 * np.pi / W},0", "-fs_motion_ramp", 1.0, "-fs_relax_time", 2.0,
        "-ts_max_time", 4.0, "-fs_probes", g, "-fs_probe_interval", 5, "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    p = read_csv(out / "probes.csv")
    m = p["time"] > 2.0
    t = p["time"][m]
    theory = wall_amplitude(L, h, A, W)
    amps = []
    for name, sign in (("left", -1), ("right", 1)):  # the left wall rises when the tank moves back
        best = None
        for wf in np.linspace(0.9, 1.1, 81) * w1:
            M = np.c_[np.sin(W * t), np.cos(W * t), np.ones_like(t), np.sin(wf * t), np.cos(wf * t)]
            c = np.linalg.lstsq(M, p[f"{name}_elevationm"][m], rcond=None)[0]
            r = np.sum((M @ c - p[f"{name}_elevationm"][m])**2)
            if best is None or r < best[0]:
                best = (r, c)
        amps.append(sign * best[1][0])
    amp = np.mean(amps)
    print(f"shaken: amplitudes {amps[0] / theory - 1:+.2%} (left), {amps[1] / theory - 1:+.2%} (right) off theory")
    assert amp == pytest.approx(theory, rel=0.05), (amps, theory)
    e = read_csv(out / "energy.csv")
    assert np.abs(e["residual_total"]).max() < 5e-5 * np.abs(e["work_motion"]).max()  # 2.2e-5 measured


def test_time_series_file_is_interpolated_smoothly(tmp_path):
    """A heave from a file sampled every 0.02 s (y = 0.01 sin 2 pi t): the spline gives the motion, its
    velocity and acceleration (timeseries tip_*) close to the exact ones, without a jump."""
    f = tmp_path / "heave.txt"
    ts = np.arange(0, 2.001, 0.02)
    f.write_text("# time value\n" + "".join(f"{x:.6f}, {0.01 * np.sin(2 * np.pi * x):.10e}\n" for x in ts))
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "beam", "-fs_structure", "prescribed", "-fs_motion_y_file", f, "-ts_dt", 0.005,
                   "-ts_max_time", 1.5, "-fs_output_dir", out], cwd=tmp_path)
    s = read_series(out)
    t = s["time"]
    inner = (t > 0.2) & (t < 1.5)
    w = 2 * np.pi
    assert np.abs(s["tip_displacement"] - 0.01 * np.sin(w * t))[inner].max() < 1e-6
    assert np.abs(s["tip_velocity"] - 0.01 * w * np.cos(w * t))[inner].max() < 1e-3 * 0.01 * w
    assert np.abs(s["tip_acceleration"] + 0.01 * w**2 * np.sin(w * t))[inner].max() < 1e-2 * 0.01 * w**2
    assert np.abs(np.diff(s["tip_acceleration"])).max() < 0.05 * 0.01 * w**2  # continuous


@pytest.mark.parametrize("args,expect", [
    (["-fs_motion_x_sines", "0.01,0,0"], ["-fs_motion_x_sines", "period 0", "T > 0"]),
    (["-fs_motion_roll_sines", "2,1"], ["-fs_motion_roll_sines", "triples", "got 2"]),
    (["-fs_motion_y_poly", "0,inf"], ["-fs_motion_y_poly", "value inf", "component 1", "finite"]),
    (["-fs_motion_ramp", "-1"], ["-fs_motion_ramp", "-1", "non-negative"]),
    (["-fs_motion_ramp", "nan"], ["-fs_motion_ramp", "nan", "out of range"]),
    (["-fs_motion_z_sines", "0.01,1,0"], ["-fs_motion_z_sines", "3-D"]),
    (["-fs_motion_x_file", "missing.txt"], ["-fs_motion_x_file", "missing.txt", "cannot open"]),
    (["-fs_motion_x_file", "bad.txt"], ["-fs_motion_x_file", "bad.txt", "line 3", "two finite numbers"]),
    (["-fs_motion_roll_file", "back.txt"], ["-fs_motion_roll_file", "back.txt", "line 4", "0.1", "strictly increase"]),
    (["-fs_motion_y_file", "one.txt"], ["-fs_motion_y_file", "one.txt", "1 points", "at least two"]),
])
def test_bad_motion_input(tmp_path, args, expect):
    (tmp_path / "bad.txt").write_text("# t x\n0 0\n0.1 abc\n")
    (tmp_path / "back.txt").write_text("0 0\n0.1 1\n\n0.1 2\n")
    (tmp_path / "one.txt").write_text("0 0\n")
    proc = run_flexslosh(tank(0.2, 0.12, 0.4, 0.01) + ["-ts_max_steps", 1, "-fs_output_dir", tmp_path / "o"] + args,
                         cwd=tmp_path, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg


ROLL = tank(0.2, 0.12, 0.4, 0.005) + ["-fs_motion_roll_sines", "3,0.7,0", "-fs_motion_x_sines", "0.005,0.5,30",
                                     "-fs_motion_ramp", 0.05]


def test_ranks_agree(tmp_path):
    """Rolled and shaken, 40 steps on 1 and 2 ranks: the same particles and energy budget."""
    runs = {}
    for n in (1, 2):
        out = tmp_path / f"r{n}"
        run_flexslosh(ROLL + ["-ts_max_steps", 40, "-fs_output_dir", out], nranks=n, cwd=tmp_path)
        runs[n] = (last_snapshot(out), read_csv(out / "energy.csv"))
    (a, ea), (b, eb) = runs[1], runs[2]
    assert np.array_equal(a["id"], b["id"])
    for f in ("position", "velocity", "density"):
        assert rel_max_diff(a[f], b[f]) < 1e-10, f
    for c in ("E_liquid_abs", "work_motion"):
        assert np.abs(ea[c] - eb[c]).max() <= 1e-10 * np.abs(ea[c]).max(), c


def test_restart_is_exact(tmp_path):
    """Restarted from the checkpoint at step 20, the run ends where the uninterrupted one does."""
    a, b = tmp_path / "A", tmp_path / "B"
    run_flexslosh(ROLL + ["-ts_max_steps", 40, "-fs_checkpoint_interval", 20, "-fs_output_dir", a], cwd=tmp_path)
    run_flexslosh(ROLL + ["-ts_max_steps", 40, "-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b],
                  cwd=tmp_path)
    pa, pb = last_snapshot(a), last_snapshot(b)
    assert np.array_equal(pa["position"], pb["position"])
    ea, eb = read_csv(a / "energy.csv"), read_csv(b / "energy.csv")
    assert ea["work_motion"][-1] == eb["work_motion"][-1]
    assert read_series(a)["motion_angle"][-1] == read_series(b)["motion_angle"][-1]

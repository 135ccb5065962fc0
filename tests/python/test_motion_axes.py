"""A 3-D tank turned about any axis through any point (docs/motion.md, "Rotation about any axis"): pitch,
yaw, a turn about -fs_motion_axis_direction and a 6-DOF motion file, against exact answers.

- Turned by yaw, pitch and an axis through a point off the tank and held, the liquid settles at rest: the
  loads (global axes, less the liquid's weight and its moment at rest in the upright tank) are then
  F = 0 and M = m (Q (c - p) - (c0 - p)) x g from the liquid's centre of mass c (tank frame) and c0
  (at the start), Q built here from the documented convention Q = R_y(yaw) R_x(pitch) R_z(roll) R_n(psi).
- A roll through the rotated frame (-fs_motion_pitch_poly 0 switches it on) is the roll of the frame
  turning about z to round-off, on 1 and 2 ranks.
- A 6-DOF file sampling an analytic motion gives the run of the same motion given by sines, to the spline's
  error.
The frame's inertial accelerations for any rotation are checked exactly in tests/c/coupling/test_frame.c.
"""
import numpy as np
import pytest

from conftest import (assert_no_crash, last_snapshot, petsc_error_message, read_series, read_snapshot,
                      rel_max_diff, run_flexslosh, snapshot_files)

G = np.array([0.0, -9.81, 0.0])
TANK3 = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "rectangular", "-fs_tank_length", 0.1,
         "-fs_tank_height", 0.08, "-fs_tank_width", 0.06, "-fs_fill", 0.4, "-fs_dx", 0.01, "-fs_c0", 10,
         "-fs_structure", "prescribed", "-fs_output_interval", 0]


def turn(axis, deg):
    """The rotation by deg degrees about axis (Rodrigues, here independent of the C code)."""
    n = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(deg)
    K = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def rotation(yaw=0.0, pitch=0.0, roll=0.0, axis=None, psi=0.0):
    Q = turn([0, 1, 0], yaw) @ turn([1, 0, 0], pitch) @ turn([0, 0, 1], roll)
    return Q @ turn(axis, psi) if axis is not None else Q


def centre(snap, weight):
    """The centre of mass: the particles' masses are their initial (hydrostatic) densities times one cell's
    volume, so the first snapshot's densities weigh them."""
    return (snap["position"] * weight[:, None]).sum(axis=0) / weight.sum()


def test_turned_tank_settles_to_the_static_loads(tmp_path):
    """Yaw 20, pitch 6 and 10 degrees about (0.3, 1, 0.4) through p = (0.15, 0.01, 0), ramped over 0.25 s and
    relaxed: averaged over the last 0.4 s (about the first sloshing period) and compared at the snapshots,
    the loads' force vanishes and their moment is the liquid's weight's moment about p."""
    out, p = tmp_path / "o", np.array([0.15, 0.01, 0.0])
    run_flexslosh(TANK3 + ["-fs_motion_yaw_poly", 20, "-fs_motion_pitch_poly", 6, "-fs_motion_axis_poly", 10,
                           "-fs_motion_axis_direction", "0.3,1,0.4", "-fs_tank_reference", "0.15,0.01,0",
                           "-fs_motion_ramp", 0.25, "-fs_relax_time", 0.9, "-ts_max_time", 0.9,
                           "-fs_output_interval", 0.05, "-fs_output_dir", out], cwd=tmp_path, timeout=600)
    s = read_series(out)
    files = snapshot_files(out)
    first = read_snapshot(files[0])
    weight, m = first["density"], s["mass"][0]
    c0 = centre(first, weight)
    Q = rotation(yaw=20, pitch=6, axis=[0.3, 1, 0.4], psi=10)
    got, want, force = [], [], []
    for f in files:
        snap = read_snapshot(f)
        if snap.attrs["time"] < 0.5 - 1e-9:
            continue
        assert np.array_equal(snap["id"], first["id"])
        c = centre(snap, weight)
        k = np.argmin(np.abs(s["time"] - snap.attrs["time"]))
        got.append([s[f"load_moment_{a}"][k] for a in "xyz"])
        force.append([s[f"load_force_{a}"][k] for a in "xyz"])
        want.append(m * np.cross(Q @ (c - p) - (c0 - p), G))
    got, want, force = np.mean(got, axis=0), np.mean(want, axis=0), np.mean(force, axis=0)
    scale = np.linalg.norm(want)
    print(f"turned tank: moment {got} against {want} (error {np.linalg.norm(got - want) / scale:.2%}), "
          f"force {np.linalg.norm(force) / (m * 9.81):.2%} of the weight")
    assert scale > 0.3 * m * 9.81 * 0.05  # a moment of a few centimetres' lever: the test sees the turn
    assert np.linalg.norm(got - want) < 0.05 * scale
    assert np.linalg.norm(force) < 0.02 * m * 9.81
    # the walls' pressure integral in the tank's frame carries the weight turned into it: m Q^T g
    wall = np.array([s[f"wall_tank_force_{a}"][-1] for a in "xyz"])
    assert np.linalg.norm(wall - m * Q.T @ G) < 0.1 * m * 9.81, (wall, m * Q.T @ G)


ROLL3 = TANK3 + ["-fs_motion_roll_sines", "4,0.6,10", "-fs_motion_x_sines", "0.004,0.5,30",
                 "-fs_motion_z_sines", "0.003,0.4,0", "-fs_tank_reference", "0.02,0.01,0.01",
                 "-fs_motion_ramp", 0.05, "-ts_max_steps", 50]


def test_roll_through_the_rotated_frame_is_the_roll(tmp_path):
    """The same roll with the whole rotation switched on (a pitch of 0): the same liquid to round-off, on 1
    and on 2 ranks."""
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    run_flexslosh(ROLL3 + ["-fs_output_dir", a], cwd=tmp_path)
    run_flexslosh(ROLL3 + ["-fs_motion_pitch_poly", 0, "-fs_output_dir", b], cwd=tmp_path)
    run_flexslosh(ROLL3 + ["-fs_motion_pitch_poly", 0, "-fs_output_dir", c], nranks=2, cwd=tmp_path)
    sa, sb, sc = read_series(a), read_series(b), read_series(c)
    assert "motion_pitch" not in sa and np.all(sb["motion_pitch"] == 0)
    pa = last_snapshot(a)
    for other, s in ((b, sb), (c, sc)):
        po = last_snapshot(other)
        assert np.array_equal(pa["id"], po["id"])
        for f in ("position", "velocity", "density"):
            assert rel_max_diff(pa[f], po[f]) < 1e-9, (other, f)
        for col in ("load_force_x", "load_force_y", "load_force_z", "load_moment_x", "load_moment_y",
                    "load_moment_z", "wall_tank_force_x", "motion_angle"):
            assert rel_max_diff(sa[col], s[col]) < 1e-8, (other, col)


SINES = {"x": "0.004,0.5,30", "y": "0.003,0.4,0", "z": "0.002,0.6,60", "pitch": "3,0.5,20", "yaw": "5,0.7,0",
         "roll": "4,0.6,10"}


def test_six_dof_file_is_the_analytic_motion(tmp_path):
    """x, y, z, pitch, yaw and roll given by sines, and the same sampled every 2 ms in a 6-DOF file: the
    same motion (the spline's error) and the same liquid."""
    t = np.arange(-0.01, 0.3, 0.002)
    cols = [t]
    for c in ("x", "y", "z", "pitch", "yaw", "roll"):
        A, T, phi = (float(v) for v in SINES[c].split(","))
        cols.append(A * np.sin(2 * np.pi * t / T + np.radians(phi)))
    f = tmp_path / "six.txt"
    f.write_text("# t x y z rx ry rz\n" + "".join(" ".join(f"{v:.12e}" for v in row) + "\n"
                                                   for row in np.array(cols).T))
    common = TANK3 + ["-fs_tank_reference", "0.02,0.01,0.01", "-fs_motion_ramp", 0.05, "-ts_max_steps", 50]
    a, b = tmp_path / "a", tmp_path / "b"
    run_flexslosh(common + sum((["-fs_motion_" + c + "_sines", v] for c, v in SINES.items()), [])
                  + ["-fs_output_dir", a], cwd=tmp_path)
    run_flexslosh(common + ["-fs_motion_file", f, "-fs_output_dir", b], cwd=tmp_path)
    sa, sb = read_series(a), read_series(b)
    for col in ("motion_disp_x", "motion_disp_y", "motion_disp_z", "motion_pitch", "motion_yaw", "motion_angle"):
        assert rel_max_diff(sa[col], sb[col]) < 1e-5, col
    for col in ("tip_acceleration", "tank_angular_acceleration", "load_force_x", "load_force_z", "load_moment_y"):
        err = rel_max_diff(sa[col], sb[col])
        print(f"six-dof file: {col} differs by {err:.2e} of its largest value")
        assert err < 2e-3, col
    pa, pb = last_snapshot(a), last_snapshot(b)
    assert rel_max_diff(pa["velocity"], pb["velocity"]) < 2e-3
    # the energy budget of the whole rotation: work_motion = F . Q^T V_ref + w . M integrated, the residual the
    # integrator's error (it falls 50-fold with half the time step)
    e = np.genfromtxt(a / "energy.csv", delimiter=",", names=True)
    ratio = np.abs(e["residual_total"]).max() / np.abs(e["work_motion"]).max()
    print(f"six-dof: residual_total {ratio:.2e} of the largest |work_motion|")
    assert ratio < 1e-3


@pytest.mark.parametrize("args,expect", [
    (["-fs_dim", 2, "-fs_motion_pitch_sines", "3,1,0"], ["-fs_motion_pitch_sines", "3-D"]),
    (["-fs_dim", 2, "-fs_motion_file", "six.txt"], ["-fs_motion_file", "six.txt", "3-D"]),
    (["-fs_dim", 2, "-fs_tank_reference", "0.1,0,0"], ["-fs_tank_reference", "two values", "got 3"]),
    (["-fs_motion_axis_poly", 5], ["-fs_motion_axis_direction", "give its direction"]),
    (["-fs_motion_axis_poly", 5, "-fs_motion_axis_direction", "0,0,0"],
     ["-fs_motion_axis_direction", "has no direction", "nonzero"]),
    (["-fs_motion_axis_poly", 5, "-fs_motion_axis_direction", "1,0"], ["-fs_motion_axis_direction", "three", "got 2"]),
    (["-fs_motion_file", "short.txt"], ["-fs_motion_file", "short.txt", "line 2", "seven finite numbers"]),
    (["-fs_tank_reference", "0.1,0,5"], ["-fs_tank_reference", "its z", "[-0.06, 0.12]"]),
])
def test_bad_rotation_input(tmp_path, args, expect):
    (tmp_path / "six.txt").write_text("0 0 0 0 0 0 0\n1 0 0 0 0 0 0\n")
    (tmp_path / "short.txt").write_text("0 0 0 0 0 0 0\n1 0 0 0 0 0\n")
    proc = run_flexslosh(TANK3 + ["-ts_max_steps", 1, "-fs_output_dir", tmp_path / "o"] + args, cwd=tmp_path,
                         check=False)
    assert_no_crash(proc)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg

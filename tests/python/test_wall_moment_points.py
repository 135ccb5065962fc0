"""A moment reference point per wall (-fs_walls_moment_walls, -fs_walls_moment_points; docs/walls.md): the
reported moment of a named wall about its own point p is the moment about the load point o moved there,
M_p = M_o + (o - p) x F, to round-off (the 11 digits of timeseries.csv); the forces and every other column unchanged. A baffled tank with
free-standing baffles (walls "tank" and "baffles"), 2-D and 3-D, a few steps.
"""
import numpy as np
import pytest

from conftest import assert_no_crash, petsc_error_message, read_series, run_flexslosh

BAFFLED = ["-fs_case", "tank", "-fs_tank_shape", "baffled", "-fs_tank_compartments", 2, "-fs_tank_baffle_gap", 0.01,
           "-fs_output_interval", 0]


def moment(s, wall, dim):
    return np.array([s[f"wall_{wall}_moment_{a}"] for a in "xyz"]).T if dim == 3 else s[f"wall_{wall}_moment"]


def force(s, wall, dim):
    f = np.array([s[f"wall_{wall}_force_{a}"] for a in "xyz"[:dim]]).T
    return f if dim == 3 else np.c_[f, np.zeros(len(f))]


def moved(M, F, r, dim):
    """M + r x F, r = o - p (2-D: the z component)."""
    m = np.cross(np.broadcast_to(r, F.shape), F)
    return M + (m if dim == 3 else m[:, 2])


@pytest.mark.parametrize("dim", [2, 3])
def test_moment_about_each_walls_point(tmp_path, dim):
    base = BAFFLED + (["-fs_dim", 3, "-fs_tank_width", 0.03, "-fs_dx", 0.01, "-ts_max_steps", 3] if dim == 3 else
                      ["-fs_dx", 0.005, "-ts_max_steps", 20])
    o, p = np.array([0.05, 0.02, 0.01]), np.array([0.1, 0.03, -0.02])
    a, b = tmp_path / "a", tmp_path / "b"
    run_flexslosh(base + ["-fs_output_dir", a], cwd=tmp_path)
    run_flexslosh(base + ["-fs_walls_load_point", ",".join(map(str, o[:dim])), "-fs_walls_moment_walls", "baffles",
                          "-fs_walls_moment_points", ",".join(map(str, p[:dim])), "-fs_output_dir", b], cwd=tmp_path)
    sa, sb = read_series(a), read_series(b)
    for wall, point in (("tank", o), ("baffles", p)):
        r = -point if dim == 3 else np.r_[-point[:2], 0]  # a's moments are about the origin
        F = force(sa, wall, dim)
        want = moved(moment(sa, wall, dim), F, r, dim)
        got = moment(sb, wall, dim)
        scale = np.abs(F).max() * np.linalg.norm(point[:dim]) + np.abs(moment(sa, wall, dim)).max()
        print(f"{dim}-D {wall}: moment about its point off by {np.abs(got - want).max() / scale:.1e} of its scale")
        assert np.abs(got - want).max() <= 1e-9 * scale, wall  # the CSV keeps 11 digits
        assert np.array_equal(force(sb, wall, dim), F)
    for col in sa:  # the loads' points change nothing else
        if "_moment" not in col:
            assert np.array_equal(sa[col], sb[col]), col


@pytest.mark.parametrize("args,expect", [
    (["-fs_walls_moment_walls", "lid", "-fs_walls_moment_points", "0,0"],
     ["-fs_walls_moment_walls", '"lid"', "its walls are tank, baffles"]),
    (["-fs_walls_moment_walls", "tank,baffles", "-fs_walls_moment_points", "0,0,1"],
     ["-fs_walls_moment_points", "3 numbers", "2 walls", "expected 4"]),
    (["-fs_walls_moment_points", "0,0"], ["-fs_walls_moment_points", "2 numbers", "0 walls"]),
])
def test_bad_moment_points(tmp_path, args, expect):
    proc = run_flexslosh(BAFFLED + ["-fs_dx", 0.01, "-ts_max_steps", 0, "-fs_output_dir", tmp_path / "o"] + args,
                         cwd=tmp_path, check=False)
    assert_no_crash(proc)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg

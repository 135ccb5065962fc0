"""A user's own STL tank (issue 35): its vertices scaled, rotated and translated as read
(-fs_tank_stl_scale, -fs_tank_stl_rotate, -fs_tank_stl_translate), the unit check of a file in millimetres
read as metres, and -fs_view's estimate before the run. Coarse: every run stops after the set-up."""
import os
import re
import resource
import subprocess

import numpy as np
import pytest

from conftest import (MPI_ENV, assert_no_crash, flexslosh_bin, last_snapshot, petsc_error_message, rel_max_diff,
                      run_flexslosh)
from test_walls_3d import ascii_stl, box_facets

TANK3 = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_output_interval", 0]
# an asymmetric tank, in metres: a box with a post off its middle, so that a wrong rotation or order shows
SOLIDS = {"tank": box_facets((0, 0, 0), (0.06, 0.06, 0.03)), "post": box_facets((0.01, 0.005, 0.005), (0.02, 0.04, 0.015))}


def rot(axis, deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    c, s = round(c), round(s)  # quarter turns, exact as the solver takes them
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def stored(solids, scale, angles, shift):
    """The solids as a file would hold them so that R (scale f) + shift, R = Rz Ry Rx, gives them back."""
    R = rot(2, angles[2]) @ rot(1, angles[1]) @ rot(0, angles[0])
    back = lambda p: tuple(float(v) for v in R.T @ (np.array(p) - shift) / scale)
    return {name: [tuple(back(p) for p in t) for t in tris] for name, tris in solids.items()}


def test_scaled_rotated_translated_file_gives_the_same_tank(tmp_path):
    """A file in millimetres, turned a quarter about x then about y and moved, read with the options that undo it,
    fills the same particles as the tank in metres: the same count, positions to round-off."""
    angles, shift = (90, 90, 0), np.array([1.0, -2.0, 0.5])
    (tmp_path / "m.stl").write_text(ascii_stl(SOLIDS))
    (tmp_path / "cad.stl").write_text(ascii_stl(stored(SOLIDS, 0.001, angles, shift)))
    run_flexslosh(TANK3 + ["-fs_tank_stl", "m.stl", "-fs_dx", 0.005, "-ts_max_steps", 0, "-fs_output_dir", "ref"],
                  cwd=tmp_path)
    p = run_flexslosh(TANK3 + ["-fs_tank_stl", "cad.stl", "-fs_dx", 0.005, "-ts_max_steps", 0, "-fs_output_dir", "cad",
                               "-fs_tank_stl_scale", "mm", "-fs_tank_stl_rotate", "90,90,0",
                               "-fs_tank_stl_translate", "1,-2,0.5"], cwd=tmp_path)
    a, b = last_snapshot(tmp_path / "ref"), last_snapshot(tmp_path / "cad")
    assert len(a["position"]) == len(b["position"]) > 100
    assert np.abs(a["position"] - b["position"]).max() < 1e-12
    # the bounding box as read (millimetres, turned) and after, in metres
    line = next(l for l in p.stdout.splitlines() if l.startswith("STL tank cad.stl: bounding box"))
    assert re.search(r"as read; \[-?0\.?, 0\.06\] x \[-?0\.?, 0\.06\] x \[-?0\.?, 0\.03\] m after -fs_tank_stl_scale mm",
                     line), line
    assert "Warning" not in p.stdout
    # every rank moves the broadcast triangles alike: 2 ranks, 3 steps, as 1 rank
    for n in (1, 2):
        run_flexslosh(TANK3 + ["-fs_tank_stl", "cad.stl", "-fs_dx", 0.005, "-ts_max_steps", 3, "-fs_output_dir", f"r{n}",
                               "-fs_tank_stl_scale", "mm", "-fs_tank_stl_rotate", "90,90,0",
                               "-fs_tank_stl_translate", "1,-2,0.5"], nranks=n, cwd=tmp_path)
    a, b = last_snapshot(tmp_path / "r1"), last_snapshot(tmp_path / "r2")
    assert np.array_equal(a["id"], b["id"])
    for f in ("position", "velocity", "density"):
        assert rel_max_diff(a[f], b[f]) < 1e-10, f


def test_wrong_order_or_sign_does_not_fit(tmp_path):
    """The same file read with the angles about the other axes order (a wrong reading of the options) is not the
    tank: its box differs, and the check of the order above has teeth."""
    (tmp_path / "cad.stl").write_text(ascii_stl(stored(SOLIDS, 0.001, (90, 90, 0), np.array([1.0, -2.0, 0.5]))))
    p = run_flexslosh(TANK3 + ["-fs_tank_stl", "cad.stl", "-fs_dx", 0.005, "-ts_max_steps", 0, "-fs_output_dir", "o",
                               "-fs_tank_stl_scale", "0.001", "-fs_tank_stl_rotate", "0,90,90",
                               "-fs_tank_stl_translate", "1,-2,0.5"], cwd=tmp_path, check=False)
    line = next(l for l in p.stdout.splitlines() if l.startswith("STL tank cad.stl: bounding box"))
    assert "[0., 0.06] x [0., 0.06] x [0., 0.03] m after" not in line, line


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (4000000 * 1024, 4000000 * 1024))


@pytest.mark.parametrize("dx,expect", [
    # 200 x 60 x 30 "m" half full: 1.8e5 m^3 of liquid
    (0.002, [r"-fs_dx 0\.002\b", r"2\.25e\+13 particles", r"more than an index can count"]),
    (0.3, [r"-fs_dx 0\.3\b", r"6\.67e\+06 particles", r"12\.4 GB", r"2000 bytes a particle in 3-D",
           r"more than the 3\.8\d GB a rank may use"]),
])
def test_millimetres_read_as_metres_are_refused_at_once(tmp_path, dx, expect):
    """A CAD export in millimetres read as metres: a warning naming the unit, then an error before anything is
    allocated with the count, the memory and the options to change (under a 4 GB address-space limit, so that the
    verdict does not depend on the machine)."""
    (tmp_path / "wing.stl").write_text(ascii_stl({"bay": box_facets((0, 0, 0), (200, 60, 30))}))
    cmd = [str(flexslosh_bin()), "-fs_progress", "0", "-fs_output_dir", "o", "-ts_max_steps", "1", "-fs_dx", str(dx)]
    proc = subprocess.run(cmd + [str(a) for a in TANK3] + ["-fs_tank_stl", "wing.stl"], cwd=tmp_path,
                          env=dict(os.environ, **MPI_ENV), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=60, preexec_fn=_limit_memory)
    assert_no_crash(proc)
    assert re.search(r"Warning: the STL tank wing\.stl is 200\.? m across .*-fs_tank_stl_scale mm", proc.stdout)
    msg = petsc_error_message(proc.stdout)
    for e in expect + [r"1\.8e\+05 m\^3 of liquid", r"-fs_tank_stl_scale mm for a file in millimetres"]:
        assert re.search(e, msg), (e, msg)


@pytest.mark.parametrize("value", ["2mm", "-1", "0", "nan", "feet"])
def test_bad_scale(tmp_path, value):
    (tmp_path / "m.stl").write_text(ascii_stl(SOLIDS))
    p = run_flexslosh(TANK3 + ["-fs_tank_stl", "m.stl", "-fs_tank_stl_scale", value, "-fs_output_dir", "o"],
                      cwd=tmp_path, check=False)
    assert_no_crash(p)
    msg = petsc_error_message(p.stdout)
    assert f"-fs_tank_stl_scale {value} is not a scale" in msg and "m, cm, mm or in" in msg, msg


def test_view_prints_the_estimate(tmp_path):
    """-fs_view, before the run: the particles, the wall elements, the acoustic step CFL h/c0 of the liquid at
    rest, the steps to -ts_max_time and their wall time at the measured cost of a particle-step (3-D: 1/1.75e4 s)."""
    (tmp_path / "m.stl").write_text(ascii_stl(SOLIDS))
    p = run_flexslosh(TANK3 + ["-fs_tank_stl", "m.stl", "-fs_dx", 0.005, "-ts_max_time", 0.1, "-ts_max_steps", 0,
                               "-fs_view", "-fs_output_dir", "o"], cwd=tmp_path)
    n = len(last_snapshot(tmp_path / "o")["position"])
    m = re.search(r"estimate: (\d+) particles; time step ([0-9.e+-]+) s at the start \(limit: acoustic; the acoustic "
                  r"CFL h/c0 ([0-9.e+-]+) s\), (\d+) steps to -ts_max_time 0\.1 s \(-ts_max_steps stops the run "
                  r"first\); about 0 s of wall time for 0 steps", p.stdout)
    assert m, p.stdout[-3000:]
    assert int(m[1]) == n
    assert float(m[2]) == pytest.approx(0.01 / 20) and float(m[3]) == pytest.approx(0.01 / 20)  # h = 2 dx, c0 = 20
    assert int(m[4]) == 200
    assert re.search(r"walls: \d+ elements, bounding box \[0\.?, 0\.06\] x \[0\.?, 0\.06\] x \[0\.?, 0\.03\]", p.stdout)
    p = run_flexslosh(TANK3 + ["-fs_tank_stl", "m.stl", "-fs_dx", 0.005, "-ts_max_time", 0.01, "-fs_view",
                               "-fs_output_dir", "o2"], cwd=tmp_path)
    m = re.search(r"about ([0-9.e+-]+) s of wall time for (\d+) steps on 1 rank", p.stdout)
    assert int(m[2]) == 20 and float(m[1]) == pytest.approx(20 * n / 1.75e4, rel=0.01)

"""Three-dimensional tanks (the triangle-mesh boundary): the built-in tanks extruded across a width
and tanks from STL files, the same results on 1 and 3 ranks, and the bad input of 3-D walls."""
import numpy as np
import pytest

from conftest import REPO_ROOT, assert_no_crash, last_snapshot, petsc_error_message, read_series, rel_max_diff, run_flexslosh

TANK3 = ["-fs_case", "tank", "-fs_dim", 3, "-fs_output_interval", 0]
# cases/hydrostatic_3d.opts's settings for a liquid at rest: c0 8 m/s, a delta floor with the hydrostatic correction,
# a start-up relaxation of 0.1 s
AT_REST = ["-fs_c0", 8, "-fs_relax_time", 0.1, "-fs_delta_min", 0.1, "-fs_delta_hydrostatic"]


def box_facets(lo, hi):
    """The 12 triangles of the box lo..hi, counter-clockwise seen from outside (outward normals)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]
    tris = []
    for a, b, c, d in quads:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


def ascii_stl(solids):
    """An ASCII STL of named solids: {name: [triangles]}."""
    out = []
    for name, tris in solids.items():
        out.append(f"solid {name}")
        for t in tris:
            out += ["  facet normal 0 0 0", "    outer loop"] + [f"      vertex {p[0]} {p[1]} {p[2]}" for p in t]
            out += ["    endloop", "  endfacet"]
        out.append(f"endsolid {name}")
    return "\n".join(out) + "\n"


def one_and_three_ranks(tmp_path, args, fields=("position", "velocity", "density"), timeout=300):
    """Runs args on 1 and on 3 ranks (into tmp_path/r1, r3) and asserts the same particles, their fields equal to
    round-off; returns the 1-rank run's last snapshot."""
    snaps = {}
    for n in (1, 3):
        run_flexslosh(args + ["-fs_output_dir", tmp_path / f"r{n}"], nranks=n, cwd=tmp_path, timeout=timeout)
        snaps[n] = last_snapshot(tmp_path / f"r{n}")
    a, b = snaps[1], snaps[3]
    assert np.array_equal(a["id"], b["id"])
    for f in fields:
        assert rel_max_diff(a[f], b[f]) < 1e-10, f
    return a


def test_box_tank_ranks_agree(tmp_path):
    """The rectangular tank extruded to 3-D (0.06 x 0.06 x 0.03 m, 50 % full, dx = 5 mm, 432
    particles): 20 steps on 1 and 3 ranks give the same particles; the liquid stays in the box, and the
    loads are force and moment vectors (6 columns per wall)."""
    a = one_and_three_ranks(tmp_path, TANK3 + ["-fs_tank_length", 0.06, "-fs_tank_width", 0.03, "-fs_dx", 0.005,
                                               "-ts_max_steps", 20])
    assert len(a["id"]) == 432 and a["position"].shape[1] == 3
    x = a["position"]
    assert (x > 0).all() and (x[:, 0] < 0.06).all() and (x[:, 1] < 0.031).all() and (x[:, 2] < 0.03).all()
    s = read_series(tmp_path / "r1")
    cols = [c for c in s if c.startswith("wall_tank_")]
    assert cols == [f"wall_tank_{p}" for p in ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")]


LIFTED_ALL = ["-fs_tank_baffle_gap", 0.005, "-fs_walls_visibility", "all"]


@pytest.mark.parametrize("extra", [[], LIFTED_ALL, LIFTED_ALL + ["-fs_walls_repulsion", 0.5, "-fs_walls_repulsion_distance", 0.6]],
                         ids=["cut", "lifted-all", "lifted-all-repulsion"])
def test_baffled_tank_3d_ranks_agree(tmp_path, extra):
    """The seed's baffled tank extruded across 0.02 m (two compartments, dx = 4 mm): the liquid region
    is not convex, so fluid pairs through a baffle are cut and hidden elements dropped; also with the
    baffles lifted 5 mm and every pair and element counted (-fs_walls_visibility all), and so with the
    push back near contact of cases/baffles_at_rest_3d.opts (here from 0.6 dx, so that the rows started
    dx/2 from the walls feel it from the first step). 10 steps on 1 and 3 ranks agree, and no particle
    sits in a baffle."""
    a = one_and_three_ranks(tmp_path, TANK3 + ["-fs_tank_shape", "baffled", "-fs_tank_compartments", 2, "-fs_tank_width",
                                               0.02, "-fs_dx", 0.004, "-ts_max_steps", 10] + extra)
    x = a["position"]
    gap = 0.005 if extra else 0.0
    assert not ((x[:, 0] > 0.1) & (x[:, 0] < 0.105) & (x[:, 1] > gap)).any()  # the baffle between the compartments
    assert (x[:, 0] < 0.1).sum() == (x[:, 0] > 0.105).sum()  # the two compartments hold the same liquid


def test_stl_tank_with_an_obstacle(tmp_path):
    """A tank from an ASCII STL with two named solids (a box "tank" and a post "post" standing inside
    it, both with outward normals as STL files give them): the post is turned inside out by the check,
    no particle starts inside it, and each solid is a wall with its own load columns."""
    stl = tmp_path / "tank.stl"
    stl.write_text(ascii_stl({"tank": box_facets((0, 0, 0), (0.06, 0.06, 0.03)),
                              "post": box_facets((0.025, 0.01, 0.01), (0.035, 0.05, 0.02))}))
    out = tmp_path / "o"
    run_flexslosh(TANK3 + ["-fs_tank_shape", "stl", "-fs_tank_stl", stl, "-fs_dx", 0.005, "-ts_max_steps", 5,
                           "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    x = last_snapshot(out)["position"]
    inside = (x[:, 0] > 0.025) & (x[:, 0] < 0.035) & (x[:, 1] > 0.01) & (x[:, 1] < 0.05) & (x[:, 2] > 0.01) & (x[:, 2] < 0.02)
    assert not inside.any()
    assert len(x) == 432 - 2 * 4 * 2  # the post takes 2 x 4 x 2 lattice points below the surface
    s = read_series(out)
    assert "wall_post_force_x" in s and "wall_tank_moment_z" in s
    # the liquid at rest pushes on the post from all sides: its vertical load is the buoyancy of the
    # submerged part, rho g V (0.01 x 0.02 x 0.01 below the 0.03 m surface), measured -6.3 % at the first
    # step (the post is 2 dx wide; the liquid then starts moving around it, without a relaxation)
    assert s["wall_post_force_y"][1] == pytest.approx(1000 * 9.81 * 0.01 * 0.02 * 0.01, rel=0.07)


@pytest.mark.parametrize("name,args,expect", [
    ("stl-in-2d", ["-fs_dim", 2, "-fs_tank_shape", "stl", "-fs_tank_stl", "{box}"], ["-fs_tank_stl", "2-D", "-fs_dim 3"]),
    ("file-in-3d", ["-fs_dim", 3, "-fs_tank_shape", "file", "-fs_tank_file", "{walls}"], ["-fs_tank_file", "STL"]),
    ("missing", ["-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "{missing}"], ["missing.stl"]),
    ("open", ["-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "{open}"], ["open.stl", "triangle"]),
    ("inside-out", ["-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "{insideout}"], ["insideout.stl", "inside out"]),
    ("intersecting", ["-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "{overlap}"], ["overlap.stl", "triangle"]),
    ("truncated-binary", ["-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", "{badcount}"], ["badcount.stl", "12"]),
    ("no-stl", ["-fs_dim", 3, "-fs_tank_shape", "stl"], ["-fs_tank_stl"]),
    ("width", ["-fs_dim", 3, "-fs_tank_width", 0], ["-fs_tank_width"]),
    ("element-size", ["-fs_dim", 3, "-fs_walls_element_size", 0], ["-fs_walls_element_size", "0"]),
    ("empty-3d", ["-fs_dim", 3, "-fs_fill", 0], ["-fs_fill 0", "two-dimensional"]),
])
def test_bad_3d_input(tmp_path, name, args, expect):
    """Each bad 3-D input stops the run with an error naming the option or the file (and the triangle)."""
    box = box_facets((0, 0, 0), (0.06, 0.06, 0.03))
    files = {
        "box": ascii_stl({"tank": box}),
        "open": ascii_stl({"tank": box[:-1]}),
        "insideout": ascii_stl({"tank": [(a, c, b) for a, b, c in box]}),
        "overlap": ascii_stl({"tank": box, "post": box_facets((0.05, 0.01, 0.01), (0.08, 0.02, 0.02))}),
        "walls": "wall tank\n0 0\n1 0\n1 1\n0 1\nend\n",
    }
    paths = {k: tmp_path / (k + (".txt" if k == "walls" else ".stl")) for k in files}
    for k, text in files.items():
        paths[k].write_text(text)
    # a binary STL whose header says 12 triangles but holds 11
    import struct
    data = b"binary".ljust(80, b" ") + struct.pack("<I", 12)
    for t in box[:11]:
        data += struct.pack("<12fH", 0, 0, 0, *[c for p in t for c in p], 0)
    paths["badcount"] = tmp_path / "badcount.stl"
    paths["badcount"].write_bytes(data)
    paths["missing"] = tmp_path / "missing.stl"
    args = [str(a).format(**paths) for a in args]
    proc = run_flexslosh(["-fs_case", "tank", "-fs_dx", 0.005, "-fs_output_dir", tmp_path / "o"] + args, cwd=tmp_path,
                         check=False)
    assert_no_crash(proc)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg


def test_python_front_in_3d(tmp_path):
    """The Python front unchanged in 3-D: fields with three components, loads as force and moment
    vectors equal to the time series' columns. The liquid starts at rest and symmetric in the box: its
    load points down, through the middle of the floor (the moments about the origin put it at L/2 and
    W/2); its size swings by +-15 % about the weight in the first steps (the start-up's pressure
    waves, as in 2-D), so it is checked only loosely here (test_trimesh.c checks it at rest)."""
    from flexslosh import Solver

    opts = {"fs_case": "tank", "fs_dim": 3, "fs_tank_length": 0.06, "fs_tank_width": 0.03, "fs_dx": 0.005,
            "fs_output": True, "fs_output_dir": tmp_path, "fs_output_interval": 0, "fs_progress": False}
    with Solver(opts) as s:
        s.step(3)
        assert s.dim == 3
        x, u = s.field("position"), s.field("velocity")
        assert x.shape == (432, 3) and u.shape == (432, 3)
        loads = s.wall_loads()
    csv = read_series(tmp_path)
    assert list(loads) == ["tank"]
    got = np.concatenate([loads["tank"]["force"], loads["tank"]["moment"]])
    want = [csv[f"wall_tank_{c}"][-1] for c in ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")]
    np.testing.assert_allclose(got, want, rtol=1e-9)
    weight = csv["mass"][0] * 9.81
    assert 0.8 * weight < -got[1] < 1.2 * weight
    # symmetric but for the triangulation of the walls (each face's diagonals): measured 8.5e-4 and 1.6e-6
    # of the weight sideways, the load's line within 7.8e-4 and 2.8e-6 of the middle, with the default
    # elements of edge h (2.3e-4, 7e-8, 2.1e-4, 3e-8 with edge h/2: the imprint grows as the edge squared)
    assert abs(got[0]) < 1e-3 * weight and abs(got[2]) < 2e-6 * weight
    assert got[5] / got[1] == pytest.approx(0.03, rel=1e-3)  # M_z = x F_y
    assert -got[3] / got[1] == pytest.approx(0.015, rel=4e-6)  # M_x = -z F_y


def test_box_tank_restart_is_exact(tmp_path):
    """A 3-D tank restarted from its checkpoint at step 10 continues exactly as the uninterrupted run
    (the walls are rebuilt from the options; the checkpoint holds the particles and the time)."""
    args = TANK3 + ["-fs_tank_length", 0.06, "-fs_tank_width", 0.03, "-fs_dx", 0.005, "-ts_max_steps", 20]
    a, b = tmp_path / "a", tmp_path / "b"
    run_flexslosh(args + ["-fs_checkpoint_interval", 10, "-fs_output_dir", a], cwd=tmp_path, timeout=300)
    run_flexslosh(args + ["-fs_restart", a / "checkpoint_000010.h5", "-fs_output_dir", b], cwd=tmp_path, timeout=300)
    x, y = last_snapshot(a), last_snapshot(b)
    assert x.attrs["step"] == y.attrs["step"] == 20
    for f in ("id", "position", "velocity", "density", "pressure"):
        assert np.array_equal(x[f], y[f]), f
    sa, sb = read_series(a), read_series(b)
    for c in ("kinetic_energy", "wall_tank_force_y", "wall_tank_moment_x"):
        assert np.array_equal(sa[c][sa["step"] > 10], sb[c][sb["step"] > 10]), c


def test_liquid_boxes_in_3d(tmp_path):
    """-fs_liquid_box in 3-D (6 numbers a box): the tank case with a column box at the end of the
    extruded 4 x 3 x 2 tank places the particles of the 3-D dam_break case exactly; a box that a wall
    cuts (an STL post through it) is refused, naming the wall and its triangle."""
    c0 = 10 * np.sqrt(2 * 9.81 * 2)
    snaps = {}
    for name, args in (("tank", ["-fs_case", "tank", "-fs_tank_length", 4, "-fs_tank_height", 3, "-fs_tank_width", 2,
                                 "-fs_liquid_box", "0,1,0,2,0,2"]),
                       ("dam", ["-fs_case", "dam_break"])):
        out = tmp_path / name
        run_flexslosh(args + ["-fs_dim", 3, "-fs_dx", 0.25, "-fs_c0", c0, "-ts_max_steps", 0, "-fs_output_dir", out],
                      cwd=tmp_path)
        snaps[name] = last_snapshot(out)
    a, b = snaps["tank"], snaps["dam"]
    assert len(a["id"]) == 4 * 8 * 8 and np.array_equal(a["position"], b["position"])
    assert np.array_equal(a["density"], b["density"])
    stl = tmp_path / "tank.stl"
    stl.write_text(ascii_stl({"tank": box_facets((0, 0, 0), (0.06, 0.06, 0.03)),
                              "post": box_facets((0.025, 0.01, 0.01), (0.035, 0.05, 0.02))}))
    bad = [(["0,0.02,0,0.03,0,0.03,0.01,0.02,0,0.005,0,0.005"], "boxes 0 and 1 overlap"),
           (["0.02,0.04,0,0.03,0,0.012"], "overlaps wall \"post\""),
           (["0,0.02,0,0.03,0,0.05"], "outside the tank"),
           (["0,0.02,0,0.03"], "6 (xmin,xmax,ymin,ymax,zmin,zmax)")]
    for box, expect in bad:
        proc = run_flexslosh(TANK3 + ["-fs_tank_shape", "stl", "-fs_tank_stl", stl, "-fs_dx", 0.005, "-fs_liquid_box",
                                      box[0], "-fs_output_dir", tmp_path / "o"], cwd=tmp_path, check=False)
        assert_no_crash(proc)
        msg = petsc_error_message(proc.stdout)
        assert proc.returncode != 0 and expect in msg and "-fs_liquid_box" in msg, msg
        if "post" in expect:
            assert "triangle" in msg and "tank.stl" in msg, msg


COUPLED = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_tank_width", 0.05, "-fs_dx", 0.01,
           "-fs_output_interval", 0]
COUPLED3 = COUPLED + ["-fs_dim", 3]


def test_coupled_narrow_tank_follows_2d(tmp_path):
    """The seed's rectangular tank on the beam in 3-D, 0.05 m wide (5 particles across, 1,050 particles;
    the 2-D run's loads per unit width times the same width): the beam's tip follows the 2-D run within
    0.5 % of the initial deflection over the first 0.05 s (measured 0.1 %: the liquid moves in the beam's
    plane, the end walls add only their free-slip boundary layer), the loads the beam does not carry
    (force_z, moment_x, moment_y) stay at the walls' triangulation's imprint, far below the weight
    (measured 1.9e-4, 5e-6 and 2.3e-3 m of it with elements of edge h; 5e-6, 1.3e-7 and 3.7e-4 m with h/2),
    and the 3-D energy budget closes as the 2-D one (liquid residual over the liquid's energy: measured
    5.2e-4 against 8.5e-4 in 2-D)."""
    out3, out2 = tmp_path / "c3", tmp_path / "c2"
    run_flexslosh(COUPLED3 + ["-ts_max_time", 0.05, "-fs_output_dir", out3], cwd=tmp_path, timeout=600)
    run_flexslosh(COUPLED + ["-ts_max_time", 0.05, "-fs_output_dir", out2], cwd=tmp_path, timeout=600)
    s3, s2 = read_series(out3), read_series(out2)
    t = np.linspace(0.005, 0.05, 10)
    d3, d2 = np.interp(t, s3["time"], s3["tip_displacement"]), np.interp(t, s2["time"], s2["tip_displacement"])
    assert np.abs(d3 - d2).max() < 0.005 * 0.04, (d3, d2)
    weight = 1000 * 9.81 * 0.7 * 0.03 * 0.05
    for c, tol in (("load_force_z", 3e-4), ("load_moment_x", 1e-5), ("load_moment_y", 3e-3)):
        assert np.abs(s3[c]).max() < tol * weight, c
    e3 = np.genfromtxt(out3 / "energy.csv", delimiter=",", names=True)
    e2 = np.genfromtxt(out2 / "energy.csv", delimiter=",", names=True)
    rel3 = np.abs(e3["residual_liquid"]).max() / e3["E_liquid"][0]
    rel2 = np.abs(e2["residual_liquid"]).max() / e2["E_liquid"][0]
    assert rel3 < 1e-3 and rel3 < 1.5 * rel2, (rel3, rel2)
    assert np.abs(e3["residual_total"]).max() < 1e-5 * e3["E_total"][0]


def test_coupled_3d_ranks_and_restart(tmp_path):
    """The coupled 3-D tank: 20 steps on 3 ranks with a checkpoint at step 10 give the 1-rank run's
    particles and tip motion to round-off, and the run restarted from that checkpoint on 1 rank agrees
    with both."""
    args = COUPLED3 + ["-ts_max_steps", 20]
    a, b, c = tmp_path / "r1", tmp_path / "r3", tmp_path / "restart"
    run_flexslosh(args + ["-fs_output_dir", a], cwd=tmp_path, timeout=600)
    run_flexslosh(args + ["-fs_checkpoint_interval", 10, "-fs_output_dir", b], nranks=3, cwd=tmp_path, timeout=600)
    run_flexslosh(args + ["-fs_restart", b / "checkpoint_000010.h5", "-fs_output_dir", c], cwd=tmp_path, timeout=600)
    x = last_snapshot(a)
    for other in (b, c):
        y = last_snapshot(other)
        assert y.attrs["step"] == 20 and np.array_equal(x["id"], y["id"])
        for f in ("position", "velocity", "density"):
            assert rel_max_diff(x[f], y[f]) < 1e-10, (other, f)
        sa, so = read_series(a), read_series(other)
        assert abs(sa["tip_displacement"][-1] - so["tip_displacement"][-1]) < 1e-12


def resting_3d(tmp_path, label, args, T_end):
    """Liquid at rest 0.03 m deep in the 3-D tank of args, 0.02 m wide, with cases/hydrostatic_3d.opts's settings
    (c0 8 m/s, a delta floor of 0.1 with the hydrostatic correction, a start-up relaxation of 0.1 s) to
    T = t sqrt(g/H) = T_end on 2 ranks, a snapshot every T = 1; returns the rms speed over sqrt(gH) of the
    snapshots from T = 1 on and the last snapshot."""
    from conftest import read_snapshot, snapshot_files

    H, g = 0.03, 9.81
    tscale = np.sqrt(H / g)
    out = tmp_path / label
    run_flexslosh(TANK3 + AT_REST + ["-fs_tank_width", 0.02, "-ts_max_time", T_end * tscale, "-fs_output_interval", tscale,
                                     "-fs_output_dir", out] + args, nranks=2, cwd=tmp_path, timeout=600)
    snaps = [read_snapshot(f) for f in snapshot_files(out)][1:]
    assert len(snaps) == T_end
    rms = np.array([np.sqrt(np.mean(np.sum(sn["velocity"] ** 2, axis=1))) / np.sqrt(g * H) for sn in snaps])
    return rms, snaps[-1]


def test_lifted_baffles_3d_as_quiet_as_the_box(tmp_path):
    """Baffles lifted 5 mm off the floor in 3-D (two compartments 0.1 m long, 0.02 m wide, dx = 4 mm, 2,005
    particles), liquid at rest, with -fs_walls_visibility all: no fluid pair is cut through a wall and every
    element within the support counts, so the baffles' lower corners inside the liquid bound nothing. The liquid
    moves about as much as in the box of the same size without baffles, and a third as much as with the default
    `cut`, whose pairs cut at the corners push it. Measured to T = 4 (T = 1, 2, 3, 4): rms speed 0.0056, 0.0110,
    0.0155, 0.0176 sqrt(gH) (all), 0.0053, 0.0096, 0.0130, 0.0139 (the box), 0.0171, 0.0375, 0.0438, 0.0482
    (cut); the test runs to T = 2. At dx = 2.5 mm to T = 20 (docs/walls.md) the lifted baffles and the box
    agree to 0.001 sqrt(gH) at every T (0.014 at T = 20), and in pressure and load: the motion left is the
    coarse narrow 3-D tank's at rest, not the baffles'."""
    base = ["-fs_tank_compartments", 2, "-fs_tank_baffle_gap", 0.005, "-fs_dx", 0.004]
    rms_all, last = resting_3d(tmp_path, "all", ["-fs_tank_shape", "baffled", "-fs_walls_visibility", "all"] + base, 2)
    rms_box, _ = resting_3d(tmp_path, "box", ["-fs_tank_shape", "rectangular", "-fs_tank_length", 0.205,
                                              "-fs_dx", 0.004], 2)
    rms_cut, _ = resting_3d(tmp_path, "cut", ["-fs_tank_shape", "baffled"] + base, 2)
    x = last["position"]
    assert not ((x[:, 0] > 0.1) & (x[:, 0] < 0.105) & (x[:, 1] > 0.005)).any()  # none in the baffle
    assert (rms_all < 1.25 * rms_box).all(), (rms_all, rms_box)
    assert (rms_cut > 2.5 * rms_all).all(), (rms_cut, rms_all)
    assert rms_all[-1] < 0.012, rms_all


@pytest.mark.parametrize("case,steps", [("dam_break_3d", 40), ("standing_wave_3d", 20)])
def test_3d_validation_cases_ranks_agree(tmp_path, case, steps):
    """The 3-D validation cases of the report beside the box and the baffled tanks above: the dam break (a/dx = 10,
    4,000 particles; the column collapsing, the front moving) and the standing wave (1, 1) (h/dx = 10, 2,000
    particles) give the same particles on 1 and 3 ranks."""
    extra = ["-fs_dx", 0.1] if case == "standing_wave_3d" else []
    a = one_and_three_ranks(tmp_path, ["-options_file", REPO_ROOT / "cases" / f"{case}.opts", "-ts_max_steps", steps,
                                       "-fs_output_interval", 0] + extra, ("position", "velocity", "density", "pressure"), 600)
    # it moves: the collapse faster than 0.1 sqrt(g a); the wave (g = h = 1) at 0.050 after 20 steps (A omega = 0.094)
    assert np.abs(a["velocity"]).max() > (0.1 * np.sqrt(9.81 * 0.1) if case == "dam_break_3d" else 0.03)
    if case == "standing_wave_3d":  # the mode's amplitude, a sum over all ranks' particles, to round-off
        s1, s3 = read_series(tmp_path / "r1"), read_series(tmp_path / "r3")
        assert len(s1["mode_amplitude"]) > 2 and np.ptp(s1["mode_amplitude"]) > 0.01
        assert np.abs(s1["mode_amplitude"] - s3["mode_amplitude"]).max() < 1e-10


def test_wall_repulsion_holds_the_first_row(tmp_path):
    """A 3-D box at rest (0.036 x 0.018 m, 0.03 m of water, dx = 3 mm, 720 particles, the hydrostatic case's
    settings) to t = 0.3 s: without -fs_walls_repulsion the floor's first row (started dx/2 above the floor)
    spreads and its particles reach the bounce distance (0.1 dx), since one particle of a 3-D first row is pushed
    toward the wall by its own pressure down to 0.2 dx (docs/walls.md); with -fs_walls_repulsion 0.5 the row stays
    a row and the liquid moves less. Measured (the row's height: standard deviation / lowest, in dx; the rms speed
    over sqrt(gH)): without 0.280 / 0.106 / 0.0143, with 0.029 / 0.431 / 0.0059."""
    from concurrent.futures import ThreadPoolExecutor

    from conftest import read_snapshot, snapshot_files

    dx, H = 0.003, 0.03

    def rest(label, extra):
        out = tmp_path / label
        run_flexslosh(TANK3 + AT_REST + ["-fs_tank_shape", "rectangular", "-fs_tank_length", 0.036, "-fs_tank_height", 0.06,
                                         "-fs_tank_width", 0.018, "-fs_fill", 0.5, "-fs_dx", dx, "-ts_max_time", 0.3,
                                         "-fs_output_interval", 0.3, "-fs_output_dir", out] + extra, cwd=tmp_path, timeout=600)
        files = snapshot_files(out)
        first, last = read_snapshot(files[0]), read_snapshot(files[-1])
        assert len(files) == 2 and np.array_equal(first["id"], last["id"])  # t = 0 and 0.3, sorted by id
        y = last["position"][first["position"][:, 1] < dx, 1] / dx
        return y.std(), y.min(), np.sqrt(np.mean(np.sum(last["velocity"] ** 2, axis=1))) / np.sqrt(9.81 * H)

    with ThreadPoolExecutor(2) as ex:
        off, on = ex.map(lambda a: rest(*a), [("off", []), ("on", ["-fs_walls_repulsion", 0.5])])
    assert off[0] > 0.2 and off[1] < 0.2 and off[2] > 0.012, off
    assert on[0] < 0.04 and on[1] > 0.4 and on[2] < 0.0075, on

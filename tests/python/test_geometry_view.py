"""-fs_geometry_view: the set-up as files (geometry.png, walls.h5 + walls.xdmf, the step-0 snapshot),
written at set-up into <output_dir>/geometry (a run's results in <output_dir> stay as they are), after
which the run stops. The PNG is read with matplotlib, independently of the
writer (libpng). In 3-D the picture holds three views (front, top below it, side to its right) and
the walls' files hold the input triangles."""
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import read_summary, run_flexslosh, snapshot_files

DX = 0.004
BAFFLED = ["-fs_case", "tank", "-fs_tank_shape", "baffled", "-fs_tank_baffle_gap", 0.005, "-fs_dx", DX, "-fs_geometry_view"]

# the picture's layout and colours (src/solver/geometryview.c; the walls' palette FSImagePalette in
# src/io/png.c)
SIZE, MARGIN, GAP = 1600, 20, 40
WHITE = (255, 255, 255)
PARTICLE = (30, 90, 220)
WALLS = [(40, 40, 40), (170, 30, 30)]  # wall 0 (the tank), wall 1 (the baffles)

# the seed's baffled tank: 7 compartments of 0.1 m, 0.06 m high, baffles 5 mm thick, here lifted 5 mm
# off the floor (to 50 mm) so that they are free-standing polygons, a wall of their own (on the floor,
# the case's default, they are notches of the tank's outline)
L, H = 0.73, 0.06


def read_png(path):
    """(width, height, pixels as a (height, width, 3) uint8 array) of an 8-bit RGB PNG, read with
    matplotlib (Pillow decodes it; 8-bit samples come back as multiples of 1/255)."""
    from matplotlib import image

    px = image.imread(path, format="png")  # float32 in [0, 1]
    assert px.ndim == 3 and px.shape[2] == 3, f"expected RGB without alpha, got shape {px.shape}"
    px = np.rint(px * 255).astype(np.uint8)
    return px.shape[1], px.shape[0], px


def mask(pixels, colour):
    return (pixels == np.array(colour, dtype=np.uint8)).all(axis=2)


def expected_segments(dx):
    """FSWallsDiscretize's counts (tank, baffles): every polygon edge in ceil(length/dx) segments."""
    n = lambda length: math.ceil(length / dx - 1e-9)
    return 2 * n(L) + 2 * n(H), 6 * (2 * n(0.045) + 2 * n(0.005))


@pytest.fixture(scope="module")
def baffled(tmp_path_factory):
    out = tmp_path_factory.mktemp("geometry") / "o"
    proc = run_flexslosh(BAFFLED + ["-fs_output_dir", out], cwd=out.parent, timeout=120)
    return out / "geometry", proc


def test_png_is_valid_and_shows_the_set_up(baffled):
    out, proc = baffled
    assert f"{out}/geometry.png" in proc.stdout and f"{out}/walls.xdmf" in proc.stdout, proc.stdout
    assert "stopping after set-up" in proc.stdout
    width, height, px = read_png(out / "geometry.png")
    # 1600 px on the longer side, the tank's aspect ratio inside the margin
    assert width == SIZE
    assert abs(height - (2 * MARGIN + 1 + (SIZE - 1 - 2 * MARGIN) * H / L)) <= 2, height
    white, part = mask(px, WHITE), mask(px, PARTICLE)
    walls = [mask(px, c) for c in WALLS]
    assert white.mean() > 0.5  # white background
    assert part.sum() > 1000 and walls[0].sum() > 3000 and walls[1].sum() > 500, (part.sum(), [w.sum() for w in walls])
    assert (white | part | walls[0] | walls[1]).all()  # nothing else is drawn
    # the tank's outline (2 px lines) fills the picture inside the margin; its ticks (7 px) stand
    # outside it, on the side away from the liquid
    sides = np.nonzero(walls[0].sum(axis=0) > (height - 2 * MARGIN) / 2)[0]
    lids = np.nonzero(walls[0].sum(axis=1) > (width - 2 * MARGIN) / 2)[0]
    assert abs(sides.min() - MARGIN) <= 1 and abs(sides.max() - (width - 1 - MARGIN)) <= 1, sides
    assert abs(lids.min() - MARGIN) <= 1 and abs(lids.max() - (height - 1 - MARGIN)) <= 1, lids
    ys, xs = np.nonzero(walls[0])
    assert MARGIN - 9 <= xs.min() < MARGIN - 3 and MARGIN - 9 <= ys.min() < MARGIN - 3
    inner = walls[0][MARGIN + 3:height - MARGIN - 3, MARGIN + 3:width - MARGIN - 3]
    assert not inner.any(), "a tick of the tank points into the liquid"
    # the liquid fills the lower half (-fs_fill 0.5): particles below the middle, between the walls
    ys, xs = np.nonzero(part)
    middle = MARGIN + (height - 1 - 2 * MARGIN) / 2
    assert ys.min() > middle - 4 and ys.max() < height - MARGIN and MARGIN < xs.min() and xs.max() < width - MARGIN
    # the baffles: 6 columns of wall colour 1, each within its rectangle (their ticks point into the
    # baffle, away from the liquid around it)
    cols = np.nonzero(walls[1].any(axis=0))[0]
    assert 1 + np.count_nonzero(np.diff(cols) > 1) == 6
    scale = (SIZE - 1 - 2 * MARGIN) / L
    box = np.zeros_like(walls[1])
    for k in range(1, 7):
        x0 = 0.1 * k + 0.005 * (k - 1)
        i0, i1 = int(MARGIN + x0 * scale) - 2, int(MARGIN + (x0 + 0.005) * scale) + 3
        j0, j1 = int(height - 1 - MARGIN - 0.05 * scale) - 2, int(height - 1 - MARGIN - 0.005 * scale) + 3
        box[j0:j1, i0:i1] = True
    assert not (walls[1] & ~box).any()


def test_walls_h5_and_xdmf(baffled):
    h5py = pytest.importorskip("h5py")
    out, _ = baffled
    ntank, nbaffles = expected_segments(DX)
    nseg = ntank + nbaffles
    with h5py.File(out / "walls.h5", "r") as f:
        g = f["walls"]
        assert g.attrs["nsegments"] == nseg and g.attrs["nwalls"] == 2
        names = g.attrs["names"]
        assert (names.decode() if isinstance(names, bytes) else names) == "tank,baffles"
        pts, conn, wall, nrm, length = (g[k][...] for k in ("points", "connectivity", "wall", "normal", "length"))
    assert pts.shape == (2 * nseg, 2) and conn.shape == (nseg, 2) and wall.shape == (nseg,) and nrm.shape == (nseg, 2)
    assert (conn == np.arange(2 * nseg).reshape(nseg, 2)).all()
    assert (wall == 0).sum() == ntank and (wall == 1).sum() == nbaffles
    p0, p1 = pts[0::2], pts[1::2]
    assert np.allclose(np.linalg.norm(p1 - p0, axis=1), length) and (length <= DX + 1e-12).all()
    assert np.allclose(np.linalg.norm(nrm, axis=1), 1)
    # the normal of p0 -> p1 is (dy, -dx)/|p1 - p0|: out of the liquid
    d = (p1 - p0) / length[:, None]
    assert np.allclose(nrm, np.stack([d[:, 1], -d[:, 0]], axis=1))
    assert np.isclose(pts[:, 0].min(), 0) and np.isclose(pts[:, 0].max(), L) and np.isclose(pts[:, 1].max(), H)
    xdmf = (out / "walls.xdmf").read_text()
    for s in ('TopologyType="Polyline"', f'NumberOfElements="{nseg}"', 'NodesPerElement="2"', "walls.h5:/walls/connectivity",
              "walls.h5:/walls/points", 'GeometryType="XY"', "walls.h5:/walls/wall", "walls.h5:/walls/normal", 'Center="Cell"'):
        assert s in xdmf, s


def test_step0_snapshot_and_no_steps(baffled):
    out, _ = baffled
    files = snapshot_files(out)
    assert [f.rsplit("/", 1)[1] for f in files] == ["snapshot_000000.h5"]
    assert "snapshot_000000.h5:/particles/position" in (out / "particles.xdmf").read_text()
    assert read_summary(out)["steps"] == 0
    assert not list(out.glob("*.tmp"))


def test_two_ranks_give_the_same_png(baffled, tmp_path):
    out1, _ = baffled
    out2 = tmp_path / "o2"
    run_flexslosh(BAFFLED + ["-fs_output_dir", out2], nranks=2, cwd=tmp_path, timeout=120)
    assert (out2 / "geometry" / "geometry.png").read_bytes() == (out1 / "geometry.png").read_bytes()


def test_case_without_walls(tmp_path):
    """Taylor-Green: no walls, the picture shows the periodic box's particles; no walls.xdmf."""
    out = tmp_path / "o"
    proc = run_flexslosh(["-fs_case", "taylor_green", "-fs_dx", 0.02, "-fs_geometry_view", "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    assert "no walls" in proc.stdout
    out = out / "geometry"
    width, height, px = read_png(out / "geometry.png")
    assert width == height == SIZE
    assert mask(px, PARTICLE).sum() > 2500 and (mask(px, WHITE) | mask(px, PARTICLE)).all()
    assert not (out / "walls.xdmf").exists()


def test_max_steps_zero_writes_one_snapshot(tmp_path):
    """-ts_max_steps 0 (without -fs_geometry_view) stops after set-up with a single snapshot at t = 0."""
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "tank", "-fs_dx", 0.006, "-ts_max_steps", 0, "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    assert len(snapshot_files(out)) == 1
    assert not (out / "geometry.png").exists()


def test_single_wall_name(tmp_path):
    """The rectangular tank's one wall is named "tank" in walls.h5 and walls.xdmf (PETSc 3.18's
    PetscStrlcat cut it to "ta")."""
    h5py = pytest.importorskip("h5py")
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "tank", "-fs_dx", 0.006, "-fs_geometry_view", "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    with h5py.File(out / "geometry" / "walls.h5", "r") as f:
        names = f["walls"].attrs["names"]
    assert (names.decode() if isinstance(names, bytes) else names) == "tank"
    assert 'Value="tank"' in (out / "geometry" / "walls.xdmf").read_text()


def test_a_runs_results_are_not_touched(tmp_path):
    """The geometry view in the output directory of a finished run (the default output/<case> is the same for
    both) truncated its CSVs and rewrote its snapshot 0 and summary: it now writes into <output_dir>/geometry only."""
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "tank", "-fs_dx", 0.02, "-ts_max_steps", 3, "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    before = {f.name: f.read_bytes() for f in out.iterdir()}
    assert {"timeseries.csv", "summary.json", "snapshot_000000.h5", "walls.h5"} <= set(before)
    proc = run_flexslosh(["-fs_case", "tank", "-fs_dx", 0.01, "-fs_geometry_view", "-fs_output_dir", out], cwd=tmp_path,
                         timeout=120)
    assert f"{out}/geometry/geometry.png" in proc.stdout, proc.stdout
    assert {f.name: f.read_bytes() for f in out.iterdir() if f.name != "geometry"} == before
    assert read_summary(out / "geometry")["steps"] == 0 and read_summary(out / "geometry")["dx"] == 0.01


# ---------------------------------------------------------------- 3-D: the rectangular tank extruded
# across its width, L x H x W (x, y, z) with three different lengths so that every view's aspect
# ratio tells its axes apart; half full (-fs_fill 0.5), about 1800 particles

L3, H3, W3, DX3 = 0.3, 0.12, 0.1, 0.01
TANK3 = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_length", L3, "-fs_tank_height", H3, "-fs_tank_width", W3,
         "-fs_dx", DX3, "-fs_geometry_view"]


@pytest.fixture(scope="module")
def tank3(tmp_path_factory):
    out = tmp_path_factory.mktemp("geometry3") / "o"
    proc = run_flexslosh(TANK3 + ["-fs_output_dir", out], cwd=out.parent, timeout=120)
    return out / "geometry", proc


def runs(flags, min_gap):
    """[(first, last)] of the runs of True in flags, runs less than min_gap apart merged."""
    idx = np.nonzero(flags)[0]
    if idx.size == 0:
        return []
    cuts = np.nonzero(np.diff(idx) > min_gap)[0]
    starts = np.concatenate([[idx[0]], idx[cuts + 1]])
    ends = np.concatenate([idx[cuts], [idx[-1]]])
    return list(zip(starts.tolist(), ends.tolist()))


def views(px):
    """The three views of a 3-D picture, found in it (not from the layout's formulas): the blocks of
    non-white columns and rows, separated by at least half the gap of white (the walls' ticks reach
    7 pixels into it). Returns {"front", "top", "side"}: (rows, cols) slices of each block."""
    ink = ~mask(px, WHITE)
    cols, rows = runs(ink.any(axis=0), GAP // 2), runs(ink.any(axis=1), GAP // 2)
    assert len(cols) == 2 and len(rows) == 2, (cols, rows)
    block = lambda r, c: (slice(rows[r][0], rows[r][1] + 1), slice(cols[c][0], cols[c][1] + 1))
    # first-angle layout: front top left, top view below it, side view to its right, bottom right empty
    assert not ink[block(1, 1)].any(), "the bottom right corner is not white"
    return {"front": block(0, 0), "top": block(1, 0), "side": block(0, 1)}


def outline(wall):
    """(width, height, (first column, last column, first row, last row)) in pixels of a view's box:
    between its extreme columns and rows of wall pixels that cross at least half the view (the box's
    edges; not the ticks, nor the triangles' diagonals)."""
    h, w = wall.shape
    cols = np.nonzero(wall.sum(axis=0) > h / 2)[0]
    rows = np.nonzero(wall.sum(axis=1) > w / 2)[0]
    assert cols.size >= 2 and rows.size >= 2, (cols, rows)
    return cols.max() - cols.min(), rows.max() - rows.min(), (cols.min(), cols.max(), rows.min(), rows.max())


def test_3d_png_three_views(tank3):
    out, proc = tank3
    assert f"{out}/geometry.png" in proc.stdout and "top view below it" in proc.stdout, proc.stdout
    assert "stopping after set-up" in proc.stdout
    width, height, px = read_png(out / "geometry.png")
    # the longer side is 1600 px: here the width, front + gap + side (L + W against H + W)
    assert width == SIZE and height < SIZE, (width, height)
    white, part, wall = mask(px, WHITE), mask(px, PARTICLE), mask(px, WALLS[0])
    assert (white | part | wall).all()  # nothing else is drawn: one wall (the tank), the particles
    v = views(px)
    # the front view (x, y) is L x H, the top view (x, z) L x W, the side view (z, y) W x H: the same
    # scale in all three (each box's extent to 2 pixels, the 2-px walls)
    scale = (SIZE - 1 - 2 * MARGIN - GAP) / max(L3 + W3, H3 + W3)
    sizes = {"front": (L3, H3), "top": (L3, W3), "side": (W3, H3)}
    boxes = {}
    for name, (a, b) in sizes.items():
        pw, ph, boxes[name] = outline(wall[v[name]])
        assert abs(pw - a * scale) <= 2 and abs(ph - b * scale) <= 2, (name, pw, ph, a * scale, b * scale)
        assert abs(pw / ph - a / b) < 0.03 * a / b, (name, pw / ph, a / b)
    # the views line up: the top view under the front one (same columns), the side view beside it
    # (same rows)
    c0 = v["front"][1].start, v["top"][1].start
    assert abs((c0[0] + boxes["front"][0]) - (c0[1] + boxes["top"][0])) <= 1
    r0 = v["front"][0].start, v["side"][0].start
    assert abs((r0[0] + boxes["front"][2]) - (r0[1] + boxes["side"][2])) <= 1
    # particles in every view, inside its box; half full: in the lower half of the front and side
    # views, over the whole of the top view
    for name in ("front", "top", "side"):
        p = part[v[name]]
        i0, i1, j0, j1 = boxes[name]
        ys, xs = np.nonzero(p)
        assert p.sum() > 1000, (name, p.sum())
        assert i0 < xs.min() and xs.max() < i1 + 2 and j0 < ys.min() and ys.max() < j1 + 2, name
        middle = (j0 + j1) / 2
        if name == "top":
            assert ys.min() < j0 + 0.2 * (j1 - j0) and ys.max() > j1 - 0.2 * (j1 - j0), name
        else:
            assert ys.min() > middle - 4 and ys.max() > j1 - 0.2 * (j1 - j0), name


def test_3d_walls_h5_and_xdmf(tank3):
    h5py = pytest.importorskip("h5py")
    out, proc = tank3
    assert f"{out}/walls.xdmf" in proc.stdout and "triangles as given" in proc.stdout, proc.stdout
    with h5py.File(out / "walls.h5", "r") as f:
        g = f["walls"]
        ntri = int(g.attrs["ntriangles"])
        names = g.attrs["names"]
        assert int(g.attrs["nwalls"]) == 1 and (names.decode() if isinstance(names, bytes) else names) == "tank"
        pts, conn, wall, nrm, area = (g[k][...] for k in ("points", "connectivity", "wall", "normal", "area"))
    assert ntri >= 12  # two triangles at least on each of the box's 6 faces
    assert pts.shape == (3 * ntri, 3) and conn.shape == (ntri, 3) and wall.shape == (ntri,)
    assert nrm.shape == (ntri, 3) and area.shape == (ntri,)
    assert (conn == np.arange(3 * ntri).reshape(ntri, 3)).all() and (wall == 0).all()
    a, b, c = pts[0::3], pts[1::3], pts[2::3]
    cross = np.cross(b - a, c - a)
    assert np.allclose(area, 0.5 * np.linalg.norm(cross, axis=1), rtol=1e-12, atol=0)
    assert np.allclose(nrm, cross / np.linalg.norm(cross, axis=1)[:, None], rtol=0, atol=1e-12)
    # the box, its surface, and its normals out of the liquid (out of the box)
    assert np.allclose(pts.min(axis=0), 0, atol=1e-12) and np.allclose(pts.max(axis=0), [L3, H3, W3], rtol=1e-12)
    surface = 2 * (L3 * H3 + L3 * W3 + H3 * W3)
    assert abs(area.sum() - surface) <= 1e-12 * surface, (area.sum(), surface)
    centroid = (a + b + c) / 3
    assert (np.einsum("ij,ij->i", nrm, centroid - np.array([L3, H3, W3]) / 2) > 0).all()
    # walls.xdmf: valid XML, triangles of the points above with the cell attributes
    root = ET.parse(out / "walls.xdmf").getroot()
    grid = root.find("Domain/Grid")
    topo, geom = grid.find("Topology"), grid.find("Geometry")
    assert topo.get("TopologyType") == "Triangle" and int(topo.get("NumberOfElements")) == ntri
    assert topo.get("NodesPerElement") == "3" and topo.find("DataItem").get("Dimensions") == f"{ntri} 3"
    assert topo.find("DataItem").text.strip() == "walls.h5:/walls/connectivity"
    assert geom.get("GeometryType") == "XYZ" and geom.find("DataItem").get("Dimensions") == f"{3 * ntri} 3"
    assert geom.find("DataItem").text.strip() == "walls.h5:/walls/points"
    attrs = {e.get("Name"): e for e in grid.findall("Attribute")}
    assert set(attrs) == {"wall", "normal", "area"}
    for name, dims in (("wall", f"{ntri}"), ("normal", f"{ntri} 3"), ("area", f"{ntri}")):
        assert attrs[name].get("Center") == "Cell" and attrs[name].find("DataItem").get("Dimensions") == dims
        assert attrs[name].find("DataItem").text.strip() == f"walls.h5:/walls/{name}"
    assert not list(out.glob("*.tmp"))


def test_3d_two_ranks_give_the_same_png(tank3, tmp_path):
    out1, _ = tank3
    out2 = tmp_path / "o2"
    run_flexslosh(TANK3 + ["-fs_output_dir", out2], nranks=2, cwd=tmp_path, timeout=120)
    assert (out2 / "geometry" / "geometry.png").read_bytes() == (out1 / "geometry.png").read_bytes()


def test_3d_views_orientation(tmp_path):
    """Which way each view looks, with a tank that is not symmetric: the corner tetrahedron x/L + y/H
    + z/W <= 1 (an ASCII STL file, normals out), half full. The top view is seen from above, z growing
    downwards (the back z = 0 next to the front view): its liquid, the triangle x/L + z/W <= 1, lies
    to the upper left. The side view is seen from the x = 0 end, z to the right: its liquid lies to the
    left. Measured by the particles' centre against the centre of the walls' pixels in each view."""
    L, H, W = 0.3, 0.12, 0.1
    O, X, Y, Z = (0, 0, 0), (L, 0, 0), (0, H, 0), (0, 0, W)
    facets = [(O, X, Z), (O, Y, X), (O, Z, Y), (X, Y, Z)]  # floor, back, x = 0 end, the slanted face
    lines = ["solid corner"]
    for tri in facets:
        a, b, c = (np.array(v, dtype=float) for v in tri)
        n = np.cross(b - a, c - a)
        lines += [f"facet normal {' '.join(f'{x:.17g}' for x in n / np.linalg.norm(n))}", "outer loop"]
        lines += [f"vertex {' '.join(f'{x:.17g}' for x in v)}" for v in (a, b, c)]
        lines += ["endloop", "endfacet"]
    stl = tmp_path / "corner.stl"
    stl.write_text("\n".join(lines + ["endsolid corner"]) + "\n")
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", stl, "-fs_dx", 0.005,
                   "-fs_geometry_view", "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    _, _, px = read_png(out / "geometry" / "geometry.png")
    part, wall = mask(px, PARTICLE), mask(px, WALLS[0])
    v = views(px)
    centre = {}
    for name in ("front", "top", "side"):
        (py, px_), (wy, wx) = np.nonzero(part[v[name]]), np.nonzero(wall[v[name]])
        assert py.size > 100, name
        # the particles' centre relative to the middle of the walls, in units of the walls' extent
        centre[name] = ((px_.mean() - (wx.min() + wx.max()) / 2) / (wx.max() - wx.min()),
                        (py.mean() - (wy.min() + wy.max()) / 2) / (wy.max() - wy.min()))
    # pixel y grows downwards: a negative value is above the middle
    assert centre["front"][0] < -0.05 and centre["front"][1] > 0.05, centre  # left, low (y up)
    assert centre["top"][0] < -0.05 and centre["top"][1] < -0.05, centre  # left, up (z down)
    assert centre["side"][0] < -0.05 and centre["side"][1] > 0.05, centre  # left (z right), low

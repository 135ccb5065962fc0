"""-fs_geometry_view: the set-up as files (geometry.png, walls.h5 + walls.xdmf, the step-0 snapshot),
written at set-up, after which the run stops. The PNG is read with matplotlib, independently of the
writer (libpng)."""
import math

import numpy as np
import pytest

from conftest import read_summary, run_flexslosh, snapshot_files

DX = 0.004
BAFFLED = ["-fs_case", "tank", "-fs_tank_shape", "baffled", "-fs_tank_baffle_gap", 0.005, "-fs_dx", DX, "-fs_geometry_view"]

# the picture's layout and colours (src/boundary/impls/polygon/geometryview.c)
SIZE, MARGIN = 1600, 20
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
    return out, proc


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
    assert (out2 / "geometry.png").read_bytes() == (out1 / "geometry.png").read_bytes()


def test_case_without_walls(tmp_path):
    """Taylor-Green: no walls, the picture shows the periodic box's particles; no walls.xdmf."""
    out = tmp_path / "o"
    proc = run_flexslosh(["-fs_case", "taylor_green", "-fs_dx", 0.02, "-fs_geometry_view", "-fs_output_dir", out], cwd=tmp_path, timeout=120)
    assert "no walls" in proc.stdout
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

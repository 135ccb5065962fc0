"""The liquid's volume and mass at the start (issue 33): in tanks whose walls are not along the axes the lattice
leaves out points near the walls, and the masses are fitted so that the liquid weighs the integral of its
hydrostatic density over the exact volume below the fill level; where the lattice fits (walls along the axes) its
masses are kept. The exact masses are computed here independently, from the shapes' cross-sections. Set-up only
(-ts_max_steps 0): the step-0 snapshot and time series. The lattice's fit is checked with -fs_fill_packing lattice
(auto relaxes these tanks: test_packing.py)."""
import math

import numpy as np
import pytest

from conftest import last_snapshot, read_series, read_summary, run_flexslosh

RHO0, C0, G = 1000.0, 20.0, 9.81  # the tank case's defaults
K = G / C0**2  # rho = rho0 (1 + K (ysurf - y)), the hydrostatic start
L, H, W = 0.06, 0.06, 0.03  # the 3-D tank (x, y, z), 50 % full
DX = 0.005


def hexahedron(v):
    """The 12 triangles of a deformed box, its vertices in box_facets' order (test_walls_3d.py), outward normals."""
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]
    return [t for a, b, c, d in quads for t in ((v[a], v[b], v[c]), (v[a], v[c], v[d]))]


def box_vertices(x0, x1, y0, y1, z0, z1):
    return [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]


def ascii_stl(tris):
    out = ["solid tank"]
    for t in tris:
        out += ["facet normal 0 0 0", "outer loop"] + [f"vertex {p[0]!r} {p[1]!r} {p[2]!r}" for p in t] + ["endloop", "endfacet"]
    return "\n".join(out + ["endsolid tank"]) + "\n"


def rotated(v, axis, deg, centre):
    """The points v turned by deg degrees about the axis (1: y, vertical; 2: z, horizontal) through centre."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    i, j = (2, 0) if axis == 1 else (0, 1)  # the plane turned: z-x about y, x-y about z
    out = []
    for p in v:
        p, q = list(p), [p[k] - centre[k] for k in range(3)]
        p[i], p[j] = centre[i] + c * q[i] - s * q[j], centre[j] + s * q[i] + c * q[j]
        out.append(tuple(p))
    return out


def simpson(f, a, b):
    """Simpson's rule: exact for the cubics integrated here."""
    return (b - a) / 6 * (f(a) + 4 * f((a + b) / 2) + f(b))


def clipped_below(poly, ys):
    """The polygon (counter-clockwise (x, y) vertices) below the line y = ys: its area and the integral of
    ys - y over it (the shoelace formulas)."""
    out = []
    for k, p in enumerate(poly):
        q = poly[(k + 1) % len(poly)]
        if p[1] <= ys:
            out.append(p)
        if (p[1] <= ys) != (q[1] <= ys):
            t = (ys - p[1]) / (q[1] - p[1])
            out.append((p[0] + t * (q[0] - p[0]), ys))
    area = my = 0.0
    for k, p in enumerate(out):
        q = out[(k + 1) % len(out)]
        cr = p[0] * q[1] - q[0] * p[1]
        area += cr / 2
        my += (p[1] + q[1]) * cr / 6
    return area, ys * area - my


def prism_mass(area, moment, depth):
    """rho0 times the integral of 1 + K (ysurf - y) over a prism of the given cross-section and depth."""
    return RHO0 * depth * (area + K * moment)


def column_mass(a, ys):
    """rho0 times the integral of a(y) (1 + K (ys - y)) from 0 to ys, a(y) the horizontal section (at most quadratic)."""
    return RHO0 * simpson(lambda y: a(y) * (1 + K * (ys - y)), 0, ys)


def tank_3d(shape):
    """The STL triangles of a 3-D tank and the mass of its liquid at 50 % of its height."""
    box = box_vertices(0, L, 0, H, 0, W)
    if shape == "box":
        return hexahedron(box), column_mass(lambda y: L * W, H / 2)
    if shape == "rotated":  # 30 degrees about the vertical axis: every horizontal section the same L x W
        return hexahedron(rotated(box, 1, 30, (L / 2, 0, W / 2))), column_mass(lambda y: L * W, H / 2)
    if shape == "tilted":  # 20 degrees about z: the x-y section a rectangle turned, the fill half its height
        v = rotated(box, 2, 20, (L / 2, H / 2, 0))
        rect = [(p[0], p[1]) for p in v[:4]]
        ys = (min(p[1] for p in rect) + max(p[1] for p in rect)) / 2
        return hexahedron(v), prism_mass(*clipped_below(rect, ys), W)
    if shape == "tapered":  # a square frustum, 40 mm at the floor, 70 mm at the top
        a, b, c = 0.04, 0.07, 0.035
        v = [(c + sx * (a + (b - a) * y / H) / 2, y, c + sz * (a + (b - a) * y / H) / 2)
             for sz in (-1, 1) for y, sx in ((0, -1), (0, 1), (H, 1), (H, -1))]
        return hexahedron(v), column_mass(lambda y: (a + (b - a) * y / H) ** 2, H / 2)
    if shape == "swept":  # sheared along x by half the height: the side walls lean 26.6 degrees
        v = [(x + 0.5 * y, y, z) for x, y, z in box]
        return hexahedron(v), column_mass(lambda y: L * W, H / 2)
    raise ValueError(shape)


def setup_run(tmp_path, args, nranks):
    out = tmp_path / f"r{nranks}"
    run_flexslosh(args + ["-ts_max_steps", 0, "-fs_output_dir", out], nranks=nranks, cwd=tmp_path, timeout=60)
    return read_series(out)["mass"][0], read_summary(out), last_snapshot(out)


def assert_hydrostatic(snap, ys, rho0=RHO0):
    """Every particle below the surface ys, its density and pressure the hydrostatic ones below it."""
    y = snap["position"][:, 1]
    assert (y < ys).all()
    assert np.allclose(snap["density"], rho0 * (1 + K * (ys - y)), rtol=1e-12, atol=0)
    assert np.allclose(snap["pressure"], rho0 * G * (ys - y), rtol=0, atol=1e-9 * rho0 * G * ys)


@pytest.mark.parametrize("nranks", [1, 2])
@pytest.mark.parametrize("shape", ["rotated", "tilted", "tapered", "swept"])
def test_3d_liquid_weighs_its_exact_volume(tmp_path, shape, nranks):
    """A 3-D tank from STL whose walls are not along the axes (turned about the vertical or a horizontal axis,
    tapered, swept), 50 % full at dx = 5 mm, on 1 and 2 ranks: the lattice alone weighs 72 to 83 % of the liquid,
    the fitted masses sum to its exact mass; the start is hydrostatic below the fill level."""
    tris, exact = tank_3d(shape)
    stl = tmp_path / "tank.stl"
    stl.write_text(ascii_stl(tris))
    mass, summary, snap = setup_run(tmp_path, ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl",
                                               stl, "-fs_dx", DX, "-fs_output_interval", 0, "-fs_fill_packing", "lattice"],
                                    nranks)
    assert mass == pytest.approx(exact, rel=1e-9)
    assert summary["lattice_mass_ratio"] < 0.99  # the lattice does not fit: the fit was needed
    assert summary["liquid_mass"] == pytest.approx(exact, rel=1e-9)
    y = np.array([p[1] for t in tris for p in t])
    assert_hydrostatic(snap, (y.min() + y.max()) / 2)


@pytest.mark.parametrize("nranks", [1, 2])
def test_3d_box_keeps_its_lattice(tmp_path, nranks):
    """The same tank along the axes: the lattice fits, its masses rho dx^3 are kept as they are, and already weigh
    the exact mass."""
    tris, exact = tank_3d("box")
    stl = tmp_path / "tank.stl"
    stl.write_text(ascii_stl(tris))
    mass, summary, snap = setup_run(tmp_path, ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl",
                                               stl, "-fs_dx", DX, "-fs_output_interval", 0], nranks)
    assert len(snap["id"]) == 432
    assert mass == pytest.approx(snap["density"].sum() * DX**3, rel=1e-13)
    assert mass == pytest.approx(exact, rel=1e-12)
    assert summary["lattice_mass_ratio"] == pytest.approx(1, abs=1e-12)
    assert summary["liquid_volume"] == pytest.approx(L * W * H / 2, rel=1e-12)
    assert_hydrostatic(snap, H / 2)


@pytest.mark.parametrize("nranks", [1, 2])
@pytest.mark.parametrize("lean", [0.0, 0.03], ids=["upright", "leaning"])
def test_2d_liquid_weighs_its_exact_area(tmp_path, lean, nranks):
    """The seed's rectangular tank (0.7 x 0.06 m) as a walls file, and the same floor with the side walls leaning
    outwards by 0.03 m at the top, 50 % full at dx = 2 mm: the upright tank keeps its lattice's masses rho dx^2, the
    leaning one's are fitted to the exact mass; hydrostatic below the fill level in both."""
    walls = tmp_path / "tank.walls"
    walls.write_text(f"wall tank\n0 0\n0.7 0\n{0.7 + lean} 0.06\n{-lean} 0.06\nend\n")
    exact = column_mass(lambda y: 0.7 + 2 * lean * y / 0.06, 0.03)
    mass, summary, snap = setup_run(tmp_path, ["-fs_case", "tank", "-fs_tank_shape", "file", "-fs_tank_file", walls,
                                               "-fs_output_interval", 0, "-fs_fill_packing", "lattice"], nranks)
    assert mass == pytest.approx(exact, rel=1e-9)
    if not lean:
        assert mass == pytest.approx(snap["density"].sum() * 0.002**2, rel=1e-13)
    assert_hydrostatic(snap, 0.03)
    if lean:
        assert summary["lattice_mass_ratio"] < 0.999
    else:
        assert summary["lattice_mass_ratio"] == pytest.approx(1, abs=1e-12)

#!/usr/bin/env python3
"""Writes cases/data/wing_bay.stl: a wing tank's bay, tapered and swept, with a rib that has a lightening hole.

x along the chord, y up, z along the span. The bay runs from the root (z = 0, chord 0.08 m from x = 0) to the tip
(z = 0.06 m, chord 0.05 m from x = 0.02 m: the leading edge swept back 18 degrees, the trailing edge 0), 0.04 m
high; its side walls are neither along the axes nor parallel to each other. The rib stands across the span at
z = 0.03 m, 4 mm thick, 4 mm short of the side walls, the floor and the lid (the liquid passes around it, as
between a real rib's stiffeners), with a lightening hole 0.03 x 0.016 m in its middle, 8 mm above its foot. Two
solids: "bay" (the container) and "rib" (an obstacle, its normals out of it: flexslosh turns it inside out).
Run with no argument from the repository's root; `volume_below(y)` gives the liquid's exact volume below a level
(the tests use it).
"""
import sys
from pathlib import Path

ROOT, TIP, SPAN, SWEEP, HEIGHT = 0.08, 0.05, 0.06, 0.02, 0.04
RIB_Z, RIB_T, RIB_GAP = 0.03, 0.004, 0.004
RIB_Y = (RIB_GAP, HEIGHT - RIB_GAP)
HOLE_W, HOLE_Y = 0.03, (0.012, 0.028)


def chord(z):
    """The bay's leading and trailing edges (x) at the span station z."""
    return SWEEP * z / SPAN, ROOT + (TIP + SWEEP - ROOT) * z / SPAN


def rib_x():
    """The rib's ends along x: RIB_GAP inside the walls over its whole thickness."""
    a = max(chord(RIB_Z - RIB_T / 2)[0], chord(RIB_Z + RIB_T / 2)[0]) + RIB_GAP
    b = min(chord(RIB_Z - RIB_T / 2)[1], chord(RIB_Z + RIB_T / 2)[1]) - RIB_GAP
    return a, b


def quads_of_box(v):
    """The 6 faces of a hexahedron (vertices in test_liquid_volume.box_vertices' order), outward."""
    return [(v[a], v[b], v[c], v[d]) for a, b, c, d in
            [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]]


def bay():
    v = []
    for z in (0.0, SPAN):
        x0, x1 = chord(z)
        v.append((z, [(x0, 0.0, z), (x1, 0.0, z), (x1, HEIGHT, z), (x0, HEIGHT, z)]))
    verts = v[0][1] + v[1][1]
    return quads_of_box(verts)


def rib():
    """A plate with a rectangular hole: its two faces (rings of 4 quads), its outer rim and the hole's walls."""
    xa, xb = rib_x()
    xm = (xa + xb) / 2
    out = [(xa, RIB_Y[0]), (xb, RIB_Y[0]), (xb, RIB_Y[1]), (xa, RIB_Y[1])]
    hole = [(xm - HOLE_W / 2, HOLE_Y[0]), (xm + HOLE_W / 2, HOLE_Y[0]), (xm + HOLE_W / 2, HOLE_Y[1]),
            (xm - HOLE_W / 2, HOLE_Y[1])]
    z0, z1 = RIB_Z - RIB_T / 2, RIB_Z + RIB_T / 2
    P = lambda p, z: (p[0], p[1], z)  # noqa: E731
    quads = []
    for k in range(4):
        o0, o1, i0, i1 = out[k], out[(k + 1) % 4], hole[k], hole[(k + 1) % 4]
        quads.append((P(o0, z1), P(o1, z1), P(i1, z1), P(i0, z1)))  # the face at z1, normal +z
        quads.append((P(o0, z0), P(i0, z0), P(i1, z0), P(o1, z0)))  # the face at z0, normal -z
        quads.append((P(o0, z0), P(o1, z0), P(o1, z1), P(o0, z1)))  # the rim, outward
        quads.append((P(i0, z0), P(i0, z1), P(i1, z1), P(i1, z0)))  # the hole's wall, into the hole
    return quads


def stl(solids):
    out = []
    for name, quads in solids:
        out.append(f"solid {name}")
        for a, b, c, d in quads:
            for t in ((a, b, c), (a, c, d)):
                out += ["facet normal 0 0 0", "outer loop"] + [f"vertex {p[0]!r} {p[1]!r} {p[2]!r}" for p in t]
                out += ["endloop", "endfacet"]
        out.append(f"endsolid {name}")
    return "\n".join(out) + "\n"


def volume_below(y):
    """The exact volume of the liquid below the level y: the bay's (its horizontal section the same trapezoid at
    every height) less the rib's part below y, less the hole's."""
    section = (ROOT + TIP) / 2 * SPAN
    xa, xb = rib_x()
    rib = (xb - xa) * max(0.0, min(y, RIB_Y[1]) - RIB_Y[0]) * RIB_T
    hole = HOLE_W * max(0.0, min(y, HOLE_Y[1]) - HOLE_Y[0]) * RIB_T
    return section * y - rib + hole


if __name__ == "__main__":
    path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("cases/data/wing_bay.stl")
    path.write_text(stl([("bay", bay()), ("rib", rib())]))
    print(f"{path}: the liquid below half the height {volume_below(HEIGHT / 2):.9g} m^3")

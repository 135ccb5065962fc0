"""A small tapered tank with a rib, as a CAD export would give it: one closed solid in millimetres (docs/own-tank.md,
tests/python/test_own_tank.py).

x along the chord, y up, z along the span. The bay runs 48 mm along the span, 40 mm high; its chord narrows from
48 mm at the root (z = 0, x from 0 to 48) to 32 mm at the tip (z = 48, x from 8 to 40), so that both side walls are
off the axes. A rib 8 mm thick stands across the span in the middle, 12 mm high, from one side wall to the other: the
liquid joins the two bays above it. The solid is the liquid's container: the rib is a notch in its floor, so the file
is one closed surface, its normals out of the liquid.
"""
SPAN, HEIGHT = 48.0, 40.0
ROOT, TIP = (0.0, 48.0), (8.0, 40.0)  # the chord's ends (x) at z = 0 and z = SPAN
RIB_Z, RIB_HEIGHT = (20.0, 28.0), 12.0


def chord(z):
    """The side walls' x at the span station z."""
    u = z / SPAN
    return ROOT[0] + (TIP[0] - ROOT[0]) * u, ROOT[1] + (TIP[1] - ROOT[1]) * u


def outline():
    """The side view (z, y), counter-clockwise from z towards y: the floor with the rib's notch, the tip, the lid."""
    (z1, z2), h = RIB_Z, RIB_HEIGHT
    return [(0, 0), (z1, 0), (z1, h), (z2, h), (z2, 0), (SPAN, 0), (SPAN, HEIGHT), (0, HEIGHT)]


# the outline's triangles (indices into outline()), counter-clockwise in (z, y): it is not convex (the notch)
OUTLINE_TRIANGLES = [(0, 1, 2), (0, 2, 7), (2, 3, 7), (3, 6, 7), (3, 4, 6), (4, 5, 6)]


def triangles():
    """The tank's triangles, in millimetres, each counter-clockwise seen from outside the liquid."""
    pts = outline()
    lo = lambda p: (chord(p[0])[0], p[1], p[0])  # noqa: E731  the side wall at the chord's start (x small)
    hi = lambda p: (chord(p[0])[1], p[1], p[0])  # noqa: E731
    tris = []
    for a, b, c in OUTLINE_TRIANGLES:
        # counter-clockwise in (z, y) is clockwise seen from +x (z, y, x is left-handed): the wall at large x, whose
        # outside is +x, is turned; the wall at small x is not
        tris.append((hi(pts[a]), hi(pts[c]), hi(pts[b])))
        tris.append((lo(pts[a]), lo(pts[b]), lo(pts[c])))
    for k in range(len(pts)):  # the outline's edges swept across the chord: floor, rib, tip wall, lid, root wall
        p, q = pts[k], pts[(k + 1) % len(pts)]
        tris.append((lo(p), hi(q), lo(q)))
        tris.append((lo(p), hi(p), hi(q)))
    return tris


def volume_below(y):
    """The liquid's exact volume (mm^3) below the level y (mm): the outline's area below y times the chord, which
    is linear in z (integrated exactly, per strip of the outline)."""
    def strip(z0, z1, h):  # int_z0^z1 chord(z) dz times the height h of liquid over the strip
        w = lambda z: chord(z)[1] - chord(z)[0]  # noqa: E731
        return (z1 - z0) * (w(z0) + w(z1)) / 2 * h
    (z1, z2), hr = RIB_Z, RIB_HEIGHT
    y = min(y, HEIGHT)
    return strip(0, z1, y) + strip(z2, SPAN, y) + strip(z1, z2, max(0.0, y - hr))


def ascii_stl(tris, name="tank"):
    out = [f"solid {name}"]
    for t in tris:
        out += ["facet normal 0 0 0", "outer loop"] + [f"vertex {p[0]!r} {p[1]!r} {p[2]!r}" for p in t]
        out += ["endloop", "endfacet"]
    return "\n".join(out + [f"endsolid {name}"]) + "\n"


def write(path):
    """Writes the tank to path (ASCII STL, millimetres)."""
    with open(path, "w") as f:
        f.write(ascii_stl(triangles()))
    return path

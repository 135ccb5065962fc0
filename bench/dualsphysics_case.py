#!/usr/bin/env python3
"""Writes bench_dam_break.py's 2-D dam break, or bench_dam_break_3d.py's 3-D one (--dim 3), as a
DualSPHysics 5.4 case, in place of GenCase (closed source): NAME.xml (the run-time XML GenCase writes:
constants, execution parameters and the particle blocks) and NAME.bi4 (the particles, in DualSPHysics's
JBinaryData format), for bench_dualsphysics.py.

The case is flexslosh's dam_break (src/cases/impls/dam_break.c): a column a wide and 2a high at the
left end of a tank 4a long and 3a high, dx = a/100 by default (20,000 liquid particles), rho0 = 1000,
c0 = 10 sqrt(2 g 2a), Wendland kernel with h = 2 dx (-fs_h_over_dx's default), in DualSPHysics's x-z
plane. The numerical settings are those of DualSPHysics's own 2-D dam-break example
(examples/main/01_DamBreak/CaseDambreakVal2D_Def.xml): Verlet (an Euler step every 40), artificial
viscosity alpha = 0.02, Fourtakas density diffusion delta = 0.1, CFL 0.2, single precision. The walls
are dynamic boundary particles on the lattice, as GenCase's drawbox with faces bottom | left | right
lays them: one layer at x = 0, x = 4a and z = 0 (--layers adds more outside); the liquid particles
sit on the same lattice from dx off the walls, their density hydrostatic (GenCase's rhopgradient 2).

In 3-D (--dim 3; flexslosh's -fs_dim 3) the tank and the column are 2a across, the column spanning the
tank's whole width, as dam_break.c's -fs_dam_tank_width default. flexslosh's axes are x (length),
y (vertical), z (across); DualSPHysics's vertical is z, so flexslosh's (x, y, z) is DualSPHysics's
(x, z, y) here: the tank is 0..4a in x, 0..2a in y (across) and 0..3a in z (up). The walls are the
floor and the four side walls (no lid), as drawbox with faces bottom | left | right | front | back
lays them: one layer at x = 0, x = 4a, y = 0, y = 2a and z = 0 (--layers more outside); the liquid
sits on the same lattice from dx off the walls (dx..a, dx..2a - dx, dx..2a). The numerical settings
are those of DualSPHysics's own 3-D dam-break example (examples/main/01_DamBreak/CaseDambreak_Def.xml),
as the 2-D example's but for alpha = 0.1 (--visco), with the Wendland kernel, flexslosh's, where the
example has the cubic spline (--kernel 1), so that both codes have the same support and neighbours;
h = --hdx dx as in 2-D (the example's coefh 1 would be sqrt(3) dx), the particle mass rho0 dx^3,
dx = 0.0235 by default (bench_dam_break_3d.py's: 307,020 liquid and 79,986 wall particles).
DualSPHysics takes the kernel's 3-D normalization from the XML's data2d (false).

    /usr/bin/python3 bench/dualsphysics_case.py DIR [--dim 2] [--dx 0.01] [--time 0.1] [--timeout T] [--hdx 2]
        [--layers 1] [--kernel K] [--visco V]
    /usr/bin/python3 bench/dualsphysics_case.py --fronts OUTDIR DIR   (the surge front of each Part file
        of a run of the case in DIR, against Martin & Moyce's: T = t sqrt(2 g / a), Z = x_front / a)
"""
import argparse
import math
import struct
import sys
from pathlib import Path

# JBinaryData value types (their numbering in the format)
T_TEXT, T_BOOL, T_INT, T_UINT, T_ULLONG, T_FLOAT, T_DOUBLE, T_FLOAT3, T_DOUBLE3 = 1, 2, 7, 8, 10, 11, 12, 22, 23
_SCALAR = {T_BOOL: "i", T_INT: "i", T_UINT: "I", T_ULLONG: "Q", T_FLOAT: "f", T_DOUBLE: "d", T_FLOAT3: "3f",
           T_DOUBLE3: "3d", 3: "b", 4: "B", 5: "h", 6: "H", 9: "q", 20: "3i", 21: "3I"}
PERI_UNKNOWN, DIV_UNKNOWN = 96, 99


def _str(s):
    b = s.encode()
    return struct.pack("<I", len(b)) + b


def _value(name, vtype, v):
    out = _str(name) + struct.pack("<i", vtype)
    if vtype == T_TEXT:
        return out + _str(v)
    fmt = "<" + _SCALAR[vtype]
    return out + (struct.pack(fmt, *v) if isinstance(v, (tuple, list)) else struct.pack(fmt, v))


def _item(name, values, arrays=(), items=()):
    """One item of the format: its definition (length-prefixed), its values, its arrays, its sub-items
    (each already encoded). arrays: (name, type, count, raw bytes)."""
    vals = _str("\nVALUES") + struct.pack("<I", len(values)) + b"".join(_value(*v) for v in values)
    base = (_str("\nITEM\n") + _str(name) + struct.pack("<ii", 0, 0) + _str("%.7E") + _str("%.15E") +
            struct.pack("<III", len(arrays), len(items), len(vals)))
    out = struct.pack("<I", len(base)) + base + vals
    for aname, atype, count, raw in arrays:
        adef = _str("\nARRAY") + _str(aname) + struct.pack("<iiII", 0, atype, count, len(raw))
        out += struct.pack("<I", len(adef)) + adef + raw
    return out + b"".join(items)


def write_bi4(path, code, values, part_values, arrays):
    """A JBinaryData file: the 64-byte header (title, byte order 0 = little endian, 32-bit sizes) and the
    root item `code` with one sub-item PART_0000."""
    title = ("#FileJBD " + code).ljust(58).encode()[:58] + b"\n\0"
    head = title + bytes([0 if sys.byteorder == "little" else 1, 0, 0, 0])
    with open(path, "wb") as f:
        f.write(head + _item(code, values, (), [_item("PART_0000", part_values, arrays)]))


def read_bi4(path):
    """Reads a JBinaryData file into {item path: {name: value}} with arrays as raw (type, count, bytes)."""
    data = Path(path).read_bytes()
    pos = 64
    si64 = data[61] != 0

    def u32():
        nonlocal pos
        v = struct.unpack_from("<I", data, pos)[0]
        pos += 4
        return v

    def s():
        nonlocal pos
        n = u32()
        pos += n
        return data[pos - n:pos].decode()

    def item(prefix, out):
        nonlocal pos
        u32()
        assert s() == "\nITEM\n"
        name = s()
        pos += 8
        s(), s()
        narr, nit, sval = u32(), u32(), u32()
        rec = out.setdefault(prefix + name, {})
        if sval:
            assert s() == "\nVALUES"
            for _ in range(u32()):
                vname = s()
                vtype = struct.unpack_from("<i", data, pos)[0]
                pos += 4
                if vtype == T_TEXT:
                    rec[vname] = s()
                else:
                    fmt = "<" + _SCALAR[vtype]
                    v = struct.unpack_from(fmt, data, pos)
                    pos += struct.calcsize(fmt)
                    rec[vname] = v if len(v) > 1 else v[0]
        for _ in range(narr):
            u32()
            assert s() == "\nARRAY"
            aname = s()
            _, atype = struct.unpack_from("<ii", data, pos)
            pos += 8
            fmt = "<QQ" if si64 else "<II"
            count, size = struct.unpack_from(fmt, data, pos)
            pos += struct.calcsize(fmt)
            rec[aname] = (atype, count, data[pos:pos + size])
            pos += size
        for _ in range(nit):
            item(prefix + name + "/", out)

    out = {}
    item("", out)
    return out


def particles(dx, a, height, length, tank_height, layers):
    """The wall particles (lattice points on the floor and the side walls, `layers` deep outwards) and the
    liquid's (lattice points of the column from dx off the walls), in the x-z plane."""
    n = lambda v: int(round(v / dx))
    na, nh, nl, nt = n(a), n(height), n(length), n(tank_height)
    wall = set()
    for k in range(layers):
        wall.update((i, -k) for i in range(-k, nl + k + 1))  # floor
        wall.update((-k, j) for j in range(-k, nt + 1))  # left wall
        wall.update((nl + k, j) for j in range(-k, nt + 1))  # right wall
    wall = sorted(wall, key=lambda p: (p[1], p[0]))
    fluid = [(i, j) for j in range(1, nh + 1) for i in range(1, na + 1)]
    return [(i * dx, j * dx) for i, j in wall], [(i * dx, j * dx) for i, j in fluid]


def particles_3d(dx, a, height, length, tank_height, width, layers):
    """particles() in 3-D, in DualSPHysics's axes (x along the tank, y across, z up): the wall particles
    (lattice points on the floor and the four side walls, `layers` deep outwards, no lid) and the
    liquid's (lattice points of the column, over the tank's whole width, from dx off the walls)."""
    n = lambda v: int(round(v / dx))
    na, nh, nl, nt, nw = n(a), n(height), n(length), n(tank_height), n(width)
    wall = set()
    for k in range(layers):
        wall.update((i, j, -k) for i in range(-k, nl + k + 1) for j in range(-k, nw + k + 1))  # floor
        for j in range(-k, nw + k + 1):  # the walls at x = 0 and x = length
            wall.update((i, j, m) for i in (-k, nl + k) for m in range(-k, nt + 1))
        for i in range(-k, nl + k + 1):  # the walls at y = 0 and y = width
            wall.update((i, j, m) for j in (-k, nw + k) for m in range(-k, nt + 1))
    wall = sorted(wall, key=lambda p: (p[2], p[1], p[0]))
    fluid = [(i, j, m) for m in range(1, nh + 1) for j in range(1, nw) for i in range(1, na + 1)]
    return [(i * dx, j * dx, m * dx) for i, j, m in wall], [(i * dx, j * dx, m * dx) for i, j, m in fluid]


def write_case(outdir, name="Case", dx=0.01, a=1.0, tfinal=0.1, timeout=None, hdx=2.0, layers=1, cfl=0.2,
               visco=None, ddt=0.1, dim=2, kernel=2):
    """Writes outdir/name.xml and outdir/name.bi4 of the 2-D (dim 2) or the 3-D (dim 3) dam break; kernel
    is Wendland's (2; 1 the cubic spline) and visco defaults to DualSPHysics's 2-D example's (0.02) or 3-D
    example's (0.1). Returns a dict of the case's figures."""
    g, rho0, gamma = 9.81, 1000.0, 7.0
    height, length, tank_height = 2 * a, 4 * a, 3 * a
    c0 = 10 * math.sqrt(2 * g * height)  # flexslosh's dam_break default
    b = c0 * c0 * rho0 / gamma
    h = hdx * dx
    if visco is None:
        visco = 0.02 if dim == 2 else 0.1
    if dim == 2:
        mass = rho0 * dx * dx
        wall, fluid = particles(dx, a, height, length, tank_height, layers)
        wall, fluid = [(x, 0.0, z) for x, z in wall], [(x, 0.0, z) for x, z in fluid]
    else:
        mass = rho0 * dx * dx * dx
        width = height  # dam_break.c's -fs_dam_tank_width default
        wall, fluid = particles_3d(dx, a, height, length, tank_height, width, layers)
    nb, nf = len(wall), len(fluid)
    zmax = max(p[2] for p in fluid)
    pos = wall + fluid
    rho = [rho0] * nb + [rho0 * (1 + rho0 * g * (zmax - p[2]) / b) ** (1 / gamma) for p in fluid]
    pmin = tuple(min(p[d] for p in pos) for d in range(3))
    pmax = tuple(max(p[d] for p in pos) for d in range(3))
    np_ = nb + nf
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    values = [("Piece", T_UINT, 0), ("Npiece", T_UINT, 1), ("RunCode", T_TEXT, "00000000"), ("Date", T_TEXT, "???"),
              ("AppName", T_TEXT, "flexslosh bench/dualsphysics_case.py"), ("CaseName", T_TEXT, name),
              ("Data2d", T_BOOL, int(dim == 2)), ("Data2dPosY", T_DOUBLE, 0.0),
              ("MapPosMin", T_DOUBLE3, (0.0, 0.0, 0.0)),
              ("MapPosMax", T_DOUBLE3, (0.0, 0.0, 0.0)), ("PeriMode", T_INT, PERI_UNKNOWN),
              ("PeriXinc", T_DOUBLE3, (0.0, 0.0, 0.0)), ("PeriYinc", T_DOUBLE3, (0.0, 0.0, 0.0)),
              ("PeriZinc", T_DOUBLE3, (0.0, 0.0, 0.0)), ("AxisDiv", T_INT, DIV_UNKNOWN),
              ("CaseNp", T_ULLONG, np_), ("CaseNfixed", T_ULLONG, nb), ("CaseNmoving", T_ULLONG, 0),
              ("CaseNfloat", T_ULLONG, 0), ("CaseNfluid", T_ULLONG, nf), ("CasePosMin", T_DOUBLE3, pmin),
              ("CasePosMax", T_DOUBLE3, pmax), ("NpDynamic", T_BOOL, 0), ("ReuseIds", T_BOOL, 0),
              ("Dp", T_DOUBLE, dx), ("H", T_DOUBLE, h), ("B", T_DOUBLE, b), ("Rhop0", T_DOUBLE, rho0),
              ("Gamma", T_DOUBLE, gamma), ("MassBound", T_DOUBLE, mass), ("MassFluid", T_DOUBLE, mass),
              ("Symmetry", T_BOOL, 0), ("Splitting", T_BOOL, 0)]
    part = [("Cpart", T_UINT, 0), ("TimeStep", T_DOUBLE, 0.0), ("Npok", T_UINT, np_), ("Nout", T_UINT, 0),
            ("Step", T_UINT, 0), ("RunTime", T_DOUBLE, 0.0), ("DomainMin", T_DOUBLE3, pmin),
            ("DomainMax", T_DOUBLE3, pmax)]
    arrays = [("Idp", T_UINT, np_, struct.pack(f"<{np_}I", *range(np_))),
              ("Pos", T_FLOAT3, np_, b"".join(struct.pack("<3f", *p) for p in pos)),
              ("Vel", T_FLOAT3, np_, bytes(12 * np_)), ("Rhop", T_FLOAT, np_, struct.pack(f"<{np_}f", *rho))]
    write_bi4(outdir / f"{name}.bi4", "JPartDataBi4", values, part, arrays)
    params = [("SavePosDouble", 0), ("StepAlgorithm", 1), ("VerletSteps", 40), ("Kernel", kernel),
              ("ViscoTreatment", 1), ("Visco", visco), ("ViscoBoundFactor", 1), ("DensityDT", 2),
              ("DensityDTvalue", ddt), ("Shifting", 0), ("RigidAlgorithm", 1), ("CoefDtMin", 0.05), ("DtIni", 0),
              ("DtMin", 0), ("DtAllParticles", 0), ("TimeMax", tfinal), ("TimeOut", timeout or tfinal),
              ("RhopOutMin", 700), ("RhopOutMax", 1300)]
    # GenCase writes data2dposy only in 2-D (JCaseCtes::WriteXmlRun), and DualSPHysics checks that the
    # .bi4's Data2d and Data2dPosY match (JPartsLoad4::CheckConfig)
    dims = (['      <data2d value="true" />', '      <data2dposy value="0" />'] if dim == 2 else
            ['      <data2d value="false" />'])
    lines = ['<?xml version="1.0" encoding="UTF-8" ?>',
             '<!-- written by flexslosh bench/dualsphysics_case.py: the run-time part of a GenCase output -->',
             '<case app="flexslosh bench/dualsphysics_case.py">', "  <execution>", "    <constants>"] + dims + [
             f'      <gravity x="0" y="0" z="{-g!r}" />', f'      <cflnumber value="{cfl!r}" />',
             f'      <gamma value="{gamma!r}" />', f'      <rhop0 value="{rho0!r}" />', f'      <dp value="{dx!r}" />',
             f'      <h value="{h!r}" />', f'      <b value="{b!r}" />', f'      <massbound value="{mass!r}" />',
             f'      <massfluid value="{mass!r}" />', "    </constants>",
             f'    <particles np="{np_}" nb="{nb}" nbf="{nb}" mkboundfirst="11" mkfluidfirst="1">',
             f'      <fixed mkbound="0" mk="11" begin="0" count="{nb}" />',
             f'      <fluid mkfluid="0" mk="1" begin="{nb}" count="{nf}" />', "    </particles>", "    <parameters>"]
    lines += [f'      <parameter key="{k}" value="{v!r}" />' for k, v in params]
    lines += ["      <simulationdomain>", '        <posmin x="default" y="default" z="default" />',
              '        <posmax x="default" y="default" z="default + 50%" />', "      </simulationdomain>",
              "    </parameters>", "  </execution>", "</case>", ""]
    (outdir / f"{name}.xml").write_text("\n".join(lines))
    return {"fluid": nf, "wall": nb, "h": h, "c0": c0, "B": b}


def fluid_state(bi4, nbound):
    """(time, the liquid particles) of a DualSPHysics Part_*.bi4 file: [(x, z)] of a 2-D case, [(x, y, z)]
    of a 3-D one (the file's Data2d says which); the vertical, z, is last in both."""
    d = read_bi4(bi4)
    key = next(k for k in d if "/PART_" in k)
    part, flat = d[key], d[key.split("/")[0]].get("Data2d", 1)
    _, n, idraw = part["Idp"]
    ids = struct.unpack(f"<{n}I", idraw)
    if "Pos" in part:
        xyz = struct.unpack(f"<{3 * n}f", part["Pos"][2])
    else:
        xyz = struct.unpack(f"<{3 * n}d", part["Posd"][2])
    if flat:
        pts = [(xyz[3 * i], xyz[3 * i + 2]) for i in range(n) if ids[i] >= nbound]
    else:
        pts = [xyz[3 * i:3 * i + 3] for i in range(n) if ids[i] >= nbound]
    return part["TimeStep"], pts


def front(points, a=1.0, x0=0.0):
    """flexslosh's front_position: the largest x of the liquid within a/4 of the floor (x from the back
    wall at x0); points are (x, z) or (x, y, z), the vertical last."""
    return max(p[0] for p in points if p[-1] < 0.25 * a) - x0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--name", default="Case")
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2)
    ap.add_argument("--dx", type=float, default=None, help="particle spacing (default 0.01 in 2-D, 0.0235 in 3-D)")
    ap.add_argument("--time", type=float, default=0.1, help="physical time simulated (TimeMax)")
    ap.add_argument("--timeout", type=float, default=None, help="time between outputs (TimeOut; default: --time)")
    ap.add_argument("--hdx", type=float, default=2.0,
                    help="h/dx (DualSPHysics's examples: coefh 1, sqrt(2) in 2-D, sqrt(3) in 3-D)")
    ap.add_argument("--layers", type=int, default=1, help="layers of wall particles")
    ap.add_argument("--kernel", type=int, choices=(1, 2), default=2,
                    help="1: cubic spline, 2: Wendland (the default, flexslosh's; DualSPHysics's 3-D example has 1)")
    ap.add_argument("--visco", type=float, default=None, help="artificial viscosity (default: 0.02 in 2-D, 0.1 in 3-D)")
    ap.add_argument("--fronts", metavar="OUTDIR", help="print the fronts of a run's Part files instead")
    a = ap.parse_args()
    if a.fronts:
        nbound = read_bi4(Path(a.dir) / f"{a.name}.bi4")["JPartDataBi4"]["CaseNfixed"]
        print("     t        T    Z = x_front / a   liquid particles")
        for f in sorted(Path(a.fronts).rglob("Part_*.bi4")):
            t, pts = fluid_state(f, nbound)
            print(f"{t:8.4f} {t * math.sqrt(2 * 9.81):8.4f} {front(pts):10.4f} {len(pts):14d}")
        return 0
    dx = a.dx or (0.01 if a.dim == 2 else 0.0235)
    info = write_case(a.dir, a.name, dx, 1.0, a.time, a.timeout, a.hdx, a.layers, visco=a.visco, dim=a.dim,
                      kernel=a.kernel)
    print(f"{a.dir}/{a.name}.xml, .bi4: {info['fluid']} liquid and {info['wall']} wall particles, h = {info['h']:g}, "
          f"c0 = {info['c0']:.4f}")


if __name__ == "__main__":
    sys.exit(main())

"""bench/dualsphysics_case.py, the DualSPHysics case of the dam-break comparison, 2-D and 3-D: the
files it writes hold the dam break's particles and constants, and read back as written. With
DUALSPHYSICS set to a DualSPHysics 5.4 CPU binary (docs/performance.md, "Against DualSPHysics"),
DualSPHysics also runs each case a few steps and keeps every particle."""
import math
import os
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from conftest import REPO_ROOT

sys.path.insert(0, str(REPO_ROOT / "bench"))
import dualsphysics_case as dc  # noqa: E402


def test_case_files_hold_the_dam_break(tmp_path):
    dx = 0.05
    info = dc.write_case(tmp_path, dx=dx, tfinal=0.01)
    assert info["fluid"] == 20 * 40 and info["wall"] == 81 + 2 * 60  # floor 0..4 m, walls dx..3 m
    d = dc.read_bi4(tmp_path / "Case.bi4")
    head = (tmp_path / "Case.bi4").read_bytes()[:64]
    assert head.startswith(b"#FileJBD JPartDataBi4 ") and head[58:60] == b"\n\0"
    top, part = d["JPartDataBi4"], d["JPartDataBi4/PART_0000"]
    c0 = 10 * math.sqrt(2 * 9.81 * 2)
    assert top["CaseNp"] == info["wall"] + 800 and top["CaseNfixed"] == info["wall"] and top["CaseNfluid"] == 800
    assert top["H"] == pytest.approx(2 * dx) and top["B"] == pytest.approx(c0 * c0 * 1000 / 7)
    assert top["MassFluid"] == pytest.approx(1000 * dx * dx) and top["Data2d"] == 1
    n = part["Npok"]
    assert n == top["CaseNp"]
    ids = struct.unpack(f"<{n}I", part["Idp"][2])
    xyz = struct.unpack(f"<{3 * n}f", part["Pos"][2])
    rho = struct.unpack(f"<{n}f", part["Rhop"][2])
    assert ids == tuple(range(n))
    nb = top["CaseNfixed"]
    wall = [(xyz[3 * i], xyz[3 * i + 2]) for i in range(nb)]
    assert all(min(abs(x), abs(x - 4), abs(z)) < 1e-6 for x, z in wall)
    fluid = [(xyz[3 * i], xyz[3 * i + 2]) for i in range(nb, n)]
    assert min(x for x, _ in fluid) == pytest.approx(dx) and max(x for x, _ in fluid) == pytest.approx(1.0)
    assert max(z for _, z in fluid) == pytest.approx(2.0) and dc.front(fluid) == pytest.approx(1.0)
    # hydrostatic (Tait) density below the top particle, rho0 on the walls
    p = 1000 * 9.81 * (2.0 - dx)
    assert rho[nb] == pytest.approx(1000 * (1 + 7 * p / (1000 * c0 * c0)) ** (1 / 7), rel=1e-6)
    assert set(rho[:nb]) == {1000.0}
    root = ET.parse(tmp_path / "Case.xml").getroot()
    parts = root.find("execution/particles")
    assert int(parts.get("np")) == n and int(parts.get("nb")) == nb == int(parts.find("fixed").get("count"))
    params = {e.get("key"): e.get("value") for e in root.iter("parameter")}
    assert params["StepAlgorithm"] == "1" and params["DensityDT"] == "2" and params["Kernel"] == "2"


@pytest.mark.skipif(not os.environ.get("DUALSPHYSICS"), reason="DUALSPHYSICS (a DualSPHysics binary) not set")
def test_dualsphysics_runs_the_case(tmp_path):
    dc.write_case(tmp_path / "case", dx=0.05, tfinal=0.01)
    out = subprocess.run([os.environ["DUALSPHYSICS"], str(tmp_path / "case" / "Case"), str(tmp_path / "out"),
                          "-ompthreads:1", "-svres:0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert "[Simulation finished" in out.stdout, out.stdout[-2000:]
    t, pts = dc.fluid_state(sorted((tmp_path / "out").rglob("Part_*.bi4"))[-1], 201)
    assert t >= 0.01 and len(pts) == 800 and 1.0 <= dc.front(pts) < 1.05


def test_3d_case_files_hold_the_dam_break(tmp_path):
    """The 3-D case (flexslosh's -fs_dim 3 dam break, its (x, y, z) as DualSPHysics's (x, z, y)): a
    column 1 x 2 m, 2 m across, at x = 0 in a tank 4 x 3 m, 2 m across, walls on the lattice."""
    dx = 0.25
    info = dc.write_case(tmp_path, dx=dx, tfinal=0.01, dim=3)
    # liquid: 4 along x (dx..1 m), 7 across (dx..2 m - dx), 8 up (dx..2 m); walls: the floor 17 x 9 points
    # (0..4 m, 0..2 m), the end walls 9 x 12 (0..2 m across, dx..3 m up), the side walls 15 x 12 between them
    assert info["fluid"] == 4 * 7 * 8 and info["wall"] == 17 * 9 + 2 * 9 * 12 + 2 * 15 * 12
    d = dc.read_bi4(tmp_path / "Case.bi4")
    top, part = d["JPartDataBi4"], d["JPartDataBi4/PART_0000"]
    c0 = 10 * math.sqrt(2 * 9.81 * 2)
    nb, n = top["CaseNfixed"], part["Npok"]
    assert top["Data2d"] == 0 and top["Data2dPosY"] == 0.0
    assert top["CaseNp"] == n == info["wall"] + info["fluid"] and nb == info["wall"] and top["CaseNfluid"] == 224
    assert top["H"] == pytest.approx(2 * dx) and top["B"] == pytest.approx(c0 * c0 * 1000 / 7)
    assert top["MassFluid"] == top["MassBound"] == pytest.approx(1000 * dx ** 3)
    assert top["CasePosMin"] == (0.0, 0.0, 0.0) and top["CasePosMax"] == (4.0, 2.0, 3.0)
    assert struct.unpack(f"<{n}I", part["Idp"][2]) == tuple(range(n))
    xyz = struct.unpack(f"<{3 * n}f", part["Pos"][2])
    pts = [xyz[3 * i:3 * i + 3] for i in range(n)]
    rho = struct.unpack(f"<{n}f", part["Rhop"][2])
    # the walls: the floor and the four sides, none above the tank (no lid), each point on the lattice once
    assert all(min(abs(x), abs(x - 4), abs(y), abs(y - 2), abs(z)) < 1e-6 for x, y, z in pts[:nb])
    assert max(z for _, _, z in pts[:nb]) == pytest.approx(3.0) and len(set(pts[:nb])) == nb
    assert sum(1 for _, _, z in pts[:nb] if abs(z - 3) < 1e-6) == 2 * 9 + 2 * 15  # the walls' top rows only
    fluid = pts[nb:]
    for k, (lo, hi) in enumerate([(dx, 1.0), (dx, 2.0 - dx), (dx, 2.0)]):  # x; y across; z up
        assert min(p[k] for p in fluid) == pytest.approx(lo) and max(p[k] for p in fluid) == pytest.approx(hi)
    # hydrostatic (Tait) density in z, DualSPHysics's vertical, below the top layer; rho0 on the walls
    for (_, _, z), r in zip(fluid, rho[nb:]):
        p = 1000 * 9.81 * (2.0 - z)
        assert r == pytest.approx(1000 * (1 + 7 * p / (1000 * c0 * c0)) ** (1 / 7), rel=1e-6)
    assert rho[nb] > rho[-1] == 1000.0 and set(rho[:nb]) == {1000.0}
    # the case file reads as a state: the liquid in (x, y, z), its front at the column's face (a = 2 m for
    # front's floor band, a / 4, to hold the lowest layer, z = dx, at this dx)
    t, state = dc.fluid_state(tmp_path / "Case.bi4", nb)
    assert t == 0.0 and state == fluid and dc.front(state, a=2.0) == pytest.approx(1.0)
    root = ET.parse(tmp_path / "Case.xml").getroot()
    ctes = root.find("execution/constants")
    assert ctes.find("data2d").get("value") == "false" and ctes.find("data2dposy") is None
    assert float(ctes.find("massfluid").get("value")) == pytest.approx(1000 * dx ** 3)
    assert float(ctes.find("h").get("value")) == pytest.approx(2 * dx)
    assert ctes.find("gravity").get("z") == "-9.81"
    parts = root.find("execution/particles")
    assert int(parts.get("np")) == n and int(parts.find("fluid").get("count")) == 224
    params = {e.get("key"): e.get("value") for e in root.iter("parameter")}
    assert params["Kernel"] == "2" and params["Visco"] == "0.1" and params["DensityDT"] == "2"


@pytest.mark.skipif(not os.environ.get("DUALSPHYSICS"), reason="DUALSPHYSICS (a DualSPHysics binary) not set")
def test_dualsphysics_runs_the_3d_case(tmp_path):
    info = dc.write_case(tmp_path / "case", dx=0.2, tfinal=0.01, dim=3)
    out = subprocess.run([os.environ["DUALSPHYSICS"], str(tmp_path / "case" / "Case"), str(tmp_path / "out"),
                          "-ompthreads:1", "-svres:0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert "[Simulation finished" in out.stdout and "3D-Simulation" in out.stdout, out.stdout[-2000:]
    t, pts = dc.fluid_state(sorted((tmp_path / "out").rglob("Part_*.bi4"))[-1], info["wall"])
    assert t >= 0.01 and len(pts) == info["fluid"] == 5 * 9 * 10 and 1.0 <= dc.front(pts) < 1.05
    assert all(0 < x < 4 and 0 < y < 2 and 0 < z < 3 for x, y, z in pts)

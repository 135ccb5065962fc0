"""bench/dualsphysics_case.py, the DualSPHysics case of the dam-break comparison: the files it writes
hold the dam break's particles and constants, and read back as written. With DUALSPHYSICS set to a
DualSPHysics 5.4 CPU binary (docs/performance.md, "Against DualSPHysics"), DualSPHysics also runs
the case a few steps and keeps every particle."""
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

"""Filling a tank by volume or mass (-fs_fill_volume, -fs_fill_mass) instead of a level (-fs_fill): the level is
found by bisection on the exact volume and hydrostatic mass below it (src/cases/impls/liquid.c, FSCaseFillLevel).
Set-up only (-ts_max_steps 0).

- A 2-D box: the volume and the mass of -fs_fill 0.4 give -fs_fill 0.4's particles (positions, densities, masses
  to round-off: the level is the same to the last bits).
- A 3-D STL box tilted 20 degrees about z: the volume V and the mass M of the liquid below a level ys, computed here
  from the tilted cross-section (test_liquid_volume.py's shoelace clip), give the level ys (to 1e-9 of the height)
  and a liquid of exactly V and M, hydrostatic below ys; on 1 and 2 ranks.
"""
import re

import numpy as np
import pytest

from conftest import assert_no_crash, last_snapshot, petsc_error_message, read_summary, run_flexslosh
from test_liquid_volume import (H, L, W, assert_hydrostatic, ascii_stl, box_vertices, clipped_below, hexahedron,
                                prism_mass, rotated)

TANK2 = ["-fs_case", "tank", "-fs_tank_length", 0.2, "-fs_tank_height", 0.12, "-fs_dx", 0.005, "-fs_output_interval", 0]


def set_up(tmp_path, name, args, nranks=1):
    out = tmp_path / name
    proc = run_flexslosh(args + ["-ts_max_steps", 0, "-fs_output_dir", out], nranks=nranks, cwd=tmp_path, timeout=120)
    return last_snapshot(out), read_summary(out), proc.stdout


def level_printed(stdout):
    m = re.search(r"the liquid's level is y = ([-+0-9.eE]+)", stdout)
    assert m, stdout[-2000:]
    return float(m.group(1))


def test_2d_box_by_volume_and_mass_is_the_fill(tmp_path):
    ref, sref, _ = set_up(tmp_path, "fill", TANK2 + ["-fs_fill", 0.4])
    vol, svol, out = set_up(tmp_path, "vol", TANK2 + ["-fs_fill_volume", 0.2 * 0.12 * 0.4])
    assert level_printed(out) == pytest.approx(0.048, abs=1e-15)
    mass, smass, out = set_up(tmp_path, "mass", TANK2 + ["-fs_fill_mass", sref["liquid_mass"]])
    assert level_printed(out) == pytest.approx(0.048, abs=1e-15)
    for snap, summ in ((vol, svol), (mass, smass)):
        assert np.array_equal(snap["id"], ref["id"])
        for f in ("position", "density", "pressure"):
            assert np.allclose(snap[f], ref[f], rtol=1e-12, atol=1e-15), f
        assert summ["liquid_mass"] == pytest.approx(sref["liquid_mass"], rel=1e-13)
        assert summ["liquid_volume"] == pytest.approx(0.2 * 0.12 * 0.4, rel=1e-13)


def tilted_tank(tmp_path):
    v = rotated(box_vertices(0, L, 0, H, 0, W), 2, 20, (L / 2, H / 2, 0))
    stl = tmp_path / "tilted.stl"
    stl.write_text(ascii_stl(hexahedron(v)))
    rect = [(p[0], p[1]) for p in v[:4]]
    lo, hi = min(p[1] for p in rect), max(p[1] for p in rect)
    return stl, rect, lo, hi


@pytest.mark.parametrize("nranks", [1, 2])
def test_tilted_stl_tank_by_volume_and_mass(tmp_path, nranks):
    stl, rect, lo, hi = tilted_tank(tmp_path)
    ys = lo + 0.37 * (hi - lo)  # through the tilted side walls' corners' heights: a pentagon below it
    area, moment = clipped_below(rect, ys)
    V, M = W * area, prism_mass(area, moment, W)
    base = ["-fs_case", "tank", "-fs_dim", 3, "-fs_tank_shape", "stl", "-fs_tank_stl", stl, "-fs_dx", 0.005,
            "-fs_output_interval", 0, "-fs_fill_packing", "lattice"]
    for opt, target in (("-fs_fill_volume", V), ("-fs_fill_mass", M)):
        snap, summary, out = set_up(tmp_path, f"{opt}{nranks}", base + [opt, target], nranks)
        level = level_printed(out)
        print(f"tilted tank, {opt} {target:.6g}: level {level:.10f}, exact {ys:.10f}")
        assert level == pytest.approx(ys, abs=1e-9 * (hi - lo))
        assert summary["liquid_volume"] == pytest.approx(V, rel=1e-9)
        assert summary["liquid_mass"] == pytest.approx(M, rel=1e-9)
        assert_hydrostatic(snap, ys)


@pytest.mark.parametrize("args,expect", [
    (["-fs_fill_volume", 0.03], ["-fs_fill_volume 0.03", "more than the full tank holds", "at most 0.024", "m^2"]),
    (["-fs_fill_mass", 100], ["-fs_fill_mass 100", "more than the full tank holds", "kg per metre of width"]),
    (["-fs_fill_volume", -1], ["-fs_fill_volume", "-1"]),
    (["-fs_fill", 0.3, "-fs_fill_volume", 0.01], ["-fs_fill, -fs_fill_volume", "more than once"]),
    (["-fs_fill_volume", 0.01, "-fs_fill_mass", 5], ["-fs_fill_volume and -fs_fill_mass", "more than once"]),
    (["-fs_liquid_box", "0,0.1,0,0.05", "-fs_fill_mass", 5], ["-fs_liquid_box, -fs_fill_mass", "more than once"]),
])
def test_bad_fill_input(tmp_path, args, expect):
    proc = run_flexslosh(TANK2 + ["-ts_max_steps", 0, "-fs_output_dir", tmp_path / "o"] + args, cwd=tmp_path,
                         check=False)
    assert_no_crash(proc)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg

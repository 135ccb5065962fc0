"""The reduced model (issue 36 item 4): the msd beam with its liquid replaced by a heave describing function,
an effective mass and a damper looked up by the motion's amplitude (-fs_msd_liquid_table, docs/equivalent.md).
Exact checks: a constant table is a linear oscillator whose damping ratio and period are known in closed form;
an amplitude-dependent damper gives each cycle the damping of its amplitude; the table written from a heave grid;
bad tables and options named."""
import math

import numpy as np
import pytest

from conftest import read_series, read_summary, run_flexslosh

from flexslosh import equivalent as eq
from flexslosh.damping import damping_per_cycle

# the seed's rectangular tank on the msd beam (cases/coupled_rectangular.opts), its 2.1 kg of water replaced
SEED = ["-fs_case", "beam", "-fs_structure", "msd", "-fs_beam_tank_mass", 5.0, "-fs_beam_payload_mass", 3.36,
        "-fs_beam_preload", 0.04, "-fs_beam_damping", 0.015, "-fs_output_interval", 0, "-ts_max_time", 2.0]
M = 2.1


def reduced(tmp_path, name, rows, extra=(), check=True):
    table = tmp_path / f"{name}.txt"
    table.write_text("# A m_eff c_eq\n" + "".join(f"{a!r} {m!r} {c!r}\n" for a, m, c in rows))
    out = tmp_path / name
    proc = run_flexslosh(SEED + ["-fs_msd_liquid_table", table, "-fs_msd_liquid_mass", M, "-fs_output_dir", out]
                         + list(extra), cwd=tmp_path, check=check)
    return out, proc


def test_constant_table_is_the_linear_oscillator(tmp_path):
    """m_eff = M, c_eq = 3 N s/m at every amplitude: zeta = (c + c_eq) / (2 sqrt(K (m + M))), the period
    2 pi sqrt((m + M) / K), with m and c of the structure without its liquid (as in the coupled run)."""
    out, _ = reduced(tmp_path, "const", [(0.001, M, 3.0), (0.05, M, 3.0)])
    s = read_summary(out)
    m, K, c = s["structure"]["mass"], s["structure"]["stiffness"], s["structure"]["damping_coefficient"]
    assert m == pytest.approx(33 / 140 * 13.04 * 2.48 + 5.0 + 3.36 - M, rel=1e-12)  # the payload less the table's M
    ts = read_series(out)
    cyc = damping_per_cycle(ts["time"], ts["tip_displacement"])
    zeta = (c + 3.0) / (2 * math.sqrt(K * (m + M)))
    assert np.allclose(cyc.zeta[1:], zeta, rtol=2e-3), (cyc.zeta, zeta)
    assert np.allclose(cyc.period[1:], 2 * np.pi * math.sqrt((m + M) / K) / math.sqrt(1 - zeta**2), rtol=2e-3)


def test_amplitude_dependent_damper(tmp_path):
    """c_eq = 20 N s/m above 20 mm, 0 below 10 mm, linear between: the cycles above 20 mm damp at the larger
    ratio, those below 10 mm at the structure's own, each within 3 % of it (a cycle's amplitude falls by
    2 pi zeta within it)."""
    out, _ = reduced(tmp_path, "step", [(0.002, M, 0.0), (0.010, M, 0.0), (0.020, M, 20.0), (0.05, M, 20.0)],
                     ["-ts_max_time", 4.0])
    s = read_summary(out)
    m, K, c = s["structure"]["mass"], s["structure"]["stiffness"], s["structure"]["damping_coefficient"]
    ts = read_series(out)
    cyc = damping_per_cycle(ts["time"], ts["tip_displacement"])
    high, low = (c + 20) / (2 * math.sqrt(K * (m + M))), c / (2 * math.sqrt(K * (m + M)))
    big, small = cyc.zeta[1:][cyc.amplitude[1:] > 0.023], cyc.zeta[cyc.amplitude < 0.009]
    assert len(big) >= 2 and len(small) >= 2
    assert np.allclose(big, high, rtol=0.03), (big, high)
    assert np.allclose(small, low, rtol=0.03), (small, low)


def test_lag_keeps_the_damping_of_larger_amplitudes(tmp_path):
    """-fs_msd_liquid_lag tau: the table is looked up at the amplitude seen through a first-order lag, so the damper
    that switches off below 10 mm still acts on the first cycles below it (their amplitude lags above), and
    without the lag it does not; a constant table is the same with or without the lag."""
    rows = [(0.002, M, 0.0), (0.010, M, 0.0), (0.020, M, 20.0), (0.05, M, 20.0)]
    z = {}
    for lag in (0, 0.3):
        out, _ = reduced(tmp_path, f"lag{lag}", rows, ["-ts_max_time", 4.0, "-fs_msd_liquid_lag", lag])
        ts = read_series(out)
        cyc = damping_per_cycle(ts["time"], ts["tip_displacement"])
        z[lag] = cyc.zeta[np.flatnonzero(cyc.amplitude < 0.009)[0]]
    st = read_summary(out)["structure"]
    own = st["damping_coefficient"] / (2 * math.sqrt(st["stiffness"] * (st["mass"] + M)))
    assert z[0] == pytest.approx(own, rel=1e-3)
    assert z[0.3] - own > 7e-4, z  # measured 1.1e-3: its lagged amplitude about 11 mm, c_eq about 2 N s/m
    const = [(0.001, M, 3.0), (0.05, M, 3.0)]
    a, _ = reduced(tmp_path, "c0", const)
    b, _ = reduced(tmp_path, "c1", const, ["-fs_msd_liquid_lag", 0.3])
    assert np.allclose(read_series(a)["tip_displacement"], read_series(b)["tip_displacement"], rtol=0, atol=1e-12)


def test_bad_tables_and_options_are_named(tmp_path):
    _, p = reduced(tmp_path, "neg", [(0.001, M, 1.0), (0.01, M, -1.0)], check=False)
    assert p.returncode != 0 and "-fs_msd_liquid_table" in p.output and "row 2" in p.output and "c_eq -1" in p.output
    _, p = reduced(tmp_path, "order", [(0.01, M, 1.0), (0.001, M, 1.0)], check=False)
    assert p.returncode != 0 and "-fs_msd_liquid_table" in p.output and "line 3" in p.output
    p = run_flexslosh(SEED + ["-fs_msd_liquid_table", tmp_path / "none.txt", "-fs_msd_liquid_mass", M,
                              "-fs_output_dir", tmp_path / "x"], cwd=tmp_path, check=False)
    assert p.returncode != 0 and "cannot open" in p.output and "none.txt" in p.output
    (tmp_path / "ok.txt").write_text("0.001 2.1 0\n0.05 2.1 0\n")
    p = run_flexslosh(SEED + ["-fs_msd_liquid_table", tmp_path / "ok.txt", "-fs_output_dir", tmp_path / "y"],
                      cwd=tmp_path, check=False)
    assert p.returncode != 0 and "needs -fs_msd_liquid_mass" in p.output
    p = run_flexslosh(SEED + ["-fs_msd_liquid_lag", 0.2, "-fs_output_dir", tmp_path / "w"], cwd=tmp_path, check=False)
    assert p.returncode != 0 and "-fs_msd_liquid_lag 0.2" in p.output and "-fs_msd_liquid_table" in p.output
    p = run_flexslosh(["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", 0.02, "-ts_max_time", 0.01,
                       "-fs_msd_liquid_table", tmp_path / "ok.txt", "-fs_msd_liquid_mass", M,
                       "-fs_output_dir", tmp_path / "z"], check=False, cwd=eq.Path(__file__).parents[2])
    assert p.returncode != 0 and "-fs_case beam" in p.output


def _row(amplitude, settled=True, frequency=6.05, fill=float("nan"), m_eff=2.0, c_eq=1.0):
    return {"direction": "heave", "frequency": frequency, "fill": fill, "amplitude": amplitude, "settled": settled,
            "m_eff": m_eff if settled else float("nan"), "c_eq": c_eq if settled else float("nan"), "dx": 0.005,
            "revision": "abc", "liquid_mass": M}


def test_liquid_table_from_a_heave_grid(tmp_path):
    """The settled rows by increasing amplitude; the others named in a comment; one frequency, one fill."""
    rows = [_row(0.02, c_eq=4.0), _row(0.004, settled=False), _row(0.01, m_eff=1.9, c_eq=2.0)]
    path = eq.write_liquid_table(rows, tmp_path / "t.txt")
    text = path.read_text()
    data = np.loadtxt(path)
    assert data.tolist() == [[0.01, 1.9, 2.0], [0.02, 2.0, 4.0]]
    assert "-fs_msd_liquid_mass 2.1" in text and "left out: A = 0.004" in text and "6.05 Hz" in text
    with pytest.raises(ValueError, match="2 values of frequency"):
        eq.write_liquid_table(rows + [_row(0.03, frequency=5.0)], tmp_path / "u.txt")
    with pytest.raises(ValueError, match="1 settled rows of 2"):
        eq.write_liquid_table(rows[:2], tmp_path / "u.txt")
    with pytest.raises(ValueError, match="heave grid"):
        eq.write_liquid_table([dict(r, direction="sway") for r in rows], tmp_path / "u.txt")

"""The tank's sloshing frequencies from a free decay (flexslosh.modes, docs/equivalent.md "The tank's sloshing
frequencies"): the signal analysis recovers a damped two-mode signal exactly, and the experiment finds the 2-D
rectangular tank's first mode (linear potential theory, rectangular_modes) at a coarse resolution; the sloshing
masses come back exactly from the load of two damped mass-spring oscillators moved by the same step, and the
tank's first sloshing mass converges to theory's.

Measured (tank 0.2 m long, 0.1 m deep, c0 = 10 m/s, a 2 mm step over half the estimated period, 7 periods):
f_1 = 1.8223 Hz at dx = 2 cm (-3.7 %), 1.8893 Hz at 1 cm (-0.15 %), 1.8970 Hz at 5 mm (+0.26 %) against 1.8921 Hz;
m_1 / m = 0.3822, 0.4490 and 0.4683 against 0.4733 (-19.2, -5.1, -1.1 %: order 1.9, then 2.3).
"""
import math

import numpy as np
import pytest

from flexslosh import modes
from flexslosh.equivalent import rectangular_modes

L, H = 0.2, 0.1
TANK = {"fs_case": "tank", "fs_tank_shape": "rectangular", "fs_tank_length": L, "fs_tank_height": 2 * H,
        "fs_fill": 0.5, "fs_c0": 10, "fs_relax_time": 0.1, "fs_dx": 0.01}


def test_analysis_recovers_a_damped_two_mode_signal():
    """Two damped modes (1.9 and 3.4 Hz, damping ratios 0.02 and 0.05, the second 5 times weaker) plus an
    offset, unevenly sampled over 4 s: the frequencies, damping ratios and amplitudes come back to 1e-6."""
    rng = np.random.default_rng(3)
    t = np.r_[0.0, np.sort(rng.uniform(0.0, 4.0, 900))]
    f, z, a = [1.9, 3.4], [0.02, 0.05], [2e-3, 4e-4]
    y = 1e-4 + sum(ak * np.exp(-zk * 2 * np.pi * fk / math.sqrt(1 - zk**2) * t) * np.cos(2 * np.pi * fk * t + ph)
                   for fk, zk, ak, ph in zip(f, z, a, (0.3, -1.1)))
    r = modes.analyse(t, y, 2)
    assert len(r.modes) == 2
    for m, fk, zk, ak in zip(r.modes, f, z, a):
        assert m.frequency == pytest.approx(fk, rel=1e-6)
        assert m.damping == pytest.approx(zk, rel=1e-5)
        assert m.amplitude == pytest.approx(ak, rel=1e-5)
        assert m.sigma < 1e-6  # no residual: no uncertainty
        assert abs(m.fft_frequency - fk) < r.resolution / 2  # the windowed FFT's peak: within half a bin
    assert r.resolution == pytest.approx(1 / (t[-1] - t[0]))
    # with noise the uncertainty covers the error
    noisy = y + rng.normal(0, 2e-4, len(t))
    r = modes.analyse(t, noisy, 2)
    for m, fk in zip(r.modes, f):
        assert abs(m.frequency - fk) < 4 * m.sigma
        assert 0 < m.sigma < 0.05 * fk


def test_rectangular_tank_first_mode(tmp_path, capsys):
    """The 2-D rectangular tank at dx = L/20 (h/dx = 10): the first sloshing frequency within 1 % of linear
    theory's (measured -0.15 %), its uncertainty below 1 %; the table and modes.json written."""
    r = modes.sloshing_modes(TANK, direction="x", output_dir=tmp_path / "modes", progress=None)
    exact = rectangular_modes(L, H, 1)[0][0] / (2 * np.pi)
    assert r.length == pytest.approx(L) and r.depth == pytest.approx(H)
    assert r.estimate[0] == pytest.approx(exact, rel=1e-12)
    f1 = r.analysis.modes[0]
    assert f1.frequency == pytest.approx(exact, rel=0.01)
    assert f1.sigma < 0.01 * exact
    assert 0 <= f1.damping < 0.02
    assert (tmp_path / "modes" / "modes.json").is_file()
    assert "rectangular[Hz]" in r.table()
    # the first sloshing mass from the load on the tank held still (measured 0.4490 +- 0.0015 against 0.4733)
    assert r.estimate_mass[0] == pytest.approx(0.47327, abs=1e-5)
    assert abs(f1.mass / r.liquid_mass - r.estimate_mass[0]) < 0.03 and f1.mass_sigma < 0.005 * r.liquid_mass


def test_sloshing_masses_of_two_oscillators():
    """The equivalent mechanical model itself: two masses on springs (11.9 and 21.5 rad/s, m_n = 0.47 and 0.019 kg,
    damping ratios 0.002 and 0.03) inside a tank moved by the quintic step of 2 mm over 0.26 s, then held still;
    their pull on the tank after the step, fitted at the modes' own frequencies and decays, gives back m_n to 1e-4
    (a step's transfer |J(omega)| off by a factor would fail it)."""
    from scipy.integrate import solve_ivp

    w, m, z = np.array([11.9, 21.5]), np.array([0.47, 0.019]), np.array([0.002, 0.03])
    amp, dur = 0.002, 0.26

    def xdd(t):  # the step's acceleration, s''(u) amp / dur^2
        u = min(max(t / dur, 0.0), 1.0)
        return amp / dur**2 * (60 * u - 180 * u**2 + 120 * u**3) if 0 <= t <= dur else 0.0

    def rhs(t, q):  # q_n'' + 2 z_n w_n q_n' + w_n^2 q_n = -X''(t), relative to the tank
        return np.r_[q[2:], -2 * z * w * q[2:] - w**2 * q[:2] - xdd(t)]

    t = np.linspace(dur, dur + 4.0, 800)
    sol = solve_ivp(rhs, (0, t[-1]), np.zeros(4), t_eval=t, rtol=1e-11, atol=1e-14, max_step=1e-3)
    load = (m * (w**2 * sol.y[:2].T + 2 * z * w * sol.y[2:].T)).sum(axis=1)  # the springs' and dampers' pull
    wd = w * np.sqrt(1 - z**2)
    ms = [modes.Mode(float(f), 0.0, float(zz), 1.0, float(f)) for f, zz in zip(wd / (2 * np.pi), z)]
    for (mn, sn), mk in zip(modes.sloshing_masses(t, load, ms, amp, dur), m):
        assert mn == pytest.approx(mk, rel=1e-4)


def test_bad_direction_and_options(tmp_path):
    with pytest.raises(ValueError, match="direction 'y'"):
        modes.sloshing_modes(TANK, direction="y", output_dir=tmp_path, progress=None)
    with pytest.raises(ValueError, match="fs_structure"):
        modes.sloshing_modes({**TANK, "fs_structure": "msd"}, output_dir=tmp_path, progress=None)
    with pytest.raises(ValueError, match="direction z: a 3-D case only"):
        modes.sloshing_modes(TANK, direction="z", output_dir=tmp_path, progress=None)

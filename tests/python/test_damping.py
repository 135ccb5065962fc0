"""flexslosh.damping: peaks and damping per cycle against exact damped oscillations."""
import numpy as np
import pytest

from flexslosh.damping import damping_per_cycle, find_peaks, write_damping_csv


def damped(t, zeta, f, phase=0.0):
    w = 2 * np.pi * f
    wd = w * np.sqrt(1 - zeta**2)
    return np.exp(-zeta * w * t) * np.cos(wd * t + phase), wd


@pytest.mark.parametrize("zeta", [0.005, 0.015, 0.08])
def test_constant_damping_recovered(zeta):
    t = np.linspace(0, 4, 20001)
    y, wd = damped(t, zeta, 3.0)
    c = damping_per_cycle(t, y)
    assert len(c.zeta) >= 10
    # every cycle after the first (whose peak is the record's start) gives zeta to 1e-4 relative
    assert np.allclose(c.zeta[1:-1], zeta, rtol=1e-3)
    assert np.allclose(c.period[1:], 2 * np.pi / wd, rtol=1e-4)
    assert np.all(np.diff(c.amplitude) < 0)


def test_noise_and_offset():
    rng = np.random.default_rng(0)
    t = np.linspace(0, 3, 30001)
    y, _ = damped(t, 0.015, 3.0)
    yn = 2.5 + y + 0.01 * rng.standard_normal(len(t))
    c = damping_per_cycle(t, yn, offset=2.5)
    assert len(c.zeta) == 8  # no spurious lobes from the noise at the crossings
    assert abs(np.median(c.zeta) - 0.015) < 0.004


def test_amplitude_dependent_damping():
    """A decay whose damping grows with amplitude (like a sloshing tank's): zeta_i falls with A_i."""
    t = np.linspace(0, 6, 60001)
    w = 2 * np.pi * 2.0
    # dA/dt = -(z0 + z1 A) w A: the decrement per cycle grows with A
    z0, z1 = 0.01, 0.1
    A = np.empty_like(t)
    A[0] = 1.0
    dt = t[1] - t[0]
    for k in range(1, len(t)):
        A[k] = A[k - 1] - dt * (z0 + z1 * A[k - 1]) * w * A[k - 1]
    c = damping_per_cycle(t, A * np.cos(w * t))
    assert np.all(np.diff(c.zeta) < 0)
    assert c.zeta[-1] == pytest.approx(z0 + z1 * c.amplitude[-1], rel=0.1)


def test_peaks_alternate_and_csv(tmp_path):
    t = np.linspace(0, 2, 4001)
    y, _ = damped(t, 0.02, 2.0)
    p = find_peaks(t, y)
    assert np.all(np.sign(p.value[:-1]) != np.sign(p.value[1:]))
    c = damping_per_cycle(t, y)
    path = tmp_path / "damping.csv"
    write_damping_csv(str(path), c)
    back = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    assert back.shape == (len(c.zeta), 5)
    assert open(path).readline().strip() == "time,amplitude,period,delta,zeta"


def test_bad_input():
    with pytest.raises(ValueError, match="same length"):
        find_peaks(np.arange(4.0), np.arange(3.0))
    with pytest.raises(ValueError, match="NaN"):
        find_peaks(np.arange(4.0), np.array([0, 1, np.nan, 0]))
    assert len(damping_per_cycle(np.arange(2.0), np.arange(2.0)).zeta) == 0


def test_nonuniform_steps():
    """Time steps that shrink tenfold (a slam in a coupled run): lobes are compared by duration, not by
    sample count, so none is merged away."""
    dt = np.concatenate([np.full(400, 5e-4), np.full(20000, 5e-5)])
    t = np.concatenate([[0.0], np.cumsum(dt)])
    y, wd = damped(t, 0.015, 6.0)
    c = damping_per_cycle(t, y)
    assert len(c.zeta) == 6  # peaks at 0, 1/6, ..., 1 s; the lobe cut by the end at 1.2 s is dropped
    assert np.allclose(c.zeta[1:], 0.015, rtol=2e-3)


def test_convergence_recovers_order_and_limit():
    # f(dx) = f0 + C dx^p at dx = 4, 2, 1 (ratio 2): the observed order p and Richardson's limit f0 exactly;
    # changes that grow, or change sign, are outside the asymptotic range: NaN
    from flexslosh.damping import convergence
    f0, C, p = np.array([3.0, 2.0]), np.array([0.5, -0.2]), np.array([2.0, 1.0])
    f = [f0 + C * dx**p for dx in (4.0, 2.0, 1.0)]
    c = convergence(*f)
    assert np.allclose(c.order, p) and np.allclose(c.extrapolated, f0)
    assert np.allclose(c.change, np.abs(f[2] - f[1]))
    assert np.allclose(c.uncertainty, 1.25 * np.abs(f[2] - f0))
    bad = convergence([1.0, 1.0], [2.0, 0.5], [4.0, 0.7])
    assert np.all(np.isnan(bad.order)) and np.all(np.isnan(bad.extrapolated))


def test_band_damping():
    from flexslosh.damping import SEED_BANDS, CycleDamping, band_damping
    a = np.array([0.039, 0.030, 0.020, 0.012, 0.011, 0.003])
    z = np.array([0.02, 0.04, 0.05, 0.03, 0.01, 0.02])
    c = CycleDamping(np.arange(6.0), a, np.ones(6), z, z)
    b = band_damping(c, SEED_BANDS)
    assert np.allclose(b[[0, 1, 2, 5]], [0.03, 0.05, 0.02, 0.02]) and np.all(np.isnan(b[[3, 4]]))

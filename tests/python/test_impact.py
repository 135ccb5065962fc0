"""flexslosh.impact: the zero-phase low-pass has a Butterworth filter's squared gain and no phase shift, the filtered
peak of a slow pulse with a fast ringing on it is the pulse's, and the ringing's frequency is found."""
import math

import numpy as np
import pytest

from flexslosh.impact import dominant_frequency, impulse, lowpass, peak


def amplitude(t, y, f):
    """y's amplitude at frequency f (least squares on cos and sin)."""
    a = np.column_stack([np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)])
    c, *_ = np.linalg.lstsq(a, y, rcond=None)
    return float(np.hypot(*c)), float(np.arctan2(-c[1], c[0]))


@pytest.mark.parametrize("order", [1, 2])
def test_gain_is_the_butterworth_filters_squared(order):
    rate, fc = 20000.0, 100.0
    t = np.arange(0, 0.5, 1 / rate)
    y = np.cos(2 * np.pi * 20 * t) + np.cos(2 * np.pi * 400 * t + 0.3)
    tu, yf = lowpass(t, y, fc, order)
    assert np.allclose(tu, t)
    inner = (tu > 0.05) & (tu < 0.45)  # away from the mirrored ends
    for f, phase in ((20.0, 0.0), (400.0, 0.3)):
        gain = 1 / (1 + (f / fc) ** (2 * order))  # forwards and backwards: |H|^2; one pass would be its root
        a, ph = amplitude(tu[inner], yf[inner], f)
        assert a == pytest.approx(gain, rel=0.01), (f, a, gain)
        assert abs((ph - phase + np.pi) % (2 * np.pi) - np.pi) < 0.01  # no phase shift
    # the same record sampled unevenly gives the same filtered record
    rng = np.random.default_rng(1)
    tn = np.sort(np.concatenate([[0.0, 0.5 - 1 / rate], rng.uniform(0, 0.5 - 1 / rate, 30000)]))
    yn = np.cos(2 * np.pi * 20 * tn) + np.cos(2 * np.pi * 400 * tn + 0.3)
    tu2, yf2 = lowpass(tn, yn, fc, order, rate=rate)
    m = min(len(tu2), len(tu))
    assert np.max(np.abs(yf2[:m][inner[:m]] - yf[:m][inner[:m]])) < 0.02


def test_filtered_peak_is_the_pulses_not_the_ringing():
    """A 20 ms pulse of height 1 with a 430 Hz ringing of amplitude 2 after its start (the weakly compressible run's
    signature): the raw peak is the ringing's (about 2.9), the peak below the ringing's frequency the pulse's."""
    rate = 20000.0
    t = np.arange(0, 0.2, 1 / rate)
    pulse = np.exp(-(((t - 0.1) / 0.02) ** 2))
    ring = np.where(t > 0.09, 2 * np.exp(-(t - 0.09) / 0.02) * np.sin(2 * np.pi * 430 * (t - 0.09)), 0)
    p = pulse + ring
    assert peak(t, p, 0.05, 0.15)[1] > 2.5
    tp, pp = peak(t, p, 0.05, 0.15, cutoff=100)
    assert pp == pytest.approx(1.0, abs=0.03)
    assert tp == pytest.approx(0.1, abs=0.002)
    assert dominant_frequency(t, p, 0.09, 0.19, fmin=60) == pytest.approx(430, abs=10)
    assert np.isnan(peak(t, p, 1.0, 2.0)[1])
    # the impulse: the pulse's sqrt(pi) 0.02 whole, the ringing's part nearly cancelling (its exact integral below)
    ring_exact = 2 * 0.02 * (2 * np.pi * 430 * 0.02) / (1 + (2 * np.pi * 430 * 0.02) ** 2)
    assert impulse(t, p, 0.0, 0.1999) == pytest.approx(np.sqrt(np.pi) * 0.02 + ring_exact, rel=1e-4)
    assert impulse(t, pulse, 0.05, 0.1) == pytest.approx(np.sqrt(np.pi) * 0.02 / 2 * math.erf(2.5), rel=1e-5)
    with pytest.raises(ValueError, match="inside the record"):
        impulse(t, p, 0.1, 0.3)


@pytest.mark.parametrize("args,match", [
    (([0, 1, 2, 3], [0, 1, 2, 3], 0), "cutoff must be positive"),
    (([0, 1, 2, 3], [0, 1, 2], 10), "same length"),
    (([0, 1, 1, 3], [0, 1, 2, 3], 10), "increase strictly"),
])
def test_bad_input_is_named(args, match):
    with pytest.raises(ValueError, match=match):
        lowpass(*args)

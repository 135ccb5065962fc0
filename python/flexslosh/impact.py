"""Impact pressures from a probe's record: a zero-phase low-pass filter and the peak in a window.

A weakly compressible run rings: after an impact the liquid near the wall oscillates acoustically at a frequency
set by the run's sound speed (about c0 / (4 L), L the depth of the liquid struck; it doubles when c0 doubles), with
an amplitude that grows with c0. Those oscillations are the model's, not the liquid's (real water rings at tens of
kHz and the impact has left by then), and they make the raw peak depend on c0 without end (docs/design-pressures.md).
The impact itself, the liquid turning at the wall, is slower. Low-passed below the run's acoustic frequency, the
peak no longer depends on c0 once c0 puts that frequency well above the cut-off, and the same filter applied to a
measured record gives the quantity to compare it with.

    lowpass(t, p, cutoff, order=2)      the record on a uniform grid, filtered without phase shift
    peak(t, p, t0, t1, cutoff=None)     the largest value in [t0, t1] (of the filtered record with a cut-off)
    dominant_frequency(t, p, t0, t1)    the frequency of the largest oscillation in [t0, t1] (the run's ringing)
    impulse(t, p, t0, t1)               the pressure impulse, the integral of p over [t0, t1]

The pressure impulse over a window after the arrival does not see the ringing's swings (they cancel) and measures
what an impact hands the wall as momentum (Cooker & Peregrine's pressure-impulse theory: it stays finite where the
peak of an ideal impact does not).
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

__all__ = ["lowpass", "peak", "dominant_frequency", "impulse"]


def _uniform(t: Sequence[float], p: Sequence[float], rate: Optional[float]) -> tuple[np.ndarray, np.ndarray, float]:
    t = np.asarray(t, float)
    p = np.asarray(p, float)
    if t.ndim != 1 or t.shape != p.shape or len(t) < 4:
        raise ValueError(f"t and p must be 1-D arrays of the same length (at least 4): got shapes {t.shape} and {p.shape}")
    if not np.all(np.diff(t) > 0):
        raise ValueError("t must increase strictly")
    if rate is None:
        rate = 1.0 / float(np.median(np.diff(t)))
    if not rate > 0:
        raise ValueError(f"rate must be positive: got {rate}")
    n = int(np.floor((t[-1] - t[0]) * rate)) + 1
    tu = t[0] + np.arange(n) / rate
    return tu, np.interp(tu, t, p), rate


def lowpass(t: Sequence[float], p: Sequence[float], cutoff: float, order: int = 2,
            rate: Optional[float] = None) -> tuple[np.ndarray, np.ndarray]:
    """The record p(t) resampled on a uniform grid (``rate`` Hz; default the record's median sampling rate) and
    low-passed without phase shift: its spectrum multiplied by 1 / (1 + (f / cutoff)^(2 order)), the gain of a
    Butterworth filter of that order run forwards and backwards. The record is mirrored at both ends first, so its
    ends do not wrap onto each other. Returns (t_uniform, p_filtered)."""
    if not cutoff > 0:
        raise ValueError(f"cutoff must be positive (Hz): got {cutoff}")
    if int(order) != order or order < 1:
        raise ValueError(f"order must be a positive integer: got {order}")
    tu, pu, rate = _uniform(t, p, rate)
    ext = np.concatenate([pu[::-1], pu, pu[::-1]])
    f = np.fft.rfftfreq(len(ext), 1.0 / rate)
    gain = 1.0 / (1.0 + (f / cutoff) ** (2 * int(order)))
    out = np.fft.irfft(np.fft.rfft(ext) * gain, len(ext))
    return tu, out[len(pu): 2 * len(pu)]


def peak(t: Sequence[float], p: Sequence[float], t0: float, t1: float, cutoff: Optional[float] = None, order: int = 2,
         rate: Optional[float] = None) -> tuple[float, float]:
    """The largest value of p over [t0, t1] and its time: of the raw record, or with ``cutoff`` of the record
    low-passed by lowpass() (filtered whole, then windowed, so the window's edges are not the record's).
    (nan, nan) where the window holds no sample."""
    if cutoff is None:
        tt, pp = np.asarray(t, float), np.asarray(p, float)
    else:
        tt, pp = lowpass(t, p, cutoff, order, rate)
    sel = (tt >= t0) & (tt <= t1)
    if not np.any(sel):
        return float("nan"), float("nan")
    k = int(np.argmax(np.where(sel, pp, -np.inf)))
    return float(tt[k]), float(pp[k])


def dominant_frequency(t: Sequence[float], p: Sequence[float], t0: float, t1: float, fmin: float = 0.0,
                       rate: Optional[float] = None) -> float:
    """The frequency (Hz) of the largest peak above ``fmin`` in the spectrum of p over [t0, t1] (Hann window, mean
    removed): in a weakly compressible run's pressure after an impact, the run's acoustic ringing."""
    tu, pu, rate = _uniform(t, p, rate)
    sel = (tu >= t0) & (tu <= t1)
    if np.count_nonzero(sel) < 8:
        raise ValueError(f"the window [{t0}, {t1}] holds fewer than 8 samples")
    x = pu[sel] - pu[sel].mean()
    spec = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    f = np.fft.rfftfreq(len(x), 1.0 / rate)
    spec[f <= fmin] = 0
    return float(f[int(np.argmax(spec))])


def impulse(t: Sequence[float], p: Sequence[float], t0: float, t1: float) -> float:
    """The integral of p over [t0, t1] (trapezoids on the record's own samples, p interpolated at the window's ends):
    the pressure impulse (Pa s for p in Pa). The window must lie inside the record."""
    t = np.asarray(t, float)
    p = np.asarray(p, float)
    if t.ndim != 1 or t.shape != p.shape or len(t) < 2:
        raise ValueError(f"t and p must be 1-D arrays of the same length (at least 2): got shapes {t.shape} and {p.shape}")
    if not (t[0] <= t0 < t1 <= t[-1]):
        raise ValueError(f"the window [{t0}, {t1}] must lie inside the record [{t[0]}, {t[-1]}]")
    inside = (t > t0) & (t < t1)
    tt = np.concatenate([[t0], t[inside], [t1]])
    pp = np.interp(tt, t, p)
    return float(np.sum(0.5 * (pp[1:] + pp[:-1]) * np.diff(tt)))

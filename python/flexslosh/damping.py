"""Damping of a decaying oscillation: its peaks and the damping ratio per cycle.

For a signal y(t) oscillating about ``offset`` (the tip displacement or acceleration of a free
decay), the positive peaks A_i give the logarithmic decrement of each cycle

    delta_i = ln(A_i / A_{i+1}),    zeta_i = delta_i / sqrt(4 pi^2 + delta_i^2),

reported against the cycle's amplitude (the decay of a sloshing tank depends on the amplitude, so one
number for the whole run says little; docs/validation.md). fit_envelope gives the one number of the
seed's Fig. 10 anyway: the slope of ln|peak| against time, zeta = -slope / omega.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Peaks", "CycleDamping", "Envelope", "find_peaks", "damping_per_cycle", "fit_envelope", "write_damping_csv",
           "SEED_BANDS", "band_damping", "Convergence", "convergence"]


@dataclass
class Peaks:
    """Extrema of an oscillation, one per lobe between two crossings of the offset.

    Attributes:
        time: time of each extremum (parabolic refinement of the sampled maximum).
        value: the signal's value there, minus the offset (positive for maxima, negative for minima).
    """

    time: np.ndarray
    value: np.ndarray


@dataclass
class CycleDamping:
    """Damping per cycle of a decaying oscillation (one row per pair of successive positive peaks).

    Attributes:
        time: time of the cycle's first peak.
        amplitude: the cycle's first peak A_i (above the offset).
        period: time between the two peaks.
        delta: logarithmic decrement ln(A_i / A_{i+1}).
        zeta: damping ratio delta / sqrt(4 pi^2 + delta^2).
    """

    time: np.ndarray
    amplitude: np.ndarray
    period: np.ndarray
    delta: np.ndarray
    zeta: np.ndarray

    def as_array(self) -> np.ndarray:
        """The table as an (n, 5) array: time, amplitude, period, delta, zeta."""
        return np.column_stack([self.time, self.amplitude, self.period, self.delta, self.zeta])


def _refine(t: np.ndarray, z: np.ndarray, a: int, b: int, k: int, s: int) -> tuple[float, float]:
    """The extremum of lobe z[a:b] (sign s, sampled extremum at k): the vertex of the least-squares
    parabola through the lobe's samples within 20 % of the extremum, so that noise on single samples
    averages out; its bias is nearly the same fraction of every peak, so it cancels in the decrements."""
    seg = z[a:b] * s
    # the contiguous run around k
    lo = hi = k - a
    while lo - 1 >= 0 and seg[lo - 1] >= 0.8 * seg[k - a]:
        lo -= 1
    while hi + 1 < len(seg) and seg[hi + 1] >= 0.8 * seg[k - a]:
        hi += 1
    if hi - lo < 2:
        return float(t[k]), float(z[k])
    tt = t[a + lo : a + hi + 1]
    tc = tt.mean()
    c2, c1, c0 = np.polyfit(tt - tc, seg[lo : hi + 1], 2)
    if c2 >= 0:
        return float(t[k]), float(z[k])
    tv = -c1 / (2 * c2)
    if not (tt[0] - tc <= tv <= tt[-1] - tc):
        return float(t[k]), float(z[k])
    return float(tv + tc), float(s * (c0 - c1 * c1 / (4 * c2)))


def find_peaks(t: np.ndarray, y: np.ndarray, offset: float = 0.0, hysteresis: float = 0.05) -> Peaks:
    """Extrema of an oscillation about offset, one per lobe.

    The signal is split into lobes where it crosses the offset; a crossing counts only once the
    signal has gone beyond hysteresis times the extremum of the lobe it leaves, so that noise near the
    crossings (SPH accelerations are noisy) does not split a lobe. A first lobe that begins at the
    record's start counts (a release from rest starts at an extremum); the last lobe, which the
    record's end cuts, does not. Lobes much shorter than the median one (a noise excursion across
    the offset) are merged with their neighbours.

    Args:
        t: sample times (increasing).
        y: samples.
        offset: the equilibrium about which y oscillates.
        hysteresis: the dead band, as a fraction of the extremum of the lobe being left.

    Returns:
        The extrema (time and value minus offset), in time order, alternating in sign.
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(y, dtype=float) - offset
    if t.shape != z.shape or t.ndim != 1:
        raise ValueError(f"find_peaks: t and y must be 1-D arrays of the same length (got {t.shape} and {z.shape})")
    if not np.all(np.isfinite(z)):
        raise ValueError("find_peaks: y holds NaN or infinite values")
    if len(z) < 3:
        return Peaks(np.empty(0), np.empty(0))
    # lobes: a crossing of the offset counts once the signal has gone beyond hysteresis times the
    # extremum of the lobe it leaves (a dead band that follows the decaying amplitude)
    scale = float(np.max(np.abs(z)))
    if scale == 0:
        return Peaks(np.empty(0), np.empty(0))
    starts: list[int] = []  # first sample of each lobe
    signs: list[int] = []
    state, extremum = 0, 0.0
    for k, v in enumerate(z):
        if state == 0:
            if abs(v) > 1e-12 * scale:
                state, extremum = (1 if v > 0 else -1), abs(v)
                starts.append(0)
                signs.append(state)
            continue
        if v * state > 0:
            extremum = max(extremum, abs(v))
        elif -v * state > hysteresis * extremum:
            j = k  # the new lobe begins after the last crossing of the offset before k
            while j > 0 and z[j - 1] * state < 0:
                j -= 1
            state, extremum = -state, abs(v)
            starts.append(j)
            signs.append(state)
    # a noise excursion across the offset makes two short lobes: merge lobes much shorter than the
    # median one with their neighbours (which have the same sign) until none is left
    while len(starts) > 3:
        lengths = np.diff(np.append(t[starts], t[-1]))  # durations: steps need not be uniform
        n = int(np.argmin(lengths[1:-1])) + 1  # the end lobes may be cut by the record
        if lengths[n] >= 0.3 * np.median(lengths):
            break
        del starts[n : n + 2], signs[n : n + 2]  # lobe n and the next, which lobe n - 1 absorbs
    times: list[float] = []
    values: list[float] = []
    for n, (a, s) in enumerate(zip(starts, signs)):
        if n + 1 == len(starts):
            break  # the record ends inside the last lobe: its extremum may be cut
        b = starts[n + 1]
        k = a + int(np.argmax(z[a:b] * s))
        tk, vk = _refine(t, z, a, b, k, s)
        times.append(tk)
        values.append(vk)
    return Peaks(np.array(times), np.array(values))


def damping_per_cycle(t: np.ndarray, y: np.ndarray, offset: float = 0.0, hysteresis: float = 0.05) -> CycleDamping:
    """Logarithmic decrement and damping ratio of each cycle of a decaying oscillation.

    Args:
        t: sample times (increasing).
        y: samples of the oscillation (tip displacement, velocity or acceleration).
        offset: the equilibrium about which y oscillates.
        hysteresis: see find_peaks.

    Returns:
        One row per pair of successive positive peaks (A_i, A_{i+1}).
    """
    pk = find_peaks(t, y, offset, hysteresis)
    pos = pk.value > 0
    tp, ap = pk.time[pos], pk.value[pos]
    if len(ap) < 2:
        e = np.empty(0)
        return CycleDamping(e, e, e, e, e)
    delta = np.log(ap[:-1] / ap[1:])
    zeta = delta / np.sqrt(4 * np.pi**2 + delta**2)
    return CycleDamping(tp[:-1], ap[:-1], np.diff(tp), delta, zeta)


@dataclass
class Envelope:
    """The exponential fitted to the peaks of |y - offset| (seed Fig. 10).

    For a linear damped oscillation the envelope is exp(-zeta omega t), so the slope of ln(envelope)
    against time gives zeta = -slope / omega, omega = 2 pi / period.

    Attributes:
        time: time of each peak (maxima and minima).
        amplitude: |peak - offset|.
        slope: least-squares slope of ln(amplitude) against time (1/s).
        intercept: the fit's ln(amplitude) at t = 0.
        period: the mean period, twice the mean time between successive peaks.
        zeta: -slope * period / (2 pi).
    """

    time: np.ndarray
    amplitude: np.ndarray
    slope: float
    intercept: float
    period: float
    zeta: float

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """The fitted envelope exp(intercept + slope t)."""
        return np.exp(self.intercept + self.slope * np.asarray(t, dtype=float))


def fit_envelope(t: np.ndarray, y: np.ndarray, offset: float = 0.0, hysteresis: float = 0.05) -> Envelope:
    """Fits an exponential to the peaks of |y - offset| (one per lobe, see find_peaks).

    Args:
        t: sample times (increasing).
        y: samples of the oscillation (e.g. the tip acceleration).
        offset: the equilibrium about which y oscillates.
        hysteresis: see find_peaks.

    Returns:
        The peaks and the fit.

    Raises:
        ValueError: fewer than two peaks (less than a half cycle recorded).
    """
    pk = find_peaks(t, y, offset, hysteresis)
    amp = np.abs(pk.value)
    keep = amp > 0
    tp, amp = pk.time[keep], amp[keep]
    if len(amp) < 2:
        raise ValueError(f"fit_envelope: {len(amp)} peak(s) found, at least two are needed")
    slope, intercept = np.polyfit(tp, np.log(amp), 1)
    period = 2.0 * float(np.mean(np.diff(tp)))
    return Envelope(tp, amp, float(slope), float(intercept), period, float(-slope * period / (2 * np.pi)))


def write_damping_csv(path: str, cycles: CycleDamping) -> None:
    """Writes the damping per cycle to a CSV file (time,amplitude,period,delta,zeta), atomically."""
    import os

    tmp = f"{path}.tmp"
    np.savetxt(tmp, cycles.as_array(), delimiter=",", header="time,amplitude,period,delta,zeta", comments="", fmt="%.10g")
    os.replace(tmp, path)


#: The amplitude bands (m, from the largest) over which the seed's damping per cycle is averaged
#: (docs/seed-experiment.md): the first slams, the sloshing, the decay towards the structure's own damping.
SEED_BANDS: tuple[tuple[float, float], ...] = ((0.040, 0.025), (0.025, 0.015), (0.015, 0.010), (0.010, 0.006),
                                               (0.006, 0.004), (0.004, 0.0025))


def band_damping(cycles: CycleDamping, bands: tuple[tuple[float, float], ...] = SEED_BANDS) -> np.ndarray:
    """The mean damping ratio of the cycles whose amplitude lies in each band (hi >= A > lo); NaN for an empty band."""
    out = np.full(len(bands), np.nan)
    for k, (hi, lo) in enumerate(bands):
        m = (cycles.amplitude <= hi) & (cycles.amplitude > lo)
        if np.any(m):
            out[k] = float(np.mean(cycles.zeta[m]))
    return out


@dataclass
class Convergence:
    """A quantity at three resolutions refined by a constant ratio r (coarse, medium, fine), per component.

    Attributes:
        order: the observed order p = ln(|f1 - f2| / |f2 - f3|) / ln r (NaN where the changes do not shrink
            monotonically: the sequence is then not in its asymptotic range).
        extrapolated: Richardson's estimate f3 + (f3 - f2) / (r^p - 1) (NaN with the order).
        uncertainty: 1.25 |f3 - f2| / (r^p - 1), Roache's grid convergence index with its safety factor
            (NaN with the order).
        change: |f3 - f2|, the change between the two finest.
    """

    order: np.ndarray
    extrapolated: np.ndarray
    uncertainty: np.ndarray
    change: np.ndarray


def convergence(f1: np.ndarray, f2: np.ndarray, f3: np.ndarray, ratio: float = 2.0) -> Convergence:
    """The observed order of convergence, Richardson's extrapolation and its uncertainty from values at three
    resolutions (each refined by ``ratio``), component by component; see :class:`Convergence`."""
    f1, f2, f3 = (np.atleast_1d(np.asarray(f, dtype=float)) for f in (f1, f2, f3))
    d21, d32 = f2 - f1, f3 - f2
    with np.errstate(divide="ignore", invalid="ignore"):
        monotone = (d21 * d32 > 0) & (np.abs(d32) < np.abs(d21))
        p = np.where(monotone, np.log(np.abs(d21 / d32)) / np.log(ratio), np.nan)
        denom = ratio**p - 1
        ext = np.where(monotone, f3 + d32 / denom, np.nan)
        unc = np.where(monotone, 1.25 * np.abs(d32) / denom, np.nan)
    return Convergence(p, ext, unc, np.abs(d32))


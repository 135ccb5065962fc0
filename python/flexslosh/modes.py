"""The tank's linear sloshing frequencies and masses, for a tank of any shape, from a free-decay experiment.

``sloshing_modes`` moves the tank of a case (2-D walls, a 3-D box or an STL tank, any fill) by a small smooth
displacement step along one horizontal direction (x, or z in 3-D), over a fraction of the expected first period,
with the prescribed motion (``-fs_structure prescribed``, a ``-fs_motion_<c>_file`` written here), then holds it
still, and records the free surface at two wave gauges near the two end walls (a ``-fs_probes`` file written here).
The difference of the two elevations is the antisymmetric part of the sloshing, which a sway excites; its
spectral peaks are the sloshing frequencies: a Hann-windowed FFT finds them, a least-squares fit of a sum of
damped sinusoids refines them and gives each one's standard uncertainty and damping ratio (``analyse``). The load
on the tank held still after the step, fitted at those frequencies, gives each mode's sloshing mass, the m_n of the
equivalent mechanical model (``sloshing_masses``). The run
lasts a number of periods of the first mode's estimate from the rectangular tank's formula, omega_1^2 = g k
tanh(k h), k = pi/L, L the liquid's length along the direction and h its depth at rest (``rectangular_modes`` of
flexslosh.equivalent). The command line::

    python3 -m flexslosh.modes --options-file cases/own_tank.opts --direction x --out output/modes -fs_dx 0.004

prints a table (mode, frequency, period, the rectangular estimate, the uncertainty, m_n / m and the rectangular
estimate's) and writes modes.json. Why a
free decay, its resolution and what it was checked against: docs/equivalent.md, "The tank's sloshing
frequencies".
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .equivalent import petsc_options, rectangular_modes

__all__ = ["Mode", "Analysis", "analyse", "step_transfer", "sloshing_masses", "tank_geometry", "pulse_motion",
           "sloshing_modes", "main"]

#: direction -> (the motion's component, the axis index)
AXES = {"x": ("x", 0), "z": ("z", 2)}


# ----------------------------------------------------------------------------- the signal's analysis


@dataclass
class Mode:
    """One spectral peak of the signal: the FFT's estimate, refined by the damped-sinusoid fit."""
    frequency: float  # Hz, the fit's damped frequency
    sigma: float  # Hz, its standard uncertainty (the fit's covariance, corrected for correlated residuals)
    damping: float  # the damping ratio zeta (decay rate over the undamped angular frequency)
    amplitude: float  # the fitted amplitude at the record's start (the signal's unit)
    fft_frequency: float  # Hz, the windowed FFT's peak (parabolic interpolation)
    mass: float = float("nan")  # kg, the sloshing mass m_n (2-D: times the tank's width), from the load (sloshing_masses)
    mass_sigma: float = float("nan")  # kg, its standard uncertainty

    @property
    def period(self) -> float:
        return 1 / self.frequency


@dataclass
class Analysis:
    modes: list[Mode]
    resolution: float  # Hz, 1 / the record's length: the FFT's bin spacing
    duration: float  # s, the record analysed
    samples: int
    residual: float  # the fit's rms residual over the signal's rms


def _model(p: np.ndarray, t: np.ndarray, n: int) -> np.ndarray:
    """sum_k exp(-s_k t) (a_k cos 2 pi f_k t + b_k sin 2 pi f_k t) + c; p = [f_k, s_k, a_k, b_k]*n + [c]."""
    y = np.full_like(t, p[-1])
    for k in range(n):
        f, s, a, b = p[4 * k:4 * k + 4]
        w = 2 * np.pi * f * t
        y += np.exp(-s * t) * (a * np.cos(w) + b * np.sin(w))
    return y


def _spectrum_peaks(t: np.ndarray, y: np.ndarray, n: int, floor: float = 0.02) -> list[float]:
    """The n largest local maxima of the Hann-windowed, zero-padded spectrum of y (uniform t) above ``floor`` of
    the largest and above 1.5 bins, by parabolic interpolation of log |Y|; sorted by frequency."""
    dt = t[1] - t[0]
    m = len(y)
    pad = 1 << int(math.ceil(math.log2(16 * m)))
    spec = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(m), pad))
    freq = np.fft.rfftfreq(pad, dt)
    lo = 1.5 / (m * dt)
    peaks = [i for i in range(1, len(spec) - 1) if spec[i] >= spec[i - 1] and spec[i] > spec[i + 1] and freq[i] > lo]
    if not peaks:
        return []
    top = max(spec[i] for i in peaks)
    peaks = sorted((i for i in peaks if spec[i] >= floor * top), key=lambda i: -spec[i])[:n]
    out = []
    for i in peaks:
        a, b, c = np.log(spec[i - 1:i + 2] + 1e-300)
        d = 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c != 0 else 0.0
        out.append(float(freq[i] + d * (freq[1] - freq[0])))
    return sorted(out)


def _covariance(jac: np.ndarray, res: np.ndarray) -> np.ndarray:
    """The parameters' covariance of a least-squares fit, s^2 (J^T J)^-1 with s^2 the residuals' variance, times
    (1 + r)/(1 - r), r their lag-one autocorrelation (correlated residuals are fewer independent samples); NaN where
    J^T J is singular."""
    dof = max(len(res) - jac.shape[1], 1)
    r = float(np.corrcoef(res[:-1], res[1:])[0, 1]) if np.std(res) > 0 else 0.0
    r = min(max(r, 0.0), 0.999)
    try:
        return np.linalg.inv(jac.T @ jac) * float(res @ res) / dof * (1 + r) / (1 - r)
    except np.linalg.LinAlgError:
        return np.full((jac.shape[1], jac.shape[1]), np.nan)


def analyse(t: Sequence[float], y: Sequence[float], modes: int = 2) -> Analysis:
    """The sloshing frequencies in a free-decay record y(t): the ``modes`` largest peaks of its Hann-windowed FFT
    (resampled on a uniform grid; zero-padded 16 times, parabolic peak interpolation), then a nonlinear least-
    squares fit of as many damped sinusoids plus a constant, started from the peaks. Each mode's uncertainty is
    the fit's standard error of its frequency (covariance s^2 (J^T J)^-1), multiplied by sqrt((1 + r)/(1 - r)),
    r the residuals' lag-one autocorrelation (their effective number of independent samples). Modes whose fit did
    not converge to a positive frequency are dropped. Returns an ``Analysis`` (modes sorted by frequency)."""
    from scipy.optimize import least_squares

    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if len(t) < 16 or not np.all(np.diff(t) > 0):
        raise ValueError(f"analyse: {len(t)} samples; expected at least 16 at increasing times")
    tu = np.linspace(t[0], t[-1], len(t))
    yu = np.interp(tu, t, y)
    peaks = _spectrum_peaks(tu, yu, modes)
    dur = float(t[-1] - t[0])
    if not peaks:
        return Analysis([], 1 / dur, dur, len(t), float("nan"))
    ts = t - t[0]
    n = len(peaks)
    # the amplitudes for the FFT's frequencies and no decay, by linear least squares: the fit's start
    cols = [np.ones_like(ts)]
    for f in peaks:
        cols += [np.cos(2 * np.pi * f * ts), np.sin(2 * np.pi * f * ts)]
    lin, *_ = np.linalg.lstsq(np.array(cols).T, y, rcond=None)
    p0 = []
    for k, f in enumerate(peaks):
        p0 += [f, 0.0, lin[1 + 2 * k], lin[2 + 2 * k]]
    p0.append(lin[0])
    fit = least_squares(lambda p: _model(p, ts, n) - y, np.array(p0), x_scale="jac", method="lm", xtol=1e-14,
                        ftol=1e-14, gtol=1e-14, max_nfev=20000)
    p = fit.x
    res = fit.fun
    err = np.sqrt(np.maximum(np.diag(_covariance(fit.jac, res)), 0))
    out = []
    for k in range(n):
        f, s, a, b = p[4 * k:4 * k + 4]
        if not (f > 0):
            continue
        w = 2 * np.pi * f
        out.append(Mode(float(f), float(err[4 * k]), float(s / math.hypot(w, s)), float(math.hypot(a, b)),
                        float(peaks[k])))
    out.sort(key=lambda m: m.frequency)
    rel = float(np.sqrt(np.mean(res**2)) / max(np.std(y), 1e-300))
    return Analysis(out, 1 / dur, dur, len(t), rel)


def step_transfer(omega: float, amplitude: float, duration: float, decay: float = 0.0) -> float:
    """|J| = |int X''(t) exp((-decay + i omega) (T - t)) dt| over the displacement step X = amplitude s(u), u = t / T,
    T = duration, s(u) = 10u^3 - 15u^4 + 6u^5 (``pulse_motion``): an oscillator of damped frequency omega and decay
    rate decay, at rest before the step, is left with the displacement amplitude |J| / omega relative to the tank at
    its end (m/s)."""
    u = np.linspace(0.0, 1.0, 4097)
    s2 = 60 * u - 180 * u**2 + 120 * u**3
    f = s2 * np.exp((-decay + 1j * omega) * duration * (1 - u))
    integral = (f[0] + f[-1]) / 2 + f[1:-1].sum()
    return float(abs(integral) * (u[1] - u[0]) * amplitude / duration)


def sloshing_masses(t: Sequence[float], load: Sequence[float], modes: Sequence[Mode], amplitude: float,
                    duration: float) -> list[tuple[float, float]]:
    """The sloshing masses m_n of the equivalent mechanical model (a mass m_n on a spring of frequency omega_n for
    each mode, with a damper of ratio zeta_n, docs/equivalent.md) from the load on the tank held still after the
    displacement step: each mode, at rest before it, is left oscillating with the displacement amplitude
    |J| / omega_d (``step_transfer``, omega_d the damped frequency) relative to the tank, and its spring and damper
    pull the tank with m_n omega_n^2 times that (exactly: |omega_n^2 + 2 zeta_n omega_n (-zeta_n omega_n + i
    omega_d)| = omega_n^2). The load's amplitude at each
    mode's frequency and decay (``analyse``'s, from the gauges) comes from a linear least-squares fit from the
    record's start (the step's end), with a constant, and its standard
    uncertainty from the fit's covariance (corrected for correlated residuals as in ``analyse``); m_n =
    |F_n| omega_d / (omega_n^2 |J|). Returns
    [(m_n, sigma_n)] in the modes' order (the load's mass unit)."""
    t = np.asarray(t, float) - float(t[0])
    y = np.asarray(load, float)
    if not modes:
        return []
    wd = [2 * np.pi * m.frequency for m in modes]  # damped
    w0 = [w / math.sqrt(max(1 - m.damping**2, 1e-12)) for w, m in zip(wd, modes)]  # undamped
    cols = [np.ones_like(t)]
    for m, w, wn in zip(modes, wd, w0):
        decay = np.exp(-m.damping * wn * t)
        cols += [decay * np.cos(w * t), decay * np.sin(w * t)]
    A = np.array(cols).T
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    cov = _covariance(A, y - A @ coef)
    out = []
    for k, (m, w, wn) in enumerate(zip(modes, wd, w0)):
        a, b = coef[1 + 2 * k], coef[2 + 2 * k]
        amp = math.hypot(a, b)
        var = (a * a * cov[1 + 2 * k, 1 + 2 * k] + b * b * cov[2 + 2 * k, 2 + 2 * k]
               + 2 * a * b * cov[1 + 2 * k, 2 + 2 * k]) / max(amp * amp, 1e-300)
        scale = wn * wn / w * step_transfer(w, amplitude, duration, m.damping * wn)
        out.append((float(amp / scale), float(math.sqrt(max(var, 0.0)) / scale)))
    return out


# ----------------------------------------------------------------------------- the tank and the experiment


def _options(options: Mapping[str, Any] | None) -> dict:
    return {k.lstrip("-"): v for k, v in (options or {}).items()}


def tank_geometry(options: Mapping[str, Any] | None = None, options_file: str | os.PathLike | None = None,
                  direction: str = "x", comm=None) -> dict[str, Any]:
    """Sets the case up (no step) and reads from its liquid at rest: the dimension, dx, the liquid's length L along
    ``direction`` and its depth h (the particles' extents plus dx: the lattice sits dx/2 from the walls), and two
    vertical wave gauges, one at each end of the liquid along the direction (on the outermost particles' line,
    dx/2 from the wall; in 3-D at the middle of the other horizontal extent), each from the lowest particle of its
    column to the column's surface plus a margin (half the depth, at least 3 dx, at most half the gap to the lid
    that the fill gives: the tank's height h / fill above the floor). Returns a dict (on every rank)."""
    from .solver import Solver

    if direction not in AXES:
        raise ValueError(f"direction {direction!r}: expected x or z")
    opts = _options(options)
    opts.update({"fs_output_interval": 0, "fs_progress": False, "ts_max_time": 0})
    opts.setdefault("fs_output_dir", "output/modes/setup")
    with Solver(opts, options_file=options_file, comm=comm) as s:
        s.set_up()
        dim = s.dim
        dx = s.options.getReal("fs_dx", float("nan"))
        fill = s.options.getReal("fs_fill", float("nan"))
        relax = s.options.getReal("fs_relax_time", 0.0)
        for c in ("x", "y", "z", "roll", "pitch", "yaw", "axis"):
            for kind in ("sines", "poly", "file"):
                if s.options.hasName(f"fs_motion_{c}_{kind}"):
                    raise ValueError(f"-fs_motion_{c}_{kind} is set (by the case or the options): flexslosh.modes "
                                     f"moves the tank itself; remove it")
        x = s.positions(gather=True)
        dt = s.ts.getTimeStep()
        rank = s.comm.Get_rank()
        comm_ = s.comm
    geo = None
    if rank == 0:
        if direction == "z" and dim != 3:
            raise ValueError("direction z: a 3-D case only (a 2-D tank has x alone)")
        axis = AXES[direction][1]
        lo, hi = x.min(axis=0), x.max(axis=0)
        length = float(hi[axis] - lo[axis] + dx)
        depth = float(hi[1] - lo[1] + dx)
        floor = float(lo[1] - dx / 2)
        lid = floor + depth / fill if fill > 0 else float("inf")
        gauges = []
        for name, end in (("gauge_lo", lo[axis]), ("gauge_hi", hi[axis])):
            sel = np.abs(x[:, axis] - end) < 0.5 * dx
            other = None
            if dim == 3:
                b = 2 - axis  # the other horizontal axis
                mid = 0.5 * (lo[b] + hi[b])
                col = x[sel]
                other = float(col[np.argmin(np.abs(col[:, b] - mid)), b])
                sel &= np.abs(x[:, b] - other) < 0.5 * dx
            col = x[sel]
            bottom, top = float(col[:, 1].min()), float(col[:, 1].max() + dx / 2)
            margin = max(0.5 * depth, 3 * dx)
            if math.isfinite(lid):
                margin = min(margin, 0.5 * (lid - top))
            point = [float(end), bottom, other] if dim == 3 else [float(end), bottom]
            gauges.append({"name": name, "start": point, "end": [point[0], top + margin] + point[2:], "surface": top})
            if dim == 3 and axis == 2:  # the gauge's along-axis coordinate is z: swap x <-> z in the points
                for key in ("start", "end"):
                    p = gauges[-1][key]
                    p[0], p[2] = p[2], p[0]
        geo = {"dim": dim, "dx": dx, "fill": fill, "relax": relax, "length": length, "depth": depth, "floor": floor, "dt": dt,
               "gauges": gauges}
    return comm_.bcast(geo, root=0) if comm_.Get_size() > 1 else geo


def pulse_motion(path: str | os.PathLike, start: float, duration: float, amplitude: float, end: float) -> None:
    """Writes a ``-fs_motion_<c>_file`` time series: at rest until ``start``, then the displacement
    amplitude s(u), s(u) = 10u^3 - 15u^4 + 6u^5 (the rig's ramp: velocity and acceleration zero at both ends),
    u = (t - start)/duration, then held at ``amplitude`` until ``end``; 64 points over the step (the file's natural
    cubic spline then follows s to 1e-6 of the amplitude)."""
    u = np.linspace(0, 1, 65)
    t = np.r_[0.0, np.linspace(0.5, 0.9, 3) * start, start + u * duration,
              start + duration * np.array([1.1, 1.25, 1.5]), max(end, start + 2 * duration)]
    v = np.r_[np.zeros(4), amplitude * u**3 * (10 - 15 * u + 6 * u * u), np.full(4, amplitude)]
    with open(path, "w") as fp:
        fp.write(f"# flexslosh.modes: a displacement step of {amplitude!r} m over {duration!r} s from t = {start!r} s\n")
        for a, b in zip(t, v):
            fp.write(f"{a!r} {b!r}\n")


@dataclass
class Result:
    direction: str
    dim: int
    dx: float
    length: float
    depth: float
    amplitude: float
    pulse_start: float
    pulse_duration: float
    record_start: float
    record_end: float
    estimate: list[float]  # Hz: the rectangular formula's antisymmetric modes 1, 3, 5, ... (k = (2n-1) pi / L)
    analysis: Analysis
    output_dir: str
    gauges: list[dict] = field(default_factory=list)
    liquid_mass: float = float("nan")  # kg (2-D: times the tank's width)
    estimate_mass: list[float] = field(default_factory=list)  # the rectangular formula's m_n / m of the same modes

    def table(self) -> str:
        head = (f"sloshing modes along {self.direction}: L = {self.length:.4g} m, h = {self.depth:.4g} m, dx = {self.dx:.4g} m; "
                f"record {self.analysis.duration:.3g} s ({self.analysis.samples} samples), FFT resolution "
                f"{self.analysis.resolution:.3g} Hz, fit residual {self.analysis.residual:.2%} of the signal's rms")
        lines = [head, f"{'mode':>4} {'frequency[Hz]':>14} {'period[s]':>10} {'rectangular[Hz]':>16} "
                       f"{'uncertainty[Hz]':>16} {'damping':>9} {'fft[Hz]':>9} {'m_n/m':>8} {'+-':>8} {'rect.':>7}"]
        for i, m in enumerate(self.analysis.modes):
            est = self.estimate[i] if i < len(self.estimate) else float("nan")
            emass = self.estimate_mass[i] if i < len(self.estimate_mass) else float("nan")
            lines.append(f"{i + 1:>4} {m.frequency:>14.5f} {m.period:>10.5f} {est:>16.5f} {m.sigma:>16.2e} "
                         f"{m.damping:>9.2e} {m.fft_frequency:>9.4f} {m.mass / self.liquid_mass:>8.4f} "
                         f"{m.mass_sigma / self.liquid_mass:>8.4f} {emass:>7.4f}")
        return "\n".join(lines)

    def to_json(self) -> dict:
        d = asdict(self)
        d["units"] = {"frequency": "Hz", "period": "s", "length": "m", "depth": "m", "dx": "m", "amplitude": "m",
                      "sigma": "Hz", "estimate": "Hz", "time": "s", "mass": "kg (2-D: times the tank's width)",
                      "mass_sigma": "kg", "liquid_mass": "kg", "mass_ratio": "1", "estimate_mass": "1"}
        for m, md in zip(self.analysis.modes, d["analysis"]["modes"]):
            md["period"] = m.period
            md["mass_ratio"] = m.mass / self.liquid_mass
        return d


def sloshing_modes(options: Mapping[str, Any] | None = None, options_file: str | os.PathLike | None = None,
                   direction: str = "x", amplitude: float | None = None, periods: float = 7.0, pulse: float = 0.5,
                   modes: int = 2, output_dir: str | os.PathLike = "output/modes", comm=None,
                   progress=print) -> Result:
    """Runs the free-decay experiment on the case (``options``, ``options_file``) along ``direction`` (x, or z in
    3-D) and returns its sloshing frequencies. The tank rests until the start-up relaxation (-fs_relax_time) has
    ended, is displaced by ``amplitude`` (m; default 1 % of the liquid's length L) over ``pulse`` times the first
    period's rectangular estimate T_1 = 2 pi / omega_1 (omega_1^2 = g k tanh(k h), k = pi/L), and is then held still
    for ``periods`` T_1; the gauges' difference after the step is analysed (``analyse``) for ``modes`` peaks, and
    the load on the tank held still (``load_force_<c>``) for each mode's sloshing mass (``sloshing_masses``). The
    run writes to <output_dir>/run (probes.csv, timeseries.csv, ...), the motion and probe files to output_dir."""
    from .output import read_csv
    from .solver import Solver

    if direction not in AXES:
        raise ValueError(f"direction {direction!r}: expected x or z")
    if not (periods >= 2 and math.isfinite(periods)):
        raise ValueError(f"periods {periods}: expected at least 2 (a few periods resolve a frequency)")
    if not (0 < pulse <= 2):
        raise ValueError(f"pulse {pulse}: expected a fraction of the first period in (0, 2]")
    if amplitude is not None and not (amplitude > 0 and math.isfinite(amplitude)):
        raise ValueError(f"amplitude {amplitude}: expected a positive displacement in m")
    out = Path(output_dir)
    opts = _options(options)
    if "options_file" in opts:
        options_file = opts.pop("options_file")
    comp = AXES[direction][0]
    if "fs_structure" in opts:
        raise ValueError(f"-fs_structure is set: flexslosh.modes moves the tank itself (prescribed); remove it")
    rank = comm.Get_rank() if comm is not None else 0
    if rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    geo = tank_geometry({**opts, "fs_output_dir": str(out / "setup")}, options_file, direction, comm)
    L, h = geo["length"], geo["depth"]
    est_w, est_m = rectangular_modes(L, h, max(modes, 3))
    est = est_w / (2 * np.pi)
    period = 1 / est[0]
    amp = 0.01 * L if amplitude is None else float(amplitude)
    relax = geo["relax"]
    t0 = relax + 0.05 * period
    dur = pulse * period
    record_start = t0 + dur
    t_end = record_start + periods * period
    motion = out / "pulse.txt"
    probes = out / "gauges.txt"
    if rank == 0:
        pulse_motion(motion, t0, dur, amp, t_end + period)
        with open(probes, "w") as fp:
            fp.write("# flexslosh.modes: vertical wave gauges at the two ends of the liquid\n")
            for g in geo["gauges"]:
                fp.write(f"gauge {g['name']} " + " ".join(repr(v) for v in g["start"] + g["end"]) + "\n")
    if comm is not None and comm.Get_size() > 1:
        comm.Barrier()
    # about 100 samples per first period (the probes cost one right-hand side each)
    interval = max(1, int(period / 100 / geo["dt"])) if geo["dt"] > 0 else 1
    run_dir = out / "run"
    ropts = {**opts, "fs_structure": "prescribed", f"fs_motion_{comp}_file": str(motion), "fs_probes": str(probes),
             "fs_probe_interval": interval, "fs_series_interval": interval, "fs_output_interval": 0,
             "fs_progress": False, "ts_max_time": t_end, "fs_output_dir": str(run_dir)}
    if progress:
        progress(f"[modes] L = {L:.4g} m, h = {h:.4g} m along {direction}: estimated first period {period:.4g} s; "
                 f"step of {amp:.3g} m over {dur:.3g} s at t = {t0:.3g} s, record to t = {t_end:.4g} s")
    with Solver(ropts, options_file=options_file, comm=comm) as s:
        s.run()
        cmass = s._core.ffi.new("PetscReal *")
        s._call("FSSolverGetLiquidMass", cmass)  # 2-D: times the tank's width, as the loads
        liquid_mass = float(cmass[0])
    res = None
    if rank == 0:
        P = read_csv(run_dir / "probes.csv", allow_partial_last_row=True)
        t = P["time"]
        y = P["gauge_hi_elevation[m]"] - P["gauge_lo_elevation[m]"]
        keep = t >= record_start
        a = analyse(t[keep], y[keep], modes)
        S = read_csv(run_dir / "timeseries.csv", allow_partial_last_row=True)
        ks = S["time"] >= record_start
        for m, (mn, sn) in zip(a.modes, sloshing_masses(S["time"][ks], S[f"load_force_{comp}"][ks], a.modes, amp, dur)):
            m.mass, m.mass_sigma = mn, sn
        res = Result(direction, geo["dim"], geo["dx"], L, h, amp, t0, dur, record_start, float(t[-1]),
                     [float(v) for v in est], a, str(run_dir), geo["gauges"], liquid_mass, [float(v) for v in est_m])
        (out / "modes.json").write_text(json.dumps(res.to_json(), indent=1) + "\n")
    if comm is not None and comm.Get_size() > 1:
        res = comm.bcast(res, root=0)
    return res


# ----------------------------------------------------------------------------- the command


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m flexslosh.modes", description=(
        "The tank's linear sloshing frequencies and masses along a horizontal direction, from a free decay after a small "
        "displacement step (docs/equivalent.md, \"The tank's sloshing frequencies\"). Arguments it does not know "
        "are PETSc options for the runs (-fs_dx 0.005 ...)."))
    ap.add_argument("--options-file", help="the case (any tank: 2-D, 3-D box or STL)")
    ap.add_argument("--direction", default="x", choices=sorted(AXES), help="x, or z in 3-D (default x)")
    ap.add_argument("--fill", type=float, help="-fs_fill (default the case's)")
    ap.add_argument("--amplitude", type=float, help="the step, m (default 1 %% of the liquid's length)")
    ap.add_argument("--periods", type=float, default=7.0, help="the record, in estimated first periods (7)")
    ap.add_argument("--pulse", type=float, default=0.5, help="the step's duration over the estimated period (0.5)")
    ap.add_argument("--modes", type=int, default=2, help="spectral peaks to fit (2)")
    ap.add_argument("--out", default="output/modes", help="output folder: modes.json, run/, the motion and gauge files")
    args, petsc = ap.parse_known_args(argv)
    if args.modes < 1:
        ap.error(f"--modes {args.modes}: expected at least 1")
    opts = petsc_options(petsc)
    if args.fill is not None:
        opts["fs_fill"] = args.fill
    try:
        r = sloshing_modes(opts, args.options_file, args.direction, args.amplitude, args.periods, args.pulse,
                           args.modes, args.out)
    except ValueError as e:
        print(f"flexslosh.modes: {e}", file=sys.stderr)
        return 2
    print(r.table())
    print(f"written {Path(args.out) / 'modes.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

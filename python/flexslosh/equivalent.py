"""The liquid as an effective mass and an equivalent damping: describing functions from forced motion.

A wing or tank model that does not run SPH takes the liquid as a few numbers that depend on the motion's
amplitude, its frequency and the fill: ``describe`` shakes the tank harmonically along one direction with the
prescribed motion (``-fs_structure prescribed``, docs/motion.md), cycle after cycle until the response is
periodic, and returns per cycle, from the motion and the liquid's load on the tank,

- the energy dissipated E_d (the work the rig does on the liquid over the cycle; ``work_motion``'s change
  over the cycle checks it),
- the equivalent viscous damping c_eq = E_d / (pi omega A^2) and c_eq / (M omega),
- the effective mass m_eff: the rig's force on the liquid (beyond the static weight) in phase with the
  acceleration, over the acceleration; M_ref, the liquid's mass (its moment of inertia as a rigid body about
  the roll point for roll),
- the higher harmonics' share of the load,

and their mean and spread over the settled cycles. ``grid`` runs a grid of fills, amplitudes and frequencies
over MPI ranks (as ``flexslosh.sweep`` does: point k on rank k % size), resumes an interrupted grid, and writes
one table (``equivalent.csv``, ``equivalent.json``) and the maps (``equivalent_maps.png``). The command line::

    python3 -m flexslosh.equivalent --options-file cases/tank_rectangular.opts --direction sway \\
        --fill 0.5 --amplitude 0.001,0.004 --frequency 0.8,1.2 --out output/equivalent -fs_dx 0.01

The linear potential theory of a rectangular tank (``rectangular_modes``, ``rectangular_sway_mass``) gives
the sloshing frequencies and masses the small-amplitude runs are checked against. The definitions, the
formulas and the table's columns: docs/equivalent.md.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time as _time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from .output import code_revision

__all__ = ["DIRECTIONS", "Cycle", "Description", "describe", "analyse_cycles", "settled_window", "grid",
           "faraday_modes", "write_liquid_table", "petsc_options",
           "rectangular_modes", "rectangular_sway_mass", "write_table", "plot_maps", "main"]

G = 9.81

#: direction -> the prescribed motion's component and the load's column (the rig's force is minus it)
DIRECTIONS = {
    "heave": ("y", "load_force_y"),
    "sway": ("x", "load_force_x"),
    "surge": ("z", "load_force_z"),  # 3-D only
    "roll": ("roll", "load_moment_z"),
    "pitch": ("roll", "load_moment_z"),  # the same rotation, about z: the rig has one (docs/equivalent.md)
}


# ----------------------------------------------------------------------------- linear theory


def rectangular_modes(length: float, depth: float, n: int = 8, g: float = G) -> tuple[np.ndarray, np.ndarray]:
    """The antisymmetric sloshing modes of a 2-D rectangular tank (length L, liquid depth h) under sway, from
    linear potential theory: k_n = (2n-1) pi / L, omega_n^2 = g k_n tanh(k_n h), and the sloshing masses as
    fractions of the liquid's mass, m_n / m = 8 tanh(k_n h) / (k_n^3 L^2 h) (docs/equivalent.md). Returns
    (omega_n in rad/s, m_n / m), n = 1..n. The rigid mass is m (1 - sum m_n/m)."""
    if not (length > 0 and depth > 0):
        raise ValueError(f"rectangular_modes: length {length} and depth {depth} must be positive")
    k = (2 * np.arange(1, n + 1) - 1) * np.pi / length
    omega = np.sqrt(g * k * np.tanh(k * depth))
    return omega, 8 * np.tanh(k * depth) / (k**3 * length**2 * depth)


def rectangular_sway_mass(length: float, depth: float, omega: float, n: int = 64, g: float = G) -> float:
    """The effective mass over the liquid's mass of a 2-D rectangular tank swayed harmonically at omega
    (linear potential theory, no damping): m_eff / m = 1 + sum_n (m_n / m) omega^2 / (omega_n^2 - omega^2)."""
    wn, mn = rectangular_modes(length, depth, n, g)
    return float(1 + np.sum(mn * omega**2 / (wn**2 - omega**2)))


def faraday_modes(lengths: Sequence[float], depth: float, omega: float, gamma: float, n: int = 64,
                  g: float = G) -> list[tuple[tuple[int, ...], float]]:
    """The sloshing modes of a rectangular liquid (free surface lengths L_x or L_x, L_z; depth h) that a heave at
    omega with Gamma = A omega^2 / g excites parametrically: those inside Mathieu's first instability tongue
    |omega / 2 - omega_k| < Gamma omega_k / 4 (undamped), omega_k^2 = g k tanh(k h), k = pi |(m / L_x, n / L_z)|.
    Returns [((m,) or (m, n), omega_k)] with m, n < n, lowest first: a flat surface in such a heave is unstable
    and a Faraday wave grows from any disturbance (docs/equivalent.md)."""
    if not (all(L > 0 for L in lengths) and depth > 0 and len(lengths) in (1, 2)):
        raise ValueError(f"faraday_modes: lengths {list(lengths)} and depth {depth} must be positive (one or two lengths)")
    idx = [np.arange(n)] * len(lengths)
    found = []
    for mode in np.array(np.meshgrid(*idx, indexing="ij")).reshape(len(lengths), -1).T:
        if not mode.any():
            continue
        k = np.pi * math.hypot(*(m / L for m, L in zip(mode, lengths)))
        wk = math.sqrt(g * k * math.tanh(k * depth))
        if abs(omega / 2 - wk) < gamma * wk / 4:
            found.append((tuple(int(m) for m in mode), wk))
    return sorted(found, key=lambda f: f[1])


# ----------------------------------------------------------------------------- per-cycle analysis


@dataclass
class Cycle:
    """One forcing cycle [start, start + T]. Units: a translation's (kg, N, J, N s/m); a rotation's
    (kg m^2, N m, J, N m s/rad)."""
    index: int
    start: float
    force_sin: float  # the rig's force's Fourier coefficient on sin(omega t) (the motion's phase)
    force_cos: float  # on cos(omega t) (the velocity's phase)
    force_mean: float
    m_eff: float  # -force_sin / (A omega^2): in phase with the acceleration -A omega^2 sin(omega t)
    c_first: float  # force_cos / (A omega): in phase with the velocity
    energy: float  # E_d: integral of F v over the cycle
    energy_work: float  # the change of energy.csv's work_motion over the cycle
    c_eq: float  # E_d / (pi omega A^2)
    higher: float  # rms of the load's harmonics >= 2 over the rms of its first harmonic

    @property
    def first(self) -> float:
        return math.hypot(self.force_sin, self.force_cos)


def _window(t: np.ndarray, y: np.ndarray, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """The samples of y(t) in [a, b], the ends interpolated."""
    inside = (t > a) & (t < b)
    ya, yb = np.interp([a, b], t, y)
    return np.r_[a, t[inside], b], np.r_[ya, y[inside], yb]


def _fit(tw: np.ndarray, f: np.ndarray, omega: float, harmonics: int, free: float | None):
    """Least squares (trapezoidal weights) of f(tw) on 1, sin j omega t, cos j omega t (j = 1..harmonics) and, with
    free (rad/s), sin, cos of a free oscillation whose frequency is searched within 10 % of free: (coefficients,
    the free part of f at tw)."""
    wts = np.zeros_like(tw)
    dt = np.diff(tw)
    wts[:-1] += dt / 2
    wts[1:] += dt / 2
    sq = np.sqrt(wts)
    cols = [np.ones_like(tw)]
    for j in range(1, harmonics + 1):
        cols += [np.sin(j * omega * tw), np.cos(j * omega * tw)]
    base = np.array(cols).T
    best = None
    for wf in (np.linspace(0.9, 1.1, 41) * free if free else [None]):
        basis = base if wf is None else np.c_[base, np.sin(wf * tw), np.cos(wf * tw)]
        coef, *_ = np.linalg.lstsq(basis * sq[:, None], f * sq, rcond=1e-10)
        res = float(np.sum(wts * (basis @ coef - f) ** 2))
        if best is None or res < best[0]:
            best = (res, coef, np.zeros_like(tw) if wf is None else basis[:, -2:] @ coef[-2:])
    return best[1], best[2]


def analyse_cycles(t: np.ndarray, force: np.ndarray, work: np.ndarray | None, amplitude: float, omega: float,
                   start: float, window: int = 1, free: float | None = None, harmonics: int = 3) -> list[Cycle]:
    """The windows of ``window`` cycles [start + k n T, start + (k+1) n T] that the samples cover, for the motion
    X = amplitude sin(omega t) (start a multiple of T, after the ramp) and the rig's force on the liquid F(t)
    (beyond the static weight); work: work_motion at the same times (or None). The load's mean and first
    harmonic are its least-squares fit over the window with the harmonics up to ``harmonics`` (over whole
    cycles: its Fourier coefficients) and, with ``free`` (rad/s, e.g. the first sloshing frequency), a free
    oscillation near free, the start's transient, fitted and left out. E_d is the integral of F v per cycle
    (the free oscillation's part removed). Trapezoidal integrals over the rows."""
    period = 2 * np.pi / omega
    span = window * period
    cycles = []
    k = 0
    while start + (k + 1) * span <= t[-1] + 1e-6 * period:  # the last step lands on the window's end, to round-off
        a, b = start + k * span, start + (k + 1) * span
        tw, f = _window(t, force, a, b)
        coef, freepart = _fit(tw, f, omega, harmonics, free)
        f0, fs, fc = coef[0], coef[1], coef[2]
        g = f - freepart
        c = np.cos(omega * tw)
        rest = g - f0 - fs * np.sin(omega * tw) - fc * c
        first = 0.5 * (fs * fs + fc * fc)
        energy = np.trapz(g * amplitude * omega * c, tw) / window
        ew = float(np.diff(np.interp([a, b], t, work))[0]) / window if work is not None else float("nan")
        cycles.append(Cycle(k, a, fs, fc, f0, -fs / (amplitude * omega**2), fc / (amplitude * omega), energy, ew,
                            energy / (np.pi * omega * amplitude**2),
                            math.sqrt(np.trapz(rest * rest, tw) / span / first) if first > 0 else float("nan")))
        k += 1
    return cycles


def _change(prev: Cycle, cur: Cycle, amplitude: float) -> float:
    """The change from one cycle to the next: of the first harmonic's amplitude relative to it, and of E_d
    relative to pi A |F1| (the most a load of that amplitude can dissipate), the larger."""
    scale = cur.first if cur.first > 0 else 1.0
    return max(abs(cur.first - prev.first) / scale, abs(cur.energy - prev.energy) / (np.pi * amplitude * scale))


def _growing(cycles: Sequence[Cycle], growth: float) -> bool:
    """Whether E_d is positive on every cycle and grows by more than the factor 1 + growth from each to the next:
    a response growing exponentially from a small start (a parametric instability: the Faraday wave of a heaved
    tank), which is not periodic however small its changes measured against pi A |F_1| still are."""
    e = [c.energy for c in cycles]
    return all(a > 0 and b > (1 + growth) * a for a, b in zip(e[:-1], e[1:]))


def settled_window(cycles: Sequence[Cycle], amplitude: float, tol: float = 0.01, settle: int = 3,
                   growth: float = 0.1, earliest: int = 0) -> int | None:
    """The first cycle k from which ``settle`` consecutive changes (``_change``: cycles k..k+settle) all stay
    below tol and E_d does not grow by more than the factor 1 + growth on every one of them (``_growing``), k at
    least ``earliest`` (a heave in a Faraday tongue: only the run's last cycles); None when there is no such window."""
    for k in range(max(earliest, 0), len(cycles) - settle):
        window = cycles[k:k + settle + 1]
        if all(_change(a, b, amplitude) < tol for a, b in zip(window[:-1], window[1:])) and not _growing(window, growth):
            return k
    return None


# ----------------------------------------------------------------------------- one run


@dataclass
class Description:
    """The describing function of one run: the cycles, whether and where they settled, and the summary over
    the settled cycles (mean and standard deviation; NaN where the run never settled)."""
    direction: str
    amplitude: float  # m (roll, pitch: rad)
    frequency: float  # Hz
    reference_mass: float  # kg (roll, pitch: the liquid's rigid moment of inertia about the point, kg m^2)
    liquid_mass: float
    extent: float  # the liquid's length along the motion at rest (m)
    dx: float
    dim: int
    cycles: list[Cycle] = field(default_factory=list)
    settled_from: int | None = None
    settle: int = 3
    tol: float = 0.01
    growth: float = 0.1
    faraday: list = field(default_factory=list)  # heave: faraday_modes of the liquid's rectangle ([(mode, omega_k)])
    output_dir: str = ""

    @property
    def omega(self) -> float:
        return 2 * np.pi * self.frequency

    @property
    def settled(self) -> bool:
        return self.settled_from is not None

    def settled_cycles(self) -> list[Cycle]:
        return self.cycles[self.settled_from:self.settled_from + self.settle + 1] if self.settled else []

    def nondimensional_amplitude(self) -> float:
        """Gamma = A omega^2 / g (heave); A / L (sway, surge: L the liquid's extent along the motion); the angle
        in rad (roll, pitch)."""
        if self.direction == "heave":
            return self.amplitude * self.omega**2 / G
        if self.direction in ("sway", "surge"):
            return self.amplitude / self.extent
        return self.amplitude

    def summary(self) -> dict[str, Any]:
        sel = self.settled_cycles()

        def stat(attr: str) -> tuple[float, float]:
            if not sel:
                return float("nan"), float("nan")
            v = np.array([getattr(c, attr) for c in sel])
            return float(v.mean()), float(v.std())

        out: dict[str, Any] = {}
        for attr in ("m_eff", "energy", "energy_work", "c_eq", "c_first", "higher"):
            out[attr], out[attr + "_spread"] = stat(attr)
        out["m_eff_ratio"] = out["m_eff"] / self.reference_mass
        out["c_eq_nd"] = out["c_eq"] / (self.reference_mass * self.omega)
        out["last_change"] = (_change(self.cycles[-2], self.cycles[-1], self.amplitude)
                              if len(self.cycles) > 1 else float("nan"))
        return out


def _motion_options(direction: str, amplitude: float, frequency: float, ramp: float, dim: int | None) -> dict:
    comp, _ = DIRECTIONS[direction]
    value = math.degrees(amplitude) if comp == "roll" else amplitude
    opts = {"fs_structure": "prescribed", "fs_motion_ramp": ramp, f"fs_motion_{comp}_sines": f"{value!r},{1 / frequency!r},0"}
    return opts


def _check_direction(direction: str, amplitude: float, frequency: float) -> None:
    if direction not in DIRECTIONS:
        raise ValueError(f"direction {direction!r}: expected one of {', '.join(DIRECTIONS)}")
    if not (amplitude > 0 and math.isfinite(amplitude)):
        raise ValueError(f"amplitude {amplitude}: expected a positive finite number (m; roll, pitch: rad)")
    if not (frequency > 0 and math.isfinite(frequency)):
        raise ValueError(f"frequency {frequency}: expected a positive finite number (Hz)")


def _liquid_geometry(s, direction: str, point) -> tuple[float, float, float, list[float]]:
    """(the liquid's mass, its extent along the motion, the reference mass, its extents along x, y (, z)) at set-up:
    kg (2-D: times the tank's width), m, kg or kg m^2 (the rigid moment of inertia about the roll point), m (the
    particles' span plus dx; empty on ranks other than 0)."""
    core = s._core
    mass = core.ffi.new("PetscReal *")
    s._call("FSSolverGetLiquidMass", mass)
    x, m = s.positions(gather=True), s.field("mass", gather=True)
    extent, ref, box = float("nan"), mass[0], []
    if x is not None:
        box = [float(x[:, a].max() - x[:, a].min() + s.options.getReal("fs_dx", 0.0)) for a in range(x.shape[1])]
        width = mass[0] / float(m.sum())  # 2-D: the tank's width (1 in 3-D)
        comp = DIRECTIONS[direction][0]
        if comp in "xyz":
            axis = "xyz".index(comp)
            extent = box[axis]
        else:
            r = x[:, :2] - np.asarray(point, float)[:2]
            ref = float(width * np.sum(m * np.sum(r * r, axis=1)))
    return float(mass[0]), extent, ref, box


def describe(options: Mapping[str, Any] | None = None, direction: str = "sway", amplitude: float = 0.001,
             frequency: float = 1.0, options_file: str | os.PathLike | None = None, point: Sequence[float] | None = None,
             ramp_cycles: float = 6.0, cycles_max: int = 12, settle: int = 3, tol: float = 0.01, growth: float = 0.1,
             window: int = 1, free: float | None = None, comm=None, progress: Callable[[str], Any] | None = print, label: str = "") -> Description:
    """Shakes the tank of ``options`` (a Solver's options; ``options_file`` its case) harmonically along
    ``direction`` (heave y, sway x, surge z in 3-D, roll or pitch: the rotation about z through ``point``, x,y in
    the tank's frame, default the middle of the floor) with X = amplitude sin(2 pi frequency t) (m; roll, pitch:
    rad; Hz), started by the rig's ramp over ``ramp_cycles`` periods, cycle after cycle until ``settle``
    consecutive changes from one cycle to the next stay below ``tol`` while E_d does not grow by more than
    1 + ``growth`` from each cycle to the next (``settled_window``) or ``cycles_max``
    cycles after the ramp have run (then the run is reported not settled). The cycles start when the ramp and
    the start-up relaxation (-fs_relax_time) have ended. window: a "cycle" of the analysis is that many forcing
    periods; free: the frequency (rad/s) near which a free oscillation left by the start is fitted and removed
    (``analyse_cycles``): e.g. the tank's first sloshing frequency when it is not a multiple of the forcing's. progress(line) is called after every cycle (None:
    silent). The run writes into options' fs_output_dir (default output/equivalent/run)."""
    _check_direction(direction, amplitude, frequency)
    from .output import read_csv
    from .solver import Solver

    opts = {k.lstrip("-"): v for k, v in (options or {}).items()}
    if "options_file" in opts:
        options_file = opts.pop("options_file")
    period = 1 / frequency
    opts.update(_motion_options(direction, amplitude, frequency, ramp_cycles * period, None))
    if point is not None and DIRECTIONS[direction][0] == "roll":
        opts["fs_tank_reference"] = ",".join(repr(float(p)) for p in point[:2])
    if str(opts.get("fs_output", True)).lower() in ("false", "0", "no", "off"):
        raise ValueError(f"-fs_output {opts['fs_output']}: the describing function reads the run's timeseries.csv and "
                         "energy.csv; leave the output on (-fs_output_interval 0 writes no snapshots)")
    opts.setdefault("fs_output_dir", "output/equivalent/run")
    opts.setdefault("fs_output_interval", 0)
    opts.setdefault("fs_progress", False)
    opts["ts_max_time"] = 1e30  # driven cycle by cycle with run(until=)
    out = Path(opts["fs_output_dir"])
    comp, load = DIRECTIONS[direction]
    with Solver(opts, options_file=options_file, comm=comm) as s:
        o = s.options
        for c in ("x", "y", "z", "roll"):
            for kind in ("poly", "file") + (("sines",) if c != comp else ()):
                if o.hasName(f"fs_motion_{c}_{kind}"):
                    raise ValueError(f"-fs_motion_{c}_{kind} is set (by the case or the options): the describing "
                                     f"function moves the tank along {direction} alone; remove it")
        s.set_up()
        dim = s.dim
        if comp == "z" and dim != 3:
            raise ValueError("direction surge moves the tank along z: a 3-D case only")
        if comp == "roll" and point is None:
            raise ValueError(f"direction {direction}: give the point the tank turns about (point x,y in the tank's frame)")
        relax = o.getReal("fs_relax_time", 0.0)
        mass, extent, ref, box = _liquid_geometry(s, direction, point)
        d = Description(direction, float(amplitude), float(frequency), ref, mass, extent, o.getReal("fs_dx", float("nan")), dim,
                        settle=settle, tol=tol, growth=growth, output_dir=str(out))
        start = math.ceil(max(ramp_cycles * period, relax) / period - 1e-9) * period
        rank = s.comm.Get_rank()
        if direction == "heave" and box:
            d.faraday = faraday_modes(box[0::2], box[1], d.omega, d.nondimensional_amplitude())
            if d.faraday and progress:
                (mode, wk), *_ = d.faraday
                progress(f"{label}heave at Gamma {d.nondimensional_amplitude():.3g}: {len(d.faraday)} sloshing mode(s) of the "
                         f"liquid's rectangle ({' x '.join(f'{b:.4g}' for b in box)} m) in Mathieu's first tongue, the lowest "
                         f"{mode} at omega {wk:.4g} rad/s (forcing/2 {d.omega / 2:.4g}): a Faraday wave grows from any "
                         f"disturbance, so the run goes all {cycles_max} cycles and the criterion judges its last {settle + 1}")
        for k in range(cycles_max):
            s.run(until=start + (k + 1) * window * period)
            if rank == 0:
                ts = read_csv(out / "timeseries.csv", allow_partial_last_row=True)
                en = read_csv(out / "energy.csv", allow_partial_last_row=True)
                work = np.interp(ts["time"], en["time"], en["work_motion"]) if "work_motion" in en else None
                d.cycles = analyse_cycles(ts["time"], -ts[load], work, amplitude, 2 * np.pi * frequency, start, window,
                                          free)
                # in a Faraday tongue only the run's end can be the periodic state: its last settle + 1 cycles
                d.settled_from = settled_window(d.cycles, amplitude, tol, settle, growth,
                                                earliest=cycles_max - settle - 1 if d.faraday else 0)
                c = d.cycles[-1] if d.cycles else None
                if progress and c:
                    progress(f"{label}cycle {c.index + 1}/{cycles_max} t {c.start + window * period:.4g} s: m_eff/M {c.m_eff / ref:.4f} "
                             f"c_eq/(M omega) {c.c_eq / (ref * d.omega):.3e} change "
                             f"{d.summary()['last_change']:.2e}{' settled' if d.settled else ''}")
            done = s.comm.bcast(d.settled, root=0) if s.comm.Get_size() > 1 else d.settled
            if done:
                break
        if s.comm.Get_size() > 1:
            d = s.comm.bcast(d, root=0)
    return d


# ----------------------------------------------------------------------------- the grid and its table

#: the table's columns with their units
COLUMNS = [
    ("point", "-"), ("case", "-"), ("dim", "-"), ("dx", "m"), ("revision", "-"), ("direction", "-"), ("fill", "-"),
    ("amplitude", "m or rad"), ("frequency", "Hz"), ("omega", "rad/s"), ("nondim_amplitude", "-"),
    ("liquid_mass", "kg"), ("reference_mass", "kg or kg m^2"), ("extent", "m"), ("settled", "-"),
    ("faraday_modes", "-"), ("cycles_run", "-"), ("settled_from", "-"), ("last_change", "-"), ("m_eff", "kg or kg m^2"),
    ("m_eff_spread", "kg or kg m^2"), ("m_eff_ratio", "-"), ("energy", "J"), ("energy_spread", "J"),
    ("energy_work", "J"), ("c_eq", "N s/m or N m s/rad"), ("c_eq_spread", "N s/m or N m s/rad"), ("c_eq_nd", "-"),
    ("higher", "-"), ("higher_spread", "-"), ("output_dir", "-"),
]


def _row(index: int, case: str, fill, d: Description, revision: str) -> dict[str, Any]:
    s = d.summary()
    row = {"point": index, "case": case, "dim": d.dim, "dx": d.dx, "revision": revision, "direction": d.direction,
           "fill": fill, "amplitude": d.amplitude, "frequency": d.frequency, "omega": d.omega,
           "nondim_amplitude": d.nondimensional_amplitude(), "liquid_mass": d.liquid_mass,
           "reference_mass": d.reference_mass, "extent": d.extent, "settled": d.settled,
           "faraday_modes": len(d.faraday), "cycles_run": len(d.cycles),
           "settled_from": -1 if d.settled_from is None else d.settled_from, "output_dir": d.output_dir}
    row.update({k: s[k] for k, _ in COLUMNS if k in s})
    return row


def _point_file(out: Path, k: int) -> Path:
    return out / "points" / f"point_{k:04d}.json"


def _load_point(path: Path, params: Mapping[str, Any]) -> dict | None:
    """The finished point's record, or None when absent, incomplete or made for other parameters."""
    try:
        rec = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not rec.get("complete") or rec.get("params") != json.loads(json.dumps(params)):
        return None
    return rec


def grid(options_file: str | os.PathLike | None, direction: str, fills: Sequence[float | None],
         amplitudes: Sequence[float], frequencies: Sequence[float], base_options: Mapping[str, Any] | None = None,
         output_root: str | os.PathLike = "output/equivalent", comm=None, figures: bool = True,
         progress: Callable[[str], Any] | None = print, **describe_kw) -> list[dict] | None:
    """Runs ``describe`` for every fill x amplitude x frequency (fill None: the case's own) and writes the table
    to <output_root>/equivalent.csv and .json, and the maps to equivalent_maps.png. comm (mpi4py): the points
    spread over its ranks (point k of those still to run on rank k % size, each alone on MPI.COMM_SELF, as
    flexslosh.sweep does). A point whose record <output_root>/points/point_NNNN.json exists, is complete and has
    the same parameters is not run again: an interrupted grid resumes where it stopped. Returns the rows on
    rank 0 (None elsewhere)."""
    from .sweep import assign

    out = Path(output_root)
    base = {k.lstrip("-"): v for k, v in (base_options or {}).items()}
    case = Path(options_file).stem if options_file else str(base.get("fs_case", "case"))
    points = [(f, a, fr) for f in fills for a in amplitudes for fr in frequencies]
    for _, a, fr in points:
        _check_direction(direction, a, fr)
    params = [{"options_file": str(options_file) if options_file else None, "base": base, "direction": direction,
               "fill": f, "amplitude": a, "frequency": fr,
               "describe": {k: v for k, v in describe_kw.items()}} for f, a, fr in points]
    todo = [k for k in range(len(points)) if _load_point(_point_file(out, k), params[k]) is None]
    mine, run_comm, rank = assign(len(todo), comm)
    revision = code_revision()
    for j in mine:
        k = todo[j]
        f, a, fr = points[k]
        opts = dict(base)
        if f is not None:
            opts["fs_fill"] = f
        opts["fs_output_dir"] = str(out / "runs" / f"point_{k:04d}")
        label = f"[equivalent] point {k + 1}/{len(points)} (rank {rank}) fill {f} A {a:g} f {fr:g} Hz: "
        t0 = _time.time()
        d = describe(opts, direction, a, fr, options_file=options_file, comm=run_comm, progress=progress, label=label,
                     **describe_kw)
        row = _row(k, case, f if f is not None else float("nan"), d, revision)
        if progress:
            progress(f"{label}{'settled' if d.settled else 'NOT settled'} after {len(d.cycles)} cycles "
                     f"({_time.time() - t0:.0f} s): m_eff/M {row['m_eff_ratio']:.4f} c_eq/(M omega) {row['c_eq_nd']:.3e}")
        path = _point_file(out, k)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps({"complete": True, "params": params[k], "row": row,
                                   "cycles": [asdict(c) for c in d.cycles]}, indent=1))
        os.replace(tmp, path)
    if comm is not None:
        comm.Barrier()
    if rank != 0:
        return None
    rows = []
    for k in range(len(points)):
        rec = _load_point(_point_file(out, k), params[k])
        if rec is None:
            raise RuntimeError(f"{_point_file(out, k)}: the point's record is missing or incomplete after its run")
        rows.append(rec["row"])
    write_table(rows, out)
    if figures:
        plot_maps(rows, out / "equivalent_maps.png")
    return rows


def write_liquid_table(rows: Sequence[Mapping[str, Any]], path: str | os.PathLike) -> Path:
    """The reduced model's table (``-fs_msd_liquid_table``, docs/equivalent.md "The reduced model") from a heave
    grid's rows at one frequency and one fill: one line 'A m_eff c_eq' (m, kg, N s/m) per settled row, by increasing
    amplitude, after a comment naming the frequency, the liquid's mass (``-fs_msd_liquid_mass``) and the rows
    left out (not settled). Raises ValueError when the rows are not heave, mix frequencies or fills, or fewer than
    two settled."""
    rows = list(rows)
    if not rows or any(r["direction"] != "heave" for r in rows):
        raise ValueError("the reduced model's table: expected the rows of a heave grid (the tank moves with the beam's tip)")
    for key in ("frequency", "fill"):
        values = {repr(r[key]) for r in rows}
        if len(values) > 1:
            raise ValueError(f"the reduced model's table: the rows have {len(values)} values of {key} "
                             f"({', '.join(sorted(values))}): give the grid one (the table is at one {key})")
    use = sorted((r for r in rows if r["settled"]), key=lambda r: r["amplitude"])
    left = sorted(r["amplitude"] for r in rows if not r["settled"])
    if len(use) < 2:
        raise ValueError(f"the reduced model's table: {len(use)} settled rows of {len(rows)}: at least two are needed "
                         "(run more cycles, --cycles, or see the criterion in docs/equivalent.md)")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fill = rows[0]["fill"]
    fill = "the case's" if fill is None or (isinstance(fill, float) and not math.isfinite(fill)) else repr(fill)
    lines = [f"# the liquid's heave describing function at {rows[0]['frequency']!r} Hz, fill {fill}, "
             f"dx {rows[0]['dx']!r} m, revision {rows[0]['revision']}",
             f"# -fs_msd_liquid_mass {rows[0]['liquid_mass']!r}",
             f"# not settled, left out: A = {', '.join(repr(a) for a in left) or 'none'}",
             "# A (m)  m_eff (kg)  c_eq (N s/m)"]
    lines += [f"{r['amplitude']!r} {r['m_eff']!r} {max(r['c_eq'], 0.0)!r}" for r in use]
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, path)
    return path


def write_table(rows: Sequence[Mapping[str, Any]], out: str | os.PathLike) -> tuple[Path, Path]:
    """The rows to <out>/equivalent.csv (a header of name[unit]) and <out>/equivalent.json ({"units": ...,
    "rows": [...]}, NaN as null)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    csv_path, json_path = out / "equivalent.csv", out / "equivalent.json"
    with open(csv_path, "w", newline="") as fp:
        w = csv.writer(fp)
        w.writerow([f"{name}[{unit}]" for name, unit in COLUMNS])
        for r in rows:
            w.writerow([repr(float(r[n])) if isinstance(r[n], float) else r[n] for n, _ in COLUMNS])

    def clean(v):
        return None if isinstance(v, float) and not math.isfinite(v) else v

    json_path.write_text(json.dumps({"units": dict(COLUMNS), "rows": [{n: clean(r[n]) for n, _ in COLUMNS} for r in rows]},
                                    indent=1))
    return csv_path, json_path


def plot_maps(rows: Sequence[Mapping[str, Any]], path: str | os.PathLike) -> Path:
    """Effective mass over M_ref and c_eq / (M_ref omega) against the non-dimensional amplitude, one line per
    frequency and fill (settled points filled; a point that never settled is left out)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    direction = rows[0]["direction"] if rows else "sway"
    xlabel = {"heave": r"$\Gamma = A\omega^2/g$", "sway": "A / L", "surge": "A / L"}.get(direction, "angle (rad)")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    keys = sorted({(r["fill"], r["frequency"]) for r in rows}, key=lambda k: (str(k[0]), k[1]))
    for fill, freq in keys:
        sel = sorted((r for r in rows if r["fill"] == fill and r["frequency"] == freq and r["settled"]),
                     key=lambda r: r["nondim_amplitude"])
        if not sel:
            continue
        x = [r["nondim_amplitude"] for r in sel]
        label = f"fill {fill}, {freq:g} Hz"
        ax1.errorbar(x, [r["m_eff_ratio"] for r in sel], yerr=[r["m_eff_spread"] / r["reference_mass"] for r in sel],
                     marker="o", label=label)
        ax2.errorbar(x, [r["c_eq_nd"] for r in sel],
                     yerr=[r["c_eq_spread"] / (r["reference_mass"] * r["omega"]) for r in sel], marker="o", label=label)
    ax1.set_xlabel(xlabel)
    ax1.set_ylabel(r"$m_{eff} / M$" if direction not in ("roll", "pitch") else r"$I_{eff} / I_{rigid}$")
    ax2.set_xlabel(xlabel)
    ax2.set_ylabel(r"$c_{eq} / (M \omega)$")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    if keys:
        ax1.legend(fontsize=8)
    fig.suptitle(f"{direction}: describing functions ({len(rows)} runs)")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


# ----------------------------------------------------------------------------- command line


def _numbers(text: str, what: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{what} {text!r}: expected comma-separated numbers") from None
    if not values:
        raise argparse.ArgumentTypeError(f"{what} {text!r}: expected at least one number")
    return values


def petsc_options(words: Sequence[str]) -> dict[str, Any]:
    """-name value pairs (a name followed by another -name, or last, is a flag) as a dict."""
    opts: dict[str, Any] = {}
    i = 0
    while i < len(words):
        w = words[i]
        if not w.startswith("-") or len(w) < 2:
            raise SystemExit(f"flexslosh.equivalent: {w!r} is not an option (PETSc options are -name [value])")
        value: Any = True
        if i + 1 < len(words) and not (words[i + 1].startswith("-") and not _is_number(words[i + 1])):
            value, i = words[i + 1], i + 1
        opts[w.lstrip("-")] = value
        i += 1
    return opts


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python3 -m flexslosh.equivalent",
                                description="The liquid's effective mass and equivalent damping from forced harmonic "
                                            "motion (docs/equivalent.md). Options not listed here go to the solver "
                                            "as PETSc options (e.g. -fs_dx 0.005).")
    p.add_argument("--options-file", help="the case (cases/*.opts: a 2-D, 3-D or STL tank)")
    p.add_argument("--direction", required=True, choices=sorted(DIRECTIONS))
    p.add_argument("--fill", type=lambda t: _numbers(t, "--fill"), default=None,
                   help="fill levels, comma separated (default: the case's)")
    p.add_argument("--amplitude", type=lambda t: _numbers(t, "--amplitude"), required=True,
                   help="amplitudes, comma separated: m (roll, pitch: degrees)")
    p.add_argument("--frequency", type=lambda t: _numbers(t, "--frequency"), required=True,
                   help="frequencies, comma separated, Hz")
    p.add_argument("--point", type=lambda t: _numbers(t, "--point"), default=None,
                   help="roll, pitch: the point x,y (tank frame) the tank turns about (default the middle of the floor)")
    p.add_argument("--ramp-cycles", type=float, default=6.0, help="the rig's smooth start, in periods (6)")
    p.add_argument("--cycles", type=int, default=12, help="at most this many cycles after the ramp (12)")
    p.add_argument("--settle", type=int, default=3, help="consecutive cycle-to-cycle changes below --tol (3)")
    p.add_argument("--tol", type=float, default=0.01, help="the largest change from one cycle to the next (0.01)")
    p.add_argument("--free", type=float, default=None,
                   help="the frequency (Hz) near which a free oscillation left by the start is fitted out of each cycle "
                        "(e.g. the first sloshing frequency, forcing above it; default none)")
    p.add_argument("--growth", type=float, default=0.1,
                   help="a window whose E_d grows by more than this fraction every cycle is not settled (0.1)")
    p.add_argument("--out", default="output/equivalent", help="the table, the figures, runs/ and points/ (resumed)")
    p.add_argument("--no-figures", action="store_true")
    p.add_argument("--liquid-table", default=None,
                   help="heave: also write the reduced model's table (-fs_msd_liquid_table) to this file")
    p.add_argument("--mpi", action="store_true", help="spread the points over MPI.COMM_WORLD's ranks (mpirun)")
    args, rest = p.parse_known_args(argv)
    base = petsc_options(rest)
    if args.point is not None and len(args.point) != 2:
        p.error(f"--point {args.point}: expected two numbers x,y")
    if args.cycles < args.settle + 1:
        p.error(f"--cycles {args.cycles}: expected at least --settle + 1 = {args.settle + 1}")
    if not (args.tol > 0):
        p.error(f"--tol {args.tol}: expected a positive number")
    if not (args.growth > 0):
        p.error(f"--growth {args.growth}: expected a positive number")
    if args.free is not None and not (args.free > 0 and math.isfinite(args.free)):
        p.error(f"--free {args.free}: expected a positive frequency in Hz")
    amplitudes = [math.radians(a) for a in args.amplitude] if args.direction in ("roll", "pitch") else args.amplitude
    comm = None
    if args.mpi:
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
    try:
        rows = grid(args.options_file, args.direction, args.fill or [None], amplitudes, args.frequency, base, args.out,
                    comm=comm, figures=not args.no_figures, point=args.point, ramp_cycles=args.ramp_cycles,
                    cycles_max=args.cycles, settle=args.settle, tol=args.tol, growth=args.growth,
                    **({"free": 2 * math.pi * args.free} if args.free is not None else {}),
                    progress=lambda line: print(line, flush=True))
    except ValueError as e:
        print(f"flexslosh.equivalent: {e}", file=sys.stderr)
        return 2
    if rows is not None:
        print(f"[equivalent] {len(rows)} points, {sum(bool(r['settled']) for r in rows)} settled: "
              f"{Path(args.out) / 'equivalent.csv'}", flush=True)
        if args.liquid_table:
            try:
                print(f"[equivalent] the reduced model's table: {write_liquid_table(rows, args.liquid_table)}", flush=True)
            except ValueError as e:
                print(f"flexslosh.equivalent: {e}", file=sys.stderr)
                return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())

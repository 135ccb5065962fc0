"""The seed paper's figures (section III.B) from flexslosh runs, as PNG files.

Each function takes one :class:`~flexslosh.output.Run` or several (``read_run``), writes one PNG
(under a temporary name, renamed when complete, so a reader never sees half a file) and returns its
path:

- ``tip_acceleration``: the tip acceleration in units of g against time (seed Figs. 5 and 8);
- ``normalized_motion``: the tip displacement over its initial value, several runs (seed Fig. 9);
- ``acceleration_envelope``: the peaks of |tip acceleration| on a log scale and the damping ratio of
  the fitted exponential (seed Fig. 10);
- ``energy_terms``: the liquid's mechanical energy change, dissipation, external work and the
  budget's residual (seed Fig. 11);
- ``damping_vs_amplitude``: the damping ratio of each cycle against its amplitude (docs/validation.md);
- ``snapshots``: particles coloured by a field on a log scale at up to five times (seed Figs. 6, 7);
- ``motion``: a prescribed motion's components (-fs_structure prescribed): the translations in mm and
  the rotations (roll, pitch, yaw, the turn about an axis) in degrees, against time;
- ``wall_loads``: the liquid's load on each wall (force and moment, the wall_* columns) and the loads
  the tank receives less their static value (load_*), against time.

``is_prescribed`` tells a prescribed-motion run (its motion_* columns) from a beam run: the plot command
gives the first the motion and the loads, the second the seed's figures.

A run that lacks what a figure needs (no structure, no liquid, no snapshots) raises ValueError
naming the file and the missing column. matplotlib is imported inside the functions (Agg canvas,
no pyplot), so importing this module costs only numpy.

By default a run without particles (the solid mass) is drawn red dashed and runs with liquid blue
solid (then green, purple, orange, ...), as in the seed's Figs. 9 and 10.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from .damping import damping_per_cycle, fit_envelope
from .output import Run, read_snapshot

__all__ = [
    "G",
    "tip_acceleration",
    "normalized_motion",
    "acceleration_envelope",
    "energy_terms",
    "energy_balance",
    "damping_vs_amplitude",
    "snapshots",
    "is_prescribed",
    "motion_components",
    "motion",
    "wall_loads",
]

PathLike = Union[str, "os.PathLike[str]"]

#: Gravity of the built-in cases (m/s^2), the unit of the accelerations.
G = 9.81

_LIQUID_COLOURS = ("tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:cyan")

_UNITS = {
    "turbulent_viscosity": "m$^2$/s",
    "strain_rate": "1/s",
    "pressure": "Pa",
    "density": "kg/m$^3$",
    "velocity": "m/s",
}


def _figure(width: float, height: float, layout: Optional[str] = None) -> Any:
    """A matplotlib Figure on an Agg canvas (no pyplot: no global state, no display)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=120, layout=layout)
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Any, path: PathLike) -> Path:
    """Writes fig as PNG to path.tmp, then renames it to path."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    fig.savefig(tmp, format="png")
    os.replace(tmp, path)
    return path


def _labels(runs: Sequence[Run], labels: Optional[Sequence[str]]) -> list[str]:
    if labels is None:
        return [r.name for r in runs]
    if len(labels) != len(runs):
        raise ValueError(f"{len(labels)} label(s) for {len(runs)} run(s)")
    return list(labels)


def _styles(runs: Sequence[Run]) -> list[dict[str, Any]]:
    """Red dashed for runs without liquid, blue solid then other colours for runs with liquid."""
    out, k = [], 0
    for r in runs:
        if r.particles == 0:
            out.append({"color": "tab:red", "linestyle": "--"})
        else:
            out.append({"color": _LIQUID_COLOURS[k % len(_LIQUID_COLOURS)], "linestyle": "-"})
            k += 1
    return out


def _plain_log_ticks(axis: Any) -> None:
    """Labels a log axis at 1, 2, 5 x 10^k in plain numbers (the default labels only the decades)."""
    from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

    axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FormatStrFormatter("%g"))
    axis.set_minor_formatter(NullFormatter())


def _finish(fig: Any, ax: Any, ylabel: str, title: str, path: PathLike, xlabel: str = "t (s)",
            zero_line: bool = True, legend: str = "upper right") -> Path:
    """Labels, legend and grid of a one-axes figure, then writes it (see _save)."""
    if zero_line:
        ax.axhline(0, color="0.6", lw=0.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(loc=legend, fontsize="small")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    return _save(fig, path)


def _time(run: Run, table: str = "timeseries") -> np.ndarray:
    return run.column("time", table)


def tip_acceleration(run: Run, path: PathLike, label: Optional[str] = None) -> Path:
    """The tip acceleration in units of g against time (seed Figs. 5 and 8).

    Args:
        run: a run with a structure (timeseries.csv column tip_acceleration).
        path: the PNG to write.
        label: the legend's name of the run (default: its directory's name).

    Returns:
        path.

    Raises:
        ValueError: the run has no tip_acceleration.
    """
    a = run.column("tip_acceleration") / G
    t = _time(run)
    fig = _figure(8, 4)
    ax = fig.add_subplot()
    ax.plot(t, a, lw=0.9, color=_styles([run])[0]["color"], label=label or run.name)
    return _finish(fig, ax, "tip acceleration (g)", "Tip acceleration (seed Figs. 5, 8)", path)


def probes(run: Run, path: PathLike) -> Path:
    """The pressure probes and wave gauges of probes.csv (-fs_probes) against time: the probes'
    pressures (Pa) on the upper axes (a probe with a sensor's time response: its reading, dashed, over the
    raw pressure), the gauges' free-surface elevations (m) on the lower ones.

    Args:
        run: a run with probes.csv.
        path: the PNG to write.

    Returns:
        path.

    Raises:
        ValueError: the run has no probes.csv, or it holds neither probes nor gauges.
    """
    t = run.column("time", "probes")
    pressure = [c for c in run.probes if c.endswith("_pressure[Pa]")]
    gauges = [c for c in run.probes if "_elevation" in c]
    if not pressure and not gauges:
        raise ValueError(f"{run.directory / 'probes.csv'}: neither probes nor gauges")
    panels = [(pressure, "pressure (Pa)", "Pressure probes"), (gauges, "elevation (m)", "Wave gauges")]
    panels = [p for p in panels if p[0]]
    fig = _figure(8, 3.2 * len(panels))
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (cols, ylabel, title) in zip(axes, panels):
        for c in cols:
            line, = ax.plot(t, run.probes[c], lw=0.9, label=c.split("_pressure")[0].split("_elevation")[0])
            reading = c.replace("_pressure[Pa]", "_pressure_filtered[Pa]")
            if reading != c and reading in run.probes:
                ax.plot(t, run.probes[reading], lw=0.9, ls="--", color=line.get_color(),
                        label=f"{line.get_label()} (sensor)")
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.legend(loc="upper right", fontsize="small")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    return _save(fig, path)


def normalized_motion(runs: Sequence[Run], labels: Optional[Sequence[str]], path: PathLike) -> Path:
    """The tip displacement over its initial value, x / x0, for several runs (seed Fig. 9).

    Args:
        runs: runs with a structure, released from a non-zero tip displacement.
        labels: one legend entry per run (None: the directories' names).
        path: the PNG to write.

    Returns:
        path.

    Raises:
        ValueError: a run has no tip_displacement, or starts from zero.
    """
    labels = _labels(runs, labels)
    fig = _figure(8, 4)
    ax = fig.add_subplot()
    for run, label, style in zip(runs, labels, _styles(runs)):
        x = run.column("tip_displacement")
        if len(x) == 0 or x[0] == 0:
            raise ValueError(f"{run.directory / 'timeseries.csv'}: tip_displacement starts at 0, cannot normalize by x(t=0)")
        ax.plot(_time(run), x / x[0], lw=1.0, label=label, **style)
    return _finish(fig, ax, "$x / x_0$ (tip displacement, $x_0 = x(t=0)$)",
                   "Non-dimensional motion of the tip (seed Fig. 9)", path)


def acceleration_envelope(runs: Sequence[Run], labels: Optional[Sequence[str]], path: PathLike) -> Path:
    """The envelope of the tip acceleration on a log scale, with its damping ratio (seed Fig. 10).

    The envelope is the peaks of |tip_acceleration| (find_peaks, one per half cycle); the legend
    gives zeta = -slope / omega of the straight line fitted to ln(envelope), omega from the mean
    period (flexslosh.damping.fit_envelope), drawn dotted.

    Args:
        runs: runs with a structure.
        labels: one legend entry per run (None: the directories' names).
        path: the PNG to write.

    Returns:
        path.

    Raises:
        ValueError: a run has no tip_acceleration, or fewer than two peaks.
    """
    labels = _labels(runs, labels)
    fig = _figure(8, 4.5)
    ax = fig.add_subplot()
    for run, label, style in zip(runs, labels, _styles(runs)):
        a = run.column("tip_acceleration") / G
        try:
            env = fit_envelope(_time(run), a)
        except ValueError as err:
            raise ValueError(f"{run.directory / 'timeseries.csv'}: tip_acceleration: {err}") from None
        ax.semilogy(env.time, env.amplitude, marker="o", ms=3, lw=1.0,
                    label=f"{label}: $\\zeta$ = {100 * env.zeta:.2f} % (slope of ln envelope)", **style)
        ax.semilogy(env.time, env(env.time), color=style["color"], lw=0.7, linestyle=":")
    _plain_log_ticks(ax.yaxis)
    return _finish(fig, ax, "|tip acceleration| peaks (g)", "Envelope of the tip acceleration (seed Fig. 10)", path,
                   zero_line=False)


def energy_balance(run: Run) -> dict[str, np.ndarray]:
    """The liquid's energy budget from energy.csv (seed Eqs. 31-40), per unit width in 2-D.

    Args:
        run: a run with liquid and an energy.csv.

    Returns:
        time; mechanical = (E_kin + E_pot + E_comp) - its initial value; dissipation = work_delta +
        work_alpha + work_wall (negative: energy removed); external = work_ext; other = work_relax +
        work_bounce (those present); residual = mechanical - dissipation - external - other, which
        equals energy.csv's residual_liquid.

    Raises:
        ValueError: no energy.csv, a missing column, or a run without liquid (energies all zero).
    """
    col = lambda name: run.column(name, "energy")  # noqa: E731
    mech = col("E_kin") + col("E_pot") + col("E_comp")
    if run.particles == 0 or not np.any(mech):
        raise ValueError(f"{run.directory / 'energy.csv'}: the run has no liquid (E_kin, E_pot, E_comp are zero)")
    mech = mech - mech[0]
    diss = col("work_delta") + col("work_alpha") + col("work_wall")
    ext = col("work_ext")
    other = sum((run.energy[n] for n in ("work_relax", "work_bounce") if n in run.energy), np.zeros_like(mech))
    return {"time": col("time"), "mechanical": mech, "dissipation": diss, "external": ext, "other": other,
            "residual": mech - diss - ext - other}


def energy_terms(run: Run, path: PathLike) -> Path:
    """The liquid's energy budget against time (seed Fig. 11; colours as in the seed).

    Draws the change of the mechanical energy E_kin + E_pot + E_comp (green), the dissipation
    work_delta + work_alpha + work_wall (red), the external work of the tank's inertial forces
    work_ext (blue) and the residual (grey), see energy_balance.

    Args:
        run: a run with liquid and an energy.csv.
        path: the PNG to write.

    Returns:
        path.

    Raises:
        ValueError: see energy_balance.
    """
    e = energy_balance(run)
    unit = "J" if int(run.summary.get("dim", 2)) == 3 else "J/m"
    fig = _figure(8, 4.5)
    ax = fig.add_subplot()
    t = e["time"]
    ax.plot(t, e["mechanical"], color="tab:green", lw=1.2, label="mechanical $E_k + E_p + E_c - E(0)$")
    ax.plot(t, e["dissipation"], color="tab:red", lw=1.2, label="dissipation $W_\\delta + W_\\alpha + W_{wall}$")
    ax.plot(t, e["external"], color="tab:blue", lw=1.2, label="external work $W_{ext}$")
    if np.any(e["other"]):
        ax.plot(t, e["other"], color="tab:orange", lw=0.8, label="relaxation + bounces")
    ax.plot(t, e["residual"], color="0.4", lw=0.8, linestyle="--", label="residual")
    return _finish(fig, ax, f"energy of the liquid ({unit})", "Energy of the liquid in the tank's frame (seed Fig. 11)",
                   path, legend="best")


def is_prescribed(run: Run) -> bool:
    """Whether the run's tank was moved by a prescribed motion (-fs_structure prescribed: motion_* columns)."""
    return "motion_disp_x" in run.timeseries


#: the prescribed motion's columns: (column, label, factor to the unit shown, "translation" or "rotation")
_MOTION_COLUMNS = (
    ("motion_disp_x", "x", 1e3, "translation"),
    ("motion_disp_y", "y", 1e3, "translation"),
    ("motion_disp_z", "z", 1e3, "translation"),
    ("motion_angle", "roll (about z)", 180 / np.pi, "rotation"),
    ("motion_pitch", "pitch (about x)", 180 / np.pi, "rotation"),
    ("motion_yaw", "yaw (about y)", 180 / np.pi, "rotation"),
    ("motion_axis_angle", "about the axis", 180 / np.pi, "rotation"),
)


def motion_components(run: Run) -> dict[str, dict[str, np.ndarray]]:
    """The prescribed motion's components that move: {"translation": {label: mm}, "rotation": {label: degrees}}.

    A component whose column is absent or zero throughout is left out.

    Raises:
        ValueError: the run has no prescribed motion (no motion_disp_x column).
    """
    if not is_prescribed(run):
        raise ValueError(f"{run.directory / 'timeseries.csv'}: no column 'motion_disp_x' (not a prescribed motion)")
    out: dict[str, dict[str, np.ndarray]] = {"translation": {}, "rotation": {}}
    for col, label, factor, kind in _MOTION_COLUMNS:
        if col in run.timeseries and np.any(run.timeseries[col]):
            out[kind][label] = run.timeseries[col] * factor
    return out


def motion(run: Run, path: PathLike, label: Optional[str] = None) -> Path:
    """A prescribed motion against time: the translations of the tank's reference point (mm) above, its
    rotations (degrees) below; only the components that move (see motion_components).

    Raises:
        ValueError: the run has no prescribed motion.
    """
    comps = motion_components(run)
    t = _time(run)
    fig = _figure(8, 6)
    axes = fig.subplots(2, 1, sharex=True)
    for ax, kind, unit in ((axes[0], "translation", "mm"), (axes[1], "rotation", "degrees")):
        ax.axhline(0, color="0.6", lw=0.5)
        for name, values in comps[kind].items():
            ax.plot(t, values, lw=1.0, label=name)
        if not comps[kind]:
            ax.text(0.5, 0.5, f"no {kind}", transform=ax.transAxes, ha="center", va="center", color="0.5")
        else:
            ax.legend(loc="upper right", fontsize="small")
        ax.set_ylabel(f"{kind} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].set_title(f"Prescribed motion of the tank{' (' + label + ')' if label else ''}")
    axes[1].set_xlabel("t (s)")
    fig.tight_layout()
    return _save(fig, path)


def _wall_names(run: Run) -> list[str]:
    names = []
    for col in run.timeseries:
        if col.startswith("wall_") and col.endswith("_force_x"):
            names.append(col[len("wall_"):-len("_force_x")])
    return names


def wall_loads(run: Run, path: PathLike, label: Optional[str] = None) -> Path:
    """The liquid's loads against time: each wall's force and moment (the wall_* columns, the wall pressure and
    shear integrated; 2-D per metre of width) and, with a structure, the loads the tank receives less their value
    at rest (load_*).

    Raises:
        ValueError: the run has no walls' loads.
    """
    ts, t = run.timeseries, _time(run)
    walls = _wall_names(run)
    if not walls:
        raise ValueError(f"{run.directory / 'timeseries.csv'}: no wall_<name>_force_x column (a run without walls?)")
    three = any(f"wall_{w}_force_z" in ts for w in walls)
    per = "" if three else "/m"
    fig = _figure(8, 7)
    axes = fig.subplots(3 if "load_force_x" in ts else 2, 1, sharex=True)
    for w in walls:
        for a in "xyz" if three else "xy":
            axes[0].plot(t, ts[f"wall_{w}_force_{a}"], lw=0.9, label=f"{w} $F_{a}$")
        for a in "xyz" if three else "":
            axes[1].plot(t, ts[f"wall_{w}_moment_{a}"], lw=0.9, label=f"{w} $M_{a}$")
        if not three:
            axes[1].plot(t, ts[f"wall_{w}_moment"], lw=0.9, label=f"{w} $M_z$")
    axes[0].set_ylabel(f"wall force (N{per}, tank axes)")
    axes[1].set_ylabel(f"wall moment (N m{per})")
    if len(axes) == 3:
        for a in "xyz":
            if f"load_force_{a}" in ts and np.any(ts[f"load_force_{a}"]):
                axes[2].plot(t, ts[f"load_force_{a}"], lw=0.9, label=f"$F_{a}$ (N)")
            if f"load_moment_{a}" in ts and np.any(ts[f"load_moment_{a}"]):
                axes[2].plot(t, ts[f"load_moment_{a}"], lw=0.9, linestyle="--", label=f"$M_{a}$ (N m)")
        axes[2].set_ylabel("tank load less static\n(global axes)")
    for ax in axes:
        ax.axhline(0, color="0.6", lw=0.5)
        ax.grid(alpha=0.3)
        if ax.lines[1:]:
            ax.legend(loc="upper right", fontsize="x-small", ncol=2)
    axes[0].set_title(f"Loads of the liquid{' (' + label + ')' if label else ''}")
    axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    return _save(fig, path)


def damping_vs_amplitude(runs: Sequence[Run], labels: Optional[Sequence[str]], path: PathLike) -> Path:
    """The damping ratio of each cycle of the tip displacement against the cycle's amplitude.

    zeta_i = delta_i / sqrt(4 pi^2 + delta_i^2), delta_i = ln(A_i / A_{i+1}) (damping_per_cycle),
    the structure's own damping ratio (summary.json) dotted.

    Args:
        runs: runs with a structure.
        labels: one legend entry per run (None: the directories' names).
        path: the PNG to write.

    Returns:
        path.

    Raises:
        ValueError: a run has no tip_displacement, or no run has a whole cycle.
    """
    labels = _labels(runs, labels)
    fig = _figure(7, 4.5)
    ax = fig.add_subplot()
    drawn, structural = 0, set()
    for run, label, style in zip(runs, labels, _styles(runs)):
        c = damping_per_cycle(_time(run), run.column("tip_displacement"))
        xi = run.summary.get("structure", {}).get("damping")
        if xi is not None:
            structural.add(float(xi))
        if len(c.zeta) == 0:
            continue
        ax.plot(1e3 * c.amplitude, 100 * c.zeta, marker="o", ms=4, lw=1.0, label=label, **style)
        drawn += 1
    if drawn == 0:
        raise ValueError("no run has a whole cycle of tip_displacement (two positive peaks)")
    for xi in sorted(structural):
        ax.axhline(100 * xi, color="0.4", lw=0.8, linestyle=":", label=f"structural damping {100 * xi:g} %")
    ax.set_xscale("log")
    _plain_log_ticks(ax.xaxis)
    return _finish(fig, ax, "damping ratio $\\zeta_i$ (%)", "Damping per cycle against amplitude", path,
                   xlabel="cycle amplitude $A_i$ (tip displacement, mm)", zero_line=False, legend="best")


def _field_values(snap: dict[str, np.ndarray], field: str, path: Path) -> np.ndarray:
    if field not in snap:
        raise ValueError(f"{path}: no field {field!r} in /particles")
    v = np.asarray(snap[field], dtype=float)
    return np.linalg.norm(v, axis=1) if v.ndim == 2 else v


def snapshots(run: Run, path: PathLike, field: str = "turbulent_viscosity", times: Optional[Sequence[float]] = None,
              count: int = 5, floor: Optional[float] = None) -> Path:
    """Particles coloured by a field on a log scale, one panel per time (seed Figs. 6 and 7).

    Args:
        run: a run with particle snapshots.
        path: the PNG to write.
        field: a snapshot field (vectors are drawn by their magnitude).
        times: the times to show (the nearest snapshot of each); None: count snapshots evenly
            spread from the first to the last.
        count: how many snapshots when times is None.
        floor: the colour scale's lower end (values below it, zero included, get its colour);
            None: 1e-4 of the largest value shown.

    Returns:
        path.

    Raises:
        ValueError: the run has no snapshots, or they lack the field.
    """
    from matplotlib.colors import LogNorm

    if not run.snapshots:
        raise ValueError(f"{run.directory}: no particle snapshots (snapshots.csv / snapshot_*.h5)")
    stimes = np.array([s[0] for s in run.snapshots])
    if times is None:
        picks = np.unique(np.round(np.linspace(0, len(stimes) - 1, min(count, len(stimes)))).astype(int))
    else:
        picks = np.array([int(np.argmin(np.abs(stimes - t))) for t in times])
    snaps = [read_snapshot(run.snapshots[k][1]) for k in picks]
    values = [_field_values(s, field, s.path) for s in snaps]
    top = max(float(np.max(v)) if len(v) else 0.0 for v in values)
    lo = floor if floor is not None else (1e-4 * top if top > 0 else 1e-12)
    hi = max(top, 10 * lo)
    pos = np.concatenate([s["position"][:, :2] for s in snaps])
    (x0, y0), (x1, y1) = pos.min(axis=0), pos.max(axis=0)
    pad = 0.02 * max(x1 - x0, y1 - y0, 1e-12)
    x0, x1, y0, y1 = x0 - pad, x1 + pad, y0 - pad, y1 + pad
    width = 10.0  # inches of the panels
    panel_h = min(max(width * (y1 - y0) / (x1 - x0), 0.4), 4.0)
    fig = _figure(width + 1.6, len(snaps) * (panel_h + 0.5) + 0.6, layout="constrained")
    axes = fig.subplots(len(snaps), 1, squeeze=False)[:, 0]
    dx = float(run.summary.get("dx", 0)) or np.sqrt((x1 - x0) * (y1 - y0) / max(len(values[0]), 1))
    size = (dx / (x1 - x0) * width * 72) ** 2  # marker area in points^2: about one particle spacing
    norm = LogNorm(vmin=lo, vmax=hi, clip=True)
    for ax, snap, v in zip(axes, snaps, values):
        sc = ax.scatter(snap["position"][:, 0], snap["position"][:, 1], c=np.clip(v, lo, hi), s=size, norm=norm,
                        cmap="viridis", marker="s", linewidths=0)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_title(f"t = {snap.time:.3f} s", fontsize="small")
        ax.set_ylabel("y (m)")
    axes[-1].set_xlabel("x (m)")
    name = field.replace("_", " ")
    fig.colorbar(sc, ax=list(axes), label=f"{name} ({_UNITS.get(field, '-')})", fraction=0.03, pad=0.02)
    fig.suptitle(f"{name} of the liquid, {run.name} (seed Figs. 6, 7)")
    return _save(fig, path)

"""The validation report: run each validation case, compare it with its reference, write the report.

``python3 -m flexslosh.validate`` (``make validate``) runs flexslosh on every validation case at the
resolutions of :data:`RESOLUTIONS`, compares the quantities each case is about with an exact solution
or published data (docs/validation/data/), draws one figure per case (the reference and flexslosh on
one plot) and keeps one section of Markdown per case in ``docs/validation/sections/NAME.json``; the
report ``docs/validation/README.md`` is then assembled from the sections present, a case never run
getting a section that says so with the command that runs it. Running a subset
(``--cases taylor_green,dam_break``) replaces those sections only.

Each case is a function ``case_NAME(ctx) -> Section``: it runs the binary (the case file of cases/
with the resolution on the command line), reads the output with :func:`flexslosh.output.read_run`,
measures errors (:class:`Check`: a value against its tolerance, PASS or FAIL) and draws its PNG.
``--quick`` runs every case at a coarse resolution and for a short time (a smoke run that keeps the
machinery working, tests/python/test_validate.py; its numbers mean nothing).

Usage::

    python3 -m flexslosh.validate [--cases a,b] [--quick] [--out DIR] [--work DIR]
                                  [--resolution CASE=dx1,dx2] [--ranks N] [--reuse]
"""
from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional, Sequence

import numpy as np

from .damping import SEED_BANDS, band_damping, convergence, damping_per_cycle
from .figures import snapshots as snapshot_figure
from .output import Run, code_revision, read_csv, read_run, read_snapshot
from .waves import exact_viscous_mode, fit_decaying_oscillation, fit_decaying_wave

__all__ = ["Check", "Section", "Context", "CASES", "RESOLUTIONS", "QUICK", "run_cases", "write_report", "main"]

REPO = Path(__file__).resolve().parents[2]
G = 9.81

#: The resolutions (dx) ``make validate`` runs, per case; two where convergence is the point.
RESOLUTIONS: dict[str, list[float]] = {
    "taylor_green": [0.02, 0.01],
    "hydrostatic": [0.0015],
    "hydrostatic_3d": [0.0012],
    "baffles_at_rest_3d": [0.0025],
    "standing_wave": [0.04, 0.02],
    "standing_wave_3d": [0.1, 0.05, 1 / 30],
    "standing_wave_3d_10": [0.1, 0.05, 1 / 30],
    "dam_break": [0.05, 0.025, 0.0125],
    "dam_break_3d": [0.01],
    "dam_break_pressure": [0.03, 0.015],
    "dam_break_lobovsky": [0.015, 0.0075, 0.00375],
    "roll_tank": [0.0124, 0.0062, 0.0031],
    "impact_c0": [0.015, 0.0075, 0.00375],
    "impact_c0_roll": [0.0124, 0.0062, 0.0031],
    "beam": [0.0],
    "energy": [0.05],
    "seed": [0.005],
    "seed_convergence": [0.005, 0.0025, 0.00125],
    "reduced_model": [0.01, 0.005],
    "sway_mass": [0.01, 0.00707, 0.005],
    "sway_mass_3d": [0.02, 0.0141, 0.01],
    "seed_slams": [0.002, 0.001, 0.0007],
    "seed_slams_finest": [0.00035],
    "shapes_at_rest": [0.005, 0.0035, 0.0025],
    "shapes_at_rest_2d": [0.0025, 0.00125, 0.000625],
}

#: The coarse resolutions of ``--quick`` (and its shorter final times, in each case function).
QUICK: dict[str, list[float]] = {
    "taylor_green": [0.05],
    "hydrostatic": [0.006],
    "hydrostatic_3d": [0.01],
    "baffles_at_rest_3d": [0.005],
    "standing_wave": [0.1],
    "standing_wave_3d": [0.2],
    "standing_wave_3d_10": [0.2],
    "dam_break": [0.1],
    "dam_break_3d": [0.025],
    "dam_break_pressure": [0.06],
    "dam_break_lobovsky": [0.03],
    "roll_tank": [0.0248],
    "impact_c0": [0.03],
    "impact_c0_roll": [0.0248],
    "beam": [0.0],
    "energy": [0.1],
    "seed": [0.01],
    "seed_convergence": [0.01, 0.00707, 0.005],
    "reduced_model": [0.01],
    "sway_mass": [0.02],
    "sway_mass_3d": [0.04],
    "seed_slams": [0.01, 0.005],
    "seed_slams_finest": [0.0035],
    "shapes_at_rest": [0.005],
    "shapes_at_rest_2d": [0.0025],
}


@dataclass
class Check:
    """One measured error against its tolerance.

    Attributes:
        what: what is measured (one line of Markdown).
        value: the measured figure.
        tolerance: the bound it must meet.
        kind: "max" (value <= tolerance passes) or "min" (value >= tolerance passes).
        fmt: the format of value and tolerance (e.g. "{:.2%}").
    """

    what: str
    value: float
    tolerance: float
    kind: str = "max"
    fmt: str = "{:.3g}"

    @property
    def passed(self) -> bool:
        if not math.isfinite(self.value):
            return False
        return bool(self.value <= self.tolerance if self.kind == "max" else self.value >= self.tolerance)

    def row(self) -> str:
        """The check as a row of the section's table."""
        sign = "<=" if self.kind == "max" else ">="
        verdict = "PASS" if self.passed else "**FAIL**"
        return f"| {self.what} | {self.fmt.format(self.value)} | {sign} {self.fmt.format(self.tolerance)} | {verdict} |"


@dataclass
class RunInfo:
    """One flexslosh run of a case: its label, command line, particles, wall time (s) and the commit it ran on."""

    label: str
    command: str
    particles: int
    wall: float
    commit: str = ""


@dataclass
class Section:
    """A case's section of the report.

    Attributes:
        name: the case's key (taylor_green, ...).
        title: the section's heading.
        compared: what is compared (Markdown).
        reference: the reference, cited, with its data file (Markdown).
        figure: the PNG, relative to the report's folder ("" when none).
        caption: what the figure shows.
        checks: the measured errors against their tolerances.
        runs: the runs made.
        notes: further remarks (Markdown paragraphs).
    """

    name: str
    title: str
    compared: str
    reference: str
    figure: str = ""
    caption: str = ""
    checks: list[Check] = field(default_factory=list)
    runs: list[RunInfo] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    dxs: list[float] = field(default_factory=list)  # the resolutions run (set by run_cases)

    def markdown(self, quick: bool = False) -> str:
        """The section as Markdown (heading, compared, reference, figure, checks, runs, notes)."""
        out = [f"## {self.title}", ""]
        npass = sum(c.passed for c in self.checks)
        status = "all checks pass" if npass == len(self.checks) else f"{len(self.checks) - npass} of {len(self.checks)} checks FAIL"
        stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        mode = " (--quick smoke run: the numbers mean nothing)" if quick else ""
        earlier = sorted({r.commit for r in self.runs if r.commit and r.commit != _commit()})  # runs read by --reuse
        runs_on = f" (its runs on {', '.join(earlier)})" if earlier else ""
        out += [f"*Run {stamp} on commit {_commit()}{runs_on}{mode}: {status}.*", ""]
        out += [f"**Compared.** {self.compared}", "", f"**Reference.** {self.reference}", ""]
        if self.figure:
            out += [f"![{self.caption}]({self.figure})", "", f"*{self.caption}*", ""]
        if self.checks:
            out += ["| measured | value | tolerance | |", "|---|---|---|---|"] + [c.row() for c in self.checks] + [""]
        if self.runs:
            out += ["| run | particles | wall time | command |", "|---|---|---|---|"]
            out += [f"| {r.label} | {r.particles} | {r.wall:.0f} s | `{r.command}` |" for r in self.runs] + [""]
        for note in self.notes:
            out += [note, ""]
        return "\n".join(out)


#: The checkpoint interval (steps) of the runs that take from ten minutes to hours (the 3-D hydrostatic tank and standing
#: waves, the rolled tank, Lobovsky's dam break; the seed studies have their own): an interrupted `make validate`
#: continues them from their newest checkpoint (Context.run).
LONG_RUN_CHECKPOINTS = 2000


@dataclass
class Context:
    """What a case function needs: where to run, at which resolutions, how.

    Attributes:
        exe: the flexslosh executable.
        work: the folder of the runs' output (one folder per case and run).
        out: the report's folder (figures go there).
        quick: the smoke-run mode (coarse, short).
        resolutions: per case, the dx values to run.
        ranks: MPI ranks per run (1: no mpirun).
        reuse: take a run whose folder holds the same command's finished run (its validate_run.json)
            instead of running it again.
        ensemble: releases per run where a case measures its scatter (seed_convergence: the tip's preload
            perturbed by 1e-4 of itself, SEED_ENSEMBLE_PRELOADS).
    """

    exe: Path
    work: Path
    out: Path
    quick: bool = False
    resolutions: dict[str, list[float]] = field(default_factory=dict)
    ranks: int = 1
    reuse: bool = False
    ensemble: int = 1

    def dxs(self, case: str) -> list[float]:
        table = QUICK if self.quick else RESOLUTIONS
        return list(self.resolutions.get(case, table[case]))

    def run(self, case: str, label: str, args: Sequence[Any], runs: list[RunInfo], checkpoints: int = 0) -> Run:
        """Runs flexslosh from the repository's root with args into work/case/label, appends its
        RunInfo to runs and returns the run read; raises RuntimeError with the output's end if it fails.
        With reuse, a finished run of the same command in that folder is read instead (its wall time kept).
        checkpoints > 0: the run writes a checkpoint every that many steps, and a run of the same command that was
        interrupted (its folder holds validate_started.json and a checkpoint, no validate_run.json) continues from
        its newest checkpoint (-fs_restart) instead of starting again; the wall times of its parts add up."""
        outdir = self.work / case / label
        args = [str(a) for a in args] + (["-fs_checkpoint_interval", str(checkpoints)] if checkpoints > 0 else [])
        args += ["-fs_output_dir", str(outdir), "-fs_progress", "0"]
        cmd = [str(self.exe)] + args
        if self.ranks > 1:
            cmd = ["mpirun", "--oversubscribe", "-n", str(self.ranks)] + cmd
        record = outdir / "validate_run.json"  # written after the run finished: its command, wall time and commit
        started = outdir / "validate_started.json"  # written before: its command and the wall time of its parts so far
        done = json.loads(record.read_text()) if self.reuse and record.is_file() else {}
        if done.get("command") == cmd:
            wall, commit = float(done["wall"]), done.get("commit", "unknown")
            print(f"  {case}/{label}: reused ({wall:.0f} s when run)", flush=True)
        else:
            part = json.loads(started.read_text()) if checkpoints > 0 and started.is_file() and not record.is_file() else {}
            newest = sorted(outdir.glob("checkpoint_*.h5"))[-1:] if part.get("command") == cmd else []
            before = float(part.get("wall", 0.0)) if newest else 0.0
            if newest:
                print(f"  {case}/{label}: continuing from {newest[0].name}", flush=True)
            else:
                outdir.mkdir(parents=True, exist_ok=True)
                for old in outdir.glob("*"):
                    if old.is_file():
                        old.unlink()
            env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
            t0 = time.time()
            if checkpoints > 0:
                started.write_text(json.dumps({"command": cmd, "wall": before}))
            log = outdir / "validate_log.txt"
            with open(log, "a") as out:
                proc = subprocess.Popen(cmd + (["-fs_restart", str(newest[0])] if newest else []), cwd=REPO, env=env,
                                        stdout=out, stderr=subprocess.STDOUT, text=True)
                while True:  # the wall time so far, for a continuation after an interruption to add to
                    try:
                        proc.wait(timeout=5.0)
                        break
                    except subprocess.TimeoutExpired:
                        if checkpoints > 0:
                            started.write_text(json.dumps({"command": cmd, "wall": before + time.time() - t0}))
            tail = log.read_text()[-3000:]
            wall = before + time.time() - t0
            if proc.returncode != 0:
                raise RuntimeError(f"flexslosh failed (exit {proc.returncode}): {' '.join(cmd)}\n{tail}")
            commit = _commit()
            record.write_text(json.dumps({"command": cmd, "wall": wall, "commit": commit}))
            print(f"  {case}/{label}: {wall:.0f} s", flush=True)
        run = read_run(outdir)
        shown = ["flexslosh"] + [a for a in args[: len(args) - 4]]
        if self.ranks > 1:
            shown = ["mpirun", "-n", str(self.ranks)] + shown
        runs.append(RunInfo(label, " ".join(shown), run.particles, wall, commit))
        return run


def _commit() -> str:
    """The repository's commit (short hash, "+dirty" with uncommitted changes), or "unknown". The report's own folder
    (docs/validation, which each case rewrites) does not count: else every case after the first is stamped dirty."""
    return code_revision(exclude=("docs/validation",))


def _figure(width: float = 7.0, height: float = 4.0, ncols: int = 1) -> tuple[Any, Any]:
    """A matplotlib figure (Agg canvas) with ncols axes side by side."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, ncols)
    return fig, axes


def _save(fig: Any, ctx: Context, name: str) -> str:
    """Saves fig as ctx.out/NAME.png at 90 dpi; returns the file's name (relative to the report)."""
    ctx.out.mkdir(parents=True, exist_ok=True)
    fig.savefig(ctx.out / f"{name}.png", dpi=90)
    return f"{name}.png"


def _data(name: str) -> dict[str, np.ndarray]:
    """A reference data file of docs/validation/data/ (comment lines first, then a CSV header)."""
    return read_csv(REPO / "docs" / "validation" / "data" / name)


def _label(dx: float) -> str:
    return f"dx{dx:g}"


def _from_repo(path: Path) -> str:
    """path relative to the repository's root where it lies inside it (the runs start there): the report shows no
    machine's folders."""
    return os.path.relpath(path, REPO) if Path(path).resolve().is_relative_to(REPO.resolve()) else str(path)


def _case(name: str) -> str:
    return f"cases/{name}.opts"


# ----------------------------------------------------------------------------- the cases


def case_taylor_green(ctx: Context) -> Section:
    """Taylor-Green vortex at Re = 100: the kinetic energy's decay against exp(-16 pi^2 t/Re)."""
    sec = Section("taylor_green", "Taylor-Green vortex (2-D, periodic, Re = 100)",
                  "The kinetic energy E_k(t)/E_k(0) and its decay rate, fitted over the run, against the exact "
                  "solution at two resolutions (L/dx); the rate must converge to the exact one.",
                  "Exact: E_k(t) = E_k(0) exp(-16 pi^2 t U/(L Re)) (Taylor & Green 1937; docs/validation.md), "
                  "16 pi^2/Re = 1.579 at Re = 100: the formula, no data file.")
    tmax = 0.2 if ctx.quick else 1.0
    rate_exact = 16 * math.pi**2 / 100
    fig, ax = _figure()
    tt = np.linspace(0, tmax, 200)
    ax.plot(tt, np.exp(-rate_exact * tt), "k-", lw=2, label="exact")
    for dx in ctx.dxs("taylor_green"):
        r = ctx.run("taylor_green", _label(dx), ["-options_file", _case("taylor_green"), "-fs_dx", dx, "-ts_max_time", tmax,
                                                 "-fs_output_interval", 0], sec.runs)
        t, ek = r.column("time"), r.column("kinetic_energy")
        rate = -np.polyfit(t[t > 0.05 * tmax], np.log(ek[t > 0.05 * tmax]), 1)[0]
        ax.plot(t, ek / ek[0], "--", label=f"flexslosh L/dx = {1 / dx:.0f}")
        sec.checks.append(Check(f"L/dx = {1 / dx:.0f}: decay rate, relative error", abs(rate / rate_exact - 1), 0.02, fmt="{:.2%}"))
        sec.checks.append(Check(f"L/dx = {1 / dx:.0f}: max abs(E_k/E_k,exact - 1)", float(np.max(np.abs(ek / (ek[0] * np.exp(-rate_exact * t)) - 1))),
                                0.03, fmt="{:.2%}"))
    ax.set_xlabel("t U/L")
    ax.set_ylabel("E_k / E_k(0)")
    ax.set_yscale("log")
    ax.legend()
    sec.figure = _save(fig, ctx, "taylor_green")
    sec.caption = "Taylor-Green vortex: kinetic energy against the exact decay, two resolutions"
    return sec


def _hydrostatic(ctx: Context, name: str, what: str = "") -> Section:
    title = TITLES[name]
    sec = Section(name, title,
                  "A liquid at rest, H = 0.03 m deep, for t sqrt(g/H) = 20: the particles' pressure against rho0 g (H - y) "
                  "at the end (rms error over the particles deeper than 2h, relative to rho0 g H), the vertical load of the "
                  "liquid on the walls (all their parts) against its weight, and the rms speed sqrt(2 E_k/M) against "
                  "sqrt(g H) (the fastest particle's speed is given in the caption)." + what,
                  "Exact: p(y) = rho0 g (H - y), wall load = weight (docs/validation.md): formulas, no data file.")
    dx = ctx.dxs(name)[0]
    tmax = 0.15 if ctx.quick else 1.1
    r = ctx.run(name, _label(dx), ["-options_file", _case(name), "-fs_dx", dx, "-ts_max_time", tmax, "-fs_output_interval", tmax / 2], sec.runs,
                checkpoints=LONG_RUN_CHECKPOINTS)
    H, rho0 = 0.03, 1000.0
    snap = read_snapshot(r.snapshots[-1][1])
    y = snap["position"][:, 1]
    p = snap["pressure"]
    h = float(r.summary.get("h", 2 * dx))
    deep = y < H - 2 * h
    err = float(np.sqrt(np.mean((p[deep] - rho0 * G * (H - y[deep])) ** 2)) / (rho0 * G * H))
    fy = sum(v for c, v in r.timeseries.items() if c.startswith("wall_") and c.endswith("_force_y"))
    weight = float(r.column("mass")[-1]) * G  # the liquid's weight (per unit width in 2-D, as the load)
    tail = r.column("time") > 0.5 * tmax
    load = abs(abs(float(np.mean(fy[tail]))) / weight - 1)  # the load on the tank points down
    # the rms speed sqrt(2 E_k / M) (the quiet the specification asks for), and the largest particle's speed
    vrms = np.sqrt(2 * r.column("kinetic_energy") / r.column("mass")) / math.sqrt(G * H)
    vmax = float(np.max(r.column("max_velocity")[tail])) / math.sqrt(G * H)
    sec.checks += [Check("rms(p - rho0 g (H - y)) / (rho0 g H), particles deeper than 2h", err, 0.01, fmt="{:.2%}"),
                   Check("abs(wall load / weight - 1), mean over the second half", load, 0.01, fmt="{:.2%}"),
                   Check("rms speed / sqrt(g H), largest over the second half", float(np.max(vrms[tail])), 0.01,
                         fmt="{:.2e}")]
    fig, ax = _figure(6, 4)
    ax.plot(p / (rho0 * G * H), y / H, ".", ms=2, alpha=0.4, label=f"flexslosh H/dx = {H / dx:.0f}, t = {snap.time:.2f} s")
    yy = np.linspace(0, 1, 50)
    ax.plot(1 - yy, yy, "k-", lw=2, label="exact rho0 g (H - y)")
    ax.set_xlabel("p / (rho0 g H)")
    ax.set_ylabel("y / H")
    ax.legend()
    sec.figure = _save(fig, ctx, name)
    sec.caption = (f"{title}: the particles' pressure against depth at the end of the run, and the exact profile "
                   f"(the fastest particle in the second half: {vmax:.2e} sqrt(g H))")
    return sec


def case_hydrostatic(ctx: Context) -> Section:
    """The 2-D hydrostatic tank (cases/hydrostatic.opts)."""
    return _hydrostatic(ctx, "hydrostatic")


def case_hydrostatic_3d(ctx: Context) -> Section:
    """The 3-D hydrostatic box (cases/hydrostatic_3d.opts)."""
    return _hydrostatic(ctx, "hydrostatic_3d")


def case_baffles_at_rest_3d(ctx: Context) -> Section:
    """Lifted baffles at rest in 3-D (cases/baffles_at_rest_3d.opts)."""
    return _hydrostatic(ctx, "baffles_at_rest_3d",
                        " The tank: two compartments 0.1 m long and 0.02 m wide, the baffle between them lifted 5 mm off "
                        "the floor, with `-fs_walls_visibility all` and `-fs_walls_repulsion 0.5` (docs/walls.md).")


def _standing_wave(ctx: Context, name: str, dim: int, mode_z: int = 1, width: float = 1.0) -> Section:
    """The standing wave of cases/standing_wave.opts (2-D) or cases/standing_wave_3d.opts (3-D: mode (1, mode_z)
    in a box width h wide)."""
    L, h, A, Re = 2.0, 1.0, 0.05, 250.0
    nu = 1.0 / Re  # non-dimensional: g = h = 1, nu = h sqrt(g h)/Re
    kz = mode_z * math.pi / width if dim == 3 else 0.0
    k = math.sqrt((math.pi / L) ** 2 + kz**2)
    omega = math.sqrt(k * math.tanh(k * h))
    omega_nu, rate_nu = exact_viscous_mode(k, h, nu)
    ptol = 0.01 if dim == 2 else 0.02
    title = "Standing wave (2-D, free-slip walls)" if dim == 2 else f"Standing wave (3-D box, mode (1, {mode_z}))"
    dxs = ctx.dxs(name)
    converge = dim == 3 and len(dxs) >= 3  # the 3-D decay is checked by its convergence
    how = ", at two resolutions (h/dx)." if len(dxs) == 2 else "."
    if converge:
        how = (f" at three resolutions, in a box {L:g} h long and {width:g} h wide"
               + (f": the mode's wavelength is {2 * math.pi / k:.1f} h against the 2-D mode's {2 * L:g} h, so at the same "
                  f"h/dx it has {2 * L * k / (2 * math.pi):.1f} times fewer particles a wavelength" if mode_z else
                  f" (the 2-D wave, {width / max(dxs):.0f} to {width / min(dxs):.0f} particles across)")
               + ". The period is checked at h/dx >= 20; the decay at the finest and by its convergence, its excess over "
               "the exact rate shrinking by a fifth or more at each refinement (h/dx = 10 enters only that).")
    sec = Section(name, title,
                  "A small standing wave (A/h = 0.05, Re = 250): its period and its energy's decay rate, from a least-squares "
                  "fit of exp(-mu t)(b cos wt + c sin wt) + d to the mode's amplitude a(t) (the time series' mode_amplitude: "
                  "the particles' velocity projected on the mode's initial field; its energy decays at 2 mu) over the whole "
                  "record (python/flexslosh/waves.py), against the exact linear viscous mode" + how + " The kinetic energy's "
                  "own fit is in the notes: E_k also holds the particles' small-scale motion (their settling at the walls), "
                  "which the mode does not project on and which in 3-D at h/dx = 10 is as large as the wave's energy at the "
                  "start (docs/walls.md).",
                  f"Exact (linear, free-slip): the inviscid omega^2 = g k tanh(k h) (omega = {omega:.5f}, wave period "
                  f"{2 * math.pi / omega:.4f}, energy decay 4 nu k^2 = {4 * nu * k * k:.5f} to leading order in nu) and the exact "
                  f"linear viscous mode (Lamb's relation at finite depth, flexslosh.waves.exact_viscous_mode: period "
                  f"{2 * math.pi / omega_nu:.4f}, energy decay {rate_nu:.5f}); docs/validation.md; formulas, no data file.")
    tmax = (3.0 if dim == 2 else 2.0) if ctx.quick else (20.0 if dim == 2 else 8.0 if mode_z else 15.0)
    extra: list[Any] = [] if dim == 2 or (mode_z == 1 and width == 1.0) else ["-fs_sw_mode_z", mode_z, "-fs_sw_width", width]
    fig, ax = _figure()
    first = True
    decays: list[tuple[float, float]] = []  # (dx, decay rate / rate_nu)
    for dx in dxs:
        r = ctx.run(name, _label(dx), ["-options_file", _case("standing_wave" if dim == 2 else "standing_wave_3d"), "-fs_dx", dx,
                                       "-ts_max_time", tmax, "-fs_output_interval", 0] + extra, sec.runs,
                    checkpoints=LONG_RUN_CHECKPOINTS)
        t, ek = r.column("time"), r.column("kinetic_energy")
        amp = "mode_amplitude" in r.timeseries  # runs before the column: the kinetic energy's fit
        if first:
            ax.plot(t, r.column("mode_amplitude_linear" if amp else "kinetic_energy_linear"), "k-", lw=2,
                    label="linear theory (inviscid period, " + ("2 nu k^2)" if amp else "4 nu k^2)"))
            first = False
        ax.plot(t, r.column("mode_amplitude") if amp else ek, "--", label=f"flexslosh h/dx = {h / dx:.0f}")
        if t[-1] * omega / math.pi >= 2:  # at least one period of the wave, two of the energy
            we, lam_e, _ = fit_decaying_oscillation(t, ek / ek[0], omega)
            w, lam, _ = fit_decaying_wave(t, r.column("mode_amplitude"), omega) if amp else (we, lam_e, None)
            decays.append((dx, lam / rate_nu))
            if not converge or h / dx >= 19.5:
                sec.checks.append(Check(f"h/dx = {h / dx:.0f}: wave period / the exact viscous mode's - 1 (abs)", abs(omega_nu / w - 1), ptol, fmt="{:.2%}"))
            if not converge:
                sec.checks.append(Check(f"h/dx = {h / dx:.0f}: decay rate / the exact viscous mode's - 1 (abs)", abs(lam / rate_nu - 1), 0.10, fmt="{:.1%}"))
            sec.notes.append(f"h/dx = {h / dx:.0f}: period {omega / w - 1:+.2%} against the inviscid linear theory; decay "
                             f"{lam / (4 * nu * k * k):.3f} x 4 nu k^2, {lam / rate_nu:.3f} x the exact viscous rate"
                             + (f" (the kinetic energy's fit: period {omega / we - 1:+.2%}, decay {lam_e / rate_nu:.3f} x)." if amp
                                else ", from the kinetic energy (a run without the mode_amplitude column)."))
        else:
            sec.notes.append(f"h/dx = {h / dx:.0f}: shorter than two periods of the energy; no period or decay measured.")
    if converge and len(decays) >= 2:
        excess = [abs(v - 1) for _, v in decays]
        res = ", ".join(f"{h / d:.0f}" for d, _ in decays)
        sec.checks.append(Check(f"h/dx = {h / decays[-1][0]:.0f}: decay rate / the exact viscous mode's - 1 (abs)", excess[-1], 0.10, fmt="{:.1%}"))
        sec.checks.append(Check(f"decay rate's excess over the exact: the largest ratio finer / coarser through h/dx = {res}",
                                max(b / a for a, b in zip(excess, excess[1:])), 0.8, fmt="{:.2f}"))
    ax.set_xlabel("t sqrt(g/h)")
    ax.set_ylabel("mode amplitude a(t) / a(0)" if amp else "E_k / (rho0 g h^2 L)" if dim == 2 else "E_k")
    ax.legend()
    sec.figure = _save(fig, ctx, name)
    sec.caption = f"{title}: " + ("the mode's amplitude" if amp else "kinetic energy") + " against linear theory with its viscous decay"
    return sec


def case_standing_wave(ctx: Context) -> Section:
    """The 2-D standing wave (cases/standing_wave.opts) at two resolutions."""
    return _standing_wave(ctx, "standing_wave", 2)


def case_standing_wave_3d(ctx: Context) -> Section:
    """The 3-D standing wave, mode (1, 1) (cases/standing_wave_3d.opts)."""
    return _standing_wave(ctx, "standing_wave_3d", 3)


def case_standing_wave_3d_10(ctx: Context) -> Section:
    """The 3-D standing wave, mode (1, 0) in a box half as wide (cases/standing_wave_3d.opts, -fs_sw_mode_z 0
    -fs_sw_width 0.5)."""
    return _standing_wave(ctx, "standing_wave_3d_10", 3, mode_z=0, width=0.5)


def _dam_break(ctx: Context, name: str, dim: int) -> Section:
    a = 1.0 if dim == 2 else 0.1
    front, column = _data("martin_moyce_1952_front.csv"), _data("martin_moyce_1952_column.csv")
    title = "Dam break: surge front and column (Martin & Moyce 1952)" + (" in 3-D" if dim == 3 else "")
    sec = Section(name, title,
                  "A column a wide and 2a high collapsing on a dry floor (free-slip walls): the surge front Z = x/a against "
                  "T = t sqrt(2g/a) (relative error at the measured points with T >= 0.8, until the front reaches the far wall "
                  "at Z = 4) and the residual column height H/(2a) against tau = t sqrt(g/a) (relative error to tau = 1.3)"
                  + (", at two resolutions (a/dx)." if dim == 2 else "."),
                  "Martin, J. C. & Moyce, W. J. (1952), Part IV. An experimental study of the collapse of liquid columns on a "
                  "rigid horizontal plane, Phil. Trans. R. Soc. Lond. A 244 (882), 312-324, doi:10.1098/rsta.1952.0006: "
                  "[front](data/martin_moyce_1952_front.csv), [column](data/martin_moyce_1952_column.csv).")
    tmax = (0.3 if dim == 2 else 0.05) if ctx.quick else round(3.1 / math.sqrt(2 * G / a), 4)
    fig, (ax1, ax2) = _figure(9, 4, 2)
    ax1.plot(front["T"], front["Z"], "ko", label="Martin & Moyce 1952")
    ax2.plot(column["tau"], column["H_over_2a"], "ko", label="Martin & Moyce 1952")
    for dx in ctx.dxs(name):
        r = ctx.run(name, _label(dx), ["-options_file", _case(name), "-fs_dx", dx, "-ts_max_time", tmax, "-fs_output_interval", 0], sec.runs)
        t = r.column("time")
        # the case writes front_position and column_height in metres
        T, Z = t * math.sqrt(2 * G / a), r.column("front_position") / a
        tau, hc = t * math.sqrt(G / a), r.column("column_height") / (2 * a)
        ax1.plot(T, Z, "-", label=f"flexslosh a/dx = {a / dx:.0f}")
        ax2.plot(tau, hc, "-", label=f"flexslosh a/dx = {a / dx:.0f}")
        pts = (front["T"] >= 0.8) & (front["T"] <= T[-1]) & (front["Z"] < 3.9)
        if np.any(pts):
            err = np.interp(front["T"][pts], T, Z) / front["Z"][pts] - 1
            sec.checks.append(Check(f"a/dx = {a / dx:.0f}: front, max abs relative error (T >= 0.8, {int(pts.sum())} points)",
                                    float(np.max(np.abs(err))), 0.10, fmt="{:.1%}"))
            sec.checks.append(Check(f"a/dx = {a / dx:.0f}: front, mean relative error", float(abs(np.mean(err))), 0.10, fmt="{:.1%}"))
        pc = (column["tau"] <= min(1.3, tau[-1]))
        if np.any(pc):
            herr = np.interp(column["tau"][pc], tau, hc) / column["H_over_2a"][pc] - 1
            sec.checks.append(Check(f"a/dx = {a / dx:.0f}: column height, max abs relative error (tau <= 1.3)",
                                    float(np.max(np.abs(herr))), 0.025, fmt="{:.1%}"))
    ax1.set_xlabel("T = t sqrt(2g/a)")
    ax1.set_ylabel("Z = x_front / a")
    ax2.set_xlabel("tau = t sqrt(g/a)")
    ax2.set_ylabel("H / (2a)")
    ax1.legend()
    ax2.legend()
    sec.figure = _save(fig, ctx, name)
    sec.caption = f"{title}: front (left) and column height (right), experiment and flexslosh"
    sec.notes.append("Single-phase SPH with free-slip walls is known to run ahead of this experiment (docs/walls.md: "
                     "the front +9 % at T = 3, up to +20 % near T = 1.2); published copies of the data differ by about 5 %.")
    return sec


def case_dam_break(ctx: Context) -> Section:
    """Martin & Moyce's dam break in 2-D at two resolutions (cases/dam_break.opts)."""
    return _dam_break(ctx, "dam_break", 2)


def case_dam_break_3d(ctx: Context) -> Section:
    """Martin & Moyce's dam break in 3-D (cases/dam_break_3d.opts)."""
    return _dam_break(ctx, "dam_break_3d", 3)


#: Issue 14: why the experiment's P1 check fails. Sources read and extra runs (probes at more heights, H/dx = 40) of
#: 2026-12-02; fixed text, so that a rerun of the report keeps it.
DAM_BREAK_PRESSURE_NOTES = [
    "Issue 14 (checked 2026-12-02). The gap runs this way: on the plateau (t* in [3, 5.5]) the experiment's P1 reads "
    "0.549 rho g H, De Courcy's P4 (H/dx = 400) 0.364 and flexslosh (H/dx = 40) 0.33-0.35 at 0.16 m, so 2-D "
    "single-phase SPH sits about 35 % below the measurement (the measurement about 50 % above it).",
    "flexslosh's wall is not the cause: extra 8.4 mm probes at De Courcy's four heights (H/dx = 40) read plateau "
    "means of 1.029, 0.996, 0.894 and 0.354 at y = 6, 30, 60 and 160 mm against De Courcy's 0.978, 0.918, 0.818 and "
    "0.364 (+5 %, +9 %, +9 %, -3 %; his P2 and P3 digitized in the same TrixiParticles.jl folder as P1 and P4, not "
    "kept here). Nor is the digitizing: PySPH's own copy of the same record (pypr/pysph, "
    "pysph/examples/db_exp_data.py, get_buchner_data, commit a57e6534; BSD licence) gives a plateau mean of 0.547 "
    "against 0.549 here, and its peak 0.887 at t* = 5.84 against 0.877 at 5.83.",
    "The sensor's height and size are not settled by the sources read. TrixiParticles.jl's 2024 set-up "
    "(validation/dam_break_2d/validation_dam_break_2d.jl, commit 4dec79c45eae5ea9fb63a27e14d9e37a9a3413cf) gives P1's"
    " centre at 0.16 m and a sensor 9 mm high, and puts its numerical sensor's top at that centre (4.5 mm lower), "
    "quoting Adami, Hu & Adams (2012, J. Comput. Phys. 231, 7057-7075), who cite Greco for that shift and for "
    "uncertainties in the measurements; its July 2025 set-up (commit 0f7d337d493cd0b56a7fc00b5fe8e8f261dac9ef) made "
    "the sensor 0.09 m high, which matches this section's 0.09 m and the earlier 'moved 0.045 m lower'. PySPH's "
    "docstring puts the same record at (5.366 H, 0.2 H), i.e. y = 0.12 m. The size matters little (at 0.16 m "
    "flexslosh reads 0.334 over 0.09 m, 0.354 over 8.4 mm); the height matters a lot: flexslosh's plateau falls from "
    "0.678 to 0.594, 0.509, 0.428 and 0.354 in 15 mm steps of height from y = 0.10 m to 0.16 m (at H/dx = 40 an 8.4 "
    "mm probe's reading changes in steps of dx = 15 mm), about 10 % of the plateau per centimetre, and crosses the "
    "measured 0.549 near y = 0.12 m: a 0.09 m sensor centred at 0.12 m reads 0.553 (+1 %).",
    "A second experiment at the same y/H: Lobovsky, Botia-Vera, Castellana, Mas-Soler & Souto-Iglesias (2014), "
    "Experimental investigation of dynamic pressure loads during dam break, J. Fluids Struct. 48, 407-434, "
    "doi:10.1016/j.jfluidstructs.2014.03.009. Their H = 300 mm case has this set-up's shape in the plane (column 2H "
    "long, tank 161H/30 = 5.367H) in a tank H/2 wide, with sensors at 3, 30 and 80 mm, y/H = 0.01, 0.1 and 0.267 (as "
    "PySPH's pysph/examples/dam_break/dam_break_3d_lobovsky.py sets it up), the y/H of De Courcy's P1, P3 and P4. The"
    " paper, its percentile bands and any supplementary data were not read here. One record (non-dimensional, 25001 "
    "samples, files named 'Fig18_peak_event_5_sensors_*.dat') is public in TNL-Project/TNL-SPH (commit 0c3d51fc, "
    "examples/resources/damBreak2D/damBreak2D_experimentalDataLobovsky2014/pressure/; MIT licence for the repository,"
    " no statement on the measurements found), and PySPH keeps digitized curves at the three heights. On the plateau "
    "the record reads 0.707, 0.629 and 0.520 (PySPH's curves 0.645, 0.636 and 0.520) at y/H = 0.01, 0.1 and 0.267, "
    "against 0.978, 0.818 and 0.364 for De Courcy's 2-D SPH at H/dx = 400: 25-35 % lower near the floor, 43 % higher "
    "at y/H = 0.267.",
    "Established: flexslosh agrees with high-resolution 2-D single-phase SPH at every height, so its wall region is "
    "not what is off; and two experiments, in two facilities at two scales, show a flatter profile of the plateau "
    "pressure up the wall than 2-D single-phase SPH, lower near the floor and higher at y/H = 0.27, where Buchner's "
    "P1 (0.549, if it is at 0.16 m) and Lobovsky's 80 mm sensor (0.520) agree within 6 % (one record each). A 2-D "
    "single-phase model is therefore expected to sit well below the measurement at y/H = 0.27; the gap does not need "
    "a wrong sensor height. Not established: the physics behind it. Colagrossi & Landrini (2003), Numerical "
    "simulation of interfacial flows by smoothed particle hydrodynamics, J. Comput. Phys. 191, 448-475, treat the dam"
    " break with a two-phase model and discuss air entrapment, which their introduction ties to short-time features "
    "(maxima, rise times, oscillations); nothing read here quantifies air, the tank's width or the sensor's area on "
    "the plateau. The records also disagree on timing: P1 rises (p* > 0.3) at t* = 2.62, Lobovsky's 80 mm sensor at "
    "2.86-2.92, flexslosh at 0.16 m at 2.47-2.52; with P1 at PySPH's 0.12 m flexslosh would match Buchner but still "
    "miss Lobovsky's 80 mm sensor. In the same Lobovsky record a sensor labelled '2L' reads 0.550 against 0.681 for "
    "'sensor 2' (the label suggests a twin offset across the tank; not checked against the paper), a hint of 3-D "
    "variation.",
    "What would settle it: P1's height and diameter from Buchner's thesis (Appendix II) or Marrone et al. (2011); "
    "Lobovsky's repeated records at 80 mm, for the median and percentile band of the plateau rather than of the "
    "peaks; and a 2-D two-phase run and a 3-D run of Lobovsky's H = 300 mm tank (H/2 wide) to separate air from "
    "width. Until then the checks against the experiment at 0.16 m stay open FAILs that measure the model class; the "
    "checks against De Courcy's SPH are the ones that test flexslosh.",
]


def case_dam_break_pressure(ctx: Context) -> Section:
    """The dam break of Buchner's experiment (Marrone et al. 2011's set-up): the pressure on the far wall."""
    H = 0.6
    exp, p1, p4 = _data("buchner_2002_P1.csv"), _data("decourcy_2024_P1.csv"), _data("decourcy_2024_P4.csv")
    sec = Section("dam_break_pressure", "Dam break: pressure on the downstream wall (Buchner 2002, De Courcy et al. 2024)",
                  "The dam break of Marrone et al. (2011): a column 2H wide and H = 0.6 m high in a tank 5.366 H long "
                  "(`-fs_dam_width 1.2 -fs_dam_height 0.6 -fs_dam_tank_length 3.22`), free-slip walls; the pressure p/(rho g H) "
                  "against t* = t sqrt(g/H) on the downstream wall, read by wall probes (`-fs_probes`, the wall pressure averaged "
                  "over the sensor's height): at y = 0.16 m (the experiment's sensor P1, taken 0.09 m high, see the "
                  "notes, and De Courcy's P4, 8.4 mm high) and at y = 6 mm (De Courcy's P1). Measured: the impact's "
                  "arrival at y = 0.16 m (first t* with p* > 0.3) "
                  "against the experiment, and the mean p* over t* in [3, 5.5] (after the first peak, before the plunging wave "
                  "returns) against the experiment and against De Courcy's SPH at both heights.",
                  "Experiment: Buchner, B. (2002), Green water on ship-type offshore structures, PhD thesis, Delft University "
                  "of Technology, as set up in Marrone, Antuono, Colagrossi, Colicchio, Le Touze & Graziani (2011), delta-SPH "
                  "model for simulating violent impact flows, CMAME 200, 1526-1542, doi:10.1016/j.cma.2010.12.016 "
                  "([data](data/buchner_2002_P1.csv)). SPH: De Courcy, Rendall, Constantin, Titurus & Cooper (2024), "
                  "Incompressible delta-SPH via artificial compressibility, CMAME 420, 116700, doi:10.1016/j.cma.2023.116700, "
                  "H/dx = 400 ([P1](data/decourcy_2024_P1.csv), [P4](data/decourcy_2024_P4.csv)). All digitized by the "
                  "TrixiParticles.jl authors (MIT licence; [data/README.md](data/README.md)).")
    tmax = round((0.6 if ctx.quick else 7.3) / math.sqrt(G / H), 4)
    probes = ctx.work / "dam_break_pressure" / "probes.txt"
    probes.parent.mkdir(parents=True, exist_ok=True)
    probes.write_text("# the downstream wall: Buchner's P1 (0.09 m high), De Courcy's P4 and P1 (8.4 mm high)\n"
                      "probe Exp1 3.22 0.16 diameter 0.09\nprobe DC4 3.22 0.16 diameter 0.0084\nprobe DC1 3.22 0.006 diameter 0.0084\n")
    fig, (ax1, ax2) = _figure(11, 4.2, 2)
    ax1.plot(p1["t_star"], p1["p_star"], "r-", lw=1, label="delta-SPH P1 (De Courcy et al. 2024)")
    ax2.plot(exp["t_star"], exp["p_star"], "ko", ms=3, label="experiment P1 (Buchner 2002)")
    ax2.plot(p4["t_star"], p4["p_star"], "r-", lw=1, label="delta-SPH P4 (De Courcy et al. 2024)")
    mean = lambda t, p: float(np.mean(p[(t >= 3) & (t <= 5.5)]))  # noqa: E731
    t_exp = float(exp["t_star"][np.argmax(exp["p_star"] > 0.3)])
    for dx in ctx.dxs("dam_break_pressure"):
        r = ctx.run("dam_break_pressure", _label(dx),
                    ["-options_file", _case("dam_break"), "-fs_dam_width", 1.2, "-fs_dam_height", H, "-fs_dam_tank_length", 3.22,
                     "-fs_dam_tank_height", 1.2, "-fs_dx", dx, "-ts_max_time", tmax, "-fs_output_interval", 0,
                     "-fs_probes", os.path.relpath(probes, REPO)], sec.runs)
        ts = r.column("time", "probes") * math.sqrt(G / H)
        ps = {k: r.column(f"{k}_pressure[Pa]", "probes") / (1000 * G * H) for k in ("Exp1", "DC4", "DC1")}
        res = f"H/dx = {H / dx:.0f}"
        ax1.plot(ts, ps["DC1"], "-", lw=1, label=f"flexslosh y = 6 mm, {res}")
        ax2.plot(ts, ps["Exp1"], "-", lw=1, label=f"flexslosh y = 0.16 m (0.09 m sensor), {res}")
        hit = np.nonzero(ps["Exp1"] > 0.3)[0]
        if len(hit):
            sec.checks.append(Check(f"{res}: impact arrival t* at y = 0.16 m, abs difference from the experiment", abs(float(ts[hit[0]]) - t_exp), 0.1, fmt="{:.3f}"))
        if ts[-1] >= 5.5:
            sec.checks.append(Check(f"{res}: mean p* (t* in [3, 5.5]) at y = 0.16 m / experiment's - 1 (abs)",
                                    abs(mean(ts, ps["Exp1"]) / mean(exp["t_star"], exp["p_star"]) - 1), 0.15, fmt="{:.1%}"))
            sec.checks.append(Check(f"{res}: mean p* (t* in [3, 5.5]) at y = 0.16 m / De Courcy's P4 - 1 (abs)",
                                    abs(mean(ts, ps["DC4"]) / mean(p4["t_star"], p4["p_star"]) - 1), 0.15, fmt="{:.1%}"))
            sec.checks.append(Check(f"{res}: mean p* (t* in [3, 5.5]) at y = 6 mm / De Courcy's P1 - 1 (abs)",
                                    abs(mean(ts, ps["DC1"]) / mean(p1["t_star"], p1["p_star"]) - 1), 0.15, fmt="{:.1%}"))
            for k, ref, name in (("DC1", p1, "P1"), ("DC4", p4, "P4")):
                w = (ref["t_star"] >= 2.5) & (ref["t_star"] <= min(6.5, ts[-1]))
                rms = float(np.sqrt(np.mean((np.interp(ref["t_star"][w], ts, ps[k]) - ref["p_star"][w]) ** 2)))
                sec.notes.append(f"{res}: rms difference from De Courcy's {name} over t* in [2.5, 6.5]: {rms:.3f} rho g H (no tolerance).")
    for ax, title in ((ax1, "y = 6 mm"), (ax2, "y = 0.16 m")):
        ax.set_xlim(1.5, 7.5)
        ax.set_xlabel("t sqrt(g/H)")
        ax.set_ylabel("p / (rho g H)")
        ax.set_title(title)
        ax.legend(fontsize=7)
    ax1.set_ylim(-0.5, 4.5)
    ax2.set_ylim(-0.5, 2.0)
    sec.figure = _save(fig, ctx, "dam_break_pressure")
    sec.caption = "Dam break, pressure on the downstream wall near the floor (left) and at 0.16 m (right): experiment, published delta-SPH and flexslosh"
    sec.notes.append("The experiment's curve is one digitized record (no median or percentile band).")
    sec.notes += DAM_BREAK_PRESSURE_NOTES
    return sec


#: Lobovsky et al. (2014)'s H = 300 mm dam break (cases/dam_break_lobovsky.opts): its sensors as the case's probes
#: (cases/data/lobovsky_sensors.txt), name -> height above the floor (m).
LOBOVSKY_SENSORS = {"sensor1": 0.003, "sensor2": 0.015, "sensor3": 0.030, "sensor4": 0.080}
LOBOVSKY_TITLE = "Dam break: impact pressures against Lobovsky et al. (2014), H = 300 mm"
#: The window (t* = t sqrt(g/H)) of the pressure after the first impact: the water piled on the wall, before the
#: plunging wave returns; the same as the Buchner section's.
LOBOVSKY_PLATEAU = (3.0, 5.5)
#: Sensor 4's peak in the experiment is the later wave's (the notes): its largest p* from this t* on is checked.
LOBOVSKY_LATE = 4.0
#: The tolerances: the first arrival (t*), the plateau's mean (relative).
LOBOVSKY_TOL = {"arrival": 0.1, "plateau": 0.15}


def first_impact(t: np.ndarray, p: np.ndarray, threshold: float = 0.3, window: float = 1.0) -> tuple[float, float]:
    """The first impact of a wall pressure record p*(t*): its arrival (the first t* with p* > threshold) and its
    peak (the largest p* over [arrival, arrival + window]); (nan, nan) where p* stays below the threshold."""
    hit = np.nonzero(p > threshold)[0]
    if not len(hit):
        return math.nan, math.nan
    ta = float(t[hit[0]])
    return ta, float(np.max(p[(t >= ta) & (t <= ta + window)]))


def case_dam_break_lobovsky(ctx: Context) -> Section:
    """Lobovsky et al. (2014)'s dam break, H = 300 mm, in 2-D: the sensors' first impact peaks against the paper's
    percentiles over 100 repetitions, the pressure after the impact against one public record (three resolutions)."""
    name, H = "dam_break_lobovsky", 0.3
    scale = 1000.0 * G * H  # Pa per unit p* (rho0 = 1000 as the case's water)
    table, rec = _data("lobovsky_2014_peaks.csv"), _data("lobovsky_2014_record.csv")
    band = {f"sensor{int(k)}": (m * 100 / scale, lo * 100 / scale, hi * 100 / scale)
            for k, m, lo, hi in zip(table["sensor"], table["median_mbar"], table["p2_5_mbar"], table["p97_5_mbar"])}
    sec = Section(name, LOBOVSKY_TITLE,
                  "The H = 300 mm dam break of Lobovsky et al. (2014) in 2-D (cases/dam_break_lobovsky.opts): a column 2H "
                  "long and H high in a tank 1.61 m (5.37 H) long, free-slip walls, released at once. The case's probes "
                  "(cases/data/lobovsky_sensors.txt) read the downstream wall where the experiment's sensors 1-4 sit, "
                  "y = 3, 15, 30 and 80 mm (y/H = 0.01, 0.05, 0.1, 0.267), each averaged over its 4.2 mm face and sampled "
                  "at 20 kHz (the `_pressure_filtered` columns). Measured, as p* = p/(rho g H) against t* = t sqrt(g/H): "
                  "the first impact's peak per sensor (the largest p* within 1 of the arrival, the first t* with p* > 0.3) "
                  "against the median and the 2.5-97.5 % band of the peaks of the experiment's 100 repetitions (at sensor "
                  "4 the largest p* for t* >= 4, the later wave's: see the notes); the mean p* over t* in [3, 5.5] (the water piled on the wall "
                  "after the impact) and the arrival at sensor 1 against the one public record; the convergence of both "
                  "over three resolutions (H/dx = 20, 40, 80).",
                  "Lobovsky, Botia-Vera, Castellana, Mas-Soler & Souto-Iglesias (2014), Experimental investigation of "
                  "dynamic pressure loads during dam break, J. Fluids Struct. 48, 407-434, doi:10.1016/j.jfluidstructs."
                  "2014.03.009: the peaks' percentiles of its Table 2 as quoted by the warpSPH project (MIT; "
                  "[data](data/lobovsky_2014_peaks.csv)), and one repetition's record at 20 kHz from TNL-SPH (MIT; "
                  "[data](data/lobovsky_2014_record.csv), 1 ms means and maxima). The paper itself was not read "
                  "([data/README.md](data/README.md)).")
    tmax = round((3.0 if ctx.quick else 6.5) / math.sqrt(G / H), 4)
    fig, _ = _figure(11, 7.5)
    fig.clear()
    axes = fig.subplots(2, 2).ravel()
    tr = rec["t_star"]
    found: dict[float, dict[str, dict[str, float]]] = {}
    for ax, (k, y) in zip(axes, LOBOVSKY_SENSORS.items()):
        med, lo, hi = band[k]
        j = k[-1]
        ax.plot(tr, rec[f"p{j}_mean"], "-", color="0.3", lw=0.8, label="experiment, one repetition (1 ms means)")
        span = (LOBOVSKY_LATE, 6.5) if k == "sensor4" else (2.2, 3.2)  # where the peak is compared
        ax.fill_between(span, lo, hi, color="0.85", zorder=0, label="experiment's peaks: 2.5-97.5 % of 100")
        ax.plot(span, (med, med), color="0.4", ls="--", lw=0.8, label="experiment's peaks: median")
    for dx in ctx.dxs(name):
        r = ctx.run(name, _label(dx), ["-options_file", _case(name), "-fs_dx", dx, "-ts_max_time", tmax,
                                       "-fs_output_interval", 0], sec.runs, checkpoints=LONG_RUN_CHECKPOINTS)
        ts = r.column("time", "probes") * math.sqrt(G / H)
        got: dict[str, dict[str, float]] = {}
        for ax, k in zip(axes, LOBOVSKY_SENSORS):
            ps = r.column(f"{k}_pressure_filtered[Pa]", "probes") / scale
            ax.plot(ts, ps, "-", lw=0.8, label=f"flexslosh H/dx = {H / dx:.0f}")
            arrival, peak = first_impact(ts, ps)
            w = (ts >= LOBOVSKY_PLATEAU[0]) & (ts <= LOBOVSKY_PLATEAU[1])
            late = ts >= LOBOVSKY_LATE
            got[k] = {"arrival": arrival, "peak": peak, "max": float(np.max(ps)),
                      "late": float(np.max(ps[late])) if np.any(late) else math.nan,
                      "plateau": float(np.mean(ps[w])) if ts[-1] >= LOBOVSKY_PLATEAU[1] else math.nan}
        found[dx] = got
    for ax, (k, y) in zip(axes, LOBOVSKY_SENSORS.items()):
        ax.set_xlim(1.5, 6.5)
        ax.set_ylim(-0.3, max(2.0, 2.5 * band[k][2]))
        ax.set_title(f"{k}: y = {y * 1000:g} mm (y/H = {y / H:.3g})", fontsize=9)
        ax.set_xlabel("t* = t sqrt(g/H)")
        ax.set_ylabel("p* = p / (rho g H)")
    axes[0].legend(fontsize=6)
    sec.figure = _save(fig, ctx, name)
    sec.caption = ("Lobovsky et al. (2014), H = 300 mm: the pressure at the four sensors on the downstream wall, one "
                   "experimental record, the band and median of the experiment's peaks, and flexslosh (axes cut)")
    rec_arrival = {k: first_impact(tr, rec[f"p{k[-1]}_max"])[0] for k in LOBOVSKY_SENSORS}
    w = (tr >= LOBOVSKY_PLATEAU[0]) & (tr <= LOBOVSKY_PLATEAU[1])
    rec_plateau = {k: float(np.mean(rec[f"p{k[-1]}_mean"][w])) for k in LOBOVSKY_SENSORS}
    dxs = sorted(found, reverse=True)  # coarse to fine
    fine = dxs[-1]
    res = f"H/dx = {H / fine:.0f}"
    g = found[fine]
    for k, y in LOBOVSKY_SENSORS.items():
        med, lo, hi = band[k]
        what, key = ("the later wave's peak p* (t* >= 4)", "late") if k == "sensor4" else ("first impact's peak p*", "peak")
        sec.checks.append(Check(f"{res}: {k} (y = {y * 1000:g} mm), {what} >= the experiment's 2.5 % percentile",
                                g[k][key], lo, kind="min", fmt="{:.2f}"))
        sec.checks.append(Check(f"{res}: {k} (y = {y * 1000:g} mm), {what} <= the experiment's 97.5 % percentile",
                                g[k][key], hi, fmt="{:.2f}"))
    sec.checks.append(Check(f"{res}: sensor1 arrival t* (p* > 0.3), abs difference from the record's",
                            abs(g["sensor1"]["arrival"] - rec_arrival["sensor1"]), LOBOVSKY_TOL["arrival"], fmt="{:.3f}"))
    for k, y in LOBOVSKY_SENSORS.items():
        if math.isfinite(g[k]["plateau"]):  # the run reached the window's end (not so with --quick)
            sec.checks.append(Check(f"{res}: {k} (y = {y * 1000:g} mm), mean p* over t* in [3, 5.5] / the record's - 1 (abs)",
                                    abs(g[k]["plateau"] / rec_plateau[k] - 1), LOBOVSKY_TOL["plateau"], fmt="{:.1%}"))
    head = "| | experiment | " + " | ".join(f"H/dx = {H / d:.0f}" for d in dxs) + " |"
    rows = [head, "|---|---|" + "---|" * len(dxs)]
    for k, y in LOBOVSKY_SENSORS.items():
        med, lo, hi = band[k]
        rows.append(f"| {k} (y/H = {y / H:.3g}): first impact's peak p* | median {med:.2f} (2.5-97.5 %: {lo:.2f}-{hi:.2f}) | "
                    + " | ".join(f"{found[d][k]['peak']:.2f}" for d in dxs) + " |")
        rows.append(f"| {k}: the run's largest p* (t* <= 6.5) | record: {float(np.max(rec[f'p{k[-1]}_max'])):.2f} | "
                    + " | ".join(f"{found[d][k]['max']:.2f}" for d in dxs) + " |")
        if k == "sensor4":
            rows.append(f"| {k}: the later wave's peak p* (t* >= 4) | median {med:.2f} (2.5-97.5 %: {lo:.2f}-{hi:.2f}); "
                        f"record: {float(np.max(rec['p4_max'][tr >= LOBOVSKY_LATE])):.2f} | "
                        + " | ".join(f"{found[d][k]['late']:.2f}" for d in dxs) + " |")
        rows.append(f"| {k}: arrival t* (p* > 0.3) | record: {rec_arrival[k]:.3f} | "
                    + " | ".join(f"{found[d][k]['arrival']:.3f}" for d in dxs) + " |")
        rows.append(f"| {k}: mean p*, t* in [3, 5.5] | record: {rec_plateau[k]:.3f} | "
                    + " | ".join(f"{found[d][k]['plateau']:.3f}" for d in dxs) + " |")
    sec.notes.append("\n".join(rows))
    if len(dxs) == 3:
        conv = ["| quantity | observed order | change between the two finest |", "|---|---|---|"]
        for k in LOBOVSKY_SENSORS:
            for key, label in (("peak", "first impact's peak p*"), ("plateau", "mean p*, t* in [3, 5.5]"), ("arrival", "arrival t*")):
                f = [found[d][k][key] for d in dxs]
                c = convergence(*f)
                conv.append(f"| {k}: {label} | {float(c.order[0]):.2f} | {float(c.change[0]):.3f} "
                            f"({float(c.change[0]) / abs(f[2]):.0%} of the finest's) |")
        sec.notes.append("Convergence over H/dx = " + ", ".join(f"{H / d:.0f}" for d in dxs) + " (refined by 2; the order "
                         "is nan where the changes do not shrink monotonically: those runs are not in the asymptotic "
                         "range):\n\n" + "\n".join(conv))
    sec.notes += LOBOVSKY_NOTES
    return sec


#: What the section's reference is and is not, and what the runs of 2026-12-05 (H/dx = 20, 40, 80) showed; fixed
#: text, so that a rerun of the report keeps it.
LOBOVSKY_NOTES = [
    "What the runs of 2026-12-05 show. After the impact flexslosh converges to the 2-D single-phase solution, not "
    "to the experiment: at H/dx = 80 its mean p* over t* in [3, 5.5] is 0.971 at y/H = 0.01 and 0.366 at y/H = "
    "0.267, against 0.978 and 0.364 for De Courcy et al. (2024)'s H/dx = 400 run of the same 2-D problem (the "
    "Buchner section's data, at the same y/H), within 1 %; the record reads 0.707 and 0.520. At y/H = 0.267 the "
    "gap is the run's slower rise: over t* in [3, 4.3] it reads 0.296 against the record's 0.547, over [4.3, 5.5] "
    "0.450 against 0.491 (-8 %); near the floor it reads about 37 % above the record in both halves. So the "
    "plateau FAILs (30-37 %) measure the model class, as the Buchner section found (issue 14), not a fault of the solver. The first "
    "impact's peaks at sensors 1-3 lie above the experiment's 97.5 % percentiles at every resolution (1.4-2.4 "
    "times the medians at H/dx = 80) and do not converge (sensor 1: 4.62, 5.38, 7.64): a weakly compressible "
    "run with c0 = 24 m/s resolves no 1-5 ms peak of a stiff impact, so these checks stay open FAILs that say a "
    "design pressure cannot be read from one such run's peak. At sensor 4 the run reads a spike when the jet "
    "thrown up the wall passes (t* = 2.48, where the experiment reads nothing until 2.7-2.86): it falls with "
    "resolution (2.31, 1.48, 0.84) and is the passing jet's numerical noise; the later wave's peak there "
    "(0.91, 1.03, 1.12) lies in the experiment's band at all three resolutions. The arrival at sensor 1 is "
    "0.06-0.08 earlier than the record's: the run releases the column at once, the experiment lifts a gate.",
    "The experiment: a tank 1610 mm long, 600 mm high and 150 mm (H/2) wide, the column 600 mm long behind a gate "
    "lifted in about 0.07 s (as the warpSPH script of the next note quotes it); the sensors on the tank's centre line. The run is 2-D and releases the column at once, so "
    "its t* = 0 is the gate's first motion only up to the lift; the record's t* = 0 is as the TNL-SPH files give it.",
    "The percentiles are the paper's Table 2 as quoted in wi-re/warpSPH (scripts/probe_acsphDambreakLobovsky.py, commit "
    "b471cf92), converted here with rho g H = 1000 x 9.81 x 0.3 Pa; that source notes that sensor 4's peak is the later "
    "wave's, not the first impact's. The one public record agrees: its first impact peaks at 3.04, 1.95 and 1.54 at "
    "sensors 1-3 (inside the bands, near the medians 3.11, 1.95 and 1.49), while at sensor 4 the pressure rises without "
    "a peak (p* 0.3 at t* = 2.86, 0.5 at 3.06) and its largest value, 0.84 at t* = 5.95, comes with the plunging wave's "
    "return, inside that sensor's band (0.82-1.23). So sensor 4 is checked with its largest p* for t* >= 4.",
    "The sensor's face, 4.2 mm across, is also second-hand (a project comparing with the H = 600 mm case quotes it); "
    "the 20 kHz rate is that of the record's samples; no filter bandwidth was found, so the probes have no cut-off. "
    "At H/dx = 80 the face spans about one wall element (dx = 3.75 mm).",
    "The plateau gap is the one the Buchner section found at the same y/H (issue 14): 2-D single-phase SPH reads "
    "higher than this experiment near the floor and lower at y/H = 0.27 (where De Courcy et al.'s H/dx = 400 run reads "
    "0.364 against the record's 0.520). The first impact's peak of a weakly compressible run depends on c0 and on the "
    "resolution, and a 2-D run has neither the air the experiment entraps nor its 3-D front; the peak checks measure "
    "how far the model's single sample lands from the experiment's distribution, not a converged quantity.",
]


#: SPHERIC test 10 (lateral impact, water): windows (s) of the measured record holding one impact each
SPHERIC10_IMPACTS = ((2.2, 2.6), (3.9, 4.3), (5.5, 5.9), (7.1, 7.5))


def impact_figures(t: np.ndarray, p: np.ndarray, windows: Sequence[tuple[float, float]], threshold: float = 1000.0,
                   plateau: tuple[float, float] = (0.1, 0.35)) -> list[dict[str, float]]:
    """The impacts of a wall pressure record: per window, the first time p exceeds threshold (the impact's
    arrival), the largest p in the window (the peak) and the mean p over [arrival + plateau[0], arrival +
    plateau[1]] (the water piled on the wall after the impact); nan where p stays below threshold."""
    out = []
    for a, b in windows:
        w = (t >= a) & (t <= b)
        hit = np.nonzero(w & (p > threshold))[0]
        if not len(hit):
            out.append({"arrival": math.nan, "peak": float(np.max(p[w])) if np.any(w) else math.nan, "plateau": math.nan})
            continue
        ta = float(t[hit[0]])
        m = (t >= ta + plateau[0]) & (t <= ta + plateau[1])
        out.append({"arrival": ta, "peak": float(np.max(p[w])), "plateau": float(np.mean(p[m])) if np.any(m) else math.nan})
    return out


def case_roll_tank(ctx: Context) -> Section:
    """SPHERIC test 10 (cases/roll_tank.opts): the sensor's pressure against the experiment's, driven by the measured roll."""
    exp = _data("spheric10_lateral_water_pressure.csv")
    reps = spheric10_peak_statistics()
    sec = Section("roll_tank", "Forced sloshing: SPHERIC benchmark test 10 (rolled tank)",
                  "The tank rolled by the experiment's measured roll (cases/roll_tank.opts, `-fs_motion_roll_file`); the "
                  "pressure of the sensor on the left wall at the still-water height against the measured one, for the four "
                  "impacts of the record: the impact's arrival (the first time p > 1 kPa within 0.3 s of the experiment's), its "
                  "peak (the largest p there) against the mean and standard deviation of the peaks of 102 repetitions of the "
                  "experiment, and the mean p over 0.10-0.35 s after the arrival (the water piled on the wall after the "
                  "impact) against the record; the energy budget's residual against the work the roll does.",
                  "Experiment: Souto-Iglesias, Botia-Vera, Martin & Perez-Arribas (2011), A set of canonical problems in "
                  "sloshing. Part 0: experimental setup and data processing, Ocean Engineering 38, 1823-1830; Botia-Vera, "
                  "Souto-Iglesias, Bulian & Lobovsky (2010), 5th SPHERIC workshop (SPHERIC test 10, lateral impact, water, "
                  "one record). Pressure: the minimum and maximum of each 5 ms of the 20 kHz record "
                  "([data](data/spheric10_lateral_water_pressure.csv)); roll: windows of the record rebuilt every 5 ms "
                  "(cases/data/spheric10_roll.txt). Both from the DualSPHysics package's examples (LGPL-2.1; "
                  "[data/README.md](data/README.md)). The first four peaks of 102 repetitions: the benchmark's repeatability "
                  "file (Souto-Iglesias & Botia-Vera, SPHERIC test 10 proposal, 2011; "
                  "[data](data/spheric10_lateral_water_peaks.csv)).")
    tmax = 1.0 if ctx.quick else 8.0
    te, pe = exp["t"], exp["p"]
    ref = impact_figures(te, pe, SPHERIC10_IMPACTS)
    windows = [(f["arrival"] - 0.3, f["arrival"] + 0.3) for f in ref]
    fig, ax = _figure(10, 4.5)
    ax.plot(te, pe / 1000, "k-", lw=0.7, zorder=5, label="experiment (5 ms min/max of the 20 kHz record)")
    ax.plot([f["arrival"] for f in ref], [f["peak"] / 1000 for f in ref], "kv", ms=7, zorder=6, label="experiment: impact peaks")
    ax.errorbar([f["arrival"] + 0.06 for f in ref], reps["mean"] / 1000, yerr=reps["sd"] / 1000, fmt="rs", ms=5, capsize=3,
                zorder=6, label="experiment, 102 repetitions: peaks' mean +- SD")
    figures: dict[float, list[dict[str, float]]] = {}
    pre: dict[float, float] = {}
    pre_exp = float(np.mean(pe[(te >= PRE_IMPACT[0]) & (te <= PRE_IMPACT[1])]))
    for dx in ctx.dxs("roll_tank"):
        r = ctx.run("roll_tank", _label(dx), ["-options_file", _case("roll_tank"), "-fs_dx", dx, "-ts_max_time", tmax,
                                              "-fs_output_interval", 0], sec.runs, checkpoints=LONG_RUN_CHECKPOINTS)
        t, p = r.column("time", "probes"), r.column("sensor1_pressure[Pa]", "probes")
        ax.plot(t, p / 1000, "-", lw=0.7, alpha=0.7, label=f"flexslosh, dx = {dx * 1000:g} mm ({r.particles} particles)")
        e = r.energy
        sec.checks.append(Check(f"dx = {dx * 1000:g} mm: max abs(residual_liquid) / max abs(work_motion)",
                                float(np.max(np.abs(e["residual_liquid"]))) / float(np.max(np.abs(e["work_motion"]))), 0.01, fmt="{:.2e}"))
        if t[-1] < SPHERIC10_IMPACTS[-1][1]:
            continue
        figures[dx] = impact_figures(t, p, windows)
        pre[dx] = float(np.mean(p[(t >= PRE_IMPACT[0]) & (t <= PRE_IMPACT[1])]))
    ang = np.loadtxt(REPO / "cases" / "data" / "spheric10_roll.txt")
    ax2 = ax.twinx()
    ax2.plot(ang[:, 0], ang[:, 1], ":", color="0.4", lw=0.8, label="measured roll angle (deg, right axis)")
    ax2.set_ylabel("roll angle (deg)")
    ax2.set_ylim(-12, 12)
    ax.set_xlim(0, tmax)
    ax.set_ylim(-0.5, 5.0)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("p (kPa), sensor on the left wall")
    ax.legend(loc="upper left", fontsize=7)
    ax2.legend(loc="upper right", fontsize=7)
    sec.figure = _save(fig, ctx, "roll_tank")
    sec.caption = ("SPHERIC test 10, lateral impact: the sensor's pressure, experiment and flexslosh driven by the measured roll "
                   "(axis cut at 5 kPa)")
    if figures:
        # the checks at the finest resolution run to the end; the table shows every resolution
        dx = min(figures)
        res, sim = f"dx = {dx * 1000:g} mm", figures[dx]
        sec.checks.append(Check(f"{res}: mean p over {PRE_IMPACT[0]:g}-{PRE_IMPACT[1]:g} s (before the first impact) / "
                                "experiment's - 1 (abs)", abs(pre[dx] / pre_exp - 1), ROLL_TOL["pre"], fmt="{:.1%}"))
        for k, (f, g) in enumerate(zip(ref, sim)):
            sec.checks.append(Check(f"{res}: impact {k + 1} arrival, abs(t - t_exp) (s)", abs(g["arrival"] - f["arrival"]),
                                    ROLL_TOL["arrival"], fmt="{:.3f}"))
            sec.checks.append(Check(f"{res}: impact {k + 1} mean p 0.10-0.35 s after arrival / experiment's - 1 (abs)",
                                    abs(g["plateau"] / f["plateau"] - 1), ROLL_TOL["plateau"], fmt="{:.0%}"))
        for k, g in enumerate(sim):
            sec.checks.append(Check(f"{res}: impact {k + 1} peak, abs(p - the repetitions' mean) (kPa), within one standard "
                                    "deviation", abs(g["peak"] - reps["mean"][k]) / 1000, reps["sd"][k] / 1000, fmt="{:.2f}"))
        rows = ["| | experiment | " + " | ".join(f"flexslosh dx = {d * 1000:g} mm" for d in sorted(figures, reverse=True)) + " |",
                "|---|---|" + "---|" * len(figures),
                f"| mean p, {PRE_IMPACT[0]:g}-{PRE_IMPACT[1]:g} s | {pre_exp:.0f} Pa | "
                + " | ".join(f"{pre[d]:.0f} Pa" for d in sorted(figures, reverse=True)) + " |"]
        for k, f in enumerate(ref):
            for key, unit, scale, fmt in (("arrival", "s", 1.0, "{:.3f}"), ("peak", "kPa", 1e-3, "{:.2f}"), ("plateau", "Pa", 1.0, "{:.0f}")):
                cells = [fmt.format(figures[d][k][key] * scale) + f" {unit}" for d in sorted(figures, reverse=True)]
                given = f"{fmt.format(f[key] * scale)} {unit}"
                if key == "peak":
                    given = (f"record {given}; 102 repetitions {reps['mean'][k] / 1000:.2f} +- {reps['sd'][k] / 1000:.2f} kPa "
                             f"(2.5-97.5 %: {reps['p2.5'][k] / 1000:.2f}-{reps['p97.5'][k] / 1000:.2f})")
                rows.append(f"| impact {k + 1}: {key} | {given} | " + " | ".join(cells) + " |")
        sec.notes.append("\n".join(rows))
        if len(figures) > 1:
            dfine, dnext = sorted(figures)[:2]  # the two finest resolutions
            pairs = list(zip(figures[dfine], figures[dnext]))
            darr = max(abs(g["arrival"] - h["arrival"]) for g, h in pairs)
            dplat = max(abs(g["plateau"] / h["plateau"] - 1) for g, h in pairs)
            dpeak = max(max(g["peak"], h["peak"]) / min(g["peak"], h["peak"]) for g, h in pairs)
            dpre = abs(pre[dfine] / pre[dnext] - 1)
            sec.notes.append(f"Change between the two finest resolutions (dx = {dnext * 1000:g} and {dfine * 1000:g} mm; largest "
                             f"over the impacts): arrival {darr:.3f} s, mean p after "
                             f"the impact {dplat:.0%}, mean p before the first impact {dpre:.0%}, peak a factor {dpeak:.1f}.")
    sec.notes.append(ROLL_NOTE)
    return sec


#: The quasi-static rise before the first impact (s): the window of the mean pressure compared.
PRE_IMPACT = (0.6, 1.2)
#: The tolerances of the SPHERIC test 10 comparison (why: ROLL_NOTE); a peak within one standard deviation of the
#: repetitions' mean (spheric10_peak_statistics()).
ROLL_TOL = {"pre": 0.1, "arrival": 0.05, "plateau": 0.2}


def spheric10_peak_statistics() -> dict[str, np.ndarray]:
    """SPHERIC test 10, lateral impact, water: the first four impacts' peak pressures over the experiment's 102
    repetitions (docs/validation/data/spheric10_lateral_water_peaks.csv, mbar): their mean, sample standard deviation
    and 2.5 / 97.5 % percentiles, in Pa, one entry per impact."""
    d = _data("spheric10_lateral_water_peaks.csv")
    a = 100.0 * np.column_stack([d[f"peak{k}_mbar"] for k in range(1, 5)])
    return {"n": np.full(4, len(a)), "mean": a.mean(axis=0), "sd": a.std(axis=0, ddof=1),
            "p2.5": np.percentile(a, 2.5, axis=0), "p97.5": np.percentile(a, 97.5, axis=0)}
ROLL_NOTE = ("Tolerances: the arrival within 0.05 s (3 % of the 1.635 s period); the mean pressure before the first "
             "impact within 10 % and after each impact within 20 % (the water standing on the wall); each peak within one "
             "standard deviation of the mean of the experiment's 102 repetitions (the issue's criterion; the peaks scatter "
             "with a coefficient of variation of 20-36 %). Where the change between the two "
             "finest resolutions (above) is as large as a tolerance, the resolution does not settle that check: a PASS may be luck "
             "and a FAIL may shrink with a finer run. The impact peaks are not resolved: a weakly compressible run with "
             "c0 = 20 m/s and these particle sizes spreads the 1-5 ms peak over its own time and length scales, and the "
             "resolutions' peaks differ several times over. The arrivals and the plateaus are compared with one record (the "
             "repetition whose first peak lies nearest the mean), whose own scatter is not in these figures. The sensor reads -50 to -250 Pa while it is dry (the "
             "record's offset); flexslosh's probe reads 0 there.")


#: The impact peaks against the sound speed (issue 38): c0 as multiples of each case's own, the low-pass cut-offs
#: (Hz) below the runs' acoustic ringing, the first impact's windows.
IMPACT_TITLE = "Impact peaks against the sound speed: raw, and low-passed below the run's ringing"
IMPACT_C0_FACTORS = (1, 2, 4)
IMPACT_CUTOFF = {"lobovsky": 100.0, "roll": 50.0}
#: The largest change of a low-passed peak between the two largest c0 at the finest resolution (relative).
IMPACT_C0_TOL = 0.05
#: SPHERIC test 10's first impact: its window (s), the roll's own c0 (m/s); the dam break's c0 = 10 sqrt(2 g H).
IMPACT_ROLL_WINDOW = SPHERIC10_IMPACTS[0]
IMPACT_ROLL_C0 = 20.0
#: The pressure impulse's window (s) after the arrival of the low-passed pressure (p > 0.3 rho g H in the dam break,
#: 1 kPa in the rolled tank).
IMPACT_IMPULSE_WINDOW = 0.05


def _impact_measures(t: np.ndarray, p: np.ndarray, window: tuple[float, float], threshold: float, cutoff: float,
                     rate: float, search: tuple[float, float] = (-math.inf, math.inf)) -> tuple[float, float, float]:
    """A record's first impact, the record low-passed once (flexslosh.impact.lowpass): its raw and low-passed peaks
    over window, and the pressure impulse over IMPACT_IMPULSE_WINDOW after the first time (within search) the
    low-passed p exceeds threshold (nan where it does not or the record ends first)."""
    from .impact import impulse, lowpass, peak

    tu, pf = lowpass(t, p, cutoff, rate=rate)
    inside = (tu >= window[0]) & (tu <= window[1])
    low = float(np.max(pf[inside])) if np.any(inside) else math.nan
    hit = np.nonzero((pf > threshold) & (tu >= search[0]) & (tu <= search[1]))[0]
    imp = math.nan
    if len(hit) and tu[hit[0]] + IMPACT_IMPULSE_WINDOW <= t[-1]:
        imp = impulse(t, p, float(tu[hit[0]]), float(tu[hit[0]]) + IMPACT_IMPULSE_WINDOW)
    return peak(t, p, *window)[1], low, imp


def case_impact_c0(ctx: Context) -> Section:
    """The first impact's peak pressure against c0 (x 1, 2, 4 of the case's) and dx, raw and low-passed (flexslosh.impact):
    the Lobovsky dam break's sensors 1-3 and SPHERIC test 10's sensor, against the experiments filtered the same way."""
    from .impact import dominant_frequency

    H = 0.3
    scale = 1000.0 * G * H
    c0_dam = 10 * math.sqrt(2 * G * H)
    factors = IMPACT_C0_FACTORS[:2] if ctx.quick else IMPACT_C0_FACTORS
    sec = Section("impact_c0", IMPACT_TITLE,
                  "The first impact of two cases at three resolutions, each run with the case's c0 and with 2 and 4 times it: "
                  "the dam break of Lobovsky et al. (2014), H = 300 mm (cases/dam_break_lobovsky.opts, c0 = 10 sqrt(2 g H) = "
                  f"{c0_dam:.2f} m/s; to t* = 3.5), sensors 1-3 (y = 3, 15, 30 mm), and SPHERIC test 10's rolled tank "
                  f"(cases/roll_tank.opts, c0 = {IMPACT_ROLL_C0:g} m/s; to {IMPACT_ROLL_WINDOW[1] + 0.1:g} s), its sensor. "
                  "Measured from the probes' raw pressure (sampled every step): the peak over the first impact's window "
                  "(the dam break: [arrival, arrival + 1] in t* = t sqrt(g/H), the arrival the first p* = p/(rho g H) > 0.3; "
                  f"the rolled tank: {IMPACT_ROLL_WINDOW[0]:g}-{IMPACT_ROLL_WINDOW[1]:g} s), raw and low-passed without phase "
                  f"shift (flexslosh.impact.peak: order 2, {IMPACT_CUTOFF['lobovsky']:g} Hz for the dam break, "
                  f"{IMPACT_CUTOFF['roll']:g} Hz for the rolled tank), and the frequency of the run's ringing after the "
                  "impact (flexslosh.impact.dominant_frequency). The experiments' records low-passed the same way are the "
                  "reference of the low-passed peaks.",
                  "Lobovsky et al. (2014): one repetition's record (TNL-SPH, 1 ms means; "
                  "[data](data/lobovsky_2014_record.csv)) and the peaks' 2.5-97.5 % band of 100 repetitions "
                  "([data](data/lobovsky_2014_peaks.csv)). SPHERIC test 10: the record's 5 ms minima and maxima "
                  "([data](data/spheric10_lateral_water_pressure.csv)) and the first peaks of 102 repetitions "
                  "([data](data/spheric10_lateral_water_peaks.csv)). Sources in [data/README.md](data/README.md).")
    # the experiments, raw and low-passed
    rec = _data("lobovsky_2014_record.csv")
    table = _data("lobovsky_2014_peaks.csv")
    band = {f"sensor{int(k)}": ((hi - lo) / (2 * m)) for k, m, lo, hi in
            zip(table["sensor"], table["median_mbar"], table["p2_5_mbar"], table["p97_5_mbar"])}
    sensors = [k for k in LOBOVSKY_SENSORS if k != "sensor4"]
    tr = rec["t_star"] / math.sqrt(G / H)
    fc = IMPACT_CUTOFF["lobovsky"]
    ref: dict[str, tuple[float, float]] = {}
    for k in sensors:
        pr = rec[f"p{k[-1]}_mean"]
        ta = first_impact(tr, pr)[0]
        t1 = ta + 1 / math.sqrt(G / H)
        _, low, imp = _impact_measures(tr, pr * scale, (ta, t1), 0.3 * scale, fc, 1000.0)
        ref[k] = (float(np.max(rec[f"p{k[-1]}_max"][(tr >= ta) & (tr <= t1)])), low / scale, imp)
    roll = _data("spheric10_lateral_water_pressure.csv")
    reps = spheric10_peak_statistics()
    fr = IMPACT_CUTOFF["roll"]
    roll_ref = _impact_measures(roll["t"], roll["p"], IMPACT_ROLL_WINDOW, 1000.0, fr, 2000.0, IMPACT_ROLL_WINDOW)
    # the runs
    dam: dict[float, dict[int, dict[str, tuple[float, float]]]] = {}
    ring: dict[tuple[str, float, int], float] = {}
    tmax = round(3.5 / math.sqrt(G / H), 4)
    for dx in ctx.dxs("impact_c0"):
        dam[dx] = {}
        for f in factors:
            r = ctx.run("impact_c0", f"lobovsky_{_label(dx)}_c{f}",
                        ["-options_file", _case("dam_break_lobovsky"), "-fs_dx", dx, "-fs_c0", f"{f * c0_dam:.6g}",
                         "-ts_max_time", tmax, "-fs_output_interval", 0], sec.runs, checkpoints=LONG_RUN_CHECKPOINTS)
            t = r.column("time", "probes")
            got = {}
            for k in sensors:
                pa = r.column(f"{k}_pressure[Pa]", "probes")
                ps = pa / scale
                ta = first_impact(t, ps)[0]
                t1 = ta + 1 / math.sqrt(G / H)
                raw, low, imp = _impact_measures(t, pa, (ta, t1), 0.3 * scale, fc, 20000.0)
                got[k] = (raw / scale, low / scale, imp)
                if k == "sensor1":
                    ring[("dam", dx, f)] = dominant_frequency(t, ps, ta, min(t1, t[-1]), fmin=fc / 2, rate=20000.0)
            dam[dx][f] = got
    rolled: dict[float, dict[int, tuple[float, float]]] = {}
    for dx in ctx.dxs("impact_c0_roll"):
        rolled[dx] = {}
        for f in factors:
            r = ctx.run("impact_c0", f"roll_{_label(dx)}_c{f}",
                        ["-options_file", _case("roll_tank"), "-fs_dx", dx, "-fs_c0", f"{f * IMPACT_ROLL_C0:g}",
                         "-ts_max_time", IMPACT_ROLL_WINDOW[1] + 0.1, "-fs_output_interval", 0], sec.runs,
                        checkpoints=LONG_RUN_CHECKPOINTS)
            t, ps = r.column("time", "probes"), r.column("sensor1_pressure[Pa]", "probes")
            rolled[dx][f] = _impact_measures(t, ps, IMPACT_ROLL_WINDOW, 1000.0, fr, 20000.0, IMPACT_ROLL_WINDOW)
            ring[("roll", dx, f)] = dominant_frequency(t, ps, *IMPACT_ROLL_WINDOW, fmin=fr / 2, rate=20000.0)
    # the checks at the finest resolution: converged in c0, and against the experiment low-passed the same way
    fa, fb = factors[-2], factors[-1]
    dx = min(dam)
    res = f"H/dx = {H / dx:.0f}"
    for k in sensors:
        a, b = dam[dx][fa][k][1], dam[dx][fb][k][1]
        sec.checks.append(Check(f"dam break, {res}: {k}, low-passed peak's change from c0 x {fa} to x {fb} (abs)",
                                abs(b / a - 1), IMPACT_C0_TOL, fmt="{:.1%}"))
        sec.checks.append(Check(f"dam break, {res}, c0 x {fb}: {k}, low-passed peak / the record's low-passed - 1 (abs; "
                                "the repetitions' 95 % half-band)", abs(b / ref[k][1] - 1), band[k], fmt="{:.0%}"))
    dx = min(dam)
    for k in sensors:
        a, b = dam[dx][fa][k][2], dam[dx][fb][k][2]
        sec.checks.append(Check(f"dam break, {res}: {k}, pressure impulse's change from c0 x {fa} to x {fb} (abs)",
                                abs(b / a - 1), IMPACT_C0_TOL, fmt="{:.1%}"))
    dx = min(rolled)
    a, b = rolled[dx][fa][1], rolled[dx][fb][1]
    cv = float(reps["sd"][0] / reps["mean"][0])
    sec.checks.append(Check(f"rolled tank, dx = {dx * 1000:g} mm: low-passed first peak's change from c0 x {fa} to x {fb} (abs)",
                            abs(b / a - 1), IMPACT_C0_TOL, fmt="{:.1%}"))
    sec.checks.append(Check(f"rolled tank, dx = {dx * 1000:g} mm, c0 x {fb}: low-passed first peak / the record's low-passed "
                            "- 1 (abs; the repetitions' coefficient of variation)", abs(b / roll_ref[1] - 1), cv, fmt="{:.0%}"))
    # the tables
    head = "| run | " + " | ".join(f"c0 x {f}" for f in factors) + " |"
    rule = "|---|" + "---|" * len(factors)
    rows = ["Dam break: the first impact's peak p*, raw / low-passed at "
            f"{fc:g} Hz (experiment's record: " + ", ".join(f"{k} {ref[k][0]:.2f} / {ref[k][1]:.2f}" for k in sensors)
            + "; the repetitions' medians 3.11, 1.95, 1.49), sensor 1's ringing (Hz), and the pressure impulse over "
            f"{IMPACT_IMPULSE_WINDOW * 1000:g} ms after the low-passed pressure's arrival (the record's: "
            + ", ".join(f"{k} {ref[k][2]:.1f}" for k in sensors) + " Pa s):", "", head, rule]
    for d in sorted(dam, reverse=True):
        for k in sensors:
            rows.append(f"| H/dx = {H / d:.0f}, {k} | " + " | ".join(f"{dam[d][f][k][0]:.2f} / {dam[d][f][k][1]:.2f}"
                                                                   for f in factors) + " |")
        rows.append(f"| H/dx = {H / d:.0f}, ringing | " + " | ".join(f"{ring[('dam', d, f)]:.0f}" for f in factors) + " |")
        for k in sensors:
            rows.append(f"| H/dx = {H / d:.0f}, {k}: impulse (Pa s) | " + " | ".join(f"{dam[d][f][k][2]:.1f}" for f in factors) + " |")
    sec.notes.append("\n".join(rows))
    rows = ["Rolled tank: the first impact's peak (kPa), raw / low-passed at "
            f"{fr:g} Hz (the experiment's record {roll_ref[0] / 1000:.2f} / {roll_ref[1] / 1000:.2f}; 102 repetitions' raw "
            f"peaks {reps['mean'][0] / 1000:.2f} +- {reps['sd'][0] / 1000:.2f}), the ringing (Hz) and the impulse over "
            f"{IMPACT_IMPULSE_WINDOW * 1000:g} ms (Pa s; the record's {roll_ref[2]:.1f}, from its 5 ms minima and maxima):",
            "", head, rule]
    for d in sorted(rolled, reverse=True):
        rows.append(f"| dx = {d * 1000:g} mm | " + " | ".join(f"{rolled[d][f][0] / 1000:.2f} / {rolled[d][f][1] / 1000:.2f}"
                                                            for f in factors) + " |")
        rows.append(f"| dx = {d * 1000:g} mm, ringing | " + " | ".join(f"{ring[('roll', d, f)]:.0f}" for f in factors) + " |")
        rows.append(f"| dx = {d * 1000:g} mm, impulse (Pa s) | " + " | ".join(f"{rolled[d][f][2]:.1f}" for f in factors) + " |")
    sec.notes.append("\n".join(rows))
    d = min(dam)
    grow = [dam[d][factors[-1]][k][0] / dam[d][factors[0]][k][0] for k in sensors]
    move = [dam[d][factors[-1]][k][1] / dam[d][factors[0]][k][1] - 1 for k in sensors]
    sec.notes.append(f"At H/dx = {H / d:.0f}, from c0 x {factors[0]} to x {factors[-1]}: the raw peaks of sensors 1-3 grow "
                     + ", ".join(f"{g:.2f}" for g in grow) + " times, the low-passed ones change by "
                     + ", ".join(f"{m:+.0%}" for m in move) + "; the checks above say whether the low-passed ones have "
                     "settled between the two largest c0.")
    if len(dam) >= 3:
        d3 = sorted(dam, reverse=True)[-3:]
        lines = ["Convergence with dx at c0 x " + str(fb) + " (low-passed; refined by 2):", "",
                 "| quantity | observed order | change between the two finest |", "|---|---|---|"]
        for k in sensors:
            v = [dam[d][fb][k][1] for d in d3]
            e1, e2 = v[1] - v[0], v[2] - v[1]
            order = math.log2(abs(e1 / e2)) if e2 and e1 * e2 > 0 and abs(e1) > abs(e2) else math.nan
            lines.append(f"| dam break {k} | {order:.2f} | {e2:+.3f} ({abs(e2 / v[2]):.0%} of the finest's) |")
        sec.notes.append("\n".join(lines))
    sec.notes.append(IMPACT_NOTE)
    # the figure: the peaks against c0, raw (dashed) and low-passed (solid)
    fig, (ax1, ax2) = _figure(11, 4.2, 2)
    for d in sorted(dam, reverse=True):
        c = [f * c0_dam for f in factors]
        ax1.plot(c, [dam[d][f]["sensor1"][0] for f in factors], "--", marker="o", mfc="none", label=f"raw, H/dx = {H / d:.0f}")
        ax1.plot(c, [dam[d][f]["sensor1"][1] for f in factors], "-", marker="s", label=f"{fc:g} Hz, H/dx = {H / d:.0f}")
    ax1.axhline(ref["sensor1"][0], color="k", ls="--", lw=0.8, label="experiment's record, raw")
    ax1.axhline(ref["sensor1"][1], color="k", lw=0.8, label=f"experiment's record, {fc:g} Hz")
    ax1.set_xscale("log")
    ax1.set_xlabel("c0 (m/s)")
    ax1.set_ylabel("first impact's peak p*, sensor 1 (y = 3 mm)")
    ax1.set_title("Dam break, Lobovsky et al. (2014)", fontsize=9)
    ax1.legend(fontsize=6)
    for d in sorted(rolled, reverse=True):
        c = [f * IMPACT_ROLL_C0 for f in factors]
        ax2.plot(c, [rolled[d][f][0] / 1000 for f in factors], "--", marker="o", mfc="none", label=f"raw, dx = {d * 1000:g} mm")
        ax2.plot(c, [rolled[d][f][1] / 1000 for f in factors], "-", marker="s", label=f"{fr:g} Hz, dx = {d * 1000:g} mm")
    ax2.axhspan((reps["mean"][0] - reps["sd"][0]) / 1000, (reps["mean"][0] + reps["sd"][0]) / 1000, color="0.88", zorder=0,
                label="102 repetitions: raw mean +- SD")
    ax2.axhline(roll_ref[1] / 1000, color="k", lw=0.8, label=f"experiment's record, {fr:g} Hz")
    ax2.set_xscale("log")
    ax2.set_xlabel("c0 (m/s)")
    ax2.set_ylabel("first impact's peak (kPa)")
    ax2.set_title("SPHERIC test 10, lateral impact", fontsize=9)
    ax2.legend(fontsize=6)
    sec.figure = _save(fig, ctx, "impact_c0")
    sec.caption = ("The first impact's peak against c0: raw (dashed), low-passed below the runs' ringing (solid), and the "
                   "experiments")
    return sec


IMPACT_NOTE = ("Why low-passed: after an impact a weakly compressible run rings, the pressure at the wall oscillating "
               "acoustically at a frequency that follows c0 (the rows 'ringing' above, in the dam break), with swings that "
               "grow with c0, so the raw peak grows with c0 without settling. Real water rings at tens of kHz, and the "
               "records show the impact itself to be slower (the dam break's sensors 2 and 3 read about the same peak raw "
               "and at 100 Hz). A low-pass below the ringing keeps the slower load, the one a structure whose own "
               "frequencies lie below the cut-off responds to; a stiffer structure needs the raw impact, which a weakly "
               "compressible run at these c0 does not give. Where the impact is a flat slam (a body of liquid L long "
               "stopped at speed U), the run's pulse is rho c0 U high and 2 L / c0 long: it moves below any cut-off that "
               "keeps the wave as c0 falls, which is why the rolled tank's cut-off is lower and its c0 x 1 runs are the "
               "least trustworthy. The rolled tank's record is kept as 5 ms minima and maxima, so its low-passed peak is "
               "approximate (docs/design-pressures.md). The pressure impulse (the integral of p over "
               f"{IMPACT_IMPULSE_WINDOW * 1000:g} ms after the arrival; Cooker & Peregrine's pressure-impulse theory) does not see "
               "the ringing's swings, which cancel, and measures what the impact hands the wall as momentum.")


def _msd_exact(t: np.ndarray, x0: float, f: float, zeta: float) -> np.ndarray:
    """Free decay of a damped oscillator released from x0 at rest."""
    w = 2 * math.pi * f
    wd = w * math.sqrt(1 - zeta**2)
    return x0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))


def case_beam(ctx: Context) -> Section:
    """The cantilever: modes of the bare beam against cos kL cosh kL = -1; free decays (msd exact, modal zeta)."""
    KL = np.array([1.875104069, 4.694091133, 7.854757438, 10.995540734, 14.137168391])
    EI, m, L = 210e9 * 5.57e-7, 13.04, 2.48
    f_exact = KL**2 * math.sqrt(EI / (m * L**4)) / (2 * math.pi)
    sec = Section("beam", "Cantilever beam: modes and free decay",
                  "The bare cantilever's first five natural frequencies (modal model, 60 elements) against Euler-Bernoulli; "
                  "the solid-mass configuration's free decay from 0.04 m (cases/beam_free_decay_msd.opts) against the "
                  "damped oscillator's exact solution with the run's own frequency; the modal model's damping per cycle "
                  "(cases/beam_free_decay_modal.opts) against its 1.5 %.",
                  "Exact: omega_n = (k_n L)^2 sqrt(EI/(m L^4)), cos kL cosh kL = -1 (k_n L = 1.875104, 4.694091, 7.854757, "
                  "10.995541, 14.137168; the seed's Table I); x(t) = x0 exp(-zeta w t)(cos w_d t + zeta w/w_d sin w_d t): "
                  "formulas, no data file.")
    r = ctx.run("beam", "modes", ["-fs_case", "beam", "-fs_structure", "modal", "-fs_modal_elements", 60, "-fs_modal_modes", 5,
                                  "-ts_max_steps", 1], sec.runs)
    f = np.array(r.summary["structure"]["frequencies_hz"])
    sec.checks.append(Check("bare beam, modes 1-5: max abs relative frequency error", float(np.max(np.abs(f / f_exact - 1))), 1e-4, fmt="{:.1e}"))
    tmax = 0.5 if ctx.quick else 5.0
    r = ctx.run("beam", "msd", ["-options_file", _case("beam_free_decay_msd"), "-ts_max_time", tmax, "-fs_output_interval", 0], sec.runs)
    t, w = r.column("time"), r.column("tip_displacement")
    st = r.summary["structure"]
    f1 = float(st["frequencies_hz"][0]) if "frequencies_hz" in st else float(st.get("frequency_hz", 0))
    exact = _msd_exact(t, w[0], f1, 0.015)
    sec.checks.append(Check("msd free decay: max abs(tip - exact) / 0.04 m", float(np.max(np.abs(w - exact))) / 0.04, 1e-3, fmt="{:.1e}"))
    rm = ctx.run("beam", "modal", ["-options_file", _case("beam_free_decay_modal"), "-ts_max_time", tmax, "-fs_output_interval", 0], sec.runs)
    cyc = damping_per_cycle(rm.column("time"), rm.column("tip_displacement"))
    if len(cyc.zeta):
        late = cyc.zeta[len(cyc.zeta) // 2 :]
        sec.checks.append(Check("modal free decay: max abs(zeta per cycle - 1.5 %), second half of the cycles",
                                float(np.max(np.abs(late - 0.015))), 0.001, fmt="{:.2e}"))
    fig, (ax1, ax2) = _figure(10, 4, 2)
    n = np.arange(1, 6)
    ax1.semilogy(n, f_exact, "ko", ms=8, mfc="none", label="Euler-Bernoulli")
    ax1.semilogy(n, f, "b+", ms=10, label="flexslosh (modal, 60 elements)")
    ax1.set_xlabel("mode")
    ax1.set_ylabel("frequency (Hz)")
    ax1.legend()
    show = t <= min(tmax, 1.0)
    ax2.plot(t[show], exact[show] * 1000, "k-", lw=2, label="exact (msd)")
    ax2.plot(t[show], w[show] * 1000, "c--", label="flexslosh msd")
    tm = rm.column("time")
    ax2.plot(tm[tm <= min(tmax, 1.0)], rm.column("tip_displacement")[tm <= min(tmax, 1.0)] * 1000, "m:", label="flexslosh modal")
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel("tip displacement (mm)")
    ax2.legend(fontsize=8)
    sec.figure = _save(fig, ctx, "beam")
    sec.caption = "Cantilever: natural frequencies of the bare beam (left); free decay of the solid-mass configuration, first second (right)"
    return sec


def case_energy(ctx: Context) -> Section:
    """The energy budget's residual: the dam break and the coupled tank, each at two CFL numbers."""
    sec = Section("energy", "Energy budget residuals (seed Eqs. 31-40)",
                  "The budget's residual (energy.csv: residual_liquid for the dam break, relative to the initial mechanical "
                  "energy; residual_total for the coupled tank, relative to the beam's initial elastic energy), its largest "
                  "value over the run at CFL 1.0 and 0.5: it must be small and shrink with the time step (RK4: about 16 times).",
                  "The energy balance d(E_kin + E_pot)/dt + dE_comp/dt - (P_delta + P_alpha + P_wall) = P_ext (docs/validation.md): "
                  "an identity, no data file.")
    dx = ctx.dxs("energy")[0]
    tdb = 0.1 if ctx.quick else 0.3
    tcp = 0.05 if ctx.quick else 0.3
    res: dict[str, dict[str, float]] = {"db": {}, "cp": {}}
    fig, ax = _figure()
    for cfl in ("1.0", "0.5"):
        r = ctx.run("energy", f"dam_break_cfl{cfl}", ["-fs_case", "dam_break", "-fs_dx", dx, "-ts_max_time", tdb, "-fs_cfl", cfl, "-fs_output_interval", 0], sec.runs)
        e = r.energy
        m0 = abs(e["E_kin"][0] + e["E_pot"][0])
        res["db"][cfl] = float(np.max(np.abs(e["residual_liquid"]))) / m0
        ax.semilogy(e["time"], np.abs(e["residual_liquid"]) / m0 + 1e-16, label=f"dam break, CFL {cfl}")
        r = ctx.run("energy", f"coupled_cfl{cfl}", ["-fs_case", "tank", "-fs_structure", "msd", "-fs_dx", 0.005, "-fs_beam_preload", 0.01,
                                                   "-ts_max_time", tcp, "-fs_cfl", cfl, "-fs_output_interval", 0], sec.runs)
        e = r.energy
        es = e["E_struct_elastic"][0]
        res["cp"][cfl] = float(np.max(np.abs(e["residual_total"]))) / es
        ax.semilogy(e["time"], np.abs(e["residual_total"]) / es + 1e-16, "--", label=f"coupled tank, CFL {cfl}")
    sec.checks += [Check("dam break, CFL 1.0: max abs residual / initial mechanical energy", res["db"]["1.0"], 1e-4, fmt="{:.2e}"),
                   Check("dam break: residual ratio CFL 1.0 / CFL 0.5", res["db"]["1.0"] / res["db"]["0.5"], 8, kind="min", fmt="{:.1f}"),
                   Check("coupled tank, CFL 1.0: max abs residual_total / initial elastic energy", res["cp"]["1.0"], 1e-3, fmt="{:.2e}"),
                   Check("coupled tank: residual ratio CFL 1.0 / CFL 0.5", res["cp"]["1.0"] / res["cp"]["0.5"], 5, kind="min", fmt="{:.1f}")]
    ax.set_xlabel("t (s)")
    ax.set_ylabel("abs(residual) / reference energy")
    ax.legend(fontsize=8)
    sec.figure = _save(fig, ctx, "energy")
    sec.caption = "Energy budget residuals at two time steps: the dam break (dx = %g) and the coupled tank (dx = 0.005, msd, 0.01 m preload)" % dx
    return sec


#: The seed experiment's runs: label -> (case file, structure; None: the solid mass, the case file's own beam).
SEED_RUNS = {
    "solid_msd": ("beam_free_decay_msd", None),
    "rectangular_msd": ("coupled_rectangular", "msd"),
    "baffled_msd": ("coupled_baffled", "msd"),
    "solid_modal": ("beam_free_decay_modal", None),
    "rectangular_modal": ("coupled_rectangular", "modal"),
    "baffled_modal": ("coupled_baffled", "modal"),
}


def case_seed(ctx: Context, which: Optional[Sequence[str]] = None) -> Section:
    """The seed's experiment: the damping per cycle against amplitude, liquid against solid mass."""
    which = list(which or (["solid_msd", "rectangular_msd"] if ctx.quick else SEED_RUNS))
    sec = Section("seed", "The seed's experiment: damping per cycle against amplitude",
                  "The beam released from a 0.04 m tip deflection carrying the 50 % tank (rectangular or baffled, msd or modal "
                  "beam) or a solid mass of the same total mass: the damping ratio per cycle from the tip displacement "
                  "(`flexslosh.damping.damping_per_cycle`) against the cycle's amplitude, and the peak tip acceleration. The "
                  "seed's figures (Figs. 9-10) show the trend checked here: the liquid damps clearly more than the solid mass "
                  "once it sloshes (mean zeta over the cycles of 10-30 mm at least 1.5 times the solid's), and the damping falls "
                  "back towards the structure's 1.5 % as the motion dies out (cycles below 5 mm under 3 %); its peak tip "
                  "acceleration is about 11 g.",
                  "Calderon-Sanchez, Gonzalez, Marrone, Colagrossi & Gambioli, A SPH simulation of the sloshing phenomenon "
                  "inside fuel tanks of the aircraft wings (the seed paper; docs/seed-experiment.md): Figs. 9-10 give the "
                  "trend and about 11 g, not tabulated numbers, so no data file; the solid mass's 1.5 % is the structure's "
                  "own damping (exact).")
    dx = ctx.dxs("seed")[0]
    tmax = 0.5 if ctx.quick else 3.0
    fig, ax = _figure(8, 4.5)
    cycles = {}
    for label in which:
        case, structure = SEED_RUNS[label]
        args = ["-options_file", _case(case), "-ts_max_time", tmax, "-fs_output_interval", 0]
        if structure:
            args += ["-fs_dx", dx, "-fs_structure", structure]
        if "modal" in label:
            args += ["-fs_modal_modes", 5, "-fs_modal_elements", 40]
        r = ctx.run("seed", label, args, sec.runs)
        c = damping_per_cycle(r.column("time"), r.column("tip_displacement"))
        cycles[label] = c
        peak = float(np.max(np.abs(r.column("tip_acceleration")))) / G
        ax.plot(c.amplitude * 1000, c.zeta * 100, "o-" if "solid" not in label else "s--", ms=4, label=f"{label.replace('_', ', ')} (peak {peak:.1f} g)")
        if "solid" not in label:
            sec.checks.append(Check(f"{label}: peak tip acceleration / 11 g - 1 (abs)", abs(peak / 11 - 1), 0.2, fmt="{:.0%}"))
        if len(c.zeta):
            sec.notes.append(f"{label}: zeta per cycle (amplitude mm : %) " + " ".join(f"{a * 1000:.1f}:{z * 100:.2f}" for a, z in zip(c.amplitude, c.zeta)))
    for label, c in cycles.items():
        if "solid" in label:
            continue
        solid = cycles.get("solid_modal" if "modal" in label else "solid_msd")
        mid = (c.amplitude >= 0.010) & (c.amplitude <= 0.030)
        if solid is not None and len(solid.zeta) and np.any(mid):
            sec.checks.append(Check(f"{label}: mean zeta (10-30 mm) / solid's mean zeta", float(np.mean(c.zeta[mid]) / np.mean(solid.zeta)), 1.5, kind="min", fmt="{:.2f}"))
        small = c.amplitude < 0.005
        if np.any(small):
            sec.checks.append(Check(f"{label}: mean zeta of the cycles below 5 mm", float(np.mean(c.zeta[small])), 0.03, fmt="{:.2%}"))
    ax.axhline(1.5, color="k", lw=1, label="structure's own damping (1.5 %)")
    ax.set_xscale("log")
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    ax.xaxis.set_major_locator(FixedLocator([2, 3, 5, 10, 20, 30, 40]))
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("cycle amplitude (mm)")
    ax.set_ylabel("zeta per cycle (%)")
    ax.invert_xaxis()
    ax.legend(fontsize=8)
    sec.figure = _save(fig, ctx, "seed")
    sec.caption = f"The seed's experiment: damping ratio per cycle against the cycle's amplitude (dx = {dx * 1000:g} mm)"
    missing = [k for k in SEED_RUNS if k not in which]
    if missing:
        sec.notes.append("Not run in this report: " + ", ".join(missing) + " (`python3 -m flexslosh.validate --cases seed` runs all).")
    return sec


#: The tanks at rest of ``shapes_at_rest``: label -> (dimension, the tank's options, the packing, what it is, the
#: height H of the speeds' scale sqrt(g H)): the boxes' height (0.06 m, as the issue measures them), the wing bay's
#: liquid depth (0.02 m of its 0.04 m).
SHAPES_AT_REST: dict[str, tuple[int, list[Any], str, str, float]] = {
    "leaning_2d": (2, ["-fs_tank_shape", "file", "-fs_tank_file", "cases/data/leaning_tank.walls"], "auto",
                   "2-D, side walls leaning out 18 degrees", 0.06),
    "box": (3, ["-fs_tank_shape", "stl", "-fs_tank_stl", "cases/data/box_60x60x30mm.stl"], "auto",
            "3-D box along the axes (on its lattice)", 0.06),
    "turned": (3, ["-fs_tank_shape", "stl", "-fs_tank_stl", "cases/data/box_60x60x30mm.stl", "-fs_tank_stl_rotate",
                   "0,30,0"], "auto", "the box turned 30 degrees about the vertical", 0.06),
    "tilted": (3, ["-fs_tank_shape", "stl", "-fs_tank_stl", "cases/data/box_60x60x30mm.stl", "-fs_tank_stl_rotate",
                   "0,0,20"], "auto", "the box tilted 20 degrees about a horizontal axis", 0.06),
    # cases/own_tank.opts's walls: every element within the support, for the rib's gaps and hole (docs/own-tank.md)
    "wing_bay": (3, ["-fs_tank_shape", "stl", "-fs_tank_stl", "cases/data/wing_bay.stl", "-fs_walls_visibility", "all"],
                 "auto", "cases/data/wing_bay.stl: tapered, swept, a rib with a lightening hole; 20 mm deep", 0.02),
}
#: The settings for a liquid at rest (cases/hydrostatic_3d.opts) and the walls' push back near contact.
AT_REST_NUMERICS: list[Any] = ["-fs_c0", 8, "-fs_relax_time", 0.1, "-fs_delta_min", 0.1, "-fs_delta_hydrostatic",
                               "-fs_walls_repulsion", 0.5]


def case_shapes_at_rest(ctx: Context) -> Section:
    """Tanks whose walls are not along the axes, half full and at rest (issue 33): the largest and the rms speed
    against sqrt(g H) (H = 0.06 m, the boxes' height, as the issue measures; the wing bay's liquid depth), the walls'
    vertical load against the liquid's weight and the liquid's volume against the exact one, at three resolutions."""
    tmax = 0.3 if ctx.quick else 0.5
    sec = Section("shapes_at_rest", TITLES["shapes_at_rest"],
                  "Half-full tanks at rest from the body-fitted start (`-fs_fill_packing auto`: the lattice relaxed against "
                  "the walls where a wall is not along the axes; the masses fitted to the exact volume; the hydrostatic "
                  f"start), with `{' '.join(str(a) for a in AT_REST_NUMERICS)}`, to t = {tmax:g} s: "
                  + "; ".join(f"{k} ({v[3]})" for k, v in SHAPES_AT_REST.items())
                  + ". Checked at the finest resolution: the largest speed over the run below 0.05 sqrt(g H) and the rms "
                  "speed sqrt(2 E_k / M) below 0.01 sqrt(g H) (H = 0.06 m, the boxes' height; the wing bay's 0.02 m liquid "
                  "depth), the walls' vertical load "
                  "at the end within 1 % of the weight, the liquid's volume sum m_i / rho_i at the end within 0.1 % of "
                  "the exact volume below the fill level.",
                  "Exact: the liquid at rest (zero velocity, load = weight, the volume of the geometry below the fill "
                  "level); docs/walls.md; formulas, no data file.")
    rows = ["| tank | dx (mm) | particles | max speed / sqrt(gH) | rms speed / sqrt(gH) | (its time, s) | max, rms after 0.1 s "
            "| load / weight | volume / exact |", "|---|---|---|---|---|---|---|---|---|"]
    fig, axs = _figure(11, 4.2, ncols=2)
    for k, (label, (dim, tank, packing, what, H)) in enumerate(SHAPES_AT_REST.items()):
        dxs = sorted(ctx.dxs("shapes_at_rest" if dim == 3 else "shapes_at_rest_2d"), reverse=True)
        for dx in dxs:
            args = ["-fs_case", "tank", "-fs_dim", dim] + tank + AT_REST_NUMERICS + [
                "-fs_fill_packing", packing, "-fs_dx", dx, "-ts_max_time", tmax, "-fs_output_interval", 0]
            r = ctx.run("shapes_at_rest", f"{label}_{_label(dx)}", args, sec.runs)
            t, c = r.column("time"), math.sqrt(G * H)
            M = r.column("mass")[0]
            vmax = float(np.max(r.column("max_velocity"))) / c
            vrms_t = np.sqrt(2 * r.column("kinetic_energy") / M) / c
            vrms = float(np.max(vrms_t))
            fy = sum(v for col, v in r.timeseries.items() if col.startswith("wall_") and col.endswith("_force_y"))
            load = -float(fy[-1]) / (M * G)
            a, b = read_snapshot(r.snapshots[0][1]), read_snapshot(r.snapshots[-1][1])
            ra, rb = a["density"][np.argsort(a["id"])], b["density"][np.argsort(b["id"])]
            # sum m_i / rho_i at the end, with the start's equal volumes m_i / rho_i = M / sum rho_i (the packing's)
            volume = M * float(np.sum(ra / rb)) / float(np.sum(ra)) / float(r.summary["liquid_volume"])
            late = t > 0.1  # after the start's pressure waves (2 H / c0 = 15 ms) and the relaxation
            rows.append(f"| {label} | {1e3 * dx:g} | {r.particles:,} | {vmax:.3f} | {vrms:.4f} | {float(t[np.argmax(vrms_t)]):.3f} "
                        f"| {float(np.max(r.column('max_velocity')[late])) / c:.3f}, {float(np.max(vrms_t[late])):.4f} "
                        f"| {load:.4f} | {volume:.5f} |")
            if dx == dxs[-1]:
                sec.checks += [Check(f"{label}, dx {1e3 * dx:g} mm: largest speed / sqrt(g H)", vmax, 0.05, fmt="{:.3f}"),
                               Check(f"{label}, dx {1e3 * dx:g} mm: rms speed / sqrt(g H), largest over the run", vrms, 0.01,
                                     fmt="{:.4f}"),
                               Check(f"{label}, dx {1e3 * dx:g} mm: abs(load / weight - 1) at the end", abs(load - 1), 0.01,
                                     fmt="{:.2%}"),
                               Check(f"{label}, dx {1e3 * dx:g} mm: abs(volume / exact - 1) at the end", abs(volume - 1), 1e-3,
                                     fmt="{:.2e}")]
                axs[0].plot(t, vrms_t, color=f"C{k}", lw=1, label=f"{label}, dx {1e3 * dx:g} mm")
            axs[1].loglog([dx * 1e3], [vrms], "o", color=f"C{k}", label=label if dx == dxs[0] else None)
    sec.notes.append("\n".join(rows))
    axs[0].axhline(0.01, color="k", lw=1)
    axs[0].set_xlabel("t (s)")
    axs[0].set_ylabel("rms speed / sqrt(g H)")
    axs[1].set_xlabel("dx (mm)")
    axs[1].set_ylabel("largest rms speed / sqrt(g H)")
    for ax in axs:
        ax.legend(fontsize=7)
    sec.figure = _save(fig, ctx, "shapes_at_rest")
    sec.caption = "Left: the rms speed at the finest resolution (the line: the bound). Right: its largest value against dx"
    return sec


#: The modal beam's time step in the seed studies: its fifth mode (336 Hz, period 3.0 ms) would take dt down to
#: -fs_structure_cfl's default 0.02 of it, 6e-5 s (2.5 times the acoustic limit's steps at dx = 2 mm); RK4 at 0.05
#: of it loses 1.3e-4 of the mode's amplitude a period (its share of the release: 3e-5 of the first mode's).
MODAL_NUMERICS: list[Any] = ["-fs_structure_cfl", 0.05]

#: The seed convergence study's runs: label -> (case file, structure, extra options). The numerics of all: the
#: density diffusion split off (RKL2) at 0.8 of the acoustic limit (docs/performance.md), the detector of a
#: blow-up above the slams' compression at dx <= 1 mm, a wider bounce distance against the floor jets.
#: The seed's terms (the case files' default with walls) and Monaghan's artificial pressure in tension, which keeps
#: the layer whole while the tank falls faster than g (docs/seed-experiment.md): not the seed's model.
SEED_TERMS = "continuity,delta,pressure,viscosity,les_viscosity,gravity,wall_continuity,wall_pressure,wall_viscosity"
ARTIFICIAL_PRESSURE: list[Any] = ["-fs_terms", SEED_TERMS + ",tensile_control", "-fs_tensile_control_type",
                                  "artificial_pressure"]
NO_TENSION: list[Any] = ["-fs_walls_tension", "false"]
SEED_CONVERGENCE_RUNS = {
    "rectangular_msd": ("coupled_rectangular", "msd", []),
    "rectangular_msd_artificial_pressure": ("coupled_rectangular", "msd", ARTIFICIAL_PRESSURE),
    "rectangular_msd_no_tension": ("coupled_rectangular", "msd", NO_TENSION),
    "baffled_msd": ("coupled_baffled", "msd", []),
    "rectangular_modal": ("coupled_rectangular", "modal", ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS),
    "baffled_modal": ("coupled_baffled", "modal", ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS),
    # walls that push only: the limit dx -> 0 of the seed's walls for a liquid in tension (docs/seed-experiment.md,
    # "A layer hanging from a wall"), reached at every resolution
    "baffled_msd_no_tension": ("coupled_baffled", "msd", NO_TENSION),
    "rectangular_modal_no_tension": ("coupled_rectangular", "modal",
                                     ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS + NO_TENSION),
    "baffled_modal_no_tension": ("coupled_baffled", "modal",
                                 ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS + NO_TENSION),
}
#: The releases of an ensemble (--ensemble N takes the first N): the tip's preload (the case files' 0.04 m) perturbed by
#: 1e-4 of itself. The small cycles are chaotic: at dx = 5 mm (push-only walls, five releases) the bands' zeta
#: scatters by 0.11 / 0.19 / 0.35 / 0.40 / 0.60 / 0.90 %-points (standard deviation) from the largest band to the
#: smallest, as much as 1 against 2 ranks (docs/seed-experiment.md).
SEED_ENSEMBLE_PRELOADS = (0.04, 0.040004, 0.039996, 0.040008, 0.039992)
SEED_CONVERGENCE_NUMERICS = ["-fs_delta_split", "-fs_cfl", 0.8, "-fs_max_density_variation", 0.95,
                             "-fs_walls_bounce_distance", 0.3]


def case_seed_convergence(ctx: Context, which: Optional[Sequence[str]] = None) -> Section:
    """The seed's damping per cycle (in amplitude bands) and peak tip acceleration at three or more resolutions:
    the observed order per band, Richardson's estimate and its uncertainty, the change between the two finest."""
    which = list(which or (["rectangular_msd"] if ctx.quick else SEED_CONVERGENCE_RUNS))
    dxs = sorted(ctx.dxs("seed_convergence"), reverse=True)
    bands = " ".join(f"{1e3 * hi:g}-{1e3 * lo:g}" for hi, lo in SEED_BANDS)
    sec = Section("seed_convergence", TITLES["seed_convergence"],
                  "The seed's tanks on the beam released from a 0.04 m tip deflection (3 s; the case files with "
                  f"`{' '.join(str(a) for a in SEED_CONVERGENCE_NUMERICS)}`) at dx = "
                  f"{', '.join(f'{1e3 * d:g}' for d in dxs)} mm: the damping ratio per cycle averaged over the amplitude bands "
                  f"{bands} mm and the peak tip acceleration; per band the observed order of convergence from the three "
                  "finest, Richardson's estimate with its uncertainty (Roache's GCI, factor 1.25) and the change between the two "
                  "finest, which is checked (at most 0.5 %-points: what separates 1 and 2 ranks at dx = 5 mm). "
                  "With `--ensemble N` each run is N releases (the preload perturbed by 1e-4 of itself) and the bands are "
                  "their mean, with its standard error beside it and beside the change.",
                  "Calderon-Sanchez et al. (the seed paper): the trend of Figs. 9-10 (2-5 % per cycle while the liquid "
                  "sloshes, back towards the structure's 1.5 %) and the peak of about 11 g; no tabulated numbers, so no data "
                  "file. docs/seed-experiment.md, \"The liquid leaving the floor and the resolution\".")
    tmax = 0.5 if ctx.quick else 3.0
    fig, axs = _figure(11, 4.2, ncols=2)
    for label in which:
        case, structure, extra = SEED_CONVERGENCE_RUNS[label]
        z, peaks, zse = [], [], []
        for dx in dxs:
            zs, ps = [], []
            for e, preload in enumerate(SEED_ENSEMBLE_PRELOADS[:ctx.ensemble]):
                args = ["-options_file", _case(case), "-fs_dx", dx, "-fs_structure", structure, "-ts_max_time", tmax,
                        "-fs_output_interval", 0] + SEED_CONVERGENCE_NUMERICS + extra
                args += ["-fs_beam_preload", preload] if e else []  # the first release is the case file's
                r = ctx.run("seed_convergence", f"{label}_{_label(dx)}" + (f"_e{e}" if e else ""), args, sec.runs,
                            checkpoints=5000)
                c = damping_per_cycle(r.column("time"), r.column("tip_displacement"))
                zs.append(100 * band_damping(c))
                ps.append(float(np.max(np.abs(r.column("tip_acceleration")))) / G)
            z.append(np.mean(zs, axis=0))
            peaks.append(float(np.mean(ps)))
            zse.append(np.std(zs, axis=0, ddof=1) / np.sqrt(len(zs)) if len(zs) > 1 else np.full(len(SEED_BANDS), np.nan))
        for k, dx in enumerate(dxs):
            axs[0].plot(range(len(SEED_BANDS)), z[k], "o-", ms=4, label=f"{label.replace('_', ', ')}, dx {1e3 * dx:g} mm")
        rows = [f"{label}: zeta per band (%) by dx, then the peak tip acceleration (g):", "",
                "| dx (mm) | " + " | ".join(f"{1e3 * hi:g}-{1e3 * lo:g} mm" for hi, lo in SEED_BANDS) + " | peak (g) |",
                "|---" * (len(SEED_BANDS) + 2) + "|"]
        if ctx.ensemble > 1:
            rows[0] = (f"{label}: zeta per band (%) by dx, the mean of {ctx.ensemble} releases +- its standard error, "
                       "then the peak tip acceleration (g):")
            rows += [f"| {1e3 * dx:g} | " + " | ".join(f"{v:.2f} +- {u:.2f}" for v, u in zip(z[k], zse[k]))
                     + f" | {peaks[k]:.1f} |" for k, dx in enumerate(dxs)]
        else:
            rows += [f"| {1e3 * dx:g} | " + " | ".join(f"{v:.2f}" for v in z[k]) + f" | {peaks[k]:.1f} |"
                     for k, dx in enumerate(dxs)]
        if len(dxs) >= 3:
            cv = convergence(z[-3], z[-2], z[-1], ratio=dxs[-2] / dxs[-1])
            cp = convergence(peaks[-3], peaks[-2], peaks[-1], ratio=dxs[-2] / dxs[-1])
            rows += ["| order | " + " | ".join(f"{v:.2f}" for v in cv.order) + f" | {cp.order[0]:.2f} |",
                     "| Richardson | " + " | ".join(f"{e:.2f} +- {u:.2f}" for e, u in zip(cv.extrapolated, cv.uncertainty))
                     + f" | {cp.extrapolated[0]:.1f} +- {cp.uncertainty[0]:.1f} |"]
            if ctx.ensemble > 1:  # what the scatter of the releases alone would move the change by
                noise = 2 * np.hypot(zse[-2], zse[-1])
                rows.append("| change between the two finest, 2 x its standard error | "
                            + " | ".join(f"{c:.2f}, {u:.2f}" for c, u in zip(cv.change, noise)) + " | |")
            axs[1].plot(range(len(SEED_BANDS)), cv.change, "s-", ms=4, label=label.replace("_", ", "))
            sec.checks.append(Check(f"{label}: largest change of a band's zeta between dx = {1e3 * dxs[-2]:g} and "
                                    f"{1e3 * dxs[-1]:g} mm (%-points)", float(np.nanmax(cv.change)), 0.5, fmt="{:.2f}"))
        sec.notes.append("\n".join(rows))
    for ax in axs:
        ax.set_xticks(range(len(SEED_BANDS)))
        ax.set_xticklabels([f"{1e3 * hi:g}-{1e3 * lo:g}" for hi, lo in SEED_BANDS], fontsize=7)
        ax.set_xlabel("cycle amplitude band (mm)")
        ax.legend(fontsize=6)
    axs[0].set_ylabel("zeta per cycle (%)")
    axs[0].axhline(1.5, color="k", lw=1)
    axs[1].set_ylabel("change between the two finest (%-points)")
    sec.figure = _save(fig, ctx, "seed_convergence")
    sec.caption = "Left: the damping per band at each resolution (the line at 1.5 %: the structure's own). Right: the change between the two finest"
    sec.notes.append("Order and Richardson's estimate are NaN where the changes do not shrink monotonically (outside the "
                     "asymptotic range). The runs write a checkpoint every 5,000 steps and an interrupted run continues "
                     "from its newest (`make validate CASES=seed_convergence` again).")
    missing = [k for k in SEED_CONVERGENCE_RUNS if k not in which]
    if missing:
        sec.notes.append("Not run in this report: " + ", ".join(missing) + " (`make validate CASES=seed_convergence` runs all).")
    return sec


#: The reduced model's heave grid (docs/equivalent.md, "The reduced model"): the seed's rectangular tank shaken at the
#: coupled beam's frequency (its period 0.165 s at dx = 5 mm) over amplitudes that span the free decay's bands, 3 ramp
#: periods, 16 cycles after them, the last 5 within 30 % of each other (the impacting liquid's cycles scatter by
#: 10-20 %). The releases of the coupled runs it is compared with, and the lags of the amplitude it is looked up at.
REDUCED_FREQUENCY = 6.05
REDUCED_AMPLITUDES = (0.002, 0.003, 0.004, 0.005, 0.0065, 0.008, 0.010, 0.0125, 0.015, 0.020, 0.025, 0.032, 0.040, 0.046)
REDUCED_GRID = {"ramp_cycles": 3, "cycles_max": 16, "settle": 4, "tol": 0.3}
REDUCED_RELEASES = 5
REDUCED_LAGS = (0.0, 0.2)


def case_reduced_model(ctx: Context) -> Section:
    """The seed's rectangular tank on the msd beam with its liquid replaced by the heave describing function measured
    at the same resolution and numerics (-fs_msd_liquid_table): the damping per band against the coupled runs'
    (an ensemble of releases) and the two runs' wall times."""
    from . import equivalent as eq

    dxs = sorted(ctx.dxs("reduced_model"), reverse=True)
    releases = 1 if ctx.quick else REDUCED_RELEASES
    amplitudes = (0.01, 0.02, 0.04) if ctx.quick else REDUCED_AMPLITUDES
    grid_kw = dict(REDUCED_GRID, cycles_max=8) if ctx.quick else REDUCED_GRID
    tmax = 1.0 if ctx.quick else 3.0
    numerics = ["-fs_delta_max", 0.5, "-fs_delta_cfl", 0.1875] + SEED_CONVERGENCE_NUMERICS + NO_TENSION
    sec = Section("reduced_model", TITLES["reduced_model"],
                  "The seed's rectangular tank on the msd beam released from a 0.04 m tip deflection (3 s): the coupled run "
                  f"({releases} release(s), the preload perturbed by 1e-4 of itself, push-only walls and the seed_convergence "
                  "numerics) against the reduced model (`-fs_case beam -fs_msd_liquid_table`), whose table is the liquid's heave "
                  f"describing function at {REDUCED_FREQUENCY} Hz from `flexslosh.equivalent` at the same dx and numerics "
                  f"(amplitudes {', '.join(f'{1e3 * a:g}' for a in amplitudes)} mm). Compared: the damping ratio per cycle "
                  "averaged over the seed's amplitude bands, the reduced model's minus the releases' mean (checked within "
                  "0.3 %-points at the finest dx, the memoryless model), and the wall times.",
                  "The coupled runs themselves (issue 36 item 4: each band within 0.3 %-points, at least 1,000 times "
                  "cheaper); docs/equivalent.md, \"The reduced model\".")
    fig, ax = _figure(7, 4.2)
    rows = ["| dx (mm) | run | " + " | ".join(f"{1e3 * hi:g}-{1e3 * lo:g} mm" for hi, lo in SEED_BANDS) + " | wall (s) |",
            "|---|---" + "|---" * len(SEED_BANDS) + "|---|"]
    for dx in dxs:
        base = {"fs_dx": dx, "fs_c0": 20, "fs_relax_time": 0.1, "fs_tank_width": 0.1}
        base.update(eq.petsc_options([str(a) for a in numerics]))
        t0 = time.time()
        grid_rows = eq.grid(_case("tank_rectangular"), "heave", [None], list(amplitudes), [REDUCED_FREQUENCY], base,
                            ctx.work / "reduced_model" / f"heave_{_label(dx)}", figures=False, progress=None, **grid_kw)
        table = eq.write_liquid_table(grid_rows, ctx.work / "reduced_model" / f"table_{_label(dx)}.txt")
        sec.notes.append(f"dx = {1e3 * dx:g} mm: the heave grid's rows, m_eff / M and c_eq / (M omega) by amplitude (mm): "
                         + "; ".join(f"{1e3 * r['amplitude']:g}: " + (f"{r['m_eff_ratio']:.3f}, {r['c_eq_nd']:.3f}"
                                                                          if r["settled"] else "not settled")
                                     for r in grid_rows)
                         + f" ({time.time() - t0:.0f} s here, 0 when its points were read back).")
        zs, walls = [], []
        for e, preload in enumerate(SEED_ENSEMBLE_PRELOADS[:releases]):
            args = ["-options_file", _case("coupled_rectangular"), "-fs_dx", dx, "-fs_structure", "msd", "-ts_max_time", tmax,
                    "-fs_output_interval", 0] + SEED_CONVERGENCE_NUMERICS + NO_TENSION
            args += ["-fs_beam_preload", preload] if e else []
            r = ctx.run("seed_convergence", f"rectangular_msd_no_tension_{_label(dx)}" + (f"_e{e}" if e else "")
                        + ("_quick" if ctx.quick else ""), args, sec.runs, checkpoints=5000)
            zs.append(100 * band_damping(damping_per_cycle(r.column("time"), r.column("tip_displacement"))))
            walls.append(sec.runs[-1].wall)
        zc = np.mean(zs, axis=0)
        se = np.std(zs, axis=0, ddof=1) / np.sqrt(len(zs)) if len(zs) > 1 else np.full(len(SEED_BANDS), np.nan)
        rows.append(f"| {1e3 * dx:g} | coupled, {len(zs)} release(s), mean +- SE | " + " | ".join(
            f"{v:.2f} +- {u:.2f}" for v, u in zip(zc, se)) + f" | {np.mean(walls):.0f} |")
        color = f"C{dxs.index(dx)}"  # one colour per dx: the coupled runs' line solid, the reduced model's dashed
        ax.errorbar(range(len(SEED_BANDS)), zc, yerr=se, fmt="o-", ms=4, color=color, label=f"coupled, dx {1e3 * dx:g} mm")
        mass = float(grid_rows[0]["liquid_mass"])
        for lag in REDUCED_LAGS:
            args = ["-fs_case", "beam", "-fs_structure", "msd", "-fs_beam_tank_mass", 5.0, "-fs_beam_payload_mass", 3.36,
                    "-fs_beam_preload", 0.04, "-fs_beam_damping", 0.015, "-ts_max_time", tmax, "-fs_output_interval", 0,
                    "-fs_msd_liquid_table", _from_repo(table), "-fs_msd_liquid_mass", mass, "-fs_msd_liquid_lag", lag]
            r = ctx.run("reduced_model", f"reduced_{_label(dx)}_lag{lag:g}", args, sec.runs)
            zr = 100 * band_damping(damping_per_cycle(r.column("time"), r.column("tip_displacement")))
            wall = float(r.summary.get("wall_time", sec.runs[-1].wall))
            rows.append(f"| {1e3 * dx:g} | reduced, lag {lag:g} s (its difference) | " + " | ".join(
                f"{v:.2f} ({v - c:+.2f})" for v, c in zip(zr, zc)) + f" | {wall:.3f} |")
            ax.plot(range(len(SEED_BANDS)), zr, "^:" if lag else "s--", ms=4, color=color,
                    label=f"reduced, lag {lag:g} s, dx {1e3 * dx:g} mm")
            if dx == dxs[-1] and lag == 0:
                for k, (hi, lo) in enumerate(SEED_BANDS):
                    sec.checks.append(Check(f"dx = {1e3 * dx:g} mm, band {1e3 * hi:g}-{1e3 * lo:g} mm: reduced minus coupled "
                                            "(%-points, abs)", abs(float(zr[k] - zc[k])), 0.3, fmt="{:.2f}"))
                sec.checks.append(Check(f"dx = {1e3 * dx:g} mm: the coupled run's wall time over the reduced model's "
                                        "(the solver's own, summary.json)", float(np.mean(walls)) / max(wall, 1e-9), 1000,
                                        kind="min", fmt="{:.0f}"))
    sec.notes.insert(0, "\n".join(rows))
    ax.set_xticks(range(len(SEED_BANDS)))
    ax.set_xticklabels([f"{1e3 * hi:g}-{1e3 * lo:g}" for hi, lo in SEED_BANDS], fontsize=7)
    ax.set_xlabel("cycle amplitude band (mm)")
    ax.set_ylabel("zeta per cycle (%)")
    ax.axhline(1.5, color="k", lw=1)
    ax.legend(fontsize=6)
    sec.figure = _save(fig, ctx, "reduced_model")
    sec.caption = ("The damping per band: the coupled runs (solid, mean and standard error) and the reduced model (dashed: "
                   "no lag; dotted: the lag), a colour per dx")
    return sec


#: The swayed rectangular tank against linear potential theory (docs/equivalent.md): a 0.2 m long tank, 0.1 m deep,
#: c0 = 10 m/s, in 3-D 0.1 m wide (its transverse modes are the 2-D ones). label -> (dim, omega / omega_1, A / L,
#: describe's settings). Above omega_1 the ramp leaves a free oscillation at omega_1 that beats with the forcing
#: (the cycles scatter by +-0.03 m): it is fitted out (free) and the cycles are never within 3 % of each other, so
#: the mean of the cycles after the first is taken. In 3-D A / L = 0.02: at 0.005 the liquid's own motion at rest
#: (its rms speed 0.01 sqrt(g H), docs/walls.md) is larger than the tank's (6 mm/s) and each cycle's m_eff scatters by
#: +-5 %; the 2-D tank gives the same m_eff at both amplitudes (1.1473 and 1.1470 at dx = 1 cm).
SWAY_RUNS: dict[str, tuple[int, float, float, dict[str, Any]]] = {
    "2-D, 0.5 omega_1": (2, 0.5, 0.005, {"ramp_cycles": 4, "cycles_max": 5, "settle": 2, "tol": 0.03}),
    "2-D, 1.5 omega_1": (2, 1.5, 0.005, {"ramp_cycles": 6, "cycles_max": 8, "settle": 2, "tol": 0.03, "free": 1.0}),
    "3-D, 0.5 omega_1": (3, 0.5, 0.02, {"ramp_cycles": 4, "cycles_max": 5, "settle": 2, "tol": 0.03}),
    "3-D, 1.5 omega_1": (3, 1.5, 0.01, {"ramp_cycles": 6, "cycles_max": 8, "settle": 2, "tol": 0.03, "free": 1.0}),
}
SWAY_TANK = {"fs_case": "tank", "fs_tank_shape": "rectangular", "fs_tank_length": 0.2, "fs_tank_height": 0.2, "fs_fill": 0.5,
             "fs_c0": 10, "fs_relax_time": 0.25}


def sway_mass_of(record: dict) -> tuple[float, int]:
    """m_eff / m of a describing-function point's record (flexslosh.equivalent.grid): the settled cycles' mean, else
    the mean of the cycles after the first; and the number of cycles averaged."""
    row, cycles = record["row"], record["cycles"]
    if row["settled"]:
        return float(row["m_eff_ratio"]), int(record["params"]["describe"].get("settle", 3)) + 1
    m = [c["m_eff"] / row["reference_mass"] for c in cycles[1:]]
    return float(np.mean(m)), len(m)


def case_sway_mass(ctx: Context) -> Section:
    """The effective mass of a swayed rectangular tank below and above its first sloshing frequency, 2-D and a 3-D
    box, at three resolutions, against linear potential theory (issue 36 item 3)."""
    from . import equivalent as eq

    L, h = SWAY_TANK["fs_tank_length"], SWAY_TANK["fs_tank_height"] * SWAY_TANK["fs_fill"]
    w1 = float(eq.rectangular_modes(L, h)[0][0])
    sec = Section("sway_mass", TITLES["sway_mass"],
                  "A rectangular tank 0.2 m long, half full (0.1 m deep), c0 = 10 m/s, swayed along x as A sin(omega t) "
                  "(`flexslosh.equivalent`, the load in phase with the acceleration over the acceleration) at half and at "
                  "1.5 times its first sloshing frequency omega_1, in 2-D (A / L = 0.005) and as a 3-D box 0.1 m wide "
                  "(A / L = 0.02 below omega_1, 0.01 above), at three resolutions each: m_eff / m against theory, checked "
                  "within 3 % of m at the finest (the issue's bound) and closer there than at the coarsest. Above omega_1 "
                  "the free oscillation at omega_1 left by the ramp is fitted out and the mean of the cycles after the "
                  "first is taken (they beat, never within 3 % of each other).",
                  "Linear potential theory, the equivalent mechanical model (Graham & Rodriguez 1952; Abramson, NASA SP-106, "
                  "1966): m_eff / m = 1 + sum_n (m_n / m) omega^2 / (omega_n^2 - omega^2), "
                  f"{eq.rectangular_sway_mass(L, h, 0.5 * w1):.4f} at 0.5 omega_1 and {eq.rectangular_sway_mass(L, h, 1.5 * w1):.4f} "
                  "at 1.5 omega_1 (docs/equivalent.md); formulas, no data file.")
    rows = ["| run | dx (mm) | particles | m_eff / m (cycles) | theory | error (% of m) | wall (s) |", "|---|---|---|---|---|---|---|"]
    fig, ax = _figure(7, 4.2)
    for k, (label, (dim, ratio, a_over_l, kw)) in enumerate(SWAY_RUNS.items()):
        dxs = sorted(ctx.dxs("sway_mass" if dim == 2 else "sway_mass_3d"), reverse=True)
        omega = ratio * w1
        exact = eq.rectangular_sway_mass(L, h, omega)
        kw = dict(kw, **({"free": kw["free"] * w1} if "free" in kw else {}))
        if ctx.quick:
            kw["cycles_max"] = 3
        errs = []
        for dx in dxs:
            base = dict(SWAY_TANK, fs_dim=dim, fs_dx=dx, **({"fs_tank_width": 0.1} if dim == 3 else {}))
            out = ctx.work / "sway_mass" / f"{dim}d_{ratio:g}_{_label(dx)}"
            t0 = time.time()
            eq.grid(None, "sway", [None], [a_over_l * L], [omega / (2 * np.pi)], base, out, figures=False, progress=None, **kw)
            record = json.loads((out / "points" / "point_0000.json").read_text())
            m, n = sway_mass_of(record)
            summary = json.loads((Path(record["row"]["output_dir"]) / "summary.json").read_text())
            sec.runs.append(RunInfo(f"sway {dim}-D {ratio:g} omega_1 {_label(dx)}",
                                    "python3 -m flexslosh.equivalent --direction sway "
                                    f"--amplitude {a_over_l * L:g} --frequency {omega / (2 * np.pi):.6g} "
                                    f"--ramp-cycles {kw['ramp_cycles']:g} --cycles {kw['cycles_max']} --settle {kw['settle']} "
                                    f"--tol {kw['tol']:g} " + (f"--free {kw['free'] / (2 * np.pi):.6g} " if "free" in kw else "")
                                    + " ".join(f"-{o} {v}" for o, v in base.items()),
                                    int(summary["particles"]), float(summary.get("wall_time", time.time() - t0)),
                                    str(record["row"].get("revision", _commit()))))  # the commit the point ran on
            errs.append(m - exact)
            rows.append(f"| {label} | {1e3 * dx:.3g} | {int(summary['particles']):,} | {m:.4f} ({n}{', settled' if record['row']['settled'] else ''}) "
                        f"| {exact:.4f} | {100 * (m - exact):+.2f} | {float(summary.get('wall_time', 0)):.0f} |")
        ax.loglog([1e3 * d for d in dxs], [max(abs(e), 1e-5) for e in errs], "o-", color=f"C{k}", label=label)
        if len(dxs) >= 2:
            order = math.log(abs(errs[-2] / errs[-1])) / math.log(dxs[-2] / dxs[-1]) if errs[-1] and errs[-2] else float("nan")
            rows.append(f"| {label}: observed order of the error (two finest), change between them | | | {order:.2f} | "
                        f"| {100 * abs(errs[-1] - errs[-2]):.2f} | |")
            sec.checks.append(Check(f"{label}, dx {1e3 * dxs[-1]:.3g} mm: abs(m_eff / m - theory)", abs(errs[-1]), 0.03,
                                    fmt="{:.4f}"))
            sec.checks.append(Check(f"{label}: its error at dx {1e3 * dxs[-1]:.3g} mm over the error at {1e3 * dxs[0]:.3g} mm",
                                    abs(errs[-1]) / max(abs(errs[0]), 1e-12), 1.0, fmt="{:.2f}"))
    sec.notes.append("\n".join(rows))
    ax.axhline(0.03, color="k", lw=1)
    ax.set_xlabel("dx (mm)")
    ax.set_ylabel("abs(m_eff / m - theory)")
    ax.legend(fontsize=7)
    sec.figure = _save(fig, ctx, "sway_mass")
    sec.caption = "The effective mass's error against dx (the line: the issue's 3 % of m)"
    return sec


#: The seed's tanks through the release and the first slams: label -> (case file, structure, extra options).
SEED_SLAMS_RUNS = {
    "rectangular_msd": ("coupled_rectangular", "msd", []),
    "rectangular_modal": ("coupled_rectangular", "modal", ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS),
    "baffled_msd": ("coupled_baffled", "msd", []),
    "baffled_modal": ("coupled_baffled", "modal", ["-fs_modal_modes", 5, "-fs_modal_elements", 40] + MODAL_NUMERICS),
}
#: The instants of the seed's Figs. 6-7 drawn here (the seed does not give its own): the release, the first
#: slams and the first return.
SEED_SLAM_INSTANTS = (0.05, 0.1, 0.2, 0.3, 0.5)


def case_seed_slams(ctx: Context, which: Optional[Sequence[str]] = None) -> Section:
    """The seed's tanks through the first 0.5 s (the release and the first slams) at the seed's c0 = 20 m/s and
    h/dx = 2, down to its L/dx = 2000: no blow-up, the energy budget closed, the steps against the acoustic limit's,
    the largest compression against the slam's Mach number, and the turbulent viscosity at five instants (Figs. 6-7)."""
    which = list(which or (["rectangular_msd"] if ctx.quick else SEED_SLAMS_RUNS))
    dxs = sorted(ctx.dxs("seed_slams"), reverse=True)
    finest = ctx.dxs("seed_slams_finest")
    tmax = 0.1 if ctx.quick else 0.5
    c0 = 20.0
    sec = Section("seed_slams", TITLES["seed_slams"],
                  f"The seed's tanks (rectangular and baffled, msd and modal beam) released from a 0.04 m tip deflection, to "
                  f"t = {tmax:g} s at dx = {', '.join(f'{1e3 * d:g}' for d in dxs)} mm, and the rectangular tank on the msd beam "
                  f"at dx = {', '.join(f'{1e3 * d:g}' for d in finest)} mm (L/dx = {0.7 / finest[0]:.0f}), all with the seed's "
                  "c0 = 20 m/s and h/dx = 2 and the case files' numerics with "
                  f"`{' '.join(str(a) for a in SEED_CONVERGENCE_NUMERICS)}`. Checked per run: it reaches the final time (no "
                  "blow-up, no particle lost), the energy budget's residual (largest abs(residual_total) over the beam's "
                  "initial elastic energy) below 1e-3, the steps per simulated second at most 1.5 times the acoustic limit's "
                  "alone (h / (c0 + |u|max) at CFL 1, with the run's mean largest speed). Reported: the largest "
                  "abs(rho/rho0 - 1) and the largest speed's Mach number.",
                  "Calderon-Sanchez et al. (the seed paper), Figs. 6-7: the turbulent kinetic energy on a log scale at five "
                  "instants, rectangular tank at L/dx = 2000, baffled at L_i/dx = 360, c0 = 20 m/s, h/dx = 2; no tabulated "
                  "values, so no data file. docs/performance.md, \"What stops the seed's tank at dx = 1 mm\".")
    plan = [(label, dx) for dx in dxs for label in which] + [("rectangular_msd", dx) for dx in finest if "rectangular_msd" in which]
    rows = ["| run | dx (mm) | particles | steps / s | x acoustic | max abs(rho/rho0 - 1) | max Mach | residual / E_beam | wall (s) |",
            "|---|---|---|---|---|---|---|---|---|"]
    runs: dict[tuple[str, float], Run] = {}
    fig, axs = _figure(13, 4.2, ncols=3)
    for label, dx in plan:
        case, structure, extra = SEED_SLAMS_RUNS[label]
        args = ["-options_file", _case(case), "-fs_dx", dx, "-fs_structure", structure, "-ts_max_time", tmax,
                "-fs_output_interval", 0.05] + SEED_CONVERGENCE_NUMERICS + extra
        name = f"{label}, dx {1e3 * dx:g} mm"
        try:
            r = ctx.run("seed_slams", f"{label}_{_label(dx)}", args, sec.runs, checkpoints=2000)
        except RuntimeError as err:
            sec.checks.append(Check(f"{name}: reaches t = {tmax:g} s (the run failed)", math.inf, tmax, kind="max"))
            sec.notes.append(f"{name} failed: " + str(err).splitlines()[-1][:400])
            continue
        runs[(label, dx)] = r
        t = r.column("time")
        e = r.energy
        residual = float(np.max(np.abs(e["residual_total"]))) / float(e["E_struct_elastic"][0])
        umax = r.column("max_velocity")
        acoustic = float(t[-1]) * (c0 + float(np.mean(umax))) / (2 * dx)
        steps = float(r.summary.get("final_step", len(t) - 1))  # a continued run's "steps" counts its last part only
        comp, mach = float(np.max(r.column("max_density_variation"))), float(np.max(umax)) / c0
        rows.append(f"| {label.replace('_', ', ')} | {1e3 * dx:g} | {r.particles:,} | {steps / t[-1]:,.0f} | "
                    f"{steps / acoustic:.2f} | {comp:.3f} | {mach:.2f} | {residual:.1e} | {sec.runs[-1].wall:,.0f} |")
        sec.checks += [Check(f"{name}: reaches t = {tmax:g} s", float(t[-1]), tmax * (1 - 1e-9), kind="min", fmt="{:.4g}"),
                       Check(f"{name}: max abs(residual_total) / initial elastic energy", residual, 1e-3, fmt="{:.1e}"),
                       Check(f"{name}: steps / acoustic limit's", steps / acoustic, 1.5, fmt="{:.2f}")]
        axs[0].loglog([mach], [comp], "o" if "rect" in label else "s", ms=4 + 2 * np.log2(max(dxs) / dx),
                      color=f"C{list(SEED_SLAMS_RUNS).index(label)}", label=name)
        if label == "rectangular_msd":
            axs[1].plot(t, 1e3 * r.column("tip_displacement"), lw=1, label=f"dx {1e3 * dx:g} mm")
            axs[2].plot(t, r.column("kinetic_energy"), lw=1, label=f"kinetic (tank's frame), dx {1e3 * dx:g} mm")
            axs[2].plot(e["time"], -np.asarray(e["work_delta"]) - np.asarray(e["work_alpha"]), "--", lw=1,
                        label=f"dissipated (delta + alpha), dx {1e3 * dx:g} mm")
    sec.notes.append("\n".join(rows))
    m = np.logspace(-1.3, 0.3, 20)
    axs[0].loglog(m, m**2, "k:", lw=1, label="Ma^2")
    axs[0].set_xlabel("largest speed / c0")
    axs[0].set_ylabel("max abs(rho/rho0 - 1)")
    axs[1].set_xlabel("t (s)")
    axs[1].set_ylabel("tip displacement (mm)")
    axs[2].set_xlabel("t (s)")
    axs[2].set_ylabel("energy (J per m of width)")
    for ax in axs:
        ax.legend(fontsize=6)
    sec.figure = _save(fig, ctx, "seed_slams")
    sec.caption = ("Left: the largest compression against the largest speed's Mach number (marker size: finer dx). Middle and "
                   "right: the rectangular tank on the msd beam, tip displacement, the liquid's kinetic energy in the tank's frame and the energy "
                   "dissipated by the density diffusion and the viscosity, at each dx")
    for label, fig_no in (("rectangular_msd", 6), ("baffled_msd", 7)):
        done = [dx for (lb, dx) in runs if lb == label]
        if done:
            dx = min(done)
            png = snapshot_figure(runs[(label, dx)], ctx.out / f"seed_slams_fig{fig_no}.png", "turbulent_viscosity", times=SEED_SLAM_INSTANTS)
            sec.notes.append(f"The seed's Fig. {fig_no} ({label.replace('_', ', ')}, dx = {1e3 * dx:g} mm): the Smagorinsky "
                             f"viscosity on a log scale at t = {', '.join(f'{t:g}' for t in SEED_SLAM_INSTANTS)} s: "
                             f"![Fig. {fig_no}]({png.name})")
    sec.notes.append("The runs write a checkpoint every 2,000 steps; an interrupted run continues from its newest "
                     "(`make validate CASES=seed_slams` again).")
    missing = [k for k in SEED_SLAMS_RUNS if k not in which]
    if missing:
        sec.notes.append("Not run in this report: " + ", ".join(missing) + " (`make validate CASES=seed_slams` runs all).")
    return sec


#: The cases in the report's order: key -> (function, the command that runs it alone).
CASES: dict[str, Callable[[Context], Section]] = {
    "taylor_green": case_taylor_green,
    "hydrostatic": case_hydrostatic,
    "hydrostatic_3d": case_hydrostatic_3d,
    "baffles_at_rest_3d": case_baffles_at_rest_3d,
    "standing_wave": case_standing_wave,
    "standing_wave_3d": case_standing_wave_3d,
    "standing_wave_3d_10": case_standing_wave_3d_10,
    "dam_break": case_dam_break,
    "dam_break_pressure": case_dam_break_pressure,
    "dam_break_lobovsky": case_dam_break_lobovsky,
    "dam_break_3d": case_dam_break_3d,
    "roll_tank": case_roll_tank,
    "impact_c0": case_impact_c0,
    "beam": case_beam,
    "energy": case_energy,
    "seed": case_seed,
    "seed_convergence": case_seed_convergence,
    "reduced_model": case_reduced_model,
    "sway_mass": case_sway_mass,
    "seed_slams": case_seed_slams,
    "shapes_at_rest": case_shapes_at_rest,
}

TITLES = {
    "shapes_at_rest": "Tanks at rest whose walls are not along the axes (2-D and 3-D)",
    "taylor_green": "Taylor-Green vortex (2-D, periodic, Re = 100)",
    "hydrostatic": "Hydrostatic tank (2-D)",
    "hydrostatic_3d": "Hydrostatic tank (3-D box, triangle-mesh walls)",
    "baffles_at_rest_3d": "Lifted baffles at rest (3-D, the liquid passing under a baffle)",
    "standing_wave": "Standing wave (2-D, free-slip walls)",
    "standing_wave_3d": "Standing wave (3-D box, mode (1, 1))",
    "standing_wave_3d_10": "Standing wave (3-D box, mode (1, 0))",
    "dam_break": "Dam break: surge front and column (Martin & Moyce 1952)",
    "dam_break_pressure": "Dam break: pressure on the downstream wall (Buchner 2002, De Courcy et al. 2024)",
    "dam_break_lobovsky": LOBOVSKY_TITLE,
    "dam_break_3d": "Dam break: surge front and column (Martin & Moyce 1952) in 3-D",
    "roll_tank": "Forced sloshing: SPHERIC benchmark test 10 (rolled tank)",
    "impact_c0": IMPACT_TITLE,
    "beam": "Cantilever beam: modes and free decay",
    "energy": "Energy budget residuals (seed Eqs. 31-40)",
    "seed": "The seed's experiment: damping per cycle against amplitude",
    "seed_convergence": "The seed's experiment: the damping per cycle converging with resolution",
    "seed_slams": "The seed's tanks through the first slams, down to L/dx = 2000",
    "reduced_model": "The seed's experiment without particles: the reduced model against the coupled runs",
    "sway_mass": "The swayed tank's effective mass against potential theory (2-D and a 3-D box)",
}


def run_cases(ctx: Context, names: Sequence[str]) -> dict[str, Section]:
    """Runs the named cases; a case that fails gets a section saying so with the error."""
    done: dict[str, Section] = {}
    for name in names:
        print(f"validate: {name} at dx = {ctx.dxs(name)}{' (quick)' if ctx.quick else ''}", flush=True)
        try:
            done[name] = CASES[name](ctx)
            done[name].dxs = ctx.dxs(name)
        except (RuntimeError, ValueError, FileNotFoundError, KeyError, IndexError) as err:
            sec = Section(name, TITLES[name], "The case did not complete.", "See the case's function in python/flexslosh/validate.py.")
            sec.checks.append(Check("the case ran to its end", 0.0, 1.0, kind="min", fmt="{:g}"))
            sec.notes.append("Error:\n\n```\n" + str(err)[-2000:] + "\n```")
            done[name] = sec
    return done


HEADER = """# Validation report

Written by `make validate` (`python3 -m flexslosh.validate`, python/flexslosh/validate.py): each section
below is the output of a real run of the case at the resolution(s) it names, with the measured errors
against their tolerances (PASS or **FAIL**) and the wall time on the machine that ran it. The reference
data are in [data/](data/README.md) with their sources; the formulas and the tests that check the same
physics at coarse resolutions are in [../validation.md](../validation.md). A case not run in this report
says so with the command that runs it. Resolutions: `make validate` runs those of `RESOLUTIONS` in
validate.py (`--resolution CASE=dx1,dx2` overrides); `make validate CASES=a,b` runs a subset and rewrites
only their sections; `--quick` is a smoke run (coarse and short, its numbers meaningless). The table
gives the resolutions each case ran at and those `make validate` runs: where they differ the run was
coarser, to fit the time of this report.
"""


def write_report(out: Path, sections: dict[str, Section], quick: bool = False) -> Path:
    """Writes each new section to out/sections/NAME.json (its Markdown, its count of checks passed and
    its wall time), then out/README.md from all sections present (in the order of CASES), with a
    summary table and a "not run" section for each case never run."""
    secdir = out / "sections"
    secdir.mkdir(parents=True, exist_ok=True)
    for name, sec in sections.items():
        (secdir / f"{name}.json").write_text(json.dumps({"passed": sum(c.passed for c in sec.checks), "checks": len(sec.checks),
                                                         "wall": sum(r.wall for r in sec.runs),
                                                         "runs": [r.label for r in sec.runs], "dx": sec.dxs,
                                                         "markdown": sec.markdown(quick)}, indent=1) + "\n")
    body, rows = [], []
    default = lambda name: ", ".join(f"{d:g}" for d in RESOLUTIONS[name]) if RESOLUTIONS[name] != [0.0] else "-"  # noqa: E731
    for name in CASES:
        js = secdir / f"{name}.json"
        anchor = _anchor(TITLES[name])
        if js.is_file():
            s = json.loads(js.read_text())
            body.append(s["markdown"] + "\n")
            verdict = "pass" if s["passed"] == s["checks"] else f"**{s['checks'] - s['passed']} of {s['checks']} FAIL**"
            ran = ", ".join(f"{d:g}" for d in s["dx"]) if s.get("dx") else ", ".join(r[2:] for r in s.get("runs", []) if r.startswith("dx"))
            ran = "-" if ran in ("", "0") else ran
            rows.append(f"| [{TITLES[name]}](#{anchor}) | {verdict} | {ran} | {default(name)} | {s['wall']:.0f} s |")
        else:
            cmd = f"make validate CASES={name}"
            body.append(f"## {TITLES[name]}\n\n**Not run in this report.** Run it with `{cmd}` "
                        f"(resolution(s) dx = {', '.join(f'{d:g}' for d in RESOLUTIONS[name])}).\n")
            rows.append(f"| [{TITLES[name]}](#{anchor}) | not run | | {default(name)} | |")
    table = "\n| case | checks | dx run | dx of `make validate` | wall time |\n|---|---|---|---|---|\n"
    text = HEADER + table + "\n".join(rows) + "\n\n" + "\n".join(body)
    path = out / "README.md"
    path.write_text(text)
    return path


def _anchor(title: str) -> str:
    """GitHub's anchor of a heading."""
    import re

    text = re.sub(r"[^\w\- ]", "", title.strip().lower())
    return text.replace(" ", "-")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python3 -m flexslosh.validate", description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", default="", help="comma-separated cases (default: all): " + ", ".join(CASES))
    p.add_argument("--quick", action="store_true", help="coarse, short smoke runs")
    p.add_argument("--out", default=str(REPO / "docs" / "validation"), help="the report's folder (default docs/validation)")
    p.add_argument("--work", default=str(REPO / "output" / "validate"), help="the runs' output folder (default output/validate)")
    p.add_argument("--resolution", action="append", default=[], metavar="CASE=dx1,dx2", help="the dx values of a case")
    p.add_argument("--ranks", type=int, default=1, help="MPI ranks per run (default 1)")
    p.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(REPO / "build")), help="the build folder")
    p.add_argument("--ensemble", type=int, default=1,
                   help="releases per seed_convergence run, the tip's preload perturbed by 1e-4 of itself (default 1; "
                        f"at most {len(SEED_ENSEMBLE_PRELOADS)}): the bands' mean and its standard error")
    p.add_argument("--reuse", action="store_true",
                   help="read a run already in --work when it finished with the same command (its validate_run.json) "
                        "instead of running it again: to redo a section's checks and figure")
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line; returns 0 when the report was written (FAILs included), 2 on bad arguments."""
    args = _parser().parse_args(argv)
    names = [c.strip() for c in args.cases.split(",") if c.strip()] or list(CASES)
    bad = [c for c in names if c not in CASES]
    if bad:
        print(f"validate: unknown case(s) {', '.join(bad)}; known: {', '.join(CASES)}", file=sys.stderr)
        return 2
    res: dict[str, list[float]] = {}
    for item in args.resolution:
        case, _, values = item.partition("=")
        if case not in RESOLUTIONS or not values:
            print(f"validate: --resolution {item!r}: expected CASE=dx1,dx2 with a known case or resolution list "
                  f"({', '.join(RESOLUTIONS)})", file=sys.stderr)
            return 2
        res[case] = [float(v) for v in values.split(",")]
    exe = Path(args.build) / "flexslosh"
    if not exe.is_file():
        print(f"validate: {exe} not found: build first (make build)", file=sys.stderr)
        return 2
    if not 1 <= args.ensemble <= len(SEED_ENSEMBLE_PRELOADS):
        print(f"validate: --ensemble {args.ensemble}: expected 1 to {len(SEED_ENSEMBLE_PRELOADS)}", file=sys.stderr)
        return 2
    ctx = Context(exe=exe.resolve(), work=Path(args.work).resolve(), out=Path(args.out).resolve(), quick=args.quick,
                  resolutions=res, ranks=args.ranks, reuse=args.reuse, ensemble=args.ensemble)
    for name in names:  # the report is rewritten after each case, so that an interrupted run keeps the cases done
        path = write_report(ctx.out, run_cases(ctx, [name]), args.quick)
    print(f"validate: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

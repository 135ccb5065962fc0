"""Command line: the seed's figures and the damping per cycle of flexslosh runs.

Usage::

    python3 -m flexslosh.plot OUTPUT_DIR [OUTPUT_DIR ...] [--labels a,b] [--out DIR] [--field NAME]

For each run it writes ``tip_acceleration.png``, ``energy_terms.png``, ``snapshots.png`` (particles
coloured by --field), ``probes.png`` (the pressure probes and wave gauges of probes.csv, for a run
with -fs_probes) and ``damping.csv`` (damping per cycle of tip_displacement: time, amplitude,
period, delta, zeta) into the run's directory; for all the runs together ``normalized_motion.png``,
``acceleration_envelope.png`` and ``damping_vs_amplitude.png`` into the first run's directory. A run
of a prescribed motion (-fs_structure prescribed) gets ``motion.png`` (the motion's components) and
``wall_loads.png`` (the walls' loads and the tank's) instead of the beam's figures (tip acceleration,
damping), and is left out of the figures of all the runs together. With
``--out DIR`` everything goes to DIR instead, the per-run files named ``<name>_<label>.<ext>``.
A figure the data do not allow (no structure, no liquid, no snapshots) is skipped with a one-line
note on stderr; the paths written are printed on stdout, one per line. A directory that is not a
flexslosh output (no timeseries.csv) or a malformed file stops it with a one-line message and exit
status 1.

``python3 -m flexslosh.plot movie OUTPUT_DIR [--field NAME] [--output FILE] [--fps N] [--every N]
[--frame K]`` writes an animation of one run instead (see :mod:`flexslosh.movie`).
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path
from typing import Callable, Optional, Sequence

from . import figures
from .damping import damping_per_cycle, write_damping_csv
from .output import Run, read_run

__all__ = ["main"]

PROG = "python3 -m flexslosh.plot"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Writes the seed paper's figures (Figs. 5-11) and damping.csv for flexslosh output directories.",
    )
    p.add_argument("dirs", nargs="+", metavar="OUTPUT_DIR", help="a flexslosh output directory (-fs_output_dir)")
    p.add_argument("--labels", help="comma-separated legend labels, one per directory (default: the directory names)")
    p.add_argument("--out", metavar="DIR", help="write every file here (created if needed) instead of the run directories")
    p.add_argument("--field", default="turbulent_viscosity",
                   help="snapshot field of snapshots.png (default turbulent_viscosity; e.g. strain_rate, pressure, velocity)")
    return p


def _file_label(label: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", label).strip("_") or "run"


def _attempt(what: str, make: Callable[[], Path], written: list[Path]) -> None:
    """Runs make(); records its path, or prints a one-line note when the data do not allow it."""
    try:
        written.append(make())
    except (ValueError, OSError) as err:
        print(f"note: skipped {what}: {err}", file=sys.stderr)


def _damping_csv(run: Run, path: Path) -> Path:
    cycles = damping_per_cycle(run.column("time"), run.column("tip_displacement"))
    write_damping_csv(str(path), cycles)
    return path


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Runs the command line.

    Args:
        argv: the arguments (default: sys.argv[1:]); a first argument ``movie`` runs
            :func:`flexslosh.movie.main` on the rest.

    Returns:
        The exit status: 0, or 1 when a directory cannot be read (argparse exits with 2 on bad usage).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["movie"]:  # the subcommand (a run directory named movie: ./movie)
        from . import movie

        return movie.main(argv[1:])
    args = _parser().parse_args(argv)
    labels = args.labels.split(",") if args.labels else None
    if labels is not None and len(labels) != len(args.dirs):
        _parser().error(f"--labels has {len(labels)} label(s) for {len(args.dirs)} director(ies)")
    try:
        runs = [read_run(d) for d in args.dirs]
    except (OSError, ValueError) as err:
        print(f"{PROG}: {err}", file=sys.stderr)
        return 1
    if labels is None:
        labels = [r.name for r in runs]
    out = Path(args.out) if args.out else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    used: set[str] = set()
    for run, label in zip(runs, labels):
        if out is None:
            place = lambda stem, ext, run=run: run.directory / f"{stem}.{ext}"  # noqa: E731
        else:
            tag = _file_label(label)
            while tag in used:
                tag += "_"
            used.add(tag)
            place = lambda stem, ext, tag=tag: out / f"{stem}_{tag}.{ext}"  # noqa: E731
        if figures.is_prescribed(run):  # the rig's motion and the loads, not a beam's response
            _attempt(f"motion of {label}", lambda: figures.motion(run, place("motion", "png"), label), written)
            _attempt(f"wall_loads of {label}", lambda: figures.wall_loads(run, place("wall_loads", "png"), label),
                     written)
        else:
            _attempt(f"damping.csv of {label}", lambda: _damping_csv(run, place("damping", "csv")), written)
            _attempt(f"tip_acceleration of {label}",
                     lambda: figures.tip_acceleration(run, place("tip_acceleration", "png"), label), written)
        _attempt(f"energy_terms of {label}", lambda: figures.energy_terms(run, place("energy_terms", "png")), written)
        _attempt(f"snapshots of {label}", lambda: figures.snapshots(run, place("snapshots", "png"), field=args.field), written)
        if run.probes:
            _attempt(f"probes of {label}", lambda: figures.probes(run, place("probes", "png")), written)
    beams = [(r, lab) for r, lab in zip(runs, labels) if not figures.is_prescribed(r)]
    common = out if out is not None else runs[0].directory
    for name in ("normalized_motion", "acceleration_envelope", "damping_vs_amplitude") if beams else ():
        make = getattr(figures, name)
        _attempt(name, lambda: make([r for r, _ in beams], [lab for _, lab in beams], common / f"{name}.png"), written)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())

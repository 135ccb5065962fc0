"""Reading a flexslosh output directory into numpy arrays.

A run (``-fs_output_dir DIR``) leaves in DIR:

- ``timeseries.csv``: a header ``step,time,dt,dt_limit,...`` and one row per step (required);
- ``energy.csv``: the energy budget, one row per step (``step,time,E_kin,E_pot,...``);
- ``summary.json``: what ran (particles, ranks, steps, the structure, the options);
- ``snapshots.csv`` + ``snapshot_NNNNNN.h5``: particle snapshots, HDF5 group ``/particles`` with the
  datasets position, velocity, density, pressure, strain_rate, turbulent_viscosity, rank, id and
  the attributes time, step, dim, nparticles;
- ``beam_shape_NNNNNN.csv`` (modal beam): ``# time T step N``, then ``x,w,rotation`` at the nodes.

``read_run`` gathers them in a :class:`Run`; ``read_csv`` and ``read_snapshot`` read one file. Every
reader raises ``FileNotFoundError`` or ``ValueError`` with the file's path and what is wrong (a
missing file, a row with the wrong number of fields, a value that is not a number), never a bare
numpy error. The C code writes every file under a temporary name and renames it when complete, and
flushes one whole row of a CSV at a time, so a malformed row means a damaged file, or the torn last
line of a run that crashed or is still running (``allow_partial_last_row`` drops that one).
"""
from __future__ import annotations

import glob
import json
import os
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence, Union

import numpy as np


def code_revision(exclude: Sequence[str] = ()) -> str:
    """The checkout's commit (short hash, "+dirty" when tracked files under it differ from it, the paths in
    ``exclude`` left out), or "unknown" outside a git checkout: the stamp of a run's results."""
    root = str(Path(__file__).resolve().parents[2])
    try:
        head = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no", "--", "."]
                               + [f":(exclude){e}" for e in exclude], capture_output=True, text=True, timeout=10).stdout.strip()
        return (head + ("+dirty" if dirty else "")) if head else "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"

__all__ = ["Run", "Snapshot", "read_run", "read_csv", "read_snapshot", "SNAPSHOT_FIELDS"]

PathLike = Union[str, "os.PathLike[str]"]

#: The datasets of a snapshot's /particles group.
SNAPSHOT_FIELDS = ("position", "velocity", "density", "pressure", "strain_rate", "turbulent_viscosity", "rank", "id")


def _parse_column(values: np.ndarray) -> np.ndarray:
    """A column of strings as int64 when every value is an integer, else float64 (raises ValueError)."""
    try:
        return values.astype(np.int64)
    except (ValueError, OverflowError):
        return values.astype(np.float64)


def read_csv(path: PathLike, text_columns: Sequence[str] = (), allow_partial_last_row: bool = False) -> dict[str, np.ndarray]:
    """Reads a CSV file with a header line into columns.

    Lines starting with ``#`` before the header (the beam shapes' ``# time T step N``) are skipped.
    A column whose values are all integers is int64 (``step``), the other numeric ones float64.

    Args:
        path: the file.
        text_columns: columns kept as strings (e.g. ``file`` in snapshots.csv); every other column
            must hold numbers.
        allow_partial_last_row: drop a last row that is incomplete and lacks its newline (the torn
            line of a run that crashed or is still writing) instead of raising ValueError.

    Returns:
        Column name -> 1-D array, in the header's order (zero-length arrays when there is no row).

    Raises:
        FileNotFoundError: the file does not exist.
        ValueError: the file is empty, its header repeats a name, a row has the wrong number of
            fields, or a value is not a number; the message names the file and the line.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    with open(path, newline="") as fp:
        lines = fp.read().split("\n")
    lineno = 0
    while lineno < len(lines) and lines[lineno].startswith("#"):
        lineno += 1
    if lineno >= len(lines) or not lines[lineno].strip():
        raise ValueError(f"{path}: empty file (no header line)")
    header = [h.strip() for h in lines[lineno].rstrip("\r").split(",")]
    if len(set(header)) != len(header) or "" in header:
        raise ValueError(f"{path}: malformed header line {lineno + 1}: {lines[lineno][:200]!r}")
    rows: list[list[str]] = []
    linenos: list[int] = []  # the file's line number of each row
    torn_last = len(lines[-1]) > 0  # the file does not end with a newline
    for k in range(lineno + 1, len(lines)):
        line = lines[k]
        if not line.strip():
            continue
        rows.append(line.rstrip("\r").split(","))
        linenos.append(k + 1)
    numeric = [c for c, name in enumerate(header) if name not in text_columns]
    if rows and torn_last and allow_partial_last_row:
        last = rows[-1]
        if len(last) != len(header) or not all(_is_number(last[c]) for c in numeric):
            rows.pop()
            linenos.pop()
    for fields, n in zip(rows, linenos):
        if len(fields) != len(header):
            what = "a partially written last row" if n == linenos[-1] and torn_last else "a malformed row"
            raise ValueError(f"{path}: line {n} has {len(fields)} fields, the header has {len(header)} ({what})")
    table = np.array(rows, dtype=str).reshape(len(rows), len(header))
    out: dict[str, np.ndarray] = {}
    for c, name in enumerate(header):
        if c not in numeric:
            out[name] = table[:, c]
            continue
        try:
            out[name] = _parse_column(table[:, c])
        except ValueError:
            bad = next(r for r in range(len(rows)) if not _is_number(rows[r][c]))
            raise ValueError(f"{path}: line {linenos[bad]}, column {name!r}: {rows[bad][c]!r} is not a number") from None
    return out


def _is_number(text: str) -> bool:
    """Whether float() reads text."""
    try:
        float(text)
    except ValueError:
        return False
    return True


class Snapshot(dict):
    """A particle snapshot: field name -> numpy array, rows sorted by particle id.

    Attributes:
        path: the HDF5 file.
        attrs: the attributes of /particles (time, step, dim, nparticles).
        time: the simulated time.
        step: the time step.
        dim: the dimension (2 or 3); position and velocity have dim columns.
    """

    path: Path
    attrs: dict[str, Any]

    @property
    def time(self) -> float:
        return float(self.attrs["time"])

    @property
    def step(self) -> int:
        return int(self.attrs["step"])

    @property
    def dim(self) -> int:
        return int(self.attrs["dim"])


def read_snapshot(path: PathLike) -> Snapshot:
    """Reads a particle snapshot ``snapshot_NNNNNN.h5``.

    Args:
        path: the HDF5 file.

    Returns:
        A :class:`Snapshot` (a dict) with the fields of :data:`SNAPSHOT_FIELDS` (position and velocity
        (n, dim), the others (n,)), every row sorted by ``id``, and the attributes time, step, dim.

    Raises:
        FileNotFoundError: the file does not exist.
        ValueError: it is not HDF5, has no /particles group, lacks a field or an attribute, or its
            fields disagree in length.
    """
    import h5py  # lazily: only snapshots need it

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    snap = Snapshot()
    try:
        h5 = h5py.File(path, "r")
    except OSError as err:
        raise ValueError(f"{path}: not a readable HDF5 file ({err})") from None
    with h5:
        if "particles" not in h5:
            raise ValueError(f"{path}: no /particles group (not a flexslosh snapshot)")
        grp = h5["particles"]
        missing = [f for f in SNAPSHOT_FIELDS if f not in grp]
        if missing:
            raise ValueError(f"{path}: /particles lacks the field(s) {', '.join(missing)}")
        attrs = {k: (v.item() if hasattr(v, "item") else v) for k, v in grp.attrs.items()}
        for a in ("time", "step", "dim"):
            if a not in attrs:
                raise ValueError(f"{path}: /particles lacks the attribute {a!r}")
        ids = grp["id"][...]
        n = len(ids)
        if "nparticles" in attrs and int(attrs["nparticles"]) != n:
            raise ValueError(f"{path}: /particles/id has {n} rows, the attribute nparticles says {attrs['nparticles']}")
        order = np.argsort(ids, kind="stable")
        for name, dset in grp.items():
            data = dset[...]
            if len(data) != n:
                raise ValueError(f"{path}: /particles/{name} has {len(data)} rows, /particles/id {n}")
            snap[name] = data[order]
    snap.attrs = attrs
    snap.path = path
    return snap


@dataclass
class Run:
    """A flexslosh output directory, read.

    Attributes:
        directory: the output directory.
        timeseries: timeseries.csv, column name -> 1-D array (one row per step).
        energy: energy.csv, column name -> 1-D array; empty when the run wrote none.
        summary: summary.json; empty when the run did not finish writing it.
        snapshots: (time, path) of each particle snapshot, in time order.
        beam_shapes: the beam_shape_NNNNNN.csv files (modal beam), in step order.
        probes: probes.csv (-fs_probes), column name (with its unit, e.g. "p1_pressure[Pa]") -> 1-D
            array; empty when the run had no probes.
    """

    directory: Path
    timeseries: dict[str, np.ndarray]
    energy: dict[str, np.ndarray] = field(default_factory=dict)
    summary: dict[str, Any] = field(default_factory=dict)
    snapshots: list[tuple[float, Path]] = field(default_factory=list)
    beam_shapes: list[Path] = field(default_factory=list)
    probes: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def name(self) -> str:
        """The directory's name (the default label in figures)."""
        return self.directory.name

    @property
    def particles(self) -> int:
        """The number of particles (summary.json, else the first snapshot's, else 0)."""
        if "particles" in self.summary:
            return int(self.summary["particles"])
        if self.snapshots:
            return len(read_snapshot(self.snapshots[0][1])["id"])
        return 0

    def column(self, name: str, table: str = "timeseries") -> np.ndarray:
        """A column of timeseries.csv (table="timeseries"), energy.csv ("energy") or probes.csv ("probes").

        Raises:
            ValueError: the file has no such column (the message names the file and the column).
        """
        data = {"timeseries": self.timeseries, "energy": self.energy, "probes": self.probes}[table]
        if name not in data:
            what = f"no {table}.csv" if table != "timeseries" and not data else f"no column {name!r}"
            hint = " (a run without a structure?)" if name.startswith(("tip_", "tank_", "load_")) else ""
            raise ValueError(f"{self.directory / (table + '.csv')}: {what}{hint}")
        return data[name]

    def dt_limits(self) -> np.ndarray:
        """What set each step's dt: timeseries.csv's ``dt_limit`` codes as names ("acoustic", "viscous",
        "skin", "body_force", "structure", "final_time", "integrator", or a term's name such as "delta"
        for its diffusivity), one per row, in the order of summary.json's ``dt_limit_steps``.

        Raises:
            ValueError: the run has no dt_limit column or no summary.json to name the codes.
        """
        codes = self.column("dt_limit")
        if "dt_limit_steps" not in self.summary:
            raise ValueError(f"{self.directory / 'summary.json'}: no dt_limit_steps to name the dt_limit codes")
        names = list(self.summary["dt_limit_steps"])
        return np.array([names[int(c)] if 0 <= int(c) < len(names) else "unknown" for c in codes])


def _snapshot_index(directory: Path) -> list[tuple[float, Path]]:
    index = directory / "snapshots.csv"
    if index.is_file():
        cols = read_csv(index, text_columns=("file", "fields"))
        for need in ("time", "file"):
            if need not in cols:
                raise ValueError(f"{index}: no column {need!r}")
        entries = [(float(t), directory / str(f)) for t, f in zip(cols["time"], cols["file"])]
    else:
        import h5py

        entries = []
        for name in sorted(glob.glob(str(directory / "snapshot_[0-9]*.h5"))):
            with h5py.File(name, "r") as h5:
                entries.append((float(h5["particles"].attrs["time"]), Path(name)))
    return sorted(entries, key=lambda e: e[0])


def read_run(directory: PathLike, allow_partial_last_row: bool = False) -> Run:
    """Reads a flexslosh output directory.

    Args:
        directory: the run's ``-fs_output_dir``.
        allow_partial_last_row: see :func:`read_csv` (for a run still writing its CSV files).

    Returns:
        The :class:`Run`; snapshots are listed, not read (see :func:`read_snapshot`).

    Raises:
        FileNotFoundError: the directory or its timeseries.csv does not exist.
        ValueError: a file is malformed (see :func:`read_csv`), or summary.json is not JSON.
    """
    directory = Path(directory)
    if not directory.is_dir():
        raise FileNotFoundError(f"{directory}: no such directory")
    ts = directory / "timeseries.csv"
    if not ts.is_file():
        raise FileNotFoundError(f"{ts}: no such file ({directory} is not a flexslosh output directory)")
    run = Run(directory=directory, timeseries=read_csv(ts, allow_partial_last_row=allow_partial_last_row))
    if (directory / "energy.csv").is_file():
        run.energy = read_csv(directory / "energy.csv", allow_partial_last_row=allow_partial_last_row)
    summary = directory / "summary.json"
    if summary.is_file():
        try:
            run.summary = json.loads(summary.read_text())
        except json.JSONDecodeError as err:
            raise ValueError(f"{summary}: not valid JSON ({err})") from None
    if (directory / "probes.csv").is_file():
        run.probes = read_csv(directory / "probes.csv", allow_partial_last_row=allow_partial_last_row)
    run.snapshots = _snapshot_index(directory)
    run.beam_shapes = [Path(p) for p in sorted(glob.glob(str(directory / "beam_shape_[0-9]*.csv")))]
    return run

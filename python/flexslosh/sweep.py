"""Parameter sweeps: many runs (fill levels, tank shapes, structures...) and the damping of each.

``sweep(cases, base_options)`` runs every case (a dict of options over ``base_options``) and measures
the damping per cycle of the tank's free decay (``flexslosh.damping.damping_per_cycle`` on the tip
displacement) into one table, one row per case and cycle, written to ``<output_root>/damping.csv``::

    from flexslosh.sweep import sweep
    cases = [{"fs_fill": f, "fs_tank_shape": s} for s in ("rectangular", "baffled") for f in (0.3, 0.5)]
    table = sweep(cases, base_options={"options_file": "cases/coupled_rectangular.opts", "ts_max_time": 1})

With ``comm`` (an mpi4py communicator, e.g. MPI.COMM_WORLD) the cases are spread over its ranks, case k
on rank k % size, each run alone on MPI.COMM_SELF, and the rows gathered to rank 0; without it the
cases run one after the other, each on PETSC_COMM_WORLD. Both give the same table.
"""
from __future__ import annotations

import csv
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .damping import damping_per_cycle
from .solver import Solver, initialize

__all__ = ["sweep", "run_case", "write_table", "format_table", "assign"]

_COLUMNS = ("case", "cycle", "time", "amplitude", "period", "delta", "zeta")


def _key(name: str) -> str:
    return name[1:] if name.startswith("-") else name


def run_case(options: Mapping[str, Any], comm=None, signal: str = "tip_displacement", offset: float = 0.0):
    """Runs one case to its end and returns (times, signal values, CycleDamping). options may hold
    "options_file". signal: tip_displacement, tip_velocity or tip_acceleration (the tank's motion
    along y), or any callable(solver) -> float."""
    opts = dict(options)
    options_file = opts.pop("options_file", None)
    part = {"tip_displacement": "disp", "tip_velocity": "vel", "tip_acceleration": "acc"}
    if callable(signal):
        measure = signal
    elif signal in part:
        measure = lambda s: s.tank_motion()[part[signal]][1]  # noqa: E731
    else:
        raise ValueError(f"unknown signal {signal!r}: expected one of {sorted(part)} or a callable")
    with Solver(opts, options_file=options_file, comm=comm) as s:
        s.set_up()
        t, y = [s.time], [measure(s)]

        def record(solver):
            t.append(solver.time)
            y.append(measure(solver))

        s.run(callback=record)
    t, y = np.array(t), np.array(y)
    return t, y, damping_per_cycle(t, y, offset)


def _rows(index: int, params: Mapping[str, Any], result) -> list[dict]:
    d = result.as_array()
    return [dict({"case": index}, **params, cycle=k, time=row[0], amplitude=row[1], period=row[2], delta=row[3], zeta=row[4])
            for k, row in enumerate(d)]


def _table(rows: list[dict], names: Sequence[str]) -> np.ndarray:
    """The rows as a structured array: case, the parameters (float where every value is a number, else
    text), cycle, time, amplitude, period, delta, zeta."""
    dtype, numeric = [("case", np.int64)], {}
    for name in names:
        values = [r[name] for r in rows if name in r]
        numeric[name] = all(isinstance(v, (int, float, np.number)) and not isinstance(v, bool) for v in values)
        dtype.append((name, np.float64 if numeric[name] else f"U{max([len(str(v)) for v in values] + [1])}"))
    dtype += [("cycle", np.int64)] + [(c, np.float64) for c in _COLUMNS[2:]]
    out = np.zeros(len(rows), dtype=dtype)
    for k, r in enumerate(rows):
        params = tuple(r.get(n, np.nan) if numeric[n] else str(r.get(n, "")) for n in names)
        out[k] = (r["case"],) + params + tuple(r[c] for c in _COLUMNS[1:])
    return out


def write_table(table: np.ndarray, path: str | os.PathLike) -> Path:
    """Writes a sweep's table to CSV (a header row of the field names, then one row per case and cycle)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fp:
        w = csv.writer(fp)
        w.writerow(table.dtype.names)
        for row in table:
            w.writerow([repr(float(v)) if isinstance(v, (float, np.floating)) else v for v in row.tolist()])
    return path


def format_table(table: np.ndarray, columns: Sequence[str] | None = None) -> str:
    """A sweep's table (or the named columns of it) as aligned text, a header line then one line per row."""
    columns = list(columns or table.dtype.names)
    cells = [[f"{v:.6g}" if isinstance(v, (float, np.floating)) else str(v) for v in (row[c] for c in columns)] for row in table]
    widths = [max([len(c)] + [len(r[k]) for r in cells]) for k, c in enumerate(columns)]
    return "\n".join("  ".join(v.rjust(w) for v, w in zip(line, widths)) for line in [columns] + cells)


def assign(n: int, comm=None) -> tuple[range, Any, int]:
    """The share of n runs this process makes: (the indices, the communicator each run gets, this rank).
    comm None: all of them, one after the other on PETSC_COMM_WORLD (None), rank its rank there; an mpi4py
    communicator: run k on rank k % size, each alone on MPI.COMM_SELF."""
    if comm is None:
        return range(n), None, initialize().PETSc.COMM_WORLD.getRank()
    from mpi4py import MPI

    rank, size = comm.Get_rank(), comm.Get_size()
    return range(rank, n, size), MPI.COMM_SELF, rank


def sweep(cases: Sequence[Mapping[str, Any]], base_options: Mapping[str, Any] | None = None, comm=None,
          output_root: str | os.PathLike = "output/sweep", signal: str = "tip_displacement", offset: float = 0.0,
          csv_name: str | None = "damping.csv") -> np.ndarray | None:
    """Runs every case and tabulates the damping per cycle of each.

    Args:
        cases: one dict of options per case (keys as in Solver; "options_file" allowed); they win
            over base_options. The keys of the cases become the table's parameter columns.
        base_options: the options every case shares.
        comm: None: the cases one after the other in this process group (each on PETSC_COMM_WORLD);
            an mpi4py communicator: case k on rank k % size, alone (MPI.COMM_SELF), the rows gathered
            to rank 0.
        output_root: each case writes into <output_root>/case_<k> (unless it sets fs_output_dir); the
            table goes to <output_root>/<csv_name> (csv_name None: not written).
        signal, offset: what is measured (see run_case) and the value it oscillates about.

    Returns:
        On rank 0 the table, a numpy structured array with the fields case, the parameters, cycle, time,
        amplitude, period, delta, zeta (one row per case and cycle, in case order); None on the other
        ranks.
    """
    base = {_key(k): v for k, v in (base_options or {}).items()}
    names: list[str] = []
    for case in cases:
        for k in case:
            if _key(k) not in names:
                names.append(_key(k))
    mine, run_comm, rank = assign(len(cases), comm)
    rows: list[dict] = []
    for k in mine:
        params = {_key(n): v for n, v in cases[k].items()}
        opts = dict(base, **params)
        opts.setdefault("fs_output_dir", str(Path(output_root) / f"case_{k:03d}"))
        _, _, result = run_case(opts, comm=run_comm, signal=signal, offset=offset)
        rows += _rows(k, params, result)
    if comm is not None:
        gathered = comm.gather(rows, root=0)
        rows = [r for part in gathered for r in part] if rank == 0 else []
    if rank != 0:
        return None
    rows.sort(key=lambda r: (r["case"], r["cycle"]))
    table = _table(rows, names)
    if csv_name:
        write_table(table, Path(output_root) / csv_name)
    return table

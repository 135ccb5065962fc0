"""An animation of a run: the particles coloured by a field, the walls, the time and the tip's motion.

Usage::

    python3 -m flexslosh.plot movie OUTPUT_DIR [--field NAME] [--output FILE] [--fps N] [--every N]
                                              [--frame K] [--slice Z]

Each frame is one particle snapshot (``snapshots.csv``): the particles, in the tank's frame, coloured
by ``--field`` on one colour scale for the whole movie, the walls (``walls.h5``, which every run with
walls writes beside its snapshots), the time in the title and, for a run with a structure, a panel
of the tip's displacement (``tip_displacement`` of timeseries.csv) with a marker at the frame's
time. A 3-D run is shown as a slice: the particles within one particle spacing of the plane
z = ``--slice`` (default the middle of the walls' or the particles' box) and the walls cut by it.

The movie is MP4 through matplotlib's ffmpeg writer when ffmpeg is installed, GIF through its Pillow
writer otherwise (or when FILE ends in ``.gif``). ``--frame K`` writes snapshot K alone as a PNG
instead (negative K counts from the end). matplotlib is imported inside the functions (Agg canvas,
no pyplot).
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from .figures import _UNITS, _figure
from .output import Run, Snapshot, read_run, read_snapshot

__all__ = ["FIELDS", "movie", "frame", "read_walls", "field_values", "main"]

PathLike = Union[str, "os.PathLike[str]"]

PROG = "python3 -m flexslosh.plot movie"

#: The fields a movie can show: name -> what it is (vectors by their magnitude or one component).
FIELDS = {
    "velocity": "speed |u|",
    "velocity_x": "velocity, x component",
    "velocity_y": "velocity, y component",
    "velocity_z": "velocity, z component (3-D)",
    "pressure": "pressure",
    "density": "density",
    "strain_rate": "strain rate ||D||",
    "turbulent_viscosity": "Smagorinsky viscosity",
    "rank": "MPI rank",
}

_LOG_FIELDS = ("strain_rate", "turbulent_viscosity")  # drawn on a log scale, as in figures.snapshots


def _check_field(field: str) -> None:
    """Raises ValueError naming field and the choices when field is not one of FIELDS."""
    if field not in FIELDS:
        raise ValueError(f"unknown field {field!r}: choose one of {', '.join(FIELDS)}")


def field_values(snap: Snapshot, field: str) -> np.ndarray:
    """The values of field at the particles of snap (one per particle).

    Args:
        snap: a snapshot (read_snapshot).
        field: one of :data:`FIELDS`.

    Raises:
        ValueError: field is not one of FIELDS (the message names the choices), or velocity_z in 2-D.
    """
    _check_field(field)
    if field.startswith("velocity_"):
        axis = "xyz".index(field[-1])
        if axis >= snap.dim:
            raise ValueError(f"field {field!r}: the run is {snap.dim}-D")
        return np.asarray(snap["velocity"][:, axis], dtype=float)
    v = np.asarray(snap[field], dtype=float)
    return np.linalg.norm(v, axis=1) if v.ndim == 2 else v


def read_walls(directory: PathLike) -> Optional[dict[str, Any]]:
    """The walls of a run (``walls.h5``), or None when the run wrote none (a case without walls).

    Returns:
        ``{"dim": 2 or 3, "elements": (nel, nodes, dim) array, "wall": (nel,) wall index, "names": [...]}``:
        segments (nodes = 2) in 2-D, the walls' triangles as given (nodes = 3) in 3-D.
    """
    import h5py

    path = Path(directory) / "walls.h5"
    if not path.is_file():
        return None
    with h5py.File(path, "r") as h5:
        grp = h5["walls"]
        points = grp["points"][...]
        conn = grp["connectivity"][...].astype(np.int64)
        wall = grp["wall"][...].astype(np.int64)
        names = grp.attrs.get("names", b"")
    names = names.decode() if isinstance(names, bytes) else str(names)
    return {"dim": points.shape[1], "elements": points[conn], "wall": wall, "names": names.split(",") if names else []}


def _slice_triangles(tri: np.ndarray, z: float) -> np.ndarray:
    """The segments (k, 2, 2) in x, y where the plane z = const cuts the triangles tri (n, 3, 3)."""
    d = tri[:, :, 2] - z
    segs = []
    for t, dz in zip(tri, d):
        pts = []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            if (dz[a] < 0) != (dz[b] < 0):  # the edge crosses the plane
                s = dz[a] / (dz[a] - dz[b])
                pts.append(t[a, :2] + s * (t[b, :2] - t[a, :2]))
        if len(pts) == 2:
            segs.append(pts)
    return np.array(segs, dtype=float).reshape(-1, 2, 2)


class _Movie:
    """The figure of a run's movie and the routine that draws snapshot k into it."""

    def __init__(self, run: Run, field: str, slice_z: Optional[float], dpi: int) -> None:
        from matplotlib.collections import LineCollection
        from matplotlib.colors import LogNorm, Normalize

        _check_field(field)
        if not run.snapshots:
            raise ValueError(f"{run.directory}: no particle snapshots (snapshots.csv / snapshot_*.h5)")
        self.run, self.field = run, field
        self.snaps = [read_snapshot(p) for _, p in run.snapshots]
        dim = self.snaps[0].dim
        walls = read_walls(run.directory)
        segs = np.zeros((0, 2, 2))
        box = np.concatenate([s["position"] for s in self.snaps])
        if walls is not None:
            box = np.concatenate([box, walls["elements"].reshape(-1, dim)])
        lo, hi = box.min(axis=0), box.max(axis=0)
        self.dx = float(run.summary.get("dx", 0)) or float(np.sqrt(np.prod(hi[:2] - lo[:2]) / max(len(self.snaps[0]["id"]), 1)))
        self.slice_z = None
        if dim == 3:
            self.slice_z = 0.5 * (lo[2] + hi[2]) if slice_z is None else float(slice_z)
        if walls is not None:
            segs = walls["elements"] if dim == 2 else _slice_triangles(walls["elements"], self.slice_z)
        values = [field_values(s, field)[self._visible(s)] for s in self.snaps]
        allv = np.concatenate(values) if values else np.zeros(0)
        vmin, vmax = (float(allv.min()), float(allv.max())) if len(allv) else (0.0, 1.0)
        if field in _LOG_FIELDS:
            vmax = max(vmax, 1e-12)
            self.norm = LogNorm(vmin=max(1e-4 * vmax, float(allv[allv > 0].min()) if np.any(allv > 0) else 1e-4 * vmax),
                                vmax=vmax, clip=True)
        else:
            self.norm = Normalize(vmin=vmin, vmax=vmax if vmax > vmin else vmin + 1)

        # the layout: the tank on top, the tip's motion below when the run has a structure
        pad = 0.03 * max(hi[0] - lo[0], hi[1] - lo[1])
        x0, x1, y0, y1 = lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad
        width = 8.0
        tank_h = min(max(width * (y1 - y0) / (x1 - x0), 1.5), 6.0)
        self.tip = "tip_displacement" in run.timeseries
        fig = _figure(width + 1.4, tank_h + (1.8 if self.tip else 0) + 0.8, layout="constrained")
        fig.set_dpi(dpi)
        if self.tip:
            ax, axt = fig.subplots(2, 1, height_ratios=[tank_h, 1.6])
        else:
            ax, axt = fig.subplots(1, 1), None
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        size = (0.9 * self.dx / (x1 - x0) * width * 72) ** 2  # marker area (points^2): about one spacing
        self.scatter = ax.scatter(np.zeros(0), np.zeros(0), c=np.zeros(0), s=size, norm=self.norm, cmap="viridis",
                                  marker="s", linewidths=0)
        if len(segs):
            ax.add_collection(LineCollection(segs, colors="0.15", linewidths=1.5))
        label = FIELDS[field] + f" ({_UNITS.get(field.split('_')[0] if field.startswith('velocity') else field, '-')})"
        fig.colorbar(self.scatter, ax=ax, label=label, fraction=0.04, pad=0.02)
        if axt is not None:
            t = run.column("time")
            w = 1e3 * run.column("tip_displacement")
            axt.plot(t, w, color="tab:blue", lw=1)
            axt.axhline(0, color="0.6", lw=0.6)
            axt.set_xlabel("t (s)")
            axt.set_ylabel("tip displacement (mm)")
            axt.set_xlim(t[0], t[-1] if len(t) and t[-1] > t[0] else t[0] + 1)
            (self.marker,) = axt.plot([], [], "o", color="tab:red", ms=7)
            self.cursor = axt.axvline(0, color="tab:red", lw=0.8)
            self.tip_t, self.tip_w = t, w
        self.fig, self.ax = fig, ax
        where = f", slice z = {self.slice_z:.4g} m" if self.slice_z is not None else ""
        self.title = f"{run.name}: {FIELDS[field]}{where}"

    def _visible(self, snap: Snapshot) -> np.ndarray:
        """The particles drawn: all in 2-D, those within one spacing of the slice in 3-D."""
        if snap.dim == 2:
            return np.ones(len(snap["id"]), dtype=bool)
        return np.abs(snap["position"][:, 2] - self.slice_z) <= self.dx

    def draw(self, k: int) -> None:
        """Draws snapshot k into the figure."""
        snap = self.snaps[k]
        keep = self._visible(snap)
        self.scatter.set_offsets(snap["position"][keep, :2])
        self.scatter.set_array(field_values(snap, self.field)[keep])
        self.ax.set_title(f"{self.title}, t = {snap.time:.3f} s", fontsize="medium")
        if self.tip:
            w = float(np.interp(snap.time, self.tip_t, self.tip_w))
            self.marker.set_data([snap.time], [w])
            self.cursor.set_xdata([snap.time, snap.time])


def _run(run_or_dir: Union[Run, PathLike]) -> Run:
    return run_or_dir if isinstance(run_or_dir, Run) else read_run(run_or_dir, allow_partial_last_row=True)


def movie(run_or_dir: Union[Run, PathLike], path: Optional[PathLike] = None, field: str = "velocity", fps: float = 10,
          every: int = 1, slice_z: Optional[float] = None, dpi: int = 100) -> Path:
    """Writes the animation of a run's snapshots.

    Args:
        run_or_dir: a Run (read_run) or its output directory.
        path: the file; its suffix chooses the writer (``.mp4`` ffmpeg, ``.gif`` Pillow). None:
            ``movie.mp4`` in the run's directory when ffmpeg is installed, ``movie.gif`` otherwise.
        field: one of :data:`FIELDS`.
        fps: frames per second.
        every: use every N-th snapshot (the first is always used).
        slice_z: 3-D runs: the plane shown (None: the middle of the box).
        dpi: pixels per inch of the frames.

    Returns:
        The path written (under a temporary name first, renamed when complete).

    Raises:
        ValueError: an unknown field (the message lists the choices), every < 1, no snapshots,
            an ``.mp4`` without ffmpeg or another suffix.
    """
    from matplotlib import animation

    _check_field(field)
    if every < 1:
        raise ValueError(f"every must be 1 or more, not {every}")
    run = _run(run_or_dir)
    ffmpeg = animation.writers.is_available("ffmpeg") and shutil.which("ffmpeg") is not None
    path = Path(path) if path is not None else run.directory / ("movie.mp4" if ffmpeg else "movie.gif")
    suffix = path.suffix.lower()
    if suffix == ".mp4" and not ffmpeg:
        raise ValueError(f"{path}: MP4 needs ffmpeg, which is not installed; write a .gif instead")
    if suffix not in (".mp4", ".gif"):
        raise ValueError(f"{path}: the movie is .mp4 (ffmpeg) or .gif (Pillow)")
    mv = _Movie(run, field, slice_z, dpi)
    writer = animation.FFMpegWriter(fps=fps) if suffix == ".mp4" else animation.PillowWriter(fps=fps)
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)  # the writers pick the format from the suffix
    with writer.saving(mv.fig, str(tmp), dpi):
        for k in range(0, len(mv.snaps), every):
            mv.draw(k)
            writer.grab_frame()
    os.replace(tmp, path)
    return path


def frame(run_or_dir: Union[Run, PathLike], k: int, path: Optional[PathLike] = None, field: str = "velocity",
          slice_z: Optional[float] = None, dpi: int = 100) -> Path:
    """Writes snapshot k of a run as the movie would show it, as a PNG.

    Args:
        run_or_dir: a Run or its output directory.
        k: the snapshot's index in snapshots.csv (negative: from the end).
        path: the PNG (None: ``frame_<k>.png`` in the run's directory).
        field, slice_z, dpi: as in :func:`movie`.

    Raises:
        ValueError: an unknown field, no snapshots, or k out of range.
    """
    _check_field(field)
    run = _run(run_or_dir)
    n = len(run.snapshots)
    if not -n <= k < n:
        raise ValueError(f"{run.directory}: snapshot {k} out of range (the run has {n} snapshot(s))")
    k %= n
    mv = _Movie(run, field, slice_z, dpi)
    mv.draw(k)
    path = Path(path) if path is not None else run.directory / f"frame_{k}.png"
    tmp = path.with_name(path.name + ".tmp")
    mv.fig.savefig(tmp, format="png", dpi=dpi)
    os.replace(tmp, path)
    return path


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=PROG, description="Writes an animation (MP4 with ffmpeg, else GIF) of a flexslosh "
                                "run's particles coloured by a field, with the walls, the time and the tip's motion.")
    p.add_argument("dir", metavar="OUTPUT_DIR", help="a flexslosh output directory (-fs_output_dir) with snapshots")
    p.add_argument("--field", default="velocity", help=f"the colour: one of {', '.join(FIELDS)} (default velocity)")
    p.add_argument("--output", metavar="FILE", help="the movie (.mp4 or .gif) or, with --frame, the PNG "
                   "(default OUTPUT_DIR/movie.mp4, or movie.gif without ffmpeg; OUTPUT_DIR/frame_K.png)")
    p.add_argument("--fps", type=float, default=10, help="frames per second (default 10)")
    p.add_argument("--every", type=int, default=1, metavar="N", help="use every N-th snapshot (default 1)")
    p.add_argument("--frame", type=int, metavar="K", help="write snapshot K (negative: from the end) as a PNG instead")
    p.add_argument("--slice", type=float, metavar="Z", dest="slice_z",
                   help="3-D: show the plane z = Z (default the middle of the box)")
    p.add_argument("--dpi", type=int, default=100, help="pixels per inch (default 100)")
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Runs ``python3 -m flexslosh.plot movie``.

    Args:
        argv: the arguments after ``movie`` (default: sys.argv[2:]).

    Returns:
        The exit status: 0, 1 when the run cannot be read or drawn, 2 on bad usage (argparse, or an
        unknown --field).
    """
    parser = _parser()
    args = parser.parse_args(argv if argv is not None else sys.argv[2:])
    if args.field not in FIELDS:
        parser.error(f"argument --field: unknown field {args.field!r}: choose one of {', '.join(FIELDS)}")
    try:
        if args.frame is not None:
            path = frame(args.dir, args.frame, args.output, args.field, args.slice_z, args.dpi)
        else:
            path = movie(args.dir, args.output, args.field, args.fps, args.every, args.slice_z, args.dpi)
    except (OSError, ValueError) as err:
        print(f"{PROG}: {err}", file=sys.stderr)
        return 1
    if not (Path(args.dir) / "walls.h5").is_file():
        print(f"note: {args.dir} has no walls.h5 (a case without walls): none drawn", file=sys.stderr)
    print(path)
    return 0

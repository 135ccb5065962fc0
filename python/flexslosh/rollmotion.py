"""The measured roll of SPHERIC test 10 (lateral impact, water), rebuilt from windows of the record.

The experiment's roll angle is public as a 20 kHz, spline-smoothed record (8.35 s, 3.2 MB; see
cases/data/README.md). This repository keeps only short windows of it, each a few rows 0.04 s long
(cases/data/spheric10_roll_samples.txt, the values as recorded), about every 0.7 s. Each window gives
the angle and its first two derivatives at the window's centre (a polynomial through its rows); between
two centres the angle is the quintic Hermite polynomial that matches those three values at both ends.
The first window starts at t = 0 and its polynomial is used before its centre; the last window's
polynomial is used after its centre. A window left out of the reconstruction (2.80-2.84 s, before it was
added) was matched to 0.04 degrees (1 % of the 4 degree amplitude).

``python3 -m flexslosh.rollmotion`` writes cases/data/spheric10_roll.txt (time, degrees, every 5 ms),
the file cases/roll_tank.opts reads with ``-fs_motion_roll_file``.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Sequence

import numpy as np

__all__ = ["window_nodes", "reconstruct", "write_roll_file", "SAMPLES", "ROLL_FILE"]

REPO = Path(__file__).resolve().parents[2]
SAMPLES = REPO / "cases" / "data" / "spheric10_roll_samples.txt"
ROLL_FILE = REPO / "cases" / "data" / "spheric10_roll.txt"
WINDOW_GAP = 0.1  # rows closer than this (s) to the previous row belong to the same window


def window_nodes(t: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """The windows' centres with the angle and its first two derivatives there.

    Args:
        t: the sample times (s), increasing.
        a: the angles there.

    Returns:
        (nodes, polys): nodes is an array of rows (centre, a, a', a''); polys[i] is the polynomial
        (numpy.polyfit coefficients in t - centre) of window i, of degree min(4, rows - 1).
    """
    starts = [0] + [i for i in range(1, len(t)) if t[i] - t[i - 1] > WINDOW_GAP] + [len(t)]
    nodes, polys = [], []
    for s, e in zip(starts[:-1], starts[1:]):
        if e - s < 3:
            raise ValueError(f"the window at t = {t[s]:g} s has {e - s} rows; at least 3 are needed")
        tc = float(np.mean(t[s:e]))
        p = np.polyfit(t[s:e] - tc, a[s:e], min(4, e - s - 1))
        nodes.append((tc, np.polyval(p, 0.0), np.polyval(np.polyder(p), 0.0), np.polyval(np.polyder(p, 2), 0.0)))
        polys.append(p)
    return np.array(nodes), polys


def reconstruct(t: np.ndarray, a: np.ndarray, tq: np.ndarray) -> np.ndarray:
    """The angle at the times tq, rebuilt from the windows of samples (t, a) as the module says."""
    nodes, polys = window_nodes(t, a)
    tq = np.asarray(tq, dtype=float)
    out = np.empty_like(tq)
    first, last = tq < nodes[0, 0], tq > nodes[-1, 0]
    out[first] = np.polyval(polys[0], tq[first] - nodes[0, 0])
    out[last] = np.polyval(polys[-1], tq[last] - nodes[-1, 0])
    mid = ~(first | last)
    i = np.clip(np.searchsorted(nodes[:, 0], tq[mid]) - 1, 0, len(nodes) - 2)
    h = nodes[i + 1, 0] - nodes[i, 0]
    s = (tq[mid] - nodes[i, 0]) / h
    s2, s3, s4, s5 = s**2, s**3, s**4, s**5
    # quintic Hermite basis: value, slope (times h) and curvature (times h^2) at both ends
    out[mid] = ((1 - 10 * s3 + 15 * s4 - 6 * s5) * nodes[i, 1] + (s - 6 * s3 + 8 * s4 - 3 * s5) * h * nodes[i, 2]
                + (0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5) * h**2 * nodes[i, 3]
                + (10 * s3 - 15 * s4 + 6 * s5) * nodes[i + 1, 1] + (-4 * s3 + 7 * s4 - 3 * s5) * h * nodes[i + 1, 2]
                + (0.5 * s3 - s4 + 0.5 * s5) * h**2 * nodes[i + 1, 3])
    return out


def write_roll_file(samples: Path = SAMPLES, out: Path = ROLL_FILE, dt: float = 0.005, tend: float = 8.2) -> None:
    """Writes the rebuilt angle every dt from 0 to tend as lines 'time degrees' with a comment header."""
    d = np.loadtxt(samples)
    tq = np.round(np.arange(0.0, tend + dt / 2, dt), 6)
    aq = reconstruct(d[:, 0], d[:, 1], tq)
    aq[np.abs(aq) < 5e-7] = 0.0  # no "-0.000000"
    head = ("# SPHERIC test 10, lateral impact, water: the measured roll angle (degrees, positive: the sensor's wall,\n"
            "# the left one, goes down), rebuilt every 5 ms from the windows of the 20 kHz record in\n"
            "# cases/data/spheric10_roll_samples.txt (python/flexslosh/rollmotion.py; cases/data/README.md).\n"
            "# time[s] angle[deg]\n")
    out.write_text(head + "".join(f"{x:.3f} {y:.6f}\n" for x, y in zip(tq, aq)))


def main(argv: Sequence[str] | None = None) -> int:
    """Rewrites cases/data/spheric10_roll.txt from the samples."""
    del argv
    write_roll_file()
    print(f"wrote {ROLL_FILE.relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/env python3
"""Memory benchmark: the peak resident memory of the dam break (src/cases, the bench_dam_break.py set-up)
over its particles, at two resolutions, on 1 and 2 ranks, with the breakdown by data structure of
summary.json's "memory"; and what a particle costs at the margin: the growth of the peak resident memory
between the two resolutions over the growth of the particle count. The peak per particle holds each
process's fixed cost (the libraries, MPI and PETSc: about 49 MB a process with Debian's PETSc, of which
about 40 MB are the shared libraries' pages), which a particle count divides; the marginal cost is what
the data structures take for each particle. With several ranks the peak counts each rank's copy of the
libraries' pages, which the ranks of a node share (one physical copy): the figure "with the libraries'
shared pages counted once" (summary.json's "peak_resident_shared_once") is what the run takes from the
machine.

    /usr/bin/python3 bench/bench_memory.py [--dim 2] [--dx 0.0045,0.0032] [--ranks 1,2] [--steps 3] [-- options]

Defaults: 2-D, dx 0.0045 and 0.0032 (98,568 and about 195,000 particles); in 3-D (--dim 3) dx 0.0235 and
0.0296 (310,675 and about 155,000 particles). A few steps suffice: every structure has its size after
the first rebuild of the lists, and the final snapshot is written with all of them allocated.
"""
import argparse
import os
import tempfile
from pathlib import Path

from benchutil import print_memory, run_logged

ROOT = Path(__file__).resolve().parents[1]


def measure(exe, nranks, dim, dx, steps, extra):
    args = ["-fs_case", "dam_break", "-fs_dim", dim, "-fs_dx", repr(dx), "-ts_max_steps", steps,
            "-fs_output_interval", "0"] + extra
    with tempfile.TemporaryDirectory() as d:
        summary, _ = run_logged(exe, nranks, args, d, [])
    return summary


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dim", type=int, default=2, choices=(2, 3))
    ap.add_argument("--dx", default=None, help="two particle spacings, comma-separated")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--steps", type=int, default=3)
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    ap.add_argument("extra", nargs="*", help="more flexslosh options (after --), e.g. -fs_neighbour_candidates bits")
    a = ap.parse_args()
    exe = Path(a.build) / "flexslosh"
    dxs = [float(v) for v in (a.dx or ("0.0045,0.0032" if a.dim == 2 else "0.0235,0.0296")).split(",")]
    print(f"flexslosh memory benchmark: {a.dim}-D dam break, dx = {dxs}, {a.steps} steps {' '.join(a.extra)}")
    for nr in [int(r) for r in a.ranks.split(",")]:
        peaks = []
        for dx in dxs:
            s = measure(exe, nr, a.dim, dx, a.steps, a.extra)
            n, peak = s["particles"], s["memory"]["peak_resident"]
            once = s["memory"].get("peak_resident_shared_once", peak)
            peaks.append((n, peak))
            print(f"\n{nr} rank(s), dx = {dx}: {n} particles, peak resident {peak / 2**20:.1f} MiB, "
                  f"{peak / n:.0f} bytes a particle ({once / n:.0f} with the libraries' shared pages counted once)")
            print_memory(s)
        (n0, p0), (n1, p1) = peaks
        if n0 != n1:
            marginal = (p1 - p0) / (n1 - n0)
            fixed = p0 - marginal * n0
            print(f"\n{nr} rank(s): marginal cost {marginal:.0f} bytes a particle; fixed cost {fixed / 2**20:.1f} MiB "
                  f"({fixed / 2**20 / nr:.1f} MiB a process)")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""flexslosh against DualSPHysics 5.4 (CPU build) on bench_dam_break.py's 2-D dam break, or with
--dim 3 on bench_dam_break_3d.py's 3-D one (flexslosh's -fs_dim 3; dx = 0.0235 and 0.02 s by default
then), in one invocation on the same machine: DualSPHysics on 1 and 2 OpenMP threads and flexslosh on
1 and 2 MPI ranks, alternating (D1, F1, D2, F2), --rounds times; prints the wall times, the steps each
code took, the surge front each reached, and the ratio flexslosh / DualSPHysics per worker count (the
target: at most 0.5). DualSPHysics's case is written by dualsphysics_case.py (its settings there:
Verlet, Fourtakas density diffusion, artificial viscosity, CFL 0.2, single precision, the Wendland
kernel as flexslosh's); its binary is
not part of flexslosh: build it as docs/performance.md says and pass its path.

Wall times are of the whole process (set-up, the steps, the output at the end) for both codes, beside
each code's own time of the steps (DualSPHysics's "Simulation Runtime", flexslosh's FSStep event),
and that time per particle-step (microseconds: the steps' time over the liquid particles times the
steps), which compares runs of different sizes. The codes' particles and steps differ: DualSPHysics
also computes its wall particles (their number is printed) and takes Verlet steps (one force
evaluation each) where flexslosh takes RK4 steps (four) with boundary-integral walls.
Before the first run the script waits (up to --wait-tries times 30 s) for the 1-minute load average
to fall below --max-load; for each run it prints the CPU time others took during it (/proc/stat's busy
time less the run's own), the measure of how quiet the machine was, and the run's own CPU time (on a
shared machine the 1-worker runs' CPU times compare the codes better than their wall times).

    /usr/bin/python3 bench/bench_dualsphysics.py --dualsphysics PATH [--dim 2] [--dx 0.01] [--time 0.1] [--rounds 2]
"""
import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import dualsphysics_case
from benchutil import run_logged

ROOT = Path(__file__).resolve().parents[1]


def busy_seconds():
    """The machine's busy CPU time so far (all cores, /proc/stat), or None where there is none."""
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
    except OSError:
        return None
    return (sum(v[:8]) - v[3] - v[4]) / os.sysconf("SC_CLK_TCK")


def timed(fn):
    """Runs fn(); returns (its result, wall seconds, the run's CPU seconds, others' CPU seconds)."""
    r0, b0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), busy_seconds(), time.perf_counter()
    res = fn()
    t1, b1, r1 = time.perf_counter(), busy_seconds(), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)
    others = None if b0 is None else max(0.0, (b1 - b0) - cpu)
    return res, t1 - t0, cpu, others


def run_dualsphysics(exe, casedir, outdir, threads, nbound, a):
    cmd = [str(exe), str(Path(casedir) / "Case"), str(outdir), f"-ompthreads:{threads}", "-svres:0"]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    out = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
    if "[Simulation finished" not in out:
        sys.exit("DualSPHysics failed:\n" + out[-3000:])
    def num(label):
        m = re.search(label + r"\.*: ([\d.,]+)", out)
        return m.group(1).replace(",", "") if m else None

    parts = sorted(Path(outdir).rglob("Part_*.bi4"))
    t, pts = dualsphysics_case.fluid_state(parts[-1], nbound)
    return {"steps": int(num("Steps of simulation")), "step_time": float(num("Simulation Runtime")),
            "particles": len(pts), "front": dualsphysics_case.front(pts, a), "time": t,
            "excluded": int(num("Excluded particles") or 0)}


def run_flexslosh(exe, nranks, dx, tfinal, outdir, dim=2):
    args = ["-fs_case", "dam_break", "-fs_dx", repr(dx), "-ts_max_time", repr(tfinal), "-fs_output_interval", "0"]
    if dim == 3:
        args += ["-fs_dim", "3"]
    s, t = run_logged(exe, nranks, args, outdir, ["FSStep"])
    with open(Path(outdir) / "timeseries.csv") as f:
        head = f.readline().strip().split(",")
        last = f.readlines()[-1].strip().split(",")
    return {"steps": s["steps"], "step_time": t.get("FSStep", float("nan")), "particles": s["particles"],
            "front": float(last[head.index("front_position")]), "time": float(last[head.index("time")]),
            "excluded": 0}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dualsphysics", required=True, help="path of DualSPHysics5.4CPU_linux64")
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2)
    ap.add_argument("--dx", type=float, default=None, help="default 0.01 in 2-D, 0.0235 in 3-D")
    ap.add_argument("--time", type=float, default=None,
                    help="physical time simulated (default 0.1 s in 2-D, 0.02 s in 3-D)")
    ap.add_argument("--workers", default="1,2", help="OpenMP threads / MPI ranks")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--max-load", type=float, default=0.5)
    ap.add_argument("--wait-tries", type=int, default=10)
    ap.add_argument("--build", default=os.environ.get("FLEXSLOSH_BUILD", str(ROOT / "build")))
    a = ap.parse_args()
    a.dx = a.dx or (0.01 if a.dim == 2 else 0.0235)
    a.time = a.time or (0.1 if a.dim == 2 else 0.02)
    exe = Path(a.build) / "flexslosh"
    dsph = Path(a.dualsphysics).resolve()
    workers = [int(w) for w in a.workers.split(",")]
    for _ in range(a.wait_tries):
        if os.getloadavg()[0] < a.max_load:
            break
        print(f"load average {os.getloadavg()[0]:.2f} >= {a.max_load}: waiting 30 s", flush=True)
        time.sleep(30)
    load0 = os.getloadavg()
    shape = "1 x 2 m column, 4 x 3 m tank" if a.dim == 2 else "1 x 2 x 2 m column, 4 x 3 x 2 m tank"
    print(f"{a.dim}-D dam break {shape}, dx = {a.dx}, {a.time} s; {time.strftime('%Y-%m-%d %H:%M')}, "
          f"{os.cpu_count()} CPUs, load average at the start {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        case = dualsphysics_case.write_case(Path(tmp) / "case", dx=a.dx, tfinal=a.time, dim=a.dim)
        print(f"DualSPHysics's case: {case['fluid']} liquid and {case['wall']} wall particles", flush=True)
        for rnd in range(1, a.rounds + 1):
            for w in workers:
                for code in ("DualSPHysics", "flexslosh"):
                    out = Path(tmp) / f"{code}-{w}-{rnd}"
                    out.mkdir()
                    load = os.getloadavg()[0]
                    if code == "DualSPHysics":
                        fn = lambda: run_dualsphysics(dsph, Path(tmp) / "case", out, w, case["wall"], 1.0)
                    else:
                        fn = lambda: run_flexslosh(exe, w, a.dx, a.time, out, a.dim)
                    r, wall, cpu, others = timed(fn)
                    r["per_step"] = 1e6 * r["step_time"] / (r["particles"] * r["steps"])
                    r.update(code=code, workers=w, round=rnd, wall=wall, cpu=cpu, others=others, load=load)
                    rows.append(r)
                    oth = "n/a" if others is None else f"{others:.1f} s"
                    print(f"  round {rnd}  {code:12s} {w} {'thread(s)' if code == 'DualSPHysics' else 'rank(s) '}"
                          f"  wall {wall:8.2f} s  steps' own time {r['step_time']:8.2f} s  steps {r['steps']:6d}"
                          f"  {r['per_step']:7.3f} us per particle-step"
                          f"  front {r['front']:.4f} m at t = {r['time']:.4f} s  CPU {cpu:7.1f} s  others' CPU {oth}"
                          f"  load before {load:.2f}", flush=True)
    print(f"\n{'code':13s} {'workers':>7s} {'particles':>9s} {'steps':>6s} " +
          " ".join(f"{'round ' + str(r):>9s}" for r in range(1, a.rounds + 1)) +
          f" {'best':>8s} {'CPU':>8s} {'front':>7s} {'us/p-step':>9s}   (seconds; CPU and us per particle-step: "
          "the best run's, CPU of all its threads or ranks)")
    best, cpu = {}, {}
    for code in ("DualSPHysics", "flexslosh"):
        for w in workers:
            rs = [r for r in rows if r["code"] == code and r["workers"] == w]
            fastest = min(rs, key=lambda r: r["wall"])
            best[code, w], cpu[code, w] = fastest["wall"], fastest["cpu"]
            print(f"{code:13s} {w:7d} {rs[0]['particles']:9d} {rs[0]['steps']:6d} " +
                  " ".join(f"{r['wall']:9.2f}" for r in rs) + f" {best[code, w]:8.2f} {cpu[code, w]:8.2f}"
                  f" {rs[0]['front']:7.3f} {fastest['per_step']:9.3f}")
    for w in workers:
        ratio = best["flexslosh", w] / best["DualSPHysics", w]
        print(f"flexslosh / DualSPHysics on {w}: {ratio:.3f} (best wall times; target <= 0.5: "
              f"{'met' if ratio <= 0.5 else 'NOT met'}); CPU times {cpu['flexslosh', w] / cpu['DualSPHysics', w]:.3f}")


if __name__ == "__main__":
    sys.exit(main())

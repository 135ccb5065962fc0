"""Shared by the benchmark scripts: run flexslosh (on 1 rank or under mpirun) with -log_view and read
back summary.json and the times of flexslosh's log events."""
import json
import os
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path


def run_logged(exe, nranks, args, outdir, events):
    """Runs `exe args -log_view` on nranks ranks; returns (summary.json as a dict, {event: seconds})."""
    cmd = [str(exe)] + [str(a) for a in args] + ["-fs_output_dir", str(outdir), "-fs_progress", "0", "-log_view"]
    if nranks > 1:  # a rank a core where there are enough cores; oversubscribed ranks are not bound (Open MPI refuses)
        bind = ["--bind-to", "core"] if nranks <= (os.cpu_count() or 1) else ["--bind-to", "none"]
        cmd = ["mpirun", "--oversubscribe"] + bind + ["-n", str(nranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    out = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=True).stdout
    summary = json.load(open(Path(outdir) / "summary.json"))
    times = {}
    for ev in events:
        m = re.search(r"^%s\s+\d+\s+\S+\s+(\S+)" % ev, out, re.M)
        if m:
            times[ev] = float(m.group(1))
    return summary, times


MEMORY_LABELS = [("particle_fields", "particle fields (swarm)"), ("particle_work", "particle records, aux, gamma"),
                 ("ts_vectors", "TS vectors"), ("candidates", "candidates"),
                 ("cells", "cell list"), ("halo", "halo buffers"), ("walls_lists", "walls: particles' lists"),
                 ("walls_elements", "walls: elements"), ("accounted", "accounted (allocated)"),
                 ("peak_resident", "peak resident, all ranks"), ("not_accounted", "not accounted (the process, ...)"),
                 ("shared_clean", "of it shared clean pages (libraries)"),
                 ("peak_resident_shared_once", "peak resident, shared pages once")]


def print_memory(summary):
    """The memory breakdown of summary.json ("memory", src/solver/memory.c): bytes per particle of each
    data structure's allocation (capacity, summed over the ranks) beside the peak resident memory."""
    mem, n = summary.get("memory"), max(summary["particles"], 1)
    if not mem:
        return
    print("  memory per particle by structure (allocated; untouched capacity is not resident):")
    for key, label in MEMORY_LABELS:
        if key in mem:
            print(f"    {label:34s} {mem[key] / n:8.0f} bytes  ({mem[key] / 2**20:8.1f} MiB)")


def step_time(result):
    """The wall time of the steps (flexslosh's FSStep event; the whole run without it) of a (summary, times, ...)
    result of run_logged."""
    summary, times = result[0], result[1]
    return times.get("FSStep", summary["wall_time"])


def run_rounds(run_one, ranks, rounds, side_by_side=False):
    """Runs run_one(nranks) for each rank count in turn, `rounds` times over (1, 2, 1, 2, ... ranks: the rank counts
    interleaved, so that a slow spell of a shared machine does not fall on one rank count only), printing each
    round's step times and 1 -> 2 rank efficiency as it goes. Returns {nranks: the run with the fastest steps}.

    One run's time on a shared virtual machine varies by up to a fifth, most when both cores are busy (measured:
    the 3-D dam break benchmark's 2-rank run 126.9-159.3 s in three rounds, its 1-rank run 233.9-270.5 s), so
    figures compared across rank counts or builds come from the fastest of several rounds.

    side_by_side: each round also runs two 1-rank runs at once, which share nothing but the machine: the ratio of
    the 1-rank run's time alone to theirs is the machine's own 1 -> 2 core efficiency (shared caches, memory
    bandwidth, the host's clock when both cores are busy), the most a 2-rank run can reach on it."""
    best = {}
    for rnd in range(1, rounds + 1):
        walls = {}
        for nr in ranks:
            r = run_one(nr)
            walls[nr] = step_time(r)
            if nr not in best or walls[nr] < step_time(best[nr]):
                best[nr] = r
        line = ", ".join(f"{nr} rank(s) {walls[nr]:.3f} s" for nr in ranks)
        if 1 in walls and 2 in walls:
            line += f", efficiency 1 -> 2 ranks {100 * walls[1] / (2 * walls[2]):.1f} %"
        if side_by_side and 1 in walls:
            with ThreadPoolExecutor(2) as ex:
                pair = [step_time(r) for r in ex.map(run_one, [1, 1])]
            ceiling = walls[1] / max(pair)
            line += (f"; two 1-rank runs side by side {pair[0]:.3f} / {pair[1]:.3f} s: the machine's own 1 -> 2 core "
                     f"efficiency {100 * ceiling:.1f} %")
            if 2 in walls:
                line += f", the 2-rank run's {100 * walls[1] / (2 * walls[2]) / ceiling:.1f} % of it"
        if rounds > 1 or side_by_side:
            print(f"round {rnd}: {line}", flush=True)
    return best

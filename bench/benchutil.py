"""Shared by the benchmark scripts: run flexslosh (on 1 rank or under mpirun) with -log_view and read
back summary.json and the times of flexslosh's log events."""
import json
import os
import re
import subprocess
from pathlib import Path


def run_logged(exe, nranks, args, outdir, events):
    """Runs `exe args -log_view` on nranks ranks; returns (summary.json as a dict, {event: seconds})."""
    cmd = [str(exe)] + [str(a) for a in args] + ["-fs_output_dir", str(outdir), "-fs_progress", "0", "-log_view"]
    if nranks > 1:
        cmd = ["mpirun", "--oversubscribe", "--bind-to", "core", "-n", str(nranks)] + cmd
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
                 ("peak_resident", "peak resident, all ranks"), ("not_accounted", "not accounted (the process, ...)")]


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

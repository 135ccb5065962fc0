"""What survives a crash: a coupled run killed with SIGKILL after its second checkpoint leaves only valid
files and, restarted from its newest checkpoint, gives the uninterrupted run's rows and final snapshot
bit for bit; a full disk (a file-size limit, or a tiny tmpfs where one can be mounted) stops the run with
an error naming the file, and what was written before stays valid. docs/running.md, "What survives a crash"."""
import csv
import json
import os
import re
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, assert_no_crash, flexslosh_bin, mpirun_bin, petsc_error_message, run_flexslosh

# the coupled tank at dx 1 cm (210 particles, about 150 steps a second on 2 ranks); a snapshot every 33 steps
BASE = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_dx", "0.01", "-fs_output_interval", "0.02",
        "-fs_checkpoint_interval", "40"]
STEPS = 200
NRANKS = 2


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run, STEPS steps on NRANKS ranks."""
    out = tmp_path_factory.mktemp("reference")
    run_flexslosh(BASE + ["-ts_max_steps", STEPS, "-fs_output_dir", out], nranks=NRANKS, cwd=out, timeout=120)
    return out


def descendants(pid):
    """The processes below pid (mpirun's ranks), from /proc."""
    children = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    found, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            found.append(c)
            todo.append(c)
    return found


def check_csv(path):
    """Whole rows only: a header, then rows of as many numbers, each ending with a newline."""
    text = path.read_text()
    assert text.endswith("\n"), f"{path.name}: a torn last row"
    rows = list(csv.reader(text.splitlines()))
    for row in rows[1:]:
        assert len(row) == len(rows[0]), f"{path.name}: a row of {len(row)} fields, the header has {len(rows[0])}"
        if path.name != "snapshots.csv":
            np.array(row, dtype=float)
    return rows


def check_output_dir(out):
    """Every file of a run's output directory is valid; returns the names of the leftover *.tmp files (a write
    the kill interrupted, never read)."""
    leftovers = []
    for f in sorted(out.iterdir()):
        if f.suffix == ".tmp":
            leftovers.append(f.name)
        elif f.suffix == ".h5":
            with h5py.File(f, "r") as h5:
                assert list(h5.keys()), f"{f.name} is empty"
                if f.name.startswith("checkpoint_"):
                    assert h5["particles/position"].shape[0] == h5["header"].attrs["nparticles"]
        elif f.suffix == ".csv":
            check_csv(f)
        elif f.suffix == ".xdmf":
            ET.parse(f)
        elif f.suffix == ".json":
            pytest.fail(f"summary.json of a killed run: {f}")
    # the XDMF index lists the snapshots of snapshots.csv, each complete; snapshots.csv is renamed first, so a kill
    # between the two renames leaves the newest snapshot out of the XDMF only (the restart rewrites both)
    if not (out / "snapshots.csv").exists():
        assert not (out / "particles.xdmf").exists()
        return leftovers
    index = [r[3] for r in check_csv(out / "snapshots.csv")[1:]]
    listed = []
    if (out / "particles.xdmf").exists():
        listed = [item.text.split(":")[0] for item in ET.parse(out / "particles.xdmf").iter("DataItem")
                  if item.text.endswith("/particles/position")]
    assert listed in (index, index[:-1])
    for name in index:
        with h5py.File(out / name, "r") as h5:
            assert h5["particles/position"].shape[0] == h5["particles"].attrs["nparticles"]
    return leftovers


def test_a_killed_run_restarts_bit_for_bit(reference, tmp_path):
    out = tmp_path / "killed"
    cmd = [mpirun_bin(), "--oversubscribe", "-n", str(NRANKS), str(flexslosh_bin()), "-fs_progress", "0"] + \
        [str(a) for a in BASE] + ["-ts_max_steps", "100000", "-fs_output_dir", str(out)]
    proc = subprocess.Popen(cmd, env=dict(os.environ, **MPI_ENV), cwd=tmp_path, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while not (out / "checkpoint_000080.h5").exists():  # the second checkpoint
            assert proc.poll() is None, "the run ended before its second checkpoint"
            assert time.monotonic() < deadline, "no second checkpoint within 60 s"
            time.sleep(0.01)
        pids = descendants(proc.pid)
        os.killpg(proc.pid, signal.SIGKILL)
        for pid in pids:  # a rank in a process group of its own
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    time.sleep(0.2)
    leftovers = check_output_dir(out)
    for name in leftovers:  # only the temporary name of an output file
        assert re.fullmatch(r"(snapshot|checkpoint)_\d{6}\.h5\.tmp|(snapshots|timeseries|energy)\.csv\.tmp|"
                            r"particles\.xdmf\.tmp", name), name
    newest = max(out.glob("checkpoint_[0-9][0-9][0-9][0-9][0-9][0-9].h5"))
    assert newest.name >= "checkpoint_000080.h5"
    run_flexslosh(BASE + ["-ts_max_steps", STEPS, "-fs_output_dir", out, "-fs_restart", newest], nranks=NRANKS, cwd=tmp_path,
                  timeout=120)
    for name in ("timeseries.csv", "energy.csv", "snapshots.csv", "particles.xdmf"):
        assert (out / name).read_text() == (reference / name).read_text(), name
    final = check_csv(reference / "snapshots.csv")[-1][3]
    with h5py.File(reference / final, "r") as a, h5py.File(out / final, "r") as b:
        assert sorted(a["particles"].keys()) == sorted(b["particles"].keys())
        assert dict(a["particles"].attrs) == dict(b["particles"].attrs)
        for name in a["particles"]:
            assert np.array_equal(a["particles"][name][...], b["particles"][name][...]), name


# ---- a full disk: a file-size limit (RLIMIT_FSIZE) on the ranks, SIGXFSZ ignored so that writes fail with EFBIG
# (set on each rank, not on mpirun, whose own shared-memory files must stay unlimited)

LIMITED = ("import os, resource, signal, sys; signal.signal(signal.SIGXFSZ, signal.SIG_IGN); "
           "n = int(sys.argv[1]); resource.setrlimit(resource.RLIMIT_FSIZE, (n, n)); os.execv(sys.argv[2], sys.argv[2:])")


def run_limited(limit, args, cwd):
    cmd = [mpirun_bin(), "--oversubscribe", "-n", str(NRANKS), sys.executable, "-c", LIMITED, str(limit), str(flexslosh_bin()),
           "-fs_progress", "0"] + [str(a) for a in args]
    proc = subprocess.run(cmd, env=dict(os.environ, **MPI_ENV), cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=60)
    return proc


def test_a_full_disk_names_the_snapshot(reference, tmp_path):
    # the limit between walls.h5 and the first snapshot's size: the first snapshot cannot be written
    walls, snap = (reference / "walls.h5").stat().st_size, (reference / "snapshot_000000.h5").stat().st_size
    assert walls < snap
    out = tmp_path / "full"
    proc = run_limited((walls + snap) // 2, BASE + ["-ts_max_steps", STEPS, "-fs_output_dir", out], tmp_path)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert f'Cannot write "{out}/snapshot_000000.h5"' in msg, msg
    assert check_output_dir(out) == ["snapshot_000000.h5.tmp"]
    assert (out / "walls.h5").exists() and (out / "walls.xdmf").exists()
    # the time series' first row, as the uninterrupted run's
    assert (out / "timeseries.csv").read_text().splitlines() == (reference / "timeseries.csv").read_text().splitlines()[:2]


def test_a_full_disk_names_the_time_series(reference, tmp_path):
    # a limit above every HDF5 file: the growing time series reaches it first
    limit = max(f.stat().st_size for f in reference.glob("*.h5")) + 4096
    assert (reference / "timeseries.csv").stat().st_size > 2 * limit
    out = tmp_path / "full"
    proc = run_limited(limit, BASE + ["-ts_max_steps", STEPS, "-fs_output_dir", out], tmp_path)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert f'Cannot write to time series "{out}/timeseries.csv": File too large' in msg, msg
    check_output_dir(out)
    # whole rows, the uninterrupted run's; the checkpoints and snapshots written before are complete and equal
    rows = (out / "timeseries.csv").read_text().splitlines()
    assert 10 < len(rows) < STEPS and rows == (reference / "timeseries.csv").read_text().splitlines()[:len(rows)]
    assert (out / "checkpoint_000040.h5").exists()
    # reported before another file is written (the row's write status rides on the next step's reduction): no
    # checkpoint of the failed row's step or after it
    failed = len(rows) - 1
    assert all(int(f.stem.split("_")[1]) < failed for f in out.glob("checkpoint_*.h5")), (failed, sorted(out.glob("*.h5")))
    for f in list(out.glob("snapshot_*.h5")) + list(out.glob("checkpoint_*.h5")):
        with h5py.File(f, "r") as a, h5py.File(reference / f.name, "r") as b:
            for name in a["particles"]:
                assert np.array_equal(a["particles"][name][...], b["particles"][name][...]), (f.name, name)


@pytest.fixture
def tiny_disk(tmp_path):
    """A 160 KiB tmpfs (root only: skipped where it cannot be mounted), unmounted afterwards."""
    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=160k", "tmpfs", str(disk)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here")
    yield disk
    subprocess.run(["umount", str(disk)], check=True)


def test_a_full_filesystem_names_the_file(reference, tiny_disk, tmp_path):
    # a real full disk (ENOSPC): the run stops naming the file it could not write; the rest is valid
    out = tiny_disk / "o"
    proc = run_flexslosh(BASE + ["-ts_max_steps", STEPS, "-fs_output_dir", out], nranks=NRANKS, cwd=tmp_path, check=False,
                         timeout=60)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert re.search(rf'Cannot write (to time series )?"{re.escape(str(out))}/[a-z_0-9.]+"', msg), msg
    check_output_dir(out)
    for name in ("timeseries.csv", "energy.csv"):
        rows = (out / name).read_text().splitlines()
        assert rows == (reference / name).read_text().splitlines()[:len(rows)], name


# ---- one run per output directory (issue 34 item 4): a lock, and a new run's directory holds its own results only

TG_SMALL = ["-fs_case", "taylor_green", "-fs_dx", "0.04", "-fs_progress", "0"]


def test_one_run_per_directory_and_no_stale_results(tmp_path):
    out = tmp_path / "o"
    first = subprocess.Popen([str(flexslosh_bin())] + TG_SMALL + ["-ts_max_steps", "1000000", "-fs_output_interval", "0.01",
                                                                    "-fs_checkpoint_interval", "20", "-fs_output_dir", str(out)],
                             cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while not (out / "checkpoint_000040.h5").exists():  # running, with snapshots and checkpoints written
            assert first.poll() is None and time.monotonic() < deadline, "the first run did not reach step 40"
            time.sleep(0.02)
        # a second run into the same directory: both wrote there (torn rows, an orphan snapshot) and ended with 0
        second = run_flexslosh(TG_SMALL + ["-ts_max_steps", 3, "-fs_output_dir", out], cwd=tmp_path, check=False, timeout=60)
        assert first.poll() is None, "the first run ended: the test did not overlap them"
        assert_no_crash(second)
        msg = petsc_error_message(second.stdout)
        assert second.returncode != 0 and f'Output directory "{out}" (option -fs_output_dir) is in use by another run ' \
            f"(flexslosh, pid {first.pid} on host " in msg, msg
        assert (out / "flexslosh.lock").read_text().startswith(f"flexslosh, pid {first.pid} on host ")
    finally:
        first.kill()  # as a crash would: its lock file stays, its lock ends with it
        first.wait(timeout=30)
    check_output_dir(out)
    assert len(list(out.glob("snapshot_*.h5"))) > 3 and (out / "flexslosh.lock").exists()
    # a new run there (not a restart): the killed run's lock is free, and its results (the higher-numbered snapshots,
    # the checkpoints; summary.json when a run ended) are removed, what is not a run's file is kept
    (out / "notes.txt").write_text("mine\n")
    (out / "figures").mkdir()
    (out / "summary.json").write_text('{"dx": 1}\n')
    third = run_flexslosh(TG_SMALL + ["-ts_max_steps", 3, "-fs_output_interval", 0, "-fs_output_dir", out], cwd=tmp_path,
                          timeout=60)
    assert f"Output directory {out}: removed the earlier run's results (" in third.stdout, third.stdout
    assert sorted(f.name for f in out.iterdir()) == ["energy.csv", "figures", "notes.txt", "particles.xdmf",
                                                     "snapshot_000000.h5", "snapshot_000001.h5", "snapshots.csv",
                                                     "summary.json", "timeseries.csv"]
    assert json.loads((out / "summary.json").read_text())["steps"] == 3
    assert len(check_csv(out / "timeseries.csv")) == 5


# ---- output files go where they are meant to (issue 34 item 7): a link or a file planted under an output's name or
# its temporary name is replaced, never written through (O_EXCL | O_NOFOLLOW, the HDF5 files created so by rank 0)

def plant(out, victims, names):
    """a symbolic link (or, for the names marked "hard", a hard link) to a file of its own in victims under each name"""
    for name in names:
        how, name = ("hard", name[5:]) if name.startswith("hard:") else ("symlink", name)
        victim = victims / name.replace("/", "_")
        victim.write_text(f"precious {name}\n")
        (out / name).unlink(missing_ok=True)
        if how == "symlink":
            (out / name).symlink_to(victim)
        else:
            os.link(victim, out / name)


def test_links_and_files_planted_in_the_output_directory_are_not_written_through(tmp_path):
    out, victims = tmp_path / "o", tmp_path / "victims"
    out.mkdir()
    victims.mkdir()
    # a new run: under the outputs' names (a new run removes them first, FSOutputDirClear)
    plant(out, victims, ["summary.json.tmp", "snapshot_000000.h5.tmp", "timeseries.csv", "checkpoint_000020.h5.tmp",
                         "walls.h5.tmp", "particles.xdmf.tmp", "hard:energy.csv", "hard:snapshots.csv.tmp"])
    run_flexslosh(BASE + ["-ts_max_steps", 20, "-fs_checkpoint_interval", 20, "-fs_output_dir", out], nranks=NRANKS,
                  cwd=tmp_path, timeout=120)
    # a restart, which keeps the directory's files: under the temporary names of what it writes (each created anew)
    plant(out, victims, [f"snapshot_{n:06d}.h5.tmp" for n in range(8)] +
          ["summary.json.tmp", "checkpoint_000040.h5.tmp", "walls.h5.tmp", "walls.xdmf.tmp", "particles.xdmf.tmp",
           "timeseries.csv.tmp", "hard:energy.csv.tmp", "hard:snapshots.csv.tmp"])
    run_flexslosh(BASE + ["-ts_max_steps", 40, "-fs_checkpoint_interval", 20, "-fs_output_dir", out, "-fs_restart",
                          out / "checkpoint_000020.h5"], nranks=NRANKS, cwd=tmp_path, timeout=120)
    for victim in victims.iterdir():
        assert victim.read_text() == f"precious {victim.name}\n", victim.name
    unused = {f for f in out.glob("snapshot_*.h5.tmp") if f.is_symlink()}  # planted for snapshots not written
    assert unused and set(out.glob("*.tmp")) == unused
    for name in ("timeseries.csv", "energy.csv"):  # the header and steps 0 to 40
        assert len(check_csv(out / name)) == 42, name
    assert len(check_csv(out / "snapshots.csv")) == 1 + len(list(out.glob("snapshot_*.h5")))
    for f in set(out.iterdir()) - unused:
        assert f.is_file() and not f.is_symlink() and f.stat().st_nlink == 1, f.name
    assert (out / "checkpoint_000040.h5").exists() and (out / "walls.h5").exists()

"""Shared helpers and fixtures of the flexslosh Python test suite.

The tests drive the flexslosh executable (build/flexslosh, or $FLEXSLOSH_BUILD/flexslosh) and read
its output files:
  timeseries.csv        step,time,dt,kinetic_energy,mass,momentum_*,max_velocity,...
  snapshot_NNNNNN.h5    /particles/{position,velocity,density,pressure,strain_rate,
                        turbulent_viscosity,rank,id}, attributes time, step, dim, nparticles
  checkpoint_NNNNNN.h5  written every -fs_checkpoint_interval steps
  summary.json          what ran, how long, with which options

Helpers (importable with `from conftest import ...`, and also offered as fixtures):
  flexslosh_bin(), build_dir(), run_flexslosh(args, nranks, cwd, check, timeout),
  read_series(dir), read_snapshot(path), last_snapshot(dir), read_summary(dir),
  petsc_error_message(output), assert_no_crash(proc).
"""
import glob
import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]

# the Python package of this checkout (make build also makes build/venv, whose .pth points at it)
import sys  # noqa: E402

sys.path.insert(0, str(REPO_ROOT / "python"))

# The suite starts the executable over a thousand times, most runs stopping before their first step, so Open
# MPI's start weighs: its default choice of messaging layer first tries the network fabrics through libfabric (the
# cm layer's ofi), which takes about 0.2 s at every start here. Naming ob1 (shared memory) skips it: 0.5 -> 0.3 s
# a run. Set before anything here initialises MPI, so the tests' own petsc4py and mpi4py start the same way.
# (Open MPI's "isolated" singletons would save 0.1 s more, but they share one session directory and collide when
# several start at once.)
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_pml": "ob1"}
os.environ.update(MPI_ENV)

# The Taylor-Green run most tests start from (2500 particles, about 0.05 s per step on one core).
TG = ["-fs_case", "taylor_green", "-fs_dx", "0.02", "-fs_output_interval", "0"]


def build_dir():
    """The build directory: $FLEXSLOSH_BUILD, else <repo>/build."""
    return Path(os.environ.get("FLEXSLOSH_BUILD", REPO_ROOT / "build")).resolve()


def flexslosh_bin():
    return build_dir() / "flexslosh"


def plugin_path():
    return build_dir() / "libfsdrag.so"


def mpirun_bin():
    for name in ("mpirun", "mpiexec"):
        path = shutil.which(name)
        if path:
            return path
    raise RuntimeError("mpirun/mpiexec not found on PATH")


def _tail(text, n=4000):
    return text if len(text) <= n else "...\n" + text[-n:]


def run_flexslosh(args, nranks=1, cwd=None, check=True, timeout=300, progress=False, env=None):
    """Runs flexslosh with args (a list of strings or numbers).

    nranks > 1 runs under `mpirun --oversubscribe -n nranks`. -fs_progress 0 is put first unless
    progress is True (a later -fs_progress in args still wins). Returns the CompletedProcess with
    stdout and stderr combined in .stdout (also as .output). check=True fails the test, showing the
    end of the output, when the exit status is not 0. env: more environment variables (a dict).
    """
    exe = flexslosh_bin()
    if not exe.exists():
        pytest.fail(f"flexslosh executable not found at {exe}: build first (cmake -S . -B build && cmake --build build)")
    args = [str(a) for a in args]
    if not progress:
        args = ["-fs_progress", "0"] + args
    cmd = [str(exe)] + args
    if nranks > 1:
        cmd = [mpirun_bin(), "--oversubscribe", "-n", str(nranks)] + cmd
    extra, env = env or {}, dict(os.environ)
    env.update(MPI_ENV)
    env.update({k: str(v) for k, v in extra.items()})
    proc = subprocess.run(cmd, cwd=str(cwd) if cwd else None, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=timeout)
    proc.output = proc.stdout
    proc.cmd = " ".join(cmd)
    if check and proc.returncode != 0:
        pytest.fail(f"flexslosh failed (exit {proc.returncode}): {proc.cmd}\n{_tail(proc.stdout)}")
    return proc


def read_series(directory):
    """timeseries.csv of a run as a dict column name -> 1-D numpy array (step as int)."""
    path = Path(directory) / "timeseries.csv"
    with open(path) as fp:
        header = fp.readline().strip().split(",")
        rows = [line.strip().split(",") for line in fp if line.strip()]
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    cols = {name: data[:, k] for k, name in enumerate(header)}
    cols["step"] = cols["step"].astype(np.int64)
    return cols


class Snapshot(dict):
    """A particle snapshot: field name -> array, rows sorted by particle id; .attrs holds the HDF5
    attributes of /particles (time, step, dim, nparticles) and .path the file."""

    attrs = {}
    path = None


def read_snapshot(path):
    import h5py

    snap = Snapshot()
    with h5py.File(path, "r") as h5:
        grp = h5["particles"]
        ids = grp["id"][...]
        order = np.argsort(ids, kind="stable")
        for name, dset in grp.items():
            snap[name] = dset[...][order]
        snap.attrs = {k: (v.item() if hasattr(v, "item") else v) for k, v in grp.attrs.items()}
    snap.path = Path(path)
    return snap


def snapshot_files(directory):
    return sorted(glob.glob(str(Path(directory) / "snapshot_[0-9]*.h5")))


def last_snapshot(directory):
    files = snapshot_files(directory)
    assert files, f"no snapshot in {directory}"
    return read_snapshot(files[-1])


def read_summary(directory):
    with open(Path(directory) / "summary.json") as fp:
        return json.load(fp)


def petsc_error_message(output):
    """The text of the error message(s): flexslosh's short report and diagnostic lines ("[rank] flexslosh: ...",
    src/sys/errors.c), and with -fs_error_trace PETSc's report, the lines after "--- Error Message ---" up to "See
    https://petsc.org", without the "option left" warnings.
    (PETSc's option table at the end of an error repeats every option given: tests must not find
    the option they passed there.)"""
    lines, inside = [], False
    for line in output.splitlines():
        body = re.sub(r"^\[\d+\]PETSC ERROR: ?", "", line)
        if "Error Message" in body and "----" in body:
            inside = True
            continue
        if inside and (body.startswith("See https://petsc.org") or body.startswith("See http")):
            inside = False
            continue
        if inside:
            if body.startswith("WARNING! There are option(s) set that were not used") or body.startswith("Option left:"):
                continue
            lines.append(body)
        elif re.match(r"^\[\d+\] flexslosh:", line):
            lines.append(line)
    return "\n".join(lines)


def assert_no_crash(proc):
    """The run ended by itself (an error return, not a signal or a crash)."""
    assert proc.returncode > 0, f"expected an error exit, got {proc.returncode}\n{_tail(proc.stdout)}"
    for bad in ("Segmentation", "signal", "SEGV", "Traceback", "core dumped"):
        assert bad not in proc.stdout, f"crash marker {bad!r} in the output:\n{_tail(proc.stdout)}"


def rel_max_diff(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = np.abs(a).max()
    return np.abs(a - b).max() / (scale if scale > 0 else 1.0)


# ------------------------------------------------------------------ fixtures


@pytest.fixture(scope="session")
def flexslosh():
    exe = flexslosh_bin()
    if not exe.exists():
        pytest.fail(f"flexslosh executable not found at {exe}: build first")
    return exe


@pytest.fixture
def run(tmp_path, flexslosh):
    """run(args, nranks=1, cwd=tmp_path, check=True, timeout=300) -> CompletedProcess."""

    def _run(args, nranks=1, cwd=None, check=True, timeout=300, progress=False):
        return run_flexslosh(args, nranks=nranks, cwd=cwd or tmp_path, check=check, timeout=timeout, progress=progress)

    return _run


@pytest.fixture
def series():
    return read_series


@pytest.fixture
def snapshot():
    return read_snapshot


PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def plot_cli(*args):
    """Runs `python -m flexslosh.plot ARGS` with the repository's package; the CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=str(REPO_ROOT / "python"))
    return subprocess.run([PYTHON, "-m", "flexslosh.plot", *map(str, args)], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=120)

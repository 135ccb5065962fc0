"""No hang on many ranks: an error raised on one rank only ends every rank, with its message, within
seconds (each run under a timeout). The faults come from FLEXSLOSH_FAULT=KIND:RANK:STEP (src/sys/fault.c,
for the tests only): alloc fails an allocation on RANK at STEP, leak moves one of RANK's particles out of
the tank. docs/running.md, "What survives a crash"."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, flexslosh_bin, mpirun_bin, petsc_error_message

TANK = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_dx", "0.01", "-ts_max_steps", "200",
        "-fs_progress", "0", "-fs_options_left", "0"]
LIMIT = 60  # seconds: a run that has not ended by then hangs (each ends in 1-3 s on an idle machine)


def run_timed(cmd, cwd, fault=None):
    """Runs cmd (mpirun ...) with FLEXSLOSH_FAULT=fault; returns the process; fails on a hang."""
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    env.pop("FLEXSLOSH_FAULT", None)
    if fault:
        env["FLEXSLOSH_FAULT"] = fault
    try:
        proc = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=LIMIT)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"hung: not ended after {LIMIT} s: {' '.join(map(str, cmd))}\n{(e.stdout or b'')[-3000:]}")
    return proc


def run_ranks(nranks, args, cwd, fault=None):
    return run_timed([mpirun_bin(), "--oversubscribe", "-n", nranks, flexslosh_bin()] + args, cwd, fault)


@pytest.mark.parametrize("nranks,rank", [(2, 1), (3, 2), (3, 0)])
def test_an_allocation_failure_on_one_rank_ends_every_rank(tmp_path, nranks, rank):
    proc = run_ranks(nranks, TANK + ["-fs_output_dir", tmp_path / "o"], tmp_path, fault=f"alloc:{rank}:5")
    assert proc.returncode != 0, proc.stdout[-3000:]
    assert f"Allocation failed on rank {rank} at step 5" in petsc_error_message(proc.stdout), proc.stdout[-3000:]


@pytest.mark.parametrize("nranks,rank", [(2, 1), (3, 2)])
def test_a_particle_leaving_the_tank_on_one_rank_ends_every_rank(tmp_path, nranks, rank):
    proc = run_ranks(nranks, TANK + ["-fs_output_dir", tmp_path / "o"], tmp_path, fault=f"leak:{rank}:5")
    assert proc.returncode != 0, proc.stdout[-3000:]
    # injected at step 5, caught by the first leak check from then on (the checks come with the lists' rebuilds)
    m = re.search(r"\[flexslosh\] leak: particle \d+ crossed wall \"tank\".* at step (\d+)", proc.stdout)
    assert m and int(m.group(1)) >= 5, proc.stdout[-3000:]
    assert "Particles crossed a wall on 1 rank(s)" in petsc_error_message(proc.stdout)


def test_a_file_rank_0_cannot_read_ends_every_rank(tmp_path):
    # the input files (probes, walls, motions) are read by rank 0 and broadcast: its error is every rank's
    probes = tmp_path / "probes.txt"
    probes.mkdir()  # a directory: not readable as a file, even by root
    proc = run_ranks(3, TANK + ["-fs_output_dir", tmp_path / "o", "-fs_probes", probes], tmp_path)
    assert proc.returncode != 0
    assert str(probes) in petsc_error_message(proc.stdout), proc.stdout[-3000:]


def test_a_wall_file_one_rank_cannot_open_ends_every_rank(tmp_path):
    # every rank reads the wall file: one rank's path is missing (as on a node without the file; here mpirun
    # gives rank 2 another path)
    (tmp_path / "box.walls").write_text("wall tank\n0 0\n1 0\n1 1\n0 1\nend\n")
    args = [flexslosh_bin(), "-fs_case", "tank", "-fs_tank_shape", "file", "-fs_dx", "0.05", "-ts_max_steps", "5",
            "-fs_progress", "0", "-fs_output_dir", tmp_path / "o", "-fs_tank_file"]
    proc = run_timed([mpirun_bin(), "--oversubscribe", "-n", 2] + args + [tmp_path / "box.walls", ":", "-n", 1] + args +
                              [tmp_path / "missing.walls"], tmp_path)
    assert proc.returncode != 0
    assert "Cannot open the wall file" in petsc_error_message(proc.stdout), proc.stdout[-3000:]


def test_an_output_dir_one_rank_cannot_write_ends_every_rank(tmp_path):
    # the output directory is read-only for rank 1 only (as on a node that mounts it read-only): rank 1 runs in a mount
    # namespace of its own (unshare, root only: skipped elsewhere) where the directory is a read-only bind mount of
    # itself. It hung in the first parallel HDF5 open; every rank now creates a file there before any parallel open
    out = tmp_path / "o"
    out.mkdir()
    readonly = f"mount --bind {out} {out} && mount -o remount,bind,ro {out}"
    if subprocess.run(["unshare", "-m", "--propagation", "private", "sh", "-c", readonly], capture_output=True).returncode:
        pytest.skip("cannot make a mount namespace here (unshare -m, root only)")
    args = [flexslosh_bin(), "-fs_case", "taylor_green", "-fs_dx", "0.05", "-ts_max_steps", "3", "-fs_progress", "0",
            "-fs_output_dir", out]
    proc = run_timed([mpirun_bin(), "--oversubscribe", "-n", 1] + args + [":", "-n", 1, "unshare", "-m", "--propagation",
                     "private", "sh", "-c", readonly + ' && exec "$0" "$@"'] + args, tmp_path)
    assert proc.returncode != 0
    assert f'Cannot write output directory "{out}" (option -fs_output_dir) on rank 1 of 2: Read-only file system' in \
        petsc_error_message(proc.stdout), proc.stdout[-3000:]
    assert not list(out.iterdir())  # nothing written, nothing left


# ranks given different options (an MPMD launch): one set for rank 0, one for rank 1, and the error's words
DIFFERENT = {
    # it hung, or ended in MPI_ERR_TRUNCATE in the first migration (issue 34)
    "dx": (["-fs_dx", "0.02"], ["-fs_dx", "0.04"], "-fs_dx is 0.02 on rank 0 and 0.04 on rank 1"),
    # it ran, each rank with its own viscosity
    "missing": (["-fs_dx", "0.05"], ["-fs_dx", "0.05", "-fs_nu", "0.001"], "-fs_nu is (not set) on rank 0 and 0.001 on rank 1"),
    # the same value written differently, and the diagnostics of one process: no error
    "same": (["-fs_dx", "0.05"], ["-fs_dx", "5e-2", "-info", ":sys"], None),
}


@pytest.mark.parametrize("name", list(DIFFERENT))
def test_ranks_given_different_options_stop_naming_the_option(tmp_path, name):
    first, second, words = DIFFERENT[name]
    args = [flexslosh_bin(), "-fs_case", "taylor_green", "-ts_max_steps", "3", "-fs_progress", "0", "-fs_output_dir",
            tmp_path / "o"]
    proc = run_timed([mpirun_bin(), "--oversubscribe", "-n", 1] + args + first + [":", "-n", 1] + args + second, tmp_path)
    if words is None:
        assert proc.returncode == 0, proc.stdout[-3000:]
        return
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    assert "The ranks were given different options: " + words in msg, proc.stdout[-3000:]
    assert "Every rank of a run must be given the same options" in msg


SCRIPT = """
import math
import sys
import flexslosh
from flexslosh import Solver
from flexslosh.solver import FlexsloshError
from mpi4py import MPI


class Breaking(flexslosh.structure.MassSpringDamper):
    def rhs(self, t, y, loads):
        if t > 0.01:
            raise ValueError(f"the spring broke at t = {t:.3f}")
        return super().rhs(t, y, loads)


class NaNEnergy(flexslosh.structure.MassSpringDamper):
    calls = 0

    def energy(self, y):
        self.calls += 1  # the kinetic energy NaN from the 50th call (rank 0), about the 10th step
        e = super().energy(y)
        return (math.nan if self.calls >= 50 else e[0], e[1], e[2])


flexslosh.register_structure("pybreak", Breaking)
flexslosh.register_structure("pynan", NaNEnergy)
options = {"fs_output": False, "fs_progress": False, "fs_dx": 0.01, "ts_max_steps": 200}
if sys.argv[1] == "structure":
    options["fs_structure"] = "pybreak"
if sys.argv[1] == "energy":  # energy.csv's values are checked, its structure's energy with them
    options.update(fs_structure="pynan", fs_output=True, fs_output_dir=sys.argv[3])
try:
    with Solver(options, options_file=sys.argv[2]) as s:
        s.run()
except FlexsloshError as e:
    if sys.argv[1] not in ("structure", "energy"):
        raise  # uncaught on this rank only: flexslosh ends every rank
    print(f"rank {MPI.COMM_WORLD.Get_rank()} caught: {str(e).splitlines()[0]}", flush=True)
"""


def run_script(tmp_path, nranks, mode, fault=None):
    script = tmp_path / "script.py"
    script.write_text(SCRIPT)
    return run_timed([mpirun_bin(), "--oversubscribe", "-n", nranks, sys.executable, script, mode,
                      REPO_ROOT / "cases" / "coupled_rectangular.opts", tmp_path / "o"], tmp_path, fault)


def test_a_python_structure_failing_on_rank_0_reaches_every_rank(tmp_path):
    proc = run_script(tmp_path, 3, "structure")
    assert proc.returncode == 0, proc.stdout[-3000:]
    for r in range(3):
        assert f"rank {r} caught: FSSolverSolve: Structure pybreak" in proc.stdout and "the spring broke" in proc.stdout


@pytest.mark.parametrize("nranks", [1, 2])
def test_a_python_structure_energy_not_finite_stops_every_rank(tmp_path, nranks):
    # issue 34: energy.csv took the NaN and the run went on; now the run stops before the row is written
    proc = run_script(tmp_path, nranks, "energy")
    assert proc.returncode == 0, proc.stdout[-3000:]
    for r in range(nranks):
        m = re.search(rf"rank {r} caught: FSSolverSolve: .*The run blew up: the structure's energy is not finite: structure "
                      r"pynan's kinetic energy is NaN at step (\d+), time [0-9.e-]+ \(state: [-0-9.e, ]+\)\. "
                      r"Likely cause: the model's energy routine", proc.stdout)
        assert m, proc.stdout[-3000:]
    energy = np.loadtxt(tmp_path / "o" / "energy.csv", delimiter=",", skiprows=1, ndmin=2)
    assert np.isfinite(energy).all() and energy[-1, 0] == int(m.group(1)) - 1


@pytest.mark.parametrize("nranks", [2, 3])
def test_an_uncaught_error_on_one_python_rank_ends_every_rank(tmp_path, nranks):
    # rank 1 raises FlexsloshError and nobody catches it: at exit flexslosh aborts the run (else PETSc's
    # finalization would wait for the ranks still in a collective)
    proc = run_script(tmp_path, nranks, "alloc", fault="alloc:1:3")
    assert proc.returncode != 0
    assert "FlexsloshError: FSSolverSolve: Allocation failed on rank 1 at step 3" in proc.stdout, proc.stdout[-3000:]

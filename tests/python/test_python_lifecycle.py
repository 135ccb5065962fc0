"""The Python front's life cycle (issue 34, item 8): each Solver reads its own options (none leak into the
next one), Ctrl-C stops run() between two steps with a consistent output and a checkpoint, a destroyed
solver's TS and swarm raise instead of crashing, and the swarm's fields are read-only (writes cannot
reach the particles, whose state is the TS's). 1 rank in this process; the interrupt in a subprocess."""
import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, run_flexslosh
import python_api_mpi as M

from flexslosh import Solver

TANK_FILE = str(REPO_ROOT / "cases" / "coupled_rectangular.opts")


def test_a_solvers_options_do_not_leak_into_the_next():
    """Solver A from coupled_rectangular.opts lives on while B runs Taylor-Green: B sees none of A's options
    (-fs_structure msd, -ts_max_time 3, -fs_delta_max 0.5), PETSc's default database none of either's, and A
    still reads its own after B is gone."""
    from petsc4py import PETSc

    with Solver(M.TANK, options_file=TANK_FILE) as a:
        assert a.options.getString("fs_structure") == "msd"
        assert not PETSc.Options().hasName("fs_structure") and not PETSc.Options().hasName("fs_dx")
        with Solver(dict(M.QUIET, fs_case="taylor_green", fs_dx=0.1)) as b:
            assert not b.options.hasName("fs_structure") and not b.options.hasName("fs_delta_max")
            assert b.options.getString("fs_case") == "taylor_green"
            b.set_up()
            assert b.ts.getMaxTime() != 3.0 and b.structure_state().size == 0
            assert b.energy()["work_ext"] == 0  # no structure
            b.step()
        a.set_up()  # the TS's and the structure's options are read here, from A's own database
        assert a.ts.getMaxTime() == 3.0 and a.structure_state().size == 2
        assert a.options.getString("fs_delta_max") == "0.5" and a.options.getString("fs_case") == "tank"
    assert not PETSc.Options().hasName("fs_case")


def test_destroyed_solver_raises_instead_of_crashing():
    """A destroyed solver's TS and swarm, fetched before or after destroy(), raise RuntimeError: petsc4py would
    pass the null handle to PETSc (an optimized build then dies of a segmentation fault)."""
    s = Solver(M.TG).set_up()
    ts, sw, opts = s.ts, s.swarm, s.options
    s.destroy()
    for use in (lambda: ts.getTime(), lambda: sw.getLocalSize(), lambda: sw.getField("position"),
                lambda: s.ts, lambda: s.swarm, lambda: s.options, lambda: opts.getAll(), lambda: s.time,
                lambda: s.step(), lambda: s.run(), lambda: s.positions()):
        with pytest.raises(RuntimeError, match="Solver has been destroyed"):
            use()
    assert ts.handle == 0 and sw.handle == 0
    s.destroy()  # idempotent


def test_swarm_fields_are_read_only():
    """The swarm mirrors the TS state (unpacked after each step): a write through getField could not reach the
    particles, so the array is read-only and the write raises."""
    with Solver(M.TG) as s:
        s.step()
        sw, x0 = s.swarm, s.positions()
        x = sw.getField("position")
        try:
            assert not x.flags.writeable
            with pytest.raises(ValueError, match="read-only"):
                x[0] = 1.0
            with pytest.raises(ValueError, match="read-only"):
                x += 1.0
        finally:
            sw.restoreField("position")
        assert np.array_equal(s.positions(), x0)


INTERRUPTED = """
import json, os, subprocess, sys, time
from flexslosh import Solver
opts = dict(fs_case="taylor_green", fs_dx=0.02, fs_progress=False, ts_max_steps=400, fs_output_interval=0,
            fs_checkpoint_interval=100000, fs_output_dir=sys.argv[1])
with Solver(opts) as s:
    s.step()
    # Ctrl-C from outside: the solver keeps the GIL in its calls, so no thread of this process could send it
    sent = os.path.join(sys.argv[1], "sent")
    subprocess.Popen(["/bin/sh", "-c", f"sleep 0.5; date +%s.%N > {sent}; kill -INT {os.getpid()}"])
    try:
        s.run()
        result = {"interrupted": False}
    except KeyboardInterrupt:
        result = {"interrupted": True, "step": s.step_number}
    result["delay"] = time.time() - float(open(sent).read())
    result["finished"] = s.finished
print("RESULT " + json.dumps(result))
"""


def test_ctrl_c_stops_run_at_a_step_with_consistent_output(tmp_path):
    """SIGINT during run() (no callback) raises KeyboardInterrupt after the step in progress, not at the end of
    the run; the output is the binary's run to that step, byte for byte in the CSVs, with a checkpoint of that
    step from which the binary goes on as the uninterrupted run."""
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    # SIGINT at its default in the child: a suite started in the background by a shell without job control runs
    # with SIGINT ignored, which the child would inherit (and the front rightly leaves an ignored SIGINT ignored)
    proc = subprocess.run([sys.executable, "-c", INTERRUPTED, str(tmp_path / "py")], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=120,
                          preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert proc.returncode == 0, proc.stdout[-3000:]
    result = json.loads(proc.stdout.split("RESULT ", 1)[1])
    assert result["interrupted"] and not result["finished"], result
    assert result["delay"] < 1.0, result  # one step of this run is about 0.05 s
    step = result["step"]
    checkpoint = tmp_path / "py" / f"checkpoint_{step:06d}.h5"
    assert checkpoint.is_file()
    # the binary's run 3 steps further: the interrupted run's files are its first rows, byte for byte (every
    # step has its row); and a restart from the checkpoint ends as it does
    tg = ["-fs_case", "taylor_green", "-fs_dx", 0.02, "-ts_max_steps", step + 3, "-fs_output_interval", 0]
    run_flexslosh(tg + ["-fs_output_dir", tmp_path / "binary"])
    for csv in ("timeseries.csv", "energy.csv"):
        py, binary = ((tmp_path / d / csv).read_bytes().splitlines(keepends=True) for d in ("py", "binary"))
        assert len(py) == step + 2 and py == binary[:step + 2], csv  # the header, steps 0..step
    run_flexslosh(tg + ["-fs_restart", checkpoint, "-fs_output_dir", tmp_path / "restart"])
    rows = (tmp_path / "restart" / "timeseries.csv").read_bytes().splitlines()
    assert rows[-3:] == (tmp_path / "binary" / "timeseries.csv").read_bytes().splitlines()[-3:]

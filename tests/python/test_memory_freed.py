"""Every byte a run takes from PETSc's allocator is given back by its end (-malloc_debug -malloc_dump lists what is
not, one line per block: "[rank] N bytes Function() at file:line").

The runs cover the paths a leak was found on: a restart (its set-up record's texts were not freed when nothing
differed), the registration tables (PetscFunctionList nodes never destroyed: the tables now live in plain memory
that outlives PetscFinalize), the error handler the program pushes (never popped). The other runs keep the
parts that allocate and free each step in view: the coupled tank on the modal beam (SLEPc), checkpoints, wall
sensors with faces on 2 ranks, a plug-in term, the 3-D baffled tank on 2 ranks."""
import re

import pytest

from conftest import REPO_ROOT, read_summary, run_flexslosh

DUMP = ["-malloc_debug", "-malloc_dump"]
UNFREED = re.compile(r"^\[\s*\d+\]\s*\d+ bytes \S+ at ")


def unfreed(proc):
    """The lines of -malloc_dump's report of unfreed blocks."""
    return [line for line in proc.output.splitlines() if UNFREED.match(line)]


def test_a_run_and_its_restart_free_everything(tmp_path):
    out = tmp_path / "o"
    base = ["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", "0.01", "-fs_output_dir", out]
    p = run_flexslosh(base + ["-ts_max_steps", "20", "-fs_checkpoint_interval", "10"] + DUMP, cwd=REPO_ROOT)
    assert not unfreed(p), unfreed(p)[:10]
    p = run_flexslosh(base + ["-ts_max_steps", "30", "-fs_restart", out / "checkpoint_000020.h5"] + DUMP, cwd=REPO_ROOT)
    assert read_summary(out)["steps"] == 10  # the 10 steps after the checkpoint's 20
    assert not unfreed(p), unfreed(p)[:10]


@pytest.mark.parametrize("name,nranks,args", [
    ("modal beam", 1, ["-options_file", "cases/coupled_rectangular.opts", "-fs_structure", "modal", "-fs_dx", "0.01",
                       "-ts_max_steps", "10"]),
    ("sensors on 2 ranks", 2, ["-options_file", "cases/dam_break_lobovsky.opts", "-fs_dx", "0.03", "-ts_max_steps", "20"]),
    ("plug-in term", 1, ["-options_file", "cases/roll_tank.opts", "-fs_dx", "0.02", "-ts_max_steps", "10",
                         "-dll_append", "LIBFSDRAG", "-fs_terms", "continuity,delta,pressure,viscosity,les_viscosity,"
                         "gravity,wall_continuity,wall_pressure,wall_viscosity,drag"]),
    ("3-D on 2 ranks", 2, ["-options_file", "cases/coupled_baffled_3d.opts", "-fs_dx", "0.02", "-ts_max_steps", "3"]),
])
def test_runs_free_everything(tmp_path, name, nranks, args):
    from conftest import plugin_path
    args = [str(plugin_path()) if a == "LIBFSDRAG" else a for a in args]
    p = run_flexslosh(args + ["-fs_output_dir", tmp_path / "o"] + DUMP, nranks=nranks, cwd=REPO_ROOT)
    assert not unfreed(p), unfreed(p)[:10]

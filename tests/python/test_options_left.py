"""Options given but never used (a misspelt -fs_dx_) are reported at the end of a run, by the executable
and by the Python package; -fs_options_left 0 or PETSc's -options_left (true or false) turns it off."""
import os
import subprocess
import sys

import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, run_flexslosh

SMALL = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-fs_output_interval", "0", "-ts_max_steps", "2"]
WARNING = "Warning: option -fs_dx_ 0.1 was given but never used"


def test_misspelt_option_is_reported(tmp_path):
    proc = run_flexslosh(SMALL + ["-fs_dx_", "0.1", "-fs_output_dir", tmp_path / "o"], cwd=tmp_path)
    assert proc.stdout.count(WARNING) == 1, proc.stdout
    assert "-fs_options_left 0" in proc.stdout


def test_misspelt_option_is_reported_once_on_two_ranks(tmp_path):
    proc = run_flexslosh(SMALL + ["-fs_dx_", "0.1", "-fs_output_dir", tmp_path / "o"], nranks=2, cwd=tmp_path)
    assert proc.stdout.count(WARNING) == 1, proc.stdout


@pytest.mark.parametrize("off", [["-fs_options_left", "0"], ["-options_left", "0"]])
def test_report_can_be_turned_off(tmp_path, off):
    proc = run_flexslosh(SMALL + ["-fs_dx_", "0.1", "-fs_output_dir", tmp_path / "o"] + off, cwd=tmp_path)
    assert "-fs_dx_" not in proc.stdout, proc.stdout


def test_petsc_options_left_replaces_the_report(tmp_path):
    proc = run_flexslosh(SMALL + ["-fs_dx_", "0.1", "-fs_output_dir", tmp_path / "o", "-options_left"], cwd=tmp_path)
    assert WARNING not in proc.stdout and "Option left: name:-fs_dx_ value: 0.1" in proc.stdout, proc.stdout


@pytest.mark.parametrize("case", ["taylor_green", "dam_break", "coupled_rectangular", "beam_free_decay_modal",
                                  "coupled_baffled_3d"])
def test_case_files_leave_no_option_unused(tmp_path, case):
    args = ["-options_file", REPO_ROOT / "cases" / f"{case}.opts", "-ts_max_steps", "1", "-fs_output", "0"]
    if case == "coupled_baffled_3d":
        args += ["-fs_geometry_view"]  # set-up only: stops before the first step
    proc = run_flexslosh(args, cwd=tmp_path)
    assert "never used" not in proc.stdout, proc.stdout


SCRIPT = """
import sys
from flexslosh import Solver
opts = {"fs_case": "taylor_green", "fs_dx": 0.05, "fs_dx_": 0.1, "ts_max_steps": 2, "fs_progress": False,
        "fs_output_dir": sys.argv[1], "fs_output_interval": 0}
if sys.argv[2] == "off":
    opts["fs_options_left"] = False
with Solver(opts) as s:
    s.run()
with Solver({k: v for k, v in opts.items() if k != "fs_dx_"}) as s:  # the option went with its solver
    s.run()
print("done")
"""


@pytest.mark.parametrize("mode", ["on", "off"])
def test_python_solver_reports_its_unused_options(tmp_path, mode):
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(tmp_path / "o"), mode], env=env, cwd=tmp_path,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    assert proc.returncode == 0 and "done" in proc.stdout, proc.stdout
    assert proc.stdout.count(WARNING) == (1 if mode == "on" else 0), proc.stdout

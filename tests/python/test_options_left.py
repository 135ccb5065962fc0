"""Options nothing reads. A -fs_ option that no object reads (misspelt, -fs_dx_, or an option of an object the run
does not use) is refused before the first step, naming the registered options nearest to it (FSSolverCheckOptions,
src/solver/optionscheck.c); the Python front refuses its file's and dict's. Other options (-ts_*, PETSc's) are
reported at the end of the run as before; -fs_options_left 0 or PETSc's -options_left (true or false) turns that
report off, -fs_options_check 0 the refusal."""
import os
import subprocess
import sys

import pytest

from conftest import MPI_ENV, REPO_ROOT, build_dir, petsc_error_message, plugin_path, run_flexslosh

SMALL = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-fs_output_interval", "0", "-ts_max_steps", "2"]
WARNING = "Warning: option -fs_dx_ 0.1 was given but never used"
TS_WARNING = "Warning: option -ts_max_stepz 3 was given but never used"


def refused(tmp_path, extra, nranks=1):
    """The run with extra options: it must stop before its first step; returns PETSc's error message."""
    out = tmp_path / "o"
    proc = run_flexslosh(SMALL + ["-fs_output_dir", out] + extra, nranks=nranks, cwd=tmp_path, check=False)
    assert proc.returncode != 0, proc.stdout
    assert not (out / "timeseries.csv").exists(), "a step was taken"
    return petsc_error_message(proc.stdout)


def test_misspelt_option_is_refused_with_the_nearest_names(tmp_path):
    msg = refused(tmp_path, ["-fs_dx_", "0.1"])
    assert "-fs_dx_ is not an option of flexslosh: did you mean -fs_dx (the solver)" in msg, msg
    assert "-fs_options_check 0" in msg


def test_misspelt_motion_is_refused_on_two_ranks(tmp_path):
    # the case: the roll's option misspelt ran the whole run without roll
    msg = refused(tmp_path, ["-fs_structure", "prescribed", "-fs_motion_roll_sine", "5,1,0"], nranks=2)
    assert msg.count("-fs_motion_roll_sine is not an option of flexslosh: did you mean -fs_motion_roll_sines "
                     "(structure model prescribed)") == 1, msg


def test_options_of_objects_not_in_use_are_refused(tmp_path):
    msg = refused(tmp_path, ["-fs_shifting_c", "0.5", "-fs_Beam_E", "1e9", "-fs_tank_fill", "0.5"])
    assert ("-fs_shifting_c is an option of the term shifting, which this run does not use (-fs_terms is "
            "continuity,delta,pressure,viscosity,les_viscosity,gravity)") in msg, msg
    assert ("-fs_Beam_E is an option of the structure model msd or the structure model modal, which this run does "
            "not use (-fs_structure is none)") in msg, msg
    assert "-fs_tank_fill is not an option of flexslosh: did you mean -fs_tank_file (case tank)" in msg, msg
    assert "3 options given that nothing reads" in msg, msg


def test_options_known_only_at_set_up_are_judged_there(tmp_path):
    msg = refused(tmp_path, ["-fs_walls_noslip", "floor", "-fs_tg_depth", "1"])
    assert "-fs_tg_depth is an option of the case taylor_green that this set-up does not read" in msg, msg
    msg = refused(tmp_path, ["-fs_walls_noslip", "floor"])
    assert "-fs_walls_noslip is an option of the walls, which this run does not use (the case taylor_green " \
           "has no walls)" in msg, msg
    # raised by the set-up (its frame is in the full report, -fs_error_trace)
    assert "FSSolverSetUp" in run_flexslosh(SMALL + ["-fs_walls_noslip", "floor", "-fs_error_trace"], cwd=tmp_path,
                                            check=False).stdout


def test_plugin_and_sub_object_options(tmp_path):
    drag = ["-dll_append", plugin_path(), "-fs_drag_rate", "2"]
    msg = refused(tmp_path, drag)
    assert "-fs_drag_rate is an option of the term drag, which this run does not use" in msg, msg
    msg = refused(tmp_path, ["-fs_modal_eps_tol", "1e-10"])
    assert "-fs_modal_eps_tol is an option of the structure model modal, which this run does not use" in msg, msg
    beam = ["-fs_case", "beam", "-fs_structure", "modal", "-ts_max_steps", "1", "-fs_output", "0"]
    proc = run_flexslosh(beam + ["-fs_modal_eps_tol", "1e-10"], cwd=tmp_path)  # read by SLEPc at set-up
    assert "nothing reads" not in proc.stdout and "never used" not in proc.stdout, proc.stdout


def test_check_off_and_other_options_reported_at_the_end(tmp_path):
    proc = run_flexslosh(SMALL + ["-fs_dx_", "0.1", "-fs_options_check", "0", "-ts_max_stepz", "3",
                                  "-fs_output_dir", tmp_path / "o"], cwd=tmp_path)
    assert proc.stdout.count(WARNING) == 1 and proc.stdout.count(TS_WARNING) == 1, proc.stdout
    assert "-fs_options_left 0" in proc.stdout


@pytest.mark.parametrize("off", [["-fs_options_left", "0"], ["-options_left", "0"]])
def test_report_can_be_turned_off(tmp_path, off):
    proc = run_flexslosh(SMALL + ["-ts_max_stepz", "3", "-fs_output_dir", tmp_path / "o"] + off, cwd=tmp_path)
    assert "-ts_max_stepz" not in proc.stdout, proc.stdout


def test_petsc_options_left_replaces_the_report(tmp_path):
    proc = run_flexslosh(SMALL + ["-ts_max_stepz", "3", "-fs_output_dir", tmp_path / "o", "-options_left"],
                         cwd=tmp_path)
    assert TS_WARNING not in proc.stdout and "Option left: name:-ts_max_stepz value: 3" in proc.stdout, proc.stdout


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
from flexslosh.solver import FlexsloshError, set_options
opts = {"fs_case": "taylor_green", "fs_dx": 0.05, "ts_max_steps": 2, "fs_progress": False,
        "fs_output_dir": sys.argv[1], "fs_output_interval": 0}
try:
    Solver(dict(opts, fs_dx_=0.1))
except FlexsloshError as e:
    print("construction:", e)
s = Solver(dict(opts, fs_walls_noslip="floor"))
try:
    s.run()
except FlexsloshError as e:
    print("set-up:", e)
s.destroy()
set_options({"fs_motion_x_sines": "0.01,1,0"})  # the process's options: for the solvers that read them
with Solver(dict(opts, ts_max_stepz=3)) as s:  # not an -fs_ option: reported when the solver goes
    s.run()
print("done")
"""


def test_python_solver_refuses_its_misspelt_options(tmp_path):
    env = dict(os.environ, **MPI_ENV, FLEXSLOSH_BUILD=str(build_dir()))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "python"), env.get("PYTHONPATH", "")])
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(tmp_path / "o")], env=env, cwd=tmp_path,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    assert proc.returncode == 0 and "done" in proc.stdout, proc.stdout
    assert "construction: FSSolverSetFromOptions: 1 option given that nothing reads:\n  -fs_dx_ is not an option " \
           "of flexslosh: did you mean -fs_dx (the solver)" in proc.stdout, proc.stdout
    assert "set-up: FSSolverSetUp: 1 option given that nothing reads:\n  -fs_walls_noslip is an option of the walls" \
        in proc.stdout, proc.stdout
    assert proc.stdout.count("Warning: option -ts_max_stepz 3 was given but never used") == 1, proc.stdout

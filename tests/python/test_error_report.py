"""An error's report is short: the message given where the error was raised, where (function, file and line; for
an error inside PETSc, the first flexslosh function on the way out), and the option for PETSc's full report
(-fs_error_trace), each line starting with "[rank] flexslosh:"; on several ranks every rank ends at once with a
non-zero status (src/sys/errors.c, app/flexslosh.c; docs/running.md, "Errors")."""
import time

from conftest import petsc_error_message, run_flexslosh

TG = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-ts_max_steps", "2"]
NOISE = ("Configure options", "petsc-maint", "Option Table", "PETSC ERROR", "Petsc Release Version")


def report(proc):
    return [line for line in proc.stdout.splitlines() if line.startswith("[0] flexslosh:")]


def test_an_error_of_ours_is_three_lines(tmp_path):
    proc = run_flexslosh(TG + ["-fs_dx", "-1", "-fs_output_dir", tmp_path / "o"], cwd=tmp_path, check=False)
    assert proc.returncode == 63, proc.stdout  # PETSC_ERR_ARG_OUTOFRANGE, the status of the run
    lines = report(proc)
    assert lines[0] == "[0] flexslosh: error: -fs_dx -1 is out of range: expected a positive number", proc.stdout
    assert lines[1].startswith("[0] flexslosh:   in FSOptionsReal() at src/sys/options.c:"), lines
    assert lines[1].endswith("(PETSc error 63: Argument out of range)"), lines
    assert "-fs_error_trace" in lines[2] and len(lines) == 3, lines
    assert len(proc.stdout.splitlines()) == 3 and not any(n in proc.stdout for n in NOISE), proc.stdout
    # the tests' reader of error messages finds it
    assert "-fs_dx -1 is out of range" in petsc_error_message(proc.stdout)


def test_an_error_inside_petsc_names_the_flexslosh_function_that_called(tmp_path):
    proc = run_flexslosh(TG + ["-ts_type", "nosuch", "-fs_output_dir", tmp_path / "o"], cwd=tmp_path, check=False)
    assert proc.returncode == 86, proc.stdout  # PETSC_ERR_UNKNOWN_TYPE
    lines = report(proc)
    assert lines[0] == "[0] flexslosh: error: Unknown TS type: nosuch", proc.stdout
    assert lines[1].startswith("[0] flexslosh:   in TSSetType() at "), lines
    assert lines[2].startswith("[0] flexslosh:   called from FSSolverSetUpTS() at src/solver/stepping.c:"), lines
    assert lines[2].endswith("through TSSetFromOptions()"), lines
    assert len(lines) == 4 and not any(n in proc.stdout for n in NOISE), proc.stdout


def test_error_trace_gives_petscs_full_report(tmp_path):
    proc = run_flexslosh(TG + ["-fs_dx", "-1", "-fs_error_trace", "-fs_output_dir", tmp_path / "o"], cwd=tmp_path,
                         check=False)
    assert proc.returncode == 63
    assert "Configure options" in proc.stdout and "#1 FSOptionsReal() at" in proc.stdout, proc.stdout
    assert "-fs_dx -1 is out of range" in petsc_error_message(proc.stdout)


def test_a_missing_options_file_is_one_line(tmp_path):
    proc = run_flexslosh(["-options_file", tmp_path / "none.opts"], cwd=tmp_path, check=False)
    assert proc.returncode != 0
    assert proc.stdout.strip() == f"[0] flexslosh: error: cannot read options file {tmp_path / 'none.opts'}: " \
                                  "No such file or directory", proc.stdout


def test_an_error_on_one_rank_of_three_ends_every_rank_at_once(tmp_path):
    t0 = time.time()
    proc = run_flexslosh(TG + ["-fs_dx", "-1", "-fs_output_dir", tmp_path / "o"], nranks=3, cwd=tmp_path, check=False,
                         timeout=60)
    assert proc.returncode != 0
    assert time.time() - t0 < 8, "PETSc's handler kept the other ranks 10 s"
    lines = [line for line in proc.stdout.splitlines() if "flexslosh:" in line]
    assert lines[0] == "[0] flexslosh: error: -fs_dx -1 is out of range: expected a positive number", proc.stdout
    assert len(lines) == 3, proc.stdout  # printed once, by rank 0 of the communicator
    assert not any(n in proc.stdout for n in NOISE), proc.stdout

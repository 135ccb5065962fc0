"""Without -fs_output_dir a run writes into a directory of its own, output/<name>-<YYYYMMDD-HHMMSS> (-2, -3, ...
when a run of the same second took it), named after the options file (-fs_output_name), so that a second run of
the same case or of another keeps the first's results; a restart continues in its checkpoint's directory
(docs/running.md, "The output directory")."""
import re

from conftest import REPO_ROOT, petsc_error_message, read_series, run_flexslosh

TG = ["-fs_dx", "0.05", "-ts_max_steps", "2", "-fs_output_interval", "0"]
STAMP = r"\d{8}-\d{6}(-\d+)?"


def said_dir(proc):
    m = re.search(r"^Output directory: (\S+) \(new for this run", proc.stdout, re.M)
    assert m, proc.stdout
    return m.group(1)


def test_two_runs_of_one_case_keep_both_results(tmp_path):
    opts = REPO_ROOT / "cases" / "taylor_green.opts"
    first = run_flexslosh(["-options_file", opts] + TG, cwd=tmp_path)
    second = run_flexslosh(["-options_file", opts] + TG + ["-ts_max_steps", "3"], cwd=tmp_path)
    a, b = said_dir(first), said_dir(second)
    assert re.fullmatch(r"output/taylor_green-" + STAMP, a) and re.fullmatch(r"output/taylor_green-" + STAMP, b)
    assert a != b
    assert read_series(tmp_path / a)["step"][-1] == 2 and read_series(tmp_path / b)["step"][-1] == 3
    assert "removed the earlier run's results" not in first.stdout + second.stdout


def test_the_name_comes_from_the_option_else_the_case(tmp_path):
    named = run_flexslosh(["-fs_case", "taylor_green", "-fs_output_name", "mine"] + TG, cwd=tmp_path)
    assert re.fullmatch(r"output/mine-" + STAMP, said_dir(named))
    plain = run_flexslosh(["-fs_case", "taylor_green"] + TG, cwd=tmp_path)
    assert re.fullmatch(r"output/taylor_green-" + STAMP, said_dir(plain))
    bad = run_flexslosh(["-fs_case", "taylor_green", "-fs_output_name", "a/b"] + TG, cwd=tmp_path, check=False)
    assert bad.returncode != 0
    assert "-fs_output_name \"a/b\": expected a name without '/'" in petsc_error_message(bad.stdout)


def test_a_given_directory_is_used_as_before_and_a_restart_continues_its_checkpoints(tmp_path):
    given = run_flexslosh(["-fs_case", "taylor_green", "-fs_output_dir", "mine", "-fs_checkpoint_interval", "2"] + TG,
                          cwd=tmp_path)
    assert "Output directory:" not in given.stdout and (tmp_path / "mine" / "checkpoint_000002.h5").exists()
    run_flexslosh(["-fs_case", "taylor_green", "-fs_restart", "mine/checkpoint_000002.h5"] + TG +
                  ["-ts_max_steps", "4"], cwd=tmp_path)
    assert read_series(tmp_path / "mine")["step"][-1] == 4
    assert not (tmp_path / "output").exists()

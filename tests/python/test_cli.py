"""Command line: -help, the registry listings, options files and summary.json."""
import re

import numpy as np
import pytest

from conftest import REPO_ROOT, TG, read_series, read_summary, run_flexslosh, snapshot_files

SOLVER_C = REPO_ROOT / "src" / "solver" / "solver.c"


def registered_options():
    """(option, kind, default field) for every PetscOptions*("-fs_...") call in src/solver/solver.c."""
    src = SOLVER_C.read_text()
    calls = re.findall(r'(?:PetscOptions|FSOptions)(\w+)\(\s*(?:PetscOptionsObject,\s*)?"(-fs_\w+)"\s*,\s*"(?:[^"\\]|\\.)*"\s*,\s*"[^"]*"\s*,\s*([^,]+),', src)
    assert len(calls) >= 25, f"parsed only {len(calls)} options from {SOLVER_C}: regex out of date?"
    return calls


def literal_defaults():
    """Field -> literal default assigned in FSSolverCreate (s->cfl = 0.4; ...)."""
    src = SOLVER_C.read_text()
    body = src[src.index("PetscErrorCode FSSolverCreate("):src.index("PetscErrorCode FSSolverSetDefaultPhysics(")]
    return {f: float(v) for f, v in re.findall(r"s->(?:\w+\.)?(\w+)\s*=\s*([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s*;", body)}


@pytest.fixture(scope="module")
def help_output(tmp_path_factory):
    from conftest import run_flexslosh

    proc = run_flexslosh(["-help"], cwd=tmp_path_factory.mktemp("help"))
    assert proc.returncode == 0
    return proc.stdout


def help_value(help_text, option):
    """The first value shown in <...> after the option in -help, e.g. '0.4' for '-fs_cfl <0.4 : 0.4>'."""
    m = re.search(r"^\s*" + re.escape(option) + r":? <(?:now )?([^ :>]*)", help_text, re.M)
    return m.group(1) if m else None


def test_help_lists_every_solver_option(help_output):
    missing = [opt for _, opt, _ in registered_options() if help_value(help_output, opt) is None]
    assert not missing, f"options registered in solver.c but not shown by -help: {missing}"


def test_help_shows_defaults(help_output):
    defaults = literal_defaults()
    # defaults the taylor_green case (the default case) sets before the options are read
    case_defaults = {"-fs_dx": 0.02, "-fs_rho0": 1.0, "-fs_c0": 10.0, "-fs_nu": 0.01}
    checked = 0
    for kind, opt, field in registered_options():
        field = field.strip()
        if kind not in ("Real", "Int"):
            continue
        shown = help_value(help_output, opt)
        if opt in case_defaults:
            expected = case_defaults[opt]
        else:
            m = re.match(r"&?s->(?:\w+\.)?(\w+)$", field)
            if not m or m.group(1) not in defaults:
                continue
            expected = defaults[m.group(1)]
        assert shown is not None and float(shown) == pytest.approx(expected, rel=1e-12), f"{opt}: -help shows <{shown}>, default is {expected}"
        checked += 1
    assert checked >= 15
    assert "-fs_cfl <0.4" in help_output
    assert re.search(r"-fs_case <now taylor_green", help_output)
    assert re.search(r"-fs_terms <now continuity,delta,pressure,viscosity,les_viscosity,gravity", help_output)


def test_help_shows_monitor_defaults(help_output):
    """The built-in monitors' options (src/monitor/impls/, read in the solver's options block): -help shows each with
    the default its monitor's create routine gives (0 where none: PetscNew)."""
    checked = {}
    for path in sorted((REPO_ROOT / "src" / "monitor" / "impls").rglob("*.c")):
        src = path.read_text()
        for kind, opt, field in re.findall(r'FSOptions(Real|Int)\(\s*PetscOptionsObject,\s*"(-fs_\w+)"\s*,\s*(?:"(?:[^"\\]|\\.)*"\s*)+'
                                           r',\s*"[^"]*"\s*,\s*&\w+->(\w+)\s*,', src):
            m = re.search(r"\w+->(?:\w+\.)?" + field + r"\s*=\s*([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s*;", src)
            expected = float(m.group(1)) if m else 0.0
            shown = help_value(help_output, opt)
            assert shown is not None and float(shown) == pytest.approx(expected, rel=1e-12), f"{opt} ({path.name}): -help shows <{shown}>, default is {expected}"
            checked[opt] = expected
    assert {"-fs_output_interval", "-fs_checkpoint_interval", "-fs_probe_interval", "-fs_progress_interval",
            "-fs_rest_check_time", "-fs_rest_check_speed", "-fs_rest_check_dt"} <= set(checked), checked


def test_help_lists_ts_options(help_output):
    for opt in ("-ts_type", "-ts_max_time", "-ts_max_steps"):
        assert re.search(r"^\s*" + opt + r" <", help_output, re.M), f"{opt} not in -help"
    assert "rk" in re.search(r"^\s*-ts_type <.*$", help_output, re.M).group(0)


def test_help_shows_actual_ts_defaults(help_output):
    assert re.search(r"^\s*-ts_type <now rk4lean\b", help_output, re.M)


def listing(output, header):
    """Names in a registry listing: the indented lines after the header line."""
    lines = output.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith(header))
    names = []
    for line in lines[start + 1:]:
        m = re.match(r"^\s+(\w+)\s{2,}\S", line)
        if not m:
            break
        names.append(m.group(1))
    return lines[start], names


def test_terms_view(run):
    proc = run(["-fs_terms_view", "-ts_max_steps", "0", "-fs_output", "0"])
    header, names = listing(proc.stdout, "Registered physics terms")
    builtin = ["continuity", "delta", "pressure", "viscosity", "les_viscosity", "gravity"]
    missing = [t for t in builtin if t not in names]
    assert not missing, f"built-in terms not listed: {missing}"
    # exactly the terms src/package.c registers, each once, and the count in the header agrees
    registered = re.findall(r'FSTermRegister\(\s*"(\w+)"', (REPO_ROOT / "src" / "terms" / "interface" / "terms.c").read_text())
    assert sorted(names) == sorted(registered)
    assert f"({len(names)})" in header


def test_case_view(run):
    proc = run(["-fs_case_view", "-ts_max_steps", "0", "-fs_output", "0"])
    _, names = listing(proc.stdout, "Registered cases")
    # exactly the cases src/cases.c registers, each once
    registered = re.findall(r'FSCaseRegister\(\s*"(\w+)"', (REPO_ROOT / "src" / "cases" / "interface" / "cases.c").read_text())
    assert {"shear", "taylor_green", "beam"} <= set(names)
    assert sorted(names) == sorted(registered)


def test_options_file_runs(run, tmp_path):
    opts = REPO_ROOT / "cases" / "taylor_green.opts"
    run(["-options_file", opts, "-ts_max_steps", "3", "-fs_output_dir", tmp_path / "out"])
    s = read_summary(tmp_path / "out")
    assert s["case"] == "taylor_green"
    assert s["particles"] == 50 * 50  # -fs_dx 0.02 from the file
    assert s["steps"] == 3
    assert "-fs_tg_Re 100" in s["options"]


def test_command_line_overrides_options_file(run, tmp_path):
    opts = tmp_path / "run.opts"
    opts.write_text("# a comment\n-fs_case taylor_green\n-fs_dx 0.05\n-ts_max_steps 2\n-fs_output_dir from_file\n")
    run(["-options_file", opts])
    assert read_summary(tmp_path / "from_file")["particles"] == 20 * 20
    # given after -options_file, a command-line option wins (PETSc reads the arguments in order)
    run(["-options_file", opts, "-fs_dx", "0.04", "-fs_output_dir", tmp_path / "cli"])
    s = read_summary(tmp_path / "cli")
    assert s["particles"] == 25 * 25
    assert s["dx"] == pytest.approx(0.04)
    assert not (tmp_path / "cli" / "from_file").exists()


def test_summary_json(run, tmp_path):
    out = tmp_path / "out"
    run(TG + ["-fs_dx", "0.05", "-ts_max_steps", "4", "-fs_output_dir", out])
    s = read_summary(out)
    for key in ("program", "case", "dim", "ranks", "particles", "steps", "wall_time", "particle_steps_per_second",
                "pair_visits_per_second", "peak_memory_bytes", "options"):
        assert key in s, f"summary.json lacks {key}"
    assert s["program"].startswith("flexslosh")
    assert s["case"] == "taylor_green" and s["dim"] == 2 and s["ranks"] == 1
    assert s["particles"] == 400 and s["steps"] == 4
    assert s["wall_time"] > 0
    # 4 steps of 400 particles were done in wall_time
    assert s["particle_steps_per_second"] == pytest.approx(4 * 400 / s["wall_time"], rel=1e-6)
    assert s["pair_visits_per_second"] > s["particle_steps_per_second"]
    assert 1e6 < s["peak_memory_bytes"] < 1e10
    assert "-fs_dx 0.05" in s["options"] and "-ts_max_steps 4" in s["options"]
    # output interval 0: the first and the last snapshot only
    assert len(snapshot_files(out)) == 2


def test_progress_line(run, tmp_path):
    """The progress monitor: with -fs_progress_interval 0 a line after each step (none for the start), the time and
    the share of -ts_max_time growing, with the output files or without (-fs_output 0); none with -fs_progress 0; and
    summary.json (the summary monitor) only with the output."""
    for k, extra in enumerate(([], ["-fs_output", "0"])):
        out = tmp_path / f"out{k}"
        proc = run(TG + ["-fs_dx", "0.1", "-ts_max_steps", "3", "-ts_max_time", "1", "-fs_progress_interval", "0",
                         "-fs_output_dir", out] + extra, progress=True)
        lines = re.findall(r"^step +(\d+)  t = (\S+) +dt = (\S+) +([\d.]+)%  elapsed +[\d.]+ s  left ~ *[\d.]+ s$",
                           proc.stdout, re.M)
        assert [int(l[0]) for l in lines] == [1, 2, 3], proc.stdout
        t = [float(l[1]) for l in lines]
        assert 0 < t[0] < t[1] < t[2] < 1
        assert [float(l[3]) for l in lines] == pytest.approx([100 * x for x in t], abs=0.06)
        assert (out / "summary.json").exists() == (not extra)
    proc = run(TG + ["-fs_dx", "0.1", "-ts_max_steps", "3", "-fs_progress_interval", "0", "-fs_progress", "0",
                     "-fs_output", "0"], progress=True)
    assert not re.search(r"^step ", proc.stdout, re.M)


@pytest.mark.parametrize("opts", sorted(p.name for p in (REPO_ROOT / "cases").glob("*.opts")))
def test_case_files_run(tmp_path, opts):
    """Every case file in cases/ sets up and takes a few steps as written (its resolution included), from
    the repository's root, against which case files name their data files (cases/data/)."""
    run_flexslosh(["-options_file", REPO_ROOT / "cases" / opts, "-ts_max_steps", 3, "-fs_output_interval", 0,
                   "-fs_output_dir", tmp_path / "o"], cwd=REPO_ROOT, timeout=300)
    assert (tmp_path / "o" / "summary.json").exists()


@pytest.mark.parametrize("opts", ["coupled_rectangular.opts", "coupled_baffled.opts"])
def test_coupled_case_files_run_with_the_modal_beam(tmp_path, opts):
    """The seed's coupled cases run with either structure model: the case files choose msd, and
    -fs_structure modal gives the tank's translation and rotation from the SLEPc modes."""
    out = tmp_path / "o"
    run_flexslosh(["-options_file", REPO_ROOT / "cases" / opts, "-fs_structure", "modal", "-ts_max_steps", 20,
                   "-fs_output_interval", 0, "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    s = read_series(out)
    assert s["tip_displacement"][0] == pytest.approx(0.04, rel=1e-4)  # the static shape in 5 modes
    assert s["tip_displacement"][-1] < s["tip_displacement"][0] and np.abs(s["tank_rotation"]).max() > 0

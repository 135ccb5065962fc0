"""The validation report's machinery (python/flexslosh/validate.py) keeps working: the quick mode of four
cheap cases (the beam, Taylor-Green, the rolled tank, the impact peaks against c0) runs into a temporary folder and writes its sections, figures and
report. Only the structure is checked here, not the physics (the physics tests check that), and the
quick mode's coarse numbers are allowed to FAIL their tolerances."""
import json
import re

import numpy as np

import pytest

from conftest import REPO_ROOT, build_dir

validate = pytest.importorskip("flexslosh.validate")


def test_quick_report(tmp_path):
    out, work = tmp_path / "report", tmp_path / "runs"
    rc = validate.main(["--quick", "--cases", "beam,taylor_green,roll_tank,impact_c0", "--out", str(out), "--work", str(work),
                        "--build", str(build_dir())])
    assert rc == 0
    report = (out / "README.md").read_text()
    # one section per case, in the order of CASES; the cases not run say so with their command
    heads = re.findall(r"^## (.+)$", report, re.M)
    assert heads == [validate.TITLES[c] for c in validate.CASES]
    assert "Not run in this report" in report and "make validate CASES=seed" in report
    for name in ("beam", "taylor_green", "roll_tank", "impact_c0"):
        summary = json.loads((out / "sections" / f"{name}.json").read_text())
        section = summary["markdown"]
        assert section in report
        for part in ("**Compared.**", "**Reference.**", "| measured | value | tolerance |", "| run | particles | wall time | command |",
                     "--quick smoke run"):
            assert part in section, (name, part)
        rows = re.findall(r"^\| .+ \| (PASS|\*\*FAIL\*\*) \|$", section, re.M)
        assert rows, section
        # the figure: a PNG in the report's folder, linked from the section, small
        fig = re.search(r"!\[[^\]]+\]\(([^)]+\.png)\)", section).group(1)
        png = out / fig
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size < 200_000
        assert summary["checks"] == len(rows) and summary["wall"] >= 0
    # the bare beam's modes are exact whatever the mode: that check passes
    assert re.search(r"modes 1-5: max abs relative frequency error \| \S+ \| <= \S+ \| PASS", report)
    # nothing in the report points outside the report's folder but the repository's docs
    assert "/tmp" not in report and str(REPO_ROOT) not in report


def test_bad_arguments(capsys):
    assert validate.main(["--cases", "no_such_case"]) == 2
    assert "unknown case" in capsys.readouterr().err
    assert validate.main(["--resolution", "taylor_green"]) == 2


def test_spheric10_data(tmp_path):
    """SPHERIC test 10's data: the roll file the case reads is what flexslosh.rollmotion rebuilds from the
    copied rows of the record and passes through them; the pressure record's four impacts are found."""
    import numpy as np

    from flexslosh import rollmotion
    from flexslosh.output import read_csv

    out = tmp_path / "roll.txt"
    rollmotion.write_roll_file(out=out)
    assert out.read_text() == rollmotion.ROLL_FILE.read_text(), "cases/data/spheric10_roll.txt is stale: python3 -m flexslosh.rollmotion"
    rows = np.loadtxt(rollmotion.SAMPLES)
    assert len(rows) == 71 and np.all(np.diff(rows[:, 0]) > 0)
    assert np.max(np.abs(rollmotion.reconstruct(rows[:, 0], rows[:, 1], rows[:, 0]) - rows[:, 1])) < 1e-3
    roll = np.loadtxt(rollmotion.ROLL_FILE)
    assert roll[0, 0] == 0 and roll[0, 1] == 0 and roll[-1, 0] >= 8.0 and 3.8 < np.max(np.abs(roll[:, 1])) < 4.2
    exp = read_csv(REPO_ROOT / "docs" / "validation" / "data" / "spheric10_lateral_water_pressure.csv")
    assert len(exp["t"]) == 3341 and np.all(np.diff(exp["t"]) >= 0)
    figs = validate.impact_figures(exp["t"], exp["p"], validate.SPHERIC10_IMPACTS)
    assert [round(f["arrival"], 3) for f in figs] == [2.375, 4.05, 5.672, 7.303]
    assert [round(f["peak"]) for f in figs] == [3683, 3890, 2663, 7148]


def test_impact_figures():
    """impact_figures on a made-up record: a step to 2 kPa at t = 1 with a 5 kPa spike, nothing in the second window."""
    import math

    import numpy as np

    t = np.linspace(0, 3, 3001)
    p = np.where(t >= 1.0, 2000.0, 0.0)
    p[t == 1.0] = 5000.0
    f = validate.impact_figures(t, p, [(0.5, 1.5), (1.6, 1.9)], threshold=1000.0)
    assert f[0]["arrival"] == 1.0 and f[0]["peak"] == 5000.0 and f[0]["plateau"] == 2000.0
    p[t >= 1.55] = 0.0
    f = validate.impact_figures(t, p, [(1.6, 1.9)])
    assert math.isnan(f[0]["arrival"]) and math.isnan(f[0]["plateau"]) and f[0]["peak"] == 0.0


def test_reuse(tmp_path, capsys):
    """--reuse reads a finished run of the same command from --work instead of running it again (its wall
    time kept, the section naming the commit it ran on when that is another), and runs again where the command
    differs: a section's checks are redone from the same runs."""
    out, work = tmp_path / "report", tmp_path / "runs"
    common = ["--quick", "--cases", "beam", "--out", str(out), "--work", str(work), "--build", str(build_dir())]
    assert validate.main(common) == 0
    first = (out / "README.md").read_text()
    records = sorted(work.rglob("validate_run.json"))
    assert records and all(json.loads(r.read_text())["wall"] > 0 for r in records)
    capsys.readouterr()
    assert validate.main(common + ["--reuse"]) == 0
    assert capsys.readouterr().out.count(": reused (") == len(records)
    rows = lambda text: re.findall(r"^\| .+ \| (?:PASS|\*\*FAIL\*\*) \|$|^\| \S+ \| \d+ \| \d+ s \| .+ \|$", text, re.M)  # noqa: E731
    assert rows((out / "README.md").read_text()) == rows(first)
    assert "(its runs on" not in first  # run on the commit the section was written on
    # runs of an earlier commit: the section says which
    for r in records:
        r.write_text(json.dumps(dict(json.loads(r.read_text()), commit="abc1234")))
    assert validate.main(common + ["--reuse"]) == 0
    assert "(its runs on abc1234)" in (out / "README.md").read_text()
    capsys.readouterr()
    # a run recorded with another command is run again
    changed = json.loads(records[0].read_text())
    changed["command"] = changed["command"] + ["-fs_dt", "1"]
    records[0].write_text(json.dumps(changed))
    assert validate.main(common + ["--reuse"]) == 0
    assert capsys.readouterr().out.count(": reused (") == len(records) - 1
    assert json.loads(records[0].read_text())["command"] != changed["command"]


def test_an_interrupted_run_continues_from_its_checkpoint(tmp_path, capsys):
    # Context.run(checkpoints=N): a run whose folder holds its start record and checkpoints but no finish record
    # (interrupted) continues from its newest checkpoint, and ends as the uninterrupted run did (bitwise: same ranks)
    ctx = validate.Context(exe=build_dir() / "flexslosh", work=tmp_path, out=tmp_path)
    args = ["-options_file", REPO_ROOT / "cases" / "taylor_green.opts", "-fs_dx", 0.05, "-ts_max_steps", 25,
            "-fs_output_interval", 0]
    ctx.run("tg", "a", args, [], checkpoints=10)
    folder = tmp_path / "tg" / "a"
    whole = (folder / "timeseries.csv").read_text()
    assert sorted(p.name for p in folder.glob("checkpoint_*.h5")) == ["checkpoint_000010.h5", "checkpoint_000020.h5"]
    (folder / "validate_run.json").unlink()  # interrupted after step 20's checkpoint was lost, at step 15 or so
    (folder / "checkpoint_000020.h5").unlink()
    runs = []
    ctx.run("tg", "a", args, runs, checkpoints=10)
    assert "continuing from checkpoint_000010.h5" in capsys.readouterr().out
    assert (folder / "timeseries.csv").read_text() == whole
    assert json.loads((folder / "validate_run.json").read_text())["wall"] >= runs[0].wall > 0


def test_seed_ensemble(tmp_path):
    """--ensemble N: each seed_convergence run is N releases, the preload perturbed (the first the case file's), and
    the bands are their mean with its standard error."""
    assert validate.main(["--ensemble", "0"]) == 2 and validate.main(["--ensemble", "99"]) == 2
    ctx = validate.Context(exe=build_dir() / "flexslosh", work=tmp_path, out=tmp_path, quick=True,
                           resolutions={"seed_convergence": [0.01]}, ensemble=2)
    sec = validate.case_seed_convergence(ctx)
    commands = [r.command for r in sec.runs]
    assert len(commands) == 2 and "-fs_beam_preload 0.040004" in commands[1] and "-fs_beam_preload" not in commands[0]
    table = "\n".join(sec.notes)
    assert "the mean of 2 releases +- its standard error" in table
    # the releases differ (the slams are chaotic): a standard error that is not zero in some band
    row = re.search(r"^\| 10 \| (.+) \|$", table, re.M).group(1).split(" | ")
    assert len(row) == len(validate.SEED_BANDS) + 1, table  # the bands (nan beyond 0.5 s's cycles), the peak
    se = [float(v.split("+-")[1]) for v in row[:-1] if "nan" not in v]
    assert se and max(se) > 0, table


def test_spheric10_repetitions_statistics():
    """The SPHERIC test 10 repeatability file reads as its 102 repetitions of the first four peaks: the first peak's
    mean and standard deviation are the figures quoted for it elsewhere (3,710 +- 732 Pa, "37 +- 7 mbar")."""
    from flexslosh.validate import spheric10_peak_statistics
    s = spheric10_peak_statistics()
    assert list(s["n"]) == [102] * 4
    assert s["mean"][0] == pytest.approx(3710, abs=1) and s["sd"][0] == pytest.approx(732, abs=1)
    assert np.all(s["p2.5"] < s["mean"]) and np.all(s["mean"] < s["p97.5"])
    assert np.allclose(s["mean"][1:], [4816, 4691, 4642], atol=1)

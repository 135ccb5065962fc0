"""The validation report's machinery (python/flexslosh/validate.py) keeps working: the quick mode of two
cheap cases (the beam, Taylor-Green) runs into a temporary folder and writes its sections, figures and
report. Only the structure is checked here, not the physics (the physics tests check that), and the
quick mode's coarse numbers are allowed to FAIL their tolerances."""
import json
import re

import pytest

from conftest import REPO_ROOT, build_dir

validate = pytest.importorskip("flexslosh.validate")


def test_quick_report(tmp_path):
    out, work = tmp_path / "report", tmp_path / "runs"
    rc = validate.main(["--quick", "--cases", "beam,taylor_green", "--out", str(out), "--work", str(work),
                        "--build", str(build_dir())])
    assert rc == 0
    report = (out / "README.md").read_text()
    # one section per case, in the order of CASES; the cases not run say so with their command
    heads = re.findall(r"^## (.+)$", report, re.M)
    assert heads == [validate.TITLES[c] for c in validate.CASES]
    assert "Not run in this report" in report and "make validate CASES=seed" in report
    for name in ("beam", "taylor_green"):
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

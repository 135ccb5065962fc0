"""-fs_pair_cache: the pair pass of a right-hand side takes the pairs the first pass picked, with their kernel
factors, from the cache (yes) or picks them again from the candidates (no). Both give the same pairs in the same
order and the same values: the runs are the same bit for bit, with walls, on two ranks, in 3-D (a baffled tank), and with the split
density diffusion (whose stages read the cache too); the cache's memory is counted in the particle work."""
import numpy as np
import pytest

from conftest import REPO_ROOT, last_snapshot, read_series, read_summary, run_flexslosh

CASES = {
    "dam_break": ["-options_file", str(REPO_ROOT / "cases" / "dam_break.opts"), "-fs_dx", "0.05", "-ts_max_steps", "40"],
    "dam_break_split": ["-options_file", str(REPO_ROOT / "cases" / "dam_break.opts"), "-fs_dx", "0.05",
                        "-ts_max_steps", "40", "-fs_delta_split"],
    "baffled_3d": ["-options_file", str(REPO_ROOT / "cases" / "coupled_baffled_3d.opts"), "-fs_dx", "0.015",
                   "-ts_max_steps", "6"],
}


def run(tmp_path, name, args, nranks):
    out = tmp_path / name
    run_flexslosh(args + ["-fs_output_interval", "0", "-fs_output_dir", out], nranks=nranks, cwd=tmp_path)
    return out


@pytest.mark.parametrize("case,nranks", [("dam_break", 1), ("dam_break", 2), ("dam_break_split", 1), ("baffled_3d", 1)])
def test_cache_gives_the_same_run(tmp_path, case, nranks):
    yes = run(tmp_path, "yes", CASES[case] + ["-fs_pair_cache", "yes"], nranks)
    no = run(tmp_path, "no", CASES[case] + ["-fs_pair_cache", "no"], nranks)
    sa, sb = read_series(yes), read_series(no)
    for c in sa:
        if c != "wall_time":
            assert np.array_equal(sa[c], sb[c], equal_nan=True), c
    fa, fb = last_snapshot(yes), last_snapshot(no)
    for f in ("position", "velocity", "density"):
        assert np.array_equal(fa[f], fb[f]), f
    # the cache holds 12 bytes for each candidate pair (an upper bound on the pairs), counted in the particle work
    ya, na = read_summary(yes), read_summary(no)
    assert ya["memory"]["particle_work"] - na["memory"]["particle_work"] >= 12 * ya["pair_visits"] / ya["steps"] / 8


def test_auto_is_yes_in_2d_and_no_in_3d(tmp_path):
    for case in ("dam_break", "baffled_3d"):
        auto = read_summary(run(tmp_path, f"{case}-auto", CASES[case] + ["-ts_max_steps", "1"], 1))
        no = read_summary(run(tmp_path, f"{case}-no", CASES[case] + ["-ts_max_steps", "1", "-fs_pair_cache", "no"], 1))
        grew = auto["memory"]["particle_work"] > no["memory"]["particle_work"]
        assert grew == (case == "dam_break"), case

"""Moving the ranks' cuts as the liquid moves (-fs_rebalance_threshold): the load follows the liquid, the results stay
those of fixed cuts to round-off, and a restart on as many ranks goes on with the cuts the run had."""
import json

import h5py
import pytest

from conftest import TG, last_snapshot, petsc_error_message, rel_max_diff, run_flexslosh
from test_restart import FIELDS, check_continuation

DAM = ["-options_file", "cases/dam_break.opts", "-fs_dx", "0.05", "-ts_max_time", "0.8", "-fs_output_interval", "0"]
# with wall elements of edge h/2, whose work (four times the elements of the default) makes the rank at the back wall's
# excess plain at this size: with the default edge h the whole-plane steps of the cuts (128 particles) cannot bring
# 1.17 x the mean work nearer than 1.13 x
DAM3 = ["-options_file", "cases/dam_break_3d.opts", "-fs_dx", "0.0125", "-ts_max_steps", "6", "-fs_output_interval", "0",
        "-fs_walls_element_size", "0.5"]


def summary(directory):
    with open(directory / "summary.json") as f:
        return json.load(f)


@pytest.fixture(scope="module")
def dam_runs(tmp_path_factory):
    """The 2-D dam break (400 particles) on 2 ranks with fixed cuts and with the default rebalancing."""
    from conftest import REPO_ROOT
    out = {}
    for name, thr in (("fixed", "0"), ("moving", "1.2")):
        d = tmp_path_factory.mktemp(name)
        run_flexslosh(DAM + ["-fs_rebalance_threshold", thr, "-fs_output_dir", d], nranks=2, cwd=REPO_ROOT)
        out[name] = d
    return out


def test_the_cuts_follow_the_collapsing_column(dam_runs):
    fixed, moving = summary(dam_runs["fixed"]), summary(dam_runs["moving"])
    # measured: with fixed cuts the largest rank holds 1.46 x the mean over the run (1.65 at the end); with the cuts
    # moved 4 times, 1.11 (1.10)
    assert fixed["rebalances"] == 0 and moving["rebalances"] >= 3
    assert fixed["parallel"]["imbalance_owned"] > 1.4
    assert moving["parallel"]["imbalance_owned"] < 1.15
    assert moving["steps"] == fixed["steps"]


def assert_same_to_round_off(dir_a, dir_b, tol):
    """The last snapshots of two runs, particle by particle (by id): positions, velocities, densities within tol."""
    a, b = last_snapshot(dir_a), last_snapshot(dir_b)
    ka = {int(i): k for k, i in enumerate(a["id"])}
    order = [ka[int(i)] for i in b["id"]]
    for f in ("position", "velocity", "density"):
        err = rel_max_diff(a[f][order], b[f])
        assert err < tol, f"{f}: other cuts changed the run by {err:.3g} (relative)"


def test_moving_cuts_change_nothing_but_round_off(dam_runs):
    assert_same_to_round_off(dam_runs["fixed"], dam_runs["moving"], 1e-9)


@pytest.fixture(scope="module")
def dam3_runs(tmp_path_factory):
    """The 3-D dam break (2,048 particles) on 2 ranks, the cuts balanced on the particles and on their work."""
    from conftest import REPO_ROOT
    out = {}
    for balance in ("particles", "work"):
        d = tmp_path_factory.mktemp(balance)
        run_flexslosh(DAM3 + ["-fs_balance", balance, "-fs_output_dir", d], nranks=2, cwd=REPO_ROOT)
        out[balance] = d
    return out


def test_the_cuts_balance_the_work_of_the_walls(dam3_runs):
    """The rank at the back wall has the wall elements of two walls more (the column's back and the corner): counting
    particles it does more of the work of a right-hand side (candidate pairs and wall elements, FSSolverGetWork)."""
    p, w = summary(dam3_runs["particles"])["parallel"], summary(dam3_runs["work"])["parallel"]
    assert p["grid"] == [2, 1, 1] and w["grid"] == [2, 1, 1]
    # measured: 1024 / 1024 particles with 1.25 x the mean work; 768 / 1280 with 1.04
    assert p["owned"][0] == p["owned"][1] and p["imbalance_work_end"] > 1.2
    assert w["owned"][0] < 0.65 * w["owned"][1] and w["imbalance_work_end"] < 1.06


def test_balancing_the_work_changes_nothing_but_round_off(dam3_runs):
    assert_same_to_round_off(dam3_runs["particles"], dam3_runs["work"], 1e-12)  # measured 2e-14


def test_a_rebalanced_run_restarts_exactly(tmp_path):
    """Taylor-Green on 2 ranks with the cuts moved every 5 steps: the restart takes the checkpoint's cuts."""
    a, b = tmp_path / "A", tmp_path / "B"
    opts = TG + ["-fs_rebalance_threshold", "1", "-fs_rebalance_interval", "5"]
    run_flexslosh(opts + ["-ts_max_steps", "40", "-fs_checkpoint_interval", "20", "-fs_output_dir", a], nranks=2,
                  cwd=tmp_path)
    assert summary(a)["rebalances"] >= 2
    with h5py.File(a / "checkpoint_000020.h5", "r") as h5:
        layout = h5["layout/domain"][()]
    assert sorted(layout[1:4].tolist()) == [1, 1, 2] and layout[0] > 0  # the last balance's step, then the grid
    run_flexslosh(opts + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b, "-ts_max_steps", "40"],
                  nranks=2, cwd=tmp_path)
    check_continuation(a, b, tol=0.0)


def test_bad_threshold_is_refused(tmp_path):
    proc = run_flexslosh(TG + ["-ts_max_steps", "1", "-fs_rebalance_threshold", "0.5", "-fs_output_dir", tmp_path],
                         check=False, cwd=tmp_path)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    assert "-fs_rebalance_threshold 0.5" in msg and ">= 1" in msg


def test_the_rebalance_check_takes_no_collective(tmp_path):
    """With -fs_balance work (the default) whether the cuts must move is decided from the ranks' work summed and
    maximized in the step's own reduction (FSSolverRebalanceWork): a run whose rebuilds may move the cuts (threshold
    1e300: checked at every rebuild after the interval, never moved) takes the collectives a step of one whose cuts
    never move (threshold 0: never checked), the lists rebuilt every step. Measured equal; before, the check's
    MPI_Allgather of a value a rank (P values, at every rebuild) added 0.23 a step over 130 steps."""
    from conftest import REPO_ROOT
    coll = {}
    for thr in ("0", "1e300"):
        out = tmp_path / f"thr{thr}"
        run_flexslosh(["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", "0.005", "-ts_max_steps", "130",
                       "-fs_neighbour_rebuild", "always", "-fs_rebalance_threshold", thr, "-fs_rebalance_interval", "100",
                       "-fs_output_interval", "0", "-fs_output_dir", out], nranks=2, cwd=REPO_ROOT)
        s = summary(out)
        assert s["steps"] == 130 and s["rebalances"] == 0 and s["neighbour_rebuilds"] >= 130
        coll[thr] = max(s["parallel"]["collectives_per_step"])
    assert abs(coll["1e300"] - coll["0"]) < 1e-9, coll

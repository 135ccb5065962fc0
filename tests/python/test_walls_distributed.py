"""The distributed wall mesh (-fs_walls_distribute, the default): on more than one rank each rank holds only the wall
elements near its part of the domain, made again whenever the cuts move. The run is the one with every element on
every rank (-fs_walls_distribute false), to the last bit, and the elements' memory over the ranks falls."""
import json

import numpy as np
import pytest

from conftest import REPO_ROOT, last_snapshot, run_flexslosh

# the 3-D dam break (2,048 particles, elements of edge h/2) on 3 ranks with the cuts moved every 5 steps as the column
# collapses
DAM3 = ["-options_file", "cases/dam_break_3d.opts", "-fs_dx", "0.0125", "-ts_max_steps", "30", "-fs_output_interval",
        "0", "-fs_walls_element_size", "0.5", "-fs_rebalance_threshold", "1.02", "-fs_rebalance_interval", "5"]


def summary(directory):
    with open(directory / "summary.json") as f:
        return json.load(f)


@pytest.fixture(scope="module")
def dam3(tmp_path_factory):
    out = {}
    for name, extra in (("all", ["-fs_walls_distribute", "false"]), ("distributed", [])):
        d = tmp_path_factory.mktemp(name)
        run_flexslosh(DAM3 + extra + ["-fs_output_dir", d], nranks=3, cwd=REPO_ROOT, timeout=600)
        out[name] = d
    return out


def test_distributed_walls_give_the_same_run(dam3):
    """The particles after 30 steps and the walls' loads at every step are those of the run that holds every element
    on every rank, bit for bit: each rank searches the same elements in the same order (its grid a block of the
    whole grid), and the wall pressure's sums reach each element's owner at its own index."""
    a, b = summary(dam3["all"]), summary(dam3["distributed"])
    assert a["rebalances"] >= 2 and b["rebalances"] == a["rebalances"]  # measured 2: the elements made 3 times
    x, y = last_snapshot(dam3["all"]), last_snapshot(dam3["distributed"])
    ka = {int(i): k for k, i in enumerate(x["id"])}
    order = [ka[int(i)] for i in y["id"]]
    for f in ("position", "velocity", "density", "pressure"):
        assert np.array_equal(x[f][order], y[f]), f
    ta = np.genfromtxt(dam3["all"] / "timeseries.csv", delimiter=",", names=True)
    tb = np.genfromtxt(dam3["distributed"] / "timeseries.csv", delimiter=",", names=True)
    loads = [n for n in ta.dtype.names if n.startswith("wall_")]
    assert len(loads) == 6 and np.abs(ta["wall_tank_force_y"]).max() > 0
    for n in loads:
        assert np.array_equal(ta[n], tb[n]), n


def test_distributed_walls_take_less_memory(dam3):
    """The elements' memory summed over the 3 ranks: every rank holding all of them, 3 times one rank's; distributed,
    each rank the elements near its part (within twice the candidate radius and the largest element: in this small
    tank a part and its margin cover much of the tank). Measured 7.77 MB against 5.28 MB."""
    a, b = summary(dam3["all"])["memory"], summary(dam3["distributed"])["memory"]
    assert b["walls_elements"] < 0.75 * a["walls_elements"], (a["walls_elements"], b["walls_elements"])


def test_probes_read_the_same_with_distributed_walls(tmp_path):
    """The rolled 3-D tank's probes (a probe on the end wall reading its nearest element, two gauges) on 2 ranks with
    the cuts moved every 5 steps (on the work, the lists built at every step): the probes find their elements among all of them at the set-up (every element made
    for the while) and keep their numbers, and at each sample each rank reads those it holds and owns, wherever the
    cuts have gone; the gauges' Shepard factor from all the elements. The probes' file is the one of the run that
    holds every element on every rank, bit for bit (measured)."""
    base = ["-options_file", REPO_ROOT / "cases/roll_tank_3d.opts", "-ts_max_steps", "20", "-fs_output_interval", "0",
            "-fs_rebalance_threshold", "1", "-fs_rebalance_interval", "5", "-fs_balance", "work", "-fs_neighbour_rebuild",
            "always"]
    out = {}
    for name, extra in (("all", ["-fs_walls_distribute", "false"]), ("distributed", [])):
        out[name] = tmp_path / name
        run_flexslosh(base + extra + ["-fs_output_dir", out[name]], nranks=2, cwd=REPO_ROOT, timeout=600)
    assert summary(out["distributed"])["rebalances"] >= 2 and summary(out["distributed"])["wall_elements_distributed"]
    a = np.genfromtxt(out["all"] / "probes.csv", delimiter=",", names=True)
    b = np.genfromtxt(out["distributed"] / "probes.csv", delimiter=",", names=True)
    assert len(a) == 21 and a.dtype.names == b.dtype.names
    assert np.abs(a["sensor1_pressurePa"]).max() > 50 and a["left_elevationm"].min() > 0.09
    for n in a.dtype.names:
        assert np.array_equal(a[n], b[n]), n

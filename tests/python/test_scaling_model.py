"""bench/scaling_model.py's replay of the decomposition and of the distributed wall mesh (docs/performance.md, "A
measured scaling model"): the wall elements a rank holds against a direct count, and the replayed decomposition of
the 3-D baffled tank against the counts of flexslosh's own runs (bench_scaling.py, 2026-12-06)."""
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
scaling_model = pytest.importorskip("scaling_model")


@pytest.mark.parametrize("P", [1, 2, 8, 32])
def test_elements_per_rank_against_a_direct_count(P):
    """Each rank holds the elements whose centroid lies within the margin of its part: the difference array over
    the process grid gives what testing every element against every part's grown box gives."""
    m = scaling_model
    x, lo, hi, w = m.lattice_baffled3d(0.005, 0.05)
    dlo, dhi = m.domain(lo, hi, 0.01)
    dec = m.decompose(x, dlo, dhi, P, 0.025, w, on_work=True)
    el = m.walls_baffled3d(0.01, 0.05)
    margin = m.element_margin(0.01)
    held = m.elements_per_rank(dec, el, margin)
    direct = np.zeros(P, dtype=int)
    for k, idx in enumerate(np.ndindex(*reversed(dec.grid[:3]))):
        c = tuple(reversed(idx))  # rank = i + nx (j + ny k)
        inside = np.ones(len(el), dtype=bool)
        for d in range(3):
            inside &= (el[:, d] >= dec.cuts[d][c[d]] - margin) | (c[d] == 0)
            inside &= (el[:, d] <= dec.cuts[d][c[d] + 1] + margin) | (c[d] == dec.grid[d] - 1)
        direct[k] = inside.sum()
    assert np.array_equal(held, direct)
    assert held.sum() >= len(el) and (P > 1 or held[0] == len(el))


def test_replayed_decomposition_matches_the_counted_runs():
    """The baffled tank at dx = 5 mm (0.05 m wide, 8,400 particles): the grids, largest owned and ghost counts and
    most ranks sent to that flexslosh's runs counted on 8, 32 and 64 ranks (bench_scaling.py --cases baffled3d), and
    the wall elements held summed over the ranks within 4 % of the counted (10,892 on 1 rank, 24,993 on 8, 161,939
    on 64: the lattice on each face stands for the refined elements)."""
    m = scaling_model
    x, lo, hi, w = m.lattice_baffled3d(0.005, 0.05)
    dlo, dhi = m.domain(lo, hi, 0.01)
    el = m.walls_baffled3d(0.01, 0.05)
    counted = {8: ((8, 1, 1), 1080, 600, 2, 24993), 32: ((8, 2, 2), 270, 1410, 11, 99973),
               64: ((16, 2, 2), 135, 1005, 11, 161939)}
    for P, (grid, owned, ghosts, sends, held) in counted.items():
        dec = m.decompose(x, dlo, dhi, P, 0.025, w)
        assert tuple(dec.grid) == grid and dec.owned.max() == owned and dec.ghosts.max() == ghosts
        assert dec.sendranks.max() == sends
        replayed = m.elements_per_rank(m.decompose(x, dlo, dhi, P, 0.025, w, on_work=True), el, m.element_margin(0.01))
        assert abs(replayed.sum() / held - 1) < 0.04, (P, replayed.sum(), held)

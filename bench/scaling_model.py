#!/usr/bin/env python3
"""The scaling model of docs/performance.md ("A measured scaling model"): the wall time, parallel efficiency and
memory a rank of a run on 1 to 1,024 cores, from
  - the decomposition flexslosh makes (FSDecompChooseGrid and FSDecompBalance of src/particles/decomp.c, replayed
    here on the case's initial particle lattice, the cuts on the pairs' share as -fs_balance work puts them on the
    work): per rank the owned particles, ghosts, ranks sent to, and the wall elements it holds (the distributed wall
    mesh, replayed on the walls' surfaces);
  - the per-core cost c of a particle-step (bench_scaling.py --timed; a ghost costs --ghost-share of it);
  - the counted runs of bench/bench_scaling.py (--counts: their summary.json): collectives per step, messages per
    step per rank sent to (the halo's and the wall pressure's), bytes per ghost per step, the memory items;
  - an assumed network: latency alpha and bandwidth beta (InfiniBand-class: 1.5 us, 10 GB/s); an allreduce of a few
    values costs ceil(log2 P) alpha.

    T_step(P) = c W_max(P) drift(P) + c_g G_max(P)                   (compute: the rank with the most work)
              + m S_max(P) alpha + b G_max(P) / beta                   (messages: to S_max ranks, of G_max ghosts)
              + C ceil(log2 P) alpha                                   (collectives)
    T(P) = steps T_step(P);  efficiency E(P) = T(1) / (P T(P))
    M(P) = max over the ranks of  M_rank + a N_owned + b G + e E_held   (memory a rank; --fit-memory fits them)

Beside the main rows (the cuts of the start): the imbalance's drift over a sloshing run with the cuts following the
liquid (--drift, with that run's collectives a step), and the cuts on the particles (-fs_balance particles).

    /usr/bin/python3 bench/scaling_model.py --counts COUNTS [--validate] [--fit-memory] [--plot docs/images/scaling.png]
"""
import argparse
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

NBINS = 4096
# bytes a rank: its own, an owned particle, a ghost, a wall element held (fitted: --fit-memory, 2026-12-06)
MEM2D = [12.1e6, 1494.0, 241.0, 115.0]
MEM3D = [16.7e6, 1871.0, 459.0, 184.0]


@dataclass
class Decomp:
    """A replayed decomposition: the process grid, per rank the owned particles, ghosts, ranks sent to and work
    (the owned particles' weights; their count without weights), and the cuts per direction."""
    grid: tuple
    owned: np.ndarray
    ghosts: np.ndarray
    sendranks: np.ndarray
    work: np.ndarray
    cuts: list


def choose_grid(P, dim, length, minwidth):
    """FSDecompChooseGrid: the process grid of P ranks with the least interface area, every subdomain at
    least minwidth wide (no periodic directions here)."""
    best, grid = None, None
    for a in range(1, P + 1):
        if P % a:
            continue
        for b in range(1, P // a + 1):
            if (P // a) % b:
                continue
            c = P // a // b
            if dim == 2 and c != 1:
                continue
            n = (a, b, c)
            ok, area = True, 0.0
            for d in range(dim):
                if length[d] / n[d] < minwidth and n[d] > 1:
                    ok = False
                cross = 1.0
                for e in range(dim):
                    if e != d:
                        cross *= length[e]
                area += (n[d] - 1) * cross
            if ok and (best is None or area < best):
                best, grid = area, n
    return grid


def balance(x, lo, length, grid, minwidth, weights=None):
    """FSDecompBalance: per direction, cuts at the bin edge closest to each quantile of a 4096-bin histogram of the
    particles (weights: of their work, -fs_balance work), then the minimum width."""
    dim = x.shape[1]
    cuts = []
    for d in range(dim):
        n = grid[d]
        cut = lo[d] + length[d] * np.arange(n + 1) / n
        if n > 1:
            b = np.clip(((x[:, d] - lo[d]) / length[d] * NBINS).astype(np.int64), 0, NBINS - 1)
            hist = np.bincount(b, weights=weights, minlength=NBINS)
            total = hist.sum()
            acc, k = 0.0, 1
            for i in range(NBINS):
                below = acc
                acc += hist[i]
                while k < n and acc * n >= total * k:
                    before = i > 0 and total * k - below * n < acc * n - total * k
                    cut[k] = lo[d] + length[d] * (i if before else i + 1) / NBINS
                    k += 1
                if k >= n:
                    break
            for i in range(1, n):
                cut[i] = max(cut[i], cut[i - 1] + minwidth)
            for i in range(n - 1, 0, -1):
                cut[i] = min(cut[i], cut[i + 1] - minwidth)
        cuts.append(cut)
    return cuts


def decompose(x, lo, hi, P, width, weights=None, on_work=False):
    """Per rank: owned particles, ghosts received, ranks sent to (FSHaloFindSends on the initial lattice), and with
    weights the work (the sum of the owned particles' weights); on_work: the cuts balance the weights instead of
    the particles (-fs_balance work, with the pairs' share standing for a particle's work)."""
    dim = x.shape[1]
    length = [hi[d] - lo[d] for d in range(dim)]
    grid = choose_grid(P, dim, length, width)
    cuts = balance(x, lo, length, grid, width, weights if on_work else None)
    c = np.empty_like(x, dtype=np.int64)
    low = np.empty(x.shape, dtype=bool)
    high = np.empty(x.shape, dtype=bool)
    for d in range(dim):
        c[:, d] = np.clip(np.searchsorted(cuts[d], x[:, d], side="right") - 1, 0, grid[d] - 1)
        low[:, d] = x[:, d] - cuts[d][c[:, d]] < width
        high[:, d] = cuts[d][c[:, d] + 1] - x[:, d] < width
    stride = [1, grid[0], grid[0] * grid[1]]
    rank = sum(c[:, d] * stride[d] for d in range(dim))
    owned = np.bincount(rank, minlength=P)
    ghosts = np.zeros(P, dtype=np.int64)
    links = np.zeros((P, P), dtype=bool) if P <= 4096 else None
    for off in np.ndindex(*([3] * dim)):
        o = np.array(off) - 1
        if not o.any():
            continue
        m = np.ones(len(x), dtype=bool)
        for d in range(dim):
            if o[d] < 0:
                m &= low[:, d] & (c[:, d] > 0)
            elif o[d] > 0:
                m &= high[:, d] & (c[:, d] < grid[d] - 1)
        dest = sum((c[m, d] + o[d]) * stride[d] for d in range(dim))
        ghosts += np.bincount(dest, minlength=P)
        links[rank[m], dest] = True
    sendranks = links.sum(axis=1)
    work = np.bincount(rank, weights=weights, minlength=P) if weights is not None else owned.astype(float)
    return Decomp(grid, owned, ghosts, sendranks, work, cuts)


def element_margin(h, element_radius=0.58):
    """How far beyond its part a rank holds wall elements' centroids with the distributed mesh: the bounding sphere
    (radius r, at most element_radius h) meets the part grown by 2 (R + r), R = 2h + the skin 0.5h the candidate
    radius: 2 R + 3 r."""
    return (2 * 2.5 + 3 * element_radius) * h


def elements_per_rank(dec, walls, margin):
    """The wall elements each rank holds with the distributed wall mesh (-fs_walls_distribute, the default on
    several ranks; docs/walls.md): those whose centroid lies within margin of the rank's part of the domain
    (the bounding sphere meeting the part grown by 2 (R + r): margin = 2 R + 3 r, R the candidate radius, r the
    largest element's bounding radius). walls: the elements' centroids."""
    dim = walls.shape[1]
    lo_idx = []
    hi_idx = []
    for d in range(dim):
        cut = dec.cuts[d]
        n = dec.grid[d]
        inner = cut[1:n]  # the cuts between parts: an element belongs to every part whose grown interval holds it
        lo_idx.append(np.clip(np.searchsorted(inner, walls[:, d] - margin, side="right"), 0, n - 1))
        hi_idx.append(np.clip(np.searchsorted(inner, walls[:, d] + margin, side="left"), 0, n - 1))
    # each element adds one to a box of parts in the process grid: a difference array over the grid, summed up
    shape = [dec.grid[d] + 1 for d in range(dim)]
    diff = np.zeros(shape, dtype=np.int64)
    for corner in np.ndindex(*([2] * dim)):
        at = tuple(hi_idx[d] + 1 if corner[d] else lo_idx[d] for d in range(dim))
        np.add.at(diff, at, (-1) ** sum(corner))
    for d in range(dim):
        diff = np.cumsum(diff, axis=d)
    count = diff[tuple(slice(0, dec.grid[d]) for d in range(dim))]
    return count.transpose(*reversed(range(dim))).ravel()  # rank = i + nx (j + ny k)


def neighbour_weights(idx, n):
    """Each lattice particle's neighbours within the support (2h = 4 dx) inside its block of n[d] particles a side
    (walls and the free surface cut the rest), over the mean: the share of the pair work each particle carries.
    The count depends only on the distances to the block's faces clipped to 4, so it is computed per class."""
    dim = len(n)
    offs = [o for o in np.ndindex(*([9] * dim)) if 0 < sum((np.array(o) - 4) ** 2) < 16]
    offs = np.array(offs) - 4
    cls = np.stack([np.minimum(idx[:, d], 4) * 5 + np.minimum(n[d] - 1 - idx[:, d], 4) for d in range(dim)], axis=1)
    keys, inv = np.unique(cls, axis=0, return_inverse=True)
    counts = np.empty(len(keys))
    for k, key in enumerate(keys):
        lo, hi = key // 5, key % 5
        counts[k] = np.all((offs >= -lo) & (offs <= hi), axis=1).sum()
    w = counts[inv.ravel()]
    return w / w.mean()


def lattice_seed2d(dx):
    """cases/coupled_rectangular.opts: the 0.7 x 0.06 m tank filled to 0.03 m, particles at (i + 1/2) dx; with each
    particle's share of the pair work."""
    nx, ny = round(0.7 / dx), round(0.03 / dx)
    I, J = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    idx = np.column_stack([I.ravel(), J.ravel()])
    return (idx + 0.5) * dx, [0, 0], [0.7, 0.06], neighbour_weights(idx, [nx, ny])


def lattice_baffled3d(dx, width):
    """cases/coupled_baffled_3d.opts: 7 compartments 0.1 m long between 5 mm baffles, 0.06 m high, filled to 0.03 m
    (no pair reaches through a baffle: 4 dx <= 5 mm)."""
    nx, ny, nz = round(0.1 / dx), round(0.03 / dx), round(width / dx)
    I, J, K = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    idx = np.column_stack([I.ravel(), J.ravel(), K.ravel()])
    w = neighbour_weights(idx, [nx, ny, nz])
    x = (idx + 0.5) * dx
    xs = np.concatenate([x + [k * 0.105, 0, 0] for k in range(7)])
    return xs, [0, 0, 0], [0.73, 0.06, width], np.tile(w, 7)


def walls_seed2d(h, size=1.0):
    """cases/coupled_rectangular.opts's walls: the 0.7 x 0.06 m rectangle's sides cut into segments of size h
    (-fs_walls_element_size): their centres."""
    pts = []
    for (x0, y0), (x1, y1) in [((0, 0), (0.7, 0)), ((0.7, 0), (0.7, 0.06)), ((0.7, 0.06), (0, 0.06)), ((0, 0.06), (0, 0))]:
        n = max(1, math.ceil(math.hypot(x1 - x0, y1 - y0) / (size * h)))
        t = (np.arange(n) + 0.5) / n
        pts.append(np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0)]))
    return np.concatenate(pts)


def walls_baffled3d(h, width, area=0.189):
    """cases/coupled_baffled_3d.opts's walls (the box 0.73 x 0.06 x width, six baffles 5 mm thick and 45 mm high at
    the compartments' ends): points on a square lattice of side sqrt(area) h over every face, standing for the
    refined elements' centroids (area: an element's mean area in h^2, measured: 15,692 elements on the 0.2969 m^2 of
    the 0.1 m wide tank at h = 1 cm with -fs_walls_element_size 1)."""
    a = math.sqrt(area) * h

    def face(origin, u, v, lu, lv):
        nu, nv = max(1, round(lu / a)), max(1, round(lv / a))
        U, V = np.meshgrid((np.arange(nu) + 0.5) / nu * lu, (np.arange(nv) + 0.5) / nv * lv, indexing="ij")
        return np.array(origin) + U.ravel()[:, None] * np.array(u) + V.ravel()[:, None] * np.array(v)

    L, H, W = 0.73, 0.06, width
    ex, ey, ez = [1, 0, 0], [0, 1, 0], [0, 0, 1]
    faces = [face([0, 0, 0], ex, ez, L, W), face([0, H, 0], ex, ez, L, W),   # floor, lid
             face([0, 0, 0], ex, ey, L, H), face([0, 0, W], ex, ey, L, H),   # front, back
             face([0, 0, 0], ey, ez, H, W), face([L, 0, 0], ey, ez, H, W)]   # the ends
    for k in range(6):
        x0 = 0.1 + k * 0.105
        faces += [face([x0, 0, 0], ey, ez, 0.045, W), face([x0 + 0.005, 0, 0], ey, ez, 0.045, W),
                  face([x0, 0.045, 0], ex, ez, 0.005, W)]
    return np.concatenate(faces)


def domain(lo, hi, h):
    """FSCaseSetDomainAround: the walls' box with a margin of 4 h."""
    return [v - 4 * h for v in lo], [v + 4 * h for v in hi]


def counted(counts_dir, case):
    """The counted runs of one case: {ranks: summary}."""
    out = {}
    for d in sorted(Path(counts_dir, case).glob("np*")):
        f = d / "summary.json"
        if f.exists():
            out[int(d.name[2:])] = json.load(open(f))
    return out


def rates(runs):
    """From the counted runs of a case (P >= 2): collectives per step, messages per step per rank sent to (the halo's
    and the wall pressure's) and bytes sent per ghost per step."""
    col, msg, byt = [], [], []
    for P, s in runs.items():
        if P < 2:
            continue
        p = s["parallel"]
        col.append(max(p["collectives_per_step"]))
        sr = sum(p["send_ranks"])
        msg.append(sum(p["messages_per_step"]) / max(sr, 1))
        byt.append(sum(p["bytes_per_step"]) / max(sum(p["ghosts_mean"]), 1))
    return dict(collectives=max(col), messages_per_sendrank=float(np.mean(msg)), bytes_per_ghost=float(np.mean(byt)))


def decompositions(x, w, lo, hi, h, Ps, on_work=False):
    """The replayed decomposition on each P of Ps: {P: Decomp}."""
    dlo, dhi = domain(lo, hi, h)
    return {P: decompose(x, dlo, dhi, P, 2.5 * h, w, on_work) for P in Ps}  # the halo: support 2h plus the skin 0.5h


def drift_at(drift, P):
    """The drift factor at P: drift is a number or {P: factor} (measured), interpolated in log2 P from 1 at P = 1."""
    if not isinstance(drift, dict):
        return drift if P > 1 else 1.0
    pts = sorted([(1, 1.0)] + list(drift.items()))
    if P >= pts[-1][0]:
        return pts[-1][1]
    lp = [math.log2(p) for p, _ in pts]
    return float(np.interp(math.log2(P), lp, [f for _, f in pts]))


def project(decs, dim, steps, cost, ghost_cost, r, alpha=1.5e-6, beta=10e9, drift=1.0, collectives=None, mem=None,
            elements=None, nelements=0):
    """Wall time (s) and efficiency on each P of the decompositions decs, with the breakdown of a step; with mem
    (bytes: process, particle, ghost, element), elements ({P: wall elements per rank}) and nelements (all of them) the
    largest memory of a rank, as it is and with every element on every rank."""
    rows = []
    for P, dec in sorted(decs.items()):
        grid, owned, ghosts, sendranks, work = dec.grid, dec.owned, dec.ghosts, dec.sendranks, dec.work
        comp = cost * work.max() * drift_at(drift, P) + ghost_cost * ghosts.max()
        lg = math.ceil(math.log2(P)) if P > 1 else 0
        halo = (r["messages_per_sendrank"] * sendranks.max() * alpha + r["bytes_per_ghost"] * ghosts.max() / beta) if P > 1 else 0
        coll = (collectives or r["collectives"]) * lg * alpha
        row = dict(P=P, grid=grid[:dim], owned_max=int(owned.max()), ghosts_max=int(ghosts.max()),
                   work_imbalance=float(work.max() * P / work.sum()), sendranks_max=int(sendranks.max()),
                   compute=comp, halo=halo, collectives=coll, step=comp + halo + coll)
        if mem is not None:
            el = elements[P]
            rest = mem[0] + mem[1] * owned + mem[2] * ghosts
            row.update(elements_max=int(el.max()), memory_max=float((rest + mem[3] * el).max()),
                       memory_every_element=float((rest + mem[3] * nelements).max()))
        rows.append(row)
    t1 = rows[0]["step"] * steps
    for row in rows:
        row["wall"] = row["step"] * steps
        row["efficiency"] = t1 / (row["P"] * row["wall"])
    return rows


def validate(counts_dir):
    """The replayed decomposition against the counted runs' first step: largest owned count, largest ghost count and
    most ranks sent to, per rank count; replayed with the cuts on the particles and on the pairs' share (the counted
    runs balance -fs_balance's work, which also weighs the wall elements: neither replay is exact there)."""
    print("replayed decomposition against the counted runs (first step): owned max, ghosts max, send ranks max"
          " (measured / replayed on particles / replayed on pairs)")
    for case, (x, lo, hi, w), h in [("seed2d", lattice_seed2d(0.002), 0.004),
                                    ("baffled3d", lattice_baffled3d(0.005, 0.05), 0.01)]:
        dlo, dhi = domain(lo, hi, h)
        for P, s in sorted(counted(counts_dir, case).items()):
            p = s["parallel"]
            dp = decompose(x, dlo, dhi, P, 2.5 * h, w)
            dw = decompose(x, dlo, dhi, P, 2.5 * h, w, on_work=True)
            grid, owned, ghosts, sendranks = dp.grid, dp.owned, dp.ghosts, dp.sendranks
            owned_w, ghosts_w, sendranks_w = dw.owned, dw.ghosts, dw.sendranks
            print(f"  {case:9s} {P:3d} ranks: grid {'x'.join(str(int(g)) for g in p['grid'])} / {'x'.join(map(str, grid[:x.shape[1]]))}"
                  f"  owned {max(p['owned_first']):6.0f} / {owned.max():6d} / {owned_w.max():6d}"
                  f"  ghosts {max(p['ghosts_first']):6.0f} / {ghosts.max():6d} / {ghosts_w.max():6d}"
                  f"  send ranks {max(p['send_ranks']):3.0f} / {sendranks.max():3d} / {sendranks_w.max():3d}")
    print("the wall elements held, summed over the ranks (counted: summary.json's walls_elements over the bytes of an "
          "element on one rank; replayed on the pairs' cuts)")
    x, lo, hi, w = lattice_baffled3d(0.005, 0.05)
    dlo, dhi = domain(lo, hi, 0.01)
    el = walls_baffled3d(0.01, 0.05)
    runs = counted(counts_dir, "baffled3d")
    if 1 in runs:
        per = runs[1]["memory"]["walls_elements"] / runs[1]["wall_elements"]
        for P, s in sorted(runs.items()):
            held = elements_per_rank(decompose(x, dlo, dhi, P, 0.025, w, on_work=True), el, element_margin(0.01))
            print(f"  baffled3d {P:3d} ranks: {s['memory']['walls_elements'] / per:8.0f} / {held.sum():8d}")


def fit_memory(counts_dir, case):
    """The memory coefficients from the counted runs of a case (summary.json's "memory", summed over the ranks, and
    "parallel"'s owned and ghost counts at the end): the accounted bytes without the wall elements fitted as
    a N + b G + c P (N the particles, G the ghosts summed over the ranks, P the ranks), the wall elements' bytes per element from
    the 1-rank run (every element), and a rank's own bytes (the peak's unaccounted part less the pages shared
    with the node's other ranks) as their largest mean over the runs. Prints and returns (own, a, b, element)."""
    runs = counted(counts_dir, case)
    rows = []
    for P, s in sorted(runs.items()):
        m, p = s["memory"], s["parallel"]
        rows.append((P, s["particles"], sum(p["ghosts"]), m["accounted"] - m["walls_elements"], m["walls_elements"],
                     (m["not_accounted"] - m["shared_clean"]) / P, s["wall_elements"]))
    A = np.array([[r[1], r[2], r[0]] for r in rows], dtype=float)
    y = np.array([r[3] for r in rows], dtype=float)
    (a, b, c), *_ = np.linalg.lstsq(A, y, rcond=None)
    one = runs.get(1)
    el = one["memory"]["walls_elements"] / max(one["wall_elements"], 1) if one else float("nan")
    own = max(r[5] for r in rows) + c
    print(f"{case}: memory a rank = {own / 1e6:.1f} MB + {a:.0f} B an owned particle + {b:.0f} B a ghost + {el:.0f} B a "
          f"wall element held (the rank's own: its largest unshared and unaccounted part, {max(r[5] for r in rows) / 1e6:.1f}"
          f" MB, and {c / 1e6:.2f} MB of the accounted items a rank)")
    for P, N, G, acc, wel, o, ne in rows:
        print(f"  {P:4d} ranks: accounted less elements {acc / 1e6:8.2f} MB (fit {(a * N + b * G + c * P) / 1e6:8.2f}), "
              f"elements held {wel / el if el > 0 else 0:9.0f} of {ne} ({wel / 1e6:6.2f} MB), own {o / 1e6:6.1f} MB a rank")
    return own, a, b, el


def fmt_time(t):
    return f"{t / 3600:.1f} h" if t >= 3600 else (f"{t / 60:.1f} min" if t >= 60 else f"{t:.1f} s")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", required=True, help="bench_scaling.py's --out")
    ap.add_argument("--cost2d", type=float, default=4.82e-6,
                    help="s per particle-step, one core, the seed's 2-D tank (bench_scaling.py --timed)")
    ap.add_argument("--cost3d", type=float, default=5.6e-5,
                    help="s per particle-step, one core, the 3-D baffled tank (bench_scaling.py --timed, dx = 2.5 mm)")
    ap.add_argument("--ghost-share", type=float, default=0.02, help="a ghost's cost per step over a particle's")
    ap.add_argument("--steps2d", type=float, default=123700,
                    help="steps of (a): 3 s (the 0.7 mm run's 20,616 steps a simulated second through the slams, doubled)")
    ap.add_argument("--steps3d", type=float, default=87000, help="steps of (b): 3 s")
    ap.add_argument("--drift", default="2:1.018,8:1.131",
                    help="the pair lists' imbalance over a sloshing run, the cuts moving with the liquid (a scenario), "
                         "measured on some rank counts (P:factor,...; bench_scaling.py --cases seed2d_slosh, 2 mm, "
                         "-fs_rebalance_threshold 1.2; 2:1.018,8:1.090 with 1.1): "
                         "interpolated in log2 P from 1 on one rank, the last one's beyond")
    ap.add_argument("--element-radius", type=float, default=0.58,
                    help="the largest wall element's bounding radius in h (edges of at most h: h / sqrt(3))")
    ap.add_argument("--mem2d", type=float, nargs=4, default=MEM2D, metavar=("PROCESS", "PARTICLE", "GHOST", "ELEMENT"),
                    help="bytes a rank: its own (not shared with the node's other ranks), per owned particle, per ghost,"
                         " per wall element (2-D; fitted to the counted runs' summary.json, --fit-memory)")
    ap.add_argument("--mem3d", type=float, nargs=4, default=MEM3D, metavar=("PROCESS", "PARTICLE", "GHOST", "ELEMENT"),
                    help="the same in 3-D")
    ap.add_argument("--fit-memory", action="store_true", help="fit the memory coefficients to the counted runs")
    ap.add_argument("--alpha", type=float, default=1.5e-6, help="the network's latency a message (s)")
    ap.add_argument("--beta", type=float, default=10e9, help="the network's bandwidth a rank (bytes/s)")
    ap.add_argument("--plot", help="PNG of the efficiencies")
    ap.add_argument("--json", help="the projections as JSON")
    ap.add_argument("--validate", action="store_true", help="compare the replayed decomposition with the counted runs")
    a = ap.parse_args()
    a.drift = {int(k): float(v) for k, v in (item.split(":") for item in a.drift.split(","))}
    drift_label = ", ".join(f"x{v:g} on {k}" for k, v in sorted(a.drift.items()))
    if a.validate:
        validate(a.counts)
    if a.fit_memory:
        for case in ("seed2d", "baffled3d"):
            if counted(a.counts, case):
                fit_memory(a.counts, case)
        return 0
    Ps = [2 ** k for k in range(11)]
    out = {}
    # the sloshing runs whose collectives a step the drifted columns take: (a)'s numerics (the split, rebuilds every 2-3
    # steps in the slams), and for (b) the case file's own (no split: seed2d_slosh_5mm)
    for key, case, slosh_case, lat, walls, dim, h, steps, cost in [
        ("a", "seed2d", "seed2d_slosh", lambda: lattice_seed2d(0.00035), lambda: walls_seed2d(0.0007), 2, 0.0007,
         a.steps2d, a.cost2d),
        ("b", "baffled3d", "seed2d_slosh_5mm", lambda: lattice_baffled3d(0.001, 0.1), lambda: walls_baffled3d(0.002, 0.1),
         3, 0.002, a.steps3d, a.cost3d),
    ]:
        runs = counted(a.counts, case)
        if not runs:
            print(f"no counted runs of {case} in {a.counts}", file=sys.stderr)
            continue
        r = rates(runs)
        # over a sloshing run the lists' rebuilds, the migrations and the cuts' moves add their collectives
        slosh = {P: s for P, s in counted(a.counts, slosh_case).items() if P > 1}
        coll_slosh = max(rates(slosh)["collectives"], r["collectives"]) if slosh else r["collectives"]
        x, lo, hi, w = lat()
        decs = decompositions(x, w, lo, hi, h, Ps)
        decs_work = decompositions(x, w, lo, hi, h, Ps, on_work=True)
        el = walls()
        margin = element_margin(h, a.element_radius)
        if dim == 3:
            elements = {P: elements_per_rank(d, el, margin) for P, d in decs_work.items()}
        else:  # a polygon's segments are not distributed (a few thousand): every rank holds them all
            elements = {P: np.full(P, len(el)) for P in decs_work}
        mem = a.mem3d if dim == 3 else a.mem2d
        common = dict(dim=dim, steps=steps, cost=cost, ghost_cost=a.ghost_share * cost, r=r, alpha=a.alpha, beta=a.beta)
        rows = project(decs_work, mem=mem, elements=elements, nelements=len(el), **common)
        scen = {"drifted": project(decs_work, drift=a.drift, collectives=coll_slosh, **common),
                "cuts on particles": project(decs, **common)}
        out[key] = dict(case=case, particles=len(x), wall_elements=len(el), steps=steps, cost=cost, rates=r, rows=rows,
                        collectives_sloshing=coll_slosh, scenarios=scen)
        print(f"\n({key}) {case}: {len(x)} particles, {len(el)} wall elements, {steps:.0f} steps, {cost:.3g} s per "
              f"particle-step on one core; counted: {r['collectives']:.1f} collectives/step, "
              f"{r['messages_per_sendrank']:.1f} messages/step per rank sent to, {r['bytes_per_ghost']:.0f} bytes/ghost/step; "
              f"{coll_slosh:.2f} collectives/step over the sloshing run ({slosh_case}: the drifted column)")
        print("cores  grid       owned max  work imb.  ghosts max  send ranks  compute ms  halo ms  coll ms   step ms"
              "   wall time  efficiency  elements max  memory max (MB) | " + "  ".join(scen))
        for k, w in enumerate(rows):
            print(f"{w['P']:5d}  {'x'.join(map(str, w['grid'])):9s} {w['owned_max']:10d} {w['work_imbalance']:9.3f}"
                  f" {w['ghosts_max']:10d} {w['sendranks_max']:10d} {1e3 * w['compute']:11.3f} {1e3 * w['halo']:8.3f}"
                  f" {1e3 * w['collectives']:8.3f} {1e3 * w['step']:9.3f}  {fmt_time(w['wall']):>10s}  "
                  f"{100 * w['efficiency']:8.1f} %  {w['elements_max']:12d}  {w['memory_max'] / 1e6:15.1f} | "
                  + "  ".join(f"{100 * scen[s][k]['efficiency']:8.1f} %" for s in scen))
    if a.json:
        json.dump(out, open(a.json, "w"), indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    if a.plot and out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 3, figsize=(14, 4))
        for key, o in out.items():
            P = [w["P"] for w in o["rows"]]
            ax[0].loglog(P, [w["wall"] / 3600 for w in o["rows"]], "o-", label=f"({key}) {o['case']}, {o['particles']:,} particles")
            line = ax[1].semilogx(P, [100 * w["efficiency"] for w in o["rows"]], "o-", label=f"({key})")
            ax[1].semilogx(P, [100 * w["efficiency"] for w in o["scenarios"]["drifted"]], "s--", color=line[0].get_color(),
                           label=f"({key}) drifted ({drift_label} ranks)")
            line = ax[2].loglog(P, [w["memory_max"] / 1e6 for w in o["rows"]], "o-", label=f"({key})")
            if o["rows"][-1]["memory_every_element"] > 1.01 * o["rows"][-1]["memory_max"]:
                ax[2].loglog(P, [w["memory_every_element"] / 1e6 for w in o["rows"]], "x:", color=line[0].get_color(),
                             label=f"({key}) every wall element on every rank")
        for o in out.values():
            ax[0].loglog(P, [o["rows"][0]["wall"] / 3600 / p for p in P], "k:", lw=0.8)
        ax[2].set_xlabel("cores")
        ax[2].set_ylabel("memory of the fullest rank (MB)")
        ax[2].legend(fontsize=8)
        ax[0].set_xlabel("cores")
        ax[0].set_ylabel("wall time of 3 s (h)")
        ax[0].legend(fontsize=8)
        ax[1].set_xlabel("cores")
        ax[1].set_ylabel("parallel efficiency (%)")
        ax[1].set_ylim(0, 105)
        ax[1].legend(fontsize=7, loc="lower left")
        for axis in ax:
            axis.grid(True, which="both", lw=0.3)
        fig.suptitle(f"flexslosh projected (latency {a.alpha * 1e6:.1f} us, bandwidth {a.beta / 1e9:.0f} GB/s)", fontsize=10)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)


if __name__ == "__main__":
    sys.exit(main())

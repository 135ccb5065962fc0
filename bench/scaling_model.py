#!/usr/bin/env python3
"""The scaling model of docs/performance.md ("A measured scaling model"): the wall time and parallel
efficiency of a run on 1 to 1,024 cores from
  - the decomposition flexslosh makes (FSDecompChooseGrid and FSDecompBalance of src/particles/decomp.c,
    replayed here on the case's initial particle lattice: owned particles, ghosts, ranks sent to);
  - the per-core cost of a particle-step, measured on 1 and 2 ranks (--cost, seconds per particle-step,
    and --ghost-cost, per ghost-step);
  - the counted runs of bench/bench_scaling.py (--counts: their summary.json): collectives per step, halo
    messages per step per rank sent to, bytes per ghost per step, the wall pressure's values reduced per
    right-hand side, the load imbalance of the pair lists over the ghosts' and particles' counts;
  - an assumed network: latency alpha, bandwidth beta (InfiniBand-class: 1.5 us, 10 GB/s), an allreduce
    costing ceil(log2 P) alpha plus, for long vectors, 2 n bytes / beta.

    T_step(P) = c N_max(P) k_imb + c_g G_max(P)                       (compute, the slowest rank)
              + m S_max(P) alpha + b G_max(P) / beta                   (halo: messages, bytes)
              + C ceil(log2 P) alpha                                   (collectives)
              + r [ceil(log2 P) alpha + 2 * 8 V / beta + 8 V / mu]     (the wall pressure's sums: r per step,
                                                                        V values each, mu: memory bandwidth)
    T(P) = steps T_step(P);  efficiency E(P) = T(1) / (P T(P))

The wall pressure's sums are neighbour messages since issue 37 (r = 0 in the counts; their messages and bytes are
in the halo's m and b). Scenarios beside the cuts on the particles: the cuts on the work (-fs_balance work, the
default, replayed with the pairs' share standing for the work), the imbalance's drift over a sloshing run with the
cuts following the liquid (--drift), and the collectives with the time-series rows thinned out (<case>_thin runs).

    /usr/bin/python3 bench/scaling_model.py --counts /tmp/scal/counted [--plot docs/images/scaling.png]
"""
import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

NBINS = 4096


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
    if weights is not None:
        return grid, owned, ghosts, sendranks, np.bincount(rank, weights=weights, minlength=P)
    return grid, owned, ghosts, sendranks


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
    """From the counted runs of a case (P >= 2): collectives per step, halo messages per step per rank sent to,
    bytes sent per ghost per step, wall-pressure reductions per step and values per reduction at that dx, and the
    pairs' imbalance over the owned particles' (what the pair lists add to the count's imbalance) per P."""
    col, msg, byt, imb = [], [], [], {}
    for P, s in runs.items():
        if P < 2:
            continue
        p = s["parallel"]
        col.append(max(p["collectives_per_step"]))
        sr = sum(p["send_ranks"])
        msg.append(sum(p["messages_per_step"]) / max(sr, 1))
        byt.append(sum(p["bytes_per_step"]) / max(sum(p["ghosts_mean"]), 1))
        imb[P] = p["imbalance_pairs"] / max(p["imbalance_owned"], 1e-9)
    s = runs[max(runs)]
    rhs_per_step = s["rhs_evaluations"] / max(s["steps"], 1)
    return dict(collectives=max(col), messages_per_sendrank=float(np.mean(msg)), bytes_per_ghost=float(np.mean(byt)),
                wp_reductions=s.get("wall_pressure_reductions", 0) * rhs_per_step,
                wp_values=s.get("wall_pressure_reduced_values", 0) / max(s.get("wall_pressure_reductions", 1), 1),
                dx=s["dx"], pair_imbalance=imb)


def decompositions(x, w, lo, hi, h, Ps, on_work=False):
    """The replayed decomposition on each P of Ps: {P: (grid, owned, ghosts, sendranks, work)}."""
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


def project(decs, dim, steps, cost, ghost_cost, r, wp_values, alpha=1.5e-6, beta=10e9, mu=10e9, drift=1.0,
            collectives=None, wall_pressure=True):
    """Wall time (s) and efficiency on each P of the decompositions decs, with the breakdown of a step."""
    rows = []
    for P, (grid, owned, ghosts, sendranks, work) in sorted(decs.items()):
        comp = cost * work.max() * drift_at(drift, P) + ghost_cost * ghosts.max()
        lg = math.ceil(math.log2(P)) if P > 1 else 0
        halo = (r["messages_per_sendrank"] * sendranks.max() * alpha + r["bytes_per_ghost"] * ghosts.max() / beta) if P > 1 else 0
        coll = (collectives or r["collectives"]) * lg * alpha
        wp = r["wp_reductions"] * (2 * 8 * wp_values / beta + 8 * wp_values / mu) if P > 1 and wall_pressure else 0
        rows.append(dict(P=P, grid=grid[:dim], owned_max=int(owned.max()), ghosts_max=int(ghosts.max()),
                         work_imbalance=float(work.max() * P / work.sum()), sendranks_max=int(sendranks.max()),
                         compute=comp, halo=halo, collectives=coll, wall_pressure=wp, step=comp + halo + coll + wp))
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
            grid, owned, ghosts, sendranks, _ = decompose(x, dlo, dhi, P, 2.5 * h, w)
            _, owned_w, ghosts_w, sendranks_w, _ = decompose(x, dlo, dhi, P, 2.5 * h, w, on_work=True)
            print(f"  {case:9s} {P:3d} ranks: grid {'x'.join(str(int(g)) for g in p['grid'])} / {'x'.join(map(str, grid[:x.shape[1]]))}"
                  f"  owned {max(p['owned_first']):6.0f} / {owned.max():6d} / {owned_w.max():6d}"
                  f"  ghosts {max(p['ghosts_first']):6.0f} / {ghosts.max():6d} / {ghosts_w.max():6d}"
                  f"  send ranks {max(p['send_ranks']):3.0f} / {sendranks.max():3d} / {sendranks_w.max():3d}")


def fmt_time(t):
    return f"{t / 3600:.1f} h" if t >= 3600 else (f"{t / 60:.1f} min" if t >= 60 else f"{t:.1f} s")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", required=True, help="bench_scaling.py's --out")
    ap.add_argument("--cost2d", type=float, default=4.43e-6,
                    help="s per particle-step, one core, the seed's 2-D tank (bench_scaling.py --timed)")
    ap.add_argument("--cost3d", type=float, default=6.6e-5,
                    help="s per particle-step, one core, the 3-D baffled tank (bench_scaling.py --timed, dx = 2.5 mm)")
    ap.add_argument("--ghost-share", type=float, default=0.02, help="a ghost's cost per step over a particle's")
    ap.add_argument("--steps2d", type=float, default=284000, help="steps of (a): 3 s")
    ap.add_argument("--steps3d", type=float, default=87000, help="steps of (b): 3 s")
    ap.add_argument("--wp3d", type=float, nargs=2, default=[589400, 0.0025], metavar=("VALUES", "DX"),
                    help="the 3-D tank's wall-pressure values per sum measured at DX (0.1 m wide; scaled by 1/dx^2)")
    ap.add_argument("--drift", default="2:1.013,8:1.201",
                    help="the pair lists' imbalance over a sloshing run, the cuts moving with the liquid (a scenario), "
                         "measured on some rank counts (P:factor,...; bench_scaling.py --cases seed2d_slosh): "
                         "interpolated in log2 P from 1 on one rank, the last one's beyond")
    ap.add_argument("--collectives-series", type=float, default=None,
                    help="collectives per step with the time-series rows thinned out (a scenario; default: counted, "
                         "the largest of bench_scaling.py's <case>_thin runs in --counts)")
    ap.add_argument("--alpha", type=float, default=1.5e-6)
    ap.add_argument("--beta", type=float, default=10e9)
    ap.add_argument("--plot", help="PNG of the efficiencies")
    ap.add_argument("--json", help="the projections as JSON")
    ap.add_argument("--validate", action="store_true", help="compare the replayed decomposition with the counted runs")
    a = ap.parse_args()
    a.drift = {int(k): float(v) for k, v in (item.split(":") for item in a.drift.split(","))}
    drift_label = ", ".join(f"x{v:g} on {k}" for k, v in sorted(a.drift.items()))
    if a.validate:
        validate(a.counts)
    Ps = [2 ** k for k in range(11)]
    out = {}
    for key, case, lat, dim, h, steps, cost in [
        ("a", "seed2d", lambda: lattice_seed2d(0.00035), 2, 0.0007, a.steps2d, a.cost2d),
        ("b", "baffled3d", lambda: lattice_baffled3d(0.001, 0.1), 3, 0.002, a.steps3d, a.cost3d),
    ]:
        runs = counted(a.counts, case)
        if not runs:
            print(f"no counted runs of {case} in {a.counts}", file=sys.stderr)
            continue
        r = rates(runs)
        thin = counted(a.counts, case + "_thin")
        coll_thin = a.collectives_series or (rates(thin)["collectives"] if len(thin) > 1 else r["collectives"])
        # over a sloshing run the lists' rebuilds, the migrations and the cuts' moves add their collectives
        slosh = {P: s for P, s in counted(a.counts, "seed2d_slosh").items() if P > 1}
        coll_slosh = max(rates(slosh)["collectives"], r["collectives"]) if slosh else r["collectives"]
        dx = h / 2
        if dim == 2:  # segments ~ 1/dx
            wp_values = r["wp_values"] * r["dx"] / dx
        else:  # triangles ~ 1/dx^2, from the 0.1 m wide tank's count (the counted runs' is 0.05 m wide)
            wp_values = a.wp3d[0] * (a.wp3d[1] / dx) ** 2
        x, lo, hi, w = lat()
        decs = decompositions(x, w, lo, hi, h, Ps)
        decs_work = decompositions(x, w, lo, hi, h, Ps, on_work=True)
        common = dict(dim=dim, steps=steps, cost=cost, ghost_cost=a.ghost_share * cost, r=r, wp_values=wp_values,
                      alpha=a.alpha, beta=a.beta)
        rows = project(decs, **common)
        scen = {"drift": project(decs, drift=a.drift, collectives=coll_slosh, **common),
                "work": project(decs_work, **common),
                "work_drift": project(decs_work, drift=a.drift, collectives=coll_slosh, **common),
                "all": project(decs_work, drift=a.drift, collectives=coll_slosh - r["collectives"] + coll_thin,
                               **common)}
        out[key] = dict(case=case, particles=len(x), steps=steps, cost=cost, rates=r, wp_values=wp_values, rows=rows,
                        collectives_thinned=coll_thin, collectives_sloshing=coll_slosh,
                        scenarios=scen)
        print(f"\n({key}) {case}: {len(x)} particles, {steps:.0f} steps, {cost:.3g} s per particle-step on one core; "
              f"counted rates: {r['collectives']:.1f} collectives/step, {r['messages_per_sendrank']:.1f} messages/step "
              f"per rank sent to, {r['bytes_per_ghost']:.0f} bytes/ghost/step, {r['wp_reductions']:.0f} wall-pressure "
              f"sums/step of {wp_values:.0f} values; {coll_thin:.2f} collectives/step with the rows thinned out, "
              f"{coll_slosh:.2f} over a sloshing second (the drifted columns)")
        print("cores  grid       owned max  work imb.  ghosts max  send ranks  compute ms  halo ms  coll ms  wall-p ms"
              "   step ms   wall time  efficiency | drifted  cuts on work  and drifted  and rows thinned")
        for k, w in enumerate(rows):
            print(f"{w['P']:5d}  {'x'.join(map(str, w['grid'])):9s} {w['owned_max']:10d} {w['work_imbalance']:9.3f}"
                  f" {w['ghosts_max']:10d} {w['sendranks_max']:10d} {1e3 * w['compute']:11.3f} {1e3 * w['halo']:8.3f}"
                  f" {1e3 * w['collectives']:8.3f} {1e3 * w['wall_pressure']:9.3f} {1e3 * w['step']:9.3f}  "
                  f"{fmt_time(w['wall']):>10s}  {100 * w['efficiency']:8.1f} % | "
                  + "  ".join(f"{100 * scen[s][k]['efficiency']:8.1f} %" for s in scen))
    if a.json:
        json.dump(out, open(a.json, "w"), indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    if a.plot and out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for key, o in out.items():
            P = [w["P"] for w in o["rows"]]
            ax[0].loglog(P, [w["wall"] / 3600 for w in o["rows"]], "o-", label=f"({key}) {o['case']}, {o['particles']:,} particles")
            line = ax[1].semilogx(P, [100 * w["efficiency"] for w in o["rows"]], "o-", label=f"({key}) cuts on particles")
            ax[1].semilogx(P, [100 * w["efficiency"] for w in o["scenarios"]["work"]], "s--", color=line[0].get_color(),
                           label=f"({key}) cuts on work (-fs_balance work)")
            ax[1].semilogx(P, [100 * w["efficiency"] for w in o["scenarios"]["all"]], ":", color=line[0].get_color(),
                           label=f"({key}) cuts on work, drifted ({drift_label} ranks), rows thinned")
        for o in out.values():
            ax[0].loglog(P, [o["rows"][0]["wall"] / 3600 / p for p in P], "k:", lw=0.8)
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

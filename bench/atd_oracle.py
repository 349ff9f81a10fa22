"""Is the true successor even the nearest? An oracle bound for sparse AIS (ATD 2025,
~30-min posits) cut at known 30–60 min gaps (issue 15 goal 3a; session 27).

    python bench/atd_oracle.py [FILE] [--gaps 1800 3600] [--reach 7200]

FILE defaults to ../shared/data/real/atd2025-noaa/example_truth.csv.gz (MIT; read from
$WAKELINE_SHARED or ../shared); the cut is ``bench/atd_known_gaps.py``'s
(``cut_known_gaps(lo, hi, seed=0)``, one window per track). Every (end i, start j) with
0 < start − end ≤ ``--reach`` s is a candidate. Per predictor, the miss (m) of the start's
first fix against where the end says the ship is after the gap ``T``:

- ``distance``: no motion, |p_j − p_i|;
- ``end DR``: the end's last reported SOG/COG, p_i + v_i·T;
- ``start DR``: backwards from the start's first reported SOG/COG, p_j − v_j·T;
- ``mean DR``: the mean of both reported velocities (``atd_known_gaps.py --baseline``);
- ``one turn``: one course change in the gap, v_i then v_j (the association's predictor,
  on the reported velocities);
- ``fitted end``: the end's velocity from its last two fixes (a 30-min leg).

Each is ranked raw and per second of gap (miss / T: a predictor's error grows with the
gap, so a later start is not nearer for being later). Printed per predictor and ranking:
the share of true pairs whose successor is the end's nearest start (``fwd``), whose end is
the start's nearest end (``bwd``), both (``mutual``); then the same for *any* predictor
(the oracle: some predictor puts the truth first) — all shares of the true pairs that
are candidates (gap within ``--reach``, reachable at ``--v-max`` kn plus 2 km) — and a
one-to-one assignment by each
predictor (``optimal_assign`` over each end's and start's 10 nearest, the gate at the
true pairs' own cost quantiles 30-99 %): P_CA of the true pairs within reach / P_FA of
every join, per gate. ``--ours``: the association at its defaults, scored alike.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from wakeline.core import geo
from wakeline.core.associate import _miss_one_turn, optimal_assign
from wakeline.core.evaluate_association import (
    _truth,
    consecutive_true_pairs,
    cut_known_gaps,
    pair_scores,
)
from wakeline.core.io import read_points
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import sort_points, track_index

SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD = SHARED / "data/real/atd2025-noaa/example_truth.csv.gz"


def candidates(t_end: np.ndarray, t_start: np.ndarray, reach_s: float):
    """Every (end i, start j) with 0 < t_start[j] − t_end[i] ≤ reach_s."""
    by_t = np.argsort(t_start, kind="stable")
    ts = t_start[by_t]
    lo = np.searchsorted(ts, t_end, side="right")
    hi = np.searchsorted(ts, t_end + reach_s, side="right")
    cnt = hi - lo
    i = np.repeat(np.arange(len(t_end)), cnt)
    # the k-th candidate of end i is by_t[lo[i] + k]
    first = np.repeat(np.cumsum(cnt) - cnt, cnt)
    j = by_t[np.repeat(lo, cnt) + np.arange(len(i)) - first]
    return i, j


def nearest(owner: np.ndarray, cost: np.ndarray, n: int) -> np.ndarray:
    """Per owner (0..n−1): the index of its cheapest row (−1 when none)."""
    order = np.lexsort((cost, owner))
    first = np.r_[True, owner[order][1:] != owner[order][:-1]]
    out = np.full(n, -1)
    out[owner[order][first]] = order[first]
    return out


def k_nearest(owner: np.ndarray, cost: np.ndarray, k: int) -> np.ndarray:
    """Mask of each owner's ``k`` cheapest rows."""
    order = np.lexsort((cost, owner))
    o = owner[order]
    start = np.r_[0, np.flatnonzero(o[1:] != o[:-1]) + 1]
    rank = np.arange(len(o)) - np.repeat(start, np.diff(np.r_[start, len(o)]))
    keep = np.zeros(len(owner), dtype=bool)
    keep[order[rank < k]] = True
    return keep


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", default=ATD)
    ap.add_argument("--gaps", nargs=2, type=float, default=(1800.0, 3600.0))
    ap.add_argument("--reach", type=float, default=7200.0)
    ap.add_argument("--k", type=int, default=10, help="nearest per end / start assigned")
    ap.add_argument("--v-max", type=float, default=40.0, help="kn, the candidates' reach")
    ap.add_argument("--ours", action="store_true", help="also ours, optimal, scored alike")
    ap.add_argument(
        "--every",
        type=float,
        default=None,
        help="one window in every S s of track, only where the gap it leaves is known "
        "(cut_known_gaps' every_s; default: one window per track, as atd_known_gaps.py)",
    )
    a = ap.parse_args(argv)
    cpu = time.process_time()
    pts = read_points(a.file, mapping=["batch=track_id"]).points
    cut = cut_known_gaps(pts.assign(truth=_truth(pts)), *a.gaps, seed=0, every_s=a.every)
    df = sort_points(cut).reset_index(drop=True)
    ix = track_index(df)
    t = time_seconds(df["time"])
    lon, lat = df["lon"].to_numpy(), df["lat"].to_numpy()
    sog = df["speed"].to_numpy() * geo.KN_MS
    cog = np.radians(df["course"].to_numpy())
    vx, vy = sog * np.sin(cog), sog * np.cos(cog)
    e, s = ix.ends - 1, ix.starts
    n = len(s)
    truth = df["truth"].astype(str).to_numpy()
    true = consecutive_true_pairs(truth[s], t[s])
    i, j = candidates(t[e], t[s], a.reach)
    gap = t[s[j]] - t[e[i]]
    # the start's first fix in metres from the end's last fix (the end's plane); only
    # pairs reachable at --v-max kn plus 2 km (the rest are no one's nearest)
    px, py = geo.to_local(lon[s[j]], lat[s[j]], lon[e[i]], lat[e[i]])
    ok = np.hypot(px, py) <= a.v_max * geo.KN_MS * gap + 2000.0
    i, j, gap, px, py = i[ok], j[ok], gap[ok], px[ok], py[ok]
    # a 2-fix velocity at each end (nan for a single fix)
    two = (ix.ends - ix.starts) >= 2
    pe = np.where(two, e - 1, e)
    dt = t[e] - t[pe]
    ex, ey = geo.to_local(lon[e], lat[e], lon[pe], lat[pe])
    with np.errstate(invalid="ignore", divide="ignore"):
        fvx = np.where(two & (dt > 0), ex / dt, np.nan)
        fvy = np.where(two & (dt > 0), ey / dt, np.nan)
    vix, viy = vx[e[i]], vy[e[i]]
    vjx, vjy = vx[s[j]], vy[s[j]]
    miss = {
        "distance": np.hypot(px, py),
        "end DR": np.hypot(px - vix * gap, py - viy * gap),
        "start DR": np.hypot(px - vjx * gap, py - vjy * gap),
        "mean DR": np.hypot(px - 0.5 * (vix + vjx) * gap, py - 0.5 * (viy + vjy) * gap),
        "one turn": _miss_one_turn(px, py, vix * gap, viy * gap, vjx * gap, vjy * gap),
        "fitted end": np.where(
            np.isfinite(fvx[i]),
            np.hypot(px - fvx[i] * gap, py - fvy[i] * gap),
            np.hypot(px - vix * gap, py - viy * gap),  # a single fix: its reported velocity
        ),
    }
    ti = np.array([p[0] for p in sorted(true)])
    tj = np.array([p[1] for p in sorted(true)])
    key = i * n + j
    order = np.argsort(key)
    at = order[np.searchsorted(key[order], ti * n + tj)]
    found = key[at] == ti * n + tj
    t_gap = t[s[tj]] - t[e[ti]]
    print(
        f"{Path(a.file).name}: known gaps {a.gaps[0]:g}-{a.gaps[1]:g} s"
        f"{f' every {a.every:g} s' if a.every else ''}, {n} pieces, "
        f"{len(true)} true pairs ({int(found.sum())} candidates within {a.reach:g} s; raw gap "
        "10/50/90 % "
        f"{np.percentile(t_gap, 10):.0f} / {np.percentile(t_gap, 50):.0f} / "
        f"{np.percentile(t_gap, 90):.0f} s), {len(i):,} candidates "
        f"(per end median {np.median(np.bincount(i, minlength=n)):.0f})"
    )
    ti, tj, at = ti[found], tj[found], at[found]
    m = len(ti)  # shares below: of the true pairs that are candidates
    reach = set(zip(ti.tolist(), tj.tolist(), strict=True))
    print(f"{'predictor':<12} {'rank':<6} {'fwd':>6} {'bwd':>6} {'mutual':>6}  median miss m")
    any_fwd = np.zeros(len(ti), dtype=bool)
    any_mut = np.zeros(len(ti), dtype=bool)
    costs = {}
    for name, mv in miss.items():
        for rank, c in (("raw", mv), ("per s", mv / gap)):
            fwd = nearest(i, c, n)[ti] == at
            bwd = nearest(j, c, n)[tj] == at
            any_fwd |= fwd
            any_mut |= fwd & bwd
            costs[(name, rank)] = c
            print(
                f"{name:<12} {rank:<6} {fwd.sum() / m:6.3f} {bwd.sum() / m:6.3f} "
                f"{(fwd & bwd).sum() / m:6.3f}  {np.median(mv[at]):.0f}"
            )
    print(
        f"any predictor: the truth is the end's nearest start for {any_fwd.sum() / m:.3f} of "
        f"the true pairs, mutual nearest for {any_mut.sum() / m:.3f}"
    )
    print(
        "one-to-one assignment by each predictor (gate at the true pairs' cost quantiles; "
        "P_CA of the true pairs within reach, P_FA of every join):"
    )
    qs = (30, 50, 70, 80, 90, 95, 99)
    print(f"{'predictor':<12} {'rank':<6} " + " ".join(f"{'q' + str(q):>11}" for q in qs))
    for (name, rank), c in costs.items():
        keep = k_nearest(i, c, a.k) | k_nearest(j, c, a.k)
        ki, kj, kc = i[keep], j[keep], c[keep]
        cells = []
        for q in qs:
            gate = float(np.percentile(c[at], q))
            ch = optimal_assign(ki, kj, kc, gate)
            # P_CA over the true pairs within reach, P_FA over every join
            sc = pair_scores(set(zip(ki[ch].tolist(), kj[ch].tolist(), strict=True)), reach)
            cells.append(f"{sc['p_ca']:.3f}/{sc['p_fa']:.3f}")
        print(f"{name:<12} {rank:<6} " + " ".join(f"{x:>11}" for x in cells))
    if a.ours:
        # ours, optimal, at today's defaults, scored the same way (its pieces renumbered:
        # matched to these by (truth, first time))
        from wakeline.core.evaluate_association import run_method

        res = run_method(cut, "ours, optimal")
        seg = res.segments
        key_of = {
            (tr, tt): k
            for k, (tr, tt) in enumerate(zip(truth[s].tolist(), t[s].tolist(), strict=True))
        }
        o_tr = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
        o_t = time_seconds(seg.points["time"])[seg.index.starts]
        mine = np.array([key_of[(x, y)] for x, y in zip(o_tr.tolist(), o_t.tolist(), strict=True)])
        ch = res.chosen
        out = set(zip(mine[res.pairs.i[ch]].tolist(), mine[res.pairs.j[ch]].tolist(), strict=True))
        sc = pair_scores(out, reach)
        print(
            f"ours, optimal (defaults): P_CA {sc['p_ca']:.3f} of the true pairs within reach, "
            f"P_FA {sc['p_fa']:.3f} ({len(out)} joins; over every true pair "
            f"{pair_scores(out, true)['p_ca']:.3f})"
        )
    print(f"CPU {time.process_time() - cpu:.0f} s")


if __name__ == "__main__":
    main()

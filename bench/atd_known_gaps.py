"""Where the joins on sparse AIS (ATD 2025, ~30-min posits) at known 30–60 min gaps come
from: right and wrong joins by the band of their gap as the time limits count it (``first``
≤ ``max_gap_s`` < ``soft`` ≤ ``soft_gap_s`` < ``long``), with raw gaps and piece sizes.

    python bench/atd_known_gaps.py [FILE] [--set NAME=VALUE ...]

FILE defaults to ../shared/data/real/atd2025-noaa/example_truth.csv.gz (MIT; read from
../shared, or WAKELINE_SHARED). Session 21: with each end's 30-min step counted as T_gap,
1,143 of 1,346 wrong joins were in the first band (gaps of about one report).

``--baseline`` also prints what the cut leaves within reach (true pairs by raw gap) and a
plain dead reckoning on the reported speed and course (the mean of the end's last report
and the start's first, a gate of ``g0 + r × gap`` metres, greedy by miss / gate): how far
a rule with no model of the ships' turns or density gets on the same cut (session 22).
"""

import argparse
import os
from pathlib import Path

import numpy as np

from wakeline.core.associate import LinkParams, counted_gap
from wakeline.core.evaluate_association import _truth, cut_known_gaps, run_method
from wakeline.core.io import read_points

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD = SHARED / "data/real/atd2025-noaa/example_truth.csv.gz"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", default=ATD)
    ap.add_argument("--set", action="append", default=[], help="LinkParams NAME=VALUE")
    ap.add_argument("--gaps", nargs=2, type=float, default=(1800.0, 3600.0))
    ap.add_argument("--baseline", action="store_true", help="reach and dead-reckoning rows")
    a = ap.parse_args(argv)
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set))
    pts = read_points(a.file, mapping=["batch=track_id"]).points
    cut = cut_known_gaps(pts.assign(truth=_truth(pts)), *a.gaps, seed=0)
    res = run_method(cut, "ours, optimal", params)
    seg = res.segments
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    ch = res.chosen
    i, j = res.pairs.i[ch], res.pairs.j[ch]
    right = truth[i] == truth[j]
    counted = counted_gap(res.pairs)[ch]
    band = np.where(
        counted <= params.max_gap_s,
        "first",
        np.where(counted <= max(params.soft_gap_s, params.max_gap_s), "soft", "long"),
    )
    print(f"{Path(a.file).name}, known gaps {a.gaps[0]:g}-{a.gaps[1]:g} s")
    print(f"joins {len(ch)}: right {int(right.sum())}, wrong {int((~right).sum())}")
    for b in ("first", "soft", "long"):
        m = band == b
        print(f"  {b:<5} right {int((right & m).sum()):5d}  wrong {int((~right & m).sum()):5d}")
    for name, m in (("right", right), ("wrong", ~right)):
        if m.any():
            q = np.percentile(res.pairs.gap_s[ch][m], [10, 50, 90])
            print(f"  {name}: raw gap 10/50/90 % {q[0]:.0f} / {q[1]:.0f} / {q[2]:.0f} s")
    single = (seg.n[i] == 1) | (seg.n[j] == 1)
    print(f"  wrong joins with a single-fix piece: {int((~right & single).sum())}")
    if a.baseline:
        baseline(cut)


def baseline(cut, reach_s: float = 7200.0) -> None:
    """Reach of the cut's true pairs, and plain dead reckoning on the reported motion."""
    from wakeline.core import geo
    from wakeline.core.evaluate_association import consecutive_true_pairs, pair_scores
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import sort_points, track_index

    df = sort_points(cut).reset_index(drop=True)
    ix = track_index(df)
    t = time_seconds(df["time"])
    lon, lat = df["lon"].to_numpy(), df["lat"].to_numpy()
    sog = df["speed"].to_numpy() * geo.KN_MS
    cog = np.radians(df["course"].to_numpy())
    vx, vy = sog * np.sin(cog), sog * np.cos(cog)
    e, s = ix.ends - 1, ix.starts
    truth = df["truth"].astype(str).to_numpy()
    true = consecutive_true_pairs(truth[s], t[s])
    ti, tj = np.array(sorted(true)).T
    gap_true = t[s[tj]] - t[e[ti]]
    print(f"true pairs {len(true)}; within reach by raw gap:")
    for h in (3600, 5400, 7200, 14400):
        print(f"  <= {h:5d} s: {np.mean(gap_true <= h):.3f}")
    tr = ix.track_of_row
    inner = (tr[1:] == tr[:-1]) & (np.diff(t) >= 1800) & (np.diff(t) <= 3600)
    moved = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])[inner]
    q = np.percentile(moved, [50, 90])
    print(f"  a 30-60 min step inside a piece moves (50 / 90 %): {q[0]:.0f} / {q[1]:.0f} m")
    # Every (end, start) pair with a start 0 < gap <= reach_s after the end.
    by_t = np.argsort(t[s])
    ts = t[s][by_t]
    lo = np.searchsorted(ts, t[e], side="right")
    hi = np.searchsorted(ts, t[e] + reach_s, side="right")
    i = np.repeat(np.arange(len(e)), hi - lo)
    j = by_t[np.concatenate([np.arange(a, b) for a, b in zip(lo, hi, strict=True)])]
    gap = t[s[j]] - t[e[i]]
    ue, ve = 0.5 * (vx[e[i]] + vx[s[j]]), 0.5 * (vy[e[i]] + vy[s[j]])
    dx, dy = geo.to_local(lon[s[j]], lat[s[j]], lon[e[i]], lat[e[i]])
    miss = np.hypot(dx - ue * gap, dy - ve * gap)
    for g0, r in ((300.0, 0.2), (500.0, 0.3), (1000.0, 0.5)):
        gate = g0 + r * gap
        k = np.flatnonzero(miss < gate)
        k = k[np.argsort(miss[k] / gate[k], kind="stable")]
        used_i, used_j, out = set(), set(), set()
        for q in k:  # greedy, best first (a bench, not a hot path)
            a_, b_ = int(i[q]), int(j[q])
            if a_ not in used_i and b_ not in used_j:
                used_i.add(a_)
                used_j.add(b_)
                out.add((a_, b_))
        sc = pair_scores(out, true)
        print(
            f"  dead reckoning, gate {g0:g} m + {r:g} x gap (s), reach {reach_s:g} s: "
            f"P_CA {sc['p_ca']:.3f}  P_FA {sc['p_fa']:.3f}  joins {len(out)}"
        )


if __name__ == "__main__":
    main()

"""Why ours misses and joins wrongly on Saronic's days overlaid on one day at long known
gaps (issue 15 goal 3a; session 27, docs/prereg/session27_overlay.md).

    python bench/overlay_why.py                              # tuning split, 600-1,800 s
    python bench/overlay_why.py --split held                 # held-out split (once)
    python bench/overlay_why.py --set NAME=VALUE [--list]

Splits (fixed before any candidate): ``tune`` = overlay seed 0 (``--seed-overlay 0``:
time-of-day offsets and berth offsets), cut seeds 0, 1, 2; ``held`` = overlay seeds 1 and
2, cut seeds 0, 1, 2 each. ``--spread-m 100`` (berths apart) and one 600-1,800 s window in
every 2 h of track, as ``bench/overlay_days.py --spread-m 100 --bands 600 1800``.

Per missed true pair (every gap): ``no candidate`` (not a candidate up to ``long_gap_s``:
reachability, ``min_gap_steps``, or a gap beyond it), ``taken`` (a piece joined elsewhere:
``taken, cheaper`` when that join costs less than the true pair as the second look prices
it, ``taken, dearer`` else), ``over no_join`` (the true pair costs more than the gate /
``no_join``), ``rival cheaper`` (another candidate of either piece up to ``long_gap_s``,
joined or not, costs less), ``within margin`` (the cheapest of both, but a rival within
the margin). Prices are the second look's (``max_gap_s`` = ``long_gap_s``, the spread
term among all candidates up to it), so a first-pass pair priced here may differ slightly
from the assignment's. Each row is also tagged by the smaller piece's fixes (1, 2-3, 4+),
at rest (``at_rest_pairs``) and the raw gap. Per wrong join: kind (``skip`` / ``loose`` /
``swap``, any gap), band (``first`` / ``soft`` / ``long``), at rest, single fix, and the
true successor's price against the join's.
"""

import argparse
import sys
from collections import Counter
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import overlay_days as od  # noqa: E402

from wakeline.core.associate import (  # noqa: E402
    LinkParams,
    at_rest_pairs,
    candidate_pairs,
    counted_gap,
    pair_cost,
)
from wakeline.core.evaluate_association import (  # noqa: E402
    consecutive_true_pairs,
    pair_scores,
    run_method,
)

SPLITS = {"tune": ((0,), (0, 1, 2)), "held": ((1, 2), (0, 1, 2))}


def _size(n: int) -> str:
    return "1" if n == 1 else ("2-3" if n <= 3 else "4+")


def case_rows(cut, params: LinkParams) -> tuple[list, list, dict]:
    """(miss rows, wrong join rows, scores) of one cut overlay."""
    a = run_method(cut, "ours, optimal", params)
    seg = a.segments
    n = len(seg)
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    true = consecutive_true_pairs(truth, seg.t0)
    ch = a.chosen
    out = {(int(a.pairs.i[k]), int(a.pairs.j[k])): float(a.cost[k]) for k in ch}
    scores = pair_scores(set(out), true)
    scores["correct"] = len(set(out) & true)
    succ = {i: j for i, j in true}
    pred = {j: i for i, j in true}
    wide = replace(params, max_gap_s=params.long_gap_s)
    cand = candidate_pairs(seg, wide)
    cost = pair_cost(cand, wide, "scaled", seg)
    rest = at_rest_pairs(seg, cand, params)
    # the three terms apart (each alone: the position term with its spread)
    terms = [
        pair_cost(cand, replace(wide, alpha=w[0], beta=w[1], gamma=w[2]), "scaled", seg)
        for w in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    ]
    key = {(int(x), int(y)): k for k, (x, y) in enumerate(zip(cand.i, cand.j, strict=True))}
    best_i = np.full(n, np.inf)
    best_j = np.full(n, np.inf)
    np.minimum.at(best_i, cand.i, cost)
    np.minimum.at(best_j, cand.j, cost)
    counted = counted_gap(cand)
    used_i = {i: (i, j) for i, j in out}
    used_j = {j: (i, j) for i, j in out}
    limit = min(params.gate, params.no_join)
    misses = []
    for i, j in sorted(true - set(out)):
        k = key.get((i, j))
        gap = float(seg.t0[j] - seg.t1[i])
        row = {"gap": gap, "size": _size(int(min(seg.n[i], seg.n[j]))), "i": i, "j": j}
        if k is None:
            misses.append({**row, "why": "no candidate", "rest": "?", "cost": np.nan})
            continue
        c = float(cost[k])
        row.update(rest="rest" if rest[k] else "not", cost=c, counted=float(counted[k]))
        row.update(pos=terms[0][k], crs=terms[1][k], spd=terms[2][k], miss_m=cand.miss_m[k])
        row.update(dc=cand.dcourse_deg[k], dv=cand.dspeed_kn[k], dist=cand.dist_m[k])
        other = [used_i[i]] if i in used_i else []
        other += [used_j[j]] if j in used_j else []
        if other:
            oc = min(float(cost[key[p]]) if p in key else out[p] for p in other)
            why = "taken, cheaper" if oc < c else "taken, dearer"
        elif c > limit:
            why = "over no_join"
        else:
            # the cheapest rival of either piece (the pair itself excluded)
            m = ((cand.i == i) | (cand.j == j)) & ~((cand.i == i) & (cand.j == j))
            r = float(cost[m].min()) if m.any() else np.inf
            why = "rival cheaper" if r < c else "within margin"
            row["rival"] = r
        misses.append({**row, "why": why})
    wrongs = []
    for (i, j), c in out.items():
        if (i, j) in true:
            continue
        k = key.get((i, j))
        kind = "skip" if truth[i] == truth[j] else ("swap" if i in succ and j in pred else "loose")
        g = float(seg.t0[j] - seg.t1[i])
        cg = float(counted[k]) if k is not None else g
        band = (
            "first"
            if cg <= params.max_gap_s
            else ("soft" if cg <= max(params.soft_gap_s, params.max_gap_s) else "long")
        )
        alt = [key.get((i, succ[i]))] if i in succ else []
        alt += [key.get((pred[j], j))] if j in pred else []
        alt_c = [float(cost[q]) for q in alt if q is not None]
        wrongs.append(
            {
                "kind": kind,
                "band": band,
                "gap": g,
                "size": _size(int(min(seg.n[i], seg.n[j]))),
                "rest": "rest" if k is not None and rest[k] else "not",
                "cost": float(cost[k]) if k is not None else c,
                "chosen_cost": c,
                "true_cost": min(alt_c) if alt_c else np.nan,
                "i": i,
                "j": j,
            }
        )
    return misses, wrongs, scores


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--split", choices=tuple(SPLITS), default="tune")
    ap.add_argument("--spread-m", type=float, default=100.0)
    ap.add_argument("--band", type=float, nargs=2, default=(600.0, 1800.0))
    ap.add_argument("--every", type=float, default=7200.0)
    ap.add_argument("--set", action="append", default=[], help="LinkParams NAME=VALUE")
    ap.add_argument("--list", action="store_true", help="every miss and wrong join")
    a = ap.parse_args(argv)
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set))
    overlays, seeds = SPLITS[a.split]
    misses, wrongs, tp, jn, cj = [], [], 0, 0, 0
    for so in overlays:
        df = od.overlay_saronic(2.0, so, a.spread_m)
        for sd in seeds:
            c = od.cut(df, tuple(a.band), a.every, sd)
            m, w, s = case_rows(c, params)
            print(
                f"overlay {so} seed {sd}: P_CA {s['p_ca']:.3f} P_FA {s['p_fa']:.3f} "
                f"(true {s['true_pairs']}, joins {s['out_pairs']}, right {s['correct']})"
            )
            tp += s["true_pairs"]
            jn += s["out_pairs"]
            cj += s["correct"]
            misses += [dict(r, case=f"{so}/{sd}") for r in m]
            wrongs += [dict(r, case=f"{so}/{sd}") for r in w]
    print(
        f"{a.split} pooled: P_CA {cj / max(tp, 1):.3f} P_FA {(jn - cj) / max(jn, 1):.3f} "
        f"(true {tp}, joins {jn}, right {cj}); misses {len(misses)}, wrong {len(wrongs)}"
    )
    print("misses by why:", dict(Counter(r["why"] for r in misses).most_common()))
    for col in ("size", "rest"):
        tab = Counter((r["why"], r[col]) for r in misses)
        print(f"  x {col}:", dict(sorted(tab.items())))
    for lo, hi in ((0, 720), (720, 1200), (1200, 1800), (1800, 3600), (3600, np.inf)):
        rs = [r for r in misses if lo < r["gap"] <= hi]
        print(f"  gap {lo}-{hi}: {len(rs)}", dict(Counter(r["why"] for r in rs)))
    print("wrong joins by kind x band:", dict(Counter((r["kind"], r["band"]) for r in wrongs)))
    print("  x rest:", dict(Counter((r["band"], r["rest"]) for r in wrongs)))
    print("  x size:", dict(Counter(r["size"] for r in wrongs)))
    dear = [r for r in wrongs if np.isfinite(r["true_cost"])]
    print(
        f"  with a true alternative priced: {len(dear)}; that alternative cheaper: "
        f"{sum(r['true_cost'] < r['cost'] for r in dear)}; over no_join: "
        f"{sum(r['true_cost'] > min(params.gate, params.no_join) for r in dear)}"
    )
    if a.list:
        for r in sorted(misses, key=lambda r: (r["why"], r["gap"])):
            print(
                f"  miss {r['case']} {r['why']:<14} gap {r['gap']:6.0f} size {r['size']:<3} "
                f"{r['rest']:<4} cost {r['cost']:.2f} rival {r.get('rival', np.nan):.2f} "
                f"pos {r.get('pos', np.nan):.2f} crs {r.get('crs', np.nan):.2f} "
                f"spd {r.get('spd', np.nan):.2f} dc {r.get('dc', np.nan):4.0f} "
                f"dv {r.get('dv', np.nan):4.1f} miss {r.get('miss_m', np.nan):5.0f} "
                f"dist {r.get('dist', np.nan):5.0f}"
            )
        for r in sorted(wrongs, key=lambda r: (r["band"], r["kind"])):
            print(
                f"  wrong {r['case']} {r['kind']:<5} {r['band']:<5} gap {r['gap']:6.0f} "
                f"size {r['size']:<3} {r['rest']:<4} cost {r['cost']:.2f} "
                f"(assigned {r['chosen_cost']:.2f}) "
                f"true alt {r['true_cost']:.2f}"
            )


if __name__ == "__main__":
    main()

"""Why association fails on decimated MTAD (issue 15 goal 3c): every wrong join and every
missed true pair, at any gap, with what decided it.

    python bench/assoc_sparse_why.py --set mtad-tune --rate 180 [--set-param NAME=VALUE] [--list]
    python bench/assoc_sparse_why.py --rate 180 --loose     # what keeps each loose pair loose

Per true pair (consecutive pieces of one track, any gap): joined, or missed because
``beyond`` (not a candidate of any pass: gap over ``soft_gap_s`` and the second look did not
reach it, or over ``long_gap_s``; raw gap), ``unreach`` (gap within reach but no candidate:
reachability, ``min_gap_steps``, soft-gap eligibility), ``taken`` (a piece went to a wrong
join), ``loose`` (a candidate, both pieces left free: cost above ``no_join`` / the gate, or
dropped by the margin / soft-gap test). Per wrong join: the band of its gap as the time
limits count it (``first`` ≤ ``max_gap_s`` < ``soft`` ≤ ``soft_gap_s`` < ``long``; less the
step allowance, ``step_allowance_s``), and whether the old end has a true
successor / the new start a true predecessor at all (``loose``: one of them has none —
a track's last or first piece joined; ``swap``: both had one).
Tallies by the fixes of the smaller piece (1, 2, 3, 4+).

``--loose`` (session 30): per ``loose`` true pair its gap as the time limits count it, its
cost and gap price, the cheapest rival of either piece not claimed more cheaply (its
piece's ship: ``s`` the pair's own, ``o`` another; gap; fixes), the first of: the second
look's only, over ``no_join`` (or by the gap price), a rival cheaper, a rival within the
margin; and which of four terms, taken away alone, joins it (``P`` gap_price 0, ``M``
margin 0, ``N`` no_join = gate = 5, ``L`` the long margins 0; the scene run again each).
"""

import argparse
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import assoc_rates as ar  # noqa: E402
import sampling_sweep as sw  # noqa: E402

from wakeline.core.associate import (  # noqa: E402
    LinkParams,
    _both_moving,
    _gap_price,
    counted_gap,
)
from wakeline.core.evaluate_association import (  # noqa: E402
    _truth,
    consecutive_true_pairs,
    cut_known_gaps,
    run_method,
)


def _fixes(n: int) -> str:
    return str(n) if n < 4 else "4+"


def scene_rows(
    pts, params: LinkParams, gaps, seed: int = 0, loose: bool = True
) -> tuple[list, list]:
    """(true pair rows, wrong join rows) of one scene cut at known ``gaps`` (lo, hi) s."""
    ship = pts["batch"].astype(str).str.split("-").str[0]
    df = pts.assign(truth=_truth(pts.assign(batch=ship)))
    cut = cut_known_gaps(df, *gaps, seed=seed)
    a = run_method(cut, "ours, optimal", params)
    seg = a.segments
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    true = consecutive_true_pairs(truth, seg.t0)
    succ, pred = {i for i, _ in true}, {j for _, j in true}
    pi, pj = a.pairs.i, a.pairs.j
    key = {(int(x), int(y)): k for k, (x, y) in enumerate(zip(pi, pj, strict=True))}
    ch = a.chosen
    out = {(int(pi[k]), int(pj[k])): int(k) for k in ch}
    used_i = {i for i, _ in out}
    used_j = {j for _, j in out}
    n = seg.n
    step = np.fmax(seg.step1, 0)

    def pair_row(i: int, j: int, k) -> dict:
        """The columns a true pair and a wrong join share (k: the pair's row, or None)."""
        gap = seg.t0[j] - seg.t1[i]
        return dict(
            i=i,
            j=j,
            gap=gap,
            steps=gap / step[i] if step[i] > 0 else np.nan,
            ni=int(n[i]),
            nj=int(n[j]),
            cost=float(a.cost[k]) if k is not None else np.nan,
            miss=float(a.pairs.miss_m[k]) if k is not None else np.nan,
        )

    pi0, pj0 = a.base_pairs.i, a.base_pairs.j
    first = {(int(x), int(y)) for x, y in zip(pi0, pj0, strict=True)}
    counted_all = counted_gap(a.pairs)
    price_all = _gap_price(a.pairs, params)
    total = np.asarray(a.cost, dtype=float) + price_all
    claim_i = {i: float(total[k]) for (i, _j), k in out.items()}
    claim_j = {j: float(total[k]) for (_i, j), k in out.items()}
    moving = _both_moving(a.segments, a.pairs, params)

    def loose_row(i: int, j: int, k: int) -> dict:
        """What decides a loose true pair: its cost, gap price and counted gap, the best
        rival of either piece (not claimed more cheaply by a chosen pair), and the first
        test that would drop it."""
        c = float(total[k])
        ri = [
            q
            for q in np.flatnonzero(pi == i)
            if q != k and claim_j.get(int(pj[q]), np.inf) >= total[q]
        ]
        rj = [
            q
            for q in np.flatnonzero(pj == j)
            if q != k and claim_i.get(int(pi[q]), np.inf) >= total[q]
        ]
        best_i = min((float(total[q]) for q in ri), default=np.inf)
        best_j = min((float(total[q]) for q in rj), default=np.inf)
        rival = min(best_i, best_j)

        # the cheapest rival: which ship (s: the pair's own, o: another), its gap, fixes
        def who(q, side):
            o = int(pj[q]) if side == "i" else int(pi[q])
            return (
                f"{side}:{'s' if truth[o] == truth[i] else 'o'}"
                f"{(seg.t0[o] - seg.t1[i]) if side == 'i' else (seg.t0[j] - seg.t1[o]):+.0f}s"
                f"/{int(n[o])}f"
            )

        qs = [(float(total[q]), q, "i") for q in ri] + [(float(total[q]), q, "j") for q in rj]
        best_who = who(min(qs)[1], min(qs)[2]) if qs else "-"
        long = counted_all[k] > params.max_gap_s
        lim = min(params.gate, params.no_join)
        lm = params.long_margin_moving if moving[k] else params.long_margin
        m = lm if long else params.margin  # as core/associate.py's long_margin_moving
        if (i, j) not in first:
            why = "2nd look only"
        elif c > lim:
            why = "gap price" if a.cost[k] <= lim else "over no_join"
        elif rival < c:
            why = "rival cheaper"
        elif rival < c + m:
            why = "within margin"
        else:
            why = "other"
        return dict(
            counted=float(counted_all[k]),
            price=float(price_all[k]),
            total=c,
            rival_i=best_i,
            rival_j=best_j,
            first=(i, j) in first,
            lm=lm,
            decide=why,
            best_who=best_who,
        )

    trues = []
    for i, j in sorted(true):
        gap = seg.t0[j] - seg.t1[i]
        k = key.get((i, j))
        if (i, j) in out:
            why = "joined"
        elif k is None:
            why = "beyond" if gap > params.soft_gap_s else "unreach"
        elif i in used_i or j in used_j:
            why = "taken"
        else:
            why = "loose"
        row = dict(**pair_row(i, j, k), why=why)
        if why == "loose" and loose:
            row.update(loose_row(i, j, k))
        trues.append(row)
    wrongs = []
    counted = counted_gap(a.pairs)
    for (i, j), k in out.items():
        if (i, j) in true:
            continue
        band = (
            "first"
            if counted[k] <= params.max_gap_s
            else ("soft" if counted[k] <= max(params.soft_gap_s, params.max_gap_s) else "long")
        )
        kind = "skip" if truth[i] == truth[j] else ("swap" if i in succ and j in pred else "loose")
        wrongs.append(
            dict(
                **pair_row(i, j, k),
                dist=float(a.pairs.dist_m[k]),
                band=band,
                kind=kind,
                moving=bool(a.segments.motion1[i] and a.segments.motion0[j]),
            )
        )
    return trues, wrongs


#: Counterfactuals of ``--loose``: each term of the decision taken away alone (LinkParams
#: changes); a loose true pair that one of them joins was decided by that term.
COUNTERFACTUALS = {
    "price": dict(gap_price=0.0),
    "margin": dict(margin=0.0),
    "nojoin": dict(no_join=5.0, gate=5.0),
    "long_m": dict(long_margin=0.0, long_margin_moving=0.0),
}


def joined_under(pts, params: LinkParams, gaps, seed: int = 0) -> dict:
    """Per counterfactual: the set of true pairs (i, j) joined with that change."""
    out = {}
    for name, change in COUNTERFACTUALS.items():
        rows, _w = scene_rows(pts, params.replace(**change), gaps, seed, loose=False)
        out[name] = {(r["i"], r["j"]) for r in rows if r["why"] == "joined"}
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--set", default="mtad-tune", help="mtad-tune or mtad-held")
    ap.add_argument("--rate", type=float, default=180.0)
    ap.add_argument("--set-param", action="append", default=[], help="LinkParams NAME=VALUE")
    ap.add_argument("--list", action="store_true", help="print every wrong join and miss")
    ap.add_argument(
        "--loose",
        action="store_true",
        help="per loose true pair: counted gap, cost + gap price, best rivals, the deciding test",
    )
    a = ap.parse_args(argv)
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set_param))
    scenes, (gaps, _every) = ar.scenes_of(a.set)
    trues, wrongs = [], []
    for s, (pts, _sep) in enumerate(scenes):
        cut = sw.decimate(pts, a.rate)
        t, w = scene_rows(cut, params, gaps)
        if a.loose:
            cf = joined_under(cut, params, gaps)
            for r in t:
                if r["why"] == "loose":
                    r["cf"] = "".join(
                        name[0].upper() if (r["i"], r["j"]) in got else "."
                        for name, got in cf.items()
                    )
        trues += [dict(r, scene=s) for r in t]
        wrongs += [dict(r, scene=s) for r in w]
    print(f"{a.set} at {a.rate:g} s: {len(trues)} true pairs, {len(wrongs)} wrong joins")
    print("true pairs by outcome:", dict(Counter(r["why"] for r in trues)))
    print("misses by outcome x smaller piece fixes:")
    for why in ("beyond", "unreach", "taken", "loose"):
        c = Counter(_fixes(min(r["ni"], r["nj"])) for r in trues if r["why"] == why)
        print(f"  {why:<8}", dict(sorted(c.items())))
    print("true pairs by gap band (joined / all):")
    for lo, hi in ((0, 720), (720, 1200), (1200, 3600), (3600, np.inf)):
        rs = [r for r in trues if lo < r["gap"] <= hi]
        print(f"  {lo:>5}-{hi:<5} {sum(r['why'] == 'joined' for r in rs):4d} / {len(rs):4d}")
    print("wrong joins by band x kind:", dict(Counter((r["band"], r["kind"]) for r in wrongs)))
    print(
        "wrong joins by smaller piece fixes:",
        dict(sorted(Counter(_fixes(min(r["ni"], r["nj"])) for r in wrongs).items())),
    )
    print("wrong joins, gap < 1 step of the old end:", sum(r["steps"] < 1.0 for r in wrongs))
    if a.loose:
        rs = [r for r in trues if r["why"] == "loose"]
        print("\nloose true pairs by their cheapest rival:", dict(Counter(r["decide"] for r in rs)))
        print(
            "joined with one term taken away (P gap_price 0, M margin 0, N no_join = gate = 5,"
            " L long margins 0):",
            {n: sum(r["cf"][q] != "." for r in rs) for q, n in enumerate(COUNTERFACTUALS)},
        )
        print(
            "  sc  gap s counted steps  n_i->n_j first  cost price total rival_i rival_j  "
            "by             PMNL  cheapest rival (side:ship gap/fixes)"
        )
        for r in sorted(rs, key=lambda r: (r["decide"], r["scene"], r["gap"])):
            print(
                f"  {r['scene']:2d} {r['gap']:6.0f} {r['counted']:7.0f} {r['steps']:5.1f}"
                f" {r['ni']:4d}->{r['nj']:<4d} {'y' if r['first'] else 'n':>4}"
                f" {r['cost']:5.2f} {r['price']:5.2f} {r['total']:5.2f}"
                f" {r['rival_i']:7.2f} {r['rival_j']:7.2f}  {r['decide']:<14} {r['cf']}  {r['best_who']}"
            )
    if a.list:
        print("\nwrong joins:")
        for r in sorted(wrongs, key=lambda r: (r["band"], r["scene"])):
            print(
                f"  sc{r['scene']} {r['band']:<5} {r['kind']:<5} gap {r['gap']:6.0f} s "
                f"({r['steps']:4.1f} steps) n {r['ni']:3d}->{r['nj']:<3d} cost {r['cost']:.2f} "
                f"miss {r['miss']:6.0f} m dist {r['dist']:6.0f} m moving {r['moving']}"
            )
        print("\nmisses:")
        for r in sorted(trues, key=lambda r: (r["why"], r["scene"])):
            if r["why"] != "joined":
                print(
                    f"  sc{r['scene']} {r['why']:<7} gap {r['gap']:6.0f} s ({r['steps']:4.1f} steps)"
                    f" n {r['ni']:3d}->{r['nj']:<3d} cost {r['cost']:.2f} miss {r['miss']:6.0f} m"
                )


if __name__ == "__main__":
    main()

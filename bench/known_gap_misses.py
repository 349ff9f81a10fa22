"""Where the misses and the wrong joins of MTAD cut at known gaps come from (issue 15).

Each track of mtad-dtwcm/original loses one window of 300-900 s (``cut_known_gaps``, as
``wakeline evaluate associate --real ... --truth-sep - --gaps 300 900 --seed S``) and the
defaults join the pieces. Every true pair is then put in one class: joined (by the
first pass, or beyond T_gap by the second look), or missed — not a candidate of the
first pass (and why not: a piece of fewer than three fixes, a slow piece, a piece with a
cheap candidate within T_gap, priced beyond the gate, or a gap beyond the soft T_gap),
not chosen by the assignment (a piece taken by a wrong join, or both loose), dropped by
the margin test or by the soft-gap test. Every wrong join is classed by where it was made
(within T_gap, across the soft T_gap, by the second look) and by whether one of its
pieces has its true partner beyond T_gap (the assignment could not see it there).

The classes come from the last assignment of the first pass (after the chain pass),
recorded by wrapping ``margin_test`` and ``soft_gap_test`` while it runs.

    python bench/known_gap_misses.py [--seeds 0 2 4] [--half "tuning half"] [--set k=v ...]
"""

import argparse
import os
from collections import Counter
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import numpy as np

from wakeline.core import associate as A
from wakeline.core.evaluate_association import (
    MTAD_SPLIT,
    _truth,
    consecutive_true_pairs,
    cut_known_gaps,
)
from wakeline.core.io import read_points

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
MTAD = SHARED / "data" / "real" / "mtad-dtwcm" / "original"


@contextmanager
def recorded(log: dict):
    """``margin_test`` and ``soft_gap_test`` of ``wakeline.core.associate`` wrapped so that
    their last call's input and output are kept in ``log``; restored afterwards."""
    margin, soft = A.margin_test, A.soft_gap_test

    def margin_rec(seg, pairs, cost, chosen, m, displaced=None):
        out = margin(seg, pairs, cost, chosen, m, displaced)
        log["margin"] = (pairs, chosen, out)
        return out

    def soft_rec(pairs, cost, chosen, params, n):
        out = soft(pairs, cost, chosen, params, n)
        log["soft"] = out
        return out

    A.margin_test, A.soft_gap_test = margin_rec, soft_rec
    try:
        yield log
    finally:
        A.margin_test, A.soft_gap_test = margin, soft


def why_not_first(base, params: A.LinkParams, i: int, j: int, cheap_end, cheap_start) -> str:
    """Why the true pair (i, j) beyond T_gap is no candidate of the first pass."""
    gap = base.t0[j] - base.t1[i]
    if gap > A._soft_gap(params):
        return "gap beyond soft_gap_s"
    slow = params.rest_kn * A.geo.KN_MS
    why = []
    for n, v, side in (
        (base.n[i], np.hypot(base.vx1[i], base.vy1[i]), "old"),
        (base.n[j], np.hypot(base.vx0[j], base.vy0[j]), "new"),
    ):
        if n < A.SOFT_FIXES:
            why.append(f"{side} piece < {A.SOFT_FIXES} fixes")
        elif v <= slow:
            why.append(f"{side} piece slow")
    if cheap_end[i] or cheap_start[j]:
        why.append("a candidate within T_gap cheaper than long_margin")
    return " + ".join(why) or "priced beyond the gate, or reach"


def classify(df, params: A.LinkParams, seed: int) -> tuple[Counter, Counter]:
    """Counts of the true pairs' classes and of the wrong joins' classes for one scene."""
    log: dict = {}
    with recorded(log):
        a = A.associate_interrupted(cut_known_gaps(df, 300, 900, seed=seed), params)
    base = a.base
    pairs, chosen_in, after_margin = log["margin"]
    after_soft = log["soft"]
    truth = base.column("truth").astype(str).to_numpy()[base.index.starts]
    true = consecutive_true_pairs(truth, base.t0)
    key = {
        (i, j): k for k, (i, j) in enumerate(zip(pairs.i.tolist(), pairs.j.tolist(), strict=True))
    }
    final = set(zip(a.pairs.i[a.chosen].tolist(), a.pairs.j[a.chosen].tolist(), strict=True))
    # Pieces with a candidate within T_gap cheaper than long_margin (not "open").
    n = len(base)
    inner = A.candidate_pairs(base, params)
    c_inner = A._pricing(inner, params, "scaled", base).total(inner, params, n)
    best_end, best_start = np.full(n, np.inf), np.full(n, np.inf)
    np.minimum.at(best_end, inner.i, c_inner)
    np.minimum.at(best_start, inner.j, c_inner)
    cheap_end, cheap_start = best_end < params.long_margin, best_start < params.long_margin
    taken_i = {int(pairs.i[k]): int(pairs.j[k]) for k in chosen_in}
    taken_j = {int(pairs.j[k]): int(pairs.i[k]) for k in chosen_in}
    in_set, in_margin, in_soft = (
        set(chosen_in.tolist()),
        set(after_margin.tolist()),
        set(after_soft.tolist()),
    )
    pairs_out = Counter()
    for i, j in true:
        gap = base.t0[j] - base.t1[i]
        where = (
            "within T_gap"
            if gap <= params.max_gap_s
            else ("T_gap to soft_gap_s" if gap <= A._soft_gap(params) else "beyond soft_gap_s")
        )
        k = key.get((i, j))
        if (i, j) in final:
            how = "joined" if k is not None and k in in_soft else "joined by the second look"
        elif k is None:
            how = "missed: not in the first pass: " + why_not_first(
                base, params, i, j, cheap_end, cheap_start
            )
        elif k not in in_set:
            wrong = (i in taken_i and taken_i[i] != j) or (j in taken_j and taken_j[j] != i)
            how = "missed: not assigned: " + (
                "a piece taken by a wrong join" if wrong else "both loose"
            )
        elif k not in in_margin:
            how = "missed: dropped by the margin test"
        elif k not in in_soft:
            how = "missed: dropped by the soft-gap test"
        else:
            how = "missed: lost in the second look (long_rivals)"
        pairs_out[(where, how)] += 1
    succ = {i: j for i, j in true}
    pred = {j: i for i, j in true}
    first = set(zip(a.base_pairs.i.tolist(), a.base_pairs.j.tolist(), strict=True))
    wrong_out = Counter()
    for i, j in final - set(true):
        gap = base.t0[j] - base.t1[i]
        made = (
            "within T_gap"
            if gap <= params.max_gap_s
            else ("across the soft T_gap" if (i, j) in first else "by the second look")
        )
        long_partner = (i in succ and base.t0[succ[i]] - base.t1[i] > params.max_gap_s) or (
            j in pred and base.t0[j] - base.t1[pred[j]] > params.max_gap_s
        )
        short = min(base.n[i], base.n[j]) < A.SOFT_FIXES
        wrong_out[
            (
                made,
                "a piece's true partner beyond T_gap" if long_partner else "partners within T_gap",
                "a piece of < 3 fixes" if short else "pieces of >= 3 fixes",
            )
        ] += 1
    return pairs_out, wrong_out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 2, 4])
    ap.add_argument("--half", default="tuning half", choices=[*MTAD_SPLIT, "all"])
    ap.add_argument("--data", type=Path, default=MTAD)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    args = ap.parse_args()
    params = A.LinkParams()
    for kv in args.set:
        name, value = kv.split("=", 1)
        old = getattr(params, name)
        params = replace(
            params, **{name: value.lower() == "true" if isinstance(old, bool) else type(old)(value)}
        )
    names = (
        [n for half in MTAD_SPLIT.values() for n in half]
        if args.half == "all"
        else MTAD_SPLIT[args.half]
    )
    frames = {}
    for name in names:
        df = read_points(args.data / name).points
        df["truth"] = _truth(df.assign(batch=df["batch"].astype(str).str.split("-").str[0]))
        frames[name] = df
    pairs_total, wrong_total = Counter(), Counter()
    for seed in args.seeds:
        for df in frames.values():
            p, w = classify(df, params, seed)
            pairs_total.update(p)
            wrong_total.update(w)
    n_true = sum(pairs_total.values())
    print(f"MTAD {args.half}, known gaps 300-900 s, seeds {args.seeds}: {n_true} true pairs")
    for (where, how), c in sorted(pairs_total.items()):
        print(f"  {where:<20} {how:<95} {c:4d}")
    print(f"wrong joins: {sum(wrong_total.values())}")
    for (made, partner, short), c in sorted(wrong_total.items()):
        print(f"  {made:<22} {partner:<36} {short:<22} {c:4d}")


if __name__ == "__main__":
    main()

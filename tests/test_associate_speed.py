"""Association speed (issue 17) without changing its result: the grid's narrower time
windows and the second look's reuse of the first look's searches."""

import numpy as np
import pytest

from wakeline.core import associate as assoc_mod
from wakeline.core import simulate
from wakeline.core.associate import LinkParams, associate_interrupted, candidate_pairs
from wakeline.core.segments import segment_stats


@pytest.fixture(scope="module")
def rerun_scene():
    """150 ships in 27 km (the bench's density): a scene where released joins come back
    and the second look runs again (long_gap_pass)."""
    area = 20.0 * np.sqrt(150 / 80.0)
    return simulate.segments_scene(seed=4, n_ships=150, area_km=area, period_s=60.0)


def _same_pairs(a, b):
    for f in a.__dataclass_fields__:
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)


def test_narrowed_search_equals_a_new_search(rerun_scene):
    # Fewer ends and starts, more ends, more starts, more of both: always the pairs,
    # features and order of a new candidate_pairs search.
    seg = segment_stats(rerun_scene)
    params = LinkParams().replace(max_gap_s=3600.0)
    n = len(seg)
    rng = np.random.default_rng(5)
    e0, s0 = rng.random(n) < 0.6, rng.random(n) < 0.6
    first, before = assoc_mod._narrowed(seg, params, e0, s0, None)
    _same_pairs(first, candidate_pairs(seg, params, e0, s0))
    fewer_e, fewer_s = e0 & (rng.random(n) < 0.7), s0 & (rng.random(n) < 0.7)
    more_e, more_s = fewer_e | (rng.random(n) < 0.1), fewer_s | (rng.random(n) < 0.1)
    for e, s in [
        (fewer_e, fewer_s),
        (more_e, fewer_s),
        (fewer_e, more_s),
        (more_e, more_s),
        (None, fewer_s),
        (fewer_e, None),
    ]:
        got, _ = assoc_mod._narrowed(seg, params, e, s, before)
        _same_pairs(got, candidate_pairs(seg, params, e, s))
        assert len(got) > 0


#: The scene's released joins come back and the second look runs again with the end fits
#: of 10 fixes it was chosen with (its 60 s tracks take 9 under end_span_s).
#: ``rivals_reach`` 2: long_rivals' own searches (up to twice T_gap) are told apart from
#: the second look's (up to long_gap_s, which long_rivals also reaches since session 27).
REPLAY = LinkParams().replace(end_span_s=0.0, rivals_reach=2.0)


def test_second_look_reuses_the_first_looks_searches(rerun_scene, monkeypatch):
    # The second look has fewer loose pieces than the first: its three searches are the
    # first's, filtered (no new grid search), the candidates of the same searches keep
    # their prices (one pricing fewer), and the association is the same as with every
    # search made and priced anew.
    searches = []
    search = assoc_mod.candidate_pairs
    priced = []
    pricing = assoc_mod._pricing

    def counted(*args, **kwargs):
        min_gap = args[4] if len(args) > 4 else kwargs.get("min_gap_s", 0.0)
        searches.append((args[1].max_gap_s, min_gap))
        return search(*args, **kwargs)

    def counted_pricing(*args, **kwargs):
        priced.append(len(args[0]))
        return pricing(*args, **kwargs)

    monkeypatch.setattr(assoc_mod, "candidate_pairs", counted)
    monkeypatch.setattr(assoc_mod, "_pricing", counted_pricing)
    a = associate_interrupted(rerun_scene, REPLAY)
    look = (REPLAY.long_gap_s, 0.0)  # the second look's searches
    assert searches.count(look) == 3  # one look's
    reused = len(priced)

    monkeypatch.setattr(
        assoc_mod, "_narrowed", lambda s, p, e, st, before, **_: _fresh(s, p, e, st)
    )
    searches.clear()
    priced.clear()
    b = associate_interrupted(rerun_scene, REPLAY)
    assert searches.count(look) == 2 * 3  # the second look searched again
    assert len(priced) == reused + 1  # and priced its candidates again
    _same_pairs(a.pairs, b.pairs)
    np.testing.assert_array_equal(a.cost, b.cost)
    np.testing.assert_array_equal(a.chosen, b.chosen)


def _fresh(seg, params, ends, starts):
    found = assoc_mod.candidate_pairs(seg, params, ends, starts)
    return found, None


def test_grid_looks_at_few_pairs_beyond_those_it_finds(rerun_scene, monkeypatch):
    # A start in a neighbouring cube is looked at only from the time it could be reached:
    # the grid tests 2.9× the pairs it keeps here (5.9× with the whole time window in all
    # 27 cubes), and the association is the k-d tree's.
    looked = []
    ranges = assoc_mod.concat_ranges

    def counted(lo, cnt):
        looked.append(int(np.sum(cnt)))
        return ranges(lo, cnt)

    monkeypatch.setattr(assoc_mod, "concat_ranges", counted)
    seg = segment_stats(rerun_scene)
    params = LinkParams()
    found = assoc_mod._grid_pairs(seg, params)
    assert 0 < sum(looked) < 4 * len(found[0])
    a = associate_interrupted(rerun_scene, params)
    monkeypatch.setattr(assoc_mod, "_grid_pairs", lambda *args: None)
    b = associate_interrupted(rerun_scene, params)
    _same_pairs(a.pairs, b.pairs)
    np.testing.assert_array_equal(a.cost, b.cost)
    np.testing.assert_array_equal(a.chosen, b.chosen)


def test_per_track_summaries_are_computed_once(rerun_scene, monkeypatch):
    # Speeds, courses and Earth-centred positions are asked for in every candidate search
    # and pricing: computed once per summary (the same values), and one great-circle
    # distance per pair found in a search.
    from wakeline.core import geo
    from wakeline.core.segments import ecef

    seg = segment_stats(rerun_scene)
    assert seg.speed0_kn is seg.speed0_kn and seg.course1_deg is seg.course1_deg
    np.testing.assert_array_equal(seg.speed1_kn, np.hypot(seg.vx1, seg.vy1) / geo.KN_MS)
    np.testing.assert_array_equal(seg.ecef0, ecef(seg.lon0, seg.lat0))
    np.testing.assert_array_equal(seg.ecef1, ecef(seg.lon1, seg.lat1))
    calls = []
    haversine = geo.haversine_m

    def counted(*args):
        calls.append(len(args[0]))
        return haversine(*args)

    monkeypatch.setattr(geo, "haversine_m", counted)
    found = candidate_pairs(seg, LinkParams())
    assert len(calls) == 1 and len(found) > 0
    monkeypatch.undo()
    again = assoc_mod.pair_features(seg, found.i, found.j)
    _same_pairs(found, again)


def test_margin_test_by_index_equals_the_join(rerun_scene):
    # The one-to-one margin test (arrays indexed by end) keeps exactly the pairs the
    # join of every chosen pair with its end's candidates keeps, on random costs and
    # random one-to-one choices, margins from 0.01 to 1.
    seg = segment_stats(rerun_scene)
    params = LinkParams()
    pairs = candidate_pairs(seg, params)
    rng = np.random.default_rng(11)
    n = len(seg)
    for trial in range(6):
        cost = rng.random(len(pairs)) * 2
        if trial % 2:
            cost[rng.random(len(pairs)) < 0.05] = np.inf
        order = rng.permutation(len(pairs))
        used_i, used_j, chosen = np.zeros(n, bool), np.zeros(n, bool), []
        for p in order[: len(pairs) // 2]:  # a greedy one-to-one choice
            i, j = pairs.i[p], pairs.j[p]
            if not used_i[i] and not used_j[j]:
                used_i[i] = used_j[j] = True
                chosen.append(p)
        chosen = np.sort(np.array(chosen))
        margin = [0.01, 0.1, 0.3, 1.0, 0.2, 0.05][trial]
        claim_i, claim_j = np.full(n, np.inf), np.full(n, np.inf)
        claim_j[pairs.j[chosen]] = cost[chosen]
        claim_i[pairs.i[chosen]] = cost[chosen]
        fast = assoc_mod.margin_test(seg, pairs, cost, chosen, margin)
        joined = assoc_mod._margin_test_joined(seg, pairs, cost, chosen, margin, claim_i, claim_j)
        np.testing.assert_array_equal(fast, joined)
        assert 0 < len(fast) < len(chosen)


def _two_cheapest_by_sort(owner, cost, n):
    """The lexsort formulation of _two_cheapest (before issue 17's session 18)."""
    order = np.lexsort((cost, owner))
    o = owner[order]
    first = np.flatnonzero(np.r_[True, o[1:] != o[:-1]]) if len(o) else np.zeros(0, "int64")
    best = np.full(n, -1, dtype="int64")
    best[o[first]] = order[first]
    second = np.full(n, np.inf)
    nxt = first + 1
    has = nxt < len(o)
    has[has] = o[nxt[has]] == o[first[has]]
    second[o[first[has]]] = cost[order[nxt[has]]]
    return best, second


def test_two_cheapest_without_a_sort_equals_the_sort():
    # Ties (the first index wins), infinite costs, owners with one pair or none, NaN.
    rng = np.random.default_rng(3)
    n = 300
    for trial in range(8):
        m = [0, 1, 50, 2000][trial % 4]
        owner = rng.integers(0, n, m)
        cost = np.round(rng.random(m) * 3, 1)  # many ties
        cost[rng.random(m) < 0.1] = np.inf
        if trial >= 4 and m:
            cost[rng.integers(0, m)] = np.nan
        got = assoc_mod._two_cheapest(owner, cost, n)
        want = _two_cheapest_by_sort(owner, cost, n)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])


def _soft_gap_test_all_pairs(pairs, cost, chosen, params, n):
    """soft_gap_test with the rivals of every pair scattered (before issue 17's session 18)."""
    long = pairs.gap_s[chosen] > params.max_gap_s
    if not long.any():
        return chosen
    claim_end = np.full(n, np.inf)
    claim_start = np.full(n, np.inf)
    claim_end[pairs.i[chosen]] = cost[chosen]
    claim_start[pairs.j[chosen]] = cost[chosen]
    mine = np.zeros(len(pairs), dtype=bool)
    mine[chosen] = True
    rival_i = np.where(mine | (claim_start[pairs.j] < cost), np.inf, cost)
    rival_j = np.where(mine | (claim_end[pairs.i] < cost), np.inf, cost)
    best_i = np.full(n, np.inf)
    best_j = np.full(n, np.inf)
    np.minimum.at(best_i, pairs.i, rival_i)
    np.minimum.at(best_j, pairs.j, rival_j)
    c = cost[chosen] + params.long_margin
    close = (best_i[pairs.i[chosen]] < c) | (best_j[pairs.j[chosen]] < c)
    return chosen[~(long & close)]


def test_soft_gap_test_on_the_long_joins_pieces_equals_all_pairs():
    # One-to-one joins, some beyond max_gap_s; ties, inf and NaN costs; rivals claimed
    # more cheaply elsewhere or not.
    rng = np.random.default_rng(5)
    params = LinkParams()
    n, dropped, kept = 400, 0, 0
    for trial in range(12):
        m = [0, 30, 600, 3000][trial % 4]
        i, j = rng.integers(0, n, m), rng.integers(0, n, m)
        gap = rng.uniform(0.0, 2.0 * params.max_gap_s, m)
        cost = np.round(rng.random(m) * 2, 1)
        cost[rng.random(m) < 0.05] = np.inf
        if trial >= 6 and m:
            cost[rng.integers(0, m, 3)] = np.nan
        z = np.zeros(m)
        pairs = assoc_mod.Pairs(i, j, gap, z, z, z, z)
        # One-to-one: the first pair of each end among the first of each start.
        first_i = np.unique(i, return_index=True)[1]
        cand = np.sort(first_i)
        chosen = cand[np.unique(j[cand], return_index=True)[1]]
        chosen = np.sort(rng.permutation(chosen)[: len(chosen) // 2])
        with np.errstate(invalid="ignore"):  # NaN in np.minimum, either way
            got = assoc_mod.soft_gap_test(pairs, cost, chosen, params, n)
            want = _soft_gap_test_all_pairs(pairs, cost, chosen, params, n)
        np.testing.assert_array_equal(got, want)
        dropped += len(chosen) - len(want)
        kept += int((gap[want] > params.max_gap_s).sum())
    assert dropped > 0 and kept > 0  # both outcomes tested


def test_soft_gap_test_scatters_only_the_long_joins_pieces_pairs(monkeypatch):
    # 2,000 joins, one beyond max_gap_s: its two pieces' few pairs are scattered, not all.
    params = LinkParams()
    n = 4000
    i = np.r_[np.arange(2000), np.arange(2000)]
    j = np.r_[np.arange(2000) + 2000, (np.arange(2000) + 1) % 2000 + 2000]
    gap = np.full(4000, 60.0)
    gap[0] = 1.5 * params.max_gap_s
    z = np.zeros(4000)
    pairs = assoc_mod.Pairs(i, j, gap, z, z, z, z)
    cost = np.r_[np.full(2000, 0.5), np.full(2000, 1.4)]
    scattered = []

    class _Minimum:
        def at(self, out, idx, values):
            scattered.append(len(idx))
            np.minimum.at(out, idx, values)

    class _Np:
        minimum = _Minimum()

        def __getattr__(self, name):
            return getattr(np, name)

    monkeypatch.setattr(assoc_mod, "np", _Np())
    got = assoc_mod.soft_gap_test(pairs, cost, np.arange(2000), params, n)
    monkeypatch.undo()
    np.testing.assert_array_equal(got, np.arange(2000))  # rivals claimed more cheaply
    assert sum(scattered) <= 4, scattered  # end 0's two pairs, start 2000's two


def test_order_by_rank_equals_lexsort():
    # Ties in time (index order), NaN times (last), a subset's places in the whole
    # ranking, and keys too wide for one integer (the lexsort fallback).
    from wakeline.core.segments import order_by, time_rank

    rng = np.random.default_rng(8)
    for major_hi in (5, 2**40, 2**62):
        t = np.round(rng.random(5000) * 100, 0)
        t[rng.random(5000) < 0.02] = np.nan
        major = rng.integers(0, major_hi, 5000)
        major[:100] = major[100]  # a big group
        rank = time_rank(t)
        np.testing.assert_array_equal(order_by(major, rank), np.lexsort((t, major)))
        sub = np.flatnonzero(rng.random(5000) < 0.3)
        np.testing.assert_array_equal(
            order_by(major[sub], rank[sub]), np.lexsort((t[sub], major[sub]))
        )


def test_association_sorts_no_pairs_or_tracks_by_lexsort(rerun_scene, monkeypatch):
    # The grid's (cube, time) orders, the targets' leaders, the chain refit's order and
    # the second look's two cheapest are one integer sort or scatter-minima, not
    # lexsort (n log n with indirect merges: 13 ms per call at 100 k tracks against 1 ms);
    # the association is the same as with lexsort and the sorted two cheapest.
    import sys

    calls = []
    lexsort = np.lexsort

    def counted(keys, *args, **kwargs):
        caller = sys._getframe(1).f_globals.get("__name__", "")
        if caller.startswith("wakeline.core.associate") or caller.startswith(
            "wakeline.core.segments"
        ):
            calls.append(caller)
        return lexsort(keys, *args, **kwargs)

    from wakeline.core import segments as seg_mod

    def by_lexsort(major, rank):
        return lexsort((rank, major))

    with monkeypatch.context() as m:  # the same orders by lexsort
        m.setattr(assoc_mod, "order_by", by_lexsort)
        m.setattr(seg_mod, "order_by", by_lexsort)
        m.setattr(assoc_mod, "_two_cheapest", _two_cheapest_by_sort)
        a = associate_interrupted(rerun_scene, LinkParams())
    monkeypatch.setattr(np, "lexsort", counted)
    b = associate_interrupted(rerun_scene, LinkParams())
    assert calls == []
    _same_pairs(a.pairs, b.pairs)
    np.testing.assert_array_equal(a.chosen, b.chosen)
    np.testing.assert_array_equal(a.target_of_track, b.target_of_track)


def test_pricing_weighted_mean_by_columns_is_the_stacks_bits():
    # _pricing's weighted mean by columns (a + b + c + 0.0) instead of an m × 3 stack's
    # row sums: the same bits, with signed zeros, unknown (NaN) and infinite terms, huge
    # terms that overflow, and weights of 0.
    rng = np.random.default_rng(2)
    m = 200_000
    terms = []
    for _ in range(3):
        c = np.abs(rng.standard_normal(m)) * 10.0 ** rng.integers(-8, 300, m)
        c[rng.random(m) < 0.2] = -0.0
        c[rng.random(m) < 0.2] = 0.0
        c[rng.random(m) < 0.1] = np.nan
        c[rng.random(m) < 0.05] = np.inf
        terms.append(c)
    for weights in [(0.5, 0.25, 0.25), (1.0, 0.0, 0.0), (0.3, 0.7, 0.0), (0.0, 0.0, 1.0)]:
        t = np.column_stack(terms)
        w = np.array(weights) * np.isfinite(t)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            cost = (w * np.nan_to_num(t)).sum(axis=1) / w.sum(axis=1)
            share = np.nan_to_num(w[:, 0] / w.sum(axis=1))
        cost = np.where(w.sum(axis=1) > 0, cost, np.inf)
        got_cost, got_share = assoc_mod._weighted_mean(tuple(terms), weights)
        np.testing.assert_array_equal(got_cost.view(np.int64), cost.view(np.int64))
        np.testing.assert_array_equal(got_share.view(np.int64), share.view(np.int64))


def test_references_by_inf_equal_those_of_the_pairs_used():
    # The tightest ln σ per end and start, the pairs not used set to inf instead of
    # gathered out: the same bits (NaN and infinite σ, signed zeros, blind pairs).
    rng = np.random.default_rng(4)
    n, m = 500, 20_000
    pairs = assoc_mod.Pairs(
        np.sort(rng.integers(0, n, m)),
        rng.integers(0, n, m),
        rng.random(m) * 1500,
        *(rng.random(m) for _ in range(4)),
    )
    log_sd = rng.standard_normal(m)
    log_sd[rng.random(m) < 0.05] = np.nan
    log_sd[rng.random(m) < 0.05] = np.inf
    log_sd[rng.random(m) < 0.05] = -0.0
    log_sd[rng.random(m) < 0.05] = 0.0
    priced = assoc_mod._Priced(rng.random(m) * 3, rng.random(m), log_sd, rng.random(m) < 0.1)
    params = LinkParams()
    got = assoc_mod._references(pairs, priced, params, n)
    ok = (priced.cost <= min(params.gate, params.no_join)) & ~priced.blind & np.isfinite(log_sd)
    for (ti, tj), use in zip(got, (ok & (pairs.gap_s <= params.max_gap_s), ok), strict=True):
        want_i, want_j = np.full(n, np.inf), np.full(n, np.inf)
        np.minimum.at(want_i, pairs.i[use], log_sd[use])
        np.minimum.at(want_j, pairs.j[use], log_sd[use])
        np.testing.assert_array_equal(ti.view(np.int64), want_i.view(np.int64))
        np.testing.assert_array_equal(tj.view(np.int64), want_j.view(np.int64))


def test_bench_stages_reports_every_stage_and_restores_the_functions(
    rerun_scene, monkeypatch, capsys
):
    # `python bench/bench_associate.py --stages`: own CPU time per stage at each size,
    # its growth, and the association's functions unwrapped afterwards.
    import sys
    from pathlib import Path

    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[1] / "bench"))
    import bench_associate

    sizes = {1000: rerun_scene, 10_000: rerun_scene}
    monkeypatch.setattr(bench_associate, "scene", lambda n: sizes[n])
    before = {name: getattr(assoc_mod, name) for name in bench_associate.STAGES}
    bench_associate.stages([1000, 10_000], 1)
    out = capsys.readouterr().out
    for name in ("total", "candidate_pairs", "segment_stats", "(the rest)"):
        assert f"\n{name} " in out
    assert "growth per 10x" in out
    assert all(getattr(assoc_mod, name) is fn for name, fn in before.items())
    sys.modules.pop("bench_associate", None)

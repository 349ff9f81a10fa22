"""``slow_change_ms2`` / ``slow_end_kn`` (session 28, candidate C of
docs/prereg/session28_overlay_b.md; failed its guard 2, MTAD's held-out own cuts, so off by
default): the speed tolerance grows with the gap only where one end is slow."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from test_associate import track

from wakeline.core import geo
from wakeline.core.associate import LinkParams, associate_interrupted, candidate_pairs, pair_cost
from wakeline.core.errors import InputError


def _ferry(seed: int, v2_kn: float) -> pd.DataFrame:
    """A ferry at 25 kn heading east, seen every 60 s for 10 min (f1), silent 20-25 min
    while it changes speed evenly to ``v2_kn`` and turns north, then seen at ``v2_kn``
    heading north (f2); GPS jitter 5 m."""
    rng = np.random.default_rng(seed)
    v1, v2 = 25 * geo.KN_MS, v2_kn * geo.KN_MS
    t1 = 60.0 * np.arange(11)
    gap = rng.uniform(1200, 1500)
    x_gap = t1[-1] * v1 + 0.5 * (v1 + v2) * gap
    t2 = t1[-1] + gap + 60.0 * np.arange(10)
    y2 = v2 * (t2 - t2[0])
    return pd.concat(
        [
            track("f1", t1, v1 * t1 + rng.normal(0, 5, 11), rng.normal(0, 5, 11), truth="F"),
            track("f2", t2, x_gap + rng.normal(0, 5, 10), y2 + rng.normal(0, 5, 10), truth="F"),
        ],
        ignore_index=True,
    )


def _joined(df: pd.DataFrame, params: LinkParams | None = None) -> bool:
    pt = associate_interrupted(df, params).pair_table()
    return list(zip(pt["batch_a"], pt["batch_b"], strict=True)) == [("f1", "f2")]


def _cost(df: pd.DataFrame, params: LinkParams | None = None) -> float:
    """The pair f1 → f2's price as the second look sees it (``max_gap_s`` = ``long_gap_s``,
    as bench/overlay_why.py prices)."""
    params = params or LinkParams()
    seg = associate_interrupted(df, params).segments
    wide = replace(params, max_gap_s=params.long_gap_s)
    cand = candidate_pairs(seg, wide)
    batches = seg.column("batch").astype(str).to_numpy()[seg.index.starts]
    k = np.flatnonzero((batches[cand.i] == "f1") & (batches[cand.j] == "f2"))
    assert len(k) == 1
    return float(pair_cost(cand, wide, "scaled", seg)[k[0]])


def test_a_ferry_arriving_at_a_berth_is_joined_where_one_end_is_slow():
    """25 kn before a 20-25 min silence, 3 kn after: 22 kn apart, over four tolerances, left
    loose by default. With 0.01 m/s² allowed where one end is under 5 kn it is joined in
    each of six seeds; with ``slow_end_kn`` 2 the 3 kn end is not slow and it stays loose."""
    assert LinkParams().slow_change_ms2 == 0.0
    on = LinkParams(slow_change_ms2=0.01)
    assert on.slow_end_kn == 5.0
    for s in range(6):
        df = _ferry(s, 3.0)
        assert not _joined(df)
        assert _joined(df, on)
        assert not _joined(df, LinkParams(slow_change_ms2=0.01, slow_end_kn=2.0))
        # leaving the berth: the same ship played backwards in time is joined alike
        back = df.assign(time=df["time"].max() - (df["time"] - df["time"].min()))
        back["batch"] = back["batch"].map({"f1": "f2", "f2": "f1"})
        assert not _joined(back)
        assert _joined(back, on)


def test_moving_ends_keep_their_tolerance_whatever_the_gap():
    """Both ends faster than ``slow_end_kn`` (25 kn, then 12 kn): the pair's price is the
    same bits with the option on, while ``speed_change_ms2`` (every pair) lowers it."""
    for s in range(4):
        df = _ferry(s, 12.0)
        off = _cost(df)
        assert _cost(df, LinkParams(slow_change_ms2=0.01)) == off
        assert _cost(df, LinkParams(slow_change_ms2=0.01, slow_end_kn=13.0)) < off
        assert _cost(df, LinkParams(speed_change_ms2=0.01)) < off


@pytest.mark.parametrize(
    "bad",
    [
        {"slow_change_ms2": -0.01},
        {"slow_change_ms2": 1.5},
        {"slow_end_kn": -1.0},
        {"slow_end_kn": 60.0},
    ],
)
def test_slow_change_is_validated(bad):
    with pytest.raises(InputError):
        LinkParams(**bad).checked()
    p = LinkParams(slow_change_ms2=1.0, slow_end_kn=50.0).checked()
    assert p.slow_change_ms2 == 1.0 and p.slow_end_kn == 50.0

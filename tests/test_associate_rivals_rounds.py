"""``rivals_rounds`` (session 28, adopted by docs/prereg/session28_overlay.md): the release
test of ``long_rivals`` made again with the pieces the first round released counted loose."""

import numpy as np
import pandas as pd
import pytest
from test_associate import track

from wakeline.core.associate import LinkParams, associate_interrupted
from wakeline.core.errors import InputError


def _chained_berths(seed: int) -> pd.DataFrame:
    """Three berths. Ship A lies at P, seen for 7 min (a1), silent 23-27 min, then seen
    again at P (a2). A newcomer B switches its AIS on at Q, 35 m off, 7-8 min after A fell
    silent (b, no piece before). Ship C lies at R, 100 m off P the other way: seen (c1, 30
    min) until 7-8 min before a2 begins, then silent 25-28 min (c2 at R). Within T_gap the
    assignment sees a1 → b and c1 → a2 only (each ~1.1: a move within the rest allowance)
    and takes both; the ships' own continuations lie beyond T_gap. GPS jitter 2 m."""
    rng = np.random.default_rng(seed)
    t_a1 = 60.0 * np.arange(8)
    a2_start = t_a1[-1] + rng.uniform(1400, 1600)
    t_a2 = a2_start + 60.0 * np.arange(30)
    t_b = t_a1[-1] + rng.uniform(420, 480) + 60.0 * np.arange(40)
    c1_end = a2_start - rng.uniform(420, 480)
    t_c1 = c1_end - 60.0 * np.arange(30)[::-1]
    t_c2 = c1_end + rng.uniform(1500, 1700) + 60.0 * np.arange(20)

    def jitter(n: int) -> np.ndarray:
        return rng.normal(0, 2.0, n)

    return pd.concat(
        [
            track("a1", t_a1, jitter(8), jitter(8), truth="A"),
            track("a2", t_a2, jitter(30), jitter(30), truth="A"),
            track("b", t_b, 35 + jitter(40), jitter(40), truth="B"),
            track("c1", t_c1, jitter(30), 100 + jitter(30), truth="C"),
            track("c2", t_c2, jitter(20), 100 + jitter(20), truth="C"),
        ],
        ignore_index=True,
    )


def _pairs(df: pd.DataFrame, params: LinkParams | None = None) -> list:
    pt = associate_interrupted(df, params).pair_table()
    return sorted(zip(pt["batch_a"], pt["batch_b"], strict=True))


def test_a_wrong_join_gives_way_once_its_rivals_own_wrong_join_has():
    """One round (the rule before): c1 → a2 gives way to C's own c2 beyond T_gap, but a1 →
    b was tested while a2 was still taken, so it stays and a2 is left loose (Saronic's days
    overlaid: v4d5 → v4d7 at 33 m while v4d5's own next piece was held by v4d3). Two
    rounds: a2 is loose in the second, a1 → b gives way and the second look joins A and C
    each to itself. Eight seeds."""
    assert LinkParams().rivals_rounds == 2
    one = LinkParams(rivals_rounds=1)
    for s in range(8):
        df = _chained_berths(s)
        assert _pairs(df, one) == [("a1", "b"), ("c1", "c2")]
        assert _pairs(df) == [("a1", "a2"), ("c1", "c2")]
        assert _pairs(df, LinkParams(rivals_rounds=3)) == _pairs(df)
        # without long_rivals the rounds change nothing
        off = LinkParams(long_rivals=False)
        assert _pairs(df, off) == _pairs(df, LinkParams(long_rivals=False, rivals_rounds=1))


@pytest.mark.parametrize("bad", [0, 11, 1.5, -1])
def test_rivals_rounds_is_validated(bad):
    with pytest.raises(InputError):
        LinkParams(rivals_rounds=bad).checked()
    assert LinkParams(rivals_rounds=10).checked().rivals_rounds == 10

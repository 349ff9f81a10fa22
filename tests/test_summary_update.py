"""A review decision updates the layer's summary incrementally (h133 #6): the result
equals a full recompute; the fast per-track labels and first targets equal the slow ones."""

import numpy as np
import pandas as pd

from wakeline.app.models import _first_per_track, batch_summary
from wakeline.core.review import _labels, point_labels
from wakeline.core.sorted_sets import distinct, union
from wakeline.core.tracks import sort_points, summary_update, track_summary


def _points(seed: int = 0, tracks: int = 40) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    sizes = rng.integers(1, 30, tracks)
    n = int(sizes.sum())
    t = np.concatenate([np.sort(rng.uniform(0, 3600, s)) for s in sizes])
    df = pd.DataFrame(
        {
            "sensor": np.repeat(np.where(np.arange(tracks) % 3 == 0, "AIS", "R1"), sizes),
            "batch": np.repeat(np.arange(tracks).astype(str), sizes),
            "time": pd.to_datetime(1.7e9 + t, unit="s", utc=True),
            "lon": 10 + rng.normal(0, 0.05, n).cumsum() / 10,
            "lat": 55 + rng.normal(0, 0.05, n).cumsum() / 10,
        }
    )
    df["target"] = np.repeat(rng.integers(0, tracks // 2, tracks).astype(str), sizes)
    return sort_points(df.sample(frac=1.0, random_state=seed).reset_index(drop=True))


def test_a_relabelling_keeps_every_summary_row_and_equals_a_full_recompute():
    before = _points()
    old = batch_summary(before)
    after = before.copy()
    rng = np.random.default_rng(1)
    after["target"] = rng.integers(0, 5, len(after)).astype(str)  # a decision's relabelling
    full = batch_summary(after)
    quick = batch_summary(after, previous=(before, old))
    pd.testing.assert_frame_equal(quick, full)
    assert not quick["target"].equals(old["target"])


def test_changed_rows_are_summarized_again_and_other_tracks_kept():
    before = _points(2)
    old = track_summary(before)
    after = before.copy()
    after.loc[[3, 50, 51], "lon"] += 0.3  # two or three tracks' positions
    after.loc[[100], "time"] += pd.Timedelta(seconds=1)
    quick = summary_update(after, before, old)
    pd.testing.assert_frame_equal(quick, track_summary(after))
    changed = (quick["length_m"] != old["length_m"]).sum()
    assert 1 <= changed <= 4


def test_other_tracks_or_row_counts_give_none():
    before = _points(3)
    old = track_summary(before)
    assert summary_update(before.iloc[:-1].reset_index(drop=True), before, old) is None
    other = before.copy()
    other.loc[other["batch"] == "0", "batch"] = "new"
    assert summary_update(other, before, old) is None


def test_first_target_per_track_is_the_first_non_null_as_group_by_gives():
    pts = _points(4)
    rng = np.random.default_rng(4)
    pts["target"] = np.where(rng.random(len(pts)) < 0.3, None, rng.integers(0, 9, len(pts)))
    pts.loc[pts["batch"] == "5", "target"] = None  # a track without one
    keys = ["sensor", "batch"]
    summary = track_summary(pts)
    first = pts.astype({"sensor": str, "batch": str}).groupby(keys)["target"].first()
    want = first.reindex(pd.MultiIndex.from_frame(summary[keys])).to_numpy()
    got = _first_per_track(pts, "target")
    assert [None if pd.isna(x) else x for x in got] == [None if pd.isna(x) else x for x in want]


def test_point_labels_equal_the_text_labels():
    pts = _points(5)
    pts.loc[2, "batch"] = np.nan
    want = _labels(pts[["sensor", "batch"]].astype(str))
    assert np.array_equal(point_labels(pts), want)
    num = pd.DataFrame({"sensor": ["A", "A", "B"], "batch": [1.0, np.nan, 1.0]})
    assert np.array_equal(point_labels(num), _labels(num.astype(str)))


def test_sorted_sets_equal_numpy():
    rng = np.random.default_rng(6)
    a, b = rng.integers(0, 1000, 500), rng.integers(-5, 50, 80)
    assert np.array_equal(distinct(a), np.unique(a))
    assert np.array_equal(union(a, b), np.union1d(a, b))
    assert np.array_equal(distinct(a[:0]), np.unique(a[:0]))

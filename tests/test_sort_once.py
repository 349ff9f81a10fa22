"""Sort once: a table sorted or checked by ``sorted_with_index`` is remembered, safely."""

import numpy as np
import pandas as pd

from wakeline.core import tracks
from wakeline.core.tracks import known_order, sort_points, sorted_with_index, track_seconds


def _table(seed: int = 0, n: int = 400) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    return pd.DataFrame(
        {
            "sensor": pd.Series(rng.choice(["R1", "AIS", "Ä2"], n), dtype="str"),
            "batch": pd.Series(rng.choice(["9", "10", "b", "é", "1"], n), dtype="str"),
            "time": pd.Timestamp("2024-05-01", tz="UTC")
            + pd.to_timedelta(rng.integers(0, 50, n), unit="s"),
            "lon": rng.uniform(120, 121, n),
            "lat": rng.uniform(30, 31, n),
        }
    )


def _codes_index(df: pd.DataFrame):
    sensor, batch = tracks._key_codes(df)
    return tracks._index_from_codes(df, sensor, batch)


def test_checked_order_matches_the_factorized_order():
    df = _table()
    out, index = sorted_with_index(df)
    # A fresh copy in the same order goes through the text comparison, not the sort.
    again = out.copy()
    assert known_order(again) is None
    same, index2 = sorted_with_index(again)
    assert same is again
    ref = _codes_index(out)
    for a, b in ((index, index2), (index, ref)):
        np.testing.assert_array_equal(a.starts, b.starts)
        np.testing.assert_array_equal(a.track_of_row, b.track_of_row)
        pd.testing.assert_frame_equal(a.keys, b.keys)


def test_known_table_is_answered_without_sorting(monkeypatch):
    out, index = sorted_with_index(_table(1))
    monkeypatch.setattr(tracks, "time_seconds", None)  # any re-derivation would fail
    assert sorted_with_index(out)[1] is index
    assert sort_points(out) is out
    assert tracks.track_index(out) is index
    assert track_seconds(out) is known_order(out)[1]


def _in_order(df: pd.DataFrame) -> bool:
    sensor, batch = tracks._key_codes(df)
    track = sensor * (int(batch.max()) + 1) + batch
    return tracks._is_sorted(track, tracks.time_seconds(df["time"]))


def test_derived_or_changed_tables_are_not_trusted():
    out, _ = sorted_with_index(_table(2))
    shuffled = out.iloc[np.random.default_rng(0).permutation(len(out))]
    assert known_order(shuffled) is None
    again, _ = sorted_with_index(shuffled)
    assert again is not shuffled and _in_order(again)
    out["time"] = out["time"].iloc[::-1].to_numpy()  # a replaced key column
    assert known_order(out) is None
    resorted, index = sorted_with_index(out)
    assert resorted is not out and _in_order(resorted)
    np.testing.assert_array_equal(index.starts, _codes_index(resorted).starts)


def test_object_keys_are_remembered_too():
    df = _table(3).astype({"sensor": object, "batch": object})
    out, index = sorted_with_index(df)
    assert known_order(out) is not None and sorted_with_index(out)[1] is index
    out["batch"] = out["batch"].to_numpy()[::-1]
    assert known_order(out) is None


def test_sorting_rebuilds_text_keys_exactly():
    df = _table(4)[["time", "batch", "lon", "sensor", "lat"]].assign(extra=np.arange(400))
    out, _ = sorted_with_index(df)
    sensor, batch = tracks._key_codes(df)
    track = sensor * (int(batch.max()) + 1) + batch
    order = tracks._sort_order(track, tracks.time_seconds(df["time"]))
    pd.testing.assert_frame_equal(out, df.iloc[order].reset_index(drop=True), check_exact=True)

"""Sort once: a table sorted or checked by ``sorted_with_index`` is remembered, safely."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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


def _reference(df: pd.DataFrame) -> pd.DataFrame:
    """The order every path must give: sensor, batch (as text), time, then input order."""
    k = df.assign(_row=np.arange(len(df)))
    return (
        k.sort_values(["sensor", "batch", "time", "_row"], kind="stable")
        .drop(columns="_row")
        .reset_index(drop=True)
    )


_BATCHES = ["0", "7", "9", "10", "100", "-3", "007", "+5", "b", "é", " 5", "12345678901"]


@settings(max_examples=60, deadline=None)
@given(
    batches=st.lists(st.sampled_from(_BATCHES), min_size=1, max_size=8, unique=True),
    sizes=st.lists(st.integers(1, 40), min_size=1, max_size=8),
    layout=st.sampled_from(["runs", "runs split", "time order", "shuffled"]),
    seed=st.integers(0, 2**16),
)
def test_every_sort_path_gives_the_reference_order(batches, sizes, layout, seed):
    """Contiguous runs out of text order (runs are sorted), a track split over two runs,
    a time-ordered export (radix by track) and shuffled rows; integer-like batch text
    (a lookup) and other text (a hash): all give the reference order and index."""
    rng = np.random.default_rng(seed)
    sizes = (sizes * len(batches))[: len(batches)]
    batch = np.repeat(batches, sizes)
    step = np.concatenate([np.arange(k) for k in sizes]) * 10
    t = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(step, unit="s")
    df = pd.DataFrame(
        {
            "sensor": pd.Series(
                np.where(rng.random(len(batch)) < 0.2, "AIS", "R1")
                if layout == "shuffled"
                else "R1",
                dtype="str",
            ),
            "batch": pd.Series(batch, dtype="str"),
            "time": t,
            "lon": rng.uniform(120, 121, len(batch)),
            "lat": rng.uniform(30, 31, len(batch)),
        }
    )
    if layout == "runs split" and len(df) > 2:
        cut = len(df) // 2
        df = pd.concat([df.iloc[cut:], df.iloc[:cut]]).reset_index(drop=True)
    elif layout == "time order":
        df = df.sort_values("time", kind="stable").reset_index(drop=True)
    elif layout == "shuffled":
        df = df.iloc[rng.permutation(len(df))].reset_index(drop=True)
    tracks._IN_ORDER.clear()
    out, index = sorted_with_index(df)
    ref = _reference(df)
    pd.testing.assert_frame_equal(out, ref, check_exact=True)
    expected = _codes_index(ref)
    np.testing.assert_array_equal(index.starts, expected.starts)
    np.testing.assert_array_equal(index.ends, expected.ends)
    np.testing.assert_array_equal(index.track_of_row, expected.track_of_row)
    pd.testing.assert_frame_equal(index.keys, expected.keys)
    np.testing.assert_array_equal(track_seconds(out), tracks.time_seconds(ref["time"]))


@pytest.mark.parametrize(
    "values",
    [["0", "17", "-3", "17", "10", "9", "100"], ["12345678901", "5", "5"], ["3"] * 5],
)
def test_integer_text_is_factorized_as_pandas_does(values):
    col = pd.Series(values, dtype="str")
    codes, uniques = tracks._integer_text_codes(col)
    ref_codes, ref_uniques = pd.factorize(col, sort=True)
    np.testing.assert_array_equal(codes, ref_codes)
    assert list(uniques) == list(ref_uniques)


@pytest.mark.parametrize(
    "values", [["007", "7"], ["-0", "0"], ["+5"], [" 5"], ["1e3"], ["a", "1"], ["1", None]]
)
def test_text_that_is_not_plain_integers_takes_the_hash(values):
    assert tracks._integer_text_codes(pd.Series(values, dtype="str")) is None


def test_contiguous_runs_are_reordered_not_sorted(monkeypatch):
    """Batches "0".."11" each in one run: the runs are put in text order, no row sort."""
    n = 12
    df = pd.DataFrame(
        {
            "sensor": pd.Series(["R1"] * (n * 20), dtype="str"),
            "batch": pd.Series(np.repeat([str(k) for k in range(n)], 20), dtype="str"),
            "time": pd.Timestamp("2024-05-01", tz="UTC")
            + pd.to_timedelta(np.tile(np.arange(20) * 10, n), unit="s"),
            "lon": np.arange(n * 20.0),
            "lat": np.zeros(n * 20),
        }
    )
    monkeypatch.setattr(tracks, "_sort_order", None)  # a row sort would fail
    out, index = sorted_with_index(df)
    pd.testing.assert_frame_equal(out, _reference(df), check_exact=True)
    assert list(index.keys["batch"][:4]) == ["0", "1", "10", "11"]

"""Timestamps written from the int64 epoch match Arrow's strftime: at the ms for a whole
ms, at the us or ns a finer time needs (nothing cut; each row on its own, so a file
written in blocks reads the same)."""

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core.io import read_points, write_points
from wakeline.core.io.writer import iso_ms_from_ns


def _arrow_reference(ns: np.ndarray) -> list:
    """Arrow's strftime at the ns, the digits below the ms dropped where they are zeros
    (in threes: 9, 6 or 3 decimals)."""
    arr = pa.array(ns, type=pa.timestamp("ns", "UTC"))
    out = []
    for text in pc.strftime(arr, format="%Y-%m-%dT%H:%M:%SZ").to_pylist():
        for zeros in ("000000Z", "000Z"):
            if text.endswith(zeros):
                text = text[: -len(zeros)] + "Z"
                break
        out.append(text)
    return out


def _spread(scale: int) -> np.ndarray:
    rng = np.random.default_rng(17)
    ns = rng.integers(-(2**62) // scale, 2**62 // scale, 5000) * scale
    edges = [0, -1, -999_999, -1_000_000, -1_000_001, 1, 999_999, 951_782_400 * 10**9]
    edges = [e // scale * scale for e in edges]
    ns[: len(edges)] = edges  # around the epoch, and 2000-02-29
    return ns


def test_epoch_integer_text_matches_strftime():
    for scale in (1_000_000, 1_000, 1):
        ns = _spread(scale)
        assert iso_ms_from_ns(ns).to_pylist() == _arrow_reference(ns), scale
    mixed = np.concatenate([_spread(1_000_000)[:50], _spread(1_000)[:50], _spread(1)[:50]])
    got = iso_ms_from_ns(mixed).to_pylist()
    assert got == _arrow_reference(mixed)  # each row at its own precision
    assert {len(t) for t in got} == {24, 27, 30}


def test_nulls_and_empty():
    ns = np.array([0, 5, 10**18])
    valid = np.array([True, False, True])
    out = iso_ms_from_ns(ns, valid).to_pylist()
    assert out == ["1970-01-01T00:00:00.000Z", None, "2001-09-09T01:46:40.000Z"]
    assert iso_ms_from_ns(np.zeros(0, dtype="int64")).to_pylist() == []


def test_sub_ms_times_survive_writing_and_reading(tmp_path):
    """500 fixes 0.1 ms apart: written at the ms they were 50 distinct times (fuzzing
    found a re-clean dropping 450 as duplicates)."""
    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    for step in (pd.Timedelta(100, "us"), pd.Timedelta(37, "ns")):
        pts = pd.DataFrame(
            {
                "sensor": "S",
                "batch": "1",
                "time": t0 + step * np.arange(500),
                "lon": 10 + 1e-6 * np.arange(500),
                "lat": 55.0,
            }
        )
        write_points(pts, tmp_path / "sub.csv")
        back = read_points(tmp_path / "sub.csv").points
        assert back["time"].dt.as_unit("ns").equals(pts["time"].dt.as_unit("ns")), step

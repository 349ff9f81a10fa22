"""Timestamps written from the int64 epoch match Arrow's strftime of the ms-cut time."""

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core.io.writer import iso_ms_from_ns


def _arrow_reference(ns: np.ndarray) -> list:
    arr = pc.cast(
        pa.array(ns, type=pa.timestamp("ns", "UTC")), pa.timestamp("ms", "UTC"), safe=False
    )
    return pc.strftime(arr, format="%Y-%m-%dT%H:%M:%SZ").to_pylist()


def test_epoch_integer_text_matches_strftime():
    rng = np.random.default_rng(17)
    ns = rng.integers(-(2**62), 2**62, 5000)
    edges = [0, -1, -999_999, -1_000_000, -1_000_001, 1, 999_999, 951_782_400 * 10**9]
    ns[: len(edges)] = edges  # around the epoch, and 2000-02-29
    assert iso_ms_from_ns(ns).to_pylist() == _arrow_reference(ns)


def test_nulls_and_empty():
    ns = np.array([0, 5, 10**18])
    valid = np.array([True, False, True])
    out = iso_ms_from_ns(ns, valid).to_pylist()
    assert out == ["1970-01-01T00:00:00.000Z", None, "2001-09-09T01:46:40.000Z"]
    assert iso_ms_from_ns(np.zeros(0, dtype="int64")).to_pylist() == []

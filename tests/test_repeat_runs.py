"""core.sorted_sets.repeat_runs: np.repeat(values, sizes) filled by GIL-releasing numpy
calls (np.repeat holds the GIL while it fills a million-point output; h180)."""

import numpy as np
import pytest

from wakeline.core.sorted_sets import repeat_runs


@pytest.mark.parametrize("dtype", ["float64", "int64", "bool", "float32", "datetime64[ns]"])
def test_repeat_runs_equals_numpy(dtype):
    rng = np.random.default_rng(0)
    for _ in range(400):
        k = int(rng.integers(0, 9))
        sizes = rng.integers(0, 4, k)  # empty runs among them, first and last too
        values = rng.integers(0, 50, k).astype(dtype)
        got, want = repeat_runs(values, sizes), np.repeat(values, sizes)
        assert got.dtype == want.dtype
        assert np.array_equal(got, want)


def test_run_numbers_equal_numpy():
    rng = np.random.default_rng(1)
    for _ in range(400):
        k = int(rng.integers(0, 9))
        sizes = rng.integers(0, 4, k)
        got, want = repeat_runs(None, sizes), np.repeat(np.arange(k), sizes)
        assert got.dtype == want.dtype
        assert np.array_equal(got, want)


def test_million_points_and_object_values():
    rng = np.random.default_rng(2)
    sizes = rng.integers(0, 1000, 2000)
    values = rng.random(2000)
    assert np.array_equal(repeat_runs(values, sizes), np.repeat(values, sizes))
    text = np.array(["a", None, "c"], dtype=object)  # object values: np.repeat itself
    assert list(repeat_runs(text, [2, 0, 1])) == ["a", "a", "c"]

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


def test_member_equals_isin():
    """core.sorted_sets.member is np.isin for integer arrays (by sort and searchsorted,
    which release the GIL; np.isin's hash table holds it): many random draws, empty
    arrays, duplicates, negatives, keys beyond every value."""
    from wakeline.core.sorted_sets import member

    rng = np.random.default_rng(3)
    for _ in range(500):
        x = rng.integers(-20, 20, int(rng.integers(0, 30)))
        keys = rng.integers(-25, 25, int(rng.integers(0, 30)))
        got, want = member(x, keys), np.isin(x, keys)
        assert got.dtype == bool and got.shape == want.shape
        assert np.array_equal(got, want)
    x = rng.integers(0, 2**40, 1_000_000)
    keys = np.concatenate([x[::3], rng.integers(0, 2**40, 100_000)])
    assert np.array_equal(member(x, keys), np.isin(x, keys))


def test_member_takes_scalars_and_object_arrays_as_np_isin_does():
    """Review h216: a scalar and object arrays (None beside ints) go to np.isin."""
    from wakeline.core.sorted_sets import member

    assert bool(member(np.int64(3), np.array([1, 3])))
    mixed = np.array([None, 1, "a"], dtype=object)
    assert member(mixed, np.array([1, "a"], dtype=object)).tolist() == [False, True, True]

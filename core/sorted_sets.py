"""Set operations on integer arrays by sorting, pure numpy (worker-safe).

numpy 2.4's ``np.unique`` (and so ``np.union1d``) of many distinct integers goes through a
hash table that takes 0.6-1.6 s for a million values, against 6-25 ms to sort and mask; a
worker holding the GIL that long stalls the window. These give the same sorted distinct
values as ``np.unique`` / ``np.union1d`` for integer arrays.
"""

import numpy as np


def distinct(a: np.ndarray) -> np.ndarray:
    """Sorted distinct values of an integer array (``np.unique(a)``, by sort and mask)."""
    s = np.sort(np.asarray(a).ravel())
    if len(s) < 2:
        return s
    keep = np.empty(len(s), dtype=bool)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def union(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Sorted distinct values in either integer array (``np.union1d``)."""
    return distinct(np.concatenate([np.asarray(a).ravel(), np.asarray(b).ravel()]))


def member(x: np.ndarray, keys: np.ndarray) -> np.ndarray:
    """``np.isin(x, keys)`` for integer arrays, by sort and ``searchsorted``: ``np.isin``
    of a million integers goes through ``np.unique``'s hash table with the GIL held
    (0.3-0.7 s of a worker's Associate on 1.1 M points stalled the window); sorting,
    searching and taking release it."""
    x = np.asarray(x)
    if x.dtype == object or np.asarray(keys).dtype == object or x.ndim == 0:
        return np.isin(x, keys)  # mixed objects do not sort; a scalar has no take
    ks = distinct(keys)
    if len(ks) == 0 or x.size == 0:
        return np.zeros(x.shape, dtype=bool)
    pos = np.searchsorted(ks, x)
    np.minimum(pos, len(ks) - 1, out=pos)
    return ks.take(pos) == x


def repeat_runs(values: np.ndarray | None, sizes: np.ndarray) -> np.ndarray:
    """``np.repeat(values, sizes)`` for a 1-D ``values`` and non-negative integer
    ``sizes`` (one per value); ``values`` None: each item's run number
    (``np.repeat(np.arange(len(sizes)), sizes)``), as intp.

    ``np.repeat`` holds the GIL while it fills its output, and the output's fresh pages
    are part of that: at a million points 50–300 ms on the shared test machine, a worker
    stalling the window's event loop all that time (bench/gui_block_probe.py). Here the
    output is filled by ``fill``, ``cumsum`` and ``take``, which release it."""
    sizes = np.asarray(sizes)
    if values is not None:
        values = np.asarray(values)
        if values.dtype.hasobject or values.ndim != 1:
            return np.repeat(values, sizes)
    n = int(sizes.sum()) if len(sizes) else 0
    if n == 0:
        return np.repeat(np.arange(len(sizes)) if values is None else values, sizes)
    nonempty = np.flatnonzero(sizes)
    ends = np.cumsum(sizes[nonempty])
    run = np.empty(n, dtype=np.intp)
    run.fill(0)  # not np.zeros: calloc may clear the pages with the GIL held
    run[ends[:-1]] = np.diff(nonempty)
    run[0] = nonempty[0]
    np.cumsum(run, out=run)
    return run if values is None else values.take(run)

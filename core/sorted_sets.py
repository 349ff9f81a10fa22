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

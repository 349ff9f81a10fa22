"""``noise_k_law`` (session 28, h185; D-man-1): the noise floor's k at the same false-alarm
probability under the heading change's REAL law at a window's span, not the normal law.

The floor takes δ on a straight noisy track as |normal| with sd σ·sqrt(12/p)·hypot(1/lb,
1/lf) (``maneuver._heading_noise_deg``). Where a window spans few σ the law is far from
normal (h170: at 3 σ δ passes 4 sd in 4.2 % of the rows, not 0.006 %). ``C_TABLE`` holds,
per k, p and span r = min(lb, lf) / σ (observed, as the floor takes the spans), the
quantile of δ / sd at the tail probability P(|Z| > k) of the normal law, divided by k (at
least 1): the factor k is multiplied by. Simulated by ``bench/noise_law_table.py``
(straight windows, white noise, 1.2 M window pairs per p, seed 0); beyond the last bin
(64 σ) the law is taken as normal (1), and every row made non-increasing in r.
"""

from __future__ import annotations

import numpy as np

P_GRID = (3, 4, 5, 6, 8, 10, 14, 20)
K_GRID = (1.5, 2.0, 2.5, 3.0, 3.5)
#: bin edges of r (σ): geometric from 1 to 64, ratio sqrt(2)
R_EDGES = tuple(float(v) for v in np.geomspace(1.0, 64.0, 13))

from wakeline.core._noise_law_table import C_TABLE  # noqa: E402  (generated numbers)

_TABLE = np.asarray(C_TABLE, dtype=float)  # [k][p][r bin]
_edges = np.asarray(R_EDGES)
# bin centres (log), then 1 at twice the last edge: the law is normal far out
_LOG_R = np.append(np.log(np.sqrt(_edges[:-1] * _edges[1:])), np.log(2.0 * _edges[-1]))
_TABLE = np.concatenate([_TABLE, np.ones(_TABLE.shape[:2] + (1,))], axis=-1)


def _frac(value: np.ndarray, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower grid index and weight of the next, ``value`` clipped to the grid's ends."""
    pos = np.interp(value, grid, np.arange(len(grid), dtype=float))
    lo = np.minimum(np.floor(pos).astype("int64"), len(grid) - 2)
    return lo, pos - lo


def law_factor(k: float | np.ndarray, p: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Per row: the factor (≥ 1) k is multiplied by at ``p`` points per window and span
    ``r`` σ; trilinear in (k, p, log r) within the table, its ends beyond it; r NaN or
    not positive: the factor of the shortest span."""
    p = np.asarray(p, dtype=float)
    r = np.asarray(r, dtype=float)
    k = np.broadcast_to(np.asarray(k, dtype=float), p.shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        lr = np.log(np.where(r > 0, r, 1e-300))
    lr = np.where(np.isnan(lr), -np.inf, lr)
    ki, kw = _frac(k, np.asarray(K_GRID))
    pi, pw = _frac(p, np.asarray(P_GRID, dtype=float))
    ri, rw = _frac(lr, _LOG_R)
    out = np.zeros(p.shape)
    for dk, wk in ((0, 1 - kw), (1, kw)):
        for dp, wp in ((0, 1 - pw), (1, pw)):
            for dr, wr in ((0, 1 - rw), (1, rw)):
                out += wk * wp * wr * _TABLE[ki + dk, pi + dp, ri + dr]
    return np.maximum(out, 1.0)

"""The heading-change law of straight noisy windows, as a table for ``noise_k_law``.

For a window pair of p points each (sharing the centre point, as the detector's), along a
straight line with the window span L, white noise σ per axis: z = δ / sd, sd the noise
floor's normal-law deviation (``_heading_noise_deg``: σ·sqrt(12/p)·hypot(1/lb, 1/lf), with
the OBSERVED spans lb, lf, as the detector takes them). Binned by r = min(lb, lf) / σ, the
quantile of z at the tail probability 2(1 − Φ(k)) of today's k, divided by k (at least 1):
``core/noise_law.py``'s C_TABLE. Run: ``python bench/noise_law_table.py [--n N] [--seed S]``
(prints the table as Python to paste).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from wakeline.core.maneuver import _angle_diff, window_headings

P_GRID = (3, 4, 5, 6, 8, 10, 14, 20)
K_GRID = (1.5, 2.0, 2.5, 3.0, 3.5)
# bin edges of r (observed min span in σ): geometric, 1 … 64; the table holds each bin's
# geometric centre; beyond 64 σ the law is taken as normal (c = 1)
R_EDGES = tuple(float(v) for v in np.geomspace(1.0, 64.0, 13))


def tail(k: float) -> float:
    return math.erfc(k / math.sqrt(2.0))  # P(|Z| > k)


def simulate(p: int, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """z and r of n straight window pairs (true span log-uniform 0.7 … 90 σ)."""
    m = 2 * p - 1
    span = np.exp(rng.uniform(np.log(0.7), np.log(90.0), n))
    step = span / (p - 1)
    i = np.arange(m)
    ang = rng.uniform(0, 2 * np.pi, n)
    s = step[:, None] * i[None, :]
    x = s * np.cos(ang)[:, None] + rng.standard_normal((n, m))
    y = s * np.sin(ang)[:, None] + rng.standard_normal((n, m))
    x -= x[:, :1]
    y -= y[:, :1]
    hb = window_headings(x[:, :p].ravel(), y[:, :p].ravel(), p)[p - 1 :: p]
    hf = window_headings(x[:, p - 1 :].ravel(), y[:, p - 1 :].ravel(), p)[p - 1 :: p]
    delta = _angle_diff(hb, hf)
    lb = np.hypot(x[:, p - 1] - x[:, 0], y[:, p - 1] - y[:, 0])
    lf = np.hypot(x[:, -1] - x[:, p - 1], y[:, -1] - y[:, p - 1])
    sd = np.degrees(np.hypot(np.sqrt(12.0 / p) / lb, np.sqrt(12.0 / p) / lf))
    return delta / sd, np.minimum(lb, lf)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_200_000, help="window pairs per p")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    edges = np.asarray(R_EDGES)
    table = np.ones((len(K_GRID), len(P_GRID), len(edges) - 1))
    counts = np.zeros((len(P_GRID), len(edges) - 1), dtype=int)
    for j, p in enumerate(P_GRID):
        zs, rs = [], []
        for _ in range(6):
            z, r = simulate(p, a.n // 6, rng)
            zs.append(z)
            rs.append(r)
        z, r = np.concatenate(zs), np.concatenate(rs)
        b = np.searchsorted(edges, r) - 1
        for i in range(len(edges) - 1):
            zi = z[b == i]
            counts[j, i] = len(zi)
            for q, k in enumerate(K_GRID):
                table[q, j, i] = max(1.0, float(np.quantile(zi, 1.0 - tail(k))) / k)
    # c grows as the span shrinks: each row made non-increasing in r (sampling noise)
    table = np.maximum.accumulate(table[..., ::-1], axis=-1)[..., ::-1]
    print("# pairs per bin, min", counts.min(), "max", counts.max())
    print("C_TABLE = (  # [k][p][r bin]")
    for q, k in enumerate(K_GRID):
        print(f"    (  # k = {k}")
        for j, p in enumerate(P_GRID):
            print("        (" + ", ".join(f"{v:.3f}" for v in table[q, j]) + f"),  # p {p}")
        print("    ),")
    print(")")


if __name__ == "__main__":
    main()

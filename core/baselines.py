"""Maneuver-detection baselines of seed 000 §3.1, as real implementations.

- :func:`imm_detect`: an interacting-multiple-model filter with three constant-velocity
  models (process noise 0, Q₂ = 0.001·I, Q₃ = 0.00144·I), Markov matrix with 0.95 on
  the diagonal and 0.025 elsewhere, started at sample 10 with μ = (0.8, 0.1, 0.1); a
  maneuver is declared when the maneuvering models' probability μ₂ + μ₃ exceeds 0.8,
  after which the filter is started afresh. The paper gives no units: we use kilometres
  and minutes (Q in km²/min⁴ of white acceleration noise), the measurement noise is the
  position noise σ, and the initial velocity is the least-squares slope over the
  velocity-accumulation window of 11 samples.
- :func:`entropy_detect`: information-entropy segmentation — k-means labels on the leg
  headings (k = the true number of maneuvers, as the paper grants), then the (sub)track
  with the highest label entropy is split where the two parts' weighted entropy is
  lowest, until every part's entropy is below 0.3 or there are k + 1 parts.

Both work on one track's local (x, y) metres and times (s) and return the indices of the
detected maneuver points. They are baselines: a loop per sample (IMM) or per split
(entropy) is accepted here, not in Wakeline's own detector.
"""

import numpy as np
from scipy.cluster.vq import kmeans2

IMM_Q = (0.0, 0.001, 0.00144)  # km²/min⁴
IMM_P = np.array([[0.95, 0.025, 0.025], [0.025, 0.95, 0.025], [0.025, 0.025, 0.95]])
IMM_MU0 = np.array([0.8, 0.1, 0.1])


def _cv_matrices(dt_min: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    f1 = np.array([[1.0, dt_min], [0.0, 1.0]])
    g = np.array([[dt_min**2 / 2.0], [dt_min]])
    F = np.kron(np.eye(2), f1)  # state (x, vx, y, vy)
    Q = np.kron(np.eye(2), g @ g.T * q)
    return F, Q


def imm_detect(
    x_m: np.ndarray,
    y_m: np.ndarray,
    t_s: np.ndarray,
    sigma_m: float,
    start: int = 10,
    window: int = 11,
    threshold: float = 0.8,
) -> np.ndarray:
    """Indices of maneuvers found by the three-model IMM (see module docstring)."""
    z = np.column_stack([x_m, y_m]) / 1000.0  # km
    t = (t_s - t_s[0]) / 60.0  # minutes
    n = len(z)
    H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    R = np.eye(2) * (sigma_m / 1000.0) ** 2
    found = []
    k0 = 0
    while k0 + start < n:
        # initialise from the accumulation window: least-squares position and velocity
        w = slice(k0, min(k0 + max(window, start), n))
        tw = t[w] - t[k0 + start - 1]
        A = np.column_stack([np.ones_like(tw), tw])
        coef, *_ = np.linalg.lstsq(A, z[w], rcond=None)
        state = np.array([coef[0, 0], coef[1, 0], coef[0, 1], coef[1, 1]])
        P0 = np.diag([R[0, 0], 0.01, R[1, 1], 0.01])
        xs = [state.copy() for _ in range(3)]
        Ps = [P0.copy() for _ in range(3)]
        mu = IMM_MU0.copy()
        restarted = False
        for k in range(k0 + start, n):
            dt = t[k] - t[k - 1]
            # mixing
            c = IMM_P.T @ mu
            mix = (IMM_P * mu[:, None]) / np.where(c > 0, c, 1e-300)[None, :]
            x0 = [sum(mix[i, j] * xs[i] for i in range(3)) for j in range(3)]
            P0s = [
                sum(mix[i, j] * (Ps[i] + np.outer(xs[i] - x0[j], xs[i] - x0[j])) for i in range(3))
                for j in range(3)
            ]
            like = np.zeros(3)
            for j in range(3):
                F, Q = _cv_matrices(dt, IMM_Q[j])
                xp = F @ x0[j]
                Pp = F @ P0s[j] @ F.T + Q
                S = H @ Pp @ H.T + R
                resid = z[k] - H @ xp
                Si = np.linalg.inv(S)
                K = Pp @ H.T @ Si
                xs[j] = xp + K @ resid
                Ps[j] = (np.eye(4) - K @ H) @ Pp
                like[j] = np.exp(-0.5 * resid @ Si @ resid) / (
                    2 * np.pi * np.sqrt(np.linalg.det(S))
                )
            mu = c * like
            total = mu.sum()
            mu = mu / total if total > 0 else IMM_MU0.copy()
            if mu[1] + mu[2] > threshold:
                found.append(k)
                k0 = k
                restarted = True
                break
        if not restarted:
            break
    return np.asarray(found, dtype="int64")


def _entropy(labels: np.ndarray, k: int) -> float:
    if len(labels) == 0:
        return 0.0
    p = np.bincount(labels, minlength=k) / len(labels)
    p = p[p > 0]
    return float(-(p * np.log2(p)).sum())


def entropy_detect(
    x_m: np.ndarray, y_m: np.ndarray, n_maneuvers: int, threshold: float = 0.3, seed: int = 0
) -> np.ndarray:
    """Indices of maneuvers found by entropy segmentation (see module docstring)."""
    n = len(x_m)
    if n_maneuvers <= 0 or n < 4:
        return np.zeros(0, dtype="int64")
    heading = np.arctan2(np.diff(x_m), np.diff(y_m))  # leg i: point i -> i+1
    features = np.column_stack([np.cos(heading), np.sin(heading)])
    k = max(int(n_maneuvers), 2)
    _, labels = kmeans2(features, k, minit="++", seed=seed)
    parts = [(0, len(labels))]  # leg ranges
    splits: list[int] = []
    while len(parts) <= n_maneuvers:
        ent = [_entropy(labels[a:b], k) for a, b in parts]
        i = int(np.argmax(ent))
        if ent[i] < threshold:
            break
        a, b = parts[i]
        best, best_cut = np.inf, None
        for cut in range(a + 1, b):
            h = (
                (cut - a) * _entropy(labels[a:cut], k) + (b - cut) * _entropy(labels[cut:b], k)
            ) / (b - a)
            if h < best:
                best, best_cut = h, cut
        if best_cut is None:
            break
        parts[i : i + 1] = [(a, best_cut), (best_cut, b)]
        splits.append(best_cut)  # legs best_cut-1 and best_cut meet at point best_cut
    return np.asarray(sorted(splits), dtype="int64")

"""Evaluations that reproduce the papers' tables with our methods and the baselines."""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import baselines, simulate
from wakeline.core.compress import compress_with, douglas_peucker_mask
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import local_xy

#: Seed 000 Table 1, mean Dis_e in metres: (sigma, class) -> (IMM, entropy, paper's method)
SEED000_TABLE1 = {
    (300, "short"): (1211.09, 737.97, 463.50),
    (300, "medium"): (1339.40, 2279.62, 547.72),
    (300, "long"): (2503.84, 3239.33, 1005.47),
    (600, "short"): (1671.84, 1181.92, 973.93),
    (600, "medium"): (2621.60, 2946.93, 1058.74),
    (600, "long"): (2998.29, 7734.53, 1075.10),
}

METHODS = ("IMM", "entropy", "PCA (paper)", "PCA + LS vertices", "Douglas-Peucker")


def match_turns(
    pred: np.ndarray, truth: np.ndarray, track_of_row: np.ndarray, tol: int = 2
) -> dict:
    """Precision, recall and F1 of detected turn points; a detection (true turn) counts when
    a true turn (detection) of the same track lies within ±``tol`` samples."""
    n = len(pred)

    def near(mask: np.ndarray) -> np.ndarray:
        out = mask.copy()
        for k in range(1, tol + 1):
            same = track_of_row[k:] == track_of_row[:-k]
            out[k:] |= mask[:-k] & same
            out[:-k] |= mask[k:] & same
        return out

    tp_pred = int((pred & near(truth)).sum()) if n else 0
    tp_true = int((truth & near(pred)).sum()) if n else 0
    precision = tp_pred / pred.sum() if pred.sum() else (1.0 if not truth.sum() else 0.0)
    recall = tp_true / truth.sum() if truth.sum() else 1.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return {"precision": float(precision), "recall": float(recall), "f1": float(f1)}


@dataclass(frozen=True)
class ManeuverEvaluation:
    """Per (sigma, class, method): mean Dis_e against truth and observations, turn scores."""

    table: pd.DataFrame
    n_tracks: int
    seed: int
    params: ManeuverParams
    dp_tolerance_sigmas: float

    def format(self) -> str:
        """Seed 000 Table 1's layout with our figures, then turn-point detection scores."""
        t = self.table
        lines = [
            f"Seed 000 protocol: {self.n_tracks} tracks per class, seed {self.seed}; 16 kn, 5 min period, "
            f"turns 15-45 deg every 6-12 periods. Ours: p = {self.params.window_p}, n = {self.params.radius_n}, "
            f"t = {self.params.threshold_deg:g} deg; DP tolerance {self.dp_tolerance_sigmas:g} sigma.",
            "",
            "Mean Dis_e against the TRUE path, metres (paper's figures in brackets)",
            f"{'sigma':>5} {'class':<7} {'IMM':>16} {'entropy':>16} {'PCA (paper)':>17} "
            f"{'PCA + LS vertices':>17} {'Douglas-Peucker':>15}",
        ]
        for (sigma, cls), paper in SEED000_TABLE1.items():
            row = t[(t.sigma == sigma) & (t["class"] == cls)].set_index("method")
            if row.empty:
                continue
            d = row["dis_e_true_m"]
            lines.append(
                f"{sigma:>5} {cls:<7} {d['IMM']:7.0f} ({paper[0]:6.0f}) {d['entropy']:7.0f} ({paper[1]:6.0f}) "
                f"{d['PCA (paper)']:7.0f} ({paper[2]:7.0f}) {d['PCA + LS vertices']:17.0f} "
                f"{d['Douglas-Peucker']:15.0f}"
            )
        lines += [
            "",
            "Mean Dis_e against the OBSERVED points, metres (a perfect track scores ~sigma*sqrt(pi/2))",
            f"{'sigma':>5} {'class':<7} " + " ".join(f"{m:>17}" for m in METHODS),
        ]
        for sigma, cls in SEED000_TABLE1:
            row = t[(t.sigma == sigma) & (t["class"] == cls)].set_index("method")
            if not row.empty:
                lines.append(
                    f"{sigma:>5} {cls:<7} "
                    + " ".join(f"{row.loc[m, 'dis_e_obs_m']:17.0f}" for m in METHODS)
                )
        lines += [
            "",
            "Turn points (match within +-2 samples): precision / recall / F1; share of points kept",
            f"{'sigma':>5} {'class':<7} "
            + " ".join(f"{m:>23}" for m in ("IMM", "entropy", "PCA", "Douglas-Peucker")),
        ]
        for sigma, cls in SEED000_TABLE1:
            row = t[(t.sigma == sigma) & (t["class"] == cls)].set_index("method")
            if row.empty:
                continue
            cells = []
            for m in ("IMM", "entropy", "PCA (paper)", "Douglas-Peucker"):
                r = row.loc[m]
                cells.append(f"{r.precision:.2f}/{r.recall:.2f}/{r.f1:.2f} {r.ratio:5.3f}")
            lines.append(f"{sigma:>5} {cls:<7} " + " ".join(f"{c:>23}" for c in cells))
        return "\n".join(lines)


def evaluate_maneuver(
    n_tracks: int = 100,
    seed: int = 0,
    params: ManeuverParams | None = None,
    dp_tolerance_sigmas: float = 2.0,
    sigmas: tuple[float, ...] = (300.0, 600.0),
    classes: tuple[str, ...] = ("short", "medium", "long"),
    progress: Progress | None = None,
) -> ManeuverEvaluation:
    """Seed 000 §3.1's protocol: Dis_e and turn detection for ours and the baselines."""
    params = (params or ManeuverParams()).checked()
    progress = progress or null_progress
    rows = []
    cases = [(s, c) for s in sigmas for c in classes]
    for k, (sigma, cls) in enumerate(cases):
        progress(k / len(cases), f"sigma {sigma:g} m, {cls} tracks")
        df = simulate.maneuver_tracks(n_tracks, cls, sigma, seed=seed + 1000 * k)
        result = detect(df, params)
        pts, index = result.points, result.index
        truth = pts["true_turn"].to_numpy() == 1
        x, y = local_xy(pts, index)
        t = time_seconds(pts["time"])
        imm = np.zeros(len(pts), dtype=bool)
        entropy = np.zeros(len(pts), dtype=bool)
        for a, b in zip(index.starts, index.ends, strict=True):  # baselines: one track at a time
            imm[a + baselines.imm_detect(x[a:b], y[a:b], t[a:b], sigma)] = True
            entropy[
                a + baselines.entropy_detect(x[a:b], y[a:b], int(truth[a:b].sum()), seed=seed)
            ] = True
        masks = {
            "IMM": imm,
            "entropy": entropy,
            "PCA (paper)": result.is_maneuver,
            "PCA + LS vertices": result.is_maneuver,
            "Douglas-Peucker": douglas_peucker_mask(x, y, index, dp_tolerance_sigmas * sigma),
        }
        for method, mask in masks.items():
            comp = compress_with(
                None, mask, refine=(method == "PCA + LS vertices"), sorted_points=pts
            )
            overall = comp.report()["overall"]
            inner = mask.copy()
            inner[index.starts] = False
            inner[index.ends - 1] = False
            rows.append(
                {
                    "sigma": int(sigma),
                    "class": cls,
                    "method": method,
                    "dis_e_true_m": overall["dis_e_true_m"],
                    "dis_e_obs_m": overall["dis_e_m"],
                    "ratio": overall["ratio"],
                    **match_turns(inner, truth, index.track_of_row),
                }
            )
    progress(1.0, "done")
    return ManeuverEvaluation(pd.DataFrame(rows), n_tracks, seed, params, dp_tolerance_sigmas)

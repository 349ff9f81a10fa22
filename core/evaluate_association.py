"""Scores for association (SPEC §5, §6) and the evaluation on simulated scenes.

Pair scores (seed 003): P_CA = |OAP ∩ TAP| / |TAP| and P_FA = |OAP − TAP| / |OAP|.
Target scores (seed 001 eq. 15–17): a target is correctly identified when one output
cluster holds exactly its segments; P = correct / clusters, R = correct / true targets.
Pairwise scores: over all pairs of segments, "same cluster" against "same ship".
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import simulate
from wakeline.core.associate import LinkParams, associate_interrupted, associate_segments
from wakeline.core.progress import Progress, null_progress

#: Seed 001 Table 3 (real East China Sea radar): method -> (P, R, F1)
SEED001_TABLE3 = {
    "S+LDM+σ (seed 001)": (0.7553, 0.7688, 0.7606),
    "S+DTW+σ": (0.5684, 0.5183, 0.5391),
    "S+Hausdorff+σ": (0.4938, 0.5611, 0.5253),
    "TSMM-KNN": (0.6331, 0.5974, 0.6118),
}


def _f1(p: float, r: float) -> float:
    return 2 * p * r / (p + r) if p + r else 0.0


def pair_scores(out_pairs: set, true_pairs: set) -> dict:
    """P_CA and P_FA of output pairs against true pairs (sets of hashable pair keys)."""
    hit = len(out_pairs & true_pairs)
    return {
        "p_ca": hit / len(true_pairs) if true_pairs else 1.0,
        "p_fa": (len(out_pairs) - hit) / len(out_pairs) if out_pairs else 0.0,
        "out_pairs": len(out_pairs),
        "true_pairs": len(true_pairs),
    }


def consecutive_true_pairs(truth: np.ndarray, t0: np.ndarray) -> set:
    """True (old, new) pairs: each ship's segments in time order, one pair per step."""
    order = np.lexsort((t0, truth))
    same = truth[order][1:] == truth[order][:-1]
    return set(zip(order[:-1][same].tolist(), order[1:][same].tolist(), strict=True))


def cluster_scores(labels: np.ndarray, truth: np.ndarray) -> dict:
    """Target-level (seed 001) and pairwise precision, recall and F1 of a clustering."""
    df = pd.DataFrame({"c": pd.factorize(labels)[0], "t": pd.factorize(truth)[0]})
    n_c = df.groupby("c").size()
    n_t = df.groupby("t").size()
    n_ct = df.groupby(["c", "t"]).size()
    # A cluster is a correct target when it holds one ship and all of that ship's segments.
    pure = n_ct.reset_index(name="n")
    pure = pure[(pure["n"].to_numpy() == n_c.loc[pure["c"]].to_numpy())]
    correct = int((pure["n"].to_numpy() == n_t.loc[pure["t"]].to_numpy()).sum())
    p = correct / len(n_c) if len(n_c) else 1.0
    r = correct / len(n_t) if len(n_t) else 1.0

    def pairs(counts: pd.Series) -> float:
        v = counts.to_numpy(dtype="float64")
        return float((v * (v - 1) / 2).sum())

    tp, same_c, same_t = pairs(n_ct), pairs(n_c), pairs(n_t)
    pp = tp / same_c if same_c else 1.0
    pr = tp / same_t if same_t else 1.0
    return {
        "precision": p,
        "recall": r,
        "f1": _f1(p, r),
        "pair_precision": pp,
        "pair_recall": pr,
        "pair_f1": _f1(pp, pr),
        "targets_out": len(n_c),
        "targets_true": len(n_t),
    }


def score_association(assoc, truth_column: str = "truth") -> dict:
    """All scores of an :class:`~wakeline.core.associate.Association` whose points carry
    the true ship in ``truth_column``."""
    seg = assoc.segments
    truth = seg.points[truth_column].astype(str).to_numpy()[seg.index.starts]
    out = set(
        zip(assoc.pairs.i[assoc.chosen].tolist(), assoc.pairs.j[assoc.chosen].tolist(), strict=True)
    )
    return {
        **cluster_scores(assoc.target_of_track, truth),
        **pair_scores(out, consecutive_true_pairs(truth, seg.t0)),
    }


#: Scene classes: (ships, area side km, position noise m)
SCENES = {
    "sparse": (20, 60.0, 30.0),
    "dense": (80, 20.0, 30.0),
    "very dense": (250, 20.0, 60.0),
}

#: Method label -> (mode, method, normalize, params changes)
METHODS = {
    "ours, optimal": ("interrupted", "optimal", "scaled", {}),
    "ours, greedy": ("interrupted", "greedy", "scaled", {}),
    "ours, clustering": ("segments", "motion", "", {}),
    "ours, no dead reckoning": ("interrupted", "optimal", "scaled", {"predict": False}),
    "seed 003 (min-max, greedy)": (
        "interrupted",
        "greedy",
        "minmax",
        {"predict": False, "gate": 1.0},
    ),
    "seed 001 S+LDM+σ": ("segments", "area", "", {}),
    "S+DTW+σ": ("segments", "dtw", "", {}),
    "S+Hausdorff+σ": ("segments", "hausdorff", "", {}),
}


def run_method(points: pd.DataFrame, label: str, params: LinkParams | None = None):
    """Run one of :data:`METHODS` on ``points``."""
    mode, method, normalize, changes = METHODS[label]
    params = (params or LinkParams()).replace(**changes)
    if mode == "interrupted":
        return associate_interrupted(points, params, method=method, normalize=normalize)
    return associate_segments(points, params, method=method)


@dataclass(frozen=True)
class AssociationEvaluation:
    """Mean scores per (scene class, method) over ``scenes`` seeds."""

    table: pd.DataFrame
    scenes: int
    seed: int

    def format(self) -> str:
        cols = ["precision", "recall", "f1", "pair_f1", "p_ca", "p_fa"]
        lines = [
            f"Single-sensor association, {self.scenes} simulated scenes per class "
            f"(seed {self.seed}; 2 h, one radar, period 10 s, each ship broken into 2-4 batches "
            "by gaps of 20 s-10 min)",
            "",
            f"{'scene':<11} {'method':<28} {'P':>6} {'R':>6} {'F1':>6} {'pairF1':>7} "
            f"{'P_CA':>6} {'P_FA':>6} {'segments':>8}",
        ]
        for _, row in self.table.iterrows():
            vals = " ".join(f"{row[c]:{7 if c == 'pair_f1' else 6}.3f}" for c in cols)
            lines.append(f"{row['scene']:<11} {row['method']:<28} {vals} {row['segments']:8.0f}")
        lines += ["", "Seed 001 Table 3 (its real radar data, target level):"]
        for name, (p, r, f) in SEED001_TABLE3.items():
            lines.append(f"  {name:<24} P {p:.4f}  R {r:.4f}  F1 {f:.4f}")
        return "\n".join(lines)


def evaluate_association(
    scenes: int = 5,
    seed: int = 0,
    params: LinkParams | None = None,
    methods: tuple[str, ...] = tuple(METHODS),
    progress: Progress | None = None,
) -> AssociationEvaluation:
    """Every method of :data:`METHODS` on ``scenes`` seeded scenes of each class."""
    progress = progress or null_progress
    rows = []
    total = len(SCENES) * scenes
    done = 0
    for name, (ships, area, sigma) in SCENES.items():
        for k in range(scenes):
            progress(done / total, f"{name} scene {k + 1}/{scenes}")
            df = simulate.segments_scene(seed=seed + k, n_ships=ships, area_km=area, sigma_m=sigma)
            for label in methods:
                sc = score_association(run_method(df, label, params))
                rows.append({"scene": name, "method": label, "seed": seed + k, **sc})
            done += 1
    full = pd.DataFrame(rows)
    segs = full.assign(segments=full["true_pairs"] + full["targets_true"])
    table = (
        segs.groupby(["scene", "method"], sort=False)
        .mean(numeric_only=True)
        .reset_index()
        .drop(columns=["seed"])
    )
    progress(1.0, "done")
    return AssociationEvaluation(table, scenes, seed)


def cut_at_gaps(
    points: pd.DataFrame,
    min_gap_s: float,
    factor: float = 4.0,
    truth_column: str = "truth",
    seed: int = 0,
) -> pd.DataFrame:
    """Real data made into an association test: each track is cut where the time step
    exceeds ``min_gap_s`` and ``factor`` × the track's median step; the old batch becomes
    the truth (``truth_column``, unless the table has one) and the pieces get shuffled
    numbers, so batch ids leak nothing."""
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import sort_points, track_index

    df = sort_points(points).copy()
    index = track_index(df)
    t = time_seconds(df["time"])
    step = np.diff(t, prepend=np.nan)
    step[index.starts] = np.nan
    median = pd.Series(step).groupby(index.track_of_row).transform("median").to_numpy()
    new = index.first_of_track() | (step > np.maximum(min_gap_s, factor * median))
    piece = np.cumsum(new) - 1
    if truth_column not in df.columns:
        df[truth_column] = df["batch"].astype(str)
    perm = np.random.default_rng(seed).permutation(int(piece.max()) + 1 if len(piece) else 0)
    df["batch"] = perm[piece].astype(str)
    return df

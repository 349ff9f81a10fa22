"""Seed 000's compression at equal points kept: the compressor against Douglas–Peucker
keeping the SAME number of points per track.

``wakeline evaluate maneuver --tracks 100 --seed S`` compares the compressor (the maneuver
points, least-squares vertices: "PCA + LS vertices") with Douglas–Peucker at a tolerance of
2 sigma, which keeps about three times as many points; a setting that keeps fewer turn
points raises the compressor's Dis_e for that reason alone. Here Douglas–Peucker keeps, on
every track, as many points as the compressor does (:func:`douglas_peucker_count_mask`),
and the ratio compressor Dis_e / Douglas–Peucker Dis_e is printed, against the true path
and against the observed points (a lower ratio: the compressor is better for its points).
The same tracks, the same simulation seeds (``seed + 1000 k``) as the evaluation's table.

Run: ``python bench/seed000_equal_points.py [--seed 0] [--tracks 100] [--set k=v ...]``
(``--set``: one more row per case, the defaults with these ``ManeuverParams`` changes).
"""

import argparse

import numpy as np

from wakeline.core import simulate
from wakeline.core.compress import compress_with, douglas_peucker_count_mask
from wakeline.core.evaluate import match_turns
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.tracks import local_xy


def case(n_tracks: int, cls: str, sigma: float, seed: int, params: ManeuverParams) -> dict:
    """One seed-000 case (class, sigma): points kept, P/R/F1 and the equal-points Dis_e."""
    df = simulate.maneuver_tracks(n_tracks, cls, sigma, seed=seed)
    result = detect(df, params)
    pts, index = result.points, result.index
    mask = result.is_maneuver.copy()
    mask[index.starts] = True
    mask[index.ends - 1] = True
    k = np.bincount(index.track_of_row[mask], minlength=index.n_tracks)
    x, y = local_xy(pts, index)
    dp = douglas_peucker_count_mask(x, y, index, k)
    ours = compress_with(None, mask, refine=True, sorted_points=pts).report()["overall"]
    raw = compress_with(None, mask, refine=False, sorted_points=pts).report()["overall"]
    base = compress_with(None, dp, refine=False, sorted_points=pts).report()["overall"]
    inner = result.is_maneuver.copy()
    inner[index.starts] = False
    inner[index.ends - 1] = False
    truth = pts["true_turn"].to_numpy() == 1
    return {
        "kept": int(mask.sum()),
        "dp_kept": int(dp.sum()),
        "share": mask.sum() / len(mask),
        **match_turns(inner, truth, index.track_of_row),
        "ls_true": ours["dis_e_true_m"],
        "ls_obs": ours["dis_e_m"],
        "raw_true": raw["dis_e_true_m"],
        "dp_true": base["dis_e_true_m"],
        "dp_obs": base["dis_e_m"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tracks", type=int, default=100)
    ap.add_argument("--set", nargs="*", metavar="KEY=VALUE", help="ManeuverParams changes")
    args = ap.parse_args()
    variants = {"default": ManeuverParams()}
    if args.set:
        base = ManeuverParams()
        changes = {}
        for k, v in (item.split("=", 1) for item in args.set):
            kind = type(getattr(base, k))
            changes[k] = v.lower() in ("true", "1") if kind is bool else kind(float(v))
        variants[" ".join(args.set)] = base.replace(**changes).checked()
    print(
        f"Seed 000 at equal points kept (seed {args.seed}, {args.tracks} tracks per class): "
        "the compressor (PCA + LS vertices) against Douglas-Peucker keeping as many points "
        "per track; Dis_e in metres, ratio = compressor / DP."
    )
    print(
        f"{'sigma':>5} {'class':7} {'variant':32} {'kept':>6} {'share':>6} {'P/R/F1':>15} "
        f"{'LS true':>8} {'DP true':>8} {'ratio':>6} {'LS obs':>7} {'DP obs':>7} {'ratio':>6} "
        f"{'raw true':>8}"
    )
    cases = [(s, c) for s in (300.0, 600.0) for c in ("short", "medium", "long")]
    for k, (sigma, cls) in enumerate(cases):  # the evaluation's seeds: seed + 1000 k
        for name, params in variants.items():
            r = case(args.tracks, cls, sigma, args.seed + 1000 * k, params)
            assert r["kept"] == r["dp_kept"]
            prf = f"{r['precision']:.2f}/{r['recall']:.2f}/{r['f1']:.2f}"
            print(
                f"{sigma:5.0f} {cls:7} {name:32} {r['kept']:>6} {r['share']:6.3f} {prf:>15} "
                f"{r['ls_true']:8.1f} {r['dp_true']:8.1f} {r['ls_true'] / r['dp_true']:6.3f} "
                f"{r['ls_obs']:7.1f} {r['dp_obs']:7.1f} {r['ls_obs'] / r['dp_obs']:6.3f} "
                f"{r['raw_true']:8.1f}"
            )


if __name__ == "__main__":
    main()

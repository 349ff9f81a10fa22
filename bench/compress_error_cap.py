"""Compression against Douglas–Peucker with the error bound capped (operator test 7, D9).

    python bench/compress_error_cap.py [--sets saronic ...] [--caps 0 200 500 1000 2000]

Issue 15's goal 2b (ours keeps no more points than Douglas–Peucker at the same Dis_e) as
``wakeline evaluate maneuver --real`` measures it (:func:`compression_against_dp`, the
detector's defaults, on the raw points of bench/real_set_points.py), once per
``compress.error_cap_m`` (0 = no cap, the default): ours kept / Dis_e, DP kept at the same
Dis_e, whether 2b holds, the farthest point from our compressed track, and the error
bound's median and largest over the tracks (with the number of tracks the cap lowered).

    python bench/compress_error_cap.py --seed000 [--caps ...]

Seed 000's protocol instead (the tracks of ``wakeline evaluate maneuver --tracks 100 --seed
0``): that command's tables compress to the maneuver points alone and do not use the error
bound, so this prints what ``wakeline compress``'s defaults (turning_keep: the bound on)
give on the same tracks per cap: share kept, Dis_e against the true path and the observed.
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from real_set_points import SETS, set_points  # noqa: E402

from wakeline.core.compress import (  # noqa: E402
    CompressParams,
    compress_with,
    error_bounds,
    turning_keep,
)
from wakeline.core.evaluate_real import compression_against_dp  # noqa: E402
from wakeline.core.maneuver import ManeuverParams, detect  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sets", nargs="+", default=[s for s in SETS if s != "atd_dataset1"])
    ap.add_argument("--caps", nargs="+", type=float, default=[0, 200, 500, 1000, 2000])
    ap.add_argument("--seed000", action="store_true", help="seed 000's simulated tracks")
    args = ap.parse_args()
    if args.seed000:
        return seed000(args.caps)
    print(
        "set           cap_m  ours_kept  ours_dis_e   dp_kept  dp_dis_e  2b  ours_max_err  "
        "tol_median  tol_max  capped"
    )
    for name in args.sets:
        res = detect(set_points(name), ManeuverParams())
        for cap in args.caps:
            cp = CompressParams(error_cap_m=cap)
            comp = compression_against_dp(res, cp)
            own = compress_with(
                None, turning_keep(res, cp), refine=cp.refine, sorted_points=res.points
            ).report()["overall"]
            b = error_bounds(res, cp)
            capped = int((cp.error_sigmas * b["noise_m"] > b["error_tol_m"] + 1e-9).sum())
            ok = "yes" if comp["ours_kept"] <= comp["dp_kept"] else "NO"
            print(
                f"{name:<13} {cap:5g} {comp['ours_kept']:10,} {comp['ours_dis_e_m']:11.1f} "
                f"{comp['dp_kept']:9,} {comp['dp_dis_e_m']:9.1f} {ok:>3} "
                f"{own['max_error_m']:13,.0f} {b['error_tol_m'].median():11,.0f} "
                f"{b['error_tol_m'].max():8,.0f} {capped:7,}",
                flush=True,
            )


def seed000(caps: list[float]) -> None:
    from wakeline.core import simulate

    print("sigma class    cap_m  kept_share  dis_e_true  dis_e_obs  max_err")
    k = 0
    for sigma in (300.0, 600.0):
        for cls in ("short", "medium", "long"):
            df = simulate.maneuver_tracks(100, cls, sigma, seed=0 + 1000 * k)
            k += 1
            res = detect(df, ManeuverParams())
            for cap in caps:
                cp = CompressParams(error_cap_m=cap)
                o = compress_with(
                    None, turning_keep(res, cp), refine=cp.refine, sorted_points=res.points
                ).report()["overall"]
                print(
                    f"{sigma:5g} {cls:<7} {cap:6g} {o['ratio']:11.3f} {o['dis_e_true_m']:11.1f} "
                    f"{o['dis_e_m']:10.1f} {o['max_error_m']:8,.0f}",
                    flush=True,
                )


if __name__ == "__main__":
    main()

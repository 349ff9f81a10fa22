"""Compression against Douglas–Peucker with the error bound capped (operator test 7, D9).

    python bench/compress_error_cap.py [--sets saronic ...] [--caps 0 200 500 1000 2000]

Issue 15's goal 2b (ours keeps no more points than Douglas–Peucker at the same Dis_e) as
``wakeline evaluate maneuver --real`` measures it (:func:`compression_against_dp`, the
detector's defaults, on the raw points of bench/real_set_points.py), once per
``compress.error_cap_m`` (0 = no cap, the default): ours kept / Dis_e, DP kept at the same
Dis_e, whether 2b holds, the farthest point from our compressed track, and the error
bound's median and largest over the tracks (with the number of tracks the cap lowered).
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
    args = ap.parse_args()
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


if __name__ == "__main__":
    main()

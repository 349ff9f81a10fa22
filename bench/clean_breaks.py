"""The speed rule's breaks on the real sets, and what ``speed.split_at_breaks`` would change
(operator test 7, D3).

    python bench/clean_breaks.py [--sets saronic dma ...] [--legs 20]

For each set (bench/real_set_points.py) cleaned with the defaults: the breaks (an impossible
leg followed by plausible ones), the splits (jumps beyond split_factor and split_km), and
the impossible legs left inside a track, each listed (track, time, km, s, kn). Then the same
with ``speed.split_at_breaks=true``: tracks out, splits, impossible legs left (0 expected),
points kept and whether the kept points are the same rows at the same places.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from real_set_points import SETS, set_points  # noqa: E402

from wakeline.core import geo  # noqa: E402
from wakeline.core.clean import CleanParams, clean  # noqa: E402
from wakeline.core.schema import time_seconds  # noqa: E402
from wakeline.core.tracks import sort_points  # noqa: E402


def impossible_legs(points, sp) -> int:
    """Legs between consecutive output points of one track beyond v_max · dt + tolerance."""
    pts = sort_points(points)
    t = time_seconds(pts["time"])
    lon, lat = pts["lon"].to_numpy(), pts["lat"].to_numpy()
    key = pts["sensor"].astype(str) + "\x1f" + pts["batch"].astype(str)
    same = key.to_numpy()[1:] == key.to_numpy()[:-1]
    d = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])
    return int((same & (d > sp.v_max_kn * geo.KN_MS * np.diff(t) + sp.tolerance_m)).sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sets", nargs="+", default=list(SETS), choices=list(SETS))
    ap.add_argument("--legs", type=int, default=20, help="kept legs listed per set")
    ap.add_argument(
        "--set",
        nargs="+",
        default=["speed.split_at_breaks=true"],
        help="the settings compared with the defaults (default: speed.split_at_breaks=true)",
    )
    args = ap.parse_args()
    on = CleanParams().with_settings(args.set)
    for name in args.sets:
        pts = set_points(name)
        base = clean(pts)
        sp = base.report["rules"]["speed"]
        legs = sp["break_legs"]
        print(
            f"{name}: {base.report['points_in']:,} points, {base.report['tracks_in']:,} tracks; "
            f"default: kept {base.report['points_out']:,}, tracks out {base.report['tracks_out']:,}, "
            f"speed removed {sp['removed']:,}, breaks {sp['breaks']}, splits {sp['splits']}, "
            f"impossible legs kept {sp['breaks_kept']} (all legs checked: "
            f"{impossible_legs(base.points, CleanParams().speed)})"
        )
        for leg in legs[: args.legs]:
            print(
                f"    {leg['sensor']}:{leg['batch']} {leg['from_time']} -> {leg['time']}: "
                f"{leg['km']:.3f} km in {leg['s']:g} s, {leg['kn']} kn"
            )
        split = clean(pts, on)
        s2 = split.report["rules"]["speed"]
        same_rows = np.array_equal(
            np.sort(base.points["wl_id"].to_numpy()), np.sort(split.points["wl_id"].to_numpy())
        )
        moved = same_rows and not (
            base.points.sort_values("wl_id")[["lon", "lat", "time"]].reset_index(drop=True)
        ).equals(split.points.sort_values("wl_id")[["lon", "lat", "time"]].reset_index(drop=True))
        print(
            f"  {' '.join(args.set)}: kept {split.report['points_out']:,}, tracks out "
            f"{split.report['tracks_out']:,} ({split.report['tracks_out'] - base.report['tracks_out']:+,}), "
            f"splits {s2['splits']} ({s2['splits'] - sp['splits']:+}), impossible legs left "
            f"{impossible_legs(split.points, CleanParams().speed)}; same rows kept {same_rows}"
            f"{', moved' if moved else ''}; identical output "
            f"{base.points.equals(split.points)}"
        )


if __name__ == "__main__":
    main()

"""Where the slow maneuver points of a real AIS file come from (issue 15 goal 1; ATD 2025).

    python bench/slow_maneuvers.py                        # ATD example_truth (the tuning file)
    python bench/slow_maneuvers.py FILE [--map k=col ...]
    python bench/slow_maneuvers.py --max-step-windows 0   # headings across any step (before)

For the detector with sparse stays off (``rest_steps=0``, the rule before session 18) and on (the
default), the maneuver points and the goal's slow share (speed over the chord from the fix
before to the fix after, as ``wakeline evaluate maneuver --real`` counts it), split by what
the two legs show: at rest or crawling (the legs together slower than 1 kn), or a reversal
of a ship under way (each leg at least 1 kn: the chord over two legs 30 min each is no
speed there). With the file's reported SOG when it has one. Also the maneuvers the change
removes, and whether the reported course changed by more than 15 deg between the fixes
either side (where SOG is at least 1 kn at both: a rough check, random fixes 30 min apart
show it half the time). Last, the position noise: the distance between consecutive posits
that both report SOG 0.
"""

import argparse
import os
from pathlib import Path

import numpy as np

from wakeline.core import geo
from wakeline.core.evaluate_real import _speed_either_side_kn, _track_files
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.tracks import local_xy, track_seconds

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
DEFAULT = SHARED / "data" / "real" / "atd2025-noaa" / "example_truth.csv.gz"


def legs_kn(x, y, t, index, rows):
    """Speed (kn) of the leg into and out of each row (NaN at a track's ends)."""
    tr = index.track_of_row[rows]
    ok = (rows - 1 >= index.starts[tr]) & (rows + 1 < index.ends[tr])
    a, b = np.clip(rows - 1, 0, len(x) - 1), np.clip(rows + 1, 0, len(x) - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        into = np.hypot(x[rows] - x[a], y[rows] - y[a]) / (t[rows] - t[a]) / geo.KN_MS
        out = np.hypot(x[b] - x[rows], y[b] - y[rows]) / (t[b] - t[rows]) / geo.KN_MS
        both = (
            (np.hypot(x[rows] - x[a], y[rows] - y[a]) + np.hypot(x[b] - x[rows], y[b] - y[rows]))
            / (t[b] - t[a])
            / geo.KN_MS
        )
    nan = np.nan
    return np.where(ok, into, nan), np.where(ok, out, nan), np.where(ok, both, nan)


def course_change(pts, index, rows):
    """|reported course after − before| (deg) where SOG ≥ 1 kn at both fixes, else NaN."""
    if "course" not in pts or "speed" not in pts:
        return np.full(len(rows), np.nan)
    cog, sog = pts["course"].to_numpy(float), pts["speed"].to_numpy(float)
    tr = index.track_of_row[rows]
    ok = (rows - 1 >= index.starts[tr]) & (rows + 1 < index.ends[tr])
    a, b = np.clip(rows - 1, 0, len(cog) - 1), np.clip(rows + 1, 0, len(cog) - 1)
    ok &= (sog[a] >= 1) & (sog[b] >= 1)
    return np.where(ok, np.abs((cog[b] - cog[a] + 180) % 360 - 180), np.nan)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", default=str(DEFAULT))
    ap.add_argument("--map", nargs="*", default=None)
    ap.add_argument(
        "--max-step-windows",
        type=float,
        default=ManeuverParams().max_step_windows,
        help="the detector's max_step_windows (0 = headings across any step, as before)",
    )
    args = ap.parse_args()
    pts = _track_files(Path(args.file), args.map)
    results = {
        s: detect(pts, ManeuverParams(rest_steps=s, max_step_windows=args.max_step_windows))
        for s in (0.0, 1.0)
    }
    for steps, res in results.items():
        p, index = res.points, res.index
        x, y = local_xy(p, index)
        t = track_seconds(p)
        rows = np.flatnonzero(res.is_maneuver)
        chord = _speed_either_side_kn(p, index)[rows]
        into, out, both = legs_kn(x, y, t, index, rows)
        slow = chord < 1
        n = max(len(rows), 1)
        stop = slow & (both < 1)
        reversal = slow & (into >= 1) & (out >= 1)
        line = (
            f"rest_steps={steps:g}: {len(rows)} maneuvers, slow (chord) {slow.sum()} "
            f"= {slow.sum() / n:.3f}; of these at rest or crawling (legs < 1 kn) {stop.sum()}, "
            f"reversals under way (each leg >= 1 kn) {reversal.sum()}, other "
            f"{(slow & ~stop & ~reversal).sum()}; slow without the reversals "
            f"{(slow & ~reversal).sum() / n:.3f}; at-rest fixes {int(res.at_rest.sum())}"
        )
        if "speed" in p:
            sog = p["speed"].to_numpy(float)[rows]
            line += f"; reported SOG < 1 kn at the point {(sog < 1).sum()} = {(sog < 1).mean():.3f}"
        print(line)
    before, after = results[0.0], results[1.0]
    gone = np.flatnonzero(before.is_maneuver & ~after.is_maneuver)
    kept = np.flatnonzero(before.is_maneuver & after.is_maneuver)
    for label, rows in (("removed by rest_steps=1", gone), ("kept", kept)):
        d = course_change(before.points, before.index, rows)
        defined = np.isfinite(d)
        share = (d[defined] > 15).mean() if defined.any() else float("nan")
        print(
            f"{label}: {len(rows)}; reported course change > 15 deg between the fixes either side "
            f"{int((d[defined] > 15).sum())} of {int(defined.sum())} with SOG >= 1 kn ({share:.2f})"
        )
    if "speed" in pts:  # the noise: consecutive posits of a ship that reports SOG 0 at both
        p, index = before.points, before.index
        x, y = local_xy(p, index)
        t = track_seconds(p)
        sog = p["speed"].to_numpy(float)
        tr = index.track_of_row
        still = (tr[1:] == tr[:-1]) & (sog[1:] == 0) & (sog[:-1] == 0)
        dt, d = np.diff(t), np.hypot(np.diff(x), np.diff(y))
        for lo, hi in ((0, 300), (1500, 2100)):
            k = still & (dt >= lo) & (dt < hi)
            if k.any():
                med = float(np.median(d[k]))
                # Rayleigh: median sqrt(2 ln 2) * sigma * sqrt(2) for two fixes' difference
                sigma = med / np.sqrt(2 * np.log(2)) / np.sqrt(2)
                print(
                    f"both SOG 0, {lo}-{hi} s apart: {int(k.sum())} pairs, distance median "
                    f"{med:.0f} m, 90 % {np.percentile(d[k], 90):.0f} m, sigma per axis {sigma:.0f} m"
                )


if __name__ == "__main__":
    main()

"""Speeds whose header names no unit, checked against the speed the positions give
(operator test 6, D-import-14): a console writing km/h under ``航速`` is read as knots
without a word, although its speeds are 1.852 times what the positions show.

The check is per file (MTAD mixes units between tracks, so a per-row rule would fire on
real data): the median, over moving rows, of the speed column over the speed from the
previous position on the same track. A median near one unit's factor names that unit and
the flag that reads it. Vectorized: one sort, then whole-column differences.
"""

import numpy as np
import pandas as pd

#: What every warning of :func:`speed_unit_warnings` holds (a read in pieces says it once).
SPEED_UNIT_MARK = ", not knots: over "
#: (factor a speed in this unit read as knots is of the true speed, unit, --speed-unit)
LIKELY_UNITS = (
    (1852.0 / 1000.0, "km/h", "km/h"),  # 1.852
    (1852.0 / 3600.0, "m/s", "m/s"),  # 0.514
    (1852.0 / 1609.344, "mph", "mph"),  # 1.151
)
#: How far (relative) the median ratio may lie from a unit's factor: mph's 1.151 is 15 %
#: from knots' 1.0, so 5 % keeps every unit apart from knots and from the others.
TOLERANCE = 0.05
#: Standard errors of the median that must part the likely unit from knots (and from the
#: next unit): mph's 1.151 is 0.14 from knots in log, so a noisy file's 1.13 is no mph.
SURE = 3.0
#: Rows it takes before the median is trusted.
MIN_ROWS = 20
#: Consecutive rows of a track further apart than this are not compared (a gap).
MAX_SPAN_S = 600.0
#: Moving: the positions say more than this many knots.
MOVING_KN = 2.0
_EARTH_M = 6371008.8


def speed_ratio(points: pd.DataFrame) -> tuple[float, int]:
    """(median over moving rows of the speed column over the speed from the previous
    position of the track, rows compared, the standard error of the median's log) over the
    moving rows of ``points`` (the canonical table: sensor, batch, time, lon, lat,
    speed in knots as read); (nan, 0) when nothing compares."""
    need = ("batch", "time", "lon", "lat", "speed")
    if len(points) < 2 or any(c not in points.columns for c in need):
        return float("nan"), 0, float("inf")
    keys = [points["sensor"]] if "sensor" in points.columns else []
    keys.append(points["batch"])
    track = np.zeros(len(points), dtype="int64")
    for k in keys:
        codes, uniques = pd.factorize(k.astype(str), sort=False)
        track = track * max(len(uniques), 1) + codes
    t = pd.to_datetime(points["time"], utc=True)
    secs = (t - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds().to_numpy()
    lon = points["lon"].to_numpy(dtype="float64")
    lat = points["lat"].to_numpy(dtype="float64")
    speed = pd.to_numeric(points["speed"], errors="coerce").to_numpy(dtype="float64")
    ok = np.isfinite(secs) & np.isfinite(lon) & np.isfinite(lat) & np.isfinite(speed)
    if ok.sum() < 2:
        return float("nan"), 0, float("inf")
    track, secs, lon, lat, speed = track[ok], secs[ok], lon[ok], lat[ok], speed[ok]
    order = np.lexsort((secs, track))
    track, secs, lon, lat, speed = (a[order] for a in (track, secs, lon, lat, speed))
    # the next row of the same track: a console's speed column is often the speed from
    # the previous position (MTAD's scenes: exactly), noise and all, so the positions are
    # compared pair by pair, not over a longer baseline that averages their noise away
    same = (track[1:] == track[:-1]) & (np.diff(secs) > 0) & (np.diff(secs) <= MAX_SPAN_S)
    dt = np.diff(secs)
    la0, la1 = np.radians(lat[:-1]), np.radians(lat[1:])
    dlon = np.radians(((lon[1:] - lon[:-1] + 180.0) % 360.0) - 180.0)
    dist = np.hypot(dlon * np.cos((la0 + la1) / 2.0), la1 - la0) * _EARTH_M
    with np.errstate(divide="ignore", invalid="ignore"):
        derived = dist / dt * 3600.0 / 1852.0
        ratio = speed[1:] / derived
    use = same & (derived > MOVING_KN) & (speed[1:] > 0) & np.isfinite(ratio)
    n = int(use.sum())
    if n < MIN_ROWS:
        return float("nan"), n, float("inf")
    logs = np.log(ratio[use])
    q1, med, q3 = np.percentile(logs, [25, 50, 75])
    # the median's standard error (normal: 1.253 sigma / sqrt n, sigma from the IQR)
    return float(np.exp(med)), n, float(1.253 * (q3 - q1) / 1.349 / np.sqrt(n))


def likely_unit(ratio: float, spread: float = 0.0) -> tuple[str, str, float] | None:
    """(unit, --speed-unit value, its factor) whose factor ``ratio`` lies within
    :data:`TOLERANCE` of, while knots' 1.0 lies more than :data:`SURE` standard errors
    (``spread``, of the log median) from it and every other unit's factor further than
    its own; None near knots, between units or at any other ratio."""
    if not np.isfinite(ratio) or ratio <= 0 or not np.isfinite(spread):
        return None
    off = np.log(ratio)
    if abs(off) <= SURE * spread:  # knots not ruled out (a noisy radar's speeds)
        return None
    near = sorted(
        (abs(off - np.log(factor)), factor, unit, flag) for factor, unit, flag in LIKELY_UNITS
    )
    gap, factor, unit, flag = near[0]
    if gap > np.log1p(TOLERANCE) or near[1][0] <= SURE * spread:
        return None
    return unit, flag, factor


def speed_unit_warnings(points: pd.DataFrame, header: str | None, read_as: str) -> list[str]:
    """A warning when the speeds in ``header`` (read as knots: no unit in the header, none
    given) look like another unit by :func:`speed_ratio`; [] otherwise."""
    if not header or read_as != "knots":
        return []
    ratio, n, spread = speed_ratio(points)
    found = likely_unit(ratio, spread)
    if found is None:
        return []
    unit, flag, factor = found
    return [
        f"the speeds in {header!r} look like {unit}, not knots: over {n:,} moving rows they "
        f"are a median {ratio:.2f} times the speed the positions show (a speed in {unit} "
        f"read as knots is {factor:.3f} times it); if they are {unit}, read them with "
        f"--speed-unit {flag}"
    ]

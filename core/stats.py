"""Figures of a layer's point table for the Statistics panel (SPEC §7; seed 003's
auxiliary panel): tracks per sensor, targets, track lifetimes, points per track, spatial
extent, sampling interval per sensor, time span, at-rest spans and maneuvers.

One pure function, :func:`layer_stats`, vectorized over all points (per-track figures from
``reduceat`` over the track runs; per-sensor medians from one sort): no Python loop per
point or per track. It never imports Qt; the window calls it in a worker thread.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.tracks import run_medians, sorted_with_index, track_seconds

#: Bins of the lifetime histogram.
HIST_BINS = 20
#: Cells along the longer side of the extent's box in the "area covered" grid.
GRID_CELLS = 100
#: km per degree of latitude (spherical Earth of :data:`~wakeline.core.geo.EARTH_RADIUS_M`).
KM_PER_DEG = geo.EARTH_RADIUS_M * geo.DEG_TO_RAD / 1000.0


@dataclass(frozen=True)
class Spread:
    """min / median / 90th percentile / max of a per-track figure (its unit: the field
    it is kept in says)."""

    min: float
    median: float
    p90: float
    max: float

    @classmethod
    def of(cls, values: np.ndarray) -> "Spread":
        v = np.asarray(values, dtype="float64")
        v = v[np.isfinite(v)]
        if not len(v):
            return cls(np.nan, np.nan, np.nan, np.nan)
        lo, med, p90, hi = np.percentile(v, [0, 50, 90, 100])
        return cls(float(lo), float(med), float(p90), float(hi))


@dataclass(frozen=True)
class Extent:
    """The points' lon/lat box (degrees), its size (km) and the area the tracks cover:
    ``covered_km2`` is the area of the grid cells (``cell_km`` a side, about
    :data:`GRID_CELLS` along the box's longer side) holding at least one point. A box
    across ±180° runs east from ``lon_min`` to ``lon_max`` < ``lon_min``."""

    lon_min: float
    lon_max: float
    lat_min: float
    lat_max: float
    width_km: float  # east-west, along the box's middle latitude
    height_km: float  # north-south
    box_km2: float
    covered_km2: float
    cell_km: float


@dataclass(frozen=True)
class LayerStats:
    """What :func:`layer_stats` found. Durations in seconds, times as seconds since
    1970-01-01 UTC (the layers' clock), distances in km."""

    points: int
    tracks: int
    #: One row per sensor: ``sensor``, ``tracks``, ``points``, ``interval_s`` (median
    #: sampling interval of the sensor's steps forward in time; NaN with none).
    sensors: pd.DataFrame
    #: Distinct target ids, or None when the layer has none (only associated, fused and
    #: reviewed layers do); ``target_source`` says where they were read.
    targets: int | None
    target_source: str
    lifetime_s: Spread
    #: The lifetime histogram: ``HIST_BINS + 1`` edges (s) and the tracks in each bin.
    hist_edges_s: np.ndarray
    hist_counts: np.ndarray
    points_per_track: Spread
    extent: Extent | None
    start_s: float
    end_s: float
    #: At-rest spans of a cleaned layer (its ``at_rest`` table): count, total and median
    #: duration (s); None when the layer has no such table.
    at_rest: dict | None = None
    #: Maneuver points (an ``is_maneuver`` column): count and tracks with at least one;
    #: None when the layer has no such column.
    maneuvers: dict | None = None
    #: Rows the time window kept (None: no window).
    window: tuple[float, float] | None = None

    @property
    def span_s(self) -> float:
        return self.end_s - self.start_s


def _targets(pts: pd.DataFrame) -> tuple[int | None, str]:
    """Distinct target ids: the ``target`` column (associated layers), or one target per
    track where each track is a target's (fused and reviewed layers: a ``members``
    column lists each target's tracks)."""
    if "target" in pts.columns:
        col = pts["target"]
        return int(col.nunique(dropna=True)), "target"
    if "members" in pts.columns:
        return int(pts["batch"].nunique(dropna=True)), "members"
    return None, ""


def _extent(lon: np.ndarray, lat: np.ndarray) -> Extent | None:
    ok = np.isfinite(lon) & np.isfinite(lat)
    if not ok.any():
        return None
    lon, lat = lon[ok], lat[ok]
    if lon.max() - lon.min() > 180.0:  # perhaps across ±180°: the shortest arc holding all
        s = np.unique(lon)
        gaps = np.diff(s)
        i = int(np.argmax(gaps))
        if gaps[i] > s[0] + 360.0 - s[-1]:  # the widest empty arc is inside, not at ±180°
            lon = np.where(lon >= s[i + 1], lon, lon + 360.0)  # east of it, continuous
    x0, x1, y0, y1 = float(lon.min()), float(lon.max()), float(lat.min()), float(lat.max())
    coslat = np.cos(0.5 * (y0 + y1) * geo.DEG_TO_RAD)
    width = float((x1 - x0) * KM_PER_DEG * coslat)
    height = float((y1 - y0) * KM_PER_DEG)
    side = max(width, height)
    cell = side / GRID_CELLS if side > 0 else 0.0
    if cell > 0:
        # A round cell size (1, 2 or 5 × 10^k km), so that the figure reads plainly.
        mag = 10.0 ** np.floor(np.log10(cell))
        cell = float(mag * next(m for m in (1, 2, 5, 10) if m * mag >= cell))
        ix = np.floor((lon - x0) * KM_PER_DEG * coslat / cell).astype("int64")
        iy = np.floor((lat - y0) * KM_PER_DEG / cell).astype("int64")
        # Distinct cells by a mask over the few cell numbers (~100 x 100), not np.unique
        # (numpy 2.4 hashes: 1M points 80-1,060 ms against ~1 ms, holding the GIL).
        code = ix * (int(iy.max()) + 1) + iy
        seen = np.zeros(int(code.max()) + 1, dtype=bool)
        seen[code] = True
        cells = int(np.count_nonzero(seen))
        # Cells on the box's east and north edges reach past it: never more than the box.
        covered = min(cells * cell * cell, width * height)
    else:
        covered = 0.0
    if x1 > 180.0:  # across ±180°: the east bound is given as it reads (x1 < x0)
        x1 -= 360.0
    return Extent(x0, x1, y0, y1, width, height, width * height, float(covered), cell)


def _median_by_group(code: np.ndarray, values: np.ndarray, n_groups: int) -> np.ndarray:
    """Median of ``values`` per group code 0 … n_groups − 1 (NaN for an empty group)."""
    order = np.argsort(code, kind="stable")
    count = np.bincount(code, minlength=n_groups)
    return run_medians(values[order], np.cumsum(count) - count, count)


def layer_stats(
    points: pd.DataFrame,
    tables: dict[str, pd.DataFrame] | None = None,
    window: tuple[float, float] | None = None,
) -> LayerStats:
    """The Statistics panel's figures of one layer's point table (canonical columns; a
    ``target``, ``members`` or ``is_maneuver`` column and an ``at_rest`` side table in
    ``tables`` are used when present). ``window``: only the rows with a time in
    [start, end] (s since 1970 UTC), tracks cut to it."""
    pts, index = sorted_with_index(points)
    t = track_seconds(pts)
    if window is not None:
        keep = (t >= window[0]) & (t <= window[1])
        if not keep.all():
            pts = pts[keep].reset_index(drop=True)
            pts, index = sorted_with_index(pts)
            t = track_seconds(pts)
    n, k = len(pts), index.n_tracks
    starts, ends = index.starts, index.ends
    lifetime = t[ends - 1] - t[starts] if k else np.zeros(0)
    sizes = index.sizes

    # Per sensor: tracks, points, the median step forward in time.
    sensor_code, sensor_names = pd.factorize(index.keys["sensor"].astype(str), sort=True)
    sensor_code = np.asarray(sensor_code, dtype="int64")
    n_sensors = len(sensor_names)
    dt = np.diff(t) if n > 1 else np.zeros(0)
    step_ok = np.ones(len(dt), dtype=bool)
    step_ok[starts[1:] - 1] = False  # a step from one track into the next
    step_ok &= dt > 0  # a row repeated at the same time is no interval
    step_track = index.track_of_row[1:][step_ok]
    interval = _median_by_group(sensor_code[step_track], dt[step_ok], n_sensors)
    sensors = pd.DataFrame(
        {
            "sensor": np.asarray(sensor_names, dtype=object),
            "tracks": np.bincount(sensor_code, minlength=n_sensors),
            "points": np.bincount(sensor_code, weights=sizes, minlength=n_sensors).astype("int64"),
            "interval_s": interval,
        }
    )

    targets, target_source = _targets(pts)
    hi = float(lifetime.max()) if k else 0.0
    counts, edges = np.histogram(lifetime, bins=HIST_BINS, range=(0.0, hi if hi > 0 else 1.0))

    at_rest = None
    rest = (tables or {}).get("at_rest")
    if rest is not None:
        d = pd.to_numeric(rest.get("duration_s", pd.Series(dtype=float)), errors="coerce")
        d = d.to_numpy(dtype="float64")
        at_rest = {
            "spans": int(len(d)),
            "total_s": float(np.nansum(d)),
            "median_s": float(np.nanmedian(d)) if len(d) else float("nan"),
            "tracks": int(rest[["sensor", "batch"]].drop_duplicates().shape[0]) if len(d) else 0,
        }
    maneuvers = None
    if "is_maneuver" in pts.columns:
        flag = pts["is_maneuver"].to_numpy(dtype=bool, na_value=False)
        per_track = np.add.reduceat(flag.astype("int64"), starts) if k else np.zeros(0)
        maneuvers = {"points": int(flag.sum()), "tracks": int((per_track > 0).sum())}

    return LayerStats(
        points=n,
        tracks=k,
        sensors=sensors,
        targets=targets,
        target_source=target_source,
        lifetime_s=Spread.of(lifetime),
        hist_edges_s=edges,
        hist_counts=counts,
        points_per_track=Spread.of(sizes),
        extent=_extent(pts["lon"].to_numpy(dtype="float64"), pts["lat"].to_numpy(dtype="float64")),
        start_s=float(t.min()) if n else float("nan"),
        end_s=float(t.max()) if n else float("nan"),
        at_rest=at_rest,
        maneuvers=maneuvers,
        window=window,
    )

"""Tracks: grouping the point table by ``(sensor, batch)``, sorted by time.

Everything here is vectorized over all tracks at once: rows are sorted so each track is
one contiguous run, and per-track quantities come from ``np.*.reduceat`` over the run
starts. No Python loop per point or per track.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.schema import ordered_columns, time_seconds


@dataclass(frozen=True)
class TrackIndex:
    """Where each track lies in a sorted point table.

    ``starts[k]:ends[k]`` are the rows of track ``k``; ``track_of_row[i]`` is the track
    number of row ``i``; ``keys`` holds ``sensor`` and ``batch`` of each track.
    """

    starts: np.ndarray
    ends: np.ndarray
    track_of_row: np.ndarray
    keys: pd.DataFrame

    @property
    def n_tracks(self) -> int:
        return len(self.starts)

    @property
    def sizes(self) -> np.ndarray:
        return self.ends - self.starts

    def first_of_track(self) -> np.ndarray:
        """Boolean per row: the first row of its track."""
        mask = np.zeros(len(self.track_of_row), dtype=bool)
        mask[self.starts] = True
        return mask


def _key_codes(df: pd.DataFrame, sort: bool = True) -> tuple[np.ndarray, np.ndarray]:
    sensor_codes, _ = pd.factorize(df["sensor"], sort=sort, use_na_sentinel=False)
    batch_codes, _ = pd.factorize(df["batch"], sort=sort, use_na_sentinel=False)
    return sensor_codes.astype("int64"), batch_codes.astype("int64")


def sorted_with_index(df: pd.DataFrame) -> tuple[pd.DataFrame, "TrackIndex"]:
    """Rows ordered by sensor, batch (as text) and time, and their :class:`TrackIndex`,
    from one factorization. The table is returned as is when already in order."""
    n = len(df)
    if n == 0:
        out = df.reset_index(drop=True)
        return out, track_index(out)
    sensor, batch = _key_codes(df)
    t = time_seconds(df["time"])
    track = sensor * (int(batch.max()) + 1) + batch
    if _is_sorted(track, t):
        fresh = isinstance(df.index, pd.RangeIndex) and df.index.start == 0
        out = df if fresh else df.reset_index(drop=True)
        return out, _index_from_codes(out, sensor, batch)
    order = _sort_order(track, t)
    out = df.iloc[order].reset_index(drop=True)
    return out, _index_from_codes(out, sensor[order], batch[order])


def _is_sorted(track: np.ndarray, t: np.ndarray) -> bool:
    d_track = np.diff(track)
    return bool(np.all(d_track >= 0) and np.all((d_track > 0) | (np.diff(t) >= 0)))


def _sort_order(track: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Stable order by (track, time): one int64 key (ms) when it fits, else a lexsort."""
    t_ms = np.round((t - t.min()) * 1000.0)
    span = float(t_ms.max()) + 1.0
    if float(track.max() + 1) * span < 2**62:
        order = np.argsort(track.astype("int64") * int(span) + t_ms.astype("int64"), kind="stable")
        if _is_sorted(track[order], t[order]):  # sub-millisecond ties could leave disorder
            return order
    return np.lexsort((t, track))


def sort_points(df: pd.DataFrame) -> pd.DataFrame:
    """Rows ordered by sensor, batch (as text) and time; stable; a fresh RangeIndex.

    Returns ``df`` itself (not a copy) when it is already in that order.
    """
    return sorted_with_index(df)[0]


def track_index(df: pd.DataFrame) -> TrackIndex:
    """The :class:`TrackIndex` of a table sorted by :func:`sort_points`."""
    if len(df) == 0:
        empty = np.zeros(0, dtype="int64")
        return TrackIndex(
            empty, empty, empty, pd.DataFrame({"sensor": [], "batch": []}, dtype="str")
        )
    sensor_codes, batch_codes = _key_codes(df, sort=False)
    return _index_from_codes(df, sensor_codes, batch_codes)


def _index_from_codes(
    df: pd.DataFrame, sensor_codes: np.ndarray, batch_codes: np.ndarray
) -> TrackIndex:
    n = len(df)
    change = np.empty(n, dtype=bool)
    change[0] = True
    change[1:] = (sensor_codes[1:] != sensor_codes[:-1]) | (batch_codes[1:] != batch_codes[:-1])
    starts = np.flatnonzero(change).astype("int64")
    ends = np.append(starts[1:], n).astype("int64")
    track_of_row = np.cumsum(change).astype("int64") - 1
    keys = pd.DataFrame(
        {
            "sensor": df["sensor"].iloc[starts].to_numpy(),
            "batch": df["batch"].iloc[starts].to_numpy(),
        }
    ).astype("str")
    return TrackIndex(starts, ends, track_of_row, keys)


def track_origins(df: pd.DataFrame, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """Per-track local-plane origin: circular-mean longitude and mean latitude, degrees."""
    lon = np.radians(df["lon"].to_numpy(dtype="float64"))
    lat = df["lat"].to_numpy(dtype="float64")
    if index.n_tracks == 0:
        return np.zeros(0), np.zeros(0)
    s = np.add.reduceat(np.sin(lon), index.starts)
    c = np.add.reduceat(np.cos(lon), index.starts)
    lon0 = np.degrees(np.arctan2(s, c))
    lat0 = np.add.reduceat(lat, index.starts) / index.sizes
    return lon0, lat0


def local_xy(df: pd.DataFrame, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """Every point in its own track's local plane (equirectangular, metres; see geo.to_local)."""
    lon0, lat0 = track_origins(df, index)
    return geo.to_local(
        df["lon"].to_numpy(dtype="float64"),
        df["lat"].to_numpy(dtype="float64"),
        lon0[index.track_of_row],
        lat0[index.track_of_row],
    )


def step_motion(
    df: pd.DataFrame, index: TrackIndex
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per row: distance (m), time step (s), speed (kn) and course (deg) from the previous row.

    The first row of each track has NaN. Distances are great-circle (haversine), courses
    initial great-circle bearings, so tracks crossing 180° are handled.
    """
    n = len(df)
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    t = time_seconds(df["time"])
    dist = np.full(n, np.nan)
    dt = np.full(n, np.nan)
    course = np.full(n, np.nan)
    if n > 1:
        dist[1:] = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])
        dt[1:] = t[1:] - t[:-1]
        course[1:] = geo.initial_bearing_deg(lon[:-1], lat[:-1], lon[1:], lat[1:])
    first = index.first_of_track()
    dist[first] = np.nan
    dt[first] = np.nan
    course[first] = np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = np.where(dt > 0, dist / dt / geo.KN_MS, np.nan)
    course[dist == 0] = np.nan
    return dist, dt, speed, course


def derive_motion(
    df: pd.DataFrame, index: TrackIndex | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Speed (kn) and course (deg) of every point derived from positions.

    A point takes the motion of the leg arriving at it; the first point of a track takes
    the leg leaving it. Single-point tracks and zero-time steps give NaN. ``df`` must be
    sorted (:func:`sort_points`).
    """
    index = index or track_index(df)
    _, _, speed, course = step_motion(df, index)
    # First point of each track: copy from the second row when that row is in the same track.
    first = index.starts
    has_next = index.sizes > 1
    speed[first[has_next]] = speed[first[has_next] + 1]
    course[first[has_next]] = course[first[has_next] + 1]
    return speed, course


def fill_motion(df: pd.DataFrame) -> pd.DataFrame:
    """Copy of ``df`` (sorted) with missing ``speed``/``course`` derived from positions.

    Values present in the input are kept as they are.
    """
    out = sort_points(df).copy()
    index = track_index(out)
    speed, course = derive_motion(out, index)
    for name, derived in (("speed", speed), ("course", course)):
        if name not in out.columns:
            out[name] = derived
        else:
            given = out[name].to_numpy(dtype="float64")
            out[name] = np.where(np.isnan(given), derived, given)
    return out[ordered_columns(out)]


def track_summary(df: pd.DataFrame) -> pd.DataFrame:
    """One row per track: sensor, batch, points, start, end, duration_s, length_m, mean_speed_kn."""
    df = sort_points(df)
    index = track_index(df)
    if index.n_tracks == 0:
        return pd.DataFrame(
            columns=[
                "sensor",
                "batch",
                "points",
                "start",
                "end",
                "duration_s",
                "length_m",
                "mean_speed_kn",
            ]
        )
    dist, _, _, _ = step_motion(df, index)
    dist = np.nan_to_num(dist)
    t = time_seconds(df["time"])
    length = np.add.reduceat(dist, index.starts)
    duration = t[index.ends - 1] - t[index.starts]
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_speed = np.where(duration > 0, length / duration / geo.KN_MS, np.nan)
    times = df["time"]
    out = index.keys.copy()
    out["points"] = index.sizes
    out["start"] = times.iloc[index.starts].to_numpy()
    out["end"] = times.iloc[index.ends - 1].to_numpy()
    out["duration_s"] = duration
    out["length_m"] = length
    out["mean_speed_kn"] = mean_speed
    return out


def concat_ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """``starts[k], starts[k] + 1, …`` (``counts[k]`` values) for every k, concatenated."""
    counts = np.asarray(counts, dtype="int64")
    offsets = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    return np.repeat(np.asarray(starts, dtype="int64"), counts) + offsets


def interp_positions(
    df: pd.DataFrame,
    index: TrackIndex,
    track: np.ndarray,
    times_s: np.ndarray,
    max_gap_s: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions of tracks ``track[k]`` at times ``times_s[k]`` (seconds), linear in time.

    ``df`` is sorted with ``index``. Returns lon, lat (degrees; longitude differences are
    wrapped, so tracks across 180° interpolate the short way) and a mask of queries inside
    their track's time span (outside, the nearest end is returned) and, with ``max_gap_s``,
    between two points at most that far apart in time. Vectorized over all
    queries: one ``searchsorted`` on a (track, time) key.
    """
    track = np.asarray(track, dtype="int64")
    times_s = np.asarray(times_s, dtype="float64")
    t = time_seconds(df["time"])
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    if len(track) == 0:
        e = np.zeros(0)
        return e, e, e.astype(bool)
    base = float(min(t.min(), times_s.min()))
    span = float(max(t.max(), times_s.max()) - base) + 1.0
    key = index.track_of_row * span + (t - base)
    q = track * span + (times_s - base)
    hi = np.searchsorted(key, q, side="left")
    hi = np.clip(hi, index.starts[track], index.ends[track] - 1)
    lo = np.maximum(hi - 1, index.starts[track])
    dt = t[hi] - t[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(dt > 0, (times_s - t[lo]) / dt, 0.0)
    f = np.clip(f, 0.0, 1.0)
    out_lon = geo.wrap180(lon[lo] + geo.wrap180(lon[hi] - lon[lo]) * f)
    out_lat = lat[lo] + (lat[hi] - lat[lo]) * f
    inside = (times_s >= t[index.starts[track]]) & (times_s <= t[index.ends[track] - 1])
    if max_gap_s is not None:
        inside &= dt <= max_gap_s
    return out_lon, out_lat, inside

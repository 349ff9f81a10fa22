"""The time dimension of the map (issue 13): every track's position at a time ``t`` and
its trail, and the time-window predicates of the map and the batch table. Pure numpy.

A :class:`TimeIndex` is built once (in a worker) over the visible layers' points, sorted
per track by time. Each point gets a composite key ``track · span + (time − t_min)`` that
increases through the whole array, so one :func:`numpy.searchsorted` answers "where is
``t`` in track k" for every track at once: a frame costs O(tracks · log points), with no
Python loop per track.
"""

import math
from dataclasses import dataclass

import numpy as np

from wakeline.core.params import Params, finite_number, param
from wakeline.core.sorted_sets import repeat_runs

#: Times below this many seconds since 1970 (i.e. before 1980) are read as elapsed time
#: from a scene start (MTAD, Øresund), not as dates: no radar/AIS export is that old.
RELATIVE_LIMIT_S = 10 * 365.25 * 86400.0


def is_relative_time(time_s: np.ndarray) -> bool:
    """True when times (s since 1970) are small: elapsed time from a scene start."""
    finite = time_s[np.isfinite(time_s)]
    return bool(len(finite)) and float(finite.max()) < RELATIVE_LIMIT_S


def format_elapsed(seconds: float) -> str:
    """``T+h:mm:ss`` (``T+2 d 03:04:05`` beyond a day; tenths when not whole)."""
    if not math.isfinite(seconds):
        return "—"
    sign = "-" if seconds < 0 else "+"
    tenths = round(abs(seconds) * 10)  # rounded first: 59.97 s is 0:01:00, not 0:00:00
    s = tenths / 10.0
    days, rest = divmod(s, 86400.0)
    h, rest = divmod(rest, 3600.0)
    m, sec = divmod(rest, 60.0)
    sec_text = f"{sec:04.1f}" if tenths % 10 else f"{round(sec):02d}"
    clock = f"{int(h):d}:{int(m):02d}:{sec_text}"
    if days:
        clock = f"{int(days)} d {int(h):02d}:{int(m):02d}:{sec_text}"
    return f"T{sign}{clock}"


@dataclass(frozen=True)
class PlaybackParams(Params):
    """How the time slider plays the scene (the panel's spin boxes are made from these)."""

    trail_min: float = param(
        10.0,
        "min",
        "trail drawn behind each track's position at t (0 = markers only)",
        0.0,
        10080.0,
    )
    speed: float = param(
        60.0, "s/s", "playback speed: scene seconds per wall-clock second (×1 … ×1000)", 1.0, 1000.0
    )
    step_s: float = param(60.0, "s", "one step of the step buttons", 0.1, 86400.0)
    fps: float = param(20.0, "1/s", "frames drawn per second while playing", 1.0, 60.0)


@dataclass(frozen=True)
class TimeWindow:
    """The map's time window [``start_s``, ``end_s``]: seconds on the layers' clock (since
    1970-01-01 UTC; for scene-relative times such as MTAD's, the seconds after the scene
    start the importer reads). Kept by the session, saved in the project as
    :meth:`to_json` (``{"start": …, "end": …, "unit": "s"}``)."""

    start_s: float
    end_s: float
    #: The unit of ``start_s`` and ``end_s`` (written beside them in the project).
    UNIT = "s"

    def __post_init__(self) -> None:
        for name in ("start_s", "end_s"):
            object.__setattr__(
                self, name, finite_number(getattr(self, name), f"time window: {name}")
            )
        if self.end_s < self.start_s:
            raise ValueError(
                f"time window: ends ({self.end_s} s) before it starts ({self.start_s} s)"
            )

    @classmethod
    def of(cls, window: "TimeWindow | tuple[float, float] | None") -> "TimeWindow | None":
        """``window`` as a TimeWindow: (from, to) in s, a TimeWindow, or None."""
        if window is None or isinstance(window, TimeWindow):
            return window
        start, end = window
        return cls(start, end)

    def bounds(self) -> tuple[float, float]:
        """(from, to) in s, as the time panel holds it."""
        return (self.start_s, self.end_s)

    def to_json(self) -> dict:
        """The plain value the project stores, with its unit."""
        return {"start": self.start_s, "end": self.end_s, "unit": self.UNIT}

    @classmethod
    def from_json(cls, value: object) -> "TimeWindow | None":
        """Read :meth:`to_json`'s value back (None: no window). Raises ValueError when it
        is not one: not a mapping of two finite numbers in seconds, or ending before it
        starts."""
        if value is None:
            return None
        if not isinstance(value, dict) or set(value) != {"start", "end", "unit"}:
            raise ValueError(f"time window: expected start, end and unit, got {value!r}")
        if value["unit"] != cls.UNIT:
            raise ValueError(f"time window: unit must be {cls.UNIT!r}, got {value['unit']!r}")
        return cls(value["start"], value["end"])


#: The unit of the slider's time in the project (the ``current_time`` state row).
CURRENT_TIME_UNIT = "s"


def current_time_to_json(t: float | None) -> dict | None:
    """The slider's time ``t`` (s on the layers' clock, as :class:`TimeWindow`; None:
    not kept) as the project stores it: ``{"t": …, "unit": "s"}``, or None."""
    return None if t is None else {"t": float(t), "unit": CURRENT_TIME_UNIT}


def current_time_from_json(value: object) -> float | None:
    """Read :func:`current_time_to_json`'s value back (None: not kept). Raises ValueError
    when it is not one: not a mapping of one finite number in seconds."""
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) != {"t", "unit"}:
        raise ValueError(f"slider time: expected t and unit, got {value!r:.120}")
    if value["unit"] != CURRENT_TIME_UNIT:
        raise ValueError(f"slider time: unit must be {CURRENT_TIME_UNIT!r}, got {value['unit']!r}")
    return check_current_time(value["t"])


def check_current_time(t: object) -> float | None:
    """``t`` as the slider's time (s; None stays None). Raises ValueError when it is not a
    finite number."""
    if t is None:
        return None
    return finite_number(t, "slider time:")


def _empty_i() -> np.ndarray:
    return np.zeros(0, dtype="int64")


@dataclass(frozen=True)
class TimeIndex:
    """Points of many tracks, each track's rows ``starts[k]:ends[k]`` sorted by time (s).

    ``group`` is an integer per track (the layer / colour it is drawn in).
    """

    time_s: np.ndarray
    lon: np.ndarray
    lat: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    group: np.ndarray
    t0: np.ndarray  # per track: first time (s)
    t1: np.ndarray  # per track: last time (s)
    key: np.ndarray  # per point: track · span + (time − t_min), increasing
    t_min: float
    span: float

    @property
    def n_tracks(self) -> int:
        return len(self.starts)

    @property
    def n_points(self) -> int:
        return len(self.time_s)

    def bounds(self) -> tuple[float, float] | None:
        """(first, last) time (s) of all tracks; None when empty."""
        if not self.n_tracks:
            return None
        return float(self.t0.min()), float(self.t1.max())

    # -- positions ---------------------------------------------------------------------

    def _interp(self, tracks: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """lon, lat of ``tracks`` at times ``t`` (one per track, inside its span),
        interpolated linearly between the two points around ``t``."""
        if len(tracks) == 0:
            return np.zeros(0), np.zeros(0)
        s, e = self.starts[tracks], self.ends[tracks]
        q = tracks * self.span + (t - self.t_min)
        j = np.searchsorted(self.key, q, side="right")  # first point after t
        i = np.clip(j - 1, s, e - 1)
        j = np.minimum(i + 1, e - 1)
        ti, tj = self.time_s[i], self.time_s[j]
        dt = tj - ti
        with np.errstate(invalid="ignore", divide="ignore"):
            w = np.where(dt > 0, (t - ti) / dt, 0.0)
        w = np.clip(w, 0.0, 1.0)
        lon = self.lon[i] + w * (self.lon[j] - self.lon[i])
        lat = self.lat[i] + w * (self.lat[j] - self.lat[i])
        return lon, lat

    def active(self, t: float) -> np.ndarray:
        """Tracks alive at ``t`` (first time ≤ t ≤ last time)."""
        return np.flatnonzero((self.t0 <= t) & (self.t1 >= t))

    def positions_at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(tracks, lon, lat): every track alive at ``t`` and its interpolated position."""
        tracks = self.active(t)
        lon, lat = self._interp(tracks, np.full(len(tracks), float(t)))
        return tracks, lon, lat

    def trail(
        self, t: float, trail_s: float, max_vertices: int = 400_000
    ) -> tuple[np.ndarray, np.ndarray]:
        """The last ``trail_s`` seconds before ``t`` of every track that has them, as one
        NaN-separated curve (lon, lat): per track its position at the trail's start, the
        points inside, its position at ``t`` (or its end), then NaN. When the points
        inside exceed ``max_vertices``, every k-th is kept (the two ends always are)."""
        if trail_s <= 0 or not self.n_tracks:
            return np.zeros(0), np.zeros(0)
        t = float(t)
        a = t - float(trail_s)
        tracks = np.flatnonzero((self.t0 <= t) & (self.t1 >= a))
        if len(tracks) == 0:
            return np.zeros(0), np.zeros(0)
        base = tracks * self.span - self.t_min
        # Each track's window clipped to its own span: a key below its first time or
        # beyond its last would fall among its neighbour's keys (a trail that began
        # before the data pulled in the previous track's end).
        a_k = np.maximum(a, self.t0[tracks])
        t_k = np.minimum(t, self.t1[tracks])
        lo = np.searchsorted(self.key, base + a_k, side="right")  # points after a
        hi = np.searchsorted(self.key, base + t_k, side="right")  # … up to t
        n = hi - lo
        total = int(n.sum())
        first = np.cumsum(n) - n
        run = np.arange(total) - np.repeat(first, n)  # position inside each track's run
        src = np.repeat(lo, n) + run
        if total > max_vertices:
            stride = -(-total // max_vertices)
            keep = run % stride == 0
            src = src[keep]
            n = np.bincount(np.repeat(np.arange(len(tracks)), n)[keep], minlength=len(tracks))
            first = np.cumsum(n) - n
            run = np.arange(len(src)) - np.repeat(first, n)
        tail_lon, tail_lat = self._interp(tracks, a_k)
        head_lon, head_lat = self._interp(tracks, t_k)
        seg = n + 3  # tail, points, head, NaN
        off = np.cumsum(seg) - seg
        lon = np.full(int(seg.sum()), np.nan)
        lat = np.full(int(seg.sum()), np.nan)
        lon[off], lat[off] = tail_lon, tail_lat
        dest = np.repeat(off + 1, n) + run
        lon[dest], lat[dest] = self.lon[src], self.lat[src]
        lon[off + 1 + n], lat[off + 1 + n] = head_lon, head_lat
        return lon, lat

    # -- time window -------------------------------------------------------------------

    def overlapping(self, t_from: float, t_to: float) -> np.ndarray:
        """Per track: True when its time span overlaps [t_from, t_to]."""
        return overlapping(self.t0, self.t1, t_from, t_to)


def overlapping(t0: np.ndarray, t1: np.ndarray, t_from: float, t_to: float) -> np.ndarray:
    """Tracks (first time ``t0``, last ``t1``, s) whose span meets [t_from, t_to]."""
    return (np.asarray(t0) <= t_to) & (np.asarray(t1) >= t_from)


def window_rows(
    time_s: np.ndarray, starts: np.ndarray, ends: np.ndarray, t_from: float, t_to: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The points of tracks (rows ``starts[k]:ends[k]``) with time in [t_from, t_to]:
    (kept rows, kept tracks, their new starts, their new ends) over the kept rows."""
    return mask_rows((time_s >= t_from) & (time_s <= t_to), starts, ends)


def mask_rows(
    keep: np.ndarray, starts: np.ndarray, ends: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The points ``keep`` (bool per point) of tracks (rows ``starts[k]:ends[k]``, end to
    end): (kept rows, kept tracks, their new starts, their new ends) over the kept rows."""
    rows = np.flatnonzero(keep)
    track = repeat_runs(None, ends - starts)
    per = np.bincount(track[rows], minlength=len(starts)) if len(rows) else np.zeros(len(starts))
    kept = np.flatnonzero(per > 0)
    sizes = per[kept].astype("int64")
    new_ends = np.cumsum(sizes)
    return rows, kept, new_ends - sizes, new_ends


def spread_picks(group: np.ndarray, key: np.ndarray, max_per: int) -> np.ndarray:
    """Indices of at most ``max_per`` items of each group, spread evenly over the group's
    items in ``key`` order (ties: in input order), its first and last kept: per group of
    ``n`` the items ``np.linspace(0, n - 1, min(n, max_per)).round()`` of that order, as
    a loop per group would pick them (one ``lexsort`` and array arithmetic, no loop).
    Returned in group, then key order."""
    group, key = np.asarray(group), np.asarray(key)
    if len(group) == 0 or max_per < 1:
        return _empty_i()
    order = np.lexsort((key, group))
    g = group[order]
    starts = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])
    sizes = np.diff(np.r_[starts, len(g)])
    per = np.minimum(sizes, max_per)
    first = np.cumsum(per) - per
    j = np.arange(int(per.sum())) - np.repeat(first, per)  # pick number inside its group
    size, n = np.repeat(sizes, per), np.repeat(per, per)
    step = (size - 1) / np.maximum(n - 1, 1)
    pos = np.round(j * step).astype("int64")
    pos = np.where((j == n - 1) & (n > 1), size - 1, pos)  # linspace ends on the last
    return order[np.repeat(starts, per) + pos]


def _per_point(values: np.ndarray, first: np.ndarray, n: int) -> np.ndarray:
    """``np.repeat(values, sizes)`` for runs of ``n`` points starting at ``first``
    (increasing, from 0; every run non-empty): the differences at the runs' starts,
    summed up (integers, exact).

    ``np.repeat`` holds the GIL while it fills its output, and at a million points the
    output's fresh pages alone took 50–120 ms on the shared test machine (the GUI
    thread stopped meanwhile, e.g. right after an Open project); ``cumsum`` releases it."""
    out = np.empty(n, dtype="int64")
    out.fill(0)  # not np.zeros: calloc may clear the pages with the GIL held
    out[first] = np.diff(np.asarray(values, dtype="int64"), prepend=0)
    return np.cumsum(out, out=out)


def build_index(
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]],
) -> TimeIndex:
    """One index over several layers: ``parts`` = (time_s, lon, lat, starts, ends) each,
    tracks sorted by time inside; the part's number becomes the tracks' ``group``."""
    times, lons, lats, starts, ends, groups = [], [], [], [], [], []
    offset = 0
    for g, (t, lon, lat, s, e) in enumerate(parts):
        s = np.asarray(s, dtype="int64")
        e = np.asarray(e, dtype="int64")
        ok = e > s
        times.append(np.asarray(t, dtype="float64"))
        lons.append(np.asarray(lon, dtype="float64"))
        lats.append(np.asarray(lat, dtype="float64"))
        starts.append(s[ok] + offset)
        ends.append(e[ok] + offset)
        groups.append(np.full(int(ok.sum()), g, dtype="int64"))
        offset += len(t)
    cat = lambda xs, f: np.concatenate(xs) if xs else f()  # noqa: E731
    time_s = cat(times, lambda: np.zeros(0))
    s = cat(starts, _empty_i)
    e = cat(ends, _empty_i)
    if len(s) == 0:
        z = np.zeros(0)
        return TimeIndex(z, z, z, _empty_i(), _empty_i(), _empty_i(), z, z, z, 0.0, 1.0)
    sizes = e - s
    first = np.cumsum(sizes) - sizes
    lon, lat = cat(lons, lambda: np.zeros(0)), cat(lats, lambda: np.zeros(0))
    if len(time_s) != int(sizes.sum()) or not np.array_equal(s, first):
        # Tracks not end to end over all the points: gather their rows.
        rows = np.arange(int(sizes.sum()))
        rows += _per_point(s - first, first, len(rows))
        time_s, lon, lat = time_s[rows], lon[rows], lat[rows]
    s, e = first, first + sizes
    t0, t1 = time_s[s], time_s[e - 1]
    t_min = float(t0.min())
    span = float(t1.max()) - t_min + 1.0
    key = _per_point(np.arange(len(s)), first, len(time_s)) * span + (time_s - t_min)
    return TimeIndex(
        time_s=time_s,
        lon=lon,
        lat=lat,
        starts=s,
        ends=e,
        group=cat(groups, _empty_i),
        t0=t0,
        t1=t1,
        key=key,
        t_min=t_min,
        span=span,
    )


__all__ = [
    "PlaybackParams",
    "TimeIndex",
    "build_index",
    "mask_rows",
    "overlapping",
    "spread_picks",
    "window_rows",
]

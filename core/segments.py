"""Per-track summaries for association: where and how each track starts and ends.

Everything is vectorized over tracks: the first and last ``k`` points of every track are
gathered into a (tracks × k) block and fitted by a straight line in time at once.
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.tracks import (
    TrackIndex,
    known_order,
    local_xy,
    sorted_with_index,
    track_origins,
    track_seconds,
)


@dataclass(frozen=True)
class Segments:
    """One entry per track (``index.keys`` gives sensor and batch), arrays of length n.

    Times in seconds since the epoch; positions in degrees; velocities ``v*`` in m/s east
    and north from a least-squares line over the first / last ``k`` points; speed in knots
    and course in degrees at both ends; ``ldm_deg`` the linear directional mean of the
    legs (seed 001 eq. 11; in the track's own frame, north at its origin; NaN without a
    leg that moves); ``cross`` the open shoelace sum of the track in its own local
    frame (m², for seed 001's area S). Those two, the local frames and the sampling period
    are computed from the points when first asked for (only some methods use them).

    ``points`` holds the columns association reads, sorted by track and time; when the
    input had more and had to be sorted, ``source`` is the input and ``source_row`` the
    input row of every sorted row (:meth:`full_points` puts them together).
    """

    points: pd.DataFrame
    index: TrackIndex
    sensor_code: np.ndarray
    n: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    lon0: np.ndarray
    lat0: np.ndarray
    lon1: np.ndarray
    lat1: np.ndarray
    vx0: np.ndarray
    vy0: np.ndarray
    vx1: np.ndarray
    vy1: np.ndarray
    #: Standard error (m, per axis) of the fitted start / end position and (m/s) of the
    #: fitted start / end velocity; a piece too short to show its own noise takes its
    #: sensor's median residual. ``moving0`` / ``moving1``: the end's motion is known
    #: (at least two fixes spanning time, or a reported speed and course).
    pos_sd0: np.ndarray = None  # type: ignore[assignment]
    pos_sd1: np.ndarray = None  # type: ignore[assignment]
    vel_sd0: np.ndarray = None  # type: ignore[assignment]
    vel_sd1: np.ndarray = None  # type: ignore[assignment]
    motion0: np.ndarray = None  # type: ignore[assignment]
    motion1: np.ndarray = None  # type: ignore[assignment]
    #: Position noise (m, per axis) behind ``pos_sd*``: the end's own fit residuals, or
    #: its sensor's median where the end has too few points.
    noise0: np.ndarray = None  # type: ignore[assignment]
    noise1: np.ndarray = None  # type: ignore[assignment]
    #: Reported speed (kn) at the start / end: the median over its first / last three
    #: points where reported, course or none (NaN elsewhere); the reach of a fast craft.
    sog0: np.ndarray | None = None
    sog1: np.ndarray | None = None
    #: Acceleration (m/s²) the start / end shows beyond its noise (0 where none shows).
    accel0: np.ndarray | None = None
    accel1: np.ndarray | None = None
    #: Median time step (s) between the first / last ``end_points`` fixes of the piece
    #: (its sensor's median where the piece has fewer than three): when its ship is seen.
    step0: np.ndarray | None = None
    step1: np.ndarray | None = None
    #: Time (s) spanned by the fixes of the piece's own start / end fit (``end_points``,
    #: or up to ``end_points_max`` where they show no acceleration; 0 for a single fix):
    #: how long the end was seen as it is fitted.
    span0: np.ndarray | None = None
    span1: np.ndarray | None = None
    source: pd.DataFrame | None = None
    source_row: np.ndarray | None = None
    #: Shortest positive time step (s) between the first / last ``end_points`` fixes of
    #: the piece (NaN for a single fix, or fixes all at one instant): how soon its ship
    #: has been seen again, jitter included (``LinkParams.min_gap_least_steps``).
    least_step0: np.ndarray | None = None
    least_step1: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t0)

    def full_points(self) -> pd.DataFrame:
        """Every input row with all its columns, in the order of ``points``."""
        if self.source is None:
            return self.points
        return self.source.take(self.source_row).reset_index(drop=True)

    def column(self, name: str) -> pd.Series:
        """Column ``name`` of the input, in the order of ``points`` (any input column)."""
        if name in self.points.columns or self.source is None:
            return self.points[name]
        return self.source[name].take(self.source_row).reset_index(drop=True)

    @cached_property
    def _shape(self) -> dict:
        return _track_shape(self.points, self.index)

    @property
    def ldm_deg(self) -> np.ndarray:
        return self._shape["ldm_deg"]

    @property
    def cross(self) -> np.ndarray:
        return self._shape["cross"]

    @property
    def origin_lon(self) -> np.ndarray:
        return self._shape["origin_lon"]

    @property
    def origin_lat(self) -> np.ndarray:
        return self._shape["origin_lat"]

    @property
    def first_xy(self) -> np.ndarray:
        return self._shape["first_xy"]

    @property
    def last_xy(self) -> np.ndarray:
        return self._shape["last_xy"]

    @property
    def period_s(self) -> np.ndarray:
        return self._shape["period_s"]

    # Speeds, courses and Earth-centred positions are computed once per summary (the
    # association asks for them in every candidate search and pricing; read only).
    @cached_property
    def speed0_kn(self) -> np.ndarray:
        return np.hypot(self.vx0, self.vy0) / geo.KN_MS

    @cached_property
    def speed1_kn(self) -> np.ndarray:
        return np.hypot(self.vx1, self.vy1) / geo.KN_MS

    @cached_property
    def course0_deg(self) -> np.ndarray:
        return geo.wrap360(np.degrees(np.arctan2(self.vx0, self.vy0)))

    @cached_property
    def course1_deg(self) -> np.ndarray:
        return geo.wrap360(np.degrees(np.arctan2(self.vx1, self.vy1)))

    @cached_property
    def ecef0(self) -> np.ndarray:
        """Earth-centred position (m, n × 3) of each start (:func:`ecef`)."""
        return ecef(self.lon0, self.lat0)

    @cached_property
    def ecef1(self) -> np.ndarray:
        """Earth-centred position (m, n × 3) of each end (:func:`ecef`)."""
        return ecef(self.lon1, self.lat1)

    @cached_property
    def t0_rank(self) -> np.ndarray:
        """Each track's place (0..n−1) in start-time order, ties by index: the key that
        orders tracks by (group, start time) in one integer sort (:func:`order_by`)."""
        return time_rank(self.t0)

    @cached_property
    def t1_rank(self) -> np.ndarray:
        """Each track's place (0..n−1) in end-time order, ties by index (:func:`order_by`)."""
        return time_rank(self.t1)


def time_rank(t: np.ndarray) -> np.ndarray:
    """Place (0..n−1) of each value of ``t`` in ascending order, ties (and NaN, last) in
    index order: what a stable sort of ``t`` puts where."""
    rank = np.empty(len(t), dtype="int64")
    rank[np.argsort(t, kind="stable")] = np.arange(len(t))
    return rank


def order_by(major: np.ndarray, rank: np.ndarray) -> np.ndarray:
    """``np.lexsort((t, major))`` from ``rank`` = :func:`time_rank` of ``t`` (``major``
    and ``rank`` of the same rows; ``rank`` may be a subset's places in a larger
    ranking): one sort of the unique integer keys ``major·R + rank`` (R above every rank)
    instead of two stable indirect sorts — the same permutation, several times faster
    at 100 k tracks. Falls back to ``lexsort`` when ``major`` is negative or the keys
    would not fit in 63 bits."""
    if len(major) == 0:
        return np.zeros(0, dtype="int64")
    big = int(rank.max()) + 1
    lo, hi = int(major.min()), int(major.max())
    if lo < 0 or (hi + 1) * big >= 2**63:
        return np.lexsort((rank, major))
    return np.argsort(major.astype("int64") * big + rank)


def _end_fit(
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
    rows: np.ndarray,
    valid: np.ndarray,
    anchor: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """Line fit x(t), y(t) over ``rows`` (tracks × k, ``valid`` mask) about the anchor row.

    Returns the fitted lon/lat at the anchor's time, the velocity (m/s east, north), the
    residual standard deviation per axis (m; NaN with fewer than 3 points), the standard
    error factors of the anchor position (× residual sd) and of the velocity (× residual
    sd, 1/s; infinite without a time span).
    """
    return _line_fit(*_local(lon, lat, t, rows, anchor), valid, lon[anchor], lat[anchor])


def _local(
    lon: np.ndarray, lat: np.ndarray, t: np.ndarray, rows: np.ndarray, anchor: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """East, north (m) and time (s) of ``rows`` (tracks × k) from each track's anchor row."""
    x, y = geo.to_local(lon[rows], lat[rows], lon[anchor][:, None], lat[anchor][:, None])
    return x, y, t[rows] - t[anchor][:, None]


def _line_fit(
    x: np.ndarray,
    y: np.ndarray,
    tt: np.ndarray,
    valid: np.ndarray,
    lon_a: np.ndarray,
    lat_a: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """:func:`_end_fit` on local coordinates (:func:`_local`) about anchors at
    ``lon_a``, ``lat_a``."""
    w = valid.astype("float64")
    sw = w.sum(axis=1)
    mt = (w * tt).sum(axis=1) / sw
    mx = (w * x).sum(axis=1) / sw
    my = (w * y).sum(axis=1) / sw
    dt = (tt - mt[:, None]) * w
    var = (dt * dt).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        bx = np.where(var > 0, (dt * (x - mx[:, None])).sum(axis=1) / var, 0.0)
        by = np.where(var > 0, (dt * (y - my[:, None])).sum(axis=1) / var, 0.0)
    ax = mx - bx * mt
    ay = my - by * mt
    flon, flat = geo.from_local(ax, ay, lon_a, lat_a)
    rx = (x - ax[:, None] - bx[:, None] * tt) * w
    ry = (y - ay[:, None] - by[:, None] * tt) * w
    with np.errstate(invalid="ignore", divide="ignore"):
        resid = np.where(
            sw > 2, np.sqrt(((rx * rx + ry * ry).sum(axis=1)) / (2 * (sw - 2))), np.nan
        )
        pos_f = np.sqrt(1.0 / sw + np.where(var > 0, mt * mt / var, 0.0))
        vel_f = np.where(var > 0, 1.0 / np.sqrt(var), np.inf)
    return flon, flat, bx, by, resid, pos_f, vel_f


def _accel(x: np.ndarray, y: np.ndarray, tt: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per end: the acceleration (m/s²) its fixes show beyond their noise.

    A quadratic fit x(t), y(t) over the end's fixes in local coordinates about its anchor
    (:func:`_local`; tracks × k, ``valid`` a prefix of each row, times in order, as
    :func:`_end_rows` gives them). Its quadratic terms, both axes together, against their
    standard errors — the noise estimated from the same residuals, at least
    :data:`NOISE_FLOOR_M`, with 2(d − 3) degrees of freedom for d distinct instants (a
    copied fix adds no evidence): 0 unless they pass :func:`_f_crit` at
    :data:`TEST_LEVEL`, else the acceleration by which they pass it (continuous: 0 at the
    threshold), at most :data:`ACCEL_MAX`. Turns count as well as speed changes. Ends of
    fixes at fewer than 4 instants show none.
    """
    w = valid.astype("float64")
    sw = w.sum(axis=1)
    instants = 1 + ((tt[:, 1:] != tt[:, :-1]) & valid[:, 1:]).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = (tt - ((w * tt).sum(axis=1) / sw)[:, None]) * w
        u2 = u * u
        var = u2.sum(axis=1)
        # The quadratic orthogonal to the constant and to the line over the valid rows.
        q = (u2 - (var / sw)[:, None] - ((u2 * u).sum(axis=1) / var)[:, None] * u) * w
        qq = (q * q).sum(axis=1)
        c2 = np.zeros(len(sw))
        r2 = np.zeros(len(sw))
        for v in (x, y):
            mv = (w * v).sum(axis=1) / sw
            bv = (u * v).sum(axis=1) / var
            cv = (q * v).sum(axis=1) / qq
            r = (v - mv[:, None] - bv[:, None] * u - cv[:, None] * q) * w
            c2 += cv * cv
            r2 += (r * r).sum(axis=1)
        dof = 2 * (instants - 3)
        noise2 = np.maximum(r2 / dof, NOISE_FLOOR_M**2)  # per axis
        se2 = noise2 / qq  # of the quadratic term
        # Fixes at two instants leave a quadratic of rounding noise only.
        spread = qq > 1e-9 * (u2 * u2).sum(axis=1)
        crit = _f_crit(dof)
        shows = (instants > 3) & spread & (c2 > crit * se2)
        shown = 2 * np.sqrt(np.maximum(c2 - crit * se2, 0.0))
        return np.where(shows, np.minimum(shown, ACCEL_MAX), 0.0)


#: Position noise (m, per axis) an end is never assumed to be below: exact synthetic
#: positions still carry rounding, which would pass for a curve.
NOISE_FLOOR_M = 0.01

#: The most acceleration (m/s²) an end is taken to show: no ship turns or speeds up
#: harder (10 m/s turning 5 °/s is 0.87); fixes crowded into milliseconds can seem to.
ACCEL_MAX = 1.0


#: Level of the tests that tell an end's curve or bend from its noise.
TEST_LEVEL = 0.01


def _f_crit(m: np.ndarray, level: float = TEST_LEVEL) -> np.ndarray:
    """Threshold on |c|² / se² of a two-axis estimate c whose standard error se comes
    from the residuals with ``m`` degrees of freedom, at ``level``: the statistic is
    2·F(2, m), whose upper tail has the closed form m·(level^(−2/m) − 1) (9.21, the χ²
    value, as m grows; 13.0 at m = 14, the 10-fix quadratic)."""
    m = np.maximum(np.asarray(m, dtype="float64"), 1.0)
    return m * (level ** (-2.0 / m) - 1.0)


def _end_rows(
    index: TrackIndex, tracks: np.ndarray, width: int, head: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rows (tracks × ``width``) of the first (``head``) or last fixes of ``tracks``
    from their start / end inwards, which of them are fixes of the track, and the anchor
    row (the first / last fix)."""
    offs = np.arange(width)
    starts, ends = index.starts[tracks], index.ends[tracks]
    if head:
        rows = np.minimum(starts[:, None] + offs, ends[:, None] - 1)
        anchor = starts
    else:
        rows = np.maximum(ends[:, None] - 1 - offs, starts[:, None])
        anchor = ends - 1
    valid = offs[None, :] < np.minimum(index.sizes[tracks], width)[:, None]
    return rows, valid, anchor


def _end_least_step(t: np.ndarray, rows: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per end: the shortest positive time step (s) between its fixes (``rows``/``valid``
    as :func:`_end_rows` gives them); NaN where it has none (a single fix, or fixes at
    one instant: no evidence of its own, and no sensor's figure put in its place)."""
    tt = np.where(valid, t[rows], np.nan)
    steps = np.abs(np.diff(tt, axis=1))
    steps = np.where(steps > 0, steps, np.inf)  # NaN (not a fix) and copies alike
    least = steps.min(axis=1, initial=np.inf)
    return np.where(np.isfinite(least), least, np.nan)


def _end_step(
    t: np.ndarray, rows: np.ndarray, valid: np.ndarray, sensor_code: np.ndarray
) -> np.ndarray:
    """Per end: the median time step (s) between its fixes (``rows``/``valid`` as
    :func:`_end_rows` gives them), where it has three or more; its sensor's median of
    those elsewhere (NaN when no end of the sensor has three)."""
    tt = np.where(valid, t[rows], np.nan)
    steps = np.abs(np.diff(tt, axis=1))
    enough = np.isfinite(steps).sum(axis=1) >= 2
    step = np.full(len(rows), np.nan)
    if enough.any():
        step[enough] = np.nanmedian(steps[enough], axis=1)
    per_sensor = pd.Series(step).groupby(sensor_code).median()
    return np.where(enough, step, per_sensor.reindex(sensor_code).to_numpy())


#: Ends whose longer fits are tested or made at once, for fits of 40 fixes (bounds the
#: temporaries: a block of ends × fit width floats each; wider fits take fewer ends).
FIT_BLOCK = 16384


def _straight_fits(
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    k: "int | np.ndarray",
    k_max: "int | np.ndarray",
    head: bool,
) -> tuple[tuple[np.ndarray, ...], np.ndarray, np.ndarray]:
    """:func:`_end_fit` of every track's start (``head``) or end over ``k`` fixes, or 2k,
    4k … (at most ``k_max``) while the fixes over that span show no acceleration
    (:func:`_accel`): the longest span over which the straight line holds, so a long
    steady track's velocity is known better and a turning one's is not averaged over a
    turn its fixes show. A turn too slow to show in the noise is averaged over, and the
    fit's velocity error, a line's, is then too small (docs/evaluation.md). ``k`` and
    ``k_max``: one for all tracks, or one per track (``end_span_s``).

    Returns the fit, the number of fixes each fit took, and the acceleration (m/s²) each
    end's first ``k`` fixes show (the recent motion: a turn a longer span shows may be
    over before the gap).
    """
    n = len(index.sizes)
    kk = np.broadcast_to(np.maximum(np.asarray(k, dtype="int64"), 1), (n,))
    km = np.maximum(np.broadcast_to(np.asarray(k_max, dtype="int64"), (n,)), kk)
    out = [np.empty(n) for _ in range(7)]
    used = np.empty(n, dtype="int64")
    accel = np.zeros(n)
    block = max(1024, FIT_BLOCK * 40 // max(int(km.max()) if n else 40, 40))
    for b in range(0, n, block):
        part = np.arange(b, min(b + block, n))
        fit, width, acc = _straight_block(lon, lat, t, index, part, kk[part], km[part], head)
        for arr, v in zip(out, fit, strict=True):
            arr[part] = v
        used[part] = np.minimum(index.sizes[part], width)
        accel[part] = acc
    return tuple(out), used, accel


def _straight_block(
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    part: np.ndarray,
    k: np.ndarray,
    k_max: np.ndarray,
    head: bool,
) -> tuple[list, np.ndarray, np.ndarray]:
    """:func:`_straight_fits` of the tracks ``part`` (``k``, ``k_max`` per track): their
    fits, span widths and accelerations."""
    size = index.sizes[part]
    top_each = np.minimum(k_max, np.maximum(k, size))
    top = int(top_each.max())
    rows, _valid, anchor = _end_rows(index, part, top, head)
    x, y, tt = _local(lon, lat, t, rows, anchor)
    offs = np.arange(top)

    def span(sub: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, ...]:
        c = int(w.max())
        return x[sub, :c], y[sub, :c], tt[sub, :c], offs[:c] < np.minimum(size[sub], w)[:, None]

    everyone = np.arange(len(part))
    first = span(everyone, k)
    best = list(_line_fit(*first, lon[anchor], lat[anchor]))
    acc = _accel(*first)
    width = k.copy()
    cand = np.flatnonzero((size > k) & (k < top_each))
    while len(cand):
        w = np.minimum(2 * width[cand], top_each[cand])
        ok = _accel(*span(cand, w)) == 0
        cand, w = cand[ok], w[ok]
        if not len(cand):
            break
        width[cand] = w
        longer = _line_fit(*span(cand, w), lon[anchor[cand]], lat[anchor[cand]])
        for arr, v in zip(best, longer, strict=True):
            arr[cand] = v
        cand = cand[(size[cand] > w) & (w < top_each[cand])]
    return best, width, acc


def _reported_velocity(
    pts: pd.DataFrame, rows: np.ndarray, valid: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """Velocity (m/s east, north) from reported speed/course over ``rows``; NaN where none."""
    if "speed" not in pts.columns or "course" not in pts.columns:
        return None
    sog = pts["speed"].to_numpy(dtype="float64")[rows]
    cog = pts["course"].to_numpy(dtype="float64")[rows]
    ok = valid & np.isfinite(sog) & np.isfinite(cog)
    if not ok.any():
        return None
    rad = np.radians(cog)
    w = ok.astype("float64")
    sog = np.where(ok, sog, 0.0) * geo.KN_MS
    with np.errstate(invalid="ignore", divide="ignore"):
        vx = (w * sog * np.sin(np.where(ok, rad, 0.0))).sum(axis=1) / w.sum(axis=1)
        vy = (w * sog * np.cos(np.where(ok, rad, 0.0))).sum(axis=1) / w.sum(axis=1)
    return vx, vy


#: A reported speed at most this (kn, the error of a reported velocity) is a stop.
STOP_KN = 0.3


def _reported_sog(pts: pd.DataFrame, rows: np.ndarray, valid: np.ndarray) -> np.ndarray | None:
    """Reported speeds (kn) over ``rows`` (NaN where not reported or not ``valid``); None
    when the table reports no speed."""
    if "speed" not in pts.columns:
        return None
    sog = pts["speed"].to_numpy(dtype="float64", na_value=np.nan)[rows]
    return np.where(valid, sog, np.nan)


def _median_sog(sog: np.ndarray | None) -> np.ndarray | None:
    """Per end: the median reported speed (kn), NaN where none."""
    if sog is None:
        return None
    out = np.full(len(sog), np.nan)
    have = np.isfinite(sog).any(axis=1)
    out[have] = np.nanmedian(sog[have], axis=1)
    return out


def _reported_stop(sog: np.ndarray) -> np.ndarray:
    """Per end: every reported speed (at least one) is at most :data:`STOP_KN` — the ship
    lay still, course or none."""
    ok = np.isfinite(sog)
    with np.errstate(invalid="ignore"):
        slow = (sog <= STOP_KN) | ~ok
    return ok.any(axis=1) & slow.all(axis=1)


#: The fewest fixes an end fit takes under ``end_span_s``: three, whose line fit shows
#: its noise as well as its motion.
END_MIN_FIXES = 3


def _span_widths(
    step_s: np.ndarray, end_span_s: float, k: int, k_max: int
) -> tuple[np.ndarray, np.ndarray]:
    """Per end: the fixes its fit takes (``1 + round(end_span_s / step_s)``, within
    [:data:`END_MIN_FIXES`, ``k``]; ``k`` where the step is unknown) and the most its
    straight-run fit may take (``k_max`` × that / ``k``): the same track time at any
    sampling (``end_span_s`` 450: 9 fixes of 1-min AIS, 3 of 3-min AIS, not 27 min)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        want = 1.0 + np.round(end_span_s / step_s)
    want = np.where(np.isfinite(want), want, k)
    kk = np.clip(want, min(END_MIN_FIXES, k), k).astype("int64")
    km = np.maximum(kk, np.round(kk * (max(k_max, k) / k))).astype("int64")
    return kk, km


def segment_stats(
    points: pd.DataFrame,
    end_points: int = 10,
    use_reported_motion: bool = True,
    end_points_max: int | None = None,
    end_span_s: float = 0.0,
) -> Segments:
    """Summaries of every track of ``points`` (any order) for association.

    ``end_points``: points per end fit; with ``end_points_max`` an end is fitted over 2×,
    4× … as many, up to that, while its fixes over the span show no acceleration
    (:func:`_straight_fits`). With ``use_reported_motion`` the end velocities come from the
    reported speed and course (AIS) over the last three points where present.
    ``end_span_s`` (s, 0 = off): an end fit takes the fixes of about that much track
    time at its end's median step, ``end_points`` at most and :data:`END_MIN_FIXES` at
    least, and ``end_points_max`` shrinks in proportion (:func:`_span_widths`).

    A table that must be sorted first is sorted on the columns read here only (with the
    input row of each); the others are gathered when asked for (``full_points``).
    """
    source = source_row = None
    extra = [c for c in points.columns if c not in _READ]
    if extra and points.columns.is_unique and known_order(points) is None:
        narrow = points[[c for c in points.columns if c in _READ]]
        narrow = narrow.assign(**{_ROW: np.arange(len(points), dtype="int64")})
        pts, index = sorted_with_index(narrow)
        source_row = pts[_ROW].to_numpy()
        if not np.array_equal(source_row, np.arange(len(points))):
            source = points
        else:  # already in order: the input itself is the sorted table
            pts, index = sorted_with_index(points)
            source_row = None
    else:
        pts, index = sorted_with_index(points)
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    t = track_seconds(pts)
    sizes = index.sizes
    k = max(int(end_points), 1)
    k_max = int(end_points_max or k)
    everyone = np.arange(len(sizes))
    head, valid, _ = _end_rows(index, everyone, k, head=True)
    tail, _, _ = _end_rows(index, everyone, k, head=False)
    sensor_code = pd.factorize(index.keys["sensor"])[0].astype("int64")
    step0, step1 = (_end_step(t, rows, valid, sensor_code) for rows in (head, tail))
    least0, least1 = (_end_least_step(t, rows, valid) for rows in (head, tail))
    widths = [(k, k_max), (k, k_max)]
    if end_span_s > 0:
        widths = [_span_widths(step, end_span_s, k, k_max) for step in (step0, step1)]
    (fit0, used0, accel0), (fit1, used1, accel1) = (
        _straight_fits(lon, lat, t, index, kk, km, h)
        for (kk, km), h in zip(widths, (True, False), strict=True)
    )
    (lon0, lat0, vx0, vy0, res0, pf0, vf0), (lon1, lat1, vx1, vy1, res1, pf1, vf1) = fit0, fit1
    offs = np.arange(k)
    motion0, motion1 = np.isfinite(vf0), np.isfinite(vf1)
    few = valid & (offs[None, :] < 3)  # the reported motion of an end: its three last fixes
    sog0, sog1 = _reported_sog(pts, head, few), _reported_sog(pts, tail, few)
    if use_reported_motion:
        for rows, (vx, vy), known, vf, sog in (
            (head, (vx0, vy0), motion0, vf0, sog0),
            (tail, (vx1, vy1), motion1, vf1, sog1),
        ):
            rep = _reported_velocity(pts, rows, few)
            have = np.zeros(len(vx), dtype=bool)
            if rep is not None:
                have = np.isfinite(rep[0])
                vx[have] = rep[0][have]
                vy[have] = rep[1][have]
                known |= have
                # A reported velocity is good to a few tenths of a knot.
                vf[have] = np.minimum(vf[have], 0.0)
            # A reported speed without a course still tells a stop: within the report's
            # own error of zero the velocity is zero whatever the heading.
            if sog is not None:
                stop = _reported_stop(sog) & ~have
                vx[stop] = 0.0
                vy[stop] = 0.0
                known |= stop
                vf[stop] = np.minimum(vf[stop], 0.0)

    # The time each end's own fit spans (over the fixes it used, up to end_points_max).
    span0 = t[index.starts + np.maximum(used0, 1) - 1] - t[index.starts]
    span1 = t[index.ends - 1] - t[index.ends - np.maximum(used1, 1)]
    # Noise per axis: each end's own residuals, or its sensor's median where it has too
    # few points (the whole table's median if no track of the sensor shows any).
    res = np.where(np.isfinite(res0), res0, res1)
    per_sensor = pd.Series(res).groupby(sensor_code).median()
    overall = float(np.nanmedian(res)) if np.isfinite(res).any() else 0.0
    fallback = per_sensor.reindex(sensor_code).fillna(overall).to_numpy()
    res0 = np.where(np.isfinite(res0), res0, fallback)
    res1 = np.where(np.isfinite(res1), res1, fallback)
    rep_sd = 0.3 * geo.KN_MS
    with np.errstate(invalid="ignore"):
        vel_sd0 = np.where(vf0 == 0.0, rep_sd, np.where(np.isfinite(vf0), res0 * vf0, np.inf))
        vel_sd1 = np.where(vf1 == 0.0, rep_sd, np.where(np.isfinite(vf1), res1 * vf1, np.inf))
    return Segments(
        points=pts,
        index=index,
        sensor_code=sensor_code,
        n=sizes,
        t0=t[index.starts],
        t1=t[index.ends - 1],
        lon0=lon0,
        lat0=lat0,
        lon1=lon1,
        lat1=lat1,
        vx0=vx0,
        vy0=vy0,
        vx1=vx1,
        vy1=vy1,
        pos_sd0=res0 * pf0,
        pos_sd1=res1 * pf1,
        vel_sd0=vel_sd0,
        vel_sd1=vel_sd1,
        motion0=motion0,
        motion1=motion1,
        noise0=res0,
        noise1=res1,
        sog0=_median_sog(sog0),
        sog1=_median_sog(sog1),
        accel0=accel0,
        accel1=accel1,
        step0=step0,
        step1=step1,
        span0=span0,
        span1=span1,
        source=source,
        source_row=source_row,
        least_step0=least0,
        least_step1=least1,
    )


#: The columns :func:`segment_stats` reads (``speed`` and ``course`` where reported), and
#: the input row it carries through a sort.
_READ = ("sensor", "batch", "time", "lon", "lat", "speed", "course")
_ROW = "_source_row"


def _track_shape(pts: pd.DataFrame, index: TrackIndex) -> dict:
    """Per track from its legs: the linear directional mean (deg), the open shoelace sum
    in the track's local frame (m²), that frame's origin, the first and last point in it
    (m), and the median sampling interval (s)."""
    n_tr = index.n_tracks
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    t = track_seconds(pts)
    same = np.zeros(len(pts), dtype=bool)
    if len(pts) > 1:
        same[1:] = index.track_of_row[1:] == index.track_of_row[:-1]
    legs = np.flatnonzero(same)
    ox, oy = track_origins(pts, index)
    x, y = local_xy(pts, index)
    # the legs' directions in the track's plane (north at its origin): taken from each
    # leg's own north they turned with the meridians' convergence along the track
    moved = (lon[legs] != lon[legs - 1]) | (lat[legs] != lat[legs - 1])
    lx, ly = x[legs[moved]] - x[legs[moved] - 1], y[legs[moved]] - y[legs[moved] - 1]
    norm = np.hypot(lx, ly)
    norm[norm == 0.0] = 1.0
    owner = index.track_of_row[legs[moved]]
    ldm = geo.wrap360(
        np.degrees(
            np.arctan2(np.bincount(owner, lx / norm, n_tr), np.bincount(owner, ly / norm, n_tr))
        )
    )
    ldm[np.bincount(owner, minlength=n_tr) == 0] = np.nan  # no leg that moves: no direction
    cross = np.bincount(
        index.track_of_row[legs],
        x[legs - 1] * y[legs] - y[legs - 1] * x[legs],
        n_tr,
    )
    dt = np.diff(t)[legs - 1] if len(legs) else np.zeros(0)
    period = (
        pd.Series(dt).groupby(index.track_of_row[legs]).median().reindex(range(n_tr)).to_numpy()
    )
    return {
        "ldm_deg": ldm,
        "cross": cross,
        "origin_lon": ox,
        "origin_lat": oy,
        "first_xy": np.column_stack([x[index.starts], y[index.starts]]),
        "last_xy": np.column_stack([x[index.ends - 1], y[index.ends - 1]]),
        "period_s": period,
    }


def chain_refit(
    seg: Segments,
    chain: np.ndarray,
    end_points: int = 10,
    accel_ms2: float = 0.0,
    drift_ms: float = np.inf,
    end_span_s: float = 0.0,
) -> tuple[Segments, np.ndarray]:
    """``seg`` with the ends of short pieces refitted over the chain each piece sits in.

    ``chain`` labels every track with its chain (tracks joined one after another, no two
    of a chain overlapping in time). A piece's end is fitted on the last ``end_points``
    fixes of its chain up to and including that end (its own and its predecessors'), its
    start on the first ``end_points`` fixes from it on (its own and its successors'): a
    single fix borrows the motion of its neighbours, and two fixes 460 m apart in noise
    get the steadier velocity of the longer track they continue. The position noise of
    the refitted end is the larger of the piece's own and the chain fit's residuals (a
    chain that is no straight line says so). An end is replaced only where the chain fit
    knows its velocity better (smaller ``vel_sd``) than the piece's own fit: long pieces
    and reported (AIS) motion keep theirs. Motion borrowed across gaps is trusted less
    the farther it reaches: ``accel_ms2`` × the time the fit spans beyond the piece (at
    most ``drift_ms``) is added to its velocity error.

    With ``end_span_s`` (s) each end takes the fixes of that much track time at its
    piece's median step instead (:func:`_span_widths`), a piece short when it has fewer.

    Returns the new summaries and, per track, whether either end was refitted.
    """
    from dataclasses import replace

    pts, index = seg.points, seg.index
    k = max(int(end_points), 1)
    n = len(seg)
    chain = np.asarray(chain)
    # The chains laid end to end, without moving a row: pieces in (chain, start) order,
    # ``off`` the place of each piece's first fix in that virtual sequence.
    porder = order_by(chain, seg.t0_rank)
    place = np.empty(n, dtype="int64")
    place[porder] = np.arange(n)
    off = np.concatenate([[0], np.cumsum(index.sizes[porder])])
    c_sorted = chain[porder]
    lo = off[np.searchsorted(c_sorted, chain, side="left")]
    hi = off[np.searchsorted(c_sorted, chain, side="right")]
    first = off[place]
    last = first + index.sizes - 1
    k0 = k1 = np.full(n, k)
    if end_span_s > 0 and seg.step0 is not None and seg.step1 is not None:
        k0 = _span_widths(seg.step0, end_span_s, k, k)[0]
        k1 = _span_widths(seg.step1, end_span_s, k, k)[0]
    # Only a piece shorter than the fit in a chain of several can change.
    short = np.flatnonzero((index.sizes < np.maximum(k0, k1)) & (hi - lo > index.sizes))
    changed = np.zeros(n, dtype=bool)
    if len(short) == 0:
        return seg, changed

    def row(v: np.ndarray) -> np.ndarray:
        q = np.searchsorted(off, v, side="right") - 1
        return index.starts[porder[q]] + (v - off[q])

    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    t = track_seconds(pts)
    offs = np.arange(k)
    lo_s, hi_s = lo[short][:, None], hi[short][:, None]
    tail = last[short][:, None] - offs
    valid1 = (tail >= lo_s) & (offs < k1[short][:, None])
    head = first[short][:, None] + offs
    valid0 = (head < hi_s) & (offs < k0[short][:, None])
    blocks = (
        ("0", row(np.minimum(head, hi_s - 1)), valid0, index.starts[short]),
        ("1", row(np.maximum(tail, lo_s)), valid1, index.ends[short] - 1),
    )
    own_span = seg.t1[short] - seg.t0[short]
    out = {}
    for end, rows, valid, anchor in blocks:
        flon, flat, bx, by, resid, pf, vf = _end_fit(lon, lat, t, rows, valid, anchor)
        own = getattr(seg, f"noise{end}")[short]
        noise = np.fmax(own, resid)
        # Motion borrowed across a gap holds only as well as the ship kept it: the time
        # the fit reaches beyond the piece adds accel × time (at most drift) of error.
        t_far = np.where(valid, t[rows], t[anchor][:, None])
        reach = np.abs(t_far - t[anchor][:, None]).max(axis=1)
        borrowed = np.minimum(accel_ms2 * np.maximum(reach - own_span, 0.0), drift_ms)
        with np.errstate(invalid="ignore"):
            vel_sd = np.where(np.isfinite(vf), np.hypot(noise * vf, borrowed), np.inf)
        better = vel_sd < getattr(seg, f"vel_sd{end}")[short]
        take = short[better]
        changed[take] = True
        new = {
            f"lon{end}": flon,
            f"lat{end}": flat,
            f"vx{end}": bx,
            f"vy{end}": by,
            f"pos_sd{end}": noise * pf,
            f"vel_sd{end}": vel_sd,
            f"motion{end}": np.ones(len(short), dtype=bool),
            f"noise{end}": noise,
        }
        for f, v in new.items():
            col = getattr(seg, f).copy()
            col[take] = v[better]
            out[f] = col
    return replace(seg, **out), changed


def ecef(lon: np.ndarray, lat: np.ndarray) -> np.ndarray:
    """Earth-centred coordinates in metres on the sphere (for spatial indexing)."""
    lo = np.radians(lon)
    la = np.radians(lat)
    return geo.EARTH_RADIUS_M * np.column_stack(
        [np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)]
    )

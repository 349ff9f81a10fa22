"""Maneuver detection by PCA heading and a maximum filter (seed 000, SPEC §3).

For every point ``o`` of a track (in its local plane, metres) the heading of the ``p``
points ending at ``o`` and of the ``p`` points starting at ``o`` is the direction of the
first principal component of their positions, oriented by the displacement from the
window's first to its last point. The maneuver factor δ_o is the absolute difference of
the two headings in [0°, 180°]. A maneuver point satisfies δ_o > t (condition 1) and
δ_o = max(δ_{o-n} … δ_{o+n}) (condition 2, mirror padding at the ends, one point per
plateau).

Everything runs on all tracks at once: window sums are accumulated by a loop over the
``p`` offsets (never over windows), the 2×2 PCA has a closed form, and the maximum
filter runs over all tracks concatenated with −∞ separators.

Sampling: ``p`` counts points. With irregular sampling a window still holds ``p`` points,
whatever time they span; resample first (cleaning) when the period varies a lot, or set
``window_s`` so that ``p`` is chosen per track from its median sampling interval.
"""

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.params import Params, param
from wakeline.core.tracks import TrackIndex, local_xy, sorted_with_index, track_seconds

MANEUVER_COLUMNS = ("sensor", "batch", "index", "time", "lon", "lat", "factor")


@dataclass(frozen=True)
class ManeuverParams(Params):
    """Parameters of the PCA + maximum-filter detector (seed 000 §3.1 defaults)."""

    window_p: int = param(
        5,
        "points",
        "points per heading window (p)",
        lo=2,
        hi=1000,
        source="ours; seed 000 leaves p open",
    )
    radius_n: int = param(
        5, "points", "maximum-filter radius (n)", lo=1, hi=1000, source="seed 000 §3.1"
    )
    threshold_deg: float = param(
        15.0,
        "deg",
        "smallest heading change that counts (t)",
        lo=0.0,
        hi=180.0,
        source="seed 000 §3.1",
    )
    window_s: float = param(
        0.0,
        "s",
        "if > 0: choose p per track as window_s / median sampling interval",
        lo=0.0,
        hi=1e7,
    )


#: Windows per block: temporaries of ~8 MB stay in the allocator's reusable heap, where
#: row-sized ones (80 MB at 10 M points) would be fresh pages every time.
BLOCK = 1 << 20


def window_headings(
    x: np.ndarray, y: np.ndarray, p: int, anchor: np.ndarray | None = None
) -> np.ndarray:
    """Heading (deg, [0, 360)) of the ``p`` points ending at each index; NaN for the first p-1.

    ``x``/``y`` are one track, or tracks concatenated (windows that straddle two tracks
    are the caller's to mask). Window sums are short convolutions, so nothing accumulates
    along the array; ``anchor`` (row numbers) says which point each row's coordinates are
    taken relative to — its track's first point keeps the numbers small, so E[u²] − E[u]²
    loses no precision. Work goes in blocks of ``BLOCK`` windows.
    """
    n = len(x)
    out = np.full(n, np.nan)
    if n < p:
        return out
    ref = np.zeros(n, dtype="int64") if anchor is None else anchor
    for first in range(p - 1, n, BLOCK):  # a loop over blocks, not over windows
        last = min(n, first + BLOCK)
        rows = slice(first - p + 1, last)
        u = x[rows] - x[ref[rows]]
        v = y[rows] - y[ref[rows]]
        out[first:last] = _block_headings(u, v, p)
    return out


def _block_headings(u: np.ndarray, v: np.ndarray, p: int) -> np.ndarray:
    n = len(u)
    ones = np.ones(p)
    mu = np.convolve(u, ones, "valid") / p
    mv = np.convolve(v, ones, "valid") / p
    cxx = np.convolve(u * u, ones, "valid") / p - mu * mu
    cyy = np.convolve(v * v, ones, "valid") / p - mv * mv
    cxy = np.convolve(u * v, ones, "valid") / p - mu * mv
    theta = 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)  # major axis, radians from +x
    ax, ay = np.cos(theta), np.sin(theta)
    # Orient by travel: from the window's first point to its last.
    flip = ax * (u[p - 1 :] - u[: n - p + 1]) + ay * (v[p - 1 :] - v[: n - p + 1]) < 0
    heading = np.degrees(np.arctan2(ax, ay)) + np.where(flip, 180.0, 0.0)
    return heading % 360.0


def maneuver_factor(x: np.ndarray, y: np.ndarray, index: TrackIndex, p: int) -> np.ndarray:
    """δ per point (deg in [0, 180]); NaN where a window would leave its track."""
    anchor = index.starts[index.track_of_row]
    h = window_headings(x, y, p, anchor)  # backward window ending at i
    n = len(x)
    delta = np.full(n, np.nan)
    if n < 2 * p - 1:
        return delta
    # The forward window starting at o is the backward window ending at o + p - 1.
    back = h[: n - p + 1]
    fwd = h[p - 1 :]
    d = geo.angle_diff(back, fwd)
    pos = np.arange(n) - anchor
    size = index.sizes[index.track_of_row]
    valid = (pos >= p - 1) & (pos <= size - p)
    delta[: n - p + 1] = d
    delta[~valid] = np.nan
    return delta


def local_maxima(delta: np.ndarray, index: TrackIndex, radius: int) -> np.ndarray:
    """Mask of points whose δ equals the maximum over ±radius within its track's valid span.

    Mirror padding and clipping give the same maximum (a mirrored value lies inside the
    window anyway), so tracks are concatenated with ``radius`` −∞ separators and one
    maximum filter runs over all of them. On a plateau only the first point is kept.
    """
    from scipy.ndimage import maximum_filter1d  # lazy: keeps `wakeline --help` fast

    finite = np.isfinite(delta)
    if not finite.any():
        return np.zeros(len(delta), dtype=bool)
    vals = np.where(finite, delta, -np.inf)
    # -inf gaps of `radius` between tracks keep windows from reaching a neighbour track.
    n = len(vals)
    slots = np.arange(n) + index.track_of_row * radius
    padded = np.full(n + index.n_tracks * radius, -np.inf)
    padded[slots] = vals
    filtered = maximum_filter1d(padded, size=2 * radius + 1, mode="constant", cval=-np.inf)[slots]
    peak = finite & (vals == filtered)
    # One point per plateau: drop a peak when an equal peak precedes it within the radius.
    track = index.track_of_row
    for k in range(1, radius + 1):
        earlier = np.zeros(n, dtype=bool)
        earlier[k:] = peak[:-k] & (vals[:-k] == vals[k:]) & (track[:-k] == track[k:])
        peak &= ~earlier
    return peak


@dataclass(frozen=True)
class ManeuverResult:
    """Detector output over a sorted point table."""

    points: pd.DataFrame  # the sorted input
    index: TrackIndex
    factor: np.ndarray  # δ per point, deg (NaN where undefined)
    is_maneuver: np.ndarray  # bool per point
    window_p: np.ndarray  # p used for each track

    def table(self) -> pd.DataFrame:
        """One row per maneuver point: sensor, batch, index, time, lon, lat, factor.

        Rows are taken column by column (``take`` on the Arrow/numpy arrays), never by
        converting a whole column to Python objects."""
        rows = np.flatnonzero(self.is_maneuver)
        sub = self.points[["sensor", "batch", "time", "lon", "lat"]].iloc[rows]
        sub = sub.reset_index(drop=True)
        out = pd.DataFrame(
            {
                "sensor": sub["sensor"],
                "batch": sub["batch"],
                "index": (rows - self.index.starts[self.index.track_of_row[rows]]).astype("int64"),
                "time": sub["time"],
                "lon": sub["lon"],
                "lat": sub["lat"],
                "factor": self.factor[rows],
            }
        )
        return out.astype({"sensor": "str", "batch": "str"})


def _p_per_track(t: np.ndarray, index: TrackIndex, params: ManeuverParams) -> np.ndarray:
    p = np.full(index.n_tracks, int(params.window_p), dtype="int64")
    if params.window_s > 0:
        dt = np.diff(t, prepend=np.nan)
        dt[index.starts] = np.nan
        med = (
            pd.Series(dt)
            .groupby(index.track_of_row)
            .median()
            .reindex(range(index.n_tracks))
            .to_numpy()
        )
        with np.errstate(invalid="ignore", divide="ignore"):
            chosen = np.where(
                np.isfinite(med) & (med > 0), np.round(params.window_s / med), params.window_p
            )
        p = np.clip(chosen, 2, 1000).astype("int64")
    return p


def detect(
    points: pd.DataFrame, params: ManeuverParams | None = None, progress=None
) -> ManeuverResult:
    """Run the detector on every track of a canonical table."""
    params = (params or ManeuverParams()).checked()
    pts, index = sorted_with_index(points)
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    p_track = _p_per_track(t, index, params)
    factor = np.full(len(pts), np.nan)
    distinct = np.unique(p_track)
    if len(distinct) == 1:  # one p for all (usual): no row selection, no sub-index
        if progress:
            progress(0.0, f"maneuver factor, p = {distinct[0]}")
        factor = maneuver_factor(x, y, index, int(distinct[0]))
        distinct = distinct[:0]
    for k, p in enumerate(distinct):  # one pass per distinct p (usually one)
        if progress:
            progress(k / len(distinct), f"maneuver factor, p = {p}")
        rows = np.flatnonzero(p_track[index.track_of_row] == p)
        sub = TrackIndex(*_sub_index(index, p_track == p))
        factor[rows] = maneuver_factor(x[rows], y[rows], sub, int(p))
    peaks = local_maxima(factor, index, int(params.radius_n))
    is_maneuver = peaks & (factor > params.threshold_deg)
    return ManeuverResult(pts, index, factor, is_maneuver, p_track)


def _sub_index(index: TrackIndex, selected: np.ndarray):
    sizes = index.sizes[selected]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype("int64")
    ends = starts + sizes
    track_of_row = np.repeat(np.arange(len(sizes)), sizes)
    return starts, ends, track_of_row, index.keys[selected].reset_index(drop=True)


def smallest_detectable_turn_deg(
    eps_m: float, speed_kn: float, t1_s: float, t2_s: float | None = None
) -> float:
    """Seed 000 eq. 10: the smallest turn (deg) that position errors of at most ``eps_m``
    cannot fake, for legs of ``t1_s`` and ``t2_s`` seconds at ``speed_kn``."""
    t2_s = t1_s if t2_s is None else t2_s
    v = speed_kn * geo.KN_MS
    return 180.0 - math.degrees(
        math.atan(v * t1_s / (2 * eps_m)) + math.atan(v * t2_s / (2 * eps_m))
    )


def largest_tolerable_error_m(threshold_deg: float, speed_kn: float, leg_s: float) -> float:
    """Seed 000 eq. 12 (equal legs): the largest position error (m) for which a turn of
    ``threshold_deg`` stays above the noise; 16 kn, 30 min legs, 15° → ≈ 975 m."""
    v = speed_kn * geo.KN_MS
    return v * leg_s / (2.0 * math.tan(math.radians(180.0 - threshold_deg) / 2.0))

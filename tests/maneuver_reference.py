"""Maneuver detection by PCA heading and a maximum filter (seed 000, SPEC §3).

(Frozen reference copy; since h79 its ``_scales`` ends with ``max_window_s`` itself and the
default ``max_window_s`` is 320 s, as in core/maneuver.py.)

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

Time, not points (ours, docs/evaluation.md "Departures: cleaning, maneuvers, compression"):
the window is ``window_s`` seconds, turned into ``p`` points per track from its median
sampling interval (never fewer than ``window_p``), so one default serves 1 s radar and
5 min plots alike; ``window_s = 0`` is the paper's fixed ``p``. Gradual turns: the window
doubles up to ``max_window_s`` and a turn seen only at a longer window is added where no
turn lies within one window of it. Turns that take a while: the first scale's windows are
also compared ``gap_s`` apart (the turn itself between them; the gapped δ must also exceed
t at the neighbouring points). Sharp turns close together (radar): the window also halves
down to ``min_window_s`` on tracks sampled fast enough for 3 points in it; such a turn must
clear the noise floor (at least t) with its own point left out too, so one stray plot is
no turn. Each added turn needs no turn already found within its reach.
No maneuver where the ship covers either window slower
than ``min_speed_kn`` or where a window touches an at-rest span (cleaning's stationary
rule: positions within ``rest_radius_m`` for ``rest_window_s``). ``ManeuverParams.paper()``
switches all of these off.
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
    """Parameters of the PCA + maximum-filter detector (seed 000 §3.1 defaults for p, n, t;
    windows in seconds, gradual turns, minimum speed and at-rest spans are ours)."""

    window_p: int = param(
        5,
        "points",
        "points per heading window (p); with window_s > 0 the fewest points per window",
        lo=2,
        hi=1000,
        source="ours; seed 000 leaves p open",
    )
    radius_n: int = param(
        5,
        "points",
        "maximum-filter radius (n); at least one window at each scale",
        lo=1,
        hi=1000,
        source="seed 000 §3.1",
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
        10.0,
        "s",
        "heading window in seconds: p per track = window_s / its median sampling interval "
        "(never fewer than window_p points); 0 = p points whatever time they span (paper)",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    max_window_s: float = param(
        320.0,
        "s",
        "gradual turns: the longest window; windows double from window_s while within it and "
        "end with it (10 s: 10, 20, ..., 320 s); a turn found only at a longer window counts "
        "where no shorter-window turn lies within that window; 0 = one scale",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    min_speed_kn: float = param(
        1.0,
        "kn",
        "no maneuver where the ship covers its window before or after slower than this",
        lo=0.0,
        hi=100.0,
        source="ours; seed 001 eq. 1's 1 kn",
    )
    slow_side: float = param(
        1.0,
        "",
        "the slower window needs only this share of min_speed_kn (the faster one all of it)",
        lo=0.0,
        hi=1.0,
    )
    noise_k: float = param(
        2.0,
        "",
        "a turn must also exceed this many standard deviations of the heading change that the "
        "track's own position noise gives its two windows (noise estimated per track); 0 = off",
        lo=0.0,
        hi=100.0,
        source="ours; seed 000 eq. 10-12 make the same point with a fixed error",
    )
    noise_lag_s: float = param(
        0.0, "s", "noise against the points this many seconds either side; 0 = neighbours"
    )
    noise_min_span: float = param(
        0.0, "sigma", "each window spans this many track-noise sigma, else no turn; 0 = off"
    )
    noise_k_windows: bool = param(
        False, "", "k = max(noise_k, sqrt(2 ln N)), N = track points / window points"
    )
    noise_min_windows: float = param(
        0.0, "windows", "the two above only where track points / window points >= this"
    )
    gap_s: float = param(
        10.0,
        "s",
        "turns that take a while: the first scale's windows are also compared with this many "
        "seconds between them (the turn itself left out; tracks sampled at least every "
        "gap_s, one point each side at least); 0 = off",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    min_window_s: float = param(
        5.0,
        "s",
        "sharp turns close together: windows also halve from window_s down to this duration "
        "on tracks sampled fast enough for 3 points in it; a turn found there counts when it "
        "also clears the noise floor with its own plot left out, and no turn already found "
        "lies within that window; 0 = off",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    rest_radius_m: float = param(
        50.0,
        "m",
        "at-rest spans (cleaning's stationary rule) are no maneuvers; 0 = off",
        lo=0.0,
        hi=1e5,
    )
    rest_window_s: float = param(
        180.0, "s", "at rest: the shortest stay that counts", lo=1.0, hi=1e7
    )
    rest_steps: float = param(  # added with core (session 18): sparse tracks' stays
        1.0, "intervals", "at rest: the stay spans this many median intervals", lo=0.0, hi=1000.0
    )

    @classmethod
    def paper(cls) -> "ManeuverParams":
        """Seed 000 as written: p points per window, one scale, no speed or rest rule."""
        return cls(
            window_s=0.0,
            max_window_s=0.0,
            min_speed_kn=0.0,
            rest_radius_m=0.0,
            noise_k=0.0,
            min_window_s=0.0,
            gap_s=0.0,
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
    # The same arithmetic, operation for operation, as mean / covariance / closed-form PCA
    # written plainly; done in place so a block allocates a handful of arrays, not twenty.
    n = len(u)
    ones = np.ones(p)
    mu = np.convolve(u, ones, "valid")
    mu /= p
    mv = np.convolve(v, ones, "valid")
    mv /= p
    tmp = np.multiply(u, u)
    cxx = np.convolve(tmp, ones, "valid")
    cxx /= p
    cxx -= np.multiply(mu, mu, out=tmp[: n - p + 1])
    np.multiply(v, v, out=tmp)
    cyy = np.convolve(tmp, ones, "valid")
    cyy /= p
    cyy -= np.multiply(mv, mv, out=tmp[: n - p + 1])
    np.multiply(u, v, out=tmp)
    cxy = np.convolve(tmp, ones, "valid")
    cxy /= p
    cxy -= np.multiply(mu, mv, out=tmp[: n - p + 1])
    cxy *= 2.0
    cxx -= cyy
    theta = np.arctan2(cxy, cxx, out=cxy)
    theta *= 0.5  # major axis, radians from +x
    ax, ay = np.cos(theta, out=cxx), np.sin(theta, out=cyy)
    # Orient by travel: from the window's first point to its last.
    du = np.subtract(u[p - 1 :], u[: n - p + 1], out=mu)
    du *= ax
    dv = np.subtract(v[p - 1 :], v[: n - p + 1], out=mv)
    dv *= ay
    du += dv
    flip = du < 0
    heading = np.arctan2(ax, ay, out=theta)
    np.degrees(heading, out=heading)
    heading += 0.0  # as the plain form's "+ where(flip, 180, 0)": -0.0 becomes 0.0
    heading[flip] += 180.0
    return np.remainder(heading, 360.0, out=heading)


def maneuver_factor(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, p: int, gap: int = 0
) -> np.ndarray:
    """δ per point (deg in [0, 180]); NaN where a window would leave its track. ``gap``: the
    backward window ends ``gap`` points before the point and the forward one starts
    ``gap`` points after it (0: both at the point, seed 000)."""
    anchor = index.starts[index.track_of_row]
    h = window_headings(x, y, p, anchor)  # backward window ending at i
    n = len(x)
    delta = np.full(n, np.nan)
    q = int(gap)
    if n < 2 * p - 1 + 2 * q:
        return delta
    # The forward window starting at o + q is the backward window ending at o + q + p - 1.
    back = h[: n - p + 1 - 2 * q]
    fwd = h[p - 1 + 2 * q :]
    d = geo.angle_diff(back, fwd)
    pos = np.arange(n) - anchor
    size = index.sizes[index.track_of_row]
    valid = (pos >= p - 1 + q) & (pos <= size - p - q)
    delta[q : n - p + 1 - q] = d
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
    # One point per plateau: drop a peak when a peak (as it stands before offset k)
    # precedes it by k rows in its track, for k = 1 … radius. Two peaks of one track within
    # the radius are equal (each is the other's window maximum), so only such clustered
    # peaks are touched, and the loop runs over them alone.
    rows = np.flatnonzero(peak)
    track = index.track_of_row
    if len(rows) > 1:
        close = (np.diff(rows) <= radius) & (track[rows[1:]] == track[rows[:-1]])
        if close.any():
            clustered = np.zeros(len(rows), dtype=bool)
            clustered[1:] |= close
            clustered[:-1] |= close
            q = rows[clustered]
            alive = np.ones(len(q), dtype=bool)
            for k in range(1, radius + 1):  # a loop over offsets, on the clustered peaks only
                pos = np.minimum(np.searchsorted(q, q - k), len(q) - 1)
                hit = (q[pos] == q - k) & alive[pos] & (track[q[pos]] == track[q])
                alive &= ~hit
            peak[q[~alive]] = False
    return peak


@dataclass(frozen=True)
class ManeuverResult:
    """Detector output over a sorted point table."""

    points: pd.DataFrame  # the sorted input
    index: TrackIndex
    factor: np.ndarray  # δ per point, deg (NaN where undefined)
    is_maneuver: np.ndarray  # bool per point
    window_p: np.ndarray  # p used for each track (first scale)
    at_rest: np.ndarray | None = None  # bool per point: in an at-rest span
    params: ManeuverParams | None = None  # the parameters used

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


def median_interval_s(t: np.ndarray, index: TrackIndex) -> np.ndarray:
    """Median sampling interval (s) of each track; NaN for one-point tracks."""
    dt = np.diff(t, prepend=np.nan)
    dt[index.starts] = np.nan
    return (
        pd.Series(dt).groupby(index.track_of_row).median().reindex(range(index.n_tracks)).to_numpy()
    )


def _p_per_track(
    t: np.ndarray,
    index: TrackIndex,
    params: ManeuverParams,
    window_s: float | None = None,
    med: np.ndarray | None = None,
) -> np.ndarray:
    """Points per window for each track: ``window_s`` over the track's median interval
    (``med``, computed when not given), never fewer than ``window_p``; ``window_p`` itself
    when no duration is given."""
    window_s = params.window_s if window_s is None else window_s
    p = np.full(index.n_tracks, int(params.window_p), dtype="int64")
    if window_s > 0:
        med = median_interval_s(t, index) if med is None else med
        with np.errstate(invalid="ignore", divide="ignore"):
            chosen = np.where(np.isfinite(med) & (med > 0), np.round(window_s / med), 0)
        p = np.clip(np.maximum(chosen, params.window_p), 2, 1000).astype("int64")
    return p


def _scales(params: ManeuverParams) -> list[float]:
    """Window durations (s): window_s doubled while within max_window_s, then max_window_s
    itself when the doubling does not land on it (10 s up to 320 s: 10, 20, ..., 320; 8 s:
    8, 16, ..., 256, 320); [0] = points only."""
    if params.window_s <= 0:
        return [0.0]
    out = [float(params.window_s)]
    top = float(params.max_window_s)
    if top <= params.window_s * (1 + 1e-9):  # 0 = one scale; none shorter than window_s
        return out
    while out[-1] * 2 <= top * (1 + 1e-9):
        out.append(out[-1] * 2)
    if out[-1] < top * (1 - 1e-9):
        out.append(float(top))
    return out


def _fine_scales(params: ManeuverParams) -> list[float]:
    """Window durations (s) below window_s: halved down to min_window_s."""
    if params.window_s <= 0 or params.min_window_s <= 0:
        return []
    out = []
    d = params.window_s / 2
    while d >= params.min_window_s * (1 - 1e-9):
        out.append(d)
        d /= 2
    return out


def _near(
    mask: np.ndarray, index: TrackIndex, reach: np.ndarray, rows: np.ndarray | None = None
) -> np.ndarray:
    """Per row (or per row of ``rows``): is a ``mask`` row of the same track within
    ±``reach`` rows (``reach`` per row, aligned with ``rows`` when given)?"""
    cs = np.concatenate([[0], np.cumsum(mask)])
    row = np.arange(len(mask)) if rows is None else rows
    tr = index.track_of_row[row]
    lo = np.maximum(row - reach, index.starts[tr])
    hi = np.minimum(row + reach + 1, index.ends[tr])
    return cs[hi] - cs[lo] > 0


def position_noise_m(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, lag: np.ndarray | int = 1
) -> np.ndarray:
    """Per track: position noise std per axis (m), robust: the median distance of each point
    from the time interpolation of the points ``lag`` before and after it (``lag`` per
    track; a lag of a window also catches error that wanders over the window, as a radar's
    reflection centre does along a hull), scaled for Gaussian noise."""
    n = len(x)
    tr = index.track_of_row
    out = np.zeros(index.n_tracks)
    lag_row = np.broadcast_to(np.asarray(lag, dtype="int64"), (index.n_tracks,))[tr] if n else tr
    row = np.arange(n)
    a, b = row - lag_row, row + lag_row
    ok = (a >= index.starts[tr]) & (b < index.ends[tr])
    i, a, b = row[ok], a[ok], b[ok]
    if not len(i):
        return out
    span = t[b] - t[a]
    w = np.where(span > 0, (t[i] - t[a]) / np.where(span > 0, span, 1.0), 0.5)
    ex = x[i] - ((1 - w) * x[a] + w * x[b])
    ey = y[i] - ((1 - w) * y[a] + w * y[b])
    # each axis' residual has variance sigma^2 (1 + w^2 + (1-w)^2); |e| of 2-D Gaussian
    # noise has median sigma * sqrt(2 ln 2)
    r = np.hypot(ex, ey) / np.sqrt(1 + w**2 + (1 - w) ** 2) / np.sqrt(2 * np.log(2))
    med = pd.Series(r).groupby(tr[i]).median()
    out[med.index.to_numpy()] = med.to_numpy()
    return out


def _heading_noise_deg(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    sigma: np.ndarray,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """Std (deg) of δ from position noise: each window's PCA heading errs by about
    σ / L · sqrt(12 / p) rad for p points spread over L metres (a line fit's slope).
    Per row, or per row of ``rows`` (``p_row`` aligned with them)."""
    n = len(x)
    row = np.arange(n) if rows is None else rows
    a = np.clip(row - p_row + 1, 0, n - 1)
    b = np.clip(row + p_row - 1, 0, n - 1)
    xo, yo = x[row], y[row]
    with np.errstate(invalid="ignore", divide="ignore"):
        lb = np.hypot(xo - x[a], yo - y[a])
        lf = np.hypot(x[b] - xo, y[b] - yo)
        s = sigma[index.track_of_row[row]] * np.sqrt(12.0 / p_row)
        return np.degrees(np.hypot(s / lb, s / lf))


def _window_speed_ms(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """The slower of the straight-line speeds (m/s) over the window ending at each point
    and the one starting there (p points each); NaN where a window leaves the track.
    Per row, or per row of ``rows`` (``p_row`` aligned with them)."""
    n = len(x)
    row = np.arange(n) if rows is None else rows
    tr = index.track_of_row[row]
    a = row - p_row + 1
    b = row + p_row - 1
    ok = (a >= index.starts[tr]) & (b < index.ends[tr])
    a = np.clip(a, 0, n - 1)
    b = np.clip(b, 0, n - 1)
    xo, yo, to = x[row], y[row], t[row]
    with np.errstate(invalid="ignore", divide="ignore"):
        v_back = np.hypot(xo - x[a], yo - y[a]) / (to - t[a])
        v_fwd = np.hypot(x[b] - xo, y[b] - yo) / (t[b] - to)
    return np.where(ok, np.fmin(v_back, v_fwd), np.nan)


def _faster_window_speed_ms(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, p_row: np.ndarray, rows
) -> np.ndarray:
    """The faster of the two windows' straight-line speeds (m/s); NaN as above."""
    n = len(x)
    tr = index.track_of_row[rows]
    a, b = rows - p_row + 1, rows + p_row - 1
    ok = (a >= index.starts[tr]) & (b < index.ends[tr])
    a, b = np.clip(a, 0, n - 1), np.clip(b, 0, n - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        v_back = np.hypot(x[rows] - x[a], y[rows] - y[a]) / (t[rows] - t[a])
        v_fwd = np.hypot(x[b] - x[rows], y[b] - y[rows]) / (t[b] - t[rows])
    return np.where(ok, np.fmax(v_back, v_fwd), np.nan)


def _one_scale(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_track: np.ndarray,
    radius: np.ndarray,
    active: np.ndarray | None = None,
    gap: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """δ per point and its local maxima (radius per track), one pass per distinct p; only
    on the ``active`` tracks when given (NaN and no peak elsewhere)."""
    factor = np.full(len(x), np.nan)
    peaks = np.zeros(len(x), dtype=bool)
    active = np.ones(index.n_tracks, dtype=bool) if active is None else active
    for p in np.unique(p_track[active]):  # usually one or a few
        chosen = (p_track == p) & active
        rows = np.flatnonzero(chosen[index.track_of_row])
        sub = TrackIndex(*_sub_index(index, chosen))
        factor[rows] = maneuver_factor(x[rows], y[rows], sub, int(p), gap)
        for r in np.unique(radius[chosen]):
            same_r = chosen & (radius == r)
            rr = np.flatnonzero(same_r[index.track_of_row])
            sub_r = TrackIndex(*_sub_index(index, same_r))
            peaks[rr] = local_maxima(factor[rr], sub_r, int(r))
    return factor, peaks


def _rest_mask(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    radius_m: float,
    window_s: float,
    steps: float = 0.0,
) -> np.ndarray:
    """Cleaning's at-rest rule (:func:`wakeline.core.clean.at_rest`), run only on the tracks
    that can hold a stay: a stay ending at a point covers every fix of the last
    ``window_s`` before it, so somewhere the point and the first fix of that window lie
    within 2·``radius_m``, at least ``window_s`` after the track's first fix. Tracks that
    never do are left out (same result, less work)."""
    from wakeline.core.clean import at_rest, rest_frame  # the same rule cleaning uses

    n = len(x)
    rest = np.zeros(n, dtype=bool)
    if n == 0:
        return rest
    x, y, t = rest_frame(x, y, t, index, window_s, steps)
    tr = index.track_of_row
    rel = t - t[index.starts[tr]]
    span = np.zeros(index.n_tracks)
    has = index.sizes > 0
    span[has] = rel[index.ends[has] - 1]
    offset = np.concatenate([[0.0], np.cumsum(span + 2.0 * window_s + 1.0)[:-1]])
    ts = rel + offset[tr]
    # first fix at or after t - window_s (a little later, so rounding never widens it)
    a = np.searchsorted(ts, ts - window_s + 1e-3)
    close = (np.hypot(x - x[a], y - y[a]) <= 2.0 * radius_m * (1 + 1e-9) + 1e-6) & (
        rel >= window_s * (1 - 1e-9)
    )
    possible = np.zeros(index.n_tracks, dtype=bool)
    possible[tr[close]] = True
    if not possible.any():
        return rest
    if possible.all():
        return at_rest(x, y, t, index, radius_m, window_s)
    rows = np.flatnonzero(possible[tr])
    sub = TrackIndex(*_sub_index(index, possible))
    rest[rows] = at_rest(x[rows], y[rows], t[rows], sub, radius_m, window_s)
    return rest


def _gathered_headings(x: np.ndarray, y: np.ndarray, first: np.ndarray, p: int) -> np.ndarray:
    """PCA heading (deg) of the ``p`` points from each row of ``first`` (a few candidate
    windows, gathered as a candidates × p block), oriented first to last point."""
    rows = first[:, None] + np.arange(p)
    u = x[rows] - x[first][:, None]
    v = y[rows] - y[first][:, None]
    u0, v0 = u - u.mean(axis=1, keepdims=True), v - v.mean(axis=1, keepdims=True)
    cxx, cyy, cxy = (u0 * u0).mean(axis=1), (v0 * v0).mean(axis=1), (u0 * v0).mean(axis=1)
    theta = 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)
    ax, ay = np.cos(theta), np.sin(theta)
    flip = (u[:, -1] - u[:, 0]) * ax + (v[:, -1] - v[:, 0]) * ay < 0
    return np.remainder(np.degrees(np.arctan2(ax, ay)) + np.where(flip, 180.0, 0.0), 360.0)


def _leave_one_out_deg(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, p_c: np.ndarray, cand: np.ndarray
) -> np.ndarray:
    """Per candidate o: the heading change between the ``p`` points before o and the ``p``
    after it, o itself left out (a single stray plot bends both of o's own windows, and
    neither of these); NaN where a window would leave the track."""
    out = np.full(len(cand), np.nan)
    tr = index.track_of_row[cand]
    ok = (cand - p_c >= index.starts[tr]) & (cand + p_c < index.ends[tr])
    for p in np.unique(p_c[ok]):  # a few distinct window sizes
        sel = ok & (p_c == p)
        o = cand[sel]
        out[sel] = geo.angle_diff(
            _gathered_headings(x, y, o - p, int(p)), _gathered_headings(x, y, o + 1, int(p))
        )
    return out


def detect(
    points: pd.DataFrame, params: ManeuverParams | None = None, progress=None
) -> ManeuverResult:
    """Run the detector on every track of a canonical table.

    At the first window duration the paper's rule runs as written (δ > t and the maximum
    within ±n points). Gradual turns: at each doubled duration up to ``max_window_s`` a peak
    above t counts where no turn already found lies within one window of it. Turns that
    take a while: the first scale's windows ``gap_s`` apart. Sharp turns close together:
    windows halved down to ``min_window_s`` where 3 points fit, a turn counting only when it
    clears the noise floor with its own point left out. Every added turn needs no turn
    already found within its reach. No maneuver inside an at-rest span, on a window touching
    one, or where the ship covers a window slower than ``min_speed_kn``. The extra tests run
    on the candidates (peaks above t) only.
    """
    params = (params or ManeuverParams()).checked()
    pts, index = sorted_with_index(points)
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    tr = index.track_of_row
    noise: list[np.ndarray] = []  # the track noise, computed when first needed
    rest = np.zeros(len(pts), dtype=bool)
    if params.rest_radius_m > 0 and len(pts):
        rest = _rest_mask(
            x, y, t, index, params.rest_radius_m, params.rest_window_s, params.rest_steps
        )
    any_rest = bool(rest.any())

    def accept(f: np.ndarray, cand: np.ndarray, p_c: np.ndarray, reach: np.ndarray, fine: bool):
        """The candidates that clear the noise floor (always at a fine scale, with the
        candidate's own point left out too), the minimum speed over ``reach`` points and
        the at-rest spans."""
        ok = np.ones(len(cand), dtype=bool)
        if not len(cand):
            return ok
        if params.noise_k > 0 or fine:
            if not noise:
                lag = 1
                if params.noise_lag_s > 0:  # session 18: noise over a window's length
                    med_ = median_interval_s(t, index)
                    with np.errstate(invalid="ignore", divide="ignore"):
                        ok_ = np.isfinite(med_) & (med_ > 0)
                        lag = np.where(ok_, np.round(params.noise_lag_s / med_), 1)
                    lag = np.clip(lag, 1, 1000).astype("int64")
                noise.append(position_noise_m(x, y, t, index, lag))
            k = params.noise_k
            # h178, session 28: the two h170 options only on tracks with enough windows
            # (the track's points / its first scale's window points)
            p_one = _p_per_track(t, index, params, scales[0], med)[index.track_of_row[cand]]
            size = index.sizes[index.track_of_row[cand]]
            gated = size >= params.noise_min_windows * np.maximum(p_one, 1)
            if params.noise_k > 0 and params.noise_k_windows:  # h170, session 27
                n_win = np.maximum(index.sizes[index.track_of_row[cand]] / p_c, 1.0)
                k = np.maximum(params.noise_k, np.sqrt(2.0 * np.log(n_win)))
                k = np.where(gated, k, params.noise_k)
            with np.errstate(invalid="ignore"):
                floor = np.maximum(
                    k * _heading_noise_deg(x, y, index, p_c, noise[0], cand),
                    params.threshold_deg,
                )
                ok &= f[cand] > floor
                if params.noise_k > 0 and params.noise_min_span > 0:  # h170, session 27
                    a = np.clip(cand - p_c + 1, 0, len(x) - 1)
                    b = np.clip(cand + p_c - 1, 0, len(x) - 1)
                    span_m = params.noise_min_span * noise[0][index.track_of_row[cand]]
                    lb = np.hypot(x[cand] - x[a], y[cand] - y[a])
                    lf = np.hypot(x[b] - x[cand], y[b] - y[cand])
                    ok &= ~((lb < span_m) | (lf < span_m)) | ~gated
                if fine:
                    ok &= _leave_one_out_deg(x, y, index, p_c, cand) > floor
        if params.min_speed_kn > 0:
            speed = params.min_speed_kn * geo.KN_MS
            with np.errstate(invalid="ignore"):
                ok &= _window_speed_ms(x, y, t, index, reach, cand) >= params.slow_side * speed
                ok &= _faster_window_speed_ms(x, y, t, index, reach, cand) >= speed
        if any_rest:
            ok &= ~_near(rest, index, reach - 1, cand)
        return ok

    def add(f: np.ndarray, cand: np.ndarray, ok: np.ndarray, reach: np.ndarray) -> None:
        new = cand[ok]
        new = new[~_near(found, index, reach[ok], new)]
        factor[new] = f[new]
        found[new] = True

    scales = _scales(params)
    fine_scales = _fine_scales(params)
    med = median_interval_s(t, index) if params.window_s > 0 else None
    found = np.zeros(len(pts), dtype=bool)
    factor = np.full(len(pts), np.nan)
    p_first = np.full(index.n_tracks, int(params.window_p), dtype="int64")
    prev_p = np.zeros(index.n_tracks, dtype="int64")
    n_steps = len(scales) + len(fine_scales) + (params.gap_s > 0)
    for k, duration in enumerate(scales):
        if progress:
            progress(k / n_steps, f"maneuver factor, {duration:g} s windows")
        p_track = _p_per_track(t, index, params, duration, med)
        if k > 0:
            # tracks whose window did not grow at this duration have nothing new to find
            grew = p_track > prev_p
            if not grew.any():
                continue
        radius = (
            np.maximum(p_track, params.radius_n)
            if k > 0
            else np.full_like(p_track, params.radius_n)
        )
        f_k, peaks = _one_scale(x, y, index, p_track, radius, grew if k > 0 else None)
        with np.errstate(invalid="ignore"):
            cand = np.flatnonzero(peaks & (f_k > params.threshold_deg))
        p_c = p_track[tr[cand]]
        ok = accept(f_k, cand, p_c, p_c, fine=False)
        if k == 0:
            factor, p_first = f_k, p_track
            found[cand[ok]] = True
        else:
            add(f_k, cand, ok, p_c)
        prev_p = p_track
    if params.gap_s > 0 and med is not None:
        if progress:
            progress(len(scales) / n_steps, f"maneuver factor, windows {params.gap_s:g} s apart")
        with np.errstate(invalid="ignore", divide="ignore"):
            gap = np.where(np.isfinite(med) & (med > 0), np.round(params.gap_s / med / 2), 0)
        gap = gap.astype("int64")  # points left out either side of the point
        for g in np.unique(gap[gap > 0]):  # a few distinct gaps
            f_g, peaks = _one_scale(x, y, index, p_first, p_first + g, gap == g, int(g))
            with np.errstate(invalid="ignore"):
                cand = np.flatnonzero(peaks & (f_g > params.threshold_deg))
            p_c = p_first[tr[cand]]
            ok = accept(f_g, cand, p_c, p_c + g, fine=False)
            # a turn that takes a while bends the gapped windows at the neighbouring points
            # too; one noisy window pair does not
            lo, hi = np.maximum(cand - 1, 0), np.minimum(cand + 1, len(f_g) - 1)
            with np.errstate(invalid="ignore"):
                ok &= np.fmin(f_g[lo], f_g[hi]) > params.threshold_deg
            add(f_g, cand, ok, p_c + g)
    shortest = p_first
    for k, duration in enumerate(fine_scales):
        if progress:
            progress((len(scales) + k + 1) / n_steps, f"maneuver factor, {duration:g} s windows")
        with np.errstate(invalid="ignore", divide="ignore"):
            chosen = np.where(np.isfinite(med) & (med > 0), np.round(duration / med), 0)
        p_track = np.clip(chosen, 3, 1000).astype("int64")
        # only where 3 points fit and the window is shorter than any before
        active = (chosen >= 3) & (p_track < shortest)
        if not active.any():
            continue
        f_k, peaks = _one_scale(x, y, index, p_track, p_track, active)
        with np.errstate(invalid="ignore"):
            cand = np.flatnonzero(peaks & (f_k > params.threshold_deg))
        p_c = p_track[tr[cand]]
        add(f_k, cand, accept(f_k, cand, p_c, p_c, fine=True), p_c)
        shortest = np.where(active, p_track, shortest)
    if progress:
        progress(1.0, "maneuvers found")
    return ManeuverResult(pts, index, factor, found, p_first, rest, params)


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

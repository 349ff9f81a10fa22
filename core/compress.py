"""Track compression to turning points, and its distance error Dis_e (seed 000 §3.3).

A compressed track is a polyline in time: knots at the kept points' times, positions at
the knots. Every original point is reconstructed on it by time interpolation, and Dis_e
is the mean distance (metres) between reconstructed and original positions
(synchronized Euclidean distance) — against the observed points, and against the true
path where the table carries ``true_lon``/``true_lat`` (simulations).

Vertex placement: the paper keeps the raw (noisy) points. ``refine=True`` instead places
the knots where the piecewise-linear function of time through them best fits all the
track's points in the least-squares sense — exactly the quantity Dis_e measures, solved
for all tracks at once as one tridiagonal system. All knots move, each track's first and
last point too (the kept rows are the first and last, at fitted positions); with
``keep_ends`` (CompressParams) those two stay where they were observed, as SPEC §3 words
it, and the knots between are fitted around them.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.params import Params, param
from wakeline.core.schema import time_seconds, to_float
from wakeline.core.tracks import (
    TrackIndex,
    concat_ranges,
    local_xy,
    median_interval_s,
    repeated_rows,
    rows_of,
    sorted_with_index,
    track_origins,
    track_seconds,
)


@dataclass(frozen=True)
class CompressParams(Params):
    """Compression settings."""

    refine: bool = param(
        True, "", "place vertices by least squares on the neighbouring legs (else raw points)"
    )
    keep_ends: bool = param(
        False,
        "",
        "with refine: each track's first and last point stay at their observed positions "
        "(SPEC §3: compression keeps them) and only the knots between are placed by least "
        "squares; off: the ends are placed too (lower Dis_e, docs/evaluation.md)",
        source="SPEC §3; ours: off",
    )
    dp_tolerance_m: float = param(
        600.0, "m", "Douglas–Peucker tolerance (method dp)", lo=0.0, hi=1e7
    )
    keep_rest: bool = param(
        True,
        "",
        "keep where each at-rest span starts and ends, and inside it what Douglas–Peucker "
        "needs at the rest radius (a moored ship's drift over hours)",
    )
    gap_factor: float = param(
        10.0,
        "",
        "keep both ends of an interval longer than this many times the track's median "
        "interval (outside at-rest spans); 0 = off",
        lo=0.0,
        hi=1e6,
    )
    speed_change_kn: float = param(
        0.0,
        "kn",
        "keep where the speed over the window after a point differs from the one before by "
        "more than this and by more than speed_change_ratio (a local maximum); 0 = off (the "
        "error bound keeps what a speed change costs in Dis_e)",
        lo=0.0,
        hi=100.0,
    )
    speed_change_ratio: float = param(
        0.25, "", "relative speed change that counts (of the faster window)", lo=0.0, hi=10.0
    )
    error_sigmas: float = param(
        10.0,
        "",
        "error bound between kept points: split (top-down, by the synchronized distance Dis_e "
        "measures) wherever a point lies farther than this many times the track's own "
        "position noise from the time interpolation of the kept points; 0 = off",
        lo=0.0,
        hi=1e4,
        source="ours; top-down time-ratio Douglas–Peucker",
    )
    error_floor_m: float = param(
        50.0,
        "m",
        "the error bound is never below this (default: the at-rest radius)",
        lo=0.0,
        hi=1e6,
        source="ours",
    )
    error_cap_m: float = param(
        0.0,
        "m",
        "the error bound is never above this (metres; at least error_floor_m): on sparse "
        "tracks (30-min AIS posits) the track's \"noise\" is the ship's own motion between "
        "fixes and error_sigmas times it is kilometres; 0 = no cap",
        lo=0.0,
        hi=1e7,
        source="ours (operator test 7, D9)",
    )

    @classmethod
    def paper(cls) -> "CompressParams":
        """Seed 000 as written: the maneuver points only, raw vertices."""
        return cls(
            refine=False, keep_rest=False, gap_factor=0.0, speed_change_kn=0.0, error_sigmas=0.0
        )


def _segments(kept: np.ndarray, index: TrackIndex, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each point: the knot number (global) that starts its segment, and its weight w
    in [0, 1] toward the next knot."""
    n = len(kept)
    knot_no = np.cumsum(kept) - 1  # knot number of each kept row
    row = np.arange(n)
    last_kept_row = np.maximum.accumulate(np.where(kept, row, -1))
    left = knot_no[last_kept_row]
    # The last point of a track closes the last segment: use the segment before it.
    last = np.zeros(n, dtype=bool)
    last[index.ends - 1] = True
    single = index.sizes[index.track_of_row] == 1
    left = np.where(last & ~single, left - 1, left)
    knot_rows = np.flatnonzero(kept)
    k_t = t[knot_rows]
    right = np.minimum(left + 1, len(knot_rows) - 1)
    span = k_t[right] - k_t[left]
    with np.errstate(invalid="ignore", divide="ignore"):
        w = np.where(span > 0, (t - k_t[left]) / span, 0.0)
    w = np.where(single, 0.0, np.clip(w, 0.0, 1.0))
    return left, w


def _least_squares_knots(
    left: np.ndarray,
    w: np.ndarray,
    xy: np.ndarray,
    n_knots: int,
    single_knot: np.ndarray,
    fixed: np.ndarray | None = None,
    fixed_xy: np.ndarray | None = None,
) -> np.ndarray:
    """Knot positions minimizing Σ |(1-w) c_left + w c_left+1 - xy|² (all tracks at once);
    the knots marked in ``fixed`` (bool per knot) stay at ``fixed_xy`` (K, 2) and the
    others are fitted around them (a constrained least squares: their rows become the
    identity, their couplings move to the right-hand side)."""
    from scipy.linalg import solve_banded  # lazy: keeps `wakeline --help` fast

    a = 1.0 - w
    diag = np.bincount(left, a * a, minlength=n_knots) + np.bincount(
        np.minimum(left + 1, n_knots - 1), w * w, minlength=n_knots
    )
    off = np.bincount(left, a * w, minlength=n_knots)[: n_knots - 1]
    rhs = np.zeros((n_knots, 2))
    for d in range(2):
        rhs[:, d] = np.bincount(left, a * xy[:, d], minlength=n_knots) + np.bincount(
            np.minimum(left + 1, n_knots - 1), w * xy[:, d], minlength=n_knots
        )
    # A knot of a one-point track couples to nothing: off-diagonals there are zero anyway
    # because its points have w = 0; make the diagonal safe.
    diag = np.where(diag > 0, diag, 1.0)
    upper = off.copy()  # A[i, i+1]
    lower = off.copy()  # A[i+1, i]
    if fixed is not None and fixed.any():
        c = np.where(fixed[:, None], fixed_xy, 0.0)
        rhs[1:] -= lower[:, None] * c[:-1]  # row i+1's coupling to a fixed knot i
        rhs[:-1] -= upper[:, None] * c[1:]  # row i's coupling to a fixed knot i+1
        cut = fixed[:-1] | fixed[1:]
        upper[cut] = 0.0
        lower[cut] = 0.0
        diag = np.where(fixed, 1.0, diag)
        rhs[fixed] = fixed_xy[fixed]
    ab = np.zeros((3, n_knots))
    ab[0, 1:] = upper
    ab[1] = diag
    ab[2, :-1] = lower
    out = solve_banded((1, 1), ab, rhs)
    free_single = single_knot if fixed is None else single_knot & ~fixed
    out[free_single] = rhs[free_single] / diag[free_single, None]
    if fixed is not None:
        out[fixed] = fixed_xy[fixed]
    return out


@dataclass(frozen=True)
class Compressed:
    """A compression of every track of a sorted table."""

    points: pd.DataFrame  # the sorted input (without rows repeating their predecessor)
    index: TrackIndex
    kept: np.ndarray  # bool per point
    knot_xy: np.ndarray  # (K, 2) local metres of each knot (track frame)
    reconstructed_xy: np.ndarray  # (N, 2) every point reconstructed on the compressed track
    xy: np.ndarray  # (N, 2) observed points in the track frame
    true_xy: np.ndarray | None  # (N, 2) true positions (simulations) or None
    repeats: int = 0  # input rows repeating their predecessor (time, place): set aside

    def point_errors(self, against: str = "observed") -> np.ndarray:
        """Synchronized distance (m) of every original point."""
        ref = self.xy if against == "observed" else self.true_xy
        if ref is None:
            raise ValueError("no true positions (true_lon/true_lat) in this table")
        return np.hypot(*(self.reconstructed_xy - ref).T)

    def report(self) -> dict:
        """Dis_e (m) and share of points kept, per track and overall."""
        idx = self.index
        err_obs = self.point_errors("observed")
        kept_n = (
            np.add.reduceat(self.kept.astype("int64"), idx.starts) if idx.n_tracks else np.zeros(0)
        )
        per = idx.keys.copy()
        per["points"] = idx.sizes
        per["kept"] = kept_n
        per["ratio"] = kept_n / idx.sizes
        per["dis_e_m"] = np.add.reduceat(err_obs, idx.starts) / idx.sizes if idx.n_tracks else []
        # the farthest original point from the compressed track (synchronized distance)
        per["max_error_m"] = np.maximum.reduceat(err_obs, idx.starts) if idx.n_tracks else []
        overall = {
            "points": int(idx.sizes.sum()),
            "kept": int(self.kept.sum()),
            "ratio": float(self.kept.sum() / max(idx.sizes.sum(), 1)),
            "dis_e_m": float(err_obs.mean()) if len(err_obs) else 0.0,
            "max_error_m": float(err_obs.max()) if len(err_obs) else 0.0,
        }
        if self.repeats:
            overall["repeated_rows"] = self.repeats
        if self.true_xy is not None:
            err_true = self.point_errors("truth")
            known = np.isfinite(err_true)  # points with a truth (a blank cell has none)
            if known.any():
                n_known = np.add.reduceat(known.astype("int64"), idx.starts)
                with np.errstate(invalid="ignore", divide="ignore"):
                    sums = np.add.reduceat(np.where(known, err_true, 0.0), idx.starts)
                    per["dis_e_true_m"] = np.where(n_known > 0, sums / n_known, np.nan)
                overall["dis_e_true_m"] = float(err_true[known].mean())
                # a track without any truth: None in the report (JSON has no NaN)
                per["dis_e_true_m"] = per["dis_e_true_m"].astype(object).where(n_known > 0, None)
        return {
            "overall": overall,
            "tracks": per.to_dict(orient="records"),
            "ratio_definition": "kept points / original points",
        }

    def kept_points(self) -> pd.DataFrame:
        """The kept points (canonical columns) at their compressed positions."""
        rows = np.flatnonzero(self.kept)
        out = self.points.iloc[rows].reset_index(drop=True).copy()
        lon0, lat0 = track_origins(self.points, self.index)
        tr = self.index.track_of_row[rows]
        lon, lat = geo.from_local(self.knot_xy[:, 0], self.knot_xy[:, 1], lon0[tr], lat0[tr])
        out["lon"] = np.round(lon, 7)  # 1e-7 deg is about 1 cm
        out["lat"] = np.round(lat, 7)
        return out


def compress_with(
    points: pd.DataFrame,
    keep: np.ndarray | None = None,
    refine: bool = True,
    sorted_points: pd.DataFrame | None = None,
    keep_ends: bool = False,
) -> Compressed:
    """Compress to the rows marked in ``keep`` (aligned with ``sort_points(points)``)
    plus each track's first and last point. Rows that repeat their predecessor (same
    time and place) are set aside (counted in ``repeats``; a repeat marked in ``keep``
    keeps its original): they would weigh twice in the fit and in Dis_e. With ``refine``
    every knot is placed by least squares, the track's ends too, unless ``keep_ends``:
    then the first and last point stay where they were observed (SPEC §3's wording)."""

    pts, index = sorted_with_index(sorted_points if sorted_points is not None else points)
    n = len(pts)
    kept = np.zeros(n, dtype=bool) if keep is None else np.asarray(keep, dtype=bool).copy()
    kept[index.starts] = True
    kept[index.ends - 1] = True
    repeat = repeated_rows(pts, index)
    repeats = int(repeat.sum())
    if repeats:  # set aside: a row repeating its predecessor is kept as that one, once
        original = np.maximum.accumulate(np.where(repeat, 0, np.arange(n)))
        kept[original[np.flatnonzero(kept & repeat)]] = True
        rows = np.flatnonzero(~repeat)
        kept = kept[rows]
        pts, index = rows_of(pts, rows)
        n = len(pts)
    x, y = local_xy(pts, index)
    xy = np.column_stack([x, y])
    t = track_seconds(pts)
    left, w = _segments(kept, index, t)
    knot_rows = np.flatnonzero(kept)
    if refine and n:
        single_knot = np.zeros(len(knot_rows), dtype=bool)
        single_knot[np.searchsorted(knot_rows, index.starts[index.sizes == 1])] = True
        fixed = fixed_xy = None
        if keep_ends:
            ends = np.zeros(n, dtype=bool)
            ends[index.starts] = True
            ends[index.ends - 1] = True
            fixed = ends[knot_rows]
            fixed_xy = xy[knot_rows]
        knot_xy = _least_squares_knots(left, w, xy, len(knot_rows), single_knot, fixed, fixed_xy)
    else:
        knot_xy = xy[knot_rows]
    right = np.minimum(left + 1, len(knot_rows) - 1)
    recon = (1.0 - w)[:, None] * knot_xy[left] + w[:, None] * knot_xy[right]
    true_xy = None
    if {"true_lon", "true_lat"} <= set(pts.columns):
        lon0, lat0 = track_origins(pts, index)
        tx, ty = geo.to_local(  # a blank or unreadable truth cell: NaN, not an error
            to_float(pts["true_lon"]),
            to_float(pts["true_lat"]),
            lon0[index.track_of_row],
            lat0[index.track_of_row],
        )
        true_xy = np.column_stack([tx, ty])
    return Compressed(pts, index, kept, knot_xy, recon, xy, true_xy, repeats)


DP_DISTANCES = ("segment", "line")


def turning_keep(result, params: CompressParams | None = None) -> np.ndarray:
    """Rows a maneuver compression keeps, over ``result.points`` (a :class:`ManeuverResult`):
    the maneuver points, and — ours, for time-synchronized Dis_e on real traffic — at-rest
    span ends (plus Douglas–Peucker inside a span at the rest radius), both ends of long
    gaps and speed changes. Track ends are added by :func:`compress_with`."""
    from wakeline.core.clean import rest_frame, rest_spans
    from wakeline.core.maneuver import (
        ManeuverParams,
        ManeuverResult,
        _near,
        _sub_index,
        local_maxima,
        window_ends,
    )

    params = params or CompressParams()
    pts, index = result.points, result.index
    keep = np.asarray(result.is_maneuver, dtype=bool).copy()
    if not len(keep):
        return keep
    repeat = repeated_rows(pts, index)
    if repeat.any():  # rows repeating their predecessor (time and place): never kept
        rows = np.flatnonzero(~repeat)
        sub_pts, sub_index = rows_of(pts, rows)
        at_rest = None if result.at_rest is None else np.asarray(result.at_rest)[rows]
        sub = ManeuverResult(
            sub_pts, sub_index, np.asarray(result.factor)[rows], keep[rows],
            result.window_p, at_rest, result.params,
        )  # fmt: skip
        keep[:] = False
        keep[rows] = turning_keep(sub, params)
        return keep
    rest = np.zeros(len(keep), dtype=bool) if result.at_rest is None else np.asarray(result.at_rest)
    x, y = local_xy(pts, index)
    t = time_seconds(pts["time"])
    tr = index.track_of_row
    # the rule that made the spans (unknown: the defaults of before sparse stays)
    mp = result.params if result.params is not None else ManeuverParams(rest_steps=0.0)
    med_track: np.ndarray | None = None  # each track's median interval (s), when first needed
    if params.keep_rest and rest.any():
        spans = rest_spans(rest, index)
        keep[spans[:, 0]] = True
        keep[spans[:, 1]] = True
        sizes = spans[:, 1] - spans[:, 0] + 1
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype("int64")
        rows = concat_ranges(spans[:, 0], sizes)
        span_of_row = np.repeat(np.arange(len(sizes)), sizes)
        sub = TrackIndex(starts, starts + sizes, span_of_row, pd.DataFrame(index=range(len(sizes))))
        # inside a span at the radius that made it (a sparse track's grows with its window)
        if mp.rest_steps > 0:
            med_track = median_interval_s(t, index)
        xs, ys, _ = rest_frame(x, y, t, index, mp.rest_window_s, mp.rest_steps, med_track)
        keep[rows[douglas_peucker_mask(xs[rows], ys[rows], sub, mp.rest_radius_m)]] = True
    p_row = np.asarray(result.window_p)[tr]
    if params.gap_factor > 0 and len(t) > 1:
        med = (median_interval_s(t, index) if med_track is None else med_track)[tr]
        big = (np.diff(t) > params.gap_factor * med[1:]) & (tr[1:] == tr[:-1])
        gap = np.zeros(len(t), dtype=bool)
        gap[1:] |= big
        gap[:-1] |= big
        keep |= gap & ~rest
    if params.speed_change_kn > 0:
        n = len(x)
        a, b, inside = window_ends(index, np.arange(n), p_row, n)
        with np.errstate(invalid="ignore", divide="ignore"):
            v_back = np.hypot(x - x[a], y - y[a]) / (t - t[a])
            v_fwd = np.hypot(x[b] - x, y[b] - y) / (t[b] - t)
            dv = np.where(inside, np.abs(v_fwd - v_back), np.nan)
            big = dv > np.maximum(
                params.speed_change_kn * geo.KN_MS,
                params.speed_change_ratio * np.fmax(v_back, v_fwd),
            )
        peaks = np.zeros(n, dtype=bool)
        p_track = np.asarray(result.window_p)
        for p in np.unique(p_track):  # one pass per distinct window (usually one)
            chosen = p_track == p
            rows = np.flatnonzero(chosen[tr])
            sub = TrackIndex(*_sub_index(index, chosen))
            peaks[rows] = local_maxima(dv[rows], sub, int(p))
        keep |= big & peaks & ~_near(rest, index, p_row - 1)
    if params.error_sigmas > 0:
        _, tol = _error_bound(x, y, t, index, params)
        keep = synchronized_split_mask(x, y, t, index, keep, tol)
    return keep


def _error_bound(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, params: CompressParams
) -> tuple[np.ndarray, np.ndarray]:
    """Per track: the position-noise estimate (m, per axis; the maneuver detector's) and
    the error bound the top-down split uses: ``error_sigmas`` × noise, at least
    ``error_floor_m``, at most ``error_cap_m`` when that is set."""
    from wakeline.core.maneuver import position_noise_m

    sigma = position_noise_m(x, y, t, index)
    tol = np.maximum(params.error_sigmas * sigma, params.error_floor_m)
    if params.error_cap_m > 0:
        tol = np.minimum(tol, max(params.error_cap_m, params.error_floor_m))
    return sigma, tol


def error_bounds(result, params: CompressParams | None = None) -> pd.DataFrame:
    """Per track of ``result.index`` (a :class:`ManeuverResult`): sensor, batch, the
    noise estimate ``noise_m`` and the error bound ``error_tol_m`` :func:`turning_keep`
    splits at (both NaN when ``error_sigmas`` is 0: no bound; ``noise_m`` NaN for a
    track of fewer than 3 points, whose bound is the floor)."""
    params = params or CompressParams()
    pts, index = result.points, result.index
    out = index.keys.reset_index(drop=True).copy()
    if params.error_sigmas <= 0 or not len(pts):
        out["noise_m"] = np.nan
        out["error_tol_m"] = np.nan
        return out
    repeat = repeated_rows(pts, index)
    if repeat.any():  # as turning_keep: the rows repeating their predecessor left out
        pts, index = rows_of(pts, np.flatnonzero(~repeat))
    x, y = local_xy(pts, index)
    sigma, tol = _error_bound(x, y, time_seconds(pts["time"]), index, params)
    # a track of one or two points has no noise estimate (no point between two others):
    # its bound is the floor, its noise not known (NaN), not 0
    out["noise_m"] = np.where(index.sizes >= 3, sigma, np.nan)
    out["error_tol_m"] = tol
    return out


def synchronized_split_mask(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    keep: np.ndarray,
    tolerance_m: np.ndarray | float,
) -> np.ndarray:
    """Top-down split by the synchronized distance (time-ratio Douglas–Peucker), all tracks
    at once: starting from the ``keep`` rows and each track's ends, a segment whose farthest
    point (distance to the time interpolation of its ends, metres) exceeds the tolerance
    (``tolerance_m`` per track or one value) is split there, until none does."""
    keep = np.asarray(keep, dtype=bool).copy()
    keep[index.starts] = True
    keep[index.ends - 1] = True
    tol_track = np.broadcast_to(np.asarray(tolerance_m, dtype="float64"), (index.n_tracks,))
    rows_k = np.flatnonzero(keep)
    same = index.track_of_row[rows_k[1:]] == index.track_of_row[rows_k[:-1]]
    seg_a, seg_b = rows_k[:-1][same], rows_k[1:][same]
    wide = seg_b - seg_a >= 2
    seg_a, seg_b = seg_a[wide], seg_b[wide]
    while len(seg_a):  # rounds ≈ depth of the recursion
        counts = seg_b - seg_a - 1
        seg_of = np.repeat(np.arange(len(seg_a)), counts)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rows = seg_a[seg_of] + 1 + (np.arange(counts.sum()) - first[seg_of])
        a, b = seg_a[seg_of], seg_b[seg_of]
        span = t[b] - t[a]
        with np.errstate(invalid="ignore", divide="ignore"):
            w = np.where(span > 0, (t[rows] - t[a]) / span, 0.5)
        dist = np.hypot(x[rows] - (x[a] + w * (x[b] - x[a])), y[rows] - (y[a] + w * (y[b] - y[a])))
        seg_max = np.maximum.reduceat(dist, first)
        is_max = dist == seg_max[seg_of]
        arg = np.minimum.reduceat(np.where(is_max, rows, np.iinfo(np.int64).max), first)
        split = seg_max > tol_track[index.track_of_row[seg_a]]
        keep[arg[split]] = True
        seg_a, seg_b, arg = seg_a[split], seg_b[split], arg[split]
        seg_a, seg_b = np.concatenate([seg_a, arg]), np.concatenate([arg, seg_b])
        wide = seg_b - seg_a >= 2
        seg_a, seg_b = seg_a[wide], seg_b[wide]
    return keep


def douglas_peucker_mask(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, tolerance_m: float, distance: str = "segment"
) -> np.ndarray:
    """Douglas–Peucker on all tracks at once: which points (metres, track plane) are kept.

    ``distance="segment"`` (default): a point's distance to the chord *segment*, as GEOS
    measures it; runs in ``shapely.simplify`` over all tracks at once (one linestring per
    track, the row number carried as z so kept vertices map back to rows).
    ``distance="line"``: perpendicular distance to the chord's infinite line (the
    textbook form), our vectorized rounds (:func:`_dp_line_mask`). Both take the first
    farthest point and split when it is beyond the tolerance; they differ only where a
    point lies beyond a chord's ends (loops, U-turns). See docs/benchmarks.md.
    """
    if distance == "line":
        return _dp_line_mask(x, y, index, tolerance_m)
    if distance != "segment":
        raise ValueError(f"distance must be one of {', '.join(DP_DISTANCES)}")
    import shapely  # lazy: keeps `wakeline --help` fast

    keep = np.zeros(len(x), dtype=bool)
    keep[index.starts] = True
    keep[index.ends - 1] = True
    rows = np.flatnonzero((index.sizes >= 3)[index.track_of_row])
    if len(rows) == 0:
        return keep
    coords = np.column_stack([x[rows], y[rows], rows.astype("float64")])
    # shapely wants the line numbers 0, 1, 2 … without gaps (short tracks are left out).
    track = index.track_of_row[rows]
    line_no = np.concatenate([[0], np.cumsum(np.diff(track) != 0)]).astype("int64")
    lines = shapely.linestrings(coords, indices=line_no)
    simple = shapely.simplify(lines, float(tolerance_m), preserve_topology=False)
    kept_rows = shapely.get_coordinates(simple, include_z=True)[:, 2]
    keep[kept_rows.astype("int64")] = True
    return keep


def _dp_line_mask(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, tolerance_m: float
) -> np.ndarray:
    """Douglas–Peucker by perpendicular distance to the chord's line, all tracks at once.

    Each round takes every open segment of every track, finds its farthest interior point
    with one vectorized pass, and splits the segments whose farthest point is beyond the
    tolerance. Rounds ≈ depth of the recursion.
    """
    keep = np.zeros(len(x), dtype=bool)
    keep[index.starts] = True
    keep[index.ends - 1] = True
    seg_a = index.starts[index.sizes >= 3]
    seg_b = (index.ends - 1)[index.sizes >= 3]
    while len(seg_a):
        counts = seg_b - seg_a - 1
        seg_of = np.repeat(np.arange(len(seg_a)), counts)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rows = seg_a[seg_of] + 1 + (np.arange(counts.sum()) - first[seg_of])
        ax, ay = x[seg_a][seg_of], y[seg_a][seg_of]
        bx, by = x[seg_b][seg_of], y[seg_b][seg_of]
        dx, dy = bx - ax, by - ay
        norm = np.hypot(dx, dy)
        px, py = x[rows] - ax, y[rows] - ay
        with np.errstate(invalid="ignore", divide="ignore"):
            dist = np.where(norm > 0, np.abs(dx * py - dy * px) / norm, np.hypot(px, py))
        seg_max = np.maximum.reduceat(dist, first)
        is_max = dist == seg_max[seg_of]
        arg = np.minimum.reduceat(np.where(is_max, rows, np.iinfo(np.int64).max), first)
        split = seg_max > tolerance_m
        keep[arg[split]] = True
        seg_a, seg_b, arg = seg_a[split], seg_b[split], arg[split]
        seg_a, seg_b = np.concatenate([seg_a, arg]), np.concatenate([arg, seg_b])
        wide = seg_b - seg_a >= 2
        seg_a, seg_b = seg_a[wide], seg_b[wide]
    return keep


def douglas_peucker_count_mask(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    kept_per_track: np.ndarray,
    distance: str = "segment",
) -> np.ndarray:
    """Douglas–Peucker keeping a given number of points per track, all tracks at once.

    The recursion's tree is built without a tolerance (every segment with a point inside
    is split at its first farthest point); a split point's weight is the smallest split
    distance on its path from the root (its own included), so that Douglas–Peucker at a
    tolerance keeps exactly the points weighing more than it. Each track keeps its two
    ends and the ``kept_per_track[i] - 2`` heaviest points (ties: the shallower, then the
    earlier): Douglas–Peucker at the tolerance that keeps that many, where one does.
    Compares a compressor with Douglas–Peucker at equal points kept. ``distance`` as in
    :func:`douglas_peucker_mask` (``segment``: to the chord segment; ``line``: to its line).
    """
    if distance not in DP_DISTANCES:
        raise ValueError(f"distance must be one of {', '.join(DP_DISTANCES)}")
    n = len(x)
    weight = np.full(n, -np.inf)
    depth = np.zeros(n, dtype="int64")
    weight[index.starts] = np.inf
    weight[index.ends - 1] = np.inf
    seg_a = index.starts[index.sizes >= 3]
    seg_b = (index.ends - 1)[index.sizes >= 3]
    seg_w = np.full(len(seg_a), np.inf)  # the smallest split distance above the segment
    level = 1
    while len(seg_a):  # rounds = depth of the recursion
        counts = seg_b - seg_a - 1
        seg_of = np.repeat(np.arange(len(seg_a)), counts)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rows = seg_a[seg_of] + 1 + (np.arange(counts.sum()) - first[seg_of])
        ax, ay = x[seg_a][seg_of], y[seg_a][seg_of]
        dx, dy = x[seg_b][seg_of] - ax, y[seg_b][seg_of] - ay
        px, py = x[rows] - ax, y[rows] - ay
        norm2 = dx * dx + dy * dy
        with np.errstate(invalid="ignore", divide="ignore"):
            if distance == "line":
                dist = np.where(
                    norm2 > 0, np.abs(dx * py - dy * px) / np.sqrt(norm2), np.hypot(px, py)
                )
            else:
                u = np.where(norm2 > 0, np.clip((px * dx + py * dy) / norm2, 0.0, 1.0), 0.0)
                dist = np.hypot(px - u * dx, py - u * dy)
        dist = np.where(np.isnan(dist), -np.inf, dist)  # a NaN position weighs least
        seg_max = np.maximum.reduceat(dist, first)
        is_max = dist == seg_max[np.repeat(np.arange(len(seg_a)), counts)]
        arg = np.minimum.reduceat(np.where(is_max, rows, np.iinfo(np.int64).max), first)
        w = np.minimum(seg_w, seg_max)
        weight[arg] = w
        depth[arg] = level
        level += 1
        seg_a, seg_b = np.concatenate([seg_a, arg]), np.concatenate([arg, seg_b])
        seg_w = np.concatenate([w, w])
        wide = seg_b - seg_a >= 2
        seg_a, seg_b, seg_w = seg_a[wide], seg_b[wide], seg_w[wide]
    track = index.track_of_row
    order = np.lexsort((np.arange(n), depth, -weight, track))  # by track, heaviest first
    rank = np.empty(n, dtype="int64")
    rank[order] = np.arange(n) - index.starts[track[order]]
    want = np.asarray(kept_per_track, dtype="int64")
    return rank < np.maximum(want, 2)[track]

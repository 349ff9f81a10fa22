"""Level of detail for NaN-separated track curves, pure numpy (worker-safe).

Per track, a point is dropped when it falls in the same screen pixel as the previous
point of its track (a run of points in one pixel keeps its first, so that is the previous
*kept* point too); the first and last point of every track are kept. Every input point
thus lies in the pixel of a drawn vertex of its own track, and turns survive down to the
pixel. With a box, points whose two legs both lie beyond one edge are dropped and the
curve is broken there, so no false straight line joins the two sides of a gap.
"""

import numpy as np

from wakeline.core import geo
from wakeline.core.sorted_sets import repeat_runs

#: A leg is not drawn when the ship went unseen longer than this (s) and than
#: :data:`GAP_FACTOR` times its track's median time step, or longer than
#: :data:`GAP_ALWAYS_S` whatever the sampling: a straight line across hours or days says
#: where nobody saw it, and crosses land (the ATD and Saronic AIS sets).
GAP_BREAK_S = 1800.0
GAP_FACTOR = 10.0
GAP_ALWAYS_S = 3 * 3600.0
#: Nor a leg no ship could sail: faster than this (kn) over more than
#: :data:`JUMP_MIN_M` (two ships under one id, a position error; short legs of noisy
#: radar plots may seem fast and are drawn).
JUMP_KN = 60.0
JUMP_MIN_M = 1000.0


def gap_breaks(
    time_s: np.ndarray,
    starts: np.ndarray,
    ends: np.ndarray,
    lon: np.ndarray | None = None,
    lat: np.ndarray | None = None,
) -> np.ndarray:
    """Per point: the leg arriving at it spans a gap (see :data:`GAP_BREAK_S`), or, with
    positions (degrees), a jump no ship could make (:data:`JUMP_KN`), so the curve breaks
    before it. ``time_s`` in seconds, sorted within each track; NaN times never break."""
    n = len(time_s)
    out = np.zeros(n, dtype=bool)
    if n < 2 or len(starts) == 0:
        return out
    step = np.empty(n)
    step[0] = np.nan
    np.subtract(time_s[1:], time_s[:-1], out=step[1:])
    step[starts] = np.nan
    sizes = ends - starts
    track = repeat_runs(None, sizes)
    # Median step of each track (the lower middle of its steps): steps sorted per track,
    # NaN last, and the middle of the finite ones taken.
    finite = np.isfinite(step)
    order = np.lexsort((np.where(finite, step, np.inf), track))
    count = np.bincount(track[finite], minlength=len(starts))
    middle = starts + np.maximum(count - 1, 0) // 2
    median = np.where(count > 0, step[order[np.minimum(middle, n - 1)]], np.inf)
    limit = np.minimum(np.maximum(GAP_BREAK_S, GAP_FACTOR * median), GAP_ALWAYS_S)
    with np.errstate(invalid="ignore"):
        out[:] = step > limit[track]
    if lon is not None and lat is not None:
        # A leg is at most R·(|Δlat| + |Δlon|) long (radians: along the meridian, then
        # the parallel; the great circle is shorter): only the legs whose bound passes
        # both limits are measured (a million legs' haversine was ~100 ms of a review
        # decision's worker), the others are no jump whatever their length.
        with np.errstate(invalid="ignore"):
            bound = np.abs(lat[1:] - lat[:-1]) + np.abs(lon[1:] - lon[:-1])
            bound = np.radians(bound) * (geo.EARTH_RADIUS_M * (1.0 + 1e-9))
            speed_m = JUMP_KN * geo.KN_MS * step[1:]
            maybe = np.flatnonzero((bound > JUMP_MIN_M) & (bound > speed_m)) + 1
        dist = np.zeros(n)
        dist[maybe] = geo.haversine_m(lon[maybe - 1], lat[maybe - 1], lon[maybe], lat[maybe])
        with np.errstate(invalid="ignore", divide="ignore"):
            fast = (dist > JUMP_MIN_M) & (dist > JUMP_KN * geo.KN_MS * step)
        out |= fast & np.isfinite(step)
    return out


def split_at(
    starts: np.ndarray, ends: np.ndarray, breaks: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Track bounds with every break point starting a piece of its own (for
    :func:`decimate`, which keeps the ends of each piece and breaks between pieces)."""
    cut = np.flatnonzero(breaks)
    if not len(cut):
        return starts, ends
    # The union of sorted bounds by a mask over the points, not np.union1d: numpy 2.4's
    # np.unique on a million distinct ints takes 0.7-1.6 s (a worker holding the GIL that
    # long stalls the window); the masks take a few ms.
    size = len(breaks) + 1
    first = np.zeros(size, dtype=bool)
    first[starts] = True
    first[cut] = True
    last = np.zeros(size, dtype=bool)
    last[ends] = True
    last[cut] = True
    return np.flatnonzero(first), np.flatnonzero(last)


def _outcode(lon: np.ndarray, lat: np.ndarray, box: tuple[float, float, float, float]):
    x0, x1, y0, y1 = box
    return (
        (lon < x0).astype(np.uint8)
        | ((lon > x1).astype(np.uint8) << 1)
        | ((lat < y0).astype(np.uint8) << 2)
        | ((lat > y1).astype(np.uint8) << 3)
    )


def decimate(
    lon: np.ndarray,
    lat: np.ndarray,
    starts: np.ndarray,
    ends: np.ndarray,
    px: tuple[float, float] | None,
    box: tuple[float, float, float, float] | None = None,
    origin: tuple[float, float] = (0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray]:
    """Which points to draw, and where a curve must break: ``(keep, brk)``, bool per point.

    ``px`` is the pixel size (degrees lon, lat), None for no pixel decimation; ``box``
    ``(x0, x1, y0, y1)`` the region to draw, None for everything; pixels are counted from
    ``origin`` (the view's corner, so cells match screen pixels). ``brk[i]``: a kept point
    that must not be joined to the previous kept point (track start or clipped gap).
    Vectorized over all tracks; every track keeps its first and last point in ``box``.
    """
    n = len(lon)
    first = np.zeros(n, dtype=bool)
    first[starts] = True
    last = np.zeros(n, dtype=bool)
    last[ends - 1] = True
    keep = np.ones(n, dtype=bool)
    if px is not None and n:
        ix = np.floor((lon - origin[0]) / px[0])
        iy = np.floor((lat - origin[1]) / px[1])
        same = np.zeros(n, dtype=bool)
        same[1:] = (ix[1:] == ix[:-1]) & (iy[1:] == iy[:-1])
        keep = ~same | first | last
    brk = first.copy()
    if box is not None and n:
        code = _outcode(lon, lat, box)
        # Leg i joins point i-1 to point i; it may cross the box unless both ends lie
        # beyond the same edge.
        leg = np.zeros(n + 1, dtype=bool)
        leg[1:n] = (code[1:] & code[:-1]) == 0
        leg[starts] = False
        near = (code == 0) | leg[:n] | leg[1:]
        clipped = ~near
        keep &= near
        # Break before a kept point when points were clipped since the previous kept one.
        c = np.cumsum(clipped, dtype=np.intp)  # a bool cumsum holds the GIL
        kept_idx = np.flatnonzero(keep)
        gap = np.zeros(len(kept_idx), dtype=bool)
        gap[1:] = c[kept_idx[1:]] != c[kept_idx[:-1]]
        brk[kept_idx[gap]] = True
    return keep, brk


def nan_join(
    lon: np.ndarray, lat: np.ndarray, keep: np.ndarray, brk: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Kept points as one pair of arrays, a NaN before every break but the first."""
    idx = np.flatnonzero(keep)
    if len(idx) == 0:
        return np.zeros(0), np.zeros(0)
    b = brk[idx]
    b[0] = False
    pieces = np.cumsum(b, dtype=np.intp)
    out_lon = np.full(len(idx) + int(pieces[-1]), np.nan)
    out_lat = np.full(len(out_lon), np.nan)
    dest = np.arange(len(idx)) + pieces
    out_lon[dest] = lon[idx]
    out_lat[dest] = lat[idx]
    return out_lon, out_lat


def lod_box(
    view: tuple[float, float, float, float], margin: float = 1.0
) -> tuple[float, float, float, float]:
    """``view`` (x0, x1, y0, y1) grown by ``margin`` view sizes on every side."""
    x0, x1, y0, y1 = view
    w, h = (x1 - x0) * margin, (y1 - y0) * margin
    return (x0 - w, x1 + w, y0 - h, y1 + h)

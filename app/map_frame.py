"""Where the points are: the view a map opens on (pure numpy, worker-safe).

"Fit to data" shows every point; the first view of a file (and of a screenshot, a
project, a render without bounds) frames where the points are instead: the 0.5–99.5 %
quantiles of longitude and latitude over the visible layers, with the margin of a fit.
A tail beyond a quantile is still shown whole when it is near (within a quarter of the
quantiles' span): so only far-flung points are left out — three West-Coast positions of
the ATD set's Gulf traffic no longer make the traffic a speck — and a set without such
points is framed exactly as a fit frames it. A tail that runs on past a quantile without
an empty stretch wider than a tenth of the span (routes going on: the ATD set's Florida
Atlantic and Bahamas traffic, 58 tracks east of 78° W) is shown as far as it runs.

Each layer keeps a small :class:`PositionSketch` (its quantiles at every 0.1 %, every
0.01 % in the outer 1 % of each side, from at most :data:`SAMPLE_MAX` points), made in
the worker with the layer's geometry; the sketches of several layers are merged,
weighted by the share of points each quantile stands for, on the GUI thread in well
under a millisecond.
"""

from dataclasses import dataclass

import numpy as np

#: The quantiles of longitude and latitude the first view frames.
FRAME_QUANTILES = (0.005, 0.995)
#: A tail beyond a quantile nearer than this fraction of the quantiles' span is shown.
NEAR_TAIL = 0.25
#: A tail beyond a quantile is shown as far as it runs on without an empty stretch wider
#: than this fraction of the quantiles' span (routes that go on past the quantile).
TAIL_GAP = 0.1
#: Quantiles kept per layer: every 0.01 % in the outer 1 % of each side (where the
#: tails are judged), every 0.1 % between.
SKETCH_PROBS = np.unique(
    np.r_[np.linspace(0.0, 0.01, 101), np.linspace(0.01, 0.99, 981), np.linspace(0.99, 1.0, 101)]
)
#: The share of a layer's points each sketch value stands for (sums to 1).
_SKETCH_WEIGHT = np.gradient(SKETCH_PROBS) / np.gradient(SKETCH_PROBS).sum()
#: Points a sketch is made from at most (an even stride through the layer).
SAMPLE_MAX = 200_000


@dataclass(frozen=True)
class PositionSketch:
    """``n`` finite positions summed up by their longitude and latitude quantiles at
    :data:`SKETCH_PROBS` (the first and last are the minimum and maximum)."""

    n: int
    lon: np.ndarray
    lat: np.ndarray

    def box(self) -> tuple[float, float, float, float]:
        """``(west, south, east, north)`` of every position."""
        return (float(self.lon[0]), float(self.lat[0]), float(self.lon[-1]), float(self.lat[-1]))


def position_sketch(
    lon: np.ndarray, lat: np.ndarray, like: "PositionSketch | None" = None
) -> PositionSketch | None:
    """The sketch of the finite positions ``lon``, ``lat`` (degrees), None if none.
    ``like``: the sketch of the same positions in another order, all finite (a layer's
    lines made again): its extremes are kept, only the sampled quantiles are made."""
    lon, lat = np.asarray(lon, dtype="float64"), np.asarray(lat, dtype="float64")
    if like is not None and like.n == len(lon) == len(lat):
        q_lon = np.quantile(_sample(lon), SKETCH_PROBS)
        q_lat = np.quantile(_sample(lat), SKETCH_PROBS)
        q_lon[0], q_lon[-1] = like.lon[0], like.lon[-1]
        q_lat[0], q_lat[-1] = like.lat[0], like.lat[-1]
        return PositionSketch(like.n, q_lon, q_lat)
    ok = np.isfinite(lon) & np.isfinite(lat)
    n = int(ok.sum())
    if n == 0:
        return None
    lon, lat = lon[ok], lat[ok]
    q_lon = np.quantile(_sample(lon), SKETCH_PROBS)
    q_lat = np.quantile(_sample(lat), SKETCH_PROBS)
    # The extremes exactly, whatever the sample: "fit all" and the near-tail rule use them.
    q_lon[0], q_lon[-1] = lon.min(), lon.max()
    q_lat[0], q_lat[-1] = lat.min(), lat.max()
    return PositionSketch(n, q_lon, q_lat)


def _sample(values: np.ndarray) -> np.ndarray:
    if len(values) <= SAMPLE_MAX:
        return values
    return values[:: -(-len(values) // SAMPLE_MAX)]


def framed_box(
    sketches: list[PositionSketch | None],
) -> tuple[float, float, float, float] | None:
    """``(west, south, east, north)`` framing where the points of ``sketches`` are (see
    the module's description); None when there are none."""
    sketches = [s for s in sketches if s is not None and s.n > 0]
    if not sketches:
        return None
    edges = []
    for axis in ("lon", "lat"):
        values = np.concatenate([getattr(s, axis) for s in sketches])
        weight = np.concatenate([s.n * _SKETCH_WEIGHT for s in sketches])
        order = np.argsort(values, kind="stable")
        values, cum = values[order], np.cumsum(weight[order])
        cum /= cum[-1]
        last = len(values) - 1
        lo = values[min(int(np.searchsorted(cum, FRAME_QUANTILES[0])), last)]
        hi = values[min(int(np.searchsorted(cum, FRAME_QUANTILES[1])), last)]
        reach = NEAR_TAIL * (hi - lo)
        west = values[0] if lo - values[0] <= reach else _tail_end(values, lo, hi, -1)
        east = values[-1] if values[-1] - hi <= reach else _tail_end(values, lo, hi, 1)
        edges.append((float(west), float(east)))  # both tails judged by the quantiles
    (w, e), (s, n) = edges
    return (w, s, e, n)


def _tail_end(values: np.ndarray, lo: float, hi: float, side: int) -> float:
    """How far the tail beyond ``lo`` (``side`` -1) or ``hi`` (+1) runs on from the
    quantile without an empty stretch wider than :data:`TAIL_GAP` × (hi − lo) between
    consecutive sketch values (``values`` sorted): a route going on past the quantile
    is shown, positions far off beyond a gap are not."""
    gap = TAIL_GAP * (hi - lo)
    if side < 0:
        tail = values[values <= lo][::-1]  # from the quantile outwards
    else:
        tail = values[values >= hi]
    if len(tail) < 2:
        return lo if side < 0 else hi
    wide = np.flatnonzero(np.abs(np.diff(tail)) > gap)
    return float(tail[wide[0]] if len(wide) else tail[-1])

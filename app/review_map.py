"""Map drawing of a proposal for the main map canvas (issue 13): the proposal's two
tracks in their own colours on top (the colours the map's legend names for them), the
other member tracks of their target(s) muted under them, and across a single-sensor gap
a dashed straight connector plus the predicted path (cubic Hermite from the old track's
end position and velocity to the new track's start position and velocity, as stitching
fills it).

:func:`proposal_geometry` returns plain arrays (testable, Qt-free in spirit);
:func:`proposal_items` turns them into pyqtgraph items the canvas adds and removes.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore

from wakeline.app.map_selection import SELECTION_PALETTE
from wakeline.core import geo
from wakeline.core.review import ReviewState, _labels
from wakeline.core.schema import time_seconds

PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
)
#: The proposal's two tracks (old, new) when no colours are given: the colours the map's
#: selection gives two selected tracks over a blue and an orange layer (brown and pink:
#: apart for a deuteranope too, as red and green are not).
PAIR_COLORS = tuple(c for c in SELECTION_PALETTE if c not in ("#1f77b4", "#ff7f0e"))[:2]
#: The target's other members: context, one quiet colour, no legend line.
MUTED = "#9a9a9a"
#: Stacking (zValue): context members under the selection's curves (50), the gap's
#: connector and predicted path over them, the proposal's two tracks on top (marks: 60).
Z_MEMBER, Z_GAP, Z_PAIR = 45, 55, 56


@dataclass
class Piece:
    track: str
    lon: np.ndarray
    lat: np.ndarray
    color: str
    context: bool = False  # a member of the target other than the proposal's two tracks


@dataclass
class ProposalGeometry:
    """What to draw for one proposal; ``bounds`` = (lon0, lat0, lon1, lat1) of its two
    tracks, to zoom to."""

    proposal: str
    pieces: list[Piece] = field(default_factory=list)
    connector: tuple[np.ndarray, np.ndarray] | None = None  # straight, dashed
    predicted: tuple[np.ndarray, np.ndarray] | None = None  # across the gap
    bounds: tuple[float, float, float, float] | None = None


def _end_velocity(t: np.ndarray, lon: np.ndarray, lat: np.ndarray, at_end: bool, k: int = 5):
    """Least-squares velocity (m/s east, north) of the last (or first) ``k`` points."""
    sl = slice(-k, None) if at_end else slice(0, k)
    tt, lo, la = t[sl], lon[sl], lat[sl]
    if len(tt) < 2 or np.ptp(tt) <= 0:
        return 0.0, 0.0
    x, y = geo.to_local(lo, la, lo[-1 if at_end else 0], la[-1 if at_end else 0])
    tc = tt - tt.mean()
    den = float((tc * tc).sum())
    return float((tc * (x - x.mean())).sum() / den), float((tc * (y - y.mean())).sum() / den)


def predicted_path(
    end: tuple[float, float, float],
    v_end: tuple[float, float],
    start: tuple[float, float, float],
    v_start: tuple[float, float],
    n: int = 24,
) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Hermite path (lon, lat) from ``end`` = (t, lon, lat) with velocity ``v_end``
    (m/s) to ``start`` with ``v_start``, ``n`` points."""
    t0, lon0, lat0 = end
    t1, lon1, lat1 = start
    g = max(t1 - t0, 1e-6)
    s = np.linspace(0.0, 1.0, n)
    h10, h01, h11 = s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    ex, ey = geo.to_local(np.array([lon1]), np.array([lat1]), lon0, lat0)
    x = h10 * g * v_end[0] + h01 * ex[0] + h11 * g * v_start[0]
    y = h10 * g * v_end[1] + h01 * ey[0] + h11 * g * v_start[1]
    lon, lat = geo.from_local(x, y, np.full(n, lon0), np.full(n, lat0))
    return np.asarray(lon), np.asarray(lat)


def proposal_geometry(
    state: ReviewState,
    points: pd.DataFrame,
    proposal: str,
    colors: dict[str, str] | None = None,
) -> ProposalGeometry:
    """Pieces (members of the target(s) of the proposal's two tracks): the two tracks in
    ``colors`` (by ``sensor:batch``; default :data:`PAIR_COLORS`, old then new), the other
    members as context in :data:`MUTED`; for a proposal with a gap the connector and
    predicted path."""
    p = state.proposals.set_index("proposal").loc[proposal]
    members = list(
        dict.fromkeys(
            state.members(state.target(p["track_a"])) + state.members(state.target(p["track_b"]))
        )
    )
    for t in (p["track_a"], p["track_b"]):  # a rejected pair: both still shown
        if t not in members:
            members.append(t)
    lab = _labels(points[["sensor", "batch"]].astype(str))
    sel = pd.Series(lab).isin(members).to_numpy()
    pts = points[sel]
    lab = lab[sel]
    t = time_seconds(pts["time"]) if len(pts) else np.zeros(0)
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    geom = ProposalGeometry(proposal)
    pair = dict(zip((p["track_a"], p["track_b"]), PAIR_COLORS, strict=True))
    pair.update({t: c for t, c in (colors or {}).items() if t in pair})
    tracks = {}
    for m in members:  # a handful of members
        idx = np.flatnonzero(lab == m)
        idx = idx[np.argsort(t[idx], kind="stable")]
        tracks[m] = (t[idx], lon[idx], lat[idx])
        geom.pieces.append(Piece(m, lon[idx], lat[idx], pair.get(m, MUTED), m not in pair))
    ta, tb = tracks.get(p["track_a"]), tracks.get(p["track_b"])
    # Zoom to the proposal's two tracks (the other members are drawn, maybe off view).
    both = [x for x in (ta, tb) if x is not None and len(x[0])]
    if both:
        blon = np.concatenate([x[1] for x in both])
        blat = np.concatenate([x[2] for x in both])
        geom.bounds = (float(blon.min()), float(blat.min()), float(blon.max()), float(blat.max()))
    if ta is not None and tb is not None and len(ta[0]) and len(tb[0]):
        if ta[0][-1] > tb[0][0]:  # make a the earlier-ending track
            ta, tb = tb, ta
        if tb[0][0] > ta[0][-1]:  # a gap between the two
            end = (ta[0][-1], ta[1][-1], ta[2][-1])
            start = (tb[0][0], tb[1][0], tb[2][0])
            geom.connector = (np.array([end[1], start[1]]), np.array([end[2], start[2]]))
            geom.predicted = predicted_path(
                end, _end_velocity(*ta, at_end=True), start, _end_velocity(*tb, at_end=False)
            )
    return geom


def proposal_items(geom: ProposalGeometry) -> list[pg.GraphicsObject]:
    """pyqtgraph items for :func:`proposal_geometry`: one curve per piece (own colour,
    start marked; context pieces thinner, under the others), the dashed connector and the
    predicted path (dotted). Each item has its zValue (:data:`Z_PAIR` …)."""
    items: list[pg.GraphicsObject] = []
    for piece in geom.pieces:
        z, width, size = (Z_MEMBER, 2, 7) if piece.context else (Z_PAIR, 3, 9)
        curve = pg.PlotDataItem(
            piece.lon, piece.lat, pen=pg.mkPen(piece.color, width=width), name=piece.track
        )
        curve.setZValue(z)
        items.append(curve)
        if len(piece.lon):
            start = pg.ScatterPlotItem(
                piece.lon[:1], piece.lat[:1], size=size, brush=pg.mkBrush(piece.color), pen=None
            )
            start.setZValue(z)
            items.append(start)
    if geom.connector is not None:
        items.append(
            pg.PlotDataItem(
                *geom.connector,
                pen=pg.mkPen("#333333", width=1.5, style=QtCore.Qt.PenStyle.DashLine),
            )
        )
        items[-1].setZValue(Z_GAP)
    if geom.predicted is not None:
        items.append(
            pg.PlotDataItem(
                *geom.predicted,
                # Neutral ink, as the connector's: a colour of the palette would read as
                # the track the legend names in it.
                pen=pg.mkPen("#000000", width=2, style=QtCore.Qt.PenStyle.DotLine),
            )
        )
        items[-1].setZValue(Z_GAP)
    return items

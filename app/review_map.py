"""Map drawing of a proposal for the main map canvas (issue 13): the proposal's two
tracks in their own colours on top (the colours the map's legend names for them), the
other member tracks of their target(s) muted under them, and across a single-sensor gap
a dashed straight connector plus the predicted path (cubic Hermite from the old track's
end position and velocity to the new track's start position and velocity, as stitching
fills it).

:func:`proposal_geometry` returns plain arrays (testable, Qt-free in spirit);
:func:`proposal_items` turns them into pyqtgraph items; :class:`ProposalItems` keeps
one canvas's items and reuses them from one proposal to the next (``setData``, ``setPen``:
making and deleting pyqtgraph items was most of a redraw on the GUI thread).
"""

from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from wakeline.app.map_draw import unwrap_tracks
from wakeline.app.map_selection import SELECTION_PALETTE
from wakeline.core import geo
from wakeline.core.review import ReviewState, _point_label_codes
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
    #: the proposal's status, as its join is drawn (:func:`as_decided`): pending dashed,
    #: accepted solid, rejected or split not drawn as a join
    status: str = "pending"


#: A join's pen by its proposal's status (the connector across a gap, and every join of
#: the review on the map, :func:`join_segments`): undecided dashed, accepted solid;
#: rejected and split proposals join nothing and are not drawn as joins.
JOIN_INK = "#333333"
JOIN_STYLE = {
    "pending": QtCore.Qt.PenStyle.DashLine,
    "accepted": QtCore.Qt.PenStyle.SolidLine,
}


def join_pen(status: str, width: float = 1.5) -> QtGui.QPen:
    """The pen of a join whose proposal is ``status`` (pending: dashed; accepted: solid)."""
    return pg.mkPen(JOIN_INK, width=width, style=JOIN_STYLE.get(status, JOIN_STYLE["pending"]))


def as_decided(geom: ProposalGeometry, status: str) -> ProposalGeometry:
    """``geom`` drawn as its proposal now stands: a rejected or split proposal's gap
    keeps no connector nor predicted path (they are not joined); others keep theirs,
    the connector's pen by ``status``."""
    if status in JOIN_STYLE:
        return geom if geom.status == status else replace(geom, status=status)
    return replace(geom, connector=None, predicted=None, status=status)


def join_segments(
    state: ReviewState,
    t: np.ndarray,
    lon: np.ndarray,
    lat: np.ndarray,
    ranges: dict[str, tuple[int, int]],
    skip: str | None = None,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every join of a review across a gap, by status (``pending``, ``accepted``): the
    straight line from the earlier track's last point to the later track's first, as
    the proposal's connector draws it; NaN-separated (lon, lat) pairs for one curve per
    status. ``t``, ``lon``, ``lat``: the review's points, time-sorted within each track,
    in the map's band; ``ranges``: each track's rows. Proposals whose tracks overlap in
    time (two sensors' fusion) have no gap and no line; rejected and split ones none.
    ``skip``: a proposal left out (the current one, whose connector the review draws:
    two dashed lines of different widths over each other looked solid)."""
    status = np.asarray(state.status, dtype=object)
    keep = np.ones(len(status), dtype=bool)
    if skip is not None and skip in state._row:
        keep[state._row[skip]] = False
    out = {}
    for kind in JOIN_STYLE:
        rows = np.flatnonzero((status == kind) & keep)
        pairs = [
            (ranges[a], ranges[b])
            for a, b in zip(state.track_a[rows], state.track_b[rows], strict=True)
            if a in ranges
            and b in ranges
            and ranges[a][1] > ranges[a][0]
            and ranges[b][1] > ranges[b][0]
        ]
        if not pairs:
            out[kind] = (np.zeros(0), np.zeros(0))
            continue
        r = np.asarray(pairs, dtype="int64")  # (n, 2, 2): (a start, a end), (b start, b end)
        a_end, b_end = r[:, 0, 1] - 1, r[:, 1, 1] - 1
        a_first, b_first = r[:, 0, 0], r[:, 1, 0]
        swap = t[a_end] > t[b_first]  # the earlier-ending track first
        end = np.where(swap, b_end, a_end)
        start = np.where(swap, a_first, b_first)
        gap = t[start] > t[end]
        end, start = end[gap], start[gap]
        nan = np.full(len(end), np.nan)
        out[kind] = (
            np.column_stack([lon[end], lon[start], nan]).ravel(),
            np.column_stack([lat[end], lat[start], nan]).ravel(),
        )
    return out


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
    lon_west: float | None = None,
) -> ProposalGeometry:
    """Pieces (members of the target(s) of the proposal's two tracks): the two tracks in
    ``colors`` (by ``sensor:batch``; default :data:`PAIR_COLORS`, old then new), the other
    members as context in :data:`MUTED`; for a proposal with a gap the connector and
    predicted path. ``lon_west``: the band their layer is drawn in (-180 or 0); None:
    the band of ``points`` (:func:`wakeline.core.geo.lon_band_west`, as the map decides a
    layer's: give the whole layer's points, or its band)."""
    if lon_west is None:
        lon_west = geo.lon_band_west(points["lon"].to_numpy(dtype="float64"))
    members = proposal_members(state, proposal)
    codes, labels = _point_label_codes(points)  # text per track, not per point
    sel = np.isin(labels, np.asarray(list(members), dtype=str))[codes]
    pts = points[sel]
    lab = labels[codes[sel]]
    t = time_seconds(pts["time"]) if len(pts) else np.zeros(0)
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    tracks = {}
    for m in members:  # a handful of members
        idx = np.flatnonzero(lab == m)
        idx = idx[np.argsort(t[idx], kind="stable")]
        tracks[m] = (t[idx], lon[idx], lat[idx])
    return tracks_geometry(state, proposal, tracks, colors, lon_west)


def proposal_members(state: ReviewState, proposal: str) -> list[str]:
    """The tracks :func:`proposal_geometry` draws: the members of the target(s) of the
    proposal's two tracks, earliest first, and the two tracks (a rejected pair's too)."""
    k = state._row[proposal]
    a, b = state.track_a[k], state.track_b[k]
    return list(
        dict.fromkeys([*state.members(state.target(a)), *state.members(state.target(b)), a, b])
    )


def tracks_geometry(
    state: ReviewState,
    proposal: str,
    tracks: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]],
    colors: dict[str, str] | None = None,
    lon_west: float = -180.0,
) -> ProposalGeometry:
    """:func:`proposal_geometry` from the time-sorted arrays (t, lon, lat) of every track
    of :func:`proposal_members` (in that order), drawn in the band ``lon_west`` (their
    layer's: :func:`~wakeline.app.map_draw.unwrap_tracks`, as the map draws it)."""
    k = state._row[proposal]
    track_a, track_b = state.track_a[k], state.track_b[k]
    geom = ProposalGeometry(proposal)
    pair = dict(zip((track_a, track_b), PAIR_COLORS, strict=True))
    pair.update({t: c for t, c in (colors or {}).items() if t in pair})
    # each track continuous across 180° and in its layer's band, as the map draws it: not
    # a line across the whole world, nor two tracks 360° apart
    tracks = dict(zip(tracks, _in_band(list(tracks.values()), lon_west), strict=True))
    for m, (_t, lon, lat) in tracks.items():
        geom.pieces.append(Piece(m, lon, lat, pair.get(m, MUTED), m not in pair))
    ta, tb = tracks.get(track_a), tracks.get(track_b)
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
            plon, plat = predicted_path(
                end, _end_velocity(*ta, at_end=True), start, _end_velocity(*tb, at_end=False)
            )
            if bends_off(plon, plat, end, start):
                geom.predicted = (_continuous(np.r_[end[1], plon])[1:], plat)
            # else the predicted path is the connector's straight line: drawn (dotted, 2 px)
            # over it, it hid the dashes of a pending join, which looked accepted (solid);
            # operator test 11, Saronic AIS, whose points have no speed nor course
    return geom


#: A predicted path that strays less than this share of the gap's straight distance from
#: the connector's line (and not past its ends) is that line (:func:`bends_off`).
STRAIGHT_SHARE = 0.02


def bends_off(
    plon: np.ndarray,
    plat: np.ndarray,
    end: tuple[float, float, float],
    start: tuple[float, float, float],
    share: float = STRAIGHT_SHARE,
) -> bool:
    """Whether the predicted path (``plon, plat``) from ``end`` to ``start`` (t, lon, lat)
    departs from their straight connector by more than ``share`` of its length (at least
    0.5 m): sideways, or along it before ``end`` or past ``start``."""
    x, y = geo.to_local(np.asarray(plon), np.asarray(plat), end[1], end[2])
    ex, ey = geo.to_local(np.array([start[1]]), np.array([start[2]]), end[1], end[2])
    length = float(np.hypot(ex[0], ey[0]))
    tol = max(share * length, 0.5)
    if length == 0.0:
        return bool(np.hypot(x, y).max(initial=0.0) > tol)
    ux, uy = ex[0] / length, ey[0] / length
    along = x * ux + y * uy
    side = np.abs(x * uy - y * ux)
    return bool(side.max(initial=0.0) > tol or along.min() < -tol or along.max() > length + tol)


def _in_band(tracks: list[tuple], west: float) -> list[tuple]:
    """The tracks (t, lon, lat) with lon as the map draws them in the band ``west``: one
    :func:`~wakeline.app.map_draw.unwrap_tracks` over all of them."""
    if not tracks:
        return []
    sizes = np.array([len(lon) for _t, lon, _lat in tracks], dtype="int64")
    starts = np.r_[0, np.cumsum(sizes)[:-1]].astype("int64")
    lon = np.concatenate([np.asarray(lon, dtype="float64") for _t, lon, _lat in tracks])
    lon = unwrap_tracks(lon, starts[sizes > 0], sizes[sizes > 0], west)
    return [
        (t, lon[k : k + n], lat) for (t, _lon, lat), k, n in zip(tracks, starts, sizes, strict=True)
    ]


def _continuous(lon: np.ndarray) -> np.ndarray:
    """Longitudes made continuous from the first (±360° steps removed): one track of
    :func:`~wakeline.app.map_draw.unwrap_tracks`."""
    lon = np.asarray(lon, dtype="float64")
    return unwrap_tracks(lon, np.array([0]), np.array([len(lon)]))


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
        items.append(pg.PlotDataItem(*geom.connector, pen=join_pen(geom.status)))
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


class ProposalItems:
    """The items of :func:`proposal_items` on one canvas, made once and reused.

    :meth:`show` puts a geometry's arrays and colours into the kept items (one curve per
    piece, the connector and the predicted path: the colours, widths and zValues
    :func:`proposal_items` gives them; the pieces' start marks in two scatter items, the
    context's and the pair's, at those zValues) and hides the rest; :meth:`clear` hides
    them all. A piece whose arrays are the ones already shown keeps its data (a new colour
    only restyles it), so the same proposal in the legend's new colours costs little.
    ``z`` overrides every zValue (the members of a selected fused track).
    """

    def __init__(self, canvas, z: float | None = None) -> None:
        self.canvas = canvas
        self.z = z
        self.curves: list[pg.PlotDataItem] = []
        self.marks = {  # start marks: (item, what it shows) for context, pair
            context: (self._add(pg.ScatterPlotItem(pen=None)), None) for context in (True, False)
        }
        for context, (item, _) in self.marks.items():
            item.setZValue(self._z(Z_MEMBER if context else Z_PAIR))
        self.connector: pg.PlotDataItem | None = None
        self._joined = "pending"  # the status the connector's pen shows (join_pen)
        self.predicted: pg.PlotDataItem | None = None
        self.shown: list[pg.GraphicsObject] = []  # in use
        self._data: list[tuple] = []  # per curve: the (lon, lat) arrays it shows
        self._style: list[tuple | None] = []  # per curve: (color, context)

    def _z(self, z: float) -> float:
        return z if self.z is None else self.z

    def _add(self, item: pg.GraphicsObject) -> pg.GraphicsObject:
        item.setVisible(False)
        self.canvas.addItem(item)
        return item

    def _line(self, pen: QtGui.QPen) -> pg.PlotDataItem:
        item = pg.PlotDataItem([], [], pen=pen)
        item.setZValue(self._z(Z_GAP))
        return self._add(item)

    def reserve(self, n: int, batch: int) -> bool:
        """Make (hidden) up to ``batch`` more piece curves towards ``n``; True while short."""
        for _ in range(min(batch, n - len(self.curves))):
            self.curves.append(self._add(pg.PlotDataItem([], [])))
            self._data.append((None, None))
            self._style.append(None)
        return len(self.curves) < n

    def show(self, geom: ProposalGeometry) -> list[pg.GraphicsObject]:
        """Draw ``geom``; returns the items in use."""
        shown: list[pg.GraphicsObject] = []
        n = len(geom.pieces)
        self.reserve(n, n)
        starts: dict[bool, list] = {True: [], False: []}
        for k, piece in enumerate(geom.pieces):
            curve = self.curves[k]
            z, width = (Z_MEMBER, 2) if piece.context else (Z_PAIR, 3)
            style = (piece.color, piece.context)
            if self._data[k][0] is not piece.lon or self._data[k][1] is not piece.lat:
                curve.setData(piece.lon, piece.lat, pen=pg.mkPen(piece.color, width=width))
                self._data[k] = (piece.lon, piece.lat)
            elif self._style[k] != style:
                curve.setPen(pg.mkPen(piece.color, width=width))
            self._style[k] = style
            curve.opts["name"] = piece.track
            curve.setZValue(self._z(z))
            curve.setVisible(True)
            shown.append(curve)
            if len(piece.lon):
                starts[piece.context].append((piece.lon[0], piece.lat[0], piece.color))
        for k in range(n, len(self.curves)):
            self._hide(k)
        for context, (item, was) in self.marks.items():
            now = tuple(starts[context])
            if now != was:
                if now:
                    x, y, colors = zip(*now, strict=True)
                    brushes = [pg.mkBrush(c) for c in colors]
                    item.setData(x, y, size=7 if context else 9, brush=brushes)
                else:
                    item.setData([], [])
                self.marks[context] = (item, now)
            item.setVisible(bool(now))
            if now:
                shown.append(item)
        if geom.connector is not None and self.connector is None:
            self.connector = self._line(join_pen(geom.status))
            self._joined = geom.status
        if geom.connector is not None and geom.status != self._joined:
            self.connector.setPen(join_pen(geom.status))  # decided: solid
            self._joined = geom.status
        if geom.predicted is not None and self.predicted is None:
            # Neutral ink, as the connector's: a colour of the palette would read as the
            # track the legend names in it.
            dot = QtCore.Qt.PenStyle.DotLine
            self.predicted = self._line(pg.mkPen("#000000", width=2, style=dot))
        for item, xy in ((self.connector, geom.connector), (self.predicted, geom.predicted)):
            if item is None:
                continue
            if xy is None:
                if item.isVisible():
                    item.setData([], [])
                    item.setVisible(False)
                continue
            item.setData(*xy)
            item.setVisible(True)
            shown.append(item)
        self.shown = shown
        return shown

    def _hide(self, k: int) -> None:
        curve = self.curves[k]
        if self._data[k][0] is not None:
            curve.setData([], [])
            self._data[k] = (None, None)
        curve.opts["name"] = None
        curve.setVisible(False)

    def clear(self) -> None:
        """Hide every item (kept for the next proposal)."""
        for k in range(len(self.curves)):
            self._hide(k)
        for context, (item, was) in self.marks.items():
            if was:
                item.setData([], [])
            item.setVisible(False)
            self.marks[context] = (item, None)
        for item in (self.connector, self.predicted):
            if item is not None and item.isVisible():
                item.setData([], [])
                item.setVisible(False)
        self.shown = []

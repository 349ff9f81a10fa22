"""Views of the current proposal (issue 13): the Gantt chart of its target's members and
the nearby candidates with a time cursor, and the candidate network (tracks as nodes,
candidate links as edges weighted by cost; clicking an edge selects its proposal).

Both take the core :class:`~wakeline.core.review.ReviewState` and redraw on
:meth:`show_proposal`; neither edits anything. Their pyqtgraph items are made once and
reused (:class:`ItemPool`): making and deleting tens of text items per proposal was most
of a redraw on the GUI thread.
"""

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from wakeline.app import ink
from wakeline.app import review_text as T
from wakeline.core.review import ReviewState

MEMBER = "#1f77b4"
NEARBY = "#b0b0b0"
STATUS_PEN = {
    "pending": ("#4a6fa5", QtCore.Qt.PenStyle.SolidLine),
    "accepted": ("#2ca02c", QtCore.Qt.PenStyle.SolidLine),
    "rejected": ("#d62728", QtCore.Qt.PenStyle.DashLine),
    "split": ("#ff7f0e", QtCore.Qt.PenStyle.DashLine),
    "runner-up": ("#9a9a9a", QtCore.Qt.PenStyle.DotLine),
    "manual": ("#9467bd", QtCore.Qt.PenStyle.SolidLine),
}


def neighbourhood(state: ReviewState, proposal: str, hops: int = 1) -> tuple[list, list]:
    """Tracks around a proposal: (members of its target(s), nearby tracks) — nearby are
    the tracks linked to a member by any proposal or runner-up, ``hops`` steps out."""
    k = state._row.get(proposal)
    if k is None:
        return [], []
    a, b = state.track_a[k], state.track_b[k]
    members = list(dict.fromkeys(state.members(state.target(a)) + state.members(state.target(b))))
    base = _static(state)["adj"]
    manual: dict[str, set] = {}
    for x, y in state.links:
        manual.setdefault(x, set()).add(y)
        manual.setdefault(y, set()).add(x)
    seen = set(members)
    frontier = set(members)
    for _ in range(hops):
        new = set()
        for t in frontier:
            new |= base.get(t, set())
            new |= manual.get(t, set())
        new -= seen
        seen |= new
        frontier = new
    t0 = _static(state)["t0"]
    nearby = sorted(seen - set(members), key=lambda x: t0[x])
    return members, nearby


_STATIC: dict[int, tuple[object, dict]] = {}


def _static(state: ReviewState) -> dict:
    """Arrays of the links that never change (proposals and runner-ups) and their
    adjacency; built once per state."""
    hit = _STATIC.get(id(state))
    if hit is not None and hit[0] is state:
        return hit[1]
    p = state.proposals
    ta, tb = state.track_a, state.track_b
    rival = p["runner_up"].to_numpy().astype(object)
    has = rival != ""
    side_a = p["runner_up_side"].to_numpy().astype(object) == "a"
    pid = p["proposal"].to_numpy().astype(object)
    cost = p["cost"].to_numpy(dtype="float64")
    rcost = p["runner_up_cost"].to_numpy(dtype="float64")
    gate = p["gate"].to_numpy(dtype="float64")
    d = {
        "a": np.concatenate([ta, np.where(side_a, ta, rival)[has]]),
        "b": np.concatenate([tb, np.where(side_a, rival, tb)[has]]),
        "cost": np.concatenate([cost, rcost[has]]),
        "gate": np.concatenate([gate, gate[has]]),
        "proposal": np.concatenate([pid, pid[has]]),
        "n_prop": len(p),
    }
    adj: dict[str, set] = {}
    for a, b in zip(d["a"].tolist(), d["b"].tolist(), strict=True):
        adj.setdefault(a, set()).add(b)
        adj.setdefault(b, set()).add(a)
    d["adj"] = adj
    d["t0"] = dict(zip(state._labels_arr.tolist(), state._t0_arr.tolist(), strict=True))
    d["span"] = (  # first and last time of every track, by row of state.tracks
        state.tracks["t0"].to_numpy(dtype="float64"),
        state.tracks["t1"].to_numpy(dtype="float64"),
    )
    if len(_STATIC) > 8:
        _STATIC.clear()
    _STATIC[id(state)] = (state, d)
    return d


def _t0(state: ReviewState) -> dict:
    return _static(state)["t0"]


#: Where the track names sit: this far from the centre (the nodes' circle has radius 1).
NAME_AT = 1.09


def _z(item, z: float):
    item.setZValue(z)
    return item


class ItemPool:
    """Items of one kind in a plot, made on demand and kept: :meth:`take` hands out the
    next one (shown), :meth:`done` hides those the last drawing did not take."""

    def __init__(self, plot: pg.PlotWidget, make) -> None:
        self.plot, self.make = plot, make
        self.items: list = []
        self.used = 0
        self._shown = 0

    def begin(self) -> None:
        self.used = 0

    def reserve(self, n: int, batch: int) -> bool:
        """Make (hidden) up to ``batch`` more items towards ``n``; True while short."""
        for _ in range(min(batch, n - len(self.items))):
            item = self.make()
            item.setVisible(False)
            self.plot.addItem(item)
            self.items.append(item)
        return len(self.items) < n

    def take(self):
        if self.used == len(self.items):
            item = self.make()
            self.plot.addItem(item)
            self.items.append(item)
        item = self.items[self.used]
        self.used += 1
        item.setVisible(True)
        return item

    def done(self) -> list:
        """Hide the items not taken since :meth:`begin`; the items in use."""
        for item in self.items[self.used : self._shown]:
            item.setVisible(False)
        self._shown = self.used
        return self.items[: self.used]


def candidate_edges(state: ReviewState, among: list[str] | None = None) -> pd.DataFrame:
    """Every known candidate link (or those between the tracks ``among``): the proposals
    (``kind`` = their status), their runner-ups (``runner-up``) and the manual links
    (``manual``). Columns a, b, cost, gate, kind, proposal."""
    d = _static(state)
    n = d["n_prop"]
    kind = np.concatenate(
        [state.status.astype(object), np.full(len(d["a"]) - n, "runner-up", dtype=object)]
    )
    links = sorted(state.links)
    a = np.concatenate([d["a"], np.array([x for x, _ in links], dtype=object)])
    b = np.concatenate([d["b"], np.array([y for _, y in links], dtype=object)])
    m = len(links)
    cols = {
        "a": a,
        "b": b,
        "cost": np.concatenate([d["cost"], np.full(m, np.nan)]),
        "gate": np.concatenate([d["gate"], np.full(m, np.nan)]),
        "kind": np.concatenate([kind, np.full(m, "manual", dtype=object)]),
        "proposal": np.concatenate([d["proposal"], np.full(m, "", dtype=object)]),
    }
    if among is not None:
        keep = np.isin(a, np.asarray(among, dtype=object)) & np.isin(
            b, np.asarray(among, dtype=object)
        )
        cols = {k: v[keep] for k, v in cols.items()}
    return pd.DataFrame(cols)


class GanttView(pg.PlotWidget):
    """Lifetimes of the current proposal's members (coloured) and of nearby candidates
    (grey), one row per track, time in minutes; a draggable time cursor."""

    time_changed = QtCore.Signal(float)  # seconds since epoch

    def __init__(self, state: ReviewState, parent=None) -> None:
        ink.setup()
        # No context menus: made and dropped again, pyqtgraph's view-box menu took ~10 ms
        # of the bind's GUI-thread turn per view.
        super().__init__(parent, background="w", enableMenu=False)
        self.state = state
        self.setLabel("bottom", self.tr("time"), units=self.tr("min"))
        # Minutes stay minutes: no "kmin" on data spanning days.
        self.getAxis("bottom").enableAutoSIPrefix(False)
        self.getPlotItem().hideAxis("left")
        self.getPlotItem().setMenuEnabled(False)
        self.t_ref = float(state.tracks["t0"].min()) if len(state.tracks) else 0.0
        self.retranslate()  # the axis names its zero in the display zone (h191)
        self.cursor = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen("#d62728", width=1.5))
        self.cursor.sigPositionChanged.connect(self._cursor_moved)
        self.rows: list[str] = []
        self.members: list[str] = []
        self._items: list = []  # the items showing the current proposal
        self._span = None  # the shown rows' bar starts and ends (min), for _fit_x
        self.addItem(self.cursor)
        self._bars = pg.BarGraphItem(x0=[], x1=[], y=[], height=0.6)
        self._bars.setVisible(False)
        self.addItem(self._bars)
        self._labels = ItemPool(self, lambda: pg.TextItem("", anchor=(1, 0.5)))
        self._brush = {c: pg.mkBrush(c) for c in (MEMBER, NEARBY)}
        self._pen = {c: pg.mkPen(c) for c in (MEMBER, NEARBY)}

    def retranslate(self) -> None:
        """The time axis' title in the current language (a live switch left it English),
        with its zero as a date in View ▸ Time zone's zone (``0 = 2026-12-05 08:00:00 UTC+8``)."""
        from wakeline.app.time_text import format_time, is_relative_time

        zero = format_time(self.t_ref, is_relative_time(np.asarray([self.t_ref])))
        self.setLabel("bottom", f"{self.tr('time')} (0 = {zero})", units=self.tr("min"))

    def set_time(self, t_s: float) -> None:
        """Move the cursor to ``t_s`` (s since epoch) without re-emitting."""
        self.cursor.blockSignals(True)
        self.cursor.setValue((t_s - self.t_ref) / 60.0)
        self.cursor.blockSignals(False)

    def time(self) -> float:
        return self.t_ref + 60.0 * float(self.cursor.value())

    def _cursor_moved(self) -> None:
        self.time_changed.emit(self.time())

    def pools_for(self, proposal: str) -> list[tuple[ItemPool, int]]:
        """The item pools and how many items :meth:`show_proposal` will take from them."""
        members, nearby = neighbourhood(self.state, proposal)
        return [(self._labels, len(members) + len(nearby))]

    def show_proposal(self, proposal: str) -> None:
        st = self.state
        members, nearby = neighbourhood(st, proposal)
        self.members, self.rows = members, members + nearby
        self._labels.begin()
        if not self.rows:
            self._span = None
            self._labels.done()
            self._bars.setVisible(False)
            self._items = []
            return
        t0, t1 = _static(st)["span"]
        rows = np.array([st._track_no[t] for t in self.rows], dtype="int64")
        x0 = (t0[rows] - self.t_ref) / 60.0
        x1 = (t1[rows] - self.t_ref) / 60.0
        y = -np.arange(len(self.rows), dtype=float)
        colors = [MEMBER] * len(members) + [NEARBY] * len(nearby)
        self._bars.setOpts(
            x0=x0,
            x1=x1,
            y=y,
            height=0.6,
            brushes=[self._brush[c] for c in colors],
            pens=[self._pen[c] for c in colors],
        )
        self._bars.setVisible(True)
        k_row = st._row[proposal]
        pair = (st.track_a[k_row], st.track_b[k_row])
        for k, name in enumerate(self.rows):
            bold = name in pair
            text = self._labels.take()
            text.setText(("▶ " if bold else "") + name, "#000" if k < len(members) else "#666")
            text.setPos(x0[k], y[k])
        self._items = [self._bars, *self._labels.done()]
        self._span = (x0, x1)
        self._fit_x()
        self.setYRange(float(y.min()) - 0.8, 0.8, padding=0)
        # The cursor stays at the slider's time (it moved to the first bar's start, away
        # from the slider, which still showed its own time).

    def _fit_x(self) -> None:
        """The time range of the shown rows, with room on the left for each row's label
        (drawn left of its bar, a fixed size in pixels): in a narrow dock a 30 % margin
        left the first member's name off the chart."""
        span = getattr(self, "_span", None)  # (resized while PlotWidget builds: none yet)
        if span is None or self.plotItem is None:  # nothing shown, or closed
            return
        x0, x1 = span
        lo, hi = float(np.min(x0)), float(np.max(x1))
        right = hi + 0.05 * (hi - lo) + 1.0
        left = lo - (0.3 * (hi - lo) + 1.0)
        width_px = self.getViewBox().width()
        if width_px > 0:
            labels = self._labels.items[: self._labels.used]
            # label k ends at its bar's start: (x0 - left) / (right - left) >= its share
            share = np.array([t.textItem.boundingRect().width() + 6.0 for t in labels])
            share = np.minimum(share / width_px, 0.8)
            k = np.arange(min(len(share), len(x0)))
            if len(k):
                need = (x0[k] - share[k] * right) / (1.0 - share[k])
                left = min(left, float(need.min()))
        self.setXRange(left, right, padding=0)
        self._fitted = tuple(self.getViewBox().viewRange()[0])

    def resizeEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().resizeEvent(event)
        # fitted again only while the operator has not panned or zoomed it (review)
        fitted = getattr(self, "_fitted", None)  # (resized while PlotWidget builds: none)
        if fitted is None or self.plotItem is None:
            self._fit_x()
        elif np.allclose(self.getViewBox().viewRange()[0], fitted):
            self._fit_x()


class NetworkView(pg.PlotWidget):
    """Tracks around the current proposal as nodes (members filled), candidate links as
    edges: width grows as cost falls (relative to the gate), colour and dash by status
    (runner-ups dotted grey, manual merges purple). Clicking an edge emits
    ``proposal_clicked`` with its proposal."""

    proposal_clicked = QtCore.Signal(str)

    def __init__(self, state: ReviewState, parent=None) -> None:
        ink.setup()
        super().__init__(parent, background="w", enableMenu=False)  # as GanttView
        self.state = state
        self.getPlotItem().hideAxis("left")
        self.getPlotItem().hideAxis("bottom")
        self.getPlotItem().setMenuEnabled(False)
        self.setAspectLocked(True)
        self.pos: dict[str, tuple[float, float]] = {}
        self.edges = pd.DataFrame()
        self.current = ""
        self.max_nodes = 24  # members always; the nearest others up to this many nodes
        self._items: list = []  # the items showing the current proposal
        self._lines = ItemPool(self, lambda: _z(pg.PlotCurveItem(), 1))
        self._costs = ItemPool(self, self._cost_item)
        self._names = ItemPool(self, lambda: _z(pg.TextItem("", color="#000"), 3))
        self._dots = pg.ScatterPlotItem(size=14, pen=pg.mkPen("#333", width=1.2))
        self._dots.setVisible(False)
        self._dots.setZValue(2)  # edges under the nodes, names and costs over them
        self.addItem(self._dots)
        self._node_brush = {c: pg.mkBrush(c) for c in (MEMBER, "#ffffff")}
        self._name_px: tuple[float, float] | None = None  # widest name, line height (px)
        self.getPlotItem().getViewBox().sigResized.connect(self._resized)
        self.scene().sigMouseClicked.connect(self._clicked)
        self.scene().sigMouseMoved.connect(self._hover)
        self._plan: list = []

    @staticmethod
    def _cost_item() -> pg.TextItem:
        item = pg.TextItem("", anchor=(0.5, 0.5), fill=pg.mkBrush(255, 255, 255, 225))
        item.textItem.document().setDocumentMargin(1)  # a tight box: room in a small circle
        item.setZValue(5)
        return item

    def _nodes(self, proposal: str, hops: int) -> tuple[list[str], list[str]]:
        members, nearby = neighbourhood(self.state, proposal, hops)
        return members, members + nearby[: max(0, self.max_nodes - len(members))]

    def pools_for(self, proposal: str, hops: int = 2) -> list[tuple[ItemPool, int]]:
        """The item pools and how many items :meth:`show_proposal` will take from them."""
        _members, nodes = self._nodes(proposal, hops)
        n_edges = len(candidate_edges(self.state, nodes)) if nodes else 0
        return [(self._lines, n_edges), (self._costs, n_edges), (self._names, len(nodes))]

    def show_proposal(self, proposal: str, hops: int = 2) -> None:
        self.current = proposal
        members, nodes = self._nodes(proposal, hops)
        for pool in (self._lines, self._costs, self._names):
            pool.begin()
        if not nodes:
            self.edges = pd.DataFrame()
            for pool in (self._lines, self._costs, self._names):
                pool.done()
            self._dots.setVisible(False)
            self._items = []
            self._plan = []
            return
        # Circle, members first (so they sit together), in time order.
        ang = 2 * np.pi * np.arange(len(nodes)) / len(nodes) + np.pi / 2
        self.pos = {
            n: (float(np.cos(a)), float(np.sin(a))) for n, a in zip(nodes, ang, strict=True)
        }
        self.edges = candidate_edges(self.state, nodes)
        labels: list = []
        for r in self.edges.itertuples():  # one item per edge: tens around a proposal
            color, style = STATUS_PEN.get(r.kind, STATUS_PEN["pending"])
            rel = r.cost / r.gate if r.gate == r.gate and r.gate > 0 else 0.5
            width = 1.0 + 5.0 * float(np.clip(1.0 - rel, 0.0, 1.0))
            if r.proposal == proposal and r.kind != "runner-up":
                width += 2.0
            (xa, ya), (xb, yb) = self.pos[r.a], self.pos[r.b]
            line = self._lines.take()
            line.setData([xa, xb], [ya, yb], pen=pg.mkPen(color, width=width, style=style))
            if r.kind not in ("manual", "runner-up") and r.cost == r.cost:
                labels.append((r.proposal == proposal, r, color, (xa, ya, xb, yb)))
        xy = np.array([self.pos[n] for n in nodes])
        in_target = set(members)
        brushes = [self._node_brush[MEMBER if n in in_target else "#ffffff"] for n in nodes]
        self._dots.setData(xy[:, 0], xy[:, 1], brush=brushes)
        self._dots.setVisible(True)
        # Labels: planned here, placed by _frame -> _place_labels once the view's size in
        # pixels is known (names and costs are pixels: on a narrow dock the chords' middles
        # and the names crowd a circle some tens of pixels wide).
        k = self.state._row.get(proposal)
        pair = {self.state.track_a[k], self.state.track_b[k]} if k is not None else set()
        plan: list = []
        for n, a in zip(nodes, ang, strict=True):
            c, s = float(np.cos(a)), float(np.sin(a))
            t = self._names.take()
            t.setText(n)
            anchor = (0.5 - 0.5 * c, 0.5 + 0.5 * s)
            t.setAnchor(anchor)
            rank = 1 if n in pair else (2 if n in in_target else 3)
            plan.append((rank, t, [(NAME_AT * c, NAME_AT * s)], anchor))
        for current, r, color, (xa, ya, xb, yb) in labels:
            lab = self._costs.take()
            lab.setText(f"{r.cost:.3g}", color)
            plan.append((0 if current else 4, lab, (xa, ya, xb, yb), (0.5, 0.5)))
        self._plan = sorted(plan, key=lambda item: item[0])  # stable: time order within
        self._items = [
            *self._lines.done(),
            self._dots,
            *self._costs.done(),
            *self._names.done(),
        ]
        metrics = QtGui.QFontMetricsF(self._names.items[0].textItem.font()) if nodes else None
        self._name_px = (
            (max(metrics.horizontalAdvance(n) for n in nodes) + 8.0, metrics.height() + 4.0)
            if metrics
            else (0.0, 0.0)
        )
        self._frame()

    def _frame(self) -> None:
        """The circle with its track names whole in the view: the names are pixels
        beside the nodes, so the range that holds them depends on the view's size in
        pixels (a fixed ±1.6 cut "S1:378113585" at a narrow dock's edges)."""
        vb = self.getPlotItem().getViewBox()
        w_px, h_px = float(vb.width()), float(vb.height())
        name_w, name_h = self._name_px or (0.0, 0.0)
        x_half, y_half = 1.6, 1.45
        if w_px > 0 and h_px > 0:
            # A name reaches NAME_AT + its width in data units (2·half / pixels each).
            x_half = max(x_half, NAME_AT / max(1.0 - 2.0 * name_w / w_px, 0.2))
            y_half = max(y_half, NAME_AT / max(1.0 - 2.0 * name_h / h_px, 0.2))
        # One call: the locked aspect then widens whichever axis needs it (two calls
        # narrowed the first to fit the second).
        self.setRange(xRange=(-x_half, x_half), yRange=(-y_half, y_half), padding=0)
        if w_px > 0 and h_px > 0:
            # The locked aspect widens one axis: pixels per unit are the smaller ratio.
            self._place_labels(min(w_px / (2 * x_half), h_px / (2 * y_half)))

    def _resized(self, *_args) -> None:
        if self._name_px is not None:  # a proposal shown: keep its names in view
            self._frame()

    def _place_labels(self, px: float) -> None:
        """Show the planned names and costs where their boxes (pixels) do not overlap,
        most important first: the current proposal's cost, its two track names, the other
        members' names, the nearby tracks' names, the other costs. A cost tries its edge's
        middle, then beside it along the edge's normal, then a third of the way from either
        end; a name its node's side, then further out or slid along the circle; a label
        with no free place in the view is hidden (every cost is in the queue table and in
        the edge's tooltip; the proposal's own names and cost are shown even so).
        ``px``: pixels per view unit. Tens of labels, tens of boxes each."""
        taken: list[QtCore.QRectF] = []
        vb = self.getPlotItem().getViewBox()
        w_px, h_px = float(vb.width()), float(vb.height())
        view = QtCore.QRectF(-w_px / 2, -h_px / 2, w_px, h_px).adjusted(-1, -1, 1, 1)
        for rank, item, where, anchor in self._plan:
            br = item.textItem.boundingRect()
            w, h = float(br.width()), float(br.height())
            if len(where) == 4:  # an edge: candidate places along and beside it
                xa, ya, xb, yb = where
                ex, ey = (xb - xa) * px, (yb - ya) * px
                norm = float(np.hypot(ex, ey)) or 1.0
                nx, ny = -ey / norm, ex / norm  # unit normal (pixels)
                step = 0.5 * abs(nx) * w + 0.5 * abs(ny) * h + 1.0  # half a box off the line
                spots = []
                for u in (0.5, 0.35, 0.65):
                    for off in (0.0, step, -step, 1.5 * step, -1.5 * step):
                        spots.append(
                            (
                                (xa + u * (xb - xa)) * px + off * nx,
                                -(ya + u * (yb - ya)) * px + off * ny,
                            )
                        )
            else:  # a name: beside its node, else further out or slid along the circle
                ((x, y),) = where
                r = float(np.hypot(x, y)) or 1.0
                ux, uy = x / r, -y / r  # outwards (pixels, y down)
                spots = [
                    (x * px + out * ux - slide * uy, -y * px + out * uy + slide * ux)
                    for out in (0.0, 0.5 * h, h)
                    for slide in (0.0, 0.6 * h, -0.6 * h)
                ]
            chosen = None
            for cx, cy in spots:
                rect = QtCore.QRectF(cx - anchor[0] * w, cy - anchor[1] * h, w, h)
                if view.contains(rect) and not any(rect.intersects(o) for o in taken):
                    chosen = (cx, cy, rect)
                    break
            if chosen is None and rank <= 1:  # the proposal's own names and cost: always
                cx, cy = spots[0]
                chosen = (cx, cy, QtCore.QRectF(cx - anchor[0] * w, cy - anchor[1] * h, w, h))
            item.setVisible(chosen is not None)
            if chosen is not None:
                item.setPos(chosen[0] / px, -chosen[1] / px)
                taken.append(chosen[2])

    def _hover(self, scene_pos) -> None:
        """An edge's proposal, tracks and cost as the tooltip (a cost hidden when crowded)."""
        vb = self.getPlotItem().getViewBox()
        p = vb.mapSceneToView(scene_pos)
        pid = self.edge_at(float(p.x()), float(p.y()))
        tip = ""
        if pid:
            r = self.edges[(self.edges["proposal"] == pid) & (self.edges["kind"] != "runner-up")]
            if len(r):
                r = r.iloc[0]
                tip = f"{pid}: {r['a']} → {r['b']}, {T.column_titles()['cost']} {T.cost_text(r['cost'])}"
        if tip != self.toolTip():
            self.setToolTip(tip)

    def edge_at(self, x: float, y: float, tol: float = 0.08) -> str:
        """The proposal of the nearest proposal edge within ``tol`` (view units) of (x, y);
        runner-up and manual edges select nothing ("")."""
        e = self.edges
        if len(e) == 0:
            return ""
        e = e[~e["kind"].isin(["runner-up", "manual"])]
        if len(e) == 0:
            return ""
        a = np.array([self.pos[t] for t in e["a"]])
        b = np.array([self.pos[t] for t in e["b"]])
        d = b - a
        den = np.maximum((d * d).sum(axis=1), 1e-12)
        u = np.clip(((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1]) / den, 0, 1)
        dist = np.hypot(a[:, 0] + u * d[:, 0] - x, a[:, 1] + u * d[:, 1] - y)
        k = int(np.argmin(dist))
        return str(e["proposal"].iloc[k]) if dist[k] <= tol else ""

    def edge_midpoint(self, proposal: str) -> tuple[float, float]:
        """View coordinates of the middle of a proposal's edge (for tests and tours)."""
        r = self.edges[
            (self.edges["proposal"] == proposal) & ~self.edges["kind"].isin(["runner-up", "manual"])
        ].iloc[0]
        (xa, ya), (xb, yb) = self.pos[r["a"]], self.pos[r["b"]]
        return (xa + xb) / 2, (ya + yb) / 2

    def _clicked(self, event) -> None:
        vb = self.getPlotItem().getViewBox()
        p = vb.mapSceneToView(event.scenePos())
        pid = self.edge_at(float(p.x()), float(p.y()))
        if pid:
            self.proposal_clicked.emit(pid)

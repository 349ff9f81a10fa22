"""Views of the current proposal (issue 13): the Gantt chart of its target's members and
the nearby candidates with a time cursor, and the candidate network (tracks as nodes,
candidate links as edges weighted by cost; clicking an edge selects its proposal).

Both take the core :class:`~wakeline.core.review.ReviewState` and redraw on
:meth:`show_proposal`; neither edits anything.
"""

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore

from wakeline.app import ink
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
    p = state.proposals
    row = p.index[p["proposal"] == proposal]
    if len(row) == 0:
        return [], []
    r = p.loc[row[0]]
    members = list(
        dict.fromkeys(
            state.members(state.target(r["track_a"])) + state.members(state.target(r["track_b"]))
        )
    )
    adj = _adjacency(state)
    seen = set(members)
    frontier = set(members)
    for _ in range(hops):
        new = set().union(*(adj.get(t, ()) for t in frontier)) - seen
        seen |= new
        frontier = new
    t0 = _t0(state)
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
    if len(_STATIC) > 8:
        _STATIC.clear()
    _STATIC[id(state)] = (state, d)
    return d


def _adjacency(state: ReviewState) -> dict:
    base = _static(state)["adj"]
    if not state.links:
        return base
    adj = {k: set(v) for k, v in base.items()}
    for a, b in state.links:
        adj.setdefault(a, set()).add(b)
        adj.setdefault(b, set()).add(a)
    return adj


def _t0(state: ReviewState) -> dict:
    return dict(zip(state._labels_arr.tolist(), state._t0_arr.tolist(), strict=True))


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
        super().__init__(parent, background="w")
        self.state = state
        self.setLabel("bottom", self.tr("time"), units=self.tr("min"))
        # Minutes stay minutes: no "kmin" on data spanning days.
        self.getAxis("bottom").enableAutoSIPrefix(False)
        self.getPlotItem().hideAxis("left")
        self.getPlotItem().setMenuEnabled(False)
        self.t_ref = float(state.tracks["t0"].min()) if len(state.tracks) else 0.0
        self.cursor = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen("#d62728", width=1.5))
        self.cursor.sigPositionChanged.connect(self._cursor_moved)
        self.rows: list[str] = []
        self.members: list[str] = []
        self._items: list = []
        self.addItem(self.cursor)

    def set_time(self, t_s: float) -> None:
        """Move the cursor to ``t_s`` (s since epoch) without re-emitting."""
        self.cursor.blockSignals(True)
        self.cursor.setValue((t_s - self.t_ref) / 60.0)
        self.cursor.blockSignals(False)

    def time(self) -> float:
        return self.t_ref + 60.0 * float(self.cursor.value())

    def _cursor_moved(self) -> None:
        self.time_changed.emit(self.time())

    def show_proposal(self, proposal: str) -> None:
        for it in self._items:
            self.removeItem(it)
        self._items = []
        members, nearby = neighbourhood(self.state, proposal)
        self.members, self.rows = members, members + nearby
        if not self.rows:
            return
        span = self.state.tracks.set_index("track").loc[self.rows]
        x0 = (span["t0"].to_numpy() - self.t_ref) / 60.0
        x1 = (span["t1"].to_numpy() - self.t_ref) / 60.0
        y = -np.arange(len(self.rows), dtype=float)
        colors = [MEMBER] * len(members) + [NEARBY] * len(nearby)
        bars = pg.BarGraphItem(
            x0=x0,
            x1=x1,
            y=y,
            height=0.6,
            brushes=[pg.mkBrush(c) for c in colors],
            pens=[pg.mkPen(c) for c in colors],
        )
        self.addItem(bars)
        self._items.append(bars)
        p = self.state.proposals.set_index("proposal").loc[proposal]
        for k, name in enumerate(self.rows):
            bold = name in (p["track_a"], p["track_b"])
            text = pg.TextItem(
                ("▶ " if bold else "") + name,
                color="#000" if k < len(members) else "#666",
                anchor=(1, 0.5),
            )
            text.setPos(x0[k], y[k])
            self.addItem(text)
            self._items.append(text)
        lo, hi = float(np.min(x0)), float(np.max(x1))
        pad = 0.3 * (hi - lo) + 1.0
        self.setXRange(lo - pad, hi + 0.05 * (hi - lo) + 1.0, padding=0)
        self.setYRange(float(y.min()) - 0.8, 0.8, padding=0)
        if not lo <= self.cursor.value() <= hi:
            self.set_time(self.t_ref + 60.0 * lo)


class NetworkView(pg.PlotWidget):
    """Tracks around the current proposal as nodes (members filled), candidate links as
    edges: width grows as cost falls (relative to the gate), colour and dash by status
    (runner-ups dotted grey, manual merges purple). Clicking an edge emits
    ``proposal_clicked`` with its proposal."""

    proposal_clicked = QtCore.Signal(str)

    def __init__(self, state: ReviewState, parent=None) -> None:
        ink.setup()
        super().__init__(parent, background="w")
        self.state = state
        self.getPlotItem().hideAxis("left")
        self.getPlotItem().hideAxis("bottom")
        self.getPlotItem().setMenuEnabled(False)
        self.setAspectLocked(True)
        self.pos: dict[str, tuple[float, float]] = {}
        self.edges = pd.DataFrame()
        self.current = ""
        self.max_nodes = 24  # members always; the nearest others up to this many nodes
        self._items: list = []
        self.scene().sigMouseClicked.connect(self._clicked)

    def show_proposal(self, proposal: str, hops: int = 2) -> None:
        for it in self._items:
            self.removeItem(it)
        self._items = []
        self.current = proposal
        members, nearby = neighbourhood(self.state, proposal, hops)
        nodes = members + nearby[: max(0, self.max_nodes - len(members))]
        if not nodes:
            self.edges = pd.DataFrame()
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
            line = pg.PlotCurveItem(
                [xa, xb], [ya, yb], pen=pg.mkPen(color, width=width, style=style)
            )
            self.addItem(line)
            self._items.append(line)
            if r.kind not in ("manual", "runner-up") and r.cost == r.cost:
                labels.append((r.proposal == proposal, (xa + xb) / 2, (ya + yb) / 2, r, color))
        xy = np.array([self.pos[n] for n in nodes])
        brushes = [pg.mkBrush(MEMBER if n in members else "#ffffff") for n in nodes]
        dots = pg.ScatterPlotItem(
            xy[:, 0], xy[:, 1], size=14, brush=brushes, pen=pg.mkPen("#333", width=1.2)
        )
        self.addItem(dots)
        self._items.append(dots)
        self._cost_labels(labels)
        # Track labels outside the circle, each pointing away from it (below the node
        # they sat on the edges' lines and on each other).
        for n, a in zip(nodes, ang, strict=True):
            c, s = float(np.cos(a)), float(np.sin(a))
            t = pg.TextItem(n, color="#000", anchor=(0.5 - 0.5 * c, 0.5 + 0.5 * s))
            t.setPos(1.09 * c, 1.09 * s)
            self.addItem(t)
            self._items.append(t)
        self.setXRange(-1.6, 1.6, padding=0)
        self.setYRange(-1.45, 1.45, padding=0)

    def _cost_labels(self, labels: list) -> None:
        """Each proposal edge's cost on a white box at its middle; the current proposal's
        first, then the others only where they keep clear of labels already placed (on a
        dense neighbourhood the chords' middles crowd the centre). Tens of labels."""
        placed: list[tuple[float, float]] = []
        for current, x, y, r, color in sorted(labels, key=lambda item: not item[0]):
            if not current and any(abs(x - px) < 0.3 and abs(y - py) < 0.12 for px, py in placed):
                continue
            lab = pg.TextItem(
                f"{r.cost:.3g}",
                color=color,
                anchor=(0.5, 0.5),
                fill=pg.mkBrush(255, 255, 255, 225),
            )
            lab.setPos(x, y)
            lab.setZValue(5)
            self.addItem(lab)
            self._items.append(lab)
            placed.append((x, y))

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

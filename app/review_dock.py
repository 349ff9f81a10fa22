"""The review in the main window (issue 13): a Review dock (queue panel, Gantt chart,
candidate network) shown while the active layer has proposals, the Review and Edit
menus, the current proposal on the map and on a linked before/after map.

:class:`ReviewDock` binds the core :class:`~wakeline.core.review.ReviewState` of a layer
(:func:`wakeline.core.review_session.bind`, in a worker) to the widgets of
:mod:`wakeline.app.review_panel` and :mod:`wakeline.app.review_views`; one
:class:`~wakeline.app.review_undo.ReviewController` (and undo stack) per layer's queue,
kept while the window lives so switching layers keeps the undo history. Decisions are
applied and stored by :class:`wakeline.app.review_sync.ProjectDecisions`; the layer's
points follow through :class:`wakeline.app.review_sync.ReviewSync`.
"""

import contextlib
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd
import pyqtgraph as pg
import shiboken6
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import undo_order
from wakeline.app.layer_names import shown_name
from wakeline.app.map_canvas import MapCanvas
from wakeline.app.map_colors import delta_e
from wakeline.app.review_map import (
    JOIN_STYLE,
    PALETTE,
    Z_GAP,
    Piece,
    ProposalGeometry,
    ProposalItems,
    as_decided,
    join_pen,
    join_segments,
    proposal_geometry,
    proposal_members,
    tracks_geometry,
)
from wakeline.app.review_model import queue_digest
from wakeline.app.review_panel import ReviewPanel
from wakeline.app.review_sync import ProjectDecisions, ReviewSync, fuse_active, fuse_selected
from wakeline.app.review_undo import ReviewController
from wakeline.app.review_views import GanttView, NetworkView
from wakeline.app.time_panel import link_gantt
from wakeline.app.worker import Failed, Finished
from wakeline.core import geo
from wakeline.core.review import RERUN
from wakeline.core.review_session import queue_key, review_bindable, sorted_by_track
from wakeline.core.schema import time_seconds

TR_CONTEXT = "ReviewDock"
#: Opacity of the layers behind a proposal on the maps: its context, muted.
CONTEXT_OPACITY = 0.35


#: Colour difference (CIE ΔE) between a proposal's two tracks when the window picks them.
PAIR_DELTA_E = 40.0
#: The proposal is drawn again in the legend's colours this long after the map's
#: selection last changed: a layer updated after a decision clears the selection and
#: restores it a few event-loop turns later, and the proposal follows once, not twice.
REDRAW_MS = 40
#: Proposal geometries kept per queue (the current one, those looked at lately).
GEOMETRY_CACHE = 64
#: Items made per event-loop turn ahead of a new queue's first drawing.
WARM_BATCH = 8
#: Between two stages of a bind: a real timer, as the window's draw queue
#: (``window_layers.STEP_MS``); with a zero delay the next stage ran before the paint of
#: the last one, in the same event-loop block.
BIND_STEP_MS = 10
#: The Review dock's height when it comes up (px), unless the map would keep less than
#: MAP_MIN_SHARE of the window's height: at 1280x720 the dock at 360 px left the map
#: 200-214 px of 720 (review h158; 436 before the right column ran down to the status
#: bar); at 1400x900 the map keeps 379 px, as before.
REVIEW_DOCK_PX = 360
MAP_MIN_SHARE = 0.42


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


REVIEW_KEYS = (  # (action, key, panel method); the texts: review_texts()
    ("next", "J", "next"),
    ("previous", "K", "previous"),
    ("accept", "A", "accept"),
    ("reject", "R", "reject"),
    ("split", "S", "split"),
    ("split_target", "Shift+S", "split_target"),
    ("merge", "M", "merge"),
)


def join_text(status: str) -> str:
    """The legend's line of the review's joins of ``status`` (pending, accepted)."""
    if status == "accepted":
        return tr("accepted join")
    return tr("pending join (dashed)")


def review_texts() -> dict[str, str]:
    """The Review menu's texts in the current language (each a ``tr`` of a literal: the
    translations test finds them; a text kept in a table was missed, and stayed English)."""
    return {
        "next": tr("&Next proposal"),
        "previous": tr("&Previous proposal"),
        "accept": tr("&Accept"),
        "reject": tr("&Reject"),
        "split": tr("&Split track"),
        "split_target": tr("Split &target"),
        "merge": tr("&Merge selected rows"),
    }


def undo_stack_of(session, key: str, state) -> tuple[list, int]:
    """The undo stack to push again for queue ``key`` whose state ``state`` replayed the
    stored rows (:func:`~wakeline.core.review_store.undo_history`; in the bind's worker).
    Empty when the rows read now are not the ones replayed (a row appended meanwhile)."""
    from wakeline.core.review_store import undo_history

    rows = list(session.decisions)
    mine = sum(1 for r in rows if isinstance(r, dict) and r.get("queue") == key and "change" in r)
    if mine != len(state.log):
        return [], 0
    return undo_history(rows, key)


def undo_text(prefix: str, command: str) -> str:
    """Edit ▸ Undo/Redo's text: ``prefix`` (translated) and the command's own text."""
    return f"{prefix} {command}" if command else prefix


@dataclass
class Bound:
    """One layer's review: its state's controller, the points its proposals were made on
    (sorted by track, with each track's row range) and its widgets."""

    lid: str
    key: str
    controller: ReviewController
    points: pd.DataFrame
    ranges: dict[str, tuple[int, int]]
    widget: QtWidgets.QWidget
    panel: ReviewPanel
    gantt: GanttView
    network: NetworkView
    cache: dict = field(default_factory=dict)
    #: t, lon, lat of points, time-sorted within each track, lon in the band of the map
    #: (:func:`track_arrays`), and the band's west edge
    arrays: tuple | None = None
    geometries: dict = field(default_factory=dict)  # (proposal, members) -> geometry
    #: the queue of a re-run: it opens with the carried decisions, its undo stack empty
    rerun: bool = False
    #: the decision log's length when a decision was last echoed (ReviewDock._echo)
    echoed: int = -1

    @property
    def lon_west(self) -> float:
        """The band the points are drawn in (-180 or 0, as their layer is drawn)."""
        if self.arrays is None:  # before the worker's arrays: the points' band
            return geo.lon_band_west(self.points["lon"].to_numpy(dtype="float64"))
        return self.arrays[3]

    def geometry(self, proposal: str, members: list[str]) -> ProposalGeometry:
        """The map geometry of ``proposal`` (:func:`proposal_geometry`) whose target(s)
        hold ``members``: from the points' arrays, cached (it depends on nothing else)."""
        key = (proposal, tuple(members))
        geom = self.geometries.get(key)
        if geom is None:
            st = self.controller.state
            if self.arrays is None:
                pts = self.track_points(members)
                geom = proposal_geometry(st, pts, proposal, lon_west=self.lon_west)
            else:
                t, lon, lat, west = self.arrays
                empty = (0, 0)
                sl = {m: slice(*self.ranges.get(m, empty)) for m in members}
                tracks = {m: (t[k], lon[k], lat[k]) for m, k in sl.items()}
                geom = tracks_geometry(st, proposal, tracks, lon_west=west)
            if len(self.geometries) >= GEOMETRY_CACHE:
                self.geometries.clear()
            self.geometries[key] = geom
        return geom

    def track_points(self, labels: list[str]) -> pd.DataFrame:
        """The points of the tracks ``labels`` (``sensor:batch``)."""
        parts = [self.points.iloc[slice(*self.ranges[t])] for t in labels if t in self.ranges]
        return pd.concat(parts) if parts else self.points.iloc[:0]


def track_arrays(points: pd.DataFrame, ranges: dict[str, tuple[int, int]]) -> tuple:
    """Time (s), lon and lat of ``points`` (sorted by track, rows ``ranges``), each
    track's in time order (stable) as :func:`proposal_geometry` orders them (worker), and
    the band the map draws them in (:func:`wakeline.core.geo.lon_band_west`: a scene
    across 180° in [0, 360)); lon is moved into it, so the pieces lie on their layer."""
    t = time_seconds(points["time"]) if len(points) else np.zeros(0)
    code = np.zeros(len(points), dtype="int64")
    for k, (start, end) in enumerate(ranges.values()):
        code[start:end] = k
    order = np.lexsort((t, code))
    lon = points["lon"].to_numpy(dtype="float64")[order]
    lat = points["lat"].to_numpy(dtype="float64")[order]
    west = geo.lon_band_west(lon)
    if west != -180.0:
        lon = geo.into_band(lon, west)
    return np.asarray(t, dtype="float64")[order], lon, lat, west


class ReviewDock(QtCore.QObject):
    """The review part of the main window ``w`` (created once, after its actions)."""

    def __init__(self, w) -> None:
        super().__init__(w)
        self.w = w
        self.bound: Bound | None = None
        self.queues: dict[str, Bound] = {}
        self._binding: str | None = None
        self._items: dict[str, list] = {"proposal": [], "members": []}  # (canvas, item) shown
        # The items of each group on each map, made once and reused (ProposalItems).
        self._pools: dict[str, dict] = {"proposal": {}, "members": {}}
        self._lines: dict = {}  # proposal item -> its own legend line's text (main map)
        # every join of the bound review on the main map, by status (pending dashed,
        # accepted solid): one curve each, and its legend line's text
        self._joins: dict[str, pg.PlotDataItem] = {}
        self._join_lines: dict = {}  # join curve -> its legend line's text
        self._joins_key = None  # (queue, its log's length, language) the joins show
        self._geom: ProposalGeometry | None = None  # the current proposal's, as computed
        self._redraw = QtCore.QTimer(self)  # the proposal again in the legend's colours
        self._redraw.setSingleShot(True)
        self._redraw.setInterval(REDRAW_MS)
        self._redraw.timeout.connect(self._draw_proposal)
        self._views = QtCore.QTimer(self)  # Gantt, then network, on later event-loop turns
        self._views.setSingleShot(True)
        self._views.setInterval(0)
        self._views.timeout.connect(self._draw_views)
        self._said_empty: set[str] = set()  # queues with no proposal, said in the log
        self._views_todo: list[str] = []  # "gantt" and/or "network" still to draw
        self._views_proposal = ""
        self._bind_steps = None  # the stages of a bind still to run (_bind_stages)
        self._bind_timer = QtCore.QTimer(self)
        self._bind_timer.setSingleShot(True)
        self._bind_timer.setInterval(BIND_STEP_MS)
        self._bind_timer.timeout.connect(self._next_bind_step)
        self.group = QtGui.QUndoGroup(self)
        self.sync = ReviewSync(self)
        from wakeline.app.worker import JobRunner

        self.binder = JobRunner(self)
        self.binder.message.connect(self._on_bind_message)
        self.stack = QtWidgets.QStackedWidget()
        self.empty = QtWidgets.QLabel(tr("No proposals: run Associate or Fuse on a layer."))
        self.stack.addWidget(self.empty)
        self.blank = QtWidgets.QWidget()  # the dock's first turn, before a queue's widgets
        self.stack.addWidget(self.blank)
        area = QtCore.Qt.DockWidgetArea
        from wakeline.app.main_window import scrolled

        # In a scroll area: its table's filters and counts ask 801 px at least, which
        # widened a 960-px window to 1,187 px when the dock came up (h225 item 1).
        self.dock = self._dock(
            "review", tr("Review"), scrolled(self.stack), area.BottomDockWidgetArea
        )
        self.echo = QtWidgets.QLabel()  # the last review decision (_echo)
        self.echo.setMinimumWidth(1)  # a long text is cut, never widens the window
        w.statusBar().addPermanentWidget(self.echo)
        # The before map sits beside the main map in the centre (View ▸ Before/after map).
        self.before = MapCanvas(w)
        self.before.lod_executor = w.lod_worker
        self.before.setTitle(tr("before: the input pieces"), size="9pt")
        legend = self.before.legend  # no legend column: the narrow map keeps its width
        legend.updateSize = lambda: (legend.setMaximumWidth(0), legend.setVisible(False))
        self.split = QtWidgets.QSplitter()
        central = w.centralWidget()
        if central is w.canvas:
            w.takeCentralWidget()
            w.setCentralWidget(self.split)
        else:  # the map with the time slider under it: the slider stays under both maps
            lay = central.layout()
            lay.replaceWidget(w.canvas, self.split)
            lay.setStretchFactor(self.split, 1)
        self.split.addWidget(self.before)
        self.split.addWidget(w.canvas)
        self.before.hide()
        self._linking = False
        self.act_before = QtGui.QAction(tr("Before/after &map (linked)"), w, checkable=True)
        self.act_before.toggled.connect(self.show_before)
        self._before_layers: list[str] = []
        self._build_menus()
        w.layer_list.setSelectionMode(QtWidgets.QAbstractItemView.SelectionMode.ExtendedSelection)
        # The window's signals this dock listens to; close() lets go of them, so that the
        # widgets' destruction (which emits some of them) never calls into a half-gone dock.
        self._listening = [
            (w.canvas.vb.sigRangeChanged, lambda *_: self._link(w.canvas, self.before)),
            (self.before.vb.sigRangeChangedManually, lambda *_: self._link(self.before, w.canvas)),
            (w.layer_list.currentItemChanged, lambda *_: self.refresh()),
            (w.layersChanged, self.refresh),
            (w.batch_view.selectionModel().selectionChanged, self._show_members),
            (w.batch_model.modelReset, lambda: self._clear_items("members")),
            (w.canvas.selectionShown, self._redraw.start),  # its colours follow the legend
        ]
        for signal, slot in self._listening:
            signal.connect(slot)
        self.refresh()

    def show_before(self, on: bool = True) -> None:
        """Show (or hide) the before map beside the main map, on the same view."""
        self.before.setVisible(on)
        if on:
            width = self.split.width()
            self.split.setSizes([width * 2 // 5, width - width * 2 // 5])
            self._link(self.w.canvas, self.before)
            if self._geom is not None:  # the current proposal, not drawn while hidden
                self._draw_proposal()
        if self.act_before.isChecked() != on:
            self.act_before.setChecked(on)

    def _link(self, src: MapCanvas, dst: MapCanvas) -> None:
        """The same view on both maps (each keeps its aspect; the other follows)."""
        if self._linking or not dst.isVisible():
            return
        self._linking = True
        try:
            (x0, x1), (y0, y1) = src.vb.viewRange()
            dst.vb.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0)
        finally:
            self._linking = False

    def _dock(self, key: str, title: str, widget, where) -> QtWidgets.QDockWidget:
        dock = QtWidgets.QDockWidget(title, self.w)
        dock.setObjectName(key)
        dock.setWidget(widget)
        self.w.addDockWidget(where, dock)
        dock.hide()
        return dock

    # -- menus ----------------------------------------------------------------------

    def _build_menus(self) -> None:
        w = self.w
        bar = w.menuBar()
        self.edit_menu = QtWidgets.QMenu(tr("&Edit"), w)
        # Not QUndoGroup.createUndoAction: its prefix is fixed when it is made (English,
        # before the window's language is set), and every change of the stack wrote it
        # back over the translated text (operator test h150). These set the text in the
        # current language each time (_undo_note).
        self.act_undo = QtGui.QAction(w)
        self.act_undo.triggered.connect(self.undo)
        self.act_undo.setShortcut(QtGui.QKeySequence("Ctrl+Z"))
        self.act_redo = QtGui.QAction(w)
        self.act_redo.triggered.connect(self.redo)
        self.act_redo.setShortcuts(
            [QtGui.QKeySequence("Ctrl+Shift+Z"), QtGui.QKeySequence("Ctrl+Y")]
        )
        for signal in (
            self.group.activeStackChanged,
            self.group.canUndoChanged,
            self.group.undoTextChanged,
            self.group.canRedoChanged,
            self.group.redoTextChanged,
        ):
            signal.connect(self._undo_note)
        self.edit_menu.addActions([self.act_undo, self.act_redo])
        self.edit_menu.aboutToShow.connect(self._undo_note)
        bar.insertMenu(w.menus["run"].menuAction(), self.edit_menu)
        self.review_menu = QtWidgets.QMenu(tr("Revie&w"), w)
        self.review_actions: dict[str, QtGui.QAction] = {}
        texts = review_texts()
        for name, key, method in REVIEW_KEYS:
            act = QtGui.QAction(texts[name], w)
            act.setShortcut(QtGui.QKeySequence(key))
            # h181 D-review-5: the letters act where the operator reviews — the Review
            # dock (queue, Gantt, evidence) and the maps — not in the batch table, the
            # log or the Parameters (a stray A there decided the current proposal).
            act.setShortcutContext(QtCore.Qt.ShortcutContext.WidgetWithChildrenShortcut)
            act.triggered.connect(lambda _=False, m=method: self._panel_call(m))
            self.review_menu.addAction(act)
            self.review_actions[name] = act
        self.review_menu.addSeparator()
        self.review_menu.addAction(self.dock.toggleViewAction())
        bar.insertMenu(w.menus["view"].menuAction(), self.review_menu)
        for widget in (self.dock, w.canvas, self.before):
            widget.addActions(list(self.review_actions.values()))
        w.addActions([self.act_undo, self.act_redo])
        self.act_fuse = QtGui.QAction(tr("Fuse selected la&yers (two or more)"), w)
        self.act_fuse.triggered.connect(lambda: fuse_selected(w))
        w.menus["run"].insertAction(w.actions_["save_pipeline"], self.act_fuse)
        # Run ▸ Fuse with two or more layers selected fuses those layers.
        w.actions_["fuse"].triggered.disconnect()
        w.actions_["fuse"].triggered.connect(self._fuse)
        w.menus["view"].addAction(self.act_before)
        w.menus["export"].addSeparator()
        self.act_export = QtGui.QAction(w)
        self.act_export.triggered.connect(self.sync.export_dialog)
        self.act_export_log = QtGui.QAction(w)
        self.act_export_log.triggered.connect(self.sync.export_log_dialog)
        w.menus["export"].addActions([self.act_export, self.act_export_log])
        self._enable(False)
        from wakeline.app.review_join import TrackJoin

        self.join = TrackJoin(self)  # Review ▸ Join selected tracks (no proposal needed)
        self.retranslate()

    def retranslate(self) -> None:
        """The menus' texts again (the language changed while the window runs)."""
        self.edit_menu.setTitle(tr("&Edit"))
        for bound in self.queues.values():  # each command's own text (accept A0001 …)
            if shiboken6.isValid(bound.controller.stack):
                bound.controller.retranslate()
        self._undo_note()
        self.review_menu.setTitle(tr("Revie&w"))
        self.join.retranslate()
        for name, text in review_texts().items():
            self.review_actions[name].setText(text)
        self.act_fuse.setText(tr("Fuse selected la&yers (two or more)"))
        self.act_before.setText(tr("Before/after &map (linked)"))
        self.act_export.setText(tr("&Reviewed tracks (decisions honoured)…"))
        self.act_export_log.setText(tr("&Decision log…"))
        # Built before the window's first language was set: the dock's title (its tab)
        # and the texts made then follow the language too.
        self.dock.setWindowTitle(tr("Review"))
        self.empty.setText(tr("No proposals: run Associate or Fuse on a layer."))
        self.before.setTitle(tr("before: the input pieces"), size="9pt")
        for bound in self.queues.values():
            bound.gantt.retranslate()
        self._draw_joins()  # the legend's join lines in the new language

    def _fuse(self) -> None:
        if len(self.w.layer_list.selectedItems()) >= 2:
            fuse_selected(self.w)
        else:
            fuse_active(self.w)

    def _stacks(self) -> list:
        """The stacks Edit ▸ Undo / Redo choose from: the active layer's (its review
        decisions or point restores, the group's active stack) and the window's layer
        edits (colour, order, removal)."""
        stacks = [self.group.activeStack()]
        layers = getattr(self.w, "layer_undo", None)
        if layers is not None and layers._alive():
            layers._drop_stale()
            stacks.append(layers.stack)
        return stacks

    def _layer_stack(self, stack) -> bool:
        layers = getattr(self.w, "layer_undo", None)
        return layers is not None and stack is layers.stack

    def undo(self) -> None:
        """Edit ▸ Undo (Ctrl+Z): the newest edit, whichever stack holds it
        (:mod:`~wakeline.app.undo_order`; operator test 11: a colour change, then Ctrl+Z
        took out an older point restore)."""
        stack, _cmd = undo_order.pick_undo(self._stacks())
        if stack is None:
            return
        if self._layer_stack(stack):
            self.w.layer_undo.undo()
        else:
            stack.undo()
        self._undo_note()

    def redo(self) -> None:
        """Edit ▸ Redo (Ctrl+Shift+Z): the edit undone last, whichever stack holds it."""
        stack, _cmd = undo_order.pick_redo(self._stacks())
        if stack is None:
            return
        if self._layer_stack(stack):
            self.w.layer_undo.redo()
        else:
            stack.redo()
        self._undo_note()

    def _undo_note(self, *_args) -> None:
        """Edit ▸ Undo / Redo name the edit they will undo / redo (the newest of the
        active layer's stack and the layer edits'), and Undo says why it has nothing to
        undo in the queue of a re-run: a step run is not undone (no layer edit is), and
        the earlier run's undo history went with its queue; what still applied was
        carried over (the log says what)."""
        group = self.group
        if not (shiboken6.isValid(group) and shiboken6.isValid(self.act_undo)):
            return  # the window is going
        stacks = self._stacks()
        u_stack, u_cmd = undo_order.pick_undo(stacks)
        r_stack, r_cmd = undo_order.pick_redo(stacks)
        can_undo = u_cmd is not None

        def named(cmd, stack) -> str:
            if cmd is None:
                return ""
            return cmd.label() if self._layer_stack(stack) else cmd.text()

        self.act_undo.setEnabled(can_undo)
        self.act_undo.setText(undo_text(tr("&Undo"), named(u_cmd, u_stack)))
        self.act_redo.setEnabled(r_cmd is not None)
        self.act_redo.setText(undo_text(tr("&Redo"), named(r_cmd, r_stack)))
        b = self.bound
        if b is not None and b.rerun and not can_undo:
            self.act_undo.setText(tr("&Undo (nothing since the step ran again)"))
            self.act_undo.setToolTip(
                tr(
                    "Running a step again is not undone by Undo (no layer edit is): the "
                    "decisions of the earlier run that still apply, those made while it "
                    "ran included, were carried over, and the decision log keeps every one."
                )
            )
        elif b is not None and not can_undo and self._repaired_only(b):
            # h196: a reopen rebuilds the undo stack from the stored rows (undo_history);
            # a repair made on opening is a barrier it does not cross.
            self.act_undo.setText(tr("&Undo (nothing since the repair made on opening)"))
            self.act_undo.setToolTip(
                tr(
                    "Opening the project repaired decisions an older Wakeline left "
                    "inconsistent; decisions made before the repair are changed by deciding "
                    "again (Accept, Reject, Reset), and the decision log keeps every one."
                )
            )
        else:
            self.act_undo.setToolTip("")  # the action's text

    @staticmethod
    def _repaired_only(b) -> bool:
        """The queue's undo stack is empty after a repair made on opening (a barrier of
        :func:`~wakeline.core.review_store.undo_history`)."""
        log = b.controller.state.log
        return b.controller.stack.count() == 0 and any(e.action == "repair" for e in log)

    def _enable(self, on: bool) -> None:
        for act in self.review_actions.values():
            act.setEnabled(on)

    def _panel_call(self, method: str) -> None:
        b = self.bound
        if b is None:
            return
        getattr(b.panel, method)()

    def _echo(self, b) -> None:
        """A decision (by key, menu, undo or redo) said in the status bar (a label of
        its own: the points' count message follows at once) and in the Log dock (h181
        D-review-5: a stray key changed a decision without a word)."""
        from wakeline.app.review_undo import action_name

        log = b.controller.state.log
        if not log or not shiboken6.isValid(self.echo):
            return
        if len(log) == b.echoed:  # a decision that changed nothing: not logged, not said
            return
        b.echoed = len(log)
        self._draw_joins()  # the decided join solid, or gone
        entry = log[-1]
        action = entry.action
        if action.startswith("undo "):
            name = tr("undo {0}").format(action_name(action[5:]))
        elif action.startswith("redo "):
            name = tr("redo {0}").format(action_name(action[5:]))
        else:
            name = action_name(action)
        text = tr("Review: {0} {1}").format(name, entry.proposal or entry.tracks)
        self.echo.setText(text)
        from wakeline.app.review_text import decision_text

        changed = decision_text(b.controller.state, entry)  # h225 item 8: what it did
        self.w.log_message(f"{text}: {changed}" if changed else text)

    # -- binding --------------------------------------------------------------------

    def refresh(self) -> None:
        """Follow the active layer: bind its queue (in the worker) or hide the dock."""
        layer = self.w.active_layer()
        layers = self.w.session.layers
        for key in [
            k
            for k, b in self.queues.items()
            if b.lid not in layers or queue_key(layers[b.lid]) != k
        ]:
            self._drop(key)  # the layer was removed or its step run again: a new queue
        if not review_bindable(self.w.session, layer):  # an empty queue too: hand joins
            self._show(None)
            return
        key = queue_key(layer)
        if self.bound is not None and self.bound.key == key:
            return
        if key in self.queues:
            self._show(self.queues[key])
        elif self._binding != key:
            self._binding = key
            from wakeline.core.review_session import bind

            session, lid = self.w.session, layer.id

            def job(progress):
                progress(0.0, "reading the proposals")
                state, points = bind(session, session.layers[lid])
                history = undo_stack_of(session, key, state)
                pts, ranges = sorted_by_track(points)
                state.target_of_track()  # cached: the first proposal's evidence names it
                arrays = track_arrays(pts, ranges)
                return key, lid, state, pts, ranges, arrays, queue_digest(state), history

            self.binder.run("review", job)

    @property
    def busy(self) -> bool:
        """Binding or updating the layer is under way (tests wait on it), the map's paints
        held for a swap included (hold_map: the map shows the swap only when it ends)."""
        settling = self.bound is not None and self.bound.panel._settle.isActive()
        drawing = self._redraw.isActive() or bool(self._views_todo) or self._bind_steps is not None
        drawing = drawing or self.w.canvas.holding_paints
        return (
            self.binder.busy or self._binding is not None or self.sync.busy or settling or drawing
        )

    def _on_bind_message(self, msg) -> None:
        if isinstance(msg, Failed):
            self._binding = None
            self.w.log_message(f"{tr('Error')} (review): {msg.message}")
        if not isinstance(msg, Finished):
            return
        # The widgets are made and the first proposal drawn over a few event-loop turns
        # (queue; Gantt and network; the maps), none of them a long block.
        self._bind_steps = self._bind_stages(*msg.result)
        self._next_bind_step()

    def _next_bind_step(self) -> None:
        steps = self._bind_steps
        if steps is None:
            return
        try:
            next(steps)
        except StopIteration:
            self._bind_steps = None
            return
        self._bind_timer.start()

    def _bind_stages(self, key, lid, state, pts, ranges, arrays, digest, history=([], 0)):
        """Bind a queue the worker read, one stage per event-loop turn (a generator);
        a layer removed or run again meanwhile drops it."""

        def stale() -> bool:
            layers = self.w.session.layers
            if lid in layers and queue_key(layers[lid]) == key:
                return False
            self._binding = None
            self.refresh()
            return True

        if stale():
            return
        # The widgets made between turns are children of the dock's stack from the start
        # (hidden), never top-level windows held only by this generator: a parentless
        # widget dropped with it waited for the garbage collector (pyqtgraph's cycles),
        # which could delete it while Qt listed the top-level widgets (a crash seen in
        # the GUI tests' teardown). A bind dropped midway deletes what it made.
        made: list[QtWidgets.QWidget] = []

        def dropped() -> bool:
            if not stale():
                return False
            for widget in made:
                widget.deleteLater()
            return True

        controller = ReviewController(state, ProjectDecisions(self.w, key), self)
        # The undo stack the session that made the stored decisions left (h196: Undo
        # after a reopen undoes the last decision made before the close); no row is
        # written and nothing applied again (500 commands: a few ms).
        controller.restore(*history)
        panel = ReviewPanel(controller, self.stack, digest=digest)
        made.append(panel)
        for act in panel.actions:  # the window's Review and Edit menus hold the keys
            panel.removeAction(act)
        yield
        if dropped():
            return
        gantt = GanttView(state, self.stack)  # a turn each (both in one: 26-39 ms CPU on ATD)
        made.append(gantt)
        yield
        if dropped():
            return
        network = NetworkView(state, self.stack)
        made.append(network)
        yield
        if dropped():
            return
        box = QtWidgets.QSplitter()
        box.addWidget(panel)
        views = QtWidgets.QSplitter()
        views.addWidget(gantt)
        views.addWidget(network)
        box.addWidget(views)
        views.setSizes([420, 280])  # the Gantt's time axis and its title need the room
        # The queue as wide as its columns (the method column was past the edge at
        # 1600 x 950, "同步/最优…": operator test 8 D8); the views take what changes.
        box.setSizes([max(560, panel.table_width()), 700])
        box.setStretchFactor(0, 0)
        box.setStretchFactor(1, 1)
        bound = Bound(lid, key, controller, pts, ranges, box, panel, gantt, network)
        bound.arrays = arrays
        bound.rerun = any(e.action == RERUN for e in state.log)
        # Only the shown queue's panel draws (a queue still binding waits for _show).
        panel.current_settled.connect(
            lambda pid, b=bound: self.bound is b and self.show_proposal(pid)
        )
        network.proposal_clicked.connect(panel.set_current)
        if getattr(self.w, "time_panel", None) is not None:  # the slider's cursor in the Gantt
            link_gantt(self.w.time_panel, gantt)
        controller.changed.connect(lambda _p, b=bound: self.sync.schedule(b))
        bound.echoed = len(controller.state.log)  # restored decisions are not echoed
        controller.changed.connect(lambda _p, b=bound: self._echo(b))
        self.group.addStack(controller.stack)
        self.stack.addWidget(box)
        self.queues[key] = bound
        self._binding = None
        layer = self.w.session.layers[lid]
        if state.version and layer.meta.get("review_decisions") != len(state.log):
            self.sync.schedule(bound)  # decisions replayed that the stored layer lacks
        yield
        # The items the first proposal's drawing takes, made ahead a few per turn
        # (making pyqtgraph items is the slow part of a first drawing).
        pid = panel.current()
        if pid:
            n = len(proposal_members(state, pid))
            pools = [(self._pool("proposal", c), n) for c in (self.w.canvas, self.before)]
            pools += gantt.pools_for(pid) + network.pools_for(pid)
            for pool, n in pools:
                while self.queues.get(key) is bound and pool.reserve(n, WARM_BATCH):
                    yield
                yield
        if self.queues.get(key) is not bound:
            return  # dropped meanwhile (its layer removed or run again)
        active = self.w.active_layer()
        if active is not None and queue_key(active) == key:
            yield from self._show_stages(bound)

    def _drop(self, key: str) -> None:
        bound = self.queues.pop(key)
        self.sync.forget(key)
        self.group.removeStack(bound.controller.stack)
        self.stack.removeWidget(bound.widget)
        bound.widget.deleteLater()
        if self.bound is bound:
            self.bound = None
            self._geom = None
            self._clear_items()

    def _show(self, bound: Bound | None) -> None:
        for _ in self._show_stages(bound):
            pass

    def height_to_show(self) -> int:
        """The dock's height as it comes up in the bottom docks' place: REVIEW_DOCK_PX,
        or less so that the map keeps MAP_MIN_SHARE of the window's height (not less
        than the dock's least height)."""
        w = self.w
        # The bottom area now, down to the status bar (its tab bar too: resizeDocks
        # sizes the area of tabbed docks, the dock itself gets that less the tab bar).
        bottom = w.statusBar().geometry().top()
        # (A dock tabbed behind another is "visible", moved out of the window.)
        tops = [w.docks[k].geometry().top() for k in ("stats", "log") if w.docks[k].isVisible()]
        below = [bottom - top for top in tops if 0 <= top < bottom]
        room = max(below, default=0) + w.canvas.height() - round(MAP_MIN_SHARE * w.height())
        return max(self.dock.minimumSizeHint().height(), min(REVIEW_DOCK_PX, room))

    def fit_to_window(self) -> None:
        """The window made smaller: the dock gives the map back what it took below
        MAP_MIN_SHARE of the window's height (Qt takes a smaller window's height from the
        map alone), down to the dock's least height; it never grows here."""
        w = self.w
        if not self.dock.isVisible() or self.dock.isFloating():
            return
        short = round(MAP_MIN_SHARE * w.height()) - w.canvas.height()
        least = self.dock.minimumSizeHint().height()
        if short > 2 and self.dock.height() > least:
            # resizeDocks sizes the area (the dock and its tab bar): height_to_show
            area = w.statusBar().geometry().top() - self.dock.geometry().top()
            tabs = max(0, area - self.dock.height())
            height = max(least, self.dock.height() - short) + tabs
            w.resizeDocks([self.dock], [height], QtCore.Qt.Orientation.Vertical)

    def _show_stages(self, bound: Bound | None):
        """Show ``bound``'s queue (None: hide the dock), a generator: the dock, the map of
        the layers before the step, the first proposal; a binding runs one stage per
        event-loop turn, each painted before the next (showing the dock, its table and
        the first proposal in one turn, with their paints, held the GUI thread 100-120
        ms of CPU on ATD's Run ▸ Associate)."""
        if bound is self.bound and (bound is None) == self.dock.isHidden():
            return
        self.bound = bound
        self._enable(bound is not None)
        self._geom = None
        self._clear_items()
        self._draw_joins()  # the joins of this queue, or none
        if bound is None:
            self.group.setActiveStack(None)
            self.stack.setCurrentWidget(self.empty)
            self.dock.hide()
            return
        self.group.setActiveStack(bound.controller.stack)
        if self.dock.isHidden() and not len(bound.controller.state.proposals):
            # Nothing to review: the dock stays closed (it took a third of the map at
            # 1366x768 for "0 proposals", h225 item 7); bound, so Review ▸ Join and
            # the dock's own toggle (Review ▸ Review) work; the log says so, once.
            self.stack.setCurrentWidget(bound.widget)
            if bound.key not in self._said_empty:
                self._said_empty.add(bound.key)
                name = self.w.session.layers[bound.lid].name
                self.w.log_message(
                    tr(
                        "Review: 0 proposals on {0}; nothing to review (Review ▸ Review opens the queue)"
                    ).format(shown_name(name))
                )
            return
        if self.dock.isHidden():
            # The dock first, blank, in the log's place and at its height (the map
            # resized once: each size costs the map a paint and a new level of detail);
            # the queue's table and views on the next turn.
            self.stack.setCurrentWidget(self.blank)
            if self.dock not in self.w.tabifiedDockWidgets(self.w.docks["log"]):
                self.w.tabifyDockWidget(self.w.docks["log"], self.dock)  # (one layout)
            height = self.height_to_show()
            self.dock.show()
            self.w.resizeDocks([self.dock], [height], QtCore.Qt.Orientation.Vertical)
            self.dock.raise_()
            yield
            if self.bound is not bound:
                return
        self.stack.setCurrentWidget(bound.widget)
        self.dock.raise_()
        yield
        if self.bound is not bound:  # another queue shown, or the dock hidden, meanwhile
            return
        self._draw_before(self.w.session.layers[bound.lid])
        yield
        if self.bound is not bound:
            return
        pid = bound.panel.current()
        if pid:  # the map zoomed to it (and painted), then the proposal drawn
            geom = bound.geometry(pid, proposal_members(bound.controller.state, pid))
            if geom.bounds:
                self._zoom_to(geom.bounds)
                yield
                if self.bound is not bound:
                    return
        bound.panel._settle.stop()  # a new queue's first row: shown here, not again
        self.show_proposal(bound.panel.current())

    def _draw_before(self, layer) -> None:
        from wakeline.app.layer_view import draw_as

        for name in self._before_layers:
            self.before.remove_layer(name)
        self._before_layers = []
        for iid in layer.inputs or [layer.parent]:
            view = self.w.views.get(iid)
            if view is not None:
                src = self.w.session.layers[iid]
                self.before.set_draw_data(draw_as(view, iid, src.name), True)
                self._before_layers.append(iid)

    # -- drawing --------------------------------------------------------------------

    def _pool(self, group: str, canvas: MapCanvas) -> ProposalItems:
        pools = self._pools[group]
        if canvas not in pools:
            pools[canvas] = ProposalItems(canvas, z=55 if group == "members" else None)
        return pools[canvas]

    def _clear_items(self, group: str | None = None) -> None:
        for g in [group] if group else list(self._items):
            if g == "proposal":
                self._redraw.stop()
                self._sync_lines({})
            for pool in self._pools[g].values():
                pool.clear()  # hidden, kept for the next one
            self._items[g] = []
            if g == "proposal":
                for canvas in (self.w.canvas, self.before):
                    canvas.mute_layers(1.0)

    def _add_items(self, geom: ProposalGeometry, group: str) -> None:
        """Show ``geom`` in the group's items on both maps (they replace what they showed);
        the proposal on the before map only while it is shown (:meth:`show_before` draws
        it then): a hidden map's curves were set at every key for nothing."""
        shown = []
        for canvas in (self.w.canvas, self.before):
            pool = self._pool(group, canvas)
            if group == "proposal" and canvas is self.before and canvas.isHidden():
                pool.clear()
                continue
            shown += [(canvas, item) for item in pool.show(geom)]
        self._items[group] = shown

    def _sync_lines(self, wanted: dict) -> None:
        """The main map's legend lines of the proposal's own curves: ``wanted`` (item ->
        text), the others removed; a line whose curve changed colour is repainted."""
        legend = self.w.canvas.legend
        for item, text in list(self._lines.items()):
            if wanted.get(item) != text:
                legend.removeItem(item)
                del self._lines[item]
        for item, text in wanted.items():
            if item not in self._lines:
                legend.addItem(item, text)
                self._lines[item] = text
        for sample, _label in legend.items:
            if sample.item in self._lines:
                sample.update()  # its line takes the curve's new pen

    def _draw_proposal(self) -> None:
        """Draw the current proposal on both maps: its two tracks on top in the colours
        the main map's legend names them in (a selected track's selection colour; a track
        not selected, as a fused layer's pair, a free colour and a legend line of its
        own), the other members of its target muted, the layers muted behind it. Again
        (:data:`REDRAW_MS` after) whenever the main map's selection changes; the items
        are reused, and the same proposal in new colours only restyles them."""
        self._redraw.stop()
        geom = self._geom
        if geom is None:
            self._clear_items("proposal")
            return
        canvas = self.w.canvas
        free = canvas.free_colors()
        named: dict[str, str] = {}  # track -> legend text, for a line of its own
        given: dict[str, str] = {}  # track -> its colour: the pair's two must differ plainly
        pieces = []
        for piece in geom.pieces:
            if not piece.context:
                sensor, _, batch = piece.track.partition(":")
                color = canvas.selection_color(sensor, batch) or given.get(piece.track)
                if color is None:
                    # plum beside navy passed the map's test (ΔE 25) but not an eye's
                    far = [
                        c
                        for c in free
                        if all(delta_e(c, g) >= PAIR_DELTA_E for g in given.values())
                    ]
                    color = (far or free or [piece.color])[0]
                    free = [c for c in free if c != color]
                    named[piece.track] = f"{sensor} · {batch}"
                given[piece.track] = color
                piece = replace(piece, color=color)
            pieces.append(piece)
        status = self.bound.controller.state.status_of(geom.proposal) if self.bound else "pending"
        self._add_items(as_decided(replace(geom, pieces=pieces), status), "proposal")
        wanted = {}
        for c, item in self._items["proposal"]:
            name = item.opts.get("name") if isinstance(item, pg.PlotDataItem) else None
            if c is canvas and name in named:
                wanted[item] = named[name]
        self._sync_lines(wanted)
        for c in (canvas, self.before):
            c.mute_layers(CONTEXT_OPACITY)

    def _draw_joins(self) -> None:
        """Every join of the bound review across a gap on the main map: the undecided
        (pending) ones dashed, the accepted ones solid, rejected and split ones not at all
        (:func:`~wakeline.app.review_map.join_segments`), each kind with a legend line
        while it has any ("pending join (dashed)"); none while no review is bound or its
        layer is hidden. Again after every decision (:meth:`_echo`)."""
        b = self.bound
        layer = self.w.session.layers.get(b.lid) if b is not None else None
        shown = b is not None and b.arrays is not None and layer is not None and layer.visible
        # the same queue, decisions and language: nothing to do (J/K move between
        # proposals; a decision, undo or redo adds to the state's log)
        # the current proposal's join is its connector's (drawn once: two dashed lines
        # over each other looked solid, a pending join as an accepted one; h249)
        current = getattr(self, "_joins_current", None)
        key = (
            (id(b), len(b.controller.state.log), tr("pending join (dashed)"), current)
            if shown
            else None
        )
        if key is not None and key == getattr(self, "_joins_key", None):
            return
        self._joins_key = key
        segments: dict = {}
        named: set | None = None  # the kinds the legend names (None: those drawn)
        if shown:
            t, lon, lat, _west = b.arrays
            segments = join_segments(b.controller.state, t, lon, lat, b.ranges, skip=current)
            if current is not None:  # the legend names the current one's kind too
                every = join_segments(b.controller.state, t, lon, lat, b.ranges)
                named = {k for k, (x, _y) in every.items() if len(x)}
        canvas = self.w.canvas
        for status in JOIN_STYLE:
            lon, lat = segments.get(status, (np.zeros(0), np.zeros(0)))
            has = bool(len(lon)) if named is None else status in named
            item = self._joins.get(status)
            if item is None:
                if not has:
                    continue
                item = pg.PlotDataItem([], [], pen=join_pen(status, 1.2))
                item.setZValue(Z_GAP - 1)  # under the current proposal's connector
                canvas.addItem(item)
                self._joins[status] = item
            item.setData(lon, lat, connect="finite")
            item.setVisible(has)
            self._join_legend(item, join_text(status) if has else None)

    def layer_visibility_changed(self, lid: str) -> None:
        """Layer ``lid`` hidden or shown (the Layers list): the joins of the review bound
        to it leave the map with it, or come back."""
        if self.bound is not None and self.bound.lid == lid:
            self._draw_joins()

    def _join_legend(self, item, text: str | None) -> None:
        """The main map's legend line of a join curve: ``text``, or none."""
        legend = self.w.canvas.legend
        present = any(sample.item is item for sample, _label in legend.items)
        if present and (text is None or self._join_lines.get(item) != text):
            legend.removeItem(item)
            present = False
        if text is not None and not present:
            legend.addItem(item, text)
        self._join_lines[item] = text

    def show_proposal(self, proposal: str) -> None:
        """Zoom to the proposal, its tracks selected, its pieces in the legend's colours
        over the muted layers, the gap's dashed connector and predicted path (both maps);
        Gantt and network on the next event-loop turns (one each)."""
        b = self.bound
        self._geom = None
        self._views_todo = []
        self._joins_current = proposal or None
        self._draw_joins()
        if b is None or not proposal:
            self._clear_items("proposal")
            return
        st = b.controller.state
        k = st._row[proposal]
        a, c = st.track_a[k], st.track_b[k]
        geom = b.geometry(proposal, proposal_members(st, proposal))
        if geom.bounds:
            self._zoom_to(geom.bounds)
        layer = self.w.session.layers.get(b.lid)
        if layer is not None and layer.step == "fuse":
            keys = [("fused", st.target(a))]
        else:
            keys = [tuple(t.split(":", 1)) for t in (a, c)]
        self.w.select_tracks(keys)  # the map's selection and legend name the colours
        self._geom = geom
        self._draw_proposal()  # now, in the selection's colours (no redraw pending)
        self._views_proposal = proposal
        self._views_todo = ["gantt", "network"]
        self._views.start()

    def hold_map(self) -> None:
        """The main map paints once when the decision's layer is swapped in (the layer,
        its level of detail, the time index, the proposal drawn again), not at each turn
        of it: a key painted the map about 8 times (ATD dataset1), now twice (the key's
        own change, then the swap). Not for a proposal shown (a key that moves the
        view): held there, the map painted 9 times a key on ATD dataset1, up to 1.3 s
        late."""
        w = self.w
        if w.time_panel.is_playing:  # the slider's frames keep coming
            return
        w.canvas.hold_paints(
            lambda: (
                not (
                    w.drawing
                    or w.canvas.lod_busy
                    or w.lod_worker.pending
                    or w.time_controller.busy
                    or self._redraw.isActive()
                )
            )
        )

    def _zoom_to(self, bounds: tuple[float, float, float, float]) -> None:
        """The main map's view on a proposal's bounds (lon0, lat0, lon1, lat1)."""
        x0, y0, x1, y1 = bounds
        self.w.canvas.vb.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0.15)

    def _draw_views(self) -> None:
        """One of the current proposal's views (Gantt, then network) per event-loop turn."""
        b = self.bound
        if b is None or not self._views_todo:
            self._views_todo = []
            return
        view = self._views_todo.pop(0)
        (b.gantt if view == "gantt" else b.network).show_proposal(self._views_proposal)
        if self._views_todo:
            self._views.start()

    def _show_members(self, *_args) -> None:
        """A fused track selected: its member tracks drawn in their own colours on both
        maps; the status bar lists them and the sensors behind its points."""
        b, layer = self.bound, self.w.active_layer()
        if b is None or layer is None or layer.id != b.lid or "members" not in layer.points:
            self._clear_items("members")
            return
        view = self.w.views.get(layer.id)
        chosen = view.tracks(self.w.selected_keys()) if view is not None else None
        if chosen is None or not len(chosen):
            self._clear_items("members")
            return
        members = sorted({m for text in chosen["members"].astype(str) for m in text.split("+")})
        pts = b.track_points(members)
        west = b.lon_west
        self.before.show_selection(pts, lon_west=west)  # its legend names each member's colour
        geom = ProposalGeometry("")
        for k, m in enumerate(members):
            one = b.track_points([m])
            sensor, _, batch = m.partition(":")
            color = self.before.selection_color(sensor, batch) or PALETTE[k % len(PALETTE)]
            lon = one["lon"].to_numpy(dtype="float64")
            if west != -180.0:
                lon = geo.into_band(lon, west)
            geom.pieces.append(Piece(m, lon, one["lat"].to_numpy(), color))
        self._add_items(geom, "members")
        sensors = chosen["source"].astype(str).value_counts() if "source" in chosen else {}
        text = ", ".join(f"{s}: {n}" for s, n in dict(sensors).items())
        self.w.statusBar().showMessage(
            f"{tr('members')}: {' + '.join(members)}; {tr('points by sensors')}: {text}",
            15000,
        )

    def close(self) -> None:
        """Stop listening to the window and stop the workers (the window is closing)."""
        for signal, slot in self._listening:
            with contextlib.suppress(RuntimeError, TypeError):  # already gone
                signal.disconnect(slot)
        self._listening = []
        self._redraw.stop()
        self._views.stop()
        self._views_todo = []
        self._bind_timer.stop()
        self._bind_steps = None
        self.sync.stop()  # no queue's layer update started after its runner is stopped
        for runner in (self.binder, self.sync.runner):
            runner.cancel()
            runner.wait(5000)

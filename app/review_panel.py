"""The review panel (issue 13): the queue of proposals with their evidence, sortable by
margin or cost and filtered by status and sensor, and the keyboard flow as ``QAction``s
(next, previous, accept, reject, split, merge, undo, redo) for the window's menu.

A thin table model over the core's :class:`~wakeline.core.review.ReviewState`; every
decision goes through a :class:`~wakeline.app.review_undo.ReviewController`.
"""

import numpy as np
import shiboken6
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import review_text as T
from wakeline.app.review_model import (
    COLUMNS,
    SORT_ROLE,
    ProposalFilter,
    ProposalModel,
    QueueDigest,
    queue_digest,
)
from wakeline.app.review_undo import ReviewController

#: Columns the queue hides until the operator shows them (the header's right-click
#: menu): the evidence line under the queue says both for the current proposal. Without
#: them the three new columns (target, Δcourse, Δspeed) cost the queue 108 px more than
#: before on MTAD Scene-3 (1,195 px, 1,087 before; 1,364 with them); the method column
#: stays (operator test 8 D8 wanted it whole at 1600 x 950).
HIDDEN_BY_DEFAULT: tuple[str, ...] = ("distance_m", "runner_up")

__all__ = ["COLUMNS", "SORT_ROLE", "ProposalFilter", "ProposalModel", "ReviewPanel"]


class ReviewPanel(QtWidgets.QWidget):
    """Queue, filters, evidence of the current proposal and the review actions.

    ``current_changed(proposal)`` is emitted when the current proposal changes;
    ``current_settled(proposal)`` when it has stayed for :attr:`settle_ms` (the map, Gantt
    and network follow that one, so holding a key down never waits for redraws).
    :attr:`actions` lists the ``QAction``s for the menu. ``digest`` (made in the worker
    by :func:`~wakeline.app.review_model.queue_digest`, else here) gives the widest cell
    texts the columns are sized from and the sensors of the filter.
    """

    current_changed = QtCore.Signal(str)
    current_settled = QtCore.Signal(str)  # the same, once the keys rest (for heavy views)

    #: Widest a column is sized to (px); a longer text is elided in the middle.
    MAX_COLUMN_PX = 360

    def __init__(
        self, controller: ReviewController, parent=None, digest: QueueDigest | None = None
    ) -> None:
        super().__init__(parent)
        self.digest = digest if digest is not None else queue_digest(controller.state)
        self.controller = controller
        self.advance = True  # move to the next proposal after accept / reject
        self.settle_ms = 80
        self._settle = QtCore.QTimer(self)
        self._settle.setSingleShot(True)
        self._settle.timeout.connect(lambda: self.current_settled.emit(self.current()))
        self.model = ProposalModel(controller, self)
        self.proxy = TitledFilter(self)
        self.proxy.kind = queue_kind(controller.state)
        self.proxy.setSourceModel(self.model)
        self.view = QtWidgets.QTableView()
        self.view.setModel(self.proxy)
        self.view.setSortingEnabled(True)
        self.view.setSelectionBehavior(QtWidgets.QAbstractItemView.SelectionBehavior.SelectRows)
        self.view.verticalHeader().setVisible(False)
        self.view.verticalHeader().setDefaultSectionSize(20)
        self.view.horizontalHeader().setStretchLastSection(True)
        # "milliAmpere:…" hid the batch number: a long track label keeps both ends.
        self.view.setTextElideMode(QtCore.Qt.TextElideMode.ElideMiddle)
        # Sized from the digest's few widest texts by font metrics: resizeColumnsToContents
        # asked the model for every role of 200 rows x 10 columns on the GUI thread.
        self.fit_columns()
        self._arrange_columns()
        self.view.selectionModel().currentRowChanged.connect(self._row_changed)

        self.status_box = QtWidgets.QComboBox()
        self.status_box.addItems(T.status_filter_items())
        self.sensor_box = QtWidgets.QComboBox()
        self.sensor_box.addItems([T.all_sensors(), *self.digest.sensors])
        self.sort_box = QtWidgets.QComboBox()
        self.sort_box.addItems(T.sort_items())
        for box in (self.status_box, self.sensor_box):
            box.currentIndexChanged.connect(self._filter_changed)
        self.sort_box.currentIndexChanged.connect(self._sort_changed)
        self.evidence = QtWidgets.QLabel()
        self.evidence.setWordWrap(True)
        self.evidence.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        self.counts = QtWidgets.QLabel()

        top = QtWidgets.QHBoxLayout()
        for w in (self.status_box, self.sensor_box, self.sort_box):
            top.addWidget(w)
        top.addStretch(1)
        top.addWidget(self.counts)
        # h225 item 8: what pending / accept / reject mean, over the queue.
        # One line (cut at the right on a narrow dock: the whole text is its tooltip), so
        # the queue keeps its rows at 1280x720.
        self.hint = QtWidgets.QLabel()
        self.hint.setObjectName("review_hint")
        self.hint.setSizePolicy(
            QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Fixed
        )
        self._set_hint()
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(2, 2, 2, 2)
        lay.addLayout(top)
        lay.addWidget(self.hint)
        lay.addWidget(self.view, 1)
        lay.addWidget(self.evidence)

        self.actions = self._make_actions()
        self.addActions(self.actions)
        controller.changed.connect(self._after_change)
        self._sort_changed()
        self._update_counts()
        if self.proxy.rowCount():
            self.view.selectRow(0)
            self.view.setCurrentIndex(self.proxy.index(0, 0))

    def fit_columns(self) -> None:
        """Column widths (px) from font metrics of the digest's widest texts and the titles
        (a handful of strings a column, whatever the queue's length)."""
        style = self.view.style()
        cell_fm, head = self.view.fontMetrics(), self.view.horizontalHeader()
        head_fm = head.fontMetrics()
        pad = 2 * (style.pixelMetric(QtWidgets.QStyle.PixelMetric.PM_FocusFrameHMargin) + 1) + 6
        head_pad = 3 * style.pixelMetric(
            QtWidgets.QStyle.PixelMetric.PM_HeaderMargin
        ) + style.pixelMetric(QtWidgets.QStyle.PixelMetric.PM_HeaderMarkSize)
        titles = T.column_titles(self.proxy.kind)
        statuses = list(T.status_names().values())
        for col, (name, _) in enumerate(COLUMNS):
            texts = statuses if name == "status" else self.digest.widest.get(name, [])
            if name == "method":  # as shown: in the window's language ("同步/最优分配")
                texts = [T.method_text(t) for t in texts]
            cell = max((cell_fm.horizontalAdvance(t) for t in texts), default=0) + pad
            title = head_fm.horizontalAdvance(titles[name]) + head_pad
            head.resizeSection(col, min(max(cell, title), self.MAX_COLUMN_PX))

    #: Columns hidden until the operator shows them (the header's right-click menu): the
    #: queue keeps its other columns readable in a 1280-px window. Shared by the queues
    #: of one window's life (a new queue keeps the operator's choice).
    hidden_columns: set[str] = set(HIDDEN_BY_DEFAULT)
    #: The target column sits after the status (SPEC §7 lists it first), its logical
    #: place the last (the columns' numbers before it stay).
    TARGET_AFTER = "status"

    def _arrange_columns(self) -> None:
        """The target column moved beside the status, the hidden columns hidden, and the
        header's right-click menu to show or hide each."""
        names = [n for n, _ in COLUMNS]
        head = self.view.horizontalHeader()
        target = names.index("target")
        head.moveSection(
            head.visualIndex(target), head.visualIndex(names.index(self.TARGET_AFTER)) + 1
        )
        for col, name in enumerate(names):
            self.view.setColumnHidden(col, name in ReviewPanel.hidden_columns)
        head.setContextMenuPolicy(QtCore.Qt.ContextMenuPolicy.CustomContextMenu)
        head.customContextMenuRequested.connect(self._header_menu)

    def column_menu(self) -> QtWidgets.QMenu:
        """The header's right-click menu: one checkable entry per column (in the order
        shown), on when the column shows; the proposal column always shows."""
        menu = QtWidgets.QMenu(self.view)
        head = self.view.horizontalHeader()
        titles = T.column_titles(self.proxy.kind)
        for visual in range(head.count()):
            col = head.logicalIndex(visual)
            name = COLUMNS[col][0]
            act = menu.addAction(titles[name])
            act.setCheckable(True)
            act.setChecked(not self.view.isColumnHidden(col))
            act.setEnabled(name != "proposal")
            act.toggled.connect(lambda on, n=name: self.show_column(n, on))
        return menu

    def show_column(self, name: str, on: bool = True) -> None:
        """Show (or hide) column ``name``; the choice holds for the next queues too."""
        col = [n for n, _ in COLUMNS].index(name)
        self.view.setColumnHidden(col, not on)
        if on:
            ReviewPanel.hidden_columns.discard(name)
        else:
            ReviewPanel.hidden_columns.add(name)

    def _header_menu(self, pos) -> None:
        menu = self.column_menu()
        menu.popup(self.view.horizontalHeader().viewport().mapToGlobal(pos))

    def table_width(self) -> int:
        """Width (px) the queue needs to show every column: their sum, the frame, the
        vertical scroll bar and the panel's margins."""
        view = self.view
        columns = sum(
            view.columnWidth(c)
            for c in range(self.proxy.columnCount())
            if not view.isColumnHidden(c)
        )
        bar = view.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent)
        return columns + bar + 2 * view.frameWidth() + 8

    # -- actions ------------------------------------------------------------------------

    def _make_actions(self) -> list[QtGui.QAction]:
        def act(text: str, key: str, slot, tip: str) -> QtGui.QAction:
            a = QtGui.QAction(text, self)
            a.setShortcut(QtGui.QKeySequence(key))
            a.setShortcutContext(QtCore.Qt.ShortcutContext.WidgetWithChildrenShortcut)
            a.setToolTip(tip)
            a.triggered.connect(slot)
            return a

        texts = self._action_texts()
        keys = ("J", "K", "A", "R", "S", "Shift+S", "M")
        slots = (
            self.next,
            self.previous,
            self.accept,
            self.reject,
            self.split,
            self.split_target,
            self.merge,
        )
        (
            self.act_next,
            self.act_prev,
            self.act_accept,
            self.act_reject,
            self.act_split,
            self.act_split_target,
            self.act_merge,
        ) = (act(t, k, f, tip) for (t, tip), k, f in zip(texts, keys, slots, strict=True))
        # Not QUndoStack.createUndoAction: its prefix stays in the language it was made
        # in after a switch (each change of the stack writes it back); _undo_texts.
        stack = self.controller.stack
        self.act_undo = QtGui.QAction(self)
        self.act_undo.triggered.connect(stack.undo)
        self.act_undo.setShortcut(QtGui.QKeySequence.StandardKey.Undo)
        self.act_redo = QtGui.QAction(self)
        self.act_redo.triggered.connect(stack.redo)
        self.act_redo.setShortcut(QtGui.QKeySequence.StandardKey.Redo)
        for signal in (
            stack.canUndoChanged,
            stack.undoTextChanged,
            stack.canRedoChanged,
            stack.redoTextChanged,
        ):
            signal.connect(self._undo_texts)
        self._undo_texts()
        for a in (self.act_undo, self.act_redo):
            a.setShortcutContext(QtCore.Qt.ShortcutContext.WidgetWithChildrenShortcut)
        return [
            self.act_next,
            self.act_prev,
            self.act_accept,
            self.act_reject,
            self.act_split,
            self.act_split_target,
            self.act_merge,
            self.act_undo,
            self.act_redo,
        ]

    def _undo_texts(self, *_args) -> None:
        """Undo/Redo: enabled as the stack says, the text in the current language."""
        stack = self.controller.stack
        if not (shiboken6.isValid(stack) and shiboken6.isValid(self.act_undo)):
            return  # the stack going with its queue says it is empty: nothing to show
        for action, prefix, can, text in (
            (self.act_undo, self.tr("Undo"), stack.canUndo(), stack.undoText()),
            (self.act_redo, self.tr("Redo"), stack.canRedo(), stack.redoText()),
        ):
            action.setEnabled(can)
            action.setText(f"{prefix} {text}" if text else prefix)

    def _action_texts(self) -> list[tuple[str, str]]:
        """(text, tooltip) of next, previous, accept, reject, split, split target, merge."""
        tr = self.tr
        return [
            (tr("Next proposal"), tr("next proposal in the queue")),
            (tr("Previous proposal"), tr("previous proposal")),
            (tr("Accept"), tr("accept: the two tracks are one ship")),
            (tr("Reject"), tr("reject: not one ship; never proposed again")),
            (tr("Split track"), tr("track B leaves its target")),
            (tr("Split target"), tr("the target falls back into its tracks")),
            (tr("Merge"), tr("merge the tracks of the selected rows")),
        ]

    def current(self) -> str:
        """The current proposal id ("" when the queue is empty)."""
        idx = self.view.currentIndex()
        if not idx.isValid():
            return ""
        return self.model.ids[self.proxy.mapToSource(idx).row()]

    def current_at(self, row: int) -> str:
        """The proposal id shown at ``row`` of the queue (as filtered and sorted)."""
        return self.model.ids[self.proxy.mapToSource(self.proxy.index(row, 0)).row()]

    def set_current(self, proposal: str) -> bool:
        """Make ``proposal`` current (clearing filters that hide it)."""
        row = self.model.row_of.get(proposal)
        if row is None:
            return False
        pidx = self.proxy.mapFromSource(self.model.index(row, 0))
        if not pidx.isValid():
            self.status_box.setCurrentIndex(0)
            self.sensor_box.setCurrentIndex(0)
            pidx = self.proxy.mapFromSource(self.model.index(row, 0))
        self.view.setCurrentIndex(pidx)
        self.view.selectRow(pidx.row())
        self.view.scrollTo(pidx)
        return True

    def _step(self, d: int) -> None:
        n = self.proxy.rowCount()
        if n == 0:
            return
        r = self.view.currentIndex().row()
        r = min(max(r + d, 0), n - 1) if r >= 0 else 0
        self.view.setCurrentIndex(self.proxy.index(r, 0))
        self.view.selectRow(r)

    def next(self) -> None:
        self._step(1)

    def previous(self) -> None:
        self._step(-1)

    def _decide(self, fn) -> None:
        pid = self.current()
        if not pid:
            return
        row = self.view.currentIndex().row()
        fn(pid)
        if self.advance:
            # The filter may have hidden the decided row: stay at the same position.
            n = self.proxy.rowCount()
            if n:
                r = min(row + (1 if self._row_of_current_is(pid) else 0), n - 1)
                self.view.setCurrentIndex(self.proxy.index(r, 0))
                self.view.selectRow(r)

    def _row_of_current_is(self, pid: str) -> bool:
        return self.current() == pid

    def accept(self) -> None:
        self._decide(self.controller.accept)

    def reject(self) -> None:
        self._decide(self.controller.reject)

    def split(self) -> None:
        pid = self.current()
        if pid:
            self.controller.split_track(self._tracks(pid)[1])

    def split_target(self) -> None:
        pid = self.current()
        if pid:
            st = self.controller.state
            self.controller.split_target(st.target(self._tracks(pid)[0]))

    def merge(self) -> None:
        """Merge the tracks of every selected row (two tracks of one row, or more)."""
        rows = sorted(
            {self.proxy.mapToSource(i).row() for i in self.view.selectionModel().selectedRows()}
        )
        tracks = []
        for r in rows:
            tracks += self._tracks(self.model.ids[r])
        tracks = list(dict.fromkeys(tracks))
        if len(tracks) >= 2:
            self.controller.merge(tracks)

    def _tracks(self, pid: str) -> tuple[str, str]:
        r = self.model.row_of[pid]
        return str(self.model.cols["track_a"][r]), str(self.model.cols["track_b"][r])

    # -- view state ---------------------------------------------------------------------

    def _filter_changed(self) -> None:
        status = T.STATUS_FILTERS[max(self.status_box.currentIndex(), 0)]
        sensor = self.sensor_box.currentText() if self.sensor_box.currentIndex() > 0 else ""
        self.proxy.set_filter(status, sensor)
        if self.proxy.rowCount() and not self.view.currentIndex().isValid():
            self._step(0)

    def _sort_changed(self) -> None:
        names = [n for n, _ in COLUMNS]
        k = self.sort_box.currentIndex()
        col, order = (
            (names.index("margin"), QtCore.Qt.SortOrder.AscendingOrder)
            if k == 0
            else (names.index("cost"), QtCore.Qt.SortOrder.DescendingOrder)
            if k == 1
            else (names.index("proposal"), QtCore.Qt.SortOrder.AscendingOrder)
        )
        self.view.sortByColumn(col, order)
        if self.proxy.rowCount():  # a new order starts at the top of the queue
            self.view.setCurrentIndex(self.proxy.index(0, 0))
            self.view.selectRow(0)

    def _row_changed(self, current, _previous) -> None:
        pid = self.current()
        self._show_evidence(pid)
        self.current_changed.emit(pid)
        self._settle.start(self.settle_ms)

    def _after_change(self, _proposals: list) -> None:
        self._update_counts()
        self._show_evidence(self.current())
        self._settle.start(self.settle_ms)

    def _update_counts(self) -> None:
        st = self.controller.state.status
        vals, n = np.unique(st.astype(str), return_counts=True) if len(st) else ([], [])
        c = dict(zip(vals, n, strict=True))
        from wakeline.app.review_join import hand_joins_text

        text = T.counts_text(len(st), c) + hand_joins_text(self.controller.state)
        self.counts.setText(text)

    def _show_evidence(self, pid: str) -> None:
        if not pid:
            self.evidence.setText("")
            return
        st = self.controller.state
        row = int(self.model.prop[self.model.row_of[pid]])
        self.evidence.setText(T.evidence_text(st, pid, st.proposals.iloc[row]))

    #: The hint line shows while the queue keeps at least this many rows beside it.
    HINT_MIN_ROWS = 4

    def resizeEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().resizeEvent(event)
        self._fit_hint()  # the layout has placed the view at the new size already

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().showEvent(event)
        self._fit_hint()

    def _fit_hint(self) -> None:
        """Show the hint line only when the queue keeps :attr:`HINT_MIN_ROWS` rows with
        it (a low dock at 1280x720 gives its rows to the queue; the hint stays the
        header's and the panel's tooltip)."""
        if not (shiboken6.isValid(self) and shiboken6.isValid(self.hint)):
            return
        spacing = max(self.layout().spacing(), 0)
        line = self.hint.sizeHint().height() + spacing
        shown = not self.hint.isHidden()  # not isVisible(): False before the dock shows
        # From the view's own height (set by the layout at once, shown or not), not its
        # viewport's (resized only when a hidden dock shows).
        view = self.view
        chrome = view.horizontalHeader().sizeHint().height() + 2 * view.frameWidth()
        viewport = view.height() - chrome + (line if shown else 0)
        rows = (viewport - line) / max(self.view.verticalHeader().defaultSectionSize(), 1)
        show = rows >= self.HINT_MIN_ROWS
        if show != shown:
            self.hint.setVisible(show)
            self.layout().activate()  # the rows given back now, not a turn later

    def _set_hint(self) -> None:
        self.hint.setText(T.queue_hint())
        self.hint.setToolTip(T.queue_hint())

    def changeEvent(self, event) -> None:  # noqa: N802 - Qt API
        if event.type() == QtCore.QEvent.Type.LanguageChange:
            self.retranslate()
        super().changeEvent(event)

    def retranslate(self) -> None:
        """Texts again in the current language (filters, actions, counts, evidence)."""
        for box, items in (
            (self.status_box, T.status_filter_items()),
            (self.sensor_box, [T.all_sensors()]),
            (self.sort_box, T.sort_items()),
        ):
            for k, text in enumerate(items):
                box.setItemText(k, text)
        for action, (text, tip) in zip(self.actions, self._action_texts(), strict=False):
            action.setText(text)
            action.setToolTip(tip)
        if shiboken6.isValid(self.controller.stack):
            self.controller.retranslate()  # the commands' own texts (accept A0001 …)
        self._undo_texts()
        self._set_hint()
        self.model.headerDataChanged.emit(QtCore.Qt.Orientation.Horizontal, 0, len(COLUMNS) - 1)
        self.fit_columns()
        self._after_change([])


def queue_kind(state) -> str:
    """The kind of every proposal of ``state`` ("fuse", "associate"), "" when mixed."""
    kinds = set(state.proposals["kind"].astype(str).tolist()) if len(state.proposals) else set()
    return kinds.pop() if len(kinds) == 1 else ""


class TitledFilter(ProposalFilter):
    """The queue's filter, its column titles with their unit (metres for a fusion's
    costs, scaled for an association's) and a tooltip saying what each means."""

    kind = ""

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if orientation == QtCore.Qt.Orientation.Horizontal and 0 <= section < len(COLUMNS):
            name = COLUMNS[section][0]
            if role == QtCore.Qt.ItemDataRole.DisplayRole:
                return T.column_titles(self.kind)[name]
            if role == QtCore.Qt.ItemDataRole.ToolTipRole:
                return T.column_tips().get(name)
        return super().headerData(section, orientation, role)

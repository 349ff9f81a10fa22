"""Review ▸ Join selected tracks and Review ▸ Split selected tracks' target: the
operator joins two tracks (or more) selected in the batch table into one target where no
proposal links them (an MMSI typed wrong: operator test 5, D-review-7), and cuts such a
target back into its tracks.

Both are decisions of the layer's review like the queue's keys: made through its
:class:`~wakeline.app.review_undo.ReviewController` (Ctrl+Z undoes them), stored in the
project at once, replayed by ``wakeline review --decisions`` from the exported decision
log. The join is :func:`~wakeline.core.review_join.join_tracks`: tracks of one sensor
that overlap in time are joined only when the operator says so in the question asked.
"""

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.core_text import shown
from wakeline.core import review as R
from wakeline.core.errors import InputError
from wakeline.core.review_join import join_tracks, overlap_problem
from wakeline.core.review_session import queue_key, reviewable

TR_CONTEXT = "ReviewJoin"


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


def join_texts() -> dict[str, str]:
    """The actions' texts in the current language."""
    return {
        "join": tr("&Join selected tracks"),
        "split_join": tr("Split selected tracks' tar&get"),
    }


def hand_joins_text(state: R.ReviewState) -> str:
    """The queue's note of the manual links (joins by hand: Join selected tracks, the
    queue's merge): "" when there is none, else "; 1 joined by hand: A + B" (the first
    three pairs named), appended to the queue's counts."""
    links = sorted(state.links)
    if not links:
        return ""
    named = ", ".join(f"{a} + {b}" for a, b in links[:3]) + ("…" if len(links) > 3 else "")
    return tr("; {0} joined by hand: {1}").format(len(links), named)


#: Shortcuts (window-wide; the Review keys are single letters, these are not).
JOIN_KEYS = {"join": "Ctrl+J", "split_join": "Ctrl+Shift+J"}


class TrackJoin(QtCore.QObject):
    """The two actions, in the Review menu and the batch table's context menu."""

    def __init__(self, dock) -> None:
        super().__init__(dock)
        self.dock, self.w = dock, dock.w
        self.actions: dict[str, QtGui.QAction] = {}
        texts = join_texts()
        for name, slot in (("join", self.join_selected), ("split_join", self.split_selected)):
            act = QtGui.QAction(texts[name], self.w)
            act.setShortcut(QtGui.QKeySequence(JOIN_KEYS[name]))
            act.triggered.connect(lambda _=False, s=slot: s())
            self.actions[name] = act
        menu = dock.review_menu
        first = menu.actions()[0] if menu.actions() else None
        sep = menu.insertSeparator(first) if first is not None else None
        for act in self.actions.values():
            menu.insertAction(sep, act)
        self.w.addActions(list(self.actions.values()))
        view = self.w.batch_view
        view.setContextMenuPolicy(QtCore.Qt.ContextMenuPolicy.CustomContextMenu)
        view.customContextMenuRequested.connect(self._context_menu)

    def retranslate(self) -> None:
        for name, text in join_texts().items():
            self.actions[name].setText(text)

    def _context_menu(self, pos) -> None:
        menu = QtWidgets.QMenu(self.w.batch_view)
        menu.addActions(list(self.actions.values()))
        menu.popup(self.w.batch_view.viewport().mapToGlobal(pos))

    # -- the decisions ----------------------------------------------------------------

    def _bound(self):
        """The review of the active layer, bound; else None after saying why."""
        layer = self.w.active_layer()
        if layer is None or not reviewable(layer):
            self.w.log_message(
                tr(
                    "Join: tracks are joined in an associated layer (Run ▸ Associate "
                    "first, then select its tracks)"
                )
            )
            return None
        b = self.dock.bound
        if b is None or b.lid != layer.id or b.key != queue_key(layer):
            self.dock.refresh()
            self.w.log_message(tr("Join: the layer's review is still being read; try again"))
            return None
        return b

    def _labels(self) -> list[str]:
        return [R.track_label(s, b) for s, b in self.w.selected_keys()]

    def _fused_members(self, b) -> list[list[str]] | None:
        """On a fused layer, the member tracks of each selected fused target (its
        ``members`` column, ``radar:1+AIS:1``), in table order: the table lists fused
        targets (sensor ``fused``), the review decides on their member tracks (operator
        test 8, D2: Ctrl+J said "no track 'fused:radar:0'"). None on another layer."""
        layer = self.w.active_layer()
        if layer is None or layer.step != "fuse" or "members" not in layer.points:
            return None
        keys = self.w.selected_keys()
        view = self.w.views.get(layer.id)
        if view is None or not keys:
            return []
        chosen = view.tracks(keys)
        first = (
            chosen.astype({"sensor": str, "batch": str, "members": str})
            .groupby(["sensor", "batch"], sort=False)["members"]
            .first()
        )
        known = b.controller.state._track_no
        out = []
        for key in keys:
            text = first.get(tuple(key))
            if text is None:
                continue
            members = [m for m in str(text).split("+") if m in known]
            if not members and key[1] in known:
                members = [key[1]]  # the target is named after its earliest track
            if members:
                out.append(members)
        return out

    def _unknown(self, state, labels: list[str], what: str) -> bool:
        """Whether a label is no track of the review (said in the log, translated)."""
        missing = [x for x in labels if x not in state._track_no]
        if missing:
            self.w.log_message(
                tr("{0}: {1} is not a track of this layer's review").format(what, missing[0])
            )
        return bool(missing)

    def join_selected(self) -> bool:
        """Join the tracks selected in the batch table (two or more) into one target; on
        a fused layer, the selected fused targets (their member tracks)."""
        if len(self.w.selected_keys()) < 2:
            self.w.log_message(tr("Join: select two tracks (or more) in the table"))
            return False
        b = self._bound()
        if b is None:
            return False
        state = b.controller.state
        fused = self._fused_members(b)
        if fused is None:
            labels = self._labels()
            if self._unknown(state, labels, tr("Join")):
                return False
        else:
            # one track per target: the join joins targets (review.merge)
            labels = list(dict.fromkeys(m[0] for m in fused))
            if len({state.target(x) for x in labels}) < 2:
                self.w.log_message(tr("Join: the tracks are one target already"))
                return False
        try:
            problem = overlap_problem(state, labels)
            if problem and not self.ask_overlap(problem):
                return False
            change = join_tracks(state, labels, overlap_ok=True)
        except InputError as exc:
            self.w.log_message(f"{tr('Join')}: {shown(exc)}")
            return False
        if change.empty:
            self.w.log_message(tr("Join: the tracks are one target already"))
            return False
        b.controller.do(change)
        self.w.log_message(tr("Joined {0} by hand (Ctrl+Z undoes)").format(", ".join(labels)))
        return True

    def ask_overlap(self, problem: str) -> bool:
        """Whether the operator joins tracks of one sensor that overlap in time."""
        buttons = QtWidgets.QMessageBox.StandardButton
        answer = QtWidgets.QMessageBox.question(
            self.w,
            tr("Join overlapping tracks?"),
            tr("{0}. Join them anyway?").format(shown(problem)),
            buttons.Yes | buttons.No,
            buttons.No,
        )
        return answer == buttons.Yes

    def split_selected(self) -> bool:
        """Cut the target of the first selected track back into its tracks; on a fused
        layer, the first selected fused target into its member tracks."""
        if not self.w.selected_keys():
            self.w.log_message(tr("Split: select a track of the target in the table"))
            return False
        b = self._bound()
        if b is None:
            return False
        state = b.controller.state
        fused = self._fused_members(b)
        labels = self._labels() if fused is None else [m[0] for m in fused]
        if not labels:
            self.w.log_message(tr("Split: select a track of the target in the table"))
            return False
        if self._unknown(state, labels[:1], tr("Split")):
            return False
        try:
            change = R.split_target(state, state.target(labels[0]))
        except InputError as exc:
            self.w.log_message(f"{tr('Split')}: {shown(exc)}")
            return False
        if change.empty:
            self.w.log_message(tr("Split: the track is a target of its own"))
            return False
        b.controller.do(change)
        return True

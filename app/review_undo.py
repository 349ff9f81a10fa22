"""Undo and redo of review decisions: a thin ``QUndoCommand`` over the core's pure
:class:`~wakeline.core.review.Change`, and a controller that owns the ``QUndoStack``, the
:class:`~wakeline.core.review.ReviewState` and (optionally) the project's decision store.

Every do, undo and redo is applied to the state and written to the store at once (undo
is stored as the inverse change it is), so a reopened project replays to the same state.
"""

from PySide6 import QtCore, QtGui

from wakeline.app import undo_order
from wakeline.core import review as R
from wakeline.core.review_store import ReviewStore


def action_name(action: str) -> str:
    """A decision's name in the current language (the Undo / Redo menu texts)."""
    names = {
        "accept": QtCore.QCoreApplication.translate("ReviewCommand", "accept"),
        "reject": QtCore.QCoreApplication.translate("ReviewCommand", "reject"),
        "reset": QtCore.QCoreApplication.translate("ReviewCommand", "reset"),
        "merge": QtCore.QCoreApplication.translate("ReviewCommand", "merge"),
        "split track": QtCore.QCoreApplication.translate("ReviewCommand", "split track"),
        "split target": QtCore.QCoreApplication.translate("ReviewCommand", "split target"),
        "repair": QtCore.QCoreApplication.translate("ReviewCommand", "repair"),
    }
    return names.get(action, action)


class ReviewCommand(QtGui.QUndoCommand):
    """One decision on the undo stack."""

    def __init__(self, controller: "ReviewController", change: R.Change) -> None:
        self.controller = controller
        self.change = change
        self.done = False  # redo() ran once: the next is a Redo, not the decision
        super().__init__(self.title())
        undo_order.stamp(self)  # Edit ▸ Undo's one order with the layer edits

    def title(self) -> str:
        """The command's text in the current language (Edit ▸ Undo/Redo show it)."""
        change = self.change
        tracks = ", ".join(change.tracks[:3]) + ("…" if len(change.tracks) > 3 else "")
        return (
            QtCore.QCoreApplication.translate("ReviewCommand", "{0} {1}")
            .format(action_name(change.action), change.proposal or tracks)
            .strip()
        )

    def redo(self) -> None:
        how = "redo" if self.done else "do"
        self.done = True
        self.controller._apply(self.change, how)

    def undo(self) -> None:
        undo_order.undone(self)
        self.controller._apply(self.change.inverse(), "undo")


class ReviewController(QtCore.QObject):
    """The review session of the GUI: state + undo stack (+ store).

    ``changed`` is emitted after every applied change with the proposals it touched.
    """

    changed = QtCore.Signal(list)

    def __init__(self, state: R.ReviewState, store: ReviewStore | None = None, parent=None) -> None:
        super().__init__(parent)
        self.state = state
        self.store = store
        self.stack = QtGui.QUndoStack(self)
        self._restoring = False  # restore(): the commands move, nothing is applied

    def _apply(self, change: R.Change, how: str = "do") -> None:
        if self._restoring:
            return
        if self.store is not None:  # how: the row says how it came (a reopen reads it)
            self.store.apply(self.state, change, how)
        else:
            self.state.apply(change, how=how)
        self.changed.emit(sorted(change.status_after))

    def restore(self, changes: list[R.Change], index: int) -> None:
        """Push again the undo stack a reopened project's decisions left
        (:func:`~wakeline.core.review_store.undo_history`): the commands and the index
        where the session that made them left it, so Undo and Redo go on as there. The
        state has them applied already (replayed from the rows): nothing is applied,
        written to the project or emitted per command."""
        self._restoring = True
        try:
            for change in changes:
                cmd = ReviewCommand(self, change)
                self.stack.push(cmd)  # its redo() does nothing now
                cmd.done = True  # the next redo() is a Redo
            self.stack.setIndex(index)  # the undone ones' undo() does nothing either
        finally:
            self._restoring = False

    def retranslate(self) -> None:
        """Every command's text again in the current language (after a switch)."""
        for k in range(self.stack.count()):
            cmd = self.stack.command(k)
            if isinstance(cmd, ReviewCommand):
                cmd.setText(cmd.title())

    def do(self, change: R.Change) -> None:
        """Apply a decision through the undo stack; one that changes nothing is not
        pushed (no do-nothing step to undo, nothing written to the decision log)."""
        if change.empty:
            self.changed.emit(sorted(change.status_after))  # the views show it as it is
            return
        self.stack.push(ReviewCommand(self, change))

    def accept(self, proposal: str) -> None:
        self.do(R.accept(self.state, proposal))

    def reject(self, proposal: str) -> None:
        self.do(R.reject(self.state, proposal))

    def reset(self, proposal: str) -> None:
        self.do(R.reset(self.state, proposal))

    def merge(self, tracks: list[str]) -> None:
        self.do(R.merge(self.state, tracks))

    def split_track(self, track: str) -> None:
        self.do(R.split_track(self.state, track))

    def split_target(self, target: str) -> None:
        self.do(R.split_target(self.state, target))

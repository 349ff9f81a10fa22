"""Undo of Layer ▸ Remove: a thin ``QUndoCommand`` over the core's
:meth:`~wakeline.core.session.Session.remove_layer` and its inverse
:meth:`~wakeline.core.session.Session.restore_layer`, on a stack of the window's own
(Edit ▸ Restore removed layer / Remove layer again; the review's decisions keep their
stacks, one per queue).

Both directions go through the session, whose events the project writer follows: a
removal deletes the layer's rows at once, an undo writes the layer (points, lineage, side
tables) and the layer order again at once. Its review decisions are never deleted (the
decision log keeps them), so the restored layer's review binds to them as before.
"""

import shiboken6
from PySide6 import QtCore, QtGui

from wakeline.app.layer_names import shown_name
from wakeline.core.errors import InputError

#: The translation context of the texts here (the window's).
TR_CONTEXT = "MainWindow"
#: Removed layers kept for an undo (their points stay in memory until dropped).
UNDO_LIMIT = 20


def tr(text: str) -> str:
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


class RemoveLayerCommand(QtGui.QUndoCommand):
    """One layer's removal on the window's layer stack."""

    def __init__(self, window, layer_id: str) -> None:
        self.window = window
        self.layer_id = layer_id
        self.name = shown_name(window.session.layers[layer_id].name)
        self.removal = None  # the core's record of the last removal
        self.view = None  # the window's prepared view of the layer (no new preparing)
        super().__init__(self.name)

    @property
    def stale(self) -> bool:
        """The session was cleared since (a project opened or closed): nothing to restore."""
        removal = self.removal
        return removal is not None and removal.generation != self.window.session.generation

    def redo(self) -> None:
        w = self.window
        if self.layer_id not in w.session.layers:
            return
        self.view = w.views.get(self.layer_id)
        self.removal = w.session.remove_layer(self.layer_id)

    def undo(self) -> None:
        w, removal = self.window, self.removal
        if removal is None or self.stale:
            return
        if self.view is not None and self.layer_id not in w.views:
            w.views[self.layer_id] = self.view  # taken as it was: drawn, not prepared again
        try:
            w.session.restore_layer(removal)
        except InputError as exc:  # never into Qt's loop
            w.views.pop(self.layer_id, None)
            w.log_message(f"{tr('Error')}: {self.name}: {exc}")
            return
        w.log_message(tr("Layer {0} restored").format(self.name))


class LayerUndo:
    """The window's stack of layer removals and its two Edit menu entries."""

    def __init__(self, window, menu) -> None:
        self.window = window
        self.stack = QtGui.QUndoStack(window)
        self.stack.setUndoLimit(UNDO_LIMIT)
        self.act_undo = QtGui.QAction(window)
        self.act_undo.triggered.connect(self.undo)
        self.act_redo = QtGui.QAction(window)
        self.act_redo.triggered.connect(self.redo)
        menu.addSeparator()
        menu.addActions([self.act_undo, self.act_redo])
        menu.aboutToShow.connect(self.retranslate)
        for signal in (self.stack.indexChanged, self.stack.cleanChanged):
            signal.connect(self.retranslate)
        self.retranslate()

    def _alive(self) -> bool:
        """The stack and the actions still exist (not during the window's teardown)."""
        return all(shiboken6.isValid(o) for o in (self.stack, self.act_undo, self.act_redo))

    def _drop_stale(self) -> None:
        if not self._alive():
            return
        cmd = self.stack.command(0) if self.stack.count() else None
        if isinstance(cmd, RemoveLayerCommand) and cmd.stale:
            self.stack.clear()

    def remove(self, layer_id: str) -> None:
        """Remove layer ``layer_id`` through the stack (undoable)."""
        self._drop_stale()
        self.stack.push(RemoveLayerCommand(self.window, layer_id))

    def undo(self) -> None:
        self._drop_stale()
        self.stack.undo()

    def redo(self) -> None:
        self._drop_stale()
        self.stack.redo()

    def retranslate(self, *_args) -> None:
        """The entries' texts (the layer they name) in the current language."""
        if not self._alive():
            return
        self._drop_stale()
        stack = self.stack
        self.act_undo.setEnabled(stack.canUndo())
        self.act_redo.setEnabled(stack.canRedo())
        undo, redo = stack.undoText(), stack.redoText()
        self.act_undo.setText(
            tr("Restore removed &layer {0}").format(undo) if undo else tr("Restore removed &layer")
        )
        self.act_redo.setText(
            tr("Remove layer {0} ag&ain").format(redo) if redo else tr("Remove layer ag&ain")
        )

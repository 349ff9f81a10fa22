"""Undo of the layer edits: thin ``QUndoCommand`` over the core's
:meth:`~wakeline.core.session.Session.remove_layer` and its inverse
:meth:`~wakeline.core.session.Session.restore_layer`, a layer's colour
(:meth:`~wakeline.core.session.Session.set_color`, Layers ▸ Colour…) and its place in
the order (:meth:`~wakeline.core.session.Session.move_layer`, Move up / Move down), on a
stack of the window's own (Edit ▸ Restore removed layer / Remove layer again, Undo layer
colour …: the entries name the edit; the review's decisions keep their stacks, one per
queue).

Both directions go through the session, whose events the project writer follows: a
removal deletes the layer's rows at once, an undo writes the layer (points, lineage, side
tables) and the layer order again at once. Its review decisions are never deleted (the
decision log keeps them), so the restored layer's review binds to them as before.
"""

import shiboken6
from PySide6 import QtCore, QtGui

from wakeline.app import undo_order
from wakeline.app.layer_names import shown_name
from wakeline.core.errors import InputError

#: The translation context of the texts here (the window's).
TR_CONTEXT = "MainWindow"
#: Removed layers kept for an undo (their points stay in memory until dropped).
UNDO_LIMIT = 20


def tr(text: str) -> str:
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


class LayerCommand(QtGui.QUndoCommand):
    """A layer edit on the window's layer stack, made in one piece of work (a session's
    generation): stale once a project is opened or closed."""

    def __init__(self, window, layer_id: str) -> None:
        self.window = window
        self.layer_id = layer_id
        self.name = shown_name(window.session.layers[layer_id].name)
        self.generation = window.session.generation
        super().__init__(self.name)
        undo_order.stamp(self)  # Edit ▸ Undo's one order with the review's stacks

    @property
    def stale(self) -> bool:
        """The session was cleared since (a project opened or closed): nothing to undo."""
        return self.generation != self.window.session.generation

    def label(self) -> str:
        """The edit named after Edit ▸ Undo / Redo (the window's one pair)."""
        return tr("remove layer {0}").format(self.name)

    def undo_text(self) -> str:
        return tr("Restore removed &layer {0}").format(self.name)

    def redo_text(self) -> str:
        return tr("Remove layer {0} ag&ain").format(self.name)


class RemoveLayerCommand(LayerCommand):
    """One layer's removal on the window's layer stack."""

    def __init__(self, window, layer_id: str) -> None:
        super().__init__(window, layer_id)
        self.removal = None  # the core's record of the last removal
        self.error: Exception | None = None  # why the session refused the removal
        self.view = None  # the window's prepared view of the layer (no new preparing)

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
        try:
            self.removal = w.session.remove_layer(self.layer_id)
        except (InputError, KeyError, TypeError, ValueError) as exc:
            # raised out of a C++ call (the stack's push), it would be lost; kept for
            # LayerUndo.remove to raise, and the command leaves the stack (nothing done)
            self.error = exc
            self.setObsolete(True)

    def undo(self) -> None:
        undo_order.undone(self)
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


class InverseLayerCommand(LayerCommand):
    """An edit whose session call (:meth:`apply`) returns the value that undoes it: the
    first redo keeps that value, undo applies it; nothing while the command is stale or
    the layer is gone."""

    def __init__(self, window, layer_id: str, value) -> None:
        super().__init__(window, layer_id)
        self.value = value
        self.old = None

    def apply(self, value):
        raise NotImplementedError

    def _live(self) -> bool:
        return not self.stale and self.layer_id in self.window.session.layers

    def redo(self) -> None:
        if not self._live():
            return
        old = self.apply(self.value)
        if self.old is None:
            self.old = old

    def undo(self) -> None:
        undo_order.undone(self)
        if self.old is None or not self._live():
            return
        self.apply(self.old)


class ColorLayerCommand(InverseLayerCommand):
    """A layer drawn in the operator's colour (Layers ▸ Colour…); undo: the colour, and
    whether it was chosen, it had."""

    def __init__(self, window, layer_id: str, color: str) -> None:
        super().__init__(window, layer_id, (color, True))

    def apply(self, value: tuple[str, bool]) -> tuple[str, bool]:
        return self.window.session.set_color(self.layer_id, *value)

    def label(self) -> str:
        return tr("layer colour ({0})").format(self.name)

    def undo_text(self) -> str:
        return tr("Undo &layer colour ({0})").format(self.name)

    def redo_text(self) -> str:
        return tr("Redo layer colour ({0}) ag&ain").format(self.name)


class MoveLayerCommand(InverseLayerCommand):
    """A layer moved to another place of the order (Layers ▸ Move up / Move down, or
    dragged); undo: back to its place."""

    def apply(self, pos: int) -> int:
        return self.window.session.move_layer(self.layer_id, pos)

    def label(self) -> str:
        return tr("layer move ({0})").format(self.name)

    def undo_text(self) -> str:
        return tr("Undo &layer move ({0})").format(self.name)

    def redo_text(self) -> str:
        return tr("Redo layer move ({0}) ag&ain").format(self.name)


class ReorderLayersCommand(LayerCommand):
    """The layers put in another order at once (several rows dragged in the Layers
    list); undo: the order before, for the layers still there."""

    def __init__(self, window, layer_id: str, order: list[str]) -> None:
        super().__init__(window, layer_id)
        self.order = list(order)
        self.old = list(window.session.layers)

    def label(self) -> str:
        return tr("layer move ({0})").format(self.name)

    def undo_text(self) -> str:
        return tr("Undo &layer move ({0})").format(self.name)

    def redo_text(self) -> str:
        return tr("Redo layer move ({0}) ag&ain").format(self.name)

    def _put(self, order: list[str]) -> None:
        if self.stale:
            return
        now = list(self.window.session.layers)
        want = [i for i in order if i in now] + [i for i in now if i not in order]
        if want != now:
            self.window.session.reorder(want)

    def redo(self) -> None:
        self._put(self.order)

    def undo(self) -> None:
        undo_order.undone(self)
        self._put(self.old)


class LayerUndo:
    """The window's stack of layer edits (removal, colour, order) and its two actions
    (kept off the Edit menu: its one Undo / Redo pair takes this stack's edits in
    turn with the review's, :mod:`~wakeline.app.undo_order`)."""

    def __init__(self, window, menu) -> None:
        self.window = window
        self.stack = QtGui.QUndoStack(window)
        self.stack.setUndoLimit(UNDO_LIMIT)
        self.act_undo = QtGui.QAction(window)
        self.act_undo.triggered.connect(self.undo)
        self.act_redo = QtGui.QAction(window)
        self.act_redo.triggered.connect(self.redo)
        # Not in the Edit menu (operator test 11): Edit ▸ Undo / Redo (the review dock's,
        # Ctrl+Z) undo the newest edit of this stack and the active layer's
        # (undo_order); these stay for scripts and tests.
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
        if isinstance(cmd, LayerCommand) and cmd.stale:
            self.stack.clear()

    def remove(self, layer_id: str) -> None:
        """Remove layer ``layer_id`` through the stack (undoable)."""
        self._drop_stale()
        command = RemoveLayerCommand(self.window, layer_id)
        self.stack.push(command)  # an obsolete command (refused) is not kept
        if command.error is not None:
            raise command.error

    def push(self, command: LayerCommand) -> None:
        """Do ``command`` (a colour, a move) through the stack (undoable)."""
        self._drop_stale()
        self.stack.push(command)

    def undo(self) -> None:
        self._drop_stale()
        self.stack.undo()

    def took(self, layer) -> bool:
        """``layer`` (the object) is one a removal on the stack took out (and is back
        when its undo emits ``added``)."""
        if layer is None or not self._alive():
            return False
        for k in range(self.stack.count()):
            cmd = self.stack.command(k)
            if isinstance(cmd, RemoveLayerCommand) and cmd.removal is not None:
                if cmd.removal.layer is layer and not cmd.stale:
                    return True
        return False

    def redo(self) -> None:
        self._drop_stale()
        cmd = self.stack.command(self.stack.index()) if self.stack.canRedo() else None
        self.stack.redo()
        if isinstance(cmd, RemoveLayerCommand) and cmd.error is not None:  # refused: said
            self.window.log_message(f"{tr('Error')}: {cmd.name}: {cmd.error}")
            cmd.error = None
            self.retranslate()  # the stack dropped it: no index change said so

    def retranslate(self, *_args) -> None:
        """The entries' texts (the layer they name) in the current language."""
        if not self._alive():
            return
        self._drop_stale()
        stack = self.stack
        self.act_undo.setEnabled(stack.canUndo())
        self.act_redo.setEnabled(stack.canRedo())
        index = stack.index()
        undo = stack.command(index - 1) if index > 0 else None
        redo = stack.command(index) if index < stack.count() else None
        self.act_undo.setText(
            undo.undo_text() if isinstance(undo, LayerCommand) else tr("Restore removed &layer")
        )
        self.act_redo.setText(
            redo.redo_text() if isinstance(redo, LayerCommand) else tr("Remove layer ag&ain")
        )
        review = getattr(self.window, "review", None)
        if review is not None:
            review._undo_note()  # Edit ▸ Undo / Redo name the newest edit of both

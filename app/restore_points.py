"""Putting back points removed by cleaning (SPEC §2), in the window: a thin
``QUndoCommand`` over the core's :class:`~wakeline.core.clean_restore.Restore`.

The removed points are the map's × marks (View ▸ Show points removed by cleaning; the
hover says the rule). A right click on the map offers, for the × nearest the cursor:
restore this point; restore every point its rule removed on its track; and, for the
layer, restore the removed points in the map's view. Edit ▸ Restore … does it for the
active layer's selected tracks, a box dragged on the map, or the view.

Each restore is applied to the session at once (:func:`~wakeline.core.clean_restore.apply`:
points, reject trail, counts, lineage; the ``changed`` event has the project write the
layer), and lands on an undo stack of the layer's own in the review's ``QUndoGroup``, so
Edit ▸ Undo / Redo (Ctrl+Z, Ctrl+Shift+Z) act on it while the layer is the active one. A
re-run of Clean makes a new layer: its stack is emptied (the restored points are put back
by the run itself, :meth:`~wakeline.core.session.Session.run_step`).
"""

import math

import numpy as np
from PySide6 import QtCore, QtGui

from wakeline.app import undo_order
from wakeline.app.layer_names import shown_name
from wakeline.core import clean_restore as CR
from wakeline.core.errors import InputError

#: A removed point within this many pixels of a right click is the one it means.
PICK_PX = 8.0


TR_CONTEXT = "RestorePoints"


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


def rule_name(rule: str) -> str:
    """A clean rule's name in the window's language, as the clean summary and the
    Parameters say it (转向异常 for turn; operator test 11: the Restore entries, undo
    texts and log said the English identifiers in the Chinese window)."""
    from wakeline.app.core_text import shown

    return shown(rule)


def rules_text(rules: dict[str, int]) -> str:
    """ "speed 3, turn 1": points per rule (the rules' names as the clean summary says
    them, in the window's language)."""
    return ", ".join(f"{rule_name(rule)} {n:,}" for rule, n in rules.items())


class RestoreCommand(QtGui.QUndoCommand):
    """One restore on the undo stack."""

    def __init__(self, tool: "RestoreTool", change: CR.Restore) -> None:
        self.tool = tool
        self.change = change
        super().__init__(self.title())
        undo_order.stamp(self)  # Edit ▸ Undo's one order with the layer edits

    def title(self) -> str:
        """Edit ▸ Undo / Redo's text, in the current language."""
        return tr("restore {0} points ({1})").format(
            f"{len(self.change):,}", rules_text(self.change.rules)
        )

    def redo(self) -> None:
        self.tool._apply(self.change)

    def undo(self) -> None:
        undo_order.undone(self)
        self.tool._apply(self.change.inverse())


class RestoreTool(QtCore.QObject):
    """The window's Restore: map context menu, Edit menu entries, one undo stack per
    cleaned layer (in the review dock's undo group)."""

    def __init__(self, w) -> None:
        super().__init__(w)
        self.w = w
        self.group: QtGui.QUndoGroup = w.review.group
        self.stacks: dict[str, QtGui.QUndoStack] = {}
        #: the stacks of removed layers (Layer ▸ Remove), with the session's generation:
        #: Edit ▸ Undo's Restore removed layer brings the layer and its restores back
        self.parked: dict[str, tuple[QtGui.QUndoStack, int]] = {}
        self._applying = False  # our own "changed" event (not a re-run)
        self._todo: list[CR.Restore] = []  # do / undo / redo waiting for the worker
        self._job: int | None = None
        self._making: CR.Restore | None = None  # the change the worker makes now
        from wakeline.app.worker import JobRunner

        self.runner = JobRunner(self)
        self.runner.message.connect(self._on_message)
        self._menu_actions: list[QtGui.QAction] = []
        self.act_tracks = QtGui.QAction(w)
        self.act_tracks.triggered.connect(self.restore_selected_tracks)
        self.act_view = QtGui.QAction(w)
        self.act_view.triggered.connect(lambda: self.restore_in_view())
        self.act_box = QtGui.QAction(w, checkable=True)  # the next drag on the map: a box
        menu = w.review.edit_menu
        menu.addSeparator()
        menu.addActions([self.act_tracks, self.act_box, self.act_view])
        vb = w.canvas.vb
        self._raise_menu = vb.raiseContextMenu
        vb.raiseContextMenu = self._context_menu
        self._drag = vb.mouseDragEvent
        vb.mouseDragEvent = self._drag_event
        w.session.subscribe(self._on_event)
        self.group.activeStackChanged.connect(self._keep_active)
        self.retranslate()

    def retranslate(self) -> None:
        self.act_tracks.setText(tr("Re&store points removed by cleaning on the selected tracks"))
        self.act_view.setText(tr("Restore removed points &in the map's view"))
        self.act_box.setText(tr("Restore removed points in a &box (drag it on the map)"))
        tip = tr(
            "Put the points clean removed back into the active cleaned layer (undo: Ctrl+Z); "
            "View ▸ Show points removed by cleaning shows them as ×, Box zoom frames a box"
        )
        for act in (self.act_tracks, self.act_view, self.act_box):
            act.setToolTip(tip)
            act.setStatusTip(tip)
        for stack in self.stacks.values():
            for k in range(stack.count()):
                cmd = stack.command(k)
                if isinstance(cmd, RestoreCommand):
                    cmd.setText(cmd.title())

    # -- the undo stacks ---------------------------------------------------------------

    def stack(self, lid: str) -> QtGui.QUndoStack:
        if lid not in self.stacks:
            stack = QtGui.QUndoStack(self)
            self.stacks[lid] = stack
            self.group.addStack(stack)
        return self.stacks[lid]

    def _drop(self, lid: str) -> None:
        stack = self.stacks.pop(lid, None)
        if stack is not None:
            self.group.removeStack(stack)
            stack.deleteLater()

    def _park(self, lid: str) -> None:
        """Layer ``lid`` was removed: its stack leaves the group, kept for an undo of
        the removal (operator test 11, F2: its restores could no longer be undone)."""
        stack = self.stacks.pop(lid, None)
        if stack is not None:
            self.group.removeStack(stack)
            self.parked[lid] = (stack, self.w.session.generation)

    def _unpark(self, lid: str) -> None:
        """Layer ``lid`` is back (its removal undone: the very layer the removal took, in
        the same work): its stack too; parked stacks of closed work go (a project opened
        may use the same ids again)."""
        generation = self.w.session.generation
        undo = getattr(self.w, "layer_undo", None)
        back = undo is not None and undo.took(self.w.session.get(lid))
        for key, (stack, gen) in list(self.parked.items()):
            if gen != generation or key == lid:
                del self.parked[key]
                if key == lid and back and gen == generation and lid not in self.stacks:
                    self.stacks[lid] = stack
                    self.group.addStack(stack)
                else:
                    stack.deleteLater()

    def _on_event(self, event: str, lid: str) -> None:
        if event == "removed":
            self._park(lid)  # gone: kept for an undo of the removal
        elif event == "added":
            self._unpark(lid)
        elif event == "changed" and not self._applying:
            self._drop(lid)  # made again (a re-run): the commands are stale
        if event in ("active", "removed", "changed", "added"):
            self._keep_active()

    def _keep_active(self, *_args) -> None:
        """Edit ▸ Undo acts on the active layer's restores when it has some; a review's
        stack stays when the active layer is under review."""
        lid = self.w.session.active
        current = self.group.activeStack()
        mine = self.stacks.get(lid) if lid else None
        if mine is not None and current is not mine:
            if current is None or current in self.stacks.values():
                self.group.setActiveStack(mine)
        elif mine is None and current is not None and current in self.stacks.values():
            self.group.setActiveStack(None)

    # -- restoring -----------------------------------------------------------------------

    def restore(self, lid: str, ids) -> bool:
        """Put the rejected points ``ids`` (``wl_id``) of layer ``lid`` back, through
        its undo stack. False (the log says why) when nothing could be restored."""
        layer = self.w.session.get(lid)
        pending = self._pending_ids(lid)
        if len(pending):  # restores not swapped in yet: their points are not asked twice
            ids = np.setdiff1d(np.asarray(list(ids), dtype="int64"), pending)
            if not len(ids):
                self.w.log_message(tr("Restore: those points are being restored"))
                return False
        try:
            change = CR.restore_change(layer, ids)
        except InputError as exc:
            self.w.log_message(tr("Restore: {0}").format(str(exc)))
            return False
        if self.w.session.active != lid:  # the layer restored into becomes the active one
            self.w.select_layer(lid)
        self.stack(lid).push(RestoreCommand(self, change))
        self._keep_active()
        return True

    def _pending_ids(self, lid: str) -> np.ndarray:
        """The points of layer ``lid`` the changes queued or being made will have put
        back (a restore chosen meanwhile still sees them in the rejected table)."""
        out: set[int] = set()
        for change in [self._making, *self._todo]:
            if change is not None and change.layer == lid:
                out = out - set(change.ids) if change.undo else out | set(change.ids)
        return np.array(sorted(out), dtype="int64")

    def _apply(self, change: CR.Restore) -> None:
        """Apply ``change`` (a command's do, undo or redo): queued, then made in the
        worker one at a time (the tables and the layer's map view: 0.3-0.5 s for 100,000
        points, too long for the GUI thread) and swapped in here."""
        self._todo.append(change)
        self._next()

    @property
    def busy(self) -> bool:
        """A restore (or its undo) is being made or waits (tests wait on it)."""
        return self._job is not None or bool(self._todo)

    def _next(self) -> None:
        from wakeline.app.layer_view import prepare_view

        while self._job is None and self._todo:
            change = self._todo.pop(0)
            try:
                layer, rejected = CR.check(self.w.session, change)
            except InputError as exc:
                self.w.log_message(tr("Restore: {0}").format(str(exc)))
                continue
            previous = self.w.views.get(layer.id)
            colors = tuple(previous.colors) if previous is not None and previous.colors else None
            look = (layer.kind, layer.color, layer.name, self.w.canvas.current_view())
            look += (self.w.canvas.plot_size_px(), colors)

            def job(progress, change=change, points=layer.points, rejected=rejected, look=look,
                    previous=previous):  # fmt: skip
                progress(0.0, "restoring points removed by cleaning")
                pts, rej = CR.restored_tables(points, rejected, change)
                return change, points, prepare_view(pts, *look, previous=previous), rej

            self._job = self.runner.run("restore", job)
            self._making = change

    def _on_message(self, msg) -> None:
        from wakeline.app.worker import Cancelled, Failed, Finished

        if not isinstance(msg, Finished | Failed | Cancelled) or msg.job != self._job:
            return
        self._job = self._making = None
        try:
            if isinstance(msg, Failed):
                self.w.log_message(tr("Restore: {0}").format(msg.message))
            elif isinstance(msg, Finished):
                self._swap(*msg.result)
        finally:
            self._next()

    def _swap(self, change: CR.Restore, read, view, rejected) -> None:
        """Put the tables made in the worker into the layer (with the map view made
        there), unless the layer changed meanwhile (a re-run of Clean)."""
        layer = self.w.session.get(change.layer)
        if layer is None or layer.points is not read or layer.run != change.run:
            self.w.log_message(tr("Restore: the layer changed meanwhile; nothing restored"))
            return
        self._applying = True
        self.w._pending_views = {(layer.step, layer.role): view}
        if layer.id == self.w.active:  # the batch table is rebuilt: keep its selection
            self.w._restore_selection = self.w.selected_keys() or None
        try:
            CR.put(self.w.session, change, view.points, rejected)
        except InputError as exc:
            self.w.log_message(tr("Restore: {0}").format(str(exc)))
            return
        finally:
            self._applying = False
            self.w._pending_views = {}
        text = (
            tr("Took out again {0} restored points ({1}) of {2}")
            if change.undo
            else tr("Restored {0} points removed by cleaning ({1}) into {2}")
        )
        self.w.log_message(
            text.format(f"{len(change):,}", rules_text(change.rules), shown_name(layer.name))
        )
        made = self.w.session.children(layer.id)
        if made:  # their steps read the points before: said, not re-run by themselves
            self.w.log_message(
                tr(
                    "{0} layers made from it keep the points they read: run their steps again"
                ).format(len(made))
            )

    def restore_selected_tracks(self) -> bool:
        """Edit ▸ Restore … on the selected tracks: every removed point of theirs."""
        layer = self.w.active_layer()
        rejected = CR.rejected_of(layer)
        keys = self.w.selected_keys()
        if rejected is None or not keys:
            self.w.log_message(
                tr(
                    "Restore: select tracks of a cleaned layer first (its points removed by "
                    "cleaning are put back)"
                )
            )
            return False
        ids = CR.chosen_ids(rejected, tracks=keys)
        return self.restore(layer.id, ids) if len(ids) else self._none_chosen()

    def restore_in_view(self, lid: str | None = None) -> bool:
        """Every removed point of layer ``lid`` (default: the active one) in the map's
        view (a box: Box zoom frames it first)."""
        layer = self.w.session.get(lid) if lid else self.w.active_layer()
        rejected = CR.rejected_of(layer)
        if rejected is None:
            self.w.log_message(tr("Restore: the active layer has no points removed by cleaning"))
            return False
        x0, x1, y0, y1 = self.w.canvas.current_view()
        box = (x0, y0, x1, y1) if x1 - x0 < 360 else (-180.0, y0, 180.0, y1)
        ids = CR.chosen_ids(rejected, box=box)
        return self.restore(layer.id, ids) if len(ids) else self._none_chosen()

    def restore_in_box(
        self, box: tuple[float, float, float, float], lid: str | None = None
    ) -> bool:
        """Every removed point of layer ``lid`` (default: the active one) inside ``box``
        (west, south, east, north, degrees on the map's axes)."""
        layer = self.w.session.get(lid) if lid else self.w.active_layer()
        rejected = CR.rejected_of(layer)
        if rejected is None:
            self.w.log_message(tr("Restore: the active layer has no points removed by cleaning"))
            return False
        west, south, east, north = box
        if east - west >= 360:
            west, east = -180.0, 180.0
        ids = CR.chosen_ids(rejected, box=(west, south, east, north))
        return self.restore(layer.id, ids) if len(ids) else self._none_chosen()

    def _drag_event(self, ev, axis=None) -> None:
        """A left drag on the map while Edit ▸ Restore … in a box is on draws the box (as
        Box zoom does) and, let go, restores the removed points in it; else the map's own
        drag (pan, Box zoom)."""
        left = QtCore.Qt.MouseButton.LeftButton
        if not self.act_box.isChecked() or ev.button() != left or axis is not None:
            self._drag(ev, axis)
            return
        ev.accept()
        vb = self.w.canvas.vb
        if not ev.isFinish():
            vb.updateScaleBox(ev.buttonDownPos(), ev.pos())
            return
        vb.rbScaleBox.hide()
        rect = QtCore.QRectF(ev.buttonDownPos(left), ev.pos())
        rect = vb.childGroup.mapRectFromParent(rect).normalized()
        self.act_box.setChecked(False)  # one box
        self.restore_in_box((rect.left(), rect.top(), rect.right(), rect.bottom()))

    def _none_chosen(self) -> bool:
        self.w.log_message(tr("Restore: no removed point there"))
        return False

    # -- the map's right click -------------------------------------------------------------

    def removed_near(self, lon: float, lat: float, pixels: float = PICK_PX):
        """The removed point (a row of a shown layer's reject trail) nearest ``lon,
        lat`` within ``pixels`` on screen: (layer id, row) or None. Read from the trail
        itself (the × marks are drawn from it), wrapped longitudes allowed."""
        w = self.w
        if not (math.isfinite(lon) and math.isfinite(lat)):
            return None
        if not w.map_option("map/show_removed", False):
            return None
        px_x, px_y = w.canvas.vb.viewPixelSize()
        best = None
        for lid, layer in w.session.layers.items():
            rejected = CR.rejected_of(layer)
            if rejected is None or not layer.visible or not len(rejected):
                continue
            rx = rejected["lon"].to_numpy(dtype="float64")
            ry = rejected["lat"].to_numpy(dtype="float64")
            dx = ((rx - lon + 180.0) % 360.0 - 180.0) / px_x
            d = np.hypot(dx, (ry - lat) / px_y)
            d[~CR.restorable(rejected)] = np.inf
            if not np.isfinite(d).any():
                continue
            i = int(np.nanargmin(np.where(np.isnan(d), np.inf, d)))
            if d[i] <= pixels and (best is None or d[i] < best[0]):
                best = (float(d[i]), lid, i)
        return None if best is None else (best[1], best[2])

    def menu_actions(self, lon: float, lat: float) -> list[QtGui.QAction]:
        """The right-click menu's Restore entries for the map point ``lon, lat``."""
        w, out = self.w, []
        hit = self.removed_near(lon, lat)
        if hit is not None:
            lid, i = hit
            row = w.session.get(lid).tables[CR.REJECTED].iloc[i]
            rule, wid = str(row["rule"]), int(row["wl_id"])
            sensor, batch = str(row["sensor"]), str(row["batch"])
            one = QtGui.QAction(
                tr("Restore this point (removed by {0})").format(rule_name(rule)), w
            )
            one.triggered.connect(lambda _=False: self.restore(lid, [wid]))
            out.append(one)
            rejected = w.session.get(lid).tables[CR.REJECTED]
            ids = CR.chosen_ids(rejected, rules=[rule], track=(sensor, batch))
            many = QtGui.QAction(
                tr("Restore all {0} points removed by {1} on {2} · {3}").format(
                    f"{len(ids):,}", rule_name(rule), sensor, batch
                ),
                w,
            )
            many.triggered.connect(lambda _=False: self.restore(lid, ids))
            out.append(many)
        else:
            lid = w.session.active
        if CR.rejected_of(w.session.get(lid)) is not None:
            view = QtGui.QAction(tr("Restore removed points in the map's view"), w)
            view.triggered.connect(lambda _=False: self.restore_in_view(lid))
            out.append(view)
        return out

    def _context_menu(self, ev) -> None:
        """The map's right-click menu with the Restore entries on top."""
        vb = self.w.canvas.vb
        menu = vb.getMenu(ev)
        for act in self._menu_actions:
            if menu is not None:
                menu.removeAction(act)
        self._menu_actions = []
        if menu is not None:
            p = vb.mapSceneToView(ev.scenePos())
            acts = self.menu_actions(p.x(), p.y())
            if acts:
                first = menu.actions()[0] if menu.actions() else None
                sep = QtGui.QAction(self.w)
                sep.setSeparator(True)
                acts.append(sep)
                for act in acts:
                    menu.insertAction(first, act)
                self._menu_actions = acts
        self._raise_menu(ev)


def install(w) -> RestoreTool:
    """The window's Restore (after its review dock: the Edit menu and undo group)."""
    return RestoreTool(w)

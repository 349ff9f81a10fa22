"""The window's layers: a view over the session's layers (by id), drawn one per turn.

Mixed into :class:`~wakeline.app.main_window.MainWindow`. Session events add, redraw,
hide or remove a layer; prepared arrays are swapped into the map one layer per
event-loop turn so a result of several layers never blocks in one piece.
"""

import functools
import html
from collections.abc import Iterable

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtWidgets

from wakeline.app.layer_names import shown_name
from wakeline.app.layer_view import (
    DRAW_STYLE,
    PART_SEP,
    is_part_of,
    map_layers,
    prepare_view_apart,
)
from wakeline.app.map_canvas import color_icon
from wakeline.app.models import batch_summary
from wakeline.core.errors import InputError
from wakeline.core.session import BEARING_KIND, COLOR_CHOSEN, Layer, check_color


def layer_text(layer: Layer, gap: str = "  ") -> str:
    """A layer's line in the Layers list: its name and its kind in the window's language
    ("scene.csv  [source]", zh_CN "scene.csv  [源数据]"); a name whose last step word
    says the kind already is not followed by it again ("a.csv · fused", not "a.csv ·
    fused  [fused]": operator test 8, D7)."""
    name, kind = shown_name(layer.name), kind_text(layer.kind)
    if " · " in name and name.rsplit(" · ", 1)[1].startswith(kind):
        return name
    return f"{name}{gap}[{kind}]"


def kind_text(kind: str) -> str:
    """A layer's kind in the window's language ("source", zh_CN "源数据")."""
    app = QtCore.QCoreApplication
    kinds = {
        "source": app.translate("MainWindow", "source"),
        "cleaned": app.translate("MainWindow", "cleaned"),
        "maneuvers": app.translate("MainWindow", "maneuvers"),
        "compressed": app.translate("MainWindow", "compressed"),
        "associated": app.translate("MainWindow", "associated"),
        "fused": app.translate("MainWindow", "fused"),
        "bearing": app.translate("MainWindow", "bearing"),
    }
    return kinds.get(kind, kind)


def layer_tip(session, layer: Layer) -> str:
    """The Layers list's tooltip of a layer made from several (a fuse across layers): the
    name of every input, which its own name counts beyond the first two
    (:func:`wakeline.core.words.joined_names`); empty for others. Rich text, so Qt wraps it."""
    names = [shown_name(session.layers[i].name) for i in layer.inputs if i in session.layers]
    if len(names) < 2:
        return ""
    text = QtCore.QCoreApplication.translate("MainWindow", "Made from {0} layers: {1}").format(
        f"{len(names):,}", " + ".join(names)
    )
    return f"<p>{html.escape(text)}</p>"


def _relabelled(text: str, old: str, new: str) -> str:
    """A legend label drawn with a layer's name ``old`` (one language) with ``new``."""
    return new + text[len(old) :] if text.startswith(old) else text


#: Between two pieces of drawing work: a real timer (not a zero-delay call), so the map's
#: paint of one piece and the next piece fall in different event-loop turns.
STEP_MS = 5

EMPTY = pd.DataFrame(columns=["sensor", "batch", "time", "lon", "lat"])
#: layer kinds whose points are a sampling of their own (not the source layer's times):
#: the Detection-limit text describes them, not their source
OWN_SAMPLING_KINDS = ("fused",)
#: Settings (QSettings) of the map's View menu choices, and their defaults.
COLOR_BY_TRACK_KEY = "map/color_by_track"
SHOW_REMOVED_KEY = "map/show_removed"
#: View ▸ Keep the active layer on top: over the layer order (default) or in its place.
ACTIVE_ON_TOP_KEY = "map/active_on_top"
#: The map layer of a cleaned layer's removed points (``<layer id>/removed``).
REMOVED_PART = "removed"
#: How long the map's view must rest before the track labels follow it (ms).
LABELS_MS = 80
#: Positions labels are placed for layers of at most this many tracks (one search each).
LABEL_TRACKS_MAX = 2_000
#: Batch table columns sized to their text when a layer is shown.
FITTED_COLUMNS = ("sensor", "batch", "points", "start", "end")


class LayersMixin:
    """Layers list, the active layer and the drawing queue."""

    TR_CONTEXT = "MainWindow"

    @property
    def layers(self) -> dict[str, Layer]:
        return self.session.layers

    def legend_in_language(self) -> None:
        """The bearing layers' fixed legend words (observer, other batches, …) as drawn,
        in the window's language now (a language switch; new drawings take it anyway)."""
        from wakeline.app.bearing_view import legend_words, reworded
        from wakeline.app.layer_view import PART_SEP

        words = legend_words()
        for name in self.canvas.layer_names():
            lid, sep, part = name.rpartition(PART_SEP)
            layer = self.session.layers.get(lid) if sep else None
            if layer is not None and layer.kind == BEARING_KIND:
                rename = functools.partial(reworded, part=part, words=words)
                self.canvas.relabel_layer(name, rename)
        # The × marks of removed points: their legend lines (rule names) made anew in the
        # worker, in the window's language (operator test 11, F20)
        if getattr(self, "_removed_drawn", None):
            self._removed_drawn, self._removed_shown = {}, {}
            for lid in list(self.session.layers):
                self._update_removed(lid)
        # A layer's name's step words (D-i18n-2): the label it was drawn with, said anew.
        drawn = getattr(self, "_drawn_labels", {})
        for lid, old in list(drawn.items()):
            layer = self.session.layers.get(lid)
            if layer is None:
                del drawn[lid]
                continue
            new = shown_name(layer.name)
            if old and new != old and lid in self.canvas.layer_names():
                self.canvas.relabel_layer(lid, functools.partial(_relabelled, old=old, new=new))
                drawn[lid] = new

    def colors_in_use(self, exclude: Iterable[str] = ()) -> tuple[set[str], set[str]]:
        """The colours the layers are drawn in: those of the visible layers and those of
        the hidden ones, without the layers ``exclude`` (a step's re-run replaces them)."""
        shown: set[str] = set()
        hidden: set[str] = set()
        for lid, layer in self.session.layers.items():
            if lid in exclude:
                continue
            view = self.views.get(lid)
            colors = view.colors if view is not None and view.colors else (layer.color,)
            (shown if layer.visible else hidden).update(colors)
        return shown, hidden

    def replaced_by_run(self, lid: str, steps: Iterable[str]) -> set[str]:
        """The layers a run of ``steps`` on layer ``lid`` replaces in place (the session
        replaces a step's layers made from the same input): ``lid``'s children of the first
        step, their children of the next (a pipeline's stages), and so on."""
        out: set[str] = set()
        current = {lid}
        for step in steps:
            current = {
                i
                for i, lay in self.session.layers.items()
                if lay.parent in current and lay.step == step and not lay.inputs
            }
            out |= current
        return out

    def _adopt_view(self, event: str, lid: str) -> None:
        """The session's first listener (before the project writer reads the layer): a
        new or replaced layer takes the view a job prepared for it, and the colour it was
        drawn in there, chosen apart from the other layers'; a layer added by a script or
        a test is prepared here (small), in a colour no other layer shows."""
        layer = self.session.layers.get(lid)
        if event not in ("added", "changed") or layer is None:
            return
        if layer.kind == BEARING_KIND:
            # Prepared in the worker that read it (or opened the project); a bearing
            # layer added by a script or a test is prepared here (small).
            view = self.views.get(lid)
            if view is None or view.points is not layer.points:
                from wakeline.app.bearing_view import (
                    bearing_layer_view,
                    layer_detections,
                    layer_scene,
                )

                scene = layer_scene(layer)
                detections = layer_detections(layer)
                report = layer.meta.get("report")
                self.views[lid] = bearing_layer_view(layer.points, detections, report, scene)
            return
        pending = self._pending_views.pop((layer.step, layer.role), None)
        chosen = bool(layer.meta.get(COLOR_CHOSEN))  # the operator's (Colour…): kept
        if pending is not None:
            self.views[lid] = pending
            if chosen and pending.draw is not None and pending.colors[:1] != (layer.color,):
                from wakeline.app.map_colors import chosen_colors
                from wakeline.app.map_draw import with_colors

                pending.draw = with_colors(pending.draw, chosen_colors(pending.colors, layer.color))
            if pending.colors:
                layer.color = pending.colors[0]
        elif lid not in self.views or event == "changed":
            keep = self.views.get(lid)
            in_use = self.colors_in_use(exclude={lid})
            first = keep.colors[0] if keep is not None and keep.colors else layer.color
            self.views[lid] = prepare_view_apart(
                layer.points,
                layer.kind,
                in_use,
                layer.name,
                first=layer.color if chosen else first,
                chosen=chosen,
            )
            layer.points = self.views[lid].points
            layer.color = self.views[lid].colors[0] if self.views[lid].colors else layer.color

    def _on_session_event(self, event: str, lid: str) -> None:
        if event == "time_window" and not self._stats_timer.isActive():
            self._stats_timer.start()  # the Statistics figures of the window's points
        if event in ("time_window", "current_time", "map_view", "active"):
            # The time controller and the view keeper follow the first three; the active
            # layer is the window's own (set_active), or made current after an open.
            return
        layer = self.session.layers.get(lid)
        if event == "added":
            self._queue_draw(lid)
            item = QtWidgets.QListWidgetItem(color_icon(layer.color), layer_text(layer))
            item.setData(QtCore.Qt.ItemDataRole.UserRole, lid)
            tip = layer_tip(self.session, layer)
            if tip:
                item.setToolTip(tip)
            item.setFlags(item.flags() | QtCore.Qt.ItemFlag.ItemIsUserCheckable)
            checked = (
                QtCore.Qt.CheckState.Checked if layer.visible else QtCore.Qt.CheckState.Unchecked
            )
            item.setCheckState(checked)
            # in the session's order: a removed layer restored (Edit ▸ Restore removed
            # layer) takes its place back; a new one is the last
            order = list(self.session.layers)
            row = order.index(lid) if lid in order else self.layer_list.count()
            self.layer_list.insertItem(min(row, self.layer_list.count()), item)
            self._make_current = lid  # once the drawing queue is through (one per turn)
            lat = layer.points.get("lat")
            if (
                len(self.session.layers) == 1
                and lat is not None
                and len(lat)
                and not self._view_planned
            ):
                self.canvas.set_true_aspect(float(np.nanmean(lat.to_numpy())))
        elif event == "changed":
            self._queue_draw(lid)
            row = self.layer_row(lid)
            if row >= 0:  # a re-run may draw it in another colour
                self.layer_list.item(row).setIcon(color_icon(layer.color))
            if lid == self.active:
                self._make_current = lid
        elif event == "removed":
            for name in self.map_names(lid):
                self.canvas.remove_layer(name)
            gone = self.views.pop(lid, None)
            # its sensor choice and whole view (View ▸ Sensors) go too: an undo shows it
            # whole, its view prepared again from its points
            getattr(self, "_full_views", {}).pop(lid, None)
            getattr(self, "hidden_sensors", {}).pop(lid, None)
            if gone is not None and gone.points is self.bearings:
                # Next turn: a project opened clears the session and shows its own.
                QtCore.QTimer.singleShot(0, self._bearings_removed)
            row = self.layer_row(lid)
            if row >= 0:
                self.layer_list.takeItem(row)
            if not self.session.layers:
                self.set_active(None)
            step = self.stale_label.property("step")
            if step and not any(
                layer.step == step or (step == "pipeline" and layer.step)
                for layer in self.session.layers.values()
            ):  # no layer left that its re-run failure speaks of (h175 review F7)
                self.stale_label.hide()
                self.stale_label.setProperty("step", None)
        elif event == "reordered":
            self._order_layer_list()
            self._emphasize()  # the map's stacking follows the list
        elif event == "color" and layer is not None:
            self._recolor(lid)
        elif event == "visibility":
            for name in self.map_names(lid):
                self.canvas.set_visible(name, layer.visible)
            if lid == self.active:  # its selected tracks hide and show with it
                self._table_selection_changed()
            review = getattr(self, "review", None)
            if review is not None:
                review.layer_visibility_changed(lid)  # its joins hide and show with it
        self.layersChanged.emit()

    def _view_state(self, replace_all: bool = False) -> dict:
        """What a job needs to plan the view its layers will be shown in (GUI thread):
        where the points of the visible layers are (none when ``replace_all``; sketches
        made in the worker with each layer), plot size, aspect."""
        keep = not replace_all and bool(self.session.layers)
        data = self.canvas.visible_draw_data() if keep else []
        sketches = [d.geometry.sketch() for d in data]
        lat0 = self.canvas._lat0 if keep else None
        return {"sketches": sketches, "size_px": self.canvas.plot_size_px(), "lat0": lat0}

    def _plan_view(self, plan: dict | None) -> None:
        """Before a job's layers are added: the aspect and range it planned (the layers'
        level of detail was computed for that view in the worker, so none is redone)."""
        if plan is None:
            return
        if plan.get("lat0") is not None:
            self.canvas.set_true_aspect(plan["lat0"])
        self.canvas.show_range(plan["target"])
        self._view_planned = True

    def _queue_draw(self, lid: str) -> None:
        """Swap a layer's prepared arrays into the map on a later event-loop turn, one
        layer per turn, so a result of several layers never blocks in one piece."""
        if getattr(self, "hidden_sensors", None) is not None and self.sensor_filter_pending(lid):
            return  # its view for the sensors shown comes first (View ▸ Sensors)
        if lid not in self._draw_queue:
            self._draw_queue.append(lid)
        if not self._draw_scheduled:
            self._draw_scheduled = True
            QtCore.QTimer.singleShot(STEP_MS, self._draw_next)

    def _draw_next(self) -> None:
        """One piece of drawing work per event-loop turn (each may cost the map a paint):
        a layer swapped in, then the fit, then the current layer, then the selection."""
        self._draw_scheduled = False
        if self._draw_queue:
            lid = self._draw_queue.pop(0)
            layer = self.session.layers.get(lid)
            if layer is not None and lid in self.views:
                label = shown_name(layer.name)
                drawn = map_layers(self.views[lid], lid, label)
                if not hasattr(self, "_drawn_labels"):
                    self._drawn_labels: dict[str, str] = {}
                self._drawn_labels[lid] = label
                keep = {d.name for d in drawn}
                removed = f"{lid}{PART_SEP}{REMOVED_PART}"
                for name in self.map_names(lid):  # a part the layer has no more
                    if name not in keep and name != removed:
                        self.canvas.remove_layer(name)
                for data in drawn:
                    self.canvas.set_draw_data(data, layer.visible)
                self._after_swap(lid)
                timing = getattr(self, "time_controller", None)
                if timing is not None:
                    timing.layer_swapped()  # cut to the time window again
                if layer.visible and self.canvas.isVisible():
                    # Paint now, in this turn: Qt would merge the paints of layers swapped in
                    # on successive turns into one long paint of them all.
                    self.canvas.viewport().repaint()
        elif self._fit_after_draw:
            self._fit_after_draw = False
            self.canvas.frame()
        elif self._make_current is not None:
            lid, self._make_current = self._make_current, None
            if lid in self.session.layers:
                if lid == self.active:
                    if not self._refresh_active(lid):
                        self.set_active(lid)
                else:
                    self.select_layer(lid)
            self._after_current = True
        elif self._after_current:
            self._after_current = False
            self._after_drawn()
        if self.drawing and not self._draw_scheduled:
            self._draw_scheduled = True
            QtCore.QTimer.singleShot(STEP_MS, self._draw_next)

    def _after_drawn(self) -> None:
        """Hook run when the queued layers are drawn (a restored selection)."""
        pending, self._restore_selection = self._restore_selection, None
        if pending:
            self._selecting = True
            self.select_tracks(pending)
            self._selecting = False
            # The session's too (another layer made current meanwhile dropped it).
            selection = [(self.active, s, b) for s, b in pending]
            if selection != self.session.selection:
                self.session.selection = selection
                self.project.put_state("selection", selection)

    @property
    def drawing(self) -> bool:
        """Layers are still waiting to be swapped into the map (or fitted, made current)."""
        return (
            bool(self._draw_queue)
            or self._fit_after_draw
            or self._make_current is not None
            or self._after_current
            or getattr(self, "_styling", 0) > 0
            or bool(getattr(self, "_filtering", ()))  # a view for the sensors shown
        )

    def _bearings_removed(self) -> None:
        """The bearing layer the Bearing-only dock and the Detail panel showed was
        removed: they show the last bearing layer left, or nothing."""
        layers = self.session.layers.values()
        if self.bearings is not None and any(lay.points is self.bearings for lay in layers):
            return  # another one is shown meanwhile
        left = [i for i, lay in self.session.layers.items() if lay.kind == BEARING_KIND]
        if left and left[-1] in self.views:
            self.show_bearing_layer(self.views[left[-1]])
            return
        self.bearings = self.bearing_detections = None
        self.bearing_view.clear()
        self.detail.clear_bearings()

    def map_names(self, lid: str) -> list[str]:
        """The map layers that draw session layer ``lid`` (a bearing layer: its parts)."""
        return [n for n in self.canvas.layer_names() if is_part_of(n, lid)]

    def _order_layer_list(self) -> None:
        """The Layers list in the session's order (a removed layer restored in its
        place), its current layer kept, no signal of the moves."""
        lst = self.layer_list
        role = QtCore.Qt.ItemDataRole.UserRole
        current = lst.currentItem().data(role) if lst.currentItem() is not None else None
        was = lst.blockSignals(True)
        try:
            for target, lid in enumerate(self.session.layers):
                row = self.layer_row(lid)
                if row >= 0 and row != target:
                    lst.insertItem(target, lst.takeItem(row))
            if current is not None and self.layer_row(current) >= 0:
                lst.setCurrentRow(self.layer_row(current))
        finally:
            lst.blockSignals(was)

    def layer_row(self, lid: str) -> int:
        """Row of layer ``lid`` in the Layers list (-1 when absent)."""
        for r in range(self.layer_list.count()):
            if self.layer_list.item(r).data(QtCore.Qt.ItemDataRole.UserRole) == lid:
                return r
        return -1

    def layer_id(self, name: str) -> str | None:
        """The first layer with display name ``name`` (tests and scripts)."""
        return next((i for i, lay in self.session.layers.items() if lay.name == name), None)

    def select_layer(self, lid: str) -> None:
        """Make ``lid`` the active layer, as a click in the Layers list does."""
        row = self.layer_row(lid)
        if row >= 0:
            # Only this layer selected: a step's new layer must not join the layers
            # selected before it (Run ▸ Fuse takes the selection).
            flag = QtCore.QItemSelectionModel.SelectionFlag.ClearAndSelect
            self.layer_list.setCurrentRow(row, flag)

    def remove_active_layer(self) -> None:
        """Layer ▸ Remove: the active layer leaves the session (and the project), undoably
        (Edit ▸ Restore removed layer: :mod:`~wakeline.app.layer_undo`), so no question is
        asked first, children or review decisions or not: an undo brings back the layer,
        its lineage and side tables, and its decisions were never deleted. A layer under
        review made from it keeps the points its proposals were made on (the core does,
        :func:`~wakeline.core.review_session.keep_inputs`): the log says which, and the
        review binds in this window and after a reopen alike."""
        lid = self.active
        if lid is None or lid not in self.session.layers:
            return
        from wakeline.core.review_session import review_dependents

        name = self.session.layers[lid].name
        children, decisions = self.removal_cost(lid)
        try:
            kept = [lay.name for lay in review_dependents(self.session, lid)]
            self.layer_undo.remove(lid)
        except (InputError, KeyError, TypeError, ValueError) as exc:  # never into Qt's loop
            self.log_message(f"{self.tr('Error')}: {name}: {exc}")
            return
        parts = []
        if children:
            parts.append(self.tr("{0} layer(s) were made from it").format(children))
        if decisions:
            parts.append(self.tr("it carries {0} review decision(s)").format(decisions))
        said = f" ({'; '.join(parts)})" if parts else ""
        self.log_message(
            self.tr("Removed layer {0}{1}; Edit ▸ Restore removed layer brings it back").format(
                shown_name(name), said
            )
        )
        if kept:
            self.log_message(
                self.tr(
                    "Removed layer {0}; the review of {1} keeps the points its proposals "
                    "were made on (in the project): its decisions stay"
                ).format(name, "; ".join(kept))
            )

    def removal_cost(self, lid: str) -> tuple[int, int]:
        """What removing layer ``lid`` touches: (layers made from it, review decisions
        made on its queues); the log says them (an undo restores the layer)."""
        children = sum(
            1
            for lay in self.session.layers.values()
            if lay.id != lid and (lay.parent == lid or lid in (lay.inputs or ()))
        )
        decisions = sum(
            1
            for d in self.session.decisions
            if isinstance(d, dict) and str(d.get("queue", "")).split("@")[0] == lid
        )
        return children, decisions

    def _layer_item_changed(self, item: QtWidgets.QListWidgetItem) -> None:
        lid = item.data(QtCore.Qt.ItemDataRole.UserRole)
        if lid in self.session.layers:
            visible = item.checkState() == QtCore.Qt.CheckState.Checked
            self.session.set_visible(lid, visible)

    def _layer_current_changed(self, current, _previous) -> None:
        self.set_active(current.data(QtCore.Qt.ItemDataRole.UserRole) if current else None)

    def set_active(self, lid: str | None) -> None:
        """Make ``lid`` the layer the batch table, statistics and steps work on."""
        self.active = lid if lid in self.session.layers else None
        self.activeChanged.emit()
        # The session keeps it (the project writes it); its selection keeps only this
        # layer's tracks, selected again in the table below (_reselect).
        self.session.set_active(self.active)
        if self.canvas.selected_points() is not None and len(self.canvas.selected_points()):
            self.canvas.show_selection(EMPTY)
        self.detail.clear()
        view = self.views.get(self.active) if self.active else None
        from wakeline.app.display_zone import apply_zone

        apply_zone(self)  # this layer's data may have come in another zone (View ▸ Time zone)
        if view is not None:
            self.batch_model.set_summary(view.summary, view.text, view.extra.get("table_index"))
        else:
            self.batch_model.set_summary(batch_summary(EMPTY))
        self._fit_time_columns()
        if view is not None:
            # The detection limit depends on the raw sampling: take it from the source
            # layer, except for a fused layer, whose points are a sampling of their own
            # (a 1 s radar fused on a 30 s AIS's times is a 30 s track: h168 D-gui-2).
            layer = self.session.get(self.active)
            own = layer is not None and layer.kind in OWN_SAMPLING_KINDS
            source = layer if own else self.session.root(self.active)
            root = view if own else self.views.get(source.id, view)
            self.params.show_guidance(root.summary, root.points, _guide_key(source, root))
        layer = self.session.get(self.active)
        if view is not None and layer.kind == BEARING_KIND and self.bearings is not view.points:
            self.show_bearing_layer(view)  # its map and detections in the dock
        self._update_stats()
        # The map tells the active layer apart: on top, the others dimmed, its tracks
        # each in its own colour (View ▸ Colour by track), labelled; the last one's back
        # in its layer colour.
        self._emphasize()
        for other in list(self.session.layers):
            self._restyle(other)
        self._labels_later()
        points_action = getattr(self, "actions_", {}).get("draw_points")
        if points_action is not None:
            want = self._wanted_style(self.active) if self.active else None
            points_action.blockSignals(True)
            points_action.setEnabled(want is not None and want[1] is not None)
            points_action.setChecked(bool(want and want[1]))
            points_action.blockSignals(False)

    def _refresh_active(self, lid: str) -> bool:
        """The active layer's points replaced with the same tracks (a review decision
        relabels targets): the batch table's cells are updated in place, so its selection
        is kept, and the map's selection and the Detail panel are drawn again only when
        the selected tracks' points changed in more than their target; before, each
        decision cleared them, reset the table and selected its rows again (the map's
        selection and the Detail plots drawn twice). False when the tracks differ (or a
        bearing layer): :meth:`set_active` does the whole."""
        view = self.views.get(lid)
        layer = self.session.get(lid)
        if view is None or layer is None or layer.kind == BEARING_KIND:
            return False
        if not self.batch_model.update_summary(
            view.summary, view.text, view.extra.get("table_index")
        ):
            return False
        self.show_name_columns()  # a vessel table's names joined (the same tracks)
        root = self.session.root(lid)
        if layer.kind in OWN_SAMPLING_KINDS or root is None or root.id == lid:
            # its own sampling changed (set_active)
            self.params.show_guidance(view.summary, view.points, _guide_key(layer, view))
        keys = self.selected_keys()
        if keys and not _same_but_targets(view.tracks(keys), self.canvas.selected_points()):
            self._selecting = True  # the selection drawn from the new points (kept)
            try:
                self._table_selection_changed()
            finally:
                self._selecting = False
        self._update_stats()
        return True

    def _fit_time_columns(self) -> None:
        """The batch table's first columns (Sensor … End) as wide as their longest text
        or title (font metrics of one string per column, not a pass over the rows): Start
        was cut to "2024-01-0 00:00:0" at the default width, and Sensor and Points took
        100 px for "S1" and "16"."""
        view, model = self.batch_view, self.batch_model
        header = view.horizontalHeader()
        style = view.style()
        margin = 2 * (style.pixelMetric(QtWidgets.QStyle.PixelMetric.PM_FocusFrameHMargin) + 1)
        fm = view.fontMetrics()
        for col, (key, _title) in enumerate(model.COLUMNS):
            if key not in FITTED_COLUMNS:
                continue
            widest = max((fm.horizontalAdvance(t) for t in model.wide_texts(key)), default=0)
            text = widest + margin + 6
            view.setColumnWidth(col, max(text, header.sectionSizeHint(col)))

    def active_layer(self) -> Layer | None:
        return self.session.get(self.active)

    # -- how the map tells ships and layers apart (h227) ------------------------------

    def map_option(self, key: str, default: bool) -> bool:
        """A View menu choice kept in the settings (``default`` when never set)."""
        value = self.settings.value(key, default)
        return value if isinstance(value, bool) else str(value).lower() in ("true", "1")

    def set_color_by_track(self, on: bool) -> None:
        """View ▸ Colour by track: the active layer's tracks each in its own colour (when
        it has at most :data:`~wakeline.app.map_draw.TRACK_COLORS_MAX`); kept in the
        settings."""
        self.settings.setValue(COLOR_BY_TRACK_KEY, bool(on))
        for lid in list(self.session.layers):
            self._restyle(lid)

    def set_show_removed(self, on: bool) -> None:
        """View ▸ Show points removed by cleaning: each cleaned layer's ``rejected`` rows
        as × markers coloured by rule; kept in the settings."""
        self.settings.setValue(SHOW_REMOVED_KEY, bool(on))
        for lid in list(self.session.layers):
            self._update_removed(lid)

    def set_draw_as_points(self, on: bool) -> None:
        """View ▸ Draw active layer as points: this layer's detections as dots (radar
        plots: the default for a layer that looks like plots) or joined as lines."""
        if self.active is None:
            return
        if not hasattr(self, "_draw_points"):
            self._draw_points: dict[str, bool] = {}
        self._draw_points[self.active] = bool(on)
        self._restyle(self.active)

    def _wanted_style(self, lid: str) -> tuple[bool, bool | None] | None:
        """(by track, as points) the map should draw layer ``lid`` with; as points None:
        not a choice for it (maneuver marks). None: a layer not drawn as tracks."""
        from wakeline.app.map_draw import TRACK_COLORS_MAX

        layer, view = self.session.get(lid), self.views.get(lid)
        if layer is None or view is None or view.draw is None or layer.kind == BEARING_KIND:
            return None
        if layer.kind == "maneuvers":
            return False, None
        by_track = (
            lid == self.active
            and self.map_option(COLOR_BY_TRACK_KEY, True)
            and 1 < view.draw.geometry.n_tracks <= TRACK_COLORS_MAX
        )
        chosen = getattr(self, "_draw_points", {}).get(lid)
        points = bool(view.extra.get("plots")) if chosen is None else chosen
        return by_track, points

    def _restyle(self, lid: str) -> None:
        """Draw layer ``lid`` in the colours and style :meth:`_wanted_style` says: the
        curves are made again in the worker (colour by track, dots or lines) and the
        result swapped in like a new drawing."""
        want = self._wanted_style(lid)
        view = self.views.get(lid)
        if want is None or view is None:
            return
        by_track, points = want
        data = view.draw
        geom = data.geometry
        is_points = data.style.width == 0 and data.style.symbol_size > 0
        if by_track == (geom.plain is not None) and (points is None or points == is_points):
            return
        from wakeline.app.map_colors import track_colors
        from wakeline.app.map_draw import as_points, recolor
        from wakeline.app.map_paths import with_paths

        others = {
            c
            for other, v in self.views.items()
            if other != lid and self.session.get(other) is not None and v.colors
            for c in v.colors
            if self.session.get(other).visible
        }
        palette = track_colors(others)
        width = DRAW_STYLE.get(self.session.get(lid).kind, (0, 1.3))[1] or 1.3

        def job(data=data):
            out = recolor(data, by_track, palette)
            if points is not None:
                out = as_points(out, points)
                if not points and out.style.width != width:
                    import dataclasses

                    out = dataclasses.replace(
                        out, style=dataclasses.replace(out.style, width=width)
                    )
            return with_paths(out)

        def done(result, view=view, data=data) -> None:
            self._styling -= 1
            if result is None or self.views.get(lid) is not view or view.draw is not data:
                return  # the layer was drawn anew meanwhile (it is restyled then)
            view.draw = result
            self._queue_draw(lid)

        self._styling = getattr(self, "_styling", 0) + 1  # drawing until it is swapped in
        self.lod_worker(job, done)

    def _after_swap(self, lid: str) -> None:
        """A layer's drawing swapped into the map: its style, the removed points, the
        active layer's emphasis and labels follow."""
        self._restyle(lid)
        self._update_removed(lid)
        self._emphasize()
        self._labels_later()

    def _emphasize(self) -> None:
        """The map's stacking in the Layers list's order (a layer higher in the list
        drawn over those below it), the active layer's map layers on top of them all
        (View ▸ Keep the active layer on top, the default; else in its place), the
        others dimmed (View: with one layer shown there is nothing to dim)."""
        order = list(reversed(self.session.layers))  # drawn first to drawn last
        if order != getattr(self, "_stacked", None):
            self._stacked = order
            self.canvas.set_layer_order(order, PART_SEP)
        names = self.map_names(self.active) if self.active else None
        self.canvas.set_emphasis(names, lift=self.map_option(ACTIVE_ON_TOP_KEY, True))

    def set_active_on_top(self, on: bool) -> None:
        """View ▸ Keep the active layer on top (of the layer order); kept in the settings."""
        self.settings.setValue(ACTIVE_ON_TOP_KEY, bool(on))
        self._emphasize()

    # -- the operator's colour and order of the layers (SPEC §7) ------------------------

    def _recolor(self, lid: str) -> None:
        """Layer ``lid``'s colour changed (Layers ▸ Colour…, its undo, a script): its
        swatch in the Layers list, and its drawing and legend entries in the colour (the
        prepared arrays recoloured, no new preparing)."""
        from wakeline.app.map_colors import chosen_colors
        from wakeline.app.map_draw import with_colors

        layer, view = self.session.get(lid), self.views.get(lid)
        row = self.layer_row(lid)
        if row >= 0:
            self.layer_list.item(row).setIcon(color_icon(layer.color))
        if view is None or view.draw is None or layer.kind == BEARING_KIND:
            return
        colors = chosen_colors(view.colors, layer.color)
        if colors == view.colors:
            return
        view.draw = with_colors(view.draw, colors)
        full = getattr(self, "_full_views", {}).get(lid)  # View ▸ Sensors' whole view
        if full is not None and full is not view and full.draw is not None:
            full.draw = with_colors(full.draw, chosen_colors(full.colors, layer.color))
        self._queue_draw(lid)

    def choose_layer_color(self, lid: str | None = None) -> None:
        """Layers ▸ Colour…: the operator picks layer ``lid``'s colour (default: the
        active layer's) in a colour dialog; set undoably and saved at once."""
        lid = lid or self.active
        layer = self.session.get(lid)
        if layer is None or layer.kind == BEARING_KIND:
            return
        from PySide6 import QtGui

        title = self.tr("Colour of layer {0}").format(shown_name(layer.name))
        color = QtWidgets.QColorDialog.getColor(QtGui.QColor(layer.color), self, title)
        if color.isValid():
            self.set_layer_color(lid, color.name())

    def set_layer_color(self, lid: str, color: str) -> None:
        """Draw layer ``lid`` in ``color`` (``#rrggbb``), through the layer stack (Edit ▸
        Undo layer colour)."""
        from wakeline.app.layer_undo import ColorLayerCommand

        layer = self.session.get(lid)
        if layer is None or layer.kind == BEARING_KIND:
            return
        try:
            color = check_color(color)
        except InputError as exc:
            self.log_message(f"{self.tr('Error')}: {exc}")
            return
        if color != layer.color or not layer.meta.get(COLOR_CHOSEN):
            self.layer_undo.push(ColorLayerCommand(self, lid, color))

    def move_layer(self, lid: str | None, delta: int) -> None:
        """Layers ▸ Move up (``delta`` -1) / Move down (+1): layer ``lid`` (default: the
        active one) one place up or down the list, the map's stacking with it; undoable."""
        from wakeline.app.layer_undo import MoveLayerCommand

        lid = lid or self.active
        order = list(self.session.layers)
        if lid not in order:
            return
        pos = order.index(lid) + int(delta)
        if 0 <= pos < len(order):
            self.layer_undo.push(MoveLayerCommand(self, lid, pos))

    def _layers_dropped(self, *_args) -> None:
        """Rows dragged to another place of the Layers list: the session's order follows
        on the next turn (Qt may move several rows, one signal each), undoably."""
        if not getattr(self, "_drop_due", False):
            self._drop_due = True
            QtCore.QTimer.singleShot(0, self._take_dropped_order)

    def _take_dropped_order(self) -> None:
        from wakeline.app.layer_undo import MoveLayerCommand, ReorderLayersCommand

        self._drop_due = False
        role = QtCore.Qt.ItemDataRole.UserRole
        shown = [self.layer_list.item(r).data(role) for r in range(self.layer_list.count())]
        order = list(self.session.layers)
        if shown == order:
            return
        if sorted(shown) != sorted(order):
            self._order_layer_list()
            return
        # one layer moved (the common drag): that layer's move; else the whole order
        for lid in order:
            if [i for i in shown if i != lid] == [i for i in order if i != lid]:
                self.layer_undo.push(MoveLayerCommand(self, lid, shown.index(lid)))
                return
        moved = next(i for i, j in zip(shown, order, strict=True) if i != j)
        self.layer_undo.push(ReorderLayersCommand(self, moved, shown))

    def _layer_menu(self, pos) -> None:
        """The Layers list's context menu: Colour…, Move up, Move down, Remove."""
        item = self.layer_list.itemAt(pos)
        if item is None:
            return
        lid = item.data(QtCore.Qt.ItemDataRole.UserRole)
        layer = self.session.get(lid)
        if layer is None:
            return
        order = list(self.session.layers)
        menu = QtWidgets.QMenu(self.layer_list)
        color = menu.addAction(self.tr("&Colour…"))
        color.setEnabled(layer.kind != BEARING_KIND)
        color.triggered.connect(lambda: self.choose_layer_color(lid))
        up = menu.addAction(self.tr("Move &up"))
        up.setEnabled(order.index(lid) > 0)
        up.triggered.connect(lambda: self.move_layer(lid, -1))
        down = menu.addAction(self.tr("Move &down"))
        down.setEnabled(order.index(lid) < len(order) - 1)
        down.triggered.connect(lambda: self.move_layer(lid, 1))
        menu.addSeparator()
        remove = menu.addAction(self.tr("&Remove"))
        remove.triggered.connect(lambda: (self.select_layer(lid), self.remove_active_layer()))
        self._layer_context_menu = menu  # tests look at it
        menu.popup(self.layer_list.viewport().mapToGlobal(pos))

    def _update_removed(self, lid: str) -> None:
        """The removed-points overlay of layer ``lid`` drawn, made (in the worker) or
        taken away, as View ▸ Show points removed by cleaning says."""
        layer, view = self.session.get(lid), self.views.get(lid)
        name = f"{lid}{PART_SEP}{REMOVED_PART}"
        table = layer.tables.get("rejected") if layer is not None else None
        want = (
            layer is not None
            and view is not None
            and view.draw is not None
            and table is not None
            and len(table) > 0
            and self.map_option(SHOW_REMOVED_KEY, False)
        )
        if not hasattr(self, "_removed_drawn"):
            self._removed_drawn: dict[str, tuple] = {}
        if not want:
            if name in self.canvas.layer_names():
                self.canvas.remove_layer(name)
            return
        cached = self._removed_drawn.get(lid)
        if cached is not None and cached[0] is table:
            # drawn anew when absent, or drawn from another table (points restored)
            shown = getattr(self, "_removed_shown", {})
            stale = name not in self.canvas.layer_names() or shown.get(lid) is not table
            if stale and cached[1] is not None:
                self.canvas.set_draw_data(cached[1], layer.visible)
                self._removed_shown = {**shown, lid: table}
                self._emphasize()
            return
        from wakeline.app.map_draw import rejected_layer
        from wakeline.app.map_paths import with_paths

        west = view.draw.geometry.lon_west
        label = shown_name(layer.name)

        def job():
            data = rejected_layer(table, name, west)
            if data is None:
                return None
            import dataclasses

            # the geometry's labels too: a new level of detail makes the curves from them
            geometry = dataclasses.replace(
                data.geometry, labels=tuple(f"{label} · {t}" for t in data.geometry.labels)
            )
            curves = tuple(
                dataclasses.replace(c, label=f"{label} · {c.label}") for c in data.curves
            )
            return with_paths(dataclasses.replace(data, geometry=geometry, curves=curves))

        def done(result) -> None:
            self._styling -= 1
            self._removed_drawn[lid] = (table, result)
            if self.session.get(lid) is layer and result is not None:
                self._update_removed(lid)

        self._removed_drawn[lid] = (table, None)  # asked for
        self._styling = getattr(self, "_styling", 0) + 1
        self.lod_worker(job, done)

    # -- track labels ------------------------------------------------------------------

    def _labels_later(self) -> None:
        """Place the active layer's track labels once the map's view rests."""
        if not hasattr(self, "_labels_timer"):
            from wakeline.app.map_labels import TrackLabels

            self.track_labels = TrackLabels(self.canvas)
            self._labels_timer = QtCore.QTimer(self)
            self._labels_timer.setSingleShot(True)
            self._labels_timer.setInterval(LABELS_MS)
            self._labels_timer.timeout.connect(self.update_track_labels)
            self.canvas.vb.sigRangeChanged.connect(lambda *_: self._labels_timer.start())
            self.canvas.vb.sigResized.connect(lambda *_: self._labels_timer.start())
            overlay = getattr(getattr(self, "time_controller", None), "overlay", None)
            if overlay is not None:
                overlay.drawn.connect(lambda _t: self._labels_timer.start())
        self._labels_timer.start()

    def update_track_labels(self) -> list[str]:
        """The active layer's track labels (batch, and the ship's name where the file
        has one) beside its Positions markers while Positions is on, else at each track's
        last point; decluttered (:mod:`~wakeline.app.map_labels`). Returns the texts."""
        labels = getattr(self, "track_labels", None)
        if labels is None:
            return []
        lid = self.active
        layer, view = self.session.get(lid), self.views.get(lid) if lid else None
        if (
            layer is None
            or view is None
            or layer.kind in (BEARING_KIND, "maneuvers")
            or not layer.visible
            or lid not in self.canvas.layer_names()
        ):
            labels.clear()
            return []
        from wakeline.app.map_labels import NAME_COLUMNS, position_at

        geom = self.canvas.draw_data(lid).geometry
        overlay = getattr(getattr(self, "time_controller", None), "overlay", None)
        t = overlay._last[0] if overlay is not None and overlay._last is not None else None
        positions = (
            t is not None
            and overlay.markers.isVisible()
            and self.time_panel.overlay_on()
            and geom.n_tracks <= LABEL_TRACKS_MAX
        )
        if positions:
            rows, alive = position_at(geom.time_s, geom.starts, geom.ends, t)
        else:
            rows, alive = geom.ends - 1, np.ones(geom.n_tracks, dtype=bool)
        lon = np.where(alive, geom.lon[rows] if len(rows) else rows, np.nan)
        lat = np.where(alive, geom.lat[rows] if len(rows) else rows, np.nan)
        if positions and len(rows):  # between its fixes, as the marker is drawn
            nxt = np.minimum(rows + 1, geom.ends - 1)
            dt = geom.time_s[nxt] - geom.time_s[rows]
            with np.errstate(divide="ignore", invalid="ignore"):
                f = np.where(dt > 0, np.clip((t - geom.time_s[rows]) / dt, 0.0, 1.0), 0.0)
            lon = lon + f * (geom.lon[nxt] - geom.lon[rows])
            lat = lat + f * (geom.lat[nxt] - geom.lat[rows])
        # only the tracks whose label point is in view get a text (thousands of tracks:
        # none at all past the limit, decided with numpy before any text is made)
        from wakeline.app.map_labels import LABEL_LIMIT

        (x0, x1), (y0, y1) = self.canvas.vb.viewRange()
        inside = np.flatnonzero((lon >= x0) & (lon <= x1) & (lat >= y0) & (lat <= y1))
        if len(inside) == 0 or len(inside) > LABEL_LIMIT:
            labels.clear()
            return []
        name_col = next((c for c in NAME_COLUMNS if c in view.points.columns), None)
        texts, colors = [], []
        for k in inside:
            text = str(geom.batch[k])
            if name_col is not None:
                rng = view.ranges.get((str(geom.sensor[k]), str(geom.batch[k])))
                if rng is not None:
                    ship = view.points[name_col].iloc[rng[0]]
                    if isinstance(ship, str) and ship.strip():
                        text = f"{text} {ship.strip()}"
            texts.append(text)
            colors.append(geom.colors[int(geom.group[k])] if len(geom.colors) else "#000")
        return labels.show(lon[inside], lat[inside], texts, colors)


def _same_but_targets(a: pd.DataFrame | None, b: pd.DataFrame | None) -> bool:
    """Whether two tracks' points are the same but for their ``target`` (the map's
    selection and the Detail panel, which do not show it, need no new drawing)."""
    if a is None or b is None or len(a) != len(b) or list(a.columns) != list(b.columns):
        return False
    for col in a.columns:  # column by column in numpy (DataFrame.equals took ~10 ms)
        if col == "target":
            continue
        x, y = a[col].to_numpy(), b[col].to_numpy()
        if x is y:
            continue
        if x.dtype != y.dtype:
            return False
        if x.dtype.kind == "f":
            if not np.array_equal(x, y, equal_nan=True):
                return False
        elif not np.array_equal(x, y):  # NaT or None unequal: drawn again, as before
            return False
    return True


def _guide_key(layer, view) -> tuple:
    """The parameter panel's key for a layer's guidance (its preset suggestion is computed
    once per key): the layer's id and run, and its points' length (a review decision
    replaces them with the same tracks)."""
    return (layer.id, layer.run, len(view.points))

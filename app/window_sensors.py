"""View ▸ Sensors: one sensor's tracks of a layer hidden from the window (a layer of
radar and AIS, of radar and lidar).

A view filter, kept per layer: the layer's points (what the steps, the export and the
project see) are untouched; the window shows a view prepared from the points of the
sensors shown (:func:`~wakeline.app.layer_view.prepare_view`, in the map's worker), so
the map, the hover and pick, the labels and the batch table leave the hidden sensors'
tracks out (their rows are filtered out of the table, not greyed), and the status bar
counts what is shown of the layer. Each sensor keeps its colour.
"""

import numpy as np
import pandas as pd
from PySide6 import QtWidgets

from wakeline.app.layer_names import shown_name
from wakeline.core.session import BEARING_KIND

#: The key of a filtered view's hidden sensors in ``LayerView.extra``.
HIDDEN_KEY = "sensors_hidden"


def layer_sensors(points: pd.DataFrame) -> list[str]:
    """The sensors of a layer's points, sorted as the map colours them."""
    if "sensor" not in points.columns or not len(points):
        return []
    return [str(s) for s in np.unique(pd.unique(points["sensor"]).astype(str))]


def sensor_colors(view) -> dict[str, str]:
    """Each sensor's colour in a layer's (unfiltered) view: sorted sensors take the
    view's colours in turn (:func:`~wakeline.app.map_draw.layer_geometry`)."""
    colors = view.colors if view is not None else ()
    if not colors or view.draw is None:
        return {}
    names = sorted({str(s) for s in view.draw.geometry.sensor})
    return {s: colors[k % len(colors)] for k, s in enumerate(names)}


class SensorsMixin:
    """The window's per-layer sensor filter (a mixin of :class:`MainWindow`)."""

    TR_CONTEXT = "MainWindow"

    def install_sensor_menu(self) -> None:
        """View ▸ Sensors of the active layer: a checkable entry per sensor."""
        self.sensor_menu = QtWidgets.QMenu(self)
        self.sensor_menu.aboutToShow.connect(self._fill_sensor_menu)
        self.menus["view"].insertMenu(self.actions_["color_by_track"], self.sensor_menu)
        self.hidden_sensors: dict[str, frozenset[str]] = {}
        self._full_views: dict = {}  # lid -> the layer's unfiltered view
        self._filtering: set[str] = set()  # layers whose filtered view is being prepared
        self.retranslate_sensor_menu()

    def retranslate_sensor_menu(self) -> None:
        self.sensor_menu.setTitle(self.tr("&Sensors of the active layer"))
        self._fill_sensor_menu()

    def _fill_sensor_menu(self) -> None:
        menu = self.sensor_menu
        menu.clear()
        layer = self.session.get(self.active) if self.active else None
        sensors = layer_sensors(layer.points) if layer is not None else []
        if layer is None or layer.kind == BEARING_KIND or len(sensors) < 2:
            note = menu.addAction(self.tr("(the active layer has one sensor)"))
            note.setEnabled(False)
            menu.menuAction().setEnabled(layer is not None)
            return
        hidden = self.hidden_sensors.get(layer.id, frozenset())
        shown = [s for s in sensors if s not in hidden]
        for k, sensor in enumerate(sensors):
            # "&1 AIS": a digit each (the sensors' own names may share letters)
            label = self.tr("Show {0}").format(sensor.replace("&", "&&"))
            act = menu.addAction(f"&{k + 1} {label}" if k < 9 else label)
            act.setToolTip(
                self.tr(
                    "Show or hide the tracks of sensor {0} (a view filter: the layer's "
                    "points are not changed)"
                ).format(sensor)
            )
            act.setCheckable(True)
            act.setChecked(sensor not in hidden)
            # the last sensor shown stays shown (hide the layer in the Layers list)
            act.setEnabled(not (sensor in shown and len(shown) == 1))
            act.toggled.connect(
                lambda on, lid=layer.id, s=sensor: self.set_sensor_shown(lid, s, on)
            )
        menu.addSeparator()
        every = menu.addAction(self.tr("Show &all sensors"))
        every.setEnabled(bool(hidden))
        every.triggered.connect(lambda _=False, lid=layer.id: self.show_all_sensors(lid))
        menu.menuAction().setEnabled(True)

    def set_sensor_shown(self, lid: str, sensor: str, on: bool) -> None:
        """Show or hide ``sensor``'s tracks of layer ``lid`` (the last one shown stays)."""
        layer = self.session.get(lid)
        if layer is None:
            return
        hidden = set(self.hidden_sensors.get(lid, frozenset()))
        (hidden.discard if on else hidden.add)(str(sensor))
        if not [s for s in layer_sensors(layer.points) if s not in hidden]:
            return
        self._set_hidden(lid, frozenset(hidden))

    def show_all_sensors(self, lid: str) -> None:
        self._set_hidden(lid, frozenset())

    def _set_hidden(self, lid: str, hidden: frozenset) -> None:
        if hidden == self.hidden_sensors.get(lid, frozenset()):
            return
        if hidden:
            self.hidden_sensors[lid] = hidden
        else:
            self.hidden_sensors.pop(lid, None)
        self._queue_draw(lid)

    def sensor_filter_pending(self, lid: str) -> bool:
        """Called before layer ``lid`` is drawn: True when its view must first be
        prepared again for the sensors shown (the job then queues the drawing)."""
        view = self.views.get(lid)
        layer = self.session.get(lid)
        if view is None or layer is None or layer.kind == BEARING_KIND:
            return False
        want = self.hidden_sensors.get(lid, frozenset())
        have = view.extra.get(HIDDEN_KEY, frozenset())
        if want == have:
            return False
        if lid in self._filtering:
            return True
        full = view if not have else self._full_views.get(lid)
        if full is None or full.points is not layer.points:
            full = None  # the layer changed: its whole view is made again below
        if not have:
            self._full_views[lid] = view
        if not want and full is not None:  # every sensor shown again: the whole view back
            self.views[lid] = full
            self._full_views.pop(lid, None)
            self._after_filter(lid)
            return False
        self._start_filter(lid, layer, full, want)
        return True

    def _start_filter(self, lid: str, layer, full, hidden: frozenset) -> None:
        from wakeline.app.layer_view import prepare_view

        colors = sensor_colors(full) if full is not None else {}
        points = layer.points
        view, size_px = self.canvas.current_view(), self.canvas.plot_size_px()
        kind, color, name = layer.kind, layer.color, layer.name

        def job(points=points):
            sensors = points["sensor"].astype(str)
            pts = points[~sensors.isin(hidden).to_numpy()] if hidden else points
            if hidden and not len(pts):
                # its points changed (a step re-run in place) to the hidden sensors' only:
                # shown whole, the choice dropped (the menu of one sensor has no way back)
                pts = points
            shown = layer_sensors(pts)
            own = tuple(colors[s] for s in shown if s in colors) if colors else None
            lv = prepare_view(
                pts,
                kind,
                color,
                name,
                view,
                size_px,
                colors=own if own and len(own) == len(shown) and kind == "source" else None,
            )
            lv.extra[HIDDEN_KEY] = hidden if pts is not points else frozenset()
            lv.extra["points_all"] = len(points)
            lv.extra["choice_dropped"] = bool(hidden) and pts is points
            return lv

        def done(result, points=points) -> None:
            self._filtering.discard(lid)
            layer_now = self.session.get(lid)
            if layer_now is None:
                return
            if result is None and layer_now.points is points:
                # the preparation failed (logged): shown whole, not tried again and again
                if self.hidden_sensors.pop(lid, None):
                    self.log_message(
                        self.tr(
                            "{0}: the view without sensors {1} could not be made; shown whole"
                        ).format(shown_name(name), ", ".join(sorted(hidden)))
                    )
                self._queue_draw(lid)
                return
            if result is None or layer_now.points is not points:
                self._queue_draw(lid)  # changed meanwhile: filtered again from it
                return
            whole = result.extra.pop("choice_dropped", False)
            if whole and self.hidden_sensors.get(lid) == hidden:
                self.hidden_sensors.pop(lid, None)  # every sensor of its points was hidden
            if result.extra.get(HIDDEN_KEY) != self.hidden_sensors.get(lid, frozenset()):
                self._queue_draw(lid)  # another choice made meanwhile
                return
            if whole:
                self._full_views.pop(lid, None)  # this one is whole
            elif lid not in self._full_views and lid in self.views:
                self._full_views[lid] = self.views[lid]
            self.views[lid] = result
            self._after_filter(lid)

        self._filtering.add(lid)
        self.lod_worker(job, done)

    def _after_filter(self, lid: str) -> None:
        """A layer's view swapped for its sensors shown: drawn, and the batch table,
        labels and counts follow when it is the active layer; the time slider's markers
        and trails too (its index was made over the view before: a hidden sensor's
        position stayed on the map, operator test 11)."""
        self._queue_draw(lid)
        self.layersChanged.emit()
        if lid == self.active:
            self._make_current = lid
        self.show_counts()

    def sensors_note(self, layer) -> str:
        """The status bar's note of a layer's hidden sensors ("" when none)."""
        hidden = self.hidden_sensors.get(layer.id) if layer is not None else None
        if not hidden:
            return ""
        return self.tr("sensors hidden: {0}").format(", ".join(sorted(hidden)))

    def shown_points(self, layer) -> int:
        """Points of ``layer`` the window shows (its sensors shown)."""
        view = self.views.get(layer.id)
        if view is not None and view.extra.get(HIDDEN_KEY):
            return len(view.points)
        return len(layer.points)

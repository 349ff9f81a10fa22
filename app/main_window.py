"""The main window: map in the centre; Layers, Parameters, Batch table, Statistics,
Detail and Log panels around it.

The window is a view and controller over a :class:`wakeline.core.session.Session`: the
session owns the layers (by id, with lineage); the window draws what the session says.
Slow work never runs on the GUI thread: importing, hashing, steps, preparing the arrays
for drawing and the batch table (:mod:`wakeline.app.layer_view`) run in the worker
(:mod:`wakeline.app.jobs`), and the project file is written by a background writer
(:mod:`wakeline.app.project_controller`). The GUI thread swaps finished data in.
"""

from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtWidgets

from wakeline.app import i18n
from wakeline.app.actions import build_actions, retranslate
from wakeline.app.bearing_view import BearingView
from wakeline.app.detail import DetailPanel
from wakeline.app.dialogs import ImportReportDialog
from wakeline.app.import_dialog import ImportDialog
from wakeline.app.jobs import JobsMixin, preload
from wakeline.app.layer_view import LayerView, draw_as, maneuver_table, prepare_view
from wakeline.app.lod_worker import LodWorker
from wakeline.app.map_canvas import MapCanvas, color_icon
from wakeline.app.models import BatchTableModel, batch_summary
from wakeline.app.params_panel import ParamsPanel
from wakeline.app.project_controller import ProjectController
from wakeline.app.review_dock import ReviewDock
from wakeline.app.time_panel import install_time
from wakeline.app.worker import JobRunner
from wakeline.core.session import Layer, Session
from wakeline.resources import coastline_path

EMPTY = pd.DataFrame(columns=["sensor", "batch", "time", "lon", "lat"])


def format_dms(value: float, positive: str, negative: str) -> str:
    """Degrees as D°MM'SS.s" with a hemisphere letter."""
    hemi = positive if value >= 0 else negative
    v = abs(value)
    d = int(v)
    m = int((v - d) * 60)
    s = (v - d - m / 60) * 3600
    return f"{d}°{m:02d}'{s:04.1f}\"{hemi}"


class MainWindow(JobsMixin, QtWidgets.QMainWindow):
    """Wakeline's main window."""

    layersChanged = QtCore.Signal()

    def __init__(self, settings: QtCore.QSettings | None = None) -> None:
        super().__init__()
        self.settings = settings or QtCore.QSettings("Wakeline", "Wakeline")
        preload()
        self.session = Session()
        self.views: dict[str, LayerView] = {}
        self.active: str | None = None
        self.translator = None
        self.language = "en"
        self.runner = JobRunner(self)
        self.runner.message.connect(self._on_job_message)
        self._job_context: dict[int, tuple] = {}
        self._selecting = False
        self._pending_views: dict = {}
        self._draw_queue: list[str] = []
        self._make_current: str | None = None
        self._restore_selection: list | None = None
        self._fit_after_draw = False
        self.project = ProjectController(self.session, self)
        self.project.failed.connect(self._save_failed)
        self.session.subscribe(self._on_session_event)

        self.canvas = MapCanvas(self)
        self.lod_worker = LodWorker(self)
        self.canvas.lod_executor = self.lod_worker
        self.setCentralWidget(self.canvas)
        try:
            coast = np.load(coastline_path())
            self.canvas.set_coastline(
                coast["lon"].astype("float64"), coast["lat"].astype("float64")
            )
        except OSError:
            pass
        self.canvas.cursorMoved.connect(self._show_cursor)
        self.canvas.trackClicked.connect(self._track_clicked)
        self.canvas.pointHovered.connect(self._show_hover)
        self.time_controller = install_time(self)  # slider under the map: self.time_panel

        self.layer_list = QtWidgets.QListWidget()
        self.layer_list.itemChanged.connect(self._layer_item_changed)
        self.layer_list.currentItemChanged.connect(self._layer_current_changed)
        self.params = ParamsPanel()
        self.params.changed.connect(lambda _k: self.project.put_params(self.params.to_dict()))
        self.params.refused.connect(lambda text: self.log_message(f"{self.tr('Refused')}: {text}"))
        self.batch_model = BatchTableModel(self)
        self.batch_view = QtWidgets.QTableView()
        self.batch_view.setModel(self.batch_model)
        self.batch_view.setSortingEnabled(True)
        behavior = QtWidgets.QAbstractItemView
        self.batch_view.setSelectionBehavior(behavior.SelectionBehavior.SelectRows)
        self.batch_view.setSelectionMode(behavior.SelectionMode.ExtendedSelection)
        self.batch_view.verticalHeader().setVisible(False)
        self.batch_view.setAlternatingRowColors(True)
        header = self.batch_view.horizontalHeader()
        header.setStretchLastSection(True)
        header.setResizeContentsPrecision(50)  # size columns from 50 rows, not all
        self.batch_view.selectionModel().selectionChanged.connect(self._table_selection_changed)
        self.filter_edit = QtWidgets.QLineEdit()
        self.filter_edit.setClearButtonEnabled(True)
        self.filter_edit.textChanged.connect(self.batch_model.set_filter)
        batch_box = QtWidgets.QWidget()
        bl = QtWidgets.QVBoxLayout(batch_box)
        bl.setContentsMargins(2, 2, 2, 2)
        bl.addWidget(self.filter_edit)
        bl.addWidget(self.batch_view)
        self.stats = QtWidgets.QPlainTextEdit(readOnly=True)
        self.detail = DetailPanel()
        self.bearing_view = BearingView()
        self.log = QtWidgets.QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(5000)
        self._build_docks(batch_box)

        self.progress = QtWidgets.QProgressBar()
        self.progress.setMaximumWidth(260)
        self.progress.setRange(0, 1000)
        self.progress.hide()
        self.cancel_button = QtWidgets.QToolButton()
        self.cancel_button.clicked.connect(self.runner.cancel)
        self.cancel_button.hide()
        self.cursor_label = QtWidgets.QLabel()
        for widget in (self.progress, self.cancel_button, self.cursor_label):
            self.statusBar().addPermanentWidget(widget)

        build_actions(self)
        self.review = ReviewDock(self)  # the review dock, its menus and the before map
        self.set_language(self.settings.value("language", i18n.system_language()))
        for key, restore in (("geometry", self.restoreGeometry), ("state", self.restoreState)):
            value = self.settings.value(key)
            if value is not None:
                restore(value)

    def _build_docks(self, batch_box: QtWidgets.QWidget) -> None:
        area = QtCore.Qt.DockWidgetArea
        self.docks = {}
        for key, widget, where in (
            ("layers", self.layer_list, area.LeftDockWidgetArea),
            ("params", self.params, area.LeftDockWidgetArea),
            ("batches", batch_box, area.RightDockWidgetArea),
            ("detail", self.detail, area.RightDockWidgetArea),
            ("bearing", self.bearing_view, area.RightDockWidgetArea),
            ("stats", self.stats, area.BottomDockWidgetArea),
            ("log", self.log, area.BottomDockWidgetArea),
        ):
            dock = QtWidgets.QDockWidget(self)
            dock.setObjectName(key)
            dock.setWidget(widget)
            self.addDockWidget(where, dock)
            self.docks[key] = dock
        self.tabifyDockWidget(self.docks["stats"], self.docks["log"])
        self.tabifyDockWidget(self.docks["detail"], self.docks["bearing"])
        self.docks["detail"].raise_()
        self.docks["log"].raise_()
        d = self.docks
        horizontal, vertical = QtCore.Qt.Orientation.Horizontal, QtCore.Qt.Orientation.Vertical
        self.resizeDocks([d["layers"], d["batches"]], [300, 560], horizontal)
        self.resizeDocks(
            [d["layers"], d["params"], d["batches"], d["detail"], d["log"]],
            [150, 450, 420, 260, 130],
            vertical,
        )

    # -- texts ---------------------------------------------------------------------

    def retranslate(self) -> None:
        """Set every visible text (called again when the language changes)."""
        title = self.tr("Wakeline")
        if self.project.path is not None:
            title += f" — {self.project.path.name}"
            if self.project.read_only:
                title += " " + self.tr("[read-only]")
            if self.project.dirty:
                title += " " + self.tr("[not saved]")
        self.setWindowTitle(title)
        retranslate(self)
        self.detail.retranslate()
        self.params.retranslate()
        self.canvas.setLabel("bottom", self.tr("longitude"), units="°")
        self.canvas.setLabel("left", self.tr("latitude"), units="°")
        self._update_stats()

    def set_language(self, code: str) -> None:
        code = code if code in i18n.LANGUAGES else "en"
        app = QtWidgets.QApplication.instance()
        self.translator = i18n.install(app, code, self.translator)
        self.language = code
        self.lang_actions[code].setChecked(True)
        self.settings.setValue("language", code)
        self.retranslate()

    # -- layers (views over the session) -----------------------------------------------

    @property
    def layers(self) -> dict[str, Layer]:
        return self.session.layers

    def open_dialog(self) -> None:
        dialog = ImportDialog(self)
        if dialog.exec() == QtWidgets.QDialog.DialogCode.Accepted:
            self.load_file(**dialog.options())

    def _on_session_event(self, event: str, lid: str) -> None:
        layer = self.session.layers.get(lid)
        if event in ("added", "changed"):
            pending = self._pending_views.pop((layer.step, layer.role), None)
            if pending is not None:
                self.views[lid] = pending
            elif lid not in self.views or event == "changed":
                # A layer added by a script or test: small, prepared here.
                self.views[lid] = prepare_view(layer.points, layer.kind, layer.color)
                layer.points = self.views[lid].points
        if event == "added":
            self._queue_draw(lid)
            item = QtWidgets.QListWidgetItem(
                color_icon(layer.color), f"{layer.name}  [{layer.kind}]"
            )
            item.setData(QtCore.Qt.ItemDataRole.UserRole, lid)
            item.setFlags(item.flags() | QtCore.Qt.ItemFlag.ItemIsUserCheckable)
            checked = (
                QtCore.Qt.CheckState.Checked if layer.visible else QtCore.Qt.CheckState.Unchecked
            )
            item.setCheckState(checked)
            self.layer_list.addItem(item)
            self._make_current = lid  # once the drawing queue is through (one per turn)
            if len(self.session.layers) == 1 and len(layer.points):
                self.canvas.set_true_aspect(float(np.nanmean(layer.points["lat"].to_numpy())))
        elif event == "changed":
            self._queue_draw(lid)
            if lid == self.active:
                self._make_current = lid
        elif event == "removed":
            self.canvas.remove_layer(lid)
            self.views.pop(lid, None)
            row = self.layer_row(lid)
            if row >= 0:
                self.layer_list.takeItem(row)
            if not self.session.layers:
                self.set_active(None)
        elif event == "visibility":
            self.canvas.set_visible(lid, layer.visible)
        self.layersChanged.emit()

    def _queue_draw(self, lid: str) -> None:
        """Swap a layer's prepared arrays into the map on a later event-loop turn, one
        layer per turn, so a result of several layers never blocks in one piece."""
        if lid not in self._draw_queue:
            self._draw_queue.append(lid)
        if len(self._draw_queue) == 1:
            QtCore.QTimer.singleShot(0, self._draw_next)

    def _draw_next(self) -> None:
        if self._draw_queue:
            lid = self._draw_queue.pop(0)
            layer = self.session.layers.get(lid)
            if layer is not None and lid in self.views:
                self.canvas.set_draw_data(draw_as(self.views[lid], lid, layer.name), layer.visible)
        if self._draw_queue:
            QtCore.QTimer.singleShot(0, self._draw_next)
            return
        if self._fit_after_draw:
            self._fit_after_draw = False
            self.canvas.fit()
        if self._make_current is not None:
            lid, self._make_current = self._make_current, None
            if lid in self.session.layers:
                if lid == self.active:
                    self.set_active(lid)
                else:
                    self.select_layer(lid)
            self._after_drawn()

    def _after_drawn(self) -> None:
        """Hook run when the queued layers are drawn (a restored selection)."""
        pending, self._restore_selection = self._restore_selection, None
        if pending:
            self._selecting = True
            self.select_tracks(pending)
            self._selecting = False

    @property
    def drawing(self) -> bool:
        """Layers are still waiting to be swapped into the map."""
        return bool(self._draw_queue) or self._make_current is not None

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
            self.layer_list.setCurrentRow(row)

    def show_import_report(self) -> QtWidgets.QDialog | None:
        """The import report of the active layer's source file."""
        if self.active is None:
            return None
        dialog = ImportReportDialog(self.session.root(self.active), self)
        dialog.show()
        return dialog

    def remove_active_layer(self) -> None:
        if self.active is not None:
            self.session.remove_layer(self.active)

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
        view = self.views.get(self.active) if self.active else None
        if view is not None:
            self.batch_model.set_summary(view.summary, view.text)
        else:
            self.batch_model.set_summary(batch_summary(EMPTY))
        if self.canvas.selected_points() is not None and len(self.canvas.selected_points()):
            self.canvas.show_selection(EMPTY)
        self.detail.clear()
        if view is not None:
            # The detection limit depends on the raw sampling: take it from the source layer.
            root = self.views.get(self.session.root(self.active).id, view)
            self.params.show_guidance(root.summary)
        self.project.put_state("active", self.active)
        self._update_stats()

    def active_layer(self) -> Layer | None:
        return self.session.get(self.active)

    # -- selection -----------------------------------------------------------------

    def selected_keys(self) -> list[tuple[str, str]]:
        rows = {i.row() for i in self.batch_view.selectionModel().selectedRows()}
        return [self.batch_model.key_of_row(r) for r in sorted(rows)]

    def select_tracks(self, keys: list[tuple[str, str]], add: bool = False) -> None:
        """Select rows of the batch table by (sensor, batch); the map follows."""
        sel = self.batch_view.selectionModel()
        flags = QtCore.QItemSelectionModel.SelectionFlag
        selection = QtCore.QItemSelection()
        last = None
        for sensor, batch in keys:
            row = self.batch_model.row_of_key(sensor, batch)
            if row is None:
                continue
            idx = self.batch_model.index(row, 0)
            if idx.isValid():
                selection.select(idx, idx)
                last = idx
        mode = flags.Select | flags.Rows
        sel.select(selection, mode if add else mode | flags.Clear)
        if last is not None:
            self.batch_view.scrollTo(last)

    def _table_selection_changed(self, *_args) -> None:
        view = self.views.get(self.active) if self.active else None
        if view is None:
            return
        keys = self.selected_keys()
        chosen = view.tracks(keys)
        self.canvas.show_selection(chosen, maneuver_table(chosen))
        if keys:
            self._show_detail(self.active, keys[0])
        else:
            self.detail.clear()
        if not self._selecting:
            self.session.selection = [(self.active, s, b) for s, b in keys]
            self.project.put_state("selection", self.session.selection)

    def zoom_to_selection(self) -> None:
        self.canvas.zoom_to_selection()

    def export_map_image(self, path: Path | None = None) -> bool:
        """File ▸ Export map image: the map as drawn, offscreen, to PNG."""
        from wakeline.app.map_render import render_png

        if path is None:
            chosen, _ = QtWidgets.QFileDialog.getSaveFileName(
                self, self.tr("Export map image"), "map.png", "PNG (*.png)"
            )
            if not chosen:
                return False
            path = Path(chosen)
        ok = bool(render_png(self.canvas, path))
        text = self.tr("map image written to {0}") if ok else self.tr("map image not written: {0}")
        self.log_message(text.format(path))
        return ok

    def _show_hover(self, info) -> None:
        if info:
            speed = info.get("speed_kn")
            speed_text = "" if speed is None or speed != speed else f", {speed:.1f} kn"
            self.statusBar().showMessage(
                f"{info.get('sensor')} / {info.get('batch')}: {info.get('time')}{speed_text}", 4000
            )

    def _show_detail(self, lid: str, key: tuple[str, str]) -> None:
        view = self.views[lid]
        man = self.session.related(lid, "maneuvers")
        comp = self.session.related(lid, "compressed")
        man_view = self.views.get(man.id) if man is not None else None
        comp_view = self.views.get(comp.id) if comp is not None else None
        factor = (man_view or view).tracks([key])
        threshold = man.meta.get("threshold_deg") if man is not None else None
        compressed = comp_view.tracks([key]) if comp_view is not None else None
        dis = None
        if comp is not None:
            dis = comp.meta.get("dis_e_by_track", {}).get(f"{key[0]}\x1f{key[1]}")
        self.detail.show_track(factor, threshold, compressed, factor, dis_e_m=dis)

    def _track_clicked(self, lid: str, sensor: str, batch: str, add: bool) -> None:
        if lid != self.active:
            self.select_layer(lid)
        self.select_tracks([(sensor, batch)], add=add)

    # -- misc ----------------------------------------------------------------------

    def _update_stats(self) -> None:
        layer = self.active_layer()
        if layer is None:
            self.stats.setPlainText(self.tr("No layer. File ▸ Open tracks… (Ctrl+O)"))
            return
        view = self.views.get(layer.id)
        summary = view.summary if view is not None else batch_summary(EMPTY)
        tracks = len(summary)
        sensors = ", ".join(sorted(summary["sensor"].astype(str).unique())) if tracks else ""
        lines = [
            f"{self.tr('Layer')}: {layer.name} [{layer.kind}]  ({layer.id})",
            f"{self.tr('Points')}: {len(layer.points):,}   {self.tr('Tracks')}: {tracks:,}   "
            f"{self.tr('Sensors')}: {sensors}",
        ]
        if layer.parent:
            parent = self.session.get(layer.parent)
            made = f"{layer.step} ← {parent.name if parent else layer.parent}"
            lines.append(f"{self.tr('Made by')}: {made}, {layer.created}")
        if tracks and view is not None and len(view.text.get("start", [])):
            first = view.text["start"][int(np.argmin(summary["start"].to_numpy()))]
            last = view.text["end"][int(np.argmax(summary["end"].to_numpy()))]
            lines.append(f"{self.tr('Time')}: {first} – {last}")
        for key in ("dis_e_m", "rejected", "threshold_deg"):
            value = layer.meta.get(key)
            if value is not None:
                lines.append(
                    f"{key}: {value:.1f}" if isinstance(value, float) else f"{key}: {value}"
                )
        self.stats.setPlainText("\n".join(lines))
        self.statusBar().showMessage(
            f"{len(layer.points):,} {self.tr('points')}, {tracks:,} {self.tr('tracks')}"
        )

    def log_message(self, text: str) -> None:
        self.log.appendPlainText(text)

    def _show_cursor(self, lon: float, lat: float) -> None:
        self.cursor_label.setText(
            f"{lon:.5f}°, {lat:.5f}°   {format_dms(lat, 'N', 'S')} {format_dms(lon, 'E', 'W')}"
        )

    def _save_failed(self, message: str) -> None:
        text = self.tr("Saving the project failed: {0}").format(message)
        self.log_message(f"{self.tr('Error')}: {text}")
        self.retranslate()
        QtWidgets.QMessageBox.warning(self, self.tr("Project not saved"), text)

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt API
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("state", self.saveState())
        self.runner.cancel()
        self.runner.wait(5000)
        self.review.close()
        self.lod_worker.wait(5000)
        self.project.detach()
        super().closeEvent(event)


__all__ = ["MainWindow", "format_dms", "maneuver_table", "Path"]

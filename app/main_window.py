"""The main window: map in the centre; Layers, Parameters, Batch table, Statistics,
Detail and Log panels around it; pipeline steps run in a worker thread.

The window only adapts the core: layers are :class:`wakeline.core.project.Layer`, steps
are :mod:`wakeline.core.pipeline` functions, export and the project file are core code.
"""

import gzip
import json
from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import i18n
from wakeline.app.detail import DetailPanel
from wakeline.app.map_canvas import PALETTE, MapCanvas, color_icon
from wakeline.app.models import BatchFilterModel, BatchTableModel, FrameModel, batch_summary
from wakeline.app.params_panel import ParamsPanel
from wakeline.app.worker import Cancelled, Failed, Finished, JobRunner, Progress, Started
from wakeline.core import pipeline
from wakeline.core.errors import InputError
from wakeline.core.export import export_csv, export_geojson
from wakeline.core.io import FAMILIES, read_points
from wakeline.core.project import Layer, Project, Source, file_hash, load_project, save_project
from wakeline.core.tracks import sort_points
from wakeline.resources import coastline_path

#: Quarantined rows kept with a source layer (and in the project) for viewing.
QUARANTINE_KEPT = 10_000

KIND_COLORS = {
    "cleaned": "#2ca02c",
    "maneuvers": "#9467bd",
    "compressed": "#d62728",
    "associated": "#ff7f0e",
    "fused": "#17becf",
}


def format_dms(value: float, positive: str, negative: str) -> str:
    """Degrees as D°MM'SS.s" with a hemisphere letter."""
    hemi = positive if value >= 0 else negative
    v = abs(value)
    d = int(v)
    m = int((v - d) * 60)
    s = (v - d - m / 60) * 3600
    return f"{d}°{m:02d}'{s:04.1f}\"{hemi}"


def maneuver_table(points: pd.DataFrame) -> pd.DataFrame | None:
    """Maneuver points of a layer that carries ``is_maneuver`` (else None)."""
    if "is_maneuver" not in points.columns:
        return None
    hit = points["is_maneuver"].to_numpy(dtype=bool)
    out = points.loc[hit, ["sensor", "batch", "time", "lon", "lat"]].copy()
    out["factor"] = points.loc[hit, "maneuver_factor"].to_numpy()
    return out.reset_index(drop=True)


def preview_lines(path: Path, n: int = 12) -> str:
    """The first lines of a file as text (gzip and odd encodings tolerated)."""
    opener = gzip.open if path.suffix == ".gz" else open
    try:
        with opener(path, "rb") as fh:
            raw = b"".join(fh.readline() for _ in range(n))
    except OSError as exc:
        return str(exc)
    for enc in ("utf-8-sig", "gb18030", "latin-1"):
        try:
            return raw.decode(enc)
        except UnicodeDecodeError:
            continue
    return raw.decode("latin-1")


def summarize(report: dict) -> str:
    """A step's report as one readable line (key figures only; nested reports flattened)."""
    parts = []
    for key, value in report.items():
        if isinstance(value, dict):
            if key in ("rules", "params", "tracks_report"):
                continue
            parts.append(f"{key}: [{summarize(value)}]")
        elif isinstance(value, bool):
            continue
        elif isinstance(value, float):
            parts.append(f"{key} {value:,.3g}" if abs(value) < 1 else f"{key} {value:,.1f}")
        elif isinstance(value, int):
            parts.append(f"{key} {value:,}")
        elif isinstance(value, str):
            parts.append(f"{key} {value}")
    return ", ".join(parts)


class ImportDialog(QtWidgets.QDialog):
    """Pick a file; see its first rows; choose the layout, encoding and column mapping."""

    def __init__(self, parent=None, path: Path | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle(self.tr("Import tracks"))
        self.path_edit = QtWidgets.QLineEdit(str(path or ""))
        browse = QtWidgets.QPushButton(self.tr("Browse…"))
        browse.clicked.connect(self._browse)
        self.format_box = QtWidgets.QComboBox()
        self.format_box.addItems(list(FAMILIES))
        self.encoding_box = QtWidgets.QComboBox()
        self.encoding_box.addItems(["auto", "utf-8", "gb18030", "latin-1"])
        self.mapping_edit = QtWidgets.QLineEdit()
        self.mapping_edit.setPlaceholderText("batch=MMSI, time=BaseDateTime, lon=LON, lat=LAT")
        self.sensor_edit = QtWidgets.QLineEdit()
        self.sensor_edit.setPlaceholderText(self.tr("sensor name when the file has none"))
        self.preview = QtWidgets.QPlainTextEdit(readOnly=True)
        self.preview.setLineWrapMode(QtWidgets.QPlainTextEdit.LineWrapMode.NoWrap)
        self.preview.setFont(
            QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        )
        self.path_edit.textChanged.connect(self._update_preview)
        form = QtWidgets.QFormLayout()
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.path_edit, 1)
        row.addWidget(browse)
        form.addRow(self.tr("File"), row)
        form.addRow(self.tr("Layout"), self.format_box)
        form.addRow(self.tr("Encoding"), self.encoding_box)
        form.addRow(self.tr("Column mapping"), self.mapping_edit)
        form.addRow(self.tr("Sensor"), self.sensor_edit)
        buttons = QtWidgets.QDialogButtonBox(
            QtWidgets.QDialogButtonBox.StandardButton.Ok
            | QtWidgets.QDialogButtonBox.StandardButton.Cancel
        )
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        lay = QtWidgets.QVBoxLayout(self)
        lay.addLayout(form)
        lay.addWidget(QtWidgets.QLabel(self.tr("First rows of the file:")))
        lay.addWidget(self.preview, 1)
        lay.addWidget(buttons)
        self.resize(760, 480)
        self._update_preview()

    def _browse(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self,
            self.tr("Open track file"),
            "",
            "Track files (*.csv *.csv.gz *.txt);;All files (*)",
        )
        if path:
            self.path_edit.setText(path)

    def _update_preview(self) -> None:
        p = Path(self.path_edit.text())
        self.preview.setPlainText(preview_lines(p) if p.is_file() else "")

    def options(self) -> dict:
        mapping = [m.strip() for m in self.mapping_edit.text().split(",") if m.strip()]
        enc = self.encoding_box.currentText()
        return {
            "path": Path(self.path_edit.text()),
            "fmt": self.format_box.currentText(),
            "encoding": None if enc == "auto" else enc,
            "mapping": mapping,
            "sensor": self.sensor_edit.text().strip() or None,
        }


class ImportReportDialog(QtWidgets.QDialog):
    """A source layer's import report and its quarantined rows (line, reason, raw text)."""

    def __init__(self, layer: Layer, parent=None) -> None:
        super().__init__(parent)
        self.setWindowTitle(self.tr("Import report: {0}").format(layer.name))
        rep = layer.meta.get("report", {})
        text = QtWidgets.QPlainTextEdit(readOnly=True)
        text.setPlainText(json.dumps(rep, indent=2, ensure_ascii=False, default=str))
        self.table = QtWidgets.QTableView()
        self.table.setModel(FrameModel(pd.DataFrame(layer.meta.get("quarantine", [])), self))
        self.table.horizontalHeader().setStretchLastSection(True)
        lay = QtWidgets.QVBoxLayout(self)
        lay.addWidget(text, 1)
        lay.addWidget(
            QtWidgets.QLabel(
                self.tr("Quarantined rows ({0:,}; the first {1:,} are kept):").format(
                    int(rep.get("rows_quarantined", 0)), QUARANTINE_KEPT
                )
            )
        )
        lay.addWidget(self.table, 2)
        close = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
        close.rejected.connect(self.reject)
        lay.addWidget(close)
        self.resize(900, 600)


class MainWindow(QtWidgets.QMainWindow):
    """Wakeline's main window."""

    layersChanged = QtCore.Signal()

    def __init__(self, settings: QtCore.QSettings | None = None) -> None:
        super().__init__()
        self.settings = settings or QtCore.QSettings("Wakeline", "Wakeline")
        self.layers: dict[str, Layer] = {}
        self.sources: list[Source] = []
        self.active: str | None = None
        self.project_path: Path | None = None
        self.translator = None
        self.language = "en"
        self.runner = JobRunner(self)
        self.runner.message.connect(self._on_job_message)
        self._job_context: dict[int, tuple[str, str]] = {}
        self._selecting = False

        self.canvas = MapCanvas(self)
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

        # Layers
        self.layer_list = QtWidgets.QListWidget()
        self.layer_list.itemChanged.connect(self._layer_item_changed)
        self.layer_list.currentItemChanged.connect(self._layer_current_changed)
        # Parameters
        self.params = ParamsPanel()
        self.params.changed.connect(lambda _k: self.autosave())
        self.params.refused.connect(lambda text: self.log_message(f"{self.tr('Refused')}: {text}"))
        # Batch table
        self.batch_model = BatchTableModel(self)
        self.batch_proxy = BatchFilterModel(self)
        self.batch_proxy.setSourceModel(self.batch_model)
        self.batch_view = QtWidgets.QTableView()
        self.batch_view.setModel(self.batch_proxy)
        self.batch_view.setSortingEnabled(True)
        self.batch_view.setSelectionBehavior(
            QtWidgets.QAbstractItemView.SelectionBehavior.SelectRows
        )
        self.batch_view.setSelectionMode(
            QtWidgets.QAbstractItemView.SelectionMode.ExtendedSelection
        )
        self.batch_view.verticalHeader().setVisible(False)
        self.batch_view.setAlternatingRowColors(True)
        self.batch_view.horizontalHeader().setStretchLastSection(True)
        self.batch_view.selectionModel().selectionChanged.connect(self._table_selection_changed)
        self.filter_edit = QtWidgets.QLineEdit()
        self.filter_edit.setClearButtonEnabled(True)
        self.filter_edit.textChanged.connect(self.batch_proxy.setFilterFixedString)
        batch_box = QtWidgets.QWidget()
        bl = QtWidgets.QVBoxLayout(batch_box)
        bl.setContentsMargins(2, 2, 2, 2)
        bl.addWidget(self.filter_edit)
        bl.addWidget(self.batch_view)
        # Statistics, detail, log
        self.stats = QtWidgets.QPlainTextEdit(readOnly=True)
        self.detail = DetailPanel()
        self.log = QtWidgets.QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(5000)

        self.docks = {}
        for key, widget, area in (
            ("layers", self.layer_list, QtCore.Qt.DockWidgetArea.LeftDockWidgetArea),
            ("params", self.params, QtCore.Qt.DockWidgetArea.LeftDockWidgetArea),
            ("batches", batch_box, QtCore.Qt.DockWidgetArea.RightDockWidgetArea),
            ("detail", self.detail, QtCore.Qt.DockWidgetArea.RightDockWidgetArea),
            ("stats", self.stats, QtCore.Qt.DockWidgetArea.BottomDockWidgetArea),
            ("log", self.log, QtCore.Qt.DockWidgetArea.BottomDockWidgetArea),
        ):
            dock = QtWidgets.QDockWidget(self)
            dock.setObjectName(key)
            dock.setWidget(widget)
            self.addDockWidget(area, dock)
            self.docks[key] = dock
        self.tabifyDockWidget(self.docks["stats"], self.docks["log"])
        self.docks["log"].raise_()
        self.resizeDocks(
            [self.docks["layers"], self.docks["batches"]],
            [300, 560],
            QtCore.Qt.Orientation.Horizontal,
        )
        self.resizeDocks(
            [
                self.docks["layers"],
                self.docks["params"],
                self.docks["batches"],
                self.docks["detail"],
                self.docks["log"],
            ],
            [150, 450, 420, 260, 130],
            QtCore.Qt.Orientation.Vertical,
        )

        # Status bar: progress, cancel, cursor
        self.progress = QtWidgets.QProgressBar()
        self.progress.setMaximumWidth(260)
        self.progress.setRange(0, 1000)
        self.progress.hide()
        self.cancel_button = QtWidgets.QToolButton()
        self.cancel_button.clicked.connect(self.runner.cancel)
        self.cancel_button.hide()
        self.cursor_label = QtWidgets.QLabel()
        self.statusBar().addPermanentWidget(self.progress)
        self.statusBar().addPermanentWidget(self.cancel_button)
        self.statusBar().addPermanentWidget(self.cursor_label)

        self._build_actions()
        self.set_language(self.settings.value("language", i18n.system_language()))
        geometry = self.settings.value("geometry")
        if geometry is not None:
            self.restoreGeometry(geometry)
        state = self.settings.value("state")
        if state is not None:
            self.restoreState(state)

    # -- actions and texts ---------------------------------------------------------

    def _build_actions(self) -> None:
        style = self.style()
        sp = QtWidgets.QStyle.StandardPixmap
        a = {}
        a["open"] = QtGui.QAction(style.standardIcon(sp.SP_DialogOpenButton), "", self)
        a["open"].setShortcut(QtGui.QKeySequence.StandardKey.Open)
        a["open"].triggered.connect(self.open_dialog)
        a["open_bearings"] = QtGui.QAction("", self, triggered=self.open_bearings_dialog)
        a["open_project"] = QtGui.QAction("", self, triggered=self.open_project_dialog)
        a["save_project"] = QtGui.QAction(style.standardIcon(sp.SP_DialogSaveButton), "", self)
        a["save_project"].setShortcut(QtGui.QKeySequence.StandardKey.Save)
        a["save_project"].triggered.connect(self.save_project_dialog)
        a["export_csv"] = QtGui.QAction("", self, triggered=lambda: self.export_dialog("csv"))
        a["export_geojson"] = QtGui.QAction(
            "", self, triggered=lambda: self.export_dialog("geojson")
        )
        a["export_maneuvers"] = QtGui.QAction(
            "", self, triggered=lambda: self.export_dialog("maneuvers")
        )
        a["quit"] = QtGui.QAction("", self, triggered=self.close)
        a["quit"].setShortcut(QtGui.QKeySequence.StandardKey.Quit)
        a["pipeline"] = QtGui.QAction(style.standardIcon(sp.SP_MediaPlay), "", self)
        a["pipeline"].triggered.connect(lambda: self.run_step("pipeline"))
        for step in ("clean", "maneuvers", "compress", "associate", "fuse"):
            a[step] = QtGui.QAction("", self, triggered=lambda _=False, s=step: self.run_step(s))
        a["cancel"] = QtGui.QAction(style.standardIcon(sp.SP_BrowserStop), "", self)
        a["cancel"].triggered.connect(self.runner.cancel)
        a["fit"] = QtGui.QAction(style.standardIcon(sp.SP_TitleBarMaxButton), "", self)
        a["fit"].triggered.connect(lambda: self.canvas.fit())
        a["box"] = QtGui.QAction("", self, checkable=True)
        a["box"].toggled.connect(self.canvas.set_box_zoom)
        a["remove_layer"] = QtGui.QAction("", self, triggered=self.remove_active_layer)
        a["import_report"] = QtGui.QAction("", self, triggered=self.show_import_report)
        self.actions_ = a

        self.menus = {k: QtWidgets.QMenu(self) for k in ("file", "export", "run", "view", "lang")}
        m = self.menus
        m["file"].addAction(a["open"])
        m["file"].addAction(a["open_bearings"])
        m["file"].addAction(a["open_project"])
        m["file"].addAction(a["save_project"])
        m["file"].addMenu(m["export"])
        m["export"].addAction(a["export_csv"])
        m["export"].addAction(a["export_geojson"])
        m["export"].addAction(a["export_maneuvers"])
        m["file"].addSeparator()
        m["file"].addAction(a["quit"])
        m["run"].addAction(a["pipeline"])
        m["run"].addSeparator()
        for step in ("clean", "maneuvers", "compress", "associate", "fuse"):
            m["run"].addAction(a[step])
        m["run"].addSeparator()
        m["run"].addAction(a["cancel"])
        m["view"].addAction(a["fit"])
        m["view"].addAction(a["box"])
        m["view"].addAction(a["remove_layer"])
        m["view"].addAction(a["import_report"])
        m["view"].addSeparator()
        for dock in self.docks.values():
            m["view"].addAction(dock.toggleViewAction())
        group = QtGui.QActionGroup(self)
        self.lang_actions = {}
        for code, label in i18n.LANGUAGES.items():
            act = QtGui.QAction(label, self, checkable=True)
            act.triggered.connect(lambda _=False, c=code: self.set_language(c))
            group.addAction(act)
            m["lang"].addAction(act)
            self.lang_actions[code] = act
        for key in ("file", "run", "view", "lang"):
            self.menuBar().addMenu(m[key])
        self.toolbar = self.addToolBar("main")
        self.toolbar.setObjectName("toolbar")
        for key in (
            "open",
            "save_project",
            None,
            "pipeline",
            "clean",
            "maneuvers",
            "compress",
            "associate",
            "fuse",
            "cancel",
            None,
            "fit",
            "box",
        ):
            if key is None:
                self.toolbar.addSeparator()
            else:
                self.toolbar.addAction(a[key])

    def retranslate(self) -> None:
        """Set every visible text (called again when the language changes)."""
        a, m = self.actions_, self.menus
        self.setWindowTitle(
            self.tr("Wakeline") + (f" — {self.project_path.name}" if self.project_path else "")
        )
        texts = {
            "open": self.tr("&Open tracks…"),
            "open_project": self.tr("Open &project…"),
            "open_bearings": self.tr("Open &bearings (bearing-only detection)…"),
            "save_project": self.tr("&Save project as…"),
            "export_csv": self.tr("Active layer as &CSV…"),
            "export_geojson": self.tr("Active layer as &GeoJSON…"),
            "export_maneuvers": self.tr("&Maneuver points as CSV…"),
            "quit": self.tr("&Quit"),
            "pipeline": self.tr("Run &pipeline (clean, maneuvers, compress)"),
            "clean": self.tr("&Clean"),
            "maneuvers": self.tr("&Maneuvers"),
            "compress": self.tr("C&ompress"),
            "associate": self.tr("&Associate (one sensor)"),
            "fuse": self.tr("&Fuse (several sensors)"),
            "cancel": self.tr("Cancel the running job"),
            "fit": self.tr("&Fit to data"),
            "box": self.tr("&Box zoom"),
            "remove_layer": self.tr("&Remove active layer"),
            "import_report": self.tr("&Import report and quarantined rows…"),
        }
        for key, text in texts.items():
            a[key].setText(text)
        m["file"].setTitle(self.tr("&File"))
        m["export"].setTitle(self.tr("&Export"))
        m["run"].setTitle(self.tr("&Run"))
        m["view"].setTitle(self.tr("&View"))
        m["lang"].setTitle(self.tr("&Language"))
        titles = {
            "layers": self.tr("Layers"),
            "params": self.tr("Parameters"),
            "batches": self.tr("Batch table"),
            "detail": self.tr("Detail"),
            "stats": self.tr("Statistics"),
            "log": self.tr("Log"),
        }
        for key, title in titles.items():
            self.docks[key].setWindowTitle(title)
        self.filter_edit.setPlaceholderText(self.tr("Filter batches (any column)…"))
        self.cancel_button.setText(self.tr("Cancel"))
        self.batch_model.set_titles(
            [
                self.tr("Sensor"),
                self.tr("Batch"),
                self.tr("Points"),
                self.tr("Start (UTC)"),
                self.tr("End (UTC)"),
                self.tr("Duration (min)"),
                self.tr("Length (km)"),
                self.tr("Speed (kn)"),
                self.tr("Maneuvers"),
                self.tr("Target"),
                self.tr("Status"),
            ]
        )
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

    # -- loading -------------------------------------------------------------------

    def open_dialog(self) -> None:
        dialog = ImportDialog(self)
        if dialog.exec() != QtWidgets.QDialog.DialogCode.Accepted:
            return
        self.load_file(**dialog.options())

    def load_file(
        self,
        path: Path,
        fmt: str = "auto",
        encoding: str | None = None,
        mapping: list[str] | None = None,
        sensor: str | None = None,
    ) -> bool:
        """Import a file as a new layer; errors go to a dialog and the log."""
        path = Path(path)
        try:
            kw = {"sensor": sensor} if sensor else {}
            result = read_points(path, fmt=fmt, mapping=mapping or [], encoding=encoding, **kw)
            if len(result.points) == 0:
                raise InputError(f"{path.name}: no usable points")
        except (InputError, OSError) as exc:
            text = str(exc) if isinstance(exc, InputError) else f"{path}: {exc.strerror or exc}"
            self.log_message(f"{self.tr('Error')}: {text}")
            QtWidgets.QMessageBox.warning(self, self.tr("Cannot open file"), text)
            return False
        rep = result.report
        self.log_message(
            f"{path.name}: {rep['rows_imported']:,} rows in {rep['tracks']:,} tracks "
            f"({rep['format_label']}, {rep['encoding']}); {rep['rows_quarantined']:,} quarantined"
        )
        for reason, count in rep["quarantine_reasons"].items():
            self.log_message(f"    quarantined {count:,}: {reason}")
        if len(result.quarantine):
            self.log_message(
                f"    first quarantined rows:\n{result.quarantine.head(5).to_string()}"
            )
        self.sources.append(Source(str(path.resolve()), file_hash(path)))
        quarantine = result.quarantine.head(QUARANTINE_KEPT).astype(str).to_dict("records")
        self.add_layer(
            path.name,
            "source",
            result.points,
            {"file": str(path), "report": rep, "quarantine": quarantine},
        )
        self.canvas.fit()
        return True

    def open_bearings_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Open bearings"), "", "CSV (*.csv *.txt);;All files (*)"
        )
        if path:
            self.load_bearings(Path(path))

    def load_bearings(self, path: Path) -> int | None:
        """Read ``batch,time,bearing[,obs_lon,obs_lat]`` and run seed 002's detector on it
        in the worker; the Detail panel shows the sequences, z and the detections."""
        from wakeline.core.bearing import read_bearings

        try:
            bearings = read_bearings(path)
        except (InputError, OSError) as exc:
            self.log_message(f"{self.tr('Error')}: {exc}")
            QtWidgets.QMessageBox.warning(self, self.tr("Cannot open file"), str(exc))
            return None
        self.bearings = bearings
        self.log_message(
            f"{Path(path).name}: {len(bearings):,} bearings in {bearings['batch'].nunique()} sequences"
        )
        params = self.params.params("bearing")
        job = self.runner.run("bearing", lambda prog: pipeline.step_bearing(bearings, params, prog))
        self._job_context = {job: ("bearing", Path(path).name)}
        return job

    # -- layers --------------------------------------------------------------------

    def _unique_name(self, name: str) -> str:
        out, k = name, 2
        while out in self.layers:
            out = f"{name} ({k})"
            k += 1
        return out

    def add_layer(
        self,
        name: str,
        kind: str,
        points: pd.DataFrame,
        meta: dict | None = None,
        color: str | None = None,
        visible: bool = True,
        autosave: bool = True,
    ) -> str:
        name = self._unique_name(name)
        if color is None:
            color = KIND_COLORS.get(kind, PALETTE[len(self.layers) % len(PALETTE)])
        layer = Layer(name, kind, sort_points(points), visible, color, dict(meta or {}))
        self.layers[name] = layer
        self._draw_layer(layer)
        item = QtWidgets.QListWidgetItem(color_icon(color), f"{name}  [{kind}]")
        item.setData(QtCore.Qt.ItemDataRole.UserRole, name)
        item.setFlags(item.flags() | QtCore.Qt.ItemFlag.ItemIsUserCheckable)
        item.setCheckState(
            QtCore.Qt.CheckState.Checked if visible else QtCore.Qt.CheckState.Unchecked
        )
        self.layer_list.addItem(item)
        self.layer_list.setCurrentItem(item)
        if len(self.layers) == 1 and len(layer.points):
            self.canvas.set_true_aspect(float(layer.points["lat"].mean()))
        self.layersChanged.emit()
        if autosave:
            self.autosave()
        return name

    def _draw_layer(self, layer: Layer) -> None:
        pts = layer.points
        if layer.kind == "maneuvers":
            # The maneuver layer is the track with δ: show its turning points only.
            marks = maneuver_table(pts)
            self.canvas.set_layer(
                layer.name,
                marks.assign(batch=marks["batch"]) if marks is not None else pts.head(0),
                layer.color,
                symbols=True,
                width=0,
            )
            for item in self.canvas.layer_items(layer.name):
                item.setPen(None)
                item.setSymbolSize(8)
        else:
            self.canvas.set_layer(
                layer.name,
                pts,
                layer.color,
                by_sensor=layer.kind == "source",
                symbols=layer.kind in ("source", "compressed"),
                width=2.5 if layer.kind in ("compressed", "fused") else 1.3,
            )
        self.canvas.set_visible(layer.name, layer.visible)

    def layer_row(self, name: str) -> int:
        """Row of layer ``name`` in the Layers list (-1 when absent)."""
        names = self._layer_order()
        return names.index(name) if name in names else -1

    def select_layer(self, name: str) -> None:
        """Make ``name`` the active layer, as a click in the Layers list does."""
        row = self.layer_row(name)
        if row >= 0:
            self.layer_list.setCurrentRow(row)

    def show_import_report(self) -> QtWidgets.QDialog | None:
        """The import report of the active layer's source file."""
        layer = self.active_layer()
        if layer is None:
            return None
        source = self.layers.get(layer.name.split(" · ")[0], layer)
        dialog = ImportReportDialog(source, self)
        dialog.show()
        return dialog

    def remove_active_layer(self) -> None:
        if self.active is None:
            return
        name = self.active
        self.canvas.remove_layer(name)
        del self.layers[name]
        self.layer_list.takeItem(self.layer_row(name))
        if not self.layers:
            self.set_active(None)
        self.autosave()

    def _layer_item_changed(self, item: QtWidgets.QListWidgetItem) -> None:
        name = item.data(QtCore.Qt.ItemDataRole.UserRole)
        if name in self.layers:
            visible = item.checkState() == QtCore.Qt.CheckState.Checked
            if self.layers[name].visible != visible:
                self.layers[name].visible = visible
                self.canvas.set_visible(name, visible)
                self.autosave()

    def _layer_current_changed(self, current, _previous) -> None:
        self.set_active(current.data(QtCore.Qt.ItemDataRole.UserRole) if current else None)

    def set_active(self, name: str | None) -> None:
        """Make ``name`` the layer the batch table, statistics and steps work on."""
        self.active = name
        layer = self.layers.get(name) if name else None
        if layer is None:
            self.batch_model.set_summary(
                batch_summary(pd.DataFrame(columns=["sensor", "batch", "time", "lon", "lat"]))
            )
            self.canvas.show_selection(pd.DataFrame())
            self._update_stats()
            return
        pts = layer.points
        if layer.kind == "maneuvers":
            summary = batch_summary(pts, maneuver_table(pts))
        else:
            summary = batch_summary(pts)
        self.batch_model.set_summary(summary)
        self.batch_view.resizeColumnsToContents()
        # The detection limit depends on the raw sampling: take it from the source layer.
        root = self.layers.get(name.split(" · ")[0], layer)
        self.params.show_guidance(summary if root is layer else batch_summary(root.points))
        self.canvas.show_selection(pd.DataFrame())
        self.detail.clear()
        self._update_stats()

    def active_layer(self) -> Layer | None:
        return self.layers.get(self.active) if self.active else None

    # -- selection -----------------------------------------------------------------

    def selected_keys(self) -> list[tuple[str, str]]:
        rows = {
            self.batch_proxy.mapToSource(i).row()
            for i in self.batch_view.selectionModel().selectedRows()
        }
        return [self.batch_model.key_of_row(r) for r in sorted(rows)]

    def select_tracks(self, keys: list[tuple[str, str]], add: bool = False) -> None:
        """Select rows of the batch table by (sensor, batch); the map follows."""
        sel = self.batch_view.selectionModel()
        flags = QtCore.QItemSelectionModel.SelectionFlag
        if not add:
            sel.clearSelection()
        last = None
        for sensor, batch in keys:
            row = self.batch_model.row_of_key(sensor, batch)
            if row is None:
                continue
            idx = self.batch_proxy.mapFromSource(self.batch_model.index(row, 0))
            if idx.isValid():
                sel.select(idx, flags.Select | flags.Rows)
                last = idx
        if last is not None:
            self.batch_view.scrollTo(last)

    def _table_selection_changed(self, *_args) -> None:
        layer = self.active_layer()
        if layer is None:
            return
        keys = self.selected_keys()
        pts = layer.points
        if keys:
            key_frame = pd.MultiIndex.from_tuples(keys)
            mask = pd.MultiIndex.from_arrays(
                [pts["sensor"].astype(str), pts["batch"].astype(str)]
            ).isin(key_frame)
            chosen = pts[mask]
        else:
            chosen = pts.head(0)
        marks = maneuver_table(chosen)
        self.canvas.show_selection(chosen, marks)
        if len(keys) >= 1:
            self._show_detail(layer, keys[0])
        else:
            self.detail.clear()
        self.autosave()

    def _show_detail(self, layer: Layer, key: tuple[str, str]) -> None:
        def track_of(lay: Layer | None) -> pd.DataFrame | None:
            if lay is None:
                return None
            p = lay.points
            m = (p["sensor"].astype(str) == key[0]) & (p["batch"].astype(str) == key[1])
            return p[m]

        base = layer.name.split(" · ")[0]
        man = self.layers.get(f"{base} · maneuvers") if layer.kind != "maneuvers" else layer
        comp = self.layers.get(f"{base} · compressed") if layer.kind != "compressed" else layer
        factor = track_of(man) if man is not None else track_of(layer)
        threshold = man.meta.get("threshold_deg") if man is not None else None
        self.detail.show_track(
            factor if factor is not None else track_of(layer),
            threshold,
            track_of(comp),
            track_of(man) if man is not None else track_of(layer),
        )

    def _track_clicked(self, layer: str, sensor: str, batch: str, add: bool) -> None:
        if layer != self.active:
            self.select_layer(layer)
        self.select_tracks([(sensor, batch)], add=add)

    # -- running steps -------------------------------------------------------------

    def run_step(self, step: str) -> int | None:
        """Run a pipeline step on the active layer in the worker thread."""
        layer = self.active_layer()
        if layer is None:
            QtWidgets.QMessageBox.information(
                self, self.tr("Nothing to run on"), self.tr("Open a track file first.")
            )
            return None
        pts = layer.points
        p = self.params
        fns = {
            "pipeline": lambda prog: pipeline.default_pipeline(
                pts, p.clean_params(), p.params("maneuver"), p.params("compress"), prog
            ),
            "clean": lambda prog: pipeline.step_clean(pts, p.clean_params(), prog),
            "maneuvers": lambda prog: pipeline.step_maneuvers(pts, p.params("maneuver"), prog),
            "compress": lambda prog: pipeline.step_compress(
                pts, p.params("maneuver"), p.params("compress"), prog
            ),
            "associate": lambda prog: pipeline.step_associate(pts, p.params("associate"), prog),
            "fuse": lambda prog: pipeline.step_fuse(pts, p.params("fuse"), prog),
        }
        job = self.runner.run(step, fns[step])
        # One job at a time: an older job's result will never be applied.
        self._job_context = {job: (step, layer.name)}
        return job

    def _on_job_message(self, msg) -> None:
        if isinstance(msg, Started):
            self.progress.setValue(0)
            self.progress.show()
            self.cancel_button.show()
            self.statusBar().showMessage(self.tr("Running {0}…").format(msg.name))
        elif isinstance(msg, Progress):
            self.progress.setValue(int(msg.fraction * 1000))
            if msg.text:
                self.statusBar().showMessage(msg.text)
        else:
            if msg.job in self._job_context:
                self.progress.hide()
                self.cancel_button.hide()
            step, base = self._job_context.pop(msg.job, (msg.name, ""))
            if isinstance(msg, Finished):
                self._apply_result(base, msg.result)
                self.statusBar().showMessage(
                    self.tr("{0} done in {1:.1f} s").format(step, msg.seconds), 8000
                )
                self.log_message(f"{step} on {base}: {summarize(msg.result.report)}")
            elif isinstance(msg, Failed):
                self.log_message(f"{self.tr('Error')} ({step}): {msg.message}")
                if msg.detail:
                    self.log_message(msg.detail)
                QtWidgets.QMessageBox.warning(self, self.tr("{0} failed").format(step), msg.message)
            elif isinstance(msg, Cancelled):
                self.log_message(self.tr("{0} cancelled").format(step))
                self.statusBar().showMessage(self.tr("{0} cancelled").format(step), 5000)

    def _apply_result(self, base: str, result: pipeline.StepResult) -> None:
        if result.step == "bearing":
            self.bearing_detections = result.report["table"]
            self.detail.show_bearings(
                self.bearings, self.bearing_detections, self.params.params("bearing")
            )
            self.docks["detail"].raise_()
            return
        root = base.split(" · ")[0]
        for new in result.layers:
            name = f"{root} · {new.suffix}"
            if name in self.layers:  # a re-run replaces the old result
                self.canvas.remove_layer(name)
                del self.layers[name]
                self.layer_list.takeItem(self.layer_row(name))
            self.add_layer(name, new.kind, new.points, {**new.meta, "from": base}, autosave=False)
        self.autosave()

    # -- export --------------------------------------------------------------------

    def export_dialog(self, kind: str) -> None:
        layer = self.active_layer()
        if layer is None:
            return
        filt = "GeoJSON (*.geojson)" if kind == "geojson" else "CSV (*.csv)"
        suffix = ".geojson" if kind == "geojson" else ".csv"
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Export"), layer.name.replace(" · ", "_") + suffix, filt
        )
        if path:
            self.export(kind, Path(path))

    def export(self, kind: str, path: Path) -> bool:
        """Write the active layer (or its maneuver points) to ``path``."""
        layer = self.active_layer()
        if layer is None:
            return False
        try:
            if kind == "csv":
                export_csv(layer.points, path)
            elif kind == "geojson":
                export_geojson(layer.points, path, maneuver_table(layer.points))
            else:
                man = maneuver_table(layer.points)
                if man is None:
                    raise InputError(
                        self.tr("this layer has no maneuver points: run Maneuvers or Compress")
                    )
                export_csv(man, path)
        except (InputError, OSError) as exc:
            QtWidgets.QMessageBox.warning(self, self.tr("Export failed"), str(exc))
            self.log_message(f"{self.tr('Error')}: {exc}")
            return False
        self.log_message(self.tr("exported {0} to {1}").format(layer.name, path))
        return True

    # -- project -------------------------------------------------------------------

    def project(self) -> Project:
        return Project(
            sources=list(self.sources),
            params=self.params.to_dict(),
            layers=[self.layers[n] for n in self._layer_order()],
            selection=[(self.active or "", s, b) for s, b in self.selected_keys()],
        )

    def _layer_order(self) -> list[str]:
        return [
            self.layer_list.item(r).data(QtCore.Qt.ItemDataRole.UserRole)
            for r in range(self.layer_list.count())
        ]

    def save_project(self, path: Path) -> None:
        self.project_path = Path(path)
        save_project(self.project(), self.project_path)
        self.retranslate()

    def autosave(self) -> None:
        """Save after every change once the work has a project file."""
        if self.project_path is not None and not self._selecting:
            try:
                save_project(self.project(), self.project_path)
            except OSError as exc:
                self.log_message(f"{self.tr('Autosave failed')}: {exc}")

    def open_project(self, path: Path) -> bool:
        try:
            proj = load_project(path)
        except InputError as exc:
            QtWidgets.QMessageBox.warning(self, self.tr("Cannot open project"), str(exc))
            self.log_message(f"{self.tr('Error')}: {exc}")
            return False
        self.project_path = None  # no autosave while restoring
        for name in list(self.layers):
            self.canvas.remove_layer(name)
        self.layers.clear()
        self.layer_list.clear()
        self.sources = proj.sources
        problems = self.params.from_dict(proj.params)
        for layer in proj.layers:
            self.add_layer(
                layer.name,
                layer.kind,
                layer.points,
                layer.meta,
                layer.color,
                layer.visible,
                autosave=False,
            )
        sel = [r for r in proj.selection if r[0]]
        if sel:
            self.select_layer(sel[0][0])
            self._selecting = True
            self.select_tracks([(s, b) for _, s, b in sel])
            self._selecting = False
        self.project_path = Path(path)
        self.retranslate()
        self.canvas.fit()
        warnings = proj.source_problems() + problems
        for w in warnings:
            self.log_message(f"{self.tr('Warning')}: {w}")
        if warnings:
            QtWidgets.QMessageBox.warning(
                self, self.tr("Project opened with warnings"), "\n".join(warnings)
            )
        return True

    def open_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Open project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            self.open_project(Path(path))

    def save_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Save project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            if not path.endswith(".wakeline"):
                path += ".wakeline"
            self.save_project(Path(path))

    # -- misc ----------------------------------------------------------------------

    def _update_stats(self) -> None:
        layer = self.active_layer()
        if layer is None:
            self.stats.setPlainText(self.tr("No layer. File ▸ Open tracks… (Ctrl+O)"))
            return
        pts = layer.points
        tracks = self.batch_model.rowCount()
        t = pts["time"]
        lines = [
            f"{self.tr('Layer')}: {layer.name} [{layer.kind}]",
            f"{self.tr('Points')}: {len(pts):,}   {self.tr('Tracks')}: {tracks:,}   "
            f"{self.tr('Sensors')}: {', '.join(sorted(pts['sensor'].astype(str).unique()))}",
        ]
        if len(pts):
            lines.append(
                f"{self.tr('Time')}: {t.min():%Y-%m-%d %H:%M:%S} – {t.max():%Y-%m-%d %H:%M:%S} UTC"
            )
        for key in ("dis_e_m", "rejected", "threshold_deg"):
            if key in layer.meta:
                lines.append(
                    f"{key}: {layer.meta[key]:.1f}"
                    if isinstance(layer.meta[key], float)
                    else f"{key}: {layer.meta[key]}"
                )
        self.stats.setPlainText("\n".join(lines))
        self.statusBar().showMessage(
            f"{len(pts):,} {self.tr('points')}, {tracks:,} {self.tr('tracks')}"
        )

    def log_message(self, text: str) -> None:
        self.log.appendPlainText(text)

    def _show_cursor(self, lon: float, lat: float) -> None:
        self.cursor_label.setText(
            f"{lon:.5f}°, {lat:.5f}°   {format_dms(lat, 'N', 'S')} {format_dms(lon, 'E', 'W')}"
        )

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt API
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("state", self.saveState())
        self.runner.cancel()
        self.runner.wait(5000)
        super().closeEvent(event)

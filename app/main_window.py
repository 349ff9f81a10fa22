"""The main window: the map in the centre, a track list, the import log.

This is the foundation window; the full application (parameters, batch table with
selection, worker thread, detail views, export, project file) grows on it.
"""

from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.map_canvas import PALETTE, MapCanvas
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.tracks import track_summary


def format_dms(value: float, positive: str, negative: str) -> str:
    """Degrees as D°MM'SS.s" with a hemisphere letter."""
    hemi = positive if value >= 0 else negative
    v = abs(value)
    d = int(v)
    m = int((v - d) * 60)
    s = (v - d - m / 60) * 3600
    return f"{d}°{m:02d}'{s:04.1f}\"{hemi}"


class TrackTableModel(QtCore.QAbstractTableModel):
    """A read-only table over the core's track summary."""

    COLUMNS = (
        ("sensor", "Sensor"),
        ("batch", "Batch"),
        ("points", "Points"),
        ("start", "Start (UTC)"),
        ("duration_s", "Duration (min)"),
        ("length_m", "Length (km)"),
        ("mean_speed_kn", "Speed (kn)"),
    )

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self._df = pd.DataFrame()

    def set_summary(self, df: pd.DataFrame) -> None:
        self.beginResetModel()
        self._df = df.reset_index(drop=True)
        self.endResetModel()

    def rowCount(self, parent: QtCore.QModelIndex | None = None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df)

    def columnCount(self, parent: QtCore.QModelIndex | None = None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self.COLUMNS)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if (
            role == QtCore.Qt.ItemDataRole.DisplayRole
            and orientation == QtCore.Qt.Orientation.Horizontal
        ):
            return self.COLUMNS[section][1]
        return None

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid() or role not in (
            QtCore.Qt.ItemDataRole.DisplayRole,
            QtCore.Qt.ItemDataRole.TextAlignmentRole,
        ):
            return None
        key = self.COLUMNS[index.column()][0]
        value = self._df.iloc[index.row()][key]
        if role == QtCore.Qt.ItemDataRole.TextAlignmentRole:
            return (
                int(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
                if key not in ("sensor", "batch")
                else None
            )
        if key == "start":
            return pd.Timestamp(value).strftime("%Y-%m-%d %H:%M:%S")
        if key == "duration_s":
            return f"{value / 60:.1f}"
        if key == "length_m":
            return f"{value / 1000:.2f}"
        if key == "mean_speed_kn":
            return "" if np.isnan(value) else f"{value:.1f}"
        return str(value)


class MainWindow(QtWidgets.QMainWindow):
    """Wakeline's main window."""

    def __init__(self) -> None:
        super().__init__()
        self.setWindowTitle("Wakeline")
        self.points = pd.DataFrame()
        self.canvas = MapCanvas(self)
        self.setCentralWidget(self.canvas)

        self.track_model = TrackTableModel(self)
        self.track_view = QtWidgets.QTableView()
        self.track_view.setModel(self.track_model)
        self.track_view.setSortingEnabled(False)
        self.track_view.verticalHeader().setVisible(False)
        self.track_view.setAlternatingRowColors(True)
        self.track_view.horizontalHeader().setStretchLastSection(True)
        dock = QtWidgets.QDockWidget("Tracks", self)
        dock.setObjectName("tracks")
        dock.setWidget(self.track_view)
        self.addDockWidget(QtCore.Qt.DockWidgetArea.RightDockWidgetArea, dock)

        self.log = QtWidgets.QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(2000)
        log_dock = QtWidgets.QDockWidget("Log", self)
        log_dock.setObjectName("log")
        log_dock.setWidget(self.log)
        self.addDockWidget(QtCore.Qt.DockWidgetArea.BottomDockWidgetArea, log_dock)

        self.resizeDocks([dock], [560], QtCore.Qt.Orientation.Horizontal)
        self.resizeDocks([log_dock], [120], QtCore.Qt.Orientation.Vertical)

        self.cursor_label = QtWidgets.QLabel()
        self.statusBar().addPermanentWidget(self.cursor_label)
        self.canvas.cursorMoved.connect(self._show_cursor)

        file_menu = self.menuBar().addMenu("&File")
        open_action = file_menu.addAction("&Open…", self.open_dialog)
        open_action.setShortcut(QtGui.QKeySequence.StandardKey.Open)
        file_menu.addSeparator()
        quit_action = file_menu.addAction("&Quit", self.close)
        quit_action.setShortcut(QtGui.QKeySequence.StandardKey.Quit)
        view_menu = self.menuBar().addMenu("&View")
        view_menu.addAction("&Fit to data", self.canvas.fit)
        view_menu.addAction(dock.toggleViewAction())
        view_menu.addAction(log_dock.toggleViewAction())

    # -- loading ---------------------------------------------------------------------

    def open_dialog(self) -> None:
        paths, _ = QtWidgets.QFileDialog.getOpenFileNames(
            self, "Open track files", "", "Track files (*.csv *.csv.gz *.txt);;All files (*)"
        )
        for path in paths:
            self.load_file(Path(path))

    def load_file(self, path: Path) -> bool:
        """Import a file and add its points; errors go to a dialog and the log."""
        try:
            result = read_points(path)
        except InputError as exc:
            self.log_message(f"Error: {exc}")
            QtWidgets.QMessageBox.warning(self, "Cannot open file", str(exc))
            return False
        rep = result.report
        self.log_message(
            f"{path.name}: {rep['rows_imported']:,} rows in {rep['tracks']:,} tracks "
            f"({rep['format_label']}, {rep['encoding']}); {rep['rows_quarantined']:,} quarantined"
        )
        for reason, count in rep["quarantine_reasons"].items():
            self.log_message(f"    quarantined {count:,}: {reason}")
        self.add_points(result.points)
        return True

    def add_points(self, points: pd.DataFrame) -> None:
        self.points = (
            points if self.points.empty else pd.concat([self.points, points], ignore_index=True)
        )
        self._redraw()

    def _redraw(self) -> None:
        if self.points.empty:
            return
        self.canvas.set_true_aspect(float(self.points["lat"].mean()))
        for k, (sensor, group) in enumerate(self.points.groupby("sensor", sort=True)):
            self.canvas.set_layer(str(sensor), group, PALETTE[k % len(PALETTE)])
        self.track_model.set_summary(track_summary(self.points))
        self.track_view.resizeColumnsToContents()
        self.canvas.fit()
        n_tracks = self.track_model.rowCount()
        self.statusBar().showMessage(f"{len(self.points):,} points, {n_tracks:,} tracks")

    def log_message(self, text: str) -> None:
        self.log.appendPlainText(text)

    def _show_cursor(self, lon: float, lat: float) -> None:
        self.cursor_label.setText(
            f"{lon:.5f}°, {lat:.5f}°   {format_dms(lat, 'N', 'S')} {format_dms(lon, 'E', 'W')}"
        )

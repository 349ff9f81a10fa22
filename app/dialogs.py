"""Dialogs of the main window: import (file, layout, encoding, mapping) and the import
report with the quarantined rows."""

import gzip
import json
from pathlib import Path

import pandas as pd
from PySide6 import QtGui, QtWidgets

from wakeline.app.models import FrameModel
from wakeline.core.io import FAMILIES

#: Quarantined rows kept with a source layer (and in the project) for viewing.
QUARANTINE_KEPT = 10_000


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

    def __init__(self, layer, parent=None) -> None:
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

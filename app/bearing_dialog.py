"""File ▸ Open bearings: pick a bearing file, see its first rows, the layout found and the
column of each bearing field (the track import dialog's mapping boxes, made from the
bearing reader's fields), the encoding and the origin of an observer in metres.

``options()`` returns the keyword arguments of
:func:`wakeline.core.bearing_read.read_bearing_file` (``path`` apart), as
``wakeline bearing``'s --map, --origin and --encoding give them.
"""

from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.core_text import shown
from wakeline.app.import_dialog import (
    ENCODINGS,
    NONE,
    lay_out_dialog,
    mapping_group_of,
    origin_edit,
)
from wakeline.core.bearing_read import BEARING_FIELDS, inspect_bearings
from wakeline.core.errors import InputError


def _tr(context: str, text: str) -> str:
    return QtCore.QCoreApplication.translate(context, text)


class BearingDialog(QtWidgets.QDialog):
    """Pick a bearing file; see its first rows; choose the columns, encoding and origin."""

    def __init__(
        self, parent=None, path: Path | None = None, tracks: list[tuple[str, str]] = ()
    ) -> None:
        """``tracks``: (layer id, name) of the track layers open, to gate the bearings on."""
        super().__init__(parent)
        self.setWindowTitle(_tr("MainWindow", "Open bearings"))
        self._info: dict = {}
        self._updating = False
        self.path_edit = QtWidgets.QLineEdit(str(path or ""))
        browse = QtWidgets.QPushButton(_tr("ImportDialog", "Browse…"))
        browse.clicked.connect(self._browse)
        self.encoding_box = QtWidgets.QComboBox()
        for enc in ENCODINGS:  # "auto" in the window's language
            self.encoding_box.addItem(_tr("ImportDialog", "auto") if enc == "auto" else enc, enc)
        self.encoding_box.setEditable(True)
        self.origin_edit = origin_edit()
        # Several targets in one series (a camera's frame): one sequence per target by
        # gating on a track layer (GNSS truth, AIS), as `wakeline bearing --tracks`.
        self.tracks_box = QtWidgets.QComboBox()
        self.tracks_box.addItem(self.tr("none"), None)
        for lid, name in tracks:
            self.tracks_box.addItem(name, lid)
        self.tracks_box.setEnabled(bool(tracks))
        self.tracks_box.setToolTip(
            self.tr(
                "A track layer of the targets (GNSS truth, AIS): each bearing goes to the "
                "track whose bearing from the observer lies within the gate, the nearest per "
                "series, track and time. A camera's series holds several targets and clutter; "
                "the detector needs one target's sequence."
            )
        )
        self.gate_box = QtWidgets.QDoubleSpinBox()
        self.gate_box.setRange(0.1, 45.0)
        self.gate_box.setDecimals(1)
        self.gate_box.setValue(3.0)
        self.gate_box.setSuffix(" °")
        self.gate_box.setToolTip(self.tr("Largest bearing difference to a track"))
        self.layout_label = QtWidgets.QLabel()
        self.layout_label.setWordWrap(True)
        self.mapping_boxes, mapping_group = mapping_group_of(BEARING_FIELDS, self._changed)
        self.notes_label = QtWidgets.QLabel()
        self.notes_label.setWordWrap(True)
        self.warning_label = QtWidgets.QLabel()
        self.warning_label.setWordWrap(True)
        self.warning_label.setStyleSheet("color: #b35900")
        self.preview = QtWidgets.QPlainTextEdit(readOnly=True)
        self.preview.setLineWrapMode(QtWidgets.QPlainTextEdit.LineWrapMode.NoWrap)
        self.preview.setFont(
            QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        )
        form = QtWidgets.QFormLayout()
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.path_edit, 1)
        row.addWidget(browse)
        form.addRow(_tr("ImportDialog", "File"), row)
        form.addRow(_tr("ImportDialog", "Encoding"), self.encoding_box)
        form.addRow(_tr("ImportDialog", "Origin of x/y metres"), self.origin_edit)
        form.addRow(self.tr("Gate on tracks"), self.tracks_box)
        form.addRow(self.tr("Gate"), self.gate_box)
        form.addRow(_tr("ImportDialog", "Detected"), self.layout_label)
        self.buttons = QtWidgets.QDialogButtonBox(
            QtWidgets.QDialogButtonBox.StandardButton.Ok
            | QtWidgets.QDialogButtonBox.StandardButton.Cancel
        )
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        lay_out_dialog(
            self,
            form,
            self.preview,
            [mapping_group, self.notes_label, self.warning_label],
            self.buttons,
            520,
        )
        self.path_edit.textChanged.connect(self.refresh)
        self.encoding_box.currentTextChanged.connect(self.refresh)
        self.origin_edit.editingFinished.connect(self._changed)
        self.refresh()

    def _browse(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self,
            _tr("MainWindow", "Open bearings"),
            "",
            "CSV (*.csv *.txt *.tsv *.gz *.bz2 *.xz *.zst *.zip);;All files (*)",
        )
        if path:
            self.path_edit.setText(path)

    def _encoding(self) -> str | None:
        enc = self.encoding_box.currentText().strip()
        return None if enc in ("", "auto", _tr("ImportDialog", "auto")) else enc

    def _origin(self) -> str | None:
        return self.origin_edit.text().strip() or None

    def _inspect(self, mapping: list[str] | None) -> dict:
        path = Path(self.path_edit.text())
        if not path.is_file():
            return {}
        try:
            return inspect_bearings(path, mapping, self._origin(), self._encoding())
        except (InputError, OSError) as exc:
            return {"problem": str(exc), "columns": [], "preview": [], "mapping": {}}

    def refresh(self) -> None:
        """Read the file's first rows again (file or encoding changed): the boxes take
        what the names or a known layout give; the operator's choices are dropped."""
        self._info = self._inspect(None)
        info = self._info
        text = ""
        if info.get("columns"):
            sep = "\t" if info.get("delimiter") == "\t" else (info.get("delimiter") or ",") + " "
            rows = [info["columns"]] if info.get("header") else []
            text = "\n".join(sep.join(r) for r in rows + info["preview"])
        self.preview.setPlainText(text)
        self._updating = True
        joined = [v for v in info.get("mapping", {}).values() if "+" in v]
        for name, box in self.mapping_boxes.items():
            box.clear()
            box.addItem(NONE)
            if name == "batch":
                box.addItems(joined)  # a known layout's series of two columns (A+B)
            box.addItems(info.get("columns", []))
            box.setEnabled(bool(info.get("columns")))
            chosen = info.get("mapping", {}).get(name)
            box.setCurrentIndex(max(box.findText(chosen), 0) if chosen else 0)
        self._updating = False
        self._show(info)

    def _changed(self) -> None:
        if self._updating:
            return
        self._show(self._inspect(self.options()["mapping"]))

    def _show(self, info: dict) -> None:
        if info.get("layout"):
            self.layout_label.setText(info["layout"])
        elif info.get("columns"):
            self.layout_label.setText(self.tr("columns by their names"))
        else:
            self.layout_label.setText("")
        self.notes_label.setText("\n".join(shown(n) for n in info.get("notes", [])))
        problem = info.get("problem")
        self.warning_label.setText(shown(problem) if problem else "")
        ok = self.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        ok.setEnabled(bool(info.get("columns")) and not problem)

    def mapping(self) -> dict[str, str]:
        """Bearing field → the file's column (``A+B``: two joined), as the boxes hold it."""
        return {
            name: box.currentText()
            for name, box in self.mapping_boxes.items()
            if box.currentIndex() > 0 and box.currentText() != NONE
        }

    def options(self) -> dict:
        """``read_bearing_file``'s keywords: ``mapping`` (``field=column`` items),
        ``origin`` (``"LAT,LON"`` or None), ``encoding`` (None: detected)."""
        return {
            "mapping": [f"{k}={v}" for k, v in self.mapping().items()],
            "origin": self._origin(),
            "encoding": self._encoding(),
        }

    def gate(self) -> dict:
        """``{"tracks": layer id, "gate_deg": …}`` when a track layer is chosen, else {}."""
        lid = self.tracks_box.currentData()
        return {"tracks": lid, "gate_deg": self.gate_box.value()} if lid else {}

    def path(self) -> Path:
        return Path(self.path_edit.text())

"""The import dialog: pick a file, see its first rows, the detected layout and column
mapping, change the mapping from the file's own columns, choose encoding, time zone and the lines above the
header (a title longer than the detection reaches).

Self-contained (core objects only). ``options()`` returns the keyword arguments of
:func:`wakeline.core.io.read_points`: ``read_points(**dialog.options())``.
"""

from pathlib import Path

import shiboken6
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.core_text import shown
from wakeline.core.errors import InputError
from wakeline.core.io import FAMILIES, inspect_file
from wakeline.core.io.formats import MAP_FIELDS
from wakeline.core.io.reader import FILE_BATCH

NONE = "—"
ENCODINGS = ("auto", "utf-8", "gb18030", "utf-16", "latin-1")
#: Offered zones (the box is editable: any IANA name or ±HH:MM is accepted).
ZONES = (
    "UTC",
    "Asia/Shanghai",
    "+08:00",
    "Asia/Tokyo",
    "Europe/Oslo",
    "Europe/Copenhagen",
    "America/New_York",
)


def _choices(items: tuple[tuple[str, str], ...], tip: str) -> QtWidgets.QComboBox:
    """A box of (value, shown text) choices, the first chosen, with tooltip ``tip``
    (``currentData()`` is the chosen value: a ``read_points`` keyword's)."""
    box = QtWidgets.QComboBox()
    for value, text in items:
        box.addItem(text, value)
    box.setToolTip(tip)
    return box


def _tr(text: str) -> str:
    """``text`` in the import dialog's translation context (shared with the bearing one)."""
    return QtCore.QCoreApplication.translate("ImportDialog", text)


def origin_edit() -> QtWidgets.QLineEdit:
    """The origin field of a file whose positions are metres on a local plane, as
    ``--origin LAT,LON`` (the track and the bearing import dialogs)."""
    edit = QtWidgets.QLineEdit()
    edit.setPlaceholderText(_tr("LAT, LON (only for x/y metres)"))
    edit.setToolTip(
        _tr(
            "Latitude and longitude (degrees) of the point a file's x/y or east/north "
            "metres are measured from: the radar's site or the frame's zero."
        )
    )
    return edit


def field_labels() -> dict[str, str]:
    """The mapping's fields as the dialogs label them, in the current language beside the
    field's name ("经度 lon", as the errors name a missing column; English: the name),
    operator test 6 (D-i18n-2)."""
    return {
        "sensor": QtCore.QCoreApplication.translate("FieldName", "sensor"),
        "batch": QtCore.QCoreApplication.translate("FieldName", "batch"),
        "time": QtCore.QCoreApplication.translate("FieldName", "time"),
        "lon": QtCore.QCoreApplication.translate("FieldName", "lon"),
        "lat": QtCore.QCoreApplication.translate("FieldName", "lat"),
        "speed": QtCore.QCoreApplication.translate("FieldName", "speed"),
        "course": QtCore.QCoreApplication.translate("FieldName", "course"),
        "truth": QtCore.QCoreApplication.translate("FieldName", "truth"),
        "east": QtCore.QCoreApplication.translate("FieldName", "east"),
        "north": QtCore.QCoreApplication.translate("FieldName", "north"),
        "east_offset": QtCore.QCoreApplication.translate("FieldName", "east_offset"),
        "north_offset": QtCore.QCoreApplication.translate("FieldName", "north_offset"),
        "range": QtCore.QCoreApplication.translate("FieldName", "range"),
        "bearing": QtCore.QCoreApplication.translate("FieldName", "bearing"),
        "gps_week": QtCore.QCoreApplication.translate("FieldName", "gps_week"),
        "gps_seconds": QtCore.QCoreApplication.translate("FieldName", "gps_seconds"),
        "target": QtCore.QCoreApplication.translate("FieldName", "target"),
        "obs_lon": QtCore.QCoreApplication.translate("FieldName", "obs_lon"),
        "obs_lat": QtCore.QCoreApplication.translate("FieldName", "obs_lat"),
        "obs_east": QtCore.QCoreApplication.translate("FieldName", "obs_east"),
        "obs_north": QtCore.QCoreApplication.translate("FieldName", "obs_north"),
    }


def mapping_group_of(
    fields: tuple[str, ...], changed
) -> tuple[dict[str, QtWidgets.QComboBox], QtWidgets.QGroupBox]:
    """One box per field (``--map``'s fields: the track reader's or the bearing reader's),
    each to list the file's columns (never free text), in a "Column mapping" group;
    ``changed`` is called when one is changed."""
    boxes: dict[str, QtWidgets.QComboBox] = {}
    form = QtWidgets.QFormLayout()
    labels = field_labels()
    for name in fields:
        box = QtWidgets.QComboBox()
        box.currentIndexChanged.connect(changed)
        boxes[name] = box
        form.addRow(labels.get(name, name), box)
    group = QtWidgets.QGroupBox(_tr("Column mapping"))
    group.setLayout(form)
    return boxes, group


def lay_out_dialog(
    dialog: QtWidgets.QDialog,
    form: QtWidgets.QLayout,
    preview: QtWidgets.QWidget,
    right_widgets: list[QtWidgets.QWidget],
    buttons: QtWidgets.QWidget,
    height: int,
) -> None:
    """The file dialogs' common body: the form and the file's first rows on the left
    (3 parts), the mapping group and notes on the right (2 parts), the buttons below."""
    left = QtWidgets.QVBoxLayout()
    left.addLayout(form)
    left.addWidget(QtWidgets.QLabel(_tr("First rows of the file:")))
    left.addWidget(preview, 1)
    right = QtWidgets.QVBoxLayout()
    for widget in right_widgets:
        right.addWidget(widget)
    right.addStretch(1)
    body = QtWidgets.QHBoxLayout()
    body.addLayout(left, 3)
    body.addLayout(right, 2)
    lay = QtWidgets.QVBoxLayout(dialog)
    lay.addLayout(body, 1)
    lay.addWidget(buttons)
    dialog.resize(1000, height)


class ImportDialog(QtWidgets.QDialog):
    """Pick a file; see its first rows; choose layout, encoding, column mapping, zone."""

    def __init__(self, parent=None, path: Path | None = None, executor=None) -> None:
        super().__init__(parent)
        self.setWindowTitle(self.tr("Import tracks"))
        #: ``executor(job, done)``: runs the preview read of the first rows (40–130 ms on a
        #: loaded machine) off the GUI thread and calls ``done(result)`` on it (the
        #: window's LodWorker); None: read here (a dialog of its own, tests).
        self.executor = executor
        self._preview_key = None  # the file and options the preview shown was read with
        self._preview_said: dict | None = None
        self._preview_wanted = None  # those of the read asked for last (None: none asked)
        self._info: dict = {}
        self._missing: list[str] = []  # required fields no column is mapped to
        self._updating = False
        self.path_edit = QtWidgets.QLineEdit(str(path or ""))
        browse = QtWidgets.QPushButton(self.tr("Browse…"))
        browse.clicked.connect(self._browse)
        # "auto" shown in the window's language, the value kept as the item's data
        self.format_box = QtWidgets.QComboBox()
        for family in FAMILIES:
            self.format_box.addItem(self.tr("auto") if family == "auto" else family, family)
        self.encoding_box = QtWidgets.QComboBox()
        for enc in ENCODINGS:
            self.encoding_box.addItem(self.tr("auto") if enc == "auto" else enc, enc)
        self.encoding_box.setEditable(True)
        self.tz_box = QtWidgets.QComboBox()
        self.tz_box.setEditable(True)
        self.tz_box.addItems(list(ZONES))
        self.tz_box.setToolTip(
            self.tr(
                "Zone of times written without one (IANA name or ±HH:MM). "
                "Unix times are absolute and not shifted."
            )
        )
        # Lines before the header (a title block): -1 shows "auto" (detected, as import
        # without --skip-rows); N skips N physical lines, as `--skip-rows N`.
        self.skip_box = QtWidgets.QSpinBox()
        self.skip_box.setRange(-1, 100000)
        self.skip_box.setValue(-1)
        self.skip_box.setSpecialValueText(self.tr("auto"))
        self.skip_box.setToolTip(
            self.tr(
                "Lines before the header (a title or notes), skipped and counted; auto finds "
                "a title of up to 10 lines above a header naming known columns."
            )
        )
        # A file whose positions are metres on a local plane (x/y, east/north): where
        # they are measured from, as `--origin LAT,LON`.
        self.origin_edit = origin_edit()
        # How slashed dates read (03/04/2025), as `--date-order`.
        self.date_order_box = _choices(
            (
                ("auto", self.tr("auto")),
                ("day-first", self.tr("day first (dd/mm/yyyy)")),
                ("month-first", self.tr("month first (mm/dd/yyyy)")),
            ),
            self.tr(
                "How dates like 03/04/2025 read: auto reads them day first unless a date "
                "shows the month first (a second number above 12); the import says what "
                "decided it."
            ),
        )
        # What numbers in the time column count, as `--time-unit`.
        self.time_unit_box = _choices(
            (
                ("auto", self.tr("auto")),
                ("seconds", self.tr("seconds")),
                ("excel-days", self.tr("Excel serial days")),
            ),
            self.tr(
                "Numbers in the time column: seconds (unix, or from a scene start) or Excel "
                "serial days (45658.5 is 2025-01-01 12:00). Auto takes Excel days when all "
                "lie between 20000 and 80000 and the header says so or they step less than "
                "0.01 between rows; the import says which it read."
            ),
        )
        # The units of a speed column and of x/y metres whose headers name none, as
        # `--speed-unit` and `--distance-unit` (a header such as speed_mps names its own).
        self.speed_unit_box = _choices(
            (
                ("auto", self.tr("auto (knots)")),
                ("knots", self.tr("knots")),
                ("m/s", self.tr("m/s")),
                ("km/h", self.tr("km/h")),
                ("mph", self.tr("mph")),
            ),
            self.tr(
                "Unit of a speed column whose header names none; a header such as speed_mps, "
                "sog_kmh or Speed (m/s) names its own. Speeds are converted to knots."
            ),
        )
        self.distance_unit_box = _choices(
            (
                ("auto", self.tr("auto (metres)")),
                ("m", self.tr("metres")),
                ("km", self.tr("km")),
                ("nm", self.tr("nautical miles")),
                ("yd", self.tr("yards")),
            ),
            self.tr(
                "Unit of x/y, offsets and range on a local plane whose headers name none; "
                "a header such as x_km, range_nm or y_yd names its own."
            ),
        )
        # The day of times of day written without a date (a radar's log), as `--date`.
        self.date_edit = QtWidgets.QLineEdit()
        self.date_edit.setPlaceholderText(self.tr("YYYY-MM-DD (only for times without a date)"))
        self.date_edit.setToolTip(
            self.tr(
                "The day of times written without a date (23:50:00.5): they are read on it, "
                "a day later after each step back past midnight within a track. Empty: "
                "1970-01-01, as relative times."
            )
        )
        self.date_edit.textChanged.connect(self._update_warning)
        self.sensor_edit = QtWidgets.QLineEdit()
        self.sensor_edit.setPlaceholderText(self.tr("sensor name when the file has none"))
        self.layout_label = QtWidgets.QLabel()
        self.layout_label.setWordWrap(True)

        # One row per canonical field: a list of the file's columns (never free text).
        # MAP_FIELDS: the track fields plus gps_week, gps_seconds (a GPS time for time)
        self.mapping_boxes, mapping_group = mapping_group_of(MAP_FIELDS, self._mapping_changed)
        self.extra_label = QtWidgets.QLabel()
        self.extra_label.setWordWrap(True)
        self.warning_label = QtWidgets.QLabel()
        self.warning_label.setWordWrap(True)
        self.warning_label.setStyleSheet("color: #b35900")
        # What a read of the first rows says (its warnings, the rows it would quarantine)
        # while the dialog is open: the log said it after OK (operator test 9, D11).
        self.read_label = QtWidgets.QLabel()
        self.read_label.setWordWrap(True)
        self.read_label.setStyleSheet("color: #b35900")
        self.read_label.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)

        self.preview = QtWidgets.QPlainTextEdit(readOnly=True)
        self.preview.setLineWrapMode(QtWidgets.QPlainTextEdit.LineWrapMode.NoWrap)
        self.preview.setFont(
            QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        )

        form = QtWidgets.QFormLayout()
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.path_edit, 1)
        row.addWidget(browse)
        form.addRow(self.tr("File"), row)
        form.addRow(self.tr("Layout"), self.format_box)
        form.addRow(self.tr("Encoding"), self.encoding_box)
        form.addRow(self.tr("Time zone"), self.tz_box)
        form.addRow(self.tr("Lines above the header"), self.skip_box)
        form.addRow(self.tr("Origin of x/y metres"), self.origin_edit)
        form.addRow(self.tr("Date order"), self.date_order_box)
        form.addRow(self.tr("Time numbers"), self.time_unit_box)
        form.addRow(self.tr("Speed unit"), self.speed_unit_box)
        form.addRow(self.tr("Distance unit"), self.distance_unit_box)
        form.addRow(self.tr("Date of clock times"), self.date_edit)
        form.addRow(self.tr("Sensor"), self.sensor_edit)
        form.addRow(self.tr("Detected"), self.layout_label)
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
            [mapping_group, self.extra_label, self.warning_label, self.read_label],
            self.buttons,
            560,
        )

        self.path_edit.textChanged.connect(self.refresh)
        self.format_box.currentIndexChanged.connect(self.refresh)
        self.encoding_box.currentTextChanged.connect(self.refresh)
        self.skip_box.valueChanged.connect(self.refresh)
        self.origin_edit.editingFinished.connect(self._origin_changed)
        self.tz_box.currentTextChanged.connect(self._update_warning)
        for box in (self.date_order_box, self.time_unit_box, self.speed_unit_box):
            box.currentIndexChanged.connect(self._update_warning)
        self.refresh()

    # -- detection ---------------------------------------------------------------------

    def _browse(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self,
            self.tr("Open track file"),
            "",
            "Track files (*.csv *.txt *.tsv *.nmea *.log *.gpx *.geojson *.gz *.bz2 *.xz *.zst *.zip);;"
            "All files (*)",
        )
        if path:
            self.path_edit.setText(path)

    def _encoding(self) -> str | None:
        enc = self.encoding_box.currentText().strip()
        return None if enc in ("", "auto", self.tr("auto")) else enc

    def _format(self) -> str:
        """The layout chosen (``auto``: detected), whatever the language shows."""
        return str(self.format_box.currentData() or self.format_box.currentText())

    def _skip_rows(self) -> int | None:
        """Lines before the header as chosen; None: detected ("auto")."""
        value = self.skip_box.value()
        return None if value < 0 else value

    def _origin(self) -> str | None:
        return self.origin_edit.text().strip() or None

    def _clock_date(self) -> str | None:
        """The Date field as YYYY-MM-DD; None when empty or not a date."""
        from wakeline.core.io.timetext import check_clock_date

        try:
            return check_clock_date(self.date_edit.text())
        except InputError:
            return None

    def _origin_changed(self) -> None:
        self._recheck()
        self._update_warning()

    def refresh(self) -> None:
        """Detect the layout and mapping again (file, layout, encoding or the lines above
        the header changed); the operator's own choices are dropped."""
        path = Path(self.path_edit.text())
        self._info = {}
        text, problem = "", None
        if path.is_file():
            try:
                self._info = inspect_file(
                    path,
                    fmt=self._format(),
                    encoding=self._encoding(),
                    skip_rows=self._skip_rows(),
                    origin=self._origin(),
                )
            except (InputError, OSError) as exc:
                problem = str(exc)
        info = self._info
        if info:
            sep = "\t" if info["delimiter"] == "\t" else info["delimiter"] + " "
            rows = [info["columns"]] if info["header"] else []
            text = "\n".join(sep.join(r) for r in rows + info["preview"])
            problem = info["problem"]
        self.preview.setPlainText(text)
        self._fill_mapping()
        if info:
            delim = {"\t": "tab", " ": "space"}.get(info["delimiter"], info["delimiter"])
            label = (
                shown(info["format_label"]) if info["format_label"] else self.tr("no layout fits")
            )
            text = f"{label}; {info['encoding']}; " + self.tr("delimiter") + f" {delim}"
            above = len(info.get("lines_above_header") or ())
            if above:
                text += "; " + self.tr("{0} line(s) above the header skipped").format(above)
            self.layout_label.setText(text)
        else:
            self.layout_label.setText("")
        # The engine's advice names command-line flags; here it names this dialog's fields.
        self._problem = shown(problem) if problem else problem
        self._missing = list(info.get("missing", [])) if info else []
        self._update_warning()

    def _fill_mapping(self) -> None:
        info = self._info
        columns = info.get("columns", []) if info.get("kind") == "csv" else []
        mapping = info.get("mapping", {})
        self._updating = True
        for name, box in self.mapping_boxes.items():
            box.clear()
            box.addItem(NONE)
            if name == "batch" and mapping.get("batch") == FILE_BATCH:
                box.addItem(FILE_BATCH)
            box.addItems(columns)
            box.setEnabled(bool(columns))
            chosen = mapping.get(name)
            box.setCurrentIndex(max(box.findText(chosen), 0) if chosen else 0)
        self._updating = False
        self._update_extra()

    def _mapping_changed(self) -> None:
        if not self._updating:
            self._update_extra()
            self._recheck()
            self._update_warning()

    def _recheck(self) -> None:
        """Why an import would fail with the mapping as the boxes now hold it (the
        detection's "missing required column" stayed after the operator mapped every
        column of a headerless file)."""
        path = Path(self.path_edit.text())
        if not self._info or self._info.get("kind") != "csv" or not path.is_file():
            return
        try:
            info = inspect_file(
                path,
                fmt=self._format(),
                mapping=self.mapping() or None,
                encoding=self._encoding(),
                skip_rows=self._skip_rows(),
                origin=self._origin(),
            )
        except (InputError, OSError) as exc:
            problem, missing = str(exc), []
        else:
            problem, missing = info["problem"], info.get("missing", [])
        self._problem = shown(problem) if problem else None
        self._missing = [m for m in missing if m not in self.mapping()]
        if not self.mapping() and self._info.get("guessed"):
            # every box emptied: the import reads no guess (the values chose the boxes)
            self._missing = ["batch", "time", "lon", "lat"]

    def _update_extra(self) -> None:
        columns = self._info.get("columns", []) if self._info.get("kind") == "csv" else []
        used = set(self.mapping().values())
        extra = [c for c in columns if c not in used]
        self.extra_label.setText(
            self.tr("Unmapped columns (kept as extra columns): {0}").format(
                ", ".join(extra) if extra else NONE
            )
        )

    def _update_warning(self) -> None:
        from wakeline.core.io.formats import header_is_local

        problems = []
        if getattr(self, "_problem", None):
            problems.append(self._problem)
        time_col = self.mapping().get("time")
        zone = self.tz_box.currentText().strip()
        if time_col and header_is_local(time_col) and zone.upper() in ("", "UTC"):
            problems.append(
                self.tr(
                    "The time column {0} holds local times: choose their time zone, or they "
                    "are read as UTC."
                ).format(time_col)
            )
        guessed = self._info.get("guessed")
        if guessed and self.mapping() == guessed["mapping"]:
            problems.append(
                self.tr(
                    "The file has no header: its columns were chosen by their values. Check "
                    "them against the first rows."
                )
                + (
                    ""
                    if guessed["lon_lat_seen"]
                    else " "
                    + self.tr(
                        "Which degree column is longitude ({0} or {1}) does not show in the "
                        "values: swap them if the tracks lie in the wrong place."
                    ).format(guessed["mapping"]["lon"], guessed["mapping"]["lat"])
                )
            )
        if self._missing:  # no layout fits: the fields recognised are mapped, these are not
            problems.append(
                self.tr("Required fields still without a column: {0}.").format(
                    ", ".join(field_labels().get(m, m) for m in self._missing)
                )
            )
        elif (
            time_col is None
            and "gps_seconds" not in self.mapping()
            and self._info.get("kind") == "csv"
        ):
            problems.append(self.tr("Choose the time column."))
        day = self.date_edit.text().strip()
        if day and self._clock_date() is None:
            problems.append(self.tr("Date of clock times {0}: give it as YYYY-MM-DD.").format(day))
        elif not day and self._info.get("clock_only") and time_col == self._info["clock_only"]:
            problems.append(
                self.tr(
                    "The times in {0} are times of day without a date: give their Date of "
                    "clock times, or they are read on 1970-01-01 as relative times."
                ).format(time_col)
            )
        said, refused = [], None
        if not self._missing and not getattr(self, "_problem", None):
            said, refused = self._preview_lines()
            if not said and self.preview_pending:  # the worker reads them (executor)
                said = [self.tr("Reading the first rows…")]
        if refused:
            problems.append(refused)
        self.warning_label.setText("\n".join(problems))
        self.read_label.setText("\n".join(said))
        # OK only once every required field has a column (D-import-12): an OK pressed
        # before failed in an error box that sent the operator back to a fresh dialog.
        # Nor while the first rows are all quarantined (a CST time needs a zone: D11).
        box = getattr(self, "buttons", None)  # (not made yet while the dialog builds)
        ok = box.button(QtWidgets.QDialogButtonBox.StandardButton.Ok) if box else None
        if ok is not None:
            ok.setEnabled(not self._missing and refused is None)
            if self._missing:
                ok.setToolTip(
                    self.tr("Map a column to each required field first: {0}").format(
                        ", ".join(field_labels().get(m, m) for m in self._missing)
                    )
                )
            else:
                ok.setToolTip(refused or "")

    def preview_read(self) -> dict | None:
        """What reading the file's first rows with the dialog's options says
        (:func:`~wakeline.core.io.preview.preview_read`), remembered per file and options.

        With an :attr:`executor` the read runs off the GUI thread: None until it comes
        back (:attr:`preview_pending`), then the warnings are shown again; a read for an
        earlier choice of file or options that comes back late is dropped."""
        from wakeline.core.io.preview import preview_read

        path = Path(self.path_edit.text())
        if not self._info or self._info.get("kind") != "csv" or not path.is_file():
            self._preview_wanted = None
            return None
        options = {k: v for k, v in self.options().items() if k != "path"}
        key = (str(path), path.stat().st_mtime_ns, repr(sorted(options.items())))
        if self._preview_key == key:
            return self._preview_said
        if self.executor is None:
            self._preview_key, self._preview_said = key, preview_read(path, **options)
            return self._preview_said
        if self._preview_wanted != key:
            self._preview_wanted = key
            self.executor(
                lambda: preview_read(path, **options),
                lambda said, key=key: self._preview_arrived(key, said),
            )
        return None

    @property
    def preview_pending(self) -> bool:
        """A read of the first rows for the file and options as they are now is running."""
        return self._preview_wanted is not None and self._preview_wanted != self._preview_key

    def _preview_arrived(self, key, said: dict | None) -> None:
        """The worker's read of the first rows (GUI thread): shown when it is for the file
        and options chosen now; dropped when they changed meanwhile (a newer read runs)."""
        if not shiboken6.isValid(self) or key != self._preview_wanted:
            return
        self._preview_key, self._preview_said = key, said
        self._update_warning()

    def _preview_lines(self) -> tuple[list[str], str | None]:
        """The warnings and quarantine reasons of a read of the first rows, in the
        window's words (the import dialog's fields, not flags), and why OK is refused
        (every row read would be quarantined) or None (operator test 9, D11)."""
        said = self.preview_read()
        if not said or not said["rows_read"]:
            return [], None
        lines = [shown(w) for w in said["warnings"]]
        reasons = sorted(said["quarantine_reasons"].items(), key=lambda kv: -kv[1])
        lines += [
            self.tr("{0} of the first {1} rows would be quarantined: {2}").format(
                f"{n:,}", f"{said['rows_read']:,}", shown(why)
            )
            for why, n in reasons
        ]
        if not lines:
            return [], None
        head = self.tr("Reading the first {0} rows:").format(f"{said['rows_read']:,}")
        refused = None
        if said["rows_imported"] == 0:
            refused = self.tr("Nothing would be imported: {0}").format(
                shown(reasons[0][0]) if reasons else ""
            )
        return [head, *(f"• {line}" for line in lines)], refused

    # -- result ------------------------------------------------------------------------

    def mapping(self) -> dict[str, str]:
        """Canonical field → the file's column, as chosen in the boxes."""
        out = {}
        for name, box in self.mapping_boxes.items():
            text = box.currentText()
            if box.currentIndex() > 0 and text not in (NONE, FILE_BATCH):
                out[name] = text
        return out

    def extra_columns(self) -> list[str]:
        """The file's columns no field takes (they travel as extra columns)."""
        used = set(self.mapping().values())
        return [c for c in self._info.get("columns", []) if c not in used]

    def options(self) -> dict:
        """Keyword arguments of ``read_points`` (``sensor`` only when one is typed;
        ``skip_rows`` None: detected; ``date_order``: auto, day-first or month-first;
        ``time_unit``: auto, seconds or excel-days; ``clock_date``: the day of times
        without a date, None: 1970-01-01; ``speed_unit``, ``distance_unit``: of columns
        whose header names none)."""
        zone = self.tz_box.currentText().strip()
        out = {
            "path": Path(self.path_edit.text()),
            "fmt": self._format(),
            "encoding": self._encoding(),
            "mapping": [f"{k}={v}" for k, v in self.mapping().items()],
            "tz": None if zone.upper() in ("", "UTC") else zone,
            "skip_rows": self._skip_rows(),
            "date_order": self.date_order_box.currentData(),
            "time_unit": self.time_unit_box.currentData(),
            "clock_date": self._clock_date(),
            "speed_unit": self.speed_unit_box.currentData(),
            "distance_unit": self.distance_unit_box.currentData(),
        }
        if self._origin():
            out["origin"] = self._origin()
        sensor = self.sensor_edit.text().strip()
        if sensor:
            out["sensor"] = sensor
        return out

    def sizeHint(self) -> QtCore.QSize:  # noqa: N802 - Qt naming
        return QtCore.QSize(1000, 560)

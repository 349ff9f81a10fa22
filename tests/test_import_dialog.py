"""The import dialog (app/import_dialog.py): detected mapping, choices from the file's
columns, time zone; options() feeds read_points directly."""

import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from conftest import DATA  # noqa: E402
from wakeline.app.import_dialog import NONE, ImportDialog  # noqa: E402
from wakeline.core.io import read_points  # noqa: E402

pytestmark = pytest.mark.gui
BATTERY = DATA / "battery"


def test_shows_detected_mapping_and_extra_columns(qtbot):
    dlg = ImportDialog(path=BATTERY / "chinese_gb18030.csv")
    qtbot.addWidget(dlg)
    assert dlg.mapping() == {
        "batch": "MMSI",
        "time": "Unix时间戳",
        "lon": "经度",
        "lat": "纬度",
        "speed": "航速",
        "course": "航向",
    }
    assert dlg.extra_columns() == ["时间(Local)", "船首向", "船名"]
    assert "船名" in dlg.extra_label.text()
    assert "gb18030" in dlg.layout_label.text()
    box = dlg.mapping_boxes["time"]
    items = [box.itemText(i) for i in range(box.count())]
    assert items[0] == NONE and items[1:] == [
        "时间(Local)",
        "Unix时间戳",
        "MMSI",
        "纬度",
        "经度",
        "航速",
        "航向",
        "船首向",
        "船名",
    ]
    assert not box.isEditable()  # a list of the file's columns, not free text


def test_changing_the_mapping_and_zone_reaches_read_points(qtbot):
    dlg = ImportDialog(path=BATTERY / "chinese_gb18030.csv")
    qtbot.addWidget(dlg)
    dlg.mapping_boxes["time"].setCurrentText("时间(Local)")
    assert "local times" in dlg.warning_label.text()
    assert "时间(Local)" not in dlg.extra_columns() and "Unix时间戳" in dlg.extra_columns()
    dlg.tz_box.setCurrentText("Asia/Shanghai")
    assert dlg.warning_label.text() == ""
    opts = dlg.options()
    assert opts["tz"] == "Asia/Shanghai" and "time=时间(Local)" in opts["mapping"]
    result = read_points(**opts)
    assert result.report["columns"]["time"] == "时间(Local)"
    # 08:00 in Shanghai is 00:00 UTC, as the unix column says
    assert result.points["time"].iloc[0] == pd.Timestamp("2024-01-01T00:00:00Z")


def test_unreadable_file_and_nmea(qtbot, write):
    dlg = ImportDialog(path=write("empty.csv", ""))
    qtbot.addWidget(dlg)
    assert "empty" in dlg.warning_label.text()
    dlg.path_edit.setText(str(BATTERY / "ais_log.nmea"))
    assert "NMEA" in dlg.layout_label.text()
    assert dlg.mapping() == {}
    assert len(read_points(**dlg.options()).points) == 2
    from test_gpx_import import OPENCPN

    dlg.path_edit.setText(str(write("track.gpx", OPENCPN)))
    assert "GPX" in dlg.layout_label.text()
    assert dlg.mapping() == {} and not dlg.warning_label.text()
    assert len(read_points(**dlg.options()).points) == 5


def test_lines_above_the_header_reach_preview_mapping_and_read_points(qtbot, write):
    """A file with 12 lines of notes above its header (past the detection's 10 lines): on
    "auto" the dialog shows the notes as the header and the error names the dialog's field;
    with 12 lines above the header, the preview starts at the header, the mapping is the
    file's and read_points(**options()) counts every line."""
    from test_skip_rows_everywhere import NOTES, ROWS, _titled_text

    path = write("titled.csv", _titled_text())
    dlg = ImportDialog(path=path)
    qtbot.addWidget(dlg)
    assert dlg.skip_box.text() == "auto" and dlg.options()["skip_rows"] is None
    assert dlg.mapping().get("time") is None
    assert "Lines above the header field" in dlg.warning_label.text()
    dlg.skip_box.setValue(NOTES)
    assert dlg.preview.toPlainText().startswith("track_id, time, lon, lat")
    assert f"{NOTES} line(s) above the header skipped" in dlg.layout_label.text()
    assert dlg.mapping() == {
        "batch": "track_id",
        "time": "time",
        "lon": "lon",
        "lat": "lat",
        "speed": "speed",
        "course": "course",
    }
    assert dlg.warning_label.text() == ""
    rep = read_points(**dlg.options()).report
    assert len(rep["lines_above_header"]) == NOTES and rep["blank_lines"] == 1
    assert rep["rows_imported"] == ROWS - 1 and rep["rows_quarantined"] == 1
    lines = len(path.read_text().splitlines())
    assert rep["rows_imported"] + rep["rows_quarantined"] + NOTES + 1 + 1 == lines


def test_file_open_passes_the_lines_above_the_header_to_the_import(window, write, monkeypatch):
    """File ▸ Open tracks…: the dialog's lines above the header reach the import job
    (``load_file(**dialog.options())``); the layer's report counts the 12 lines."""
    from PySide6 import QtWidgets
    from test_skip_rows_everywhere import NOTES, ROWS, _titled_text

    from wakeline.app import main_window
    from wakeline.app.main import wait_for_jobs

    path = write("titled.csv", _titled_text())

    class Chosen(ImportDialog):
        def exec(self):
            self.path_edit.setText(str(path))
            self.skip_box.setValue(NOTES)
            return QtWidgets.QDialog.DialogCode.Accepted

    monkeypatch.setattr(main_window, "ImportDialog", Chosen)
    window.open_dialog()
    wait_for_jobs(window)
    layer = window.session.get(window.layer_id(path.name))
    rep = layer.meta["report"]
    assert len(layer.points) == ROWS - 1 and len(rep["lines_above_header"]) == NOTES
    assert rep["skip_rows_given"] == NOTES


def test_lines_above_the_header_past_the_end_show_the_message(qtbot, write):
    """Lines above the header at or past the file's end: the dialog shows the refusal
    with the file's line count (was: the last line read as the header), and a count
    back inside the file reads again."""
    path = write("short.csv", "batch,time,lon,lat\n1,1714521600,10.0,57.0\n")
    dlg = ImportDialog(path=path)
    qtbot.addWidget(dlg)
    dlg.skip_box.setValue(100)
    warning = dlg.warning_label.text()
    assert "Lines above the header field: the file has 2 lines" in warning, warning
    assert dlg.preview.toPlainText() == "" and dlg.mapping() == {}
    dlg.skip_box.setValue(0)
    assert dlg.warning_label.text() == "" and dlg.mapping()["time"] == "time"


def test_file_open_with_lines_past_the_end_tells_the_operator(window, write, monkeypatch):
    """File ▸ Open tracks… accepted with more lines above the header than the file has:
    the import is refused with a message naming the dialog's field and the line count
    (no layer, no crash)."""
    from PySide6 import QtWidgets

    from wakeline.app import main_window
    from wakeline.app.main import wait_for_jobs

    path = write("short.csv", "batch,time,lon,lat\n1,1714521600,10.0,57.0\n")
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))

    class Chosen(ImportDialog):
        def exec(self):
            self.path_edit.setText(str(path))
            self.skip_box.setValue(100)
            return QtWidgets.QDialog.DialogCode.Accepted

    monkeypatch.setattr(main_window, "ImportDialog", Chosen)
    window.open_dialog()
    wait_for_jobs(window)
    assert window.layer_id(path.name) is None
    assert shown and "Lines above the header field" in shown[-1]
    assert "the file has 2 lines" in shown[-1]


def test_the_dialogs_advice_names_its_own_fields_not_cli_flags(qtbot, write):
    """Operator test (Autoferry detections.csv.gz: local metres, no track id): the
    dialog's warning told a window user to "map columns with --map field=column" and
    "skip the lines above it with --skip-rows N"."""
    head = "scenario,scan,time,sensor_id,sensor,own_north,own_east,k,meas_north,meas_east\n"
    rows = "".join(
        f"2,{k},{1620114891.8 + k},2,radar,-16.6,-390.4,0,{k}.5,-3.25\n" for k in range(9)
    )
    dlg = ImportDialog(path=write("detections.csv", head + rows))
    qtbot.addWidget(dlg)
    warning = dlg.warning_label.text()
    # Since the local-plane reading: the metres are recognised and the origin asked for.
    assert "'meas_east' east, 'meas_north' north" in warning, warning
    assert "--" not in warning, warning
    assert "Origin of x/y metres field" in warning, warning
    assert "without a column" not in warning, warning  # the file names its one track
    # A file with neither positions nor metres still gets the mapping advice.
    dlg = ImportDialog(path=write("plots.csv", head.replace("meas_", "m_") + rows))
    qtbot.addWidget(dlg)
    warning = dlg.warning_label.text()
    assert "missing required column" in warning and "--" not in warning, warning
    assert "map the columns in the import dialog" in warning, warning


def test_the_warning_follows_the_mapping(qtbot, write):
    """Operator test (Saronic vessels.csv: no header, "batch lon lat unix-time"): after
    mapping col1..col4 the dialog still said "missing required column batch, time, lon,
    lat" (the detection's verdict), though OK then imported all 18,834 rows."""
    rows = "".join(f"{k % 3} 23.{k:05d} 37.5 {1722468684 + 60 * k}\n" for k in range(30))
    dlg = ImportDialog(path=write("vessels.csv", rows))
    qtbot.addWidget(dlg)
    # Since session 23 the columns are chosen by their values, and the operator is told
    # to check them (lon/lat: both within ±90, so the order is a guess).
    guess = {"batch": "col1", "lon": "col2", "lat": "col3", "time": "col4"}
    assert dlg.mapping() == guess
    warning = dlg.warning_label.text()
    assert "no header" in warning and "col2 or col3" in warning, warning
    for field in guess:
        dlg.mapping_boxes[field].setCurrentIndex(0)
    assert "without a column: batch, time, lon, lat" in dlg.warning_label.text()
    for field, col in (("batch", "col1"), ("lon", "col3"), ("lat", "col2"), ("time", "col4")):
        box = dlg.mapping_boxes[field]
        box.setCurrentIndex(box.findText(col))
    assert dlg.warning_label.text() == "", dlg.warning_label.text()
    assert read_points(**dlg.options()).report["rows_imported"] == 30
    box = dlg.mapping_boxes["lat"]  # unmapped again: the reason comes back
    box.setCurrentIndex(0)
    assert "lat" in dlg.warning_label.text() and "missing" in dlg.warning_label.text()


def test_no_layout_fits_yet_the_recognised_fields_are_mapped(qtbot, write):
    """Operator test (Autoferry detections.csv.gz in File > Open): no layout fits (local
    metres, no track id), and the dialog left every box empty, not even time -> time or
    sensor -> sensor, saying only "Choose the time column." The fields the synonym table
    knows are mapped; the warning names the required ones still missing. (Since the
    local-plane reading, meas_east/meas_north are known metres: here renamed to names no
    table knows.)"""
    from wakeline.core.io import inspect_file

    head = "scenario,scan,time,sensor_id,sensor,own_n,own_e,k,meas_north,meas_east\n"
    head = head.replace("meas_north", "rn").replace("meas_east", "re")
    rows = "".join(
        f"2,{k},{1620114891.8 + k},2,radar,-16.6,-390.4,0,{k}.5,-3.25\n" for k in range(9)
    )
    path = write("detections.csv", head + rows)
    info = inspect_file(path)
    assert info["problem"] and info["missing"] == ["batch", "lon", "lat"]
    assert info["mapping"] == {"sensor": "sensor", "time": "time"}
    dlg = ImportDialog(path=path)
    qtbot.addWidget(dlg)
    assert dlg.mapping() == {"sensor": "sensor", "time": "time"}
    warning = dlg.warning_label.text()
    assert "Required fields still without a column: batch, lon, lat." in warning, warning
    assert "Choose the time column" not in warning
    for field, col in (("batch", "scan"), ("lon", "re")):
        box = dlg.mapping_boxes[field]
        box.setCurrentIndex(box.findText(col))
    assert "without a column: lat." in dlg.warning_label.text(), dlg.warning_label.text()
    box = dlg.mapping_boxes["lat"]
    box.setCurrentIndex(box.findText("rn"))
    assert dlg.warning_label.text() == "", dlg.warning_label.text()


def test_the_real_autoferry_detections_map_time_and_sensor(qtbot):
    from conftest import real_file

    dlg = ImportDialog(path=real_file("autoferry-fusion", "detections.csv.gz"))
    qtbot.addWidget(dlg)
    assert dlg.mapping() == {
        "sensor": "sensor",
        "time": "time",
        "east": "meas_east",
        "north": "meas_north",
        "east_offset": "own_east",
        "north_offset": "own_north",
    }
    assert "Origin of x/y metres" in dlg.warning_label.text()  # Piren's origin: SOURCE.md
    dlg.origin_edit.setText("63.4389029083,10.39908278")
    dlg.origin_edit.editingFinished.emit()
    assert dlg.warning_label.text() == "", dlg.warning_label.text()


def test_x_y_metres_ask_for_the_origin_and_it_reaches_read_points(qtbot, tmp_path):
    path = tmp_path / "radar_xy.csv"
    path.write_text("time,track,x,y\n" + "".join(f"{1e9 + k},1,{3 * k},{k}\n" for k in range(20)))
    dlg = ImportDialog(path=path)
    qtbot.addWidget(dlg)
    assert dlg.mapping()["east"] == "x" and dlg.mapping()["north"] == "y"
    warning = dlg.warning_label.text()
    assert "Origin of x/y metres" in warning and "--origin" not in warning
    dlg.origin_edit.setText("63.4389, 10.3991")
    dlg.origin_edit.editingFinished.emit()
    assert dlg.warning_label.text() == ""
    opts = dlg.options()
    assert opts["origin"] == "63.4389, 10.3991"
    result = read_points(**opts)
    assert result.report["rows_imported"] == 20 and result.report["plane_origin"] == [
        63.4389,
        10.3991,
    ]


def test_the_date_order_and_time_numbers_reach_read_points(qtbot, write):
    rows = "".join(f"1,03/{k + 1:02d}/2025 08:00:00,57.{k},11.{k}\n" for k in range(9))
    dlg = ImportDialog(path=write("us.csv", "MMSI,BaseDateTime,LAT,LON\n" + rows))
    qtbot.addWidget(dlg)
    assert dlg.options()["date_order"] == "auto" and dlg.options()["time_unit"] == "auto"
    dlg.date_order_box.setCurrentIndex(dlg.date_order_box.findData("month-first"))
    dlg.time_unit_box.setCurrentIndex(dlg.time_unit_box.findData("seconds"))
    opts = dlg.options()
    assert opts["date_order"] == "month-first" and opts["time_unit"] == "seconds"
    got = read_points(**opts).points["time"]
    assert got.dt.month.unique().tolist() == [3]  # 03/01 ... 03/09: March, not day 3


def test_times_of_day_alone_ask_for_their_date_and_it_reaches_the_import(
    window, write, monkeypatch
):
    """A radar log of times of day (23:50:00.5): the dialog says to give their date; the
    Date of clock times field reaches read_points through File ▸ Open (``clock_date``)."""
    from PySide6 import QtWidgets

    from wakeline.app import main_window
    from wakeline.app.main import wait_for_jobs

    rows = "".join(f"23:5{k}:00.5,{1 + k % 2},37.9{k},23.6{k}\n" for k in range(8))
    path = write("tod.csv", "Time,Track,Lat,Lon\n" + rows)
    dlg = ImportDialog(path=path)
    assert "times of day without a date" in dlg.warning_label.text()
    dlg.date_edit.setText("2024-13-01")
    assert "YYYY-MM-DD" in dlg.warning_label.text() and dlg.options()["clock_date"] is None
    dlg.date_edit.setText("2024-03-05")
    assert dlg.warning_label.text() == "" and dlg.options()["clock_date"] == "2024-03-05"
    dlg.deleteLater()

    class Chosen(ImportDialog):
        def exec(self):
            self.path_edit.setText(str(path))
            self.date_edit.setText("2024-03-05")
            return QtWidgets.QDialog.DialogCode.Accepted

    monkeypatch.setattr(main_window, "ImportDialog", Chosen)
    window.open_dialog()
    wait_for_jobs(window)
    layer = window.session.get(window.layer_id(path.name))
    assert layer.meta["report"]["clock_date"] == "2024-03-05"
    assert layer.points["time"].min() == pd.Timestamp("2024-03-05T23:50:00.5Z")


def test_a_zipped_file_previews_and_opens_as_the_plain_one(qtbot, window, tmp_path, monkeypatch):
    """A zip of one CSV (as MarineCadastre and the Danish Maritime Authority ship a day):
    the dialog's preview, layout and mapping are the plain file's, and File ▸ Open imports
    it (the report says zip; the layer keeps the layout export "as it came in" writes)."""
    import zipfile

    from PySide6 import QtWidgets

    from wakeline.app import main_window
    from wakeline.app.main import wait_for_jobs

    src = BATTERY / "chinese_gb18030.csv"
    packed = tmp_path / "day.zip"
    with zipfile.ZipFile(packed, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.write(src, "day/chinese_gb18030.csv")
    plain, dlg = ImportDialog(path=src), ImportDialog(path=packed)
    qtbot.addWidget(plain)
    qtbot.addWidget(dlg)
    assert dlg.preview.toPlainText() == plain.preview.toPlainText() != ""
    assert dlg.mapping() == plain.mapping() and dlg.warning_label.text() == ""
    assert "gb18030" in dlg.layout_label.text()

    class Chosen(ImportDialog):
        def exec(self):
            self.path_edit.setText(str(packed))
            return QtWidgets.QDialog.DialogCode.Accepted

    monkeypatch.setattr(main_window, "ImportDialog", Chosen)
    window.open_dialog()
    wait_for_jobs(window)
    layer = window.session.get(window.layer_id(packed.name))
    assert layer.meta["report"]["compression"] == "zip"
    assert len(layer.points) == len(read_points(src).points) > 0
    assert layer.meta.get("layout") is not None


def test_the_speed_and_distance_units_reach_read_points(qtbot, write):
    rows = "".join(f"1,2025-03-01 08:00:0{k},57.{k},11.{k},{k}\n" for k in range(5))
    dlg = ImportDialog(path=write("v.csv", "MMSI,BaseDateTime,LAT,LON,SOG\n" + rows))
    qtbot.addWidget(dlg)
    opts = dlg.options()
    assert opts["speed_unit"] == "auto" and opts["distance_unit"] == "auto"
    dlg.speed_unit_box.setCurrentIndex(dlg.speed_unit_box.findData("km/h"))
    dlg.distance_unit_box.setCurrentIndex(dlg.distance_unit_box.findData("yd"))
    opts = dlg.options()
    assert opts["speed_unit"] == "km/h" and opts["distance_unit"] == "yd"
    got = read_points(**opts).points["speed"]
    assert got.tolist() == pytest.approx([k * 1000 / 1852 for k in range(5)])


def test_gps_week_and_seconds_are_mapping_fields_that_reach_read_points(qtbot, tmp_path):
    """The dialog's mapping rows come from the fields `--map` takes: gps_week and
    gps_seconds among them (h149). A GPS file shows them filled (not time), and columns
    no name shows as GPS time read so when chosen in them."""
    src = tmp_path / "gps.csv"
    src.write_text("gps_week,tow,id,lat,lon\n2295,86418,1,37.9,23.6\n")
    dlg = ImportDialog(path=src)
    qtbot.addWidget(dlg)
    assert dlg.mapping() == {
        "batch": "id",
        "lon": "lon",
        "lat": "lat",
        "gps_week": "gps_week",
        "gps_seconds": "tow",
    }
    assert "time column" not in dlg.warning_label.text()
    got = read_points(**dlg.options())
    assert got.points["time"].tolist() == [pd.Timestamp("2024-01-01", tz="UTC")]
    other = tmp_path / "plain.csv"
    other.write_text("W,S,id,lat,lon\n2295,86418,1,37.9,23.6\n")
    dlg = ImportDialog(path=other)
    qtbot.addWidget(dlg)
    dlg.mapping_boxes["gps_week"].setCurrentText("W")
    dlg.mapping_boxes["gps_seconds"].setCurrentText("S")
    assert dlg.warning_label.text() == ""
    got = read_points(**dlg.options())
    assert got.points["time"].tolist() == [pd.Timestamp("2024-01-01", tz="UTC")]


def test_the_dialog_says_what_a_read_of_the_first_rows_would_warn(qtbot, write):
    """Operator test 9, D11: the dialog warned about nothing for a Chinese export without
    a zone, decimal commas or CST times; the log said it after OK, the dialog closed (and
    a CST file failed outright). Now a read of the first rows with the dialog's options
    says its warnings and the rows it would quarantine, in the dialog's words, and OK
    waits while nothing would be imported."""
    from PySide6 import QtWidgets

    rows = ["批号;时间;经度;纬度"] + [
        f"{1 + k % 2};2024/8/1 8:{k:02d}:12;23,{52378 + k};37,{90000 + k}" for k in range(40)
    ]
    gbk = write("excel.csv", "\r\n".join(rows) + "\r\n", encoding="gbk")
    dlg = ImportDialog(path=gbk)
    qtbot.addWidget(dlg)
    said = dlg.read_label.text()
    assert "Reading the first 40 rows:" in said
    assert "decimal comma" in said and "Asia/Shanghai" in said and "Time zone field" in said
    assert "--tz" not in said
    ok = dlg.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
    assert ok.isEnabled()
    dlg.tz_box.setCurrentText("Asia/Shanghai")
    assert "carry no zone" not in dlg.read_label.text()  # the zone chosen: no such warning

    cst = write(
        "cst.csv",
        "mmsi,BaseDateTime,lat,lon\n"
        + "".join(f"1,2024-08-01 08:{k:02d}:00 CST,37.9,23.{k:02d}\n" for k in range(30)),
    )
    dlg = ImportDialog(path=cst)
    qtbot.addWidget(dlg)
    ok = dlg.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
    assert "30 of the first 30 rows would be quarantined" in dlg.read_label.text()
    assert "CST is ambiguous" in dlg.warning_label.text() and not ok.isEnabled()
    assert "Nothing would be imported" in ok.toolTip()
    dlg.tz_box.setCurrentText("Asia/Shanghai")
    assert ok.isEnabled() and "quarantined" not in dlg.read_label.text()
    result = read_points(**dlg.options())
    assert len(result.points) == 30
    assert result.points["time"].iloc[0] == pd.Timestamp("2024-08-01T00:00:00Z")


def test_the_first_rows_are_read_off_the_gui_thread_and_a_late_read_is_dropped(
    qtbot, write, monkeypatch
):
    """The 400-row preview read ran on the GUI thread (40–130 ms under load, at every
    option changed). With the window's worker (an executor, as File ▸ Open gives it) it
    runs off the GUI thread; the dialog says it reads, shows what the read says once it
    is back, reads again when an option changes, and drops a read for an earlier choice
    that comes back after the newer one."""
    import threading

    from PySide6 import QtWidgets

    from wakeline.app.lod_worker import LodWorker
    from wakeline.core.io import preview

    real = preview.preview_read
    gui = threading.get_ident()
    threads, first_may_end = [], threading.Event()

    def recording(path, **options):
        threads.append(threading.get_ident())
        if options.get("tz") is None and len(threads) == 1:
            first_may_end.wait(10)  # the first read (no zone) comes back last
        return real(path, **options)

    monkeypatch.setattr(preview, "preview_read", recording)
    rows = ["mmsi,BaseDateTime,lat,lon"] + [
        f"1,2024-08-01 08:{k:02d}:00 CST,37.9,23.{k:02d}" for k in range(30)
    ]
    cst = write("cst.csv", "\n".join(rows) + "\n")
    worker = LodWorker()
    dlg = ImportDialog(path=cst, executor=worker)
    qtbot.addWidget(dlg)
    ok = dlg.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
    assert dlg.read_label.text() == "Reading the first rows…" and dlg.preview_pending
    # a zone chosen while the first read still runs: a second read, back first
    dlg.tz_box.setCurrentText("Asia/Shanghai")
    qtbot.waitUntil(lambda: not dlg.preview_pending, timeout=10_000)
    assert "quarantined" not in dlg.read_label.text() and ok.isEnabled()
    assert "Reading the first rows" not in dlg.read_label.text()
    first_may_end.set()  # the first read (CST without a zone: all quarantined) ends late
    assert worker.wait(10_000)
    qtbot.wait(50)  # its result handed over (LodWorker.STEP_MS) and dropped
    assert "quarantined" not in dlg.read_label.text() and ok.isEnabled()
    # back to UTC: read again (remembered reads are per choice, the last one only)
    dlg.tz_box.setCurrentText("UTC")
    qtbot.waitUntil(
        lambda: "30 of the first 30 rows would be quarantined" in dlg.read_label.text(),
        timeout=10_000,
    )
    assert not ok.isEnabled() and "Nothing would be imported" in ok.toolTip()
    assert len(threads) == 3 and gui not in threads  # every read in the worker

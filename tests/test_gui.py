"""GUI tests (pytest-qt, offscreen): the main window on the core engine."""

import json
import os
import time

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtCore, QtWidgets  # noqa: E402

from conftest import load  # noqa: E402
from wakeline.app import i18n  # noqa: E402
from wakeline.app.main import run, wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow, format_dms  # noqa: E402
from wakeline.app.map_canvas import nan_separated  # noqa: E402
from wakeline.app.worker import Cancelled, Finished, JobRunner  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import read_points, write_points  # noqa: E402
from wakeline.core.project import load_project  # noqa: E402
from wakeline.resources import demo_path, translations_dir  # noqa: E402

pytestmark = pytest.mark.gui


def test_demo_draws_one_curve_per_sensor(window):
    lid = load(window, demo_path())
    assert lid is not None and window.canvas.layer_names() == [lid]
    items = window.canvas.layer_items(lid)
    assert len(items) == 2  # AIS and R1
    points = window.layers[lid].points
    n_tracks = points.groupby(["sensor", "batch"]).ngroups
    assert window.batch_model.rowCount() == n_tracks
    nan_gaps = sum(int(np.isnan(i.getOriginalDataset()[0]).sum()) for i in items)
    assert nan_gaps == n_tracks - 2  # one NaN between consecutive tracks of a curve
    vb = window.canvas.getPlotItem().getViewBox()
    assert vb.state["aspectLocked"] == pytest.approx(np.cos(np.radians(points["lat"].mean())))


def test_pipeline_adds_layers_and_selection_follows_both_ways(window, qtbot):
    load(window, demo_path())
    window.run_step("pipeline")
    wait_for_jobs(window)
    kinds = [lay.kind for lay in window.layers.values()]
    assert kinds == ["source", "cleaned", "maneuvers", "compressed"]
    comp = next(n for n, lay in window.layers.items() if lay.kind == "compressed")
    window.layer_list.setCurrentRow(3)
    assert window.active == comp
    # Table -> map: selecting a row highlights exactly that track.
    sensor, batch = window.batch_model.key_of_row(0)
    window.select_tracks([(sensor, batch)])
    x, _ = window.canvas.selection.getOriginalDataset()
    pts = window.layers[comp].points
    n = int(((pts["sensor"] == sensor) & (pts["batch"] == batch)).sum())
    assert len(x) == n and not np.isnan(x).any()
    # The Detail panel follows on a later event-loop turn.
    qtbot.waitUntil(lambda: window.detail.comp_kept.getData()[0] is not None, timeout=5000)
    # Map -> table: a click on another track's point selects its row.
    other = pts[(pts["sensor"] != sensor) | (pts["batch"] != batch)].iloc[0]
    window.canvas.fit()
    QtWidgets.QApplication.processEvents()
    assert window.canvas.pick(float(other["lon"]), float(other["lat"]))
    assert window.selected_keys() == [(str(other["sensor"]), str(other["batch"]))]
    # Text filter narrows the table.
    window.filter_edit.setText("AIS")
    model = window.batch_model
    shown = {model.index(r, 0).data() for r in range(model.rowCount())}
    assert shown == {"AIS"}


def test_event_loop_keeps_turning_and_cancel_stops_a_long_job(qtbot):
    runner = JobRunner()
    messages = []
    runner.message.connect(lambda m: messages.append(m))

    def long_job(progress):
        for k in range(400):
            progress(k / 400, "working")
            time.sleep(0.01)
        return "done"

    ticks = []
    timer = QtCore.QTimer()
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start(10)
    runner.run("long", long_job)
    # The GUI thread keeps processing events while the job runs (4 s in all).
    qtbot.waitUntil(lambda: len(ticks) >= 15, timeout=3500)
    assert runner.busy
    runner.cancel()
    qtbot.waitUntil(lambda: any(isinstance(m, Cancelled) for m in messages), timeout=5000)
    assert not any(isinstance(m, Finished) for m in messages)
    timer.stop()
    # A new job replaces a running one, and only its result arrives.
    job = runner.run("again", long_job)
    runner.run("short", lambda progress: 42)
    qtbot.waitUntil(lambda: any(isinstance(m, Finished) and m.result == 42 for m in messages))
    assert not any(isinstance(m, Finished) and m.job == job for m in messages)
    runner.wait()


def test_errors_in_a_job_reach_a_dialog_and_the_log(window, monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    lid = load(window, demo_path())
    window.run_step("fuse")
    wait_for_jobs(window)
    assert any(lay.kind == "fused" for lay in window.layers.values())
    single = window.layers[lid].points
    radar = window.session.add_layer("radar only", "source", single[single["sensor"] == "R1"])
    wait_for_jobs(window)  # the new layer is drawn and made active on later turns
    assert window.active == radar.id
    window.run_step("fuse")
    wait_for_jobs(window)
    assert shown and "at least two sensors" in shown[-1]
    assert "at least two sensors" in window.log.toPlainText()


def test_export_refuses_csv_text_under_a_spreadsheet_name(window, tmp_path, monkeypatch):
    """File ▸ Export ▸ CSV to tracks.xlsx wrote CSV text there (the command line refuses
    it since its own operator test): the window refuses it with the same rule and words,
    writes nothing and starts no job; .csv still goes through."""
    from wakeline.core.errors import InputError
    from wakeline.core.export import check_text_path

    shown = []
    monkeypatch.setattr(
        QtWidgets.QMessageBox, "warning", lambda _p, _t, text, *a: shown.append(text)
    )
    load(window, demo_path())
    for name, kind in (("tracks.xlsx", "csv"), ("m.ods", "maneuvers"), ("t.csv.gz", "csv")):
        assert window.export(kind, tmp_path / name) is None
        wait_for_jobs(window)
        assert not (tmp_path / name).exists()
        with pytest.raises(InputError) as exc:
            check_text_path(tmp_path / name)
        assert shown[-1] == str(exc.value) and "write to .csv" in shown[-1]
    assert window.export_as_came_in(tmp_path / "again.xlsx") is None
    assert not (tmp_path / "again.xlsx").exists()
    assert "again.xlsx" in window.log.toPlainText()
    assert window.export("csv", tmp_path / "tracks.csv")
    wait_for_jobs(window)
    assert (tmp_path / "tracks.csv").exists()


def test_export_as_it_came_in_suggests_csv_for_a_compressed_source(window, tmp_path, monkeypatch):
    """A layer read from radar.csv.gz is offered as ….csv (its plain text would be refused
    under .gz), and the name the operator picks is written."""
    import gzip

    src = tmp_path / "radar.csv.gz"
    with gzip.open(src, "wt") as fh:
        fh.write("sensor,batch,time,lon,lat\n")
        fh.writelines(f"S1,7,2024-05-01T00:0{k}:00Z,11.5{k},57.6\n" for k in range(5))
    load(window, src)
    seen = []

    def dialog(_parent, _title, suggestion, filt):
        seen.append((suggestion, filt))
        return str(tmp_path / suggestion), filt

    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", dialog)
    assert window.export_as_came_in()
    wait_for_jobs(window)
    assert seen[0][0].endswith(".csv") and "(*.csv)" in seen[0][1]
    assert (tmp_path / seen[0][0]).read_text().startswith("sensor,batch,time")


def test_export_and_reimport(window, tmp_path):
    lid = load(window, demo_path())
    window.run_step("compress")
    wait_for_jobs(window)
    comp = next(n for n, lay in window.layers.items() if lay.kind == "compressed")
    window.set_active(comp)
    out = tmp_path / "compressed.csv"
    assert window.export("csv", out)
    wait_for_jobs(window)
    back = read_points(out).points
    assert len(back) == len(window.layers[comp].points)
    gj = tmp_path / "compressed.geojson"
    assert window.export("geojson", gj)
    wait_for_jobs(window)
    assert json.loads(gj.read_text())["type"] == "FeatureCollection"
    man = tmp_path / "maneuvers.csv"
    assert window.export("maneuvers", man)
    wait_for_jobs(window)
    maneuvers = window.session.related(comp, "maneuvers")
    assert len(pd.read_csv(man)) == int(maneuvers.points["is_maneuver"].sum())
    # The GUI writes the same maneuver table as `wakeline maneuvers`-style output (index kept).
    assert list(pd.read_csv(man).columns) == [
        "sensor",
        "batch",
        "index",
        "time",
        "lon",
        "lat",
        "factor",
    ]
    assert window.session.root(comp).id == lid


def _project_bench(qtbot, tmp_path, monkeypatch):
    """The demo scene as a CSV, shared window settings and the dialogs recorded: (scene
    path, a function making a window, warning texts, question texts)."""
    shown, asked = [], []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    monkeypatch.setattr(QtWidgets.QMessageBox, "question", lambda *a: asked.append(a[2]))
    src = tmp_path / "scene.csv"
    write_points(simulate.demo_scene(), src)
    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)

    def new_window() -> MainWindow:
        w = MainWindow(settings)
        qtbot.addWidget(w)
        return w

    return src, new_window, shown, asked


def test_project_save_close_reopen(qtbot, tmp_path, monkeypatch):
    src, new_window, shown, _ = _project_bench(qtbot, tmp_path, monkeypatch)
    w = new_window()
    load(w, src)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    w.params.from_dict({"maneuver": {"threshold_deg": 20.0}})
    w.run_step("compress")
    wait_for_jobs(w)
    w.select_tracks([w.batch_model.key_of_row(1)])
    keys = w.selected_keys()
    layers = [(i, lay.name, lay.parent) for i, lay in w.layers.items()]
    w.close()  # autosaved after every change: nothing else to do

    w2 = new_window()
    w2.open_project(proj)
    wait_for_jobs(w2)
    assert [(i, lay.name, lay.parent) for i, lay in w2.layers.items()] == layers
    assert w2.params.params("maneuver").threshold_deg == 20.0
    assert w2.selected_keys() == keys
    assert not shown
    # The source changes: reported, not fatal.
    src.write_text(src.read_text() + "\n")
    w3 = new_window()
    w3.open_project(proj)
    wait_for_jobs(w3)
    assert shown and "changed" in shown[-1]
    # Not a project: a dialog, and the open session is left as it was.
    before = list(w3.layers)
    junk = tmp_path / "junk.wakeline"
    junk.write_text("nope" * 100)
    w3.open_project(junk)
    wait_for_jobs(w3)
    assert "not a Wakeline project" in shown[-1]
    assert list(w3.layers) == before and w3.project.path == proj
    w2.close()
    w3.close()


def test_a_project_saves_the_parameters_set_before_it_was_saved(qtbot, tmp_path, monkeypatch):
    """Save and Save as wrote the parameter table the session had when a project was
    opened (none for a first save), not the panel's: parameters set before the first save,
    or since opening before a Save as, came back as the defaults or the old values."""
    src, new_window, _, _ = _project_bench(qtbot, tmp_path, monkeypatch)
    w = new_window()
    load(w, src)
    w.params.from_dict({"maneuver": {"threshold_deg": 22.0}})
    first, other = tmp_path / "first.wakeline", tmp_path / "other.wakeline"
    w.save_project(first)
    assert w.project.flush(30)
    assert load_project(first).params["maneuver"]["threshold_deg"] == 22.0  # none before
    w.params.from_dict({"maneuver": {"threshold_deg": 25.0}})
    w.save_project(other)  # Save as
    assert w.project.flush(30)
    assert load_project(other).params["maneuver"]["threshold_deg"] == 25.0  # 22 before
    w.close()
    w2 = new_window()
    w2.open_project(other)
    wait_for_jobs(w2)
    assert w2.params.params("maneuver").threshold_deg == 25.0
    w2.close()


def test_project_reopens_where_the_operator_was(qtbot, tmp_path, monkeypatch):
    """Operator test: a reopened project framed all the data again and made the last
    layer active (the view Save as stored was never read back, the active layer never
    saved by it). Now the active layer, the hidden layer, the selected tracks, the map's
    view (written once it settles, not per move) and the time window come back in a new
    window; a bad view-state row is left out with one warning and the project opens."""
    import sqlite3

    from wakeline.core.session import MapView

    src, new_window, shown, _ = _project_bench(qtbot, tmp_path, monkeypatch)
    w = new_window()
    w.resize(1200, 800)
    lid = load(w, src)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    w.run_step("pipeline")
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.drawing and not w.time_controller.busy, timeout=20_000)
    cleaned = next(i for i, lay in w.layers.items() if lay.kind == "cleaned")
    assert cleaned != list(w.layers)[-1]  # not the layer an open made active before
    w.select_layer(cleaned)
    w.layer_list.item(w.layer_row(lid)).setCheckState(QtCore.Qt.CheckState.Unchecked)
    assert not w.layers[lid].visible
    t_lo, t_hi = w.time_panel.time_range()
    window = (t_lo + 0.2 * (t_hi - t_lo), t_lo + 0.7 * (t_hi - t_lo))
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window(window)
    rows = w.batch_model.rowCount()
    keys = [w.batch_model.key_of_row(1), w.batch_model.key_of_row(3)]
    w.select_tracks(keys)
    keys = w.selected_keys()
    assert len(keys) == 2
    # The table reset (here: the window set again) keeps the selection (Qt dropped it).
    w.batch_model.set_time_window(window)
    assert w.batch_model.rowCount() == rows and w.selected_keys() == keys
    # A pan of 20 steps: one write once it settles, not one per step.
    events = []
    w.session.subscribe(lambda e, _lid: events.append(e))
    x0, x1, y0, y1 = w.canvas.current_view()
    cx, cy, dx, dy = (x0 + x1) / 2, (y0 + y1) / 2, (x1 - x0) / 8, (y1 - y0) / 8
    for k in range(20):
        w.canvas.vb.setRange(
            xRange=(cx - dx + k * dx / 100, cx + dx + k * dx / 100),
            yRange=(cy - dy, cy + dy),
            padding=0,
        )
        QtWidgets.QApplication.processEvents()
    assert w.view_keeper.pending and "map_view" not in events
    qtbot.waitUntil(lambda: not w.view_keeper.pending, timeout=5000)
    assert events.count("map_view") == 1
    assert w.project.flush(30)
    panned = MapView.of(w.canvas.current_view())
    assert load_project(proj).map_view == panned  # written without Save as
    # Zoomed into one corner, then closed at once: the last view is written on close.
    x0, x1, y0, y1 = panned.bounds()
    w.canvas.vb.setRange(xRange=(x0, x0 + (x1 - x0) / 3), yRange=(y0, y0 + (y1 - y0) / 3))
    view = w.canvas.current_view()
    size = w.canvas.plot_size_px()
    w.close()
    back = load_project(proj)
    assert back.active == cleaned and back.map_view == MapView(*view)
    assert back.selection == [(cleaned, s, b) for s, b in keys]

    w2 = new_window()
    w2.resize(1200, 800)
    w2.open_project(proj)
    wait_for_jobs(w2)
    qtbot.waitUntil(lambda: not w2.drawing and not w2.time_controller.busy, timeout=20_000)
    assert not shown
    assert w2.active == cleaned and w2.session.active == cleaned
    assert w2.layer_list.currentItem().data(QtCore.Qt.ItemDataRole.UserRole) == cleaned
    assert not w2.layers[lid].visible and all(
        lay.visible for i, lay in w2.layers.items() if i != lid
    )
    state = QtCore.Qt.CheckState
    assert w2.layer_list.item(w2.layer_row(lid)).checkState() == state.Unchecked
    assert all(not item.isVisible() for n in w2.map_names(lid) for item in w2.canvas.layer_items(n))
    assert w2.selected_keys() == keys
    assert w2.session.selection == [(cleaned, s, b) for s, b in keys]
    assert w2.time_panel.time_window() == window
    assert w2.canvas.plot_size_px() == size
    got = w2.canvas.current_view()
    px = ((view[1] - view[0]) / size[0], (view[3] - view[2]) / size[1])
    for k in range(4):
        assert abs(got[k] - view[k]) <= px[k // 2], (got, view)
    reopened = list(w2.layers)
    w2.close()  # a closed window lets its layers go (defect #8)
    assert not w2.layers

    # A bad time-window row: one warning, and the project opens with the rest.
    con = sqlite3.connect(proj)
    row = '{"start": 5, "end": 1, "unit": "s"}'
    con.execute("INSERT OR REPLACE INTO state VALUES ('time_window', ?)", (row,))
    con.commit()
    con.close()
    w3 = new_window()
    w3.resize(1200, 800)
    w3.open_project(proj)
    wait_for_jobs(w3)
    qtbot.waitUntil(lambda: not w3.drawing and not w3.time_controller.busy, timeout=20_000)
    assert len(shown) == 1 and "time window" in shown[0] and "left out" in shown[0]
    assert "time window" in w3.log.toPlainText()
    assert list(w3.layers) == reopened and w3.active == cleaned
    assert w3.time_panel.time_window() is None and w3.selected_keys() == keys
    w3.close()


def test_panning_a_read_only_project_is_no_unsaved_work(qtbot, tmp_path):
    """With the view and the active layer written as they change, a read-only project
    panned, or another layer made active, would offer Save as on closing: not work lost.
    A change to the layers still is."""
    from wakeline.app.project_controller import ProjectController
    from wakeline.core.project import save_project
    from wakeline.core.session import Session

    s = Session()
    a = s.add_layer("a", "source", simulate.demo_scene().head(50))
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    ctl = ProjectController(s)
    ctl.follow(path, read_only=True)
    s.set_map_view((10.0, 11.0, 57.0, 57.5))
    s.set_active(a.id)
    assert not ctl.unsaved
    s.set_visible(a.id, False)
    assert ctl.unsaved
    ctl.detach()


def test_a_table_reset_selects_the_selection_again(window, tmp_path):
    """A batch-table reset (a time window, a filter) dropped the rows' selection without
    a signal, so the map and the project kept tracks the table no longer showed selected.
    Now the session's selection is selected again where its rows are shown (a range per
    run of rows, one lookup per key), and the tracks a window hides come back with it."""
    n = 600
    k = np.repeat(np.arange(n), 3)
    t = 1_714_521_600 + (k % 60) * 60 + np.tile([0, 10, 20], n)
    csv = tmp_path / "many.csv"
    pd.DataFrame(
        {
            "sensor": "R1",
            "batch": k.astype(str),
            "time": pd.to_datetime(t, unit="s", utc=True).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "lon": 122 + 1e-3 * (k % 30) + 1e-5 * np.tile([0, 1, 2], n),
            "lat": 30 + 1e-3 * (k // 30),
        }
    ).to_csv(csv, index=False)
    lid = load(window, csv)
    model = window.batch_model
    model.sort(1, QtCore.Qt.SortOrder.DescendingOrder)
    wanted = [("R1", str(b)) for b in range(0, n, 3)] + [("R1", "nope")]
    window.select_tracks(wanted)
    shown = window.selected_keys()
    assert sorted(shown) == sorted(wanted[:-1])
    assert shown == [
        model.key_of_row(r) for r in range(model.rowCount()) if model.key_of_row(r) in shown
    ]
    assert window.session.selection == [(lid, s, b) for s, b in shown]
    t0 = 1_714_521_600
    model.set_time_window((t0, t0 + 29 * 60 + 30))  # tracks k % 60 < 30: half of them
    inside = [key for key in shown if int(key[1]) % 60 < 30]
    assert sorted(window.selected_keys()) == sorted(inside) and len(inside) < len(shown)
    assert len(window.session.selection) == len(shown)  # the hidden ones kept
    model.set_time_window(None)
    model.set_filter("")
    assert sorted(window.selected_keys()) == sorted(shown)
    assert model.keys_of_rows(model.rows_of_keys(wanted)) == shown


def _open_in(new_window, qtbot, proj, size):
    w = new_window()
    w.resize(*size)
    w.show()
    qtbot.waitExposed(w)
    w.open_project(proj)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.drawing and not w.time_controller.busy, timeout=20_000)
    return w


def test_a_window_of_another_shape_fits_the_saved_view_without_writing_it(
    qtbot, tmp_path, monkeypatch
):
    """Review: a project opened in a window of another shape widened one axis of its
    saved view (the aspect lock) and wrote that wider view back 400 ms later, so the
    saved view grew with every open in a window of another shape. Now the saved view is
    fitted into the window (all of it shown, one axis exact) and stays as it was — in the
    session and the file, a resize too, and on close — until the operator pans or zooms;
    reopened in the first window's shape it shows what it showed there."""
    from wakeline.app.view_keeper import SETTLE_MS
    from wakeline.core.session import MapView

    src, new_window, shown, _ = _project_bench(qtbot, tmp_path, monkeypatch)
    w = new_window()
    w.resize(1200, 800)
    w.show()
    qtbot.waitExposed(w)
    load(w, src)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    x0, x1, y0, y1 = w.canvas.current_view()
    w.canvas.vb.setRange(
        xRange=(x0 + 0.3 * (x1 - x0), x0 + 0.6 * (x1 - x0)),
        yRange=(y0 + 0.2 * (y1 - y0), y0 + 0.5 * (y1 - y0)),
        padding=0,
    )
    first = w.canvas.current_view()
    size = w.canvas.plot_size_px()
    w.close()
    saved = load_project(proj).map_view
    assert saved == MapView(*first)

    def fits(view, target, px) -> bool:
        """``view`` shows all of ``target``, one axis exactly (within a pixel)."""
        inside = all(
            (view[k] <= target[k] + px[k // 2]) if k % 2 == 0 else view[k] >= target[k] - px[k // 2]
            for k in range(4)
        )
        exact = [all(abs(view[k] - target[k]) <= px[k // 2] for k in ax) for ax in ((0, 1), (2, 3))]
        return inside and any(exact)

    for shape in ((1500, 600), (800, 900)):
        w2 = _open_in(new_window, qtbot, proj, shape)
        got, px_size = w2.canvas.current_view(), w2.canvas.plot_size_px()
        px = ((got[1] - got[0]) / px_size[0], (got[3] - got[2]) / px_size[1])
        assert fits(got, saved.bounds(), px), (got, saved)
        assert not same_shape(got, first), (got, first)  # the fit is another shape
        w2.resize(shape[0] - 100, shape[1] + 50)  # a resize keeps it too
        qtbot.wait(SETTLE_MS + 200)
        assert not w2.view_keeper.pending and w2.session.map_view == saved
        w2.close()
        assert load_project(proj).map_view == saved, shape  # not written back
    # Back in a window of the first one's size: the saved view fitted as before (its
    # plot may differ by a few pixels: the docks), never grown by the opens between.
    # The docks as a new window has them, not as the 800-px window left them in the
    # shared settings: since h179 a window may be narrower than 1,368 px (1200 stays
    # 1200), and docks restored from a narrower one leave the map another width.
    w.settings.remove("state")
    w3 = _open_in(new_window, qtbot, proj, (1200, 800))
    got, px_size = w3.canvas.current_view(), w3.canvas.plot_size_px()
    px = ((got[1] - got[0]) / px_size[0], (got[3] - got[2]) / px_size[1])
    assert fits(got, saved.bounds(), px), (got, saved)
    assert abs(px_size[0] - size[0]) < 0.1 * size[0] and abs(px_size[1] - size[1]) < 0.1 * size[1]
    assert all(abs(got[k] - first[k]) <= 0.1 * (first[1] - first[0]) for k in (0, 1))
    assert all(abs(got[k] - first[k]) <= 0.1 * (first[3] - first[2]) for k in (2, 3))
    # The operator pans: the view shown is written once it settles.
    w3.canvas.vb._resetTarget()  # as a mouse drag does
    w3.canvas.vb.translateBy(x=0.1 * (first[1] - first[0]))
    qtbot.waitUntil(lambda: w3.session.map_view != saved, timeout=5000)
    assert w3.session.map_view == MapView(*w3.canvas.current_view())
    assert w3.project.flush(30) and load_project(proj).map_view == w3.session.map_view
    w3.close()
    assert not shown


def same_shape(a, b) -> bool:
    """Two views of the same width-to-height ratio (within 1 %)."""
    return abs((a[1] - a[0]) / (a[3] - a[2]) / ((b[1] - b[0]) / (b[3] - b[2])) - 1) < 0.01


def test_project_open_in_two_windows_loses_nothing(qtbot, tmp_path, monkeypatch):
    """Operator test: both windows numbered their new layer L2 and one's was lost. The
    second window opens the project read-only, says who holds it, refuses Save as onto
    it, and offers Save as when closed with changes."""
    src, new_window, shown, asked = _project_bench(qtbot, tmp_path, monkeypatch)
    a, b = new_window(), new_window()
    load(a, src)
    proj = tmp_path / "work.wakeline"
    a.save_project(proj)
    a.project.flush()
    b.open_project(proj)
    wait_for_jobs(b)
    assert b.project.read_only and "read-only" in b.windowTitle()
    assert shown and f"process {os.getpid()}" in shown[-1] and "read-only" in shown[-1]
    a.run_step("clean")
    wait_for_jobs(a)
    b.run_step("compress")
    wait_for_jobs(b)
    b.save_project(proj)  # onto the file the other window holds: refused, nothing written
    assert "save it under another name" in shown[-1] and b.project.path == proj
    a.project.flush()
    assert [lay.kind for lay in load_project(proj).layers] == ["source", "cleaned"]
    b.close()  # changed while read-only: Save as is offered
    assert asked and "read-only" in asked[-1]
    a.close()
    assert not (tmp_path / "work.wakeline.lock").exists()
    c = new_window()  # once both are closed the project opens writable
    c.open_project(proj)
    wait_for_jobs(c)
    assert not c.project.read_only and [lay.kind for lay in c.layers.values()] == [
        "source",
        "cleaned",
    ]
    c.close()


def test_project_renamed_or_copied_while_open_loses_nothing(qtbot, tmp_path, monkeypatch):
    """Operator test: a copy of an open project held one layer of four, and renaming it
    while open lost the work (it sat in a -wal side file). Now the file alone holds every
    flushed write; a write after the rename fails with one dialog (not one per change),
    and closing offers Save as."""
    import shutil

    src, new_window, shown, asked = _project_bench(qtbot, tmp_path, monkeypatch)
    w = new_window()
    load(w, src)
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    w.run_step("clean")
    wait_for_jobs(w)
    w.run_step("compress")
    wait_for_jobs(w)
    assert w.project.flush()
    shutil.copyfile(proj, tmp_path / "copy.wakeline")
    kinds = [lay.kind for lay in load_project(tmp_path / "copy.wakeline").layers]
    assert kinds == ["source", "cleaned", "maneuvers", "compressed"]
    proj.rename(tmp_path / "moved.wakeline")
    w.run_step("maneuvers")
    wait_for_jobs(w)
    w.project.flush()
    qtbot.waitUntil(lambda: w.project.dirty, timeout=5000)
    w.select_layer(next(iter(w.layers)))
    w.run_step("clean")  # a second failing change: logged, no second dialog
    wait_for_jobs(w)
    w.project.flush()
    qtbot.waitUntil(lambda: w.project.failures >= 2, timeout=5000)
    assert len([t for t in shown if "moved, renamed or removed" in t]) == 1
    assert "not saved" in w.windowTitle() and not proj.exists()
    w.close()
    assert asked and "could not be written" in asked[-1]
    back = load_project(tmp_path / "moved.wakeline")
    assert [lay.kind for lay in back.layers] == kinds


def test_parameters_panel_refuses_bad_values_and_round_trips_presets(window, tmp_path):
    p = window.params
    p.from_dict({"maneuver": {"threshold_deg": 25.0}, "clean": {"speed": {"v_max_kn": 22.0}}})
    assert p.params("maneuver").threshold_deg == 25.0
    assert p.clean_params().speed.v_max_kn == 22.0
    problems = p.from_dict({"fuse": {"alpha": 3.0}})  # above its range
    assert problems and p.params("fuse").alpha == 0.2
    preset = tmp_path / "preset.json"
    p.save_preset(preset)
    p.reset()
    assert p.params("maneuver").threshold_deg == 15.0
    assert p.load_preset(preset) == []
    assert p.params("maneuver").threshold_deg == 25.0
    # a preset saved before presets had a version (max_window_s 600 s meant 10 ... 320 s)
    old = json.loads(preset.read_text(encoding="utf-8"))
    assert old.pop("wakeline_params") == 2
    old["maneuver"]["max_window_s"] = 600.0
    preset.write_text(json.dumps(old), encoding="utf-8")
    assert p.load_preset(preset) == []
    assert p.params("maneuver").max_window_s == 320.0
    # Every parameter of the core is in the tree, with its unit in the tooltip.
    leaf = p.root.child("associate", "max_gap_s")
    assert "[s]" in leaf.opts["tip"] and "seed 003" in leaf.opts["tip"]


def test_parameters_panel_max_gap_is_the_limit_as_on_the_command_line(qtbot, window, tmp_path):
    """Operator test: resample max_gap_s set in the Parameters panel left the adaptive limit
    on (a step up to max_gap_steps = 2 of the track's median step is no gap), so the
    panel's clean bridged the 120 s steps that `wakeline clean --resample 30 --max-gap 100`
    leaves alone: 117 points against the command line's 30. The panel applies the core's
    rule (core.transform.stated_max_gap): max_gap_steps shows 0 and a note says why; the
    pipeline file (wakeline batch) and the project keep it; a max_gap_steps the operator
    sets is kept."""
    from test_clean import straight

    from conftest import make_window
    from wakeline.app.cli import main as cli_main
    from wakeline.core.pipeline import Pipeline

    src, by_cli = tmp_path / "sparse.csv", tmp_path / "cli.csv"
    straight(30, period_s=120.0).to_csv(src, index=False)
    flags = ["--resample", "30", "--off", "short_tracks"]
    assert cli_main(["clean", str(src), "-o", str(by_cli), *flags, "--max-gap", "100"]) == 0
    assert len(pd.read_csv(by_cli)) == 30  # every 120 s step is a gap
    lid = load(window, src)
    p = window.params
    resample = p.root.child("clean", "resample")
    p.root.child("clean", "short_tracks", "enabled").setValue(False)
    resample.child("enabled").setValue(True)
    resample.child("period_s").setValue(30.0)
    resample.child("max_gap_s").setValue(100.0)  # as the operator types it
    assert window.step_params("clean")["clean"].resample.max_gap_steps == 0
    assert resample.child("max_gap_steps").value() == 0  # shown
    assert "max_gap_steps is now 0" in p.note.text()
    window.run_step("clean")
    wait_for_jobs(window)
    cleaned = window.session.find(lid, "clean", "cleaned")
    assert len(cleaned.points) == 30  # the command line's result (117 before)
    assert cleaned.params["clean"]["resample"]["max_gap_steps"] == 0  # what it ran with
    # The pipeline file the panel saves runs the same in `wakeline batch`.
    pipe = tmp_path / "pipe.json"
    window.save_pipeline(pipe)
    stages = Pipeline.from_json(pipe.read_text(encoding="utf-8")).stages
    assert stages[0][1]["clean"].resample.max_gap_steps == 0
    # The project reopens with the same values, and the step runs the same again.
    proj = tmp_path / "gap.wakeline"
    window.save_project(proj)
    window.close()
    w2 = make_window(qtbot, tmp_path)
    try:
        w2.open_project(proj)
        wait_for_jobs(w2)
        back = w2.params.clean_params().resample
        assert (back.max_gap_s, back.max_gap_steps) == (100.0, 0)
        w2.run_step("clean")
        wait_for_jobs(w2)
        assert len(w2.session.find(lid, "clean", "cleaned").points) == 30
        # A max_gap_steps the operator sets is theirs, whatever max_gap_s they set after.
        again = w2.params.root.child("clean", "resample")
        again.child("max_gap_steps").setValue(3.0)
        again.child("max_gap_s").setValue(90.0)
        assert w2.params.clean_params().resample.max_gap_steps == 3
        assert w2.params.note.text() == ""
        # Defaults: nothing stated, the adaptive limit again until max_gap_s is set.
        w2.params.reset()
        assert w2.params.clean_params().resample.max_gap_steps == 2
        again.child("max_gap_s").setValue(90.0)
        assert w2.params.clean_params().resample.max_gap_steps == 0
    finally:
        w2.runner.cancel()
        w2.runner.wait()
        w2.close()


def test_a_destroyed_parameter_tree_leaves_no_wrapper_of_its_root_item(qtbot):
    """pyqtgraph's tree keeps a Python wrapper of the root item Qt made, which PySide did
    not forget when the tree died: a C++ object later made at that address came back to
    Python as that QTreeWidgetItem (a SpinBox's lineEdit(), a plot's children(): the GUI
    tests' intermittent AttributeErrors). The wrapper goes with the tree."""
    import shiboken6

    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    root = panel.tree.invisibleRootItem()._real_item
    assert shiboken6.isValid(root) and root.childCount() > 0
    panel.deleteLater()
    QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)
    assert not shiboken6.isValid(panel.tree)
    assert not shiboken6.isValid(root), "the dead root item's wrapper is still registered"


def test_quarantined_rows_are_viewable(window, tmp_path):
    src = tmp_path / "with_bad_rows.csv"
    write_points(simulate.demo_scene().head(50), src)
    with open(src, "a") as fh:
        fh.write("AIS,9,not-a-time,122.5,30.5,,,,,\nAIS,9,2024-05-01T00:00:00Z,999,30.5,,,,,\n")
    assert load(window, src)
    dialog = window.show_import_report()
    model = dialog.table.model()
    assert model.rowCount() == 2
    headers = [
        model.headerData(c, QtCore.Qt.Orientation.Horizontal) for c in range(model.columnCount())
    ]
    assert "reason" in headers
    dialog.close()


def test_a_last_line_cut_short_is_logged_with_its_line(window, tmp_path):
    """Operator test 4 (D-import-5): the window's log named a cut last line "short row: 5
    of 12 fields" without its line or what it means."""
    src = tmp_path / "cut.csv"
    write_points(simulate.demo_scene().head(50), src)
    with open(src, "a") as fh:
        fh.write("AIS,9,2024-05-01T00:00:00Z\n")
    assert load(window, src)
    log = window.log.toPlainText()
    assert "short row: 3 of 10 fields (line 52)" in log
    assert "line 52, the file's last line, has 3 of 10 fields: the file may be cut short" in log


def test_bad_file_shows_a_dialog_not_a_crash(window, tmp_path, monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n")
    assert not load(window, bad)
    assert not load(window, tmp_path / "missing.csv")
    assert shown and "missing required column" in shown[0]
    assert "Error" in window.log.toPlainText() and "no such file" in window.log.toPlainText()
    assert window.layers == {}


def test_a_file_with_no_usable_row_says_why(window, tmp_path, monkeypatch):
    """Operator test: a file whose every time is unreadable (US clock times with AM/PM,
    until h111 read them; now words) showed only "no usable points"; the dialog names the
    reason, how many rows, and what to try, in the window's words (the import dialog, not
    --map)."""
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    us = tmp_path / "us_times.csv"
    rows = [f"7,08h0{m} on the 1st of May,12.{m},56.0" for m in range(5)]
    us.write_text("mmsi,timestamp,lon,lat\n" + "\n".join(rows) + "\n")
    header_only = tmp_path / "header_only.csv"
    header_only.write_text("mmsi,timestamp,lon,lat\n")
    assert not load(window, us)
    assert not load(window, header_only)
    assert len(shown) == 2
    assert "all 5 rows were quarantined" in shown[0] and "unparsable time" in shown[0]
    assert "Column mapping" in shown[0] and "--map" not in shown[0]
    assert "no data rows" in shown[1]
    assert window.layers == {}


def test_chinese_translation_switches_the_menus(window):
    ts = translations_dir() / "wakeline_zh_CN.ts"
    assert len(i18n.TsTranslator(ts)) > 40
    window.set_language("zh_CN")
    titles = [a.text() for a in window.menuBar().actions()]
    assert "文件(&F)" in titles
    assert window.docks["batches"].windowTitle() == "批次表"
    assert "审核(&W)" in titles and "撤销(&U)" == window.review.act_undo.text()  # operator test
    window.set_language("en")
    assert window.menuBar().actions()[0].text() == "&File"
    assert "Revie&w" in [a.text() for a in window.menuBar().actions()]


def test_detail_plot_titles_follow_the_language_at_once(window, qtbot):
    """GUI test: the Detail plots' titles stayed English after Language ▸ 简体中文 until
    the next selection; they are written again with the rest of the window."""
    load(window, demo_path())
    window.run_step("pipeline")
    wait_for_jobs(window)
    comp = next(n for n, lay in window.layers.items() if lay.kind == "compressed")
    window.select_layer(comp)
    wait_for_jobs(window)
    window.select_tracks([window.batch_model.key_of_row(0)])
    qtbot.waitUntil(lambda: window.detail.comp_kept.getData()[0] is not None, timeout=5000)
    d = window.detail

    def titles() -> list[str]:
        return [p.getPlotItem().titleLabel.text for p in (d.factor_plot, d.comp_plot)]

    en = titles()
    assert "maneuvers; threshold" in en[0] and "points kept, Dis_e" in en[1], en
    window.set_language("zh_CN")
    try:
        zh = titles()
        assert "个机动点；阈值" in zh[0] and "保留" in zh[1] and "Dis_e" in zh[1], zh
        assert [t.split()[0] for t in zh] != [t.split()[0] for t in en]
    finally:
        window.set_language("en")
    assert titles() == en


def test_nan_separated_unwraps_the_antimeridian():
    df = pd.DataFrame(
        {
            "sensor": ["S"] * 5,
            "batch": ["a", "a", "a", "b", "b"],
            "time": pd.to_datetime([0, 3600, 7200, 0, 3600], unit="s", utc=True),  # ~12 kn
            "lon": [179.9, -179.9, -179.7, 10.0, 10.1],
            "lat": [0.0, 0.0, 0.0, 1.0, 1.0],
        }
    )
    lon, lat = nan_separated(df)
    assert np.allclose(lon[:3], [179.9, 180.1, 180.3])
    assert np.isnan(lon[3]) and np.allclose(lon[4:], [10.0, 10.1])


def test_dms():
    assert format_dms(30.5, "N", "S") == "30°30'00.0\"N"
    assert format_dms(-122.25, "E", "W") == "122°15'00.0\"W"


def _main_windows() -> int:
    return sum(isinstance(w, MainWindow) for w in QtWidgets.QApplication.topLevelWidgets())


def test_screenshot_runs_the_pipeline(qapp, tmp_path):
    png = tmp_path / "shot.png"
    before = _main_windows()
    assert run([demo_path()], screenshot=png, language="en") == 0
    # Its window is deleted before run() returns (a test with no qtbot has no teardown
    # that would end it; it lived on into later tests).
    assert _main_windows() == before
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    from PySide6 import QtGui

    img = QtGui.QImage(str(png))
    assert (img.width(), img.height()) == (1400, 900)


def test_qt_binding_keeps_reference_counts():
    """PySide6 6.12.0 drops a reference to True on every Signal.emit(); a long session then
    aborts at exit. pyproject.toml excludes that version; this catches a relapse."""
    import sys

    class Emitter(QtCore.QObject):
        sig = QtCore.Signal(int)

    e = Emitter()
    got = []
    e.sig.connect(lambda v: got.append(v))
    before = sys.getrefcount(True)
    for k in range(100):
        e.sig.emit(k)
    assert sys.getrefcount(True) - before > -50, "this PySide6 leaks references on emit()"


def test_bearing_only_data_shows_the_statistic_and_detections(window, tmp_path, monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    from wakeline.core.bearing import simulate_table

    path = tmp_path / "bearings.csv"
    simulate_table(seed=1).to_csv(path, index=False)
    assert window.load_bearings(path) is not None
    wait_for_jobs(window)
    det = window.bearing_detections
    assert len(det) > 0
    window.detail.bearing_batch.setCurrentText(str(det["batch"].iloc[0]))
    x, z = window.detail.z_curve.getData()
    assert len(x) > 100 and np.nanmax(np.abs(z)) > window.params.params("bearing").z_crit
    assert len(window.detail.detect_lines) == 2 * int(
        (det["batch"] == window.detail.bearing_batch.currentText()).sum()
    )
    bad = tmp_path / "bad_bearings.csv"
    bad.write_text("batch,time,bearing\n1,2024-01-01T00:00:00Z,abc\n")
    window.load_bearings(bad)
    wait_for_jobs(window)
    assert shown and "no usable bearing" in shown[-1] and "not a finite number" in shown[-1]


def test_failed_save_shows_a_dialog_and_marks_the_title(window, tmp_path, monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    folder = tmp_path / "work"
    folder.mkdir()
    load(window, demo_path())
    proj = folder / "p.wakeline"
    window.save_project(proj)
    assert window.project.flush(30)
    QtWidgets.QApplication.processEvents()
    assert not shown and proj.exists()
    for p in folder.iterdir():
        p.unlink()
    folder.rmdir()
    (tmp_path / "work").write_text("a file where the folder was")
    window.session.set_visible(window.layer_id("demo.csv"), False)
    window.run_step("clean")
    wait_for_jobs(window)
    assert window.project.flush(30)
    QtCore.QCoreApplication.processEvents()
    assert shown and "Saving the project failed" in shown[0]
    assert "[not saved]" in window.windowTitle()
    assert "Saving the project failed" in window.log.toPlainText()


def test_command_line_opens_files_in_the_application(monkeypatch, tmp_path):
    from wakeline.app import cli

    seen = {}
    monkeypatch.setattr(
        "wakeline.app.main.run",
        lambda files, screenshot=None, read=None: seen.update(files=files, read=read) or 0,
    )
    assert cli.main(["a.csv", "b.csv"]) == 0
    assert [p.name for p in seen["files"]] == ["a.csv", "b.csv"] and seen["read"] == {}
    assert cli.main(["--debug"]) == 0 and seen["files"] == []
    # the reading flags reach the import (a radar's x/y metres need their origin)
    assert cli.main(["gui", "xy.csv", "--origin", "63.4,10.4", "--tz", "+01:00"]) == 0
    assert seen["read"] == {"origin": "63.4,10.4", "tz": "+01:00"}


def test_pipeline_presets_are_the_cli_json(window, tmp_path):
    from wakeline.core.pipeline import Pipeline

    window.params.from_dict({"maneuver": {"threshold_deg": 22.0}})
    path = tmp_path / "pipe.json"
    window.save_pipeline(path)
    pipe = Pipeline.from_json(path.read_text())
    assert [name for name, _ in pipe.stages] == ["clean", "compress"]
    assert pipe.stages[1][1]["maneuver"].threshold_deg == 22.0
    window.params.reset()
    assert window.load_pipeline(path) == []
    assert window.params.params("maneuver").threshold_deg == 22.0


def test_export_as_it_came_in_follows_lineage(window, tmp_path):
    """A result layer is written in the layout of the file its source came from."""
    src = tmp_path / "radar.csv"
    df = simulate.demo_scene().head(300)
    lines = ["SendShipNO,SendTime,nNO,lon,lat"]
    secs = (df["time"] - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds().astype(int)
    for s, t, b, lon, lat in zip(
        df["sensor"], secs, df["batch"], df["lon"], df["lat"], strict=True
    ):
        lines.append(f"{s},{t},{b},{lon:.6f},{lat:.6f}")
    src.write_text("\n".join(lines) + "\n")
    lid = load(window, src)
    assert window.layers[lid].meta.get("layout")
    window.run_step("clean")
    wait_for_jobs(window)
    cleaned = window.session.find(lid, "clean", "cleaned")
    window.select_layer(cleaned.id)
    out = tmp_path / "back.csv"
    assert window.export_as_came_in(out) is not None
    wait_for_jobs(window)
    assert out.read_text().splitlines()[0] == "SendShipNO,SendTime,nNO,lon,lat"


def test_an_untouched_layer_comes_back_as_it_came_in_row_order_and_all(window, tmp_path):
    """Operator test: Export ▸ As it came in of a source layer wrote its rows in track
    order (the window keeps layers sorted), where the CLI gives the file back byte for
    byte. A radar export in time order (tracks interleaved) comes back identical; the
    cleaned layer keeps the file's order of the rows it kept."""
    src = tmp_path / "radar.csv"
    df = simulate.demo_scene(seed=3).head(400).sort_values("time", kind="stable")
    lines = ["SendTime,nNO,lon,lat,SendShipNO"]
    secs = (df["time"] - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds().astype(int)
    for s, t, b, lon, lat in zip(
        df["sensor"], secs, df["batch"], df["lon"], df["lat"], strict=True
    ):
        lines.append(f"{t},{b},{lon:.6f},{lat:.6f},{s}")
    src.write_text("\n".join(lines) + "\n")
    lid = load(window, src)
    assert not window.layers[lid].points["wl_row"].is_monotonic_increasing  # stored sorted
    out = tmp_path / "back.csv"
    assert window.export_as_came_in(out) is not None
    wait_for_jobs(window)
    assert out.read_bytes() == src.read_bytes()
    window.run_step("clean")
    wait_for_jobs(window)
    window.select_layer(window.session.find(lid, "clean", "cleaned").id)
    assert window.export_as_came_in(out) is not None
    wait_for_jobs(window)
    kept = out.read_text().splitlines()
    assert kept[0] == lines[0] and len(kept) > 300
    assert [lines.index(x) for x in kept[1:]] == sorted(lines.index(x) for x in kept[1:])
    csv_out = tmp_path / "canonical.csv"
    assert window.export("csv", csv_out) is not None
    wait_for_jobs(window)
    assert "wl_row" not in csv_out.read_text().splitlines()[0]


def test_canonical_export_of_an_untouched_layer_exports_like_as_it_came_in(window, tmp_path):
    """Operator test h150 (4b): File ▸ Export CSV of an unchanged source layer wrote its
    rows in track order (the window keeps layers sorted), so `wakeline export --like` of
    it wrote the file's lines in batch/time order, not the file's (docs/export.md: the
    same bytes as the window's As it came in). The canonical CSV of a layer that carries
    its file rows is written in the file's order; a course the import blanked (380.4)
    comes back too."""
    from wakeline.app.cli import main

    src = tmp_path / "radar.csv"
    df = simulate.demo_scene(seed=3).head(400).sort_values("time", kind="stable")
    lines = ["SendTime,nNO,lon,lat,course,SendShipNO"]
    secs = (df["time"] - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds().astype(int)
    for k, (s, t, b, lon, lat) in enumerate(
        zip(df["sensor"], secs, df["batch"], df["lon"], df["lat"], strict=True)
    ):
        course = "380.4" if k == 250 else f"{(k * 7) % 360}.5"
        lines.append(f"{t},{b},{lon:.6f},{lat:.6f},{course},{s}")
    src.write_text("\n".join(lines) + "\n")
    lid = load(window, src)
    assert not window.layers[lid].points["wl_row"].is_monotonic_increasing  # stored sorted
    came, canon, like = tmp_path / "came.csv", tmp_path / "canonical.csv", tmp_path / "like.csv"
    assert window.export_as_came_in(came) is not None
    assert window.export("csv", canon) is not None
    wait_for_jobs(window)
    assert came.read_bytes() == src.read_bytes()
    assert "wl_row" not in canon.read_text().splitlines()[0]
    assert main(["export", str(canon), "-o", str(like), "--like", str(src)]) == 0
    assert like.read_bytes() == came.read_bytes()


def test_map_image_and_relative_times(window, tmp_path):
    src = tmp_path / "scene.csv"
    df = simulate.demo_scene().head(400)
    df["time"] = pd.to_datetime(
        (df["time"] - df["time"].min()).dt.total_seconds(), unit="s", utc=True
    )  # seconds from a scene start, as MTAD has them
    write_points(df, src)
    load(window, src)
    assert window.batch_model.index(0, 3).data().startswith("T+")
    png = tmp_path / "map.png"
    assert window.export_map_image(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_detail_time_axes_keep_minutes(qtbot):
    """A track of hours: the detail plots' time axes say "min", never "kmin"."""
    from wakeline.app.detail import DetailPanel

    panel = DetailPanel()
    qtbot.addWidget(panel)
    panel.factor_curve.setData(np.linspace(0.0, 5000.0, 50), np.zeros(50))
    panel.factor_plot.getPlotItem().enableAutoRange()
    panel.resize(600, 400)
    panel.show()
    qtbot.waitExposed(panel)
    QtWidgets.QApplication.processEvents()
    for plot in (panel.factor_plot, panel.z_plot):
        label = plot.getAxis("bottom").labelString()
        assert "(min)" in label and "kmin" not in label, label


def test_detail_time_axis_of_a_track_without_factor_is_not_the_last_tracks(qtbot):
    """Operator test: after an 8-day track's δ, a fused track (no δ: "run Maneuvers or
    Compress to see δ") showed the time axis of the 8-day one, 0 … 12,000 min."""
    from wakeline.app.detail import DetailPanel

    panel = DetailPanel()
    qtbot.addWidget(panel)
    panel.resize(600, 400)
    panel.show()
    qtbot.waitExposed(panel)
    t0 = pd.Timestamp("2024-08-01", tz="UTC")
    long = pd.DataFrame(
        {
            "time": t0 + pd.to_timedelta(np.arange(100) * 130.0, unit="min"),
            "maneuver_factor": np.linspace(0.0, 90.0, 100),
            "is_maneuver": np.arange(100) == 50,
        }
    )
    panel.show_track(long, threshold_deg=15.0)
    QtWidgets.QApplication.processEvents()
    assert panel.factor_plot.viewRange()[0][1] > 10_000
    panel.show_track(pd.DataFrame({"time": long["time"].head(5)}))
    QtWidgets.QApplication.processEvents()
    assert panel.factor_plot.viewRange()[0][1] <= 1.0
    panel.show_track(long.head(20), threshold_deg=15.0)  # data again: its own range
    QtWidgets.QApplication.processEvents()
    assert 2000 < panel.factor_plot.viewRange()[0][1] < 3000


def test_detail_says_why_its_factor_plot_is_empty(qtbot):
    """Operator test h150: with no track selected, and on a fused track (no δ), the
    maneuver-factor plot was empty axes with no text. It says why, in the language set,
    in a smaller font than a figure's title (which keeps its own size after a reason)."""
    from wakeline.app.detail import DetailPanel

    panel = DetailPanel()
    qtbot.addWidget(panel)

    def title() -> tuple[str, str]:
        label = panel.factor_plot.getPlotItem().titleLabel
        return label.text, label.opts["size"]

    panel.clear()
    assert title() == ("No track selected.<br>Click one on the map or in the table.", "9pt")
    # h225 item 7: no empty -0.4…0.4 axes under the hint
    axes = [panel.factor_plot.getPlotItem().getAxis(side) for side in ("left", "bottom")]
    assert not any(axis.isVisible() for axis in axes)
    t0 = pd.Timestamp("2024-08-01", tz="UTC")
    fused = pd.DataFrame({"time": t0 + pd.to_timedelta(np.arange(5), unit="min")})
    panel.show_track(fused, fused=True)
    assert all(axis.isVisible() for axis in axes)
    assert title()[0] == "No δ for a fused track: run Maneuvers on its layer"
    panel.show_track(fused)
    assert title()[0] == "No δ for this track: run Maneuvers on its layer"
    app = QtWidgets.QApplication.instance()
    translator = i18n.install(app, "zh_CN", None)
    try:
        panel.retranslate()
        assert title()[0] == "此航迹没有 δ：请对其图层运行机动检测"
    finally:
        i18n.install(app, "en", translator)
    panel.retranslate()
    with_factor = fused.assign(maneuver_factor=1.0, is_maneuver=np.arange(5) == 2)
    panel.show_track(with_factor, threshold_deg=15.0)
    assert title() == ("1 maneuver; threshold 15°", "11pt")


def test_detail_factor_curve_breaks_at_gaps_and_leaves_undefined_ends_out(qtbot):
    """Operator test: the DMA ship's δ (its hours at rest cleaned away) was drawn as
    straight ramps from 50° to 125° across 4-hour gaps, and the ends where δ is undefined
    as 0°. The curve breaks at a gap of more than 10 median steps; NaN is not drawn."""
    from wakeline.app.detail import DetailPanel

    panel = DetailPanel()
    qtbot.addWidget(panel)
    t0 = pd.Timestamp("2023-03-01", tz="UTC")
    minutes = np.r_[np.arange(40.0), 280.0 + np.arange(40.0)]  # a 4-hour gap
    delta = np.r_[np.nan, np.nan, np.linspace(0, 50, 36), np.nan, np.nan] + 0.0
    delta = np.r_[delta, 125.0 - delta]
    track = pd.DataFrame(
        {
            "time": t0 + pd.to_timedelta(minutes, unit="min"),
            "maneuver_factor": delta,
            "is_maneuver": np.zeros(80, dtype=bool),
        }
    )
    panel.show_track(track, threshold_deg=15.0)
    x, y = panel.factor_curve.getData()
    gap = np.flatnonzero(np.isnan(x))
    assert len(gap) == 1 and x[gap[0] - 1] == 39.0 and x[gap[0] + 1] == 280.0
    assert not (y == 0.0)[np.isfinite(x)][:2].any()  # the undefined start is not 0°
    assert np.isnan(y[:2]).all() and panel.factor_curve.opts["connect"] == "finite"


def test_detail_compression_plot_draws_a_track_across_the_antimeridian_in_its_band(qtbot):
    """MTAD scene 7 moved so AIS:1 crosses 180°: the Detail panel's compression plot drew
    raw longitudes, a line from −180 to 180 across the whole plot. Now the original and
    the compressed track are continuous, in the band the map draws their layer in
    (given, or the track's own)."""
    from conftest import MTAD7_AIS1_MIDDLE, mtad_on_180
    from wakeline.app.detail import DetailPanel

    pts = mtad_on_180(MTAD7_AIS1_MIDDLE)
    track = pts[(pts["sensor"] == "AIS") & (pts["batch"].astype(str) == "1")]
    track = track.sort_values("time").reset_index(drop=True)
    assert (track["lon"] > 179.9).any() and (track["lon"] < -179.9).any()
    kept = track.iloc[[0, 20, 40, 60, len(track) - 1]]
    panel = DetailPanel()
    qtbot.addWidget(panel)
    for west in (None, 0.0):
        panel.show_track(track, compressed=kept, original=track, dis_e_m=10.0, lon_west=west)
        x, _ = panel.comp_orig.getData()
        k, _ = panel.comp_kept.getData()
        assert 179.5 < x.min() and x.max() < 180.5 and np.ptp(x) < 0.5  # was ~360
        assert np.allclose(k, x[[0, 20, 40, 60, len(track) - 1]])


def test_screenshot_of_a_file_that_does_not_load_ends_with_an_error(qtbot, tmp_path, capsys):
    """`wakeline gui BAD --screenshot X` returned never: the failure's modal dialog waited
    for a click no one could give. Now the failure is printed and the run ends (exit 2)."""
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    started = time.perf_counter()
    assert run([empty], screenshot=tmp_path / "x.png", language="en") == 2
    assert time.perf_counter() - started < 60
    assert "the file is empty" in capsys.readouterr().err


def test_screenshot_of_a_missing_file_beside_a_good_one_ends(qtbot, tmp_path, capsys, monkeypatch):
    """Operator test 9, D4: `wakeline gui MISSING GOOD --screenshot P` hung for ever in a
    modal "Cannot open file" box (the failure of one file of several). Now no modal box
    opens in a screenshot run: the failure goes to stderr, the good file is drawn, the
    PNG is written and the exit status is 2."""

    def no_box(*args, **kwargs):
        raise AssertionError(f"a modal box in a screenshot run: {args[1:]}")

    for name in ("warning", "information", "critical", "question"):
        monkeypatch.setattr(QtWidgets.QMessageBox, name, no_box)
    png = tmp_path / "shot.png"
    started = time.perf_counter()
    assert run([tmp_path / "nofile.csv", demo_path()], screenshot=png, language="en") == 2
    assert time.perf_counter() - started < 60
    assert png.is_file() and png.stat().st_size > 10_000
    err = capsys.readouterr().err
    assert "Cannot open file: " in err and "nofile.csv: no such file" in err


def test_a_scripted_window_tells_on_stderr_not_in_a_box(window, tmp_path, capsys, monkeypatch):
    """D4: the same "Cannot open file" box blocked load_files in a scripted window
    (interactive False); an interactive one still shows it."""
    boxes = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: boxes.append(a[1:]))
    good = tmp_path / "good.csv"
    good.write_text(
        "sensor,batch,time,lon,lat\n"
        + "".join(f"S,1,2024-01-01T00:00:{k:02d}Z,10.{k:02d},55\n" for k in range(10))
    )
    window.interactive = False
    window.load_files([tmp_path / "gone.csv", good])
    wait_for_jobs(window)
    assert boxes == [] and window.layer_id("good.csv") is not None
    assert "gone.csv" in capsys.readouterr().err
    window.interactive = True
    window.load_files([tmp_path / "gone2.csv", good])
    wait_for_jobs(window)
    assert len(boxes) == 1 and "gone2.csv" in boxes[0][1]


def test_a_headerless_files_refusal_names_map_flags_on_stderr_and_the_field_in_the_window(
    window, tmp_path, capsys, monkeypatch
):
    """Operator test 11, F7: `wakeline gui vessels.csv` (no header) said on stderr "the
    import dialog's Column mapping (time=col4, …)"; at the command line the suggested
    mapping is said as the flags to give (--map time=col4 …), in the window's box as the
    dialog's field."""
    boxes = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: boxes.append(a[1:]))
    bare = tmp_path / "bare.csv"
    bare.write_text(
        "".join(
            f"{7 + k % 2} {23.4 + k * 1e-3:.5f} {37.3 + k * 1e-3:.5f} {1722468684 + k}\n"
            for k in range(40)
        )
    )
    window.interactive = False
    window.load_files([bare])
    wait_for_jobs(window)
    err = capsys.readouterr().err
    assert "no header" in err and "--map time=col4" in err and "--map lon=col2" in err
    assert "import dialog" not in err
    window.interactive = True
    window.load_files([bare])
    wait_for_jobs(window)
    said = " ".join(b[1] for b in boxes)
    assert "Column mapping (" in said and "time=col4" in said and "--map" not in said


def test_window_messages_name_the_import_dialog_not_cli_flags(window, write):
    """Operator test: a log warning told a window user to 'give the zone with --tz'."""
    from wakeline.app.window_words import window_words

    rows = ["batch,本地时间,lon,lat"] + [
        f"1,2023-05-01 10:{k:02d}:00,{10 + k * 1e-3:.3f},55" for k in range(20)
    ]
    load(window, write("local.csv", "\n".join(rows) + "\n"))
    log = window.log.toPlainText()
    assert "read as UTC" in log and "Time zone field" in log and "--tz" not in log
    for text in (
        "map it: --map batch=COLUMN, or --map sensor=COLUMN",
        "x.csv: cannot decode; choose the file's encoding (--encoding, e.g. gb18030)",
        "use --tz Europe/Oslo or --delimiter ';'",
    ):
        assert "--" not in window_words(text), window_words(text)
    assert window_words("a value -- not a flag") == "a value -- not a flag"


def test_the_log_says_where_a_steps_points_went_and_why_nothing_fused(window, tmp_path):
    """Operator test (ATD dataset1): the pipeline's log line gave the counts in and out of
    clean, not that 36,031 of 43,359 removed points were the stationary rule's; a fuse
    that paired nothing (MTAD error level 1: the nearest pair 1,651 m apart, the gate
    1,000 m) did not say which gate refused or what to change. The log now has each step's
    own summary, with the window's words."""
    pts = simulate.demo_scene(seed=3)
    moored = pts[pts["sensor"] == "AIS"].head(40).copy()
    moored["batch"], moored["lon"], moored["lat"] = "moored", 10.0, 55.0
    src = tmp_path / "scene.csv"
    write_points(pd.concat([pts, moored], ignore_index=True), src)
    load(window, src)
    window.run_step("pipeline")
    wait_for_jobs(window)
    log = window.log.toPlainText()
    assert "clean: kept" in log and "removed" in log and "stationary" in log, log
    assert "maneuver points; kept" in log and "Dis_e" in log, log
    # Sensors 5 km apart: nothing pairs, and the log says which gate to open, and where.
    apart = pts.copy()
    apart.loc[apart["sensor"] == "R1", "lat"] += 0.045
    far = tmp_path / "apart.csv"
    write_points(apart, far)
    load(window, far)
    window.run_step("fuse")
    wait_for_jobs(window)
    log = window.log.toPlainText()
    assert "0 pairs" in log and "max_distance_m" in log, log
    assert "Parameters panel" in log and "--set" not in log, log


def test_a_job_cancelled_by_the_next_one_says_so(window, tmp_path):
    """Operator test: File ▸ Open of a second file while Associate ran on ATD dataset1
    cancelled the Associate (one job at a time); the log said only "associate
    cancelled". It now names the job that took its place and says to run it again."""
    load(window, demo_path())
    started = []

    def long_job(progress):
        for k in range(2000):
            started.append(k)
            progress(k / 2000, "working")
            time.sleep(0.005)
        return ("export", "x", tmp_path / "x")

    window._start("associate", long_job, ("associate", "demo"))
    deadline = time.time() + 5
    while not started and time.time() < deadline:
        QtWidgets.QApplication.processEvents()
    src = tmp_path / "other.csv"
    write_points(simulate.demo_scene(seed=5), src)
    load(window, src)
    log = window.log.toPlainText()
    # the jobs by their titles (job_title), not their internal names (h159)
    assert "Associate cancelled: Open other.csv took its place" in log, log
    assert "run Associate again" in log, log
    window.runner.cancel()  # a job cancelled by hand says only that
    window._start("associate", long_job, ("associate", "demo"))
    window.runner.cancel()
    wait_for_jobs(window)
    assert window.log.toPlainText().splitlines()[-1] == "Associate cancelled"
    assert window._replaced == {}
    # a replaced job that ends before it sees the cancel leaves no entry behind (review)
    from wakeline.app.worker import Failed

    window._replaced[999] = "open other.csv"
    window._on_job_message(Failed(999, "associate", "gone", ""))
    assert window._replaced == {}


def test_files_of_one_name_get_layer_names_apart(window, tmp_path):
    """Operator test: ais/tracks.csv and radar/tracks.csv were both "tracks.csv" in the
    Layers list and the legend (and "tracks.csv + tracks.csv · fused"); a file opened
    twice gave two layers of one name."""
    paths = []
    for folder, seed in (("ais", 1), ("radar", 2)):
        (tmp_path / folder).mkdir()
        paths.append(tmp_path / folder / "tracks.csv")
        write_points(simulate.demo_scene(seed=seed), paths[-1])
    window.load_files(paths)
    wait_for_jobs(window)
    window.load_files(paths[:1])
    wait_for_jobs(window)
    names = [lay.name for lay in window.layers.values()]
    assert names == ["tracks.csv", "radar/tracks.csv", "tracks.csv (2)"], names
    shown = [window.layer_list.item(r).text() for r in range(window.layer_list.count())]
    assert len(set(shown)) == 3, shown
    # a third file of that name whose folder is "radar" too: the folders above tell it
    # apart, as the core names the sensors of a fusion (review of session 21)
    other = tmp_path / "b" / "radar" / "tracks.csv"
    other.parent.mkdir(parents=True)
    write_points(simulate.demo_scene(seed=3), other)
    window.load_files([other])
    wait_for_jobs(window)
    assert [lay.name for lay in window.layers.values()][-1] == "b/radar/tracks.csv"


def test_parameters_panel_loads_a_table_by_the_command_lines_max_gap_rule(qtbot):
    """Review of session 21: the panel applied the max_gap rule when an edit changed a
    value, the command line by what a table holds. A loaded table (project, preset,
    pipeline) now decides as the command line does: an older table with only max_gap_s
    gives max_gap_steps 0 even when max_gap_s equals the current value, an earlier edit
    of max_gap_steps does not carry over, and the order of the values does not matter.
    (The note under the tree follows a language switch: tests/test_translations.py.)"""
    from wakeline.app.params_panel import ParamsPanel
    from wakeline.core.clean import CleanParams

    def cli(resample: dict) -> float:
        settings = {f"resample.{k}": str(v) for k, v in resample.items()}
        return CleanParams().with_settings(settings).resample.max_gap_steps

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    default_gap = panel.clean_params().resample.max_gap_s
    for before, table in (
        ({}, {"max_gap_s": default_gap}),  # an older table, max_gap_s unchanged
        ({"max_gap_steps": 3.0}, {"max_gap_s": 100.0}),  # an edit before the load
        ({}, {"max_gap_steps": 2.0, "max_gap_s": 100.0}),  # both, steps listed first
        ({}, {"max_gap_s": 100.0, "max_gap_steps": 2.0}),
    ):
        panel.reset()
        for name, v in before.items():
            panel.root.child("clean", "resample", name).setValue(v)
        assert panel.from_dict({"clean": {"resample": table}}) == []
        shown = panel.root.child("clean", "resample", "max_gap_steps").value()
        assert panel.clean_params().resample.max_gap_steps == cli(table) == shown, table


def test_the_log_counts_one_track_in_the_singular(window, tmp_path):
    """Operator test (Saronic vessel_1, Øresund): the log read "1 tracks", "1 targets",
    "1 pairs". One helper (:func:`wakeline.core.words.count`) now makes the counted nouns
    of the window's log and of the command line's summaries."""
    from wakeline.core.words import count

    assert [count(1, "track"), count(2, "track"), count(0, "pair")] == [
        "1 track",
        "2 tracks",
        "0 pairs",
    ]
    assert count(1_234, "row") == "1,234 rows"
    pts = simulate.demo_scene(seed=3)
    ais = pts[pts["sensor"] == "AIS"]
    one = ais[ais["batch"] == ais["batch"].iloc[0]].copy()
    src = tmp_path / "one.csv"
    write_points(one, src)
    load(window, src)
    window.run_step("clean")
    wait_for_jobs(window)
    log = window.log.toPlainText()
    assert f"one.csv: {len(one)} rows in 1 track (" in log, log
    assert f"clean on one.csv: kept {len(one)} of {len(one)} points in 1 track" in log, log
    # The same ship silent for 5 min: two tracks, joined into one target by one pair.
    t = pd.to_datetime(one["time"])
    mid = t.iloc[len(t) // 2]
    two = one[(t < mid) | (t > mid + pd.Timedelta(minutes=5))].copy()
    two["batch"] = np.where(pd.to_datetime(two["time"]) < mid, "first", "second")
    src = tmp_path / "two.csv"
    write_points(two, src)
    load(window, src)
    window.run_step("associate")
    wait_for_jobs(window)
    log = window.log.toPlainText()
    assert "two.csv: 2 tracks -> 1 target (1 join of 1 candidate pair, optimal)" in log, log
    for wrong in ("1 tracks", "1 targets", "1 joins", "1 candidate pairs", "1 pairs"):
        assert f" {wrong}" not in log, log


def test_detail_title_counts_one_maneuver_in_the_singular(qtbot):
    """Seen on ATD dataset1's window (session 21): "1 maneuvers; threshold 15°"."""
    from wakeline.app.detail import DetailPanel

    panel = DetailPanel()
    qtbot.addWidget(panel)
    t = pd.to_datetime(np.arange(6) * 60.0, unit="s", utc=True)
    track = pd.DataFrame(
        {
            "time": t,
            "lon": np.linspace(10.0, 10.05, 6),
            "lat": np.full(6, 55.0),
            "maneuver_factor": [0.0, 5.0, 40.0, 5.0, 0.0, 0.0],
            "is_maneuver": [False, False, True, False, False, False],
        }
    )
    panel.show_track(track, threshold_deg=15.0)
    assert panel.factor_plot.getPlotItem().titleLabel.text == "1 maneuver; threshold 15°"
    panel.show_track(track.assign(is_maneuver=track["maneuver_factor"] > 1), threshold_deg=15.0)
    assert panel.factor_plot.getPlotItem().titleLabel.text == "3 maneuvers; threshold 15°"


@pytest.mark.parametrize("language", ["en", "zh_CN"])
def test_help_menu_about_and_documentation(window, monkeypatch, language):
    """Operator test 8, D10: no Help menu, nothing showed the version, the licence or the
    data credits. Help (the last menu) ▸ About Wakeline names the version, the licence,
    Qt and PySide6, the four seed papers, the bundled data's notices (links to their
    files) and the real data sets; Help ▸ Documentation gives the README, which links
    docs/, and never asks for a browser on a screen without a desktop (offscreen)."""
    import importlib.metadata

    import PySide6
    from PySide6 import QtGui

    from wakeline.app import about

    opened = []
    monkeypatch.setattr(QtGui.QDesktopServices, "openUrl", lambda url: opened.append(url) or True)
    window.set_language(language)
    try:
        bar = [a.menu() for a in window.menuBar().actions()]
        assert bar[-1] is window.menus["help"]
        help_actions = window.menus["help"].actions()
        keys = window.actions_["keys"]  # Help ▸ Keyboard shortcuts (h230, h225 item 11)
        assert help_actions == [window.actions_["docs"], keys, window.actions_["about"]]
        dialog = window.show_about()
        text = dialog.text.toPlainText()
        version = importlib.metadata.version("wakeline")
        assert f"Wakeline {version}" in text and "MIT" in text
        assert QtCore.qVersion() in text and PySide6.__version__ in text
        for seed in ("000", "001", "002", "003"):
            assert seed in text
        for name in ("Natural Earth", "Autoferry", "MTAD"):
            assert name in text
        html = dialog.text.toHtml()
        for notice in ("NOTICE.md", "README.md"):  # the bundled files, linked
            assert notice in html
        assert about.resource_path("coastline", "NOTICE.md").exists()
        if language == "zh_CN":
            assert dialog.windowTitle() == "关于 Wakeline"
            assert window.menus["help"].title() == "帮助(&H)" and "许可证" in text
            assert "种子文献 000：" in text and "未声明" in text
        else:
            assert dialog.windowTitle() == "About Wakeline" and "Licence: MIT" in text
        dialog.close()
        window.actions_["docs"].trigger()
        path = window.open_documentation()
        assert path is not None and path.name == "README.md" and path.exists()
        assert (path.parent / "docs" / "review.md").exists()
        assert not opened  # offscreen: the log says where it is, no browser asked
        assert str(path) in window.log.toPlainText().splitlines()[-1]
    finally:
        window.set_language("en")


# -- the map tells ships and layers apart (h227; operator review h225 items 2-4, 9) ----


def _layer_of(window, kind: str) -> str:
    return next(i for i, lay in window.layers.items() if lay.kind == kind)


def test_the_active_layer_is_drawn_on_top_and_the_others_dimmed(window):
    from wakeline.app.map_canvas import DIM_OPACITY

    load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    src, cleaned = _layer_of(window, "source"), _layer_of(window, "cleaned")
    for active, other in ((cleaned, src), (src, cleaned), (cleaned, src)):
        window.select_layer(active)
        wait_for_jobs(window)
        on_top = window.canvas.layer_items(active)
        below = window.canvas.layer_items(other)
        assert min(i.zValue() for i in on_top) > max(i.zValue() for i in below)
        assert all(i.opacity() == 1.0 for i in on_top)
        assert all(i.opacity() == pytest.approx(DIM_OPACITY) for i in below)


def test_the_active_layer_is_coloured_by_track_and_back(qtbot, tmp_path):
    from conftest import make_window
    from wakeline.app.map_colors import TRACK_PALETTE

    w = make_window(qtbot, tmp_path, track_colors=True)
    try:
        lid = load(w, demo_path())
        w.select_layer(lid)
        wait_for_jobs(w)
        n_tracks = w.batch_model.rowCount()
        data = w.canvas.draw_data(lid)
        colours = [data.geometry.colors[g] for g in data.geometry.group]
        assert len(colours) == n_tracks
        assert len(set(colours)) == min(n_tracks, len(TRACK_PALETTE))
        assert len(w.canvas.layer_items(lid)) == min(n_tracks, len(TRACK_PALETTE))
        # the Layers list and the other layers keep the layer's own colours
        assert w.views[lid].colors == data.geometry.plain[1]
        w.actions_["color_by_track"].setChecked(False)  # View ▸ Colour by track off
        wait_for_jobs(w)
        assert len(w.canvas.layer_items(lid)) == 2  # AIS and R1 again
        assert w.settings.value("map/color_by_track") in (False, "false")
        # the track labels: at most one per track, none overlapping (decluttered)
        texts = w.update_track_labels()
        assert 0 < len(texts) <= n_tracks
    finally:
        w.runner.cancel()
        w.runner.wait()


def test_points_removed_by_cleaning_drawn_as_an_overlay(window):
    load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    cleaned = _layer_of(window, "cleaned")
    rejected = window.layers[cleaned].tables["rejected"]
    assert len(rejected) > 0
    name = f"{cleaned}/removed"
    assert name not in window.canvas.layer_names()  # off by default
    window.actions_["show_removed"].setChecked(True)
    wait_for_jobs(window)
    data = window.canvas.draw_data(name)
    with_pos = int((rejected["lon"].notna() & rejected["lat"].notna()).sum())
    assert data.n_vertices == with_pos
    rules = sorted(rejected["rule"].astype(str).unique())
    assert [c.label.rsplit(" · ", 1)[1].split(" (")[0] for c in data.curves] == [
        f"removed: {r}" for r in rules
    ]
    # the hover over a removed point says its rule
    window.canvas.fit()
    QtWidgets.QApplication.processEvents()
    g = data.geometry
    info = window.canvas.hover(float(g.lon[0]), float(g.lat[0]))
    assert info is not None and info.get("note", "").startswith("removed by clean: ")
    window.session.set_visible(cleaned, False)  # hidden with its layer
    assert not any(i.isVisible() for i in window.canvas.layer_items(name))
    window.actions_["show_removed"].setChecked(False)
    assert name not in window.canvas.layer_names()


def test_a_point_restored_twice_before_the_first_is_back_is_restored_once(window, qtbot):
    """Restore this point chosen again while the first restore is still made in the
    worker: the second passed its check (the point still in the rejected table), failed
    in the worker, and stayed on the undo stack as done; its undo then took the first's
    point out and a second undo put its row into the rejected table twice."""
    load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    lid = _layer_of(window, "cleaned")
    layer = window.layers[lid]
    rej0, n0 = layer.tables["rejected"], len(layer.points)
    wid = int(rej0[rej0.action == "removed"].wl_id.iloc[0])
    tool = window.restore_tool
    tool.restore(lid, [wid])
    tool.restore(lid, [wid])  # before the first is swapped in
    qtbot.waitUntil(lambda: not tool.busy, timeout=60_000)
    wait_for_jobs(window)
    assert layer.restored == [wid] and len(layer.points) == n0 + 1
    stack = tool.stack(lid)
    while stack.canUndo():
        stack.undo()
        qtbot.waitUntil(lambda: not tool.busy, timeout=60_000)
        wait_for_jobs(window)
    assert layer.restored == [] and len(layer.points) == n0
    rej = layer.tables["rejected"]
    assert len(rej) == len(rej0) and rej.wl_id.tolist() == rej0.wl_id.tolist()


def test_removed_points_restored_from_the_map_with_undo(window, qtbot, tmp_path):
    """SPEC §2: the operator puts points removed by cleaning back — the × nearest a right
    click (one, or all its rule removed on its track), the selected tracks' or those in
    the map's view — into the cleaned layer; Edit ▸ Undo / Redo; the layer's lineage
    records them; the × marks and the batch table follow."""
    load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    lid = _layer_of(window, "cleaned")
    layer = window.layers[lid]
    rej0, n0, ids0 = layer.tables["rejected"], len(layer.points), set(layer.points.wl_id)
    window.actions_["show_removed"].setChecked(True)
    wait_for_jobs(window)
    window.canvas.fit()
    QtWidgets.QApplication.processEvents()
    tool = window.restore_tool

    def settle():  # the restore is made in the worker, then swapped in
        qtbot.waitUntil(lambda: not tool.busy, timeout=60_000)
        wait_for_jobs(window)

    # the × of a row whose point was removed (not changed), its rule and track
    removed = rej0[rej0.action == "removed"]
    row = removed.iloc[len(removed) // 2]
    rule, track = str(row.rule), (str(row.sensor), str(row.batch))
    same = removed[(removed.rule == rule) & (removed.sensor.astype(str) == track[0])]
    same = same[same.batch.astype(str) == track[1]]
    window.canvas.vb.setRange(
        xRange=(row.lon - 1e-4, row.lon + 1e-4), yRange=(row.lat - 1e-4, row.lat + 1e-4)
    )
    QtWidgets.QApplication.processEvents()
    hit = tool.removed_near(float(row.lon), float(row.lat))
    assert hit is not None and hit[0] == lid
    acts = tool.menu_actions(float(row.lon), float(row.lat))
    texts = [a.text() for a in acts]
    hit_row = rej0.iloc[hit[1]]
    assert texts[0] == f"Restore this point (removed by {hit_row.rule})"
    assert texts[-1] == "Restore removed points in the map's view"
    hit_id = int(hit_row.wl_id)
    acts[0].trigger()
    settle()
    assert hit_id in set(layer.points.wl_id) and hit_id not in set(layer.tables["rejected"].wl_id)
    assert len(layer.points) == n0 + 1 and layer.restored == [hit_id]
    assert layer.lineage()["restored"] == [hit_id]
    assert window.canvas.draw_data(f"{lid}/removed").geometry.n_points == len(rej0) - 1
    undo = window.review.act_undo
    assert undo.isEnabled() and "restore 1 points" in undo.text()
    undo.trigger()
    settle()
    assert len(layer.points) == n0 and layer.restored == []
    assert len(layer.tables["rejected"]) == len(rej0)
    assert window.canvas.draw_data(f"{lid}/removed").geometry.n_points == len(rej0)
    window.review.act_redo.trigger()
    settle()
    assert layer.restored == [hit_id]
    undo.trigger()
    settle()
    # all its rule removed on its track: "Restore all N points removed by RULE on S · B"
    many = tool.menu_actions(float(row.lon), float(row.lat))[1]
    on_track = (rej0.sensor.astype(str) == str(hit_row.sensor)) & (
        rej0.batch.astype(str) == str(hit_row.batch)
    )
    want = set(rej0[on_track & (rej0.rule == hit_row.rule) & (rej0.action != "replaced")].wl_id)
    assert many.text() == (
        f"Restore all {len(want)} points removed by {hit_row.rule} on "
        f"{hit_row.sensor} · {hit_row.batch}"
    )
    many.trigger()
    settle()
    assert set(layer.restored) == want and hit_id in want
    # File ▸ Export of the layer writes them
    window.select_layer(lid)
    window.export("csv", tmp_path / "restored.csv")
    wait_for_jobs(window)
    out = pd.read_csv(tmp_path / "restored.csv")
    back = rej0[rej0.wl_id.isin(want)].drop_duplicates("wl_id")
    assert len(out) == len(layer.points) == n0 + len(set(back.wl_id) - ids0)
    got = set(zip(out.batch.astype(str), out.lon.round(6), strict=True))
    assert set(zip(back.batch.astype(str), back.lon.round(6), strict=True)) <= got
    # a box dragged on the map (Edit ▸ Restore … in a box): the points left inside it
    left = layer.tables["rejected"]
    left = left[left.action != "replaced"]
    mid = left.iloc[len(left) // 2]
    west, east, south, north = mid.lon - 0.01, mid.lon + 0.01, mid.lat - 0.01, mid.lat + 0.01
    inside = set(
        left[left.lon.between(west, east) & left.lat.between(south, north)].wl_id.astype(int)
    )
    vb = window.canvas.vb
    down = vb.childGroup.mapToParent(QtCore.QPointF(west, north))
    up = vb.childGroup.mapToParent(QtCore.QPointF(east, south))

    class Drag:  # pyqtgraph's MouseDragEvent, as the map's view box gets it
        def __init__(self, finish):
            self.finish = finish

        def button(self):
            return QtCore.Qt.MouseButton.LeftButton

        def isFinish(self):  # noqa: N802 - pyqtgraph's API
            return self.finish

        def buttonDownPos(self, _button=None):  # noqa: N802
            return down

        def pos(self):
            return up

        def accept(self):
            pass

    box = tool.act_box
    assert "box" in box.text() and box.isCheckable()
    box.setChecked(True)
    vb.mouseDragEvent(Drag(False))
    vb.mouseDragEvent(Drag(True))
    settle()
    assert not box.isChecked() and len(inside) > 0
    assert set(layer.restored) == want | inside
    # the map's view: everything left in it
    window.canvas.fit()
    QtWidgets.QApplication.processEvents()
    assert tool.restore_in_view()
    settle()
    left = layer.tables["rejected"]
    assert (left.action == "replaced").all()
    assert len(left) == 0 and f"{lid}/removed" not in window.canvas.layer_names()
    # three undos give back the layer as clean made it
    undo.trigger()
    undo.trigger()
    undo.trigger()
    settle()
    assert len(layer.points) == n0 and layer.restored == [] and not undo.isEnabled()
    assert window.canvas.draw_data(f"{lid}/removed").geometry.n_points == len(rej0)


def _plots_file(folder, seed: int = 7, scans: int = 150, per: int = 6):
    """A radar's plots: every scan (3 s) several detections of one batch, scattered."""
    rng = np.random.default_rng(seed)
    t = np.repeat(np.arange(scans) * 3.0, per)
    df = pd.DataFrame(
        {
            "sensor": "radar",
            "batch": "plots",
            "time": pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(t, "s"),
            "lon": 10.39 + rng.normal(0, 0.004, len(t)),
            "lat": 63.44 + rng.normal(0, 0.002, len(t)),
        }
    )
    path = folder / "plots.csv"
    write_points(df, path)
    return path


def _ship_file(folder, seed: int = 3):
    """Two ships' AIS tracks (a fix every 10 s, about 10 kn): tracks, not plots."""
    rng = np.random.default_rng(seed)
    frames = []
    for k in range(2):
        n = 120
        t = np.arange(n) * 10.0
        frames.append(
            pd.DataFrame(
                {
                    "sensor": "AIS",
                    "batch": str(100 + k),
                    "time": pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(t, "s"),
                    "lon": 10.30 + 0.01 * k + t * 9e-5 + rng.normal(0, 1e-5, n),
                    "lat": 63.40 + t * 2e-5 * (1 + k) + rng.normal(0, 1e-5, n),
                }
            )
        )
    path = folder / "ships.csv"
    write_points(pd.concat(frames, ignore_index=True), path)
    return path


def test_track_steps_on_radar_plots_warn_without_refusing(window, tmp_path):
    """Session 30 "noticed, left": Run ▸ pipeline on radar plots (the Autoferry
    detections) drew a scribble without a word. It warns in the Log before the run (non-
    modal, the run goes on); a layer of ships' tracks runs without it; Associate (which
    joins tracks) is not warned about."""
    plots = load(window, _plots_file(tmp_path))
    ships = load(window, _ship_file(tmp_path))
    assert window.views[plots].extra.get("plots") and not window.views[ships].extra.get("plots")
    warning = "which looks like radar plots"
    for lid, step, warned in (
        (ships, "pipeline", False),
        (plots, "pipeline", True),
        (plots, "maneuvers", True),
        (plots, "associate", False),
    ):
        window.select_layer(lid)
        before = window.log.toPlainText().count(warning)
        assert window.run_step(step) is not None  # not refused
        wait_for_jobs(window)
        assert window.log.toPlainText().count(warning) == before + warned, (lid, step)
    kinds = {lay.kind for lay in window.layers.values() if lay.name.startswith("plots.csv")}
    assert "compressed" in kinds  # the pipeline ran on the plots all the same


@pytest.mark.parametrize("plots", [True, False])
def test_screenshot_shows_radar_plots_without_the_track_steps(
    qapp, tmp_path, monkeypatch, capsys, plots
):
    """`wakeline gui FILE --screenshot PNG` ran clean, maneuvers, compress on radar plots
    and showed the compressed "tracks" (a scribble). Now a file that is mostly plots is
    shown as dots, the steps not run, and stderr says why with the guidance; ships'
    tracks still get the pipeline."""
    seen = {}
    grab = MainWindow.grab

    def recording_grab(self, *a):
        seen["kinds"] = sorted(lay.kind for lay in self.layers.values())
        lid = next(i for i, lay in self.layers.items() if lay.kind == "source")
        style = self.canvas.draw_data(lid).style
        seen["dots"] = style.width == 0 and style.symbol_size > 0
        seen["guidance"] = self.params.guidance.text()
        return grab(self, *a)

    monkeypatch.setattr(MainWindow, "grab", recording_grab)
    path = _plots_file(tmp_path) if plots else _ship_file(tmp_path)
    assert run([path], screenshot=tmp_path / "shot.png", language="en") == 0
    err = capsys.readouterr().err
    said = [x for x in err.splitlines() if "looks like radar plots, not tracks" in x]
    if plots:
        assert seen["kinds"] == ["source"] and seen["dots"]
        assert said == [
            f"wakeline: {path.name}: most of it looks like radar plots, not tracks: the "
            "track steps (clean, maneuvers, compress) were not run; the screenshot shows the "
            "plots as dots"
        ]
        assert "radar plots" in seen["guidance"]
        assert f"wakeline: {' '.join(seen['guidance'].split())}" in err.splitlines()
    else:
        assert "compressed" in seen["kinds"] and not said


def test_radar_plots_layer_drawn_as_points_with_a_per_layer_choice(window, tmp_path):
    path = _plots_file(tmp_path)
    lid = load(window, path)
    window.select_layer(lid)
    wait_for_jobs(window)
    style = window.canvas.draw_data(lid).style
    assert style.width == 0 and style.symbol_size > 0  # dots, no line
    action = window.actions_["draw_points"]
    assert action.isEnabled() and action.isChecked()
    action.setChecked(False)  # this layer joined as lines
    wait_for_jobs(window)
    assert window.canvas.draw_data(lid).style.width > 0
    action.setChecked(True)
    wait_for_jobs(window)
    assert window.canvas.draw_data(lid).style.width == 0


def test_the_removed_marks_legend_names_the_rules_in_the_windows_language_in_whole_words(
    window,
):
    """Operator test 11, F20: the Chinese window's legend of the × marks said "removed:
    turn (3)" (made in the worker, in English) and cut a rule's name mid-word ("removed:
    st…ry (12,169)"). Now the lines are in the window's language with the rules' names
    the clean summary uses, made anew on a language switch, and shortened by whole words."""
    from wakeline.app.core_text import shown
    from wakeline.app.map_legend import SideLegend

    load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    lid = _layer_of(window, "cleaned")
    name = f"{lid}/removed"
    rules = sorted(window.layers[lid].tables["rejected"]["rule"].astype(str).unique())
    window.actions_["show_removed"].setChecked(True)
    wait_for_jobs(window)
    english = [c.label for c in window.canvas.draw_data(name).curves]
    assert all(f"removed: {r} (" in t for t, r in zip(english, rules, strict=True))
    try:
        window.set_language("zh_CN")
        wait_for_jobs(window)
        labels = [c.label for c in window.canvas.draw_data(name).curves]
        for label, rule in zip(labels, rules, strict=True):
            assert f"已删除：{shown(rule)}（" in label and shown(rule) != rule, label
            assert "removed" not in label
    finally:
        window.set_language("en")
    wait_for_jobs(window)
    assert [c.label for c in window.canvas.draw_data(name).curves] == english
    legend = SideLegend()
    for text in ("saronic.csv · S1 · removed: stationary (12,169)", "removed: stationary (12,169)"):
        shown_text = legend.shown_label(text).split("&nbsp;")[-1]
        words = set(text.replace("·", " ").split())
        assert "stationary (12,169)" in shown_text  # the rule and its count whole
        kept = shown_text.replace("…", " ").split()
        assert all(w in words for w in kept), shown_text  # no word cut


def test_restore_texts_name_the_clean_rules_in_the_windows_language(window, qtbot):
    """Operator test 11 (h249): in the Chinese window the map's Restore entries, Edit ▸
    Undo's text and the log said the rules' English identifiers ("由 turn 删除") while the
    clean summary and the Parameters say 转向异常: the names now come from the same
    catalog."""
    from wakeline.app.restore_points import rule_name, rules_text
    from wakeline.core.clean import STEPS

    window.set_language("zh_CN")
    try:
        names = {rule: rule_name(rule) for rule in (*STEPS, "same_time")}
        assert all(name != rule and not name.isascii() for rule, name in names.items())
        assert names["turn"] == "转向异常"
        assert rules_text({"turn": 1, "stationary": 12_169}) == "转向异常 1, 静止点 12,169"
        # the log names the layer as the Layers list does ("· 已清洗", not "· cleaned")
        load(window, demo_path())
        window.run_step("clean")
        wait_for_jobs(window)
        lid = _layer_of(window, "cleaned")
        window.canvas.fit()
        QtWidgets.QApplication.processEvents()
        assert window.restore_tool.restore_in_view(lid)
        qtbot.waitUntil(lambda: not window.restore_tool.busy, timeout=60_000)
        wait_for_jobs(window)
        said = window.log.toPlainText().splitlines()[-1]
        assert "已清洗" in said and "cleaned" not in said and "恢复" in said
    finally:
        window.set_language("en")
    assert rules_text({"turn": 1, "stationary": 12_169}) == "turn 1, stationary 12,169"

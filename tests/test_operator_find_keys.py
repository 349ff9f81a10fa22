"""Operator review h225 items 5, 8, 11, 12 and 17 (h230): finding one ship (a column
filter, Enter selects and zooms, a selection off the map is panned to), the review queue's
hint, units and decision log line, the keyboard shortcuts, the confirmation before
removing a layer with children or decisions, and the map's measuring mode."""

import math

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from PySide6 import QtCore, QtWidgets  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from test_gui_review_low import _fused_review  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.app.map_interact import measure  # noqa: E402
from wakeline.app.models import BatchTableModel, batch_summary  # noqa: E402
from wakeline.core import geo  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

pytestmark = pytest.mark.gui


def _track(sensor, batch, lon0, lat0, n=20, step_deg=0.01, name=None, t0="2024-05-01"):
    t = pd.date_range(t0, periods=n, freq="60s", tz="UTC")
    out = pd.DataFrame(
        {
            "sensor": sensor,
            "batch": batch,
            "time": t,
            "lon": lon0 + step_deg * np.arange(n),
            "lat": lat0 + 0.5 * step_deg * np.arange(n),
        }
    )
    if name is not None:
        out["shipname"] = name
    return out


def _points():
    return pd.concat(
        [
            _track("AIS", "4139", 10.0, 50.0, name="ARGO"),
            _track("AIS", "41390", 10.5, 50.2, name="BLUE STAR"),
            _track("radar", "7", 11.0, 50.4, name="the 4139 tug"),
            _track("radar", "12", 11.5, 50.6, name=""),
        ],
        ignore_index=True,
    )


def _model(points):
    model = BatchTableModel()
    model.set_summary(batch_summary(points))
    return model


def _shown(model):
    return [model.key_of_row(r) for r in range(model.rowCount())]


def test_the_filter_can_aim_at_one_column_and_plain_text_keeps_any_column(qapp):
    model = _model(_points())
    model.set_filter("4139")  # any column: the batches and the name that holds it
    assert sorted(_shown(model)) == [("AIS", "4139"), ("AIS", "41390"), ("radar", "7")]
    model.set_filter("batch:4139")  # the Batch column only: the tug's name is left out
    assert sorted(_shown(model)) == [("AIS", "4139"), ("AIS", "41390")]
    assert model.filter_column() == "batch"
    model.set_filter("Sensor: radar")  # the title, any case, a space after the colon
    assert sorted(_shown(model)) == [("radar", "12"), ("radar", "7")]
    model.set_filter("name:star")  # the ship's name (a "shipname" column in the file)
    assert _shown(model) == [("AIS", "41390")]
    model.set_filter("mmsi:41390")  # an alias of the Batch column
    assert _shown(model) == [("AIS", "41390")]
    # A prefix that names no column is text: "00:00" is in every start time.
    model.set_filter("00:0")
    assert model.filter_column() is None and model.rowCount() == 4
    model.set_filter_column("sensor")  # the column chosen beside the filter
    model.set_filter("ais")
    assert sorted(_shown(model)) == [("AIS", "4139"), ("AIS", "41390")]


def test_enter_prefers_the_exact_match_and_the_name_column_shows_only_with_names(qapp):
    model = _model(_points())
    model.sort(1, QtCore.Qt.SortOrder.DescendingOrder)  # "41390" above "4139"
    model.set_filter("batch:4139")
    assert model.key_of_row(0) == ("AIS", "41390")
    assert model.key_of_row(model.best_match_row()) == ("AIS", "4139")
    model.set_filter("batch:413")  # no exact match: the first row shown
    assert model.best_match_row() == 0
    model.set_filter("batch:999")
    assert model.best_match_row() is None
    assert model.has_names
    col = [k for k, _ in model.COLUMNS].index("name")
    model.set_filter("")
    names = {model.key_of_row(r): model.index(r, col).data() for r in range(model.rowCount())}
    assert names[("AIS", "4139")] == "ARGO" and names[("radar", "12")] == ""
    bare = _model(_points().drop(columns="shipname"))
    assert not bare.has_names


def _window_with(qtbot, tmp_path, points):
    path = tmp_path / "ships.csv"
    write_points(points, path)
    w = _window(qtbot, tmp_path)
    w.load_files([path])
    _settle(w)
    w.select_layer(w.layer_id(path.name))
    _settle(w)
    return w


def _spread_points():
    """Three tracks far apart, one of them a few hundred metres long (a speck at the
    scale showing all three)."""
    return pd.concat(
        [
            _track("S1", "100", 0.0, 40.0, step_deg=0.05),
            _track("S1", "200", 8.0, 44.0, step_deg=0.05),
            _track("S1", "300", 4.0, 36.0, step_deg=0.0002, name="SPECK"),
        ],
        ignore_index=True,
    )


def _view_box(w):
    (x0, x1), (y0, y1) = w.canvas.vb.viewRange()
    return x0, x1, y0, y1


def test_enter_in_the_filter_selects_the_match_and_zooms_the_map_to_it(qtbot, tmp_path):
    w = _window_with(qtbot, tmp_path, _spread_points())
    w.canvas.fit()
    before = _view_box(w)
    w.filter_edit.setText("batch:300")
    QTest.keyClick(w.filter_edit, QtCore.Qt.Key.Key_Return)
    _settle(w)
    assert w.selected_keys() == [("S1", "300")]
    x0, x1, y0, y1 = _view_box(w)
    pts = w.layers[w.active].points
    speck = pts[pts["batch"] == "300"]
    assert x0 <= speck["lon"].min() and speck["lon"].max() <= x1
    assert y0 <= speck["lat"].min() and speck["lat"].max() <= y1
    assert (x1 - x0) < (before[1] - before[0]) / 10  # zoomed in to the speck
    w.close()


def test_a_selected_track_off_the_map_is_panned_to_at_the_same_scale(qtbot, tmp_path):
    w = _window_with(qtbot, tmp_path, _spread_points())
    pts = w.layers[w.active].points
    first = pts[pts["batch"] == "100"]
    w.canvas.fit(first)  # the map on track 100 only
    _settle(w)
    x0, x1, y0, y1 = _view_box(w)
    w.select_tracks([("S1", "200")])  # as a click in the batch table
    _settle(w)
    n0, n1, m0, m1 = _view_box(w)
    assert n1 - n0 == pytest.approx(x1 - x0, rel=1e-6)  # a pan: the same scale
    other = pts[pts["batch"] == "200"]
    cx, cy = (
        (other["lon"].min() + other["lon"].max()) / 2,
        (other["lat"].min() + other["lat"].max()) / 2,
    )
    assert n0 < cx < n1 and m0 < cy < m1
    assert w.canvas.bring_selection_into_view() == ""  # on the map now: nothing more
    # A track picked on the map stays where it was clicked (no pan, no zoom).
    before = _view_box(w)
    hit = other.iloc[5]
    w.canvas.pick(float(hit["lon"]), float(hit["lat"]))
    _settle(w)
    assert _view_box(w) == pytest.approx(before)
    w.close()


def _press(w, widget, key, modifier=QtCore.Qt.KeyboardModifier.NoModifier):
    """A key with the focus on ``widget`` (the window active first: a shortcut of the
    map or the time panel acts only with the focus in them)."""
    w.activateWindow()
    QtWidgets.QApplication.processEvents()
    widget.setFocus()
    deadline = QtCore.QDeadlineTimer(3000)
    while not widget.hasFocus() and not deadline.hasExpired():
        w.activateWindow()
        widget.setFocus()
        QtWidgets.QApplication.processEvents()
    assert widget.hasFocus()
    QTest.keyClick(QtWidgets.QApplication.focusWidget() or widget, key, modifier)
    QtWidgets.QApplication.processEvents()


def test_shortcuts_trigger_their_actions_and_are_listed(qtbot, tmp_path, monkeypatch):
    w = _window_with(qtbot, tmp_path, _spread_points())
    runs = []
    monkeypatch.setattr(w, "run_step", lambda step: runs.append(step))
    _press(w, w.canvas, QtCore.Qt.Key.Key_F5)
    assert runs == ["pipeline"]
    # Space plays and pauses with the map focused; in the filter it is a space.
    assert not w.time_panel.is_playing
    qtbot.waitUntil(lambda: math.isfinite(w.time_panel.time()), timeout=5000)  # its range set
    _press(w, w.canvas, QtCore.Qt.Key.Key_Space)
    assert w.time_panel.is_playing
    _press(w, w.canvas, QtCore.Qt.Key.Key_Space)
    assert not w.time_panel.is_playing
    w.filter_edit.clear()
    _press(w, w.filter_edit, QtCore.Qt.Key.Key_Space)
    assert not w.time_panel.is_playing and w.filter_edit.text() == " "
    w.filter_edit.clear()
    # Right steps the time forward by one step (the map focused).
    w.time_panel.set_time(w.time_panel._lo)
    t0 = w.time_panel.time()
    _press(w, w.canvas, QtCore.Qt.Key.Key_Right)
    assert w.time_panel.time() == pytest.approx(t0 + w.time_panel.params().step_s)
    _press(w, w.canvas, QtCore.Qt.Key.Key_Left)
    assert w.time_panel.time() == pytest.approx(t0)
    # B: box zoom on; Z: zoom to the selection; Ctrl+F: the filter has the focus.
    _press(w, w.canvas, QtCore.Qt.Key.Key_B)
    assert w.actions_["box"].isChecked()
    _press(w, w.canvas, QtCore.Qt.Key.Key_Escape)
    assert not w.actions_["box"].isChecked()
    zoomed = []
    monkeypatch.setattr(w.canvas, "zoom_to_selection", lambda: zoomed.append(1) or True)
    _press(w, w.canvas, QtCore.Qt.Key.Key_Z)
    assert zoomed == [1]
    _press(w, w.canvas, QtCore.Qt.Key.Key_F, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert QtWidgets.QApplication.focusWidget() is w.filter_edit
    # Shown in the menus and in Help ▸ Keyboard shortcuts.
    view = {a.text(): a.shortcut().toString() for a in w.menus["view"].actions()}
    assert view["&Fit to data"] == "Home" and view["&Zoom to selection"] == "Z"
    from wakeline.app.actions import keys_text

    text = keys_text(w)
    for key in ("F5", "Space", "Home", "Z", "B", "Ctrl+F"):
        assert f"<b>{key}</b>" in text, key
    w.close()


def _no_question(monkeypatch):
    asked = []
    box = QtWidgets.QMessageBox
    monkeypatch.setattr(
        box, "question", lambda *a, **k: asked.append(a[2]) or box.StandardButton.Yes
    )
    return asked


def test_removing_a_layer_with_children_is_undone_without_a_question(qtbot, tmp_path, monkeypatch):
    """h237 (was: asked first, h225 item 12): removal is an undoable command; Edit ▸
    Restore removed layer brings the layer back in its place, drawn and in the project."""
    w = _window_with(qtbot, tmp_path, _spread_points())
    src = w.active
    w.run_step("clean")
    _settle(w)
    cleaned = next(lid for lid, lay in w.layers.items() if lay.parent == src)
    asked = _no_question(monkeypatch)
    w.select_layer(src)
    w.remove_active_layer()
    _settle(w)
    assert src not in w.layers and not asked
    assert src not in w.canvas.layer_names() and w.layer_row(src) < 0
    undo = w.layer_undo
    assert undo.act_undo.isEnabled() and "Restore removed" in undo.act_undo.text()
    undo.act_undo.trigger()
    _settle(w)
    assert list(w.layers) == [src, cleaned] and w.layer_row(src) == 0
    assert src in w.canvas.layer_names() and w.active == src
    assert w.layers[cleaned].parent == src
    undo.act_redo.trigger()  # Remove layer again
    _settle(w)
    assert src not in w.layers and w.layer_row(src) < 0
    undo.act_undo.trigger()
    _settle(w)
    w.select_layer(cleaned)  # no children, no decisions: removed the same way
    w.remove_active_layer()
    _settle(w)
    assert cleaned not in w.layers and not asked
    w.close()


def test_removing_a_fused_layer_with_review_decisions_is_undone_with_them(
    qtbot, tmp_path, monkeypatch
):
    w = _fused_review(qtbot, tmp_path)
    fused = w.active
    panel = w.review.bound.panel
    panel.view.setFocus()
    panel.accept()
    _settle(w)
    children, decisions = w.removal_cost(fused)
    assert children == 0 and decisions >= 1
    statuses = list(w.review.bound.controller.state.status)
    asked = _no_question(monkeypatch)
    w.remove_active_layer()
    _settle(w)
    assert fused not in w.layers and not asked
    w.layer_undo.undo()
    _settle(w)
    assert fused in w.layers and w.active == fused
    w.select_layer(fused)
    _settle(w)
    assert list(w.review.bound.controller.state.status) == statuses  # its decisions bind again
    w.close()


def test_the_review_queue_says_what_pending_accept_and_reject_mean(qtbot, tmp_path):
    w = _fused_review(qtbot, tmp_path)
    b = w.review.bound
    panel, st = b.panel, b.controller.state
    assert "Pending = joined" in panel.hint.text() and "never proposed" in panel.hint.text()
    titles = [
        panel.view.model().headerData(c, QtCore.Qt.Orientation.Horizontal)
        for c in range(panel.view.model().columnCount())
    ]
    assert "margin m" in titles and "cost m" in titles  # a fusion's costs are metres
    targets_before = len(set(st.target_of_track().tolist()))
    pid = panel.current()
    a, b_track = st.proposals.set_index("proposal").loc[pid, ["track_a", "track_b"]]
    panel.view.setFocus()
    panel.reject()
    _settle(w)
    line = w.log.toPlainText().splitlines()[-1]
    total = len(set(st.target_of_track().tolist()))
    assert total == targets_before + 1  # the rejected pair fell apart
    assert line == (
        f"Review: reject {pid}: {a} and {b_track} are 2 targets now ({total} targets in all)"
    )
    assert w.review.echo.text() == f"Review: reject {pid}"
    w.close()


def test_measure_gives_range_and_bearing_between_two_known_points(qtbot, tmp_path):
    # Along a meridian: one degree of latitude is R·π/180, due north.
    r = measure(5.0, 60.0, 5.0, 61.0)
    assert r["range_m"] == pytest.approx(geo.EARTH_RADIUS_M * math.pi / 180, rel=1e-9)
    assert r["range_nm"] == pytest.approx(r["range_m"] / 1852.0)
    assert r["bearing_deg"] == pytest.approx(0.0, abs=1e-9)
    # Along the equator, due west; the short way across 180°.
    r = measure(179.5, 0.0, -179.5, 0.0)
    assert r["range_m"] == pytest.approx(geo.EARTH_RADIUS_M * math.pi / 180, rel=1e-9)
    assert r["bearing_deg"] == pytest.approx(90.0, abs=1e-9)
    assert measure(0.0, 0.0, -1.0, 0.0)["bearing_deg"] == pytest.approx(270.0, abs=1e-9)
    # In the window: the action's mode, two clicks, a line drawn, Esc leaves it.
    w = _window_with(qtbot, tmp_path, _spread_points())
    w.actions_["measure"].setChecked(True)
    assert w.canvas.is_measuring()
    assert w.canvas.measure_click(0.0, 40.0) is None
    result = w.canvas.measure_click(0.0, 41.0)
    assert result["bearing_deg"] == pytest.approx(0.0, abs=1e-9)
    x, _ = w.canvas._measure_line.getData()
    assert len(x) == 2 and w.canvas._measure_label.isVisible()
    assert "nm" in w.statusBar().currentMessage()
    w.actions_["box"].setChecked(True)  # the other map mode: measuring stops
    assert not w.actions_["measure"].isChecked() and not w.canvas.is_measuring()
    w.actions_["measure"].setChecked(True)
    _press(w, w.canvas, QtCore.Qt.Key.Key_Escape)
    assert not w.actions_["measure"].isChecked() and not w.canvas.is_measuring()
    w.close()

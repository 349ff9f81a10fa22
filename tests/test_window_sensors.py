"""The map's per-layer view of the operator's choosing (h237): the active layer's legend
entries in bold, and View ▸ Sensors — one sensor's tracks of a layer hidden (a view
filter: the layer's points untouched), the batch table and the status bar's counts
following."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _window  # noqa: E402

from wakeline.core.io import write_points  # noqa: E402

pytestmark = pytest.mark.gui


def _two_sensors(n=40):
    t = pd.date_range("2024-05-01", periods=n, freq="10s", tz="UTC")
    parts = []
    for sensor, batches, lat0 in (("AIS", ("101", "102"), 50.0), ("radar", ("7",), 50.2)):
        for k, b in enumerate(batches):
            parts.append(
                pd.DataFrame(
                    {
                        "sensor": sensor,
                        "batch": b,
                        "time": t,
                        "lon": 10.0 + 0.1 * k + 0.001 * np.arange(n),
                        "lat": lat0 + 0.0005 * np.arange(n),
                    }
                )
            )
    return pd.concat(parts, ignore_index=True)


def _loaded(qtbot, tmp_path):
    path = tmp_path / "scene.csv"
    write_points(_two_sensors(), path)
    w = _window(qtbot, tmp_path)
    w.load_files([path])
    _settle(w)
    lid = w.layer_id(path.name)
    w.select_layer(lid)
    _settle(w)
    return w, lid


def _bold(w, lid):
    legend = w.canvas.legend
    items = [i for n in w.map_names(lid) for i in w.canvas.layer_items(n)]
    return [legend.is_bold(i) for i in items]


def test_the_active_layers_legend_entries_are_bold_and_only_them(qtbot, tmp_path):
    w, src = _loaded(qtbot, tmp_path)
    widest = w.canvas.legend.widest  # the column reserved from the start
    w.run_step("clean")
    _settle(w)
    cleaned = next(i for i, lay in w.layers.items() if lay.parent == src)
    w.select_layer(cleaned)
    _settle(w)
    assert _bold(w, cleaned) and all(_bold(w, cleaned))
    assert _bold(w, src) and not any(_bold(w, src))
    legend = w.canvas.legend
    bold = [lab for sample, lab in legend.items if legend.is_bold(sample.item)]
    assert bold and all(lab.opts.get("bold") for lab in bold)
    # drawn as the plain label is fitted (never shortened more for being bold)
    assert all(lab.text == legend.shown_label(lab.toolTip()) for lab in bold)
    w.select_layer(src)
    _settle(w)
    assert all(_bold(w, src)) and not any(_bold(w, cleaned))
    # a bold label fits the reserved column: it never widens it
    assert w.canvas.legend.widest == widest
    w.close()


def _sensor_actions(w):
    w._fill_sensor_menu()
    return {a.text().split(" ")[-1]: a for a in w.sensor_menu.actions() if a.isCheckable()}


def test_a_sensor_hidden_leaves_the_map_table_and_counts_not_the_layer(qtbot, tmp_path):
    w, lid = _loaded(qtbot, tmp_path)
    layer = w.layers[lid]
    points = layer.points
    acts = _sensor_actions(w)
    assert sorted(acts) == ["AIS", "radar"] and all(a.isChecked() for a in acts.values())
    colors = dict(zip(("AIS", "radar"), w.views[lid].colors, strict=False))
    acts["radar"].setChecked(False)  # View ▸ Sensors ▸ radar off
    _settle(w)
    view = w.views[lid]
    assert set(view.points["sensor"]) == {"AIS"} and len(view.points) == 80
    assert w.layers[lid].points is points and len(points) == 120  # a view filter only
    assert set(view.draw.geometry.sensor) == {"AIS"}
    assert view.colors[0] == colors["AIS"]  # each sensor keeps its colour
    model = w.batch_model  # the table's rows filtered (not greyed)
    assert sorted(model.key_of_row(r) for r in range(model.rowCount())) == [
        ("AIS", "101"),
        ("AIS", "102"),
    ]
    assert "80 points" in w.counts_text and "sensors hidden: radar" in w.counts_text
    acts = _sensor_actions(w)
    assert not acts["radar"].isChecked() and not acts["AIS"].isEnabled()  # the last one stays
    # kept per layer: another layer made active and back keeps the choice
    w.run_step("clean")
    _settle(w)
    cleaned = next(i for i, lay in w.layers.items() if lay.parent == lid)
    w.select_layer(cleaned)
    _settle(w)
    assert all(a.isChecked() for a in _sensor_actions(w).values())
    assert model.rowCount() == 3
    w.select_layer(lid)
    _settle(w)
    assert model.rowCount() == 2 and set(w.views[lid].points["sensor"]) == {"AIS"}
    _sensor_actions(w)["radar"].setChecked(True)
    _settle(w)
    assert w.views[lid].points is w.layers[lid].points and model.rowCount() == 3
    assert "sensors hidden" not in w.counts_text and "120 points" in w.counts_text
    # removed with a sensor hidden, then restored: shown whole (its choice went with it)
    _sensor_actions(w)["AIS"].setChecked(False)
    _settle(w)
    assert set(w.views[lid].points["sensor"]) == {"radar"}
    w.remove_active_layer()
    _settle(w)
    assert lid not in w._full_views and lid not in w.hidden_sensors
    w.layer_undo.undo()
    _settle(w)
    assert set(w.views[lid].points["sensor"]) == {"AIS", "radar"}
    assert sorted(w.map_names(lid)) and w.layers[lid].points is points
    w.close()


def test_a_layer_changed_to_its_hidden_sensors_only_is_shown_whole(qtbot, tmp_path):
    """AIS hidden, then the layer's points changed (a step re-run in place, a vessel
    table joined) to AIS rows only: the filter would show nothing and View ▸ Sensors,
    of one sensor, offers no way back; the layer is shown whole, its choice dropped
    (h245)."""
    w, lid = _loaded(qtbot, tmp_path)
    _sensor_actions(w)["AIS"].setChecked(False)
    _settle(w)
    assert set(w.views[lid].points["sensor"]) == {"radar"}
    points = w.layers[lid].points
    ais = points[points["sensor"] == "AIS"].reset_index(drop=True)
    w.session.replace_points(lid, ais)
    _settle(w)
    assert len(w.views[lid].points) == len(ais) and w.batch_model.rowCount() == 2
    assert lid not in w.hidden_sensors and "sensors hidden" not in w.counts_text
    assert lid not in w._full_views  # no second whole view kept
    w.close()


def test_a_failed_sensor_filter_shows_the_layer_whole_once_not_again_and_again(
    qtbot, tmp_path, monkeypatch
):
    """The worker's filtered view failing (None handed back, the layer unchanged) was
    queued again at once, failing again every turn for ever (the window never settled);
    the layer is shown whole, its choice dropped, and the log says so (h245)."""
    import wakeline.app.layer_view as layer_view

    w, lid = _loaded(qtbot, tmp_path)
    whole = w.views[lid]
    calls = []
    prepare = layer_view.prepare_view

    def failing(*args, **kwargs):
        calls.append(1)
        raise RuntimeError("a failed preparation")

    monkeypatch.setattr(layer_view, "prepare_view", failing)
    _sensor_actions(w)["radar"].setChecked(False)
    _settle(w, timeout_s=15)
    monkeypatch.setattr(layer_view, "prepare_view", prepare)
    assert len(calls) == 1
    assert lid not in w.hidden_sensors and w.views[lid] is whole
    assert "sensors hidden" not in w.counts_text
    assert "radar" in w.log.toPlainText().splitlines()[-1]
    w.close()


def _time_tracks(w) -> int:
    """How many tracks the time slider's markers run over (its index, once rebuilt)."""
    from PySide6 import QtCore, QtWidgets

    tc = w.time_controller
    timer = QtCore.QElapsedTimer()
    timer.start()
    while (tc.busy or w.drawing) and timer.elapsed() < 20_000:
        QtWidgets.QApplication.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
    _settle(w)
    return len(tc.overlay.scene.color_of_track)


def test_a_hidden_sensors_tracks_leave_the_time_sliders_markers(qtbot, tmp_path):
    """Operator test 11 (h249): on Autoferry radar + lidar, radar hidden, the position
    marker of a radar plot stayed on the map at the slider's time (the slider's index was
    made before the filter and not again)."""
    w, lid = _loaded(qtbot, tmp_path)
    assert _time_tracks(w) == 3  # AIS 101, 102 and radar 7
    _sensor_actions(w)["radar"].setChecked(False)
    _settle(w)
    assert _time_tracks(w) == 2  # the radar's track gone from the markers and trails
    _sensor_actions(w)["radar"].setChecked(True)
    _settle(w)
    assert _time_tracks(w) == 3
    w.close()

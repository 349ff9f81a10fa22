"""Operator test 5 (h181): the Parameters dock's refusals (D-params-1, D-params-2) and
the map with every layer unticked or across the antimeridian (D-map-2, D-map-3)."""

import pytest

pytest.importorskip("pytestqt")

from wakeline.app.params_panel import ParamsPanel  # noqa: E402

pytestmark = pytest.mark.gui


def test_a_refusal_is_said_once_and_cleared_by_defaults(qtbot):
    panel = ParamsPanel()
    qtbot.addWidget(panel)
    panel.show()
    said = []
    panel.refused.connect(said.append)
    for path, value in (
        (("clean", "stationary", "radius_m"), -50.0),
        (("clean", "speed", "v_max_kn"), 0.0),
        (("maneuver", "threshold_deg"), -3.0),
    ):
        said.clear()
        panel.root.child(*path).setValue(value)
        qtbot.wait(10)
        assert len(said) == 1, (path, said)  # was 2: the spin box echoed it back
        assert panel.problem.text() == said[0]
    panel.root.child("maneuver", "threshold_deg").setValue(-3.0)  # again, a later turn
    qtbot.wait(10)
    assert len(said) == 2  # a second attempt is said again
    panel.reset()
    assert panel.problem.text() == ""  # every value is a default again
    assert panel.to_dict() == ParamsPanel().to_dict()


def test_with_every_layer_unticked_the_map_shows_no_track(qtbot, tmp_path):
    """D-map-2: the selected track's curve and legend row and the time markers stayed."""
    from PySide6 import QtCore
    from test_review_window import _settle, _window

    from wakeline.core import simulate
    from wakeline.core.io import write_points

    src = tmp_path / "scene.csv"
    write_points(simulate.demo_scene(), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    key = w.batch_model.key_of_row(0)
    w.select_tracks([key])
    _settle(w)

    def legend_rows():
        return [label.text for _, label in w.canvas.legend.items if label.isVisible()]

    qtbot.waitUntil(lambda: any(key[1] in t for t in legend_rows()), timeout=5000)
    item = w.layer_list.item(w.layer_row(w.layer_id(src.name)))
    item.setCheckState(QtCore.Qt.CheckState.Unchecked)
    _settle(w)
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=5000)
    qtbot.wait(20)
    assert legend_rows() == []
    assert not any(i.isVisible() for i in w.canvas._selection_items)
    assert len(w.time_controller.overlay.markers.getData()[0]) == 0
    assert w.selected_keys() == [key]  # the table keeps it
    item.setCheckState(QtCore.Qt.CheckState.Checked)
    _settle(w)
    qtbot.waitUntil(lambda: any(key[1] in t for t in legend_rows()), timeout=5000)
    w.close()


def test_longitude_labels_wrap_past_the_antimeridian(qtbot):
    """D-map-3: a track drawn across 180° ran on to 180.2, 180.4 on the axis."""
    from wakeline.app.map_canvas import MapCanvas, wrap_longitude

    assert [wrap_longitude(v) for v in (179.8, 180.0, -180.0, 0.0)] == [179.8, 180.0, -180.0, 0.0]
    assert wrap_longitude(180.2) == pytest.approx(-179.8)
    assert wrap_longitude(-180.4) == pytest.approx(179.6)
    assert wrap_longitude(540.0) == 180.0
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    axis = canvas.getAxis("bottom")
    assert axis.tickStrings([179.8, 180.0, 180.2, 180.4], 1.0, 0.2) == [
        "179.8",
        "180.0",
        "-179.8",
        "-179.6",
    ]

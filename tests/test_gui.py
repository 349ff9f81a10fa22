"""GUI tests (pytest-qt, offscreen)."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtWidgets  # noqa: E402

from wakeline.app.main import run  # noqa: E402
from wakeline.app.main_window import MainWindow, format_dms  # noqa: E402
from wakeline.app.map_canvas import nan_separated  # noqa: E402
from wakeline.resources import demo_path  # noqa: E402

pytestmark = pytest.mark.gui


@pytest.fixture
def window(qtbot):
    w = MainWindow()
    qtbot.addWidget(w)
    w.resize(1400, 900)
    return w


def test_demo_draws_one_curve_per_sensor(window):
    assert window.load_file(demo_path())
    assert sorted(window.canvas.layer_names()) == ["AIS", "R1"]
    n_tracks = window.track_model.rowCount()
    assert n_tracks == window.points.groupby(["sensor", "batch"]).ngroups
    nan_gaps = 0
    for name in window.canvas.layer_names():
        x, _ = window.canvas.layer_item(name).getData()
        nan_gaps += int(np.isnan(x).sum())
    assert nan_gaps == n_tracks - 2  # one NaN between consecutive tracks of a layer
    vb = window.canvas.getPlotItem().getViewBox()
    lat = window.points.lat.mean()
    assert vb.state["aspectLocked"] == pytest.approx(np.cos(np.radians(lat)))


def test_bad_file_shows_a_dialog_not_a_crash(window, tmp_path, monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n")
    assert not window.load_file(bad)
    assert shown and "missing required column" in shown[0]
    assert "Error:" in window.log.toPlainText()


def test_nan_separated_unwraps_the_antimeridian():
    df = pd.DataFrame(
        {
            "sensor": ["S"] * 5,
            "batch": ["a", "a", "a", "b", "b"],
            "time": pd.to_datetime([0, 60, 120, 0, 60], unit="s", utc=True),
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


def test_screenshot(qapp, tmp_path):
    png = tmp_path / "shot.png"
    assert run([demo_path()], screenshot=png) == 0
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000

"""The bearing view (pytest-qt, offscreen): bearing lines on the map, detections table."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from wakeline.app.bearing_view import BearingView, bearing_line_points  # noqa: E402
from wakeline.core import geo  # noqa: E402
from wakeline.core.bearing import detect_with_report  # noqa: E402
from wakeline.core.bearing_eval import simulate_table  # noqa: E402

pytestmark = pytest.mark.gui


def test_bearing_lines_start_at_the_observer_and_point_along_the_bearing():
    df = simulate_table(seed=3)
    lines = bearing_line_points(df, 10_000.0, max_lines=5)
    assert lines["batch"].nunique() == 5 * df["batch"].nunique()
    start, end = lines.iloc[0::2], lines.iloc[1::2]
    assert np.isin(start["lon"].round(7), df["obs_lon"].round(7)).all()
    dist = geo.haversine_m(
        start.lon.to_numpy(), start.lat.to_numpy(), end.lon.to_numpy(), end.lat.to_numpy()
    )
    assert np.allclose(dist, 10_000.0, rtol=0.01)
    az = geo.initial_bearing_deg(
        start.lon.to_numpy(), start.lat.to_numpy(), end.lon.to_numpy(), end.lat.to_numpy()
    )
    merged = start.assign(az=az).merge(
        df[["batch", "time", "bearing"]].rename(columns={"batch": "b"}),
        left_on="time",
        right_on="time",
    )
    merged = merged[merged["batch"].str.split("#").str[0] == merged["b"]]
    assert len(merged) and np.abs(geo.angle_diff(merged["az"], merged["bearing"])).max() < 0.5
    assert bearing_line_points(df.drop(columns=["obs_lon", "obs_lat"])).empty


def test_view_shows_lines_and_exports_detections(qtbot, tmp_path):
    df = simulate_table(seed=4)
    df = df[df.batch.isin(["s2-m", "s4-straight"])]
    table, report = detect_with_report(df)
    view = BearingView()
    qtbot.addWidget(view)
    view.show_result(df, table, report)
    assert {"observer", "bearing lines"} <= set(view.map.layer_names())
    assert ("maneuvers" in view.map.layer_names()) == (len(table) > 0)
    assert view.model.rowCount() == len(table)
    assert "windows tested" in view.log.toPlainText()
    out = tmp_path / "d.csv"
    view.export(out)
    back = pd.read_csv(out)
    assert list(back.columns) == ["batch", "detect_time", "maneuver_time", "z"]
    assert len(back) == len(table)
    view.model.sort(3)  # sort by z
    assert view.model.rowCount() == len(table)


BLUE, RED, GREY = (0x1F, 0x77, 0xB4), (0xD6, 0x27, 0x28), (0x55, 0x55, 0x55)


def rgb_of(widget) -> np.ndarray:
    """The widget's pixels as an (h, w, 3) array, every map curve painted afresh."""
    from PySide6 import QtGui

    for name in widget.map.layer_names():
        for item in widget.map.layer_items(name):
            item.curve.update()
    img = widget.map.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    raw = np.frombuffer(img.constBits(), dtype=np.uint8).reshape(h, img.bytesPerLine())
    return raw[:, : w * 3].reshape(h, w, 3).copy()


def to_px(canvas, lon: float, lat: float) -> tuple[int, int]:
    """Pixel (x, y) of the map widget's image where ``lon, lat`` is drawn."""
    from PySide6 import QtCore

    scene = canvas.vb.mapViewToScene(QtCore.QPointF(lon, lat))
    p = canvas.viewport().mapTo(canvas, canvas.mapFromScene(scene))
    return p.x(), p.y()


def has_colour(rgb: np.ndarray, xy: tuple[int, int], colour, radius: int = 2) -> bool:
    x, y = xy
    patch = rgb[max(y - radius, 0) : y + radius + 1, max(x - radius, 0) : x + radius + 1]
    return bool((np.abs(patch.astype(int) - colour).max(axis=-1) <= 40).any())


def along(lines: pd.DataFrame, fractions) -> list[tuple[float, float]]:
    """Points at ``fractions`` of the way from each line's start to its end."""
    start, end = lines.iloc[0::2], lines.iloc[1::2]
    x0, y0 = start["lon"].to_numpy(), start["lat"].to_numpy()
    x1, y1 = end["lon"].to_numpy(), end["lat"].to_numpy()
    return [
        (float(a + f * (b - a)), float(c + f * (d - c)))
        for a, b, c, d in zip(x0, x1, y0, y1, strict=True)
        for f in fractions
    ]


def eo_like_table() -> pd.DataFrame:
    """A camera's bearings at 63.4° N from a ferry that hardly moves (like the Autoferry
    EO file), two targets sweeping round it; no detections."""
    t = pd.date_range("2021-05-05 08:50", periods=240, freq="2s", tz="UTC")
    rows = []
    for batch, b0, rate in (("t1", 20.0, 0.6), ("t2", 200.0, -0.4)):
        rows.append(
            pd.DataFrame(
                {
                    "sensor": "eo",
                    "batch": batch,
                    "time": t,
                    "bearing": (b0 + rate * np.arange(len(t))) % 360.0,
                    "obs_lon": 10.3855 + 1e-5 * np.arange(len(t)),
                    "obs_lat": 63.4360 + 5e-6 * np.arange(len(t)),
                }
            )
        )
    return pd.concat(rows, ignore_index=True)


@pytest.mark.parametrize("case", ["sim", "eo"])
def test_bearing_lines_maneuvers_and_observer_are_painted(qtbot, case):
    """Every bearing line is a 20 km leg between two points of one time: the map's jump
    breaking cut each one to a lone vertex and nothing was painted (a dock with the
    observer alone). Now the pixels along the lines have the lines' colours."""
    if case == "sim":
        df = simulate_table(seed=4)
        table, report = detect_with_report(df)
        assert len(table)
    else:
        df, table, report = eo_like_table(), pd.DataFrame(), []
    view = BearingView()
    qtbot.addWidget(view)
    view.resize(1200, 700)
    view.show()
    qtbot.waitExposed(view)
    view.show_result(df, table, report)
    qtbot.wait(50)
    rgb = rgb_of(view)
    canvas = view.map
    (x0, x1), (y0, y1) = canvas.vb.viewRange()

    lines = bearing_line_points(df, 20_000.0)
    # Every line lies in the view (fit to the lines and the observer).
    assert lines["lon"].between(x0, x1).all() and lines["lat"].between(y0, y1).all()
    points = along(lines, (0.4, 0.7, 0.95))
    blue = [has_colour(rgb, to_px(canvas, *p), BLUE) for p in points]
    # Red maneuver lines lie over some of the blue ones.
    assert np.mean(blue) > 0.9, f"{np.mean(blue):.0%} of the bearing-line samples are blue"
    if len(table):
        maneuvers = bearing_line_points(df, 20_000.0, at_times=table)
        assert len(maneuvers) == 2 * len(table)
        for p in along(maneuvers, (0.3, 0.6, 0.9)):
            assert has_colour(rgb, to_px(canvas, *p), RED), p
    # The observer's track is drawn over the fan of lines that start on it.
    obs = df[["obs_lon", "obs_lat"]].to_numpy()[:: max(len(df) // 20, 1)]
    assert all(has_colour(rgb, to_px(canvas, lon, lat), GREY) for lon, lat in obs)


def test_map_keeps_a_usable_width_in_a_narrow_dock(qtbot):
    """In the main window's right dock (tabbed, ~560 px) the map was given ~200 px, of
    which the latitude axis and the legend column took all but ~40 px of plot. The view
    now asks for room for a plot of MIN_PLOT_PX and puts the table under the map when
    the two do not fit side by side."""
    from PySide6 import QtCore, QtWidgets

    from wakeline.app.bearing_view import MIN_PLOT_PX

    win = QtWidgets.QMainWindow()
    qtbot.addWidget(win)
    win.setCentralWidget(QtWidgets.QLabel("map"))
    view = BearingView()
    dock = QtWidgets.QDockWidget("Bearing-only", win)
    dock.setWidget(view)
    win.addDockWidget(QtCore.Qt.DockWidgetArea.RightDockWidgetArea, dock)
    win.resize(1400, 800)
    win.resizeDocks([dock], [300], QtCore.Qt.Orientation.Horizontal)
    win.show()
    qtbot.waitExposed(win)
    df = simulate_table(seed=4)
    view.show_result(df, *detect_with_report(df))
    qtbot.wait(50)
    assert view.split.orientation() == QtCore.Qt.Orientation.Vertical
    assert view.map.plot_size_px()[0] >= MIN_PLOT_PX
    assert view.width() < 800  # the dock stays a dock, not half the window
    # Wide (floating, or a wide dock): map and table side by side, the map the larger.
    dock.setFloating(True)
    dock.resize(1400, 700)
    qtbot.waitUntil(lambda: view.split.orientation() == QtCore.Qt.Orientation.Horizontal)
    qtbot.waitUntil(lambda: view.map.width() > view.width() // 2)
    assert view.map.plot_size_px()[0] >= MIN_PLOT_PX

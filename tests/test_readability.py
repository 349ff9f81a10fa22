"""The map and window read well on real files: layer colours, framing, axis and table
text, scale bar (GUI tests, pytest-qt, offscreen)."""

import itertools

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtGui  # noqa: E402

from conftest import load  # noqa: E402
from wakeline.app.cli import main  # noqa: E402
from wakeline.app.main import wait_for_jobs  # noqa: E402
from wakeline.app.map_canvas import MapCanvas  # noqa: E402
from wakeline.core.session import KIND_COLORS  # noqa: E402
from wakeline.resources import demo_path  # noqa: E402

pytestmark = pytest.mark.gui


# -- colour vision ---------------------------------------------------------------------

#: Machado, Oliveira & Fernandes (2009), deuteranopia (severity 1), on linear RGB.
DEUTERANOPIA = np.array(
    [
        [0.367322, 0.860646, -0.227968],
        [0.280085, 0.672501, 0.047413],
        [-0.011820, 0.042940, 0.968881],
    ]
)


def _linear(color: str) -> np.ndarray:
    c = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _lab(color: str) -> np.ndarray:
    """CIELAB (D65) of ``#rrggbb``."""
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = (m @ _linear(color)) / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a: str, b: str) -> float:
    """CIE76 colour difference (the test's own, not the application's)."""
    return float(np.linalg.norm(_lab(a) - _lab(b)))


def _hex(linear: np.ndarray) -> str:
    c = np.clip(linear, 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return "#" + "".join(f"{int(round(v * 255)):02x}" for v in s)


def deutan(color: str) -> str:
    """The colour a deuteranope sees (simulated)."""
    return _hex(DEUTERANOPIA @ _linear(color))


def test_simulated_deuteranopia_confuses_red_and_green():
    # The simulation itself: tab10's red and green merge, blue and orange do not.
    assert delta_e(deutan("#d62728"), deutan("#2ca02c")) < 10
    assert delta_e(deutan("#1f77b4"), deutan("#ff7f0e")) > 80


# -- 1. layer colours --------------------------------------------------------------------


def test_each_visible_layer_has_a_colour_of_its_own(window, tmp_path):
    """The demo (AIS and R1 in one file) and a second file, then the pipeline: no colour
    is drawn by two layers (the R1 sensor and a radar file were drawn in the compressed
    layer's red), the derived layers keep their kinds' colours, and each layer's icon in
    the Layers list is the colour its curves are drawn in."""
    demo = load(window, demo_path())
    radar = pd.read_csv(demo_path())
    radar = radar[radar["sensor"] == "R1"].assign(sensor="radar")
    path = tmp_path / "radar.csv"
    radar.to_csv(path, index=False)
    load(window, path)
    window.select_layer(demo)
    window.run_step("pipeline")
    wait_for_jobs(window)
    assert [lay.kind for lay in window.layers.values()] == [
        "source",
        "source",
        "cleaned",
        "maneuvers",
        "compressed",
    ]
    colors = {}
    for lid, layer in window.layers.items():
        drawn = [c.color for c in window.canvas.draw_data(lid).curves]
        assert drawn[0] == layer.color
        colors[lid] = set(drawn)
    for a, b in itertools.combinations(colors, 2):
        assert not colors[a] & colors[b], (window.layers[a].name, window.layers[b].name)
    for layer in window.layers.values():
        if layer.kind in KIND_COLORS:
            assert layer.color == KIND_COLORS[layer.kind]
    row = window.layer_row(window.layer_id("radar.csv"))
    icon = window.layer_list.item(row).icon().pixmap(14, 14).toImage()
    assert icon.pixelColor(7, 7).name() == window.layers[window.layer_id("radar.csv")].color


def test_maneuver_marks_are_drawn_over_the_compressed_lines(window):
    """The compressed layer comes after the maneuvers, and its lines run through the same
    points: drawn later at an equal height they hid the marks (an operator's report)."""
    demo = load(window, demo_path())
    window.select_layer(demo)
    window.run_step("pipeline")
    wait_for_jobs(window)
    # whichever layer is active (drawn on top of the others: session 30), the marks stay
    # over its lines (the compressed layer made active hid them)
    for active in [None, *window.layers]:
        if active is not None:
            window.select_layer(active)
            wait_for_jobs(window)
        z = {}
        for lid, layer in window.layers.items():
            items = window.canvas._items[lid]
            assert items
            z[layer.kind] = min(item.zValue() for item in items)
        lines = max(z[k] for k in ("source", "cleaned", "compressed"))
        assert z["maneuvers"] > lines, (active, z)
        assert z["maneuvers"] < window.canvas.marks.zValue()  # under the selection's marks


def test_a_rerun_keeps_its_colour_and_a_second_result_of_a_kind_takes_another(window, tmp_path):
    demo = load(window, demo_path())
    window.run_step("clean")
    wait_for_jobs(window)
    cleaned = next(i for i, lay in window.layers.items() if lay.kind == "cleaned")
    assert window.layers[cleaned].color == KIND_COLORS["cleaned"]
    window.select_layer(demo)
    window.run_step("clean")  # replaces the cleaned layer in place: its colour stays
    wait_for_jobs(window)
    assert window.layers[cleaned].color == KIND_COLORS["cleaned"]
    other = tmp_path / "other.csv"
    pd.read_csv(demo_path()).assign(sensor="B").to_csv(other, index=False)
    second = load(window, other)
    window.select_layer(second)
    window.run_step("clean")
    wait_for_jobs(window)
    greens = [i for i, lay in window.layers.items() if lay.kind == "cleaned"]
    assert len(greens) == 2
    assert window.layers[greens[1]].color != KIND_COLORS["cleaned"]
    shown = [c.color for d in window.canvas.visible_draw_data() for c in d.curves]
    assert len(shown) == len(set(shown))


def test_render_by_batch_keeps_batch_colours_apart_from_steps_and_on_top(
    qapp, tmp_path, monkeypatch
):
    """``render --step clean maneuvers --color-by batch``: no batch in a colour that looks
    like a step layer's (the cleaned green was the third batch colour), and the batches
    drawn over the steps' lines, under the maneuver marks."""
    from wakeline.app import map_render

    drawn = {}

    def keep(layers, path, **kw):
        drawn["layers"] = list(layers)
        return {"bounds": (0, 0, 1, 1), "layers": 0, "points": 0, "vertices": 0, "size": (1, 1)}

    monkeypatch.setattr(map_render, "render_png", keep)
    pts = pd.read_csv(demo_path())
    csv = tmp_path / "demo.csv"
    pts.to_csv(csv, index=False)
    args = ["render", str(csv), "-o", str(tmp_path / "x.png"), "--color-by", "batch"]
    assert main([*args, "--step", "clean", "maneuvers"]) == 0
    source, *steps = drawn["layers"]
    batch_colors = set(source.geometry.colors)
    assert len(batch_colors) >= 10  # the demo has more batches than that
    for step in steps:
        for c in step.geometry.colors:
            assert all(delta_e(c, b) >= 20 for b in batch_colors), (step.name, c)
    lines = [s for s in steps if s.style.width]
    marks = [s for s in steps if not s.style.width]
    assert lines and marks
    assert all(source.style.z > s.style.z for s in lines)
    assert all(source.style.z < s.style.z for s in marks)


def test_selection_colours_stay_apart_for_a_deuteranope(qtbot):
    """Two and three tracks selected over a blue layer: their colours differ for a
    deuteranope as well (the selection went red, then green)."""
    rows = []
    for k in range(4):
        lon = 10.0 + 0.01 * np.arange(20)
        rows.append(
            pd.DataFrame(
                {
                    "sensor": "S",
                    "batch": str(k),
                    "time": pd.to_datetime(np.arange(20) * 10, unit="s", utc=True),
                    "lon": lon,
                    "lat": 55.0 + 0.01 * k,
                }
            )
        )
    df = pd.concat(rows, ignore_index=True)
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.set_layer("L", df, "#1f77b4")
    for n in (2, 3, 4):
        canvas.show_selection(df[df["batch"].astype(int) < n])
        colours = [canvas.selection_color("S", str(k)) for k in range(n)]
        for a, b in itertools.combinations(colours, 2):
            assert delta_e(deutan(a), deutan(b)) >= 20, (n, a, b)
        assert all(delta_e(c, "#1f77b4") >= 20 for c in colours)


# -- 2. framing --------------------------------------------------------------------------


def _view_holds(window, points: pd.DataFrame) -> np.ndarray:
    x0, x1, y0, y1 = window.canvas.current_view()
    lon, lat = points["lon"].to_numpy(), points["lat"].to_numpy()
    return (lon >= x0) & (lon <= x1) & (lat >= y0) & (lat <= y1)


def gulf_with_outliers(n_tracks: int = 40, n_points: int = 120) -> pd.DataFrame:
    """Tracks in a 6° x 3° box (the ATD set's Gulf traffic) and one track whose last
    three positions are 25° west and 17° north (its West-Coast outliers)."""
    rng = np.random.default_rng(7)
    rows = []
    t = pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(np.arange(n_points) * 60, "s")
    for k in range(n_tracks):
        lon0, lat0 = rng.uniform(-96, -90), rng.uniform(26, 29)
        step = (
            rng.normal(0, 0.002, (n_points, 2)).cumsum(axis=0)
            + 0.003 * np.arange(n_points)[:, None]
        )
        rows.append(
            pd.DataFrame(
                {
                    "sensor": "S1",
                    "batch": str(1000 + k),
                    "time": t,
                    "lon": lon0 + step[:, 0],
                    "lat": lat0 + step[:, 1],
                }
            )
        )
    far = rows[0].copy()
    far.loc[far.index[-3:], ["lon", "lat"]] = [[-122.8, 46.0], [-122.9, 46.1], [-123.0, 46.2]]
    rows[0] = far
    return pd.concat(rows, ignore_index=True)


def test_first_view_frames_the_points_and_fit_to_data_shows_all(window, tmp_path):
    """Three far-flung positions among 4,800: the first view frames the traffic (every
    point but those three, and not 20° of empty map), "Fit to data" every point."""
    pts = gulf_with_outliers()
    path = tmp_path / "gulf.csv"
    pts.to_csv(path, index=False)
    load(window, path)
    inside = _view_holds(window, pts)
    assert (~inside).sum() == 3
    x0, x1, y0, y1 = window.canvas.current_view()
    window.actions_["fit"].trigger()
    assert _view_holds(window, pts).all()
    f0, f1, g0, g1 = window.canvas.current_view()
    # The traffic at over 4x the scale "Fit to data" shows it (it spans 33° then).
    assert (x1 - x0) < 0.25 * (f1 - f0) and (y1 - y0) < 0.25 * (g1 - g0)
    # The screenshot's view is the first view too (MapCanvas.frame).
    window.canvas.frame()
    assert (~_view_holds(window, pts)).sum() == 3


def test_demo_and_mtad_scene_are_framed_whole(window):
    """Sets without far-flung points open as a fit shows them: every point in view."""
    from conftest import real_file

    demo = load(window, demo_path())
    assert _view_holds(window, window.layers[demo].points).all()
    window.canvas.frame()
    framed = window.canvas.current_view()
    window.canvas.fit()
    assert window.canvas.current_view() == pytest.approx(framed)
    two = real_file("mtad-dtwcm", "two_sensor")
    window.session.clear()
    window.load_files([two / "scene-6_error_0_AIS.csv", two / "scene-6_error_0_radar.csv"])
    wait_for_jobs(window)
    assert len(window.layers) == 2
    for layer in window.layers.values():
        assert _view_holds(window, layer.points).all(), layer.name


# -- 3. axis title and time columns --------------------------------------------------------


def oresund_like() -> pd.DataFrame:
    """Tracks in 0.14° x 0.06° at 56°N: latitude ticks like "56.025"."""
    rows = []
    for k in range(6):
        lon = np.linspace(12.58, 12.72, 50)
        lat = 56.0 + 0.01 * k + 0.002 * np.sin(np.arange(50) / 5.0)
        t = pd.to_datetime(1_717_200_000 + 60 * np.arange(50), unit="s", utc=True)
        rows.append(
            pd.DataFrame({"sensor": "S1", "batch": str(k), "time": t, "lon": lon, "lat": lat})
        )
    return pd.concat(rows, ignore_index=True)


def _left_axis_overlap(canvas) -> float:
    """Pixels by which the latitude axis' title reaches into its widest tick label."""
    from PySide6 import QtGui

    axis = canvas.getAxis("left")
    image = QtGui.QImage(10, 10, QtGui.QImage.Format.Format_ARGB32)
    painter = QtGui.QPainter(image)
    try:
        _, _, texts = axis.generateDrawSpecs(painter)
    finally:
        painter.end()
    assert texts, "no tick labels drawn"
    title = axis.label.mapRectToParent(axis.label.boundingRect())
    return title.right() - min(rect.left() for rect, _flags, _text in texts)


def test_rendered_latitude_title_clears_its_tick_labels(qapp, tmp_path, monkeypatch):
    """``wakeline render`` of the Øresund encounters: the image was grabbed while the
    latitude axis still had the room of its first, shorter labels, and "latitude (°)" sat
    on "56.025". Checked in the canvas as it is grabbed."""
    from wakeline.app import map_render
    from wakeline.app.map_draw import prepare_layer

    seen = []
    grab = MapCanvas.grab

    def checked_grab(self, *args):
        seen.append(_left_axis_overlap(self))
        return grab(self, *args)

    monkeypatch.setattr(MapCanvas, "grab", checked_grab)
    layer = prepare_layer(oresund_like(), "oresund", build_index=False)
    map_render.render_png([layer], tmp_path / "o.png", size=(1200, 800))
    assert seen and seen[0] <= 0, f"the axis title covers {seen[0]:.1f} px of a tick label"


def _time_column_fits(window) -> None:
    model, view = window.batch_model, window.batch_view
    fm = view.fontMetrics()
    assert model.rowCount() > 0
    for key in ("sensor", "batch", "points", "start", "end"):
        col = [k for k, _ in model.COLUMNS].index(key)
        if view.isColumnHidden(col):  # Sensor, for one sensor (h225 item 16)
            assert key == "sensor" and model.frame["sensor"].nunique() == 1
            continue
        widest = max(
            fm.horizontalAdvance(model.index(r, col).data()) for r in range(model.rowCount())
        )
        # The item delegate's text margins: (focus frame margin + 1) on each side.
        assert widest + 6 <= view.columnWidth(col), (key, widest, view.columnWidth(col))


def test_batch_table_time_columns_fit_their_text(window, tmp_path):
    """Dates ("2024-06-01 00:00:00" was cut to "2024-06-0 00:00:0") and elapsed times
    of a day and more ("T+1 d 03:46:40") fit their columns; so do sensors, batches and
    point counts, in columns no wider than they need (Start in view in a narrow dock)."""
    dated = tmp_path / "dated.csv"
    oresund_like().to_csv(dated, index=False)
    lid = load(window, dated)
    window.select_layer(lid)
    _time_column_fits(window)
    left_of_start = sum(window.batch_view.columnWidth(c) for c in range(3))
    assert left_of_start < 240  # Sensor, Batch, Points: 300 px at Qt's default width
    elapsed = tmp_path / "elapsed.csv"
    pts = oresund_like().assign(
        time=lambda d: pd.to_datetime(100_000 + d.index * 10.5, unit="s", utc=True)
    )
    pts.to_csv(elapsed, index=False)
    lid = load(window, elapsed)
    window.select_layer(lid)
    assert window.batch_model.index(0, 3).data().startswith("T+1 d")
    _time_column_fits(window)


# -- 4. scale bar --------------------------------------------------------------------------


def _luminance(rgb) -> float:
    c = np.asarray(rgb, dtype="float64") / 255.0
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return float(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2])


def contrast(a, b) -> float:
    """WCAG contrast ratio of two RGB colours (4.5 is the floor for normal text)."""
    la, lb = sorted((_luminance(a), _luminance(b)), reverse=True)
    return (la + 0.05) / (lb + 0.05)


def test_scale_bar_label_reads_on_the_map(qtbot):
    """The scale bar's "1 km" was light grey on white (contrast 1.7): its text, as drawn
    over tracks and grid, now contrasts with its own background as body text must."""
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(800, 500)
    pts = oresund_like()
    canvas.set_layer("o", pts, "#1f77b4")
    canvas.set_true_aspect(56.0)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.fit()
    qtbot.wait(50)
    label = canvas.scale_bar.text
    assert label.toPlainText().endswith("km")
    image = canvas.grab().toImage()
    rect = canvas.mapFromScene(label.sceneBoundingRect()).boundingRect()
    rgb = np.array(
        [
            [image.pixelColor(x, y).getRgb()[:3] for x in range(rect.left(), rect.right())]
            for y in range(rect.top(), rect.bottom())
        ]
    ).reshape(-1, 3)
    lum = np.array([_luminance(c) for c in rgb])
    text, ground = rgb[np.argmin(lum)], rgb[np.argmax(lum)]
    assert contrast(text, ground) >= 4.5, (text, ground)
    assert contrast(label.color.getRgb()[:3], (255, 255, 255)) >= 7.0


def test_axis_and_legend_text_read_on_the_white_plots(qtbot):
    """pyqtgraph's text is light grey, made for a black background (contrast about 1.5 on
    our white plots): axes, tick labels, titles and legend entries are drawn in dark ink,
    on the map, the detail plots and the review's time lines."""
    from wakeline.app.detail import DetailPanel

    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.set_layer("o", oresund_like(), "#1f77b4")
    white = (255, 255, 255)
    for side in ("left", "bottom"):
        axis = canvas.getAxis(side)
        assert contrast(axis.textPen().color().getRgb()[:3], white) >= 4.5
        assert contrast(axis.pen().color().getRgb()[:3], white) >= 4.5
    for _, label in canvas.legend.items:
        assert contrast(QtGui.QColor(label.opts["color"]).getRgb()[:3], white) >= 4.5
    detail = DetailPanel()
    qtbot.addWidget(detail)
    axis = detail.factor_plot.getAxis("left")
    assert contrast(axis.textPen().color().getRgb()[:3], white) >= 4.5


def test_default_window_shows_long_names_tabs_and_zoned_times_whole(qtbot, tmp_path):
    """Operator test 7, D16: at the default size (1400x900) with a file of a long name
    after Run ▸ pipeline, the legend draws each layer's name whole (two lines where one
    is too narrow), the Layers list wraps a long name instead of cutting it, the Detail
    dock's tabs fit its width (no "Bearing-"), and the time label holds a time with a
    zone offset ("… UTC+2" was cut to "UTC+")."""
    import html
    import re

    from PySide6 import QtCore
    from test_review_window import _settle

    from wakeline.app.main_window import MainWindow
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    src = tmp_path / "a_radar_console_zh.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=4, area_km=5), src)
    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "en")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1400, 900)
    w.show()
    try:
        w.load_files([src])
        _settle(w)
        w.select_layer(w.layer_id(src.name))
        w.run_step("pipeline")
        _settle(w)
        legend = w.canvas.legend
        names = [lab.toolTip() for _, lab in legend.items]
        assert any("cleaned · compressed" in n for n in names), names
        for _, lab in legend.items:
            lines = [html.unescape(t) for t in re.split(r"<br>", lab.text)]
            drawn = " ".join(t.replace("\xa0", " ").strip() for t in lines)
            # whole, not shortened: every word of the name drawn, in order (a name may be
            # on lines of its own: a layer coloured by track names the layer, then the
            # first track, "FILE · steps\n488 · +1 same colour")
            assert drawn.split() == lab.toolTip().split(), (drawn, lab.toolTip())
            assert len(lines) >= lab.toolTip().count("\n") + 1, (lines, lab.toolTip())
            for line in lines:
                assert legend._metrics.horizontalAdvance(line) <= legend._label_px + 1, line
        view = w.layer_list
        width = view.viewport().width()
        for row in range(view.count()):
            rect = view.visualItemRect(view.item(row))
            assert rect.right() <= width, (view.item(row).text(), rect, width)
        assert view.horizontalScrollBar().maximum() == 0
        assert any(
            view.visualItemRect(view.item(r)).height() > view.visualItemRect(view.item(0)).height()
            for r in range(view.count())
        )  # a long name on two lines
        bar = w.detail.tabBar()
        assert bar.tabRect(bar.count() - 1).right() <= bar.width(), [
            bar.tabText(k) for k in range(bar.count())
        ]
        label = w.time_panel.time_label
        widest = label.fontMetrics().horizontalAdvance("2021-05-04 09:54:53.033 UTC+12:45")
        assert label.width() >= widest
    finally:
        w.close()

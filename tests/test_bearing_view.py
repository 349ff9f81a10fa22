"""The bearing view (pytest-qt, offscreen): bearing lines on the map, detections table."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from conftest import canvas_rgb  # noqa: E402
from wakeline.app.bearing_view import (  # noqa: E402
    MAX_LENGTH_M,
    MAX_LINE_COLOURS,
    MIN_TABLE_ROWS,
    OTHER_LABEL,
    RANGE_MARGIN,
    BearingView,
    bearing_line_points,
    line_length_m,
)
from wakeline.core import geo  # noqa: E402
from wakeline.core.bearing import detect_with_report, report_lines  # noqa: E402
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


def test_bearing_line_points_picks_by_the_one_spread_rule(monkeypatch):
    """bearing_line_points picked its lines with a loop of its own (a linspace per batch)
    beside ``spread_picks`` (the time window's): one rule now, so a change of it moves
    both. Here the rule is swapped for "the first ``max_per`` of each batch in time"."""
    from wakeline.app import bearing_view

    df = simulate_table(seed=3).sample(frac=1.0, random_state=0)  # rows in no order
    expected = bearing_line_points(df, 1_000.0, max_lines=7)

    def first_ones(group, key, max_per):
        order = np.lexsort((key, group))
        g = np.asarray(group)[order]
        rank = np.arange(len(g)) - np.searchsorted(g, g)  # place inside its group
        return order[rank < max_per]

    monkeypatch.setattr(bearing_view, "spread_picks", first_ones)
    lines = bearing_line_points(df, 1_000.0, max_lines=7)
    want = df.sort_values(["batch", "time"]).groupby("batch").head(7)
    assert lines["time"].iloc[::2].tolist() == want["time"].tolist()
    # the rule itself: per batch, the rows np.linspace(0, n - 1, 7).round() in time
    spread = df.sort_values(["batch", "time"]).groupby("batch", group_keys=False)
    spread = spread.apply(lambda g: g.iloc[np.linspace(0, len(g) - 1, 7).round().astype(int)])
    assert expected["time"].iloc[::2].tolist() == spread["time"].tolist()


def test_a_bearing_layers_detections_come_from_one_helper():
    """``layer_detections``: a bearing layer's detections, or (a layer stored without
    them) an empty table with the detector's columns; it was written out three times
    (window, project opening, scene) with a ``batch`` column only."""
    from wakeline.app.bearing_view import bearing_stats, layer_detections, layer_scene
    from wakeline.core.session import Session

    df = simulate_table(seed=3)
    detections, report = detect_with_report(df)
    session = Session()
    lay = session.put_bearings("b.csv", df, detections, {"file": "/b.csv", "report": report})
    assert layer_detections(lay) is detections
    lay.tables = {}
    empty = layer_detections(lay)
    assert empty.empty and list(empty.columns) == list(detections.columns)
    assert layer_scene(lay) is not None and "Detections: 0" in bearing_stats(lay)


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


RED, GREY = (0xD6, 0x27, 0x28), (0x55, 0x55, 0x55)


def rgb(name: str) -> tuple[int, int, int]:
    return tuple(int(name[k : k + 2], 16) for k in (1, 3, 5))


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


#: Where the Autoferry EO/IR scenes are (Trondheim harbour).
HARBOUR = (10.39908, 63.43890)


def harbour_table(
    ranges=((80.0, 300.0), (150.0, 450.0)), duration_s: float = 100.0, truth: bool = False
) -> pd.DataFrame:
    """A camera's bearings in a harbour, like the Autoferry EO/IR files: a ferry that
    drifts ~10 m in ``duration_s`` (4 Hz), each target moving from one range to another
    (metres) across the view. ``truth`` adds the targets' true positions."""
    t = np.arange(0.0, duration_s, 0.25)
    time = pd.Timestamp("2021-05-05 09:06:00", tz="UTC") + pd.to_timedelta(t, unit="s")
    lat0 = HARBOUR[1]
    m_lon = geo.EARTH_RADIUS_M * np.cos(np.radians(lat0)) * np.pi / 180.0
    m_lat = geo.EARTH_RADIUS_M * np.pi / 180.0
    ox, oy = 0.1 * t, 0.02 * t  # metres east and north of HARBOUR
    rows = []
    for k, (r0, r1) in enumerate(ranges):
        az = np.radians(40.0 + 150.0 * k + 0.3 * t)  # sweeping round the ferry
        r = np.linspace(r0, r1, len(t))
        tx, ty = ox + r * np.sin(az), oy + r * np.cos(az)
        part = pd.DataFrame(
            {
                "batch": f"s16_t{k + 1}",
                "time": time,
                "bearing": np.degrees(np.arctan2(tx - ox, ty - oy)) % 360.0,
                "obs_lon": HARBOUR[0] + ox / m_lon,
                "obs_lat": lat0 + oy / m_lat,
            }
        )
        if truth:
            part = part.assign(true_lon=HARBOUR[0] + tx / m_lon, true_lat=lat0 + ty / m_lat)
        rows.append(part)
    return pd.concat(rows, ignore_index=True)


def line_colour(view, batch_id: str) -> tuple[int, int, int]:
    """The colour the view gives the line ``batch#k``."""
    return rgb(view.colours[batch_id.rsplit("#", 1)[0]][0])


@pytest.mark.parametrize("case", ["sim", "eo", "harbour"])
def test_bearing_lines_maneuvers_and_observer_are_painted(qtbot, case):
    """Every bearing line is a long leg between two points of one time: the map's jump
    breaking cut each one to a lone vertex and nothing was painted (a dock with the
    observer alone). Now the pixels along the lines have their batch's colour."""
    if case == "sim":
        df = simulate_table(seed=4)
        table, report = detect_with_report(df)
        assert len(table)
    elif case == "eo":
        df, table, report = eo_like_table(), pd.DataFrame(), []
    else:
        df, table, report = harbour_table(), pd.DataFrame(), []
    view = BearingView()
    qtbot.addWidget(view)
    view.resize(1200, 700)
    view.show()
    qtbot.waitExposed(view)
    view.show_result(df, table, report)
    qtbot.wait(50)
    pixels = rgb_of(view)
    canvas = view.map
    (x0, x1), (y0, y1) = canvas.vb.viewRange()

    lines = bearing_line_points(df, view.length_m)
    # Every line lies in the view (fit to the lines and the observer).
    assert lines["lon"].between(x0, x1).all() and lines["lat"].between(y0, y1).all()
    fractions = (0.4, 0.7, 0.95)
    points = along(lines, fractions)
    colours = np.repeat([line_colour(view, b) for b in lines["batch"].iloc[0::2]], 3, axis=0)
    hit = [has_colour(pixels, to_px(canvas, *p), c) for p, c in zip(points, colours, strict=True)]
    # Red maneuver lines (and the other batches' lines) lie over some of them.
    assert np.mean(hit) > 0.85, f"{np.mean(hit):.0%} of the line samples have their colour"
    if len(table):
        maneuvers = bearing_line_points(df, view.length_m, at_times=table)
        assert len(maneuvers) == 2 * len(table)
        for p in along(maneuvers, (0.3, 0.6, 0.9)):
            assert has_colour(pixels, to_px(canvas, *p), RED), p
    # The observer's track is drawn over the fan of lines that start on it.
    obs = df[["obs_lon", "obs_lat"]].to_numpy()[:: max(len(df) // 20, 1)]
    assert all(has_colour(pixels, to_px(canvas, lon, lat), GREY) for lon, lat in obs)


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


def test_lines_are_as_long_as_a_harbour_scene_and_the_view_shows_it(qtbot):
    """Camera bearings in a harbour (targets 80–450 m off, 100-s sequences, a ferry that
    hardly moves) were drawn 20 km long and fitted into a 60–90 km view: nothing could be
    seen. The length now follows the data (the sequences' duration, the observer's track,
    or the ranges when the table knows them) and the view the scene."""
    df = harbour_table()
    view = BearingView()
    qtbot.addWidget(view)
    view.resize(900, 600)
    view.show()
    qtbot.waitExposed(view)
    view.show_result(df, pd.DataFrame(), [])
    assert 300.0 <= view.length_m <= 1_000.0
    (x0, x1), (y0, y1) = view.map.vb.viewRange()
    lat0 = HARBOUR[1]
    width_m = geo.haversine_m(np.array([x0]), np.array([lat0]), np.array([x1]), np.array([lat0]))
    height_m = geo.haversine_m(np.array([x0]), np.array([y0]), np.array([x0]), np.array([y1]))
    assert float(max(width_m[0], height_m[0])) < 4_000.0  # not 60 km
    assert float(min(width_m[0], height_m[0])) > 2 * 300.0  # the fan, not a zoom on the ferry
    inside = lambda lon, lat: (x0 <= lon <= x1) and (y0 <= lat <= y1)  # noqa: E731
    # The observer's whole track and the near part of every line (where the targets are)
    assert all(inside(*p) for p in df[["obs_lon", "obs_lat"]].to_numpy())
    lines = bearing_line_points(df, view.length_m)
    near = along(lines, (0.0, 0.25, 0.5, 1.0))
    assert all(inside(*p) for p in near)
    # and every target position (80–450 m) lies on the drawn part of its line
    truth = harbour_table(truth=True)
    r = geo.haversine_m(
        truth["obs_lon"].to_numpy(), truth["obs_lat"].to_numpy(),
        truth["true_lon"].to_numpy(), truth["true_lat"].to_numpy(),
    )  # fmt: skip
    assert r.max() < view.length_m
    assert all(inside(*p) for p in truth[["true_lon", "true_lat"]].to_numpy()[::40])

    # The ranges known (a truth position or a range column): just past the far target.
    assert line_length_m(truth) == pytest.approx(RANGE_MARGIN * np.percentile(r, 95))
    assert line_length_m(df.assign(range_m=2_000.0)) == pytest.approx(RANGE_MARGIN * 2_000.0)
    # A 15-min sequence of a target 20 km off, the observer moving 5 km: 20 km as before.
    assert line_length_m(simulate_table(seed=4)) == MAX_LENGTH_M
    # The length can be set: for a call, or for the view until set back to the data's.
    view.show_result(df, pd.DataFrame(), [], length_m=5_000.0)
    assert view.length_m == 5_000.0
    view.set_line_length(2_500.0)
    assert view.length_m == 2_500.0
    end = bearing_line_points(df, 2_500.0).iloc[1::2]
    (x0, x1), (y0, y1) = view.map.vb.viewRange()
    assert end["lon"].between(x0, x1).all() and end["lat"].between(y0, y1).all()
    view.set_line_length(None)
    assert view.length_m == line_length_m(df)


def test_length_box_follows_the_core_parameter_and_sets_the_length(qtbot):
    """No widget set the lines' length (only ``set_line_length`` from code). The dock has a
    spin box now, its unit and range the core's ``BearingLineParams.length_m`` (metres,
    0 … 20 km; 0 reads "from the data"); it shows the length drawn, and a value typed in
    redraws the lines that long, through the length-change path (``length_changed``)."""
    import dataclasses

    from wakeline.core.bearing import BearingLineParams

    field = {f.name: f for f in dataclasses.fields(BearingLineParams)}["length_m"]
    df = harbour_table()
    view = BearingView()
    qtbot.addWidget(view)
    box = view.length_box
    assert (box.minimum(), box.maximum()) == (field.metadata["lo"], field.metadata["hi"])
    assert box.suffix() == " m" and field.metadata["unit"] == "m"
    assert box.specialValueText() == "from the data" and box.value() == field.default == 0.0
    assert BearingLineParams(length_m=25_000.0).problems()  # beyond the box's range
    view.show_result(df, pd.DataFrame(), [])
    auto = line_length_m(df)
    assert view.length_m == auto and box.value() == pytest.approx(auto, abs=0.5)
    with qtbot.waitSignal(view.length_changed, timeout=5000):
        box.setValue(1_234.0)
    assert view.fixed_length_m == 1_234.0 and view.length_m == 1_234.0
    assert view.scene.length_m == 1_234.0
    g = view.map.draw_data("bearing lines").geometry
    d = geo.haversine_m(g.lon[g.starts], g.lat[g.starts], g.lon[g.starts + 1], g.lat[g.starts + 1])
    assert d == pytest.approx(1_234.0, rel=1e-3)
    # The lowest value: from the data again (the box then shows the length drawn).
    with qtbot.waitSignal(view.length_changed, timeout=5000):
        box.setValue(box.minimum())
    assert view.fixed_length_m is None and view.length_m == auto
    assert box.value() == pytest.approx(auto, abs=0.5)


def test_a_new_lengths_scene_is_made_by_the_executor_and_only_the_newest_is_shown(qtbot):
    """The dock made a new length's scene on the GUI thread (13–29 ms for a real EO file,
    44–72 ms at 9,000 bearings). It is made by the executor (the main window's LOD
    worker) now, and swapped in when done. Two changes in a row: the first's scene
    arrives after the second was asked for and is not drawn (the second is made next);
    a scene of a length asked for before other data were shown is dropped too."""
    df = harbour_table()
    view = BearingView()
    qtbot.addWidget(view)
    view.show_result(df, pd.DataFrame(), [])
    jobs = []
    view.executor = lambda job, done: jobs.append((job, done))
    shown = []
    view.length_changed.connect(lambda: shown.append(view.length_m))
    first = view.length_m
    view.set_line_length(800.0)
    view.set_line_length(1_600.0)
    assert len(jobs) == 1 and view.busy and view.length_m == first  # nothing made here
    job, done = jobs.pop()
    done(job())  # 800 m: stale, the 1,600 m scene is asked for
    assert view.length_m == first and shown == [] and len(jobs) == 1
    job, done = jobs.pop()
    scene = job()
    assert scene.length_m == 1_600.0
    done(scene)
    assert view.scene is scene and view.length_m == 1_600.0 and shown == [1_600.0]
    assert not view.busy and view.length_box.value() == 1_600.0
    # Asked for, then other data shown before it is made: dropped.
    view.set_line_length(3_000.0)
    other = harbour_table().iloc[:200]
    view.show_result(other, pd.DataFrame(), [])
    kept = view.scene
    job, done = jobs.pop()
    done(job())
    assert view.scene is kept and view.bearings is other and shown == [1_600.0]


def test_each_batch_has_its_own_pen_and_legend_entry(qtbot):
    """Both targets' lines were one blue layer: now a colour and a legend entry per batch
    (up to MAX_LINE_COLOURS; the rest share one, "other batches")."""
    df = harbour_table()
    view = BearingView()
    qtbot.addWidget(view)
    view.show_result(df, pd.DataFrame(), [])
    items = view.map.layer_items("bearing lines")
    assert len(items) == 2
    pens = {it.opts["pen"].color().name() for it in items}
    assert len(pens) == 2
    assert {c for c, _ in view.colours.values()} == pens
    assert not pens & {"#d62728", "#555555"}  # not the maneuvers' red, not the observer's grey
    # each curve holds exactly one batch's lines: its points are that batch's line ends
    for it in items:
        colour = it.opts["pen"].color().name()
        batch = next(b for b, (c, _) in view.colours.items() if c == colour)
        lines = bearing_line_points(df[df["batch"] == batch], view.length_m)
        x, y = it.curve.getData()
        ok = np.isfinite(x)
        assert np.allclose(np.sort(x[ok]), np.sort(lines["lon"].to_numpy()))
    labels = [label.text for _, label in view.map.legend.items]
    assert labels == ["observer", "s16_t1", "s16_t2"]

    many = pd.concat(
        [eo_like_table().assign(batch=f"b{k:02d}") for k in range(MAX_LINE_COLOURS + 3)],
        ignore_index=True,
    )
    view.show_result(many, pd.DataFrame(), [])
    items = view.map.layer_items("bearing lines")
    assert len(items) == MAX_LINE_COLOURS
    assert len({it.opts["pen"].color().name() for it in items}) == MAX_LINE_COLOURS
    labels = [label.text for _, label in view.map.legend.items]
    assert OTHER_LABEL in labels and "b00" in labels and "b10" not in labels


def test_report_says_what_was_not_estimated(qtbot):
    """A batch where no window was tested printed ``noise ≈ None°``."""
    untested = {
        "batch": "s3_t1",
        "too_short": "",
        "excluded": {"gap": 5, "sparse": 3},
        "detections": 0,
        "tested": 0,
        "windows": 8,
        "noise_deg": None,
        "min_rate_change_deg_min": None,
        "min_turn_deg": None,
    }
    tested = {
        **untested,
        "batch": "s3_t2",
        "excluded": {"gap": 9},
        "detections": 1,
        "tested": 12,
        "windows": 21,
        "noise_deg": 0.8701,
        "min_rate_change_deg_min": 9.51,
        "min_turn_deg": 10.0,
    }
    lines = report_lines([untested, tested])
    assert lines[0] == (
        "batch s3_t1: 0 detection(s); 0 of 8 windows tested (skipped: 5 gap, 3 sparse); "
        "noise and detectable change not estimated: no window tested"
    )
    assert "noise ≈ 0.8701°, smallest bearing-rate change ≈ 9.51°/min" in lines[1]
    assert "None" not in "\n".join(lines)
    assert "not estimated" in report_lines([{**tested, "noise_deg": None}])[0]
    # the view lists it so; a real run of a batch too gappy to test says the same
    df = harbour_table()
    gappy = df[(df["batch"] == "s16_t1") & (np.arange(len(df)) % 40 == 0)]
    table, report = detect_with_report(pd.concat([gappy, df[df["batch"] == "s16_t2"]]))
    view = BearingView()
    qtbot.addWidget(view)
    view.show_result(df, table, report)
    text = view.log.toPlainText()
    assert "None" not in text and "s16_t1" in text


def test_loading_bearings_raises_the_dock_with_map_and_table_in_view(qtbot, tmp_path):
    """At 1800×1000 the Detail panel's Bearing-only tab came to the front, not the
    Bearing-only dock; and that dock's map was 142 px high with one detection row shown."""
    from PySide6 import QtCore

    from tests.conftest import make_window
    from wakeline.app.main import wait_for_jobs

    w = make_window(qtbot, tmp_path, (1800, 1000))
    w.show()
    qtbot.waitExposed(w)
    path = tmp_path / "bearings.csv"
    simulate_table(seed=4).to_csv(path, index=False)
    w.load_bearings(path)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.docks["bearing"].visibleRegion().isEmpty())
    assert w.docks["detail"].visibleRegion().isEmpty()  # tabbed behind
    view = w.bearing_view
    assert view.split.orientation() == QtCore.Qt.Orientation.Vertical
    # the mapped area (fractional since h136): 179.4 px where the bounding rect, which has
    # its half-pixel border, rounded to 180
    assert view.map.plot_size_px()[1] >= 179
    assert len(w.bearing_detections) >= MIN_TABLE_ROWS
    rows = view.table.viewport().height() // view.table.verticalHeader().defaultSectionSize()
    assert rows >= MIN_TABLE_ROWS
    w.runner.cancel()
    w.runner.wait()


def test_main_map_shows_the_bearings_when_no_track_is_loaded(qtbot, tmp_path):
    """With only a bearing file loaded the main map sat at empty 0–1° axes (the bearings
    went to their dock alone). Now it draws the observer and the bearing lines, prepared
    in the worker, framed on them; with a track layer shown it keeps its view."""
    from tests.conftest import make_window
    from wakeline.app.main import wait_for_jobs
    from wakeline.resources import demo_path

    w = make_window(qtbot, tmp_path, (1600, 1000))
    w.show()
    qtbot.waitExposed(w)
    df = harbour_table()
    path = tmp_path / "bearings.csv"
    df.to_csv(path, index=False)
    w.load_bearings(path)
    wait_for_jobs(w)
    canvas = w.canvas
    lid = w.layer_id("bearings.csv")
    assert w.map_names(lid) == [f"{lid}/observer", f"{lid}/lines"]  # no maneuver lines
    # Framed on the harbour scene: not 0–1°, not a 60-km view, the fan in view.
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    lat0 = HARBOUR[1]
    width_m = geo.haversine_m(np.array([x0]), np.array([lat0]), np.array([x1]), np.array([lat0]))
    assert 2 * 300.0 < float(width_m[0]) < 4_000.0
    inside = lambda lon, lat: (x0 <= lon <= x1) and (y0 <= lat <= y1)  # noqa: E731
    assert all(inside(*p) for p in df[["obs_lon", "obs_lat"]].to_numpy())
    lines = bearing_line_points(df, w.bearing_view.length_m)
    assert all(inside(*p) for p in along(lines, (0.0, 0.5, 1.0)))
    # The pixels: each line in its batch's colour, the observer in grey over them (the
    # time slider's positions off: they draw the observer's trail over it).
    w.time_panel.overlay_box.setChecked(False)
    qtbot.wait(50)
    pixels = canvas_rgb(canvas)
    view = w.bearing_view
    points = along(lines, (0.4, 0.7, 0.95))
    colours = np.repeat([line_colour(view, b) for b in lines["batch"].iloc[0::2]], 3, axis=0)
    hit = [has_colour(pixels, to_px(canvas, *p), c) for p, c in zip(points, colours, strict=True)]
    assert np.mean(hit) > 0.85, f"{np.mean(hit):.0%} of the line samples have their colour"
    obs = df[["obs_lon", "obs_lat"]].to_numpy()[:: max(len(df) // 20, 1)]
    assert all(has_colour(pixels, to_px(canvas, lon, lat), GREY) for lon, lat in obs)
    labels = [label.text for _, label in canvas.legend.items]
    assert "bearings.csv · observer" in labels and "bearings.csv · s16_t1" in labels

    # A track layer shown: loading bearings again keeps the map's view.
    w.load_file(demo_path())
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.drawing)
    before = canvas.current_view()
    w.load_bearings(path)
    wait_for_jobs(w)
    assert canvas.current_view() == pytest.approx(before)
    assert len(w.map_names(lid)) == 2  # the file's layer replaced, not a second one
    assert [lay.kind for lay in w.layers.values()].count("bearing") == 1
    w.runner.cancel()
    w.runner.wait()


def test_a_bearing_scene_east_of_the_antimeridian_is_drawn_in_one_band():
    """The observer just east of 180° (−179.999…−179.95°) casting lines west across it:
    the observer decided its band alone ([−180, 180)) and the lines theirs ([0, 360)),
    so the scene's parts were drawn 360° apart and the view spanned the world. Now the
    scene has one band (``scene_band``, the map's rule over all its positions); the
    lines' length no longer shrinks when the observer's track crosses 180° (its extent
    was taken from −180 to 180)."""
    from wakeline.app.bearing_view import bearing_scene, line_length_m, scene_band

    df = simulate_table(seed=4)
    detections, _ = detect_with_report(df)
    assert len(detections)
    east = df.assign(obs_lon=geo.wrap180(df["obs_lon"] + 180.0 - df["obs_lon"].min() + 0.001))
    assert (east["obs_lon"] < -179.9).all()
    scene = bearing_scene(east, detections, 20000.0)
    assert len(scene.layers) == 3
    assert {d.geometry.lon_west for d in scene.layers} == {0.0}
    for d in scene.layers:
        assert 179.5 < d.geometry.lon.min() and d.geometry.lon.max() < 180.5
    x0, x1, _, _ = scene.target
    assert x0 < 180.0 < x1 and x1 - x0 < 1.0  # was ~400
    assert scene_band(df, pd.DataFrame({"lon": [122.0]})) == -180.0  # elsewhere: as before
    across = df.assign(obs_lon=geo.wrap180(df["obs_lon"] + 180.0 - df["obs_lon"].mean()))
    assert (across["obs_lon"] > 179.9).any() and (across["obs_lon"] < -179.9).any()
    assert line_length_m(across) == pytest.approx(line_length_m(df))  # was 8.4 against 20 km

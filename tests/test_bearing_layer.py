"""A bearing file is a layer of the session like a track file: in the Layers list with a
visibility toggle, saved in the project and read back with identical arrays, and cut by
the time slider's window (pytest-qt, offscreen; the core part without Qt)."""

import numpy as np
import pandas as pd
import pytest
from test_bearing_view import harbour_table, has_colour, line_colour, to_px

from conftest import canvas_rgb, make_window
from wakeline.core import geo
from wakeline.core.bearing import detect_with_report, read_bearings_checked
from wakeline.core.bearing_eval import simulate_table
from wakeline.core.project import load_project, save_project
from wakeline.core.session import BEARING_KIND, Session


def test_bearing_layer_is_kept_and_replaced_per_file_and_read_back_exactly(tmp_path):
    """Core: the bearing table, the detections and the report go into the project file
    (Parquet blobs, JSON) and come back equal; the same file read again replaces its
    layer (same id), another file adds one."""
    simulate_table(seed=4).to_csv(tmp_path / "b.csv", index=False)
    df, _ = read_bearings_checked(tmp_path / "b.csv")  # as the window reads it
    detections, report = detect_with_report(df)
    assert len(detections)
    session = Session()
    meta = {"file": "/data/b.csv", "report": report, "length_m": 2500.0}
    first = session.put_bearings("b.csv", df, detections, meta)
    again = session.put_bearings("b.csv", df.iloc[:100], detections.iloc[:1], meta)
    assert again.id == first.id and len(session.layers) == 1
    assert len(session.layers[first.id].points) == 100
    other = session.put_bearings("c.csv", df, detections, {**meta, "file": "/data/c.csv"})
    session.set_visible(other.id, False)
    save_project(session, tmp_path / "p.wakeline")

    proj = load_project(tmp_path / "p.wakeline")
    assert [(lay.id, lay.kind, lay.visible) for lay in proj.layers] == [
        (first.id, BEARING_KIND, True),
        (other.id, BEARING_KIND, False),
    ]
    back = proj.layers[1]
    pd.testing.assert_frame_equal(back.points, df.reset_index(drop=True))
    pd.testing.assert_frame_equal(back.tables["detections"], detections)
    assert back.meta == {**meta, "file": "/data/c.csv"}


def test_lines_drawn_are_the_picks_of_bearing_line_points_and_a_window_picks_again():
    """The lines a scene draws, now chosen from every bearing's line, are those
    bearing_line_points picked (at most 60 per batch over the sequence); a window picks up
    to 60 among its own bearings, in the same colours."""
    from wakeline.app.bearing_view import (
        MAX_LINES,
        bearing_line_points,
        bearing_scene,
        window_lines,
    )
    from wakeline.core.schema import time_seconds

    df = simulate_table(seed=4)
    scene = bearing_scene(df, pd.DataFrame(columns=["batch"]), 5000.0)
    drawn = scene.layers[1].geometry
    old = bearing_line_points(df, 5000.0)
    # The same lines (batch, time) and ends (their aspect latitude is the mean of the
    # lines' observer positions: a few nanodegrees apart).
    prefix = pd.Series(drawn.batch).astype(str).str.rsplit("#", n=1).str[0].to_numpy()
    mine = pd.DataFrame(
        {
            "batch": np.repeat(prefix, 2),
            "time": drawn.time_s,
            "lon": drawn.lon,
            "lat": drawn.lat,
        }
    )
    theirs = old.assign(
        batch=old["batch"].str.rsplit("#", n=1).str[0],
        time=time_seconds(old["time"]),
    )[["batch", "time", "lon", "lat"]]
    mine, theirs = (d.sort_values(list(d.columns)).to_numpy() for d in (mine, theirs))
    assert (mine[:, 0] == theirs[:, 0]).all()
    assert np.allclose(mine[:, 1:].astype(float), theirs[:, 1:].astype(float), atol=1e-6)
    t = scene.all_lines.time_s[scene.all_lines.starts]
    a, b = t.min() + 100.0, t.min() + 160.0
    cut = window_lines(scene.all_lines, scene.line_batch, (a, b))
    times = cut.time_s[cut.starts]
    assert times.min() >= a and times.max() <= b
    n_batches = df["batch"].nunique()
    assert cut.n_tracks == MAX_LINES * n_batches  # 61 bearings per batch in the window
    assert cut.labels == drawn.labels and cut.colors == drawn.colors


def _lines(w, lid: str):
    return w.canvas.draw_data(f"{lid}/lines").geometry


def _window(qtbot, tmp_path, size=(1400, 900)):
    w = make_window(qtbot, tmp_path, size)
    w.show()
    qtbot.waitExposed(w)
    return w


def _open_bearings(w, qtbot, path) -> str:
    from wakeline.app.main import wait_for_jobs

    w.load_bearings(path)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=20_000)
    return w.layer_id(path.name)


@pytest.mark.gui
def test_bearing_layer_is_in_the_layers_list_and_its_toggle_hides_it(qtbot, tmp_path, monkeypatch):
    """(a) The bearings' map layers were in no list: the operator could not hide them.
    Now the file is one item of the Layers list; unchecking it hides the observer, the
    lines and the maneuver lines (items and pixels); checking it shows them again."""
    from PySide6 import QtCore

    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = harbour_table()
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    assert lid is not None and w.layers[lid].kind == BEARING_KIND
    assert w.layer_list.count() == 1
    item = w.layer_list.item(w.layer_row(lid))
    assert item.text() == "bearings.csv  [bearing]"
    assert item.checkState() == QtCore.Qt.CheckState.Checked
    names = w.map_names(lid)
    assert names == [f"{lid}/observer", f"{lid}/lines"]
    w.time_panel.overlay_box.setChecked(False)  # the slider's markers and trail off

    def painted() -> float:
        """Share of sampled points along the lines painted in their batch's colour."""
        qtbot.wait(30)
        pixels = canvas_rgb(w.canvas)
        geom = _lines(w, lid)
        mid_lon = 0.5 * (geom.lon[geom.starts] + geom.lon[geom.ends - 1])
        mid_lat = 0.5 * (geom.lat[geom.starts] + geom.lat[geom.ends - 1])
        colours = [line_colour(w.bearing_view, b) for b in geom.batch]
        hits = [
            has_colour(pixels, to_px(w.canvas, x, y), c)
            for x, y, c in zip(mid_lon, mid_lat, colours, strict=True)
        ]
        return float(np.mean(hits))

    assert painted() > 0.85
    item.setCheckState(QtCore.Qt.CheckState.Unchecked)  # as a click on its box does
    assert not w.layers[lid].visible
    assert not any(it.isVisible() for n in names for it in w.canvas.layer_items(n))
    assert painted() < 0.05
    item.setCheckState(QtCore.Qt.CheckState.Checked)
    assert all(it.isVisible() for n in names for it in w.canvas.layer_items(n))
    assert painted() > 0.85
    # Steps refuse it (it has no tracks) rather than fail in the worker.
    w.select_layer(lid)
    from PySide6 import QtWidgets

    told = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "information", lambda *a: told.append(a[2]))
    assert w.run_step("clean") is None and "no tracks" in told[0]
    assert "Bearings: 800   Sequences: 2   Detections: 0" in w.stats.toPlainText()
    # A second file is a second layer; choosing a layer shows it in the Bearing-only dock.
    other = tmp_path / "other.csv"
    simulate_table(seed=4).to_csv(other, index=False)
    second = _open_bearings(w, qtbot, other)
    assert w.layer_list.count() == 2 and second != lid
    assert w.bearings is w.layers[second].points
    w.select_layer(lid)
    assert w.bearings is w.layers[lid].points and w.bearing_view.model.rowCount() == 0
    # Removed: its map layers go too; the dock shows the layer left, then nothing.
    w.remove_active_layer()
    assert w.map_names(lid) == [] and w.layer_list.count() == 1 and w.map_names(second)
    qtbot.waitUntil(lambda: w.bearings is w.layers[second].points, timeout=2000)
    w.session.remove_layer(second)
    qtbot.waitUntil(lambda: w.bearings is None, timeout=2000)
    assert w.bearings is None and w.bearing_view.model.rowCount() == 0
    assert w.bearing_view.map.layer_names() == [] and w.detail.bearing_batch.count() == 0
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_bearing_layer_is_saved_and_reopened_with_identical_arrays(qtbot, tmp_path):
    """(b) Save, reopen: the bearings were gone. Now the layer is written to the project
    (its table and detections as Parquet, by the project writer's thread, like a track
    layer) when it is loaded into a saved project, its visibility as it changes; the
    reopened project has it with the same table, detections, report, map arrays and
    visibility, and the Bearing-only dock shows it again."""
    from wakeline.app.main import wait_for_jobs
    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    w.load_file(demo_path())
    wait_for_jobs(w)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    path = tmp_path / "bearings.csv"
    simulate_table(seed=4).to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)  # after the save: written as it comes
    layer = w.layers[lid]
    view = w.views[lid]
    assert len(view.extra["detections"]) and f"{lid}/maneuvers" in w.map_names(lid)
    drawn = {n: w.canvas.draw_data(n).geometry for n in w.map_names(lid)}
    w.session.set_visible(lid, False)
    assert w.project.flush(30)
    w.close()

    w2 = make_window(qtbot, tmp_path)
    w2.open_project(proj)
    wait_for_jobs(w2)
    again = w2.layers[lid]
    assert (again.name, again.kind, again.visible) == ("bearings.csv", BEARING_KIND, False)
    pd.testing.assert_frame_equal(again.points, layer.points)
    pd.testing.assert_frame_equal(
        again.tables["detections"], layer.tables["detections"].reset_index(drop=True)
    )
    assert again.meta["report"] == layer.meta["report"]
    assert again.meta["length_m"] == pytest.approx(layer.meta["length_m"])
    assert w2.map_names(lid) == list(drawn)
    for name, geom in drawn.items():
        back = w2.canvas.draw_data(name).geometry
        for key in ("lon", "lat", "time_s", "starts", "ends", "batch"):
            np.testing.assert_array_equal(getattr(back, key), getattr(geom, key), err_msg=key)
        assert not any(it.isVisible() for it in w2.canvas.layer_items(name))
    assert w2.layer_list.item(w2.layer_row(lid)).text() == "bearings.csv  [bearing]"
    assert w2.bearing_view.model.rowCount() == len(layer.tables["detections"])
    w2.runner.cancel()
    w2.runner.wait()
    w2.close()


@pytest.mark.gui
def test_time_window_cuts_the_bearing_lines(qtbot, tmp_path):
    """(c) The time window cut the track layers only: bearing lines from outside it
    stayed on the map. Now the slider spans the bearings (with no track layer it had no
    range, so no window could be set) and a window keeps only lines, maneuver lines and
    observer positions of times inside it; the lines are chosen again among the window's
    own bearings (up to 60 per batch, spread over it: a 20-s window had kept the 12 of
    the whole sequence's 60 that fell in it); switched off, all come back."""
    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = harbour_table()  # 2 batches of 400 bearings, 4 Hz over 100 s
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    panel = w.time_panel
    t_s = df["time"].astype("int64").to_numpy() / 1e9
    batch = df["batch"].to_numpy()
    assert panel.time_range() == pytest.approx((t_s.min(), t_s.max()))
    full = _lines(w, lid)
    assert full.n_tracks == 120  # 60 lines per batch
    for seconds, per_batch in ((20.0, 60), (5.0, 21)):  # 81 and 21 bearings per batch
        a, b = t_s.min() + 20.0, t_s.min() + 20.0 + seconds
        with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
            panel.set_time_window((a, b))
        qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=10_000)
        cut = _lines(w, lid)
        assert cut.n_points == 2 * cut.n_tracks  # whole lines, both ends
        line_t = cut.time_s[cut.starts]
        line_batch = np.array([str(x).rsplit("#", 1)[0] for x in cut.batch])
        for name in ("s16_t1", "s16_t2"):
            mine = line_t[line_batch == name]
            there = t_s[(batch == name) & (t_s >= a) & (t_s <= b)]
            assert len(mine) == per_batch
            assert (np.abs(mine[:, None] - there[None, :]).min(axis=1) < 1e-3).all()
            assert mine.min() == pytest.approx(there.min(), abs=1e-3)  # spread over it
            assert mine.max() == pytest.approx(there.max(), abs=1e-3)
        assert cut.labels == full.labels and cut.colors == full.colors
        drawn = sum(len(c.lon) for c in w.canvas.draw_data(f"{lid}/lines").curves)
        assert drawn <= 3 * cut.n_tracks  # two vertices and a break per line at most
        observer = w.canvas.draw_data(f"{lid}/observer").geometry
        assert observer.n_points and observer.time_s.min() >= a and observer.time_s.max() <= b
    # Hidden and shown again under the window: still cut.
    w.session.set_visible(lid, False)
    w.session.set_visible(lid, True)
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=10_000)
    assert _lines(w, lid).n_tracks == cut.n_tracks
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        panel.set_time_window(None)
    qtbot.waitUntil(lambda: _lines(w, lid).n_tracks == full.n_tracks, timeout=10_000)
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_time_window_cuts_the_bearing_docks_map_in_the_worker(qtbot, tmp_path, monkeypatch):
    """The Bearing-only dock's own map was not cut by the time window: with a window set
    the main map drew the window's lines, the dock still the whole sequence's fan. Now the
    dock's parts are cut as the main map's (the same lines: window_lines' picks among the
    window's bearings), in the worker; a scene shown again under the window (a new line
    length) is cut too; clearing the window restores the full fan."""
    import threading

    from wakeline.app import bearing_view

    threads = []
    real = getattr(bearing_view, "window_scene_layers", None)

    def probe(*args, **kwargs):
        threads.append(threading.current_thread() is threading.main_thread())
        return real(*args, **kwargs)

    monkeypatch.setattr(bearing_view, "window_scene_layers", probe, raising=False)
    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = harbour_table()  # 2 batches of 400 bearings, 4 Hz over 100 s
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    dock = w.bearing_view.map
    observer_name, lines_name = bearing_view.LAYER_NAMES[:2]

    def dock_lines():
        return dock.draw_data(lines_name).geometry

    full = dock_lines()
    assert full.n_tracks == 120  # 60 lines per batch: the whole sequence's fan
    t_s = df["time"].astype("int64").to_numpy() / 1e9
    a, b = t_s.min() + 20.0, t_s.min() + 25.0  # 21 bearings per batch
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window((a, b))
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=10_000)
    cut = dock_lines()
    line_t = cut.time_s[cut.starts]
    assert cut.n_tracks == 42 and line_t.min() >= a and line_t.max() <= b
    main = _lines(w, lid)  # the same lines as the main map's
    np.testing.assert_array_equal(np.sort(main.time_s), np.sort(cut.time_s))
    np.testing.assert_allclose(np.sort(main.lon), np.sort(cut.lon))
    assert cut.labels == full.labels and cut.colors == full.colors
    observer = dock.draw_data(observer_name).geometry
    assert observer.n_points and observer.time_s.min() >= a and observer.time_s.max() <= b
    assert threads == [False]  # cut in the worker
    # The dock shows a scene again (another line length) under the window: cut as well.
    w.bearing_view.set_line_length(2_000.0)
    qtbot.waitUntil(lambda: dock_lines().n_tracks == 42, timeout=10_000)
    qtbot.waitUntil(lambda: w.layers[lid].meta["length_m"] == 2_000.0, timeout=10_000)
    qtbot.waitUntil(lambda: not w.time_controller.busy and not w.drawing, timeout=10_000)
    assert len(threads) >= 2 and True not in threads
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window(None)
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=10_000)
    assert dock_lines().n_tracks == 120
    assert dock.draw_data(observer_name).geometry.n_points == len(df)
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_line_length_changed_in_the_dock_redraws_the_main_maps_layer(qtbot, tmp_path):
    """A line length set in the Bearing-only dock redrew the dock only: the main map kept
    the old lines. Now the main map's parts are made again from the dock's new scene (in
    the LOD worker), still cut by the time window, and the layer keeps the new length (the
    project's ``length_m``)."""
    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = harbour_table()
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    before = _lines(w, lid)
    t_s = df["time"].astype("int64").to_numpy() / 1e9
    a, b = t_s.min() + 20.0, t_s.min() + 25.0
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window((a, b))
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=10_000)
    curves = w.views[lid].extra["curves"]
    length = 0.5 * w.bearing_view.length_m
    w.bearing_view.set_line_length(length)
    qtbot.waitUntil(lambda: w.layers[lid].meta["length_m"] == length, timeout=10_000)
    qtbot.waitUntil(lambda: not w.time_controller.busy and not w.drawing, timeout=10_000)
    assert w.views[lid].extra["scene"] is w.bearing_view.scene
    assert w.views[lid].extra["curves"] is curves  # z is not made again
    cut = _lines(w, lid)
    assert cut.n_tracks == 42  # the window's lines (21 per batch), at the new length
    dock = w.bearing_view.map.draw_data("bearing lines").geometry
    np.testing.assert_allclose(np.sort(cut.lon), np.sort(dock.lon))
    np.testing.assert_allclose(np.sort(cut.lat), np.sort(dock.lat))

    def lengths_m(g):  # each line's length, observer to far end (flat, as they are made)
        dlon, dlat = g.lon[g.starts + 1] - g.lon[g.starts], g.lat[g.starts + 1] - g.lat[g.starts]
        cos = np.cos(np.radians(g.lat[g.starts].mean()))
        return np.radians(np.hypot(dlon * cos, dlat)) * geo.EARTH_RADIUS_M

    assert lengths_m(before) == pytest.approx(2 * length, rel=1e-3)
    assert lengths_m(cut) == pytest.approx(length, rel=1e-3)  # half as long on the main map
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window(None)
    qtbot.waitUntil(lambda: _lines(w, lid).n_tracks == 120, timeout=10_000)
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_length_box_redraws_both_maps_and_the_scene_is_made_in_the_worker(
    qtbot, tmp_path, monkeypatch
):
    """The dock's length box drives the length-change path: the dock's lines, the main
    map's layer and the project's ``length_m`` follow it. The dock's new scene was made on
    the GUI thread (``bearing_scene`` in ``show_result``); it is made in the LOD worker
    now (the thread recorded in the build), and of two quick changes the newer wins."""
    import threading

    from wakeline.app import bearing_view

    calls = []
    real = bearing_view.bearing_scene

    def probe(bearings, detections, length_m=None, build_index=False):
        calls.append((threading.current_thread() is threading.main_thread(), length_m))
        return real(bearings, detections, length_m, build_index)

    monkeypatch.setattr(bearing_view, "bearing_scene", probe)
    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    harbour_table().to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    dock = w.bearing_view
    box = dock.length_box
    assert box.value() == pytest.approx(dock.length_m, abs=0.5)  # the length drawn
    calls.clear()
    box.setValue(700.0)
    box.setValue(1_100.0)  # at once: the 700-m scene, if made, is not the one left
    qtbot.waitUntil(lambda: w.layers[lid].meta["length_m"] == 1_100.0, timeout=10_000)
    qtbot.waitUntil(lambda: not dock.busy and not w.drawing, timeout=10_000)
    qtbot.wait(200)  # a stale result would land meanwhile
    assert calls and all(not on_gui for on_gui, _ in calls)  # made in the worker
    assert calls[-1][1] == 1_100.0 and dock.length_m == 1_100.0
    assert dock.scene.length_m == 1_100.0 and w.views[lid].extra["scene"] is dock.scene
    assert w.layers[lid].meta["length_m"] == 1_100.0 and box.value() == 1_100.0
    main = _lines(w, lid)
    d = geo.haversine_m(
        main.lon[main.starts],
        main.lat[main.starts],
        main.lon[main.starts + 1],
        main.lat[main.starts + 1],
    )
    assert d == pytest.approx(1_100.0, rel=1e-3)  # the main map's lines too
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_a_bearing_projects_window_and_length_come_back_on_both_maps(qtbot, tmp_path):
    """A bearing layer saved with a line length set in the dock's box and a time window:
    reopened, the slider has the same span and window, the length box and the layer the
    same length, and the main map and the dock draw the same window's lines as before."""
    from wakeline.app.main import wait_for_jobs

    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = harbour_table()
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    w.bearing_view.length_box.setValue(700.0)
    qtbot.waitUntil(lambda: w.layers[lid].meta["length_m"] == 700.0, timeout=10_000)
    t_s = df["time"].astype("int64").to_numpy() / 1e9
    window = (t_s.min() + 20.0, t_s.min() + 25.0)
    with qtbot.waitSignal(w.time_controller.window_applied, timeout=10_000):
        w.time_panel.set_time_window(window)
    qtbot.waitUntil(lambda: not w.time_controller.busy and not w.drawing, timeout=10_000)
    span = w.time_panel.time_range()
    main, dock = _lines(w, lid), w.bearing_view.map.draw_data("bearing lines").geometry
    assert main.n_tracks == dock.n_tracks == 42
    assert w.project.flush(30)
    w.runner.cancel()
    w.runner.wait()
    w.close()

    w2 = make_window(qtbot, tmp_path)
    w2.show()
    w2.open_project(proj)
    wait_for_jobs(w2)
    qtbot.waitUntil(lambda: not w2.time_controller.busy and not w2.drawing, timeout=20_000)
    assert w2.time_panel.time_range() == span and w2.time_panel.time_window() == window
    assert w2.layers[lid].meta["length_m"] == 700.0
    assert w2.bearing_view.length_box.value() == 700.0
    back = _lines(w2, lid)
    back_dock = w2.bearing_view.map.draw_data("bearing lines").geometry
    for key in ("lon", "lat", "time_s"):
        np.testing.assert_array_equal(getattr(back, key), getattr(main, key), err_msg=key)
        np.testing.assert_array_equal(getattr(back_dock, key), getattr(dock, key), err_msg=key)
    w2.runner.cancel()
    w2.runner.wait()
    w2.close()


@pytest.mark.gui
def test_detail_curves_are_made_in_the_worker_not_on_the_gui_thread(qtbot, tmp_path, monkeypatch):
    """The Detail panel's z over a sequence (seed 002's statistic, ~90 ms at 9,000
    bearings) was computed on the GUI thread when a bearing file was shown; it is made in
    the worker that reads the file, for every sequence, and the panel draws those
    curves (the same as computing them there). It was computed twice per sequence there
    (the detector's, then the panel's: 0.7 s CPU more on this table); now the curves are
    the detector's own statistic, computed once per sequence."""
    import threading

    from wakeline.app import detail
    from wakeline.core import bearing

    calls = []
    real = bearing.statistic

    def probe(*args, **kwargs):
        calls.append(threading.current_thread() is threading.main_thread())
        return real(*args, **kwargs)

    monkeypatch.setattr(bearing, "statistic", probe)
    w = _window(qtbot, tmp_path)
    path = tmp_path / "bearings.csv"
    df = simulate_table(seed=4)
    df.to_csv(path, index=False)
    _open_bearings(w, qtbot, path)
    batches = sorted(df["batch"].astype(str).unique())
    assert len(batches) > 1 and calls.count(False) == len(batches) and True not in calls
    panel = w.detail
    for batch in batches:  # the operator picks each sequence: still nothing on the GUI thread
        panel.bearing_batch.setCurrentText(batch)
        minutes, bearing, bt, z, _ = panel._curves[batch]
        np.testing.assert_array_equal(panel.z_curve.getData()[1], z)
    assert True not in calls
    fresh = detail.sequence_curves(w.bearings, panel._bparams, batches[-1])[batches[-1]]
    np.testing.assert_array_equal(panel.z_curve.getData()[1], fresh[3])
    np.testing.assert_array_equal(panel.b_curve.getData()[1], fresh[1])
    # Other parameters in the panel than the detector's: the curves are made for them.
    other = panel._bparams.replace(window_x_s=panel._bparams.window_x_s / 2)
    made = (panel._bparams, panel._curves)
    panel.show_bearings(w.bearings, panel._detections, other, made)
    assert panel._curves == {}
    panel.bearing_batch.setCurrentText(batches[-1])
    fresh = detail.sequence_curves(w.bearings, other, batches[-1])[batches[-1]]
    assert len(fresh[3]) and not np.array_equal(fresh[3], made[1][batches[-1]][3])
    np.testing.assert_array_equal(panel.z_curve.getData()[1], fresh[3])


@pytest.mark.gui
def test_reopened_changed_bearing_file_keeps_its_new_hash(qtbot, tmp_path):
    """A bearing file edited and opened again replaced its layer (with the new hash in its
    meta) but the session's Source kept the first read's hash, and the project writer
    wrote sources on "added" only: the saved project then said the file had changed since
    it was loaded. Now the Source's hash is replaced and written on "changed" too."""
    from wakeline.app.main import wait_for_jobs
    from wakeline.core.project import file_hash

    w = _window(qtbot, tmp_path)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    path = tmp_path / "b.csv"
    simulate_table(seed=4).to_csv(path, index=False)
    w.load_bearings(path)
    wait_for_jobs(w)
    simulate_table(seed=5).to_csv(path, index=False)  # the file is edited, opened again
    w.load_bearings(path)
    wait_for_jobs(w)
    (layer,) = w.session.layers.values()
    sha = file_hash(path)
    assert layer.meta["sha256"] == sha
    assert [(s.path, s.sha256) for s in w.session.sources] == [(str(path.resolve()), sha)]
    assert w.project.flush(30)
    assert load_project(proj).source_problems() == []
    w.runner.cancel()
    w.runner.wait()
    w.close()


def _legend(w) -> list[str]:
    """The main map's legend entries, top to bottom."""
    return [label.text for _sample, label in w.canvas.legend.items]


@pytest.mark.gui
def test_a_hidden_layers_entries_leave_the_legend(qtbot, tmp_path):
    """Review: a layer unticked in the Layers list left its entries in the map's legend
    (pyqtgraph draws a hidden curve's entry as an eye). Now a hidden point layer's sensor
    lines and a hidden bearing layer's observer and line entries leave the legend, come
    back in their place when ticked again, and a layer hidden in a reopened project has
    none; a click on an entry's sample no longer hides the curve behind the Layers list."""
    from PySide6 import QtCore

    from wakeline.app.main import wait_for_jobs
    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    w.load_file(demo_path())
    wait_for_jobs(w)
    demo = w.layer_id(demo_path().name)
    path = tmp_path / "bearings.csv"
    harbour_table().to_csv(path, index=False)
    bear = _open_bearings(w, qtbot, path)
    full = _legend(w)
    points = [t for t in full if not t.startswith("bearings.csv")]
    bearing = [t for t in full if t.startswith("bearings.csv")]
    assert points and len(bearing) >= 2, full  # sensors; observer and lines
    state = QtCore.Qt.CheckState
    w.layer_list.item(w.layer_row(demo)).setCheckState(state.Unchecked)
    assert _legend(w) == bearing
    w.layer_list.item(w.layer_row(bear)).setCheckState(state.Unchecked)
    assert _legend(w) == []
    w.layer_list.item(w.layer_row(demo)).setCheckState(state.Checked)
    assert _legend(w) == points
    w.layer_list.item(w.layer_row(bear)).setCheckState(state.Checked)
    assert _legend(w) == full  # back in their place
    # A click on a sample leaves the curve as the Layers list says.
    sample, _label = w.canvas.legend.items[0]
    event = QtCore.QEvent(QtCore.QEvent.Type.None_)
    event.button = lambda: QtCore.Qt.MouseButton.LeftButton
    event.accept = event.ignore = lambda: None
    sample.mouseClickEvent(event)
    assert sample.item.isVisible()
    # A layer hidden in a project is opened without entries; ticked, they come.
    proj = tmp_path / "work.wakeline"
    w.session.set_visible(bear, False)
    w.save_project(proj)
    assert w.project.flush(30)
    w.close()
    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    wait_for_jobs(w2)
    qtbot.waitUntil(lambda: not w2.drawing, timeout=20_000)
    assert _legend(w2) == points
    w2.session.set_visible(bear, True)
    assert _legend(w2) == full
    w2.runner.cancel()
    w2.runner.wait()
    w2.close()


@pytest.mark.gui
def test_bearing_lines_lie_under_the_tracks_in_colours_of_their_own(qtbot, tmp_path):
    """Operator test h150: on the main map the bearing fan (60 lines a batch) was drawn
    over the truth tracks and the plots, which could not be seen; a batch's lines had a
    track layer's brown, and two batches navy and purple (ΔE 25) or two oranges (ΔE 18).
    The lines lie under every track layer (and the selection's halo); the batches'
    colours are far apart and apart from the first sources'."""
    import itertools

    from wakeline.app.bearing_view import LINE_COLOURS, MAX_LINE_COLOURS
    from wakeline.app.map_colors import SOURCE_COLORS, delta_e

    own = LINE_COLOURS[:MAX_LINE_COLOURS]
    assert min(delta_e(a, b) for a, b in itertools.combinations(own, 2)) >= 39
    assert min(delta_e(a, s) for a in own for s in SOURCE_COLORS[:3]) >= 30
    w = _window(qtbot, tmp_path)
    df = harbour_table()
    tracks = tmp_path / "tracks.csv"
    pd.DataFrame(
        {
            "mmsi": 1,
            "time": df["time"].iloc[:50],
            "lon": df["obs_lon"].iloc[:50] + 0.01,
            "lat": df["obs_lat"].iloc[:50],
        }
    ).to_csv(tracks, index=False)
    from conftest import load

    src = load(w, tracks)
    path = tmp_path / "bearings.csv"
    df.to_csv(path, index=False)
    lid = _open_bearings(w, qtbot, path)
    qtbot.waitUntil(lambda: bool(w.canvas._items.get(f"{lid}/lines")), timeout=10_000)
    lines = w.canvas._items[f"{lid}/lines"]
    track = w.canvas._items[src]
    assert max(it.zValue() for it in lines) < min(it.zValue() for it in track)
    assert max(it.zValue() for it in lines) < w.canvas.selection.zValue()
    w.close()

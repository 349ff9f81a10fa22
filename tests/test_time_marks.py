"""The time slider's markers and trail drawn from arrays and worker-made images
(app/map_marks.py, TimeOverlay), and the map worker at close (h122 M1, L7)."""

import threading
import time

import numpy as np
import pytest

from conftest import canvas_rgb
from wakeline.app.map_draw import LayerGeometry


def _geometry(k: int = 300, per: int = 60) -> LayerGeometry:
    rng = np.random.default_rng(1)
    t = (rng.integers(0, 600, k)[:, None] + 10.0 * np.arange(per)).ravel() + 1.7e9
    lon = (122 + rng.uniform(0, 1.0, k)[:, None] + 1e-4 * np.arange(per)).ravel()
    lat = (30 + rng.uniform(0, 0.6, k)[:, None] + 0.0 * np.arange(per)).ravel()
    starts = np.arange(k) * per
    return LayerGeometry(
        lon, lat, starts, starts + per, np.repeat(np.arange(k), per), np.full(k, "R1", object),
        np.arange(k).astype(str).astype(object), t, np.zeros(k * per), np.zeros(k, "int64"),
        ("R1",), ("#1f77b4",), False,
    )  # fmt: skip


def _yellow_at(rgb: np.ndarray, canvas, lon: np.ndarray, lat: np.ndarray) -> float:
    """Share of the positions with a marker's yellow within 2 px of their pixel."""
    from PySide6 import QtCore

    vb = canvas.vb
    hits = 0
    for x, y in zip(lon, lat, strict=True):
        pt = canvas.mapFromScene(vb.mapViewToScene(QtCore.QPointF(x, y)))
        px, py = pt.x(), pt.y()
        patch = rgb[max(py - 2, 0) : py + 3, max(px - 2, 0) : px + 3].astype(int)
        yellow = (patch[..., 0] > 200) & (patch[..., 1] > 160) & (patch[..., 2] < 90)
        hits += bool(yellow.any())
    return hits / max(len(lon), 1)


@pytest.mark.gui
def test_markers_are_copied_from_the_workers_image_and_stamped_when_panned(qtbot, monkeypatch):
    from wakeline.app import map_marks
    from wakeline.app.lod_worker import LodWorker
    from wakeline.app.map_canvas import MapCanvas
    from wakeline.app.map_time import TimeOverlay, index_job

    scene = index_job([_geometry()])
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(900, 650)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.vb.setRange(xRange=(121.9, 123.2), yRange=(29.9, 30.7), padding=0)
    overlay = TimeOverlay(canvas, LodWorker(canvas))
    overlay.set_scene(scene)
    qtbot.waitUntil(lambda: not overlay.busy, timeout=5000)
    stamped = []
    real = map_marks.stamp

    def counted(p, x, y, symbol):
        stamped.append(len(x))
        real(p, x, y, symbol)

    monkeypatch.setattr(map_marks, "stamp", counted)
    t = 1.7e9 + 500.0
    with qtbot.waitSignal(overlay.drawn, timeout=10_000):
        overlay.show_at(t, 300.0)
    qtbot.waitUntil(lambda: not overlay.busy, timeout=5000)
    x, y = overlay.markers.getData()
    _, lon, lat = scene.index.positions_at(t)
    assert len(x) == len(lon) > 100
    assert np.allclose(np.sort(x), np.sort(lon))
    assert overlay.markers.sprite is not None and overlay.trail.sprite is not None
    assert overlay.trail.path is not None  # built in the worker
    stamped.clear()
    rgb = canvas_rgb(canvas)
    assert not stamped, "the markers were stamped on the GUI thread, not copied"
    assert _yellow_at(rgb, canvas, x, y) > 0.95
    dark = (rgb.sum(axis=2) < 150).sum()  # the trails (#202020) and the outlines
    assert dark > 500
    # Panned: stamped from the arrays until the frame for the new view is in.
    canvas.vb.setRange(xRange=(121.95, 123.25), yRange=(29.9, 30.7), padding=0)
    rgb = canvas_rgb(canvas)
    assert stamped and _yellow_at(rgb, canvas, x, y) > 0.95
    with qtbot.waitSignal(overlay.drawn, timeout=10_000):
        pass  # the frame asked again for the new view
    qtbot.waitUntil(lambda: not overlay.busy, timeout=5000)
    stamped.clear()
    rgb = canvas_rgb(canvas)
    assert not stamped and _yellow_at(rgb, canvas, x, y) > 0.95


@pytest.mark.gui
def test_a_slider_dragged_fast_draws_only_the_latest_time(qtbot):
    """Coalescing: frames asked for while one is made are not queued; the last one is
    the one drawn."""
    from wakeline.app.lod_worker import LodWorker
    from wakeline.app.map_canvas import MapCanvas
    from wakeline.app.map_time import TimeOverlay, index_job

    scene = index_job([_geometry()])
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.show()
    jobs = []
    worker = LodWorker(canvas)

    def executor(job, done):
        jobs.append(job)
        worker(job, done)

    overlay = TimeOverlay(canvas, executor)
    overlay.set_scene(scene)
    drawn = []
    overlay.drawn.connect(drawn.append)
    times = 1.7e9 + np.linspace(100.0, 900.0, 30)
    for t in times:
        overlay.show_at(float(t), 120.0)
    qtbot.waitUntil(lambda: not overlay.busy, timeout=10_000)
    assert len(jobs) <= 3  # the first, then the latest asked meanwhile
    assert drawn[-1] == pytest.approx(times[-1])


@pytest.mark.gui
def test_a_map_job_ending_after_its_window_is_gone_raises_nothing(qtbot):
    """h122 L7: a frame finished after the window (the worker's owner) was deleted
    emitted on a deleted object ("Signal source has been deleted") in the pool thread."""
    import shiboken6
    from PySide6 import QtCore

    from wakeline.app.lod_worker import LodWorker

    owner = QtCore.QObject()
    worker = LodWorker(owner)
    go, started = threading.Event(), threading.Event()
    got = []

    def job():
        started.set()
        go.wait(5)
        return 1

    worker(job, got.append)
    assert started.wait(5)
    shiboken6.delete(owner)  # the window closed and deleted while the job runs
    go.set()
    assert QtCore.QThreadPool.globalInstance().waitForDone(5000)
    qtbot.wait(50)
    assert got == []


@pytest.mark.gui
def test_closing_the_window_while_playing_stops_the_frames(qtbot, tmp_path):
    """h122 L7 in the window: closed during playback, no frame is asked for after the
    map's jobs are through, and deleting the window then raises nothing."""
    import shiboken6
    from PySide6 import QtCore
    from test_time import _scene_csv

    from conftest import load
    from wakeline.app.main_window import MainWindow

    _scene_csv(tmp_path / "four.csv")
    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "en")
    w = MainWindow(settings)  # not the fixture's: deleted here
    w.resize(1000, 700)
    w.show()
    load(w, tmp_path / "four.csv")
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=20_000)
    panel, overlay = w.time_panel, w.time_controller.overlay
    drawn = []
    overlay.drawn.connect(drawn.append)
    panel.speed.setValue(10.0)
    panel.play()
    qtbot.waitUntil(lambda: len(drawn) >= 3, timeout=5000)
    w.close()
    assert not panel.is_playing
    n = len(drawn)
    end = time.perf_counter() + 0.3
    while time.perf_counter() < end:
        QtCore.QCoreApplication.processEvents()
    assert not overlay._running and len(drawn) <= n + 1
    shiboken6.delete(w)
    assert QtCore.QThreadPool.globalInstance().waitForDone(5000)
    qtbot.wait(50)

"""The time slider's markers and trail drawn from arrays and worker-made images
(app/map_marks.py, TimeOverlay), and the map worker at close (h122 M1, L7)."""

import threading
import time

import numpy as np
import pytest

from conftest import canvas_rgb
from wakeline.app.map_draw import LayerGeometry


def _geometry(k: int = 300, per: int = 60, color: str = "#1f77b4", seed: int = 1) -> LayerGeometry:
    rng = np.random.default_rng(seed)
    t = (rng.integers(0, 600, k)[:, None] + 10.0 * np.arange(per)).ravel() + 1.7e9
    lon = (122 + rng.uniform(0, 1.0, k)[:, None] + 1e-4 * np.arange(per)).ravel()
    lat = (30 + rng.uniform(0, 0.6, k)[:, None] + 0.0 * np.arange(per)).ravel()
    starts = np.arange(k) * per
    return LayerGeometry(
        lon, lat, starts, starts + per, np.repeat(np.arange(k), per), np.full(k, "R1", object),
        np.arange(k).astype(str).astype(object), t, np.zeros(k * per), np.zeros(k, "int64"),
        ("R1",), (color,), False,
    )  # fmt: skip


BLUE, RED = "#1f77b4", "#d62728"


def _two_layers():
    """Two layers' scene: 300 tracks in blue, 300 in red (the layers' colours)."""
    from wakeline.app.map_time import index_job

    return index_job([_geometry(color=BLUE), _geometry(color=RED, seed=2)])


def _color_at(
    rgb: np.ndarray, canvas, lon: np.ndarray, lat: np.ndarray, color: str, ratio: float = 1.0
) -> float:
    """Share of the positions with a marker pixel of ``color`` (within 24 of each
    channel) within 2 px of their pixel (``rgb`` at ``ratio`` pixels a px)."""
    from PySide6 import QtCore

    want = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)])
    vb = canvas.vb
    hits = 0
    r = int(round(2 * ratio))
    for x, y in zip(lon, lat, strict=True):
        pt = canvas.mapFromScene(vb.mapViewToScene(QtCore.QPointF(x, y)))
        px, py = int(round(pt.x() * ratio)), int(round(pt.y() * ratio))
        patch = rgb[max(py - r, 0) : py + r + 1, max(px - r, 0) : px + r + 1].astype(int)
        hits += bool((np.abs(patch - want).max(axis=2) <= 24).any())
    return hits / max(len(lon), 1)


def _yellow_at(rgb: np.ndarray, canvas, lon: np.ndarray, lat: np.ndarray) -> float:
    """Share of the positions with their layer's marker colour (blue: :func:`_geometry`)
    within 2 px of their pixel."""
    return _color_at(rgb, canvas, lon, lat, BLUE)


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
def test_each_layers_markers_are_in_its_colour(qtbot, monkeypatch):
    """The markers at t are each filled with their layer's colour (they were all one
    yellow), in the worker's image and when the paint stamps them (panned)."""
    from PySide6 import QtGui, QtWidgets

    from wakeline.app import map_marks
    from wakeline.app.lod_worker import LodWorker
    from wakeline.app.map_canvas import MapCanvas
    from wakeline.app.map_time import TimeOverlay

    scene = _two_layers()
    holder = QtWidgets.QWidget()  # the map inside a window, away from its corner
    qtbot.addWidget(holder)
    layout = QtWidgets.QVBoxLayout(holder)
    layout.setContentsMargins(37, 23, 5, 5)
    canvas = MapCanvas()
    layout.addWidget(canvas)
    holder.resize(942, 678)
    holder.show()
    qtbot.waitExposed(canvas)
    canvas.vb.setRange(xRange=(121.9, 123.2), yRange=(29.9, 30.7), padding=0)
    overlay = TimeOverlay(canvas, LodWorker(canvas))
    overlay.set_scene(scene)
    t = 1.7e9 + 500.0
    with qtbot.waitSignal(overlay.drawn, timeout=10_000):
        overlay.show_at(t, 300.0)
    qtbot.waitUntil(lambda: not overlay.busy, timeout=5000)
    stamped = []
    real = map_marks.stamp
    monkeypatch.setattr(
        map_marks, "stamp", lambda p, x, y, s: (stamped.append(1), real(p, x, y, s))
    )
    tracks, lon, lat = scene.index.positions_at(t)
    color = np.asarray(scene.colors)[scene.color_of_track[tracks]]
    blue, red = color == BLUE, color == RED
    assert blue.sum() > 100 and red.sum() > 100
    codes = overlay.markers.codes()
    assert codes is not None and set(np.asarray(overlay.markers.colors)[codes]) == {BLUE, RED}
    for panned in (False, True):
        if panned:  # stamped on the GUI thread until the frame for the view is in
            canvas.vb.setRange(xRange=(121.95, 123.25), yRange=(29.9, 30.7), padding=0)
        rgb = canvas_rgb(canvas)
        assert bool(stamped) == panned
        # a marker may lie under another layer's: most, not all
        assert _color_at(rgb, canvas, lon[blue], lat[blue], BLUE) > 0.9
        assert _color_at(rgb, canvas, lon[red], lat[red], RED) > 0.9
        yellow = (rgb[..., 0] > 200) & (rgb[..., 1] > 160) & (rgb[..., 2] < 90)
        assert yellow.sum() == 0  # no marker in the old single colour
    # A grab of the whole window: the worker's image where the map is (the paint once
    # placed it by the device transform, which holds the map's offset in the window).
    canvas.vb.setRange(xRange=(121.9, 123.2), yRange=(29.9, 30.7), padding=0)
    qtbot.waitUntil(lambda: not overlay.busy, timeout=5000)
    stamped.clear()
    image = holder.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    raw = np.frombuffer(image.constBits(), np.uint8).reshape(image.height(), image.bytesPerLine())
    whole = raw[:, : image.width() * 3].reshape(image.height(), image.width(), 3)
    g = canvas.geometry()
    rgb = whole[g.top() : g.bottom() + 1, g.left() : g.right() + 1]
    assert not stamped and overlay.markers.sprite is not None
    assert _color_at(rgb, canvas, lon[blue], lat[blue], BLUE) > 0.9
    assert _color_at(rgb, canvas, lon[red], lat[red], RED) > 0.9


_HIGH_DPI = """
import sys
import numpy as np
sys.path.insert(0, {tests!r})
from PySide6 import QtWidgets
app = QtWidgets.QApplication([])
from wakeline.app import map_marks
from wakeline.app.lod_worker import LodWorker
from wakeline.app.map_canvas import MapCanvas
from wakeline.app.map_time import TimeOverlay
from conftest import canvas_rgb
from test_time_marks import BLUE, RED, _color_at, _two_layers

scene = _two_layers()
canvas = MapCanvas()
canvas.resize(900, 650)
canvas.show()
canvas.vb.setRange(xRange=(121.9, 123.2), yRange=(29.9, 30.7), padding=0)
overlay = TimeOverlay(canvas, LodWorker(canvas))
overlay.set_scene(scene)
drawn = []
overlay.drawn.connect(drawn.append)
def wait(ok):
    import time
    end = time.monotonic() + 20
    while not ok() and time.monotonic() < end:
        app.processEvents()
wait(lambda: not overlay.busy)
t = 1.7e9 + 500.0
overlay.show_at(t, 300.0)
wait(lambda: drawn and not overlay.busy)
stamped = []
real = map_marks.stamp
map_marks.stamp = lambda p, x, y, s: (stamped.append(1), real(p, x, y, s))
ratio = canvas.devicePixelRatioF()
sprite = overlay.markers.sprite
rgb = canvas_rgb(canvas)
tracks, lon, lat = scene.index.positions_at(t)
color = np.asarray(scene.colors)[scene.color_of_track[tracks]]
print(ratio, sprite.image.devicePixelRatio(), overlay.trail.sprite.image.devicePixelRatio(),
      rgb.shape[1], len(stamped),
      round(_color_at(rgb, canvas, lon[color == BLUE], lat[color == BLUE], BLUE, ratio), 3),
      round(_color_at(rgb, canvas, lon[color == RED], lat[color == RED], RED, ratio), 3))
"""


@pytest.mark.gui
def test_on_a_high_dpi_screen_the_worker_draws_the_markers(tmp_path):
    """Device pixel ratio 2 (QT_SCALE_FACTOR=2): the worker draws the markers and the
    trail at that ratio, and the paint copies them (it stamped them on the GUI thread)."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    script = tmp_path / "high_dpi.py"
    script.write_text(_HIGH_DPI.format(tests=str(Path(__file__).parent)))
    env = dict(os.environ, QT_SCALE_FACTOR="2", QT_QPA_PLATFORM="offscreen")
    out = subprocess.run(
        [sys.executable, str(script)], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    ratio, marks, trail, width, stamped, blue, red = out.stdout.split()[-7:]
    assert float(ratio) == float(marks) == float(trail) == 2.0
    assert int(width) == 1800  # the grab has the device's pixels
    assert int(stamped) == 0, "the markers were stamped on the GUI thread"
    assert float(blue) > 0.9 and float(red) > 0.9


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
    # none after the close (a frame queued behind the running one was drawn after it,
    # two frames in all, on a loaded machine in the full run)
    assert not overlay._running and len(drawn) == n
    shiboken6.delete(w)
    assert QtCore.QThreadPool.globalInstance().waitForDone(5000)
    qtbot.wait(50)

"""A review decision's points swapped in after the map's view moved (View ▸ Before/after
map, then a pan): the associated layer is drawn for the view the map shows, not for the
one the decision's job saw when it started (h140: the orange associated lines missing
from the main map after Before/after map on 959k points)."""

import threading
import time

import numpy as np
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtCore, QtGui, QtWidgets  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

import wakeline.app.review_sync as review_sync  # noqa: E402
from wakeline.app.map_draw import lod_is_stale, relod  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

pytestmark = pytest.mark.gui


def _spin(w, until, timeout_s: float = 30.0) -> None:
    app = QtWidgets.QApplication.instance()
    t0 = time.monotonic()
    while not until():
        assert time.monotonic() - t0 < timeout_s, "timed out"
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)


def _pixels_of(canvas, color: str) -> int:
    """Pixels of the map's plot area in ``color``'s hue (drawn muted, over white)."""
    img = canvas.grab(canvas.mapFromScene(canvas.vb.sceneBoundingRect()).boundingRect())
    img = img.toImage().convertToFormat(QtGui.QImage.Format.Format_RGB32)
    a = np.frombuffer(img.constBits(), np.uint8).reshape(img.height(), img.bytesPerLine() // 4, 4)
    b, g, r = (a[:, : img.width(), k].astype(int) for k in range(3))
    c = QtGui.QColor(color)
    # orange (#ff7f0e) at any opacity over white: red > green > blue, clearly tinted
    assert c.red() > c.green() > c.blue()
    return int(((r - g > 15) & (g - b > 15)).sum())


def test_decision_swapped_in_after_the_view_moved_is_drawn(qtbot, tmp_path, monkeypatch):
    pts = simulate.segments_scene(seed=5, n_ships=60, area_km=120.0)
    path = tmp_path / "seg.csv"
    write_points(pts, path)
    w = _window(qtbot, tmp_path)
    w.load_file(path)
    _settle(w)
    src = w.layer_id(path.name)
    w.run_step("associate")
    _settle(w)
    assoc = w.session.find(src, "associate")
    w.select_layer(assoc.id)
    _settle(w)
    bound = w.review.bound
    assert bound is not None and bound.lid == assoc.id
    canvas = w.canvas
    color = canvas.draw_data(assoc.id).curves[0].color
    assert _pixels_of(canvas, color) > 200  # drawn before anything moves

    # The decision's job (points + their drawing, for the view it sees) is held until
    # the view moved: Before/after map, then to the tracks farthest from the view (beyond
    # the region the job decimates for: the view and one view size around it).
    gate = threading.Event()
    decided = review_sync.decided_points

    def held(*args, **kwargs):
        gate.wait(30)
        return decided(*args, **kwargs)

    monkeypatch.setattr(review_sync, "decided_points", held)
    bound.panel.accept()
    _spin(w, lambda: w.review.sync._job is not None)
    w.review.act_before.trigger()
    _spin(w, lambda: w.review.before.isVisible() and not canvas.lod_busy)
    x0, x1, y0, y1 = canvas.current_view()
    geom = canvas.draw_data(assoc.id).geometry
    # where the tracks are thick (near the middle of the scene), but beyond that region
    out = (np.abs(geom.lon - (x0 + x1) / 2) > 1.6 * (x1 - x0)) | (
        np.abs(geom.lat - (y0 + y1) / 2) > 1.6 * (y1 - y0)
    )
    mid = np.hypot(geom.lon - np.median(geom.lon), geom.lat - np.median(geom.lat))
    k = np.flatnonzero(out)[np.argmin(mid[out])]
    cx, cy = geom.lon[k], geom.lat[k]
    hx, hy = (x1 - x0) / 2, (y1 - y0) / 2
    canvas.vb.setRange(xRange=(cx - hx, cx + hx), yRange=(cy - hy, cy + hy), padding=0)
    _spin(w, lambda: not canvas.lod_busy)
    gate.set()
    _settle(w)
    w.grab().save(str(tmp_path / "after.png"))  # WAKELINE_SHOTS-like: look at it

    data = canvas.draw_data(assoc.id)
    assert w.layers[assoc.id].points is not None and assoc.meta.get("review_decisions") == 1
    view, size = canvas.current_view(), canvas.plot_size_px()
    # every track in the view is drawn: as many pixels as the data decimated afresh
    shown = _pixels_of(canvas, color)
    canvas.set_draw_data(relod(data, view, size))
    expected = _pixels_of(canvas, color)
    assert expected > 50 and shown >= 0.9 * expected, (shown, expected)
    assert not lod_is_stale(data, view, size), (data.view, view)
    w.close()

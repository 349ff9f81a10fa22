"""Map images: draw prepared layers with the map canvas, offscreen, into a PNG.

:func:`render_png` serves ``wakeline render`` and the window's File ▸ Export map image.
With ``bare`` the image is the plot area alone and its edges are exactly the bounds:
pixel column ``i`` covers longitudes ``W + i·(E−W)/w … W + (i+1)·(E−W)/w`` and row ``j``
latitudes ``N − (j+1)·(N−S)/h … N − j·(N−S)/h``.
"""

import math
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.layer_view import framed_range
from wakeline.app.map_canvas import MapCanvas
from wakeline.app.map_draw import DrawData
from wakeline.resources import coastline_path

#: Width (px) of an image when only the bounds are given.
DEFAULT_WIDTH = 1200
DEFAULT_SIZE = (1200, 800)


def frame_bounds(layers: Iterable[DrawData]) -> tuple[float, float, float, float]:
    """``(W, S, E, N)`` framing where the points of ``layers`` are, with a 5 % margin (a
    few far-flung points are left out: :mod:`wakeline.app.map_frame`)."""
    target = framed_range([d.geometry.sketch() for d in layers])
    if target is None:
        return (-180.0, -85.0, 180.0, 85.0)
    x0, x1, y0, y1 = target
    return (x0, y0, x1, y1)


def true_aspect(bounds: tuple[float, float, float, float]) -> float:
    """Width over height (km over km) of ``bounds`` at their middle latitude."""
    w, s, e, n = bounds
    cos = max(math.cos(math.radians((s + n) / 2)), 0.05)
    return (e - w) * cos / (n - s)


def fit_bounds_to(
    bounds: tuple[float, float, float, float], aspect: float
) -> tuple[float, float, float, float]:
    """``bounds`` grown (about their centre) to a true-aspect width/height of ``aspect``."""
    w, s, e, n = bounds
    now = true_aspect(bounds)
    if now < aspect:  # too narrow: widen
        half = (e - w) * aspect / now / 2
        c = (w + e) / 2
        return (c - half, s, c + half, n)
    half = (n - s) * now / aspect / 2
    c = (s + n) / 2
    return (w, c - half, e, c + half)


def _source_layers(source) -> tuple[list[DrawData], MapCanvas | None]:
    if isinstance(source, MapCanvas):
        return source.visible_draw_data(), source
    return list(source), None


def render_png(
    source: "MapCanvas | Iterable[DrawData]",
    path: str | Path,
    size: tuple[int, int] | None = None,
    bounds: tuple[float, float, float, float] | None = None,
    bare: bool = False,
    coastline: bool = True,
) -> dict:
    """Draw ``source`` (a live canvas: its visible layers, selection and view; or prepared
    layers) into the PNG ``path``; returns what was drawn (size, bounds, vertices).

    ``size`` (w, h) px; ``bounds`` (W, S, E, N) degrees, default the canvas' view or
    where the data are, with a margin (:func:`frame_bounds`). Without ``bare`` the image
    is the whole map widget (axes, legend, scale bar), the bounds shown whole at the true
    aspect. With ``bare`` it is the plot area alone with its edges exactly at ``bounds``: the missing one of size/bounds is
    chosen for the true aspect; when both are given they are both honoured (the aspect
    then is the one they make).
    """
    layers, live = _source_layers(source)
    if bounds is None and live is not None:
        x0, x1, y0, y1 = live.current_view()
        bounds = (x0, y0, x1, y1)
    given_bounds = bounds is not None
    bounds = bounds or frame_bounds(layers)
    if size is None:
        ratio = true_aspect(bounds) if given_bounds else DEFAULT_SIZE[0] / DEFAULT_SIZE[1]
        ratio = min(max(ratio, 0.2), 5.0)
        size = (DEFAULT_WIDTH, max(int(round(DEFAULT_WIDTH / ratio)), 16))
        if not given_bounds:
            bounds = fit_bounds_to(bounds, ratio)
    elif not given_bounds and bare:
        bounds = fit_bounds_to(bounds, size[0] / size[1])
    w, h = int(size[0]), int(size[1])
    west, south, east, north = bounds

    canvas = MapCanvas()
    canvas.setAttribute(QtCore.Qt.WidgetAttribute.WA_DontShowOnScreen, True)
    if coastline:
        try:
            coast = np.load(coastline_path())
            canvas.set_coastline(coast["lon"], coast["lat"])
        except OSError:
            pass
    for data in layers:
        canvas.set_draw_data(data, visible=True)
    if live is not None and len(live.selected_points()):
        canvas.show_selection(
            live.selected_points(), _marks_of(live), lon_west=live.selection_band()
        )
    canvas.set_true_aspect((south + north) / 2)
    canvas.set_bare(bare)
    if bare:
        canvas.vb.setAspectLocked(False)
    canvas.resize(w, h)
    canvas.show()
    QtWidgets.QApplication.processEvents()
    if bare:
        # Grow the widget until the plot area itself is w x h.
        for _ in range(3):
            vw, vh = (round(v) for v in canvas.plot_size_px())
            if (vw, vh) == (w, h):
                break
            canvas.resize(canvas.width() + w - vw, canvas.height() + h - vh)
            QtWidgets.QApplication.processEvents()
    canvas.vb.setRange(xRange=(west, east), yRange=(south, north), padding=0)
    QtWidgets.QApplication.processEvents()
    # A paint measured the new tick labels; an axis they widen is laid out on the next
    # turn (else the grab shows the axis title over its labels).
    QtWidgets.QApplication.processEvents()
    canvas.refresh_lod()
    if bare:
        image = QtGui.QImage(w, h, QtGui.QImage.Format.Format_ARGB32)
        image.fill(QtGui.QColor("white"))
        painter = QtGui.QPainter(image)
        canvas.scene().render(
            painter,
            QtCore.QRectF(0, 0, w, h),
            canvas.vb.sceneBoundingRect(),
            QtCore.Qt.AspectRatioMode.IgnoreAspectRatio,
        )
        painter.end()
    else:
        image = canvas.grab().toImage()
    x0, x1, y0, y1 = canvas.current_view()
    info = {
        "size": (image.width(), image.height()),
        "bounds": (x0, y0, x1, y1),
        "layers": len(layers),
        "points": sum(d.geometry.n_points for d in layers),
        "vertices": canvas.n_vertices(),
    }
    canvas.close()
    canvas.deleteLater()
    if not image.save(str(path), "PNG"):
        raise OSError(f"cannot write the image {path}")
    return info


def _marks_of(canvas: MapCanvas) -> pd.DataFrame | None:
    x, y = canvas.marks.getData()
    if x is None or len(x) == 0:
        return None
    return pd.DataFrame({"lon": x, "lat": y})

"""Painter paths and images of the map's curves, made off the GUI thread.

pyqtgraph builds a curve's ``QPainterPath`` from its arrays on the first paint after
``setData`` (20–28 ms of GUI-thread CPU for 120k vertices). A ``QPainterPath`` is a
plain value class (reentrant), so a worker can build it with pyqtgraph's own
``arrayToQPath`` and the canvas hands it to the curve item after ``setData``.

Stroking the path is the larger cost (a 1-px line through 180k vertices: 50–70 ms of
Qt's raster engine) and Qt allows painting on a ``QImage`` in any thread. So a worker
also strokes each long curve into a :class:`Sprite`, an image of the view the curve was
decimated for, and :class:`SpriteCurve` paints by copying it while the map shows that
view at that scale with that pen; any other paint (a pan beyond the image, a zoom not yet
redone, another pen) strokes the path as pyqtgraph does. PySide holds the GIL while
``QPainter.drawPath`` runs, so the worker strokes in pieces of ~``CHUNK_VERTICES``
vertices: the GUI thread waits at most one piece for the GIL.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pyqtgraph as pg
import pyqtgraph.graphicsItems.PlotDataItem as _plot_data_item
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.map_draw import Curve, DrawData

#: Curves with fewer vertices are left to pyqtgraph (cheap; wide pens draw segments).
MIN_VERTICES = 2_000
#: Symbols are drawn when a curve has at most this many vertices after the level of
#: detail; beyond, lines are drawn with a 1-px pen (and may have a sprite).
SYMBOLS_MAX = 3_000
#: Vertices stroked per ``drawPath`` call when a worker makes a sprite (~5 ms each).
CHUNK_VERTICES = 12_000
#: A longer curve's path is built in pieces of about this many vertices (cut at NaN
#: separators) appended to one path: pyqtgraph reads the whole path in from a byte
#: stream in one call with the GIL held (25 ms per million vertices here, 60-300 ms
#: of a stalled window when its pages are fresh; S29).
PATH_PIECE_VERTICES = 100_000
#: Largest difference (pixels, across the image) between the map's scale and the image's
#: for the image to be copied unscaled: a line is off by at most this at the far edge.
#: The worker draws at the map's own scale (the plot area's fractional size, not a
#: rounded one), so only a view changed since differs: an image made for a plot 0.5 px
#: narrower than its rounded width was copied 0.5 px off across it, and with the corner's
#: rounding a line was drawn up to a pixel beside its stroke (h136).
SCALE_TOLERANCE_PX = 0.25
#: Largest sprite (pixels): a bigger plot area is stroked on the GUI thread as before.
MAX_SPRITE_PIXELS = 4096 * 4096
#: A curve of at least this many vertices whose sprite no longer fits the view (a
#: resize, a zoom, a pan, the map refitted to a new layer) paints its old sprite
#: scaled and moved onto the view while the worker makes the new one, instead of
#: stroking it on the GUI thread: 15-60 ms a curve of 650 k vertices, 19 strokes
#: (0.3 s) when the review dock opened beside a million points (S29). Shorter curves
#: stroke as before; the new sprite is exact.
STAND_IN_VERTICES = 100_000


@dataclass(frozen=True)
class Sprite:
    """A curve stroked into ``image`` for ``view`` (x0, x1, y0, y1, degrees) shown on the
    image's pixels, with a cosmetic pen of colour ``rgba`` and ``width`` px."""

    image: QtGui.QImage
    view: tuple[float, float, float, float]
    rgba: int  # the pen's colour, QColor.rgba()
    width: float
    antialias: bool
    n: int  # length of the curve's arrays (NaN separators included)
    #: The plot area (w, h, logical px, fractional) the image shows ``view`` on; its
    #: pixels are device pixels (``image.devicePixelRatio()`` of them per logical one).
    size: tuple[float, float] | None = field(default=None, compare=False)

    def covers(self, view: tuple[float, float, float, float]) -> bool:
        """``view`` (x0, x1, y0, y1, degrees) lies within the image, to a pixel."""
        x0, x1, y0, y1 = self.view
        tx = (x1 - x0) / self.image.width()  # one pixel, in degrees
        ty = (y1 - y0) / self.image.height()
        return (
            view[0] >= x0 - tx and view[1] <= x1 + tx and view[2] >= y0 - ty and view[3] <= y1 + ty
        )

    def shows(self, item: pg.PlotCurveItem) -> bool:
        """The image is of ``item``'s data with ``item``'s pen (at some view)."""
        opts = item.opts
        pen = opts.get("pen")
        return not (
            pen is None
            or item.xData is None
            or len(item.xData) != self.n
            or opts.get("shadowPen") is not None
            or opts.get("fillLevel") is not None
            or bool(opts.get("antialias")) != self.antialias
            or pen.widthF() != self.width
            or pen.style() != QtCore.Qt.PenStyle.SolidLine
            or pen.color().rgba() != self.rgba
        )

    def draw_scaled(self, p: QtGui.QPainter, item: pg.PlotCurveItem) -> bool:
        """Copy the image onto ``p`` scaled and moved to where its view lies in
        ``item``'s view now (a stand-in while a new one is made: lines a little thicker
        or thinner, nothing beyond the image's view); False (nothing painted) when it
        is not of ``item``'s data and pen, or ``p`` is rotated or of another pixel
        ratio."""
        if not self.shows(item):
            return False
        device = p.device()
        if device is None or abs(device.devicePixelRatioF() - self.image.devicePixelRatio()) > 1e-6:
            return False
        t = p.transform()
        if abs(t.m12()) > 1e-12 or abs(t.m21()) > 1e-12:
            return False
        x0, x1, y0, y1 = self.view
        target = QtCore.QRectF(t.map(QtCore.QPointF(x0, y1)), t.map(QtCore.QPointF(x1, y0)))
        if not (target.width() > 0 and target.height() > 0):
            return False
        p.save()
        p.resetTransform()
        p.drawImage(target, self.image, QtCore.QRectF(self.image.rect()))
        p.restore()
        return True

    def draw(self, p: QtGui.QPainter, item: pg.PlotCurveItem) -> bool:
        """Copy the image onto ``p`` if it shows ``item`` exactly as a stroke would;
        False (nothing painted) otherwise."""
        if not self.shows(item):
            return False
        corner = image_corner(p, item, self.view, self.image, self.size)
        if corner is None:
            return False
        p.save()
        p.resetTransform()
        p.drawImage(corner, self.image)
        p.restore()
        return True


def image_corner(
    p: QtGui.QPainter,
    item: QtWidgets.QGraphicsItem,
    view: tuple[float, float, float, float],
    image: QtGui.QImage,
    size: tuple[float, float] | None = None,
) -> QtCore.QPointF | None:
    """Where (logical pixels of ``p`` with its transform reset) to copy ``image``, made
    by a worker showing ``view`` (x0, x1, y0, y1, degrees) on a plot area of ``size`` (w,
    h, logical px; None: the image's size) at the image's device pixel ratio, so that it
    shows ``item``'s data exactly as a paint through ``p`` would: its pixels on the
    device's, its corner on a device pixel. None when it cannot (another scale or device
    pixel ratio, a rotation, panned beyond the image)."""
    device = p.device()
    dpr = image.devicePixelRatio()
    if device is None or abs(device.devicePixelRatioF() - dpr) > 1e-6:
        return None  # made for another pixel ratio: the paint strokes
    # Logical pixels (not p.deviceTransform(): a grab of the whole window paints the map
    # redirected, the redirection's offset in the device transform but not in the one a
    # reset leaves, and the image landed that offset away).
    t = p.transform()
    x0, x1, y0, y1 = view
    w, h = image.width(), image.height()
    sw, sh = (w / dpr, h / dpr) if size is None else size
    tolerance = 1.01 if size is None else SCALE_TOLERANCE_PX
    if abs(t.m12()) > 1e-12 or abs(t.m21()) > 1e-12:
        return None
    # The map's scale equals the image's to within ``tolerance`` device px across it.
    if abs(t.m11() * (x1 - x0) - sw) * dpr > tolerance or (
        abs(-t.m22() * (y1 - y0) - sh) * dpr > tolerance
    ):
        return None
    vb = item.getViewBox()
    if vb is None:
        return None
    shown = vb.viewRect()
    tx, ty = (x1 - x0) / sw, (y1 - y0) / sh  # one logical pixel, in degrees
    if not (
        shown.left() >= x0 - tx
        and shown.right() <= x1 + tx
        and shown.top() >= y0 - ty
        and shown.bottom() <= y1 + ty
    ):
        return None  # panned beyond the image: stroke until a new one is made
    corner = t.map(QtCore.QPointF(x0, y1))  # on a device pixel
    return QtCore.QPointF(round(corner.x() * dpr) / dpr, round(corner.y() * dpr) / dpr)


def image_size(size_px: tuple[float, float], dpr: float = 1.0) -> tuple[int, int]:
    """The image (device pixels) that covers a plot area of ``size_px`` (logical px,
    fractional) at the pixel ratio ``dpr``."""
    return (
        int(math.ceil(float(size_px[0]) * dpr - 1e-6)),
        int(math.ceil(float(size_px[1]) * dpr - 1e-6)),
    )


def _chunks(lon: np.ndarray, size: int) -> list[tuple[int, int]]:
    """``[a, b)`` ranges of about ``size`` vertices that cut only at NaN separators."""
    n = len(lon)
    if n <= size:
        return [(0, n)]
    gaps = np.flatnonzero(~np.isfinite(lon))
    if len(gaps) == 0:
        return [(0, n)]
    want = np.arange(size, n, size)
    cuts = np.unique(gaps[np.minimum(np.searchsorted(gaps, want), len(gaps) - 1)])
    bounds = np.concatenate([[0], cuts + 1, [n]])
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]


def curve_path(lon: np.ndarray, lat: np.ndarray) -> QtGui.QPainterPath:
    """``pg.arrayToQPath(lon, lat, connect="finite")``, built in pieces of about
    ``PATH_PIECE_VERTICES`` vertices cut at NaN separators, so that no single call holds
    the GIL for the whole curve. It strokes the same pixels (each piece starts a new
    subpath where the whole one would; tests/test_map_sprites.py)."""
    pieces = _chunks(lon, PATH_PIECE_VERTICES)
    if len(pieces) == 1:
        return pg.arrayToQPath(lon, lat, connect="finite")
    path = QtGui.QPainterPath()
    path.reserve(len(lon))
    for a, b in pieces:
        path.addPath(pg.arrayToQPath(lon[a:b], lat[a:b], connect="finite"))
    return path


def crosses(
    lon: np.ndarray, lat: np.ndarray, px: tuple[float, float], size_px: float
) -> tuple[np.ndarray, np.ndarray]:
    """A small cross (two segments, ``size_px`` pixels of ``px`` degrees wide) at every
    finite vertex: arrays to draw with ``connect="pairs"``."""
    ok = np.isfinite(lon) & np.isfinite(lat)
    x, y = lon[ok], lat[ok]
    dx, dy = px[0] * size_px / 2, px[1] * size_px / 2
    xs = np.stack([x - dx, x + dx, x, x], axis=1).ravel()
    ys = np.stack([y, y, y - dy, y + dy], axis=1).ravel()
    return xs, ys


def render_sprite(
    curve: Curve,
    view: tuple[float, float, float, float],
    size_px: tuple[int, int],
    width: float = 1.0,
    antialias: bool = False,
    connect: str = "finite",
    dpr: float = 1.0,
) -> Sprite | None:
    """Stroke ``curve`` into an image showing ``view`` on a plot area of ``size_px`` (w,
    h, logical px; fractional as the map's) at the map's scale, ``dpr`` device pixels a
    logical one (pure; for a worker thread). None when the view or size cannot make one.
    ``connect="pairs"``: the curve is segments (crosses), stroked in pieces of whole
    segments."""
    x0, x1, y0, y1 = view
    w, h = image_size(size_px, dpr)
    if w <= 0 or h <= 0 or w * h > MAX_SPRITE_PIXELS or not (x1 > x0 and y1 > y0):
        return None
    image = QtGui.QImage(w, h, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QtCore.Qt.GlobalColor.transparent)
    sx, sy = size_px[0] * dpr / (x1 - x0), size_px[1] * dpr / (y1 - y0)
    pen = pg.mkPen(curve.color, width=width * dpr)
    painter = QtGui.QPainter(image)
    try:
        painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, antialias)
        painter.setPen(pen)
        painter.setTransform(QtGui.QTransform(sx, 0.0, 0.0, -sy, -x0 * sx, y1 * sy))
        if connect == "pairs":
            step = CHUNK_VERTICES - CHUNK_VERTICES % 2
            pieces = [(a, min(a + step, len(curve.lon))) for a in range(0, len(curve.lon), step)]
        else:
            pieces = _chunks(curve.lon, CHUNK_VERTICES)
        for a, b in pieces:
            painter.drawPath(pg.arrayToQPath(curve.lon[a:b], curve.lat[a:b], connect=connect))
    finally:
        painter.end()
    image.setDevicePixelRatio(dpr)
    rgba = pen.color().rgba()
    size = (float(size_px[0]), float(size_px[1]))
    return Sprite(image, (x0, x1, y0, y1), rgba, float(width), antialias, len(curve.lon), size)


def with_paths(data: DrawData, sprites: bool = True) -> DrawData:
    """``data`` with the path of every long line curve built and, when it was decimated
    for a view (``data.view``), its sprite stroked (call it in a worker)."""
    size = None
    if sprites and data.view is not None and data.px is not None:
        x0, x1, y0, y1 = data.view
        size = ((x1 - x0) / data.px[0], (y1 - y0) / data.px[1])  # the map's, fractional
    antialias = bool(pg.getConfigOption("antialias"))
    if not data.style.width:
        # Markers only: symbols while few, else 1-px crosses (one path) whose sprite is
        # made here; never the line path.
        if size is None or not data.style.symbol_size:
            return data

        def marks(c: Curve) -> Curve:
            if c.n_vertices <= SYMBOLS_MAX or c.sprite is not None:
                return c
            xs, ys = crosses(c.lon, c.lat, data.px, data.style.symbol_size)
            cross = replace(c, lon=xs, lat=ys)
            sprite = render_sprite(cross, data.view, size, 1.0, antialias, connect="pairs")
            return replace(c, sprite=sprite)

        return replace(data, curves=tuple(marks(c) for c in data.curves))

    def one(c: Curve) -> Curve:
        if len(c.lon) < MIN_VERTICES:
            return c
        if c.path is None:
            c = replace(c, path=curve_path(c.lon, c.lat))
        if size is not None and c.sprite is None and c.n_vertices > SYMBOLS_MAX:
            c = replace(c, sprite=render_sprite(c, data.view, size, 1.0, antialias))
        return c

    return replace(data, curves=tuple(one(c) for c in data.curves))


class SpriteCurve(pg.PlotCurveItem):
    """A curve item that copies its :class:`Sprite` when it fits, else strokes — or,
    a curve of ``STAND_IN_VERTICES`` or more while ``remaking()`` says a new sprite is
    on its way, copies the old one scaled to the view (:meth:`Sprite.draw_scaled`)."""

    sprite: Sprite | None = None
    #: Set by the map: true while a level of detail or sprite job is asked for or runs.
    remaking = None

    def paint(self, p, opt, widget) -> None:
        sprite = self.sprite
        if sprite is not None and sprite.draw(p, self):
            return
        if (
            sprite is not None
            and sprite.n >= STAND_IN_VERTICES
            and self.remaking is not None
            and self.remaking()
            and sprite.draw_scaled(p, self)
        ):
            return
        super().paint(p, opt, widget)


#: Style arguments :class:`UniformScatter` takes one value of for every spot.
_STYLE_ARGS = ("pen", "brush", "symbol", "size")


class UniformScatter(pg.ScatterPlotItem):
    """A scatter item whose spots all share one style (one symbol, size, pen, brush),
    the way a layer's curve draws its symbols.

    pyqtgraph's ``addPoints`` looks up each spot's symbol in its atlas in Python (a
    style tuple and a key per spot; a layer of 12 sensor curves swapped in after every
    pan and zoom). Here the one style is looked up once and its place in the atlas given
    to every spot with a numpy assignment (3,000 spots: 1.0 ms against 2.5 ms, and no
    Python object per spot); any other call (spots, per-spot styles or data, hover
    styles, no pixel mode or atlas) goes to pyqtgraph.
    """

    def pixelVectors(self, direction=None):  # noqa: N802 - pyqtgraph's name
        """pyqtgraph's, computed once per view for every scatter of one view box: keyed by
        the scale of the box's data-to-scene transform (a layer's items carry no transform
        of their own, the scene is drawn unscaled, and translation does not count). Each
        paint asks it two or three times per item (bounds, culling), ~0.1 ms each: with
        200 single-track layers a repaint spent ~60 ms there."""
        vb = self.getViewBox() if direction is None and self._exportOpts is False else None
        if not isinstance(vb, pg.ViewBox) or self.parentItem() is None:
            return super().pixelVectors(direction)
        t = vb.childGroup.sceneTransform()
        key = (t.m11(), t.m12(), t.m21(), t.m22())
        cached = getattr(vb, "_wakeline_pixel_vectors", None)
        if cached is not None and cached[0] == key:
            return cached[1]
        pv = super().pixelVectors()
        if pv[0] is not None:
            vb._wakeline_pixel_vectors = (key, pv)
        return pv

    def _uniform(self, args: tuple, kargs: dict) -> bool:
        if args or "spots" in kargs or "pos" in kargs or len(self.data):
            return False
        if kargs.get("x") is None or kargs.get("y") is None or kargs.get("data") is not None:
            return False
        if kargs.get("mask") is not None or kargs.get("hoverable", self.opts["hoverable"]):
            return False
        if not kargs.get("pxMode", self.opts["pxMode"]):
            return False
        if not kargs.get("useCache", self.opts["useCache"]):
            return False
        return not any(isinstance(kargs.get(k), (list, np.ndarray)) for k in _STYLE_ARGS)

    def addPoints(self, *args, **kargs) -> None:  # noqa: N802 - pyqtgraph's name
        if not self._uniform(args, kargs):
            super().addPoints(*args, **kargs)
            return
        x = np.asarray(kargs["x"], dtype=float)
        y = np.asarray(kargs["y"], dtype=float)
        # np.empty: the object fields (symbol, pen, brush, data, item) start as None,
        # which means "the item's default" (self.opts) to pyqtgraph.
        data = np.empty(len(y), dtype=self.data.dtype)
        data["x"] = x
        data["y"] = y
        data["size"] = -1
        data["visible"] = True
        data["hovered"] = False
        for k in ("name", "pxMode", "antialias", "tip", "useCache"):
            if k in kargs:
                if k == "pxMode":
                    self.setPxMode(kargs[k])
                else:
                    self.opts[k] = kargs[k]
        for k in _STYLE_ARGS:
            if k in kargs:
                setter = getattr(self, "set" + k.capitalize())
                setter(kargs[k], update=False, dataSet=data[:0])
        if len(data):
            # The one style, in the atlas' order, from the first spot's defaults.
            style = tuple(c[0] for c in self._style(["symbol", "size", "pen", "brush"], data[:1]))
            data["sourceRect"] = self.fragmentAtlas[[style]][0]
        self.data = data
        self.prepareGeometryChange()
        self.informViewBoundsChanged()
        self.bounds = [None, None]
        self._maybeRebuildAtlas()
        self._updateMaxSpotSizes(data=data)
        self.invalidate()
        self.sigPlotChanged.emit(self)


class LayerItem(pg.PlotDataItem):
    """``pg.PlotDataItem`` whose curve is a :class:`SpriteCurve` and whose symbols are a
    :class:`UniformScatter`."""

    def __init__(self, *args, **kwargs) -> None:
        # PlotDataItem makes its curve and scatter by the names PlotCurveItem and
        # ScatterPlotItem of its module: point the names at ours for the constructor
        # (GUI thread only, never re-entered).
        curve, scatter = _plot_data_item.PlotCurveItem, _plot_data_item.ScatterPlotItem
        _plot_data_item.PlotCurveItem = SpriteCurve
        _plot_data_item.ScatterPlotItem = UniformScatter
        try:
            super().__init__(*args, **kwargs)
        finally:
            _plot_data_item.PlotCurveItem = curve
            _plot_data_item.ScatterPlotItem = scatter

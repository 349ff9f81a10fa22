"""Many markers of one style drawn from arrays: the time slider's positions at ``t``.

pyqtgraph's ``ScatterPlotItem.setData`` does Python work for every spot (a key, an id
and a style lookup per spot: 140–200 ms of GUI-thread CPU for the 13k–66k positions of
the ATD example's five layers). :class:`MarkerItem` keeps the positions as two arrays
and paints them with one ``QPainter.drawPixmapFragments`` call per few thousand markers
(a symbol pixmap stamped at every position, the coordinates mapped with numpy).

A worker draws the same stamps into an image of the view (:func:`render_marks`, a
:class:`MarkSprite`); while the map shows that view at that scale the paint only copies
the image (< 1 ms). Any other paint (a pan or zoom before the next frame, a high-DPI
screen) stamps the symbols as above. PySide holds the GIL while ``drawPixmapFragments``
runs, so the worker stamps in pieces of :data:`CHUNK` markers.
"""

import math
from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from wakeline.app.map_paths import MAX_SPRITE_PIXELS, image_corner

MARKER_PEN = "#111111"
MARKER_PEN_WIDTH = 1.2
MARKER_BRUSH = "#ffcc00"
#: Markers stamped per ``drawPixmapFragments`` call (a few ms each).
CHUNK = 8_000


def marker_symbol(size: float) -> QtGui.QImage:
    """A filled circle ``size`` px across with a dark outline (as pyqtgraph's ``"o"``)
    on a transparent square image (any thread: a QImage)."""
    side = int(math.ceil(size + MARKER_PEN_WIDTH)) + 2
    image = QtGui.QImage(side, side, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(image)
    try:
        painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, True)
        painter.setPen(pg.mkPen(MARKER_PEN, width=MARKER_PEN_WIDTH))
        painter.setBrush(pg.mkBrush(MARKER_BRUSH))
        c = side / 2.0
        painter.drawEllipse(QtCore.QRectF(c - size / 2.0, c - size / 2.0, size, size))
    finally:
        painter.end()
    return image


def stamp(p: QtGui.QPainter, x: np.ndarray, y: np.ndarray, symbol: QtGui.QPixmap) -> None:
    """Copy ``symbol`` centred on every (x, y) (device pixels of ``p``), in pieces."""
    n = len(x)
    if not n:
        return
    frags = pg.Qt.internals.PrimitiveArray(QtGui.QPainter.PixmapFragment, 10)
    w, h = symbol.width(), symbol.height()
    for a in range(0, n, CHUNK):
        b = min(a + CHUNK, n)
        frags.resize(b - a)
        f = frags.ndarray()
        f[:, 0] = x[a:b]
        f[:, 1] = y[a:b]
        f[:, 2:6] = (0.0, 0.0, w, h)  # source rectangle
        f[:, 6:10] = (1.0, 1.0, 0.0, 1.0)  # scale x, y, rotation, opacity
        p.drawPixmapFragments(*frags.drawargs(), symbol)


@dataclass(frozen=True)
class MarkSprite:
    """Markers of ``size`` px stamped into ``image``, which shows ``view`` (x0, x1, y0,
    y1, degrees) on its pixels; ``n`` markers."""

    image: QtGui.QImage
    view: tuple[float, float, float, float]
    size: float
    n: int


def render_marks(
    lon: np.ndarray,
    lat: np.ndarray,
    view: tuple[float, float, float, float],
    size_px: tuple[int, int],
    size: float,
) -> MarkSprite | None:
    """Stamp a marker of ``size`` px at every (lon, lat) into an image of ``size_px``
    (w, h) showing ``view`` (pure; for a worker thread). None when the view or size
    cannot make one, or the platform makes no pixmap off the GUI thread."""
    x0, x1, y0, y1 = view
    w, h = int(size_px[0]), int(size_px[1])
    if w <= 0 or h <= 0 or w * h > MAX_SPRITE_PIXELS or not (x1 > x0 and y1 > y0):
        return None
    symbol = QtGui.QPixmap.fromImage(marker_symbol(size))
    if symbol.isNull():  # no pixmaps outside the GUI thread here: the paint stamps
        return None
    sx, sy = w / (x1 - x0), h / (y1 - y0)
    px = (np.asarray(lon, dtype=float) - x0) * sx
    py = (y1 - np.asarray(lat, dtype=float)) * sy
    r = symbol.width()
    keep = (px > -r) & (px < w + r) & (py > -r) & (py < h + r)
    image = QtGui.QImage(w, h, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(image)
    try:
        stamp(painter, px[keep], py[keep], symbol)
    finally:
        painter.end()
    n = int(np.count_nonzero(np.isfinite(px) & np.isfinite(py)))
    return MarkSprite(image, (x0, x1, y0, y1), float(size), n)


class MarkerItem(pg.GraphicsObject):
    """Markers of one style (``"o"``, :data:`MARKER_BRUSH` with a dark outline) at the
    points of two arrays, ``size`` px across whatever the zoom. ``setData(x, y,
    sprite)``: new positions, with the image a worker stamped them into (or None)."""

    def __init__(self, size: float = 10.0) -> None:
        super().__init__()
        self.opts = {"size": float(size)}
        self._x = np.zeros(0)
        self._y = np.zeros(0)
        self._data_rect: QtCore.QRectF | None = None
        self._rect: QtCore.QRectF | None = None
        self.sprite: MarkSprite | None = None
        self._symbols: dict[float, QtGui.QPixmap] = {}

    def setData(self, x, y, sprite: MarkSprite | None = None) -> None:  # noqa: N802
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        ok = np.isfinite(x) & np.isfinite(y)
        if not ok.all():
            x, y = x[ok], y[ok]
        self._x, self._y = x, y
        self.sprite = sprite
        if len(x):
            x0, x1, y0, y1 = x.min(), x.max(), y.min(), y.max()
            self._data_rect = QtCore.QRectF(x0, y0, x1 - x0, y1 - y0)
        else:
            self._data_rect = None
        self.prepareGeometryChange()
        self._rect = None
        self.update()

    def getData(self) -> tuple[np.ndarray, np.ndarray]:  # noqa: N802 - pyqtgraph's name
        return self._x, self._y

    def setSize(self, size: float) -> None:  # noqa: N802 - pyqtgraph's name
        self.opts["size"] = float(size)
        self.prepareGeometryChange()
        self._rect = None
        self.update()

    def symbol(self) -> QtGui.QPixmap:
        size = self.opts["size"]
        pixmap = self._symbols.get(size)
        if pixmap is None:
            pixmap = self._symbols[size] = QtGui.QPixmap.fromImage(marker_symbol(size))
        return pixmap

    def viewTransformChanged(self) -> None:  # noqa: N802 - pyqtgraph's hook
        self.prepareGeometryChange()
        self._rect = None

    def boundingRect(self) -> QtCore.QRectF:  # noqa: N802 - Qt API
        if self._data_rect is None:
            return QtCore.QRectF()
        if self._rect is None:
            rect = QtCore.QRectF(self._data_rect)
            vb = self.getViewBox()
            px = vb.viewPixelSize() if vb is not None else (0.0, 0.0)
            pad = self.opts["size"] / 2.0 + 2.0  # the symbol's half and its outline
            dx, dy = px[0] * pad, px[1] * pad
            self._rect = rect.adjusted(-dx, -dy, dx, dy)
        return self._rect

    def paint(self, p, opt, widget) -> None:
        if not len(self._x):
            return
        sprite = self.sprite
        if (
            sprite is not None
            and sprite.n == len(self._x)
            and sprite.size == self.opts["size"]
            and (corner := image_corner(p, self, sprite.view, sprite.image)) is not None
        ):
            p.save()
            p.resetTransform()
            p.drawImage(corner, sprite.image)
            p.restore()
            return
        # Stamped here: only the markers in the view, mapped with numpy.
        vb = self.getViewBox()
        x, y = self._x, self._y
        if vb is not None:
            r = vb.viewRect()
            px = vb.viewPixelSize()
            pad = (self.opts["size"] + 4.0) * max(px[0], px[1])
            keep = (
                (x >= r.left() - pad)
                & (x <= r.right() + pad)
                & (y >= r.top() - pad)
                & (y <= r.bottom() + pad)
            )
            x, y = x[keep], y[keep]
        t = p.transform()
        dx = t.m11() * x + t.m21() * y + t.dx()
        dy = t.m12() * x + t.m22() * y + t.dy()
        p.save()
        p.resetTransform()
        stamp(p, dx, dy, self.symbol())
        p.restore()

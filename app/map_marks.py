"""Many markers drawn from arrays: the time slider's positions at ``t``, each in its
layer's colour (a colour code per marker and the colours).

pyqtgraph's ``ScatterPlotItem.setData`` does Python work for every spot (a key, an id
and a style lookup per spot: 140–200 ms of GUI-thread CPU for the 13k–66k positions of
the ATD example's five layers). :class:`MarkerItem` keeps the positions as two arrays
and paints them with one ``QPainter.drawPixmapFragments`` call per few thousand markers
(a symbol pixmap stamped at every position, the coordinates mapped with numpy).

A worker draws the same stamps into an image of the view (:func:`render_marks`, a
:class:`MarkSprite`); while the map shows that view at that scale the paint only copies
the image (< 1 ms); on a high-DPI screen the worker draws it at the screen's device pixel
ratio. Any other paint (a pan or zoom before the next frame) stamps the symbols as
above. PySide holds the GIL while ``drawPixmapFragments``
runs, so the worker stamps in pieces of :data:`CHUNK` markers.
"""

import math
from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from wakeline.app.map_paths import MAX_SPRITE_PIXELS, image_corner, image_size

MARKER_PEN = "#111111"
MARKER_PEN_WIDTH = 1.2
MARKER_BRUSH = "#ffcc00"  # markers with no colour of their own
#: Markers stamped per ``drawPixmapFragments`` call (a few ms each).
CHUNK = 8_000


def marker_symbol(size: float, color: str = MARKER_BRUSH, dpr: float = 1.0) -> QtGui.QImage:
    """A circle filled with ``color``, ``size`` px across with a dark outline (as
    pyqtgraph's ``"o"``) on a transparent square image, drawn ``dpr`` image pixels per px
    (any thread: a QImage)."""
    side = int(math.ceil((size + MARKER_PEN_WIDTH) * dpr)) + 2
    image = QtGui.QImage(side, side, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(image)
    try:
        painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, True)
        painter.setPen(pg.mkPen(MARKER_PEN, width=MARKER_PEN_WIDTH * dpr))
        painter.setBrush(pg.mkBrush(color))
        c, d = side / 2.0, size * dpr
        painter.drawEllipse(QtCore.QRectF(c - d / 2.0, c - d / 2.0, d, d))
    finally:
        painter.end()
    return image


def by_color(codes: np.ndarray | None, n_colors: int, n: int) -> list[tuple[int, np.ndarray]]:
    """The markers of each colour: (colour code, their indices) for the codes present
    (one sort, no loop per marker). No codes: every marker of colour 0."""
    if codes is None or n_colors <= 1:
        return [(0, np.arange(n))] if n else []
    codes = np.clip(np.asarray(codes, dtype="int64"), 0, n_colors - 1)
    order = np.argsort(codes, kind="stable")
    counts = np.bincount(codes, minlength=n_colors)
    ends = np.cumsum(counts)
    return [(k, order[ends[k] - counts[k] : ends[k]]) for k in np.flatnonzero(counts).tolist()]


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
    y1, degrees) on a plot area of ``plot`` (w, h, logical px) at the image's device pixel
    ratio; ``n`` markers, in ``colors``."""

    image: QtGui.QImage
    view: tuple[float, float, float, float]
    size: float
    n: int
    plot: tuple[float, float] | None = None
    colors: tuple[str, ...] = (MARKER_BRUSH,)


def render_marks(
    lon: np.ndarray,
    lat: np.ndarray,
    view: tuple[float, float, float, float],
    size_px: tuple[float, float],
    size: float,
    codes: np.ndarray | None = None,
    colors: tuple[str, ...] = (MARKER_BRUSH,),
    dpr: float = 1.0,
) -> MarkSprite | None:
    """Stamp a marker of ``size`` px at every (lon, lat), marker ``i`` filled with
    ``colors[codes[i]]`` (no codes: the first colour), into an image showing ``view`` on
    a plot area of ``size_px`` (w, h, logical px, fractional as the map's) at ``dpr``
    device pixels a px (pure; for a worker thread). None when the view or size cannot
    make one, or the platform makes no pixmap off the GUI thread."""
    x0, x1, y0, y1 = view
    w, h = image_size(size_px, dpr)
    if w <= 0 or h <= 0 or w * h > MAX_SPRITE_PIXELS or not (x1 > x0 and y1 > y0):
        return None
    colors = tuple(colors) or (MARKER_BRUSH,)
    sx, sy = size_px[0] * dpr / (x1 - x0), size_px[1] * dpr / (y1 - y0)
    px = (np.asarray(lon, dtype=float) - x0) * sx
    py = (y1 - np.asarray(lat, dtype=float)) * sy
    image = QtGui.QImage(w, h, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(image)
    try:
        for k, rows in by_color(codes, len(colors), len(px)):
            symbol = QtGui.QPixmap.fromImage(marker_symbol(size, colors[k], dpr))
            if symbol.isNull():  # no pixmaps outside the GUI thread here: the paint stamps
                return None
            r = symbol.width()
            x, y = px[rows], py[rows]
            keep = (x > -r) & (x < w + r) & (y > -r) & (y < h + r)
            stamp(painter, x[keep], y[keep], symbol)
    finally:
        painter.end()
    image.setDevicePixelRatio(dpr)
    n = int(np.count_nonzero(np.isfinite(px) & np.isfinite(py)))
    plot = (float(size_px[0]), float(size_px[1]))
    return MarkSprite(image, (x0, x1, y0, y1), float(size), n, plot, colors)


class MarkerItem(pg.GraphicsObject):
    """Markers (``"o"`` with a dark outline) at the points of two arrays, ``size`` px
    across whatever the zoom, each filled with its colour. ``setData(x, y, sprite,
    codes, colors)``: new positions, with the image a worker stamped them into (or
    None), marker ``i`` in ``colors[codes[i]]`` (no codes: :data:`MARKER_BRUSH`)."""

    def __init__(self, size: float = 10.0) -> None:
        super().__init__()
        self.opts = {"size": float(size)}
        self._x = np.zeros(0)
        self._y = np.zeros(0)
        self._data_rect: QtCore.QRectF | None = None
        self._rect: QtCore.QRectF | None = None
        self.sprite: MarkSprite | None = None
        self._codes: np.ndarray | None = None
        self.colors: tuple[str, ...] = (MARKER_BRUSH,)
        self._symbols: dict[tuple[float, str], QtGui.QPixmap] = {}

    def setData(  # noqa: N802 - pyqtgraph's name
        self,
        x,
        y,
        sprite: MarkSprite | None = None,
        codes: np.ndarray | None = None,
        colors: tuple[str, ...] | None = None,
    ) -> None:
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        codes = None if codes is None else np.asarray(codes, dtype="int64")
        ok = np.isfinite(x) & np.isfinite(y)
        if not ok.all():
            x, y = x[ok], y[ok]
            codes = None if codes is None else codes[ok]
        self._x, self._y = x, y
        self._codes = codes
        self.colors = tuple(colors) if colors else (MARKER_BRUSH,)
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

    def codes(self) -> np.ndarray | None:
        """The colour code of every marker (an index into :attr:`colors`), or None."""
        return self._codes

    def symbol(self, color: str = MARKER_BRUSH) -> QtGui.QPixmap:
        key = (self.opts["size"], color)
        pixmap = self._symbols.get(key)
        if pixmap is None:
            if len(self._symbols) > 64:
                self._symbols.clear()
            pixmap = QtGui.QPixmap.fromImage(marker_symbol(key[0], color))
            self._symbols[key] = pixmap
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
            and sprite.colors == self.colors
            and (corner := image_corner(p, self, sprite.view, sprite.image, sprite.plot))
            is not None
        ):
            p.save()
            p.resetTransform()
            p.drawImage(corner, sprite.image)
            p.restore()
            return
        # Stamped here: only the markers in the view, mapped with numpy.
        vb = self.getViewBox()
        x, y, codes = self._x, self._y, self._codes
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
            codes = None if codes is None else codes[keep]
        t = p.transform()
        dx = t.m11() * x + t.m21() * y + t.dx()
        dy = t.m12() * x + t.m22() * y + t.dy()
        p.save()
        p.resetTransform()
        for k, rows in by_color(codes, len(self.colors), len(dx)):
            stamp(p, dx[rows], dy[rows], self.symbol(self.colors[k]))
        p.restore()

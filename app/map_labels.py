"""Track labels on the map: a track's name (batch, and the ship's name when the file has
one) beside its current-position marker while Positions is on, else at its last point.

Which labels are drawn is decided by :func:`declutter` (numpy, no Qt): the labels in view,
none when more than :data:`LABEL_LIMIT` are (zoomed far out they would cover the
tracks), and of those only labels that overlap no label kept before them. The GUI thread
only moves a few text items (at most the limit).
"""

import numpy as np
import pyqtgraph as pg
from PySide6 import QtGui

#: No label is drawn when more than this many tracks' label points are in view.
LABEL_LIMIT = 60
#: A label's height (px) and its gap from its point.
LABEL_H_PX = 14.0
LABEL_GAP_PX = 6.0
#: Columns that name a ship, in order of preference (AIS files).
NAME_COLUMNS = ("shipname", "ship_name", "vessel_name", "vesselname", "name")
#: Over the Positions markers (71) and trail (70), under the hover (99).
LABEL_Z = 72


def position_at(
    time_s: np.ndarray, starts: np.ndarray, ends: np.ndarray, t: float
) -> tuple[np.ndarray, np.ndarray]:
    """Per track, the row of its last point at or before ``t`` and whether the track is
    alive at ``t`` (first point ≤ t ≤ last point). Times are sorted within each track."""
    n = len(starts)
    rows = np.zeros(n, dtype="int64")
    if n == 0:
        return rows, np.zeros(0, dtype=bool)
    first, last = time_s[starts], time_s[ends - 1]
    alive = (first <= t) & (t <= last)
    for k in np.flatnonzero(alive):  # only tracks alive at t (labels are few)
        a, e = int(starts[k]), int(ends[k])
        rows[k] = a + max(int(np.searchsorted(time_s[a:e], t, side="right")) - 1, 0)
    return rows, alive


def declutter(
    x_px: np.ndarray,
    y_px: np.ndarray,
    widths_px: np.ndarray,
    size_px: tuple[float, float],
    limit: int = LABEL_LIMIT,
) -> np.ndarray:
    """Indices of the labels to draw: anchored at ``x_px, y_px`` (pixels from the view's
    top-left), each ``widths_px`` wide and :data:`LABEL_H_PX` high, drawn right of its
    point; those in view, none when more than ``limit`` are; then, in order, each label
    that overlaps no label kept before it."""
    w, h = size_px
    inside = np.flatnonzero((x_px >= 0) & (x_px <= w) & (y_px >= 0) & (y_px <= h))
    if len(inside) == 0 or len(inside) > limit:
        return np.zeros(0, dtype="int64")
    kept: list[int] = []
    boxes: list[tuple[float, float, float, float]] = []
    for i in inside:
        x0 = float(x_px[i]) + LABEL_GAP_PX
        y0 = float(y_px[i]) - LABEL_H_PX / 2
        box = (x0, y0, x0 + float(widths_px[i]), y0 + LABEL_H_PX)
        if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in boxes):
            continue
        kept.append(int(i))
        boxes.append(box)
    return np.asarray(kept, dtype="int64")


class TrackLabels:
    """A pool of text items on a map canvas, shown for the labels :func:`declutter` keeps."""

    def __init__(self, canvas) -> None:
        self.canvas = canvas
        self.items: list[pg.TextItem] = []
        font = QtGui.QFont()
        font.setPointSizeF(8.0)
        self.font = font
        self.metrics = QtGui.QFontMetricsF(font)
        self.shown: list[str] = []

    def _item(self, k: int) -> pg.TextItem:
        while len(self.items) <= k:
            item = pg.TextItem(anchor=(0, 0.5), fill=pg.mkBrush(255, 255, 255, 190))
            item.setFont(self.font)
            item.setZValue(LABEL_Z)
            item.hide()
            self.canvas.addItem(item, ignoreBounds=True)
            self.items.append(item)
        return self.items[k]

    def show(
        self,
        lon: np.ndarray,
        lat: np.ndarray,
        texts: list[str],
        colors: list[str],
    ) -> list[str]:
        """Label the points ``lon, lat`` (degrees) with ``texts`` in ``colors``,
        decluttered for the map's view; returns the texts drawn."""
        (x0, x1), (y0, y1) = self.canvas.vb.viewRange()
        w, h = self.canvas.plot_size_px()
        lon, lat = np.asarray(lon, dtype="float64"), np.asarray(lat, dtype="float64")
        x_px = (lon - x0) / max(x1 - x0, 1e-12) * w
        y_px = (y1 - lat) / max(y1 - y0, 1e-12) * h
        ok = np.isfinite(x_px) & np.isfinite(y_px)
        inside = ok & (x_px >= 0) & (x_px <= w) & (y_px >= 0) & (y_px <= h)
        widths = np.zeros(len(texts))
        if 0 < int(inside.sum()) <= LABEL_LIMIT:
            for i in np.flatnonzero(inside):
                widths[i] = self.metrics.horizontalAdvance(texts[i]) + 8.0
        keep = declutter(np.where(ok, x_px, -1.0), np.where(ok, y_px, -1.0), widths, (w, h))
        pixel = self.canvas.vb.viewPixelSize()[0]
        for k, i in enumerate(keep):
            item = self._item(k)
            item.setText(texts[i], color=colors[i])
            item.setPos(float(lon[i]) + LABEL_GAP_PX * pixel, float(lat[i]))
            item.show()
        for item in self.items[len(keep) :]:
            item.hide()
        self.shown = [texts[i] for i in keep]
        return self.shown

    def clear(self) -> None:
        for item in self.items:
            item.hide()
        self.shown = []

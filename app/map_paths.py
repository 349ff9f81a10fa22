"""Painter paths of the map's curves, built off the GUI thread.

pyqtgraph builds a curve's ``QPainterPath`` from its arrays on the first paint after
``setData`` (20–28 ms of GUI-thread CPU for 120k vertices). A ``QPainterPath`` is a
plain value class (reentrant), so a worker can build it with pyqtgraph's own
``arrayToQPath`` and the canvas hands it to the curve item after ``setData``: the paint
then only strokes it.
"""

from dataclasses import replace

import pyqtgraph as pg

from wakeline.app.map_draw import DrawData

#: Curves with fewer vertices are left to pyqtgraph (cheap; wide pens draw segments).
MIN_VERTICES = 2_000


def with_paths(data: DrawData) -> DrawData:
    """``data`` with the path of every long line curve built (call it in a worker)."""
    if not data.style.width:
        return data  # markers only: drawn as symbols or crosses, never as this path
    curves = tuple(
        replace(c, path=pg.arrayToQPath(c.lon, c.lat, connect="finite"))
        if len(c.lon) >= MIN_VERTICES and c.path is None
        else c
        for c in data.curves
    )
    return replace(data, curves=curves)

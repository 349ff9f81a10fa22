"""The map: lon/lat with a true aspect at the data's latitude, tracks drawn per layer.

Each layer is ONE pyqtgraph curve whose tracks are separated by NaN (``connect="finite"``),
so thousands of tracks cost a handful of items.
"""

import math

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore

from wakeline.core.tracks import sort_points, track_index

PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf")


def nan_separated(points: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """lon, lat of all tracks in one pair of arrays, a NaN between consecutive tracks.

    Longitudes are unwrapped along each track so a track crossing 180° stays continuous.
    """
    df = sort_points(points)
    index = track_index(df)
    n, k = len(df), index.n_tracks
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    if n == 0:
        return np.zeros(0), np.zeros(0)
    step = np.diff(lon, prepend=lon[0])
    step[index.starts] = 0.0
    jumps = np.where(step > 180.0, -360.0, np.where(step < -180.0, 360.0, 0.0))
    # Accumulate the ±360° corrections within each track only.
    cum = np.cumsum(jumps)
    cum -= np.repeat(cum[index.starts], index.sizes)
    lon = lon + cum
    out_lon = np.full(n + k - 1, np.nan)
    out_lat = np.full(n + k - 1, np.nan)
    dest = np.arange(n) + index.track_of_row  # one slot more per track before
    out_lon[dest] = lon
    out_lat[dest] = lat
    return out_lon, out_lat


class MapCanvas(pg.PlotWidget):
    """A pyqtgraph plot set up as a lon/lat chart."""

    cursorMoved = QtCore.Signal(float, float)  # lon, lat in degrees

    def __init__(self, parent=None) -> None:
        super().__init__(parent=parent, background="w")
        self.setLabel("bottom", "longitude", units="°")
        self.setLabel("left", "latitude", units="°")
        self.showGrid(x=True, y=True, alpha=0.25)
        self.getPlotItem().getViewBox().setAspectLocked(True, ratio=1.0)
        self._layers: dict[str, pg.PlotDataItem] = {}
        self.addLegend(offset=(10, 10))
        self.scene().sigMouseMoved.connect(self._mouse_moved)

    def set_true_aspect(self, lat_deg: float) -> None:
        """Lock the aspect so one km is as long east-west as north-south at ``lat_deg``."""
        # pyqtgraph's ratio is x-scale over y-scale (pixels per unit): a degree of
        # longitude is cos(lat) times as long as a degree of latitude.
        self.getPlotItem().getViewBox().setAspectLocked(
            True, ratio=max(math.cos(math.radians(lat_deg)), 0.05)
        )

    def set_layer(self, name: str, points: pd.DataFrame, color: str, width: float = 1.5) -> None:
        """Draw (or redraw) a layer: all tracks of ``points`` as one NaN-separated curve."""
        lon, lat = nan_separated(points)
        pen = pg.mkPen(color, width=width)
        if name in self._layers:
            self._layers[name].setData(lon, lat, connect="finite")
            self._layers[name].setPen(pen)
            return
        item = self.plot(
            lon,
            lat,
            pen=pen,
            connect="finite",
            name=name,
            symbol="o",
            symbolSize=2.5,
            symbolPen=None,
            symbolBrush=color,
        )
        self._layers[name] = item

    def layer_names(self) -> list[str]:
        return list(self._layers)

    def layer_item(self, name: str) -> pg.PlotDataItem:
        return self._layers[name]

    def fit(self) -> None:
        self.getPlotItem().getViewBox().autoRange(padding=0.05)

    def _mouse_moved(self, pos) -> None:
        vb = self.getPlotItem().getViewBox()
        if self.sceneBoundingRect().contains(pos):
            p = vb.mapSceneToView(pos)
            self.cursorMoved.emit(p.x(), p.y())

"""The map: lon/lat with a true aspect at the data's latitude, tracks drawn per layer.

Each layer (per sensor) is ONE pyqtgraph curve whose tracks are separated by NaN
(``connect="finite"``), so thousands of tracks cost a handful of items. The selection is
one more curve drawn on top. A click picks the nearest track point within a few pixels
(k-d tree per layer, built on first use).
"""

import math

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore, QtGui
from scipy.spatial import cKDTree

from wakeline.core.tracks import sort_points, track_index

PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf")
KM_PER_DEG = 111.195
NICE_KM = (0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000)


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


class _Pickable:
    """Points of one drawn layer with their (sensor, batch), for picking by click."""

    def __init__(self, points: pd.DataFrame) -> None:
        self.lon = points["lon"].to_numpy(dtype="float64")
        self.lat = points["lat"].to_numpy(dtype="float64")
        self.sensor = points["sensor"].astype(str).to_numpy()
        self.batch = points["batch"].astype(str).to_numpy()
        self._tree: cKDTree | None = None
        self._scale = math.cos(math.radians(float(np.nanmean(self.lat)))) if len(self.lat) else 1

    def nearest(self, lon: float, lat: float) -> tuple[float, int]:
        if self._tree is None:
            self._tree = cKDTree(np.column_stack([self.lon * self._scale, self.lat]))
        d, i = self._tree.query([lon * self._scale, lat])
        return float(d), int(i)


class MapCanvas(pg.PlotWidget):
    """A pyqtgraph plot set up as a lon/lat chart with layers, selection and picking."""

    cursorMoved = QtCore.Signal(float, float)  # lon, lat in degrees
    trackClicked = QtCore.Signal(str, str, str, bool)  # layer, sensor, batch, add to selection

    def __init__(self, parent=None) -> None:
        super().__init__(parent=parent, background="w")
        self.setLabel("bottom", "longitude", units="°")
        self.setLabel("left", "latitude", units="°")
        self.showGrid(x=True, y=True, alpha=0.25)
        self.vb = self.getPlotItem().getViewBox()
        self.vb.setAspectLocked(True, ratio=1.0)
        # The view is set by fit() from the data; pyqtgraph's auto range would ask every
        # item for bounds (and a clipped NaN-separated curve may have none).
        self.vb.disableAutoRange()
        self._items: dict[str, list[pg.PlotDataItem]] = {}
        self._pick: dict[str, _Pickable] = {}
        self._visible: dict[str, bool] = {}
        self._lat0 = 0.0
        self.legend = self.addLegend(offset=(10, 10))
        self.coastline = pg.PlotDataItem(pen=pg.mkPen("#8a8a8a", width=1), connect="finite")
        self.coastline.setZValue(-10)
        self.addItem(self.coastline)
        # The selection is a wide translucent halo under the tracks, so the selected
        # track itself stays visible on top of it.
        self.selection = pg.PlotDataItem(
            pen=pg.mkPen(QtGui.QColor(255, 170, 0, 170), width=9), connect="finite", name=None
        )
        self.selection.setZValue(-1)
        self.addItem(self.selection)
        self.marks = pg.ScatterPlotItem(size=8, pen=pg.mkPen("k"), brush=pg.mkBrush("w"))
        self.marks.setZValue(60)
        self.addItem(self.marks)
        self.scale_bar = pg.ScaleBar(size=0.1, suffix="")
        self.scale_bar.setParentItem(self.vb)
        self.scale_bar.anchor((1, 1), (1, 1), offset=(-20, -20))
        self.vb.sigRangeChanged.connect(self._update_scale_bar)
        self.scene().sigMouseMoved.connect(self._mouse_moved)
        self.scene().sigMouseClicked.connect(self._mouse_clicked)

    # -- layers --------------------------------------------------------------------

    def set_coastline(self, lon: np.ndarray, lat: np.ndarray) -> None:
        self.coastline.setData(lon, lat, connect="finite")

    def set_true_aspect(self, lat_deg: float) -> None:
        """Lock the aspect so one km is as long east-west as north-south at ``lat_deg``."""
        # pyqtgraph's ratio is x-scale over y-scale (pixels per unit): a degree of
        # longitude is cos(lat) times as long as a degree of latitude.
        self._lat0 = lat_deg
        self.vb.setAspectLocked(True, ratio=max(math.cos(math.radians(lat_deg)), 0.05))

    def set_layer(
        self,
        name: str,
        points: pd.DataFrame,
        color: str,
        by_sensor: bool = False,
        symbols: bool = True,
        width: float = 1.5,
    ) -> None:
        """Draw (or redraw) a layer: its tracks as one NaN-separated curve (one per sensor
        with ``by_sensor``, in palette colours starting at ``color``)."""
        self.remove_layer(name)
        groups = list(points.groupby("sensor", sort=True)) if by_sensor else [(None, points)]
        start = PALETTE.index(color) if color in PALETTE else 0
        items = []
        for k, (sensor, group) in enumerate(groups):
            c = PALETTE[(start + k) % len(PALETTE)] if by_sensor else color
            lon, lat = nan_separated(group)
            label = name if sensor is None else f"{name} · {sensor}"
            kw = {}
            if symbols:
                kw = {"symbol": "o", "symbolSize": 3, "symbolPen": None, "symbolBrush": c}
            item = pg.PlotDataItem(
                lon, lat, pen=pg.mkPen(c, width=width), connect="finite", name=label, **kw
            )
            self.addItem(item)
            # After addItem: clipping asks the item's view box, which it has only now.
            item.setDownsampling(auto=True, method="peak")
            item.setClipToView(True)
            items.append(item)
        self._items[name] = items
        self._pick[name] = _Pickable(points)
        self._visible[name] = True

    def remove_layer(self, name: str) -> None:
        for item in self._items.pop(name, []):
            self.removeItem(item)
            self.legend.removeItem(item)
        self._pick.pop(name, None)
        self._visible.pop(name, None)

    def set_visible(self, name: str, visible: bool) -> None:
        for item in self._items.get(name, []):
            item.setVisible(visible)
        if name in self._visible:
            self._visible[name] = visible

    def layer_names(self) -> list[str]:
        return list(self._items)

    def layer_items(self, name: str) -> list[pg.PlotDataItem]:
        return self._items[name]

    def n_items(self) -> int:
        return sum(len(v) for v in self._items.values())

    # -- selection -----------------------------------------------------------------

    def show_selection(self, points: pd.DataFrame, marks: pd.DataFrame | None = None) -> None:
        """Highlight ``points`` (the selected tracks) and optional marked points."""
        lon, lat = nan_separated(points) if len(points) else (np.zeros(0), np.zeros(0))
        self.selection.setData(lon, lat, connect="finite")
        if marks is not None and len(marks):
            self.marks.setData(marks["lon"].to_numpy(), marks["lat"].to_numpy())
        else:
            self.marks.setData([], [])

    def fit(self, points: pd.DataFrame | None = None) -> None:
        """Show ``points`` (default: every visible layer) with a margin."""
        if points is not None:
            lon, lat = points["lon"].to_numpy(), points["lat"].to_numpy()
        else:
            shown = [p for n, p in self._pick.items() if self._visible.get(n)]
            lon = np.concatenate([p.lon for p in shown]) if shown else np.zeros(0)
            lat = np.concatenate([p.lat for p in shown]) if shown else np.zeros(0)
        if len(lon) == 0:
            return
        pad_x = max(float(np.ptp(lon)) * 0.05, 0.01)
        pad_y = max(float(np.ptp(lat)) * 0.05, 0.01)
        self.vb.setRange(
            xRange=(float(lon.min()) - pad_x, float(lon.max()) + pad_x),
            yRange=(float(lat.min()) - pad_y, float(lat.max()) + pad_y),
            padding=0,
        )

    def set_box_zoom(self, on: bool) -> None:
        self.vb.setMouseMode(pg.ViewBox.RectMode if on else pg.ViewBox.PanMode)

    # -- events --------------------------------------------------------------------

    def _update_scale_bar(self) -> None:
        (x0, x1), _ = self.vb.viewRange()
        km_per_deg = KM_PER_DEG * max(math.cos(math.radians(self._lat0)), 0.05)
        width_km = (x1 - x0) * km_per_deg
        target = width_km / 5.0
        km = max([k for k in NICE_KM if k <= target] or [NICE_KM[0]])
        self.scale_bar.size = km / km_per_deg
        self.scale_bar.text.setText(f"{km:g} km")
        self.scale_bar.updateBar()

    def _mouse_moved(self, pos) -> None:
        if self.sceneBoundingRect().contains(pos):
            p = self.vb.mapSceneToView(pos)
            self.cursorMoved.emit(p.x(), p.y())

    def _mouse_clicked(self, event) -> None:
        if event.button() != QtCore.Qt.MouseButton.LeftButton or event.double():
            return
        p = self.vb.mapSceneToView(event.scenePos())
        add = bool(event.modifiers() & QtCore.Qt.KeyboardModifier.ControlModifier)
        self.pick(p.x(), p.y(), add)

    def pick(self, lon: float, lat: float, add: bool = False, pixels: float = 8.0) -> bool:
        """Emit ``trackClicked`` for the nearest visible track point within ``pixels``."""
        px = self.vb.viewPixelSize()
        scale = math.cos(math.radians(self._lat0))
        limit = pixels * max(px[0] * scale, px[1])
        best = None
        for name, pickable in self._pick.items():
            if not self._visible.get(name) or len(pickable.lon) == 0:
                continue
            d, i = pickable.nearest(lon, lat)
            if d <= limit and (best is None or d < best[0]):
                best = (d, name, pickable.sensor[i], pickable.batch[i])
        if best is None:
            return False
        self.trackClicked.emit(best[1], best[2], best[3], add)
        return True

    def render_png(self, path: str) -> bool:
        return self.grab().save(path)


def color_icon(color: str) -> QtGui.QIcon:
    pix = QtGui.QPixmap(14, 14)
    pix.fill(QtGui.QColor(color))
    return QtGui.QIcon(pix)


def prepare_draw(
    points: pd.DataFrame,
    color: str,
    by_sensor: bool = False,
    symbols: bool = True,
    width: float = 1.5,
) -> dict:
    """The arrays :meth:`MapCanvas.set_draw_data` shows; pure numpy, for a worker thread."""
    groups = list(points.groupby("sensor", sort=True)) if by_sensor else [(None, points)]
    start = PALETTE.index(color) if color in PALETTE else 0
    curves = []
    for k, (sensor, group) in enumerate(groups):
        c = PALETTE[(start + k) % len(PALETTE)] if by_sensor else color
        lon, lat = nan_separated(group)
        curves.append((sensor, c, lon, lat))
    return {"curves": curves, "symbols": symbols, "width": width, "pick": _Pickable(points)}


def _set_draw_data(self: "MapCanvas", name: str, data: dict) -> None:
    """Show prepared arrays as layer ``name`` (GUI thread; no computation here)."""
    self.remove_layer(name)
    items = []
    for sensor, c, lon, lat in data["curves"]:
        label = name if sensor is None else f"{name} · {sensor}"
        kw = {}
        if data["symbols"]:
            size = 8 if data["width"] == 0 else 3
            kw = {"symbol": "o", "symbolSize": size, "symbolPen": None, "symbolBrush": c}
        pen = pg.mkPen(c, width=data["width"]) if data["width"] > 0 else None
        item = pg.PlotDataItem(lon, lat, pen=pen, connect="finite", name=label, **kw)
        self.addItem(item)
        items.append(item)
    self._items[name] = items
    self._pick[name] = data["pick"]
    self._visible[name] = True


MapCanvas.set_draw_data = _set_draw_data

"""The map: lon/lat with a true aspect at the data's latitude, tracks drawn per layer.

Each layer is a few pyqtgraph curves (one per colour) whose tracks are separated by NaN
(``connect="finite"``), so thousands of tracks cost a handful of items. What is drawn is
prepared by the pure functions of :mod:`wakeline.app.map_draw` (sorting, unwrapping,
per-pixel level of detail, k-d tree) and only swapped in here (:meth:`set_draw_data`);
pyqtgraph's clip-to-view and auto-downsampling are never used (they assume x sorted and
drop most of a NaN-separated curve of many tracks). On zoom and pan the level of detail
is redone for layers whose decimation no longer fits the view: synchronously by default,
or through :attr:`MapCanvas.lod_executor` (e.g. a worker thread).

The legend sits in its own column right of the plot, so it never covers data. The
selection colours each batch differently. Hovering shows sensor, batch, time (elapsed
``T+…`` for scene-relative times) and speed of the nearest point.
"""

import dataclasses
import math
from collections.abc import Callable

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import ink
from wakeline.app.layer_view import framed_range, padded_range
from wakeline.app.map_coast import coastline_draw
from wakeline.app.map_draw import (
    PALETTE,
    DrawData,
    LayerStyle,
    lod_is_stale,
    nan_separated,
    prepare_layer,
    relod,
)
from wakeline.app.map_interact import MapInteractMixin
from wakeline.app.map_legend import SideLegend
from wakeline.app.map_paths import (
    SCALE_TOLERANCE_PX,
    SYMBOLS_MAX,
    LayerItem,
    crosses,
    with_paths,
)

__all__ = ["PALETTE", "MapCanvas", "color_icon", "nan_separated"]

# SYMBOLS_MAX (map_paths): symbols are drawn when a curve has at most this many vertices
# after the level of detail (zoomed in), all of one style (map_paths.UniformScatter: set
# with numpy, not spot by spot). Lines show without them beyond; marker-only layers show
# 1-px crosses.

#: The widest latitude tick label the left axis keeps room for from the start: thousandths of
#: a degree (ticks 111 m apart) south of the equator.
WIDEST_LATITUDE = "-88.888"
#: The scale bar and its label: dark grey (contrast 10 on white).
SCALE_BAR_COLOR = "#404040"
#: Opacity of the layers other than the active one (:meth:`MapCanvas.set_emphasis`).
DIM_OPACITY = 0.35
#: Added to the stacking of the active layer's items: over the other layers, under the
#: selection (z 50) and the marks; a step's marks layers get it always (over an active
#: layer's lines: :meth:`MapCanvas._z_of`).
ACTIVE_Z = 10.0
#: The layers' order (:meth:`MapCanvas.set_layer_order`) spreads their stacking over
#: this much of one unit: a later layer over an earlier one of the same kind of drawing,
#: never across kinds (a bearing file's lines stay under the tracks, marks over them).
ORDER_Z_SPAN = 0.9
#: The selected tracks' maneuver points (px), over the maneuver layer's dots.
SELECTED_MARK_PX = 12


def marker_px(style_px: float, n: int) -> float:
    """A markers-only layer's dot size (px) for ``n`` dots in view: the style's while
    they are few, smaller as they crowd (at overview scale 400 dots of 8 px buried a
    100 km route: h225 item 10)."""
    if n <= 150:
        return style_px
    if n <= 600:
        return max(min(style_px, 6.0), 2.0)
    return max(min(style_px, 4.0), 2.0)


#: Selection curve items made with the canvas (more are made when needed).
SELECTION_POOL = 12
#: Cache mode of a layer's curves.
CACHE = QtWidgets.QGraphicsItem.CacheMode.DeviceCoordinateCache
#: Qt's pixmap cache (KiB) that holds those pixmaps. Its default, 10 MiB, holds two
#: window-sized ARGB pixmaps: with more curves every paint evicted and stroked them all.
PIXMAP_CACHE_KIB = 256 * 1024
#: hold_paints: how often the hold's end is checked, and the longest hold (ms; a review
#: key's swap on ATD dataset1 took 130 ms at a load of 6 on 2 cores, over 400 at 8)
HOLD_CHECK_MS = 10
HOLD_MAX_MS = 1000

#: ``executor(job, done)``: run ``job()`` (pure, returns DrawData) somewhere and call
#: ``done(result)`` on the GUI thread.
LodExecutor = Callable[[Callable[[], DrawData], Callable[[DrawData], None]], None]


class LongitudeAxis(pg.AxisItem):
    """The bottom axis: major ticks at least a label's width apart. pyqtgraph puts 2.25
    or more labelled intervals on any width, so a narrow map (the before/after pair)
    printed "131.16131.18131.20" as one string."""

    GAP_PX = 10.0  # free space between two tick labels

    def tickSpacing(self, minVal: float, maxVal: float, size: float):  # noqa: N802, N803
        levels = super().tickSpacing(minVal, maxVal, size)
        dif = abs(maxVal - minVal)
        if not levels or size <= 0 or dif == 0 or self._tickSpacing is not None:
            return levels
        px = size / dif  # pixels per degree
        major = levels[0][0]
        metrics = QtGui.QFontMetricsF(self.style.get("tickFont") or self.font())

        def room(spacing: float) -> float:
            texts = self.tickStrings([minVal, maxVal, (minVal + maxVal) / 2], 1.0, spacing)
            return max(metrics.horizontalAdvance(t) for t in texts) + self.GAP_PX

        if major * px >= room(major):
            return levels
        while major * px < room(major) and major < dif:
            exp = math.floor(math.log10(major))
            m = round(major / 10**exp, 6)
            major = (2.0 if m < 2 else 5.0 if m < 5 else 10.0) * 10**exp
        m = round(major / 10 ** math.floor(math.log10(major)), 6)
        return [(major, 0.0), (major / (2.0 if m == 2 else 5.0), 0.0)]

    def tickStrings(self, values, scale, spacing):  # noqa: N802 - pyqtgraph's name
        """Longitudes as they are read: a track drawn across the antimeridian runs on
        past 180° (continuous), its labels wrap (180.2 -> -179.8; h181 D-map-3)."""
        return super().tickStrings([wrap_longitude(v) for v in values], scale, spacing)


def wrap_longitude(value: float) -> float:
    """``value`` in [-180, 180] (180 stays 180, 540 is 180, -180 stays -180)."""
    if -180.0 <= value <= 180.0:
        return value
    w = (value + 180.0) % 360.0 - 180.0
    return 180.0 if w == -180.0 and value > 0 else w


class MapCanvas(MapInteractMixin, pg.PlotWidget):
    """A pyqtgraph plot set up as a lon/lat chart with layers, selection, hover, picking."""

    cursorMoved = QtCore.Signal(float, float)  # lon, lat in degrees
    trackClicked = QtCore.Signal(str, str, str, bool)  # layer, sensor, batch, add to selection
    pointHovered = QtCore.Signal(object)  # dict (layer, sensor, batch, time, speed_kn) or None
    selectionShown = QtCore.Signal()  # show_selection drew a new selection (new colours)

    def __init__(self, parent=None) -> None:
        ink.setup()
        super().__init__(
            parent=parent, background="w", axisItems={"bottom": LongitudeAxis("bottom")}
        )
        if QtGui.QPixmapCache.cacheLimit() < PIXMAP_CACHE_KIB:
            QtGui.QPixmapCache.setCacheLimit(PIXMAP_CACHE_KIB)
        self.plot_item = self.getPlotItem()
        self.setLabel("bottom", "longitude", units="°")
        self.setLabel("left", "latitude", units="°")
        for side in ("left", "bottom"):  # degrees, never "m°" (near 0° E or 0° N)
            self.getAxis(side).enableAutoSIPrefix(False)
        self.showGrid(x=True, y=True, alpha=0.25)
        # Room for latitude labels from the start, never given back: an axis that widened
        # or narrowed with its labels would resize the view box, and every layer would be
        # decimated and stroked again. The room is measured in the axis' font (pyqtgraph's
        # tickTextWidth only counts when the text space is not expanded, and its measured
        # width starts at 30 px: labels like "56.025" took more, and the axis widened one
        # layout pass after the paint that measured them — a render grabbed before that
        # had the axis title over its tick labels).
        left = self.getAxis("left")
        left.textWidth = max(left.textWidth, self.tick_text_room(left))
        left.setStyle(autoReduceTextSpace=False)
        # Axes and grid replay their labels on every paint (~10 ms each); cached, a
        # repaint for a new layer or the selection copies them while the view stays.
        for side in ("left", "bottom"):
            self.getAxis(side).setCacheMode(CACHE)
        self.vb = self.plot_item.getViewBox()
        self.vb.setAspectLocked(True, ratio=1.0)
        # The view is set by fit() from the data, never by pyqtgraph's auto range.
        self.vb.disableAutoRange()
        self._items: dict[str, list[pg.PlotDataItem]] = {}
        self._data: dict[str, DrawData] = {}
        self._visible: dict[str, bool] = {}
        self._lat0 = 0.0
        self.lod_executor: LodExecutor | None = None
        self._lod_pending: set[str] = set()
        self.legend = SideLegend(offset=None, verSpacing=-4)
        self.plot_item.layout.addItem(self.legend, 2, 3)
        self.plot_item.layout.setAlignment(self.legend, QtCore.Qt.AlignmentFlag.AlignTop)
        self.plot_item.legend = None
        self.coastline = pg.PlotDataItem(pen=pg.mkPen("#8a8a8a", width=1), connect="finite")
        self.coastline.setZValue(-10)
        self.addItem(self.coastline)
        self._coast: DrawData | None = None
        self._coast_pending = False
        # The selection: a wide translucent halo under the tracks, and every selected
        # batch drawn on top in its own colour.
        self.selection = pg.PlotDataItem(
            pen=pg.mkPen(QtGui.QColor(255, 170, 0, 150), width=9), connect="finite"
        )
        self.selection.setZValue(-1)
        self.addItem(self.selection)
        self._selection_items: list[pg.PlotDataItem] = []
        # Reused curve items of the selection, made now (a first click would pay for them).
        self._selection_pool: list[pg.PlotDataItem] = []
        self._legend_wanted: list = []  # (item, legend text) to show on the next turn
        self._legend_timer = QtCore.QTimer(self)  # owned: never fires on a deleted canvas
        self._legend_timer.setSingleShot(True)
        self._legend_timer.setInterval(5)
        self._legend_timer.timeout.connect(self._sync_selection_legend)
        for _ in range(SELECTION_POOL):
            self._selection_pool.append(self._new_selection_item())
        self._selected = pd.DataFrame()
        self._selection_west = -180.0  # the band of the selection's layer
        self._selection_colors: dict[tuple[str, str], str] = {}  # (sensor, batch) -> colour
        self._context_opacity = 1.0  # of the layers' curves (< 1: muted behind a review)
        # The active layer's map layers (set_emphasis): on top, the others dimmed; None:
        # every layer as it is (a render, no window).
        self._emphasis: set[str] | None = None
        self._lift = True  # the emphasized layers drawn over the others too
        self._order: dict[str, int] = {}  # a session layer's place (set_layer_order)
        self._order_sep = "/"
        # The selected tracks' maneuver points: larger than the maneuver layer's dots,
        # yellow with a black rim, over everything but the hover.
        self.marks = pg.ScatterPlotItem(
            size=SELECTED_MARK_PX, pen=pg.mkPen("k", width=1.5), brush=pg.mkBrush("#ffd400")
        )
        self.marks.setZValue(60)
        self.addItem(self.marks)
        self.hover_label = pg.TextItem(
            color="k", fill=pg.mkBrush(255, 255, 255, 225), border=pg.mkPen("#777"), anchor=(0, 1)
        )
        self.hover_label.setZValue(100)
        self.hover_label.hide()
        self.addItem(self.hover_label, ignoreBounds=True)
        self.hover_dot = pg.ScatterPlotItem(size=9, pen=pg.mkPen("k", width=1.5), brush=None)
        self.hover_dot.setZValue(99)
        self.addItem(self.hover_dot, ignoreBounds=True)
        self.scale_bar = pg.ScaleBar(size=0.1, suffix="", brush=SCALE_BAR_COLOR)
        # pyqtgraph draws its label light grey (200, 200, 200: contrast 1.7 on white):
        # dark text on a light translucent box, readable over tracks and grid.
        self.scale_bar.text.setColor(SCALE_BAR_COLOR)
        self.scale_bar.text.fill = pg.mkBrush(255, 255, 255, 210)
        self.scale_bar.setParentItem(self.vb)
        self.scale_bar.anchor((1, 1), (1, 1), offset=(-20, -20))
        self._lod_timer = QtCore.QTimer(self)
        self._lod_timer.setSingleShot(True)
        self._lod_timer.setInterval(60)
        self._lod_timer.timeout.connect(self.refresh_lod)
        # hold_paints: the condition that ends a hold, its clock and the timer checking it
        self._hold_until = None
        self._hold_clock = QtCore.QElapsedTimer()
        self._hold_timer = QtCore.QTimer(self, interval=HOLD_CHECK_MS)
        self._hold_timer.timeout.connect(self._check_hold)
        self.vb.sigRangeChanged.connect(self._update_scale_bar)
        self.vb.sigRangeChanged.connect(lambda *_: self._lod_timer.start())
        self.vb.sigResized.connect(lambda *_: self._lod_timer.start())
        self.scene().sigMouseMoved.connect(self._mouse_moved)
        self.scene().sigMouseClicked.connect(self._mouse_clicked)
        menu = self.vb.menu
        menu.addSeparator()
        menu.addAction("Zoom to selection", self.zoom_to_selection)
        menu.addAction("Zoom to all", self.fit)

    # -- view ------------------------------------------------------------------------

    @staticmethod
    def tick_text_room(axis: pg.AxisItem, widest: str = WIDEST_LATITUDE) -> float:
        """Pixels the widest latitude label takes in ``axis``' tick font (the axis then
        grows by itself for a wider one)."""
        font = axis.style["tickFont"] or axis.font()
        return math.ceil(QtGui.QFontMetricsF(font).horizontalAdvance(widest)) + 2

    def close(self) -> bool:
        """Stop the deferred updates first: pyqtgraph's ``close`` deletes the plot's items
        (the legend among them) while this widget lives on, and a legend update still due
        would then reach a deleted legend (seen as a teardown error in a GUI test)."""
        self._legend_timer.stop()
        self._lod_timer.stop()
        self._legend_wanted = []
        return super().close()

    def _new_selection_item(self) -> pg.PlotDataItem:
        item = pg.PlotDataItem(connect="finite")
        item.setZValue(50)
        item.setVisible(False)
        self.addItem(item)
        return item

    def current_view(self) -> tuple[float, float, float, float]:
        """The view box range ``(x0, x1, y0, y1)`` in degrees."""
        (x0, x1), (y0, y1) = self.vb.viewRange()
        return (float(x0), float(x1), float(y0), float(y1))

    def plot_size_px(self) -> tuple[float, float]:
        """Width and height (logical pixels) of the plot area the view is mapped onto:
        fractional as the layout makes it, so that a sprite made for it is at the map's
        own scale (one made for the rounded width was off by up to half a pixel across
        it, and its lines a pixel beside the stroke's at some legend widths)."""
        r = self.vb.rect()
        return (max(float(r.width()), 1.0), max(float(r.height()), 1.0))

    def set_true_aspect(self, lat_deg: float) -> None:
        """Lock the aspect so one km is as long east-west as north-south at ``lat_deg``."""
        # pyqtgraph's ratio is x-scale over y-scale (pixels per unit): a degree of
        # longitude is cos(lat) times as long as a degree of latitude.
        self._lat0 = lat_deg
        self.vb.setAspectLocked(True, ratio=max(math.cos(math.radians(lat_deg)), 0.05))

    def set_bare(self, bare: bool) -> None:
        """Plot area only: no axes, grid, legend, scale bar or margins (for images)."""
        for side in ("left", "bottom"):
            self.plot_item.showAxis(side, not bare)
        self.showGrid(x=not bare, y=not bare, alpha=0.25)
        self.legend.bare = bare
        self.legend.updateSize()
        self.scale_bar.setVisible(not bare)
        m = 0 if bare else 1
        self.plot_item.layout.setContentsMargins(m, m, m, m)

    # -- layers ----------------------------------------------------------------------

    def set_coastline(self, lon: np.ndarray, lat: np.ndarray) -> None:
        """The background coastline (NaN-separated lines, degrees); decimated like layers."""
        geom = coastline_draw(np.asarray(lon), np.asarray(lat))
        self._coast = prepare_layer(geom, "coast", build_index=False)
        self.coastline.setData(self._coast.curves[0].lon, self._coast.curves[0].lat)

    def set_layer(
        self,
        name: str,
        points: pd.DataFrame,
        color: str,
        by_sensor: bool = False,
        symbols: bool = True,
        width: float = 1.5,
    ) -> None:
        """Prepare and draw a layer on the GUI thread (see :meth:`set_draw_data` for the
        worker way): its tracks NaN-separated, one curve per sensor with ``by_sensor``."""
        style = LayerStyle(width=width, symbol_size=3 if symbols else 0)
        data = prepare_layer(
            points, name, color, by_sensor=by_sensor, style=style, build_index=False
        )
        self.set_draw_data(data)

    def set_draw_data(self, data: DrawData, visible: bool | None = None) -> None:
        """Swap in a prepared layer (from :func:`~wakeline.app.map_draw.prepare_layer`).

        Replaces the layer's curves in place when their number is unchanged (visibility
        and pen kept), else rebuilds them. The level of detail follows on the next view
        change, or now when the view is known.
        """
        name = data.name
        items = self._items.get(name, [])
        old = self._data.get(name)
        # Colours or legend words changed (a layer coloured by track and back, as many
        # curves as before): items made anew, their pen, brush and legend entry with them.
        restyled = old is not None and [(c.color, c.label) for c in old.curves] != [
            (c.color, c.label) for c in data.curves
        ]
        if len(items) != len(data.curves) or restyled:
            was_visible = self._visible.get(name, True)
            self.remove_layer(name)
            items = []
            for curve in data.curves:
                kw = {}
                if data.style.symbol_size:
                    symbol = data.style.symbol if not data.style.width else "o"
                    # One pen and brush object each for good: the symbol atlas keys a
                    # style by their ids (a colour given as text made a new brush, and
                    # a new atlas entry, at every swap).
                    kw = {
                        "symbol": symbol,
                        "symbolSize": data.style.symbol_size,
                        "symbolPen": pg.mkPen(None),
                        "symbolBrush": pg.mkBrush(curve.color),
                    }
                pen = pg.mkPen(curve.color, width=data.style.width) if data.style.width else None
                item = LayerItem(pen=pen, connect="finite", **kw)
                if kw:
                    # The legend draws its sample with the scatter's style, which
                    # pyqtgraph sets only with symbols to draw (a curve zoomed to no
                    # vertex showed pyqtgraph's default, a large black-rimmed dot).
                    item.scatter.setSymbol(kw["symbol"], update=False)
                    item.scatter.setSize(kw["symbolSize"], update=False)
                    item.scatter.setPen(kw["symbolPen"], update=False)
                    item.scatter.setBrush(kw["symbolBrush"], update=False)
                # No re-plot on every view change (pyqtgraph's dynamic range limit would
                # rebuild the symbols of every curve at each pan and zoom step).
                item.setDynamicRangeLimit(None)
                # Painted into a pixmap once per data or view change: a repaint for the
                # selection, hover or another layer blits it instead of stroking again.
                item.curve.setCacheMode(CACHE)
                # Its symbols too: pyqtgraph paints a scatter in Python (~0.4 ms an item,
                # 200 single-track layers ~80 ms a repaint); cached, a repaint for
                # another layer, the hover or the selection blits them.
                item.scatter.setCacheMode(CACHE)
                item.setOpacity(self._opacity_of(name))
                item.setZValue(self._z_of(name, data.style))
                self.addItem(item)
                if curve.label:
                    self.legend.addItem(item, curve.label)
                items.append(item)
            self._items[name] = items
            self._visible[name] = was_visible
            self._bold_legend()  # entries made anew: bold again if the layer is active
        self._data[name] = data
        self._lod_pending.discard(name)  # a result for the old data is ignored on arrival
        if visible is not None:
            self._visible[name] = visible
        self._swap_curves(data)
        for item in items:
            item.setVisible(self._visible[name])
        self.legend.show_entries(items, self._visible[name])
        if data.px is None:
            if data.geometry.n_points > 50_000:
                self._lod_timer.start()
        elif self._made_for_another_view(data):
            # Decimated (and its sprites stroked) by a job for the view the map showed
            # when the job started: a review decision's points swapped in after the
            # Before/after map, a zoom or the next proposal moved the view kept the old
            # view's clipping (tracks beyond it not drawn) until another view change.
            self._lod_timer.start()

    def _made_for_another_view(self, data: DrawData) -> bool:
        """``data`` was decimated, or its sprites made, for a view or plot size other
        than the map's now."""
        view, size = self.current_view(), self.plot_size_px()
        return lod_is_stale(data, view, size) or sprite_is_stale(data, view, size)

    def _swap_curves(self, data: DrawData) -> None:
        for item, curve in zip(self._items.get(data.name, []), data.curves, strict=False):
            self._swap_curve(item, curve, data)
            # Qt can keep a device-coordinate cache at its old place when new data change
            # the bounds of a curve larger than the view (seen after a zoom, a pan or a
            # resize): drop the cached pixmap with the data it showed.
            for part in (item.curve, item.scatter):
                part.setCacheMode(QtWidgets.QGraphicsItem.CacheMode.NoCache)
                part.setCacheMode(CACHE)

    def _swap_curve(self, item: pg.PlotDataItem, curve, data: DrawData) -> None:
        """Swap one prepared curve into its item (line or markers).

        One ``setData`` with the new arrays and the new style together: pyqtgraph's
        ``setSymbol`` and ``setPen`` each redraw the item from its *old* arrays (symbols
        turned on over the old 37 k-vertex curve blocked the GUI thread for 720 ms).
        """
        few = curve.n_vertices <= SYMBOLS_MAX
        if data.style.symbol_size and not data.style.width:
            # Markers only (maneuver points): symbols while few, else small 1-px
            # crosses drawn as one path (pyqtgraph builds symbols point by point).
            if few:
                size = marker_px(data.style.symbol_size, curve.n_vertices)
                item.setData(
                    curve.lon,
                    curve.lat,
                    connect="finite",
                    symbol=data.style.symbol,
                    symbolSize=size,
                    pen=None,
                )
            else:
                xs, ys = self._crosses(curve, data.style.symbol_size)
                pen = pg.mkPen(curve.color, width=1)
                item.setData(xs, ys, connect="pairs", symbol=None, pen=pen)
            item.curve.sprite = None if few else curve.sprite
            item.curve.remaking = self._remaking
            return
        style = {}
        if data.style.symbol_size and data.style.width:
            # Symbols on a line only where they can be told apart (each costs every
            # paint a pixmap copy).
            style["symbol"] = "o" if few else None
        if data.style.width:
            # A wide pen costs Qt's raster engine 5x a 1-px one (120k vertices: 159 ms
            # at 1.3 px against 28 ms at 1 px): wide lines only where few vertices.
            width = data.style.width if few else 1.0
            if item.opts["pen"] is None or item.opts["pen"].widthF() != width:
                style["pen"] = pg.mkPen(curve.color, width=width)
        item.setData(curve.lon, curve.lat, connect="finite", **style)
        if curve.path is not None:  # built in a worker (map_paths): paint only strokes
            item.curve.path = curve.path
        # Stroked in a worker for this view: the paint copies it while it fits (a long
        # curve's, scaled, while the worker makes the next: map_paths.STAND_IN_VERTICES).
        item.curve.sprite = curve.sprite
        item.curve.remaking = self._remaking

    def _crosses(self, curve, size_px: float) -> tuple[np.ndarray, np.ndarray]:
        """A small cross (two segments, ``size_px`` wide) at every finite vertex."""
        return crosses(curve.lon, curve.lat, self.vb.viewPixelSize(), size_px)

    def refresh_lod(self, names: list[str] | None = None) -> None:
        """Redo the level of detail of layers (default all) whose decimation is stale."""
        view, size = self.current_view(), self.plot_size_px()
        coast = self._coast
        if coast is not None and not self._coast_pending and lod_is_stale(coast, view, size):
            if self.lod_executor is None:
                self._apply_coast(relod(coast, view, size))
            else:  # the full 1:50m coastline is decimated in the worker too
                self._coast_pending = True
                self.lod_executor(lambda c=coast: relod(c, view, size), self._apply_coast)
        for name in list(names or self._data):
            data = self._data.get(name)
            if data is None or name in self._lod_pending:
                continue
            # Sprites are redone for a moved or resized view of the shown layers only (a
            # hidden layer's are redone when it is shown again).
            if not lod_is_stale(data, view, size) and not (
                self.lod_executor is not None
                and self._visible.get(name, True)
                and sprite_is_stale(data, view, size)
            ):
                continue
            if self.lod_executor is None:
                self._apply_lod(relod(data, view, size))
            else:
                self._lod_pending.add(name)
                self.lod_executor(
                    lambda d=data: with_paths(relod(d, view, size)),
                    lambda result, name=name: self._apply_lod(result, name),
                )

    def _apply_coast(self, data: DrawData | None) -> None:
        if data is None:  # the job failed: keep the coastline drawn as it is
            self._coast_pending = False
            return
        self._coast, self._coast_pending = data, False
        self.coastline.setData(data.curves[0].lon, data.curves[0].lat)
        if self.lod_executor is not None:
            self._lod_timer.start()  # the view may have moved on while the job ran

    def _apply_lod(self, data: DrawData | None, name: str | None = None) -> None:
        """Swap in a redone level of detail; ``data`` None: the job failed (the layer keeps
        its drawing and may be redone at the next view change)."""
        if data is None:
            self._lod_pending.discard(name)
            return
        self._lod_pending.discard(data.name)
        current = self._data.get(data.name)
        if current is None or current.geometry is not data.geometry:
            return  # the layer was replaced or removed meanwhile
        self._data[data.name] = data
        self._swap_curves(data)
        if self.lod_executor is not None:
            self._lod_timer.start()  # the view may have moved on while the job ran

    def remove_layer(self, name: str) -> None:
        for item in self._items.pop(name, []):
            self.removeItem(item)
            self.legend.removeItem(item)
        self._data.pop(name, None)
        self._visible.pop(name, None)
        self._lod_pending.discard(name)

    def mute_layers(self, opacity: float = 1.0) -> None:
        """Draw every layer's curves at ``opacity`` (1: as they are; less: muted, the
        context behind the curves of a proposal under review), layers added later too."""
        self._context_opacity = float(opacity)
        self._apply_emphasis()

    def set_emphasis(self, names: list[str] | None, lift: bool = True) -> None:
        """Map layers ``names`` (the active layer's) drawn on top (``lift``; else in
        their place of the layer order) at full opacity and the others dimmed to
        :data:`DIM_OPACITY` (None: every layer as it is), layers added later too:
        switching the active layer changes the picture (h225 item 3)."""
        self._emphasis = None if names is None else set(names)
        self._lift = bool(lift)
        self._apply_emphasis()

    def set_layer_order(self, ids: list[str], sep: str = "/") -> None:
        """The layers' stacking: layer ``ids[k]`` (and its parts, ``<id><sep><part>``)
        over ``ids[:k]`` among items of one kind of drawing (:data:`ORDER_Z_SPAN`); a
        map layer not named in them stays under the ordered ones."""
        self._order = {lid: k + 1 for k, lid in enumerate(ids)}
        self._order_sep = sep
        self._apply_emphasis()

    def _order_z(self, name: str) -> float:
        rank = self._order.get(name)
        if rank is None:
            rank = self._order.get(name.partition(self._order_sep)[0], 0)
        return ORDER_Z_SPAN * rank / (len(self._order) + 1)

    def _opacity_of(self, name: str) -> float:
        dim = self._emphasis is not None and name not in self._emphasis
        return self._context_opacity * (DIM_OPACITY if dim else 1.0)

    def _z_of(self, name: str, style: LayerStyle | None) -> float:
        """A layer drawn under the tracks on purpose (z < 0: a bearing file's lines)
        stays under them when active. A step's marks (markers only, drawn over the
        tracks on purpose: z > 0, the maneuvers' dots, the removed points' crosses)
        stay over the active layer's lines: lifted by :data:`ACTIVE_Z` always, and once
        more when active (a compressed layer made active hid the maneuver marks). The
        layer order adds less than a unit (:data:`ORDER_Z_SPAN`); the active layer is
        lifted only while :meth:`set_emphasis` was asked to (View ▸ Keep the active layer
        on top)."""
        z = style.z if style is not None else 0.0
        lift = self._lift and self._emphasis is not None and name in self._emphasis and z >= 0
        marks = style is not None and z > 0 and style.width == 0 and not style.plots
        order = self._order_z(name) if self._order else 0.0
        return z + order + (ACTIVE_Z if lift else 0.0) + (ACTIVE_Z if marks else 0.0)

    def _apply_emphasis(self) -> None:
        for name, items in self._items.items():
            data = self._data.get(name)
            z = self._z_of(name, data.style if data is not None else None)
            for item in items:
                item.setOpacity(self._opacity_of(name))
                item.setZValue(z)
        self._bold_legend()

    def _bold_legend(self) -> None:
        """The emphasized (active) layer's legend entries in bold, the others plain."""
        names = self._emphasis or set()
        self.legend.set_bold([i for n in names for i in self._items.get(n, [])])

    def set_visible(self, name: str, visible: bool) -> None:
        """Show or hide layer ``name``'s curves and their legend entries."""
        for item in self._items.get(name, []):
            item.setVisible(visible)
        self.legend.show_entries(self._items.get(name, []), visible)
        if name in self._visible:
            self._visible[name] = visible
        if visible and self.lod_executor is not None:
            self._lod_timer.start()  # its sprites may be for a view left while hidden

    def hold_paints(self, until) -> None:
        """Paint the map once, when ``until()`` is true (checked every HOLD_CHECK_MS; at
        most HOLD_MAX_MS later), not at each step of a change made over several
        event-loop turns: a review key's layer swapped in, its level of detail and the
        proposal drawn again painted the map about 8 times per key (ATD dataset1)."""
        if self._hold_until is None:
            self._hold_clock.start()
            self.viewport().setUpdatesEnabled(False)
            self._hold_timer.start()
        self._hold_until = until

    @property
    def holding_paints(self) -> bool:
        return self._hold_until is not None

    def release_paints(self) -> None:
        """End a hold now: the map paints what it holds."""
        if self._hold_until is None:
            return
        self._hold_until = None
        self._hold_timer.stop()
        self.viewport().setUpdatesEnabled(True)
        self.viewport().update()

    def _check_hold(self) -> None:
        if self._hold_until is None:
            self._hold_timer.stop()
        elif self._hold_clock.elapsed() >= HOLD_MAX_MS or self._hold_until():
            self.release_paints()

    def _remaking(self) -> bool:
        """A new level of detail or sprite is on its way (a job is out, or the timer
        that asks for one runs), so a stale sprite may stand in meanwhile."""
        return self.lod_executor is not None and (
            bool(self._lod_pending) or self._lod_timer.isActive()
        )

    @property
    def lod_busy(self) -> bool:
        """Level-of-detail or sprite work is asked for or running (a view change pending,
        a worker job not yet back)."""
        return bool(self._lod_pending) or self._coast_pending or self._lod_timer.isActive()

    def layer_names(self) -> list[str]:
        return list(self._items)

    def layer_items(self, name: str) -> list[pg.PlotDataItem]:
        return self._items[name]

    def relabel_layer(self, name: str, rename) -> None:
        """Layer ``name``'s legend entries and labels renamed by ``rename`` (a label → the
        new one: the words of a language switch), its data kept as drawn."""
        for item in self._items.get(name, []):
            self.legend.rename(item, rename)
        data = self._data.get(name)
        if data is not None:
            geometry = dataclasses.replace(
                data.geometry, labels=tuple(rename(t) for t in data.geometry.labels)
            )
            curves = tuple(dataclasses.replace(c, label=rename(c.label)) for c in data.curves)
            self._data[name] = dataclasses.replace(data, geometry=geometry, curves=curves)

    def draw_data(self, name: str) -> DrawData:
        """The prepared data of layer ``name`` as drawn now."""
        return self._data[name]

    def visible_draw_data(self) -> list[DrawData]:
        return [d for n, d in self._data.items() if self._visible.get(n)]

    def n_items(self) -> int:
        return sum(len(v) for v in self._items.values())

    def n_vertices(self) -> int:
        """Vertices in the drawn paths of the visible layers (after level of detail)."""
        return sum(d.n_vertices for d in self.visible_draw_data())

    def frame(self) -> None:
        """Show where the points of the visible layers are, with a margin: a first view
        (:mod:`wakeline.app.map_frame`; a few far-flung points are left out, :meth:`fit`
        shows them)."""
        self.show_range(framed_range([d.geometry.sketch() for d in self.visible_draw_data()]))

    def fit(self, points: pd.DataFrame | None = None, lon_west: float | None = None) -> None:
        """Show ``points`` (default: every point of every visible layer) with a margin:
        "Fit to data", "Zoom to all"; ``lon_west``: the band ``points`` are drawn in."""
        if points is not None:
            lon, lat = nan_separated(points, lon_west)
            boxes = [(np.nanmin(lon), np.nanmin(lat), np.nanmax(lon), np.nanmax(lat))]
        else:
            boxes = [d.geometry.bounds() for d in self.visible_draw_data()]
        self.show_range(padded_range(boxes))

    def show_range(self, target: tuple[float, float, float, float] | None) -> None:
        """Ask for the range ``(x0, x1, y0, y1)`` (degrees; the aspect lock widens one
        axis) and redo the level of detail of layers whose decimation no longer fits."""
        if target is None:
            return
        x0, x1, y0, y1 = target
        self.vb.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0)
        self.refresh_lod()

    def set_box_zoom(self, on: bool) -> None:
        self.vb.setMouseMode(pg.ViewBox.RectMode if on else pg.ViewBox.PanMode)

    def render_png(self, path: str) -> bool:
        return self.grab().save(path)


def sprite_is_stale(
    data: DrawData, view: tuple[float, float, float, float], size_px: tuple[int, int]
) -> bool:
    """True when a curve of ``data`` has a sprite that no longer shows ``view`` at
    ``size_px`` (panned or resized): a worker makes new ones, strokes fill in meanwhile."""
    sprites = [c.sprite for c in data.curves if c.sprite is not None]
    if data.view is None or not sprites:
        return False
    sprite = sprites[0]
    made = sprite.size or (sprite.image.width(), sprite.image.height())
    tol = SCALE_TOLERANCE_PX  # as the paint copies it (map_paths.image_corner)
    if abs(made[0] - size_px[0]) > tol or abs(made[1] - size_px[1]) > tol:
        return True  # the plot area was resized
    x0, x1, y0, y1 = view
    sx0, sx1, sy0, sy1 = sprite.view
    tx, ty = (sx1 - sx0) / max(size_px[0], 1), (sy1 - sy0) / max(size_px[1], 1)
    zoomed = abs((x1 - x0) - (sx1 - sx0)) > tol * tx or abs((y1 - y0) - (sy1 - sy0)) > tol * ty
    return zoomed or not sprite.covers(view)


def color_icon(color: str) -> QtGui.QIcon:
    """A layer's colour swatch with a dark rim, the same pixmap in every mode: a
    selected row's highlight tinted the swatch away (h225 item 3)."""
    pix = QtGui.QPixmap(14, 14)
    pix.fill(QtGui.QColor("#202020"))
    painter = QtGui.QPainter(pix)
    try:
        painter.fillRect(1, 1, 12, 12, QtGui.QColor(color))
    finally:
        painter.end()
    icon = QtGui.QIcon()
    for mode in (QtGui.QIcon.Mode.Normal, QtGui.QIcon.Mode.Selected, QtGui.QIcon.Mode.Active):
        icon.addPixmap(pix, mode)
    return icon

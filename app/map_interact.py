"""The map's interaction: selection (each batch in its own colour), zoom to selection,
hover (sensor, batch, time, speed of the nearest point), picking and the scale bar.

Mixed into :class:`~wakeline.app.map_canvas.MapCanvas` (which owns the items and signals).
"""

import math

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtCore

from wakeline.app.map_colors import apart_from
from wakeline.app.map_draw import named_tracks
from wakeline.app.map_legend import short_label
from wakeline.app.map_selection import SELECTION_PALETTE, selection_curves
from wakeline.core import geo

KM_PER_DEG = 111.195
#: A selected track whose box is under this many pixels both ways is zoomed to.
TINY_PX = 10.0
M_PER_NM = 1852.0


def measure(lon0: float, lat0: float, lon1: float, lat1: float) -> dict:
    """Range (great circle, m and nm) and initial bearing (° true) from point 0 to point
    1, and their text as the map shows it."""
    lon1_band = lon0 + float(geo.wrap180(lon1 - lon0))  # the short way across 180°
    range_m = float(geo.haversine_m(lon0, lat0, lon1_band, lat1))
    bearing = float(geo.initial_bearing_deg(lon0, lat0, lon1_band, lat1))
    nm = range_m / M_PER_NM
    dist = f"{range_m:,.0f} m" if range_m < 10_000 else f"{range_m / 1000:,.2f} km"
    text = f"{dist} · {nm:,.2f} nm · {bearing:05.1f}° T"
    return {"range_m": range_m, "range_nm": nm, "bearing_deg": bearing, "text": text}


NICE_KM = (0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000)


class MapInteractMixin:
    """Selection, hover, picking and scale bar of the map canvas."""

    def show_selection(
        self,
        points: pd.DataFrame,
        marks: pd.DataFrame | None = None,
        gaps: bool = True,
        lon_west: float = -180.0,
    ) -> None:
        """Highlight ``points`` (the selected tracks, each batch in its own colour) and
        optional marked points; ``gaps``: break the lines at gaps, as their layer is drawn;
        ``lon_west``: the band their layer is drawn in (its geometry's ``lon_west``).

        The curve items and their legend lines are kept and reused from one selection to
        the next (making pyqtgraph items and legend labels is the slow part of a click).
        """
        self._selected = points
        self._selection_west = lon_west
        curves: tuple = ()
        self._selection_colors = {}
        if len(points) == 0:
            self.selection.setData([], [])
        else:
            shown = self.visible_draw_data()
            used = {c.color for d in shown for c in d.curves}
            own = {}  # tracks a layer coloured by track names already: one legend line each
            for d in shown:
                own.update(named_tracks(d.geometry))
            halo, curves, self._selection_colors = selection_curves(
                points, used, gaps, lon_west, own
            )
            self.selection.setData(halo.lon, halo.lat, connect="finite")
        pool = self._selection_pool
        while len(pool) < len(curves):
            pool.append(self._new_selection_item())
        wanted = []
        for k, item in enumerate(pool):
            curve = curves[k] if k < len(curves) else None
            if curve is None:
                item.setData([], [])
                item.setVisible(False)
                wanted.append((item, ""))
                continue
            item.setPen(pg.mkPen(curve.color, width=2.5))
            item.setData(curve.lon, curve.lat, connect="finite")
            item.setVisible(True)
            wanted.append((item, curve.label))
        self._selection_items = pool[: len(curves)]
        # The legend lines follow on a later event-loop turn (a new legend label costs
        # pyqtgraph ~9 ms of text layout; ten of them would double the click).
        self._legend_wanted = wanted
        self._legend_timer.start()
        if marks is not None and len(marks):
            lon = marks["lon"].to_numpy(dtype="float64")
            if lon_west != -180.0:
                lon = geo.into_band(lon, lon_west)
            self.marks.setData(lon, marks["lat"].to_numpy())
        else:
            self.marks.setData([], [])
        self.selectionShown.emit()

    def _sync_selection_legend(self) -> None:
        """Legend lines for the selection's curves as :meth:`show_selection` left them."""
        wanted, self._legend_wanted = self._legend_wanted, []
        labels = {id(sample.item): label for sample, label in self.legend.items}
        for item, text in wanted:
            label = labels.get(id(item))
            if not text and label is not None:
                self.legend.removeItem(item)
            elif text and label is None:
                self.legend.addItem(item, text)
            elif text and label.text != short_label(text):
                label.setText(short_label(text))
        for sample, _label in self.legend.items:
            if sample.item in self._selection_items:
                sample.update()  # its line takes the item's new pen

    def selected_points(self) -> pd.DataFrame:
        """The points last passed to :meth:`show_selection`."""
        return self._selected

    def selection_band(self) -> float:
        """The band (west edge, -180 or 0) the selection is drawn in: its layer's."""
        return self._selection_west

    def selection_items(self) -> list[pg.PlotDataItem]:
        """The per-batch coloured curves of the selection."""
        return list(self._selection_items)

    def selection_color(self, sensor: str, batch: str) -> str | None:
        """The colour the selection (and its legend line) gives the track ``sensor``,
        ``batch``; None when it is not selected."""
        return self._selection_colors.get((str(sensor), str(batch)))

    def free_colors(self, taken: set[str] | frozenset[str] = frozenset()) -> list[str]:
        """Colours of the selection's palette that no visible layer, no selected track
        and nothing in ``taken`` uses (for other curves named in the legend)."""
        used = {c.color for d in self.visible_draw_data() for c in d.curves}
        used |= set(self._selection_colors.values()) | set(taken)
        return list(apart_from(SELECTION_PALETTE, used))

    def zoom_to_selection(self) -> bool:
        """Fit the view to the selected tracks; False when nothing is selected."""
        if len(self._selected) == 0:
            return False
        self.fit(self._selected, self._selection_west)
        return True

    def bring_selection_into_view(self, speck_px: float = TINY_PX) -> str:
        """Make the selection visible without a jump: nothing when its box is on screen
        and at least ``speck_px`` wide or high; zoom to it (:meth:`zoom_to_selection`)
        when it would be a speck under ``speck_px``; else pan the view (same scale) to
        centre it. Returns what was done: "", "pan" or "zoom" (h225 item 5)."""
        if len(self._selected) == 0:
            return ""
        from wakeline.app.map_draw import nan_separated

        lon, lat = nan_separated(self._selected, self._selection_west)
        if not len(lon) or not np.isfinite(lon).any():
            return ""
        bx0, bx1, by0, by1 = np.nanmin(lon), np.nanmax(lon), np.nanmin(lat), np.nanmax(lat)
        (x0, x1), (y0, y1) = self.vb.viewRange()
        px_x, px_y = self.vb.viewPixelSize()
        speck = (bx1 - bx0) / px_x < speck_px and (by1 - by0) / px_y < speck_px
        if speck:
            self.zoom_to_selection()
            return "zoom"
        inside = bx0 >= x0 and bx1 <= x1 and by0 >= y0 and by1 <= y1
        if inside:
            return ""
        if bx0 < x1 and bx1 > x0 and by0 < y1 and by1 > y0 and (bx1 - bx0) > (x1 - x0):
            return ""  # wider than the view and partly on it: panning would not show more
        dx = (bx0 + bx1) / 2 - (x0 + x1) / 2
        dy = (by0 + by1) / 2 - (y0 + y1) / 2
        self.vb.translateBy(x=dx, y=dy)
        self.refresh_lod()
        return "pan"

    # -- measure (h225 item 17) ---------------------------------------------------------

    def set_measure(self, on: bool) -> None:
        """The measuring mode: two clicks on the map give the range (m, nm) and bearing
        (° true) from the first to the second, with a line between them."""
        self._measuring = bool(on)
        self._measure_from = None
        if on:
            self.vb.setMouseMode(pg.ViewBox.PanMode)
        self._measure_items()
        if not on:
            self._measure_line.setData([], [])
            self._measure_label.hide()

    def is_measuring(self) -> bool:
        return bool(getattr(self, "_measuring", False))

    def _measure_items(self):
        if getattr(self, "_measure_line", None) is None:
            self._measure_line = pg.PlotDataItem(
                pen=pg.mkPen("#d62728", width=2, style=QtCore.Qt.PenStyle.DashLine),
                symbol="+",
                symbolSize=12,
                symbolPen=pg.mkPen("#d62728", width=2),
            )
            self._measure_line.setZValue(110)
            self.addItem(self._measure_line, ignoreBounds=True)
            self._measure_label = pg.TextItem(
                color="k",
                fill=pg.mkBrush(255, 255, 255, 230),
                border=pg.mkPen("#d62728"),
                anchor=(0, 1),
            )
            self._measure_label.setZValue(111)
            self._measure_label.hide()
            self.addItem(self._measure_label, ignoreBounds=True)
        return self._measure_line, self._measure_label

    def measure_click(self, lon: float, lat: float) -> dict | None:
        """One click of the measuring mode at ``lon, lat`` (degrees): the first sets the
        start, the second gives the result (a dict: range_m, range_nm, bearing_deg and
        the shown text; the line and label stay until the next click or Esc)."""
        line, label = self._measure_items()
        if getattr(self, "_measure_from", None) is None:
            self._measure_from = (lon, lat)
            line.setData([lon], [lat])
            label.hide()
            self.measure_result = None
            return None
        lon0, lat0 = self._measure_from
        self._measure_from = None
        result = measure(lon0, lat0, lon, lat)
        line.setData([lon0, lon], [lat0, lat])
        label.setText(result["text"])
        label.setPos(lon, lat)
        label.show()
        self.measure_result = result
        callback = getattr(self, "measured", None)
        if callback is not None:
            callback(result["text"])
        return result

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
        if self.vb.sceneBoundingRect().contains(pos):
            p = self.vb.mapSceneToView(pos)
            self.cursorMoved.emit(p.x(), p.y())
            self.hover(p.x(), p.y())
        else:
            self.hover(math.nan, math.nan)

    def _mouse_clicked(self, event) -> None:
        if event.button() != QtCore.Qt.MouseButton.LeftButton or event.double():
            return
        p = self.vb.mapSceneToView(event.scenePos())
        if self.is_measuring():
            self.measure_click(p.x(), p.y())
            return
        add = bool(event.modifiers() & QtCore.Qt.KeyboardModifier.ControlModifier)
        self.pick(p.x(), p.y(), add)

    def nearest(self, lon: float, lat: float, pixels: float = 8.0) -> dict | None:
        """The visible track point nearest ``lon, lat`` within ``pixels`` on screen:
        layer, sensor, batch, time (text), time_s, speed_kn, lon, lat; None if none."""
        if not (math.isfinite(lon) and math.isfinite(lat)):
            return None
        px_x, px_y = self.vb.viewPixelSize()
        best = None
        # a removed point (an overlay with notes) before the source point it lies on
        layers = sorted(self._data.items(), key=lambda kv: kv[1].geometry.point_note is None)
        for name, data in layers:
            geom = data.geometry
            if not self._visible.get(name) or geom.n_points == 0:
                continue
            _, i = geom.nearest(lon, lat)
            d_px = math.hypot((geom.lon[i] - lon) / px_x, (geom.lat[i] - lat) / px_y)
            if d_px <= pixels and (best is None or d_px < best[0]):
                best = (d_px, name, i)
        if best is None:
            return None
        info = self._data[best[1]].geometry.describe(best[2])
        info["layer"] = best[1]
        return info

    def hover(self, lon: float, lat: float) -> dict | None:
        """Show the label of the point under ``lon, lat`` (hidden when none)."""
        info = self.nearest(lon, lat)
        if info is None:
            self.hover_label.hide()
            self.hover_dot.setData([], [])
        else:
            speed = info["speed_kn"]
            if "note" in info:  # a point the clean step removed: its rule and reason
                self.hover_label.setText(
                    f"{info['note']}\n{info['sensor']} · batch {info['batch']}\n{info['time']}"
                )
            else:
                self.hover_label.setText(
                    f"{info['sensor']} · batch {info['batch']}\n{info['time']}\n"
                    + (f"{speed:.1f} kn" if math.isfinite(speed) else "speed —")
                )
            self.hover_label.setPos(info["lon"], info["lat"])
            self.hover_label.show()
            self.hover_dot.setData([info["lon"]], [info["lat"]])
        self.pointHovered.emit(info)
        return info

    def pick(self, lon: float, lat: float, add: bool = False, pixels: float = 8.0) -> bool:
        """Emit ``trackClicked`` for the nearest visible track point within ``pixels``."""
        info = self.nearest(lon, lat, pixels)
        if info is None:
            return False
        self.trackClicked.emit(info["layer"], info["sensor"], info["batch"], add)
        return True

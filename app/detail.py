"""Detail views: the selected track's maneuver factor and compression; bearing-only data
with the detector's z statistic (GLR or AUC, as set) and its threshold band."""

from collections.abc import Callable

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtWidgets

from wakeline.app import ink
from wakeline.app.map_draw import unwrap_tracks
from wakeline.core import geo
from wakeline.core.bearing import BearingParams, auc_statistic
from wakeline.core.schema import time_seconds


def sequence_curves(
    bearings: pd.DataFrame,
    params: BearingParams,
    batch: str | None = None,
    statistic: pd.DataFrame | None = None,
) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]]:
    """The Detail panel's curves of every bearing sequence (or of ``batch`` only), pure
    and for a worker: per batch (time since its start in min, unwrapped bearing in °,
    the tested boundaries' times in min, their z, its start in s since 1970).
    ``statistic``: the detector's own (``batch, boundary_s, z``, from
    :func:`~wakeline.core.bearing.detect_with_statistic` with ``params``), taken instead
    of computing z again."""
    out = {}
    if bearings.empty:
        return out
    key = bearings["batch"].astype(str)
    rows = bearings if batch is None else bearings[key == batch]
    given = {}
    if statistic is not None:
        given = {
            str(name): (s["boundary_s"].to_numpy(dtype="float64"), s["z"].to_numpy("float64"))
            for name, s in statistic.groupby(statistic["batch"].astype(str), sort=False)
        }
    for name, g in rows.groupby(key, sort=True):  # a step per sequence, vectorized within
        g = g.sort_values("time", kind="stable")
        t = time_seconds(g["time"])
        b = g["bearing"].to_numpy(dtype="float64")
        if statistic is not None:  # a sequence with no tested boundary has no row
            bt, z = given.get(str(name), (np.zeros(0), np.zeros(0)))
        else:
            obs = [
                g[c].to_numpy(dtype="float64") if c in g.columns else None
                for c in ("obs_lon", "obs_lat")
            ]
            bt, z = auc_statistic(t, b, params, *obs)
        t0 = float(t[0])
        curve = np.degrees(np.unwrap(np.radians(b)))
        out[str(name)] = ((t - t0) / 60.0, curve, (bt - t0) / 60.0, z, t0)
    return out


def drawn_track_lon(track: pd.DataFrame, west: float | None = None) -> np.ndarray:
    """One track's longitudes as the map draws them: continuous across 180° and in the
    band ``west`` (None: the track's own) — :func:`~wakeline.app.map_draw.unwrap_tracks`;
    raw, a track across 180° was a line across the whole world."""
    lon = track["lon"].to_numpy(dtype="float64")
    if west is None:
        west = geo.lon_band_west(lon)
    return unwrap_tracks(lon, np.zeros(1, dtype="int64"), np.array([len(lon)]), west)


#: A time step this many times the track's median step breaks the δ curve.
GAP_STEPS = 10.0


def gaps_broken(minutes: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A curve's x (minutes) and y with a NaN inserted in every gap longer than
    :data:`GAP_STEPS` median steps (at least 1 min), drawn with ``connect="finite"``: a
    line across hours without fixes (a ship at rest, cleaned away) is no value of δ; the
    track's ends, where δ is undefined (NaN), are left out rather than drawn at 0."""
    x = np.asarray(minutes, dtype="float64")
    y = np.asarray(values, dtype="float64")
    if len(x) < 3:
        return x, y
    step = np.diff(x)
    limit = max(GAP_STEPS * float(np.median(step)), 1.0)
    cut = np.flatnonzero(step > limit) + 1
    return np.insert(x, cut, np.nan), np.insert(y, cut, np.nan)


#: A plot's title (pyqtgraph's default) and a reason's, shown instead of a figure.
TITLE_PT, REASON_PT = "11pt", "9pt"


class DetailPanel(QtWidgets.QTabWidget):
    """Plots for one selected track."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        ink.setup()
        self.factor_plot = pg.PlotWidget(background="w")
        self.factor_plot.getAxis("bottom").enableAutoSIPrefix(False)  # no "kmin"
        self.factor_plot.getAxis("left").enableAutoSIPrefix(False)  # no "m°"
        self.factor_curve = self.factor_plot.plot(pen=pg.mkPen("#1f77b4", width=1.5))
        self.factor_marks = pg.ScatterPlotItem(size=9, brush=pg.mkBrush("#d62728"), pen=None)
        self.factor_plot.addItem(self.factor_marks)
        self.threshold = pg.InfiniteLine(
            angle=0, pen=pg.mkPen("#555", style=pg.QtCore.Qt.PenStyle.DashLine)
        )
        self.factor_plot.addItem(self.threshold)
        self.comp_plot = pg.PlotWidget(background="w")
        for side in ("left", "bottom"):  # no "m°" near 0° E or 0° N
            self.comp_plot.getAxis(side).enableAutoSIPrefix(False)
        self.comp_plot.getPlotItem().getViewBox().setAspectLocked(True)
        self.comp_orig = self.comp_plot.plot(
            pen=pg.mkPen("#9a9a9a", width=1),
            symbol="o",
            symbolSize=3,
            symbolBrush="#9a9a9a",
            symbolPen=None,
        )
        self.comp_kept = self.comp_plot.plot(
            pen=pg.mkPen("#d62728", width=2), symbol="o", symbolSize=7, symbolBrush="#d62728"
        )
        self.addTab(self.factor_plot, "δ")
        self.addTab(self.comp_plot, "Compression")
        # Bearing-only: bearing over time above the detector's z statistic with its ±z band.
        self.bearing_box = QtWidgets.QWidget()
        self.bearing_batch = QtWidgets.QComboBox()
        self.bearing_batch.currentTextChanged.connect(self._draw_bearing)
        self.bearing_plots = pg.GraphicsLayoutWidget()
        self.bearing_plots.setBackground("w")
        self.b_plot = self.bearing_plots.addPlot(row=0, col=0)
        self.z_plot = self.bearing_plots.addPlot(row=1, col=0)
        self.z_plot.setXLink(self.b_plot)
        self.z_plot.getAxis("bottom").enableAutoSIPrefix(False)
        self.b_curve = self.b_plot.plot(
            pen=None, symbol="o", symbolSize=3, symbolBrush="#1f77b4", symbolPen=None
        )
        self.z_curve = self.z_plot.plot(pen=pg.mkPen("#1f77b4", width=1.2))
        self.z_band = pg.LinearRegionItem(
            orientation="horizontal", movable=False, brush=(0, 0, 0, 25)
        )
        self.z_plot.addItem(self.z_band)
        self.detect_lines: list = []
        lay = QtWidgets.QVBoxLayout(self.bearing_box)
        lay.setContentsMargins(0, 0, 0, 0)
        lay.addWidget(self.bearing_batch)
        lay.addWidget(self.bearing_plots)
        self.addTab(self.bearing_box, "Bearing")
        self.setTabVisible(2, False)  # shown with a bearing layer (show_bearings)
        self._bearings = pd.DataFrame()
        self._detections = pd.DataFrame()
        self._bparams = BearingParams()
        self._curves: dict = {}
        self.message = ""
        #: Each plot's title as made (a plot, and how to write its text): the language
        #: menu writes them again at once, not at the next selection.
        self._titles: dict[str, tuple[object, Callable[[], str]]] = {}
        self.retranslate()

    def retranslate(self) -> None:
        """Tab titles and axis labels in the current language."""
        self.setTabText(0, self.tr("Maneuver factor"))
        # one word on the tab, the whole title in its tooltip: the three tabs' titles
        # did not fit the dock at the window's default size ("Bearing-", operator test
        # 7, D16)
        self.setTabText(1, self.tr("Compression"))
        self.setTabToolTip(1, self.tr("Compressed over original"))
        # not "Bearing-only": the dock beside this one has that name (h225 item 16)
        self.setTabText(2, self.tr("Bearing over time"))
        self.setTabToolTip(2, self.tr("The bearing sequence and the detector's z statistic"))
        minutes = self.tr("min")
        self.factor_plot.setLabel("bottom", self.tr("time since track start"), units=minutes)
        self.factor_plot.setLabel("left", self.tr("maneuver factor δ"), units="°")
        self.comp_plot.setLabel("bottom", self.tr("longitude"), units="°")
        self.comp_plot.setLabel("left", self.tr("latitude"), units="°")
        self.b_plot.setLabel("left", self.tr("bearing"), units="°")
        self.z_plot.setLabel("left", self._z_label())
        self.z_plot.setLabel("bottom", self.tr("time"), units=minutes)
        for plot, make in self._titles.values():
            self._write_title(plot, make)

    def _set_title(self, name: str, plot, make: Callable[[], str], size: str | None = None) -> None:
        """Title ``plot`` with ``make()`` (a text through ``self.tr``), kept for
        :meth:`retranslate`; ``size``: a smaller font (a reason, not a figure)."""
        write = make if size is None else (lambda: (make(), size))
        self._titles[name] = (plot, write)
        self._write_title(plot, write)

    @staticmethod
    def _write_title(plot, make) -> None:
        made = make()  # the size is given each time: the label keeps the last one
        text, size = made if isinstance(made, tuple) else (made, TITLE_PT)
        plot.setTitle(text, size=size)

    def _z_label(self) -> str:
        """The z axis's name: the detector's statistic (GLR or AUC)."""
        return self.tr("z (GLR)") if self._bparams.glr else self.tr("z (AUC)")

    def show_bearings(
        self,
        bearings: pd.DataFrame,
        detections: pd.DataFrame,
        params: BearingParams,
        curves: tuple[BearingParams, dict] | None = None,
    ) -> None:
        """Bearing sequences and their detections; the combo picks the sequence.
        ``curves``: :func:`sequence_curves` made in a worker with those parameters (used
        while they are the panel's; else a sequence's curves are made when shown)."""
        self._bearings, self._detections, self._bparams = bearings, detections, params
        self._curves = curves[1] if curves is not None and curves[0] == params else {}
        self.bearing_batch.blockSignals(True)
        self.bearing_batch.clear()
        self.bearing_batch.addItems(sorted(bearings["batch"].astype(str).unique()))
        self.bearing_batch.blockSignals(False)
        self._draw_bearing(self.bearing_batch.currentText())
        self.setTabVisible(2, True)
        self.setCurrentWidget(self.bearing_box)

    def clear_bearings(self) -> None:
        """No bearing sequence shown (its layer was removed)."""
        self._bearings, self._detections, self._curves = pd.DataFrame(), pd.DataFrame(), {}
        self.bearing_batch.blockSignals(True)
        self.bearing_batch.clear()
        self.bearing_batch.blockSignals(False)
        self._draw_bearing("")
        for curve in (self.b_curve, self.z_curve):
            curve.setData([], [])
        self._set_title("bearing", self.b_plot, str)
        self.setTabVisible(2, False)

    def _draw_bearing(self, batch: str) -> None:
        for line in self.detect_lines:
            for plot in (self.b_plot, self.z_plot):
                if line in plot.items:
                    plot.removeItem(line)
        self.detect_lines = []
        if self._bearings.empty or not batch:
            return
        p = self._bparams
        curves = self._curves.get(batch) or sequence_curves(self._bearings, p, batch).get(batch)
        if curves is None:
            return
        minutes, bearing, bt, z, t0 = curves
        self.b_curve.setData(minutes, bearing)
        self.z_curve.setData(bt, z)
        self.z_plot.setLabel("left", self._z_label())
        self.z_band.setRegion((-p.z_crit, p.z_crit))
        det = self._detections[self._detections["batch"].astype(str) == batch]
        for when in time_seconds(det["maneuver_time"]) if len(det) else []:
            for plot in (self.b_plot, self.z_plot):
                line = pg.InfiniteLine((when - t0) / 60.0, pen=pg.mkPen("#d62728", width=1.5))
                plot.addItem(line)
                self.detect_lines.append(line)
        found = len(det)
        self._set_title(
            "bearing",
            self.b_plot,
            lambda: (
                self.tr("{0}: 1 maneuver detected; band ±{2:.2f}")
                if found == 1
                else self.tr("{0}: {1} maneuvers detected; band ±{2:.2f}")
            ).format(batch, found, p.z_crit),
        )

    def clear(self) -> None:
        self.factor_curve.setData([], [])
        self.factor_marks.setData([], [])
        # An empty plot keeps no time axis of the track shown before (minutes of an
        # 8-day track under a 2-hour one's "run Maneuvers or Compress to see δ").
        self.factor_plot.setXRange(0.0, 1.0, padding=0)
        self.factor_plot.enableAutoRange(axis="x")
        self.comp_orig.setData([], [])
        self.comp_kept.setData([], [])
        # No track: say so, not empty axes (operator test h150; h225 item 7: the empty
        # -0.4…0.4 axes are gone too, and the hint is on two short lines, not cut).
        self._set_title(
            "factor",
            self.factor_plot,
            lambda: self.tr("No track selected.<br>Click one on the map or in the table."),
            REASON_PT,
        )
        self._set_title(
            "compression", self.comp_plot, lambda: self.tr("No track selected"), REASON_PT
        )
        self._show_axes(False)

    def _show_axes(self, on: bool) -> None:
        """The δ and compression plots' axes and threshold line, shown only with a track."""
        for plot in (self.factor_plot, self.comp_plot):
            item = plot.getPlotItem()
            for side in ("left", "bottom"):
                item.showAxis(side, on)
        self.threshold.setVisible(on)

    def show_track(
        self,
        track: pd.DataFrame,
        threshold_deg: float | None = None,
        compressed: pd.DataFrame | None = None,
        original: pd.DataFrame | None = None,
        dis_e_m: float | None = None,
        lon_west: float | None = None,
        fused: bool = False,
    ) -> None:
        """Plot one track (points of one sensor/batch, time-sorted); ``dis_e_m`` is the
        compressed track's Dis_e, metres; ``lon_west``: the band the map draws its layer
        in (-180 or 0; None: the track's own, :func:`wakeline.core.geo.lon_band_west`);
        ``fused``: the track is a fused target's (its reason for no δ says so)."""
        self.clear()
        self._show_axes(True)
        if "maneuver_factor" in track.columns and len(track):
            t = time_seconds(track["time"])
            minutes = (t - t[0]) / 60.0
            delta = track["maneuver_factor"].to_numpy(dtype="float64")
            x, y = gaps_broken(minutes, delta)
            self.factor_curve.setData(x, y, connect="finite")
            hits = track["is_maneuver"].to_numpy(dtype=bool)
            self.factor_marks.setData(minutes[hits], delta[hits])
            if threshold_deg is not None:
                self.threshold.setValue(threshold_deg)
            n_hits = int(hits.sum())
            self._set_title(
                "factor",
                self.factor_plot,
                lambda: (
                    self.tr("1 maneuver; threshold {1:g}°")
                    if n_hits == 1
                    else self.tr("{0} maneuvers; threshold {1:g}°")
                ).format(n_hits, threshold_deg or 0),
            )
        elif fused:  # a fused target's points are the sensors' points merged: no δ
            self._set_title(
                "factor",
                self.factor_plot,
                lambda: self.tr("No δ for a fused track: run Maneuvers on its layer"),
                REASON_PT,
            )
        else:
            self._set_title(
                "factor",
                self.factor_plot,
                lambda: self.tr("No δ for this track: run Maneuvers on its layer"),
                REASON_PT,
            )
        if compressed is not None and original is not None and len(compressed):
            olon, klon = drawn_track_lon(original, lon_west), drawn_track_lon(compressed, lon_west)
            self.comp_orig.setData(olon, original["lat"].to_numpy())
            self.comp_kept.setData(klon, compressed["lat"].to_numpy())
            lat = float(original["lat"].mean())
            self.comp_plot.getPlotItem().getViewBox().setAspectLocked(
                True, ratio=max(np.cos(np.radians(lat)), 0.05)
            )
            dis = np.nan if dis_e_m is None else dis_e_m
            kept, of = len(compressed), len(original)
            self._set_title(
                "compression",
                self.comp_plot,
                lambda: self.tr("{0} of {1} points kept, Dis_e {2:.0f} m").format(kept, of, dis),
            )
        else:
            self._set_title(
                "compression", self.comp_plot, lambda: self.tr("run Compress to compare"), REASON_PT
            )

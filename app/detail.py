"""Detail views of the selected track: maneuver factor over time, compression."""

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtWidgets

from wakeline.core.schema import time_seconds


class DetailPanel(QtWidgets.QTabWidget):
    """Plots for one selected track."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.factor_plot = pg.PlotWidget(background="w")
        self.factor_plot.setLabel("bottom", "time since track start", units="min")
        self.factor_plot.setLabel("left", "maneuver factor δ", units="°")
        self.factor_curve = self.factor_plot.plot(pen=pg.mkPen("#1f77b4", width=1.5))
        self.factor_marks = pg.ScatterPlotItem(size=9, brush=pg.mkBrush("#d62728"), pen=None)
        self.factor_plot.addItem(self.factor_marks)
        self.threshold = pg.InfiniteLine(
            angle=0, pen=pg.mkPen("#555", style=pg.QtCore.Qt.PenStyle.DashLine)
        )
        self.factor_plot.addItem(self.threshold)
        self.comp_plot = pg.PlotWidget(background="w")
        self.comp_plot.setLabel("bottom", "longitude", units="°")
        self.comp_plot.setLabel("left", "latitude", units="°")
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
        self.message = ""

    def retranslate(self) -> None:
        self.setTabText(0, self.tr("Maneuver factor"))
        self.setTabText(1, self.tr("Compressed over original"))

    def clear(self) -> None:
        self.factor_curve.setData([], [])
        self.factor_marks.setData([], [])
        self.comp_orig.setData([], [])
        self.comp_kept.setData([], [])
        self.factor_plot.setTitle("")
        self.comp_plot.setTitle("")

    def show_track(
        self,
        track: pd.DataFrame,
        threshold_deg: float | None = None,
        compressed: pd.DataFrame | None = None,
        original: pd.DataFrame | None = None,
    ) -> None:
        """Plot one track (points of one sensor/batch, time-sorted)."""
        self.clear()
        if "maneuver_factor" in track.columns and len(track):
            t = time_seconds(track["time"])
            minutes = (t - t[0]) / 60.0
            delta = track["maneuver_factor"].to_numpy(dtype="float64")
            self.factor_curve.setData(minutes, np.nan_to_num(delta, nan=0.0))
            hits = track["is_maneuver"].to_numpy(dtype=bool)
            self.factor_marks.setData(minutes[hits], delta[hits])
            if threshold_deg is not None:
                self.threshold.setValue(threshold_deg)
            self.factor_plot.setTitle(
                self.tr("{0} maneuvers; threshold {1:g}°").format(
                    int(hits.sum()), threshold_deg or 0
                )
            )
        else:
            self.factor_plot.setTitle(self.tr("run Maneuvers or Compress to see δ"))
        if compressed is not None and original is not None and len(compressed):
            self.comp_orig.setData(original["lon"].to_numpy(), original["lat"].to_numpy())
            self.comp_kept.setData(compressed["lon"].to_numpy(), compressed["lat"].to_numpy())
            lat = float(original["lat"].mean())
            self.comp_plot.getPlotItem().getViewBox().setAspectLocked(
                True, ratio=max(np.cos(np.radians(lat)), 0.05)
            )
            dis = compressed["dis_e_m"].iloc[0] if "dis_e_m" in compressed.columns else np.nan
            self.comp_plot.setTitle(
                self.tr("{0} of {1} points kept, Dis_e {2:.0f} m").format(
                    len(compressed), len(original), dis
                )
            )
        else:
            self.comp_plot.setTitle(self.tr("run Compress to compare"))

"""The Statistics dock (SPEC §7, seed 003's auxiliary panel): a compact table of the
active layer's figures and a histogram of its track lifetimes.

The figures come from :func:`wakeline.core.stats.layer_stats`, run off the GUI thread by an
executor (``executor(job, done)``, the window's :class:`~wakeline.app.lod_worker.LodWorker`):
one job at a time; a request made while one runs waits for it and replaces any other
waiting request, and a result for anything but the latest request is dropped. The texts
go through ``QCoreApplication.translate`` in the ``StatsPanel`` context.
"""

import math
import threading
from collections.abc import Callable

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtWidgets

from wakeline.app import ink
from wakeline.app.time_text import format_time, is_relative_time
from wakeline.core.stats import LayerStats, Spread, layer_stats

TR_CONTEXT = "StatsPanel"
#: The lifetime histogram's least height (px) while the dock is raised: its title, axis
#: and label take about 70 px, this leaves about 80 px of bars (at the 104 px the
#: bottom dock area had in the default window they were 15 px high, as measured by
#: ``docs/tools/render_statistics_dock.py``, docs/map.md).
HIST_MIN_HEIGHT = 150
#: The table's least height, and the histogram's while the dock is behind another tab
#: (px): no taller than the text box the dock held before (70 px with the note).
LOW_MIN_HEIGHT = 48


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


def tracks_text(n: int) -> str:
    """'1 track', '2 tracks' (tester: "1 tracks")."""
    return tr("1 track") if n == 1 else tr("{0} tracks").format(f"{n:,}")


def points_text(n: int) -> str:
    """'1 point', '2 points'."""
    return tr("1 point") if n == 1 else tr("{0} points").format(f"{n:,}")


def duration_unit(seconds: float) -> tuple[float, str]:
    """The divisor and translated unit that show ``seconds`` as a figure of a few digits:
    s below 2 min, min below 2 h, h below 2 days, else days."""
    s = abs(seconds) if math.isfinite(seconds) else 0.0
    if s < 120:
        return 1.0, tr("s")
    if s < 7200:
        return 60.0, tr("min")
    if s < 2 * 86400:
        return 3600.0, tr("h")
    return 86400.0, tr("d")


def _num(value: float, digits: int = 1) -> str:
    if not math.isfinite(value):
        return "—"
    return f"{value:,.0f}" if abs(value) >= 100 or value == int(value) else f"{value:,.{digits}f}"


def duration_text(seconds: float) -> str:
    """A duration with its unit (``45 s``, ``3.5 min``, ``2.1 h``, ``3.0 d``)."""
    if not math.isfinite(seconds):
        return "—"
    div, unit = duration_unit(seconds)
    return f"{_num(seconds / div)} {unit}"


def spread_text(sp: Spread, durations: bool) -> str:
    """``min / median / 90 % / max`` in one unit (the median's, for durations)."""
    values = (sp.min, sp.median, sp.p90, sp.max)
    if not math.isfinite(sp.median):
        return "—"
    if durations:
        div, unit = duration_unit(sp.median)
        return " / ".join(_num(v / div) for v in values) + f" {unit}"
    return " / ".join(_num(v) for v in values)


def area_text(km2: float) -> str:
    if km2 < 1:
        return f"{km2 * 1e6:,.0f} {tr('m²')}" if km2 > 0 else f"0 {tr('km²')}"
    return f"{_num(km2)} {tr('km²')}"


def length_text(km: float) -> str:
    return f"{km * 1000:,.0f} {tr('m')}" if km < 1 else f"{_num(km)} {tr('km')}"


def stats_rows(s: LayerStats) -> list[tuple[str, str]]:
    """The table's rows (figure, value), translated, every value with its unit."""
    relative = is_relative_time(np.array([s.start_s, s.end_s]))
    if s.window is None:
        rows = [(tr("Points"), f"{s.points:,}"), (tr("Tracks"), f"{s.tracks:,}")]
    else:  # said first: every figure below counts the window's points only
        rows = [
            (
                tr("Time window"),
                tr("only the points in {0} – {1}").format(
                    format_time(s.window[0], relative), format_time(s.window[1], relative)
                ),
            ),
            (tr("Points in the window"), f"{s.points:,}"),
            (tr("Tracks with points in the window"), f"{s.tracks:,}"),
        ]
    for r in s.sensors.itertuples(index=False):
        interval = duration_text(r.interval_s) if math.isfinite(r.interval_s) else "—"
        rows.append(
            (
                tr("Sensor {0}").format(r.sensor),
                tr("{0}, {1}, median interval {2}").format(
                    tracks_text(r.tracks), points_text(r.points), interval
                ),
            )
        )
    if s.targets is None:
        rows.append((tr("Targets"), tr("no target ids")))
    else:
        rows.append((tr("Targets"), f"{s.targets:,}"))
    rows.append((tr("Track lifetime min / median / 90 % / max"), spread_text(s.lifetime_s, True)))
    rows.append(
        (tr("Points per track min / median / 90 % / max"), spread_text(s.points_per_track, False))
    )
    e = s.extent
    if e is not None:
        rows.append((tr("Longitude"), f"{e.lon_min:.5f}° … {e.lon_max:.5f}°"))
        rows.append((tr("Latitude"), f"{e.lat_min:.5f}° … {e.lat_max:.5f}°"))
        rows.append(
            (
                tr("Extent (east-west × north-south)"),
                f"{length_text(e.width_km)} × {length_text(e.height_km)} = {area_text(e.box_km2)}",
            )
        )
        rows.append(
            (
                tr("Area covered"),
                tr("{0} (cells of {1} holding a point)").format(
                    area_text(e.covered_km2), length_text(e.cell_km)
                ),
            )
        )
    if s.points:
        rows.append(
            (
                tr("Time"),
                f"{format_time(s.start_s, relative)} – {format_time(s.end_s, relative)}",
            )
        )
        rows.append((tr("Time span"), duration_text(s.span_s)))
    if s.at_rest is not None:
        r = s.at_rest
        rows.append(
            (
                tr("At-rest spans"),
                tr("{0} in {1}, total {2}, median {3}").format(
                    f"{r['spans']:,}",
                    tracks_text(r["tracks"]),
                    duration_text(r["total_s"]),
                    duration_text(r["median_s"]),
                ),
            )
        )
    if s.maneuvers is not None:
        m = s.maneuvers
        rows.append(
            (
                tr("Maneuvers"),
                tr("{0} in {1}").format(points_text(m["points"]), tracks_text(m["tracks"])),
            )
        )
    return rows


class StatsPanel(QtWidgets.QWidget):
    """The Statistics dock: the figures table above a lifetime histogram."""

    def __init__(self, parent: QtWidgets.QWidget | None = None) -> None:
        super().__init__(parent)
        ink.setup()
        #: ``executor(job, done)``: runs ``job()`` off the GUI thread and calls
        #: ``done(result)`` on it (the window's LodWorker); None: run here (tests).
        self.executor: Callable | None = None
        self.stats: LayerStats | None = None
        #: Thread id of the job that computed :attr:`stats`.
        self.computed_in: int | None = None
        #: The request key :attr:`stats` answer (the table may show them while the
        #: latest request, :attr:`key`, is computed).
        self.shown_key: tuple | None = None
        #: Results dropped because a newer request had been made.
        self.dropped = 0
        self._head: list[tuple[str, str]] = []
        self._message = ""
        self._key: tuple | None = None  # the latest request's key
        self._token = 0
        self._busy = False
        self._waiting: tuple | None = None  # (token, job) to start when the running ends

        self.note = QtWidgets.QLabel(wordWrap=True)
        self.note.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.table = QtWidgets.QTableWidget(0, 2)
        self.table.verticalHeader().setVisible(False)
        self.table.horizontalHeader().setVisible(False)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setWordWrap(False)
        # A long layer name or figure keeps both ends (the name's end is what differs
        # between a layer and the next: "scene.csv · cleaned · compressed"); the tooltip
        # holds the whole (operator test 6, D-stats-1).
        self.table.setTextElideMode(QtCore.Qt.TextElideMode.ElideMiddle)
        self.table.verticalHeader().setDefaultSectionSize(self.table.fontMetrics().height() + 4)
        self.hist = pg.PlotWidget(background="w")
        self.hist.setMouseEnabled(x=False, y=False)
        self.hist.hideButtons()
        self.hist.setMenuEnabled(False)
        for side in ("left", "bottom"):
            self.hist.getAxis(side).enableAutoSIPrefix(False)
        self.bars = pg.BarGraphItem(x=[], height=[], width=1.0, brush="#1f77b4", pen="#1f77b4")
        self.hist.addItem(self.bars)
        # The table scrolls, so a few rows will do; the histogram asks for its height
        # while the dock is raised (set_raised).
        for widget in (self.table, self.hist):
            widget.setMinimumHeight(LOW_MIN_HEIGHT)
        split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        split.addWidget(self.table)
        split.addWidget(self.hist)
        split.setStretchFactor(0, 3)
        split.setStretchFactor(1, 2)
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(2, 2, 2, 2)
        lay.addWidget(self.note)
        lay.addWidget(split, 1)
        self.split = split

    def sizeHint(self) -> QtCore.QSize:  # noqa: N802 - Qt API
        """As high as the text box the dock held before (the plot's 480 px hint made the
        bottom dock area take height from the docks above it)."""
        return QtCore.QSize(520, 192)

    def set_raised(self, raised: bool) -> None:
        """The dock is shown (its tab raised) or not (behind the Log tab, closed): while
        shown the histogram keeps :data:`HIST_MIN_HEIGHT` px, so the bottom dock area
        grows to it; behind the Log it asks no more height of the docks above than the
        text box before it (the Bearing-only dock's map). Connected to the dock's
        ``visibilityChanged``."""
        self.hist.setMinimumHeight(HIST_MIN_HEIGHT if raised else LOW_MIN_HEIGHT)

    # -- requests ------------------------------------------------------------------

    @property
    def key(self) -> tuple | None:
        """What the latest request was for (None: a message, no figures)."""
        return self._key

    @property
    def busy(self) -> bool:
        """A job is running or waiting."""
        return self._busy or self._waiting is not None

    #: The share of the table's width the labels may take at most (their text elided in
    #: the middle beyond it): a long label left the values a few characters.
    LABEL_SHARE = 0.45

    def fit_label_column(self) -> None:
        """The labels' column as wide as its texts, at most :data:`LABEL_SHARE` of the
        table; the values take the rest."""
        self.table.resizeColumnToContents(0)
        cap = max(60, int(self.table.viewport().width() * self.LABEL_SHARE))
        if self.table.columnWidth(0) > cap:
            self.table.setColumnWidth(0, cap)

    def resizeEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        super().resizeEvent(event)
        if self.table.rowCount():
            self.fit_label_column()

    def show_message(self, text: str) -> None:
        """Text instead of figures (no layer; a bearing layer's summary)."""
        self._key = None
        self._token += 1  # a result on its way is for something else now
        self._waiting = None
        self.stats = self.shown_key = None
        self._head = []
        self._message = text
        self.note.setText(text)
        self.note.show()
        self.split.hide()

    def compute(
        self,
        key: tuple,
        points,
        tables: dict | None = None,
        window: tuple[float, float] | None = None,
        head: list[tuple[str, str]] | None = None,
    ) -> bool:
        """Ask for the figures of ``points`` (``key`` says which layer, data and window they
        are); the table shows them when they come. False when ``key`` is what is shown
        (or coming) already: only the head rows are set again."""
        self._head = list(head or [])
        if key == self._key:
            self._fill()
            return False
        shown = self.shown_key
        # the same layer (first item) and time window (last item) with new data
        same_layer = shown is not None and (shown[:1], shown[-1:]) == (key[:1], key[-1:])
        self._key = key
        self._token += 1
        token = self._token

        def job():
            return token, threading.get_ident(), layer_stats(points, tables, window)

        if not same_layer or self.stats is None:
            # Above the figures of the last layer until the new ones come; the same
            # layer's new points in the same window (a review decision) keep its figures
            # until then: the note shown and hidden again laid the dock out twice a key.
            self._message = tr("Computing…")
            self.note.setText(self._message)
            self.note.show()
        if self.executor is None:
            self._arrived(job())
        elif self._busy:
            self._waiting = (token, job)  # replaces any request that was waiting
        else:
            self._busy = True
            self.executor(job, self._arrived)
        return True

    def _arrived(self, result) -> None:
        self._busy = False
        if self._waiting is not None:
            _token, job = self._waiting
            self._waiting = None
            self._busy = True
            self.executor(job, self._arrived)
        if result is None:  # the job failed (logged by the executor)
            if not self.busy:
                self._message = tr("The figures could not be computed (see the log).")
                self.note.setText(self._message)
                self.note.show()
            return
        token, ident, stats = result
        if token != self._token:
            self.dropped += 1
            return
        self.stats, self.computed_in, self.shown_key = stats, ident, self._key
        self._message = ""
        self._fill()

    # -- drawing -------------------------------------------------------------------

    def retranslate(self) -> None:
        if self.stats is not None:
            self._fill()

    def _fill(self) -> None:
        if self.stats is None:
            return
        rows = self._head + stats_rows(self.stats)
        self.note.setText(self._message)
        self.note.setVisible(bool(self._message))
        self.split.show()
        self.table.setRowCount(len(rows))
        for i, (label, value) in enumerate(rows):
            for j, text in enumerate((label, value)):
                item = QtWidgets.QTableWidgetItem(text)
                item.setToolTip(text)
                self.table.setItem(i, j, item)
        self.fit_label_column()
        s = self.stats
        div, unit = duration_unit(float(s.hist_edges_s[-1]) if len(s.hist_edges_s) else 0.0)
        edges = s.hist_edges_s / div
        self.bars.setOpts(
            x=0.5 * (edges[1:] + edges[:-1]),
            height=s.hist_counts,
            width=float(edges[1] - edges[0]) if len(edges) > 1 else 1.0,
        )
        self.hist.setTitle(tr("Track lifetimes"))
        self.hist.setLabel("bottom", tr("lifetime"), units=unit)
        self.hist.setLabel("left", tr("tracks"))
        self.hist.getPlotItem().enableAutoRange()

    def rows(self) -> list[tuple[str, str]]:
        """The table's rows as shown."""
        return [
            (self.table.item(i, 0).text(), self.table.item(i, 1).text())
            for i in range(self.table.rowCount())
        ]

    def toPlainText(self) -> str:  # noqa: N802 - as the QPlainTextEdit it replaced
        """What the dock shows, as text: the note, then ``figure: value`` lines."""
        if self.stats is None:
            return self._message
        lines = [self._message] if self._message else []
        return "\n".join(lines + [f"{a}: {b}" for a, b in self.rows()])

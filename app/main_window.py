"""The main window: map in the centre; Layers, Parameters, Batch table, Statistics,
Detail and Log panels around it.

The window is a view and controller over a :class:`wakeline.core.session.Session`: the
session owns the layers (by id, with lineage); the window draws what the session says.
Slow work never runs on the GUI thread: importing, hashing, steps, preparing the arrays
for drawing and the batch table (:mod:`wakeline.app.layer_view`) run in the worker
(:mod:`wakeline.app.jobs`), and the project file is written by a background writer
(:mod:`wakeline.app.project_controller`). The GUI thread swaps finished data in.

The window is assembled from mixins: layers and the drawing queue
(:mod:`wakeline.app.window_layers`), selection, detail and hover
(:mod:`wakeline.app.window_selection`), jobs (:mod:`wakeline.app.jobs`, with
:mod:`~wakeline.app.jobs_import` and :mod:`~wakeline.app.jobs_project`).
"""

import weakref
from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import about, cjk_font, i18n
from wakeline.app.actions import build_actions, retranslate
from wakeline.app.bearing_view import BearingView, bearing_stats
from wakeline.app.core_text import shown
from wakeline.app.detail import DetailPanel
from wakeline.app.dialogs import ImportReportDialog
from wakeline.app.import_dialog import ImportDialog
from wakeline.app.jobs import JobsMixin, preload
from wakeline.app.layer_names import shown_name
from wakeline.app.layer_undo import LayerUndo
from wakeline.app.layer_view import LayerView, maneuver_table
from wakeline.app.lod_worker import LodWorker
from wakeline.app.map_canvas import MapCanvas
from wakeline.app.models import BatchTableModel
from wakeline.app.params_panel import ParamsPanel
from wakeline.app.project_controller import ProjectController
from wakeline.app.review_dock import ReviewDock
from wakeline.app.stats_panel import StatsPanel, points_text, tracks_text
from wakeline.app.time_panel import dark_palette, install_time, palette_icon
from wakeline.app.view_keeper import MapViewKeeper
from wakeline.app.window_layers import EMPTY, LayersMixin, layer_text
from wakeline.app.window_selection import SelectionMixin
from wakeline.app.window_sensors import SensorsMixin
from wakeline.app.window_vessels import VesselsMixin
from wakeline.app.worker import JobRunner, give_back_free_memory
from wakeline.core import geo
from wakeline.core.session import BEARING_KIND, Session
from wakeline.resources import coastline_path

#: Rows of the batch table always in sight (its least height): 5 made the right column
#: 705 px tall at least, more than a 150 % or 200 % laptop screen has (operator look h225).
BATCH_MIN_ROWS = 3
#: The batch table's columns shown right after Batch (a file's ship names and types).
BATCH_AFTER_BATCH = ("name", "ship_type")
#: A screen whose free height (``availableGeometry``, logical px) is below this gets the
#: compact layout at start: Layers tabbed with Parameters, the batch table with Detail
#: (1366x768, 1280x720 at 150 %, 1920x1080 at 200 %); 1440x900 and up keep every dock apart.
COMPACT_SCREEN_HEIGHT = 800
#: The compact layout's left and right columns, shares of the window's width at start.
COMPACT_LEFT_SHARE, COMPACT_RIGHT_SHARE = 0.19, 0.245
#: ... and the bottom docks' share of its height.
COMPACT_BOTTOM_SHARE = 0.15
#: Between two recomputations of the Statistics figures while the time window moves (ms).
STATS_WINDOW_MS = 300


def format_dms(value: float, positive: str, negative: str) -> str:
    """Degrees as D°MM'SS.s" with a hemisphere letter."""
    hemi = positive if value >= 0 else negative
    v = abs(value)
    d = int(v)
    m = int((v - d) * 60)
    s = (v - d - m / 60) * 3600
    return f"{d}°{m:02d}'{s:04.1f}\"{hemi}"


#: The least width (px) of the map (with its legend column) in the main window: with
#: the Parameters dock and the right column beside it, the window stays under 960 px
#: wide (1920x1080 at 200 %); 480 held it at 1,097 px at least (operator look h225). The
#: docks are given their widths at start (resizeDocks), so the map is wider than this on
#: any screen that has the room.
MAP_MIN_WIDTH_PX = 320
#: Hover text in the status bar stays this long (ms), in its own label: the counts stay.
HOVER_MS = 4000


def scrolled(widget: QtWidgets.QWidget) -> QtWidgets.QScrollArea:
    """``widget`` in a frameless scroll area that resizes it: a dock holding it asks the
    window for no more than a scroll area's least size, and a screen too small for the
    widget's own least size scrolls it instead of growing the window off the screen."""
    area = QtWidgets.QScrollArea()
    area.setWidgetResizable(True)
    area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
    area.setWidget(widget)
    return area


def hide_stray_tab_bars(window: QtWidgets.QMainWindow) -> int:
    """Hide the dock tab bars Qt left behind: tabifying a second group of docks makes a
    second bar for the first group that the layout never uses again; it stayed drawn
    where the layout first put it (an empty two-tab box between the time panel and the
    log, operator look h225 item 16). Such a bar is never given its docks' titles: it is
    the one whose tabs are all untitled. Returns how many were hidden."""
    hidden = 0
    for bar in window.findChildren(QtWidgets.QTabBar):
        if bar.parentWidget() is not window or not bar.isVisibleTo(window) or not bar.count():
            continue
        if not any(bar.tabText(i) for i in range(bar.count())):
            bar.hide()
            hidden += 1
    return hidden


def points_inside(points: pd.DataFrame, window: tuple[float, float]) -> int:
    """How many of ``points`` have a time in ``window`` (s since 1970, both ends kept):
    the times compared as datetime64 to the window's ends in ns (2 M points: a few ms;
    through seconds as floats it took 80 ms on the GUI thread)."""
    if "time" not in points or not len(points):
        return 0
    times = points["time"].array
    t = np.asarray(times.tz_convert(None) if getattr(times, "tz", None) else times)
    lo, hi = (np.datetime64(round(x * 1e9), "ns") for x in window)
    return int(np.count_nonzero((t >= lo) & (t <= hi)))


class MainWindow(
    LayersMixin, SelectionMixin, SensorsMixin, VesselsMixin, JobsMixin, QtWidgets.QMainWindow
):
    """Wakeline's main window."""

    layersChanged = QtCore.Signal()
    activeChanged = QtCore.Signal()  # the layer the table and steps work on
    #: Every window made and not yet deleted (weak): what the GUI tests' teardown ends,
    #: without listing the application's top-level widgets — that list wraps every one,
    #: and one a garbage collection was deleting made it segfault (tests/conftest.py).
    alive: "weakref.WeakSet[MainWindow]" = weakref.WeakSet()

    def __init__(self, settings: QtCore.QSettings | None = None) -> None:
        super().__init__()
        MainWindow.alive.add(self)
        self.settings = settings or QtCore.QSettings("Wakeline", "Wakeline")
        preload()
        self.session = Session()
        self.views: dict[str, LayerView] = {}
        self.active: str | None = None
        #: The bearing table and detections the Bearing-only dock shows (None: none).
        self.bearings = None
        self.bearing_detections = None
        self.translator = None
        self.language = "en"
        self.runner = JobRunner(self)
        self.runner.message.connect(self._on_job_message)
        self._job_context: dict[int, tuple] = {}
        self._job_fns: dict[
            int, tuple
        ] = {}  # the running job, to run again when stale (_follow_up)
        self._replaced: dict[int, str] = {}  # a running job -> the job that took its place
        # Jobs the window started by itself (a stale re-run, a carry made again): their
        # failure is said in the status bar and the log, not in a dialog (_follow_up).
        self._automatic: set[int] = set()
        # Exports run on their own runner, one after the other (jobs._start_export).
        self.export_runner = JobRunner(self)
        self.export_runner.message.connect(self._on_job_message)
        self._export_context: dict[int, tuple] = {}
        self._export_queue: list[tuple] = []
        self._export_running: int | None = None
        self._selecting = False
        self._pending_views: dict = {}
        self._draw_queue: list[str] = []
        self._make_current: str | None = None
        self._restore_selection: list | None = None
        self._fit_after_draw = False
        self._after_current = False  # the current layer is set; _after_drawn next
        self._view_planned = False  # a job set the aspect and range for its layers
        self._draw_scheduled = False  # a _draw_next is queued on the event loop
        self._detail_key = None  # (layer, track) the Detail panel shows next turn
        # First listener: a new layer takes its prepared view and colour before the
        # project writer (the next listener) reads it.
        self.session.subscribe(self._adopt_view)
        self.project = ProjectController(self.session, self)
        self.project.failed.connect(self._save_failed)
        self.session.subscribe(self._on_session_event)

        self.canvas = MapCanvas(self)
        # The map keeps MAP_MIN_WIDTH_PX when the window is narrow: the docks beside it
        # give way first (h179: with the time panel's controls wrapping, the window may
        # be narrower than 1,368 px, and the map alone took the loss, to a 45-px plot).
        self.canvas.setMinimumWidth(MAP_MIN_WIDTH_PX)
        self.lod_worker = LodWorker(self)
        self.canvas.lod_executor = self.lod_worker
        self.setCentralWidget(self.canvas)
        try:
            coast = np.load(coastline_path())
            self.canvas.set_coastline(
                coast["lon"].astype("float64"), coast["lat"].astype("float64")
            )
        except OSError:
            pass
        self.canvas.cursorMoved.connect(self._show_cursor)
        self.canvas.trackClicked.connect(self._track_clicked)
        self.canvas.pointHovered.connect(self.show_hover)
        self.time_controller = install_time(self)  # slider under the map: self.time_panel
        # The map's view, written to the session (and the project) once it settles.
        self.view_keeper = MapViewKeeper(self.canvas, self.session, self)

        self.layer_list = QtWidgets.QListWidget()
        # A long name wraps at its " · " onto a second line, in the dock's width: it was
        # cut ("… · cleaned  [cleaned", operator test 7, D16) behind a scroll bar.
        self.layer_list.setWordWrap(True)
        self.layer_list.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)
        self.layer_list.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.layer_list.itemChanged.connect(self._layer_item_changed)
        self.layer_list.currentItemChanged.connect(self._layer_current_changed)
        # Colour…, Move up / Move down on a right click, and rows dragged to reorder the
        # layers (the map's stacking follows the list: SPEC §7)
        self.layer_list.setContextMenuPolicy(QtCore.Qt.ContextMenuPolicy.CustomContextMenu)
        self.layer_list.customContextMenuRequested.connect(self._layer_menu)
        self.layer_list.setDragDropMode(QtWidgets.QAbstractItemView.DragDropMode.InternalMove)
        self.layer_list.model().rowsMoved.connect(self._layers_dropped)
        self.params = ParamsPanel()
        self.params.executor = self.lod_worker  # the preset suggestion: off this thread
        self.params.changed.connect(lambda _k: self.project.put_params(self.params.to_dict()))
        self.params.refused.connect(lambda text: self.log_message(f"{self.tr('Refused')}: {text}"))
        self.params.message.connect(self.log_message)
        self.batch_model = BatchTableModel(self)
        self.batch_view = QtWidgets.QTableView()
        self.batch_view.setModel(self.batch_model)
        self.batch_view.setSortingEnabled(True)
        behavior = QtWidgets.QAbstractItemView
        self.batch_view.setSelectionBehavior(behavior.SelectionBehavior.SelectRows)
        self.batch_view.setSelectionMode(behavior.SelectionMode.ExtendedSelection)
        self.batch_view.verticalHeader().setVisible(False)
        self.batch_view.setAlternatingRowColors(True)
        header = self.batch_view.horizontalHeader()
        header.setStretchLastSection(True)
        header.setResizeContentsPrecision(50)  # size columns from 50 rows, not all
        # Name and Type (a file's ship names, File ▸ Load ship names' types) shown right
        # after Batch: last, the Type column sat off-screen at x=1008 px of a 389-px table
        # (1400 x 900; operator test 11, F5) and loading the types seemed to do nothing.
        # Moved on the header (what the view shows), the model's columns keep their
        # places (sorting, filters, the selection address them by those).
        keys = [key for key, _title in self.batch_model.COLUMNS]
        for k, key in enumerate(BATCH_AFTER_BATCH):
            header.moveSection(header.visualIndex(keys.index(key)), keys.index("batch") + 1 + k)
        self.batch_view.selectionModel().selectionChanged.connect(self._table_selection_changed)
        self.batch_model.modelReset.connect(self._reselect)  # after the view dropped it
        self.batch_model.modelReset.connect(self.fit_batch_columns)
        # At least BATCH_MIN_ROWS rows under the header: beside the Review dock at
        # 1400x900 the table was one row of 15 (operator test h150); the Detail dock
        # beside it gives way instead.
        scroll = self.batch_view.horizontalScrollBar().sizeHint().height()
        self.batch_view.setMinimumHeight(
            header.sizeHint().height()
            + BATCH_MIN_ROWS * self.batch_view.verticalHeader().defaultSectionSize()
            + scroll
            + 2 * self.batch_view.frameWidth()
        )
        self.filter_edit = QtWidgets.QLineEdit()
        self.filter_edit.setClearButtonEnabled(True)
        self.filter_edit.textChanged.connect(self.batch_model.set_filter)
        batch_box = QtWidgets.QWidget()
        bl = QtWidgets.QVBoxLayout(batch_box)
        bl.setContentsMargins(2, 2, 2, 2)
        bl.addWidget(self.filter_edit)
        bl.addWidget(self.batch_view)
        # What the table counts (it, the Statistics dock and the status bar count three
        # different things under a time window: operator test, ATD 06:00-12:00).
        self.batch_count = QtWidgets.QLabel()
        self.batch_count.setWordWrap(True)
        bl.addWidget(self.batch_count)
        for signal in (self.batch_model.modelReset, self.batch_model.layoutChanged):
            signal.connect(self.update_batch_count)
        self.stats = StatsPanel()
        self.stats.executor = self.lod_worker  # the figures of a layer: off this thread
        # The figures follow the map's time window, at most every STATS_WINDOW_MS.
        self._stats_timer = QtCore.QTimer(self, singleShot=True, interval=STATS_WINDOW_MS)
        self._stats_timer.timeout.connect(self._update_stats)
        self.detail = DetailPanel()
        self.bearing_view = BearingView()
        self.bearing_view.executor = self.lod_worker  # a new length's scene: off this thread
        self.time_controller.attach_bearing_view(self.bearing_view)  # the window cuts it too
        self.bearing_view.length_changed.connect(self.bearing_length_changed)
        self.log = QtWidgets.QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(5000)
        self._build_docks(batch_box)

        self.progress = QtWidgets.QProgressBar()
        self.progress.setMaximumWidth(260)
        self.progress.setRange(0, 1000)
        self.progress.hide()
        self.cancel_button = QtWidgets.QToolButton()
        self.cancel_button.clicked.connect(self.cancel_jobs)
        self.cancel_button.hide()
        self.cursor_label = QtWidgets.QLabel()
        # What the pointer is over (a track's point): its own label, cleared after
        # HOVER_MS; in the message area it took the counts' place, and they were gone
        # when it expired (operator look h225 item 6).
        self.hover_label = QtWidgets.QLabel()
        self.hover_label.setMinimumWidth(1)  # a long text is cut, never widens the window
        self._hover_timer = QtCore.QTimer(self, singleShot=True, interval=HOVER_MS)
        self._hover_timer.timeout.connect(self.hover_label.clear)
        #: The status bar's counts, shown again whenever a timed message expires.
        self.counts_text = ""
        self.statusBar().messageChanged.connect(self._message_changed)
        # A step the window ran again by itself failed: said until that step runs again
        # (jobs._automatic_failed); the status bar's messages come and go.
        self.stale_label = QtWidgets.QLabel()
        self.stale_label.setStyleSheet("color: #b00000")
        self.stale_label.hide()
        for widget in (
            self.stale_label,
            self.progress,
            self.cancel_button,
            self.hover_label,
            self.cursor_label,
        ):
            self.statusBar().addPermanentWidget(widget)

        build_actions(self)
        self.actions_["cancel"].setEnabled(False)  # on while a job runs (jobs.py)
        self.set_icons()
        self._add_legend_toggle()
        self.review = ReviewDock(self)  # the review dock, its menus and the before map
        # Edit ▸ Restore removed layer / Remove layer again (the layer removals' stack)
        self.layer_undo = LayerUndo(self, self.review.edit_menu)
        self.install_sensor_menu()  # View ▸ Sensors of the active layer
        from wakeline.app.restore_points import install as install_restore

        self.restore_tool = install_restore(self)  # Edit ▸ Restore, the map's right click
        self._fit_timer = QtCore.QTimer(self, singleShot=True, interval=0)
        self._fit_timer.timeout.connect(self.review.fit_to_window)
        self.set_language(self.settings.value("language", i18n.system_language()))
        # Run ▸ Pipeline stages, as the last window left them (a project brings its own);
        # after the language: a name dropped is said in it.
        self.set_pipeline_stages(self.stored_pipeline_stages(), store=False)
        for key, restore in (("geometry", self.restoreGeometry), ("state", self.restoreState)):
            value = self.settings.value(key)
            if value is not None:
                restore(value)
        hide_stray_tab_bars(self)
        #: The columns' widths still to fit the window's width on its first show (the
        #: compact layout, no state restored from the settings).
        self._fit_columns = self.compact and self.settings.value("state") is None

    def _add_legend_toggle(self) -> None:
        """View ▸ Show legend: the map's legend column, on or off (kept in the settings):
        off, the map takes its width (about 200 px of a 659-px map at 1366x768)."""
        action = QtGui.QAction(self, checkable=True)
        shown = self.settings.value("legend", True)
        action.setChecked(shown not in (False, "false", "0", 0))
        action.toggled.connect(self.show_legend)
        self.actions_["legend"] = action
        view = self.menus["view"]
        first_dock = next(iter(self.docks.values())).toggleViewAction()
        view.insertAction(first_dock, action)
        self.canvas.legend.set_shown(action.isChecked())

    def show_legend(self, on: bool = True) -> None:
        """The map's legend shown (or hidden), and kept so for the next start."""
        self.canvas.legend.set_shown(on)
        self.settings.setValue("legend", bool(on))
        if self.actions_["legend"].isChecked() != on:
            self.actions_["legend"].setChecked(on)

    @staticmethod
    def compact_screen(available: QtCore.QRect) -> bool:
        """Whether a screen of ``available`` (its free geometry, logical px) gets the
        compact layout: less than COMPACT_SCREEN_HEIGHT high."""
        return available.height() < COMPACT_SCREEN_HEIGHT

    def arrange_compact(self) -> None:
        """The compact layout: Layers tabbed with Parameters, the batch table with Detail
        (and Bearing-only), the table in front; the left and right columns then ask for
        one dock's height, not two (operator look h225 item 1)."""
        d = self.docks
        if d["params"] not in self.tabifiedDockWidgets(d["layers"]):
            self.tabifyDockWidget(d["layers"], d["params"])
        for key in ("detail", "bearing"):  # one group of three, the table first
            if d[key] not in self.tabifiedDockWidgets(d["batches"]):
                self.tabifyDockWidget(d["batches"], d[key])
        d["layers"].raise_()
        d["batches"].raise_()

    def _build_docks(self, batch_box: QtWidgets.QWidget) -> None:
        area = QtCore.Qt.DockWidgetArea
        self.docks = {}
        for key, widget, where in (
            ("layers", self.layer_list, area.LeftDockWidgetArea),
            ("params", self.params, area.LeftDockWidgetArea),
            ("batches", batch_box, area.RightDockWidgetArea),
            ("detail", self.detail, area.RightDockWidgetArea),
            # in a scroll area: its map and table ask 380x336 at least (h225 item 1)
            ("bearing", scrolled(self.bearing_view), area.RightDockWidgetArea),
            ("stats", self.stats, area.BottomDockWidgetArea),
            ("log", self.log, area.BottomDockWidgetArea),
        ):
            dock = QtWidgets.QDockWidget(self)
            dock.setObjectName(key)
            dock.setWidget(widget)
            self.addDockWidget(where, dock)
            self.docks[key] = dock
        # The right column (batch table, Detail/Bearing-only) runs down to the status
        # bar; the bottom docks (Statistics, Log, Review) sit under the map and the left
        # column. Across the whole width, the Review dock left the batch table one row
        # of 15 at 1400x900 (operator test h150): the right column's docks have least
        # heights (the Bearing-only dock's map and table) that it could not share.
        self.setCorner(QtCore.Qt.Corner.BottomRightCorner, area.RightDockWidgetArea)
        self.tabifyDockWidget(self.docks["stats"], self.docks["log"])
        # The lifetime histogram keeps a readable height while the Statistics tab is up.
        self.docks["stats"].visibilityChanged.connect(self.stats.set_raised)
        self.tabifyDockWidget(self.docks["detail"], self.docks["bearing"])
        self.docks["detail"].raise_()
        self.docks["log"].raise_()
        d = self.docks
        horizontal, vertical = QtCore.Qt.Orientation.Horizontal, QtCore.Qt.Orientation.Vertical
        screen = self.screen() or QtWidgets.QApplication.primaryScreen()
        self.compact = screen is not None and self.compact_screen(screen.availableGeometry())
        if self.compact:  # before the sizes: tabbing makes the columns again
            self.arrange_compact()
        # 395: the right column as it was at 1400x900 (412 px) while the time panel's
        # controls held the map at 685 px at least; asked 560 with the controls wrapping,
        # the map would be 528 px at 1400x900 on two lines of controls (h179).
        # Compact: narrower columns, the map keeps about half the window at 1366 px
        # (h225 item 7: 659 of 1,366 px); the table's End column still in sight.
        widths = [260, 330] if self.compact else [300, 395]
        self.resizeDocks([d["layers"], d["batches"]], widths, horizontal)
        # The detail/bearing tabs get the larger share of the right column: the bearing
        # dock's map and its detections table under it (a 142-px map, one clipped row).
        self.resizeDocks(
            [d["layers"], d["params"], d["batches"], d["detail"], d["log"]],
            [150, 450, 300, 460, 130],
            vertical,
        )

    # -- texts ---------------------------------------------------------------------

    def update_title(self) -> None:
        """The window title: the project file and whether it is read-only or unsaved."""
        title = self.tr("Wakeline")
        if self.project.path is not None:
            title += f" — {self.project.path.name}"
            if self.project.read_only:
                title += " " + self.tr("[read-only]")
            if self.project.dirty:
                title += " " + self.tr("[not saved]")
        self.setWindowTitle(title)

    def retranslate(self) -> None:
        """Set every visible text (called again when the language changes)."""
        self.update_title()
        retranslate(self)
        if "legend" in self.actions_:
            self.actions_["legend"].setText(self.tr("Show &legend"))
            self.actions_["legend"].setToolTip(
                self.tr("The map's legend column; hidden, the map takes its width")
            )
        self.update_batch_count()
        self.detail.retranslate()
        self.params.retranslate()
        self.stats.retranslate()
        self.bearing_view.retranslate()
        if hasattr(self, "review"):  # built after the first retranslate
            self.review.retranslate()
        if hasattr(self, "layer_undo"):
            self.layer_undo.retranslate()
        if hasattr(self, "sensor_menu"):
            self.retranslate_sensor_menu()
        if hasattr(self, "restore_tool"):
            self.restore_tool.retranslate()
        for row in range(self.layer_list.count()):  # the kinds' tags: [source], [fused] …
            item = self.layer_list.item(row)
            layer = self.session.layers.get(item.data(QtCore.Qt.ItemDataRole.UserRole))
            if layer is not None:
                item.setText(layer_text(layer))
        self.canvas.setLabel("bottom", self.tr("longitude"), units="°")
        self.canvas.setLabel("left", self.tr("latitude"), units="°")
        self.legend_in_language()
        self._update_stats()
        self.restale()

    def set_language(self, code: str) -> None:
        code = code if code in i18n.LANGUAGES else "en"
        app = QtWidgets.QApplication.instance()
        self.translator = i18n.install(app, code, self.translator)
        self.language = code
        self.lang_actions[code].setChecked(True)
        self.settings.setValue("language", code)
        self.retranslate()
        if code in cjk_font.CJK_LANGUAGES:
            self.check_cjk_font()

    #: Whether the window asked the font database for a CJK font (it asks once).
    _cjk_checked = False

    def check_cjk_font(self) -> bool:
        """Whether Chinese text can be drawn (a font covers Simplified Chinese); asked
        the first time the window needs Chinese glyphs (a zh_CN start or switch, a log
        line or loaded data holding Chinese text). Without one, says so once in the log
        and the status bar, naming the package to install (operator test 7, D4: every
        Chinese text was boxes, with no word)."""
        if self._cjk_checked:
            return True
        self._cjk_checked = True
        if cjk_font.has_cjk_font():
            return True
        # English in either language: a Chinese message would be boxes too.
        text = cjk_font.missing_font_text()
        self.log.appendPlainText(f"Warning: {text}")
        self.statusBar().showMessage(text, 60_000)
        return False

    # -- dialogs -------------------------------------------------------------------

    def open_dialog(self) -> None:
        # the read of the first rows (its warnings, quarantine) in the map's worker pool
        dialog = ImportDialog(self, executor=self.lod_worker)
        if dialog.exec() == QtWidgets.QDialog.DialogCode.Accepted:
            self.load_file(**dialog.options())

    def show_import_report(self) -> QtWidgets.QDialog | None:
        """The import report of the active layer's source file."""
        if self.active is None:
            return None
        dialog = ImportReportDialog(self.session.root(self.active), self)
        dialog.show()
        return dialog

    def show_about(self) -> QtWidgets.QDialog:
        """Help ▸ About Wakeline (version, licence, papers, data notices, Qt versions)."""
        dialog = about.AboutDialog(self)
        dialog.show()
        return dialog

    def open_documentation(self) -> Path | None:
        """Help ▸ Documentation: the README (it links every page of docs/) in the
        browser; the log says where it is (all it does without a desktop: offscreen)."""
        path, opened = about.open_documentation()
        if path is None:
            self.log_message(self.tr("Documentation: not installed with this copy of Wakeline"))
        elif opened:
            self.log_message(self.tr("Documentation opened in the browser: {0}").format(path))
        else:
            self.log_message(self.tr("Documentation: {0}").format(path))
        return path

    # -- misc ----------------------------------------------------------------------

    def _update_stats(self) -> None:
        """The Statistics dock: the active layer's figures, computed in the worker
        (:class:`~wakeline.app.stats_panel.StatsPanel`), over the map's time window when
        one is set; the status bar's counts at once."""
        layer = self.active_layer()
        if layer is None:
            self.stats.show_message(self.tr("No layer. File ▸ Open tracks… (Ctrl+O)"))
            return
        if layer.kind == BEARING_KIND:
            self.stats.show_message(bearing_stats(layer, self.tr))
            return
        head = [(self.tr("Layer"), f"{layer_text(layer, ' ')}  ({layer.id})")]
        if layer.parent:
            parent = self.session.get(layer.parent)
            source = shown_name(parent.name) if parent else layer.parent
            # the step and its input; when, in a row of its own (elided in the middle
            # beside the input's name it read "vessel_3_id...-12-05T22:12:47Z": D7)
            head.append((self.tr("Made by"), f"{shown(layer.step)} ← {source}"))
            made_at = str(layer.created).replace("T", " ").removesuffix("Z")
            head.append((self.tr("Made at"), f"{made_at} UTC" if made_at else "–"))
        head += self._result_rows(layer)
        tw = self.session.time_window
        window = (tw.start_s, tw.end_s) if tw is not None else None
        key = (layer.id, id(layer.points), len(layer.points), window)
        self.stats.compute(key, layer.points, dict(layer.tables), window, head)
        self._show_counts_text(self.counts_message(layer, window))

    def counts_message(self, layer, window: tuple[float, float] | None) -> str:
        """The status bar's counts: the layer's points and tracks; with a time window,
        what the window shows of them: "In the time window: 0 of 1 track, 0 of 1,131
        points" (its tracks counted as the batch table counts them, those whose span
        overlaps the window; operator test 8, D4: the table said "0 of 1" while the
        status bar still said "1,131 points, 1 track")."""
        view = self.views.get(layer.id)
        tracks = len(view.summary) if view is not None else 0
        # View ▸ Sensors: what the window shows of the layer (its sensors shown)
        note = self.sensors_note(layer)
        points = view.points if note and view is not None else layer.points
        text = self.tr("{0}, {1}").format(points_text(len(points)), tracks_text(tracks))
        overlap = self.batch_model.tracks_overlapping(window) if view is not None else None
        if overlap is None or window is None:
            return f"{text} ({note})" if note else text
        inside = points_inside(points, window)
        text = self.tr("In the time window: {0} of {1}, {2} of {3}").format(
            f"{overlap:,}", tracks_text(tracks), f"{inside:,}", points_text(len(points))
        )
        return f"{text} ({note})" if note else text

    def show_counts(self) -> None:
        """The status bar's counts of the active layer now (the time window moved: the
        batch table's count changed at once, the Statistics dock follows on its timer)."""
        layer = self.active_layer()
        if layer is None or layer.kind == BEARING_KIND:
            return
        tw = self.session.time_window
        window = (tw.start_s, tw.end_s) if tw is not None else None
        self._show_counts_text(self.counts_message(layer, window))

    def _show_counts_text(self, text: str) -> None:
        self.counts_text = text
        self.statusBar().showMessage(text)

    def _message_changed(self, text: str) -> None:
        """A timed message expired (or was cleared): the counts come back; they were
        gone for good 4 s after a hover or a job's "done" (operator look h225 item 6)."""
        if not text and self.counts_text:
            layer = self.active_layer()
            if layer is None or layer.kind == BEARING_KIND:
                self.counts_text = ""
                return
            # on the next turn: QStatusBar is still clearing its message here
            QtCore.QTimer.singleShot(0, self, self._restore_counts)

    def _restore_counts(self) -> None:
        if self.counts_text and not self.statusBar().currentMessage():
            self.statusBar().showMessage(self.counts_text)

    def show_hover(self, info) -> None:
        """What the pointer is over, in the status bar's hover label for HOVER_MS."""
        if not info:
            return
        speed = info.get("speed_kn")
        speed_text = "" if speed is None or speed != speed else f", {speed:.1f} kn"
        self.hover_label.setText(
            f"{info.get('sensor')} / {info.get('batch')}: {info.get('time')}{speed_text}"
        )
        self._hover_timer.start()

    def fit_batch_columns(self) -> None:
        """The batch table's Sensor column hidden while the layer has one sensor: its
        width went to a column that says the same on every row, and End sat behind the
        scroll bar at every window size (h225 item 16; the columns' widths:
        window_layers._fit_time_columns)."""
        frame = self.batch_model.frame
        one = len(frame) > 0 and "sensor" in frame.columns and frame["sensor"].nunique() <= 1
        self.batch_view.setColumnHidden(0, bool(one))

    def update_batch_count(self) -> None:
        """The line under the batch table: how many tracks it shows and why not all."""
        shown, total = self.batch_model.counts()
        filtered, windowed = self.batch_model.shown_because()
        if not (filtered or windowed):
            self.batch_count.setText(tracks_text(total))
            return
        why = []
        if filtered:
            why.append(self.tr("matching the filter"))
        if windowed:
            why.append(self.tr("whose time span overlaps the time window"))
        those = self.tr(" and ").join(why)
        if total == 1:
            self.batch_count.setText(self.tr("{0} of 1 track: those {1}").format(shown, those))
            return
        self.batch_count.setText(
            self.tr("{0} of {1} tracks: those {2}").format(f"{shown:,}", f"{total:,}", those)
        )

    def _result_rows(self, layer) -> list[tuple[str, str]]:
        """The Statistics dock's rows for what a step did: Dis_e, the maneuver threshold,
        and the points clean removed and changed, rule by rule (was one "rejected" count
        that mixed the two: ATD dataset1 "rejected 43638" beside 102,861 → 59,502 points,
        whose difference is the 43,359 removed; the 279 changed are kept)."""
        meta, rows = layer.meta, []
        if meta.get("dis_e_m") is not None:
            label = self.tr("Dis_e (mean synchronized distance)")
            rows.append((label, self.tr("{0} m").format(f"{meta['dis_e_m']:,.1f}")))
        if meta.get("threshold_deg") is not None:
            rows.append((self.tr("Maneuver threshold"), f"{meta['threshold_deg']:g}°"))
        labels = {
            "removed": self.tr("Removed by clean"),
            "changed": self.tr("Changed by clean (kept, new values)"),
            "replaced": self.tr("Replaced by clean"),
        }
        counts = meta.get("clean_counts")
        rejected = layer.tables.get("rejected")
        if (
            counts is None  # a project saved before the step kept its counts
            and isinstance(rejected, pd.DataFrame)
            and {"rule", "action"} <= set(rejected.columns)
        ):
            per = rejected.groupby(["action", "rule"], sort=False).size()
            counts = {a: dict(p.droplevel(0).items()) for a, p in per.groupby(level=0, sort=False)}
        if counts:
            for action, per in counts.items():
                # each rule by its name in the window's language (as the log says it)
                rules = self.tr(", ").join(f"{shown(rule)} {n:,}" for rule, n in per.items())
                label = labels.get(action, action)
                rows.append((label, f"{sum(per.values()):,} ({rules})"))
        elif meta.get("rejected") is not None:
            rows.append((self.tr("Removed or changed by clean"), f"{meta['rejected']:,}"))
        return rows

    def log_message(self, text: str) -> None:
        text = shown(text)
        self.log.appendPlainText(text)
        if not self._cjk_checked and cjk_font.needs_cjk(text):
            self.check_cjk_font()  # a file's Chinese headers quoted in an English window

    def log_lines(self, head: str, lines: list[str]) -> None:
        """``head: line`` for one line; ``head:`` and the lines indented under it for more
        (a pipeline's stages)."""
        if len(lines) == 1:
            self.log_message(self.tr("{0}: {1}").format(head, lines[0]))
            return
        self.log_message(self.tr("{0}:").format(head))
        for line in lines:
            self.log_message(f"    {line}")

    def _show_cursor(self, lon: float, lat: float) -> None:
        lon = float(geo.wrap180(lon))  # tracks across 180° are drawn on past it
        self.cursor_label.setText(
            f"{lon:.5f}°, {lat:.5f}°   {format_dms(lat, 'N', 'S')} {format_dms(lon, 'E', 'W')}"
        )

    def _save_failed(self, message: str) -> None:
        """A write to the project failed: logged each time, one dialog (the first since
        the file was saved or opened — not one per change); closing offers Save as."""
        text = self.tr("Saving the project failed: {0}").format(shown(message))
        if not self.project.repeated:  # the other writes of the same change: said once
            self.log_message(f"{self.tr('Error')}: {text}")
        self.update_title()
        if self.project.failures == 1:
            self.tell(self.tr("Project not saved"), text)

    def set_icons(self) -> None:
        """The toolbar's one-colour icons for the palette now (palette_icon); on a dark
        one, the filter's placeholder in the text colour too (h225 item 15)."""
        sp = QtWidgets.QStyle.StandardPixmap
        for key, pixmap in (("pipeline", sp.SP_MediaPlay), ("fit", sp.SP_TitleBarMaxButton)):
            self.actions_[key].setIcon(palette_icon(self, pixmap))
        palette = self.filter_edit.palette()
        if dark_palette(self.palette()):
            hint = palette.color(QtGui.QPalette.ColorRole.Text)
            hint.setAlpha(170)
            palette.setColor(QtGui.QPalette.ColorRole.PlaceholderText, hint)
            self.filter_edit.setPalette(palette)
        else:
            self.filter_edit.setPalette(QtGui.QPalette())

    def changeEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().changeEvent(event)
        if event.type() == QtCore.QEvent.Type.PaletteChange and hasattr(self, "actions_"):
            self.set_icons()

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().showEvent(event)
        if self._fit_columns:
            self._fit_columns = False
            QtCore.QTimer.singleShot(0, self, self.fit_columns)

    def fit_columns(self) -> None:
        """The compact layout's side columns as shares of the window's width (the map
        keeps about half of it): at 960 px, 260 and 330 px left the map 360 px, half of
        it the legend (h225 item 7)."""
        width = self.width()
        self.resizeDocks(
            [self.docks["layers"], self.docks["batches"]],
            [round(COMPACT_LEFT_SHARE * width), round(COMPACT_RIGHT_SHARE * width)],
            QtCore.Qt.Orientation.Horizontal,
        )
        # the bottom docks (Statistics, Log) a smaller share of a short window's height
        self.resizeDocks(
            [self.docks["log"]],
            [round(COMPACT_BOTTOM_SHARE * self.height())],
            QtCore.Qt.Orientation.Vertical,
        )

    def resizeEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().resizeEvent(event)
        # Smaller: the Review dock gives the map back its share once the layout settled
        # (ReviewDock.fit_to_window); a timer, so that a drag's sizes make one fit.
        if event.size().height() < event.oldSize().height() and hasattr(self, "review"):
            self._fit_timer.start()

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt API
        if (self.project.unsaved or self.project.dirty) and not self._close_unsaved():
            event.ignore()
            return
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("state", self.saveState())
        self.runner.cancel()
        self.runner.wait(5000)
        self._job_fns.clear()  # the job's function, kept to run it again, holds its inputs
        self._export_queue.clear()  # a file being written is finished (or cancelled)
        if not self.export_runner.wait(30_000):
            self.export_runner.cancel()  # its partial file is removed
            self.export_runner.wait(5000)
        self.review.close()
        self.time_panel.pause()  # no frame asked for after the map's jobs are through
        self.time_controller.overlay.stop()  # nor one queued behind the running one
        self.lod_worker.wait(5000)
        if self.view_keeper.pending:  # the last zoom is kept too
            self.view_keeper.store()
        if self.time_controller.time_pending:  # and the slider's last move
            self.time_controller.store_time()
        self.project.detach()
        # Nothing of the work stays in memory: the window's objects were frozen at start
        # (main.freeze_startup_objects) and a closed window is not collected (nor, in the
        # tests, deleted windows: conftest), so its layers, their prepared views and what the
        # map drew of them are let go here, by reference (defect #8: a second window held
        # the first one's 2 GB).
        self.session.clear()
        give_back_free_memory()  # and what the allocators kept of it goes back to the system
        super().closeEvent(event)

    def _close_unsaved(self) -> bool:
        """Changes are not all in a file — the project was opened read-only (open
        elsewhere, or not writable), or a write failed (the file moved, a full disk, a
        failed Save as): offer Save as before closing. False keeps the window open."""
        if not getattr(self, "interactive", True):  # nobody to answer (a screenshot)
            return True
        buttons = QtWidgets.QMessageBox.StandardButton
        if self.project.dirty:
            text = self.tr(
                "Some changes could not be written to the project file (see the log). "
                "Save the work as a new project before closing?"
            )
        else:
            text = self.tr(
                "This project was opened read-only, so the changes made since are not in "
                "any file. Save them as a new project before closing?"
            )
        answer = QtWidgets.QMessageBox.question(
            self,
            self.tr("Changes not saved"),
            text,
            buttons.Save | buttons.Discard | buttons.Cancel,
        )
        if answer == buttons.Cancel:
            return False
        if answer == buttons.Save:
            self.save_project_dialog()
            return not (self.project.unsaved or self.project.dirty)
        return True


__all__ = ["MainWindow", "format_dms", "maneuver_table", "Path", "EMPTY"]

"""The time dimension on the map (issue 13): every visible track's position at the time
slider's ``t`` (one scatter item) with a trail of the last minutes (one NaN-separated
curve), and the time window that hides points outside [from, to].

The pure functions here run in a worker: :func:`index_job` builds the
:class:`~wakeline.core.timeline.TimeIndex` over the visible layers once, and
:func:`window_draw_data` cuts a layer's geometry to the window and redoes its level of
detail. A frame on the GUI thread is two ``searchsorted`` calls over the index
(:meth:`TimeIndex.positions_at`, :meth:`TimeIndex.trail`) and two ``setData``.
:class:`TimeController` joins the main window, the :class:`~wakeline.app.time_panel.TimePanel`
and the map.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore

from wakeline.app.layer_names import shown_name
from wakeline.app.layer_view import PART_SEP, is_part_of
from wakeline.app.map_draw import Curve, DrawData, LayerGeometry, prepare_layer
from wakeline.app.map_marks import MarkerItem, render_marks
from wakeline.app.map_paths import SpriteCurve, render_sprite
from wakeline.core.sorted_sets import repeat_runs
from wakeline.core.timeline import TimeIndex, build_index, mask_rows

TRAIL_COLOR = "#202020"
#: Trails wider than 1 px only up to this many vertices: Qt's raster engine draws a wide
#: (or translucent) pen several times slower (see map_canvas).
WIDE_MAX = 20_000
#: Beyond this many markers they are drawn smaller (a busy harbour stays readable).
MANY_MARKERS = 500
#: No window of the session waits for the panel (:attr:`TimeController._restore`).
_NO_RESTORE = object()
#: The slider's time is written to the session (and so the project) this long (ms) after
#: its last move: once a drag or the playback settles, never once per frame.
SETTLE_MS = 400
#: A frame is made again for a panned or zoomed map this long (ms) after its last move.
VIEW_MS = 80


def thin_to_pixels(
    lon: np.ndarray, lat: np.ndarray, px: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """A NaN-separated curve without the vertices that fall in the pixel of the vertex
    before them (``px`` = pixel size in degrees); the first and last vertex of every
    piece are kept, so no piece gets shorter than a pixel."""
    if len(lon) < 3 or not (px[0] > 0 and px[1] > 0):
        return lon, lat
    with np.errstate(invalid="ignore"):
        ix = np.floor(lon / px[0])
        iy = np.floor(lat / px[1])
    gap = np.isnan(lon)
    keep = np.ones(len(lon), dtype=bool)
    keep[1:] = (ix[1:] != ix[:-1]) | (iy[1:] != iy[:-1])
    keep |= gap
    keep[1:] |= gap[:-1]  # first vertex of a piece
    keep[:-1] |= gap[1:]  # last vertex of a piece
    keep[-1] = True
    return lon[keep], lat[keep]


@dataclass(frozen=True)
class TimeScene:
    """What the overlay draws from: the index, a colour code per track and the colours,
    and whether times are elapsed from a scene start (MTAD) rather than dates."""

    index: TimeIndex
    color_of_track: np.ndarray
    colors: tuple[str, ...]
    relative: bool


def one_clock(geometries: dict[str, LayerGeometry], active: str | None) -> list[LayerGeometry]:
    """The layers the time slider runs over: all of them when their times are all dates or
    all elapsed from a scene start (MTAD); when both kinds are open, those of the active
    layer's kind (else of the most layers): seconds from a scene start on a slider of
    dates ran it from 1970 to now. ``geometries`` by map layer name; ``active``: a session
    layer id, drawn as the map layer of its id or as parts (``L3/observer``)."""
    kinds = {name: g.relative for name, g in geometries.items()}
    if len(set(kinds.values())) < 2:
        return list(geometries.values())
    mine = [k for name, k in kinds.items() if active is not None and is_part_of(name, active)]
    keep = mine[0] if mine else sum(kinds.values()) * 2 > len(kinds)
    return [g for name, g in geometries.items() if kinds[name] == keep]


def left_out(geometries: dict[str, LayerGeometry], kept: list[LayerGeometry]) -> tuple[int, bool]:
    """The layers :func:`one_clock` leaves off the slider: how many (session layers, a
    layer drawn in parts counted once) and whether their times are elapsed from a scene
    start (``T+…``; else dates). (0, False) when every layer is on it (operator test 8,
    D4: the slider over dates left an MTAD scene out and nothing said so)."""
    ids = {id(g) for g in kept}
    out = {
        name.split(PART_SEP, 1)[0]: g.relative for name, g in geometries.items() if id(g) not in ids
    }
    if not out:
        return 0, False
    return len(out), bool(next(iter(out.values())))


def index_job(geometries: list[LayerGeometry]) -> TimeScene:
    """The time index over the tracks of ``geometries`` (pure; for a worker)."""
    colors: list[str] = []
    codes = []
    for g in geometries:
        base = len(colors)
        colors.extend(g.colors)
        codes.append(base + np.asarray(g.group, dtype="int64")[np.asarray(g.ends) > g.starts])
    index = build_index([(g.time_s, g.lon, g.lat, g.starts, g.ends) for g in geometries])
    relative = bool(geometries) and all(g.relative for g in geometries)
    code = np.concatenate(codes) if codes else np.zeros(0, dtype="int64")
    return TimeScene(index, code, tuple(colors), relative)


def window_geometry(g: LayerGeometry, t_from: float, t_to: float) -> LayerGeometry:
    """``g`` with only the points whose time lies in [t_from, t_to] (s); tracks with no
    such point drop out."""
    return geometry_rows(g, (g.time_s >= t_from) & (g.time_s <= t_to))


def geometry_rows(g: LayerGeometry, keep: np.ndarray) -> LayerGeometry:
    """``g`` with only the points ``keep`` (bool per point); tracks with none drop out
    (curves, colours and labels kept)."""
    rows, kept, starts, ends = mask_rows(keep, g.starts, g.ends)
    return LayerGeometry(
        lon=g.lon[rows],
        lat=g.lat[rows],
        starts=starts,
        ends=ends,
        track=repeat_runs(None, ends - starts),
        sensor=g.sensor[kept],
        batch=g.batch[kept],
        time_s=g.time_s[rows],
        speed_kn=g.speed_kn[rows],
        group=g.group[kept],
        labels=g.labels,
        colors=g.colors,
        relative=g.relative,
        point_batch=None if g.point_batch is None else g.point_batch[rows],
        lon_west=g.lon_west,
    )


def window_draw_data(
    data: DrawData,
    window: tuple[float, float] | None,
    view: tuple[float, float, float, float] | None,
    size_px: tuple[int, int] | None,
    cut: Callable[[tuple[float, float]], LayerGeometry] | None = None,
) -> DrawData:
    """A layer's draw data cut to ``window`` (None: the whole layer), its level of detail
    done for ``view`` and its hover index built (pure; for a worker). ``cut(window)``:
    the layer's own cut (a bearing layer's lines: chosen again among every bearing of the
    window, :func:`~wakeline.app.bearing_view.window_lines`); its legend labels are the
    layer's."""
    if window is None:
        geom = data.geometry
    elif cut is not None:
        geom = replace(cut(window), labels=data.geometry.labels)
    else:
        geom = window_geometry(data.geometry, *window)
    out = prepare_layer(geom, data.name, style=data.style, view=view, size_px=size_px)
    return replace(out, name=data.name)


def marker_size(n: int) -> float:
    """The markers' size (px) when ``n`` are shown: smaller beyond :data:`MANY_MARKERS`."""
    return 10.0 if n <= MANY_MARKERS else 6.0


def trail_width(n: int) -> float:
    """The trail's pen (px) for ``n`` vertices: 1 px beyond :data:`WIDE_MAX`."""
    return 3.0 if n <= WIDE_MAX else 1.0


@dataclass(frozen=True)
class Frame:
    """What one time step draws: the tracks alive at ``t``, their positions, the trail;
    made in a worker for a view: the trail's painter path and the trail and markers
    drawn into images of that view (None: the paint draws them from the arrays)."""

    t: float
    tracks: np.ndarray
    lon: np.ndarray
    lat: np.ndarray
    trail_lon: np.ndarray
    trail_lat: np.ndarray
    trail_path: object = field(default=None, compare=False, repr=False)
    trail_sprite: object = field(default=None, compare=False, repr=False)
    marks_sprite: object = field(default=None, compare=False, repr=False)
    #: The colour code of every position (an index into ``colors``), or None.
    codes: np.ndarray | None = field(default=None, compare=False, repr=False)
    colors: tuple[str, ...] = ()


def frame_job(
    index: TimeIndex,
    t: float,
    trail_s: float,
    px: tuple[float, float],
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[float, float] | None = None,
    colors: tuple[np.ndarray, tuple[str, ...]] | None = None,
    dpr: float = 1.0,
) -> Frame:
    """Positions at ``t`` and the trails thinned to the pixel ``px`` (pure; a worker);
    ``colors``: the colour code of every track of ``index`` and the colours (the
    :class:`TimeScene`'s), each position's marker in its track's (its layer's) colour.
    With ``view`` and ``size_px`` (the map's range and plot size, logical px) and ``dpr``
    (the map's device pixel ratio): the trail's path, and the trail and markers drawn
    into images of that view at that ratio (:mod:`map_paths`, :mod:`map_marks`), so the
    GUI thread only copies them (on a high-DPI screen too)."""
    tracks, lon, lat = index.positions_at(t)
    tl, ta = thin_to_pixels(*index.trail(t, trail_s), px)
    codes, names = None, ()
    if colors is not None and len(colors[1]):
        codes, names = np.asarray(colors[0], dtype="int64")[tracks], tuple(colors[1])
    frame = Frame(float(t), tracks, lon, lat, tl, ta, codes=codes, colors=names)
    if view is None or size_px is None:
        return frame
    path = pg.arrayToQPath(tl, ta, connect="finite") if len(tl) else None
    trail_sprite = None
    if len(tl):
        antialias = bool(pg.getConfigOption("antialias"))
        curve = Curve("trail", TRAIL_COLOR, tl, ta)
        width = trail_width(len(tl))
        trail_sprite = render_sprite(curve, view, size_px, width, antialias, dpr=dpr)
    size = marker_size(len(tracks))
    if names:
        marks = render_marks(lon, lat, view, size_px, size, codes, names, dpr)
    else:
        marks = render_marks(lon, lat, view, size_px, size, dpr=dpr)
    return replace(frame, trail_path=path, trail_sprite=trail_sprite, marks_sprite=marks)


def guarded(job):
    """``job`` returning None instead of raising (the worker would drop the callback,
    and a waiting overlay or controller would wait for ever)."""

    def run():
        try:
            return job()
        except Exception:  # noqa: BLE001 - a failed frame or cut keeps the old drawing
            return None

    return run


class TimeOverlay(QtCore.QObject):
    """The markers at ``t`` (:class:`~wakeline.app.map_marks.MarkerItem`) and the trails
    (one curve) on a MapCanvas.

    With an ``executor`` (the map's LOD worker protocol) frames are computed in a worker
    and the latest wanted time wins: a slider dragged fast never queues frames, a result
    for an older time than one asked since is dropped; the worker also builds the
    trail's path and draws the trail and the markers into images of the view, so a frame
    costs the GUI thread two ``setData`` of arrays and two image copies. A pan or zoom
    asks for the frame again for the new view (the paint draws from the arrays until it
    arrives). Without an executor, :meth:`show_at` draws at once. ``drawn(t)`` follows
    every swapped-in frame.
    """

    drawn = QtCore.Signal(float)

    def __init__(self, canvas: pg.PlotWidget, executor=None) -> None:
        super().__init__(canvas)
        self.canvas = canvas
        self.executor = executor
        self.trail = SpriteCurve(pen=pg.mkPen(TRAIL_COLOR, width=1.5), connect="finite")
        self.trail.setZValue(70)
        # Drawn from arrays (pyqtgraph's scatter does Python work per spot).
        self.markers = MarkerItem(size=10)
        self.markers.setZValue(71)
        for item in (self.trail, self.markers):
            canvas.addItem(item, ignoreBounds=True)
        # The slider's time, at the view's top left while the Positions markers show:
        # the markers are the ships at this time, the lines every time (h225 item 18).
        self.clock = pg.TextItem(
            color="#202020", fill=pg.mkBrush(255, 236, 140, 225), border=pg.mkPen("#8a7a20")
        )
        self.clock.setParentItem(canvas.vb)
        self.clock.setPos(6, 6)
        self.clock.setZValue(80)
        self.clock.hide()
        self.scene: TimeScene | None = None
        self.shown_tracks = np.zeros(0, dtype="int64")
        self._wanted: tuple | None = None
        self._running = False
        self._asked = 0  # frames asked for; a result older than the last drawn is dropped
        self._shown_ask = 0
        self._last: tuple[float, float] | None = None  # (t, trail_s) last asked for
        self._stopped = False  # the window closed: no frame asked for or drawn
        # A pan, zoom or resize: the frame again for the new view, once it settles.
        self._view_timer = QtCore.QTimer(self)
        self._view_timer.setSingleShot(True)
        self._view_timer.setInterval(VIEW_MS)
        self._view_timer.timeout.connect(self._view_changed)
        if executor is not None:
            canvas.vb.sigRangeChanged.connect(lambda *_: self._view_timer.start())
            canvas.vb.sigResized.connect(lambda *_: self._view_timer.start())

    @property
    def busy(self) -> bool:
        return self._running or self._wanted is not None or self._view_timer.isActive()

    def set_scene(self, scene: TimeScene | None) -> None:
        self.scene = scene
        if scene is None:
            self.clear()

    def clear(self) -> None:
        self._wanted = None
        self._asked += 1  # a frame under way is dropped on arrival
        self._shown_ask = self._asked
        self.markers.setData([], [])
        self.trail.setData([], [])
        self.trail.sprite = None
        self.shown_tracks = np.zeros(0, dtype="int64")

    def stop(self) -> None:
        """No frame after this (the window closes): the one wanted next is dropped, the
        one under way is dropped on arrival, and neither a view change nor a time asks
        for another (a frame queued behind the running one was drawn after the close)."""
        self._stopped = True
        self._wanted = None
        self._view_timer.stop()
        self._asked += 1
        self._shown_ask = self._asked
        self.scene = None  # its arrays are the layers' size: not kept by a closed window

    def show_at(self, t: float, trail_s: float) -> None:
        """Draw every track's position at ``t`` (s) and its last ``trail_s`` seconds."""
        if self._stopped:
            return
        self._last = (float(t), float(trail_s))
        if self.scene is None:
            self.clear()
            return
        vb = self.canvas.vb
        self._asked += 1
        colors = (self.scene.color_of_track, self.scene.colors)
        if self.executor is None:
            px = vb.viewPixelSize()
            self._wanted = (self.scene.index, float(t), float(trail_s), px, None, None, colors)
            self._apply(frame_job(*self._take()), self._asked)
            return
        (x0, x1), (y0, y1) = vb.viewRange()
        r = vb.rect()  # the area the view is mapped onto (fractional: the map's scale)
        size = (max(float(r.width()), 1.0), max(float(r.height()), 1.0))
        view = (float(x0), float(x1), float(y0), float(y1))
        dpr = self.device_ratio()  # drawn at it (a high-DPI screen)
        px = vb.viewPixelSize()
        self._wanted = (self.scene.index, float(t), float(trail_s), px, view, size, colors, dpr)
        if not self._running:
            self._submit()

    def device_ratio(self) -> float:
        """The map's device pixels per logical pixel (> 1 on a high-DPI screen)."""
        return float(self.canvas.devicePixelRatioF())

    def _view_changed(self) -> None:
        if self._last is not None and self.scene is not None and self.markers.isVisible():
            self.show_at(*self._last)

    def _take(self) -> tuple:
        wanted, self._wanted = self._wanted, None
        return wanted

    def _submit(self) -> None:
        args = self._take()
        ask = self._asked
        self._running = True
        self.executor(guarded(lambda: frame_job(*args)), lambda f: self._done(f, ask))

    def _done(self, frame: Frame | None, ask: int) -> None:
        self._running = False
        if self._wanted is not None:
            self._submit()  # a newer time arrived meanwhile: draw that one next
        if self.scene is not None and frame is not None:
            self._apply(frame, ask)

    def _apply(self, frame: Frame, ask: int) -> None:
        if ask < self._shown_ask:
            return  # stale: a newer frame (or a clear) is on the map already
        self._shown_ask = ask
        self.shown_tracks = frame.tracks
        size = marker_size(len(frame.tracks))
        if self.markers.opts["size"] != size:
            self.markers.setSize(size)
        self.markers.setData(frame.lon, frame.lat, frame.marks_sprite, frame.codes, frame.colors)
        width = trail_width(len(frame.trail_lon))
        if self.trail.opts["pen"].widthF() != width:
            self.trail.setPen(pg.mkPen(TRAIL_COLOR, width=width))
        self.trail.setData(frame.trail_lon, frame.trail_lat, connect="finite")
        if frame.trail_path is not None:  # built in the worker: the paint only strokes
            self.trail.path = frame.trail_path
        self.trail.sprite = frame.trail_sprite  # drawn in the worker: the paint copies it
        self.drawn.emit(frame.t)

    def set_visible(self, on: bool) -> None:
        self.markers.setVisible(on)
        self.trail.setVisible(on)
        self.clock.setVisible(on and bool(self.clock.textItem.toPlainText()))

    def set_clock(self, text: str) -> None:
        """The slider's time as the markers show it ("Positions at …"); hidden while the
        markers are."""
        self.clock.setText(text)
        self.clock.setVisible(bool(text) and self.markers.isVisible())


class TimeController(QtCore.QObject):
    """Keeps the time panel, the map overlay, the map's window filter and the batch
    table's time filter in step with the main window's visible layers.

    The index is rebuilt in a worker after the layers change (once their drawing is
    through); a window change cuts every visible layer in a worker and swaps the results
    in. ``window`` is the main window (its ``views``, ``session``, ``canvas``,
    ``batch_model``, ``lod_worker``, ``drawing`` and ``layersChanged``).

    The window is the session's (``Session.time_window``, saved in the project): the
    panel's changes are written to it, and a window the session gets otherwise (a project
    opened) is set on the panel once the slider spans the new layers. The slider's time is
    the session's too (``Session.current_time``): written once it settles
    (:data:`SETTLE_MS` after its last move, not while playing; :meth:`store_time` at once
    for Save as and closing), and set on the slider like the window.
    """

    scene_ready = QtCore.Signal()
    #: The panel's window is on the maps: emitted once every job of a window change is
    #: through (at once when it needed none).
    window_applied = QtCore.Signal()

    def __init__(self, window, panel) -> None:
        super().__init__(window)
        self.window, self.panel = window, panel
        self.overlay = TimeOverlay(window.canvas, window.lod_worker)
        self._gen = 0
        self._filtered: dict[str, tuple] = {}  # layer id -> (window, geometry it was cut from)
        self._dock = None  # the Bearing-only dock (attach_bearing_view)
        self._dock_cut: dict | None = None  # its scene and the window it is cut to
        self._pending = 0
        self._window_owed = False  # window_applied owed once no job is pending
        self._indexing: int | None = None  # the rebuild whose index is being made
        # A window the session got (a project opened), for the panel after the rebuild.
        self._restore: object = _NO_RESTORE
        # The clock of the last scene with tracks (scene times or dates; None: none yet).
        self._clock: bool | None = None
        self._writing = False  # the panel's window being written to the session
        self._restore_t: object = _NO_RESTORE  # the session's slider time, for the panel
        # The slider's time (s) and clock when every layer was hidden, for the next span.
        self._kept_t: tuple[float, bool] | None = None
        self._time_timer = QtCore.QTimer(self)  # the slider's time, once it settles
        self._time_timer.setSingleShot(True)
        self._time_timer.setInterval(SETTLE_MS)
        self._time_timer.timeout.connect(self._time_settled)
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(50)
        self._timer.timeout.connect(self._rebuild)
        window.layersChanged.connect(self._timer.start)
        # A layer's drawing swapped in without a layer change (restyled: View ▸ Colour
        # tracks … apart, as points; its sensors filtered): cut to the window again.
        self._recut = QtCore.QTimer(self)
        self._recut.setSingleShot(True)
        self._recut.setInterval(50)
        self._recut.timeout.connect(self._recut_now)
        window.activeChanged.connect(self._active_changed)
        panel.time_changed.connect(self._draw)
        panel.time_changed.connect(lambda _t: self._time_timer.start())
        # Paused: written once it settles (a late timer skipped while playing).
        panel.play_button.toggled.connect(lambda on: on or self._time_timer.start())
        panel.trail_changed.connect(lambda: self._draw(panel.time()))
        panel.window_changed.connect(self._window_changed)
        panel.overlay_toggled.connect(self._overlay_toggled)
        window.session.subscribe(self._session_event)

    def attach_bearing_view(self, view) -> None:
        """Cut the Bearing-only dock's map (``view``, a
        :class:`~wakeline.app.bearing_view.BearingView`) to the window as well: at every
        window change and every scene it shows (its ``scene_shown``)."""
        self._dock = view
        view.scene_shown.connect(self._dock_shown)

    @property
    def busy(self) -> bool:
        """A rebuild or a window cut is waiting or running."""
        return (
            self._timer.isActive()
            or self._recut.isActive()
            or self._pending > 0
            or self.overlay.busy
        )

    def layer_swapped(self) -> None:
        """A layer's full drawing was put on the map (the window's drawing queue): once
        the queue is through, the layers whose shown drawing is no more their cut are
        cut again (a restyle swaps in the whole layer and is no layer change)."""
        self._recut.start()

    def _recut_now(self) -> None:
        if self._timer.isActive():
            return  # the rebuild cuts
        if self.window.drawing:
            self._recut.start()
            return
        self._apply_window(self._originals())

    def _originals(self) -> dict[str, tuple[DrawData, object, bool, object]]:
        """The map layers of the visible session layers, by map name: (their full draw
        data, the prepared data it comes from, whether the slider's index runs over it,
        their own cut or None). A bearing layer's parts are cut by the window like point
        layers, its lines chosen again among the bearings of the window (``cut``); only
        its observer joins the index (the slider's span and the observer's position at t:
        a bearing line is two points of one time, a track of no duration)."""
        from wakeline.app.layer_view import map_layers

        out = {}
        for lid, layer in self.window.session.layers.items():
            view = self.window.views.get(lid)
            if not layer.visible or view is None:
                continue
            parts = view.extra.get("parts")
            sources = parts if parts is not None else [view.draw]
            cuts = view.extra.get("cuts", {})
            for data, src in zip(
                map_layers(view, lid, shown_name(layer.name)), sources, strict=True
            ):
                indexed = parts is None or src.name == "observer"
                out[data.name] = (data, src, indexed, cuts.get(src.name) if parts else None)
        return out

    def _rebuild(self) -> None:
        if self.window.drawing:
            self._timer.start()
            return
        self._gen += 1
        gen = self._indexing = self._gen
        originals = self._originals()
        drawn = {
            name: d.geometry
            for name, (d, _, indexed, _) in originals.items()
            if indexed and (d.style.width > 0 or d.style.plots)
        }
        lines = one_clock(drawn, self.window.active)
        self.panel.set_left_out(*left_out(drawn, lines))
        self._run(lambda: index_job(lines), lambda scene: self._scene_done(gen, scene))
        self._apply_window(originals)

    def _active_changed(self) -> None:
        """With dates and scene times both open, the slider follows the active layer's."""
        kinds = {d.geometry.relative for d, *_ in self._originals().values()}
        if len(kinds) > 1:
            self._timer.start()

    def _run(self, job, done) -> None:
        self._pending += 1

        def finish(result) -> None:
            self._pending -= 1
            if result is not None:
                done(result)
            if not self._pending and self._window_owed:
                # every job of the window is through (a stale result dropped counts too)
                self._window_owed = False
                self.window_applied.emit()

        self.window.lod_worker(guarded(job), finish)

    def _scene_done(self, gen: int, scene: TimeScene) -> None:
        if gen != self._gen:
            return
        self._indexing = None
        restore, restore_t = self._restore, self._restore_t
        empty = not scene.index.n_tracks
        if not empty:  # else kept for a slider with a span (a layer shown)
            self._restore = self._restore_t = _NO_RESTORE
        self.overlay.set_scene(None if empty else scene)
        # A scene with no track (every layer hidden) has no clock: the panel keeps the
        # last one, so its window stays and cuts the layers shown again.
        if (
            restore is _NO_RESTORE
            and not empty
            and self._clock is not None
            and scene.relative != self._clock
            and self.panel.time_window() is not None
        ):
            self.panel.set_time_window(None)  # a window on the other clock cut everything
        if empty and self._restore_t is _NO_RESTORE and math.isfinite(self.panel.time()):
            # The slider loses its time with its span: written (a move not yet settled)
            # and kept for the layers shown again.
            self.store_time()
            self._kept_t = (self.panel.time(), bool(self._clock))
        kept = None
        if not empty:
            self._clock = scene.relative
            kept, self._kept_t = self._kept_t, None
        self.panel.set_range(scene.index.bounds(), bool(self._clock))
        if restore is not _NO_RESTORE and not empty:
            self.panel.set_time_window(restore)  # the opened project's: cuts the map
        if restore_t is not _NO_RESTORE and self._restore_t is _NO_RESTORE:
            self.panel.set_time(restore_t)  # the opened project's (within the span)
        elif kept is not None and kept[1] == scene.relative:
            lo, hi = self.panel.time_range()
            if lo <= kept[0] <= hi:
                self.panel.set_time(kept[0])  # where it was before every layer was hidden
        self._draw(self.panel.time())
        self.scene_ready.emit()

    def _session_event(self, event: str, _lid: str) -> None:
        """The session's time window changed (a project opened, a script): the panel
        takes it — after the rebuild under way (or, every layer hidden, once one is
        shown), so the slider spans the new layers first and the new layers are the ones
        cut. Not the panel's own changes written back."""
        if event == "removed" or (event == "current_time" and not self._writing):
            self._kept_t = None  # a layer removed, a project opened, a script
        if event == "current_time":
            self._session_time()
        if event != "time_window" or self._writing:
            return
        window = self.window.session.time_window
        bounds = window.bounds() if window is not None else None
        if (
            self._timer.isActive()
            or self._indexing is not None
            or not math.isfinite(self.panel.time())  # no span (every layer hidden)
        ):
            self._restore = bounds
        elif bounds != self.panel.time_window():
            self.panel.set_time_window(bounds)

    def _session_time(self) -> None:
        """The session's slider time changed (a project opened, a script): the slider
        takes it, after the rebuild under way (as the window). Not the panel's own time
        written back; a move of the slider not yet written is dropped for it."""
        if self._writing:
            return
        self._time_timer.stop()
        t = self.window.session.current_time
        if t is None:  # cleared: nothing to show
            self._restore_t = _NO_RESTORE
        elif (
            self._timer.isActive()
            or self._indexing is not None
            or not math.isfinite(self.panel.time())  # no span yet
        ):
            self._restore_t = t
        elif self.panel.time() != t:
            self._restore_t = _NO_RESTORE
            self.panel.set_time(t)

    @property
    def time_pending(self) -> bool:
        """A move of the slider waits to be written to the session."""
        return self._time_timer.isActive()

    def _time_settled(self) -> None:
        if self.panel.is_playing:
            return  # written when paused (play_button) or at its end, not per frame
        self.store_time()

    def store_time(self) -> None:
        """Write the slider's time to the session now (Save as, closing, once it settles;
        the project writes it). Not while an opened project's time waits for the slider,
        nor when the slider has no time."""
        self._time_timer.stop()
        t = self.panel.time()
        if self._restore_t is not _NO_RESTORE or not math.isfinite(t):
            return
        self._writing = True
        try:
            self.window.session.set_current_time(t)
        finally:
            self._writing = False

    def _draw(self, t: float) -> None:
        if self.panel.overlay_on():
            self.overlay.show_at(t, self.panel.params().trail_min * 60.0)
            text = self.panel.time_label.text()
            self.overlay.set_clock(
                QtCore.QCoreApplication.translate("MainWindow", "Positions at {0}").format(text)
                if text and text != "—"
                else ""
            )

    def _overlay_toggled(self, on: bool) -> None:
        self.overlay.set_visible(on)
        self._draw(self.panel.time())

    def _window_changed(self, window) -> None:
        # The session keeps it (the project writes it: ProjectController).
        self._writing = True
        try:
            self.window.session.set_time_window(window)
        finally:
            self._writing = False
        self.window.batch_model.set_time_window(window)
        if hasattr(self.window, "show_counts"):
            self.window.show_counts()  # the status bar agrees with the table at once
        self._window_owed = True
        self._apply_window(self._originals())
        self._cut_dock()
        if not self._pending:
            self._window_owed = False
            self.window_applied.emit()

    def _apply_window(self, originals: dict[str, tuple[DrawData, object, bool, object]]) -> None:
        """Cut every visible layer to the panel's window (or restore it) in a worker.
        A layer is cut again when the window or its data changed, or when the window
        redrew it from its full data meanwhile."""
        window = self.panel.time_window()
        canvas = self.window.canvas
        view, size = canvas.current_view(), canvas.plot_size_px()
        for lid, (data, source, _indexed, cut) in originals.items():
            old = self._filtered.get(lid)
            if lid not in canvas.layer_names():
                continue
            # A layer on the other clock (scene times beside dates) is never cut.
            same_clock = data.geometry.relative == self.panel._relative
            win = window if same_clock else None
            shown = canvas.draw_data(lid).geometry
            if old is None and win is None:
                continue  # never cut: the canvas shows the full layer
            if (
                old is not None
                and old["win"] == win
                and old["src"] is source
                and (old["shown"] is None or old["shown"] is shown)
            ):
                continue  # cut (or being cut) for this window already
            if win is None:  # back to the full layer: its prepared data, LOD in a worker
                self._filtered.pop(lid, None)
                canvas.set_draw_data(data)
                canvas.refresh_lod([lid])
                continue
            state = {"win": win, "src": source, "shown": None}
            self._filtered[lid] = state
            self._window_owed = True

            def done(result: DrawData, lid=lid, state=state) -> None:
                if self._filtered.get(lid) is not state or lid not in canvas.layer_names():
                    return  # a newer window or layer meanwhile
                canvas.set_draw_data(result)
                state["shown"] = result.geometry

            self._run(lambda d=data, w=win, c=cut: window_draw_data(d, w, view, size, c), done)

    def _dock_shown(self) -> None:
        """The dock drew a scene in full: cut it to the window (when one is set)."""
        self._dock_cut = None
        self._cut_dock()

    def _cut_dock(self) -> None:
        """Cut the dock's scene to the panel's window in a worker, each part as the main
        map cuts its copy (:func:`~wakeline.app.bearing_view.window_scene_layers`), or
        draw it in full again when the window is cleared. A scene on the other clock
        (scene times beside dates) is never cut."""
        from wakeline.app.bearing_view import window_scene_layers

        dock = self._dock
        scene = dock.scene if dock is not None else None
        if scene is None or not scene.layers:
            self._dock_cut = None
            return
        window = self.panel.time_window()
        win = window if scene.layers[0].geometry.relative == self.panel._relative else None
        old = self._dock_cut
        if old is None and win is None:
            return  # drawn in full already
        if old is not None and old["scene"] is scene and old["win"] == win:
            return  # cut (or being cut) for this window already
        if win is None:
            self._dock_cut = None
            dock.draw_layers(scene.layers)
            return
        state = {"scene": scene, "win": win}
        self._dock_cut = state
        self._window_owed = True

        def done(layers: list[DrawData]) -> None:
            if self._dock_cut is not state or dock.scene is not scene:
                return  # a newer window or scene meanwhile
            dock.draw_layers(layers)

        self._run(lambda: window_scene_layers(scene, win), done)

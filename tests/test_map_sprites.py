"""Curves stroked in a worker (sprites): the paint copies them and draws what a stroke
draws; any view they do not fit falls back to stroking; the legend never resizes the map."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtGui, QtWidgets  # noqa: E402

from conftest import canvas_rgb  # noqa: E402
from wakeline.app import map_legend, map_paths  # noqa: E402
from wakeline.app.map_canvas import MapCanvas, sprite_is_stale  # noqa: E402
from wakeline.app.map_draw import LayerStyle, prepare_layer  # noqa: E402
from wakeline.app.map_paths import _chunks, with_paths  # noqa: E402
from wakeline.core import geo  # noqa: E402

pytestmark = pytest.mark.gui

LON0, LAT0 = -135.0, 5.0


def many_tracks(seed: int, n_tracks: int = 150, n_points: int = 200) -> pd.DataFrame:
    """Random-walk tracks in every direction (enough vertices for sprites), rows shuffled."""
    rng = np.random.default_rng(seed)
    heading = rng.uniform(0, 2 * np.pi, n_tracks)[:, None] + rng.normal(
        0, 0.15, (n_tracks, n_points)
    ).cumsum(axis=1)
    step = rng.uniform(60, 200, n_tracks)[:, None]
    x = rng.uniform(-20e3, 20e3, n_tracks)[:, None] + (step * np.sin(heading)).cumsum(axis=1)
    y = rng.uniform(-20e3, 20e3, n_tracks)[:, None] + (step * np.cos(heading)).cumsum(axis=1)
    lon, lat = geo.from_local(x.ravel(), y.ravel(), LON0, LAT0)
    t0 = pd.Timestamp("2024-05-01", tz="UTC")
    df = pd.DataFrame(
        {
            "sensor": "R1",
            "batch": np.repeat(np.arange(n_tracks).astype(str), n_points),
            "time": t0 + pd.to_timedelta(np.tile(np.arange(n_points) * 5, n_tracks), "s"),
            "lon": lon,
            "lat": lat,
        }
    )
    return df.sample(frac=1.0, random_state=seed).reset_index(drop=True)


def ink(rgb: np.ndarray) -> np.ndarray:
    """Saturated pixels: the tracks (not the white background, grey grid or axes)."""
    a = rgb.astype(int)
    return (a.max(axis=2) - a.min(axis=2)) > 60


def shown(qtbot, df: pd.DataFrame, sprites: bool, kind: str = "line") -> MapCanvas:
    """A canvas showing ``df`` with a worker-style executor (run at once), its layer's
    first view made as the window makes it (with or without sprites)."""
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(700, 520)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.lod_executor = lambda job, done: done(job()) if sprites else done(_no_sprites(job()))
    canvas.set_true_aspect(LAT0)
    style = LayerStyle(width=1.3) if kind == "line" else LayerStyle(width=0, symbol_size=4)
    canvas.set_draw_data(prepare_layer(df, "L", "#d62728", style=style))
    canvas.fit()
    qtbot.wait(150)  # the level-of-detail timer
    canvas.refresh_lod()
    qtbot.wait(20)
    return canvas


@pytest.fixture
def sprite_calls(monkeypatch) -> list[bool]:
    """What ``Sprite.draw`` answered during the test (True: the image was copied)."""
    calls: list[bool] = []
    original = map_paths.Sprite.draw

    def spy(self, p, item):
        ok = original(self, p, item)
        calls.append(ok)
        return ok

    monkeypatch.setattr(map_paths.Sprite, "draw", spy)
    return calls


def _no_sprites(data):
    from dataclasses import replace

    return replace(data, curves=tuple(replace(c, sprite=None) for c in data.curves))


@pytest.mark.parametrize(
    ("seed", "chars"),
    [(2, map_legend.RESERVED_CHARS)] + [(1, chars) for chars in range(12, 41)],
)
@pytest.mark.parametrize("kind", ["line", "marks"])
def test_a_sprite_draws_what_the_stroke_draws(qtbot, seed, kind, chars, sprite_calls, monkeypatch):
    """At every legend width (12-40 characters): the plot area's width is then fractional
    in many ways, and a sprite made for its rounded width was copied up to a pixel off
    (fails at 20, 22, 24 before h136)."""
    monkeypatch.setattr(map_legend, "RESERVED_CHARS", chars)
    df = many_tracks(seed)
    if kind == "marks":
        df = df.iloc[::5].reset_index(drop=True)
    with_sprite = shown(qtbot, df, sprites=True, kind=kind)
    data = with_sprite.draw_data("L")
    assert data.view is not None
    assert any(c.sprite is not None for c in data.curves)
    sprite_calls.clear()
    a = canvas_rgb(with_sprite)
    assert sprite_calls and all(sprite_calls), "the sprite was not used for the paint"
    stroked = shown(qtbot, df, sprites=False, kind=kind)
    b = canvas_rgb(stroked)
    ia, ib = ink(a), ink(b)
    assert ib.sum() > 2000  # the scene is drawn at all
    # The same pixels, to within the one-pixel rounding of the image's corner.
    near_b = ib.copy()
    near_b[1:] |= ib[:-1]
    near_b[:-1] |= ib[1:]
    near_b[:, 1:] |= ib[:, :-1]
    near_b[:, :-1] |= ib[:, 1:]
    near_a = ia.copy()
    near_a[1:] |= ia[:-1]
    near_a[:-1] |= ia[1:]
    near_a[:, 1:] |= ia[:, :-1]
    near_a[:, :-1] |= ia[:, 1:]
    assert (ia & ~near_b).sum() <= 0.01 * ia.sum()
    assert (ib & ~near_a).sum() <= 0.01 * ib.sum()


def test_a_pan_beyond_the_sprite_strokes_then_makes_a_new_one(qtbot, sprite_calls):
    df = many_tracks(3)
    canvas = shown(qtbot, df, sprites=True)
    jobs = []
    canvas.lod_executor = lambda job, done: jobs.append((job, done))
    old = canvas.draw_data("L")
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    dx = 0.3 * (x1 - x0)
    canvas.vb.setRange(xRange=(x0 + dx, x1 + dx), yRange=(y0, y1), padding=0)
    view, size = canvas.current_view(), canvas.plot_size_px()
    assert sprite_is_stale(old, view, size)
    sprite_calls.clear()
    before = canvas_rgb(canvas)
    assert sprite_calls and not any(sprite_calls)  # the old image does not cover the view
    assert ink(before).sum() > 1000  # but the stroke drew the tracks meanwhile
    canvas.refresh_lod()
    assert jobs, "no new sprite was asked for"
    job, done = jobs.pop()
    done(job())
    new = canvas.draw_data("L")
    assert not sprite_is_stale(new, canvas.current_view(), canvas.plot_size_px())
    sprite_calls.clear()
    canvas_rgb(canvas)
    assert sprite_calls and all(sprite_calls)


def test_no_sprite_without_a_view_or_for_short_curves():
    df = many_tracks(4, n_tracks=3, n_points=50)
    full = with_paths(prepare_layer(df, "L", style=LayerStyle(width=1)))
    assert full.view is None and all(c.sprite is None for c in full.curves)
    few = with_paths(
        prepare_layer(
            df, "L", style=LayerStyle(width=1), view=(-136, -134, 4, 6), size_px=(300, 300)
        )
    )
    assert all(c.sprite is None for c in few.curves)  # 150 vertices: stroked, cheap


def test_chunks_cut_only_at_separators():
    rng = np.random.default_rng(0)
    lengths = rng.integers(1, 900, 400)
    parts = [np.append(rng.normal(size=n), np.nan) for n in lengths]
    lon = np.concatenate(parts)[:-1]
    pieces = _chunks(lon, 5000)
    assert pieces[0][0] == 0 and pieces[-1][1] == len(lon)
    for (_a, b), (c, _d) in zip(pieces[:-1], pieces[1:], strict=True):
        assert b == c and np.isnan(lon[b - 1])  # each piece ends on a separator
    assert max(b - a for a, b in pieces) <= 5000 + 900
    assert _chunks(lon[:10], 5000) == [(0, 10)]


def test_a_long_layer_name_never_widens_the_legend(qtbot):
    df = many_tracks(5, n_tracks=4, n_points=20)
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(900, 500)
    canvas.show()
    qtbot.waitExposed(canvas)
    width = canvas.legend.width()
    vb = canvas.vb.rect().width()
    for k, name in enumerate(
        ["a", "W" * 60, "radar export 2024-05-01 · cleaned · compressed · maneuvers", "船" * 40]
    ):
        canvas.set_draw_data(prepare_layer(df, name, "#1f77b4"))
        qtbot.wait(10)
        assert canvas.legend.width() == pytest.approx(width), k
        assert canvas.vb.rect().width() == pytest.approx(vb), k


def test_a_resize_makes_new_sprites_for_the_new_size(qtbot, sprite_calls):
    canvas = shown(qtbot, many_tracks(6), sprites=True)
    old = canvas.draw_data("L")
    canvas.resize(canvas.width() + 120, canvas.height() - 60)
    qtbot.wait(20)
    assert sprite_is_stale(old, canvas.current_view(), canvas.plot_size_px())
    canvas.refresh_lod()  # the executor runs the job at once
    new = canvas.draw_data("L")
    assert not sprite_is_stale(new, canvas.current_view(), canvas.plot_size_px())
    sprite_calls.clear()
    canvas_rgb(canvas)
    assert sprite_calls and all(sprite_calls)


def _cached_and_fresh(canvas: MapCanvas) -> tuple[np.ndarray, np.ndarray]:
    """Track pixels as painted through the items' caches, and painted afresh (no cache)."""
    cached = ink(grab_cached(canvas))
    items = [it.curve for n in canvas.layer_names() for it in canvas.layer_items(n)]
    modes = [it.cacheMode() for it in items]
    for it in items:
        it.setCacheMode(QtWidgets.QGraphicsItem.CacheMode.NoCache)
    fresh = ink(grab_cached(canvas))
    for it, mode in zip(items, modes, strict=True):
        it.setCacheMode(mode)
    return cached, fresh


def grab_cached(canvas: MapCanvas) -> np.ndarray:
    img = canvas.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    raw = np.frombuffer(img.constBits(), dtype=np.uint8).reshape(h, img.bytesPerLine())
    return raw[:, : w * 3].reshape(h, w, 3).copy()


@pytest.mark.parametrize("sprites", [True, False])
def test_no_ghost_of_the_cache_after_zoom_pan_and_resize(qtbot, sprites):
    """Qt kept a curve's device-coordinate cache at its old place when new level-of-detail
    data changed the bounds of a curve larger than the view: tracks drawn shifted or
    missing after a zoom or a pan. What is shown equals a fresh paint."""
    canvas = shown(qtbot, many_tracks(7, n_tracks=200, n_points=300), sprites=sprites)
    steps = []
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    cx, cy, hw, hh = (x0 + x1) / 2, (y0 + y1) / 2, (x1 - x0) / 8, (y1 - y0) / 8
    steps.append(
        lambda: canvas.vb.setRange(xRange=(cx - hw, cx + hw), yRange=(cy - hh, cy + hh), padding=0)
    )
    steps.append(
        lambda: canvas.vb.setRange(
            xRange=(cx - hw * 0.4, cx + hw * 1.6), yRange=(cy - hh, cy + hh), padding=0
        )
    )
    steps.append(
        lambda: canvas.vb.setRange(
            xRange=(cx - hw * 0.4, cx + hw * 1.6), yRange=(cy - hh * 1.6, cy + hh * 0.4), padding=0
        )
    )
    steps.append(lambda: canvas.resize(canvas.width() - 150, canvas.height() + 40))
    for k, step in enumerate(steps):
        grab_cached(canvas)  # the caches filled for the view before the step
        step()
        qtbot.wait(120)
        canvas.refresh_lod()
        qtbot.wait(20)
        cached, fresh = _cached_and_fresh(canvas)
        assert fresh.sum() > 500, k
        near = fresh.copy()
        near[1:] |= fresh[:-1]
        near[:-1] |= fresh[1:]
        near[:, 1:] |= fresh[:, :-1]
        near[:, :-1] |= fresh[:, 1:]
        assert (cached & ~near).sum() <= 0.002 * cached.sum(), k
        assert cached.sum() >= 0.98 * fresh.sum(), k


def test_a_high_dpi_paint_strokes_instead_of_copying(qtbot):
    canvas = shown(qtbot, many_tracks(8), sprites=True)
    item = next(it.curve for it in canvas.layer_items("L") if it.curve.sprite is not None)
    image = QtGui.QImage(200, 200, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
    image.setDevicePixelRatio(2.0)
    painter = QtGui.QPainter(image)
    try:
        assert item.sprite.draw(painter, item) is False
    finally:
        painter.end()


def test_a_failed_drawing_job_is_let_go(qtbot, monkeypatch):
    """A job that raises in the worker is logged and handed back as None: the layer is not
    left waiting for it (it would never be redone)."""
    from wakeline.app import map_canvas
    from wakeline.app.lod_worker import LodWorker

    canvas = shown(qtbot, many_tracks(9), sprites=True)
    canvas.lod_executor = LodWorker(canvas)

    def broken(*_args, **_kw):
        raise RuntimeError("decimation failed")

    monkeypatch.setattr(map_canvas, "relod", broken)
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    canvas.vb.setRange(xRange=(x0, x0 + (x1 - x0) / 5), yRange=(y0, y0 + (y1 - y0) / 5))
    canvas.refresh_lod()
    qtbot.waitUntil(lambda: not canvas.lod_busy, timeout=10_000)
    assert "L" in canvas.layer_names()


def _scatter_pixels(qtbot, cls, x, y, **style) -> np.ndarray:
    import pyqtgraph as pg

    plot = pg.PlotWidget(background="w")
    qtbot.addWidget(plot)
    plot.resize(300, 240)
    plot.show()
    qtbot.waitExposed(plot)
    plot.setRange(xRange=(0, 1), yRange=(0, 1), padding=0)
    item = cls()
    plot.addItem(item)
    item.setData(x=x, y=y, **style)
    img = plot.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    raw = np.frombuffer(img.constBits(), dtype=np.uint8).reshape(h, img.bytesPerLine())
    return raw[:, : w * 3].reshape(h, w, 3).copy()


def test_uniform_scatter_draws_what_pyqtgraph_draws(qtbot):
    """The vectorized scatter puts the same symbol at the same pixels as pyqtgraph's."""
    import pyqtgraph as pg

    rng = np.random.default_rng(3)
    x, y = rng.random(400), rng.random(400)
    x[::37] = np.nan  # the NaN separators of a layer's curve
    style = {"symbol": "o", "size": 5, "pen": pg.mkPen(None), "brush": pg.mkBrush("#d62728")}
    ours = _scatter_pixels(qtbot, map_paths.UniformScatter, x, y, **style)
    theirs = _scatter_pixels(qtbot, pg.ScatterPlotItem, x, y, **style)
    assert ink(ours).sum() > 1000
    assert np.array_equal(ours, theirs)


def test_a_swap_sets_symbols_once_per_curve_never_spot_by_spot(qtbot, monkeypatch):
    """Swapping a layer's level of detail hands each curve's symbols over in one piece:
    one symbol style looked up per curve (pyqtgraph looked one up per spot, ~10 µs each:
    a layer of 12 sensors at 3,000 symbols blocked the GUI thread for 200 ms and more),
    and the symbols are set on the new arrays only (pyqtgraph's setSymbol redrew them
    first on the old 100 k-vertex curve: 700 ms)."""
    import pyqtgraph.graphicsItems.ScatterPlotItem as scatter_module

    looked_up, largest = [], [0]
    atlas_get = scatter_module.SymbolAtlas.__getitem__

    def counting(self, styles):
        looked_up.append(len(styles))
        return atlas_get(self, styles)

    add_points = map_paths.UniformScatter.addPoints

    def recording(self, *args, **kwargs):
        y = kwargs.get("y")
        largest[0] = max(largest[0], 0 if y is None else len(y))
        return add_points(self, *args, **kwargs)

    monkeypatch.setattr(scatter_module.SymbolAtlas, "__getitem__", counting)
    monkeypatch.setattr(map_paths.UniformScatter, "addPoints", recording)
    df = many_tracks(5, n_tracks=240, n_points=120)
    df["sensor"] = "S" + (df["batch"].astype(int) % 3).astype(str)
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(700, 520)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.lod_executor = lambda job, done: done(job())
    canvas.set_true_aspect(LAT0)
    style = LayerStyle(width=1.3, symbol_size=3)
    canvas.set_draw_data(prepare_layer(df, "L", "#1f77b4", by_sensor=True, style=style))
    canvas.fit()
    canvas.refresh_lod()
    qtbot.wait(20)
    data = canvas.draw_data("L")
    assert len(data.curves) == 3
    assert min(c.n_vertices for c in data.curves) > map_paths.SYMBOLS_MAX  # lines only
    for item, curve in zip(canvas.layer_items("L"), data.curves, strict=True):
        # No symbol drawn yet, but the legend's sample already has the layer's.
        assert item.scatter.opts["size"] == 3
        assert item.scatter.opts["brush"].color().name() == QtGui.QColor(curve.color).name()
    looked_up.clear()
    largest[0] = 0
    canvas.vb.scaleBy((0.06, 0.06))
    canvas.refresh_lod()
    qtbot.wait(20)
    data = canvas.draw_data("L")
    few = [c for c in data.curves if c.n_vertices <= map_paths.SYMBOLS_MAX]
    assert few, "zoomed in, some curve should carry symbols"
    for item, curve in zip(canvas.layer_items("L"), data.curves, strict=True):
        if curve.n_vertices <= map_paths.SYMBOLS_MAX:
            # Every vertex of the curve has its symbol: nothing is drawn less.
            assert item.scatter.isVisible()
            assert np.array_equal(item.scatter.data["x"], curve.lon, equal_nan=True)
    assert largest[0] <= map_paths.SYMBOLS_MAX + 1000  # never the old long curve
    assert sum(looked_up) <= len(few)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("antialias", [False, True])
def test_a_path_built_in_pieces_strokes_what_the_whole_one_strokes(
    qtbot, monkeypatch, seed, antialias
):
    """map_paths.curve_path (pieces cut at NaN separators, S29) against pyqtgraph's one
    call: the same pixels, on random tracks with single and repeated separators, a
    separator first and last, and pieces as small as a few vertices."""
    import pyqtgraph as pg
    from PySide6 import QtCore

    rng = np.random.default_rng(seed)
    parts = []
    for _ in range(60):
        k = int(rng.integers(1, 40))
        xy = rng.normal(0, 1, (k, 2)).cumsum(axis=0) + rng.uniform(-40, 40, 2)
        parts.append(xy)
        parts.append(np.full((int(rng.integers(1, 3)), 2), np.nan))
    xy = np.concatenate([np.full((1, 2), np.nan), *parts])
    lon, lat = xy[:, 0].copy(), xy[:, 1].copy()
    monkeypatch.setattr(map_paths, "PATH_PIECE_VERTICES", int(rng.integers(5, 60)))
    assert len(map_paths._chunks(lon, map_paths.PATH_PIECE_VERTICES)) > 5

    def stroke(path) -> bytes:
        image = QtGui.QImage(400, 400, QtGui.QImage.Format.Format_ARGB32_Premultiplied)
        image.fill(QtCore.Qt.GlobalColor.transparent)
        p = QtGui.QPainter(image)
        p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, antialias)
        p.setPen(pg.mkPen("#d02020", width=1))
        p.setTransform(QtGui.QTransform(4.0, 0.0, 0.0, -4.0, 200.0, 200.0))
        p.drawPath(path)
        p.end()
        return bytes(image.constBits())

    whole = pg.arrayToQPath(lon, lat, connect="finite")
    pieces = map_paths.curve_path(lon, lat)
    assert stroke(pieces) == stroke(whole)
    assert pieces.boundingRect() == whole.boundingRect()


@pytest.mark.parametrize("move", ["zoom in", "zoom out", "pan", "resize"])
def test_a_long_curve_stands_in_its_old_sprite_while_the_new_one_is_made(
    qtbot, monkeypatch, sprite_calls, move
):
    """S29: a curve of STAND_IN_VERTICES or more whose sprite no longer fits paints the
    old image scaled onto the view while a new one is on its way (no stroke on the GUI
    thread: 15-60 ms per 650 k-vertex curve), its tracks where the stroke puts them;
    without a job on its way it strokes; the new sprite is copied exactly."""
    import pyqtgraph as pg

    strokes = []
    original = pg.PlotCurveItem.paint

    def counted(self, p, opt, widget):
        if isinstance(self, map_paths.SpriteCurve) and self.sprite is not None:
            strokes.append(len(self.xData))
        return original(self, p, opt, widget)

    monkeypatch.setattr(pg.PlotCurveItem, "paint", counted)
    df = many_tracks(5)
    canvas = shown(qtbot, df, sprites=True)
    (curve,) = [c for c in canvas.draw_data("L").curves if c.sprite is not None]
    monkeypatch.setattr(map_paths, "STAND_IN_VERTICES", curve.sprite.n)  # this one
    jobs = []
    canvas.lod_executor = lambda job, done: jobs.append((job, done))
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    w = x1 - x0
    if move == "zoom in":
        canvas.vb.scaleBy((0.8, 0.8))
    elif move == "zoom out":
        canvas.vb.scaleBy((1.2, 1.2))
    elif move == "pan":
        canvas.vb.setRange(xRange=(x0 + 0.2 * w, x1 + 0.2 * w), yRange=(y0, y1), padding=0)
    else:
        canvas.resize(640, 470)
        qtbot.wait(20)
    assert sprite_is_stale(canvas.draw_data("L"), canvas.current_view(), canvas.plot_size_px())
    assert canvas.lod_busy
    strokes.clear()
    sprite_calls.clear()
    stand_in = ink(canvas_rgb(canvas))
    assert sprite_calls and not any(sprite_calls)  # the old image does not fit as it is
    assert not strokes, "a long curve was stroked while its new sprite was on its way"
    qtbot.wait(100)  # the level-of-detail timer asks for the new one
    assert jobs
    # Where the stroke puts the tracks (the same view, no job on its way: strokes).
    executor, canvas.lod_executor = canvas.lod_executor, None
    stroked = ink(canvas_rgb(canvas))
    assert strokes, "without a job on its way the curve strokes"
    canvas.lod_executor = executor
    near = stroked.copy()
    for _ in range(3):  # within 3 px (lines scaled by up to 1.25)
        near[1:] |= near[:-1].copy()
        near[:-1] |= near[1:].copy()
        near[:, 1:] |= near[:, :-1].copy()
        near[:, :-1] |= near[:, 1:].copy()
    assert stand_in.sum() > 1000
    assert (stand_in & ~near).sum() <= 0.02 * stand_in.sum()
    if move in ("zoom in", "resize"):  # the old image covers the view: all of it drawn
        assert stand_in.sum() >= 0.6 * stroked.sum()
    while jobs:
        job, done = jobs.pop(0)
        done(job())
    assert not sprite_is_stale(canvas.draw_data("L"), canvas.current_view(), canvas.plot_size_px())
    strokes.clear()
    sprite_calls.clear()
    canvas_rgb(canvas)
    assert sprite_calls and all(sprite_calls) and not strokes

"""The map draws every point: level of detail, rendering, hover, legend, times, coastline."""

import time

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtGui, QtWidgets  # noqa: E402

from wakeline.app.cli import main  # noqa: E402
from wakeline.app.map_canvas import MapCanvas  # noqa: E402
from wakeline.app.map_draw import (  # noqa: E402
    LayerStyle,
    decimate,
    format_time,
    layer_geometry,
    lod_is_stale,
    prepare_layer,
    relod,
)
from wakeline.core import geo  # noqa: E402
from wakeline.resources import coastline_path  # noqa: E402

pytestmark = pytest.mark.gui

#: Open Pacific, no land: every coloured pixel is a track.
LON0, LAT0 = -135.0, 5.0


def star_scene(seed: int = 3, n_tracks: int = 24, n_points: int = 120) -> pd.DataFrame:
    """Tracks leaving a common area in every direction, zig-zagging, rows shuffled."""
    rng = np.random.default_rng(seed)
    rows = []
    for k in range(n_tracks):
        heading = 360.0 * k / n_tracks + rng.uniform(-5, 5)
        # Zig-zag: ±35° legs of 15 points, 150 m steps.
        legs = np.where((np.arange(n_points) // 15) % 2 == 0, 35.0, -35.0)
        h = np.radians(heading + legs)
        x = np.cumsum(150.0 * np.sin(h)) + 3000.0 * np.sin(np.radians(heading))
        y = np.cumsum(150.0 * np.cos(h)) + 3000.0 * np.cos(np.radians(heading))
        lon, lat = geo.from_local(x, y, LON0, LAT0)
        t = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(np.arange(n_points) * 10, "s")
        rows.append(
            pd.DataFrame({"sensor": "R1", "batch": str(100 + k), "time": t, "lon": lon, "lat": lat})
        )
    df = pd.concat(rows, ignore_index=True)
    return df.sample(frac=1.0, random_state=seed).reset_index(drop=True)


def image_array(path) -> np.ndarray:
    """RGB array (h, w, 3) of a PNG."""
    img = QtGui.QImage(str(path)).convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    raw = np.frombuffer(img.constBits(), dtype=np.uint8).reshape(h, img.bytesPerLine())
    return raw[:, : w * 3].reshape(h, w, 3).copy()


def to_pixel(lon, lat, bounds, size):
    w, s, e, n = bounds
    col = (np.asarray(lon) - w) / (e - w) * size[0]
    row = (n - np.asarray(lat)) / (n - s) * size[1]
    return col, row


def coloured(rgb: np.ndarray) -> np.ndarray:
    """Saturated pixels (tracks; not white, grey coastline or grid)."""
    a = rgb.astype(int)
    return (a.max(axis=2) - a.min(axis=2)) > 60


def test_render_bare_draws_every_point_of_every_track(qapp, tmp_path, capsys):
    df = star_scene()
    csv = tmp_path / "star.csv"
    df.to_csv(csv, index=False)
    png = tmp_path / "star.png"
    pad = 0.01
    bounds = (
        df["lon"].min() - pad,
        df["lat"].min() - pad,
        df["lon"].max() + pad,
        df["lat"].max() + pad,
    )
    size = (400, 400)
    arg = ",".join(f"{v:.6f}" for v in bounds)
    code = main(
        ["render", str(csv), "-o", str(png), "--bare", "--size", "400x400", "--bounds", arg]
    )
    assert code == 0, capsys.readouterr().err
    assert "drawn vertices" in capsys.readouterr().out
    rgb = image_array(png)
    assert rgb.shape[:2] == (size[1], size[0])
    hit = coloured(rgb)
    bounds = tuple(float(f"{v:.6f}") for v in bounds)
    col, row = to_pixel(df["lon"], df["lat"], bounds, size)
    # Each point: a coloured pixel within 1 px of where it falls.
    c, r = np.floor(col).astype(int), np.floor(row).astype(int)
    near = np.zeros(len(df), dtype=bool)
    for dc in (-1, 0, 1):
        for dr in (-1, 0, 1):
            cc, rr = np.clip(c + dc, 0, size[0] - 1), np.clip(r + dr, 0, size[1] - 1)
            near |= hit[rr, cc]
    missing = df.loc[~near, "batch"].unique()
    assert near.all(), f"{(~near).sum()} points of tracks {missing} not drawn"


def test_bare_render_edges_are_exactly_the_bounds(qapp, tmp_path):
    lon, lat = LON0 + 2.55, LAT0 + 2.05
    df = pd.DataFrame(
        {
            "sensor": ["S"],
            "batch": ["1"],
            "time": pd.to_datetime([0], unit="s", utc=True) + pd.Timedelta("20000D"),
            "lon": [lon],
            "lat": [lat],
        }
    )
    csv = tmp_path / "one.csv"
    df.to_csv(csv, index=False)
    png = tmp_path / "one.png"
    bounds = (LON0, LAT0, LON0 + 10.0, LAT0 + 10.0)
    arg = ",".join(str(v) for v in bounds)
    assert (
        main(["render", str(csv), "-o", str(png), "--bare", "--size", "200x100", "--bounds", arg])
        == 0
    )
    hit = coloured(image_array(png))
    rows, cols = np.nonzero(hit)
    assert len(rows) > 0
    col, row = to_pixel(lon, lat, bounds, (200, 100))
    # The symbol is centred on the point: its pixel centroid within half a pixel.
    assert abs((cols.mean() + 0.5) - col) <= 0.6
    assert abs((rows.mean() + 0.5) - row) <= 0.6


def test_lod_keeps_every_track_and_every_turn_to_the_pixel():
    df = star_scene(n_tracks=12, n_points=400)
    geom = layer_geometry(df)
    px = (0.01, 0.01)  # about 1.1 km: several 150 m steps per pixel
    keep, brk = decimate(geom.lon, geom.lat, geom.starts, geom.ends, px)
    assert keep.sum() < 0.5 * len(keep)  # it does decimate
    assert keep[geom.starts].all() and keep[geom.ends - 1].all()
    # Every point lies in the pixel of a kept point of its own track (turns included).
    ix = np.floor(geom.lon / px[0]).astype(int)
    iy = np.floor(geom.lat / px[1]).astype(int)
    cells = set(zip(geom.track, ix, iy, strict=True))
    kept = set(zip(geom.track[keep], ix[keep], iy[keep], strict=True))
    assert cells == kept
    # And each point's pixel is the one of the last kept point before it (or itself).
    last_kept = np.maximum.accumulate(np.where(keep, np.arange(len(keep)), 0))
    assert np.array_equal(ix[last_kept], ix) and np.array_equal(iy[last_kept], iy)
    assert brk[geom.starts].all()


def test_lod_clips_to_the_view_and_breaks_the_curve_there():
    # One track going out of the box and coming back: no line may join the two sides.
    x = np.concatenate([np.linspace(0, 1, 11), np.full(10, 5.0), np.linspace(1, 0, 11)])
    y = np.concatenate([np.zeros(11), np.linspace(0, 1, 10), np.ones(11)])
    starts, ends = np.array([0]), np.array([len(x)])
    keep, brk = decimate(x, y, starts, ends, (0.01, 0.01), box=(-0.5, 1.5, -0.5, 1.5))
    assert not keep[12:20].any()  # the excursion far outside is dropped
    assert keep[:12].all() and keep[20:].all()  # ... but not the legs into the box
    assert brk[20] and not brk[1:20].any()  # the curve restarts after the gap
    data = prepare_layer(
        pd.DataFrame(
            {
                "sensor": "S",
                "batch": "a",
                "time": pd.to_datetime(np.arange(len(x)), unit="s", utc=True),
                "lon": x,
                "lat": y,
            }
        ),
        "t",
        view=(-0.5, 1.5, -0.5, 1.5),
        size_px=(200, 200),
        style=LayerStyle(gaps=False),  # degrees per second: every leg an impossible jump
    )
    curve = data.curves[0]
    assert np.isnan(curve.lon).sum() == 1  # one break, at the gap
    assert data.n_vertices == curve.n_vertices


def test_a_gap_of_hours_is_not_drawn_as_a_straight_line():
    """ATD's AIS has ships unseen for a day and Saronic's for hours: the straight leg
    across the gap crossed land. A leg longer than 30 min and 10 of its track's steps is
    left undrawn, in the decimated curves, the full-resolution ones and the selection;
    a track sampled every 30 min keeps its legs, and a missed fix or two does not break."""
    from wakeline.app.map_draw import nan_separated
    from wakeline.app.map_selection import selection_curves

    t_a = np.r_[np.arange(0, 3600, 10.0), 86_400 + np.arange(0, 3600, 10.0)]  # a day unseen
    t_b = np.arange(0, 48 * 1800, 1800.0)  # every 30 min, steadily
    t_c = np.delete(np.arange(0, 3600, 10.0), [50, 51, 200])  # a few missed fixes
    parts = []
    for k, t in enumerate((t_a, t_b, t_c)):
        parts.append(
            pd.DataFrame(
                {
                    "sensor": "S",
                    "batch": f"b{k}",
                    "time": pd.to_datetime(t, unit="s", utc=True),
                    "lon": LON0 + k + 0.001 * np.arange(len(t)),
                    "lat": LAT0 + 0.0005 * np.arange(len(t)) ** 1.1,
                }
            )
        )
    df = pd.concat(parts, ignore_index=True)
    geom = layer_geometry(df)
    assert np.flatnonzero(geom.gap_break).tolist() == [360]  # b0's first fix after the day
    for view, size in ((None, None), ((LON0 - 1, LON0 + 4, LAT0 - 1, LAT0 + 4), (400, 400))):
        curve = prepare_layer(df, "t", view=view, size_px=size).curves[0]
        assert np.isnan(curve.lon).sum() == 3  # two track starts and the gap
    lon, _ = nan_separated(df)
    assert np.isnan(lon).sum() == 3
    halo, _, _ = selection_curves(df)
    assert np.isnan(halo.lon).sum() == 3


def test_gaps_always_break_past_3_h_and_at_impossible_jumps_but_not_in_compressed_layers():
    """An operator's findings on ATD: a two-point track (its median step is its gap) drew a
    960 km line across a day, and one id jumping California-Florida at 4,700 kn was drawn;
    and the compressed layer lost legs the ship sailed in plain view, its own steps being
    long. A leg longer than 3 h, or faster than 60 kn over more than 1 km, breaks; a
    compressed layer (``LayerStyle(gaps=False)``) and its selection break at track ends only."""
    from wakeline.app.map_selection import selection_curves

    def tr(batch, t, lon, lat):
        return pd.DataFrame(
            {
                "sensor": "S",
                "batch": batch,
                "time": pd.to_datetime(np.asarray(t, float), unit="s", utc=True),
                "lon": lon,
                "lat": lat,
            }
        )

    two = tr("two", [0, 86_400], [LON0, LON0 + 8.0], [LAT0, LAT0 + 2.0])  # a day apart
    t = np.arange(0, 3000, 600.0)  # every 10 min, a jump of 30 degrees in the middle
    jump = tr("jump", t, LON0 + np.r_[0, 0.01, 30.0, 30.01, 30.02], LAT0 + np.zeros(5))
    noisy = tr("noisy", np.arange(0, 20, 1.0), LON0 + 0.0003 * (-1) ** np.arange(20), LAT0)
    df = pd.concat([two, jump, noisy], ignore_index=True)
    geom = layer_geometry(df)
    assert np.flatnonzero(geom.gap_break).tolist() == [2, 26]  # jump, noisy (none), two
    curve = prepare_layer(df, "t").curves[0]
    assert np.isnan(curve.lon).sum() == 2 + 2
    flat = prepare_layer(df, "t", style=LayerStyle(gaps=False)).curves[0]
    assert np.isnan(flat.lon).sum() == 2  # track starts only
    halo, _, _ = selection_curves(df, gaps=False)
    assert np.isnan(halo.lon).sum() == 2


def test_jump_breaks_measure_only_the_legs_their_bound_lets_pass():
    """gap_breaks measures (haversine) only the legs whose bound R·(|Δlat| + |Δlon|)
    passes both limits; the breaks are those of every leg measured: legs around the
    limits, across 180° (unwrapped and not), NaN positions and times, repeated times."""
    from wakeline.app import map_lod

    rng = np.random.default_rng(11)
    n = 20_000
    t = np.cumsum(rng.choice([0.0, 1.0, 10.0, 60.0, 600.0, 4000.0], n))
    t[rng.integers(0, n, 30)] = np.nan
    km = rng.choice([0.0, 0.3, 0.99, 1.0, 1.01, 3.0, 50.0, 500.0], n) / 111.2
    lat = np.clip(np.cumsum(km * rng.normal(size=n)), -80, 80)
    lon = 179.5 + np.cumsum(km * rng.normal(size=n) * 3)
    lon[rng.integers(0, n, 500)] -= 360.0  # across 180° as read, not unwrapped
    lat[rng.integers(0, n, 20)] = np.nan
    starts = np.r_[0, np.sort(rng.choice(np.arange(1, n), 300, replace=False))]
    ends = np.r_[starts[1:], n]
    got = map_lod.gap_breaks(t, starts, ends, lon, lat)
    # every leg measured, as before
    want = map_lod.gap_breaks(t, starts, ends)
    step = np.r_[np.nan, np.diff(t)]
    step[starts] = np.nan
    dist = np.r_[0.0, geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])]
    with np.errstate(invalid="ignore"):
        fast = (dist > map_lod.JUMP_MIN_M) & (dist > map_lod.JUMP_KN * geo.KN_MS * step)
    want |= fast & np.isfinite(step)
    np.testing.assert_array_equal(got, want)
    assert fast.sum() > 100 and (got & ~map_lod.gap_breaks(t, starts, ends)).any()


def test_relod_when_zooming_in(qtbot):
    df = star_scene(n_tracks=6, n_points=300)
    coarse = prepare_layer(
        df, "s", view=(LON0 - 1, LON0 + 1, LAT0 - 1, LAT0 + 1), size_px=(100, 100)
    )
    fine_view = (LON0 - 0.05, LON0 + 0.05, LAT0 - 0.05, LAT0 + 0.05)
    assert lod_is_stale(coarse, fine_view, (100, 100))
    fine = relod(coarse, fine_view, (100, 100))
    assert fine.geometry is coarse.geometry
    assert not lod_is_stale(fine, fine_view, (100, 100))
    # Canvas: the layer is decimated again when the view changes (synchronous default).
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(500, 400)
    canvas.set_draw_data(prepare_layer(df, "s", style=LayerStyle(width=1)))
    full = canvas.draw_data("s").n_vertices
    assert full == len(df)  # no view yet: every point
    canvas.set_true_aspect(LAT0)
    canvas.fit()
    zoomed_out = canvas.n_vertices()
    assert 6 <= zoomed_out <= full
    # A worker-style executor: the job is pure and its result swapped in afterwards.
    jobs = []
    canvas.lod_executor = lambda job, done: jobs.append((job, done))
    canvas.vb.setRange(xRange=fine_view[:2], yRange=fine_view[2:], padding=0)
    canvas.refresh_lod()
    assert len(jobs) == 1
    job, done = jobs[0]
    done(job())
    assert canvas.draw_data("s").px[0] < 0.01


def test_degree_axes_near_greenwich_stay_in_degrees(qtbot):
    """Operator test: zoomed in at 0° E (the Thames at Greenwich) the map's longitude axis
    read "longitude (m°)" with ticks -3 … 3 — pyqtgraph's SI prefix on degrees, read as
    3° by anyone; the Detail views' δ (empty: "m°", ±500) and compressed-track axes too."""
    from wakeline.app.detail import DetailPanel

    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(500, 400)
    canvas.show()
    canvas.vb.setRange(xRange=(-0.003, 0.003), yRange=(51.47, 51.48), padding=0)
    detail = DetailPanel()
    qtbot.addWidget(detail)
    detail.resize(500, 400)
    detail.show()
    detail.comp_plot.setXRange(-0.002, 0.002, padding=0)
    detail.comp_plot.setYRange(-0.001, 0.001, padding=0)
    QtWidgets.QApplication.processEvents()
    axes = [canvas.getAxis("bottom"), canvas.getAxis("left"), detail.factor_plot.getAxis("left")]
    axes += [detail.comp_plot.getAxis("bottom"), detail.comp_plot.getAxis("left")]
    for axis in axes:
        assert "(°)" in axis.labelString(), axis.labelString()
        assert axis.autoSIPrefixScale == 1.0


@pytest.mark.parametrize("width", [420, 560, 900])
def test_longitude_tick_labels_keep_apart(qtbot, width):
    """Operator test: the before/after maps (a narrow map each) printed their longitude
    labels as one string, "131.16131.18131.20": pyqtgraph spaces major ticks by the
    axis length alone. Major ticks are now at least a label's width apart."""
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(width, 420)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.set_true_aspect(19.72)
    canvas.vb.setRange(xRange=(131.14, 131.23), yRange=(19.65, 19.80), padding=0)
    QtWidgets.QApplication.processEvents()
    axis = canvas.getAxis("bottom")
    (lo, hi), size = canvas.vb.viewRange()[0], axis.geometry().width()
    spacing, values = axis.tickValues(lo, hi, size)[0]
    texts = axis.tickStrings(values, 1.0, spacing)
    metrics = QtGui.QFontMetricsF(axis.style.get("tickFont") or axis.font())
    widest = max(metrics.horizontalAdvance(t) for t in texts)
    assert spacing * size / (hi - lo) >= widest + 4, (spacing, texts, size)
    assert len(values) >= 1


def _small_layer(k: int):
    """Layer ``layer{k}``: one five-point track, 0.01° east of layer k − 1's."""
    df = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "1",
            "time": pd.date_range("2024-01-01", periods=5, freq="min", tz="UTC"),
            "lon": 10 + k * 0.01 + np.arange(5) * 1e-3,
            "lat": 55 + np.arange(5) * 1e-3,
        }
    )
    return prepare_layer(df, f"layer{k}", style=LayerStyle(width=1))


def _shown_canvas(qtbot) -> "MapCanvas":
    """A map canvas of 700 × 420 px, shown and exposed."""
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(700, 420)
    canvas.show()
    qtbot.waitExposed(canvas)
    return canvas


def test_a_legend_longer_than_the_map_leaves_the_map_its_size(qtbot):
    """Operator test: with eleven files and their steps shown (some 50 legend lines) the
    legend beside the map made the plot's row taller than the window: the longitude
    axis went out of sight, the view became a strip of 0.015° and the legend's lines
    spread apart. The map keeps its size; the lines that do not fit are clipped."""
    canvas = _shown_canvas(qtbot)
    for k in range(30):
        canvas.set_draw_data(_small_layer(k))
    canvas.set_true_aspect(55.0)
    canvas.fit()
    QtWidgets.QApplication.processEvents()
    QtWidgets.QApplication.processEvents()
    view = canvas.vb.sceneBoundingRect()
    axis = canvas.getAxis("bottom").sceneBoundingRect()
    assert view.bottom() <= canvas.height() and axis.bottom() <= canvas.height() + 1, (
        view,
        axis,
    )
    assert canvas.legend.geometry().bottom() <= canvas.height()


def test_a_short_legend_shows_its_lines_whole(qtbot):
    """Seen on a render of one MTAD scene: the legend's one line was cut in half, since
    the legend's height (which clips its children since it may be clipped) left out its
    layout's margins. Every label of a short legend lies inside the legend."""
    canvas = _shown_canvas(qtbot)
    for k in range(3):
        canvas.set_draw_data(_small_layer(k))
        QtWidgets.QApplication.processEvents()
        legend = canvas.legend
        inside = legend.rect()
        for _sample, label in legend.items:
            box = label.mapRectToParent(label.boundingRect())
            assert inside.top() <= box.top() and box.bottom() <= inside.bottom() + 0.5, (
                k,
                box,
                inside,
            )


def test_hover_shows_sensor_batch_time_speed_and_elapsed_time(qtbot):
    t = pd.to_datetime([0.0, 100.0, 200.0], unit="s", utc=True)  # MTAD: seconds from start
    df = pd.DataFrame(
        {"sensor": "AIS", "batch": "412", "time": t, "lon": [120.0, 120.01, 120.02], "lat": 30.0}
    )
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.set_layer("mtad", df, "#1f77b4")
    canvas.set_true_aspect(30.0)
    canvas.fit()
    info = canvas.hover(120.0101, 30.0001)
    assert info["sensor"] == "AIS" and info["batch"] == "412" and info["layer"] == "mtad"
    assert info["time"] == "T+0:01:40"
    # 0.01° of longitude at 30°N in 100 s: 964 m / 100 s = 18.7 kn.
    assert info["speed_kn"] == pytest.approx(18.74, abs=0.05)
    text = canvas.hover_label.toPlainText()
    assert "T+0:01:40" in text and "1970" not in text and "18.7 kn" in text
    assert canvas.hover(121.0, 31.0) is None and not canvas.hover_label.isVisible()
    assert format_time(1714521600.0, relative=False) == "2024-05-01 00:00:00 UTC"
    assert format_time(90061.0, relative=True) == "T+1 d 01:01:01"


def test_legend_beside_the_map_and_selection_in_distinct_colours(qtbot):
    df = star_scene(n_tracks=5, n_points=30)
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(800, 500)
    canvas.show()
    canvas.set_layer("star", df, "#1f77b4", by_sensor=True)
    canvas.set_true_aspect(LAT0)
    canvas.fit()
    chosen = df[df["batch"].isin(["100", "101", "102"])]
    (fx0, fx1), (fy0, fy1) = canvas.vb.viewRange()
    canvas.show_selection(chosen)
    qtbot.wait(10)
    legend = canvas.legend.sceneBoundingRect()
    assert legend.width() > 0
    assert legend.left() >= canvas.vb.sceneBoundingRect().right() - 1.0
    colours = {item.opts["pen"].color().name() for item in canvas.selection_items()}
    assert len(colours) == 3
    chosen = df[df["batch"] == "101"]
    canvas.show_selection(chosen)
    assert canvas.zoom_to_selection()
    (x0, x1), (y0, y1) = canvas.vb.viewRange()
    assert x0 <= chosen["lon"].min() and chosen["lon"].max() <= x1
    assert y0 <= chosen["lat"].min() and chosen["lat"].max() <= y1
    assert (x1 - x0) * (y1 - y0) < 0.8 * (fx1 - fx0) * (fy1 - fy0)


def test_coastline_is_full_resolution_and_loads_fast():
    t = time.perf_counter()
    coast = np.load(coastline_path())
    lon = coast["lon"]
    assert time.perf_counter() - t < 1.0
    assert lon.dtype == np.float32 and int(np.isfinite(lon).sum()) == 60_416
    assert int(np.isnan(lon).sum()) == 1_428  # 1,429 lines


@pytest.mark.parametrize(
    "args",
    [
        ["--bounds", "10,5,9,6"],
        ["--bounds", "a,b,c,d"],
        ["--size", "12"],
    ],
)
def test_render_bad_arguments_exit_2(tmp_path, args, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["render", "x.csv", "-o", str(tmp_path / "x.png"), *args])
    assert exc.value.code == 2
    assert "render" in capsys.readouterr().err


def test_render_refuses_a_non_png_output(tmp_path, capsys):
    assert main(["render", "x.csv", "-o", str(tmp_path / "x.jpg")]) == 2
    assert ".png" in capsys.readouterr().err


def test_render_png_from_the_window_canvas_leaves_it_untouched(qtbot, tmp_path):
    from wakeline.app.map_render import render_png

    df = star_scene(n_tracks=4, n_points=40)
    canvas = MapCanvas()
    qtbot.addWidget(canvas)
    canvas.resize(700, 500)
    canvas.set_layer("star", df, "#1f77b4")
    canvas.set_true_aspect(LAT0)
    canvas.fit()
    canvas.show_selection(df[df["batch"] == "101"])
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.fit()
    QtWidgets.QApplication.processEvents()
    view, size = canvas.current_view(), canvas.size()
    info = render_png(canvas, tmp_path / "map.png", size=(300, 200))
    assert info["size"] == (300, 200) and info["points"] == len(df)
    assert canvas.current_view() == view and canvas.size() == size
    assert coloured(image_array(tmp_path / "map.png")).sum() > 100


def test_render_runs_steps_first(qapp, tmp_path, capsys):
    csv = tmp_path / "star.csv"
    star_scene(n_tracks=4, n_points=60).to_csv(csv, index=False)
    png = tmp_path / "steps.png"
    assert (
        main(
            ["render", str(csv), "-o", str(png), "--size", "300x200", "--step", "clean", "compress"]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "rendered 4 layers" in out  # source, cleaned, maneuvers, compressed
    assert png.stat().st_size > 0
    # Operator test: the flag given twice ran the last step only (no cleaned layer).
    argv = ["render", str(csv), "-o", str(png), "--size", "300x200"]
    assert main([*argv, "--step", "clean", "--step", "compress"]) == 0
    assert "rendered 4 layers" in capsys.readouterr().out


def test_render_help(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["render", "--help"])
    assert exc.value.code == 0
    assert "usage: wakeline render" in capsys.readouterr().out


def test_render_fuses_two_files_as_fuse_reads_them(tmp_path):
    """`render A_AIS.csv A_radar.csv --step fuse` names the sensors from the files, as
    `fuse` does (it failed with "found S1": both files were the default sensor)."""
    from wakeline.app.cli import main

    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    for name, dlat in (("s_AIS.csv", 0.0), ("s_radar.csv", 0.0005)):
        rows = [
            ("S1", 1, t0 + pd.Timedelta(seconds=30 * k), 122.0 + 0.003 * k, 30.0 + dlat)
            for k in range(40)
        ]  # each file names its one sensor alike (as MTAD's two-sensor files)
        pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"]).to_csv(
            tmp_path / name, index=False
        )
    png = tmp_path / "f.png"
    argv = ["render", str(tmp_path / "s_AIS.csv"), str(tmp_path / "s_radar.csv")]
    assert main(argv + ["-o", str(png), "--step", "fuse", "--size", "300x200"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_render_names_the_input_files_in_the_legend(tmp_path, monkeypatch):
    """`render a.csv b.csv` named the combined layer "input" in the legend (and its steps
    "input · fused"): the files are named."""
    from pathlib import Path

    from wakeline.app import map_render
    from wakeline.app.cli import main
    from wakeline.app.cli_render import input_name

    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    for name, dlat in (("a.csv", 0.0), ("b.csv", 0.01)):
        rows = [
            ("S1", 1, t0 + pd.Timedelta(seconds=30 * k), 10.0 + 0.003 * k, 55 + dlat)
            for k in range(9)
        ]
        pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"]).to_csv(
            tmp_path / name, index=False
        )
    seen = []

    def fake_render(layers, path, **_kw):
        seen.extend(layer.name for layer in layers)
        return {
            "layers": len(layers),
            "points": 0,
            "vertices": 0,
            "size": (1, 1),
            "bounds": (0, 0, 1, 1),
        }

    monkeypatch.setattr(map_render, "render_png", fake_render)
    argv = [
        "render",
        str(tmp_path / "a.csv"),
        str(tmp_path / "b.csv"),
        "-o",
        str(tmp_path / "x.png"),
    ]
    assert main(argv + ["--step", "clean"]) == 0
    assert seen and all(n.startswith("a.csv + b.csv") for n in seen), seen
    assert not any(n.startswith("input") for n in seen)
    paths = [tmp_path / f"f{k}.csv" for k in range(11)]
    assert input_name(paths[:1]) == "f0.csv"
    assert input_name([Path("ais.csv"), Path("radar.txt")]) == "ais.csv + radar.txt"
    assert input_name([Path("x.csv"), Path("x.csv")]) == "x.csv + x.csv"
    # operator test 10: "{ore_gbk,dma_semicolon_comma}.csv", "{ore_gbk,d…mma}.csv" in the
    # legend, named neither file; now each file whole, or the first and how many more
    two = input_name([Path("ore_gbk.csv"), Path("dma_semicolon_comma.csv")])
    assert two == "ore_gbk.csv + dma_semicolon_comma.csv"
    assert input_name([Path("s_AIS.csv"), Path("s_radar.csv")]) == "s_AIS.csv + s_radar.csv"
    assert input_name(paths) == "f0.csv + f1.csv and 9 more"
    assert not any("{" in input_name(paths[:k]) for k in range(1, 12))


def test_render_steps_draw_each_layer_once_and_the_input_in_its_own_colour(tmp_path):
    """`render --step maneuvers compress`: compress makes the maneuvers again, and the
    copy was drawn as a second layer that took the input's blue (the input came out brown
    beside the red compressed line, an operator's report)."""
    from wakeline.app.cli_render import run_steps
    from wakeline.app.map_colors import SOURCE_COLORS, layer_colors
    from wakeline.core.simulate import maneuver_tracks

    derived = run_steps(maneuver_tracks(3, "short", 300.0, seed=2), ["maneuvers", "compress"])
    assert [suffix for suffix, _, _ in derived] == ["maneuvers", "compressed"]
    taken = {layer_colors(kind, 1)[0] for _, kind, _ in derived}
    assert layer_colors("source", 1, taken)[0] == SOURCE_COLORS[0]


def test_render_frames_a_harbour_scene_closely(qapp, tmp_path, capsys):
    """A scene 1 km across (Autoferry's Trondheim harbour radar) filled a fifth of the
    rendered view's height (0.20): the fit padded at least 0.01° (a kilometre) on each
    side. The margin is now 5 % with a 50 m floor, so the scene fills most of the view's
    height (the legend beside the map takes some of its width)."""
    from wakeline.app.layer_view import padded_range

    t = pd.Timestamp("2021-05-04T07:55:00Z") + pd.to_timedelta(np.arange(60) * 2, "s")
    lon = 10.385 + np.linspace(0.0, 0.012, 60)  # ~600 m east
    lat = 63.4340 + np.linspace(0.0, 0.007, 60)  # ~780 m north
    csv = tmp_path / "harbour.csv"
    pd.DataFrame({"sensor": "radar", "batch": "1", "time": t, "lon": lon, "lat": lat}).to_csv(
        csv, index=False
    )
    assert main(["render", str(csv), "-o", str(tmp_path / "h.png")]) == 0
    out = capsys.readouterr().out
    w, s, e, n = (float(v) for v in out.split("bounds ")[1].rstrip(")\n").split(","))
    assert w <= lon.min() and e >= lon.max() and s <= lat.min() and n >= lat.max()
    assert (lat.max() - lat.min()) / (n - s) > 0.6  # was 0.20
    # A single fix: 50 m each side (was 1.1 km).
    x0, x1, y0, y1 = padded_range([(10.39, 63.44, 10.39, 63.44)])
    assert geo.haversine_m(x0, 63.44, x1, 63.44) == pytest.approx(100.0, rel=0.01)
    assert geo.haversine_m(10.39, y0, 10.39, y1) == pytest.approx(100.0, rel=0.01)


def test_legend_shortens_the_file_name_and_keeps_what_the_layer_is(qapp):
    """Seen on a render of two Autoferry files: the whole label was shortened in its
    middle, so the file's name was cut at a different place in each line
    ("autoferry_{ra…v · maneuvers", "autoferry_{ra… · compressed"). Now the file's name
    is shortened in its own middle and "· what" stays whole."""
    from wakeline.app.map_legend import SideLegend

    legend = SideLegend()
    name = "autoferry_{radar,lidar}_zh.csv"
    for what in ("lidar", "cleaned", "maneuvers", "compressed"):
        label = legend.fit_label(f"{name} · {what}")
        head, sep, tail = label.rpartition(" · ")
        assert tail == what and "…" in head, label
        # narrower (h129); the extension left out, the name's own end kept (h150)
        assert head.startswith("auto") and head.endswith("_zh"), label
        assert legend._metrics.horizontalAdvance(label) <= legend._label_px
    assert legend.fit_label("a.csv · cleaned") == "a.csv · cleaned"
    assert legend.fit_label("x" * 60).count("…") == 1  # no separator: shortened whole


def _capture_rendered_layers(monkeypatch) -> dict:
    """Make `wakeline render` hand its layers to a dict (name -> layer) instead of drawing."""
    from wakeline.app import map_render

    seen = {}

    def fake_render(layers, path, **_kw):
        seen.update({d.name: d for d in layers})
        return {"layers": len(layers), "points": 0, "vertices": 0, "size": (1, 1),
                "bounds": (0, 0, 1, 1)}  # fmt: skip

    monkeypatch.setattr(map_render, "render_png", fake_render)
    return seen


def test_render_draws_a_maneuvers_table_as_marks_beside_its_tracks(tmp_path, monkeypatch):
    """`render clean.csv man.csv` (the file `wakeline maneuvers` wrote): the turning
    points were read as one more sensor's tracks ("atd_{cle,m}an.csv · m"), joined by
    lines. They are drawn as maneuver marks named after their file."""
    from wakeline.core.simulate import maneuver_tracks

    tracks, marks = tmp_path / "clean.csv", tmp_path / "man.csv"
    maneuver_tracks(3, "short", 50.0, seed=4).to_csv(tracks, index=False)
    assert main(["maneuvers", str(tracks), "-o", str(marks)]) == 0
    n_marks = len(pd.read_csv(marks))
    assert n_marks > 0
    seen = _capture_rendered_layers(monkeypatch)
    assert main(["render", str(tracks), str(marks), "-o", str(tmp_path / "x.png")]) == 0
    assert list(seen) == ["clean.csv", "man.csv · maneuvers"], list(seen)
    assert seen["clean.csv"].geometry.n_points == len(pd.read_csv(tracks))
    assert seen["man.csv · maneuvers"].geometry.n_points == n_marks
    seen.clear()
    assert main(["render", str(marks), "-o", str(tmp_path / "y.png")]) == 0
    assert list(seen) == ["man.csv · maneuvers"]
    assert main(["render", str(marks), "-o", str(tmp_path / "z.png"), "--step", "clean"]) == 2


def _one_ship_in_two_batches(tmp_path):
    """One radar track at 5 m/s, east, cut by a 300 s gap into batches 1 and 2: the
    file's path and its number of rows."""
    t = np.arange(0, 1800, 10.0)
    keep = (t < 700) | (t >= 1000)  # a 300 s gap
    x, y = 5.0 * t[keep], np.zeros(keep.sum())
    lon, lat = geo.from_local(x, y, LON0, LAT0)
    csv = tmp_path / "two.csv"
    pd.DataFrame(
        {
            "sensor": "R1",
            "batch": np.where(t[keep] < 700, "1", "2"),
            "time": pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(t[keep], "s"),
            "lon": lon,
            "lat": lat,
        }
    ).to_csv(csv, index=False)
    return csv, int(keep.sum())


def test_render_draws_an_associated_target_as_one_line_across_its_join(tmp_path, monkeypatch):
    """`render --step associate`: the associated layer was drawn as the pieces it joined,
    each on its own, so no join could be seen in the image (an ATD join of a ship heading
    south-west to one 18 km north-east looked like two unrelated tracks). Each target is
    one line now: the join is drawn from the old piece's end to the new one's start."""

    csv, n = _one_ship_in_two_batches(tmp_path)
    seen = _capture_rendered_layers(monkeypatch)
    argv = ["render", str(csv), "-o", str(tmp_path / "x.png"), "--step", "associate"]
    assert main(argv) == 0
    assert len(seen["two.csv"].geometry.starts) == 2  # the input: its two batches
    joined = seen["two.csv · associated"].geometry
    assert len(joined.starts) == 1 and joined.n_points == n  # one line, joined


def test_the_windows_associated_layer_is_one_line_per_target(window, tmp_path):
    """Steps ▸ Associate in the window: the associated layer drew the pieces it joined
    each on its own (only `wakeline render` drew a target as one line), so a join was
    invisible on screen. The layer's drawing is one line per target now, through the
    same layer preparation as render; its table keeps both batches."""
    from conftest import load
    from wakeline.app.main import wait_for_jobs

    csv, n = _one_ship_in_two_batches(tmp_path)
    lid = load(window, csv)
    assert len(window.canvas.draw_data(lid).geometry.starts) == 2
    window.run_step("associate")
    wait_for_jobs(window)
    (assoc,) = [lay for lay in window.layers.values() if lay.kind == "associated"]
    assert set(assoc.points["batch"].astype(str)) == {"1", "2"}
    assert assoc.points["target"].nunique() == 1  # the step joined them
    geom = window.canvas.draw_data(assoc.id).geometry
    assert list(geom.starts) == [0] and list(geom.ends) == [n] and geom.n_points == n
    # Hover and click name the point's own batch, not the line's target (a click on the
    # map selected a batch the batch table did not have)
    assert {geom.describe(i)["batch"] for i in (0, n - 1)} == {"1", "2"}
    from wakeline.app.map_time import window_geometry

    late = window_geometry(geom, geom.time_s[-1] - 1.0, geom.time_s[-1])
    assert late.describe(late.n_points - 1)["batch"] == "2"


def test_a_per_batch_layer_keeps_its_batch_count_beside_a_long_file_name(qapp):
    """Coloured by batch, the layer's one legend line said "FILE · 37 batches, a colour
    each": too long to keep any of the file's name, so the whole was cut in its middle
    and the count was lost. The line is "FILE · 37 batches" (the colours say the rest)."""
    import pandas as pd

    from wakeline.app.map_draw import layer_geometry
    from wakeline.app.map_legend import SideLegend

    pts = pd.DataFrame(
        {
            "sensor": "R1",
            "batch": [str(k // 3) for k in range(111)],
            "time": pd.date_range("2024-01-01", periods=111, freq="10s", tz="UTC"),
            "lon": np.linspace(10.0, 10.1, 111),
            "lat": 63.4,
        }
    )
    geo = layer_geometry(pts, label="autoferry_radar_zh_gbk.csv", color_by="batch")
    label = SideLegend().fit_label(geo.labels[0])
    assert label.endswith(" · 37 batches") and label.startswith("autof"), label


def test_a_scene_across_the_antimeridian_is_drawn_in_one_piece(window, tmp_path):
    """The committed ATD sample (42 US ships, ~15° of longitude) moved so its centre lies
    on 180°: its tracks start on both sides of the antimeridian. The map drew them at
    x ≈ +180 and x ≈ −180, 360° apart (only each track was unwrapped, from its first
    point); now the layer is drawn in [0, 360) (``geo.lon_band_west``), all of it within
    the scene's own span, and the view, hover, selection, maneuver marks, time slider,
    coastline and the exported image follow it."""
    from conftest import DATA, load
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.map_render import render_png
    from wakeline.app.map_time import frame_job, index_job, window_geometry
    from wakeline.core.io import read_points

    pts = read_points(DATA / "atd2025_example_sample.csv").points
    lon = pts["lon"].to_numpy(float)
    span = lon.max() - lon.min()
    moved = geo.wrap180(lon + 180.0 - geo.circular_mean_deg(lon))
    assert (moved < -170).any() and (moved > 170).any()  # tracks on both sides
    csv = tmp_path / "atd_on_180.csv"
    pts.assign(lon=moved).to_csv(csv, index=False)
    lid = load(window, csv)
    geom = window.canvas.draw_data(lid).geometry
    assert geom.lon_west == 0.0
    assert geom.lon.max() - geom.lon.min() <= span + 1e-9  # was ~360
    lo, hi = 180.0 - span, 180.0 + span
    assert lo < geom.lon.min() and geom.lon.max() < hi
    x0, x1, _, _ = window.canvas.current_view()  # the first view frames it about 180°
    assert x0 < 180 < x1 and x1 - x0 < 3 * span
    # hover finds a point where it is drawn, east of 180° (a lon near -171° in the file)
    east = int(np.argmax(geom.lon))
    info = window.canvas.nearest(float(geom.lon[east]), float(geom.lat[east]))
    assert info is not None and info["lon"] > 180.0
    # a selection on either side lies on its layer
    keys = [tuple(k) for k in pts[["sensor", "batch"]].astype(str).drop_duplicates().to_numpy()]
    window.select_tracks(keys)
    wait_for_jobs(window)
    halo, _ = window.canvas.selection.getData()
    assert np.nanmin(halo) >= geom.lon.min() - 1e-9 and np.nanmax(halo) <= geom.lon.max() + 1e-9
    window.canvas.zoom_to_selection()
    x0, x1, _, _ = window.canvas.current_view()
    assert x0 < 180 < x1 and x1 - x0 < 3 * span
    # the time slider's positions
    scene = index_job([geom])
    t = float(np.median(geom.time_s))
    frame = frame_job(scene.index, t, 3600.0, (1e-3, 1e-3))
    assert len(frame.lon) and frame.lon.min() > lo and frame.lon.max() < hi
    assert window_geometry(geom, t, t + 3600.0).lon_west == 0.0  # a time window keeps it
    # the coastline is there east of 180° too (a copy of the west, one turn on)
    coast = window.canvas._coast.geometry
    assert np.nanmax(coast.lon) > 350
    # the exported image frames the scene about 180°
    out = render_png(window.canvas, tmp_path / "map.png", size=(400, 300))
    w, _, e, _ = out["bounds"]
    assert w < 180 < e and e - w < 3 * span
    # the maneuvers layer, drawn from its marks alone, keeps the layer's band
    window.run_step("maneuvers")
    wait_for_jobs(window)
    (marks,) = [lay for lay in window.layers.values() if lay.kind == "maneuvers"]
    g = window.canvas.draw_data(marks.id).geometry
    assert g.n_points and g.lon_west == 0.0 and lo < g.lon.min() and g.lon.max() < hi
    assert (g.lon > 180).any() and (g.lon < 180).any()


def test_lon_band_keeps_one_sided_and_greenwich_scenes_where_they_are():
    """[-180, 180) unless the longitudes lie closer together in [0, 360)."""
    assert geo.lon_band_west(np.array([-100.0, -80.0])) == -180.0  # one side: a tie
    assert geo.lon_band_west(np.array([-1.0, 2.0])) == -180.0  # across Greenwich
    assert geo.lon_band_west(np.array([179.9, -179.9, np.nan])) == 0.0
    assert geo.lon_band_west(np.array([120.0, -120.0])) == 0.0  # across the Pacific
    assert geo.lon_band_west(np.array([np.nan])) == -180.0
    assert np.allclose(geo.into_band(np.array([-179.9, 179.9, 0.5]), 0.0), [180.1, 179.9, 0.5])


# -- telling ships and layers apart (h227; operator review h225 items 2, 4, 9) -----------


def plots_scene(seed: int, scans: int = 120, per_scan: int = 6) -> pd.DataFrame:
    """One sensor's radar plots written as one batch: ``per_scan`` detections of targets
    and clutter scattered over a harbour at each scan time (3 s apart)."""
    rng = np.random.default_rng(seed)
    t0 = pd.Timestamp("2024-05-01", tz="UTC")
    t = np.repeat(np.arange(scans) * 3.0, per_scan)
    n = len(t)
    return pd.DataFrame(
        {
            "sensor": "radar",
            "batch": "plots",
            "time": t0 + pd.to_timedelta(t, "s"),
            "lon": 10.39 + rng.normal(0, 0.004, n),
            "lat": 63.44 + rng.normal(0, 0.002, n),
        }
    )


@pytest.mark.parametrize("n_tracks", [2, 7, 12, 17])
def test_colour_by_track_gives_each_track_its_own_colour(n_tracks):
    """Up to the palette's size every track of the layer is drawn in a colour no other
    track of it has, every point still drawn; and back to the layer's colour."""
    from wakeline.app.map_colors import TRACK_PALETTE, delta_e
    from wakeline.app.map_draw import recolor

    for seed in (1, 2):
        data = prepare_layer(star_scene(seed, n_tracks, 40), "stars", "#2ca02c")
        out = recolor(data, True)
        geom = out.geometry
        colour_of_track = [geom.colors[g] for g in geom.group]
        assert len(set(colour_of_track)) == n_tracks
        assert set(colour_of_track) <= set(TRACK_PALETTE)
        # well separated: no two closer than ΔE 15 (2.3 is a just-noticeable difference)
        cols = sorted(set(colour_of_track))
        if len(cols) > 1:
            assert min(delta_e(a, b) for i, a in enumerate(cols) for b in cols[i + 1 :]) >= 15
        assert out.n_vertices == data.n_vertices  # every point of every track
        back = recolor(out, False)
        assert back.geometry.colors == ("#2ca02c",) and back.n_vertices == data.n_vertices
        assert [c.color for c in back.curves] == ["#2ca02c"]


def test_colour_by_track_legend_says_and_n_more_and_explains_a_reused_colour():
    from wakeline.app.map_draw import LEGEND_TRACKS, recolor

    palette = ("#1f77b4", "#ff7f0e", "#8c564b", "#e377c2", "#d62728", "#7b4173") * 3
    palette = tuple(dict.fromkeys(palette)) + ("#393b79", "#31a354", "#e6550d", "#8c6d31")
    palette += ("#9467bd", "#17becf", "#2ca02c", "#bcbd22", "#637939")  # 15 colours
    for n_tracks in (16, 25, 40):
        data = prepare_layer(star_scene(5, n_tracks, 20), "stars", "#2ca02c")
        out = recolor(data, True, palette)
        labels = [c.label for c in out.curves]
        shown = [t for t in labels if t]
        assert len(shown) == LEGEND_TRACKS
        more = int(shown[-1].split("and ")[1].split(" more")[0])
        tracks_per_colour = np.bincount(out.geometry.group)
        assert more == n_tracks - tracks_per_colour[: LEGEND_TRACKS - 1].sum()
        assert shown[0].startswith("stars\n")  # the first line names the layer alone
        first = True  # the first reused colour is said in words, the next ones "(+k)"
        for g, text in enumerate(shown[:-1]):
            k = tracks_per_colour[g] - 1
            if k > 0:
                assert text.endswith(f" · +{k} same colour" if first else f" (+{k})"), text
                first = False
            else:
                assert "+" not in text, text


def test_a_selection_legend_says_how_many_more_it_does_not_name():
    from wakeline.app.map_selection import LEGEND_BATCHES, selection_curves

    for n in (13, 25, 60):
        pts = star_scene(9, n, 10)
        _halo, curves, colors = selection_curves(pts)
        labels = [c.label for c in curves if c.label]
        groups = len(curves)
        if groups > LEGEND_BATCHES:
            assert len(labels) == LEGEND_BATCHES
            assert labels[-1].startswith("… and ")
            named = sum(1 for _ in range(n) if _ % groups < LEGEND_BATCHES - 1)
            assert f"and {n - named:,} more selected" in labels[-1]
        reused = n > groups
        assert any("same colour" in t for t in labels) == reused


def test_removed_points_overlay_marks_every_removed_row_by_rule():
    from wakeline.app.map_draw import RULE_COLORS, rejected_layer

    rng = np.random.default_rng(4)
    for n in (7, 300):
        rules = rng.choice(["stationary", "turn", "isolated"], n)
        rejected = pd.DataFrame(
            {
                "sensor": "S1",
                "batch": rng.choice(["1", "2"], n),
                "time": pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(np.arange(n), "s"),
                "lon": 23.5 + rng.normal(0, 0.01, n),
                "lat": 37.9 + rng.normal(0, 0.01, n),
                "rule": rules,
                "action": "removed",
                "params": [f"p={r}" for r in rules],
            }
        )
        data = rejected_layer(rejected, "L2/removed")
        assert data.style.width == 0 and data.style.symbol == "x"
        assert data.n_vertices == n  # one marker per removed row, no line joins them
        names = sorted(set(rules))
        assert [c.label for c in data.curves] == [
            f"removed: {r} ({int((rules == r).sum()):,})" for r in names
        ]
        assert len({c.color for c in data.curves}) == len(names)
        from wakeline.app.map_colors import PALETTE, TRACK_PALETTE, apart_from

        # told apart from every layer and track colour
        assert apart_from(RULE_COLORS, {*PALETTE, *TRACK_PALETTE}) == RULE_COLORS
        assert {c.color for c in data.curves} <= set(RULE_COLORS)
        geom = data.geometry
        for i in rng.integers(0, n, 5):  # the hover names the rule of that very point
            j = int(np.flatnonzero((rejected["lon"] == geom.lon[i]).to_numpy())[0])
            note = geom.describe(int(i))["note"]
            assert note == f"removed by clean: {rules[j]} (removed) p={rules[j]}"


def test_radar_plots_are_drawn_as_points_tracks_as_lines():
    """The guidance's plots test (core.tracks.plot_like) decides: a layer of plots is
    drawn as dots (no line), ships' tracks as lines, over two seeds each."""
    from wakeline.app.layer_view import looks_like_plots, prepare_view

    for seed in (1, 2):
        plots = prepare_view(plots_scene(seed), "source", "#1f77b4")
        assert plots.extra.get("plots") and looks_like_plots(plots.points)
        assert plots.draw.style.width == 0 and plots.draw.style.symbol_size > 0
        assert plots.draw.style.plots  # still on the time slider
        tracks = prepare_view(star_scene(seed, 6, 60), "source", "#1f77b4")
        assert not tracks.extra.get("plots") and tracks.draw.style.width > 0


def test_track_labels_are_decluttered_and_left_out_when_too_many():
    from wakeline.app.map_labels import LABEL_H_PX, LABEL_LIMIT, declutter

    rng = np.random.default_rng(3)
    for n in (5, 40, LABEL_LIMIT):
        x, y = rng.uniform(0, 600, n), rng.uniform(0, 400, n)
        widths = rng.uniform(30, 90, n)
        keep = declutter(x, y, widths, (600, 400))
        assert 0 < len(keep) <= n
        boxes = [(x[i] + 6, y[i] - LABEL_H_PX / 2, widths[i], LABEL_H_PX) for i in keep]
        for a in range(len(boxes)):  # no two drawn labels overlap
            for b in range(a + 1, len(boxes)):
                (x0, y0, w0, h0), (x1, y1, w1, h1) = boxes[a], boxes[b]
                assert x0 + w0 <= x1 or x1 + w1 <= x0 or y0 + h0 <= y1 or y1 + h1 <= y0
    many = LABEL_LIMIT + 1  # zoomed far out: none
    assert (
        len(
            declutter(
                rng.uniform(0, 600, many), rng.uniform(0, 400, many), np.full(many, 9.0), (600, 400)
            )
        )
        == 0
    )


def test_maneuver_dots_shrink_as_they_crowd():
    from wakeline.app.map_canvas import marker_px

    sizes = [marker_px(8.0, n) for n in (10, 150, 151, 600, 601, 3000)]
    assert sizes[0] == sizes[1] == 8.0
    assert sizes == sorted(sizes, reverse=True) and sizes[-1] < sizes[0]


def test_the_quick_plots_check_agrees_with_the_guidance_test():
    """``looks_like_plots``' quick no (numpy over the rows) never hides plots the core's
    test (``plot_like`` over ``track_summary``) finds: scans, tracks, 2-row shared times."""
    from wakeline.app.layer_view import looks_like_plots
    from wakeline.core.tracks import plot_like, sort_points, track_summary

    def full(pts):
        summary = track_summary(pts)
        like = plot_like(summary)
        n = summary["points"].to_numpy(dtype="float64")
        return bool(n[like].sum() * 2 > n.sum())

    for seed in (1, 2, 3):
        pairs = plots_scene(seed, scans=200, per_scan=2)  # runs of two rows at one time
        for pts in (plots_scene(seed), star_scene(seed, 8, 50), pairs):
            pts = sort_points(pts)
            assert looks_like_plots(pts) == full(pts)


def test_a_layer_recoloured_with_as_many_curves_takes_the_new_colours(qtbot):
    """Two sensors' plots coloured by track: still two curves, but the items and their
    legend entries take the track colours (they kept the sensors' brush and words)."""
    from wakeline.app.map_draw import as_points, recolor

    canvas = _shown_canvas(qtbot)
    for seed in (1, 2):
        pts = pd.concat([plots_scene(seed), plots_scene(seed + 10).assign(sensor="lidar")])
        data = as_points(prepare_layer(pts, "ferry", by_sensor=True), True)
        canvas.set_draw_data(data)
        out = recolor(data, True)
        assert len(out.curves) == len(data.curves) == 2
        canvas.set_draw_data(out)
        items = canvas.layer_items("ferry")
        brushes = [i.opts["symbolBrush"].color().name() for i in items]
        assert brushes == [c.color for c in out.curves] != [c.color for c in data.curves]
        shown = {lab.text for _s, lab in canvas.legend.items}
        last_lines = [c.label.split("\n")[-1].split(" · ")[-1] for c in out.curves]
        assert all(t in " ".join(shown) for t in last_lines), (last_lines, shown)
        canvas.remove_layer("ferry")


def test_a_selected_track_of_a_layer_coloured_by_track_has_one_legend_line(qtbot):
    """Operator test 10: an MTAD scene's compressed layer coloured by track, its track
    9001/412434718-0 selected: the legend said "9001:412434718-0" (the track's colour) and
    "9001 · 412434718-0" (the selection's). One line per track now, named "sensor · batch"
    as the selection names it, the selected track drawn in the colour its line shows; a
    track the layer's legend does not name keeps its selection line."""
    from wakeline.app.map_draw import named_tracks, recolor
    from wakeline.app.map_legend import short_label

    canvas = _shown_canvas(qtbot)
    for seed in (3, 4):
        pts = pd.concat(
            [star_scene(seed, 3, 30), star_scene(seed + 1, 3, 30).assign(sensor="R2")],
            ignore_index=True,
        )
        data = recolor(prepare_layer(pts, "scene", "#2ca02c"), True)
        canvas.set_draw_data(data)
        named = named_tracks(data.geometry)
        assert len(named) == 6  # every track has its line (6 ≤ LEGEND_TRACKS)
        sensor, batch = "R2", str(pts.loc[pts["sensor"] == "R2", "batch"].iloc[1])
        canvas.show_selection(pts[(pts["sensor"] == sensor) & (pts["batch"] == batch)])
        canvas._sync_selection_legend()
        texts = [label.text for _s, label in canvas.legend.items]
        name = f"{sensor} · {batch}"
        assert sum(short_label(name) in t or name in t for t in texts) == 1, texts
        assert not any(f"{sensor}:{batch}" in t for t in texts), texts
        # drawn in the colour its legend line shows, and the window's swatch agrees
        colour = named[(sensor, batch)]
        assert [i.opts["pen"].color().name() for i in canvas.selection_items()] == [colour]
        assert canvas.selection_color(sensor, batch) == colour
        canvas.remove_layer("scene")
    # a layer in its own colour: the selection names its track, in a colour of its own
    plain = prepare_layer(pts, "scene", "#2ca02c")
    canvas.set_draw_data(plain)
    canvas.show_selection(pts[(pts["sensor"] == sensor) & (pts["batch"] == batch)])
    canvas._sync_selection_legend()
    texts = [label.text for _s, label in canvas.legend.items]
    assert sum(name in t for t in texts) == 1
    assert canvas.selection_color(sensor, batch) != "#2ca02c"

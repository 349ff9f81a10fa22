"""Map drawing: 1 M points across 2,000 tracks (rows shuffled). What is drawn (vertices in
the path after the per-pixel level of detail, against what the previous clip-to-view +
auto-downsample drawing kept), the worker-side preparation time, time to first paint and
the mean frame time of a scripted pan/zoom, against drawing one curve item per track with
every point (the naive way, measured in the same run).

Run: ``QT_QPA_PLATFORM=offscreen python bench/bench_map.py [--points 1000000] [--tracks 2000]``.
Times are process CPU times (the machine is shared; wall times there measure the others).
Goal (issue 8): < 50 ms per frame.
"""

import argparse
import time

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtWidgets

from wakeline.app.map_canvas import MapCanvas
from wakeline.app.map_draw import LayerStyle, nan_separated, prepare_layer, relod
from wakeline.core import geo


def make_points(n_points: int, n_tracks: int, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    per = n_points // n_tracks
    track = np.repeat(np.arange(n_tracks), per)
    k = np.tile(np.arange(per), n_tracks)
    heading = np.cumsum(np.where(rng.random(len(k)) < 0.01, rng.normal(0, 40, len(k)), 0.0))
    heading += np.repeat(rng.uniform(0, 360, n_tracks), per)
    x = np.cumsum(60.0 * np.sin(np.radians(heading)))
    y = np.cumsum(60.0 * np.cos(np.radians(heading)))
    x -= np.repeat(x[k == 0], per)
    y -= np.repeat(y[k == 0], per)
    lon, lat = geo.from_local(
        x, y, 122.0 + rng.uniform(0, 3, n_tracks)[track], 29.0 + rng.uniform(0, 3, n_tracks)[track]
    )
    t = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(k * 10, unit="s")
    return pd.DataFrame(
        {"sensor": "R1", "batch": pd.Series(track).astype("str"), "time": t, "lon": lon, "lat": lat}
    )


def frames(app: QtWidgets.QApplication, widget, vb, steps: int = 40, each=None) -> float:
    """Mean seconds per frame over a scripted zoom in, pan and zoom out (``each()`` runs
    inside every frame: our level of detail, done synchronously here). Process CPU time,
    not wall time: the bench machine is shared, and wall time there measures the others."""
    (x0, x1), (y0, y1) = vb.viewRange()
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    times = []
    for k in range(steps):
        f = 1.0 - 0.8 * k / steps if k < steps // 2 else 0.2 + 0.8 * (k - steps // 2) / (steps // 2)
        dx = 0.3 * (x1 - x0) * np.sin(k / 6)
        w, h = (x1 - x0) * f / 2, (y1 - y0) * f / 2
        t = time.process_time()
        vb.setRange(xRange=(cx + dx - w, cx + dx + w), yRange=(cy - h, cy + h), padding=0)
        if each is not None:
            each()
        widget.repaint()
        app.processEvents()
        times.append(time.process_time() - t)
    return float(np.mean(times))


def old_way_vertices(app, df: pd.DataFrame) -> int:
    """Vertices the previous drawing (pyqtgraph clip-to-view + auto-downsampling on one
    NaN-separated curve) actually put in the path, at the same fitted view."""
    plot = pg.PlotWidget()
    plot.resize(1000, 700)
    plot.show()
    vb = plot.getPlotItem().getViewBox()
    vb.setAspectLocked(True, ratio=np.cos(np.radians(float(df["lat"].mean()))))
    lon, lat = nan_separated(df)
    item = pg.PlotDataItem(lon, lat, connect="finite")
    plot.addItem(item)
    item.setDownsampling(auto=True, method="peak")
    item.setClipToView(True)
    vb.setRange(xRange=(np.nanmin(lon), np.nanmax(lon)), yRange=(np.nanmin(lat), np.nanmax(lat)))
    plot.repaint()
    app.processEvents()
    x, _ = item.curve.getData()
    n = int(np.isfinite(x).sum()) if x is not None else 0
    plot.close()
    return n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--tracks", type=int, default=2000)
    ap.add_argument("--naive-tracks", type=int, default=500, help="tracks of the baseline")
    args = ap.parse_args()
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    df = make_points(args.points, args.tracks)
    df = df.sample(frac=1.0, random_state=1).reset_index(drop=True)  # rows in any order

    canvas = MapCanvas()
    canvas.resize(1000, 700)
    canvas.show()
    app.processEvents()
    t = time.process_time()
    data = prepare_layer(df, "bench", style=LayerStyle(width=1.0))
    t_prepare = time.process_time() - t
    t = time.process_time()
    canvas.set_true_aspect(float(df["lat"].mean()))
    canvas.set_draw_data(data)
    canvas.fit()  # fits and decimates for the view
    canvas.repaint()
    app.processEvents()
    first = time.process_time() - t
    x0, x1, y0, y1 = canvas.current_view()
    t = time.process_time()
    relod(canvas.draw_data("bench"), (x0, x1, y0, y1), canvas.plot_size_px())
    t_lod = time.process_time() - t
    drawn_full = canvas.n_vertices()
    pieces = sum(int(np.isnan(c.lon).sum()) + 1 for c in canvas.draw_data("bench").curves)
    print(
        f"prepare_layer (worker side: sort, unwrap, speed, k-d tree): {t_prepare * 1000:.0f} ms; "
        f"level of detail for a view: {t_lod * 1000:.0f} ms"
    )
    print(
        f"ours, fitted view: {args.points:,} points in {args.tracks:,} tracks drawn as "
        f"{drawn_full:,} vertices in {pieces:,} NaN-separated pieces "
        f"(every point within its pixel of a vertex) in {canvas.n_items()} item(s); "
        f"swap + fit + first paint {first * 1000:.0f} ms"
    )
    frame = frames(app, canvas, canvas.vb, each=canvas.refresh_lod)
    canvas.vb.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0)
    canvas.refresh_lod()
    frame_deferred = frames(app, canvas, canvas.vb)
    canvas.vb.setRange(
        xRange=((x0 + x1) / 2 - (x1 - x0) / 40, (x0 + x1) / 2 + (x1 - x0) / 40),
        yRange=((y0 + y1) / 2 - (y1 - y0) / 40, (y0 + y1) / 2 + (y1 - y0) / 40),
        padding=0,
    )
    canvas.refresh_lod()
    print(
        f"ours, pan/zoom: mean frame {frame * 1000:.1f} ms with the level of detail redone "
        f"in every frame, {frame_deferred * 1000:.1f} ms with it deferred (the canvas redoes "
        "it 60 ms after the view settles, or in a worker); "
        f"zoomed in 20x: {canvas.n_vertices():,} vertices (view and one view around it)"
    )
    old = old_way_vertices(app, df)
    print(
        f"previous drawing (clip-to-view + auto-downsample on the NaN-separated curve): "
        f"{old:,} vertices at the fitted view (ours {drawn_full:,})"
    )

    plot = pg.PlotWidget()
    plot.resize(1000, 700)
    plot.show()
    app.processEvents()
    sub = df[df["batch"].astype(int) < args.naive_tracks].sort_values(["batch", "time"])
    t = time.process_time()
    for _, g in sub.groupby("batch", sort=False):
        plot.plot(g["lon"].to_numpy(), g["lat"].to_numpy(), pen="b")
    plot.repaint()
    app.processEvents()
    first_naive = time.process_time() - t
    frame_naive = frames(app, plot, plot.getPlotItem().getViewBox())
    print(
        f"baseline, one item per track, every point: {len(sub):,} points in "
        f"{args.naive_tracks:,} items: first paint {first_naive * 1000:.0f} ms, mean frame "
        f"{frame_naive * 1000:.1f} ms (ours, with all {args.tracks:,} tracks: "
        f"{first_naive / first:.1f}x faster to first paint, {frame_naive / frame:.1f}x per frame "
        "with the level of detail in every frame)"
    )


if __name__ == "__main__":
    main()

"""Map drawing: 1 M points across 2,000 tracks, time to first paint and the mean frame time
of a scripted pan/zoom, against drawing one curve item per track (the naive way).

Run: ``QT_QPA_PLATFORM=offscreen python bench/bench_map.py [--points 1000000] [--tracks 2000]``.
Goal (issue 8): < 50 ms per frame.
"""

import argparse
import time

import numpy as np
import pandas as pd
import pyqtgraph as pg
from PySide6 import QtWidgets

from wakeline.app.map_canvas import MapCanvas, nan_separated
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


def frames(app: QtWidgets.QApplication, widget, vb, steps: int = 40) -> float:
    """Mean seconds per frame over a scripted zoom in, pan and zoom out."""
    (x0, x1), (y0, y1) = vb.viewRange()
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    times = []
    for k in range(steps):
        f = 1.0 - 0.8 * k / steps if k < steps // 2 else 0.2 + 0.8 * (k - steps // 2) / (steps // 2)
        dx = 0.3 * (x1 - x0) * np.sin(k / 6)
        w, h = (x1 - x0) * f / 2, (y1 - y0) * f / 2
        t = time.perf_counter()
        vb.setRange(xRange=(cx + dx - w, cx + dx + w), yRange=(cy - h, cy + h), padding=0)
        widget.repaint()
        app.processEvents()
        times.append(time.perf_counter() - t)
    return float(np.mean(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--tracks", type=int, default=2000)
    ap.add_argument("--naive-tracks", type=int, default=2000)
    args = ap.parse_args()
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    df = make_points(args.points, args.tracks)

    canvas = MapCanvas()
    canvas.resize(1000, 700)
    canvas.show()
    app.processEvents()
    t = time.perf_counter()
    canvas.set_layer("bench", df, "#1f77b4", symbols=False)
    canvas.set_true_aspect(float(df["lat"].mean()))
    canvas.fit()
    canvas.repaint()
    app.processEvents()
    first = time.perf_counter() - t
    frame = frames(app, canvas, canvas.vb)
    print(
        f"ours: {args.points:,} points in {args.tracks:,} tracks as {canvas.n_items()} item(s): "
        f"first paint {first * 1000:.0f} ms, mean frame {frame * 1000:.1f} ms"
    )

    plot = pg.PlotWidget()
    plot.resize(1000, 700)
    plot.show()
    app.processEvents()
    sub = df[df["batch"].astype(int) < args.naive_tracks]
    t = time.perf_counter()
    for _, g in sub.groupby("batch", sort=False):
        plot.plot(g["lon"].to_numpy(), g["lat"].to_numpy(), pen="b")
    plot.repaint()
    app.processEvents()
    first_naive = time.perf_counter() - t
    frame_naive = frames(app, plot, plot.getPlotItem().getViewBox())
    print(
        f"one item per track: {len(sub):,} points in {args.naive_tracks:,} items: first paint "
        f"{first_naive * 1000:.0f} ms, mean frame {frame_naive * 1000:.1f} ms "
        f"(ours {first_naive / first:.1f}x faster to first paint, {frame_naive / frame:.1f}x per frame)"
    )
    lon, _ = nan_separated(df)
    print(f"NaN separators: {int(np.isnan(lon).sum()):,} (tracks - 1)")


if __name__ == "__main__":
    main()

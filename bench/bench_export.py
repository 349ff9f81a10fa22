"""Export throughput: ``write_layout`` in a radar layout (GB18030, unix seconds, 6-decimal
positions, two operator text columns) and in the day-first DMA time format, against
``write_points`` (the canonical CSV, pyarrow's CSV writer) on the same points.

Best of ``--repeat`` runs each, alternating; prints seconds and the ratio to the
baseline. Run: ``python bench/bench_export.py [--rows 1000000]``.
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.io import write_points
from wakeline.core.io.export_like import write_layout
from wakeline.core.io.layout import Column, preset_layout


def make_points(rows: int, tracks: int, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    per = rows // tracks
    track = np.repeat(np.arange(tracks), per)
    k = np.tile(np.arange(per), tracks)
    n = len(track)
    t = pd.Timestamp("2022-10-01T02:16:03Z") + pd.to_timedelta(k * 10 + track, unit="s")
    return pd.DataFrame(
        {
            "sensor": pd.Series(np.where(track % 3 == 0, "1043", "1044"), dtype="str"),
            "batch": pd.Series(track.astype(str), dtype="str"),
            "time": t,
            "lon": np.round(122 + k * 1e-4 + rng.normal(0, 1e-4, n), 6),
            "lat": np.round(30 + k * 1e-4 + rng.normal(0, 1e-4, n), 6),
            "speed": np.round(rng.uniform(0, 20, n), 1),
            "course": np.round(rng.uniform(0, 360, n), 1),
            "目标类型": pd.Series(np.where(track % 2 == 0, "货船", "渔船"), dtype="str"),
            "备注": pd.Series(np.where(k % 50 == 0, "疑似拖网", ""), dtype="str"),
        }
    )


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--tracks", type=int, default=1_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    pts = make_points(args.rows, args.tracks)
    radar = preset_layout("radar")
    radar = radar.__class__(
        **{
            **radar.__dict__,
            "columns": radar.columns
            + (Column("目标类型", key="目标类型"), Column("备注", key="备注")),
        }
    )
    dma = preset_layout("dma")
    folder = Path(tempfile.mkdtemp(prefix="wakeline-bench-"))
    runs = {
        "canonical write_points (baseline)": lambda: write_points(pts, folder / "c.csv"),
        "radar layout, GB18030": lambda: write_layout(pts, radar, folder / "r.csv"),
        "dma layout, day-first": lambda: write_layout(pts, dma, folder / "d.csv"),
    }
    results = {name: best(fn, args.repeat) for name, fn in runs.items()}
    base = results["canonical write_points (baseline)"]
    print(f"{len(pts):,} points")
    for name, sec in results.items():
        print(f"{name:36s} {sec:7.2f} s  {len(pts) / sec / 1e6:5.2f} M rows/s  {sec / base:4.2f}x")
    for f in folder.iterdir():
        f.unlink()
    folder.rmdir()


if __name__ == "__main__":
    main()

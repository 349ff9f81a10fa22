"""Cleaning throughput: the default rules over many tracks (goal: 10 M points of 10 k tracks
in <= 10 s on the 2-core machine). Prints seconds and points/s, and the same table sorted
with pandas as a baseline run in the same command.

Run: ``python bench/bench_clean.py [--points 10000000] [--tracks 10000]``.
"""

import argparse
import time

import numpy as np
from bench_maneuver import make_points

from wakeline.core import geo
from wakeline.core.clean import clean


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=10_000_000)
    ap.add_argument("--tracks", type=int, default=10_000)
    args = ap.parse_args()
    df = make_points(args.points, args.tracks)
    rng = np.random.default_rng(1)
    n = len(df)
    jumps = rng.choice(n, n // 1000, replace=False)  # 0.1 % jumps of 2-10 km
    lon, lat = geo.destination(
        df.lon.to_numpy()[jumps],
        df.lat.to_numpy()[jumps],
        rng.uniform(0, 360, len(jumps)),
        rng.uniform(2000, 10000, len(jumps)),
    )
    df.loc[jumps, "lon"], df.loc[jumps, "lat"] = lon, lat
    df["speed"] = rng.uniform(8, 14, n).round(1)
    print(f"{n:,} points in {args.tracks:,} tracks, {len(jumps):,} injected jumps")

    t = time.perf_counter()
    df.sort_values(["sensor", "batch", "time"], kind="stable")
    base = time.perf_counter() - t
    t = time.perf_counter()
    result = clean(df)
    sec = time.perf_counter() - t
    rules = ", ".join(
        f"{k} {v.get('removed', 0) + v.get('changed', 0):,}"
        for k, v in result.report["rules"].items()
    )
    print(f"baseline: pandas sort_values by sensor, batch, time: {base:.2f} s")
    print(
        f"clean() default rules: {sec:.2f} s, {n / sec / 1e6:.2f} M points/s "
        f"({sec / base:.1f}x the sort) (goal <= 10 s)"
    )
    print(f"  {rules}")
    ordered = result.points  # already in track order: no sort needed
    t = time.perf_counter()
    clean(ordered)
    sec2 = time.perf_counter() - t
    print(
        f"clean() again on its own output (rows already in track order): {sec2:.2f} s, "
        f"{len(ordered) / sec2 / 1e6:.2f} M points/s"
    )


if __name__ == "__main__":
    main()

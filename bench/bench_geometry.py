"""CPU time of the geometry the engine's hot paths share: the local plane
(``tracks.local_xy``), interpolation along the great circle (``tracks.interp_positions``),
and ``detect`` / ``clean`` over it, on ``bench_maneuver.make_points`` tracks. CPU time (best
of several runs) is the steadier figure on a shared machine; run it on two commits, or
with ``PYTHONPATH`` pointing at an unpacked older tree, to compare.

Run: ``python bench/bench_geometry.py [--points 10000000] [--tracks 10000]``.
"""

import argparse
import time

import numpy as np
from bench_maneuver import make_points

from wakeline.core.clean import clean
from wakeline.core.maneuver import detect
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import interp_positions, local_xy, sorted_with_index


def best_cpu(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        c = time.process_time()
        fn()
        best = min(best, time.process_time() - c)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=10_000_000)
    ap.add_argument("--tracks", type=int, default=10_000)
    args = ap.parse_args()
    df = make_points(args.points, args.tracks)
    pts, index = sorted_with_index(df)
    n = len(pts)
    print(f"{n:,} points in {index.n_tracks:,} tracks (CPU seconds, best of several)")
    print(f"local_xy: {best_cpu(lambda: local_xy(pts, index), 7):.3f} s")
    rng = np.random.default_rng(0)
    track = rng.integers(0, index.n_tracks, n // 10)
    t = time_seconds(pts["time"])
    span = t[index.ends - 1] - t[index.starts]
    q = t[index.starts[track]] + rng.uniform(0.0, 1.0, len(track)) * span[track]
    cost = best_cpu(lambda: interp_positions(pts, index, track, q), 5)
    print(f"interp_positions, {len(track):,} queries: {cost:.3f} s")
    print(f"detect (sorted table): {best_cpu(lambda: detect(pts), 3):.2f} s")
    df["speed"] = rng.uniform(8, 14, n).round(1)
    print(f"clean: {best_cpu(lambda: clean(df), 2):.2f} s")


if __name__ == "__main__":
    main()

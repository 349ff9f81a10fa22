"""Interrupted-track association at scale: time and memory for 1 k, 10 k and 100 k
segments, the growth per 10× segments of the candidate pairs and of the whole association
(wall and CPU time; the k-d tree way of earlier versions measured in the same run), and
the speed-up over the dense way (an n×n cost matrix and linear_sum_assignment) on a
subset both can run.

Run: ``python bench/bench_associate.py [--segments 1000 10000 100000] [--dense 2500]
[--repeat 2]``.
Goals: issue 6, 10 k segments in < 10 s and 100 k well below the machine's 24 GB;
issue 17, association growth ≤ 11× per 10× segments. CPU time is printed beside wall
time: on a shared machine it is the steadier of the two.
"""

import argparse
import hashlib
import os
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from wakeline.core import associate as assoc_mod
from wakeline.core import geo, simulate
from wakeline.core.associate import (
    LinkParams,
    Pairs,
    _miss_one_turn,
    associate_interrupted,
    candidate_pairs,
    pair_cost,
)
from wakeline.core.evaluate_association import score_association
from wakeline.core.segments import segment_stats
from wakeline.core.tracks import sorted_with_index


def scene(n_segments: int, seed: int = 0):
    """About ``n_segments`` segments: ships at the density of the 'dense' class scaled up,
    60 s sampling (points per segment do not matter to the pairing).

    Simulating 100 k segments takes minutes, so each scene is kept in
    ``$WAKELINE_BENCH_CACHE`` (default ``~/.cache/wakeline-bench``) as Parquet, keyed by
    its size, its seed and a hash of the simulator's source: a changed simulator makes a
    new scene. Set ``WAKELINE_BENCH_CACHE=`` (empty) to simulate every time."""
    ships = max(int(n_segments / 3.0), 2)
    area = 20.0 * np.sqrt(ships / 80.0)
    folder = os.environ.get("WAKELINE_BENCH_CACHE", str(Path.home() / ".cache/wakeline-bench"))
    if not folder:
        return simulate.segments_scene(seed=seed, n_ships=ships, area_km=area, period_s=60.0)
    digest = hashlib.sha256(Path(simulate.__file__).read_bytes()).hexdigest()[:12]
    path = Path(folder) / f"scene-{n_segments}-{seed}-{digest}.parquet"
    if path.exists():
        return pd.read_parquet(path)
    df = simulate.segments_scene(seed=seed, n_ships=ships, area_km=area, period_s=60.0)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    df.to_parquet(tmp)
    os.replace(tmp, path)
    return pd.read_parquet(path)  # the same dtypes whether simulated now or before


def dense_baseline(points, params: LinkParams) -> tuple[float, int]:
    """Every (old, new) pair scored in an n×n matrix, then linear_sum_assignment."""
    t = time.perf_counter()
    seg = segment_stats(points, params.end_points, end_points_max=params.end_points_max)
    n = len(seg)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    gap = seg.t0[j] - seg.t1[i]
    dist = geo.haversine_m(seg.lon1[i], seg.lat1[i], seg.lon0[j], seg.lat0[j])
    px, py = geo.to_local(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    miss = _miss_one_turn(
        px, py, seg.vx1[i] * gap, seg.vy1[i] * gap, seg.vx0[j] * gap, seg.vy0[j] * gap
    )
    dc = geo.angle_diff(seg.course1_deg[i], seg.course0_deg[j])
    dv = np.abs(seg.speed1_kn[i] - seg.speed0_kn[j])
    cost = pair_cost(Pairs(i, j, gap, dist, miss, dc, dv), params, seg=seg)
    ok = (gap > 0) & (gap <= params.max_gap_s) & (cost <= params.gate)
    big = 1e6
    matrix = np.where(ok, cost, big).reshape(n, n)
    r, c = linear_sum_assignment(matrix)
    chosen = int((matrix[r, c] < big).sum())
    return time.perf_counter() - t, chosen


def timed(fn, repeat: int) -> tuple[float, float]:
    """Best wall and best CPU time (s) of ``repeat`` runs."""
    wall, cpu = [], []
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w)
        cpu.append(time.process_time() - c)
    return min(wall), min(cpu)


def tree_pairs(seg, params: LinkParams) -> Pairs:
    """Candidate pairs the way of earlier versions: the k-d tree only."""
    grid = assoc_mod._grid_pairs
    assoc_mod._grid_pairs = lambda *args, **kwargs: None
    try:
        return candidate_pairs(seg, params)
    finally:
        assoc_mod._grid_pairs = grid


def growth(sizes: list[int], repeat: int) -> None:
    """Candidate pairs (grid and sweep; k-d tree) and the whole association per size, and
    the growth per 10× segments of each."""
    params = LinkParams()
    prev = None
    with open("/proc/loadavg") as f:
        print(f"load before: {f.read().split()[0]}")
    for n in sizes:
        df = scene(n)
        # Sorted once, as the step before hands it on (issue 17, "sort once"); the sort of
        # the unsorted points is timed apart: it is n log n and not the association's.
        w, c = time.perf_counter(), time.process_time()
        df, _ = sorted_with_index(df)
        sort_t = (time.perf_counter() - w, time.process_time() - c)
        seg = segment_stats(df, params.end_points, end_points_max=params.end_points_max)
        t = {
            "pairs": timed(lambda seg=seg: candidate_pairs(seg, params), repeat),
            "k-d tree pairs": timed(lambda seg=seg: tree_pairs(seg, params), repeat),
            "association": timed(lambda df=df: associate_interrupted(df, params), repeat),
        }
        line = f"{len(seg):>7,} segments: " + ", ".join(
            f"{k} {w:.3f} s wall / {c:.3f} s CPU" for k, (w, c) in t.items()
        )
        line += f" (sorting the {len(df):,} unsorted points before: {sort_t[1]:.2f} s CPU)"
        if prev is not None:
            f = np.log10(len(seg) / prev[0])
            line += "; growth per 10x (wall/CPU): " + ", ".join(
                f"{k} {(t[k][0] / prev[1][k][0]) ** (1 / f):.1f}x/"
                f"{(t[k][1] / prev[1][k][1]) ** (1 / f):.1f}x"
                for k in t
            )
        with open("/proc/loadavg") as fh:
            print(line + f"  (goal <= 11x; load {fh.read().split()[0]})", flush=True)
        prev = (len(seg), t)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--segments", type=int, nargs="+", default=[1000, 10_000, 100_000])
    ap.add_argument("--dense", type=int, default=2500, help="segments for the dense comparison")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--growth-only", action="store_true", help="only the growth per 10x (issue 17)")
    args = ap.parse_args()
    params = LinkParams()
    growth(args.segments, args.repeat)
    if args.growth_only:
        return

    df = scene(args.dense)
    t = time.perf_counter()
    a = associate_interrupted(df, params)
    ours = time.perf_counter() - t
    base, base_pairs = dense_baseline(df, params)
    print(
        f"{len(a.segments):,} segments: ours {ours:.2f} s ({len(a.chosen):,} joins), "
        f"dense n×n + linear_sum_assignment {base:.2f} s ({base_pairs:,} joins): "
        f"{base / ours:.0f}× faster"
    )
    for n in args.segments:
        t = time.perf_counter()
        df = scene(n)
        sim = time.perf_counter() - t
        for method in ("optimal", "greedy"):
            t = time.perf_counter()
            a = associate_interrupted(df, params, method=method)
            el = time.perf_counter() - t
            tracemalloc.start()
            associate_interrupted(df, params, method=method)
            peak = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
            sc = score_association(a)
            print(
                f"{len(a.segments):,} segments ({len(df):,} points, simulated in {sim:.0f} s), "
                f"{method}: {el:.2f} s, {len(a.pairs):,} candidate pairs, "
                f"P_CA {sc['p_ca']:.3f} P_FA {sc['p_fa']:.3f}; "
                f"peak memory of the association {peak:,.0f} MB (input table excluded)"
            )
        del df, a


if __name__ == "__main__":
    main()

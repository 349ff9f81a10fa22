"""Interrupted-track association at scale: time and memory for 10 k and 100 k segments,
and the speed-up over the dense way (an n×n cost matrix and linear_sum_assignment) on a
subset both can run.

Run: ``python bench/bench_associate.py [--segments 10000 100000] [--dense 2500]``.
Goals (issue 6): 10 k segments in < 10 s; 100 k well below the machine's 24 GB.
"""

import argparse
import time
import tracemalloc

import numpy as np
from scipy.optimize import linear_sum_assignment

from wakeline.core import geo, simulate
from wakeline.core.associate import (
    LinkParams,
    Pairs,
    _miss_one_turn,
    associate_interrupted,
    pair_cost,
)
from wakeline.core.evaluate_association import score_association
from wakeline.core.segments import segment_stats


def scene(n_segments: int, seed: int = 0):
    """About ``n_segments`` segments: ships at the density of the 'dense' class scaled up,
    60 s sampling (points per segment do not matter to the pairing)."""
    ships = max(int(n_segments / 3.0), 2)
    area = 20.0 * np.sqrt(ships / 80.0)
    return simulate.segments_scene(seed=seed, n_ships=ships, area_km=area, period_s=60.0)


def dense_baseline(points, params: LinkParams) -> tuple[float, int]:
    """Every (old, new) pair scored in an n×n matrix, then linear_sum_assignment."""
    t = time.perf_counter()
    seg = segment_stats(points, params.end_points)
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--segments", type=int, nargs="+", default=[10_000, 100_000])
    ap.add_argument("--dense", type=int, default=2500, help="segments for the dense comparison")
    args = ap.parse_args()
    params = LinkParams()

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

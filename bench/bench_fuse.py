"""Multi-sensor association and fusion at scale: 2 × 2,000 simulated tracks, against the
dense way (every track of sensor 1 × every track of sensor 2 measured, as seed 003's
double loop does) on a subset both can run.

Run: ``python bench/bench_fuse.py [--ships 2000] [--dense-ships 300]``.
Goal (issue 7): 2 × 2,000 tracks associated in < 30 s.
"""

import argparse
import time

import numpy as np

from wakeline.core import simulate
from wakeline.core.associate import optimal_assign
from wakeline.core.evaluate_association import fusion_errors, sensor_pair_scores
from wakeline.core.fuse import (
    FuseParams,
    _count_in,
    _spans,
    _sync_distance,
    associate_sensors,
    fuse,
)
from wakeline.core.tracks import sorted_with_index


def scene(ships: int, seed: int = 0):
    area = 30.0 * np.sqrt(ships / 40.0)  # the '40 / 30 km' density
    return simulate.multisensor_scene(seed=seed, n_ships=ships, area_km=area)


def dense_baseline(df, params: FuseParams) -> tuple[float, int]:
    """All n₁ × n₂ pairs: overlap and ratio gates, synchronized distance, assignment."""
    t = time.perf_counter()
    pts, index = sorted_with_index(df)
    ts, t0, t1 = _spans(pts, index)
    sensor = index.keys["sensor"].to_numpy()
    ia, ib = np.flatnonzero(sensor == "AIS"), np.flatnonzero(sensor == "R1")
    a, b = np.repeat(ia, len(ib)), np.tile(ib, len(ia))
    lo, hi = np.maximum(t0[a], t0[b]), np.minimum(t1[a], t1[b])
    ok = hi - lo >= params.min_overlap_s
    a, b, lo, hi = a[ok], b[ok], lo[ok], hi[ok]
    na, ra = _count_in(ts, index, a, lo, hi)
    nb, rb = _count_in(ts, index, b, lo, hi)
    ratio = np.maximum(na, nb) / np.maximum(np.minimum(na, nb), 1)
    ok = (np.minimum(na, nb) >= 2) & (ratio <= params.count_ratio_max)
    a, b, na, ra, nb, rb = a[ok], b[ok], na[ok], ra[ok], nb[ok], rb[ok]
    base_a = na <= nb
    d = _sync_distance(
        pts,
        index,
        ts,
        np.where(base_a, a, b),
        np.where(base_a, b, a),
        np.where(base_a, ra, rb),
        np.minimum(na, nb),
        params.max_interp_s,
    )
    chosen = optimal_assign(a, b, d, params.max_distance_m)
    return time.perf_counter() - t, len(chosen)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--ships", type=int, default=2000)
    ap.add_argument("--dense-ships", type=int, default=300)
    args = ap.parse_args()
    params = FuseParams()

    df = scene(args.dense_ships)
    t = time.perf_counter()
    a = associate_sensors(df, params)
    ours = time.perf_counter() - t
    base, base_pairs = dense_baseline(df, params)
    print(
        f"{args.dense_ships} ships: ours {ours:.2f} s ({len(a.chosen)} pairs), all n1 x n2 pairs "
        f"{base:.2f} s ({base_pairs} pairs): {base / ours:.1f}x faster"
    )

    t = time.perf_counter()
    df = scene(args.ships)
    sim = time.perf_counter() - t
    counts = df.groupby("sensor")["batch"].nunique().to_dict()
    for distance in ("sync", "dtw"):
        t = time.perf_counter()
        a = associate_sensors(df, params, distance=distance)
        el = time.perf_counter() - t
        sc = sensor_pair_scores(a)
        print(
            f"{counts} tracks ({len(df):,} points, simulated in {sim:.0f} s), {distance}: "
            f"associated in {el:.2f} s, {len(a.a):,} candidates, "
            f"P_CA {sc['p_ca']:.3f} P_FA {sc['p_fa']:.3f}"
        )
    t = time.perf_counter()
    a = associate_sensors(df, params)
    f = fuse(a, params)
    el = time.perf_counter() - t
    err = fusion_errors(a, f)
    print(
        f"associate + fuse: {el:.2f} s, {len(f):,} fused points; error in the overlap: fused "
        f"{err['fused_m']:.1f} m, AIS {err['AIS_m']:.1f} m, R1 {err['R1_m']:.1f} m"
    )


if __name__ == "__main__":
    main()

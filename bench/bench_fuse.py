"""Multi-sensor association and fusion at scale: 2 × 2,000 simulated tracks, against the
dense way (every track of sensor 1 × every track of sensor 2 measured, as seed 003's
double loop does) on a subset both can run.

Run: ``python bench/bench_fuse.py [--ships 2000] [--dense-ships 300]``.
Goal (issue 7): 2 × 2,000 tracks associated in < 30 s.

``--atd`` (session 27, h168 D-fuse-2): the probe grid of the two ATD 2025 files as two
sensors, made over each track's whole span then filtered (before) against made from the
fixes' short intervals (after, ``core/fuse._probe_grid``): probes, time and peak memory
(tracemalloc) of grid + positions, with ratios; then associate + fuse of the pair.
``--time-base`` (session 27, h168 D-fuse-1): the h168 1 s radar + 30 s AIS of one ship fused
with each ``time_base``: points, radar fixes kept, mean distance from the AIS path.
Both need WAKELINE_SHARED; the second also the h168 pair (``ship_radar_1s.csv``,
``ship_ais_30s.csv``, made by operator test 4 from the DMA sample ship and not kept in
the repo or in shared/): ``--pair-dir DIR`` (default $WAKELINE_H168_DIR); without it the
run says so and stops.
"""

import argparse
import os
import time
import tracemalloc
from pathlib import Path

import numpy as np

from wakeline.core import simulate
from wakeline.core.associate import optimal_assign
from wakeline.core.evaluate_association import fusion_errors, sensor_pair_scores
from wakeline.core.fuse import (
    FuseParams,
    _count_in,
    _probe_grid,
    _spans,
    _sync_distance,
    associate_sensors,
    fuse,
)
from wakeline.core.tracks import concat_ranges, interp_positions, sorted_with_index


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


def _whole_span_probes(pts, index, t0, t1, params: FuseParams):
    """The probe grid as it was made before session 27: every grid time over each track's
    span (plus half a step), positions for all, then the ones in long gaps dropped."""
    p = params.probe_s
    g0 = np.ceil((t0 - p / 2) / p).astype("int64")
    g1 = np.floor((t1 + p / 2) / p).astype("int64")
    count = np.maximum(g1 - g0 + 1, 1)
    track = np.repeat(np.arange(index.n_tracks), count)
    grid = concat_ranges(g0, count)
    lon, lat, ok = interp_positions(pts, index, track, grid * p, params.max_interp_s)
    near_end = (grid * p >= t0[track] - p) & (grid * p <= t1[track] + p)
    ok |= near_end & ((grid * p < t0[track]) | (grid * p > t1[track]))
    return track[ok], grid[ok], lon[ok], lat[ok]


def _new_probes(pts, index, t0, t1, params: FuseParams):
    t = _spans(pts, index)[0]
    track, grid = _probe_grid(t, index, t0, t1, params)
    lon, lat, _ = interp_positions(pts, index, track, grid * params.probe_s)
    return track, grid, lon, lat


def _measured(fn, *args):
    tracemalloc.start()
    t = time.perf_counter()
    out = fn(*args)
    el = time.perf_counter() - t
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return out, el, peak


def atd(params: FuseParams) -> None:
    from wakeline.app.cli_review import read_inputs

    d = Path(os.environ.get("WAKELINE_SHARED", "/work/shared")) / "data/real/atd2025-noaa"
    df = read_inputs([d / "example_truth.csv.gz", d / "dataset1_truth.csv.gz"])
    pts, index = sorted_with_index(df)
    _, t0, t1 = _spans(pts, index)
    old, t_old, m_old = _measured(_whole_span_probes, pts, index, t0, t1, params)
    new, t_new, m_new = _measured(_new_probes, pts, index, t0, t1, params)
    same = all(np.array_equal(a, b) for a, b in zip(old, new, strict=True))
    p = params.probe_s
    made = int(np.maximum(np.floor((t1 + p / 2) / p) - np.ceil((t0 - p / 2) / p) + 1, 1).sum())
    print(f"whole-span grid: {made:,} probes interpolated before the long-gap filter")
    print(
        f"ATD 2025 pair ({len(df):,} points, {index.n_tracks:,} tracks): probes {len(old[0]):,} "
        f"(before) / {len(new[0]):,} (after), identical: {same}; "
        f"time {t_old:.2f} s -> {t_new:.2f} s ({t_old / t_new:.0f}x); "
        f"peak {m_old / 1e6:,.0f} MB -> {m_new / 1e6:,.0f} MB ({m_old / m_new:.0f}x)"
    )
    t = time.perf_counter()
    a = associate_sensors(df, params)
    t_a = time.perf_counter() - t
    t = time.perf_counter()
    f = fuse(a, params)
    t_f = time.perf_counter() - t
    print(
        f"  associate {t_a:.2f} s ({len(a.chosen)} pairs of {len(a.a):,} candidates), "
        f"fuse {t_f:.2f} s ({len(f):,} points)"
    )


def time_bases(params: FuseParams, d: Path) -> None:
    from wakeline.app.cli_review import read_inputs
    from wakeline.core import geo
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import track_index

    df = read_inputs([d / "ship_radar_1s.csv", d / "ship_ais_30s.csv"])
    ais = df[df["sensor"] != "RADAR1"].sort_values("time")
    radar_times = set(time_seconds(df.loc[df["sensor"] == "RADAR1", "time"]))
    a = associate_sensors(df, params)
    for mode in ("weight", "densest", "union"):
        p = params.replace(time_base=mode)
        t = time.perf_counter()
        f = fuse(a, p)
        el = time.perf_counter() - t
        ft = time_seconds(f["time"])
        ai = ais.reset_index(drop=True)
        lon, lat, ok = interp_positions(ai, track_index(ai), np.zeros(len(f), "int64"), ft)
        dist = geo.haversine_m(f["lon"].to_numpy(), f["lat"].to_numpy(), lon, lat)[ok]
        kept = len(radar_times & set(ft))
        print(
            f"  time_base {mode:8s} {len(f):6,} fused points, radar fix times in it {kept:6,} of "
            f"{len(radar_times):,}; from the AIS path (where it covers): mean "
            f"{dist.mean():.1f} m, p95 {np.percentile(dist, 95):.1f} m; fuse {el:.2f} s"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--ships", type=int, default=2000)
    ap.add_argument("--dense-ships", type=int, default=300)
    ap.add_argument("--atd", action="store_true", help="the ATD pair's probe grid, before/after")
    ap.add_argument("--time-base", action="store_true", help="the h168 pair, each time_base")
    ap.add_argument(
        "--pair-dir",
        type=Path,
        default=os.environ.get("WAKELINE_H168_DIR"),
        help="folder with ship_radar_1s.csv and ship_ais_30s.csv (for --time-base)",
    )
    args = ap.parse_args()
    params = FuseParams()
    if args.atd or args.time_base:
        if args.atd:
            atd(params)
        if args.time_base:
            d = args.pair_dir
            if d is None or not (Path(d) / "ship_radar_1s.csv").exists():
                raise SystemExit(
                    "--time-base needs the h168 pair: --pair-dir DIR with ship_radar_1s.csv "
                    "and ship_ais_30s.csv (session 27's scratch copy is gone)"
                )
            print("h168 1 s radar + 30 s AIS of one ship:")
            time_bases(params, Path(d))
        return

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

"""Interrupted-track association at scale: time and memory for 1 k, 10 k and 100 k
segments, the growth per 10× segments of the candidate pairs and of the whole association
(wall and CPU time; the k-d tree way of earlier versions measured in the same run), and
the speed-up over the dense way (an n×n cost matrix and linear_sum_assignment) on a
subset both can run.

Run: ``python bench/bench_associate.py [--segments 1000 10000 100000] [--dense 2500]
[--repeat 2]``; ``--stages``: CPU time per stage of one association at 10 k and 100 k
segments (or ``--segments``) and its growth; ``--density``: ships per km² around a ship
and candidate pairs per segment of each scene.
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


#: The functions of core/associate.py (and segments.py, through it) whose own CPU time
#: ``--stages`` reports.
STAGES = (
    "segment_stats", "chain_refit", "components", "candidate_pairs", "_pricing",
    "pair_features", "prediction_miss", "at_rest_pairs", "optimal_assign", "insert_skipped",
    "margin_test", "soft_gap_test", "_released", "_narrowed", "_two_cheapest", "_skips",
    "_targets", "_references", "_spread", "first_pass_pairs", "long_gap_pass",
    "assign_interrupted", "_fitted", "_soft_ends", "_both_moving",
)  # fmt: skip


def stages(sizes: list[int], repeat: int) -> None:
    """Exclusive CPU time (``time.process_time``) of each stage of one association per
    size (best of ``repeat`` by total), and its growth per 10× segments: each function of
    :data:`STAGES` wrapped, its callees' time taken off its own."""
    acc: dict[str, float] = {}
    stack: list[float] = []

    def wrapped(name, fn):
        def run(*args, **kwargs):
            t = time.process_time()
            stack.append(0.0)
            try:
                return fn(*args, **kwargs)
            finally:
                spent = time.process_time() - t
                acc[name] = acc.get(name, 0.0) + spent - stack.pop()
                if stack:
                    stack[-1] += spent

        return run

    saved = {name: getattr(assoc_mod, name) for name in STAGES if hasattr(assoc_mod, name)}
    for name, fn in saved.items():
        setattr(assoc_mod, name, wrapped(name, fn))
    params = LinkParams()
    rows = {}
    try:
        for n in sizes:
            df, _ = sorted_with_index(scene(n))
            best = None
            for _ in range(repeat):
                acc.clear()
                t = time.process_time()
                assoc_mod.associate_interrupted(df, params)
                total = time.process_time() - t
                acc["(the rest)"] = total - sum(acc.values())
                acc["total"] = total
                if best is None or total < best["total"]:
                    best = dict(acc)
            rows[n] = best
    finally:
        for name, fn in saved.items():
            setattr(assoc_mod, name, fn)
    with open("/proc/loadavg") as f:
        print(f"CPU s per stage, own time, best of {repeat} (load {f.read().split()[0]})")
    last = rows[sizes[-1]]
    print(f"{'stage':22s}" + "".join(f"{n:>10,}" for n in sizes) + "  growth per 10x")
    for k in sorted(last, key=lambda k: -last[k]):
        cells = "".join(f"{rows[n].get(k, 0.0):10.3f}" for n in sizes)
        a, b = rows[sizes[0]].get(k, 0.0), last[k]
        f = np.log10(sizes[-1] / sizes[0])
        grow = f"{(b / a) ** (1 / f):6.1f}x" if a > 0 and f > 0 else ""
        print(f"{k:22s}{cells}  {grow}")


def density(sizes: list[int]) -> None:
    """How dense each scene is where its ships are: ships per km² around a ship (the
    other ships in its 10 km cell in the same 10 min), candidate pairs per segment."""
    params = LinkParams()
    for n in sizes:
        df, _ = sorted_with_index(scene(n))
        seg = segment_stats(df, params.end_points, end_points_max=params.end_points_max)
        pairs = candidate_pairs(seg, params)
        lon0, lat0 = float(df["lon"].mean()), float(df["lat"].mean())
        x, y = geo.to_local(df["lon"].to_numpy(), df["lat"].to_numpy(), lon0, lat0)
        t = (df["time"] - df["time"].min()).dt.total_seconds().to_numpy()
        cell = np.floor(x / 10_000.0) * 1e6 + np.floor(y / 10_000.0) + (t // 600) * 1e12
        ship = pd.factorize(df["truth"])[0]
        occupied = pd.DataFrame({"cell": cell, "ship": ship}).drop_duplicates()
        count = occupied.groupby("cell").size().to_numpy()
        around = (count * count).sum() / count.sum() / 100.0  # per km² of a 10 km cell
        ships = max(int(n / 3.0), 2)
        print(
            f"scene({n}): {len(seg):,} segments, {ships:,} ships started at "
            f"{ships / (20.0 * np.sqrt(ships / 80.0)) ** 2:.3f} per km² for "
            f"{(t.max() - t.min()) / 3600:.1f} h; ships per km² around a ship {around:.3f}; "
            f"{len(pairs) / len(seg):.2f} candidate pairs per segment"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--segments", type=int, nargs="+", default=None)
    ap.add_argument("--dense", type=int, default=2500, help="segments for the dense comparison")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--growth-only", action="store_true", help="only the growth per 10x (issue 17)")
    ap.add_argument("--stages", action="store_true", help="CPU time per stage and its growth")
    ap.add_argument("--density", action="store_true", help="how dense each scene is")
    args = ap.parse_args()
    params = LinkParams()
    if args.stages or args.density:
        sizes = args.segments or [10_000, 100_000]
        if args.density:
            density(sizes)
        if args.stages:
            stages(sizes, args.repeat)
        return
    args.segments = args.segments or [1000, 10_000, 100_000]
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

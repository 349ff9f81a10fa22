"""Maneuver-detector throughput: points/s over many tracks, and the speed-up over a
straightforward per-window loop (``numpy.linalg.eigh`` per window) on a subset.

Run: ``python bench/bench_maneuver.py [--points 10000000] [--tracks 10000] [--loop-points 20000]``.
Goals (issue 4, issue 17): detect() >= 10 M points/s at 10 M points and >= 300x the loop.
"""

import argparse
import time

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.maneuver import ManeuverParams, detect, maneuver_factor
from wakeline.core.tracks import local_xy, track_index


def make_points(n_points: int, n_tracks: int, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    per = n_points // n_tracks
    track = np.repeat(np.arange(n_tracks), per)
    k = np.tile(np.arange(per), n_tracks)
    # random-walk headings: a turn now and then, noisy positions, 10 s sampling, ~12 kn
    turn = np.where(rng.random(len(k)) < 0.01, rng.normal(0, 40, len(k)), 0.0)
    turn[k == 0] = rng.uniform(0, 360, n_tracks)
    heading = np.cumsum(turn)
    heading -= np.repeat(heading[k == 0], per) - np.repeat(turn[k == 0], per)
    step = 60.0
    x = np.cumsum(step * np.sin(np.radians(heading)))
    y = np.cumsum(step * np.cos(np.radians(heading)))
    x -= np.repeat(x[k == 0], per)
    y -= np.repeat(y[k == 0], per)
    x += rng.normal(0, 20, len(x))
    y += rng.normal(0, 20, len(y))
    lon, lat = geo.from_local(x, y, 122.0 + (track % 100) * 0.05, 30.0 + (track // 100) * 0.05)
    t = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(k * 10, unit="s")
    return pd.DataFrame(
        {"sensor": "R1", "batch": pd.Series(track).astype("str"), "time": t, "lon": lon, "lat": lat}
    )


def best_of(fn, repeat: int):
    """Best wall and best CPU time (s) of ``repeat`` calls of ``fn``, and its last result."""
    wall = cpu = np.inf
    result = None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        result = fn()
        wall = min(wall, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return wall, cpu, result


def loop_factor(x: np.ndarray, y: np.ndarray, p: int) -> np.ndarray:
    n = len(x)
    out = np.full(n, np.nan)

    def heading(a, b):
        pts = np.column_stack([x[a:b], y[a:b]])
        w, v = np.linalg.eigh(np.cov(pts.T, bias=True))
        axis = v[:, np.argmax(w)]
        if axis @ (pts[-1] - pts[0]) < 0:
            axis = -axis
        return np.degrees(np.arctan2(axis[0], axis[1]))

    for o in range(p - 1, n - p + 1):
        out[o] = abs((heading(o - p + 1, o + 1) - heading(o, o + p) + 180) % 360 - 180)
    return out


def compare(rev: str, n_points: int, n_tracks: int, repeat: int) -> None:
    """detect() of revision ``rev`` and of the working tree, interleaved, best of ``repeat``."""
    import importlib.util
    import subprocess
    import tempfile
    from pathlib import Path

    from wakeline.core import maneuver as now

    root = Path(__file__).resolve().parent.parent

    def module_of(name: str, file: str):
        src = subprocess.run(
            ["git", "show", f"{rev}:{file}"], cwd=root, check=True, capture_output=True
        ).stdout
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / f"{name}.py"
            path.write_bytes(src)
            spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
        return module

    before = module_of("maneuver_before", "core/maneuver.py")
    # the projection and the repeated-rows check it calls, as they were at ``rev`` too
    tracks_before = module_of("tracks_before", "core/tracks.py")
    before.local_xy = tracks_before.local_xy
    before.repeated_rows = tracks_before.repeated_rows
    from wakeline.core.tracks import sorted_with_index

    df = sorted_with_index(make_points(n_points, n_tracks))[0]  # in track order, as a step
    with open("/proc/loadavg") as f:  # before would hand it on (no sort in the times)
        print(f"{len(df):,} points in {n_tracks:,} tracks; load average {f.read().strip()}")
    for label, params in (("defaults", ManeuverParams()), ("paper", ManeuverParams.paper())):
        tb = tn = cb = cn = np.inf
        for _ in range(repeat):
            t, c = time.perf_counter(), time.process_time()
            a = before.detect(df, params)
            tb, cb = min(tb, time.perf_counter() - t), min(cb, time.process_time() - c)
            t, c = time.perf_counter(), time.process_time()
            b = now.detect(df, params)
            tn, cn = min(tn, time.perf_counter() - t), min(cn, time.process_time() - c)
        same = (
            np.array_equal(a.is_maneuver, b.is_maneuver)
            and np.array_equal(a.factor.view("int64"), b.factor.view("int64"))
            and np.array_equal(a.at_rest, b.at_rest)
        )
        print(
            f"{label}: {rev} {tb:.2f} s wall, {cb:.2f} s CPU ({len(df) / cb / 1e6:.2f} M/s); "
            f"now {tn:.2f} s wall, {cn:.2f} s CPU ({len(df) / cn / 1e6:.2f} M/s): "
            f"{cb / cn:.2f}x CPU, {tb / tn:.2f}x wall; identical (maneuvers, factor bits, "
            f"at rest): {same}"
        )
    with open("/proc/loadavg") as f:
        print(f"load average after: {f.read().strip()}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=10_000_000)
    ap.add_argument("--tracks", type=int, default=10_000)
    ap.add_argument("--loop-points", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--against",
        metavar="REV",
        help="also time core/maneuver.py (with tracks.local_xy and repeated_rows) of this git "
        "revision in the same process, and check "
        "that both give the same maneuver points and factor bits (e.g. 85bebba)",
    )
    args = ap.parse_args()
    if args.against:
        compare(args.against, args.points, args.tracks, args.repeat)
        return
    params = ManeuverParams()
    df = make_points(args.points, args.tracks)
    print(
        f"{len(df):,} points in {args.tracks:,} tracks, p = {params.window_p}, n = {params.radius_n}"
    )

    best_full, cpu_full, result = best_of(lambda: detect(df, params), args.repeat)
    print(
        f"detect() end to end (sort, projection, factor, max filter): {best_full:.2f} s, "
        f"{len(df) / best_full / 1e6:.1f} M points/s (CPU {cpu_full:.2f} s, "
        f"{len(df) / cpu_full / 1e6:.1f} M points/s), {int(result.is_maneuver.sum()):,} maneuvers"
    )
    in_order = result.points  # sorted and remembered: what a pipeline step hands on
    best_sorted, cpu_sorted, _ = best_of(lambda: detect(in_order, params), args.repeat)
    print(
        f"detect() on the table in track order: {best_sorted:.2f} s, "
        f"{len(df) / best_sorted / 1e6:.1f} M points/s (CPU {cpu_sorted:.2f} s, "
        f"{len(df) / cpu_sorted / 1e6:.1f} M points/s; goal >= 10 M/s)"
    )

    paper = ManeuverParams.paper()
    best_paper, _, _ = best_of(lambda: detect(df, paper), args.repeat)
    print(
        f"detect() with ManeuverParams.paper() (one scale, no speed/rest/noise tests): "
        f"{best_paper:.2f} s, {len(df) / best_paper / 1e6:.1f} M points/s; defaults cost "
        f"{best_full / best_paper:.1f}x the paper's rule"
    )
    with open("/proc/loadavg") as f:
        print(f"load average: {f.read().strip()}")

    pts, index = result.points, result.index
    x, y = local_xy(pts, index)
    best_core, _, _ = best_of(lambda: maneuver_factor(x, y, index, params.window_p), args.repeat)
    print(
        f"maneuver factor alone (projected input): {best_core:.2f} s, {len(df) / best_core / 1e6:.1f} M points/s"
    )

    m = args.loop_points
    sub = pts.iloc[:m]
    sx, sy = local_xy(sub, track_index(sub))
    sub_index = track_index(sub)
    t = time.perf_counter()
    ref = np.concatenate(
        [
            loop_factor(sx[a:b], sy[a:b], params.window_p)
            for a, b in zip(sub_index.starts, sub_index.ends, strict=True)
        ]
    )
    loop_s = time.perf_counter() - t
    t = time.perf_counter()
    vec = maneuver_factor(sx, sy, sub_index, params.window_p)
    vec_s = time.perf_counter() - t
    assert np.allclose(np.nan_to_num(ref), np.nan_to_num(vec), atol=1e-6)
    loop_rate = m / loop_s
    print(
        f"per-window eigh loop on {m:,} points: {loop_s:.2f} s, {loop_rate / 1e3:.1f} k points/s "
        f"(same values as the vectorized factor)"
    )
    print(
        f"speed-up, factor vs loop (points/s): {len(df) / best_core / loop_rate:,.0f}x; "
        f"end-to-end detect vs loop: {len(df) / best_full / loop_rate:,.0f}x (goal >= 300x)"
    )
    print(f"vectorized factor on the same {m:,} points: {vec_s * 1e3:.1f} ms")


if __name__ == "__main__":
    main()

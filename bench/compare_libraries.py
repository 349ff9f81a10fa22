"""Wakeline against MovingPandas and Stone Soup: the same tasks, the same parameters, the
results checked against each other, best of ``--repeat`` runs each, in one run.

The comparison libraries live in their own virtual environment so that the project's
dependencies stay as they are (CI never installs them)::

    python3 -m venv .venv-cmp
    .venv-cmp/bin/pip install -e ".[compare]"      # = -e . movingpandas stonesoup
    WAKELINE_SHARED=/work/shared .venv-cmp/bin/python bench/compare_libraries.py

Options: ``--sizes 10000 100000 1000000`` (synthetic points), ``--cap 120`` (seconds per
single run: a run still going then is killed and printed as ``> cap``; a larger size
after a capped one is not tried), ``--repeat 3``, ``--only dp tdtr stops gaps speed t2t``.

Every run of every contestant is a forked child process that gets its input prepared
(a fresh copy of the same table, rows already in track order) before the clock starts;
the clock covers everything from that table to the answer, including what the other
library needs first (projection to a metric CRS, building its objects). Tasks:

- ``dp``: Douglas–Peucker at a tolerance in metres. Ours: ``douglas_peucker_mask`` (what
  ``wakeline compress --method dp`` runs; GEOS ``simplify`` in each track's local plane).
  MovingPandas: project to an azimuthal equidistant CRS about the data's centre (pyproj),
  build the ``TrajectoryCollection``, ``DouglasPeuckerGeneralizer.generalize`` (GEOS too).
  Agreement: the share of points both keep or both drop, and the kept counts.
- ``tdtr``: the time-ratio Douglas–Peucker (synchronized distance). Ours:
  ``synchronized_split_mask`` (``compress``'s error bound); MovingPandas:
  ``TopDownTimeRatioGeneralizer``. Same agreement measure.
- ``stops``: at rest / stop detection, radius 50 m (diameter 100 m), 180 s. Ours:
  ``at_rest`` + ``rest_spans`` (cleaning's stationary rule); MovingPandas:
  ``TrajectoryStopDetector.get_stop_time_ranges``. Agreement: stop counts, total stopped
  time, and the share of points both call stopped or both call moving.
- ``gaps``: split where the time step exceeds 600 s. Ours: ``cut_at_gaps(factor=0)``;
  MovingPandas: ``ObservationGapSplitter``. Agreement: pieces of two or more points.
- ``speed``: speed of every point from positions. Ours: ``derive_motion`` (haversine);
  MovingPandas: ``add_speed`` (in the metric CRS). Agreement: the largest relative
  difference.
- ``t2t``: track-to-track association of two sensors. Ours: ``associate_sensors``
  (``wakeline fuse``'s association). Stone Soup: ``TrackToTrackCounting`` (it compares
  states at equal timestamps only, so every track is first interpolated with Stone Soup's
  ``interpolate_state_mutable_sequence`` onto a common 60 s grid, ``probe_s``'s value).
  Agreement and quality: P_CA / P_FA of both against the truth (``pair_scores``), on
  the MTAD files (Stone Soup at several thresholds, and with its ``one_to_one``) and on
  the simulator's scene, plain and ``--hard`` (split radar tracks, ships without AIS).

Data: synthetic tracks (1,000 points per track at 10 s, ~12 kn, with stops and gaps), the
Saronic AIS set (``$WAKELINE_SHARED/data/real/greece-ais-annotated/vessels.csv``, GPL,
read in place), the MTAD two-sensor samplings (``mtad-dtwcm/two_sensor``, 44 files) and
the simulator's two-sensor scene, tiled side by side for the larger sizes.
"""

import argparse
import multiprocessing
import os
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import sorted_with_index

SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = SHARED / "data" / "real"
RADIUS_M, WINDOW_S, GAP_S = 50.0, 180.0, 600.0


# --------------------------------------------------------------------------------------
# running with a cap


@dataclass
class Timing:
    best: float | None  # best of the runs that finished (s); None: the first hit the cap
    runs: int
    capped: bool
    summary: object = None
    parts: dict | None = None  # best time of named parts (s)

    failed: str | None = None  # the child's exception or death, when it had no answer

    def text(self, cap: float) -> str:
        if self.best is None and self.failed:
            return f"failed ({self.failed[:60]})"
        if self.best is None:
            return f"> {cap:g} s"
        return f"{self.best:.3f} s" + (" (cap hit later)" if self.capped else "")


def _child(conn, prepare, run, summarize, repeat):
    warnings.simplefilter("ignore")
    try:
        result = None
        for _ in range(repeat):
            arg = prepare()
            t = time.perf_counter()
            result = run(arg)
            conn.send(("t", time.perf_counter() - t, getattr(result, "parts", None)))
        conn.send(("s", summarize(result)))
    except Exception as e:  # noqa: BLE001 - reported in the table
        conn.send(("e", f"{type(e).__name__}: {e}"))
    conn.close()


def timed(prepare, run, summarize, repeat: int, cap: float) -> Timing:
    """Best of ``repeat`` runs in a forked child, each run capped at ``cap`` seconds."""
    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    p = ctx.Process(target=_child, args=(child, prepare, run, summarize, repeat))
    p.start()
    child.close()
    times, parts, summary, capped, failed = [], {}, None, False, None
    while True:
        if not parent.poll(cap if len(times) < repeat else 3 * cap):
            capped = True
            break
        try:
            msg = parent.recv()
        except EOFError:
            failed = summary = f"child died (exit code {p.join(5) or p.exitcode})"
            break
        if msg[0] == "t":
            times.append(msg[1])
            for k, v in (msg[2] or {}).items():
                parts[k] = min(parts.get(k, np.inf), v)
        elif msg[0] == "s":
            summary = msg[1]
            break
        else:
            failed = summary = msg[1]
            break
    if p.is_alive():
        p.kill()
    p.join()
    best = min(times) if times else None
    return Timing(best, len(times), capped, summary, parts or None, failed)


class Parts(tuple):
    """A result with the times of its parts (``parts``)."""

    parts: dict


def with_parts(result, parts: dict):
    out = Parts((result,))
    out.parts = parts
    return out


# --------------------------------------------------------------------------------------
# data


def synthetic(n_points: int, seed: int = 0, per: int = 1000) -> pd.DataFrame:
    """Tracks of ``per`` points every 10 s at ~12 kn with noise 5 m, each with two stops
    (10-30 min, the ship still) and some gaps (20-60 min of missing reports): canonical
    columns, rows in track order (batches zero-padded), a ``row`` number and truth of
    the stops (``true_stop``)."""
    rng = np.random.default_rng(seed)
    n_tracks = max(n_points // per, 1)
    n = n_tracks * per
    k = np.tile(np.arange(per), n_tracks)
    track = np.repeat(np.arange(n_tracks), per)
    moving = np.ones(n, dtype=bool)
    for _ in range(2):
        start = rng.integers(50, per - 250, n_tracks)
        length = rng.integers(60, 181, n_tracks)
        moving &= ~((k >= np.repeat(start, per)) & (k < np.repeat(start + length, per)))
    # every 10 s, and after a random 0.2 % of points 20-60 min without reports (the ship
    # sails on: the gap is in time and in place)
    dt = 10.0 + np.where(rng.random(n) < 0.002, rng.integers(120, 361, n) * 10.0, 0.0)
    dt[k == 0] = 0.0
    turn = np.where(rng.random(n) < 0.01, rng.normal(0, 40, n), 0.0)
    turn[k == 0] = rng.uniform(0, 360, n_tracks)
    heading = np.cumsum(turn)
    heading -= np.repeat(heading[k == 0], per) - np.repeat(turn[k == 0], per)
    step = 6.0 * dt * moving  # ~12 kn
    x = np.cumsum(step * np.sin(np.radians(heading)))
    y = np.cumsum(step * np.cos(np.radians(heading)))
    x -= np.repeat(x[k == 0], per)
    y -= np.repeat(y[k == 0], per)
    x += rng.normal(0, 5, n)
    y += rng.normal(0, 5, n)
    lon, lat = geo.from_local(x, y, 122.0 + (track % 30) * 0.02, 30.0 + (track // 30) * 0.02)
    elapsed = np.cumsum(dt) - np.repeat(np.cumsum(dt)[k == 0], per)
    t = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(elapsed, unit="s")
    df = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": pd.Series(track).map("{:06d}".format),
            "time": t,
            "lon": lon,
            "lat": lat,
            "true_stop": ~moving,
        }
    )
    return _rows(df)


def saronic() -> pd.DataFrame:
    raw = pd.read_csv(
        REAL / "greece-ais-annotated" / "vessels.csv", sep=" ", names=["id", "lon", "lat", "t"]
    )
    df = pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": raw["id"].astype(str),
            "time": pd.to_datetime(raw["t"], unit="s", utc=True),
            "lon": raw["lon"],
            "lat": raw["lat"],
        }
    )
    return _rows(df)


def _rows(df: pd.DataFrame) -> pd.DataFrame:
    df, _ = sorted_with_index(df)
    df = df.reset_index(drop=True)
    df["row"] = np.arange(len(df))
    return df


def fresh(df: pd.DataFrame):
    """A copy made before the clock starts (Wakeline remembers a table's order: a copy
    makes every run sort and index from scratch)."""
    return lambda: df.copy()


# --------------------------------------------------------------------------------------
# MovingPandas side


def aeqd(df: pd.DataFrame) -> str:
    lon0, lat0 = float(df["lon"].median()), float(df["lat"].median())
    return f"+proj=aeqd +lat_0={lat0:.4f} +lon_0={lon0:.4f} +datum=WGS84 +units=m"


def mp_collection(df: pd.DataFrame, crs: str):
    """Project (pyproj, vectorized) and build the TrajectoryCollection; times in parts."""
    import movingpandas as mpd
    from pyproj import Transformer

    t0 = time.perf_counter()
    x, y = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(
        df["lon"].to_numpy(), df["lat"].to_numpy()
    )
    d = pd.DataFrame(
        {
            "tid": df["batch"].to_numpy(),
            "t": df["time"].dt.tz_convert(None).to_numpy(),
            "x": x,
            "y": y,
            "row": df["row"].to_numpy(),
        }
    )
    tc = mpd.TrajectoryCollection(d, traj_id_col="tid", t="t", x="x", y="y", crs=crs)
    return tc, time.perf_counter() - t0


def mp_rows(tc) -> np.ndarray:
    return np.unique(np.concatenate([tr.df["row"].to_numpy() for tr in tc.trajectories]))


# --------------------------------------------------------------------------------------
# tasks


def agree_mask(a: np.ndarray, b: np.ndarray) -> str:
    return (
        f"kept {a.sum():,} vs {b.sum():,}; same decision on {np.mean(a == b):.4%} of points, "
        f"kept by both {np.sum(a & b) / max(np.sum(a | b), 1):.4f} of kept by either"
    )


def task_dp(df: pd.DataFrame, tol: float, repeat: int, cap: float):
    from wakeline.core.compress import douglas_peucker_mask
    from wakeline.core.tracks import local_xy

    crs = aeqd(df)
    n = len(df)

    def ours(d):
        pts, index = sorted_with_index(d)
        x, y = local_xy(pts, index)
        return douglas_peucker_mask(x, y, index, tol)

    def theirs(d):
        import movingpandas as mpd

        tc, build = mp_collection(d, crs)
        t = time.perf_counter()
        out = mpd.DouglasPeuckerGeneralizer(tc).generalize(tolerance=tol)
        return with_parts(out, {"build": build, "op": time.perf_counter() - t})

    def mask_of(res):
        m = np.zeros(n, dtype=bool)
        m[mp_rows(res[0])] = True
        return m

    a = timed(fresh(df), ours, lambda m: m, repeat, cap)
    b = timed(fresh(df), theirs, mask_of, repeat, cap)
    check = "-"
    if b.best is not None:
        # where the two differ: the plane (ours: each track's own equirectangular plane;
        # theirs: one azimuthal equidistant CRS), and MovingPandas keeping every point whose
        # position equals a kept vertex's (a moored ship's repeated fixes)
        from pyproj import Transformer

        pts, index = sorted_with_index(df.copy())
        x, y = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(
            pts["lon"].to_numpy(), pts["lat"].to_numpy()
        )
        same_plane = douglas_peucker_mask(x, y, index, tol)
        key = pd.Series(list(zip(index.track_of_row, x, y, strict=True)))
        kept_keys = set(key[same_plane])
        with_repeats = key.isin(kept_keys).to_numpy()
        check = (
            f"{agree_mask(a.summary, b.summary)}; ours in their CRS: "
            f"{agree_mask(same_plane, b.summary)}; ours in their CRS plus every point "
            f"repeating a kept position: {agree_mask(with_repeats, b.summary)}"
        )
    return a, b, check


def task_tdtr(df: pd.DataFrame, tol: float, repeat: int, cap: float):
    from wakeline.core.compress import synchronized_split_mask
    from wakeline.core.tracks import local_xy, track_seconds

    crs = aeqd(df)
    n = len(df)

    def ours(d):
        pts, index = sorted_with_index(d)
        x, y = local_xy(pts, index)
        t = track_seconds(pts)
        return synchronized_split_mask(x, y, t, index, np.zeros(len(x), dtype=bool), tol)

    def theirs(d):
        import movingpandas as mpd

        tc, build = mp_collection(d, crs)
        t = time.perf_counter()
        out = mpd.TopDownTimeRatioGeneralizer(tc).generalize(tolerance=tol)
        return with_parts(out, {"build": build, "op": time.perf_counter() - t})

    def mask_of(res):
        m = np.zeros(n, dtype=bool)
        m[mp_rows(res[0])] = True
        return m

    a = timed(fresh(df), ours, lambda m: m, repeat, cap)
    b = timed(fresh(df), theirs, mask_of, repeat, cap)
    check = agree_mask(a.summary, b.summary) if b.best is not None else "-"
    return a, b, check


def _stopped_points(df: pd.DataFrame, track: np.ndarray, t0: np.ndarray, t1: np.ndarray):
    """Per row of ``df`` (track order): inside one of the intervals [t0, t1] of its track?"""
    codes = pd.factorize(df["batch"])[0]
    ts = time_seconds(df["time"])
    key = codes * 1e9 + (ts - ts.min())
    mark = np.zeros(len(df) + 1, dtype="int64")
    lo = np.searchsorted(key, track * 1e9 + t0, side="left")
    hi = np.searchsorted(key, track * 1e9 + t1, side="right")
    np.add.at(mark, lo, 1)
    np.add.at(mark, hi, -1)
    return np.cumsum(mark[:-1]) > 0, ts.min()


def task_stops(df: pd.DataFrame, repeat: int, cap: float):
    from wakeline.core.clean import at_rest, rest_spans
    from wakeline.core.tracks import local_xy, track_seconds

    crs = aeqd(df)
    codes_of = {b: i for i, b in enumerate(pd.unique(df["batch"]))}

    def ours(d):
        pts, index = sorted_with_index(d)
        x, y = local_xy(pts, index)
        t = track_seconds(pts)
        rest = at_rest(x, y, t, index, RADIUS_M, WINDOW_S)
        spans = rest_spans(rest, index)
        return index.track_of_row[spans[:, 0]], t[spans[:, 0]], t[spans[:, 1]]

    def theirs(d):
        import datetime

        import movingpandas as mpd

        tc, build = mp_collection(d, crs)
        t = time.perf_counter()
        ranges = mpd.TrajectoryStopDetector(tc).get_stop_time_ranges(
            max_diameter=2 * RADIUS_M, min_duration=datetime.timedelta(seconds=WINDOW_S)
        )
        return with_parts(ranges, {"build": build, "op": time.perf_counter() - t})

    def summ_ours(res):
        tr, a, b = res
        return tr, a, b

    def summ_theirs(res):
        ranges = res[0]
        tr = np.array([codes_of[r.traj_id] for r in ranges], dtype="int64")
        t0 = np.array([pd.Timestamp(r.t_0).tz_localize("UTC").value / 1e9 for r in ranges])
        t1 = np.array([pd.Timestamp(r.t_n).tz_localize("UTC").value / 1e9 for r in ranges])
        return tr, t0, t1

    a = timed(fresh(df), ours, summ_ours, repeat, cap)
    b = timed(fresh(df), theirs, summ_theirs, repeat, cap)
    check = "-"
    if a.best is not None and b.best is not None and not isinstance(b.summary, str):
        ts_min = time_seconds(df["time"]).min()
        (tra, a0, a1), (trb, b0, b1) = a.summary, b.summary
        pa, _ = _stopped_points(df, tra, a0 - ts_min, a1 - ts_min)
        pb, _ = _stopped_points(df, trb, b0 - ts_min, b1 - ts_min)
        check = (
            f"stops {len(tra):,} vs {len(trb):,}; stopped {np.sum(a1 - a0) / 3600:.1f} h vs "
            f"{np.sum(b1 - b0) / 3600:.1f} h; same call on {np.mean(pa == pb):.4%} of points"
        )
        if "true_stop" in df.columns:
            truth = df["true_stop"].to_numpy()
            check += (
                f"; agree with the true stops on {np.mean(pa == truth):.4%} / "
                f"{np.mean(pb == truth):.4%} of points"
            )
    return a, b, check


def task_gaps(df: pd.DataFrame, repeat: int, cap: float):
    from wakeline.core.evaluate_association import cut_at_gaps

    crs = aeqd(df)

    def ours(d):
        return cut_at_gaps(d, GAP_S, factor=0.0)

    def theirs(d):
        import datetime

        import movingpandas as mpd

        tc, build = mp_collection(d, crs)
        t = time.perf_counter()
        out = mpd.ObservationGapSplitter(tc).split(gap=datetime.timedelta(seconds=GAP_S))
        return with_parts(out, {"build": build, "op": time.perf_counter() - t})

    def summ_ours(cut):
        g = cut.groupby("batch")
        moved = g["lon"].nunique().gt(1) | g["lat"].nunique().gt(1)
        return int(cut["batch"].nunique()), int((g.size().ge(2) & moved).sum())

    def summ_theirs(res):
        return len(res[0].trajectories)

    a = timed(fresh(df), ours, summ_ours, repeat, cap)
    b = timed(fresh(df), theirs, summ_theirs, repeat, cap)
    check = "-"
    if a.best is not None and b.best is not None:
        check = (
            f"pieces {a.summary[0]:,} (of which {a.summary[1]:,} with >= 2 points that move) "
            f"vs {b.summary:,} (MovingPandas drops 1-point and zero-length pieces)"
        )
    return a, b, check


def task_speed(df: pd.DataFrame, repeat: int, cap: float):
    from wakeline.core.tracks import derive_motion

    crs = aeqd(df)
    n = len(df)

    def ours(d):
        pts, index = sorted_with_index(d)
        return derive_motion(pts, index)[0] * geo.KN_MS  # m/s

    def theirs(d):
        tc, build = mp_collection(d, crs)
        t = time.perf_counter()
        tc.add_speed(overwrite=True)
        return with_parts(tc, {"build": build, "op": time.perf_counter() - t})

    def summ_theirs(res):
        v = np.full(n, np.nan)
        for tr in res[0].trajectories:
            v[tr.df["row"].to_numpy()] = tr.df["speed"].to_numpy()
        return v

    a = timed(fresh(df), ours, lambda v: v, repeat, cap)
    b = timed(fresh(df), theirs, summ_theirs, repeat, cap)
    check = "-"
    if a.best is not None and b.best is not None:
        va, vb = a.summary, b.summary
        fast = np.isfinite(va) & np.isfinite(vb) & (va > 1.0)
        rel = np.abs(va[fast] - vb[fast]) / va[fast]
        check = (
            f"speed over 1 m/s: relative difference median {np.median(rel):.2e}, "
            f"max {rel.max():.2e} (haversine vs the projection's metres)"
        )
    return a, b, check


# --------------------------------------------------------------------------------------
# two sensors


def stonesoup_pairs(
    df: pd.DataFrame, key_of: dict, threshold_m: float, grid_s: float, one_to_one: bool = False
):
    """Stone Soup's counting technique on ``df``; returns the chosen (a, b) track numbers
    (``key_of``: (sensor, batch) -> our track number) and the times of the parts."""
    import datetime

    from pyproj import Transformer
    from stonesoup.dataassociator.tracktotrack import TrackToTrackCounting
    from stonesoup.functions.interpolate import interpolate_state_mutable_sequence
    from stonesoup.types.state import State
    from stonesoup.types.track import Track

    t0 = time.perf_counter()
    crs = aeqd(df)
    x, y = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(
        df["lon"].to_numpy(), df["lat"].to_numpy()
    )
    secs = time_seconds(df["time"])
    origin = datetime.datetime(2000, 1, 1)
    base = np.floor(secs.min())
    sensors = sorted(df["sensor"].astype(str).unique())
    sets: dict[str, set] = {s: set() for s in sensors}
    number = {}
    grouped = df.assign(_x=x, _y=y, _s=secs).groupby(["sensor", "batch"], sort=False)
    for (sensor, batch), g in grouped:
        ts = g["_s"].to_numpy() - base
        states = [
            State([[xx], [yy]], timestamp=origin + datetime.timedelta(seconds=float(tt)))
            for xx, yy, tt in zip(g["_x"].to_numpy(), g["_y"].to_numpy(), ts, strict=True)
        ]
        track = Track(states)
        grid = np.arange(np.ceil(ts.min() / grid_s), np.floor(ts.max() / grid_s) + 1) * grid_s
        if len(grid) == 0:
            continue
        times = [origin + datetime.timedelta(seconds=float(s)) for s in grid]
        track = interpolate_state_mutable_sequence(track, times)
        if not isinstance(track, Track):
            track = Track(list(track.states))
        number[id(track)] = key_of[(str(sensor), str(batch))]
        sets[str(sensor)].add(track)
    build = time.perf_counter() - t0
    t = time.perf_counter()
    assoc = TrackToTrackCounting(
        association_threshold=threshold_m,
        consec_pairs_confirm=3,
        consec_misses_end=2,
        pos_map=[0, 1],
        one_to_one=one_to_one,
    ).associate_tracks(sets[sensors[0]], sets[sensors[1]])
    op = time.perf_counter() - t
    pairs = set()
    for a in assoc.associations:
        k1, k2 = (number[id(o)] for o in a.objects)
        pairs.add((min(k1, k2), max(k1, k2)))
    return pairs, {"build": build, "op": op}


def _pairs_oriented(pairs: set, sensor: np.ndarray) -> set:
    return {(a, b) if sensor[a] < sensor[b] else (b, a) for a, b in pairs}


def t2t_scene(
    df: pd.DataFrame,
    params,
    threshold_m: float,
    repeat: int,
    cap: float,
    one_to_one: bool = False,
    ours: bool = True,
):
    from wakeline.core.evaluate_association import (
        pair_scores,
        sensor_pair_scores,
        true_sensor_pairs,
    )
    from wakeline.core.fuse import associate_sensors

    ref = associate_sensors(df, params)  # for the truth and the track numbers
    keys = ref.index.keys
    key_of = {
        (str(s), str(b)): i
        for i, (s, b) in enumerate(zip(keys["sensor"], keys["batch"], strict=True))
    }
    sensor = keys["sensor"].astype(str).to_numpy()
    truth = true_sensor_pairs(ref)

    a = None
    if ours:
        a = timed(
            fresh(df), lambda d: associate_sensors(d, params), sensor_pair_scores, repeat, cap
        )

    def theirs(d):
        pairs, parts = stonesoup_pairs(d, key_of, threshold_m, 60.0, one_to_one)
        return with_parts(pairs, parts)

    b = timed(
        fresh(df),
        theirs,
        lambda r: pair_scores(_pairs_oriented(r[0], sensor), truth),
        repeat,
        cap,
    )
    return a, b


def mtad_scenes() -> list[pd.DataFrame]:
    from wakeline.core.io import read_points

    out = []
    folder = REAL / "mtad-dtwcm" / "two_sensor"
    for path in sorted(folder.glob("scene-*_AIS.csv")):
        parts = []
        for k, sensor in enumerate(("AIS", "radar")):
            d = read_points(str(path).replace("_AIS", f"_{sensor}"), sensor=sensor).points
            codes = pd.factorize(d["batch"])[0]  # the batch numbers leak the truth: renumber
            perm = np.random.default_rng(k).permutation(codes.max() + 1) + 500 * k
            d["batch"] = perm[codes].astype(str)
            parts.append(d)
        out.append(pd.concat(parts, ignore_index=True))
    return out


def sim_scene(n_points: int, hard: bool = False) -> pd.DataFrame:
    """The simulator's two-sensor scene (radar R1 and AIS) of about 10 k points, and for
    more points copies of it side by side (one density; ships and batches renamed per
    copy, so a copy's ship is not the same ship as the original's)."""
    from bench_commands import tiled

    from wakeline.core.simulate import multisensor_scene

    base = multisensor_scene(0, n_ships=24 if hard else 16, hard=hard)
    copies = max(int(round(n_points / len(base))), 1)
    if copies == 1:
        return base
    out = tiled(base, copies)
    out["truth"] = out["truth"].astype(str) + "~" + out["batch"].str.rsplit("~", n=1).str[-1]
    return out


# --------------------------------------------------------------------------------------


def ratio(a: Timing, b: Timing, cap: float) -> str:
    if a.best is None:
        return "-"
    if b.best is None and b.failed:
        return "-"
    if b.best is None:
        return f"> {cap / a.best:,.0f}x"
    return f"{b.best / a.best:,.1f}x"


def line(task: str, data: str, a: Timing, b: Timing, cap: float, check: str) -> dict:
    parts = ""
    if b.parts:
        parts = " (" + ", ".join(f"{k} {v:.3f} s" for k, v in b.parts.items()) + ")"
    print(
        f"{task:<6} {data:<24} ours {a.text(cap):>12}   theirs {b.text(cap):>12}{parts}   "
        f"theirs/ours {ratio(a, b, cap)}",
        flush=True,
    )
    if check:
        print(f"{'':<7}agreement: {check}", flush=True)
    return {"task": task, "data": data, "ours": a.best, "theirs": b.best, "check": check}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    ap.add_argument("--cap", type=float, default=120.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--only",
        nargs="+",
        default=["dp", "tdtr", "stops", "gaps", "speed", "t2t"],
        choices=["dp", "tdtr", "stops", "gaps", "speed", "t2t"],
    )
    ap.add_argument("--tolerance", type=float, default=50.0, help="DP/TDTR tolerance (m)")
    args = ap.parse_args()
    import movingpandas
    import stonesoup

    print(
        f"movingpandas {movingpandas.__version__}, stonesoup {stonesoup.__version__}, "
        f"numpy {np.__version__}, pandas {pd.__version__}; load average "
        f"{' '.join(f'{v:.2f}' for v in os.getloadavg())}; best of {args.repeat}, "
        f"cap {args.cap:g} s per run",
        flush=True,
    )
    cap, rep = args.cap, args.repeat
    synth = {n: synthetic(n) for n in args.sizes}
    real = {"Saronic AIS 18,834"} if (REAL / "greece-ais-annotated").exists() else set()
    sets = [(f"synthetic {n:,}", synth[n]) for n in args.sizes]
    if real:
        sets.insert(0, ("Saronic AIS 18,834", saronic()))
    tasks = {
        "dp": lambda d: task_dp(d, args.tolerance, rep, cap),
        "tdtr": lambda d: task_tdtr(d, args.tolerance, rep, cap),
        "stops": lambda d: task_stops(d, rep, cap),
        "gaps": lambda d: task_gaps(d, rep, cap),
        "speed": lambda d: task_speed(d, rep, cap),
    }
    for name in [t for t in args.only if t in tasks]:
        over = False
        for label, d in sets:
            if over and label.startswith("synthetic"):
                print(f"{name:<6} {label:<24} not tried: a smaller size hit the cap")
                continue
            a, b, check = tasks[name](d)
            line(name, label, a, b, cap, check)
            over |= b.best is None or a.best is None
    if "t2t" in args.only:
        from wakeline.core.fuse import FuseParams

        if (REAL / "mtad-dtwcm").exists():
            scenes = mtad_scenes()
            params = FuseParams(max_distance_m=50_000.0)  # tests/test_real_fuse.py's set-up
            ours_t, sa = [], []
            for d in scenes:
                a, _ = t2t_scene(d, params, 5_000.0, rep, cap, ours=True)
                ours_t.append(a.best)
                sa.append(a.summary)
            fa = pd.DataFrame(sa)
            variants = [(thr, False) for thr in (2_000.0, 5_000.0, 10_000.0, 50_000.0)]
            variants += [(5_000.0, True), (10_000.0, True)]
            for thr, one in variants:
                theirs_t, sb, failed, ok = 0.0, [], [], []
                for k, d in enumerate(scenes):
                    _, b = t2t_scene(d, params, thr, rep, cap, one_to_one=one, ours=False)
                    if isinstance(b.summary, dict):
                        theirs_t += b.best
                        sb.append(b.summary)
                        ok.append(k)
                    else:  # an exception in Stone Soup: counted, left out of the means
                        failed.append(str(b.summary))
                fb, tb = pd.DataFrame(sb), Timing(theirs_t, rep, False)
                ta = Timing(float(np.sum(np.array(ours_t)[ok])), rep, False)
                fa_ok = fa.iloc[ok]
                how = f"thr {thr / 1000:g} km" + (", 1:1" if one else "")
                if failed:
                    print(f"       Stone Soup failed on {len(failed)} of 44 files: {failed[0]}")
                line(
                    "t2t",
                    f"MTAD {len(ok)} files, {how}",
                    ta,
                    tb,
                    cap,
                    f"P_CA / P_FA ours (gate 50 km) {fa_ok.p_ca.mean():.3f} / "
                    f"{fa_ok.p_fa.mean():.3f}, Stone Soup ({how}) {fb.p_ca.mean():.3f} / "
                    f"{fb.p_fa.mean():.3f} (means over the {len(ok)} files both ran; "
                    "times summed over them)",
                )
        over = {False: False, True: False}
        for n, hard in [(n, h) for h in (False, True) for n in args.sizes]:
            d = sim_scene(n, hard)
            label = f"sim 2-sensor{' hard' if hard else ''} {len(d):,}"
            if over[hard]:
                print(f"t2t    {label:<24} not tried: a smaller size hit the cap")
                continue
            params = FuseParams()
            a, b = t2t_scene(d, params, params.max_distance_m, rep, cap)
            fmt = lambda s: (  # noqa: E731
                f"{s['p_ca']:.3f} / {s['p_fa']:.3f}" if isinstance(s, dict) else "-"
            )
            line(
                "t2t",
                label,
                a,
                b,
                cap,
                f"P_CA / P_FA ours {fmt(a.summary)}, Stone Soup {fmt(b.summary)} "
                f"(both at {params.max_distance_m:g} m)",
            )
            over[hard] |= b.best is None


if __name__ == "__main__":
    main()

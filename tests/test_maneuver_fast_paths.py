"""Issue 17, session 18: the shortcuts of ``detect()`` give the same output, bit for bit.

``detect()`` against the frozen straightforward detector (``tests/maneuver_reference.py``)
on scenes that take each shortcut: the benchmark's kind of table (tracks of one length,
10 s fixes, dense turns: the in-place screen of the first longer scale, the strided noise
medians, the stride screen of at-rest spans, the first scale written without a row mask),
radar-rate tracks (1.5 s: the gapped and the 5 s windows), AIS with gaps and moored spans,
and one- and two-fix tracks. The helpers themselves against their plain formulations.
"""

import maneuver_reference as reference
import numpy as np
import pandas as pd
import pytest

from wakeline.core import geo
from wakeline.core import maneuver as mod
from wakeline.core.clean import at_rest
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.tracks import (
    TrackIndex,
    local_xy,
    sorted_with_index,
    track_origins,
    track_seconds,
)

T0 = pd.Timestamp("2024-05-01", tz="UTC")


def _table(tracks: list[tuple[np.ndarray, np.ndarray, np.ndarray]], sensor="S") -> pd.DataFrame:
    """Tracks of (x m, y m, t s) about a few origins, as a points table."""
    parts = []
    for k, (x, y, t) in enumerate(tracks):
        lon, lat = geo.from_local(x, y, 122.0 + 0.05 * (k % 7), 30.0 + 0.05 * (k // 7))
        parts.append(
            pd.DataFrame(
                {
                    "sensor": sensor,
                    "batch": f"b{k}",
                    "time": T0 + pd.to_timedelta(t, unit="s"),
                    "lon": lon,
                    "lat": lat,
                }
            )
        )
    return pd.concat(parts, ignore_index=True)


def _walk(rng, n, period_s, step_m, noise_m, turn_p=0.01, turn_sd=40.0, stay=None):
    """A random walk of headings (a turn now and then), noisy positions; ``stay`` =
    (first, count): that many fixes held at one place (with the noise)."""
    heading = np.radians(
        rng.uniform(0, 360)
        + np.cumsum(np.where(rng.random(n) < turn_p, rng.normal(0, turn_sd, n), 0.0))
    )
    step = np.full(n, step_m)
    if stay is not None:
        step[stay[0] : stay[0] + stay[1]] = 0.0
    x = np.cumsum(step * np.sin(heading)) + rng.normal(0, noise_m, n)
    y = np.cumsum(step * np.cos(heading)) + rng.normal(0, noise_m, n)
    return x, y, np.arange(n) * period_s


def bench_like(seed=0, n_tracks=24, per=1000):
    """bench/bench_maneuver.make_points' kind of table, smaller."""
    rng = np.random.default_rng(seed)
    return _table([_walk(rng, per, 10.0, 60.0, 20.0) for _ in range(n_tracks)])


def radar(seed=1, n_tracks=6):
    """1.5 s fixes at 4–8 m/s, turns, a stray plot now and then, uneven lengths."""
    rng = np.random.default_rng(seed)
    tracks = []
    for _ in range(n_tracks):
        n = int(rng.integers(200, 1500))
        x, y, t = _walk(rng, n, 1.5, rng.uniform(6, 12), 1.0, turn_p=0.02, turn_sd=60.0)
        off = rng.random(n) < 0.01
        x[off] += 8.0
        t = t + rng.uniform(-0.05, 0.05, n)  # jittered fix times
        tracks.append((x, y, np.sort(t)))
    return _table(tracks, sensor="R")


def ais(seed=2, n_tracks=8):
    """10 s fixes with gaps, moored spans of about 3, 10 and 40 min, slow and fast ships
    turning often, and one- and two-fix tracks."""
    rng = np.random.default_rng(seed)
    tracks = []
    for k in range(n_tracks):
        n = int(rng.integers(100, 800))
        stay = (int(rng.integers(0, n // 2)), [19, 60, 240][k % 3])
        speed, noise = rng.choice([3.0, 60.0]), rng.choice([2.0, 8.0])
        x, y, t = _walk(rng, n, 10.0, speed, noise, turn_p=0.04, turn_sd=60.0, stay=stay)
        if k % 2:
            t = t + np.where(np.arange(n) > n // 3, 600.0, 0.0)  # a 10 min gap
        tracks.append((x, y, t))
    tracks.append((np.zeros(1), np.zeros(1), np.zeros(1)))
    tracks.append((np.array([0.0, 50.0]), np.array([0.0, 5.0]), np.array([0.0, 10.0])))
    return _table(tracks, sensor="A")


SCENES = {"bench_like": bench_like, "radar": radar, "ais": ais}
PARAMS = [
    ManeuverParams(),
    ManeuverParams.paper(),
    ManeuverParams(threshold_deg=60.0, min_speed_kn=0.0, rest_radius_m=10.0),
    ManeuverParams(window_s=30.0, max_window_s=2000.0, radius_n=9, noise_k=0.0),
    ManeuverParams(slow_side=0.3, min_speed_kn=10.0),  # 672 / 74 / 16 maneuvers, 611 / 60 / 15 at 1
]


def _reference_params(params: ManeuverParams):
    """The reference's parameters: it predates ``max_step_windows`` (headings not taken
    across a long step), so it is compared with that rule off, and ``window_max_s`` (h131,
    off by default), ``radius_s`` and ``edge_s`` (h162; the defaults since session 31, set 0
    here), ``slow_side_step_s`` (session 27: slow_side everywhere, its bound tested in
    test_maneuver.py), and ``rest_north_box`` (it calls cleaning's at_rest with its
    default, the box in the track's axes)."""
    fields = dict(params.__dict__)
    assert fields.pop("max_step_windows") == 0
    assert fields.pop("window_max_s") == 0
    assert fields.pop("radius_s") == 0
    assert fields.pop("edge_s") == 0
    fields.pop("step_noise_max")  # h240: no effect with radius_s and edge_s 0
    assert fields.pop("slow_side_step_s") == 0 and fields.pop("slow_side_span_s") == 0
    assert not fields.pop("rest_north_box")
    assert not fields.pop("noise_k_law")  # h185, off by default
    assert not fields.pop("rest_noise_sigmas")  # h193; default 5 since h195, set 0 above
    fields.pop("rest_noise_cap_m")  # h195: no effect with rest_noise_sigmas 0 (set above)
    assert fields.pop("confirm_z") == 0  # h203, off by default
    fields.pop("confirm_legs")  # h203: no effect with confirm_z 0
    fields.pop("confirm_grow")  # h208: no effect with confirm_z 0
    fields.pop("confirm_grow_deg")  # h208: no effect with confirm_z 0
    return reference.ManeuverParams(**fields)


@pytest.mark.parametrize("scene", sorted(SCENES))
@pytest.mark.parametrize("which", range(len(PARAMS)))
def test_detect_equals_the_straightforward_detector(scene, which):
    df = SCENES[scene]()
    params = PARAMS[which].replace(
        max_step_windows=0.0,
        slow_side_step_s=0.0,
        rest_noise_sigmas=0.0,
        confirm_z=0.0,
        radius_s=0.0,  # h162's, default since session 31 (h241): the reference predates it
        edge_s=0.0,
    )
    ours = detect(df, params)
    ref = reference.detect(df, _reference_params(params))
    assert np.array_equal(ours.is_maneuver, ref.is_maneuver)
    assert np.array_equal(ours.factor.view("int64"), ref.factor.view("int64"))
    assert np.array_equal(ours.at_rest, ref.at_rest)
    assert np.array_equal(ours.window_p, ref.window_p)
    if which == 0:  # the comparison is about maneuvers and at-rest spans found
        assert ref.is_maneuver.sum() > 10
        assert scene != "ais" or ref.at_rest.sum() > 100


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_no_step_beyond_the_reach_no_change(scene):
    # no step of these scenes is longer than 4 at-rest windows (720 s; the AIS scene's 10 min
    # gap is shorter): the default, max_step_windows = 4, cuts nothing and changes no bit
    df = SCENES[scene]()
    on, off = detect(df), detect(df, ManeuverParams(max_step_windows=0.0))
    if scene == "ais":
        pts, index = sorted_with_index(df)
        dt = np.diff(track_seconds(pts))[np.diff(index.track_of_row) == 0]
        assert dt.max() == 610.0  # the gap is spanned
    assert np.array_equal(on.is_maneuver, off.is_maneuver)
    assert np.array_equal(on.factor.view("int64"), off.factor.view("int64"))
    assert np.array_equal(on.at_rest, off.at_rest)
    assert np.array_equal(on.window_p, off.window_p)


def test_the_scenes_take_the_shortcuts(monkeypatch):
    # the bench-like table: the first longer scale screened in place, the noise medians on
    # strided views, at-rest by the stride screen alone; radar: gapped and 5 s windows
    calls = []
    for name in ("_screen_every_row", "_rest_screen", "_one_scale"):
        real = getattr(mod, name)

        def spy(*args, _name=name, _real=real, **kwargs):
            calls.append(_name)
            return _real(*args, **kwargs)

        monkeypatch.setattr(mod, name, spy)
    strided = []
    real_as_strided = np.lib.stride_tricks.as_strided
    monkeypatch.setattr(
        np.lib.stride_tricks,
        "as_strided",
        lambda *a, **k: strided.append(1) or real_as_strided(*a, **k),
    )
    detect(bench_like())
    assert "_screen_every_row" in calls and "_rest_screen" not in calls and strided
    calls.clear()
    detect(radar())
    assert calls.count("_one_scale") >= 2  # the gapped windows and the 5 s windows


def _plain_local_xy(pts, index):
    """``tracks.local_xy`` the plain way: each track's centre on the sphere, then every
    point's great-circle distance and initial bearing from it (azimuthal equidistant)."""
    lon, lat = pts["lon"].to_numpy(), pts["lat"].to_numpy()
    lo, la = np.radians(lon), np.radians(lat)
    row = index.track_of_row
    ex = np.bincount(row, np.cos(la) * np.cos(lo))
    ey = np.bincount(row, np.cos(la) * np.sin(lo))
    ez = np.bincount(row, np.sin(la))
    lon0 = np.degrees(np.arctan2(ey, ex))[row]
    lat0 = np.degrees(np.arctan2(ez, np.hypot(ex, ey)))[row]
    d = geo.haversine_m(lon0, lat0, lon, lat)
    b = np.radians(geo.initial_bearing_deg(lon0, lat0, lon, lat))
    return d * np.sin(b), d * np.cos(b)


def test_local_plane_equals_the_plain_projection():
    df = pd.concat([ais(), radar()], ignore_index=True)
    lon = df["lon"].to_numpy().copy()
    across = df["batch"].to_numpy() == "b1"
    lon[across] = geo.wrap180(
        lon[across] + 58.0 + np.where(np.arange(across.sum()) % 2, 0.001, -0.001)
    )
    lon[5] = np.nan  # a bad fix: its track's plane is NaN
    df["lon"] = lon
    for table in (df, df[df["batch"] != "b0"]):  # with and without the NaN
        pts, index = sorted_with_index(table.reset_index(drop=True))
        x, y = local_xy(pts, index)
        want_x, want_y = _plain_local_xy(pts, index)
        np.testing.assert_allclose(x, want_x, rtol=0, atol=1e-6)
        np.testing.assert_allclose(y, want_y, rtol=0, atol=1e-6)
        # and geo.to_local about the track's origin, bit for bit
        lon0, lat0 = track_origins(pts, index)
        tr = index.track_of_row
        gx, gy = geo.to_local(pts["lon"].to_numpy(), pts["lat"].to_numpy(), lon0[tr], lat0[tr])
        assert np.array_equal(x, gx, equal_nan=True) and np.array_equal(y, gy, equal_nan=True)
    assert np.array_equal(np.radians(lon), lon * geo.DEG_TO_RAD, equal_nan=True)


def _xyt(df):
    pts, index = sorted_with_index(df)
    x, y = local_xy(pts, index)
    return x, y, track_seconds(pts), index


@pytest.mark.parametrize("seed", range(6))
def test_rest_screen_by_strides_equals_the_cleaning_rule(seed):
    rng = np.random.default_rng(seed)
    tracks = []
    for k in range(10):
        n = int(rng.integers(2, 400))
        period = rng.choice([1.0, 2.0, 10.0, 30.0, 180.0])
        # stays of about the window (180 s), some exactly, at a jitter near the radius
        count = int(rng.choice([180.0 / period, 180.0 / period + 1, 2 * 180.0 / period, 3]))
        stay = (int(rng.integers(0, n)), max(count, 1))
        x, y, t = _walk(
            rng, n, period, rng.choice([0.5, 5.0, 40.0]), rng.choice([1.0, 20.0, 30.0]), stay=stay
        )
        if k % 4 == 1:
            t = t + np.where(np.arange(n) > n // 2, 400.0, 0.0)  # a gap: the other screen
        if k % 5 == 2:
            t = t * rng.uniform(0.9, 1.1)
        tracks.append((x, y, t))
    tracks.append((np.zeros(3), np.zeros(3), np.zeros(3)))  # all at one time
    x, y, t, index = _xyt(_table(tracks))
    if seed == 5:
        x = x.copy()
        x[index.starts[3] + 1] = np.nan  # a fix without a position
    strides = mod._rest_strides(t, index, 180.0)
    assert (strides >= 2).any() and (strides == 1).any()
    for radius, window in ((50.0, 180.0), (5.0, 60.0), (30.0, 180.0), (500.0, 600.0)):
        got = mod._rest_mask(x, y, t, index, radius, window)
        assert np.array_equal(got, at_rest(x, y, t, index, radius, window)), (radius, window)


def test_a_stay_of_exactly_the_window_is_seen_by_the_stride_screen(monkeypatch):
    # regular fixes, a stay spanning exactly window / period steps (the fewest a stay can
    # have): the stride screen must flag its track; the other screen is not asked
    monkeypatch.setattr(mod, "_rest_screen", lambda *a, **k: pytest.fail("not a stride track"))
    for period in (1.0, 3.0, 10.0, 20.0):
        steps = int(180.0 / period)
        for first in range(0, 40, 3):
            n = first + steps + 30
            x = np.concatenate(
                [
                    np.arange(first) * 40.0,
                    np.full(steps + 1, first * 40.0),
                    first * 40.0 + 40.0 * np.arange(1, n - first - steps),
                ]
            )
            y = np.zeros(n)
            x, y, t, index = _xyt(_table([(x, y, np.arange(n) * period)]))
            want = at_rest(x, y, t, index, 50.0, 180.0)
            assert want.any()
            assert np.array_equal(mod._rest_mask(x, y, t, index, 50.0, 180.0), want)


def test_noise_and_speed_tests_equal_their_plain_forms():
    rng = np.random.default_rng(4)
    df = pd.concat([ais(), radar()], ignore_index=True)
    x, y, t, index = _xyt(df)
    x, y, t = x.copy(), y.copy(), t.copy()
    n = len(x)
    dup = rng.choice(n - 1, 40, replace=False)
    x[dup + 1], y[dup + 1] = x[dup], y[dup]  # zero-length legs
    t[dup[:10] + 1] = t[dup[:10]]  # zero time steps
    x[rng.choice(n, 5)] = np.nan
    x[rng.choice(n, 5)] *= 1e150  # lengths out of the safe range
    rows = np.sort(rng.choice(n, 5000, replace=False))
    p = rng.integers(2, 12, len(rows))
    sigma = rng.choice(
        [0.0, 1e-120, 0.5, 5.0, np.nan], index.n_tracks, p=[0.1, 0.05, 0.35, 0.45, 0.05]
    )
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        noise = mod._heading_noise_deg(x, y, index, p, sigma, rows)
        speed = mod._window_speed_ms(x, y, t, index, p, rows)
    for k, threshold in ((2.0, 15.0), (0.5, 1.0), (7.0, 60.0)):
        with np.errstate(invalid="ignore", over="ignore"):
            floor = np.maximum(k * noise, threshold)
        delta = rng.uniform(0, 120, len(rows))
        # δ at the floor, a hair either side of it, and at the threshold
        tie = rng.random(len(rows)) < 0.3
        delta[tie] = np.where(np.isfinite(floor[tie]), floor[tie], threshold)
        near = rng.random(len(rows)) < 0.2
        delta[near] = np.nextafter(delta[near], rng.choice([0.0, 1e300], near.sum()))
        with np.errstate(invalid="ignore"):
            want = delta > floor
        got = mod._clears_noise(x, y, index, p, sigma, rows, delta, k, threshold)
        assert np.array_equal(got, want)
    for limit in (0.5, 2.0, float(np.nanmedian(speed))):
        with np.errstate(invalid="ignore"):
            want = speed >= limit
        assert np.array_equal(mod._fast_enough(x, y, t, index, p, rows, limit), want)
        at = np.nanmedian(speed)  # a speed exactly at the limit
        with np.errstate(invalid="ignore"):
            assert np.array_equal(mod._fast_enough(x, y, t, index, p, rows, at), speed >= at)


def test_noise_medians_on_strided_runs_equal_the_gathers():
    # tracks of one length one after another: the strided view of the keys; with a NaN
    # position in one track (its run goes to the groupby) and without
    for nan in (False, True):
        df = bench_like(seed=3, n_tracks=150, per=60)
        x, y, t, index = _xyt(df)
        if nan:
            x = x.copy()
            x[index.starts[7] + 20] = np.nan
        for lag in (1, 3):
            want = reference.position_noise_m(x, y, t, index, lag)
            got = mod.position_noise_m(x, y, t, index, lag)
            assert np.array_equal(got.view("int64"), want.view("int64"))


def test_runs_masks_and_window_sums_equal_their_plain_forms():
    rng = np.random.default_rng(9)
    for _ in range(300):
        n = int(rng.integers(0, 40))
        mask = rng.random(n) < rng.random()
        edge = np.diff(mask.view(np.int8), prepend=np.int8(0), append=np.int8(0))
        lo, hi = mod._runs(mask)
        assert np.array_equal(lo, np.flatnonzero(edge == 1))
        assert np.array_equal(hi, np.flatnonzero(edge == -1))
        if n:
            a = np.sort(rng.integers(0, n, rng.integers(0, 6)))
            b = np.minimum(a + rng.integers(0, 8, len(a)), n)
            assert np.array_equal(mod._span_mask(a, b, n, inside=False), ~mod._span_mask(a, b, n))
    u = rng.normal(0, 1e3, 500)
    keep = u.copy()
    for p in range(2, 40):
        got = mod._window_sums(u, p)
        want = np.array([u[i : i + p].sum() for i in range(len(u) - p + 1)])
        assert np.allclose(got, want, rtol=1e-12, atol=1e-9)
        got += 1.0  # the caller works in place: never on the input
        assert np.array_equal(u, keep)


def test_first_scale_without_a_row_mask_equals_the_plain_factor():
    # every track long enough (δ written as it comes, NaN put in after) and not (the mask)
    for df in (bench_like(n_tracks=5, per=200), ais()):
        x, y, t, index = _xyt(df)
        u, v = mod._anchored_xy(x, y, index)
        every = np.ones(index.n_tracks, dtype=bool)
        for p in (2, 5, 9):
            got = mod._factor_every_row(u, v, index, p, every)
            want = reference.maneuver_factor(x, y, index, p)
            assert np.array_equal(np.isnan(got), np.isnan(want))
            assert np.array_equal(
                np.nan_to_num(got).view("int64"), np.nan_to_num(want).view("int64")
            )


def test_rest_strides_mark_what_cannot_be_known():
    t = np.array([0.0, 10, 20, 30, 0, 100, 200, 0, 0, np.nan, 5, 0])
    sizes = np.array([4, 3, 1, 3, 1])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    index = TrackIndex(
        starts, starts + sizes, np.repeat(np.arange(5), sizes), pd.DataFrame(index=range(5))
    )
    s = mod._rest_strides(t, index, 180.0)
    # 10 s steps: a stay spans ≥ 18 steps, stride 8 (a power of two ≤ 9); 100 s steps: 2
    # steps, stride 1 (the other screen); one fix: 0; a NaN time: 1
    assert s.tolist() == [8, 1, 0, 1, 0]


def test_repeated_rows_equal_the_plain_rule():
    from wakeline.core.tracks import repeated_rows

    for ties in (False, True):
        df = ais(seed=5)
        if ties:  # a fix repeated, a time shared by two positions, P Q P Q
            df = pd.concat([df, df.iloc[[3, 40]], df.iloc[[50]].assign(lon=0.0)], ignore_index=True)
        pts, index = sorted_with_index(df)
        got = repeated_rows(pts, index)
        key = pd.DataFrame(
            {"k": index.track_of_row, "t": track_seconds(pts), "x": pts["lon"], "y": pts["lat"]}
        )
        assert np.array_equal(got, key.duplicated(keep="first").to_numpy())
        assert got.any() == ties

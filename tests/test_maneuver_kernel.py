"""The fast maneuver kernel against the straightforward detector (issue 17).

``tests/maneuver_reference.py`` is a frozen copy of ``core/maneuver.py`` as it was before
the kernel was reworked (main at fc44de4, with the gapped and fine windows of s4-15; the
noise lag ``noise_lag_s`` of session 18 added to both; ``max_step_windows``, the cut at
long steps, and ``window_max_s`` (h131, off by default) are not in the copy and are compared
off): δ of
every row at every window scale, a maximum filter over every row, the rules on the
candidates. When results change on purpose, change both (or retire this copy). ``detect()`` must give the same maneuver points, the same
δ bit for bit (NaN where undefined) and the same at-rest mask, on random scenes of several
tracks with irregular sampling, gaps, at-rest spans, turns and plateaus of equal δ.
"""

import maneuver_reference as reference
import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core import geo
from wakeline.core.maneuver import ManeuverParams, _angle_diff, _wrap360, detect


def _track(rng, n, batch, lattice):
    """One track: legs with random turns, irregular time steps with gaps, an at-rest span
    now and then; on ``lattice`` exact 100 m steps on the axes and no noise (ties)."""
    if lattice:
        step = rng.choice([[100.0, 0.0], [0.0, 100.0], [-100.0, 0.0], [0.0, -100.0]], n)
        legs = np.repeat(step[:: max(n // 6, 1)], max(n // 6, 1), axis=0)[:n]
        legs = np.vstack([legs, step[: n - len(legs)]])
        xy = np.cumsum(legs, axis=0)
        dt = np.full(n, 10.0)
    else:
        heading = np.cumsum(np.where(rng.random(n) < 0.05, rng.normal(0, 60, n), 0.0))
        speed = rng.choice([0.3, 3.0, 8.0], n // 20 + 1).repeat(20)[:n]  # m/s, slow or not
        dt = rng.choice([1.0, 2.0, 10.0, 30.0], p=[0.3, 0.3, 0.3, 0.1], size=n)
        dt *= rng.uniform(0.5, 1.5, n)
        dt[rng.random(n) < 0.02] *= 40  # gaps
        step = speed * dt
        rest = rng.random(n // 50 + 1) < 0.2  # at-rest spans of 50 fixes
        step[rest.repeat(50)[:n]] = 0.0
        xy = np.cumsum(
            np.c_[step * np.sin(np.radians(heading)), step * np.cos(np.radians(heading))], axis=0
        )
        xy += rng.normal(0, rng.choice([0.5, 3.0, 20.0]), xy.shape)
    t = np.cumsum(dt)
    lon, lat = geo.from_local(xy[:, 0], xy[:, 1], 10.0, 55.0)
    return pd.DataFrame(
        {
            "sensor": "S",
            "batch": batch,
            "time": pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(t, unit="s"),
            "lon": lon,
            "lat": lat,
        }
    )


def _scene(seed, n_tracks, lattice):
    rng = np.random.default_rng(seed)
    sizes = rng.integers(1, 700, n_tracks)
    parts = [_track(rng, int(s), f"b{k}", lattice) for k, s in enumerate(sizes)]
    return pd.concat(parts, ignore_index=True)


PARAMS = [
    ManeuverParams(),
    ManeuverParams.paper(),
    ManeuverParams(window_s=5.0, radius_n=2, threshold_deg=5.0),
    ManeuverParams(window_s=30.0, max_window_s=2000.0, radius_n=9, noise_k=0.0),
    ManeuverParams(threshold_deg=60.0, min_speed_kn=0.0, rest_radius_m=10.0),
    ManeuverParams(noise_lag_s=10.0, noise_k=4.0),
    ManeuverParams(noise_min_span=3.0, noise_k_windows=True),  # h170, options
    ManeuverParams(noise_min_span=3.0, noise_k_windows=True, noise_min_windows=40.0),  # h178
]


def _same(df, params):
    # the reference predates max_step_windows (no heading across a long step) and
    # slow_side_step_s (slow_side's bound, tested in test_maneuver.py): those rules off
    params = params.replace(
        max_step_windows=0.0,
        window_max_s=0.0,
        slow_side_step_s=0.0,
        rest_noise_sigmas=0.0,
        confirm_z=0.0,
        radius_s=0.0,  # h162's, default since session 31 (h241): the reference predates it
        edge_s=0.0,
    )
    ours = detect(df, params)
    fields = dict(params.__dict__)
    fields.pop("max_step_windows")
    fields.pop("window_max_s")
    assert fields.pop("radius_s") == 0 and fields.pop("edge_s") == 0  # h162 (set 0 above)
    fields.pop("step_noise_max")  # h240: no effect with radius_s and edge_s 0
    assert fields.pop("slow_side_step_s") == 0 and fields.pop("slow_side_span_s") == 0
    assert not fields.pop("noise_k_law")  # h185, off by default
    assert not fields.pop("rest_noise_sigmas")  # h193; default 5 since h195, set 0 above
    fields.pop("rest_noise_cap_m")  # h195: no effect with rest_noise_sigmas 0 (set above)
    assert fields.pop("confirm_z") == 0  # h203, off by default (set 0 above)
    fields.pop("confirm_legs")  # h203: no effect with confirm_z 0
    fields.pop("confirm_grow")  # h208: no effect with confirm_z 0
    fields.pop("confirm_grow_deg")  # h208: no effect with confirm_z 0
    assert not fields.pop("rest_north_box")  # the reference calls at_rest's default box
    ref = reference.detect(df, reference.ManeuverParams(**fields))
    assert np.array_equal(ours.is_maneuver, ref.is_maneuver)
    assert np.array_equal(ours.factor, ref.factor, equal_nan=True)
    assert np.array_equal(ours.factor.view("int64"), ref.factor.view("int64"))  # bits, -0.0
    assert np.array_equal(ours.at_rest, ref.at_rest)
    assert np.array_equal(ours.window_p, ref.window_p)
    return int(ref.is_maneuver.sum())


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    n_tracks=st.integers(1, 6),
    lattice=st.booleans(),
    which=st.integers(0, len(PARAMS) - 1),
)
def test_kernel_equals_the_straightforward_detector(seed, n_tracks, lattice, which):
    _same(_scene(seed, n_tracks, lattice), PARAMS[which])


@pytest.mark.parametrize("params", PARAMS)
def test_kernel_equals_the_straightforward_detector_on_a_larger_scene(params):
    found = _same(_scene(17, 30, False), params)
    assert found > 0  # the comparison is about maneuvers, not only about nothing found


def test_plateaus_of_equal_factor_are_resolved_as_before():
    # exact axis-parallel legs without noise: runs of exactly equal δ at every scale
    df = _scene(3, 8, True)
    for params in PARAMS:
        _same(df, params)


def test_cheap_wraps_equal_the_remainder_bit_for_bit():
    rng = np.random.default_rng(5)
    edge = [-360.0, -180.0, -0.0, 0.0, 180.0, 360.0, -1e-17, -5e-324, 719.9999999999999]
    h = np.concatenate([rng.uniform(-360, 720, 100_000), edge, [np.nan]])
    want = np.remainder(h, 360.0)
    assert np.array_equal(_wrap360(h.copy()).view("int64"), want.view("int64"))
    a = np.concatenate([rng.uniform(0, 360, 100_000), [0.0, 180.0, 359.99999999999994, np.nan]])
    b = np.concatenate([rng.uniform(0, 360, 100_000), [180.0, 0.0, 0.0, 1.0]])
    b[:1000] = a[:1000]
    assert np.array_equal(_angle_diff(a, b).view("int64"), geo.angle_diff(a, b).view("int64"))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    lattice=st.booleans(),
    density=st.sampled_from([0.002, 0.02, 0.2, 0.9]),
    p=st.integers(2, 12),
    radius_n=st.integers(1, 12),
)
def test_candidates_on_rows_of_interest_equal_those_of_all_rows(
    seed, lattice, density, p, radius_n
):
    # δ computed only around the rows of interest (and whole tracks where a plateau
    # reaches too far) gives the candidates of the full computation among those rows
    from wakeline.core.maneuver import _scale_candidates
    from wakeline.core.tracks import local_xy, sorted_with_index

    pts, index = sorted_with_index(_scene(seed, 4, lattice))
    x, y = local_xy(pts, index)
    rng = np.random.default_rng(seed)
    p_track = rng.integers(p, p + 3, index.n_tracks)
    radius = np.maximum(p_track, radius_n)
    active = rng.random(index.n_tracks) < 0.8
    interest = rng.random(len(x)) < density
    want, want_f, _ = _scale_candidates(x, y, index, p_track, radius, 10.0, active)
    got, got_f, _ = _scale_candidates(x, y, index, p_track, radius, 10.0, active, interest)
    keep = interest[want]
    assert np.array_equal(got, want[keep])
    assert np.array_equal(got_f, want_f[keep])


def test_plateaus_reaching_beyond_the_rows_computed_send_the_track_back():
    # δ with many ties (2 to 5 values per scene, per row): plateaus and clusters of peaks
    # everywhere, and few rows of interest, so that a cluster often reaches beyond the rows
    # computed around them; without the rule that such a track is computed whole, a few
    # scenes in a thousand differ (the plateau rule then sees part of a cluster)
    import wakeline.core.maneuver as mod
    from wakeline.core.tracks import TrackIndex, concat_ranges

    for seed in range(1500):
        rng = np.random.default_rng(seed)
        sizes = rng.integers(1, 80, 6)
        n = int(sizes.sum())
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        index = TrackIndex(
            starts, starts + sizes, np.repeat(np.arange(6), sizes), pd.DataFrame(index=range(6))
        )
        values = rng.integers(0, rng.integers(2, 6), n) * 10.0
        values[rng.random(n) < 0.02] = np.nan

        def factor_on_runs(x, y, index, p, lo, hi, above=None, values=values):
            rows = concat_ranges(lo, hi - lo)
            return rows, values[rows]

        def screen_every_row(x, y, index, p, lo, hi, above, values=values):
            rows = concat_ranges(lo, hi - lo)
            return rows, values[rows]

        def factor_every_row(x, y, index, p, chosen, values=values):
            lo, hi = index.starts + (p - 1), index.ends - (p - 1)
            ok = chosen & (hi > lo)
            rows = concat_ranges(lo[ok], (hi - lo)[ok])
            out = np.full(len(values), np.nan)
            out[rows] = values[rows]
            return out

        p_track = rng.integers(2, 4, 6)
        radius = np.maximum(p_track, rng.integers(1, 6))
        active = np.ones(6, dtype=bool)
        interest = rng.random(n) < rng.choice([0.005, 0.02, 0.05])
        x = np.zeros(n)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(mod, "_factor_on_runs", factor_on_runs)
            mp.setattr(mod, "_factor_every_row", factor_every_row)
            mp.setattr(mod, "_screen_every_row", screen_every_row)
            want, want_f, _ = mod._scale_candidates(x, x, index, p_track, radius, 5.0, active)
            got, got_f, _ = mod._scale_candidates(
                x, x, index, p_track, radius, 5.0, active, interest
            )
        assert np.array_equal(got, want[interest[want]]), seed
        assert np.array_equal(got_f, want_f[interest[want]]), seed


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_position_noise_by_slices_equals_the_gathers(seed):
    from wakeline.core.maneuver import position_noise_m
    from wakeline.core.tracks import local_xy, sorted_with_index, track_seconds

    pts, index = sorted_with_index(_scene(seed, 8, False))
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    lags = np.random.default_rng(seed).integers(1, 6, index.n_tracks)
    for lag in (1, 2, 5, lags):
        want = reference.position_noise_m(x, y, t, index, lag)
        got = position_noise_m(x, y, t, index, lag)
        assert np.array_equal(got.view("int64"), want.view("int64"))
        assert (want > 0).any()


@pytest.mark.parametrize("window_s", [1.0, 7.5, 180.0, 3600.0])
def test_guessed_search_equals_searchsorted(window_s):
    from wakeline.core.maneuver import _search_sorted
    from wakeline.core.tracks import sorted_with_index, track_seconds

    for seed, lattice in ((0, True), (1, False), (2, False)):
        pts, index = sorted_with_index(_scene(seed, 8, lattice))
        t = track_seconds(pts)
        ts = t - np.repeat(t[index.starts], index.sizes)
        ts += np.repeat(np.arange(index.n_tracks) * 1e7, index.sizes)  # tracks apart
        q = ts - window_s + 1e-3
        span = ts[index.ends - 1] - ts[index.starts]
        step = span / np.maximum(index.sizes - 1, 1)
        got = _search_sorted(ts, q, index, step, window_s)
        assert np.array_equal(got, np.searchsorted(ts, q))
        half = len(ts) // 2  # the second half only, as a block
        got = _search_sorted(ts, q[half:], index, step, window_s, half)
        assert np.array_equal(got, np.searchsorted(ts, q[half:]))


def test_projection_by_repeat_equals_the_gathers():
    from wakeline.core.tracks import local_xy, sorted_with_index, track_origins

    df = _scene(4, 8, False)
    lon = df["lon"].to_numpy()
    df["lon"] = np.where(np.arange(len(df)) % 3 == 0, lon + 170.0, lon - 190.0)  # across 180°
    df["lon"] = geo.wrap180(df["lon"].to_numpy())
    pts, index = sorted_with_index(df)
    x, y = local_xy(pts, index)
    lon0, lat0 = track_origins(pts, index)
    row = index.track_of_row
    want_x, want_y = geo.to_local(
        pts["lon"].to_numpy(), pts["lat"].to_numpy(), lon0[row], lat0[row]
    )
    assert np.array_equal(x.view("int64"), want_x.view("int64"))
    assert np.array_equal(y.view("int64"), want_y.view("int64"))
    h = np.array([-1e4, -360.0, 719.0, 720.0, np.inf, -np.inf, np.nan, -0.0, 5.0])
    with np.errstate(invalid="ignore"):  # the remainder of an infinity is NaN
        assert np.array_equal(geo.remainder360(h.copy()), np.remainder(h, 360.0), equal_nan=True)


def test_long_windows_far_from_the_track_anchor():
    # 1 s fixes over 600 km: windows of up to 320 points (the screen's sums of short
    # convolutions) whose coordinates are far larger than their spread
    rng = np.random.default_rng(11)
    n = 20_000
    heading = 40.0 + np.cumsum(np.where(rng.random(n) < 0.002, rng.normal(0, 30, n), 0.0))
    heading += 5.0 * np.sin(np.arange(n) / 400.0)  # gradual turns too
    x = np.cumsum(30.0 * np.sin(np.radians(heading))) + rng.normal(0, 1.0, n)
    y = np.cumsum(30.0 * np.cos(np.radians(heading))) + rng.normal(0, 1.0, n)
    lon, lat = geo.from_local(x, y, 3.0, 50.0)
    t = pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(np.arange(n), unit="s")
    df = pd.DataFrame({"sensor": "R", "batch": "1", "time": t, "lon": lon, "lat": lat})
    for params in (ManeuverParams(), ManeuverParams(threshold_deg=3.0, noise_k=0.0)):
        assert _same(df, params) > 0


def test_median_interval_equals_the_groupby():
    from wakeline.core.maneuver import median_interval_s
    from wakeline.core.tracks import sorted_with_index, track_seconds

    for seed, lattice in ((0, True), (1, False), (5, False)):
        pts, index = sorted_with_index(_scene(seed, 10, lattice))
        t = track_seconds(pts)
        want = reference.median_interval_s(t, index)
        got = median_interval_s(t, index)
        assert np.array_equal(got, want, equal_nan=True)
        assert np.array_equal(np.nan_to_num(got).view("int64"), np.nan_to_num(want).view("int64"))


def test_span_mask_equals_marking_each_run():
    from wakeline.core.maneuver import _span_mask

    rng = np.random.default_rng(2)
    for _ in range(200):
        n = int(rng.integers(1, 60))
        lo = np.sort(rng.integers(0, n, rng.integers(0, 8)))
        hi = np.minimum(lo + rng.integers(0, 10, len(lo)), n)
        want = np.zeros(n, dtype=bool)
        for a, b in zip(lo, hi, strict=True):
            want[a:b] = True
        assert np.array_equal(_span_mask(lo, hi, n), want)


def test_group_median_equals_the_groupby_bit_for_bit():
    from wakeline.core.maneuver import _group_median

    rng = np.random.default_rng(8)
    for trial in range(20):
        sizes = rng.choice([1, 2, 5, 6, 40, 41], 60)  # shared sizes, odd and even
        sizes[: trial % 4] = rng.integers(1, 30, trial % 4)  # and a few of their own
        group = np.repeat(np.arange(60), sizes)
        values = rng.lognormal(0, 2, len(group))
        if trial % 5 == 0:
            values[rng.random(len(values)) < 0.1] = np.nan
        group = group[group != 7]  # a group without values
        values = values[: len(group)]
        has, med = _group_median(values, group, 60)
        want = pd.Series(values).groupby(group).median()
        assert np.array_equal(np.flatnonzero(has), want.index.to_numpy())
        assert np.array_equal(med.view("int64"), want.to_numpy().view("int64"))


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    n_tracks=st.integers(1, 12),
    parts=st.integers(2, 5),
    which=st.integers(0, len(PARAMS) - 1),
)
def test_detection_in_parts_of_whole_tracks_equals_one_pass(seed, n_tracks, parts, which):
    df = _scene(seed, n_tracks, False)
    one = detect(df, PARAMS[which], parts=1)
    split = detect(df, PARAMS[which], parts=parts)
    assert np.array_equal(split.factor.view("int64"), one.factor.view("int64"))
    assert np.array_equal(split.is_maneuver, one.is_maneuver)
    assert np.array_equal(split.at_rest, one.at_rest)
    assert np.array_equal(split.window_p, one.window_p)
    assert split.table().equals(one.table())


def test_a_cancel_in_one_part_stops_every_part():
    from wakeline.core.errors import Cancelled

    df = _scene(5, 12, False)
    calls = []

    def progress(fraction, text=""):
        calls.append(fraction)
        if len(calls) >= 2:
            raise Cancelled("stop")

    with pytest.raises(Cancelled):
        detect(df, ManeuverParams(), progress=progress, parts=3)


@pytest.mark.parametrize("p", [12, 16, 17, 32, 100, 320])
def test_gathered_window_moments_equal_the_convolutions_bit_for_bit(p):
    # the exact δ behind the long-window screen sums only the windows it needs, by the
    # same BLAS dot product np.convolve makes for a kernel longer than 11
    from wakeline.core.maneuver import _block_moments, _gathered_moments

    rng = np.random.default_rng(p)
    u = np.cumsum(rng.normal(30.0, 5.0, 3000)) + rng.normal(0, 20.0, 3000)
    v = np.cumsum(rng.normal(-10.0, 5.0, 3000)) + rng.normal(0, 20.0, 3000)
    want = _block_moments(u, v, p)
    ends = np.sort(rng.choice(np.arange(p - 1, len(u)), 400, replace=False))
    got = _gathered_moments(u, v, p, ends)
    for w, g in zip(want, got, strict=True):
        assert np.array_equal(w[ends - (p - 1)].view("int64"), g.view("int64"))

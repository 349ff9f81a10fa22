import numpy as np
import pandas as pd
import pytest

from wakeline.core import geo
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import (
    derive_motion,
    fill_motion,
    interp_positions,
    local_xy,
    sort_points,
    track_index,
    track_origins,
    track_summary,
)


def _points(rows):
    df = pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"])
    df["time"] = pd.to_datetime(df["time"], utc=True, format="ISO8601")
    return df


def test_sort_and_index_keep_batches_as_text():
    df = _points(
        [
            ("S1", "7", "2024-01-01T00:00:10Z", 0, 0),
            ("S1", "007", "2024-01-01T00:00:00Z", 0, 0),
            ("S1", "7", "2024-01-01T00:00:00Z", 0, 0),
            ("S0", "7", "2024-01-01T00:00:00Z", 0, 0),
        ]
    )
    s = sort_points(df)
    assert list(zip(s.sensor, s.batch, strict=True)) == [
        ("S0", "7"),
        ("S1", "007"),
        ("S1", "7"),
        ("S1", "7"),
    ]
    assert s.time.iloc[2] < s.time.iloc[3]
    idx = track_index(s)
    assert idx.n_tracks == 3
    assert list(idx.sizes) == [1, 1, 2]
    assert list(idx.track_of_row) == [0, 1, 2, 2]


def test_sorted_table_is_returned_as_is():
    df = _points(
        [("S1", "1", "2024-01-01T00:00:00Z", 0, 0), ("S1", "1", "2024-01-01T00:00:01Z", 0, 0)]
    )
    assert sort_points(df) is df


def test_derived_speed_and_course_northbound():
    # 10 kn due north: 1852*10/3600 m/s, one point a minute
    step_deg = np.degrees(10 * geo.KN_MS * 60 / geo.EARTH_RADIUS_M)
    rows = [("S1", "1", f"2024-01-01T00:{k:02d}:00Z", 5.0, 40.0 + k * step_deg) for k in range(5)]
    speed, course = derive_motion(_points(rows))
    assert np.allclose(speed, 10.0, rtol=1e-6)
    assert np.allclose(course, 0.0, atol=1e-6)


def test_derived_course_across_the_antimeridian():
    rows = [
        ("S1", "1", f"2024-01-01T00:{k:02d}:00Z", lon, -17.0)
        for k, lon in enumerate([179.96, 179.98, -180.0, -179.98, -179.96])
    ]
    speed, course = derive_motion(_points(rows))
    assert np.allclose(course, 90.0, atol=0.01)
    assert np.allclose(speed, speed[0], rtol=1e-6)
    assert speed[0] == pytest.approx(geo.haversine_m(179.96, -17, 179.98, -17) / 60 / geo.KN_MS)


def test_single_point_and_same_time_give_nan():
    rows = [
        ("S1", "a", "2024-01-01T00:00:00Z", 0, 0),
        ("S1", "b", "2024-01-01T00:00:00Z", 0, 0),
        ("S1", "b", "2024-01-01T00:00:00Z", 0, 0.01),
    ]
    speed, _ = derive_motion(_points(rows))
    assert np.isnan(speed).all()


def test_fill_motion_keeps_given_values():
    rows = [("S1", "1", f"2024-01-01T00:{k:02d}:00Z", 0.0, k * 0.01) for k in range(3)]
    df = _points(rows)
    df["speed"] = [np.nan, 12.5, np.nan]
    out = fill_motion(df)
    assert out.speed.iloc[1] == 12.5
    assert out.speed.iloc[0] == pytest.approx(out.speed.iloc[2])
    assert out.course.notna().all()


def test_local_xy_each_track_about_its_own_origin():
    rows = [
        ("S1", "a", "2024-01-01T00:00:00Z", 179.99, 0.0),
        ("S1", "a", "2024-01-01T00:01:00Z", -179.99, 0.0),
        ("S1", "b", "2024-01-01T00:00:00Z", 10.0, 50.0),
        ("S1", "b", "2024-01-01T00:01:00Z", 10.0, 50.01),
    ]
    df = sort_points(_points(rows))
    x, y = local_xy(df, track_index(df))
    assert x[1] - x[0] == pytest.approx(geo.haversine_m(179.99, 0, -179.99, 0), rel=1e-6)
    assert abs(x[0] + x[1]) < 1e-6  # centred on the track
    assert y[3] - y[2] == pytest.approx(geo.haversine_m(10, 50, 10, 50.01), rel=1e-6)


def test_track_summary():
    rows = [("S1", "1", f"2024-01-01T00:{k:02d}:00Z", 0.0, k * 0.01) for k in range(4)]
    rows.append(("S2", "x", "2024-01-01T00:00:00Z", 1.0, 1.0))
    summary = track_summary(_points(rows))
    assert list(summary.points) == [4, 1]
    first = summary.iloc[0]
    assert first.duration_s == 180
    assert first.length_m == pytest.approx(geo.haversine_m(0, 0, 0, 0.03), rel=1e-9)
    assert first.mean_speed_kn == pytest.approx(first.length_m / 180 / geo.KN_MS)
    assert np.isnan(summary.iloc[1].mean_speed_kn)


def test_time_seconds_independent_of_resolution():
    t = pd.Series(pd.to_datetime(["2024-01-01T00:00:01.5Z"], utc=True)).dt.as_unit("us")
    assert time_seconds(t)[0] == pytest.approx(1704067201.5)
    assert time_seconds(t.dt.as_unit("ns"))[0] == pytest.approx(1704067201.5)


def test_sort_keeps_sub_millisecond_order():
    rows = [
        ("S1", "1", "2024-01-01T00:00:00.0004Z", 0, 1),
        ("S1", "1", "2024-01-01T00:00:00.0001Z", 0, 0),
        ("S0", "2", "2024-01-01T00:00:00Z", 0, 0),
    ]
    s = sort_points(_points(rows))
    assert list(s.lat) == [0, 0, 1]
    rng = np.random.default_rng(0)
    n = 2000
    df = pd.DataFrame(
        {
            "sensor": rng.choice(["A", "B"], n),
            "batch": rng.choice(["1", "10", "2"], n),
            "time": pd.to_datetime(rng.integers(0, 10**12, n), unit="ns", utc=True),
            "lon": 0.0,
            "lat": 0.0,
        }
    )
    s = sort_points(df)
    ref = df.sort_values(["sensor", "batch", "time"], kind="stable").reset_index(drop=True)
    pd.testing.assert_frame_equal(s, ref)


def test_track_origin_and_plane_turn_with_the_globe():
    # one track near the pole, across 180°: the origin is the points' centre on the
    # sphere (it turns with the track when the globe turns), and every point's distance
    # from it in the plane is its great-circle distance
    lon, lat = geo.destination(179.0, 86.0, np.linspace(0, 300, 30), np.full(30, 80_000.0))
    rows = [("S1", "a", f"2024-01-01T00:{k:02d}:00Z", lon[k], lat[k]) for k in range(30)]
    df = sort_points(_points(rows))
    index = track_index(df)
    lon0, lat0 = track_origins(df, index)
    x, y = local_xy(df, index)
    d = geo.haversine_m(lon0[0], lat0[0], df["lon"].to_numpy(), df["lat"].to_numpy())
    np.testing.assert_allclose(np.hypot(x, y), d, rtol=1e-9)
    assert geo.haversine_m(lon0[0], lat0[0], *geo.centre_deg(lon, lat)) < 1e-6
    want = geo.to_local(df["lon"].to_numpy(), df["lat"].to_numpy(), lon0[0], lat0[0])
    assert np.array_equal(x, want[0]) and np.array_equal(y, want[1])  # bit for bit


def test_interpolation_follows_the_great_circle():
    # 40 km east-west at 72° N: linear in degrees the midpoint lay 50 m off the great circle
    rows = [
        ("S1", "a", "2024-01-01T00:00:00Z", 10.0, 72.0),
        ("S1", "a", "2024-01-01T01:00:00Z", 11.2, 72.0),
    ]
    df = sort_points(_points(rows))
    index = track_index(df)
    t0 = time_seconds(df["time"])[0]
    lon, lat, ok = interp_positions(df, index, np.array([0, 0, 0]), t0 + np.array([0, 1800, 3600]))
    assert ok.all() and lon[0] == 10.0 and lat[0] == 72.0 and lat[2] == 72.0
    mid = geo.destination(
        10.0, 72.0, geo.initial_bearing_deg(10.0, 72.0, 11.2, 72.0),
        0.5 * geo.haversine_m(10.0, 72.0, 11.2, 72.0),
    )  # fmt: skip
    assert geo.haversine_m(lon[1], lat[1], *mid) < 0.01


def test_natural_ranks_order_ids_by_their_leading_number():
    """D19's order: ids by the number they start with, then the rest (a track clean split,
    `338000000#2`, right after its own), ids without a number after, in text order; a
    total order of the values, whatever order they come in."""
    from wakeline.core.tracks import natural_ranks

    want = ["-3", "2", "007", "7", "9#2", "10", "21", "161", "338000000", "338000000#2"]
    want += ["338000001", "A2", "x"]
    rng = np.random.default_rng(0)
    for _ in range(3):
        values = list(rng.permutation(np.array(want, dtype=object)))
        rank, n = natural_ranks(values)
        assert n == len(want)
        assert [v for _, v in sorted(zip(rank, values, strict=True))] == want


def _scene_with_some_motion(seed: int) -> pd.DataFrame:
    from wakeline.core import simulate

    df = simulate.maneuver_tracks(3, "short", 50.0, seed=seed)
    df = df.sample(frac=1.0, random_state=seed).reset_index(drop=True)  # any row order
    rng = np.random.default_rng(seed)
    given = rng.random(len(df)) < 0.3
    df["speed"] = np.where(given, np.round(rng.uniform(0, 30, len(df)), 1), np.nan)
    df["course"] = np.where(given & (rng.random(len(df)) < 0.5), 123.0, np.nan)
    return df


@pytest.mark.parametrize("seed", [0, 1])
def test_with_derived_motion_fills_blanks_only_in_row_order_and_says_so(seed):
    from wakeline.core.tracks import MOTION_DERIVED, fill_motion, with_derived_motion

    df = _scene_with_some_motion(seed)
    out = with_derived_motion(df)
    assert len(out) == len(df) and (out.time.to_numpy() == df.time.to_numpy()).all()
    for name in ("speed", "course"):
        given = df[name].notna().to_numpy()
        assert (out[name].to_numpy()[given] == df[name].to_numpy()[given]).all()  # untouched
        assert out[name].notna().all()  # every point of a track of several points
        said = out[MOTION_DERIVED].str.contains(name).to_numpy()
        assert (said == ~given).all()
    # the values are fill_motion's (the sorted reference), rounded to 3 decimals
    ref = fill_motion(df)
    back = sort_points(out)
    assert np.allclose(back.speed, ref.speed, atol=6e-4)
    assert np.allclose(back.course, ref.course, atol=6e-4)


def test_derive_motion_flag_on_import_clean_and_compress(tmp_path):
    from wakeline.app.cli import main

    src = tmp_path / "in.csv"
    df = _scene_with_some_motion(3)
    df.to_csv(src, index=False)
    for cmd in (["import"], ["clean"], ["compress"]):
        plain, derived = tmp_path / "plain.csv", tmp_path / "derived.csv"
        assert main([*cmd, str(src), "-o", str(plain)]) == 0
        assert main([*cmd, str(src), "-o", str(derived), "--derive-motion"]) == 0
        a = pd.read_csv(plain, dtype={"batch": str})
        b = pd.read_csv(derived, dtype={"batch": str}, keep_default_na=False, na_values=[""])
        assert "motion_derived" not in a.columns, cmd  # the default is unchanged
        assert a.speed.isna().any(), cmd
        assert b.speed.notna().all() and b.course.notna().all(), cmd
        kept = b.motion_derived.isna().to_numpy()  # rows whose both values were given
        assert (a.speed.to_numpy()[kept] == b.speed.to_numpy()[kept]).all(), cmd
        assert list(b.columns[: len(a.columns)]) == list(a.columns), cmd

import json

import numpy as np
import pandas as pd
import pytest
from test_clean import move, straight

from wakeline.app.cli import main
from wakeline.core import geo
from wakeline.core.clean import CleanParams, clean, restore
from wakeline.core.errors import InputError
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import sorted_with_index
from wakeline.core.transform import (
    BsplineParams,
    ResampleParams,
    SmoothParams,
    bspline_segments,
    greedy_sample,
    resample,
    smooth,
    stated_max_gap,
)


def test_resample_on_a_grid_without_bridging_gaps():
    df = straight(40, period_s=7.0)
    df = df.drop(index=range(15, 25)).reset_index(drop=True)  # a 77 s gap
    df["wl_id"] = np.arange(len(df))
    out = resample(df, ResampleParams(enabled=True, period_s=10.0, max_gap_s=60.0), next_id=100)
    t = time_seconds(out["time"]) - time_seconds(df["time"])[0]
    assert np.allclose(t % 10.0, 0.0)
    gap_start, gap_end = 14 * 7.0, 25 * 7.0
    assert not np.any((t > gap_start) & (t < gap_end))
    # straight line at constant speed: interpolated positions lie on it
    full = straight(400, period_s=1.0)
    truth = full.set_index(time_seconds(full["time"]).round(3))
    for _, row in out.iterrows():
        ref = truth.loc[round(time_seconds(pd.Series([row.time]))[0], 3)]
        assert geo.haversine_m(row.lon, row.lat, ref.lon, ref.lat) < 0.05
    assert out.wl_id.min() == 100


def test_resample_a_sparse_track_finer_than_max_gap_keeps_it():
    """A track fixed every 120 s (MTAD decimated), resampled at 30 s with the default
    max_gap_s of 60 s: every step was a "gap", and only grid times falling on a fix were
    kept (8 of 118 fixes in three tracks). A step up to max_gap_steps (2) of the track's
    median step is no gap; a gap longer than that still is not bridged."""
    df = straight(30, period_s=120.0)
    df = df.drop(index=range(12, 16)).reset_index(drop=True)  # one 600 s gap
    df["wl_id"] = np.arange(len(df))
    params = ResampleParams(enabled=True, period_s=30.0, max_gap_s=60.0)
    out = resample(df, params)
    t = time_seconds(out["time"]) - time_seconds(df["time"])[0]
    assert len(out) == (11 * 120 // 30 + 1) + (29 - 16) * 120 // 30 + 1  # both pieces whole
    assert not np.any((t > 11 * 120) & (t < 16 * 120))  # the 600 s gap is not bridged
    old = resample(df, ResampleParams(enabled=True, period_s=30.0, max_gap_s=60.0,
                                      max_gap_steps=0.0))  # fmt: skip
    assert len(old) == len(df)  # what it did: the fixes alone (grid times on a fix)


def test_resample_a_sparse_track_is_not_bridged_beyond_the_cap(tmp_path):
    """SPEC §2.8: never across a gap longer than max_gap. The adaptive limit (max_gap_steps
    of the track's median step) made every step of a sparse track "no gap": two fixes 6 h
    apart became 1,081 points at 20 s, ATD's 30-min posits straight lines across hours.
    It is capped at max_gap_cap_s (600 s), and a max_gap_s given is the limit."""
    two = straight(2, period_s=6 * 3600.0)
    two["wl_id"] = np.arange(2)
    out = resample(two, ResampleParams(enabled=True, period_s=20.0))
    assert len(out) == 2  # the two fixes (on the grid), nothing between
    wide = resample(two, ResampleParams(enabled=True, period_s=20.0, max_gap_cap_s=1e7))
    assert len(wide) == 6 * 3600 // 20 + 1  # what it did without the cap
    # 120 s steps (under the cap) are still no gap, 900 s ones (2 x 900 > 600) are.
    for period, expect in ((120.0, 29 * 120 // 30 + 1), (900.0, 30)):
        df = straight(30, period_s=period)
        df["wl_id"] = np.arange(len(df))
        assert len(resample(df, ResampleParams(enabled=True, period_s=30.0))) == expect
    # A max_gap_s given (--set, --max-gap, a saved table without max_gap_steps) wins.
    assert CleanParams().with_settings(["resample.max_gap_s=60"]).resample.max_gap_steps == 0
    keep = CleanParams().with_settings(["resample.max_gap_s=60", "resample.max_gap_steps=3"])
    assert keep.resample.max_gap_steps == 3
    df = straight(30, period_s=120.0)
    src, a, b = tmp_path / "a.csv", tmp_path / "b.csv", tmp_path / "c.csv"
    df.to_csv(src, index=False)
    common = ["clean", str(src), "--resample", "30", "--off", "short_tracks"]
    assert main([*common, "-o", str(a)]) == 0
    assert main([*common, "-o", str(b), "--max-gap", "60"]) == 0
    assert len(pd.read_csv(a)) == 29 * 120 // 30 + 1
    assert len(pd.read_csv(b)) == 30  # the fixes alone: every 120 s step is a gap


def test_a_stated_max_gap_is_the_limit_one_rule_for_command_line_panel_and_batch():
    """SPEC §2.8: a max_gap_s the operator states is the gap limit (max_gap_steps 0, the
    adaptive limit off) unless max_gap_steps is stated too. The rule is one function of
    the core: the command line's settings, a pipeline file (``wakeline batch``) and the
    GUI's parameter panel (which had no such rule) all call it."""
    from wakeline.core.pipeline import Pipeline

    assert stated_max_gap({"max_gap_s": 300.0}) == {"max_gap_s": 300.0, "max_gap_steps": 0.0}
    both = {"max_gap_s": "300", "max_gap_steps": "3"}
    assert stated_max_gap(both) == both
    assert stated_max_gap({"period_s": 30.0}) == {"period_s": 30.0}  # nothing stated: adaptive
    source = {"max_gap_s": 300.0}
    stated_max_gap(source)
    assert source == {"max_gap_s": 300.0}  # the caller's values are left as they were
    # The command line's settings and a pipeline file batch reads take it from there.
    assert CleanParams().with_settings(["resample.max_gap_s=300"]).resample.max_gap_steps == 0
    stage = {"step": "clean", "params": {"clean": {"resample": {"max_gap_s": 300}}}}
    text = json.dumps({"wakeline_pipeline": 2, "steps": [stage]})
    assert Pipeline.from_json(text).stages[0][1]["clean"].resample.max_gap_steps == 0


def test_smooth_reduces_noise_and_keeps_tracks_apart():
    rng = np.random.default_rng(0)
    a = straight(100, batch="a")
    b = straight(100, batch="b", lon0=123.0)
    clean_a = a.copy()
    noisy = pd.concat([a, b], ignore_index=True)
    noisy[["lon", "lat"]] += rng.normal(0, 2e-4, (200, 2))
    out = smooth(noisy, SmoothParams(enabled=True, window=5))
    err_before = geo.haversine_m(noisy.lon[:100], noisy.lat[:100], clean_a.lon, clean_a.lat).mean()
    err_after = geo.haversine_m(out.lon[:100], out.lat[:100], clean_a.lon, clean_a.lat).mean()
    assert err_after < 0.65 * err_before
    assert (
        geo.haversine_m(out.lon[100], out.lat[100], b.lon[0], b.lat[0]) < 100
    )  # b is not pulled to a
    line = smooth(straight(30), SmoothParams(enabled=True, window=7))
    assert np.allclose(line.lat[3:27], straight(30).lat[3:27], atol=1e-7)


def _turning_track(n: int, batch: str, rng) -> tuple[pd.DataFrame, pd.DataFrame]:
    """A ship on a slow arc (a point every 10 s at 10 kn), true and with 30 m noise."""
    t = np.arange(n) * 10.0
    heading = np.radians(20.0 + 0.15 * t)  # 0.15 deg/s
    v = 10 * geo.KN_MS
    x = np.cumsum(v * 10.0 * np.sin(heading))
    y = np.cumsum(v * 10.0 * np.cos(heading))
    lon, lat = geo.from_local(x, y, 122.0, 30.0)
    true = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": batch,
            "time": pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(t, unit="s"),
            "lon": lon,
            "lat": lat,
        }
    )
    nlon, nlat = geo.from_local(x + rng.normal(0, 30, n), y + rng.normal(0, 30, n), 122.0, 30.0)
    return true, true.assign(lon=nlon, lat=nlat)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_smooth_cubic_bspline_option_reduces_noise_same_rows(seed):
    rng = np.random.default_rng(seed)
    true, noisy = _turning_track(120, "a", rng)
    short_true, short = _turning_track(4, "b", rng)  # too short for a spline: as it was
    pts = pd.concat([noisy, short], ignore_index=True)
    assert SmoothParams().method == "average"  # the default is unchanged
    out = smooth(pts, SmoothParams(enabled=True, method="bspline"))
    assert len(out) == len(pts) and (out.time.to_numpy() == sorted_with_index(pts)[0].time).all()
    a = out[out.batch == "a"].reset_index(drop=True)
    before = geo.haversine_m(noisy.lon, noisy.lat, true.lon, true.lat).mean()
    after = geo.haversine_m(a.lon, a.lat, true.lon, true.lat).mean()
    assert after < 0.6 * before
    b = out[out.batch == "b"].reset_index(drop=True)
    assert np.allclose(b.lon, short.lon, atol=1e-7) and np.allclose(b.lat, short.lat, atol=1e-7)
    # fewer knots (a knot per 20 points) smooth more on this gentle arc, and differ
    coarse = smooth(pts, SmoothParams(enabled=True, method="bspline", window=21))
    assert np.abs(coarse.lon - out.lon).max() > 1e-6  # about 0.1 m


@pytest.mark.parametrize("seed", [0, 1])
def test_smooth_bspline_over_a_long_gap_in_a_track_gives_positions(seed):
    """Knots evenly spaced in time put knot spans with no point in a track's gap (an
    AIS ship silent for hours): the least-squares fit had no solution and every point
    of the track came out NaN. Each part's noise is still reduced."""
    rng = np.random.default_rng(seed)
    true1, noisy1 = _turning_track(60, "a", rng)
    true2, noisy2 = _turning_track(60, "a", rng)
    later = pd.to_timedelta(10, unit="h")
    true = pd.concat([true1, true2.assign(time=true2.time + later)], ignore_index=True)
    noisy = pd.concat([noisy1, noisy2.assign(time=noisy2.time + later)], ignore_index=True)
    out = smooth(noisy, SmoothParams(enabled=True, method="bspline"))
    assert len(out) == len(noisy) and np.isfinite(out[["lon", "lat"]].to_numpy()).all()
    before = geo.haversine_m(noisy.lon, noisy.lat, true.lon, true.lat).mean()
    after = geo.haversine_m(out.lon, out.lat, true.lon, true.lat).mean()
    assert after < 0.6 * before


def test_smooth_bspline_is_rule_10s_fit_not_a_copy(monkeypatch):
    """Rule 9's B-spline and rule 10 call the one fit (transform.spline_fit)."""
    from wakeline.core import transform

    calls = []
    real = transform.spline_fit

    def spy(*args, **kw):
        calls.append(len(args[3]))
        return real(*args, **kw)

    monkeypatch.setattr(transform, "spline_fit", spy)
    _true, noisy = _turning_track(60, "a", np.random.default_rng(3))
    transform.smooth(noisy, SmoothParams(enabled=True, method="bspline"))
    transform.bspline_segments(noisy, BsplineParams(enabled=True))
    assert len(calls) == 2


def test_cli_smooth_method_bspline(tmp_path, capsys):
    _true, noisy = _turning_track(60, "a", np.random.default_rng(4))
    src = tmp_path / "in.csv"
    noisy.to_csv(src, index=False)
    out = tmp_path / "out.csv"
    argv = ["clean", str(src), "-o", str(out), "--smooth", "--set", "smooth.method=bspline"]
    assert main(argv) == 0
    spline = pd.read_csv(out)
    assert len(spline) > 50  # the other rules may remove a noisy point or two
    average = tmp_path / "average.csv"
    assert main(["clean", str(src), "-o", str(average), "--smooth"]) == 0
    average = pd.read_csv(average)
    assert len(average) == len(spline) and np.abs(average.lon - spline.lon).max() > 1e-6
    argv[-1] = "smooth.method=cubic"
    assert main(argv) == 2
    assert "smooth.method" in capsys.readouterr().err


def test_greedy_sampling_matches_the_sequential_rule():
    rng = np.random.default_rng(3)
    frames = []
    for k in range(6):
        t = np.cumsum(rng.exponential(8.0, int(rng.integers(1, 80))))
        frames.append(
            pd.DataFrame(
                {
                    "sensor": "S",
                    "batch": str(k),
                    "time": pd.to_datetime(t, unit="s", utc=True),
                    "lon": 0.0,
                    "lat": 0.0,
                }
            )
        )
    pts, index = sorted_with_index(pd.concat(frames, ignore_index=True))
    t = time_seconds(pts["time"])
    got = greedy_sample(t, index, 21.0)
    ref = np.zeros(len(t), dtype=bool)
    for a, b in zip(index.starts, index.ends, strict=True):
        last = None
        for i in range(a, b):
            if last is None or t[i] - last >= 21.0:
                ref[i] = True
                last = t[i]
    assert np.array_equal(got, ref)


def two_ship_batch():
    """Batch 77 follows ship A for 20 min, then (radar confusion) ship B 6 km away."""
    a = straight(120, speed_kn=12, batch="77", course=40.0).assign(truth="A")
    b = straight(120, speed_kn=14, batch="77", course=300.0, lon0=122.06, lat0=30.01).assign(
        truth="B"
    )
    b["time"] = b["time"] + pd.Timedelta(seconds=1200)
    return pd.concat([a, b], ignore_index=True)


def test_two_ship_batch_is_split_into_two_segments():
    result = clean(two_ship_batch(), CleanParams().with_settings(["bspline.enabled=true"]))
    pts = result.points
    assert sorted(pts.batch.unique()) == ["77/1", "77/2"]
    assert set(pts.parent_batch) == {"77"}
    assert pts.groupby("batch").truth.agg(set).to_dict() == {"77/1": {"A"}, "77/2": {"B"}}
    assert result.report["rules"]["speed"]["breaks"] == 1  # ship B was not thrown away as outliers
    assert result.report["rules"]["bspline"]["replaced"] == 240


def test_bspline_interpolates_at_half_the_sampling_interval():
    df = straight(60, period_s=10.0)
    out = bspline_segments(df.drop(index=range(20, 24)), BsplineParams(enabled=True, sample_s=21.0))
    assert out.batch.unique().tolist() == ["1"]  # one ship, one segment
    t = time_seconds(out["time"])
    new = out.interpolated.to_numpy() == 1
    assert new.any()
    assert np.allclose(np.diff(t)[np.flatnonzero(new) - 1], 10.5)
    truth = straight(1200, period_s=0.5)
    tt = time_seconds(truth["time"])
    for lon, lat, ti in zip(out.lon[new], out.lat[new], t[new], strict=True):
        j = np.argmin(np.abs(tt - ti))
        assert geo.haversine_m(lon, lat, truth.lon[j], truth.lat[j]) < 5.0


def test_replaced_points_are_in_the_trail_and_not_restorable_one_by_one():
    df = straight(50)
    move(df, 10, 30)
    result = clean(df, CleanParams().with_settings(["smooth.enabled=true"]))
    trail = result.rejected[result.rejected.action == "replaced"]
    assert len(trail) > 0 and set(trail.rule) == {"smooth"}
    with pytest.raises(InputError, match="cleaning again without that step"):
        restore(result.points, result.rejected, trail.wl_id[:1])


def test_cli_transform_flags(tmp_path, capsys):
    src = tmp_path / "two.csv"
    two_ship_batch().to_csv(src, index=False)
    out = tmp_path / "out.csv"
    assert main(["clean", str(src), "-o", str(out), "--bspline"]) == 0
    assert sorted(pd.read_csv(out, dtype={"batch": str}).batch.unique()) == ["77/1", "77/2"]
    assert (
        main(
            [
                "clean",
                str(src),
                "-o",
                str(out),
                "--resample",
                "20",
                "--max-gap",
                "30",
                "--smooth",
                "3",
            ]
        )
        == 0
    )
    res = pd.read_csv(out)
    assert len(res) < 240
    assert "resample" in capsys.readouterr().err
    assert main(["clean", str(src), "-o", str(out), "--smooth", "2"]) == 2
    assert "smooth.window must be at least 3" in capsys.readouterr().err


@pytest.mark.parametrize("step", ["resample", "bspline"])
def test_points_a_transform_makes_get_their_tracks_speed_and_course(step):
    """Resampled or spline points had speed and course blank (an export like the original
    wrote empty course cells, fuzzing): derived from the new track."""
    df = straight(120, period_s=10.0, speed_kn=12.0, batch="a")
    df["course"] = np.nan
    df["speed"] = np.nan
    out = clean(df, CleanParams().with_settings([f"{step}.enabled=true"])).points
    assert len(out) > 10
    assert out["speed"].between(11.0, 13.0).mean() > 0.9
    assert np.isfinite(out["course"]).all()


def test_bspline_delta_d_per_interval_and_the_papers_way():
    # 20 kn, 10 s fixes, Δt 21 s: ordinary sampled legs ~216 m; a 70 s silence makes one
    # leg of ~720 m > Δd = 450 m, which is a jump only under the paper's rule
    df = straight(60, speed_kn=20.0, period_s=10.0).drop(index=range(20, 26))
    ours = bspline_segments(df, BsplineParams(enabled=True, sample_s=21.0))
    assert ours.batch.unique().tolist() == ["1"]
    paper = bspline_segments(
        df, BsplineParams(enabled=True, sample_s=21.0, jump_per_interval=False)
    )
    assert paper.batch.unique().tolist() == ["1/1", "1/2"]


def test_bspline_judges_the_turn_after_a_jump_only_the_papers_way():
    # a 3 km jump south off a course of 60°: the leg out of it turns ~120° against the
    # jump's course; only the paper's rule splits there too (a one-fix segment)
    df = straight(60, speed_kn=12.0, period_s=10.0)
    df.loc[30:, "lat"] = df.loc[30:, "lat"] - 0.03
    ours = BsplineParams(enabled=True, sample_s=21.0, quality_ratio=1.0)  # multi-target rule
    paper = BsplineParams(enabled=True, sample_s=21.0, quality_ratio=1.0, judge_after_jump=True)
    assert bspline_segments(df, ours).batch.nunique() == 2  # the jump alone splits
    assert bspline_segments(df, paper).batch.nunique() == 3  # and the turn out of it too

"""Multi-sensor association and fusion (SPEC §6)."""

import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core import geo, simulate
from wakeline.core.errors import InputError
from wakeline.core.evaluate_association import (
    fusion_errors,
    sensor_pair_scores,
    single_sensor_shifts,
)
from wakeline.core.fuse import FuseParams, associate_sensors, fuse, member_weights
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import interp_positions, sorted_with_index

T0 = pd.Timestamp("2024-05-01T00:00:00Z")


def observe(sensor, batch, t0, t1, period, sigma, seed, truth="A", bias=(0.0, 0.0), course=60.0):
    """A ship at 6 m/s on ``course`` seen from t0 to t1 every ``period`` s with noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(t0, t1 + 1e-9, period)
    rad = np.radians(course)
    x, y = 6.0 * np.sin(rad) * t, 6.0 * np.cos(rad) * t
    lon, lat = geo.from_local(
        x + bias[0] + rng.normal(0, sigma, len(t)),
        y + bias[1] + rng.normal(0, sigma, len(t)),
        122.5,
        30.5,
    )
    tlon, tlat = geo.from_local(x, y, 122.5, 30.5)
    return pd.DataFrame(
        {
            "sensor": sensor,
            "batch": batch,
            "time": T0 + pd.to_timedelta(t, unit="s"),
            "lon": lon,
            "lat": lat,
            "truth": truth,
            "true_lon": tlon,
            "true_lat": tlat,
        }
    )


def test_a_ship_seen_by_two_sensors_is_paired_and_fused_between_them():
    ais = observe("AIS", "7", 0, 1800, 6.0, 10.0, 1)
    radar = observe("R1", "300", 0, 1800, 10.0, 100.0, 2)
    a = associate_sensors(pd.concat([ais, radar]))
    assert a.pair_table()[["batch_a", "batch_b"]].values.tolist() == [["7", "300"]]
    f = fuse(a)
    # named after its earliest track, as the review names it (h168 D-review-2)
    assert set(f["batch"]) == {"AIS:7"} and f["members"].iloc[0] == "AIS:7+R1:300"
    both = f[f["n_sources"] == 2]
    assert len(both) > 200
    # Each fused point lies on the segment between the AIS point and the radar track
    # at that time, much closer to the AIS (less noisy) end.
    pts, index = sorted_with_index(pd.concat([ais, radar]))
    radar_track = int(np.flatnonzero(index.keys["sensor"] == "R1")[0])
    t = time_seconds(both["time"])
    rl, ra, _ = interp_positions(pts, index, np.full(len(t), radar_track), t)
    ais_at = ais.set_index("time").loc[both["time"]]
    d_ais = geo.haversine_m(both["lon"], both["lat"], ais_at["lon"], ais_at["lat"])
    d_rad = geo.haversine_m(both["lon"], both["lat"], rl, ra)
    d_ar = geo.haversine_m(ais_at["lon"], ais_at["lat"], rl, ra)
    np.testing.assert_allclose(d_ais + d_rad, d_ar, atol=0.5)
    assert np.all(d_ais <= d_rad)
    assert both["weight_base"].min() > 0.85  # 0.2 x regularity (equal) + 0.8 x noise (99 %)


def test_non_overlapping_tracks_are_never_paired():
    ais = observe("AIS", "1", 0, 900, 6.0, 10.0, 1)
    radar = observe("R1", "2", 1000, 1800, 10.0, 50.0, 2)
    a = associate_sensors(pd.concat([ais, radar]))
    assert len(a.chosen) == 0 and len(a.a) == 0
    f = fuse(a)
    assert f["batch"].nunique() == 2 and set(f["n_sources"]) == {1}


def test_point_count_ratio_gate():
    """Counts compared at each track's own rate: 2 s AIS and 30 s radar of one ship pair
    (seed 003's raw counts, 15x, refuse them); a track silent over most of the common
    span is still refused."""
    ais = observe("AIS", "1", 0, 1800, 2.0, 10.0, 1)
    radar = observe("R1", "2", 0, 1800, 30.0, 10.0, 2)  # 15x fewer points
    assert len(associate_sensors(pd.concat([ais, radar])).chosen) == 1
    paper = FuseParams(count_at_rates=False)
    assert len(associate_sensors(pd.concat([ais, radar]), paper).chosen) == 0
    loose = FuseParams(count_at_rates=False, count_ratio_max=20.0)
    assert len(associate_sensors(pd.concat([ais, radar]), loose).chosen) == 1
    t = (ais["time"] - T0).dt.total_seconds()
    quiet = ais[(t < 150) | ((t > 1650) & (t < 1700))]  # 200 s of points over 1700 s
    assert len(associate_sensors(pd.concat([quiet, radar])).chosen) == 0


def test_a_short_common_span_densely_seen_by_both_sensors_is_compared():
    """Autoferry's harbour radar (1.7 s) and lidar (0.5 s) see a boat together for 35-59 s:
    under min_overlap_s (60 s) the true pairs were never compared, 7 of 18 went unfused,
    and in scenario 4 the lidar track of one boat was fused with the radar track of the
    other, 60 m away, the one pair that overlapped 60 s. A shorter span with
    min_overlap_fixes of each track is compared; sparse tracks still need 60 s."""
    lid_a = observe("lidar", "a", 0, 76, 0.5, 2.0, 1, truth="A")
    rad_a = observe("radar", "a", 17, 76, 1.7, 3.0, 2, truth="A")  # 59 s with lidar a
    lid_b = observe("lidar", "b", 20, 78, 0.5, 2.0, 3, truth="B", bias=(60.0, 0.0))
    rad_b = observe("radar", "b", -19, 78, 1.7, 3.0, 4, truth="B", bias=(60.0, 0.0))
    df = pd.concat([lid_a, rad_a, lid_b, rad_b], ignore_index=True)
    got = associate_sensors(df).pair_table()[["batch_a", "batch_b"]].values.tolist()
    assert sorted(got) == [["a", "a"], ["b", "b"]]
    seconds_only = FuseParams(min_overlap_fixes=0)
    wrong = associate_sensors(df, seconds_only).pair_table()[["batch_a", "batch_b"]]
    assert wrong.values.tolist() == [["a", "b"]]  # what it did: two boats fused
    # 10 s tracks over 50 s: 5 fixes each, refused as before.
    ais = observe("AIS", "1", 0, 300, 10.0, 5.0, 5)
    radar = observe("R1", "2", 250, 600, 10.0, 20.0, 6)
    assert len(associate_sensors(pd.concat([ais, radar])).a) == 0


def test_a_dense_common_span_still_needs_half_of_min_overlap_s():
    """min_overlap_fixes (15) alone let a 10 Hz sensor pair compare over 1.5 s: two boats
    60 m apart passing each other, both seen at 10 Hz for the same 2 s, were fused. The
    short span must also be at least half of min_overlap_s (30 s), which Autoferry's true
    radar + lidar pairs (34.8-59 s together, bench/fuse_autoferry.py) are."""
    from wakeline.core.pipeline import STEPS

    u = np.array([np.sin(np.radians(60.0)), np.cos(np.radians(60.0))])
    meet = 2 * 6.0 * 29.0 * u + 60.0 * np.array([u[1], -u[0]])  # 60 m apart at t = 29 s
    a = observe("L1", "a", 0, 30, 0.1, 1.0, 1, truth="A")
    b = observe("L2", "b", 28, 60, 0.1, 1.0, 2, truth="B", bias=tuple(meet), course=240.0)
    df = pd.concat([a, b], ignore_index=True)
    got = associate_sensors(df)
    assert len(got.chosen) == 0 and got.report()["refused_short_overlap"] == 1
    assert len(associate_sensors(df, FuseParams(min_overlap_s=4.0)).chosen) == 1  # 2 s >= 2 s
    step = STEPS["fuse"]
    text = step.summary(step(df, {"fuse": FuseParams()}))
    assert "under min_overlap_s (60 s) without min_overlap_fixes (15) of each track" in text
    assert "in at least half of it (30 s)" in text, text
    # 31 s together at 10 Hz (over half of 60 s): compared, as the Autoferry pairs are.
    c = observe("L2", "c", -1, 30, 0.1, 1.0, 3, truth="A")
    long = associate_sensors(pd.concat([a, c], ignore_index=True)).pair_table()
    assert long[["batch_a", "batch_b"]].values.tolist() == [["a", "c"]]


def test_a_piece_is_not_handed_to_another_ship_far_beyond_its_own():
    """Two ships 500 m apart side by side; AIS sees both whole, the radar sees only ship
    A, broken into two pieces. Round one gives A's AIS one piece; the other piece is
    40 m from A's AIS and 500 m from B's: it waits for round two (A's AIS again), not
    B's AIS (fuzzing found 22 of 121 pairs wrong in a harbour like this)."""
    ais_a = observe("AIS", "a", 0, 1800, 10.0, 8.0, 1, truth="A")
    ais_b = observe("AIS", "b", 0, 1800, 10.0, 8.0, 2, truth="B", bias=(500.0, 0.0))
    r1 = observe("R1", "r1", 0, 850, 3.0, 30.0, 3, truth="A")
    r2 = observe("R1", "r2", 950, 1800, 3.0, 30.0, 4, truth="A")
    df = pd.concat([ais_a, ais_b, r1, r2], ignore_index=True)
    got = set(map(tuple, associate_sensors(df).pair_table()[["batch_a", "batch_b"]].values))
    assert got == {("a", "r1"), ("a", "r2")}
    paper = associate_sensors(df, FuseParams(best_factor=0.0)).pair_table()
    assert ("b", "r1") in set(map(tuple, paper[["batch_a", "batch_b"]].values)) or (
        "b", "r2") in set(map(tuple, paper[["batch_a", "batch_b"]].values))  # fmt: skip


def _steps(f: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    st = geo.haversine_m(
        f["lon"].values[:-1], f["lat"].values[:-1], f["lon"].values[1:], f["lat"].values[1:]
    )
    junction = (f["n_sources"].values[:-1] >= 2) != (f["n_sources"].values[1:] >= 2)
    return st, junction


@pytest.mark.parametrize("straddle", [False, True])
def test_junction_blend_leaves_no_jump(straddle):
    # AIS covers the first half; the radar, 250 m off to the side, goes on alone.
    ais = observe("AIS", "1", 0, 1200, 10.0, 2.0, 1)
    radar = observe(
        "R1",
        "2",
        0,
        2400,
        10.0,
        3.0,
        2,
        bias=(250.0 * np.cos(np.radians(60)), -250.0 * np.sin(np.radians(60))),
    )
    a = associate_sensors(pd.concat([ais, radar]))
    raw, junction = _steps(fuse(a, FuseParams(blend_points=0)))
    sampling = np.median(raw)  # 6 m/s × 10 s = 60 m
    assert raw[junction].max() > 2.0 * sampling
    blended = fuse(a, FuseParams(blend_straddle=straddle))
    st, _ = _steps(blended)
    assert st.max() <= 1.25 * sampling


def test_weights_favour_regular_and_quiet_sensors_and_sum_to_one():
    q = pd.DataFrame({"interval_var_s2": [0.1, 4.0, 0.1, 0.1], "noise_m": [10.0, 10.0, 10.0, 40.0]})
    target = np.array(["A", "A", "B", "B"])
    w = member_weights(q, target, 0.5, 0.5)
    np.testing.assert_allclose([w[0] + w[1], w[2] + w[3]], 1.0)
    assert w[0] > w[1] and w[2] > w[3]
    # Noise only: inverse-variance weights, 16:1 for a 4x noisier sensor.
    w = member_weights(q, target, 0.0, 1.0)
    assert w[2] / w[3] == pytest.approx(16.0)


@pytest.mark.parametrize(("ships", "area", "lanes"), [(40, 30.0, 0), (300, 30.0, 3)])
def test_simulated_scenes_meet_the_issue_targets(ships, area, lanes):
    df = simulate.multisensor_scene(seed=3, n_ships=ships, area_km=area, lanes=lanes)
    a = associate_sensors(df)
    sc = sensor_pair_scores(a)
    assert sc["p_ca"] >= 0.95 and sc["p_fa"] <= 0.05
    err = fusion_errors(a, fuse(a))
    assert err["fused_m"] <= min(err["AIS_m"], err["R1_m"])


def test_dtw_and_greedy_run_and_agree_on_an_easy_scene():
    df = simulate.multisensor_scene(seed=4, n_ships=20)
    ref = sorted(associate_sensors(df).pair_table()["batch_a"])
    for distance in ("sync", "dtw"):
        for method in ("optimal", "greedy"):
            a = associate_sensors(df, distance=distance, method=method)
            assert sorted(a.pair_table()["batch_a"]) == ref


def test_bad_requests():
    one = observe("AIS", "1", 0, 600, 6.0, 10.0, 1)
    with pytest.raises(InputError, match="at least two sensors"):
        associate_sensors(one)
    two = pd.concat([one, observe("R1", "2", 0, 600, 10.0, 10.0, 2)])
    with pytest.raises(InputError, match="unknown distance"):
        associate_sensors(two, distance="euclid")
    with pytest.raises(InputError, match="max_distance_m must be at least"):
        associate_sensors(two, FuseParams(max_distance_m=0.0))


def test_cli_fuse_round_trip_and_errors(tmp_path, capsys):
    src = tmp_path / "ms.csv"
    assert main(["simulate", "multisensor", "-o", str(src), "--seed", "5"]) == 0
    out, pairs = tmp_path / "fused.csv", tmp_path / "pairs.csv"
    assert main(["fuse", str(src), "-o", str(out), "--pairs", str(pairs)]) == 0
    f = pd.read_csv(out)
    assert set(f["sensor"]) == {"fused"} and f["members"].str.contains(r"\+").any()
    assert list(pd.read_csv(pairs).columns[:5]) == [
        "sensor_a",
        "batch_a",
        "sensor_b",
        "batch_b",
        "distance",
    ]
    # Every fused track holds one ship.
    assert f.groupby("batch")["truth"].nunique().max() == 1
    # Re-import: a valid canonical file.
    assert main(["import", str(out), "-o", str(tmp_path / "again.csv")]) == 0
    capsys.readouterr()
    single = tmp_path / "one.csv"
    observe("AIS", "1", 0, 600, 6.0, 10.0, 1).to_csv(single, index=False)
    bad = tmp_path / "bad.csv"
    assert main(["fuse", str(single), "-o", str(bad)]) == 2
    assert main(["fuse", str(src), "-o", str(bad), "--set", "alpha=2"]) == 2
    assert main(["fuse", str(tmp_path / "missing.csv"), "-o", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "at least two sensors" in err and "alpha must be at most 1" in err
    assert not bad.exists()


def test_fuse_summary_counts_inputs_and_says_why_nothing_paired():
    """The summary names the input points next to the fused ones, and when no pair is
    chosen it names the two limits to raise (found by a helper: 0 pairs, no reason)."""
    from wakeline.core.pipeline import _summary_fuse

    class R:
        report = {
            "tracks": 30, "sensors": 2, "targets": 30, "pairs_chosen": 0,
            "candidate_pairs": 10, "distance": "sync", "method": "optimal",
            "fused_points": 772, "points_in": 772, "max_distance_m": 1000.0,
            "max_interp_s": 600.0,
        }  # fmt: skip

    text = _summary_fuse(R())
    assert "from 772 input points" in text and "max_distance_m (1000 m)" in text
    R.report = {**R.report, "pairs_chosen": 5, "fused_points": 500}
    text = _summary_fuse(R())
    assert "become one" in text and "max_distance_m" not in text


def test_when_every_pair_is_beyond_the_gate_the_summary_says_how_far_the_nearest_is():
    """MTAD V2's positive demo pair (one ship, sources 9001 / 9002) lies 3.1 km apart on
    average: the summary said "the other 1 were farther apart on average than the gate",
    with no figure to raise the gate to. It now says it was, and the nearest's distance."""
    from wakeline.core.pipeline import STEPS

    ais = observe("AIS", "1", 0, 1800, 10.0, 10.0, 1)
    radar = observe("R1", "2", 0, 1800, 10.0, 10.0, 2, course=70.0)  # 0 to 1.9 km apart
    df = pd.concat([ais, radar], ignore_index=True)
    rep = associate_sensors(df, FuseParams(max_distance_m=600.0)).report()
    assert rep["pairs_chosen"] == 0 and rep["nearest_m"] == pytest.approx(940.0, abs=30.0)
    step = STEPS["fuse"]
    text = step.summary(step(df, {"fuse": FuseParams(max_distance_m=600.0)}))
    assert "1 pair of tracks came within" in text, text
    assert "refused: none by the gates; it was farther apart on average than the gate" in text, text
    assert "the nearest 9" in text and "m apart on average" in text, text


def test_a_single_sensors_points_keep_their_reported_speed_and_course():
    """AIS SOG/COG pass through fusion where AIS alone covers the time (fuzzing found them
    recomputed from positions); where two sensors blend, the fused track's motion."""
    ais = observe("AIS", "1", 0, 1800, 10.0, 5.0, 1).assign(speed=11.7, course=60.3)
    radar = observe("R1", "2", 900, 1800, 10.0, 30.0, 2)
    lone = observe("AIS", "9", 0, 600, 10.0, 5.0, 3, truth="B", bias=(5000.0, 0.0))
    lone = lone.assign(speed=8.2, course=61.0)
    fused = fuse(associate_sensors(pd.concat([ais, radar, lone], ignore_index=True)))
    alone = fused[fused["n_sources"] == 1]
    assert len(alone) > 60 and (alone["speed"].isin([11.7, 8.2])).all()
    assert (alone["course"].isin([60.3, 61.0])).all()
    both = fused[fused["n_sources"] >= 2]
    assert len(both) > 50 and 10.5 < both["speed"].median() < 13.0  # 6 m/s ≈ 11.7 kn


def test_a_later_piece_is_judged_against_rivals_of_its_own_time():
    """The best distance a pair is compared with comes from pairs over the same time: a
    radar piece far off (400 m) after a close one (5 m) still joins its only AIS (review:
    the close earlier piece's 5 m refused it)."""
    ais = observe("AIS", "A", 0, 7200, 10.0, 0.0, 1, course=90.0)
    p1 = observe("R1", "P1", 0, 3596, 4.0, 0.0, 2, course=90.0, bias=(0.0, 5.0))
    p2 = observe("R1", "P2", 3600, 7200, 4.0, 0.0, 3, course=90.0, bias=(0.0, 400.0))
    pairs = associate_sensors(pd.concat([ais, p1, p2], ignore_index=True)).pair_table()
    assert sorted(pairs["batch_b"]) == ["P1", "P2"]


def test_a_fix_after_a_long_gap_is_where_the_track_was():
    """A query at one of a track's own times is that fix, even when a gap longer than
    ``max_gap_s`` precedes it (it was 'not covered': a fix both sensors hold after one
    sensor's gap came out twice, once fused and once alone)."""
    ais = observe("AIS", "1", 0, 1800, 10.0, 5.0, 1)
    t = (ais["time"] - T0).dt.total_seconds()
    ais = ais[(t == 0) | (t >= 700)]  # 0 s, then 700 s of silence
    pts, index = sorted_with_index(ais)
    q = time_seconds(pd.Series(T0 + pd.to_timedelta([700.0, 350.0, 1800.0], unit="s")))
    lon, lat, ok = interp_positions(pts, index, np.zeros(3, "int64"), q, 600.0)
    assert ok.tolist() == [True, False, True]
    assert (lon[0], lat[0]) == (ais["lon"].iloc[1], ais["lat"].iloc[1])
    radar = observe("R1", "2", 600, 1800, 10.0, 30.0, 2)
    both = ais.set_index("time")[["lon", "lat"]].loc[radar["time"].iloc[10]]
    radar.loc[radar.index[10], ["lon", "lat"]] = both.to_numpy()  # the same fix at 700 s
    f = fuse(associate_sensors(pd.concat([ais, radar], ignore_index=True)))
    assert not f.duplicated(["batch", "time"]).any()
    at = f[f["time"] == radar["time"].iloc[10]]
    assert len(at) == 1 and at["n_sources"].iloc[0] == 2


def test_single_sensor_shifts_measure_a_lone_point_against_its_own_fix():
    """The evaluation's view of fusion where one sensor is alone: each such fused point
    against its sensor's fix at that time (the fused error in the overlap never saw the
    lone points the junction blend moved)."""
    ais = observe("AIS", "1", 0, 1800, 10.0, 5.0, 1)
    radar = observe("R1", "2", 0, 900, 10.0, 30.0, 2)
    a = associate_sensors(pd.concat([ais, radar], ignore_index=True))
    f = fuse(a, FuseParams(blend_points=0))
    got = single_sensor_shifts(a.points, f)
    assert got["single_shift_max"] < 0.05  # without a blend: the fixes themselves
    assert got["single_fused_err"] == pytest.approx(got["single_own_err"], abs=0.05)
    lone = np.flatnonzero(f["n_sources"].to_numpy() == 1)
    assert len(lone) > 50
    f.loc[lone[-1], "lat"] += 100.0 / 111_195.0  # 100 m north
    got = single_sensor_shifts(a.points, f)
    assert got["single_shift_max"] == pytest.approx(100.0, abs=0.5)
    assert got["single_shift_p99"] < 100.0
    assert set(got) <= set(fusion_errors(a, f))


def _own_fix_shift(assoc, fused: pd.DataFrame) -> pd.DataFrame:
    """The fused points of one source next to their sensor's own fix: shift (m)."""
    one = fused[fused["n_sources"] == 1].drop(columns="sensor")
    own = assoc.points[["sensor", "time", "truth", "lon", "lat"]]
    m = one.rename(columns={"source": "sensor"}).merge(
        own, on=["sensor", "time", "truth"], suffixes=("", "_own")
    )
    assert len(m) == len(one)
    m["shift"] = geo.haversine_m(m["lon"], m["lat"], m["lon_own"], m["lat_own"])
    return m


@pytest.mark.parametrize("straddle", [False, True])
def test_a_sensor_seen_alone_for_minutes_keeps_its_own_fixes(straddle):
    """Sparse sensors (radar every 240 s, σ 300 m; AIS every 300 s, σ 100 m), one of them
    starting 10 min to 45 min before the other: seed 003's line through the fused part's
    last points, extrapolated backwards over the lone stretch, put lone radar fixes
    4.1 km off (MTAD two-sensor scene 0: an AIS fix 4 km off, 735 s before the fused
    part). The single sensor's points now stay within its noise of its own fixes, those
    out of reach of the blend window are its fixes, and their error against truth is
    theirs."""
    sensors = (
        simulate.SensorSpec("R1", period_s=240.0, sigma_m=300.0, coverage=0.95),
        simulate.SensorSpec("AIS", period_s=300.0, sigma_m=100.0, coverage=0.6),
    )
    df = simulate.multisensor_scene(
        seed=1, n_ships=12, area_km=60.0, duration_s=3 * 3600.0, sensors=sensors
    )
    a = associate_sensors(df)
    f = fuse(a, FuseParams(blend_straddle=straddle))
    m = _own_fix_shift(a, f)
    # One sensor starts at least 10 min before the other on most ships.
    t = time_seconds(df["time"])
    first = df.assign(t=t).groupby(["truth", "sensor"])["t"].min().unstack()
    assert ((first["AIS"] - first["R1"]).abs() >= 600).sum() >= 6
    sigma = m["sensor"].map({"R1": 300.0, "AIS": 100.0})
    assert (m["shift"] <= 2.0 * sigma).all()  # was up to 4.1 km (R1) and 283 m (AIS)
    # Points more than 2 k = 6 rows from any fused point of their track are untouched.
    g = f.groupby("batch", sort=False)
    row = g.cumcount().to_numpy()
    fused_row = np.where(f["n_sources"].to_numpy() >= 2, row, np.nan)
    nxt = pd.Series(fused_row).groupby(f["batch"].to_numpy()).bfill().to_numpy()
    prv = pd.Series(fused_row).groupby(f["batch"].to_numpy()).ffill().to_numpy()
    far = ~(np.abs(nxt - row) <= 6) & ~(np.abs(row - prv) <= 6)
    far_times = set(f.loc[far & (f["n_sources"].to_numpy() == 1), "time"])
    lone = m[m["time"].isin(far_times)]
    assert len(lone) > 20 and lone["shift"].max() < 0.05
    err = geo.haversine_m(m["lon"], m["lat"], m["true_lon"], m["true_lat"])
    own = geo.haversine_m(m["lon_own"], m["lat_own"], m["true_lon"], m["true_lat"])
    assert err.mean() <= 1.05 * own.mean()  # was 467 m against 377 m


def test_a_short_stretch_between_fused_parts_lies_between_their_offsets():
    """A gap fill: AIS silent for 700 s, the radar (250 m to the east, every 300 s) seen
    alone twice in it. Both points sit in the windows of both junctions: each moves by
    no more than the fused track's largest distance from the radar next to the stretch,
    toward the fused track (the step into the stretch shrinks)."""
    ais = observe("AIS", "1", 0, 3600, 60.0, 100.0, 1)
    t = (ais["time"] - T0).dt.total_seconds()
    ais = ais[(t <= 1200) | (t >= 1900)]
    radar = observe("R1", "2", 0, 3600, 300.0, 3.0, 2, bias=(250.0, 0.0))
    a = associate_sensors(pd.concat([ais, radar], ignore_index=True))
    f = fuse(a)
    m = _own_fix_shift(a, f)
    lone = m[m["time"].isin(T0 + pd.to_timedelta([1500, 1800], unit="s"))]
    assert len(lone) == 2
    pts, index = a.points, a.index
    radar_track = int(np.flatnonzero(index.keys["sensor"] == "R1")[0])
    both = f[f["n_sources"] >= 2]
    tb = (both["time"] - T0).dt.total_seconds().to_numpy()
    near = both[(np.abs(tb - 1200) <= 180) | (np.abs(tb - 1900) <= 180)]
    tn = time_seconds(near["time"])
    rl, ra, _ = interp_positions(pts, index, np.full(len(near), radar_track), tn)
    apart = geo.haversine_m(near["lon"], near["lat"], rl, ra).max()
    assert (lone["shift"] <= apart + 0.5).all() and (lone["shift"] > 50.0).all()
    dx, _ = geo.to_local(lone["lon"], lone["lat"], lone["lon_own"], lone["lat_own"])
    assert (dx < 0).all()  # toward the fused track, west of the radar


def test_time_base_weight_densest_union_and_the_summary_says_what_was_not_kept():
    """h168 D-fuse-1: a 1 s radar (noisy) and a 30 s AIS (quiet) of one ship. ``weight``
    fuses on the AIS's times and drops the radar's fixes between them, and the summary
    says so (sensor, interval, count, how to keep them); ``densest`` and ``union`` keep
    every radar time; ``union`` also every AIS time, one point per time."""
    from wakeline.core.pipeline import STEPS

    # (an hour: over 20 min the AIS's noise estimate is mostly the smoothing's ends)
    radar = observe("R1", "1", 0, 3600, 1.0, 30.0, 1)
    ais = observe("AIS", "2", 7, 3600, 30.0, 3.0, 2)  # at radar times: one point per time
    ais_off = observe("AIS", "2", 7.5, 3600, 30.0, 3.0, 2)  # between radar times
    df = pd.concat([radar, ais], ignore_index=True)
    a = associate_sensors(df, FuseParams())
    n_r, n_a = len(radar), len(ais)
    rep = {}
    f = fuse(a, FuseParams(), report=rep)
    assert len(f) == n_a + 30  # AIS times, and the radar's 7 s before and 23 s after AIS
    assert rep["base_fixes"] == {"AIS": n_a} and rep["base_interval_s"]["AIS"] == 30.0
    assert rep["not_kept"] == {"R1": n_r - 30 - n_a}  # radar fixes at AIS times are blended
    assert len(fuse(a, FuseParams(time_base="densest"))) == n_r
    assert len(fuse(a, FuseParams(time_base="union"))) == n_r
    df2 = pd.concat([radar, ais_off], ignore_index=True)
    a2 = associate_sensors(df2, FuseParams())
    fu = fuse(a2, FuseParams(time_base="union"))
    assert len(fu) == n_r + len(ais_off) and not fu["time"].duplicated().any()
    err = geo.haversine_m(fu["lon"], fu["lat"], fu["true_lon"], fu["true_lat"])
    r_err = geo.haversine_m(radar["lon"], radar["lat"], radar["true_lon"], radar["true_lat"])
    assert err.mean() < 0.5 * r_err.mean()  # the quiet AIS dominates the blend
    step = STEPS["fuse"]
    text = step.summary(step(df, {"fuse": FuseParams()}))
    assert f"fused on AIS's 30 s times (time_base weight): {n_r - 30 - n_a:,} R1 fixes" in text
    assert "--time-base union keeps them" in text, text
    text = step.summary(step(df, {"fuse": FuseParams(time_base="union")}))
    assert "fused on every sensor's times" in text and "not kept" not in text, text
    with pytest.raises(InputError):
        FuseParams(time_base="fastest").checked()


def test_probe_grid_from_short_intervals_is_the_whole_span_grid_filtered():
    """h168 D-fuse-2: the probes made from the fixes' short intervals are exactly those
    of every grid time over each span kept after the long-gap filter (which over ATD's
    day-long sparse tracks made 3.4 GB of probes to throw away)."""
    from wakeline.core.fuse import _probe_grid, _spans
    from wakeline.core.tracks import concat_ranges

    rng = np.random.default_rng(3)
    parts = []
    for k in range(12):  # tracks with gaps of 5 s .. 2 h
        t = np.cumsum(rng.choice([5.0, 30.0, 60.0, 700.0, 7200.0], 40)) + rng.uniform(0, 90)
        parts.append(
            pd.DataFrame(
                {
                    "sensor": f"S{k % 2}",
                    "batch": str(k),
                    "time": T0 + pd.to_timedelta(np.round(t, 1), unit="s"),
                    "lon": 122.5 + rng.normal(0, 0.01, 40),
                    "lat": 30.5 + rng.normal(0, 0.01, 40),
                }
            )
        )
    pts, index = sorted_with_index(pd.concat(parts, ignore_index=True))
    t, t0, t1 = _spans(pts, index)
    params = FuseParams()
    p = params.probe_s
    g0 = np.ceil((t0 - p / 2) / p).astype("int64")
    count = np.maximum(np.floor((t1 + p / 2) / p).astype("int64") - g0 + 1, 1)
    track = np.repeat(np.arange(index.n_tracks), count)
    grid = concat_ranges(g0, count)
    _, _, ok = interp_positions(pts, index, track, grid * p, params.max_interp_s)
    ok |= (
        (grid * p >= t0[track] - p)
        & (grid * p <= t1[track] + p)
        & ((grid * p < t0[track]) | (grid * p > t1[track]))
    )
    new_track, new_grid = _probe_grid(t, index, t0, t1, params)
    assert np.array_equal(new_track, track[ok]) and np.array_equal(new_grid, grid[ok])
    assert len(new_grid) < 0.2 * len(grid)


def _plots(sensor: str, period: float, sigma: float, seed: int) -> pd.DataFrame:
    """Two ships 150 m apart seen by one sensor, written as plots: every detection of a
    scan in one batch (as Autoferry's radar and lidar read with --map batch=scenario)."""
    one = observe(sensor, "1", 0, 600, period, sigma, seed, truth="A")
    two = observe(sensor, "1", 0, 600, period, sigma, seed + 1, truth="B", bias=(150.0, 0.0))
    return pd.concat([one, two], ignore_index=True)


def test_plots_are_fused_with_a_warning_marked_proposals_and_their_scan_interval():
    """Operator test 8, D1: fusing the Autoferry radar and lidar plots (one "track" per
    scenario holding two boats and clutter) made zig-zag tracks with several points at one
    time, said "fused on lidar's 0 s times" and showed the pairs as comfortable joins. The
    summary now says how many tracks are plots and how many fused times hold several
    points, names what to do, gives the scan interval, and marks the proposals."""
    from wakeline.core.pipeline import STEPS

    lidar = _plots("lidar", 2.0, 3.0, 1)
    radar = _plots("radar", 2.5, 20.0, 3)
    ship = observe("AIS", "9", 0, 600, 10.0, 3.0, 5, course=200.0)  # a track, paired with none
    step = STEPS["fuse"]
    res = step(pd.concat([lidar, radar, ship], ignore_index=True), {"fuse": FuseParams()})
    rep = res.report
    fused = res.tables["points"]
    props = res.tables["proposals"]
    assert rep["plot_tracks"] == 2 and rep["tracks"] == 3
    several = fused.duplicated(["batch", "time"], keep=False)
    assert several.any()  # fused and said, not silently
    assert rep["fused_shared_times"] == fused[several].drop_duplicates(["batch", "time"]).shape[0]
    assert rep["fused_times"] == fused.drop_duplicates(["batch", "time"]).shape[0]
    text = step.summary(res)
    assert "2 of the 3 tracks are plots, not tracks" in text, text
    assert f"several points at {rep['fused_shared_times']:,} of their" in text
    assert "join the plots into tracks first" in text
    assert " 0 s times" not in text
    base = next(iter(rep["base_interval_s"].values()))
    assert base in (2.0, 2.5), rep["base_interval_s"]  # the scan's, not the plots' 0 s
    assert list(props["plot_tracks"]) == ["lidar:1+radar:1"]
    # tracks of one ship each: no warning, no mark
    ok = step(
        pd.concat(
            [observe("AIS", "7", 0, 600, 6.0, 5.0, 1), observe("R1", "3", 0, 600, 10.0, 30.0, 2)]
        ),
        {"fuse": FuseParams()},
    )
    assert "plot_tracks" not in ok.report and "plots" not in step.summary(ok)
    assert list(ok.tables["proposals"]["plot_tracks"]) == [""]


def test_associate_warns_of_plots_and_marks_their_proposals():
    """Operator test 8, D1: the associate summary says nothing of plots either."""
    from wakeline.core.associate import LinkParams
    from wakeline.core.pipeline import STEPS

    first = _plots("R1", 2.0, 3.0, 1)
    first = first[first["time"] < T0 + pd.Timedelta(seconds=300)]
    later = _plots("R1", 2.0, 3.0, 1)
    later = later[later["time"] > T0 + pd.Timedelta(seconds=330)].assign(batch="2")
    step = STEPS["associate"]
    res = step(pd.concat([first, later], ignore_index=True), {"associate": LinkParams()})
    assert res.report["plot_tracks"] == 2
    assert "2 of the 2 tracks are plots, not tracks" in step.summary(res)
    props = res.tables["proposals"]
    assert len(props) == 1 and (props["plot_tracks"] == "R1:1+R1:2").all()

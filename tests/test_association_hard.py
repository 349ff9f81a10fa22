"""Issue 15: association that says "no partner", hard scenes, the papers' own options."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_associate import straight, track

from wakeline.app.cli import main
from wakeline.core import geo, simulate
from wakeline.core.associate import (
    LinkParams,
    associate_interrupted,
    pair_cost,
    pair_features,
    prediction_miss,
    stitch,
)
from wakeline.core.errors import InputError
from wakeline.core.evaluate_association import (
    cut_at_gaps,
    cut_known_gaps,
    error_breakdown,
    evaluate_real_association,
    score_association,
)
from wakeline.core.fuse import FuseParams, associate_sensors
from wakeline.core.segments import _accel, _straight_fits, chain_refit, segment_stats
from wakeline.core.transform import BsplineParams, bspline_segments, knot_vector


def noisy(df, sigma, seed):
    rng = np.random.default_rng(seed)
    x, y = geo.to_local(df["lon"].to_numpy(), df["lat"].to_numpy(), 122.5, 30.5)
    lon, lat = geo.from_local(
        x + rng.normal(0, sigma, len(df)), y + rng.normal(0, sigma, len(df)), 122.5, 30.5
    )
    return df.assign(lon=lon, lat=lat)


def test_end_noise_is_measured_per_track_and_short_pieces_have_no_motion():
    quiet = noisy(straight("1", 0, 600), 5.0, 0)
    loud = noisy(straight("2", 0, 600, start=(0, 5000)), 200.0, 1)
    single = straight("3", 0, 0, start=(0, 9000))
    seg = segment_stats(pd.concat([quiet, loud, single]))
    order = seg.index.keys["batch"].tolist()
    sd = dict(zip(order, seg.pos_sd1, strict=True))
    assert sd["1"] < 10 < 50 < sd["2"]
    motion = dict(zip(order, seg.motion1, strict=True))
    assert motion["1"] and motion["2"] and not motion["3"]
    assert np.isfinite(sd["3"])  # the sensor's median noise stands in


def turning(rate_deg_s, gap_s, speed=6.0, turn_from=520.0):
    """One ship east at ``speed`` m/s that starts a steady turn at ``turn_from`` s and
    keeps turning through a gap: piece "1" to 600 s, piece "2" from 600 + ``gap_s``."""
    t = np.arange(0.0, 1501.0)
    turn = np.where(t >= turn_from, np.radians(rate_deg_s), 0.0)
    heading = np.radians(90.0) + np.cumsum(turn)
    x, y = np.cumsum(speed * np.sin(heading)), np.cumsum(speed * np.cos(heading))
    a = (t <= 600) & (t % 10 == 0)
    b = (t >= 600 + gap_s) & (t % 10 == 0)
    return pd.concat(
        [track("1", t[a], x[a], y[a], truth="A"), track("2", t[b], x[b], y[b], truth="A")]
    )


def test_an_end_shows_the_acceleration_its_fixes_carry_beyond_their_noise():
    # A turn of 0.3 deg/s at 6 m/s (0.031 m/s² towards the centre) over the last 80 s.
    seg = segment_stats(turning(0.3, 240.0))
    assert 0.02 < seg.accel1[0] < 0.04 and 0.02 < seg.accel0[1] < 0.04  # end of 1, start of 2
    assert seg.accel0[0] == 0.0  # piece 1 starts straight
    # Straight tracks in noise: an acceleration shows at about 1 % of the ends (the test's
    # level), not more; with 3 fixes nothing can show.
    rng = np.random.default_rng(5)
    tracks = [
        noisy(straight(str(k), 0, 90, speed=rng.uniform(2, 10), start=(0, 3000 * k)), 30.0, k)
        for k in range(1000)
    ]
    seg = segment_stats(pd.concat([*tracks, straight("short", 0, 20, start=(0, -5000))]))
    assert (seg.accel1 > 0).mean() <= 0.02 and (seg.accel0 > 0).mean() <= 0.02
    assert seg.accel1[list(seg.index.keys["batch"]).index("short")] == 0.0


@pytest.mark.parametrize("fixes", [4, 5, 7, 10, 25, 40])
def test_the_acceleration_test_holds_its_level_for_any_number_of_fixes(fixes):
    # The noise is estimated from the same residuals: the statistic is 2·F(2, 2(n − 3)),
    # not χ²₂ (9.21 gave 18 % false alarms at 4 fixes, 3 % at 10). Uneven times, ends
    # shorter than the span; 20,000 straight ends in 30 m noise.
    rng = np.random.default_rng(fixes)
    n = 20000
    tt = np.sort(rng.uniform(0, 10 * fixes, (n, fixes)), axis=1) - 10 * fixes
    x = 5 * tt + rng.normal(0, 30, (n, fixes))
    y = -3 * tt + rng.normal(0, 30, (n, fixes))
    valid = np.ones((n, fixes), dtype=bool)
    if fixes >= 10:  # ends of fewer fixes than the span (a prefix, as _end_rows gives)
        valid = np.arange(fixes) < rng.integers(fixes // 2, fixes + 1, n)[:, None]
    rate = (_accel(x, y, tt, valid) > 0).mean()
    assert 0.006 < rate < 0.014
    # A copied fix adds no evidence: 5 instants each twice are tested as 5.
    dup = np.repeat(np.arange(0.0, 50.0, 10.0) - 40.0, 2) * np.ones((n, 1))
    xy = [np.repeat(rng.normal(0, 3, (n, 5)), 2, axis=1) for _ in range(2)]
    assert 0.006 < (_accel(*xy, dup, np.ones((n, 10), dtype=bool)) > 0).mean() < 0.014
    # Fixes at two instants: a quadratic of rounding noise only, never an acceleration.
    two = np.where(np.arange(fixes) < fixes // 2, -7.1, 0.0) * np.ones((n, 1))
    assert not (_accel(x, y, two, np.ones((n, fixes), dtype=bool)) > 0).any()


def test_an_end_is_fitted_over_as_many_fixes_as_its_straight_run_allows():
    # 60 fixes at 10 s in 30 m noise: straight (40 fixes fitted at both ends); turning
    # 0.5 deg/s over its last 150 s (the end keeps 10, the start takes 40); 8 fixes (all 8).
    steady = noisy(straight("1", 0, 590, speed=7.0, course=60.0), 30.0, 3)
    t = np.arange(0.0, 591.0, 10.0)
    heading = np.radians(60.0) + np.radians(0.5) * np.clip(t - 440.0, 0.0, None)
    step = np.diff(t, prepend=0.0)
    x, y = np.cumsum(7.0 * step * np.sin(heading)), np.cumsum(7.0 * step * np.cos(heading))
    bend = noisy(track("2", t, x, y + 8000.0), 30.0, 4)
    short = noisy(straight("3", 0, 70, start=(0, -8000)), 30.0, 5)
    df = pd.concat([steady, bend, short])
    seg = segment_stats(df)
    lon, lat = seg.points["lon"].to_numpy(), seg.points["lat"].to_numpy()
    t_s = (seg.points["time"].astype("int64").to_numpy() / 1e9).astype("float64")
    widths = [_straight_fits(lon, lat, t_s, seg.index, 10, 40, head)[1] for head in (True, False)]
    assert widths[0].tolist() == [40, 40, 8] and widths[1].tolist() == [40, 10, 8]
    # The longer fit knows the steady ship's velocity about (40 / 10)^1.5 = 8x better.
    longer = segment_stats(df, end_points_max=40)
    assert longer.vel_sd1[0] < seg.vel_sd1[0] / 4
    assert longer.vel_sd1[1] == seg.vel_sd1[1] and longer.vel_sd1[2] == seg.vel_sd1[2]


def test_longer_end_fits_join_more_in_crowded_hard_scenes():
    # Measured (seeds 0-1 tuning, 5-6 held out, docs/evaluation.md): very dense P_CA
    # 0.681 / 0.664 -> 0.778 / 0.755 at lower P_FA. Here seeds 11-12 of the very dense class
    # (0.692 / 0.193 -> 0.762 / 0.140 and 0.691 / 0.224 -> 0.774 / 0.159).
    got = []
    for seed in (11, 12):
        df = simulate.segments_scene(seed=seed, n_ships=250, area_km=20.0, sigma_m=60.0, hard=True)
        got.append(
            [
                score_association(associate_interrupted(df, LinkParams(end_points_max=k)))
                for k in (10, 40)
            ]
        )
    for short, long in got:
        assert long["p_ca"] > short["p_ca"] + 0.03 and long["p_fa"] <= short["p_fa"] + 0.01


def test_a_ship_seen_turning_keeps_the_wider_gate_across_the_gap():
    # Turning at 0.3 deg/s through a 240 s gap: the dead-reckoned end misses by ~400 m,
    # far beyond ½·accel_ms2·gap² (29 m); the turn the old end shows widens the gate.
    df = turning(0.3, 240.0)
    joined = associate_interrupted(df)
    assert joined.pair_table()[["batch_a", "batch_b"]].values.tolist() == [["1", "2"]]
    assert len(associate_interrupted(df, LinkParams(measured_accel=False)).chosen) == 0


def test_a_loose_end_stays_loose_next_to_another_ship():
    # Ship A ends heading east; 300 s later ship B appears 500 m north of where A would be,
    # sailing the opposite way. Reachable, and near; not the same ship.
    a = straight("1", 0, 600, speed=6.0, course=90.0, truth="A")
    t = np.arange(900, 1501, 10.0)
    b = track("2", t, 6.0 * 900 - 6.0 * (t - 900), np.full(len(t), 500.0), truth="B")
    assoc = associate_interrupted(pd.concat([a, b]))
    assert len(assoc.pairs) == 1 and len(assoc.chosen) == 0
    # ... while its true continuation, 1 m/s faster after the gap, is joined.
    c = straight("3", 900, 1500, speed=6.5, course=90.0, truth="A")
    assoc = associate_interrupted(pd.concat([a, c]))
    assert assoc.pair_table()[["batch_a", "batch_b"]].values.tolist() == [["1", "3"]]


def test_a_wider_prediction_pays_its_spread_against_the_tightest_plausible_rival():
    # Ship A ends at 600 s heading east. Its next piece starts 100 s later; another
    # ship starts 600 s later 150 m off A's prediction (plausible: half a minute's worth
    # of unknown acceleration); a third start 50 s later lies 2 km off (implausible).
    a = noisy(straight("1", 0, 600, course=90.0, truth="A"), 5.0, 0)
    p = noisy(straight("2", 700, 1300, course=90.0, truth="A"), 5.0, 1)
    q = noisy(straight("3", 1200, 1800, course=90.0, start=(0.0, 150.0), truth="B"), 5.0, 2)
    far = noisy(straight("4", 650, 1250, course=90.0, start=(0.0, 2000.0), truth="C"), 5.0, 3)
    seg = segment_stats(pd.concat([a, p, q, far]))
    k = {b: n for n, b in enumerate(seg.index.keys["batch"])}
    i = np.array([k["1"], k["1"], k["1"]])
    j = np.array([k["2"], k["3"], k["4"]])
    pairs = pair_features(seg, i, j)
    on = pair_cost(pairs, LinkParams(), "scaled", seg)
    off = pair_cost(pairs, LinkParams(log_sigma=0.0), "scaled", seg)
    _, sigma, _ = prediction_miss(seg, pairs, LinkParams())
    assert on[0] == pytest.approx(off[0])  # the tightest plausible pays nothing
    assert off[1] < LinkParams().no_join and off[2] > LinkParams().gate  # 2 km in 50 s
    share = 0.5  # alpha's part of the weights when course and speed are known
    assert on[1] - off[1] == pytest.approx(share * 0.5 * np.log(sigma[1] / sigma[0]))
    assert sigma[2] < sigma[0]  # tighter, but it cannot be the ship: (1, 2) paid nothing
    # A lone candidate pays nothing however long its gap.
    alone = pair_features(seg, i[1:2], j[1:2])
    assert pair_cost(alone, LinkParams(), "scaled", seg)[0] == pytest.approx(off[1])


def test_the_spread_is_taken_on_the_new_start_side_too():
    # Start 3 continues ship B's piece 5 after 100 s; ship A's end 1 reaches it only
    # after 600 s. End 1 has no other candidate: it pays against start 3's tighter one.
    a = noisy(straight("1", 0, 600, course=90.0, truth="A"), 5.0, 0)
    five = noisy(straight("5", 500, 1100, course=90.0, start=(0.0, 150.0), truth="B"), 5.0, 4)
    q = noisy(straight("3", 1200, 1800, course=90.0, start=(0.0, 150.0), truth="B"), 5.0, 2)
    seg = segment_stats(pd.concat([a, five, q]))
    k = {b: n for n, b in enumerate(seg.index.keys["batch"])}
    pairs = pair_features(seg, np.array([k["1"], k["5"]]), np.array([k["3"], k["3"]]))
    on = pair_cost(pairs, LinkParams(), "scaled", seg)
    off = pair_cost(pairs, LinkParams(log_sigma=0.0), "scaled", seg)
    _, sigma, _ = prediction_miss(seg, pairs, LinkParams())
    assert off[0] < LinkParams().no_join and on[1] == pytest.approx(off[1])
    assert on[0] - off[0] == pytest.approx(0.5 * 0.5 * np.log(sigma[0] / sigma[1]))


def test_a_rejected_pair_shapes_no_other_pair_in_the_second_look():
    # A's pieces 1 and 2 lie 1800 s apart (a second-look join); X starts at 1's prediction
    # 200 s after it and turns away. Rejecting (1, X) must leave what the scene without X
    # gives: the rejected pair is no reference for the spread of 1's other candidates.
    one = straight("1", 0, 600, course=90.0, truth="A")
    two = straight("2", 2400, 3000, course=90.0, start=(0.0, 6000.0), truth="A")
    x = straight("X", 800, 3000, course=0.0, start=(4800.0, -4800.0), truth="B")
    alone = associate_interrupted(pd.concat([one, two])).pair_table()
    assoc = associate_interrupted(pd.concat([one, two, x]))
    assert assoc.pair_table()[["batch_a", "batch_b"]].values.tolist() == [["1", "X"]]
    keys = assoc.segments.index.keys["batch"].astype(str).tolist()
    n = len(keys)
    redone = assoc.without(np.array([keys.index("1") * n + keys.index("X")])).pair_table()
    assert redone[["batch_a", "batch_b"]].values.tolist() == [["1", "2"]]
    assert redone["cost"].iloc[0] == pytest.approx(alone["cost"].iloc[0])


def test_every_stored_cost_is_the_pair_cost_of_the_candidates_returned():
    # Long (second-look) pairs included: their spread is taken among the first pass's
    # candidates and the long ones looked at, as pair_cost over all returned gives it.
    df = simulate.segments_scene(seed=12, n_ships=60, area_km=4.0, sigma_m=20.0, hard=True)
    params = LinkParams()
    a = associate_interrupted(df, params)
    assert a.long_joins().sum() > 5
    fresh = pair_features(a.segments, a.pairs.i, a.pairs.j)
    np.testing.assert_allclose(a.cost, pair_cost(fresh, params, "scaled", a.segments))


def test_without_the_uncertainty_gate_there_is_no_spread_term():
    # The fixed tolerance of v1 has no σ: log_sigma changes nothing, the second look
    # included (it once failed there for want of σ).
    df = simulate.segments_scene(seed=12, n_ships=60, area_km=4.0, sigma_m=20.0, hard=True)
    a = associate_interrupted(df, LinkParams(uncertainty_gate=False))
    b = associate_interrupted(df, LinkParams(uncertainty_gate=False, log_sigma=0.0))
    assert a.long_joins().sum() > 0
    np.testing.assert_array_equal(a.chosen, b.chosen)
    np.testing.assert_allclose(a.cost, b.cost)


def test_the_spread_term_helps_on_hard_harbour_scenes():
    # Held out from the choice of log_sigma (seeds 0-1 and MTAD's tuning half chose it):
    # on every seed more true pairs, and no more wrong joins on the mean. With the second
    # look's margin of session 15 for moving pieces (0.1) the second look finds more of
    # the long pairs either way, so the spread term's lead is smaller there (+0.022 to
    # +0.042 against +0.076 to +0.141 with one margin of 0.25 for all). Pinned with the
    # hard T_gap it was chosen with (soft_gap_s=0): with the soft T_gap of session 16 the
    # first pass joins most of those long pairs itself and the lead shrinks to 0.000 to
    # +0.023 (margin 0.1), and its P_FA is 0.059 against 0.044 (docs/evaluation.md).
    ships, area, sigma = 60, 4.0, 20.0
    for margin, lead in ((0.25, 0.03), (LinkParams().long_margin_moving, 0.015)):
        on, off = [], []
        base = LinkParams(long_margin_moving=margin, soft_gap_s=0.0)
        for seed in (11, 12, 13):
            df = simulate.segments_scene(
                seed=seed, n_ships=ships, area_km=area, sigma_m=sigma, hard=True
            )
            on.append(score_association(associate_interrupted(df, base)))
            off.append(score_association(associate_interrupted(df, base.replace(log_sigma=0.0))))
        assert all(a["p_ca"] > b["p_ca"] + lead for a, b in zip(on, off, strict=True))
        assert np.mean([a["p_fa"] for a in on]) <= np.mean([b["p_fa"] for b in off]) + 0.01


def test_margin_test_refuses_a_coin_toss():
    # One end, two simultaneous starts equally far either side of the prediction.
    a = straight("1", 0, 600, speed=6.0, course=90.0, truth="A")
    x0 = 6.0 * 900
    left = straight("2", 900, 1500, speed=6.0, course=90.0, start=(x0 - 5400, 150.0), truth="B")
    right = straight("3", 900, 1500, speed=6.0, course=90.0, start=(x0 - 5400, -150.0), truth="C")
    df = pd.concat([a, left, right])
    assert len(associate_interrupted(df).chosen) == 0
    assert len(associate_interrupted(df, LinkParams(margin=0.0)).chosen) == 1


def test_one_point_piece_between_two_pieces_is_threaded_in():
    a = straight("1", 0, 600, truth="A")
    p = straight("2", 800, 800, truth="A")
    b = straight("3", 1000, 1600, truth="A")
    sc = score_association(associate_interrupted(pd.concat([a, p, b])))
    assert sc["p_ca"] == 1.0 and sc["p_fa"] == 0.0


def test_hard_scene_has_what_the_easy_one_lacks():
    easy = simulate.segments_scene(seed=3, n_ships=15, area_km=10.0)
    hard = simulate.segments_scene(seed=3, n_ships=15, area_km=10.0, hard=True)
    assert not easy["truth"].str.startswith("clutter").any()
    clutter = hard[hard["truth"].str.startswith("clutter")]
    assert clutter["batch"].nunique() == round(0.3 * 15)
    assert clutter.groupby("batch").size().between(3, 15).all()
    ships = hard[~hard["truth"].str.startswith("clutter")]
    t = (ships["time"] - ships["time"].min()).dt.total_seconds().to_numpy()
    steps = ships.assign(t=t).sort_values(["batch", "t"]).groupby("batch")["t"].diff().dropna()
    assert (steps > 15).mean() > 0.05  # missed scans (10 s period)
    # Gaps between pieces of one ship reach beyond the 720 s default limit.
    spans = ships.assign(t=t).groupby(["truth", "batch"])["t"].agg(["min", "max"]).reset_index()
    spans = spans.sort_values(["truth", "min"])
    gaps = spans.groupby("truth")["min"].shift(-1) - spans["max"]
    assert (gaps > LinkParams().max_gap_s).any()
    # Speed changes: the true path is not at constant speed for some ship.
    assert easy["truth"].nunique() == 15


def test_hard_multisensor_scene_and_split_radar_tracks_pair_with_one_ais_track():
    df = simulate.multisensor_scene(seed=2, n_ships=12, area_km=20.0, hard=True)
    per_ship = df.groupby("truth")["sensor"].unique()
    assert (per_ship.map(len) == 1).any()  # ships without AIS (and clutter)
    # One ship, AIS whole, radar split into two batches with a 60 s gap.
    ais = straight("A1", 0, 1200, period=6.0, truth="S").assign(sensor="AIS")
    r1 = straight("R1a", 0, 500, truth="S").assign(sensor="R1")
    r2 = straight("R1b", 560, 1200, truth="S").assign(sensor="R1")
    assoc = associate_sensors(pd.concat([ais, r1, r2]))
    assert len(assoc.chosen) == 2 and len(set(assoc.target_of_track)) == 1
    strict = associate_sensors(pd.concat([ais, r1, r2]), FuseParams(pieces=False))
    assert len(strict.chosen) == 1
    whole = associate_sensors(pd.concat([ais, r1, r2]), distance="dtw_whole")
    assert len(whole.chosen) >= 1


def test_line_fill_follows_a_straight_track_and_bad_fill_is_refused():
    df = noisy(
        pd.concat([straight("1", 0, 600, truth="A"), straight("2", 900, 1500, truth="A")]), 20.0, 4
    )
    assoc = associate_interrupted(df)
    for fill in ("line", "hermite"):
        out = stitch(assoc, fill=fill)
        f = out[out["interpolated"]]
        t = (f["time"] - pd.Timestamp("2024-05-01T00:00:00Z")).dt.total_seconds().to_numpy()
        x, y = geo.to_local(f["lon"].to_numpy(), f["lat"].to_numpy(), 122.5, 30.5)
        err = np.hypot(x - 6.0 * np.sin(np.radians(45)) * t, y - 6.0 * np.cos(np.radians(45)) * t)
        assert len(f) == 29 and err.mean() < 40, fill
    with pytest.raises(InputError, match="unknown gap fill"):
        stitch(assoc, fill="spline")


def test_knot_vector_is_clamped_and_beats_raw_noise():
    t = np.arange(20.0)
    k = knot_vector(t)
    assert (k[:4] == 0).all() and (k[-4:] == 19).all() and len(k) == 8 + 20 // 4 - 1
    df = simulate.segments_scene(seed=5, n_ships=4, area_km=10.0, sigma_m=40.0)
    out = bspline_segments(df, BsplineParams(enabled=True))
    o = out[out["interpolated"] == 0]
    fit = geo.haversine_m(o["lon"], o["lat"], o["true_lon"], o["true_lat"]).mean()
    raw = geo.haversine_m(df["lon"], df["lat"], df["true_lon"], df["true_lat"]).mean()
    assert fit < 0.8 * raw


def test_real_evaluation_on_a_folder_and_its_errors(tmp_path, capsys):
    df = simulate.segments_scene(seed=1, n_ships=6, area_km=20.0, pieces=(1, 1))
    df.drop(columns=["truth", "true_lon", "true_lat"]).to_csv(tmp_path / "a.csv", index=False)
    (tmp_path / "notes.txt").write_text("not a track file")
    ev = evaluate_real_association(tmp_path, cut_s=60.0, methods=("ours, optimal",))
    assert ev.table["pieces"].iloc[0] == df["batch"].nunique()  # no gaps: nothing cut
    assert "ours, optimal" in ev.format()
    assert [f for f, _ in ev.skipped] == ["notes.txt"]  # read since h111, no track in it
    assert main(["evaluate", "associate", "--real", str(tmp_path), "--cut-s", "60"]) == 0
    assert "P_CA" in capsys.readouterr().out
    assert main(["evaluate", "associate", "--real", str(tmp_path / "none")]) == 2
    assert "no such file or folder" in capsys.readouterr().err
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["evaluate", "associate", "--real", str(empty)]) == 2
    assert "no track files in this folder" in capsys.readouterr().err


@settings(max_examples=40, deadline=None)
@given(
    spans=st.lists(st.integers(1, 40), min_size=1, max_size=6),
    step=st.sampled_from([1.0, 10.0, 30.0, 1800.0]),
    lo=st.floats(0.0, 3000.0),
    width=st.floats(0.0, 3000.0),
    seed=st.integers(0, 2**16),
    own_truth=st.booleans(),
)
def test_known_gap_cut_loses_one_window_per_track_and_nothing_else(
    spans, step, lo, width, seed, own_truth
):
    # Each track either stays whole or loses the fixes of one window of [lo, lo + width]
    # s, at least 120 s from its ends: two pieces of one track, the fixes between them
    # exactly the window's, every other fix where it was; each piece one track's; the
    # pieces renumbered. Input shuffled; a truth column already there is kept.
    hi = lo + width
    rows = [
        (f"s{k}", pd.Timestamp("2024-05-01", tz="UTC") + pd.Timedelta(seconds=step * m), k, m)
        for k, n in enumerate(spans)
        for m in range(n)
    ]
    df = pd.DataFrame(rows, columns=["batch", "time", "k", "m"])
    df = df.assign(sensor="AIS", lon=10.0 + 0.01 * df["k"], lat=55.0 + 1e-4 * df["m"])
    if own_truth:
        df["truth"] = "ship-" + df["batch"]
    df = df.sample(frac=1.0, random_state=seed % 1000).reset_index(drop=True)
    out = cut_known_gaps(df, lo, hi, seed=seed)
    name = {b: ("ship-" + b if own_truth else b) for b in df["batch"]}
    assert (out.groupby("batch")["truth"].nunique() == 1).all()  # a piece is one track's
    # Every fix kept is an input fix of its truth's track, unchanged.
    back = out.merge(df, on=["k", "m"], suffixes=("", "_in"))
    assert len(back) == len(out)
    assert (back["truth"] == back["batch_in"].map(name)).all()
    assert (back["lon"] == back["lon_in"]).all() and (back["lat"] == back["lat_in"]).all()
    assert (back["time"] == back["time_in"]).all()
    assert not set(out["batch"]) & set(df["batch"])  # renumbered
    cut = 0
    for b, whole in df.groupby("batch"):
        part = out[out["truth"] == name[b]]
        pieces = part.groupby("batch")["time"].agg(["min", "max", "size"]).sort_values("min")
        assert len(pieces) in (1, 2)
        assert part["time"].is_unique
        if len(pieces) == 1:
            assert len(part) == len(whole)
            continue
        cut += 1
        first, second = pieces.iloc[0], pieces.iloc[1]
        gap = (second["min"] - first["max"]).total_seconds()
        assert gap >= lo
        assert gap <= hi + 2 * step + 1e-6
        lost = whole[(whole["time"] > first["max"]) & (whole["time"] < second["min"])]
        assert len(part) + len(lost) == len(whole)
        span = (whole["time"].max() - whole["time"].min()).total_seconds()
        assert span >= lo + 240 - 1e-6
    assert out["batch"].nunique() == len(spans) + cut


@settings(max_examples=40, deadline=None)
@given(
    spans=st.lists(st.integers(1, 300), min_size=1, max_size=5),
    step=st.sampled_from([1.0, 10.0, 60.0, 360.0]),
    silent=st.lists(st.integers(0, 299), max_size=4),
    lo=st.floats(0.0, 600.0),
    width=st.floats(0.0, 600.0),
    every=st.floats(900.0, 5000.0),
    seed=st.integers(0, 2**16),
)
def test_known_gaps_every_span_are_known_and_lose_nothing_else(
    spans, step, silent, lo, width, every, seed
):
    # One window per `every` s of each track: each piece one track's, every fix kept is an
    # input fix, the fixes lost are exactly those between consecutive pieces, and every
    # gap between consecutive pieces is known: at least lo, at most hi + 2 median steps
    # (tracks with a silence of 20 steps at some fixes: no window is made across it; fixes
    # 360 s apart: two windows with no fix between them would make one unknown gap, found
    # by the review).
    hi = lo + width
    rows = []
    for k, n in enumerate(spans):
        t = step * np.arange(n, dtype=float)
        for m in silent:
            t[m % n :] += 20 * step if m % n else 0.0
        rows += [(f"s{k}", t[m], k, m) for m in range(n)]
    df = pd.DataFrame(rows, columns=["batch", "sec", "k", "m"])
    df["time"] = pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(df["sec"], unit="s")
    df = df.assign(sensor="AIS", lon=10.0 + 0.01 * df["k"], lat=55.0 + 1e-4 * df["m"])
    df = df.sample(frac=1.0, random_state=seed % 1000).reset_index(drop=True)
    out = cut_known_gaps(df, lo, hi, seed=seed, every_s=every)
    assert (out.groupby("batch")["truth"].nunique() == 1).all()
    back = out.merge(df, on=["k", "m"], suffixes=("", "_in"))
    assert len(back) == len(out)
    assert (back["truth"] == back["batch_in"]).all()
    assert (back["time"] == back["time_in"]).all() and (back["lon"] == back["lon_in"]).all()
    for b, whole in df.groupby("batch"):
        part = out[out["truth"] == b]
        pieces = part.groupby("batch")["sec"].agg(["min", "max", "size"]).sort_values("min")
        assert (pieces["min"].to_numpy()[1:] > pieces["max"].to_numpy()[:-1]).all()
        gaps = pieces["min"].to_numpy()[1:] - pieces["max"].to_numpy()[:-1]
        median = np.median(np.diff(np.sort(whole["sec"].to_numpy()))) if len(whole) > 1 else 0
        assert (gaps >= lo - 1e-6).all() and (gaps <= hi + 2 * median + 1e-6).all()
        lost = len(whole) - len(part)
        between = sum(
            ((whole["sec"] > a) & (whole["sec"] < c)).sum()
            for a, c in zip(
                pieces["max"].to_numpy()[:-1], pieces["min"].to_numpy()[1:], strict=True
            )
        )
        assert lost == between
        span = whole["sec"].max() - whole["sec"].min()
        assert len(pieces) <= int(span // every) + 2


def test_known_gap_cut_keeps_tracks_of_two_sensors_apart():
    # Batch 7 of R1 and batch 7 of R2 are two ships (found by the review: one truth).
    t0 = pd.Timestamp("2024-05-01", tz="UTC")
    rows = [
        (s, "7", t0 + pd.Timedelta(seconds=off + 10.0 * m), 10.0 + 0.1 * k, 55.0)
        for k, (s, off) in enumerate((("R1", 0.0), ("R2", 5.0)))
        for m in range(200)
    ]
    df = pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"])
    for out in (cut_known_gaps(df, 300.0, 600.0), cut_at_gaps(df.iloc[::2], 5.0)):
        assert out.groupby(["sensor", "batch"])["truth"].first().nunique() == 2


def test_known_gap_cut_on_the_command_line(tmp_path, capsys):
    df = simulate.segments_scene(seed=1, n_ships=6, area_km=20.0, pieces=(1, 1))
    df.drop(columns=["truth", "true_lon", "true_lat"]).to_csv(tmp_path / "a.csv", index=False)
    ev = evaluate_real_association(tmp_path, gaps=(60.0, 120.0), methods=("ours, optimal",))
    assert ev.table["pieces"].iloc[0] > df["batch"].nunique()
    assert ev.table["true_pairs"].iloc[0] == ev.table["pieces"].iloc[0] - df["batch"].nunique()
    assert "known gaps" in ev.format()
    assert main(["evaluate", "associate", "--real", str(tmp_path), "--gaps", "60", "120"]) == 0
    assert "60-120 s of fixes" in capsys.readouterr().out
    assert main(["evaluate", "associate", "--real", str(tmp_path), "--gaps-every", "600"]) == 2
    assert "--gaps-every needs --gaps" in capsys.readouterr().err
    args = ["evaluate", "associate", "--real", str(tmp_path), "--gaps", "60", "120"]
    assert main([*args, "--gaps-every", "1800"]) == 0
    assert "each cut every 1800 s by removing 60-120 s of fixes" in capsys.readouterr().out
    with pytest.raises(ValueError, match="lo <= hi"):
        cut_known_gaps(df, 120.0, 60.0)


def test_error_breakdown_names_each_wrong_join_and_miss():
    # A ends; its true continuation A2 starts 300 s later; a loose clutter piece C sits on
    # A's path. Force every join through the open gates and read the breakdown.
    a = straight("1", 0, 600, speed=6.0, course=90.0, truth="A")
    a2 = straight("2", 900, 1500, speed=6.0, course=90.0, start=(5400.0, 0.0), truth="A")
    c = straight("3", 700, 800, speed=6.0, course=90.0, start=(4200.0, 0.0), truth="C")
    df = pd.concat([a, a2, c])
    assoc = associate_interrupted(df)
    counts = error_breakdown(assoc)
    assert set(counts) == {
        "wrong_skip",
        "wrong_loose",
        "wrong_swap",
        "miss_not_candidate",
        "miss_taken",
        "miss_left_loose",
    }
    out = {tuple(r) for r in assoc.pair_table()[["batch_a", "batch_b"]].values.tolist()}
    wrong = len(out - {("1", "2")})
    assert counts["wrong_loose"] + counts["wrong_skip"] + counts["wrong_swap"] == wrong
    assert counts["wrong_loose"] == len(out & {("1", "3"), ("3", "2")})
    missed = int(("1", "2") not in out)
    assert counts["miss_taken"] + counts["miss_left_loose"] + counts["miss_not_candidate"] == missed


def test_real_evaluation_reports_the_mtad_halves_apart(tmp_path):
    for name, seed in (("Scene-0.csv", 1), ("Scene-6.csv", 2), ("Scene-3.csv", 3)):
        df = simulate.segments_scene(seed=seed, n_ships=4, area_km=10.0, pieces=(2, 2))
        df = df.assign(batch=df["truth"])  # whole tracks with real gaps, cut by the test
        df.drop(columns=["truth", "true_lon", "true_lat"]).to_csv(tmp_path / name, index=False)
    ev = evaluate_real_association(tmp_path, cut_s=15.0, methods=("ours, optimal",))
    text = ev.format()
    assert "MTAD tuning half (Scene-0.csv, Scene-6.csv)" in text
    assert "held-out half" not in text  # one file of that half: no mean printed
    assert "wrong_skip" in text and "miss_left_loose" in text


def _lane(name, y, seed):
    """A ship sailing east at 6 m/s at north offset ``y``: a long piece, two single fixes
    200 s apart, a long piece (10 m noise)."""
    parts = [
        straight(f"{name}1", 0, 600, course=90.0, start=(0, y), truth=name),
        straight(f"{name}s1", 800, 800, course=90.0, start=(0, y), truth=name),
        straight(f"{name}s2", 1000, 1000, course=90.0, start=(0, y), truth=name),
        straight(f"{name}2", 1200, 1800, course=90.0, start=(0, y), truth=name),
    ]
    return noisy(pd.concat(parts), 10.0, seed)


def test_chain_evidence_threads_single_fixes_of_two_neighbouring_ships():
    # Two ships 1.2 km apart each leave two single fixes between their long pieces. Pair
    # by pair, a single fix to a single fix has no motion on either side: without
    # blind_order all four such pairs cost the same, and the margin test refuses the tie
    # or the solver crosses them. With the chain pass each single fix borrows the motion
    # of the piece it was joined to, and only the true pairs stay cheap; blind_order
    # alone (the slower of the four, 6 m/s against 8.5 m/s across) also finds them.
    missed = 0
    for seed in range(3):
        df = pd.concat([_lane("A", 0.0, seed), _lane("B", 1200.0, seed + 10)])
        chained = score_association(associate_interrupted(df))
        assert chained["p_ca"] == 1.0 and chained["p_fa"] == 0.0
        flat = LinkParams(chain_passes=0, blind_order=0.0)
        single = score_association(associate_interrupted(df, flat))
        missed += single["p_ca"] < 1.0
        ordered = score_association(associate_interrupted(df, LinkParams(chain_passes=0)))
        assert ordered["p_ca"] == 1.0 and ordered["p_fa"] == 0.0
    assert missed == 3


def test_chain_refit_borrows_motion_only_where_it_is_better():
    df = pd.concat([_lane("A", 0.0, 0), noisy(straight("L", 0, 1800, start=(0, 5000)), 10.0, 1)])
    seg = segment_stats(df)
    names = seg.index.keys["batch"].tolist()
    k = {b: names.index(b) for b in names}
    chain = np.arange(len(seg))
    for b in ("As1", "As2", "A2"):
        chain[k[b]] = chain[k["A1"]]
    new, changed = chain_refit(seg, chain, 10, accel_ms2=0.001, drift_ms=1.0)
    # The single fixes had no motion; now they carry the lane's 6 m/s east at both ends
    # (the end from their predecessors, the start from their successors).
    assert not seg.motion1[k["As1"]] and not seg.motion0[k["As2"]]
    for b in ("As1", "As2"):
        for vx, vy in ((new.vx0, new.vy0), (new.vx1, new.vy1)):
            assert abs(vx[k[b]] - 6.0) < 0.5 and abs(vy[k[b]]) < 0.5
    # Long pieces, and a track in a chain of its own, keep their own fits.
    assert changed[k["As1"]] and changed[k["As2"]]
    assert not changed[k["L"]] and new.vx1[k["L"]] == seg.vx1[k["L"]]
    assert new.vx1[k["A1"]] == seg.vx1[k["A1"]] and new.vx0[k["A2"]] == seg.vx0[k["A2"]]
    # Borrowed motion is trusted less than the lane's own: its error grows with the gap.
    assert new.vel_sd1[k["As1"]] > seg.vel_sd1[k["A1"]]


def test_chain_passes_keep_every_pair_priced_on_the_summaries_returned():
    # Only the pairs touching a refitted piece are re-priced; whatever the number of
    # passes, every pair's features and cost must be those of the final summaries.
    df = pd.concat([_lane("A", 0.0, 3), _lane("B", 1200.0, 4), _lane("C", 2500.0, 5)])
    for passes in (1, 2, 3):
        params = LinkParams(chain_passes=passes)
        a = associate_interrupted(df, params)
        fresh = pair_features(a.segments, a.pairs.i, a.pairs.j)
        for f in ("gap_s", "dist_m", "miss_m", "dcourse_deg", "dspeed_kn"):
            np.testing.assert_allclose(getattr(a.pairs, f), getattr(fresh, f))
        np.testing.assert_allclose(a.cost, pair_cost(fresh, params, "scaled", a.segments))


def test_moving_pieces_need_a_smaller_second_look_margin():
    """Session 15: across a gap beyond T_gap, two pieces both seen moving are joined when
    each is the other's cheapest by long_margin_moving (0.1) instead of long_margin (0.25).
    On hard harbour scenes not used to choose it: more true pairs on every seed, wrong
    joins no more than 0.01 higher on the mean (chosen on MTAD's tuning half cut at known
    gaps of 300-900 s and hard seeds 0-1; ATD's 30-min posits at rest keep 0.25).
    Pinned with the hard T_gap it was chosen with; with the soft T_gap of session 16 (the
    first pass joins most pairs up to 1,200 s itself) the lead is smaller (0.000 to +0.031
    against +0.028 to +0.038; P_FA +0.006 on the mean) and never negative."""
    for soft, lead in ((0.0, 0.02), (LinkParams().soft_gap_s, -1e-9)):
        on, off = [], []
        for seed in (21, 22, 23):
            df = simulate.segments_scene(
                seed=seed, n_ships=60, area_km=4.0, sigma_m=20.0, hard=True
            )
            base = LinkParams(soft_gap_s=soft)
            on.append(score_association(associate_interrupted(df, base)))
            off.append(
                score_association(associate_interrupted(df, base.replace(long_margin_moving=0.25)))
            )
        assert all(a["p_ca"] > b["p_ca"] + lead for a, b in zip(on, off, strict=True))
        assert np.mean([a["p_fa"] for a in on]) <= np.mean([b["p_fa"] for b in off]) + 0.01

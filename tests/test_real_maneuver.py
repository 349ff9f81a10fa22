"""Real AIS (Saronic Gulf, GPL, read from ../shared): our detector against the annotator's
CHANGE_IN_HEADING labels. The labels are another algorithm's output (5-10 deg thresholds),
not truth: we report agreement with default parameters and check it is sane, no tuning."""

import numpy as np
import pandas as pd
import pytest

from conftest import real_file
from wakeline.core.evaluate import match_turns
from wakeline.core.io import read_points
from wakeline.core.maneuver import detect
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import sort_points

pytestmark = pytest.mark.real


@pytest.mark.parametrize("vessel", [1, 3])
def test_agreement_with_annotated_heading_changes(vessel):
    pts = sort_points(
        read_points(real_file("greece-ais-annotated", f"vessel_{vessel}_id_annotated.csv")).points
    )
    t = time_seconds(pts["time"])
    # cut the track at its real gaps (the annotator's GAP_PERIOD, 600 s)
    pts["batch"] = pts["batch"] + "/" + np.cumsum(np.r_[0, np.diff(t) > 600]).astype(str)
    result = detect(pts)
    p = result.points
    labelled = p["annotation"].str.contains("CHANGE_IN_HEADING").to_numpy()
    moving = (
        pd.to_numeric(p["speed"], errors="coerce").to_numpy() >= 2.0
    )  # headings at rest are noise
    scores = match_turns(
        result.is_maneuver & moving, labelled & moving, result.index.track_of_row, tol=2
    )
    print(
        f"vessel {vessel}: {int((result.is_maneuver & moving).sum())} detections, "
        f"{int((labelled & moving).sum())} labels, {scores}"
    )
    assert scores["precision"] >= 0.9  # what we call a turn, the annotator calls one too
    assert scores["recall"] >= 0.3  # it labels every 5-10 deg change; we look for >= 15 deg


# --- issue 15: goals on real sets, default parameters (autoferry scenarios 2-6 were used to
# choose the 10 s window; 13-22 were looked at while tuning since 2026-12-03, the blind check
# is the lidar; the AIS sets were not tuned on) ---------------------------------------------


def _real(folder: str):
    from wakeline.core.evaluate_real import evaluate_real

    ev = evaluate_real(real_file(folder))
    print(ev.format())
    return ev.rows.set_index("method")


def test_real_ais_ships_at_rest_make_no_maneuvers():
    rows = _real("greece-ais-annotated")
    assert rows.loc["ours", "slow_share"] <= 0.05  # measured 0.000 (0.011 before max_step_windows)
    assert rows.loc["paper", "slow_share"] > 0.5  # the issue: 64-83 % on moored ships
    # on this harbour/port traffic the compressor keeps fewer points than DP at its Dis_e
    assert rows.loc["ours", "ours_kept"] <= rows.loc["ours", "dp_kept"]


@pytest.mark.parametrize("rate_s", [180.0, 600.0])
def test_saronic_ferry_decimated_makes_no_turns_across_its_hours_in_port(rate_s):
    # vessel 2, the fast ferry, has AIS gaps of 45-62 min in port; decimated to 180 s or
    # 600 s (the first fix at or after each tick, as bench/sampling_sweep.py) the heading
    # window before the first fix after a gap spanned the hour: reversals with a slow chord
    # (slow share 0.179 / 0.231 without the cut, docs/evaluation.md "Sampling-rate sweep")
    from wakeline.core import real_sets
    from wakeline.core.evaluate_real import slow_share
    from wakeline.core.maneuver import ManeuverParams, median_interval_s

    pts = real_sets.read_greece(real_file("greece-ais-annotated"))
    ferry = pts[pts["batch"] == "2"].sort_values("time").reset_index(drop=True)
    t = time_seconds(ferry["time"])
    rows = np.unique(np.searchsorted(t, np.arange(t[0], t[-1] + 1.0, rate_s)))
    ferry = ferry.iloc[rows[rows < len(t)]].reset_index(drop=True)
    ours = detect(ferry)
    spanned = detect(ferry, ManeuverParams(max_step_windows=0))
    assert slow_share(spanned) > 0.1  # measured 0.179 / 0.231
    assert slow_share(ours) == 0.0
    assert ours.is_maneuver.sum() >= 0.8 * spanned.is_maneuver.sum()  # 24 / 28, 19 / 13
    # no window of a maneuver point holds a step beyond the reach (4 x max(180 s, median))
    t = time_seconds(ours.points["time"])
    reach = 4 * max(180.0, float(median_interval_s(t, ours.index)[0]))
    p = int(ours.window_p[0])  # 5 points at every scale at this sampling
    for r in np.flatnonzero(ours.is_maneuver):
        assert np.diff(t[r - p + 1 : r + p]).max() <= reach


def test_real_radar_turns_against_gnss_truth():
    rows = _real("autoferry-fusion")
    # measured on exclusive radar tracks, GNSS jumps not scored: precision 0.90, recall 0.86
    # (tuning 2-6: 0.95 / 1.00; scenarios 13-22: 0.83 / 0.71; before session 27's slow_side
    # default 0.90 / 0.79 and 13-22 0.82 / 0.57). Issue goal 0.8 / 0.7: met on every split
    # (13-22 by one turn: 5 of 7), see docs/evaluation.md.
    assert rows.loc["ours", "precision"] >= 0.8
    assert rows.loc["ours", "recall"] >= 0.8
    assert rows.loc["ours, scenarios 13-22", "precision"] >= 0.8
    assert rows.loc["ours, scenarios 13-22", "recall"] >= 0.7
    assert rows.loc["ours", "ours_kept"] <= rows.loc["ours", "dp_kept"]


def test_one_gnss_jump_in_the_autoferry_truth():
    # scenario 6, target 1 jumps 3.2 m in 0.12 s at 2 m/s: its +33/-16 deg "turns" are the
    # jump; no other track of the set has a step beyond 0.4 m
    from wakeline.core import real_sets
    from wakeline.core.evaluate_real import gnss_faults

    _, truth = real_sets.read_autoferry(real_file("autoferry-fusion"))
    faults = gnss_faults(truth)
    assert set(faults["batch"]) == {"6/1"}
    assert faults["t_s"].max() - faults["t_s"].min() < 2.0


def test_autoferry_exclusive_tracks_share_no_plot():
    from wakeline.core import real_sets

    plain, _ = real_sets.read_autoferry(real_file("autoferry-fusion"))
    excl, _ = real_sets.read_autoferry(real_file("autoferry-fusion"), exclusive=True)
    key = ["time", "lon", "lat"]
    assert plain.duplicated(key).sum() > 0  # two targets given one merged plot
    assert excl.duplicated(key).sum() == 0
    assert len(excl) >= 0.95 * len(plain)


def test_real_harbour_traffic_compresses_no_worse_than_douglas_peucker():
    # issue 15: the DMA ship's harbour manoeuvring kept 88 points where DP needed 56 at the
    # same Dis_e; the synchronized error bound fixes it (measured: 120 vs 150 at 9.3 m)
    rows = _real("dma-single-ship")
    assert rows.loc["ours", "ours_kept"] <= rows.loc["ours", "dp_kept"]
    assert rows.loc["ours", "slow_share"] <= 0.05


def test_autoferry_lidar_tracks():
    # the lidar (never used before) with the radar's 15 m gate and exclusive rule: the same
    # 18 target tracks, one return per scan every 0.504 s (radar 1.68 s), measured 2,099
    # returns against the radar's 1,009; no return serves two targets
    from wakeline.core import real_sets
    from wakeline.core.schema import time_seconds

    lidar, _ = real_sets.read_autoferry(
        real_file("autoferry-fusion"), exclusive=True, sensor="lidar"
    )
    assert set(lidar["sensor"]) == {"lidar"} and lidar["batch"].nunique() == 18
    assert 2000 <= len(lidar) <= 2200
    assert lidar.duplicated(["time", "lon", "lat"]).sum() == 0
    t, b = time_seconds(lidar["time"]), lidar["batch"].to_numpy()
    assert abs(np.median(np.diff(t)[b[1:] == b[:-1]]) - 0.504) < 0.01


def test_radar_turn_option_meets_the_goal_on_both_splits():
    # docs/evaluation.md "Radar turns: every scenario a tuning scenario": 5-point windows on
    # radar (8 s) with the noise floor over a window (10 s); windows 8 ... 256 s and 320 s
    # (the default max_window_s). Measured: all 24 detections 0.96 / 0.93; 2-6 1.00 / 1.00;
    # 13-22 0.89 / 0.86 (default 13-22: 0.82 / 0.57). An option, not the default: the
    # recalibrated synthetic radar loses 2.3-3.4 recall points in 3 of 4 seeds (h79).
    from wakeline.core.evaluate_real import evaluate_real
    from wakeline.core.maneuver import ManeuverParams

    option = ManeuverParams(window_s=8.0, noise_lag_s=10.0)
    rows = evaluate_real(real_file("autoferry-fusion"), option).rows.set_index("method")
    for split in ("ours, tuning 2-6", "ours, scenarios 13-22"):
        assert rows.loc[split, "precision"] >= 0.8, split
        assert rows.loc[split, "recall"] >= 0.7, split
    lidar = evaluate_real(real_file("autoferry-fusion"), option, sensor="lidar")
    lidar = lidar.rows.set_index("method")  # measured 0.78 / 1.00 (default 0.80 / 1.00)
    assert lidar.loc["ours", "precision"] >= 0.75 and lidar.loc["ours", "recall"] == 1.0


def test_radar_at_slower_scans_window_max_s_option():
    # docs/evaluation.md "Radar at slower scans (h131)": the Autoferry radar decimated to one
    # plot every 5 s (5.04 s steps), scored against its GNSS as a plain file. Measured:
    # default 1.00 / 0.43 (10 detections, 14 turns); window_max_s 20 0.89 / 0.64 (18). An
    # option, not the default: it failed its pre-set blind lidar guard (5 s: 1.00 -> 0.91).
    # Against the defaults before session 31 (the slow-scan pair off), as it was measured.
    import importlib.util
    import tempfile
    from pathlib import Path

    from conftest import REPO
    from wakeline.core import real_sets
    from wakeline.core.io import write_points
    from wakeline.core.maneuver import ManeuverParams

    folder = real_file("autoferry-fusion")
    spec = importlib.util.spec_from_file_location(
        "_bench_scan_rates", REPO / "bench" / "radar_scan_rates.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    pts, truth = real_sets.read_autoferry(folder, exclusive=True, sensor="radar")
    plots = bench.decimate(pts, 5.0)
    off = ManeuverParams(radius_s=0.0, edge_s=0.0, step_noise_max=0.0)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_points(truth, tmp / "gnss.csv")
        before = bench.score(plots, tmp / "gnss.csv", off, tmp)
        after = bench.score(plots, tmp / "gnss.csv", off.replace(window_max_s=20.0), tmp)
        own = bench.score(pts, tmp / "gnss.csv", off.replace(window_max_s=20.0), tmp)
    assert before["R"] < 0.5 and after["R"] >= 0.6  # one turn in 14 is 0.07
    assert after["P"] >= 0.85
    assert (own["P"], own["R"]) == pytest.approx((0.903, 0.857), abs=0.001)  # as the default


def test_radar_at_slower_scans_radius_s_edge_s_by_default():
    # docs/evaluation.md "Radar at slower scans (h162)", "Session 31: slow scans, gated": the
    # Autoferry radar decimated to 4 and 5 s, scored against its GNSS as a plain file.
    # Measured: the pair off (the defaults before session 31) 0.92 / 0.46 (12 detections, 13
    # turns) and 1.00 / 0.43 (10, 14); radius_s 15 + edge_s 12 on every track 0.90 / 0.92 (21)
    # and 0.88 / 0.79 (17); the defaults since session 31 (the pair where the noise per
    # step's run is under 0.15, docs/prereg/session31_slow_scans_b.md) 0.94 / 0.92 (18) and
    # 0.93 / 0.79 (15): goal 2a at 4-5 s scans by default.
    import importlib.util
    import tempfile
    from pathlib import Path

    from conftest import REPO
    from wakeline.core import real_sets
    from wakeline.core.io import write_points
    from wakeline.core.maneuver import ManeuverParams

    folder = real_file("autoferry-fusion")
    spec = importlib.util.spec_from_file_location(
        "_bench_scan_rates_h162", REPO / "bench" / "radar_scan_rates.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    pts, truth = real_sets.read_autoferry(folder, exclusive=True, sensor="radar")
    off = ManeuverParams(radius_s=0.0, edge_s=0.0, step_noise_max=0.0)
    ungated = off.replace(radius_s=15.0, edge_s=12.0)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_points(truth, tmp / "gnss.csv")
        for rate in (4.0, 5.0):
            plots = bench.decimate(pts, rate)
            before = bench.score(plots, tmp / "gnss.csv", off, tmp)
            after = bench.score(plots, tmp / "gnss.csv", ungated, tmp)
            default = bench.score(plots, tmp / "gnss.csv", ManeuverParams(), tmp)
            assert before["R"] < 0.5 and after["R"] >= 0.75  # one turn in 14 is 0.07
            assert after["P"] >= 0.85
            assert default["R"] == after["R"] and default["P"] >= 0.9  # 2a: >= 0.7 at >= 0.8
        own = bench.score(pts, tmp / "gnss.csv", ManeuverParams(), tmp)
        own_off = bench.score(pts, tmp / "gnss.csv", off, tmp)
    assert (own["P"], own["R"]) == pytest.approx((0.903, 0.857), abs=0.001)
    assert (own["P"], own["R"]) == (own_off["P"], own_off["R"])  # own rate: as before

"""Seed 000's detection limit in the parameter panel: numbers for tracks, a reason for
radar plots (points sharing times) and for batches whose speed is no ship's."""

import math

import numpy as np
import pandas as pd
import pytest

from wakeline.core import geo
from wakeline.core.maneuver import (
    detection_limit,
    largest_tolerable_error_m,
    smallest_detectable_turn_deg,
)
from wakeline.core.tracks import track_summary

T0 = pd.Timestamp("2024-05-01T08:00:00Z")


def _ships(n_ships: int = 12, n_scans: int = 60, dt: float = 10.0, kn: float = 12.0):
    """Ships on straight lines; one row per ship and scan (times exactly shared)."""
    rows = []
    v = kn * geo.KN_MS
    for s in range(n_ships):
        lat0, lon0 = 59.0 + 0.05 * s, 10.0 + 0.03 * s
        for k in range(n_scans):
            north = v * dt * k
            rows.append((s, k, T0 + pd.Timedelta(seconds=dt * k), lon0, lat0 + north / 111_195.0))
    return pd.DataFrame(rows, columns=["ship", "scan", "time", "lon", "lat"])


def _points(df: pd.DataFrame, batch: pd.Series) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "sensor": "S1",
            "batch": batch.astype(str),
            "time": df["time"],
            "lon": df["lon"],
            "lat": df["lat"],
            "speed": np.nan,
            "course": np.nan,
        }
    )


def test_tracks_give_the_seed_000_numbers():
    df = _ships()
    limit = detection_limit(track_summary(_points(df, df["ship"])), 5, 15.0)
    assert limit.reason is None
    assert limit.speed_kn == pytest.approx(12.0, rel=1e-3)
    assert limit.interval_s == pytest.approx(10.0)
    assert limit.leg_s == pytest.approx(50.0)
    assert limit.eps_m == pytest.approx(largest_tolerable_error_m(15.0, limit.speed_kn, 50.0))
    assert limit.turn_deg == pytest.approx(
        smallest_detectable_turn_deg(100.0, limit.speed_kn, 50.0)
    )


def test_the_interval_and_window_are_the_detectors_own():
    """The panel's figure was each track's mean interval (a gap stretched it: MTAD
    Scene-35 read 58 s where its steps are ~30 s and the Statistics dock said 31 s), and
    its legs were window_p points, though the detector takes window_s seconds of points
    (10 s of 1 s radar: 10 points, not 5)."""
    df = _ships(dt=1.0, n_scans=600)
    df = df[(df["scan"] < 200) | (df["scan"] >= 400)]  # a 200 s gap in every track
    summary = track_summary(_points(df, df["ship"]))
    assert (summary["interval_s"] == 1.0).all()
    limit = detection_limit(summary, 5, 15.0, window_s=10.0)
    assert limit.interval_s == pytest.approx(1.0)  # was (599 s / 399 steps) 1.5 s
    assert limit.window_p == 10 and limit.leg_s == pytest.approx(10.0)
    sparse = _ships(dt=60.0)  # 60 s plots: 10 s is under one step, window_p points
    limit = detection_limit(track_summary(_points(sparse, sparse["ship"])), 5, 15.0, window_s=10.0)
    assert limit.window_p == 5 and limit.leg_s == pytest.approx(300.0)
    # window_max_s (off by default): as many points as fit in 20 s where 3 do (5 s plots:
    # 4, 6 s plots: 3); 60 s plots keep window_p
    for dt, p in ((5.0, 4), (6.0, 3)):
        slow = _ships(dt=dt)
        limit = detection_limit(
            track_summary(_points(slow, slow["ship"])), 5, 15.0, window_s=10.0, window_max_s=20.0
        )
        assert limit.window_p == p and limit.leg_s == pytest.approx(p * dt)
    limit = detection_limit(
        track_summary(_points(sparse, sparse["ship"])), 5, 15.0, window_s=10.0, window_max_s=20.0
    )
    assert limit.window_p == 5


@pytest.mark.parametrize("jitter_s", [0.0, 0.05])
def test_radar_plots_one_batch_per_scan_give_a_reason_not_numbers(jitter_s):
    """Tester: the Autoferry radar written one batch per scan showed "median speed
    1440.9 kn, interval 0 s" as the detection limit."""
    df = _ships()
    df["time"] = df["time"] + pd.to_timedelta(df["ship"] * jitter_s, unit="s")
    limit = detection_limit(track_summary(_points(df, df["scan"])), 5, 15.0)
    assert limit.reason is not None and "points share times" in limit.reason
    assert "plots" in limit.reason
    assert math.isnan(limit.eps_m) and math.isnan(limit.turn_deg)


def test_batches_holding_several_ships_give_a_reason():
    """Each batch alternates between two ships 5 km apart every 10 s: ~970 kn."""
    df = _ships(n_ships=2)
    df = df[(df["scan"] % 2) == df["ship"]].copy()  # scan k: ship k % 2
    limit = detection_limit(track_summary(_points(df, pd.Series(0, index=df.index))), 5, 15.0)
    assert limit.reason is not None and "no ship's" in limit.reason
    assert limit.speed_kn > 100


def test_nothing_to_judge():
    assert (
        detection_limit(
            track_summary(_points(_ships().iloc[:0], pd.Series([], dtype=int))), 5, 15.0
        )
        is None
    )
    one = _ships().iloc[:1]
    assert detection_limit(track_summary(_points(one, one["ship"])), 5, 15.0) is None


def test_the_panel_says_why(qtbot):
    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    df = _ships()
    panel.show_guidance(track_summary(_points(df, df["scan"])))
    text = panel.guidance.text()
    assert "points share times" in text and "kn" not in text.split(":")[0]
    assert "1440" not in text and "interval 0 s" not in text
    panel.show_guidance(track_summary(_points(df, df["ship"])))
    assert "median speed 12.0 kn, interval 10 s" in panel.guidance.text()


def test_the_panel_follows_the_window_it_is_given(qtbot):
    """The guidance was computed once per layer: a new window_s or threshold left it
    describing windows the detector no longer takes."""
    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    df = _ships(dt=1.0, n_scans=300)
    panel.show_guidance(track_summary(_points(df, df["ship"])))
    # the paper's window in the tooltip, the operator's words in the text (h225 item 13)
    assert "legs of p = 10 points (10 s)" in panel.guidance.toolTip()
    assert panel.guidance.text().startswith("Smallest turn found for this data: ")
    assert "p = " not in panel.guidance.text() and "seed" not in panel.guidance.text()
    assert panel.from_dict({"maneuver": {"window_s": 20.0}}) == []
    assert "legs of p = 20 points (20 s)" in panel.guidance.toolTip()


def test_repeated_rows_are_no_evidence_of_plots():
    """Tester h133 (item 9): Autoferry's GNSS truth repeats each fix once per radar scan
    (same id, time and position); its two tracks were called "radar plots (one batch per
    scan)". A row repeating an earlier one is not counted, and says so."""
    df = _ships(dt=1.0, n_scans=120)
    thrice = pd.concat([df, df, df]).sort_values(["ship", "scan"], kind="stable")
    summary = track_summary(_points(thrice, thrice["ship"]))
    assert (summary["repeats"] == 2 * 120).all()
    limit = detection_limit(summary, 5, 15.0)
    assert limit.reason is None and limit.repeats == 12 * 240
    assert limit.interval_s == pytest.approx(1.0) and limit.speed_kn == pytest.approx(12.0, 1e-3)
    # Radar plots written twice are still radar plots.
    plots = pd.concat([df, df])
    limit = detection_limit(track_summary(_points(plots, plots["scan"])), 5, 15.0)
    assert limit.reason is not None and "points share times" in limit.reason


def test_fast_tracks_with_gaps_are_tracks():
    """GNSS at 10 Hz (Autoferry's truth: steps of 0.08-0.2 s) with gaps between runs: the
    median step (0.1 s) is the interval, not a sign of plots."""
    df = _ships(n_ships=2, dt=0.1, n_scans=2000, kn=6.0)
    df = df[(df["scan"] % 500) < 100]  # 10 s runs, 40 s gaps
    summary = track_summary(_points(df, df["ship"]))
    limit = detection_limit(summary, 5, 15.0)
    assert limit.reason is None
    assert limit.interval_s == pytest.approx(0.1)


def test_the_panel_names_fast_intervals_and_repeats(qtbot):
    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    df = _ships(n_ships=2, dt=0.1, n_scans=2000, kn=6.0)
    df = df[(df["scan"] % 500) < 100]
    twice = pd.concat([df, df.iloc[:7]]).sort_values(["ship", "scan"], kind="stable")
    panel.show_guidance(track_summary(_points(twice, twice["ship"])))
    text = panel.guidance.text()
    assert "interval 0.1 s" in text and "plots" not in text
    assert "7 rows repeat an earlier row of their track" in text


def _runs_over_days(repeat: int = 1):
    """Two boats seen at 10 Hz in 100 s runs at 6 kn, one run a day (as Autoferry's GNSS
    truth read as one track per target: 2 days of 79-152 s scenarios), each fix written
    ``repeat`` times (the truth repeats a fix once per radar scan)."""
    runs = []
    for day in range(3):
        run = _ships(n_ships=2, dt=0.1, n_scans=1000, kn=6.0)
        run["time"] = run["time"] + pd.Timedelta(days=day)
        run["lat"] = run["lat"] + 0.01 * day  # each run starts where the boat is that day
        runs.append(run)
    df = pd.concat(runs * repeat).sort_values(["ship", "time"], kind="stable")
    return df.reset_index(drop=True)


def test_tracks_spanning_days_give_the_speed_between_their_gaps_and_say_so():
    """Operator test 8, D5: the guidance on Autoferry's truth (2 tracks of 2 days, 17,852
    repeated rows) said "median speed 0.1 kn" and "position errors up to 0 m": the speed
    was taken over the days between the runs."""
    df = _runs_over_days(repeat=2)
    summary = track_summary(_points(df, df["ship"]))
    assert (summary["gap_s"] > 0.9 * summary["duration_s"]).all()
    limit = detection_limit(summary, 5, 15.0, window_s=10.0)
    assert limit.reason is None and limit.repeats == 2 * 3000
    assert limit.speed_kn == pytest.approx(6.0, rel=1e-3)  # was 0.01 kn over the days
    assert limit.gap_tracks == 2 and limit.tracks == 2
    assert limit.gap_span_s == pytest.approx(2 * 86400 + 99.9, abs=1.0)
    assert limit.gap_share > 0.99
    # one run: no gaps, nothing said
    one = df[df["time"] < T0 + pd.Timedelta(hours=1)]
    limit = detection_limit(track_summary(_points(one, one["ship"])), 5, 15.0)
    assert limit.gap_tracks == 0 and limit.speed_kn == pytest.approx(6.0, rel=1e-3)


def test_the_panel_says_the_tracks_span_days_and_promises_no_turn_at_0_m(qtbot):
    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    df = _runs_over_days(repeat=2)
    panel.show_guidance(track_summary(_points(df, df["ship"])))
    text = panel.guidance.text()
    assert "median speed 6.0 kn" in text, text
    assert "2 of 2 tracks span 48.0 h, 100% of it in long gaps" in text, text
    assert "6,000 rows repeat an earlier row" in text
    # 0.5 kn, 0.1 s fixes, 10 s legs: no error of 1 m or more lets a 15° turn through
    slow = _ships(n_ships=2, dt=0.1, n_scans=1000, kn=0.5)
    panel.show_guidance(track_summary(_points(slow, slow["ship"])))
    text = panel.guidance.text()
    assert "up to 0 m" not in text and "only from position errors under 1 m" in text, text


def test_plot_like_is_per_track_and_spares_tracks_with_a_few_shared_times():
    """One test of plots (core.tracks.plot_like) for the guidance, fusion, association
    and the review: a batch holding two ships at every scan is plots; a ship's track is
    not, even with some fixes sharing a time stamp (AIS repeats a time stamp)."""
    from wakeline.core.tracks import plot_like

    df = _ships(n_ships=2, dt=10.0, n_scans=60)
    scenario = pd.Series("all", index=df.index)
    assert plot_like(track_summary(_points(df, scenario))).tolist() == [True]
    assert plot_like(track_summary(_points(df, df["ship"]))).tolist() == [False, False]
    one = df[df["ship"] == 0].copy()
    stamps = one["time"].copy()
    stamps.iloc[1:10:2] = stamps.iloc[0:9:2].to_numpy()  # 5 of 60 fixes share a stamp
    one["time"] = stamps
    assert plot_like(track_summary(_points(one, one["ship"]))).tolist() == [False]
    limit = detection_limit(track_summary(_points(df, scenario)), 5, 15.0)
    assert limit.reason is not None and "hold several positions at one time" in limit.reason
    # a short AIS track with two fixes stamped alike (review h216): 2 of 3 or 4 rows share
    for n in (3, 4):
        short = one.iloc[:n].copy()
        short["time"] = short["time"].iloc[[0, 0, *range(2, n)]].to_numpy()
        assert plot_like(track_summary(_points(short, short["ship"]))).tolist() == [False]

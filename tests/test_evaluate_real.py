"""The radar-turn evaluation's truth (core/evaluate_real.py) on synthetic GNSS tracks."""

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.evaluate_real import gnss_faults, score_turns, sound_turns, truth_turns


def _gnss(course_of_t, duration_s=120.0, rate_hz=8.0, speed_ms=2.5, noise_m=0.03, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(0, duration_s, 1 / rate_hz)
    c = np.radians(course_of_t(t))
    dt = 1 / rate_hz
    x = np.cumsum(speed_ms * np.sin(c) * dt) + rng.normal(0, noise_m, len(t))
    y = np.cumsum(speed_ms * np.cos(c) * dt) + rng.normal(0, noise_m, len(t))
    return t, x, y


def _table(t, x, y, batch="6/1"):
    lon, lat = geo.from_local(x, y, 10.4, 63.44)
    return pd.DataFrame(
        {
            "sensor": "gnss",
            "batch": batch,
            "time": pd.to_datetime(t, unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )


def test_a_gnss_jump_is_a_fault_not_a_turn():
    # straight at 2.5 m/s; at 60 s the fix jumps 3.5 m sideways within one 0.12 s step
    # (as scenario 6, target 1 does): the course over 2 s swings > 15 deg and back
    t, x, y = _gnss(lambda t: np.full_like(t, 60.0))
    jumped = x - 3.5 * np.cos(np.radians(60.0)) * (t >= 60.0)
    jumped_y = y + 3.5 * np.sin(np.radians(60.0)) * (t >= 60.0)
    truth = _table(t, jumped, jumped_y)
    turns = truth_turns(truth)
    assert len(turns) >= 1  # the jump looks like a turn to the course rule
    faults = gnss_faults(truth)
    assert len(faults) >= 1
    assert np.all(np.abs(faults["t_s"] - 60.0) < 0.5)
    assert sound_turns(turns, faults, 2.0).empty
    # a detection next to it is not counted wrong (the turn stays in the truth for precision)
    det = pd.DataFrame({"batch": ["6/1"], "t_s": [61.0]})
    assert score_turns(det, turns, 10.0, sound_turns(turns, faults, 2.0))["precision"] == 1.0


def test_a_real_turn_with_sound_gnss_is_scored():
    t, x, y = _gnss(lambda t: 60.0 + 40.0 * np.clip((t - 50.0) / 10.0, 0, 1), seed=1)
    truth = _table(t, x, y)
    turns = truth_turns(truth)
    assert len(turns) == 1 and 35 <= turns["change_deg"].iloc[0] <= 45
    assert gnss_faults(truth).empty
    assert len(sound_turns(turns, gnss_faults(truth), 2.0)) == 1


def test_any_track_file_or_folder_is_scored_without_turn_truth(tmp_path):
    """`evaluate maneuver --real` took only the four sets it knows ("no known real set" on
    MTAD's scenes or an ATD file); any track file or folder of them now gets the scores that
    need no truth. Two files reusing the same batch ids stay two tracks each."""
    from wakeline.core import simulate
    from wakeline.core.evaluate_real import evaluate_real
    from wakeline.core.io import write_points

    scene = simulate.segments_scene(seed=2, n_ships=3, area_km=10.0)
    (tmp_path / "sets").mkdir()
    for k in range(2):
        write_points(scene, tmp_path / "sets" / f"scene-{k}.csv")
    one = evaluate_real(tmp_path / "sets" / "scene-0.csv").rows.set_index("method")
    both = evaluate_real(tmp_path / "sets").rows.set_index("method")
    assert set(one.index) == {"ours", "paper"}
    assert both.loc["ours", "points"] == 2 * one.loc["ours", "points"]
    assert both.loc["ours", "maneuvers"] == 2 * one.loc["ours", "maneuvers"]
    for col in ("slow_share", "ours_kept", "dp_kept", "at_rest_spans"):
        assert col in one.columns
    assert one.loc["ours", "ours_kept"] <= one.loc["ours", "points"]


def test_hard_scene_scoring_tolerance_per_track_and_unseen_turns():
    """Hard maneuver scenes (core/evaluate.py): the match tolerance is per track (2 periods,
    at least 10 s: 60 s on 30 s AIS), and a turn inside a gap is not scored for recall."""
    from wakeline.core.evaluate import observable_turns

    turns = pd.DataFrame(
        {
            "batch": ["ais", "radar", "radar", "radar"],
            "start_s": [1000.0, 1000.0, 2000.0, 3000.0],
            "end_s": [1010.0, 1010.0, 2005.0, 3100.0],
            "change_deg": [40.0, 40.0, 60.0, 10.0],
            "speed_kn": [8.0, 8.0, 8.0, 8.0],
        }
    )
    tol = pd.Series({"ais": 60.0, "radar": 10.0})
    det = pd.DataFrame({"batch": ["ais", "radar"], "t_s": [1050.0, 1050.0]})
    s = score_turns(det, turns, tol, turns.iloc[:2])
    assert s["precision"] == 0.5 and s["recall"] == 0.5  # 40 s late: right on AIS only
    # radar plots every 1.5 s, none from 1900 s to 2100 s: the turn at 2000 s is unseen
    t = np.arange(0.0, 4000.0, 1.5)
    t = t[(t < 1900.0) | (t > 2100.0)]
    ais = np.arange(0.0, 4000.0, 30.0)
    points = pd.concat([_table(t, t * 0, t, "radar"), _table(ais, ais * 0, ais, "ais")])
    seen = observable_turns(turns, points, tol, threshold_deg=15.0)
    # the turn in the gap and the 10° one are not scored; the others are
    assert sorted(seen["start_s"]) == [1000.0, 1000.0]


def test_observable_turns_does_not_see_a_neighbouring_tracks_samples():
    """A turn's search window reaching before the scene's first time (or after its last)
    must not fall among the previous (next) batch's keys: batch "b" starts at 50 s, so its
    turn from 5 s has no sample before it even though batch "a" samples from 0 s; a turn
    ending at "b"'s last sample has none after it, though "c" samples from 0 s."""
    from wakeline.core.evaluate import observable_turns

    ta, tb = np.arange(0.0, 1001.0), np.arange(50.0, 1001.0)
    points = pd.concat(
        [_table(ta, ta * 0, ta, "a"), _table(tb, tb * 0, tb, "b"), _table(ta, ta * 0, ta, "c")]
    )
    turns = pd.DataFrame(
        {
            "batch": ["b", "b", "b"],
            "start_s": [5.0, 995.0, 500.0],
            "end_s": [60.0, 1000.5, 520.0],
            "change_deg": [90.0, 90.0, 90.0],
            "speed_kn": [10.0, 10.0, 10.0],
        }
    )
    tol = pd.Series({"a": 10.0, "b": 10.0, "c": 10.0})
    seen = observable_turns(turns, points, tol, 15.0)
    assert list(seen["start_s"]) == [500.0]
    # each batch alone: the same answer
    alone = observable_turns(turns, points[points["batch"] == "b"], tol, 15.0)
    assert list(alone["start_s"]) == [500.0]

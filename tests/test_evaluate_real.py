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

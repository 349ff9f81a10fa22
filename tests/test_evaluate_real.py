"""The radar-turn evaluation's truth (core/evaluate_real.py) on synthetic GNSS tracks."""

import numpy as np
import pandas as pd
import pytest

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
    # goal 1's count beside its share (session 30): the share is the count over maneuvers
    for method in ("ours", "paper"):
        count, total = both.loc[method, "slow_maneuvers"], both.loc[method, "maneuvers"]
        assert 0 <= count <= total
        assert both.loc[method, "slow_share"] == pytest.approx(count / max(total, 1))


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


def _autoferry_folder(folder, seed=0):
    """A two-target Autoferry-like set: GNSS at 5 Hz, radar plots every 1.68 s (one per
    target and clutter), lidar every 0.5 s with three returns per hull (0.3, 1.5 and 4 m
    from the GNSS position) and clutter 40 m off; measurements relative to the ferry."""
    rng = np.random.default_rng(seed)
    folder.mkdir()
    t_truth = np.arange(0.0, 60.0, 0.2)
    pos = {
        1: (100.0 + 2.0 * t_truth, 50.0 + 0 * t_truth),
        2: (20.0 + 0 * t_truth, 200.0 - 1.5 * t_truth),
    }
    truth = pd.concat(
        pd.DataFrame(
            {
                "scenario": 2,
                "scan": np.arange(len(t_truth)),
                "target_id": k,
                "time": 1.6e9 + t_truth,
                "north": n,
                "east": e,
                "down": 0.0,
            }
        )
        for k, (n, e) in pos.items()
    )
    truth.to_csv(folder / "ground_truth.csv.gz", index=False)
    own = (5.0, -3.0)
    rows = []
    for sensor, dt, offsets in (("radar", 1.68, (0.5,)), ("lidar", 0.5, (0.3, 1.5, 4.0))):
        for scan, t in enumerate(np.arange(0.1, 59.0, dt)):
            for n, e in pos.values():
                gn, ge = np.interp(t, t_truth, n), np.interp(t, t_truth, e)
                for off in rng.permutation(offsets):  # returns in no particular order
                    rows.append((2, scan, 1.6e9 + t, sensor, gn + off - own[0], ge - own[1]))
            rows.append((2, scan, 1.6e9 + t, sensor, 300.0, 300.0))  # clutter
    det = pd.DataFrame(
        rows, columns=["scenario", "scan", "time", "sensor", "meas_north", "meas_east"]
    )
    det = det.assign(
        own_north=own[0],
        own_east=own[1],
        sensor_id=det["sensor"].map({"lidar": 1, "radar": 2}),
        k=0,
        bearing_rad=np.nan,
    )
    det.to_csv(folder / "detections.csv.gz", index=False)
    return pos


def test_autoferry_lidar_tracks_keep_the_nearest_return_per_scan(tmp_path):
    """`read_autoferry(sensor="lidar")` (before: radar only) makes tracks of the lidar's
    returns with the radar's gate and rules: one return per target and scan (the nearest
    to its GNSS position: 0.3 m here, of three), 0.5 s apart, its sensor named lidar."""
    import pytest

    from wakeline.core import real_sets
    from wakeline.core.errors import InputError

    folder = tmp_path / "autoferry"
    _autoferry_folder(folder)
    radar, truth = real_sets.read_autoferry(folder, exclusive=True)
    lidar, truth2 = real_sets.read_autoferry(folder, exclusive=True, sensor="lidar")
    assert set(radar["sensor"]) == {"radar"} and set(lidar["sensor"]) == {"lidar"}
    assert truth.equals(truth2)
    assert set(lidar["batch"]) == {"2/1", "2/2"}
    for pts, dt in ((radar, 1.68), (lidar, 0.5)):
        for _, g in pts.groupby("batch"):
            steps = np.diff(time_seconds_of(g))
            assert np.allclose(steps, dt, atol=1e-3)  # one plot per scan, clutter gated out
    # the kept lidar return is the 0.3 m one: positions 0.3 m north of the GNSS track
    g = lidar[lidar["batch"] == "2/1"]
    x, y = geo.to_local(
        g["lon"].to_numpy(), g["lat"].to_numpy(), real_sets.PIREN_LON, real_sets.PIREN_LAT
    )
    t = time_seconds_of(g) - 1.6e9
    assert np.allclose(y - (100.0 + 2.0 * t), 0.3, atol=0.02)
    assert np.allclose(x, 50.0, atol=0.02)
    with pytest.raises(InputError, match="position sensors"):
        real_sets.read_autoferry(folder, sensor="eo")


def test_evaluate_real_scores_the_autoferry_lidar(tmp_path):
    """`evaluate_real(..., sensor="lidar")` scores the lidar tracks (straight targets: no
    truth turn, no detection), names the sensor, and refuses lidar on a set without one."""
    import pytest

    from wakeline.core.errors import InputError
    from wakeline.core.evaluate_real import evaluate_real

    folder = tmp_path / "autoferry"
    _autoferry_folder(folder)
    radar = evaluate_real(folder)
    lidar = evaluate_real(folder, sensor="lidar")
    assert "lidar" in lidar.name and "lidar" not in radar.name
    rows = lidar.rows.set_index("method")
    assert rows.loc["ours", "points"] > 3 * radar.rows.set_index("method").loc["ours", "points"]
    assert rows.loc["ours", "turns"] == 0 and rows.loc["ours", "detections"] == 0
    (tmp_path / "other").mkdir()
    pts = _table(*_gnss(lambda t: np.full_like(t, 10.0)), batch="a")
    pts.to_csv(tmp_path / "other" / "a.csv", index=False)
    with pytest.raises(InputError, match="only the Autoferry"):
        evaluate_real(tmp_path / "other", sensor="lidar")


def time_seconds_of(df: pd.DataFrame) -> np.ndarray:
    from wakeline.core.schema import time_seconds

    return time_seconds(df["time"])


def test_any_track_file_is_scored_against_a_gnss_truth_file(tmp_path):
    """`evaluate maneuver --real FILE --gnss TRUTH` (before: turn truth only for the
    Autoferry folder): each observed track is scored against the truth track it follows,
    whatever the two files call their tracks; a clutter track follows none and is left out
    of the turns, its detections counted as wrong."""
    import pytest

    from wakeline.core.errors import InputError
    from wakeline.core.evaluate_real import evaluate_real, match_to_truth
    from wakeline.core.io import write_points

    # Two targets logged at 8 Hz: one turns 90° at 60 s, one runs straight 300 m away.
    t, x, y = _gnss(lambda t: np.where(t < 60, 0.0, 90.0))
    t2, x2, y2 = _gnss(lambda t: np.full_like(t, 180.0), seed=1)
    truth = pd.concat([_table(t, x, y, "boat A"), _table(t2, x2 + 300.0, y2, "boat B")])
    # A radar sees both every 1.7 s with 1 m of noise, under numbers of its own, and a
    # clutter track that follows nobody.
    rng = np.random.default_rng(3)
    scans = np.arange(0.5, 119.0, 1.7)
    observed = []
    for name, (tt, xx, yy) in (("7", (t, x, y)), ("12", (t2, x2 + 300.0, y2))):
        ox = np.interp(scans, tt, xx) + rng.normal(0, 1.0, len(scans))
        oy = np.interp(scans, tt, yy) + rng.normal(0, 1.0, len(scans))
        observed.append(_table(scans, ox, oy, name).assign(sensor="radar"))
    observed.append(
        _table(scans, 150.0 + rng.normal(0, 1.0, len(scans)), 2.0 * scans, "99").assign(
            sensor="radar"
        )
    )
    write_points(pd.concat(observed), tmp_path / "radar.csv")
    write_points(truth, tmp_path / "gnss.csv")

    match = match_to_truth(pd.concat(observed), truth).set_index("batch")
    assert match.loc["7", "truth_batch"] == "boat A"
    assert match.loc["12", "truth_batch"] == "boat B"
    assert pd.isna(match.loc["99", "truth_batch"])
    assert match.loc["7", "median_m"] < 3.0

    rows = evaluate_real(tmp_path / "radar.csv", gnss=tmp_path / "gnss.csv").rows
    ours = rows.set_index("method").loc["ours"]
    assert ours["turns"] == 1 and ours["recall"] == 1.0
    assert ours["tracks_matched"] == "2/3"
    with pytest.raises(InputError, match="within 0.1 m"):
        evaluate_real(tmp_path / "radar.csv", gnss=tmp_path / "gnss.csv", gate_m=0.1)


def test_the_autoferry_set_written_out_scores_the_same_with_its_gnss_file(tmp_path):
    """The generic --gnss path on the real Autoferry radar tracks and GNSS logs written out
    as two plain files (track numbers shuffled) gives the figures of the set's own reader."""
    from conftest import real_file
    from wakeline.core import real_sets
    from wakeline.core.evaluate_real import evaluate_real
    from wakeline.core.io import write_points

    folder = real_file("autoferry-fusion")
    pts, truth = real_sets.read_autoferry(folder, exclusive=True)
    names = pts["batch"].astype(str).unique()
    perm = np.random.default_rng(0).permutation(len(names)).astype(str)
    new = dict(zip(names, perm, strict=True))
    write_points(pts.assign(batch=pts["batch"].astype(str).map(new)), tmp_path / "radar.csv")
    write_points(truth, tmp_path / "gnss.csv")
    native = evaluate_real(folder).rows.set_index("method")
    plain = evaluate_real(
        tmp_path / "radar.csv", gnss=tmp_path / "gnss.csv", gnss_fault_m=0.5
    ).rows.set_index("method")
    for method in ("ours", "paper"):
        for col in ("detections", "turns", "precision", "recall"):
            assert plain.loc[method, col] == native.loc[method, col], (method, col)
    assert plain.loc["ours", "tracks_matched"] == f"{len(names)}/{len(names)}"


def test_the_autoferry_set_in_metres_on_its_frame_scores_the_same(tmp_path):
    """The same two plain files with the positions as metres on Autoferry's own "Piren"
    frame (x/y, read with --origin): the figures of the set's own reader."""
    from conftest import real_file
    from wakeline.core import real_sets
    from wakeline.core.evaluate_real import evaluate_real
    from wakeline.core.geo import to_local

    lat0, lon0 = 63.4389029083, 10.39908278
    folder = real_file("autoferry-fusion")
    pts, truth = real_sets.read_autoferry(folder, exclusive=True)
    for df, name in ((pts, "radar.csv"), (truth, "gnss.csv")):
        x, y = to_local(df["lon"], df["lat"], lon0, lat0)
        out = pd.DataFrame({"time": df["time"], "batch": df["batch"].astype(str), "x": x, "y": y})
        out.to_csv(tmp_path / name, index=False, float_format="%.17g")
    native = evaluate_real(folder).rows.set_index("method")
    plane = evaluate_real(
        tmp_path / "radar.csv",
        gnss=tmp_path / "gnss.csv",
        gnss_fault_m=0.5,
        read={"origin": f"{lat0},{lon0}"},
    ).rows.set_index("method")
    for method in ("ours", "paper"):
        for col in ("detections", "turns", "precision", "recall"):
            assert plane.loc[method, col] == native.loc[method, col], (method, col)


def test_real_scores_print_counts_as_integers():
    """Operator test 7, D17: `evaluate maneuver --real` printed `points 1009.000` because
    the split rows lack the counts (NaN made the columns float): counts stay integers in
    the table (and its CSV), blank where a row has none; scores keep 3 decimals."""
    from pathlib import Path

    from wakeline.core.evaluate_real import RealEvaluation, counts_as_integers

    rows = [
        {"method": "ours", "points": 1009, "maneuvers": 31, "precision": 0.9032, "kept": 69},
        {"method": "ours, tuning 2-6", "precision": 0.947, "detections": 19},
    ]
    table = counts_as_integers(rows)
    assert str(table["points"].dtype) == "Int64" and str(table["detections"].dtype) == "Int64"
    assert table["precision"].dtype == "float64"
    text = RealEvaluation("x", Path("x"), table).format()
    assert "1009" in text and "1009.0" not in text and " 31 " in text
    assert "0.903" in text and "0.947" in text
    assert "NaN" not in text and "<NA>" not in text

"""The Statistics panel's figures (core.stats.layer_stats) on a scene whose answers are
known by construction."""

import numpy as np
import pandas as pd
import pytest

from wakeline.core.stats import GRID_CELLS, KM_PER_DEG, layer_stats

T0 = pd.Timestamp("2024-05-01 08:00", tz="UTC")


def _track(sensor: str, batch: str, n: int, step_s: float, lon0: float, lat0: float, **extra):
    t = T0 + pd.to_timedelta(np.arange(n) * step_s, unit="s")
    return pd.DataFrame(
        {
            "sensor": sensor,
            "batch": batch,
            "time": t,
            "lon": lon0 + np.arange(n) * 0.001,
            "lat": np.full(n, lat0),
            **extra,
        }
    )


def scene() -> pd.DataFrame:
    """Radar R: 3 tracks of 11, 21, 31 points every 10 s (lifetimes 100, 200, 300 s);
    AIS A: 1 track of 5 points every 60 s (240 s). Rows shuffled."""
    parts = [
        _track("R", "1", 11, 10.0, 10.0, 55.0),
        _track("R", "2", 21, 10.0, 10.0, 55.1),
        _track("R", "3", 31, 10.0, 10.0, 55.2),
        _track("A", "9", 5, 60.0, 10.5, 55.0),
    ]
    df = pd.concat(parts, ignore_index=True)
    return df.sample(frac=1.0, random_state=1).reset_index(drop=True)


def test_counts_lifetimes_intervals_and_extent_of_a_known_scene():
    s = layer_stats(scene())
    assert (s.points, s.tracks) == (68, 4)
    by = s.sensors.set_index("sensor")
    assert by.loc["R", "tracks"] == 3 and by.loc["A", "tracks"] == 1
    assert by.loc["R", "points"] == 63 and by.loc["A", "points"] == 5
    assert by.loc["R", "interval_s"] == pytest.approx(10.0)
    assert by.loc["A", "interval_s"] == pytest.approx(60.0)
    assert s.targets is None  # no target ids in a source layer
    lt = s.lifetime_s
    assert (lt.min, lt.median, lt.max) == pytest.approx((100.0, 220.0, 300.0))
    assert lt.p90 == pytest.approx(np.percentile([100, 200, 240, 300], 90))
    assert s.hist_counts.sum() == 4 and s.hist_edges_s[-1] == pytest.approx(300.0)
    assert s.hist_counts[0] == 0 and s.hist_counts[-1] == 1  # the 300 s track in the last bin
    pp = s.points_per_track
    assert (pp.min, pp.median, pp.max) == (5, 16, 31)
    assert s.span_s == pytest.approx(300.0)
    assert s.start_s == pytest.approx(T0.timestamp())
    e = s.extent
    assert (e.lon_min, e.lon_max) == pytest.approx((10.0, 10.504))
    assert (e.lat_min, e.lat_max) == pytest.approx((55.0, 55.2))
    assert e.height_km == pytest.approx(0.2 * KM_PER_DEG)
    assert e.width_km == pytest.approx(0.504 * KM_PER_DEG * np.cos(np.radians(55.1)))
    assert e.box_km2 == pytest.approx(e.width_km * e.height_km)
    # Four straight east-west lines cover a thin strip of the box, counted in cells.
    assert e.cell_km == pytest.approx(0.5)  # 32.2 km / 100 cells → 0.5 km
    assert 0 < e.covered_km2 < 0.2 * e.box_km2
    assert max(e.width_km, e.height_km) / e.cell_km <= GRID_CELLS
    assert s.at_rest is None and s.maneuvers is None


def test_targets_rest_spans_maneuvers_and_time_window():
    pts = scene()
    # Associated: tracks 1 and 2 are one target; 3 and 9 two more.
    pts["target"] = pts["batch"].map({"1": "T1", "2": "T1", "3": "T2", "9": "T3"})
    pts["is_maneuver"] = (pts["batch"] == "3") & (pts["lon"] >= 10.0095)
    rest = pd.DataFrame({"sensor": ["R", "R"], "batch": ["1", "3"], "duration_s": [600.0, 1800.0]})
    s = layer_stats(pts, {"at_rest": rest})
    assert s.targets == 3 and s.target_source == "target"
    assert s.at_rest == {"spans": 2, "total_s": 2400.0, "median_s": 1200.0, "tracks": 2}
    assert s.maneuvers == {"points": 21, "tracks": 1}
    # A fused layer: one track per target, listed by its members.
    fused = scene().assign(members="R:1+A:9")
    assert layer_stats(fused).targets == 4
    # The first 150 s: track 1 whole, 2 and 3 cut to 16 points, the AIS track to 3.
    w = (T0.timestamp(), T0.timestamp() + 150.0)
    s = layer_stats(pts, window=w)
    assert s.points == 11 + 16 + 16 + 3 and s.lifetime_s.max == pytest.approx(150.0)
    assert s.window == w and s.span_s == pytest.approx(150.0)


def test_an_empty_layer_and_a_single_point():
    empty = scene().iloc[:0]
    s = layer_stats(empty)
    assert (s.points, s.tracks, s.extent) == (0, 0, None)
    assert np.isnan(s.lifetime_s.median) and s.hist_counts.sum() == 0
    one = scene().iloc[:1]
    s = layer_stats(one)
    assert s.tracks == 1 and s.lifetime_s.max == 0.0 and np.isnan(s.sensors["interval_s"][0])
    assert s.extent.box_km2 == 0.0 and s.extent.covered_km2 == 0.0


def test_a_cleaned_layer_carries_its_at_rest_spans_to_the_figures():
    """run_clean keeps the stationary rule's spans beside the layer (``at_rest``)."""
    from wakeline.core.pipeline import run_clean

    n = 300
    lon = 10 + np.concatenate(
        [np.arange(100) * 0.0005, np.full(100, 0.05), 0.05 + np.arange(100) * 0.0005]
    )
    pts = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "7",
            "time": T0 + pd.to_timedelta(np.arange(n) * 10.0, unit="s"),
            "lon": lon,
            "lat": np.full(n, 55.0),
        }
    )
    layer = run_clean(pts, {}).layers[0]
    assert len(layer.tables["at_rest"]) == 1
    rest = layer_stats(layer.points, layer.tables).at_rest
    assert rest["spans"] == 1 and rest["tracks"] == 1
    assert 990.0 <= rest["total_s"] <= 1100.0  # 100 fixes 10 s apart at one place


def test_the_at_rest_table_comes_back_from_a_project_and_an_empty_one_too(tmp_path):
    """The cleaned layer's at_rest side table is stored with the layer: a reopened
    project counts the same spans (and a layer with none keeps an empty table)."""
    from wakeline.core.project import load_project, save_project
    from wakeline.core.session import Session

    n = 300
    lon = 10 + np.concatenate(
        [np.arange(100) * 0.0005, np.full(100, 0.05), 0.05 + np.arange(100) * 0.0005]
    )
    moored = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "7",
            "time": T0 + pd.to_timedelta(np.arange(n) * 10.0, unit="s"),
            "lon": lon,
            "lat": np.full(n, 55.0),
        }
    )
    s = Session()
    for name, pts in (("moored.csv", moored), ("moving.csv", scene())):
        lid = s.add_layer(name, "source", pts).id
        s.apply_result(lid, s.run_step(lid, "clean"))
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    back = {lay.name: lay for lay in load_project(path).layers}
    cleaned = [name for name in back if name.endswith("cleaned")]
    assert len(cleaned) == 2
    rests = {name: layer_stats(back[name].points, back[name].tables).at_rest for name in cleaned}
    assert rests[next(n for n in cleaned if n.startswith("moored"))]["spans"] == 1
    assert rests[next(n for n in cleaned if n.startswith("moving"))]["spans"] == 0


def test_extent_across_the_antimeridian_is_the_short_arc():
    """Review: an 11 km track from 179.95° E to 179.95° W read as 39,420 km wide (the box
    of the raw longitudes); the box runs east across ±180°."""
    lon = np.linspace(179.95, 180.05, 50)
    lon = np.where(lon > 180.0, lon - 360.0, lon)
    pts = pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": "1",
            "time": pd.date_range("2024-05-01", periods=50, freq="10s", tz="UTC"),
            "lon": lon,
            "lat": np.full(50, 10.0),
        }
    )
    e = layer_stats(pts).extent
    assert 10.0 < e.width_km < 12.0 and e.covered_km2 <= e.box_km2 < 1.0
    assert e.lon_min == pytest.approx(179.95) and e.lon_max == pytest.approx(-179.95)
    # a track spanning 200° without crossing (the wider arc is the one at ±180°) is left as it is
    wide = pts.assign(lon=np.linspace(-100.0, 100.0, 50))
    e = layer_stats(wide).extent
    assert e.lon_min == -100.0 and e.lon_max == 100.0

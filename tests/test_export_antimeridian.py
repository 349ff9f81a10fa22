"""Operator test 5's D-export-3: a track across the antimeridian was one GeoJSON
LineString whose longitudes jump 179.98 → −179.96 (web maps draw a line across the
world). It is now cut into a MultiLineString at ±180° (RFC 7946 §3.1.9), the crossing's
latitude and time interpolated; the added vertices are named in
``antimeridian_vertices`` and the reader leaves them out: the file reads back to the
same points, none invented."""

import json

import numpy as np
import pandas as pd

from wakeline.core.export import antimeridian_parts, export_geojson
from wakeline.core.io import read_points


def _across() -> pd.DataFrame:
    """East over 180° (179.99 → −179.99), then back west; 10 s fixes, ms times."""
    lon = np.array([179.97, 179.98, 179.99, -179.99, -179.98, -179.99, 179.99, 179.98])
    t = pd.Timestamp("2024-01-01T00:00:00.250Z") + pd.to_timedelta(np.arange(8) * 10, "s")
    return pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "7",
            "time": t,
            "lon": lon,
            "lat": 52.0 + np.arange(8) * 1e-3,
            "speed": np.nan,
            "course": np.nan,
        }
    )


def test_a_line_across_the_antimeridian_is_cut_and_reads_back_to_its_fixes(tmp_path):
    pts = _across()
    out = tmp_path / "a.geojson"
    export_geojson(pts, out)
    feature = json.loads(out.read_text())["features"][0]
    geom, props = feature["geometry"], feature["properties"]
    assert geom["type"] == "MultiLineString" and len(geom["coordinates"]) == 3
    flat = [v for part in geom["coordinates"] for v in part]
    assert len(flat) == len(props["times"]) == len(pts) + 4
    for part in geom["coordinates"]:
        lon = np.asarray(part)[:, 0]
        assert (np.abs(np.diff(lon)) <= 180).all()  # no step across the world
    added = props["antimeridian_vertices"]
    assert added == [3, 4, 8, 9]
    assert [flat[i][0] for i in added] == [180.0, -180.0, -180.0, 180.0]
    # halfway between 179.99 and -179.99 (0.01° each side): the mean latitude and time
    assert flat[3][1] == flat[4][1] == round(52.0025, 7)
    assert props["times"][3] == props["times"][4]  # in the file's unit (ms), within 1 ms
    mid = pd.Timestamp(props["times"][3]) - pd.Timestamp("2024-01-01T00:00:25.250Z")
    assert abs(mid) <= pd.Timedelta(milliseconds=1)
    times = pd.to_datetime(props["times"])
    assert times.is_monotonic_increasing
    back = read_points(out)
    assert back.report["cut_vertices"] == 4
    got = back.points
    assert (got["time"].to_numpy() == pts["time"].to_numpy()).all()
    assert np.array_equal(got["lon"].to_numpy(), pts["lon"].to_numpy())
    assert np.array_equal(got["lat"].to_numpy(), pts["lat"].to_numpy())


def test_a_line_that_does_not_cross_stays_one_linestring(tmp_path):
    pts = _across().iloc[:3]
    export_geojson(pts, tmp_path / "a.geojson")
    feature = json.loads((tmp_path / "a.geojson").read_text())["features"][0]
    assert feature["geometry"]["type"] == "LineString"
    assert "antimeridian_vertices" not in feature["properties"]
    lon = np.array([10.0, 10.1])
    assert antimeridian_parts(lon, lon, np.array([0, 1]), "s") is None

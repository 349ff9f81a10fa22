"""GeoJSON read as tracks (core/io/geojson.py): our own export reads back (one time per
vertex), foreign point collections by their property names, and every feature or vertex a
point or a quarantined row."""

import json

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.export import export_geojson
from wakeline.core.io import read_points
from wakeline.core.io.reader import inspect_file


def _accounted(r) -> None:
    rep = r.report
    assert rep["rows_read"] == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["rows_imported"] == len(r.points)


def test_our_geojson_export_reads_back_as_the_same_tracks(tmp_path):
    rng = np.random.default_rng(1)
    t = pd.date_range("2024-01-01", periods=30, freq="2500ms", tz="UTC")
    pts = pd.DataFrame(
        {
            "sensor": ["radar"] * 30 + ["ais"] * 30 + ["ais"],
            "batch": ["7"] * 30 + ["257000001"] * 30 + ["lonely"],
            "time": t.append(t).append(t[:1]),
            "lon": 10.0 + rng.normal(0, 0.01, 61),
            "lat": 59.0 + rng.normal(0, 0.01, 61),
        }
    )
    maneuvers = pts.iloc[[3]].assign(factor=22.0)
    export_geojson(pts, tmp_path / "out.geojson", maneuvers)
    r = read_points(tmp_path / "out.geojson")
    _accounted(r)
    assert r.report["format"] == "geojson" and r.report["maneuver_points"] == 1
    key = ["sensor", "batch", "time"]
    want = pts.sort_values(key).reset_index(drop=True)
    got = r.points.sort_values(key).reset_index(drop=True)
    assert (got[["sensor", "batch"]].to_numpy() == want[["sensor", "batch"]].to_numpy()).all()
    assert (got["time"] == want["time"]).all()  # 2.5 s steps: the fractions kept
    assert np.allclose(got["lon"], want["lon"], atol=1e-7)


def test_foreign_point_features_and_what_cannot_be_a_track(tmp_path):
    feats = [
        {
            "type": "Feature",
            "geometry": {"type": "Point", "coordinates": [10 + i * 1e-3, 59.0]},
            "properties": {"MMSI": 257000000 + i % 2, "timestamp": f"2024-01-01T00:00:{i:02d}Z"},
        }
        for i in range(10)
    ]
    feats += [
        {
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": [[10, 59], [10.1, 59]]},
            "properties": {"name": "a route"},
        },
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": []}, "properties": {}},
        {
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": [[10, 59], [10.1, 95]]},
            "properties": {"id": "x", "coordTimes": ["2024-01-01T00:00:00Z", 1704067210]},
        },
    ]
    path = tmp_path / "foreign.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}), encoding="utf-8")
    r = read_points(path)
    _accounted(r)
    assert r.points["batch"].value_counts().to_dict() == {"257000000": 5, "257000001": 5, "x": 1}
    assert r.quarantine["line"].tolist() == [11, 12, 13]  # feature numbers
    assert r.quarantine["reason"].iloc[0].startswith("a line without per-vertex times")
    assert any("no time per vertex" in w for w in r.report["warnings"])
    info = inspect_file(path)
    assert info["kind"] == "geojson" and info["problem"] is None


@settings(max_examples=30, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.sampled_from(["LineString", "Point", "Polygon", None]),
            st.integers(0, 4),
            st.booleans(),
            st.one_of(st.floats(-100, 100), st.just(float("nan"))),
        ),
        max_size=8,
    )
)
def test_any_feature_collection_is_accounted_for(tmp_path_factory, specs):
    feats = []
    for kind, n, with_times, lat in specs:
        lat_v = None if lat != lat else lat
        coords = [[10.0 + j * 1e-3, lat_v] for j in range(max(n, 1))]
        times = [f"2024-01-01T00:00:{j:02d}Z" for j in range(max(n, 1))]
        props = {"times": times} if with_times else {"name": "no times"}
        geom = {"type": kind, "coordinates": coords if kind != "Point" else coords[0]}
        feats.append({"type": "Feature", "geometry": geom if kind else None, "properties": props})
    path = tmp_path_factory.mktemp("gj") / "any.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}), encoding="utf-8")
    r = read_points(path)
    _accounted(r)


def test_a_json_that_is_no_geojson_gets_a_short_message(tmp_path):
    """h122's M4: a JSON document read as a CSV header quoted the whole file (262 k
    characters) in the message; the names are cut (40 characters each, 40 at most)."""
    import pytest

    from wakeline.core.errors import InputError

    path = tmp_path / "rows.json"
    path.write_text(json.dumps([{"a": i, "b": "x" * 50} for i in range(20000)]), encoding="utf-8")
    with pytest.raises(InputError, match="headers found") as exc:
        read_points(path)
    assert len(str(exc.value)) < 2500


def test_numeric_and_zoned_times_read_as_the_csv_reader_reads_them(tmp_path):
    """h130: unix milliseconds and fractional seconds raised a TypeError, a compact
    yyyymmddHHMMSS too; naive times ignored --tz. The times go through the CSV reader's
    parse now."""
    import pandas as pd

    def one(times, **kw):
        feats = [
            {
                "type": "Feature",
                "geometry": {"type": "LineString", "coordinates": [[10, 59], [10.001, 59]]},
                "properties": {"batch": "1", "times": times},
            }
        ]
        path = tmp_path / "t.geojson"
        path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
        return read_points(path, **kw).points["time"].tolist()

    t0 = pd.Timestamp("2024-01-01T00:00:00.123Z")
    assert one([1704067200123, 1704067210456]) == [t0, pd.Timestamp("2024-01-01T00:00:10.456Z")]
    assert one([1704067200.5, 1704067210.5])[0] == pd.Timestamp("2024-01-01T00:00:00.5Z")
    assert one(["20240101120000", "20240101120010"])[0] == pd.Timestamp("2024-01-01T12:00:00Z")
    zoned = one(["2024-01-01 08:00:00", "2024-01-01 08:00:10"], tz="+08:00")
    assert zoned[0] == pd.Timestamp("2024-01-01T00:00:00Z")


def test_speed_course_and_carried_columns_go_per_vertex_and_read_back(tmp_path):
    """Operator test 7, D12: the GeoJSON export dropped speed, course and the columns the
    import carried. They are written per vertex in ``coordinateProperties`` (one value per
    vertex, null where missing; null on the vertices an antimeridian cut adds) and read
    back; Wakeline's internal columns are left out and named by the command line."""
    from wakeline.app.cli import main
    from wakeline.core.io import write_points

    rng = np.random.default_rng(4)
    n = 12
    t = pd.date_range("2024-03-01", periods=n, freq="10s", tz="UTC")
    lon = np.r_[179.997 + 0.0005 * np.arange(6), -179.9995 + 0.0005 * np.arange(6)]
    pts = pd.DataFrame(
        {
            "sensor": ["ais"] * n + ["radar"] * 3,
            "batch": ["1"] * n + ["9"] * 3,
            "time": t.append(t[:3]),
            "lon": np.r_[lon, 20.0 + rng.normal(0, 0.001, 3)],
            "lat": 60.0 + rng.normal(0, 0.001, n + 3),
            "speed": np.r_[rng.uniform(5, 15, n), [np.nan, 7.5, 8.0]],
            "course": np.r_[rng.uniform(0, 359, n), [90.0, np.nan, 91.0]],
            "航迹向": pd.Series([f"{v:.1f}" for v in rng.uniform(0, 359, n + 3)], dtype="str"),
            "course_read": np.nan,
        }
    )
    src = tmp_path / "in.csv"
    write_points(pts, src)
    out = tmp_path / "out.geojson"
    assert main(["export", str(src), "-o", str(out)]) == 0
    doc = json.loads(out.read_text(encoding="utf-8"))
    ais = next(f for f in doc["features"] if f["properties"]["sensor"] == "ais")
    per = ais["properties"]["coordinateProperties"]
    assert set(per) == {"speed", "course", "航迹向"}
    assert ais["geometry"]["type"] == "MultiLineString"  # cut at ±180°: two added vertices
    n_vertices = sum(len(p) for p in ais["geometry"]["coordinates"])
    assert all(len(v) == n_vertices == n + 2 for v in per.values())
    assert sum(v is None for v in per["speed"]) == 2  # the added vertices
    back = read_points(out).points
    key = ["sensor", "batch", "time"]
    want = pts.sort_values(key).reset_index(drop=True)
    got = back.sort_values(key).reset_index(drop=True)
    assert len(got) == len(want)
    for col in ("speed", "course"):
        np.testing.assert_allclose(got[col], want[col], equal_nan=True)
    assert got["航迹向"].tolist() == want["航迹向"].tolist()
    assert "course_read" not in got.columns

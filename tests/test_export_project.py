"""Export (CSV safe for spreadsheets, GeoJSON) and the project file."""

import json
import sqlite3

import pandas as pd
import pytest

from wakeline.core import simulate
from wakeline.core.errors import InputError
from wakeline.core.export import export_csv, export_geojson, geojson, spreadsheet_safe
from wakeline.core.io import read_points
from wakeline.core.maneuver import detect
from wakeline.core.project import Layer, Project, Source, file_hash, load_project, save_project


def test_formula_cells_are_defused_and_numbers_untouched(tmp_path):
    df = simulate.demo_scene().head(4).copy()
    df["batch"] = ["=HYPERLINK(1)", "+cmd", "-cmd", "@SUM(A1)"]
    df["note"] = ["-2.5", "+1", "1e-3", "=1+2"]  # numbers as text stay numbers (issue 14)
    safe = spreadsheet_safe(df)
    assert safe["batch"].tolist() == ["'=HYPERLINK(1)", "'+cmd", "'-cmd", "'@SUM(A1)"]
    assert safe["note"].tolist() == ["-2.5", "+1", "1e-3", "'=1+2"]
    assert (safe["lon"] == df["lon"]).all()
    path = tmp_path / "out.csv"
    export_csv(df, path)
    text = path.read_text()
    assert "'=HYPERLINK(1)" in text and ",=" not in text
    back = read_points(path).points
    assert len(back) == 4


def test_export_and_reimport_round_trip(tmp_path):
    df = simulate.demo_scene()
    path = tmp_path / "demo.csv"
    export_csv(df, path)
    back = read_points(path).points
    assert len(back) == len(df)
    assert back.groupby(["sensor", "batch"]).ngroups == df.groupby(["sensor", "batch"]).ngroups


def test_geojson_has_a_line_per_track_and_maneuver_points(tmp_path):
    df = simulate.demo_scene()
    man = detect(df).table()
    gj = geojson(df, man)
    kinds = pd.Series([f["geometry"]["type"] for f in gj["features"]])
    n_tracks = df.groupby(["sensor", "batch"]).ngroups
    assert (kinds == "LineString").sum() + (kinds == "Point").sum() == n_tracks + len(man)
    first = gj["features"][0]
    lon, lat = first["geometry"]["coordinates"][0]
    assert -180 <= lon <= 180 and -90 <= lat <= 90
    path = tmp_path / "demo.geojson"
    export_geojson(df, path, man)
    assert json.loads(path.read_text())["type"] == "FeatureCollection"


def test_project_round_trip_and_source_checks(tmp_path):
    src = tmp_path / "demo.csv"
    df = simulate.demo_scene()
    export_csv(df, src)
    points = read_points(src).points
    proj = Project(
        sources=[Source(str(src), file_hash(src))],
        params={"maneuver": {"window_p": 7}},
        layers=[Layer("L1", "demo", "source", points, True, "#123456", {"file": str(src)})],
        selection=[("L1", "R1", str(points["batch"].iloc[0]))],
    )
    path = tmp_path / "p.wakeline"
    save_project(proj, path)
    back = load_project(path)
    assert back.params == proj.params and back.selection == proj.selection
    assert back.layers[0].id == "L1" and back.layers[0].name == "demo"
    pd.testing.assert_frame_equal(back.layers[0].points, points)
    assert back.layers[0].color == "#123456" and back.source_problems() == []
    src.write_text(src.read_text() + "\n")
    assert "changed" in back.source_problems()[0]
    src.unlink()
    assert "missing" in load_project(path).source_problems()[0]


def test_bad_project_files(tmp_path):
    with pytest.raises(InputError, match="no such project"):
        load_project(tmp_path / "nope.wakeline")
    junk = tmp_path / "junk.wakeline"
    junk.write_bytes(b"not a database at all" * 10)
    with pytest.raises(InputError, match="not a Wakeline project"):
        load_project(junk)
    other = tmp_path / "other.wakeline"
    con = sqlite3.connect(other)
    con.execute("CREATE TABLE x (a)")
    con.commit()
    con.close()
    with pytest.raises(InputError, match="not a Wakeline project"):
        load_project(other)


def test_the_window_s_file_row_is_never_written(tmp_path):
    """The window keeps each point's file row (wl_row) for Export ▸ As it came in; the
    canonical and the reviewed-tracks exports wrote it as a column (review)."""
    from wakeline.core.export_review import export_tracks_csv

    pts = simulate.demo_scene(seed=1).head(50)
    pts = pts.assign(wl_row=range(len(pts)))
    for write in (export_csv, export_tracks_csv):
        out = tmp_path / f"{write.__name__}.csv"
        write(pts, out)
        assert "wl_row" not in out.read_text().splitlines()[0]


def test_a_table_with_its_file_rows_is_exported_in_the_file_s_order(tmp_path):
    """h155: the window's layers are kept in track order with each point's file row; the
    canonical CSV of one is written in the file's order (a table whose file rows repeat
    or are missing, e.g. points a step added, as given)."""
    pts = simulate.demo_scene(seed=1).head(60).reset_index(drop=True)
    shuffled = pts.assign(wl_row=range(len(pts))).sample(frac=1.0, random_state=2)
    out, plain = tmp_path / "out.csv", tmp_path / "plain.csv"
    export_csv(shuffled, out)
    export_csv(pts, plain)
    assert out.read_bytes() == plain.read_bytes()
    repeated = shuffled.assign(wl_row=[0] + list(range(len(pts) - 1)))
    export_csv(repeated, out)
    export_csv(shuffled.drop(columns="wl_row"), plain)
    assert out.read_bytes() == plain.read_bytes()

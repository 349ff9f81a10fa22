"""Operator test 5's D-export-2: one associated layer exported as CSV, GeoJSON and GPX
re-imported as 5, 6 and 6 tracks (the GPX lost the target). Every format now keeps the
member tracks and carries their targets (docs/export.md "Targets in every format"): read
back, the same points and the same targets."""

import numpy as np
import pandas as pd

from wakeline.app.cli import main
from wakeline.core.export import export_geojson
from wakeline.core.export_review import export_gpx, export_tracks
from wakeline.core.io import read_points, write_points


def _associated() -> pd.DataFrame:
    """Three tracks in two targets: AIS:rx1/367 (a sensor with a colon) and R/12 one
    target, R/13 alone; times to the millisecond, positions of 7 decimals."""
    t0 = pd.Timestamp("2024-08-02T00:00:00.123Z")
    rows = []
    for sensor, batch, target, start, lat in (
        ("AIS:rx1", "367", "367", 0, 38.0),
        ("R", "12", "367", 600, 38.01),
        ("R", "13", "R:13", 100, 38.2),
    ):
        for k in range(4):
            rows.append(
                (
                    sensor,
                    batch,
                    t0 + pd.Timedelta(seconds=start + 10 * k),
                    23.5 + k * 1e-4,
                    lat,
                    target,
                )
            )
    cols = ["sensor", "batch", "time", "lon", "lat", "target"]
    return pd.DataFrame(rows, columns=cols).assign(speed=np.nan, course=np.nan)


def _key(p: pd.DataFrame) -> pd.DataFrame:
    p = p.assign(sensor=p["sensor"].astype(str), batch=p["batch"].astype(str))
    p = p.assign(target=p["target"].astype(str))
    cols = ["sensor", "batch", "time", "lon", "lat", "target"]
    return p.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)[cols]


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    a, b = _key(a), _key(b)
    assert a[["sensor", "batch", "target"]].equals(b[["sensor", "batch", "target"]])
    assert (a["time"].to_numpy() == b["time"].to_numpy()).all()
    assert np.array_equal(a["lon"].to_numpy(), b["lon"].to_numpy())
    assert np.array_equal(a["lat"].to_numpy(), b["lat"].to_numpy())


def test_cli_export_of_an_associated_layer_round_trips_in_every_format(tmp_path, capsys):
    pts = _associated()
    src = tmp_path / "assoc.csv"
    write_points(pts, src)
    for suffix in ("csv", "geojson", "gpx"):
        out = tmp_path / f"x.{suffix}"
        assert main(["export", str(src), "-o", str(out)]) == 0
        back = read_points(out)
        assert back.points.groupby(["sensor", "batch"]).ngroups == 3, suffix
        _same(pts, back.points)
        note = [w for w in back.report["warnings"] if "carries targets" in w]
        assert note and "3 tracks in 2 targets" in note[0], suffix
        assert ("--map batch=target" in note[0]) == (suffix == "csv")
    err = capsys.readouterr().err
    assert "2 targets in the 'target' column" in err
    assert not (tmp_path / "x.members.csv").exists()
    gpx = (tmp_path / "x.gpx").read_text()
    assert gpx.count("<trk>") == 2 and gpx.count("<trkseg>") == 3  # a <trk> per target
    # the streamed import says it too
    assert main(["import", str(tmp_path / "x.csv"), "-o", str(tmp_path / "y.csv")]) == 0
    assert "--map batch=target reads one track per target" in capsys.readouterr().err


def test_a_layout_still_writes_one_id_per_target(tmp_path, capsys):
    src = tmp_path / "assoc.csv"
    write_points(_associated(), src)
    out = tmp_path / "x.csv"
    assert main(["export", str(src), "-o", str(out), "--layout", "canonical"]) == 0
    assert "members in" in capsys.readouterr().err
    assert read_points(out).points.groupby(["sensor", "batch"]).ngroups == 2
    assert (tmp_path / "x.members.csv").exists()


def test_merged_tracks_of_a_review_are_written_per_member(tmp_path):
    """`wakeline review` and the window write merged tracks (sensor 'merged', batch the
    target, source_track the member) to GeoJSON and GPX: read back as the member tracks
    with their targets, as the reviewed CSV reads."""
    pts = _associated().query("sensor == 'R'").reset_index(drop=True)
    merged = pts.assign(
        source_track=pts["sensor"] + ":" + pts["batch"],
        members="R:12",
        sensor="merged",
        batch=pts["target"],
    )
    for suffix in ("geojson", "gpx"):
        out = tmp_path / f"m.{suffix}"
        export_tracks(merged, out)
        _same(pts, read_points(out).points)


def test_merged_tracks_with_a_colon_in_a_sensor_split_by_their_source_sensor(tmp_path):
    """Merged tracks keep each row's own sensor in ``source_sensor`` (as
    :func:`merged_tracks` writes them): a sensor named ``AIS:rx1`` comes back as that
    sensor with batch ``367`` from GeoJSON and GPX, not as sensor ``AIS``, batch ``rx1:367``."""
    pts = _associated()
    merged = pts.assign(
        source_track=pts["sensor"] + ":" + pts["batch"],
        source_sensor=pts["sensor"],
        members="AIS:rx1:367+R:12",
        sensor="merged",
        batch=pts["target"],
    )
    for suffix in ("geojson", "gpx"):
        out = tmp_path / f"m.{suffix}"
        export_tracks(merged, out)
        back = read_points(out).points
        assert set(back["sensor"]) == {"AIS:rx1", "R"}
        _same(pts, back)


def test_tracks_without_targets_are_written_as_before(tmp_path):
    pts = _associated().drop(columns="target")
    export_gpx(pts, tmp_path / "a.gpx")
    export_geojson(pts, tmp_path / "a.geojson")
    for name in ("a.gpx", "a.geojson"):
        back = read_points(tmp_path / name)
        assert "target" not in back.points.columns
        assert back.points.groupby(["sensor", "batch"]).ngroups == 3
    assert "wakeline target" not in (tmp_path / "a.gpx").read_text()


def test_a_gpx_target_whose_segments_do_not_match_stays_one_track(tmp_path):
    """A <trk> typed as our target but edited (a segment removed) reads as one track."""
    export_gpx(_associated(), tmp_path / "a.gpx")
    text = (tmp_path / "a.gpx").read_text()
    cut = text.index("</trkseg>") + len("</trkseg>")
    edited = text[: text.index("<trkseg>")] + text[cut:]
    (tmp_path / "b.gpx").write_text(edited)
    back = read_points(tmp_path / "b.gpx").points
    assert len(back) == 8
    assert back.groupby(["sensor", "batch"]).ngroups == 2


def test_a_file_read_in_pieces_says_its_targets_once(tmp_path, monkeypatch):
    """``wakeline import`` of a quoted CSV with a target column, read in pieces: the
    targets note once, with the whole file's counts (h192: a piece's '2 tracks in 1
    targets' came before it)."""
    from wakeline.core.io import import_to_csv, reader

    lines = ["sensor,batch,time,lon,lat,target"]
    for b in range(6):
        for k in range(300):
            s = b * 300 + k
            stamp = f"2024-01-01T{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}Z"
            lines.append(
                f'"S1","{b}",{stamp},{23 + b * 0.01 + k * 1e-4:.6f},{37.5 + k * 1e-4:.6f},{b // 2}'
            )
    src = tmp_path / "t.csv"
    src.write_text("\n".join(lines) + "\n")
    whole = [w for w in read_points(src).report["warnings"] if "carries targets" in w]
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report.get("pieces", 0) > 2
    assert [w for w in got.report["warnings"] if "carries targets" in w] == whole
    assert len(whole) == 1 and "6 tracks in 3 targets" in whole[0]


def test_merged_rows_without_source_sensor_keep_their_own_track():
    """Review h209: a merged layer where some rows have no ``source_sensor`` (an older
    merged file read with a new one) or a blank one: those rows split at the first ':'
    and keep their own track (pd.factorize's NaN code -1 gave them another track's batch)."""
    from wakeline.core.export import member_sensor_batch

    pts = _associated()
    merged = pts.assign(
        source_track=pts["sensor"] + ":" + pts["batch"],
        source_sensor=pts["sensor"],
        sensor="merged",
        batch=pts["target"],
    )
    old = merged.drop(columns="source_sensor").iloc[:4]
    mixed = pd.concat([old, merged.iloc[4:]], ignore_index=True)
    blank = merged.assign(source_sensor=merged["source_sensor"].where(merged.index >= 4, ""))
    for frame in (mixed, blank):
        sensor, batch = member_sensor_batch(frame)
        assert (sensor + ":" + batch).tolist() == frame["source_track"].tolist()
        assert set(sensor.iloc[4:]) == {"R"} and set(batch.iloc[4:]) == {"12", "13"}


def test_a_csv_export_names_the_internal_columns_it_leaves_out(tmp_path, capsys):
    """Operator test 10: a fused layer exported to CSV said "7 columns" and its source,
    n_sources and weight_base were gone without a word (GeoJSON names them). Every
    internal column not in the file is named; every one named is absent from the file."""
    cli = main
    scene = tmp_path / "two.csv"
    assert cli(["simulate", "multisensor", "--seed", "3", "-o", str(scene)]) == 0
    fused = tmp_path / "fused.csv"
    assert cli(["fuse", str(scene), "-o", str(fused)]) == 0
    capsys.readouterr()
    out = tmp_path / "x.csv"
    assert cli(["export", str(fused), "-o", str(out)]) == 0
    msg = capsys.readouterr().err
    said = msg.split("not written: ")[1].split(" (Wakeline's internal columns)")[0].split(", ")
    header = pd.read_csv(out, nrows=0).columns
    assert {"source", "n_sources"} <= set(said)
    assert not set(said) & set(header)
    gone = set(pd.read_csv(fused, nrows=0).columns) - set(header) - {"members", "course_read"}
    assert gone == set(said)
    assert cli(["export", str(out), "-o", str(tmp_path / "again.csv")]) == 0
    assert "not written" not in capsys.readouterr().err

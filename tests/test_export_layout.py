"""Export in the operator's own layout (issue 19): layout detection, formatting, round trips."""

import json

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.conftest import DATA, real_file
from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.export_like import (
    assign_target_ids,
    format_numbers,
    format_times,
    layout_meta,
    write_layout,
)
from wakeline.core.io.layout import (
    WIDEN_MAX_DECIMALS,
    Layout,
    NumberFormat,
    TimeFormat,
    describe_layout,
    preset_layout,
)

LAYOUTS = DATA / "layouts"
#: Every import layout with a sample: file -> the format the import detects.
SAMPLES = {
    "canonical.csv": "canonical",
    "radar_gb18030.csv": "radar",
    "marinecadastre.csv": "ais-marinecadastre",
    "dma.csv": "ais-dma",
    "mtad_scene.csv": "mtad-scene",
    "mtad_measurement.csv": "mtad-measurement",
}
KEY = ["sensor", "batch", "time"]


def _run(*argv) -> int:
    return main([str(a) for a in argv])


@pytest.mark.parametrize("name", SAMPLES)
def test_unchanged_table_exports_like_the_original_byte_for_byte(name, tmp_path):
    original = LAYOUTS / name
    result = read_points(original)
    assert result.report["format"] == SAMPLES[name]
    assert result.report["rows_quarantined"] == 0
    out = tmp_path / name
    write_layout(result.points, describe_layout(original, result.report), out)
    assert out.read_bytes() == original.read_bytes()


@pytest.mark.parametrize("name", SAMPLES)
def test_cli_import_then_export_like_gives_the_original_bytes(name, tmp_path):
    original = LAYOUTS / name
    canonical, out = tmp_path / "c.csv", tmp_path / name
    assert _run("import", original, "-o", canonical) == 0
    assert _run("export", canonical, "-o", out, "--like", original) == 0
    assert out.read_bytes() == original.read_bytes()


def _same_points(a: pd.DataFrame, b: pd.DataFrame, decimals: dict[str, int]) -> None:
    a = a.sort_values(KEY, kind="stable").reset_index(drop=True)
    b = b.sort_values(KEY, kind="stable").reset_index(drop=True)
    assert len(a) == len(b)
    for col in ("sensor", "batch"):
        assert a[col].astype(str).tolist() == b[col].astype(str).tolist()
    assert (a["time"] == b["time"]).all()
    for col, d in decimals.items():
        x, y = a[col].to_numpy(dtype=float), b[col].to_numpy(dtype=float)
        both = np.isfinite(x) & np.isfinite(y)
        assert (np.isfinite(x) == np.isfinite(y)).all(), col
        assert np.all(np.abs(x[both] - y[both]) <= 0.51 * 10.0**-d + 1e-12), col


@pytest.mark.parametrize("name", SAMPLES)
def test_compressed_table_exported_like_reimports_to_the_same_points(name, tmp_path):
    original = LAYOUTS / name
    comp, out = tmp_path / "comp.csv", tmp_path / f"out_{name}"
    assert _run("compress", original, "-o", comp, "--window", 3, "--radius", 2) == 0
    assert _run("export", comp, "-o", out, "--like", original) == 0
    layout = describe_layout(original)
    again = read_points(out)
    assert again.report["format"] == SAMPLES[name]
    assert again.report["encoding"] == layout.encoding
    kept = read_points(comp).points
    assert 0 < len(kept) < len(read_points(original).points)
    precision = {
        c.field: (c.number.decimals if c.number.trim in ("none", "zeros", "keep1") else 12)
        for c in layout.columns
        if c.number is not None
    }
    _same_points(kept, again.points, precision)
    # The operator's columns come back as they were.
    extras = [c.key for c in layout.columns if c.field is None]
    a = kept.sort_values(KEY, kind="stable").reset_index(drop=True)
    b = again.points.sort_values(KEY, kind="stable").reset_index(drop=True)
    for col in extras:
        assert a[col].tolist() == b[col].tolist(), col


def test_compressed_radar_export_is_gb18030_with_header_and_unix_seconds(tmp_path):
    original = LAYOUTS / "radar_gb18030.csv"
    comp, out = tmp_path / "comp.csv", tmp_path / "radar_out.csv"
    assert _run("compress", original, "-o", comp, "--window", 3, "--radius", 2) == 0
    assert _run("export", comp, "-o", out, "--like", original) == 0
    raw = out.read_bytes()
    with pytest.raises(UnicodeDecodeError):
        raw.decode("utf-8")  # the Chinese columns are GB18030 bytes
    text = raw.decode("gb18030")
    lines = text.split("\r\n")
    assert lines[0] == original.read_bytes().decode("gb18030").split("\r\n")[0]
    assert lines[0] == "SendShipNO,SendTime,nNO,lon,lat,speed,course,目标类型,备注"
    rows = [ln.split(",") for ln in lines[1:] if ln]
    assert all(r[1].isdigit() and len(r[1]) == 10 for r in rows)  # unix seconds
    assert all(len(r[3].split(".")[1]) == 6 for r in rows)  # lon precision kept
    assert {r[7] for r in rows} == {"货船", "渔船", "油轮"}


def test_iso_times_with_an_offset_are_written_in_that_offset(write, tmp_path):
    src = write(
        "offset.csv",
        "batch,time,lon,lat\n"
        "7,2022-10-01T10:16:03+08:00,122.5,30.25\n"
        "7,2022-10-01T10:16:33+08:00,122.5,30.5\n",
    )
    res = read_points(src)
    assert res.points["time"].iloc[0] == pd.Timestamp("2022-10-01T02:16:03Z")
    layout = describe_layout(src, res.report)
    assert layout.time.tz == "+08:00"
    out = tmp_path / "out.csv"
    write_layout(res.points, layout, out)
    assert out.read_bytes() == src.read_bytes()


def test_tz_option_writes_naive_local_times(tmp_path):
    out = tmp_path / "local.csv"
    src = LAYOUTS / "marinecadastre.csv"
    assert _run("export", src, "-o", out, "--like", src, "--tz", "Asia/Shanghai") == 0
    first = out.read_text().splitlines()[1].split(",")
    assert first[1] == "2022-10-01T10:16:03"  # 02:16:03 UTC


def test_gap_fills_are_written_with_operator_columns_left_empty(tmp_path):
    original = LAYOUTS / "radar_gb18030.csv"
    pts = read_points(original).points
    fill = pts.iloc[[3]].copy()  # a made point copies its neighbour's columns ...
    fill["time"] = fill["time"] + pd.Timedelta(seconds=10)
    pts = pd.concat([pts.assign(interpolated=False), fill.assign(interpolated=True)])
    out = tmp_path / "out.csv"
    rep = write_layout(pts, describe_layout(original), out)
    assert rep["rows_made"] == 1
    last = out.read_bytes().decode("gb18030").split("\r\n")[-2].split(",")
    assert last[7:] == ["", ""]  # ... but not the operator's columns
    assert last[2] == "101" and last[0] == "1043"
    assert "interpolated" not in out.read_bytes().decode("gb18030").split("\r\n")[0]


def _merged(pts: pd.DataFrame) -> pd.DataFrame:
    # Batches 102 and 103 are one target (T2); 101 is alone (T1). 103 starts first.
    out = pts.copy()
    out["target"] = np.where(out["batch"] == "101", "T1", "T2")
    out.loc[out["batch"] == "103", "time"] -= pd.Timedelta(hours=1)
    return out


def test_merged_targets_take_the_first_member_batch_and_list_members(tmp_path):
    pts = _merged(read_points(LAYOUTS / "radar_gb18030.csv").points)
    ids, members = assign_target_ids(pts)
    assert set(ids.loc[pts["target"] == "T2", "batch"]) == {"103"}
    assert set(ids.loc[pts["target"] == "T1", "batch"]) == {"101"}
    table = members.sort_values(["batch", "member_batch"]).reset_index(drop=True)
    assert table[["batch", "member_batch", "target"]].values.tolist() == [
        ["101", "101", "T1"],
        ["103", "102", "T2"],
        ["103", "103", "T2"],
    ]
    renumbered, members = assign_target_ids(pts, renumber=True)
    assert set(renumbered.loc[pts["target"] == "T2", "batch"]) == {"1"}  # T2 starts first
    assert set(renumbered.loc[pts["target"] == "T1", "batch"]) == {"2"}
    assert sorted(members["batch"]) == ["1", "1", "2"]


def test_cli_export_of_merged_table_writes_members_sidecar(tmp_path):
    original = LAYOUTS / "radar_gb18030.csv"
    merged = tmp_path / "merged.csv"
    from wakeline.core.io import write_points

    write_points(_merged(read_points(original).points), merged)
    out = tmp_path / "out.csv"
    assert _run("export", merged, "-o", out, "--like", original) == 0
    side = pd.read_csv(tmp_path / "out.members.csv", dtype=str)
    assert list(side.columns) == ["sensor", "batch", "member_sensor", "member_batch", "target"]
    assert len(side) == 3
    back = read_points(out).points
    assert sorted(back["batch"].unique()) == ["101", "103"]
    assert "target" not in back.columns  # internal column left out
    assert _run("export", merged, "-o", out, "--like", original, "--columns", "target") == 0
    assert "target" in read_points(out).points.columns


def test_fused_members_give_the_first_member_id():
    pts = pd.DataFrame(
        {
            "sensor": "fused",
            "batch": ["F1", "F1", "F2"],
            "time": pd.to_datetime([0, 10, 0], unit="s", utc=True),
            "lon": [1.0, 1.1, 2.0],
            "lat": [3.0, 3.1, 4.0],
            "members": ["R1:12+R2:7", "R1:12+R2:7", "R2:9"],
        }
    )
    ids, members = assign_target_ids(pts)
    assert ids["sensor"].tolist() == ["R1", "R1", "R2"]
    assert ids["batch"].tolist() == ["12", "12", "9"]
    assert members[["batch", "member_sensor", "member_batch", "target"]].values.tolist() == [
        ["12", "R1", "12", "F1"],
        ["12", "R2", "7", "F1"],
        ["9", "R2", "9", "F2"],
    ]
    ids, members = assign_target_ids(pts, prefer_sensor="R2")
    assert ids["batch"].tolist() == ["7", "7", "9"]
    assert members["batch"].tolist() == ["7", "7", "9"]


def test_canonical_export_leaves_internal_columns_out(tmp_path):
    pts = read_points(LAYOUTS / "mtad_scene.csv").points
    pts["wl_id"] = np.arange(len(pts))
    pts["interpolated"] = False
    out = tmp_path / "out.csv"
    write_layout(pts, preset_layout("canonical"), out)
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["sensor", "batch", "time", "lon", "lat", "speed", "course", "vel"]
    write_layout(pts, preset_layout("canonical"), out, columns=["wl_id"])
    assert out.read_text().splitlines()[0].endswith(",wl_id")


@pytest.mark.parametrize(
    ("preset", "family", "encoding"),
    [
        ("radar", "radar", "gb18030"),
        ("marinecadastre", "ais-marinecadastre", "utf-8"),
        ("dma", "ais-dma", "utf-8"),
        ("canonical", "canonical", "utf-8"),
    ],
)
def test_presets_reimport_as_their_format(preset, family, encoding, tmp_path):
    src = LAYOUTS / "canonical.csv"
    out = tmp_path / f"{preset}.csv"
    assert _run("export", src, "-o", out, "--layout", preset) == 0
    again = read_points(out)
    assert again.report["format"] == family
    out.read_bytes().decode(encoding)  # ASCII-only here, so any of the two would read it
    before = read_points(src).points
    layout = preset_layout(preset)
    if layout.field_column("sensor") is None:
        before = before.assign(sensor="S1")
    if preset != "canonical":  # these write whole seconds
        before = before.assign(time=before["time"].dt.round("s"))
    decimals = {
        c.field: c.number.decimals if c.number.trim != "repr" else 12
        for c in layout.columns
        if c.number is not None
    }
    _same_points(before, again.points, decimals)


def test_layout_survives_json_and_like_accepts_it(tmp_path):
    original = LAYOUTS / "dma.csv"
    layout = describe_layout(original)
    data = json.loads(json.dumps(layout.to_dict()))
    assert Layout.from_dict(data) == layout
    path = tmp_path / "dma.layout.json"
    out = tmp_path / "out.csv"
    assert _run("export", original, "-o", out, "--like", original, "--save-layout", path) == 0
    assert Layout.from_dict(json.loads(path.read_text())) == layout
    assert _run("export", original, "-o", out, "--like", path) == 0
    assert out.read_bytes() == original.read_bytes()


def test_encoding_option_and_encoding_errors(tmp_path, capsys):
    original = LAYOUTS / "radar_gb18030.csv"
    out = tmp_path / "out.csv"
    assert _run("export", original, "-o", out, "--like", original, "--encoding", "utf-8") == 0
    assert "目标类型" in out.read_text(encoding="utf-8")
    bad = tmp_path / "bad.csv"
    assert _run("export", original, "-o", bad, "--like", original, "--encoding", "latin-1") == 2
    assert "cannot be written in latin-1" in capsys.readouterr().err
    assert not bad.exists()
    assert _run("export", original, "-o", bad, "--like", original, "--encoding", "nope") == 2
    assert "unknown encoding" in capsys.readouterr().err


def test_bad_arguments_exit_2_with_one_message(tmp_path, capsys):
    src = LAYOUTS / "canonical.csv"
    out = tmp_path / "out.csv"
    assert _run("export", src, "-o", out, "--like", src, "--layout", "radar") == 2
    assert "not both" in capsys.readouterr().err
    assert _run("export", src, "-o", out, "--columns", "nosuch") == 2
    assert "no column nosuch" in capsys.readouterr().err
    assert _run("export", src, "-o", out, "--layout", "dma", "--tz", "Mars/Base") == 2
    assert "unknown time zone" in capsys.readouterr().err
    assert _run("export", src, "-o", out, "--like", tmp_path / "missing.csv") == 2
    assert "no such file" in capsys.readouterr().err
    bad_json = tmp_path / "x.json"
    bad_json.write_text("{}")
    assert _run("export", src, "-o", out, "--like", bad_json) == 2
    assert "not a Wakeline layout" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize(
    ("texts", "expected"),
    [
        (["1", "22", "333"], NumberFormat(0, "none")),
        (["1.50", "2.25", "3.00"], NumberFormat(2, "none")),
        (["1.5", "2.25", "3"], NumberFormat(2, "zeros")),
        (["1.5", "2.25", "3.0"], NumberFormat(2, "keep1")),
        (["20.149536268409268", "337.0"], NumberFormat(15, "repr1")),
        (["a", "b"], None),
        (["57,6671", "11,80", "3"], NumberFormat(4, "zeros", "", ",")),
    ],
)
def test_number_format_detection(texts, expected):
    assert NumberFormat.detect(pd.Series(texts)) == expected


def test_number_formatting_round_trips_each_style():
    x = np.array([1.5, -2.25, 3.0, -0.0001, np.nan, 0.30000000000000004])
    assert format_numbers(x, NumberFormat(2, "none")).to_pylist() == [
        "1.50",
        "-2.25",
        "3.00",
        "0.00",
        "",
        "0.30",
    ]
    assert format_numbers(x, NumberFormat(3, "zeros")).to_pylist()[:4] == ["1.5", "-2.25", "3", "0"]
    assert format_numbers(x, NumberFormat(3, "keep1", "NaN")).to_pylist()[2:5] == [
        "3.0",
        "0.0",
        "NaN",
    ]
    reprs = format_numbers(x, NumberFormat(17, "repr1")).to_pylist()
    assert reprs[2] == "3.0" and reprs[3] == "-0.0001" and reprs[5] == "0.30000000000000004"


def test_time_formatting():
    t = pd.Series(
        pd.to_datetime(["2023-03-01T00:01:46.5Z", None, "1969-12-31T23:59:59Z"], format="ISO8601")
    )
    day_first = TimeFormat("text", "%d/%m/%Y %H:%M:%S", 1, "zeros", "")
    assert format_times(t, day_first).to_pylist() == [
        "01/03/2023 00:01:46.5",
        "",
        "31/12/1969 23:59:59",
    ]
    unix = TimeFormat("unix", number=NumberFormat(0, "none"))
    assert format_times(t, unix).to_pylist() == ["1677628907", "", "-1"]
    millis = TimeFormat("unix", scale=1000, number=NumberFormat(0, "none"))
    assert format_times(t, millis).to_pylist()[0] == "1677628906500"


def test_describe_layout_reports_unreadable_time(write):
    src = write("odd.csv", "batch,time,lon,lat\n1,yesterday noon,1,2\n")
    report = {"columns": {"batch": "batch", "time": "time", "lon": "lon", "lat": "lat"}}
    with pytest.raises(InputError, match="time format"):
        describe_layout(src, report)
    assert layout_meta(src, report) is None  # the import hook never fails for it


@pytest.mark.real
@pytest.mark.parametrize(
    "parts",
    [
        ("dma-single-ship", "sample_ship.csv"),
        ("dma-single-ship", "processed_dp.csv"),
        ("mtad-dtwcm", "original", "Scene-0.csv"),
        ("mtad-dtwcm", "original", "Scene-100.csv"),
        ("mtad-v2-stats", "demo_pairs", "negative_track1.csv"),
        ("greece-ais-annotated", "vessel_5_id_annotated.csv"),
        ("oresund-encounters", "encounters.csv"),
    ],
)
def test_real_files_round_trip_byte_for_byte(parts, tmp_path):
    original = real_file(*parts)
    res = read_points(original)
    out = tmp_path / "out.csv"
    write_layout(res.points, describe_layout(original, res.report), out)
    assert out.read_bytes() == original.read_bytes()


def test_export_help(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["export", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for option in ("--like", "--layout", "--encoding", "--columns", "--renumber", "--tz"):
        assert option in out


def test_tz_refused_when_times_carry_their_zone(tmp_path, capsys):
    src = LAYOUTS / "canonical.csv"
    assert _run("export", src, "-o", tmp_path / "o.csv", "--like", src, "--tz", "+08:00") == 2
    assert "naive times only" in capsys.readouterr().err


def test_file_without_header_stays_without(write, tmp_path):
    src = write("nohead.csv", "7;1664590563;122.5;30.25\n7;1664590593;122.5;30.5\n")
    res = read_points(src, mapping=["batch=col1", "time=col2", "lon=col3", "lat=col4"])
    out = tmp_path / "out.csv"
    write_layout(res.points, describe_layout(src, res.report), out)
    assert out.read_bytes() == src.read_bytes()


def test_semicolons_quoted_cells_and_no_final_newline_come_back(write, tmp_path):
    src = write(
        "quoted.csv",
        '"track_id";"timestamp";"lat";"lon";"note"\r\n'
        '"A7";"2022-10-01 02:16:03.5";"30.25";"122.5";"say ""hi"""\r\n'
        '"A7";"2022-10-01 02:16:04";"30.5";"122.75";""',
    )
    res = read_points(src)
    layout = describe_layout(src, res.report)
    assert (layout.delimiter, layout.quoting, layout.final_newline) == (";", "all", False)
    assert layout.time.pattern == "%Y-%m-%d %H:%M:%S" and layout.time.frac_trim == "zeros"
    out = tmp_path / "out.csv"
    write_layout(res.points, layout, out)
    assert out.read_bytes() == src.read_bytes()


def test_operator_column_named_target_is_not_taken_for_a_merge(write, tmp_path):
    src = write(
        "own.csv",
        "batch,time,lon,lat,target\n7,1664590563,122.5,30.25,harbour\n8,1664590563,122.5,30.5,harbour\n",
    )
    out = tmp_path / "out.csv"
    assert _run("export", src, "-o", out, "--like", src) == 0
    assert out.read_bytes() == src.read_bytes()
    assert not (tmp_path / "out.members.csv").exists()


def test_like_takes_the_mapping_the_import_was_given(write, tmp_path):
    src = write("odd.csv", "boat,when,x,y\nA,1664590563,122.5,30.25\nA,1664590573,122.5,30.5\n")
    mapping = ["batch=boat", "time=when", "lon=x", "lat=y"]
    canonical, out = tmp_path / "c.csv", tmp_path / "out.csv"
    assert _run("import", src, "-o", canonical, *(f"--map={m}" for m in mapping)) == 0
    assert _run("export", canonical, "-o", out, "--like", src) == 2  # cannot tell the layout
    assert (
        _run("export", canonical, "-o", out, "--like", src, *(f"--map={m}" for m in mapping)) == 0
    )
    assert out.read_bytes() == src.read_bytes()


@settings(
    max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    lon=st.lists(st.floats(-179.9999, 179.9999), min_size=1, max_size=30),
    decimals=st.integers(1, 6),
    delim=st.sampled_from([";", "\t"]),
    relative=st.booleans(),
)
def test_decimal_comma_files_import_whole_and_export_back_byte_for_byte(
    tmp_path_factory, lon, decimals, delim, relative
):
    """European spreadsheet exports (``;`` between columns, ``57,6671``): every row is a
    point with the number it says, the warning counts the values, and ``--like`` writes
    the same bytes back (found by a helper: 3,300 of 3,300 DMA rows were quarantined as
    "unparsable lon")."""
    tmp = tmp_path_factory.mktemp("dc")
    n = len(lon)
    lat = [(-60.0 + 0.37 * k) for k in range(n)]
    times = (
        [f"{12.5 + 10 * k:.1f}".replace(".", ",") for k in range(n)]
        if relative
        else [f"2024-05-01T00:{k // 60:02d}:{k % 60:02d}Z" for k in range(n)]
    )
    rows = [delim.join(["mmsi", "time", "longitude", "latitude"])]
    for k in range(n):
        x = f"{lon[k]:.{decimals}f}".replace(".", ",")
        x = x.lstrip("-") if float(x.replace(",", ".")) == 0 else x  # no "-0,0" (nor "-0.0")
        y = f"{lat[k]:.{decimals}f}".replace(".", ",")
        rows.append(delim.join(["219000001", times[k], x, y]))
    src = tmp / "eu.csv"
    src.write_text("\n".join(rows) + "\n", encoding="utf-8")
    res = read_points(src)
    assert res.report["rows_imported"] == n and res.report["rows_quarantined"] == 0
    assert res.report["decimal_comma_values"] == 2 * n + (n if relative else 0)
    assert any("decimal comma" in w for w in res.report["warnings"])
    expect = np.array([float(f"{v:.{decimals}f}") for v in lon])
    got = res.points.sort_values("time", kind="stable")["lon"].to_numpy()
    np.testing.assert_allclose(got, expect, rtol=0, atol=1e-12)
    canonical, back = tmp / "c.csv", tmp / "back.csv"
    assert _run("import", src, "-o", canonical) == 0
    assert _run("export", canonical, "-o", back, "--like", src) == 0
    assert back.read_bytes() == src.read_bytes()


def test_comma_separated_files_keep_their_meaning(write):
    """In a comma-separated file a comma never means a decimal point: a quoted "57,6" is
    not a number there (quarantined and said so, not silently read as 57.6)."""
    path = write(
        "comma.csv",
        'sensor,batch,time,lon,lat\nS1,1,2024-05-01T00:00:00Z,"11,5",57.6\n'
        "S1,1,2024-05-01T00:00:10Z,11.6,57.6\n",
    )
    res = read_points(path)
    assert res.report["rows_imported"] == 1 and res.report["decimal_comma_values"] == 0
    assert res.quarantine["reason"].tolist() == ["unparsable lon"]


def test_export_writes_the_format_its_suffix_names(tmp_path, capsys):
    """-o x.geojson / x.gpx write those formats (they wrote CSV silently); a compressed
    suffix, or a CSV layout asked for a map format, is refused with a message."""
    src = tmp_path / "p.csv"
    src.write_text(
        "sensor,batch,time,lon,lat\nS1,7,2024-05-01T00:00:00Z,11.5,57.6\n"
        "S1,7,2024-05-01T00:00:10Z,11.6,57.7\n"
    )
    gj, gpx = tmp_path / "x.geojson", tmp_path / "x.gpx"
    assert _run("export", src, "-o", gj) == 0
    doc = json.loads(gj.read_text())
    assert doc["type"] == "FeatureCollection"
    assert doc["features"][0]["geometry"]["coordinates"] == [[11.5, 57.6], [11.6, 57.7]]
    assert _run("export", src, "-o", gpx) == 0 and "<gpx" in gpx.read_text()
    capsys.readouterr()
    assert _run("export", src, "-o", tmp_path / "x.csv.gz") == 2
    assert "plain text" in capsys.readouterr().err
    assert _run("export", src, "-o", tmp_path / "y.geojson", "--layout", "dma") == 2
    assert not (tmp_path / "x.csv.gz").exists() and not (tmp_path / "y.geojson").exists()


def test_export_refuses_a_spreadsheet_suffix(tmp_path, capsys):
    """Operator test: `wakeline export … -o tracks.xlsx` wrote CSV text into tracks.xlsx
    (which a spreadsheet refuses to open) and said "exported"; it is refused, naming the
    formats export writes."""
    src = tmp_path / "p.csv"
    src.write_text("sensor,batch,time,lon,lat\nS1,7,2024-05-01T00:00:00Z,11.5,57.6\n")
    for name in ("tracks.xlsx", "tracks.ods"):
        assert _run("export", src, "-o", tmp_path / name) == 2
        err = capsys.readouterr().err
        assert "write to .csv" in err and err.count("\n") == 1, err
        assert not (tmp_path / name).exists()


def test_relative_times_written_as_dates_are_warned_about(tmp_path, capsys):
    """Operator test: an MTAD scene (seconds from its start) exported --layout dma came
    out as 01/01/1970 00:00:00 … without a word; a reader takes those for January 1970.
    The export says so (not for the canonical layout, which stores them so, nor when the
    times are written as seconds)."""
    src = tmp_path / "scene.csv"
    src.write_text("MMSI,time,lat,lon,vel,cou\n7,0.0,20.1,131.2,9,90\n7,10.0,20.1,131.21,9,90\n")
    for layout, warned in (("dma", True), ("marinecadastre", True), ("canonical", False)):
        assert _run("export", src, "-o", tmp_path / f"{layout}.csv", "--layout", layout) == 0
        err = capsys.readouterr().err
        assert ("January 1970" in err) == warned, (layout, err)
    assert _run("export", src, "-o", tmp_path / "like.csv", "--like", src) == 0
    assert "January 1970" not in capsys.readouterr().err
    assert (tmp_path / "like.csv").read_text().splitlines()[1].split(",")[1] == "0.0"


@pytest.mark.parametrize(
    ("text", "utc"),
    [
        ("2024-05-01 08:01:04,123", "2024-05-01T08:01:04.123Z"),  # ISO 8601's comma
        ("2024-05-01 08:01:04 UTC", "2024-05-01T08:01:04Z"),  # the zone as a word
        ("01.05.2024 08:01:04", "2024-05-01T08:01:04Z"),  # day-first with dots
        ("01/05/2024 08:01:04 UTC", "2024-05-01T08:01:04Z"),
    ],
)
def test_more_written_times_import_and_export_back(text, utc, tmp_path, capsys):
    """Operator test: times written "08:01:04,123" (ISO 8601 allows the comma; Python's
    logging writes it), "… UTC", and "01.05.2024 08:01:04" (German, Norwegian exports)
    were every row quarantined as unparsable, and export --like could not tell their
    format. They read as what they say, and export --like writes them back byte for
    byte."""
    src = tmp_path / "t.csv"
    src.write_text(f"mmsi;timestamp;lon;lat\n7;{text};12.0;56.0\n7;{text};12.001;56.001\n")
    out, back = tmp_path / "out.csv", tmp_path / "back.csv"
    assert _run("import", src, "-o", out) == 0
    assert (
        pd.read_csv(out)["time"].iloc[0]
        == pd.Timestamp(utc).strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"
    )
    assert _run("export", out, "-o", back, "--like", src) == 0
    assert back.read_bytes() == src.read_bytes()


def test_rows_beyond_the_sampled_start_keep_their_precision(tmp_path):
    """8,000 rows with 4 decimals and whole seconds, then a vessel with 6 decimals and
    half seconds: exported like the original, every value reads back as it was (fuzzing:
    the later rows were rounded to the start's format, up to 5 m and 0.5 s off)."""
    rows = ["sensor,batch,time,lon,lat"]
    for i in range(8000):
        t = f"{i // 3600:02d}:{i // 60 % 60:02d}:{i % 60:02d}"
        rows.append(f"S1,A,2024-01-01T{t}Z,{10 + i * 1e-4:.4f},{55 + i * 1e-4:.4f}")
    for i in range(300):
        t = f"{i // 3600:02d}:{i // 60 % 60:02d}:{i % 60:02d}.500"
        rows.append(f"S1,B,2024-01-01T{t}Z,{11 + i * 1.234567e-4:.6f},{55.001234 + i * 1e-6:.6f}")
    src = tmp_path / "mix.csv"
    src.write_text("\n".join(rows) + "\n")
    assert main(["import", str(src), "-o", str(tmp_path / "i.csv")]) == 0
    assert (
        main(["export", str(tmp_path / "i.csv"), "--like", str(src), "-o", str(tmp_path / "e.csv")])
        == 0
    )
    a, b = read_points(src).points, read_points(tmp_path / "e.csv").points
    assert len(a) == len(b) == 8300
    assert (a["time"].to_numpy() == b["time"].to_numpy()).all()
    assert np.abs(a["lon"].to_numpy() - b["lon"].to_numpy()).max() < 1e-9
    assert np.abs(a["lat"].to_numpy() - b["lat"].to_numpy()).max() < 1e-9


def test_one_damaged_row_does_not_widen_a_whole_column(tmp_path):
    """A latitude out of range with 9 decimals (quarantined) and a longitude with 20
    decimals late in the file: the first widens nothing, the second at most to
    WIDEN_MAX_DECIMALS, and no value is written with float noise (review: one such row
    gave every row 20 decimals, ``10.12340000000000017977``)."""
    rows = ["batch,time,lon,lat"]
    for i in range(6000):  # the damaged rows beyond the sampled start
        rows.append(f"A,2024-01-01T{i // 3600:02d}:{i // 60 % 60:02d}:{i % 60:02d}Z,"
                    f"{10 + i * 1e-4:.4f},{55 + i * 1e-4:.4f}")  # fmt: skip
    rows.append("A,2024-01-01T02:00:00Z,10.4,95.123456789")
    rows.append("A,2024-01-01T02:00:01Z,10.12345678901234567890,55.5")
    src = tmp_path / "d.csv"
    src.write_text("\n".join(rows) + "\n")
    layout = describe_layout(src)
    assert layout.field_column("lat").number.decimals == 4
    assert layout.field_column("lon").number.decimals == WIDEN_MAX_DECIMALS
    out = tmp_path / "e.csv"
    assert main(["export", str(src), "--like", str(src), "-o", str(out)]) == 0
    text = out.read_text().splitlines()
    assert max(len(line.split(",")[2].partition(".")[2]) for line in text[1:]) <= 10
    assert ",10.0001000000," in out.read_text()  # not 10.00010000000000043
    # the same rows within the sampled start: the latitude as before, the longitude
    # written as the shortest text that reads back the same
    src.write_text("\n".join(rows[:1] + rows[-2:] + rows[1:-2]) + "\n")
    layout = describe_layout(src)
    assert layout.field_column("lat").number.decimals == 4
    assert layout.field_column("lon").number.trim.startswith("repr")


def test_quarantined_lines_do_not_set_the_number_formats(tmp_path):
    """One malformed line (``;`` for ``,``: a short row, quarantined on reading) put its
    remark under the speed column of the layout's sample, and the speed format fell back to
    the default: every ``0.0`` came back as ``0`` (operator test). Quarantined lines set no
    format, so the file comes back as it came in, less the quarantined line; a stray word
    in a number column (an unparsable value, quarantined too) sets nothing either."""
    rows = [
        "batch,time,lon,lat,speed,flag,remark",
        "2,2024-08-01 08:40:06,23.64286,37.94322,0.0,-1.0,note:STOP_START",
        "2,2024-08-01 08:41:06,23.64386,37.94322,1.5,2.5,note:STOP_END",
        "2;2024-08-01 08:41:30;23.64436,37.94322,7.96139,318.52919,note:SHORT",
        "2,2024-08-01 08:42:06,23.64486,37.94322,10.0,-1.0,note:CHANGE",
        "2,2024-08-01 08:43:06,23.64586,37.94322,0.0,-1.0,note:STOP_START",
    ]
    src = tmp_path / "one_bad_line.csv"
    src.write_text("\n".join(rows) + "\n", encoding="utf-8")
    result = read_points(src)
    assert result.report["quarantine_reasons"] == {"short row: 5 of 7 fields": 1}
    layout = Layout.from_dict(layout_meta(src, result.report))
    assert layout.field_column("speed").number == NumberFormat(1, "none")
    assert layout.field_column("lon").number == NumberFormat(5, "none")
    out = tmp_path / "back.csv"
    write_layout(result.points.sort_values("time", kind="stable"), layout, out)
    assert out.read_text(encoding="utf-8") == "\n".join(rows[:3] + rows[4:]) + "\n"
    # a word in the column: not a number format's concern
    assert NumberFormat.detect(pd.Series(["0.0", "1.5", "x", *["2.0"] * 9])) == NumberFormat(
        1, "none"
    )
    with_na = pd.Series(["0.0", "NaN", "x", *["1.5"] * 18])
    assert NumberFormat.detect(with_na) == NumberFormat(1, "none", "NaN")


def test_sensors_sharing_an_id_in_a_layout_without_sensor_column_are_warned(tmp_path, capsys):
    """AIS and two radars all with batch 007, written to a layout with no sensor column:
    read back they would be one track; the export says so (fuzzing)."""
    rows = ["sensor,batch,time,lon,lat"]
    for k, s in enumerate(("AIS", "R1", "R2")):
        rows += [
            f"{s},007,2024-01-01T00:{m:02d}:00Z,{10 + 0.05 * k + m * 1e-3:.4f},55"
            for m in range(20)
        ]
    src = tmp_path / "mixed.csv"
    src.write_text("\n".join(rows) + "\n")
    assert (
        main(["export", str(src), "--layout", "marinecadastre", "-o", str(tmp_path / "m.csv")]) == 0
    )
    err = capsys.readouterr().err
    assert "used by more than one sensor (e.g. 007: AIS, R1, R2)" in err
    assert main(["export", str(src), "--layout", "canonical", "-o", str(tmp_path / "c.csv")]) == 0
    assert "more than one sensor" not in capsys.readouterr().err


def _semicolon_file(path, comma_every: int | None, rng) -> None:
    """An AIS export with ';' between columns, fixed decimals (``23.00``, ``291.0``) and,
    every ``comma_every``-th row, decimal commas (a spreadsheet's locale on some rows)."""
    lines = ["MMSI;BaseDateTime;LAT;LON;SOG;COG"]
    t0 = pd.Timestamp("2024-08-02T00:56:14")
    for k in range(90):
        mmsi = 3 if k < 45 else 7
        row = [
            f"{37 + 0.00271 * k + rng.uniform(0, 1e-4):.5f}",
            f"{25 - 0.00712 * k:.5f}",
            f"{rng.choice([22.0, 23.0, 22.5]) + (k % 3) * 0.01:.2f}",
            f"{rng.uniform(280, 300):.1f}",
        ]
        if comma_every and k % comma_every == 0:
            row = [v.replace(".", ",") for v in row]
        when = (t0 + pd.Timedelta(minutes=k)).strftime("%Y-%m-%dT%H:%M:%S")
        lines.append(";".join([str(mmsi), when, *row]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_like_a_file_with_some_decimal_comma_rows_keeps_every_columns_digits(tmp_path, capsys):
    """Operator test 7, D10: a file whose every third row writes decimal commas lost every
    column's number format on `export --like` (`37.38980` → `37.3898`, `23.00` → `23`,
    `291.0` → `291`: 473 of 600 lines differed). Now each column keeps its digits; the
    separator most rows use is written on every row, and a note says so; only the comma
    rows differ, by their separator alone."""
    rng = np.random.default_rng(7)
    src, dots = tmp_path / "mixed.csv", tmp_path / "dots.csv"
    _semicolon_file(src, 3, rng)
    text = src.read_text(encoding="utf-8")
    dots.write_text(
        "\n".join(
            ln if k == 0 else ";".join(c.replace(",", ".") for c in ln.split(";"))
            for k, ln in enumerate(text.splitlines())
        )
        + "\n",
        encoding="utf-8",
    )
    imp, out = tmp_path / "imp.csv", tmp_path / "out.csv"
    assert main(["import", str(src), "-o", str(imp)]) == 0
    capsys.readouterr()
    assert main(["export", str(imp), "-o", str(out), "--like", str(src)]) == 0
    err = capsys.readouterr().err
    assert "30 of the first 90 rows" in err and "written with a point on every row" in err
    got = out.read_text(encoding="utf-8").splitlines()
    want = text.splitlines()
    differ = [k for k, (a, b) in enumerate(zip(got, want, strict=True)) if a != b]
    assert differ == [k for k in range(1, 91) if (k - 1) % 3 == 0]
    assert out.read_text(encoding="utf-8") == dots.read_text(encoding="utf-8")


def test_like_a_file_imported_with_tz_writes_the_zone_it_was_read_in(tmp_path, capsys):
    """Operator test 7, D15: `export --like` of a file imported with --tz wrote UTC clock
    times (2 h off) unless --tz was given again. Its first rows are IN's tracks at the
    same places one offset apart: that offset is written (a note says so), and the file
    comes back byte for byte, after clean too (IN a subset of the rows); a file read
    as UTC gets no offset."""
    rng = np.random.default_rng(8)
    src = tmp_path / "local.csv"
    _semicolon_file(src, None, rng)
    imp, out = tmp_path / "imp.csv", tmp_path / "out.csv"
    assert main(["import", str(src), "--tz", "Europe/Oslo", "-o", str(imp)]) == 0
    first = pd.read_csv(imp)["time"].iloc[0]
    assert first.startswith("2024-08-01T22:56:14")  # read as Oslo summer time
    capsys.readouterr()
    assert main(["export", str(imp), "-o", str(out), "--like", str(src)]) == 0
    err = capsys.readouterr().err
    assert "written in UTC+02:00" in err
    assert out.read_bytes() == src.read_bytes()
    # a subset of the rows (every other one) still tells the zone
    half = tmp_path / "half.csv"
    pd.read_csv(imp, dtype=str).iloc[::2].to_csv(half, index=False)
    assert main(["export", str(half), "-o", str(out), "--like", str(src)]) == 0
    assert "written in UTC+02:00" in capsys.readouterr().err
    kept = out.read_text().splitlines()
    assert set(kept) <= set(src.read_text().splitlines()) and len(kept) == 46
    # read as UTC: written as UTC, no zone note
    assert main(["import", str(src), "-o", str(imp)]) == 0
    capsys.readouterr()
    assert main(["export", str(imp), "-o", str(out), "--like", str(src)]) == 0
    assert "UTC+" not in capsys.readouterr().err
    assert out.read_bytes() == src.read_bytes()


def test_like_a_file_whose_rows_span_summer_time_asks_for_the_zone(tmp_path, capsys):
    """D15, the other case: ORIGINAL's first rows span a change to summer time (two
    offsets, neither dominant), so no fixed offset would give them back: a warning asks
    for --tz; with it, the file comes back byte for byte."""
    lines = ["MMSI;BaseDateTime;LAT;LON;SOG;COG"]
    t0 = pd.Timestamp("2024-03-30T13:00:00")  # Oslo: summer time from 31 March 02:00
    for k in range(40):  # every 2 h: 01:00 then 03:00 (02:00-03:00 is not a clock time)
        when = (t0 + pd.Timedelta(hours=2 * k)).strftime("%Y-%m-%dT%H:%M:%S")
        lines.append(f"5;{when};{59 + 0.01 * k:.5f};{10 + 0.01 * k:.5f};12.00;45.0")
    src = tmp_path / "dst.csv"
    src.write_text("\n".join(lines) + "\n", encoding="utf-8")
    imp, out = tmp_path / "imp.csv", tmp_path / "out.csv"
    assert main(["import", str(src), "--tz", "Europe/Oslo", "-o", str(imp)]) == 0
    capsys.readouterr()
    assert main(["export", str(imp), "-o", str(out), "--like", str(src)]) == 0
    err = capsys.readouterr().err
    assert "warning:" in err and "UTC+01:00" in err and "UTC+02:00" in err and "--tz" in err
    assert (
        main(["export", str(imp), "-o", str(out), "--like", str(src), "--tz", "Europe/Oslo"]) == 0
    )
    assert out.read_bytes() == src.read_bytes()

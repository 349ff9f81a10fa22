"""Import of every supported layout, encodings, delimiters, and the round trip."""

import gzip

import numpy as np
import pandas as pd
import pytest

from conftest import DATA, real_file
from wakeline.core import simulate
from wakeline.core.errors import InputError
from wakeline.core.io import label_points, read_association_table, read_points, sniff, write_points

CANONICAL = (
    "sensor,batch,time,lon,lat,speed,course\n"
    "S1,007,2022-10-01T02:16:03.000Z,122.5,30.25,12.5,45\n"
    "S1,007,2022-10-01T02:16:13.500Z,122.501,30.251,12.4,44.5\n"
    "S2,7,2022-10-01T02:16:03.000Z,122.6,30.3,,\n"
)


def test_canonical(write):
    r = read_points(write("c.csv", CANONICAL))
    p = r.points
    assert r.report["format"] == "canonical"
    assert list(p.columns) == ["sensor", "batch", "time", "lon", "lat", "speed", "course"]
    assert list(p.batch) == ["007", "007", "7"]  # text, not numbers
    assert p.time.iloc[1] == pd.Timestamp("2022-10-01T02:16:13.5Z")
    assert str(p.time.dtype) == "datetime64[ns, UTC]"
    assert np.isnan(p.speed.iloc[2])
    assert r.report["tracks"] == 2
    assert len(r.quarantine) == 0


def test_round_trip_is_identical(tmp_path):
    scene = simulate.multisensor_scene(seed=3, n_ships=4)
    first = tmp_path / "a.csv"
    second = tmp_path / "b.csv"
    write_points(scene, first)
    result = read_points(first)
    write_points(result.points, second)
    assert first.read_bytes() == second.read_bytes()
    assert len(result.points) == len(scene)


def test_round_trip_keeps_text_that_needs_quotes(tmp_path, write):
    src = write(
        "q.csv",
        'sensor,batch,time,lon,lat,name\nS1,"A,1",2024-01-01T00:00:00.000Z,1,2,"say ""hi"""\n',
    )
    result = read_points(src)
    assert result.points.batch.iloc[0] == "A,1"
    assert result.points.name.iloc[0] == 'say "hi"'
    out = tmp_path / "out.csv"
    write_points(result.points, out)
    again = read_points(out)
    pd.testing.assert_frame_equal(again.points, result.points)


def test_radar_export(write):
    text = (
        "SendShipNO,SendTime,nNO,lon,lat,speed,course\n"
        "3,1664590563,12,122.1,30.1,10.2,90\n3,1664590573,12,122.101,30.1,10.3,90.5\n"
    )
    r = read_points(write("radar.csv", text))
    assert r.report["format"] == "radar"
    p = r.points
    assert list(p.sensor.unique()) == ["3"] and list(p.batch.unique()) == ["12"]
    assert p.time.iloc[0] == pd.Timestamp("2022-10-01T02:16:03Z")
    assert p.speed.tolist() == [10.2, 10.3]


def test_radar_export_in_milliseconds(write):
    r = read_points(
        write("radar.csv", "SendShipNO,SendTime,nNO,lon,lat\n3,1664590563250,12,122.1,30.1\n")
    )
    assert r.points.time.iloc[0] == pd.Timestamp("2022-10-01T02:16:03.25Z")


def test_ais_marinecadastre(write):
    text = (
        "MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO\n"
        "367123450,2024-01-01T00:00:05,29.5,-94.1,11.2,181.3,180,SEA STAR,IMO123\n"
        "367123450,2024-01-01T00:01:05,29.49,-94.1,11.1,181.0,180,SEA STAR,IMO123\n"
    )
    r = read_points(write("mc.csv", text))
    assert r.report["format"] == "ais-marinecadastre"
    p = r.points
    assert p.batch.iloc[0] == "367123450"
    assert p.lat.iloc[0] == 29.5 and p.lon.iloc[0] == -94.1
    assert p.speed.iloc[0] == 11.2 and p.course.iloc[0] == 181.3
    assert p.time.iloc[0] == pd.Timestamp("2024-01-01T00:00:05Z")
    assert p.VesselName.iloc[0] == "SEA STAR"  # extra columns carried through


def test_ais_dma_day_first(write):
    text = (
        "# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,Heading\n"
        "01/03/2023 00:01:46,Class A,220614000,57.6671,11.8045,Under way,0.0,9.1,45.2,44\n"
        "13/03/2023 10:01:46,Class A,220614000,57.6672,11.8046,Under way,0.0,9.0,45.0,44\n"
    )
    r = read_points(write("dma.csv", text))
    assert r.report["format"] == "ais-dma"
    assert list(r.points.time) == [
        pd.Timestamp("2023-03-01T00:01:46Z"),
        pd.Timestamp("2023-03-13T10:01:46Z"),
    ]
    assert r.points.speed.tolist() == [9.1, 9.0]


def _month_first_text(rows: int = 200) -> str:
    """A generic AIS file whose times write the month first (US: 05/17/2024 08:00:00),
    one fix every 2 h from 1 May: days up to 12 for the first 132 rows."""
    t0 = pd.Timestamp("2024-05-01 08:00:00")
    lines = [
        f"366{k % 3},{(t0 + pd.Timedelta(hours=2 * k)).strftime('%m/%d/%Y %H:%M:%S')},"
        f"{-70 + k * 1e-3:.4f},{41 + k * 1e-3:.4f}"
        for k in range(rows)
    ]
    return "mmsi,timestamp,lon,lat\n" + "\n".join(lines) + "\n"


def test_month_first_times_are_read_month_first(write, tmp_path, monkeypatch):
    """Operator test: a file of US times (mm/dd/yyyy) was read day-first: its first 132
    rows (days up to 12) landed months away, 1 May as 5 January, and the other 68 were
    quarantined as unparsable. The file shows the order (a second number above 12, no
    first one): read so, with a warning, streamed or whole (a streamed piece holding only
    days up to 12 cannot tell alone), and written back so by export --like."""
    from wakeline.app.cli import main
    from wakeline.core.io import import_to_csv, reader

    src = write("us.csv", _month_first_text())
    want = pd.Timestamp("2024-05-01T08:00:00Z") + pd.to_timedelta(2 * np.arange(200), unit="h")
    r = read_points(src)
    assert r.report["rows_quarantined"] == 0 and r.report["time_format"] == "month-first text"
    assert sorted(r.points["time"]) == list(want)
    assert any("month first" in w for w in r.report["warnings"])
    monkeypatch.setattr(reader, "STREAM_BYTES", 2000)  # the first pieces: days up to 12
    out = tmp_path / "out.csv"
    streamed = import_to_csv(src, out)
    assert streamed.report["rows_quarantined"] == 0
    assert sorted(pd.to_datetime(pd.read_csv(out)["time"])) == list(want)
    back = tmp_path / "back.csv"
    assert main(["export", str(out), "-o", str(back), "--like", str(src)]) == 0
    assert back.read_text().splitlines()[1:3] == src.read_text().splitlines()[1:3]
    # Day-first stays day-first (13/05/2024), and a file that cannot tell (no number
    # above 12) is read day-first as documented.
    day = write("eu.csv", "mmsi,timestamp,lon,lat\n1,13/05/2024 08:00:00,10,55\n")
    assert read_points(day).points["time"].iloc[0] == pd.Timestamp("2024-05-13T08:00:00Z")
    both = write("amb.csv", "mmsi,timestamp,lon,lat\n1,05/01/2024 08:00:00,10,55\n")
    assert read_points(both).points["time"].iloc[0] == pd.Timestamp("2024-01-05T08:00:00Z")


def test_times_written_as_digits_alone(write, tmp_path, monkeypatch):
    """Operator test: times written yyyymmddHHMMSS (20240501080104, as some radar and
    logger exports do) were read as unix milliseconds and every row quarantined as "time
    outside 1677-2262". 14-digit whole numbers cannot be unix times Wakeline reads: they
    are read as the clock time they spell (UTC, or --tz), whole and streamed; one that
    spells no time is quarantined as unparsable; export --like writes them back so."""
    from wakeline.app.cli import main
    from wakeline.core.io import import_to_csv, reader

    t0 = pd.Timestamp("2024-05-01 08:00:00")
    times = [(t0 + pd.Timedelta(seconds=37 * k)).strftime("%Y%m%d%H%M%S") for k in range(120)]
    times[60] = "20241341250000"  # month 13: no time
    rows = [f"7,{t},{12 + k * 1e-3:.4f},56.0" for k, t in enumerate(times)]
    src = write("compact.csv", "mmsi,timestamp,lon,lat\n" + "\n".join(rows) + "\n")
    want = [pd.Timestamp(t, tz="UTC") for k, t in enumerate(times) if k != 60]
    r = read_points(src)
    assert r.report["time_format"] == "yyyymmddHHMMSS text"
    assert list(r.points["time"]) == want
    assert r.quarantine["line"].tolist() == [62]
    assert r.quarantine["reason"].tolist() == ["unparsable time"]
    local = read_points(src, tz="Europe/Copenhagen")  # CEST: UTC+2
    assert local.points["time"].iloc[0] == pd.Timestamp("2024-05-01T06:00:00Z")
    monkeypatch.setattr(reader, "STREAM_BYTES", 1000)
    out = tmp_path / "out.csv"
    assert import_to_csv(src, out).report["rows_quarantined"] == 1
    assert list(pd.to_datetime(pd.read_csv(out)["time"])) == want
    back = tmp_path / "back.csv"
    assert main(["export", str(out), "-o", str(back), "--like", str(src)]) == 0
    assert back.read_text().splitlines()[1:4] == src.read_text().splitlines()[1:4]
    # Unix milliseconds (13 digits today) stay unix milliseconds.
    ms = write("ms.csv", "mmsi,timestamp,lon,lat\n7,1714550464000,12.0,56.0\n")
    assert read_points(ms).points["time"].iloc[0] == pd.Timestamp("2024-05-01T08:01:04Z")


def test_delimiter_as_typed_on_a_command_line(write, tmp_path, capsys):
    """Operator test: `--delimiter '\\t'` (the shell passes backslash-t) and `--delimiter
    tab` read a tab-separated file as one column ("missing required column …, headers
    found: mmsi<TAB>timestamp…"); `--delimiter ';;'` was taken too. The words for a tab
    are understood, anything longer than a character is refused by name."""
    from wakeline.app.cli import main

    src = write("tab.csv", "mmsi\ttimestamp\tlon\tlat\n7\t2024-05-01T00:00:00Z\t11.5\t57.6\n")
    for given in ("\\t", "tab", "\t"):
        assert len(read_points(src, delimiter=given).points) == 1
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--delimiter", ";;"]) == 2
    assert "--delimiter ';;': give one character" in capsys.readouterr().err


def test_mtad_measurement_and_association_table(write):
    meas = (
        "batch,source,time,lat,lon,vel,cou\n"
        "1,9001,0,20.1,131.2,9.5,90\n1,9001,10,20.1,131.21,9.5,90\n"
        "4,9002,5,20.1,131.2,9.4,91\n4,9002,2000,20.2,131.3,9.4,91\n"
    )
    r = read_points(write("场景-1.csv", meas))
    assert r.report["format"] == "mtad-measurement"
    p = r.points
    assert sorted(p.sensor.unique()) == ["9001", "9002"]
    assert p.time.iloc[1] == pd.Timestamp("1970-01-01T00:00:10Z")
    assert p.course.iloc[0] == 90 and "vel" in p.columns  # vel's unit varies in MTAD: kept as is
    table = read_association_table(
        write(
            "关联结果-1.csv",
            "t_s,t_e,mmsi,source,batch\n0,100,412-0-0,9001,1\n0,1000,412-0-1,9002,4\n",
        )
    )
    truth = label_points(p, table)
    assert truth.tolist() == ["412-0-0", "412-0-0", "412-0-1", ""]


def test_mtad_two_sensor_layout_takes_mmsi_as_truth(write):
    text = "mmsi,time,lat,lon,vel,cou,batch\n413804828-0,913.7,20.12,131.22,9.2,278.6,0\n"
    r = read_points(write("scene-0_error_1_AIS.csv", text), sensor="9001")
    assert r.report["format"] == "mtad-scene"
    assert r.points.batch.iloc[0] == "0" and r.points.truth.iloc[0] == "413804828-0"
    assert r.points.sensor.iloc[0] == "9001"


def test_explicit_mapping_semicolons_and_timezones(write):
    text = "id;when;x;y\nA;2022-10-01T10:16:03+08:00;122.5;30.2\nA;2022-10-01T10:16:13+08:00;122.5;30.3\n"
    path = write("odd.csv", text)
    with pytest.raises(InputError, match="missing required column"):
        read_points(path)
    r = read_points(path, mapping=["batch=id", "time=when", "lon=x", "lat=y"])
    assert r.report["delimiter"] == ";"
    assert r.points.time.iloc[0] == pd.Timestamp("2022-10-01T02:16:03Z")
    assert r.points.lon.tolist() == [122.5, 122.5]


def test_tab_delimited_headerless_file_with_mapping(write):
    text = "5\t23.48402\t37.35515\t1722468684\n5\t23.48502\t37.35615\t1722468744\n"
    path = write("vessels.tsv", text)
    sn = sniff(path)
    assert (
        sn.delimiter == "\t"
        and not sn.has_header
        and sn.columns == ("col1", "col2", "col3", "col4")
    )
    r = read_points(path, mapping={"batch": "col1", "lon": "col2", "lat": "col3", "time": "col4"})
    assert len(r.points) == 2 and r.points.batch.iloc[0] == "5"
    assert r.points.time.iloc[0] == pd.Timestamp(1722468684, unit="s", tz="UTC")


@pytest.mark.parametrize("encoding", ["utf-8", "utf-8-sig", "gb18030", "gbk"])
def test_encodings(write, encoding):
    text = (
        "sensor,batch,time,lon,lat,船名\n雷达1,甲-001,2024-01-01T00:00:00Z,122.5,30.2,浙渔养12345\n"
    )
    r = read_points(write(f"enc-{encoding}.csv", text, encoding=encoding))
    p = r.points
    assert (
        p.sensor.iloc[0] == "雷达1"
        and p.batch.iloc[0] == "甲-001"
        and p["船名"].iloc[0] == "浙渔养12345"
    )
    assert r.report["encoding"] == ("gb18030" if encoding in ("gb18030", "gbk") else "utf-8")


def test_gzip_input(tmp_path):
    path = tmp_path / "c.csv.gz"
    with gzip.open(path, "wt", encoding="utf-8") as fh:
        fh.write(CANONICAL)
    r = read_points(path)
    assert r.report["compression"] == "gzip" and len(r.points) == 3


def test_crlf_and_blank_lines(write):
    text = CANONICAL.replace("\n", "\r\n").replace("S2,", "\r\nS2,")
    r = read_points(write("crlf.csv", text))
    assert len(r.points) == 3 and r.report["blank_lines"] == 1 and len(r.quarantine) == 0
    assert r.points.batch.iloc[0] == "007"


@pytest.mark.parametrize("streamed", [False, True])
def test_an_unreadable_speed_or_course_is_blanked_not_the_fix(write, tmp_path, streamed):
    """Operator test: a row whose course was written "-" (or speed "unknown") was quarantined
    as "unparsable course": a good fix lost for an attribute that is derived from the
    positions where missing. The value is blanked, the row kept and the blank counted
    (as a course outside [0, 360) is); an unreadable position still quarantines."""
    from wakeline.app.cli import main
    from wakeline.core.io import import_to_csv

    text = (
        "mmsi,timestamp,lon,lat,sog,cog\n"
        "7,2024-05-01T08:00:00Z,12.0,56.0,9.5,-\n"
        "7,2024-05-01T08:01:00Z,12.001,56.001,unknown,45\n"
        "7,2024-05-01T08:02:00Z,12.002,56.002,9.5,511\n"
        "7,2024-05-01T08:03:00Z,x,56.003,9.5,45\n"
    )
    path = write("dash.csv", text)
    if streamed:
        r = import_to_csv(path, tmp_path / "o.csv")
        points = pd.read_csv(tmp_path / "o.csv")
    else:
        r = read_points(path)
        points = r.points
    assert len(points) == 3 and r.quarantine["reason"].tolist() == ["unparsable lon"]
    assert points["course"].isna().tolist() == [True, False, True]
    assert points["speed"].isna().tolist() == [False, True, False]
    assert r.report["values_blanked"] == {
        "unparsable speed": 1,
        "unparsable course": 1,
        "course outside [0, 360)": 1,
    }
    if not streamed:
        import contextlib
        import io

        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            assert main(["import", str(path), "-o", str(tmp_path / "c.csv")]) == 0
        assert "values blanked, their rows kept: unparsable speed 1" in err.getvalue()


def test_real_atd2025_sample():
    r = read_points(DATA / "atd2025_example_sample.csv")
    assert r.report["format"] == "generic"
    assert r.report["columns"]["batch"] == "track_id"
    assert r.report["tracks"] == 42
    assert r.report["rows_imported"] == 1590
    assert r.report["values_blanked"] == {"course outside [0, 360)": 1}
    assert r.points.time.min() == pd.Timestamp("2024-01-01T00:00:01Z")
    assert {"point_id", "point_id_original"} <= set(r.points.columns)


@pytest.mark.real
def test_real_atd2025_full_file():
    r = read_points(real_file("atd2025-noaa", "dataset1_truth.csv.gz"))
    assert r.report["rows_imported"] == 102_861 and r.report["tracks"] == 5_620
    assert r.report["rows_quarantined"] == 0


@pytest.mark.real
def test_real_mtad_scene_with_bom():
    r = read_points(real_file("mtad-dtwcm", "original", "Scene-0.csv"))
    assert r.report["format"] == "mtad-scene"
    assert r.report["rows_imported"] == 1549
    assert r.points.batch.str.contains("-").all()


@pytest.mark.real
def test_real_mtad_demo_pairs_have_sources():
    r = read_points(real_file("mtad-v2-stats", "demo_pairs", "positive_track2.csv"))
    assert list(r.points.sensor.unique()) == ["9002"] and r.report["rows_imported"] == 94


@pytest.mark.real
def test_real_dma_single_ship_day_first():
    r = read_points(real_file("dma-single-ship", "sample_ship.csv"))
    assert r.report["rows_imported"] == 3300
    assert r.points.time.min() == pd.Timestamp("2023-03-01T00:01:46Z")
    assert r.points.time.max() == pd.Timestamp("2023-03-01T23:59:51Z")


@pytest.mark.real
def test_real_greece_space_separated():
    r = read_points(real_file("greece-ais-annotated", "vessel_1_id_annotated.csv"))
    assert r.report["delimiter"] == " "
    assert r.report["rows_imported"] == 9427
    raw = read_points(
        real_file("greece-ais-annotated", "vessels.csv"),
        mapping={"batch": "col1", "lon": "col2", "lat": "col3", "time": "col4"},
    )
    assert raw.report["rows_imported"] == 18_834 and raw.report["tracks"] == 5


@pytest.mark.real
def test_real_oresund():
    r = read_points(real_file("oresund-encounters", "encounters.csv"))
    assert r.report["rows_imported"] == 664 and r.points.speed.notna().all()

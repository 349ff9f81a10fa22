"""``export --like`` writes GPS time back as the file had it (h159): GPS week and seconds
of the week (header-recognised, or ``--map gps_week= --map gps_seconds=``), or GPS seconds
since 1980-01-06, in the seconds' number style, the leap seconds added back as the reader
took them off. Before, the seconds column got unix seconds (``2295,1704067200``)."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_import_gps_time import _gps
from wakeline.app.cli import main
from wakeline.core.io import read_points
from wakeline.core.io.export_like import format_gps, write_layout
from wakeline.core.io.layout import Layout, NumberFormat, TimeFormat, describe_layout

#: several weeks (2295 ends in track 1; 2297), fractions trimmed as the file writes them
WEEKS = (
    "gps_week,gps_seconds,id,lat,lon\n"
    "2295,604790.5,1,37.9,23.6\n"
    "2295,604795.25,1,37.91,23.61\n"
    "2295,604799.75,1,37.92,23.62\n"
    "2296,0.125,1,37.93,23.63\n"
    "2296,4,1,37.94,23.64\n"
    "2297,3600,2,37.95,23.65\n"
    "2297,3610.5,2,37.96,23.66\n"
    "2297,3620.875,2,37.97,23.67\n"
)
#: fixed decimals, other headers the reader knows (GPSWeek, TOW (s)), CRLF
FIXED = (
    "GPSWeek;TOW (s);id;lat;lon\r\n"
    "2295;86418.000;1;37.9;23.6\r\n"
    "2295;86428.500;1;37.91;23.61\r\n"
    "2296;86418.250;2;37.92;23.62\r\n"
    "2296;86428.125;2;37.93;23.63\r\n"
)
#: GPS seconds since 1980-01-06, two weeks apart
SINCE_1980 = (
    "gps_time,id,lat,lon\n"
    "1388102418.000,1,37.9,23.6\n"
    "1388102428.500,1,37.91,23.61\n"
    "1388707218.250,2,37.92,23.62\n"
    "1388707228.125,2,37.93,23.63\n"
)
#: columns no name shows as GPS time, read with --map
MAPPED = WEEKS.replace("gps_week,gps_seconds", "W,S")
GPS_MAP = ["--map", "gps_week=W", "--map", "gps_seconds=S"]


@pytest.mark.parametrize(
    "text, flags",
    [(WEEKS, []), (FIXED, []), (SINCE_1980, []), (MAPPED, GPS_MAP)],
    ids=["weeks", "fixed", "since_1980", "mapped"],
)
def test_import_then_export_like_gives_the_same_bytes(tmp_path, text, flags):
    src = tmp_path / "gps.csv"
    src.write_bytes(text.encode())
    out = tmp_path / "back.csv"
    in_map = [f.replace("--map", "--in-map") for f in flags]
    main(["export", str(src), "-o", str(out), "--like", str(src), *flags, *in_map])
    assert out.read_bytes() == src.read_bytes()
    # through the canonical CSV in between (wakeline import, then export --like)
    canonical = tmp_path / "canonical.csv"
    main(["import", str(src), "-o", str(canonical), *flags])
    assert "2024-01-0" in canonical.read_text()  # canonical: ISO times
    main(["export", str(canonical), "-o", str(out), "--like", str(src), *flags])
    assert out.read_bytes() == src.read_bytes()


def test_the_layout_from_the_import_report_and_its_json(tmp_path):
    """The window's layer keeps the layout learnt from the import's report (its
    ``time_gps_week``); the JSON keeps it; a report without the key (before h159)
    finds the week column by its name."""
    src = tmp_path / "gps.csv"
    src.write_text(MAPPED)
    r = read_points(src, mapping=["gps_week=W", "gps_seconds=S"])
    assert r.report["time_gps_week"] == "W"
    layout = Layout.from_dict(describe_layout(src, r.report).to_dict())
    assert layout.time.kind == "gps_week" and layout.field_column("gps_week").name == "W"
    assert layout.time.number == NumberFormat(3, "zeros")
    write_layout(r.points, layout, tmp_path / "out.csv")
    assert (tmp_path / "out.csv").read_text() == MAPPED
    src.write_text(WEEKS)
    r = read_points(src)
    old = {k: v for k, v in r.report.items() if k != "time_gps_week"}
    assert describe_layout(src, old).field_column("gps_week").name == "gps_week"
    src.write_text(SINCE_1980)
    r = read_points(src)
    assert r.report["time_gps_week"] == ""
    assert describe_layout(src, r.report).time.kind == "gps"
    src.write_text("time,id,lat,lon\n2024-01-01T00:00:00Z,1,37.9,23.6\n")
    assert "time_gps_week" not in read_points(src).report  # other files: no new key


def test_the_streamed_import_reports_the_week_column(tmp_path, monkeypatch):
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    src = tmp_path / "gps.csv"
    src.write_text(WEEKS)
    monkeypatch.setattr(reader, "STREAM_BYTES", 100)
    rep = import_to_csv(src, tmp_path / "c.csv").report
    assert rep.get("streamed") and rep["time_gps_week"] == "gps_week"


def test_a_moved_or_made_point_gets_its_week_from_its_time(tmp_path):
    """The week column is written from the time (not carried): a point a step moved
    over a week's end, or made by one, has its own week."""
    src = tmp_path / "gps.csv"
    src.write_text(WEEKS)
    r = read_points(src)
    points = r.points.copy()
    points.loc[0, "time"] += pd.Timedelta(seconds=20)  # 604790.5 + 20 s: next week's 10.5
    write_layout(points, describe_layout(src, r.report), tmp_path / "out.csv")
    assert (tmp_path / "out.csv").read_text().splitlines()[1] == "2296,10.5,1,37.9,23.6"


def test_rounding_to_the_decimals_carries_into_the_next_week():
    t = pd.Series(pd.to_datetime(["2024-01-06T23:59:41.9996Z", None], utc=True, format="ISO8601"))
    tf = TimeFormat("gps_week", suffix="", number=NumberFormat(3, "none"))
    assert format_gps(t, tf).to_pylist() == ["0.000", ""]
    assert format_gps(t, tf, NumberFormat(0, "none")).to_pylist() == ["2296", ""]


def test_leap_seconds_are_added_back_as_the_reader_took_them_off():
    """Across 2017-01-01 (GPS - UTC 17 -> 18 s) and back to 1981: each UTC second is
    written as the GPS second that reads back to it (the reader's table, against a list
    of the leap dates written apart from it)."""
    utc = pd.to_datetime(
        [
            "1981-06-30T23:59:59Z",
            "1981-07-01T00:00:00Z",
            "2016-12-31T23:59:59.5Z",
            "2017-01-01T00:00:00Z",
            "2024-01-01T00:00:00Z",
        ],
        utc=True,
        format="ISO8601",
    )
    tf = TimeFormat("gps", suffix="", number=NumberFormat(1, "none"))
    want = [f"{_gps(t):.1f}" for t in utc]
    assert format_gps(pd.Series(utc), tf).to_pylist() == want
    assert want[3] == f"{float(want[2]) + 1.5:.1f}"  # 18 s from then on, no second skipped


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seconds=st.integers(0, 50 * 365 * 86_400), ms=st.integers(0, 999))
def test_any_instant_is_written_as_the_gps_time_that_reads_back_to_it(seconds, ms):
    from wakeline.core.io.reader import gps_ns

    t = pd.Timestamp("1980-01-06", tz="UTC") + pd.Timedelta(seconds=seconds, milliseconds=ms)
    g = round(_gps(t), 3)
    number = NumberFormat(3, "none")
    times = pd.Series([t])
    week = format_gps(times, TimeFormat("gps_week", number=number), NumberFormat(0, "none"))
    sow = format_gps(times, TimeFormat("gps_week", number=number))
    since = format_gps(times, TimeFormat("gps", number=number))
    assert int(week[0].as_py()) == int(g // 604800)
    assert sow[0].as_py() == f"{g - 604800 * (g // 604800):.3f}"
    assert since[0].as_py() == f"{g:.3f}"
    ns, ok, _ = gps_ns(np.array([float(sow[0].as_py())]), np.array([float(week[0].as_py())]))
    assert ok.all() and abs(int(ns[0]) - t.value) < 1_000  # to the ns a float holds
    again = pd.Series([pd.Timestamp(int(ns[0]), tz="UTC")])  # read, written again: same text
    assert format_gps(again, TimeFormat("gps_week", number=number)) == sow

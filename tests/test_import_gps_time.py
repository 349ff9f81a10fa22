"""GPS times (h134): a GPS week column with seconds of the week (``gps_week`` +
``gps_seconds`` / ``tow``), or GPS seconds since 1980-01-06 (``gps_time``), read as UTC
with the leap seconds (GPS - UTC = 18 s since 2017-01-01)."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_import_spaced_pipe_nmea import _lines_accounted, _three_ways
from wakeline.core.io import read_points

#: Leap seconds (UTC dates after which GPS - UTC grew by one), written out apart from the
#: reader's table.
LEAP_DATES = (
    "1981-07-01 1982-07-01 1983-07-01 1985-07-01 1988-01-01 1990-01-01 1991-01-01 "
    "1992-07-01 1993-07-01 1994-07-01 1996-01-01 1997-07-01 1999-01-01 2006-01-01 "
    "2009-01-01 2012-07-01 2015-07-01 2017-01-01"
).split()


def _gps(t: pd.Timestamp) -> float:
    leap = sum(t >= pd.Timestamp(d, tz="UTC") for d in LEAP_DATES)
    return (t - pd.Timestamp("1980-01-06", tz="UTC")).total_seconds() + leap


def test_week_and_seconds_of_the_week(tmp_path, monkeypatch):
    times = pd.date_range("2024-01-01", periods=40, freq="7s", tz="UTC")
    rows = ["gps_week,gps_seconds,id,lat,lon"]
    for k, t in enumerate(times):
        g = _gps(t)
        rows.append(f"{int(g // 604800)},{g % 604800:.1f},{1 + k % 2},37.{k:04d},23.6")
    src = tmp_path / "gps.csv"
    src.write_text("\n".join(rows) + "\n")
    r = _three_ways(src, tmp_path, monkeypatch)
    assert r.report["rows_quarantined"] == 0
    assert sorted(r.points["time"]) == list(times)
    assert rows[1].startswith("2295,86418.0")  # 2024-01-01 00:00:00 UTC is 00:00:18 GPS
    assert r.report["time_format"] == "GPS week and seconds of week"
    assert any("18 s since 2017" in w for w in r.report["warnings"])


@pytest.mark.parametrize(
    "header", ["GPSWeek,TOW (s)", "week,time_of_week", "gps_wk,gps_tow", "WN,sow"]
)
def test_headers_that_name_gps_week_and_seconds(tmp_path, header):
    src = tmp_path / "gps.csv"
    src.write_text(f"{header},id,lat,lon\n2295,86418.5,1,37.9,23.6\n")
    r = read_points(src)
    assert r.points["time"].tolist() == [pd.Timestamp("2024-01-01 00:00:00.5", tz="UTC")]


def test_gps_seconds_since_the_epoch_and_bad_rows(tmp_path):
    src = tmp_path / "gps.csv"
    src.write_text(
        "gps_time,id,lat,lon\n"
        "1356998418,1,37.9,23.6\n"  # 2023-01-06 00:00:18 GPS
        "86418.0,1,37.9,23.6\n"  # seconds of a week, but which week?
        ",1,37.9,23.6\n"
    )
    r = read_points(src)
    _lines_accounted(r, src)
    assert r.points["time"].tolist() == [pd.Timestamp("2023-01-06", tz="UTC")]
    assert r.quarantine["reason"].tolist() == [
        "GPS seconds of the week in 'gps_time' (below 604,800) without a week column "
        "(gps_week): the week is unknown",
        "missing time",
    ]


def test_bad_weeks_and_seconds_are_quarantined(tmp_path):
    src = tmp_path / "gps.csv"
    src.write_text(
        "gps_week,tow,id,lat,lon\n"
        "2295,86418,1,37.9,23.6\n"
        ",86428,1,37.9,23.6\n"
        "2295,604800,1,37.9,23.6\n"
        "2295.5,10,1,37.9,23.6\n"
        "2295,,1,37.9,23.6\n"
        "2295,abc,1,37.9,23.6\n"
    )
    r = read_points(src)
    _lines_accounted(r, src)
    assert len(r.points) == 1
    reasons = r.quarantine.set_index("line")["reason"].to_dict()
    assert reasons[3] == "missing GPS week ('gps_week')"
    assert reasons[4].startswith("GPS week or seconds of the week out of range")
    assert reasons[5].startswith("GPS week or seconds of the week out of range")
    assert reasons[6] == "missing time"
    assert reasons[7] == "unparsable time"


def test_ten_bit_weeks_are_said(tmp_path):
    src = tmp_path / "gps.csv"
    src.write_text("gps_week,tow,id,lat,lon\n247,86418,1,37.9,23.6\n")  # 2295 - 2048
    r = read_points(src)
    assert any("modulo 1024" in w for w in r.report["warnings"])


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seconds=st.integers(0, 45 * 365 * 86_400), ms=st.integers(0, 999))
def test_any_instant_reads_back(seconds, ms):
    from wakeline.core.io.reader import gps_ns

    t = pd.Timestamp("1981-01-01", tz="UTC") + pd.Timedelta(seconds=seconds, milliseconds=ms)
    g = round(_gps(t), 3)
    ns, ok, _ = gps_ns(np.array([g % 604800]), np.array([float(g // 604800)]))
    assert ok.all() and abs(int(ns[0]) - t.value) < 1_000  # to the µs a float holds
    ns, ok, _ = gps_ns(np.array([g]), None)
    assert ok.all() and abs(int(ns[0]) - t.value) < 1_000


def test_milliseconds_of_the_week_are_not_read_as_seconds(tmp_path):
    """``gps_ms`` (u-blox's iTOW is milliseconds of the week) is no GPS seconds column:
    300,000 ms (5 min into the week) read as seconds was 3.5 days into it, silently."""
    from wakeline.core.errors import InputError

    src = tmp_path / "itow.csv"
    src.write_text("gps_week,gps_ms,id,lat,lon\n2295,300000,1,37.9,23.6\n")
    with pytest.raises(InputError, match="time"):
        read_points(src)


# --- --map gps_week=COLUMN, gps_seconds=COLUMN (h149) ---------------------------------------

_PLAIN_NAMES = "W,S,id,lat,lon\n2295,86418,1,37.9,23.6\n2295,86428.5,1,37.9,23.6\n"
_T = [pd.Timestamp("2024-01-01", tz="UTC"), pd.Timestamp("2024-01-01 00:00:10.5", tz="UTC")]


def test_week_and_seconds_columns_are_mapped(tmp_path, monkeypatch):
    """Columns no name shows as GPS time (`W`, `S`) are read so when mapped: before, the
    only way to read them was to rename the columns (`--map` knew no week field, and
    `--map time=S` read seconds of the week as relative seconds)."""
    src = tmp_path / "gps.csv"
    src.write_text(_PLAIN_NAMES)
    r = read_points(src, mapping=["gps_week=W", "gps_seconds=S"])
    assert r.points["time"].tolist() == _T
    assert r.report["time_format"] == "GPS week and seconds of week"
    assert r.points["W"].tolist() == ["2295", "2295"]  # the week travels as an extra column
    # GPS seconds since 1980-01-06 alone
    src.write_text("S,id,lat,lon\n1356998418,1,37.9,23.6\n")
    r = read_points(src, mapping=["gps_seconds=S"])
    assert r.points["time"].tolist() == [pd.Timestamp("2023-01-06", tz="UTC")]
    assert r.report["time_format"] == "GPS seconds since 1980-01-06"


def test_one_of_the_pair_mapped_takes_the_other_by_its_name(tmp_path):
    src = tmp_path / "gps.csv"
    src.write_text("gps_week,S,id,lat,lon\n2295,86418,1,37.9,23.6\n")
    r = read_points(src, mapping=["gps_seconds=S"])
    assert r.points["time"].tolist() == _T[:1]
    src.write_text("W,tow,id,lat,lon\n2295,86418,1,37.9,23.6\n")
    r = read_points(src, mapping=["gps_week=W"])
    assert r.points["time"].tolist() == _T[:1]


def test_gps_mappings_that_cannot_be_read_are_refused(tmp_path):
    from wakeline.core.errors import InputError

    src = tmp_path / "gps.csv"
    src.write_text(_PLAIN_NAMES)
    with pytest.raises(InputError, match="add --map gps_seconds=COLUMN"):
        read_points(src, mapping=["gps_week=W"])
    with pytest.raises(InputError, match="the time is one or the other"):
        read_points(src, mapping=["gps_seconds=S", "time=S"])
    with pytest.raises(InputError, match="mapped column.*not found: gps_week=X"):
        read_points(src, mapping=["gps_week=X", "gps_seconds=S"])
    with pytest.raises(InputError, match="fields are .*gps_week, gps_seconds"):
        read_points(src, mapping=["gps=W"])


def test_cli_map_gps_columns(tmp_path, capsys):
    from wakeline.app.cli import main

    src = tmp_path / "gps.csv"
    src.write_text(_PLAIN_NAMES)
    out = tmp_path / "out.csv"
    main(["import", str(src), "-o", str(out), "--map", "gps_week=W", "--map", "gps_seconds=S"])
    said = capsys.readouterr()
    assert "GPS week and seconds of week" in said.out + said.err
    assert pd.read_csv(out)["time"].tolist() == [
        "2024-01-01T00:00:00.000Z",
        "2024-01-01T00:00:10.500Z",
    ]


def test_the_detected_mapping_names_gps_fields_so_mapping_it_again_reads_gps(tmp_path):
    """`inspect_file` (the File ▸ Open dialog's detection) gave a GPS file's mapping as
    `time=tow`; the dialog hands every box to the import, and `--map time=tow` read the
    seconds of the week as relative seconds (1970-01-02). It now gives gps_week and
    gps_seconds, which read GPS time."""
    from wakeline.core.io.reader import inspect_file

    src = tmp_path / "gps.csv"
    src.write_text("gps_week,tow,id,lat,lon\n2295,86418,1,37.9,23.6\n")
    mapping = inspect_file(src)["mapping"]
    assert mapping["gps_week"] == "gps_week" and mapping["gps_seconds"] == "tow"
    assert "time" not in mapping
    r = read_points(src, mapping=[f"{k}={v}" for k, v in mapping.items()])
    assert r.points["time"].tolist() == _T[:1]

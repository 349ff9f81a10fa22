"""Issue 14: no silent loss, any encoding and line ending, real headers, time zones, NMEA
logs, output checks. Files of the battery are in tests/data/battery."""

import os
import stat
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import DATA
from wakeline.core.errors import InputError
from wakeline.core.export import spreadsheet_safe
from wakeline.core.io import read_points, sniff
from wakeline.core.io.writer import check_outputs, remove_stale_parts, write_csv

BATTERY = DATA / "battery"


def canonical_lines(n: int, remark=lambda i: "ok") -> list[str]:
    return [
        f"S1,{100 + i % 3},2024-05-01T00:{i // 60 % 60:02d}:{i % 60:02d}Z,"
        f"{12 + i * 1e-3:.4f},{55 + i * 5e-4:.4f},{10 + i % 5 * 0.1:.1f},{i * 7 % 360},{remark(i)}"
        for i in range(n)
    ]


HEADER = "sensor,batch,time,lon,lat,speed,course,remark"


def data_lines(text: str) -> int:
    """Non-blank physical lines after the header (LF, CRLF or CR)."""
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    return sum(1 for line in lines[1:] if line.strip())


def assert_all_accounted(result, n_lines: int) -> None:
    rep = result.report
    assert rep["rows_read"] == n_lines
    assert rep["rows_imported"] + rep["rows_quarantined"] == n_lines
    assert len(result.points) == rep["rows_imported"]
    assert len(result.quarantine) == rep["rows_quarantined"]
    lines = result.quarantine["line"].to_numpy()
    assert len(set(lines.tolist())) == len(lines)  # one row per line


# --- 1. nothing lost -------------------------------------------------------------------


def test_stray_quote_loses_nothing():
    path = BATTERY / "stray_quote.csv"
    r = read_points(path)
    assert_all_accounted(r, 200)
    assert r.report["rows_imported"] == 200  # the row with the quote is a point too
    assert r.points["remark"].iloc[37] == '"unclosed remark'
    assert any("quotes do not balance" in w for w in r.report["warnings"])


def test_stray_quote_after_the_sampled_start(write):
    # No quote in the sampled start: read without quoting, so one line is one row.
    body = canonical_lines(6000, lambda i: '"never closed, with a comma' if i == 5500 else "ok")
    path = write("late.csv", "\n".join([HEADER, *body]) + "\n")
    assert path.stat().st_size > 256 * 1024
    r = read_points(path)
    assert_all_accounted(r, 6000)
    # Read line by line: the quote did not swallow the lines after it, and the row
    # itself (one field too many when unquoted) parses as CSV on its own.
    assert r.report["rows_imported"] == 6000
    assert r.points["remark"].iloc[5500] == "never closed, with a comma"


def test_quoted_cells_with_delimiters_survive_a_stray_quote(write):
    body = canonical_lines(50, lambda i: {3: '"a, b"', 9: '"x ""y"""', 20: '"open'}.get(i, "ok"))
    r = read_points(write("mix.csv", "\n".join([HEADER, *body]) + "\n"))
    assert_all_accounted(r, 50)
    assert r.points["remark"].iloc[3] == "a, b"
    assert r.points["remark"].iloc[9] == 'x "y"'


_DAMAGE = st.sampled_from(
    ["quote", "quote_comma", "short", "long", "blank", "garbage_time", "bad_byte", "lat"]
)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(5, 60),
    damage=st.lists(st.tuples(st.integers(0, 10_000), _DAMAGE), max_size=8),
    ending=st.sampled_from(["\n", "\r\n", "\r"]),
    bom=st.booleans(),
)
def test_count_identity_on_random_damage(tmp_path_factory, n, damage, ending, bom):
    lines = canonical_lines(n)
    for pos, kind in damage:
        i = pos % len(lines)
        cells = lines[i].split(",")
        if kind == "quote":
            cells[pos % len(cells)] = '"' + cells[pos % len(cells)]
        elif kind == "quote_comma":
            cells[-1] = '"half, open'
        elif kind == "short":
            cells = cells[: 1 + pos % 6]
        elif kind == "long":
            cells.append("extra")
        elif kind == "garbage_time" and len(cells) > 2:
            cells[2] = "yesterday"
        elif kind == "lat" and len(cells) > 4:
            cells[4] = "95.5"
        line = ",".join(cells)
        if kind == "blank":
            line = ""
        lines[i] = line
    text = ending.join([HEADER, *lines]) + ending
    raw = text.encode("utf-8")
    for pos, kind in damage:
        if kind == "bad_byte":  # an invalid UTF-8 byte inside a data line
            at = raw.find(b"ok", pos % max(len(raw), 1))
            if at > 0:
                raw = raw[:at] + b"\xff" + raw[at + 1 :]
    if bom:
        raw = b"\xef\xbb\xbf" + raw
    path = tmp_path_factory.mktemp("dmg") / "d.csv"
    path.write_bytes(raw)
    decoded = raw.decode("utf-8", errors="replace")
    expected = data_lines(decoded)
    try:
        r = read_points(path)
    except InputError as exc:
        # Refused only as "not this encoding": more damaged lines than good ones.
        lines = [x for x in decoded.replace("\r", "\n").split("\n")[1:] if x.strip()]
        assert sum("\ufffd" in x for x in lines) > 0.5 * len(lines), exc
        return
    assert_all_accounted(r, expected)


# --- 2. encodings and line endings -------------------------------------------------------


def test_utf16_with_bom_and_crlf():
    r = read_points(BATTERY / "utf16_bom.csv")
    assert r.report["encoding"] == "utf-16"
    assert_all_accounted(r, 20)


def test_utf16_without_bom_by_option_and_by_detection(write):
    text = "\n".join([HEADER, *canonical_lines(10)]) + "\n"
    path = write("u16.csv", text.encode("utf-16-le"))
    assert_all_accounted(read_points(path, encoding="utf-16-le"), 10)
    assert_all_accounted(read_points(path), 10)  # detected: every other byte is zero


def test_cr_only_line_endings():
    sn = sniff(BATTERY / "cr_only.csv")
    assert sn.line_ending == "\r" and len(sn.columns) == 8
    assert_all_accounted(read_points(BATTERY / "cr_only.csv"), 20)


def test_gb18030_text_only_after_the_sampled_start(write):
    body = canonical_lines(6000, lambda i: "浙渔号" if i == 5800 else "ok")
    path = write("late_gb.csv", "\n".join([HEADER, *body]) + "\n", encoding="gb18030")
    r = read_points(path)
    assert r.report["encoding"] == "gb18030"
    assert r.points["remark"].iloc[5800] == "浙渔号"
    assert_all_accounted(r, 6000)


def test_undecodable_bytes_are_quarantined_not_fatal(write):
    body = "\n".join([HEADER, *canonical_lines(30)]) + "\n"
    raw = body.encode().replace(b"ok", "caf\u00e9".encode(), 1)
    # a UTF-8 sample, then bytes that neither UTF-8 nor anything else explains (81 and
    # 9D: undefined in Windows-1252 too, the fallback of a line not valid UTF-8)
    raw = (
        raw.replace(b"caf\xc3\xa9", b"caf\xc3\xa9")
        + b"S1,9,2024-05-01T01:00:00Z,1,2,3,4,\x81\x9d\n"
    )
    r = read_points(write("junk.csv", raw))
    assert_all_accounted(r, 31)
    assert r.quarantine["line"].tolist() == [32]
    assert "not valid" in r.quarantine["reason"].iloc[0]


@pytest.mark.parametrize("streamed", [False, True])
def test_a_header_line_again_is_named_so(write, tmp_path, monkeypatch, streamed):
    """Operator test: two exports joined into one file repeat the header mid-file; the
    line was quarantined as "unparsable time". It is named for what it is — here with
    Chinese names in GB18030, read whole and streamed in pieces."""
    from wakeline.core.io import import_to_csv, reader

    header = "批号,时间,经度,纬度,航速(节),航向"
    rows = [
        f"{400 + i % 2},2024-05-01 08:{i // 60:02d}:{i % 60:02d},"
        f"{122 + i * 1e-3:.4f},{30 + i * 1e-3:.4f},9.5,45"
        for i in range(300)
    ]
    text = "\n".join([header, *rows[:150], header, *rows[150:]]) + "\n"
    path = write("joined.csv", text, encoding="gb18030")
    if streamed:
        monkeypatch.setattr(reader, "STREAM_BYTES", 2000)
        r = import_to_csv(path, tmp_path / "out.csv")
        assert len(pd.read_csv(tmp_path / "out.csv")) == 300
    else:
        r = read_points(path)
        assert_all_accounted(r, 301)
    assert r.report["rows_imported"] == 300
    assert r.quarantine["line"].tolist() == [152]
    assert r.quarantine["reason"].tolist() == ["the header line again (files joined?)"]


def test_a_header_line_again_in_another_case_is_named_so(write):
    """h122's L4: a joined export writing its header upper-case (TIME,ID,LAT,LON) was
    quarantined as "unparsable time"."""
    rows = [
        f"2024-05-01 08:00:{i:02d},{1 + i % 2},{30 + i * 1e-3:.4f},{122 + i * 1e-3:.4f}"
        for i in range(40)
    ]
    text = "\n".join(["time,id,lat,lon", *rows[:20], "TIME,ID,LAT,LON", *rows[20:]]) + "\n"
    r = read_points(write("joined_case.csv", text))
    assert_all_accounted(r, 41)
    assert r.quarantine["reason"].tolist() == ["the header line again (files joined?)"]


@pytest.mark.parametrize("streamed", [False, True])
def test_nul_bytes_and_joined_files_with_a_bom(write, tmp_path, monkeypatch, streamed):
    """Operator test: a logger's file cut short by a power loss ends in a block of NUL
    bytes: the file was refused as binary and its good lines lost. A NUL byte in a line
    made its id a track of its own ("\\x00219230000"), and a header repeated with its byte
    order mark (files joined with cat) was an "unparsable time". Now the block is one
    damaged line, a line with NUL bytes is quarantined as damaged, and the repeated
    header is named."""
    from wakeline.core.io import import_to_csv, reader

    rows = [
        f"7,2024-05-01 08:{k // 60:02d}:{k % 60:02d},{12 + k * 1e-3:.4f},56.0" for k in range(60)
    ]
    part = "\ufeffmmsi,timestamp,lon,lat\r\n" + "\r\n".join(rows) + "\r\n"
    damaged = part.replace("\r\n7,", "\r\n\x007,", 1)  # line 2: a NUL byte first
    raw = damaged.encode() + part.encode() + b"\x00" * 4096
    path = write("logger.csv", raw)
    if streamed:
        monkeypatch.setattr(reader, "STREAM_BYTES", 1000)
        r = import_to_csv(path, tmp_path / "out.csv")
        points = pd.read_csv(tmp_path / "out.csv", dtype={"batch": str})
    else:
        r = read_points(path)
        points = r.points
        assert_all_accounted(r, 122)  # 2 x 60 rows, the second header, the NUL block
    assert r.report["rows_imported"] == 119
    assert set(points["batch"]) == {"7"}
    assert r.quarantine["line"].tolist() == [2, 62, 123]
    reasons = r.quarantine["reason"].tolist()
    assert reasons[:2] == [
        "NUL bytes in the line (damaged)",
        "the header line again (files joined?)",
    ]
    assert reasons[2].startswith("short row")


@pytest.mark.parametrize("unit", ["auto", "seconds"])
def test_a_cut_last_line_after_a_stray_quote_says_nothing_of_a_time_unit(write, tmp_path, unit):
    """Operator test 10: seconds from a scene start (Øresund), one stray quote and the last
    line cut short. Read in pieces, the cut line came alone; its time column held no
    time, was labelled text, and the import warned "--time-unit seconds applies to
    numbers; the times ... are text" — a flag the operator never gave (the first piece's
    decision passed on), or gave for times that are numbers."""
    from wakeline.core.io import import_to_csv

    rows = [
        f"0,GW,219230000,{64.6 + 20 * k:.3f},{12.62 + k * 1e-4:.6f},56.03,9.0,81" for k in range(40)
    ]
    rows[10] = rows[10].replace(",GW,", ',"GW,', 1)
    rows[-1] = rows[-1][:30]
    header = "encounter_id,ship_role,mmsi,timestamp,lon,lat,sog,cog"
    path = write("cut.csv", "\n".join([header, *rows]))
    r = import_to_csv(path, tmp_path / "out.csv", time_unit=unit)
    assert r.report["rows_imported"] + r.report["rows_quarantined"] == 40
    assert r.report["rows_imported"] == 39
    assert not [w for w in r.report["warnings"] if "--time-unit" in w]
    assert any("the file's last line" in w for w in r.report["warnings"])


def test_a_5_mb_cell(write):
    body = canonical_lines(5, lambda i: "x" * 5_000_000 if i == 2 else "ok")
    r = read_points(write("big.csv", "\n".join([HEADER, *body]) + "\n"))
    assert_all_accounted(r, 5)
    assert len(r.points["remark"].iloc[2]) == 5_000_000


# --- 3. headers as users write them ------------------------------------------------------


@pytest.mark.parametrize("streamed", [False, True])
def test_rows_ending_with_the_delimiter_and_excels_sep_line(write, tmp_path, monkeypatch, streamed):
    """Operator test: an export whose every row ends with a delimiter the header lacks
    ("…,80.9,") had all its rows quarantined as "too many fields: 7 of 6"; a European
    Excel file starting with "sep=;" was refused ("headers found: sep=, col2"). The empty
    last field is one more (empty) column; the sep line names the delimiter and is skipped
    — line numbers stay physical lines."""
    from wakeline.core.io import import_to_csv, reader

    rows = [
        f"7,2024-05-01 08:{k // 60:02d}:{k % 60:02d},{12 + k * 1e-3:.4f},56.0," for k in range(90)
    ]
    rows[40] = "7,not a time,12.0,56.0,"
    trailing = write("trailing.csv", "mmsi,timestamp,lon,lat\n" + "\n".join(rows) + "\n")
    semi = [r.rstrip(",").replace(",", ";").replace(".", ",") for r in rows]
    excel = write("excel.csv", "sep=;\nmmsi;timestamp;lon;lat\n" + "\n".join(semi) + "\n")
    for path, header_lines in ((trailing, 1), (excel, 2)):
        if streamed:
            monkeypatch.setattr(reader, "STREAM_BYTES", 1000)
            r = import_to_csv(path, tmp_path / "out.csv")
            points = pd.read_csv(tmp_path / "out.csv")
        else:
            r = read_points(path)
            points = r.points
            assert_all_accounted(r, 90)
        assert r.report["rows_imported"] == 89 and len(points) == 89
        assert r.quarantine["line"].tolist() == [41 + header_lines]
        assert r.quarantine["reason"].tolist() == ["unparsable time"]
        assert points["lon"].iloc[1] == pytest.approx(12.001)


def test_public_ais_export_with_unit_suffixes():
    r = read_points(BATTERY / "public_ais_units.csv")
    cols = r.report["columns"]
    assert cols["lat"] == "Latitude_degrees" and cols["lon"] == "Longitude_degrees"
    assert cols["speed"] == "SOG_knots" and cols["course"] == "COG_degrees"
    assert cols["batch"] == "MMSI" and cols["time"] == "BaseDateTime"
    assert r.report["extra_columns"] == ["Heading_degrees", "VesselName"]
    assert_all_accounted(r, 30)


def test_chinese_gb18030_export():
    r = read_points(BATTERY / "chinese_gb18030.csv")
    cols = r.report["columns"]
    assert r.report["encoding"] == "gb18030"
    assert cols == {
        "batch": "MMSI",
        "time": "Unix时间戳",
        "lon": "经度",
        "lat": "纬度",
        "speed": "航速",
        "course": "航向",
    }
    assert r.report["extra_columns"] == ["时间(Local)", "船首向", "船名"]
    # Unix time is absolute: 08:00 local (UTC+8) is 00:00 UTC.
    assert r.points["time"].iloc[0] == pd.Timestamp("2024-01-01T00:00:00Z")
    assert r.points["船名"].iloc[0] == "浙渔0号"
    assert_all_accounted(r, 30)


@pytest.mark.parametrize(
    "header, field",
    [
        ("航速(kn)", "speed"),
        ("纬度（度）", "lat"),
        ("Speed Over Ground", "speed"),
        ("TRACK_ID", "batch"),
        ("批号", "batch"),
        ("目标号", "batch"),
        ("雷达号", "sensor"),
        ("LON [deg]", "lon"),
    ],
)
def test_synonyms(write, header, field):
    cols = {"batch": "id", "time": "time", "lon": "lon", "lat": "lat", field: header}
    names = list(dict.fromkeys(cols.values()))
    row = {"id": "1", "time": "2024-01-01T00:00:00Z", "lon": "1", "lat": "2", header: "3"}
    text = ",".join(names) + "\n" + ",".join(row[c] for c in names) + "\n"
    r = read_points(write("syn.csv", text))
    assert r.report["columns"][field] == header


# --- 4. time zones ---------------------------------------------------------------------------


LOCAL = "MMSI,时间(Local),纬度,经度\n1,2024-01-01 08:00:00,30,122\n1,2024-01-01 08:00:10,30,122\n"


def test_local_time_column_warns_when_read_as_utc(write):
    r = read_points(write("local.csv", LOCAL, encoding="gb18030"))
    assert r.points["time"].iloc[0] == pd.Timestamp("2024-01-01T08:00:00Z")
    assert any("--tz" in w and "时间(Local)" in w for w in r.report["warnings"])


@pytest.mark.parametrize("tz", ["Asia/Shanghai", "+08:00", "UTC+0800"])
def test_tz_option(write, tz):
    r = read_points(write("local.csv", LOCAL, encoding="gb18030"), tz=tz)
    assert r.points["time"].iloc[0] == pd.Timestamp("2024-01-01T00:00:00Z")
    assert not any("--tz" in w for w in r.report["warnings"])
    assert r.layout["time_zone"] == tz


def test_tz_leaves_zoned_and_unix_times_alone(write):
    zoned = write("z.csv", "batch,time,lon,lat\n1,2024-01-01T08:00:00+08:00,1,2\n")
    assert read_points(zoned, tz="Europe/Oslo").points["time"].iloc[0] == pd.Timestamp(
        "2024-01-01T00:00:00Z"
    )
    unix = write("u.csv", "batch,time,lon,lat\n1,1704067200,1,2\n")
    assert read_points(unix, tz="+05:00").points["time"].iloc[0] == pd.Timestamp(
        "2024-01-01T00:00:00Z"
    )


def test_bad_zone_is_a_clear_error(write):
    with pytest.raises(InputError, match="time zone"):
        read_points(write("local.csv", LOCAL, encoding="gb18030"), tz="Mars/Olympus")


OUTSIDE = "time outside 1677-2262"


@pytest.mark.parametrize(
    ("fmt", "tz"),
    [
        ("{y}-01-01T00:00:{s:02d}Z", None),  # zoned ISO text
        ("{y}-01-01 00:00:{s:02d}", None),  # naive ISO text, read as UTC
        ("{y}-01-01 00:00:{s:02d}", "Europe/Oslo"),  # naive ISO text in a zone
        ("01/01/{y} 00:00:{s:02d}", None),  # day-first text
        ("01/01/{y} 00:00:{s:02d}", "+08:00"),
    ],
)
def test_times_a_ns_clock_cannot_hold_are_quarantined_not_fatal(write, fmt, tz):
    """Years before 1677 or after 2262 (a typo, a placeholder like 9999) are rows with a
    reason, not an error that stops every command (fuzzing found it)."""
    years = [2024, 2024, 2300, 1600, 9999, 2024]
    body = "".join(f"A,1,{fmt.format(y=y, s=i)},10.{i},55\n" for i, y in enumerate(years))
    r = read_points(write("span.csv", "sensor,batch,time,lon,lat\n" + body), tz=tz)
    assert_all_accounted(r, 6)
    assert r.report["rows_imported"] == 3
    assert r.quarantine["line"].tolist() == [4, 5, 6]
    assert (r.quarantine["reason"].str.startswith(OUTSIDE)).all()


def test_repeated_hour_of_a_clock_change_is_placed_by_track_order(write):
    """Local times through the autumn change (02:00-02:59 twice): two ships logged every
    2 min, interleaved; each row lands on its true UTC instant. A track showing one pass
    only stays quarantined with the reason; the spring gap has no times to place."""
    utc = pd.date_range("2024-10-27T00:00Z", "2024-10-27T02:30Z", freq="2min")
    wall = utc.tz_convert("Europe/Copenhagen").strftime("%Y-%m-%d %H:%M:%S")
    lines = [f"{b},{w},{10 + i * 1e-3:.4f},55" for i, w in enumerate(wall) for b in ("A", "B")]
    lines += ["C,2024-10-27 02:30:00,11,56", "C,2024-10-27 03:10:00,11.01,56"]  # one pass
    lines += ["D,2024-03-31 02:30:00,12,57"]  # a wall clock the spring change skips
    r = read_points(
        write("dst.csv", "batch,time,lon,lat\n" + "\n".join(lines) + "\n"), tz="Europe/Copenhagen"
    )
    assert_all_accounted(r, len(lines))
    pts = r.points.sort_values(["batch", "time"])
    for b in ("A", "B"):
        got = pd.DatetimeIndex(pts.loc[pts["batch"] == b, "time"])
        assert (got.as_unit("ns") == utc.as_unit("ns")).all() and len(got) == len(utc), b
    assert r.quarantine["line"].tolist() == [len(lines) - 1, len(lines) + 1]
    assert r.quarantine["reason"].str.contains("clock change in Europe/Copenhagen").all()
    assert any("placed in the first or second pass" in w for w in r.report["warnings"])
    assert r.report["restarting_tracks"] == {}


def test_repeated_hour_rows_out_of_order_stay_quarantined(write, tmp_path, monkeypatch):
    """A message 10 min late, a file newest-first or shuffled: the rows of the repeated hour
    are not placed (a step back is not a second pass); read in pieces, the two passes of
    a track are placed as the whole-file reader places them."""
    late = ["A,2021-10-31 01:50:00,10.0,55", "A,2021-10-31 02:10:00,10.01,55"]
    late += ["A,2021-10-31 02:30:00,10.02,55", "A,2021-10-31 02:20:00,10.03,55"]
    late += ["A,2021-10-31 02:40:00,10.04,55", "A,2021-10-31 03:10:00,10.05,55"]
    head = "batch,time,lon,lat\n"
    r = read_points(write("late.csv", head + "\n".join(late) + "\n"), tz="Europe/Copenhagen")
    assert r.quarantine["line"].tolist() == [3, 4, 5, 6]
    newest = read_points(
        write("newest.csv", head + "\n".join(late[::-1]) + "\n"), tz="Europe/Copenhagen"
    )
    assert newest.report["rows_quarantined"] == 4
    utc = pd.date_range("2024-10-27T00:00Z", "2024-10-27T01:58Z", freq="2min")
    wall = utc.tz_convert("Europe/Copenhagen").strftime("%Y-%m-%d %H:%M:%S")
    rows = [f"A,{w},{10 + i * 1e-3:.4f},55" for i, w in enumerate(wall)]
    shuffled = [rows[i] for i in np.random.default_rng(1).permutation(len(rows))]
    r = read_points(write("sh.csv", head + "\n".join(shuffled) + "\n"), tz="Europe/Copenhagen")
    assert r.report["rows_quarantined"] == len(rows)  # every row is in the repeated hour
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, write_points

    src = write("sorted.csv", head + "\n".join(rows) + "\n")
    whole = read_points(src, tz="Europe/Copenhagen")
    assert whole.report["rows_quarantined"] == 0
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)  # the passes in different pieces
    import_to_csv(src, tmp_path / "streamed.csv", tz="Europe/Copenhagen")
    assert (tmp_path / "streamed.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    years=st.lists(st.integers(1, 9999), min_size=1, max_size=8),
    tz=st.sampled_from([None, "Europe/Copenhagen", "America/New_York", "+05:30"]),
    text=st.sampled_from(
        ["{y:04d}-{m:02d}-{d:02d}T{h:02d}:30:00", "{d:02d}/{m:02d}/{y:04d} {h:02d}:30:00"]
    ),
    month=st.integers(1, 12),
    day=st.integers(1, 28),
    hour=st.integers(0, 23),
)
def test_any_year_and_hour_is_a_point_or_a_quarantine_row(write, years, tz, text, month, day, hour):
    body = "".join(
        f"A,{i % 2},{text.format(y=y, m=month, d=day, h=hour)},10,55\n" for i, y in enumerate(years)
    )
    r = read_points(write("any.csv", "sensor,batch,time,lon,lat\n" + body), tz=tz)
    assert_all_accounted(r, len(years))


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    forms=st.lists(st.sampled_from(["z", "offset", "naive", "s", "ms"]), min_size=2, max_size=40),
    start=st.integers(1_000_000_000, 1_900_000_000),
    steps=st.lists(st.integers(0, 3_600), min_size=40, max_size=40),
    stray=st.sampled_from([None, "7", "0", "2031-01-01T00:00:00Z", "123456789012"]),
)
def test_times_in_two_forms_are_each_read_in_their_own(write, forms, start, steps, stray):
    """Operator test 10: a column of ISO 8601 times with unix seconds among them (two
    exports joined), or the other way: the minority form was quarantined as "unparsable
    time" (half the file at 50/50). Every time, whatever its form, now reads as the time
    it writes; a stray value far from the column's span (a small number, another year)
    stays a quarantine row, and every line is a point or a quarantine row."""
    t = start + np.cumsum(steps[: len(forms)])
    when = pd.to_datetime(t, unit="s", utc=True)
    cells = {
        "z": when.strftime("%Y-%m-%dT%H:%M:%SZ"),
        "offset": when.tz_convert("+08:00").strftime("%Y-%m-%dT%H:%M:%S+08:00"),
        "naive": when.strftime("%Y-%m-%d %H:%M:%S"),
        "s": pd.Index(t.astype(str)),
        "ms": pd.Index((t * 1000).astype(str)),
    }
    rows = [f"1,{cells[f][i]},10,55" for i, f in enumerate(forms)]
    if stray is not None:
        rows.insert(len(rows) // 2, f"1,{stray},10,55")
    r = read_points(write("two.csv", "batch,time,lon,lat\n" + "\n".join(rows) + "\n"))
    assert_all_accounted(r, len(rows))
    points = r.points.sort_values("time", kind="stable")
    got = (points["time"] - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds()
    read = got.round().astype("int64").to_numpy()
    assert sorted(read.tolist())[: len(t)] == sorted(t.tolist()) or stray == "2031-01-01T00:00:00Z"
    assert set(t.tolist()) <= set(read.tolist())  # every written time, in any form
    if stray in ("7", "0"):
        assert r.report["rows_quarantined"] == 1  # never 1970
    if set(forms) & {"s", "ms"} and set(forms) & {"z", "offset", "naive"}:
        kinds = [f in ("s", "ms") for f in forms]
        assert r.report["other_form_times"] >= min(sum(kinds), len(kinds) - sum(kinds))


def test_relative_times_are_flagged(write):
    r = read_points(write("rel.csv", "batch,time,lon,lat\n1,0,1,2\n1,12.5,1,2\n"))
    assert r.report["time_relative"] is True
    assert r.points["time"].iloc[1] == pd.Timestamp("1970-01-01T00:00:12.5Z")
    assert any("relative" in w for w in r.report["warnings"])


# --- 5. NMEA ---------------------------------------------------------------------------------


def test_nmea_log():
    r = read_points(BATTERY / "ais_log.nmea")
    rep = r.report
    assert rep["format"] == "ais-nmea"
    assert sorted(r.points["batch"]) == ["366053209", "413355820"]
    assert r.points["time"].iloc[0] == pd.Timestamp(1671620143, unit="s", tz="UTC")
    assert r.points["time"].iloc[1] == pd.Timestamp(1671620145, unit="s", tz="UTC")
    assert r.points["lon"].iloc[0] == pytest.approx(-122.341618)
    reasons = dict(zip(r.quarantine["line"], r.quarantine["reason"], strict=True))
    assert reasons[5] == "bad NMEA checksum"
    assert reasons[7].startswith("not an AIS sentence")
    assert reasons[8].startswith("no receive time")
    assert reasons[9] == "incomplete multi-part message"
    assert rep["fragments_assembled"] == 1 and rep["static_messages"] == 1
    # every non-blank line is a point, a quarantined row, static data or a merged fragment
    accounted = (
        rep["rows_imported"]
        + rep["rows_quarantined"]
        + rep["static_messages"]
        + rep["fragments_assembled"]
        + sum(rep["messages_ignored_by_type"].values())
    )
    assert accounted == rep["rows_read"] == 8


def test_nmea_log_of_base_and_shore_stations(write):
    """Shore networks log the same sentences under other AIS talkers (``!BSVDM`` in
    Norway's and Denmark's, ``!ABVDM``, ``!SAVDM``): each is read as ``!AIVDM`` is; a
    GPS sentence stays a quarantined row."""
    payload = "1,1,,B,15M67FC000G?ufbE`FepT@3n00Sa,0"

    def sentence(talker: str) -> str:
        body = f"{talker}VDM,{payload}"
        check = 0
        for ch in body:
            check ^= ord(ch)
        return f"!{body}*{check:02X}"

    lines = [f"{1671620143 + i},{sentence(t)}" for i, t in enumerate(("AI", "BS", "AB", "SA"))]
    lines.append("1671620150,$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47")
    r = read_points(write("shore.nmea", "\n".join(lines) + "\n"))
    assert r.report["format"] == "ais-nmea"
    assert len(r.points) == 4 and (r.points["batch"] == "366053209").all()
    assert r.quarantine["reason"].tolist() == [
        "not an AIS sentence (!AIVDM, !AIVDO or another AIS talker's VDM/VDO)"
    ]


def test_nmea_names_from_static_data(write):
    text = (BATTERY / "ais_log.nmea").read_text()
    # the static message (type 5) for 351759000 and a position report of the same ship
    r = read_points(write("n.nmea", text))
    assert "name" in r.points.columns  # names carried as an extra column


# --- 7. outputs ------------------------------------------------------------------------------


def cli(capsys, *args) -> tuple[int, str]:
    from wakeline.app.cli import main

    code = main([str(a) for a in args])
    return code, capsys.readouterr().err


def test_output_checks(tmp_path):
    src = BATTERY / "public_ais_units.csv"
    out = tmp_path / "o.csv"
    with pytest.raises(InputError, match="also given as"):
        check_outputs([src], {"--output": out, "--quarantine": tmp_path / "." / "o.csv"})
    with pytest.raises(InputError, match="also an input"):
        check_outputs([src], {"--output": src})
    out.write_text("keep me\n")
    out.chmod(stat.S_IRUSR | stat.S_IRGRP)
    try:
        with pytest.raises(InputError, match="read-only"):
            check_outputs([src], {"--output": out})
        with pytest.raises(InputError, match="read-only"):
            write_csv(pd.DataFrame({"a": [1]}), out)
        assert out.read_text() == "keep me\n"
    finally:
        out.chmod(stat.S_IRUSR | stat.S_IWUSR)


def test_cli_refuses_quarantine_equal_to_output(tmp_path, capsys):
    out = tmp_path / "o.csv"
    code, err = cli(capsys, "import", BATTERY / "stray_quote.csv", "-o", out, "--quarantine", out)
    assert code == 2 and "--quarantine" in err
    assert not out.exists()


def test_stale_part_files_are_removed(tmp_path):
    out = tmp_path / "o.csv"
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()
    stale = tmp_path / f".o.csv.{dead}.abcd1234.part"
    legacy = tmp_path / ".o.csv.k2j4h5g6.part"
    other = tmp_path / ".other.csv.abcd1234.part"
    for p in (stale, legacy, other):
        p.write_bytes(b"x" * 10)
    os.utime(legacy, (0, 0))
    write_csv(pd.DataFrame({"a": [1]}), out)
    assert not stale.exists() and not legacy.exists() and other.exists()
    assert remove_stale_parts(out) == []


@pytest.mark.parametrize(
    "setting, name",
    [
        ("short_tracks.min_points=inf", "min_points"),
        ("short_tracks.min_points=1e400", "min_points"),
    ],
)
def test_cli_whole_number_parameters_out_of_range(tmp_path, capsys, setting, name):
    src = BATTERY / "public_ais_units.csv"
    code, err = cli(capsys, "clean", src, "-o", tmp_path / "c.csv", "--set", setting)
    assert code == 2, err
    assert name in err and "internal error" not in err


def test_params_reject_inf_and_huge_values():
    from wakeline.core.fuse import FuseParams

    for value in ("inf", "1e400", "-inf", "1e30"):
        fields = [f for f in FuseParams.describe() if type(f["default"]) is int]
        if not fields:
            pytest.skip("no whole-number fuse parameter")
        with pytest.raises(InputError, match=fields[0]["name"]):
            FuseParams().replace(**{fields[0]["name"]: value}).checked()


def test_spreadsheet_safe_defuses_only_text():
    r = read_points(BATTERY / "formula_cells.csv")
    safe = spreadsheet_safe(r.points)
    assert safe["remark"].tolist() == ['\'=HYPERLINK("http://x")', "'+cmd", "'@SUM(A1)", "-2.5"]
    assert safe["lon"].dtype == np.float64  # numbers stay numbers


def test_cli_canonical_output_is_exact_data(tmp_path, capsys):
    out = tmp_path / "o.csv"
    code, err = cli(capsys, "import", BATTERY / "formula_cells.csv", "-o", out)
    assert code == 0, err
    assert "=HYPERLINK" in out.read_text()
    assert "columns: " in err


# --- 6. bounded memory: the streamed import writes what the whole-file import writes ---------


@pytest.mark.parametrize(
    "name", ["public_ais_units.csv", "chinese_gb18030.csv", "cr_only.csv", "utf16_bom.csv", None]
)
def test_streamed_import_equals_whole_file_import(tmp_path, monkeypatch, name):
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, write_points

    if name is None:  # refused rows, blank lines, bad values spread over many pieces
        lines = canonical_lines(120)
        for i in range(0, 120, 13):
            lines[i] = lines[i].replace(",55.", ",95.", 1)
        for i in range(5, 120, 17):
            lines[i] = "S1,1,2"
        lines[40] = ""
        src = tmp_path / "dirty.csv"
        src.write_text("\n".join([HEADER, *lines]) + "\n")
    else:
        src = BATTERY / name
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)  # many pieces
    whole = read_points(src)
    write_points(whole.points, tmp_path / "whole.csv")
    streamed = import_to_csv(src, tmp_path / "streamed.csv")
    assert streamed.report.get("streamed") is True
    assert (tmp_path / "streamed.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    pd.testing.assert_frame_equal(streamed.quarantine, whole.quarantine)
    for key in ("rows_read", "rows_imported", "rows_quarantined", "tracks", "sensors"):
        assert streamed.report[key] == whole.report[key], key


@pytest.mark.parametrize(
    "case", ["bad value", "quoted start", "late edge blank", "late comma", "all quarantined"]
)
def test_import_reads_what_the_stream_cannot_in_pieces_byte_for_byte(tmp_path, monkeypatch, case):
    """`wakeline import` read a file whole when the streamed reader gave up (one value only
    the careful parse reads, quotes in the start): now piece by piece (``pieces`` in the
    report), and the output is the whole-file import's byte for byte — a text column that
    needs quotes in one later piece is quoted in every piece, as the whole table's writer
    quotes it."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, write_points

    lines = canonical_lines(150)
    if case == "bad value":
        lines[77] = lines[77].replace(",12.", ",12O.", 1)
    elif case == "quoted start":
        lines[0] = lines[0].replace(",ok", ',"ok, said the pilot"')
    elif case == "late edge blank":
        lines[120] = lines[120].replace(",ok", ", ok")
    elif case == "late comma":  # a quoted comma far after the sampled start
        lines[140] = lines[140].replace(",ok", ',"a, b"')
    else:  # no piece has a point: the header alone, as the whole-file import writes it
        lines = [line.replace(",12.", ",12O.", 1) for line in lines]
    src = tmp_path / "in.csv"
    src.write_text("\n".join([HEADER, *lines]) + "\n")
    monkeypatch.setattr(reader, "STREAM_BYTES", 400)  # many pieces
    whole = read_points(src)
    write_points(whole.points, tmp_path / "whole.csv")
    got = import_to_csv(src, tmp_path / "pieces.csv")
    assert (tmp_path / "pieces.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    pd.testing.assert_frame_equal(got.quarantine, whole.quarantine)
    for key in ("rows_read", "rows_imported", "rows_quarantined", "tracks", "sensors"):
        assert got.report[key] == whole.report[key], key
    if case in ("bad value", "quoted start"):
        assert got.report.get("pieces", 0) > 5
    assert not list(tmp_path.glob("*.part")) and not list(tmp_path.glob("part*"))


def test_tracks_that_restart_their_time_are_flagged(write):
    """Several passes under one id, each timed from the start (the Øresund encounters:
    one MMSI in five encounters): a warning names the batch and the way out; a shuffled
    file and AIS messages a little out of order are not flagged."""
    rows = []
    for run in range(3):  # batch 7: three passes, each from t = 0 to 50 min
        rows += [f"S1,7,{60 * m},{11 + run + m * 1e-3:.4f},57.5" for m in range(0, 50, 5)]
    rows += [f"S1,8,{60 * m},12.0,{57 + m * 1e-3:.4f}" for m in range(40)]
    rows[-5], rows[-6] = rows[-6], rows[-5]  # one message late by a minute: not a restart
    res = read_points(write("passes.csv", "sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n"))
    # named sensor:batch (two sensors' tracks may share a batch name)
    assert res.report["restarting_tracks"] == {"S1:7": 3}
    assert any(
        "start their time again" in w and "batch S1:7: 3 runs" in w for w in res.report["warnings"]
    )
    rng = np.random.default_rng(0)
    shuffled = [rows[i] for i in rng.permutation(len(rows))]
    res = read_points(
        write("shuffled.csv", "sensor,batch,time,lon,lat\n" + "\n".join(shuffled) + "\n")
    )
    assert res.report["restarting_tracks"] == {}


def test_times_read_as_arrow_timestamps_with_a_gap_stay_exact():
    """A time column Arrow typed as timestamps, one cell empty: the others keep every ns
    (a conversion through floats moved them by 64 ns)."""
    import pyarrow as pa

    from wakeline.core.io.reader import parse_times

    ns = np.array([1_714_522_466_215_000_000, 0, 1_714_522_486_215_000_123])
    arr = pa.chunked_array([pa.array(ns, type=pa.timestamp("ns", "UTC"), mask=ns == 0)])
    got, ok = parse_times(arr, "auto")
    assert ok.tolist() == [True, False, True]
    assert got[ok].tolist() == ns[ok].tolist()


def test_unix_seconds_and_milliseconds_in_one_column(write):
    """A feed that switched from seconds to milliseconds: each number read in its own unit
    (fuzzing: the seconds rows were quarantined as 'decades before'); a damaged 9-digit
    number (1975) in a 2023 file is still refused."""
    rows = [f"S,1,{1_700_000_000 + 10 * i},{10 + i * 1e-3:.3f},55" for i in range(20)]
    rows += [f"S,1,{(1_700_000_200 + 10 * i) * 1000},{10.02 + i * 1e-3:.3f},55" for i in range(20)]
    rows += ["S,1,170000000,10.5,55"]
    r = read_points(write("mix.csv", "sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n"))
    assert r.report["rows_imported"] == 40 and r.quarantine["line"].tolist() == [42]
    t = r.points["time"].astype("int64").to_numpy() // 10**9
    assert (np.diff(t) == 10).all() and t[0] == 1_700_000_000


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
def test_edge_typos_read_in_pieces_are_a_part_of_the_whole_reads(tmp_path, monkeypatch, way):
    """A mistyped date in a track's first or last row (the edge-row rule). A read in
    pieces judges a track's edges in the file's last piece only (a track's last row there
    is its last in the file; the other tracks of the earlier pieces are known): the last
    row of a track ending there is quarantined as the whole read does; a typo in the first
    row of a track that begins in an earlier piece is only seen by a whole read; a track
    that began in an earlier piece and comes back in the last one after days (a row 5
    days on, then rows 10 days on) is not taken for a typo there. Every row is still a
    point or a quarantine row with its line."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv
    from wakeline.core.io.reader import line_pieces

    t0 = pd.Timestamp("2023-06-01 03:00:00")
    remark = '"ok, a"' if way == "in pieces" else "ok"  # quotes: read in pieces

    def line(batch: str, t: pd.Timestamp, k: int) -> str:
        return f"S1,{batch},{t:%Y-%m-%dT%H:%M:%S}Z,{12 + k * 1e-3:.4f},55.0,10,0,{remark}"

    rows = []
    for batch, n, typo in (("A", 30, "first"), ("B", 30, None)):
        for k in range(n):
            t = t0 + pd.Timedelta(seconds=10 * k)
            rows.append(line(batch, t.replace(year=2012) if typo and k == 0 else t, k))
    rows += [line("D", t0 + pd.Timedelta(seconds=10 * k), k) for k in range(3)]
    c = [t0 + pd.Timedelta(seconds=10 * k) for k in range(30)]
    c[-1] = c[-1].replace(year=2033)  # A's typo in an earlier piece spans 2012-2023
    rows += [line("C", t, k) for k, t in enumerate(c)]
    d_back = [t0 + pd.Timedelta(days=5)] + [t0 + pd.Timedelta(days=10, seconds=k) for k in range(3)]
    rows += [line("D", t, k) for k, t in enumerate(d_back)]
    src = tmp_path / "edges.csv"
    src.write_text("\n".join([HEADER, *rows]) + "\n")

    def last_piece(size: int) -> str:
        with open(src, "rb") as f:
            parts = list(line_pieces(f, size))
        return parts[-1][0].decode() if len(parts) >= 4 else ""

    # the test's premise: C ends and D comes back in the last piece, D began before it
    size = next(n for n in range(400, 900, 10) if last_piece(n).count(",C,") >= 4)
    assert last_piece(size).count(",D,") == 4
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    c_last = 2 + 63 + 29
    whole = read_points(src)
    assert whole.quarantine["line"].tolist() == [2, c_last]
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report.get("streamed" if way == "streamed" else "pieces")
    assert got.quarantine["line"].tolist() == [c_last]  # A's first row: only a whole read
    assert got.quarantine["reason"].str.startswith("time days from the rest").all()
    assert got.report["rows_imported"] + got.report["rows_quarantined"] == len(rows)
    assert len(pd.read_csv(tmp_path / "out.csv")) == got.report["rows_imported"] == len(rows) - 1


@settings(max_examples=40, deadline=None)
@given(
    tracks=st.lists(
        st.tuples(st.integers(3, 25), st.integers(1, 900), st.integers(0, 6 * 3600)),
        min_size=1,
        max_size=4,
    ),
    typo=st.one_of(
        st.none(),
        st.tuples(
            st.integers(0, 3),
            st.booleans(),
            st.sampled_from(["year", "month", "day"]),
            st.integers(1, 9) | st.integers(-9, -1),
        ),
    ),
    edge_gap_h=st.integers(0, 23),
)
def test_edge_typo_property(tmp_path_factory, tracks, typo, edge_gap_h):
    """Tracks of one day (3-25 rows, a step of 1 s to 15 min, starting within 6 h), the
    first track's last row up to 23 h after its others (real): nothing is quarantined;
    with one first or last row's year, month or day mistyped (1-9 off; a day's typo
    taken as >= 2 days), that row alone is, and every row is a point or a quarantine row."""
    t0 = pd.Timestamp("2023-06-15 00:00:00")
    rows, typo_line = [], None
    for b, (n, step, offset) in enumerate(tracks):
        times = [t0 + pd.Timedelta(seconds=offset + step * k) for k in range(n)]
        typo_here = typo is not None and typo[0] % len(tracks) == b
        # A 3-row track's typical step for its first row is its other step: with the
        # real edge gap there (up to 23 h) a month's typo lies within 100x of it and
        # stays (the price of keeping 3-row daily tracks, review F1).
        if b == 0 and not (n == 3 and typo_here and typo[1]):
            times[-1] += pd.Timedelta(hours=edge_gap_h)
        if typo_here:
            _, first, unit, off = typo
            i = 0 if first else n - 1
            if unit == "day" and abs(off) < 2:
                off = 2 if off > 0 else -2
            times[i] += pd.DateOffset(**{unit + "s": off})
            typo_line = 2 + len(rows) + i
        rows += [
            f"S1,{b},{t:%Y-%m-%dT%H:%M:%S}Z,{12 + k * 1e-3:.4f},55.0,10,0,ok"
            for k, t in enumerate(times)
        ]
    path = tmp_path_factory.mktemp("edge") / "e.csv"
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    r = read_points(path)
    assert_all_accounted(r, len(rows))
    assert r.quarantine["line"].tolist() == ([] if typo_line is None else [typo_line])


# --- the edge-row rule read in pieces (review h60: F2, F4, F5) ------------------------------

_D, _H, _M = pd.Timedelta(days=1), pd.Timedelta(hours=1), pd.Timedelta(minutes=1)
_T0 = pd.Timestamp("2023-06-01 00:00:00")


def _edge_rows(rows, way: str) -> list[str]:
    """(batch, time) pairs as canonical lines; quoted remarks send the import in pieces."""
    remark = '"ok, a"' if way == "in pieces" else "ok"
    return [
        f"S1,{b},{t:%Y-%m-%dT%H:%M:%S}Z,{12 + k % 999 * 1e-3:.4f},55.0,10,0,{remark}"
        for k, (b, t) in enumerate(rows)
    ]


def _size_with_last(src, rows_in_last: int) -> int:
    """A piece size giving >= 2 pieces whose last one with rows holds ``rows_in_last``."""
    from wakeline.core.io.reader import line_pieces

    for size in range(200, 8000, 3):
        with open(src, "rb") as f:
            parts = [p for p, _ in line_pieces(f, size) if p.strip()]
        if len(parts) >= 2 and parts[-1].decode().strip().count("\n") + 1 == rows_in_last:
            return size
    raise AssertionError("no such piece size")


def _whole_and_in_pieces(src, tmp_path, monkeypatch, size: int, way: str, n: int):
    """The quarantined lines of a whole read and of `import_to_csv` at ``size``; every
    row is a point or a quarantine row in both."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    whole = read_points(src)
    assert len(whole.points) + len(whole.quarantine) == n
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report.get("streamed" if way == "streamed" else "pieces")
    assert got.report["rows_imported"] + got.report["rows_quarantined"] == n
    assert len(pd.read_csv(tmp_path / "out.csv")) == got.report["rows_imported"]
    return whole.quarantine["line"].tolist(), got.quarantine["line"].tolist()


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
@pytest.mark.parametrize("case", ["daily", "hourly"])
def test_a_read_in_pieces_keeps_a_real_last_row_the_whole_read_keeps(
    tmp_path, monkeypatch, case, way
):
    """F2: the typical step of a track came from the last piece's rows only: a ship's
    daily noon reports whose last one came 3 days after its previous (within 100 × its
    daily step), or an hourly satellite-AIS ship seen again 2.5 days on (within 100 × its
    hourly step), lost that real last row when the last piece held its last 3 rows.
    Now each track's earlier steps are carried (count, span, sum of steps): the read in
    pieces keeps it, as the whole read does."""
    if case == "daily":
        rows = [("A", _T0 + k * _D) for k in range(30)] + [("A", _T0 + 32 * _D)]
    else:
        rows = [("A", _T0 + k * _H) for k in range(72)] + [("A", _T0 + 131 * _H)]
    src = tmp_path / "e.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, way)]) + "\n")
    size = _size_with_last(src, 3)
    whole, got = _whole_and_in_pieces(src, tmp_path, monkeypatch, size, way, len(rows))
    assert whole == [] and got == []


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
def test_a_track_split_over_pieces_covers_its_whole_span(tmp_path, monkeypatch, way):
    """F5: a covering track's rows split over pieces (B on day 0, and on day 5 in the last
    piece) covered only the days of each piece's rows, leaving a hole where A's real row
    on day 3 then had no other track: quarantined in pieces, kept whole. Each track's
    span is now carried whole (min and max merged over the pieces)."""
    rows = [("B", _T0 + k * _M) for k in range(50)] + [("A", _T0 + k * _M) for k in range(50)]
    rows += [("A", _T0 + 3 * _D)] + [("B", _T0 + 5 * _D + k * _M) for k in range(10)]
    src = tmp_path / "e.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, way)]) + "\n")
    size = _size_with_last(src, 15)  # A's last row and B's day 5 in the last piece
    whole, got = _whole_and_in_pieces(src, tmp_path, monkeypatch, size, way, len(rows))
    assert whole == [] and got == []


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
def test_blank_lines_in_the_last_piece_leave_the_edge_rule_on(tmp_path, monkeypatch, way):
    """F4: a file whose last piece holds only blank lines never ran the edge-row rule (it
    ran in the last piece only): a 2013 typo in B's last row passed. The rule now runs in
    the last piece with rows."""
    rows = [(b, _T0 + k * _M) for b in "AB" for k in range(30)]
    rows[-1] = ("B", (_T0 + 29 * _M).replace(year=2013))
    src = tmp_path / "e.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, way), *[""] * 3000]) + "\n")
    from wakeline.core.io.reader import line_pieces

    with open(src, "rb") as f:
        parts = [p for p, _ in line_pieces(f, 1200)]
    assert len(parts) >= 3 and not parts[-1].strip()  # the premise: a blank last piece
    whole, got = _whole_and_in_pieces(src, tmp_path, monkeypatch, 1200, way, len(rows))
    assert whole == got == [61]


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    tracks=st.lists(
        st.tuples(
            st.integers(2, 40),  # rows
            st.sampled_from([10, 600, 3600, 86_400]),  # step (s)
            st.integers(0, 3 * 86_400),  # start
            st.integers(0, 6 * 86_400),  # last row's extra gap (s)
        ),
        min_size=1,
        max_size=4,
    ),
    typo=st.one_of(st.none(), st.tuples(st.integers(0, 3), st.booleans(), st.integers(-9, 9))),
    size=st.integers(250, 3000),
    interleave=st.booleans(),
)
def test_edge_rule_in_pieces_quarantines_only_what_a_whole_read_does(
    tmp_path, monkeypatch, tracks, typo, size, interleave
):
    """Tracks of any step (10 s to a day), a real gap before a last row, a mistyped year in
    a first or last row, tracks one after the other or interleaved, read in pieces of any
    size: the rows the edge-row rule quarantines are a part of the whole read's (a read in
    pieces may miss a typo, never take a real row), and every row is a point or a
    quarantine row."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    per_track = []
    for b, (n, step, start, gap) in enumerate(tracks):
        times = [_T0 + pd.Timedelta(seconds=start + step * k) for k in range(n)]
        times[-1] += pd.Timedelta(seconds=gap)
        if typo is not None and typo[0] % len(tracks) == b and typo[2]:
            i = 0 if typo[1] else n - 1
            times[i] = times[i] + pd.DateOffset(years=typo[2])
        per_track.append([(str(b), t) for t in times])
    if interleave:
        rows = [
            r for k in range(max(map(len, per_track))) for tr in per_track for r in tr[k : k + 1]
        ]
    else:
        rows = [r for tr in per_track for r in tr]
    src = tmp_path / "p.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, "streamed")]) + "\n")
    whole = read_points(src)
    assert len(whole.points) + len(whole.quarantine) == len(rows)
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report["rows_imported"] + got.report["rows_quarantined"] == len(rows)
    assert set(got.quarantine["line"]) <= set(whole.quarantine["line"])


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
@pytest.mark.parametrize("here", [1, 2])
def test_a_last_row_typo_with_few_rows_of_its_track_in_the_last_piece(
    tmp_path, monkeypatch, here, way
):
    """A track's last row is judged in the last piece with rows even when only 1 or 2 of
    its rows are there (the rest carried from the earlier pieces): a 2013 typo in A's last
    row, after B's rows, is quarantined as the whole read does (before, a track needed 3
    rows in the last piece)."""
    rows = [("A", _T0 + k * _M) for k in range(40)] + [("B", _T0 + k * _M) for k in range(40)]
    if here == 2:
        rows.append(("A", _T0 + 40 * _M))
    rows.append(("A", (_T0 + 41 * _M).replace(year=2013)))
    src = tmp_path / "e.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, way)]) + "\n")
    size = _size_with_last(src, here)
    whole, got = _whole_and_in_pieces(src, tmp_path, monkeypatch, size, way, len(rows))
    assert whole == got == [len(rows) + 1]


# --- a track whose times jump by months, read whole and in pieces (h149) -------------------

_LONE = "time days away from its track's rows before and after it"


def test_a_track_jumping_by_months_reads_alike_whole_and_in_pieces(tmp_path, monkeypatch):
    """One id over a year, its rows out of time order by months (h134's `lone.csv`): a
    whole read keeps every row (the track is not written in time order, so no row of it
    is judged lone), while pieces of 200 bytes judged each piece's few rows in order and
    quarantined 5 as "time days away from its track's rows". A piece now leaves such rows
    to the whole file (WholeFileNeeded): the same points and quarantine every way."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, write_points
    from wakeline.core.io.pieces import read_in_pieces

    days = ["03-01", "01-01", "01-15", "02-01", "03-03", "02-15", "03-15", "12-15", "03-15"]
    days += ["12-15", "12-15", "05-15"]
    for way in ("streamed", "in pieces"):
        note = '"a, b"' if way == "in pieces" else "ab"  # quotes: read in pieces
        lines = ["time,id,lat,lon,note"]
        for k in range(36):
            lines.append(f"2024-{days[k % 12]} 10:00:0{k % 3},1,{37 + k * 1e-4:.4f},23.6,{note}")
        src = tmp_path / f"lone_{way[:2]}.csv"
        src.write_text("\n".join(lines) + "\n")
        whole = read_points(src)
        assert whole.report["rows_quarantined"] == 0 and whole.report["rows_imported"] == 36
        write_points(whole.points, tmp_path / "whole.csv")
        monkeypatch.setattr(reader, "STREAM_BYTES", 200)
        got = import_to_csv(src, tmp_path / "out.csv")
        assert (tmp_path / "out.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
        assert got.report["rows_quarantined"] == 0, got.quarantine["reason"].tolist()
        monkeypatch.undo()
        with pytest.raises(reader.WholeFileNeeded):  # a piece leaves it to the whole file
            read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
            monkeypatch.setattr(reader, "STREAM_BYTES", 200)
            read_in_pieces(sniff(src), read, lambda p: None, tmp_path / "scratch")
        monkeypatch.undo()


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    tracks=st.lists(
        st.lists(st.integers(0, 365), min_size=2, max_size=25),  # each row's day of the year
        min_size=1,
        max_size=3,
    ),
    in_order=st.booleans(),
    typo=st.one_of(st.none(), st.tuples(st.integers(0, 2), st.integers(0, 24), st.integers(1, 9))),
    size=st.integers(200, 2000),
    way=st.sampled_from(["streamed", "in pieces"]),
)
def test_lone_rows_in_pieces_are_the_whole_reads_when_times_jump_by_months(
    tmp_path, monkeypatch, tracks, in_order, typo, size, way
):
    """Tracks whose rows lie days to months apart (in time order or not), one row's year
    perhaps mistyped, read streamed or in pieces of any size: the rows quarantined as lone
    ("time days away from its track's rows…") are exactly the whole read's, the rest of
    the quarantine a part of the whole read's (the edge-row rule may miss a typo in
    pieces), and every row is a point or a quarantine row."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    t0 = pd.Timestamp("2024-01-01 10:00:00")
    rows = []
    for b, days in enumerate(tracks):
        days = sorted(days) if in_order else days
        times = [t0 + pd.Timedelta(days=d, seconds=k) for k, d in enumerate(days)]
        if typo is not None and typo[0] % len(tracks) == b:
            i = typo[1] % len(times)
            times[i] = times[i] + pd.DateOffset(years=typo[2])
        rows += [(str(b), t) for t in times]
    src = tmp_path / "m.csv"
    src.write_text("\n".join([HEADER, *_edge_rows(rows, way)]) + "\n")
    whole = read_points(src)
    assert len(whole.points) + len(whole.quarantine) == len(rows)
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report["rows_imported"] + got.report["rows_quarantined"] == len(rows)
    assert len(pd.read_csv(tmp_path / "out.csv")) == got.report["rows_imported"]

    def lone(q):
        return q.loc[q["reason"].str.startswith(_LONE), "line"].tolist()

    assert lone(got.quarantine) == lone(whole.quarantine)
    assert set(got.quarantine["line"]) <= set(whole.quarantine["line"])


def test_repeated_rows_are_counted_not_read_as_passes(write, monkeypatch):
    """Operator test 9, D8: rows written twice (every 7th, and a block of the first ones
    appended at the end) were reported as "several passes or ships share one id", which
    sent the operator to look for a column that does not exist; they are counted as
    repeats and left out of the restart test. A real second pass is still flagged."""
    rows = []
    for b in (1, 2, 3):
        rows += [f"{b},{60 * m},{11 + b + m * 1e-3:.4f},57.5,{9 + b}.5" for m in range(60)]
    doubled = [r for k, r in enumerate(rows) for _ in range(2 if k % 7 == 0 else 1)]
    again = doubled + rows[:20]  # the start of the export appended at the end
    expected = len(again) - len(rows)
    res_path = write("twice.csv", "id,time,lon,lat,speed\n" + "\n".join(again) + "\n")
    res = read_points(res_path)
    assert res.report["repeated_rows"] == expected
    assert res.report["restarting_tracks"] == {}
    said = [w for w in res.report["warnings"] if "repeat an earlier row exactly" in w]
    assert said and said[0].startswith(f"{expected:,} rows repeat")
    assert not any("start their time again" in w for w in res.report["warnings"])
    # read streamed in pieces of 2 KB (as `wakeline clean` and `batch` read): the rows
    # repeated at the end repeat rows of the first piece, counted the same
    from wakeline.core.clean_stream import clean_file
    from wakeline.core.io import reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 2 << 10)
    got = clean_file(res_path, write("c.csv", ""), write("c_rej.csv", ""))
    assert got.streamed
    assert got.read_report["repeated_rows"] == expected
    assert got.read_report["restarting_tracks"] == {}
    monkeypatch.undo()
    # the same time and track at another place is not a repeat; a true second pass (new
    # positions, from t = 0 again) is still a restart
    moved = [r.replace(",57.5,", ",57.6,") for r in rows[:20]]
    res = read_points(write("pass.csv", "id,time,lon,lat,speed\n" + "\n".join(rows + moved) + "\n"))
    assert res.report["repeated_rows"] == 0
    assert res.report["restarting_tracks"] == {"1": 2}

"""D-import-9 (operator test 5): two exports pasted into one CSV, the second with its
columns in another order (or a column more, or named otherwise), were read under the
first header: ids as times, latitudes as longitudes, exit status 0. A line of column
names starts a second table, read by its own header or quarantined with "split the
file"; every line is a point or a quarantine row, whole, streamed or in pieces."""

import re

import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.io import import_to_csv, read_points, reader

FIRST = ["index", "position_timestamp", "mmsi", "latitude", "longitude"]


def _rows(n: int, start: int = 0) -> list[dict]:
    return [
        {
            "index": str(start + i),
            "position_timestamp": f"2023-03-01T{(start + i) // 3600:02d}:"
            f"{(start + i) // 60 % 60:02d}:{(start + i) % 60:02d}Z",
            "mmsi": str(220614000 + (start + i) % 2),
            "latitude": f"{57.6 + (start + i) * 1e-4:.4f}",
            "longitude": f"{11.7 + (start + i) * 1e-4:.4f}",
            "sog": "10.5",
            "lat": f"{57.6 + (start + i) * 1e-4:.4f}",
            "lon": f"{11.7 + (start + i) * 1e-4:.4f}",
        }
        for i in range(n)
    ]


def _block(header: list[str], rows: list[dict]) -> list[str]:
    return [",".join(header)] + [",".join(r[c] for c in header) for r in rows]


def _file(second: list[str], n1: int, n2: int) -> str:
    return "\n".join(_block(FIRST, _rows(n1)) + _block(second, _rows(n2, n1))) + "\n"


def _read(path, how, tmp_path, monkeypatch):
    if how == "whole":
        r = read_points(path)
        return r, r.points
    monkeypatch.setattr(reader, "STREAM_BYTES", 600)  # many pieces
    out = tmp_path / f"out_{how}.csv"
    r = import_to_csv(path, out)
    return r, pd.read_csv(out, dtype={"batch": str})


def _accounted(r, n_lines: int) -> None:
    rep = r.report
    assert rep["rows_read"] == n_lines
    assert rep["rows_imported"] + rep["rows_quarantined"] == n_lines
    assert len(r.quarantine) == rep["rows_quarantined"]
    lines = r.quarantine["line"].tolist()
    assert len(set(lines)) == len(lines)


@pytest.mark.parametrize("how", ["whole", "streamed"])
@pytest.mark.parametrize(
    "second, said",
    [
        (["index", "mmsi", "position_timestamp", "longitude", "latitude"], "in another order"),
        (
            FIRST + ["sog"],
            "changed (+sog): read by its own header (30 rows; columns it adds not read)",
        ),
        (
            ["index", "position_timestamp", "mmsi", "lat", "lon"],
            "changed (latitude \u2192 lat; longitude \u2192 lon)",
        ),
        (["mmsi", "position_timestamp", "longitude", "latitude"], "changed (\u2212index)"),
    ],
)
def test_a_second_table_is_read_by_its_own_header(write, tmp_path, monkeypatch, how, second, said):
    path = write("two.csv", _file(second, 40, 30))
    r, points = _read(path, how, tmp_path, monkeypatch)
    _accounted(r, 71)
    assert r.report["rows_imported"] == 70
    assert r.quarantine["line"].tolist() == [42]
    assert r.quarantine["reason"].iloc[0].startswith("the header of a second table")
    note = [w for w in r.report["warnings"] if "second table" in w]
    assert len(note) == 1 and note[0].startswith("line 42 starts a second table")
    assert said in note[0] and "read by its own header (30 rows" in note[0]
    one = read_points(write("one.csv", "\n".join(_block(FIRST, _rows(70))) + "\n")).points
    points = points.sort_values(["batch", "time"], ignore_index=True)
    one = one.sort_values(["batch", "time"], ignore_index=True)
    assert points["batch"].astype(str).tolist() == one["batch"].astype(str).tolist()
    assert (pd.to_datetime(points["time"]) == pd.to_datetime(one["time"])).all()
    assert points["lat"].round(6).tolist() == one["lat"].round(6).tolist()
    assert points["lon"].round(6).tolist() == one["lon"].round(6).tolist()


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_a_second_table_without_a_column_read_is_quarantined(write, tmp_path, monkeypatch, how):
    """No time column under the second header: the header and its rows quarantined,
    the line named and "split the file" said."""
    second = ["index", "mmsi", "latitude", "longitude", "sog"]
    path = write("two.csv", _file(second, 40, 30))
    r, _ = _read(path, how, tmp_path, monkeypatch)
    _accounted(r, 71)
    assert r.report["rows_imported"] == 40
    assert r.quarantine["line"].tolist() == list(range(42, 73))
    assert r.quarantine["reason"].iloc[1].startswith("under the second table's header at line 42")
    note = [w for w in r.report["warnings"] if "second table" in w]
    assert len(note) == 1 and "its 30 rows quarantined; split the file" in note[0]


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_a_second_table_with_another_delimiter_or_chinese_names(write, tmp_path, monkeypatch, how):
    """The tester's not-tried cases: Chinese headers under English ones are read by their
    own header (their fields known); a second table separated by ';' is quarantined with
    the line named (before: 31 "short row" and "the file may be cut short")."""
    cn = ["批号", "时间", "纬度", "经度"]
    rows = _rows(60)
    eng = ["mmsi", "position_timestamp", "latitude", "longitude"]
    lines = _block(eng, rows[:30]) + [",".join(cn)] + _block(eng, rows[30:])[1:]
    r, _ = _read(write("cn.csv", "\n".join(lines) + "\n"), how, tmp_path, monkeypatch)
    _accounted(r, 61)
    assert r.report["rows_imported"] == 60
    semi = _block(eng, rows[:30]) + [x.replace(",", ";") for x in _block(eng, rows[30:])]
    r, _ = _read(write("semi.csv", "\n".join(semi) + "\n"), how, tmp_path, monkeypatch)
    _accounted(r, 61)
    assert r.report["rows_imported"] == 30
    assert r.quarantine["reason"].iloc[0] == (
        "the header of a second table separated by ';': split the file"
    )
    note = [w for w in r.report["warnings"] if "second table" in w or "cut short" in w]
    assert note == [
        "line 32 starts a second table separated by ';': its 30 rows quarantined; split the "
        "file and import each table on its own"
    ]


def test_the_time_format_is_not_judged_on_the_other_table(write):
    """The tester's case: the longer second table put ids (220614000) in the first
    header's time column, which then parsed as unix seconds for every row."""
    second = ["index", "mmsi", "position_timestamp", "longitude", "latitude"]
    r = read_points(write("two.csv", _file(second, 20, 60)))
    assert r.report["rows_imported"] == 80
    assert r.report["time_format"] != "unix s"
    assert r.points["time"].dt.year.eq(2023).all()
    assert r.points["lat"].between(57, 58).all() and r.points["lon"].between(11, 12).all()


def test_each_table_s_times_are_read_in_their_own_form(write):
    """The first table writes ISO times, the second (longer) day-first dates: each read
    in its own form, said once (before: one form judged on both, the other quarantined)."""
    second = ["index", "mmsi", "position_timestamp", "longitude", "latitude"]
    text = _file(second, 20, 60)
    head, _, tail = text.partition("\n" + ",".join(second) + "\n")
    tail = re.sub(
        r"(\d{4})-(\d\d)-(\d\d)T([\d:]+)Z", lambda m: f"{m[3]}/{m[2]}/{m[1]} {m[4]}", tail
    )
    r = read_points(write("forms.csv", head + "\n" + ",".join(second) + "\n" + tail))
    assert r.report["rows_imported"] == 80
    one = read_points(write("one.csv", "\n".join(_block(FIRST, _rows(80))) + "\n")).points
    assert (r.points["time"].to_numpy() == one["time"].to_numpy()).all()
    said = [w for w in r.report["warnings"] if "in 2 forms" in w]
    assert said == [
        "the tables of this file write the times in 'position_timestamp' in 2 forms (ISO 8601 "
        "text, day-first text): each table's read in its own"
    ]


def test_zoned_times_in_one_table_and_zone_less_in_the_other_are_counted(write):
    second = ["index", "mmsi", "position_timestamp", "longitude", "latitude"]
    text = _file(second, 20, 30)
    head, _, tail = text.partition("\n" + ",".join(second) + "\n")
    tail = re.sub(r"(\d{4}-\d\d-\d\d)T([\d:]+)Z", r"\1 \2", tail)  # no zone
    r = read_points(write("zones.csv", head + "\n" + ",".join(second) + "\n" + tail))
    assert r.report["rows_imported"] == 50
    said = [w for w in r.report["warnings"] if "carry no zone" in w]
    assert len(said) == 1 and said[0].startswith("30 of 50 times in 'position_timestamp'")


_HEADERS = st.permutations(FIRST).flatmap(
    lambda order: st.sampled_from(
        [list(order), list(order) + ["sog"], [c for c in order if c != "index"]]
    )
)


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    blocks=st.lists(st.tuples(_HEADERS, st.integers(0, 12)), min_size=1, max_size=4),
    n1=st.integers(1, 12),
)
def test_any_tables_lose_no_line_and_read_their_rows(write, blocks, n1):
    """Property: tables of the known columns in any order, with a column more or less,
    pasted one after the other: every line is a point or a quarantine row, every data
    row is a point with its own values, every header line but the first is quarantined."""
    lines = _block(FIRST, _rows(n1))
    start = n1
    for header, n in blocks:
        lines += _block(header, _rows(n, start))
        start += n
    path = write("many.csv", "\n".join(lines) + "\n")
    r = read_points(path)
    _accounted(r, len(lines) - 1)
    assert r.report["rows_imported"] == start
    assert len(r.quarantine) == len(blocks)
    truth = pd.DataFrame(_rows(start))
    got = r.points.sort_values("time", ignore_index=True)
    assert got["lat"].round(6).tolist() == truth["latitude"].astype(float).tolist()
    assert got["lon"].round(6).tolist() == truth["longitude"].astype(float).tolist()
    assert got["batch"].astype(str).tolist() == truth["mmsi"].tolist()

"""Time texts beyond ISO and slashed dates: English month names (01-Jan-2024 00:00:05,
asctime), Chinese dates (2024年1月1日), clock times without a date (23:50:00.5, --date,
rollover past midnight) and HHMMSS numbers (core/io/timetext.py, docs/import.md)."""

from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import import_to_csv, inspect_file, read_points
from wakeline.core.io.layout import describe_layout
from wakeline.core.io.pieces import read_in_pieces
from wakeline.core.io.reader import parse_times
from wakeline.core.io.sniff import sniff
from wakeline.core.io.timetext import (
    chinese_iso,
    clock_seconds,
    hhmmss_evidence,
    named_iso,
    roll_days,
)

START = pd.Timestamp("2024-01-01 00:00:00", tz="UTC")
TIMES = pd.date_range(START, periods=30, freq="1s")
_SETTINGS = settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


def _write(path: Path, cells: list[str], header: str = "time,id,lat,lon") -> Path:
    cells = [f'"{c}"' if "," in c else c for c in cells]
    rows = [f"{c},{1 + k % 2},37.{k:04d},23.{k:04d}" for k, c in enumerate(cells)]
    path.write_text(header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


def _times(points: pd.DataFrame) -> list:
    return sorted(points["time"].tolist())


@pytest.mark.parametrize(
    "fmt",
    [
        "%d-%b-%Y %H:%M:%S",  # 01-Jan-2024 00:00:05
        "%d-%b-%y %H.%M.%S",  # Oracle: 01-JAN-24 00.00.05 (upper-cased below)
        "%b %d, %Y %I:%M:%S %p",  # Jan 01, 2024 12:00:05 AM
        "%d %B %Y %H:%M:%S",  # 01 January 2024 00:00:05
        "%a %b %d %H:%M:%S %Y",  # asctime: Mon Jan 01 00:00:05 2024
        "%a, %d %b %Y %H:%M:%S +0000",  # e-mail
        "%d/%b/%Y:%H:%M:%S +0000",  # web logs
        "%Y年%m月%d日 %H:%M:%S",
        "%Y年%m月%d日 %H时%M分%S秒",
        "%Y年%m月%d日%H:%M:%S",
    ],
)
def test_month_names_and_chinese_dates_read_every_row(tmp_path, fmt):
    cells = [t.strftime(fmt) for t in TIMES]
    if "%y" in fmt:
        cells = [c.upper() for c in cells]
    r = read_points(_write(tmp_path / "t.csv", cells))
    assert len(r.points) == 30 and len(r.quarantine) == 0
    assert _times(r.points) == list(TIMES)
    assert r.report["time_format"] == ("Chinese date text" if "年" in fmt else "month-name text")


def test_the_probe_files_forms():
    got = named_iso(
        pd.Series(
            [
                "01-Jan-2024 00:00:05",
                "01-JAN-24 00.00.05",
                "Jan 1, 2024 12:00:05 PM",
                "1 January 2024 00:00:05",
                "Mon Jan 01 00:00:05 2024",
                "Mon Jan  1 00:00:05 UTC 2024",
                "31-Feb-2024 00:00:00",  # no such day: the ISO parser refuses it
                "01-Foo-2024 00:00:00",
            ]
        )
    ).tolist()
    assert got[:6] == ["2024-01-01T00:00:05"] * 2 + ["2024-01-01T12:00:05"] + [
        "2024-01-01T00:00:05"
    ] * 2 + ["2024-01-01T00:00:05Z"]
    assert pd.isna(got[7])
    han = chinese_iso(
        pd.Series(
            ["2024年1月1日 00:00:05", "2024年01月01日 00时00分05秒", "2024年1月1日 下午3:00:05"]
        )
    )
    assert han.tolist() == ["2024-01-01T00:00:05", "2024-01-01T00:00:05", "2024-01-01T15:00:05"]


def test_a_bad_month_name_row_is_quarantined_alone_and_the_zone_applies(tmp_path):
    cells = [t.strftime("%d-%b-%Y %H:%M:%S") for t in TIMES]
    cells[4] = "31-Feb-2024 00:00:00"
    cells[7] = "01-Foo-2024 00:00:07"
    r = read_points(_write(tmp_path / "t.csv", cells), tz="+08:00")
    assert len(r.points) == 28
    assert sorted(r.quarantine["line"].tolist()) == [6, 9]
    assert set(r.quarantine["reason"]) == {"unparsable time"}
    assert r.points["time"].min() == START - pd.Timedelta(hours=8)


@_SETTINGS
@given(
    seconds=st.lists(
        st.integers(0, 40 * 365 * 86_400), min_size=3, max_size=20, unique=True
    ),  # 2000-2040
    fmt=st.sampled_from(
        [
            "%d-%b-%Y %H:%M:%S",
            "%d-%B-%Y %H:%M:%S",
            "%b %d, %Y %I:%M:%S %p",
            "%a %b %d %H:%M:%S %Y",
            "%d %b %Y %H:%M:%S",
            "%Y年%m月%d日 %H:%M:%S",
            "%Y年%m月%d日 %H时%M分%S秒",
        ]
    ),
    upper=st.booleans(),
)
def test_month_names_and_chinese_dates_read_back_any_time(seconds, fmt, upper):
    times = [pd.Timestamp("2000-01-01", tz="UTC") + pd.Timedelta(seconds=s) for s in seconds]
    cells = [t.strftime(fmt) for t in times]
    if upper:
        cells = [c.upper() for c in cells]
    ns, ok = parse_times(pa.chunked_array([pa.array(cells)]), "auto")
    assert ok.all()
    assert (ns == np.array([t.value for t in times])).all()


def test_clock_times_without_a_date_read_relative_and_on_the_date_given(tmp_path):
    cells = [t.strftime("%H:%M:%S") + ".5" for t in TIMES + pd.Timedelta(hours=23, minutes=50)]
    p = _write(tmp_path / "tod.csv", cells, "Time,Track,Lat,Lon")
    r = read_points(p)
    assert len(r.points) == 30 and r.report["time_relative"]
    assert r.report["time_format"] == "clock time text"
    assert r.report["clock_date"] is None and r.report["clock_rollovers"] == 0
    assert r.points["time"].min() == pd.Timestamp("1970-01-01 23:50:00.5", tz="UTC")
    assert any("give their day with --date YYYY-MM-DD" in w for w in r.report["warnings"])
    d = read_points(p, clock_date="2024-03-05", tz="Europe/Oslo")
    assert not d.report["time_relative"] and d.report["clock_date"] == "2024-03-05"
    assert d.points["time"].min() == pd.Timestamp("2024-03-05 22:50:00.5", tz="UTC")
    with pytest.raises(InputError, match="YYYY-MM-DD"):
        read_points(p, clock_date="05/03/2024")
    info = inspect_file(p)
    assert info["clock_only"] == "Time"


def test_the_day_rolls_over_by_track_and_is_counted(tmp_path):
    # two tracks 23:59:50 → 00:00:19, and one that steps back 1 min only (no rollover)
    cells, ids = [], []
    for k in range(30):
        s = (86_390 + k) % 86_400
        for tr in (1, 2):
            cells.append(f"{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}")
            ids.append(tr)
    cells += ["10:00:00", "09:59:00", "10:01:00"]
    ids += [3, 3, 3]
    rows = [f"{c},{i},37.9,23.{k:04d}" for k, (c, i) in enumerate(zip(cells, ids, strict=True))]
    p = tmp_path / "roll.csv"
    p.write_text("Time,Track,Lat,Lon\n" + "\n".join(rows) + "\n")
    r = read_points(p, clock_date="2024-01-01")
    assert r.report["clock_rollovers"] == 2
    one = r.points[r.points["batch"] == "1"]["time"]
    assert one.min() == pd.Timestamp("2024-01-01 23:59:50", tz="UTC")
    assert one.max() == pd.Timestamp("2024-01-02 00:00:19", tz="UTC")
    three = r.points[r.points["batch"] == "3"]["time"]
    assert three.max() == pd.Timestamp("2024-01-01 10:01:00", tz="UTC")
    assert any("passes midnight" in w for w in r.report["warnings"])


@_SETTINGS
@given(
    steps=st.lists(st.integers(1, 3 * 3600), min_size=1, max_size=40),
    start=st.integers(0, 86_399),
)
def test_rolled_clock_times_are_the_times_they_were(steps, start):
    """Times of one track, each step forward under 12 h, written as clock times alone:
    rolled over midnight they are the times again."""
    true = start + np.concatenate([[0], np.cumsum(steps)]).astype("int64")
    clock = (true % 86_400) * 1_000_000_000
    got, rolled = roll_days(np.zeros(len(true), "int64"), clock, np.ones(len(true), bool))
    assert (got == true * 1_000_000_000).all()
    assert rolled == int(true[-1] // 86_400 - true[0] // 86_400)


@_SETTINGS
@given(st.lists(st.integers(0, 86_399), min_size=1, max_size=30), st.integers(0, 999))
def test_clock_seconds_of_any_time(seconds, ms):
    text = pd.Series([f"{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}.{ms:03d}" for s in seconds])
    got = clock_seconds(text).to_numpy()
    assert np.allclose(got, np.asarray(seconds) + ms / 1000)


def test_hhmmss_numbers_are_clocks_only_when_their_steps_show_it(tmp_path):
    probe = np.arange(120000, 120030, dtype="float64")  # no minute passed: no evidence
    assert hhmmss_evidence(probe) is None
    p = _write(tmp_path / "hh.csv", [str(int(v)) for v in probe], "TIME,TRK,LAT,LON")
    assert read_points(p, mapping=["batch=TRK"]).report["time_format"] == "relative s"
    sod = 12 * 3600 + np.arange(0, 180, 3)  # every 3 s across three minutes
    hh = (sod // 3600) * 10000 + (sod // 60 % 60) * 100 + sod % 60
    assert hhmmss_evidence(hh.astype("float64")) == (120057, 120100)
    p = _write(tmp_path / "hh2.csv", [str(v) for v in hh], "TIME,TRK,LAT,LON")
    r = read_points(p, mapping=["batch=TRK"], clock_date="2024-01-01")
    assert r.report["time_format"] == "HHMMSS clock numbers"
    assert r.report["hhmmss"] == [120057, 120100]
    assert r.points["time"].min() == pd.Timestamp("2024-01-01 12:00:00", tz="UTC")
    assert any("written HHMMSS" in w for w in r.report["warnings"])
    # the operator says seconds: seconds
    s = read_points(p, mapping=["batch=TRK"], time_unit="seconds")
    assert s.report["time_format"] == "relative s"
    # relative seconds never are: they pass 59 within a minute
    assert hhmmss_evidence(np.arange(0, 200, 3, dtype="float64")) is None
    assert hhmmss_evidence(np.arange(120000, 120200, 7, dtype="float64")) is None


@_SETTINGS
@given(step=st.integers(1, 19), n=st.integers(25, 80), start=st.integers(0, 80_000))
def test_a_clock_written_hhmmss_is_found_and_seconds_are_not(step, n, start):
    sod = (start + step * np.arange(n)) % 86_400
    hh = (sod // 3600) * 10000 + (sod // 60 % 60) * 100 + sod % 60
    if len(np.unique(sod // 60)) > 1:  # a minute passed: the clock shows
        assert hhmmss_evidence(hh.astype("float64")) is not None
    seconds = (start + step * np.arange(n)).astype("float64")
    if np.ptp(seconds) >= 100:  # plain seconds over 100 s land on a number ending 60-99
        assert hhmmss_evidence(seconds) is None


def test_streamed_and_piece_reads_are_the_whole_read(tmp_path, monkeypatch):
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 256)
    for name, cells, header in (
        ("m.csv", [t.strftime("%d-%b-%Y %H:%M:%S") for t in TIMES], "time,id,lat,lon"),
        ("c.csv", [t.strftime("%Y年%m月%d日 %H时%M分%S秒") for t in TIMES], "时间,批号,纬度,经度"),
        ("t.csv", [t.strftime("%H:%M:%S") for t in TIMES], "Time,Track,Lat,Lon"),
    ):
        p = _write(tmp_path / name, cells, header)
        whole = read_points(p, clock_date="2024-01-01")
        out = tmp_path / f"o_{name}"
        r = import_to_csv(p, out, clock_date="2024-01-01")
        got = pd.to_datetime(pd.read_csv(out)["time"], utc=True)
        assert sorted(got) == _times(whole.points) == list(TIMES)
        assert r.report["time_format"] == whole.report["time_format"]
        if name != "t.csv":
            assert r.report.get("streamed") and r.report["warnings"] == whole.report["warnings"]
            seen: list[pd.DataFrame] = []
            read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
            res = read_in_pieces(sniff(p), read, seen.append, tmp_path / "s")
            assert res.report["pieces"] > 1 and _times(pd.concat(seen)) == list(TIMES)


def test_the_cli_batch_and_clean_take_date(tmp_path, capsys):
    from wakeline.core.batch import BatchOptions, _read_options

    assert _read_options(BatchOptions(clock_date="2024-01-01"))["clock_date"] == "2024-01-01"
    p = _write(tmp_path / "t.csv", [t.strftime("%H:%M:%S") for t in TIMES], "Time,Track,Lat,Lon")
    out = tmp_path / "o.csv"
    assert main(["import", str(p), "-o", str(out), "--date", "2024-01-01"]) == 0
    assert "times of day read on 2024-01-01, 0 past midnight" in capsys.readouterr().err
    assert sorted(pd.to_datetime(pd.read_csv(out)["time"], utc=True)) == list(TIMES)
    cleaned = tmp_path / "c.csv"
    assert main(["clean", str(p), "-o", str(cleaned), "--date", "2024-01-01"]) == 0
    assert pd.to_datetime(pd.read_csv(cleaned)["time"], utc=True).min() == START
    with pytest.raises(SystemExit):
        main(["import", str(p), "-o", str(out), "--date"])


def test_date_given_for_dated_times_is_said(tmp_path):
    p = _write(tmp_path / "m.csv", [t.strftime("%d-%b-%Y %H:%M:%S") for t in TIMES])
    r = read_points(p, clock_date="2023-05-05")
    assert _times(r.points) == list(TIMES)
    (said,) = [w for w in r.report["warnings"] if "--date (for times of day" in w]
    assert "month-name text, with their dates" in said


@pytest.mark.parametrize(
    "cells",
    [
        [t.strftime("%d-%b-%Y %H:%M:%S") for t in TIMES],
        [t.strftime("%d-%b-%y %H.%M.%S").upper() for t in TIMES],
        [t.strftime("%a %b %d %H:%M:%S %Y") for t in TIMES],
        [f"{t.year}年{t.month}月{t.day}日 {t.strftime('%H:%M:%S')}" for t in TIMES],
        [t.strftime("%Y年%m月%d日 %H时%M分%S秒") for t in TIMES],
        [t.strftime("%H:%M:%S") + ".5" for t in TIMES],
    ],
)
def test_export_like_writes_the_forms_back(tmp_path, cells, capsys):
    p = _write(tmp_path / "f.csv", cells)
    imported = tmp_path / "i.csv"
    assert main(["import", str(p), "-o", str(imported)]) == 0
    again = tmp_path / "again.csv"
    capsys.readouterr()
    assert main(["export", str(imported), "-o", str(again), "--like", str(p)]) == 0
    assert again.read_bytes() == p.read_bytes()
    assert "January 1970" not in capsys.readouterr().err  # times of day: no dates written


def test_export_like_writes_iso_for_forms_it_reads_only(tmp_path):
    p = _write(tmp_path / "us.csv", [t.strftime("%b %d, %Y %I:%M:%S %p") for t in TIMES])
    assert describe_layout(p).time.pattern == "%Y-%m-%dT%H:%M:%S"


def test_the_window_names_the_dialog_field(tmp_path):
    from wakeline.app.window_words import window_words

    said = window_words(
        "read on 1970-01-01 as relative times; give their day with --date YYYY-MM-DD"
    )
    assert "--" not in said and "Date of clock times" in said
    p = _write(tmp_path / "m.csv", [t.strftime("%d-%b-%Y %H:%M:%S") for t in TIMES])
    for w in read_points(p, clock_date="2024-01-01").report["warnings"]:
        assert "--" not in window_words(w), window_words(w)
    assert "Date of clock times field (for times of day" in window_words(w)


def test_a_batch_reads_times_of_day_on_the_date_given(tmp_path):
    pytest.importorskip("dask")
    from wakeline.core.batch import BatchOptions, run_batch
    from wakeline.core.pipeline import Pipeline

    times = pd.date_range("2024-01-01 23:00", periods=200, freq="60s", tz="UTC")  # to 02:19
    p = _write(tmp_path / "t.csv", [t.strftime("%H:%M:%S") for t in times], "Time,Track,Lat,Lon")
    opts = BatchOptions(csv=True, clock_date="2024-01-01")
    rep = run_batch(Pipeline.default(), [p], tmp_path / "out", opts).report
    assert rep["rows_read"] == 200 and rep["quarantined"] == 0
    got = pd.to_datetime(pd.read_csv(tmp_path / "out" / "clean.csv")["time"], utc=True)
    assert got.min() >= times[0] and got.max() <= times[-1]  # rolled over by track
    with pytest.raises(InputError, match="YYYY-MM-DD"):
        run_batch(Pipeline.default(), [p], tmp_path / "o2", BatchOptions(clock_date="1/2/24"))


def test_gui_file_and_evaluate_real_take_date(monkeypatch, capsys):
    from wakeline.app import cli

    seen = {}
    monkeypatch.setattr(
        "wakeline.app.main.run",
        lambda files, screenshot=None, read=None: seen.update(files=files, read=read) or 0,
    )
    assert cli.main(["gui", "tod.csv", "--date", "2024-01-01"]) == 0
    assert seen["read"] == {"clock_date": "2024-01-01"}
    # evaluate takes it for --real's files only (as every reading flag)
    assert main(["evaluate", "maneuver", "--date", "2024-01-01"]) == 2
    assert "apply to --real's files" in capsys.readouterr().err


@pytest.mark.parametrize(
    "head,date",
    [
        ("日期,时间,批号,纬度,经度", lambda t: f"{t.year}年{t.month}月{t.day}日"),
        ("Date,Time,id,lat,lon", lambda t: t.strftime("%d-%b-%y").upper()),
    ],
)
def test_a_date_column_in_words_beside_clock_times_reads_and_writes_back(tmp_path, head, date):
    rows = [
        f"{date(t)},{t.strftime('%H:%M:%S')},{1 + k % 2},37.{k:04d},23.{k:04d}"
        for k, t in enumerate(TIMES)
    ]
    p = tmp_path / "dt.csv"
    p.write_text(head + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    r = read_points(p)
    assert _times(r.points) == list(TIMES) and r.report["time_date_column"]
    imported, again = tmp_path / "i.csv", tmp_path / "again.csv"
    assert main(["import", str(p), "-o", str(imported)]) == 0
    assert main(["export", str(imported), "-o", str(again), "--like", str(p)]) == 0
    assert again.read_bytes() == p.read_bytes()

"""A time column of Excel serial days (45658.5 = 2025-01-01 12:00) is read as dates by
a stated rule or ``--time-unit excel-days``; a clock of seconds in the same range is not,
and is never turned into dates without a message."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import import_to_csv, read_points
from wakeline.core.io.layout import describe_layout

START = pd.Timestamp("2025-01-01 12:00", tz="UTC")


def _write(path: Path, times: np.ndarray, header: str = "time", digits: int = 10) -> Path:
    lines = [f"id,{header},lat,lon"] + [
        f"{1 + k % 2},{t:.{digits}f},57.{k:03d},11.{k:03d}" for k, t in enumerate(times)
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


def _excel(n: int = 60, step_s: float = 10.0) -> np.ndarray:
    return 45658.5 + np.arange(n) * step_s / 86400.0


def test_excel_days_are_read_as_dates_and_the_report_says_why(tmp_path):
    r = read_points(_write(tmp_path / "x.csv", _excel()))
    assert len(r.points) == 60 and len(r.quarantine) == 0
    want = START + pd.to_timedelta(np.arange(60) * 10, unit="s")
    assert sorted(r.points["time"]) == list(want)
    assert r.report["time_format"] == "Excel serial days"
    assert r.report["time_unit"].startswith("Excel serial days (all lie in 20,000-80,000")
    (w,) = [w for w in r.report["warnings"] if "Excel serial days" in w]
    assert w.startswith("60 times in 'time' were read as Excel serial days")
    assert "--time-unit seconds" in w


def test_a_header_naming_excel_days_decides_without_the_steps(tmp_path):
    # whole hours apart (0.0417 day steps, above the step rule): the header says it
    days = 45658.0 + np.arange(30) / 24.0
    r = read_points(
        _write(tmp_path / "x.csv", days, header="ExcelDate"), mapping=["time=ExcelDate"]
    )
    assert r.report["time_format"] == "Excel serial days"
    assert "the header 'ExcelDate' names them" in r.report["time_unit"]
    assert sorted(r.points["time"])[1] - sorted(r.points["time"])[0] == pd.Timedelta("1h")


def test_a_clock_of_seconds_in_the_range_stays_seconds_and_is_said(tmp_path):
    secs = 30_000.25 + np.arange(60) * 1.5  # a 8.3 h scene clock, 1.5 s steps
    r = read_points(_write(tmp_path / "s.csv", secs, digits=2))
    assert r.report["time_format"] == "relative s" and r.report["time_relative"]
    assert r.points["time"].min() == pd.Timestamp("1970-01-01 08:20:00.25", tz="UTC")
    (w,) = [w for w in r.report["warnings"] if "--time-unit excel-days" in w]
    assert "lie between 20,000 and 80,000: read as seconds" in w
    assert "steps of a clock of seconds" in r.report["time_unit"]
    # ... and the operator may say otherwise: every row read, none lost
    days = read_points(tmp_path / "s.csv", time_unit="excel-days")
    assert days.report["time_unit"] == "Excel serial days (given: --time-unit)"
    assert len(days.points) == 60 and days.points["time"].min().year == 1982


def test_seconds_given_never_reads_days(tmp_path):
    r = read_points(_write(tmp_path / "x.csv", _excel()), time_unit="seconds")
    assert r.report["time_format"] == "relative s"
    assert not any("Excel" in w for w in r.report["warnings"])


def test_whole_numbers_in_the_range_are_seconds(tmp_path):
    r = read_points(_write(tmp_path / "s.csv", 40_000.0 + np.arange(60), digits=0))
    assert r.report["time_format"] == "relative s"  # no fractions: not days with clock times
    assert any("--time-unit excel-days" in w for w in r.report["warnings"])


def test_unix_seconds_are_untouched(tmp_path):
    r = read_points(_write(tmp_path / "u.csv", 1.7e9 + np.arange(60) * 0.25, digits=2))
    assert r.report["time_format"] == "unix s"
    assert r.report["time_unit"] == "unix s"
    assert not any("Excel" in w for w in r.report["warnings"])


def test_a_damaged_value_neither_hides_the_days_nor_is_lost(tmp_path):
    days = _excel(200)
    days[57] = 7.5  # cut short
    r = read_points(_write(tmp_path / "x.csv", days))
    assert r.report["time_format"] == "Excel serial days"
    assert len(r.points) + len(r.quarantine) == 200
    assert r.quarantine["line"].tolist() == [59]


def test_the_zone_applies_to_excel_wall_clock_times(tmp_path):
    r = read_points(_write(tmp_path / "x.csv", _excel(5)), tz="+08:00")
    assert r.points["time"].min() == START - pd.Timedelta("8h")


def test_streamed_import_and_pieces_agree_with_the_whole_read(tmp_path, monkeypatch):
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 512)
    p = _write(tmp_path / "x.csv", _excel(300))
    out = tmp_path / "o.csv"
    r = import_to_csv(p, out)
    assert r.report.get("streamed") and r.report["time_format"] == "Excel serial days"
    whole = read_points(p).points["time"]
    assert sorted(pd.to_datetime(pd.read_csv(out)["time"], utc=True)) == sorted(whole)
    assert sum("Excel serial days" in w for w in r.report["warnings"]) == 1
    assert r.report["warnings"][0].startswith("300 times")


def test_the_cli_flag_and_an_unknown_unit(tmp_path, capsys):
    secs = _write(tmp_path / "s.csv", 30_000.25 + np.arange(60) * 1.5, digits=2)
    out = tmp_path / "o.csv"
    assert main(["import", str(secs), "-o", str(out), "--time-unit", "excel-days"]) == 0
    assert "times read as Excel serial days (given: --time-unit)" in capsys.readouterr().err
    with pytest.raises(InputError, match="unknown time unit 'hours'"):
        read_points(secs, time_unit="hours")


def test_export_like_writes_excel_days_back(tmp_path):
    p = _write(tmp_path / "x.csv", _excel(40))
    assert describe_layout(p).time.kind == "excel"
    out = tmp_path / "back.csv"
    assert main(["export", str(p), "-o", str(out), "--like", str(p)]) == 0
    assert out.read_text().splitlines()[:2] == p.read_text().splitlines()[:2]
    # read back: the same points (times to the ms the reading keeps)
    a, b = read_points(p).points, read_points(out).points
    assert a["time"].tolist() == b["time"].tolist()
    assert np.array_equal(a[["lon", "lat"]].to_numpy(), b[["lon", "lat"]].to_numpy())


def test_a_unit_given_for_text_times_is_said_and_clean_refuses_an_unknown_one(tmp_path):
    from wakeline.core.clean_stream import clean_file

    p = tmp_path / "iso.csv"
    p.write_text(
        "id,time,lat,lon\n1,2025-01-01T12:00:00Z,57.1,11.1\n1,2025-01-01T12:00:10Z,57.2,11.2\n"
    )
    r = read_points(p, time_unit="excel-days")
    assert len(r.points) == 2 and r.points["time"].iloc[0] == START
    assert any(
        w.startswith("--time-unit excel-days applies to numbers") for w in r.report["warnings"]
    )
    with pytest.raises(InputError, match="unknown time unit"):
        clean_file(p, tmp_path / "o.csv", time_unit="days")


def test_a_read_in_pieces_decides_on_its_first_piece(tmp_path, monkeypatch):
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    days = _excel(101)  # the last piece: one row, no step to judge by
    lines = ["id,time,lat,lon"] + [
        f'"1",{t:.10f},57.{k:03d},11.{k:03d}' for k, t in enumerate(days)
    ]
    p = tmp_path / "q.csv"
    p.write_text("\n".join(lines) + "\n")
    r = import_to_csv(p, tmp_path / "o.csv")
    whole = read_points(p)
    assert r.report["pieces"] > 3 and r.report["excel_days"] == 101
    assert r.report["warnings"] == whole.report["warnings"]
    got = pd.to_datetime(pd.read_csv(tmp_path / "o.csv")["time"], utc=True)
    assert got.tolist() == whole.points["time"].tolist()

"""Slashed dates (03/04/2025) read day first, month first, or as the file shows:
``--date-order`` / ``read_points(date_order=...)`` through every reader."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import import_to_csv, read_points
from wakeline.core.io.layout import describe_layout
from wakeline.core.io.pieces import read_in_pieces
from wakeline.core.io.sniff import sniff

#: A US export: month first; March 1-20 every 12 h (days 13-20 show the order).
US_TIMES = pd.date_range("2025-03-01", periods=40, freq="12h", tz="UTC")


def _write(path: Path, times: pd.DatetimeIndex, fmt: str) -> Path:
    lines = ["MMSI,BaseDateTime,LAT,LON"] + [
        f"{1 + k % 2},{t.strftime(fmt)},57.{k:03d},11.{k:03d}" for k, t in enumerate(times)
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


def _times(points: pd.DataFrame) -> list:
    return sorted(points["time"].tolist())


def test_a_us_file_reads_month_first_with_the_flag_and_by_itself(tmp_path):
    p = _write(tmp_path / "us.csv", US_TIMES, "%m/%d/%Y %H:%M:%S")
    given = read_points(p, date_order="month-first")
    assert len(given.points) == 40 and len(given.quarantine) == 0
    assert _times(given.points) == list(US_TIMES)
    assert given.report["date_order"] == "month-first (given: --date-order)"
    auto = read_points(p)  # days 13-20 decide it
    assert _times(auto.points) == list(US_TIMES)
    assert auto.report["date_order"].startswith("month-first (the file shows it: 16 dates")
    assert any("--date-order month-first" in w for w in auto.report["warnings"])


def test_ambiguous_dates_need_the_flag_and_the_warning_names_it(tmp_path):
    times = US_TIMES[:20]  # March 1-10 only: every date reads either way
    p = _write(tmp_path / "amb.csv", times, "%m/%d/%Y %H:%M:%S")
    auto = read_points(p)
    assert _times(auto.points) != list(times)  # read as 3 January ...: the old default
    (warning,) = [w for w in auto.report["warnings"] if "read day first" in w]
    assert "--date-order month-first" in warning
    assert auto.report["date_order"].startswith("day-first (assumed")
    assert _times(read_points(p, date_order="month-first").points) == list(times)


@pytest.mark.parametrize("corrupt", ["31/02/2025 10:00:00", "02/31/2025 10:00:00"])
def test_a_date_no_calendar_has_is_no_evidence_of_the_order(tmp_path, corrupt):
    """h122's M2: one corrupt date (31/02, 02/31: no date either way) among ambiguous
    month-first dates is quarantined and shows no order: the ambiguity warning stays, and a
    file whose other dates show the month first is still read so."""
    times = US_TIMES[:20]  # every good date reads either way
    p = _write(tmp_path / "amb.csv", times, "%m/%d/%Y %H:%M:%S")
    lines = p.read_text().splitlines()
    lines[5] = lines[5].split(",")[0] + f",{corrupt}," + ",".join(lines[5].split(",")[2:])
    p.write_text("\n".join(lines) + "\n")
    r = read_points(p)
    assert len(r.points) == 19 and r.quarantine["reason"].tolist() == ["unparsable time"]
    assert r.report["date_order"].startswith("day-first (assumed"), r.report["date_order"]
    (warning,) = [w for w in r.report["warnings"] if "read day first" in w]
    assert "18 could be mm/dd/yyyy" in warning  # 19 good, one of them 03/03
    us = _write(tmp_path / "us.csv", US_TIMES, "%m/%d/%Y %H:%M:%S")  # days 13-20 show it
    lines = us.read_text().splitlines()
    lines[5] = lines[5].split(",")[0] + f",{corrupt}," + ",".join(lines[5].split(",")[2:])
    us.write_text("\n".join(lines) + "\n")
    r = read_points(us)
    assert r.report["date_order"].startswith("month-first (the file shows it")
    assert len(r.points) == 39


def test_a_day_above_12_says_the_file_decided_day_first(tmp_path):
    p = _write(tmp_path / "eu.csv", US_TIMES, "%d/%m/%Y %H:%M:%S")
    r = read_points(p)
    assert _times(r.points) == list(US_TIMES)
    assert (
        r.report["date_order"]
        == "day-first (the file shows it: 16 dates have a first number above 12)"
    )
    assert not any("day first" in w for w in r.report["warnings"])


def test_a_date_the_given_order_cannot_read_is_quarantined_and_counted(tmp_path):
    p = _write(tmp_path / "us.csv", US_TIMES, "%m/%d/%Y %H:%M:%S")
    r = read_points(p, date_order="day-first")
    assert len(r.points) + len(r.quarantine) == 40  # nothing lost
    assert r.quarantine["reason"].value_counts().to_dict() == {"unparsable time": 16}
    (w,) = [w for w in r.report["warnings"] if "--date-order day-first says" in w]
    assert w.startswith("16 dates in 'BaseDateTime' have a second number above 12")


def test_an_unknown_order_is_refused(tmp_path):
    p = _write(tmp_path / "us.csv", US_TIMES, "%m/%d/%Y %H:%M:%S")
    with pytest.raises(InputError, match="unknown date order 'ymd'"):
        read_points(p, date_order="ymd")


def test_the_streamed_pieces_and_batch_readers_take_the_order(tmp_path, monkeypatch):
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 256)  # several pieces
    times = US_TIMES[:20]
    p = _write(tmp_path / "amb.csv", times, "%m/%d/%Y %H:%M:%S")
    out = tmp_path / "o.csv"
    r = import_to_csv(p, out, date_order="month-first")
    assert r.report.get("streamed") and r.report["date_order"].startswith("month-first (given")
    got = pd.read_csv(out)["time"]
    assert sorted(pd.to_datetime(got, utc=True)) == list(times)
    seen: list[pd.DataFrame] = []
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
    res = read_in_pieces(
        sniff(p), {**read, "date_order": "month-first"}, seen.append, tmp_path / "s"
    )
    assert res.report["pieces"] > 1
    assert _times(pd.concat(seen)) == list(times)


def test_batch_options_and_the_cli_take_the_flag(tmp_path, capsys):
    from wakeline.core.batch import BatchOptions, _read_options

    assert _read_options(BatchOptions(date_order="month-first"))["date_order"] == "month-first"
    p = _write(tmp_path / "amb.csv", US_TIMES[:20], "%m/%d/%Y %H:%M:%S")
    out = tmp_path / "o.csv"
    assert main(["import", str(p), "-o", str(out), "--date-order", "month-first"]) == 0
    assert "dates read month-first (given: --date-order)" in capsys.readouterr().err
    assert sorted(pd.to_datetime(pd.read_csv(out)["time"], utc=True)) == list(US_TIMES[:20])


def test_export_like_writes_the_order_given(tmp_path):
    p = _write(tmp_path / "amb.csv", US_TIMES[:20], "%m/%d/%Y %H:%M:%S")
    assert describe_layout(p).time.pattern.startswith("%d/%m/%Y")  # as auto reads it
    assert describe_layout(p, date_order="month-first").time.pattern.startswith("%m/%d/%Y")


_DAY = 86_400


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.integers(min_value=946_684_800, max_value=4_070_908_800),  # a start in 2000-2098
    st.lists(st.integers(min_value=0, max_value=400 * _DAY), min_size=1, max_size=30),
)
def test_property_day_and_month_first_writings_read_back_the_same(tmp_path, start, offsets):
    seconds = start + np.sort(np.asarray(offsets, dtype="int64"))
    times = pd.DatetimeIndex(pd.to_datetime(seconds, unit="s", utc=True))
    day = read_points(
        _write(tmp_path / "d.csv", times, "%d/%m/%Y %H:%M:%S"), date_order="day-first"
    )
    month = read_points(
        _write(tmp_path / "m.csv", times, "%m/%d/%Y %H:%M:%S"), date_order="month-first"
    )
    # every row a point or a quarantined row; the same instants either way
    assert len(day.points) + len(day.quarantine) == len(times)
    assert len(month.quarantine) == len(day.quarantine)
    assert _times(day.points) == _times(month.points)
    if not len(day.quarantine):
        assert _times(day.points) == list(times)


def test_a_batch_reads_its_csv_inputs_in_the_order_given(tmp_path):
    pytest.importorskip("dask")
    from wakeline.core.batch import BatchOptions, run_batch
    from wakeline.core.pipeline import Pipeline

    times = pd.date_range("2025-03-01", periods=200, freq="60s", tz="UTC")
    p = _write(tmp_path / "amb.csv", times, "%m/%d/%Y %H:%M:%S")
    opts = BatchOptions(csv=True, date_order="month-first", time_unit="seconds")
    rep = run_batch(Pipeline.default(), [p], tmp_path / "out", opts).report
    assert rep["rows_read"] == 200 and rep["quarantined"] == 0
    got = pd.to_datetime(pd.read_csv(tmp_path / "out" / "clean.csv")["time"], utc=True)
    assert got.min() >= times[0] and got.max() <= times[-1]  # March 1, not January 3


def test_the_window_names_the_dialogs_fields_for_the_flags(tmp_path):
    from wakeline.app.window_words import window_words

    p = _write(tmp_path / "amb.csv", US_TIMES[:20], "%m/%d/%Y %H:%M:%S")
    for w in read_points(p).report["warnings"] + [
        "if they are seconds, read again with --time-unit seconds",
        "read again with --time-unit excel-days",
    ]:
        assert "--" not in window_words(w), window_words(w)
    assert "Date order set to month first" in window_words(
        "read again with --date-order month-first"
    )


@pytest.mark.parametrize("fmt", ["%m/%d/%Y %H:%M:%S", "%d/%m/%Y %H:%M:%S"])
@pytest.mark.parametrize("order", ["auto", "day-first"])
def test_a_read_in_pieces_says_what_a_whole_read_says(tmp_path, monkeypatch, fmt, order):
    # quoted ids: read piece by piece; the pieces' counts are summed, and a day above 12
    # in one piece shows the order for all (before: one warning per piece, each its count)
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    times = pd.date_range("2025-03-01", periods=40, freq="12h", tz="UTC")
    lines = ["MMSI,BaseDateTime,LAT,LON"] + [
        f'"1",{t.strftime(fmt)},57.{k:02d},11.{k:02d}' for k, t in enumerate(times)
    ]
    p = tmp_path / "q.csv"
    p.write_text("\n".join(lines) + "\n")
    r = import_to_csv(p, tmp_path / "o.csv", date_order=order)
    whole = read_points(p, date_order=order).report
    if whole["time_format"] == "month-first text" and order == "auto":
        assert "pieces" not in r.report  # shown month first in one piece: read whole
    elif order == "day-first" and fmt.startswith("%m"):
        # month-first dates read day first jump by months between rows, days from the
        # rows around them: a piece leaves such rows to a whole read (h149), or, since
        # session 27, to its track's next row in a later piece (LonePending): either way
        # the rows and the quarantine are the whole read's
        w = read_points(p, date_order=order)
        assert r.report["rows_imported"] == len(w.points)
        assert r.report["rows_quarantined"] == len(w.quarantine)
        assert sorted(r.quarantine["line"]) == sorted(w.quarantine["line"])
    else:
        assert r.report["pieces"] > 3
    assert r.report["warnings"] == whole["warnings"]
    assert r.report["date_order"] == whole["date_order"]
    assert r.report.get("date_order_refused") == whole.get("date_order_refused")


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    spelling=st.sampled_from(["{}m", "{}M", "{}.m.", "{}.M.", "{}.m", "{} m", "{}. m."]),
    upper=st.booleans(),
    month_first=st.booleans(),
    seconds=st.lists(st.integers(0, 86_399), min_size=3, max_size=12, unique=True),
)
def test_12_hour_clocks_read_however_am_and_pm_are_written(
    tmp_path, spelling, upper, month_first, seconds
):
    """An operator's US export wrote `03/12/2026 09:00:00 p.m.` (h118): every row was
    quarantined as unparsable time; strptime's %p takes AM/PM only."""
    start = pd.Timestamp("2026-03-14", tz="UTC")  # day 14: the order matters
    times = [start + pd.Timedelta(s, "s") for s in sorted(seconds)]
    rows = []
    for k, t in enumerate(times):
        letter = "a" if t.hour < 12 else "p"
        suffix = spelling.replace("{}", letter.upper() if upper else letter)
        date = t.strftime("%m/%d/%Y" if month_first else "%d/%m/%Y")
        rows.append(f"{date} {t.strftime('%I:%M:%S')} {suffix},A,57.{k:03d},11.5")
    p = tmp_path / "pm.csv"
    p.write_text("time,id,lat,lon\n" + "\n".join(rows) + "\n")
    order = "month-first" if month_first else "day-first"
    res = read_points(p, date_order=order)
    assert res.report["rows_quarantined"] == 0
    assert _times(res.points) == list(times)


def test_nothing_imported_because_of_a_given_order_or_unit_names_the_flag(tmp_path, capsys):
    """h118: a day-first file read with --date-order month-first, or Unix seconds read
    with --time-unit excel-days, ended "the time column is not a time Wakeline reads …
    check --map time=…": the flag that caused it was not named."""
    p = _write(tmp_path / "eu.csv", US_TIMES[:20] + pd.Timedelta(days=13), "%d/%m/%Y %H:%M:%S")
    out = tmp_path / "o.csv"
    assert main(["import", str(p), "-o", str(out), "--date-order", "month-first"]) == 2
    err = capsys.readouterr().err.splitlines()[-1]
    assert "20 dates cannot be month-first, as --date-order month-first says" in err
    assert err.endswith("try --date-order auto")
    u = tmp_path / "unix.csv"
    u.write_text(
        "t,id,lat,lon\n" + "".join(f"{1_700_000_000 + k},A,57.1,11.{k}\n" for k in range(5))
    )
    assert main(["import", str(u), "-o", str(out), "--time-unit", "excel-days"]) == 2
    err = capsys.readouterr().err.splitlines()[-1]
    assert "read as Excel serial days, as --time-unit excel-days says" in err
    assert err.endswith("try --time-unit auto")


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    spelling=st.sampled_from(["{}m", "{}M", "{}.m.", "{}.M.", " {}m", " {}.m.", " {}.M."]),
    upper=st.booleans(),
    split=st.booleans(),
    seconds=st.lists(st.integers(0, 86_399), min_size=3, max_size=10, unique=True),
)
def test_export_like_writes_am_and_pm_as_the_file_did(tmp_path, spelling, upper, split, seconds):
    """h118: `export --like` of a file with `09:00:00 p.m.` was refused ("cannot tell the
    time format"); now the mark comes back as written, also in a Date,Time layout."""
    from wakeline.core.io.export_like import write_layout
    from wakeline.core.io.layout import load_layout

    start = pd.Timestamp("2026-03-14", tz="UTC")
    rows = []
    for k, s in enumerate(sorted(seconds)):
        t = start + pd.Timedelta(s, "s")
        letter = "a" if t.hour < 12 else "p"
        mark = spelling.replace("{}", letter.upper() if upper else letter)
        sep = "," if split else " "
        rows.append(
            f"{t.strftime('%m/%d/%Y')}{sep}{t.strftime('%I:%M:%S')}{mark},A,57.{k:03d},11.5"
        )
    head = "Date,Time,id,lat,lon" if split else "time,id,lat,lon"
    p = tmp_path / "pm.csv"
    p.write_text(head + "\n" + "\n".join(rows) + "\n")
    res = read_points(p)
    assert res.report["rows_quarantined"] == 0
    out = tmp_path / "back.csv"
    write_layout(res.points, load_layout(p), out)
    assert out.read_text() == p.read_text()

"""SPEC §1 bad input: clear messages, exit status 2, nothing lost, no half-written files."""

import bz2
import json
import lzma
import os

import pandas as pd
import pytest

import wakeline.core.io.writer as writer_mod
from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import read_points, write_points

GOOD = "S1,1,2024-01-01T00:00:{s:02d}Z,122.5,30.{s:02d}"


def _file_with(write, bad_rows: dict[int, str], n: int = 10) -> tuple:
    """A canonical file of n good rows with bad rows inserted at the given data positions."""
    lines = ["sensor,batch,time,lon,lat"]
    for k in range(n):
        if k in bad_rows:
            lines.append(bad_rows[k])
        lines.append(GOOD.format(s=k))
    return write("mixed.csv", "\n".join(lines) + "\n"), lines


def _run(capsys, *args) -> tuple[int, str, str]:
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(
    ("row", "reason"),
    [
        ("S1,1,2024-01-01T00:01:00Z,122.5", "short row: 4 of 5 fields"),
        ("S1,1,2024-01-01T00:01:00Z,122.5,30,9", "too many fields: 6 of 5"),
        ("S1,1,not a time,122.5,30", "unparsable time"),
        ("S1,1,,122.5,30", "missing time"),
        ("S1,1,2024-01-01T00:01:00Z,east,30", "unparsable lon"),
        ("S1,1,2024-01-01T00:01:00Z,122.5,", "missing lat"),
        ("S1,1,2024-01-01T00:01:00Z,190.5,30", "lon out of range"),
        ("S1,1,2024-01-01T00:01:00Z,122.5,-91", "lat out of range"),
        ("S1,,2024-01-01T00:01:00Z,122.5,30", "missing batch"),
        ("S1,1,2024-01-01T00:01:00Z,122.5,30,", "too many fields: 6 of 5"),
    ],
)
def test_bad_row_is_quarantined_with_line_and_reason(write, row, reason):
    path, lines = _file_with(write, {3: row, 7: row})
    r = read_points(path)
    assert len(r.points) == 10  # every good row imported
    q = r.quarantine
    assert q.reason.tolist() == [reason, reason]
    expected_lines = [i + 1 for i, line in enumerate(lines) if line == row]
    assert q.line.tolist() == expected_lines
    assert q.text.tolist() == [row, row]
    assert r.report["rows_quarantined"] == 2
    assert r.report["quarantine_reasons"] == {reason: 2}
    assert r.report["rows_read"] == 12


def test_line_numbers_survive_blank_lines_and_many_bad_rows(write):
    rows = ["sensor,batch,time,lon,lat", ""]
    expected = []
    for k in range(200):
        if k % 7 == 0:
            rows.append("S1,1,2024-01-01T00:00:00Z,999,30")
            expected.append(len(rows))
        if k % 11 == 0:
            rows.append("S1,1")
            expected.append(len(rows))
        if k % 13 == 0:
            rows.append("")
        rows.append(f"S1,1,2024-01-01T00:{k // 60:02d}:{k % 60:02d}Z,122.5,30")
    r = read_points(write("many.csv", "\n".join(rows) + "\n"))
    assert len(r.points) == 200
    assert r.quarantine.line.tolist() == expected
    assert r.report["blank_lines"] == 1 + len(range(0, 200, 13))


def test_quarantine_and_report_files(write, tmp_path, capsys):
    path, _ = _file_with(write, {2: "S1,1,2024-01-01T00:01:00Z,200,30"})
    out, q, rep = tmp_path / "out.csv", tmp_path / "q.csv", tmp_path / "r.json"
    code, _, err = _run(capsys, "import", path, "-o", out, "--quarantine", q, "--report", rep)
    assert code == 0
    assert "10 rows" in err and "1 quarantined" in err
    assert len(pd.read_csv(out)) == 10
    qdf = pd.read_csv(q)
    assert qdf.line.tolist() == [4] and qdf.reason.tolist() == ["lon out of range"]
    report = json.loads(rep.read_text())
    assert report["rows_quarantined"] == 1 and report["rows_imported"] == 10


def test_missing_column_names_it_and_lists_headers(write, tmp_path, capsys):
    path = write("nolat.csv", "sensor,batch,time,lon,depth\nS1,1,2024-01-01T00:00:00Z,1,2\n")
    out = tmp_path / "out.csv"
    code, _, err = _run(capsys, "import", path, "-o", out)
    assert code == 2
    assert "missing required column lat" in err
    assert "headers found: sensor, batch, time, lon, depth" in err
    assert not out.exists()
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "sep, given, shown",
    [(",", ";", "','"), (";", ",", "';'"), ("\t", ",", "tab"), (",", "|", "','")],
)
def test_a_wrong_delimiter_says_the_header_is_one_column(
    write, tmp_path, capsys, sep, given, shown
):
    """Operator test 10: `--delimiter ';'` on a comma-separated GBK export listed "headers
    found: 批号,时间,经度,…", which reads as the seven columns found. The one name is said
    to be one column, with the separator it holds; the window says it in Chinese."""
    from wakeline.app import core_text

    header = sep.join(["批号", "时间", "经度", "纬度"])
    path = write(
        "gbk.csv",
        header + "\n" + sep.join(["7", "2024-01-01 00:00:00", "12", "56"]) + "\n",
        "gb18030",
    )
    code, _, err = _run(capsys, "import", path, "-o", tmp_path / "o.csv", "--delimiter", given)
    assert code == 2
    assert f"headers found: one column, {header!r} (separated by {shown}? check --delimiter)" in err
    with pytest.raises(InputError) as exc:
        read_points(path, delimiter=given)
    core_text.set_language("zh_CN")
    try:
        zh = core_text.shown(str(exc.value))
    finally:
        core_text.set_language("en")
    assert f"只有一列 {header!r}（分隔符其实是 {shown}？" in zh
    assert main(["import", str(path), "-o", str(tmp_path / "ok.csv")]) == 0  # left to sniff


def test_explicit_format_missing_column(write, tmp_path, capsys):
    path = write("r.csv", "SendShipNO,SendTime,lon,lat\n1,1664590563,1,2\n")
    code, _, err = _run(capsys, "import", path, "-o", tmp_path / "o.csv", "--format", "radar")
    assert code == 2 and "missing column(s) nNO" in err and "headers found: SendShipNO" in err


def test_mapping_to_absent_column(write, tmp_path, capsys):
    path = write("c.csv", "sensor,batch,time,lon,lat\nS1,1,2024-01-01T00:00:00Z,1,2\n")
    code, _, err = _run(capsys, "import", path, "-o", tmp_path / "o.csv", "--map", "batch=MMSI")
    assert code == 2 and "mapped column(s) not found: batch=MMSI" in err
    code, _, err = _run(capsys, "import", path, "-o", tmp_path / "o.csv", "--map", "vessel=MMSI")
    assert code == 2 and "unknown field 'vessel'" in err


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "the file is empty"),
        (b"\n\n  \n", "the file is empty"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)) * 4, "binary file"),
        # Compressed files open (tests/test_compressed.py); damaged ones are refused.
        (b"PK\x03\x04" + bytes(200), "a zip archive cut short or damaged"),
        (bz2.compress(b"batch,time,lon,lat\n" * 50)[:-20], "cut short or damaged (bz2: "),
        (lzma.compress(b"batch,time,lon,lat\n" * 50)[:-20], "cut short or damaged (xz: "),
        (b"\x1f\x8b\x08\x00garbage-not-gzip" * 10, "cut short or damaged (gzip: "),
        (b"7z\xbc\xaf\x27\x1c" + bytes(200), "a 7z archive; Wakeline opens text files, gzip"),
    ],
)
def test_unreadable_files_exit_2_with_one_line(write, tmp_path, capsys, content, message):
    path = write("bad.csv", content)
    out = tmp_path / "out.csv"
    code, stdout, err = _run(capsys, "import", path, "-o", out)
    assert code == 2
    assert message in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists() and stdout == ""


def test_wrong_encoding(write, tmp_path, capsys):
    path = write(
        "latin.csv",
        b"sensor,batch,time,lon,lat\n" + b"S1,\xe9t\xe9,2024-01-01T00:00:00Z,1,2\n" * 3,
    )
    code, _, err = _run(capsys, "import", path, "-o", tmp_path / "o.csv", "--encoding", "ascii")
    assert code == 2 and "cannot decode" in err


def test_a_few_undecodable_bytes_are_quarantined(write, tmp_path, capsys):
    path = write(
        "latin.csv",
        b"sensor,batch,time,lon,lat\nS1,1,2024-01-01T00:00:00Z,1,2\n" + b"\xff\xfe\xff",
    )
    q = tmp_path / "q.csv"
    code, _, err = _run(
        capsys, "import", path, "-o", tmp_path / "o.csv", "--encoding", "ascii", "--quarantine", q
    )
    assert code == 0, err
    assert "1 quarantined" in err and q.read_text().splitlines()[1].startswith("3,")


def test_missing_input_and_output_folder(tmp_path, capsys, write):
    code, _, err = _run(capsys, "import", tmp_path / "nothere.csv", "-o", tmp_path / "o.csv")
    assert code == 2 and "no such file" in err
    good = write("c.csv", "sensor,batch,time,lon,lat\nS1,1,2024-01-01T00:00:00Z,1,2\n")
    code, _, err = _run(capsys, "import", good, "-o", tmp_path / "no" / "o.csv")
    assert code == 2 and "does not exist" in err


def test_write_is_atomic(tmp_path, monkeypatch):
    target = tmp_path / "out.csv"
    target.write_text("old content\n")
    df = read_points_df()

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(writer_mod.pacsv, "write_csv", boom)
    with pytest.raises(OSError):
        write_points(df, target)
    assert target.read_text() == "old content\n"
    assert os.listdir(tmp_path) == ["out.csv"]  # no temporary file left behind


def test_internal_error_has_no_traceback(tmp_path, monkeypatch, capsys, write):
    import wakeline.core.io as io_mod

    def broken(*args, **kwargs):
        raise RuntimeError("something unexpected")

    monkeypatch.setattr(io_mod, "read_points", broken)
    monkeypatch.setattr(io_mod, "import_to_csv", broken)
    good = write("c.csv", "sensor,batch,time,lon,lat\nS1,1,2024-01-01T00:00:00Z,1,2\n")
    code, _, err = _run(capsys, "import", good, "-o", tmp_path / "o.csv")
    assert code == 1
    assert "internal error: RuntimeError: something unexpected" in err and "Traceback" not in err


def test_input_error_type():
    with pytest.raises(InputError):
        read_points("/definitely/not/here.csv")


def read_points_df() -> pd.DataFrame:
    return pd.DataFrame(
        {
            "sensor": ["S1"],
            "batch": ["1"],
            "time": pd.to_datetime(["2024-01-01"], utc=True),
            "lon": [1.0],
            "lat": [2.0],
        }
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_output_into_a_pipe_is_written_in_place_never_replaced(tmp_path):
    """``-o /dev/null`` or a named pipe: the data goes into it and it stays what it was
    (an atomic rename once turned /dev/null into a regular file)."""
    import stat
    import threading

    src = tmp_path / "in.csv"
    src.write_text(
        "sensor,batch,time,lat,lon\n"
        "R1,1,2024-01-01T00:00:00Z,30.0,120.0\n"
        "R1,1,2024-01-01T00:00:10Z,30.001,120.001\n"
    )
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()))
    reader.start()
    assert main(["import", str(src), "-o", str(fifo)]) == 0
    reader.join(10)
    assert stat.S_ISFIFO(fifo.stat().st_mode)
    assert got and got[0].count(b"\n") == 3
    assert not list(tmp_path.glob(".*.part"))


def test_an_import_that_keeps_nothing_fails_and_says_why(tmp_path, capsys):
    """Every row quarantined (a local-metres file) or no data rows: exit 2 with the reason
    and what to try; the quarantine is still written (nothing lost)."""
    from wakeline.app.cli import main

    metres = tmp_path / "metres.csv"
    metres.write_text(
        "mmsi,time,lon,lat\n1,2024-01-01T00:00:00Z,1234.5,-80.2\n1,2024-01-01T00:00:10Z,1240.0,-81\n"
    )
    q = tmp_path / "q.csv"
    assert main(["import", str(metres), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 2
    err = capsys.readouterr().err
    assert "all 2 rows were quarantined" in err and "degrees" in err
    assert len(q.read_text().strip().splitlines()) == 3  # header + both rows
    assert not (tmp_path / "o.csv").exists()  # no header-only output (h111: there was one)
    header_only = tmp_path / "h.csv"
    header_only.write_text("mmsi,time,lon,lat\n")
    assert main(["import", str(header_only), "-o", str(tmp_path / "o2.csv")]) == 2
    assert "no data rows" in capsys.readouterr().err
    assert not (tmp_path / "o2.csv").exists()


def test_a_gzip_cut_short_is_named_and_explained(tmp_path, capsys):
    """A .gz copied incompletely: an InputError naming the file and what to do (it was
    'Truncated compressed stream' with no file name), from read_points and the CLI."""
    import gzip

    from wakeline.app.cli import main

    rows = "".join(
        f"S1,1,2024-05-01T00:{k // 60:02d}:{k % 60:02d}Z,11.{k:04d},57.5\n" for k in range(3000)
    )
    full = gzip.compress(("sensor,batch,time,lon,lat\n" + rows).encode())
    cut = tmp_path / "cut.csv.gz"
    cut.write_bytes(full[: len(full) // 2])  # cut within the sniffer's first bytes
    with pytest.raises(InputError, match="cut.csv.gz: .*copy the file again"):
        read_points(cut)
    big = "".join(
        f"S1,{k % 97},2024-05-01T{k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d}Z,"
        f"{(k * 7919) % 100000 / 1e4:.4f},57.{k:06d}\n"
        for k in range(200_000)
    )
    full = gzip.compress(("sensor,batch,time,lon,lat\n" + big).encode(), compresslevel=1)
    cut.write_bytes(full[: len(full) * 9 // 10])  # cut beyond them: found while reading
    with pytest.raises(InputError, match="cut.csv.gz: the compressed data is cut short"):
        read_points(cut)
    assert main(["import", str(cut), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "cut.csv.gz" in err and "copy the file again" in err
    assert not (tmp_path / "o.csv").exists()


def test_a_unix_time_cut_short_is_quarantined_not_read_as_1970(tmp_path):
    """The last line cut inside its unix time ('172' of '1723247791') read as 00:02:52 on
    1 January 1970 inside a 2024 track; now it is quarantined with its reason, whether the
    file is read whole or in pieces (the CLI streams it)."""
    from wakeline.app.cli import main

    lines = [f"7 23.{5000 + k:05d} 38.04 {1723247000 + 10 * k}" for k in range(300)]
    src = tmp_path / "cut.txt"
    src.write_text("\n".join(lines) + "\n7 23.52422 38.04177 172")
    mapping = ["batch=col1", "lon=col2", "lat=col3", "time=col4"]
    res = read_points(src, mapping=mapping)
    assert res.report["rows_imported"] == 300
    assert res.quarantine["reason"].str.startswith("time decades before").tolist() == [True]
    assert not res.report["time_relative"]
    q = tmp_path / "q.csv"
    argv = ["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]
    assert main(argv + [a for m in mapping for a in ("--map", m)]) == 0
    assert "time decades before" in q.read_text()
    assert len(pd.read_csv(tmp_path / "o.csv")) == 300


@pytest.mark.parametrize("fmt", ["%Y-%m-%d %H:%M:%S", "%d/%m/%Y %H:%M:%S"])
def test_a_mistyped_year_in_text_times_is_quarantined(tmp_path, fmt):
    """Operator test: 1700-01-01 among 2023 rows (and 2203) parsed, imported, and
    survived clean; as with a unix number cut short, a text time decades from the file's
    others is a quarantine row with its line — read whole, by the CLI's streamed read, and
    a legitimate span of years (a 20-year archive) is untouched."""
    from wakeline.app.cli import main

    t0 = pd.Timestamp("2023-05-01 10:00:00")
    times = [t0 + pd.Timedelta(minutes=k) for k in range(40)]
    times[10] = times[10].replace(year=1700)
    times[25] = times[25].replace(year=2203)
    rows = ["sensor,batch,time,lon,lat"]
    rows += [f"AIS,1,{t.strftime(fmt)},{10 + k * 1e-3:.3f},55" for k, t in enumerate(times)]
    # 19 years earlier, a track of its own: a time of this archive
    rows += [f"AIS,2,{t.replace(year=2004).strftime(fmt)},11,55" for t in times[:5]]
    src = tmp_path / "years.csv"
    src.write_text("\n".join(rows) + "\n")
    res = read_points(src)
    assert res.report["rows_imported"] == 43
    assert res.quarantine["line"].tolist() == [12, 27]
    assert res.quarantine["reason"].str.startswith("time decades away").all()
    q = tmp_path / "q.csv"
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 0
    assert pd.read_csv(q)["line"].tolist() == [12, 27]
    assert len(pd.read_csv(tmp_path / "o.csv")) == 43


def test_a_lone_row_days_from_its_track_is_quarantined_and_real_gaps_are_not(tmp_path):
    """Operator test: 2032 and 2013 among 2023 rows (within the decades rule) imported,
    survived clean, and stretched the track over 19 years. A row days away from both rows
    of its track around it in the file, while those two are close, is quarantined; a real
    gap (a ship silent for days, then several rows), a track's first row days away on a
    day the file's other ships were recorded, and two interleaved tracks on different days
    are not."""
    from wakeline.app.cli import main

    t0 = pd.Timestamp("2023-03-01 03:00:00")
    rows = ["sensor,batch,time,lon,lat"]
    for k in range(60):  # track A, interleaved with track B (B is a week later)
        ta = t0 + pd.Timedelta(seconds=10 * k)
        if k == 20:
            ta = ta.replace(year=2032)  # mistyped year
        if k == 40:
            ta = ta.replace(month=7)  # mistyped month
        rows.append(f"AIS,A,{ta:%Y-%m-%d %H:%M:%S},{10 + k * 1e-4:.4f},55")
        tb = t0 + pd.Timedelta(days=7, seconds=10 * k)
        rows.append(f"AIS,B,{tb:%Y-%m-%d %H:%M:%S},{11 + k * 1e-4:.4f},55")
    for k in range(5):  # track C: silent for 3 days, then five rows
        tc = t0 + pd.Timedelta(days=3 if k >= 2 else 0, seconds=10 * k)
        rows.append(f"AIS,C,{tc:%Y-%m-%d %H:%M:%S},{12 + k * 1e-4:.4f},55")
    rows.append(f"AIS,D,{t0 - pd.Timedelta(days=30):%Y-%m-%d %H:%M:%S},13,55")  # first row
    rows += [f"AIS,D,{t0 + pd.Timedelta(seconds=10 * k):%Y-%m-%d %H:%M:%S},13,55" for k in range(5)]
    # track E: recorded on the day of D's first row (D's first row is not alone in the file)
    e0 = t0 - pd.Timedelta(days=30, hours=2)
    rows += [f"AIS,E,{e0 + pd.Timedelta(minutes=k):%Y-%m-%d %H:%M:%S},14,55" for k in range(5)]
    src = tmp_path / "typo.csv"
    src.write_text("\n".join(rows) + "\n")
    res = read_points(src)
    assert res.quarantine["line"].tolist() == [42, 82]
    assert res.quarantine["reason"].str.startswith("time days away").all()
    q = tmp_path / "q.csv"
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 0
    assert pd.read_csv(q)["line"].tolist() == [42, 82]


def _track_rows(batch: str, times, lon: float) -> list[str]:
    return [
        f"AIS,{batch},{t:%Y-%m-%d %H:%M:%S},{lon + k * 1e-4:.4f},55" for k, t in enumerate(times)
    ]


def test_a_mistyped_date_in_a_tracks_first_or_last_row_is_quarantined(tmp_path):
    """A track's first or last row has one neighbour, so the lone-row rule never saw a
    typo there: 2013 for 2023 in the last row of one track, 2024 in the first row of
    another imported and stretched them over 10 years and 1 year. Such an edge row is
    quarantined when it lies days from the rest of its track (and 100 times its median
    step), where no other track of the file is."""
    t0 = pd.Timestamp("2023-06-01 03:00:00")
    a = [t0 + pd.Timedelta(seconds=10 * k) for k in range(30)]
    a[-1] = a[-1].replace(year=2013)  # last row, line 31
    b = [t0 + pd.Timedelta(minutes=5, seconds=6 * k) for k in range(20)]
    b[0] = b[0].replace(year=2024)  # first row, line 32
    c = [t0 + pd.Timedelta(minutes=k) for k in range(10)]
    c[-1] += pd.Timedelta(days=3)  # a month's typo would be 30 days: a day's, 3 (line 61)
    rows = ["sensor,batch,time,lon,lat"]
    rows += _track_rows("A", a, 10) + _track_rows("B", b, 11) + _track_rows("C", c, 12)
    src = tmp_path / "edges.csv"
    src.write_text("\n".join(rows) + "\n")
    res = read_points(src)
    assert res.quarantine["line"].tolist() == [31, 32, 61]
    assert res.quarantine["reason"].str.startswith("time days from the rest of its track").all()
    assert res.report["rows_imported"] + res.report["rows_quarantined"] == 60
    span = res.points.groupby("batch")["time"].agg(lambda t: t.max() - t.min())
    assert (span < pd.Timedelta(hours=1)).all()
    q = tmp_path / "q.csv"
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 0
    assert pd.read_csv(q)["line"].tolist() == [31, 32, 61]
    assert len(pd.read_csv(tmp_path / "o.csv")) == 57


def test_edge_rows_of_real_data_shapes_are_kept(tmp_path):
    """What real data looks like at a track's ends is not quarantined: a ship seen again
    a day and more later while other ships are recorded then (AIS visits); a track
    sampled daily (a day's step is its own rhythm); a track of two rows (no step of its
    own to compare); a track whose last rows come back together after days (a real gap
    of several rows); an edge row within a day of its neighbour."""
    t0 = pd.Timestamp("2023-06-01 03:00:00")
    rows = ["sensor,batch,time,lon,lat"]
    visit = [t0 + pd.Timedelta(seconds=10 * k) for k in range(20)]
    visit.append(t0 + pd.Timedelta(days=2, hours=5))  # seen again 2 days later, once
    rows += _track_rows("V", visit, 10)
    other = [t0 + pd.Timedelta(hours=6 * k) for k in range(12)]  # a ship over those 3 days
    rows += _track_rows("O", other, 11)
    rows += _track_rows("D", [t0 + pd.Timedelta(days=k) for k in range(6)], 12)  # daily
    rows += _track_rows("T", [t0, t0 + pd.Timedelta(days=400)], 13)  # two rows
    back = [t0 + pd.Timedelta(seconds=30 * k) for k in range(10)]
    back += [t0 + pd.Timedelta(days=5, seconds=30 * k) for k in range(3)]  # 3 rows, 5 d on
    rows += _track_rows("G", back, 14)
    near = [t0 + pd.Timedelta(seconds=5 * k) for k in range(10)]
    near.append(t0 + pd.Timedelta(hours=23))  # within a day
    rows += _track_rows("N", near, 15)
    src = tmp_path / "real_shapes.csv"
    src.write_text("\n".join(rows) + "\n")
    res = read_points(src)
    assert len(res.quarantine) == 0
    assert res.report["rows_imported"] == len(rows) - 1


def test_a_one_track_file_whose_last_row_comes_back_alone_days_later_is_quarantined(tmp_path):
    """The rule's limit, as documented: with no other track in the file to say the day was
    recorded, a single row days after a track's rows is taken for a typo (the row keeps
    its line in the quarantine); with a second row there it is a real gap."""
    t0 = pd.Timestamp("2023-06-01 03:00:00")
    times = [t0 + pd.Timedelta(seconds=10 * k) for k in range(20)]
    rows = ["sensor,batch,time,lon,lat"] + _track_rows("A", [*times, t0 + pd.Timedelta(days=2)], 10)
    src = tmp_path / "one.csv"
    src.write_text("\n".join(rows) + "\n")
    assert read_points(src).quarantine["line"].tolist() == [22]
    rows.append(f"AIS,A,{t0 + pd.Timedelta(days=2, seconds=10):%Y-%m-%d %H:%M:%S},10,55")
    src.write_text("\n".join(rows) + "\n")
    assert len(read_points(src).quarantine) == 0


def test_unix_ms_cut_short_or_too_large_get_their_own_reason(tmp_path):
    """A millisecond file: a time cut to 9 digits is decades early; one cut to 11 digits
    (read as seconds: year 2508) and 1e22 are outside 1677-2262; none is 'unparsable'
    (review), and the CLI's streamed read agrees."""
    from wakeline.app.cli import main

    rows = ["batch,time,lon,lat"]
    rows += [f"A,{1700000000000 + 1000 * k},{10 + k * 1e-3:.3f},55" for k in range(50)]
    rows += ["A,170000001,10.5,55", "A,17000000220,10.5,55", "A,1e22,10.5,55"]
    src = tmp_path / "ms.csv"
    src.write_text("\n".join(rows) + "\n")
    res = read_points(src)
    assert res.report["rows_imported"] == 50
    assert res.quarantine["reason"].str.split(" ").str[:3].str.join(" ").tolist() == [
        "time decades before",
        "time outside 1677-2262",
        "time outside 1677-2262",
    ]
    q = tmp_path / "q.csv"
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 0
    assert pd.read_csv(q)["reason"].tolist() == res.quarantine["reason"].tolist()


def test_a_header_without_a_line_end_is_a_header_only_file(tmp_path, capsys):
    """`sensor,batch,time,lon,lat` and nothing else, no newline: 'no data rows', not 'a
    line is longer than 512 MB' (fuzzing)."""
    from wakeline.app.cli import main

    p = tmp_path / "h.csv"
    p.write_text("sensor,batch,time,lon,lat")
    assert main(["import", str(p), "-o", str(tmp_path / "o.csv")]) == 2
    assert "no data rows" in capsys.readouterr().err


def test_a_stray_nul_byte_is_its_rows_problem_in_any_file(tmp_path):
    """One NUL byte in a 40-line file refused the whole file as binary, while in a long
    file (beyond the sample) it only quarantined its row (fuzzing): now the row either
    way; a PNG is still a binary file."""
    from wakeline.core.errors import InputError
    from wakeline.core.io import read_points

    rows = [f"S,1,2024-01-01T00:00:{i:02d}Z,{10 + i * 1e-3:.3f},55" for i in range(40)]
    rows[5] = rows[5].replace("55", "5\x005")
    p = tmp_path / "nul.csv"
    p.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    r = read_points(p)
    assert r.report["rows_imported"] == 39 and r.quarantine["line"].tolist() == [7]
    png = tmp_path / "x.csv"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    with pytest.raises(InputError, match="binary"):
        read_points(png)


def test_tracks_of_three_or_four_daily_rows_are_kept(tmp_path):
    """Review h60 F1: with 3 rows both steps of a track are end steps; left out of its
    median step, that was 0 and the limit a day, so a ship's 3 noon reports (a day and an
    hour apart) lost 2 of them, and 3 ships of 3 reports each in consecutive weeks 6 of 9.
    The typical step of an edge row is now the median of its track's steps without its
    own step: they are kept, and a mistyped year in such a track is still quarantined."""
    t0 = pd.Timestamp("2023-06-01 00:00:00")
    step = pd.Timedelta(days=1, hours=1)
    cases = {
        "noon3": _track_rows("A", [t0 + k * step for k in range(3)], 10),
        "noon4": _track_rows("A", [t0 + k * step for k in range(4)], 10),
        "noon3x3": [
            row
            for w, b in enumerate("ABC")
            for row in _track_rows(b, [t0 + pd.Timedelta(weeks=w) + k * step for k in range(3)], 10)
        ],
    }
    for name, rows in cases.items():
        src = tmp_path / f"{name}.csv"
        src.write_text("\n".join(["sensor,batch,time,lon,lat", *rows]) + "\n")
        res = read_points(src)
        assert len(res.quarantine) == 0 and len(res.points) == len(rows), name
        q = tmp_path / f"{name}.q.csv"
        assert (
            main(["import", str(src), "-o", str(tmp_path / "o.csv"), "--quarantine", str(q)]) == 0
        )
        assert len(pd.read_csv(q)) == 0 and len(pd.read_csv(tmp_path / "o.csv")) == len(rows)
    typo = [t0 + k * step for k in range(3)]
    typo[-1] = typo[-1].replace(year=2013)
    src = tmp_path / "typo3.csv"
    src.write_text("\n".join(["sensor,batch,time,lon,lat", *_track_rows("A", typo, 10)]) + "\n")
    res = read_points(src)
    assert res.quarantine["line"].tolist() == [4] and len(res.points) == 2


def test_one_row_is_counted_in_the_singular():
    """Tester h133 (item 12), the core's messages: "all 1 rows were quarantined"."""
    from wakeline.core.io import nothing_imported

    rep = {"rows_read": 1, "quarantine_reasons": {"unparsable time": 1}}
    assert "nothing imported: the one row was quarantined, 1 as" in nothing_imported(rep, "x")
    rep = {"rows_read": 2, "quarantine_reasons": {"unparsable time": 2}}
    assert "all 2 rows were quarantined" in nothing_imported(rep, "x")


def test_every_missing_input_says_no_such_file(write, tmp_path, capsys):
    """Tester h133 (item 13): `wakeline review x.csv -o y.csv --proposals nonexist.csv`
    printed Python's "No such file or directory", as did a missing batch pipeline; every
    other input said "no such file" (one check, core.io.sniff.opening)."""
    path, _ = _file_with(write, {})
    gone = tmp_path / "nonexist.csv"
    out = str(tmp_path / "y.csv")
    for args in (
        ("review", str(path), "-o", out, "--proposals", str(gone)),
        ("batch", str(tmp_path / "nonexist.json"), str(path), "-o", str(tmp_path / "o")),
        ("clean", str(gone), "-o", out),
    ):
        code, _, err = _run(capsys, *args)
        assert code == 2 and err.strip().endswith(": no such file"), (args, err)
        assert "No such file or directory" not in err, (args, err)


@pytest.mark.parametrize("encoding", ["utf-8", "gb18030"])
def test_a_header_only_file_is_said_in_one_wording_by_every_subcommand(tmp_path, capsys, encoding):
    """Operator test 10: on a header-only file `export` said "no usable points: nothing to
    export", every other subcommand "no data rows (a header only?)". One wording now,
    exit 2, no output written."""
    from wakeline.app.cli import main

    src = tmp_path / "h.csv"
    src.write_bytes("批号,时间,经度,纬度\r\n".encode(encoding))
    said = {}
    for sub in ("import", "clean", "maneuvers", "compress", "export"):
        out = tmp_path / f"{sub}.csv"
        assert main([sub, str(src), "-o", str(out)]) == 2, sub
        err = capsys.readouterr().err
        said[sub] = err.strip().splitlines()[-1]
        assert not out.exists(), sub
    assert all(
        f"{src}: no data rows (a header only?); nothing imported" in t for t in said.values()
    ), said
    assert len(set(said.values())) == 1, said

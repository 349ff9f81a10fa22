"""The streamed clean (core/clean_stream.py) equals reading the file whole and cleaning it
in memory: points, reject trail, report and quarantine, on files whose tracks are
scattered through the file, cut into several pieces and blocks."""

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core import clean_stream, geo, simulate
from wakeline.core.clean import CleanParams, block_cuts, clean
from wakeline.core.clean_stream import clean_file
from wakeline.core.errors import Cancelled
from wakeline.core.io import read_points, reader, write_csv, write_points


def scattered_file(path, seed: int = 0, damaged: bool = True) -> None:
    """Two sensors, tracks with jumps, duplicates, a stay and a short track, rows in time
    order across tracks (every track's rows spread through the file), one track's rows
    split between the start and the end, and some damaged lines."""
    rng = np.random.default_rng(seed)
    df = simulate.segments_scene(seed=seed, n_ships=6, duration_s=1800.0, pieces=(1, 2))
    df = df.drop(columns=[c for c in df.columns if c.startswith("true_")])
    df["sensor"] = np.where(df["batch"].astype(str).str[-1].isin(["1", "3"]), "AIS", "R1")
    df["speed"] = np.round(rng.uniform(5, 15, len(df)), 1)
    df.loc[rng.choice(len(df), 5, replace=False), "speed"] = 90.0  # reported-speed outliers
    jump = rng.choice(np.arange(1, len(df) - 1), 12, replace=False)
    lon, lat = geo.destination(df.lon.to_numpy()[jump], df.lat.to_numpy()[jump], 45.0, 8000.0)
    df.loc[jump, "lon"], df.loc[jump, "lat"] = lon, lat
    dup = df.iloc[rng.choice(len(df), 8, replace=False)]
    stay = df.iloc[[0] * 30].copy()  # a ship at rest for 10 min
    stay["batch"], stay["sensor"] = "stay", "R1"
    stay["time"] = stay["time"].iloc[0] + pd.to_timedelta(np.arange(30) * 20.0, unit="s")
    stay["lon"] += rng.normal(0, 5e-5, 30)
    short = df.iloc[:4].assign(batch="short")
    df = pd.concat([df, dup, stay, short], ignore_index=True)
    df = df.iloc[np.argsort(df["time"].to_numpy(), kind="stable")].reset_index(drop=True)
    late = np.flatnonzero(df["batch"].to_numpy() == df["batch"].iloc[0])[::2]
    df = pd.concat([df.drop(index=late), df.iloc[late]], ignore_index=True)
    write_points(df[["sensor", "batch", "time", "lon", "lat", "speed", "course"]], path)
    if damaged:
        lines = path.read_text().splitlines()
        lines.insert(40, "R1,9,not a time,122.0,30.0,10.0,90.0")
        lines.insert(500, "R1,9,2024-05-01T00:00:00Z,999.0,30.0,10.0,90.0")
        lines.insert(900, "R1,9,2024-05-01T00:00:00Z,122.0")
        lines.insert(901, "")
        path.write_text("\n".join(lines) + "\n")


def in_memory(path, out, rej, params=None):
    """The step in memory, written as `wakeline clean` writes it (tracks in natural order)."""
    from wakeline.core.tracks import natural_track_order

    read = read_points(path)
    result = clean(read.points, params)
    write_points(natural_track_order(result.points), out)
    write_csv(result.rejected, rej)
    return result.report, read


def as_json(obj) -> str:
    return json.dumps(obj, sort_keys=True, default=str)


@pytest.mark.parametrize("block_rows", [150, 10**6])
def test_streamed_clean_equals_in_memory(tmp_path, monkeypatch, block_rows):
    src = tmp_path / "scattered.csv"
    scattered_file(src)
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", block_rows)
    want_report, want_read = in_memory(src, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)  # a dozen pieces
    cuts = []

    def spy(ends, rows):
        cuts.extend(block_cuts(ends, rows))
        return cuts

    monkeypatch.setattr(clean_stream, "block_cuts", spy)
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=block_rows)
    assert got.streamed
    assert len(cuts) >= (4 if block_rows == 150 else 1)
    assert src.stat().st_size > 8 * (4 << 10)  # eight pieces or more
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert as_json(got.report) == as_json(want_report)
    rules = want_report["rules"]
    assert rules["speed"]["removed"] and rules["stationary"]["removed"]
    assert rules["duplicates"]["removed"] == 8 and rules["short_tracks"]["removed"]
    # the reading's quarantine and counts are the same as the whole-file reader's
    for key in ("rows_read", "rows_imported", "rows_quarantined", "blank_lines", "tracks"):
        assert got.read_report[key] == want_read.report[key], key
    pd.testing.assert_frame_equal(
        got.quarantine.reset_index(drop=True), want_read.quarantine.reset_index(drop=True)
    )
    assert got.read_report["rows_quarantined"] == 3


def test_streamed_clean_keeps_the_files_ids(tmp_path, monkeypatch):
    """Cleaning a file that carries wl_id (a cleaned file of an earlier version: clean's
    points are written without it since D18) keeps its ids (as the in-memory clean does)."""
    src = tmp_path / "scattered.csv"
    scattered_file(src, seed=1, damaged=False)
    first = tmp_path / "first.csv"
    clean_file(src, first, params=CleanParams().with_settings(["turn.enabled=false"]))
    assert "wl_id" not in first.read_text().splitlines()[0].split(",")
    cleaned = read_points(first).points
    rng = np.random.default_rng(1)
    ids = rng.permutation(len(cleaned)) * 3 + 7  # ids of some earlier cleaning
    write_csv(cleaned.assign(wl_id=ids), first)
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", 250)
    want_report, _ = in_memory(first, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 8 << 10)
    got = clean_file(first, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=250)
    assert got.streamed
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert as_json(got.report) == as_json(want_report)
    trail = pd.read_csv(tmp_path / "b_rej.csv")
    assert len(trail) and set(trail["wl_id"]) <= set(ids)  # the file's ids, not row numbers


def test_streamed_clean_cancels_cleanly(tmp_path, monkeypatch):
    src = tmp_path / "scattered.csv"
    scattered_file(src, damaged=False)
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    monkeypatch.setattr("tempfile.tempdir", str(scratch))
    monkeypatch.setattr(reader, "STREAM_BYTES", 16 << 10)
    seen = []

    def progress(fraction: float, text: str) -> None:
        seen.append(fraction)
        if fraction > 0.6:
            raise Cancelled()

    with pytest.raises(Cancelled):
        clean_file(
            src, tmp_path / "out.csv", tmp_path / "rej.csv", progress=progress, block_rows=150
        )
    assert seen == sorted(seen) and max(seen) > 0.6  # progress moved on through the blocks
    assert not (tmp_path / "out.csv").exists() and not (tmp_path / "rej.csv").exists()
    assert list(scratch.iterdir()) == []
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]


def test_cli_clean_streams_and_matches_the_step(tmp_path, monkeypatch, capsys):
    src = tmp_path / "scattered.csv"
    scattered_file(src, seed=2)
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", 200)
    out, rej, rep = tmp_path / "out.csv", tmp_path / "rej.csv", tmp_path / "rep.json"
    code = main(["clean", str(src), "-o", str(out), "--rejected", str(rej), "--report", str(rep)])
    assert code == 0
    err = capsys.readouterr().err
    assert "3 rows quarantined on reading" in err and "kept " in err
    want_report, _ = in_memory(src, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    assert out.read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert rej.read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    report = json.loads(rep.read_text())
    assert report["points_out"] == want_report["points_out"]
    assert report["rules"]["speed"]["removed"] == want_report["rules"]["speed"]["removed"]
    assert report["params"]["clean"]["speed"]["v_max_kn"] == 40.0


def test_clean_file_falls_back_for_transforms_and_quotes(tmp_path):
    src = tmp_path / "scattered.csv"
    scattered_file(src, seed=3, damaged=False)
    params = CleanParams().with_settings(["smooth.enabled=true"])
    got = clean_file(src, tmp_path / "b.csv", params=params)
    assert not got.streamed
    read = read_points(src)
    want = clean(read.points, params)
    got_points = read_points(tmp_path / "b.csv").points
    assert "wl_id" not in got_points.columns  # clean's row id is not written (D18)
    pd.testing.assert_frame_equal(got_points, read_points_of(want.points, tmp_path))


def read_points_of(points: pd.DataFrame, folder) -> pd.DataFrame:
    write_points(points, folder / "want.csv")
    return read_points(folder / "want.csv").points


def test_scratch_of_a_killed_run_is_removed_by_the_next(tmp_path, monkeypatch):
    import subprocess
    import sys

    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    )
    stale = tmp_path / f"{clean_stream.SCRATCH_PREFIX}{int(dead.stdout)}-abc123"
    stale.mkdir()
    (stale / "run00000.arrow").write_bytes(b"x" * 100)
    alive = tmp_path / f"{clean_stream.SCRATCH_PREFIX}{__import__('os').getpid()}-def456"
    alive.mkdir()
    other = tmp_path / "wakeline-clean-notapid"
    other.mkdir()
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    src = tmp_path / "scattered.csv"
    scattered_file(src, damaged=False)
    clean_file(src, tmp_path / "out.csv")
    assert not stale.exists() and alive.exists() and other.exists()
    assert not [
        p
        for p in tmp_path.iterdir()
        if p.name.startswith("wakeline-clean-") and p not in (alive, other)
    ]


def test_a_late_stray_quote_is_quoted_as_the_whole_table_would(tmp_path, monkeypatch):
    """A quote after the sampled start is plain text (no quoting, as read_points reads
    it); the output quotes that column in every block, as the whole table's writer does."""
    src = tmp_path / "scattered.csv"
    scattered_file(src, damaged=False)
    lines = src.read_text().splitlines()
    lines = [lines[0] + ",remark"] + [line + ",ok" for line in lines[1:]]
    lines[-10] = lines[-10][:-2] + '"unclosed remark'
    src.write_text("\n".join(lines) + "\n")
    monkeypatch.setattr(sys.modules["wakeline.core.io.sniff"], "SAMPLE_BYTES", 4096)
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", 200)
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    want_report, _ = in_memory(src, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=200)
    assert got.streamed
    assert '"""unclosed remark"' in (tmp_path / "a.csv").read_text()
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert as_json(got.report) == as_json(want_report)


# -- a value the streamed reader cannot convert: the file read again in pieces --------------


def _bad_lon(line: str) -> str:
    """The line with its longitude mistyped (a letter l for a one): only the careful
    parse reads that column then, and the row is quarantined as unparsable."""
    parts = line.split(",")
    parts[3] = "l" + parts[3][1:]
    return ",".join(parts)


def _spy_reads(monkeypatch) -> list[int]:
    """The sizes of the files read_points reads from now on (pieces, or the whole file)."""
    import wakeline.core.io as wio

    sizes: list[int] = []
    real = wio.read_points

    def spy(path, *args, **kwargs):
        sizes.append(Path(path).stat().st_size)
        return real(path, *args, **kwargs)

    monkeypatch.setattr(wio, "read_points", spy)
    return sizes


def _same_as_in_memory(tmp_path, src, got, block_rows: int, tz: str | None = None) -> None:
    """Points, reject trail, clean report, quarantine and the import report of ``got``
    equal reading ``src`` whole and cleaning it in memory."""
    read = read_points(src, tz=tz)
    want = clean(read.points)
    write_points(want.points, tmp_path / "a.csv")
    write_csv(want.rejected, tmp_path / "a_rej.csv")
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert as_json(got.report) == as_json(want.report)
    pd.testing.assert_frame_equal(got.quarantine, read.quarantine)
    mine = {k: v for k, v in got.read_report.items() if k not in ("pieces", "streamed")}
    assert as_json(mine) == as_json(read.report)


@pytest.mark.parametrize("block_rows", [150, 10**6])
def test_a_bad_value_mid_file_is_read_in_pieces_not_whole(tmp_path, monkeypatch, block_rows):
    """Before: one value only the careful parse reads made `wakeline clean` read the whole
    file at once (a 318 MB file: peak 2.56 GB against 1.44 GB without it). Now the file
    is read again piece by piece (core/io/pieces.py), each piece its own careful parse:
    the same points, reject trail, quarantine (file line numbers, reasons) and import
    report as the whole-table way."""
    src = tmp_path / "scattered.csv"
    scattered_file(src)
    lines = src.read_text().splitlines()
    lines[700] = _bad_lon(lines[700])
    src.write_text("\n".join(lines) + "\n")
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", block_rows)
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)  # a dozen pieces
    sizes = _spy_reads(monkeypatch)
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=block_rows)
    assert got.streamed and got.read_report["pieces"] >= 10
    assert sizes and max(sizes) < src.stat().st_size / 4  # pieces, never the whole file
    monkeypatch.undo()
    _same_as_in_memory(tmp_path, src, got, block_rows)
    assert got.read_report["quarantine_reasons"]["unparsable lon"] == 1
    assert 701 in got.quarantine["line"].tolist() and got.read_report["rows_quarantined"] == 4


def _damaged_track_file(path, case: str) -> int:
    """A canonical file of a few tracks in time order with one mistyped longitude (where
    ``case`` says); returns the STREAM_BYTES to read it with."""
    rng = np.random.default_rng(5)
    n = 900
    k = np.arange(n)
    t = pd.Timestamp("2024-05-01T00:00:00Z") + pd.to_timedelta(k // 3 * 10.0, unit="s")
    df = pd.DataFrame(
        {
            "sensor": np.where(k % 3 == 0, "AIS", "R1"),
            "batch": (k % 3).astype(str),
            "time": t,
            "lon": 122.0 + k // 3 * 1e-4 + (k % 3) * 0.1 + rng.normal(0, 1e-5, n),
            "lat": 30.0 + k // 3 * 1e-4 + rng.normal(0, 1e-5, n),
            "speed": np.round(rng.uniform(5, 15, n), 1),
        }
    )
    if case == "header_only":  # a header longer than a read: the first piece is itself
        df["remark_" + "r" * 3000] = "ok"
    if case in ("gb18030", "latin1"):
        df["remark"] = "ok"
    if case == "clock_change":  # local times through the autumn clock change (02:00-03:00)
        utc = pd.Timestamp("2024-10-26T23:50:00Z") + pd.to_timedelta(k // 3 * 20.0, unit="s")
        df["time"] = utc.tz_convert("Europe/Oslo").tz_localize(None).strftime("%Y-%m-%d %H:%M:%S")
    write_points(df, path)
    lines = path.read_text().splitlines()
    at = {"first": 1, "last": len(lines) - 1, "header_only": 400, "quoted": 450}
    at.update({"unbalanced": 450, "blank_tail": 300, "clock_change": 1})
    at.update({"gb18030": 200, "latin1": 600})
    lines[at[case]] = _bad_lon(lines[at[case]])
    if case in ("quoted", "unbalanced"):  # quotes in the start: pieces read quoted
        lines[1:] = [line.replace("R1,", '"R1",', 1) for line in lines[1:]]
        lines[60] = lines[60].replace('"R1",', '"R1" ,')  # a space after the quote
    if case == "unbalanced":  # a quoted cell over two lines: the whole file line by line
        lines[701] = lines[701].replace('"R1",', '"R\n1",')
    if case == "blank_tail":  # the last pieces hold blank lines only
        lines += [""] * 5000
    data = ("\n".join(lines) + "\n").encode()
    if case == "gb18030":  # Chinese text after an ASCII start: the file reads as GB18030
        data = data[:20000] + data[20000:].replace(b",ok\n", ",船\n".encode("gb18030"))
    if case == "latin1":  # one line neither UTF-8 nor GB18030 reads: read as Windows-1252
        at = data.index(b",ok\n", 30000)
        data = data[:at] + b",caf\xe9\n" + data[at + 4 :]
    path.write_bytes(data)
    return len(lines[0]) + 10 if case == "header_only" else 4 << 10


@pytest.mark.parametrize(
    "case",
    ["first", "last", "header_only", "quoted", "unbalanced", "blank_tail", "gb18030", "latin1"],
)
def test_pieces_equal_the_whole_table_way(tmp_path, monkeypatch, case):
    """A bad value in the first piece, in the last; a first piece that is the header
    alone; quotes in the file's start (the pieces read quoted, as the whole file); a
    quoted cell over two lines (the whole file is then read line by line: so is every
    piece); pieces of blank lines at the end. Each equals the whole-table way."""
    src = tmp_path / "tracks.csv"
    monkeypatch.setattr(reader, "STREAM_BYTES", _damaged_track_file(src, case))
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", 200)
    monkeypatch.setattr(sys.modules["wakeline.core.io.sniff"], "SAMPLE_BYTES", 4096)
    sizes = _spy_reads(monkeypatch)
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=200)
    assert got.streamed and got.read_report["pieces"] >= 5
    assert max(sizes) < src.stat().st_size / 3
    if case == "header_only":
        assert sizes[0] < len(src.read_text().splitlines()[0]) + 2  # the header alone
    _same_as_in_memory(tmp_path, src, got, 200)
    monkeypatch.undo()
    assert got.read_report["quarantine_reasons"].get("unparsable lon") == 1
    if case == "gb18030":
        assert got.read_report["encoding"] == "gb18030" and not len(got.quarantine) > 1
    if case == "latin1":
        assert got.read_report["encoding"] == "utf-8" and len(got.quarantine) == 1
        assert got.read_report["encoding_fallback"]["cp1252"]["lines"] == 1
        assert any("read as Windows-1252" in w for w in got.read_report["warnings"])
    if case == "quoted":
        assert got.read_report["quarantine_reasons"] == {"unparsable lon": 1}
    if case == "unbalanced":
        assert any(w.startswith("quotes do not balance") for w in got.read_report["warnings"])
    if case == "blank_tail":
        assert got.read_report["blank_lines"] == 5000


def test_a_repeated_hour_read_in_pieces_falls_back_to_the_whole_file(tmp_path, monkeypatch):
    """Local times through a clock change, and a bad value first: the streamed reader
    gives up, the pieces meet the repeated hour (placed by each track's order over the
    whole file), and the file is read whole, with the same outputs."""
    src = tmp_path / "tracks.csv"
    monkeypatch.setattr(reader, "STREAM_BYTES", _damaged_track_file(src, "clock_change"))
    sizes = _spy_reads(monkeypatch)
    got = clean_file(
        src, tmp_path / "b.csv", tmp_path / "b_rej.csv", tz="Europe/Oslo", block_rows=200
    )
    assert not got.streamed
    assert any("hour the clock change" in w for w in got.read_report["warnings"])
    assert len(sizes) > 2 and sizes[-1] == src.stat().st_size > 3 * max(sizes[:-1])
    monkeypatch.undo()
    _same_as_in_memory(tmp_path, src, got, 200, tz="Europe/Oslo")


@pytest.mark.parametrize("block_rows", [150, 10**6])
def test_a_late_course_as_read_is_in_every_block(tmp_path, monkeypatch, block_rows):
    """h155: the canonical CSV carries the courses the import changed (course_read); a
    streamed clean whose only changed courses (380.4, 360.0) come in later pieces wrote
    blocks without the column under a header with it (a row one cell short)."""
    src = tmp_path / "scattered.csv"
    scattered_file(src, damaged=False)
    lines = src.read_text().splitlines()
    for k, value in ((len(lines) - 30, "380.4"), (len(lines) - 300, "360.0")):
        cells = lines[k].split(",")
        cells[6] = value
        lines[k] = ",".join(cells)
    src.write_text("\n".join(lines) + "\n")
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", block_rows)
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)  # a dozen pieces
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=block_rows)
    assert got.streamed
    want = clean(read_points(src).points)
    write_points(want.points, tmp_path / "a.csv")
    write_csv(want.rejected, tmp_path / "a_rej.csv")
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert "course_read" in (tmp_path / "b.csv").read_text().splitlines()[0]


@pytest.mark.parametrize("block_rows", [120, 10**6])
def test_streamed_clean_writes_tracks_in_natural_order(tmp_path, monkeypatch, block_rows):
    """D19: `wakeline clean` lists tracks in natural order (9, 9#2, 10, 100, not 10, 100,
    9) however the file is read: streamed in pieces and blocks cut in the steps' text
    order, the blocks are written again in natural order (with a track clean split at an
    impossible jump, `9#2`), byte for byte as the whole table is written."""
    rng = np.random.default_rng(5)
    rows = []
    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    for k, batch in enumerate(["100", "9", "10", "1000", "22", "x7"]):
        n = 90
        lon = 10.0 + 0.01 * k + 0.0001 * np.arange(n) + rng.normal(0, 1e-6, n)
        lat = 59.0 + 0.0001 * np.arange(n)
        if batch == "9":
            lat[45:] += 0.9  # 100 km in 10 s: clean splits the track (9#2)
        for i in range(n):
            rows.append(("R1", batch, t0 + pd.Timedelta(seconds=10 * i), lon[i], lat[i]))
    df = pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"])
    src = tmp_path / "ids.csv"
    write_points(df.sort_values("time", kind="stable"), src)  # tracks interleaved by time
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", block_rows)
    in_memory(src, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    got = clean_file(src, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=block_rows)
    assert got.streamed
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    batches = pd.read_csv(tmp_path / "b.csv", dtype=str)["batch"]
    assert batches[batches != batches.shift()].tolist() == [
        "9",
        "9#2",
        "10",
        "22",
        "100",
        "1000",
        "x7",
    ]
    assert main(["clean", str(src), "-o", str(tmp_path / "c.csv")]) == 0
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()

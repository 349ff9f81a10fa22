"""The streamed clean (core/clean_stream.py) equals reading the file whole and cleaning it
in memory: points, reject trail, report and quarantine, on files whose tracks are
scattered through the file, cut into several pieces and blocks."""

import json
import sys

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
    read = read_points(path)
    result = clean(read.points, params)
    write_points(result.points, out)
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
    """Cleaning a cleaned file again keeps its wl_id (as the in-memory clean does)."""
    src = tmp_path / "scattered.csv"
    scattered_file(src, seed=1, damaged=False)
    first = tmp_path / "first.csv"
    clean_file(src, first, params=CleanParams().with_settings(["turn.enabled=false"]))
    monkeypatch.setattr("wakeline.core.clean.BLOCK_ROWS", 250)
    want_report, _ = in_memory(first, tmp_path / "a.csv", tmp_path / "a_rej.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 8 << 10)
    got = clean_file(first, tmp_path / "b.csv", tmp_path / "b_rej.csv", block_rows=250)
    assert got.streamed
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    assert (tmp_path / "b_rej.csv").read_bytes() == (tmp_path / "a_rej.csv").read_bytes()
    assert as_json(got.report) == as_json(want_report)


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
    assert report["params"]["clean"]["speed"]["v_max_kn"] == 30.0


def test_clean_file_falls_back_for_transforms_and_quotes(tmp_path):
    src = tmp_path / "scattered.csv"
    scattered_file(src, seed=3, damaged=False)
    params = CleanParams().with_settings(["smooth.enabled=true"])
    got = clean_file(src, tmp_path / "b.csv", params=params)
    assert not got.streamed
    read = read_points(src)
    want = clean(read.points, params)
    pd.testing.assert_frame_equal(
        read_points(tmp_path / "b.csv").points.drop(columns="wl_id"),
        read_points_of(want.points, tmp_path).drop(columns="wl_id"),
    )


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

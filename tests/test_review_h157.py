"""Reviewer h157's findings on session 26's core changes: each was a failing test (xfail
with its reason) until its defect was fixed."""

import pandas as pd
import pytest

from wakeline.core.io.reader import read_points


def test_a_portuguese_latin1_line_in_a_utf8_file_reads_as_windows_1252(tmp_path):
    p = tmp_path / "pt.csv"
    rows = [f"2024-01-01 01:{k:02d}:00,9,37.{k:02d},23.60,São Bento Ø" for k in range(40)]
    body = ("time,id,lat,lon,name\n" + "\n".join(rows) + "\n").encode("utf-8")
    body += "2024-01-01 00:03:00,2,37.30,23.60,NAVEGAÇÃO\n".encode("cp1252")
    body += "2024-01-01 00:04:00,3,37.40,23.60,Associação\n".encode("cp1252")
    p.write_bytes(body)
    names = read_points(p).points.drop_duplicates("batch").set_index("batch")["name"]
    assert names["2"] == "NAVEGAÇÃO" and names["3"] == "Associação"


def test_gbk_traditional_characters_in_a_gb18030_file_stay_chinese(tmp_path):
    p = tmp_path / "gb.csv"
    names = ["远洋一号", "海丰号", "中远之星", "職位"]
    lines = ["time,id,lat,lon,name"]
    for k in range(40):
        lines.append(f"2024-01-01 00:{k:02d}:00,{k % 4},37.{k:02d},23.60,{names[k % 4]}")
    p.write_bytes(("\n".join(lines) + "\n").encode("gb18030"))
    got = read_points(p).points.drop_duplicates("batch").set_index("batch")["name"]
    assert got["3"] == "職位"


def test_an_archive_written_vessel_by_vessel_is_read_in_pieces(tmp_path, monkeypatch):
    import numpy as np

    import wakeline.core.io.reader as reader
    from wakeline.core.io.pieces import read_in_pieces
    from wakeline.core.io.sniff import sniff

    rng = np.random.default_rng(1)
    t0 = pd.Timestamp("2024-01-01")
    lines = ["mmsi,time,lat,lon"]
    for v in range(300):
        start = t0 + pd.Timedelta(
            days=int(rng.integers(0, 30)), seconds=int(rng.integers(0, 80000))
        )
        for k in range(40):
            t = start + pd.Timedelta(seconds=10 * k)
            lines.append(f"{200000000 + v},{t},{37 + v * 0.01 + k * 1e-4:.5f},23.6")
        if v == 7:  # AIS on again at a berth three days later: one more fix
            lines.append(f"{200000000 + v},{start + pd.Timedelta(days=3)},{37 + v * 0.01:.5f},23.6")
    src = tmp_path / "grouped.csv"
    src.write_text("\n".join(lines) + "\n")
    whole = read_points(src)
    assert len(whole.points) == 12_001 and len(whole.quarantine) == 0
    monkeypatch.setattr(reader, "STREAM_BYTES", 64_000)
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
    read_in_pieces(sniff(src), read, lambda p: None, tmp_path / "scratch")  # no WholeFileNeeded


def test_one_repeated_time_does_not_cost_a_series_its_detection(tmp_path):
    from wakeline.core.bearing import detect_with_report, read_bearings
    from wakeline.core.bearing_eval import simulate_table

    df = simulate_table(seed=0)
    df = df[df["batch"] == "s2-m"][["batch", "time", "bearing", "obs_lon", "obs_lat"]]
    row = df.iloc[[len(df) // 3]].copy()
    row["bearing"] = (row["bearing"] + 0.7) % 360
    p = tmp_path / "b.csv"
    pd.concat([df, row]).sort_values("time", kind="stable").to_csv(p, index=False)
    table, _ = detect_with_report(read_bearings(p))
    assert len(table) == 1  # the clean series' one detection


def test_a_late_fix_lone_by_its_track_rows_in_a_later_piece_is_read_whole(tmp_path, monkeypatch):
    """The carried row is judged when its track comes back in a later piece: vessel 7's
    fix three days late, then vessel 7's run going on after other vessels, is lone in the
    whole file, so the pieces leave it to the whole read, and the import quarantines it
    as the whole read does."""
    import numpy as np

    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, write_points
    from wakeline.core.io.pieces import read_in_pieces
    from wakeline.core.io.sniff import sniff

    t0 = pd.Timestamp("2024-01-01")
    rng = np.random.default_rng(2)
    lines = ["mmsi,time,lat,lon"]

    def run(v: int, start: pd.Timestamp, k0: int) -> None:
        for k in range(k0, k0 + 40):
            t = start + pd.Timedelta(seconds=10 * k)
            lines.append(f"{200000000 + v},{t},{37 + v * 0.01 + k * 1e-4:.5f},23.6")

    starts = [t0 + pd.Timedelta(days=int(rng.integers(0, 30))) for _ in range(60)]
    for v in range(60):
        run(v, starts[v], 0)
        if v == 7:
            lines.append(f"{200000000 + v},{starts[v] + pd.Timedelta(days=3)},37.07,23.6")
    run(7, starts[7], 40)  # vessel 7 again, right after its first run
    src = tmp_path / "late.csv"
    src.write_text("\n".join(lines) + "\n")
    whole = read_points(src)
    assert len(whole.quarantine) == 1 and "days away" in whole.quarantine["reason"].iloc[0]
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 20_000)
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
    with pytest.raises(reader.WholeFileNeeded):
        read_in_pieces(sniff(src), read, lambda p: None, tmp_path / "scratch")
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report["rows_quarantined"] == 1
    assert (tmp_path / "out.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()

"""Operator test 5's import notes: a time column mixing zoned and zone-less times
(D-import-10), zone-less times in a file from a Chinese system (D-import-8), positions
rounded to 2 decimals or fewer (D-import-7). Each said once, whole, streamed or in
pieces, with the counts and what to do."""

import re

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.io import import_to_csv, read_points, reader
from wakeline.core.io.grid import GRID_MARK, grid_decimals


def _ship(n: int, naive_every: int = 0, decimals: int = 4) -> str:
    rows = ["mmsi,time,lat,lon"]
    for i in range(n):
        t = pd.Timestamp("2023-03-01T00:00:00Z") + pd.Timedelta(seconds=10 * i)
        if naive_every and i % naive_every == 0:
            stamp = (t + pd.Timedelta(hours=8)).strftime("%Y-%m-%d %H:%M:%S")  # Beijing clock
        else:
            stamp = t.strftime("%Y-%m-%dT%H:%M:%SZ")
        lat, lon = 57.6 + i * 4e-4, 11.7 + i * 3e-4
        rows.append(f"220614000,{stamp},{lat:.{decimals}f},{lon:.{decimals}f}")
    return "\n".join(rows) + "\n"


def _read(path, how, tmp_path, monkeypatch):
    if how == "whole":
        return read_points(path)
    monkeypatch.setattr(reader, "STREAM_BYTES", 2000)
    return import_to_csv(path, tmp_path / f"out_{how}.csv")


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_zoned_and_zone_less_times_mixed_are_counted_and_the_tz_hint_given(
    write, tmp_path, monkeypatch, how
):
    r = _read(write("mixed.csv", _ship(300, naive_every=2)), how, tmp_path, monkeypatch)
    said = [w for w in r.report["warnings"] if "carry no zone" in w]
    assert said == [
        "150 of 300 times in 'time' carry no zone and 150 do: those without were read as UTC; "
        "if they are local times, give their zone with --tz (e.g. --tz Asia/Shanghai; times "
        "with a zone keep it)"
    ]
    assert r.report["zoneless_times"] == 150 and r.report["zoned_times"] == 150


def test_no_zone_note_for_one_kind_of_times_or_with_tz(write):
    for text in (_ship(100), _ship(100, naive_every=1)):
        r = read_points(write("one.csv", text))
        assert not [w for w in r.report["warnings"] if "zone" in w]
    r = read_points(write("mixed.csv", _ship(100, naive_every=2)), tz="Asia/Shanghai")
    assert not [w for w in r.report["warnings"] if "carry no zone" in w]
    # with --tz the Beijing clock times are the same instants as the zoned ones
    assert r.points["time"].diff().dropna().dt.total_seconds().eq(10).all()


@pytest.mark.parametrize("encoding", ["gb18030", "utf-8"])
def test_zone_less_times_from_a_chinese_system_get_one_note(write, encoding):
    text = _ship(60, naive_every=1).replace("mmsi,time,lat,lon", "批号,时间,纬度,经度")
    r = read_points(write("cn.csv", text, encoding=encoding))
    said = [w for w in r.report["warnings"] if "carry no zone" in w]
    assert said == [
        "the times in '时间' carry no zone: read as UTC (this file looks written on a Chinese "
        "system: if they are local times, --tz Asia/Shanghai)"
    ]
    r = read_points(write("cn.csv", text, encoding=encoding), tz="Asia/Shanghai")
    assert not [w for w in r.report["warnings"] if "zone" in w]
    # an English file of zone-less times: no note (most exports write UTC so)
    r = read_points(write("en.csv", _ship(60, naive_every=1)))
    assert not [w for w in r.report["warnings"] if "zone" in w]


@pytest.mark.parametrize("how", ["whole", "streamed"])
@pytest.mark.parametrize("decimals, said", [(2, True), (1, True), (3, False), (5, False)])
def test_positions_on_a_coarse_grid_are_named_with_the_step(
    write, tmp_path, monkeypatch, how, decimals, said
):
    r = _read(write("grid.csv", _ship(400, decimals=decimals)), how, tmp_path, monkeypatch)
    grid = [w for w in r.report["warnings"] if w.startswith(GRID_MARK)]
    if not said:
        assert grid == []
        return
    assert len(grid) == 1
    metres = {2: "1,112 m north–south", 1: "11,119 m north–south"}[decimals]
    assert f"at most {decimals} decimal" in grid[0] and metres in grid[0]
    assert "stationary rule" in grid[0]


@settings(max_examples=60, deadline=None)
@given(
    decimals=st.integers(0, 6),
    lat=st.floats(-80, 80),
    lon=st.floats(-179, 179),
    n=st.integers(50, 400),
    step=st.floats(1e-5, 0.05),
)
def test_grid_decimals_finds_the_rounding(decimals, lat, lon, n, step):
    """Property: positions rounded to k decimals are judged on a grid of k decimals (or
    fewer) when k <= 2 and they take three values or more; finer ones never."""
    i = np.arange(n)
    la = np.round(lat + i * step, decimals)
    lo = np.round(lon + i * step * 0.7, decimals)
    got = grid_decimals(lo, la)
    spread = len(np.unique(la)) >= 3 or len(np.unique(lo)) >= 3
    if decimals <= 2 and spread:
        assert got is not None and got <= decimals
    if decimals > 2 and got is not None:
        # a finer rounding judged coarse only when its values happen to lie on the grid
        assert np.allclose(la * 10**got, np.round(la * 10**got), atol=1e-6)


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_zoned_then_zone_less_pieces_are_counted_over_the_file(write, tmp_path, monkeypatch, how):
    """The first half of the file zoned, the second zone-less: a streamed read sees each
    piece with one kind only; the counts are the file's."""
    lines = _ship(300).splitlines()
    naive = [re.sub(r"T([\d:]+)Z", r" \1", x) for x in lines[151:]]
    path = write("halves.csv", "\n".join(lines[:151] + naive) + "\n")
    r = _read(path, how, tmp_path, monkeypatch)
    said = [w for w in r.report["warnings"] if "carry no zone" in w]
    assert len(said) == 1 and said[0].startswith("150 of 300 times in 'time' carry no zone")


def test_pieces_say_the_mixed_zones_once_not_the_chinese_note_too(tmp_path, monkeypatch):
    """A quoted GB18030 file (read in pieces) zoned in its first half and zone-less in its
    second: the whole-file reader says only the zones-mixed warning; the pieces said the
    Chinese system's note too (a zone-less piece's), h192."""
    lines = ["批号,时间,经度,纬度"]
    for b in range(4):
        for k in range(300):
            s = b * 300 + k
            zone = "+08:00" if b < 2 else ""
            stamp = f"2024-01-01T{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}{zone}"
            lines.append(f'"{b}",{stamp},{120 + b * 0.01 + k * 1e-4:.6f},{30 + k * 1e-4:.6f}')
    src = tmp_path / "zones_gb.csv"
    src.write_bytes(("\n".join(lines) + "\n").encode("gb18030"))
    whole = [w for w in read_points(src).report["warnings"] if "zone" in w]
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert got.report.get("pieces", 0) > 2
    assert [w for w in got.report["warnings"] if "zone" in w] == whole
    assert len(whole) == 1 and "600 of 1,200 times" in whole[0]


def _offset_file(path, offsets, quoted=False, encoding="utf-8"):
    """One ship's times written each with the next of ``offsets`` in turn (a "" zone-less):
    the instants 10 s apart whatever the offset."""
    rows = ["mmsi,time,lat,lon"]
    for i in range(400):
        t = pd.Timestamp("2024-01-01T00:00:00Z") + pd.Timedelta(seconds=10 * i)
        off = offsets[i % len(offsets)]
        if off and off != "Z":
            sign = -1 if off[0] == "-" else 1
            hours, minutes = int(off[1:3]), int(off[-2:])
            wall = t + sign * pd.Timedelta(hours=hours, minutes=minutes)
        else:
            wall = t
        stamp = wall.strftime("%Y-%m-%dT%H:%M:%S") + off
        mmsi = '"366970770"' if quoted else "366970770"
        rows.append(f"{mmsi},{stamp},{30 + i * 1e-4:.5f},{-90 + i * 1e-4:.5f}")
    path.write_bytes(("\n".join(rows) + "\n").encode(encoding))
    return path


@pytest.mark.parametrize("how", ["whole", "streamed", "pieces"])
@pytest.mark.parametrize(
    "offsets, zone",
    [
        (["-05:00"], "-05:00"),
        (["+0800"], "+08:00"),
        (["Z"], "+00:00"),
        (["Z", "+08:00"], "mixed"),
        (["-05:00", "-04:00"], "mixed"),
        (["-05:00", ""], "mixed"),
        ([""], None),
    ],
)
def test_the_report_names_the_offset_the_times_were_written_with(
    tmp_path, monkeypatch, how, offsets, zone
):
    """Operator test 10: a file whose every time ends in -05:00 reported time_zone "UTC"
    (only --tz), so View ▸ Time zone ▸ "the zone the data came in" showed UTC. The report
    now counts the offsets written (``time_offsets``) and names the one of them, or
    "mixed"; ``time_zone`` (the import's --tz) and the instants are unchanged."""
    path = _offset_file(tmp_path / "ship.csv", offsets, quoted=how == "pieces")
    if how == "whole":
        got = read_points(path)
    else:
        monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
        got = import_to_csv(path, tmp_path / "out.csv")
        assert bool(got.report.get("pieces")) == (how == "pieces")
    report = got.report
    assert report["time_zone"] == "UTC"
    assert report.get("time_zone_written") == zone
    written = report.get("time_offsets", {})
    zoned = sum(1 for i in range(400) if offsets[i % len(offsets)])
    assert sum(written.values()) == zoned
    if zone not in (None, "mixed"):
        assert written == {zone: 400}
    if how == "whole":  # the instants: 10 s apart from 2024-01-01 00:00 UTC, any offset
        t = got.points["time"].sort_values().reset_index(drop=True)
        assert t.iloc[0] == pd.Timestamp("2024-01-01T00:00:00Z")
        assert (t.diff().dropna() == pd.Timedelta(seconds=10)).all()


def test_written_offsets_reads_each_form():
    import pyarrow as pa

    texts = pa.array(
        [
            "2024-01-01T00:00:00-05:00",
            "2024-01-01 00:00:00.250+0530",
            "2024-01-01T00:00:00 +01:00",
            "2024-01-01T00:00:00Z",
            "2024-01-01 00:00:00 UTC",
            "2024-01-01T00:00:00",
            "2024-01-01",  # a date's "-01" is no offset
            "",
        ]
    )
    got = reader.written_offsets(texts)
    assert got == {"-05:00": 1, "+05:30": 1, "+01:00": 1, "+00:00": 2}
    assert reader.written_zone({"-05:00": 3}) == "-05:00"
    assert reader.written_zone({"-05:00": 3}, zoneless=1) == "mixed"
    assert reader.written_zone({}) is None

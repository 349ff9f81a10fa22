"""Import of layouts the importer could not read before h124: columns aligned with runs
of blanks (pandas' to_string, MATLAB, radar logs), ``|`` as the delimiter, decimal
degrees with a hemisphere letter (``37.05N``), and NMEA's degrees and minutes run
together (``3754.0300,N,02336.0600,E``). Each read whole, streamed and in pieces."""

import re

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.io import read_points, sniff, write_points
from wakeline.core.io.sniff import blank_cells, blank_layout


def _frame(n: int = 30, south_west: bool = False) -> pd.DataFrame:
    sign = -1.0 if south_west else 1.0
    return pd.DataFrame(
        {
            "time": pd.date_range("2024-01-01", periods=n, freq="s").strftime("%Y-%m-%d %H:%M:%S"),
            "track": [1, 2] * (n // 2),
            "lat": [sign * (37.9 + i * 1e-4) for i in range(n)],
            "lon": [sign * (23.6 + i * 1e-4) for i in range(n)],
        }
    )


def _three_ways(src, tmp_path, monkeypatch, size: int = 300):
    """The file read whole, imported streamed (pieces of ``size`` bytes) and read in
    pieces: the canonical bytes and quarantines must agree; returns the whole read."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv
    from wakeline.core.io.pieces import read_in_pieces

    whole = read_points(src)
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    streamed = import_to_csv(src, tmp_path / "streamed.csv")
    assert (tmp_path / "streamed.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    pd.testing.assert_frame_equal(streamed.quarantine, whole.quarantine)
    got = []
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
    pieces = read_in_pieces(sniff(src), read, got.append, tmp_path / "scratch")
    assert pieces.report["pieces"] > 2
    joined = pd.concat(got, ignore_index=True) if got else whole.points.iloc[:0]
    write_points(joined, tmp_path / "pieces.csv")
    assert (tmp_path / "pieces.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    pd.testing.assert_frame_equal(pieces.quarantine, whole.quarantine)
    for key in ("rows_read", "rows_imported", "rows_quarantined", "blank_lines", "tracks"):
        assert streamed.report[key] == pieces.report[key] == whole.report[key], key
    for key in ("ddmm", "dms", "hemisphere_degrees"):
        assert streamed.report.get(key) == pieces.report.get(key) == whole.report.get(key), key
    assert set(streamed.report["warnings"]) == set(whole.report["warnings"])
    assert set(pieces.report["warnings"]) == set(whole.report["warnings"])
    return whole


def _lines_accounted(r, src, header: int = 1) -> None:
    """Every line is a point, a quarantined row, a blank line or the header."""
    rep = r.report
    assert rep["rows_read"] == rep["rows_imported"] + rep["rows_quarantined"]
    lines = src.read_bytes().decode().replace("\r\n", "\n").rstrip("\n").split("\n")
    assert rep["rows_read"] + rep["blank_lines"] + header == len(lines)


def _expected(df: pd.DataFrame, r) -> None:
    assert len(r.quarantine) == 0, r.quarantine.to_dict("records")
    assert r.points["lat"].round(9).tolist() == df["lat"].round(9).tolist()
    assert r.points["lon"].round(9).tolist() == df["lon"].round(9).tolist()
    assert r.points["batch"].tolist() == df["track"].astype(str).tolist()
    assert r.points["time"].tolist() == pd.to_datetime(df["time"], utc=True).tolist()


# --- 1. columns aligned with runs of blanks -------------------------------------------------


def _aligned(df: pd.DataFrame, kind: str) -> str:
    rows = zip(df.track, df.time, df.lat, df.lon, strict=True)
    if kind == "to_string":  # pandas' index: a first column without a name
        return df.to_string() + "\n"
    if kind == "to_string_no_index":  # names right-aligned, a date and clock apart
        return df.to_string(index=False) + "\n"
    if kind == "iso":  # the checker's spaces.csv
        return "time        id   lat        lon\n" + "".join(
            f"{t.replace(' ', 'T')}    {k}  {la:.6f}  {lo:.6f}\n" for k, t, la, lo in rows
        )
    if kind == "name_with_a_space":  # "Track No": names apart by two blanks or more
        return "Track No   Time                  Lat         Lon\n" + "".join(
            f"{k:>8}   {t}   {la:.6f}  {lo:.6f}\n" for k, t, la, lo in rows
        )
    if kind == "tabs_crlf_edges":  # tabs among the blanks, blanks at line ends, CRLF
        return "time    id   lat  lon\r\n" + "".join(
            f"  {t}\t {k}   {la:.6f}\t{lo:.6f}  \r\n" for k, t, la, lo in rows
        )
    raise ValueError(kind)


@pytest.mark.parametrize(
    "kind", ["to_string", "to_string_no_index", "iso", "name_with_a_space", "tabs_crlf_edges"]
)
def test_columns_aligned_with_blanks_are_read(kind, tmp_path, monkeypatch):
    # before h124: every row quarantined "short row: 9 of 20 fields"
    df = _frame()
    src = tmp_path / f"{kind}.txt"
    src.write_bytes(_aligned(df, kind).encode())
    sn = sniff(src)
    assert sn.delimiter == " " and sn.blank_runs
    assert sn.join_date_clock == (kind != "iso")
    r = _three_ways(src, tmp_path, monkeypatch)
    _expected(df, r)
    _lines_accounted(r, src)
    assert r.report["delimiter"] == " "
    note = [w for w in r.report["warnings"] if "aligned with blanks" in w]
    assert len(note) == 1 and ("date and the clock" in note[0]) == sn.join_date_clock


def test_checkers_space_aligned_probe(tmp_path):
    text = "time        id   lat        lon\n2024-01-01T00:00:00    1  37.900000  23.600000\n"
    text += "2024-01-01T00:00:01    2  37.900500  23.601000\n"
    src = tmp_path / "spaces.csv"
    src.write_text(text)
    r = read_points(src)
    assert len(r.points) == 2 and r.report["columns"]["batch"] == "id"


def test_refused_and_blank_lines_of_an_aligned_file_are_said_as_written(tmp_path, monkeypatch):
    df = _frame()
    lines = _aligned(df, "iso").splitlines()
    lines[4] = "  ".join(lines[4].split()[:3])  # a short row
    lines[9] = lines[9] + "   extra"  # one cell too many
    lines.insert(12, "    ")  # a line of blanks
    src = tmp_path / "bad.txt"
    src.write_text("\n".join(lines) + "\n")
    r = _three_ways(src, tmp_path, monkeypatch)
    assert r.quarantine["line"].tolist() == [5, 10]
    assert r.quarantine["reason"].tolist() == [
        "short row: 3 of 4 fields",
        "too many fields: 5 of 4",
    ]
    assert r.quarantine["text"].tolist() == [lines[4], lines[9]]  # as in the file, blanks and all
    assert r.report["blank_lines"] == 1
    _lines_accounted(r, src)


def test_quoted_cells_keep_their_blanks(tmp_path, monkeypatch):
    df = _frame()
    src = tmp_path / "q.txt"
    src.write_text(
        "time  name  lat  lon\n"
        + "".join(
            f'{t.replace(" ", "T")}  "Ship  {k}"  {la:.6f}  {lo:.6f}\n'
            for k, t, la, lo in zip(df.track, df.time, df.lat, df.lon, strict=True)
        )
    )
    r = _three_ways(src, tmp_path, monkeypatch)
    assert r.points["name"].tolist() == [f"Ship  {k}" for k in df.track]
    assert len(r.points) == 30


def test_single_spaces_with_empty_cells_and_spaces_inside_other_delimiters_stay(write):
    # a file of single spaces whose rows have empty cells keeps them (no runs merged)
    src = write(
        "single.txt",
        "time id lat lon speed\n"
        + "".join(f"2024-01-01T00:00:0{i} 1 37.{i} 23.{i} \n" for i in range(5)),
    )
    sn = sniff(src)
    assert not sn.blank_runs and sn.columns == ("time", "id", "lat", "lon", "speed")
    assert len(read_points(src).points) == 5
    # tab and comma files with a space inside their date-times are never split there
    for delim in ("\t", ",", ";", "|"):
        body = delim.join(["time", "id", "lat", "lon"]) + "\n"
        body += "".join(
            delim.join([f"2024-01-01 00:00:0{i}", "1", "37.5", "23.5"]) + "\n" for i in range(5)
        )
        sn = sniff(write("d.txt", body))
        assert sn.delimiter == delim and not sn.blank_runs
        r = read_points(write("d.txt", body))
        assert len(r.points) == 5 and len(r.quarantine) == 0


def test_blank_layout_rules():
    # a date and clock apart: joined only when the header then fits the rows
    assert blank_layout(["t  id  lat  lon", "2024-01-01 00:00:00  1  5.0  6.0"] * 2)[:2] == (
        True,
        True,
    )
    assert blank_layout(["date  clock  lat  lon", "2024-01-01 00:00:00  5.0  6.0"] * 2)[:2] == (
        True,
        False,
    )
    assert blank_cells("  a  b\t c  ") == ["a", "b", "c"]
    assert blank_cells('1  "x  y"  2', quotes=True) == ["1", '"x  y"', "2"]
    assert blank_cells("13/09/2020 12:00:00 PM  7", join=True) == ["13/09/2020 12:00:00 PM", "7"]


_NAMES = ("time", "track", "lat", "lon")


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    widths=st.lists(st.integers(1, 6), min_size=4, max_size=4),
    lead=st.integers(0, 3),
    space_in_time=st.booleans(),
    right=st.booleans(),
    values=st.lists(
        st.tuples(
            st.integers(0, 86_399),
            st.integers(1, 999),
            st.floats(-89.9, 89.9, allow_nan=False),
            st.floats(-179.9, 179.9, allow_nan=False),
        ),
        min_size=2,
        max_size=12,
    ),
)
def test_any_blank_aligned_table_reads_back(tmp_path, widths, lead, space_in_time, right, values):
    """Whatever the gaps (one blank or more), the alignment (left or right) and the
    blanks before a line, a blank-aligned table reads back to its values."""
    sep = "T" if not space_in_time else " "
    rows = [
        (
            (pd.Timestamp("2024-05-01") + pd.Timedelta(seconds=s)).strftime(
                f"%Y-%m-%d{sep}%H:%M:%S"
            ),
            str(k),
            f"{la:.6f}",
            f"{lo:.6f}",
        )
        for s, k, la, lo in values
    ]
    cols = list(zip(_NAMES, *rows, strict=True))
    size = [max(len(c) for c in col) for col in cols]

    def line(cells) -> str:
        out = [c.rjust(w) if right else c.ljust(w) for c, w in zip(cells, size, strict=True)]
        return " " * lead + "".join(c + " " * g for c, g in zip(out, widths, strict=True))

    src = tmp_path / "any.txt"
    src.write_text("\n".join(line(c) for c in [_NAMES, *rows]) + "\n")
    r = read_points(src)
    assert len(r.quarantine) == 0, (r.quarantine.to_dict("records"), src.read_text())
    got = r.points.sort_values(["time", "batch"], kind="stable")
    want = pd.DataFrame(rows, columns=_NAMES)
    want["time"] = pd.to_datetime(want["time"], utc=True)
    want = want.sort_values(["time", "track"], kind="stable")
    assert sorted(got["batch"]) == sorted(want["track"])
    assert np.allclose(np.sort(got["lat"]), np.sort(want["lat"].astype(float)))
    assert np.allclose(np.sort(got["lon"]), np.sort(want["lon"].astype(float)))


# --- 2. the | delimiter ----------------------------------------------------------------------


def test_pipe_delimiter_is_sniffed(tmp_path, monkeypatch, write):
    # before h124: "missing required column ... headers found: time|id|lat|lon"
    df = _frame()
    src = tmp_path / "pipe.csv"
    src.write_text(
        "time|id|lat|lon\n"
        + "".join(
            f"{t}|{k}|{la:.6f}|{lo:.6f}\n"
            for k, t, la, lo in zip(df.track, df.time, df.lat, df.lon, strict=True)
        )
    )
    assert sniff(src).delimiter == "|"
    r = _three_ways(src, tmp_path, monkeypatch)
    _expected(df, r)
    assert r.report["delimiter"] == "|"
    # a comma file with a | in a cell stays a comma file; "pipe" names it on a command line
    body = "time,id,lat,lon,note\n" + "".join(
        f"2024-01-01 00:00:0{i},1,37.5,23.5,a|b\n" for i in range(4)
    )
    assert sniff(write("c.csv", body)).delimiter == ","
    assert sniff(src, delimiter="pipe").delimiter == "|"


# --- 3. decimal degrees with a hemisphere letter -------------------------------------------


@pytest.mark.parametrize(
    ("lat", "lon", "want"),
    [
        ("37.05N", "23.05W", (37.05, -23.05)),
        ("N37.05", "W23.05", (37.05, -23.05)),
        ("N 37.05", "W 23.05", (37.05, -23.05)),
        ("37.05 S", "23.05 E", (-37.05, 23.05)),
        ("37.05s", "123.5e", (-37.05, 123.5)),
    ],
)
def test_decimal_degrees_with_a_hemisphere_letter(tmp_path, lat, lon, want):
    # before h124: "unparsable lon" for every row
    src = tmp_path / "h.csv"
    src.write_text(
        f"time,id,lat,lon\n2024-01-01 00:00:00,1,{lat},{lon}\n2024-01-01 00:00:01,1,{lat},{lon}\n"
    )
    r = read_points(src)
    assert len(r.quarantine) == 0
    assert (r.points["lat"].iloc[0], r.points["lon"].iloc[0]) == pytest.approx(want)
    assert r.report["hemisphere_degrees"] == 4 and "dms" not in r.report
    assert any(
        "4 positions were written in decimal degrees with a hemisphere" in w
        for w in r.report["warnings"]
    )


@settings(max_examples=60, deadline=None)
@given(
    value=st.floats(0, 179.999, allow_nan=False),
    decimals=st.integers(0, 6),
    letter=st.sampled_from("NSEW"),
    before=st.booleans(),
    gap=st.sampled_from(["", " "]),
)
def test_hemisphere_letter_gives_the_sign(value, decimals, letter, before, gap):
    from wakeline.core.io.reader import _with_dms

    number = f"{value:.{decimals}f}"
    text = f"{letter}{gap}{number}" if before else f"{number}{gap}{letter}"
    values, counted = np.array([np.nan]), {}
    assert _with_dms(pd.Series([text]), values, counted) == 1
    assert values[0] == pytest.approx(float(number) * (-1 if letter in "SW" else 1))
    assert counted == {"hemisphere_degrees": 1}


def test_hemisphere_positions_read_whole_streamed_and_in_pieces(tmp_path, monkeypatch):
    df = _frame(south_west=True)
    src = tmp_path / "hemi.csv"
    src.write_text(
        "time,id,lat,lon\n"
        + "".join(
            f"{t},{k},{-la:.6f}S,W {-lo:.6f}\n"
            for k, t, la, lo in zip(df.track, df.time, df.lat, df.lon, strict=True)
        )
    )
    r = _three_ways(src, tmp_path, monkeypatch)
    _expected(df, r)
    assert r.report["hemisphere_degrees"] == 60


# --- 4. NMEA's ddmm.mmmm ------------------------------------------------------------------


def _ddmm_text(deg: float, width: int) -> str:
    a = abs(deg)
    d = int(a)
    m = round((a - d) * 60, 4)
    if m >= 60:
        d, m = d + 1, 0.0
    return f"{d * 100 + m:0{width + 5}.4f}"


def _nmea(df: pd.DataFrame, letters: bool) -> str:
    head = "time,id,lat,latd,lon,lond\n" if letters else "time,id,lat,lon\n"
    out = []
    for k, t, la, lo in zip(df.track, df.time, df.lat, df.lon, strict=True):
        if letters:
            ns, ew = ("N" if la >= 0 else "S"), ("E" if lo >= 0 else "W")
            out.append(f"{t},{k},{_ddmm_text(la, 4)},{ns},{_ddmm_text(lo, 5)},{ew}\n")
        else:
            sla, slo = ("-" if la < 0 else ""), ("-" if lo < 0 else "")
            out.append(f"{t},{k},{sla}{_ddmm_text(la, 4)},{slo}{_ddmm_text(lo, 5)}\n")
    return head + "".join(out)


@pytest.mark.parametrize("letters", [True, False])
@pytest.mark.parametrize("south_west", [False, True])
def test_nmea_degrees_and_minutes_are_read(tmp_path, monkeypatch, letters, south_west):
    # before h124: every row quarantined "lon out of range"
    df = _frame(south_west=south_west)
    df["lat"], df["lon"] = df["lat"].round(6), df["lon"].round(6)
    src = tmp_path / "nmea.csv"
    src.write_text(_nmea(df, letters))
    r = _three_ways(src, tmp_path, monkeypatch)
    assert len(r.quarantine) == 0
    assert np.allclose(r.points["lat"], df["lat"], atol=2e-6)
    assert np.allclose(r.points["lon"], df["lon"], atol=2e-6)
    assert r.report["ddmm"] == 60
    said = " ".join(r.report["warnings"])
    assert "60 positions were written as NMEA writes them" in said
    assert ("'latd' and 'lond'" in said) == letters
    _lines_accounted(r, src)


def test_ddmm_with_letters_quarantines_a_damaged_value(tmp_path):
    df = _frame(n=200)
    lines = _nmea(df, True).splitlines()
    lines[7] = lines[7].replace(",3754.", ",3794.", 1)  # minutes 94
    src = tmp_path / "n.csv"
    src.write_text("\n".join(lines) + "\n")
    r = read_points(src)
    assert r.quarantine["line"].tolist() == [8]
    assert r.quarantine["reason"].tolist() == [
        "lat not in ddmm.mmmm as the rest of its column (minutes 60 or more)"
    ]
    assert len(r.points) == 199


@pytest.mark.parametrize(
    ("rows", "why"),
    [
        # plain degrees with lon 100-180: lon never decides
        (["30.5,121.5", "30.6,121.6", "30.7,122.1"], "plain"),
        # lat holds the longitudes, lon the latitudes (swapped): stays swapped, said so
        (["121.5,30.5", "121.6,30.6", "122.1,30.7"], "swapped"),
        # some lat within 90 and no hemisphere column: not all ddmm, none read so
        (["3754.0,2336.0", "37.9,23.6", "3754.1,2336.1"], "mixed"),
    ],
)
def test_ddmm_does_not_steal_a_file_in_degrees(tmp_path, rows, why):
    src = tmp_path / "d.csv"
    src.write_text(
        "time,id,lat,lon\n"
        + "".join(f"2024-01-01 00:00:0{i},1,{row}\n" for i, row in enumerate(rows))
    )
    r = read_points(src)
    assert "ddmm" not in r.report
    if why == "plain":
        assert len(r.points) == 3
    elif why == "swapped":
        assert len(r.points) == 0 and r.report["lat_beyond_90_lon_within"] == 3
        assert any("look swapped" in w for w in r.report["warnings"])
    else:
        assert len(r.points) == 1


def test_ddmm_pieces_that_judge_apart_are_read_as_the_whole(tmp_path, monkeypatch):
    """A file whose first rows read as ddmm (all beyond 90) and later ones do not: the
    pieces would judge apart, so the import reads it as the whole read does."""
    df = _frame(n=60)
    rows = _nmea(df, False).splitlines()
    rows[40:] = [r.split(",")[0] + f",1,37.{i},23.{i}" for i, r in enumerate(rows[40:])]
    src = tmp_path / "mixed.csv"
    src.write_text("\n".join(rows) + "\n")
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    whole = read_points(src)
    assert "ddmm" not in whole.report  # not every lat lies beyond 90
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    got = import_to_csv(src, tmp_path / "got.csv")
    assert (tmp_path / "got.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    assert got.report["rows_quarantined"] == whole.report["rows_quarantined"]


@settings(max_examples=100, deadline=None)
@given(deg=st.integers(0, 90), minutes=st.floats(0, 59.9999, allow_nan=False), neg=st.booleans())
def test_ddmm_numbers_read_back(deg, minutes, neg):
    from wakeline.core.io.reader import _ddmm

    value = deg * 100 + round(minutes, 4)
    want = deg + round(minutes, 4) / 60
    if want > 90:
        assert np.isnan(_ddmm(np.array([value]), 90.0)[0])
        return
    got = _ddmm(np.array([-value if neg else value]), 90.0)[0]
    assert got == pytest.approx(-want if neg else want, abs=1e-9)
    assert np.isnan(_ddmm(np.array([deg * 100 + 60.5]), 180.0)[0])  # minutes 60 or more


@pytest.mark.parametrize("letters", [True, False])
def test_export_like_writes_ddmm_back_in_its_own_form(tmp_path, letters):
    """export --like an NMEA-style file writes ddmm.mmmm back (zero-padded as the file
    pads; with the hemisphere letters from the signs, or a minus sign without them):
    read, exported like itself, the same bytes."""
    from wakeline.app.cli import main
    from wakeline.core.io.layout import Layout, load_layout

    df = _frame(south_west=True)
    df.loc[::3, "lat"] *= -1  # both hemispheres
    df["lat"], df["lon"] = df["lat"].round(6), df["lon"].round(6)
    src = tmp_path / "nmea.csv"
    src.write_text(_nmea(df, letters))
    out = tmp_path / "back.csv"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    assert out.read_bytes() == src.read_bytes()
    layout = load_layout(src)
    # lon's zeros show (02336.0600: 5 digits); a lat of 3754 shows none to pad to
    assert (layout.field_column("lat").ddmm, layout.field_column("lon").ddmm) == (1, 5)
    assert [c.hemisphere for c in layout.columns if c.hemisphere] == (
        ["lat", "lon"] if letters else []
    )
    assert Layout.from_dict(layout.to_dict()) == layout


def test_format_ddmm_carries_minutes_that_round_to_sixty():
    from wakeline.core.io.export_like import format_ddmm
    from wakeline.core.io.layout import NumberFormat

    got = format_ddmm(
        np.array([37.9999999, -5.5, 0.25, np.nan]), NumberFormat(4, "none"), 4, signed=True
    )
    assert got.to_pylist() == ["3800.0000", "-0530.0000", "0015.0000", ""]


def _reference_runs(data: bytes, quotes: bool) -> bytes:
    """blank_runs, line by line and character by character (slow, plain)."""
    import re

    out = []
    for line in re.split(rb"(\r\n|\r|\n)", data):
        if line in (b"\r\n", b"\r", b"\n"):
            out.append(line)
            continue
        cells, cell, inside = [], b"", False
        for ch in (bytes([c]) for c in line):
            if ch == b'"' and quotes:
                inside = not inside
            if ch in b" \t" and not inside:
                if cell:
                    cells.append(cell)
                cell = b""
                continue
            cell += ch
        if cell:
            cells.append(cell)
        out.append(b"\x1f".join(cells))
    return b"".join(out)


@settings(max_examples=300, deadline=None)
@given(
    data=st.lists(st.sampled_from([b" ", b"\t", b"a", b"7", b'"', b"\n", b"\r\n", b"\r"])).map(
        b"".join
    ),
    quotes=st.booleans(),
)
def test_blank_runs_agree_with_a_plain_line_by_line_split(data, quotes):
    """The vectorized separator (numpy over the bytes) gives what splitting each line at
    its runs of blanks (outside quotes) gives."""
    from wakeline.core.io.sniff import blank_runs

    assert blank_runs(data, quotes) == _reference_runs(data, quotes)


def test_ddmm_a_damaged_letter_costs_its_row_not_the_signs(tmp_path, monkeypatch):
    """One letter cell neither E nor W: that row is quarantined, the others keep the
    signs their letters give (the letter column is still the column of letters)."""
    df = _frame(n=600, south_west=True)
    lines = _nmea(df, True).splitlines()
    lines[250] = lines[250][:-1] + "X"  # lond
    src = tmp_path / "n.csv"
    src.write_text("\n".join(lines) + "\n")
    # pieces of 200 rows or so: the damaged letter is under 1 % of its piece's
    r = _three_ways(src, tmp_path, monkeypatch, size=10_000)
    assert r.quarantine["line"].tolist() == [251]
    assert r.quarantine["reason"].tolist() == ["lon hemisphere letter not E or W"]
    assert (r.points["lat"] < 0).all() and (r.points["lon"] < 0).all()
    assert any("'latd' and 'lond'" in w for w in r.report["warnings"])


def test_ddmm_pieces_that_take_signs_apart_are_read_as_the_whole(tmp_path, monkeypatch):
    """Small pieces where a damaged letter is more than 1 % of one: that piece finds no
    letter column and would take its signs otherwise; the import reads the file as the
    whole read does."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv

    df = _frame(n=120, south_west=True)
    lines = _nmea(df, True).splitlines()
    lines[50] = lines[50][:-1] + "X"
    src = tmp_path / "n.csv"
    src.write_text("\n".join(lines) + "\n")
    whole = read_points(src)
    assert whole.quarantine["reason"].tolist() == ["lon hemisphere letter not E or W"]
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    got = import_to_csv(src, tmp_path / "got.csv")
    assert (tmp_path / "got.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    pd.testing.assert_frame_equal(got.quarantine, whole.quarantine)


@pytest.mark.parametrize(
    ("lat_form", "lon_form"),
    [("{:.2f}{}", "{:.2f}{}"), ("{1}{0:.4f}", "{1} {0:.4f}"), ("{:.3f} {}", "{:.3f} {}")],
)
def test_export_like_writes_hemisphere_degrees_back(tmp_path, lat_form, lon_form):
    """Decimal degrees with a hemisphere letter are written back in the file's form
    (letter before or after, the gap, the decimals): the same bytes."""
    from wakeline.app.cli import main

    df = _frame(south_west=True)
    df.loc[::4, "lon"] *= -1
    lines = ["time,id,lat,lon"]
    for k, t, la, lo in zip(df.track, df.time, df.lat, df.lon, strict=True):
        lat = lat_form.format(abs(la), "S" if la < 0 else "N")
        lon = lon_form.format(abs(lo), "W" if lo < 0 else "E")
        lines.append(f"{t},{k},{lat},{lon}")
    src = tmp_path / "hemi.csv"
    src.write_text("\n".join(lines) + "\n")
    first = read_points(src)
    assert len(first.quarantine) == 0 and first.report["hemisphere_degrees"] == 60
    out = tmp_path / "back.csv"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    assert out.read_bytes() == src.read_bytes()


def test_an_unquoted_text_with_a_blank_is_read_in_fixed_columns(tmp_path):
    """pandas' to_string of a name with a space (``Ship A``): refused before h135 (every
    row quarantined "too many fields: 7 of 5"; once read as a nameless index column,
    every value under the wrong name); now read by the columns' places, each value under
    its own name."""
    df = _frame(n=6)
    df.insert(2, "name", ["Ship A", "Ship B"] * 3)
    src = tmp_path / "names.txt"
    src.write_text(df.to_string(index=False) + "\n")
    r = read_points(src)
    assert len(r.quarantine) == 0 and len(r.points) == 6
    assert r.points["name"].tolist() == df["name"].tolist()
    assert r.points["lat"].round(4).tolist() == df["lat"].round(4).tolist()
    assert not any("date and the clock" in w for w in r.report["warnings"])


def test_degrees_with_letters_and_one_damaged_value_stay_degrees(tmp_path):
    """A lat in degrees beside N/S letters with one value beyond 90 (damaged): not read
    as ddmm.mmmm (its 37.9 would be 0°37.9'); that row alone is out of range."""
    rows = [f"2024-01-01 00:00:{i:02d},1,{37.9 + i / 100:.4f},N,{23.6:.4f},E" for i in range(20)]
    rows[7] = rows[7].replace(",37.97", ",3757.0", 1)  # reads as ddmm (57 minutes)
    src = tmp_path / "deg.csv"
    src.write_text("time,id,lat,latd,lon,lond\n" + "\n".join(rows) + "\n")
    r = read_points(src)
    assert "ddmm" not in r.report
    assert r.quarantine["reason"].tolist() == ["lat out of range"]
    assert r.points["lat"].between(37.8, 38.2).all() and len(r.points) == 19


@pytest.mark.parametrize(
    "kind", ["to_string", "to_string_no_index", "iso", "name_with_a_space", "tabs_crlf_edges"]
)
def test_export_like_writes_a_blank_aligned_file_aligned(kind, tmp_path):
    """h135: export --like a file aligned with blanks wrote its cells one blank apart;
    now each column is as wide as its widest cell (header included), two blanks apart,
    numbers and times to the right: every line as long as the header, the cells of a
    column ending at one place. The file reads back to the same points."""
    from wakeline.app.cli import main

    df = _frame()
    src = tmp_path / f"{kind}.txt"
    src.write_bytes(_aligned(df, kind).encode())
    out = tmp_path / "back.txt"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    lines = out.read_bytes().decode().replace("\r\n", "\n").rstrip("\n").split("\n")
    assert len({len(line) for line in lines}) == 1, lines[:3]  # lon, a number, is last
    # the gaps between columns are blank on every line, header included
    blank = "".join(
        " " if all(line[i] == " " for line in lines) else "x" for i in range(len(lines[0]))
    )
    assert len(re.findall(r"x {2,}(?=x)", blank)) == len(read_points(src).report["columns"]) - 1 + (
        kind == "to_string"
    ), blank
    assert '"' not in out.read_text()  # a date and clock a blank apart are not quoted
    a, b = read_points(src), read_points(out)
    assert len(b.quarantine) == 0
    cols = ["sensor", "batch", "time", "lon", "lat"]
    pd.testing.assert_frame_equal(a.points[cols], b.points[cols])


# --- fixed columns (h135) ---------------------------------------------------------------------

FIXED = (
    "Track No  Time                       Lat        Lon  Note\n"
    "       1  2024-01-01 00:00:00  37.900000  23.600000  ab\n"
    "       2  2024-01-01 00:00:01             23.600100\n"
    "      12  2024-01-01 00:00:02  37.900200  23.600200  xy\n"
    "      12  2024-01-01 00:00:03  37.900300  23.600300\n"
    "\n"
    "      13  2024-01-01 00:00:04  37.900400  23.600400  cd\n"
)


def test_empty_cells_and_a_name_one_blank_from_the_next_read_in_fixed_columns(
    tmp_path, monkeypatch
):
    """A blank-aligned file with empty cells (a lat, trailing notes) and a header name of
    two words one blank apart: read by the columns' places, the same whole, streamed and
    in pieces; before, every row with an empty cell was quarantined as short."""
    src = tmp_path / "fixed.txt"
    src.write_text(FIXED)
    sn = sniff(src)
    assert sn.fixed_gutters and sn.columns == ("Track No", "Time", "Lat", "Lon", "Note")
    r = _three_ways(src, tmp_path, monkeypatch, size=90)
    assert r.quarantine[["line", "reason"]].values.tolist() == [[3, "missing lat"]]
    assert r.points["batch"].tolist() == ["1", "12", "12", "13"]
    assert r.points["Note"].tolist() == ["ab", "xy", "", "cd"]
    assert r.points["lat"].tolist() == [37.9, 37.9002, 37.9003, 37.9004]
    _lines_accounted(r, src)


@pytest.mark.parametrize("note", ["  xy", "  x y", ""])
def test_a_row_read_today_reads_the_same_in_fixed_columns(tmp_path, monkeypatch, note):
    """Fixed columns only add rows: every point the blank runs read (emulated: no fixed
    reading) is read, the same, in fixed columns; a file every judged row of which the
    runs read is not read in fixed columns at all."""
    import importlib

    sniff_module = importlib.import_module("wakeline.core.io.sniff")
    src = tmp_path / "f.txt"
    src.write_text(FIXED.replace("  xy\n", note + "\n"))
    now = read_points(src).points
    with monkeypatch.context() as m:
        m.setattr(sniff_module, "_fixed_instead", lambda *a, **k: None)
        today = read_points(src).points
    key = ["batch", "time"]
    cols = ["batch", "time", "lon", "lat"]
    both = today[cols].merge(now[cols], on=key, how="left", suffixes=("", "_now"))
    assert len(today) <= len(now)
    assert (both["lat"] == both["lat_now"]).all() and (both["lon"] == both["lon_now"]).all()
    df = _frame()
    src.write_text(_aligned(df, "name_with_a_space"))
    assert sniff(src).fixed_gutters == ()


def test_an_aligned_file_with_empty_cells_round_trips(tmp_path):
    """Read in fixed columns, exported --like itself (aligned), read back: the same points,
    an empty speed and an empty note included (h135)."""
    from wakeline.app.cli import main

    rows = [
        ("Track No", "Time", "Lat", "Lon", "Speed", "Note"),
        ("1", "2024-01-01 00:00:00", "37.900000", "23.600000", "5.5", "ab"),
        ("1", "2024-01-01 00:00:01", "37.900100", "23.600100", "", ""),
        ("12", "2024-01-01 00:00:02", "37.900200", "23.600200", "", "xy"),
        ("12", "2024-01-01 00:00:03", "37.900300", "23.600300", "12.0", ""),
    ]
    text = "".join(
        f"{a:>8}  {b:<19}  {c:>9}  {d:>9}  {e:>5}  {f}".rstrip() + "\n" for a, b, c, d, e, f in rows
    )
    src = tmp_path / "e.txt"
    src.write_text(text)
    a = read_points(src)
    assert len(a.quarantine) == 0 and np.isnan(a.points["speed"].iloc[[1, 2]]).all()
    out = tmp_path / "back.txt"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    b = read_points(out)
    assert len(b.quarantine) == 0, out.read_text()
    cols = ["batch", "time", "lon", "lat", "speed", "Note"]
    pd.testing.assert_frame_equal(a.points[cols], b.points[cols])

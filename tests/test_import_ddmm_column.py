"""NMEA's degrees and minutes with the letter in the cell, judged over the column (h149).

``123.5W`` is 1°23.5' written without NMEA's zero padding (``00123.5W``) or 123.5° in
decimal degrees: in isolation nothing tells. A column is read in one form: ddmm.mmmm when
more of its cells show that form (four or five digits before the point, or beyond
90°/180° as degrees, with minutes below 60) than show degrees (minutes 60 or more: no
ddmm.mmmm), else decimal degrees, with a warning when three-digit cells could have been
either. A cell that is not in its column's form is quarantined with its reason, never
read in the other form. Read whole, streamed and in pieces alike."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_import_hemisphere_forms import _nmea_cell
from tests.test_import_spaced_pipe_nmea import _lines_accounted, _three_ways
from wakeline.core.io import read_points

_T0 = pd.Timestamp("2024-01-01")


def _file(path, lat_cells, lon_cells):
    rows = ["time,id,lat,lon"]
    for i, (a, o) in enumerate(zip(lat_cells, lon_cells, strict=True)):
        t = _T0 + pd.Timedelta(seconds=10 * i)
        rows.append(f"{t:%Y-%m-%dT%H:%M:%S},1,{a},{o}")
    path.write_text("\n".join(rows) + "\n")
    return path


def test_an_unpadded_lon_reads_as_the_rest_of_its_column(tmp_path):
    """`123.5W` beside `02342.10E` is 1°23.5' W (before: 123.5° W, the cell judged alone)."""
    src = _file(tmp_path / "a.csv", ["3754.03N"] * 3, ["02342.10E", "123.5W", "00123.6W"])
    r = read_points(src)
    assert r.report["rows_quarantined"] == 0
    np.testing.assert_allclose(r.points["lon"], [23.701667, -(1 + 23.5 / 60), -1.393333], atol=1e-6)
    assert r.report["ddmm_unpadded"] == 1 and r.report["ddmm_in_cell"] == 6
    assert any("without NMEA's zero padding" in w for w in r.report["warnings"])


def test_a_column_without_evidence_stays_degrees_and_says_it_is_ambiguous(tmp_path):
    src = _file(tmp_path / "b.csv", ["37.5N", "37.6N", "37.7N"], ["123.5W", "123.6W", "165.5W"])
    r = read_points(src)
    assert r.points["lon"].tolist() == [-123.5, -123.6, -165.5]
    assert r.report["ddmm_ambiguous"] == 2  # 165.5 cannot be 1°65.5'
    (note,) = [w for w in r.report["warnings"] if "three digits before the point" in w]
    assert note.startswith("2 positions") and "pad them (00123.5W)" in note
    assert r.report["lettered_forms"] == {"lat": "degrees", "lon": "degrees"}


def test_a_cell_in_the_other_form_is_quarantined_not_guessed(tmp_path):
    """Degrees with one padded dddmm.mm cell (`00123.6W` would read 123.6° as a number):
    quarantined with its reason. ddmm.mmmm with one cell of minutes 60 or more: the
    column's own reason."""
    src = _file(tmp_path / "c.csv", ["37.5N"] * 3, ["123.5W", "165.5W", "00123.6W"])
    r = read_points(src)
    _lines_accounted(r, src)
    assert r.quarantine["reason"].tolist() == [
        "lon in ddmm.mmmm (degrees and minutes run together, like 3754.03N) where the rest "
        "of its column is decimal degrees with a letter"
    ]
    src = _file(tmp_path / "d.csv", ["3754.03N"] * 3, ["02342.10E", "02342.20E", "165.5W"])
    r = read_points(src)
    _lines_accounted(r, src)
    assert r.quarantine["reason"].tolist() == [
        "lon not in ddmm.mmmm as the rest of its column (minutes 60 or more)"
    ]


@pytest.mark.parametrize("way", ["streamed", "in pieces"])
def test_pieces_that_see_different_forms_read_the_file_whole(tmp_path, monkeypatch, way):
    """The evidence only in the file's last rows: the first pieces hold unpadded cells
    alone (degrees by themselves). Streamed and in pieces (quotes in the file) the
    pieces disagree and the file is read whole: the same bytes and report."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, sniff, write_points
    from wakeline.core.io.pieces import read_in_pieces

    lat = [f"{3700 + k * 0.01:.2f}N" for k in range(40)]
    lon = [f"{123 + k * 0.01:.2f}W" for k in range(36)] + ["02342.10E"] * 4
    if way == "in pieces":
        lat = [f'"{a}"' for a in lat]
    src = _file(tmp_path / "e.csv", lat, lon)
    whole = read_points(src)
    assert whole.report["rows_quarantined"] == 0
    assert whole.points["lon"].iloc[0] == pytest.approx(-(1 + 23 / 60))
    assert whole.report["ddmm_unpadded"] == 36
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    got = import_to_csv(src, tmp_path / "out.csv")
    assert (tmp_path / "out.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    for key in ("rows_quarantined", "ddmm_in_cell", "ddmm_unpadded", "lettered_forms"):
        assert got.report.get(key) == whole.report.get(key), key
    assert set(got.report["warnings"]) == set(whole.report["warnings"])
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None}
    with pytest.raises(reader.WholeFileNeeded):  # the pieces judge apart: one judgement
        read_in_pieces(sniff(src), read, lambda p: None, tmp_path / "scratch")


def test_pieces_that_agree_read_in_pieces(tmp_path, monkeypatch):
    """Every piece holding cells that show ddmm.mmmm: read in pieces as the whole file."""
    lat = [f"{3700 + k * 0.01:.2f}N" for k in range(40)]
    lon = [f"{123 + k * 0.01:.2f}W" if k % 3 else "02342.10E" for k in range(40)]
    src = _file(tmp_path / "f.csv", lat, lon)
    r = _three_ways(src, tmp_path, monkeypatch, size=300)
    assert r.report["rows_quarantined"] == 0 and r.report["ddmm_unpadded"] == 26


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    lat=st.lists(st.floats(1.0, 89.99, allow_nan=False), min_size=1, max_size=12),
    lon=st.lists(st.floats(0.02, 179.99, allow_nan=False), min_size=1, max_size=12),
    shown=st.floats(10.0, 179.99, allow_nan=False),
    signs=st.integers(0, 3),
    padded=st.booleans(),
)
def test_ddmm_columns_read_back_whatever_the_padding(
    tmp_path_factory, lat, lon, shown, signs, padded
):
    """Positions written as ddmm.mmmm / dddmm.mmmm with letters, padded or not, the lon
    column holding one position of 10° or more (its five digits show the form): every
    cell reads back its position; none is read as decimal degrees."""
    n = max(len(lat), len(lon))
    lat = (lat * n)[:n]
    lon = ([shown] + lon * n)[: n + 1]
    lat = [lat[0]] + lat
    lat = [-a if signs & 1 else a for a in lat]
    lon = [-o if signs & 2 else o for o in lon]
    cells_lat = [_nmea_cell(a, "NS", 4 if padded else 0) for a in lat]
    cells_lon = [_nmea_cell(o, "EW", 5 if padded else 0) for o in lon]
    src = _file(tmp_path_factory.mktemp("p") / "p.csv", cells_lat, cells_lon)
    r = read_points(src)
    assert len(r.points) == len(lat), r.quarantine.to_dict("records")
    np.testing.assert_allclose(r.points["lat"], lat, atol=2e-6)
    np.testing.assert_allclose(r.points["lon"], lon, atol=2e-6)
    assert r.report["lettered_forms"]["lon"] == "ddmm"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    lon=st.lists(st.floats(-179.9, 179.9, allow_nan=False), min_size=1, max_size=15),
    decimals=st.integers(1, 5),
)
def test_decimal_degree_columns_stay_degrees_and_count_the_ambiguous(
    tmp_path_factory, lon, decimals
):
    """Decimal degrees with letters are never read as ddmm.mmmm (no cell shows it); the
    warning counts the three-digit cells that could be dddmm.mm unpadded."""
    cells = [f"{abs(o):.{decimals}f}{'W' if o < 0 else 'E'}" for o in lon]
    src = _file(tmp_path_factory.mktemp("q") / "q.csv", ["37.5N"] * len(lon), cells)
    r = read_points(src)
    assert len(r.points) == len(lon)
    written = [float(c[:-1]) * (-1 if c.endswith("W") else 1) for c in cells]
    np.testing.assert_allclose(r.points["lon"], written, atol=1e-9)
    ambiguous = sum(100 <= abs(w) and abs(w) % 100 < 60 for w in written)
    assert r.report.get("ddmm_ambiguous", 0) == ambiguous

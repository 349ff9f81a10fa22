"""Positions whose sign is a hemisphere letter (h134): plain decimal degrees with a column
of N/S (E/W) beside them, and NMEA's ddmm.mmmm with the letter in the cell (``3754.03N``,
``02342.10E``). Each read whole, streamed and in pieces alike; every line a point or a
quarantined row."""

import numpy as np
import pandas as pd
import pyarrow as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.test_import_spaced_pipe_nmea import _lines_accounted, _three_ways
from wakeline.core.io import read_points


def _letters_file(lat, lon, header=("time", "id", "lat", "ns", "lon", "ew")) -> str:
    rows = [",".join(header)]
    for i, (a, o) in enumerate(zip(lat, lon, strict=True)):
        t = pd.Timestamp("2024-01-01") + pd.Timedelta(seconds=10 * i)
        rows.append(
            f"{t:%Y-%m-%dT%H:%M:%S},{1 + i % 2},{abs(a):.6f},{'S' if a < 0 else 'N'},"
            f"{abs(o):.6f},{'W' if o < 0 else 'E'}"
        )
    return "\n".join(rows) + "\n"


def _track(n: int = 40) -> tuple[np.ndarray, np.ndarray]:
    lat = np.round(-37.9 + np.arange(n) * 1e-4, 6)
    lon = np.round(-23.6 - np.arange(n) * 1e-4, 6)
    return lat, lon


def test_decimal_degrees_take_their_signs_from_letter_columns(tmp_path, monkeypatch):
    lat, lon = _track()
    src = tmp_path / "letters.csv"
    src.write_text(_letters_file(lat, lon))
    r = _three_ways(src, tmp_path, monkeypatch)
    assert len(r.points) == 40 and r.report["rows_quarantined"] == 0
    got = r.points.sort_values("time")
    np.testing.assert_allclose(got["lat"], lat)  # south and west: negative, not mirrored
    np.testing.assert_allclose(got["lon"], lon)
    assert r.report["letter_signs"] == 80
    assert any("hemisphere letters in 'ns' and 'ew'" in w for w in r.report["warnings"])


def test_letter_columns_named_as_exports_name_them_and_mixed_hemispheres(tmp_path):
    src = tmp_path / "ns.csv"
    src.write_text(
        "time,id,Latitude,N/S,Longitude,E/W\n"
        "2024-01-01T00:00:00,1,0.5,N,0.25,w\n"
        "2024-01-01T00:00:10,1,0.4, S ,0.35,E\n"
        "2024-01-01T00:00:20,1,0.3,s,0.45,W\n"
    )
    r = read_points(src)
    assert r.points["lat"].tolist() == [0.5, -0.4, -0.3]
    assert r.points["lon"].tolist() == [-0.25, 0.35, -0.45]


def test_letter_against_the_sign_and_other_letters_are_quarantined(tmp_path):
    lines = ["time,id,lat,ns,lon,ew"]
    for i in range(200):
        lines.append(f"2024-01-01T00:{i // 60:02d}:{i % 60:02d},1,37.9,S,23.6,W")
    lines[5] = "2024-01-01T00:00:04,1,-37.9,N,23.6,W"  # the sign says south, the letter north
    lines[6] = "2024-01-01T00:00:05,1,-37.9,S,23.6,W"  # both say south: -37.9
    lines[7] = "2024-01-01T00:00:06,1,37.9,S,23.6,Q"  # one damaged letter among 200
    lines[8] = "2024-01-01T00:00:07,1,,S,23.6,W"
    lines[9] = "2024-01-01T00:00:08,1,37.9,,23.6,W"  # no letter: the number as written
    src = tmp_path / "bad.csv"
    src.write_text("\n".join(lines) + "\n")
    r = read_points(src)
    _lines_accounted(r, src)
    reasons = dict(zip(r.quarantine["line"], r.quarantine["reason"], strict=True))
    assert reasons == {
        6: "lat negative but its hemisphere letter says N",
        8: "lon hemisphere letter not E or W",
        9: "missing lat",
    }
    assert (r.points["lon"] == -23.6).all()
    assert sorted(set(r.points["lat"])) == [-37.9, 37.9]  # 37.9 only where no letter
    assert (r.points["lat"] == 37.9).sum() == 1


def test_a_letter_column_beside_the_fast_path_costs_nothing_when_numeric(tmp_path):
    """Numbers beside lat/lon (the common file) are no letter column: no cast, no note."""
    src = tmp_path / "plain.csv"
    src.write_text("time,id,lat,lon,sog\n2024-01-01T00:00:00,1,-37.9,-23.6,5\n")
    r = read_points(src)
    assert "letter_signs" not in r.report
    assert r.points["lat"].tolist() == [-37.9]


def test_one_rule_for_reader_and_layout(tmp_path):
    """The layout export --like learns marks the letter columns the reader reads (one
    helper: 99 % of present cells, not all of them), and writes the file back."""
    from wakeline.app.cli import main
    from wakeline.core.io.layout import load_layout

    lat, lon = _track(200)
    text = _letters_file(lat, lon).splitlines()
    text[3] = text[3].rsplit(",", 1)[0] + ",?"  # one damaged lon letter
    src = tmp_path / "letters.csv"
    src.write_text("\n".join(text) + "\n")
    layout = load_layout(src)
    assert {c.key: c.hemisphere for c in layout.columns if c.hemisphere} == {
        "ns": "lat",
        "ew": "lon",
    }
    clean = tmp_path / "clean.csv"
    clean.write_text(_letters_file(lat, lon))
    out = tmp_path / "back.csv"
    assert main(["export", str(clean), "-o", str(out), "--like", str(clean)]) == 0
    assert out.read_bytes() == clean.read_bytes()


def test_hemisphere_letters_helper():
    from wakeline.core.io.reader import hemisphere_letters

    neg, other, pos = hemisphere_letters(pa.array(["N", " s", "", None, "n"]), "NS")
    assert neg.tolist() == [False, True, False, False, False]
    assert pos.tolist() == [True, False, False, False, True]
    assert not other.any()
    assert hemisphere_letters(pa.array([1.0, 2.0]), "NS") is None
    assert hemisphere_letters(pa.array(["N", "X"]), "NS") is None  # 50 %: not letters
    assert hemisphere_letters(pa.array(["", None]), "NS") is None


@settings(max_examples=60, deadline=None)
@given(
    lat=st.floats(-89.999, 89.999, allow_nan=False),
    lon=st.floats(-179.999, 179.999, allow_nan=False),
)
def test_letter_columns_read_back_any_position(tmp_path_factory, lat, lon):
    lat, lon = round(lat, 6), round(lon, 6)
    src = tmp_path_factory.mktemp("h") / "p.csv"
    src.write_text(_letters_file([lat, lat], [lon, lon]))
    r = read_points(src)
    assert r.points["lat"].tolist() == [abs(lat) * (-1 if lat < 0 else 1)] * 2
    assert r.points["lon"].tolist() == [abs(lon) * (-1 if lon < 0 else 1)] * 2


# --- NMEA's ddmm.mmmm with the letter in the cell ---------------------------------------


def _nmea_cell(value: float, letters: str, width: int, form: str = "{n}{h}") -> str:
    a = abs(value)
    deg = int(a)
    minutes = round((a - deg) * 60, 4)
    if minutes >= 60:
        deg, minutes = deg + 1, 0.0
    number = f"{deg * 100 + minutes:0{width + 5}.4f}"
    return form.format(n=number, h=letters[int(value < 0)])


def test_ddmm_with_the_letter_in_the_cell(tmp_path, monkeypatch):
    lat, lon = _track()
    rows = ["time,id,lat,lon"]
    forms = ["{n}{h}", "{n} {h}", "{h}{n}", "{h} {n}"]
    for i, (a, o) in enumerate(zip(lat, lon, strict=True)):
        t = pd.Timestamp("2024-01-01") + pd.Timedelta(seconds=10 * i)
        f = forms[i % 4]
        rows.append(
            f"{t:%Y-%m-%dT%H:%M:%S},{1 + i % 2},{_nmea_cell(a, 'NS', 4, f)},"
            f"{_nmea_cell(o, 'EW', 5, f)}"
        )
    src = tmp_path / "cells.csv"
    src.write_text("\n".join(rows) + "\n")
    r = _three_ways(src, tmp_path, monkeypatch)
    assert r.report["rows_quarantined"] == 0 and r.report["ddmm_in_cell"] == 80
    got = r.points.sort_values("time")
    np.testing.assert_allclose(got["lat"], lat, atol=1e-6)
    np.testing.assert_allclose(got["lon"], lon, atol=1e-6)
    assert any("letter in the cell" in w for w in r.report["warnings"])


def test_ddmm_cells_edge_forms(tmp_path):
    src = tmp_path / "edge.csv"
    src.write_text(
        "time,id,lat,lon\n"
        "2024-01-01T00:00:00,1,3754.03N,02342.10E\n"
        "2024-01-01T00:00:10,1,0030.5000S,942.1W\n"  # lat under a degree; unpadded lon > 180
        "2024-01-01T00:00:20,1,3754,03S,02342.10E\n"  # decimal comma (quoted or ; files)
        "2024-01-01T00:00:30,1,3775.05S,02342.12W\n"  # minutes 75: no position
        "2024-01-01T00:00:40,1,37.5S,123.5W\n"  # unpadded, in ddmm.mmmm columns (h149)
    )
    r = read_points(src)
    _lines_accounted(r, src)
    got = r.points.set_index(r.points["time"].dt.second)["lat"].to_dict()
    assert got[0] == pytest.approx(37.9005) and got[10] == pytest.approx(-0.508333, abs=1e-6)
    # one form a column (h149): before, 37.5S was -37.5 beside 3754.03N (-37.9005) and
    # 123.5W -123.5 beside 02342.10E, each cell judged alone
    assert got[40] == pytest.approx(-0.625)
    lon = r.points.set_index(r.points["time"].dt.second)["lon"].to_dict()
    assert lon[10] == pytest.approx(-9.701667, abs=1e-6)
    assert lon[40] == pytest.approx(-(1 + 23.5 / 60))
    assert set(r.quarantine["line"]) == {4, 5}  # the comma splits the row; minutes 75
    assert r.quarantine.set_index("line")["reason"][5] == (
        "lat not in ddmm.mmmm as the rest of its column (minutes 60 or more)"
    )
    assert r.report["ddmm_unpadded"] == 3  # 37.5S, 942.1W, 123.5W
    assert r.report["lettered_forms"] == {"lat": "ddmm", "lon": "ddmm"}


@settings(max_examples=100, deadline=None)
@given(
    lat=st.floats(-89.99, 89.99, allow_nan=False),
    lon=st.floats(-179.99, 179.99, allow_nan=False),
    form=st.sampled_from(["{n}{h}", "{n} {h}", "{h}{n}", "{h} {n}"]),
)
def test_ddmm_cells_read_back_any_position(tmp_path_factory, lat, lon, form):
    lat_cell, lon_cell = _nmea_cell(lat, "NS", 4, form), _nmea_cell(lon, "EW", 5, form)
    src = tmp_path_factory.mktemp("d") / "p.csv"
    src.write_text(f"time,id,lat,lon\n2024-01-01T00:00:00,1,{lat_cell},{lon_cell}\n")
    r = read_points(src)
    assert len(r.points) == 1, r.quarantine
    # written to 1e-4 minutes: 1.7e-6 degrees
    assert r.points["lat"].iloc[0] == pytest.approx(lat, abs=2e-6)
    assert r.points["lon"].iloc[0] == pytest.approx(lon, abs=2e-6)

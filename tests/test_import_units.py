"""Units of speeds and local-plane lengths (h134): a header that names its unit
(``speed_mps``, ``sog_kmh``, ``速度(km/h)``, ``Speed (m/s)``, ``x_yd``) is read in it and
converted (knots, metres); ``--speed-unit`` / ``--distance-unit`` give the unit of columns
whose header names none."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.geo import haversine_m, to_local
from wakeline.core.io import read_points
from wakeline.core.io.formats import normalize_header, speed_unit

KNOT = 1852.0  # metres per hour


def _speeds(path, header: str, values) -> None:
    rows = [f"time,id,lat,lon,{header}"]
    for k, v in enumerate(values):
        rows.append(f"2024-01-01T00:00:{k:02d},{1 + k % 2},37.{k:04d},23.6,{v}")
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")


@pytest.mark.parametrize(
    ("header", "per_hour"),
    [
        ("speed_mps", 3600.0),
        ("Speed (m/s)", 3600.0),
        ("speed_ms", 3600.0),
        ("sog_kmh", 1000.0),
        ("SOG [km/h]", 1000.0),
        ("速度(km/h)", 1000.0),
        ("speed_kph", 1000.0),
        ("speed_mph", 1609.344),
        ("速度(米/秒)", 3600.0),
        ("speed_kn", KNOT),
        ("SOG (knots)", KNOT),
        ("speed", KNOT),
    ],
)
def test_a_header_naming_its_speed_unit(tmp_path, header, per_hour):
    src = tmp_path / "s.csv"
    values = [0.0, 5.0, 12.5, 18.52]
    _speeds(src, header, values)
    r = read_points(src)
    assert r.report["columns"]["speed"] == header
    np.testing.assert_allclose(r.points["speed"], np.array(values) * per_hour / KNOT)
    said = any("converted to knots" in w for w in r.report["warnings"])
    assert said == (per_hour != KNOT)


def test_the_flag_gives_the_unit_of_a_header_without_one(tmp_path, monkeypatch):
    src = tmp_path / "s.csv"
    _speeds(src, "speed", [float(k) for k in range(40)])
    r = _three_ways_units(src, tmp_path, monkeypatch, speed_unit="m/s")
    np.testing.assert_allclose(sorted(r.points["speed"]), np.arange(40) * 3600 / KNOT)
    assert "speeds were given in m/s (--speed-unit): converted to knots" in r.report["warnings"]
    # a header naming its own unit wins, and the flag is said to be unused
    src2 = tmp_path / "s2.csv"
    _speeds(src2, "speed_kmh", [18.52])
    r = read_points(src2, speed_unit="m/s")
    assert r.points["speed"].tolist() == [10.0]
    assert any("--speed-unit m/s not used" in w for w in r.report["warnings"])
    with pytest.raises(InputError, match="--speed-unit 'furlongs'"):
        read_points(src, speed_unit="furlongs")


def _three_ways_units(src, tmp_path, monkeypatch, **units):
    """The streamed and piece reads with the units given agree with the whole read."""
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, sniff, write_points
    from wakeline.core.io.pieces import read_in_pieces

    whole = read_points(src, **units)
    write_points(whole.points, tmp_path / "whole.csv")
    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    streamed = import_to_csv(src, tmp_path / "streamed.csv", **units)
    assert (tmp_path / "streamed.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    got = []
    read = {"fmt": "auto", "mapping": None, "sensor": "S1", "tz": None, **units}
    pieces = read_in_pieces(sniff(src), read, got.append, tmp_path / "scratch")
    assert pieces.report["pieces"] > 2
    write_points(pd.concat(got, ignore_index=True), tmp_path / "pieces.csv")
    assert (tmp_path / "pieces.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    assert set(streamed.report["warnings"]) == set(whole.report["warnings"])
    assert set(pieces.report["warnings"]) == set(whole.report["warnings"])
    return whole


def test_speed_unit_words_normalise_to_the_speed_field():
    for header in ("speed_mps", "sog_kmh", "speed_kph", "speed_mph", "速度(km/h)"):
        assert normalize_header(header) in ("speed", "sog", "速度"), header


@settings(max_examples=100, deadline=None)
@given(
    v=st.floats(0, 1e4, allow_nan=False),
    unit=st.sampled_from(["m/s", "km/h", "mph", "knots"]),
)
def test_speed_units_convert_any_value(v, unit):
    import pyarrow as pa

    from wakeline.core.io.reader import _in_knots

    got = _in_knots(pa.array([v]), "speed", unit, {}).to_pylist()[0]
    per_hour = speed_unit("speed", unit)[0]
    assert got == pytest.approx(v * per_hour / KNOT, rel=1e-12)
    assert speed_unit(f"speed ({unit})")[1] == unit


ORIGIN = (63.4389029083, 10.39908278)


@pytest.mark.parametrize(
    ("names", "flag", "metres"),
    [
        (("x_yd", "y_yd"), "auto", 0.9144),
        (("x (yards)", "y (yards)"), "auto", 0.9144),
        (("x", "y"), "yd", 0.9144),
        (("x", "y"), "km", 1000.0),
        (("x", "y"), "nm", 1852.0),
        (("x_km", "y_km"), "yd", 1000.0),  # the header's own unit wins
    ],
)
def test_plane_lengths_in_the_unit_named_or_given(tmp_path, names, flag, metres):
    lat = ORIGIN[0] + np.linspace(0, 0.01, 10)
    lon = ORIGIN[1] + np.linspace(0, 0.02, 10)
    east, north = to_local(lon, lat, ORIGIN[1], ORIGIN[0])
    df = pd.DataFrame({"time": 1_620_000_000 + np.arange(10), "track": 1})
    df[names[0]], df[names[1]] = np.round(east / metres, 6), np.round(north / metres, 6)
    src = tmp_path / "xy.csv"
    df.to_csv(src, index=False)
    r = read_points(src, origin=f"{ORIGIN[0]},{ORIGIN[1]}", distance_unit=flag)
    assert r.report["rows_quarantined"] == 0
    assert haversine_m(r.points["lon"], r.points["lat"], lon, lat).max() < 0.01


def test_cli_flags(tmp_path, capsys):
    src = tmp_path / "s.csv"
    _speeds(src, "speed", [10.0])
    out = tmp_path / "out.csv"
    assert main(["import", str(src), "-o", str(out), "--speed-unit", "km/h"]) == 0
    got = pd.read_csv(out)
    assert got["speed"].tolist() == pytest.approx([10.0 * 1000 / KNOT])
    assert main(["clean", str(src), "-o", str(tmp_path / "c.csv"), "--speed-unit", "mph"]) == 0
    with pytest.raises(SystemExit):
        main(["import", str(src), "-o", str(out), "--distance-unit", "furlongs"])


@pytest.mark.parametrize("header", ["speed_mps", "sog_kmh", "速度(km/h)", "speed"])
def test_export_like_writes_speeds_back_in_the_unit_of_their_header(tmp_path, header):
    src = tmp_path / "s.csv"
    _speeds(src, header, [0.0, 5.5, 12.25, 18.5])
    out = tmp_path / "back.csv"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    assert out.read_text(encoding="utf-8") == src.read_text(encoding="utf-8")

"""Speeds under a header with no unit checked against the positions (h191, D-import-14):
a file whose speeds are km/h, m/s or mph read as knots is named, with the flag that reads
it; knots, a header naming its unit, a given --speed-unit and the real sets stay quiet."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import real_file
from wakeline.app.core_text import translate
from wakeline.app.window_words import window_words
from wakeline.core.io import read_points
from wakeline.core.io.speed_check import likely_unit, speed_ratio, speed_unit_warnings

PER_KNOT = {"knots": 1.0, "km/h": 1.852, "m/s": 1852 / 3600, "mph": 1852 / 1609.344}


def tracks(unit: str, n_tracks=4, n=60, dt=30.0, noise_m=0.0, seed=0) -> pd.DataFrame:
    """Straight tracks at 8-20 kn, the speed column in ``unit`` (its true value)."""
    rng = np.random.default_rng(seed)
    rows = []
    for k in range(n_tracks):
        kn = rng.uniform(8, 20)
        heading = rng.uniform(0, 2 * np.pi)
        s = np.arange(n) * dt
        dist = kn * 1852 / 3600 * s
        north = (
            dist * np.cos(heading) + rng.normal(0, noise_m, n)
            if noise_m
            else dist * np.cos(heading)
        )
        east = dist * np.sin(heading) + (rng.normal(0, noise_m, n) if noise_m else 0)
        lat = 30 + north / 111_195.0
        lon = 122 + east / (111_195.0 * np.cos(np.radians(30)))
        t = pd.Timestamp("2026-12-05", tz="UTC") + pd.to_timedelta(s, unit="s")
        speed = np.full(n, kn * PER_KNOT[unit]) * rng.uniform(0.98, 1.02, n)
        rows.append(
            pd.DataFrame(
                {"sensor": "S1", "batch": str(k), "time": t, "lon": lon, "lat": lat, "speed": speed}
            )
        )
    return pd.concat(rows, ignore_index=True).sample(frac=1.0, random_state=seed)


@pytest.mark.parametrize("unit", ["km/h", "m/s", "mph"])
def test_each_unit_is_named_with_its_flag(unit):
    w = speed_unit_warnings(tracks(unit), "航速", "knots")
    assert len(w) == 1 and f"look like {unit}," in w[0] and w[0].endswith(f"--speed-unit {unit}")


def test_knots_are_quiet():
    assert speed_unit_warnings(tracks("knots"), "航速", "knots") == []
    assert speed_ratio(tracks("knots"))[0] == pytest.approx(1.0, abs=0.03)


def test_no_speed_or_too_few_rows_is_quiet():
    assert speed_unit_warnings(tracks("km/h").drop(columns="speed"), "航速", "knots") == []
    assert speed_unit_warnings(tracks("km/h", n_tracks=1, n=5), "航速", "knots") == []


def test_noisy_speeds_near_mph_are_not_called_mph():
    """A noisy radar's speeds (1.13 with a wide spread: operator test 6's s3e1 AIS) do not
    rule knots out: no unit is named."""
    assert likely_unit(1.13, 0.18) is None
    assert likely_unit(1.15, 0.005) == ("mph", "mph", pytest.approx(1.1508, abs=1e-3))
    assert likely_unit(1.0, 0.0) is None and likely_unit(3.0, 0.0) is None


@settings(max_examples=25, deadline=None)
@given(unit=st.sampled_from(sorted(PER_KNOT)), seed=st.integers(0, 10_000))
def test_property_the_unit_found_is_the_unit_written(unit, seed):
    """Any clean straight tracks: the check names exactly the unit the speeds are in,
    and says nothing about knots."""
    w = speed_unit_warnings(tracks(unit, seed=seed), "speed_col", "knots")
    if unit == "knots":
        assert w == []
    else:
        assert len(w) == 1 and f"look like {unit}," in w[0]


@settings(
    max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(seed=st.integers(0, 10_000), unit=st.sampled_from(["knots", "km/h"]))
def test_property_import_warns_and_loses_nothing(write, seed, unit):
    """Through the importer (a Chinese console file): every row is read, speeds as written
    (not converted: the check only warns), and the warning is there for km/h only."""
    df = tracks(unit, seed=seed).sort_values(["batch", "time"])
    lines = ["批号,时间,经度,纬度,航速"] + [
        f"{b},{t:%Y-%m-%d %H:%M:%S},{x:.6f},{y:.6f},{v:.2f}"
        for b, t, x, y, v in zip(df.batch, df.time, df.lon, df.lat, df.speed, strict=True)
    ]
    r = read_points(write("c.csv", ("\r\n".join(lines) + "\r\n").encode("gb18030")))
    assert len(r.points) == len(df) and len(r.quarantine) == 0
    assert np.allclose(np.sort(r.points["speed"]), np.sort(np.round(df.speed, 2)))
    warned = [w for w in r.report["warnings"] if "look like" in w]
    assert len(warned) == (unit == "km/h")


def test_header_unit_or_given_unit_is_not_checked(write):
    df = tracks("km/h").sort_values(["batch", "time"])
    body = [
        f"{b},{t:%Y-%m-%d %H:%M:%S},{x:.6f},{y:.6f},{v:.2f}"
        for b, t, x, y, v in zip(df.batch, df.time, df.lon, df.lat, df.speed, strict=True)
    ]
    for header, opts in (
        ("速度(节)", {}),
        ("航速", {"speed_unit": "km/h"}),
        ("航速", {"speed_unit": "knots"}),
    ):
        text = "\n".join([f"批号,时间,经度,纬度,{header}"] + body) + "\n"
        r = read_points(write("h.csv", text), **opts)
        assert not [w for w in r.report["warnings"] if "look like" in w], (header, opts)


def test_the_warning_in_the_window_and_in_chinese():
    w = speed_unit_warnings(tracks("km/h"), "航速", "knots")[0]
    shown = window_words(w)
    assert shown.endswith("choose km/h in the import dialog's Speed unit field")
    zh = translate(shown, "zh_CN")
    assert "航速看来是 km/h" in zh and "航速单位" in zh and "look like" not in zh
    assert "请用 --speed-unit km/h 读取" in translate(w, "zh_CN")


@pytest.mark.parametrize(
    "parts, mapping",
    [
        (("greece-ais-annotated", "vessel_1_id_annotated.csv"), None),
        (("greece-ais-annotated", "vessel_3_id_annotated.csv"), None),
        (("dma-single-ship", "sample_ship.csv"), None),
        (("oresund-encounters", "encounters.csv"), None),
        (("mtad-dtwcm", "original", "Scene-7.csv"), None),
        (("mtad-dtwcm", "two_sensor", "scene-3_error_1_radar.csv"), None),
        (("atd2025-noaa", "dataset1_truth.csv.gz"), None),
        (("atd2025-noaa", "example_truth.csv.gz"), None),
    ],
)
def test_no_warning_on_the_real_sets(parts, mapping):
    r = read_points(real_file(*parts), mapping=mapping)
    assert not [w for w in r.report["warnings"] if "look like" in w]


@pytest.mark.parametrize("quoted", [False, True])
def test_streamed_and_pieced_imports_warn_once(tmp_path, monkeypatch, quoted):
    """``wakeline import`` of a file read in pieces (streamed, or quoted: in pieces) says
    the speed warning once, as the whole-file reader does."""
    from wakeline.core.io import reader
    from wakeline.core.io.reader import import_to_csv

    df = tracks("km/h", n_tracks=6, n=200).sort_values(["batch", "time"])
    q = '"' if quoted else ""
    lines = ["批号,时间,经度,纬度,航速"] + [
        f"{q}{b}{q},{t:%Y-%m-%d %H:%M:%S},{x:.6f},{y:.6f},{v:.2f}"
        for b, t, x, y, v in zip(df.batch, df.time, df.lon, df.lat, df.speed, strict=True)
    ]
    src = tmp_path / "big.csv"
    src.write_bytes(("\r\n".join(lines) + "\r\n").encode("gb18030"))
    whole = read_points(src)
    monkeypatch.setattr(reader, "STREAM_BYTES", 4 << 10)
    assert src.stat().st_size > 8 * (4 << 10)
    got = import_to_csv(src, tmp_path / "out.csv")
    said = [w for w in got.report["warnings"] if "look like km/h" in w]
    assert len(said) == 1
    assert [w for w in whole.report["warnings"] if "look like km/h" in w]
    assert got.report["rows_imported"] == len(df)

"""``export --like`` writes a ``Date,Time`` layout's two columns and degrees-and-minutes
positions back in their own forms (core/io/layout.py, core/io/export_like.py)."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from wakeline.core.io import read_points
from wakeline.core.io.export_like import format_angles, write_layout
from wakeline.core.io.layout import AngleFormat, Layout, describe_layout


def _round_trip(path: Path, tmp_path: Path, **read) -> tuple[pd.DataFrame, pd.DataFrame, Path]:
    first = read_points(path, **read)
    layout = describe_layout(path, first.report, date_order=read.get("date_order", "auto"))
    out = tmp_path / f"back_{path.name}"
    write_layout(first.points, layout, out)
    return first.points, read_points(out, **read).points, out


@pytest.mark.parametrize(
    ("text", "fmt"),
    [
        ("57°40.0260000'N", AngleFormat(decimals=7)),
        ("N 57 40.026", AngleFormat(suffix=False, gap=" ", deg_mark=" ", min_mark="", decimals=3)),
        ("057°05.50'E", AngleFormat(deg_mark="°", decimals=2, deg_width=3, min_width=2)),
        (
            "N 57 40 01.6",
            AngleFormat(
                suffix=False,
                gap=" ",
                deg_mark=" ",
                min_mark=" ",
                seconds=True,
                decimals=1,
                sec_width=2,
            ),
        ),
        ("57°40'01.60\"N", AngleFormat(seconds=True, sec_mark='"', decimals=2, sec_width=2)),
    ],
)
def test_an_angle_style_is_learnt_and_written_back(text, fmt):
    got = AngleFormat.detect(pd.Series([text, text]))
    assert got == fmt
    lat = read_points_value(text)
    hemi = ("E", "W") if text.rstrip().endswith("E") else ("N", "S")
    assert format_angles(np.array([lat]), got, *hemi).to_pylist() == [text]


def read_points_value(text: str) -> float:
    """The degrees the importer reads from ``text`` (its degrees-and-minutes rule)."""
    from wakeline.core.io.reader import _with_dms

    values = np.array([np.nan])
    assert _with_dms(pd.Series([text]), values) == 1
    return float(values[0])


def test_minutes_that_round_to_60_carry_into_the_degrees():
    fmt = AngleFormat(decimals=2)
    assert format_angles(np.array([57.99999999, -0.5, np.nan]), fmt, "N", "S").to_pylist() == [
        "58°0.00'N",
        "0°30.00'S",
        "",
    ]


def test_a_date_time_layout_with_month_first_iso_and_midnight_rounding(tmp_path):
    p = tmp_path / "us.csv"
    p.write_text(
        "MMSI,Date,Time,Latitude,Longitude\n"
        "1,03/04/2025,23:59:59.9,57.1,11.1\n"
        "1,03/05/2025,00:00:09.9,57.2,11.2\n"
    )
    first, again, out = _round_trip(p, tmp_path, date_order="month-first")
    assert first["time"].iloc[0] == pd.Timestamp("2025-03-04 23:59:59.9", tz="UTC")
    assert again["time"].tolist() == first["time"].tolist()
    assert out.read_text() == p.read_text()
    # the date column follows the clock's rounding: 23:59:59.96 at 1 digit is the next day
    lay = describe_layout(p, date_order="month-first")
    late = first.assign(
        time=pd.to_datetime(
            ["2025-03-04 23:59:59.96", "2025-03-05 00:00:00"], utc=True, format="ISO8601"
        )
    )
    write_layout(late, lay, out)
    assert out.read_text().splitlines()[1].startswith("1,03/05/2025,00:00:00.0,")
    iso = tmp_path / "iso.csv"
    iso.write_text(
        "id;Date;Time;lat;lon\n7;2025-01-02;08:00:01;57,5;11,5\n7;2025-01-02;08:00:11;57,6;11,6\n"
    )
    _, _, out = _round_trip(iso, tmp_path)
    assert out.read_text() == iso.read_text()


def test_the_layout_json_keeps_the_angle_and_the_date_column(tmp_path):
    p = tmp_path / "p.csv"
    p.write_text(
        "Target,Date,Time,Latitude,Longitude\n"
        "a,01/02/2024,10:00:00,57°40.026'N,11°48.270'E\n"
        "a,13/02/2024,10:00:10,33°52.300'S,70°30.000'W\n"
    )
    lay = describe_layout(p)
    again = Layout.from_dict(lay.to_dict())
    assert again == lay
    assert [c.field for c in lay.columns] == ["batch", "date", "time", "lat", "lon"]
    first, back, out = _round_trip(p, tmp_path)
    assert out.read_text() == p.read_text()
    assert np.array_equal(back[["lon", "lat"]].to_numpy(), first[["lon", "lat"]].to_numpy())


def test_a_12_hour_clock_apart_from_its_month_first_date(tmp_path):
    p = tmp_path / "ampm.csv"
    p.write_text(
        "MMSI,Date,Time,LAT,LON\n"
        "1,05/17/2024,08:01:04 PM,57.1,11.1\n"
        "1,05/18/2024,12:00:00 AM,57.2,11.2\n"
        "1,05/18/2024,12:30:00 PM,57.3,11.3\n"
    )
    first, again, out = _round_trip(p, tmp_path)
    assert first["time"].dt.hour.tolist() == [20, 0, 12]
    assert again["time"].tolist() == first["time"].tolist()
    assert out.read_text() == p.read_text()

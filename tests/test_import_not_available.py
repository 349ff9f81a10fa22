"""AIS "not available" values (ITU-R M.1371): SOG 1023 (102.3 kn), COG 3600 (360°),
lon 181 / lat 91 are no values; a radar's speed column keeps 102.3 kn."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.io import import_to_csv, read_points

NO_POSITION = "position not available (lon 181 / lat 91)"


def _ais_text(
    rows: list[tuple[str, str, str, str]], header: str = "MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading"
) -> str:
    lines = [header]
    for k, (lat, lon, sog, cog) in enumerate(rows):
        lines.append(
            f"219000001,2024-05-01T08:{k // 60:02d}:{k % 60:02d},{lat},{lon},{sog},{cog},511"
        )
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("streamed", [False, True])
def test_ais_not_available_values_are_no_values(write, tmp_path, streamed):
    """Tester: 102.3 kn, COG 360, lat 91 / lon 181 imported as real values (102.3 kn
    flowed into cleaning and statistics). Speed and course are blanked and counted, the
    row kept; an n/a position is quarantined with its own reason."""
    rows = [
        ("56.0", "12.0", "9.5", "45.0"),
        ("56.001", "12.001", "102.3", "45.0"),
        ("56.002", "12.002", "9.5", "360.0"),
        ("91", "181", "102.3", "360.0"),
        ("56.003", "12.003", "102.2", "359.9"),
    ]
    path = write("ais.csv", _ais_text(rows))
    if streamed:
        r = import_to_csv(path, tmp_path / "o.csv")
        points = pd.read_csv(tmp_path / "o.csv")
    else:
        r = read_points(path)
        points = r.points
    assert r.report["format"] == "ais-marinecadastre"
    assert len(points) == 4
    assert r.quarantine["reason"].tolist() == [NO_POSITION]
    assert r.quarantine["line"].tolist() == [5]
    assert points["speed"].isna().tolist() == [False, True, False, False]
    assert points["course"].isna().tolist() == [False, False, True, False]
    assert points["speed"].iloc[3] == pytest.approx(102.2)  # "102.2 or more": a value
    assert r.report["values_blanked"] == {
        "speed 102.3 (AIS: not available)": 1,
        "course 360 (AIS: not available)": 1,
    }


def test_sog_named_column_in_a_generic_file_is_ais(write):
    text = (
        "track_id,time,lon,lat,sog_knots,cog\n"
        "7,2024-05-01T08:00:00Z,12.0,56.0,102.3,10\n"
        "7,2024-05-01T08:01:00Z,12.001,56.001,9.0,10\n"
    )
    r = read_points(write("g.csv", text))
    assert r.points["speed"].isna().tolist() == [True, False]
    assert r.report["values_blanked"] == {"speed 102.3 (AIS: not available)": 1}


def test_a_radars_speed_of_102_3_kn_is_kept(write):
    """A radar's speed column (not SOG, not an AIS layout): 102.3 kn is the number the
    radar measured (a helicopter, a fast boat's glint); cleaning judges it, not the reader."""
    text = (
        "SendShipNO,SendTime,nNO,lon,lat,speed,course\n"
        "R1,1714550400,7,12.0,56.0,102.3,10\n"
        "R1,1714550410,7,12.001,56.001,9.0,10\n"
    )
    r = read_points(write("radar.csv", text))
    assert r.points["speed"].tolist() == [102.3, 9.0]
    assert r.report["values_blanked"] == {}


def test_na_position_in_any_layout_has_its_own_reason(write):
    text = (
        "batch,time,lon,lat\n"
        "7,2024-05-01T08:00:00Z,181,91\n"
        "7,2024-05-01T08:01:00Z,12.0,91\n"
        "7,2024-05-01T08:02:00Z,12.0,95\n"
        "7,2024-05-01T08:03:00Z,12.0,56.0\n"
    )
    r = read_points(write("p.csv", text))
    assert r.quarantine["reason"].tolist() == [NO_POSITION, NO_POSITION, "lat out of range"]


@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.lists(
        st.tuples(
            st.sampled_from(["56.5", "-33.25", "91", "90", "95"]),
            st.sampled_from(["12.5", "-179.9", "181", "180"]),
            st.sampled_from(["0", "9.5", "102.2", "102.3", "102.30", "-", ""]),
            st.sampled_from(["0", "45.5", "359.9", "360", "360.0", "511", ""]),
        ),
        min_size=1,
        max_size=40,
    )
)
def test_every_row_is_a_point_or_quarantined_and_no_na_value_survives(tmp_path_factory, rows):
    path = tmp_path_factory.mktemp("na") / "ais.csv"
    path.write_text(_ais_text(rows), encoding="utf-8")
    r = read_points(path)
    rep = r.report
    assert rep["rows_imported"] + rep["rows_quarantined"] == len(rows)
    na_pos = [lat == "91" or lon == "181" for lat, lon, _, _ in rows]
    bad_pos = [lat == "95" for lat, _, _, _ in rows]
    assert rep["rows_quarantined"] == sum(a or b for a, b in zip(na_pos, bad_pos, strict=True))
    assert rep["quarantine_reasons"].get(NO_POSITION, 0) == sum(na_pos)
    speed = r.points["speed"].to_numpy()
    course = r.points["course"].to_numpy()
    assert not np.any(np.isclose(speed, 102.3))
    assert not np.any(course >= 360)
    kept = [
        (s, c)
        for (s, c), a, b in zip([x[2:] for x in rows], na_pos, bad_pos, strict=True)
        if not (a or b)
    ]
    assert np.isnan(speed).sum() == sum(s in ("102.3", "102.30", "-", "") for s, _ in kept)


def test_cli_round_trip_import_export_like_reimport_gives_the_same_rows(write, tmp_path):
    """import -> export --like the original -> import again: the same canonical rows (the
    blanked values are written empty, not as the AIS code; the n/a position stays out)."""
    from wakeline.app.cli import main

    rows = [
        ("56.0", "12.0", "9.5", "45.0"),
        ("56.001", "12.001", "102.3", "45.0"),
        ("91", "181", "102.3", "360.0"),
        ("56.002", "12.002", "9.5", "360.0"),
    ]
    src = write("ais.csv", "Radar track export 2024-05-01\n" + _ais_text(rows))
    first, like, second = tmp_path / "c.csv", tmp_path / "like.csv", tmp_path / "c2.csv"
    assert main(["import", str(src), "-o", str(first)]) == 0
    assert main(["export", str(first), "-o", str(like), "--like", str(src)]) == 0
    assert like.read_text().splitlines()[0] == "Radar track export 2024-05-01"
    assert main(["import", str(like), "-o", str(second)]) == 0
    assert first.read_bytes() == second.read_bytes()
    assert len(pd.read_csv(second)) == 3

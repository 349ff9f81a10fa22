"""Latitude and longitude under each other's names: warned of, never swapped silently."""

import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.io import import_to_csv, nothing_imported, read_points


def _generic(values: list[tuple[float, float]], header: str = "track_id,time,lat,lon") -> str:
    lines = [header]
    for k, (a, b) in enumerate(values):
        lines.append(f"7,2024-05-01T08:{k // 60:02d}:{k % 60:02d}Z,{a:.5f},{b:.5f}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("streamed", [False, True])
def test_longitudes_under_lat_are_named_and_the_fix_given(write, tmp_path, streamed):
    """Tester: a file whose 'lat' holds 120-131 and 'lon' 20-30. Every row was
    quarantined as 'lat out of range' with a hint about projections; the message now says
    the columns look swapped and gives the --map that reads them; nothing is swapped."""
    values = [(120 + k * 0.1, 20 + k * 0.1) for k in range(100)]
    path = write("swapped.csv", _generic(values))
    if streamed:
        r = import_to_csv(path, tmp_path / "o.csv")
    else:
        r = read_points(path)
    assert r.report["rows_imported"] == 0
    assert r.report["lat_beyond_90_lon_within"] == 100
    assert any("the columns look swapped" in w for w in r.report["warnings"])
    msg = nothing_imported(r.report)
    assert "try --map lat=lon --map lon=lat" in msg
    fixed = read_points(path, mapping=["lat=lon", "lon=lat"])
    assert fixed.report["rows_imported"] == 100
    assert fixed.points["lat"].iloc[0] == pytest.approx(20.0)
    assert not any("swapped" in w for w in fixed.report["warnings"])


def test_a_few_rows_beyond_90_do_not_warn(write):
    values = [(56 + k * 1e-3, 12 + k * 1e-3) for k in range(20)]
    values[3] = (123.0, 12.0)  # one damaged row
    r = read_points(write("one.csv", _generic(values)))
    assert r.report["rows_quarantined"] == 1
    assert not any("swapped" in w for w in r.report["warnings"])


def test_a_known_layout_with_its_position_columns_the_other_way_round_warns(
    write, capsys, tmp_path
):
    """Both in range (LON holding 56°N, LAT 12°E): not decidable from the values; the
    MarineCadastre layout has LAT before LON, so the reversed order is named."""
    text = "MMSI,BaseDateTime,LON,LAT,SOG,COG\n" + "".join(
        f"219000001,2024-05-01T08:00:{k:02d},{56 + k * 1e-3:.4f},{12 + k * 1e-3:.4f},9.5,45\n"
        for k in range(10)
    )
    path = write("mc.csv", text)
    r = read_points(path)
    assert r.report["rows_imported"] == 10  # not guessed: imported as the names say
    assert r.points["lon"].iloc[0] == pytest.approx(56.0)
    assert any("the position columns come as LON, LAT" in w for w in r.report["warnings"])
    assert main(["import", str(path), "-o", str(tmp_path / "o.csv")]) == 0
    assert "--map lat=LON --map lon=LAT" in capsys.readouterr().err
    usual = write("ok.csv", text.replace("LON,LAT", "LAT,LON", 1))
    assert not any("position columns" in w for w in read_points(usual).report["warnings"])


def test_a_generic_file_in_either_order_does_not_warn(write):
    for header in ("track_id,time,lat,lon", "track_id,time,lon,lat"):
        r = read_points(write("g.csv", _generic([(30.0, 30.0), (30.1, 30.1)], header)))
        assert r.report["warnings"] == []


@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.lists(
        st.tuples(st.floats(-180, 180, allow_nan=False), st.floats(-180, 180, allow_nan=False)),
        min_size=1,
        max_size=40,
    )
)
def test_the_swap_warning_follows_the_values(tmp_path_factory, values):
    path = tmp_path_factory.mktemp("s") / "s.csv"
    path.write_text(_generic(values), encoding="utf-8")
    r = read_points(path)
    rep = r.report
    assert rep["rows_imported"] + rep["rows_quarantined"] == len(values)
    s = pd.Series([round(a, 5) for a, _ in values])
    b = pd.Series([round(x, 5) for _, x in values])
    expect = int(((s.abs() > 90) & (s.abs() <= 180) & (b.abs() <= 90)).sum())
    assert rep["lat_beyond_90_lon_within"] == expect
    warned = any("the columns look swapped" in w for w in rep["warnings"])
    assert warned == (expect > len(values) / 2)
    # never swapped: every point is where its names put it
    assert (r.points["lat"].abs() <= 90).all()
    if warned:  # a file judged swapped keeps no row at a mirrored place (D2)
        assert len(r.points) == 0 and rep["rows_quarantined"] == len(values)


def _half_swapped(n: int = 100, in_range: int = 40, quoted: bool = False) -> str:
    """Lat/lon swapped in every row; ``in_range`` rows have a longitude within ±90 (so
    their lat "fits"), the others a longitude beyond 90 (out of range as lat)."""
    q = '"' if quoted else ""
    lines = ["track_id,time,lat,lon"]
    for k in range(n):
        lon = -80.0 - k * 0.01 if k < in_range else 120.0 + k * 0.01
        lines.append(
            f"{q}{k % 7}{q},2024-05-01T08:{k // 60:02d}:{k % 60:02d}Z,{lon:.5f},{30.5:.5f}"
        )
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("how", ["whole", "streamed", "pieces"])
def test_a_file_judged_swapped_keeps_no_row_at_a_mirrored_place(write, tmp_path, how, capsys):
    """Operator test 7, D2: 2,098 of 2,999 rows were quarantined as 'lat out of range'
    and the other 901 (longitudes between -90 and -76) imported at latitudes -76 to -90
    with exit 0. Now every row of a file judged swapped is quarantined, counted, and the
    import fails naming the --map; read with it, every row is a point."""
    path = write("half.csv", _half_swapped(quoted=how == "pieces"))
    if how == "whole":
        r = read_points(path)
    else:
        r = import_to_csv(path, tmp_path / "o.csv")
    rep = r.report
    assert rep["rows_imported"] == 0 and rep["rows_quarantined"] == 100
    assert rep["quarantine_reasons"] == {
        "lat out of range": 60,
        "in a file whose lat and lon columns look swapped": 40,
    }
    assert main(["import", str(path), "-o", str(tmp_path / "c.csv")]) == 2
    assert "--map lat=lon --map lon=lat" in capsys.readouterr().err
    fixed = read_points(path, mapping=["lat=lon", "lon=lat"])
    assert len(fixed.points) == 100 and (fixed.points["lat"] == 30.5).all()


def test_batch_keeps_no_row_of_a_swapped_file(write, tmp_path, capsys):
    pytest.importorskip("dask.dataframe")
    import json

    from wakeline.core.pipeline import Pipeline

    good = write("good.csv", _generic([(30.0 + k * 1e-3, 20.0) for k in range(30)]))
    half = write("half.csv", _half_swapped())
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "o"
    main(["batch", str(pipe), str(good), str(half), "-o", str(out)])
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 130 and rep["quarantined"] == 100  # none of half.csv kept
    capsys.readouterr()


def _two_sensors(sensor_column: bool = True, quoted: bool = False) -> str:
    """R1: lat/lon swapped in all 300 rows (200 of them out of range as lat, 100 within:
    they would be mirrored); R2: 60 rows with its columns right. Most of the file's rows
    look swapped."""
    q = '"' if quoted else ""
    lines = ["sensor,track_id,time,lat,lon" if sensor_column else "track_id,time,lat,lon"]
    for k in range(360):
        own, tid = ("R1", 1) if k < 300 else ("R2", 2)
        if own == "R1":
            lat, lon = (-80.0 - k * 0.01 if k < 100 else 120.0 + k * 0.01), 30.5
        else:
            lat, lon = 30.5 + k * 1e-4, 120.0 + k * 1e-4
        head = f"{q}{own}{q},{tid}" if sensor_column else f"{q}{own}{q}"
        lines.append(
            f"{head},2024-05-01T{k // 3600:02d}:{k // 60 % 60:02d}:{k % 60:02d}Z,{lat:.5f},{lon:.5f}"
        )
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("how", ["whole", "streamed", "pieces"])
@pytest.mark.parametrize("sensor_column", [True, False])
def test_swapped_columns_are_judged_per_sensor_or_track(
    write, tmp_path, how, sensor_column, monkeypatch
):
    """Review h209: judged over the whole file, a sensor whose columns are right was
    quarantined with the one whose columns are swapped (and with fewer rows swapped a
    swapped sensor's in-range rows were kept, mirrored). Judged per sensor (per track
    without a sensor column): R1 quarantined, R2 read; the warning names R1."""
    from wakeline.core.io import reader

    if how == "pieces":
        monkeypatch.setattr(reader, "STREAM_BYTES", 2048)
    elif how == "streamed":
        monkeypatch.setattr(reader, "STREAM_BYTES", 4096)
    path = write("two.csv", _two_sensors(sensor_column, quoted=how == "pieces"))
    r = read_points(path) if how == "whole" else import_to_csv(path, tmp_path / "o.csv")
    rep = r.report
    assert rep["rows_imported"] == 60 and rep["rows_quarantined"] == 300
    assert rep["quarantine_reasons"] == {
        "lat out of range": 200,
        "in a file whose lat and lon columns look swapped": 100,
    }
    kind = "sensor" if sensor_column else "track"
    warned = [w for w in rep["warnings"] if "look swapped" in w]
    assert len(warned) == 1 and f"1 {kind}(s) of 2 ({kind} R1)" in warned[0]
    if how == "whole":
        assert (r.points["lat"] < 90).all() and set(
            r.points["sensor" if sensor_column else "batch"]
        ) == {"R2"}

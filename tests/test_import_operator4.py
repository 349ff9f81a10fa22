"""Operator test 4 (h168): import messages an operator can act on — times cut to the
minute, a decimal comma's example from the file, a header alone, a Date/Time column by
its values, 12-hour AM/PM clocks as a US file's sign, a camera's bearing rows in a file
read as tracks, and a file whose last line is cut short."""

import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import read_points

HEALTH = [HealthCheck.function_scoped_fixture]


def _write(tmp_path, name: str, lines: list[str], newline: str = "\n"):
    path = tmp_path / name
    path.write_text(newline.join(lines) + newline, encoding="utf-8")
    return path


def _minute_lines(per_minute: list[int], seconds: bool) -> list[str]:
    """One ship moving east, ``per_minute[k]`` rows in minute k (times cut to the minute,
    or with their seconds)."""
    lines, i = ["mmsi,timestamp,lat,lon"], 0
    for minute, n in enumerate(per_minute):
        for j in range(n):
            sec = f":{(j * 60 // n):02d}" if seconds else ""
            hh, mm = divmod(minute, 60)
            lines.append(f"219000001,2023-03-01 {hh:02d}:{mm:02d}{sec},57.6,{11.8 + i * 1e-4:.4f}")
            i += 1
    return lines


@settings(max_examples=25, deadline=None, suppress_health_check=HEALTH)
@given(st.lists(st.integers(1, 6), min_size=2, max_size=40), st.booleans())
def test_times_cut_to_the_minute_are_named(tmp_path, per_minute, seconds):
    path = _write(tmp_path, "m.csv", _minute_lines(per_minute, seconds))
    rep = read_points(path).report
    shared = sum(n - 1 for n in per_minute)
    said = [w for w in rep["warnings"] if "were the seconds lost" in w]
    if seconds and any(n > 1 for n in per_minute) or not shared:
        assert not said  # seconds there, or one row a minute: nothing to say
    else:
        assert len(said) == 1
        assert f"whole minutes and {shared:,} rows share a minute" in said[0]


def test_times_cut_to_the_minute_on_the_cli(tmp_path, capsys):
    path = _write(tmp_path, "m.csv", _minute_lines([3, 3, 2], seconds=False), "\r\n")
    assert main(["import", str(path), "-o", str(tmp_path / "o.csv")]) == 0
    err = capsys.readouterr().err
    assert "warning: the times in 'timestamp' are whole minutes and 5 rows share" in err
    assert "Excel saves m/d/yyyy h:mm" in err


@settings(max_examples=25, deadline=None, suppress_health_check=HEALTH)
@given(st.lists(st.integers(0, 999_999), min_size=3, max_size=20))
def test_the_decimal_comma_example_comes_from_the_file(tmp_path, frac):
    lines = ["mmsi;time;lat;lon"]
    for k, f in enumerate(frac):
        lines.append(f"219000001;2023-03-01T00:{k // 60:02d}:{k % 60:02d}Z;55,{f:06d};12,{k:04d}")
    path = _write(tmp_path, "c.csv", lines)
    rep = read_points(path).report
    said = [w for w in rep["warnings"] if "decimal comma" in w]
    assert len(said) == 1 and "57,6671" not in said[0]
    example = re.search(r"decimal numbers \((\S+) as (\S+)\)$", said[0])
    assert example and example.group(1) in path.read_text()
    assert example.group(2) == example.group(1).replace(",", ".")


def test_a_header_alone_gives_the_error_alone(tmp_path, capsys):
    path = _write(tmp_path, "h.csv", ["mmsi,time,lat,lon"])
    assert main(["import", str(path), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert not err.startswith("imported") and err.count("\n") == 1
    assert "no data rows (a header only?)" in err


def _ampm_lines(n: int = 30) -> list[str]:
    out = ["MMSI,Date/Time,Lat,Lon"]
    for k in range(n):
        h = 12 if k < 10 else 1
        out.append(f"219000001,3/1/2023 {h}:{k:02d}:46 {'AM' if k < 20 else 'PM'},57.6,11.{k:04d}")
    return out


def test_a_date_time_column_is_suggested_by_its_values(tmp_path):
    path = _write(tmp_path, "us.csv", _ampm_lines())
    with pytest.raises(InputError, match=r"the time may be in 'Date/Time': --map time=Date/Time"):
        read_points(path)


def test_am_pm_clocks_read_month_first(tmp_path):
    path = _write(tmp_path, "us.csv", _ampm_lines())
    res = read_points(path, mapping={"time": "Date/Time"})
    times = res.points["time"]
    assert (times.dt.month == 3).all() and (times.dt.day == 1).all()  # 1 March, not 3 Jan
    assert "month-first (assumed from the 12-hour AM/PM clock" in res.report["date_order"]
    assert any("12-hour clock with AM/PM" in w for w in res.report["warnings"])
    # 1/1/2023 reads the same either way: nothing to assume, nothing said
    same = [line.replace("3/1/2023", "1/1/2023") for line in _ampm_lines()]
    res = read_points(_write(tmp_path, "same.csv", same), mapping={"time": "Date/Time"})
    assert not any("12-hour clock" in w for w in res.report["warnings"])
    # a day above 12 shows day first: AM/PM does not override it
    lines = _ampm_lines() + ["219000001,13/1/2023 1:00:00 PM,57.6,11.9"]
    res = read_points(_write(tmp_path, "eu.csv", lines), mapping={"time": "Date/Time"})
    assert (res.points["time"].dt.month == 1).all()


def test_camera_rows_in_a_detection_file_read_as_tracks(tmp_path, capsys):
    head = (
        "scenario,scan,time,sensor_id,sensor,own_north,own_east,k,meas_north,meas_east,bearing_rad"
    )
    lines = [head]
    for k in range(20):
        t = 1620114891.5 + k
        lines.append(f"2,{k},{t},1,radar,-16.6,-390.4,0,{10 + k},{-400 - k},")
        lines.append(f"2,{k},{t},4,eo,-16.6,-390.4,0,,,0.42")
        lines.append(f"2,{k},{t},4,eo,-16.6,-390.4,1,,,1.07")
    lines.append(f"2,20,{1620114911.5},5,ir,-16.6,-390.4,,,,")  # an empty scan
    path = _write(tmp_path, "det.csv", lines)
    out = tmp_path / "o.csv"
    assert main(["import", str(path), "-o", str(out), "--origin", "63.4389,10.3990"]) == 0
    err = capsys.readouterr().err
    assert "40 of 61 rows carry a bearing ('bearing_rad') and no position" in err
    assert "`wakeline bearing`" in err and "File > Open bearings" in err
    assert "empty scans (nothing detected): 1" in err
    assert "missing east" not in err
    assert "batch=sensor_id" not in err  # sensor_id names the sensor: no track id


def test_a_last_line_cut_short_is_named(tmp_path):
    lines = [
        "mmsi,time,lat,lon,speed",
        *(f"219000001,2023-03-01T00:00:{k:02d}Z,57.6,11.{k:04d},10" for k in range(20)),
    ]
    lines.append("219000001,2023-03-01T00:00:30Z,57.6")
    path = _write(tmp_path, "cut.csv", lines)
    rep = read_points(path).report
    said = [w for w in rep["warnings"] if "the file's last line" in w]
    assert said == [
        "line 22, the file's last line, has 3 of 5 fields: the file may be cut short (still "
        "being written or copied when it was read); open it again once it is complete"
    ]
    # a short row inside the file is no cut
    inside = lines[:5] + [lines[-1]] + lines[5:-1]
    rep = read_points(_write(tmp_path, "mid.csv", inside)).report
    assert not [w for w in rep["warnings"] if "the file's last line" in w]

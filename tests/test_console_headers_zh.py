"""Chinese radar/plotter console headers for longitude and latitude (h191, D-import-11):
东经 / 北纬 and their unit, hemisphere and target forms are read as lon / lat."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.io import read_points
from wakeline.core.io.formats import SYNONYMS, normalize_header

LON_HEADERS = [
    "东经",
    "东经(度)",
    "东经（度）",
    "东经(°)",
    "东经°",
    "东经(E)",
    "东经E",
    "经度(°)",
    "经度°",
    "经度E",
    "经度_E",
    "目标经度",
    "目标经度(度)",
]
LAT_HEADERS = [
    "北纬",
    "北纬(度)",
    "北纬（度）",
    "北纬(°)",
    "北纬°",
    "北纬(N)",
    "北纬N",
    "纬度(°)",
    "纬度°",
    "纬度N",
    "纬度_N",
    "目标纬度",
    "目标纬度(度)",
]


@pytest.mark.parametrize("header", LON_HEADERS)
def test_lon_alias(write, header):
    text = f"目标批号,时刻,{header},纬度\n1,2026-12-05 08:00:00,122.41,30.5\n"
    r = read_points(write("lon.csv", text.encode("gb18030")))
    assert r.report["columns"]["lon"] == header
    assert r.points["lon"].iloc[0] == pytest.approx(122.41)


@pytest.mark.parametrize("header", LAT_HEADERS)
def test_lat_alias(write, header):
    text = f"目标批号,时刻,经度,{header}\n1,2026-12-05 08:00:00,122.41,30.5\n"
    r = read_points(write("lat.csv", text.encode("gb18030")))
    assert r.report["columns"]["lat"] == header
    assert r.points["lat"].iloc[0] == pytest.approx(30.5)


def test_operator_console_b_header(write):
    """Operator test 6's console B: every column by name, no --map."""
    header = "目标批号,时刻,东经,北纬,速度(节),航向(度)"
    rows = "\r\n".join(
        f"{i % 3},2026-12-05 08:00:{i:02d},122.{i:02d},30.{i:02d},12.5,90" for i in range(20)
    )
    r = read_points(write("b.csv", (header + "\r\n" + rows + "\r\n").encode("gb18030")))
    cols = r.report["columns"]
    assert cols["lon"] == "东经" and cols["lat"] == "北纬"
    assert cols["batch"] == "目标批号" and cols["time"] == "时刻"
    assert cols["speed"] == "速度(节)" and cols["course"] == "航向(度)"
    assert len(r.points) == 20 and len(r.quarantine) == 0


def test_no_alias_is_taken_by_another_field():
    """The new names belong to lon/lat only (东 and 北 stay the plane's east/north)."""
    new = {"东经", "北纬", "目标经度", "目标纬度", "经度e", "纬度n", "经度°", "纬度°"}
    for field, names in SYNONYMS.items():
        keys = {normalize_header(n) for n in names}
        if field == "lon":
            assert {"东经", "目标经度", "经度e", "经度°"} <= keys
        elif field == "lat":
            assert {"北纬", "目标纬度", "纬度n", "纬度°"} <= keys
        else:
            assert not keys & new, field


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    lon_header=st.sampled_from(LON_HEADERS),
    lat_header=st.sampled_from(LAT_HEADERS),
    lons=st.lists(st.floats(-179.9, 179.9, allow_nan=False), min_size=1, max_size=30),
    seed=st.integers(0, 2**16),
    crlf=st.booleans(),
)
def test_values_under_console_headers_are_read_exactly(
    write, lon_header, lat_header, lons, seed, crlf
):
    """Any console header pair reads every row, each value as written (nothing lost)."""
    rng = np.random.default_rng(seed)
    lats = rng.uniform(-89.9, 89.9, len(lons))
    end = "\r\n" if crlf else "\n"
    lines = [f"批号,时间,{lon_header},{lat_header}"]
    for i, (x, y) in enumerate(zip(lons, lats, strict=True)):
        lines.append(f"{i % 4},2026-12-05 08:{i // 60:02d}:{i % 60:02d},{x:.6f},{y:.6f}")
    r = read_points(write("p.csv", (end.join(lines) + end).encode("gb18030")))
    assert r.report["columns"]["lon"] == lon_header
    assert r.report["columns"]["lat"] == lat_header
    assert len(r.points) == len(lons)
    assert len(r.quarantine) == 0
    want_lon = np.sort(np.round(np.asarray(lons), 6))
    want_lat = np.sort(np.round(lats, 6))
    assert np.allclose(np.sort(r.points["lon"].to_numpy()), want_lon, atol=1e-9)
    assert np.allclose(np.sort(r.points["lat"].to_numpy()), want_lat, atol=1e-9)

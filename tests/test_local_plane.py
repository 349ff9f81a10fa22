"""Positions in metres on a local plane (a radar's x/y about its site, a NED frame's
east/north, an ownship's offsets): read with ``--origin LAT,LON`` into lon/lat, every row
a point or a quarantine row, and written back as they came by ``export --like``."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import real_file
from wakeline.core.errors import InputError
from wakeline.core.geo import haversine_m, to_local
from wakeline.core.io import read_points
from wakeline.core.io.export_like import write_layout
from wakeline.core.io.layout import load_layout
from wakeline.core.io.reader import PLANE_TOO_FAR, import_to_csv, inspect_file

ORIGIN = (63.4389029083, 10.39908278)  # Autoferry's "Piren" frame
ORIGIN_TEXT = f"{ORIGIN[0]},{ORIGIN[1]}"


def _track(n: int = 60, seed: int = 0) -> pd.DataFrame:
    """Two boats in the harbour, 2 s apart, as lon/lat (the truth the metres came from)."""
    rng = np.random.default_rng(seed)
    t = 1_620_000_000 + 2.0 * np.arange(n)
    rows = []
    for boat, (lon0, lat0, vx, vy) in enumerate(
        ((10.395, 63.437, 3.0, 1.0), (10.402, 63.441, -2.0, -2.5)), start=1
    ):
        dx = np.cumsum(np.full(n, vx * 2.0)) + rng.normal(0, 0.5, n)
        dy = np.cumsum(np.full(n, vy * 2.0)) + rng.normal(0, 0.5, n)
        lat = lat0 + dy / 111_195.0
        lon = lon0 + dx / (111_195.0 * np.cos(np.radians(lat0)))
        rows.append(pd.DataFrame({"track": boat, "time": t, "lon": lon, "lat": lat}))
    return pd.concat(rows, ignore_index=True)


def _write_xy(df: pd.DataFrame, path, names=("x", "y"), own=None, lat0_lon0=ORIGIN) -> None:
    east, north = to_local(df["lon"], df["lat"], lat0_lon0[1], lat0_lon0[0])
    out = pd.DataFrame({"time": df["time"], "track": df["track"]})
    if own is not None:  # the ownship's place in the frame; the file holds what is left
        out[own[0]], out[own[1]] = 25.0, -40.0
        east, north = east - 25.0, north + 40.0
    out[names[0]], out[names[1]] = np.round(east, 3), np.round(north, 3)
    out.to_csv(path, index=False)


def _error_m(points: pd.DataFrame, truth: pd.DataFrame) -> np.ndarray:
    p = points.sort_values(["batch", "time"]).reset_index(drop=True)
    t = truth.sort_values(["track", "time"]).reset_index(drop=True)
    return haversine_m(p["lon"], p["lat"], t["lon"], t["lat"])


def test_x_y_metres_with_an_origin_read_as_the_positions_they_were(tmp_path):
    truth = _track()
    path = tmp_path / "radar_xy.csv"
    _write_xy(truth, path)
    res = read_points(path, origin=ORIGIN_TEXT)
    assert res.report["rows_quarantined"] == 0 and res.report["rows_imported"] == len(truth)
    assert res.report["plane_origin"] == list(ORIGIN)
    assert res.report["columns"]["east"] == "x" and res.report["columns"]["north"] == "y"
    assert _error_m(res.points, truth).max() < 0.01  # written to the millimetre
    # the file's own metres travel on as extra columns, as they came
    raw = pd.read_csv(path, dtype=str)
    assert sorted(res.points["x"]) == sorted(raw["x"]) and sorted(res.points["y"]) == sorted(
        raw["y"]
    )


def test_without_an_origin_the_message_names_the_columns_and_the_flag(tmp_path):
    path = tmp_path / "radar_xy.csv"
    _write_xy(_track(), path)
    with pytest.raises(InputError) as exc:
        read_points(path)
    text = str(exc.value)
    assert "'x' east" in text and "'y' north" in text and "--origin LAT,LON" in text
    info = inspect_file(path)  # the import dialog: the same problem, the plane noticed
    assert info["plane"] and "--origin" in info["problem"]
    assert inspect_file(path, origin=ORIGIN_TEXT)["problem"] is None


@pytest.mark.parametrize(
    "bad", ["63.4", "63.4,10.4,5", "north,east", "95,10", "63,200", 63.4, (63.4,)]
)
def test_a_bad_origin_is_refused_with_the_form_it_takes(tmp_path, bad):
    path = tmp_path / "radar_xy.csv"
    _write_xy(_track(), path)
    with pytest.raises(InputError, match="--origin"):
        read_points(path, origin=bad)


def test_chinese_headers_and_ownship_offsets(tmp_path):
    truth = _track(seed=1)
    path = tmp_path / "本船.csv"
    _write_xy(truth, path, names=("东", "北"), own=("own_east", "own_north"))
    res = read_points(path, origin=ORIGIN_TEXT)
    cols = res.report["columns"]
    assert (cols["east"], cols["north"]) == ("东", "北")
    assert (cols["east_offset"], cols["north_offset"]) == ("own_east", "own_north")
    assert _error_m(res.points, truth).max() < 0.01


def test_lon_lat_win_over_x_y_and_an_unused_origin_is_said(tmp_path):
    truth = _track()
    path = tmp_path / "both.csv"
    df = truth.rename(columns={"track": "batch"}).assign(x=1.0, y=2.0)
    df.to_csv(path, index=False)
    plain = read_points(path)
    assert "east" not in plain.report["columns"]
    assert {"x", "y"} <= set(plain.report["extra_columns"])
    given_origin = read_points(path, origin=ORIGIN_TEXT)
    pd.testing.assert_frame_equal(given_origin.points, plain.points)
    assert any("--origin" in w and "not used" in w for w in given_origin.report["warnings"])


def test_a_plane_column_mapped_on_a_lon_lat_file_is_carried_and_written_back(tmp_path):
    # --map east=px on a file with lon/lat: px was taken by the mapping, used for nothing
    # and dropped from the points (export --like then wrote it blank)
    path = tmp_path / "both.csv"
    df = _track(n=5).rename(columns={"track": "batch"}).assign(px=np.arange(10) * 1.5)
    df.to_csv(path, index=False)
    res = read_points(path, mapping=["east=px"])
    assert res.points["px"].astype(float).tolist() == (np.arange(10) * 1.5).tolist()
    assert any(w.startswith("--map east=px was not used") for w in res.report["warnings"])
    out = tmp_path / "out.csv"
    write_layout(res.points, load_layout(path, mapping={"east": "px"}), out)
    assert out.read_bytes() == path.read_bytes()


def test_rows_without_metres_are_quarantined_and_counted(tmp_path):
    path = tmp_path / "gaps.csv"
    _write_xy(_track(n=10), path)
    lines = path.read_text().splitlines()
    lines[3] = lines[3].rsplit(",", 2)[0] + ",,5.0"  # no east
    lines[5] = lines[5].rsplit(",", 1)[0] + ",abc"  # north not a number
    path.write_text("\n".join(lines) + "\n")
    res = read_points(path, origin=ORIGIN_TEXT)
    rep = res.report
    assert rep["rows_read"] == 20 == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["quarantine_reasons"] == {
        "missing east ('x', metres)": 1,
        "unparsable north ('y', metres)": 1,
    }
    assert sorted(res.quarantine["line"]) == [4, 6]


def test_streamed_import_gives_the_same_points(tmp_path):
    path = tmp_path / "radar_xy.csv"
    _write_xy(_track(n=200), path, own=("own_x", "own_y"))
    whole = read_points(path, origin=ORIGIN_TEXT)
    out = tmp_path / "out.csv"
    streamed = import_to_csv(path, out, origin=ORIGIN_TEXT)
    assert streamed.report["plane_origin"] == list(ORIGIN)
    again = read_points(out)
    np.testing.assert_allclose(again.points["lon"], whole.points["lon"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(again.points["lat"], whole.points["lat"], rtol=0, atol=1e-12)


@pytest.mark.parametrize("own", [None, ("own_east", "own_north")])
def test_export_like_writes_the_metres_back_as_they_came(tmp_path, own):
    path = tmp_path / "radar_xy.csv"
    _write_xy(_track(), path, own=own)
    res = read_points(path, origin=ORIGIN_TEXT)
    layout = load_layout(path, origin=ORIGIN_TEXT)
    assert layout.origin == ORIGIN
    out = tmp_path / "back.csv"
    write_layout(res.points, layout, out)
    assert out.read_text() == path.read_text()


@settings(max_examples=40, deadline=None)
@given(
    lat0=st.floats(-80, 80),
    lon0=st.floats(-180, 180),
    east=st.lists(st.floats(-50_000, 50_000), min_size=2, max_size=20),
    north=st.floats(-50_000, 50_000),
)
def test_any_origin_and_metres_come_back_on_the_plane(tmp_path_factory, lat0, lon0, east, north):
    path = tmp_path_factory.mktemp("plane") / "p.csv"
    e = np.round(np.asarray(east), 3)
    n = np.round(north + np.arange(len(e)) * 10.0, 3)
    pd.DataFrame({"t": 1e9 + np.arange(len(e)), "id": 7, "x": e, "y": n}).to_csv(path, index=False)
    pts = read_points(path, origin=f"{lat0!r},{lon0!r}").points
    x, y = to_local(pts["lon"], pts["lat"], lon0, lat0)
    np.testing.assert_allclose(x, e, rtol=0, atol=1e-5)
    np.testing.assert_allclose(y, n, rtol=0, atol=1e-5)


def test_autoferry_detections_open_in_the_frame_of_their_truth():
    """Autoferry's lidar detections (metres from the ownship, which is itself in metres
    from "Piren") land 4.9 m median from the GNSS truth read the same way (SOURCE.md)."""
    det = real_file("autoferry-fusion", "detections.csv.gz")
    truth = real_file("autoferry-fusion", "ground_truth.csv.gz")
    d = read_points(det, origin=ORIGIN_TEXT)
    rep = d.report
    assert rep["rows_read"] == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["sensors"] == {"lidar": 3078, "radar": 2952}  # the cameras give bearings
    g = read_points(truth, origin=ORIGIN_TEXT).points
    lidar = d.points[d.points["sensor"] == "lidar"]
    m = lidar.merge(
        g[["scenario", "scan", "lon", "lat"]], on=["scenario", "scan"], suffixes=("", "_t")
    )
    m["d"] = haversine_m(m["lon"], m["lat"], m["lon_t"], m["lat_t"])
    nearest = m.groupby(["scenario", "scan", "k"])["d"].min()
    assert 4.0 < float(nearest.median()) < 6.0


def _write_polar(df, path, names=("range", "bearing"), scale=1.0, radians=False) -> None:
    """A radar site's export: range and true bearing of each plot from the origin."""
    east, north = to_local(df["lon"], df["lat"], ORIGIN[1], ORIGIN[0])
    b = np.mod(np.arctan2(east, north), 2 * np.pi)
    out = pd.DataFrame({"time": df["time"], "track": df["track"]})
    out[names[0]] = np.round(np.hypot(east, north) / scale, 6)
    out[names[1]] = np.round(b if radians else np.degrees(b), 7)
    out.to_csv(path, index=False)


@pytest.mark.parametrize(
    "names, scale, radians",
    [
        (("range", "bearing"), 1.0, False),
        (("Range (NM)", "Azimuth"), 1852.0, False),
        (("range_km", "bearing_rad"), 1000.0, True),
        (("距离(海里)", "方位"), 1852.0, False),
    ],
)
def test_range_and_bearing_from_the_site_in_the_units_the_header_names(
    tmp_path, names, scale, radians
):
    truth = _track(seed=2)
    path = tmp_path / "site.csv"
    _write_polar(truth, path, names, scale, radians)
    with pytest.raises(InputError, match="range and bearing from a site"):
        read_points(path)
    res = read_points(path, origin=ORIGIN_TEXT)
    assert res.report["rows_quarantined"] == 0
    assert (res.report["columns"]["range"], res.report["columns"]["bearing"]) == names
    assert _error_m(res.points, truth).max() < 0.02
    layout = load_layout(path, origin=ORIGIN_TEXT)
    out = tmp_path / "back.csv"
    write_layout(res.points, layout, out)
    back = pd.read_csv(out)
    orig = pd.read_csv(path)
    np.testing.assert_allclose(back[names[0]], orig[names[0]], rtol=0, atol=2e-6)
    np.testing.assert_allclose(back[names[1]], orig[names[1]], rtol=0, atol=2e-7)


def test_x_y_in_kilometres_are_read_as_kilometres(tmp_path):
    truth = _track(seed=3)
    path = tmp_path / "km.csv"
    east, north = to_local(truth["lon"], truth["lat"], ORIGIN[1], ORIGIN[0])
    pd.DataFrame(
        {
            "time": truth["time"].astype("int64"),
            "track": truth["track"],
            "x_km": east / 1e3,
            "y_km": north / 1e3,
        }
    ).to_csv(path, index=False, float_format="%.9f")
    res = read_points(path, origin=ORIGIN_TEXT)
    assert _error_m(res.points, truth).max() < 0.01
    out = tmp_path / "back.csv"
    write_layout(res.points, load_layout(path, origin=ORIGIN_TEXT), out)
    assert out.read_text() == path.read_text()


def test_a_negative_range_is_quarantined(tmp_path):
    path = tmp_path / "site.csv"
    _write_polar(_track(n=5), path)
    lines = path.read_text().splitlines()
    head, *rest = lines[2].split(",")
    lines[2] = ",".join([head, rest[0], "-" + rest[1], rest[2]])
    path.write_text("\n".join(lines) + "\n")
    res = read_points(path, origin=ORIGIN_TEXT)
    assert res.report["quarantine_reasons"] == {"range negative ('range')": 1}
    assert res.report["rows_imported"] + res.report["rows_quarantined"] == 10


@pytest.mark.parametrize("far", ["3e7", "-2.1e7", "inf"])
def test_metres_beyond_half_the_earth_are_quarantined_not_wrapped(tmp_path, far):
    # The plane is one-to-one only within pi * R of the origin (20,015 km): 3e7 m was read
    # as a fix at some other place on the globe (and inf warned from numpy).
    path = tmp_path / "xy.csv"
    _write_xy(_track(n=5), path)
    lines = path.read_text().splitlines()
    cells = lines[3].split(",")
    cells[2] = far
    lines[3] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with np.errstate(all="raise"):
        res = read_points(path, origin=ORIGIN_TEXT)
    reason = "east infinite" if far == "inf" else PLANE_TOO_FAR
    assert res.report["quarantine_reasons"] == {reason: 1}
    assert res.quarantine["line"].tolist() == [4]
    assert res.report["rows_imported"] == 9
    assert (haversine_m(res.points["lon"], res.points["lat"], ORIGIN[1], ORIGIN[0]) < 5e3).all()


def test_the_report_names_the_metre_columns_carried(tmp_path):
    # the points carry x/y as they came, but the report's extra_columns (which `import`
    # prints as "extra columns (carried as they are)") left them out
    path = tmp_path / "xy.csv"
    _write_xy(_track(n=5), path)
    whole = read_points(path, origin=ORIGIN_TEXT)
    assert whole.report["extra_columns"] == ["x", "y"] == list(whole.points.columns[-2:])
    streamed = import_to_csv(path, tmp_path / "s.csv", origin=ORIGIN_TEXT)
    assert streamed.report.get("streamed") and streamed.report["extra_columns"] == ["x", "y"]


def test_a_quarantine_reason_names_the_unit_the_header_gives(tmp_path):
    # "missing range ('Range (NM)', metres)": the reason named metres whatever the header
    path = tmp_path / "site.csv"
    _write_polar(_track(n=5), path, names=("Range (NM)", "bearing_rad"), scale=1852.0, radians=True)
    lines = path.read_text().splitlines()
    lines[2] = ",".join(lines[2].split(",")[:2] + ["", lines[2].split(",")[3]])
    lines[4] = ",".join(lines[4].split(",")[:3] + ["x"])
    path.write_text("\n".join(lines) + "\n")
    res = read_points(path, origin=ORIGIN_TEXT)
    assert res.report["quarantine_reasons"] == {
        "missing range ('Range (NM)', nautical miles)": 1,
        "unparsable bearing ('bearing_rad', radians)": 1,
    }


def test_the_window_words_of_the_origin_messages():
    # "--origin 60,10 was not used" read "the import dialog's Origin of x/y metres
    # field,10 was not used", and "--origin (metres" lost its "(metres"
    from wakeline.app.window_words import window_words

    field = "the import dialog's Origin of x/y metres field"
    assert window_words("--origin 60,10 was not used: x") == f"{field} was not used: x"
    assert window_words(PLANE_TOO_FAR) == PLANE_TOO_FAR.replace("--origin", field)
    assert window_words("use --skip-rows 3, then") == (
        "use the import dialog's Lines above the header field, then"
    )


def test_a_bearing_beyond_a_full_turn_is_quarantined_and_reasons_name_the_unit(tmp_path):
    """An operator's shore radar export (h118): a bearing of 365.5° or 720° was read as
    5.5° or 0° without a word, and a blank range in nautical miles was reported as
    "missing range (…, metres)"."""
    path = tmp_path / "site.csv"
    _write_polar(_track(n=5), path, names=("Range (NM)", "Bearing (deg)"), scale=1852.0)
    lines = path.read_text().splitlines()
    for row, col, value in ((1, 3, "365.5"), (2, 3, "720"), (3, 3, "-20"), (4, 2, "")):
        cells = lines[row].split(",")
        cells[col] = value
        lines[row] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    res = read_points(path, origin=ORIGIN_TEXT)
    assert res.report["quarantine_reasons"] == {
        "bearing beyond ±360° ('Bearing (deg)', degrees)": 2,
        "missing range ('Range (NM)', nautical miles)": 1,
    }
    assert res.report["rows_imported"] + res.report["rows_quarantined"] == 10
    # a signed bearing (-20°) is a bearing: kept, 340° from the site
    east, north = to_local(res.points["lon"], res.points["lat"], ORIGIN[1], ORIGIN[0])
    az = np.degrees(np.arctan2(east, north)) % 360
    assert np.isclose(az, 340.0, atol=1e-6).sum() == 1


@settings(max_examples=30, deadline=None)
@given(
    bearings=st.lists(
        st.floats(-800, 800, allow_nan=False).map(lambda v: round(v, 3)), min_size=1, max_size=12
    ),
    radians=st.booleans(),
)
def test_bearings_within_a_turn_are_read_and_beyond_it_quarantined(
    tmp_path_factory, bearings, radians
):
    path = tmp_path_factory.mktemp("b") / "site.csv"
    scale = np.pi / 180.0 if radians else 1.0
    head = "time,track,range_m," + ("bearing_rad" if radians else "bearing")
    rows = [f"{1_620_000_000 + 10 * k},1,1000,{b * scale!r}" for k, b in enumerate(bearings)]
    path.write_text("\n".join([head, *rows]) + "\n")
    res = read_points(path, origin=ORIGIN_TEXT)
    inside = np.abs(np.array(bearings)) <= 360.0 + 1e-9
    rep = res.report
    assert rep["rows_read"] == len(bearings)
    assert rep["rows_imported"] == inside.sum()
    assert rep["rows_imported"] + rep["rows_quarantined"] == len(bearings)
    if inside.any():
        east, north = to_local(res.points["lon"], res.points["lat"], ORIGIN[1], ORIGIN[0])
        got = np.degrees(np.arctan2(east, north))
        want = np.array(bearings)[inside]
        diff = (got - want + 180.0) % 360.0 - 180.0
        assert np.abs(diff).max() < 1e-6


def test_x_y_beside_range_and_bearing_the_mapped_pair_is_read_and_the_other_said(tmp_path):
    """An operator's file with x/y (km) and range/bearing columns (h118): x/y were read
    without a word, and `--map range=… --map bearing=…` was ignored (the report listed
    range and bearing as mapped while the positions came from x/y)."""
    truth = _track(n=6, seed=4)
    east, north = to_local(truth["lon"], truth["lat"], ORIGIN[1], ORIGIN[0])
    frame = pd.DataFrame(
        {
            "time": truth["time"].astype("int64"),
            "track": truth["track"],
            "x (km)": np.round(east / 1e3, 7),
            "y (km)": np.round(north / 1e3, 7),
            "range": 500.0,  # another plot's place: not the truth
            "bearing": 45.0,
        }
    )
    path = tmp_path / "both.csv"
    frame.to_csv(path, index=False)
    res = read_points(path, origin=ORIGIN_TEXT)
    assert _error_m(res.points, truth).max() < 0.01
    (warning,) = [w for w in res.report["warnings"] if "two kinds" in w]
    assert "--map range=range --map bearing=bearing" in warning
    for how in ({"mapping": ["range=range", "bearing=bearing"]}, {"stream": True}):
        if "stream" in how:
            out = tmp_path / "out.csv"
            rep = import_to_csv(
                path, out, origin=ORIGIN_TEXT, mapping=["range=range", "bearing=bearing"]
            )
            pts = pd.read_csv(out)
            assert any(
                "--map 'east=x (km)' --map 'north=y (km)'" in w for w in rep.report["warnings"]
            )
        else:
            res = read_points(path, origin=ORIGIN_TEXT, **how)
            pts = res.points
            assert "east" not in res.report["columns"]
        e, n = to_local(pts["lon"], pts["lat"], ORIGIN[1], ORIGIN[0])
        np.testing.assert_allclose(np.hypot(e, n), 500.0, atol=1e-6)
        np.testing.assert_allclose(np.degrees(np.arctan2(e, n)), 45.0, atol=1e-7)


def test_import_says_how_the_plane_positions_were_read(tmp_path, capsys):
    """`wakeline import` names each plane column's unit and the origin it used (h118: a
    swapped --origin or a unit read wrong gave no sign in the console)."""
    from wakeline.app.cli import main

    path = tmp_path / "site.csv"
    _write_polar(_track(n=5), path, names=("Range (NM)", "bearing_rad"), scale=1852.0, radians=True)
    out = tmp_path / "o.csv"
    assert main(["import", str(path), "-o", str(out), "--origin", ORIGIN_TEXT]) == 0
    assert (
        "positions: range 'Range (NM)' in nautical miles, bearing 'bearing_rad' in radians; "
        f"about the origin lat {ORIGIN[0]}, lon {ORIGIN[1]}"
    ) in capsys.readouterr().err


@settings(max_examples=30, deadline=None)
@given(
    cells=st.lists(
        st.tuples(
            st.floats(-3000, 3000, allow_nan=False),
            st.floats(-3000, 3000, allow_nan=False),
            st.floats(-500, 500, allow_nan=False),
            st.floats(-500, 500, allow_nan=False),
            st.integers(0, 999_999),
        ),
        min_size=3,
        max_size=12,
    )
)
def test_full_precision_metres_and_unix_times_come_back_byte_for_byte(tmp_path_factory, cells):
    """Autoferry writes every float in full (repr): `84.63510099212183`, time
    `1620114894.71274`. The plane and back cost ~1e-9 m and a time's float ~2e-7 s, so
    an unchanged table came back different in the last digits (h118: 71,086 lines of
    ground_truth.csv differed); now every unmoved row keeps its own text."""
    rows = [
        f"{1_620_114_891 + k}.{frac:06d}".rstrip("0").rstrip(".")
        + f",lidar,{on!r},{oe!r},{n!r},{e!r}"
        for k, (n, e, on, oe, frac) in enumerate(cells)
    ]
    path = tmp_path_factory.mktemp("ned") / "det.csv"
    path.write_text(
        "time,sensor,own_north,own_east,meas_north,meas_east\n" + "\n".join(rows) + "\n"
    )
    res = read_points(path, origin=ORIGIN_TEXT)
    out = path.with_name("back.csv")
    write_layout(res.points, load_layout(path, origin=ORIGIN_TEXT), out)
    assert out.read_text() == path.read_text()


@pytest.mark.parametrize("quoted", [False, True])
def test_bearings_beyond_a_turn_are_counted_once_whole_streamed_or_in_pieces(
    tmp_path, monkeypatch, quoted
):
    """Degrees under a radians header (h118: 1,800 of 2,000 rows quarantined with exit 0
    and no word): one warning with the count and what to do, the same whole, streamed
    and read in pieces (quoted ids)."""
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 300)
    q = '"' if quoted else ""
    lines = ["time,track,range_km,bearing_rad"] + [
        f"{1_620_000_000 + 10 * k},{q}7{q},1.5,{(k * 37) % 360}" for k in range(40)
    ]
    path = tmp_path / "site.csv"
    path.write_text("\n".join(lines) + "\n")
    whole = read_points(path, origin=ORIGIN_TEXT).report
    streamed = import_to_csv(path, tmp_path / "o.csv", origin=ORIGIN_TEXT).report
    assert streamed.get("pieces" if quoted else "streamed")
    beyond = sum(1 for k in range(40) if (k * 37) % 360 > 2 * np.pi)
    for rep in (whole, streamed):
        (w,) = [w for w in rep["warnings"] if "beyond a full turn" in w]
        assert w.startswith(f"{beyond} of 40 rows have a bearing in 'bearing_rad'")
        assert "look like degrees" in w
        assert rep["rows_imported"] + rep["rows_quarantined"] == 40
    assert streamed["warnings"] == whole["warnings"]

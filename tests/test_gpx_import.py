"""GPX tracks read as points (core/io/gpx.py): OpenCPN's track export, our own GPX export
read back, and every track point a point or a quarantined row."""

import gzip

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.export_review import export_gpx
from wakeline.core.io import read_points
from wakeline.core.io.reader import inspect_file

OPENCPN = """<?xml version="1.0" encoding="utf-8" ?>
<gpx version="1.1" creator="OpenCPN" xmlns="http://www.topografix.com/GPX/1/1" xmlns:opencpn="http://www.opencpn.org">
  <wpt lat="60.1" lon="10.1"><name>mark</name></wpt>
  <trk>
    <name>Track</name>
    <extensions><opencpn:guid>abc</opencpn:guid></extensions>
    <trkseg>
      <trkpt lat="59.90000" lon="10.60000"><time>2024-05-01T10:00:00Z</time></trkpt>
      <trkpt lat="59.90010" lon="10.60020"><time>2024-05-01T10:00:10Z</time></trkpt>
      <trkpt lat="59.90020" lon="10.60040"></trkpt>
    </trkseg>
    <trkseg>
      <trkpt lat="95.0" lon="10.60060"><time>2024-05-01T10:00:30Z</time></trkpt>
      <trkpt lat="59.90040" lon="10.60080"><time>yesterday</time></trkpt>
      <trkpt lat="59.90050" lon="10.60100"><time>2024-05-01T12:00:50+02:00</time></trkpt>
    </trkseg>
  </trk>
  <trk><name>Track</name><trkseg>
    <trkpt lat="59.8" lon="10.5"><time>2024-05-01T11:00:00Z</time><speed>5.0</speed><course>90</course></trkpt>
    <trkpt lat="59.8" lon="10.5001"><time>2024-05-01T11:00:10Z</time></trkpt>
  </trkseg></trk>
  <rte><rtept lat="59" lon="10"/><rtept lat="59.1" lon="10"/></rte>
</gpx>
"""


def _accounted(r) -> None:
    rep = r.report
    assert rep["rows_read"] == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["rows_imported"] == len(r.points)
    assert rep["rows_quarantined"] == len(r.quarantine)


def test_an_opencpn_track_export(tmp_path):
    path = tmp_path / "ocpn.gpx"
    path.write_text(OPENCPN, encoding="utf-8")
    r = read_points(path)
    _accounted(r)
    assert r.report["format"] == "gpx" and r.report["gpx_tracks"] == 2
    # two tracks of one name stay two tracks
    assert r.points.groupby("batch").size().to_dict() == {"Track": 3, "Track (2)": 2}
    first = r.points[r.points["batch"] == "Track"]
    assert first["time"].iloc[-1] == pd.Timestamp("2024-05-01T10:00:50Z")  # +02:00 read
    fast = r.points[r.points["batch"] == "Track (2)"].iloc[0]
    assert fast["speed"] == pytest.approx(5.0 * 3600 / 1852)  # GPX 1.0 m/s -> knots
    assert fast["course"] == 90.0
    assert dict(zip(r.quarantine["line"], r.quarantine["reason"], strict=True)) == {
        10: "no <time>",
        13: "lat beyond ±90° or lon beyond ±180°",
        14: "unparsable <time>",
    }
    assert r.quarantine["text"].iloc[0].strip().startswith('<trkpt lat="59.90020"')
    assert r.report["waypoints"] == 1 and r.report["route_points"] == 2
    assert any("plans, not tracks" in w for w in r.report["warnings"])
    assert any("share a name" in w for w in r.report["warnings"])


def test_our_own_gpx_export_reads_back(tmp_path):
    rng = np.random.default_rng(0)
    n = 40
    pts = pd.DataFrame(
        {
            "sensor": ["radar"] * 20 + ["ais"] * 20,
            "batch": ["7"] * 20 + ["257000001"] * 20,
            "time": pd.date_range("2024-01-01", periods=20, freq="10s", tz="UTC").append(
                pd.date_range("2024-01-01", periods=20, freq="10s", tz="UTC")
            ),
            "lon": 10.0 + rng.normal(0, 0.01, n),
            "lat": 59.0 + rng.normal(0, 0.01, n),
        }
    )
    export_gpx(pts, tmp_path / "out.gpx")
    back = read_points(tmp_path / "out.gpx").points
    assert sorted(back.groupby(["sensor", "batch"]).size().items()) == [
        (("ais", "257000001"), 20),
        (("radar", "7"), 20),
    ]
    want = pts.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    got = back.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    assert (got["time"] == want["time"]).all()
    assert np.allclose(got["lon"], want["lon"], atol=1e-9)


def test_a_gpx_cut_short_keeps_what_came_before(tmp_path):
    text = OPENCPN.split("  <trk><name>Track</name>")[0] + (
        '  <trk><trkseg><trkpt lat="59.7" lon="10.4"><time>2024-05-01T12:00:00Z</time>'
    )
    path = tmp_path / "cut.gpx.gz"
    path.write_bytes(gzip.compress(text.encode("utf-8")))
    r = read_points(path)
    _accounted(r)
    assert len(r.points) == 3  # the first track's readable points
    last = r.quarantine.iloc[-1]
    assert last["reason"].startswith("not well-formed XML")
    assert "<trkpt" in last["text"]  # the cut point is a quarantined line, not lost
    assert any("stops being well-formed" in w for w in r.report["warnings"])


def test_the_dialog_sees_a_gpx_without_columns(tmp_path):
    path = tmp_path / "t.gpx"
    path.write_text(OPENCPN, encoding="utf-8")
    info = inspect_file(path)
    assert info["kind"] == "gpx" and info["format"] == "gpx" and info["problem"] is None


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.one_of(st.floats(-100, 100), st.just(float("nan"))),
            st.one_of(st.floats(-200, 200), st.just(float("nan"))),
            st.one_of(st.integers(0, 10**6), st.none(), st.just(-1)),
        ),
        min_size=0,
        max_size=12,
    )
)
def test_any_track_points_are_accounted_for(tmp_path_factory, cells):
    """Each <trkpt>, whatever its position and time, is a point or a quarantined row."""
    body = []
    for lat, lon, t in cells:
        lat_a = "" if lat != lat else f' lat="{lat}"'
        lon_a = "" if lon != lon else f' lon="{lon}"'
        if t is None:
            inner = ""
        elif t < 0:
            inner = "<time>not a time</time>"
        else:
            inner = f"<time>{pd.Timestamp(1.7e9 + t, unit='s', tz='UTC').isoformat()}</time>"
        body.append(f"<trkpt{lat_a}{lon_a}>{inner}</trkpt>")
    text = '<?xml version="1.0"?>\n<gpx version="1.1"><trk><trkseg>\n'
    text += "\n".join(body) + "\n</trkseg></trk></gpx>\n"
    path = tmp_path_factory.mktemp("gpx") / "any.gpx"
    path.write_text(text, encoding="utf-8")
    r = read_points(path)
    _accounted(r)
    assert r.report["rows_read"] == len(cells)
    ok = [
        lat == lat
        and lon == lon
        and abs(lat) <= 90
        and abs(lon) <= 180
        and t is not None
        and t >= 0
        for lat, lon, t in cells
    ]
    assert len(r.points) == sum(ok)


def test_sensor_names_with_a_colon_and_merged_tracks_read_back(tmp_path):
    """h130: the name sensor:batch was split at its first ':' (sensor 'AIS:rx1' came back
    as 'AIS'), and merged tracks, named by their batch alone, came back under S1."""
    t = pd.date_range("2024-01-01", periods=5, freq="10s", tz="UTC")
    lon = 10 + np.arange(5) * 1e-3
    pts = pd.concat(
        [
            pd.DataFrame(
                {"sensor": "AIS:rx1", "batch": "367128730", "time": t, "lon": lon, "lat": 59.0}
            ),
            pd.DataFrame(
                {"sensor": "merged", "batch": "T1", "time": t, "lon": lon + 1, "lat": 59.0}
            ),
        ]
    )
    export_gpx(pts, tmp_path / "o.gpx")
    back = read_points(tmp_path / "o.gpx").points
    assert back.groupby(["sensor", "batch"]).size().to_dict() == {
        ("AIS:rx1", "367128730"): 5,
        ("merged", "T1"): 5,
    }


def test_our_export_reads_back_to_the_last_digit(tmp_path):
    """Three tracks of our own export (a sensor with a colon among them) read back with
    the same sensors, batches, times and positions to the last of 17 digits."""
    rng = np.random.default_rng(1)
    n = 3000
    pts = pd.DataFrame(
        {
            "sensor": np.where(np.arange(n) < 1000, "AIS:rx1", "radar"),
            "batch": (np.arange(n) // 500).astype(str),
            "time": pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(np.arange(n), "s"),
            "lon": 10.0 + rng.normal(0, 0.01, n),
            "lat": 59.0 + rng.normal(0, 0.01, n),
        }
    )
    export_gpx(pts, tmp_path / "ours.gpx")
    back = read_points(tmp_path / "ours.gpx").points
    back = back.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    want = pts.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    assert (back[["sensor", "batch"]] == want[["sensor", "batch"]]).all().all()
    assert (back["time"] == want["time"]).all()
    assert np.array_equal(back["lon"].to_numpy(), want["lon"].to_numpy())


def test_a_prefixed_child_is_read_by_its_local_name(tmp_path):
    """<g:time>, <g:speed> directly under a <trkpt> are read by their local names: no
    point quarantined for its time, no speed lost (h141)."""
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<gpx creator="x" version="1.1" xmlns:g="urn:g">\n<trk><name>A</name><trkseg>\n'
        '<trkpt lat="59.5" lon="10.25"><time>2024-05-01T10:00:00Z</time>'
        "<g:speed>5</g:speed></trkpt>\n"
        '<trkpt lat="59.6" lon="10.25"><g:time>2024-05-01T10:00:10Z</g:time></trkpt>\n'
        "</trkseg></trk>\n</gpx>\n"
    )
    path = tmp_path / "prefixed.gpx"
    path.write_text(text, encoding="utf-8")
    got = read_points(path)
    assert len(got.points) == 2 and got.points["speed"].notna().sum() == 1


@pytest.mark.parametrize(
    "inside", ["<trk><name>x</name></trk>", "<x:wpt lat='1' lon='1'/>", "<x:trkseg/>"]
)
def test_a_document_element_in_a_points_extensions_loses_no_point(tmp_path, inside):
    """A <trk>, <wpt> or <trkseg> inside a point's <extensions> is counted by its local
    name wherever it stands (expat's reading); the three points are all read (h141)."""
    point = '<trkpt lat="59.5" lon="10.25"><time>2024-05-01T10:0{}:00Z</time>{}</trkpt>'
    text = (
        '<gpx creator="x"><trk><trkseg>'
        + point.format(0, "")
        + point.format(1, f"<extensions>{inside}</extensions>")
        + point.format(2, "")
        + "</trkseg></trk></gpx>"
    )
    path = tmp_path / "inside.gpx"
    path.write_text(text, encoding="utf-8")
    got = read_points(path)
    assert len(got.points) + len(got.quarantine) == 3
    assert len(got.points) == 3


def test_our_gpx_keeps_speed_and_course(tmp_path):
    """Session 29's leftover: the GPX export dropped speed and course. They are written per
    point as Garmin's TrackPointExtension v2 (gpxtpx:speed m/s, gpxtpx:course degrees) and
    read back to their precision; a point without them has no extension, a course of
    360 or more is written in [0, 360)."""
    rng = np.random.default_rng(7)
    n = 600
    pts = pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": (np.arange(n) // 200).astype(str),
            "time": pd.Timestamp("2024-01-01", tz="UTC") + pd.to_timedelta(np.arange(n), "s"),
            "lon": 10.0 + rng.normal(0, 0.01, n),
            "lat": 59.0 + rng.normal(0, 0.01, n),
            "speed": rng.uniform(0, 30, n),
            "course": rng.uniform(0, 360, n),
        }
    )
    pts.loc[5, "speed"] = np.nan
    pts.loc[6, "course"] = np.nan
    pts.loc[7, ["speed", "course"]] = np.nan
    pts.loc[8, "course"] = 370.0
    pts.loc[9, "speed"] = -2.0  # negative: no gpxtpx:speed (the schema's speed is >= 0)
    path = tmp_path / "sc.gpx"
    export_gpx(pts, path)
    text = path.read_text(encoding="utf-8")
    assert "http://www.garmin.com/xmlschemas/TrackPointExtension/v2" in text
    assert text.count("<gpxtpx:speed>") == n - 3 and text.count("<gpxtpx:course>") == n - 2
    back = read_points(path).points.sort_values(["batch", "time"]).reset_index(drop=True)
    want = pts.sort_values(["batch", "time"]).reset_index(drop=True)
    want.loc[want["course"] >= 360, "course"] -= 360
    want.loc[want["speed"] < 0, "speed"] = np.nan
    for col in ("speed", "course"):
        got, exp = back[col].to_numpy(), want[col].to_numpy()
        assert np.array_equal(np.isnan(got), np.isnan(exp)), col
        assert np.allclose(got, exp, rtol=1e-12, atol=1e-12, equal_nan=True), col
    assert back.loc[8, "course"] == pytest.approx(10.0)


def test_the_gpx_export_says_which_columns_it_leaves_out(tmp_path, capsys):
    """Operator test 10: `wakeline export … -o x.gpx` of a file with its own columns (the
    GB18030 export's 备注, MTAD's vel) said "exported 664 rows as gpx" and the columns were
    gone on the way back, where GeoJSON carries them. The message now names every column
    the GPX file lacks; each one named is a column that did not come back, and each one
    not named did."""
    from wakeline.app.cli import main

    src = tmp_path / "in.csv"
    rows = [
        f"7,2024-05-01 08:00:{k:02d},{12 + k * 1e-4:.4f},56.0,9.5,45,船{k},{k}" for k in range(30)
    ]
    src.write_text("批号,时间,经度,纬度,航速,航向,备注,序号\n" + "\n".join(rows) + "\n")
    assert main(["export", str(src), "-o", str(tmp_path / "x.gpx")]) == 0
    msg = capsys.readouterr().err
    assert "not written: 备注, 序号 (a GPX point holds" in msg
    back = read_points(tmp_path / "x.gpx").points
    assert len(back) == 30 and {"speed", "course"} <= set(back.columns)
    assert not {"备注", "序号"} & set(back.columns)
    plain = tmp_path / "plain.csv"
    plain.write_text("batch,time,lon,lat\n" + "\n".join(r.rsplit(",", 4)[0] for r in rows) + "\n")
    assert main(["export", str(plain), "-o", str(tmp_path / "p.gpx")]) == 0
    assert "not written" not in capsys.readouterr().err


def test_speed_and_course_read_from_a_points_extensions(tmp_path):
    """Another program's GPX 1.1: gpxtpx:speed/course under TrackPointExtension, or a bare
    <speed> in <extensions>, are m/s and degrees; GPX 1.0's own <speed> comes first."""
    ns = 'xmlns:gpxtpx="http://www.garmin.com/xmlschemas/TrackPointExtension/v2"'
    point = '<trkpt lat="59.5" lon="10.25"><time>2024-05-01T10:0{}:00Z</time>{}</trkpt>'
    tpx = (
        "<extensions><gpxtpx:TrackPointExtension><gpxtpx:speed>{}</gpxtpx:speed>"
        "<gpxtpx:course>{}</gpxtpx:course></gpxtpx:TrackPointExtension></extensions>"
    )
    body = [
        point.format(0, tpx.format(5.144444, 45.5)),
        point.format(1, "<extensions><speed>2.5</speed></extensions>"),
        point.format(2, "<speed>1</speed>" + tpx.format(9, 90)),
        point.format(3, ""),
    ]
    text = f'<gpx creator="x" version="1.1" {ns}><trk><trkseg>{"".join(body)}</trkseg></trk></gpx>'
    path = tmp_path / "ext.gpx"
    path.write_text(text, encoding="utf-8")
    got = read_points(path).points.sort_values("time").reset_index(drop=True)
    kn = 3600 / 1852
    assert got["speed"].tolist()[:3] == pytest.approx([5.144444 * kn, 2.5 * kn, 1 * kn])
    assert np.isnan(got["speed"].iloc[3])
    assert got["course"].iloc[0] == 45.5 and got["course"].iloc[2] == 90.0
    assert got["course"].iloc[[1, 3]].isna().all()


def test_a_gpx_speed_or_course_out_of_range_is_blanked_as_a_csvs(tmp_path):
    """Review h231: a GPX's speed and course (GPX 1.0's own or an extension's) came in as
    read: a negative or infinite speed, a course of -10 or 370 stayed in the points (a
    delimited file's import blanks them). Now checked alike: a full circle is north, the
    others blanked and counted, the point kept; the same values in a CSV give the same."""
    speeds = ["5", "-1", "INF", "2", "", "3"]
    courses = ["10", "20", "360", "-10", "370", "359.5"]
    point = '<trkpt lat="59.5" lon="10.25"><time>2024-05-01T10:0{}:00Z</time>{}</trkpt>'
    tpx = (
        "<extensions><gpxtpx:TrackPointExtension>{}<gpxtpx:course>{}</gpxtpx:course>"
        "</gpxtpx:TrackPointExtension></extensions>"
    )
    body = [
        point.format(i, tpx.format(f"<gpxtpx:speed>{v}</gpxtpx:speed>" if v else "", c))
        for i, (v, c) in enumerate(zip(speeds, courses, strict=True))
    ]
    ns = 'xmlns:gpxtpx="http://www.garmin.com/xmlschemas/TrackPointExtension/v2"'
    text = f'<gpx version="1.1" creator="x" {ns}><trk><trkseg>{"".join(body)}</trkseg></trk></gpx>'
    path = tmp_path / "range.gpx"
    path.write_text(text, encoding="utf-8")
    got = read_points(path)
    pts = got.points.sort_values("time").reset_index(drop=True)
    assert len(pts) == 6  # every point kept
    kn = 3600 / 1852
    np.testing.assert_allclose(
        pts["speed"].to_numpy(), [5 * kn, np.nan, np.nan, 2 * kn, np.nan, 3 * kn]
    )
    np.testing.assert_allclose(pts["course"].to_numpy(), [10, 20, 0, np.nan, np.nan, 359.5])
    blanked = got.report["values_blanked"]
    # a CSV of the same values (knots) blanks the same ones, under the same names
    csv = tmp_path / "range.csv"
    rows = [
        f"A,2024-05-01T10:0{i}:00Z,10.25,59.5,{float(v) * kn if v else ''},{c}"
        for i, (v, c) in enumerate(zip(speeds, courses, strict=True))
    ]
    csv.write_text("id,time,lon,lat,speed,course\n" + "\n".join(rows) + "\n")
    want = read_points(csv, mapping={"batch": "id"})
    assert (
        blanked
        == want.report["values_blanked"]
        == {
            "speed negative or infinite": 2,
            "course outside [0, 360)": 2,
        }
    )
    np.testing.assert_array_equal(
        np.isnan(pts["speed"].to_numpy()), want.points["speed"].isna().to_numpy()
    )
    np.testing.assert_array_equal(pts["course"].to_numpy(), want.points["course"].to_numpy())

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


def _read_both(path, monkeypatch):
    """The file read by the fast reading and by expat's callbacks alone (h135), and
    whether the fast reading took it."""
    from wakeline.core.io import gpx

    took = []
    fast_parse = gpx._fast_parse

    def spy(data):
        out = fast_parse(data)
        took.append(out is not None)
        return out

    monkeypatch.setattr(gpx, "_fast_parse", spy)
    fast = read_points(path)
    monkeypatch.setattr(gpx, "_fast_parse", lambda data: None)
    slow = read_points(path)
    monkeypatch.setattr(gpx, "_fast_parse", fast_parse)
    return fast, slow, took[0]


def _same(a, b) -> None:
    pd.testing.assert_frame_equal(a.points, b.points)
    pd.testing.assert_frame_equal(a.quarantine, b.quarantine)
    assert a.report == b.report


def test_the_fast_reading_reads_as_expat_does(tmp_path, monkeypatch):
    """h135: the track points cut out by Arrow's string kernels are expat's, to the line
    numbers of the quarantined ones; our export and OpenCPN's take the fast reading."""
    from wakeline.core.io import gpx

    path = tmp_path / "ocpn.gpx"
    path.write_text(OPENCPN.replace("\n", "\r\n"), encoding="utf-8")
    for chunk in (gpx.FAST_CHUNK_BYTES, 200, 1):  # one part; parts cut before a <trkpt>
        monkeypatch.setattr(gpx, "FAST_CHUNK_BYTES", chunk)
        fast, slow, took = _read_both(path, monkeypatch)
        assert took
        _same(fast, slow)
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
    monkeypatch.setattr(gpx, "FAST_CHUNK_BYTES", 50_000)  # tracks cut across parts
    fast, slow, took = _read_both(tmp_path / "ours.gpx", monkeypatch)
    assert took
    _same(fast, slow)
    back = fast.points.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    want = pts.sort_values(["sensor", "batch", "time"]).reset_index(drop=True)
    assert (back[["sensor", "batch"]] == want[["sensor", "batch"]]).all().all()
    assert (back["time"] == want["time"]).all()
    assert np.array_equal(back["lon"].to_numpy(), want["lon"].to_numpy())  # 17 digits


def test_a_prefixed_child_reads_as_expat_reads_it(tmp_path, monkeypatch):
    """expat reads <g:time>, <g:speed> directly under a <trkpt> by their local names: the
    fast reading leaves such a file to expat rather than lose the time (a point
    quarantined) or the speed (h141)."""
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
    fast, slow, _ = _read_both(path, monkeypatch)
    _same(fast, slow)
    assert len(fast.points) == 2 and fast.points["speed"].notna().sum() == 1


@pytest.mark.parametrize(
    "inside", ["<trk><name>x</name></trk>", "<x:wpt lat='1' lon='1'/>", "<x:trkseg/>"]
)
def test_a_document_element_in_a_points_extensions_reads_as_expat_reads_it(
    tmp_path, monkeypatch, inside
):
    """expat counts a <trk>, <wpt> or <trkseg> wherever it stands, by its local name, in
    a point's <extensions> too (a new track for the points after it, a waypoint or a
    segment in the report): the fast reading leaves such a file to expat (h141)."""
    point = '<trkpt lat="59.5" lon="10.25"><time>2024-05-01T10:00:00Z</time>{}</trkpt>'
    text = (
        '<gpx creator="x"><trk><trkseg>'
        + point.format("")
        + point.format(f"<extensions>{inside}</extensions>")
        + point.format("")
        + "</trkseg></trk></gpx>"
    )
    path = tmp_path / "inside.gpx"
    path.write_text(text, encoding="utf-8")
    fast, slow, _ = _read_both(path, monkeypatch)
    _same(fast, slow)


#: the first _PLAIN of each list are track points the fast reading takes
_PLAIN = 8
_ATTR_LIST = [
    ' lat="59.5" lon="10.25"',
    ' lat="-59.5" lon="-170.000000001"',
    ' lon="10.25" lat="59.5"',
    ' lat="59.5"',
    ' lat = "59.5"\n  lon="1e1" ele="3"',
    ' lat="95" lon="10"',
    ' lat=" 59.5\t" lon="+.5"',
    ' lat="5x" lon="10"',
    ' lat="" lon="0x1"',
    " lat='59.5' lon='10.25'",
    ' lat="59.5" lon="10" note="a &amp; b"',
    ' lat="59.5" lon="10" x:lat="1"',
]
_ATTR = st.sampled_from(_ATTR_LIST)
_CHILD_LIST = [
    "",
    "<time>2024-05-01T10:00:00Z</time>",
    "\n  <time> 2024-05-01T10:00:10Z </time>\n",
    "<ele>3</ele><time>2024-05-01T10:00:20+02:00</time><speed>2.5</speed><course>90</course>",
    "<time>yesterday</time>",
    "<time/>",
    "<time>1714557600</time><course>-1</course>",
    "<time>2024-05-01T10:00:30Z</time><extensions><x:speed>9</x:speed></extensions>",
    "<time>2024-05-01T10:01:20Z</time><speed>fast</speed>",
    "<time>2024-05-01T10:00:30Z</time><time>2024-05-01T10:00:40Z</time>",
    "<time>2024-05-01T10:00:50Z</time><name>a &lt; b</name>",
    "<time><![CDATA[2024-05-01T10:01:00Z]]></time>",
    "<time>2024-05-01T10:01:10Z</time><!-- a note -->",
    "<time>2024-05-01T10:01:30Z</time><link><text>x</text></link>",
    "<time>2024-05-01T10:01:40Z</time><x:speed>4</x:speed>",
    "<x:time>2024-05-01T10:01:50Z</x:time>",
]
_CHILD = st.sampled_from(_CHILD_LIST)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.sampled_from(["", "<name>A</name>", "<name>A</name><src>S</src>", "<src>x</src>"]),
            st.lists(st.tuples(_ATTR, _CHILD, st.booleans()), max_size=6),
        ),
        max_size=4,
    ),
    st.booleans(),
    st.sampled_from(["OpenCPN", "Wakeline"]),
    st.booleans(),
    st.sampled_from([1, 120, 1 << 20]),
)
def test_any_gpx_reads_as_expat_reads_it(tmp_path_factory, tracks, crlf, creator, plain, chunk):
    """h135: whatever the track points look like, the fast reading gives expat's table
    (or leaves the file to expat)."""
    import _pytest.monkeypatch

    body = []
    for head, points in tracks:
        body.append(f"<trk>{head}<trkseg>")
        for attrs, child, closed in points:
            if plain:  # half the files: only what the fast reading takes
                attrs = _ATTR_LIST[_ATTR_LIST.index(attrs) % _PLAIN]
                child = _CHILD_LIST[_CHILD_LIST.index(child) % _PLAIN]
                closed = False
            body.append(
                f"<trkpt{attrs}/>" if closed and not child else f"<trkpt{attrs}>{child}</trkpt>"
            )
        body.append("</trkseg></trk>")
    text = f'<?xml version="1.0" encoding="UTF-8"?>\n<gpx creator="{creator}" version="1.1">\n'
    text += "\n".join(body) + "\n</gpx>\n"
    if crlf:
        text = text.replace("\n", "\r\n")
    path = tmp_path_factory.mktemp("gpx") / "any.gpx"
    path.write_bytes(text.encode("utf-8"))
    from wakeline.core.io import gpx

    with _pytest.monkeypatch.MonkeyPatch.context() as mp:
        mp.setattr(gpx, "FAST_CHUNK_BYTES", chunk)  # parts cut before a <trkpt>
        fast, slow, _ = _read_both(path, mp)
    _same(fast, slow)

"""An AIS NMEA log's tag block source (``\\s:RADAR1,c:…*hh\\``) names the sensor (h191,
D-import-13); a line without one keeps S1, a given --sensor names every point."""

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyais.encode import encode_dict

from wakeline.core.io import read_points
from wakeline.core.io.nmea import tag_source


def _tagged(fields: str, sentence: str) -> str:
    check = 0
    for ch in fields:
        check ^= ord(ch)
    return f"\\{fields}*{check:02X}\\{sentence}"


def _sentence(mmsi: int, i: int) -> str:
    msg = {"type": 1, "mmsi": mmsi, "lon": 122.0 + i * 1e-3, "lat": 30.0, "speed": 10.0}
    msg["course"] = 90.0
    (sentence,) = encode_dict(msg, radio_channel="A", talker_id="AI", sentence_type="VDO")
    return sentence


def test_tag_source_forms():
    assert tag_source("\\s:RADAR1,c:1796428800*46\\!AIVDO,1,1,,A,1,0*1B") == "RADAR1"
    assert tag_source("\\c:1796428800,s:rx 2*46\\!AIVDO") == "rx 2"
    assert tag_source("\\c:1796428800*46\\!AIVDO") == ""
    assert tag_source("1671620143 !AIVDM,1,1,,B,15M6,0*5C") == ""


def test_operator_log_is_read_with_its_station(write):
    lines = [
        _tagged(f"s:RADAR1,c:{1796428800 + 10 * i}", _sentence(412000001, i)) for i in range(5)
    ]
    path = write("log.nmea", "\n".join(lines) + "\n")
    assert set(read_points(path).points["sensor"]) == {"RADAR1"}
    assert set(read_points(path, sensor="AIS").points["sensor"]) == {"AIS"}


@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    sources=st.lists(
        st.one_of(
            st.just(""),
            st.text(
                st.characters(whitelist_categories=("Lu", "Ll", "Nd", "Lo"), max_codepoint=0x9FFF),
                min_size=1,
                max_size=8,
            ),
        ),
        min_size=1,
        max_size=25,
    )
)
def test_property_each_point_has_its_lines_source(write, sources):
    """Every line is a point (nothing lost) whose sensor is its tag block's source, S1
    where the line names none."""
    lines = []
    for i, src in enumerate(sources):
        fields = (f"s:{src}," if src else "") + f"c:{1796428800 + 10 * i}"
        lines.append(_tagged(fields, _sentence(412000000 + i, i)))
    r = read_points(write("p.nmea", "\n".join(lines) + "\n"))
    assert len(r.points) == len(sources) and len(r.quarantine) == 0
    got = dict(zip(r.points["batch"].astype(str), r.points["sensor"].astype(str), strict=True))
    for i, src in enumerate(sources):
        assert got[str(412000000 + i)] == (src.strip() or "S1")


def test_the_battery_log_names_its_one_tagged_line():
    """The battery's log: one line has a tag block from shore station 2573345 (as
    Kystverket's feed writes), the others a time stamp only and keep S1."""
    from conftest import DATA

    r = read_points(DATA / "battery" / "ais_log.nmea")
    assert set(r.points["sensor"]) == {"S1", "2573345"}
    assert (r.points["sensor"] == "2573345").sum() == 1

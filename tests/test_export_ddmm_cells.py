"""``export --like`` writes NMEA's ddmm.mmmm with the letter in the cell (``3754.03N``)
back in its form (h149): the padding, the minutes' decimals, the letter before or after
and its gap. Before, such a file came back as signed decimal degrees (``37.9005``)."""

import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_import_hemisphere_forms import _nmea_cell
from wakeline.app.cli import main
from wakeline.core.io import read_points
from wakeline.core.io.export_like import write_layout
from wakeline.core.io.layout import AngleFormat, Layout, describe_layout

PADDED = (
    "time,id,lat,lon\n"
    "2024-01-01T00:00:00Z,1,3754.0300N,02342.1000E\n"
    "2024-01-01T00:00:10Z,1,0030.5000S,00123.5000W\n"
    "2024-01-01T00:00:20Z,2,3754.0712N,17959.9999W\n"
)
#: unpadded (123.5W is 1°23.5'), the letter before with a gap, trimmed decimals
UNPADDED = (
    "time,id,lat,lon\n"
    "2024-01-01T00:00:00Z,1,N 3754.03,E 2342.1\n"
    "2024-01-01T00:00:10Z,1,S 942.1,W 123.5\n"
    "2024-01-01T00:00:20Z,2,N 3754.07,W 12059.99\n"
)


@pytest.mark.parametrize("text", [PADDED, UNPADDED], ids=["padded", "unpadded"])
def test_import_then_export_like_gives_the_same_bytes(tmp_path, text):
    src = tmp_path / "nmea.csv"
    src.write_bytes(text.encode())
    out = tmp_path / "back.csv"
    main(["export", str(src), "-o", str(out), "--like", str(src)])
    assert out.read_bytes() == src.read_bytes()
    # through the canonical CSV in between (wakeline import, then export --like)
    canonical = tmp_path / "canonical.csv"
    main(["import", str(src), "-o", str(canonical)])
    assert "3754" not in canonical.read_text()  # canonical: signed decimal degrees
    main(["export", str(canonical), "-o", str(out), "--like", str(src)])
    assert out.read_bytes() == src.read_bytes()


def test_the_form_is_learnt_from_the_import_report():
    src = pd.Series(["3754.0300N", "0030.5000S"])
    assert AngleFormat.detect(src, ddmm=True) == AngleFormat(
        deg_mark="", min_mark="", decimals=4, trim="none", deg_width=4, ddmm=True
    )
    # a column of decimal degrees with letters stays so
    assert not AngleFormat.detect(pd.Series(["37.5N", "37.6N"])).ddmm


def test_a_moved_point_is_written_in_the_form_and_the_json_keeps_it(tmp_path):
    src = tmp_path / "nmea.csv"
    src.write_text(PADDED)
    first = read_points(src)
    layout = describe_layout(src, first.report)
    again = Layout.from_dict(layout.to_dict())
    assert again == layout and again.field_column("lon").angle.ddmm
    points = first.points.copy()
    points.loc[0, "lat"] = -12.5  # a step moved it: 12°30' S
    write_layout(points, again, tmp_path / "out.csv")
    assert "1230.0000S,02342.1000E" in (tmp_path / "out.csv").read_text()
    # a layout JSON written before h149 (no "ddmm" in its angle) still loads
    old = layout.to_dict()
    for c in old["columns"]:
        if c.get("angle"):
            c["angle"].pop("ddmm")
    assert not Layout.from_dict(old).field_column("lon").angle.ddmm


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    rows=st.lists(
        st.tuples(st.floats(1e-5, 89.99), st.floats(1e-5, 179.99), st.booleans(), st.booleans()),
        min_size=1,
        max_size=8,
    ),
    shown=st.floats(10.0, 89.0),
    form=st.sampled_from(["{n}{h}", "{n} {h}", "{h}{n}", "{h} {n}"]),
    padded=st.booleans(),
)
def test_any_positions_come_back_byte_for_byte(tmp_path_factory, rows, shown, form, padded):
    """Random positions written as ddmm.mmmm cells (4 decimals of minutes), padded or
    not, in any of the letter's places: import, export --like the file, the same bytes.
    The first row lies 10°-89° N, 10°-89° E: its cells show the form. (A position of
    0.0000 minutes comes back with the positive letter: -0 is 0.)"""
    # (no cell of 0.0000 minutes: read as 0, whose letter, N or S, no number keeps)
    rows = [(shown, shown)] + [(-a if s else a, -o if w else o) for a, o, s, w in rows]
    lines = ["time,id,lat,lon"]
    for i, (lat, lon) in enumerate(rows):
        a = _nmea_cell(lat, "NS", 4 if padded else 0, form)
        o = _nmea_cell(lon, "EW", 5 if padded else 0, form)
        lines.append(f"2024-01-01T00:00:{i:02d}Z,1,{a},{o}")
    folder = tmp_path_factory.mktemp("x")
    src = folder / "p.csv"
    src.write_text("\n".join(lines) + "\n")
    first = read_points(src)
    assert first.report["rows_quarantined"] == 0, first.quarantine.to_dict("records")
    write_layout(first.points, describe_layout(src, first.report), folder / "back.csv")
    assert (folder / "back.csv").read_text() == src.read_text()

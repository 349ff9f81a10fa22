"""A title above the header ("Radar track export 2024-05-01", then the header on line 2):
the header is found among the first lines, the lines above it skipped and counted."""

import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.io import import_to_csv, read_points, sniff
from wakeline.core.io.export_like import write_layout
from wakeline.core.io.layout import describe_layout

HEADERS = {
    "en": "track_id,time,lon,lat,speed,course",
    "zh": "批号,时间,经度,纬度,航速(节),航向",
    "ais": "MMSI,BaseDateTime,LAT,LON,SOG,COG",
}


def _rows(n: int, kind: str = "en", delim: str = ",") -> list[str]:
    out = []
    for k in range(n):
        t = f"2024-05-01T08:{k // 60:02d}:{k % 60:02d}"
        lon, lat = f"{122 + k * 1e-3:.4f}", f"{30 + k * 1e-3:.4f}"
        cells = (
            [str(400 + k % 2), t, lat, lon] if kind == "ais" else [str(400 + k % 2), t, lon, lat]
        )
        out.append(delim.join([*cells, "9.5", "45"]))
    return out


@pytest.mark.parametrize("streamed", [False, True, "quoted"])
@pytest.mark.parametrize("kind", ["en", "zh"])
def test_a_title_line_above_the_header_is_skipped_and_counted(
    write, tmp_path, monkeypatch, kind, streamed
):
    """Tester: an export whose first line is "Radar track export 2024-05-01" and header on
    line 2 was refused (missing required column; headers found: Radar track export…).
    Streamed in small pieces too, with and without a quoted cell."""
    from wakeline.core.io import reader

    rows = _rows(50)
    if streamed == "quoted":
        rows[7] = rows[7].replace("400,", '"400",', 1)
    text = "Radar track export 2024-05-01\n" + HEADERS[kind] + "\n" + "\n".join(rows) + "\n"
    path = write("titled.csv", text, encoding="gb18030" if kind == "zh" else "utf-8")
    if streamed:
        monkeypatch.setattr(reader, "STREAM_BYTES", 600)
        r = import_to_csv(path, tmp_path / "o.csv")
        points = pd.read_csv(tmp_path / "o.csv")
    else:
        r = read_points(path)
        points = r.points
    assert len(points) == 50 and r.report["rows_quarantined"] == 0
    assert r.report["lines_above_header"] == [
        {
            "line": 1,
            "reason": "above the header (a title?): skipped",
            "text": "Radar track export 2024-05-01",
        }
    ]
    assert any("1 line(s) above the header skipped" in w for w in r.report["warnings"])
    assert points["lon"].iloc[1] == pytest.approx(122.001)


def test_several_title_lines_with_blank_lines_and_a_bad_row_keep_line_numbers(write):
    rows = _rows(20)
    rows[5] = "400,not a time,122.0,30.0,9.5,45"
    text = "Export\nStation 3, radar 2\n\n" + HEADERS["en"] + "\n" + "\n".join(rows) + "\n"
    r = read_points(write("t.csv", text))
    assert [x["line"] for x in r.report["lines_above_header"]] == [1, 2]
    assert r.quarantine["line"].tolist() == [4 + 6]  # physical line of rows[5]
    assert r.report["rows_imported"] == 19


def test_the_cli_says_which_lines_it_skipped(write, tmp_path, capsys):
    text = "Radar track export 2024-05-01\n" + HEADERS["en"] + "\n" + "\n".join(_rows(5)) + "\n"
    path = write("t.csv", text)
    assert main(["import", str(path), "-o", str(tmp_path / "o.csv")]) == 0
    err = capsys.readouterr().err
    assert "imported 5 rows" in err
    assert "line 1: 'Radar track export 2024-05-01'" in err


def test_a_file_without_title_or_without_header_is_read_as_before(write):
    plain = write("p.csv", HEADERS["en"] + "\n" + "\n".join(_rows(5)) + "\n")
    assert sniff(plain).title_lines == () and sniff(plain).skip_rows == 1
    bare = write("b.csv", "\n".join(_rows(5)) + "\n")
    sn = sniff(bare)
    assert sn.title_lines == () and sn.skip_rows <= 1  # as before: no line searched past


def test_explicit_skip_rows_in_sniff(write):
    text = "a,b,c\nx,y,z\n" + HEADERS["en"] + "\n" + "\n".join(_rows(3)) + "\n"
    sn = sniff(write("s.csv", text), skip_rows=2)
    assert sn.columns[0] == "track_id" and sn.skip_rows == 3
    assert [n for n, _ in sn.title_lines] == [1, 2]


def test_export_like_writes_the_title_back_and_reimports_the_same_rows(write, tmp_path):
    text = (
        "Radar track export 2024-05-01\n"
        + HEADERS["ais"]
        + "\n"
        + "\n".join(_rows(30, "ais"))
        + "\n"
    )
    src = write("t.csv", text)
    r = read_points(src)
    out = tmp_path / "like.csv"
    write_layout(r.points, describe_layout(src, r.report), out)
    assert out.read_bytes() == src.read_bytes()
    again = read_points(out)
    pd.testing.assert_frame_equal(again.points, r.points)
    # Blank lines among the titles and above the header come back too (they were
    # dropped: a GB18030 export with a blank line under its title lost it).
    spaced = write("s.csv", "\nRadar track export\n\nStation 3\n\n" + text.split("\n", 1)[1])
    r = read_points(spaced)
    write_layout(r.points, describe_layout(spaced, r.report), out)
    assert out.read_bytes() == spaced.read_bytes()


@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    titles=st.lists(
        st.text(
            st.characters(whitelist_categories=("L", "N", "Zs"), whitelist_characters=":-/"),
            min_size=1,
            max_size=30,
        ).filter(lambda s: s.strip()),
        min_size=0,
        max_size=5,
    ),
    blanks=st.lists(st.booleans(), min_size=5, max_size=5),
    kind=st.sampled_from(sorted(HEADERS)),
    delim=st.sampled_from([",", ";", "\t"]),
    n=st.integers(1, 30),
)
def test_count_identity_with_title_lines(tmp_path_factory, titles, blanks, kind, delim, n):
    """Every physical line is the header, blank, a skipped title, a point or quarantined."""
    lines = []
    for k, t in enumerate(titles):
        lines.append(t)
        if blanks[k]:
            lines.append("")
    header = HEADERS[kind].replace(",", delim)
    lines += [header, *_rows(n, kind, delim)]
    path = tmp_path_factory.mktemp("t") / "t.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    r = read_points(path)
    rep = r.report
    assert rep["rows_imported"] == n, rep
    skipped = len(rep["lines_above_header"])
    assert skipped == len(titles)
    total = rep["rows_imported"] + rep["rows_quarantined"] + skipped + 1 + rep["blank_lines"]
    # The blank lines between the titles and the header are counted too (they were not:
    # the report fell short of the file's lines by them).
    assert rep["blank_lines_above_header"] == sum(blanks[: len(titles)])
    assert total + rep["blank_lines_above_header"] == len(lines)


def test_every_line_above_the_header_is_counted_in_the_reports(write, tmp_path):
    """An operator's GB18030 radar export: a title, an export-time line, a blank line,
    then the header. The import report named the two title lines but not the blank one,
    so its counts fell a line short of the file; `wakeline clean --report` alike. Blank
    lines above the header and Excel's "sep=;" line are counted now."""
    rows = [r.replace(",", ";") for r in _rows(6, "zh")]
    text = "sep=;\n\n雷达航迹导出\n导出时间：2024-05-01\n\n" + HEADERS["zh"].replace(",", ";")
    path = write("t.csv", text + "\n" + "\n".join(rows) + "\n")
    lines = len(path.read_text(encoding="utf-8").splitlines())
    rep = read_points(path).report
    assert len(rep["lines_above_header"]) == 2 and rep["excel_sep_line"] == 1
    assert rep["blank_lines_above_header"] == 2 and rep["rows_read"] == 6
    above = len(rep["lines_above_header"]) + rep["blank_lines_above_header"] + 1
    assert rep["rows_read"] + rep["blank_lines"] + above + 1 == lines
    report = tmp_path / "r.json"
    out = tmp_path / "o.csv"
    assert main(["clean", str(path), "-o", str(out), "--report", str(report)]) == 0
    import json

    read = json.loads(report.read_text())["read"]
    assert read["skipped_above_header"] == 5  # was 2
    assert read["rows_read"] + read["blank_lines"] + read["skipped_above_header"] + 1 == lines


def test_skip_rows_option_for_a_title_longer_than_detection_looks(write, tmp_path, capsys):
    """Twelve lines of notes above the header: past what detection looks at (10), so the
    import is refused naming --skip-rows; `wakeline import --skip-rows 12` reads it, the
    12 lines counted, and export --like with the report writes them back."""
    notes = [f"note {k}: exported by station {k}" for k in range(12)]
    text = "\n".join([*notes, HEADERS["en"], *_rows(40)]) + "\n"
    path = write("long.csv", text)
    out = tmp_path / "o.csv"
    assert main(["import", str(path), "-o", str(out)]) == 2
    assert "skip the lines above it with --skip-rows N" in capsys.readouterr().err
    report = tmp_path / "r.json"
    assert (
        main(["import", str(path), "-o", str(out), "--skip-rows", "12", "--report", str(report)])
        == 0
    )
    assert "12 line(s) above the header skipped" in capsys.readouterr().err
    assert len(pd.read_csv(out)) == 40
    r = read_points(path, skip_rows=12)
    assert r.report["rows_imported"] == 40 and len(r.report["lines_above_header"]) == 12
    like = tmp_path / "like.csv"
    write_layout(r.points, describe_layout(path, r.report), like)
    assert like.read_bytes() == path.read_bytes()
    assert main(["import", str(path), "-o", str(out), "--skip-rows", "-1"]) == 2

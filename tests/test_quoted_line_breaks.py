"""A quoted cell that holds a line break (h157): every quarantine row names the physical
line of the file (the first line of its record), as a text editor numbers it, and every
line is accounted for — the bearing reader (one record, one bearing) and the track
reader (which reads such a file line by line, every physical line a point or a
quarantine row: SPEC §2)."""

import pandas as pd
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.bearing_read import read_bearing_file, summary_lines
from wakeline.core.io import read_points

#: The probe's file (h157's bearing_lines.py): a quoted field over lines 6-7.
PROBE = [
    "time,batch,bearing",  # 1
    "2024-01-01 00:00:00,A,10",  # 2
    "2024-01-01 00:00:01,A,11,extra",  # 3 wrong fields
    "",  # 4 blank
    "2024-01-01 00:00:02,A,12",  # 5
    '2024-01-01 00:00:03,"A\nB",13',  # 6-7 quoted line break
    "2024-01-01 00:00:04,A,x",  # 8 bad bearing
    "2024-01-01 00:00:05,,15",  # 9 missing batch
    "2024-01-01 00:00:06,A,16",  # 10
]


def test_bearing_quarantine_names_the_physical_lines_after_a_quoted_line_break(tmp_path):
    p = tmp_path / "b.csv"
    p.write_text("\n".join(PROBE) + "\n")
    got = read_bearing_file(p)
    q = got.quarantine
    assert q["line"].tolist() == [3, 8, 9]  # were 3, 7, 8
    assert q["reason"].tolist() == [
        "4 fields, not 3",
        "bearing not a finite number",
        "missing batch",
    ]
    assert got.bearings["batch"].tolist() == ["A", "A", "A\nB", "A"]
    rep = got.report
    # every physical line: the header, a bearing, a quarantine row, blank, or a line that
    # continues a quoted cell
    assert rep["lines"] == rep["bearings"] + len(q) == 7
    assert 1 + rep["lines"] + rep["blank"] + rep["continued_lines"] == 10
    assert "1 line continues a quoted cell" in summary_lines(rep)[0]


def test_track_reader_numbers_the_same_file_by_its_physical_lines(tmp_path):
    """The track reader reads a file whose quoted cell runs over a line end line by line
    (every physical line a point or a quarantine row): its numbers are the file's."""
    p = tmp_path / "t.csv"
    lines = [r.replace("bearing", "lat,lon") for r in PROBE]
    lines = [lines[0]] + [r + ",5" if r else r for r in lines[1:]]
    p.write_text("\n".join(lines) + "\n")
    got = read_points(p)
    q = got.quarantine
    assert q["line"].tolist() == [3, 6, 7, 8, 9]
    assert q["text"].tolist()[1:3] == ['2024-01-01 00:00:03,"A', 'B",13,5']
    rep = got.report
    assert rep["rows_imported"] + rep["rows_quarantined"] == rep["rows_read"] == 8
    assert 1 + rep["rows_read"] + rep["blank_lines"] == 10


_TIME = "2024-01-01 00:{:02d}:{:02d}"


@st.composite
def quoted_files(draw):
    """Rows of a bearing file, some with a batch quoted over one or more line breaks,
    some bad (an extra field, an unreadable bearing), some blank."""
    n = draw(st.integers(3, 25))
    rows = []
    for k in range(n):
        kind = draw(
            st.sampled_from(["ok", "ok", "quoted", "quoted_extra", "extra", "bad", "blank"])
        )
        t = _TIME.format(k // 60, k % 60)
        if kind.startswith("quoted"):
            parts = draw(st.lists(st.sampled_from(["A", "B c", "d,e", 'x""y']), min_size=2))
            end = draw(st.sampled_from(["\n", "\r\n"]))
            extra = ",9" if kind == "quoted_extra" else ""  # a refused record over lines
            rows.append((kind, f'{t},"{end.join(parts)}",{10 + k}{extra}'))
        elif kind == "extra":
            rows.append((kind, f"{t},A,{10 + k},9"))
        elif kind == "bad":
            rows.append((kind, f"{t},A,x{k}"))
        elif kind == "blank":
            rows.append((kind, ""))
        else:
            rows.append((kind, f"{t},A,{10 + k}"))
    return rows


BAD = ("extra", "bad", "quoted_extra")


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rows=quoted_files())
def test_bearing_line_numbers_are_the_record_starts(tmp_path_factory, rows):
    if all(kind in (*BAD, "blank") for kind, _ in rows):
        rows = [*rows, ("ok", f"{_TIME.format(59, 59)},A,1")]
    p = tmp_path_factory.mktemp("q") / "b.csv"
    text = "time,batch,bearing\n" + "".join(r + "\n" for _, r in rows)
    p.write_bytes(text.encode())
    starts, line = [], 2  # each record's first physical line
    for _, r in rows:
        starts.append(line)
        line += r.count("\n") + 1
    bad = [s for (kind, _), s in zip(rows, starts, strict=True) if kind in BAD]
    got = read_bearing_file(p)
    assert got.quarantine["line"].tolist() == bad
    ok = [kind in ("ok", "quoted") for kind, _ in rows]
    assert len(got.bearings) == sum(ok)
    quoted = [r.split(",", 1)[1].rsplit(",", 1)[0] for kind, r in rows if kind == "quoted"]
    want = [q[1:-1].replace('""', '"') for q in quoted]
    assert [b for b in got.bearings["batch"] if b != "A"] == want
    rep = got.report
    physical = text.replace("\r\n", "\n").count("\n")
    assert 1 + rep["lines"] + rep["blank"] + rep["continued_lines"] == physical
    # the quarantine's texts are the records' own fields
    assert all(isinstance(t, str) for t in pd.Series(got.quarantine["text"]))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rows=quoted_files())
def test_track_reader_line_numbers_are_the_physical_lines(tmp_path_factory, rows):
    """The track reader reads a file with a quoted line break line by line: each
    quarantine row is the physical line it names, and every line is counted once."""
    rows = [(kind, r + ",5" if r else r) for kind, r in rows]
    rows.append(("ok", f"{_TIME.format(59, 59)},A,1,5"))
    p = tmp_path_factory.mktemp("t") / "t.csv"
    text = "time,batch,lat,lon\n" + "".join(r + "\n" for _, r in rows)
    p.write_bytes(text.encode())
    got = read_points(p)
    physical = text.replace("\r\n", "\n").split("\n")[:-1]
    rep = got.report
    assert 1 + rep["rows_read"] + rep["blank_lines"] == len(physical)
    assert rep["rows_imported"] + rep["rows_quarantined"] == rep["rows_read"]
    for line, raw in zip(got.quarantine["line"], got.quarantine["text"], strict=True):
        assert physical[line - 1].strip() == raw.strip()

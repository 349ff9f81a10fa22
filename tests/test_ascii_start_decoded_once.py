"""A file that starts ASCII and has lines that are not UTF-8 later (Windows-1252 ship
names, or GB18030 Chinese ones) is parsed once (h179): its start reads as UTF-8, and the
strict first reading's decoder asks the whole file's judgement at the first line that
does not decode and goes on — in UTF-8 with that line read as Windows-1252 (or GB18030),
or, the text so far all ASCII and the file judged GB18030, as GB18030 — instead of
failing the reading and the file being read again whole (and, by ``wakeline import``,
in pieces as well). The rows are those of the file read as it is meant (the same
names written in UTF-8; the GB18030 file with its encoding given)."""

import pandas as pd
import pytest

import wakeline.core.io.decoding as decoding
import wakeline.core.io.reader as reader
from wakeline.core.io import import_to_csv, read_points, write_points

LATIN = ["Bjørn", "Ålesund", "São Paulo"]
CHINESE = ["远洋一号", "海丰号", "中远之星"]


def _file(path, names, encoding, rows=20_000):
    lines = ["time,id,lat,lon,name\n"]
    for k in range(rows):
        ship = f"ship{k % 50}"
        if k >= rows // 2 and k % 10 == 0:
            ship = names[k % len(names)]
        lines.append(
            f"2024-01-01 {k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d},{k % 50},"
            f"37.{k % 1000:03d},23.60,{ship}\n"
        )
    path.write_bytes("".join(lines).encode(encoding))
    return path


@pytest.fixture
def counted(monkeypatch):
    """Whole-file parses (reader._read_table), judgements (decide_file), and files
    Arrow opened itself (the fast UTF-8 path: a parse that failed counted too)."""
    count = {"parses": 0, "judged": 0, "arrow": 0}
    read_table, judge, arrow = reader._read_table, decoding.decide_file, reader.open_for_arrow

    def parse(*a, **k):
        count["parses"] += 1
        return read_table(*a, **k)

    def judged(*a, **k):
        count["judged"] += 1
        return judge(*a, **k)

    def arrow_open(*a, **k):
        count["arrow"] += 1
        return arrow(*a, **k)

    monkeypatch.setattr(reader, "_read_table", parse)
    monkeypatch.setattr(reader, "decide_file", judged)
    monkeypatch.setattr(reader, "open_for_arrow", arrow_open)
    reader._JUDGED.clear()
    reader._VALID_UTF8.clear()
    yield count
    reader._JUDGED.clear()
    reader._VALID_UTF8.clear()


@pytest.mark.parametrize(
    "names, encoding, fallback",
    [(LATIN, "cp1252", {"cp1252"}), (CHINESE, "gb18030", set())],
    ids=["latin1_late", "gb18030_late"],
)
def test_an_ascii_start_with_other_lines_later_is_parsed_once(
    tmp_path, counted, names, encoding, fallback
):
    path = _file(tmp_path / "late.csv", names, encoding)
    whole = read_points(path)
    # one parse, one judgement; before: Arrow's UTF-8 parse failed half way, the file was
    # judged, then parsed again line by line (2 parses). A scan of the bytes (stopping at
    # the first block not valid UTF-8) sent it to the line decoder instead of Arrow.
    assert counted == {"parses": 1, "judged": 1, "arrow": 0}
    assert set(whole.report.get("encoding_fallback", {})) == fallback
    if encoding == "gb18030":
        assert whole.report["encoding"] == "gb18030"
        assert whole.report["warnings"][0] == reader.encoding_note("utf-8", "gb18030")
        ref = read_points(path, encoding="gb18030")  # as it is meant
    else:
        ref = read_points(_file(tmp_path / "utf8.csv", names, "utf-8"))
    pd.testing.assert_frame_equal(whole.points, ref.points)
    assert set(names) <= set(whole.points["name"])
    # wakeline import: streamed in one go (before: the stream failed, then pieces)
    reader._JUDGED.clear()
    reader._VALID_UTF8.clear()
    counted.update(parses=0, judged=0, arrow=0)
    got = import_to_csv(path, tmp_path / "o.csv")
    assert got.report["streamed"] and "pieces" not in got.report
    assert counted["judged"] == 1 and counted["arrow"] == 0
    write_points(whole.points, tmp_path / "w.csv")
    assert (tmp_path / "o.csv").read_bytes() == (tmp_path / "w.csv").read_bytes()
    assert got.report["warnings"] == whole.report["warnings"]
    assert got.report["encoding"] == whole.report["encoding"]
    assert got.report.get("encoding_fallback") == whole.report.get("encoding_fallback")


def test_text_before_the_first_bad_line_not_ascii_is_read_again_as_before(tmp_path, counted):
    """A UTF-8 start with non-ASCII text (``Bjørn``) and GB18030 lines later: GB18030 would
    read the start otherwise, so the decoder does not go on in it; the file is read again
    as the judgement says (the reading before h179)."""
    head = "time,id,lat,lon,name\n2024-01-01 00:00:00,1,37.0,23.6,Bjørn\n".encode()
    body = _file(tmp_path / "b.csv", CHINESE, "gb18030").read_bytes().split(b"\n", 1)[1]
    path = tmp_path / "mixed.csv"
    path.write_bytes(head + body)
    got = read_points(path)
    assert counted["parses"] == 2 and counted["judged"] == 1
    assert len(got.points) == 20_001 and set(CHINESE) <= set(got.points["name"])

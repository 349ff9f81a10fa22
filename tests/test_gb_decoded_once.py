"""A GB18030 file with a UTF-8 line (h157 (5)) is decoded once: the strict first
reading's decoder asks the whole file's judgement (a short read: it stops after
EVIDENCE_LINES failing lines) at the first line that does not decode and, the file being
GB18030, goes on line by line instead of failing the reading; the streamed import
reports the lines read as UTF-8 itself instead of reading the file again in pieces. The
text, quarantine and warnings are those of the whole-file reader, as before."""

import pandas as pd
import pytest

import wakeline.core.io.decoding as decoding
from wakeline.core.io import import_to_csv, read_points, write_points

NAMES = ["远洋一号", "海丰号", "中远之星"]
#: UTF-8 lines: not valid GB18030 (an en dash: E2 80 93), valid GB18030 but plainly
#: UTF-8 (Chinese in UTF-8), and a line valid in neither nor Windows-1252 (81: replaced,
#: its row quarantined).
LINES = {
    "not_gb": "2024-01-02 00:00:00,u,37.5,23.6,Bjørn – Ålesund\n".encode(),
    "utf8_chinese": "2024-01-02 00:00:01,v,37.6,23.6,远洋 UTF-8\n".encode(),
    "replaced": b"2024-01-02 00:00:02,w,37.7,23.6,ok\x81\n",
}


def _file(tmp_path, rows: int, tail: list[bytes]):
    body = "time,id,lat,lon,name\n" + "".join(
        f"2024-01-01 {k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d},{k % 50},"
        f"37.{k % 1000:03d},23.60,{NAMES[k % 3]}\n"
        for k in range(rows)
    )
    p = tmp_path / "gb.csv"
    p.write_bytes(body.encode("gb18030") + b"".join(tail))
    return p


@pytest.fixture
def decoded(monkeypatch):
    """Bytes handed to the line decoder (every reading of a GB18030 file goes through it)."""
    count = {"bytes": 0}
    orig = decoding.LineDecoder.decode

    def counted(self, data=b"", final=False):
        count["bytes"] += len(data)
        return orig(self, data, final)

    monkeypatch.setattr(decoding.LineDecoder, "decode", counted)
    return count


@pytest.mark.parametrize("tail", [["not_gb"], ["utf8_chinese"], ["not_gb", "utf8_chinese"]])
def test_the_streamed_import_decodes_once_and_says_what_the_whole_reader_says(
    tmp_path, decoded, tail
):
    clean = _file(tmp_path, 20_000, [])  # the cost of reading it without those lines
    import_to_csv(clean, tmp_path / "o.csv")
    stream_cost, decoded["bytes"] = decoded["bytes"], 0
    read_points(clean)
    whole_cost, decoded["bytes"] = decoded["bytes"], 0
    p = _file(tmp_path, 20_000, [LINES[k] for k in tail])
    size = p.stat().st_size
    got = import_to_csv(p, tmp_path / "o.csv")
    # decoded once (the whole-file judgement stops after EVIDENCE_LINES failing lines);
    # before: the file again in pieces, strictly then line by line (not_gb: +2 sizes)
    assert decoded["bytes"] < stream_cost + 0.5 * size
    assert got.report["streamed"] and "pieces" not in got.report
    decoded["bytes"] = 0
    whole = read_points(p)
    assert decoded["bytes"] < whole_cost + 0.5 * size  # before (not_gb): +1 size
    write_points(whole.points, tmp_path / "w.csv")
    assert (tmp_path / "o.csv").read_bytes() == (tmp_path / "w.csv").read_bytes()
    assert got.report["warnings"] == whole.report["warnings"]
    assert got.report["encoding_fallback"] == whole.report["encoding_fallback"]
    assert got.report["encoding_fallback"]["utf-8"]["lines"] == len(tail)
    pd.testing.assert_frame_equal(got.quarantine, whole.quarantine)
    names = set(whole.points["name"])
    assert {"Bjørn – Ålesund" if "not_gb" in tail else "远洋 UTF-8", *NAMES} <= names


def test_a_line_nothing_reads_is_quarantined_as_before(tmp_path, decoded):
    p = _file(tmp_path, 2_000, [LINES["not_gb"], LINES["replaced"]])
    got = import_to_csv(p, tmp_path / "o.csv")
    whole = read_points(p)
    assert got.report["warnings"] == whole.report["warnings"]
    assert got.report["encoding_fallback"] == whole.report["encoding_fallback"]
    assert any(w.startswith("some bytes are not valid gb18030") for w in got.report["warnings"])
    pd.testing.assert_frame_equal(got.quarantine, whole.quarantine)
    assert whole.quarantine["line"].tolist() == [2003]


def test_a_file_the_whole_judgement_reads_as_utf8_is_still_read_again(tmp_path, decoded):
    """Mostly UTF-8 after a GB18030 start: the judgement differs, the reading fails and
    the file is read in the judged encoding (as before)."""
    head = "time,id,lat,lon,name\n" + "".join(
        f"2024-01-01 00:00:{k:02d},{k},37.5,23.6,远洋\n" for k in range(3)
    )
    rest = "".join(f"2024-01-01 01:{k // 60:02d}:{k % 60:02d},{k},37.5,23.6,Ålesund – Bjørn\n"
                   for k in range(3000))  # fmt: skip
    p = tmp_path / "mixed.csv"
    p.write_bytes(head.encode("gb18030") + rest.encode())
    whole = read_points(p)
    assert set(whole.points["name"]) == {"Ålesund – Bjørn", "远洋"}


def test_a_quoted_file_read_in_pieces_decodes_once(tmp_path, decoded, monkeypatch):
    """Quotes in the start: the import reads in pieces; the first piece with the line not
    valid GB18030 asks the whole file's judgement once, and no piece is read again."""
    import wakeline.core.io.reader as reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 200_000)

    def quoted(tail):
        p = _file(tmp_path, 20_000, tail)  # every time quoted
        lines = p.read_bytes().split(b"\n")
        body = [lines[0]] + [b'"' + line[:19] + b'"' + line[19:] for line in lines[1:] if line]
        p.write_bytes(b"\n".join(body) + b"\n")
        return p

    clean = quoted([])
    import_to_csv(clean, tmp_path / "o.csv")
    cost, decoded["bytes"] = decoded["bytes"], 0
    p = quoted([LINES["not_gb"]])
    got = import_to_csv(p, tmp_path / "o.csv")
    assert got.report["pieces"] > 3
    assert decoded["bytes"] < cost + 0.5 * p.stat().st_size  # before: + 2 sizes
    whole = read_points(p)
    write_points(whole.points, tmp_path / "w.csv")
    assert (tmp_path / "o.csv").read_bytes() == (tmp_path / "w.csv").read_bytes()
    assert got.report["warnings"] == whole.report["warnings"]
    assert got.report["encoding_fallback"] == whole.report["encoding_fallback"]

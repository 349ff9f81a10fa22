"""h133's #4: a CSV mixing UTF-8 and Latin-1 lines was read entirely as GB18030, garbling
even its valid lines. The encoding is now judged on evidence (core/io/decoding.py): UTF-8
with each line that is not valid UTF-8 read as Windows-1252 and reported, GB18030 only
when it explains the file better; every reader decodes the same way."""

import tempfile
from pathlib import Path
from unittest import mock

import pandas as pd
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.core.io import import_to_csv, read_points, reader, sniff
from wakeline.core.io.decoding import decide, decode_text
from wakeline.core.io.sniff import read_small_table

HEADER = "sensor,batch,time,lon,lat,name"


def _row(i: int, name: str, sensor: str = "S1") -> str:
    return f"{sensor},{i % 3},2024-01-01T00:{i // 60 % 60:02d}:{i % 60:02d}Z,{10 + i * 1e-4:.4f},60.0,{name}"


def _file(tmp: Path, lines: list[bytes], name: str = "m.csv", head: bytes = b"") -> Path:
    path = tmp / name
    path.write_bytes(head + HEADER.encode() + b"\n" + b"\n".join(lines) + b"\n")
    return path


def _fallback_warnings(report: dict) -> list[str]:
    return [w for w in report["warnings"] if w.startswith("text encoding:")]


def test_utf8_and_latin1_lines_one_sensor_each_line_right(tmp_path):
    """h133's repro: 15 UTF-8 rows of sensor "Bjørn", then 15 Latin-1 rows: one sensor,
    3 tracks, a warning naming the Latin-1 lines; before: GB18030, Bj酶rn and Bj鴕n."""
    lines = [_row(i, "x", "Bjørn").encode() for i in range(15)]
    lines += [_row(i, "x", "Bjørn").encode("latin-1") for i in range(15, 30)]
    path = _file(tmp_path, lines)
    assert sniff(path).encoding == "utf-8"
    assert sniff(path).preview[0][0] == "Bjørn"
    r = read_points(path)
    assert r.report["encoding"] == "utf-8"
    assert r.points["sensor"].unique().tolist() == ["Bjørn"]
    assert r.report["tracks"] == 3 and len(r.quarantine) == 0
    assert r.report["encoding_fallback"] == {
        "cp1252": {"lines": 15, "first_lines": [17, 18, 19, 20, 21]}
    }
    (warning,) = _fallback_warnings(r.report)
    assert "15 lines not valid utf-8 were read as Windows-1252" in warning
    assert "lines 17, 18, 19, 20, 21, …" in warning


def test_late_mixed_lines_after_an_ascii_start_whole_and_streamed(tmp_path):
    """bad/mixed_big.csv's shape: an ASCII start longer than the sample, then UTF-8 and
    Latin-1 lines: the valid UTF-8 rows are read right (before: garbled as GB18030), the
    Latin-1 ones too, by the whole-file and the streamed reader alike."""
    lines = [_row(i, "Plain").encode() for i in range(6000)]
    lines += [_row(i, "Bjørnøya").encode() for i in range(6000, 6050)]
    lines += [_row(i, "Bjørnøya").encode("latin-1") for i in range(6050, 6100)]
    path = _file(tmp_path, lines)
    with mock.patch("wakeline.core.io.sniff.SAMPLE_BYTES", 4096):
        whole = read_points(path)
        with mock.patch.object(reader, "STREAM_BYTES", 8192):
            streamed = import_to_csv(path, tmp_path / "out.csv")
    assert whole.points["name"].iloc[6000:].eq("Bjørnøya").all()
    assert whole.report["encoding_fallback"]["cp1252"]["first_lines"][0] == 6052
    out = pd.read_csv(tmp_path / "out.csv")
    assert out["name"].iloc[6000:].eq("Bjørnøya").all() and len(out) == 6100
    # h179: streamed in one go (the decoder asks the judgement at line 6052 and goes on);
    # before, the file was read again in pieces
    assert streamed.report["streamed"] and "pieces" not in streamed.report
    assert streamed.report["encoding_fallback"] == whole.report["encoding_fallback"]
    assert _fallback_warnings(streamed.report) == _fallback_warnings(whole.report)


def test_chinese_gb18030_still_gb18030(tmp_path):
    """GB18030 text (a Chinese header and names) is GB18030 as before: no fallback."""
    text = "批号,时间,经度,纬度,船名\n" + "".join(
        f"{i},2024-05-01 08:00:{i:02d},122.{i:02d},30.0,浙渔号{i}\n" for i in range(40)
    )
    path = tmp_path / "zh.csv"
    path.write_bytes(text.encode("gb18030"))
    r = read_points(path, tz="Asia/Shanghai")
    assert r.report["encoding"] == "gb18030" and "encoding_fallback" not in r.report
    assert r.points["船名"].iloc[3] == "浙渔号3"


def test_utf8_bom_with_a_latin1_line(tmp_path):
    lines = [_row(0, "Å").encode(), _row(1, "Å").encode("latin-1"), _row(2, "ok").encode()]
    path = _file(tmp_path, lines, head=b"\xef\xbb\xbf")
    sn = sniff(path)
    assert sn.bom and sn.columns[0] == "sensor"
    r = read_points(path)
    assert r.points["name"].tolist() == ["Å", "Å", "ok"]
    assert r.report["encoding_fallback"]["cp1252"]["first_lines"] == [3]


def test_utf16_with_bom_is_utf16(tmp_path):
    text = HEADER + "\n" + "\n".join(_row(i, "Bjørn 浙") for i in range(10)) + "\n"
    path = tmp_path / "u16.csv"
    path.write_bytes(text.encode("utf-16"))
    r = read_points(path)
    assert r.report["encoding"] == "utf-16" and "encoding_fallback" not in r.report
    assert r.points["name"].eq("Bjørn 浙").all()


def test_a_line_neither_reads_is_quarantined_and_a_quarantined_latin1_line_keeps_its_text(
    tmp_path,
):
    lines = [_row(0, "é").encode(), _row(1, "\x81").encode("latin-1")]
    lines += [_row(2, "é").encode("latin-1").replace(b",10.", b",1O.")]
    r = read_points(_file(tmp_path, lines))
    assert r.report["rows_imported"] + r.report["rows_quarantined"] == 3
    q = r.quarantine.set_index("line")
    assert q.loc[3, "reason"] == "bytes not valid utf-8"
    assert q.loc[4, "reason"] == "unparsable lon" and q.loc[4, "text"].endswith(",é")


def test_the_explicit_encoding_is_obeyed(tmp_path):
    """--encoding utf-8 on a mixed file: as named, the Latin-1 lines quarantined."""
    lines = [_row(0, "é").encode(), _row(1, "é").encode("latin-1")]
    r = read_points(_file(tmp_path, lines), encoding="utf-8")
    assert r.quarantine["line"].tolist() == [3] and "encoding_fallback" not in r.report


def test_small_tables_decode_the_same_way(tmp_path):
    path = tmp_path / "t.csv"
    path.write_bytes("a,b\n1,Bjørn\n".encode() + "2,Bjørn\n".encode("latin-1"))
    assert read_small_table(path, ("a",), "test")["b"].tolist() == ["Bjørn", "Bjørn"]


def test_pure_latin1_text_reads_as_windows_1252():
    data = "a,b\n1,Bjørn\n2,Ærø\n3,ok\n".encode("latin-1")
    enc, text, dec = decide(data)
    assert enc == "utf-8" and text == data.decode("latin-1")
    assert dec.fallbacks.counts == {"cp1252": 2}


def test_line_decoder_is_the_same_in_any_chunks():
    data = "x\r\nBjørn\r\n".encode() + "Bjørn\r\nø\rø\n".encode("latin-1") + "中\n".encode()
    whole, dec = decode_text(data, "utf-8")
    for size in (1, 2, 3, 5, 7):
        from wakeline.core.io.decoding import LineDecoder

        d = LineDecoder("utf-8")
        parts = [d.decode(data[k : k + size]) for k in range(0, len(data), size)]
        assert "".join(parts) + d.decode(b"", final=True) == whole
        assert d.fallbacks.first == dec.fallbacks.first == {"cp1252": [3, 4, 5]}


# --- properties ------------------------------------------------------------------------

_UTF8_NAMES = st.sampled_from(["Bjørn", "Ærøskøbing", "São Tomé", "海巡", "Ålesund °", "naïve"])
_LATIN1_NAMES = st.sampled_from(["Bjørn", "Tromsø", "Málaga", "Müller", "Åre", "Façade"])
_GB_NAMES = st.sampled_from(["浙渔号", "东海航迹", "船", "闽渔"])
_LINE = st.tuples(st.sampled_from(["ascii", "utf8", "latin1", "gb"]), st.integers(0, 5))


def _mixed_file(kinds: list[tuple[str, str]]) -> tuple[list[bytes], list[str]]:
    raw, texts = [], []
    for i, (kind, name) in enumerate(kinds):
        text = _row(i, name)
        enc = {"ascii": "ascii", "utf8": "utf-8", "latin1": "latin-1", "gb": "gb18030"}[kind]
        raw.append(text.encode(enc))
        texts.append(name)
    return raw, texts


@st.composite
def _kinds(draw):
    n = draw(st.integers(1, 60))
    out = []
    for _ in range(n):
        kind = draw(st.sampled_from(["ascii", "utf8", "latin1", "gb"]))
        names = {"ascii": st.just("ok"), "utf8": _UTF8_NAMES}
        names.update({"latin1": _LATIN1_NAMES, "gb": _GB_NAMES})
        out.append((kind, draw(names[kind])))
    return out


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kinds=_kinds(), sample=st.sampled_from([1 << 18, 600]), stream=st.sampled_from([0, 2000]))
def test_mixed_lines_never_lose_a_line_nor_garble_utf8(kinds, sample, stream):
    """Random mixtures of ASCII, UTF-8, Latin-1 and GB18030 lines: points + quarantine =
    lines, whole or streamed in pieces; when most non-ASCII bytes are in UTF-8 lines,
    every UTF-8 line reads exactly, every Latin-1 line reads as Latin-1, every GB18030
    line as GB18030 (h148; before: garbled as Windows-1252), and a warning per fallback
    names its lines."""
    raw, names = _mixed_file(kinds)
    with tempfile.TemporaryDirectory() as tmp:
        path = _file(Path(tmp), raw)
        with mock.patch("wakeline.core.io.sniff.SAMPLE_BYTES", sample):
            if stream:
                with mock.patch.object(reader, "STREAM_BYTES", stream):
                    res = import_to_csv(path, Path(tmp) / "o.csv")
                rep = res.report
                got = pd.read_csv(Path(tmp) / "o.csv", keep_default_na=False)["name"].tolist()
            else:
                res = read_points(path)
                rep = res.report
                got = res.points["name"].tolist()
    assert rep["rows_imported"] + rep["rows_quarantined"] == len(kinds)
    high = {k: 0 for k in ("utf8", "latin1", "gb")}
    for (kind, _), line in zip(kinds, raw, strict=True):
        if kind != "ascii":
            high[kind] += sum(b >= 0x80 for b in line)
    if high["utf8"] > high["latin1"] + high["gb"]:  # mostly UTF-8: UTF-8 decides
        assert rep["encoding"] == "utf-8"
        assert rep["rows_quarantined"] == 0 and len(got) == len(kinds)
        # one Chinese character alone (2 bytes) is no evidence against Latin-1 (h160: 'ÇÃ'
        # pairs as GB2312 too): read as Windows-1252, as any failing line
        read_as = [
            ("latin1", name.encode("gb18030").decode("cp1252"))
            if kind == "gb" and len(name) < 2
            else (kind, name)
            for kind, name in kinds
        ]
        for (kind, name), read in zip(read_as, got, strict=True):
            assert read == name, (kind, name, read)  # GB18030 lines too (h148)
        fell = rep.get("encoding_fallback", {})
        for kind, enc, label in (
            ("latin1", "cp1252", "Windows-1252"),
            ("gb", "gb18030", "GB18030"),
        ):
            lines = sum(k == kind for k, _ in read_as)
            assert fell.get(enc, {}).get("lines", 0) == lines
            said = [w for w in _fallback_warnings(rep) if f"read as {label}" in w]
            assert len(said) == bool(lines)
        assert len(_fallback_warnings(rep)) == len(fell)
    if high["gb"] and not high["utf8"] and not high["latin1"]:  # GB18030 only: as before
        assert rep["encoding"] == "gb18030" and got == names


def test_a_large_gb18030_file_stays_gb18030(tmp_path):
    """A GB18030 file larger than the sample, Chinese on every line: more failing lines
    than are looked at (EVIDENCE_LINES) in one chunk; their share stands for the rest
    (the first cut judged it UTF-8 and garbled the header)."""
    rows = "批号,时间,经度,纬度,船名\n" + "".join(
        f"{i % 50},2024-05-01 08:{i // 60 % 60:02d}:{i % 60:02d},122.{i % 100:02d},30.0,浙渔号\n"
        for i in range(3000)
    )
    path = tmp_path / "gb.csv"
    path.write_bytes(rows.encode("gb18030"))
    with (
        mock.patch("wakeline.core.io.sniff.SAMPLE_BYTES", 4096),
        mock.patch("wakeline.core.io.decoding.EVIDENCE_LINES", 100),
    ):
        assert sniff(path).columns[0] == "批号"
        r = read_points(path, tz="Asia/Shanghai")
    assert r.report["encoding"] == "gb18030" and "encoding_fallback" not in r.report
    assert r.points["船名"].eq("浙渔号").all() and len(r.points) == 3000


# --- h148: Chinese lines in GBK inside UTF-8, UTF-8 lines inside GB18030 ----------------

_SHIPS = ["浙岱渔03856", "鲁荣渔2682", "闽狮渔06677", "苏连渔128", "辽大金渔1515"]


def _ships_file(tmp: Path, gbk_rows: set[int], n: int = 60) -> Path:
    """A UTF-8 export (Chinese ship names) with some rows appended by a GBK tool."""
    out = [b"sensor,batch,time,lon,lat,name,note"]
    for i in range(n):
        name = _SHIPS[i % len(_SHIPS)]
        row = _row(i, name, "AIS") + ",渔船"
        out.append(row.encode("gbk" if i in gbk_rows else "utf-8"))
    path = tmp / "ships.csv"
    path.write_bytes(b"\r\n".join(out) + b"\r\n")
    return path


def test_gbk_rows_in_a_utf8_file_are_read_as_gb18030_and_named(tmp_path):
    """Rows a GBK tool appended to a UTF-8 file: each read as GB18030 (its non-ASCII
    bytes pair as GB2312 characters), named in a warning with the encoding; whole and
    streamed alike (before: garbled as Windows-1252, "Õã´ÔÓæ")."""
    gbk = {7, 8, 30, 31, 32, 59}
    path = _ships_file(tmp_path, gbk)
    whole = read_points(path)
    assert whole.report["encoding"] == "utf-8" and len(whole.quarantine) == 0
    names = whole.points["name"].tolist()
    assert names == [_SHIPS[i % len(_SHIPS)] for i in range(60)]
    assert whole.points["note"].eq("渔船").all()
    assert whole.report["encoding_fallback"] == {
        "gb18030": {"lines": 6, "first_lines": [9, 10, 32, 33, 34]}
    }
    (warning,) = _fallback_warnings(whole.report)
    assert "6 lines not valid utf-8 were read as GB18030 (Chinese)" in warning
    assert "(lines 9, 10, 32, 33, 34, …)" in warning
    with mock.patch.object(reader, "STREAM_BYTES", 1500):
        streamed = import_to_csv(path, tmp_path / "out.csv")
    assert streamed.report["streamed"] and "pieces" not in streamed.report  # h179: once
    assert pd.read_csv(tmp_path / "out.csv")["name"].tolist() == names
    assert streamed.report["encoding_fallback"] == whole.report["encoding_fallback"]
    assert _fallback_warnings(streamed.report) == [warning]


def test_a_latin1_line_beside_gbk_lines_stays_windows_1252(tmp_path):
    """A line whose non-ASCII bytes do not pair as GB2312 (Latin-1 letters alone, or
    a GBK character outside GB2312) is Windows-1252 as before: two warnings."""
    lines = [_row(0, "浙渔").encode(), _row(1, "浙渔").encode("gbk")]
    lines += [_row(2, "Bjørn").encode("latin-1"), _row(3, "Ærø").encode("latin-1")]
    lines += [_row(4, "镕").encode("gbk")]  # 镕 (E946): GBK, not GB2312
    r = read_points(_file(tmp_path, lines))
    assert r.points["name"].tolist()[:4] == ["浙渔", "浙渔", "Bjørn", "Ærø"]
    assert r.report["encoding_fallback"] == {
        "gb18030": {"lines": 1, "first_lines": [3]},
        "cp1252": {"lines": 3, "first_lines": [4, 5, 6]},
    }
    assert len(_fallback_warnings(r.report)) == 2


def _gb_file(tmp: Path, utf8_rows: dict[int, str], n: int = 80) -> Path:
    out = ["批号,时间,经度,纬度,船名".encode("gb18030")]
    for i in range(n):
        name = utf8_rows.get(i, "浙渔号")
        row = f"{i % 5},2024-05-01 08:{i // 60:02d}:{i % 60:02d},122.{i:02d},30.0,{name}"
        out.append(row.encode("utf-8" if i in utf8_rows else "gb18030"))
    path = tmp / "gb.csv"
    path.write_bytes(b"\n".join(out) + b"\n")
    return path


def test_utf8_rows_in_a_gb18030_file_are_read_as_utf8_and_named(tmp_path):
    """UTF-8 rows in a file judged GB18030: read as UTF-8 where, read as GB18030, their
    non-ASCII bytes would not pair as GB2312 characters and, as UTF-8, they hold a 3- or
    4-byte sequence and no C1 control (h160), and named in a warning; whole, streamed
    and in the sniff's preview alike (before: garbled, no warning). A UTF-8 name that
    happens to pair (海巡, 3 % of two-character names) stays GB18030, and so does one of
    2-byte sequences only (Tromsø Ø: GBK characters outside GB2312, 職 = C2 9A, are such
    UTF-8 by chance)."""
    rows = {5: "Ålesund €", 6: "浙渔", 40: "Tromsø Ø", 41: "海巡"}
    path = _gb_file(tmp_path, rows)
    assert sniff(path).encoding == "gb18030"
    whole = read_points(path, tz="Asia/Shanghai")
    assert whole.report["encoding"] == "gb18030" and len(whole.quarantine) == 0
    got = whole.points["船名"].tolist()
    assert [got[i] for i in (5, 6)] == ["Ålesund €", "浙渔"]
    assert got[40] == "Tromsø Ø".encode().decode("gb18030")
    assert got[41] == "海巡".encode().decode("gb18030") and got[0] == "浙渔号"
    assert whole.report["encoding_fallback"] == {"utf-8": {"lines": 2, "first_lines": [7, 8]}}
    (warning,) = _fallback_warnings(whole.report)
    assert "2 lines valid UTF-8 (as gb18030 not Chinese text) were read as UTF-8" in warning
    assert "(lines 7, 8)" in warning
    with mock.patch.object(reader, "STREAM_BYTES", 1000):
        streamed = import_to_csv(path, tmp_path / "out.csv", tz="Asia/Shanghai")
    # streamed once, the UTF-8 lines reported by the streamed reader (h167; before, the
    # file was read again in pieces)
    assert streamed.report["streamed"] and "pieces" not in streamed.report
    assert pd.read_csv(tmp_path / "out.csv")["船名"].tolist() == got
    assert streamed.report["encoding_fallback"] == whole.report["encoding_fallback"]


def test_a_gb18030_file_whose_lines_fail_is_judged_again_as_before(tmp_path):
    """Read strictly first: a line not valid GB18030 still sends the file to the whole
    file's judgement (here: GB18030, that line read as Windows-1252)."""
    path = _gb_file(tmp_path, {})
    path.write_bytes(
        path.read_bytes()
        + _row(0, "x").encode()[:0]
        + "9,2024-05-01 09:00:00,122.5,30.0,\xd8\n".encode("latin-1")
    )
    r = read_points(path, tz="Asia/Shanghai")
    assert r.report["encoding"] == "gb18030"
    assert r.report["encoding_fallback"] == {"cp1252": {"lines": 1, "first_lines": [82]}}
    assert r.points["船名"].iloc[-1] == "Ø"

"""The line decoder finds a chunk's failing lines at once (h148: numpy over the bytes, runs
decoded at C speed) where it went line by line: the same text, fallbacks (counts and line
numbers), evidence and line count as the line-by-line decoder it replaces
(tests/decoding_reference.py) for every mixture of lines, decoded whole, in chunks of any
size, and in pieces as the streamed reader reads them (a fresh decoder per piece)."""

from unittest import mock

import decoding_reference as ref
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from wakeline.core.io import decoding
from wakeline.core.io.decoding import LineDecoder, merge_fallbacks

_UTF8 = ["Bjørn", "Ærøskøbing", "海巡 01", "𝔘 ship", "São Tomé", "naïve", "€uro"]
_CP1252 = ["Bjørn", "Tromsø", "Málaga", "ÆØ", "Façade €", "œuvre", "“quoted”", "NAVEGAÇÃO"]
_CP1252 += ["Associação", "öß", "ÇÃÇÃ"]  # GB2312 pairs, 2 or 4 in a row (h160)
_GB = ["浙渔号", "东海航迹", "闽渔", "船 1", "鱻", "€", "職位", "聯位"]  # 職: valid UTF-8 C2 9A
_ODD = [  # not valid UTF-8 in ways a lead/continuation count alone does not see
    b"\xc0\xaf",  # overlong /
    b"\xe0\x80\xaf",  # overlong
    b"\xed\xa0\x80",  # a surrogate
    b"\xf4\x90\x80\x80",  # above U+10FFFF
    b"\xf5\x80\x80\x80",
    b"\xc3",  # cut short
    b"\xe6\xb5",
    b"\x80",  # a lone continuation
    b"\xc3\xa9\xa9",
    b"\x81\x8d\x8f\x90\x9d",  # what Windows-1252 leaves undefined
    b"\xfe\xff",
    b"\x810",  # a GB18030 four-byte start cut short
]


@st.composite
def _line(draw) -> bytes:
    kind = draw(st.sampled_from(["ascii", "utf8", "cp1252", "gb", "odd", "bytes"]))
    if kind == "ascii":
        return draw(st.sampled_from([b"", b"a,b,1.5", b"S1,0,2024-01-01T00:00:00Z,10.0,60.0"]))
    if kind == "utf8":
        return draw(st.sampled_from(_UTF8)).encode()
    if kind == "cp1252":
        return b"x," + draw(st.sampled_from(_CP1252)).encode("cp1252")
    if kind == "gb":
        return b"1," + draw(st.sampled_from(_GB)).encode("gb18030")
    if kind == "odd":
        return b"a" + draw(st.sampled_from(_ODD)) + draw(st.sampled_from([b"", b"b", b"\xa1"]))
    raw = draw(st.binary(min_size=1, max_size=12))
    return raw.replace(b"\n", b"").replace(b"\r", b"")


@st.composite
def _text(draw) -> bytes:
    lines = draw(st.lists(_line(), min_size=1, max_size=40))
    ends = draw(st.lists(st.sampled_from([b"\n", b"\r\n", b"\r"]), min_size=len(lines)))
    data = b"".join(a + b for a, b in zip(lines, ends, strict=False))
    if draw(st.booleans()):  # no line end at the end
        data = data.rstrip(b"\r\n")
    if draw(st.integers(0, 5)) == 0:
        data = b"\xef\xbb\xbf" + data
    return data


def _state(dec) -> tuple:
    ev = dec.evidence
    return (
        dict(dec.fallbacks.counts),
        {k: list(v) for k, v in dec.fallbacks.first.items()},
        list(dec.fallbacks.counts),  # the order the encodings came in
        (ev.good, ev.bad, ev.gb, ev.bad_lines),
        dec.line,
    )


def _chunked(cls, data: bytes, size: int, enc: str = "utf-8") -> tuple[str, tuple]:
    dec = cls(enc)
    text = "".join(dec.decode(data[k : k + size]) for k in range(0, len(data), size))
    return text + dec.decode(b"", final=True), _state(dec)


def _pieces(cls, data: bytes, lines_per_piece: int, enc: str) -> tuple[list[str], dict]:
    """A fresh decoder per piece of whole lines (the streamed reader's pieces)."""
    lines = data.splitlines(keepends=True)
    texts, infos = [], []
    for k in range(0, len(lines), lines_per_piece):
        dec = cls(enc)
        texts.append(dec.decode(b"".join(lines[k : k + lines_per_piece]), final=True))
        first = {h: v for h, v in dec.fallbacks.first.items() if h != "replaced"}
        counts = {h: v for h, v in dec.fallbacks.counts.items() if h != "replaced"}
        infos.append(({h: {"lines": counts[h], "first_lines": first[h]} for h in counts}, k + 1))
    return texts, merge_fallbacks(infos)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    data=_text(),
    size=st.sampled_from([1, 3, 7, 64, 1 << 20]),
    evidence_lines=st.sampled_from([5000, 2, 0]),
    per_piece=st.integers(1, 9),
    enc=st.sampled_from(["utf-8", "gb18030"]),
)
@example(
    data=b"a\r\nb\xf8\r\n\xf8\r\r\n\xc6\xd8\n", size=1, evidence_lines=1, per_piece=2, enc="utf-8"
)
def test_the_fast_decoder_decodes_as_the_line_by_line_one(
    data, size, evidence_lines, per_piece, enc
):
    with mock.patch.object(decoding, "EVIDENCE_LINES", evidence_lines):
        whole_new = _chunked(LineDecoder, data, len(data) + 1, enc)
        whole_old = _chunked(ref.LineDecoder, data, len(data) + 1, enc)
        assert whole_new == whole_old
        assert _chunked(LineDecoder, data, size, enc) == _chunked(ref.LineDecoder, data, size, enc)
        new, old = (
            _pieces(LineDecoder, data, per_piece, enc),
            _pieces(ref.LineDecoder, data, per_piece, enc),
        )
        assert new == old


def test_a_windows_1252_file_is_one_decode_per_run(tmp_path):
    """Every line Windows-1252 (and a few neither reads): the text and line numbers of the
    line-by-line decoder, the lines counted once per chunk."""
    rows = [f"S{i % 7},{i},Bjørn Ærø {i}".encode("cp1252") for i in range(3000)]
    rows[10] += b"\x81"
    rows[2000] = "中".encode() + rows[2000]
    data = b"h,e,ad\r\n" + b"\r\n".join(rows) + b"\r\n"
    new, old = _chunked(LineDecoder, data, 4096), _chunked(ref.LineDecoder, data, 4096)
    assert new == old
    assert new[1][0] == {"cp1252": 2999, "replaced": 1}
    assert new[1][1]["replaced"] == [12] and new[1][1]["cp1252"][:2] == [2, 3]


def test_the_tail_of_the_evidence_is_added_in_order():
    """Past EVIDENCE_LINES the failing lines add at the rate so far, in order: read late
    (the whole-file reader never reads it), the same float as added line by line."""
    data = b"".join(
        (b"\xc6\xd8\xc6\xd8" if i % 3 else b"\xf8 a \xf8\xf8") + b"\n" for i in range(200)
    )
    with mock.patch.object(decoding, "EVIDENCE_LINES", 7):
        new, old = _chunked(LineDecoder, data, 50), _chunked(ref.LineDecoder, data, 50)
    assert new == old and 0 < new[1][3][2] < new[1][3][1]


def test_every_gb2312_pair_decodes_as_gb18030():
    """The evidence counts a line whose non-ASCII bytes pair as GB2312 as GB18030 without
    decoding it: every such pair decodes."""
    for lead in [*range(0xA1, 0xAA), *range(0xB0, 0xF8)]:
        for trail in range(0xA1, 0xFF):
            bytes([lead, trail]).decode("gb18030")

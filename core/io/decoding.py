"""How a text file's bytes become text: one decision per file and one line decoder, for
every reader (sniff's sample and the import dialog's preview, the whole-file reader, the
streamed and piece readers of import, clean and batch, the quarantine's line texts, NMEA
logs and small tables).

The decision (:func:`decide`, over a sample or :func:`decide_file` over the whole file):
text valid UTF-8 is UTF-8. Otherwise the lines that are not valid UTF-8 are weighed
against those that are: GB18030 when the failing lines hold most of the non-ASCII bytes
*and* at least :data:`GB_SHARE` of their non-ASCII bytes pair up as GB2312 characters
(lead A1-A9 or B0-F7, trail A1-FE: Chinese text, whose characters are two high bytes). A
Latin-1 line fails that: its accented letters are single high bytes beside ASCII
(``Bjørn`` is ``F8 72``, which GB18030 reads as 鴕, one character eating the ``r``).
Otherwise UTF-8, and each line that is not valid UTF-8 is decoded on its own: as GB18030
when its non-ASCII bytes pair as GB2312 characters (the same test, line by line: rows a
GBK tool appended) and it holds :data:`GB_RUN` (4) of them in a row (two Chinese
characters: Latin-1 accents pair too, ``NAVEGAÇÃO`` has ``C7 C3``, ``Associação`` ``E7
E3``, but rarely four in a row; h160), else as Windows-1252 ("Latin-1" as Windows writes it; it is Latin-1
for every printable character), and reported: per encoding how many lines and the first
line numbers (:func:`fallback_warning`). A line that none reads (a byte Windows-1252
leaves undefined: 81, 8D, 8F, 90, 9D) keeps U+FFFD for its bad bytes and its row is
quarantined ("bytes not valid utf-8"), as before. In a file read as GB18030 a line that
is valid UTF-8, whose non-ASCII bytes do not pair as GB2312 characters, that holds a 3-
or 4-byte UTF-8 sequence (lead E0-F4) and whose UTF-8 text has no C1 control character
(U+0080-U+009F) is read as UTF-8, reported the same way (GB18030 reads nearly any byte
pair, so UTF-8 text decodes as GB18030 too, garbled). Anything less stays GB18030
(h160): GBK characters outside GB2312 are valid 2-byte UTF-8 by chance (``職`` is ``C2
9A``, a C1 control), so UTF-8 of Latin letters only stays GB18030, garbled; so do ``é``
(``C3 A9``, one GB2312 pair) and about 3 % of two-character Chinese names in UTF-8 (they
pair whole); a line that is not valid GB18030 is read as UTF-8 if it is valid UTF-8, else
as Windows-1252.

Why a reported fallback rather than quarantining those lines: a Latin-1 line in a UTF-8
file is a whole, good row (an export appended by a Windows tool); the fallback keeps its
point, reads its text right (``Bjørn`` stays one sensor), and the warning names the
lines, so nothing is lost and nothing is garbled silently. A UTF-8 line is never read
otherwise: valid UTF-8 with non-ASCII bytes is almost never an accident of another
encoding. Reading the whole file as GB18030 (what the importer did) garbled even the
valid lines.

The line decoder (:class:`LineDecoder`) decodes whole lines chunk by chunk with the
codec's C decoder; only a chunk that fails (or in GB18030 holds non-ASCII bytes) is
looked into: numpy finds the lines read otherwise (in GB18030 the failing ones by
decoding on from each), and the runs between them and the runs of lines read alike are
decoded at C speed, not line by line (h148: a file wholly Windows-1252, 2 M rows, about
20 times faster; bench/bench_decoding.py). A clean UTF-8 file pays nothing. It is also
a Python codec (``codec_name``): ``wakeline-lines-utf-8`` decodes as above wherever a
codec name is taken (``io.TextIOWrapper``, ``pandas.read_csv``). UTF-16 and UTF-32 text
(a byte order mark) and an encoding the user names are decoded as they were: strictly,
undecodable bytes quarantined. A file judged GB18030 is read first strictly but for its
UTF-8 lines (``fail``: a line not valid GB18030 sends it to the whole file's judgement,
as before; the decoder asks it there, ``judge``, and when it says GB18030 goes on line by
line: the text the reading again gave, without reading the file again, h167).
"""

import codecs
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: The encoding a line that is not valid UTF-8 is read in (then reported).
FALLBACK = "cp1252"
#: What the warning calls it.
FALLBACK_LABEL = "Windows-1252 (Latin-1)"
#: Line numbers kept (and named in the warning) per fallback.
FIRST_LINES = 5
#: The share of the failing lines' non-ASCII bytes that must pair as GB2312 characters
#: for GB18030 to explain the file.
GB_SHARE = 0.8
#: Failing lines looked at before the whole-file judgement stops (a GB18030 file after an
#: ASCII start fails on every Chinese line: enough is enough).
EVIDENCE_LINES = 5_000
#: Bytes :func:`decide_file` reads at a time.
JUDGE_CHUNK = 256 * 1024
#: The prefix of the codecs this module registers (``wakeline-lines-utf-8``).
PREFIX = "wakeline-lines-"

_HIGH = bytes(range(128, 256))
_GB2312_PAIR = re.compile(rb"[\xa1-\xa9\xb0-\xf7][\xa1-\xfe]")
#: A run of :data:`GB_RUN` non-ASCII bytes (with every byte paired as GB2312: two Chinese
#: characters in a row).
GB_RUN = 4
_HIGH_RUN = re.compile(rb"[\x80-\xff]{%d}" % GB_RUN)
#: C1 control characters: in text read as UTF-8 they say it was not UTF-8.
_C1 = re.compile("[\x80-\x9f]")
_LINE_END = re.compile(rb"[\r\n]")
#: The first window decoded after a failing line (bytes; then 4 times larger each time).
_WINDOW = 256


def _table(*spans: tuple[int, int], dtype=bool, value=True) -> np.ndarray:
    out = np.zeros(256, dtype)
    for lo, hi in spans:
        out[lo : hi + 1] = value
    return out


#: UTF-8: the length of the sequence a byte starts (1: a continuation byte; 0: a byte
#: UTF-8 never has), and the range of the byte after a lead (E0, ED, F0, F4 narrow it:
#: no overlong forms, no surrogates, nothing above U+10FFFF).
_SEQ = _table((0x80, 0xBF), dtype=np.int8, value=1)
_SEQ[0xC2:0xE0], _SEQ[0xE0:0xF0], _SEQ[0xF0:0xF5] = 2, 3, 4
_SEQ_LO, _SEQ_HI = np.full(256, 0x80, np.uint8), np.full(256, 0xBF, np.uint8)
_SEQ_LO[0xE0], _SEQ_HI[0xED], _SEQ_LO[0xF0], _SEQ_HI[0xF4] = 0xA0, 0x9F, 0x90, 0x8F
#: GB2312's characters: lead A1-A9 or B0-F7, trail A1-FE (as :data:`_GB2312_PAIR`).
_GB_LEAD = _table((0xA1, 0xA9), (0xB0, 0xF7))
_GB_TRAIL = _table((0xA1, 0xFE))
#: The bytes Windows-1252 leaves undefined.
_CP1252_UNDEFINED = _table((0x81, 0x81), (0x8D, 0x8D), (0x8F, 0x90), (0x9D, 0x9D))
#: What a line is read as otherwise than in the primary encoding (the fallbacks' names;
#: :meth:`LineDecoder._lines_fast`).
_READ_AS = (FALLBACK, "gb18030", "utf-8", "replaced")
_CP, _GB, _U8, _REP = range(4)


def _distinct(sorted_values: np.ndarray) -> np.ndarray:
    """The distinct values of a sorted array."""
    return sorted_values[np.r_[True, sorted_values[1:] != sorted_values[:-1]]]


class _Bytes:
    """A segment of whole lines as numpy sees it: its non-ASCII bytes (``high``: their
    positions, ``value``: the bytes, ``line``: their lines) and its line ends (``ends``:
    positions of CR and LF; a line lies between two, an empty one between CR and LF)."""

    def __init__(self, seg: bytes, lines_only: bool = False) -> None:
        arr = np.frombuffer(seg, np.uint8)
        self.n = len(arr)
        self.arr = arr
        self.ends = np.flatnonzero((arr == 0x0A) | (arr == 0x0D))
        if lines_only:
            return
        self.high = np.flatnonzero(arr >= 0x80)
        self.value = arr[self.high]
        self.line = np.searchsorted(self.ends, self.high)  # 0-based, in this segment

    def span(self, lines: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Start and end (its line end, or the segment's end) of each line."""
        ends = np.append(self.ends, self.n)
        starts = np.append(0, self.ends + 1)
        return starts[lines], ends[lines]

    def per_line(self, where=None) -> np.ndarray:
        """Non-ASCII bytes (those ``where`` is true) per line."""
        lines = self.line if where is None else self.line[where]
        return np.bincount(lines, minlength=len(self.ends) + 1)

    def utf8_errors(self) -> np.ndarray:
        """Which non-ASCII bytes make their line invalid UTF-8: a line with none is valid
        UTF-8 (every non-ASCII byte in a well-formed sequence), a line with any is not."""
        pad = np.zeros(self.n + 6, np.uint8)
        pad[3 : self.n + 3] = self.arr
        at = self.high + 3
        seq = _SEQ[self.value]
        nxt = [pad[at + k] for k in (1, 2, 3)]
        cont = [(b & 0xC0) == 0x80 for b in nxt]
        lead = (
            ((seq == 2) & cont[0])
            | ((seq == 3) & cont[0] & cont[1])
            | ((seq == 4) & cont[0] & cont[1] & cont[2])
        )
        lead &= (nxt[0] >= _SEQ_LO[self.value]) & (nxt[0] <= _SEQ_HI[self.value])
        prev = [_SEQ[pad[at - k]] for k in (1, 2, 3)]
        claimed = (
            (prev[0] >= 2)
            | ((prev[1] >= 3) & (prev[0] == 1))
            | ((prev[2] == 4) & (prev[1] == 1) & (prev[0] == 1))
        )
        ok = np.where(seq == 1, claimed, lead)  # seq 0 (never UTF-8): lead is false
        return ~ok

    def long_runs(self) -> np.ndarray:
        """Runs of at least :data:`GB_RUN` consecutive non-ASCII bytes per line."""
        pos = self.high
        if not len(pos):
            return np.zeros(len(self.ends) + 1, np.int64)
        start = np.flatnonzero(np.r_[True, pos[1:] != pos[:-1] + 1])
        length = np.diff(np.r_[start, len(pos)])
        long = start[length >= GB_RUN]
        return np.bincount(self.line[long], minlength=len(self.ends) + 1)

    def gb2312_misses(self) -> np.ndarray:
        """Which non-ASCII bytes keep their line from reading as GB2312 characters only: its
        non-ASCII bytes, run by run, pair up as lead and trail (what ``2 *
        len(_GB2312_PAIR.findall(line)) == high`` says)."""
        pos, value = self.high, self.value
        if not len(pos):
            return np.zeros(0, bool)
        joined = pos[1:] == pos[:-1] + 1  # byte k+1 follows byte k
        first = np.flatnonzero(np.r_[True, ~joined])
        run = np.cumsum(np.r_[True, ~joined]) - 1
        even = (np.arange(len(pos)) - first[run]) % 2 == 0
        paired = _GB_LEAD[value] & np.r_[joined, False] & _GB_TRAIL[np.r_[value[1:], 0]]
        return even & ~paired


def _gb_line(line: bytes, high: int) -> bool:
    """Whether a line not valid UTF-8 is read as GB18030: its non-ASCII bytes pair as
    GB2312 characters and it holds :data:`GB_RUN` of them in a row (two Chinese
    characters; Latin-1 pairs by chance: ``ÇÃ`` is ``C7 C3``, ``çã`` ``E7 E3``)."""
    return 2 * len(_GB2312_PAIR.findall(line)) == high and _HIGH_RUN.search(line) is not None


def _utf8_line(line: bytes) -> str | None:
    """A line valid in GB18030 read as UTF-8, if it is plainly UTF-8: valid, with a
    sequence of 3 or 4 bytes (lead E0-F4) and no C1 control character in its text (GBK
    characters outside GB2312, ``職`` = ``C2 9A``, are valid 2-byte UTF-8 by chance)."""
    if max(line, default=0) < 0xE0:
        return None
    try:
        text = line.decode("utf-8")
    except UnicodeDecodeError:
        return None
    return None if _C1.search(text) else text


def _high(data: bytes) -> int:
    """Bytes of ``data`` above ASCII."""
    return 0 if data.isascii() else len(data) - len(data.translate(None, _HIGH))


class Evidence:
    """What the lines said about the encoding: non-ASCII bytes in lines that decoded in
    the primary encoding (``good``), in lines that did not (``bad``), and of those in
    lines that read as GB18030 in GB2312's characters (``gb``).

    After :data:`EVIDENCE_LINES` failing lines each further one adds its share at the
    rate so far (``gb += high * gb / bad_before``); those lines are kept (``_tail``) and
    added up, in order, when ``gb`` is read (the whole-file reader never reads it)."""

    def __init__(self) -> None:
        self.good = 0
        self.bad = 0
        self._gb: float = 0
        self.bad_lines = 0
        self._tail: list[np.ndarray] = []

    @property
    def gb(self) -> float:
        if self._tail:
            highs = np.concatenate(self._tail).tolist()
            before, g = self.bad - sum(highs), self._gb
            if g:  # 0 stays 0
                for high in highs:
                    before += high
                    g += high * g / max(before - high, 1)
            self._gb, self._tail = g, []
        return self._gb

    @gb.setter
    def gb(self, value: float) -> None:
        self.gb  # noqa: B018 (the tail first)
        self._gb = value

    def choice(self, primary: str = "utf-8") -> str:
        """The encoding that explains the text best (``primary`` or ``gb18030``)."""
        if primary != "utf-8" or not self.bad:
            return primary
        if self.bad > self.good and self.gb >= GB_SHARE * self.bad:
            return "gb18030"
        return primary


@dataclass
class Fallbacks:
    """The lines decoded otherwise than in the primary encoding: per fallback encoding
    (or ``"replaced"``: U+FFFD for their bad bytes, quarantined) the count and the first
    :data:`FIRST_LINES` line numbers (1-based physical lines of the decoded input)."""

    counts: dict[str, int] = field(default_factory=dict)
    first: dict[str, list[int]] = field(default_factory=dict)

    def add(self, how: str, line: int) -> None:
        self.counts[how] = self.counts.get(how, 0) + 1
        kept = self.first.setdefault(how, [])
        if len(kept) < FIRST_LINES:
            kept.append(line)

    def add_many(self, how: str, lines: np.ndarray) -> None:
        """:meth:`add` for each of ``lines`` (in order)."""
        self.counts[how] = self.counts.get(how, 0) + len(lines)
        kept = self.first.setdefault(how, [])
        kept += lines[: max(FIRST_LINES - len(kept), 0)].tolist()

    def report(self) -> dict:
        """For the import report: ``{encoding: {"lines": n, "first_lines": [...]}}``."""
        return {
            how: {"lines": n, "first_lines": list(self.first[how])}
            for how, n in self.counts.items()
            if how != "replaced"
        }


def fallback_warning(primary: str, info: dict) -> list[str]:
    """The import's warnings for the lines read in a fallback encoding (``info``: the
    report's ``encoding_fallback``); one per fallback encoding, naming it and the lines."""
    out = []
    for how, got in info.items():
        n, first = int(got["lines"]), sorted(got["first_lines"])[:FIRST_LINES]
        label = LABELS.get(how, how)
        some = ", ".join(f"{k:,}" for k in first) + (", …" if n > len(first) else "")
        lines, were = ("line", "was") if n == 1 else ("lines", "were")
        if how == "utf-8" and primary != "utf-8":
            what = f"{lines} valid UTF-8 (as {primary} not Chinese text) {were} read as {label}"
        else:
            what = f"{lines} not valid {primary} {were} read as {label}"
        out.append(
            f"{FALLBACK_MARK} {n:,} {what} ({lines} {some}); if that is wrong, give the "
            "file's encoding (--encoding, e.g. gb18030, utf-16, latin-1)"
        )
    return out


#: The encodings (codec names) whose text a UTF-8 byte order mark may stand before: the
#: mark is dropped, not read as characters (``EF BB BF`` is 锘 and half a character in
#: GB18030, "ï»¿" in Windows-1252).
BOM_DROPPED = frozenset(("gb18030", "gbk", "gb2312", "cp1252", "latin-1", "iso8859-1", "cp936"))
#: The prefix of the codecs that drop a leading UTF-8 byte order mark, then decode in an
#: encoding the user named (``--encoding gbk`` on a GBK file with a UTF-8 BOM:
#: ``wakeline-bom-gbk``).
BOM_PREFIX = "wakeline-bom-"


def bom_codec(encoding: str) -> str:
    """The codec name that reads ``encoding`` after a UTF-8 byte order mark (dropped):
    ``encoding`` itself when it is UTF-8 (whose codecs drop it or read it as U+FEFF,
    which the readers drop), UTF-16/32 or not ASCII-based."""
    try:
        name = codecs.lookup(encoding).name
    except LookupError:
        return encoding
    if name.startswith(("utf-8", "utf-16", "utf-32", BOM_PREFIX)) or not line_decodable(name):
        return encoding
    return BOM_PREFIX + name


def plain_encoding(encoding: str) -> str:
    """``encoding`` without :data:`BOM_PREFIX` (what the report names)."""
    return encoding.removeprefix(BOM_PREFIX)


#: What the warnings call the fallback encodings.
LABELS = {FALLBACK: FALLBACK_LABEL, "gb18030": "GB18030 (Chinese)", "utf-8": "UTF-8"}
#: How every fallback warning starts (pieces make it again from summed counts).
FALLBACK_MARK = "text encoding:"


def merge_fallbacks(infos: list[tuple[dict, int]]) -> dict:
    """One ``encoding_fallback`` of the pieces' (each with the file line its piece starts
    on, 1-based): counts summed, first line numbers made file lines."""
    out: dict = {}
    for info, first_line in infos:
        for how, got in info.items():
            have = out.setdefault(how, {"lines": 0, "first_lines": []})
            have["lines"] += int(got["lines"])
            have["first_lines"] += [k + first_line - 1 for k in got["first_lines"]]
    for have in out.values():
        have["first_lines"] = sorted(have["first_lines"])[:FIRST_LINES]
    return out


class LineDecoder(codecs.IncrementalDecoder):
    """Bytes to text in ``encoding``, whole lines at a time; a line that does not decode
    (or is better read so: module docstring) is decoded in a fallback encoding (recorded
    in ``fallbacks``), else with U+FFFD for its bad bytes (recorded as ``"replaced"``).
    ``evidence`` gathers what the lines said (:class:`Evidence`). ``fail``: a line that
    does not decode raises UnicodeDecodeError instead (the strict first reading), unless
    ``judge`` (the whole file's judgement, :func:`decide_file`), asked at the first such
    line, names this encoding: then that line and the rest are decoded as without
    ``fail`` — the text the reader's next reading (the judged encoding, line by line)
    gives, without decoding the file again (h157). A UTF-8 byte order mark at the start
    is decoded as U+FEFF (the readers drop it)."""

    def __init__(
        self,
        encoding: str = "utf-8",
        errors: str = "strict",
        fail: bool = False,
        judge: Callable[[], str] | None = None,
        switch: bool = False,
    ) -> None:
        super().__init__(errors)
        self.fail = fail
        self.judge = judge
        #: A UTF-8 reading may go on as GB18030 (:meth:`_switch`).
        self.switch = switch
        self.judged: str | None = None
        self.encoding = codecs.lookup(encoding).name
        self._decode = codecs.lookup(encoding).decode  # takes a memoryview: no copy
        self.chain = (FALLBACK,) if self.encoding == "utf-8" else ("utf-8", FALLBACK)
        #: :meth:`decode_utf8`: lines valid UTF-8 are handed on as the bytes they are.
        self._raw = False
        self.reset()

    def decode_utf8(self, data: bytes = b"", final: bool = False) -> bytes:
        """:meth:`decode`, the text as UTF-8 bytes (without a byte order mark): in UTF-8
        the lines that decode are handed on as they came (checked, not decoded and
        encoded again: a clean file's reading costs little more than Arrow's own, h179)."""
        self._raw = True
        try:
            out = self.decode(data, final)
        finally:
            self._raw = False
        return out if isinstance(out, bytes) else out.encode("utf-8")

    def reset(self) -> None:
        self._parts: list[bytes] = []
        self._start = True
        self._last_cr = False
        self.line = 0  # line ends passed: the next line's number is line + 1
        self.fallbacks = Fallbacks()
        self.evidence = Evidence()
        self._ascii = True  # every byte decoded so far was ASCII
        #: A UTF-8 byte order mark was dropped before text in another encoding.
        self.bom_dropped = False

    def getstate(self) -> tuple[bytes, int]:
        return b"".join(self._parts), 0

    def setstate(self, state: tuple[bytes, int]) -> None:
        self._parts = [state[0]] if state[0] else []

    def decode(self, data: bytes = b"", final: bool = False) -> str:
        data = bytes(data)
        if self._start and (data or final):
            if not self._parts and len(data) < 3 and not final and codecs.BOM_UTF8.startswith(data):
                self._parts.append(data)  # maybe the start of a BOM: wait for more
                return ""
            data, self._parts = b"".join(self._parts) + data, []
            self._start = False
            if data.startswith(codecs.BOM_UTF8) and (
                self.encoding == "utf-8" or self.encoding in BOM_DROPPED
            ):
                # UTF-8's byte order mark; before GB18030 text (a GBK file saved by a tool
                # that adds a UTF-8 BOM, operator test 7 D1) it is no character either
                self.bom_dropped = self.encoding != "utf-8"
                self._ascii = False
                rest = self.decode(data[3:], final)
                return "\ufeff" + (rest.decode("utf-8") if isinstance(rest, bytes) else rest)
        if final:
            whole, self._parts = b"".join(self._parts) + data, []
            return self._lines(whole)
        ends = max(data.rfind(b"\n"), data.rfind(b"\r"))
        if ends < 0:
            if data:
                self._parts.append(data)
            return ""
        whole = b"".join(self._parts) + data[: ends + 1]
        self._parts = [data[ends + 1 :]] if ends + 1 < len(data) else []
        return self._lines(whole)

    def _count(self, seg: bytes, a: int, b: int) -> None:
        """Pass the line ends of ``seg[a:b]`` (LF, CRLF, CR; a CRLF across two parts once)."""
        if a >= b:
            return
        n = seg.count(b"\n", a, b) + seg.count(b"\r", a, b) - seg.count(b"\r\n", a, b)
        if self._last_cr and seg[a] == 0x0A:
            n -= 1
        self.line += n
        self._last_cr = seg[b - 1] == 0x0D

    def _lines(self, seg: bytes) -> str:
        """Whole lines decoded: at C speed; where that fails (or in GB18030, where a
        line may be UTF-8) the lines read otherwise are found at once and decoded in runs
        (:meth:`_lines_fast`); in another encoding one by one (:meth:`_lines_scan`)."""
        raw = self._raw and self.encoding == "utf-8"
        if raw and seg.isascii():  # valid UTF-8 as it is: no decoding, no encoding again
            self._count(seg, 0, len(seg))
            return seg
        try:
            text = self._decode(seg)[0]
        except UnicodeDecodeError as exc:
            at = exc.start
        else:
            if self.encoding != "gb18030" or seg.isascii():
                self.evidence.good += _high(seg)
                self._ascii = self._ascii and seg.isascii()
                self._count(seg, 0, len(seg))
                return seg if raw else text
            at = None
        if self.encoding in ("utf-8", "gb18030"):
            out = self._lines_fast(seg, at)
            if out is not None:
                return out
        if at is None:  # GB18030 that reads well as it is
            self.evidence.good += _high(seg)
            self._count(seg, 0, len(seg))
            return text
        return self._lines_scan(seg, at)

    def _lines_fast(self, seg: bytes, at: int | None) -> str | None:
        """Whole lines, some of which are read otherwise than in the primary encoding,
        decoded without a step per line. The lines that fail: in UTF-8 found by numpy
        (:meth:`_Bytes.utf8_errors`), in GB18030 by decoding from each failing line on
        (``at``: the first; None: none fail). Each is read as GB18030 when its non-ASCII
        bytes pair as GB2312 characters (the whole-file evidence's test, line by line),
        as UTF-8 when valid UTF-8 (in GB18030), else as Windows-1252, else with U+FFFD
        (quarantined); in UTF-8 GB18030 only with 4 non-ASCII bytes in a row
        (:meth:`_Bytes.long_runs`). In GB18030 a line that decodes but is valid UTF-8,
        does not pair as GB2312 and is plainly UTF-8 (:func:`_utf8_line`) is read as
        UTF-8 too. The runs of lines between them are decoded
        in the primary encoding, the runs of lines read alike (with only ASCII between
        them) as one, each at C speed; line numbers and evidence as
        :meth:`_lines_scan` (tests/test_decoding_fast.py). None if nothing is read
        otherwise, or if a run that should decode does not (then that is used)."""
        if self.encoding == "utf-8":
            b = _Bytes(seg)
            per_line = b.per_line()
            lines = failing = np.flatnonzero(b.per_line(b.utf8_errors()))
            paired = b.per_line(b.gb2312_misses())[failing] == 0  # the evidence's test
            chinese = paired & (b.long_runs()[failing] > 0)  # not Latin-1 pairs by chance
            undefined = b.per_line(_CP1252_UNDEFINED[b.value])[failing]
            how = np.where(chinese, _GB, np.where(undefined > 0, _REP, _CP))
        else:
            b, per_line, failing, lines, how = self._gb_lines(seg, at)
            paired = np.zeros(len(failing), bool)  # GB2312 pairs decode: these do not
        if not len(lines):
            return None
        if len(failing) and self.fail:
            start = int(b.span(failing[:1])[0][0])
            ascii_before = self._ascii and seg[:start].isascii()
            if self._fails():
                if ascii_before and self._switch():
                    return self._lines(seg)  # the text so far is GB18030's too: go on
                raise UnicodeDecodeError(self.encoding, seg, start, start + 1, "a line not valid")
        starts, stops = b.span(lines)
        # runs: lines read alike, with only ASCII (line ends) between them
        before = np.r_[0, np.cumsum(per_line)]  # non-ASCII bytes before each line
        gap_high = before[lines[1:]] - before[lines[:-1] + 1]
        alike = (how[1:] == how[:-1]) & (how[1:] != _REP) & (gap_high == 0)
        first = np.flatnonzero(np.r_[True, ~alike])
        last = np.r_[first[1:] - 1, len(lines) - 1]
        view, out, pos = memoryview(seg), [], 0
        try:
            for a, z, h in zip(
                starts[first].tolist(), stops[last].tolist(), how[first].tolist(), strict=True
            ):
                out.append(self._decode(view[pos:a])[0])
                if h == _REP:
                    out.append(seg[a:z].decode(self.encoding, errors="replace"))
                else:
                    out.append(seg[a:z].decode(_READ_AS[h]))
                pos = z
            out.append(self._decode(view[pos:])[0])
        except UnicodeDecodeError:
            return None
        # line numbers: 1 + the line ends before (CRLF once, also across chunks)
        ends = b.ends
        prev = ends - 1
        after_cr = b.arr[np.maximum(prev, 0)] == 0x0D
        after_cr[prev < 0] = self._last_cr
        passed = np.r_[0, np.cumsum(~((b.arr[ends] == 0x0A) & after_cr))]
        numbers = self.line + 1 + passed[lines]
        for h in dict.fromkeys(how[np.r_[True, how[1:] != how[:-1]]].tolist()):
            self.fallbacks.add_many(_READ_AS[h], numbers[how == h])
        # evidence: of the failing lines, as line by line
        ev = self.evidence
        high = per_line[failing]
        exact = min(max(EVIDENCE_LINES - ev.bad_lines, 0), len(failing))
        if exact:  # GB2312 pairs all decode as GB18030
            ev.gb += int(high[:exact][paired[:exact]].sum())
        ev.bad += int(high.sum())
        ev.bad_lines += len(failing)
        if exact < len(failing):
            ev._tail.append(high[exact:])
        ev.good += int(per_line.sum()) - int(high.sum())
        self.line += int(passed[-1])
        self._last_cr = seg[-1] == 0x0D
        return "".join(out)

    def _gb_lines(self, seg: bytes, at: int | None) -> tuple:
        """In GB18030: the lines that fail (``at``: the first; None: none) and those valid
        UTF-8 whose non-ASCII bytes do not pair as GB2312 characters and that are plainly
        UTF-8 (:func:`_utf8_line`), and what each is
        read as. A line is looked at one by one only if no byte rules UTF-8 out (a lead
        byte not followed by a continuation byte, or a continuation byte after ASCII:
        nearly every line of Chinese text in GB18030 has one)."""
        b = _Bytes(seg, lines_only=True)
        arr = b.arr
        high = arr >= 0x80
        # non-ASCII bytes per line, from its runs of them (few: Chinese text is runs)
        edge = np.empty(b.n + 1, bool)
        edge[0], edge[-1] = high[0], high[-1]
        np.not_equal(high[1:], high[:-1], out=edge[1:-1])
        run = np.flatnonzero(edge).reshape(-1, 2)  # [start, end) of each run
        run_line = np.searchsorted(b.ends, run[:, 0])
        lines = len(b.ends) + 1
        per_line = np.bincount(run_line, run[:, 1] - run[:, 0], lines).astype(np.int64)
        failing = np.zeros(0, np.int64) if at is None else self._failing(seg, at, b)
        lead, cont = arr >= 0xC0, (arr & 0xC0) == 0x80
        broken = np.empty(b.n, bool)  # only ever inside a run
        broken[:-1] = lead[:-1] & ~cont[1:]
        broken[-1] = lead[-1]
        broken[1:] |= cont[1:] & ~high[:-1]
        broken[0] |= cont[0]
        maybe = per_line > 0
        if len(run):
            broken_runs = np.logical_or.reduceat(broken, run[:, 0])
            maybe &= np.bincount(run_line, broken_runs, lines) == 0
        maybe[failing] = False
        better = []
        maybe = np.flatnonzero(maybe)
        starts, stops = b.span(maybe)
        for j, s, e in zip(maybe.tolist(), starts.tolist(), stops.tolist(), strict=True):
            line = seg[s:e]
            if 2 * len(_GB2312_PAIR.findall(line)) != per_line[j] and _utf8_line(line):
                better.append(j)
        lines = np.union1d(failing, np.array(better, np.int64))
        how = np.full(len(lines), _U8)
        fails = np.flatnonzero(np.isin(lines, failing))
        starts, stops = b.span(lines[fails])
        for k, s, e in zip(fails.tolist(), starts.tolist(), stops.tolist(), strict=True):
            how[k] = self._read_as(seg[s:e])
        return b, per_line, failing, lines, how

    @staticmethod
    def _read_as(line: bytes) -> int:
        """What a line not valid GB18030 is read as: UTF-8, Windows-1252 or neither."""
        for how in (_U8, _CP):
            try:
                line.decode(_READ_AS[how])
                return how
            except UnicodeDecodeError:
                pass
        return _REP

    def _failing(self, seg: bytes, at: int, b: "_Bytes") -> np.ndarray:
        """The lines (of ``b``) that do not decode, the first at byte ``at``: decoded
        from each failing line's end on in windows of whole lines that grow while they
        decode (a failed decode copies its input into the exception: a window, not the
        rest of the chunk, per failing line)."""
        view, found = memoryview(seg), []
        while True:
            found.append(at)
            end = _LINE_END.search(seg, at)
            pos = end.start() if end else len(seg)
            window = _WINDOW
            while pos < len(seg):
                end = _LINE_END.search(seg, pos + window)
                stop = end.end() if end else len(seg)
                try:
                    self._decode(view[pos:stop])
                except UnicodeDecodeError as exc:
                    at = pos + exc.start
                    break
                pos, window = stop, window * 4
            else:
                return np.searchsorted(b.ends, np.array(found, np.int64))

    def _lines_scan(self, seg: bytes, at: int) -> str:
        """Whole lines decoded line by line from the failing line (``at``) on. After a
        failing line the rest is decoded in windows of whole lines that grow while they
        decode (a failed decode copies its input into the exception: a window, not the
        rest of the chunk, per failing line)."""
        view, out, pos = memoryview(seg), [], 0
        bad_before = self.evidence.bad
        while True:
            start = max(pos - 1, seg.rfind(b"\n", pos, at), seg.rfind(b"\r", pos, at)) + 1
            out.append(self._decode(view[pos:start])[0])
            self._count(seg, pos, start)
            end = _LINE_END.search(seg, at)
            pos = end.start() if end else len(seg)
            out.append(self._bad(seg[start:pos]))
            window = _WINDOW
            while pos < len(seg):
                end = _LINE_END.search(seg, pos + window)
                stop = end.end() if end else len(seg)
                try:
                    out.append(self._decode(view[pos:stop])[0])
                except UnicodeDecodeError as exc:
                    at = pos + exc.start
                    break
                self._count(seg, pos, stop)
                pos, window = stop, window * 4
            else:
                self.evidence.good += _high(seg) - (self.evidence.bad - bad_before)
                return "".join(out)

    def _fails(self) -> bool:
        """Whether a line that does not decode raises (``fail``; asks ``judge`` once)."""
        if self.fail and self.judge is not None:
            judge, self.judge = self.judge, None
            self.judged = codecs.lookup(judge()).name
            self.fail = self.judged != self.encoding
        return self.fail

    def _switch(self) -> bool:
        """A UTF-8 reading whose text so far was all ASCII, of a file the judgement calls
        GB18030 (an ASCII start, Chinese lines later): it goes on as GB18030, line by line
        — the text the reading again in GB18030 gives (ASCII reads alike in both), without
        reading the file again (h179). False when that is not the case."""
        if not self.switch or self.encoding != "utf-8" or self.judged != "gb18030":
            return False
        self.encoding = "gb18030"
        self._decode = codecs.lookup("gb18030").decode
        self.chain = ("utf-8", FALLBACK)
        self.fail = False
        return True

    def _bad(self, line: bytes) -> str:
        """One line (no line end) that does not decode in the primary encoding."""
        if self._fails():
            raise UnicodeDecodeError(self.encoding, line, 0, len(line), "a line not valid")
        number = self.line + 1
        self._last_cr = False
        high = _high(line)
        ev = self.evidence
        ev.bad += high
        ev.bad_lines += 1
        if ev.bad_lines > EVIDENCE_LINES:  # enough looked at: their share stands for the rest
            ev.gb += high * ev.gb / max(ev.bad - high, 1)
        elif 2 * len(_GB2312_PAIR.findall(line)) == high:
            try:
                line.decode("gb18030")
                ev.gb += high
            except UnicodeDecodeError:
                pass
        chain = self.chain
        if self.encoding == "utf-8" and _gb_line(line, high):
            chain = ("gb18030", *chain)  # Chinese text: two characters in a row at least
        for enc in chain:
            try:
                text = line.decode(enc)
            except UnicodeDecodeError:
                continue
            self.fallbacks.add(enc, number)
            return text
        self.fallbacks.add("replaced", number)
        return line.decode(self.encoding, errors="replace")


def codec_name(encoding: str) -> str:
    """The codec that decodes as :class:`LineDecoder` in ``encoding``."""
    return PREFIX + codecs.lookup(encoding).name


def lines_codec(encoding: str, given: bool) -> str:
    """The codec name a reader decodes ``encoding`` with: the line decoder's for an
    encoding the file was judged in (UTF-8, GB18030), else ``encoding`` itself (one the
    user named, UTF-16 and UTF-32)."""
    if given or not line_decodable(encoding):
        return encoding
    return codec_name(encoding)


def line_decodable(encoding: str) -> bool:
    """Whether the line decoder takes ``encoding`` (ASCII-based: line ends are bytes)."""
    try:
        name = codecs.lookup(encoding).name
    except LookupError:
        return False
    return not name.startswith(("utf-16", "utf-32")) and "\n".encode(name) == b"\n"


class _BomDecoder(codecs.IncrementalDecoder):
    """Drops a leading UTF-8 byte order mark, then decodes in ``base``."""

    base = "utf-8"

    def __init__(self, errors: str = "strict") -> None:
        super().__init__(errors)
        self._inner = codecs.getincrementaldecoder(self.base)(errors)
        self._head = b""  # the start, until it is known whether it is the mark

    def decode(self, data: bytes = b"", final: bool = False) -> str:
        if self._head is not None:
            head = self._head + bytes(data)
            if len(head) < 3 and not final and codecs.BOM_UTF8.startswith(head):
                self._head = head
                return ""
            self._head = None
            data = head.removeprefix(codecs.BOM_UTF8)
        return self._inner.decode(data, final)

    def reset(self) -> None:
        self._inner.reset()
        self._head = b""

    def getstate(self) -> tuple[bytes, int]:
        return self._head or b"", 0

    def setstate(self, state: tuple[bytes, int]) -> None:
        self._head = state[0] if state[0] else (b"" if self._head is not None else None)


def _search_bom(name: str) -> codecs.CodecInfo | None:
    encoding = codecs.lookup(name[len(BOM_PREFIX) :]).name
    base = codecs.lookup(encoding)
    decoder = type("Decoder", (_BomDecoder,), {"base": encoding})

    def decode(data: bytes, errors: str = "strict") -> tuple[str, int]:
        return base.decode(bytes(data).removeprefix(codecs.BOM_UTF8), errors)[0], len(data)

    return _codec(BOM_PREFIX + encoding, base, decode, decoder)


def _codec(name: str, base: codecs.CodecInfo, decode, decoder) -> codecs.CodecInfo:
    """A codec named ``name`` that decodes with ``decode`` / ``decoder`` and encodes (and
    streams) as ``base``."""
    return codecs.CodecInfo(
        name=name,
        encode=base.encode,
        decode=decode,
        incrementalencoder=base.incrementalencoder,
        incrementaldecoder=decoder,
        streamreader=base.streamreader,
        streamwriter=base.streamwriter,
    )


def _search(name: str) -> codecs.CodecInfo | None:
    name = name.replace("_", "-")
    if name.startswith(BOM_PREFIX):
        return _search_bom(name)
    if not name.startswith(PREFIX):
        return None
    encoding = codecs.lookup(name[len(PREFIX) :]).name
    base = codecs.lookup(encoding)

    class Decoder(LineDecoder):
        def __init__(self, errors: str = "strict") -> None:
            super().__init__(encoding, errors)

    def decode(data: bytes, errors: str = "strict") -> tuple[str, int]:
        return Decoder(errors).decode(data, final=True), len(data)

    return _codec(PREFIX + encoding, base, decode, Decoder)


codecs.register(_search)


def decode_text(data: bytes, encoding: str) -> tuple[str, LineDecoder]:
    """``data`` (whole lines) decoded by the line decoder, and the decoder (what fell back)."""
    dec = LineDecoder(encoding)
    return dec.decode(data, final=True), dec


def decide(data: bytes) -> tuple[str, str, LineDecoder]:
    """The encoding that explains ``data`` (a sample of whole lines) best, its text, and
    the decoder that made it (its ``fallbacks``)."""
    text, dec = decode_text(data, "utf-8")
    enc = dec.evidence.choice()
    if enc != "utf-8":
        text, dec = decode_text(data, enc)
    return enc, text, dec


def decide_file(path: Path, compression: str | None) -> str:
    """:func:`decide` over the whole file, read in chunks (only its failing lines are
    looked at one by one; after :data:`EVIDENCE_LINES` of them it stops)."""
    from wakeline.core.io.compressed import open_data

    dec = LineDecoder("utf-8")
    with open_data(path, compression) as fh:
        while True:
            raw = fh.read(JUDGE_CHUNK)  # small: it stops soon after EVIDENCE_LINES
            dec.decode(raw, final=not raw)
            if not raw or dec.evidence.bad_lines >= EVIDENCE_LINES:
                break
    return dec.evidence.choice()

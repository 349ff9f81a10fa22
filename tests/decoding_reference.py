"""The line decoder as it was before h148 (core/io/decoding.py at 438de21): line by line
from the first failing line on. The reference the fast decoder is compared with
(tests/test_decoding_fast.py, bench/bench_decoding.py): the same text, line numbers and
evidence for every input. Its module constants are read from core's (EVIDENCE_LINES may
be patched there).

With h148's two rules, line by line: in UTF-8 a failing line whose non-ASCII bytes pair
as GB2312 characters is read as GB18030 (``_bad``); in GB18030 every line is looked at
(``_lines_each``): one valid UTF-8 whose non-ASCII bytes do not pair so is read as
UTF-8. With h160's stronger evidence: the UTF-8 failing line also holds 4 non-ASCII bytes
in a row (two Chinese characters; else Windows-1252), and the GB18030 line read as UTF-8
also holds a 3- or 4-byte sequence (lead E0-F4) and no C1 control character as UTF-8."""

import codecs
import re
from dataclasses import dataclass, field

from wakeline.core.io import decoding as _core

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
_LINE_END = re.compile(rb"[\r\n]")
#: The first window decoded after a failing line (bytes; then 4 times larger each time).
_WINDOW = 256


def _high(data: bytes) -> int:
    """Bytes of ``data`` above ASCII."""
    return 0 if data.isascii() else len(data) - len(data.translate(None, _HIGH))


@dataclass
class Evidence:
    """What the lines said about the encoding: non-ASCII bytes in lines that decoded in
    the primary encoding (``good``), in lines that did not (``bad``), and of those in
    lines that read as GB18030 in GB2312's characters (``gb``)."""

    good: int = 0
    bad: int = 0
    gb: float = 0
    bad_lines: int = 0

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

    def report(self) -> dict:
        """For the import report: ``{encoding: {"lines": n, "first_lines": [...]}}``."""
        return {
            how: {"lines": n, "first_lines": list(self.first[how])}
            for how, n in self.counts.items()
            if how != "replaced"
        }


class LineDecoder(codecs.IncrementalDecoder):
    """Bytes to text in ``encoding``, whole lines at a time; a line that does not decode
    is decoded by the first of ``fallbacks`` that reads it (recorded in ``fallbacks``),
    else with U+FFFD for its bad bytes (recorded as ``"replaced"``). ``evidence``
    gathers what the lines said (:class:`Evidence`). A UTF-8 byte order mark at the
    start is decoded as U+FEFF (the readers drop it)."""

    def __init__(self, encoding: str = "utf-8", errors: str = "strict") -> None:
        super().__init__(errors)
        self.encoding = codecs.lookup(encoding).name
        self._decode = codecs.lookup(encoding).decode  # takes a memoryview: no copy
        self.chain = (FALLBACK,) if self.encoding == "utf-8" else ("utf-8", FALLBACK)
        self.reset()

    def reset(self) -> None:
        self._parts: list[bytes] = []
        self._start = True
        self._last_cr = False
        self.line = 0  # line ends passed: the next line's number is line + 1
        self.fallbacks = Fallbacks()
        self.evidence = Evidence()

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
            # a UTF-8 BOM before GB18030 text is dropped too (operator test 7, D1)
            if self.encoding in ("utf-8", "gb18030") and data.startswith(codecs.BOM_UTF8):
                return "\ufeff" + self.decode(data[3:], final)
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

    def _lines_each(self, seg: bytes) -> str:
        out, pos = [], 0
        while pos < len(seg):
            end = _LINE_END.search(seg, pos)
            stop = end.start() if end else len(seg)
            line = seg[pos:stop]
            try:
                text = line.decode(self.encoding)
            except UnicodeDecodeError:
                text = self._bad(line)
            else:
                high = _high(line)
                self.evidence.good += high
                if high and 2 * len(_GB2312_PAIR.findall(line)) != high:
                    try:
                        as_utf8 = line.decode("utf-8")
                    except UnicodeDecodeError:
                        as_utf8 = None
                    if (
                        as_utf8 is not None
                        and re.search(rb"[\xe0-\xf4]", line)
                        and not re.search("[\x80-\x9f]", as_utf8)
                    ):
                        text = as_utf8
                        self.fallbacks.add("utf-8", self.line + 1)
                self._count(seg, pos, stop)
            out.append(text)
            if end:
                out.append(seg[stop : stop + 1].decode())
                self._count(seg, stop, stop + 1)
            pos = stop + 1
        return "".join(out)

    def _lines(self, seg: bytes) -> str:
        if self.encoding == "gb18030":
            return self._lines_each(seg)
        """Whole lines decoded: at C speed, and where that fails line by line from the
        failing line on. After a failing line the rest is decoded in windows of whole
        lines that grow while they decode (a failed decode copies its input into the
        exception: a window, not the rest of the chunk, per failing line)."""
        try:
            text = self._decode(seg)[0]
        except UnicodeDecodeError as exc:
            at = exc.start
        else:
            self.evidence.good += _high(seg)
            self._count(seg, 0, len(seg))
            return text
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

    def _bad(self, line: bytes) -> str:
        """One line (no line end) that does not decode in the primary encoding."""
        number = self.line + 1
        self._last_cr = False
        high = _high(line)
        ev = self.evidence
        ev.bad += high
        ev.bad_lines += 1
        if ev.bad_lines > _core.EVIDENCE_LINES:  # enough looked at: their share stands for the rest
            ev.gb += high * ev.gb / max(ev.bad - high, 1)
        elif 2 * len(_GB2312_PAIR.findall(line)) == high:
            try:
                line.decode("gb18030")
                ev.gb += high
            except UnicodeDecodeError:
                pass
        chain = self.chain
        if (
            self.encoding == "utf-8"
            and 2 * len(_GB2312_PAIR.findall(line)) == high
            and re.search(rb"[\x80-\xff]{4}", line)
        ):
            chain = ("gb18030", *chain)
        for enc in chain:
            try:
                text = line.decode(enc)
            except UnicodeDecodeError:
                continue
            self.fallbacks.add(enc, number)
            return text
        self.fallbacks.add("replaced", number)
        return line.decode(self.encoding, errors="replace")

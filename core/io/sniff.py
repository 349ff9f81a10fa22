"""Look at the first bytes of a file: compression, binary or text, encoding, line endings,
delimiter, header, and whether it is a raw AIS NMEA log rather than a CSV."""

import codecs
import contextlib
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wakeline.core.errors import InputError, NotTrackData
from wakeline.core.io.compressed import (  # noqa: F401  (packed_kind: batch's)
    compression_of,
    is_tar,
    open_data,
    packed_kind,
)
from wakeline.core.io.decoding import bom_codec, decide, decide_file, decode_text, lines_codec


def listed_headers(names, most: int = 40, each: int = 40) -> str:
    """Header names for a message: each cut to ``each`` characters, at most ``most`` of
    them (a JSON document or a binary file read as a header is one huge "name")."""
    names = [str(n) for n in names]
    shown = [n if len(n) <= each else n[: each - 1] + "…" for n in names[:most]]
    more = f" … and {len(names) - most:,} more" if len(names) > most else ""
    inside = [d for d in DELIMITERS if len(names) == 1 and d in names[0]]
    if inside:
        # a header read whole as one name (--delimiter ';' on a comma-separated file): its
        # names listed with commas looked like the columns found (operator test 10)
        most_often = max(inside, key=names[0].count)
        d = "tab" if most_often == "\t" else f"'{most_often}'"
        return f"one column, {shown[0]!r} (separated by {d}? check --delimiter)"
    return ", ".join(shown) + more


#: The first bytes of an OLE2 compound file (Excel .xls, Word .doc of Office 97-2003).
OLE2_MAGIC = bytes.fromhex("D0CF11E0A1B11AE1")

SAMPLE_BYTES = 256 * 1024
#: Data rows of the sampled start kept to judge columns by their values (``Sniff.sample``).
SAMPLE_ROWS = 1000
ENCODINGS = ("utf-8", "gb18030")
DELIMITERS = (",", ";", "\t", "|")
#: An AIS sentence (``!AIVDM``, ``!AIVDO``) under any AIS talker of IEC 61162-1: AI (mobile),
#: AB/AD/AS (base stations), AN (aid to navigation), AR (receiver), AT (transmitter), AX
#: (repeater), BS (base station, older logs) and SA (shore station): Norwegian and Danish
#: shore networks log ``!BSVDM`` and ``!ABVDM``.
NMEA_SENTENCE = re.compile(r"[!$](?:A[BDINRSTX]|BS|SA)VD[MO],")
_NMEA = NMEA_SENTENCE
#: A GeoJSON document: a JSON object whose sample names a Feature or FeatureCollection.
GEOJSON_START = re.compile(r"^\s*\{")
_GEOJSON_TYPE = re.compile(r'"type"\s*:\s*"(FeatureCollection|Feature)"')
#: The start of a GPX document: an XML declaration and comments, then ``<gpx``.
GPX_START = re.compile(r"^\s*(<\?xml[^>]*\?>\s*)?(<!--.*?-->\s*)*<gpx[\s>]", re.S)
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")
#: A block of NUL bytes (64 or more in a row).
_NUL_BLOCK = re.compile(rb"\x00{64,}")
#: Excel's first line naming the delimiter (``sep=;``), before the header.
_EXCEL_SEP = re.compile(r'"?sep=(.)"?')


@dataclass(frozen=True)
class Sniff:
    """What the start of a file says about how to read it."""

    path: Path
    compression: str | None  # "gzip", "bz2", "xz", "zstd", "zip" or None (plain text)
    encoding: str  # a Python codec name: "utf-8" (BOM allowed), "gb18030", "utf-16"...
    delimiter: str  # ",", ";", "\t", "|" or " " (see ``blank_runs``)
    has_header: bool
    skip_rows: int  # physical lines before the first data row (blank lines and the header)
    columns: tuple[str, ...]  # header names, or col1..colN when the file has no header
    preview: tuple[tuple[str, ...], ...]  # first data rows split on the delimiter (for dialogs)
    bom: bool = False  # the file starts with a byte order mark
    line_ending: str = "\n"  # "\n", "\r\n" or "\r" (of the first line)
    has_quotes: bool = False  # a '"' occurs in the sample
    kind: str = "csv"  # "csv", "nmea" (raw AIS sentences), "gpx" or "geojson" (tracks)
    encoding_given: bool = False  # the caller named the encoding
    ascii: bool = True  # the sample is plain ASCII (any ASCII-based encoding reads it)
    excel_sep: bool = False  # the file starts with Excel's "sep=;" line (skipped)
    #: Lines above the header (a title: "Radar track export 2024-05-01"), skipped:
    #: (physical line number, 1-based; text).
    title_lines: tuple[tuple[int, str], ...] = ()
    skip_rows_given: int | None = None  # the caller's skip_rows (None: detected)
    #: Blank lines above the header (or above the first row of a file without one): with
    #: the title lines, Excel's "sep=" line and the header, every line before the data.
    blank_above_header: int = 0
    #: More data rows than ``preview`` (up to :data:`SAMPLE_ROWS` of the sampled start),
    #: split the same way: what the reader judges columns by their values with (an id
    #: column no name says, a column of clock times beside a date).
    sample: tuple[tuple[str, ...], ...] = ()
    #: A blank-separated file aligned in columns (``delimiter`` " "): each run of blanks
    #: (spaces, tabs) is one separator, blanks at a line's start and end are none
    #: (:func:`blank_layout`); the reader parses the lines so changed (:func:`blank_runs`).
    blank_runs: bool = False
    #: ... and a date and the clock after it (``2024-01-01 00:00:00``) are one cell.
    join_date_clock: bool = False
    #: ... or read in fixed columns (h135; :func:`fixed_layout`): the gutters between
    #: them, character spans ``(lo, hi)`` of each line. Empty: not.
    fixed_gutters: tuple[tuple[int, int], ...] = ()
    #: Decode line by line: a line not valid in ``encoding`` in a fallback, reported
    #: (:mod:`wakeline.core.io.decoding`); set once the whole file was judged so (the
    #: reader, the pieces of a file), never by :func:`sniff`.
    line_fallback: bool = False
    #: ... and yet strictly, but for the lines better read as UTF-8 (a piece of a file
    #: judged GB18030, read first so: reader.strict_mode).
    line_strict: bool = False
    #: ... and asking, at a line not valid in ``encoding``, the whole file's judgement of
    #: its encoding (a piece of a file judged from its start: the file's
    #: :func:`~wakeline.core.io.decoding.decide_file`, asked once for all its pieces;
    #: reader._judge). None: the reader's own (a whole file), or none.
    judge: Callable[[], str] | None = field(default=None, compare=False, repr=False)
    #: The file's last line looks cut inside its last cell (no line end after it, and its
    #: last value has fewer decimals than that column has on every row before it: the
    #: file is still being written or was copied cut short; :func:`cut_last_cell`): what
    #: was seen ("'25.1' where the column's 40 rows before it have 5 decimals at least"),
    #: or "". Its row is quarantined ("cut last line").
    cut_last: str = ""

    @property
    def parse_delimiter(self) -> str:
        """The delimiter the lines are parsed with: :data:`RUN_SEP` for a file of
        ``blank_runs`` (the reader puts it between the cells), else ``delimiter``."""
        return RUN_SEP if self.blank_runs else self.delimiter


#: An input that cannot be opened, in the operator's words (every subcommand's).
_OPEN_WORDS = (
    (FileNotFoundError, "no such file"),
    (IsADirectoryError, "is a directory, not a file"),
    (PermissionError, "permission denied"),
)


def open_problem(exc: OSError) -> str | None:
    """What an error opening a file says to the operator ("no such file"), or None when
    it is not one of those (a disk error: its own text)."""
    return next((words for kind, words in _OPEN_WORDS if isinstance(exc, kind)), None)


@contextlib.contextmanager
def opening(path: str | Path) -> Iterator[None]:
    """Around opening an input file: a file that is not there, a folder or one that may
    not be read is one :class:`InputError` in the operator's words (:func:`open_problem`:
    "no such file", not Python's "No such file or directory"), for every input of every
    subcommand."""
    try:
        yield
    except OSError as exc:
        words = open_problem(exc)
        if words is None:
            raise
        raise InputError(f"{path}: {words}") from None


def _read_sample(path: Path) -> tuple[bytes, str | None]:
    """The first :data:`SAMPLE_BYTES` of the file's text (decompressed: gzip, bz2, xz,
    zstd, a zip of one file; :mod:`wakeline.core.io.compressed`) and its compression."""
    with opening(path):
        kind = compression_of(path)
        with open_data(path, kind) as fh:
            head = fh.read(SAMPLE_BYTES)
    if kind is not None and is_tar(head):
        raise InputError(
            f"{path}: a tar archive ({kind}-compressed); unpack it (tar xf FILE) and open "
            "the CSV, or give its files to `wakeline batch`"
        )
    return head, kind


def _bom_encoding(sample: bytes) -> str | None:
    if sample.startswith(b"\xef\xbb\xbf"):
        return "utf-8"
    if sample.startswith((b"\xff\xfe", b"\xfe\xff")):
        return "utf-16"
    return None


def _utf16_without_bom(sample: bytes) -> str | None:
    """UTF-16 text with no BOM: ASCII characters leave every other byte zero."""
    head = sample[:4096]
    if len(head) < 8:
        return None
    even, odd = head[0::2], head[1::2]
    if odd.count(0) > 0.4 * len(odd) and even.count(0) < 0.05 * len(even):
        return "utf-16-le"
    if even.count(0) > 0.4 * len(even) and odd.count(0) < 0.05 * len(odd):
        return "utf-16-be"
    return None


def _is_wide(encoding: str | None) -> bool:
    return bool(encoding) and encoding.lower().replace("_", "-").startswith(("utf-16", "utf-32"))


def _looks_binary(sample: bytes) -> bool:
    """Binary data: NUL bytes beyond a stray one or two (a damaged line of a text file is
    its row's problem, quarantined, wherever it lies), or many control characters."""
    # Blocks of NUL bytes (a logger's file cut short by a power loss, zeros where lines
    # were to go) are damaged lines of a text file, not the sign of a binary one.
    text = _NUL_BLOCK.sub(b"", sample)
    if not text.strip():
        return bool(sample)  # nothing but NUL bytes
    sample = text
    if sample.count(b"\x00") > max(4, len(sample) // 1000):
        return True
    control = sum(sample.count(bytes([b])) for b in (*range(0, 9), *range(14, 32)))
    return control > 0.01 * max(len(sample), 1)


def _decode(
    sample: bytes, path: Path, encoding: str | None, compression: str | None = None
) -> tuple[str, str]:
    # The sample may end inside a multi-byte character: cut at the last line end.
    full = len(sample) < SAMPLE_BYTES
    body = sample
    if not full and not _is_wide(encoding):
        cut = max(sample.rfind(b"\n"), sample.rfind(b"\r"))
        body = sample if cut < 0 else sample[: cut + 1]
    if encoding is None:
        # Judged on the evidence, one line at a time (wakeline.core.io.decoding): UTF-8,
        # its failing lines read as Windows-1252 and reported, or GB18030 when that
        # explains the text better. What neither reads keeps U+FFFD (quarantined).
        enc, text, _ = decide(body)
        if enc != "utf-8" and not full and decide_file(path, compression) == "utf-8":
            # the start looks like GB18030, the whole file is better read as UTF-8
            enc, (text, _) = "utf-8", decode_text(body, "utf-8")
        return _refuse_damaged(text, path, ENCODINGS, enc), enc
    candidates = (encoding,)
    for enc in candidates:
        if _is_wide(enc) and not full:
            body = sample[: len(sample) - len(sample) % 4]
        try:
            text = body.decode(enc, errors="strict" if full or not _is_wide(enc) else "ignore")
        except UnicodeDecodeError:
            continue
        except LookupError:
            raise InputError(f"{path}: unknown encoding {enc!r}") from None
        return text.removeprefix("\ufeff"), enc
    # A few damaged lines in otherwise good text: read it, the reader quarantines the rows
    # that hold bad bytes. A damaged header, or more damaged lines than good, means the
    # encoding is wrong: refuse, naming --encoding.
    enc = encoding
    try:
        text = sample.decode(enc, errors="replace")
    except LookupError:
        raise InputError(f"{path}: unknown encoding {enc!r}") from None
    if sample.startswith(codecs.BOM_UTF8) and codecs.lookup(enc).name.startswith("utf-8"):
        try:
            _refuse_damaged(text, path, candidates, enc)
        except InputError:
            raise InputError(
                f"{path}: a UTF-8 byte order mark followed by text that is not UTF-8; "
                "give the file's encoding (--encoding, e.g. gb18030 for Chinese text: the "
                "mark is dropped)"
            ) from None
    return _refuse_damaged(text, path, candidates, enc), enc


def _refuse_damaged(text: str, path: Path, tried: tuple[str, ...], enc: str) -> str:
    """``text`` without its BOM, unless its header or more than half of its other lines
    hold undecodable bytes (U+FFFD): then the encoding is wrong, and that is said."""
    if "\ufffd" in text:
        lines = [x for x in text.replace("\r", "\n").split("\n") if x.strip()]
        damaged = sum("\ufffd" in x for x in lines[1:])
        if not lines or "\ufffd" in lines[0] or damaged > 0.5 * (len(lines) - 1):
            raise InputError(
                f"{path}: cannot decode the text as {' or '.join(tried)}; choose the file's "
                "encoding (--encoding, e.g. gb18030, utf-16, latin-1)"
            )
    return text.removeprefix("\ufeff")


def _pick_delimiter(lines: list[str]) -> str:
    header, rest = lines[0], lines[1:6]
    best, best_score = ",", -1
    for delim in DELIMITERS:
        n = header.count(delim)
        if n == 0:
            continue
        consistent = sum(1 for line in rest if line.count(delim) == n)
        score = n + 100 * consistent
        if score > best_score:
            best, best_score = delim, score
    if best_score < 0 and len(header.split(" ")) > 1:
        return " "
    return best


#: What the reader puts between the cells of a blank-aligned file's lines (a control
#: character no text cell holds) and parses them with (:attr:`Sniff.parse_delimiter`).
RUN_SEP = "\x1f"
#: A date cell (``2024-01-01``, ``2024/1/1``, ``13/09/2020``, ``13.09.2020``) of each
#: width, written so that each lookbehind below is of one width.
_DATES: dict[int, str] = {}
for _m in ("\\d", "\\d\\d"):
    for _d in ("\\d", "\\d\\d"):
        for _p in (f"\\d{{4}}[-/.]{_m}[-/.]{_d}", f"{_d}[-/.]{_m}[-/.]\\d{{4}}"):
            _w = 6 + len(_m) // 2 + len(_d) // 2
            _DATES[_w] = f"{_DATES[_w]}|{_p}" if _w in _DATES else _p
#: The separator between a date cell and a clock cell after it (``00:00:00``, ``12:00``,
#: ``08:01:04.5``), in a line whose cells stand apart by RUN_SEP: one time written with
#: one space inside. It starts with RUN_SEP (the regex engine's fast scan), then the
#: clock after it (which most separators fail at once), then the date before it.
_DATE_CLOCK = (
    r"\x1f(?=\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?(?:[\x1f\r\n]|\Z))(?:"
    + "|".join(f"(?<=(?<![^\x1f\r\n])(?:{p})\x1f)" for p in _DATES.values())
    + ")"
)
#: ... and a morning/afternoon or UTC mark after such a clock.
_MARK = (
    r"\x1f(?:(?<=\d:\d\d\x1f)|(?<=\d:\d\d:\d\d\x1f))(?=(?:[AaPp]\.?[Mm]\.?|UTC|GMT|Z)"
    r"(?:[\x1f\r\n]|\Z))"
)


def _patterns(kind: type) -> dict:
    def c(p: str) -> re.Pattern:
        return re.compile(p.encode("ascii") if kind is bytes else p)

    return {"date_clock": c(_DATE_CLOCK), "mark": c(_MARK)}


_RUNS = {str: _patterns(str), bytes: _patterns(bytes)}


def _shifted(mask: np.ndarray, by: int, fill: bool) -> np.ndarray:
    """``mask`` moved ``by`` places (1: each element is its predecessor's), ``fill`` in
    the place left."""
    out = np.full(len(mask), fill)
    if by > 0:
        out[by:] = mask[:-by]
    else:
        out[:by] = mask[-by:]
    return out


def _blank_runs_bytes(data: bytes, quotes: bool) -> bytes:
    """:func:`blank_runs` without the joining, on bytes: vectorized (numpy), no Python
    loop per line."""
    a = np.frombuffer(data, dtype=np.uint8)
    if not len(a):
        return data
    blank = (a == 32) | (a == 9)
    ends = (a == 10) | (a == 13)
    if quotes:  # blanks inside a quoted cell (odd quotes since the line's start) stay
        count = np.cumsum(a == 34)
        at_line_start = np.maximum.accumulate(np.where(ends, count, 0))
        blank &= ((count - at_line_start) & 1) == 0
    starts = np.flatnonzero(blank & ~_shifted(blank, 1, False))
    stops = np.flatnonzero(blank & ~_shifted(blank, -1, False))
    # a run at a line's start or end is no separator: dropped
    edge = _shifted(ends, 1, True)[starts] | _shifted(ends, -1, True)[stops]
    keep = ~blank
    keep[starts[~edge]] = True
    out = a[keep].copy()
    out[blank[keep]] = 0x1F
    return out.tobytes()


def _fixed_bytes(data: bytes, gutters: tuple[tuple[int, int], ...]) -> bytes:
    """:func:`blank_runs` of a file read in fixed columns (:func:`fixed_layout`): on each
    line whose ``gutters`` (character spans, blank in the header and the judged rows) are
    blank, each gutter is one :data:`RUN_SEP` and the blanks that pad a cell (a run of
    blanks touching a gutter or the line's edge) are dropped, so that an empty cell is
    an empty cell; a line that ends before its last columns gets their separators. A line
    a gutter of which holds text (or a tab, or a byte beyond ASCII) is split at its runs
    of blanks as :func:`_blank_runs_bytes` does. Vectorized (numpy)."""
    a = np.frombuffer(data, dtype=np.uint8)
    n = len(a)
    if not n:
        return data
    width = gutters[-1][1]
    in_gutter = np.zeros(width + 1, dtype=bool)  # (the last place: beyond every gutter)
    opens = np.zeros(width + 1, dtype=bool)
    for lo, hi in gutters:
        in_gutter[lo:hi] = True
        opens[lo] = True
    ends = (a == 10) | (a == 13)
    starts = _shifted(ends, 1, True) & ~ends  # a line's first byte
    small = np.int32 if n < 2**31 else np.int64
    line = np.cumsum(starts, dtype=small) - 1  # each byte's line among those with a byte
    lines = int(line[-1]) + 1 if len(line) else 0
    idx = np.arange(n, dtype=small)
    pos = idx - np.maximum.accumulate(np.where(starts, idx, small(0)))  # place in its line
    place = np.minimum(pos, width)
    g = in_gutter[place] & ~ends
    sep = opens[place] & ~ends
    space, blank = a == 32, (a == 32) | (a == 9)
    body = ~ends & (line >= 0)
    odd = (g & ~space) | (a == 9) | (a >= 128)
    held = np.bincount(line[body & odd], minlength=lines) > 0
    has_text = np.bincount(line[body & ~blank], minlength=lines) > 0
    ok = ~held & has_text  # the lines read in fixed columns
    fixed = np.concatenate([[False], ok])[line + 1] & body
    sep &= fixed
    # runs of blanks: whether each touches a line's edge, or a gutter
    keep = ~blank
    where = np.flatnonzero(blank)
    if len(where):
        first = blank & ~(_shifted(blank, 1, False) & ~starts)
        heads = np.flatnonzero(first[where])
        edge = starts | _shifted(ends, -1, True)  # a line's first byte, its last
        at_edge = np.add.reduceat(edge[where].astype(np.int64), heads) > 0
        at_gutter = np.add.reduceat(g[where].astype(np.int64), heads) > 0
        run = np.cumsum(first[where]) - 1
        # a run between cells of a line read by runs: one separator (its first blank)
        loose = ~fixed[where] & first[where] & ~at_edge[run]
        # a blank inside a cell of a fixed line (2024-01-01 00:00:00, Track No) stays
        inner = fixed[where] & ~at_edge[run] & ~at_gutter[run]
        keep[where[loose | inner]] = True
    keep |= sep
    out = a.copy()
    out[sep | (~fixed & blank & keep)] = 0x1F
    # the separators a short fixed line lacks, after its last byte
    lack = np.where(ok, len(gutters) - np.bincount(line[sep], minlength=lines), 0)
    kept = out[keep]
    short = np.flatnonzero(lack > 0)
    if len(short):
        last = np.zeros(lines, dtype=np.int64)
        is_last = body & _shifted(ends | ~body, -1, True)
        last[line[is_last]] = idx[is_last]
        at = np.cumsum(keep)[last[short]]  # kept bytes up to and with the line's last
        kept = np.insert(kept, np.repeat(at, lack[short]), np.uint8(0x1F))
    return kept.tobytes()


def blank_runs(text, quotes: bool = False, join: bool = False, gutters=()):
    """Lines of a blank-aligned file (``str`` or ``bytes``; whole lines) with each run of
    blanks (spaces, tabs) between cells made one :data:`RUN_SEP` and the blanks at a
    line's start and end dropped; with ``quotes``, blanks inside a quoted cell stay; with
    ``join``, a date and the clock after it (and an AM/PM or UTC mark after a clock) stay
    one cell, apart by one space; with ``gutters``, a file read in fixed columns
    (:func:`_fixed_bytes`). Line ends are kept: a line stays the line it was."""
    is_str = isinstance(text, str)
    raw = text.encode("utf-8") if is_str else bytes(text)
    if gutters:
        out = _fixed_bytes(raw, tuple(tuple(g) for g in gutters))
        return out.decode("utf-8") if is_str else out
    out = _blank_runs_bytes(raw, quotes)
    if join:
        pat = _RUNS[bytes]
        out = pat["date_clock"].sub(b" ", out)
        if any(m in out for m in (b"M", b"m", b"UTC", b"GMT", b"Z")):  # else nothing to join
            out = pat["mark"].sub(b" ", out)
    return out.decode("utf-8") if is_str else out


def blank_cells(line: str, quotes: bool = False, join: bool = False, gutters=()) -> list[str]:
    """The cells of one line of a blank-aligned file (:func:`blank_runs`)."""
    text = blank_runs(line, quotes, join, gutters)
    return text.split(RUN_SEP) if text else [""]


def _fixed_instead(lines, runs: bool, join: bool, names, quotes: bool):
    """The names and gutters of a blank-separated file read in fixed columns, when that
    reads every judged row and the file's reading does not (a row with an empty cell, a
    header name one blank from the next) and, when that reading fits most judged rows,
    each of those comes out the same under the same names: a file that reads today reads
    as it did (h135). (A row that fits only by its count of cells, a minority — a date
    and clock split and an empty cell making up the count — is no reading to keep.) Else
    None."""
    if quotes:
        return None
    judged = [x for x in lines[1 : BLANK_LINES_JUDGED + 1] if x.strip(" \t")]
    if not judged:
        return None
    if runs:
        cells = [blank_cells(x, quotes, join) for x in judged]
        header = names or blank_cells(lines[0], quotes, join)
    else:
        cells = [x.split(" ") for x in judged]
        header = lines[0].split(" ")
    fits = [len(c) == len(header) for c in cells]
    if all(fits):
        return None
    found = fixed_layout([lines[0], *judged])
    if found is None:
        return None
    fixed_names, gutters = found
    again = [blank_cells(x, False, False, gutters) for x in judged]
    if any(len(c) != len(fixed_names) for c in again):
        return None
    same = [
        [v.strip(" ") for v in c] == a for c, a, fit in zip(cells, again, fits, strict=True) if fit
    ]
    if 2 * sum(fits) > len(fits) and (
        not all(same) or fixed_names != [h.strip(" ") for h in header]
    ):
        return None  # most rows read today, some otherwise in fixed columns: as today
    return fixed_names, gutters


def fixed_layout(lines: list[str]) -> tuple[list[str], tuple[tuple[int, int], ...]] | None:
    """A blank-aligned file read in fixed columns (h135): the header's names and the
    gutters (character spans ``[lo, hi)`` blank on the header and on each of the first
    :data:`BLANK_LINES_JUDGED` rows, between the header's first and last character) —
    when every judged row keeps its gutters blank and every column has a name. For a
    file of plain ASCII without tabs or quotes; None otherwise. What it reads that runs
    of blanks cannot: empty cells, and a header name one blank from the next."""
    judged = lines[: BLANK_LINES_JUDGED + 1]
    if len(judged) < 2 or any(("\t" in x or '"' in x or not x.isascii()) for x in judged):
        return None
    head = judged[0].rstrip(" ")
    lo, hi = len(head) - len(head.lstrip(" ")), len(head)
    if hi - lo < 3:
        return None
    blank = np.ones(hi, dtype=bool)
    data = np.zeros(hi, dtype=bool)  # a judged row has text there
    for k, x in enumerate(judged):
        row = np.frombuffer(x[:hi].ljust(hi).encode("ascii"), dtype=np.uint8) == 32
        blank &= row
        if k:
            data |= ~row
    blank[:lo] = False
    edges = np.flatnonzero(np.diff(np.concatenate([[0], blank.astype(np.int8), [0]])))
    gutters = [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]
    # A one-blank gutter inside a column: a date and its clock (one part has no name:
    # the name stands over the date, or right-aligned over the clock), a name of two words
    # (one part has no data under it): no column boundary.
    k = 0
    while k < len(gutters):
        bounds = [0, *[p for g in gutters for p in g], hi]
        spans = [(bounds[j], bounds[j + 1]) for j in range(0, len(bounds), 2)]
        left, right = spans[k], spans[k + 1]
        named = [bool(head[a:b].strip(" ")) for a, b in (left, right)]
        filled = [bool(data[a:b].any()) for a, b in (left, right)]
        narrow = gutters[k][1] - gutters[k][0] == 1
        if narrow and not (all(named) and all(filled)):
            del gutters[k]
        else:
            k += 1
    if not gutters:
        return None
    bounds = [0, *[p for g in gutters for p in g], None]
    names = [head[bounds[j] : bounds[j + 1]].strip(" ") for j in range(0, len(bounds), 2)]
    if not all(names):
        return None
    return names, tuple(gutters)


#: Data lines a blank-separated file's layout is judged on.
BLANK_LINES_JUDGED = 20


def blank_layout(lines: list[str], quotes: bool = False) -> tuple[bool, bool, list[str] | None]:
    """How the lines of a file separated by blank space split into cells: ``(runs,
    join, names)``. ``runs``: runs of blanks are one separator (columns aligned with
    spaces: pandas' ``to_string``, MATLAB, fixed-width text with a blank between columns)
    when that gives more of the first :data:`BLANK_LINES_JUDGED` lines below the first
    as many cells as the first line has names than single spaces do, or as many when
    the first line split at single spaces has empty cells (a file of single spaces with
    empty cells in its rows keeps them). ``join``: a date and the clock after it are one
    cell (``2024-01-01 00:00:00``) because the rows then have as many cells as the header
    has names (and not otherwise). ``names``: the first line's cells when not its plain
    split: names apart by two blanks or more (``Track No   Time``), or a first column
    with no name (its header starts with blanks and every row's first cell is a whole
    number: pandas' index)."""
    first, rows = lines[0], lines[1 : BLANK_LINES_JUDGED + 1]
    if not rows:
        return False, False, None
    single = first.split(" ")
    best = (sum(len(r.split(" ")) == len(single) for r in rows), False, False, None)
    if "" in single:  # a header (or first row) with empty cells: runs, and they win a tie
        best = (best[0] - 0.5, True, False, None)
    # Ties go to the first tried: a date and its clock as one cell (the header fitting
    # rows so joined is the likelier reading than a header of a nameless first column
    # or one name split in two), then the plain names before the others.
    apart = [len(blank_cells(r, quotes)) for r in rows]
    for join in (True, False):
        cells = [len(blank_cells(r, quotes, join)) for r in rows] if join else apart
        if join and cells == apart:
            continue  # no date and clock apart: nothing to join
        plain = blank_cells(first, quotes, join)
        options = [plain]
        wide = re.split(r"[ \t]{2,}", first.strip(" \t"))
        if wide != plain:
            options.append(wide)
        if first[:1] in (" ", "\t") and all(  # a first column without a name: an index
            blank_cells(r, quotes, join)[0].isdigit() for r in rows
        ):
            options += [["", *names] for names in options]
        for names in options:
            score = sum(n == len(names) for n in cells)
            if score > max(best[0], 0):  # a reading no row fits is none
                best = (score, True, join, None if names is plain else names)
    return best[1], best[2], best[3]


def _unique_names(names: list[str]) -> tuple[str, ...]:
    """Header names made usable: blanks become colN, repeats get a .1, .2 suffix."""
    seen: dict[str, int] = {}
    out = []
    for i, name in enumerate(names):
        name = name or f"col{i + 1}"
        if name in seen:
            seen[name] += 1
            name = f"{name}.{seen[name]}"
        else:
            seen[name] = 0
        out.append(name)
    return tuple(out)


#: Delimiters as people type them on a command line (a shell passes ``\t`` as two
#: characters).
_DELIMITER_WORDS = {
    "\\t": "\t",
    "tab": "\t",
    "space": " ",
    "comma": ",",
    "semicolon": ";",
    "pipe": "|",
}


def delimiter_given(delimiter: str | None) -> str | None:
    """The delimiter a user named: one character, or ``\\t``/``tab``/``space``/``comma``/
    ``semicolon``; None: detect. Raises :class:`InputError` for anything else."""
    if delimiter is None or delimiter == "":
        return None
    delim = _DELIMITER_WORDS.get(delimiter.lower(), delimiter)
    if len(delim) != 1:
        raise InputError(
            f"--delimiter {delimiter!r}: give one character (, ; |), or tab, \\t or space"
        )
    return delim


#: Lines looked at for a header below a title line.
TITLE_LINES_MAX = 10


def _title_count(lines: list[str], delimiter: str | None) -> int:
    """How many of the first non-blank lines are a title above the header: 0 when the
    first line names at least three known fields (or no later line names more, and at
    least three); else the index of the first of the next :data:`TITLE_LINES_MAX` lines
    that does (split on its own delimiter)."""
    from wakeline.core.io.formats import known_fields

    def named(k: int) -> int:
        delim = delimiter or _pick_delimiter(lines[k:])
        return len(known_fields(lines[k].split(delim)))

    first = named(0)
    if first >= 3 or len(lines) < 2:
        return 0
    for k in range(1, min(TITLE_LINES_MAX + 1, len(lines) - 1 + 1)):
        count = named(k)
        if count >= 3 and count > first:
            return k
    return 0


#: A cell that reads as a date and time (ISO 8601, slashed or dotted dates with a clock).
_DATETIME = re.compile(
    r"^\d{4}[-/.]\d{1,2}[-/.]\d{1,2}([T ]\d{1,2}:\d{2}(:\d{2}([.,]\d+)?)?)?"
    r"\s*([zZ]|[+-]\d{2}:?\d{2}|UTC|GMT)?$"
    r"|^\d{1,2}[-/.]\d{1,2}[-/.]\d{4}([T ]\d{1,2}:\d{2}(:\d{2}([.,]\d+)?)?)?"
    r"(\s*[AaPp]\.?[Mm]\.?)?$"
)


def cell_kind(cell: str) -> str:
    """What a cell of a line holds: ``blank``, ``number``, ``time`` (a date-time, as
    :data:`_DATETIME` reads one) or ``text``: how a headerless file's rows are told from
    a header (:func:`_is_header`) and its time column found by its values."""
    text = cell.strip().strip('"')
    if not text:
        return "blank"
    if _NUMBER.match(text):
        return "number"
    return "time" if _DATETIME.match(text) else "text"


def _is_header(first: list[str], rows: list[list[str]]) -> bool:
    """Whether the first line is a header. A line of numbers is data. A line with a
    word in it is a header, unless it holds a date-time or two numbers and is like the
    lines below it: a date-time or a number where each of them has one, cell for cell
    (a file without a header whose first row starts with ``2024-07-31T23:31:24Z``: that
    row was read as the header, and its fix was lost). A header's names are words where
    its data has numbers or times, so a name that is also a field's (a track called
    ``T`` or ``x``) does not make a data row a header. A blank cell, above or below, is
    like any (an optional value missing in a row is no header's name)."""
    if not any(f and not _NUMBER.match(f) for f in first):
        return False
    kinds = [cell_kind(f) for f in first]
    if "time" not in kinds and kinds.count("number") < 2:
        return True  # names (or a line of words: a title's "station 4" is no fix)
    rows = [r for r in rows if len(r) == len(first)]
    if not rows:
        return True

    def alike(row: list[str]) -> bool:
        return all(
            a == b or "blank" in (a, b) for a, b in zip(map(cell_kind, row), kinds, strict=True)
        )

    return not all(alike(r) for r in rows)


def _skip_rows_past_end(skip_rows: int, physical: list[str], whole: bool) -> str:
    """The refusal of a ``--skip-rows`` that leaves no line with text to read (the header
    or first row would be past the end): names the flag and the file's line count.
    ``physical``: the lines of the sample; ``whole``: the sample is the whole file."""
    count = len(physical) - int(physical[-1] == "")  # a last line end starts no line
    lines = f"{count:,} line" + ("" if count == 1 else "s")
    if not whole:
        return (
            f"--skip-rows {skip_rows}: the header must lie within the first "
            f"{SAMPLE_BYTES // 1024} KB of the file ({lines})"
        )
    if skip_rows >= count:
        return f"--skip-rows {skip_rows}: the file has {lines}"
    return (
        f"--skip-rows {skip_rows}: the file has {lines} and those after line "
        f"{skip_rows:,} are blank"
    )


#: What a file with nothing but blank space is (import, and batch's skipped inputs).
EMPTY_FILE = "the file is empty"


def sniff(
    path: str | Path,
    encoding: str | None = None,
    delimiter: str | None = None,
    skip_rows: int | None = None,
) -> Sniff:
    """Inspect a CSV file. Raises :class:`InputError` for empty, binary or undecodable files.

    A title above the header (lines that name no known column, then a line that does) is
    found among the first :data:`TITLE_LINES_MAX` lines and skipped (``title_lines``);
    ``skip_rows`` (physical lines before the header) says it instead of detecting it."""
    path = Path(path)
    delimiter = delimiter_given(delimiter)
    sample, compression = _read_sample(path)
    if not sample.strip():
        raise InputError(f"{path}: {EMPTY_FILE}")
    given = encoding is not None
    bom_enc = _bom_encoding(sample)
    if encoding is None:
        encoding = _utf16_without_bom(sample) if bom_enc is None else bom_enc
        if encoding == "utf-8":
            encoding = None  # UTF-8 with BOM: the usual candidates (BOM removed below)
    elif bom_enc == "utf-8":
        # A UTF-8 BOM before text the user says is GBK (a GBK file saved by a tool that
        # adds one, operator test 7 D1): the mark is dropped, the rest read as named.
        encoding = bom_codec(encoding)
    if not _is_wide(encoding) and _looks_binary(sample):
        if sample.startswith(OLE2_MAGIC):  # the compound file of Excel 97-2003 and Word
            raise NotTrackData(
                f"{path}: an Excel 97-2003 workbook (.xls) or another Office 97-2003 file, "
                "not a text file of rows; Wakeline reads CSV and text tables: save it as CSV "
                "(in Excel: File ▸ Save As ▸ CSV UTF-8) and open that file"
            )
        raise NotTrackData(
            f"{path}: this is a binary file, not a CSV text file "
            "(for UTF-16 text without a byte order mark give --encoding utf-16)"
        )
    text, enc = _decode(sample, path, encoding, compression)
    if _is_wide(enc) and _looks_binary(text.encode("utf-8", errors="replace")):
        raise NotTrackData(f"{path}: this is a binary file, not a CSV text file")
    first_end = re.search(r"\r\n|\n|\r", text)
    line_ending = first_end.group(0) if first_end else "\n"
    physical = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    leading_blank = next((i for i, line in enumerate(physical) if line.strip()), len(physical))
    lines = [line for line in physical if line.strip()]
    if not lines:
        raise InputError(f"{path}: {EMPTY_FILE}")
    extras = {
        "bom": bom_enc is not None,
        "line_ending": line_ending,
        "has_quotes": '"' in text,
        "ascii": text.isascii(),
        "encoding_given": given,
    }
    if GEOJSON_START.match(text.lstrip("\ufeff")) and _GEOJSON_TYPE.search(text):
        return Sniff(path, compression, enc, ",", False, 0, (), (), kind="geojson", **extras)
    if GPX_START.match(text.lstrip("\ufeff")):
        return Sniff(path, compression, enc, ",", False, 0, (), (), kind="gpx", **extras)
    if _NMEA.search(lines[0]) or sum(bool(_NMEA.search(x)) for x in lines[:20]) >= 2:
        return Sniff(path, compression, enc, ",", False, 0, (), (), kind="nmea", **extras)
    excel = _EXCEL_SEP.fullmatch(lines[0].strip())
    if excel and len(lines) > 1:  # Excel's "sep=;" line names the delimiter: skipped
        delimiter = delimiter or excel.group(1)
        lines = lines[1:]
        extras["excel_sep"] = True
        leading_blank = next(
            i for i, line in enumerate(physical) if i > leading_blank and line.strip()
        )
    titles = _title_count(lines, delimiter) if skip_rows is None else 0
    if skip_rows is not None:  # given: that many physical lines, then the header
        if skip_rows < 0:
            raise InputError(f"--skip-rows {skip_rows}: give 0 or more lines")
        if not any(line.strip() for line in physical[skip_rows:]):
            raise InputError(_skip_rows_past_end(skip_rows, physical, len(sample) < SAMPLE_BYTES))
        extras["skip_rows_given"] = skip_rows
        titles = sum(1 for line in physical[:skip_rows] if line.strip())
        titles -= int(extras.get("excel_sep", False))
        titles = max(0, min(titles, len(lines) - 1))
    if titles:
        nonblank = [i for i, line in enumerate(physical) if line.strip()]
        offset = int(extras.get("excel_sep", False))
        extras["title_lines"] = tuple((nonblank[offset + k] + 1, lines[k]) for k in range(titles))
        leading_blank = nonblank[offset + titles]
        lines = lines[titles:]
    delim = delimiter or _pick_delimiter(lines)
    names = None
    if delim == " ":  # columns aligned with runs of blanks?
        runs, join, names = blank_layout(lines, extras["has_quotes"])
        extras["blank_runs"], extras["join_date_clock"] = runs, join
        fixed = _fixed_instead(lines, runs, join, names, extras["has_quotes"])
        if fixed is not None:
            names, extras["fixed_gutters"] = fixed
            extras["blank_runs"], extras["join_date_clock"] = True, False
    if extras.get("blank_runs"):

        def split(line: str) -> list[str]:
            return blank_cells(
                line,
                extras["has_quotes"],
                extras["join_date_clock"],
                extras.get("fixed_gutters", ()),
            )
    else:

        def split(line: str) -> list[str]:
            return line.split(delim)

    first = [f.strip().strip('"') for f in (names or split(lines[0]))]
    has_header = _is_header(first, [split(line) for line in lines[1:6]])
    if has_header:
        data_lines = lines[1:6]
        rows = [split(line) for line in data_lines]
        if rows and all(len(r) == len(first) + 1 and not r[-1].strip() for r in rows):
            first.append("")  # every row ends with the delimiter: one more (empty) column
        columns = _unique_names(first)
    else:
        columns = tuple(f"col{i + 1}" for i in range(len(first)))
        data_lines = lines[:5]
    preview = tuple(tuple(f.strip('"') for f in split(line)) for line in data_lines)
    start = 1 if has_header else 0
    extras["sample"] = tuple(
        tuple(f.strip('"') for f in split(line)) for line in lines[start : start + SAMPLE_ROWS]
    )
    skip_rows = leading_blank + (1 if has_header else 0)
    titled = len(extras.get("title_lines", ()))
    extras["blank_above_header"] = leading_blank - titled - int(extras.get("excel_sep", False))
    if not extras.get("blank_runs"):
        full = len(sample) < SAMPLE_BYTES
        extras["cut_last"] = cut_last_cell(
            path, compression, enc, split, len(columns), text if full else None
        )
    return Sniff(path, compression, enc, delim, has_header, skip_rows, columns, preview, **extras)


#: Bytes read from the end of a file to judge its last line (:func:`cut_last_cell`).
TAIL_BYTES = 64 * 1024
#: Rows before the last whose last cell it is compared with (at least the first number).
CUT_EVIDENCE = (5, 200)
_NUMBER_CELL = re.compile(r"^[+-]?\d+(?:[.,](\d*))?$")


def cut_last_cell(
    path: Path,
    compression: str | None,
    enc: str,
    split: Callable[[str], list[str]],
    width: int,
    text: str | None = None,
) -> str:
    """Whether the file's last line looks cut inside its last cell (operator test 7, D7:
    ``…,25.1`` from ``…,25.13487``, imported 3 km off): the file ends without a line end,
    the line has all its fields, and its last value is a number with fewer decimals than
    that column has on each of the (at least 5, at most 200) rows before it. A file
    without a final line end is common: the evidence is the column's own precision, so a
    column written with varying decimals (``%g``: 25.1 beside 25.13487) never judges its
    last value cut. ``text``: the whole file when the sample holds it; else the end of a
    plain file is read (a compressed file's is not: ""). Returns what was seen, or ""."""
    if text is None:
        if compression is not None or enc.lower().startswith(("utf-16", "utf-32")):
            return ""
        try:
            with open(path, "rb") as fh:
                fh.seek(0, 2)
                size = fh.tell()
                fh.seek(max(0, size - TAIL_BYTES))
                raw = fh.read()
        except OSError:
            return ""
        if not raw or raw.endswith((b"\n", b"\r")):
            return ""
        try:
            text = raw.decode(enc, errors="replace")
        except LookupError:
            return ""
        lines = text.splitlines()[1:]  # the first may start mid-line
    else:
        if not text or text.endswith(("\n", "\r")):
            return ""
        lines = text.splitlines()
    if len(lines) < 2:
        return ""
    cells = split(lines[-1])
    if len(cells) != width:
        return ""  # a short row: quarantined as such, and warned of
    last = _NUMBER_CELL.match(cells[-1].strip().strip('"'))
    if last is None:
        return ""
    places = []
    for line in reversed(lines[:-1]):
        if len(places) >= CUT_EVIDENCE[1]:
            break
        row = split(line)
        if len(row) != width:
            continue
        m = _NUMBER_CELL.match(row[-1].strip().strip('"'))
        if m is not None:
            places.append(len(m.group(1) or ""))
    have = len(last.group(1) or "")
    if len(places) < CUT_EVIDENCE[0] or have >= min(places):
        return ""
    fewest = min(places)
    return (  # the value as read (a quoted cell cut short has only its opening quote)
        f"{cells[-1].strip().strip(chr(34))!r} where the column's {len(places):,} rows "
        f"before it have {fewest} decimal{'' if fewest == 1 else 's'} at least"
    )


def read_small_table(
    path: str | Path, required: tuple[str, ...], what: str, text_columns: tuple[str, ...] = ()
):
    """A small CSV of another layout (bearings, association tables), read with the same
    detection of encoding, delimiter and compression as track files. Raises
    :class:`InputError` naming the missing columns and listing the headers found."""
    import pandas as pd

    sn = sniff(path)
    missing = [c for c in required if c not in sn.columns]
    if missing:
        raise InputError(
            f"{path}: missing required column {', '.join(missing)} ({what}); "
            f"headers found: {listed_headers(sn.columns)}"
        )
    with open_data(path, sn.compression) as stream:
        return pd.read_csv(
            stream,
            sep=sn.delimiter,
            encoding=lines_codec(sn.encoding, sn.encoding_given),
            dtype={c: "str" for c in text_columns},
        )

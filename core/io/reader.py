"""Import a track file into the canonical point table (SPEC §1).

Reading uses pyarrow's multi-threaded CSV reader with the column types fixed up front
(the fast path). When a value does not convert, the file is read again with the mapped
columns as text and each value is checked on its own (the careful path), so one bad cell
costs one quarantined row, never the file.

Nothing is lost silently: a row that cannot be used goes to the *quarantine* table with
its physical line number (1-based, header included) and the reason, and every count is
in the report.
"""

import codecs
import contextlib
import csv
import dataclasses
import datetime
import functools
import io
import os
import re
import shlex
import shutil
import sys
import tempfile
import zoneinfo
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

from wakeline.core import sorted_sets
from wakeline.core.errors import InputError, NotTrackData
from wakeline.core.geo import EARTH_RADIUS_M, from_local
from wakeline.core.io.compressed import open_data, open_for_arrow
from wakeline.core.io.decoding import (
    LineDecoder,
    decide_file,
    fallback_warning,
    line_decodable,
    lines_codec,
    plain_encoding,
)
from wakeline.core.io.formats import (
    DISTANCE_UNITS,
    PLANE_FIELDS,
    SPEED_UNITS,
    Resolved,
    angle_unit,
    guess_columns,
    header_is_local,
    known_fields,
    length_unit,
    next_column,
    normalize_header,
    parse_mapping,
    plane_kind,
    resolve,
    speed_unit,
    unused_position_columns,
)
from wakeline.core.io.sniff import Sniff, blank_runs, cell_kind, listed_headers, sniff
from wakeline.core.io.timetext import (
    AMBIGUOUS_ZONES,
    NAMED_HINT,
    check_clock_date,
    chinese_iso,
    clock_seconds,
    day_ns,
    hhmmss_evidence,
    hhmmss_seconds,
    is_clock,
    named_iso,
    roll_days,
    sod_ns,
    valid_hhmmss,
    zone_words,
)
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import COURSE_READ, DEFAULT_SENSOR

QUARANTINE_COLUMNS = ("line", "reason", "text")
#: The batch "column" of a file without one: its one track is named after the file.
FILE_BATCH = "(file name)"
NO_BATCH_WARNING = (
    "no batch column: the file is one track named after the file (if a column holds "
    "each track's id, map it: --map batch=COLUMN)"
)
_TEXT_FIELDS = ("sensor", "batch", "truth")
_FLOAT_FIELDS = ("lon", "lat", "speed", "course")
#: Seconds since 1970 beyond which a number is read as milliseconds (year 5138 in seconds).
_MS_THRESHOLD = 1e11
_DAYFIRST_FORMATS = (
    "%d/%m/%Y %H:%M:%S",
    "%d/%m/%Y %H:%M:%S.%f",
    "%d/%m/%Y %H:%M",
    "%d-%m-%Y %H:%M:%S",
    "%d.%m.%Y %H:%M:%S",  # German, Norwegian …: 01.05.2024 08:01:04
    "%d.%m.%Y %H:%M:%S.%f",
    "%d.%m.%Y %H:%M",
    "%d/%m/%Y %I:%M:%S %p",  # 12-hour clocks: 01/05/2024 8:01:04 PM
    "%d/%m/%Y %I:%M %p",
    # a date alone is midnight, as an ISO 2024-05-01 reads (13/09/2020 was unparsable)
    "%d/%m/%Y",
    "%d.%m.%Y",
    "%d-%m-%Y",
)
#: The same with the month first (US exports: 05/17/2024), read only when the file says so.
_MONTHFIRST_FORMATS = tuple(
    f.replace("%d", "{d}").replace("%m", "%d").replace("{d}", "%m") for f in _DAYFIRST_FORMATS
)
#: A time that ends with a 12-hour clock's AM/PM (``3/1/2023 12:01:46 AM``, ``8:01 p.m.``).
_AMPM_END = r"\d\s*[AaPp]\.?\s?[Mm]\.?\s*$"
#: The first two numbers of a slashed date (``dd/mm/yyyy`` or ``mm/dd/yyyy``).
_SLASHED_DATE = r"^\s*(\d{1,2})[/.-](\d{1,2})[/.-]\d{4}"
#: How slashed dates (``nn/nn/yyyy``) are read: ``auto`` day first unless the file shows
#: the month first (a second number above 12, none a first), or as the operator says.
DATE_ORDERS = ("auto", "day-first", "month-first")


def check_date_order(value: str) -> str:
    """``value`` when it is one of :data:`DATE_ORDERS`; else :class:`InputError`."""
    if value not in DATE_ORDERS:
        raise InputError(
            f"unknown date order {value!r}; give one of {', '.join(DATE_ORDERS)} (--date-order)"
        )
    return value


def _slashed_parts(text: pd.Series) -> tuple[pd.Series, pd.Series]:
    """The first and second numbers of the slashed dates of ``text`` (NaN elsewhere)."""
    parts = text.str.extract(_SLASHED_DATE)
    return pd.to_numeric(parts[0], errors="coerce"), pd.to_numeric(parts[1], errors="coerce")


def real_slashed_dates(text: pd.Series, month_first: bool) -> pd.Series:
    """Which slashed dates of ``text`` are calendar dates read day first (or month
    first): 31/02/2023 is none either way, so it shows no order."""
    parts = text.str.extract(r"^\s*(\d{1,2})[/.-](\d{1,2})[/.-](\d{4})")
    day, month = (parts[1], parts[0]) if month_first else (parts[0], parts[1])
    iso = parts[2] + "-" + month.str.zfill(2) + "-" + day.str.zfill(2)
    return pd.to_datetime(iso, format="%Y-%m-%d", errors="coerce").notna()


def month_first_dates(text: pd.Series) -> int:
    """How many slashed dates of ``text`` show the month first: none has a first number
    above 12 and these have a second one above 12 (0: day-first, or no evidence). Only
    calendar dates count: a corrupt 31/02/2023 is evidence of neither order."""
    first, second = _slashed_parts(text)
    if ((first > 12) & real_slashed_dates(text, month_first=False)).any():
        return 0
    return int(((second > 12) & real_slashed_dates(text, month_first=True)).sum())


def _parse_slashed(text: pd.Series, todo: pd.Series, formats, info: dict) -> pd.Series:
    """Naive times of ``text`` where ``todo``, trying ``formats`` in turn (NaT elsewhere)."""
    parsed = pd.Series(pd.NaT, index=text.index, dtype="datetime64[ns]")
    for fmt in formats:
        left = parsed.isna() & todo
        if not left.any():
            break
        parsed[left] = _as_ns(pd.to_datetime(text[left], format=fmt, errors="coerce"), info)
    left = parsed.isna() & todo
    if left.any():
        # 12-hour clocks written "p.m." / "pm" / "P.M." (strptime's %p takes AM/PM only):
        # only the rows left over are looked at, so a file without them pays nothing
        norm = text[left].str.replace(_MERIDIEM, _meridiem, regex=True)
        changed = norm != text[left]
        if changed.any():
            again = parsed.isna() & False
            again[norm.index[changed.to_numpy()]] = True
            parsed[again] = _parse_slashed(norm.reindex(text.index), again, formats, info)[again]
    return parsed


#: A 12-hour clock's suffix as people write it (``p.m.``, ``pm``, ``P.M``), at the end.
_MERIDIEM = re.compile(r"(?<=\d)\s*([AaPp])\.?\s?[Mm]\.?\s*$")


def _meridiem(m: re.Match) -> str:
    return " " + m.group(1).upper() + "M"


@dataclass
class ImportResult:
    """What an import produced: the points, the quarantined rows and the report."""

    points: pd.DataFrame
    quarantine: pd.DataFrame
    report: dict = field(default_factory=dict)
    #: How the file was written (delimiter, encoding, BOM, line ending, header names and
    #: order, time column, format and zone, mapping): enough to write data back the same way.
    layout: dict = field(default_factory=dict)


def empty_quarantine() -> pd.DataFrame:
    """A quarantine table with no rows (columns ``QUARANTINE_COLUMNS``)."""
    return quarantine_table([], [], [])


def points_summary(points: pd.DataFrame) -> dict:
    """The report's ``tracks``, ``sensors`` (points per sensor), ``time_start`` and
    ``time_end`` (ISO) of a point table."""
    if not len(points):
        return {"tracks": 0, "sensors": {}, "time_start": None, "time_end": None}
    return {
        "tracks": int(points.groupby(["sensor", "batch"]).ngroups),
        "sensors": {str(k): int(v) for k, v in points["sensor"].value_counts().items()},
        "time_start": points["time"].min().isoformat(),
        "time_end": points["time"].max().isoformat(),
    }


def _numeric_texts(text: pd.Series) -> np.ndarray:
    """``pd.to_numeric(text, errors="coerce")`` as float64, without converting the texts
    that begin as an ISO date (``yyyy-mm-dd``: never a number, NaN): a column of ISO
    times is not turned into Python strings one by one for nothing (h135)."""
    dated = text.str.match(r"[0-9]{4}-[0-9]{2}-[0-9]{2}", na=False).to_numpy(dtype=bool)
    if not dated.any():
        return pd.to_numeric(text, errors="coerce").to_numpy(dtype="float64", copy=True)
    out = np.full(len(text), np.nan)
    if not dated.all():
        rest = pd.to_numeric(text[~dated], errors="coerce")
        out[~dated] = rest.to_numpy(dtype="float64", na_value=np.nan)
    return out


def times_of_values(values: list, timing: dict | None = None) -> tuple[pd.Series, dict]:
    """Times (UTC, NaT where unreadable) of a list of time values as a GPX or GeoJSON
    file holds them (ISO or other text, unix seconds or ms as numbers, None; or an Arrow
    string array), read as a
    CSV time column is (:func:`parse_times`; ``timing``: ``tz``, ``date_order``,
    ``clock_date``). Returns the times and what the parse found (``time_format``...)."""
    timing = timing or {}
    if isinstance(values, pa.Array):  # texts already (the GPX reader's)
        text = pa.chunked_array([values.cast(pa.string())])
    else:
        text = pa.chunked_array(
            [pa.array([None if v is None else str(v) for v in values], pa.string())]
        )
    info: dict = {}
    ns, ok = parse_times(
        text,
        "auto",
        tz=timing.get("tz"),
        info=info,
        date_order=timing.get("date_order", "auto"),
        clock_date=timing.get("clock_date"),
    )
    times = pd.Series(pd.to_datetime(np.where(ok, ns, 0), utc=True)).where(ok)
    return times.astype("datetime64[ns, UTC]"), info


def quarantine_table(lines, reasons, texts) -> pd.DataFrame:
    """A quarantine table from parallel lists (line numbers, reasons, texts), in line
    order (rows of one line keep the order they were given in)."""
    order = np.argsort(np.asarray(lines, dtype="int64"), kind="stable")
    return pd.DataFrame(
        {
            "line": np.asarray(lines, dtype="int64")[order],
            "reason": pd.Series(np.asarray(reasons, dtype=object)[order], dtype="str"),
            "text": pd.Series(np.asarray(texts, dtype=object)[order], dtype="str"),
        }
    )


#: What to do when every row of a file was quarantined for one reason.
_HINTS = {
    "lon out of range": "the positions are not longitude/latitude in degrees (local metres "
    "or another projection?): Wakeline reads WGS-84 degrees; convert them first, or check "
    "that --map lon=… and lat=… name the right columns",
    "lat out of range": "the positions are not longitude/latitude in degrees (local metres "
    "or another projection?): Wakeline reads WGS-84 degrees; convert them first, or check "
    "that --map lon=… and lat=… name the right columns",
    "unparsable time": "the time column is not a time Wakeline reads (ISO 8601, day-first "
    "dd/mm/yyyy or month-first mm/dd/yyyy, yyyymmddHHMMSS, unix seconds or milliseconds): "
    "check --map time=…",
    "missing batch": "no row has a track id: map one with --map batch=COLUMN",
}


def nothing_imported(rep: dict, name: str | None = None) -> str:
    """Why a file gave no points, and what to try: the main reason with its hint.

    ``rep``: an import report; ``name``: the file as the message names it (default: the
    report's ``input``, named only when the file has no data rows)."""
    if not rep.get("rows_read"):
        return f"{name or rep.get('input', 'the file')}: no data rows (a header only?); nothing imported"
    prefix = f"{name}: " if name else ""
    reasons = rep.get("quarantine_reasons") or {}
    if not reasons:
        return f"{prefix}nothing imported"
    reason, count = max(reasons.items(), key=lambda kv: kv[1])
    text = (
        f"{prefix}nothing imported: "
        + ("the one row was" if rep["rows_read"] == 1 else f"all {rep['rows_read']:,} rows were")
        + f" quarantined, "
        f"{count:,} as '{reason}'"
    )
    cols = rep.get("columns") or {}
    if rep.get("lat_beyond_90_lon_within", 0) > rep["rows_read"] / 2 and "lat" in cols:
        return (
            f"{text}; the lat column holds longitudes and lon latitudes, it seems: "
            f"try --map lat={cols['lon']} --map lon={cols['lat']}"
        )
    unit, order = str(rep.get("time_unit") or ""), str(rep.get("date_order") or "")
    if reason == "unparsable time" and unit.startswith("Excel") and "(given" in unit:
        return (
            f"{text}; they were read as Excel serial days, as --time-unit excel-days says, "
            "and are none (Excel's days run 1-2,958,465): try --time-unit auto"
        )
    if reason == "unparsable time" and rep.get("date_order_refused") and "(given" in order:
        given = order.split()[0]
        return (
            f"{text}; {rep['date_order_refused']:,} dates cannot be {given}, as "
            f"--date-order {given} says: try --date-order auto"
        )
    for key, hint in _HINTS.items():
        if reason.startswith(key):
            return f"{text}; {hint}"
    if reason.startswith("unparsable "):
        return f"{text}; check the column mapped to {reason.split()[-1]} (--map)"
    return text


@dataclass
class _BadRows:
    lines: list[int] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    texts: list[str] = field(default_factory=list)
    unnumbered: int = 0
    blank: int = 0
    blank_lines: list[int] = field(default_factory=list)
    quoted: list[tuple[int, str, int]] = field(default_factory=list)  # line, text, fields
    decoder: LineDecoder | None = None  # lines decoded one by one (errors "lines")

    def in_file_order(self) -> None:
        """Sort the bad rows (and the blank lines) by line number."""
        order = sorted(range(len(self.lines)), key=self.lines.__getitem__)
        self.lines = [self.lines[i] for i in order]
        self.reasons = [self.reasons[i] for i in order]
        self.texts = [self.texts[i] for i in order]
        self.blank_lines.sort()
        self.quoted.sort(key=lambda q: q[0])

    def handler(self, row) -> str:
        if row.number is None or row.number < 0:
            self.unnumbered += 1  # the caller reads again without threads
            return "skip"
        if not row.text.strip():
            self.blank += 1
            self.blank_lines.append(int(row.number))
            return "skip"
        if '"' in row.text:
            self.quoted.append((int(row.number), row.text, row.actual_columns))
        self.lines.append(int(row.number))
        if row.actual_columns < row.expected_columns:
            self.reasons.append(f"short row: {row.actual_columns} of {row.expected_columns} fields")
        else:
            self.reasons.append(f"too many fields: {row.actual_columns} of {row.expected_columns}")
        self.texts.append(row.text)
        return "skip"


class _ChunkedStream:
    """``read(n)`` over the bytes a subclass makes chunk by chunk (:meth:`_chunk`, which
    sets ``_eof`` at the end of its input): what pyarrow's CSV reader reads from."""

    _buf: bytes = b""
    _eof: bool = False

    def _chunk(self, n: int) -> bytes:
        raise NotImplementedError

    def read(self, n: int = -1) -> bytes:
        while not self._eof and (n < 0 or len(self._buf) < n):
            self._buf += self._chunk(n)
        if n < 0:
            out, self._buf = self._buf, b""
        else:
            out, self._buf = self._buf[:n], self._buf[n:]
        return out


class _Utf8Stream(_ChunkedStream):
    """A file read as text in ``encoding`` and handed on as UTF-8 bytes, chunk by chunk
    (for pyarrow, which reads UTF-8): undecodable bytes become U+FFFD when ``errors`` is
    ``"replace"`` (those rows are then quarantined); with ``"strict-lines"`` (a file
    judged GB18030) strictly, but a line better read as UTF-8 is (``decoder.fallbacks``);
    with ``"lines"`` a line that does not decode is read in a fallback encoding (``decoder.fallbacks``:
    :class:`~wakeline.core.io.decoding.LineDecoder`); a byte order mark is dropped."""

    CHUNK = 4 * 1024 * 1024

    def __init__(
        self, sn: Sniff, encoding: str, errors: str = "strict", switch: bool = False
    ) -> None:
        self._opened = open_data(sn.path, sn.compression)
        self._fh = self._opened.__enter__()
        self.decoder = None
        if errors in ("lines", "strict-lines"):
            strict = errors == "strict-lines"
            self._dec = self.decoder = LineDecoder(
                encoding, fail=strict, judge=_judge(sn) if strict else None, switch=switch
            )
        else:
            self._dec = codecs.getincrementaldecoder(encoding)(errors=errors)
        self._buf = b""
        self._eof = False
        self._first = True
        self.closed = False

    def _chunk(self, n: int) -> bytes:
        raw = self._fh.read(self.CHUNK)
        self._eof = not raw
        if self.decoder is not None:  # lines valid UTF-8 handed on as they are (h179)
            out = self._dec.decode_utf8(raw, final=self._eof)
            if self._first and out:
                out = out.removeprefix(codecs.BOM_UTF8)
                self._first = False
            return out
        text = self._dec.decode(raw, final=self._eof)
        if self._first and text:
            text = text.removeprefix("\ufeff")
            self._first = False
        return text.encode("utf-8")

    def fraction(self) -> float:
        """How far through the file on disk the reading is (0 to 1)."""
        return self._opened.fraction()

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            self._opened.__exit__(None, None, None)

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.closed = True
        self._opened.__exit__(*exc)  # a decompression error: named (InputError)


def _judge(sn: Sniff) -> Callable[[], str] | None:
    """The whole file's judgement of its encoding (:func:`decide_file`) when the readers
    ask for it (an encoding judged from the file's start, not one the user named); a
    strict reading's decoder asks it at the first line that does not decode, and goes on
    when it confirms the encoding instead of failing the reading (:class:`LineDecoder`)."""
    if sn.judge is not None:  # a piece's: the whole file's
        return sn.judge
    if sn.encoding_given or sn.line_fallback or not line_decodable(sn.encoding):
        return None
    return functools.partial(_judged, sn.path, sn.compression)


def _judged(path: Path, compression: str | None) -> str:
    """:func:`decide_file`, asked once per file as it is (the streamed import's decoder,
    then the whole-file reader's, or its next reading, ask it again: h179)."""
    try:
        st = os.stat(path)
        key = (str(path), compression, st.st_mtime_ns, st.st_size)
    except OSError:
        return decide_file(path, compression)
    if key not in _JUDGED:
        if len(_JUDGED) >= 8:
            _JUDGED.pop(next(iter(_JUDGED)))
        _JUDGED[key] = decide_file(path, compression)
    return _JUDGED[key]


_JUDGED: dict[tuple, str] = {}


def _open(sn: Sniff, encoding: str, errors: str, switch: bool = False):
    """The file's text as UTF-8 bytes, in a ``with`` block: a plain UTF-8 file as Arrow
    reads it, a compressed one through :func:`~wakeline.core.io.compressed.open_data`
    (the one opener of every reader), another encoding re-encoded (:class:`_Utf8Stream`).
    ``switch``: a UTF-8 reading may go on as GB18030 (the whole-file reader's, which says
    so: :func:`_read_rows`)."""
    if encoding in ("utf-8", "utf8") and errors == "strict":
        return open_for_arrow(sn.path, sn.compression)
    return _Utf8Stream(sn, encoding, errors, switch)


class _BlankRunStream(_ChunkedStream):
    """The UTF-8 bytes of a blank-aligned file (:attr:`Sniff.blank_runs`) with each run
    of blanks between cells made one :data:`~wakeline.core.io.sniff.RUN_SEP`, line by
    line (:func:`~wakeline.core.io.sniff.blank_runs`): what pyarrow parses."""

    def __init__(self, stream, sn: Sniff) -> None:
        self._stream, self._sn = stream, sn
        self._buf, self._carry, self._eof = b"", b"", False
        self.closed = False
        if hasattr(stream, "fraction"):  # a compressed file's progress, on disk
            self.fraction = stream.fraction

    def _chunk(self, n: int) -> bytes:
        raw = bytes(self._stream.read(4 * 1024 * 1024 if n < 0 else max(n, 1 << 16)))
        self._eof = not raw
        data = self._carry + raw
        cut = len(data) if self._eof else last_line_end(data) + 1
        self._carry = data[cut:]
        sn = self._sn
        return blank_runs(data[:cut], sn.has_quotes, sn.join_date_clock, sn.fixed_gutters)

    def close(self) -> None:
        self.closed = True
        self._stream.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.closed = True
        self._stream.__exit__(*exc)  # the opener's: a decompression error named


def _open_parsed(sn: Sniff, encoding: str, errors: str, switch: bool = False):
    """:func:`_open`, and for a blank-aligned file its lines as they are parsed."""
    stream = _open(sn, encoding, errors, switch)
    return _BlankRunStream(stream, sn) if sn.blank_runs else stream


@contextlib.contextmanager
def _quiet_undecodable_rows() -> Iterator[None]:
    """pyarrow decodes an invalid row's text as UTF-8 before calling the handler; when that
    fails it prints "Exception ignored" and the read then fails with a parse error, which
    the caller answers by reading again with replacement characters. Keep stderr clean."""
    previous = sys.unraisablehook

    def hook(unraisable) -> None:
        if not isinstance(unraisable.exc_value, UnicodeDecodeError):
            previous(unraisable)

    sys.unraisablehook = hook
    try:
        yield
    finally:
        sys.unraisablehook = previous


def _read_table(
    sn: Sniff,
    types: dict[str, pa.DataType],
    threads: bool,
    encoding: str | None = None,
    errors: str = "strict",
    quoting: bool = True,
    block_size: int | None = None,
) -> tuple[pa.Table, _BadRows]:
    bad = _BadRows()
    read = pacsv.ReadOptions(
        column_names=list(sn.columns),
        skip_rows=sn.skip_rows,
        use_threads=threads,
        **({"block_size": block_size} if block_size else {}),
    )
    parse = pacsv.ParseOptions(
        delimiter=sn.parse_delimiter,
        quote_char='"' if quoting else False,
        invalid_row_handler=bad.handler,
        ignore_empty_lines=False,
    )
    convert = pacsv.ConvertOptions(column_types=types, strings_can_be_null=False)
    # A large file is streamed in record batches: read_csv holds the whole file's raw and
    # parsed blocks at once, about twice the memory (bench/bench_memory.py). A smaller one
    # is read whole, blocks parsed on every core: about twice as fast.
    whole = threads and sn.compression is None and _file_size(sn) <= READ_WHOLE_MAX_BYTES
    opened = _open(sn, encoding or sn.encoding, errors, switch=sn.judge is None)
    stream = _BlankRunStream(opened, sn) if sn.blank_runs else opened
    bad.decoder = getattr(opened, "decoder", None)  # the lines read in a fallback
    with stream as handle, _quiet_undecodable_rows():
        if whole:
            table = pacsv.read_csv(
                handle, read_options=read, parse_options=parse, convert_options=convert
            )
        else:
            reader = pacsv.open_csv(
                handle, read_options=read, parse_options=parse, convert_options=convert
            )
            table = pa.Table.from_batches(list(reader), schema=reader.schema)
    bad.in_file_order()  # parallel parsing may report the bad rows out of order
    return table, bad


#: Files up to this size (bytes, uncompressed) are parsed whole on all cores; larger ones
#: are streamed, to keep the peak memory near the file's size.
READ_WHOLE_MAX_BYTES = 256 * 1024 * 1024


def _file_size(sn: Sniff) -> int:
    try:
        return sn.path.stat().st_size
    except OSError:
        return READ_WHOLE_MAX_BYTES + 1


def _count_lines(sn: Sniff, encoding: str) -> int:
    """Physical lines of the file (LF, CRLF or CR), streamed in chunks."""
    n_lf = n_cr = n_crlf = 0
    last = b""
    ends_open = False
    with _open(sn, encoding, "replace") as stream:
        while True:
            chunk = stream.read(16 * 1024 * 1024)
            if not chunk:
                break
            chunk = bytes(chunk)
            n_lf += chunk.count(b"\n")
            n_cr += chunk.count(b"\r")
            n_crlf += chunk.count(b"\r\n") + (last == b"\r" and chunk[:1] == b"\n")
            last = chunk[-1:]
            ends_open = last not in (b"\n", b"\r")
    return n_lf + n_cr - n_crlf + int(ends_open)


#: pyarrow block sizes tried in turn: a line longer than a block (a 5 MB cell) needs more.
_BLOCKS = (None, 64 << 20, 512 << 20)


@dataclass
class _Rows:
    """The parsed table with the physical line of each of its rows."""

    table: pa.Table
    lines: np.ndarray  # int64, 1-based physical line per table row
    bad: _BadRows
    careful: bool
    encoding: str
    replaced: bool  # undecodable bytes were replaced by U+FFFD (those rows are quarantined)
    line_by_line: bool  # quotes did not balance: read without quoting, quoted cells unquoted
    notes: list[str]
    #: Lines read in a fallback encoding (report's ``encoding_fallback``; decoding.py).
    fallback: dict = field(default_factory=dict)
    #: Each row's table in a file of several (tables.py; -1 the first), or None.
    blocks: np.ndarray | None = None


def strict_mode(sn: Sniff) -> str:
    """How the file is first read: strictly, and for a file judged GB18030 (or a piece of
    one) with its lines that are UTF-8 rather than GB18030 read as UTF-8, reported
    (``"strict-lines"``: :mod:`wakeline.core.io.decoding`). A file judged UTF-8 from its
    start and not valid UTF-8 throughout (:func:`_valid_utf8`) is read so too (h179): at
    its first line that is not UTF-8 the decoder asks the whole file's judgement and goes
    on — in UTF-8 with that line read otherwise, or, the text so far all ASCII, in GB18030
    — instead of the whole file being read again."""
    judged = sn.line_strict or not (sn.encoding_given or sn.line_fallback)
    name = codecs.lookup(sn.encoding).name if line_decodable(sn.encoding) else ""
    if judged and name == "utf-8" and _valid_utf8(sn):
        return "strict"  # Arrow reads it as it is (no Python in the way)
    return "strict-lines" if judged and name in ("gb18030", "utf-8") else "strict"


def _valid_utf8(sn: Sniff) -> bool:
    """Whether a plain file is valid UTF-8 throughout: a scan of its bytes at C speed
    (ASCII blocks only checked as such), stopping at the first block that is not; a
    compressed file is not scanned (its text reaches Arrow through Python anyway, where
    the decoder's check costs little). Kept per file as it is (size, time)."""
    if sn.compression is not None:
        return False
    try:
        st = os.stat(sn.path)
    except OSError:
        return False
    if sn.judge is not None:  # a piece (one scratch file rewritten): not kept
        return _scan_utf8(sn.path)
    key = (str(sn.path), st.st_mtime_ns, st.st_size)
    if key not in _VALID_UTF8:
        if len(_VALID_UTF8) >= 8:
            _VALID_UTF8.pop(next(iter(_VALID_UTF8)))
        _VALID_UTF8[key] = _scan_utf8(sn.path)
    return _VALID_UTF8[key]


def _scan_utf8(path: Path) -> bool:
    """Whether the file's bytes are valid UTF-8 (:func:`_valid_utf8`)."""
    dec = codecs.getincrementaldecoder("utf-8")()
    with open(path, "rb") as fh:
        while block := fh.read(_Utf8Stream.CHUNK):
            if block.isascii() and not dec.getstate()[0]:
                continue
            try:
                dec.decode(block)
            except UnicodeDecodeError:
                return False
    try:
        dec.decode(b"", final=True)
    except UnicodeDecodeError:
        return False
    return True


_VALID_UTF8: dict[tuple, bool] = {}


def _is_decode_error(exc: Exception) -> bool:
    text = str(exc)
    return isinstance(exc, UnicodeDecodeError) or "UTF8" in text or "UTF-8" in text


#: The import's note for a file whose quotes do not balance.
UNBALANCED_NOTE = (
    "quotes do not balance (a quoted cell ran over line ends): the file was read line by "
    "line, quoted cells unquoted"
)


def bom_warnings(sn: Sniff, enc: str) -> list[str]:
    """A warning when the file starts with a UTF-8 byte order mark and its text is in
    another encoding (GBK saved by a tool that adds the mark, operator test 7 D1): the
    mark was dropped and the text read as ``enc``."""
    name = plain_encoding(codecs.lookup(enc).name) if line_decodable(enc) else ""
    if not sn.bom or not name or name.startswith("utf-"):
        return []
    return [
        f"the file starts with a UTF-8 byte order mark but its text is not UTF-8: the mark "
        f"was dropped and the text read as {name}"
    ]


def encoding_note(start: str, enc: str) -> str:
    """The import's note for a file read in ``enc`` whose start reads as ``start``."""
    return f"the start of the file reads as {start} but a later line does not: read as {enc}"


def _read_rows(sn: Sniff, res: Resolved, unbalanced: bool = False) -> _Rows:
    """Parse the whole file, falling back (never failing for the file's sake) through:
    the careful all-text parse when a value does not convert; when the text does not
    decode strictly, the encoding that explains the whole file best, its failing lines
    decoded one by one (:mod:`wakeline.core.io.decoding`: UTF-8 with Windows-1252 lines,
    or GB18030), or for an encoding the user named (and UTF-16) replacement characters
    (rows quarantined); bigger blocks for very long lines; and a line-by-line parse when
    a stray quote swallowed lines (checked by counting the physical lines;
    ``unbalanced``: known beforehand, a piece of such a file)."""
    if sn.line_fallback and not sn.line_strict:  # judged already (a piece of a file)
        attempts = [(sn.encoding, "lines")]
    else:
        attempts = [(sn.encoding, strict_mode(sn)), (sn.encoding, "replace")]
    judge = not sn.encoding_given and line_decodable(sn.encoding) and not sn.line_fallback
    notes: list[str] = []
    careful = False
    # No quote in the sampled start: a quote later on is text, and each line is one row.
    quoting = sn.has_quotes
    if unbalanced:
        quoting, careful = False, True
        notes.append(UNBALANCED_NOTE)
    threads = True
    step = block = 0
    while True:
        enc, errors = attempts[step]
        try:
            table, bad = _read_table(
                sn,
                _column_types(sn, res, careful),
                threads,
                enc,
                errors,
                quoting,
                _BLOCKS[block],
            )
        except (pa.ArrowInvalid, UnicodeDecodeError) as exc:
            text = str(exc)
            # "CSV parse error": the invalid-row handler could not even decode the row.
            decoding = errors != "lines" and _is_decode_error(exc)  # "lines" cannot fail
            strict = errors in ("strict", "strict-lines")
            if decoding or ("CSV parse error" in text and strict):
                if judge and strict:  # the whole file's evidence decides (asked once)
                    attempts[step + 1] = (_judged(sn.path, sn.compression), "lines")
                if step + 1 < len(attempts):
                    step += 1
                    continue
                raise InputError(
                    f"{sn.path}: cannot decode the text as {enc}; give the file's encoding "
                    "with --encoding (e.g. gb18030, utf-16, latin-1)"
                ) from None
            if "Empty CSV file" in text or ("file is too short" in text and _one_line(sn)):
                # a header alone, without a line end
                raise InputError(
                    f"{sn.path}: no data rows (a header only?); nothing imported"
                ) from None
            if "straddl" in text or "block" in text:
                if block + 1 < len(_BLOCKS):
                    block += 1
                    continue
                raise InputError(f"{sn.path}: a line is longer than 512 MB") from None
            if ("out of sync" in text or "CSV parse error" in text) and quoting:
                quoting, careful = False, True
                continue
            if not careful:
                careful = True
                continue
            raise InputError(f"{sn.path}: cannot read the file ({text})") from None
        if bad.decoder is not None and bad.decoder.encoding != codecs.lookup(enc).name:
            enc = bad.decoder.encoding  # an ASCII start, then GB18030 (LineDecoder._switch)
        if bad.unnumbered and threads:
            threads = False  # only a single-threaded parse numbers the skipped rows
            continue
        if quoting:
            expected = _count_lines(sn, enc) - sn.skip_rows
            if table.num_rows + len(bad.lines) + bad.blank != expected:
                quoting, careful = False, True
                notes.append(UNBALANCED_NOTE)
                continue
        break
    if enc != sn.encoding:
        notes.append(encoding_note(sn.encoding, enc))
    fallback = bad.decoder.fallbacks.report() if bad.decoder else {}
    notes += fallback_warning(enc, fallback)
    replaced = errors == "replace" or bool(
        bad.decoder and bad.decoder.fallbacks.counts.get("replaced")
    )
    if replaced:
        notes.append(
            f"some bytes are not valid {enc}: their rows are quarantined "
            "(give the right --encoding to read them)"
        )
    skipped = sorted(bad.lines + bad.blank_lines)
    lines = _line_numbers(np.arange(table.num_rows), sn.skip_rows, skipped)
    if sn.blank_runs and bad.lines:  # the refused lines as the file has them, not as parsed
        bad.texts = _raw_lines(sn, np.asarray(bad.lines), enc)
    if not quoting:
        table, lines = _recover_quoted(sn, table, lines, bad)
        table = _unquote(table)
    return _Rows(table, lines, bad, careful, enc, replaced, not quoting, notes, fallback)


def _recover_quoted(
    sn: Sniff, table: pa.Table, lines: np.ndarray, bad: _BadRows
) -> tuple[pa.Table, np.ndarray]:
    """Rows read without quoting whose field count was wrong only because a quoted cell
    held the delimiter: parse them as CSV on their own and add them back."""
    n_cols = len(sn.columns)
    rec_lines, rec_rows = [], []
    for number, text, _ in bad.quoted:
        try:
            fields = next(csv.reader([text], delimiter=sn.parse_delimiter))
        except (csv.Error, StopIteration):
            continue
        if len(fields) == n_cols:
            rec_lines.append(number)
            rec_rows.append(fields)
    if not rec_rows:
        return table, lines
    try:
        extra = pa.table(
            {
                name: pa.array([row[j] for row in rec_rows], type=pa.string()).cast(
                    table.schema.field(name).type
                )
                for j, name in enumerate(sn.columns)
            }
        )
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
        return table, lines  # a value does not convert: the rows stay quarantined
    drop = set(rec_lines)
    keep = [i for i, n in enumerate(bad.lines) if n not in drop]
    bad.lines = [bad.lines[i] for i in keep]
    bad.reasons = [bad.reasons[i] for i in keep]
    bad.texts = [bad.texts[i] for i in keep]
    lines = np.concatenate([lines, np.asarray(rec_lines, dtype="int64")])
    order = np.argsort(lines, kind="stable")  # back in file order
    return pa.concat_tables([table, extra]).take(pa.array(order)), lines[order]


def _unquote(table: pa.Table) -> pa.Table:
    """Cells read without quoting that are wholly quoted lose their quotes ("" becomes ")."""
    cols = []
    for col in table.columns:
        if pa.types.is_string(col.type) and pc.any(pc.starts_with(col, '"')).as_py():
            quoted = pc.and_(
                pc.and_(pc.starts_with(col, '"'), pc.ends_with(col, '"')),
                pc.greater_equal(pc.utf8_length(col), 2),
            )
            inner = pc.replace_substring(pc.utf8_slice_codeunits(col, 1, -1), '""', '"')
            col = pc.if_else(quoted, inner, col)
        cols.append(col)
    return pa.table(cols, names=table.column_names)


def _column_types(sn: Sniff, res: Resolved, careful: bool) -> dict[str, pa.DataType]:
    types = {name: pa.string() for name in sn.columns}  # extra columns travel as text
    if careful:
        return types
    for name, src in res.columns.items():
        if name in _TEXT_FIELDS:
            # Batches and sensors repeat: decode each distinct value once.
            types[src] = pa.dictionary(pa.int32(), pa.string())
        elif name in _FLOAT_FIELDS:
            types[src] = pa.float64()
        elif name == "time":
            if res.format.time_kind == "unix":
                types[src] = pa.float64()
            elif res.format.time_kind == "auto":
                del types[src]  # let pyarrow infer: ISO text → timestamp, numbers → int/float
    return types


#: A time's written UTC offset, after its clock: Z, ±HH:MM, ±HHMM, ±HH (a space before it
#: allowed: "08:00:00 +01:00"); "UTC"/"GMT" words are Z.
_WRITTEN_OFFSET = r"\d:\d\d(?::\d\d(?:[.,]\d+)?)?\s?(?P<z>[zZ]|UTC|GMT|[+-]\d\d(?::?\d\d)?)\s*$"


def _plain_offset(text: str) -> str:
    """``+08:00`` of a written offset (``Z``/``UTC`` → ``+00:00``, ``+0800``, ``+08``)."""
    if text.upper() in ("Z", "UTC", "GMT"):
        return "+00:00"
    digits = text[1:].replace(":", "")
    return f"{text[0]}{digits[:2]}:{digits[2:4] or '00'}"


def written_offsets(texts: pa.Array | pa.ChunkedArray) -> dict[str, int]:
    """How many of the times ``texts`` carry each UTC offset at their end (``+00:00`` for
    Z), e.g. ``{"-05:00": 20000}``; times without one are not counted."""
    if isinstance(texts, pa.ChunkedArray):
        texts = texts.combine_chunks() if texts.num_chunks else pa.array([], pa.string())
    if not pa.types.is_string(texts.type) or not len(texts):
        return {}
    found = pc.struct_field(pc.extract_regex(texts, _WRITTEN_OFFSET), [0])
    out: dict[str, int] = {}
    for item in pc.value_counts(found.drop_null()).to_pylist():
        key = _plain_offset(item["values"])
        out[key] = out.get(key, 0) + int(item["counts"])
    return out


def written_zone(offsets: dict[str, int], zoneless: int = 0) -> str | None:
    """The zone a file's times were written in, by the offsets they carry
    (:func:`written_offsets`): the one offset (``-05:00``), ``mixed`` for several (or
    some times with one and some without), None when no time carries one."""
    offsets = {k: v for k, v in offsets.items() if v}
    if not offsets:
        return None
    return next(iter(offsets)) if len(offsets) == 1 and not zoneless else "mixed"


def _file_offsets(sn: Sniff, src: str, encoding: str, time_info: dict) -> dict:
    """The report's ``time_offsets`` and ``time_zone_written`` (:func:`written_zone`) of
    the ISO 8601 times of column ``src`` of ``sn``, read again as text (pyarrow reads
    ``…-05:00`` as a UTC instant and forgets the offset: View ▸ Time zone's "the zone the
    data came in" showed UTC for a file of -05:00 times, operator test 10). Empty when the
    times are not ISO 8601 text or none carries a zone (nothing read again)."""
    if time_info.get("time_format") != "ISO 8601 text":
        return {}
    zoneless = int(time_info.get("zoneless_times", 0))
    if not time_info.get("zoned_written"):
        return {}  # no time read carries a zone
    read = pacsv.ReadOptions(column_names=list(sn.columns), skip_rows=sn.skip_rows)
    parse = pacsv.ParseOptions(
        delimiter=sn.parse_delimiter,
        quote_char='"' if sn.has_quotes else False,
        invalid_row_handler=lambda _row: "skip",
        ignore_empty_lines=True,
    )
    convert = pacsv.ConvertOptions(
        include_columns=[src], column_types={src: pa.string()}, strings_can_be_null=False
    )
    errors = "strict" if encoding in ("utf-8", "utf8") else "replace"
    try:
        with _open_parsed(sn, encoding, errors) as handle, _quiet_undecodable_rows():
            table = pacsv.read_csv(
                handle, read_options=read, parse_options=parse, convert_options=convert
            )
    except (pa.ArrowInvalid, UnicodeDecodeError, OSError, KeyError):
        return {}  # unsure: the report says nothing of offsets
    offsets = written_offsets(table.column(src))
    if not offsets:
        return {}
    return {"time_offsets": offsets, "time_zone_written": written_zone(offsets, zoneless)}


def _line_numbers(rows: np.ndarray, skip_rows: int, invalid_lines: list[int]) -> np.ndarray:
    """Physical 1-based line of parsed rows (0-based row numbers), given the lines of the
    invalid rows the parser skipped."""
    rows = np.asarray(rows, dtype="int64")
    if invalid_lines:
        lines = np.sort(np.asarray(invalid_lines, dtype="int64"))
        # Rows from this position on sit below the k-th invalid line.
        pos = lines - skip_rows - 1 - np.arange(len(lines))
        rows = rows + np.searchsorted(pos, rows, side="right")
    return rows + skip_rows + 1


def line_ends_in(values: pa.Array | pa.ChunkedArray) -> np.ndarray:
    """Line ends (LF, CRLF, CR) inside each string of ``values``: a quoted cell's line
    breaks (0 where null)."""
    out = np.zeros(len(values), dtype="int64")
    for end, sign in (("\n", 1), ("\r", 1), ("\r\n", -1)):
        n = pc.fill_null(pc.count_substring(values, end), 0)
        out += sign * np.asarray(n.to_numpy(zero_copy_only=False), dtype="int64")
    return out


def record_lines(records: np.ndarray, breaks: np.ndarray) -> np.ndarray:
    """The physical 1-based first line of each record, from its number as pyarrow counts
    (a record one line, as :func:`_line_numbers` gives for the parsed rows and the
    invalid-row handler's ``row.number`` for the refused ones) and the line ends inside
    it (:func:`line_ends_in`; a quoted cell over a line end). ``records`` and ``breaks``
    cover every record after the header (rows and refused rows, any order)."""
    records = np.asarray(records, dtype="int64")
    breaks = np.asarray(breaks, dtype="int64")
    if not breaks.any():
        return records
    order = np.argsort(records, kind="stable")
    before = np.cumsum(breaks[order]) - breaks[order]  # line ends in the records above
    out = np.empty_like(records)
    out[order] = records[order] + before
    return out


#: A number written with a decimal comma (``57,6671``, ``-0,5``, ``1,5e3``): European
#: spreadsheets' exports, read as such when the file's delimiter is not the comma.
_COMMA_NUMBER = r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?"


def _with_decimal_comma(text: pd.Series, values: np.ndarray, info: dict | None = None) -> int:
    """Fill ``values`` (NaN where ``text`` is no plain number) from the texts written with
    a decimal comma, in place; returns how many. The first such text goes to
    ``info["decimal_comma_example"]`` (the warning quotes the file)."""
    miss = np.flatnonzero(np.isnan(values) & text.notna().to_numpy())
    if not len(miss):
        return 0
    sub = text.iloc[miss]
    comma = sub.str.fullmatch(_COMMA_NUMBER).fillna(False).to_numpy(dtype=bool)
    if not comma.any():
        return 0
    fixed = pd.to_numeric(sub[comma].str.replace(",", ".", regex=False), errors="coerce")
    values[miss[comma]] = fixed.to_numpy(dtype="float64")
    if info is not None:
        info.setdefault("decimal_comma_example", str(sub[comma].iloc[0]))
    return int(comma.sum())


#: A position in degrees, minutes and seconds as exports write it: ``57°40.026'N``,
#: ``N 57 40 01.6``, ``-11°12'30"``, ``东经122°24.6′``, ``30度15分N`` (minutes and seconds
#: optional, a hemisphere letter before or after); without minutes, decimal degrees
#: with a hemisphere letter: ``37.05N``, ``N37.05``, ``W 23.05``, ``37.05 S``.
_DMS = re.compile(
    r"^\s*(?P<h1>[NSEWnsew]|[东西南北][经纬]?)?\s*(?P<sign>[+-])?\s*(?P<d>\d{1,3}(?:[.,]\d+)?)"
    r"(?:\s*(?:[°º˚度d:]|\s)\s*(?:(?P<m>\d{1,2}(?:[.,]\d+)?)\s*(?:['′’´m:分]|\s)?\s*"
    r"(?:(?P<s>\d{1,2}(?:[.,]\d+)?)\s*(?:[\"″”s秒]|'')?)?)?)?\s*(?P<h2>[NSEWnsew])?\s*$"
)


#: NMEA's degrees and minutes run together with the hemisphere letter in the cell:
#: ``3754.03N``, ``02342.10E``, ``N 3754.03``, ``3754,03 S`` (four or five digits before
#: the point: ddmm, dddmm).
_DDMM_CELL = re.compile(
    r"^\s*(?P<h1>[NSEWnsew])?\s*(?P<sign>[+-])?\s*(?P<d>\d{4,5}(?:[.,]\d+)?)\s*"
    r"(?P<h2>[NSEWnsew])?\s*$"
)


#: The reason of a cell of a lettered lat/lon column not in the column's form: ddmm.mmmm
#: (degrees and minutes run together, ``3754.03N``) where the column is decimal degrees.
DDMM_CELL_CLASH = (
    "{} in ddmm.mmmm (degrees and minutes run together, like 3754.03N) where the rest of "
    "its column is decimal degrees with a letter"
)


def lettered_form(d: pd.Series, digits: pd.Series, top: float) -> tuple[bool, pd.Series]:
    """How a column writes its numbers with a hemisphere letter and no minutes (``d``:
    the numbers, ``digits``: how many digits stand before their point): NMEA's ddmm.mmmm
    (True) or decimal degrees, and the numbers read as ddmm.mmmm (NaN: none such).

    Judged over the column, never cell by cell (h149: ``123.5W`` is 1°23.5' unpadded or
    123.5°): a cell shows ddmm.mmmm when it reads as such (minutes below 60) and has four
    or five digits before its point or lies beyond ``top`` as degrees (``942.1W``); a
    cell shows degrees when it cannot be ddmm.mmmm (``165.3W``, ``85.5N``: minutes 60 or
    more). The column is ddmm.mmmm when more cells show it than show degrees."""
    as_ddmm = pd.Series(_ddmm(d.to_numpy(dtype="float64"), top), index=d.index)
    shows = as_ddmm.notna() & ((digits >= 4) | (d > top))
    against = as_ddmm.isna() & (d <= top)
    return bool(shows.sum() > against.sum()), as_ddmm


def _with_dms(
    text: pd.Series,
    values: np.ndarray,
    counted: dict | None = None,
    top: float | None = None,
    name: str | None = None,
) -> int:
    """Fill ``values`` (NaN where ``text`` is no plain number) from the texts written in
    degrees, minutes and seconds (:data:`_DMS`), in place; returns how many. Counted in
    ``counted``: ``dms``, and ``hemisphere_degrees`` those of decimal degrees with a
    hemisphere letter (no minutes: ``37.05N``). With ``top`` (90 for lat, 180 for lon),
    the numbers with a letter and no minutes are NMEA's ddmm.mmmm (``3754.03N``,
    ``02342.10E``, ``942.1E``; counted in ``ddmm_in_cell``) or decimal degrees, one form
    for the column (:func:`lettered_form`): in a ddmm.mmmm column a cell without the
    zero padding (``123.5W``, 1°23.5') is read so too (counted in ``ddmm_unpadded``) and
    one that cannot be (minutes 60 or more) is not read; in a column of degrees, a cell
    in ddmm.mmmm is not read (its rows: ``counted["_form_clash"][name]``, a mask over
    ``text``) and one with three digits that could be ddmm.mmmm unpadded (``123.5W``) is
    read as degrees and counted in ``ddmm_ambiguous``. ``counted["lettered_forms"]
    [name]``: ``ddmm`` or ``degrees`` when the column has such cells (pieces of a file
    must agree)."""
    miss = np.flatnonzero(np.isnan(values))
    if not len(miss):
        return 0
    sub = text.iloc[miss]
    sub = sub[sub.notna() & (sub != "")]
    if not len(sub):
        return 0
    parts = sub.str.extract(_DMS)
    ok = parts["d"].notna() & (parts["m"].notna() | parts["h1"].notna() | parts["h2"].notna())
    nmea = None
    if top is not None:
        rest = sub[~ok.to_numpy()]
        if len(rest):
            nmea = rest.str.extract(_DDMM_CELL)
            nmea = nmea[nmea["d"].notna() & (nmea["h1"].notna() | nmea["h2"].notna())]
    if not ok.any() and (nmea is None or not len(nmea)):
        return 0
    parts = parts[ok]
    if nmea is not None and len(nmea):
        parts = pd.concat([parts, nmea.reindex(columns=parts.columns)])

    def num(col: str) -> pd.Series:
        return pd.to_numeric(parts[col].str.replace(",", ".", regex=False), errors="coerce")

    d, m, sec = num("d"), num("m").fillna(0.0), num("s").fillna(0.0)
    good = (m < 60) & (sec < 60)
    hemi = parts["h1"].fillna("").str[:1].str.upper() + parts["h2"].fillna("").str.upper()
    south_west = hemi.str.contains("[SW西南]", regex=True) | (parts["sign"] == "-")
    deg = d + m / 60.0 + sec / 3600.0
    in_cell = pd.Series(False, index=parts.index)
    unpadded = ambiguous = 0
    if top is not None:  # NMEA's ddmm.mmmm with its letter, or degrees: one form a column
        lettered = parts["m"].isna() & (hemi != "")
        digits = parts["d"].str.split(r"[.,]", regex=True).str[0].str.len()
        if lettered.any():
            is_ddmm, as_ddmm = lettered_form(d[lettered], digits[lettered], top)
            if counted is not None and name is not None:
                counted.setdefault("lettered_forms", {})[name] = "ddmm" if is_ddmm else "degrees"
            if is_ddmm:
                in_cell = lettered
                deg = deg.where(~in_cell, as_ddmm.reindex(deg.index))
                unpadded = int((as_ddmm.notna() & (digits[lettered] < 4)).sum())
                clash, reason = as_ddmm.isna(), DDMM_REASON  # minutes 60 or more
            else:
                clash = as_ddmm.notna() & ((digits[lettered] >= 4) | (d[lettered] > top))
                reason = DDMM_CELL_CLASH
                ambiguous = int(
                    (as_ddmm.notna() & (digits[lettered] == 3) & (d[lettered] <= top)).sum()
                )
                deg = deg.where(~clash.reindex(deg.index, fill_value=False))
            if clash.any() and counted is not None and name is not None:
                mask = np.zeros(len(text), dtype=bool)
                mask[text.index.get_indexer(clash.index[clash.to_numpy()])] = True
                counted.setdefault("_form_clash", {})[name] = (mask, reason.format(name))
    deg = deg.where(good) * np.where(south_west, -1.0, 1.0)
    rows = text.index.get_indexer(deg.index)
    values[rows] = deg.to_numpy(dtype="float64")
    read = int(deg.notna().sum())
    nmea_read = int((deg.notna() & in_cell).sum())
    plain = int((deg.notna() & parts["m"].isna() & ~in_cell).sum())
    for key, k in (
        ("dms", read - plain - nmea_read),
        ("hemisphere_degrees", plain),
        ("ddmm_in_cell", nmea_read),
        ("ddmm_unpadded", unpadded),
        ("ddmm_ambiguous", ambiguous),
    ):
        if counted is not None and k:
            counted[key] = counted.get(key, 0) + k
    return read


def _numbers(
    arr: pa.ChunkedArray,
    decimal_comma: bool = False,
    counted: dict | None = None,
    angles: bool = False,
    top: float | None = None,
    name: str | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """float64 values and a mask of unparsable (present but not a number) cells. With
    ``decimal_comma``, ``57,6671`` is 57.6671 (counted in ``counted["decimal_comma"]``);
    with ``angles``, ``57°40.026'N`` is 57.6671 (counted in ``counted["dms"]``; ``37.05N``
    in ``counted["hemisphere_degrees"]``; with ``top``, ``3754.03N`` is NMEA's ddmm.mmmm:
    :func:`_with_dms`)."""
    if pa.types.is_floating(arr.type) or pa.types.is_integer(arr.type):
        return arr.to_numpy().astype("float64", copy=False) if arr.null_count == 0 else pc.cast(
            arr, pa.float64()
        ).to_numpy(zero_copy_only=False), np.zeros(len(arr), bool)
    text = pd.Series(arr.to_pandas(), dtype="str").str.strip()
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype="float64", copy=True)
    if decimal_comma:
        k = _with_decimal_comma(text, values, counted)
        if counted is not None and k:
            counted["decimal_comma"] = counted.get("decimal_comma", 0) + k
    if angles:
        _with_dms(text, values, counted, top, name)
    present = ~(text.isna() | (text == "")).to_numpy()
    lowered = text.str.lower()
    nan_words = lowered.isin(["nan", "na", "n/a", "null", "none"]).to_numpy()
    return values, present & np.isnan(values) & ~nan_words


#: Numeric times below this (seconds; 1973-03-03) are read as seconds from a scene start.
RELATIVE_BELOW_S = 1e8
#: What numbers in the time column count: ``auto`` (unix seconds or milliseconds,
#: relative seconds, or Excel serial days by :func:`excel_days_rule`' rule), ``seconds``
#: (never days), ``excel-days`` (Excel's serial day numbers, 1900 date system).
TIME_UNITS = ("auto", "seconds", "excel-days")
#: Excel serial days that ``auto`` takes for dates: 1954-10-03 to 2119-01-10.
EXCEL_RANGE = (20_000.0, 80_000.0)
#: ... when a column's typical step (median of the non-zero steps between rows, file
#: order) is below this: 0.01 day is 14.4 min, and as seconds a 100 Hz clock.
EXCEL_STEP = 0.01
#: Day 0 of Excel's 1900 date system (1899-12-30, after its 1900 leap-year bug) in unix days.
_EXCEL_EPOCH_DAYS = 25_569
#: The last day Excel writes (9999-12-31).
_EXCEL_LAST = 2_958_466
#: Headers that say a column holds Excel serial days (normalised, as a part).
_EXCEL_WORDS = ("excel", "serial", "oadate", "days")


def check_units(speed: str = "auto", distance: str = "auto") -> None:
    """:class:`InputError` unless ``speed`` is one of :data:`SPEED_UNITS` and
    ``distance`` one of :data:`DISTANCE_UNITS`."""
    if speed not in SPEED_UNITS:
        raise InputError(f"--speed-unit {speed!r}: choose one of {', '.join(SPEED_UNITS)}")
    if distance not in DISTANCE_UNITS:
        raise InputError(f"--distance-unit {distance!r}: choose one of {', '.join(DISTANCE_UNITS)}")


def check_time_unit(value: str) -> str:
    """``value`` when it is one of :data:`TIME_UNITS`; else :class:`InputError`."""
    if value not in TIME_UNITS:
        raise InputError(
            f"unknown time unit {value!r}; give one of {', '.join(TIME_UNITS)} (--time-unit)"
        )
    return value


@dataclasses.dataclass(frozen=True)
class ValueOptions:
    """How a file's values read: the keywords :func:`read_points`, :func:`import_to_csv`,
    :func:`stream_points` and the readings in pieces pass on alike (slashed dates' order,
    what numeric times count, the day of clock times, speed and distance units)."""

    date_order: str = "auto"
    time_unit: str = "auto"
    clock_date: str | None = None
    speed_unit: str = "auto"
    distance_unit: str = "auto"

    @classmethod
    def of(cls, read: dict) -> "ValueOptions":
        """The options a ``read`` dict (a reading's keywords) holds; the defaults else."""
        return cls(**{f.name: read[f.name] for f in dataclasses.fields(cls) if f.name in read})

    def checked(self) -> "ValueOptions":
        """Checked (InputError on a value not known), ``clock_date`` as ``YYYY-MM-DD``."""
        check_date_order(self.date_order)
        check_time_unit(self.time_unit)
        check_units(self.speed_unit, self.distance_unit)
        return dataclasses.replace(self, clock_date=check_clock_date(self.clock_date))

    def keywords(self) -> dict:
        return dataclasses.asdict(self)


def excel_days_rule(values: np.ndarray, header: str, info: dict) -> bool:
    """Whether ``auto`` reads numeric times as Excel serial days. Only when the values
    (99 % of them: a damaged one does not hide the rest) lie in :data:`EXCEL_RANGE` and
    either the header names them (``Excel``, ``serial``, ``OADate``, ``days``) or half have
    a fractional part and the column steps less than :data:`EXCEL_STEP` between rows (a
    clock of days: 1 s is 1.2e-5). A column in the range that is not so taken is read as
    seconds and ``info["excel_like"]`` says so (docs/import.md)."""
    finite = values[np.isfinite(values)]
    inside = (finite >= EXCEL_RANGE[0]) & (finite < EXCEL_RANGE[1])
    if not len(finite) or inside.mean() < 0.99:  # a damaged value or two: still judged
        return False
    finite = finite[inside]
    named = any(w in normalize_header(header) for w in _EXCEL_WORDS) if header else False
    steps = np.abs(np.diff(finite))
    steps = steps[steps > 0]
    step = float(np.median(steps)) if len(steps) else np.inf
    fractional = float(np.mean(finite != np.floor(finite)))
    if named or (fractional >= 0.5 and step < EXCEL_STEP):
        info["excel_why"] = (
            f"the header {header!r} names them"
            if named
            else f"all lie in {EXCEL_RANGE[0]:,.0f}-{EXCEL_RANGE[1]:,.0f}, "
            f"{fractional:.0%} have a fraction and the typical step is {step * 86400:.3g} s "
            "as days"
        )
        return True
    info["excel_like"] = info.get("excel_like", 0) + len(finite)
    return False


def _excel_ns(
    days: np.ndarray, tz: datetime.tzinfo | None, info: dict
) -> tuple[np.ndarray, np.ndarray]:
    """Excel serial days (wall-clock, naive; in ``tz`` when given, else UTC) to int64 ns
    since 1970 UTC and validity, to the millisecond (Excel's own resolution)."""
    info["time_format"] = "Excel serial days"
    info["excel_days"] = info.get("excel_days", 0) + int(np.isfinite(days).sum())
    ok = np.isfinite(days) & (days >= 1) & (days < _EXCEL_LAST)
    ms = np.rint((np.where(ok, days, _EXCEL_EPOCH_DAYS) - _EXCEL_EPOCH_DAYS) * 86_400_000.0)
    ns = ms.astype("int64") * 1_000_000
    if tz is None:
        return ns, ok
    info["naive"] = True
    wall = pd.Series(pd.to_datetime(ns, unit="ns")).where(ok)
    utc = _localize(wall, tz, info)
    good = utc.notna().to_numpy()
    out = np.zeros(len(ns), dtype="int64")
    out[good] = utc[good].dt.tz_convert(None).to_numpy().astype("datetime64[ns]").view("int64")
    return out, good


_ZONE_SUFFIX = r"(?:[zZ]|[+-]\d\d:?\d\d|UTC|GMT)$"


def parse_zone(text: str | None) -> datetime.tzinfo | None:
    """``"Asia/Shanghai"``, ``"+08:00"``, ``"-0530"``, ``"UTC"`` → a tzinfo (None for None or
    empty). Raises :class:`InputError` for anything else."""
    if text is None or not str(text).strip():
        return None
    text = str(text).strip()
    m = re.fullmatch(r"(?:UTC|GMT)?([+-])(\d{1,2}):?(\d{2})?", text, flags=re.IGNORECASE)
    if m:
        hours, minutes = int(m[2]), int(m[3] or 0)
        if hours > 14 or minutes > 59:
            raise InputError(f"time zone {text!r}: offsets run from -14:00 to +14:00")
        sign = 1 if m[1] == "+" else -1
        return datetime.timezone(sign * datetime.timedelta(hours=hours, minutes=minutes))
    if text.upper() in ("UTC", "Z", "GMT"):
        return datetime.UTC
    try:
        return zoneinfo.ZoneInfo(text)
    except (zoneinfo.ZoneInfoNotFoundError, ValueError):
        raise InputError(
            f"unknown time zone {text!r}: give an IANA name (Asia/Shanghai, Europe/Oslo) "
            "or an offset (+08:00)"
        ) from None


#: In a file of absolute unix times, a number more than this many seconds before the
#: file's median time is damaged (cut short), not a time of the file.
EARLY_BEFORE_S = 40 * 365.25 * 86400.0


def _is_compact(values: np.ndarray) -> bool:
    """Whether numbers are times written as digits alone, yyyymmddHHMMSS (20240501080104):
    most are 14-digit whole numbers, which as unix milliseconds would lie after 2286."""
    finite = values[np.isfinite(values)]
    if not len(finite):
        return False
    digits = (finite >= 1e13) & (finite < 1e14) & (finite == np.floor(finite))
    return bool(digits.mean() >= 0.9)


def _compact_iso(values: np.ndarray) -> pa.Array:
    """yyyymmddHHMMSS numbers as ISO text (``2024-05-01 08:01:04``); null where a value
    is not 14 digits (quarantined as unparsable)."""
    ok = np.isfinite(values) & (values >= 1e13) & (values < 1e14) & (values == np.floor(values))
    digits = pa.array(np.where(ok, values, 0).astype("int64")).cast(pa.string())
    parts = [pc.utf8_slice_codeunits(digits, a, b) for a, b in _COMPACT_PARTS]
    iso = pc.binary_join_element_wise(
        pc.binary_join_element_wise(*parts[:3], "-"),
        pc.binary_join_element_wise(*parts[3:], ":"),
        " ",
    )
    return pc.if_else(pa.array(ok), iso, pa.scalar(None, pa.string()))


#: Where year, month, day, hour, minute and second sit in yyyymmddHHMMSS.
_COMPACT_PARTS = ((0, 4), (4, 6), (6, 8), (8, 10), (10, 12), (12, 14))


def _epoch_ns(seconds: np.ndarray, info: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Unix seconds or milliseconds to int64 ns, and validity. Relative times (a scene's
    seconds from its start) are seconds; absolute ones are told apart number by number by
    magnitude (1.7e9 s, 1.7e12 ms: a feed that switched unit reads whole)."""
    finite = np.isfinite(seconds)
    mag = np.abs(np.where(finite, seconds, 0.0))
    median = float(np.median(mag[finite])) if finite.any() else 0.0
    ms_file = median > _MS_THRESHOLD
    if info is not None:
        info["time_format"] = "unix ms" if ms_file else "unix s"
        if finite.any() and float(mag[finite].max()) < RELATIVE_BELOW_S:
            info["time_format"] = "relative s"
            info["relative"] = True
    floor = RELATIVE_BELOW_S * (1000.0 if ms_file else 1.0)
    absolute = median >= floor or bool(info is not None and info.get("absolute"))
    per = np.full(len(seconds), 1_000_000 if ms_file else 1_000_000_000, dtype="int64")
    ok = finite.copy()
    if absolute:
        if info is not None:
            info["absolute"] = True
        ms = finite & (mag > _MS_THRESHOLD)
        per = np.where(ms, 1_000_000, 1_000_000_000).astype("int64")
        if info is not None and ms.any() and not ms[finite].all():
            info["time_format"] = "unix s and ms"
        # Among absolute times, a number from the first years after 1970 or decades before
        # the file's others: cut short (a truncated line) or damaged, not a time of this file.
        as_s = np.where(ms, mag / 1000.0, mag) * np.sign(np.where(finite, seconds, 0.0))
        centre = float(np.median(as_s[finite])) if finite.any() else 0.0
        early = finite & ((np.abs(as_s) < RELATIVE_BELOW_S) | (as_s < centre - EARLY_BEFORE_S))
        if early.any():
            ok &= ~early
            if info is not None:
                info["early_times"] = early
    beyond = finite & (mag >= 9.2e18 / per)  # e.g. a ms time cut to 11 digits, read as s
    if beyond.any():
        ok &= ~beyond
        if info is not None and "_rows" in info:
            _mark(info, "outside_span", pd.Series(beyond))
    x = np.where(ok, seconds, 0.0)
    # Whole and fractional parts apart: a float64 of ~1.7e18 ns cannot hold every ns.
    whole = np.floor(x)
    # The fraction to the finest decimal the float holds at its magnitude: 1620114891.8
    # is 1620114891.7999999523 as a float64 (a step of 2.4e-7 s there), read to the µs,
    # not to the ns, so it stays .800 (it was written .799999952, and a resampling grid
    # started from it kept the error).
    # (|x| = m·2^e with m in [0.5, 1): a float's step there is 2^(e-53))
    places = np.clip(np.floor((53 - np.frexp(x)[1]) * np.log10(2.0)), 0, 9)
    scale = 10.0**places
    frac = np.round((x - whole) * scale) / scale
    ns = whole.astype("int64") * per + np.round(frac * per).astype("int64")
    return ns, ok


#: A row is alone in time when it lies more than this from both rows of its track around
#: it in the file (and more than LONE_RATIO times their distance apart): 1 day (s).
LONE_MIN_S = 86_400.0
LONE_RATIO = 100.0


#: Steps back in time (s) smaller than this do not count against a track's file order
#: (AIS from several receivers arrives a little out of order).
ORDER_JITTER_S = 60.0


def _in_file_order(tr: np.ndarray, tt: np.ndarray) -> np.ndarray:
    """Per track code (an array indexed by code): whether its rows, in file order, run in
    time order, forward or backward, but for at most a tenth of their steps (plus two: one
    mistyped row makes two) going the other way by more than :data:`ORDER_JITTER_S`.
    ``tr``: codes grouped by track, ``tt``: their times (s) in file order within a track."""
    size = int(tr.max()) + 1 if len(tr) else 0
    same = tr[1:] == tr[:-1]
    d = np.diff(tt)
    with np.errstate(invalid="ignore"):
        fwd = np.bincount(tr[1:][same & (d > ORDER_JITTER_S)], minlength=size)
        back = np.bincount(tr[1:][same & (d < -ORDER_JITTER_S)], minlength=size)
    steps = np.bincount(tr[1:][same], minlength=size)
    return np.minimum(fwd, back) <= 0.1 * steps + 2


def _lone_times(
    ns: np.ndarray,
    ok: np.ndarray,
    track: np.ndarray,
    piece: tuple[bool, Callable[[np.ndarray], np.ndarray], "LonePending"] | None = None,
) -> np.ndarray:
    """Rows whose time is days from both rows of their track before and after them in the
    file while those two are close (a mistyped year or month: 2032 or 2013 in a 2023
    track; the decades rule misses them). Only such a lone row: a real gap, a track's
    first or last row, or rows out of order together are left alone. The rows of other
    tracks around it screen first (O(n)); only candidates are checked by track.

    ``piece`` (a piece of a file read streamed or in pieces): whether it is the last
    piece with rows, and track codes → the time (s) of each track's last valid row in the
    earlier pieces (NaN: none). Whether a track is written in time order is judged over
    all its rows in the file, and a row's track neighbours may lie in another piece, so
    a piece does not judge: when a candidate of the screen could be lone in the whole
    file — its track's order aside, its row before taken from the earlier pieces where
    the piece has none, and where its row after lies in a later piece, when it is days
    from its row before — :class:`WholeFileNeeded` is raised and the whole file judges;
    else no row of the piece is lone in the whole file either (h149: a track whose times
    jump by months had 5 rows quarantined in pieces of 200 bytes, none whole). The
    screen passes a row only when the rows of the file around it are days from it, so
    an ordinary file never meets this. With a :class:`LonePending` (the piece tuple's
    third item), a track's last row in a piece that is days from its row before is not
    a reason yet: it is carried, and judged by the track's next row in a later piece
    (the whole file is read only if that shows it lone); a track with no later row
    ends there, and a track's last row is never lone (h157: one vessel's late fix in an
    archive written vessel by vessel had the whole file read in memory)."""
    n = len(ns)
    out = np.zeros(n, dtype=bool)
    if n < 3 and piece is None:
        return out
    t = np.where(ok, np.asarray(ns, dtype="float64") / 1e9, np.nan)
    far = LONE_MIN_S
    with np.errstate(invalid="ignore"):
        step = np.abs(np.diff(t))
        cand = np.ones(n, dtype=bool)
        cand[1:] &= ~(step <= far)  # NaN (an invalid neighbour) does not clear it
        cand[:-1] &= ~(step <= far)
    cand &= ok
    pending = None if piece is None else piece[2]
    if pending is not None and len(pending):
        pending.judge(t, ok, track)  # carried rows, by their track's first row here
    if not cand.any():
        return out
    # Same-track neighbours in file order (valid rows only), for the candidates' tracks.
    rows = np.flatnonzero(ok & np.isin(track, sorted_sets.distinct(track[cand])))
    order = rows[np.argsort(track[rows], kind="stable")]
    tr, tt = track[order], t[order]
    same_prev = np.r_[False, tr[1:] == tr[:-1]]
    same_next = np.r_[tr[:-1] == tr[1:], False]
    if piece is not None:  # judged over the file: its track's order, rows in other pieces
        final, carried_last, _ = piece
        at = np.flatnonzero(cand[order])
        prev = np.where(same_prev[at], tt[np.maximum(at - 1, 0)], np.nan)
        first = ~same_prev[at]
        if first.any():
            prev[first] = carried_last(tr[at[first]])
        nxt = np.where(same_next[at], tt[np.minimum(at + 1, len(tt) - 1)], np.nan)
        t_at = tt[at]
        with np.errstate(invalid="ignore"):
            limit = np.maximum(far, LONE_RATIO * np.abs(nxt - prev))
            both = (np.abs(t_at - prev) > limit) & (np.abs(t_at - nxt) > limit)
            later = ~same_next[at] & (not final) & (np.abs(t_at - prev) > far)
        if both.any():
            raise WholeFileNeeded
        if later.any():
            pending.put(tr[at[later]], t_at[later], prev[later])
        return out
    # Only a track written in time order (either way) has neighbours to judge by: in a
    # file of rows in random order every row's neighbours are anywhere in its span.
    same_prev &= _in_file_order(tr, tt)[tr]
    prev = np.r_[np.nan, tt[:-1]]
    nxt = np.r_[tt[1:], np.nan]
    with np.errstate(invalid="ignore"):
        apart = np.abs(nxt - prev)
        limit = np.maximum(far, LONE_RATIO * apart)
        lone = (
            same_prev
            & same_next
            & (np.abs(tt - prev) > limit)
            & (np.abs(tt - nxt) > limit)
            & cand[order]
        )
    out[order[lone]] = True
    return out


def _track_summary(
    ns: np.ndarray, ok: np.ndarray, track: np.ndarray
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Per track of a piece (valid rows, file order): its codes and ``n`` (rows), ``lo``,
    ``hi`` (time span, s), ``first``, ``last`` (times of its first and last rows, s) and
    ``steps`` (sum of its steps |t[i+1] - t[i]|, s). One stable sort of the valid rows."""
    good = np.flatnonzero(np.asarray(ok) & (np.asarray(track) >= 0))
    code = np.asarray(track)[good].astype("int64")
    t = np.asarray(ns)[good].astype("float64") / 1e9
    small = len(code) and code.max() < 1 << 16  # a radix sort: 2 ms, not 20, for 266 k rows
    order = np.argsort(code.astype("uint16") if small else code, kind="stable")
    tr, tt = code[order], t[order]
    if not len(tr):
        empty = np.zeros(0)
        names = ("n", "lo", "hi", "first", "last", "steps")
        return tr, {k: empty for k in names}
    start = np.flatnonzero(np.r_[True, tr[1:] != tr[:-1]])
    end = np.r_[start[1:], len(tr)]
    step = np.r_[np.where(tr[1:] == tr[:-1], np.abs(np.diff(tt)), 0.0), 0.0]
    return tr[start], {
        "n": (end - start).astype("int64"),
        "lo": np.minimum.reduceat(tt, start),
        "hi": np.maximum.reduceat(tt, start),
        "first": tt[start],
        "last": tt[end - 1],
        "steps": np.add.reduceat(step, start),
    }


class LonePending:
    """A read in pieces: rows that ended their track's run in a piece days from their
    track's row before (:func:`_lone_times`), each waiting for the track's next row in
    a later piece. Keyed by the piece's track codes through ``keys`` (set per piece);
    a few rows per file at most (the screen passes only rows days from the file's rows
    around them), so a dict."""

    def __init__(self) -> None:
        self.rows: dict[str, tuple[float, float]] = {}
        self.keys: Callable[[np.ndarray], np.ndarray] = lambda codes: codes.astype(str)

    def __len__(self) -> int:
        return len(self.rows)

    def put(self, codes: np.ndarray, t: np.ndarray, prev: np.ndarray) -> None:
        """Carry these rows (track codes of this piece, times and their rows before, s)."""
        for key, a, b in zip(self.keys(np.asarray(codes)), t, prev, strict=True):
            self.rows[str(key)] = (float(a), float(b))

    def judge(self, t: np.ndarray, ok: np.ndarray, track: np.ndarray) -> None:
        """Judge the carried rows of the tracks with a valid row in this piece (times
        ``t``, s, file order) by that next row; raise :class:`WholeFileNeeded` where one
        is lone (days from both its neighbours), else let it go."""
        good = np.flatnonzero(ok & (track >= 0))
        codes, first = np.unique(track[good], return_index=True)
        names = self.keys(codes)
        hit = np.flatnonzero(np.isin(names, np.array(list(self.rows), dtype=object)))
        for k in hit:
            row_t, row_prev = self.rows.pop(str(names[k]))
            nxt = t[good[first[k]]]
            limit = max(LONE_MIN_S, LONE_RATIO * abs(nxt - row_prev))
            if abs(row_t - row_prev) > limit and abs(row_t - nxt) > limit:
                raise WholeFileNeeded


class EdgeCarry:
    """What a read in pieces carries from piece to piece for the edge-row rule, per track
    (a ``sensor\\x1fbatch`` key; no per-row state): its valid rows' count ``n``, time span
    ``lo``/``hi``, last time ``last`` in file order and the sum of its steps ``steps``
    (every |time difference| of consecutive rows in file order, across pieces; all in s).
    Memory: 5 numbers and a key per track of the file."""

    _FIELDS = ("n", "lo", "hi", "last", "steps")

    def __init__(self) -> None:
        self.keys = pd.Index([], dtype=object)
        self.data = {k: np.zeros(0, dtype="int64" if k == "n" else "float64") for k in self._FIELDS}

    def __len__(self) -> int:
        return len(self.keys)

    def lookup(self, keys: np.ndarray) -> dict[str, np.ndarray]:
        """For each key: its carried numbers (``n`` 0 and NaN for a track not seen) and
        ``at`` (its index here, -1 for none)."""
        at = (
            self.keys.get_indexer(pd.Index(keys, dtype=object))
            if len(self.keys)
            else np.full(len(keys), -1)
        )
        seen = at >= 0
        out: dict[str, np.ndarray] = {"at": at}
        for k in self._FIELDS:
            v = np.zeros(len(keys), dtype="int64") if k == "n" else np.full(len(keys), np.nan)
            v[seen] = self.data[k][at[seen]]
            out[k] = v
        return out

    def spans(self, skip: np.ndarray) -> np.ndarray:
        """[lo, hi] rows (s) of the carried tracks but those at the indices ``skip``."""
        keep = np.ones(len(self.keys), dtype=bool)
        keep[skip[skip >= 0]] = False
        return np.c_[self.data["lo"][keep], self.data["hi"][keep]]

    def add(self, keys: np.ndarray, piece: dict[str, np.ndarray]) -> None:
        """Merge a piece's :func:`_track_summary` (tracks named by ``keys``) in, the piece
        coming after those carried (the step from a track's carried last row to its first
        row in the piece counts)."""
        if not len(keys):
            return
        old = self.lookup(keys)
        seen = old["at"] >= 0
        d = self.data
        at = old["at"][seen]
        d["n"][at] += piece["n"][seen]
        d["lo"][at] = np.minimum(d["lo"][at], piece["lo"][seen])
        d["hi"][at] = np.maximum(d["hi"][at], piece["hi"][seen])
        d["steps"][at] += piece["steps"][seen] + np.abs(piece["first"][seen] - d["last"][at])
        d["last"][at] = piece["last"][seen]
        new = ~seen
        if new.any():
            self.keys = self.keys.append(pd.Index(np.asarray(keys, dtype=object)[new]))
            for k in self._FIELDS:
                d[k] = np.concatenate([d[k], piece[k][new]])


def _edge_times(
    ns: np.ndarray,
    ok: np.ndarray,
    track: np.ndarray,
    earlier: Callable[[np.ndarray], tuple[dict[str, np.ndarray], np.ndarray]] | None = None,
) -> np.ndarray:
    """A track's first or last row (file order, valid rows) with a mistyped date: more
    than ``limit`` = max(:data:`LONE_MIN_S`, :data:`LONE_RATIO` × the track's typical
    step) outside the span of the track's other rows, while no other track of the file
    covers its time: no other track's span (its rows but such lone edge rows) within
    :data:`LONE_MIN_S`, nor another track's lone edge row within it. The typical step of
    a candidate row: the median of its track's steps without the row's own step. Only
    tracks of at least 3 valid rows are judged. ``track``: codes; rows with a negative
    code are not judged.

    ``earlier`` (the last piece of a read in pieces): track codes → what the earlier
    pieces carried for them (:meth:`EdgeCarry.lookup`: ``n``, ``lo``, ``hi``, ``last``,
    ``steps``) and the [lo, hi] spans (s) of the earlier tracks not in this piece. A
    track seen before has its first row here left alone; its last row is judged with its
    earlier rows' span, and a typical step of max(the median of its steps here, 2 × the
    mean of its other steps) — at least the median of all its steps (half of a set of
    steps lie at or above its median, so the median is at most twice the mean), so a read
    in pieces quarantines no row a whole read keeps. Screened in O(n) (each track's first,
    second, last-but-one and last rows); only the tracks with a candidate are sorted."""
    n = len(ns)
    out = np.zeros(n, dtype=bool)
    good = np.flatnonzero(np.asarray(ok) & (np.asarray(track) >= 0))
    if not len(good):
        return out
    code = np.asarray(track)[good].astype("int64")
    size = np.bincount(code)
    t = np.asarray(ns)[good].astype("float64") / 1e9
    far = LONE_MIN_S
    present = np.flatnonzero(size)
    prior = {k: np.zeros(len(size)) for k in ("lo", "hi", "last", "steps")}
    for k in prior:
        prior[k][:] = np.nan
    n_prior = np.zeros(len(size), dtype="int64")
    covered = np.empty((0, 2))
    if earlier is not None:
        got, covered = earlier(present)
        n_prior[present] = got["n"]
        for k in prior:
            prior[k][present] = got[k]
    if len(good) + int(n_prior.sum()) < 3:
        return out

    def first_rows(keep: np.ndarray) -> np.ndarray:
        """Index (in ``good``) of each track's first kept row; -1 for none."""
        pos = np.full(len(size), -1, dtype="int64")
        idx = np.flatnonzero(keep)[::-1]
        pos[code[idx]] = idx  # repeated codes: the last assignment (the first row) stays
        return pos

    def last_rows(keep: np.ndarray) -> np.ndarray:
        pos = np.full(len(size), -1, dtype="int64")
        idx = np.flatnonzero(keep)
        pos[code[idx]] = idx
        return pos

    everyone = np.ones(len(good), dtype=bool)
    first, last = first_rows(everyone), last_rows(everyone)
    not_edge = everyone.copy()
    not_edge[first[size > 0]] = False
    second = first_rows(not_edge)
    not_edge = everyone.copy()
    not_edge[last[size > 0]] = False
    before_last = last_rows(not_edge)
    # First rows: tracks of >= 3 rows not seen before; last rows: >= 3 rows with the
    # earlier pieces' (the row next to a last row: its track's row before it here, or
    # the carried last one).
    k_first = np.flatnonzero((size >= 3) & (n_prior == 0))
    k_first = k_first[np.abs(t[first[k_first]] - t[second[k_first]]) > far]
    k_last = np.flatnonzero((size >= 1) & (size + n_prior >= 3))
    nb = np.where(size[k_last] >= 2, t[np.maximum(before_last[k_last], 0)], prior["last"][k_last])
    k_last = k_last[np.abs(t[last[k_last]] - nb) > far]
    edge = [first[k_first], last[k_last]]
    edge_i = np.concatenate(edge)
    if not len(edge_i):
        return out
    # Candidates' tracks, in file order within each track: steps, typical step, the span
    # of the track's other rows.
    cand_tracks = sorted_sets.distinct(code[edge_i])
    rows = np.flatnonzero(np.isin(code, cand_tracks))
    rows = rows[np.argsort(code[rows], kind="stable")]
    tr, tt = code[rows], t[rows]
    start = np.flatnonzero(np.r_[True, tr[1:] != tr[:-1]])
    end = np.r_[start[1:], len(tr)]
    n_first = len(edge[0])
    is_first = np.arange(len(edge_i)) < n_first
    which = np.searchsorted(tr[start], code[edge_i])
    # Each track's steps here sorted; a candidate's median without its own step (its
    # track's first step for a first row, last step for a last row): of the m - 1 other
    # steps, the lower middle one.
    step = np.abs(np.diff(tt))
    inner_at = np.flatnonzero(tr[1:] == tr[:-1])  # step j: between rows j and j + 1
    st, sv = tr[inner_at], step[inner_at]
    o = np.lexsort((sv, st))
    rank = np.empty(len(o), dtype="int64")
    rank[o] = np.arange(len(o))
    sorted_v = sv[o]
    s0 = np.searchsorted(st[o], tr[start], "left")  # each track's first sorted step
    m = np.searchsorted(st[o], tr[start], "right") - s0  # its steps here
    step_no = np.full(len(step) + 1, -1, dtype="int64")
    step_no[inner_at] = np.arange(len(inner_at))
    own_j = np.where(is_first, start[which], end[which] - 2)  # own step's j (-1: none here)
    own_j = np.where(m[which] >= 1, own_j, len(step))
    own_no = step_no[own_j]
    own_rank = np.r_[rank, -1][np.where(own_no >= 0, own_no, len(rank))]  # in all sorted
    own_rank = np.where(own_rank >= 0, own_rank - s0[which], -1)  # in its track's
    others_n = m[which] - (own_rank >= 0)
    mid = (others_n - 1) // 2
    idx = s0[which] + mid + ((own_rank >= 0) & (own_rank <= mid))
    typical = np.zeros(len(edge_i))
    has = others_n >= 1
    typical[has] = sorted_v[idx[has]]
    # A track seen before (last rows only): its other steps' mean, twice, bounds their median.
    c = code[edge_i]
    own_here = m[which] >= 1  # the last row's own step lies here, not from the carried row
    bridge = np.where(own_here, np.abs(tt[start[which]] - prior["last"][c]), 0.0)
    count = n_prior[c] - 1 + own_here
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = (prior["steps"][c] + bridge) / count
    typical = np.where((n_prior[c] > 0) & (count >= 1), np.fmax(typical, 2 * mean), typical)
    # Span of each track's rows but its first, and but its last (with its earlier rows).
    tail, head_only = tt.copy(), tt.copy()
    tail[start] = np.nan
    head_only[end - 1] = np.nan
    lo = np.where(
        is_first, np.fmin.reduceat(tail, start)[which], np.fmin.reduceat(head_only, start)[which]
    )
    hi = np.where(
        is_first, np.fmax.reduceat(tail, start)[which], np.fmax.reduceat(head_only, start)[which]
    )
    lo, hi = np.fmin(lo, prior["lo"][c]), np.fmax(hi, prior["hi"][c])
    limit = np.maximum(far, LONE_RATIO * typical)
    te = t[edge_i]
    with np.errstate(invalid="ignore"):
        alone = (te < lo - limit) | (te > hi + limit)
    if not alone.any():
        return out
    # Other tracks: the span of every track of the file within a day, a track's rows
    # but its alone edge rows (a typo's span covers nothing); an alone edge row of
    # another track within a day covers it too (two ships seen again on one day).
    lo_all = np.full(len(size), np.inf)
    hi_all = np.full(len(size), -np.inf)
    np.minimum.at(lo_all, code, t)
    np.maximum.at(hi_all, code, t)
    pos = np.where(is_first, start[which], end[which] - 1)[alone]
    core = tt.copy()
    core[pos] = np.nan
    lo_all[tr[start]] = np.fmin.reduceat(core, start)
    hi_all[tr[start]] = np.fmax.reduceat(core, start)
    lo_all = np.fmin(lo_all, prior["lo"])  # with the track's earlier rows
    hi_all = np.fmax(hi_all, prior["hi"])
    lo_all = np.where(np.isnan(lo_all), np.inf, lo_all)
    hi_all = np.where(np.isnan(hi_all), -np.inf, hi_all)
    have = np.isfinite(lo_all) & np.isfinite(hi_all)
    span_lo = np.r_[lo_all[have], np.asarray(covered, dtype="float64")[:, 0]]
    span_hi = np.r_[hi_all[have], np.asarray(covered, dtype="float64")[:, 1]]
    starts = np.sort(span_lo - far)
    stops = np.sort(span_hi + far)
    spans = np.searchsorted(starts, te, "right") - np.searchsorted(stops, te, "left")
    own = (te >= lo_all[c] - far) & (te <= hi_all[c] + far)
    others = spans - own
    lone_t = np.sort(te[alone])
    others += (
        np.searchsorted(lone_t, te + far, "right") - np.searchsorted(lone_t, te - far, "left")
    ) - alone  # itself
    out[good[edge_i[alone & (others == 0)]]] = True
    return out


def with_final(
    items: Iterator[tuple[bytes, int]], has_rows: Callable[[bytes], bool]
) -> Iterator[tuple[tuple[bytes, int], bool]]:
    """Each (piece, first line) with whether it is the last piece with rows
    (``has_rows(piece)``; pieces after it hold only blank lines). Reads ahead to the next
    piece with rows: holds one piece, and the blank ones after it, until then; a piece
    handed out is not kept here, so the caller can free it."""
    pending: list = []
    for item in items:
        if has_rows(item[0]) and pending:
            while pending:
                yield pending.pop(0), False
        pending.append(item)
        del item
    final = True  # the first held piece with rows is the last one
    while pending:
        rows = has_rows(pending[0][0])
        yield pending.pop(0), final and rows
        final = final and not rows


def blank_bytes(delimiter: str) -> Callable[[bytes], bool]:
    """``has_rows(piece)`` for :func:`with_final`: whether ``piece`` holds a byte other
    than blanks, line ends, quotes and ``delimiter`` (a row with a value)."""
    drop = b' \t\r\n\x0b\x0c"' + delimiter.encode("ascii", "ignore")

    def has_rows(piece: bytes) -> bool:
        return bool(piece.translate(None, drop))

    return has_rows


def edge_state() -> dict:
    """What a read in pieces carries from piece to piece for the edge-row rule: each
    track's :class:`EdgeCarry` numbers (``carry``, filled by the pieces before the last
    one with rows). The piece's reader is told ``final`` for the file's last piece with
    rows (:func:`with_final`), where the rule runs; and the rows the lone-time rule
    waits to judge by a later piece (``lone``, :class:`LonePending`); each track's last
    time for the steps back (``back``, :class:`LastTimes`); whether a piece found a
    sensor (track) whose lat and lon look swapped (``swapped``: the whole file judges it)."""
    return {
        "carry": EdgeCarry(),
        "lone": LonePending(),
        "back": LastTimes(),
        "swapped": [],
        "final": False,
    }


def _decades_away(ns: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Valid times more than :data:`EARLY_BEFORE_S` from the median of the valid ones
    (taken on at most ~100 k of them)."""
    good = np.flatnonzero(ok)
    if len(good) < 3:
        return np.zeros(len(ns), dtype=bool)
    sample = np.asarray(ns)[good[:: max(len(good) // 100_000, 1)]]
    centre = float(np.median(sample))  # float: 1700 minus 2023 in ns overflows int64
    return np.asarray(ok) & (
        np.abs(np.asarray(ns, dtype="float64") - centre) > EARLY_BEFORE_S * 1e9
    )


_NS_LIMIT = 9_223_372_036  # whole seconds either side of 1970 an int64 of ns can hold
_UNIT_PER_S = {"s": 1, "ms": 1_000, "us": 1_000_000, "ns": 1_000_000_000}


def _mark(info: dict | None, key: str, mask: pd.Series) -> None:
    """OR a per-row flag (a bool Series indexed by row) into ``info[key]``, a bool array
    over the whole column (``info["_rows"]`` long), which the reader turns into a reason."""
    if info is None or not mask.any():
        return
    if key not in info:
        info[key] = np.zeros(info["_rows"], dtype=bool)
    info[key][mask.index.to_numpy()[mask.to_numpy(dtype=bool)]] = True


def _as_ns(values: pd.Series, info: dict | None = None) -> pd.Series:
    """Times at ns resolution; times a ns clock cannot hold (before 1677 or after 2262,
    parsed at a coarser unit) become NaT and are marked ``outside_span`` in ``info``."""
    unit = values.dt.unit
    if unit != "ns":
        plain = values.dt.tz_convert(None) if values.dt.tz is not None else values
        raw = plain.to_numpy().view("int64")
        limit = _NS_LIMIT * _UNIT_PER_S[unit]
        outside = pd.Series((raw != np.iinfo("int64").min) & (np.abs(raw) >= limit), values.index)
        if outside.any():
            _mark(info, "outside_span", outside)
            values = values.where(~outside)
    return values.dt.as_unit("ns")


def _localize(values: pd.Series, tz: datetime.tzinfo, info: dict | None = None) -> pd.Series:
    """Naive wall-clock times in ``tz`` → UTC. A time skipped by a clock change becomes
    NaT, marked ``clock_change`` in ``info``; so does a time the clock repeated, marked
    ``ambiguous`` too with both instants (``ambiguous_first``, ``ambiguous_second``, ns)
    and the wall clock (``ambiguous_wall``), which the reader may place by track order."""
    values = _as_ns(values, info)
    utc = values.dt.tz_localize(tz, ambiguous="NaT", nonexistent="NaT")
    changed = values.notna() & utc.isna()
    _mark(info, "clock_change", changed)
    if info is not None and changed.any():
        first = values[changed].dt.tz_localize(tz, ambiguous=True, nonexistent="NaT")
        repeated = first.notna()
        if repeated.any():
            rows = first.index[repeated.to_numpy()]
            second = values[rows].dt.tz_localize(tz, ambiguous=False)
            _mark(info, "ambiguous", pd.Series(True, index=rows))
            for key, vals in (
                ("ambiguous_first", first[rows].dt.tz_convert(None)),
                ("ambiguous_second", second.dt.tz_convert(None)),
                ("ambiguous_wall", values[rows]),
            ):
                if key not in info:
                    info[key] = np.zeros(info["_rows"], dtype="int64")
                info[key][rows.to_numpy()] = vals.to_numpy().view("int64")
    return utc.dt.tz_convert("UTC")


#: A track's wall clock must step back at least this far (s) inside the repeated hour of a
#: clock change for its rows there to be read as two passes (a late message steps back
#: minutes; the change steps back an hour less the track's interval).
PASS_BACK_S = 1800.0


def _place_repeated_hour(track: np.ndarray, info: dict, ns: np.ndarray, ok: np.ndarray) -> int:
    """Times in the hour a clock change repeats, placed by their track's file order.

    A track whose times in that hour run forward, step back once by at least
    :data:`PASS_BACK_S`, then run forward again shows both passes: the rows before the
    step are the first pass, the rest the second — provided the whole track, placed so,
    runs forward in the file. Any other track (one pass, rows out of order, a file
    newest-first or shuffled) keeps them quarantined: which pass a row was is not in the
    file. Sets ``ns``/``ok`` in place and clears the placed rows from
    ``info["clock_change"]``; returns how many were placed.
    """
    amb = info.pop("ambiguous", None)
    first = info.pop("ambiguous_first", None)
    second = info.pop("ambiguous_second", None)
    wall = info.pop("ambiguous_wall", None)
    if amb is None:
        return 0
    rows = np.flatnonzero(amb)  # file order
    frame = pd.DataFrame({"track": track[rows], "wall": wall[rows]}, index=rows)
    step = frame.groupby("track")["wall"].diff().to_numpy()  # ns; NaN at a track's first
    back = step < 0
    frame["back"] = back.astype("int8")
    frame["big"] = (back & (-step >= PASS_BACK_S * 1e9)).astype("int8")
    per = frame.groupby("track").agg(backs=("back", "sum"), big=("big", "sum"))
    two = per.index[(per["backs"] == 1) & (per["big"] == 1)]
    chosen = frame["track"].isin(two).to_numpy()
    if not chosen.any():
        return 0
    after = frame["back"].groupby(frame["track"]).cummax().to_numpy(dtype=bool)
    placed = rows[chosen]
    trial = ns.copy()
    trial[placed] = np.where(after[chosen], second[placed], first[placed])
    # The whole track so placed must run forward in the file (its other rows too).
    usable = ok.copy()
    usable[placed] = True
    in_two = np.isin(track, np.asarray(two)) & usable
    members = np.flatnonzero(in_two)
    sub = pd.DataFrame({"track": track[members], "t": trial[members]})
    forward = sub.groupby("track")["t"].diff().fillna(0).to_numpy() >= 0
    bad_tracks = sorted_sets.distinct(sub["track"].to_numpy()[~forward])
    placed = placed[~np.isin(track[placed], bad_tracks)]
    ns[placed] = trial[placed]
    ok[placed] = True
    info["clock_change"][placed] = False
    return len(placed)


def _as_days(values: np.ndarray, kind: str, time_unit: str, header: str, info: dict) -> bool:
    """Whether numeric times are Excel serial days: as ``time_unit`` says, or (``auto``)
    as a streamed read's first piece decided (``info["_unit"]``), or by the rule."""
    if time_unit != "auto":
        return time_unit == "excel-days"
    if kind == "unix":
        return False
    if "_unit" in info:
        return info["_unit"] == "excel-days"
    return excel_days_rule(values, header, info)


def _piece(info: dict) -> bool:
    """Whether ``info`` is a piece's of a file read in pieces or streamed."""
    return bool(info.get("_streaming")) or "_edges" in info


def _hhmmss(values: np.ndarray, kind: str, time_unit: str, info: dict) -> np.ndarray | None:
    """Seconds of the day of numbers that are clock times written HHMMSS (values and
    steps show it: :func:`~wakeline.core.io.timetext.hhmmss_evidence`), else None; only
    for ``auto`` (a family's unix times, or ``--time-unit seconds``, stay seconds). A piece
    whose numbers could be HHMMSS leaves the judgement to a whole read (the step that
    shows it may lie across two pieces)."""
    if kind != "auto" or time_unit != "auto":
        return None
    if _piece(info) and valid_hhmmss(values):
        raise WholeFileNeeded
    evidence = hhmmss_evidence(values)
    if evidence is None:
        return None
    info["hhmmss"] = evidence
    info["time_format"] = "HHMMSS clock numbers"
    return hhmmss_seconds(values)


def _clock_ns(
    seconds: np.ndarray, clock_date: str | None, info: dict
) -> tuple[np.ndarray, np.ndarray]:
    """Seconds of the day (NaN: none) as wall-clock ns from ``clock_date``'s midnight
    (1970-01-01 when None: relative), and validity; ``info["clock_only"]`` set. A piece
    of a file leaves them to a whole read: a track's day rolls over midnight from its
    rows in any piece."""
    if _piece(info):
        raise WholeFileNeeded
    ok = np.isfinite(seconds)
    info["clock_only"] = True
    if clock_date is None:
        info["relative"] = True
    ns = np.where(ok, day_ns(clock_date) + sod_ns(seconds), 0)
    return ns, ok


def _clock_times(
    ns: np.ndarray,
    ok: np.ndarray,
    track: np.ndarray,
    zone: datetime.tzinfo | None,
    clock_date: str | None,
    info: dict,
) -> tuple[np.ndarray, np.ndarray]:
    """Clock times of a day (:func:`_clock_ns`) rolled over midnight by track
    (:func:`~wakeline.core.io.timetext.roll_days`, counted in ``info["clock_rollovers"]``)
    and, on a given day, read in ``zone`` (UTC when None)."""
    ns, rolled = roll_days(track, np.asarray(ns), np.asarray(ok))
    info["clock_rollovers"] = info.get("clock_rollovers", 0) + rolled
    if zone is None or clock_date is None:
        return ns, ok
    wall = pd.Series(pd.to_datetime(ns, unit="ns")).where(ok)
    utc = _localize(wall, zone, info)
    good = utc.notna().to_numpy()
    out = np.zeros(len(ns), dtype="int64")
    out[good] = utc[good].dt.tz_convert(None).to_numpy().astype("datetime64[ns]").view("int64")
    return out, good


def parse_times(
    arr: pa.ChunkedArray,
    kind: str,
    tz: datetime.tzinfo | None = None,
    info: dict | None = None,
    decimal_comma: bool = False,
    date_order: str = "auto",
    time_unit: str = "auto",
    header: str = "",
    clock_date: str | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """int64 ns since epoch (UTC) and a validity mask, read in the column's form
    (:func:`_parse_times_in_one_form`); then, in a column of ISO 8601 text with some unix
    seconds among them, or the other way (two exports joined: operator test 10), the
    times written in the other form, each read in its own form when it falls within a
    day of the others' span (``info["other_form_times"]`` counts them)."""
    info = {} if info is None else info
    ns, ok = _parse_times_in_one_form(
        arr, kind, tz, info, decimal_comma, date_order, time_unit, header, clock_date
    )
    if kind == "auto" and ok.any() and not ok.all():
        ns, ok = _times_in_the_other_form(arr, ns, ok, tz, info, date_order)
    return ns, ok


_ISO_DATE_START = r"\s*[0-9]{4}-[0-9]{2}-[0-9]{2}[T ][0-9]{2}:[0-9]{2}"


def _times_in_the_other_form(
    arr: pa.ChunkedArray,
    ns: np.ndarray,
    ok: np.ndarray,
    tz: datetime.tzinfo | None,
    info: dict,
    date_order: str,
) -> tuple[np.ndarray, np.ndarray]:
    """Rows left unread of a column read as absolute unix times whose text is an ISO 8601
    date and time, or of a column read as ISO 8601 text whose text is a plain number:
    read in that form, those within a day of the column's span of times
    (a stray number, a date of another year, stays unparsable)."""
    fmt = str(info.get("time_format"))
    numbers = fmt.startswith("unix") and not info.get("relative")
    if not (numbers or fmt == "ISO 8601 text") or not pa.types.is_string(arr.type):
        return ns, ok
    text = pd.Series(arr.to_pandas(), dtype="str")
    if numbers:
        other = text.str.match(_ISO_DATE_START, na=False).to_numpy(dtype=bool)
    else:
        other = text.str.fullmatch(r"\s*[0-9]{9,13}(?:\.[0-9]*)?\s*", na=False).to_numpy(dtype=bool)
    rows = np.flatnonzero(other & ~ok)
    if not len(rows):
        return ns, ok
    part = pa.chunked_array([pa.array(text.iloc[rows].tolist(), pa.string())])
    seen: dict = {}  # the other form's own reading: its masks and counts are not the column's
    if numbers:
        ns2, ok2 = _parse_times_in_one_form(part, "auto", tz, seen, date_order=date_order)
        ok2 = ok2 & (seen.get("time_format") == "ISO 8601 text")
    else:
        ns2, ok2 = _parse_times_in_one_form(part, "unix", tz, seen)
        ok2 = ok2 & (not seen.get("relative"))
    day = 86_400 * 1_000_000_000
    ok2 = ok2 & (ns2 >= ns[ok].min() - day) & (ns2 <= ns[ok].max() + day)
    if not ok2.any():
        return ns, ok
    ns, ok = ns.copy(), ok.copy()  # a pyarrow buffer's view may be read-only
    ns[rows[ok2]] = ns2[ok2]
    ok[rows[ok2]] = True
    info["other_form_times"] = info.get("other_form_times", 0) + int(ok2.sum())
    if numbers and seen.get("naive"):
        info["naive"] = True  # ISO text without a zone among the numbers: read as UTC (or --tz)
    return ns, ok


def _parse_times_in_one_form(
    arr: pa.ChunkedArray,
    kind: str,
    tz: datetime.tzinfo | None = None,
    info: dict | None = None,
    decimal_comma: bool = False,
    date_order: str = "auto",
    time_unit: str = "auto",
    header: str = "",
    clock_date: str | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """int64 ns since epoch (UTC) and a validity mask.

    Dates with English month names and Chinese dates are read as ISO text is
    (:mod:`~wakeline.core.io.timetext`). Clock times without a date (``23:50:00.5``, and
    numbers whose values and steps show HHMMSS) are times of day on ``clock_date``
    (``YYYY-MM-DD``; None: 1970-01-01, relative): ``info["clock_only"]`` is then set and
    the times are wall clock from that day's midnight, not yet rolled over midnight nor
    put in ``tz`` (:func:`_clock_times` does both, knowing the tracks).

    Numbers are Excel serial days when ``time_unit`` says so, or (``auto``) by
    :func:`excel_days_rule`' rule on the column ``header`` and its values.

    Times without a zone are UTC unless ``tz`` names their zone; numbers are unix seconds
    or milliseconds (absolute: ``tz`` does not apply), with a decimal comma too when
    ``decimal_comma``. Slashed dates are read in ``date_order`` (:data:`DATE_ORDERS`).
    ``info``, when given, receives ``time_format``, ``naive`` (text without a zone seen),
    ``relative`` (seconds from a scene start rather than since 1970), ``decimal_comma``
    (how many numbers had one) and what decided the order of slashed dates
    (``month_first``, ``day_shown``, ``dates_either_way``, ``date_order_given``,
    ``date_order_refused``)."""
    info = {} if info is None else info
    info["_rows"] = len(arr)
    if time_unit != "auto":
        info["time_unit_given"] = time_unit  # said when the times are text after all
    info.setdefault("naive", False)
    info.setdefault("relative", False)
    if clock_date is not None:
        info["clock_date_given"] = clock_date  # said when the times have dates after all
    if pa.types.is_time(arr.type):  # pyarrow typed clock times alone (23:50:00)
        arr = pc.cast(arr, pa.string())
    if pa.types.is_timestamp(arr.type):
        info["time_format"] = "ISO 8601 text"
        info["_texts"] = info.get("_texts", 0) + len(arr) - arr.null_count
        if info.get("_by_table") and tz is None:  # a piece typed by pyarrow: one kind
            valid_n = len(arr) - arr.null_count
            info["_zoned_n" if arr.type.tz is not None else "_naive_n"] = valid_n
        if arr.type.tz is not None and len(arr) > arr.null_count:
            info["zoned_written"] = True  # times with a zone: _file_offsets reads which
        if arr.type.tz is None:
            info["naive"] = True
            if tz is not None:
                utc = _localize(pd.Series(arr.to_pandas()), tz, info)
                ok = utc.notna().to_numpy()
                ns = np.zeros(len(utc), dtype="int64")
                ns[ok] = utc[ok].dt.tz_convert(None).to_numpy().astype("int64")
                return ns, ok
        per_s = _UNIT_PER_S[arr.type.unit]
        valid = np.asarray(pc.is_valid(arr), dtype=bool)
        # nulls filled first: to_numpy would give floats with NaN (and lose ns)
        raw = pc.cast(arr, pa.int64()).fill_null(0).to_numpy(zero_copy_only=False)
        outside = valid & (np.abs(raw) >= _NS_LIMIT * per_s)
        _mark(info, "outside_span", pd.Series(outside))
        ok = valid & ~outside
        ns = np.where(ok, raw, 0) * (1_000_000_000 // per_s)
        return ns, ok
    compact = False  # digits alone, yyyymmddHHMMSS: read as the text they spell
    if pa.types.is_integer(arr.type) or pa.types.is_floating(arr.type):
        seconds = pc.cast(arr, pa.float64()).to_numpy(zero_copy_only=False)
        if _as_days(seconds, kind, time_unit, header, info):
            return _excel_ns(seconds, tz, info)
        clock = _hhmmss(seconds, kind, time_unit, info)
        if clock is not None:
            return _clock_ns(clock, clock_date, info)
        if kind != "auto" or not _is_compact(seconds):
            return _epoch_ns(seconds, info)
        arr, compact = pa.chunked_array([_compact_iso(seconds)]), True
    text = pd.Series(arr.to_pandas(), dtype="str").str.strip()
    numeric = _numeric_texts(text)
    if kind == "auto" and not compact and _is_compact(numeric):
        text = pd.Series(_compact_iso(numeric).to_pandas(), index=text.index, dtype="str")
        compact, numeric = True, np.full(len(text), np.nan)
    present = ~(text.isna() | (text == ""))
    if decimal_comma:
        k = _with_decimal_comma(text, numeric, info)
        if k:
            info["decimal_comma"] = info.get("decimal_comma", 0) + k
    n_present = int(present.sum())
    info["_texts"] = info.get("_texts", 0) + n_present  # times written, of any form
    if kind == "unix" or (n_present and np.isfinite(numeric).sum() >= 0.5 * n_present):
        if _as_days(numeric, kind, time_unit, header, info):
            return _excel_ns(numeric, tz, info)
        clock = _hhmmss(numeric, kind, time_unit, info)
        if clock is not None:
            return _clock_ns(clock, clock_date, info)
        return _epoch_ns(numeric, info)
    clock = is_clock(text) & present
    if n_present and clock.sum() >= 0.5 * n_present:
        # times of day alone (a radar's log): on the day given, or relative
        info["time_format"] = "clock time text"
        info["naive"] = True
        return _clock_ns(clock_seconds(text).to_numpy(dtype="float64"), clock_date, info)
    named = named_form = None
    hint = present & text.str.contains(NAMED_HINT, regex=True).fillna(False).astype(bool)
    if hint.any():
        # Zone words after the clock (CET, EST, UTC+8): written as their offsets
        worded, words, left = zone_words(text[hint], tz is not None)
        if words or left:
            text = text.copy()
            text[hint] = worded
            for word, k in words.items():
                info.setdefault("zone_words", {})
                info["zone_words"][word] = info["zone_words"].get(word, 0) + k
            for word, rows in left.items():
                mask = np.zeros(len(text), dtype=bool)
                mask[np.flatnonzero(hint.to_numpy())[rows]] = True
                info.setdefault("zone_ambiguous", {})[word] = mask
        # English month names and Chinese dates: written again as ISO 8601 text
        cn = hint & text.str.contains("年", regex=False).fillna(False).astype(bool)
        months = named_iso(text[hint & ~cn])
        han = chinese_iso(text[cn])
        named = pd.concat([months, han]).reindex(text[hint].index)
        if named.notna().sum() >= 0.5 * n_present:
            more = "Chinese date text" if han.notna().sum() > months.notna().sum() else None
            named_form = more or "month-name text"
        if named.notna().any():
            text = text.copy()
            text[named.index] = named.where(named.notna(), text[named.index])
    sample = text[present].head(50)
    # ISO 8601's decimal comma (08:01:04,123, as Python's logging writes) and a zone
    # written as a word (08:01:04 UTC): forms the ISO parser below does not take.
    if sample.str.contains(r":\d\d,\d", regex=True).any():
        text = text.str.replace(r"(:\d\d),(\d)", r"\1.\2", regex=True)
    if sample.str.contains(r"\s(?:UTC|GMT)$", regex=True).any():
        text = text.str.replace(r"\s*(?:UTC|GMT)$", "Z", regex=True)
    dayfirst = named_form is None and (
        kind == "dayfirst" or bool(sample.str.match(r"^\d{1,2}[/.-]\d{1,2}[/.-]\d{4}").mean() > 0.5)
    )
    zoned = text.str.contains(_ZONE_SUFFIX, regex=True).fillna(False).to_numpy(dtype=bool)
    info["naive"] = bool((present.to_numpy() & ~zoned).any())
    info["time_format"] = "day-first text" if dayfirst else "ISO 8601 text"
    if compact:
        info["time_format"] = "yyyymmddHHMMSS text"
    elif named_form is not None:
        info["time_format"] = named_form
    if dayfirst and date_order != "auto":
        # The operator's order: no guessing; a date the other order only reads (a first
        # number above 12 for month first) is unparsable, and counted.
        text = text.str.removesuffix("Z")
        month = date_order == "month-first"
        formats = _MONTHFIRST_FORMATS if month else _DAYFIRST_FORMATS
        parsed = _parse_slashed(text, present, formats, info)
        info["time_format"] = "month-first text" if month else "day-first text"
        info["date_order_given"] = date_order
        first, second = _slashed_parts(text[present])
        refused = int(((first if month else second) > 12).sum())
        if refused:
            info["date_order_refused"] = info.get("date_order_refused", 0) + refused
        parsed = _localize(parsed, tz, info) if tz is not None else parsed.dt.tz_localize("UTC")
    elif dayfirst:
        text = text.str.removesuffix("Z")  # 01/05/2024 08:01:04 UTC: UTC, as naive
        parsed = _parse_slashed(text, present, _DAYFIRST_FORMATS, info)
        # Dates that day-first cannot read (05/17/2024) and none that only it can: the
        # file writes the month first. (A whole file's evidence: a piece of a streamed
        # read may hold only days up to 12.)
        if kind != "dayfirst" and (parsed.isna() & present).any():
            month_first = month_first_dates(text[present])
            if month_first:
                if info.get("_streaming"):
                    raise WholeFileNeeded
                parsed = _parse_slashed(text, present, _MONTHFIRST_FORMATS, info)
                info["time_format"] = "month-first text"
                info["month_first"] = month_first
        if kind != "dayfirst" and not info.get("month_first"):
            # read day-first: say so when no date shows it (03/01/2023 is 3 January here,
            # 1 March in a US export); a piece's days above 12 show it for the whole file
            parts = text[present].str.extract(r"^\s*(\d{1,2})/(\d{1,2})/\d{4}")  # dots: European
            first = pd.to_numeric(parts[0], errors="coerce")
            second = pd.to_numeric(parts[1], errors="coerce")
            shown = (first > 12) & parsed[present].notna()  # 31/02 shows no order
            # a 12-hour clock (8:01:04 PM) is a US export's: month first, unless a date
            # shows the day first (the whole file's evidence, as above)
            ampm = text[present].str.contains(_AMPM_END, regex=True).fillna(False)
            either = (first != second) & first.notna() & second.notna()  # the order matters
            if not shown.any() and ampm.any() and either.any():
                if info.get("_streaming"):
                    raise WholeFileNeeded
                parsed = _parse_slashed(text, present, _MONTHFIRST_FORMATS, info)
                info["time_format"] = "month-first text"
                info["month_first_ampm"] = int(ampm.sum())
            elif shown.any():
                info["dayfirst_shown"] = True
                info["day_shown"] = info.get("day_shown", 0) + int(shown.sum())
            else:
                both = (first != second) & first.notna() & second.notna() & parsed[present].notna()
                info["dates_either_way"] = info.get("dates_either_way", 0) + int(both.sum())
        parsed = _localize(parsed, tz, info) if tz is not None else parsed.dt.tz_localize("UTC")
    elif tz is not None and info["naive"]:
        parsed = pd.Series(pd.NaT, index=text.index, dtype="datetime64[ns, UTC]")
        naive = present.to_numpy() & ~zoned
        local = pd.to_datetime(text[naive], format="ISO8601", errors="coerce")
        parsed[naive] = _localize(pd.Series(local), tz, info)
        if zoned.any():
            parsed[zoned] = _as_ns(
                pd.to_datetime(text[zoned], format="ISO8601", errors="coerce", utc=True),
                info,
            )
    else:
        parsed = pd.to_datetime(text, format="ISO8601", errors="coerce", utc=True)
    parsed = _as_ns(pd.Series(parsed), info)
    ok = parsed.notna().to_numpy()
    if (ok & zoned).any():
        info["zoned_written"] = True  # times with a zone: _file_offsets reads which
    if tz is None:  # zoned and zone-less times in one column: the latter read as UTC
        with_zone = int((ok & zoned).sum())
        without = int((ok & ~zoned).sum())
        if info.get("_by_table"):  # a table or piece of several: judged over them all
            info["_zoned_n"], info["_naive_n"] = with_zone, without
        elif with_zone and without:
            info["zoneless_times"] = info.get("zoneless_times", 0) + without
            info["zoned_times"] = info.get("zoned_times", 0) + with_zone
    ns = np.zeros(len(parsed), dtype="int64")
    ns[ok] = (
        (parsed[ok] - pd.Timestamp(0, tz="UTC")).to_numpy().astype("timedelta64[ns]").view("int64")
    )
    return ns, ok


#: The GPS epoch (1980-01-06T00:00:00 UTC) in unix seconds, and a week's seconds.
GPS_EPOCH_S = 315_964_800
GPS_WEEK_S = 604_800
#: GPS - UTC (s) from each leap second on (UTC dates): 18 s since 2017-01-01.
GPS_LEAPS = (
    ("1981-07-01", 1),
    ("1982-07-01", 2),
    ("1983-07-01", 3),
    ("1985-07-01", 4),
    ("1988-01-01", 5),
    ("1990-01-01", 6),
    ("1991-01-01", 7),
    ("1992-07-01", 8),
    ("1993-07-01", 9),
    ("1994-07-01", 10),
    ("1996-01-01", 11),
    ("1997-07-01", 12),
    ("1999-01-01", 13),
    ("2006-01-01", 14),
    ("2009-01-01", 15),
    ("2012-07-01", 16),
    ("2015-07-01", 17),
    ("2017-01-01", 18),
)
#: ... the same as GPS seconds since the GPS epoch at which each offset starts.
_LEAP_AT_GPS = np.array(
    [pd.Timestamp(d, tz="UTC").timestamp() - GPS_EPOCH_S + k for d, k in GPS_LEAPS]
)
_LEAP_S = np.array([0] + [k for _, k in GPS_LEAPS], dtype="float64")
GPS_NO_WEEK = (
    "GPS seconds of the week in {!r} (below 604,800) without a week column (gps_week): "
    "the week is unknown"
)


def gps_ns(
    seconds: np.ndarray, week: np.ndarray | None, info: dict | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """UTC ns since 1970 of GPS times: ``week`` numbers (full, not modulo 1024) and
    ``seconds`` of the week (0 to 604,800), or, without ``week``, seconds since the GPS
    epoch; GPS time runs ahead of UTC by the leap seconds since 1980 (18 s since 2017,
    :data:`GPS_LEAPS`). Returns ns, a validity mask and the rows whose seconds look like
    seconds of a week with no week to count from (below 604,800 without ``week``)."""
    if info is not None:
        info["time_format"] = (
            "GPS week and seconds of week" if week is not None else "GPS seconds since 1980-01-06"
        )
    with np.errstate(invalid="ignore"):
        if week is not None:
            ok = (
                np.isfinite(week)
                & (week >= 0)
                & (week == np.floor(week))
                & (seconds >= 0)
                & (seconds < GPS_WEEK_S)
            )
            gps = np.where(ok, week, 0.0) * GPS_WEEK_S + np.where(ok, seconds, 0.0)
            no_week = np.zeros(len(seconds), dtype=bool)
        else:
            no_week = (seconds >= 0) & (seconds < GPS_WEEK_S)
            ok = np.isfinite(seconds) & (seconds >= GPS_WEEK_S) & (seconds < 9e9)
            gps = np.where(ok, seconds, 0.0)
    leap = _LEAP_S[np.searchsorted(_LEAP_AT_GPS, gps, side="right")]
    whole = np.floor(gps)
    ns = (whole - leap + GPS_EPOCH_S).astype("int64") * 1_000_000_000
    ns += np.round((gps - whole) * 1e9).astype("int64")  # the fraction to the ns a float holds
    return np.where(ok, ns, 0), ok, no_week & ~ok


#: UTC seconds since the GPS epoch (ns) from which each offset of :data:`GPS_LEAPS` holds.
_LEAP_AT_UTC_NS = np.array(
    [
        int(pd.Timestamp(d, tz="UTC").timestamp() - GPS_EPOCH_S) * 1_000_000_000
        for d, _ in GPS_LEAPS
    ],
    dtype="int64",
)


def gps_of_utc_ns(ns: np.ndarray) -> np.ndarray:
    """GPS ns since the GPS epoch (1980-01-06) of UTC ns since 1970: :func:`gps_ns`
    inverted, the leap seconds added as it takes them off (a time read from the GPS
    second of a leap second, which :func:`gps_ns` gives the UTC of the second after it,
    comes back as that second's)."""
    since = np.asarray(ns, dtype="int64") - GPS_EPOCH_S * 1_000_000_000
    leap = _LEAP_S[np.searchsorted(_LEAP_AT_UTC_NS, since, side="right")].astype("int64")
    return since + leap * 1_000_000_000


def _one_line(sn: Sniff) -> bool:
    """Whether the file holds one line at most (no line break after its first one)."""
    with open_data(sn.path, sn.compression) as fh:
        head = fh.read(1 << 16)
    return (
        len(head) < (1 << 16)
        and not head.rstrip(b"\r\n").count(b"\n")
        and b"\r" not in head.rstrip(b"\r\n")
    )


def _raw_lines(sn: Sniff, line_numbers: np.ndarray, encoding: str | None = None) -> list[str]:
    """The text of the given physical lines (1-based), as in the file.

    One streaming pass, stopping after the last wanted line; used only for the
    quarantine, so a clean file never pays for it.
    """
    if len(line_numbers) == 0:
        return []
    wanted = set(int(n) for n in line_numbers)
    last = max(wanted)
    found: dict[int, str] = {}
    # decoded as the reader decoded them (a line not valid UTF-8 in its fallback)
    enc = lines_codec(encoding or sn.encoding, sn.encoding_given and not sn.line_fallback)
    with (
        open_data(sn.path, sn.compression) as raw,
        io.TextIOWrapper(raw, encoding=enc, errors="replace", newline=None) as fh,
    ):
        for number, line in enumerate(fh, start=1):
            if number in wanted:
                found[number] = line.rstrip("\n").removeprefix("\ufeff")
            if number >= last:
                break
    return [found.get(int(n), "") for n in line_numbers]


def _garbled_header(columns: tuple[str, ...]) -> bool:
    """Whether header names look read in the wrong encoding: undecodable bytes (U+FFFD),
    or Latin-1 letters whose bytes are Chinese text in GB18030 (``ÅúºÅ`` is 批号)."""
    from wakeline.core.io.decoding import _gb_line, _high

    text = ",".join(columns).lstrip("\ufeff").removeprefix("ï»¿")
    if "\ufffd" in text:
        return True
    if text.isascii():
        return False
    try:
        raw = text.encode("cp1252")
    except UnicodeEncodeError:
        return False
    return _gb_line(raw, _high(raw))


def resolve_header(
    sn: Sniff,
    fmt: str,
    mapping: dict[str, str] | None,
    source: str,
    origin: str | tuple[float, float] | None = None,
) -> Resolved:
    """:func:`resolve` for a sniffed file, then what its sampled values decide
    (:func:`judge_by_values`: words of two meanings, a date and a clock column, an MMSI
    column no name says); when the header names few known columns, the
    error says how to skip lines above a header further down (``--skip-rows``).
    ``origin``: the local plane's (lat, lon) for east/north metres (:func:`resolve`)."""
    try:
        res = resolve(sn.columns, fmt, mapping, source=source, origin=origin)
    except InputError as exc:
        # Not track data (batch skips it among several inputs): a header of no known
        # column and no --map column, or one line alone (no row to lose: a note whose
        # words happen to name a column); a headerless table of values may be data.
        named = {str(c).strip().lower() for c in (mapping or {}).values()}
        stray = sn.has_header and (
            not sn.preview
            or (
                not known_fields(sn.columns) and not named & {c.strip().lower() for c in sn.columns}
            )
        )
        if not sn.has_header and sn.preview and "missing required column" in str(exc):
            guess, sure = content_guess(sn)
            if guess:
                flags = " ".join(f"--map {f}={c}" for f, c in guess.items())
                check = "" if sure else " (check which of the two degree columns is longitude)"
                dates = _beside(sn, guess["time"], set(guess.values()), _DATE_ONLY)
                if dates is not None and _mostly(_sample_cells(sn, guess["time"]), _CLOCK_RE):
                    check += (
                        f" (the clock times in {guess['time']} are joined with the dates "
                        f"beside them in {dates})"
                    )
                raise InputError(
                    f"{exc}; the file has no header (its first row: "
                    f"{', '.join(sn.preview[0])}); by their values the columns may be: "
                    f"{flags}{check}"
                ) from None
        if sn.has_header and sn.preview and "missing required column time" in str(exc):
            # a headed file whose time column has a name no layout knows ("Date/Time"):
            # suggested by its values, as a headerless file's columns are
            taken = {str(c) for c in (mapping or {}).values()}
            found = [
                name
                for name in sn.columns
                if name not in taken
                and (cells := _cells_of(sn, name))
                and all(cell_kind(c) == "time" and ":" in c for c in cells)
            ]
            if found:
                raise InputError(
                    f"{exc}; by its values the time may be in {found[0]!r}: "
                    f"--map {shlex.quote(f'time={found[0]}')}"
                ) from None
        garbled = sn.has_header and _garbled_header(sn.columns)
        if garbled:
            # not "not track data": a header read in the wrong encoding (operator test 7
            # D1: batch skipped such a file with exit status 0, its rows lost)
            stray = False
        refused = NotTrackData if stray else InputError
        if sn.has_header and len(known_fields(sn.columns)) < 3:
            raise refused(
                f"{exc}; if the header is further down (a title above it), skip the lines "
                "above it with --skip-rows N"
                + (
                    f"; the header looks read in the wrong encoding (read as {plain_encoding(sn.encoding)}):"
                    " give the file's encoding (--encoding, e.g. gb18030)"
                    if garbled
                    else ""
                )
            ) from None
        if stray and not isinstance(exc, NotTrackData):
            raise NotTrackData(str(exc)) from None
        raise
    return judge_by_values(sn, res, mapping)


_COMMA_NUMBER = re.compile(r"^([+-]?\d+),(\d+)$")


def content_guess(sn: Sniff) -> tuple[dict[str, str], bool]:
    """A headerless file's columns by the values of its first rows (``sn.preview``):
    field → column for time (a date-time; else a column of clock times beside a column
    of dates, which the reader joins with them; else Unix seconds or milliseconds, those
    since 2001 first: a nine-digit MMSI before them is the batch), lon and lat
    (two columns of degrees with decimals; lon the one beyond ±90 somewhere, else the
    first of the two) and batch (an integer or text column left over), and whether the
    lon/lat order was seen in the values (not only guessed by order). Empty when the
    values do not show it. Never used to read a file: a suggestion for --map.

    Of several columns of large whole numbers (Unix seconds beside a 9-digit MMSI, which
    lies in 1e8-1e9 too) the time is the one that runs forward down the rows, then the
    one after 2001 (1e9 s); the others are ids. Of more than two columns of degrees (a
    speed or course of one decimal beside the position) lon and lat are the two written
    with the most decimals, when those two have more than the rest."""
    rows = [r for r in sn.preview if len(r) == len(sn.columns)]
    if not rows:
        return {}, False
    cols = list(zip(*rows, strict=True))
    out: dict[str, str] = {}
    degrees, ids, texts, stamps, clocks, dates = [], [], [], [], [], []
    for k, (name, cells) in enumerate(zip(sn.columns, cols, strict=True)):
        cells = [c.strip().strip('"') for c in cells]
        if sn.delimiter != ",":  # 30,613482 in a ;-separated export is 30.613482
            cells = [_COMMA_NUMBER.sub(r"\1.\2", c) for c in cells]
        nums = pd.to_numeric(pd.Series(cells), errors="coerce").to_numpy(dtype="float64")
        if np.isnan(nums).all():
            # the sniffer's test of a date-time (pandas' guess per cell warned on stderr
            # for every dd/mm/yyyy and took "May 5" for a date); a date alone is no time
            # (its fixes all at midnight) and a clock alone no batch: of a Date,Time pair
            # the clock column is the time (the reader joins the dates beside it)
            if all(cell_kind(c) == "time" and ":" in c for c in cells):
                texts.append(name)
            elif all(_CLOCK_RE.match(c) for c in cells):
                clocks.append(k)
            elif all(_DATE_ONLY.match(c) for c in cells):
                dates.append(k)
            elif all(cells) and not any(
                cell_kind(c) == "time" or re.match(_CLOCK, c) for c in cells
            ):
                ids.append((k, name))
            continue
        if np.isnan(nums).any():
            continue
        if ((nums > 1e8) & (nums < 4e12)).all():
            # Unix seconds or ms, or a nine-digit MMSI: the time runs forward down the
            # rows, and lies after 2001 (sorted below)
            forward = bool((np.diff(nums) >= 0).all())
            recent = bool((((nums >= 1e9) & (nums < 4e9)) | (nums >= 1e12)).all())
            whole = bool((nums == np.round(nums)).all())
            stamps.append((not forward, not recent, k, name, whole))
        elif all("." in c for c in cells) and (np.abs(nums) <= 180).all():
            places = min(len(c.split(".")[-1]) for c in cells)
            degrees.append((name, float(np.abs(nums).max()), places))
        elif (nums == np.round(nums)).all():
            ids.append((k, name))
    # a date-time text first, then the numbers most like recent Unix times; the other
    # whole numbers of that range (an MMSI before the times) may be the batch
    stamps.sort()
    paired = [k for k in clocks if k - 1 in dates or k + 1 in dates]
    if texts:
        out["time"] = texts[0]
    elif paired:
        out["time"] = sn.columns[paired[0]]
    elif stamps:
        out["time"] = stamps.pop(0)[3]
    ids = sorted(ids + [(k, n) for _f, _o, k, n, whole in stamps if whole])
    # a column of nine-digit MMSIs before a column of small whole numbers (a course in
    # whole degrees, a status) that comes first
    ids = [
        n for _m, _k, n in sorted((not _mostly(_cells_of(sn, n), _MMSI_CELL), k, n) for k, n in ids)
    ]
    if len(degrees) > 2:
        top = sorted(degrees, key=lambda d: -d[2])
        if top[1][2] > top[2][2]:  # two written finer than the rest: the position
            degrees = [d for d in degrees if d in top[:2]]
    sure = False
    if len(degrees) == 2:
        (a, amax, _), (b, bmax, _) = degrees
        sure = (amax > 90) != (bmax > 90)
        lon, lat = (b, a) if bmax > 90 >= amax else (a, b)
        out["lon"], out["lat"] = lon, lat
    if ids:
        out["batch"] = ids[0]
    if not {"time", "lon", "lat"} <= set(out):
        return {}, False
    return out, sure


#: The reason a line above the header is skipped.
TITLE_REASON = "above the header (a title?): skipped"


def skipped_above_header(report: dict) -> int:
    """Lines of the file above its header (or first row) that are neither: the title
    lines, blank lines and Excel's "sep=" line, from an import ``report``."""
    return (
        len(report.get("lines_above_header") or ())
        + int(report.get("blank_lines_above_header", 0))
        + int(report.get("excel_sep_line", 0))
    )


def _title_report(sn: Sniff) -> list[dict]:
    """The lines skipped above the header: line number (1-based), reason and text."""
    return [{"line": n, "reason": TITLE_REASON, "text": t} for n, t in sn.title_lines]


def _title_warnings(sn: Sniff) -> list[str]:
    """One warning naming the lines above the header that were skipped."""
    if not sn.title_lines:
        return []
    shown = "; ".join(f"line {n}: {t[:60]!r}" for n, t in sn.title_lines[:3])
    more = f" and {len(sn.title_lines) - 3} more" if len(sn.title_lines) > 3 else ""
    return [
        f"{len(sn.title_lines)} line(s) above the header skipped (a title, not data): "
        f"{shown}{more}; "
        + (
            f"the header is line {sn.skip_rows}"
            if sn.has_header
            else f"the first row is line {sn.skip_rows + 1}"
        )
    ]


def _blank_run_warnings(sn: Sniff) -> list[str]:
    """A note that a file separated by blank space was read with each run of blanks one
    separator (columns aligned with spaces), and a date and the clock after it one cell."""
    if not sn.blank_runs:
        return []
    if sn.fixed_gutters:
        return [
            f"the columns are aligned with blanks and read by their places under the header "
            f"({len(sn.columns)} columns): a cell may be empty, a value may hold a blank; a "
            "row whose text crosses a gap between columns is split at its runs of blanks"
        ]
    text = (
        f"the columns are aligned with blanks: each run of spaces or tabs was read as one "
        f"separator ({len(sn.columns)} columns)"
    )
    if sn.join_date_clock:
        text += (
            "; a date and the clock after it (2024-01-01 00:00:00) were read as one time, "
            "as the header names one column fewer than the rows have parts"
        )
    return [text]


#: In the warning of :func:`_repeat_warnings` (a read in pieces says it again from the
#: summed counts).
REPEAT_MARK = " an earlier row exactly (same track, time"


def _repeat_warnings(repeated: int) -> list[str]:
    """A warning counting the rows that repeat an earlier row exactly (operator test 9,
    D8: they were reported as several passes or ships under one id)."""
    if not repeated:
        return []
    rows = "1 row repeats" if repeated == 1 else f"{repeated:,} rows repeat"
    return [
        f"{rows}{REPEAT_MARK}, position, speed and course): the same lines written twice "
        "(an export appended again?); kept here, clean removes them as duplicates"
    ]


def _mix64(x: np.ndarray) -> np.ndarray:
    """splitmix64's finalizer on uint64 values (a well-spread 64-bit hash of each)."""
    with np.errstate(over="ignore"):
        x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return x ^ (x >> np.uint64(31))


def _repeated_rows(
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
    ns: np.ndarray,
    floats: dict,
    keep: np.ndarray,
    carry: "LastTimes | None" = None,
) -> np.ndarray:
    """Rows (of ``keep``) equal to an earlier kept row in track, time, position, speed
    and course: a mask over all rows. Only a row no later than its track's latest time
    before it can repeat one; those are compared by a 64-bit hash of the values (the
    track by its name, the same in every piece; a collision would count one row too many
    in a warning, nothing more). A piece of a file read streamed or in pieces gives
    ``carry``: each track's latest time and the hashes of the rows of the pieces before
    (8 bytes a row, in sorted chunks), so a row repeating one of another piece counts as
    a whole read counts it."""
    out = np.zeros(len(keep), dtype=bool)
    use = np.flatnonzero(keep & (batch_codes >= 0))
    if not len(use):
        return out
    t = ns[use].astype("int64", copy=False)
    key = batch_codes[use].astype("int64")
    if sensor_codes is not None:
        key = sensor_codes[use].astype("int64") * (int(batch_codes.max()) + 1) + key
    row_track, tracks = pd.factorize(key, sort=False)
    names = None
    if carry is not None:
        names = _carried_keys(tracks, sensor_codes, sensor_names, batch_codes, batch_names)
        at = carry._rows(names, grow=True)
        before = carry.max_t[at]  # each track's latest time in the pieces before
    else:
        before = np.full(len(tracks), np.iinfo("int64").min, dtype="int64")
    # each row's track's latest time before it (file order; the pieces before included)
    from wakeline.core.tracks import _stable_code_order

    order = _stable_code_order(row_track)  # radix passes: linear
    if order is None:
        order = np.argsort(row_track, kind="stable")
    g = row_track[order]
    st = t[order]
    first = np.r_[True, g[1:] != g[:-1]]
    low, span = int(st.min()), int(st.max()) - int(st.min()) + 1
    if span * len(tracks) < 2**62:  # each track's running maximum in one pass
        lift = g.astype("int64") * span
        run_max = np.maximum.accumulate(st - low + lift) - lift + low
    else:
        run_max = pd.Series(st).groupby(g).cummax().to_numpy()
    prev_max = np.empty_like(st)
    prev_max[1:] = run_max[:-1]
    prev_max[first] = np.iinfo("int64").min
    prev_max = np.maximum(prev_max, before[g])
    cand_sorted = st <= prev_max
    if carry is not None:
        last = np.r_[np.flatnonzero(first)[1:] - 1, len(g) - 1]
        carry.max_t[at] = np.maximum(before, run_max[last])
    if not cand_sorted.any() and carry is None:
        return out
    cand = np.zeros(len(use), dtype=bool)
    cand[order[cand_sorted]] = True
    if names is None:
        names = _carried_keys(tracks, sensor_codes, sensor_names, batch_codes, batch_names)
    h = pd.util.hash_array(np.asarray(names, dtype=object))[row_track]
    values = [t.view("uint64")]
    for name in ("lon", "lat", "speed", "course"):
        if name in floats:
            x = floats[name]
            x = x.to_numpy() if isinstance(x, pa.ChunkedArray) else x.to_numpy(zero_copy_only=False)
            v = np.asarray(x, dtype="float64")[use]
            values.append(np.where(np.isnan(v), np.nan, v + 0.0).view("uint64"))  # one NaN
    with np.errstate(over="ignore"):
        for v in values:
            h = _mix64(h * np.uint64(0x100000001B3) ^ _mix64(v))
    dup = np.zeros(len(use), dtype=bool)
    if cand.any():
        dup = pd.Index(h).duplicated(keep="first") & cand
        if carry is not None:
            c = np.flatnonzero(cand & ~dup)
            for chunk in carry.row_hashes:  # a few candidates against each sorted chunk
                at_c = np.minimum(np.searchsorted(chunk, h[c]), len(chunk) - 1)
                dup[c[chunk[at_c] == h[c]]] = True
    if carry is not None:
        carry.row_hashes.append(np.sort(h))
        if len(carry.row_hashes) > 8:  # merged now and then: few chunks to look in
            carry.row_hashes = [np.sort(np.concatenate(carry.row_hashes), kind="stable")]
    out[use[dup]] = True
    return out


def _restart_warnings(restarting: dict[str, int], batch_src: str) -> list[str]:
    """A warning when tracks restart their time in the file (several passes or ships
    under one id)."""
    if not restarting:
        return []
    name, runs = max(restarting.items(), key=lambda kv: kv[1])
    return [
        f"{len(restarting):,} track(s) start their time again within the file (batch "
        f"{name}: {runs} runs, each going forward, the next starting at least "
        f"{RESTART_BACK_S / 60:g} min earlier): several passes or ships may share one id in "
        f"{batch_src!r}; they are joined into one track sorted by time. If a column tells "
        "them apart, map it: --map batch=COLUMN, or --map sensor=COLUMN"
    ]


TIME_UNIT_ON_TEXT_START = "--time-unit "  # the note that a given unit met text times


def _time_warnings(time_src: str, time_info: dict, zone) -> list[str]:
    """Warnings about how the time column was read (local read as UTC; relative times),
    and numbers read with a decimal comma."""
    out = []
    if time_info.get("date_column"):
        out.append(
            f"the times in {time_src!r} are clock times: each joined with its row's date "
            f"in {time_info['date_column']!r}"
        )
    if time_info.get("month_first"):
        out.append(
            f"the times in {time_src!r} write the month first (mm/dd/yyyy: "
            f"{time_info['month_first']:,} have a second number above 12, none a first): "
            "read so (--date-order month-first says it outright)"
        )
    if time_info.get("month_first_ampm"):
        out.append(
            f"the dates in {time_src!r} were read month first (m/d/yyyy) because the times "
            f"use a 12-hour clock with AM/PM ({time_info['month_first_ampm']:,} of them), as "
            "US exports (Excel en-US) write, and no date shows the order (no number above "
            "12 in either place): if the day comes first, read again with --date-order "
            "day-first"
        )
    if time_info.get("date_order_refused"):
        given = time_info.get("date_order_given", "")
        other = "day-first" if given == "month-first" else "month-first"
        place = "first" if given == "month-first" else "second"
        out.append(
            f"{time_info['date_order_refused']:,} dates in {time_src!r} have a {place} number "
            f"above 12, so they are not {given} as --date-order {given} says: quarantined as "
            f"unparsable time (are they {other}? try --date-order {other} or auto)"
        )
    if time_info.get("other_form_times"):
        out.append(
            f"{time_info['other_form_times']:,} times in {time_src!r} are written in the "
            "column's other form (unix seconds among ISO 8601 text, or ISO 8601 text among "
            "unix seconds: two exports joined?): each was read in its own form"
        )
    if time_info.get("excel_days") and time_info.get("excel_why"):  # auto decided
        out.append(
            f"{time_info['excel_days']:,} times in {time_src!r} were read as Excel serial "
            "days (1900 date system: 45658.5 is 2025-01-01 12:00) because "
            f"{time_info['excel_why']}; if they are seconds, read again with --time-unit "
            "seconds"
        )
    text = str(time_info.get("time_format")).endswith("text") and time_info.get("_texts", 1)
    if time_info.get("time_unit_given") and text:  # not for a column of no times at all
        out.append(
            f"{TIME_UNIT_ON_TEXT_START}{time_info['time_unit_given']} applies to numbers; the "
            f"times in {time_src!r} are text ({time_info['time_format']}) and were read as such"
        )
    if time_info.get("excel_like") and time_info.get("relative"):
        out.append(
            f"the times in {time_src!r} lie between {EXCEL_RANGE[0]:,.0f} and "
            f"{EXCEL_RANGE[1]:,.0f}: read as seconds from a scene start (their steps are "
            "those of a clock of seconds, not of days); if they are Excel serial days "
            "(dates 1954-2119), read again with --time-unit excel-days"
        )
    if time_info.get("decimal_comma"):
        example = time_info.get("decimal_comma_example")
        like = (
            f" ({example} as {example.replace(',', '.')})"
            if isinstance(example, str) and example
            else ""
        )
        out.append(
            f"{time_info['decimal_comma']:,} values were written with a decimal comma and "
            f"read as decimal numbers{like}"
        )
    if time_info.get("dates_either_way") and not time_info.get("dayfirst_shown"):
        out.append(
            f"the dates in {time_src!r} were read day first (dd/mm/yyyy), but none shows "
            f"which comes first ({time_info['dates_either_way']:,} could be mm/dd/yyyy, "
            "no number above 12 in either place): check the dates; if the month comes "
            "first, read again with --date-order month-first"
        )
    if time_info.get("dms"):
        out.append(
            f"{time_info['dms']:,} positions were written in degrees and minutes (like "
            "57°40.026'N) and read as decimal degrees (57.6671)"
        )
    if time_info.get("ddmm"):
        out.append(
            f"{time_info['ddmm']:,} positions were written as NMEA writes them, degrees and "
            "minutes run together (ddmm.mmmm, dddmm.mmmm: 3754.0300 is 37°54.03') and read "
            "as decimal degrees (37.9005)"
        )
    if time_info.get("ddmm_note"):
        out.append(time_info["ddmm_note"])
    if time_info.get("letter_note"):
        out.append(time_info["letter_note"])
    if time_info.get("ddmm_in_cell"):
        out.append(
            f"{time_info['ddmm_in_cell']:,} positions were written as NMEA writes them with "
            "the hemisphere letter in the cell (3754.03N, 02342.10E: degrees and minutes "
            "run together, four or five digits before the point) and read as signed decimal "
            "degrees (3754.03N is 37.9005)"
        )
    if time_info.get("ddmm_unpadded"):
        out.append(
            f"{time_info['ddmm_unpadded']:,} positions were written without NMEA's zero "
            "padding (123.5W, 942.1N) in a column of ddmm.mmmm with letters: read as "
            "degrees and minutes like the rest of their column (123.5W is 1°23.5' W, "
            "-1.391667)"
        )
    if time_info.get("ddmm_ambiguous"):
        out.append(
            f"{time_info['ddmm_ambiguous']:,} positions with a hemisphere letter and three "
            "digits before the point (like 123.5W) were read as decimal degrees (123.5°); "
            "they could be NMEA's dddmm.mm without its zero padding (1°23.5'), and no cell "
            "of their column shows which: if they are degrees and minutes, pad them "
            "(00123.5W)"
        )
    if time_info.get("hemisphere_degrees"):
        out.append(
            f"{time_info['hemisphere_degrees']:,} positions were written in decimal degrees "
            "with a hemisphere letter (like 37.05N, W 23.05) and read as signed decimal "
            "degrees (S and W negative)"
        )
    if time_info.get("speed_unit"):
        unit, named = time_info["speed_unit"]
        why = "its header says so" if named else "--speed-unit"
        out.append(f"speeds were given in {unit} ({why}): converted to knots")
    if time_info.get("speed_unit_refused"):
        out.append(
            f"--speed-unit {time_info['speed_unit_refused']} not used: the speed column's "
            "header names its own unit"
        )
    if str(time_info.get("time_format", "")).startswith("GPS"):
        out.append(
            f"the times in {time_src!r} are {time_info['time_format']} (GPS time, which "
            "runs ahead of UTC by the leap seconds since 1980: 18 s since 2017): read as UTC"
            + ("; --tz does not apply to them" if zone is not None else "")
        )
        if time_info.get("gps_ten_bit"):
            out.append(
                "every GPS week number is below 1024: if the receiver writes weeks modulo "
                "1024 (10 bits), the times are 19.6 or 39.2 years early; add 1024 or 2048 "
                "to the week column"
            )
    words = time_info.get("zone_words") or {}
    if any(not w.endswith(AS_TZ) for w in words):
        out.append(
            f"times in {time_src!r} end in a zone word or offset (CET, EST, JST, UTC+8 …): "
            "each was read at that zone's offset from UTC"
            + ("; --tz applies only to the times without one" if zone is not None else "")
        )
    for w in sorted(w for w in words if w.endswith(AS_TZ)):
        word = w.removesuffix(AS_TZ)
        out.append(
            f"the zone word {word} in {time_src!r} names more than one zone "
            f"({AMBIGUOUS_ZONES[word]}): those times were read in --tz {zone}"
        )
    if len(time_info.get("time_formats_by_table") or ()) > 1:
        forms = time_info["time_formats_by_table"]
        out.append(
            f"the tables of this file write the times in {time_src!r} in {len(forms)} forms "
            f"({', '.join(forms)}): each table's read in its own"
        )
    if time_info.get("zoneless_times") and time_info.get("zoned_times") and zone is None:
        without, with_zone = int(time_info["zoneless_times"]), int(time_info["zoned_times"])
        out.append(
            f"{without:,} of {without + with_zone:,} times in {time_src!r} carry no zone and "
            f"{with_zone:,} do: those without were read as UTC; if they are local times, "
            "give their zone with --tz (e.g. --tz Asia/Shanghai; times with a zone keep it)"
        )
    if time_info.get("naive") and zone is None and header_is_local(time_src):
        out.append(
            f"the time column {time_src!r} says it holds local times but they were read as "
            "UTC: give the zone with --tz (e.g. --tz Asia/Shanghai or --tz +08:00)"
        )
    if time_info.get("clock_placed"):
        out.append(
            f"{time_info['clock_placed']:,} local times fell in the hour the clock change "
            f"in {zone} repeats; each was placed in the first or second pass by its "
            "track's order in the file"
        )
    if time_info.get("hhmmss"):
        a, b = time_info["hhmmss"]
        out.append(
            f"the numbers in {time_src!r} are clock times written HHMMSS (every one is a "
            f"valid hhmmss and the steps jump as a clock's do, {a:06d} to {b:06d}): read as "
            "times of day, not as seconds (--time-unit seconds reads them as seconds)"
        )
    if time_info.get("clock_only"):
        given = time_info.get("clock_date_given")
        if given:
            out.append(
                f"the times in {time_src!r} are times of day without a date: read on {given} (--date)"
            )
        else:
            out.append(
                f"the times in {time_src!r} are times of day without a date: read on "
                "1970-01-01 as relative times; give their day with --date YYYY-MM-DD"
            )
        if time_info.get("clock_rollovers"):
            out.append(
                f"the times of day in {time_src!r} step back more than 12 h within a track "
                f"{time_info['clock_rollovers']:,} times (23:59:59 then 00:00:01): each "
                "such step passes midnight, into the next day"
            )
    elif time_info.get("clock_date_given") and time_info.get("time_format"):
        out.append(
            f"the times in {time_src!r} are {time_info['time_format']}, with their dates: "
            "read as such, --date (for times of day without a date) not used"
        )
    if time_info.get("relative") and not time_info.get("clock_only"):
        out.append(
            f"times in {time_src!r} are seconds from a scene start (relative), kept as "
            "such: shown from 1970-01-01T00:00:00Z"
        )
    return out


#: Encodings of Chinese systems (a file in one, or with Chinese headers, was written
#: on a machine whose clock is likely Beijing time).
_CHINESE_CODECS = ("gb18030", "gbk", "gb2312", "hz", "big5", "big5hkscs")
_CJK = re.compile(r"[\u4e00-\u9fff]")


#: Words of :func:`zone_note` (a read in pieces drops it where zones are mixed over the file).
ZONE_NOTE_MARK = "carry no zone: read as UTC (this file looks written on a Chinese system"


def zone_note(sn: Sniff, time_src: str, time_info: dict, zone) -> list[str]:
    """D-import-8: times without a zone in a file plainly from a Chinese system (its
    encoding or its headers) were read as UTC: one line saying so, with the --tz that
    reads them as Beijing time. (Not said for every zone-less file: most exports write
    UTC without a zone, and the note would be noise there.)"""
    if zone is not None or not time_info.get("naive") or time_info.get("relative"):
        return []
    if header_is_local(time_src) or time_info.get("zoneless_times"):
        return []  # said already: the header says local; zoned and zone-less mixed
    try:
        codec = codecs.lookup(sn.encoding).name
    except (LookupError, TypeError):
        codec = ""
    chinese = codec in _CHINESE_CODECS or any(_CJK.search(str(c)) for c in sn.columns)
    if not chinese:
        return []
    return [
        f"the times in {time_src!r} {ZONE_NOTE_MARK}: if they are local times, --tz Asia/Shanghai)"
    ]


def date_order_note(time_info: dict) -> str | None:
    """How slashed dates were read and what decided it (for the import report), or None
    when the times are not slashed dates."""
    if time_info.get("date_order_given"):
        return f"{time_info['date_order_given']} (given: --date-order)"
    if time_info.get("month_first"):
        return (
            f"month-first (the file shows it: {time_info['month_first']:,} dates have a "
            "second number above 12, none a first)"
        )
    if time_info.get("month_first_ampm"):
        return (
            f"month-first (assumed from the 12-hour AM/PM clock of "
            f"{time_info['month_first_ampm']:,} times, as US exports write; no date shows "
            "the order: --date-order day-first reads them day first)"
        )
    if time_info.get("day_shown") or time_info.get("dayfirst_shown"):
        shown = int(time_info.get("day_shown", 0))
        many = f"{shown:,} dates have" if shown else "a date has"
        return f"day-first (the file shows it: {many} a first number above 12)"
    if time_info.get("dates_either_way"):
        return (
            f"day-first (assumed: no date shows the order; {time_info['dates_either_way']:,} "
            "could be month-first: --date-order month-first reads them so)"
        )
    if str(time_info.get("time_format", "")).startswith(("day-first", "month-first")):
        return str(time_info["time_format"]).split()[0]
    return None


#: The counts behind the date-order and Excel-days notes, in a report when not zero (a
#: read in pieces sums them: :func:`~wakeline.core.io.pieces.merge_import_reports`).
TIME_COUNTS = (
    "other_form_times",
    "dates_either_way",
    "day_shown",
    "excel_days",
    "date_order_refused",
    "zoneless_times",
    "zoned_times",
)
#: ... and of the positions read from text (in the report as these keys when not zero;
#: a read in pieces sums them and says each once).
POSITION_COUNTS = (
    "dms",
    "hemisphere_degrees",
    "ddmm",
    "letter_signs",
    "ddmm_in_cell",
    "ddmm_unpadded",
    "ddmm_ambiguous",
)


def time_counts(time_info: dict) -> dict:
    """The non-zero :data:`TIME_COUNTS` of ``time_info`` and the reason Excel days were
    read (``excel_why``), for the import report."""
    out: dict = {k: int(time_info[k]) for k in TIME_COUNTS if time_info.get(k)}
    out.update({k: int(time_info[k]) for k in POSITION_COUNTS if time_info.get(k)})
    if time_info.get("lettered_forms"):  # lat/lon with letters: ddmm.mmmm or degrees
        out["lettered_forms"] = dict(time_info["lettered_forms"])
    if time_info.get("excel_why"):
        out["excel_why"] = time_info["excel_why"]
    if time_info.get("decimal_comma_example"):
        out["decimal_comma_example"] = str(time_info["decimal_comma_example"])
    if time_info.get("month_first_ampm"):
        out["month_first_ampm"] = int(time_info["month_first_ampm"])
    if "times_fine" in time_info and not time_info["times_fine"]:
        out["times_whole"] = "minute" if time_info.get("times_sub_hour") else "hour"
        if time_info.get("coarse_shared"):
            out["coarse_shared"] = int(time_info["coarse_shared"])
    return out


def time_unit_note(time_info: dict) -> str | None:
    """What numbers in the time column were read as, and why (for the import report), or
    None for text times."""
    fmt = str(time_info.get("time_format") or "")
    if fmt == "Excel serial days":
        return f"Excel serial days ({time_info.get('excel_why') or 'given: --time-unit'})"
    if fmt.startswith(("unix", "relative")):
        if time_info.get("excel_like"):
            return f"{fmt} (in the Excel day range, but steps of a clock of seconds)"
        return fmt
    return None


def clock_report(time_info: dict) -> dict:
    """The import report's keys for clock times without a date: ``clock_date`` (the day
    they were read on; None: 1970-01-01, relative), ``clock_rollovers`` (steps back past
    midnight read as the next day) and ``hhmmss`` (the step that showed numbers to be
    HHMMSS clock times); none for other times."""
    if not time_info.get("clock_only"):
        return {}
    out = {
        "clock_date": time_info.get("clock_date_given"),
        "clock_rollovers": int(time_info.get("clock_rollovers", 0)),
    }
    if time_info.get("hhmmss"):
        out["hhmmss"] = list(time_info["hhmmss"])
    return out


def _names_read_errors(fn: Callable) -> Callable:
    """Turn a decompression error (a gzip cut short, damaged bz2 data: raised without a
    file name) into an :class:`InputError` that names the file and says what to do."""

    @functools.wraps(fn)
    def wrapper(path, *args, **kwargs):
        try:
            return fn(path, *args, **kwargs)
        except (OSError, EOFError) as exc:
            if getattr(exc, "filename", None) or isinstance(exc, InputError):
                raise
            text = str(exc) or type(exc).__name__
            if isinstance(exc, EOFError) or any(
                w in text.lower() for w in ("compress", "gzip", "bz2", "zlib", "crc")
            ):
                raise InputError(
                    f"{path}: the compressed data is cut short or damaged ({text}); nothing "
                    "was imported. The copy is probably incomplete: copy the file again, or "
                    "decompress what is there (gzip -dc FILE > part.csv) and import that"
                ) from exc
            raise

    return wrapper


@_names_read_errors
def read_points(
    path: str | Path,
    fmt: str = "auto",
    mapping: dict[str, str] | list[str] | None = None,
    encoding: str | None = None,
    delimiter: str | None = None,
    sensor: str = DEFAULT_SENSOR,
    progress: Progress | None = None,
    tz: str | None = None,
    *,
    sniffed: Sniff | None = None,
    line_by_line: bool = False,
    edges: dict | None = None,
    skip_rows: int | None = None,
    origin: str | tuple[float, float] | None = None,
    date_order: str = "auto",
    time_unit: str = "auto",
    clock_date: str | None = None,
    speed_unit: str = "auto",
    distance_unit: str = "auto",
) -> ImportResult:
    """Read a track file (CSV of any supported layout, or a raw AIS NMEA log) into the
    canonical point table.

    ``fmt`` is ``auto`` or a format family (canonical, radar, ais, mtad, generic);
    ``mapping`` maps canonical fields to source columns (``{"batch": "MMSI"}`` or
    ``["batch=MMSI"]``); ``sensor`` names the sensor when the file has no sensor column;
    ``tz`` (IANA name or ±HH:MM) is the zone of times written without one (default UTC).
    Every data line ends up a point or a quarantined row. Raises :class:`InputError` for
    a file that cannot be read at all. A piece of a larger file is read as the whole file
    is (:mod:`wakeline.core.io.pieces`): ``sniffed`` is then the file's :class:`Sniff`
    for ``path`` (delimiter, encoding, quoting, columns; not sniffed again), and
    ``line_by_line`` reads it as a file whose quotes do not balance, and ``edges`` says
    what the earlier pieces saw for the edge-row rule (:func:`edge_state`).
    ``skip_rows`` (physical lines before the header) skips a title above the header
    instead of detecting it (:func:`~wakeline.core.io.sniff.sniff`). ``origin``
    (``"LAT,LON"`` degrees) is where a file's east/north metres (x/y on a local plane:
    a radar's site, a NED frame's zero) are measured from; they are turned into lon/lat
    by the azimuthal equidistant projection about it (:func:`~wakeline.core.geo.from_local`).
    ``date_order`` (:data:`DATE_ORDERS`) says how slashed dates read (``auto``: day first
    unless the file shows the month first); ``time_unit`` (:data:`TIME_UNITS`) what
    numeric times count (``auto``: seconds, or Excel serial days by
    :func:`excel_days_rule`' rule). ``clock_date`` (``YYYY-MM-DD``, ``--date``) is the
    day of clock times written without a date (``23:50:00.5``); without it they are read
    on 1970-01-01 as relative times.
    """
    progress = progress or null_progress
    path = Path(path)
    values = ValueOptions(date_order, time_unit, clock_date, speed_unit, distance_unit).checked()
    clock_date = values.clock_date
    if isinstance(mapping, list):
        mapping = parse_mapping(mapping)
    zone = parse_zone(tz)
    progress(0.0, f"reading {path.name}")
    sn = sniffed if sniffed is not None else sniff(path, encoding, delimiter, skip_rows)
    if sn.kind == "nmea":
        from wakeline.core.io.nmea import read_nmea

        return read_nmea(sn, sensor=sensor, progress=progress)
    if sn.kind in ("gpx", "geojson"):
        from wakeline.core.io.geojson import read_geojson
        from wakeline.core.io.gpx import read_gpx

        reader = read_gpx if sn.kind == "gpx" else read_geojson
        timing = {"tz": zone, "date_order": date_order, "clock_date": clock_date}
        return reader(sn, sensor=sensor, progress=progress, timing=timing)
    res = resolve_header(sn, fmt, mapping, str(path), origin)
    res = dataclasses.replace(res, speed_unit=speed_unit, distance_unit=distance_unit)
    rows = _read_rows(sn, res, unbalanced=line_by_line)
    notes = []
    if "batch" not in res.columns:
        n = rows.table.num_rows
        batch = pa.repeat(pa.scalar(path.name.split(".")[0] or "1"), n).dictionary_encode()
        rows.table = rows.table.append_column(FILE_BATCH, batch)
        res = dataclasses.replace(res, columns={**res.columns, "batch": FILE_BATCH})
        notes.append(no_batch_warning(sn, res.columns))
    notes += res.notes
    progress(0.6, "checking values")

    # a piece of a file: zoned and zone-less times counted for the whole file (pieces.py)
    time_info: dict = {} if edges is None else {"_edges": edges, "_by_table": True}
    points, quarantine, counts = _to_canonical(
        rows,
        sn,
        res,
        sensor,
        zone,
        time_info,
        date_order=date_order,
        time_unit=time_unit,
        clock_date=clock_date,
    )
    time_info.pop("_edges", None)
    time_info.pop("_by_table", None)
    zones = [time_info.pop("_zoned_n", 0), time_info.pop("_naive_n", 0)]
    progress(1.0, "imported")
    warnings = list(rows.notes) + notes + _title_warnings(sn) + _blank_run_warnings(sn)
    warnings += bom_warnings(sn, rows.encoding)
    warnings += _time_warnings(res.columns["time"], time_info, zone)
    warnings += zone_note(sn, res.columns["time"], time_info, zone)
    warnings += _coarse_time_warnings(res.columns["time"], time_info)
    warnings += _repeat_warnings(counts["repeated_rows"])
    warnings += _restart_warnings(counts["restarting_tracks"], res.columns["batch"])
    warnings += _back_warnings(counts["time_steps_back"], res.columns["time"], res.columns["batch"])
    warnings += position_warnings(
        sn,
        res,
        counts["lat_beyond_90_lon_within"],
        counts["rows_read"],
        time_info.pop("_swapped_in", None),
    )
    warnings += origin_warnings(res, sn.columns)
    warnings += bearing_warnings(res.columns, counts["quarantine_reasons"], counts["rows_read"])
    warnings += cut_short_warnings(sn, quarantine)
    from wakeline.core.io.geojson import targets_note

    warnings += targets_note(points, csv=True)  # Wakeline's targets (D-export-2)
    warnings += _grid_warnings(points)
    warnings += _unit_check(points, res)
    extra = carried_columns(sn, res)
    report: dict = {
        "input": str(path),
        "format": res.format.name,
        "format_label": res.format.label,
        "encoding": plain_encoding(rows.encoding),
        "delimiter": sn.delimiter,
        "compression": sn.compression,
        "header": sn.has_header,
        "lines_above_header": _title_report(sn),
        # with the header, the lines above it, blank_lines, rows_read: every physical line
        "blank_lines_above_header": sn.blank_above_header,
        "excel_sep_line": int(sn.excel_sep),
        "skip_rows_given": sn.skip_rows_given,
        "columns": res.columns,
        "extra_columns": extra,
        "careful_parse": rows.careful,
        "time_format": time_info.get("time_format"),
        "time_date_column": time_info.get("date_column"),
        # GPS time: the week column ("" for GPS seconds since 1980), for export --like
        **({"time_gps_week": res.gps_week} if res.gps_week is not None else {}),
        "date_order": date_order_note(time_info),
        "time_unit": time_unit_note(time_info),
        **time_counts(time_info),
        **clock_report(time_info),
        "time_zone": tz if zone is not None else "UTC",
        # the offsets the times were written with (-05:00): View ▸ Time zone's data zone
        **_file_offsets(
            sn,
            res.columns["time"],
            rows.encoding,
            time_info,
        ),
        "time_relative": bool(time_info.get("relative")),
        "plane_origin": list(res.origin) if res.on_plane else None,
        **counts,
        **({"encoding_fallback": rows.fallback} if rows.fallback else {}),
        **({"_zones": zones} if edges is not None and any(zones) else {}),
        "warnings": warnings,
    }
    layout = {
        "delimiter": sn.delimiter,
        "encoding": plain_encoding(rows.encoding),
        "bom": sn.bom,
        "line_ending": sn.line_ending,
        "compression": sn.compression,
        "header": sn.has_header,
        "header_names": list(sn.columns),
        "column_order": list(sn.columns),
        "skip_rows": sn.skip_rows,
        "quoting": not rows.line_by_line and sn.has_quotes,
        "mapping": dict(res.columns),
        "extra_columns": extra,
        "time_column": res.columns["time"],
        "time_format": time_info.get("time_format"),
        "time_zone": tz if zone is not None else "UTC",
        "time_relative": bool(time_info.get("relative")),
    }
    return ImportResult(points, quarantine, report, layout)


def _grid_warnings(points: pd.DataFrame) -> list[str]:
    """Positions on a grid of 2 decimals or fewer (grid.py), said once."""
    from wakeline.core.io.grid import grid_decimals, grid_warning

    if not len(points):
        return []
    k = grid_decimals(points["lon"].to_numpy(), points["lat"].to_numpy())
    return [] if k is None else [grid_warning(k, points["lat"].to_numpy())]


@dataclass
class _Text:
    """A text column as codes into its sorted distinct values (edge blanks trimmed)."""

    codes: np.ndarray  # int32 per row; -1 where null or blank
    names: np.ndarray  # object array of str
    arrow: pa.ChunkedArray | None  # the dictionary column, when trimming changed no value

    def to_arrow(self) -> pa.ChunkedArray | pa.Array:
        """The column as Arrow strings; null where missing."""
        if self.arrow is not None:
            return pc.cast(self.arrow, pa.string())
        codes = pa.array(self.codes, mask=self.codes < 0)
        return pa.array(self.names, type=pa.string()).take(codes)


def _text_column(arr: pa.ChunkedArray) -> _Text:
    """Trim and code a text column, working on its dictionary: one pass over the distinct
    values, not over the rows."""
    if not pa.types.is_dictionary(arr.type):
        arr = pc.dictionary_encode(pc.cast(arr, pa.string()))
    if arr.num_chunks == 0:
        return _Text(np.zeros(0, dtype="int32"), np.zeros(0, dtype=object), None)
    arr = arr.unify_dictionaries()
    raw = np.asarray(arr.chunk(0).dictionary.to_pylist(), dtype=object)
    values = np.asarray([v.strip() for v in raw], dtype=object)
    present = values != ""
    names, inverse = np.unique(values[present].astype(str), return_inverse=True)
    remap = np.full(len(values) + 1, -1, dtype="int32")  # the last slot maps null (-1)
    remap[np.flatnonzero(present)] = inverse
    indices = pa.chunked_array([c.indices for c in arr.chunks], type=arr.type.index_type)
    codes = remap[pc.fill_null(indices, -1).to_numpy()]
    unchanged = bool(np.all(raw == values))
    return _Text(codes, names.astype(object), arr if unchanged else None)


#: Counts of the time parse summed over a file's tables (the rest: the first table's).
_SUMMED_TIME_KEYS = (
    "other_form_times",
    "dates_either_way",
    "day_shown",
    "excel_days",
    "date_order_refused",
    "zoneless_times",
    "zoned_times",
    "decimal_comma",
    "excel_like",
    "clock_rollovers",
    "month_first",
    "month_first_ampm",
)


def _times_by_table(time_col, blocks: np.ndarray, counted: dict, times: dict):
    """The times of a file of several tables (tables.py), each table's read on its own
    (its format judged on its rows only: an ISO table and a day-first one both read).
    What each parse notes is merged into ``counted``: per-row marks put back in file
    rows, counts summed, flags OR-ed, the rest (the time format) the first table's."""
    n = len(blocks)
    ns = np.zeros(n, dtype="int64")
    ok = np.zeros(n, dtype=bool)
    start = dict(counted)
    formats: list[str] = []
    zoned = naive = 0
    for b in np.unique(blocks):
        idx = np.flatnonzero(blocks == b)
        info = {**start, "_by_table": True}
        col = time_col.take(pa.array(idx))
        ns_b, ok_b = parse_times(col, info=info, **times)
        ns[idx], ok[idx] = np.asarray(ns_b), np.asarray(ok_b)
        fmt = info.get("time_format")
        if fmt and fmt not in formats:
            formats.append(fmt)
        zoned += info.pop("_zoned_n", 0)
        naive += info.pop("_naive_n", 0)
        for key, value in info.items():
            if key in ("_rows", "_by_table"):
                continue
            if isinstance(value, (np.ndarray, pd.Series)) and len(value) == len(idx):
                full = counted.get(key)
                if not isinstance(full, np.ndarray) or len(full) != n:
                    full = np.zeros(n, dtype=bool)
                full[idx] |= np.asarray(value, dtype=bool)
                counted[key] = full
            elif (
                isinstance(value, dict)
                and value
                and all(isinstance(v, (np.ndarray, pd.Series)) for v in value.values())
            ):
                merged = counted.setdefault(key, {})
                for word, mask in value.items():
                    full = merged.get(word)
                    if not isinstance(full, np.ndarray) or len(full) != n:
                        full = np.zeros(n, dtype=bool)
                    full[idx] |= np.asarray(mask, dtype=bool)
                    merged[word] = full
            elif key in _SUMMED_TIME_KEYS and not isinstance(value, bool):
                counted[key] = counted.get(key, 0) + value - start.get(key, 0)
            elif isinstance(value, bool):
                counted[key] = bool(counted.get(key)) or value
            elif key == "zone_words" and isinstance(value, dict):
                merged = counted.setdefault(key, {})
                for word, k in value.items():
                    merged[word] = merged.get(word, 0) + k
            else:
                counted.setdefault(key, value)
    if zoned and naive:  # zoned times in one table, zone-less in another (or both mixed)
        counted["zoned_times"], counted["zoneless_times"] = zoned, naive
    if len(formats) > 1:
        counted["time_formats_by_table"] = formats
    counted["_rows"] = n
    return ns, ok


def _tables_in(rows: _Rows, sn: Sniff, res: Resolved, time_ok) -> bool:
    """Whether a piece's rows hold a header line of other columns (tables.py)."""
    from wakeline.core.io.tables import has_second_table

    return has_second_table(rows, sn, res, ~np.asarray(time_ok, dtype=bool))


def _header_again(table: pa.Table, cols: dict[str, str], rows: np.ndarray) -> np.ndarray:
    """Which of ``rows`` (a mask) repeat the header: every mapped cell is its column's
    name, in any case (a second file's header where files were joined). Looks at ``rows``
    only."""
    out = np.zeros(table.num_rows, dtype=bool)
    where = np.flatnonzero(rows)
    if not len(where):
        return out
    sub = table.take(pa.array(where))
    same = np.ones(len(where), dtype=bool)
    for src in set(cols.values()):
        text, _ = _trimmed(sub[src]) if src in sub.column_names else (None, None)
        if text is None:
            continue
        text = pc.utf8_lower(pc.utf8_ltrim(text, "\ufeff"))  # a joined file's byte order mark
        # in any case: a joined export may write its header upper-case (TIME,LAT,LON)
        same &= np.asarray(pc.fill_null(pc.equal(text, src.strip().lower()), False), dtype=bool)
    out[where[same]] = True
    return out


def _trimmed(arr: pa.ChunkedArray) -> tuple[pa.ChunkedArray, np.ndarray]:
    """Text with edge blanks removed, and a mask of missing (null or blank) cells."""
    text = pc.utf8_trim_whitespace(pc.cast(arr, pa.string()).fill_null(""))
    return text, np.asarray(pc.equal(pc.utf8_length(text), 0))


def _clean_floats(arr: pa.ChunkedArray, lo: float, hi: float, hi_open: bool = False) -> bool:
    """True when a float column has no null, NaN or value outside [lo, hi] (or [lo, hi)):
    one vectorized comparison (NaN compares false), no row-sized copy."""
    if len(arr) == 0:
        return True
    if not pa.types.is_floating(arr.type) or arr.null_count:
        return False
    upper = pc.less(arr, hi) if hi_open else pc.less_equal(arr, hi)
    return bool(pc.all(pc.and_(pc.greater_equal(arr, lo), upper)).as_py())


#: ITU-R M.1371's "not available" values as Wakeline reads them: lon 181, lat 91, SOG 1023
#: (102.3 kn), COG 3600 (360.0°).
AIS_NOT_AVAILABLE = {"lon": 181.0, "lat": 91.0, "speed": 102.3, "course": 360.0}
#: The quarantine reason of a row whose position is AIS's "not available" (as the NMEA
#: reader says it).
AIS_NO_POSITION = "position not available (lon 181 / lat 91)"
#: Speed and course column names that are AIS's own (normalised): SOG, COG.
_AIS_NAMES = {"speed": "sog", "course": "cog"}


def ais_columns(res: Resolved) -> set[str]:
    """The attribute fields (speed, course) whose column is AIS's: in an AIS layout
    (MarineCadastre, DMA), or named SOG / COG. Only there is 102.3 kn AIS's "not
    available"; a radar's speed column keeps 102.3 kn as the number it is."""
    out = set()
    for name, ais_name in _AIS_NAMES.items():
        src = res.columns.get(name)
        if src is not None and (res.format.family == "ais" or normalize_header(src) == ais_name):
            out.add(name)
    return out


def _holds(arr: pa.ChunkedArray, value: float | None) -> bool:
    """Whether a numeric column holds ``value`` (one vectorized comparison)."""
    if value is None or len(arr) == 0:
        return False
    hit = pc.any(pc.less(pc.abs(pc.subtract(arr, value)), 1e-9)).as_py()
    return bool(hit)


def _swapped_rows(lon, lat) -> np.ndarray | None:
    """Rows whose lat lies beyond ±90 (within ±180) while their lon lies within ±90: a
    longitude under the lat name and a latitude under lon (one vectorized pass; NaN and
    null count as no). None when there is nothing to judge."""
    if lon is None or lat is None or len(lat) == 0:
        return None
    try:
        a_lat, a_lon = pc.abs(pc.cast(lat, pa.float64())), pc.abs(pc.cast(lon, pa.float64()))
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
        return None
    hit = pc.and_(
        pc.and_(pc.greater(a_lat, 90.0), pc.less_equal(a_lat, 180.0)),
        pc.less_equal(a_lon, 90.0),
    )
    return np.asarray(pc.fill_null(hit, False), dtype=bool)


def _looks_swapped(lon, lat) -> int:
    """How many rows :func:`_swapped_rows` finds."""
    hit = _swapped_rows(lon, lat)
    return 0 if hit is None else int(hit.sum())


def _swapped_groups(hit: np.ndarray | None, codes: np.ndarray, n_names: int) -> np.ndarray:
    """Per name (sensor, or track where the file has no sensor column): whether most of
    its rows look swapped (:func:`_swapped_rows`)."""
    if hit is None or not n_names:
        return np.zeros(n_names, dtype=bool)
    ok = codes >= 0
    rows = np.bincount(codes[ok], minlength=n_names)
    hits = np.bincount(codes[ok & hit], minlength=n_names)
    return hits > rows / 2


#: The quarantine reason of a row of a file whose lat and lon columns look swapped (most
#: rows' lat beyond ±90° with lon within ±90°) that is not out of range itself.
SWAPPED_REASON = "in a file whose lat and lon columns look swapped"


def swapped_file(report: dict) -> bool:
    """Whether a read's counts judge the file's lat and lon columns swapped (most rows
    read have lat beyond ±90° and lon within ±90°)."""
    rows = int(report.get("rows_read", 0) or 0)
    return bool(rows) and int(report.get("lat_beyond_90_lon_within", 0) or 0) > rows / 2


#: The layouts that fix the order of the position columns (format name → the field that
#: comes first): a file of such a layout with the other order may have its names swapped.
POSITION_ORDER = {
    "radar": "lon",
    "ais-marinecadastre": "lat",
    "ais-dma": "lat",
    "mtad-measurement": "lat",
    "mtad-scene": "lat",
}


def position_warnings(
    sn: Sniff, res: Resolved, swapped: int, rows: int, groups: tuple | None = None
) -> list[str]:
    """Warnings that the lat and lon columns may hold each other's values: most rows have
    lat beyond ±90 and lon within ±90 (``swapped`` of ``rows``; or of some sensors', or
    tracks', rows in a file of several: ``groups``, (kind, names, how many in the file)),
    or a known layout's position columns come in the other order. Nothing is swapped:
    that is the user's call (``--map lat=… --map lon=…``)."""
    lat, lon = res.columns.get("lat"), res.columns.get("lon")
    if lat is None or lon is None:
        return []
    out = []
    fix = f"--map lat={lon} --map lon={lat}"
    if groups:
        kind, names, of = groups
        said = ", ".join(names[:5]) + (", …" if len(names) > 5 else "")
        out.append(
            f"column {lat!r} (read as latitude) is beyond ±90° in most rows of {len(names):,} "
            f"{kind}(s) of {of:,} ({kind} {said}) while {lon!r} lies within ±90° there "
            f"(lat_beyond_90_lon_within in the report counts them): their columns look "
            f"swapped (longitudes under {lat!r}); their rows are quarantined (none is kept "
            f"at a mirrored place), the other {kind}s' rows are read. If so, import their "
            f"rows again with {fix}"
        )
    elif rows and swapped > rows / 2:
        out.append(
            f"column {lat!r} (read as latitude) is beyond ±90° in most rows while {lon!r} "
            f"lies within ±90° (lat_beyond_90_lon_within in the report counts them): the "
            f"columns look swapped (longitudes under "
            f"{lat!r}); every row is quarantined (none is kept at a mirrored place). If so, "
            f"import again with {fix}"
        )
    first = POSITION_ORDER.get(res.format.name)
    if first is not None and lat in sn.columns and lon in sn.columns:
        lat_first = sn.columns.index(lat) < sn.columns.index(lon)
        if lat_first != (first == "lat"):
            order = f"{lat}, {lon}" if lat_first else f"{lon}, {lat}"
            usual = "latitude first" if first == "lat" else "longitude first"
            out.append(
                f"the position columns come as {order}; the {res.format.label} layout has "
                f"{usual}: if the names were swapped the positions are mirrored (check the "
                f"map; {fix} reads them the other way)"
            )
    return out


def carried_columns(sn: Sniff, res: Resolved) -> list[str]:
    """The file's columns the points carry as they came (the report's
    ``extra_columns``): those no field takes, and the local-plane ones (a plane file's
    own metres, which ``export --like`` writes back; a plane column mapped on a file
    with lon/lat, not used)."""
    plane = {res.columns[f] for f in PLANE_FIELDS if f in res.columns}
    mapped = set(res.columns.values())
    return [c for c in sn.columns if c not in mapped or c in plane]


BEARING_BEYOND = "bearing beyond"
#: In the warning :func:`bearing_warnings` gives (made again from the summed counts when
#: a file is read in pieces).
BEARING_WARNING_MARK = "beyond a full turn ("


#: The quarantine reason of a last line cut inside its last cell (sniff.cut_last_cell).
CUT_LAST_REASON = "cut last line"


def cut_short_warnings(sn: Sniff, quarantine: pd.DataFrame) -> list[str]:
    """A warning when the file's last line is a short row, or was cut inside its last
    cell (``sn.cut_last``, quarantined as :data:`CUT_LAST_REASON`): the file was cut
    short (still being written or copied when it was read). One pass over the file, only
    when a short row was quarantined."""
    if not len(quarantine) or "reason" not in quarantine.columns:
        return []
    reason = quarantine["reason"].astype(str)
    cut = quarantine[reason == CUT_LAST_REASON]
    if len(cut) and sn.cut_last:
        return [
            f"line {int(cut['line'].max()):,}{CUT_SHORT_MARK}no line end and its last value "
            f"looks cut ({sn.cut_last}): quarantined as {CUT_LAST_REASON!r}; the file may "
            "be cut short (still being written or copied when it was read); open it again "
            "once it is complete"
        ]
    short = quarantine[reason.str.startswith("short row")]
    if not len(short):
        return []
    line = int(short["line"].max())
    why = str(short.loc[short["line"] == line, "reason"].iloc[0])
    try:
        with (
            open_data(sn.path, sn.compression) as raw,
            io.TextIOWrapper(raw, encoding="latin-1", newline=None) as fh,
        ):
            after = any(line_text.strip() for k, line_text in enumerate(fh, 1) if k > line)
    except OSError:
        return []
    if after:
        return []
    fields = why.removeprefix("short row: ")
    return [
        f"line {line:,}{CUT_SHORT_MARK}{fields}: the file may be cut short (still "
        "being written or copied when it was read); open it again once it is complete"
    ]


def bearing_warnings(columns: dict[str, str], reasons: dict, rows_read: int) -> list[str]:
    """A warning counting the bearings quarantined for lying beyond a full turn, and when
    they are most of the rows of a column whose header says radians, that they look like
    degrees (the unit comes from the header alone)."""
    out = []
    rows = {k: int(v) for k, v in (reasons or {}).items() if str(k).startswith("a bearing (")}
    if rows:
        empty = int((reasons or {}).get(EMPTY_SCAN, 0))
        name = next(iter(rows)).split("'")[1]
        out.append(
            f"{sum(rows.values()):,} of {rows_read:,} rows carry a bearing ({name!r}){BEARING_ROWS_MARK}"
            "a bearing-only sensor's (a camera's), quarantined here; read them with "
            "`wakeline bearing` (in the window: File > Open bearings)"
            + (f"; empty scans (nothing detected): {empty:,}" if empty else "")
        )
    col = columns.get("bearing")
    n = sum(int(v) for k, v in (reasons or {}).items() if str(k).startswith(BEARING_BEYOND))
    if not col or not n:
        return out
    radians = angle_unit(col)[1] == "radians"
    text = (
        f"{n:,} of {rows_read:,} rows have a bearing in {col!r} beyond a full turn "
        f"({'±2π: the header says radians' if radians else '±360°'}): quarantined"
    )
    if radians and 2 * n > rows_read:
        text += (
            "; most bearings are beyond 2π, so they look like degrees: name the column "
            "without 'rad' (e.g. 'bearing') to read them as degrees"
        )
    return [*out, text]


def origin_warnings(res: Resolved, headers=()) -> list[str]:
    """A warning when an origin, or a local-plane column (``--map east=COL``), was given
    for a file whose positions are lon/lat: not used (the column is carried as an extra
    column); and when a file on a plane has positions of the other kind too (x/y beside
    range and bearing, ``headers`` its columns): which were read, and the --map that
    reads the others."""
    if res.on_plane:
        other = unused_position_columns(headers, res.columns)
        if not other:
            return []
        kind = plane_kind(res.columns)
        read = ("east", "north") if kind == "cartesian" else ("range", "bearing")
        flags = " ".join(f"--map {shlex.quote(f'{k}={v}')}" for k, v in other.items())
        return [
            f"the file has positions of two kinds: {read[0]}/{read[1]} "
            f"({res.columns[read[0]]!r}, {res.columns[read[1]]!r}) were read, "
            f"{'/'.join(other)} ({', '.join(repr(v) for v in other.values())}) are carried "
            f"as extra columns; {flags} reads those instead"
        ]
    if res.origin is None and not any(f in res.columns for f in PLANE_FIELDS):
        return []
    where = f"the file gives longitude and latitude ({res.columns.get('lon')!r}, "
    where += f"{res.columns.get('lat')!r}), not metres on a plane"
    out = []
    if res.origin is not None:
        out.append(f"--origin {res.origin[0]:g},{res.origin[1]:g} was not used: {where}")
    mapped = [f"{f}={res.columns[f]}" for f in PLANE_FIELDS if f in res.columns]
    if mapped and "lon" in res.columns:
        out.append(f"--map {' '.join(mapped)} was not used: {where}; carried as extra columns")
    return out


#: The reason of a plane position farther from the origin than half the earth's
#: circumference (20,015 km), where the azimuthal equidistant plane stops being one-to-one.
PLANE_TOO_FAR = "position beyond half the earth from --origin (metres scaled or cut wrongly?)"


def _plane_positions(
    table: pa.Table, res: Resolved, comma: bool, counted: dict, flag: Callable
) -> tuple[pa.Array, pa.Array]:
    """Lon and lat (degrees) of a file whose positions lie on a local plane about
    ``res.origin``: east and north, or range and bearing (true, clockwise from north)
    from it, plus the offsets (e.g. the ownship's place in the same frame); lengths in
    the unit their header names (km, nautical miles; else metres), a bearing in radians
    when its header says so (else degrees). Azimuthal equidistant: distance and bearing
    from the origin exact. A row without a number in any of them is quarantined with the
    column's name and the unit its header gave it; a negative range, and a bearing
    beyond a full turn either way (365.5°, 720°: no bearing of any convention, 0-360 or
    signed), are quarantined too."""
    cols = res.columns

    def values(key: str) -> np.ndarray:
        v, unparsable = _numbers(table[cols[key]], comma, counted)
        factor, word = (
            angle_unit(cols[key]) if key == "bearing" else length_unit(cols[key], res.distance_unit)
        )
        flag(unparsable, f"unparsable {key} ({cols[key]!r}, {word})")
        flag(np.isnan(v) & ~unparsable, f"missing {key} ({cols[key]!r}, {word})")
        flag(np.isinf(v), f"{key} infinite")
        if key == "bearing":
            turn = 2.0 * np.pi / factor  # 360 degrees, 2π radians
            with np.errstate(invalid="ignore"):
                beyond = np.abs(v) > turn * (1.0 + 1e-12)
            flag(
                beyond,
                f"bearing beyond ±{'360°' if factor != 1.0 else '2π'} ({cols[key]!r}, {word})",
            )
        return v * factor

    if plane_kind(cols) == "polar":
        r, b = values("range"), values("bearing")
        flag(r < 0, f"range negative ({cols['range']!r})")
        xy = [r * np.sin(b), r * np.cos(b)]
    else:
        _bearing_rows(table, cols, flag)
        xy = [values("east"), values("north")]
    for k, axis in enumerate(("east", "north")):
        if f"{axis}_offset" in cols:
            xy[k] = xy[k] + values(f"{axis}_offset")
    # The projection is one-to-one only within half the earth's circumference of the
    # origin: metres beyond it (a value cut or scaled wrongly) would wrap to some other
    # place on the globe and pass as a fix.
    with np.errstate(invalid="ignore", over="ignore"):
        far = ~(np.hypot(xy[0], xy[1]) < np.pi * EARTH_RADIUS_M)
    flag(far & np.isfinite(xy[0]) & np.isfinite(xy[1]), PLANE_TOO_FAR)
    if far.any():  # NaN and infinite included: quarantined above, no warnings from them
        xy = [np.where(far, 0.0, v) for v in xy]
    lat0, lon0 = res.origin
    lon, lat = from_local(xy[0], xy[1], lon0, lat0)
    return pa.array(lon), pa.array(lat)


#: The reason of a row of a bearing-only sensor (a camera) in a file read as positions.
BEARING_NO_POSITION = (
    "a bearing ({0!r}) and no position: a bearing-only sensor's row; read these rows with "
    "`wakeline bearing` (in the window: File > Open bearings)"
)
#: In the warning counting such rows (a read in pieces says it once, from the sums).
BEARING_ROWS_MARK = " and no position: "
#: The reason of a row with neither position nor bearing (a scan that detected nothing).
EMPTY_SCAN = "an empty scan (no position, no bearing: nothing detected)"


def _bearing_rows(table: pa.Table, cols: dict[str, str], flag: Callable) -> None:
    """Rows of east/north plane positions where both are blank: a bearing in a column the
    track import does not read (a camera's rows of a multi-sensor detection file) says
    which sensor they are and where to read them; no bearing either is an empty scan."""
    if "east" not in cols or "north" not in cols:
        return
    used = set(cols.values())
    found = [
        name
        for name in table.column_names
        if name not in used and known_fields([name]) == {"bearing"}
    ]
    if not found:
        return
    east, north = table[cols["east"]], table[cols["north"]]

    def blank(arr) -> np.ndarray:
        if pa.types.is_floating(arr.type) or pa.types.is_integer(arr.type):
            return np.asarray(arr.is_null().to_numpy(zero_copy_only=False), dtype=bool) | (
                np.isnan(arr.to_numpy(zero_copy_only=False).astype("float64"))
            )
        text = pd.Series(arr.to_pandas(), dtype="str").str.strip()
        return (text.isna() | (text == "")).to_numpy()

    none = blank(east) & blank(north)
    if not none.any():
        return
    bearing = ~blank(table[found[0]])
    flag(none & bearing, BEARING_NO_POSITION.format(found[0]))
    flag(none & ~bearing, EMPTY_SCAN)


#: Rows of a streamed import the speed-unit check looks at (the first ones, in pieces).
UNIT_CHECK_ROWS = 500_000


def _unit_checked(res) -> bool:
    """Whether the speed column is read as knots only because its header names no unit and
    none was given (not Wakeline's own canonical table)."""
    header = res.columns.get("speed")
    if not header or res.format.name == "canonical" or res.speed_unit != "auto":
        return False
    return not speed_unit(header, res.speed_unit)[2]  # [2]: its header names its unit


def _keep_for_unit_check(checked: list, points: pd.DataFrame, res) -> None:
    """A streamed piece's rows for :func:`_unit_check`, up to :data:`UNIT_CHECK_ROWS`."""
    room = UNIT_CHECK_ROWS - sum(len(c) for c in checked)
    if room > 0 and _unit_checked(res):
        cols = [c for c in ("sensor", "batch", "time", "lon", "lat", "speed") if c in points]
        checked.append(points[cols].iloc[:room])


def _unit_check(points: pd.DataFrame | None, res) -> list[str]:
    """:func:`~wakeline.core.io.speed_check.speed_unit_warnings` for a speed column read
    as knots only because its header names no unit and none was given (D-import-14)."""
    if points is None or not _unit_checked(res):
        return []
    header = res.columns["speed"]
    from wakeline.core.io.speed_check import speed_unit_warnings

    return speed_unit_warnings(points, header, "knots")


def _in_knots(arr, header: str, given: str, counted: dict):
    """A speed column in knots: as it is when its header names knots or no unit (and
    ``given`` is auto or knots), else in the unit's metres per hour over 1852 (vectorized);
    the unit and what named it in ``counted["speed_unit"]``."""
    per_hour, unit, named = speed_unit(header, given)
    if named and given not in ("auto", unit):
        counted["speed_unit_refused"] = given
    if unit == "knots":
        return arr
    counted["speed_unit"] = (unit, named)
    return pc.divide(pc.multiply(arr, pa.scalar(per_hour)), pa.scalar(1852.0))


_RANGES = {
    "lon": (-180.0, 180.0, False),
    "lat": (-90.0, 90.0, False),
    "course": (0.0, 360.0, True),
    "speed": (0.0, np.inf, False),
}


#: Of the present values of a lat (lon) column beside a hemisphere column, the share
#: that must be degrees and minutes run together (ddmm.mmmm) for the column to be read
#: so (the others, a damaged cell, are quarantined).
DDMM_SHARE = 0.99
DDMM_REASON = "{} not in ddmm.mmmm as the rest of its column (minutes 60 or more)"
#: The hemisphere letters of each position field, as a reason names them.
LETTERS = {"lat": "N or S", "lon": "E or W"}
#: The start of the warning that says where a ddmm.mmmm file's signs came from.
DDMM_NOTE_START = "lat and lon are ddmm.mmmm"


def _ddmm(v: np.ndarray, top: float) -> np.ndarray:
    """Degrees of numbers written as NMEA writes them, degrees and minutes run together
    (``3754.0300`` is 37°54.03', 37.9005; ``-02336.06`` is -23.601); NaN where ``v`` is
    no such number (minutes 60 or more, or beyond ``top`` degrees)."""
    a = np.abs(v)
    deg = np.floor(a / 100.0)
    minutes = a - 100.0 * deg
    out = np.round(deg + minutes / 60.0, 10)  # 3754.06 is 37.901, not 37.900999999999996
    with np.errstate(invalid="ignore"):
        ok = (minutes < 60.0) & (out <= top)
    return np.where(ok, np.copysign(out, v), np.nan)


def ddmm_judged(values: np.ndarray, name: str, letters: bool) -> bool:
    """Whether a lat (``name``) or lon column of numbers ``values`` (NaN: none) holds
    NMEA's ddmm.mmmm, by :func:`_ddmm_positions`' rule (for lon: given that lat does);
    ``letters``: a column of hemisphere letters stands beside it."""
    present = ~np.isnan(values)
    if not present.any():
        return False
    ok = ~np.isnan(_ddmm(values, 90.0 if name == "lat" else 180.0)) & present
    with np.errstate(invalid="ignore"):
        beyond = np.abs(values) > 90.0
    if letters:  # most lat beyond 90: a degrees column with one damaged value is not ddmm
        most = name == "lon" or 2 * beyond.sum() > present.sum()
        return bool(ok.sum() >= DDMM_SHARE * present.sum() and most)
    return bool(ok[present].all() and beyond[present].all())


def hemisphere_letters(
    cells: pa.Array | pa.ChunkedArray, letters: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Whether a column's cells are the two hemisphere ``letters`` (``"NS"``, ``"EW"``;
    case and edge blanks aside): at least one is, and 99 % of its present cells are (a
    damaged cell does not hide the column). Then per row whether it says the negative one
    (S, W), whether it holds something else (that row's sign is unknown) and whether it
    says the positive one; else None.
    A column of numbers is none (no cast: the common case costs nothing)."""
    if not (
        pa.types.is_string(cells.type)
        or pa.types.is_large_string(cells.type)
        or pa.types.is_dictionary(cells.type)
        or pa.types.is_null(cells.type)
    ):
        return None
    col = pc.utf8_upper(pc.utf8_trim_whitespace(pc.cast(cells, pa.string())))
    col = pc.fill_null(col, "")
    negative = np.asarray(pc.equal(col, letters[1]), dtype=bool)
    letter = negative | np.asarray(pc.equal(col, letters[0]), dtype=bool)
    present = np.asarray(pc.not_equal(col, ""), dtype=bool)
    if letter.any() and letter.sum() >= DDMM_SHARE * present.sum():
        return negative, present & ~letter, letter & ~negative
    return None


def hemisphere_column(
    columns: tuple[str, ...] | list[str],
    src: str,
    mapped: set[str],
    cells: Callable[[str], pa.Array | pa.ChunkedArray],
    letters: str,
) -> tuple[str, np.ndarray, np.ndarray, np.ndarray] | None:
    """The column beside ``src`` (after it, else before it) mapped to no field whose
    cells (``cells(name)``) are the hemisphere ``letters`` (:func:`hemisphere_letters`),
    with its per-row negative, other-letter and positive masks; None when no column is. One rule
    for the reader and for the layout ``export --like`` learns."""
    if src not in columns:
        return None
    i = list(columns).index(src)
    for j in (i + 1, i - 1):
        if not 0 <= j < len(columns) or columns[j] in mapped:
            continue
        got = hemisphere_letters(cells(columns[j]), letters)
        if got is not None:
            return (columns[j], *got)
    return None


def _hemisphere_column(
    sn: Sniff, table: pa.Table, src: str, mapped: set[str], letters: str
) -> tuple[str, np.ndarray, np.ndarray, np.ndarray] | None:
    """:func:`hemisphere_column` over a parsed table's columns."""
    return hemisphere_column(sn.columns, src, mapped, lambda name: table[name], letters)


#: How :func:`~wakeline.core.io.timetext.zone_words` counts an ambiguous zone word read
#: in --tz.
AS_TZ = " (as --tz)"
#: The start of the warning that says a file's decimal degrees take their signs from
#: columns of hemisphere letters beside them.
LETTER_NOTE_START = "the signs of"
#: Quarantine reason of a negative value whose letter says the positive hemisphere.
SIGN_REASON = "{} negative but its hemisphere letter says {}"


def _letter_signs(
    v: np.ndarray, hemi: tuple[str, np.ndarray, np.ndarray, np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """Degrees ``v`` signed by a column of hemisphere letters ``hemi``
    (:func:`hemisphere_column`): S and W make a value negative (``-37.9`` with ``S`` is
    -37.9 too), N and E and a blank letter keep it; NaN where the letter is another (its
    sign is unknown) and where a negative value has N (E), a contradiction, returned as
    a mask for its own reason."""
    _, negative, other, positive = hemi
    with np.errstate(invalid="ignore"):
        clash = positive & (v < 0)
    signed = np.where(negative, -np.abs(v), v)
    signed[other | clash] = np.nan
    return signed, clash


def _letter_columns(
    table: pa.Table, sn: Sniff, res: Resolved
) -> dict[str, tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
    """The columns of hemisphere letters beside lat (N/S) and lon (E/W), by field
    (:func:`hemisphere_column`); none on a local plane."""
    cols = res.columns
    if res.on_plane or "lat" not in cols or "lon" not in cols:
        return {}
    mapped = set(cols.values())
    out = {}
    for name, letters in (("lat", "NS"), ("lon", "EW")):
        hemi = _hemisphere_column(sn, table, cols[name], mapped, letters)
        if hemi is not None:
            out[name] = hemi
    return out


def _letter_note(hemis: dict, counted: dict, ddmm: bool) -> None:
    """Say in ``counted["letter_note"]`` which columns of hemisphere letters gave plain
    decimal degrees their signs (a ddmm.mmmm file says it in its own note)."""
    if ddmm or not hemis:
        return
    fields = " and ".join(hemis)
    cols = " and ".join(repr(h[0]) for h in hemis.values())
    counted["letter_note"] = (
        f"{LETTER_NOTE_START} {fields} come from the hemisphere letters in {cols} "
        "(S and W negative)"
    )


def _ddmm_positions(
    table: pa.Table, sn: Sniff, res: Resolved, comma: bool, counted: dict, hemis: dict
) -> dict[str, tuple]:
    """The lat and lon columns read as NMEA's ddmm.mmmm / dddmm.mmmm, when they are so:
    ``{field: (degrees, unparsable, not ddmm, letter neither hemisphere's or None, sign
    against the letter or None)}``, else ``{}``. The lat column decides
    (a lon of 100-180 is plain degrees): with a column of N/S beside it (and E/W beside
    lon: ``hemis``, :func:`_letter_columns`), when 99 % of its present values are
    ddmm.mmmm and most lie beyond 90; with
    none, when every lat value lies beyond 90 and is ddmm.mmmm, and every lon value lies
    beyond 90 too and is dddmm.mmmm (a file whose lat holds its longitudes, the columns
    swapped, stays as it is). Lon is read so only with lat. The letters give the sign
    (S, W negative), and a minus sign does. Counted in ``counted["ddmm"]``."""
    cols = res.columns
    if res.on_plane or "lat" not in cols or "lon" not in cols:
        return {}
    lat_arr, lon_arr = table[cols["lat"]], table[cols["lon"]]
    if _clean_floats(lat_arr, -90.0, 90.0):
        return {}  # the common case: degrees
    if pa.types.is_floating(lat_arr.type) or pa.types.is_integer(lat_arr.type):
        with np.errstate(invalid="ignore"):
            a = np.abs(lat_arr.to_numpy().astype("float64", copy=False))
        if not (a > 90.0).any():
            return {}  # degrees with a value missing: nothing beyond 90
    got = {}
    for name, arr, top in (("lat", lat_arr, 90.0), ("lon", lon_arr, 180.0)):
        v, unparsable = _numbers(arr, comma)
        hemi = hemis.get(name)
        if not ddmm_judged(v, name, hemi is not None):
            return {}
        deg = _ddmm(v, top)
        clash = None
        if hemi is not None:
            deg, clash = _letter_signs(deg, hemi)
        not_ddmm = ~np.isnan(v) & np.isnan(_ddmm(v, top)) & ~(hemi[2] if hemi else False)
        got[name] = (deg, unparsable, not_ddmm, hemi[2] if hemi else None, clash, hemi and hemi[0])
    read = int(sum((~np.isnan(g[0])).sum() for g in got.values()))
    counted["ddmm"] = counted.get("ddmm", 0) + read
    letters = [g[5] for g in got.values() if g[5]]
    counted["ddmm_note"] = DDMM_NOTE_START + (
        f"; their signs come from the hemisphere letters in "
        f"{' and '.join(map(repr, letters))} (S and W negative)"
        if letters
        else ": no column of hemisphere letters beside them, but every lat and every lon "
        "lies beyond 90 and reads as degrees and minutes (lon is read so only because lat is)"
    )
    return {name: g[:5] for name, g in got.items()}


#: Headers of a column of dates beside a time column of clock times (normalised).
_DATE_NAMES = frozenset(
    {
        "date",
        "utcdate",
        "dateutc",
        "datum",
        "fecha",
        "日期",
        "日期utc",
        "dato",
        "дата",
        "日付",
        "날짜",
    }
)
_CLOCK = r"^\s*\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?(?:\s*[AaPp]\.?[Mm]\.?)?\s*$"


#: Clock times alone (``08:01:04``, ``8:01 PM``): joined with a date column beside them.
CLOCK_ONLY = _CLOCK


def date_column(columns: tuple[str, ...] | list[str], mapped: set[str]) -> str | None:
    """The file's column of dates (``Date``, ``日期``...) that no field is mapped to."""
    for name in columns:
        if name not in mapped and normalize_header(name) in _DATE_NAMES:
            return name
    return None


def _clock_only(arr: pa.ChunkedArray) -> bool:
    """Whether a time column holds clock times without a date (``08:01:04``): at least
    99 % of its values present (a damaged one among them is its row's problem), or
    pyarrow typed it a time of day."""
    if pa.types.is_time(arr.type):
        return True
    if not (pa.types.is_string(arr.type) or pa.types.is_large_string(arr.type)):
        return False
    present = pc.drop_null(arr)
    present = present.filter(pc.not_equal(pc.utf8_trim_whitespace(present), ""))
    if not len(present):
        return False
    hits = pc.sum(pc.match_substring_regex(present, _CLOCK)).as_py() or 0
    return hits >= CLOCK_SHARE * len(present)


#: The share of a column's values (present) that must be clock times, dates or MMSIs
#: for the column to be taken as one by its values.
CLOCK_SHARE = 0.99
_CLOCK_RE = re.compile(_CLOCK)
#: A date without a clock: 2020-09-13, 13/09/2020, 13.09.2020, 09/13/2020.
_DATE_ONLY = re.compile(r"^\s*(?:\d{4}[-/.]\d{1,2}[-/.]\d{1,2}|\d{1,2}[-/.]\d{1,2}[-/.]\d{4})\s*$")
_MMSI_CELL = re.compile(r"^\d{9}$")
_ID_CELL = re.compile(r"^(?:[+-]?\d{1,12}|[A-Za-z0-9][A-Za-z0-9_\-/#]{0,15})$")
#: Whole-number columns of an AIS or GPX export that are no track's id.
_NOT_ID = re.compile(
    r"heading|hdg|status|navstat|turn|^rot$|draught|draft|length|width|beam|type|cargo"
    r"|class|accuracy|raim|maneuver|manoeuvre|second|^eta|dimension|^to(?:bow|stern|port)"
    r"|starboard|ele$|altitude|depth|count|seq|index|segid|pointid|^ogcfid$|fishing|msg"
    r"|message|repeat|flag|valid|quality|sat|hdop|pdop|fix$"
)
#: Names that say an id is not the tracked ship's (the receiver, the own ship).
_NOT_TRACK = re.compile(r"^(?:own|receiver|rx|station|base|dest|sensor|radar)")
#: Names a field is found by that mean something else too: taken only when the values
#: fit (German Länge/Breite: also a ship's length and beam; Fahrt/fart: way; French
#: route: a route's name in English; cap: heading; tid: a "track id"; the words for a
#: clock, Heure, Hora, Uhrzeit...: an hour's number 0-23 beside a column of date-times;
#: Portuguese and Italian data: English data).
#: A time that does not fit gives way to the next column the names give.
_AMBIGUOUS = {
    "lon": frozenset({"länge", "laenge"}),
    "lat": frozenset({"breite"}),
    "speed": frozenset({"fahrt", "fart"}),
    "course": frozenset({"route", "cap"}),
    "time": frozenset({"tid", "heure", "hora", "ora", "uhrzeit", "klokkeslett", "data"}),
}
_DEGREES = re.compile(r"^[+-]?\d{1,3}[.,]\d+$")


def _sample_cells(sn: Sniff, name: str) -> list[str]:
    """The non-blank cells of column ``name`` in the file's sampled rows."""
    if name not in sn.columns:
        return []
    k, width = sn.columns.index(name), len(sn.columns)
    cells = (r[k].strip() for r in sn.sample if len(r) == width)
    return [c for c in cells if c]


def _cells_of(sn: Sniff, name: str) -> list[str]:
    """The non-blank cells of column ``name`` in the file's preview rows."""
    k, width = sn.columns.index(name), len(sn.columns)
    return [c for r in sn.preview if len(r) == width and (c := r[k].strip().strip('"'))]


def _mostly(cells: list[str], pattern: re.Pattern, share: float = CLOCK_SHARE) -> bool:
    return bool(cells) and sum(bool(pattern.match(c)) for c in cells) >= share * len(cells)


def _values_fit(field: str, cells: list[str]) -> bool:
    """Whether the sampled values of a column found by an ambiguous name fit ``field``."""
    if not cells:
        return True  # nothing to judge by: as named
    if field in ("lon", "lat"):
        return _mostly(cells, _DEGREES, 0.5)
    if field == "time":
        numbers = pd.to_numeric(pd.Series(cells), errors="coerce")
        return bool(
            (numbers >= 1e8).mean() >= 0.5
            or sum(cell_kind(c) == "time" or bool(_CLOCK_RE.match(c)) for c in cells)
            >= 0.5 * len(cells)
        )
    numbers = pd.to_numeric(pd.Series(cells).str.replace(",", "."), errors="coerce")
    if numbers.notna().mean() < CLOCK_SHARE:
        return False
    if field == "course":
        # a course turns: a route's number (42 on every row) is none
        inside = ((numbers >= 0) & (numbers <= 360)).mean() >= CLOCK_SHARE
        return bool(inside and (len(cells) < 10 or numbers.nunique() > 1))
    return True


def _beside(sn: Sniff, name: str, used: set[str], pattern: re.Pattern) -> str | None:
    """The column next to ``name`` (after it, else before it) that no field reads and
    whose sampled values are ``pattern``'s (clock times, dates) at 99 %."""
    k = sn.columns.index(name)
    for j in (k + 1, k - 1):
        if 0 <= j < len(sn.columns) and sn.columns[j] not in used:
            if _mostly(_sample_cells(sn, sn.columns[j]), pattern):
                return sn.columns[j]
    return None


def id_candidates(sn: Sniff, columns: dict[str, str]) -> list[tuple[str, bool, int, int]]:
    """Columns no field reads whose sampled values look like track ids: whole numbers or
    short codes (no decimals, dates or clocks) that repeat over the rows, two or more
    distinct. (column, MMSI-like: nine digits, distinct values, rows) best first: MMSI
    -like, then a name that says id or number, then the rest, in file order."""
    used = set(columns.values())
    hint = re.compile(r"id|no$|nr|num|code|name|call|ship|vessel|boat|target|track|mmsi")
    out = []
    for k, name in enumerate(sn.columns):
        key = normalize_header(name)
        if name in used or _NOT_ID.search(key) or known_fields([name]) - {"batch", "sensor"}:
            continue
        if "sensor" in columns and "sensor" in key:  # sensor_id beside the sensor: no track id
            continue
        cells = _sample_cells(sn, name)
        distinct = len(set(cells))
        if distinct < 2 or distinct > len(cells) / 2 or not _mostly(cells, _ID_CELL):
            continue
        doubt = _not_an_id_over_time(sn, name, columns.get("time"))
        if doubt == 2:
            continue
        mmsi = _mostly(cells, _MMSI_CELL)
        rank = 0 if mmsi else 1 if hint.search(key) else 2
        rank += 3 * doubt  # an index within each time, maybe: after the others
        out.append((rank, k, name, mmsi, distinct, len(cells)))
    return [(name, mmsi, d, n) for _r, _k, name, mmsi, d, n in sorted(out)]


#: The share of a column's sampled values that must show the counter's (or the per-time
#: index's) pattern for it not to be offered as the track id.
COUNTER_SHARE = 0.9


def _not_an_id_over_time(sn: Sniff, name: str, time_src: str | None) -> int:
    """How surely a column's sampled values do not persist over time as a track's id does
    (operator test 7, D14: the Autoferry detections' ``scan`` and ``k`` were offered as
    the batch): 2 (left out of the hint) for a counter, each value at one time only (a
    message or scan number, new with every time step), or an index within each time
    (``k``: each time's values exactly 0..m-1 or 1..m, m varying between times) whose
    values do not recur from one time to the next (fewer than :data:`COUNTER_SHARE` of a
    time's values are seen at the next time: the m-th detection of a scan, m going up
    and down); 1 (offered after the others) for values that look like such an index but
    recur (track numbers 1..m, a new track now and then, or one missed in a scan: real
    ids, most likely); 0 otherwise. Judged only with evidence: the sample spans several
    times, and the index rule several times of two or more rows."""
    if time_src is None or time_src not in sn.columns or name not in sn.columns:
        return 0
    k, t, width = sn.columns.index(name), sn.columns.index(time_src), len(sn.columns)
    pairs = [
        (r[t].strip(), r[k].strip().strip('"'))
        for r in sn.sample
        if len(r) == width and r[t].strip() and r[k].strip().strip('"')
    ]
    times: dict[str, set[str]] = {}  # value → its times
    by_time: dict[str, list[str]] = {}  # time → its values (times in file order)
    for when, value in pairs:
        times.setdefault(value, set()).add(when)
        by_time.setdefault(when, []).append(value)
    if len(by_time) < 3:
        return 0
    once = sum(len(ts) == 1 for ts in times.values())
    if len(times) >= 3 and once >= COUNTER_SHARE * len(times):
        return 2  # a counter: no value is seen again at a later time
    shared = [vs for vs in by_time.values() if len(vs) >= 2]
    if len(shared) < 3:
        return 0

    def index_like(values: list[str]) -> bool:
        try:
            got = sorted(int(v) for v in values)
        except ValueError:
            return False
        return got in (list(range(len(got))), list(range(1, len(got) + 1)))

    sizes = {len(vs) for vs in by_time.values()}
    hits = sum(index_like(vs) for vs in shared)
    if len(sizes) < 2 or hits < COUNTER_SHARE * len(shared):
        return 0
    # a track's id is seen again at the next time; an index's values come and go with m
    sets = [set(vs) for vs in by_time.values()]
    seen = sum(len(a) for a in sets[:-1])
    again = sum(len(a & b) for a, b in zip(sets, sets[1:], strict=False))
    return 2 if again < COUNTER_SHARE * seen else 1


def _runs_up(sn: Sniff, name: str) -> bool:
    """Whether a column's sampled numbers never go down (a clock's seconds, shared by a
    radar scan's tracks, repeat too): not adopted as an id, only named."""
    values = pd.to_numeric(pd.Series(_sample_cells(sn, name)), errors="coerce").to_numpy()
    return bool(len(values) > 1 and (np.diff(values) >= 0).all())


def no_batch_warning(sn: Sniff, columns: dict[str, str]) -> str:
    """:data:`NO_BATCH_WARNING`, naming the columns whose values look like track ids and
    the ``--map`` that reads each."""
    found = id_candidates(sn, columns)[:3]
    if not found:
        return NO_BATCH_WARNING
    said = "; ".join(
        f"{name!r} ({'nine-digit MMSI-like numbers, ' if mmsi else ''}{d} distinct values "
        f"in the first {n} rows): --map {shlex.quote(f'batch={name}')}"
        for name, mmsi, d, n in found
    )
    return f"{NO_BATCH_WARNING}; by its values the id may be in {said}"


def judge_by_values(sn: Sniff, res: Resolved, mapping: dict[str, str] | None = None) -> Resolved:
    """What the sampled values (``sn.sample``) decide beyond the names, on a resolved
    mapping (the operator's ``mapping`` is kept as given):

    - a field found by an ambiguous name (:data:`_AMBIGUOUS`) whose values do not fit it
      is not read (an optional one travels as an extra column; a required one missing
      raises :class:`InputError`);
    - a time column of dates alone with a column of clock times beside it (99 % of its
      values, whatever its name): the clock column is the time, joined with the dates
      (``Resolved.date``); a clock-time column with a column of dates beside it (no
      column named Date): the same;
    - no batch column, and one column of nine-digit MMSI-like numbers that repeat, two
      or more distinct, that no field reads (not the receiver's or own ship's by its
      name): it is the batch, with a warning (``Resolved.notes``)."""
    if not sn.sample:
        return res
    mapping = mapping or {}
    cols = dict(res.columns)
    for what, names in _AMBIGUOUS.items():
        src = cols.get(what)
        if src is None or what in mapping or normalize_header(src) not in names:
            continue
        if not _values_fit(what, _sample_cells(sn, src)):
            del cols[what]
            other = next_column(res.format, what, sn.columns, set(cols.values()) | {src})
            if what == "time" and other is not None:
                if normalize_header(other) not in names or _values_fit(
                    what, _sample_cells(sn, other)
                ):
                    cols[what] = other
                    continue
            if what in ("time", "lon", "lat"):
                raise InputError(
                    f"{sn.path}: the column {src!r} is named like the {what} but its values "
                    f"are not (a word of two meanings); map the {what} column with "
                    f"--map {what}=COLUMN; headers found: {listed_headers(sn.columns)}"
                )
    date = None
    time_src = cols.get("time")
    used = set(cols.values())
    if time_src is not None and time_src in sn.columns:
        cells = _sample_cells(sn, time_src)
        if _mostly(cells, _CLOCK_RE):
            if date_column(sn.columns, used) is None:
                date = _beside(sn, time_src, used, _DATE_ONLY)
        elif "time" not in mapping and _mostly(cells, _DATE_ONLY):
            clock = _beside(sn, time_src, used, _CLOCK_RE)
            if clock is not None:
                cols["time"], date = clock, time_src
    notes = list(res.notes)
    if "batch" not in cols:
        mmsi = [
            c
            for c in id_candidates(sn, cols)
            if c[1] and not _NOT_TRACK.match(normalize_header(c[0])) and not _runs_up(sn, c[0])
        ]
        if len(mmsi) == 1:
            name, _m, d, n = mmsi[0]
            cols["batch"] = name
            notes.append(
                f"no column is named as the track's id: {name!r} holds nine-digit MMSI-like "
                f"numbers ({d} distinct in the first {n} rows) and is read as the batch "
                "(if another column holds each track's id, map it: --map batch=COLUMN)"
            )
    return dataclasses.replace(res, columns=cols, date=date, notes=tuple(notes))


def _to_canonical(
    rows: _Rows,
    sn: Sniff,
    res: Resolved,
    sensor: str,
    zone: datetime.tzinfo | None = None,
    time_info: dict | None = None,
    fetch_texts: bool = True,
    date_order: str = "auto",
    time_unit: str = "auto",
    clock_date: str | None = None,
    tables_read: bool = False,
):
    table, bad = rows.table, rows.bad
    n = table.num_rows
    cols = res.columns
    mapped = set(cols.values())
    # what the time parse adds, forgotten when a second table is read by its own header
    time_start = dict(time_info) if time_info is not None else None

    # Reasons as small codes: 0 = fine; the first reason found for a row wins.
    reason_names = [""]
    reasons = np.zeros(n, dtype="uint8")

    text = {name: _text_column(table[cols[name]]) for name in _TEXT_FIELDS if name in cols}

    # A blank line is a row with every cell empty; only rows without a batch can be one.
    blank = np.zeros(n, dtype=bool)
    candidates = np.flatnonzero(text["batch"].codes < 0)
    if len(candidates):
        sub = table.take(pa.array(candidates))
        all_empty = np.ones(len(candidates), dtype=bool)
        for src in sn.columns:
            all_empty &= _trimmed(sub[src])[1]
        blank[candidates[all_empty]] = True

    def flag(mask: np.ndarray, reason: str) -> None:
        if not mask.any():
            return
        new = mask & (reasons == 0) & ~blank
        if new.any():
            reason_names.append(reason)
            reasons[new] = len(reason_names) - 1

    for name in ("sensor", "batch"):
        if name in text:  # NUL bytes: a damaged line (its id would make a track of its own)
            names = text[name].names  # distinct values: a few, not one per row
            nul = np.fromiter(("\x00" in v for v in names), dtype=bool, count=len(names))
            if nul.any():
                codes = text[name].codes
                flag((codes >= 0) & nul[np.maximum(codes, 0)], "NUL bytes in the line (damaged)")
    for name in ("sensor", "batch"):
        if name in text:
            flag(text[name].codes < 0, f"missing {name}")
    if rows.replaced:
        undecodable = np.zeros(n, dtype=bool)
        for col in table.columns:
            if pa.types.is_string(col.type) or pa.types.is_dictionary(col.type):
                hit = pc.match_substring(pc.cast(col, pa.string()), "\ufffd")
                undecodable |= np.asarray(pc.fill_null(hit, False), dtype=bool)
        flag(undecodable, f"bytes not valid {rows.encoding}")
    time_col = table[cols["time"]]
    date_src = res.date or date_column(sn.columns, mapped)
    if date_src is not None and _clock_only(time_col):
        time_col = pc.binary_join_element_wise(
            pc.cast(table[date_src], pa.string()), pc.cast(time_col, pa.string()), " "
        )
        if time_info is not None:
            time_info["date_column"] = date_src
    comma = sn.delimiter != ","  # a decimal comma cannot be unquoted in a comma-separated file
    counted = time_info if time_info is not None else {}
    if res.gps_week is not None:  # GPS week and seconds of the week, or GPS seconds
        week = _numbers(table[res.gps_week], comma)[0] if res.gps_week else None
        sec = _numbers(time_col, comma)[0]
        ns, time_ok, no_week = gps_ns(sec, week, counted)
        flag(no_week, GPS_NO_WEEK.format(cols["time"]))
        if week is not None:
            flag(np.isnan(week) & ~np.isnan(sec), f"missing GPS week ({res.gps_week!r})")
            flag(
                ~np.isnan(week) & ~np.isnan(sec) & ~time_ok,
                "GPS week or seconds of the week out of range (a whole week from 0; "
                "seconds 0 to 604,800)",
            )
            low = week[time_ok]
            if len(low) and (low < 1024).all():
                counted["gps_ten_bit"] = True
    else:
        times = dict(
            kind=res.format.time_kind,
            tz=zone,
            decimal_comma=comma,
            date_order=date_order,
            time_unit=time_unit,
            header=cols["time"],
            clock_date=clock_date,
        )
        if rows.blocks is not None and len(np.unique(rows.blocks)) > 1:
            ns, time_ok = _times_by_table(time_col, rows.blocks, counted, times)
        else:
            ns, time_ok = parse_times(time_col, info=counted, **times)
    if not tables_read and (not np.all(time_ok) or bad.lines):
        # A second header line (two exports pasted into one file): its rows under the
        # first header's columns, then everything read again (tables.py).
        from wakeline.core.io.tables import second_tables

        if counted.get("_streaming") or counted.get("_edges") is not None:
            if _tables_in(rows, sn, res, time_ok):
                raise WholeFileNeeded  # a piece's line numbers and blocks are not the file's
        else:
            found = second_tables(
                rows,
                sn,
                res,
                ~np.asarray(time_ok, dtype=bool),
                lambda lines: _raw_lines(sn, lines, rows.encoding),
            )
            if found is not None:
                rows.notes += found
                time_info.clear()
                time_info.update(time_start)
                return _to_canonical(
                    rows,
                    sn,
                    res,
                    sensor,
                    zone,
                    time_info,
                    fetch_texts,
                    date_order,
                    time_unit,
                    clock_date,
                    tables_read=True,
                )
    if counted.get("clock_only"):  # times of day: over midnight by track, then the zone
        track = text["batch"].codes.astype("int64")
        if "sensor" in text:
            track = track * (len(text["sensor"].names) + 1) + text["sensor"].codes
        ns, time_ok = _clock_times(ns, time_ok, track, zone, clock_date, counted)
    early = counted.pop("early_times", None)
    if early is not None:
        flag(early, "time decades before the file's other times (a number cut short?)")
    if not time_ok.all():
        flag(_trimmed(time_col)[1], "missing time")
        outside = counted.pop("outside_span", None)
        if outside is not None:
            flag(outside, "time outside 1677-2262 (more than a ns clock holds)")
        if "ambiguous" in counted:
            if counted.get("_streaming"):
                raise WholeFileNeeded  # a track's two passes may lie in two pieces
            track = text["batch"].codes.astype("int64")
            if "sensor" in text:
                track = track * (len(text["sensor"].names) + 1) + text["sensor"].codes
            ns, time_ok = np.array(ns), np.array(time_ok)  # writable copies
            placed = _place_repeated_hour(track, counted, ns, time_ok)
            counted["clock_placed"] = counted.get("clock_placed", 0) + placed
        for word, where in counted.pop("zone_ambiguous", {}).items():
            flag(
                where,
                f"time zone {word} is ambiguous ({AMBIGUOUS_ZONES[word]}): give the zone with --tz",
            )
        changed = counted.pop("clock_change", None)
        if changed is not None:
            flag(changed, f"local time skipped or repeated by a clock change in {zone}")
        flag(_header_again(table, cols, ~time_ok), "the header line again (files joined?)")
        flag(~time_ok, "unparsable time")
    if str(counted.get("time_format", "")).endswith("text"):
        # Text times: a mistyped year (1700-01-01 among 2023 rows) parses; as with numbers
        # cut short, a time decades from the file's others is not a time of this file.
        flag(
            _decades_away(ns, time_ok),
            "time decades away from the file's other times (a mistyped year?)",
        )
    if not counted.get("relative"):
        track = text["batch"].codes.astype("int64")
        if "sensor" in text:
            track = track * (len(text["sensor"].names) + 1) + text["sensor"].codes
        edges = counted.get("_edges")
        carry = None if edges is None else edges["carry"]

        def keys(codes: np.ndarray) -> np.ndarray:
            width = len(text["sensor"].names) + 1 if "sensor" in text else 1
            b = text["batch"].names[codes // width]
            s = text["sensor"].names[codes % width] if "sensor" in text else [sensor] * len(b)
            return np.array([f"{x}\x1f{y}" for x, y in zip(s, b, strict=True)], dtype=object)

        lone_pending = None if edges is None else edges["lone"]
        if lone_pending is not None:
            lone_pending.keys = keys

        def carried_last(codes: np.ndarray) -> np.ndarray:
            if carry is None or not len(carry):
                return np.full(len(codes), np.nan)
            return carry.lookup(keys(codes))["last"]

        # A piece of a file read streamed or in pieces leaves lone rows to the whole file
        # (a track's order and neighbours lie over the file): _lone_times raises.
        flag(
            _lone_times(
                np.asarray(ns),
                np.asarray(time_ok) & (reasons == 0) & ~blank,
                track,
                piece=None
                if edges is None
                else (bool(edges.get("final")), carried_last, lone_pending),
            ),
            "time days away from its track's rows before and after it in the file "
            "(a mistyped date?)",
        )
        # A track's first or last row: judged by a whole read, and by a read in pieces in
        # its last piece with rows (a track's last row there is its last in the file),
        # with what the earlier pieces carried of each track (EdgeCarry).
        valid = np.asarray(time_ok) & (reasons == 0) & ~blank

        if edges is None or edges.get("final"):
            earlier = None
            if carry is not None and len(carry):

                def earlier(codes: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
                    got = carry.lookup(keys(codes))
                    return got, carry.spans(got["at"])

            flag(
                _edge_times(np.asarray(ns), valid, track, earlier),
                "time days from the rest of its track, at its start or end, where the file "
                "has no other track (a mistyped date?)",
            )
        else:
            codes, summary = _track_summary(np.asarray(ns), valid, track)
            carry.add(keys(codes), summary)

    floats: dict[str, pa.ChunkedArray | pa.Array] = {}
    blanked: dict[str, int] = {}
    course_read = None
    ais = ais_columns(res)
    if res.on_plane:
        floats["lon"], floats["lat"] = _plane_positions(table, res, comma, counted, flag)
    hemis = _letter_columns(table, sn, res)
    ddmm = _ddmm_positions(table, sn, res, comma, counted, hemis)
    _letter_note(hemis, counted, bool(ddmm))
    for name in _FLOAT_FIELDS:
        if name not in cols:
            continue
        arr = table[cols[name]]
        lo, hi, hi_open = _RANGES[name]
        sentinel = AIS_NOT_AVAILABLE[name] if name in ais else None
        if name in ddmm:  # NMEA's degrees and minutes run together
            v, unparsable, not_ddmm, bad_letter, clash = ddmm[name]
            flag(not_ddmm, DDMM_REASON.format(name))
            if bad_letter is not None:
                flag(bad_letter, f"{name} hemisphere letter not {LETTERS[name]}")
                flag(clash, SIGN_REASON.format(name, LETTERS[name][0]))
        elif (
            name not in hemis and _clean_floats(arr, lo, hi, hi_open) and not _holds(arr, sentinel)
        ):
            floats[name] = arr  # the common case: passes through untouched
            if name == "speed":
                floats[name] = _in_knots(arr, cols[name], res.speed_unit, counted)
            continue
        else:
            v, unparsable = _numbers(
                arr, comma, counted, angles=name in ("lon", "lat"), top=_RANGES[name][1], name=name
            )
            clash = counted.get("_form_clash", {}).pop(name, None)
            if clash is not None:  # a cell not in its column's form: neither form guessed
                flag(*clash)
            if name in hemis:  # decimal degrees with a column of hemisphere letters
                hemi = hemis[name]
                given = ~np.isnan(v)
                v, clash = _letter_signs(v, hemi)
                flag(unparsable, f"unparsable {name}")
                flag(hemi[2] & given, f"{name} hemisphere letter not {LETTERS[name]}")
                flag(clash, SIGN_REASON.format(name, LETTERS[name][0]))
                signed = given & (hemi[1] | hemi[3]) & ~clash
                counted["letter_signs"] = counted.get("letter_signs", 0) + int(signed.sum())
        with np.errstate(invalid="ignore"):
            outside = (v < lo) | (v >= hi if hi_open else v > hi) | np.isinf(v)
        as_read = v  # (course: kept below where this import changes it)
        if name in ("lon", "lat"):
            flag(unparsable, f"unparsable {name}")
            flag(np.isnan(v) & ~unparsable, f"missing {name}")
            # AIS's "not available" (lon 181, lat 91): no position, its own reason.
            flag(v == AIS_NOT_AVAILABLE[name], AIS_NO_POSITION)
            flag(outside, f"{name} out of range")
        else:
            # Counted on the rows kept (the positions are checked first: a row quarantined
            # for its position does not count its speed too).
            kept_so_far = (reasons == 0) & ~blank
            if sentinel is not None:
                # AIS's "not available" (SOG 1023 = 102.3 kn, COG 3600 = 360°): no value.
                na = np.abs(v - sentinel) < 1e-9
                if na.any():
                    label = f"{name} {sentinel:g} (AIS: not available)"
                    blanked[label] = int((na & kept_so_far).sum())
                    v = np.where(na, np.nan, v)
                    outside &= ~na
            if name == "course":  # a full circle is north (MTAD writes 360.0), not out of range
                full = v == 360.0
                if full.any():
                    v = np.where(full, 0.0, v)
                    outside &= ~full
            # Attributes, not positions: blank the value, keep the row, count it (a
            # course written "-" cost its fix; speed and course are derived from the
            # positions where missing).
            if unparsable.any():
                blanked[f"unparsable {name}"] = int((unparsable & kept_so_far).sum())
            if outside.any():
                label = (
                    "course outside [0, 360)" if name == "course" else "speed negative or infinite"
                )
                blanked[label] = int((outside & kept_so_far).sum())
                v = np.where(outside, np.nan, v)
            if name == "course":
                # A course this import changed (360.0 → 0, 380.4 or AIS's 360 blanked), as
                # the file had it, for `export --like` to write back (h135).
                changed = np.isfinite(as_read) & ~(as_read == v)
                if changed.any():
                    course_read = np.where(changed, as_read, np.nan)
        floats[name] = pa.array(v)
        if name == "speed":
            floats[name] = _in_knots(floats[name], cols[name], res.speed_unit, counted)

    counted.pop("_form_clash", None)
    blanked = {k: v for k, v in blanked.items() if v}  # values of quarantined rows only
    edges_in = (time_info or {}).get("_edges")
    if sn.cut_last and n and (edges_in is None or edges_in.get("final")):
        # the file's last line, cut inside its last cell (sniff.cut_last_cell): the last
        # row of the whole file or of its final piece (operator test 7, D7)
        lines_arr = np.asarray(rows.lines)
        flag(lines_arr == lines_arr.max(), CUT_LAST_REASON)
    hit = _swapped_rows(floats.get("lon"), floats.get("lat"))
    swapped = 0 if hit is None else int(hit.sum())
    # Judged per sensor (per track where the file has no sensor column) when it has
    # several: one sensor's columns swapped do not quarantine another's (review h209).
    group = text["sensor"] if "sensor" in text else text["batch"]
    judged = _swapped_groups(hit, group.codes, len(group.names)) if swapped else None
    if "_edges" not in (time_info or {}):  # a whole file (a piece's is judged over the file)
        read_n = int(n - int(blank.sum()) + len(bad.lines))
        present = np.unique(group.codes[group.codes >= 0])
        if len(present) > 1:
            if judged is not None and judged.any():
                # no row of such a sensor (track) is kept at the place its names give
                # (a lon within ±90 under lat would be a point mirrored across the
                # diagonal: operator test 7, D2); every row not quarantined already is, so
                inside = judged[np.maximum(group.codes, 0)] & (group.codes >= 0)
                flag(inside, SWAPPED_REASON)
                counted["_swapped_in"] = (
                    "sensor" if "sensor" in text else "track",
                    [str(x) for x in group.names[np.flatnonzero(judged)]],
                    len(present),
                )
        elif read_n and swapped > read_n / 2:
            # The file is judged swapped: every row not quarantined already is (D2).
            flag(np.ones(n, dtype=bool), SWAPPED_REASON)
    elif judged is not None and judged.any():
        # a piece with a sensor (track) that looks swapped: the whole file judges it
        time_info["_edges"].get("swapped", []).append(True)
    bad_rows = reasons != 0
    keep = ~bad_rows & ~blank
    all_kept = bool(keep.all())
    # rows that repeat an earlier row exactly: counted, and left out of the restart and
    # step-back tests (operator test 9, D8: 50 rows repeated at the end read as passes)
    repeat = _repeated_rows(
        text["sensor"].codes if "sensor" in text else None,
        np.asarray([sensor], dtype=object) if "sensor" not in text else text["sensor"].names,
        text["batch"].codes,
        text["batch"].names,
        ns,
        floats,
        keep,
        None if edges_in is None else edges_in.get("back"),
    )

    columns: dict[str, object] = {
        "sensor": text["sensor"].to_arrow()
        if "sensor" in text
        else pa.repeat(pa.scalar(sensor), n),
        "batch": text["batch"].to_arrow(),
        "time": pa.array(ns, type=pa.timestamp("ns", "UTC")),
    }
    for name in _FLOAT_FIELDS:
        columns[name] = floats[name] if name in floats else pa.nulls(n, pa.float64())
    if "truth" in text:
        columns["truth"] = pc.fill_null(text["truth"].to_arrow(), "")
    for src in carried_columns(sn, res):  # a plane file's own metres among them
        columns[src if src not in columns else f"{src}_src"] = table[src]
    out = pa.table(
        {k: pa.chunked_array([v]) if isinstance(v, pa.Array) else v for k, v in columns.items()}
    )
    # Drop every other reference to the parsed columns, so that the conversion below
    # (self_destruct) frees each column as it goes: the parsed table and the point
    # table never both exist in full (peak memory, bench/bench_memory.py).
    del columns, floats, time_col
    rows.table = table = None
    for t in text.values():
        t.arrow = None
    if not all_kept:
        out = out.filter(pa.array(keep))
    # One multi-threaded conversion; split_blocks avoids a 2-D consolidation copy.
    points = out.to_pandas(split_blocks=True, self_destruct=True)
    del out
    for name in (
        "sensor",
        "batch",
        "truth",
        *(c for c in points.columns if c not in _CANONICAL_SET),
    ):
        if name in points.columns and points[name].dtype != "str":
            points[name] = points[name].astype("str")
    if course_read is not None and np.isfinite(course_read[keep]).any():
        points[COURSE_READ] = course_read[keep]

    bad_idx = np.flatnonzero(bad_rows)
    bad_lines = rows.lines[bad_idx]
    q_lines = np.concatenate([bad_lines, np.asarray(bad.lines, dtype="int64")])
    q_reasons = [reason_names[c] for c in reasons[bad_idx]] + bad.reasons
    q_texts = (
        _raw_lines(sn, bad_lines, rows.encoding) if fetch_texts else [""] * len(bad_lines)
    ) + bad.texts
    if len(q_lines):
        order = np.argsort(q_lines, kind="stable")
        quarantine = pd.DataFrame(
            {
                "line": q_lines[order].astype("int64"),
                "reason": pd.Series(np.asarray(q_reasons, dtype=object)[order], dtype="str"),
                "text": pd.Series(np.asarray(q_texts, dtype=object)[order], dtype="str"),
            }
        )
    else:
        quarantine = empty_quarantine()

    sensor_text = text.get("sensor")
    sensor_codes = None if sensor_text is None else sensor_text.codes
    sensor_names = np.asarray([sensor], dtype=object) if sensor_text is None else sensor_text.names
    by_reason = quarantine["reason"].value_counts().to_dict() if len(quarantine) else {}
    _coarse_times(sensor_codes, text["batch"].codes, ns, time_ok & ~bad_rows, counted)
    counts = {
        "rows_read": int(n - int(blank.sum()) + len(bad.lines)),
        "rows_imported": int(len(points)),
        "rows_quarantined": int(len(quarantine)),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": int(blank.sum()) + bad.blank,
        "values_blanked": blanked,
        "lat_beyond_90_lon_within": swapped,
        "decimal_comma_values": int(counted.get("decimal_comma", 0)),
        "repeated_rows": int(repeat.sum()),
        # before _steps_back, which moves the carried last times on to this piece's
        "restarting_tracks": _restarting_tracks(
            sensor_codes,
            sensor_names,
            text["batch"].codes,
            text["batch"].names,
            ns,
            time_ok & ~bad_rows & ~repeat,
            None if edges_in is None else edges_in.get("back"),
        ),
        "time_steps_back": _steps_back(
            sensor_codes,
            sensor_names,
            text["batch"].codes,
            text["batch"].names,
            ns,
            time_ok & ~bad_rows & ~repeat,
            rows.lines,
            None if edges_in is None else edges_in.get("back"),
        ),
        **_count_tracks(
            sensor_codes,
            sensor_names,
            text["batch"].codes,
            len(text["batch"].names),
            None if all_kept else keep,
        ),
        "time_start": points["time"].min().isoformat() if len(points) else None,
        "time_end": points["time"].max().isoformat() if len(points) else None,
    }
    return points, quarantine, counts


_CANONICAL_SET = frozenset(("sensor", "batch", "time", "lon", "lat", "speed", "course", "truth"))


#: A track whose time jumps back by at least this much (s) in file order, a few times,
#: holds several runs: passes or ships that share one id.
RESTART_BACK_S = 600.0


def _coarse_times(
    sensor_codes: np.ndarray | None,
    batch_codes: np.ndarray,
    ns: np.ndarray,
    ok: np.ndarray,
    counted: dict,
) -> None:
    """Whether every time is a whole minute (or hour), and how many rows then share
    their minute with their track's row before: a file whose seconds were lost (Excel's
    m/d/yyyy h:mm cells) while its tracks report several times a minute. Counted in
    ``counted``: ``times_fine`` / ``times_sub_hour`` (some time is not a whole minute /
    hour) and ``coarse_shared``."""
    use = np.flatnonzero(ok & (batch_codes >= 0))
    if not len(use):
        return
    t = np.asarray(ns)[use].astype("int64", copy=False)
    fine = bool((t % 60_000_000_000).any())
    counted["times_fine"] = bool(counted.get("times_fine")) or fine
    counted["times_sub_hour"] = bool(counted.get("times_sub_hour")) or bool(
        (t % 3_600_000_000_000).any()
    )
    if counted["times_fine"] or len(use) < 2:
        return
    key = batch_codes[use].astype("int64")
    if sensor_codes is not None:
        key = sensor_codes[use].astype("int64") * (int(batch_codes.max()) + 1) + key
    order = np.lexsort((t, key))
    k, t = key[order], t[order]
    shared = int(((k[1:] == k[:-1]) & (t[1:] == t[:-1])).sum())
    counted["coarse_shared"] = counted.get("coarse_shared", 0) + shared


#: The start of the warning of :func:`cut_short_warnings` (a read in pieces says it once,
#: from the whole file's quarantine).
CUT_SHORT_MARK = ", the file's last line, has "


def _coarse_time_warnings(time_src: str, time_info: dict) -> list[str]:
    """A file whose times are whole minutes (hours) while its tracks report more often:
    were the seconds lost? (Operator test 4: Excel en-US saves m/d/yyyy h:mm.)"""
    shared = int(time_info.get("coarse_shared", 0) or 0)
    if time_info.get("times_fine") or not shared:
        return []
    unit = "minute" if time_info.get("times_sub_hour") else "hour"
    return [
        f"the times in {time_src!r} are whole {unit}s and {shared:,} rows share a {unit} "
        f"with their track's row before: were the seconds lost (Excel saves m/d/yyyy h:mm)? "
        "Export the file again with seconds; clean keeps only the first row of each time"
    ]


def _track_names(
    key: np.ndarray,
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
) -> np.ndarray:
    """The names of the tracks ``key`` (``sensor_code * n_batch + batch_code``) as the
    import's reports name them: the batch where the file has no sensor column, else
    ``sensor:batch`` (two sensors' tracks may share a batch name)."""
    n_batch = int(batch_codes.max()) + 1
    b = np.asarray(batch_names, dtype=object)[key % n_batch].astype(str)
    if sensor_codes is None:
        return b.astype(object)
    s = np.asarray(sensor_names, dtype=object)[key // n_batch].astype(str)
    return np.char.add(np.char.add(s, ":"), b).astype(object)


def _restarting_tracks(
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
    ns: np.ndarray,
    ok: np.ndarray,
    carry: "LastTimes | None" = None,
) -> dict[str, int]:
    """Tracks whose rows, in file order, run forward in time and then start again
    (backward by at least :data:`RESTART_BACK_S`, on at most a tenth of their steps: a
    shuffled file is not meant): track name (:func:`_track_names`) → runs. Several
    encounters of one ship or several ships under one id, which sorting by time would
    interleave into a zig-zag. A piece of a file read streamed or in pieces gives
    ``carry`` (:func:`_steps_back`'s, read here before that moves it on): a track's first
    row here steps from its last time in the pieces before, so a restart on a piece's
    first row is seen (a file of two exports cut between them). This is the piece's own
    count (its report's); the file's is :meth:`LastTimes.judged`, over every piece."""
    use = np.flatnonzero(ok & (batch_codes >= 0))
    if len(use) < (1 if carry is not None and len(carry) else 3):
        return {}
    key = batch_codes[use].astype("int64")
    if sensor_codes is not None:
        key = sensor_codes[use].astype("int64") * (int(batch_codes.max()) + 1) + key
    t = ns[use].astype("int64", copy=False)
    carried = carry is not None and len(carry) > 0
    if not carried and np.all(t[1:] >= t[:-1]):  # a time-ordered file: no track can go back
        return {}
    if np.all(key[1:] >= key[:-1]):  # grouped by track already
        k = key
    else:
        from wakeline.core.tracks import _stable_code_order

        sort = _stable_code_order(key)  # radix passes: linear; each track in file order
        if sort is None:
            sort = np.argsort(key, kind="stable")
        k, t = key[sort], t[sort]
    # each row's step from its track's row before; a track's first row here steps from
    # its carried last time, if any
    same = np.r_[False, k[1:] == k[:-1]]
    prev = np.r_[t[:1], t[:-1]]
    if carried:
        first = np.flatnonzero(~same)
        before, seen = carry.lookup(
            _carried_keys(k[first], sensor_codes, sensor_names, batch_codes, batch_names)
        )
        prev[first[seen]] = before[seen]
        same[first[seen]] = True
    back = same & (t < prev - int(RESTART_BACK_S * 1e9))
    if not back.any():
        return {}
    steps = np.bincount(k[same], minlength=int(k.max()) + 1)
    backs = np.bincount(k[back], minlength=int(k.max()) + 1)
    # each run going forward: any step back (beyond jitter) is one of the few restarts; a
    # short track in random order has steps back of every size, few of them 10 min long
    loose = same & (t < prev - int(ORDER_JITTER_S * 1e9))
    loose_n = np.bincount(k[loose], minlength=int(k.max()) + 1)
    hit = np.flatnonzero((backs > 0) & (loose_n <= 0.1 * steps))
    names = _track_names(hit, sensor_codes, sensor_names, batch_codes, batch_names)
    return {str(name): int(backs[h]) + 1 for name, h in zip(names, hit, strict=True)}


#: In the warning of :func:`_back_warnings` (a read in pieces says it again from the
#: summed counts).
BACK_MARK = " back within a track ("
#: Line numbers of steps back kept (and named in the warning).
BACK_FIRST_LINES = 5


class LastTimes:
    """What a streamed read or a read in pieces carries from piece to piece for
    :func:`_steps_back` and :func:`_restarting_tracks`: each track's last valid time (ns)
    in file order, so that a step back or a restart on a piece's first row of a track is
    seen, and each track's steps counted over the pieces, judged at the end as a whole
    read judges them (:meth:`judged`). Keyed ``sensor\x1fbatch``; one row per track in
    arrays, found by the keys' index."""

    #: The counts :meth:`add` sums per track over the pieces: steps (rows after a track's
    #: first), loose (steps back beyond the jitter), restarts, backs (the steps back
    #: warned of), and the largest step back warned of (s; its maximum, not a sum).
    COUNTS = ("steps", "loose", "restarts", "backs", "max_s")

    def __init__(self) -> None:
        self.keys = pd.Index([], dtype=object)
        self.last = np.zeros(0, dtype="int64")
        self.seen = np.zeros(0, dtype=bool)  # whether a last time was given (update)
        self.counts = np.zeros((0, len(self.COUNTS)))  # per track (add)
        self.names = np.zeros(0, dtype=object)  # each track's name as the reports give it
        self.kept = np.zeros(0, dtype="int64")  # each track's lines kept in ``lines``
        self.lines: list[tuple[np.ndarray, np.ndarray]] = []  # (track rows, lines) of backs
        #: Added to a piece's line numbers (a read in pieces: the line its piece starts on - 1).
        self.line_offset = 0
        #: Each track's latest time so far, and the hashes of the rows of the pieces before,
        #: in sorted chunks (:func:`_repeated_rows`).
        self.max_t = np.zeros(0, dtype="int64")
        self.row_hashes: list[np.ndarray] = []

    def __len__(self) -> int:
        return int(self.seen.sum())

    def _rows(self, keys: np.ndarray, grow: bool) -> np.ndarray:
        """Each key's row (-1 where unknown, unless ``grow`` adds it)."""
        keys = pd.Index(keys, dtype=object)
        at = self.keys.get_indexer(keys) if len(self.keys) else np.full(len(keys), -1)
        if grow and (at < 0).any():
            fresh = keys[at < 0]
            at[at < 0] = len(self.keys) + np.arange(len(fresh))
            self.keys = self.keys.append(fresh)
            n = len(fresh)
            self.last = np.r_[self.last, np.zeros(n, dtype="int64")]
            self.seen = np.r_[self.seen, np.zeros(n, dtype=bool)]
            self.counts = np.vstack([self.counts, np.zeros((n, len(self.COUNTS)))])
            self.names = np.r_[self.names, np.asarray(fresh, dtype=object)]
            self.kept = np.r_[self.kept, np.zeros(n, dtype="int64")]
            self.max_t = np.r_[self.max_t, np.full(n, np.iinfo("int64").min, dtype="int64")]
        return at

    def lookup(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(carried last time, whether carried) for each key."""
        at = self._rows(keys, grow=False)
        seen = at >= 0
        seen[seen] = self.seen[at[seen]]
        got = np.zeros(len(keys), dtype="int64")
        got[seen] = self.last[at[seen]]
        return got, seen

    def update(self, keys: np.ndarray, last: np.ndarray) -> None:
        at = self._rows(keys, grow=True)
        self.last[at] = np.asarray(last, dtype="int64")
        self.seen[at] = True

    def add(self, keys, names, counts: dict, back_keys, back_lines) -> None:
        """A piece's counts per track (``keys`` as :meth:`lookup`'s, ``names`` as the
        reports name them) and the file lines of its steps back (``back_keys``: their
        tracks), for :meth:`judged`."""
        at = self._rows(keys, grow=True)
        self.names[at] = np.asarray(names, dtype=object)
        for j, name in enumerate(self.COUNTS):
            values = np.asarray(counts[name], dtype="float64")
            if name == "max_s":
                self.counts[at, j] = np.fmax(self.counts[at, j], values)
            else:
                self.counts[at, j] += values
        if len(back_lines):  # a track's first few lines are all a judgement names
            rows = self._rows(back_keys, grow=False)
            rank = pd.Series(rows).groupby(rows, sort=False).cumcount().to_numpy()
            keep = rank + self.kept[rows] < BACK_FIRST_LINES
            np.add.at(self.kept, rows[keep], 1)
            self.lines.append((rows[keep], np.asarray(back_lines, dtype="int64")[keep]))

    def judged(self) -> tuple[dict[str, int], dict]:
        """``(restarting_tracks, time_steps_back)`` over every piece added, as
        :func:`_restarting_tracks` and :func:`_steps_back` judge a whole file: a track
        counts where at most a tenth of its steps (over the file) go back beyond the
        jitter."""
        steps, loose, restarts, backs, max_s = self.counts.T
        forward = loose <= 0.1 * steps
        restart = np.flatnonzero(forward & (restarts > 0))
        restarting = {str(self.names[k]): int(restarts[k]) + 1 for k in restart}
        hit = forward & (backs > 0)
        if not hit.any():
            return restarting, {}
        rows = np.concatenate([r for r, _ in self.lines]) if self.lines else np.zeros(0, int)
        lines = np.concatenate([x for _, x in self.lines]) if self.lines else np.zeros(0, int)
        lines = np.sort(lines[hit[rows]])[:BACK_FIRST_LINES]
        back = {
            "tracks": {str(self.names[k]): int(backs[k]) for k in np.flatnonzero(hit)},
            "first_lines": [int(x) for x in lines],
            "max_s": float(max_s[hit].max()),
        }
        return restarting, back


def _carried_keys(
    key: np.ndarray,
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
) -> np.ndarray:
    """:class:`LastTimes`' keys (``sensor\x1fbatch``) of the tracks ``key`` (``sensor_code
    * n_batch + batch_code``): the same track in every piece, whatever its codes there."""
    names = _track_names(key, None, sensor_names, batch_codes, batch_names)
    n_batch = int(batch_codes.max()) + 1
    sensors = np.asarray(sensor_names, dtype=object)[
        key // n_batch if sensor_codes is not None else np.zeros(len(key), "int64")
    ].astype(str)
    return np.char.add(np.char.add(sensors, "\x1f"), names.astype(str))


def _steps_back(
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
    ns: np.ndarray,
    ok: np.ndarray,
    lines: np.ndarray,
    carry: LastTimes | None = None,
) -> dict:
    """Steps back in time within a track, in file order (operator test 7, D3: a clock set
    back 10 min in 20 rows of a track; the import said nothing, clean then kept a 282 kn
    leg): a row whose time lies more than :data:`ORDER_JITTER_S` and less than
    :data:`RESTART_BACK_S` (a restart, warned of apart) before its track's row before,
    in tracks that otherwise run forward (at most a tenth of their steps go back beyond
    the jitter: a file in no time order is not meant). ``{"tracks": {track: steps},
    "first_lines": [line, …], "max_s": largest step back}`` (tracks named by
    :func:`_track_names`); {} when none. A piece of a file read streamed or in pieces
    gives ``carry``: each track's last time in the pieces before (its first row here
    steps from it), updated with this piece's."""
    use = np.flatnonzero(ok & (batch_codes >= 0))
    if not len(use):
        return {}
    t = ns[use].astype("int64", copy=False)
    if carry is None and np.all(t[1:] >= t[:-1]):  # a time-ordered file: none goes back
        return {}
    key = batch_codes[use].astype("int64")
    if sensor_codes is not None:
        key = sensor_codes[use].astype("int64") * (int(batch_codes.max()) + 1) + key
    line = np.asarray(lines)[use]
    if not np.all(key[1:] >= key[:-1]):
        from wakeline.core.tracks import _stable_code_order

        sort = _stable_code_order(key)  # radix passes: linear; each track in file order
        if sort is None:
            sort = np.argsort(key, kind="stable")
        key, t, line = key[sort], t[sort], line[sort]
    # each row's step from its track's row before (> 0: back); a track's first row here
    # steps from its carried last time, if any
    same = np.r_[False, key[1:] == key[:-1]]
    prev = np.r_[t[:1], t[:-1]]
    if carry is not None:
        first = np.flatnonzero(~same)
        last = np.r_[first[1:] - 1, len(key) - 1]
        carried_keys = _carried_keys(
            key[first], sensor_codes, sensor_names, batch_codes, batch_names
        )
        before, seen = carry.lookup(carried_keys)
        prev[first[seen]] = before[seen]
        same[first[seen]] = True
        carry.update(carried_keys, t[last])
    step = prev - t
    if carry is not None:  # the file's counts, judged over all the pieces (LastTimes.judged)
        _carry_counts(
            carry,
            carried_keys,
            first,
            key,
            same,
            step,
            line,
            sensor_codes,
            sensor_names,
            batch_codes,
            batch_names,
        )
    loose = same & (step > int(ORDER_JITTER_S * 1e9))
    if not loose.any():
        return {}
    back = loose & (step < int(RESTART_BACK_S * 1e9))
    n_keys = int(key.max()) + 1
    steps = np.bincount(key[same], minlength=n_keys)
    loose_n = np.bincount(key[loose], minlength=n_keys)
    forward = loose_n <= 0.1 * steps
    back &= forward[key]
    if not back.any():
        return {}
    backs = np.bincount(key[back], minlength=n_keys)
    hit = np.flatnonzero(backs)
    names = _track_names(hit, sensor_codes, sensor_names, batch_codes, batch_names)
    return {
        "tracks": {str(name): int(backs[h]) for name, h in zip(names, hit, strict=True)},
        "first_lines": sorted(int(x) for x in line[back])[:BACK_FIRST_LINES],
        "max_s": float(step[back].max()) / 1e9,
    }


def _carry_counts(
    carry: LastTimes,
    carried_keys: np.ndarray,
    first: np.ndarray,
    key: np.ndarray,
    same: np.ndarray,
    step: np.ndarray,
    line: np.ndarray,
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    batch_names: np.ndarray,
) -> None:
    """A piece's steps per track (rows sorted by track, ``first``: each track's first row)
    added to ``carry``'s counts, with the file lines of its steps back (the piece's
    lines + ``carry.line_offset``)."""
    starts = np.zeros(len(key), dtype=bool)
    starts[first] = True
    track = np.cumsum(starts) - 1  # each row's track in this piece
    n = len(first)
    jitter, restart = int(ORDER_JITTER_S * 1e9), int(RESTART_BACK_S * 1e9)
    loose = same & (step > jitter)
    back = loose & (step < restart)
    max_s = np.zeros(n)
    if back.any():
        np.maximum.at(max_s, track[back], step[back] / 1e9)
    counts = {
        "steps": np.bincount(track[same], minlength=n),
        "loose": np.bincount(track[loose], minlength=n),
        "restarts": np.bincount(track[same & (step > restart)], minlength=n),
        "backs": np.bincount(track[back], minlength=n),
        "max_s": max_s,
    }
    names = _track_names(key[first], sensor_codes, sensor_names, batch_codes, batch_names)
    offset = int(carry.line_offset)
    carry.add(carried_keys, names, counts, carried_keys[track[back]], line[back] + offset)


def merge_steps_back(infos: list[tuple[dict, int]]) -> dict:
    """One :func:`_steps_back` of the pieces' (each with the file line its piece starts
    on, 1-based, its lines the piece's): steps summed per track, lines made file lines."""
    out: dict = {}
    for info, first_line in infos:
        if not info:
            continue
        tracks = out.setdefault("tracks", {})
        for k, v in info.get("tracks", {}).items():
            tracks[k] = tracks.get(k, 0) + int(v)
        out["first_lines"] = sorted(
            out.get("first_lines", []) + [x + first_line - 1 for x in info.get("first_lines", [])]
        )[:BACK_FIRST_LINES]
        out["max_s"] = max(out.get("max_s", 0.0), float(info.get("max_s", 0.0)))
    return out


def _back_warnings(info: dict, time_src: str, batch_src: str) -> list[str]:
    """The warning for :func:`_steps_back`'s count: how many steps back, in how many
    tracks, the lines and the largest."""
    tracks = info.get("tracks") if info else None
    if not tracks:
        return []
    n = sum(tracks.values())
    first = info.get("first_lines", [])
    some = ", ".join(f"{k:,}" for k in first) + (", …" if n > len(first) else "")
    name, most = max(tracks.items(), key=lambda kv: kv[1])
    steps = "time step goes" if n == 1 else "time steps go"
    return [
        f"{n:,} {steps} back within a track ({len(tracks):,} track(s); the most in batch "
        f"{name}: {most:,}; line{'s' if len(first) != 1 else ''} {some}; the largest "
        f"{info.get('max_s', 0.0):,.0f} s): a clock set back, or rows out of order? Each "
        f"track is sorted by its time ({time_src!r}), so a clock set back puts those rows "
        f"among the earlier ones (a jump in speed that clean reports as a break); check "
        f"the times of those rows in {batch_src!r}"
    ]


def _count_tracks(
    sensor_codes: np.ndarray | None,
    sensor_names: np.ndarray,
    batch_codes: np.ndarray,
    n_batches: int,
    keep: np.ndarray | None,
) -> dict:
    """Tracks in all, and points per sensor, from the integer codes (one bincount)."""
    if keep is not None:
        batch_codes = batch_codes[keep]
        sensor_codes = None if sensor_codes is None else sensor_codes[keep]
    if len(batch_codes) == 0:
        return {"tracks": 0, "sensors": {}}
    n_sensors = len(sensor_names)
    if sensor_codes is None or n_sensors == 1:
        key = batch_codes
    else:
        dtype = "int32" if n_sensors * n_batches < 2**31 else "int64"
        key = sensor_codes.astype(dtype) * n_batches + batch_codes
    n_keys = n_sensors * n_batches
    if n_keys <= 4 * len(key) + 1024:
        per_key = np.bincount(key, minlength=n_keys).reshape(n_sensors, n_batches)
        tracks = int(np.count_nonzero(per_key))
        per_sensor = per_key.sum(axis=1)
    else:
        uniq = sorted_sets.distinct(key)
        tracks = len(uniq)
        per_sensor = np.bincount(sensor_codes, minlength=n_sensors)
    return {
        "tracks": tracks,
        "sensors": {str(s): int(c) for s, c in zip(sensor_names, per_sensor, strict=True) if c},
    }


@_names_read_errors
def inspect_file(
    path: str | Path,
    fmt: str = "auto",
    mapping: dict[str, str] | list[str] | None = None,
    encoding: str | None = None,
    delimiter: str | None = None,
    skip_rows: int | None = None,
    origin: str | tuple[float, float] | None = None,
) -> dict:
    """What an import of ``path`` would use, from its first 256 KiB (for the import dialog);
    ``skip_rows``: lines before the header, ``origin``: a local plane's (lat, lon), as
    :func:`read_points` takes them (None: detected; none). ``plane``: the positions are
    east/north metres (an ``origin`` is needed).

    Returns a plain dict: ``kind`` (csv or nmea), ``columns`` (the file's header names, in
    order), ``mapping`` (canonical field → column, as detected or as ``mapping`` forces
    it), ``extra`` (columns no field takes: carried as extra columns), ``format`` and
    ``format_label``, ``encoding``, ``delimiter``, ``header``, ``preview`` (first rows as
    lists of cells), ``local_time`` (the time column's name says local time),
    ``guessed`` (a file without a header: the columns chosen by the values of its first
    rows, :func:`content_guess`, and whether the lon/lat order showed in them),
    ``problem`` (why an import would fail, or None), ``missing`` (the required fields
    still without a column when no layout fits; the fields the synonyms recognise are in
    ``mapping`` all the same) and ``clock_only`` (the time column's name when its first
    rows are times of day without a date and no date column stands beside it: the import
    needs ``--date`` for their day; else None). Raises :class:`InputError` only when
    the file cannot be read at all (missing, empty, binary, undecodable)."""
    if isinstance(mapping, list):
        mapping = parse_mapping(mapping)
    sn = sniff(path, encoding, delimiter, skip_rows)
    out: dict = {
        "kind": sn.kind,
        "columns": list(sn.columns),
        "mapping": {},
        "extra": [],
        "format": {"nmea": "ais-nmea", "gpx": "gpx", "geojson": "geojson"}.get(sn.kind),
        "format_label": {
            "nmea": "Raw AIS NMEA log (!AIVDM/!AIVDO)",
            "gpx": "GPX tracks",
            "geojson": "GeoJSON tracks",
        }.get(sn.kind),
        "encoding": sn.encoding,
        "delimiter": sn.delimiter,
        "header": sn.has_header,
        "lines_above_header": _title_report(sn),
        "preview": [list(r) for r in sn.preview],
        "local_time": False,
        "problem": None,
        "missing": [],
        "plane": False,
        "clock_only": None,
    }
    if sn.kind != "csv":  # NMEA, GPX: no columns to map
        return out
    guess, sure = content_guess(sn) if not sn.has_header and not mapping else ({}, False)
    try:
        res = resolve_header(sn, fmt, guess or mapping, str(path), origin)
        if guess:  # no header: the columns chosen by their values, for the operator to check
            out["guessed"] = {"mapping": dict(guess), "lon_lat_seen": sure}
    except InputError as exc:
        out["problem"] = str(exc)
        # No layout fits: still every field the synonyms recognise, and what is missing.
        out["mapping"], out["missing"] = guess_columns(sn.columns, mapping)
        out["plane"] = plane_kind(out["mapping"]) is not None
        if out["missing"] == ["batch"]:  # the import names the one track after the file
            out["missing"] = []
            out["mapping"]["batch"] = FILE_BATCH
    else:
        out["plane"] = res.on_plane
        out["format"], out["format_label"] = res.format.name, res.format.label
        out["mapping"] = res.mapping  # a GPS time as gps_week/gps_seconds
        if "batch" not in res.columns:
            out["mapping"]["batch"] = FILE_BATCH
    used = set(out["mapping"].values())
    out["extra"] = [c for c in sn.columns if c not in used]
    time_col = out["mapping"].get("time")
    out["local_time"] = bool(time_col) and header_is_local(time_col)
    if time_col in sn.columns and date_column(sn.columns, set(out["mapping"].values())) is None:
        at = list(sn.columns).index(time_col)
        cells = pd.Series([r[at] for r in sn.preview if len(r) > at], dtype="str").str.strip()
        cells = cells[cells != ""]
        if len(cells) and is_clock(cells).all():
            out["clock_only"] = time_col
    return out


class StreamFallback(Exception):
    """The streamed import met something only the whole-file reader handles."""


class WholeFileNeeded(StreamFallback):
    """... and that no reading in pieces handles either: rows whose reading depends on
    rows anywhere else in the file (a clock change's repeated hour: a track's two passes
    may lie in two pieces)."""


_Fallback = StreamFallback


#: Bytes of whole lines parsed, converted and written at a time by :func:`import_to_csv`.
STREAM_BYTES = 16 << 20


@_names_read_errors
def import_to_csv(
    path: str | Path,
    output: str | Path,
    fmt: str = "auto",
    mapping: dict[str, str] | list[str] | None = None,
    encoding: str | None = None,
    delimiter: str | None = None,
    sensor: str = DEFAULT_SENSOR,
    tz: str | None = None,
    progress: Progress | None = None,
    skip_rows: int | None = None,
    origin: str | tuple[float, float] | None = None,
    date_order: str = "auto",
    time_unit: str = "auto",
    clock_date: str | None = None,
    speed_unit: str = "auto",
    distance_unit: str = "auto",
) -> ImportResult:
    """Import ``path`` and write the canonical CSV ``output`` batch by batch, never
    holding the whole table: memory stays about one piece of ``STREAM_BYTES`` of the file.

    The result has the quarantine, report and layout of :func:`read_points` but no points
    (an empty table). Files the streamed reader does not take (a value only the careful
    parse reads, quotes, another encoding further on) are read piece by piece by the
    importer (:func:`~wakeline.core.io.pieces.read_in_pieces`); what needs the whole file
    (a clock change's repeated hour, NMEA, UTF-16) with :func:`read_points`. The output
    is the same either way, byte for byte (quoting decided over the whole table).
    """
    from wakeline.core.io.pieces import stream_or_pieces
    from wakeline.core.io.writer import PointParts, atomic_path, write_points

    path, output = Path(path), Path(output)
    if isinstance(mapping, list):
        mapping = parse_mapping(mapping)
    parse_zone(tz)  # a zone it does not know is refused before anything is read
    values = ValueOptions(date_order, time_unit, clock_date, speed_unit, distance_unit)
    read = {
        "fmt": fmt,
        "mapping": mapping,
        "sensor": sensor,
        "tz": tz,
        "origin": origin,
        **values.checked().keywords(),
    }
    sn = sniff(path, encoding, delimiter, skip_rows)

    def whole(target: Path) -> ImportResult:
        result = read_points(
            path,
            encoding=encoding,
            delimiter=delimiter,
            progress=progress,
            skip_rows=skip_rows,
            **read,
        )
        write_points(result.points, target)
        return ImportResult(result.points.iloc[:0], result.quarantine, result.report, result.layout)

    if sn.kind != "csv":  # NMEA logs, GPX, GeoJSON
        return whole(output)
    res = resolve_header(sn, fmt, mapping, str(path), origin)
    progress = progress or null_progress
    # Each part's Arrow copy in the system's temporary folder (nothing of ours is left
    # beside the output).
    scratch = Path(tempfile.mkdtemp(prefix="wakeline-import-"))
    try:
        with atomic_path(output) as tmp:
            parts = PointParts(scratch / "parts", tmp)
            try:
                result = stream_or_pieces(
                    sn, res, read, parts, parts.reset, scratch / "pieces", progress
                )
            finally:
                parts.close()
            if result is None:  # what only a whole read gives
                parts.reset()
                return whole(tmp)
            parts.finish(result.report.get("extra_columns") or ())
            if "target" in (result.report.get("extra_columns") or ()):
                result.report["warnings"] += _written_targets_note(tmp)
            return result
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def _written_targets_note(csv_path: Path) -> list[str]:
    """:func:`~wakeline.core.io.geojson.targets_note` of a canonical CSV just written
    (its sensor, batch and target columns read back: the streamed import holds no
    points)."""
    from pyarrow import csv as pacsv

    from wakeline.core.io.geojson import targets_note

    names = ["sensor", "batch", "target"]
    opts = pacsv.ConvertOptions(
        include_columns=names, column_types=dict.fromkeys(names, pa.string())
    )
    table = pacsv.read_csv(csv_path, convert_options=opts)
    return targets_note(table.to_pandas(), csv=True)


def last_line_end(buf: bytes) -> int:
    """Index of the last line end of ``buf`` (``\\n``, or ``\\r`` in a file of old Mac
    line ends); -1 when there is none."""
    cut = buf.rfind(b"\n")
    return buf.rfind(b"\r") if cut < 0 else cut


def line_pieces(
    stream, size: int | None = None, cut: Callable[[bytes], int] = last_line_end
) -> Iterator[tuple[bytes, int]]:
    """A binary stream in pieces of whole lines (about ``size`` bytes each, default
    :data:`STREAM_BYTES`; the last as it ends), each with the physical line (1-based) it
    starts on. ``cut(buf)``: the index of the line end a piece ends on (-1: read on), e.g.
    one outside quotes."""
    size = size or STREAM_BYTES
    carry, first_line = b"", 1
    while True:
        data = bytes(stream.read(size))
        buf = carry + data
        if data:
            end = cut(buf)
            if end < 0:
                carry = buf
                continue
            piece, carry = buf[: end + 1], buf[end + 1 :]
        else:
            piece, carry = buf, b""
        if piece:
            yield piece, first_line
        first_line += piece.count(b"\n") + piece.count(b"\r") - piece.count(b"\r\n")
        if not data:
            return


def stream_points(
    sn: Sniff,
    res: Resolved,
    sink: Callable[[pd.DataFrame], None],
    sensor: str = DEFAULT_SENSOR,
    zone: datetime.tzinfo | None = None,
    tz: str | None = None,
    progress: Progress | None = None,
    date_order: str = "auto",
    time_unit: str = "auto",
    clock_date: str | None = None,
    speed_unit: str = "auto",
    distance_unit: str = "auto",
) -> ImportResult:
    """Read a CSV without quotes in its sampled start piece by piece (``STREAM_BYTES`` of
    whole lines at a time) and hand each piece's canonical points, in file order, to
    ``sink``; memory stays about one piece. Returns the quarantine, report and layout of
    :func:`read_points` (points empty). Raises :class:`StreamFallback` when the file needs the
    whole-file reader (a value that does not convert, another encoding, no points)."""
    from wakeline.core.io.grid import GridSeen, grid_warning
    from wakeline.core.io.tables import header_line

    progress = progress or null_progress
    values = ValueOptions(date_order, time_unit, clock_date, speed_unit, distance_unit).checked()
    clock_date = values.clock_date
    res = dataclasses.replace(res, speed_unit=speed_unit, distance_unit=distance_unit)
    bad = _BadRows()  # every refused or blank line of the file, numbered in the file
    types = _column_types(sn, res, careful=False)
    file_batch = "batch" not in res.columns
    if file_batch:
        res = dataclasses.replace(res, columns={**res.columns, "batch": FILE_BATCH})
    totals: dict = {
        "rows_read": 0,
        "rows_imported": 0,
        "blank_lines": 0,
        "lat_beyond_90_lon_within": 0,
        "repeated_rows": 0,
    }
    blanked: dict[str, int] = {}
    pairs: set[tuple[str, str]] = set()
    checked: list[pd.DataFrame] = []  # the rows the speed-unit check looks at
    per_sensor: dict[str, int] = {}
    quarantines: list[pd.DataFrame] = []
    starts, ends = [], []
    time_info: dict = {}
    grid = GridSeen()  # the positions' grid over the pieces (grid.py)
    edges = edge_state()
    size = max(sn.path.stat().st_size, 1)
    consumed = [0]
    # switch: an ASCII start read as UTF-8 goes on as GB18030 where the whole file's
    # judgement says so (h179), reported below as the whole-file reader reports it.
    opened = _open_parsed(sn, sn.encoding, strict_mode(sn), switch=True)
    line_decoder = getattr(getattr(opened, "_stream", opened), "decoder", None)

    def text_encoding() -> str:
        """The encoding the text is read in (so far): the file's start's, or GB18030."""
        return line_decoder.encoding if line_decoder is not None else sn.encoding

    # How far through the file on disk (a compressed file's text is larger than it).
    done = getattr(opened, "fraction", lambda: consumed[0] / size)

    def parse(piece: bytes, skip: int, first_line: int) -> tuple[pa.Table, np.ndarray]:
        """One piece of whole lines: the table and the file line of each row; refused
        and blank lines go to ``bad`` with their file line numbers."""
        for threads in (True, False):  # numbered refused rows need a single thread
            local = _BadRows()
            table = pacsv.read_csv(
                pa.BufferReader(piece),
                read_options=pacsv.ReadOptions(
                    column_names=list(sn.columns),
                    skip_rows=skip,
                    use_threads=threads,
                    block_size=max(1 << 20, len(piece) // 2 + 1),
                ),
                parse_options=pacsv.ParseOptions(
                    delimiter=sn.parse_delimiter,
                    quote_char=False,
                    invalid_row_handler=local.handler,
                    ignore_empty_lines=False,
                ),
                convert_options=pacsv.ConvertOptions(column_types=types, strings_can_be_null=False),
            )
            if not local.unnumbered:
                break
        offset = first_line - 1
        if local.lines and header_line(local.texts, sn.parse_delimiter, list(sn.columns)):
            raise WholeFileNeeded  # a second table's header (tables.py): read whole
        bad.lines += [n + offset for n in local.lines]
        bad.reasons += local.reasons
        # a blank-aligned file's lines as parsed are not its lines: fetched from the file
        bad.texts += [""] * len(local.texts) if sn.blank_runs else local.texts
        bad.blank += local.blank
        bad.blank_lines += [n + offset for n in local.blank_lines]
        skipped = sorted(local.lines + local.blank_lines)
        return table, _line_numbers(np.arange(table.num_rows), skip, skipped) + offset

    def flush(table: pa.Table, lines: np.ndarray, final: bool) -> None:
        n = table.num_rows
        if file_batch:
            name = sn.path.name.split(".")[0] or "1"
            table = table.append_column(
                FILE_BATCH, pa.repeat(pa.scalar(name), n).dictionary_encode()
            )
        rows = _Rows(table, lines, _BadRows(), False, text_encoding(), False, False, [])
        del table
        info: dict = {
            "absolute": time_info.get("absolute", False),
            **({"_unit": time_info["_unit"]} if "_unit" in time_info else {}),
            "_streaming": True,
            "_edges": {**edges, "final": final},
            "_by_table": True,  # zoned and zone-less times counted over the pieces
        }
        points, quarantine, counts = _to_canonical(
            rows,
            sn,
            res,
            sensor,
            zone,
            info,
            fetch_texts=False,
            date_order=date_order,
            time_unit=time_unit,
            clock_date=clock_date,
        )
        time_info["absolute"] = bool(info.get("absolute"))
        # The first piece of numeric times decides Excel days or seconds for the rest.
        numeric = str(info.get("time_format")).startswith(("unix", "relative", "Excel"))
        if "_unit" not in time_info and numeric:
            time_info["_unit"] = "excel-days" if info.get("excel_days") else "seconds"
        if info.get("excel_why"):
            time_info["excel_why"] = info["excel_why"]
        time_info.setdefault("time_format", info.get("time_format"))
        if info.get("date_column"):
            time_info["date_column"] = info["date_column"]
        if counts["rows_imported"]:  # pieces that read positions apart: one judgement
            time_info.setdefault("_ddmm", set()).add(
                (bool(info.get("ddmm")), info.get("ddmm_note"), info.get("letter_note"))
            )
            if len(time_info["_ddmm"]) > 1:
                raise _Fallback
        forms = time_info.setdefault("lettered_forms", {})
        for name, form in (info.get("lettered_forms") or {}).items():
            if forms.setdefault(name, form) != form:
                raise _Fallback  # ddmm.mmmm with letters in one piece, degrees in another
        for key in ("ddmm_note", "letter_note", "speed_unit", "speed_unit_refused"):
            if info.get(key):
                time_info[key] = info[key]
        for word, k in (info.get("zone_words") or {}).items():
            merged = time_info.setdefault("zone_words", {})
            merged[word] = merged.get(word, 0) + k
        time_info["naive"] = time_info.get("naive", False) or info.get("naive", False)
        if info.get("zoned_written"):
            time_info["zoned_written"] = True
        for key in ("_zoned_n", "_naive_n"):
            time_info[key] = time_info.get(key, 0) + info.get(key, 0)
        time_info["relative"] = time_info.get("relative", True) and info.get("relative", False)
        time_info["dayfirst_shown"] = time_info.get("dayfirst_shown") or info.get("dayfirst_shown")
        for key in info.keys() & {
            "month_first",
            "date_order_given",
            "time_unit_given",
            "clock_date_given",
        }:
            time_info[key] = info[key]
        for key in ("times_fine", "times_sub_hour"):
            time_info[key] = bool(time_info.get(key)) or bool(info.get(key))
        if info.get("decimal_comma_example"):
            time_info.setdefault("decimal_comma_example", info["decimal_comma_example"])
        for key in (
            "coarse_shared",
            "decimal_comma",
            "clock_placed",
            *POSITION_COUNTS,
            "other_form_times",
            "dates_either_way",
            "day_shown",
            "date_order_refused",
            "zoneless_times",
            "zoned_times",
            "excel_days",
            "excel_like",
        ):
            time_info[key] = time_info.get(key, 0) + info.get(key, 0)
        for key in totals:
            totals[key] += counts[key]
        for k, v in counts["values_blanked"].items():
            blanked[k] = blanked.get(k, 0) + v
        if len(quarantine):
            quarantines.append(quarantine)
        if len(points):
            for s, c in points["sensor"].value_counts().items():
                per_sensor[str(s)] = per_sensor.get(str(s), 0) + int(c)
            keys = points[["sensor", "batch"]].drop_duplicates()
            pairs.update(zip(keys["sensor"].astype(str), keys["batch"].astype(str), strict=True))
            starts.append(points["time"].min())
            ends.append(points["time"].max())
            grid.add(points["lon"].to_numpy(), points["lat"].to_numpy())
            _keep_for_unit_check(checked, points, res)
            sink(points)
        progress(min(0.95, done()), "importing")

    try:
        with opened as stream, _quiet_undecodable_rows():
            # Pieces of whole lines, parsed one at a time: memory stays one piece
            # (the streaming reader would read ahead as far as the file goes).
            skip = sn.skip_rows
            has_rows = blank_bytes(sn.parse_delimiter)
            for (piece, first_line), final in with_final(line_pieces(stream), has_rows):
                consumed[0] += len(piece)
                table, lines = parse(piece, skip, first_line)
                if table.num_rows:
                    flush(table, lines, final)
                del table, piece
                skip = 0
            if totals["rows_imported"] == 0:
                raise _Fallback  # nothing imported: let the whole-file path say why
            # Lines of a GB18030 file read as UTF-8: reported as the whole-file reader
            # reports them (the file is not decoded again; h157). Replaced bytes (their
            # rows quarantined) are the whole-file reader's.
            decoder = getattr(getattr(opened, "_stream", opened), "decoder", None)
            fallback = decoder.fallbacks.report() if decoder is not None else {}
            if decoder is not None and decoder.fallbacks.counts.get("replaced"):
                raise _Fallback
    except (pa.ArrowInvalid, UnicodeDecodeError) as exc:
        raise _Fallback from exc

    # Rows the parser refused (field counts), blank lines, and the texts of the rest.
    read_all = {
        "rows_read": totals["rows_read"] + len(bad.lines),
        "lat_beyond_90_lon_within": totals["lat_beyond_90_lon_within"],
    }
    if swapped_file(read_all) or edges["swapped"]:
        # judged over the whole file: its rows within range were handed on as points;
        # the whole-file reader quarantines every row of it, or of a sensor (track) (D2)
        raise WholeFileNeeded
    q = pd.concat(quarantines, ignore_index=True) if quarantines else empty_quarantine()
    if bad.lines:
        q = pd.concat(
            [
                q,
                pd.DataFrame(
                    {
                        "line": np.asarray(bad.lines, dtype="int64"),
                        "reason": pd.Series(bad.reasons, dtype="str"),
                        "text": pd.Series(bad.texts, dtype="str"),
                    }
                ),
            ],
            ignore_index=True,
        )
    q = q.sort_values("line", kind="stable", ignore_index=True)
    missing = (q["text"] == "").to_numpy()
    if missing.any():
        texts = q["text"].to_numpy(dtype=object)
        texts[missing] = _raw_lines(sn, q["line"].to_numpy()[missing], text_encoding())
        q["text"] = pd.Series(texts, dtype="str")
    by_reason = q["reason"].value_counts().to_dict() if len(q) else {}
    zoned, naive = time_info.pop("_zoned_n", 0), time_info.pop("_naive_n", 0)
    if zoned and naive:  # zoned and zone-less times in the file (any pieces)
        time_info["zoned_times"], time_info["zoneless_times"] = zoned, naive
    enc = text_encoding()
    warnings = [encoding_note(sn.encoding, enc)] if enc != codecs.lookup(sn.encoding).name else []
    warnings += fallback_warning(enc, fallback)
    warnings += bom_warnings(sn, enc)
    warnings += [no_batch_warning(sn, res.columns)] if file_batch else []
    warnings += res.notes
    warnings += _title_warnings(sn) + _blank_run_warnings(sn)
    warnings += _time_warnings(res.columns["time"], time_info, zone)
    warnings += zone_note(sn, res.columns["time"], time_info, zone)
    warnings += _coarse_time_warnings(res.columns["time"], time_info)
    # restarts and steps back judged over the whole file, each track's steps summed over
    # the pieces (a track's few rows in one piece do not make it a file in no time order)
    restarting, steps_back = edges["back"].judged()
    warnings += _repeat_warnings(totals["repeated_rows"])
    warnings += _restart_warnings(restarting, res.columns["batch"])
    warnings += _back_warnings(steps_back, res.columns["time"], res.columns["batch"])
    warnings += position_warnings(
        sn, res, totals["lat_beyond_90_lon_within"], totals["rows_read"] + len(bad.lines)
    )
    warnings += origin_warnings(res, sn.columns)
    warnings += bearing_warnings(res.columns, by_reason, totals["rows_read"] + len(bad.lines))
    warnings += cut_short_warnings(sn, q)
    if grid.decimals() is not None:
        warnings.append(grid_warning(grid.decimals(), grid.lat))
    warnings += _unit_check(pd.concat(checked, ignore_index=True) if checked else None, res)
    extra = carried_columns(sn, res)
    report: dict = {
        "input": str(sn.path),
        "format": res.format.name,
        "format_label": res.format.label,
        "encoding": plain_encoding(enc),
        "delimiter": sn.delimiter,
        "compression": sn.compression,
        "header": sn.has_header,
        "lines_above_header": _title_report(sn),
        # with the header, the lines above it, blank_lines, rows_read: every physical line
        "blank_lines_above_header": sn.blank_above_header,
        "excel_sep_line": int(sn.excel_sep),
        "skip_rows_given": sn.skip_rows_given,
        "columns": res.columns,
        "extra_columns": extra,
        "careful_parse": False,
        "streamed": True,
        **({"encoding_fallback": fallback} if fallback else {}),
        "time_format": time_info.get("time_format"),
        "time_date_column": time_info.get("date_column"),
        # GPS time: the week column ("" for GPS seconds since 1980), for export --like
        **({"time_gps_week": res.gps_week} if res.gps_week is not None else {}),
        "date_order": date_order_note(time_info),
        "time_unit": time_unit_note(time_info),
        **time_counts(time_info),
        **clock_report(time_info),
        "time_zone": tz if zone is not None else "UTC",
        **_file_offsets(sn, res.columns["time"], enc, {**time_info, "zoneless_times": naive}),
        "time_relative": bool(time_info.get("relative")),
        "plane_origin": list(res.origin) if res.on_plane else None,
        "rows_read": totals["rows_read"] + len(bad.lines),
        "rows_imported": totals["rows_imported"],
        "rows_quarantined": len(q),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": totals["blank_lines"] + bad.blank,
        "values_blanked": blanked,
        "decimal_comma_values": int(time_info.get("decimal_comma", 0)),
        # as the whole-file reader and the reader in pieces report it (review h209)
        "lat_beyond_90_lon_within": int(totals["lat_beyond_90_lon_within"]),
        "repeated_rows": int(totals["repeated_rows"]),
        "restarting_tracks": restarting,
        "time_steps_back": steps_back,
        "tracks": len(pairs),
        "sensors": per_sensor,
        "time_start": min(starts).isoformat() if starts else None,
        "time_end": max(ends).isoformat() if ends else None,
        "warnings": warnings,
    }
    layout = {
        "delimiter": sn.delimiter,
        "encoding": plain_encoding(enc),
        "bom": sn.bom,
        "line_ending": sn.line_ending,
        "compression": sn.compression,
        "header": sn.has_header,
        "header_names": list(sn.columns),
        "column_order": list(sn.columns),
        "skip_rows": sn.skip_rows,
        "quoting": False,
        "mapping": dict(res.columns),
        "extra_columns": extra,
        "time_column": res.columns["time"],
        "time_format": time_info.get("time_format"),
        "time_zone": report["time_zone"],
        "time_relative": report["time_relative"],
    }
    progress(1.0, "imported")
    empty = pd.DataFrame({c: pd.Series([], dtype="str") for c in ("sensor", "batch")})
    return ImportResult(empty, q, report, layout)

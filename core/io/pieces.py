"""Read a CSV file piece by piece with the importer: each piece its own careful parse.

Where the streamed reader (:func:`~wakeline.core.io.reader.stream_points`) gives up on a
file — a value only the careful parse reads (``12O.5`` for a longitude), a line further
on not in the encoding of the file's start — and for files with quotes in their start,
:func:`read_in_pieces` reads it from its start in pieces of whole lines (about
``STREAM_BYTES``; a quoted cell over line ends stays in one piece), each read by
:func:`~wakeline.core.io.read_points` on its own with the file's :class:`Sniff`
(delimiter, encoding, quoting, columns). One damaged value then costs its piece a careful
parse and itself a quarantine row, not a read of the whole file at once: memory stays
about one piece. Used by ``wakeline clean`` (:mod:`wakeline.core.clean_stream`) and
``wakeline batch`` (:mod:`wakeline.core.batch`).

The result is what :func:`read_points` on the whole file gives: the points (handed to a
sink piece by piece, in file order), the quarantine with the file's line numbers, and one
import report (counts summed, the first piece's columns and formats, warnings once; plus
``pieces``). Where the whole-file reader changes its reading for the whole file (quotes
that do not balance, an encoding that fails further on), every piece is read again that
way. What no reading in pieces gives raises
:class:`~wakeline.core.io.reader.WholeFileNeeded`: a clock change's repeated hour (placed
by each track's order over the whole file), or a piece the importer refuses (the
whole-file reader then says why). The tracks that start their time again within the file
(``restarting_tracks``) and the steps back in time (``time_steps_back``) are judged as a
whole read judges them: each track's last time is carried into the next piece, so that a
restart or a step back on a piece's first row is seen, and its steps are counted over the
pieces (:class:`~wakeline.core.io.reader.LastTimes`), so that a track's few rows in one
piece do not make it a track in no time order."""

import dataclasses
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.io.compressed import open_data
from wakeline.core.io.decoding import (
    FALLBACK_MARK,
    fallback_warning,
    line_decodable,
    merge_fallbacks,
)
from wakeline.core.io.formats import Resolved
from wakeline.core.io.geojson import TARGETS_MARK
from wakeline.core.io.grid import GRID_MARK, GRID_MIN_ROWS
from wakeline.core.io.reader import (
    BACK_MARK,
    BEARING_ROWS_MARK,
    BEARING_WARNING_MARK,
    CUT_SHORT_MARK,
    DDMM_NOTE_START,
    LETTER_NOTE_START,
    POSITION_COUNTS,
    REPEAT_MARK,
    TIME_COUNTS,
    TIME_UNIT_ON_TEXT_START,
    UNBALANCED_NOTE,
    ZONE_NOTE_MARK,
    ImportResult,
    WholeFileNeeded,
    _back_warnings,
    _coarse_time_warnings,
    _judged,
    _repeat_warnings,
    _restart_warnings,
    _time_warnings,
    bearing_warnings,
    blank_bytes,
    cut_short_warnings,
    date_order_note,
    edge_state,
    empty_quarantine,
    encoding_note,
    line_pieces,
    merge_steps_back,
    parse_zone,
    strict_mode,
    swapped_file,
    time_counts,
    with_final,
    written_zone,
)
from wakeline.core.io.sniff import Sniff
from wakeline.core.io.speed_check import SPEED_UNIT_MARK
from wakeline.core.progress import Progress, null_progress


def local_name(path: Path) -> str:
    """A scratch file's name that gives the same one-track name as ``path`` to a file
    without a batch column (the importer names it after the file, up to the first dot)."""
    return f"{path.name.split('.')[0]}.csv"


def pieces(sn: Sniff, opened: open_data | None = None) -> Iterator[tuple[bytes, int]]:
    """The file in pieces of whole lines (about the importer's ``STREAM_BYTES``), each
    with the physical line (1-based) it starts on. A piece ends where the quotes since its
    start balance (a quoted cell may hold line ends: it stays in one piece). The file is
    decompressed as it is read (:func:`~wakeline.core.io.compressed.open_data`;
    ``opened``: that opener, to ask how far it is)."""
    with opened or open_data(sn.path, sn.compression) as stream:
        yield from line_pieces(stream, cut=lambda buf: cut(buf, True))


def cut(buf: bytes, quoted: bool) -> int:
    """Index of the line end a piece of ``buf`` ends on (-1: none). With ``quoted``, the
    last one after an even number of quotes, unless that leaves less than half of ``buf``
    (a stray quote: the piece's own reader then reads it line by line)."""
    end = b"\n" if b"\n" in buf else b"\r"
    last = buf.rfind(end)
    if not quoted or last < 0 or b'"' not in buf:
        return last
    arr = np.frombuffer(buf, dtype=np.uint8)
    quotes = np.flatnonzero(arr == ord('"'))
    ends = np.flatnonzero(arr == ord(end))
    even = ends[np.searchsorted(quotes, ends) % 2 == 0]
    return int(even[-1]) if len(even) and even[-1] >= len(buf) // 2 else last


def piece_safe(sn: Sniff) -> bool:
    """Whether the file can be cut into pieces of whole lines at its line-end bytes (not
    UTF-16 or UTF-32 text, whose line ends are two or four bytes) and is a CSV."""
    wide = sn.encoding.lower().replace("_", "-").startswith(("utf-16", "utf-32"))
    return sn.kind == "csv" and not wide


def stream_or_pieces(
    sn: Sniff,
    res: Resolved,
    read: dict,
    sink: Callable[[pd.DataFrame], None],
    reset: Callable[[], None],
    scratch: Path,
    progress: Progress | None = None,
    pieces_progress: Progress | None = None,
) -> ImportResult | None:
    """The CSV ``sn``'s points into ``sink`` in bounded memory, as ``wakeline import``
    and ``wakeline clean`` read them: streamed (:func:`~wakeline.core.io.reader.stream_points`,
    no quotes in the start), or — where it gives up, and for quoted files — again from the
    start piece by piece (:func:`read_in_pieces`, ``reset()`` first forgetting what the
    sink got). None when only a whole read gives the points (a clock change's repeated
    hour, a piece the importer refuses, UTF-16 text, a damaged gzip whose message the
    whole-file reader gives): the caller resets its sink and reads whole. ``read``: fmt,
    mapping, sensor, tz; ``pieces_progress`` (default ``progress``) for the reading in
    pieces."""
    from wakeline.core.io.reader import StreamFallback, ValueOptions, stream_points

    tz = read.get("tz")
    try:
        if not sn.has_quotes:  # the streamed reader takes no quotes
            try:
                return stream_points(
                    sn,
                    res,
                    sink,
                    read["sensor"],
                    parse_zone(tz),
                    tz,
                    progress,
                    **ValueOptions.of(read).keywords(),
                )
            except WholeFileNeeded:
                raise
            except StreamFallback:
                reset()  # one bad value costs its piece a careful parse, not a whole read
        if not piece_safe(sn):  # UTF-16: not cut at its line-end bytes
            return None
        return read_in_pieces(sn, read, sink, scratch, pieces_progress or progress, reset)
    except WholeFileNeeded:
        return None
    except (OSError, EOFError, zlib.error) as exc:
        if isinstance(exc, OSError) and (exc.errno or exc.filename):
            raise
        return None


def read_in_pieces(
    sn: Sniff,
    read: dict,
    sink: Callable[[pd.DataFrame], None],
    scratch: Path,
    progress: Progress | None = None,
    reset: Callable[[], None] | None = None,
) -> ImportResult:
    """Read the CSV ``sn`` piece by piece, each piece by :func:`read_points` on its own
    (``read``: its keywords: fmt, mapping, sensor, tz; encoding and delimiter are the
    file's, in ``sn``), handing each piece's points (in file order; none for a piece
    without points) to ``sink``. Returns the quarantine (file line numbers), the import
    report and layout of the whole file (points empty). ``scratch``: a folder for the
    piece file (removed after).

    Every piece is read with the file's :class:`Sniff` (delimiter, encoding, quoting,
    columns: not sniffed again), as :func:`read_points` reads every line of the whole
    file. Where that reader would change its reading for the whole file — quotes that do
    not balance somewhere (it then reads every line without quoting), bytes not valid in
    the encoding of the file's start (after an ASCII start it tries GB18030, then UTF-8
    replacing what does not decode) — ``reset()`` is called to forget the points handed
    so far and every piece is read again that way (without ``reset``:
    :class:`WholeFileNeeded`). Raises :class:`WholeFileNeeded` for what only a whole-file
    read gives (module docstring). Memory: about one piece."""
    progress = progress or null_progress
    scratch.mkdir(parents=True, exist_ok=True)
    piece_file = scratch / local_name(sn.path)
    line_by_line = False
    # The whole-file reader's decodings in turn (reader._read_rows): strictly (a piece that
    # does not decode sends every piece to the next), then as the whole file's evidence
    # says, line by line (decoding.py); an encoding the user named, replacing.
    judge = not sn.encoding_given and line_decodable(sn.encoding) and not sn.line_fallback
    encodings = [(sn.encoding, "lines" if sn.line_fallback else strict_mode(sn))]
    if not judge:
        encodings.append((sn.encoding, "replace"))
    # The whole file's judgement, asked once: by the first piece with a line not valid in
    # the encoding of the file's start (its decoder goes on when the judgement confirms
    # that encoding, the pieces not read again: h167), else here.
    judged: dict[str, str] = {}

    def judgement() -> str:
        if "encoding" not in judged:
            judged["encoding"] = _judged(sn.path, sn.compression)  # the reader's too
        return judged["encoding"]

    step = 0
    try:
        while True:
            encoding, mode = encodings[step]
            # given: each piece decodes in this encoding as the whole file was judged
            piece_sn = dataclasses.replace(
                sn,
                encoding=encoding,
                encoding_given=True,
                line_fallback=mode != "strict",
                line_strict=mode == "strict-lines",
                judge=judgement if judge and mode == "strict-lines" else None,
            )
            try:
                strict = mode in ("strict", "strict-lines")
                parts = _read_all(piece_sn, read, line_by_line, strict, sink, piece_file, progress)
                break
            except _Again as again:
                if reset is None:
                    raise WholeFileNeeded from None
                reset()
                if again.quotes:
                    line_by_line = True
                else:
                    if judge and step == 0:
                        encodings.append((judgement(), "lines"))
                    step += 1
    finally:
        piece_file.unlink(missing_ok=True)
    quarantines, reports, layouts, keys, order = parts
    fallback = merge_fallbacks([(r.get("encoding_fallback", {}), 1) for r in reports])
    reports = [
        {**r, "warnings": [w for w in r.get("warnings", []) if not w.startswith(FALLBACK_MARK)]}
        for r in reports
    ]
    if encoding != sn.encoding or fallback:  # as the whole-file reader notes it
        first = [w for w in reports[0].get("warnings", []) if w != UNBALANCED_NOTE]
        notes = [UNBALANCED_NOTE] if line_by_line else []
        if encoding != sn.encoding:
            notes.append(encoding_note(sn.encoding, encoding))
        notes += fallback_warning(encoding, fallback)
        reports[0] = {**reports[0], "warnings": notes + first}
    q = pd.concat(quarantines, ignore_index=True) if quarantines else empty_quarantine()
    q = q.sort_values("line", kind="stable", ignore_index=True)
    tracks = len(pd.concat(keys).drop_duplicates()) if keys else 0
    report = merge_import_reports(sn, reports, q, tracks, read.get("tz"), order)
    layout = {**layouts[0], "compression": sn.compression} if layouts else {}
    if layout:
        layout.update(
            time_format=report["time_format"],
            time_relative=report["time_relative"],
        )
    progress(1.0, "imported")
    empty = pd.DataFrame({c: pd.Series([], dtype="str") for c in ("sensor", "batch")})
    return ImportResult(empty, q, report, layout)


class _Again(Exception):
    """A piece the whole-file reader would read otherwise: every piece is read again
    without quoting (``quotes``) or in the next encoding."""

    def __init__(self, quotes: bool) -> None:
        super().__init__()
        self.quotes = quotes


def _read_all(
    sn: Sniff,
    read: dict,
    line_by_line: bool,
    strict: bool,
    sink,
    piece_file: Path,
    progress: Progress,
) -> tuple:
    """Every piece read by :func:`read_points` as the file ``sn`` (``strict``: a piece
    with bytes not valid in its encoding raises :class:`_Again`): the quarantines (file
    line numbers), reports, layouts and track keys of the pieces."""
    from wakeline.core.io import read_points

    options = {k: v for k, v in read.items() if k not in ("encoding", "delimiter")}
    # The first piece is the file's start (its leading lines and header skipped as the
    # file's); a later one starts with data.
    first_sn = dataclasses.replace(sn, path=piece_file, compression=None)
    later_sn = dataclasses.replace(first_sn, skip_rows=0)
    size = max(_size(sn), 1)
    done = 0
    opened = open_data(sn.path, sn.compression)
    quarantines, reports, layouts, keys = [], [], [], []
    edges = edge_state()  # a track's first and last rows: judged in the last piece with rows
    has_rows = blank_bytes(sn.delimiter)
    units: set[bool] = set()  # numeric times read as Excel days, or not, per piece
    ddmm: set[tuple] = set()  # positions read as NMEA's ddmm.mmmm, or not, per piece
    forms: dict[str, str] = {}  # lettered lat/lon columns: ddmm.mmmm or degrees (h149)
    unit_given = options.get("time_unit", "auto") != "auto"  # the operator's --time-unit
    for k, ((piece, first_line), final) in enumerate(with_final(pieces(sn, opened), has_rows)):
        edges["back"].line_offset = first_line - 1  # its steps back named by file line
        piece_file.write_bytes(piece)
        done += len(piece)
        del piece
        try:
            res = read_points(
                piece_file,
                **options,
                sniffed=first_sn if k == 0 else later_sn,
                line_by_line=line_by_line,
                edges={**edges, "final": final},
            )
        except InputError:
            raise WholeFileNeeded from None  # the whole-file reader says what it is
        if edges["swapped"]:
            raise WholeFileNeeded  # a sensor (track) looks swapped: judged over the file
        warnings = res.report.get("warnings", [])
        if not unit_given and options.get("time_unit", "auto") != "auto":
            # the unit the first piece decided, passed on by this loop: no note that
            # "--time-unit" (never given) met text times (a piece of damaged lines alone)
            warnings = [w for w in warnings if not w.startswith(TIME_UNIT_ON_TEXT_START)]
            res.report["warnings"] = warnings
        clock = res.quarantine["reason"].str.contains("by a clock change", regex=False)
        if clock.any() or any("hour the clock change" in w for w in warnings):
            raise WholeFileNeeded  # a repeated hour is placed over the whole file
        if (
            res.report.get("time_format") == "month-first text"
            and read.get("date_order", "auto") == "auto"
        ):
            raise WholeFileNeeded  # the other pieces may hold only days up to 12
        fmt = str(res.report.get("time_format") or "")
        if fmt.startswith(("unix", "relative", "Excel")):
            units.add(fmt == "Excel serial days")
            if len(units) > 1:
                raise WholeFileNeeded  # pieces judged Excel days apart: one judgement
            if options.get("time_unit", "auto") == "auto":
                # the first piece of numbers decides for the rest (as the streamed read)
                options["time_unit"] = "excel-days" if fmt == "Excel serial days" else "seconds"
        if res.report.get("rows_imported"):  # ddmm.mmmm or not, signs from which letters
            notes = tuple(w for w in warnings if w.startswith((DDMM_NOTE_START, LETTER_NOTE_START)))
            ddmm.add((bool(res.report.get("ddmm")), notes))
            if len(ddmm) > 1:
                raise WholeFileNeeded  # pieces judged ddmm.mmmm positions apart: one judgement
        for name, form in (res.report.get("lettered_forms") or {}).items():
            if forms.setdefault(name, form) != form:
                raise WholeFileNeeded  # 3754.03N in one piece, 37.5N in another: one form
        if not line_by_line and UNBALANCED_NOTE in warnings:
            raise _Again(quotes=True)
        if strict and any(w.startswith("some bytes are not valid") for w in warnings):
            raise _Again(quotes=False)
        if len(res.points):
            keys.append(res.points[["sensor", "batch"]].drop_duplicates())
            sink(res.points)
        del res.points
        if len(res.quarantine):
            line = res.quarantine["line"] + (first_line - 1)
            quarantines.append(res.quarantine.assign(line=line))
        if res.report.get("time_steps_back"):  # its line numbers made the file's
            res.report["time_steps_back"] = merge_steps_back(
                [(res.report["time_steps_back"], first_line)]
            )
        if res.report.get("encoding_fallback"):  # its line numbers made the file's
            info = merge_fallbacks([(res.report["encoding_fallback"], first_line)])
            res.report["encoding_fallback"] = info
        reports.append(res.report)
        layouts.append(res.layout)
        far = done / size if sn.compression is None else opened.fraction()
        progress(min(0.95, far), "importing in pieces")
    return quarantines, reports, layouts, keys, edges["back"].judged()


def _size(sn: Sniff) -> int:
    try:
        return sn.path.stat().st_size
    except OSError:
        return 1


def _sum(dicts: list[dict]) -> dict:
    out: dict = {}
    for d in dicts:
        for key, value in d.items():
            out[key] = out.get(key, 0) + int(value)
    return out


def merge_import_reports(
    sn: Sniff,
    reports: list[dict],
    quarantine: pd.DataFrame,
    tracks: int,
    tz: str | None,
    order: tuple[dict, dict] | None = None,
) -> dict:
    """One import report of the pieces' reports, as :func:`read_points` gives it for the
    whole file: counts summed (tracks: ``tracks``, counted over the pieces' keys), the
    quarantine's reasons, the first piece's columns and formats, the time span over all,
    and the warnings once each (those with counts made again from the summed counts)."""
    first = reports[0]
    fallback = merge_fallbacks([(r.get("encoding_fallback", {}), 1) for r in reports])
    zone = parse_zone(tz)
    time_src = first["columns"]["time"]
    batch_src = first["columns"].get("batch", "")
    decimal = sum(int(r.get("decimal_comma_values", 0)) for r in reports)
    # restarts and steps back: judged over the file (``order``, LastTimes.judged), else
    # the pieces' summed
    restarting = (
        order[0] if order is not None else _sum([r.get("restarting_tracks", {}) for r in reports])
    )
    with_rows = [r for r in reports if r.get("rows_imported")]
    relative = bool(with_rows) and all(r.get("time_relative") for r in with_rows)
    # The warnings that carry a piece's count are made again from the summed counts.
    counted: set[str] = set()
    # The date order and Excel days: the pieces' counts summed, a day above 12 in any
    # piece showing the order for the whole file (as a whole read judges it).
    given = next(
        (o.split()[0] for o in (r.get("date_order") or "" for r in reports) if "(given" in o),
        None,
    )
    times: dict = {
        k: sum(int(r.get(k, 0)) for r in reports) for k in (*TIME_COUNTS, *POSITION_COUNTS)
    }
    times["dayfirst_shown"] = times["day_shown"]
    times["lettered_forms"] = {  # the pieces agree (else the file was read whole)
        k: v for r in reports for k, v in (r.get("lettered_forms") or {}).items()
    }
    times["excel_why"] = next((r["excel_why"] for r in reports if r.get("excel_why")), None)
    # zoned and zone-less times: counted by each piece, judged over the file
    zoned = sum(r.get("_zones", (0, 0))[0] for r in reports)
    naive = sum(r.get("_zones", (0, 0))[1] for r in reports)
    if zoned and naive:
        times["zoned_times"], times["zoneless_times"] = zoned, naive
    times["date_order_given"] = given
    example = next(
        (r["decimal_comma_example"] for r in reports if r.get("decimal_comma_example")), None
    )
    comma = {"decimal_comma": decimal, "decimal_comma_example": example}
    with_rows_whole = [r.get("times_whole") for r in reports if r.get("rows_imported")]
    coarse = {
        "times_fine": not with_rows_whole or None in with_rows_whole,
        "times_sub_hour": "minute" in with_rows_whole,
        "coarse_shared": sum(int(r.get("coarse_shared", 0)) for r in reports),
    }
    for r in reports:
        own_comma = {
            "decimal_comma": r.get("decimal_comma_values", 0),
            "decimal_comma_example": r.get("decimal_comma_example"),
        }
        counted.update(_time_warnings(time_src, own_comma, zone))
        own_coarse = {
            "times_fine": not r.get("times_whole"),
            "times_sub_hour": r.get("times_whole") == "minute",
            "coarse_shared": r.get("coarse_shared", 0),
        }
        counted.update(_coarse_time_warnings(time_src, own_coarse))
        own = {k: r.get(k, 0) for k in (*TIME_COUNTS, *POSITION_COUNTS, "excel_why")}
        counted.update(_time_warnings(time_src, {**own, "date_order_given": given}, zone))
        counted.update(_restart_warnings(r.get("restarting_tracks", {}), batch_src))
    relative_note = _time_warnings(time_src, {"relative": True}, zone)
    local_note = _time_warnings(time_src, {"naive": True}, zone)  # local times read as UTC
    notes, timing = [], []
    speed_said = False  # the speed-unit check (h191): the first piece's verdict, once
    for r in reports:
        for w in r.get("warnings", []):
            if w in counted or w in relative_note or BEARING_WARNING_MARK in w:
                continue
            if SPEED_UNIT_MARK in w:
                if speed_said:
                    continue
                speed_said = True
            if CUT_SHORT_MARK in w or BEARING_ROWS_MARK in w or BACK_MARK in w or REPEAT_MARK in w:
                continue  # said again below from the whole file's quarantine and reasons
            if w.startswith(TARGETS_MARK):
                continue  # a piece's counts: import_to_csv says the whole file's (h192)
            if ZONE_NOTE_MARK in w and zoned and naive:
                continue  # the zones-mixed warning below says it, as a whole read (h192)
            (timing if w in local_note else notes).append(w)
    # positions on a grid (grid.py): said when every piece with rows is on one
    # (a piece of fewer rows than GRID_MIN_ROWS is not judged on its own)
    grid = [
        next((w for w in r.get("warnings", []) if w.startswith(GRID_MARK)), None)
        for r in with_rows
        if r["rows_imported"] >= GRID_MIN_ROWS
    ]
    notes = [w for w in notes if not w.startswith(GRID_MARK)]
    if grid and None not in grid:
        notes.append(grid[0])
    warnings = list(dict.fromkeys(notes))
    warnings += _time_warnings(time_src, comma, zone)
    warnings += _time_warnings(time_src, times, zone)
    warnings += _coarse_time_warnings(time_src, coarse)
    warnings += list(dict.fromkeys(timing))
    if relative:
        warnings += relative_note
    repeated = sum(int(r.get("repeated_rows", 0)) for r in reports)  # within each piece
    warnings += _repeat_warnings(repeated)
    warnings += _restart_warnings(restarting, batch_src)
    steps_back = (
        order[1]
        if order is not None
        else merge_steps_back([(r.get("time_steps_back", {}), 1) for r in reports])
    )
    warnings += _back_warnings(steps_back, time_src, batch_src)
    reasons = _sum([r.get("quarantine_reasons", {}) for r in reports])
    warnings += bearing_warnings(
        first["columns"], reasons, sum(int(r.get("rows_read", 0)) for r in reports)
    )
    warnings += cut_short_warnings(sn, quarantine)
    starts = [pd.Timestamp(r["time_start"]) for r in reports if r.get("time_start")]
    ends = [pd.Timestamp(r["time_end"]) for r in reports if r.get("time_end")]
    # A later piece read in a fallback encoding: the whole file is read in that one.
    encodings = [r["encoding"] for r in reports]
    encoding = next((e for e in encodings if e != sn.encoding), encodings[0])
    read_all = {
        "rows_read": sum(int(r["rows_read"]) for r in reports),
        "lat_beyond_90_lon_within": sum(int(r.get("lat_beyond_90_lon_within", 0)) for r in reports),
    }
    if swapped_file(read_all):  # the whole-file reader quarantines every row of it (D2)
        raise WholeFileNeeded
    by_reason = quarantine["reason"].value_counts().to_dict() if len(quarantine) else {}
    fmt = (with_rows or reports)[0].get("time_format")
    first = {
        k: v for k, v in first.items() if k not in ("_zones", "time_offsets", "time_zone_written")
    }
    offsets = _sum([r.get("time_offsets", {}) for r in reports])  # the times' written offsets
    written = written_zone(offsets, naive)
    return {
        **first,
        **({"time_offsets": offsets, "time_zone_written": written} if written else {}),
        "date_order": date_order_note({**times, "time_format": fmt}),
        **time_counts(times),
        "input": str(sn.path),
        "encoding": encoding,
        "compression": sn.compression,
        "careful_parse": any(r.get("careful_parse") for r in reports),
        "time_format": (with_rows or reports)[0].get("time_format"),
        "time_relative": relative,
        "rows_read": sum(int(r["rows_read"]) for r in reports),
        "rows_imported": sum(int(r["rows_imported"]) for r in reports),
        "rows_quarantined": len(quarantine),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": sum(int(r.get("blank_lines", 0)) for r in reports),
        "values_blanked": _sum([r.get("values_blanked", {}) for r in reports]),
        "lat_beyond_90_lon_within": sum(int(r.get("lat_beyond_90_lon_within", 0)) for r in reports),
        "decimal_comma_values": decimal,
        "repeated_rows": repeated,
        "restarting_tracks": restarting,
        "time_steps_back": steps_back,
        "tracks": int(tracks),
        "sensors": _sum([r.get("sensors", {}) for r in reports]),
        "time_start": min(starts).isoformat() if starts else None,
        "time_end": max(ends).isoformat() if ends else None,
        "pieces": len(reports),
        **({"encoding_fallback": fallback} if fallback else {}),
        "warnings": warnings,
    }

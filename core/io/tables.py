"""A second table in one CSV: two exports pasted into one file, the second with its own
header line (D-import-9, operator test 5).

A line whose cells are column names — the first header's in another order, or a header
with a column more or less — starts a second table. Its rows are read by its own header
when that header names every column the import reads (time, positions, ids: the same
canonical fields), the first header's other columns taken by name; else the header line
and every row under it are quarantined with the line named and "split the file". A
header line that repeats the first one cell for cell is the reader's "the header line
again (files joined?)", its rows read as before. One implementation for every reading:
the whole-file reader calls :func:`second_tables` on its parsed rows; the streamed and
piece readers, which see one piece at a time, hand the file to the whole-file reader
when a piece holds such a line (:func:`header_line`).

The rows of each table are put under the first header's columns before any value is
read, so the time format is judged on the time column of both tables, never on one
table's times and the other's ids.
"""

import csv
import re
from dataclasses import dataclass, field

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core.io.formats import _ALIASES, known_fields

_NUMBER = re.compile(r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$")


def cell_name(text: str) -> str:
    """A header cell as compared: edge blanks, quotes and a byte order mark off, lower case."""
    return text.strip().strip('"').lstrip("\ufeff").strip().lower()


def _known(first: list[str]) -> set[str]:
    return {cell_name(c) for c in first} | set(_ALIASES)


def is_header_cells(cells: list[str], first: list[str]) -> bool:
    """Whether a line's cells are column names: every cell filled and none a number, at
    least two (and at least half) of them the first header's names or names the importer
    knows (synonyms in any layout)."""
    names = [cell_name(c) for c in cells]
    if len(names) < 2 or any(not n or _NUMBER.match(n) for n in names):
        return False
    own = {cell_name(c) for c in first}
    hits = sum(n in own or n in _ALIASES or bool(known_fields([n])) for n in names)
    return hits >= 2 and 2 * hits >= len(names)


def split_cells(text: str, delimiter: str) -> list[str]:
    """A line's cells as the CSV module splits them (quotes honoured)."""
    try:
        return next(csv.reader([text], delimiter=delimiter))
    except (csv.Error, StopIteration):
        return text.split(delimiter)


#: Delimiters a second table may be written with (another export's).
_DELIMITERS = (",", ";", "\t", "|")


def header_cells(text: str, delimiter: str, first: list[str]) -> tuple[list[str], str] | None:
    """A refused line's cells and delimiter when it is a header line: split by the file's
    delimiter, or by another (a second table written with ``;``); else None."""
    for delim in (delimiter, *(d for d in _DELIMITERS if d != delimiter)):
        if delim not in text:
            continue
        cells = split_cells(text, delim)
        if is_header_cells(cells, first):
            return cells, delim
    return None


def header_line(texts: list[str], delimiter: str, first: list[str]) -> bool:
    """Whether one of ``texts`` (lines the parser refused for their field count) is a
    header line of other columns than ``first``: the streamed reader then hands the file
    to the whole-file reader, which reads the second table by its header."""
    firsts = [cell_name(c) for c in first]
    for text in texts:
        found = header_cells(text, delimiter, first)
        if found is not None and (
            found[1] != delimiter or [cell_name(c) for c in found[0]] != firsts
        ):
            return True
    return False


@dataclass
class _Header:
    line: int
    names: list[str]  # its cells, as compared (cell_name)
    table_row: int | None  # its row in the parsed table, or None (a refused line)
    bad_at: int | None  # its index among the refused lines, or None
    kind: str = ""  # "same", "reordered", "other" (read by its header) or "split"
    take: list[int | None] | None = None  # per first-header column: its index here
    delimiter: str = ""  # another delimiter than the file's (a table not read)
    renamed: list[str] = field(default_factory=list)  # "lat for latitude"

    def describe(self, first: list[str]) -> str:
        """What differs from the first header, in the file's own words."""
        own = [cell_name(c) for c in first]
        taken = set(self.take or ()) if self.kind in ("reordered", "other") else set()
        more = [n for i, n in enumerate(self.names) if n not in own and i not in taken]
        less = [
            c
            for j, (c, n) in enumerate(zip(first, own, strict=True))
            if n not in self.names and (self.take is None or self.take[j] is None)
        ]
        parts = list(self.renamed) if self.kind in ("reordered", "other") else []
        parts += [f"+{n}" for n in more] + [f"\u2212{c}" for c in less]
        if not parts:
            parts.append("a column named twice" if self.kind == "split" else "in another order")
        return "; ".join(parts)


def _find(rows, sn, candidates: np.ndarray) -> list[_Header]:
    """The header lines among the parsed rows ``candidates`` (a mask) and the refused
    lines, in file order."""
    first = list(sn.columns)
    found: list[_Header] = []
    where = np.flatnonzero(candidates)
    if len(where):
        table = rows.table
        sub = table.take(pa.array(where))
        known = pa.array(sorted(_known(first)), type=pa.string())
        hits = np.zeros(len(where), dtype="int64")
        for name in first:
            text = pc.utf8_trim_whitespace(pc.cast(sub[name], pa.string()).fill_null(""))
            text = pc.utf8_lower(pc.utf8_ltrim(text, "\ufeff"))
            hits += np.asarray(pc.is_in(text, value_set=known), dtype="int64")
        maybe = (hits >= 2) & (2 * hits >= len(first))
        for i in np.flatnonzero(maybe):
            row = int(where[i])
            cells = [str(sub[name][int(i)].as_py() or "") for name in first]
            if is_header_cells(cells, first):
                names = [cell_name(c) for c in cells]
                found.append(_Header(int(rows.lines[row]), names, row, None))
    bad = rows.bad
    for k, text in enumerate(bad.texts):
        if not text:
            continue
        got = header_cells(text, sn.parse_delimiter, first)
        if got is not None:
            names = [cell_name(c) for c in got[0]]
            other = got[1] if got[1] != sn.parse_delimiter else ""
            found.append(_Header(int(bad.lines[k]), names, None, k, delimiter=other))
    return sorted(found, key=lambda h: h.line)


def _needed(sn, res) -> set[str]:
    """The columns the import reads (as compared): a second table must name them all."""
    cols = set(res.columns.values())
    cols |= {c for c in (res.date, res.gps_week) if c}
    return {cell_name(c) for c in cols if c in sn.columns}


def _judge(h: _Header, sn, res) -> None:
    own = [cell_name(c) for c in sn.columns]
    if h.names == own and not h.delimiter:
        h.kind = "same"
        return
    if h.delimiter or len(set(h.names)) != len(h.names):
        h.kind = "split"
        return
    h.take = [h.names.index(n) if n in h.names else None for n in own]
    # A column the import reads, named otherwise (lat for latitude): by its field.
    field_of = {cell_name(src): f for f, src in res.columns.items() if src in sn.columns}
    free = [i for i, n in enumerate(h.names) if n not in own]
    for j, n in enumerate(own):
        if h.take[j] is None and n in field_of:
            same = [i for i in free if field_of[n] in known_fields([h.names[i]])]
            if len(same) == 1:
                h.take[j] = same[0]
                h.renamed.append(f"{sn.columns[j]} \u2192 {h.names[same[0]]}")
    needed = _needed(sn, res)
    if any(h.take[j] is None for j, n in enumerate(own) if n in needed):
        h.kind = "split"
        return
    h.kind = "reordered" if sorted(h.names) == sorted(own) else "other"


def has_second_table(rows, sn, res, candidates: np.ndarray) -> bool:
    """Whether ``rows`` (a piece's) hold a header line of other columns than the first
    header: the piece readers then hand the file to the whole-file reader."""
    headers = _find(rows, sn, candidates)
    for h in headers:
        _judge(h, sn, res)
    return any(h.kind != "same" for h in headers)


def second_tables(rows, sn, res, candidates: np.ndarray, raw_lines) -> list[str] | None:
    """Read the rows under a second header line by that header, or quarantine them.

    ``rows``: the whole file's parsed rows (reader ``_Rows``: changed in place: its
    table, line numbers and refused lines); ``candidates``: a mask of the rows that may
    be a header line (their time did not parse); ``raw_lines(lines)``: the file's text of
    those lines. Returns the notes for the import report (one per second table, with its
    line and how many rows went where), or None when the file has no header line of
    other columns (nothing changed; a header repeated cell for cell stays the reader's).
    """
    headers = _find(rows, sn, candidates)
    for h in headers:
        _judge(h, sn, res)
    if all(h.kind == "same" for h in headers):
        return None
    first = list(sn.columns)
    table, bad = rows.table, rows.bad
    lines = np.asarray(rows.lines, dtype="int64")
    starts = np.asarray([h.line for h in headers], dtype="int64")
    # The table each row is under: -1 the first; a header line is under itself.
    block = np.searchsorted(starts, lines, side="right") - 1
    bad_lines = np.asarray(bad.lines, dtype="int64")
    bad_block = np.searchsorted(starts, bad_lines, side="right") - 1
    drop = np.zeros(table.num_rows, dtype=bool)
    moved_lines: list[int] = []
    moved_reasons: list[str] = []
    added: list[list[str | None]] = []
    added_lines: list[int] = []
    added_block: list[int] = []
    keep_bad = np.ones(len(bad_lines), dtype=bool)
    relabel: dict[int, str] = {}
    notes: list[str] = []
    columns = {name: table[name] for name in first}
    as_text = False
    for b, h in enumerate(headers):
        if h.kind == "same":
            continue
        what = h.describe(first)
        if h.table_row is not None:
            drop[h.table_row] = True
            moved_lines.append(h.line)
        else:
            keep_bad[h.bad_at] = False
            moved_lines.append(h.line)
        under_table = (block == b) & (lines != h.line)
        under_bad = (bad_block == b) & (bad_lines != h.line)
        if h.kind == "split":
            moved_reasons.append(
                f"the header of a second table separated by {h.delimiter!r}: split the file"
                if h.delimiter
                else f"the header of a second table ({what}) without a column this import "
                "reads: split the file"
            )
            reason = f"under the second table's header at line {h.line:,} (other columns): split the file"
            drop |= under_table
            for i in np.flatnonzero(under_table):
                moved_lines.append(int(lines[i]))
                moved_reasons.append(reason)
            for k in np.flatnonzero(under_bad):
                relabel[int(k)] = reason
            n = int(under_table.sum() + under_bad.sum())
            how = (
                f"separated by {h.delimiter!r}"
                if h.delimiter
                else f"with other columns ({what}), without a column this import reads"
            )
            notes.append(
                f"line {h.line:,} starts a second table {how}: its {n:,} rows quarantined; "
                "split the file and import each table on its own"
            )
            continue
        moved_reasons.append(
            "the header of a second table, its columns in another order: its rows read by it"
            if h.kind == "reordered"
            else f"the header of a second table ({what}): its rows read by it"
        )
        width = len(h.names)
        read = 0
        if width == len(first):
            mask = pa.array(under_table)
            if h.take != list(range(width)):
                as_text = True
                for j, name in enumerate(first):
                    src = h.take[j]
                    own = columns[name]
                    other = (
                        pa.nulls(len(under_table), pa.string())
                        if src is None
                        else pc.cast(table[first[src]], pa.string())
                    )
                    columns[name] = pc.if_else(mask, other, pc.cast(own, pa.string()))
            read += int(under_table.sum())
        else:  # the first table's field count under a header of another: refused
            reason = (
                f"{len(first)} fields under the second table's header at line {h.line:,} of {width}"
            )
            drop |= under_table
            for i in np.flatnonzero(under_table):
                moved_lines.append(int(lines[i]))
                moved_reasons.append(reason)
        for k in np.flatnonzero(under_bad):
            cells = split_cells(bad.texts[int(k)], sn.parse_delimiter) if bad.texts[k] else []
            if len(cells) != width:
                continue  # its own field count is wrong: refused for that
            keep_bad[k] = False
            added.append([None if src is None else cells[src] for src in h.take])
            added_lines.append(int(bad_lines[k]))
            added_block.append(b)
            read += 1
        notes.append(
            f"line {h.line:,} starts a second table with its columns "
            f"{'in another order' if h.kind == 'reordered' else f'changed ({what})'}: "
            f"read by its own header ({read:,} rows"
            f"{'; columns it adds not read' if any(w.startswith('+') for w in what.split('; ')) else ''})"
        )
    out = {name: columns[name] for name in first}
    for name in table.column_names:
        if name not in out:
            out[name] = table[name]
    if as_text:
        for name in first:
            out[name] = pc.cast(out[name], pa.string())
    new = pa.table(out)
    new_lines = lines
    if added:
        extra_cols = {}
        for j, name in enumerate(first):
            values = pa.array([row[j] for row in added], type=pa.string())
            extra_cols[name] = values
        for name in table.column_names:
            if name not in extra_cols:  # the file's one batch name, when it has no batch
                col = table[name]
                fill = col[0] if len(col) else None
                extra_cols[name] = pa.array(
                    [fill.as_py() if fill is not None else None] * len(added)
                )
        extra = pa.table(extra_cols)
        try:
            extra = extra.cast(new.schema)
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            as_text = True
            new = pa.table(
                {
                    n: pc.cast(new[n], pa.string()) if n in first else new[n]
                    for n in new.column_names
                }
            )
            extra = extra.cast(new.schema)
        new = pa.concat_tables([new, extra])
        new_lines = np.concatenate([lines, np.asarray(added_lines, dtype="int64")])
    drop_all = np.concatenate([drop, np.zeros(len(added_lines), dtype=bool)])
    order = np.argsort(new_lines, kind="stable")
    order = order[~drop_all[order]]
    rows.table = new.take(pa.array(order))
    rows.lines = new_lines[order]
    # each row's table (-1 the first): its times are read by their own table's format
    rows.blocks = np.concatenate([block, np.asarray(added_block, dtype="int64")])[order]
    rows.careful = rows.careful or as_text
    # Refused lines: the rows read by their header leave; header lines and the rows of a
    # table not read join, each with its reason.
    kept = np.flatnonzero(keep_bad)
    bad.lines = [bad.lines[k] for k in kept]
    bad.reasons = [relabel.get(int(k), bad.reasons[k]) for k in kept]
    bad.texts = [bad.texts[k] for k in kept]
    if moved_lines:
        texts = raw_lines(np.asarray(moved_lines, dtype="int64"))
        bad.lines += moved_lines
        bad.reasons += moved_reasons
        bad.texts += list(texts)
    bad.in_file_order()
    return notes

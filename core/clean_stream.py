"""Clean a track file of any size in bounded memory (issue 14): by blocks of whole tracks.

:func:`clean_file` gives the same points, reject trail and report as reading the file
with :func:`~wakeline.core.io.read_points` and running :func:`~wakeline.core.clean.clean`,
row for row, without ever holding the whole table:

1. **Spill.** The file is read piece by piece (:func:`~wakeline.core.io.reader.stream_points`,
   about 16 MB of whole lines at a time, each piece converted by the importer's one
   conversion). Each piece's points get their row number in the file's point table, are
   ordered by track key (sensor, batch as text — the order :func:`clean` sorts by) and
   written to a scratch Arrow IPC *run* with the count of rows of each key.
2. **Blocks.** From the runs' key counts the tracks' global order and sizes are known,
   and the file is cut into the same blocks of about ``BLOCK_ROWS`` rows of whole tracks
   that :func:`clean` cuts (``block_cuts``). A block is each run's contiguous slice of
   its tracks (memory-mapped, so only that slice is read), put back in file order and
   cleaned by the core's one cleaning implementation (``_clean_block``); its cleaned
   points are appended to the output CSV at once, its rejected rows to a scratch run.
3. **Reject trail.** The rejected runs (each sorted by ``wl_id``) are merged in ranges of
   ``wl_id`` into the rejected CSV, in the order :func:`clean` writes it.

Memory: one piece while spilling, then two blocks (cleaned on two threads) and their
cleaning temporaries (peaks in ``bench/bench_memory.py``). Scratch space: about the file's
size, in the system's temporary folder, removed at the end (also on error or cancel);
what a killed run left is removed by the next run (:func:`remove_stale_scratch`).

Where the streamed reader gives up (a value only the careful parse reads, a line further
on not in the encoding of the file's start) and for files with quotes in their start, the
spill is emptied and the file read piece by piece by the importer
(:func:`~wakeline.core.io.pieces.read_in_pieces`, the reading ``wakeline batch`` does):
each piece its own careful parse and quarantine, line numbers the file's, one import
report for the whole file; memory stays about one piece (session 16: a 318 MB file with
one bad longitude peaked at 2.56 GB read whole, 1.49 GB now). Read whole and cleaned in
memory, with the same outputs (``streamed`` is False in the result): what no reading in
pieces gives (a clock change's repeated hour, a piece the importer refuses), NMEA logs
and UTF-16 text, tables whose ``wl_id`` column cannot be used as ids, and cleanings
with a transforming step (``bspline``, ``resample``, ``smooth``: they number new points
across the whole table).

A text column is quoted in the output when a value that needs quotes is kept, as the
whole table's writer decides: the blocks holding such values are cleaned once beforehand
to see (none for the usual file).
"""

import os
import shutil
import tempfile
import threading
from collections import deque
from concurrent.futures import Future, ThreadPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.ipc as ipc

from wakeline.core import clean as clean_mod
from wakeline.core.clean import (
    ID,
    TRANSFORMS,
    CleanParams,
    CleanResult,
    block_cuts,
    merge_reports,
)
from wakeline.core.errors import Cancelled, InputError
from wakeline.core.io.writer import _NEEDS_QUOTES, needs_quotes
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import COURSE_READ, DEFAULT_SENSOR
from wakeline.core.tracks import natural_order, natural_track_order, sorted_with_index

#: Scratch column: a point's row number in the file's point table (its default wl_id).
ROW = "__wl_row"
_CANONICAL = frozenset(("time", "lon", "lat", "speed", "course", ROW))


@dataclass(frozen=True)
class FileCleanResult:
    """What :func:`clean_file` wrote, and the reports (no tables: they are on disk)."""

    report: dict  # clean's report, as :func:`clean` gives it
    read_report: dict  # the import report of the input (counts, mapping, warnings)
    quarantine: pd.DataFrame  # rows refused on reading: line, reason, text
    streamed: bool  # False: read whole and cleaned in memory (see the module docstring)


def clean_file(
    path: str | Path,
    output: str | Path,
    rejected: str | Path | None = None,
    params: CleanParams | None = None,
    progress: Progress | None = None,
    *,
    fmt: str = "auto",
    mapping: dict[str, str] | list[str] | None = None,
    encoding: str | None = None,
    delimiter: str | None = None,
    sensor: str = DEFAULT_SENSOR,
    tz: str | None = None,
    block_rows: int | None = None,
    skip_rows: int | None = None,
    origin: str | None = None,
    date_order: str = "auto",
    time_unit: str = "auto",
    clock_date: str | None = None,
    speed_unit: str = "auto",
    distance_unit: str = "auto",
    restore_ids=None,
    restore_rules: list[str] | None = None,
) -> FileCleanResult:
    """Clean the track file ``path`` into the canonical CSV ``output`` (and the reject
    trail into ``rejected`` when given) by blocks of whole tracks; see the module
    docstring. ``progress`` may raise :class:`~wakeline.core.errors.Cancelled` to stop:
    nothing is written then and the scratch files are removed. ``skip_rows``: physical
    lines before the header, skipped and counted (None: detected; ``read_points``);
    ``origin``: a local plane's for east/north metres; ``date_order``, ``time_unit``: how
    slashed dates and numeric times read; ``clock_date``: the day of times without a
    date (``--date``; ``read_points``); ``speed_unit``, ``distance_unit``: of columns
    whose header names none (``--speed-unit``, ``--distance-unit``). ``restore_ids``
    (``wl_id`` values) and ``restore_rules`` (rule names): points put back after
    cleaning, as the window's Restore does (``clean --restore``, ``--restore-rule``; the
    file is read and cleaned whole then). Raises
    :class:`~wakeline.core.errors.InputError` for a file without usable points."""
    from wakeline.core.io.formats import parse_mapping
    from wakeline.core.io.pieces import piece_safe, stream_or_pieces
    from wakeline.core.io.reader import (
        check_clock_date,
        check_date_order,
        check_time_unit,
        check_units,
        nothing_imported,
        parse_zone,
        resolve_header,
    )
    from wakeline.core.io.sniff import sniff

    params = (params or CleanParams()).checked()
    progress = progress or null_progress
    rows = int(block_rows or clean_mod.BLOCK_ROWS)
    path = Path(path)
    if isinstance(mapping, list):
        mapping = parse_mapping(mapping)
    options = {
        "fmt": fmt,
        "mapping": mapping,
        "encoding": encoding,
        "delimiter": delimiter,
        "sensor": sensor,
        "tz": tz,
        "skip_rows": skip_rows,
        "origin": origin,
        "date_order": date_order,
        "time_unit": time_unit,
        "clock_date": check_clock_date(clock_date),
        "speed_unit": speed_unit,
        "distance_unit": distance_unit,
    }
    parse_zone(tz)  # a zone it does not know is refused before anything is read
    check_date_order(date_order)
    check_time_unit(time_unit)
    check_units(speed_unit, distance_unit)
    sn = sniff(path, encoding, delimiter, skip_rows)
    transforms = any(getattr(params, name).enabled for name in TRANSFORMS)
    restoring = (restore_ids, restore_rules)
    if not piece_safe(sn) or transforms or restore_ids is not None or restore_rules:
        return _clean_whole(path, output, rejected, params, progress, options, restoring)
    res = resolve_header(sn, fmt, mapping, str(path), origin)  # names --skip-rows if it helps
    remove_stale_scratch()
    folder = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-"))
    reached = [0.0]  # the reading's progress so far: a second reading goes on from there

    def reading(fraction: float, text: str) -> None:
        reached[0] = max(reached[0], 0.4 * fraction)
        progress(reached[0], text)

    start: list[float] = []

    def again(fraction: float, text: str) -> None:  # a second reading goes on from there
        if not start:
            start.append(reached[0])
        reading((start[0] + (0.4 - start[0]) * fraction) / 0.4, text)

    try:
        spill = _Spill(folder)
        read = stream_or_pieces(
            sn, res, options, spill, spill.reset, folder / "pieces", reading, again
        )
        if read is None or not spill.ids_usable():
            shutil.rmtree(folder, ignore_errors=True)
            return _clean_whole(path, output, rejected, params, progress, options)
        if spill.rows == 0:
            raise InputError(nothing_imported(read.report, str(path)))
        report = _clean_runs(spill, output, rejected, params, progress, rows)
        return FileCleanResult(report, read.report, read.quarantine, True)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


#: Scratch folders of the streamed clean: ``wakeline-clean-PID-XXXXXXXX`` in the system's
#: temporary folder.
SCRATCH_PREFIX = "wakeline-clean-"


def remove_stale_scratch(folder: str | Path | None = None) -> list[Path]:
    """Remove scratch folders of ours (``wakeline-clean-PID-…``) that a killed run left
    in ``folder`` (default: the system's temporary folder): those whose process is gone.
    Returns the folders removed."""
    from wakeline.core.io.writer import _alive

    removed = []
    base = Path(folder or tempfile.gettempdir())
    try:
        entries = list(base.glob(f"{SCRATCH_PREFIX}*-*"))
    except OSError:
        return removed
    for entry in entries:
        pid = entry.name[len(SCRATCH_PREFIX) :].split("-", 1)[0]
        if pid.isdigit() and entry.is_dir() and not _alive(int(pid)):
            shutil.rmtree(entry, ignore_errors=True)
            removed.append(entry)
    return removed


def _clean_whole(
    path, output, rejected, params, progress, options, restoring=(None, None)
) -> FileCleanResult:
    """The whole-table way: read_points, clean, (put points back,) write."""
    from wakeline.core.clean import clean
    from wakeline.core.io import nothing_imported, read_points, write_csv, write_points

    read = read_points(path, progress=lambda f, text: progress(0.3 * f, text), **options)
    if len(read.points) == 0:
        raise InputError(nothing_imported(read.report, str(path)))
    result = clean(read.points, params, lambda f, text: progress(0.3 + 0.65 * f, text))
    del read.points
    points, trail, report = result.points, result.rejected, result.report
    if restoring[0] is not None or restoring[1]:
        points, trail, report = _restored(points, trail, report, *restoring)
    write_points(natural_track_order(points), output)  # as every step writes (D19)
    if rejected is not None:
        write_csv(trail, rejected)
    progress(1.0, "cleaned")
    return FileCleanResult(report, read.report, read.quarantine, False)


def _restored(points, trail, report, ids, rules):
    """Put back the points ``ids`` (``wl_id``) and those ``rules`` removed or changed
    (``clean --restore``, ``--restore-rule``): (points, rejected, report), the report with
    ``restored`` (points and their rules) and ``points_out`` as written."""
    from wakeline.core.clean import ID, restore
    from wakeline.core.clean_restore import chosen_ids, moved_counts

    chosen = chosen_ids(trail, rules=rules) if rules else np.zeros(0, dtype="int64")
    if ids is not None:
        ids = np.unique(np.asarray(ids, dtype="int64"))
        unknown = np.setdiff1d(ids, trail[ID].to_numpy())
        if len(unknown):
            raise InputError(
                f"--restore: {len(unknown):,} {ID} not removed or changed by this cleaning "
                f"(first: {', '.join(map(str, unknown[:5]))}); restore lists rows of the "
                "--rejected table of the same input and parameters"
            )
        chosen = np.union1d(chosen, ids)
    trail_back = trail[trail[ID].isin(chosen).to_numpy()]
    back = trail_back.drop_duplicates(ID)
    points, trail = restore(points, trail, chosen)
    per_rule = {str(k): int(v) for k, v in back["rule"].value_counts(sort=False).items()}
    # the rules' counts are of the rows left removed or changed (as the rejected table
    # written, and a layer's counts after the window's Restore): the summary said
    # "kept 30 of 30 points; removed 1" beside "restored 1"
    rules_report = {name: dict(v) for name, v in report.get("rules", {}).items()}
    for (action, rule), n in moved_counts(trail_back).items():
        entry = rules_report.get(rule)
        if entry is not None and action in entry:
            entry[action] = max(int(entry[action]) - n, 0)
    report = {
        **report,
        "rules": rules_report,
        "points_out": int(len(points)),
        "restored": {"points": int(len(chosen)), "rules": per_rule},
    }
    return points, trail, report


class _Spill:
    """The sink of the streamed reader: each piece of points, ordered by track key, to a
    scratch Arrow IPC run, with the rows per key."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.paths: list[Path] = []
        # per run: each of its keys (in the run's order) as a number in the registry,
        # and its rows
        self.keys: list[tuple[np.ndarray, np.ndarray]] = []
        self.registry = pd.Index([], dtype=object)  # "sensor\0batch" of every key seen
        self.sensors: list[np.ndarray] = []  # the registry's sensors and batches
        self.batches: list[np.ndarray] = []
        self.rows = 0
        self.given: list[np.ndarray] | None = None  # the file's own wl_id values
        self.given_ok = True
        # text columns with values the CSV writer quotes, and the keys (numbers in the
        # registry) of the tracks holding them: the cleaned output quotes a column in every
        # block written if a value that needs it is kept (the whole table's writer's choice)
        self.quote: set[str] = set()
        self.quote_keys: dict[str, list[np.ndarray]] = {}
        # whether some piece holds a course the import changed (COURSE_READ): every block
        # then carries the column (empty where none), as the whole table does
        self.course_read = False

    def __call__(self, points: pd.DataFrame) -> None:
        n = len(points)
        self.course_read |= COURSE_READ in points.columns
        points[ROW] = np.arange(self.rows, self.rows + n, dtype="int64")
        self.rows += n
        if ID in points.columns:
            given = pd.to_numeric(points[ID], errors="coerce")
            if self.given is None:
                self.given = []
            if given.isna().any():
                self.given_ok = False
            elif self.given_ok:
                self.given.append(given.to_numpy().astype("int64"))
        s_codes, s_names = pd.factorize(points["sensor"], sort=True, use_na_sentinel=False)
        b_codes, b_names = pd.factorize(points["batch"], sort=True, use_na_sentinel=False)
        nb = len(b_names)
        code = s_codes.astype("int64") * nb + b_codes
        order = np.argsort(code, kind="stable")
        counts = np.bincount(code, minlength=len(s_names) * nb)
        present = np.flatnonzero(counts)
        # the run's keys (in its order) as numbers in a registry of every key seen
        sensors = np.asarray(s_names, dtype=object)[present // nb]
        batches = np.asarray(b_names, dtype=object)[present % nb]
        joined = pd.Index(sensors.astype(str)) + "\x00" + pd.Index(batches.astype(str))
        known = self.registry.get_indexer(joined)
        new = known < 0
        if new.any():
            self.registry = self.registry.append(joined[new])
            self.sensors.append(sensors[new])
            self.batches.append(batches[new])
            known[new] = self.registry.get_indexer(joined[new])
        self.keys.append((known.astype("int64"), counts[present].astype("int64")))
        table = pa.Table.from_pandas(points.take(order), preserve_index=False)
        row_keys = None
        for name, column in zip(table.column_names, table.columns, strict=True):
            if not _is_text(column):
                continue
            hit = pc.match_substring_regex(column.cast(pa.string()), _NEEDS_QUOTES)
            hit = np.asarray(pc.fill_null(hit, False), dtype=bool)
            if hit.any():
                if row_keys is None:  # the run's rows are in the order of its keys
                    row_keys = np.repeat(known, counts[present])
                self.quote.add(name)
                self.quote_keys.setdefault(name, []).append(np.unique(row_keys[hit]))
        path = self.folder / f"run{len(self.paths):05d}.arrow"
        with ipc.new_file(str(path), table.schema) as writer:
            writer.write_table(table)
        self.paths.append(path)

    def reset(self) -> None:
        """Forget the runs written so far (a reading starting again)."""
        for path in self.paths:
            path.unlink(missing_ok=True)
        self.__init__(self.folder)

    def ids_usable(self) -> bool:
        """Whether the file's ``wl_id`` column (if any) is what :func:`clean` keeps:
        numbers on every row and no value twice; else rows are numbered afresh, as
        :func:`clean` does — only the in-memory path decides that the same way for a
        column that is partly unusable, so it is left to it."""
        if self.given is None:
            return True
        if not self.given_ok:
            return False
        ids = np.sort(np.concatenate(self.given)) if self.given else np.zeros(0, "int64")
        return not bool((ids[1:] == ids[:-1]).any())


def _is_text(column: pa.ChunkedArray) -> bool:
    return pa.types.is_string(column.type) or pa.types.is_large_string(column.type)


def _text_columns(df: pd.DataFrame) -> pd.DataFrame:
    """Text columns back to the importer's ``str`` dtype after a trip through Arrow."""
    for name in df.columns:
        if name not in _CANONICAL and name != ID and df[name].dtype != "str":
            if df[name].dtype == object or pd.api.types.is_string_dtype(df[name].dtype):
                df[name] = df[name].astype("str")
    return df


class _Appender:
    """Tables appended to one CSV written atomically: the header once, then bodies."""

    def __init__(self, fh, scratch: Path, points: bool, quote: frozenset[str]) -> None:
        self.fh, self.scratch, self.points, self.quote = fh, scratch, points, quote

    def add(self, table: pd.DataFrame) -> None:
        from wakeline.core.io import write_csv, write_points

        (write_points if self.points else write_csv)(table, self.scratch, self.quote)
        with open(self.scratch, "rb") as src:
            header = src.readline()
            if self.fh.tell() == 0:
                self.fh.write(header)
            if len(table):
                while block := src.read(16 << 20):
                    self.fh.write(block)


def _open_slices(paths: list[Path], ranges: list[tuple[int, int]]) -> pa.Table | None:
    """Rows ``a:b`` of each run (memory-mapped: only those rows are read), concatenated."""
    parts = []
    for path, (a, b) in zip(paths, ranges, strict=True):
        if b > a:
            with pa.memory_map(str(path)) as src:
                table = ipc.open_file(src).read_all().slice(a, b - a)
                parts.append(table.combine_chunks())  # a copy: the map can close
    if not parts:
        return None
    return pa.concat_tables(parts, promote_options="permissive")


def _clean_runs(
    spill: _Spill,
    output: str | Path,
    rejected: str | Path | None,
    params: CleanParams,
    progress: Progress,
    rows: int,
) -> dict:
    from wakeline.core.io.writer import atomic_path

    # The tracks' global order: sensor, then batch, as text (clean's sort order).
    sensors = pd.Series(np.concatenate(spill.sensors), dtype="str")
    batches = pd.Series(np.concatenate(spill.batches), dtype="str")
    s_codes, _ = pd.factorize(sensors, sort=True)
    b_codes, b_names = pd.factorize(batches, sort=True)
    order = np.argsort(s_codes.astype("int64") * len(b_names) + b_codes, kind="stable")
    rank = np.empty(len(order), dtype="int64")
    rank[order] = np.arange(len(order))
    sizes = np.zeros(len(order), dtype="int64")
    for known, counts in spill.keys:
        np.add.at(sizes, rank[known], counts)
    ends = np.cumsum(sizes)
    starts = ends - sizes
    # Per run: the global place of each of its keys (ascending) and row offsets.
    run_pos = [rank[known] for known, _ in spill.keys]
    run_cum = [np.concatenate([[0], np.cumsum(counts)]) for _, counts in spill.keys]
    if any((np.diff(pos) < 0).any() for pos in run_pos):  # a run sorted otherwise
        raise RuntimeError("streamed clean: a run's key order differs from the global order")
    blocks = block_cuts(ends, rows)
    given = spill.given is not None
    # each block's first key (in the global order)
    block_keys = np.searchsorted(starts, np.array([a for a, _ in blocks], dtype="int64"))
    stop = threading.Event()

    def check(_fraction: float = 0.0, _text: str = "") -> None:
        if stop.is_set():
            raise Cancelled()

    def work(k: int, trail: bool = True) -> tuple[CleanResult, Path | None]:
        """Block ``k``: its rows from every run, in file order, cleaned (its rejected
        rows to a scratch run with ``trail``)."""
        k0, k1 = np.searchsorted(starts, blocks[k])
        ranges = []
        for pos, cum in zip(run_pos, run_cum, strict=True):
            i0, i1 = np.searchsorted(pos, [k0, k1])
            ranges.append((int(cum[i0]), int(cum[i1])))
        table = _open_slices(spill.paths, ranges)
        src = _text_columns(table.to_pandas(split_blocks=True, self_destruct=True))
        del table
        order = np.argsort(src[ROW].to_numpy(), kind="stable")  # file order again
        src = src.take(order).reset_index(drop=True)
        row = src.pop(ROW).to_numpy()
        if spill.course_read and COURSE_READ not in src.columns:
            src[COURSE_READ] = np.nan  # a block of tracks whose courses were all kept
        src[ID] = pd.to_numeric(src[ID]).astype("int64") if given else row
        pts, index = sorted_with_index(src)
        del src
        result = clean_mod._clean_block(pts, index, params, check)
        path = None
        if trail and rejected is not None and len(result.rejected):
            path = spill.folder / f"rejected{k:05d}.arrow"
            table = pa.Table.from_pandas(result.rejected, preserve_index=False)
            with ipc.new_file(str(path), table.schema) as writer:
                writer.write_table(table)
        return result, path

    quote = _kept_quotes(spill, rank, block_keys, work, progress)
    # The file gets its tracks in natural order (batch 21 before 161: D19, as every step's
    # output is written, natural_track_order); the blocks are cut in the steps' text
    # order. Where the two differ, each cleaned block goes to scratch and the tracks are
    # written from there in natural order (memory: one chunk of rows).
    nat = natural_order(sensors, batches)
    reorder = not np.array_equal(nat, order)
    held = _HeldBlocks(spill.folder) if reorder else None
    reports: list[dict] = []
    reject_paths: list[Path] = []
    reject_template: pd.DataFrame | None = None
    scratch = spill.folder / "piece.csv"
    # Two blocks cleaned at a time on two threads (numpy releases the GIL), written in
    # order on this thread; the caller's progress (which raises to cancel) is polled here.
    pool = ThreadPoolExecutor(max_workers=2)
    pending: deque[Future] = deque()
    try:
        with atomic_path(output) as tmp, open(tmp, "wb") as fh:
            out = _Appender(fh, scratch, points=True, quote=frozenset(quote))
            for k in range(len(blocks)):
                while len(pending) < 2 and k + len(pending) < len(blocks):
                    pending.append(pool.submit(work, k + len(pending)))
                future = pending.popleft()
                while not future.done():
                    text = f"cleaning: block {k + 1} of {len(blocks)}"
                    progress(0.4 + 0.55 * k / len(blocks), text)
                    wait([future], timeout=0.1)
                result, path = future.result()
                if held is None:  # the blocks follow the natural order: each in it
                    out.add(natural_track_order(result.points))
                else:
                    held.add(result.points)
                reports.append(result.report)
                if reject_template is None:
                    reject_template = result.rejected.iloc[:0]
                if path is not None:
                    reject_paths.append(path)
                del result, future
            if held is not None:
                progress(0.95, "writing the tracks in natural order")
                held.write(out)
    except BaseException:
        stop.set()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
    if rejected is not None:
        progress(0.95, "writing the rejected points")
        _merge_rejected(reject_paths, reject_template, rejected, scratch, rows)
    progress(1.0, "cleaned")
    return reports[0] if len(reports) == 1 else merge_reports(reports)


class _HeldBlocks:
    """Cleaned blocks kept in scratch (Arrow IPC) with where each track's rows lie, then
    written track by track in natural order (:func:`~wakeline.core.tracks.natural_order`
    of the cleaned tracks: those clean split, ``338000000#2``, among them), in chunks of
    about :data:`CHUNK_ROWS` rows; neighbouring tracks of one block are read as one
    slice."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.paths: list[Path] = []
        # per block: its tracks' sensor and batch, and (block, start, end) of their rows
        self.sensors: list[np.ndarray] = []
        self.batches: list[np.ndarray] = []
        self.rows: list[np.ndarray] = []
        self.open: dict[int, pa.Table] = {}  # blocks mapped while writing

    def add(self, points: pd.DataFrame) -> None:
        k = len(self.paths)
        path = self.folder / f"cleaned{k:05d}.arrow"
        table = pa.Table.from_pandas(points, preserve_index=False)
        with ipc.new_file(str(path), table.schema) as writer:
            writer.write_table(table)
        self.paths.append(path)
        n = len(points)
        if not n:
            return
        sensor = points["sensor"].astype("str").to_numpy(dtype=object)
        batch = points["batch"].astype("str").to_numpy(dtype=object)
        change = np.ones(n, dtype=bool)
        change[1:] = (sensor[1:] != sensor[:-1]) | (batch[1:] != batch[:-1])
        starts = np.flatnonzero(change)
        ends = np.append(starts[1:], n)
        self.sensors.append(sensor[starts])
        self.batches.append(batch[starts])
        self.rows.append(np.column_stack([np.full(len(starts), k), starts, ends]).astype("int64"))

    def write(self, out: _Appender) -> None:
        if not self.rows:
            if self.paths:  # every track removed: the header of an empty table
                with pa.memory_map(str(self.paths[0])) as src:
                    out.add(_text_columns(ipc.open_file(src).read_all().to_pandas()))
            return
        order = natural_order(
            pd.Series(np.concatenate(self.sensors), dtype="str"),
            pd.Series(np.concatenate(self.batches), dtype="str"),
        )
        rows = np.concatenate(self.rows)[order]
        # neighbouring tracks of one block (contiguous rows) read as one slice
        joined = np.ones(len(rows), dtype=bool)
        joined[1:] = (rows[1:, 0] != rows[:-1, 0]) | (rows[1:, 1] != rows[:-1, 2])
        first = np.flatnonzero(joined)
        last = np.append(first[1:], len(rows)) - 1
        chunk: list[tuple[int, int, int]] = []
        size = 0
        for a, b in zip(first, last, strict=True):
            piece = (int(rows[a, 0]), int(rows[a, 1]), int(rows[b, 2]))
            chunk.append(piece)
            size += piece[2] - piece[1]
            if size >= CHUNK_ROWS:
                self._emit(chunk, out)
                chunk, size = [], 0
        if chunk:
            self._emit(chunk, out)
        self.open.clear()  # the maps close with their tables

    def _emit(self, chunk: list[tuple[int, int, int]], out: _Appender) -> None:
        for k in {k for k, _, _ in chunk} - set(self.open):  # each block mapped once
            self.open[k] = ipc.open_file(pa.memory_map(str(self.paths[k]))).read_all()
        parts = [self.open[k].slice(a, b - a) for k, a, b in chunk]
        table = pa.concat_tables(parts, promote_options="permissive")
        out.add(_text_columns(table.to_pandas()))


#: Rows written at a time when cleaned blocks are written again in natural order.
CHUNK_ROWS = 1 << 20


def _kept_quotes(
    spill: _Spill, rank: np.ndarray, block_keys: np.ndarray, work, progress: Progress
) -> set[str]:
    """The text columns the whole cleaned table's CSV quotes: those where a value that
    needs quotes is kept. Only the blocks holding such values are cleaned to see (in
    order, until every column is decided); none for the usual file without them."""
    from wakeline.core.io.writer import _needs_quotes, _to_arrow

    where: dict[int, list[str]] = {}  # block → the columns it has values to quote in
    for name, keys in spill.quote_keys.items():
        ranks = rank[np.unique(np.concatenate(keys))]
        for k in np.unique(np.searchsorted(block_keys, ranks, side="right") - 1).tolist():
            where.setdefault(int(k), []).append(name)
    quote: set[str] = set()
    for k in sorted(where):
        names = [name for name in where[k] if name not in quote]
        if not names:
            continue
        progress(0.4, "cleaning: the blocks with values to quote")
        result, _ = work(k, trail=False)
        table = _to_arrow(result.points[[n for n in names if n in result.points.columns]])
        quote.update(
            n for n, c in zip(table.column_names, table.columns, strict=True) if _needs_quotes(c)
        )
        del result, table
        if quote >= set(spill.quote_keys):
            break
    return quote


def _merge_rejected(
    paths: list[Path],
    template: pd.DataFrame | None,
    target,
    scratch: Path,
    rows: int,
) -> None:
    """The blocks' rejected runs, each sorted by (wl_id, action), merged in ranges of
    wl_id into one CSV sorted the same way (stable: a block's own order on ties); text
    columns quoted where the whole trail needs it."""
    from wakeline.core.io.writer import atomic_path

    ids = []
    quote: set[str] = set()
    for path in paths:
        with pa.memory_map(str(path)) as src:
            table = ipc.open_file(src).read_all()
            ids.append(np.array(table.column(ID), dtype="int64"))
            for name, column in zip(table.column_names, table.columns, strict=True):
                if (
                    name not in quote
                    and _is_text(column)
                    and needs_quotes(column.cast(pa.string()))
                ):
                    quote.add(name)
            del table
    step = 1024
    samples = np.sort(np.concatenate([x[::step] for x in ids])) if ids else np.zeros(0)
    cuts = samples[:: max(1, rows // step)][1:]
    bounds = [None, *cuts.tolist(), None]
    with atomic_path(target) as tmp, open(tmp, "wb") as fh:
        out = _Appender(fh, scratch, points=False, quote=frozenset(quote))
        if template is not None:
            out.add(template)
        for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
            ranges = []
            for x in ids:
                a = 0 if lo is None else int(np.searchsorted(x, lo, side="left"))
                b = len(x) if hi is None else int(np.searchsorted(x, hi, side="left"))
                ranges.append((a, b))
            table = _open_slices(paths, ranges)
            if table is None:
                continue
            part = _text_columns(table.to_pandas(split_blocks=True, self_destruct=True))
            del table
            part = part.sort_values([ID, "action"], kind="stable").reset_index(drop=True)
            out.add(part)

"""Import a track file into the canonical point table (SPEC §1).

Reading uses pyarrow's multi-threaded CSV reader with the column types fixed up front
(the fast path). When a value does not convert, the file is read again with the mapped
columns as text and each value is checked on its own (the careful path), so one bad cell
costs one quarantined row, never the file.

Nothing is lost silently: a row that cannot be used goes to the *quarantine* table with
its physical line number (1-based, header included) and the reason, and every count is
in the report.
"""

import gzip
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

from wakeline.core.errors import InputError
from wakeline.core.io.formats import Resolved, parse_mapping, resolve
from wakeline.core.io.sniff import Sniff, sniff
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import DEFAULT_SENSOR

QUARANTINE_COLUMNS = ("line", "reason", "text")
_TEXT_FIELDS = ("sensor", "batch", "truth")
_FLOAT_FIELDS = ("lon", "lat", "speed", "course")
#: Seconds since 1970 beyond which a number is read as milliseconds (year 5138 in seconds).
_MS_THRESHOLD = 1e11
_DAYFIRST_FORMATS = (
    "%d/%m/%Y %H:%M:%S",
    "%d/%m/%Y %H:%M:%S.%f",
    "%d/%m/%Y %H:%M",
    "%d-%m-%Y %H:%M:%S",
)


@dataclass
class ImportResult:
    """What an import produced: the points, the quarantined rows and the report."""

    points: pd.DataFrame
    quarantine: pd.DataFrame
    report: dict = field(default_factory=dict)


def empty_quarantine() -> pd.DataFrame:
    """A quarantine table with no rows (columns ``QUARANTINE_COLUMNS``)."""
    return pd.DataFrame(
        {
            "line": pd.Series([], dtype="int64"),
            "reason": pd.Series([], dtype="str"),
            "text": pd.Series([], dtype="str"),
        }
    )


@dataclass
class _BadRows:
    lines: list[int] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    texts: list[str] = field(default_factory=list)
    unnumbered: int = 0
    blank: int = 0

    def handler(self, row) -> str:
        if not row.text.strip():
            self.blank += 1
            return "skip"
        if row.number is None or row.number < 0:
            self.unnumbered += 1
        else:
            self.lines.append(int(row.number))
            if row.actual_columns < row.expected_columns:
                self.reasons.append(
                    f"short row: {row.actual_columns} of {row.expected_columns} fields"
                )
            else:
                self.reasons.append(
                    f"too many fields: {row.actual_columns} of {row.expected_columns}"
                )
            self.texts.append(row.text)
        return "skip"


def _read_table(
    sn: Sniff, types: dict[str, pa.DataType], threads: bool
) -> tuple[pa.Table, _BadRows]:
    bad = _BadRows()
    read = pacsv.ReadOptions(
        column_names=list(sn.columns),
        skip_rows=sn.skip_rows,
        use_threads=threads,
        encoding="utf8" if sn.encoding == "utf-8" else sn.encoding,
    )
    parse = pacsv.ParseOptions(
        delimiter=sn.delimiter, invalid_row_handler=bad.handler, ignore_empty_lines=False
    )
    convert = pacsv.ConvertOptions(column_types=types, strings_can_be_null=False)
    with pa.input_stream(str(sn.path), compression=sn.compression) as stream:
        table = pacsv.read_csv(
            stream, read_options=read, parse_options=parse, convert_options=convert
        )
    return table, bad


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


def _numbers(arr: pa.ChunkedArray) -> tuple[np.ndarray, np.ndarray]:
    """float64 values and a mask of unparsable (present but not a number) cells."""
    if pa.types.is_floating(arr.type) or pa.types.is_integer(arr.type):
        return arr.to_numpy().astype("float64", copy=False) if arr.null_count == 0 else pc.cast(
            arr, pa.float64()
        ).to_numpy(zero_copy_only=False), np.zeros(len(arr), bool)
    text = pd.Series(arr.to_pandas(), dtype="str").str.strip()
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype="float64")
    present = ~(text.isna() | (text == "")).to_numpy()
    lowered = text.str.lower()
    nan_words = lowered.isin(["nan", "na", "n/a", "null", "none"]).to_numpy()
    return values, present & np.isnan(values) & ~nan_words


def _epoch_ns(seconds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unix seconds (or milliseconds, told apart by magnitude) to int64 ns, and validity."""
    finite = np.isfinite(seconds)
    scale = 1_000_000_000
    if finite.any() and np.nanmedian(np.abs(seconds[finite])) > _MS_THRESHOLD:
        scale = 1_000_000
    ok = finite & (np.abs(seconds) < 9.2e18 / scale)
    x = np.where(ok, seconds, 0.0)
    # Whole and fractional parts apart: a float64 of ~1.7e18 ns cannot hold every ns.
    whole = np.floor(x)
    ns = whole.astype("int64") * scale + np.round((x - whole) * scale).astype("int64")
    return ns, ok


def parse_times(arr: pa.ChunkedArray, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """int64 ns since epoch (UTC) and a validity mask."""
    if pa.types.is_timestamp(arr.type):
        ns = pc.cast(arr, pa.timestamp("ns", arr.type.tz)).cast(pa.int64())
        ok = np.asarray(pc.is_valid(ns))
        return ns.fill_null(0).to_numpy(), ok
    if pa.types.is_integer(arr.type) or pa.types.is_floating(arr.type):
        seconds = pc.cast(arr, pa.float64()).to_numpy(zero_copy_only=False)
        return _epoch_ns(seconds)
    text = pd.Series(arr.to_pandas(), dtype="str").str.strip()
    present = ~(text.isna() | (text == ""))
    numeric = pd.to_numeric(text, errors="coerce")
    n_present = int(present.sum())
    if kind == "unix" or (n_present and numeric.notna().sum() >= 0.5 * n_present):
        return _epoch_ns(numeric.to_numpy(dtype="float64"))
    sample = text[present].head(50)
    dayfirst = kind == "dayfirst" or bool(
        sample.str.match(r"^\d{1,2}[/-]\d{1,2}[/-]\d{4}").mean() > 0.5
    )
    if dayfirst:
        parsed = pd.Series(pd.NaT, index=text.index, dtype="datetime64[ns, UTC]")
        for fmt in _DAYFIRST_FORMATS:
            todo = parsed.isna() & present
            if not todo.any():
                break
            parsed[todo] = pd.to_datetime(
                text[todo], format=fmt, errors="coerce", utc=True
            ).dt.as_unit("ns")
    else:
        parsed = pd.to_datetime(text, format="ISO8601", errors="coerce", utc=True)
    parsed = pd.Series(parsed).dt.as_unit("ns")
    ok = parsed.notna().to_numpy()
    ns = np.zeros(len(parsed), dtype="int64")
    ns[ok] = (
        (parsed[ok] - pd.Timestamp(0, tz="UTC")).to_numpy().astype("timedelta64[ns]").view("int64")
    )
    return ns, ok


def _raw_lines(sn: Sniff, line_numbers: np.ndarray) -> list[str]:
    """The text of the given physical lines (1-based), as in the file.

    One streaming pass, stopping after the last wanted line; used only for the
    quarantine, so a clean file never pays for it.
    """
    if len(line_numbers) == 0:
        return []
    wanted = set(int(n) for n in line_numbers)
    last = max(wanted)
    found: dict[int, str] = {}
    opener = gzip.open if sn.compression == "gzip" else open
    with opener(sn.path, "rt", encoding=sn.encoding, errors="replace", newline=None) as fh:
        for number, line in enumerate(fh, start=1):
            if number in wanted:
                found[number] = line.rstrip("\n").removeprefix("\ufeff")
            if number >= last:
                break
    return [found.get(int(n), "") for n in line_numbers]


def read_points(
    path: str | Path,
    fmt: str = "auto",
    mapping: dict[str, str] | list[str] | None = None,
    encoding: str | None = None,
    delimiter: str | None = None,
    sensor: str = DEFAULT_SENSOR,
    progress: Progress | None = None,
) -> ImportResult:
    """Read a track file into the canonical point table.

    ``fmt`` is ``auto`` or a format family (canonical, radar, ais, mtad, generic);
    ``mapping`` maps canonical fields to source columns (``{"batch": "MMSI"}`` or
    ``["batch=MMSI"]``); ``sensor`` names the sensor when the file has no sensor column.
    Raises :class:`InputError` for a file that cannot be read at all.
    """
    progress = progress or null_progress
    path = Path(path)
    if isinstance(mapping, list):
        mapping = parse_mapping(mapping)
    progress(0.0, f"reading {path.name}")
    sn = sniff(path, encoding, delimiter)
    res = resolve(sn.columns, fmt, mapping, source=str(path))

    careful = False
    try:
        table, bad = _read_table(sn, _column_types(sn, res, careful=False), threads=True)
    except pa.ArrowInvalid:
        careful = True
        table, bad = _read_table(sn, _column_types(sn, res, careful=True), threads=True)
    except UnicodeDecodeError as exc:
        raise InputError(
            f"{path}: cannot decode the text as {sn.encoding} ({exc.reason})"
        ) from None
    if bad.unnumbered:
        table, bad = _read_table(sn, _column_types(sn, res, careful), threads=False)
    progress(0.6, "checking values")

    points, quarantine, counts = _to_canonical(table, sn, res, bad, sensor)
    progress(1.0, "imported")
    report = {
        "input": str(path),
        "format": res.format.name,
        "format_label": res.format.label,
        "encoding": sn.encoding,
        "delimiter": sn.delimiter,
        "compression": sn.compression,
        "header": sn.has_header,
        "columns": res.columns,
        "careful_parse": careful,
        **counts,
    }
    return ImportResult(points, quarantine, report)


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


_RANGES = {
    "lon": (-180.0, 180.0, False),
    "lat": (-90.0, 90.0, False),
    "course": (0.0, 360.0, True),
    "speed": (0.0, np.inf, False),
}


def _to_canonical(table: pa.Table, sn: Sniff, res: Resolved, bad: _BadRows, sensor: str):
    n = table.num_rows
    cols = res.columns
    mapped = set(cols.values())

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
        if name in text:
            flag(text[name].codes < 0, f"missing {name}")
    time_col = table[cols["time"]]
    ns, time_ok = parse_times(time_col, res.format.time_kind)
    if not time_ok.all():
        flag(_trimmed(time_col)[1], "missing time")
        flag(~time_ok, "unparsable time")

    floats: dict[str, pa.ChunkedArray | pa.Array] = {}
    blanked: dict[str, int] = {}
    for name in _FLOAT_FIELDS:
        if name not in cols:
            continue
        arr = table[cols[name]]
        lo, hi, hi_open = _RANGES[name]
        if _clean_floats(arr, lo, hi, hi_open):
            floats[name] = arr  # the common case: passes through untouched
            continue
        v, unparsable = _numbers(arr)
        flag(unparsable, f"unparsable {name}")
        with np.errstate(invalid="ignore"):
            outside = (v < lo) | (v >= hi if hi_open else v > hi) | np.isinf(v)
        if name in ("lon", "lat"):
            flag(np.isnan(v) & ~unparsable, f"missing {name}")
            flag(outside, f"{name} out of range")
        elif outside.any():
            # Attributes, not positions: blank the value, keep the row, count it.
            label = "course outside [0, 360)" if name == "course" else "speed negative or infinite"
            blanked[label] = int(outside.sum())
            v = np.where(outside, np.nan, v)
        floats[name] = pa.array(v)

    bad_rows = reasons != 0
    keep = ~bad_rows & ~blank
    all_kept = bool(keep.all())

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
    for src in sn.columns:
        if src not in mapped:
            columns[src if src not in columns else f"{src}_src"] = table[src]
    out = pa.table(
        {k: pa.chunked_array([v]) if isinstance(v, pa.Array) else v for k, v in columns.items()}
    )
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

    bad_idx = np.flatnonzero(bad_rows)
    bad_lines = _line_numbers(bad_idx, sn.skip_rows, bad.lines)
    q_lines = np.concatenate([bad_lines, np.asarray(bad.lines, dtype="int64")])
    q_reasons = [reason_names[c] for c in reasons[bad_idx]] + bad.reasons
    q_texts = _raw_lines(sn, bad_lines) + bad.texts
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
    counts = {
        "rows_read": int(n - int(blank.sum()) + len(bad.lines)),
        "rows_imported": int(len(points)),
        "rows_quarantined": int(len(quarantine)),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": int(blank.sum()) + bad.blank,
        "values_blanked": blanked,
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
        uniq = np.unique(key)
        tracks = len(uniq)
        per_sensor = np.bincount(sensor_codes, minlength=n_sensors)
    return {
        "tracks": tracks,
        "sensors": {str(s): int(c) for s, c in zip(sensor_names, per_sensor, strict=True) if c},
    }

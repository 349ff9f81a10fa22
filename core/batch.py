"""Saved pipelines over inputs larger than memory, partitioned by track with Dask.

``wakeline batch PIPELINE.json IN… -o OUTDIR`` (``app/cli_batch.py``) runs
:func:`run_batch`. Three passes (docs/batch.md):

1. **Read and shuffle.** Each CSV input (any layout ``wakeline import`` reads; gzip, bz2,
   xz, zstd or a zip of one file too) is read by the importer, one Dask task per file in
   pieces of whole lines: every line a point or a quarantine row, as ``wakeline
   import``; a piece the streamed reader cannot take is read again on its own, never the
   whole file. Parquet inputs are read by a Dask dataframe in blocks (``blocksize_mb``),
   each block made canonical (unusable rows to ``OUTDIR/quarantine/``). The rows are
   written to one of ``n`` buckets on disk by a hash of (sensor, batch). Every track lands whole in one
   bucket, so a bucket holds complete tracks and about ``partition_mb`` of input.
2. **Per-track steps.** Each bucket runs the pipeline's stages with the core's own step
   functions (:class:`wakeline.core.pipeline.Pipeline`, the same code as the command
   line and the GUI) and writes every stage's table as ``OUTDIR/<step>/part-NNNNN.parquet``.
3. **Association across buckets.** Interrupted-track association joins tracks of one
   sensor that may sit in different buckets. It reads each track only through the first
   and last ``end_points`` points, or ``end_points_max`` where it runs straight
   (:func:`wakeline.core.segments.segment_stats`), so the
   buckets hand back those few points per track; the core's ``associate`` step runs once
   on them and the target of every track is mapped back onto its bucket's rows.

The scheduler is Dask's local threads by default, a ``dask.distributed`` cluster when an
address is given, or a ``LocalCluster`` of ``workers`` processes. Dask is imported only
when a batch runs (``pip install wakeline[batch]``).
"""

import contextlib
import errno
import json
import logging
import math
import os
import shutil
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError, NotTrackData
from wakeline.core.pipeline import STEPS, Pipeline, StageChain, params_to_json
from wakeline.core.schema import COURSE_READ, DEFAULT_SENSOR, TIME_DTYPE, ordered_columns
from wakeline.core.words import count as count_of

#: Steps that run bucket by bucket (each track on its own).
PER_TRACK = ("clean", "maneuvers", "compress")
STAGE = "_stage"
#: The outputs as they are written (``OUTDIR/_stage/out``), moved into OUTDIR at the end.
WORK = "out"
#: Written into OUTDIR when a batch starts, removed when it has finished (operator test 9,
#: D3): a folder holding it is an interrupted batch, which a rerun starts over in.
RUNNING = "BATCH_INCOMPLETE.txt"
ID = "wl_id"  # clean's row id (core/clean.py)
BLOCK = "_block"


@dataclass(frozen=True)
class BatchOptions:
    """How a batch is cut and where it runs."""

    #: input bytes per bucket (a bucket's tracks are processed in one call)
    partition_mb: float = 32.0
    #: Parquet inputs: megabytes (uncompressed) of row groups per block of pass 1. CSV
    #: inputs are one task per file, read in the importer's pieces (16 MB): not used
    blocksize_mb: float = 32.0
    #: ``dask.distributed`` scheduler address (``tcp://host:8786``); empty: local
    scheduler: str = ""
    #: worker processes of a LocalCluster; 0: Dask's local threaded scheduler
    workers: int = 0
    #: threads of the local scheduler (0: the cores, at most 4: each holds a partition
    #: and its working copies, so this bounds the peak memory)
    threads: int = 0
    #: LocalCluster with processes (False: threads in this process; tests)
    processes: bool = True
    #: also write OUTDIR/<step>.csv in canonical CSV
    csv: bool = False
    #: buckets (0: from the input size and ``partition_mb``)
    buckets: int = 0
    #: how CSV inputs are read, as ``wakeline clean`` reads its input (``--format``,
    #: ``--map FIELD=COLUMN``…, ``--encoding``, ``--delimiter``, ``--tz``, ``--skip-rows``:
    #: lines before the header, None detected; ``--date-order``: auto, day-first or
    #: month-first; ``--time-unit``: auto, seconds or excel-days); ``sensor`` names the
    #: sensor of inputs without a sensor column (CSV and Parquet)
    fmt: str = "auto"
    mapping: tuple[str, ...] = ()
    encoding: str | None = None
    delimiter: str | None = None
    tz: str | None = None
    sensor: str = DEFAULT_SENSOR
    #: ``--sensor-per-file``: each CSV input without a sensor column is its own sensor, named
    #: by its file name's stem (two consoles numbering their tracks alike stay apart)
    sensor_per_file: bool = False
    skip_rows: int | None = None
    #: ``--origin LAT,LON``: the local plane of inputs whose positions are east/north
    #: metres or range and bearing from a site
    origin: str | None = None
    date_order: str = "auto"
    time_unit: str = "auto"
    #: ``--date YYYY-MM-DD``: the day of times written without a date (None: 1970-01-01,
    #: relative)
    clock_date: str | None = None
    #: units of a speed column / plane lengths whose header names none (--speed-unit,
    #: --distance-unit: auto, or knots m/s km/h mph / m km nm yd)
    speed_unit: str = "auto"
    distance_unit: str = "auto"


@dataclass
class BatchResult:
    outdir: Path
    report: dict
    outputs: dict[str, Path] = field(default_factory=dict)


class BatchInterrupted(KeyboardInterrupt):
    """A batch stopped by Ctrl+C (SIGINT): ``done`` of ``partitions`` partitions of pass 2
    written (``partitions`` None: stopped in pass 1); ``outdir`` holds :data:`RUNNING`
    and the stage, no output that looks complete (operator test 9, D3/D7)."""

    def __init__(self, outdir: Path, done: int, partitions: int | None, csv: bool = False):
        super().__init__(str(outdir))
        self.outdir, self.done, self.partitions, self.csv = outdir, done, partitions, csv

    def message(self) -> str:
        if self.partitions is None:
            where = "while reading the inputs"
        elif self.csv:
            where = "while writing the CSV files"
        else:
            where = f"{self.done:,} of {count_of(self.partitions, 'partition')} written"
        return (
            f"interrupted ({where}; {self.outdir} is incomplete: run the same command again "
            "to start over in it)"
        )


def _take_outdir(outdir: Path, log) -> None:
    """Make ``outdir`` this batch's: new, empty, an earlier batch's (a ``report.json``:
    replaced whole) or an interrupted batch's (:data:`RUNNING`: started over, with a
    note); any other non-empty folder is refused. Writes :data:`RUNNING`."""
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"{outdir}: exists and is not a folder")
    if outdir.exists() and any(outdir.iterdir()):
        marker = outdir / RUNNING
        if marker.exists():
            pid = _marker_pid(marker)
            if pid and pid != os.getpid() and _alive(pid):
                raise InputError(
                    f"{outdir}: a batch is running into it (process {pid}); wait for it, or "
                    "choose a new folder"
                )
            log(
                f"{outdir}: an interrupted batch (it did not finish; its outputs were "
                "incomplete): starting over in it"
            )
        elif not (outdir / "report.json").exists():
            raise InputError(
                f"{outdir}: is not empty and holds no earlier batch; choose a new folder"
            )
        shutil.rmtree(outdir)  # an earlier batch's output: replaced whole
    outdir.mkdir(parents=True, exist_ok=True)
    (outdir / RUNNING).write_text(
        "A wakeline batch is writing into this folder, or was stopped before it finished\n"
        f"(process {os.getpid()}, started {time.strftime('%Y-%m-%dT%H:%M:%S%z')}).\n"
        "Nothing here is complete until this file is gone and report.json is written.\n"
        "Run the same command again to start over in this folder.\n",
        encoding="utf-8",
    )


def _marker_pid(marker: Path) -> int | None:
    import re

    try:
        found = re.search(r"\(process (\d+),", marker.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError):
        return None
    return int(found.group(1)) if found else None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


def _quiet_interrupt() -> None:
    """After Ctrl+C: no Python traceback from Dask's clients and workers ("Task exception
    was never retrieved … AllExit", their WARNING lines; operator test 9, D7)."""
    for name in ("distributed", "asyncio", "tornado", "tornado.application"):
        logger = logging.getLogger(name)
        logger.setLevel(logging.CRITICAL + 1)
        logger.disabled = True


@contextlib.contextmanager
def _quiet_on_sigint():
    """While a batch runs (in the main thread): Ctrl+C quiets Dask's loggers before the
    KeyboardInterrupt is raised. Quieted in the ``except``, the client's event-loop thread
    could already have logged its cancelled gathers ("Task exception was never retrieved
    … AllExit", with tracebacks) while the interrupt unwound through ``client.gather``."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous is not signal.default_int_handler:  # SIG_IGN, or the caller's own handler
        yield
        return

    def interrupted(signum, frame):
        _quiet_interrupt()
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, interrupted)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _close_client(client, opts: "BatchOptions") -> None:
    """Close a client (and the local cluster it started), quietly: an interrupted run's
    pending tasks are cancelled, not reported."""
    cluster = getattr(client, "cluster", None)
    try:
        client.close()
        if cluster is not None and not opts.scheduler:
            cluster.close()
    except (Exception, KeyboardInterrupt):  # noqa: BLE001 - shutting down after Ctrl+C
        _quiet_interrupt()


def _merge_break_legs(rep: dict, infos: list[dict]) -> None:
    """Clean's kept speed breaks over the partitions (their count is summed already): the
    fastest legs of all, as ``wakeline clean`` lists them, for the summary line."""
    from wakeline.core.clean import BREAK_LEGS_LISTED

    legs, params = [], None
    for info in infos:
        for s in info["stages"]:
            if s["step"] == "clean":
                speed = s["report"].get("rules", {}).get("speed", {})
                legs += speed.get("break_legs") or []
                params = params or speed.get("params")
    speed = rep["counts"].get("rules", {}).get("speed")
    if speed is None:
        return
    legs.sort(key=lambda leg: -(leg["kn"] if leg["kn"] is not None else math.inf))
    speed["break_legs"] = legs[:BREAK_LEGS_LISTED]
    if params is not None:
        speed["params"] = params


def breaks_said(report: dict) -> str:
    """What the summary says of clean's speed breaks, as ``wakeline clean`` says it (``;
    2 breaks kept, the fastest …``); "" when none."""
    from wakeline.core.pipeline import _break_phrases
    from wakeline.core.words import Text

    speed = report.get("steps", {}).get("clean", {}).get("counts", {}).get("rules", {})
    return str(Text(_break_phrases(speed.get("speed", {}))))


# -- checks -------------------------------------------------------------------------------


def check_pipeline(pipe: Pipeline) -> tuple[list, tuple | None]:
    """Split the stages into the per-track ones and a final interrupted association;
    raise InputError for what a batch cannot run."""
    per_track, assoc = [], None
    for k, (name, params) in enumerate(pipe.stages):
        if name in PER_TRACK:
            if assoc is not None:
                raise InputError(f"batch: {name} after associate is not supported")
            per_track.append((name, params))
        elif name == "associate":
            opts = params["associate_options"]
            if opts.mode != "interrupted":
                raise InputError(
                    "batch: associate runs in mode interrupted only (segment clustering "
                    "compares whole tracks of the entire table)"
                )
            if opts.stitch:
                raise InputError("batch: associate --stitch is not supported; stitch the result")
            if k != len(pipe.stages) - 1:
                raise InputError("batch: associate must be the last stage")
            assoc = (name, params)
        else:
            raise InputError(
                f"batch: step {name} is not supported (batch runs {', '.join(PER_TRACK)}, "
                "associate)"
            )
    if not pipe.stages:
        raise InputError("batch: the pipeline has no steps")
    return per_track, assoc


PARQUET_SUFFIXES = (".parquet", ".pq")


def _is_parquet(path: Path) -> bool:
    return path.suffix.lower() in PARQUET_SUFFIXES


def expand_inputs(paths: Sequence[Path]) -> list[Path]:
    """The inputs with each folder replaced by its data files, as ``evaluate --real``
    reads a folder (:func:`~wakeline.core.evaluate_association.real_files`: the track
    files directly in it, compressed ones and zips too; hidden files left out), or by
    its Parquet files when it holds those and no track file. A folder named ``*.parquet``
    is one Parquet input (Dask reads its parts)."""
    from wakeline.core.evaluate_association import real_files

    out: list[Path] = []
    for p in map(Path, paths):
        if not p.exists():
            raise InputError(f"{p}: no such file")
        if not p.is_dir() or _is_parquet(p):
            out.append(p)
            continue
        parquet = sorted(
            f for f in p.iterdir() if f.is_file() and not f.name.startswith(".") and _is_parquet(f)
        )
        try:
            out += real_files(p)
        except InputError:
            if not parquet:
                raise
            out += parquet
    return out


def _input_kind(paths: Sequence[Path]) -> str:
    kinds = {"parquet" if _is_parquet(p) else "csv" for p in paths}
    if len(kinds) > 1:
        raise InputError("batch: give either CSV or Parquet inputs, not both")
    return kinds.pop()


# -- pass 1: canonical blocks, hashed into buckets ----------------------------------------


def _to_float(col: pd.Series) -> np.ndarray:
    """float64 values of a text or numeric column; NaN where unreadable. Arrow's parser
    (the one ``wakeline import`` reads with) on the fast path, pandas where it refuses."""
    import pyarrow as pa
    import pyarrow.compute as pc

    if pd.api.types.is_numeric_dtype(col.dtype):
        return col.to_numpy(dtype="float64", na_value=np.nan)
    try:
        arr = pc.cast(pa.array(col, from_pandas=True), pa.float64())
        return arr.to_numpy(zero_copy_only=False)
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError):
        return pd.to_numeric(col, errors="coerce").to_numpy(dtype="float64", na_value=np.nan)


def _to_time(col: pd.Series) -> pd.Series:
    """UTC timestamps (ns) of ISO 8601 text or of a timestamp column; NaT where unreadable."""
    import pyarrow as pa
    import pyarrow.compute as pc

    if isinstance(col.dtype, pd.DatetimeTZDtype):
        return col.dt.tz_convert("UTC").astype(TIME_DTYPE)
    try:
        arr = pc.cast(pa.array(col, from_pandas=True), pa.timestamp("ns", "UTC"))
        return pd.Series(arr.to_pandas(), index=col.index).astype(TIME_DTYPE)
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError):
        t = pd.to_datetime(col, utc=True, format="ISO8601", errors="coerce")
        return t.dt.tz_convert("UTC").astype(TIME_DTYPE)


def canonical_block(
    df: pd.DataFrame, sensor: str = DEFAULT_SENSOR
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(points, quarantined rows) of one block of a canonical table read as text or typed.

    Types as ``wakeline import`` gives them: sensor and batch text (edge blanks trimmed),
    time UTC, lon/lat/speed/course float64, extra columns as read. A row without sensor,
    batch, time or a position in range is quarantined with its reason.
    """
    out = df.copy()
    if "sensor" not in out.columns:
        out.insert(0, "sensor", sensor)
    for col in ("sensor", "batch"):
        out[col] = out[col].astype("str").str.strip().where(out[col].notna())
    out["time"] = _to_time(out["time"])
    for col in ("lon", "lat", "speed", "course"):
        if col in out.columns:
            out[col] = _to_float(out[col])
    lon, lat = out["lon"].to_numpy(), out["lat"].to_numpy()
    reason = np.full(len(out), "", dtype=object)
    reason[~((lat >= -90) & (lat <= 90))] = "latitude missing or out of range"
    reason[~((lon >= -180) & (lon <= 180))] = "longitude missing or out of range"
    reason[out["time"].isna().to_numpy()] = "time missing or unreadable"
    for col in ("batch", "sensor"):
        bad = out[col].isna().to_numpy() | (out[col].fillna("") == "").to_numpy()
        reason[bad] = f"{col} missing"
    bad = reason != ""
    quarantine = df[bad].astype("str").assign(reason=reason[bad])
    good = out[~bad]
    return good[ordered_columns(good)].reset_index(drop=True), quarantine


def bucket_of(points: pd.DataFrame, n: int) -> np.ndarray:
    """Bucket (0..n-1) of every row: a stable hash of (sensor, batch), the same in every
    process and run."""
    h = pd.util.hash_pandas_object(points[["sensor", "batch"]], index=False).to_numpy()
    return (h % np.uint64(n)).astype("int64")


def _write_block(
    df: pd.DataFrame, stage: str, n: int, sensor: str = DEFAULT_SENSOR, partition_info=None
) -> pd.DataFrame:
    """Pass 1 on one block: canonical rows into bucket files, quarantine beside them.
    Returns one row of counts (a small frame Dask gathers)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    part = partition_info["number"] if partition_info else 0
    root = Path(stage)
    good, quarantine = canonical_block(df, sensor)
    if len(quarantine):
        qdir = root / "quarantine"
        qdir.mkdir(parents=True, exist_ok=True)
        pq.write_table(
            pa.Table.from_pandas(quarantine, preserve_index=False),
            qdir / f"block-{part:06d}.parquet",
        )
    _to_buckets(good, root, n, part, f"block-{part:06d}")
    return pd.DataFrame({"block": [part], "rows": [len(df)], "quarantined": [len(quarantine)]})


def _to_buckets(good: pd.DataFrame, root: Path, n: int, part: int, name: str) -> None:
    """Canonical rows of one block (number ``part``) into the bucket files ``name``."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    if ID not in good.columns:
        # The row's number in the concatenated inputs (what clean's reject trail keys on):
        # block and position here; pass 2 adds the rows of the blocks before.
        good[ID] = np.arange(len(good), dtype="int64")
        good[BLOCK] = np.int64(part)
    bucket = bucket_of(good, n)
    order = np.argsort(bucket, kind="stable")
    good, bucket = good.iloc[order], bucket[order]
    cuts = np.flatnonzero(np.diff(bucket)) + 1
    for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, len(bucket)], strict=True):
        if hi <= lo:
            continue
        d = root / f"bucket-{int(bucket[lo]):05d}"
        d.mkdir(parents=True, exist_ok=True)
        table = pa.Table.from_pandas(good.iloc[lo:hi], preserve_index=False)
        pq.write_table(table, d / f"{name}.parquet")


#: Block numbers of an imported CSV input: the file's number times this, plus its piece.
PIECES = 1 << 24

# -- pass 1 on CSV inputs: the importer, piece by piece -------------------------------------

#: Decompressed bytes read to estimate a compressed input's size (its number of buckets).
_ESTIMATE_BYTES = 4 << 20


def _damaged(path: Path, kind: str | None, exc: Exception) -> str:
    from wakeline.core.io.compressed import damaged

    return damaged(path, kind, exc)


def _head(
    path: Path, kind: str | None, limit: int, member: str | None = None
) -> tuple[bytes, int, bool]:
    """The first ``limit`` text bytes of ``path`` (decompressed by the importer's opener,
    :func:`~wakeline.core.io.compressed.open_data`; ``member``: a zip's file), the bytes
    on disk they took, and whether that is the whole file."""
    from wakeline.core.io.compressed import open_data

    opened = open_data(path, kind, member)
    with opened as stream:
        data = bytes(stream.read(limit + 1))
        used = opened.raw_bytes()
    return data[:limit], used, len(data) <= limit


@dataclass(frozen=True)
class _CsvInput:
    """What the survey of one CSV input found."""

    path: Path
    compression: str | None
    text_bytes: int  # its size as text (estimated for compressed files)
    empty: bool  # no data rows (empty, or a header only)
    member: str | None = None  # one file of a zip of several
    blank: bool = False  # nothing but blank space (import: "the file is empty")

    @property
    def name(self) -> str:
        """How messages and the quarantine name it: the file, or ``days.zip/a.csv``."""
        return str(self.path) if self.member is None else f"{self.path}/{self.member}"


def _survey_inputs(
    inputs: Sequence[Path], read: dict
) -> tuple[list[_CsvInput], list[tuple[str, str]], list[tuple[str, str]]]:
    """:func:`_survey_all` of every input. Of several, one that is not track data at all
    (:class:`NotTrackData`: a README.txt among the exports, binary, a header of no known
    column) is left out, as ``evaluate --real`` leaves it out: returned as (file, why) for
    a note. Any other refusal (a data file whose ``--map`` names a missing column, known
    columns but a required one missing, metres without an origin) is returned as (file,
    why) too, every one of them (:func:`refusal`): the batch runs on the rest and ends
    with exit status 2, saying so (D-batch-2, operator test 5: it stopped at the first).
    One input alone, or none left, is the importer's message."""
    out, not_read, refused = [], [], []
    with tempfile.TemporaryDirectory(prefix="wakeline-batch-") as tmp:
        for p in inputs:
            try:
                out += _survey_all(p, Path(tmp), read)
            except NotTrackData as exc:
                if len(inputs) == 1:
                    raise
                why = str(exc)
                not_read.append((str(p), why.removeprefix(f"{p}: ")))
            except InputError as exc:
                if len(inputs) == 1:
                    raise
                refused.append((str(p), refusal(str(exc), str(p))))
    if not out:
        gone = not_read + refused
        shown = "; ".join(f"{p}: {why}" for p, why in gone[:3])
        more = f"; and {len(gone) - 3:,} more" if len(gone) > 3 else ""
        raise InputError(f"batch: no input could be read: {shown}{more}")
    return out, not_read, refused


#: What a refused input's message gets in a batch of several (D-batch-2, operator test
#: 5): the reading flags apply to every input, so a file that needs its own cannot be
#: given them here.
OWN_FLAGS_ADVICE = (
    "the reading flags (--map, --origin, --encoding, …) apply to every input of a batch: "
    "run this file apart with its own, or `wakeline import` it to canonical CSV first and "
    "batch that"
)


def refusal(message: str, name: str) -> str:
    """An input's refusal as a batch of several lists it: the importer's message without
    the file's name, and where it asks for a reading flag, :data:`OWN_FLAGS_ADVICE`."""
    why = message.removeprefix(f"{name}: ").removeprefix(f"{name}/")
    if "--" in why or "mapped column" in why:
        why = f"{why}; {OWN_FLAGS_ADVICE}"
    return why


def _survey_all(path: Path, stage: Path, read: dict) -> list[_CsvInput]:
    """:func:`_survey` of one input; a zip of several files is several inputs, one per
    file (each checked as the importer would check it on its own)."""
    from wakeline.core.io.compressed import compression_of, data_members

    if compression_of(path) == "zip":
        import zipfile

        try:
            with zipfile.ZipFile(path) as archive:
                names = [m.filename for m in data_members(archive)]
        except zipfile.BadZipFile:
            names = []  # damaged: the survey's opener says so
        if len(names) > 1:
            return [_survey_member(path, name, stage, read) for name in names]
    return [_survey(path, stage, read)]


def _survey_member(path: Path, member: str, stage: Path, read: dict) -> _CsvInput:
    """:func:`_survey` of one file of a zip of several: its start is sniffed from a
    sample written to the stage (the importer opens a zip of one file only)."""
    import zipfile

    from wakeline.core.io import sniff
    from wakeline.core.io.compressed import zip_member
    from wakeline.core.io.pieces import local_name
    from wakeline.core.io.reader import resolve_header
    from wakeline.core.io.sniff import SAMPLE_BYTES

    label = f"{path}/{member}"
    try:
        head, _used, whole = _head(path, "zip", SAMPLE_BYTES, member)
        with zipfile.ZipFile(path) as archive:
            text_bytes = zip_member(archive, path, member).file_size
    except InputError as exc:
        raise type(exc)(str(exc).replace(f"{path}:", f"{label}:", 1)) from None
    if not head.strip():
        return _CsvInput(path, "zip", text_bytes, True, member, blank=True)
    if not whole:  # whole lines only
        cut = max(head.rfind(b"\n"), head.rfind(b"\r"))
        head = head if cut < 0 else head[: cut + 1]
    target = stage / "survey" / local_name(Path(member))
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(head)
    try:
        sn = sniff(target, read["encoding"], read["delimiter"], read["skip_rows"])
        if sn.kind == "csv":
            resolve_header(sn, read["fmt"], read["mapping"], label, read["origin"])
    except InputError as exc:
        raise type(exc)(str(exc).replace(str(target), label)) from None
    finally:
        target.unlink(missing_ok=True)
    empty = sn.kind == "csv" and not sn.preview and whole
    return _CsvInput(path, "zip", text_bytes, empty, member)


def _survey(path: Path, stage: Path, read: dict) -> _CsvInput:
    """Check one CSV input before any work (compression, encoding, columns: the
    importer's one message) and estimate its size as text."""
    from wakeline.core.io import sniff
    from wakeline.core.io.compressed import compression_of, zip_member
    from wakeline.core.io.reader import resolve_header
    from wakeline.core.io.sniff import SAMPLE_BYTES

    kind = compression_of(path)
    size = path.stat().st_size
    limit = SAMPLE_BYTES if kind is None else max(SAMPLE_BYTES, _ESTIMATE_BYTES)
    head, used, whole = _head(path, kind, limit)  # a zip of several files: refused here
    if kind is None:
        text_bytes = size
    elif kind == "zip":
        import zipfile

        with zipfile.ZipFile(path) as archive:
            text_bytes = zip_member(archive, path).file_size
    else:
        text_bytes = len(head) if whole else int(size * len(head) / max(used, 1))
    if not head.strip():
        return _CsvInput(path, kind, text_bytes, True, blank=True)
    sn = sniff(path, read["encoding"], read["delimiter"], read["skip_rows"])
    if sn.kind == "csv":
        resolve_header(sn, read["fmt"], read["mapping"], str(path), read["origin"])
    # A header alone (the whole file was in the sample and has no data line).
    empty = sn.kind == "csv" and not sn.preview and whole and len(head) <= SAMPLE_BYTES
    return _CsvInput(path, kind, text_bytes, empty)


def _import_file(
    path: str,
    file_no: int,
    stage: str,
    n: int,
    compression: str | None,
    read: dict,
    member: str | None = None,
) -> dict:
    """Pass 1 on one CSV input, read as ``wakeline import`` reads it (every line a point
    or a quarantine row, the same reasons), piece by piece into the buckets: streamed,
    or, where the streamed reader gives up (a value only the careful parse reads, another
    encoding further on, quotes), each piece read by the importer on its own. A
    compressed file (gzip, bz2, xz, zstd, a zip of one file) is decompressed as it is
    read, as the importer reads it (nothing written beside it); one file (``member``) of
    a zip of several is first decompressed into the stage folder (deleted when read).
    Returns the counts per piece (``counts``), the importer's ``warnings`` and ``rows``
    (points + quarantined)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from wakeline.core.io import read_points, sniff
    from wakeline.core.io.compressed import open_data
    from wakeline.core.io.pieces import local_name, piece_safe, read_in_pieces
    from wakeline.core.io.reader import (
        StreamFallback,
        ValueOptions,
        WholeFileNeeded,
        parse_zone,
        resolve_header,
        skipped_above_header,
        stream_points,
    )

    root, src = Path(stage), Path(path)
    read = dict(read)
    own = None  # --sensor-per-file: the file's name's stem
    if read.pop("sensor_per_file", False):  # this file's own sensor: its name's stem
        own = read["sensor"] = file_sensor(src if member is None else Path(member))
    scratch = root / f"file-{file_no:06d}"
    label = str(src) if member is None else f"{src}/{member}"
    pieces: list[int] = []
    spans: list[pd.DataFrame] = []  # each piece's tracks and their time spans

    def sink(points: pd.DataFrame) -> None:
        if not len(points):
            return
        if own is not None and prefix_sensor[0]:
            # a sensor column's values, prefixed by the file (operator test 9, D1: two
            # consoles' files, each with a sensor column AIS and a track 1, made one track)
            points["sensor"] = own + "/" + points["sensor"].astype("str")
        part = file_no * PIECES + len(pieces)
        spans.append(track_spans(points))
        _to_buckets(points, root, n, part, f"block-{part:012d}")
        pieces.append(len(points))

    def forget() -> None:
        """Remove what the streamed reader wrote before it gave up."""
        for k in range(len(pieces)):
            for f in root.glob(f"bucket-*/block-{file_no * PIECES + k:012d}.parquet"):
                f.unlink()
        pieces.clear()
        spans.clear()

    readable = src
    prefix_sensor = [False]  # the file has a sensor column (--sensor-per-file prefixes it)
    try:
        if member is not None:
            readable = scratch / local_name(Path(member))
            readable.parent.mkdir(parents=True, exist_ok=True)
            with open_data(src, "zip", member) as stream, open(readable, "wb") as out:
                while chunk := stream.read(16 << 20):
                    out.write(chunk)
        sn = sniff(readable, read["encoding"], read["delimiter"], read["skip_rows"])
        if own is not None and sn.kind == "csv":
            cols = resolve_header(sn, read["fmt"], read["mapping"], str(src), read["origin"])
            prefix_sensor[0] = "sensor" in cols.columns
        if not piece_safe(sn):  # NMEA logs, UTF-16 text: read whole
            res = read_points(readable, **read)
            sink(res.points)
            q, warnings = res.quarantine, res.report.get("warnings", [])
        else:
            q = None
            if not sn.has_quotes:
                try:
                    cols = resolve_header(
                        sn, read["fmt"], read["mapping"], str(src), read["origin"]
                    )
                    zone = parse_zone(read["tz"])
                    res = stream_points(
                        sn,
                        cols,
                        sink,
                        read["sensor"],
                        zone,
                        read["tz"],
                        **ValueOptions.of(read).keywords(),
                    )
                    q, warnings = res.quarantine, res.report.get("warnings", [])
                except WholeFileNeeded:  # the repeated hour of a clock change
                    forget()
                    res = read_points(readable, **read)
                    sink(res.points)
                    q, warnings = res.quarantine, res.report.get("warnings", [])
                except StreamFallback:
                    forget()
            if q is None:
                try:
                    res = read_in_pieces(sn, read, sink, scratch / "pieces", reset=forget)
                    q, warnings = res.quarantine, res.report.get("warnings", [])
                except WholeFileNeeded:
                    forget()
                    res = read_points(readable, **read)
                    sink(res.points)
                    q, warnings = res.quarantine, res.report.get("warnings", [])
    except InputError as exc:
        raise InputError(str(exc).replace(str(readable), label)) from None
    except (OSError, EOFError) as exc:  # a gzip cut short, met by the streamed reader
        if isinstance(exc, OSError) and (exc.errno or exc.filename):
            if member is not None and exc.errno == errno.ENOSPC:
                raise InputError(
                    f"{label}: cannot decompress into {scratch} ({exc.strerror}); give an "
                    "OUTDIR on a disk with room for the largest file of the zip"
                ) from None
            raise
        raise InputError(_damaged(src, compression, exc)) from None
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    n_q = 0 if q is None else len(q)
    if n_q:
        qdir = root / "quarantine"
        qdir.mkdir(parents=True, exist_ok=True)
        q = q.assign(file=label)[["file", "line", "reason", "text"]].astype(
            {"line": "int64", "reason": "str", "text": "str"}
        )
        pq.write_table(
            pa.Table.from_pandas(q, preserve_index=False), qdir / f"file-{file_no:06d}.parquet"
        )
    nothing = None
    if not pieces and n_q:  # every row quarantined: its counts still need a block
        pieces.append(0)
        from wakeline.core.io.reader import nothing_imported

        # as `wakeline import` refuses it (operator test 9, D2: only the totals said it)
        rep = {**res.report, "rows_read": n_q}
        rep.setdefault("quarantine_reasons", q["reason"].value_counts().to_dict())
        why = nothing_imported(rep)
        for lead in ("nothing imported: the one row was quarantined, ", "nothing imported: "):
            why = why.removeprefix(lead)
        why = why.removeprefix(f"all {n_q:,} rows were quarantined, ")
        nothing = f"0 of {count_of(n_q, 'row')} kept, all quarantined: {why} (see the quarantine)"
    blocks = file_no * PIECES + np.arange(len(pieces), dtype="int64")
    rows = np.asarray(pieces, dtype="int64")
    rows[:1] += n_q  # the file's quarantined rows counted with its first piece
    quarantined = np.zeros(len(pieces), dtype="int64")
    quarantined[:1] = n_q
    counts = pd.DataFrame({"block": blocks, "rows": rows, "quarantined": quarantined})
    lines = {  # the file's other lines: a title skipped above the header, blank lines
        "skipped_above_header": skipped_above_header(res.report),
        "blank_lines": int(res.report.get("blank_lines", 0)),
    }
    return {
        "counts": counts,
        "warnings": list(warnings),
        "rows": int(rows.sum()),
        "spans": track_spans(pd.concat(spans, ignore_index=True)) if spans else None,
        "nothing": nothing,
        **lines,
    }


def track_spans(points: pd.DataFrame) -> pd.DataFrame:
    """(sensor, batch) of ``points`` (or of spans already) with their first and last time."""
    if "start" not in points.columns:
        points = points.assign(start=points["time"], end=points["time"])
    g = points.groupby(["sensor", "batch"], observed=True, sort=False)
    return pd.DataFrame({"start": g["start"].min(), "end": g["end"].max()}).reset_index()


def shared_track_pairs(spans: dict[str, pd.DataFrame]) -> list[dict]:
    """Every pair of inputs whose tracks share (sensor, batch), in input order: ``{"inputs":
    [a, b], "ids": n, "overlapping": n of them with overlapping times, "gap_s": the
    largest gap between one file's end of a shared track and the other's start (0 when
    they overlap)}``. Read as one stream, each such id's rows of both files make one track."""
    if len(spans) < 2:
        return []
    order = {name: k for k, name in enumerate(spans)}
    frames = [df.assign(file=order[name]) for name, df in spans.items() if len(df)]
    if len(frames) < 2:
        return []
    all_spans = pd.concat(frames, ignore_index=True)
    all_spans["sensor"] = all_spans["sensor"].astype(str)
    all_spans["batch"] = all_spans["batch"].astype(str)
    many = all_spans.groupby(["sensor", "batch"])["file"].transform("nunique") > 1
    both = all_spans[many]
    if not len(both):
        return []
    pairs = both.merge(both, on=["sensor", "batch"], suffixes=("_a", "_b"))
    pairs = pairs[pairs["file_a"] < pairs["file_b"]]
    overlap = (pairs["start_a"] <= pairs["end_b"]) & (pairs["start_b"] <= pairs["end_a"])
    gap = np.maximum(
        (pairs["start_b"] - pairs["end_a"]).dt.total_seconds().to_numpy(),
        (pairs["start_a"] - pairs["end_b"]).dt.total_seconds().to_numpy(),
    )
    pairs = pairs.assign(overlapping=overlap.to_numpy(), gap_s=np.where(overlap, 0.0, gap))
    g = pairs.groupby(["file_a", "file_b"])
    table = pd.DataFrame(
        {"ids": g.size(), "overlapping": g["overlapping"].sum(), "gap_s": g["gap_s"].max()}
    )
    names = list(spans)
    return [
        {
            "inputs": [names[a], names[b]],
            "ids": int(row.ids),
            "overlapping": int(row.overlapping),
            "gap_s": float(row.gap_s),
        }
        for (a, b), row in table.iterrows()
    ]


#: Pairs a warning of :func:`shared_tracks` names (the rest: report.json)
PAIRS_SHOWN = 3


def _gap_said(seconds: float) -> str:
    if seconds >= 86400:
        return f"{seconds / 86400:,.1f} d"
    if seconds >= 3600:
        return f"{seconds / 3600:,.1f} h"
    return f"{seconds / 60:,.0f} min"


def shared_tracks(spans: dict[str, pd.DataFrame], pairs: list[dict] | None = None) -> list[str]:
    """Inputs read as one stream join every equal (sensor, batch). One summary line for
    the pairs of inputs whose shared ids overlap in time (the same export twice: D-batch-1/3,
    operator test 5, duplicates), one for those that do not (a track continued into the next
    file, or a number reused by another day or console: operator test 9, D1), each with
    the counts and the first pairs; every pair in report.json (``shared_track_ids``; D6:
    one line per pair, 102 lines in a 37-file run)."""
    pairs = shared_track_pairs(spans) if pairs is None else pairs
    out = []
    over = [p for p in pairs if p["overlapping"]]
    if over:
        files = {f for p in over for f in p["inputs"]}
        ids = sum(p["overlapping"] for p in over)
        shown, more = _pairs_said(over, [p["overlapping"] for p in over])
        head = (
            f"{over[0]['inputs'][0]} and {over[0]['inputs'][1]} share {count_of(ids, 'track id')}"
            if len(over) == 1
            else f"{len(files):,} inputs ({len(over):,} pairs) share track ids ({ids:,} in all)"
        )
        tail = "" if len(over) == 1 else f": {shown}{more}"
        out.append(
            f"warning: {head} with overlapping times{tail}: the same export twice? Read as "
            "one stream their rows join into one track each (duplicates); give each its own "
            "sensor (--sensor-per-file, or a sensor column), or run them apart; every pair in "
            "report.json (shared_track_ids)"
        )
    apart = [p for p in pairs if p["ids"] > p["overlapping"]]
    if apart:
        ids = sum(p["ids"] - p["overlapping"] for p in apart)
        gap = max(p["gap_s"] for p in apart)
        shown, more = _pairs_said(apart, [p["ids"] - p["overlapping"] for p in apart])
        out.append(
            f"warning: {count_of(ids, 'track id')} of one input continue in another at "
            f"later times (the longest gap {_gap_said(gap)}): {shown}{more}; read as one "
            "stream each is one track across the files (a capture cut into files). If the "
            "files are separate exports (other days, other consoles numbering alike), give "
            "each its own sensor (--sensor-per-file) or run them apart; every pair in "
            "report.json (shared_track_ids)"
        )
    return out


def _pairs_said(pairs: list[dict], counts: list[int]) -> tuple[str, str]:
    """The first :data:`PAIRS_SHOWN` pairs of inputs with their counts of shared ids
    ("a.csv and b.csv (12); …"), and "; and N more pairs" when there are more."""
    shown = "; ".join(
        f"{p['inputs'][0]} and {p['inputs'][1]} ({k:,})"
        for p, k in zip(pairs[:PAIRS_SHOWN], counts, strict=False)
    )
    more = f"; and {len(pairs) - PAIRS_SHOWN:,} more pairs" if len(pairs) > PAIRS_SHOWN else ""
    return shown, more


def file_sensor(path: Path) -> str:
    """The sensor a file names with ``--sensor-per-file``: its name without the data and
    compression suffixes (``radar.csv.gz`` → ``radar``)."""
    name = path.name
    for suffix in (".gz", ".bz2", ".xz", ".zst", ".zip"):
        name = name.removesuffix(suffix)
    return Path(name).stem or DEFAULT_SENSOR


def _read_options(opts: BatchOptions) -> dict:
    """``read_points`` keywords of the options (as ``wakeline clean`` passes them)."""
    from wakeline.core.io import parse_mapping

    return {
        "fmt": opts.fmt,
        "mapping": parse_mapping(list(opts.mapping)) if opts.mapping else None,
        "encoding": opts.encoding,
        "delimiter": opts.delimiter,
        "sensor": opts.sensor,
        "tz": opts.tz,
        "skip_rows": opts.skip_rows,
        "origin": opts.origin,
        "date_order": opts.date_order,
        "time_unit": opts.time_unit,
        "clock_date": opts.clock_date,
        "speed_unit": opts.speed_unit,
        "distance_unit": opts.distance_unit,
        "sensor_per_file": opts.sensor_per_file,
    }


def _import_or_refuse(path: str, file_no: int, stage: str, *args, alone: bool = True) -> dict:
    """:func:`_import_file`; of several inputs, one the importer refuses on the way (a
    refusal the survey of its start could not see) is ``{"refused": why}``, what it
    wrote to the buckets removed."""
    try:
        return _import_file(path, file_no, stage, *args)
    except InputError as exc:
        if alone:
            raise
        for f in Path(stage).glob("bucket-*/block-*.parquet"):
            if int(f.stem.split("-")[1]) // PIECES == file_no:
                f.unlink()
        return {"refused": str(exc)}


def _import_inputs(
    inputs: Sequence[_CsvInput], stage: Path, n: int, read: dict, alone: bool = True
) -> tuple[pd.DataFrame, list[str], list[str], dict[str, int]]:
    """Pass 1 over CSV inputs: each file read by the importer, one Dask task per file.
    Returns the counts per piece, the warnings (``FILE: warning: …``, in input order),
    the inputs without a data row (reported and skipped) and the lines that are neither
    rows nor headers, summed (``skipped_above_header``, ``blank_lines``)."""
    import dask

    todo = [(k, i) for k, i in enumerate(inputs) if not i.empty]
    tasks = [
        dask.delayed(_import_or_refuse, pure=False)(
            str(i.path), k, str(stage), n, i.compression, read, i.member, alone=alone
        )
        for k, i in todo
    ]
    done = dict(zip((k for k, _ in todo), dask.compute(*tasks), strict=True))
    from wakeline.core.io.sniff import EMPTY_FILE

    refused = {k: d.pop("refused") for k, d in list(done.items()) if "refused" in d}
    for k in refused:
        del done[k]
    warnings, empty = [], []
    for k, i in enumerate(inputs):
        d = done.get(k)
        if k in refused:
            continue
        if d is None or not d["rows"]:
            empty.append(i.name)
            why = EMPTY_FILE if i.blank else "no data rows (a header only?)"
            warnings.append(f"{i.name}: warning: {why}; skipped")
        if d is not None:
            warnings += [f"{i.name}: warning: {w}" for w in d["warnings"]]
    counts = [d["counts"] for d in done.values()]
    none = pd.DataFrame({c: pd.Series([], dtype="int64") for c in ("block", "rows", "quarantined")})
    lines = {k: sum(d[k] for d in done.values()) for k in ("skipped_above_header", "blank_lines")}
    # every row quarantined: refused as `wakeline import` refuses it (its rows counted)
    refused |= {k: d["nothing"] for k, d in done.items() if d.get("nothing")}
    gone = [(inputs[k].name, refusal(why, inputs[k].name)) for k, why in sorted(refused.items())]
    spans = {inputs[k].name: d["spans"] for k, d in done.items() if d.get("spans") is not None}
    lines |= {"refused": gone, "spans": spans}
    return pd.concat([none, *counts], ignore_index=True), warnings, empty, lines


def _read_parquet_inputs(inputs: Sequence[Path], stage: Path, n: int, opts) -> pd.DataFrame:
    """Pass 1 over Parquet inputs: Dask blocks, each made canonical."""
    import pyarrow as pa

    ddf = _read_dask(inputs, opts.blocksize_mb)
    _check_columns(list(ddf.columns))
    pass1 = ddf.map_partitions(
        _write_block,
        str(stage),
        n,
        opts.sensor,
        meta=pd.DataFrame(
            {
                "block": pd.Series([], dtype="int64"),
                "rows": pd.Series([], dtype="int64"),
                "quarantined": pd.Series([], dtype="int64"),
            }
        ),
    )
    try:
        return pass1.compute()
    except (ValueError, pa.ArrowException, pd.errors.ParserError) as exc:
        raise InputError(f"batch: cannot read the inputs: {_reason(exc)}") from None


def _read_dask(paths: Sequence[Path], blocksize_mb: float):
    """Parquet inputs as a Dask dataframe: row groups gathered into blocks of about
    ``blocksize_mb`` (uncompressed, as Parquet's metadata gives it; a row group is never
    split), in input order."""
    import dask.dataframe as dd

    return dd.read_parquet(
        [str(p) for p in paths],
        blocksize=max(1, int(blocksize_mb * 2**20)),
        split_row_groups="adaptive",
    )


def _reason(exc: Exception) -> str:
    """One line of a reader's error (Dask wraps the reader's own message)."""
    lines = [x.strip() for x in str(exc).splitlines() if x.strip()]
    for x in lines:
        if x.startswith("Original Message:"):
            return x.removeprefix("Original Message:").strip()
    return lines[0] if lines else type(exc).__name__


def _check_columns(columns: Sequence[str]) -> None:
    missing = [c for c in ("batch", "time", "lon", "lat") if c not in columns]
    if missing:
        raise InputError(
            f"batch: the inputs lack column(s) {', '.join(missing)}; batch reads the canonical "
            "layout in Parquet inputs (sensor,batch,time,lon,lat,…); give other layouts as CSV "
            "(any layout `wakeline import` reads)"
        )


# -- pass 2: the per-track stages on each bucket --------------------------------------------


def read_parts(folder: Path) -> pd.DataFrame:
    """The Parquet files of one folder, concatenated in name order."""
    import pyarrow.parquet as pq

    files = sorted(folder.glob("*.parquet"))
    if not files:
        return pd.DataFrame()
    return pd.concat([pq.read_table(f).to_pandas() for f in files], ignore_index=True)


def _write_part(df: pd.DataFrame, folder: Path, name: str) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder.mkdir(parents=True, exist_ok=True)
    pq.write_table(pa.Table.from_pandas(df, preserve_index=False), folder / name)


def end_summary(points: pd.DataFrame, k: int) -> pd.DataFrame:
    """The first and last ``k`` points of every track (all of a track with up to 2k):
    everything interrupted association reads of a track."""
    from wakeline.core.tracks import sorted_with_index

    if not len(points):
        return points
    pts, index = sorted_with_index(points)
    pos = np.arange(len(pts)) - index.starts[index.track_of_row]
    size = index.sizes[index.track_of_row]
    keep = (pos < k) | (pos >= size - k)
    return pts[keep].reset_index(drop=True)


def _add_counts(total: dict, rep: dict) -> dict:
    """Sum the integer counts of per-bucket step reports (rules, points, tracks)."""
    for key, value in rep.items():
        if key == "params" or isinstance(value, bool):
            continue
        if isinstance(value, (int, np.integer)):
            total[key] = int(total.get(key, 0)) + int(value)
        elif isinstance(value, dict):
            total[key] = _add_counts(dict(total.get(key, {})), value)
    return total


def _run_bucket(
    bucket: int, stage: str, outdir: str, per_track: list, assoc_k: int, offsets: tuple
) -> dict:
    """Pass 2 on one bucket: run the per-track stages, write their tables."""
    t0 = time.perf_counter()
    root, out = Path(stage), Path(outdir)
    name = f"part-{bucket:05d}.parquet"
    current = read_parts(root / f"bucket-{bucket:05d}")
    if BLOCK in current.columns:
        keys, starts = offsets  # block numbers (sorted) and the rows before each
        current[ID] += starts[np.searchsorted(keys, current[BLOCK].to_numpy())]
        current = current.drop(columns=BLOCK)
    rows_in = len(current)
    info: dict = {"bucket": bucket, "rows_in": rows_in, "stages": [], "summary": None}
    # The association's input: the per-track stages' tracks whole (the cleaned tracks,
    # not compress's few points per track: StageChain, as Pipeline.run chains them).
    chain = StageChain(current)
    if per_track and rows_in:
        res = Pipeline(tuple(per_track)).run(current)
        for (step_name, _params), sres in zip(per_track, res.stages, strict=True):
            step = STEPS[step_name]
            table = sres.tables[step.output]
            _write_part(table, out / step_name, name)
            extra = {}
            if step_name == "clean":
                _write_part(sres.tables["rejected"], out / "clean_rejected", name)
                extra["rejected"] = len(sres.tables["rejected"])
            if step_name == "compress" and "maneuvers" not in dict(per_track):
                man = [lay for lay in sres.layers if lay.suffix == "maneuvers"]
                if man:
                    _write_part(man[0].tables["maneuvers"], out / "maneuvers", name)
            info["stages"].append(
                {"step": step_name, "rows_out": len(table), "report": sres.report, **extra}
            )
            primary = [lay for lay in sres.layers if lay.suffix == step.primary]
            current = primary[0].points if primary else sres.tables.get("points", current)
            chain.done(step_name, current)
    current = chain.input("associate")
    if assoc_k:
        # The association's input, kept whole for pass 3, and its small end summary.
        _write_part(current, root / "assoc_in", name)
        info["summary"] = end_summary(current, assoc_k)
        info["assoc_rows"] = len(current)
    info["seconds"] = time.perf_counter() - t0
    return info


# -- pass 3: association across buckets ------------------------------------------------------


def _apply_targets(bucket: int, stage: str, outdir: str, targets: pd.DataFrame) -> int:
    """Pass 3 on one bucket: the association's rows (sorted by track and time) with the
    target of their track."""
    from wakeline.core.tracks import sort_points

    name = f"part-{bucket:05d}.parquet"
    pts = read_parts_file(Path(stage) / "assoc_in" / name)
    if pts is None or not len(pts):
        return 0
    pts = sort_points(pts)
    merged = pts.merge(targets, on=["sensor", "batch"], how="left", validate="many_to_one")
    _write_part(merged, Path(outdir) / "associate", name)
    return len(merged)


def read_parts_file(path: Path) -> pd.DataFrame | None:
    import pyarrow.parquet as pq

    return pq.read_table(path).to_pandas() if path.exists() else None


# -- canonical CSV of a step's partitions -------------------------------------------------


def parts_to_csv(folder: Path, path: Path, points: bool = True, tracks: bool = False) -> int:
    """Write a step's partitions as one CSV, partition after partition (bounded memory),
    with the writer the command line uses; ``tracks``: each partition's tracks in natural
    order (:func:`~wakeline.core.tracks.natural_track_order`, as the command line writes
    a step's file). Returns the rows written."""
    import pyarrow.parquet as pq

    from wakeline.core.io import write_csv, write_points
    from wakeline.core.io.writer import atomic_path
    from wakeline.core.tracks import natural_track_order

    files = sorted(folder.glob("*.parquet"))
    rows, header, columns = 0, None, None
    # the courses as read (COURSE_READ) in every partition's rows when one holds them
    course_read = points and any(COURSE_READ in pq.read_schema(f).names for f in files)
    if not points and files:  # a table (the quarantine): every partition's columns
        columns = list(dict.fromkeys(n for f in files for n in pq.read_schema(f).names))
    one = path.with_name(path.name + ".one.part")
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        for f in files:
            df = read_parts_file(f)
            if columns is None:
                columns = ordered_columns(df) if points else list(df.columns)
                if course_read and COURSE_READ not in columns:
                    columns.append(COURSE_READ)
            df = df.reindex(columns=columns)
            if tracks:
                df = natural_track_order(df)
            (write_points if points else write_csv)(df, one)
            with open(one, "rb") as src:
                first = src.readline()
                if header is None:
                    header = first
                    fh.write(first)
                shutil.copyfileobj(src, fh)
            rows += len(df)
        one.unlink(missing_ok=True)
    return rows


# -- the whole run ----------------------------------------------------------------------------


def _client(opts: BatchOptions):
    """A dask.distributed client when asked for one, else None (local threads)."""
    if opts.scheduler:
        from distributed import Client

        try:
            return Client(opts.scheduler, timeout="20s")
        except OSError as exc:
            raise InputError(f"batch: cannot reach the scheduler {opts.scheduler}: {exc}") from None
    if opts.workers:
        from distributed import Client, LocalCluster

        cluster = LocalCluster(
            n_workers=opts.workers,
            threads_per_worker=1,
            processes=opts.processes,
            dashboard_address=":0",  # any free port: 8787 may be taken (a notebook, another run)
            # the workers' own log lines (a task cancelled by Ctrl+C …): none (D7). Not even
            # ERROR: a worker whose heartbeat meets the scheduler closing after Ctrl+C logs
            # one with a traceback. A task's error still reaches the client, raised here.
            silence_logs=logging.CRITICAL,
        )
        return Client(cluster)
    return None


def run_batch(
    pipeline: Pipeline,
    inputs: Sequence[Path],
    outdir: Path,
    options: BatchOptions | None = None,
    log=None,
) -> BatchResult:
    """Run ``pipeline`` over ``inputs`` (CSV of any layout the importer reads, or
    canonical Parquet) into ``outdir``; ``log`` receives progress lines and warnings.

    Writes ``outdir/<step>/part-NNNNN.parquet`` per step (named after the CLI
    subcommand; ``clean_rejected``, ``quarantine`` and, for a compress without a
    maneuvers stage, its ``maneuvers``), ``<step>.csv`` with ``csv``, and ``report.json``.
    """
    with _quiet_on_sigint():  # Ctrl+C: one line, no Dask traceback (D7)
        return _run_batch(pipeline, inputs, outdir, options, log)


def _run_batch(
    pipeline: Pipeline,
    inputs: Sequence[Path],
    outdir: Path,
    options: BatchOptions | None = None,
    log=None,
) -> BatchResult:
    opts = options or BatchOptions()
    log = log or (lambda _msg: None)
    if not inputs:
        raise InputError("batch: give at least one input file")
    per_track, assoc = check_pipeline(pipeline)
    inputs = expand_inputs(inputs)
    kind = _input_kind(inputs)
    read = _read_options(opts)
    if opts.sensor_per_file and kind != "csv":
        raise InputError(
            "batch: --sensor-per-file: for CSV inputs only; Parquet inputs hold their sensor"
        )
    in_bytes = sum(p.stat().st_size for p in inputs if p.is_file()) or sum(
        f.stat().st_size for p in inputs if p.is_dir() for f in p.rglob("*") if f.is_file()
    )
    if kind == "csv":
        from wakeline.core.io import parse_zone
        from wakeline.core.io.reader import check_date_order, check_time_unit, check_units
        from wakeline.core.io.timetext import check_clock_date

        parse_zone(opts.tz)  # an unknown zone: one message before any work
        check_date_order(opts.date_order)
        check_time_unit(opts.time_unit)
        check_units(opts.speed_unit, opts.distance_unit)
        check_clock_date(opts.clock_date)
        # Every input checked before any work: one clear message (columns, compression).
        csv_inputs, not_read, refused = _survey_inputs(inputs, read)
        text_bytes = sum(i.text_bytes for i in csv_inputs)
    else:
        not_read, refused = [], []
        given = [
            flag
            for flag, value in (
                ("--format", opts.fmt != "auto"),
                ("--map", bool(opts.mapping)),
                ("--encoding", opts.encoding),
                ("--delimiter", opts.delimiter),
                ("--tz", opts.tz),
                ("--skip-rows", opts.skip_rows is not None),
                ("--origin", opts.origin),
                ("--date-order", opts.date_order != "auto"),
                ("--time-unit", opts.time_unit != "auto"),
                ("--date", opts.clock_date),
                ("--speed-unit", opts.speed_unit != "auto"),
                ("--distance-unit", opts.distance_unit != "auto"),
            )
            if value
        ]
        if given:
            raise InputError(
                f"batch: {', '.join(given)}: for CSV inputs only; Parquet inputs hold the "
                "canonical columns (sensor,batch,time,lon,lat,…)"
            )
        text_bytes = in_bytes
    outdir = Path(outdir)
    _take_outdir(outdir, log)
    stage = outdir / STAGE
    # Every output is written under the stage (``work``) and moved into OUTDIR at the end,
    # after which the marker goes: an interrupted run leaves no file that looks complete.
    work = stage / WORK
    # Buckets from the inputs' size as text (a compressed file's estimated from its start).
    n = opts.buckets or max(1, math.ceil(text_bytes / (opts.partition_mb * 2**20)))
    timings: dict[str, float] = {}
    progress: dict = {}  # what an interruption reports (partitions of pass 2)
    try:
        client = _client(opts)
    except KeyboardInterrupt:
        _quiet_interrupt()
        raise BatchInterrupted(outdir, 0, None) from None
    import dask

    threads = opts.threads or min(os.cpu_count() or 1, 4)
    local = contextlib.ExitStack()
    if client is None:
        # This batch's own threads: after Ctrl+C (or a task's error) Dask raises at once
        # while the other threads' partitions still run and write under the stage; the
        # batch waits for them (shutdown) before it returns, so a rerun in OUTDIR, in the
        # same process, does not race with them (rmtree failed: exit 2).
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(threads, thread_name_prefix="wakeline-batch")
        local.callback(pool.shutdown, wait=True, cancel_futures=True)
        local.enter_context(dask.config.set(scheduler="threads", num_workers=threads, pool=pool))
    buckets: list[int] = []
    try:
        t = time.perf_counter()
        warnings: list[str] = []
        shared: list[dict] = []  # pairs of inputs sharing track ids (shared_track_pairs)
        empty: list[str] = []
        lines: dict[str, int] = {}  # CSV inputs: lines skipped above headers, blank lines
        try:
            if kind == "csv":
                alone = len(csv_inputs) + len(refused) + len(not_read) == 1
                counts, warnings, empty, lines = _import_inputs(csv_inputs, stage, n, read, alone)
                refused += lines.pop("refused")
                shared = shared_track_pairs(lines.pop("spans"))
                warnings += shared_tracks({}, shared)
            else:
                counts = _read_parquet_inputs(inputs, stage, n, opts)
        except (InputError, OSError):
            # Nothing half-written is left: the same OUTDIR can be given again.
            shutil.rmtree(outdir, ignore_errors=True)
            raise
        work.mkdir(parents=True, exist_ok=True)
        timings["read_shuffle_s"] = time.perf_counter() - t
        counts = counts.sort_values("block")
        kept = (counts["rows"] - counts["quarantined"]).to_numpy()
        offsets = (counts["block"].to_numpy(), np.cumsum(kept) - kept)
        rows_read = int(counts["rows"].sum())
        quarantined = int(counts["quarantined"].sum())
        blocks = len(counts)  # pass 1's read tasks' pieces (CSV) or blocks (Parquet)
        if rows_read == quarantined:
            # nothing to run on (no data row, or every input refused): nothing written, as
            # one input alone is refused (exit status 2, not 3: docs/batch.md)
            shutil.rmtree(outdir, ignore_errors=True)
            if refused:
                refused = [(p, why.replace(" (see the quarantine)", "")) for p, why in refused]
                shown = "; ".join(f"{p}: {why}" for p, why in refused)
                raise InputError(f"batch: no input could be read: {shown}")
            if rows_read:
                raise InputError(
                    f"batch: no row kept: all {count_of(rows_read, 'row')} were quarantined"
                )
            raise InputError("batch: the inputs hold no data rows (headers only?)")
        for warning in warnings:
            log(warning)
        for name, why in not_read:
            log(f"{name}: warning: {why}; skipped")
        for name, why in refused:  # last before the totals: what matters most stays in view
            log(f"{name}: refused: {why}")
        log(
            f"read {count_of(rows_read, 'row')} into {count_of(n, 'bucket')} "
            f"({quarantined:,} quarantined)"
        )
        if (stage / "quarantine").exists():
            shutil.move(str(stage / "quarantine"), str(work / "quarantine"))

        t = time.perf_counter()
        # Every fix an end fit may take: end_points, or up to end_points_max where the
        # track runs straight.
        link = assoc[1]["associate"] if assoc else None
        assoc_k = max(int(link.end_points), int(link.end_points_max)) if link else 0
        buckets = sorted(int(d.name.split("-")[1]) for d in stage.glob("bucket-*"))
        tasks = [
            dask.delayed(_run_bucket, pure=False)(
                b, str(stage), str(work), per_track, assoc_k, offsets
            )
            for b in buckets
        ]
        progress["partitions"] = len(buckets)
        infos = list(dask.compute(*tasks))
        timings["steps_s"] = time.perf_counter() - t
        stages_rep: dict[str, dict] = {}
        for name, _params in per_track:
            stages_rep[name] = {"rows_in": 0, "rows_out": 0, "counts": {}}
        prev = rows_read - quarantined
        for name, _params in per_track:
            rep = stages_rep[name]
            rep["rows_in"] = prev
            for info in infos:
                for s in info["stages"]:
                    if s["step"] == name:
                        rep["rows_out"] += s["rows_out"]
                        rep["counts"] = _add_counts(rep["counts"], s["report"])
                        if "rejected" in s:
                            rep["rejected"] = rep.get("rejected", 0) + s["rejected"]
            if name == "clean":
                _merge_break_legs(rep, infos)
            prev = rep["rows_out"] if name != "maneuvers" else prev
        if assoc:
            t = time.perf_counter()
            stages_rep["associate"] = _associate_pass(assoc, infos, stage, work, buckets)
            timings["associate_s"] = time.perf_counter() - t
    except KeyboardInterrupt:
        _quiet_interrupt()
        local.close()  # the partitions still running are finished before they are counted
        done = len(list((work / per_track[0][0]).glob("*.parquet"))) if per_track else 0
        raise BatchInterrupted(outdir, done, progress.get("partitions")) from None
    finally:
        local.close()
        if client is not None:
            _close_client(client, opts)
    try:
        folders = sorted(p for p in work.iterdir() if p.is_dir())
        if opts.csv:
            t = time.perf_counter()
            for folder in folders:
                name = folder.name
                is_points = name in ("clean", "compress", "associate")
                tracks = is_points or name == "maneuvers"
                parts_to_csv(folder, work / f"{name}.csv", points=is_points, tracks=tracks)
            timings["csv_s"] = time.perf_counter() - t
    except KeyboardInterrupt:
        raise BatchInterrupted(outdir, len(buckets), len(buckets), csv=True) from None
    outputs = {}
    for p in sorted(work.iterdir()):  # every output complete: moved into OUTDIR
        p.rename(outdir / p.name)
        outputs[p.name] = outdir / p.name
    shutil.rmtree(stage, ignore_errors=True)
    report = {
        "inputs": [str(p) for p in inputs],
        "input_bytes": in_bytes,
        "input_text_bytes": text_bytes,
        "buckets": n,
        "blocks": blocks,
        "rows_read": rows_read,
        "quarantined": quarantined,
        **lines,
        "empty_inputs": empty,
        "skipped_inputs": [{"input": name, "reason": why} for name, why in not_read],
        # inputs the importer refused (each with its reason): the rest were processed
        "refused_inputs": [{"input": name, "reason": why} for name, why in refused],
        "warnings": warnings,
        "shared_track_ids": shared,
        "steps": stages_rep,
        "timings_s": {k: round(v, 3) for k, v in timings.items()},
        "scheduler": opts.scheduler
        or (f"LocalCluster({opts.workers})" if opts.workers else f"threads({threads})"),
        "pipeline": json.loads(pipeline.to_json()),
    }
    from wakeline.core.io import write_json

    write_json(report, outdir / "report.json")
    (outdir / RUNNING).unlink(missing_ok=True)  # the batch is complete
    return BatchResult(outdir, report, outputs)


def _associate_pass(assoc, infos, stage: Path, outdir: Path, buckets: list[int]) -> dict:
    """Pass 3: the core's associate step on every track's end points, then each
    bucket's rows get the target of their track."""
    import dask

    name, params = assoc
    summaries = [i["summary"] for i in infos if i["summary"] is not None and len(i["summary"])]
    if not summaries:
        return {"rows_in": 0, "rows_out": 0}
    ends = pd.concat(summaries, ignore_index=True)
    res = STEPS[name](ends, params)
    pts = res.tables["points"]
    targets = pts[["sensor", "batch", "target"]].drop_duplicates(["sensor", "batch"])
    for table in ("pairs", "proposals"):
        _write_part(res.tables[table], outdir / f"associate_{table}", "part-00000.parquet")
    tasks = [
        dask.delayed(_apply_targets, pure=False)(b, str(stage), str(outdir), targets)
        for b in buckets
    ]
    rows = sum(dask.compute(*tasks))
    rows_in = sum(i.get("assoc_rows", 0) for i in infos)
    return {
        "rows_in": int(rows_in),
        "rows_out": int(rows),
        "end_points_read": int(len(ends)),
        "report": {k: v for k, v in res.report.items()},
        "params": params_to_json(params),
    }

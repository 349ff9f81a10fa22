"""Write tables atomically: to a temporary file beside the target, then rename.

A reader never sees a half-written file, and a failed write leaves the old file (if any)
as it was.
"""

import contextlib
import glob
import json
import os
import re
import tempfile
import time
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

from wakeline.core.errors import InputError
from wakeline.core.schema import ordered_columns

_NEEDS_QUOTES = r'[,"\r\n]|^\s|\s$'


#: A temporary file of ours: ``.NAME.PID.XXXXXXXX.part`` (older versions: ``.NAME.XXXXXXXX.part``).
_PART = re.compile(r"^\.(?P<name>.+?)\.(?:(?P<pid>\d+)\.)?[A-Za-z0-9_]{8}\.part$")
#: A temporary file without a writer's process id is stale after this long (s).
LEGACY_PART_AGE_S = 60.0


def _same_file(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # someone else's process: leave its file alone
    return True


def remove_stale_parts(path: str | Path) -> list[Path]:
    """Remove temporary ``.part`` files that an interrupted write of ``path`` left beside it.

    A file is ours when its name is ``.NAME.PID.XXXXXXXX.part`` (or the older
    ``.NAME.XXXXXXXX.part``); it is stale when that process no longer runs (or, without a
    process id, when it was last written more than ``LEGACY_PART_AGE_S`` ago). Returns the
    files removed.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    removed = []
    try:
        entries = list(folder.glob(f".{glob.escape(path.name)}.*.part"))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        m = _PART.match(entry.name)
        if not m or m["name"] != path.name:
            continue
        try:
            if m["pid"] is not None:
                stale = not _alive(int(m["pid"]))
            else:
                stale = now - entry.stat().st_mtime > LEGACY_PART_AGE_S
            if stale and entry.is_file():
                entry.unlink()
                removed.append(entry)
        except OSError:
            continue
    return removed


def check_writable(path: str | Path) -> None:
    """Refuse (:class:`InputError`) an output that is a folder, read-only, or in a folder
    that does not exist or cannot be written; an existing read-only file is never replaced."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"{path}: the folder {folder} does not exist")
    if path.is_dir():
        raise InputError(f"{path}: is a folder; give a file name to write")
    if path.exists():
        mode = path.stat().st_mode
        if not (mode & 0o222) or not os.access(path, os.W_OK):
            raise InputError(f"{path}: the file is read-only; it is not replaced")
    if not os.access(folder, os.W_OK):
        raise InputError(f"{path}: cannot write in the folder {folder} (permission denied)")


def check_outputs(
    inputs: Iterable[str | Path | None], outputs: Mapping[str, str | Path | None]
) -> None:
    """Check a run's files before any work: raise :class:`InputError` when an output is
    also an input, when two outputs are the same file, or when an output cannot be written
    (see :func:`check_writable`). ``outputs`` maps a name for messages (``--quarantine``)
    to a path; ``None`` entries are ignored."""
    ins = [Path(p) for p in inputs if p is not None]
    outs = [(name, Path(p)) for name, p in outputs.items() if p is not None]
    for name, out in outs:
        for src in ins:
            if _same_file(out, src):
                raise InputError(
                    f"{name} {out}: is also an input; write the result to another file"
                )
    for i, (name, out) in enumerate(outs):
        for other_name, other in outs[:i]:
            if _same_file(out, other):
                raise InputError(
                    f"{name} {out}: is also given as {other_name}; each output needs its own file"
                )
    for _, out in outs:
        check_writable(out)


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; rename it onto ``path`` on success.

    A read-only target is refused (never replaced), and ``.part`` files that an
    interrupted earlier write of the same target left behind are removed first.
    """
    path = Path(path)
    check_writable(path)
    remove_stale_parts(path)
    folder = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=".part", dir=folder)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        # mkstemp makes the file private (0600); give it the mode a plain open() would.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)
        os.replace(tmp_path, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
        raise


def _to_arrow(df: pd.DataFrame) -> pa.Table:
    arrays = []
    for name in df.columns:
        col = df[name]
        if isinstance(col.dtype, pd.DatetimeTZDtype) or pd.api.types.is_datetime64_any_dtype(
            col.dtype
        ):
            ts = (
                col.dt.tz_convert("UTC")
                if getattr(col.dt, "tz", None) is not None
                else col.dt.tz_localize("UTC")
            )
            arr = pa.array(ts.dt.as_unit("ns"), type=pa.timestamp("ns", "UTC"))
            arr = pc.cast(arr, pa.timestamp("ms", "UTC"), safe=False)
            arrays.append(pc.strftime(arr, format="%Y-%m-%dT%H:%M:%SZ"))
        elif pd.api.types.is_float_dtype(col.dtype):
            arrays.append(pa.array(col.to_numpy(dtype="float64"), from_pandas=True))
        elif pd.api.types.is_integer_dtype(col.dtype) or pd.api.types.is_bool_dtype(col.dtype):
            arrays.append(pa.array(col))
        else:
            arrays.append(pa.array(col.astype("str"), type=pa.string(), from_pandas=True))
    return pa.Table.from_arrays(arrays, names=[str(c) for c in df.columns])


def _quote(name: str) -> str:
    if any(ch in name for ch in ',"\r\n'):
        return '"' + name.replace('"', '""') + '"'
    return name


def write_csv(df: pd.DataFrame, path: str | Path) -> None:
    """Write any table as UTF-8 CSV atomically.

    Timestamps are written as ISO 8601 UTC with milliseconds and ``Z``; floats in their
    shortest round-trip form; missing values as empty cells; text quoted only when it
    holds a delimiter, a quote, a line break or edge blanks.
    """
    table = _to_arrow(df)
    needs_quotes = any(
        (pa.types.is_string(c.type) and pc.any(pc.match_substring_regex(c, _NEEDS_QUOTES)).as_py())
        for c in table.columns
    )
    options = pacsv.WriteOptions(
        include_header=False, quoting_style="needed" if needs_quotes else "none"
    )
    header = (",".join(_quote(str(c)) for c in df.columns) + "\n").encode("utf-8")
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(header)
            if len(df):
                pacsv.write_csv(table, fh, options)


def write_points(points: pd.DataFrame, path: str | Path) -> None:
    """Write the canonical point table (canonical columns first, extras after)."""
    write_csv(points[ordered_columns(points)], path)


def _json_default(obj):
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.floating,)):
        return None if np.isnan(obj) else float(obj)
    if isinstance(obj, (pd.Timestamp,)):
        return obj.isoformat()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def write_json(obj: object, path: str | Path) -> None:
    """Write JSON (UTF-8, indented) atomically."""
    text = json.dumps(obj, indent=2, ensure_ascii=False, default=_json_default)
    with atomic_path(path) as tmp:
        tmp.write_text(text + "\n", encoding="utf-8")

"""Write tables atomically: to a temporary file beside the target, then rename.

A reader never sees a half-written file, and a failed write leaves the old file (if any)
as it was.
"""

import contextlib
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

from wakeline.core.errors import InputError
from wakeline.core.schema import ordered_columns

_NEEDS_QUOTES = r'[,"\r\n]|^\s|\s$'


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; rename it onto ``path`` on success."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"{path}: the folder {folder} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
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

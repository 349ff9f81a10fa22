"""The canonical point table (SPEC §1).

A pandas DataFrame with the columns below; extra columns are carried through untouched.
A *track* is the rows of one ``(sensor, batch)`` sorted by time.
"""

import numpy as np
import pandas as pd

#: Column order of the canonical CSV.
CANONICAL_COLUMNS: tuple[str, ...] = ("sensor", "batch", "time", "lon", "lat", "speed", "course")
#: Columns an input must provide (``sensor`` defaults to ``DEFAULT_SENSOR``).
REQUIRED_COLUMNS: tuple[str, ...] = ("batch", "time", "lon", "lat")
#: Optional columns with a meaning of their own.
OPTIONAL_COLUMNS: tuple[str, ...] = ("sensor", "speed", "course", "truth")
DEFAULT_SENSOR = "S1"

UNITS = {
    "time": "UTC timestamp",
    "lon": "degrees WGS84, [-180, 180]",
    "lat": "degrees WGS84, [-90, 90]",
    "speed": "knots",
    "course": "degrees true, [0, 360)",
}

TIME_DTYPE = pd.DatetimeTZDtype("ns", "UTC")
EPOCH = pd.Timestamp("1970-01-01", tz="UTC")


def empty_points() -> pd.DataFrame:
    """An empty canonical table with the right dtypes."""
    return pd.DataFrame(
        {
            "sensor": pd.Series([], dtype="str"),
            "batch": pd.Series([], dtype="str"),
            "time": pd.Series([], dtype=TIME_DTYPE),
            "lon": pd.Series([], dtype="float64"),
            "lat": pd.Series([], dtype="float64"),
            "speed": pd.Series([], dtype="float64"),
            "course": pd.Series([], dtype="float64"),
        }
    )


def time_seconds(times: pd.Series | pd.DatetimeIndex) -> np.ndarray:
    """Seconds since 1970-01-01 UTC as float64, whatever the timestamp resolution."""
    delta = pd.DatetimeIndex(times) - EPOCH
    return np.asarray(delta.total_seconds(), dtype="float64")


def seconds_to_time(seconds: np.ndarray) -> pd.Series:
    """Inverse of :func:`time_seconds`: float seconds since epoch to UTC timestamps (ns)."""
    ns = np.round(np.asarray(seconds, dtype="float64") * 1e9).astype("int64")
    return pd.Series(pd.to_datetime(ns, unit="ns", utc=True)).astype(TIME_DTYPE)


#: A point's row number among the points its file gave (added where a layer is stored in
#: track order, e.g. the window's source layers): "export as it came in" writes the rows
#: in that order again. Internal: never exported.
FILE_ROW = "wl_row"


def in_file_order(points: pd.DataFrame) -> pd.DataFrame:
    """``points`` in its file's order when it carries a usable file row
    (:data:`FILE_ROW` on every row, no value twice: a source layer of the window, or one
    a step made from it without adding points), else as given. The window's File ▸
    Export CSV and Export ▸ As it came in write a layer's rows so, and
    ``wakeline export --like`` of the CSV writes IN's order: the same bytes as the
    window's As it came in (h155)."""
    if FILE_ROW not in points.columns:
        return points
    rows = pd.to_numeric(points[FILE_ROW], errors="coerce")
    if not (rows.notna().all() and rows.is_unique):
        return points
    order = np.argsort(rows.to_numpy(), kind="stable")
    if (order[1:] > order[:-1]).all():
        return points
    return points.iloc[order]


#: The courses an import changed (360.0 read as 0; 380.4 or AIS's 360 blanked), as the
#: file had them, NaN on the other rows; absent when it changed none. ``export --like``
#: writes them back where no step changed the course since. Written to the canonical CSV
#: (so ``import`` then ``export --like`` gives the file back, h155), never by a layout.
COURSE_READ = "course_read"


#: Rows pandas parses at a time in :func:`to_float`: a slice holds the GIL for ~10 ms.
PARSE_SLICE = 65_536


def to_float(col: pd.Series) -> np.ndarray:
    """float64 values of a numeric or text column; NaN where blank or unreadable (as
    ``pd.to_numeric(col, errors="coerce")``). Text is parsed by Arrow, which releases the
    GIL, and by pandas where Arrow refuses a cell, a slice at a time: a million text cells
    turned into Python objects at once hold the GIL, and so the GUI thread waiting for
    the worker, for a quarter of a second."""
    if pd.api.types.is_numeric_dtype(col.dtype):
        return col.to_numpy(dtype="float64", na_value=np.nan)
    if isinstance(col.dtype, pd.StringDtype) and col.dtype.storage == "pyarrow":
        import pyarrow as pa
        import pyarrow.compute as pc

        text = pc.utf8_trim_whitespace(pa.array(col))
        blank = pc.equal(pc.utf8_length(text), 0)
        try:
            values = pc.cast(pc.if_else(blank, pa.scalar(None, text.type), text), pa.float64())
            return values.to_numpy(zero_copy_only=False)
        except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError):
            pass
    parts = [
        pd.to_numeric(col.iloc[a : a + PARSE_SLICE], errors="coerce").to_numpy(
            dtype="float64", na_value=np.nan
        )
        for a in range(0, len(col), PARSE_SLICE)
    ]
    return np.concatenate(parts) if parts else np.zeros(0, dtype="float64")


def ordered_columns(df: pd.DataFrame) -> list[str]:
    """Canonical columns first (those present), then the extra columns in their order."""
    head = [c for c in CANONICAL_COLUMNS if c in df.columns]
    if "truth" in df.columns:
        head.append("truth")
    return head + [c for c in df.columns if c not in head]


#: Clean's row id (``core/clean.py``): it keys the reject trail (``--rejected`` keeps
#: it) and the in-memory restore, and is never written with points (operator test 7,
#: D18: it showed in the clean, associate and review CSVs and the window's Export CSV).
ROW_ID = "wl_id"
#: Columns Wakeline keeps on its points while it works and a points file never gets.
UNWRITTEN = frozenset((FILE_ROW, ROW_ID))


def written_columns(df: pd.DataFrame) -> list[str]:
    """The columns a points file gets: :func:`ordered_columns` without the window's
    internal file row (:data:`FILE_ROW`) and clean's row id (:data:`ROW_ID`)."""
    return [c for c in ordered_columns(df) if c not in UNWRITTEN]

"""Times for the operator: dates in UTC, or elapsed time for scene-relative data.

MTAD and the Øresund encounters count seconds from a scene start; the importer reads those
as seconds after 1970-01-01. Shown as dates they would read "1970-01-01 00:16:23"; they
are shown as elapsed time ``T+0:16:23`` instead.
"""

import math

import numpy as np
import pandas as pd

#: Times below this many seconds since 1970 (i.e. before 1980) are read as elapsed time
#: from a scene start (MTAD, Øresund), not as dates: no radar/AIS export is that old.
RELATIVE_LIMIT_S = 10 * 365.25 * 86400.0


def is_relative_time(time_s: np.ndarray) -> bool:
    """True when times (s since 1970) are small: elapsed time from a scene start."""
    finite = time_s[np.isfinite(time_s)]
    return bool(len(finite)) and float(finite.max()) < RELATIVE_LIMIT_S


def format_elapsed(seconds: float) -> str:
    """``T+h:mm:ss`` (``T+2 d 03:04:05`` beyond a day; tenths when not whole)."""
    if not math.isfinite(seconds):
        return "—"
    sign = "-" if seconds < 0 else "+"
    s = abs(seconds)
    days, rest = divmod(s, 86400.0)
    h, rest = divmod(rest, 3600.0)
    m, sec = divmod(rest, 60.0)
    sec_text = f"{sec:04.1f}" if abs(sec - round(sec)) > 0.05 else f"{round(sec) % 60:02d}"
    clock = f"{int(h):d}:{int(m):02d}:{sec_text}"
    if days:
        clock = f"{int(days)} d {int(h):02d}:{int(m):02d}:{sec_text}"
    return f"T{sign}{clock}"


def format_time(seconds: float, relative: bool) -> str:
    """A time for the operator: elapsed (``T+…``) when ``relative``, else a UTC date."""
    if not math.isfinite(seconds):
        return "—"
    if relative:
        return format_elapsed(seconds)
    ts = pd.Timestamp(round(seconds * 1000.0), unit="ms", tz="UTC")
    text = ts.strftime("%Y-%m-%d %H:%M:%S")
    return text + (f".{ts.microsecond // 1000:03d}" if ts.microsecond else "") + " UTC"


def format_times(seconds: np.ndarray, relative: bool) -> list[str]:
    """:func:`format_time` of every value (for a table column)."""
    return [format_time(float(v), relative) for v in np.asarray(seconds, dtype="float64")]

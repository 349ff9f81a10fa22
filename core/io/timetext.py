"""Time texts beyond ISO 8601 and slashed dates (docs/import.md "Times"): dates with
English month names (``01-Jan-2024 00:00:05``, ``Jan 1, 2024 12:00:05 PM``, C's asctime
``Mon Jan 01 00:00:05 2024``), Chinese dates (``2024年1月1日 00:00:05``), clock times
without a date (``23:50:00.5``) and clock times written as numbers (``120059``, HHMMSS).

Every parse here is vectorised (pandas string ops and arithmetic, no Python loop per row)
and reads each row on its own: a piece of a file reads its rows as the whole file does.
Month names and Chinese dates become ISO 8601 text, read by the importer's ISO path (zones
and ``--tz`` as for ISO text); clock times become seconds of the day.
"""

import datetime
import re

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core.errors import InputError

#: English month names as written (lower case): full, three letters, and "sept".
_MONTHS = {
    name: k + 1
    for k, full in enumerate(
        (
            "january",
            "february",
            "march",
            "april",
            "may",
            "june",
            "july",
            "august",
            "september",
            "october",
            "november",
            "december",
        )
    )
    for name in (full, full[:3])
} | {"sept": 9}

#: A weekday before a date (``Mon``, ``Monday,``): read past, not checked against the date.
_WEEKDAY = r"(?:(?:mon|tue|tues|wed|thu|thur|thurs|fri|sat|sun)[a-z]*\.?,?\s+)?"
#: A clock after a date: ``00:00:05``, ``00.00.05`` (Oracle), ``12:00:05.123``, ``8:01 PM``.
_TIME = (
    r"(?P<H>\d{1,2})[:.](?P<M>\d{2})(?:[:.](?P<S>\d{2})(?:[.,](?P<F>\d{1,9}))?)?"
    r"(?:\s*(?P<P>[ap])\.?\s?m\.?)?"
)
#: A zone after the clock: ``Z``, ``UTC``, ``GMT``, ``+08:00``, ``+0800`` (others: not read).
_ZONE = r"(?:\s*(?P<Z>z|utc|gmt|[+-]\d\d:?\d\d))?"
_END = r"\s*$"
#: The month-name layouts (lower-cased text), tried in turn on the rows still unread.
_NAMED = tuple(
    re.compile(p)
    for p in (
        # 01-Jan-2024 00:00:05, 01-JAN-24 00.00.05, 1 January 2024 00:00:05,
        # Mon, 01 Jan 2024 00:00:05 +0000 (e-mail), 01/Jan/2024:00:00:05 +0000 (web logs)
        r"^\s*" + _WEEKDAY + r"(?P<d>\d{1,2})(?:st|nd|rd|th)?[-/ .]\s*(?P<mon>[a-z]{3,9})\.?"
        r"[-/ .,]\s*(?P<y>\d{4}|\d{2})(?:(?:\s+|t|:|,\s*)" + _TIME + r")?" + _ZONE + _END,
        # Jan 1, 2024 12:00:05 PM, January 01 2024 00:00:05, Monday, January 1, 2024 ...
        r"^\s*" + _WEEKDAY + r"(?P<mon>[a-z]{3,9})\.?\s+(?P<d>\d{1,2})(?:st|nd|rd|th)?,?\s+"
        r"(?P<y>\d{4})(?:(?:\s+|,\s*|t)" + _TIME + r")?" + _ZONE + _END,
        # Mon Jan 01 00:00:05 2024 (C asctime), Mon Jan  1 00:00:05 UTC 2024 (date)
        r"^\s*"
        + _WEEKDAY
        + r"(?P<mon>[a-z]{3,9})\s+(?P<d>\d{1,2})\s+"
        + _TIME
        + r"(?:\s+(?P<Z>utc|gmt|z))?\s+(?P<y>\d{4})"
        + _END,
        # 2024-Jan-01 00:00:05
        r"^\s*(?P<y>\d{4})[-/ ](?P<mon>[a-z]{3,9})[-/ ](?P<d>\d{1,2})(?:(?:\s+|t)"
        + _TIME
        + r")?"
        + _ZONE
        + _END,
    )
)
#: Chinese dates: 2024年1月1日 00:00:05, 2024年01月01日 00时00分05秒, 2024年1月1日00:00:05,
#: 2024年1月1日 下午3:00:05 (上午/下午: morning/afternoon), with a zone as above.
_CHINESE = re.compile(
    r"^\s*(?P<y>\d{4})\s*年\s*(?P<mon>\d{1,2})\s*月\s*(?P<d>\d{1,2})\s*[日号]\s*"
    r"(?:(?P<P>上午|下午|凌晨|早上|中午|晚上)?\s*(?P<H>\d{1,2})\s*[:时點点]\s*(?P<M>\d{1,2})\s*"
    r"(?:[:分]\s*(?:(?P<S>\d{1,2})(?:[.,](?P<F>\d{1,9}))?\s*秒?)?)?)?" + _ZONE + _END,
    flags=re.IGNORECASE,
)
#: Afternoon words of a Chinese 12-hour clock (the others are before noon).
_CHINESE_PM = ("下午", "晚上", "中午")
#: A clock time alone: ``23:50:00.5``, ``8:01 PM``, ``23:50`` (seconds optional).
_CLOCK = re.compile(
    r"^\s*(?P<H>\d{1,2}):(?P<M>\d{2})(?::(?P<S>\d{2})(?:[.,](?P<F>\d{1,9}))?)?"
    r"(?:\s*(?P<P>[AaPp])\.?\s?[Mm]\.?)?\s*$"
)


def _num(col: pd.Series) -> pd.Series:
    return pd.to_numeric(col, errors="coerce")


def _hours(parts: pd.DataFrame, pm: pd.Series | None = None) -> pd.Series:
    """The 24-hour hour of extracted clock parts: a 12-hour clock (``P``: ``a``/``p``, or
    ``pm`` given) maps 12 AM to 0 and 1-11 PM to 13-23; an hour above 12 with AM/PM, or
    above 23, is NaN (unparsable)."""
    hour = _num(parts["H"])
    mark = parts["P"].astype("str").str.lower() if "P" in parts else None
    if pm is None and mark is not None:
        twelve = parts["P"].notna()
        pm = twelve & mark.str.startswith("p")
    elif pm is not None:
        twelve = parts["P"].notna()
    else:
        return hour.where(hour <= 23)
    hour = hour.where(~twelve | ((hour >= 1) & (hour <= 12)))
    hour = hour.where(~twelve, (hour % 12) + np.where(pm, 12, 0))
    return hour.where(hour <= 23)


def _fraction(parts: pd.DataFrame) -> pd.Series:
    """The fraction of a second as text (``.5``, empty when none)."""
    f = parts["F"]
    return ("." + f.astype("str")).where(f.notna(), "")


def _zone(parts: pd.DataFrame) -> pd.Series:
    """The zone as ISO text (``Z``, ``+08:00``; empty: none written)."""
    z = parts["Z"].astype("str").str.upper()
    z = z.where(~z.isin(("UTC", "GMT", "Z")), "Z")
    z = z.str.replace(r"^([+-]\d\d):?(\d\d)$", r"\1:\2", regex=True)
    return z.where(parts["Z"].notna(), "")


def _iso(parts: pd.DataFrame, month: pd.Series, year: pd.Series, hour: pd.Series) -> pd.Series:
    """ISO 8601 text of extracted parts (NaN where a part is missing or out of range; the
    ISO parser then refuses days a month has not, 2023-02-30)."""
    day, minute = _num(parts["d"]), _num(parts["M"]).fillna(0)
    second = _num(parts["S"]).fillna(0)
    timed = parts["H"].notna()
    hour = hour.where(timed, 0)
    good = (
        month.between(1, 12)
        & day.between(1, 31)
        & year.notna()
        & hour.notna()
        & minute.between(0, 59)
        & second.between(0, 59)  # no leap second (pandas has none)
    )

    def two(s: pd.Series) -> pd.Series:
        return s.fillna(0).astype("int64").astype("str").str.zfill(2)

    iso = (
        year.fillna(0).astype("int64").astype("str").str.zfill(4)
        + "-"
        + two(month)
        + "-"
        + two(day)
        + "T"
        + two(hour)
        + ":"
        + two(minute)
        + ":"
        + two(second)
        + _fraction(parts)
        + _zone(parts)
    )
    return iso.where(good)


def _year(y: pd.Series) -> pd.Series:
    """Four-digit years; two digits as strptime's ``%y`` reads them (69-99: 1900s,
    00-68: 2000s: ``01-JAN-24`` is 2024)."""
    n = _num(y)
    short = y.astype("str").str.len() == 2
    return n.where(~short, n + np.where(n < 69, 2000, 1900))


def named_iso(text: pd.Series) -> pd.Series:
    """ISO 8601 text of the rows of ``text`` written with an English month name (layouts
    in :data:`_NAMED`), NaN elsewhere."""
    out = pd.Series(np.nan, index=text.index, dtype="object")
    left = text.str.lower()
    for pattern in _NAMED:
        if not len(left):
            break
        parts = left.str.extract(pattern)
        month = parts["mon"].map(_MONTHS).astype("float64")
        hit = month.notna()
        if not hit.any():
            continue
        parts, month = parts[hit], month[hit]
        iso = _iso(parts, month, _year(parts["y"]), _hours(parts))
        out[iso.index] = iso
        left = left[~hit]
    return out.astype("str").where(out.notna())


def chinese_iso(text: pd.Series) -> pd.Series:
    """ISO 8601 text of the rows of ``text`` written as Chinese dates (年月日, 时分秒,
    上午/下午), NaN elsewhere."""
    parts = text.str.extract(_CHINESE)
    hit = parts["y"].notna()
    out = pd.Series(np.nan, index=text.index, dtype="object")
    if not hit.any():
        return out
    parts = parts[hit]
    pm = parts["P"].isin(_CHINESE_PM)
    iso = _iso(parts, _num(parts["mon"]), _num(parts["y"]), _hours(parts, pm))
    out[iso.index] = iso
    return out.astype("str").where(out.notna())


#: Text that may hold a month name or a Chinese date (rows without it are not looked at).
NAMED_HINT = r"[A-Za-z]{3}|年"


def clock_seconds(text: pd.Series) -> pd.Series:
    """Seconds of the day (float) of clock times alone (``23:50:00.5``, ``8:01 PM``), NaN
    where a value is not one (or is out of range: 24:00, 12-hour 13 PM)."""
    parts = text.str.extract(_CLOCK)
    hour = _hours(parts)
    minute, second = _num(parts["M"]), _num(parts["S"]).fillna(0)
    frac = _num("0." + parts["F"].astype("str")).where(parts["F"].notna(), 0.0)
    sod = hour * 3600 + minute * 60 + second + frac
    return sod.where(minute.between(0, 59) & second.between(0, 59))


#: :data:`_CLOCK` without its groups, for Arrow's regex engine (4x pandas' on 2 M rows).
_CLOCK_ARROW = r"^\s*\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d{1,9})?)?(?:\s*[AaPp]\.?\s?[Mm]\.?)?\s*$"


def is_clock(text: pd.Series) -> pd.Series:
    """Whether each value is a clock time alone (``23:50:00.5``)."""
    arr = pa.array(text, from_pandas=True)  # Arrow-backed text: no copy
    if not pa.types.is_string(arr.type) and not pa.types.is_large_string(arr.type):
        arr = pc.cast(arr, pa.string())
    hit = pc.fill_null(pc.match_substring_regex(arr, _CLOCK_ARROW), False)
    return pd.Series(np.asarray(hit, dtype=bool), index=text.index)


def check_clock_date(value: str | datetime.date | None) -> str | None:
    """``value`` as ``YYYY-MM-DD`` (None stays None); else :class:`InputError`."""
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    if isinstance(value, datetime.date):
        return value.isoformat()[:10]
    try:
        return datetime.date.fromisoformat(str(value).strip()).isoformat()
    except ValueError:
        raise InputError(
            f"--date {value!r}: give the day of clock-only times as YYYY-MM-DD (2024-01-31)"
        ) from None


def day_ns(clock_date: str | None) -> int:
    """ns since 1970 of the day's midnight (1970-01-01 when None)."""
    if clock_date is None:
        return 0
    day = datetime.date.fromisoformat(clock_date)
    return (day - datetime.date(1970, 1, 1)).days * 86_400_000_000_000


def sod_ns(seconds: np.ndarray) -> np.ndarray:
    """Seconds of the day (float, NaN: none) to int64 ns, to the ns their text held (the
    whole and fractional seconds apart: 0.1 is 100_000_000 ns, not 99_999_999)."""
    x = np.where(np.isfinite(seconds), seconds, 0.0)
    whole = np.floor(x)
    return whole.astype("int64") * 1_000_000_000 + np.round((x - whole) * 1e9).astype("int64")


#: A clock stepping back by more than this within a track has passed midnight (s).
ROLLOVER_BACK_S = 12 * 3600.0


def roll_days(track: np.ndarray, ns: np.ndarray, ok: np.ndarray) -> tuple[np.ndarray, int]:
    """Clock times (ns from a day's midnight) with a day added at each step back of more
    than :data:`ROLLOVER_BACK_S` in a track's rows, in file order (23:59:59 then 00:00:01
    is the next day), and how many such rollovers there were. ``ok``: the rows with a
    time (the others are skipped, left as they are)."""
    rows = np.flatnonzero(ok)
    if len(rows) < 2:
        return ns, 0
    frame = pd.DataFrame({"track": track[rows], "t": ns[rows]})
    back = (frame.groupby("track", sort=False)["t"].diff() < -ROLLOVER_BACK_S * 1e9).astype("int64")
    days = back.groupby(frame["track"], sort=False).cumsum().to_numpy()
    out = np.array(ns, dtype="int64", copy=True)
    out[rows] += days * 86_400_000_000_000
    return out, int(back.sum())


def valid_hhmmss(values: np.ndarray) -> bool:
    """Whether every finite value (and one at least) is a whole number 0-235959 whose
    last two digits and middle two are below 60 (a clock written HHMMSS)."""
    finite = values[np.isfinite(values)]
    if not len(finite):
        return False
    if not ((finite >= 0) & (finite <= 235959) & (finite == np.floor(finite))).all():
        return False
    v = finite.astype("int64")
    return not (((v % 100) >= 60).any() or (((v // 100) % 100) >= 60).any())


def hhmmss_evidence(values: np.ndarray) -> tuple[int, int] | None:
    """Whether numbers are clock times written HHMMSS (``120059`` then ``120100``), and
    the step that shows it (``(120059, 120100)``), else None.

    Conservative: every finite value is a whole number 0-235959 whose last two digits
    (seconds) and middle two (minutes) are below 60; the distinct values, in order, step
    across a minute at least once (a raw step that skips 40 or more numbers no clock
    second can be), and at half the minutes passed at least, read as a clock, the step
    is no longer than twice the column's typical clock step, which is below 20 s (a
    column of seconds with such steps would have landed on a number ending 60-99; a gap
    in the recording may pass a minute or an hour in one step). A column of relative
    seconds that never passes 59 within a minute, or steps irregularly, stays seconds."""
    finite = values[np.isfinite(values)]
    if len(finite) < 3 or not valid_hhmmss(finite):
        return None
    distinct = np.unique(finite.astype("int64"))
    if len(distinct) < 3:
        return None
    clock = (distinct // 10000) * 3600 + ((distinct // 100) % 100) * 60 + distinct % 100
    raw, step = np.diff(distinct), np.diff(clock)
    across = (distinct[1:] // 100) != (distinct[:-1] // 100)
    if not across.any() or across.all():
        return None
    typical = float(np.median(step[~across]))
    regular = across & (step <= 2 * max(typical, 1.0)) & (raw >= 41)
    if typical >= 20 or regular.sum() < 0.5 * across.sum():
        return None  # most minutes passed in gaps: no clock shows
    k = int(np.flatnonzero(regular)[0])
    return int(distinct[k]), int(distinct[k + 1])


def hhmmss_seconds(values: np.ndarray) -> np.ndarray:
    """HHMMSS numbers to seconds of the day (NaN stays NaN)."""
    v = np.where(np.isfinite(values), values, 0).astype("int64")
    sod = (v // 10000) * 3600 + ((v // 100) % 100) * 60 + v % 100
    return np.where(np.isfinite(values), sod.astype("float64"), np.nan)


__all__ = [
    "NAMED_HINT",
    "ROLLOVER_BACK_S",
    "check_clock_date",
    "chinese_iso",
    "clock_seconds",
    "day_ns",
    "hhmmss_evidence",
    "hhmmss_seconds",
    "is_clock",
    "named_iso",
    "roll_days",
    "sod_ns",
    "valid_hhmmss",
]

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

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core import sorted_sets
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
#: Month names in German, French, Spanish, Portuguese, Italian, Dutch, Norwegian, Swedish
#: and Danish as written (lower case; full, and the abbreviations their locales write,
#: with and without accents): month by month, every name means the same month in every
#: language that writes it (``mar`` March, ``mai`` May, ``des`` December).
_OTHER_MONTHS = (
    "januar januari jänner jaenner jän jaen janvier janv enero ene janeiro gennaio gen",
    "februar februari février fevrier févr fevr fév fev febrero fevereiro febbraio",
    "märz maerz mär maer mars marts marzo março marco maart mrt",
    "avril avr abril abr aprile",
    "mai mayo maio maggio mag mei maj",
    "juni juin junio junho giugno giu",
    "juli juillet juil julio julho luglio lug",
    "augusti août aout aoû aou agosto ago augustus",
    "septembre septiembre setiembre setembro settembre set",
    "oktober octobre octubre outubro out ottobre ott okt",
    "novembre noviembre novembro",
    "dezember décembre decembre déc dezembro diciembre dicembre dic dez desember des",
)
_MONTHS |= {name: k + 1 for k, names in enumerate(_OTHER_MONTHS) for name in names.split()}
#: A month's word in the patterns below (lower-cased text; letters with accents too).
_MON = r"[a-zà-ɏ]{3,10}"

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
    p
    for p in (
        # 01-Jan-2024 00:00:05, 01-JAN-24 00.00.05, 1 January 2024 00:00:05,
        # Mon, 01 Jan 2024 00:00:05 +0000 (e-mail), 01/Jan/2024:00:00:05 +0000 (web logs)
        # other languages: 01-Mär-2024, 1 janv. 2024, 3. März 2024, 1er janvier 2024,
        # 15 de enero de 2024 (Spanish, Portuguese)
        r"^\s*" + _WEEKDAY + r"(?P<d>\d{1,2})(?:st|nd|rd|th|er|º|ª)?[-/ .]\s*(?:de\s+)?"
        r"(?P<mon>" + _MON + r")\.?(?:\s+de)?"
        r"[-/ .,]\s*(?P<y>\d{4}|\d{2})(?:(?:\s+|t|:|,\s*)" + _TIME + r")?" + _ZONE + _END,
        # Jan 1, 2024 12:00:05 PM, January 01 2024 00:00:05, Monday, January 1, 2024 ...
        r"^\s*" + _WEEKDAY + r"(?P<mon>[a-z]{3,9})\.?\s+(?P<d>\d{1,2})(?:st|nd|rd|th)?,?\s+"
        r"(?P<y>\d{4})(?:(?:\s+|,\s*|t)" + _TIME + r")?" + _ZONE + _END,
        # Mon Jan 01 00:00:05 2024 (C asctime), Mon Jan  1 00:00:05 UTC 2024 (date)
        r"^\s*"
        + _WEEKDAY
        + r"(?P<mon>[a-z]{3,9})\s+(?P<d>\d{1,2})\s+"
        + _TIME
        + r"(?:\s*(?P<Z>utc|gmt|z|[+-]\d\d:?\d\d))?\s+(?P<y>\d{4})"
        + _END,
        # 2024-Jan-01 00:00:05
        r"^\s*(?P<y>\d{4})[-/ ](?P<mon>"
        + _MON
        + r")\.?[-/ ](?P<d>\d{1,2})(?:(?:\s+|t)"
        + _TIME
        + r")?"
        + _ZONE
        + _END,
    )
)
#: Chinese dates: 2024年1月1日 00:00:05, 2024年01月01日 00时00分05秒, 2024年1月1日00:00:05,
#: 2024年1月1日 下午3:00:05 (上午/下午: morning/afternoon), with a zone as above.
_CHINESE = (
    r"(?i)^\s*(?P<y>\d{4})\s*年\s*(?P<mon>\d{1,2})\s*月\s*(?P<d>\d{1,2})\s*[日号]\s*"
    r"(?:(?P<P>上午|下午|凌晨|早上|中午|晚上)?\s*(?P<H>\d{1,2})\s*[:时點点]\s*(?P<M>\d{1,2})\s*"
    r"(?:[:分]\s*(?:(?P<S>\d{1,2})(?:[.,](?P<F>\d{1,9}))?\s*秒?)?)?)?" + _ZONE + _END
)
#: Afternoon words of a Chinese 12-hour clock (the others are before noon).
_CHINESE_PM = ("下午", "晚上", "中午")
#: A clock time alone: ``23:50:00.5``, ``8:01 PM``, ``23:50`` (seconds optional).
_CLOCK = (
    r"^\s*(?P<H>\d{1,2}):(?P<M>\d{2})(?::(?P<S>\d{2})(?:[.,](?P<F>\d{1,9}))?)?"
    r"(?:\s*(?P<P>[AaPp])\.?\s?[Mm]\.?)?\s*$"
)


def _arrow(text: pd.Series) -> pa.Array:
    """``text`` as an Arrow string array (no copy for Arrow-backed text)."""
    arr = pa.array(text, from_pandas=True)
    if isinstance(arr, pa.ChunkedArray):
        arr = arr.combine_chunks()
    if not (pa.types.is_string(arr.type) or pa.types.is_large_string(arr.type)):
        arr = pc.cast(arr, pa.string())
    return arr


def _extract(arr: pa.Array, pattern: str) -> tuple[dict[str, pa.Array], np.ndarray]:
    """The named groups of ``pattern`` (Arrow's regex engine, RE2: one pass in C++, not
    a Python call per row) in each value of ``arr`` (``""`` for a group that took no
    part), and which values matched."""
    got = pc.extract_regex(arr, pattern)
    # each group as plain text (short: digits, a month name), whatever the input's type
    parts = {
        f.name: pc.cast(pc.struct_field(got, [k]), pa.string()) for k, f in enumerate(got.type)
    }
    return parts, np.asarray(pc.fill_null(pc.is_valid(got), False), dtype=bool)


def _num(part: pa.Array) -> np.ndarray:
    """The digits of an extracted group as floats (NaN: empty or not matched)."""
    empty = pc.fill_null(pc.equal(part, ""), True)
    text = pc.if_else(empty, pa.scalar("0", part.type), part)
    out = pc.cast(text, pa.float64()).to_numpy(zero_copy_only=False)
    return np.where(np.asarray(empty, dtype=bool), np.nan, out)


def _given(part: pa.Array) -> np.ndarray:
    """Whether an extracted group took part (not empty, matched)."""
    return np.asarray(pc.fill_null(pc.not_equal(part, ""), False), dtype=bool)


def _hours(parts: dict, pm: np.ndarray | None = None) -> np.ndarray:
    """The 24-hour hour of extracted clock parts: a 12-hour clock (``P``: ``a``/``p``, or
    ``pm`` given) maps 12 AM to 0 and 1-11 PM to 13-23; an hour above 12 with AM/PM, or
    above 23, is NaN (unparsable)."""
    hour = _num(parts["H"])
    twelve = _given(parts["P"])
    if pm is None:
        first = pc.utf8_lower(pc.utf8_slice_codeunits(parts["P"], 0, 1))
        pm = np.asarray(pc.fill_null(pc.equal(first, "p"), False), dtype=bool)
    with np.errstate(invalid="ignore"):
        hour = np.where(twelve & ((hour < 1) | (hour > 12)), np.nan, hour)
        hour = np.where(twelve, hour % 12 + np.where(pm, 12, 0), hour)
        return np.where(hour <= 23, hour, np.nan)


def _pad(x: np.ndarray, width: int) -> pa.Array:
    """Whole numbers as text, zero-padded to ``width``."""
    whole = pa.array(np.nan_to_num(x).astype("int64"))
    return pc.utf8_lpad(pc.cast(whole, pa.string()), width, "0")


def _iso(
    parts: dict, matched: np.ndarray, month: np.ndarray, year: np.ndarray, hour: np.ndarray
) -> pa.Array:
    """ISO 8601 text of extracted parts (null where a part is missing or out of range;
    the ISO parser then refuses days a month has not, 2023-02-30)."""
    day = _num(parts["d"])
    minute, second = np.nan_to_num(_num(parts["M"])), np.nan_to_num(_num(parts["S"]))
    hour = np.where(_given(parts["H"]), hour, 0.0)
    with np.errstate(invalid="ignore"):
        good = (
            matched
            & (month >= 1)
            & (month <= 12)
            & (day >= 1)
            & (day <= 31)
            & np.isfinite(year)
            & np.isfinite(hour)
            & (minute <= 59)
            & (second <= 59)  # no leap second (pandas has none)
        )
    frac = pc.if_else(
        pa.array(_given(parts["F"])),
        pc.binary_join_element_wise(".", parts["F"], ""),
        "",
    )
    z = pc.utf8_upper(parts["Z"])
    z = pc.if_else(pc.is_in(z, pa.array(["UTC", "GMT", "Z"])), "Z", z)
    z = pc.replace_substring_regex(z, r"^([+-]\d\d):?(\d\d)$", r"\1:\2")
    iso = pc.binary_join_element_wise(
        _pad(year, 4),
        "-",
        _pad(month, 2),
        "-",
        _pad(day, 2),
        "T",
        _pad(hour, 2),
        ":",
        _pad(minute, 2),
        ":",
        _pad(second, 2),
        frac,
        pc.fill_null(z, ""),
        "",
    )
    return pc.if_else(pa.array(good), iso, pa.scalar(None, pa.string()))


def _year(y: pa.Array) -> np.ndarray:
    """Four-digit years; two digits as strptime's ``%y`` reads them (69-99: 1900s,
    00-68: 2000s: ``01-JAN-24`` is 2024)."""
    n = _num(y)
    short = np.asarray(pc.fill_null(pc.equal(pc.utf8_length(y), 2), False), dtype=bool)
    with np.errstate(invalid="ignore"):
        return np.where(short, n + np.where(n < 69, 2000, 1900), n)


def _series(iso: pa.Array, index: pd.Index) -> pd.Series:
    """ISO text (null: NaN) as a Series on ``index``."""
    out = pd.Series(iso.to_pandas(), dtype="str")
    out.index = index
    return out


#: Month names (lower case) in order of :data:`_MONTH_NUMBERS`, for Arrow's lookup.
_MONTH_NAMES = pa.array(list(_MONTHS))
_MONTH_NUMBERS = np.array(list(_MONTHS.values()) + [np.nan], dtype="float64")


def named_iso(text: pd.Series) -> pd.Series:
    """ISO 8601 text of the rows of ``text`` written with an English month name (layouts
    in :data:`_NAMED`, each tried on the rows still unread; a quick match first, the
    groups taken out of the rows that match only), NaN elsewhere."""
    arr = pc.utf8_lower(_arrow(text))
    out = np.full(len(arr), None, dtype=object)
    left = np.arange(len(arr))
    for pattern in _NAMED:
        if not len(left):
            break
        sub = arr if len(left) == len(arr) else arr.take(pa.array(left))
        hit = np.asarray(pc.fill_null(pc.match_substring_regex(sub, pattern), False), bool)
        if not hit.any():
            continue
        rows = left[hit]
        parts, matched = _extract(sub.filter(pa.array(hit)), pattern)
        at = pc.fill_null(pc.index_in(parts["mon"], value_set=_MONTH_NAMES), -1)
        month = _MONTH_NUMBERS[np.asarray(at)]
        matched &= np.isfinite(month)
        iso = _iso(parts, matched, month, _year(parts["y"]), _hours(parts))
        out[rows] = iso.to_numpy(zero_copy_only=False)
        left = left[~hit]
    return pd.Series(out, index=text.index, dtype="str")


def chinese_iso(text: pd.Series) -> pd.Series:
    """ISO 8601 text of the rows of ``text`` written as Chinese dates (年月日, 时分秒,
    上午/下午), NaN elsewhere."""
    parts, matched = _extract(_arrow(text), _CHINESE)
    if not matched.any():
        return _series(pa.nulls(len(text), pa.string()), text.index)
    pm = np.asarray(pc.fill_null(pc.is_in(parts["P"], pa.array(_CHINESE_PM)), False))
    iso = _iso(parts, matched, _num(parts["mon"]), _num(parts["y"]), _hours(parts, pm))
    return _series(iso, text.index)


#: Zone words after a clock and the offset from UTC each stands for (upper case).
ZONE_WORDS = {
    **dict.fromkeys(("UTC", "GMT", "UT", "Z", "WET"), "+00:00"),  # UTC+8: the offset
    **dict.fromkeys(("CET", "MEZ", "WEST"), "+01:00"),
    **dict.fromkeys(("CEST", "MESZ", "EET", "CAT", "SAST"), "+02:00"),
    **dict.fromkeys(("EEST", "MSK", "EAT"), "+03:00"),
    "PKT": "+05:00",
    **dict.fromkeys(("ICT", "WIB"), "+07:00"),
    **dict.fromkeys(("HKT", "SGT", "AWST", "MYT", "PHT"), "+08:00"),
    **dict.fromkeys(("JST", "KST"), "+09:00"),
    "ACST": "+09:30",
    "AEST": "+10:00",
    "ACDT": "+10:30",
    "AEDT": "+11:00",
    "NZST": "+12:00",
    "NZDT": "+13:00",
    "NDT": "-02:30",
    **dict.fromkeys(("BRT", "ART", "ADT"), "-03:00"),
    "NST": "-03:30",
    "EDT": "-04:00",
    **dict.fromkeys(("EST", "CDT"), "-05:00"),
    "MDT": "-06:00",
    **dict.fromkeys(("MST", "PDT"), "-07:00"),
    **dict.fromkeys(("PST", "AKDT"), "-08:00"),
    "AKST": "-09:00",
    "HST": "-10:00",
}
#: Zone words that name more than one zone: not read without --tz (then read in it).
AMBIGUOUS_ZONES = {
    "CST": "US Central -06:00, China +08:00, Cuba -05:00",
    "IST": "India +05:30, Ireland +01:00, Israel +02:00",
    "AST": "Atlantic -04:00, Arabia +03:00",
    "BST": "British Summer +01:00, Bangladesh +06:00",
    "GST": "Gulf +04:00, South Georgia -02:00",
    "SST": "Samoa -11:00, Singapore +08:00",
    "ECT": "Ecuador -05:00, Eastern Caribbean -04:00",
}
#: A zone word after a clock (``00:00:05 CET``, ``12:00 PM EST``, ``00:00:05 UTC+8``,
#: ``GMT+01:00``), before a year too (``date``'s ``Mon Jan  1 00:00:05 CET 2024``).
_ZONE_WORD = (
    r"^(?P<pre>.*\d[:.]\d\d(?:[.,]\d+)?(?:\s*[AaPp]\.?\s?[Mm]\.?)?)\s*\(?(?P<w>[A-Za-z]{1,5})\)?"
    r"(?:\s*(?P<o>[+-])\s*(?P<oh>\d{1,2})(?::?(?P<om>\d\d))?)?(?P<post>\s+\d{4})?\s*$"
)


#: What a text with a zone word ends in (a letter, a bracket, an offset, a year after).
_ZONE_TAIL = r"[A-Za-z]\)?\s*(?:[+-]\s*\d{1,2}(?::?\d\d)?)?(?:\s+\d{4})?\s*$"


def zone_words(text: pd.Series, tz_given: bool) -> tuple[pd.Series, dict, dict]:
    """``text`` with each zone word after a clock (:data:`ZONE_WORDS`) written as its
    offset (``2024-01-01 00:00:05 CET`` is ``2024-01-01 00:00:05+01:00``; ``UTC+8``
    ``+08:00``); an ambiguous one (:data:`AMBIGUOUS_ZONES`) dropped when ``tz_given``
    (the time is then read in --tz), else left as it is. Returns the text, the words
    read by count, and the ambiguous words left by a mask of their rows (positions in
    ``text``). Unknown words stay (the row is unparsable as before)."""
    arr = _arrow(text)
    # a quick look first: most texts (01-Jan-2024 00:00:05) end in no word
    tail = pc.match_substring_regex(arr, _ZONE_TAIL)
    if not pc.any(pc.fill_null(tail, False)).as_py():
        return text, {}, {}
    parts, matched = _extract(arr, _ZONE_WORD)
    if not matched.any():
        return text, {}, {}
    word = pc.utf8_upper(parts["w"])
    sign, hours, mins = parts["o"], parts["oh"], parts["om"]
    utc = np.asarray(pc.fill_null(pc.is_in(word, pa.array(["UTC", "GMT", "UT"])), False))
    with_offset = _given(sign)
    offset = pc.binary_join_element_wise(
        sign,
        pc.utf8_lpad(hours, 2, "0"),
        ":",
        pc.if_else(pa.array(_given(mins)), mins, pa.scalar("00", pa.string())),
        "",
    )
    named = pc.fill_null(pc.index_in(word, value_set=pa.array(list(ZONE_WORDS))), -1).to_numpy(
        zero_copy_only=False
    )
    fixed = np.asarray(list(ZONE_WORDS.values()) + [""], dtype=object)[named]
    hour_ok = np.nan_to_num(_num(hours), nan=99) <= 14
    read = matched & (named >= 0) & (~with_offset | (utc & hour_ok))
    ambiguous = (
        np.asarray(pc.fill_null(pc.is_in(word, pa.array(list(AMBIGUOUS_ZONES))), False))
        & matched
        & ~with_offset
    )
    new = pc.if_else(pa.array(with_offset), offset, pa.array(fixed, pa.string()))
    if tz_given:  # the ambiguous word dropped: the time is read in --tz
        new = pc.if_else(pa.array(ambiguous), "", new)
    rewritten = pc.binary_join_element_wise(parts["pre"], new, parts["post"], "")
    use = read | (ambiguous & tz_given)
    out = text.copy()
    if use.any():
        out[use] = np.asarray(rewritten.to_numpy(zero_copy_only=False), dtype=object)[use]
    words = pd.Series(np.asarray(word.to_numpy(zero_copy_only=False), dtype=object))
    counts = words[read & ~utc].value_counts().to_dict()
    left = (
        {} if tz_given else {w: (words == w).to_numpy() & ambiguous for w in set(words[ambiguous])}
    )
    if tz_given:
        counts.update({f"{w} (as --tz)": k for w, k in words[ambiguous].value_counts().items()})
    if (read & utc & with_offset).any():
        counts["UTC±hh"] = int((read & utc & with_offset).sum())
    return out, counts, left


#: Text that may hold a month name or a Chinese date (rows without it are not looked at).
NAMED_HINT = r"[A-Za-zÀ-ɏ]{3}|年"


def clock_seconds(text: pd.Series) -> pd.Series:
    """Seconds of the day (float) of clock times alone (``23:50:00.5``, ``8:01 PM``), NaN
    where a value is not one (or is out of range: 24:00, 12-hour 13 PM)."""
    parts, matched = _extract(_arrow(text), _CLOCK)
    hour = _hours(parts)
    minute, second = _num(parts["M"]), np.nan_to_num(_num(parts["S"]))
    digits = pc.binary_join_element_wise("0.", parts["F"], "")
    frac = np.where(_given(parts["F"]), _num(digits), 0.0)
    sod = hour * 3600 + minute * 60 + second + frac
    with np.errstate(invalid="ignore"):
        ok = matched & (minute <= 59) & (second <= 59)
    return pd.Series(np.where(ok, sod, np.nan), index=text.index)


#: :data:`_CLOCK` without its groups, for Arrow's regex engine (4x pandas' on 2 M rows).
_CLOCK_ARROW = r"^\s*\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d{1,9})?)?(?:\s*[AaPp]\.?\s?[Mm]\.?)?\s*$"


def is_clock(text: pd.Series) -> pd.Series:
    """Whether each value is a clock time alone (``23:50:00.5``)."""
    hit = pc.fill_null(pc.match_substring_regex(_arrow(text), _CLOCK_ARROW), False)
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
    distinct = sorted_sets.distinct(finite.astype("int64"))
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
    "AMBIGUOUS_ZONES",
    "NAMED_HINT",
    "ZONE_WORDS",
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
    "zone_words",
]

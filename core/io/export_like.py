"""Write points in a file layout (:mod:`wakeline.core.io.layout`): the operator's own
columns, encoding, delimiter, time format and number precision.

Every column is formatted as a whole (Arrow string kernels on integer-scaled values),
never per row in Python. Columns Wakeline did not read are written from the extra
columns the import carried through; points Wakeline made (``interpolated`` rows: gap
fills) leave them empty. Merged and fused tracks get one id per target in the layout's
batch column (see :func:`assign_target_ids`) and a members table mapping each new id to
its member batches.
"""

import codecs
import datetime as dt
import re
from dataclasses import replace

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core.errors import InputError
from wakeline.core.geo import to_local
from wakeline.core.io.formats import angle_unit, carried_speed, length_unit, speed_unit
from wakeline.core.io.layout import (
    GPS_KINDS,
    INTERNAL_COLUMNS,
    NUMBER_FIELDS,
    SAMPLE_ROWS,
    AngleFormat,
    Column,
    Layout,
    NumberFormat,
    TimeFormat,
)
from wakeline.core.io.writer import atomic_path
from wakeline.core.schema import CANONICAL_COLUMNS, COURSE_READ, EPOCH, FILE_ROW, in_file_order

#: Rows formatted and encoded at a time (bounds the memory of an export).
CHUNK_ROWS = 500_000
MEMBER_COLUMNS = ("sensor", "batch", "member_sensor", "member_batch", "target")
_CANONICAL = frozenset((*CANONICAL_COLUMNS, "truth"))


def _join(*parts) -> pa.Array:
    return pc.binary_join_element_wise(*parts, "")


def _digits(
    scaled: np.ndarray, neg: np.ndarray, decimals: int, trim: str, point: str = "."
) -> pa.Array:
    """Text of ``±scaled / 10**decimals`` (``scaled`` ≥ 0, int64) with ``decimals`` digits
    after ``point``."""
    unit = 10**decimals
    whole = pc.cast(pa.array(scaled // unit), pa.string())
    if decimals > 0:
        frac = pc.utf8_lpad(pc.cast(pa.array(scaled % unit), pa.string()), decimals, "0")
        if trim == "none":
            text = _join(whole, point, frac)
        else:
            short = pc.utf8_rtrim(frac, "0")
            empty = pc.equal(pc.utf8_length(short), 0)
            if trim == "keep1":
                text = _join(whole, point, pc.if_else(empty, "0", short))
            else:
                text = pc.if_else(empty, whole, _join(whole, point, short))
    else:
        text = whole
    return pc.if_else(pa.array(neg), _join("-", text), text)


def format_numbers(values: np.ndarray, fmt: NumberFormat) -> pa.Array:
    """Numbers as text in ``fmt``; NaN as ``fmt.na``."""
    x = np.asarray(values, dtype="float64")
    finite = np.isfinite(x)
    with np.errstate(invalid="ignore", over="ignore"):
        big = np.abs(np.where(finite, x, 0.0)) * 10.0**fmt.decimals
    if fmt.trim in ("repr", "repr1") or (big > 4e15).any():
        text = pc.cast(pa.array(np.where(finite, x, 0.0)), pa.string())
        sci = np.flatnonzero(np.asarray(pc.match_substring(text, "e")))
        if len(sci):  # rare: very small or large values, written without an exponent
            fixed = [np.format_float_positional(v, trim="-") for v in x[sci]]
            text = pc.replace_with_mask(
                text, pa.array(np.isin(np.arange(len(x)), sci)), pa.array(fixed, pa.string())
            )
        if fmt.trim == "repr1":
            text = pc.if_else(pc.match_substring(text, "."), text, _join(text, ".0"))
        if fmt.point != ".":
            text = pc.replace_substring(text, ".", fmt.point)
    else:
        scaled = np.rint(big).astype("int64")
        text = _digits(scaled, (x < 0) & (scaled != 0), fmt.decimals, fmt.trim, fmt.point)
    return pc.if_else(pa.array(finite), text, fmt.na)


def format_ddmm(values: np.ndarray, fmt: NumberFormat, width: int, signed: bool) -> pa.Array:
    """Degrees as NMEA writes them, degrees and minutes run together (37.9005 as
    ``3754.0300``; the minutes rounded to ``fmt``'s decimals first, so they never read
    60), the digits before the point zero-padded to ``width``; ``signed``: a minus sign
    for negative values (else none: a column of hemisphere letters gives the sign)."""
    x = np.asarray(values, dtype="float64")
    a = np.abs(x)
    deg = np.floor(a)
    minutes = np.round((a - deg) * 60.0, fmt.decimals)
    over = minutes >= 60.0
    deg, minutes = np.where(over, deg + 1.0, deg), np.where(over, minutes - 60.0, minutes)
    number = deg * 100.0 + minutes
    text = format_numbers(number, fmt)
    with np.errstate(invalid="ignore", divide="ignore"):
        digits = np.where(number >= 1.0, np.floor(np.log10(np.maximum(number, 1.0))) + 1, 1)
    pad = np.clip(width - np.nan_to_num(digits, nan=width), 0, width).astype("int64")
    zeros = np.array(["0" * k for k in range(width + 1)], dtype=object)[pad]
    if signed:
        zeros = np.where((x < 0) & (number > 0), "-" + zeros.astype(str), zeros).astype(object)
    text = pc.binary_join_element_wise(pa.array(zeros, pa.string()), text, "")
    return pc.if_else(pa.array(np.isfinite(x)), text, fmt.na)


def _zone(name: str):
    m = re.match(r"^([+-])(\d{2}):?(\d{2})$", name)
    if m:
        sign = 1 if m[1] == "+" else -1
        return dt.timezone(sign * dt.timedelta(hours=int(m[2]), minutes=int(m[3])))
    return name


def check_zone(name: str) -> None:
    """Raise :class:`InputError` unless ``name`` is a time zone (IANA name, ``UTC`` or an
    offset like ``+08:00``)."""
    try:
        pd.Timestamp(0, tz="UTC").tz_convert(_zone(name))
    except Exception:  # noqa: BLE001 - pandas raises several kinds for a bad zone
        raise InputError(
            f"unknown time zone {name!r}; give an IANA name (Asia/Shanghai), UTC or +08:00"
        ) from None


def _epoch_ns(times: pd.Series) -> tuple[np.ndarray, np.ndarray]:
    """int64 ns since 1970 UTC (0 where missing) and a mask of present times."""
    t = pd.to_datetime(pd.Series(times), utc=True)
    ok = t.notna().to_numpy()
    delta = (t - EPOCH).dt.as_unit("ns").to_numpy()
    ns = np.where(ok, delta.view("int64"), 0)
    return ns, ok


def _round_div(ns: np.ndarray, q: int) -> tuple[np.ndarray, np.ndarray]:
    """|ns| / q rounded half up (int64), and the sign mask."""
    neg = ns < 0
    a = np.abs(ns)
    return (a + q // 2) // q, neg


_ISO_SLICES = {"Y": (0, 4), "m": (5, 7), "d": (8, 10), "H": (11, 13), "M": (14, 16), "S": (17, 19)}
#: Seconds since 1970 of years 1000 and 10000: the span where the ISO text has fixed width.
_FIXED_WIDTH = (-30610224000, 253402300800)


def _strftime(seconds: np.ndarray, pattern: str) -> pa.Array:
    """``pattern`` (``%Y %m %d %H %M %S`` and literal text) for whole seconds since 1970.

    Cuts the fields out of Arrow's ISO text of the timestamps (a fast cast), which is
    several times faster than Arrow's strftime; other patterns use strftime."""
    arr = pa.array(seconds, pa.timestamp("s"))
    tokens = re.split(r"(%.)", pattern)
    codes = [t[1] for t in tokens if t.startswith("%") and len(t) == 2]
    in_range = len(seconds) == 0 or (
        seconds.min() >= _FIXED_WIDTH[0] and seconds.max() < _FIXED_WIDTH[1]
    )
    if not in_range or any(c not in _ISO_SLICES for c in codes) or not codes:
        return pc.strftime(arr, format=pattern)
    iso = pc.cast(arr, pa.string())
    parts = []
    for tok in tokens:
        if tok.startswith("%") and len(tok) == 2:
            a, b = _ISO_SLICES[tok[1]]
            parts.append(pc.utf8_slice_codeunits(iso, a, b))
        elif tok:
            parts.append(tok)
    return _join(*parts) if len(parts) > 1 else parts[0]


def format_angles(values: np.ndarray, fmt: AngleFormat, pos: str, neg: str) -> pa.Array:
    """Degrees as degrees and minutes (and seconds) text in ``fmt`` with the hemisphere
    letter ``pos`` (values >= 0) or ``neg``; NaN as ``fmt.na``. Rounded once, in units of
    the last part, so minutes never read 60."""
    x = np.asarray(values, dtype="float64")
    finite = np.isfinite(x)
    a = np.abs(np.where(finite, x, 0.0))
    if fmt.ddmm:  # NMEA's degrees and minutes run together with the letter: 3754.03N
        text = format_ddmm(a, NumberFormat(fmt.decimals, fmt.trim), fmt.deg_width, False)
        letter = pa.array(np.where(x < 0, neg, pos))
        text = _join(text, fmt.gap, letter) if fmt.suffix else _join(letter, fmt.gap, text)
        return pc.if_else(pa.array(finite), text, fmt.na)
    if not fmt.minutes:  # decimal degrees with the letter: 37.05N
        text = format_numbers(a, NumberFormat(fmt.decimals, fmt.trim))
        letter = pa.array(np.where(x < 0, neg, pos))
        text = _join(text, fmt.gap, letter) if fmt.suffix else _join(letter, fmt.gap, text)
        return pc.if_else(pa.array(finite), text, fmt.na)
    unit = 10**fmt.decimals
    per_deg = (3600 if fmt.seconds else 60) * unit
    units = np.rint(a * per_deg).astype("int64")
    rest = units % per_deg
    text = pc.cast(pa.array(units // per_deg), pa.string())
    if fmt.deg_width:
        text = pc.utf8_lpad(text, fmt.deg_width, "0")
    text = _join(text, fmt.deg_mark)
    zeros = np.zeros(len(x), dtype=bool)
    if fmt.seconds:
        minutes = pc.cast(pa.array(rest // (60 * unit)), pa.string())
        if fmt.min_width:
            minutes = pc.utf8_lpad(minutes, fmt.min_width, "0")
        text = _join(text, minutes, fmt.min_mark)
        rest = rest % (60 * unit)
    last = _digits(rest, zeros, fmt.decimals, fmt.trim)
    width = fmt.sec_width if fmt.seconds else fmt.min_width
    if width:  # "05.5": the whole part of the last number in two digits
        last = pc.if_else(pa.array(rest < 10 * unit), _join("0", last), last)
    text = _join(text, last, fmt.sec_mark if fmt.seconds else fmt.min_mark)
    letter = pa.array(np.where(x < 0, neg, pos))
    text = _join(text, fmt.gap, letter) if fmt.suffix else _join(letter, fmt.gap, text)
    return pc.if_else(pa.array(finite), text, fmt.na)


def _words(text: pa.Array, tf: TimeFormat) -> pa.Array:
    """Times as strftime wrote them, in the file's words: month names in capitals
    (``01-JAN-24``), a Chinese date's month and day without a leading zero (``2024年1月1日``)."""
    if tf.words == "upper":
        return pc.utf8_upper(text)
    if tf.words == "nopad":
        return pc.replace_substring_regex(text, "([年月])0", r"\1")
    return text


def format_gps(times: pd.Series, tf: TimeFormat, week: NumberFormat | None = None) -> pa.Array:
    """Times as GPS seconds in ``tf.number``'s style (``tf.kind`` ``gps_week``: of the
    week; ``gps``: since 1980-01-06), the leap seconds added back as the reader took them
    off; ``week`` given: the GPS week numbers instead, in that format. The time is
    rounded to the seconds' decimals first, so 604,799.9996 s at three decimals is 0.000
    of the next week. Missing times: the format's missing-value text."""
    from wakeline.core.io.reader import GPS_WEEK_S, gps_of_utc_ns

    ns, ok = _epoch_ns(times)
    gps = gps_of_utc_ns(np.where(ok, ns, 0))
    fmt = tf.number
    d = fmt.decimals
    week_ns = GPS_WEEK_S * 1_000_000_000
    if fmt.trim.startswith("repr") or d > 9:  # the float's shortest text: no rounding here
        weeks = np.floor_divide(gps, week_ns) if tf.kind == "gps_week" else np.zeros_like(gps)
        rest = gps - weeks * week_ns
        whole, frac = np.divmod(rest, 1_000_000_000)
        text = format_numbers(whole.astype("float64") + frac / 1e9, fmt)
    else:
        q = 10 ** (9 - d)
        scaled = np.floor_divide(gps + q // 2, q)  # rounded half up to the decimals
        weeks = np.zeros_like(scaled)
        if tf.kind == "gps_week":
            weeks = np.floor_divide(scaled, GPS_WEEK_S * 10**d)
            scaled = scaled - weeks * (GPS_WEEK_S * 10**d)
        neg = scaled < 0
        text = _digits(np.abs(scaled), neg, d, fmt.trim, fmt.point)
    if week is not None:
        return pc.if_else(pa.array(ok), format_numbers(weeks.astype("float64"), week), week.na)
    return pc.if_else(pa.array(ok), text, fmt.na)


def format_times(times: pd.Series, tf: TimeFormat, part: str = "all") -> pa.Array:
    """Times as text in ``tf``; missing times as empty cells. ``part`` ``date``: only
    the date, in ``tf.date_pattern`` (the date column of a ``Date,Time`` layout), of the
    time rounded as the clock column rounds it."""
    if tf.kind in GPS_KINDS:
        return format_gps(times, tf)
    ns, ok = _epoch_ns(times)
    if tf.kind == "excel":  # serial days of the wall clock in tf.tz (1900 date system)
        if tf.tz not in ("UTC", "Z", "+00:00", ""):
            wall = pd.to_datetime(pd.Series(times), utc=True).dt.tz_convert(_zone(tf.tz))
            local = (wall.dt.tz_localize(None) - pd.Timestamp(0)).dt.as_unit("ns")
            ns = np.where(ok, local.to_numpy().view("int64"), 0)
        days = ns / 86_400e9 + 25_569.0
        return pc.if_else(pa.array(ok), format_numbers(days, tf.number), tf.number.na)
    if tf.kind == "unix":
        unit_ns = 1_000_000_000 // tf.scale
        d = tf.number.decimals
        if not tf.number.trim.startswith("repr") and 10**d <= unit_ns:
            scaled, neg = _round_div(ns, unit_ns // 10**d)
            text = _digits(scaled, neg & (scaled != 0), d, tf.number.trim, tf.number.point)
        else:
            # whole units and the rest apart: ns / unit_ns rounds ns to a float first (a
            # step of 256 ns at today's times), so 1620114894.71274 came back .7127402
            whole, rest = np.divmod(ns, unit_ns)
            text = format_numbers(whole.astype("float64") + rest / unit_ns, tf.number)
        return pc.if_else(pa.array(ok), text, tf.number.na)
    if tf.tz not in ("UTC", "Z", "+00:00", ""):
        wall = pd.to_datetime(pd.Series(times), utc=True).dt.tz_convert(_zone(tf.tz))
        local = (wall.dt.tz_localize(None) - pd.Timestamp(0)).dt.as_unit("ns")
        ns = np.where(ok, local.to_numpy().view("int64"), 0)
    d = min(tf.frac_digits, 9)
    q = 10 ** (9 - d)
    ns = np.floor_divide(ns + q // 2, q) * q
    seconds = np.floor_divide(ns, 1_000_000_000)
    if part == "date":
        return pc.if_else(pa.array(ok), _words(_strftime(seconds, tf.date_pattern), tf), "")
    base = _strftime(seconds, tf.pattern)
    if d > 0:
        frac = (ns - seconds * 1_000_000_000) // q
        digits = _digits(frac, np.zeros(len(frac), bool), d, tf.frac_trim, tf.frac_point)
        # _digits writes "0.123" (or "0,123"): keep what follows "0".
        text = pc.if_else(
            pc.match_substring(digits, tf.frac_point),
            _join(base, pc.utf8_slice_codeunits(digits, 1)),
            base,
        )
    else:
        text = base
    text = _words(text, tf)
    if tf.meridiem and part != "date":  # " AM" / " PM" as the file wrote them (" p.m.")
        pm = tf.meridiem.replace("a", "p").replace("A", "P")
        text = pc.replace_substring(pc.replace_substring(text, " AM", tf.meridiem), " PM", pm)
    if tf.suffix:
        text = _join(text, tf.suffix)
    return pc.if_else(pa.array(ok), text, "")


def _text(series: pd.Series) -> pa.Array:
    """Any column as text; missing values as empty cells."""
    if isinstance(series.dtype, pd.DatetimeTZDtype) or pd.api.types.is_datetime64_any_dtype(
        series.dtype
    ):
        return format_times(series, TimeFormat())
    if pd.api.types.is_float_dtype(series.dtype):
        return format_numbers(series.to_numpy(dtype="float64"), NumberFormat(17, "repr"))
    arr = pa.array(series.astype("str").to_numpy(dtype=object), pa.string(), from_pandas=True)
    return pc.fill_null(arr, "")


def _blank(n: int) -> pa.Array:
    return pa.repeat(pa.scalar("", pa.string()), n)


def made_mask(points: pd.DataFrame) -> np.ndarray:
    """Rows Wakeline made (``interpolated`` true): gap fills and spline points."""
    if "interpolated" not in points.columns:
        return np.zeros(len(points), dtype=bool)
    col = points["interpolated"]
    if pd.api.types.is_bool_dtype(col.dtype) or pd.api.types.is_numeric_dtype(col.dtype):
        return col.fillna(0).astype(bool).to_numpy()
    return col.astype("str").str.lower().isin(["true", "1", "yes"]).to_numpy()


def _as_read(points: pd.DataFrame) -> np.ndarray:
    if COURSE_READ not in points.columns:
        return np.full(len(points), np.nan)
    return pd.to_numeric(points[COURSE_READ], errors="coerce").to_numpy(dtype="float64")


def courses_as_read(points: pd.DataFrame) -> np.ndarray:
    """The rows whose course is written as the file had it: the import changed it (a
    course of 360.0 read as 0 — north —, one outside [0, 360) such as 380.4 or AIS's
    "not available" 360 blanked; :data:`COURSE_READ`) and no step changed it since (it is
    still 0 where 360 was read, still empty where it was blanked); never a point
    Wakeline made."""
    read = _as_read(points)
    if not np.isfinite(read).any() or "course" not in points.columns:
        return np.zeros(len(points), dtype=bool)
    course = points["course"].to_numpy(dtype="float64")
    kept = np.isnan(course) | ((course == 0.0) & (read == 360.0))
    return np.isfinite(read) & kept & ~made_mask(points)


def _extra_key(points: pd.DataFrame, column: Column) -> str | None:
    key = column.key or column.name
    for name in (f"{key}_src", key) if key in _CANONICAL else (key, f"{key}_src"):
        if name in points.columns:
            return name
    return None


def _first_member_order(points: pd.DataFrame, target: pd.Series) -> pd.DataFrame:
    """Member tracks of every target, each target's members ordered by first time."""
    batch = points["batch"].astype("str")
    if "source_batch" in points.columns:
        src = points["source_batch"].astype("str").fillna("")
        batch = batch.where((src == "") | (src == "nan"), src)
        made = made_mask(points)
    else:
        made = np.zeros(len(points), dtype=bool)
    df = pd.DataFrame(
        {
            "target": target.astype("str").to_numpy(),
            "member_sensor": points["sensor"].astype("str").to_numpy(),
            "member_batch": batch.to_numpy(),
            "time": pd.to_datetime(points["time"], utc=True).dt.tz_localize(None).to_numpy(),
        }
    )[~made]
    first = df.groupby(["target", "member_sensor", "member_batch"], sort=False)["time"].min()
    return first.reset_index().sort_values(["target", "time"], kind="stable")


def _first(members: pd.DataFrame, by: str, prefer_sensor: str | None) -> pd.DataFrame:
    """The first member row of every ``by`` group (a member of ``prefer_sensor`` first)."""
    if prefer_sensor:
        other = (members["member_sensor"] != prefer_sensor).to_numpy()
        members = members.assign(_other=other).sort_values([by, "_other"], kind="stable")
    return members.drop_duplicates(by).set_index(by)


def assign_target_ids(
    points: pd.DataFrame, renumber: bool = False, prefer_sensor: str | None = None
) -> tuple[pd.DataFrame, pd.DataFrame | None]:
    """Points whose ``sensor``/``batch`` carry one usable id per merged or fused target.

    Associated tables (a ``target`` column) and fused tables (a ``members`` column,
    ``sensor:batch+sensor:batch``) get, by default, the sensor and batch of the target's
    first member (the member track that starts first; for fused tables the first
    listed); a member of ``prefer_sensor`` comes first when the target has one (the
    sensor whose system gets the file); with ``renumber`` fresh batch numbers 1, 2, … in
    order of the targets' start. Returns the new table and the members table (``MEMBER_COLUMNS``: the id
    written, each member's sensor and batch, the target); None for other tables.
    """
    if "members" in points.columns:
        labels = points["members"].astype("str")
        uniq = pd.unique(labels)
        rows = []
        for k, text in enumerate(uniq):  # one per target, not per point
            for label in str(text).split("+"):
                s, _, b = label.partition(":")
                rows.append((k, s, b))
        mem = pd.DataFrame(rows, columns=["k", "member_sensor", "member_batch"])
        first = _first(mem, "k", prefer_sensor)
        code = pd.Index(uniq).get_indexer(labels)
        target = points["batch"].astype("str")
        new_sensor = first["member_sensor"].to_numpy()[code]
        new_batch = first["member_batch"].to_numpy()[code]
        order_time = pd.to_datetime(points["time"], utc=True)
        mem["target"] = (
            target.groupby(code).first().reindex(mem["k"]).to_numpy()
            if len(points)
            else np.zeros(0, dtype=object)
        )
    elif "target" in points.columns:
        target = points["target"].astype("str")
        members = _first_member_order(points, target)
        first = _first(members, "target", prefer_sensor)
        new_sensor = first["member_sensor"].reindex(target).to_numpy()
        new_batch = first["member_batch"].reindex(target).to_numpy()
        code = pd.Index(first.index).get_indexer(target)
        order_time = pd.to_datetime(points["time"], utc=True)
        mem = members.rename(columns={"time": "_t"})
        mem["k"] = pd.Index(first.index).get_indexer(mem["target"])
    else:
        return points, None
    out = points.copy()
    if renumber:
        start = pd.Series(order_time.to_numpy()).groupby(code).min().sort_values(kind="stable")
        number = pd.Series(np.arange(1, len(start) + 1), index=start.index)
        new_batch = number.reindex(code).astype("str").to_numpy()
        mem_batch = number.reindex(mem["k"]).astype("str").to_numpy()
    else:
        mem_batch = pd.Series(new_batch).groupby(code).first().reindex(mem["k"]).to_numpy()
    mem_sensor = pd.Series(new_sensor).groupby(code).first().reindex(mem["k"]).to_numpy()
    out["sensor"] = pd.Series(new_sensor, index=out.index, dtype="str")
    out["batch"] = pd.Series(new_batch, index=out.index, dtype="str")
    table = pd.DataFrame(
        {
            "sensor": mem_sensor,
            "batch": mem_batch,
            "member_sensor": mem["member_sensor"].to_numpy(),
            "member_batch": mem["member_batch"].to_numpy(),
            "target": mem["target"].to_numpy(),
        }
    ).astype("str")
    return out, table


def _cells(points: pd.DataFrame, layout: Layout, extra: list[str]) -> list[pa.Array]:
    made = made_mask(points)
    any_made = bool(made.any())
    cells = []
    plane = _plane_metres(points, layout, made) if layout.origin is not None else {}
    for col in layout.columns:
        if col.field in plane:
            cells.append(plane[col.field])
        elif col.field == "time":
            cells.append(format_times(points["time"], layout.time))
        elif col.field == "date":
            cells.append(format_times(points["time"], layout.time, part="date"))
        elif col.field == "gps_week":
            week = col.number or NumberFormat(0, "none")
            if layout.time.kind == "gps_week":
                cells.append(format_gps(points["time"], layout.time, week))
            else:  # a layout edited by hand: the week of GPS seconds of the week
                cells.append(format_gps(points["time"], TimeFormat("gps_week"), week))
        elif col.ddmm and col.field in ("lon", "lat"):
            values = points[col.field].to_numpy(dtype="float64")
            signed = not any(c.hemisphere == col.field for c in layout.columns)
            cells.append(
                format_ddmm(values, col.number or NumberFormat(4, "none"), col.ddmm, signed)
            )
        elif col.hemisphere in ("lon", "lat"):
            values = points[col.hemisphere].to_numpy(dtype="float64")
            pos, neg = ("E", "W") if col.hemisphere == "lon" else ("N", "S")
            letters = np.where(np.isnan(values), "", np.where(values < 0, neg, pos))
            cells.append(pa.array(letters, pa.string()))
        elif col.angle is not None and col.field in ("lon", "lat"):
            values = points[col.field].to_numpy(dtype="float64")
            pos, neg = ("E", "W") if col.field == "lon" else ("N", "S")
            cells.append(format_angles(values, col.angle, pos, neg))
        elif col.field in NUMBER_FIELDS:
            values = (
                points[col.field].to_numpy(dtype="float64")
                if col.field in points.columns
                else np.full(len(points), np.nan)
            )
            if col.field == "course" and layout.source:  # --like a file, not a preset
                values = np.where(courses_as_read(points), _as_read(points), values)
            if any(c.hemisphere == col.field for c in layout.columns):
                values = np.abs(values)  # the letter column beside says the sign
            if col.field == "speed":  # back in the unit its header names (speed_mps)
                per_hour = speed_unit(col.name, layout.speed_unit)[0]
                if per_hour != 1852.0:
                    values = values * 1852.0 / per_hour
            cells.append(format_numbers(values, col.number or NumberFormat()))
        elif col.field is not None:
            cells.append(
                _text(points[col.field]) if col.field in points.columns else _blank(len(points))
            )
        else:
            key = _extra_key(points, col)
            arr = _text(points[key]) if key else _blank(len(points))
            if any_made:
                arr = pc.if_else(pa.array(made), "", arr)
            speed = _carried_speed_cells(points, layout, col, key, made)
            if speed is not None:
                arr = pc.if_else(pa.array(speed[0]), speed[1], arr)
            cells.append(arr)
    cells.extend(_text(points[name]) for name in extra)
    return cells


def speeds_missing(points: pd.DataFrame, col: Column, key: str | None) -> np.ndarray | None:
    """The rows that carry no value of ``col``, a speed column the importer carried unread
    (:func:`~wakeline.core.io.formats.carried_speed`: MTAD's ``vel``), but have a speed:
    points Wakeline fused or merged, whose rows have no extra columns (h150: a fused MTAD
    layer's ``vel`` written empty in all 547 rows). None for another column. Points
    Wakeline made (``interpolated``) are not among them (their columns are left empty)."""
    if carried_speed(col.name) is None or "speed" not in points.columns:
        return None
    absent = points[key].isna().to_numpy() if key else np.ones(len(points), dtype=bool)
    speed = points["speed"].to_numpy(dtype="float64")
    return absent & np.isfinite(speed) & ~made_mask(points)


def _carried_speed_cells(
    points: pd.DataFrame, layout: Layout, col: Column, key: str | None, made: np.ndarray
) -> tuple[np.ndarray, pa.Array] | None:
    """Where a carried speed column (``vel``, ``sog_kmh``) has no value but the point has
    a speed: the speed in the unit the column's header names (its rows and cells), in the
    number style of the column's other cells (else of the mapped speed's, else 2
    decimals). None when there is none, or the unit is not known (the export's notes say
    so: :func:`speeds_not_written`)."""
    rows = speeds_missing(points, col, key)
    if rows is None or not rows.any():
        return None
    per_hour, _ = carried_speed(col.name)
    if not np.isfinite(per_hour):
        return None
    present = points[key].dropna().head(SAMPLE_ROWS) if key is not None else None
    fmt = NumberFormat.detect(present) if present is not None and len(present) else None
    if fmt is None:
        mapped = layout.field_column("speed")
        fmt = (mapped.number if mapped is not None else None) or NumberFormat(2, "zeros")
    values = points["speed"].to_numpy(dtype="float64") * 1852.0 / per_hour
    return rows, format_numbers(values, fmt)


def speeds_not_written(points: pd.DataFrame, layout: Layout) -> list[str]:
    """Notes for the carried speed columns left empty on rows that have a speed: the
    column's unit is not known (MTAD's ``vel``: m/s on some tracks, knots on others), so
    the points' speed (knots) is not written there."""
    notes = []
    for col in layout.columns:
        if col.field is not None:
            continue
        key = _extra_key(points, col)
        rows = speeds_missing(points, col, key)
        if rows is None or not rows.any() or np.isfinite(carried_speed(col.name)[0]):
            continue
        notes.append(
            f"column {col.name!r} left empty on {int(rows.sum()):,} row(s) that carry none "
            "of its values (points Wakeline fused, or read from a file without the column) although they have a speed: "
            "it is a speed of no known unit (the file's own values were carried as they "
            f"came), so the speed in knots is not written there; to have it written, import "
            f"with --map speed={col.name} (and --speed-unit)"
        )
    return notes


def _plane_metres(points: pd.DataFrame, layout: Layout, made: np.ndarray) -> dict[str, pa.Array]:
    """The cells of a plane layout's position columns: the points' lon/lat back on the
    plane about ``layout.origin`` (east/north, or range and bearing), less the offset
    each row came with (its own text written back; 0 on a row Wakeline made, which has
    none), in the units the headers name."""
    lat0, lon0 = layout.origin
    xy = list(
        to_local(
            points["lon"].to_numpy(dtype="float64"),
            points["lat"].to_numpy(dtype="float64"),
            lon0,
            lat0,
        )
    )
    out: dict[str, pa.Array] = {}
    for k, axis in enumerate(("east", "north")):
        off_col = layout.field_column(f"{axis}_offset")
        if off_col is None:
            continue
        key = _extra_key(points, off_col)
        text = points[key].astype("str") if key else pd.Series("", index=points.index)
        off = pd.to_numeric(text, errors="coerce").to_numpy(dtype="float64")
        scale = length_unit(off_col.name, layout.distance_unit)[0]
        xy[k] = xy[k] - np.where(made | np.isnan(off), 0.0, off * scale)
        cells = _text(text) if key else _blank(len(points))
        out[f"{axis}_offset"] = pc.if_else(pa.array(made | (text.to_numpy() == "")), "0", cells)
    rng = np.hypot(xy[0], xy[1])
    values = {
        "east": xy[0],
        "north": xy[1],
        "range": rng,
        "bearing": np.mod(np.arctan2(xy[0], xy[1]), 2.0 * np.pi),
    }
    for name, v in values.items():
        col = layout.field_column(name)
        if col is None:
            continue
        scale = (
            angle_unit(col.name)[0]
            if name == "bearing"
            else length_unit(col.name, layout.distance_unit)[0]
        )
        fmt = col.number or NumberFormat()
        cells = format_numbers(v / scale, fmt)
        key = _extra_key(points, col)
        if key is not None:
            # A row's own text where it still says where the point is: the plane and
            # back cost ~1e-9 m, so a full-precision cell (Autoferry's 84.63510099212183)
            # came back in its last digits (84.6351009920087) on unmoved points.
            own = points[key].astype("str").fillna("")
            num = own.str.replace(fmt.point, ".", regex=False) if fmt.point != "." else own
            was = pd.to_numeric(num, errors="coerce").to_numpy(dtype="float64") * scale
            gap = np.abs(was - v)
            if name == "bearing":  # as metres at the range; -20 is 340 (written as came)
                gap = np.abs(np.mod(was - v + np.pi, 2.0 * np.pi) - np.pi) * np.maximum(rng, 1.0)
            with np.errstate(invalid="ignore"):
                same = ~made & (gap <= 1e-6)  # a micrometre: no step moves a point so little
            if same.any():
                cells = pc.if_else(pa.array(same), _text(own), cells)
        out[name] = cells
    return out


def _quote(cells: list[pa.Array], layout: Layout, text: list[bool] | None = None) -> list[pa.Array]:
    """Cells quoted as the layout does; ``text`` marks the cells that may need it (numbers
    and times never hold a quote, a line break or a delimiter other than ``.``)."""
    if layout.quoting == "all":
        return [_join('"', pc.replace_substring(c, '"', '""'), '"') for c in cells]
    pattern = "[" + re.escape(layout.delimiter) + '"\r\n]'
    aligned = layout.aligned and layout.delimiter == " "
    if aligned and text is None:  # header names, two blanks apart: one blank is no break
        pattern = '^ | $|  |["\t\r\n]'
    out = []
    for k, c in enumerate(cells):
        if text is not None and not text[k] and (aligned or layout.delimiter not in ".:-/+ "):
            # (aligned: the reader joins a date and a clock a blank apart again)
            out.append(c)
            continue
        risky = pc.match_substring_regex(c, pattern)
        if pc.any(risky).as_py():
            c = pc.if_else(risky, _join('"', pc.replace_substring(c, '"', '""'), '"'), c)
        out.append(c)
    return out


def layout_columns(points: pd.DataFrame, layout: Layout, columns: list[str] | None) -> Layout:
    """For the canonical layout: the operator's extra columns present in ``points`` (not
    Wakeline's internal ones) after the canonical ones. Other layouts are unchanged."""
    if layout.name != "canonical" or layout.source:
        return layout
    names = [c.name for c in layout.columns]
    head = [c for c in layout.columns if c.field in points.columns or c.field == "time"]
    if "truth" in points.columns:
        head.append(Column("truth", "truth", key="truth"))
    asked = set(columns or ())
    extras = [
        Column(c, None, key=c)
        for c in points.columns
        if c not in names and c != "truth" and c not in INTERNAL_COLUMNS and c not in asked
    ]
    return replace(layout, columns=tuple(head + extras))


#: Between the columns of a layout aligned with blanks (two: a header name or a cell may
#: hold one blank, "Track No", "2024-05-01 10:00:00").
ALIGNED_GAP = "  "
_FIRST_CHUNK = -1


def _widths(
    points: pd.DataFrame, layout: Layout, extra: list[str], is_text: list[bool], header
) -> dict:
    """Each column's width (its widest cell, header included) over every chunk of rows
    written: a first pass formatting the cells, chunk by chunk, for their lengths only
    (for one chunk, the cells are kept under ``_FIRST_CHUNK`` and written as they are)."""
    widths = {k: len(h[0].as_py()) for k, h in enumerate(header)}
    n = len(points)
    for start in range(0, n, CHUNK_ROWS):
        part = points.iloc[start : start + CHUNK_ROWS]
        cells = _quote(_cells(part, layout, extra), layout, is_text)
        for k, c in enumerate(cells):
            longest = pc.max(pc.utf8_length(c)).as_py() if len(c) else 0
            widths[k] = max(widths[k], int(longest or 0))
        if n <= CHUNK_ROWS:
            widths[_FIRST_CHUNK] = cells
    return widths


def _pad(cells: list[pa.Array], widths: dict, is_text: list[bool]) -> list[pa.Array]:
    """Cells padded with blanks to their column's width: text to the left, numbers and
    times to the right; the last column's text not padded (no blanks at line ends)."""
    out = []
    for k, c in enumerate(cells):
        c = c.cast(pa.string()) if c.type != pa.string() else c
        if not is_text[k]:
            out.append(pc.utf8_lpad(c, widths[k], " "))
        elif k < len(cells) - 1:
            out.append(pc.utf8_rpad(c, widths[k], " "))
        else:
            out.append(c)
    return out


def write_layout(
    points: pd.DataFrame,
    layout: Layout,
    path,
    columns: list[str] | None = None,
) -> dict:
    """Write ``points`` (in their row order) in ``layout``, atomically.

    ``columns`` names more columns of ``points`` to append (internal ones included).
    Returns a small report: rows written, columns, encoding, rows Wakeline made.
    Raises :class:`InputError` for an unknown column or text the encoding cannot hold.
    """
    extra = list(columns or ())
    missing = [c for c in extra if c not in points.columns]
    if missing:
        raise InputError(
            f"--columns: no column {', '.join(missing)}; columns are {', '.join(points.columns)}"
        )
    layout = layout_columns(points, layout, extra)
    names = [c.name for c in layout.columns] + extra
    header = _quote([pa.array([n], pa.string()) for n in names], layout)
    n = len(points)
    is_text = [c.field not in (*NUMBER_FIELDS, "time", "date", "gps_week") for c in layout.columns]
    is_text += [True] * len(extra)
    aligned = layout.aligned and layout.delimiter == " "
    widths = _widths(points, layout, extra, is_text, header) if aligned else None
    join = ALIGNED_GAP if aligned else layout.delimiter
    if widths is not None:
        header = _pad(header, widths, is_text)
    header_line = join.join(h[0].as_py() for h in header)
    if aligned:
        header_line = header_line.rstrip(" ")
    try:
        encoder = codecs.getincrementalencoder(layout.encoding)()
    except LookupError:
        raise InputError(f"unknown encoding {layout.encoding!r}") from None
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        try:
            if layout.bom and layout.encoding.replace("-", "").lower() in ("utf8", "utf_8"):
                fh.write(codecs.BOM_UTF8)
            for title in layout.title_lines:  # a title above the header, as it came
                fh.write(encoder.encode(title + layout.line_end))
            if layout.header:
                fh.write(encoder.encode(header_line + (layout.line_end if n else "")))
            for start in range(0, n, CHUNK_ROWS):
                part = points.iloc[start : start + CHUNK_ROWS]
                if widths is not None and n <= CHUNK_ROWS and _FIRST_CHUNK in widths:
                    cells = widths.pop(_FIRST_CHUNK)  # formatted once, for the widths
                else:
                    cells = _quote(_cells(part, layout, extra), layout, is_text)
                if widths is not None:
                    cells = _pad(cells, widths, is_text)
                rows = pc.binary_join_element_wise(*cells, join)
                if aligned:
                    rows = pc.utf8_rtrim(rows, " ")
                last = start + CHUNK_ROWS >= n
                text = layout.line_end.join(rows.to_pylist())
                if not last or layout.final_newline:
                    text += layout.line_end
                fh.write(encoder.encode(text, final=last))
            if not n and layout.header and layout.final_newline:
                fh.write(encoder.encode(layout.line_end, final=True))
        except UnicodeEncodeError as exc:
            raise InputError(
                f"{path}: {exc.object[exc.start : exc.end]!r} cannot be written in "
                f"{layout.encoding}; choose another --encoding (utf-8, gb18030)"
            ) from None
    return {
        "output": str(path),
        "layout": layout.name,
        "encoding": layout.encoding,
        "rows": n,
        "columns": names,
        "rows_made": int(made_mask(points).sum()),
        "courses_as_read": int(courses_as_read(points).sum())
        if layout.source and layout.field_column("course") is not None
        else 0,
    }


def _relative_times_warning(points: pd.DataFrame, layout: Layout) -> list[str]:
    """A warning when times that count from a scene start (all before 1973: relative, the
    window shows them as T+…) are written as dates: they read as days of January 1970."""
    from wakeline.core.io.reader import RELATIVE_BELOW_S

    if layout.time.kind != "text" or layout.name == "canonical":  # canonical: as stored
        return []
    if not re.search(r"%[YymdbBaj]", layout.time.pattern + layout.time.date_pattern):
        return []  # times of day alone (23:50:00.5, 120059): written as the file had them
    if "time" not in points.columns or not len(points):
        return []
    latest = (pd.to_datetime(points["time"], utc=True).max() - EPOCH).total_seconds()
    if not latest < RELATIVE_BELOW_S:
        return []
    return [
        "the times count from a scene start (relative: T+… in the window) and are written "
        f"as dates of January 1970 ({layout.time.pattern}); to keep them as seconds, "
        "export like a file whose times are seconds (--like)"
    ]


def _shared_ids(ids: pd.DataFrame, layout: Layout) -> pd.Series:
    """The batch ids written for more than one sensor in a layout without a sensor column
    (each id's sensors, as a list); empty when the file tells every track apart."""
    if any(c.field == "sensor" for c in layout.columns) or "sensor" not in ids.columns:
        return pd.Series(dtype=object)
    keys = ids[["sensor", "batch"]].astype("str").drop_duplicates()
    if keys["sensor"].nunique() < 2:
        return pd.Series(dtype=object)
    shared = keys.groupby("batch")["sensor"].agg(list)
    return shared[shared.map(len) > 1]


def _shared_ids_warning(ids: pd.DataFrame, layout: Layout) -> list[str]:
    """A warning when tracks of different sensors share a batch id and the layout has no
    sensor column: read back, each such id is one track (the sensors' fixes mixed)."""
    shared = _shared_ids(ids, layout)
    if shared.empty:
        return []
    batch, sensors = shared.index[0], shared.iloc[0]
    return [
        f"{len(shared):,} batch id(s) are used by more than one sensor (e.g. {batch}: "
        f"{', '.join(sensors)}) and the layout {layout.name!r} has no sensor column: read "
        "back, each is one track with the sensors' fixes mixed; leave out --keep-ids "
        "(or give --renumber) for fresh batch numbers, or export one sensor at a time"
    ]


def _target_rows_order(ids: pd.DataFrame, given: pd.DataFrame) -> np.ndarray:
    """The row order of a merged, fused or renumbered table: target by target (in order
    of their start, then of the id written), each target's rows in time order (rows at
    one time: by the member's sensor and batch, then as given). Depends on the rows, not
    on the order they come in: the window's layer (kept in the file's order) and the
    CLI's canonical CSV of it (track order) are written alike."""
    n = len(ids)
    # the target of each row: its written id, numbered in the ids' text order
    code = (
        ids.groupby([ids["sensor"].astype("str"), ids["batch"].astype("str")], sort=True)
        .ngroup()
        .to_numpy()
    )
    t = pd.to_datetime(ids["time"], utc=True)
    ok = t.notna().to_numpy()
    ns = np.where(ok, (t - EPOCH).dt.as_unit("ns").to_numpy().view("int64"), 0)
    ns = np.where(ok, ns, np.iinfo("int64").max)
    n_targets = int(code.max()) + 1 if n else 0
    start = pd.Series(ns).groupby(code).min().reindex(np.arange(n_targets)).to_numpy()
    rank = np.empty(n_targets, dtype="int64")
    rank[np.lexsort((np.arange(n_targets), start))] = np.arange(n_targets)
    sensor = pd.factorize(given["sensor"].astype("str"), sort=True)[0]
    batch = pd.factorize(given["batch"].astype("str"), sort=True)[0]
    return np.lexsort((np.arange(n), batch, sensor, ns, rank[code]))


def _has_file_rows(points: pd.DataFrame) -> bool:
    """Whether ``points`` carry their file's rows (:data:`FILE_ROW`, usable as
    :func:`~wakeline.core.schema.in_file_order` uses it): written in that order."""
    if FILE_ROW not in points.columns:
        return False
    rows = pd.to_numeric(points[FILE_ROW], errors="coerce")
    return bool(rows.notna().all() and rows.is_unique)


def _rows_in(points: pd.DataFrame, order: str) -> pd.DataFrame:
    """``points`` in time order (``time``, stable) or track by track (``track``: tracks
    in order of first appearance, each track's rows as they come); else as given."""
    if order == "time":
        ns = pd.to_datetime(points["time"], utc=True).dt.tz_localize(None)
        return points.iloc[np.argsort(ns.to_numpy("datetime64[ns]"), kind="stable")]
    if order == "track":
        sensor = pd.factorize(points["sensor"].astype("str"))[0]
        batch = pd.factorize(points["batch"].astype("str"))[0]
        first = pd.factorize(sensor * (batch.max(initial=0) + 1) + batch)[0]
        return points.iloc[np.argsort(first, kind="stable")]
    return points


def export_like(
    points: pd.DataFrame,
    layout: Layout,
    path,
    columns: list[str] | None = None,
    renumber: bool | None = None,
    members_path=None,
    prefer_sensor: str | None = None,
    keep_targets: bool = False,
    sort: str | None = None,
) -> dict:
    """Give merged/fused targets their ids (:func:`assign_target_ids`), write ``points`` in
    ``layout`` and, for merged or fused input, the members table beside (``members_path``,
    default ``<path stem>.members.csv``). Returns the report of :func:`write_layout` plus
    ``members`` (the sidecar's path, or None), ``targets``, ``warnings`` and ``notes``.

    ``renumber``: True gives every target a fresh batch number 1, 2, … (in order of
    start); False keeps the first member's ids; None (default) renumbers only when the
    ids written would collide in a layout that cannot tell them apart (no sensor column,
    one batch id used by two sensors: AIS 3 and radar 3 rejected as a pair), so that the
    file reads back as the targets it was written from (a note says so).

    ``keep_targets``: tracks with targets are written as they are, each row with its
    ``target`` in a column after the layout's (as GeoJSON and GPX write them,
    docs/export.md "Targets in every format"): read back, the same tracks with the same
    targets; no ids are given, no members table written.

    ``sort``: ``time`` writes the rows in time order (tracks interleaved; ties keep
    their order), ``track`` track by track (each track's rows as they come, tracks in
    order of first appearance); None (default) the layout's ``row_order`` (ORIGINAL's,
    as its first rows show it) for a table without its file's rows, else as below. The
    report's ``row_order`` says which was written.

    Row order: an unchanged table is written in its file's order (the window's layers
    carry each point's file row, :data:`~wakeline.core.schema.FILE_ROW`), else as given;
    a merged, fused or renumbered table target by target, each in time order
    (:func:`_target_rows_order`).
    """
    from pathlib import Path

    from wakeline.core.io.writer import write_csv

    points = in_file_order(points)
    own = {c.key or c.name for c in layout.columns if c.field is None}
    notes: list[str] = []
    if own & {"target", "members"} or keep_targets:
        # the operator's own columns, not a merge result; or the targets kept as a column
        ids, members = points, None
        if keep_targets and "target" not in own:
            columns = [*(c for c in columns or () if c != "target"), "target"]
    else:
        ids, members = assign_target_ids(
            points, renumber=bool(renumber), prefer_sensor=prefer_sensor
        )
        shared = _shared_ids(ids, layout) if renumber is None else pd.Series(dtype=object)
        if not shared.empty:
            if members is None:  # tracks of several sensors, not merged: one target each
                label = points["sensor"].astype("str") + ":" + points["batch"].astype("str")
                ids, members = assign_target_ids(points.assign(target=label), renumber=True)
            else:
                ids, members = assign_target_ids(points, renumber=True, prefer_sensor=prefer_sensor)
            batch, sensors = shared.index[0], shared.iloc[0]
            notes.append(
                f"batch ids renumbered 1–{members['batch'].nunique()}: {len(shared):,} id(s) "
                f"were used by more than one sensor (e.g. {batch}: {', '.join(sensors)}) and "
                f"the layout {layout.name!r} has no sensor column, so they would read back "
                "as one track; the members table maps each number to its tracks"
            )
        if members is not None:
            ids = ids.iloc[_target_rows_order(ids, points)]  # rows as in points
    from_file = _has_file_rows(points)
    order = sort or ("" if from_file else layout.row_order)
    ids = _rows_in(ids, order)
    report = write_layout(ids, layout, path, columns=columns)
    report["row_order"] = order or ("file" if from_file else "as given")
    report["warnings"] = _shared_ids_warning(ids, layout) + _relative_times_warning(ids, layout)
    if report["courses_as_read"]:
        notes.append(
            f"{report['courses_as_read']:,} course(s) written as the file had them (360.0, "
            "or a value outside [0, 360) the import blanked): the point table holds 360.0 "
            "as 0 (north) and blanks the others; a course a step changed is written as "
            "the step left it"
        )
    notes.extend(speeds_not_written(ids, layout))
    report["notes"] = notes
    report["members"] = None
    report["targets"] = None
    if members is not None:
        path = Path(path)
        side = Path(members_path) if members_path else path.with_name(path.stem + ".members.csv")
        write_csv(members, side)
        report["members"] = str(side)
        report["targets"] = int(members["target"].nunique())
    return report


def layout_meta(
    path,
    report: dict | None = None,
    tz: str | None = None,
    speed_unit: str = "auto",
    distance_unit: str = "auto",
) -> dict | None:
    """The layout of an imported file as JSON-able data, for ``layer.meta["layout"]``
    (stored in the project with the layer). ``report`` is the import report. None when
    the layout cannot be learnt (e.g. a time format only the importer's fallback parser
    reads): the import must not fail for it, and the layer can still be exported in a
    preset layout. ``tz``: the zone naive times were read in (default: ``report["tz"]``,
    else UTC). ``speed_unit``/``distance_unit``: the units the import was given for
    columns whose headers name none (written back in them)."""
    from dataclasses import replace

    from wakeline.core.io.layout import describe_layout

    try:
        layout = describe_layout(path, report, tz=tz)
    except (InputError, OSError, ValueError, KeyError):
        return None
    return replace(layout, speed_unit=speed_unit, distance_unit=distance_unit).to_dict()


def layer_layout(layers, name: str) -> Layout:
    """The layout a layer came in: its own ``meta["layout"]``, or that of the layer it was
    made from (``meta["from"]``, followed up to the imported source). ``layers`` maps
    layer names to objects with ``meta`` (:class:`wakeline.core.project.Layer`). Falls
    back to describing the source file again (``meta["file"]``) when it is still there.
    Raises :class:`InputError` when no layout can be found."""
    from pathlib import Path

    from wakeline.core.io.layout import describe_layout

    seen = set()
    current = name
    while current in layers and current not in seen:
        seen.add(current)
        meta = layers[current].meta or {}
        if meta.get("layout"):
            return Layout.from_dict(meta["layout"])
        if meta.get("file") and Path(meta["file"]).exists():
            return describe_layout(meta["file"], meta.get("report"))
        # A session layer knows its input layer by id (wakeline.core.session.Layer.parent).
        current = meta.get("from") or getattr(layers[current], "parent", None)
    raise InputError(
        f"{name}: no imported file behind this layer, so there is no layout to copy; "
        "export as canonical CSV or choose a layout"
    )


#: The offsets tried for ORIGINAL's naive times against IN's (UTC): every quarter hour
#: from −14 h to +14 h (every zone in use).
_OFFSETS_MIN = np.arange(-14 * 60, 14 * 60 + 1, 15)


def _row_keys(points: pd.DataFrame, shift_ns: int = 0) -> np.ndarray:
    """A 64-bit hash of each row's (sensor, batch, lon, lat, time − ``shift_ns``)."""
    ns, ok = _epoch_ns(points["time"])
    key = pd.DataFrame(
        {
            "track": points["sensor"].astype("str") + "\x00" + points["batch"].astype("str"),
            "lon": np.round(points["lon"].to_numpy(dtype="float64"), 7),
            "lat": np.round(points["lat"].to_numpy(dtype="float64"), 7),
            "ns": np.where(ok, ns - shift_ns, -1),
        }
    )
    return pd.util.hash_pandas_object(key, index=False).to_numpy()


def import_offsets(original, points: pd.DataFrame, read: dict | None = None) -> dict:
    """The UTC offsets the import seems to have read ``original``'s naive times in, found
    by comparing its first lines (1 MB of text, read as UTC by the importer with
    ``read``: ``read_points`` keywords) with IN's ``points``: the same track at the same
    place (to 1e-7°) at a time one offset apart (operator test 7, D15: ``export
    --like`` of a file imported with ``--tz`` wrote UTC clock times, 2 h off, unless
    ``--tz`` was given again). Returns ``{"rows": n, "hits": {minutes: rows}}``: how many
    of those first rows, read as UTC and moved back by each offset (and by no other: a
    ship at rest matches itself at other times), are rows IN holds; offsets that explain
    at least 1 % of such rows (and 2). Two offsets: a zone with summer time. Empty
    ``hits`` when nothing can be told (ORIGINAL unreadable, no common rows)."""
    import tempfile
    from pathlib import Path

    from wakeline.core.io.compressed import compression_of
    from wakeline.core.io.reader import read_points

    original = Path(original)
    try:
        packed = compression_of(original)
    except (OSError, InputError):
        packed = None
    from wakeline.core.io.layout import _raw_head

    try:
        head = _raw_head(original, packed)
    except OSError:
        return {"rows": 0, "hits": {}}
    if len(head) >= (1 << 20):
        head = head[: head.rfind(b"\n") + 1]
    keywords = {k: v for k, v in (read or {}).items() if v is not None and k != "tz"}
    with tempfile.TemporaryDirectory(prefix="wakeline-zone-") as tmp:
        inner = Path(original.stem) if packed else original  # radar.csv.gz: radar.csv
        sample = Path(tmp) / ("head" + (inner.suffix or ".csv"))
        sample.write_bytes(head)
        try:
            first = read_points(sample, **keywords).points
        except (InputError, ValueError, KeyError, OSError):
            return {"rows": 0, "hits": {}}
    first = first[first["time"].notna()]
    if not len(first) or not len(points):
        return {"rows": 0, "hits": {}}
    have = np.unique(_row_keys(points))
    match = np.zeros((len(_OFFSETS_MIN), len(first)), dtype=bool)
    for k, minutes in enumerate(_OFFSETS_MIN):
        moved = _row_keys(first, int(minutes) * 60_000_000_000)
        pos = np.clip(np.searchsorted(have, moved), 0, len(have) - 1)
        match[k] = have[pos] == moved
    # a row at rest matches itself at other times too: only rows one offset explains count
    one = match.sum(axis=0) == 1
    counts = match[:, one].sum(axis=1)
    floor = max(2, int(np.ceil(0.01 * one.sum())))
    hits = {int(m): int(n) for m, n in zip(_OFFSETS_MIN, counts, strict=True) if n >= floor}
    return {"rows": int(len(first)), "hits": hits}


def offset_text(minutes: int) -> str:
    """``+02:00`` for 120 minutes, ``-03:30`` for −210."""
    sign = "+" if minutes >= 0 else "-"
    h, m = divmod(abs(int(minutes)), 60)
    return f"{sign}{h:02d}:{m:02d}"

"""Tracks: grouping the point table by ``(sensor, batch)``, sorted by time.

Everything here is vectorized over all tracks at once: rows are sorted so each track is
one contiguous run, and per-track quantities come from ``np.*.reduceat`` over the run
starts. No Python loop per point or per track.
"""

import weakref
from dataclasses import dataclass

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core import geo
from wakeline.core.schema import ordered_columns, time_seconds
from wakeline.core.sorted_sets import repeat_runs


@dataclass(frozen=True)
class TrackIndex:
    """Where each track lies in a sorted point table.

    ``starts[k]:ends[k]`` are the rows of track ``k``; ``track_of_row[i]`` is the track
    number of row ``i``; ``keys`` holds ``sensor`` and ``batch`` of each track.
    """

    starts: np.ndarray
    ends: np.ndarray
    track_of_row: np.ndarray
    keys: pd.DataFrame

    @property
    def n_tracks(self) -> int:
        return len(self.starts)

    @property
    def sizes(self) -> np.ndarray:
        return self.ends - self.starts

    def first_of_track(self) -> np.ndarray:
        """Boolean per row: the first row of its track."""
        mask = np.zeros(len(self.track_of_row), dtype=bool)
        mask[self.starts] = True
        return mask


def _key_codes(df: pd.DataFrame, sort: bool = True) -> tuple[np.ndarray, np.ndarray]:
    return _factorized(df, sort)[:2]


def _factorized(df: pd.DataFrame, sort: bool = True) -> tuple:
    """Codes of sensor and batch (int64) and their distinct values (in text order with
    ``sort``)."""
    sensor_codes, sensor_uniques = _factorize(df["sensor"], sort)
    batch_codes, batch_uniques = _factorize(df["batch"], sort)
    return sensor_codes, batch_codes, sensor_uniques, batch_uniques


def _factorize(col: pd.Series, sort: bool) -> tuple[np.ndarray, object]:
    """``pd.factorize(col, sort=sort)`` (int64 codes), faster for Arrow text of integers."""
    fast = _integer_text_codes(col) if sort else None
    if fast is not None:
        return fast
    codes, uniques = pd.factorize(col, sort=sort, use_na_sentinel=False)
    return codes.astype("int64"), uniques


def _integer_text_codes(col: pd.Series) -> tuple[np.ndarray, object] | None:
    """Sorted factorization of Arrow text holding plain integers ("0", "17", "-3": no
    sign, spaces or leading zeros a round trip would change), or None.

    Radar batch numbers and MMSIs are such text. Parsing them is linear and a lookup on the
    integer replaces a hash of millions of strings (which misses the cache once there are
    ~10⁵ distinct values); the few distinct values are then put in text order. The codes
    and values are those of ``pd.factorize(col, sort=True)``."""
    arr = _arrow_text(col)
    if arr is None or len(col) == 0:
        return None
    sample = arr.take(pa.array(np.linspace(0, len(arr) - 1, 64).astype("int64")))
    if not pc.all(pc.match_substring_regex(sample, r"^-?[0-9]+$")).as_py():
        return None  # a failed cast of millions of rows takes seconds: look at a few first
    try:
        ints = pc.cast(arr, pa.int64())
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
        return None
    v = ints.to_numpy()
    lo, hi = int(v.min()), int(v.max())
    if hi - lo <= 4 * len(v):  # a table over the range of values
        present = np.zeros(hi - lo + 1, dtype=bool)
        present[v - lo] = True
        values = np.flatnonzero(present) + lo
        codes = (np.cumsum(present, dtype=np.intp) - 1)[v - lo]
    else:
        values, codes = np.unique(v, return_inverse=True)
    text = pa.array(values).cast(pa.string())  # the plain text of each distinct value
    # every row's text must be its value's plain text: same length is enough, as the cast
    # accepts no spaces and a sign or leading zero makes it longer
    plain_length = pc.binary_length(text).to_numpy().astype("int64")
    if not np.array_equal(pc.binary_length(arr).to_numpy().astype("int64"), plain_length[codes]):
        return None
    order = pc.sort_indices(text).to_numpy()  # text order: "10" < "9"
    new_code = np.empty(len(order), dtype="int64")
    new_code[order] = np.arange(len(order))
    uniques = pd.array(text.take(pa.array(order)).cast(arr.type), dtype=col.dtype)
    return new_code[codes].astype("int64"), uniques


#: Tables known to be in track order: id → (weak reference, fingerprint, index, seconds).
#: "Sort once": every step asks :func:`sorted_with_index`, which answers from here for a
#: table it has sorted or checked before, without sorting or re-deriving seconds.
_IN_ORDER: dict[int, tuple[weakref.ref, tuple, "TrackIndex", np.ndarray]] = {}


def _fingerprint(df: pd.DataFrame) -> tuple:
    """Length and the buffers holding the key columns: replacing a column changes it."""
    parts: list = [len(df)]
    for name in ("sensor", "batch", "time"):
        arr = df[name].array
        if isinstance(arr, pd.arrays.DatetimeArray):
            parts.append(arr.asi8.ctypes.data)
        elif hasattr(arr, "_pa_array"):
            parts.append(tuple(c.buffers()[-1].address for c in arr._pa_array.chunks))
        else:  # numpy-backed (object, numbers): the buffer, when no copy is made
            parts.append(np.asarray(arr).__array_interface__["data"][0])
    return tuple(parts)


def _remember(df: pd.DataFrame, index: "TrackIndex", t: np.ndarray) -> None:
    key = id(df)
    t = t.view()
    t.flags.writeable = False  # shared by every step that asks: nobody may change it
    ref = weakref.ref(df, lambda _ref, key=key: _IN_ORDER.pop(key, None))
    _IN_ORDER[key] = (ref, _fingerprint(df), index, t)


def remember_order(df: pd.DataFrame, index: "TrackIndex", t: np.ndarray) -> None:
    """Record that ``df`` (a fresh RangeIndex) is in track order with ``index`` and time
    ``t`` (s), as :func:`sorted_with_index` would find: for a slice of whole tracks of a
    table in order, whose index and seconds are known already."""
    _remember(df, index, t)


def known_order(df: pd.DataFrame) -> tuple["TrackIndex", np.ndarray] | None:
    """The :class:`TrackIndex` and time (s) of a table already sorted or checked, else None."""
    entry = _IN_ORDER.get(id(df))
    if entry is None or entry[0]() is not df:
        return None
    try:
        if entry[1] != _fingerprint(df):
            return None
    except (KeyError, AttributeError):
        return None
    return entry[2], entry[3]


def track_seconds(df: pd.DataFrame) -> np.ndarray:
    """:func:`time_seconds` of ``df["time"]``, from the order registry when it is known
    (then a shared, read-only array)."""
    known = known_order(df)
    return known[1] if known is not None else time_seconds(df["time"])


def _arrow_text(col: pd.Series) -> pa.ChunkedArray | None:
    arr = col.array
    if not hasattr(arr, "_pa_array") or col.hasnans:
        return None
    return arr._pa_array


def _key_runs(df: pd.DataFrame, t: np.ndarray) -> tuple[np.ndarray, bool] | None:
    """Per row, True where a new run of equal (sensor, batch) starts, and whether the table
    is already ordered by sensor, batch (as text) and time; None when the keys are not
    plain text or some run is not in time order (then only a full sort will do).

    Arrow compares neighbouring texts byte-wise (UTF-8 order is code-point order, the
    order of a sort by text), so no factorization of 10 M strings is needed."""
    sensor, batch = _arrow_text(df["sensor"]), _arrow_text(df["batch"])
    if sensor is None or batch is None:
        return None
    n = len(df)
    s0, s1 = sensor.slice(0, n - 1), sensor.slice(1)
    b0, b1 = batch.slice(0, n - 1), batch.slice(1)
    s_eq = pc.equal(s1, s0).to_numpy()
    same = s_eq & pc.equal(b1, b0).to_numpy()
    if np.any(same & ~(np.diff(t) >= 0)):
        return None
    change = np.empty(n, dtype=bool)
    change[0] = True
    change[1:] = ~same
    ordered = not pc.any(pc.less(s1, s0)).as_py() and not np.any(s_eq & pc.less(b1, b0).to_numpy())
    return change, ordered


def _reorder_runs(
    df: pd.DataFrame, change: np.ndarray
) -> tuple[pd.DataFrame, "TrackIndex", np.ndarray] | None:
    """The table in track order when every track is one run of rows in time order and
    only the runs are out of order (batches numbered "0", "1", …, "10" in a file: not
    text order): the runs are sorted, not the rows. None when a track is split over runs.
    """
    starts = np.flatnonzero(change)
    if len(starts) * 8 > len(df):
        return None  # short runs (a time-ordered export): tracks interleave, sort the rows
    sizes = np.diff(np.append(starts, len(df)))
    run_sensor = df["sensor"].iloc[starts].reset_index(drop=True)
    run_batch = df["batch"].iloc[starts].reset_index(drop=True)
    sensor_code, _ = pd.factorize(run_sensor, sort=True)
    batch_code, _ = pd.factorize(run_batch, sort=True)
    key = sensor_code.astype("int64") * (int(batch_code.max()) + 1) + batch_code
    run_order = np.argsort(key, kind="stable")
    if np.any(np.diff(key[run_order]) == 0):
        return None  # a track in several runs: the rows must be sorted
    sizes = sizes[run_order]
    order = concat_ranges(starts[run_order], sizes)
    run = repeat_runs(None, sizes)
    out = df.drop(columns=["sensor", "batch"]).iloc[order].reset_index(drop=True)
    for name, values in sorted(
        (("sensor", run_sensor), ("batch", run_batch)), key=lambda nv: df.columns.get_loc(nv[0])
    ):
        column = pd.Series(values.array.take(run_order).take(run), dtype=df[name].dtype)
        out.insert(df.columns.get_loc(name), name, column)
    change = np.zeros(len(df), dtype=bool)
    change[np.cumsum(sizes) - sizes] = True
    index = _index(change, run_sensor.iloc[run_order], run_batch.iloc[run_order])
    return out, index, order


def sorted_with_index(df: pd.DataFrame) -> tuple[pd.DataFrame, "TrackIndex"]:
    """Rows ordered by sensor, batch (as text) and time, and their :class:`TrackIndex`,
    from one factorization. The table is returned as is when already in order.

    Sort once: the answer is remembered for the returned table (see :func:`known_order`),
    so the next step that asks gets it back without sorting or checking again."""
    known = known_order(df)
    if known is not None:
        return df, known[0]
    n = len(df)
    if n == 0:
        out = df.reset_index(drop=True)
        return out, track_index(out)
    fresh = isinstance(df.index, pd.RangeIndex) and df.index.start == 0 and df.index.step == 1
    t = time_seconds(df["time"])
    runs = _key_runs(df, t) if n > 1 else None
    if runs is not None and runs[1]:
        out = df if fresh else df.reset_index(drop=True)
        index = _index_from_change(out, runs[0])
        _remember(out, index, t)
        return out, index
    if runs is not None and df.columns.is_unique:
        reordered = _reorder_runs(df, runs[0])
        if reordered is not None:
            out, index, order = reordered
            _remember(out, index, t[order])
            return out, index
    sensor, batch, sensor_uniques, batch_uniques = _factorized(df)
    track = sensor * (int(batch.max()) + 1) + batch
    if _is_sorted(track, t):
        out = df if fresh else df.reset_index(drop=True)
        index = _index_from_codes(out, sensor, batch)
        _remember(out, index, t)
        return out, index
    order = _sort_order(track, t)
    out = _take_rows(
        df, order, {"sensor": (sensor, sensor_uniques), "batch": (batch, batch_uniques)}
    )
    index = _index_from_track_codes(
        track[order], int(batch.max()) + 1, keys=(sensor_uniques, batch_uniques)
    )
    _remember(out, index, t[order])
    return out, index


def _index_from_track_codes(track: np.ndarray, n_batch: int, keys: tuple) -> TrackIndex:
    """The index of a sorted table from its track codes (``sensor * n_batch + batch``) and
    the distinct sensor and batch values the codes point to."""
    change = np.empty(len(track), dtype=bool)
    change[0] = True
    np.not_equal(track[1:], track[:-1], out=change[1:])
    code = track[change]
    sensor_values, batch_values = keys
    return _index(change, sensor_values.take(code // n_batch), batch_values.take(code % n_batch))


def _take_rows(df: pd.DataFrame, order: np.ndarray, keys: dict[str, tuple]) -> pd.DataFrame:
    """``df.iloc[order]`` with a fresh index; Arrow text keys are rebuilt from their few
    distinct values (a gather of sorted codes) instead of a random-access take of
    millions of strings, which is 5–10× slower."""
    if not df.columns.is_unique or any(_arrow_text(df[k]) is None for k in keys):
        return df.iloc[order].reset_index(drop=True)
    out = df.drop(columns=list(keys)).iloc[order].reset_index(drop=True)
    for name in sorted(keys, key=df.columns.get_loc):  # insert left to right
        codes, uniques = keys[name]
        values = pd.Series(uniques.take(codes[order]), dtype=df[name].dtype)
        out.insert(df.columns.get_loc(name), name, values)
    return out


def _is_sorted(track: np.ndarray, t: np.ndarray) -> bool:
    d_track = np.diff(track)
    return bool(np.all(d_track >= 0) and np.all((d_track > 0) | (np.diff(t) >= 0)))


def _sort_order(track: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Stable order by (track, time).

    When the rows of every track already come in time order (a time-ordered radar or AIS
    export), a stable sort by track alone is that order: a radix sort on 16-bit digits of
    the track code, linear in the rows. Otherwise one int64 key (ms) when it fits, else a
    lexsort."""
    order = _stable_code_order(track)
    if order is not None and _is_sorted(track[order], t[order]):
        return order
    t_ms = np.round((t - t.min()) * 1000.0)
    span = float(t_ms.max()) + 1.0
    if float(track.max() + 1) * span < 2**62:
        order = np.argsort(track.astype("int64") * int(span) + t_ms.astype("int64"), kind="stable")
        if _is_sorted(track[order], t[order]):  # sub-millisecond ties could leave disorder
            return order
    return np.lexsort((t, track))


def _stable_code_order(code: np.ndarray) -> np.ndarray | None:
    """Stable argsort of non-negative integer codes below 2³², by one or two radix passes
    on 16-bit digits (numpy sorts 16-bit integers by radix); None for larger codes."""
    if not len(code):
        return np.zeros(0, dtype="int64")
    top = int(code.max())
    if top < 2**16:
        return np.argsort(code.astype("uint16"), kind="stable")
    if top < 2**32:
        low = np.argsort((code & 0xFFFF).astype("uint16"), kind="stable")
        return low[np.argsort((code[low] >> 16).astype("uint16"), kind="stable")]
    return None


#: The number an id starts with, read by :func:`natural_ranks` (at most 18 digits).
_LEADING_INTEGER = r"^([+-]?\d{1,18})(.*)$"


def natural_ranks(values) -> tuple[np.ndarray, int]:
    """Each value's rank in natural order and the number of distinct values: ids that
    start with a number by that number (``2`` before ``10``; ``338000000#2``, a track
    clean split, after ``338000000`` and before ``338000001``), then by the rest of the
    id, before every id that starts otherwise (in text order); ties (``7``, ``007``) in
    text order. A total order of the values themselves, whatever table holds them, so
    pieces of one file order alike. Operator test 7, D19: the maneuvers CSV listed
    batches 161, 162, 21, … ."""
    codes, uniques = pd.factorize(pd.Series(values), sort=False, use_na_sentinel=False)
    text = pd.Series(uniques, dtype=object).astype(str)
    parts = text.str.extract(_LEADING_INTEGER)
    has = parts[0].notna().to_numpy(dtype=bool)
    number = np.zeros(len(text), dtype="int64")
    if has.any():
        number[has] = parts[0][has].astype("int64").to_numpy()
    rest = parts[1].fillna("").to_numpy(dtype=str)
    order = np.lexsort((text.to_numpy(dtype=str), rest, number, ~has))
    rank = np.empty(len(text), dtype="int64")
    rank[order] = np.arange(len(text))
    return rank[codes.astype("int64")], len(text)


def natural_order(sensor, batch) -> np.ndarray:
    """The stable order of rows by sensor (text) and batch (:func:`natural_ranks`)."""
    s_codes, s_names = pd.factorize(pd.Series(sensor), sort=True, use_na_sentinel=False)
    b_rank, nb = natural_ranks(batch)
    return np.argsort(s_codes.astype("int64") * max(nb, 1) + b_rank, kind="stable")


def natural_track_order(df: pd.DataFrame) -> pd.DataFrame:
    """``df`` with its tracks in natural order (:func:`natural_ranks`: batch 21 before
    161), each track's rows in their order: how the command line writes step outputs
    (clean, maneuvers, compress, associate) and the window's maneuvers export. The
    steps themselves order tracks by text (the sort every step shares); only the files
    are written so. A table without sensor and batch, or already so, is returned as it
    is."""
    if "sensor" not in df.columns or "batch" not in df.columns or len(df) < 2:
        return df
    order = natural_order(df["sensor"], df["batch"])
    if (order[1:] > order[:-1]).all():
        return df
    return df.iloc[order].reset_index(drop=True)


def sort_points(df: pd.DataFrame) -> pd.DataFrame:
    """Rows ordered by sensor, batch (as text) and time; stable; a fresh RangeIndex.

    Returns ``df`` itself (not a copy) when it is already in that order.
    """
    return sorted_with_index(df)[0]


def track_index(df: pd.DataFrame) -> TrackIndex:
    """The :class:`TrackIndex` of a table sorted by :func:`sort_points`."""
    known = known_order(df)
    if known is not None:
        return known[0]
    if len(df) == 0:
        empty = np.zeros(0, dtype="int64")
        return TrackIndex(
            empty, empty, empty, pd.DataFrame({"sensor": [], "batch": []}, dtype="str")
        )
    sensor_codes, batch_codes = _key_codes(df, sort=False)
    return _index_from_codes(df, sensor_codes, batch_codes)


def _index_from_codes(
    df: pd.DataFrame, sensor_codes: np.ndarray, batch_codes: np.ndarray
) -> TrackIndex:
    n = len(df)
    change = np.empty(n, dtype=bool)
    change[0] = True
    change[1:] = (sensor_codes[1:] != sensor_codes[:-1]) | (batch_codes[1:] != batch_codes[:-1])
    return _index_from_change(df, change)


def _index_from_change(df: pd.DataFrame, change: np.ndarray) -> TrackIndex:
    starts = np.flatnonzero(change)
    return _index(change, df["sensor"].iloc[starts], df["batch"].iloc[starts])


def _index(change: np.ndarray, sensor, batch) -> TrackIndex:
    """The index of a sorted table from its track-start mask and each track's keys."""
    starts = np.flatnonzero(change).astype("int64")
    ends = np.append(starts[1:], len(change)).astype("int64")
    # a bool cumsum casts through a buffer with the GIL held (10 ms at 1.1 M points, the
    # window stalled); counted as integers it releases it
    track_of_row = np.cumsum(change, dtype="int64") - 1
    keys = pd.DataFrame(
        {"sensor": np.asarray(sensor, dtype=object), "batch": np.asarray(batch, dtype=object)}
    ).astype("str")
    return TrackIndex(starts, ends, track_of_row, keys)


def track_origins(df: pd.DataFrame, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """Per-track local-plane origin, degrees: the direction of the mean of the track's
    points on the unit sphere (so it turns with the track when the scene is carried
    elsewhere on the globe, and lies on the short side of the 180° meridian)."""
    return _origins(df, index)[:2]


def _origins(df: pd.DataFrame, index: TrackIndex):
    """:func:`track_origins`, and the sines and cosines of every row's longitude and
    latitude it summed."""
    sl, cl = geo.sin_cos_deg(df["lon"].to_numpy(dtype="float64"))
    sp, cp = geo.sin_cos_lat(df["lat"].to_numpy(dtype="float64"))
    if index.n_tracks == 0:
        return np.zeros(0), np.zeros(0), sl, cl, sp, cp
    ex = np.add.reduceat(cp * cl, index.starts)
    ey = np.add.reduceat(cp * sl, index.starts)
    ez = np.add.reduceat(sp, index.starts)
    lon0 = np.degrees(np.arctan2(ey, ex))
    lat0 = np.degrees(np.arctan2(ez, np.sqrt(ex * ex + ey * ey)))
    return lon0, lat0, sl, cl, sp, cp


def local_xy(df: pd.DataFrame, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """Every point in its own track's local plane (azimuthal equidistant about the track's
    origin, metres; see geo.to_local).

    The same arithmetic as :func:`geo.to_local`, bit for bit, with the sines and cosines
    of the longitudes taken once for the origins and the plane, and the origins' once per
    track."""
    lon0, lat0, sl, cl, sp, cp = _origins(df, index)
    if index.n_tracks == 0:
        return np.zeros(0), np.zeros(0)
    sizes = index.sizes  # per-track values spread by repeat, not by a gather per row
    per_track = (*geo.sin_cos_deg(lon0), *geo.sin_cos_lat(lat0))
    sl0, cl0, sp0, cp0 = (repeat_runs(v, sizes) for v in per_track)
    return geo.plane_xy(sl, cl, sp, cp, sl0, cl0, sp0, cp0)


def step_motion(
    df: pd.DataFrame, index: TrackIndex
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per row: distance (m), time step (s), speed (kn) and course (deg) from the previous row.

    The first row of each track has NaN. Distances are great-circle (haversine), courses
    initial great-circle bearings, so tracks crossing 180° are handled.
    """
    n = len(df)
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    t = track_seconds(df)
    dist = np.full(n, np.nan)
    dt = np.full(n, np.nan)
    course = np.full(n, np.nan)
    if n > 1:
        dist[1:] = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])
        dt[1:] = t[1:] - t[:-1]
        course[1:] = geo.initial_bearing_deg(lon[:-1], lat[:-1], lon[1:], lat[1:])
    first = index.first_of_track()
    dist[first] = np.nan
    dt[first] = np.nan
    course[first] = np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = np.where(dt > 0, dist / dt / geo.KN_MS, np.nan)
    course[dist == 0] = np.nan
    return dist, dt, speed, course


def derive_motion(
    df: pd.DataFrame, index: TrackIndex | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Speed (kn) and course (deg) of every point derived from positions.

    A point takes the motion of the leg arriving at it; the first point of a track takes
    the leg leaving it. Single-point tracks and zero-time steps give NaN. ``df`` must be
    sorted (:func:`sort_points`).
    """
    index = index or track_index(df)
    _, _, speed, course = step_motion(df, index)
    # First point of each track: copy from the second row when that row is in the same track.
    first = index.starts
    has_next = index.sizes > 1
    speed[first[has_next]] = speed[first[has_next] + 1]
    course[first[has_next]] = course[first[has_next] + 1]
    return speed, course


def fill_motion(df: pd.DataFrame) -> pd.DataFrame:
    """Copy of ``df`` (sorted) with missing ``speed``/``course`` derived from positions.

    Values present in the input are kept as they are.
    """
    out = sort_points(df).copy()
    index = track_index(out)
    speed, course = derive_motion(out, index)
    for name, derived in (("speed", speed), ("course", course)):
        if name not in out.columns:
            out[name] = derived
        else:
            given = out[name].to_numpy(dtype="float64")
            out[name] = np.where(np.isnan(given), derived, given)
    return out[ordered_columns(out)]


#: The column :func:`with_derived_motion` adds: what was derived on each row.
MOTION_DERIVED = "motion_derived"


def with_derived_motion(df: pd.DataFrame) -> pd.DataFrame:
    """``df`` in its own row order with blank ``speed``/``course`` derived from positions
    (the values :func:`fill_motion` gives: the leg arriving at a point, the first point
    the leg leaving it; kn and deg, 3 decimals), and a ``motion_derived`` column naming
    what was derived on each row (``speed``, ``course``, ``speed course`` or blank).
    Values given in the input are never changed (SPEC §1: derived where missing);
    a one-point track or a zero-time step stays blank."""
    from wakeline.core.schema import to_float

    n = len(df)
    pts, index = sorted_with_index(df.assign(_wl_row=np.arange(n)))
    derived = derive_motion(pts, index) if n else (np.zeros(0), np.zeros(0))
    rows = pts["_wl_row"].to_numpy()
    out = df.copy()
    said = np.full(n, "", dtype=object)
    for name, values in zip(("speed", "course"), derived, strict=True):
        own = np.full(n, np.nan)
        own[rows] = np.round(values, 3)
        given = to_float(out[name]) if name in out.columns else np.full(n, np.nan)
        fill = np.isnan(given) & np.isfinite(own)
        out[name] = np.where(fill, own, given)
        said = np.where(fill, np.where(said == "", name, said + " " + name), said)
    out[MOTION_DERIVED] = said
    return out[ordered_columns(out)]


def track_summary(df: pd.DataFrame) -> pd.DataFrame:
    """One row per track: sensor, batch, points, start, end, duration_s, length_m,
    mean_speed_kn, interval_s (its median sampling interval, :func:`median_interval_s`;
    NaN for a one-point track) and repeats (its rows that repeat an earlier row of it:
    same time and position, :func:`repeated_rows`; counted in ``points``)."""
    df = sort_points(df)
    index = track_index(df)
    if index.n_tracks == 0:
        return pd.DataFrame(
            columns=[
                "sensor",
                "batch",
                "points",
                "start",
                "end",
                "duration_s",
                "length_m",
                "mean_speed_kn",
                "interval_s",
                "repeats",
                "shared_times",
                "gap_s",
                "gap_m",
            ]
        )
    dist, _, _, _ = step_motion(df, index)
    dist = np.nan_to_num(dist)
    t = track_seconds(df)
    length = np.add.reduceat(dist, index.starts)
    duration = t[index.ends - 1] - t[index.starts]
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_speed = np.where(duration > 0, length / duration / geo.KN_MS, np.nan)
    times = df["time"]
    out = index.keys.copy()
    out["points"] = index.sizes
    # Kept as timestamps (a tz-aware column's to_numpy() makes Timestamp objects).
    out["start"] = times.iloc[index.starts].array
    out["end"] = times.iloc[index.ends - 1].array
    out["duration_s"] = duration
    out["length_m"] = length
    out["mean_speed_kn"] = mean_speed
    out["interval_s"] = median_interval_s(t, index)
    repeated = repeated_rows(df, index)
    out["repeats"] = np.add.reduceat(repeated.astype("int64"), index.starts)
    out["shared_times"] = _shared_times(t, index, repeated)
    gap_s, gap_m = _long_gaps(t, dist, index, out["interval_s"].to_numpy(dtype="float64"))
    out["gap_s"] = gap_s
    out["gap_m"] = gap_m
    return out


#: A step is a long gap when it is longer than this many of its track's median intervals
#: and than :data:`GAP_MIN_S` (Autoferry's GNSS truth: 0.1 s steps inside each 79-152 s
#: scenario, 292 s to 24 h between them).
GAP_FACTOR = 20.0
GAP_MIN_S = 60.0
#: Below this time per point (s), a track whose points share times or that moves faster
#: than :data:`PLOT_MAX_SPEED_KN` is radar plots, not a track sampled in time (fast tracks,
#: GNSS at 10 Hz, are tracks).
PLOT_MIN_INTERVAL_S = 1.0
#: Above this speed (kn) a track is not one ship (AIS itself tops out at 102.2 kn).
PLOT_MAX_SPEED_KN = 100.0
#: A track is called plots for its shared times only when at least this many of its rows
#: share a time (review h216: 2 of a 3-fix AIS track stamped alike are no scan).
PLOT_MIN_SHARED_ROWS = 6


def _shared_times(t: np.ndarray, index: "TrackIndex", repeated: np.ndarray) -> np.ndarray:
    """Per track: its rows (repeats of an earlier row left out) whose time another such
    row of the track also has: several positions at one time."""
    rows = np.flatnonzero(~repeated)
    out = np.zeros(index.n_tracks, dtype="int64")
    if len(rows) < 2:
        return out
    tr, tt = index.track_of_row[rows], t[rows]
    eq = (tt[1:] == tt[:-1]) & (tr[1:] == tr[:-1])
    shared = np.zeros(len(rows), dtype=bool)
    shared[1:] |= eq
    shared[:-1] |= eq
    return np.bincount(tr[shared], minlength=index.n_tracks).astype("int64")


def _long_gaps(t: np.ndarray, dist: np.ndarray, index: "TrackIndex", interval: np.ndarray):
    """Per track: the time (s) and the straight-line length (m) of its long gaps (steps
    over :data:`GAP_FACTOR` median intervals and :data:`GAP_MIN_S`)."""
    n = index.n_tracks
    if len(t) < 2:
        return np.zeros(n), np.zeros(n)
    dt = np.zeros(len(t))
    dt[1:] = t[1:] - t[:-1]
    dt[index.starts] = 0.0
    limit = np.maximum(GAP_MIN_S, GAP_FACTOR * np.nan_to_num(interval, nan=np.inf))
    gap = dt > limit[index.track_of_row]
    gap_s = np.add.reduceat(np.where(gap, dt, 0.0), index.starts)
    gap_m = np.add.reduceat(np.where(gap, dist, 0.0), index.starts)
    return gap_s, gap_m


def plot_tracks(points: pd.DataFrame) -> tuple[list[str], int]:
    """The ``sensor:batch`` labels of the tracks of ``points`` that are plots
    (:func:`plot_like`), and the number of tracks."""
    summary = track_summary(points)
    like = plot_like(summary)
    labels = (
        summary["sensor"].astype(str).to_numpy()[like]
        + ":"
        + summary["batch"].astype(str).to_numpy()[like]
    )
    return [str(x) for x in labels], int(len(summary))


def plot_like(summary: pd.DataFrame) -> np.ndarray:
    """Per track of a :func:`track_summary`: whether it is plots (detections of a scan,
    of several targets and clutter), not one ship's track. Its rows (repeats left out)
    are at least two and either half of them (and at least :data:`PLOT_MIN_SHARED_ROWS`)
    share their time with another of its rows (several positions at one time), or they come under :data:`PLOT_MIN_INTERVAL_S`
    apart on average while all at one time or faster than :data:`PLOT_MAX_SPEED_KN`. The
    one test of the parameter guidance (:func:`wakeline.core.maneuver.detection_limit`),
    fusion's and association's warnings and the review's marks."""
    if summary.empty:
        return np.zeros(0, dtype=bool)
    points = summary["points"].to_numpy(dtype="float64")
    if "repeats" in summary.columns:
        points = points - summary["repeats"].to_numpy(dtype="float64")
    duration = summary["duration_s"].to_numpy(dtype="float64")
    speed = summary["mean_speed_kn"].to_numpy(dtype="float64")
    shared = (
        summary["shared_times"].to_numpy(dtype="float64")
        if "shared_times" in summary.columns
        else np.zeros(len(points))
    )
    moving = points > 1
    with np.errstate(divide="ignore", invalid="ignore"):
        span = duration / np.maximum(points - 1, 1)
        ship = np.isfinite(speed) & (speed <= PLOT_MAX_SPEED_KN)
    fast = (span < PLOT_MIN_INTERVAL_S) & ((duration <= 0) | ~ship)
    shared_half = (2 * shared >= points) & (shared >= PLOT_MIN_SHARED_ROWS)
    return moving & (shared_half | fast)


def concat_ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """``starts[k], starts[k] + 1, …`` (``counts[k]`` values, ≥ 0) for every k, concatenated,
    as one cumulative sum of steps (~10× faster for many short ranges than repeating the
    starts and adding offsets)."""
    counts = np.asarray(counts, dtype="int64")
    starts = np.asarray(starts, dtype="int64")
    if not (counts > 0).all():
        starts, counts = starts[counts > 0], counts[counts > 0]
    steps = np.ones(int(counts.sum()), dtype="int64")
    if len(steps):
        steps[0] = starts[0]
        # each range's first value, from the last value of the one before
        steps[np.cumsum(counts[:-1])] = starts[1:] - (starts[:-1] + counts[:-1] - 1)
    return np.cumsum(steps, out=steps)


#: Values per block of :func:`run_medians`' partitions.
MEDIAN_BLOCK = 1 << 16


def median_interval_s(t: np.ndarray, index: TrackIndex) -> np.ndarray:
    """Median sampling interval (s) of each track, over its steps forward in time (a row
    repeated at the same time is not a 0 s interval); NaN for one-point tracks."""
    t = np.asarray(t, dtype="float64")
    dt = np.empty(len(t))  # np.diff(t, prepend=nan), without the prepended copy
    if len(t):
        dt[0] = np.nan
        np.subtract(t[1:], t[:-1], out=dt[1:])
    dt[index.starts] = np.nan
    dt[dt == 0] = np.nan
    out = np.full(index.n_tracks, np.nan)
    if not len(dt):
        return out
    # a track sampled at one interval has it as its median (of an even count too: the
    # mean of two equal values is that value): no sort
    with np.errstate(invalid="ignore"):
        lo, hi = np.fmin.reduceat(dt, index.starts), np.fmax.reduceat(dt, index.starts)
    one = lo == hi
    out[one] = lo[one]
    other = ~one & ~np.isnan(lo)
    if other.any():  # each track's steps after its first fix: one run of dt per track
        finite = np.isfinite(dt)
        if (~finite).sum() > index.n_tracks:  # 0 s steps (NaN) beside each track's first:
            # left out first, so that every run is free of NaN (the fast median)
            per = np.add.reduceat(finite.astype("int64"), index.starts)
            count = np.where(other, per, 0)
            first = np.concatenate([[0], np.cumsum(per)[:-1]])
            out[other] = run_medians(dt[finite], first, count)[other]
        else:
            count = np.where(other, index.sizes - 1, 0)
            out[other] = run_medians(dt, index.starts + 1, count)[other]
    return out


def run_medians(values: np.ndarray, first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Median of each run ``values[first[g] : first[g] + count[g]]`` (NaN for an empty one)
    as pandas' groupby median gives it, bit for bit (NaN skipped; of an even count the mean
    of the middle two). Runs of a length that many runs share (tracks cut to one length)
    take ``np.partition`` of a runs × length block (about ``MEDIAN_BLOCK`` values at a
    time); the others, and runs holding a NaN, the groupby."""
    out = np.full(len(count), np.nan)
    rest = count > 0
    if not rest.any():
        return out
    sizes, shared = np.unique(count[rest], return_counts=True)
    nan = bool(np.isnan(values).any())
    # of an even count, the lower middle value is the largest of the lower half once the
    # upper middle one is in place (one partition point, not two); a tie of -0.0 and 0.0
    # could pick another zero there, so that takes the two points
    one_point = not np.signbit(values).any()
    for m in sizes[shared >= 8]:  # a loop over distinct lengths, few
        g = np.flatnonzero(count == m)
        med = np.empty(len(g))
        span = np.arange(m)
        step = max(1, MEDIAN_BLOCK // int(m))  # runs per chunk: ~BLOCK values
        for a in range(0, len(g), step):  # a loop over chunks of runs
            block = values[first[g[a : a + step], None] + span]
            if m % 2:
                block.partition(m // 2, axis=1)
                med[a : a + step] = block[:, m // 2]
            elif one_point:
                block.partition(m // 2, axis=1)
                med[a : a + step] = (block[:, m // 2] + block[:, : m // 2].max(axis=1)) / 2
            else:
                block.partition([m // 2 - 1, m // 2], axis=1)
                med[a : a + step] = (block[:, m // 2] + block[:, m // 2 - 1]) / 2
            if nan:  # such a run goes to the groupby
                med[a : a + step][np.isnan(block).any(axis=1)] = np.nan
        done = ~np.isnan(med)
        out[g[done]] = med[done]
        rest[g[done]] = False
    if rest.any():
        g = np.flatnonzero(rest)
        rows = concat_ranges(first[g], count[g])
        med = pd.Series(values[rows]).groupby(repeat_runs(g, count[g])).median()
        out[med.index.to_numpy()] = med.to_numpy()
    return out


def interp_positions(
    df: pd.DataFrame,
    index: TrackIndex,
    track: np.ndarray,
    times_s: np.ndarray,
    max_gap_s: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions of tracks ``track[k]`` at times ``times_s[k]`` (seconds), linear in time
    along the great circle between the fixes either side.

    ``df`` is sorted with ``index``. Returns lon, lat (degrees; longitude differences are
    wrapped, so tracks across 180° interpolate the short way) and a mask of queries inside
    their track's time span (outside, the nearest end is returned) and, with ``max_gap_s``,
    between two points at most that far apart in time or at one of the track's own times
    (a fix is where the ship was, even after a long gap). Vectorized over all
    queries: one ``searchsorted`` on a (track, time) key.
    """
    track = np.asarray(track, dtype="int64")
    times_s = np.asarray(times_s, dtype="float64")
    t = track_seconds(df)
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    if len(track) == 0:
        e = np.zeros(0)
        return e, e, e.astype(bool)
    base = float(min(t.min(), times_s.min()))
    span = float(max(t.max(), times_s.max()) - base) + 1.0
    key = index.track_of_row * span + (t - base)
    q = track * span + (times_s - base)
    hi = np.searchsorted(key, q, side="left")
    hi = np.clip(hi, index.starts[track], index.ends[track] - 1)
    # A query at one of the track's own times is that fix, whatever gap precedes it.
    lo = np.where(t[hi] == times_s, hi, np.maximum(hi - 1, index.starts[track]))
    dt = t[hi] - t[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(dt > 0, (times_s - t[lo]) / dt, 0.0)
    f = np.clip(f, 0.0, 1.0)
    # along the great circle (the radial line of the plane about the earlier fix): linear in
    # degrees, a 10 km step strayed up to L² tan(lat) / 8R from it, 6 m at 72° N; a query at
    # a fix is that fix
    lon_lo, lat_lo, lon_hi, lat_hi = lon[lo], lat[lo], lon[hi], lat[hi]
    dx, dy = geo.to_local(lon_hi, lat_hi, lon_lo, lat_lo)
    out_lon, out_lat = geo.from_local(dx * f, dy * f, lon_lo, lat_lo)
    at_lo, at_hi = f == 0.0, f == 1.0
    out_lon = np.where(at_lo, geo.wrap180(lon_lo), np.where(at_hi, geo.wrap180(lon_hi), out_lon))
    out_lat = np.where(at_lo, lat_lo, np.where(at_hi, lat_hi, out_lat))
    inside = (times_s >= t[index.starts[track]]) & (times_s <= t[index.ends[track] - 1])
    if max_gap_s is not None:
        inside &= dt <= max_gap_s
    return out_lon, out_lat, inside


def repeated_rows(pts: pd.DataFrame, index: TrackIndex) -> np.ndarray:
    """Rows (of a table in track order) that repeat an earlier row of their track: same
    time, lon and lat (the previous row, or any row of the same time: P, Q, P, Q). They
    carry no new position; a window of p points over them spans half the time and a 0 m
    step has no heading, so the detector runs without them."""
    n = len(pts)
    out = np.zeros(n, dtype=bool)
    if n < 2:
        return out
    t = track_seconds(pts)
    lon, lat = pts["lon"].to_numpy(), pts["lat"].to_numpy()
    same_t = np.zeros(n, dtype=bool)
    same_t[1:] = t[1:] == t[:-1]
    same_t[index.starts] = False
    if not same_t.any():  # (the usual case) no two fixes of a track at one time
        return out
    out[1:] = same_t[1:] & (lon[1:] == lon[:-1]) & (lat[1:] == lat[:-1])
    # Rows sharing a time with a row other than their neighbour (few): by value.
    tied = same_t.copy()
    tied[:-1] |= same_t[1:]
    if (tied & ~out).sum() > 2:
        rows = np.flatnonzero(tied)
        key = pd.DataFrame(
            {"k": index.track_of_row[rows], "t": t[rows], "x": lon[rows], "y": lat[rows]}
        )
        out[rows[key.duplicated(keep="first").to_numpy()]] = True
    return out


def rows_of(pts: pd.DataFrame, rows: np.ndarray) -> tuple[pd.DataFrame, "TrackIndex"]:
    """The given rows (ascending) of a table in track order, and their index: still in
    track order, so no sort (used to set aside :func:`repeated_rows`)."""
    return sorted_with_index(pts.iloc[rows].reset_index(drop=True))


def summary_update(
    df: pd.DataFrame, previous: pd.DataFrame, previous_summary: pd.DataFrame
) -> pd.DataFrame | None:
    """:func:`track_summary` of ``df`` from ``previous_summary`` (that of ``previous``):
    only the tracks whose rows differ in time or position are summarized again (a review
    decision relabels targets and leaves every track's rows as they were). None when the
    two tables do not hold the same tracks with the same numbers of rows (then summarize
    ``df`` whole)."""
    df, previous = sort_points(df), sort_points(previous)
    index, before = track_index(df), track_index(previous)
    if (
        len(df) != len(previous)
        or index.n_tracks != before.n_tracks
        or len(previous_summary) != index.n_tracks
        or not np.array_equal(index.starts, before.starts)
        or not np.array_equal(index.ends, before.ends)
        or not index.keys.reset_index(drop=True).equals(before.keys.reset_index(drop=True))
    ):
        return None
    changed = np.zeros(len(df), dtype=bool)
    pairs = [(track_seconds(df), track_seconds(previous))]
    pairs += [
        (df[c].to_numpy(dtype="float64"), previous[c].to_numpy(dtype="float64"))
        for c in ("lon", "lat")
    ]
    for a, b in pairs:
        changed |= (a != b) & ~(np.isnan(a) & np.isnan(b))
    out = previous_summary.reset_index(drop=True).copy()
    if not changed.any():
        return out
    touched = np.flatnonzero(np.add.reduceat(changed.astype("int64"), index.starts) > 0)
    rows = concat_ranges(index.starts[touched], index.sizes[touched])
    part = track_summary(df.iloc[rows].reset_index(drop=True))
    for col in part.columns:
        if col in out.columns:
            out.loc[touched, col] = part[col].to_numpy()
    return out

"""Qt models over core data: the batch table of a layer's tracks."""

from dataclasses import dataclass

import numpy as np
import pandas as pd
from PySide6 import QtCore

from wakeline.app.time_text import is_relative_time
from wakeline.core import sorted_sets
from wakeline.core.io.vessels import TYPE_COLUMN
from wakeline.core.timeline import overlapping
from wakeline.core.tracks import sort_points, summary_update, track_index, track_summary


def batch_summary(
    points: pd.DataFrame,
    maneuvers: pd.DataFrame | None = None,
    previous: tuple[pd.DataFrame, pd.DataFrame] | None = None,
) -> pd.DataFrame:
    """The core's track summary plus maneuvers per track, target and status.
    ``previous``: (points, summary) of an earlier view of the layer; only the tracks whose
    rows changed are summarized again (:func:`~wakeline.core.tracks.summary_update`)."""
    summary = None
    if previous is not None:
        summary = summary_update(points, previous[0], previous[1])
        if summary is not None:
            summary = summary.drop(
                columns=["maneuvers", "target", "status", "name", "ship_type"], errors="ignore"
            )
    if summary is None:
        summary = track_summary(points)
    if summary.empty:
        for col in ("maneuvers", "target", "status", "name", "ship_type"):
            summary[col] = []
        return summary
    keys = ["sensor", "batch"]
    if maneuvers is not None and len(maneuvers):
        counts = maneuvers.astype({"sensor": str, "batch": str}).groupby(keys).size()
        summary["maneuvers"] = (
            counts.reindex(pd.MultiIndex.from_frame(summary[keys])).fillna(0).astype(int).to_numpy()
        )
    else:
        summary["maneuvers"] = np.nan
    if "target" in points.columns:
        summary["target"] = _first_per_track(points, "target")
        size = summary.groupby("target")["batch"].transform("size")
        summary["status"] = np.where(size > 1, "joined", "")
    elif "members" in points.columns:
        first = points.astype({"sensor": str, "batch": str}).groupby(keys)["members"].first()
        summary["target"] = summary["batch"]
        members = first.reindex(pd.MultiIndex.from_frame(summary[keys])).to_numpy()
        summary["status"] = np.where(pd.Series(members).str.contains(r"\+"), "fused", "single")
    else:
        summary["target"] = ""
        summary["status"] = ""
    name_col = ship_name_column(points)
    summary["name"] = _first_per_track(points, name_col) if name_col else ""
    # a vessel table's ship types (File ▸ Load ship names: core.io.vessels)
    has_type = TYPE_COLUMN in points.columns and bool((points[TYPE_COLUMN] != "").any())
    summary[TYPE_COLUMN] = _first_per_track(points, TYPE_COLUMN) if has_type else ""
    return summary


#: Columns of a point table that carry the ship's name (an NMEA file's static messages
#: give ``name``; an AIS CSV export often ``shipname`` or ``vessel_name``), lower case.
NAME_COLUMNS = ("name", "shipname", "ship_name", "vessel_name", "vesselname", "ship")


def ship_name_column(points: pd.DataFrame) -> str | None:
    """The column of ``points`` holding ship names (:data:`NAME_COLUMNS`), None if none
    or if it is empty."""
    by_lower = {str(c).lower(): c for c in points.columns}
    for key in NAME_COLUMNS:
        col = by_lower.get(key)
        if col is not None:
            values = points[col]
            if values.notna().any() and (values.astype(str).str.strip() != "").any():
                return col
    return None


def _first_per_track(points: pd.DataFrame, col: str) -> np.ndarray:
    """The first non-null ``col`` of every track (NaN for none), in the order of
    :func:`track_summary`'s rows: by the track index, not a group-by over the points as
    text (a million points' keys turned into Python strings held the GIL ~1 s)."""
    pts = sort_points(points)
    index = track_index(pts)
    n = len(pts)
    v = pts[col]
    pos = np.where(v.notna().to_numpy(), np.arange(n), n)
    first = np.minimum.reduceat(pos, index.starts) if n else np.zeros(0, dtype="int64")
    out = np.array(v.iloc[np.minimum(first, max(n - 1, 0))].to_numpy(dtype=object))
    out[first >= n] = np.nan
    return out


#: Display columns made from one summary column each that a review decision leaves as
#: they were (it relabels targets): :func:`display_text` keeps their text from the
#: layer's earlier view when the column is equal (the dates are made again: the display
#: zone may have changed since).
KEPT_TEXT = (
    "sensor",
    "batch",
    "name",
    "ship_type",
    "points",
    "duration_s",
    "length_m",
    "mean_speed_kn",
    "maneuvers",
)


def _same_column(df: pd.DataFrame, old: pd.DataFrame, key: str) -> bool:
    """Whether summaries ``df`` and ``old`` hold the same column ``key`` (or neither)."""
    if key not in df.columns or key not in old.columns:
        return key not in df.columns and key not in old.columns
    return df[key].reset_index(drop=True).equals(old[key].reset_index(drop=True))


def display_text(
    df: pd.DataFrame, previous: tuple[pd.DataFrame, dict] | None = None
) -> dict[str, np.ndarray]:
    """Every column's display text, formatted once for all rows (vectorized).
    ``previous``: (summary, its display text) of the layer's earlier view: a column of
    :data:`KEPT_TEXT` equal in both keeps its text (the same arrays; a review decision
    on a million-point layer's 55 k tracks spent ~100 ms of its worker here, part of it
    holding the GIL)."""
    kept: dict[str, np.ndarray] = {}
    if previous is not None and len(previous[0]) == len(df) and len(df):
        old, old_text = previous
        kept = {k: old_text[k] for k in KEPT_TEXT if k in old_text and _same_column(df, old, k)}
    out = {}
    for key in ("sensor", "batch", "target", "status", "name", "ship_type"):
        if key in kept:
            out[key] = kept[key]
            continue
        col = df[key] if key in df.columns else pd.Series([""] * len(df))
        out[key] = col.astype(object).where(col.notna(), "").astype(str).to_numpy()
    if "points" in kept:
        out["points"] = kept["points"]
    else:
        out["points"] = (
            df["points"].astype("int64").astype(str).to_numpy() if len(df) else np.zeros(0, str)
        )
    from wakeline.app.time_text import format_times

    if len(df):
        epoch = pd.Timestamp("1970-01-01", tz="UTC")
        secs = {
            key: (pd.to_datetime(df[key], utc=True) - epoch).dt.total_seconds().to_numpy()
            for key in ("start", "end")
        }
        relative = is_relative_time(np.concatenate(list(secs.values())))
    for key in ("start", "end"):
        if not len(df):
            out[key] = np.zeros(0, str)
        elif relative:  # seconds from a scene start (MTAD, Øresund): elapsed, not 1970 dates
            out[key] = np.asarray(format_times(secs[key], True), dtype=str)
        else:
            out[key] = date_text(df[key])

    for key, scale, decimals in (
        ("duration_s", 60, 1),
        ("length_m", 1000, 2),
        ("mean_speed_kn", 1, 1),
    ):
        if key in kept:
            out[key] = kept[key]
        else:
            values = (df[key] if scale == 1 else df[key] / scale) if len(df) else []
            out[key] = fixed_text(values, decimals)
    if "maneuvers" in kept:
        out["maneuvers"] = kept["maneuvers"]
    else:
        out["maneuvers"] = fixed_text(
            df["maneuvers"] if "maneuvers" in df.columns else [np.nan] * len(df), 0
        )
    return out


def date_text(values) -> np.ndarray:
    """``YYYY-MM-DD HH:MM:SS`` of each time (a zoned time: the display zone's wall clock),
    "" for NaT; by ``np.datetime_as_string`` over the whole column (pandas' ``strftime``
    is a Python call per value: 1.7 s for a million, holding the GIL in a worker)."""
    s = pd.to_datetime(pd.Series(values))
    if getattr(s.dt, "tz", None) is not None:
        from wakeline.app.time_text import wall_clock

        s = wall_clock(s)  # the display zone's wall clock (View ▸ Time zone; UTC by default)
    a = s.to_numpy(dtype="datetime64[ns]").astype("datetime64[s]")
    text = np.strings.replace(np.datetime_as_string(a, unit="s"), "T", " ")
    return np.where(np.isnat(a), "", text).astype(str)


def fixed_text(values, decimals: int) -> np.ndarray:
    """``f"{x:.{decimals}f}"`` of each number, "" for NaN, vectorized (integer digits and
    numpy string operations, no Python call per value). Halves round to even on the scaled
    value, which may differ from ``format`` in the last digit for a value within 1e-16 of
    a half."""
    v = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype="float64")
    if not len(v):
        return np.zeros(0, dtype=str)
    scale = 10**decimals
    mag = np.abs(v) * scale
    finite = np.isfinite(mag)
    if (mag[finite] >= 2.0**62).any():  # beyond int64 digits: Python's formatting
        return np.array(["" if np.isnan(x) else f"{x:.{decimals}f}" for x in v], dtype=str)
    mag = np.where(finite, mag, 0.0)
    r = np.rint(mag).astype("int64")
    # Near a half the scaled product may have rounded across it: those few by ``format``,
    # which rounds the exact binary value.
    tie = np.flatnonzero(np.abs(mag - np.floor(mag) - 0.5) < 1e-6)
    if len(tie):
        r[tie] = [int(f"{abs(x):.{decimals}f}".replace(".", "")) for x in v[tie]]
    text = (r // scale).astype(str)
    if decimals:
        frac = np.strings.zfill((r % scale).astype(str), decimals)
        text = np.strings.add(np.strings.add(text, "."), frac)
    text = np.strings.add(np.where(np.signbit(v), "-", ""), text)
    text = np.where(np.isinf(v), np.where(v > 0, "inf", "-inf"), text)
    return np.where(np.isnan(v), "", text).astype(str)


def track_span_s(df: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """First and last time (s since 1970) of every row of a batch summary."""
    if not len(df) or "start" not in df.columns:
        return np.zeros(len(df)), np.zeros(len(df))
    epoch = pd.Timestamp("1970-01-01", tz="UTC")
    return tuple(
        (pd.to_datetime(df[k], utc=True) - epoch).dt.total_seconds().to_numpy(dtype="float64")
        for k in ("start", "end")
    )


@dataclass(frozen=True)
class TableIndex:
    """What :meth:`BatchTableModel.set_summary` derives from a summary besides its text:
    row of each (sensor, batch), every row's first and last time (s), and whether those
    are scene-relative. Made in the worker with the layer's view (:func:`table_index`),
    so a layer swapped in (a review decision applied) costs the GUI thread no pass over
    its tracks."""

    rows: int
    keys: dict
    span_s: tuple[np.ndarray, np.ndarray]
    relative: bool


#: Off only for bench/bench_review_keys.py's "before" figures: set_summary makes the
#: index itself (on the GUI thread) even when the worker prepared it.
TABLE_INDEX_IN_WORKER = True
#: A layer's new points with the same tracks (a review decision) update the batch table's
#: cells in place (:meth:`BatchTableModel.update_summary`); False: a model reset, as
#: before session 28 (bench/review_keys.py compares the two in one run).
TABLE_UPDATE_IN_PLACE = True


def table_index(
    df: pd.DataFrame, text: dict, previous: tuple[dict, TableIndex] | None = None
) -> TableIndex:
    """The :class:`TableIndex` of summary ``df`` (index 0..n-1) with display ``text``.
    ``previous``: (display text, index) of the layer's earlier view: its row of each
    (sensor, batch) is kept when ``text`` holds the same sensor and batch arrays
    (:func:`display_text` kept them: a dict of 55 k keys made with the GIL held, ~25 ms)."""
    old_text, old = previous if previous is not None else ({}, None)
    same = old is not None and old.rows == len(df)
    if same and all(text[k] is old_text.get(k) for k in ("sensor", "batch")):
        keys = old.keys
    else:
        pairs = zip(text["sensor"].tolist(), text["batch"].tolist(), strict=True)
        keys = dict(zip(pairs, range(len(df)), strict=True))
    span = track_span_s(df)
    return TableIndex(len(df), keys, span, bool(is_relative_time(np.concatenate(span))))


#: Rows of a Python-text column :meth:`BatchTableModel.widest_text` looks at.
WIDEST_ROWS = 1000


def status_words() -> dict[str, str]:
    """The batch table's status values (:func:`batch_summary`) in the current language
    (the Chinese window showed "joined", operator test 7, D11)."""
    return {
        "joined": QtCore.QCoreApplication.translate("BatchTable", "joined"),
        "fused": QtCore.QCoreApplication.translate("BatchTable", "fused"),
        "single": QtCore.QCoreApplication.translate("BatchTable", "single"),
    }


class BatchTableModel(QtCore.QAbstractTableModel):
    """The batch table over :func:`batch_summary`, with sorting and a text filter done by
    numpy over whole columns (no per-cell Python calls while sorting or filtering): the
    visible rows are a permutation ``order`` of the summary's rows."""

    COLUMNS = (
        ("sensor", "Sensor"),
        ("batch", "Batch"),
        ("points", "Points"),
        ("start", "Start (UTC)"),
        ("end", "End (UTC)"),
        ("duration_s", "Duration (min)"),
        ("length_m", "Length (km)"),
        ("mean_speed_kn", "Speed (kn)"),
        ("maneuvers", "Maneuvers"),
        ("target", "Target"),
        ("status", "Status"),
        ("name", "Name"),  # shown only when the file has ship names (has_names)
        ("ship_type", "Type"),  # ... and ship types (a vessel table's: has_types)
    )
    TEXT = ("sensor", "batch", "target", "status", "name", "ship_type")
    #: Other words a column filter (``name:argo``) may name a column by.
    FILTER_ALIASES = {
        "ship": "name",
        "shiptype": "ship_type",
        "类型": "ship_type",
        "mmsi": "batch",
        "track": "batch",
        "id": "batch",
        "speed": "mean_speed_kn",
        "length": "length_m",
        "duration": "duration_s",
    }
    #: Titles of the time columns over times elapsed from a scene start (MTAD, Øresund),
    #: shown ``T+h:mm:ss`` as on the time slider: they are no UTC dates.
    RELATIVE_TITLES = {"start": "Start (T+)", "end": "End (T+)"}

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self._titles = [t for _, t in self.COLUMNS]
        self._relative_titles = dict(self.RELATIVE_TITLES)
        #: The layer shown has scene-relative times (its Start and End are ``T+…``).
        self.relative = False
        self._filter = ""
        #: The column key the filter looks in (None: any column), from the filter's
        #: ``column:`` prefix or :meth:`set_filter_column`.
        self._filter_column: str | None = None
        self._chosen_column: str | None = None
        self._window: tuple[float, float] | None = None
        self._sort: tuple[int, QtCore.Qt.SortOrder] | None = None
        self.set_summary(
            batch_summary(pd.DataFrame(columns=["sensor", "batch", "time", "lon", "lat"]))
        )

    @property
    def frame(self) -> pd.DataFrame:
        return self._df

    def set_titles(self, titles: list[str], relative: dict[str, str] | None = None) -> None:
        """The column titles (translated); ``relative``: those of the time columns over
        scene-relative times (:attr:`RELATIVE_TITLES`)."""
        self._titles = titles
        if relative is not None:
            self._relative_titles = dict(relative)
        self.headerDataChanged.emit(QtCore.Qt.Orientation.Horizontal, 0, len(titles) - 1)

    def set_summary(
        self, df: pd.DataFrame, text: dict | None = None, index: "TableIndex | None" = None
    ) -> None:
        """Show a summary (``text``: its display columns, and ``index``: its
        :func:`table_index`, when prepared in a worker; else made here)."""
        self.beginResetModel()
        self._df = df.reset_index(drop=True)
        self._text = text if text is not None else display_text(self._df)
        if index is None or index.rows != len(self._df) or not TABLE_INDEX_IN_WORKER:
            index = table_index(self._df, self._text)
        self._keys, self._span_s, self.relative = index.keys, index.span_s, index.relative
        self._order = self._visible_rows()
        self.endResetModel()

    def update_summary(
        self, df: pd.DataFrame, text: dict | None = None, index: "TableIndex | None" = None
    ) -> bool:
        """The same tracks in the same rows with new figures (a review decision relabels
        targets): the cells change in place (one ``dataChanged``), no reset, so the
        view keeps its selection, scroll and column widths. False (nothing done) when
        the tracks, their visible order or the time kind differ: :meth:`set_summary`."""
        df = df.reset_index(drop=True)
        if not TABLE_UPDATE_IN_PLACE or len(df) != len(self._df) or not len(df):
            return False
        text = text if text is not None else display_text(df)
        if index is None or index.rows != len(df) or not TABLE_INDEX_IN_WORKER:
            index = table_index(df, text)
        if index.relative != self.relative or (
            index.keys is not self._keys and index.keys != self._keys
        ):
            return False
        old = (self._df, self._text, self._span_s)
        self._df, self._text, self._span_s = df, text, index.span_s
        order = self._visible_rows()
        if not np.array_equal(order, self._order):  # sorted or filtered by what changed
            self._df, self._text, self._span_s = old
            return False
        self.dataChanged.emit(
            self.index(0, 0), self.index(max(len(order) - 1, 0), len(self.COLUMNS) - 1)
        )
        return True

    def _visible_rows(self) -> np.ndarray:
        n = len(self._df)
        rows = np.arange(n)
        if self._sort is not None and n:
            key = self.COLUMNS[self._sort[0]][0]
            raw = self._df[key] if key in self._df.columns else pd.Series([""] * n)
            if key in self.TEXT:
                values = raw.astype(str).to_numpy()
            else:
                values = (
                    pd.to_numeric(raw, errors="coerce").to_numpy(dtype="float64")
                    if key not in ("start", "end")
                    else pd.to_datetime(raw).to_numpy()
                )
            rows = np.argsort(values, kind="stable")
            if self._sort[1] == QtCore.Qt.SortOrder.DescendingOrder:
                rows = rows[::-1]
        if self._filter and n:
            needle = self._filter.lower()
            hit = np.zeros(n, dtype=bool)
            if self._filter_column is not None:
                columns = [self._text.get(self._filter_column, np.full(n, "", dtype=str))]
            else:
                columns = self._text.values()
            for col in columns:
                hit |= np.char.find(np.char.lower(col.astype(str)), needle) >= 0
            rows = rows[hit[rows]]
        if self._window is not None and n:
            t0, t1 = self._span_s
            rows = rows[overlapping(t0[rows], t1[rows], *self._window)]
        return rows

    def sort(self, column: int, order=QtCore.Qt.SortOrder.AscendingOrder) -> None:
        self.layoutAboutToBeChanged.emit()
        self._sort = (column, order)
        self._order = self._visible_rows()
        self.layoutChanged.emit()

    def filter_column_of(self, word: str) -> str | None:
        """The column key ``word`` names (its key, its title as shown, its English title,
        an alias such as ``mmsi``; case-insensitive), None if it names none."""
        w = word.strip().lower()
        if not w:
            return None
        for i, (key, title) in enumerate(self.COLUMNS):
            shown = self._titles[i] if i < len(self._titles) else title
            titles = {key, title.lower(), str(shown).lower()}
            titles |= {t.split(" (")[0] for t in titles}  # "speed (kn)" -> "speed"
            if key in self.RELATIVE_TITLES:
                rel = (self.RELATIVE_TITLES[key], self._relative_titles.get(key, ""))
                titles |= {t.lower().split(" (")[0] for t in rel if t}
            if w in titles:
                return key
        return self.FILTER_ALIASES.get(w)

    def parse_filter(self, text: str) -> tuple[str | None, str]:
        """(column key or None, text to look for) of a filter text: ``batch:4139`` looks
        in the Batch column only; a prefix that names no column (a time ``12:30``) is
        part of the text, matched in any column."""
        text = text.strip()
        head, sep, rest = text.partition(":")
        if sep:
            key = self.filter_column_of(head)
            if key is not None:
                return key, rest.strip()
        if not sep:
            head, sep, rest = text.partition("：")  # a Chinese input method's colon
            key = self.filter_column_of(head) if sep else None
            if key is not None:
                return key, rest.strip()
        return self._chosen_column, text

    def set_filter(self, text: str) -> None:
        """Show only rows with ``text`` in any column (case-insensitive), or in one
        column: ``batch:4139``, ``sensor:AIS`` (:meth:`parse_filter`), or the column
        chosen by :meth:`set_filter_column`."""
        self.beginResetModel()
        self._raw_filter = text
        self._filter_column, self._filter = self.parse_filter(text)
        self._order = self._visible_rows()
        self.endResetModel()

    def set_filter_column(self, key: str | None) -> None:
        """The column a plain filter text looks in (None: any column)."""
        self._chosen_column = key
        self.set_filter(getattr(self, "_raw_filter", self._filter))

    def filter_column(self) -> str | None:
        """The column the current filter looks in (None: any column)."""
        return self._filter_column if self._filter else None

    def best_match_row(self) -> int | None:
        """The visible row Enter in the filter selects: one whose filtered column (or,
        filtering any column, batch) equals the filter text, else the first row shown;
        None when no row is shown."""
        if not len(self._order):
            return None
        if self._filter:
            key = self._filter_column or "batch"
            col = self._text.get(key)
            if col is not None:
                exact = np.char.lower(col[self._order].astype(str)) == self._filter.lower()
                hit = np.flatnonzero(exact)
                if len(hit):
                    return int(hit[0])
        return 0

    @property
    def has_names(self) -> bool:
        """The tracks shown have ship names (the Name column is worth showing)."""
        names = self._text.get("name")
        return names is not None and bool(len(names)) and bool((names != "").any())

    @property
    def has_types(self) -> bool:
        """The tracks shown have ship types (a vessel table's: the Type column shown)."""
        types = self._text.get("ship_type")
        return types is not None and bool(len(types)) and bool((types != "").any())

    def set_time_window(self, window: tuple[float, float] | None) -> None:
        """Show only tracks whose time span overlaps ``window`` = (from, to) in seconds
        since 1970 (None: no time filter)."""
        self.beginResetModel()
        self._window = None if window is None else (float(window[0]), float(window[1]))
        self._order = self._visible_rows()
        self.endResetModel()

    def time_window(self) -> tuple[float, float] | None:
        return self._window

    def tracks_overlapping(self, window: tuple[float, float] | None) -> int | None:
        """How many of the layer's tracks have a time span overlapping ``window`` = (from,
        to) s, as the table counts them (None: no window). The text filter plays no part."""
        if window is None:
            return None
        t0, t1 = self._span_s
        return int(overlapping(t0, t1, float(window[0]), float(window[1])).sum())

    def counts(self) -> tuple[int, int]:
        """(rows shown, tracks of the layer)."""
        return len(self._order), len(self._df)

    def shown_because(self) -> tuple[bool, bool]:
        """Why rows are hidden: (the text filter is on, the time window is on)."""
        return bool(self._filter), self._window is not None

    def key_of_row(self, row: int) -> tuple[str, str]:
        """(sensor, batch) of visible row ``row``."""
        r = self._order[row]
        return str(self._text["sensor"][r]), str(self._text["batch"][r])

    def keys_of_rows(self, rows: np.ndarray) -> list[tuple[str, str]]:
        """(sensor, batch) of visible rows ``rows`` (:meth:`key_of_row` for many)."""
        r = self._order[np.asarray(rows, dtype="int64")]
        sensors = self._text["sensor"][r].astype(str).tolist()
        batches = self._text["batch"][r].astype(str).tolist()
        return list(zip(sensors, batches, strict=True))

    def rows_of_keys(self, keys: list[tuple[str, str]]) -> np.ndarray:
        """Visible rows of the tracks ``keys`` (sensor, batch), ascending; unknown and
        filtered-out tracks are left out. One dictionary lookup per key and one inverse
        of the visible order (not a scan of the rows per key)."""
        found = np.fromiter((self._keys.get(tuple(k), -1) for k in keys), "int64", len(keys))
        where = np.full(len(self._df), -1, dtype="int64")
        where[self._order] = np.arange(len(self._order))
        rows = where[found[found >= 0]]
        return sorted_sets.distinct(rows[rows >= 0])

    def row_of_key(self, sensor: str, batch: str) -> int | None:
        """Visible row of a track (None when unknown or filtered out)."""
        r = self._keys.get((sensor, batch))
        if r is None:
            return None
        hit = np.flatnonzero(self._order == r)
        return int(hit[0]) if len(hit) else None

    def widest_text(self, key: str) -> str:
        """The longest display text of column ``key`` with its digits as "0" (what a
        column must fit). Numpy text (elapsed times ``T+…``) is read whole in one pass;
        other text from its first :data:`WIDEST_ROWS` rows (dates are all of one width,
        "2024-01-01 00:00:00"; sensors and batches much alike)."""
        texts = self.wide_texts(key)
        return max(texts, key=len) if texts else ""

    def wide_texts(self, key: str, keep: int = 8) -> list[str]:
        """The ``keep`` longest display texts of column ``key`` (digits as "0"), for the
        caller to measure: the longest in characters is not always the widest drawn
        ("lidar:00" is narrower than "radar:00": the fused targets' batch names were cut
        to "radar:…", operator test 8 D8)."""
        texts = self._text.get(key, np.zeros(0, str))
        if not len(texts):
            return []
        zero = str.maketrans("123456789", "000000000")
        if texts.dtype.kind == "U":
            lengths = np.char.str_len(texts)
            n = min(4 * keep, len(texts))  # the longest few, in one linear pass
            top = np.argpartition(-lengths, n - 1)[:n] if n < len(texts) else np.arange(n)
            found = {str(texts[i]).translate(zero) for i in top}
        else:
            found = {str(t).translate(zero) for t in texts[:WIDEST_ROWS]}
        return sorted(found, key=len, reverse=True)[:keep]

    def rowCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._order)

    def columnCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self.COLUMNS)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if (
            role == QtCore.Qt.ItemDataRole.DisplayRole
            and orientation == QtCore.Qt.Orientation.Horizontal
        ):
            key = self.COLUMNS[section][0]
            if self.relative and key in self._relative_titles:
                return self._relative_titles[key]
            from wakeline.app.time_text import zone_title

            title = self._titles[section] if section < len(self._titles) else key
            return zone_title(title)  # "Start (UTC+8)": View ▸ Time zone
        return None

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            key = self.COLUMNS[index.column()][0]
            col = self._text.get(key)
            text = col[self._order[index.row()]] if col is not None else ""
            if key == "status" and text:  # "joined", "fused": in the window's language
                return status_words().get(text, text)
            return text
        if role == QtCore.Qt.ItemDataRole.TextAlignmentRole:
            if self.COLUMNS[index.column()][0] in self.TEXT:
                return None
            return int(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        return None


class FrameModel(QtCore.QAbstractTableModel):
    """Any small DataFrame as a read-only table (the quarantine, reports)."""

    def __init__(self, df: pd.DataFrame, parent=None) -> None:
        super().__init__(parent)
        self._df = df.reset_index(drop=True)

    def rowCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df)

    def columnCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df.columns)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if role != QtCore.Qt.ItemDataRole.DisplayRole:
            return None
        if orientation == QtCore.Qt.Orientation.Horizontal:
            return str(self._df.columns[section])
        return str(section + 1)

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid() or role != QtCore.Qt.ItemDataRole.DisplayRole:
            return None
        value = self._df.iat[index.row(), index.column()]
        return "" if value is None or (isinstance(value, float) and np.isnan(value)) else str(value)

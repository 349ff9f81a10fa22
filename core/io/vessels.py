"""A table of vessels beside the tracks (ship names and types by MMSI), read and joined to
a layer's points by the ship's id.

Real sets ship one: the Saronic AIS set's ``vessel_info.csv`` (``MMSI;TYPE_CODE;TYPE;
DESCRIPTION``). The separator, encoding and compression are sniffed as for a track file;
the id column is recognised by the names the track reader takes for a track's id
(``MMSI``, ``id``, ``batch``, ``批号`` … :data:`~wakeline.core.io.formats.SYNONYMS`);
a name and a type column are optional. Rows that cannot be used are counted by reason
(:attr:`VesselTable.bad`), never dropped unsaid.
"""

import csv
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.io.formats import _ALIASES, PATTERNS, normalize_header

#: Header names of a ship's name (normalised: :func:`normalize_header`), in preference.
NAME_HEADERS = (
    "shipname",
    "vesselname",
    "name",
    "vessel",
    "ship",
    "船名",
    "船舶名称",
    "名称",
    "船只名称",
)
#: ... of its type (a text type before a numeric code).
TYPE_HEADERS = (
    "type",
    "shiptype",
    "vesseltype",
    "typetext",
    "typename",
    "船型",
    "船舶类型",
    "类型",
    "typecode",
    "shiptypecode",
)
#: The point columns the join writes (the batch table's Name and Type columns).
NAME_COLUMN = "name"
TYPE_COLUMN = "ship_type"
#: Reasons a row is not used, as :attr:`VesselTable.bad` counts them.
NO_ID = "no id"
SHORT_ROW = "wrong number of cells"
REPEATED = "id repeated with other values"


@dataclass
class VesselTable:
    """The vessels of a side file: ``table`` has ``id`` (text), ``name`` and ``type``
    (text, "" where the file has none), one row per id."""

    table: pd.DataFrame
    path: str = ""
    id_column: str = ""
    name_column: str | None = None
    type_column: str | None = None
    rows: int = 0  # data rows in the file
    bad: dict[str, int] = field(default_factory=dict)  # reason -> rows not used

    @property
    def has_names(self) -> bool:
        return bool((self.table["name"] != "").any())

    @property
    def has_types(self) -> bool:
        return bool((self.table["type"] != "").any())

    def report(self) -> str:
        """One line for the log: what was read and every row not used, with why."""
        cols = [f"id {self.id_column!r}"]
        if self.name_column:
            cols.append(f"name {self.name_column!r}")
        if self.type_column:
            cols.append(f"type {self.type_column!r}")
        text = f"{len(self.table):,} vessel(s) from {self.rows:,} row(s) ({', '.join(cols)})"
        if self.bad:
            said = ", ".join(f"{n:,} {why}" for why, n in sorted(self.bad.items()))
            text += f"; not used: {said}"
        return text


def id_text(values) -> np.ndarray:
    """Ids as the join compares them: text, stripped, a whole number's ``.0`` dropped
    (an MMSI read as a float in one file and as text in the other)."""
    s = pd.Series(values, dtype=object).astype(str).str.strip()
    return s.str.replace(r"^(-?\d+)\.0+$", r"\1", regex=True).to_numpy(dtype=object)


def _pick(headers: list[str], wanted: tuple[str, ...], taken: set[str]) -> str | None:
    keys = {h: normalize_header(h) for h in headers if h not in taken}
    for want in wanted:
        for h, k in keys.items():
            if k == want:
                return h
    return None


def id_column_of(headers: list[str]) -> str | None:
    """The header naming the ship's id: by the track reader's names for a track's id
    (its synonyms and formats' names, then its patterns such as ``vessel_mmsi``); an
    ``MMSI`` before a plain ``id``."""
    ids = [h for h in headers if _ALIASES.get(normalize_header(h)) == "batch"]
    ids += [h for h in headers if h not in ids and PATTERNS["batch"].match(normalize_header(h))]
    if not ids:
        return None
    mmsi = [h for h in ids if "mmsi" in normalize_header(h)]
    return (mmsi or ids)[0]


def read_vessels(path: str | Path) -> VesselTable:
    """Read a vessel table. Raises :class:`InputError` when no column names a ship's id
    or when neither a name nor a type column is found (nothing to show)."""
    from wakeline.core.io.compressed import open_data
    from wakeline.core.io.decoding import lines_codec
    from wakeline.core.io.sniff import listed_headers, sniff

    path = Path(path)
    sn = sniff(path)
    if not sn.has_header:
        raise InputError(
            f"{path}: a vessel table needs a header line (an id column such as MMSI, "
            "and a name or type column)"
        )
    headers = list(sn.columns)
    id_col = id_column_of(headers)
    if id_col is None:
        raise InputError(
            f"{path}: no column names a ship's id (MMSI, id, batch …); "
            f"headers found: {listed_headers(headers)}"
        )
    name_col = _pick(headers, NAME_HEADERS, {id_col})
    type_col = _pick(headers, TYPE_HEADERS, {id_col} | ({name_col} if name_col else set()))
    if name_col is None and type_col is None:
        raise InputError(
            f"{path}: no column of ship names or types; headers found: {listed_headers(headers)}"
        )
    bad: dict[str, int] = {}
    width = len(headers)
    lines: list[list[str]] = []
    with open_data(path, sn.compression) as stream:
        import io

        text = io.TextIOWrapper(stream, encoding=lines_codec(sn.encoding, sn.encoding_given))
        if sn.blank_runs or sn.delimiter == " ":
            rows = (re.split(r"\s+", line.strip()) for line in text)
        else:
            rows = csv.reader(text, delimiter=sn.delimiter)
        for k, row in enumerate(rows):
            if k < sn.skip_rows:
                continue
            if not row or all(not c.strip() for c in row):
                continue  # a blank line is no row
            lines.append(row)
    n = len(lines)
    short = [len(r) != width for r in lines]
    if any(short):
        bad[SHORT_ROW] = int(sum(short))
    rows_ok = [r for r, s in zip(lines, short, strict=True) if not s]
    df = pd.DataFrame(rows_ok, columns=headers, dtype=object) if rows_ok else None
    if df is None:
        df = pd.DataFrame({h: pd.Series(dtype=object) for h in headers})
    out = pd.DataFrame(
        {
            "id": id_text(df[id_col].to_numpy()),
            "name": _text(df, name_col),
            "type": _text(df, type_col),
        }
    )
    empty = out["id"] == ""
    if empty.any():
        bad[NO_ID] = int(empty.sum())
        out = out[~empty]
    # an id given twice: kept once when its rows agree; rows that differ from its first
    # are counted (the first is kept)
    dup = out.duplicated("id", keep="first")
    if dup.any():
        same = out.duplicated(["id", "name", "type"], keep="first")
        differ = dup & ~same
        if differ.any():
            bad[REPEATED] = int(differ.sum())
        out = out[~dup]
    return VesselTable(out.reset_index(drop=True), str(path), id_col, name_col, type_col, n, bad)


def _text(df: pd.DataFrame, col: str | None) -> np.ndarray:
    if col is None:
        return np.full(len(df), "", dtype=object)
    return df[col].fillna("").astype(str).str.strip().to_numpy(dtype=object)


@dataclass
class VesselJoin:
    """What :func:`join_vessels` did: tracks (ids) of the layer matched and not, and the
    table's vessels no track of the layer has."""

    ids: int = 0  # distinct ids in the layer
    matched: int = 0
    unmatched: list[str] = field(default_factory=list)  # layer ids the table lacks
    unused: int = 0  # table ids the layer lacks

    def report(self) -> str:
        text = f"{self.matched:,} of {self.ids:,} ship id(s) found in the vessel table"
        if self.unmatched:
            head = ", ".join(self.unmatched[:5]) + (" …" if len(self.unmatched) > 5 else "")
            text += f"; not in the table: {head}"
        if self.unused:
            text += f"; {self.unused:,} vessel(s) of the table not in the layer"
        return text


def join_vessels(points: pd.DataFrame, vessels: VesselTable) -> tuple[pd.DataFrame, VesselJoin]:
    """``points`` with the ships' names (``name``) and types (``ship_type``) of
    ``vessels`` by ``batch`` (the ship's id): a new table, the input untouched. A name
    or type the table has replaces the point's; the table's empty ones leave what the
    points had (an NMEA file's own names). Vectorized: one lookup per distinct id."""
    out = points.copy()
    if len(points) == 0:
        return out, VesselJoin()
    codes, uniques = pd.factorize(points["batch"], use_na_sentinel=False)
    keys = id_text(uniques)
    table = vessels.table.set_index("id")
    hit = pd.Index(table.index).get_indexer(keys)
    found = hit >= 0
    for src, dst, has in (
        ("name", NAME_COLUMN, vessels.name_column is not None),
        ("type", TYPE_COLUMN, vessels.type_column is not None),
    ):
        if not has:
            continue
        per_id = np.where(found, table[src].to_numpy(dtype=object)[np.maximum(hit, 0)], "")
        new = per_id[codes]
        if dst in out.columns:
            old = out[dst].astype(object).where(out[dst].notna(), "").to_numpy(dtype=object)
            new = np.where(new != "", new, old)
        out[dst] = pd.Series(new, index=out.index, dtype=object).astype(str)
    unmatched = sorted({str(k) for k, f in zip(keys, found, strict=True) if not f})
    join = VesselJoin(
        ids=len(keys),
        matched=int(found.sum()),
        unmatched=unmatched,
        unused=int(len(table) - len(set(hit[found].tolist()))),
    )
    return out, join

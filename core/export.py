"""Export of results: canonical CSV safe for spreadsheets, and GeoJSON.

CSV cells holding text that starts with ``=``, ``+``, ``-``, ``@`` (or a tab / carriage
return) would run as formulas when a spreadsheet opens the file; such text cells get a
leading apostrophe. Numbers are never touched (a longitude of −122.5 stays a number), nor
is text that is a plain number (an extra column's ``-2.5`` read as text stays ``-2.5``).
The command line's canonical CSV is exact data and is not defused; this module is the
export for people who open files in a spreadsheet.
"""

import json
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.io.writer import atomic_path, write_csv
from wakeline.core.schema import in_file_order, time_seconds, written_columns
from wakeline.core.tracks import sorted_with_index

_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
_NUMBER_TEXT = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"


def spreadsheet_safe(df: pd.DataFrame) -> pd.DataFrame:
    """A copy whose text cells cannot start a spreadsheet formula (prefix ``'``)."""
    out = df.copy()
    for name in out.columns:
        col = out[name]
        if pd.api.types.is_numeric_dtype(col.dtype) or pd.api.types.is_datetime64_any_dtype(
            col.dtype
        ):
            continue
        if isinstance(col.dtype, pd.DatetimeTZDtype) or pd.api.types.is_bool_dtype(col.dtype):
            continue
        text = col.astype("str")
        # A number stored as text ("-2.5", "+3", "-1e-5") is data, not a formula: a
        # spreadsheet reads it as the number it is, so it stays as it was.
        risky = (
            text.str.startswith(_FORMULA_START) & ~text.str.fullmatch(_NUMBER_TEXT) & col.notna()
        )
        if risky.any():
            out[name] = np.where(risky, "'" + text, col.astype(object))
    return out


#: Names of formats that are not CSV text: a CSV file given such a name does not open.
NOT_TEXT_SUFFIXES = (".xlsx", ".xls", ".xlsm", ".ods", ".parquet", ".shp", ".kml", ".kmz")
#: Names of compressed files: the writers write plain text.
COMPRESSED_SUFFIXES = (".gz", ".bz2", ".xz", ".zip", ".zst")


def check_text_path(path: str | Path) -> None:
    """Refuse (:class:`~wakeline.core.errors.InputError`, one line) a name that says the
    file is a spreadsheet, another binary format or compressed, for CSV text: written,
    ``tracks.xlsx`` held CSV text that a spreadsheet refuses to open. The command line's
    ``export`` and the window's Export menu both ask here."""
    from wakeline.core.errors import InputError

    suffix = Path(path).suffix.lower()
    if suffix in NOT_TEXT_SUFFIXES:
        raise InputError(
            f"{path}: export writes CSV text, GeoJSON or GPX, not {suffix} (a CSV "
            "file opens in a spreadsheet: write to .csv)"
        )
    if suffix in COMPRESSED_SUFFIXES:
        raise InputError(
            f"{path}: export writes plain text, not {suffix} (compress the file "
            "afterwards, or write to .csv)"
        )


def export_csv(points: pd.DataFrame, path: str | Path) -> None:
    """Canonical CSV (canonical columns first), spreadsheet-safe, written atomically;
    a name :func:`check_text_path` refuses raises InputError and writes nothing. A layer
    that carries its file's rows (the window's) is written in the file's order
    (:func:`~wakeline.core.schema.in_file_order`)."""
    check_text_path(path)
    points = in_file_order(points)
    write_csv(spreadsheet_safe(points[written_columns(points)]), path)


def member_labels(points: pd.DataFrame) -> pd.Series:
    """Each row's own track as ``sensor:batch``: merged tracks keep it in
    ``source_track``; other rows are their own."""
    if "source_track" in points.columns and points["sensor"].astype(str).eq("merged").all():
        return points["source_track"].astype(str)
    return points["sensor"].astype(str) + ":" + points["batch"].astype(str)


def carries_targets(points: pd.DataFrame) -> bool:
    """Whether ``points`` are member tracks with their targets (an associated or reviewed
    layer, or merged tracks that keep ``source_track``): written as targets of tracks in
    every format. Fused tracks are targets themselves (their points are made)."""
    if "target" not in points.columns or not len(points):
        return False
    if points["target"].isna().any():
        return False
    return not points["sensor"].astype(str).eq("fused").any()


def _iso_times(times: pd.Series) -> np.ndarray:
    """ISO 8601 UTC texts (``…Z``), all with the one fraction the finest time needs (whole
    seconds, ms, µs or ns): one unit for the column, so every text parses alike."""
    ns = pd.to_datetime(times, utc=True).dt.tz_localize(None).to_numpy("datetime64[ns]")
    if not len(ns):
        return np.zeros(0, dtype=str)
    frac = ns.astype("int64") % 1_000_000_000
    unit = next(
        (u for u, step in (("s", 10**9), ("ms", 10**6), ("us", 10**3)) if not (frac % step).any()),
        "ns",
    )
    return np.char.add(np.datetime_as_string(ns, unit=unit), "Z")


def geojson(points: pd.DataFrame, maneuvers: pd.DataFrame | None = None) -> dict:
    """A FeatureCollection: one LineString per track (Point for one-point tracks) with
    sensor, batch, points, start, end, ``times`` (one ISO time per vertex, so that the file
    reads back as tracks) and any per-track text columns (target, members, source...), plus
    one Point per maneuver when given. Coordinates are [lon, lat]. Tracks with targets
    keep their own sensor and batch and carry ``target`` (merged tracks are written per
    member track, from ``source_track``): the GeoJSON reader gives the target back."""
    if carries_targets(points) and "source_track" in points.columns:
        # merged tracks: one feature per member track, as every format writes targets
        label = member_labels(points).str.split(":", n=1)
        points = points.assign(sensor=label.str[0], batch=label.str[1])
    pts, index = sorted_with_index(points)
    lon = np.round(pts["lon"].to_numpy(dtype="float64"), 7)
    lat = np.round(pts["lat"].to_numpy(dtype="float64"), 7)
    times = pts["time"]
    extra = [
        c
        for c in ("target", "members", "truth")
        if c in pts.columns and c not in ("sensor", "batch")
    ]
    features = []
    t = time_seconds(times) if len(pts) else np.zeros(0)
    # one ISO time per vertex (as togeojson's coordTimes): the file reads back as tracks
    iso = _iso_times(times)
    for k in range(index.n_tracks):  # one feature per track; the coordinates are sliced
        s, e = int(index.starts[k]), int(index.ends[k])
        coords = np.column_stack([lon[s:e], lat[s:e]]).tolist()
        props = {
            "sensor": str(index.keys["sensor"].iloc[k]),
            "batch": str(index.keys["batch"].iloc[k]),
            "points": e - s,
            "start": times.iloc[s].isoformat(),
            "end": times.iloc[e - 1].isoformat(),
            "duration_s": float(t[e - 1] - t[s]),
            "times": iso[s:e].tolist(),
        }
        for c in extra:
            props[c] = str(pts[c].iloc[s])
        geom = (
            {"type": "Point", "coordinates": coords[0]}
            if e - s == 1
            else {"type": "LineString", "coordinates": coords}
        )
        features.append({"type": "Feature", "geometry": geom, "properties": props})
    if maneuvers is not None:
        for row in maneuvers.itertuples(index=False):
            features.append(
                {
                    "type": "Feature",
                    "geometry": {
                        "type": "Point",
                        "coordinates": [round(float(row.lon), 7), round(float(row.lat), 7)],
                    },
                    "properties": {
                        "kind": "maneuver",
                        "sensor": str(row.sensor),
                        "batch": str(row.batch),
                        "time": pd.Timestamp(row.time).isoformat(),
                        "factor_deg": round(float(row.factor), 3),
                    },
                }
            )
    return {"type": "FeatureCollection", "features": features}


def export_geojson(
    points: pd.DataFrame, path: str | Path, maneuvers: pd.DataFrame | None = None
) -> None:
    """Write :func:`geojson` atomically (UTF-8)."""
    text = json.dumps(geojson(points, maneuvers), ensure_ascii=False)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")

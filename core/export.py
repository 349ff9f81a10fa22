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

from wakeline.core.io.geojson import CUT_VERTICES, VERTEX_PROPERTIES
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


def member_sensor_batch(points: pd.DataFrame) -> tuple[pd.Series, pd.Series]:
    """Each row's own track as (sensor, batch). Merged tracks keep it in ``source_track``
    (``sensor:batch``) and, since session 29, the sensor alone in ``source_sensor``, so that a
    sensor with a ``:`` in its name splits right; without that column the first ``:`` splits."""
    label = member_labels(points)
    parts = label.str.split(":", n=1)
    sensor, batch = parts.str[0], parts.str[1]
    if "source_sensor" in points.columns and points["sensor"].astype(str).eq("merged").all():
        # the kept sensor where it is a prefix of the row's own track; else the first ':'
        # (a row from an older merged file, a blank or missing cell)
        kept = points["source_sensor"]
        key = label + "\x00" + kept.astype(str).where(kept.notna(), "")
        codes, uniq = pd.factorize(key, use_na_sentinel=False)
        own_sensor, own_batch = [], []
        for k in uniq:  # per track, not per point
            lab, sen = k.split("\x00", 1)
            usable = bool(sen) and lab.startswith(sen + ":")
            own_sensor.append(sen if usable else None)
            own_batch.append(lab[len(sen) + 1 :] if usable else None)
        own_sensor = pd.Series(np.asarray(own_sensor, dtype=object)[codes], index=label.index)
        own_batch = pd.Series(np.asarray(own_batch, dtype=object)[codes], index=label.index)
        ok = own_sensor.notna()
        sensor, batch = own_sensor.where(ok, sensor), own_batch.where(ok, batch)
    return sensor, batch


def carries_targets(points: pd.DataFrame) -> bool:
    """Whether ``points`` are member tracks with their targets (an associated or reviewed
    layer, or merged tracks that keep ``source_track``): written as targets of tracks in
    every format. Fused tracks are targets themselves (their points are made)."""
    if "target" not in points.columns or not len(points):
        return False
    if points["target"].isna().any():
        return False
    return not points["sensor"].astype(str).eq("fused").any()


_UNIT_NS = {"s": 10**9, "ms": 10**6, "us": 10**3, "ns": 1}


def _iso_times(times: pd.Series) -> tuple[np.ndarray, str]:
    """ISO 8601 UTC texts (``…Z``), all with the one fraction the finest time needs (whole
    seconds, ms, µs or ns): one unit for the column, so every text parses alike. Returns
    the texts and the unit."""
    ns = pd.to_datetime(times, utc=True).dt.tz_localize(None).to_numpy("datetime64[ns]")
    if not len(ns):
        return np.zeros(0, dtype=str), "s"
    frac = ns.astype("int64") % 1_000_000_000
    unit = next((u for u in ("s", "ms", "us") if not (frac % _UNIT_NS[u]).any()), "ns")
    return np.char.add(np.datetime_as_string(ns, unit=unit), "Z"), unit


def antimeridian_parts(
    lon: np.ndarray, lat: np.ndarray, ns: np.ndarray, unit: str
) -> tuple[list[np.ndarray], np.ndarray, list[int]] | None:
    """A line whose steps cross the antimeridian (|Δlon| > 180°) cut there into parts
    (RFC 7946 §3.1.9): each crossing ends one part on ±180° and starts the next on ∓180°
    at the latitude and time interpolated along the step (the time rounded to ``unit``).
    Returns the parts (arrays of [lon, lat]), the time (ns) of every vertex in order and
    the indices of the added vertices; None when no step crosses."""
    jumps = np.flatnonzero(np.abs(np.diff(lon)) > 180.0)
    if not len(jumps):
        return None
    a, b = jumps, jumps + 1
    east = lon[a] > 0  # east-going over 180: the next fix is at -179.x
    edge = np.where(east, 180.0, -180.0)
    far = lon[b] + np.where(east, 360.0, -360.0)  # the next fix unwrapped
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(far != lon[a], (edge - lon[a]) / (far - lon[a]), 0.0)
    f = np.clip(f, 0.0, 1.0)
    lat_x = lat[a] + f * (lat[b] - lat[a])
    step = _UNIT_NS[unit]
    t_x = ns[a] + np.round(f * (ns[b] - ns[a]) / step).astype("int64") * step
    xy = np.column_stack([lon, lat])
    parts, times, added = [], [], []
    start, n_done = 0, 0
    for k in range(len(jumps)):  # one slice per crossing (a handful per track)
        end = int(b[k])
        part = np.vstack([xy[start:end], [[edge[k], lat_x[k]]]])
        if k:
            part = np.vstack([[[-edge[k - 1], lat_x[k - 1]]], part])
        parts.append(part)
        before = t_x[k - 1 : k] if k else t_x[:0]  # int64 throughout (ns exceed 2**53)
        times.append(np.concatenate([before, ns[start:end], t_x[k : k + 1]]))
        if k:
            added.append(n_done)
        added.append(n_done + len(part) - 1)
        n_done += len(part)
        start = end
    last = np.vstack([[[-edge[-1], lat_x[-1]]], xy[start:]])
    parts.append(last)
    times.append(np.concatenate([t_x[-1:], ns[start:]]))
    added.append(n_done)
    return parts, np.concatenate(times).astype("int64"), added


#: Columns a GeoJSON feature carries otherwise (its geometry, ``times`` and per-track
#: properties), or that name the feature's own track: not written per vertex.
_NOT_PER_VERTEX = frozenset(
    ("sensor", "batch", "time", "lon", "lat", "target", "members", "truth", "source_track")
    + ("source_sensor",)
)


def vertex_columns(points: pd.DataFrame) -> tuple[list[str], list[str]]:
    """The columns :func:`geojson` writes per vertex (speed, course and the columns the
    import carried: in ``coordinateProperties``, as togeojson writes a GPX track's
    per-point values) and the columns it leaves out (Wakeline's internal ones,
    :data:`~wakeline.core.io.layout.INTERNAL_COLUMNS`; the log and docs/export.md say so)."""
    from wakeline.core.io.layout import INTERNAL_COLUMNS
    from wakeline.core.schema import UNWRITTEN

    cols = [c for c in written_columns(points) if c not in _NOT_PER_VERTEX]
    kept = [c for c in cols if c not in INTERNAL_COLUMNS]
    left = [c for c in cols if c in INTERNAL_COLUMNS and c not in UNWRITTEN]
    return kept, left


def _json_values(col: pd.Series) -> list:
    """A column as JSON values: numbers as numbers, text as text, missing as null."""
    missing = col.isna().to_numpy()
    if isinstance(col.dtype, pd.DatetimeTZDtype) or pd.api.types.is_datetime64_any_dtype(col.dtype):
        out = np.empty(len(col), dtype=object)
        if (~missing).any():
            out[~missing] = _iso_times(col[~missing])[0]
    elif pd.api.types.is_bool_dtype(col.dtype):
        out = col.astype(object).to_numpy()
    elif pd.api.types.is_numeric_dtype(col.dtype):
        x = col.to_numpy(dtype="float64", na_value=np.nan)
        out = x.astype(object)
        if pd.api.types.is_integer_dtype(col.dtype):
            out[~missing] = x[~missing].astype("int64").astype(object)
        missing = missing | ~np.isfinite(x)
    else:
        out = col.astype("str").to_numpy(dtype=object)
    out[missing] = None
    return out.tolist()


def geojson(points: pd.DataFrame, maneuvers: pd.DataFrame | None = None) -> dict:
    """A FeatureCollection: one LineString per track (Point for one-point tracks) with
    sensor, batch, points, start, end, ``times`` (one ISO time per vertex, so that the file
    reads back as tracks), ``coordinateProperties`` (speed, course and the carried columns,
    one value per vertex: :func:`vertex_columns`) and any per-track text columns (target,
    members, source...), plus
    one Point per maneuver when given. Coordinates are [lon, lat]. Tracks with targets
    keep their own sensor and batch and carry ``target`` (merged tracks are written per
    member track, from ``source_track``): the GeoJSON reader gives the target back."""
    if carries_targets(points) and "source_track" in points.columns:
        # merged tracks: one feature per member track, as every format writes targets
        sensor, batch = member_sensor_batch(points)
        points = points.assign(sensor=sensor, batch=batch)
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
    iso, unit = _iso_times(times)
    ns = (pd.to_datetime(times, utc=True).dt.tz_localize(None).to_numpy("datetime64[ns]")).astype(
        "int64"
    )
    # speed, course and the carried columns, one value per vertex (D12: they were dropped)
    per_vertex = {c: _json_values(pts[c]) for c in vertex_columns(pts)[0]}
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
        values = {c: v[s:e] for c, v in per_vertex.items()}
        cut = antimeridian_parts(lon[s:e], lat[s:e], ns[s:e], unit) if e - s > 1 else None
        if cut is not None:  # RFC 7946 §3.1.9: cut at ±180°, the added vertices named
            parts, cut_ns, added = cut
            geom = {
                "type": "MultiLineString",
                "coordinates": [np.round(p, 7).tolist() for p in parts],
            }
            text = np.datetime_as_string(cut_ns.astype("datetime64[ns]"), unit=unit)
            props["times"] = np.char.add(text, "Z").tolist()
            props[CUT_VERTICES] = added
            for v in values.values():  # the added vertices are no fixes: null
                for i in added:
                    v.insert(i, None)
        else:
            geom = (
                {"type": "Point", "coordinates": coords[0]}
                if e - s == 1
                else {"type": "LineString", "coordinates": coords}
            )
        if values:
            props[VERTEX_PROPERTIES] = values
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

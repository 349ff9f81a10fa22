"""GeoJSON tracks (our own ``.geojson`` export, GIS tools, togeojson's GPX conversions).

A FeatureCollection (or a single Feature) is read feature by feature:

- a ``LineString`` or ``MultiLineString`` with one time per vertex — the property
  ``times`` (Wakeline's export) or ``coordTimes`` (togeojson, Mapbox) — is one track;
- a ``Point`` with a time property (``time``, ``timestamp``, ``datetime``… the names the
  CSV reader knows) is one point of the track its id property names (``batch``, ``mmsi``,
  ``track_id``…, again the CSV reader's names; one track per file without one);
- Wakeline's maneuver points (``"kind": "maneuver"``) are results, not input: counted.

The id and sensor come from the feature's properties by the same names as CSV headers
(``sensor``, ``batch``, ``mmsi``…); a track without an id is ``feature N``.
A ``target`` property (Wakeline's export of tracks with targets) is read back as the
points' ``target``; the vertices a cut at the antimeridian added (``antimeridian_vertices``,
on ±180° between two fixes) are left out, so the file reads back to its fixes.

Nothing is lost silently: a feature without times (a line whose vertices have no time, a
point without a time property), with another geometry, or whose times do not match its
vertices is one quarantined row; a vertex with an unreadable time or position, or beyond
±90° / ±180°, is one quarantined row. A GeoJSON file is one document, not lines: the
quarantine's ``line`` column holds the feature's number (1-based) and its ``text`` the
start of the feature's JSON. A file that is not valid JSON is refused with the parser's
message.
"""

import functools
import json

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.io.compressed import open_data
from wakeline.core.io.formats import SYNONYMS, normalize_header
from wakeline.core.io.sniff import Sniff
from wakeline.core.progress import Progress, null_progress

#: Per-vertex times of a line feature: ours, then togeojson's.
TIME_ARRAYS = ("times", "coordTimes")
#: Property of a line Wakeline cut at the antimeridian (RFC 7946 §3.1.9): the vertices
#: the cut added on ±180° between two fixes (0-based, over the line's vertices in order).
#: They are not fixes: left out on reading.
CUT_VERTICES = "antimeridian_vertices"
#: Property of a line holding its per-vertex values, one array per column (togeojson's
#: name for a GPX track's per-point values): Wakeline writes speed, course and the columns
#: the import carried there (operator test 7, D12) and reads them back.
VERTEX_PROPERTIES = "coordinateProperties"
#: The start of :func:`targets_note` (a read in pieces says it once, for the whole file).
TARGETS_MARK = "this file carries targets: "
_TEXT_CHARS = 200


def targets_note(points: pd.DataFrame, csv: bool = False) -> list[str]:
    """The note an import gives for a file that carries Wakeline's targets (a ``target``
    column, property or GPX ``<trk>`` whose tracks it groups): the tracks are read as
    they were and keep their target, as every export writes them (docs/export.md). For a
    CSV, how to read one track per target instead."""
    if "target" not in points.columns or not len(points):
        return []
    n_tracks = len(points[["sensor", "batch"]].drop_duplicates())
    n_targets = int(points["target"].nunique())
    if n_targets >= n_tracks:
        return []
    how = "; --map batch=target reads one track per target" if csv else ""
    return [
        f"{TARGETS_MARK}{n_tracks:,} tracks in {n_targets:,} targets "
        f"(column 'target'), read with their target{how}"
    ]


def _field_of(properties: dict, field: str) -> str | None:
    """The property that names ``field`` (as a CSV header would), or None; decided once
    per set of property names (a collection's features mostly share theirs)."""
    return _field_among(tuple(properties), field)


@functools.lru_cache(maxsize=256)
def _field_among(keys: tuple, field: str):
    names = {normalize_header(str(k)): k for k in keys}
    for cand in SYNONYMS.get(field, (field,)):
        key = names.get(normalize_header(cand))
        if key is not None:
            return key
    return None


def _vertices(coords: list) -> tuple[list, list]:
    """Longitudes and latitudes of a line's vertices (None where a vertex is not a pair of
    numbers); one numpy conversion for a well-formed line."""
    try:
        xy = np.asarray(coords, dtype="float64")
        if xy.ndim == 2 and xy.shape[1] >= 2:
            return xy[:, 0].tolist(), xy[:, 1].tolist()
    except (TypeError, ValueError):
        pass
    ok = [isinstance(c, list | tuple) and len(c) >= 2 for c in coords]
    return (
        [c[0] if good else None for c, good in zip(coords, ok, strict=True)],
        [c[1] if good else None for c, good in zip(coords, ok, strict=True)],
    )


def _snippet(feature) -> str:
    text = json.dumps(feature, ensure_ascii=False)
    return text if len(text) <= _TEXT_CHARS else text[: _TEXT_CHARS - 1] + "…"


def read_geojson(
    sn: Sniff, sensor: str = "S1", progress: Progress | None = None, timing: dict | None = None
):
    """Read the tracks of a GeoJSON file into the canonical point table (an
    ``ImportResult``)."""
    from wakeline.core.io.reader import (
        ImportResult,
        points_summary,
        quarantine_table,
        times_of_values,
    )

    progress = progress or null_progress
    try:
        with open_data(sn.path, sn.compression) as fh:
            doc = json.loads(fh.read().decode(sn.encoding.replace("-sig", "") or "utf-8"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"{sn.path}: not valid GeoJSON ({str(exc)[:200]})") from None
    if isinstance(doc, dict) and doc.get("type") == "FeatureCollection":
        features = doc.get("features") or []
    elif isinstance(doc, dict) and doc.get("type") == "Feature":
        features = [doc]
    else:
        raise InputError(f"{sn.path}: GeoJSON without features (a FeatureCollection or a Feature)")
    progress(0.5, "parsed")

    cols: dict[str, list] = {
        k: [] for k in ("sensor", "batch", "time", "lon", "lat", "feature", "target")
    }
    q_line, q_reason, q_text = [], [], []
    counts = {"line_features": 0, "point_features": 0, "maneuver_points": 0, "cut_vertices": 0}

    vertex: dict[str, list] = {}  # per-vertex values (coordinateProperties) by column

    def add_vertex_values(props: dict, n_coords: int, keep: list | None) -> None:
        """The feature's per-vertex arrays (those with one value per vertex) after the
        rows added so far; columns it lacks get nulls."""
        done = len(cols["lon"])
        n = n_coords if keep is None else len(keep)
        given = props.get(VERTEX_PROPERTIES)
        if isinstance(given, dict):
            for name, arr in given.items():
                if name in TIME_ARRAYS or not isinstance(arr, list) or len(arr) != n_coords:
                    continue
                col = vertex.setdefault(str(name), [])
                col.extend([None] * (done - len(col)))
                col.extend(arr if keep is None else [arr[i] for i in keep])
        for col in vertex.values():
            col.extend([None] * (done + n - len(col)))

    def bad(k: int, feature, reason: str) -> None:
        q_line.append(k + 1)
        q_reason.append(reason)
        q_text.append(_snippet(feature))

    for k, feature in enumerate(features):
        if not isinstance(feature, dict):
            bad(k, feature, "not a GeoJSON feature")
            continue
        props = feature.get("properties") or {}
        geom = feature.get("geometry") or {}
        kind = geom.get("type") if isinstance(geom, dict) else None
        if props.get("kind") == "maneuver":
            counts["maneuver_points"] += 1
            continue
        sensor_key = _field_of(props, "sensor")
        batch_key = _field_of(props, "batch")
        own_sensor = str(props[sensor_key]) if sensor_key else sensor
        target = props.get("target")  # Wakeline's associated tracks: the track's target
        target = None if target is None else str(target)
        if kind in ("LineString", "MultiLineString"):
            counts["line_features"] += 1
            coords = geom.get("coordinates") or []
            if kind == "MultiLineString":
                coords = [c for part in coords for c in (part or [])]
            key = next((t for t in TIME_ARRAYS if t in props), None)
            times = props.get(key) if key else None
            inner = props.get(VERTEX_PROPERTIES)
            if key is None and isinstance(inner, dict):  # togeojson 5: the times in there
                key = next((t for t in TIME_ARRAYS if t in inner), None)
                times = inner.get(key) if key else None
            if key is None:
                bad(k, feature, "a line without per-vertex times (no 'times' or 'coordTimes')")
                continue
            if not isinstance(times, list) or len(times) != len(coords):
                n_t = len(times) if isinstance(times, list) else 0
                bad(k, feature, f"{len(coords)} vertices but {n_t} times in {key!r}")
                continue
            batch = str(props[batch_key]) if batch_key else f"feature {k + 1}"
            lon_k, lat_k = _vertices(coords)
            added = props.get(CUT_VERTICES)
            keep = None
            if isinstance(added, list) and added:
                # ours: vertices on ±180° the antimeridian cut added, not fixes
                drop = {int(i) for i in added if isinstance(i, int) and 0 <= i < len(coords)}
                keep = [i for i in range(len(coords)) if i not in drop]
                lon_k = [lon_k[i] for i in keep]
                lat_k = [lat_k[i] for i in keep]
                times = [times[i] for i in keep]
                counts["cut_vertices"] += len(drop)
            n = len(lon_k)
            add_vertex_values(props, len(coords), keep)
            cols["sensor"].extend([own_sensor] * n)
            cols["batch"].extend([batch] * n)
            cols["time"].extend(times)
            cols["lon"].extend(lon_k)
            cols["lat"].extend(lat_k)
            cols["feature"].extend([k] * n)
            cols["target"].extend([target] * n)
        elif kind == "Point":
            counts["point_features"] += 1
            time_key = _field_of(props, "time")
            one = next((props[a] for a in TIME_ARRAYS if isinstance(props.get(a), list)), None)
            if time_key is None and (one is None or len(one) != 1):
                bad(k, feature, "a point without a time property")
                continue
            stamp = props[time_key] if time_key is not None else one[0]  # ours: times[0]
            c = geom.get("coordinates") or []
            ok = isinstance(c, list | tuple) and len(c) >= 2
            add_vertex_values(props, 1, None)
            cols["sensor"].append(own_sensor)
            cols["batch"].append(str(props[batch_key]) if batch_key else "points")
            cols["time"].append(stamp)
            cols["lon"].append(c[0] if ok else None)
            cols["lat"].append(c[1] if ok else None)
            cols["feature"].append(k)
            cols["target"].append(target)
        else:
            bad(k, feature, f"geometry {kind or 'none'}: only LineString and Point are tracks")

    lon = pd.to_numeric(pd.Series(cols["lon"], dtype="object"), errors="coerce").to_numpy(
        dtype="float64", na_value=np.nan
    )
    lat = pd.to_numeric(pd.Series(cols["lat"], dtype="object"), errors="coerce").to_numpy(
        dtype="float64", na_value=np.nan
    )
    times, _ = times_of_values(cols["time"], timing)
    reason = np.full(len(lon), "", dtype=object)
    reason[~np.isfinite(lon) | ~np.isfinite(lat)] = "no readable lon/lat"
    out = np.isfinite(lon) & np.isfinite(lat) & ((np.abs(lat) > 90) | (np.abs(lon) > 180))
    reason[out & (reason == "")] = "lat beyond ±90° or lon beyond ±180°"
    reason[times.isna().to_numpy() & (reason == "")] = "unparsable time"
    good = reason == ""
    feature_of = np.asarray(cols["feature"], dtype="int64")
    snippets = {int(k): _snippet(features[int(k)]) for k in np.unique(feature_of[~good])}
    for k, why in zip(feature_of[~good], reason[~good], strict=True):
        q_line.append(int(k) + 1)
        q_reason.append(f"a vertex or point with {why}")
        q_text.append(snippets[int(k)])

    points = pd.DataFrame(
        {
            "sensor": pd.Series(np.asarray(cols["sensor"], dtype=object)[good], dtype="str"),
            "batch": pd.Series(np.asarray(cols["batch"], dtype=object)[good], dtype="str"),
            "time": times[good].reset_index(drop=True).astype("datetime64[ns, UTC]"),
            "lon": lon[good],
            "lat": lat[good],
        }
    )
    for name, values in vertex.items():  # speed and course as numbers, the rest as text
        values = values + [None] * (len(good) - len(values))
        arr = np.asarray(values, dtype=object)[good]
        if name in ("speed", "course"):
            points[name] = pd.to_numeric(pd.Series(arr, dtype="object"), errors="coerce").astype(
                "float64"
            )
        elif name not in points.columns:
            points[name] = pd.Series(arr, dtype="str")
    target = np.asarray(cols["target"], dtype=object)[good]
    if len(target) and any(t is not None for t in target):
        # a track without one is its own target (its batch)
        own = np.asarray(points["batch"], dtype=object)
        points["target"] = pd.Series(np.where(pd.isna(target), own, target), dtype="str")
    quarantine = quarantine_table(q_line, q_reason, q_text)
    warnings = []
    if counts["maneuver_points"]:
        warnings.append(
            f"{counts['maneuver_points']:,} maneuver point(s) (a result, not input) not imported"
        )
    no_times = sum(r.startswith("a line without per-vertex times") for r in q_reason)
    if no_times:
        warnings.append(
            f"{no_times:,} line(s) have no time per vertex ('times' or 'coordTimes'): a track "
            "needs one; export tracks as CSV or GPX to keep their times"
        )
    if len(quarantine):
        warnings.append(
            "the quarantine's 'line' column holds feature numbers (GeoJSON has no rows)"
        )
    warnings += targets_note(points)
    by_reason = quarantine["reason"].value_counts().to_dict() if len(quarantine) else {}
    progress(1.0, "imported")
    report = {
        "input": str(sn.path),
        "format": "geojson",
        "format_label": "GeoJSON tracks",
        "encoding": sn.encoding,
        "compression": sn.compression,
        "columns": {},
        "rows_read": int(len(lon) + len(q_line) - int((~good).sum())),
        "rows_imported": len(points),
        "rows_quarantined": len(quarantine),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": 0,
        "features": len(features),
        **counts,
        **points_summary(points),
        "warnings": warnings,
    }
    layout = {"format": "geojson", "encoding": sn.encoding, "compression": sn.compression}
    return ImportResult(points, quarantine, report, layout)

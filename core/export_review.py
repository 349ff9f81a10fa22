"""Export that honours the review's decisions: merged or fused tracks as CSV (optionally
with a UTF-8 byte-order mark, so spreadsheets read Chinese names), GeoJSON and GPX (for
OpenCPN), and the decision log as CSV.

"Merged" tracks are the reviewed points with their ``target``, one track per target
(``batch`` = target, the original ``sensor:batch`` kept in ``source_track``); "fused"
tracks come from :func:`wakeline.core.fuse.fuse` run on the decided targets.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.export import (
    carries_targets,
    export_geojson,
    member_labels,
    member_sensor_batch,
    spreadsheet_safe,
)
from wakeline.core.io.gpx import GPX_TARGET_TYPE
from wakeline.core.io.writer import atomic_path, write_csv
from wakeline.core.review import ReviewState, _labels, point_labels
from wakeline.core.schema import written_columns

EXPORT_FORMATS = ("csv", "geojson", "gpx")


def merged_tracks(state: ReviewState, points: pd.DataFrame) -> pd.DataFrame:
    """One track per target: every input row with ``sensor`` = ``merged``, ``batch`` =
    target, ``members`` = the target's tracks (``sensor:batch`` joined by ``+``, as
    fusion writes it) and ``source_track`` = the row's own ``sensor:batch``."""
    pts = state.label_points(points)
    pts["source_track"] = point_labels(pts)
    pts["source_sensor"] = pts["sensor"].astype(str)  # splits source_track when a sensor has ':'
    members = pts.groupby("target")["source_track"].agg(lambda s: "+".join(sorted(set(s))))
    pts["members"] = members.reindex(pts["target"]).to_numpy()
    pts["sensor"] = "merged"
    pts["batch"] = pts["target"]
    return pts.sort_values(["batch", "time"], kind="stable").reset_index(drop=True)


def fused_tracks(state: ReviewState, sassoc: object, params: object | None = None) -> pd.DataFrame:
    """:func:`wakeline.core.fuse.fuse` with the targets the decisions give (members of a
    target may be of one sensor or several)."""
    from wakeline.core.fuse import fuse

    tt = state.targets().set_index("track")["target"]
    labels = _labels(sassoc.index.keys)
    target = tt.reindex(labels).to_numpy()
    if pd.isna(target).any():
        raise InputError("the fused points hold tracks the review does not know")
    return fuse(dataclasses.replace(sassoc, target_of_track=target.astype(str)), params)


def export_tracks_csv(points: pd.DataFrame, path: str | Path, bom: bool = False) -> None:
    """Spreadsheet-safe CSV, canonical columns first; ``bom`` prefixes a UTF-8 BOM."""
    export_table_csv(points[written_columns(points)], path, bom)


#: Garmin's TrackPointExtension v2: ``<gpxtpx:speed>`` (m/s) and ``<gpxtpx:course>``
#: (degrees true, 0-360) per ``<trkpt>`` in its ``<extensions>``, as OpenCPN, Garmin and
#: others read them (GPX 1.1 has no speed or course of its own; GPX 1.0 had).
GPXTPX_NS = "http://www.garmin.com/xmlschemas/TrackPointExtension/v2"
GPXTPX_PREFIX = "gpxtpx"


def _speed_course(pts: pd.DataFrame) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The points' speed in m/s (from knots) and course in degrees [0, 360), NaN where
    missing; None for a column absent or empty throughout."""
    from wakeline.core import geo

    out = []
    for col in ("speed", "course"):
        if col not in pts.columns:
            out.append(None)
            continue
        x = pd.to_numeric(pts[col], errors="coerce").to_numpy(dtype="float64", na_value=np.nan)
        x = np.where(np.isfinite(x), x, np.nan)
        if col == "speed":
            x = np.where(x >= 0, x, np.nan)  # the extension's speed is never negative
        if not np.isfinite(x).any():
            out.append(None)
            continue
        out.append(x * geo.KN_MS if col == "speed" else np.mod(x, 360.0))
    return out[0], out[1]


def _add_speed_course(points: list, speed, course, s: int, e: int) -> None:
    """``<extensions><gpxtpx:TrackPointExtension>`` with speed and course (full digits:
    they read back as written) on each of ``points`` (rows ``s:e``) that has either."""
    from xml.etree.ElementTree import Element, SubElement

    ext = f"{{{GPXTPX_NS}}}TrackPointExtension"
    sp, co = f"{{{GPXTPX_NS}}}speed", f"{{{GPXTPX_NS}}}course"
    n = e - s
    v = speed[s:e] if speed is not None else np.full(n, np.nan)
    c = course[s:e] if course is not None else np.full(n, np.nan)
    for point, vk, ck in zip(points, v.tolist(), c.tolist(), strict=True):
        if vk != vk and ck != ck:  # both NaN: no extension
            continue
        el = Element(ext)
        if vk == vk:  # the schema's order: speed, then course
            SubElement(el, sp).text = repr(vk)
        if ck == ck:
            SubElement(el, co).text = repr(ck)
        point.extensions.append(el)


def gpx_left_out(points: pd.DataFrame) -> tuple[list[str], list[str]]:
    """The columns :func:`export_gpx` does not write though GeoJSON does (the import's
    carried columns: a GPX point holds time, position, speed and course only), and
    Wakeline's internal ones no map format writes (:func:`~wakeline.core.export.vertex_columns`)."""
    from wakeline.core.export import vertex_columns

    kept, internal = vertex_columns(points)
    return [c for c in kept if c not in ("speed", "course")], internal


def export_gpx(points: pd.DataFrame, path: str | Path, creator: str = "Wakeline") -> None:
    """GPX 1.1, written atomically (UTF-8). Tracks with targets (an associated or reviewed
    layer: a ``target`` column): one ``<trk>`` per target (name the target, ``<type>``
    :data:`GPX_TARGET_TYPE`, ``<desc>`` its member tracks ``sensor:batch`` joined by
    ``+``, ``<src>`` their sensors joined by ``+``) with one ``<trkseg>`` per
    member track, in the order the description names them. Other tracks: one ``<trk>``
    per track (name ``sensor:batch``, ``<src>`` its sensor, description its members when
    known), one segment. Points with time; speed and course where known as Garmin's
    TrackPointExtension v2 (``gpxtpx:speed`` m/s, ``gpxtpx:course`` degrees), which the
    GPX reader takes back."""
    import gpxpy.gpx

    gpx = gpxpy.gpx.GPX()
    gpx.creator = creator
    targets = carries_targets(points)
    if targets:
        member = member_labels(points)
        pts = points.assign(_member=member.to_numpy(), _target=points["target"].astype(str))
        pts = pts.sort_values(["_target", "_member", "time"], kind="stable")
        keys = pts["_target"]
    else:
        pts = points.sort_values(["sensor", "batch", "time"], kind="stable")
        # Merged and fused tracks are named by their target; others by sensor:batch.
        own = ~pts["sensor"].astype(str).isin(["merged", "fused"])
        keys = (
            pts["batch"]
            .astype(str)
            .where(~own, pts["sensor"].astype(str) + ":" + pts["batch"].astype(str))
        )
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    times = pd.to_datetime(pts["time"], utc=True).dt.to_pydatetime()
    codes, names = pd.factorize(keys, sort=False)
    sensors = pts["sensor"].astype(str).to_numpy()
    bounds = np.flatnonzero(np.diff(codes, prepend=-1, append=-1))
    if targets:
        m_codes = pd.factorize(pts["_member"], sort=False)[0]
        cuts = np.flatnonzero(np.diff(m_codes, prepend=-1, append=-1))  # member starts
        labels = pts["_member"].to_numpy()
        merged = pts["sensor"].astype(str).eq("merged").all()  # members in source_track
        own_sensor = (
            member_sensor_batch(pts)[0] if merged else pts["sensor"].astype(str)
        ).to_numpy()
    members = pts["members"].astype(str).to_numpy() if "members" in pts.columns else None

    speed, course = _speed_course(pts)
    if speed is not None or course is not None:
        gpx.nsmap[GPXTPX_PREFIX] = GPXTPX_NS

    def segment(s: int, e: int):
        seg = gpxpy.gpx.GPXTrackSegment()
        seg.points = [
            gpxpy.gpx.GPXTrackPoint(la, lo, time=tm)
            for lo, la, tm in zip(lon[s:e], lat[s:e], times[s:e], strict=True)
        ]
        if speed is not None or course is not None:
            _add_speed_course(seg.points, speed, course, s, e)
        return seg

    for s, e in zip(bounds[:-1], bounds[1:], strict=True):  # one object per track, not per point
        trk = gpxpy.gpx.GPXTrack(name=str(names[codes[s]]))
        if targets:
            parts = cuts[np.searchsorted(cuts, s) : np.searchsorted(cuts, e, side="right")]
            trk.type = GPX_TARGET_TYPE
            trk.description = "+".join(str(labels[a]) for a in parts[:-1])
            # <src>: the members' sensors (joined by '+'), so a sensor with a ':' reads back
            trk.source = "+".join(sorted(set(own_sensor[s:e].tolist())))
            for a, b in zip(parts[:-1], parts[1:], strict=True):
                trk.segments.append(segment(int(a), int(b)))
        else:
            trk.source = str(sensors[s])  # <src>: the sensor, so that the file reads back
            if members is not None:
                trk.description = members[s]
            trk.segments.append(segment(int(s), int(e)))
        gpx.tracks.append(trk)
    text = gpx.to_xml(version="1.1")
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")


def export_tracks(points: pd.DataFrame, path: str | Path, bom: bool = False) -> str:
    """Write tracks in the format named by the suffix (.csv, .geojson/.json, .gpx);
    returns the format used."""
    suffix = Path(path).suffix.lower()
    if suffix in (".geojson", ".json"):
        export_geojson(points, path)
        return "geojson"
    if suffix == ".gpx":
        export_gpx(points, path)
        return "gpx"
    if suffix in (".csv", ".txt", ""):
        export_tracks_csv(points, path, bom)
        return "csv"
    raise InputError(f"{path}: unknown export format {suffix!r} (use .csv, .geojson or .gpx)")


def export_decision_log(state: ReviewState, path: str | Path, bom: bool = False) -> None:
    """The decision log as CSV: time, action, proposal, tracks, before, after."""
    export_table_csv(state.log_table(), path, bom)


def export_table_csv(df: pd.DataFrame, path: str | Path, bom: bool = False) -> None:
    """Any table as spreadsheet-safe CSV with an optional BOM."""
    write_csv(spreadsheet_safe(df), path)
    if bom:
        p = Path(path)
        data = p.read_bytes()
        with atomic_path(p) as tmp:
            Path(tmp).write_bytes(b"\xef\xbb\xbf" + data)

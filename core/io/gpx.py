"""GPX tracks (GPX 1.0 and 1.1: OpenCPN's track export, chart plotters, phones, our own
``export --format gpx``).

Every ``<trk>`` is one track: its ``<name>`` is the batch (``track N`` when it has none;
a name that two tracks share gets `` (2)``, `` (3)``... on the later ones, with a warning).
A GPX written by Wakeline names a track ``sensor:batch``: it is read back as that sensor
and batch. Wakeline's targets (``<type>wakeline target</type>``: one ``<trk>`` per
target, one ``<trkseg>`` per member track named in order by ``<desc>``) are read back as
the member tracks with the ``<trk>``'s name as their ``target``. Each ``<trkpt>`` is a point (its ``<time>``, ISO 8601, UTC unless it says
otherwise; GPX 1.0's ``<speed>`` in m/s becomes knots, its ``<course>`` degrees; in GPX 1.1
the same from the point's ``<extensions>``: Garmin's TrackPointExtension v2
``<gpxtpx:speed>``/``<gpxtpx:course>``, as our export writes them, or a bare
``<speed>``/``<course>`` there; checked as a delimited file's: a negative or infinite
speed and a course outside [0, 360) blanked, 360 read as 0). Track
segments are one track: a segment break is a gap the cleaning and association steps see
by time.

Nothing is lost silently: a track point without a time, with a time or a position that
cannot be read, or beyond ±90° / ±180°, is a quarantined row (its line number and the
text of that line). Waypoints (``<wpt>``) and route points (``<rtept>``) are plans, not
tracks: counted in the report and named in a warning. A file that stops being
well-formed XML keeps the points before the break; every line from the break on is a
quarantined row naming the parser's complaint.

Parsing is expat's (the C parser of the standard library), one callback per element; the
table is built once at the end.
"""

from xml.parsers import expat

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core import geo
from wakeline.core.io.compressed import open_data
from wakeline.core.io.sniff import Sniff
from wakeline.core.progress import Progress, null_progress

#: ``<type>`` of a ``<trk>`` that is one target of Wakeline's, its ``<trkseg>``s the member
#: tracks named (in order) by the ``<desc>``: the GPX reader gives them back as tracks
#: with their ``target``.
GPX_TARGET_TYPE = "wakeline target"


#: The elements whose ``<speed>`` (m/s) and ``<course>`` (degrees) are a track point's
#: (by local name): Garmin's ``<gpxtpx:TrackPointExtension>`` (v2; our export writes it,
#: OpenCPN and others read it) and a point's ``<extensions>`` itself (OsmAnd's ``<speed>``).
_EXTENSION_PARENTS = ("TrackPointExtension", "extensions")


def _local(name: str) -> str:
    """An element's name without its namespace (``{http://…/1/1}trkpt`` → ``trkpt``)."""
    return name.rsplit("}", 1)[-1].rsplit(":", 1)[-1]


def _texts(values) -> pa.Array:
    """A list of texts (None where missing) or an Arrow string array, as an Arrow array."""
    if isinstance(values, pa.Array):
        return values
    return pa.array(values, pa.string())


#: A decimal number as both pandas and Arrow read it, to the same float (checked on
#: 1.2 M texts of 9 to 20 digits); anything else is read by pandas alone.
_PLAIN_NUMBER = r"^[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$"


def _numbers(texts) -> np.ndarray:
    """Attribute or element texts as float64 (NaN where missing or not a number): what
    ``pd.to_numeric(errors="coerce")`` makes of them; plain decimals are cast by Arrow in
    one call, the others (rare) go through pandas one by one."""
    texts = _texts(texts)
    plain = pc.fill_null(pc.match_substring_regex(texts, _PLAIN_NUMBER), False)
    out = np.full(len(texts), np.nan)
    keep = plain.to_numpy(zero_copy_only=False)
    if keep.any():
        out[keep] = pc.cast(texts.filter(plain), pa.float64()).to_numpy(zero_copy_only=False)
    other = ~keep & pc.is_valid(texts).to_numpy(zero_copy_only=False)
    if other.any():
        odd = texts.filter(pa.array(other)).to_pylist()
        out[other] = pd.to_numeric(pd.Series(odd, dtype="object"), errors="coerce").to_numpy(
            dtype="float64", na_value=np.nan
        )
    return out


def _line_texts(sn: Sniff, wanted: set[int], from_line: int | None) -> dict[int, str]:
    """The text of the physical lines ``wanted`` (1-based) and of every line from
    ``from_line`` on, read again from the file."""
    out: dict[int, str] = {}
    if not wanted and from_line is None:
        return out
    with open_data(sn.path, sn.compression) as fh:
        for number, raw in enumerate(fh, start=1):
            if number in wanted or (from_line is not None and number >= from_line):
                out[number] = raw.decode(sn.encoding, errors="replace").rstrip("\r\n")
    return out


def _expat_parse(fh, chunk: int = 1 << 20):
    """The track points of the GPX document in the binary file ``fh``, by expat's
    callbacks (one per element), fed ``chunk`` bytes at a time. Returns
    ``(rows, tracks, sources, counts, creator, broken)``: ``rows`` lists per field (one
    item per ``<trkpt>``: its track's index, its segment's number (1-based, over the
    file), line, lat, lon, time, speed, course texts), each ``<trk>``'s name, and its
    ``<src>``, ``<type>`` and ``<desc>`` (``sources`` as three lists), the waypoint/route point/segment counts, the
    ``creator`` and, for a file that stops being well-formed, ``(line, complaint)``."""
    parser = expat.ParserCreate(encoding=None)
    parser.buffer_text = True
    rows: dict[str, list] = {
        k: [] for k in ("track", "segment", "line", "lat", "lon", "time", "speed", "course")
    }
    tracks: list[str] = []  # each <trk>'s name ("" when it has none)
    sources: list[str] = []  # each <trk>'s <src> ("" when it has none)
    kinds: list[str] = []  # each <trk>'s <type> ("" when it has none)
    descs: list[str] = []  # each <trk>'s <desc> ("" when it has none)
    counts = {"waypoints": 0, "route_points": 0, "segments": 0}
    creator = {"text": ""}
    stack: list[str] = []
    point: dict | None = None
    text: list[str] = []

    def start(name: str, attrs: dict) -> None:
        nonlocal point
        tag = _local(name)
        stack.append(tag)
        text.clear()
        if tag == "gpx":
            creator["text"] = str(attrs.get("creator", ""))
        elif tag == "trk":
            tracks.append("")
            sources.append("")
            kinds.append("")
            descs.append("")
        elif tag == "trkseg":
            counts["segments"] += 1
        elif tag == "trkpt":
            point = {
                "track": max(len(tracks) - 1, 0),
                "segment": counts["segments"],
                "line": parser.CurrentLineNumber,
                "lat": attrs.get("lat"),
                "lon": attrs.get("lon"),
                "time": None,
                "speed": None,
                "course": None,
            }
        elif tag == "wpt":
            counts["waypoints"] += 1
        elif tag == "rtept":
            counts["route_points"] += 1

    def end(name: str) -> None:
        nonlocal point
        tag = stack.pop() if stack else _local(name)
        value = "".join(text).strip()
        text.clear()
        parent = stack[-1] if stack else ""
        if point is not None and parent == "trkpt" and tag in ("time", "speed", "course"):
            point[tag] = value
        elif point is not None and tag in ("speed", "course") and parent in _EXTENSION_PARENTS:
            if not point[tag]:  # GPX 1.0's own <speed>/<course> first, then an extension's
                point[tag] = value
        elif tag == "name" and parent == "trk" and tracks and not tracks[-1]:
            tracks[-1] = value
        elif tag == "src" and parent == "trk" and sources:
            sources[-1] = value
        elif tag == "type" and parent == "trk" and kinds:
            kinds[-1] = value
        elif tag == "desc" and parent == "trk" and descs:
            descs[-1] = value
        elif tag == "trkpt" and point is not None:
            if not tracks:  # a <trkpt> outside any <trk>: one track of its own
                tracks.append("")
                sources.append("")
                kinds.append("")
                descs.append("")
            for key in rows:
                rows[key].append(point[key])
            point = None

    def chars(data: str) -> None:
        text.append(data)

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars

    broken: tuple[int, str] | None = None
    try:
        while block := fh.read(chunk):
            parser.Parse(block, False)
        parser.Parse(b"", True)
    except expat.ExpatError as exc:
        what = f"{expat.errors.messages[exc.code]} at line {exc.lineno}, column {exc.offset}"
        broken = (exc.lineno, what)
        if point is not None:  # a track point the break cut: quarantined from its line
            broken = (min(exc.lineno, int(point["line"])), what)
    return rows, tracks, (sources, kinds, descs), counts, creator["text"], broken


def _targets_of(rows, names, trk_texts, track_sensor, track_batch, index):
    """Wakeline's own tracks with targets: every ``<trk>`` of ``<type>`` "wakeline
    target" whose ``<desc>`` names as many member tracks (``sensor:batch`` joined by
    ``+``) as it has segments gives one track per segment, named by the member, with the
    ``<trk>``'s name as its target. Returns ``(target, sensor, batch, index)`` per track
    (``index``: each point's track), ``target`` None when no ``<trk>`` is a target (the
    file reads as before); other ``<trk>``s are their own target."""
    sources, kinds, descs = trk_texts
    segment = np.asarray(rows["segment"], dtype="int64")
    wanted = [k for k, kind in enumerate(kinds) if kind == GPX_TARGET_TYPE]
    if not wanted or not len(segment):
        return None, track_sensor, track_batch, index
    target = list(track_batch)
    sensor, batch = list(track_sensor), list(track_batch)
    new_index = index.copy()
    lo = np.searchsorted(index, wanted, side="left")  # points are in document order
    hi = np.searchsorted(index, wanted, side="right")
    for k, a, e in zip(wanted, lo, hi, strict=True):  # one pass per target, not per point
        mine = slice(int(a), int(e))
        segs = np.unique(segment[mine])
        labels = descs[k].split("+") if descs[k] else []
        if len(labels) != len(segs) or not all(":" in lab for lab in labels):
            continue  # not as Wakeline writes it: the <trk> stays one track
        first = len(target)
        # <src>: the members' sensors joined by '+' (a sensor may hold a ':')
        known = sorted(filter(None, (sources[k] if k < len(sources) else "").split("+")), key=len)
        for lab in labels:
            s = next((c for c in reversed(known) if lab.startswith(c + ":")), None)
            s, b = (s, lab[len(s) + 1 :]) if s else lab.split(":", 1)
            sensor.append(s)
            batch.append(b)
            target.append(names[k])
        new_index[mine] = first + np.searchsorted(segs, segment[mine])
        target[k] = names[k]
    return target, sensor, batch, new_index


_REASONS = (
    "",
    "no readable lat/lon",
    "lat beyond ±90° or lon beyond ±180°",
    "no <time>",
    "unparsable <time>",
)


def _speed_course(rows: dict, good: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict]:
    """The points' speed (knots, from m/s) and course (degrees) checked as a delimited
    file's are (review h231: a GPX's negative speed or course of -10 or 370 came in as
    read): a full circle is north (360 -> 0); a speed negative or infinite and a course
    outside [0, 360) are blanked, the point kept; the blanked counted on the points kept
    (``values_blanked``, the delimited reader's labels)."""
    with np.errstate(invalid="ignore"):
        speed = _numbers(rows["speed"]) / geo.KN_MS
        course = _numbers(rows["course"])
        course = np.where(course == 360.0, 0.0, course)
        bad_speed = np.isinf(speed) | (speed < 0)
        bad_course = np.isinf(course) | (course < 0) | (course >= 360.0)
    blanked = {
        "speed negative or infinite": int((bad_speed & good).sum()),
        "course outside [0, 360)": int((bad_course & good).sum()),
    }
    speed = np.where(bad_speed, np.nan, speed)
    course = np.where(bad_course, np.nan, course)
    return speed, course, {k: v for k, v in blanked.items() if v}


def read_gpx(
    sn: Sniff, sensor: str = "S1", progress: Progress | None = None, timing: dict | None = None
):
    """Read the tracks of a GPX file into the canonical point table (an ``ImportResult``)."""
    from wakeline.core.io.reader import (
        ImportResult,
        points_summary,
        quarantine_table,
        times_of_values,
    )

    progress = progress or null_progress
    with open_data(sn.path, sn.compression) as fh:
        rows, tracks, (sources, kinds, descs), counts, creator, broken = _expat_parse(fh)
    progress(0.8, "parsed")

    n = len(rows["line"])
    lat = _numbers(rows["lat"])
    lon = _numbers(rows["lon"])
    time_text = _texts(rows["time"])
    times, _ = times_of_values(time_text, timing)
    # the first reason that holds, as a code into _REASONS (0: none, a point)
    no_time = pc.fill_null(pc.equal(time_text, ""), True).to_numpy(zero_copy_only=False)
    no_position = ~np.isfinite(lat) | ~np.isfinite(lon)
    bad_range = ~no_position & ((np.abs(lat) > 90) | (np.abs(lon) > 180))
    code = np.select(
        [no_position, bad_range, no_time, times.isna().to_numpy()], [1, 2, 3, 4], default=0
    )
    good = code == 0

    # Track names: unique, "sensor:batch" back to its parts in Wakeline's own files.
    names, seen, renamed = [], {}, 0
    for k, name in enumerate(tracks):
        name = name or f"track {k + 1}"
        if name in seen:
            seen[name] += 1
            name, renamed = f"{name} ({seen[name]})", renamed + 1
        else:
            seen[name] = 1
        names.append(name)
    ours = creator.lower().startswith("wakeline")
    track_sensor = [sensor] * len(names)
    track_batch = list(names)
    if ours:  # Wakeline's own: the sensor in <src> (since session 24), the name sensor:batch
        for k, name in enumerate(names):
            src = sources[k] if k < len(sources) else ""
            if src:
                track_sensor[k] = src
                track_batch[k] = name.removeprefix(src + ":")
            elif ":" in name:
                track_sensor[k], track_batch[k] = name.split(":", 1)
    index = np.asarray(rows["track"], dtype="int64")
    target = None
    if ours:  # Wakeline's targets: a <trk> per target, a <trkseg> per member (D-export-2)
        target, track_sensor, track_batch, index = _targets_of(
            rows, names, (sources, kinds, descs), track_sensor, track_batch, index
        )
    speed, course, blanked = _speed_course(rows, good)
    points = pd.DataFrame(
        {
            "sensor": pd.Series(np.asarray(track_sensor, dtype=object)[index[good]], dtype="str")
            if n
            else pd.Series([], dtype="str"),
            "batch": pd.Series(np.asarray(track_batch, dtype=object)[index[good]], dtype="str")
            if n
            else pd.Series([], dtype="str"),
            "time": times[good].reset_index(drop=True).dt.as_unit("ns")
            if n
            else pd.Series([], dtype="datetime64[ns, UTC]"),
            "lon": lon[good],
            "lat": lat[good],
            "speed": speed[good],
            "course": course[good],
        }
    )
    if target is not None:
        points["target"] = pd.Series(np.asarray(target, dtype=object)[index[good]], dtype="str")

    q_line = np.asarray(rows["line"], dtype="int64")[~good]
    q_reason = list(np.asarray(_REASONS, dtype=object)[code[~good]])
    later = []
    if broken is not None:
        from_line = broken[0]
        texts = _line_texts(sn, set(q_line.tolist()), from_line)
        later = sorted(k for k in texts if k >= from_line)
    else:
        texts = _line_texts(sn, set(q_line.tolist()), None)
    lines = q_line.tolist() + later
    reasons = q_reason + [
        f"not well-formed XML ({broken[1]}): not read from line {broken[0]} on" for _ in later
    ]
    quarantine = quarantine_table(lines, reasons, [texts.get(int(k), "") for k in lines])

    warnings = []
    if counts["waypoints"] or counts["route_points"]:
        warnings.append(
            f"{counts['waypoints']:,} waypoint(s) and {counts['route_points']:,} route point(s) are "
            "plans, not tracks: not imported"
        )
    if renamed:
        warnings.append(
            f"{renamed:,} track(s) share a name with an earlier one: numbered (2), (3)... so "
            "that each stays its own track"
        )
    from wakeline.core.io.geojson import targets_note

    warnings += targets_note(points)
    if broken is not None:
        warnings.append(
            f"the file stops being well-formed XML ({broken[1]}): the "
            f"{n:,} track points before it are read, the {len(later):,} lines from line "
            f"{broken[0]} on are quarantined"
        )
    by_reason = quarantine["reason"].value_counts().to_dict() if len(quarantine) else {}
    progress(1.0, "imported")
    report = {
        "input": str(sn.path),
        "format": "gpx",
        "format_label": "GPX tracks",
        "encoding": sn.encoding,
        "compression": sn.compression,
        "columns": {},
        "creator": creator,
        "rows_read": n + len(later),
        "rows_imported": len(points),
        "rows_quarantined": len(quarantine),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": 0,
        "values_blanked": blanked,
        "gpx_tracks": len(tracks),
        "gpx_segments": counts["segments"],
        "waypoints": counts["waypoints"],
        "route_points": counts["route_points"],
        **points_summary(points),
        "warnings": warnings,
    }
    layout = {"format": "gpx", "encoding": sn.encoding, "compression": sn.compression}
    return ImportResult(points, quarantine, report, layout)

"""GPX tracks (GPX 1.0 and 1.1: OpenCPN's track export, chart plotters, phones, our own
``export --format gpx``).

Every ``<trk>`` is one track: its ``<name>`` is the batch (``track N`` when it has none;
a name that two tracks share gets `` (2)``, `` (3)``... on the later ones, with a warning).
A GPX written by Wakeline names a track ``sensor:batch``: it is read back as that sensor
and batch. Each ``<trkpt>`` is a point (its ``<time>``, ISO 8601, UTC unless it says
otherwise; GPX 1.0's ``<speed>`` in m/s becomes knots, its ``<course>`` degrees). Track
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

import re
from xml.parsers import expat

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from wakeline.core import geo
from wakeline.core.io.compressed import open_data
from wakeline.core.io.sniff import Sniff
from wakeline.core.progress import Progress, null_progress


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


def _expat_parse(data: bytes):
    """The track points of a GPX document by expat's callbacks (one per element): the
    reading of record, for any file :func:`_fast_parse` does not vouch for. Returns
    ``(rows, tracks, sources, counts, creator, broken)``: ``rows`` lists per field (one
    item per ``<trkpt>``: its track's index, line, lat, lon, time, speed, course texts),
    each ``<trk>``'s name and ``<src>``, the waypoint/route point/segment counts, the
    ``creator`` and, for a file that stops being well-formed, ``(line, complaint)``."""
    parser = expat.ParserCreate(encoding=None)
    parser.buffer_text = True
    rows: dict[str, list] = {
        k: [] for k in ("track", "line", "lat", "lon", "time", "speed", "course")
    }
    tracks: list[str] = []  # each <trk>'s name ("" when it has none)
    sources: list[str] = []  # each <trk>'s <src> ("" when it has none)
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
        elif tag == "trkseg":
            counts["segments"] += 1
        elif tag == "trkpt":
            point = {
                "track": max(len(tracks) - 1, 0),
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
        elif tag == "name" and parent == "trk" and tracks and not tracks[-1]:
            tracks[-1] = value
        elif tag == "src" and parent == "trk" and sources:
            sources[-1] = value
        elif tag == "trkpt" and point is not None:
            if not tracks:  # a <trkpt> outside any <trk>: one track of its own
                tracks.append("")
                sources.append("")
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
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        what = f"{expat.errors.messages[exc.code]} at line {exc.lineno}, column {exc.offset}"
        broken = (exc.lineno, what)
        if point is not None:  # a track point the break cut: quarantined from its line
            broken = (min(exc.lineno, int(point["line"])), what)
    return rows, tracks, sources, counts, creator["text"], broken


_DECLARATION = re.compile(rb"^(?:\xef\xbb\xbf)?<\?xml\b[^>]*\?>")
_ENCODING = re.compile(rb"""\bencoding\s*=\s*["']([^"']*)["']""")
_UTF8 = (b"utf-8", b"utf8", b"us-ascii", b"ascii")
_PREFIXED_TRK = re.compile(rb"<[A-Za-z_][\w.-]*:trk(?:pt)?[\s/>]")
#: A <trkpt>'s attributes as the fast reading takes them: names, double-quoted values
#: without '=', '<' or '&' (so that no attribute name can be found inside a value, and no
#: entity needs decoding).
_ATTRIBUTES = r'^(?:\s+[A-Za-z_][\w.:-]*\s*=\s*"[^"=<&]*")*\s*$'
#: The attributes of nearly every <trkpt> written: lat then lon, nothing else.
_LAT_LON = r'^\s+lat\s*=\s*"(?P<lat>[^"]*)"\s+lon\s*=\s*"(?P<lon>[^"]*)"\s*$'
#: An element expat counts wherever it stands, by its local name (a track, a segment,
#: a waypoint, a route point, the document's creator), as it may stand in a point.
_DOCUMENT_TAG = r"<(?:[A-Za-z_][\w.-]*:)?(?:gpx|trk|trkseg|wpt|rtept)[\s/>]"
#: A child with a namespace prefix that expat reads by its local name (<g:time>).
_PREFIXED_FIELD = r"<[A-Za-z_][\w.-]*:(?:time|speed|course)[\s/>]"
#: A <trkpt>'s content as the fast reading takes it: children that hold text only.
_FLAT = r"^(?:\s*<[A-Za-z_][\w.:-]*(?:\s[^<>]*)?(?:/>|>[^<]*</[A-Za-z_][\w.:-]*\s*>))*\s*$"


def _all(mask) -> bool:
    return bool(pc.all(pc.fill_null(mask, False)).as_py()) if len(mask) else True


def _any(mask) -> bool:
    return bool(pc.any(pc.fill_null(mask, False)).as_py()) if len(mask) else False


def _attribute(parts: pa.Array, name: str) -> pa.Array:
    """The value of attribute ``name`` of each ``<trkpt>`` (null where it has none), from
    its attributes split at '"' (``[' lat=', value, ' lon=', value, '']``)."""
    flat = pc.list_flatten(parts)
    parent = pc.list_parent_indices(parts).to_numpy()
    offsets = parts.offsets.to_numpy()
    position = np.arange(len(flat)) - (offsets[parent] - offsets[0])
    named = pc.equal(pc.utf8_trim(flat, " \t\r\n="), name).to_numpy(zero_copy_only=False)
    hit = np.flatnonzero((position % 2 == 0) & named)
    take = np.full(len(parts), -1, dtype="int64")
    take[parent[hit]] = hit + 1
    return _normalised(flat.take(pa.array(take, mask=take < 0)))


def _normalised(values: pa.Array) -> pa.Array:
    """Attribute values as expat gives them: each line end or tab a space."""
    if _any(pc.match_substring_regex(values, r"[\t\n\r]")):
        values = pc.replace_substring_regex(values, r"\r\n|[\t\n\r]", " ")
    return values


def _child(body: pa.Array, tag: str) -> pa.Array | None:
    """The stripped text of each ``<trkpt>``'s ``<tag>`` child (null where it has none),
    or None when a child is one the fast reading does not take (twice, with attributes,
    with an entity or other than ASCII)."""
    if not _any(pc.match_substring(body, f"<{tag}")):
        return pa.nulls(len(body), pa.large_string())
    if _any(pc.greater(pc.count_substring_regex(body, rf"<{tag}[\s/>]"), 1)):
        return None
    if _any(pc.match_substring_regex(body, rf"<{tag}\s+[^\s/>]")):
        return None
    found = pc.extract_regex(body, rf"<{tag}\s*(?:/>|>(?P<v>[^<]*)</{tag}\s*>)")
    values = pc.if_else(
        pc.is_valid(found), found.field("v"), pa.scalar(None, found.type.field(0).type)
    )
    if _any(pc.match_substring(values, "&")) or not _all(
        pc.or_kleene(pc.string_is_ascii(values), pc.is_null(values))
    ):
        return None
    if _any(pc.match_substring(values, "\r")):
        values = pc.replace_substring(values, "\r\n", "\n")
    return pc.ascii_trim_whitespace(values)


def _halves(pairs: pa.Array) -> tuple[pa.Array, pa.Array]:
    """The first and second items of lists of two (a take each: ``list_element`` copies
    value by value, several times slower)."""
    flat = pc.list_flatten(pairs)
    return flat.take(np.arange(0, len(flat), 2)), flat.take(np.arange(1, len(flat), 2))


def _concatenated(texts: pa.Array) -> bytes:
    """The values of a large string array without nulls, one after the other."""
    texts = texts.cast(pa.large_string())
    _, offsets, values = texts.buffers()
    bounds = np.frombuffer(offsets, dtype="int64")[texts.offset : texts.offset + len(texts) + 1]
    return bytes(memoryview(values)[bounds[0] : bounds[-1]]) if len(texts) else b""


def _fast_parse(data: bytes):
    """What :func:`_expat_parse` returns, for a well-formed UTF-8 GPX whose track points
    are plain (double-quoted attributes, children that hold text only, no entity, comment
    or CDATA, no namespace prefix on trk/trkpt): the track points are cut out of the text
    by Arrow's string kernels (one call per field for each :data:`FAST_CHUNK_BYTES` of
    the file, :func:`_fast_chunk`), and only the rest of the document (its tracks, names,
    waypoints) goes through expat's callbacks. None for any other file (read by
    :func:`_expat_parse`, which gives the same table)."""
    declaration = _DECLARATION.match(data)
    if declaration is not None:
        encoding = _ENCODING.search(declaration.group(0))
        if encoding is not None and encoding.group(1).lower() not in _UTF8:
            return None
    body_from = declaration.end() if declaration is not None else 0
    if (
        b"\x00" in data
        or data.find(b"<?", body_from) >= 0
        or b"<!" in data
        or data.count(b"\r") != data.count(b"\r\n")
        or _PREFIXED_TRK.search(data) is not None
    ):
        return None
    try:  # well-formed (tags that match, UTF-8, no duplicate attribute...): no callbacks
        expat.ParserCreate(encoding=None).Parse(data, True)
    except expat.ExpatError:
        return None

    buffer = pa.py_buffer(data)
    chunks, start = [], 0
    while start < len(data):  # cut before a <trkpt> every FAST_CHUNK_BYTES or so
        cut = data.find(b"<trkpt", start + FAST_CHUNK_BYTES)
        stop = len(data) if cut < 0 else cut
        part = _fast_chunk(buffer.slice(start, stop - start))
        if part is None:
            return None
        chunks.append(part)
        start = stop
    if not sum(c["n"] for c in chunks):
        return None
    # lines, tracks and the rest of the document, chunk after chunk
    lines, track, skeleton = [], [], [chunks[0]["head"]]
    base, opened = 0, chunks[0]["head_trk"]
    for c in chunks:
        lines.append(1 + base + np.cumsum(c["newlines"][: c["n"]]))
        base += int(c["newlines"].sum())
        if c["n"]:
            before = opened + np.cumsum(c["rest_trk"])
            track.append(np.concatenate([[opened], before[:-1]]) - 1)
            opened = int(before[-1])
        skeleton.append(c["after"])
    track_all = np.concatenate(track)
    if track_all.min() < 0:
        return None  # a <trkpt> outside any <trk>
    # The rest of the document, without its track points: expat's callbacks (few).
    rows0, tracks, sources, counts, creator, broken = _expat_parse(b"".join(skeleton))
    if broken is not None or rows0["line"] or len(tracks) != opened:
        return None
    rows = {"track": track_all, "line": np.concatenate(lines)}
    for key in ("lat", "lon", "time", "speed", "course"):
        rows[key] = pa.concat_arrays([c[key].cast(pa.large_string()) for c in chunks])
    return rows, tracks, sources, counts, creator, None


#: The bytes of a GPX the fast reading cuts its track points out of at a time (a cut
#: falls before a <trkpt>): bounds the memory of the Arrow arrays (about five times this).
FAST_CHUNK_BYTES = 8 << 20
_TRK = r"<trk[\s/>]"


def _fast_chunk(text: pa.Buffer) -> dict | None:
    """:func:`_fast_parse` on a part of the document that starts at its beginning or at a
    ``<trkpt``: each track point's fields (Arrow string arrays), the line ends before
    each (per piece), the ``<trk>`` starts after each, and the text around the points
    (``head``: before the first, ``after``: the rest, points cut out). None when a point
    is not one the fast reading takes."""
    document = pa.LargeStringArray.from_buffers(
        1, pa.py_buffer(np.array([0, text.size], dtype="int64")), text
    )
    pieces = pc.list_flatten(pc.split_pattern(document, "<trkpt"))
    del document
    n = len(pieces) - 1
    newlines = pc.count_substring(pieces, "\n").to_numpy()
    head = pieces[0].as_py().encode("utf-8")
    out = {
        "n": n,
        "newlines": newlines,
        "head": head,
        "head_trk": len(re.findall(_TRK.encode(), head)),
    }
    if n == 0:
        empty = pa.array([], pa.large_string())
        fields = dict.fromkeys(("lat", "lon", "time", "speed", "course"), empty)
        return {**out, **fields, "rest_trk": np.zeros(0, dtype="int64"), "after": b""}
    tail = pieces.slice(1)
    del pieces
    closed = pc.split_pattern(tail, "</trkpt", max_splits=1)
    del tail
    if not _all(pc.equal(pc.list_value_length(closed), 2)):
        return None  # a self-closed <trkpt/>, or one that holds another
    block, rest = _halves(closed)
    del closed
    if not _all(pc.match_substring_regex(rest, r"^\s*>")):
        return None
    tag = pc.split_pattern(block, ">", max_splits=1)
    del block
    if not _all(pc.equal(pc.list_value_length(tag), 2)):
        return None
    attrs, body = _halves(tag)
    del tag
    if not _all(pc.match_substring_regex(attrs, _ATTRIBUTES)):
        return None
    both = pc.extract_regex(attrs, _LAT_LON)  # the usual: lat="…" lon="…", nothing else
    if both.null_count == 0:
        lat, lon = _normalised(both.field("lat")), _normalised(both.field("lon"))
    else:
        parts = pc.split_pattern(attrs, '"')
        lat, lon = _attribute(parts, "lat"), _attribute(parts, "lon")
        del parts
    del attrs, both
    if _any(pc.match_substring_regex(body, _DOCUMENT_TAG)):
        return None  # a <trk>, <wpt>... in a point (its extensions): expat counts it
    if _any(pc.match_substring(body, "<extensions")):
        body = pc.replace_substring_regex(
            body, r"(?s)<extensions(?:\s[^<>]*)?>.*?</extensions\s*>", ""
        )
    if not _all(pc.match_substring_regex(body, _FLAT)) or _any(
        pc.match_substring_regex(body, _PREFIXED_FIELD)
    ):
        return None
    children = {tag: _child(body, tag) for tag in ("time", "speed", "course")}
    del body
    if any(v is None for v in children.values()):
        return None
    rest_trk = pc.count_substring_regex(rest, _TRK).to_numpy()
    after = pc.utf8_slice_codeunits(pc.ascii_ltrim(rest, " \t\r\n"), 1)  # each '>' of </trkpt>
    del rest
    return {
        **out,
        "lat": lat,
        "lon": lon,
        **children,
        "rest_trk": rest_trk,
        "after": _concatenated(after),
    }


_REASONS = (
    "",
    "no readable lat/lon",
    "lat beyond ±90° or lon beyond ±180°",
    "no <time>",
    "unparsable <time>",
)


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
        data = fh.read()
    fast = _fast_parse(data)
    if fast is not None:
        rows, tracks, sources, counts, creator, broken = fast
    else:  # anything the fast reading does not vouch for: expat's callbacks, per element
        rows, tracks, sources, counts, creator, broken = _expat_parse(data)
    del data
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
    speed = _numbers(rows["speed"]) / geo.KN_MS
    course = _numbers(rows["course"])
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
        "gpx_tracks": len(tracks),
        "gpx_segments": counts["segments"],
        "waypoints": counts["waypoints"],
        "route_points": counts["route_points"],
        **points_summary(points),
        "warnings": warnings,
    }
    layout = {"format": "gpx", "encoding": sn.encoding, "compression": sn.compression}
    return ImportResult(points, quarantine, report, layout)

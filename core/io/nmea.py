"""Raw AIS NMEA logs (``!AIVDM`` / ``!AIVDO`` sentences, or the same from a base or shore
station: ``!BSVDM``, ``!ABVDM``...) decoded with pyais.

Each line holds one sentence, optionally after a receive time (unix seconds or
milliseconds, or ISO 8601 text, then a blank, comma, semicolon or tab) or after an
IEC 61162-450 tag block (``\\s:station,c:1671620143*hh\\``, whose ``c:`` is the unix time).
Position reports (types 1, 2, 3, 18, 19, 27) become points; static data (types 5 and 24)
name the ships (an extra ``name`` column); multi-part messages are assembled from their
fragments (sequence id and channel).

Nothing is lost silently: a line that is not a sentence, a bad checksum, an undecodable
payload, a fragment whose message never completes, a position report without a position
or without a receive time each become a quarantined row with its line number. Other
message types (base stations, aids to navigation...) are counted in the report.

Decoding is one pyais call per sentence (pyais decodes message by message); the table is
built once at the end.
"""

import io
import re
from collections import Counter

import numpy as np
import pandas as pd
from pyais import NMEAMessage
from pyais.exceptions import AISBaseException

from wakeline.core.errors import InputError
from wakeline.core.io.compressed import open_data
from wakeline.core.io.decoding import lines_codec
from wakeline.core.io.sniff import NMEA_SENTENCE, Sniff
from wakeline.core.progress import Progress, null_progress

POSITION_TYPES = frozenset((1, 2, 3, 18, 19, 27))
STATIC_TYPES = frozenset((5, 24))
_SENTENCE = NMEA_SENTENCE
_TAG_BLOCK = re.compile(r"^\\([^\\]*)\\")
_TAG_TIME = re.compile(r"(?:^|,)c:(\d+(?:\.\d+)?)")
_TAG_SOURCE = re.compile(r"(?:^|,)s:([^,*\\]+)")


def tag_source(line: str) -> str:
    """The source (``s:``, the receiving station or sensor) of a line's IEC 61162-450 tag
    block, "" when the line has none (D-import-13: the log's own name for its sensor)."""
    tag = _TAG_BLOCK.match(line)
    m = _TAG_SOURCE.search(tag.group(1)) if tag else None
    return m.group(1).strip() if m else ""


def _receive_time(prefix: str) -> float | None:
    """Unix seconds from the text before a sentence (a number or ISO text), or None."""
    text = prefix.strip().strip(",;\t ").strip()
    if not text:
        return None
    try:
        value = float(text)
    except ValueError:
        stamp = pd.to_datetime(text, errors="coerce", utc=True, format="ISO8601")
        return None if pd.isna(stamp) else stamp.value / 1e9
    if not np.isfinite(value):
        return None
    return value / 1000.0 if value > 1e11 else value


def _split(line: str) -> tuple[str | None, float | None, str]:
    """(sentence, unix time, problem) of one log line."""
    tag = _TAG_BLOCK.match(line)
    t = None
    if tag:
        m = _TAG_TIME.search(tag.group(1))
        if m:
            t = float(m.group(1))
            t = t / 1000.0 if t > 1e11 else t
        line = line[tag.end() :]
    m = _SENTENCE.search(line)
    if m is None:
        return None, None, "not an AIS sentence (!AIVDM, !AIVDO or another AIS talker's VDM/VDO)"
    if t is None:
        t = _receive_time(line[: m.start()])
    return line[m.start() :].strip(), t, ""


def _codec(sn: Sniff) -> str:
    """The codec the log's lines are decoded with: as every reader decodes (a line not
    valid UTF-8 in the fallback: wakeline.core.io.decoding)."""
    return lines_codec(sn.encoding, sn.encoding_given)


def _sensors(sources: list[str], sensor: str) -> np.ndarray:
    """Each point's sensor: ``sensor`` when one was given (not the default ``S1``), else
    its line's tag block source where there is one, ``S1`` where not."""
    out = np.asarray(sources, dtype=object)
    if sensor != "S1" or not len(out):
        return np.full(len(out), sensor, dtype=object)
    return np.where(out != "", out, sensor)


def read_nmea(sn: Sniff, sensor: str = "S1", progress: Progress | None = None):
    """Read a raw AIS NMEA log into the canonical point table (an ``ImportResult``). The
    sensor is ``sensor`` when given, else the tag block's source (``s:``) of each line that
    has one, else ``S1``."""
    from wakeline.core.io.reader import ImportResult, points_summary, quarantine_table

    progress = progress or null_progress
    q_lines: list[int] = []
    q_reasons: list[str] = []
    q_texts: list[str] = []
    rows: dict[str, list] = {k: [] for k in ("batch", "t", "lon", "lat", "speed", "course")}
    sources: list[str] = []  # each point's tag block s:, "" when its line has none
    names: dict[str, str] = {}
    pending: dict[tuple, list] = {}  # (seq id, channel, count) -> [(line, text, message)]
    ignored: Counter = Counter()
    counts = Counter()
    blank = 0

    def bad(number: int, reason: str, text: str) -> None:
        q_lines.append(number)
        q_reasons.append(reason)
        q_texts.append(text)

    def use(message: NMEAMessage, number: int, text: str, t: float | None) -> None:
        try:
            decoded = message.decode()
        except (AISBaseException, ValueError, IndexError) as exc:
            bad(number, f"undecodable AIS message ({type(exc).__name__})", text)
            return
        kind = int(decoded.msg_type)
        mmsi = str(decoded.mmsi)
        if kind in STATIC_TYPES:
            name = getattr(decoded, "shipname", None)
            if name:
                names[mmsi] = str(name).strip("@ ").strip()
            counts["static_messages"] += 1
            return
        if kind not in POSITION_TYPES:
            ignored[str(kind)] += 1
            return
        lon, lat = getattr(decoded, "lon", None), getattr(decoded, "lat", None)
        if lon is None or lat is None or abs(lon) > 180 or abs(lat) > 90:
            bad(number, "position not available (lon 181 / lat 91)", text)
            return
        if t is None:
            bad(number, "no receive time (no leading time stamp or tag block c:)", text)
            return
        speed = getattr(decoded, "speed", None)
        course = getattr(decoded, "course", None)
        rows["batch"].append(mmsi)
        sources.append(tag_source(text))
        rows["t"].append(t)
        rows["lon"].append(float(lon))
        rows["lat"].append(float(lat))
        rows["speed"].append(np.nan if speed is None or speed >= 102.3 else float(speed))
        rows["course"].append(np.nan if course is None or course >= 360 else float(course))

    progress(0.0, f"reading {sn.path.name} (AIS NMEA)")
    with (
        open_data(sn.path, sn.compression) as raw,
        io.TextIOWrapper(raw, encoding=_codec(sn), errors="replace", newline=None) as fh,
    ):
        for number, raw in enumerate(fh, start=1):
            line = raw.rstrip("\r\n").removeprefix("\ufeff")
            if not line.strip():
                blank += 1
                continue
            counts["lines"] += 1
            sentence, t, problem = _split(line)
            if sentence is None:
                bad(number, problem, line)
                continue
            try:
                message = NMEAMessage.from_string(sentence)
            except (AISBaseException, ValueError, IndexError):
                bad(number, "malformed NMEA sentence", line)
                continue
            if not message.is_valid:
                bad(number, "bad NMEA checksum", line)
                continue
            if message.frag_cnt <= 1:
                use(message, number, line, t)
                continue
            key = (message.seq_id, message.channel, message.frag_cnt)
            parts = pending.setdefault(key, [])
            if message.frag_num == 1 and parts:  # a new message reuses the id: drop the old
                for n_old, text_old, _, _ in parts:
                    bad(n_old, "incomplete multi-part message", text_old)
                parts.clear()
            parts.append((number, line, message, t))
            if len(parts) == message.frag_cnt:
                del pending[key]
                ordered = sorted(parts, key=lambda p: p[2].frag_num)
                if [p[2].frag_num for p in ordered] != list(range(1, message.frag_cnt + 1)):
                    for n_old, text_old, _, _ in parts:
                        bad(n_old, "multi-part message with missing or repeated parts", text_old)
                    continue
                try:
                    whole = NMEAMessage.assemble_from_iterable([p[2] for p in ordered])
                except (AISBaseException, ValueError, IndexError):
                    for n_old, text_old, _, _ in parts:
                        bad(n_old, "multi-part message cannot be assembled", text_old)
                    continue
                counts["fragments_assembled"] += len(parts) - 1
                first_t = next((p[3] for p in ordered if p[3] is not None), None)
                use(whole, ordered[0][0], ordered[0][1], first_t)
    for parts in pending.values():
        for n_old, text_old, _, _ in parts:
            bad(n_old, "incomplete multi-part message", text_old)

    if not rows["batch"] and not q_lines and not counts["static_messages"]:
        raise InputError(f"{sn.path}: no AIS sentences found")
    seconds = np.asarray(rows["t"], dtype="float64")
    points = pd.DataFrame(
        {
            "sensor": pd.Series(_sensors(sources, sensor), dtype="str"),
            "batch": pd.Series(rows["batch"], dtype="str"),
            "time": pd.to_datetime(np.round(seconds * 1e9).astype("int64"), utc=True),
            "lon": np.asarray(rows["lon"], dtype="float64"),
            "lat": np.asarray(rows["lat"], dtype="float64"),
            "speed": np.asarray(rows["speed"], dtype="float64"),
            "course": np.asarray(rows["course"], dtype="float64"),
        }
    )
    points["time"] = points["time"].dt.as_unit("ns")
    if names:
        points["name"] = points["batch"].map(names).fillna("").astype("str")
    quarantine = quarantine_table(q_lines, q_reasons, q_texts)
    progress(1.0, "imported")
    by_reason = quarantine["reason"].value_counts().to_dict() if len(quarantine) else {}
    report = {
        "input": str(sn.path),
        "format": "ais-nmea",
        "format_label": "Raw AIS NMEA log (!AIVDM/!AIVDO)",
        "encoding": sn.encoding,
        "compression": sn.compression,
        "columns": {},
        "rows_read": int(counts["lines"]),
        "rows_imported": len(points),
        "rows_quarantined": len(quarantine),
        "quarantine_reasons": {str(k): int(v) for k, v in by_reason.items()},
        "blank_lines": blank,
        "static_messages": int(counts["static_messages"]),
        "fragments_assembled": int(counts["fragments_assembled"]),
        "messages_ignored_by_type": dict(ignored),
        "ship_names": len(names),
        **points_summary(points),
        "warnings": [],
    }
    layout = {"format": "ais-nmea", "encoding": sn.encoding, "compression": sn.compression}
    return ImportResult(points, quarantine, report, layout)

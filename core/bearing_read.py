"""Reading a bearing file (seed 002's input, SPEC §4): ``batch, time, bearing`` and the
observer's positions, by header names (:data:`BEARING_NAMES`), a known layout
(:data:`BEARING_LAYOUTS`: the Autoferry camera detections) or ``--map field=column``
(:data:`BEARING_FIELDS`, the track reader's syntax and parser). The observer may be in
lon/lat degrees or in east/north metres on a local plane about ``--origin LAT,LON``
(turned into lon/lat by the track reader's projection, :func:`~wakeline.core.geo.from_local`).

Every data line is a bearing or a quarantine row (line, reason, text). Lines that are
legitimately not bearings (another sensor's position plot, an empty scan of a known
layout) are quarantine rows whose reason starts with :data:`NOT_A_BEARING`: the summary
counts them apart from errors. Several *different* bearings of one series at one time (a
camera frame holding several targets or clutter) are kept: they are data, not errors;
the detector reports such a series as not one target's sequence (SPEC §4's input) and
names ``--map target=COLUMN`` that splits it. Only a line repeated as is (same series,
time and bearing) is quarantined.
"""

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError

#: The fields ``--map`` takes for a bearing file. ``target`` splits a series by a
#: target/track id column (the series is then ``batch/target``); ``batch`` may join
#: several columns with ``+`` (``--map batch=scenario+sensor``).
BEARING_FIELDS = (
    "batch",
    "target",
    "time",
    "bearing",
    "obs_lon",
    "obs_lat",
    "obs_east",
    "obs_north",
)

#: Header names a bearing file may use for each field (lower case; a unit in brackets is
#: ignored; a bearing whose header says radians, ``bearing_rad``, is in radians).
BEARING_NAMES = {
    "batch": ("batch", "批号", "目标号", "航迹号", "目标", "target", "track", "id", "mmsi"),
    "time": ("time", "时间", "时刻", "timestamp", "datetime", "utc"),
    "bearing": ("bearing", "方位", "方位角", "azimuth", "brg", "bearing_deg", "bearing_rad"),
    "obs_lon": ("obs_lon", "observer_lon", "own_lon", "本舰经度", "观测点经度"),
    "obs_lat": ("obs_lat", "observer_lat", "own_lat", "本舰纬度", "观测点纬度"),
    "obs_east": ("obs_east", "observer_east", "own_east", "obs_x", "own_x"),
    "obs_north": ("obs_north", "observer_north", "own_north", "obs_y", "own_y"),
}

#: Words in a header that make it a likely column for a missing field (the suggestion in
#: the missing-column message; never used to read a file).
_HINTS = {
    "batch": (
        "batch",
        "target",
        "track",
        "series",
        "scenario",
        "run",
        "sensor",
        "mmsi",
        "id",
        "name",
        "批",
        "目标",
    ),  # fmt: skip
    "time": ("time", "date", "utc", "stamp", "时"),
    "bearing": ("bearing", "brg", "azim", "方位", "angle", "az"),
}

#: The start of the reason of a line that is no bearing but no error either.
NOT_A_BEARING = "not a bearing:"


@dataclass(frozen=True)
class BearingLayout:
    """A bearing file layout known by its header (every name in ``headers``)."""

    label: str
    headers: frozenset[str]
    #: field → column (``batch`` may be several columns, joined with ``/``)
    columns: dict[str, str | tuple[str, ...]]
    #: (lat, lon) of the plane the observer's metres are measured from
    origin: tuple[float, float] | None = None
    #: columns of another sensor's position plot: a row with them and no bearing is one
    plots: tuple[str, ...] = ()
    source: str = ""


#: Known bearing layouts, tried in order.
BEARING_LAYOUTS = (
    BearingLayout(
        label="Autoferry detections (camera bearings; the ferry in metres from Piren)",
        headers=frozenset(
            {"scenario", "scan", "time", "sensor", "own_north", "own_east", "k", "bearing_rad"}
        ),
        # one series per scenario and camera (eo, ir); bearing_rad: atan2(east, north),
        # north 0, east +pi/2 (SOURCE.md, as real_sets.autoferry_bearings reads it)
        columns={
            "batch": ("scenario", "sensor"),
            "time": "time",
            "bearing": "bearing_rad",
            "obs_east": "own_east",
            "obs_north": "own_north",
        },
        origin=(63.4389029083, 10.39908278),  # the set's "Piren" NED origin (SOURCE.md)
        plots=("meas_north", "meas_east"),
        source="shared/data/real/autoferry-fusion/SOURCE.md",
    ),
)


@dataclass
class BearingRead:
    """A bearing file read: the bearings, the quarantine (line, reason, text) and what
    happened (:func:`summary_lines`)."""

    bearings: pd.DataFrame
    quarantine: pd.DataFrame
    report: dict = field(default_factory=dict)


def _plain(name) -> str:
    return re.sub(r"[(（\[].*?[)）\]]", "", str(name)).strip().lower()


def _bearing_columns(columns) -> dict[str, str]:
    """Field → the file's column, by :data:`BEARING_NAMES` (first match wins; a unit in
    brackets, as in ``方位(度)``, is ignored)."""
    plain = {c: _plain(c) for c in columns}
    out: dict[str, str] = {}
    for name, options in BEARING_NAMES.items():
        for option in options:
            hit = [c for c in columns if plain[c] == option]
            if hit and hit[0] not in out.values():
                out[name] = hit[0]
                break
    return out


def known_layout(columns) -> BearingLayout | None:
    """The first :data:`BEARING_LAYOUTS` entry whose headers the file has."""
    have = {_plain(c) for c in columns}
    return next((lay for lay in BEARING_LAYOUTS if lay.headers <= have), None)


def suggest_mapping(columns, found: dict, missing: list[str]) -> str:
    """``--map field=column`` flags for the missing fields, by the words of the headers
    (:data:`_HINTS`); ``--map field=COLUMN`` where no header suggests one."""
    used = {c for v in found.values() for c in (v if isinstance(v, tuple) else (v,))}
    flags = []
    for f in missing:
        hit = next(
            (c for h in _HINTS[f] for c in columns if c not in used and h in _plain(c)), None
        )
        if hit is not None:
            used.add(hit)
        flags.append(f"--map {f}={hit if hit is not None else 'COLUMN'}")
    return " ".join(flags)


def resolve_bearings(
    columns, mapping: dict[str, str] | list[str] | None = None, origin=None, source: str = ""
) -> dict:
    """Which column holds each field, the layout and the plane's origin: ``{"columns":
    field → column (a tuple for a joined batch), "layout": BearingLayout | None,
    "origin": (lat, lon) | None, "notes": [...]}``. Raises :class:`InputError` naming a
    mapped column the file lacks, a required field no column holds (with a suggested
    ``--map``), or metres without an origin."""
    from wakeline.core.io.formats import parse_mapping, parse_origin
    from wakeline.core.io.sniff import listed_headers

    columns = list(columns)
    if not isinstance(mapping, dict):
        mapping = parse_mapping(mapping, BEARING_FIELDS)
    layout = known_layout(columns)
    found: dict[str, str | tuple[str, ...]] = dict(_bearing_columns(columns))
    notes = []
    if layout is not None:
        by_plain = {_plain(c): c for c in columns}
        for f, src in layout.columns.items():
            found[f] = tuple(by_plain[s] for s in src) if isinstance(src, tuple) else by_plain[src]
        notes.append(f"layout: {layout.label}")
    unknown = []
    for f, col in mapping.items():
        if col in columns:
            found[f] = col
        elif "+" in col and all(p.strip() in columns for p in col.split("+")):
            found[f] = tuple(p.strip() for p in col.split("+"))
        else:
            unknown.append(f"{f}={col}")
    if unknown:
        raise InputError(
            f"{source}: mapped column(s) not found: {', '.join(unknown)} (bearings); "
            f"headers found: {listed_headers(tuple(columns))}"
        )
    missing = [f for f in ("batch", "time", "bearing") if f not in found]
    if missing:
        raise InputError(
            f"{source}: missing required column {', '.join(missing)} (bearings); "
            f"headers found: {listed_headers(tuple(columns))}; map columns with --map "
            f"field=column, e.g. {suggest_mapping(columns, found, missing)}"
        )
    given = parse_origin(origin)
    plane = "obs_east" in found and "obs_north" in found
    if {"obs_lon", "obs_lat"} <= set(found):
        if plane:
            notes.append(
                f"observer read from {found['obs_lon']}/{found['obs_lat']} (degrees), not "
                f"from {found['obs_east']}/{found['obs_north']} (metres)"
            )
        for f in ("obs_east", "obs_north"):
            found.pop(f, None)
        if given is not None:
            notes.append("--origin not used: the observer is in lon/lat")
        given = None
    elif plane:
        if given is None and layout is not None and layout.origin is not None:
            given = layout.origin
            notes.append(
                f"observer {found['obs_east']}/{found['obs_north']} in metres from the "
                f"set's origin {given[0]},{given[1]} ({layout.source}); --origin LAT,LON "
                "overrides it"
            )
        elif given is None:
            raise InputError(
                f"{source}: the observer's positions are metres on a local plane (columns "
                f"{found['obs_east']!r} east, {found['obs_north']!r} north), not longitude "
                "and latitude: give the latitude and longitude of the plane's origin (the "
                "frame's zero) with --origin LAT,LON"
            )
        else:
            notes.append(
                f"observer {found['obs_east']}/{found['obs_north']} in metres from "
                f"--origin {given[0]},{given[1]}"
            )
    else:
        for f in ("obs_east", "obs_north", "obs_lon", "obs_lat"):
            found.pop(f, None)
        if given is not None:
            notes.append("--origin not used: the file has no observer east/north")
        given = None
    return {"columns": found, "layout": layout, "origin": given, "notes": notes}


def read_bearings(path, **options) -> pd.DataFrame:
    """Read ``batch,time,bearing[,obs_lon,obs_lat]`` (any delimiter/encoding import reads;
    Chinese and other common header names, :data:`BEARING_NAMES`; ``bearing_rad`` in
    radians): the usable bearings only (``options``: :func:`read_bearing_file`'s).

    Every line is a bearing or a quarantine row (line, reason, text), which
    :func:`read_bearings_checked` returns beside the bearings: a line with the wrong number
    of fields, no batch, an unreadable time, a bearing that is not a finite number or an
    observer position out of range. Raises :class:`InputError` for missing columns or when
    no line is usable."""
    return read_bearing_file(path, **options).bearings


def read_bearings_checked(path, **options) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The bearings of ``path`` and its quarantine (see :func:`read_bearing_file`)."""
    got = read_bearing_file(path, **options)
    return got.bearings, got.quarantine


def read_bearing_file(
    path,
    mapping: dict[str, str] | list[str] | None = None,
    origin=None,
    encoding: str | None = None,
    delimiter: str | None = None,
    skip_rows: int | None = None,
) -> BearingRead:
    """The bearings of ``path``, its quarantine and the report (lines, where they went and
    why; the columns and layout used; series holding several bearings at one time).
    ``mapping``: ``["field=column", …]`` (:data:`BEARING_FIELDS`); ``origin``: ``"LAT,LON"``
    of a plane the observer's east/north metres are measured from."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    from wakeline.core import geo
    from wakeline.core.io.compressed import open_for_arrow
    from wakeline.core.io.formats import angle_unit, length_unit
    from wakeline.core.io.reader import line_ends_in, parse_times, record_lines
    from wakeline.core.io.sniff import sniff

    sn = sniff(path, encoding, delimiter, skip_rows)
    res = resolve_bearings(sn.columns, mapping, origin, str(path))
    names, layout = res["columns"], res["layout"]
    # pyarrow numbers a row as if each record were one line: a quoted cell over a line
    # end shifts every number after it (record_lines makes them the file's lines)
    refused: list[tuple[int, str, str]] = []  # (index in skipped, reason, text)
    skipped: list[int] = []  # every record the reader left out, blank or refused
    skipped_breaks: list[int] = []  # the line ends inside each

    def invalid(row) -> str:
        skipped.append(int(row.number or 0))
        skipped_breaks.append(row.text.count("\n") + row.text.count("\r") - row.text.count("\r\n"))
        if row.text.strip():
            refused.append((len(skipped) - 1, f"{row.actual_columns} fields, not "
                            f"{row.expected_columns}", row.text))  # fmt: skip
        return "skip"

    try:
        with open_for_arrow(path, sn.compression) as stream:
            table = pcsv.read_csv(
                stream,
                read_options=pcsv.ReadOptions(
                    column_names=list(sn.columns),
                    skip_rows=sn.skip_rows,
                    encoding=sn.encoding,
                    use_threads=False,  # line numbers for the refused rows
                ),
                parse_options=pcsv.ParseOptions(
                    delimiter=sn.delimiter, invalid_row_handler=invalid, ignore_empty_lines=False
                ),
                convert_options=pcsv.ConvertOptions(
                    column_types={c: pa.string() for c in sn.columns}, strings_can_be_null=False
                ),
            )
    except (pa.ArrowInvalid, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the bearings: {exc}") from None
    df = table.to_pandas()
    n = len(df)

    def text(f: str) -> pd.Series:
        src = names[f]
        if isinstance(src, tuple):  # several columns: joined, empty when one is
            parts = [df[c].str.strip() for c in src]
            joined = parts[0].str.cat(parts[1:], sep="/")
            return joined.where(~pd.concat(parts, axis=1).eq("").any(axis=1), "")
        return df[src].str.strip()

    # each table row's record: those after the header, less those the reader left out;
    # then every record's first physical line
    taken = set(skipped)
    lines = [
        k for k in range(sn.skip_rows + 1, sn.skip_rows + 1 + n + len(taken)) if k not in taken
    ]
    breaks = np.zeros(n, dtype="int64")
    for col in table.columns:
        breaks += line_ends_in(col)
    physical = record_lines(
        np.concatenate([np.asarray(lines[:n], dtype="int64"), np.asarray(skipped, "int64")]),
        np.concatenate([breaks, np.asarray(skipped_breaks, dtype="int64")]),
    )
    line, refused_line = physical[:n], physical[n:]
    refused = [(int(refused_line[k]), why, row) for k, why, row in refused]
    blank = (
        (df.apply(lambda c: c.str.strip()) == "").all(axis=1).to_numpy() if n else np.zeros(0, bool)
    )
    reason = np.full(n, "", dtype=object)

    def flag(mask: np.ndarray, why: str) -> None:
        reason[mask & (reason == "") & ~blank] = why

    bearing_text = text("bearing")
    if layout is not None and layout.plots:  # another sensor's plot, an empty scan
        no_bearing = (bearing_text == "").to_numpy()
        plot = np.zeros(n, dtype=bool)
        for c in layout.plots:
            if c in df.columns:
                plot |= (df[c].str.strip() != "").to_numpy()
        flag(no_bearing & plot, f"{NOT_A_BEARING} a position plot ({', '.join(layout.plots)})")
        flag(no_bearing & ~plot, f"{NOT_A_BEARING} an empty scan (no measurement)")
    batch = text("batch")
    flag((batch == "").to_numpy(), "missing batch")
    if "target" in names:
        target = text("target")
        flag((target == "").to_numpy(), "missing target")
        batch = batch + "/" + target
    ns, ok = parse_times(pa.chunked_array([pa.array(text("time"))]), "auto")
    flag(~ok, "unparsable time")
    factor = angle_unit(names["bearing"] if isinstance(names["bearing"], str) else "")[0]
    bearing = pd.to_numeric(bearing_text, errors="coerce").to_numpy(dtype="float64")
    bearing = np.degrees(bearing * factor)
    flag(~np.isfinite(bearing), "bearing not a finite number")
    obs = {}
    for f, lim in (("obs_lon", 180.0), ("obs_lat", 90.0)):
        if f in names:
            t = text(f)
            v = pd.to_numeric(t, errors="coerce").to_numpy(dtype="float64")
            flag((t != "").to_numpy() & ~(np.abs(v) <= lim), f"{f} out of range or unreadable")
            obs[f] = v
    if res["origin"] is not None:  # metres on a local plane → lon/lat (the track reader's)
        xy = []
        for f in ("obs_east", "obs_north"):
            t = text(f)
            v = pd.to_numeric(t, errors="coerce").to_numpy(dtype="float64")
            flag((t != "").to_numpy() & ~np.isfinite(v), f"{f} unreadable")
            xy.append(v * length_unit(names[f])[0])
        lat0, lon0 = res["origin"]
        obs["obs_lon"], obs["obs_lat"] = geo.from_local(xy[0], xy[1], lon0, lat0)
    # A line repeated as is (same series, time and bearing: logged twice) is quarantined;
    # different bearings at one time (a frame's several targets, clutter) are kept.
    sound = np.flatnonzero((reason == "") & ~blank)
    key = pd.DataFrame({"b": batch.to_numpy()[sound], "t": ns[sound], "v": bearing[sound] % 360.0})
    repeated = np.zeros(n, dtype=bool)
    repeated[sound[key.duplicated().to_numpy()]] = True
    flag(repeated, "repeated line (same batch, time and bearing)")
    keep = (reason == "") & ~blank
    quarantine = pd.DataFrame(
        {
            "line": np.concatenate([line[~keep & ~blank], [r[0] for r in refused]]).astype("int64"),
            "reason": list(reason[~keep & ~blank]) + [r[1] for r in refused],
            "text": [  # the quarantined rows only: their fields as read
                sn.delimiter.join(r) for r in df[~keep & ~blank].itertuples(index=False)
            ]
            + [r[2] for r in refused],
        }
    )
    quarantine = quarantine.sort_values("line", kind="stable", ignore_index=True)
    if not keep.any():
        why = quarantine["reason"].value_counts().head(3).to_dict()
        raise InputError(f"{path}: no usable bearing: {len(quarantine):,} lines quarantined {why}")
    out = pd.DataFrame(
        {
            "batch": batch[keep].to_numpy().astype(str),
            "time": pd.Series(ns[keep].view("datetime64[ns]")).dt.tz_localize("UTC"),
            "bearing": bearing[keep] % 360.0,
        }
    )
    for f, v in obs.items():
        out[f] = v[keep]
    used = {c for v in names.values() for c in (v if isinstance(v, tuple) else (v,))}
    for col in df.columns:  # other columns as read
        if col not in out.columns and col not in used:
            out[col] = df[col].to_numpy()[keep]
    reasons = quarantine["reason"].value_counts().to_dict()
    per_time = out.groupby(["batch", "time"], sort=False).size()
    several = per_time[per_time > 1]
    report = {
        "lines": int(n - blank.sum() + len(refused)),
        "blank": int(blank.sum()),
        # lines that continue a record (a quoted cell's line breaks): with the header(s),
        # lines and blank, every physical line of the file
        "continued_lines": int(breaks.sum() + sum(skipped_breaks)),
        "bearings": int(len(out)),
        "series": int(out["batch"].nunique()),
        "layout": layout.label if layout is not None else None,
        "columns": {f: "+".join(v) if isinstance(v, tuple) else v for f, v in names.items()},
        "origin": list(res["origin"]) if res["origin"] is not None else None,
        "set_aside": {r: int(k) for r, k in reasons.items() if r.startswith(NOT_A_BEARING)},
        "quarantined": {r: int(k) for r, k in reasons.items() if not r.startswith(NOT_A_BEARING)},
        "several": {
            "times": int(len(several)),
            "of_times": int(len(per_time)),
            "rows": int(several.sum()),
            "series": int(several.index.get_level_values(0).nunique()),
            "most": int(several.max()) if len(several) else 1,
        },
        "notes": res["notes"],
    }
    return BearingRead(out, quarantine, report)


def summary_lines(report: dict) -> list[str]:
    """Where every line of a bearing file went, and why (for the CLI and the window's log;
    none for an empty report)."""
    if not report:
        return []
    out = [
        f"{report['lines']:,} lines: {report['bearings']:,} bearings in "
        f"{report['series']:,} series"
        + "".join(f"; {k:,} {r}" for r, k in report["set_aside"].items())
        + "".join(f"; {k:,} quarantined: {r}" for r, k in report["quarantined"].items())
        + (
            f"; {n:,} {'line continues' if n == 1 else 'lines continue'} a quoted cell"
            if (n := report.get("continued_lines", 0))
            else ""
        )
    ]
    out += report["notes"]
    cols = ", ".join(f"{f}={c}" for f, c in report["columns"].items())
    out.append(f"columns: {cols}")
    sev = report["several"]
    if sev["times"] and "gated" in report:
        out.append(
            f"{sev['rows']:,} bearings share their time with another of their series "
            f"({sev['times']:,} of {sev['of_times']:,} times, up to {sev['most']} at one "
            "time: a frame's several targets or clutter): kept, and gated on the tracks"
        )
        out += gate_lines(report["gated"])
    elif sev["times"]:
        out.append(
            f"{sev['rows']:,} bearings share their time with another of their series "
            f"({sev['times']:,} of {sev['of_times']:,} times in {sev['series']} series, up to "
            f"{sev['most']} at one time: a frame's several targets or clutter): kept, not "
            "quarantined; such a series is not one target's sequence, so the detector does "
            "not test it: split it by a target column (--map target=COLUMN) or gate it on "
            "the targets' tracks (--tracks FILE)"
        )
    return out


def inspect_bearings(
    path, mapping: dict[str, str] | list[str] | None = None, origin=None, encoding=None
) -> dict:
    """What reading ``path`` as bearings would use, from its first rows (for the Open
    bearings dialog): ``columns``, ``preview`` (first rows, lists of cells), ``encoding``,
    ``delimiter``, ``mapping`` (field → column; a joined batch as ``A+B``), ``layout`` (a
    known layout's label or None), ``origin`` ((lat, lon) used, or None), ``notes`` and
    ``problem`` (why reading would fail, or None). Raises :class:`InputError` only when
    the file cannot be read at all."""
    from wakeline.core.io.formats import parse_mapping
    from wakeline.core.io.sniff import sniff

    if not isinstance(mapping, dict):
        mapping = parse_mapping(mapping, BEARING_FIELDS)
    sn = sniff(path, encoding)
    out = {
        "columns": list(sn.columns),
        "preview": [list(r) for r in sn.preview],
        "encoding": sn.encoding,
        "delimiter": sn.delimiter,
        "header": sn.has_header,
        "mapping": {},
        "layout": None,
        "origin": None,
        "notes": [],
        "problem": None,
    }
    try:
        res = resolve_bearings(sn.columns, mapping, origin, Path(path).name)
    except InputError as exc:
        out["problem"] = str(exc)
        found = _bearing_columns(sn.columns)  # what the names alone give, for the boxes
        lay = known_layout(sn.columns)
        out["mapping"] = {**found, **mapping}
        out["layout"] = lay.label if lay is not None else None
        return out
    out["mapping"] = {
        f: "+".join(v) if isinstance(v, tuple) else v for f, v in res["columns"].items()
    }
    out["layout"] = res["layout"].label if res["layout"] is not None else None
    out["origin"] = res["origin"]
    out["notes"] = res["notes"]
    return out


def gate_to_tracks(
    bearings: pd.DataFrame, tracks: pd.DataFrame, gate_deg: float = 3.0, max_gap_s: float = 10.0
) -> tuple[pd.DataFrame, dict]:
    """One target's sequence per series and track, from bearings of several targets in one
    series (a camera's detections): a bearing goes to a track (``batch, time, lon, lat``:
    GNSS truth, AIS) when the track's bearing from the observer at that time lies within
    ``gate_deg``; per series, track and time the nearest one is kept (the rule of
    :func:`~wakeline.core.real_sets.autoferry_bearings`, which gates on the Autoferry
    truth). The track is interpolated between fixes at most ``max_gap_s`` apart (outside
    its span, or in a longer gap, it takes no bearing). New series ``SERIES/TRACK``, with
    ``track_bearing`` (degrees) beside; bearings no track is near are left out and counted.
    Returns the table and ``{"gate_deg", "tracks", "bearings_in", "kept", "series",
    "no_track", "in_two"}``."""
    from wakeline.core import geo
    from wakeline.core.schema import time_seconds

    if not {"obs_lon", "obs_lat"} <= set(bearings.columns):
        raise InputError(
            "gating bearings on tracks needs the observer's positions (obs_lon/obs_lat, "
            "or obs_east/obs_north with --origin)"
        )
    t_all = time_seconds(bearings["time"])
    # Bearings sorted by time once: a track is compared only with the bearings within
    # its time span (searchsorted), not with every bearing (h157: ~9 ms a track at 65k).
    by_time = np.argsort(t_all, kind="stable")
    t_sorted = t_all[by_time]
    olon_all = bearings["obs_lon"].to_numpy(dtype="float64")
    olat_all = bearings["obs_lat"].to_numpy(dtype="float64")
    b_all = bearings["bearing"].to_numpy(dtype="float64")
    rows, names, errs, truth = [], [], [], []
    tracks = tracks.sort_values(["batch", "time"], kind="stable")
    # each track's rows (in groupby's order of tracks), its times and positions at once
    code = tracks.groupby("batch", sort=True).ngroup().to_numpy()
    in_track = np.argsort(code, kind="stable")
    bounds = np.searchsorted(code[in_track], np.arange(code.max(initial=-1) + 2))
    track_names = tracks["batch"].to_numpy()
    track_t = time_seconds(tracks["time"])
    track_lon = tracks["lon"].to_numpy(dtype="float64")
    track_lat = tracks["lat"].to_numpy(dtype="float64")
    for a, z in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):  # per track
        rows_of = in_track[a:z]
        name = track_names[rows_of[0]]
        tt = track_t[rows_of]
        keep = np.concatenate([[True], np.diff(tt) > 0])  # one fix per time
        tt = tt[keep]
        if len(tt) < 2:
            continue
        lo = np.searchsorted(t_sorted, tt[0], side="left")
        hi = np.searchsorted(t_sorted, tt[-1], side="right")
        at = np.sort(by_time[lo:hi])  # the span's bearings, in table order
        t, olon, olat, b = t_all[at], olon_all[at], olat_all[at], b_all[at]
        lon, lat = track_lon[rows_of][keep], track_lat[rows_of][keep]
        k = np.clip(np.searchsorted(tt, t), 1, len(tt) - 1)
        inside = (t >= tt[0]) & (t <= tt[-1]) & (tt[k] - tt[k - 1] <= max_gap_s)
        plon, plat = np.interp(t, tt, lon), np.interp(t, tt, lat)
        true_b = geo.initial_bearing_deg(olon, olat, plon, plat)
        err = np.abs(geo.angle_diff(b, true_b))
        sel = np.flatnonzero(inside & (err < gate_deg) & np.isfinite(olon) & np.isfinite(olat))
        hit = at[sel]
        err, true_b = err[sel], true_b[sel]
        rows.append(hit)
        names.append(np.full(len(hit), str(name), dtype=object))
        errs.append(err)
        truth.append(true_b % 360.0)
    cat = lambda xs, dtype: np.concatenate(xs) if xs else np.zeros(0, dtype)  # noqa: E731
    row, track = cat(rows, "int64"), cat(names, object)
    cand = pd.DataFrame(
        {
            "row": row,
            "track": track,
            "err": cat(errs, "float64"),
            "track_bearing": cat(truth, "float64"),
            "series": bearings["batch"].to_numpy()[row],
            "t": t_all[row],
        }
    )
    cand = cand.sort_values(["err", "row"], kind="stable").drop_duplicates(["series", "track", "t"])
    cand = cand.sort_values(["series", "track", "t"], kind="stable")
    out = bearings.iloc[cand["row"].to_numpy()].reset_index(drop=True)
    out["batch"] = (cand["series"].astype(str) + "/" + cand["track"].astype(str)).to_numpy()
    out["track_bearing"] = cand["track_bearing"].to_numpy()
    used = cand["row"].value_counts()
    report = {
        "gate_deg": float(gate_deg),
        "tracks": int(tracks["batch"].nunique()),
        "bearings_in": int(len(bearings)),
        "kept": int(len(out)),
        "series": int(out["batch"].nunique()),
        "no_track": int(len(bearings) - len(used)),
        "in_two": int((used > 1).sum()),
    }
    return out, report


def gate_lines(report: dict) -> list[str]:
    """The gating's summary (:func:`gate_to_tracks`), for the CLI and the window's log."""
    return [
        f"gated on {report['tracks']} track(s) within {report['gate_deg']:g}°: "
        f"{report['kept']:,} bearings in {report['series']} series (the nearest per series, "
        f"track and time); {report['no_track']:,} of {report['bearings_in']:,} bearings near "
        f"no track, left out; {report['in_two']:,} taken by two tracks"
    ]

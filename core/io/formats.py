"""The input layouts Wakeline recognises, and how their columns map to canonical fields.

A format is a list of candidate header names per canonical field (matched without regard
to case or surrounding blanks) plus a signature: the headers whose presence identifies
it. Detection takes the first format, in the order of ``FORMATS``, whose signature and
required fields are all present. ``--map field=column`` overrides any field.
"""

from dataclasses import dataclass, field

from wakeline.core.errors import InputError
from wakeline.core.schema import REQUIRED_COLUMNS

FIELDS = ("sensor", "batch", "time", "lon", "lat", "speed", "course", "truth")


@dataclass(frozen=True)
class Format:
    """One input layout."""

    name: str
    family: str  # the --format value that selects it: canonical, radar, ais, mtad, generic
    label: str
    signature: tuple[str, ...]
    candidates: dict[str, tuple[str, ...]] = field(default_factory=dict)
    #: "auto" (ISO text, or unix s/ms numbers), "unix" (seconds), or "dayfirst" (dd/mm/yyyy)
    time_kind: str = "auto"


_GENERIC = {
    "sensor": ("sensor", "source", "sendshipno", "sensor_id"),
    "batch": ("batch", "nno", "track_id", "trackid", "track", "mmsi", "id", "target_id"),
    "time": (
        "time",
        "timestamp",
        "basedatetime",
        "# timestamp",
        "sendtime",
        "datetime",
        "t",
        "position_timestamp",
        "date_time",
    ),
    "lon": ("lon", "longitude", "lng", "long", "x_lon"),
    "lat": ("lat", "latitude", "y_lat"),
    "speed": ("speed", "sog", "speed_kn"),
    "course": ("course", "cog", "cou", "course_deg"),
    "truth": ("truth",),
}

FORMATS: tuple[Format, ...] = (
    Format(
        "canonical",
        "canonical",
        "Wakeline canonical CSV",
        ("sensor", "batch", "time", "lon", "lat"),
        {f: (f,) for f in FIELDS},
    ),
    Format(
        "radar",
        "radar",
        "Shipborne radar export (SendShipNO, SendTime, nNO)",
        ("SendShipNO", "SendTime", "nNO"),
        {
            "sensor": ("SendShipNO",),
            "batch": ("nNO",),
            "time": ("SendTime",),
            "lon": ("lon", "longitude"),
            "lat": ("lat", "latitude"),
            "speed": ("speed", "sog", "v"),
            "course": ("course", "cog", "heading"),
            "truth": ("truth",),
        },
        time_kind="unix",
    ),
    Format(
        "ais-marinecadastre",
        "ais",
        "AIS, US MarineCadastre (MMSI, BaseDateTime, LAT, LON)",
        ("MMSI", "BaseDateTime", "LAT", "LON"),
        {
            "batch": ("MMSI",),
            "time": ("BaseDateTime",),
            "lon": ("LON",),
            "lat": ("LAT",),
            "speed": ("SOG",),
            "course": ("COG",),
            "truth": ("truth",),
        },
    ),
    Format(
        "ais-dma",
        "ais",
        "AIS, Danish Maritime Authority (# Timestamp, MMSI, Latitude, Longitude)",
        ("# Timestamp", "MMSI", "Latitude", "Longitude"),
        {
            "batch": ("MMSI",),
            "time": ("# Timestamp",),
            "lon": ("Longitude",),
            "lat": ("Latitude",),
            "speed": ("SOG",),
            "course": ("COG",),
            "truth": ("truth",),
        },
        time_kind="dayfirst",
    ),
    Format(
        "mtad-measurement",
        "mtad",
        "MTAD measurement (batch, source, time, lat, lon, vel, cou)",
        ("batch", "source", "time", "lat", "lon", "cou"),
        {
            "sensor": ("source",),
            "batch": ("batch",),
            "time": ("time",),
            "lon": ("lon",),
            "lat": ("lat",),
            "course": ("cou",),
            "truth": ("truth", "mmsi"),
        },
        time_kind="unix",
    ),
    Format(
        "mtad-scene",
        "mtad",
        "MTAD scene (MMSI, time, lat, lon, vel, cou)",
        ("MMSI", "time", "lat", "lon", "cou"),
        {
            "sensor": ("source",),
            "batch": ("batch", "MMSI"),
            "time": ("time",),
            "lon": ("lon",),
            "lat": ("lat",),
            "course": ("cou",),
            "truth": ("truth", "MMSI"),
        },
        time_kind="unix",
    ),
    Format("generic", "generic", "Generic CSV (columns recognised by name)", (), _GENERIC),
)

FAMILIES = ("auto", "canonical", "radar", "ais", "mtad", "generic")


@dataclass(frozen=True)
class Resolved:
    """A format chosen for a file, with the source column of every canonical field."""

    format: Format
    columns: dict[str, str]  # canonical field -> source column name (present fields only)


def _lookup(headers: tuple[str, ...]) -> dict[str, str]:
    return {h.strip().lower(): h for h in headers}


def _resolve(
    fmt: Format, headers: tuple[str, ...], mapping: dict[str, str]
) -> tuple[dict[str, str], list[str]]:
    lookup = _lookup(headers)
    used = set(mapping.values())
    columns = dict(mapping)
    for name in FIELDS:
        if name in columns:
            continue
        for cand in fmt.candidates.get(name, ()):
            src = lookup.get(cand.lower())
            if src is not None and src not in used:
                columns[name] = src
                used.add(src)
                break
    missing = [f for f in REQUIRED_COLUMNS if f not in columns]
    return columns, missing


def parse_mapping(items: list[str] | None) -> dict[str, str]:
    """``["batch=MMSI", "time=t"]`` → ``{"batch": "MMSI", "time": "t"}``; checks the field names."""
    out: dict[str, str] = {}
    for item in items or ():
        name, sep, col = item.partition("=")
        name, col = name.strip(), col.strip()
        if not sep or not name or not col:
            raise InputError(f"--map {item!r}: expected field=column, e.g. batch=MMSI")
        if name not in FIELDS:
            raise InputError(
                f"--map {item!r}: unknown field {name!r}; fields are {', '.join(FIELDS)}"
            )
        out[name] = col
    return out


def resolve(
    headers: tuple[str, ...],
    family: str = "auto",
    mapping: dict[str, str] | None = None,
    source: str = "the file",
) -> Resolved:
    """Choose the format and map its columns. Raises :class:`InputError` naming what is missing."""
    mapping = dict(mapping or {})
    if family not in FAMILIES:
        raise InputError(f"unknown format {family!r}; choose one of {', '.join(FAMILIES)}")
    missing_mapped = [f"{k}={v}" for k, v in mapping.items() if v not in headers]
    if missing_mapped:
        raise InputError(
            f"{source}: mapped column(s) not found: {', '.join(missing_mapped)}; "
            f"headers found: {', '.join(headers)}"
        )
    lookup = _lookup(headers)
    candidates = [f for f in FORMATS if family in ("auto", f.family)]
    if family == "auto":
        for fmt in candidates:
            if all(s.lower() in lookup for s in fmt.signature):
                columns, missing = _resolve(fmt, headers, mapping)
                if not missing:
                    return Resolved(fmt, columns)
    else:
        best = None
        for fmt in candidates:
            columns, missing = _resolve(fmt, headers, mapping)
            absent = [s for s in fmt.signature if s.lower() not in lookup]
            if not missing and not absent:
                return Resolved(fmt, columns)
            if best is None:
                best = (
                    fmt,
                    absent
                    + [fmt.candidates[m][0] for m in missing if fmt.candidates[m][0] not in absent],
                )
        fmt, missing = best
        raise InputError(
            f"{source}: not a {fmt.label} file: missing column(s) {', '.join(missing)}; "
            f"headers found: {', '.join(headers)}"
        )
    # Auto detection failed: report against the generic names.
    _, missing = _resolve(FORMATS[-1], headers, mapping)
    names = {
        "batch": "batch (or MMSI, track_id, nNO)",
        "time": "time (or timestamp, BaseDateTime)",
        "lon": "lon (or longitude)",
        "lat": "lat (or latitude)",
    }
    raise InputError(
        f"{source}: missing required column {', '.join(names[m] for m in missing)}; "
        f"headers found: {', '.join(headers)}; map columns with --map field=column"
    )

"""The input layouts Wakeline recognises, and how their columns map to canonical fields.

A format is a list of candidate header names per canonical field (matched without regard
to case or surrounding blanks) plus a signature: the headers whose presence identifies
it. Detection takes the first format, in the order of ``FORMATS``, whose signature and
required fields are all present. ``--map field=column`` overrides any field.
"""

import re
from dataclasses import dataclass, field, replace

from wakeline.core.errors import InputError
from wakeline.core.io.sniff import listed_headers
from wakeline.core.schema import REQUIRED_COLUMNS

FIELDS = (
    "sensor",
    "batch",
    "time",
    "lon",
    "lat",
    "speed",
    "course",
    "truth",
    "east",
    "north",
    "east_offset",
    "north_offset",
    "range",
    "bearing",
)
#: Fields ``--map`` takes besides :data:`FIELDS`: a GPS week column and a column of GPS
#: seconds (of the week beside a week, else since 1980-01-06), found by name when no
#: column names a time (:func:`gps_columns`); mapped, they are the time (h149).
GPS_FIELDS = ("gps_week", "gps_seconds")
#: Every field ``--map`` (and the import dialog's column mapping) takes.
MAP_FIELDS = FIELDS + GPS_FIELDS
#: Positions in metres on a local plane (a radar's x/y about its site, a NED frame):
#: ``east``/``north`` (plus ``east_offset``/``north_offset``, e.g. the ownship's place
#: in the same frame, added to them) stand for lon/lat when the file has no lon/lat
#: columns and the frame's origin is given (``origin``; :func:`parse_origin`); without
#: east/north, ``range`` and ``bearing`` (true, clockwise from north) from the origin do.
PLANE_FIELDS = ("east", "north", "east_offset", "north_offset", "range", "bearing")
_CARTESIAN = ("east", "north", "east_offset", "north_offset")
_POLAR = ("range", "bearing", "east_offset", "north_offset")

#: Length units a plane column's header may name, tried in this order (the factor to
#: metres); a header naming none is in metres (or in ``--distance-unit``).
_LENGTH_UNITS = (
    (re.compile(r"(?<![a-z])(km|kilomet(?:er|re)s?)(?![a-z])|公里|千米"), 1000.0, "km"),
    (
        re.compile(r"(?<![a-z])(nm|nmi|nautical[ _-]?miles?)(?![a-z])|海里|浬"),
        1852.0,
        "nautical miles",
    ),
    (re.compile(r"(?<![a-z])(yd|yds|yards?)(?![a-z])|码"), 0.9144, "yards"),
    (re.compile(r"(?<![a-z])(m|met(?:er|re)s?)(?![a-z])|米"), 1.0, "metres"),
)
#: ``--distance-unit`` values: ``auto`` (a header names its unit, else metres) or the
#: unit of plane columns whose header names none.
DISTANCE_UNITS = {"auto": None, "m": (1.0, "metres"), "km": (1000.0, "km")}
DISTANCE_UNITS |= {"nm": (1852.0, "nautical miles"), "yd": (0.9144, "yards")}
#: Speed units a speed column's header may name (metres per hour of one unit).
_SPEED_UNITS = (
    (re.compile(r"(?<![a-z])(kn|kt|kts|knots?)(?![a-z])|节"), 1852.0, "knots"),
    (
        re.compile(
            r"km/h|km/hr|(?<![a-z])(kmh|kph|kmph|km_h|kilomet(?:er|re)s?[ _]per[ _]hour)"
            r"(?![a-z])|公里/小时|千米/小时|公里每小时|千米每小时|公里/时|千米/时"
        ),
        1000.0,
        "km/h",
    ),
    (re.compile(r"(?<![a-z])(mph|miles?[ _]per[ _]hour)(?![a-z])"), 1609.344, "mph"),
    (
        re.compile(
            r"m/s|m s-1|m·s|(?<![a-z])(mps|ms|m_s|ms-1|met(?:er|re)s?[ _]per[ _]second)"
            r"(?![a-z])|米/秒|米每秒"
        ),
        3600.0,
        "m/s",
    ),
)
#: ``--speed-unit`` values: ``auto`` (a header names its unit, else knots) or the unit of
#: a speed column whose header names none.
SPEED_UNITS = {"auto": None, "knots": (1852.0, "knots"), "m/s": (3600.0, "m/s")}
SPEED_UNITS |= {"km/h": (1000.0, "km/h"), "mph": (1609.344, "mph")}


def _named_unit(header: str, units) -> tuple[float, str] | None:
    text = header.strip().lower()
    for pattern, factor, name in units:
        if pattern.search(text):
            return factor, name
    return None


def length_unit(header: str, given: str = "auto") -> tuple[float, str]:
    """(metres per unit, unit) a plane column's header names (``x_km``, ``Range (NM)``,
    ``距离(海里)``, ``y_yd``); else ``given`` (:data:`DISTANCE_UNITS`), metres for auto."""
    return _named_unit(header, _LENGTH_UNITS) or DISTANCE_UNITS[given] or (1.0, "metres")


def speed_unit(header: str, given: str = "auto") -> tuple[float, str, bool]:
    """(metres per hour of one unit, unit, whether the header named it) of a speed column: the unit
    its header names (``speed_mps``, ``sog_kmh``, ``速度(km/h)``, ``Speed (m/s)``,
    ``speed_kn``), else ``given`` (:data:`SPEED_UNITS`), knots for auto."""
    named = _named_unit(header, _SPEED_UNITS)
    if named is not None:
        return (*named, True)
    return (*(SPEED_UNITS[given] or (1852.0, "knots")), False)


#: Speed columns a format names but the importer carries as they are, their unit not
#: known: MTAD's ``vel`` is SOG in m/s on its AIS-clean tracks and about knots on noisy
#: ones (data/real/mtad-dtwcm/SOURCE.md), so it is not read as the speed.
SPEEDS_CARRIED = ("vel",)


def carried_speed(header: str) -> tuple[float, str] | None:
    """For a column the importer carries unread: None when it is no speed; else (metres
    per hour of one unit, unit) when its header names the unit (``sog_kmh`` beside the
    mapped speed), (nan, "") when it does not (MTAD's ``vel``, a second ``speed``)."""
    key = normalize_header(header.strip().strip('"'))
    if key not in SPEEDS_CARRIED and known_fields([header]) != {"speed"}:
        return None
    return _named_unit(header, _SPEED_UNITS) or (float("nan"), "")


_RADIANS = re.compile(r"(?<![a-z])(rad|radians?)(?![a-z])|弧度")


def angle_unit(header: str) -> tuple[float, str]:
    """(radians per unit, unit) of a bearing column: radians when its header says so
    (``bearing_rad``, ``方位(弧度)``), else degrees."""
    if _RADIANS.search(header.strip().lower()):
        return 1.0, "radians"
    return 3.141592653589793 / 180.0, "degrees"


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


#: Synonyms of every canonical field, in order of preference, compared after
#: :func:`normalize_header` (so ``Latitude_degrees``, ``LAT (deg)``, ``纬度（度）`` all match
#: ``latitude``/``lat``/``纬度``). Times that say their zone (unix seconds) come first.
SYNONYMS: dict[str, tuple[str, ...]] = {
    "sensor": (
        "sensor",
        "source",
        "sendshipno",
        "sensor_id",
        "sensorid",
        "radar",
        "radar_id",
        "station",
        "receiver",
        "传感器",
        "传感器号",
        "雷达号",
        "雷达编号",
        "雷达",
        "站号",
        "来源",
        "数据源",
        "信源",
    ),
    "batch": (
        "batch",
        "nno",
        "track_id",
        "trackid",
        "track",
        "track_no",
        "track_number",
        "mmsi",
        "id",
        "target_id",
        "targetid",
        "target_no",
        "vessel_id",
        "ship_id",
        # after every id above: a file's "target" or "vessel" is its track only when
        # nothing names one better (Wakeline's own output has batch and target)
        "target",
        "target_number",
        "vessel",
        "ship",
        "object_id",
        "contact_id",
        # a radar's or tracker's track number, a GPX export's track (ogr2ogr: track_fid)
        "track_fid",
        "track_nr",
        "tracknum",
        "trk",
        "trk_id",
        "trk_no",
        "tno",
        "tn",
        "kennung",
        "schiff",
        "schiffs_id",
        "identifiant",
        "navire",
        "buque",
        "navio",
        "судно",
        "船舶",
        "선박",
        "批号",
        "目标号",
        "目标批号",
        "航迹号",
        "航迹批号",
        "目标编号",
        "目标id",
        "批次号",
        "目标",
        "船号",
    ),
    "time": (
        "unix时间戳",
        "unix_time",
        "unixtime",
        "unix_timestamp",
        "epoch",
        "epoch_s",
        "time",
        "timestamp",
        "basedatetime",
        "# timestamp",
        "sendtime",
        "datetime",
        "t",
        "position_timestamp",
        "date_time",
        "utc",
        "utc_time",
        "时间戳",
        "时间",
        "日期时间",
        "定位时间",
        "接收时间",
        "发送时间",
        "采集时间",
        "时刻",
        "本地时间",
        "北京时间",
        # other languages (a clock alone, Heure or Uhrzeit, is joined with the date
        # column beside it: reader._to_canonical)
        "zeitstempel",
        "zeit",
        "uhrzeit",
        "zeitpunkt",
        "datum_uhrzeit",
        "horodatage",
        "date_heure",
        "heure",
        "temps",
        "fecha_hora",
        "marca_de_tiempo",
        "tiempo",
        "hora",
        "data_hora",
        "data_ora",
        "ora",
        "tidspunkt",
        "tidpunkt",
        "klokkeslett",
        "время",
        "дата_время",
        "日時",
        "時刻",
        "時間",
        "일시",
        "시각",
        "시간",
        # "tid" (Norwegian, Swedish, Danish) is also a "track id": a time only when its
        # values are times (reader._values_fit)
        "tid",
        # last: a date column is the time when no column names one (with a column of
        # clock times beside it, the two are joined: reader._date_column)
        "date",
        "日期",
        "datum",
        "fecha",
        "dato",
        "дата",
        "日付",
        "날짜",
        # Portuguese and Italian "data" (a date), English "data" (anything): the time only
        # when its values are times (reader._values_fit)
        "data",
    ),
    # German "Länge"/"Breite" are a ship's length and beam too: last, and taken only when
    # the values are degrees with decimals (reader._values_fit)
    "lon": (
        "lon",
        "longitude",
        "lng",
        "long",
        "x_lon",
        "经度",
        # a Chinese radar's or plotter's console: east longitude, the target's longitude,
        # a hemisphere letter or degree sign kept on the name (东经(度) normalises to 东经)
        "东经",
        "目标经度",
        "经度e",
        "东经e",
        "经度°",
        "东经°",
        "längengrad",
        "laengengrad",
        "longitud",
        "longitudine",
        "lengdegrad",
        "längdgrad",
        "længdegrad",
        "долгота",
        "経度",
        "경도",
        "länge",
        "laenge",
    ),
    "lat": (
        "lat",
        "latitude",
        "y_lat",
        "纬度",
        "北纬",
        "目标纬度",
        "纬度n",
        "北纬n",
        "纬度°",
        "北纬°",
        "breitengrad",
        "latitud",
        "latitudine",
        "breddegrad",
        "широта",
        "緯度",
        "위도",
        "breite",
    ),
    "speed": (
        "speed",
        "sog",
        "speed_kn",
        "speed_over_ground",
        "velocity",
        "航速",
        "速度",
        "对地航速",
        "船速",
        "spd",
        "ground_speed",
        "geschwindigkeit",
        "vitesse",
        "velocidad",
        "velocidade",
        "velocità",
        "velocita",
        "hastighet",
        "hastighed",
        "скорость",
        "速力",
        "対地速力",
        "속력",
        "속도",
        # "Fahrt"/"fart" (German, Norwegian: way, speed) last: a number only (_values_fit)
        "fahrt",
        "fart",
    ),
    "course": (
        "course",
        "cog",
        "cou",
        "course_deg",
        "course_over_ground",
        "航向",
        "对地航向",
        # course over ground as Chinese radar consoles head it (航迹向(度)); 航向角 the
        # course angle (operator test 7, D13)
        "航迹向",
        "航向角",
        "crs",
        "kurs",
        "route_fond",
        "rumbo",
        "rumo",
        "rotta",
        "курс",
        "針路",
        "対地針路",
        "침로",
        # French "route" (course) and "cap" (heading; the one angle many French exports
        # write) last, and only with numbers (reader._values_fit): an English "Route" is
        # a route's name
        "route",
        "cap",
    ),
    "truth": ("truth", "真值"),
    # Local-plane metres (used only when the file has no lon/lat). Not "easting" /
    # "northing": those are usually UTM grid coordinates, not metres from an origin.
    "east": (
        "east",
        "x",
        "pos_x",
        "posx",
        "x_pos",
        "meas_east",
        "east_m",
        "x_east",
        "东",
        "东向",
        "东向距离",
        "x坐标",
    ),
    "north": (
        "north",
        "y",
        "pos_y",
        "posy",
        "y_pos",
        "meas_north",
        "north_m",
        "y_north",
        "北",
        "北向",
        "北向距离",
        "y坐标",
    ),
    "east_offset": ("own_east", "ownship_east", "own_x", "sensor_east", "sensor_x", "本船东"),
    "north_offset": ("own_north", "ownship_north", "own_y", "sensor_north", "sensor_y", "本船北"),
    # From the origin (a radar's site), used only without lon/lat and east/north. Unit
    # words the names keep (nm, rad) are listed; km, m, deg are dropped by normalising.
    "range": (
        "range",
        "range_nm",
        "range_nmi",
        "rng",
        "slant_range",
        "distance",
        "distance_nm",
        "dist",
        "dist_nm",
        "距离",
        "斜距",
    ),
    "bearing": (
        "bearing",
        "true_bearing",
        "azimuth",
        "az",
        "brg",
        "bearing_rad",
        "azimuth_rad",
        "方位",
        "方位角",
        "真方位",
    ),
}
_GENERIC = SYNONYMS

#: Names of a field by their form, tried (generic layout only) after every synonym of
#: the field, on the normalised name: the ship's MMSI however prefixed (``sourcemmsi``
#: of the Brest set, ``vessel_mmsi``; not the receiver's, the own ship's, nor a count
#: such as ``n_shared_mmsi``), a track's number
#: however written (``Track Nr``, ``trk_num``, ``tgt_id``), a speed or course over
#: ground spelled out.
PATTERNS: dict[str, re.Pattern] = {
    "batch": re.compile(
        r"^(?:source|src|vessel|ship|boat|target|tgt|sender|from|user|ais|tx|object|obj"
        r"|contact|craft)mmsi$"
        r"|^mmsi(?:no|nr|num|number|id|code)$"
        r"|^(?:track|trk|tgt|target|contact)(?:no|nr|num|number|id|fid|ident|identifier)$"
    ),
    "speed": re.compile(r"^(?:speed|spd)(?:overground|og|ground)$"),
    "course": re.compile(r"^(?:course|crs)(?:overground|og|ground)$"),
}

#: Unit and zone suffixes dropped before comparing names: ``_degrees``, ``_knots``,
#: ``(kn)``, ``（度）``, ``[deg]``, ``(UTC)``...
_BRACKETED = re.compile(r"\s*[\(\[（【]([^\)\]）】]*)[\)\]）】]\s*$")
_UNIT_WORD = re.compile(
    r"[\s_\-.]+(degrees|degree|deg|knots|knot|kn|kts|kt|meters|metres|m|km|seconds|sec|s|ms"
    r"|mps|kmh|kph|kmph|mph|km/h|m/s|yd|yds|yards|nm|nmi"
    r"|utc|°|度|节|秒)$"
)
_LOCAL_WORDS = ("local", "本地", "北京", "bj", "cst", "lt")
_LOCAL_NAMES = ("本地时间", "北京时间", "localtime", "local_time", "time_local")


def normalize_header(name: str) -> str:
    """A header as compared with the synonyms: lower case, full-width brackets and a unit
    or zone suffix dropped, then spaces, underscores, hyphens and dots removed
    (``"Latitude_degrees"`` → ``"latitude"``, ``"航速(kn)"`` → ``"航速"``)."""
    text = name.strip().lower().lstrip("\ufeff")
    for _ in range(2):
        text = _BRACKETED.sub("", text)
        stripped = _UNIT_WORD.sub("", text)
        if stripped:  # a bare "s" or "度" stays itself
            text = stripped
    squeezed = re.sub(r"[\s_\-.]+", "", text)
    return squeezed or text


def header_is_local(name: str) -> bool:
    """True when a time column's name says it holds local times (``时间(Local)``, 本地时间)."""
    text = name.strip().lower()
    m = _BRACKETED.search(text)
    if m and any(w in m.group(1) for w in _LOCAL_WORDS):
        return True
    return re.sub(r"[\s_\-.]+", "", text) in {n.replace("_", "") for n in _LOCAL_NAMES}


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


def _alias_table() -> dict[str, str]:
    """Normalised header name → canonical field, over the synonyms and every format's
    own names (``SendShipNO``, ``# Timestamp``, ``cou``...)."""
    out: dict[str, str] = {}
    for fmt in FORMATS:
        for name, cands in fmt.candidates.items():
            for cand in cands:
                out.setdefault(normalize_header(cand), name)
    return out


_ALIASES = _alias_table()


def known_fields(names: list[str] | tuple[str, ...]) -> set[str]:
    """The canonical fields that a line's cells name (by synonym or a format's own
    names): how a header line is told from a title line above it."""
    out = set()
    for n in names:
        key = normalize_header(n.strip().strip('"'))
        f = _ALIASES.get(key) or next((f for f, p in PATTERNS.items() if p.match(key)), None)
        if f:
            out.add(f)
    return out


@dataclass(frozen=True)
class Resolved:
    """A format chosen for a file, with the source column of every canonical field;
    ``origin`` (lat, lon degrees): the local plane's origin when the positions are
    ``east``/``north`` metres (``None`` when they are lon/lat)."""

    format: Format
    columns: dict[str, str]  # canonical field -> source column name (present fields only)
    origin: tuple[float, float] | None = None
    #: The column of dates joined with the time column's clock times, when the values
    #: show one beside it (``reader.judge_by_values``; a column named Date is found by
    #: its name when reading).
    date: str | None = None
    #: What was decided by the values (an id column adopted): warnings for the report.
    notes: tuple[str, ...] = ()
    #: The time column holds GPS seconds (no column names a time): of the week in the
    #: column ``gps_week`` names, or since the GPS epoch (1980-01-06) when it is ``""``;
    #: None: not GPS time (:func:`gps_columns`).
    gps_week: str | None = None
    #: The units of a speed column and of plane lengths whose headers name none
    #: (``--speed-unit``, ``--distance-unit``: :data:`SPEED_UNITS`, :data:`DISTANCE_UNITS`).
    speed_unit: str = "auto"
    distance_unit: str = "auto"

    @property
    def mapping(self) -> dict[str, str]:
        """``columns`` as ``--map`` names them: a GPS time as ``gps_seconds`` (and
        ``gps_week``), so that mapping them again reads GPS time (the import dialog)."""
        out = dict(self.columns)
        if self.gps_week is not None and "time" in out:
            out["gps_seconds"] = out.pop("time")
            if self.gps_week:
                out["gps_week"] = self.gps_week
        return out

    @property
    def on_plane(self) -> bool:
        """The positions are on a local plane about ``origin`` (east/north, or range and
        bearing)."""
        return self.origin is not None and plane_kind(self.columns) is not None


def plane_kind(columns: dict[str, str]) -> str | None:
    """``"cartesian"`` (east/north), ``"polar"`` (range/bearing) or None (lon/lat, or
    neither) for a resolved column mapping."""
    if "lon" in columns or "lat" in columns:
        return None
    if "east" in columns and "north" in columns:
        return "cartesian"
    if "range" in columns and "bearing" in columns:
        return "polar"
    return None


def parse_origin(value: str | tuple[float, float] | list | None) -> tuple[float, float] | None:
    """``"63.4389,10.3991"`` (or ``"63.4389 10.3991"``, a pair of numbers) → (lat, lon)
    degrees; ``None``/``""`` → ``None``. Raises :class:`InputError` on anything else."""
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    try:
        if isinstance(value, str):
            parts = [p for p in re.split(r"[,;\s]+", value.strip()) if p]
        else:
            parts = list(value)  # a number alone: TypeError, refused as the rest
        lat, lon = (float(p) for p in parts)
    except (TypeError, ValueError):
        raise InputError(
            f"--origin {value!r}: expected LAT,LON in degrees (e.g. 63.4389,10.3991)"
        ) from None
    if not (-90.0 <= lat <= 90.0 and -180.0 <= lon <= 180.0) or lat != lat or lon != lon:
        raise InputError(
            f"--origin {value!r}: latitude must be within ±90° and longitude within ±180° "
            "(latitude first)"
        )
    return lat, lon


def _lookup(headers: tuple[str, ...]) -> dict[str, str]:
    """Normalised name → header; an exact (case-insensitive) name wins over a normalised one."""
    out: dict[str, str] = {}
    for h in headers:
        out.setdefault(normalize_header(h), h)
    for h in headers:
        out[h.strip().lower()] = h
    return out


def _key(name: str) -> str:
    return normalize_header(name)


def _resolve(
    fmt: Format, headers: tuple[str, ...], mapping: dict[str, str]
) -> tuple[dict[str, str], list[str]]:
    lookup = _lookup(headers)
    used = set(mapping.values())
    columns = dict(mapping)
    for name in FIELDS:
        if name in columns:
            continue
        src = _column_for(fmt, name, lookup, used)
        if src is not None:
            columns[name] = src
            used.add(src)
    if fmt.family == "generic":
        for name, pattern in PATTERNS.items():
            if name not in columns:
                src = next((h for h in headers if h not in used and pattern.match(_key(h))), None)
                if src is not None:
                    columns[name] = src
                    used.add(src)
    return _positions(columns, mapping)


def _layout_beneath(
    fmt: Format, headers: tuple[str, ...], columns: dict[str, str]
) -> tuple[Format, dict[str, str]]:
    """A canonical header (sensor, batch, time, lon, lat) over a known layout's own
    columns: an MTAD scene with a ``sensor`` column added (two sensors in one file) is
    still MTAD, its ``cou`` the course and its ``mmsi`` the truth (operator test 9, D9:
    they became extra columns, the points had no course and no truth). The fields the
    canonical names left unmapped are taken by the first MTAD layout whose signature the
    header holds; its format is returned with them."""
    if fmt.name != "canonical":
        return fmt, columns
    lookup = _lookup(headers)
    for other in FORMATS:
        if other.family != "mtad":
            continue
        if not all(s.lower() in lookup or _key(s) in lookup for s in other.signature):
            continue
        out, used = dict(columns), set(columns.values())
        for name in other.candidates:
            if name not in out:
                src = _column_for(other, name, lookup, used)
                if src is not None:
                    out[name] = src
                    used.add(src)
        if len(out) > len(columns):
            return other, out
    return fmt, columns


def _column_for(fmt: Format, name: str, lookup: dict[str, str], used: set) -> str | None:
    """The first header (by ``lookup``, :func:`_lookup`) of ``fmt``'s candidates for
    field ``name`` that no field has taken (``used``), or None."""
    for cand in fmt.candidates.get(name, ()):
        src = lookup.get(cand.lower()) or lookup.get(_key(cand))
        if src is not None and src not in used:
            return src
    return None


def next_column(fmt: Format, name: str, headers, used: set[str]) -> str | None:
    """The column of ``headers`` that ``fmt``'s candidates give field ``name`` when the
    ``used`` columns are not to be taken (the next choice after one that did not fit)."""
    return _column_for(fmt, name, _lookup(tuple(headers)), set(used))


def _positions(columns: dict[str, str], mapping: dict[str, str]) -> tuple[dict, list[str]]:
    """Lon/lat win over local-plane positions: the plane fields found by name are dropped
    when the file has lon and lat (they stay extra columns); without them east and north
    stand for them, and without those range and bearing. Positions the operator mapped
    (``--map range=… --map bearing=…``, or east/north, or lon/lat) win over those found
    by name: before, a file with x/y and range/bearing columns read x/y even when told
    to read range and bearing. The required fields still without a column."""
    given = _mapped_positions(mapping)
    if given is not None:
        columns = {
            k: v
            for k, v in columns.items()
            if k in mapping or k not in _POSITION_FIELDS or k in _KIND_FIELDS[given]
        }
    kind = plane_kind(columns)
    keep = {"cartesian": _CARTESIAN, "polar": _POLAR}.get(kind, ())
    columns = {
        k: v for k, v in columns.items() if k not in PLANE_FIELDS or k in keep or k in mapping
    }
    position = ("lon", "lat") if kind is not None else ()
    return columns, [f for f in REQUIRED_COLUMNS if f not in columns and f not in position]


#: The position fields of each kind (the offsets go with either plane kind).
_KIND_FIELDS = {"lonlat": ("lon", "lat"), "cartesian": _CARTESIAN, "polar": _POLAR}
_POSITION_FIELDS = frozenset(("lon", "lat", *PLANE_FIELDS))


def _mapped_positions(mapping: dict[str, str]) -> str | None:
    """The kind of position the operator's mapping names (both fields of a pair:
    lon/lat, east/north or range/bearing; the first pair in that order), else None."""
    for kind, pair in (
        ("lonlat", ("lon", "lat")),
        ("cartesian", ("east", "north")),
        ("polar", ("range", "bearing")),
    ):
        if all(f in mapping for f in pair):
            return kind
    return None


def unused_position_columns(headers, columns: dict[str, str]) -> dict[str, str]:
    """Position fields (east/north, range/bearing) the synonyms find in ``headers`` on
    columns the resolved mapping ``columns`` does not read, when the file's positions
    are of another kind (a file with both x/y and range/bearing): field → column."""
    kind = plane_kind(columns)
    if kind is None:
        return {}
    other = ("range", "bearing") if kind == "cartesian" else ("east", "north")
    lookup = _lookup(tuple(headers))
    used = set(columns.values())
    out = {}
    for name in other:
        src = _column_for(FORMATS[-1], name, lookup, used)
        if src is not None:
            out[name] = src
    return out if len(out) == 2 else {}


def guess_columns(
    headers: tuple[str, ...] | list[str], mapping: dict[str, str] | None = None
) -> tuple[dict[str, str], list[str]]:
    """Every field whose column the synonym table (:data:`SYNONYMS`) recognises in
    ``headers`` (``mapping``'s choices of columns present kept first), and the required
    fields (:data:`~wakeline.core.schema.REQUIRED_COLUMNS`) still without a column.

    What the import starts from when no layout fits: the fields it knows, not nothing."""
    headers = tuple(headers)
    kept = {k: v for k, v in (mapping or {}).items() if v in headers}
    return _resolve(FORMATS[-1], headers, kept)


def parse_mapping(items: list[str] | None, fields: tuple[str, ...] = MAP_FIELDS) -> dict[str, str]:
    """``["batch=MMSI", "time=t"]`` → ``{"batch": "MMSI", "time": "t"}``; checks the field
    names against ``fields`` (the track reader's; the bearing reader passes its own)."""
    out: dict[str, str] = {}
    for item in items or ():
        name, sep, col = item.partition("=")
        name, col = name.strip(), col.strip()
        if not sep or not name or not col:
            raise InputError(f"--map {item!r}: expected field=column, e.g. batch=MMSI")
        if name not in fields:
            raise InputError(
                f"--map {item!r}: unknown field {name!r}; fields are {', '.join(fields)}"
            )
        out[name] = col
    return out


def resolve(
    headers: tuple[str, ...],
    family: str = "auto",
    mapping: dict[str, str] | None = None,
    source: str = "the file",
    origin: str | tuple[float, float] | None = None,
) -> Resolved:
    """Choose the format and map its columns. Raises :class:`InputError` naming what is
    missing. ``origin`` (lat, lon degrees, or ``"LAT,LON"``): where a file's east/north
    metres are measured from (:data:`PLANE_FIELDS`); required when a file has them
    instead of lon/lat."""
    found = _resolve_columns(headers, family, mapping, source)
    origin = parse_origin(origin)
    kind = plane_kind(found.columns)
    if kind is None:
        # lon/lat: an origin given is not used (the reader says so: origin_warnings)
        return replace(found, origin=origin)
    if origin is None:
        c = found.columns
        what = (
            f"metres on a local plane (columns {c['east']!r} east, {c['north']!r} north)"
            if kind == "cartesian"
            else f"range and bearing from a site (columns {c['range']!r}, {c['bearing']!r})"
        )
        raise InputError(
            f"{source}: the positions are {what}, not longitude and latitude: give the "
            "latitude and longitude of the plane's origin (the radar's site, the frame's "
            "zero) with --origin LAT,LON"
        )
    return replace(found, origin=origin)


#: A GPS week number's header (``gps_week``, ``GPSWeek``, ``week``, ``WN``).
_GPS_WEEK = re.compile(r"^(?:gps[\s_\-.]*)?(?:week|wk|wn)(?:[\s_\-.]*(?:no|nr|num|number))?$")
#: GPS seconds: of the week (``tow``, ``gps_tow``, ``time_of_week``, ``gps_seconds`` beside
#: a week) or since the GPS epoch (``gps_time``, ``gps_seconds`` alone); a unit after.
#: Not ``gps_ms``: milliseconds (u-blox's iTOW) read as seconds were times a thousand off.
_GPS_SECONDS = re.compile(
    r"^(?:gps[\s_\-.]*(?:seconds?|secs?|time|tow|sow)"
    r"|(?:gps[\s_\-.]*)?(?:tow|sow|time[\s_\-.]*of[\s_\-.]*week|seconds?[\s_\-.]*of[\s_\-.]*week"
    r"|week[\s_\-.]*seconds?))(?:[\s_\-.]*\(?(?:s|sec|seconds)\)?)?$"
)


def gps_columns(headers: tuple[str, ...] | list[str]) -> tuple[str | None, str | None]:
    """The GPS week column and the GPS seconds column of a header (either None when
    none is named so)."""
    week = next((h for h in headers if _GPS_WEEK.match(h.strip().lower())), None)
    seconds = next(
        (h for h in headers if h != week and _GPS_SECONDS.match(h.strip().lower())), None
    )
    return week, seconds


def _resolve_columns(
    headers: tuple[str, ...], family: str, mapping: dict[str, str] | None, source: str
) -> Resolved:
    mapping = dict(mapping or {})
    if family not in FAMILIES:
        raise InputError(f"unknown format {family!r}; choose one of {', '.join(FAMILIES)}")
    missing_mapped = [f"{k}={v}" for k, v in mapping.items() if v not in headers]
    if missing_mapped:
        raise InputError(
            f"{source}: mapped column(s) not found: {', '.join(missing_mapped)}; "
            f"headers found: {listed_headers(headers)}"
        )
    gps = {k: mapping.pop(k) for k in GPS_FIELDS if k in mapping}
    if not gps:
        return _resolve_mapped(headers, family, mapping, source)
    # --map gps_week=W and/or gps_seconds=S: S (or the GPS seconds column its name gives)
    # is the time, read as GPS seconds of the week in W (or the week column its name
    # gives; none: GPS seconds since 1980-01-06).
    if "time" in mapping:
        raise InputError(
            f"--map time={mapping['time']} and --map "
            + ", ".join(f"{k}={v}" for k, v in gps.items())
            + ": the time is one or the other (GPS week and seconds are the time)"
        )
    week, seconds = gps_columns([h for h in headers if h not in mapping.values()])
    week = gps.get("gps_week", None if week == gps.get("gps_seconds") else week)
    seconds = gps.get("gps_seconds") or next(
        (h for h in headers if h != week and _GPS_SECONDS.match(h.strip().lower())), None
    )
    if seconds is None:
        raise InputError(
            f"{source}: --map gps_week={week} needs the column of GPS seconds of the week: "
            f"add --map gps_seconds=COLUMN; headers found: {listed_headers(headers)}"
        )
    if seconds == week:
        raise InputError(f"--map gps_week and gps_seconds name one column: {week!r}")
    mapping["time"] = seconds
    found = _resolve_mapped(headers, family, mapping, source)
    return replace(found, gps_week=week or "")


def _resolve_mapped(
    headers: tuple[str, ...], family: str, mapping: dict[str, str], source: str
) -> Resolved:
    lookup = _lookup(headers)
    candidates = [f for f in FORMATS if family in ("auto", f.family)]
    if family == "auto":
        for fmt in candidates:
            if all(s.lower() in lookup or _key(s) in lookup for s in fmt.signature):
                columns, missing = _resolve(fmt, headers, mapping)
                if not missing:
                    return Resolved(*_layout_beneath(fmt, headers, columns))
    else:
        best = None
        for fmt in candidates:
            columns, missing = _resolve(fmt, headers, mapping)
            absent = [s for s in fmt.signature if s.lower() not in lookup and _key(s) not in lookup]
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
            f"headers found: {listed_headers(headers)}"
        )
    # Auto detection failed: report against the generic names.
    columns, missing = guess_columns(headers, mapping)
    gps_week = None
    if "time" in missing:  # GPS week and seconds of the week, or GPS seconds
        week, seconds = gps_columns(headers)
        if seconds is not None and seconds not in columns.values():
            columns["time"], gps_week = seconds, week or ""
            missing.remove("time")
    if not missing and gps_week is not None:
        return Resolved(FORMATS[-1], columns, gps_week=gps_week)
    if missing == ["batch"]:
        # One ship's export (time and position, no id column): the reader names the one
        # track after the file.
        return Resolved(FORMATS[-1], columns, gps_week=gps_week)
    names = {
        "batch": "batch (or MMSI, track_id, nNO)",
        "time": "time (or timestamp, BaseDateTime)",
        "lon": "lon (or longitude; or east/x metres with --origin)",
        "lat": "lat (or latitude; or north/y metres with --origin)",
    }
    raise InputError(
        f"{source}: missing required column {', '.join(names[m] for m in missing)}; "
        f"headers found: {listed_headers(headers)}; map columns with --map field=column"
    )

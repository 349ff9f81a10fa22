"""The same tracks written in the layouts a real owner might export them in (issue: the
goals are checked on captures we have not seen, in their owner's layout).

``write_variants(points, folder)`` takes canonical points (sensor, batch, time UTC, lon,
lat[, speed, course]) and writes one file per layout; each comes with the reading flags
an operator would give (``--tz`` for naive local times) and the number of its lines that
are not points (a summary line, a blank line: they must be quarantined, not lost).

Used by ``tests/test_unseen_layouts.py`` (on the MIT ATD sample in tests/data and, when
../shared is present, on the DMA, Saronic and Øresund sets written into a temporary
folder: those sets' licences keep them out of the repository).
"""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd


@dataclass(frozen=True)
class Variant:
    name: str
    path: Path
    flags: list[str] = field(default_factory=list)  # reading flags (import and --real)
    not_points: int = 0  # lines below the header that are not points (quarantined)
    exact: bool = True  # positions and times written losslessly (NMEA rounds them)


def _utc(points: pd.DataFrame) -> pd.Series:
    return pd.to_datetime(points["time"], utc=True)


def _opt(points: pd.DataFrame, col: str, fmt: str = "{:.1f}") -> list[str]:
    if col not in points.columns:
        return [""] * len(points)
    return ["" if pd.isna(v) else fmt.format(v) for v in points[col]]


def _fmt(values, digits: int = 10) -> list[str]:
    """Degrees with 10 decimals (0.01 mm: the positions survive the text)."""
    return [f"{float(v):.{digits}f}" for v in values]


def _write(path: Path, lines: list[str], encoding="utf-8", newline="\n") -> Path:
    path.write_bytes((newline.join(lines) + newline).encode(encoding))
    return path


def _unix_s(t: pd.Series) -> np.ndarray:
    return (t - pd.Timestamp("1970-01-01", tz="UTC")).dt.total_seconds().to_numpy()


def _num(v: float) -> str:
    """Seconds as text: whole numbers without a decimal point."""
    return str(int(v)) if float(v).is_integer() else repr(float(v))


def marinecadastre(points: pd.DataFrame, folder: Path) -> Variant:
    t = _utc(points)
    head = (
        "MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,"
        "Status,Length,Width,Draft,Cargo,TransceiverClass"
    )
    stamps = t.dt.strftime("%Y-%m-%dT%H:%M:%S")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    sog, cog = _opt(points, "speed"), _opt(points, "course")
    lines = [head] + [
        f'{b},{s},{la},{lo},{v},{c},511,"SHIP {b}, LTD",IMO0000000,CALL{b},70,0,120,20,6.5,70,A'
        for b, s, la, lo, v, c in zip(points["batch"], stamps, lat, lon, sog, cog, strict=True)
    ]
    return Variant("marinecadastre", _write(folder / "AIS_2024_01_01.csv", lines))


def dma(points: pd.DataFrame, folder: Path) -> Variant:
    t = _utc(points)
    head = (
        "# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,"
        "Heading,IMO,Callsign,Name,Ship type,Cargo type,Width,Length,"
        "Type of position fixing device,Draught,Destination,ETA,Data source type,A,B,C,D"
    )
    stamps = t.dt.strftime("%d/%m/%Y %H:%M:%S")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    sog, cog = _opt(points, "speed"), _opt(points, "course")
    lines = [head] + [
        f"{s},Class A,{b},{la},{lo},Under way using engine,0.0,{v},{c},,Unknown,OXA2,"
        f"NAME {b},Cargo,,20,150,GPS,7.2,GOTEBORG,01/03/2023 06:00:00,AIS,100,50,10,10"
        for b, s, la, lo, v, c in zip(points["batch"], stamps, lat, lon, sog, cog, strict=True)
    ]
    return Variant("dma", _write(folder / "aisdk-2023-03-01.csv", lines))


def radar(points: pd.DataFrame, folder: Path) -> Variant:
    """Seed 001's shipborne radar export: unix seconds, sensor = receiving ship."""
    s = _unix_s(_utc(points))
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    sog, cog = _opt(points, "speed"), _opt(points, "course")
    lines = ["SendShipNO,SendTime,nNO,lon,lat,speed,course"] + [
        f"1043,{_num(u)},{b},{lo},{la},{v},{c}"
        for u, b, lo, la, v, c in zip(s, points["batch"], lon, lat, sog, cog, strict=True)
    ]
    return Variant("radar", _write(folder / "radar_export.csv", lines))


def chinese(points: pd.DataFrame, folder: Path) -> Variant:
    """Chinese headers, Beijing local times without a zone, GB18030, CRLF."""
    local = _utc(points).dt.tz_convert("Asia/Shanghai").dt.strftime("%Y-%m-%d %H:%M:%S.%f")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    sog, cog = _opt(points, "speed"), _opt(points, "course")
    lines = ["批号,时间,经度,纬度,航速(节),航向(度),备注"] + [
        f"{b},{s},{lo},{la},{v},{c},目标"
        for b, s, lo, la, v, c in zip(points["batch"], local, lon, lat, sog, cog, strict=True)
    ]
    path = _write(folder / "航迹导出.csv", lines, encoding="gb18030", newline="\r\n")
    return Variant("chinese_gb18030_crlf", path, ["--tz", "Asia/Shanghai"])


def semicolon_comma(points: pd.DataFrame, folder: Path) -> Variant:
    """A European spreadsheet export: ``;`` between fields, decimal commas, day-first dots."""
    stamps = _utc(points).dt.strftime("%d.%m.%Y %H:%M:%S")

    def c(values):
        return [v.replace(".", ",") for v in values]

    lat, lon = c(_fmt(points["lat"])), c(_fmt(points["lon"]))
    sog, cog = c(_opt(points, "speed")), c(_opt(points, "course"))
    lines = ["MMSI;Timestamp;Latitude;Longitude;SOG;COG"] + [
        f"{b};{s};{la};{lo};{v};{co}"
        for b, s, la, lo, v, co in zip(points["batch"], stamps, lat, lon, sog, cog, strict=True)
    ]
    return Variant("semicolon_decimal_comma", _write(folder / "export_eu.csv", lines))


def epoch_ms(points: pd.DataFrame, folder: Path) -> Variant:
    ms = np.round(_unix_s(_utc(points)) * 1000).astype("int64")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["id,timestamp,lon,lat"] + [
        f"{b},{m},{lo},{la}" for b, m, lo, la in zip(points["batch"], ms, lon, lat, strict=True)
    ]
    return Variant("epoch_ms", _write(folder / "epoch_ms.csv", lines))


def iso_offset(points: pd.DataFrame, folder: Path) -> Variant:
    """ISO 8601 with the owner's offset (+02:00 and -05:00 alternating by track)."""
    t = _utc(points)
    codes = pd.factorize(points["batch"])[0]
    east = t.dt.tz_convert("Etc/GMT-2").dt.strftime("%Y-%m-%dT%H:%M:%S.%f+02:00")
    west = t.dt.tz_convert("Etc/GMT+5").dt.strftime("%Y-%m-%dT%H:%M:%S.%f-05:00")
    stamps = np.where(codes % 2 == 0, east, west)
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["vessel_id,datetime,latitude,longitude"] + [
        f"{b},{s},{la},{lo}" for b, s, la, lo in zip(points["batch"], stamps, lat, lon, strict=True)
    ]
    return Variant("iso_offset", _write(folder / "iso_offset.csv", lines))


def naive_local(points: pd.DataFrame, folder: Path) -> Variant:
    local = _utc(points).dt.tz_convert("Europe/Copenhagen").dt.strftime("%Y-%m-%d %H:%M:%S.%f")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["track,time,lat,lon"] + [
        f"{b},{s},{la},{lo}" for b, s, la, lo in zip(points["batch"], local, lat, lon, strict=True)
    ]
    return Variant(
        "naive_local_tz", _write(folder / "local.csv", lines), ["--tz", "Europe/Copenhagen"]
    )


def relative(points: pd.DataFrame, folder: Path) -> Variant:
    """Seconds from the scene's start (a simulator's or a trial's own clock)."""
    s = _unix_s(_utc(points))
    rel = s - s.min()
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["target,t,lon,lat"] + [
        f"{b},{_num(r)},{lo},{la}"
        for b, r, lo, la in zip(points["batch"], rel, lon, lat, strict=True)
    ]
    return Variant("relative_seconds", _write(folder / "relative.csv", lines))


def messy(points: pd.DataFrame, folder: Path, seed: int = 0) -> Variant:
    """Extra columns (one quoted with a comma), rows in random order, a BOM, a blank line and
    a trailing summary line."""
    t = _utc(points)
    order = np.random.default_rng(seed).permutation(len(points))
    p = points.iloc[order].reset_index(drop=True)
    stamps = t.iloc[order].dt.strftime("%Y-%m-%d %H:%M:%S.%f").to_numpy()
    lat, lon = _fmt(p["lat"]), _fmt(p["lon"])
    sog, cog = _opt(p, "speed"), _opt(p, "course")
    lines = ["Row,Operator,Vessel ID,Time (UTC),Lat,Lon,Speed (kn),Course (deg),Remark"] + [
        f'{k},ops,{b},{s},{la},{lo},{v},{c},"checked, ok"'
        for k, (b, s, la, lo, v, c) in enumerate(
            zip(p["batch"], stamps, lat, lon, sog, cog, strict=True)
        )
    ]
    lines += ["", f"Total,{len(p)} rows,,,,,,,"]
    return Variant(
        "bom_extra_shuffled_summary", _write(folder / "messy.csv", lines, "utf-8-sig"), [], 2
    )


def utf16_tab(points: pd.DataFrame, folder: Path) -> Variant:
    """Excel's "Unicode text": UTF-16 with BOM, tab-separated, CRLF."""
    stamps = _utc(points).dt.strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["MMSI\tTime\tLatitude\tLongitude"] + [
        f"{b}\t{s}\t{la}\t{lo}"
        for b, s, la, lo in zip(points["batch"], stamps, lat, lon, strict=True)
    ]
    return Variant("utf16_tab", _write(folder / "unicode.txt.csv", lines, "utf-16", "\r\n"))


def nmea(points: pd.DataFrame, folder: Path) -> Variant | None:
    """A raw AIS log: type 1 position reports behind tag blocks carrying the unix time
    (positions rounded to 1/10000 minute, as AIS sends them). None when the batches are
    not MMSIs."""
    from pyais import encode_dict

    s = _unix_s(_utc(points))
    if not points["batch"].astype(str).str.fullmatch(r"\d{1,9}").all():
        return None
    # 102.3 kn and 360° are AIS's "not available" (a set without SOG/COG)
    sog = points["speed"] if "speed" in points.columns else pd.Series(102.3, points.index)
    cog = points["course"] if "course" in points.columns else pd.Series(360.0, points.index)
    lines = []
    for b, u, lo, la, v, c in zip(
        points["batch"],
        s,
        points["lon"],
        points["lat"],
        sog.fillna(102.3),
        cog.fillna(360.0),
        strict=True,
    ):
        msg = {"type": 1, "mmsi": int(b), "lon": float(lo), "lat": float(la)}
        msg.update(speed=min(float(v), 102.3), course=float(c) % 360.0 if c < 360 else 360.0)
        (sentence,) = encode_dict(msg, radio_channel="A", talker_id="AI", sentence_type="VDM")
        tag = f"s:rx1,c:{int(round(u))}"
        check = 0
        for ch in tag:
            check ^= ord(ch)
        lines.append(f"\\{tag}*{check:02X}\\{sentence}")
    return Variant("nmea_tag_blocks", _write(folder / "ais.nmea", lines), exact=False)


def date_and_clock(points: pd.DataFrame, folder: Path) -> Variant:
    """The date and the clock time in two columns (day-first dates)."""
    t = _utc(points)
    day, clock = t.dt.strftime("%d/%m/%Y"), t.dt.strftime("%H:%M:%S.%f")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["MMSI,Date,Time,Latitude,Longitude"] + [
        f"{b},{d},{c},{la},{lo}"
        for b, d, c, la, lo in zip(points["batch"], day, clock, lat, lon, strict=True)
    ]
    return Variant("date_and_clock_columns", _write(folder / "date_time.csv", lines))


def twelve_hour(points: pd.DataFrame, folder: Path) -> Variant:
    """A US spreadsheet's month-first dates with a 12-hour clock (whole seconds)."""
    stamps = _utc(points).dt.strftime("%m/%d/%Y %I:%M:%S %p")
    lat, lon = _fmt(points["lat"]), _fmt(points["lon"])
    lines = ["MMSI,BaseDateTime,LAT,LON"] + [
        f"{b},{s},{la},{lo}" for b, s, la, lo in zip(points["batch"], stamps, lat, lon, strict=True)
    ]
    return Variant("twelve_hour_clock", _write(folder / "ampm.csv", lines))


def _dm(values, pos: str, neg: str) -> list[str]:
    out = []
    for v in values:
        a = abs(float(v))
        deg = int(a)
        out.append(f"{deg}°{(a - deg) * 60:.7f}'{pos if v >= 0 else neg}")
    return out


def degrees_minutes(points: pd.DataFrame, folder: Path) -> Variant:
    """Positions in degrees and decimal minutes with a hemisphere (a chart plotter's or a
    radar console's export): 57°40.0260000'N."""
    stamps = _utc(points).dt.strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    lat, lon = _dm(points["lat"], "N", "S"), _dm(points["lon"], "E", "W")
    lines = ["Target,Time,Latitude,Longitude"] + [
        f"{b},{s},{la},{lo}" for b, s, la, lo in zip(points["batch"], stamps, lat, lon, strict=True)
    ]
    return Variant("degrees_minutes", _write(folder / "plotter.csv", lines))


LAYOUTS = (
    marinecadastre,
    dma,
    radar,
    chinese,
    semicolon_comma,
    epoch_ms,
    iso_offset,
    naive_local,
    relative,
    messy,
    utf16_tab,
    date_and_clock,
    twelve_hour,
    degrees_minutes,
    nmea,
)


def write_variants(points: pd.DataFrame, folder: Path, layouts=LAYOUTS) -> list[Variant]:
    """Every layout of ``points`` in its own subfolder of ``folder``."""
    out = []
    for make in layouts:
        sub = Path(folder) / make.__name__
        sub.mkdir(parents=True, exist_ok=True)
        v = make(points, sub)
        if v is not None:
            out.append(v)
    return out

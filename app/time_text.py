"""Times for the operator: dates in the display zone (UTC unless View ▸ Time zone says
otherwise, h191), or elapsed time for scene-relative data.

The display zone is the window's: UTC, the zone the data came in (the import's time zone,
kept in the layer's report and so in the project) or this computer's. Every date shown
(batch table, time slider, Statistics dock, review Gantt) names it ("UTC+8"); files and
exports keep their own times (the core stores UTC).

MTAD and the Øresund encounters count seconds from a scene start; the importer reads those
as seconds after 1970-01-01. Shown as dates they would read "1970-01-01 00:16:23"; they
are shown as elapsed time ``T+0:16:23`` instead.
"""

import datetime
import math

import numpy as np
import pandas as pd

# scene-relative times are told apart and written in core (step summaries say them too)
from wakeline.core.timeline import RELATIVE_LIMIT_S, format_elapsed, is_relative_time  # noqa: F401

#: View ▸ Time zone's choices: UTC, the zone the data came in, this computer's.
ZONE_CHOICES = ("utc", "data", "local")
#: The choice when the settings keep none: the data's zone when the import named one
#: (else UTC, as :func:`zone_for` falls back).
DEFAULT_ZONE_CHOICE = "data"
#: The zone dates are shown in (None: UTC) and its name in the window.
_display: dict = {"zone": None, "label": "UTC"}


def offset_label(zone: datetime.tzinfo | None, at_s: float | None = None) -> str:
    """``UTC``, ``UTC+8``, ``UTC-3:30``: the zone's offset at ``at_s`` (s since 1970;
    now when None)."""
    if zone is None:
        return "UTC"
    at = datetime.datetime.fromtimestamp(
        at_s if at_s is not None and math.isfinite(at_s) else datetime.datetime.now().timestamp(),
        tz=datetime.UTC,
    )
    off = zone.utcoffset(at.astimezone(zone).replace(tzinfo=None)) or datetime.timedelta(0)
    minutes = int(off.total_seconds() // 60)
    if minutes == 0:
        return "UTC"
    sign = "+" if minutes > 0 else "-"
    h, m = divmod(abs(minutes), 60)
    return f"UTC{sign}{h}" + (f":{m:02d}" if m else "")


def zone_for(
    choice: str, data_zone: str | None, at_s: float | None = None
) -> tuple[datetime.tzinfo | None, str]:
    """(zone, its label) of View ▸ Time zone's ``choice`` (:data:`ZONE_CHOICES`):
    ``data`` is ``data_zone`` (the import's time zone: an IANA name or ±HH:MM), UTC when
    there is none or it cannot be read; ``local`` this computer's zone."""
    zone: datetime.tzinfo | None = None
    if choice == "local":
        zone = datetime.datetime.now().astimezone().tzinfo
    elif choice == "data" and data_zone and str(data_zone).upper() not in ("UTC", "Z", "GMT"):
        from wakeline.core.errors import InputError
        from wakeline.core.io.reader import parse_zone

        try:
            zone = parse_zone(str(data_zone))
        except InputError:
            zone = None
    label = offset_label(zone, at_s)
    return (None if label == "UTC" and choice != "local" else zone), label


def set_display_zone(zone: datetime.tzinfo | None, label: str = "UTC") -> None:
    """Dates from now on shown in ``zone`` (None: UTC), named ``label``."""
    _display["zone"] = zone
    _display["label"] = label


def display_zone() -> datetime.tzinfo | None:
    """The zone dates are shown in (None: UTC)."""
    return _display["zone"]


def zone_label() -> str:
    """The display zone's name in the window (``UTC``, ``UTC+8``)."""
    return _display["label"]


def zone_title(title: str) -> str:
    """A translated column title naming UTC (``开始 (UTC)``) naming the display zone
    instead (``开始 (UTC+8)``)."""
    return title.replace("(UTC)", f"({zone_label()})")


def wall_clock(values) -> pd.Series:
    """Times (anything ``pd.to_datetime`` reads as UTC) as the display zone's wall clock,
    zone-less (vectorized: one ``tz_convert`` over the column)."""
    s = pd.to_datetime(pd.Series(values), utc=True)
    zone = display_zone()
    if zone is not None:
        s = s.dt.tz_convert(zone)
    return s.dt.tz_localize(None)


def format_time(seconds: float, relative: bool) -> str:
    """A time for the operator: elapsed (``T+…``) when ``relative``, else a date in the
    display zone, named (``2026-12-05 08:00:00 UTC+8``)."""
    if not math.isfinite(seconds):
        return "—"
    if relative:
        return format_elapsed(seconds)
    ts = pd.Timestamp(round(seconds * 1000.0), unit="ms", tz="UTC")
    zone = display_zone()
    if zone is not None:
        ts = ts.tz_convert(zone)
    text = ts.strftime("%Y-%m-%d %H:%M:%S")
    label = zone_label() if zone is None else offset_label(zone, seconds)
    return text + (f".{ts.microsecond // 1000:03d}" if ts.microsecond else "") + " " + label


def format_times(seconds: np.ndarray, relative: bool) -> list[str]:
    """:func:`format_time` of every value (for a table column)."""
    return [format_time(float(v), relative) for v in np.asarray(seconds, dtype="float64")]

"""The engine's messages speak of command-line flags (``--tz``, ``--map``, ``--encoding``);
in the window the same advice names the import dialog's fields (operator test: a log
warning told a window user to "give the zone with --tz")."""

import re

from wakeline.core.clean import STEPS

# Whole phrases first (they read best), then any flag left over.
_PHRASES = (
    (
        "give the zone with --tz (e.g. --tz Asia/Shanghai or --tz +08:00)",
        "choose the zone in the import dialog's Time zone field (File ▸ Open tracks…; "
        "e.g. Asia/Shanghai or +08:00)",
    ),
    (
        "give their zone with --tz (e.g. --tz Asia/Shanghai; times with a zone keep it)",
        "choose their zone in the import dialog's Time zone field (File ▸ Open tracks…; "
        "e.g. Asia/Shanghai; times with a zone keep it)",
    ),
    (
        "if they are local times, --tz Asia/Shanghai)",
        "if they are local times, choose Asia/Shanghai in the import dialog's Time zone field)",
    ),
    (
        "map it: --map batch=COLUMN, or --map sensor=COLUMN",
        "map it to batch or sensor in the import dialog's Column mapping (File ▸ Open tracks…)",
    ),
    (
        "with --encoding (e.g. gb18030, utf-16, latin-1)",
        "in the import dialog's Encoding field (File ▸ Open tracks…; e.g. gb18030, utf-16, "
        "latin-1)",
    ),
    (
        "(--encoding, e.g. gb18030, utf-16, latin-1)",
        "(the import dialog's Encoding field, File ▸ Open tracks…; e.g. gb18030, utf-16, latin-1)",
    ),
    (
        "give the file's encoding (--encoding, e.g. gb18030",
        "choose the file's encoding in the import dialog's Encoding field (File ▸ Open "
        "tracks…; e.g. gb18030",
    ),
    ("give the right --encoding", "choose the right Encoding in the import dialog"),
    ("give --encoding utf-16", "choose the Encoding utf-16 in the import dialog"),
    ("map columns with --map field=column", "map the columns in the import dialog"),
    (
        "; --map batch=target reads one track per target",
        "; the import dialog's Column mapping with batch = target reads one track per target",
    ),
    (
        "with --origin LAT,LON",
        "in the import dialog's Origin of x/y metres field (File ▸ Open tracks…; LAT, LON)",
    ),
    (
        " (--set speed.split_at_breaks=true splits there)",
        " (turning on Parameters ▸ Cleaning ▸ speed ▸ split_at_breaks splits there)",
    ),
    (" with --set", " in the Parameters panel"),
    ("(--time-base union keeps it)", "(time_base union in the Parameters panel keeps it)"),
    ("(--time-base union keeps them)", "(time_base union in the Parameters panel keeps them)"),
    ("(--tracks FILE)", "(File ▸ Open bearings…, Gate on tracks)"),
    (
        "split it by a target column (--map target=COLUMN)",
        "split it by a target column (Open bearings' Column mapping, target)",
    ),
    ("--date-order month-first", "the import dialog's Date order set to month first"),
    ("--date-order day-first", "the import dialog's Date order set to day first"),
    ("--time-unit excel-days", "the import dialog's Time numbers set to Excel serial days"),
    ("--time-unit seconds", "the import dialog's Time numbers set to seconds"),
    (
        "give their day with --date YYYY-MM-DD",
        "give their day in the import dialog's Date of clock times field (YYYY-MM-DD)",
    ),
    ("(--date)", "(the import dialog's Date of clock times)"),
    ("read them with --speed-unit km/h", "choose km/h in the import dialog's Speed unit field"),
    ("read them with --speed-unit m/s", "choose m/s in the import dialog's Speed unit field"),
    ("read them with --speed-unit mph", "choose mph in the import dialog's Speed unit field"),
)
_FIELDS = {
    "tz": "Time zone",
    "map": "Column mapping",
    "encoding": "Encoding",
    "format": "Layout",
    "sensor": "Sensor",
    "delimiter": "Layout",
    "skip-rows": "Lines above the header",
    "origin": "Origin of x/y metres",
    "date-order": "Date order",
    "time-unit": "Time numbers",
    "date": "Date of clock times",
}
#: A flag and its value, if any: quoted as the engine quotes what it refuses ('95,10',
#: kept), or a bare value (dropped: the field holds it) — not a parenthesis after the
#: flag, and a value's commas kept when no space follows them (``--origin 60,10``: the
#: whole pair).
_FLAG = re.compile(
    r"--(" + "|".join(_FIELDS) + r")\b"
    r"(?:[ =](?:('[^']*')|(?![-(])[^\s,;:)]+(?:,[^\s,;:)]+)*))?"
)


def _field(m: re.Match) -> str:
    quoted = f" ({m.group(2)})" if m.group(2) else ""
    return f"the import dialog's {_FIELDS[m.group(1)]} field{quoted}"


# Several --map flags in a row (a suggested mapping): one field, the choices listed.
_MAP_VALUE = r"(?:'[^']*'|(?!-)[^\s,;:)]+)"
_MAP_RUN = re.compile(rf"--map[ =]{_MAP_VALUE}(?:\s+--map[ =]{_MAP_VALUE})+")


def _map_run(m: re.Match) -> str:
    values = re.findall(rf"--map[ =]({_MAP_VALUE})", m.group(0))
    choices = ", ".join(v.strip("'") for v in values)
    return f"the import dialog's Column mapping ({choices})"


#: ``--set RULE.PARAM=VALUE`` of a cleaning rule: its place in the Parameters panel (in
#: a summary already in the window's language, whose sentence around it is translated).
_SET_CLEAN = re.compile(r"--set (" + "|".join(STEPS) + r")\.(\w+)=([\w.+-]+)")


def _set_clean(m: re.Match) -> str:
    return f"Parameters ▸ Cleaning ▸ {m.group(1)} ▸ {m.group(2)} = {m.group(3)}"


#: ``--set NAME=VALUE`` of a step's own parameter (``mmsi_apart``: no rule before it).
_SET_FIELD = re.compile(r"--set (\w+)=([\w.+-]+)")


def _set_field(m: re.Match) -> str:
    """A step parameter's ``--set`` as its place in the Parameters panel, said as the panel
    says it (its group's title, its row's label, in the window's language; a tick box
    ticked or not): the Chinese log told the window's operator "用 --set mmsi_apart=false
    关闭" (operator test 11, F23). A name the panel does not show is left as it is."""
    import dataclasses

    from PySide6.QtCore import QCoreApplication

    from wakeline.app.params_panel import GROUPS, field_title

    name, value = m.group(1), m.group(2)
    for _key, title, cls in GROUPS:
        fields = {f.name: f for f in dataclasses.fields(cls)}
        if name not in fields:
            continue
        f = fields[name]
        label = field_title(cls, f) or name
        if isinstance(f.default, bool) and value.lower() in ("true", "false"):
            said = (
                QCoreApplication.translate("WindowWords", "ticked")
                if value.lower() == "true"
                else QCoreApplication.translate("WindowWords", "unticked")
            )
        else:
            said = f"= {value}"
        return QCoreApplication.translate("WindowWords", "{0} ▸ {1} ▸ {2} ({3})").format(
            QCoreApplication.translate("MainWindow", "Parameters"),
            QCoreApplication.translate("ParamsPanel", title),
            label,
            said,
        )
    return m.group(0)


def window_words(text: str) -> str:
    """``text`` with command-line flags replaced by the import dialog's fields (and a
    ``--set`` by its place in the Parameters panel)."""
    if "--" not in text:
        return text
    text = _SET_FIELD.sub(_set_field, text)
    for cli, window in _PHRASES:
        text = text.replace(cli, window)
    text = _SET_CLEAN.sub(_set_clean, text)
    text = _MAP_RUN.sub(_map_run, text)
    return _FLAG.sub(_field, text)

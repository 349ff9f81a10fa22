"""The pipeline steps on the command line, generated from the core's step registry.

Every step of :data:`wakeline.core.pipeline.STEPS` becomes a subcommand
(``wakeline clean|maneuvers|compress|associate|fuse IN -o OUT``) whose flags are made from
the step's parameter dataclasses: each field is ``--field-name`` (type, unit, range and
meaning in the help), ``--set NAME=VALUE`` changes any of them, and a few older spellings
(``--window``, ``--tolerance`` …) stay. The command runs the same function the desktop
application runs and writes the step's tables with the same writers.
"""

import argparse
import dataclasses
import sys
from pathlib import Path

from wakeline.app.cli_common import EPILOG, positive_int, whole_int
from wakeline.core.errors import InputError
from wakeline.core.params import shown_source
from wakeline.core.words import count

#: Older flag spellings kept beside the generated ones: (parameter set, field) -> flags.
ALIASES = {
    ("maneuver", "window_p"): ("--window",),
    ("maneuver", "radius_n"): ("--radius",),
    ("maneuver", "threshold_deg"): ("--threshold",),
    ("compress", "dp_tolerance_m"): ("--tolerance",),
    ("maneuver", "min_speed_kn"): ("--min-speed",),
}
RESERVED = {"input", "output", "report", "set", "help", "preset"}

TEXTS = {
    "clean": (
        "remove duplicates, stationary points, jumps and outliers, with a reject trail",
        "Apply the cleaning rules in order: duplicates, stationary, speed, turn, speed_outliers, "
        "isolated, short_tracks (seed 001 §4.1, seed 003 §2.2), then the opt-in transforming "
        "steps bspline, resample, smooth. Every removed, changed or replaced point goes to the "
        "rejected table with the rule, the action and the parameters.",
    ),
    "maneuvers": (
        "find maneuver (turning) points",
        "Seed 000's detector: heading of p points by PCA before and after each point, maneuver "
        "factor = their difference (deg), kept where above the threshold and the maximum within "
        "+-n points. Writes one row per maneuver point: sensor,batch,index,time,lon,lat,factor "
        "(index = 0-based position in the time-sorted track). --method imm|entropy runs the "
        "seed-000 baselines.",
    ),
    "compress": (
        "compress tracks to their turning points",
        "Keep each track's first and last point and its maneuver points (or Douglas-Peucker "
        "points); vertices are placed by least squares on the track's points unless "
        "--raw-vertices. The report gives Dis_e (mean synchronized distance, metres; also "
        "against the true path when the input has true_lon/true_lat) and the share of points "
        "kept, per track and overall.",
    ),
    "associate": (
        "join the tracks of one sensor that belong to one ship",
        "interrupted (default): old track i and new track j of one sensor with j starting "
        "within max_gap_s after i ends and reachable at v_max_kn; distance from i's end to j's "
        "start by position (dead-reckoned, allowing one course change), course and speed; "
        "optimal one-to-one assignment (or seed 003's greedy). segments: seed 001's clustering "
        "of segments (area S and directional mean, or DTW/Hausdorff baselines; 'motion' = our "
        "distance). Writes every input row with a 'target' column; --stitch joins each target "
        "into one batch and fills the gaps.",
    ),
    "fuse": (
        "pair the tracks of two or more sensors and fuse each pair into one track",
        "Tracks of different sensors that overlap in time, were near each other at some moment "
        "and have comparable point counts are compared by their mean synchronized distance (or "
        "DTW over positions) and paired one-to-one (optimal, or seed 003's greedy) up to "
        "max_distance_m. Each target becomes one track: sensor 'fused', batch = the target, "
        "named after its earliest track (sensor:batch, as the review names it); "
        "where several sensors cover the time, the positions are averaged with weights from "
        "each track's sampling regularity and noise, on the times --time-base says (default: "
        "the highest-weight track's; the summary counts the other tracks' fixes not kept); "
        "elsewhere the single sensor's points; junctions blended. Columns added: source, "
        "n_sources, weight_base, members.",
    ),
}
OUTPUT_HELP = {
    "points": "points, canonical CSV",
    "maneuvers": "maneuver points CSV to write",
}
EXTRA_HELP = {
    "rejected": "write every removed or changed point",
    "pairs": "write the joined pairs with their distances",
    "proposals": "write one row per proposed join with its evidence (cost and its parts, "
    "runner-up, margin) for `wakeline review`",
}


def _is_flat(cls: type) -> bool:
    return dataclasses.is_dataclass(cls) and not hasattr(cls, "with_settings")


def param_flag_table(sets) -> list[tuple[str, dataclasses.Field, list[str]]]:
    """(parameter set, field, flags) for every field of ``sets`` ((key, dataclass) pairs):
    ``--field-name``, or ``--key-field-name`` where a later set or a reserved name has it,
    and the older spellings of :data:`ALIASES`."""
    owner: dict[str, str] = {}
    for key, cls in reversed(sets):  # later sets (the step's options) keep the plain name
        for f in dataclasses.fields(cls):
            owner.setdefault(f.name, key)
    out = []
    for key, cls in sets:
        for f in dataclasses.fields(cls):
            plain = f.name.replace("_", "-")
            if owner[f.name] == key and f.name not in RESERVED:
                flags = [f"--{plain}"]
            else:
                flags = [f"--{key.replace('_', '-')}-{plain}"]
            flags += [a for a in ALIASES.get((key, f.name), ()) if a not in flags]
            out.append((key, f, flags))
    return out


def add_param_flags(p: argparse.ArgumentParser, sets) -> None:
    """One flag per field of ``sets`` ((key, dataclass) pairs; :func:`param_flag_table`),
    dest ``p__KEY__FIELD`` and no default: a flag given is in the namespace, whatever its
    value, and one not given is not (:func:`given_params`)."""
    for key, f, flags in param_flag_table(sets):
        kw = {
            "dest": f"p__{key}__{f.name}",
            "default": argparse.SUPPRESS,
            "help": _field_help(f),
        }
        if isinstance(f.default, bool):
            kw["action"] = argparse.BooleanOptionalAction
        else:
            kw["metavar"] = f.metadata.get("unit") or type(f.default).__name__
            if f.metadata.get("choices"):
                kw["choices"] = [c for c in f.metadata["choices"] if c]
                kw["metavar"] = None
        p.add_argument(*flags, **kw)


def given_params(args: argparse.Namespace, sets) -> dict[str, dict[str, object]]:
    """The fields of ``sets`` whose flag (:func:`add_param_flags`) was given: key -> {field:
    value as typed}."""
    values: dict[str, dict[str, object]] = {key: {} for key, _cls in sets}
    for key, f, _flags in param_flag_table(sets):
        dest = f"p__{key}__{f.name}"
        if hasattr(args, dest):
            values[key][f.name] = getattr(args, dest)
    return values


def _field_help(f: dataclasses.Field) -> str:
    m = f.metadata
    unit = f" [{m['unit']}]" if m.get("unit") else ""
    rng = ""
    if m.get("lo") is not None or m.get("hi") is not None:
        rng = (
            f", {'' if m.get('lo') is None else m['lo']}..{'' if m.get('hi') is None else m['hi']}"
        )
    src = f"; {shown_source(m['source'])}" if m.get("source") else ""
    default = f.default if f.default != "" else "auto"
    return f"{m.get('doc', '')}{unit} (default {default}{rng}{src})".replace("%", "%%")


def _clean_help() -> str:
    from wakeline.core.clean import CleanParams

    lines = []
    for d in CleanParams.describe():
        unit = f" [{d['unit']}]" if d.get("unit") else ""
        source = f" ({shown_source(d['source'])})" if d.get("source") else ""
        lines.append(f"{d['rule']}.{d['name']}={d['default']}{unit}: {d['doc']}{source}")
    return "Rules and parameters (--set rule.param=value):\n  " + "\n  ".join(lines)


def add_step_parsers(sub) -> None:
    """One subcommand per registered step."""
    from wakeline.core.pipeline import STEPS

    for name, step in STEPS.items():
        help_, description = TEXTS.get(name, (step.title, step.title))
        epilog = EPILOG
        formatter = argparse.HelpFormatter
        if name == "clean":
            epilog = _clean_help() + "\n\n" + EPILOG
            formatter = argparse.RawDescriptionHelpFormatter
        p = sub.add_parser(
            name, help=help_, description=description, epilog=epilog, formatter_class=formatter
        )
        if step.many_inputs:
            p.add_argument(
                "input",
                type=Path,
                nargs="+",
                help="track files (any layout `wakeline import` reads): one of several "
                "sensors, or one per sensor (files of one sensor each take the differing "
                "part of their names as sensor)",
            )
        else:
            p.add_argument(
                "input", type=Path, help="track file (any layout `wakeline import` reads)"
            )
        p.add_argument(
            "-o", "--output", type=Path, required=True, help=OUTPUT_HELP.get(step.output, "")
        )
        for table, flag in step.outputs:
            p.add_argument(
                flag,
                type=Path,
                dest=f"out__{table}",
                metavar="FILE.csv",
                help=EXTRA_HELP.get(table),
            )
        p.add_argument(
            "--report", type=Path, metavar="R.json", help="write the report and parameters as JSON"
        )
        if step.output == "points":
            add_derive_motion_flag(p)
        p.add_argument(
            "--set",
            action="append",
            metavar="NAME=VALUE",
            help="change a parameter (clean: RULE.PARAM=VALUE); repeatable",
        )
        add_param_flags(p, [(key, cls) for key, cls in step.params if _is_flat(cls)])
        if name == "compress":
            p.add_argument(
                "--raw-vertices",
                dest="p__compress__refine",
                action="store_false",
                default=argparse.SUPPRESS,
                help="keep the raw points as vertices (the paper's way; = --no-refine)",
            )
        if any(hasattr(cls, "paper") for _key, cls in step.params):
            p.add_argument(
                "--paper",
                action="store_true",
                help="start from the paper's parameters (e.g. seed 000 as written: windows "
                "in points, one scale, no speed, noise or rest rules, raw vertices); "
                "flags given still apply",
            )
        add_preset_flag(p, [key for key, _cls in step.params])
        if name == "clean":
            _add_clean_flags(p)
        add_read_flags(p)
        p.set_defaults(func=run_step_command, step=name)
    p = sub.add_parser(
        "presets",
        help="list the built-in parameter presets (--preset NAME)",
        description="The built-in parameter presets: measured settings that are options, not "
        "defaults (each failed a guard fixed before its runs somewhere), for the data each "
        "suits; their purpose, changes and evidence (docs/evaluation.md). The "
        "step commands, `evaluate maneuver` and `batch` take --preset NAME; flags given still "
        "apply.",
        epilog=EPILOG,
    )
    p.set_defaults(func=_cmd_presets)


def _cmd_presets(_args: argparse.Namespace) -> int:
    from wakeline.core.presets import preset_lines

    print("\n".join(preset_lines()))
    return 0


class _PresetAction(argparse.Action):
    """``--preset NAME``; ``--preset list`` prints the presets and exits (as ``--version``
    does: before the required arguments are missed)."""

    def __call__(self, parser, namespace, values, option_string=None):
        if values == "list":
            from wakeline.core.presets import preset_lines

            print("\n".join(preset_lines()))
            parser.exit()
        from wakeline.core.presets import retired_note

        note = retired_note(values)
        if note:  # a retired preset: accepted, changes nothing (core.presets.RETIRED)
            print(f"wakeline: note: {note}", file=sys.stderr)
        setattr(namespace, self.dest, values)


class _Choices(list):
    """``--preset``'s choices: the names listed (an invalid choice's error names these)
    and the ``hidden`` ones also taken (retired presets)."""

    def __init__(self, names, hidden):
        super().__init__(names)
        self.hidden = tuple(hidden)

    def __contains__(self, value) -> bool:
        return value in self.hidden or super().__contains__(value)


def add_preset_flag(p: argparse.ArgumentParser, keys: list[str] | None = None) -> None:
    """``--preset NAME`` on a command whose parameter sets (``keys``; None: any) some
    built-in preset changes (:mod:`wakeline.core.presets`); nothing otherwise. A retired
    preset's name (``RETIRED``) that applied there is still taken, not listed: a note, no
    change."""
    from wakeline.core.presets import RETIRED, presets

    names = [
        name
        for name, pr in presets().items()
        if keys is None or any(pr.changes.get(key) for key in keys)
    ]
    if not names:
        return
    retired = [r.name for r in RETIRED.values() if keys is None or set(r.keys) & set(keys)]
    p.add_argument(
        "--preset",
        action=_PresetAction,
        choices=_Choices([*names, "list"], retired),
        metavar="NAME",
        help=f"start from a built-in preset: {', '.join(names)} (`wakeline presets` or "
        "--preset list gives their purpose and evidence); flags given still apply",
    )


def _add_clean_flags(p: argparse.ArgumentParser) -> None:
    from wakeline.app.cli_common import positive_float
    from wakeline.core.clean import RULES

    p.add_argument(
        "--off",
        action="append",
        choices=RULES,
        metavar="RULE",
        help="switch a rule off; repeatable",
    )
    p.add_argument(
        "--resample",
        type=positive_float,
        metavar="SECONDS",
        help="resample every track to this period (seed 003 uses 20 s)",
    )
    p.add_argument(
        "--max-gap",
        type=positive_float,
        metavar="SECONDS",
        help="resample: never interpolate across longer gaps. Given, it is the limit; "
        "by default 60 s, and on a sparse track a step up to 2 of its median steps "
        "(resample.max_gap_steps), never above 600 s (resample.max_gap_cap_s), is no gap",
    )
    p.add_argument(
        "--smooth",
        type=positive_int,
        nargs="?",
        const=5,
        metavar="WINDOW",
        help="moving weighted average of positions over WINDOW points (default 5)",
    )
    p.add_argument(
        "--bspline",
        action="store_true",
        help="seed 001 sampling-segmentation-B-spline-interpolation (splits batches holding two ships)",
    )
    p.add_argument(
        "--restore",
        type=Path,
        metavar="LIST.csv",
        help="put back, after cleaning, the points whose wl_id LIST.csv lists (rows of a "
        "--rejected table of the same input and parameters, kept in a spreadsheet or by a "
        "filter: the window's Restore, for batch work)",
    )
    p.add_argument(
        "--restore-rule",
        action="append",
        metavar="RULE",
        help="put back, after cleaning, every point RULE removed or changed (unlike --off "
        "RULE, the later rules ran without them); repeatable",
    )


def add_read_flags(
    p: argparse.ArgumentParser,
    *,
    rename: tuple[str, ...] = (),
    omit: tuple[str, ...] = (),
    prefix: str = "in",
    description: str | None = None,
    helps: dict[str, str] | None = None,
) -> None:
    """How to read the input, for `wakeline import` and every command reading track files
    (a reading error names --map, so every one takes it), in a group of their own.

    A command whose own flags already use some of these names (``export``'s --format,
    --map, --encoding, --tz shape the file it writes) gets those as ``--PREFIX-NAME``
    (``rename``); ``omit`` leaves flags out (``evaluate``'s --sensor is another thing);
    ``description`` says under the group's title what the flags apply to; ``helps``
    (flag name → text) says what a flag means for a command that reads another kind of
    file (``bearing``'s --map takes the bearing fields).
    :func:`read_options` gives the ``read_points`` keywords whatever the flags are named.
    """
    from wakeline.core.io import FAMILIES
    from wakeline.core.io.formats import DISTANCE_UNITS, SPEED_UNITS
    from wakeline.core.io.reader import DATE_ORDERS, TIME_UNITS

    flags = {  # read_points keyword -> (flag name, argparse keywords)
        "fmt": (
            "format",
            {"choices": FAMILIES, "default": "auto", "help": "input layout (default: auto-detect)"},
        ),
        "mapping": (
            "map",
            {
                "action": "append",
                "metavar": "FIELD=COLUMN",
                "help": "take canonical FIELD (sensor, batch, time, lon, lat, speed, course, "
                "truth; with --origin east, north, range, bearing, east_offset, "
                "north_offset) from COLUMN; repeatable",
            },
        ),
        "encoding": (
            "encoding",
            {"help": "text encoding (default: detect UTF-8 / UTF-16 by BOM / GB18030)"},
        ),
        "delimiter": (
            "delimiter",
            {
                "help": "field delimiter: a character, tab, space or pipe (default: detect "
                ", ; tab | or columns aligned with blanks)"
            },
        ),
        "tz": (
            "tz",
            {
                "metavar": "ZONE",
                "help": "zone of times written without one: IANA name (Asia/Shanghai) or "
                "±HH:MM (default UTC; unix times are absolute and not shifted)",
            },
        ),
        "sensor": (
            "sensor",
            {
                "default": "S1",
                "help": "sensor name when the file has no sensor column (default S1)",
            },
        ),
        "origin": (
            "origin",
            {
                "metavar": "LAT,LON",
                "help": "origin (degrees) of a file whose positions are metres on a local "
                "plane (columns east/north or x/y, optionally plus own_east/own_north): "
                "the radar's site or the frame's zero",
            },
        ),
        "skip_rows": (
            "skip-rows",
            {
                "type": whole_int,
                "metavar": "N",
                "help": "lines before the header (a title), skipped and counted (default: "
                "detect a title above a header naming known columns)",
            },
        ),
        "date_order": (
            "date-order",
            {
                "choices": DATE_ORDERS,
                "default": "auto",
                "help": "slashed dates (03/04/2025): day-first (dd/mm/yyyy), month-first "
                "(mm/dd/yyyy), or auto: day first unless a second number above 12 shows the "
                "month first (default auto; the report says what decided it)",
            },
        ),
        "time_unit": (
            "time-unit",
            {
                "choices": TIME_UNITS,
                "default": "auto",
                "help": "numbers in the time column: seconds (unix s or ms, or from a scene "
                "start), excel-days (Excel serial days, 45658.5 = 2025-01-01 12:00), or "
                "auto: Excel days when all lie in 20000-80000 and the header says so or they "
                "step less than 0.01 between rows; else seconds (default auto)",
            },
        ),
        "speed_unit": (
            "speed-unit",
            {
                "choices": tuple(SPEED_UNITS),
                "default": "auto",
                "help": "unit of a speed column whose header names none (a header such as "
                "speed_mps, sog_kmh, Speed (m/s), 速度(km/h) names its own; default auto: "
                "knots); speeds are converted to knots",
            },
        ),
        "distance_unit": (
            "distance-unit",
            {
                "choices": tuple(DISTANCE_UNITS),
                "default": "auto",
                "help": "unit of local-plane x/y, offsets and range whose headers name none "
                "(x_km, range_nm, y_yd name their own; default auto: metres)",
            },
        ),
        "clock_date": (
            "date",
            {
                "metavar": "YYYY-MM-DD",
                "help": "the day of times written without a date (23:50:00.5, or HHMMSS "
                "numbers that step as a clock): read as times of day on it, a day later "
                "after each step back past midnight within a track (default: 1970-01-01, "
                "as relative times)",
            },
        ),
    }
    unknown = (set(rename) | set(omit) | set(helps or ())) - {n for n, _kw in flags.values()}
    if unknown:
        raise ValueError(f"no reading flag {sorted(unknown)}")
    group = p.add_argument_group("reading the input", description)
    dests = {}
    for keyword, (name, kw) in flags.items():
        if name in omit:
            continue
        flag = f"--{prefix}-{name}" if name in rename else f"--{name}"
        dests[keyword] = flag[2:].replace("-", "_")
        if helps and name in helps:
            kw = {**kw, "help": helps[name]}
        group.add_argument(flag, dest=dests[keyword], **kw)
    defaults = {k: flags[k][1].get("default") for k in dests}
    p.set_defaults(read_dests=dests, read_defaults=defaults)


def read_options(args: argparse.Namespace, given: bool = False) -> dict:
    """The ``read_points`` keywords of :func:`add_read_flags`' flags (those given to
    the command's parser, under the names it gave them); ``given``: only those whose
    value is not the flag's default."""
    out = {keyword: getattr(args, dest) for keyword, dest in args.read_dests.items()}
    if given:
        out = {k: v for k, v in out.items() if v != args.read_defaults.get(k)}
    return out


def _split_settings(settings: list[str] | None) -> list[tuple[str, str]]:
    out = []
    for text in settings or []:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise InputError(f"--set expects NAME=VALUE, got {text!r}")
        out.append((name.strip(), value.strip()))
    return out


def step_params(step, args: argparse.Namespace) -> dict:
    """The step's parameter sets from the generated flags, ``--set`` and clean's extras."""
    values: dict[str, dict[str, object]] = {key: {} for key, _ in step.params}
    values.update(given_params(args, [(k, c) for k, c in step.params if _is_flat(c)]))
    if hasattr(args, "p__compress__refine"):
        values["compress"]["refine"] = args.p__compress__refine
    flat = [(key, cls) for key, cls in step.params if _is_flat(cls)]
    nested = [(key, cls) for key, cls in step.params if not _is_flat(cls)]
    settings: list[str] = []
    for name, value in _split_settings(getattr(args, "set", None)):
        owner = next(
            (key for key, cls in flat if name in {f.name for f in dataclasses.fields(cls)}), None
        )
        if owner is not None:
            values[owner][name] = value
        elif nested:
            settings.append(f"{name}={value}")
        else:
            known = sorted({f.name for _, cls in flat for f in dataclasses.fields(cls)})
            raise InputError(f"unknown parameter {name!r}; known: {', '.join(known)}")
    if step.name == "clean":
        settings += [f"{rule}.enabled=false" for rule in args.off or []]
        if args.resample is not None:
            settings += ["resample.enabled=true", f"resample.period_s={args.resample}"]
        if args.max_gap is not None:
            settings += [f"resample.max_gap_s={args.max_gap}"]
        if args.smooth is not None:
            settings += ["smooth.enabled=true", f"smooth.window={args.smooth}"]
        if args.bspline:
            settings += ["bspline.enabled=true"]
    out = {}
    paper = getattr(args, "paper", False)
    base = {key: cls.paper() if paper and hasattr(cls, "paper") else cls() for key, cls in flat}
    if getattr(args, "preset", None):  # over the defaults (or --paper), under the flags
        from wakeline.core.presets import apply_preset

        base = apply_preset(args.preset, base)
    for key, _cls in flat:
        out[key] = base[key].replace(**values[key]).checked()
    for key, cls in nested:
        out[key] = cls().with_settings(settings).checked()
    return out


READ_KEYS = ("rows_read", "rows_imported", "rows_quarantined", "quarantine_reasons", "blank_lines")


def read_counts(report: dict) -> dict:
    """The reading's counts for a step's ``--report``: every line of the input is a point,
    a quarantine row, a blank line, the header or a line skipped above it (a title, or
    ``--skip-rows``), and the JSON says how many went where and why."""
    from wakeline.core.io.reader import skipped_above_header

    out = {key: report[key] for key in READ_KEYS if key in report}
    return out | {"skipped_above_header": skipped_above_header(report)}


def say_quarantined(path, report: dict, command: str = "import") -> None:
    """One line on stderr: how many rows reading quarantined, and why; ``command`` is the
    one whose ``--quarantine`` writes them."""
    n = report.get("rows_quarantined", 0)
    if not n:
        return
    print(
        f"{path}: {count(n, 'row')} quarantined on reading ({quarantine_reasons(report)}); run "
        f"`wakeline {command}` with --quarantine to see them",
        file=sys.stderr,
    )


def quarantine_reasons(report: dict, shown: int = 3) -> str:
    """The reasons rows were quarantined, most frequent first, each with its count: the
    first ``shown`` and how many more ('1 short row: 2 of 7 fields; 1 unparsable lat; 2
    more reasons'); one more is given rather than counted."""
    reasons = sorted(report.get("quarantine_reasons", {}).items(), key=lambda kv: -kv[1])
    if len(reasons) == shown + 1:
        shown += 1
    why = "; ".join(f"{k:,} {reason}" for reason, k in reasons[:shown])
    more = len(reasons) - shown
    return why + (f"; {count(more, 'more reason')}" if more > 0 else "")


def read_input(path: Path, counts: dict | None = None, **options):
    """Points of any layout ``import`` reads (``options``: read_points keywords);
    quarantined rows are counted on stderr and, when ``counts`` is given, into it."""
    from wakeline.core.io import nothing_imported, read_points

    result = read_points(path, **options)
    say_quarantined(path, result.report)
    if counts is not None:
        counts.update(read_counts(result.report))
    if len(result.points) == 0:
        raise InputError(nothing_imported(result.report, str(path)))
    return result.points


def write_table(name: str, table, path: Path) -> None:
    """How every step table is written (the GUI's export uses the same function)."""
    from wakeline.core.io import write_csv, write_points
    from wakeline.core.tracks import natural_track_order

    # tracks in natural order (batch 21 before 161), as clean writes them (D19); other
    # tables keep their order (clean's reject trail: by wl_id)
    if name in ("points", "maneuvers"):
        table = natural_track_order(table)
    (write_points if name == "points" else write_csv)(table, path)


DERIVE_MOTION_HELP = (
    "fill blank speed (kn) and course (deg) of the points written from their positions "
    "(SPEC §1: derived where missing; the leg arriving at each point) and add a column "
    "motion_derived naming what was derived on each row; given values are never changed "
    "(default: blanks stay blank)"
)


def add_derive_motion_flag(p: argparse.ArgumentParser) -> None:
    p.add_argument("--derive-motion", action="store_true", help=DERIVE_MOTION_HELP)


def derive_motion_in_file(path: Path) -> None:
    """Rewrite the canonical points file ``path`` (written by import or clean, which
    stream) with its blank speed/course derived (:func:`with_derived_motion`)."""
    from wakeline.core.io import read_points, write_points
    from wakeline.core.tracks import with_derived_motion

    pts = read_points(path).points  # in the file's row order, which is kept
    write_points(with_derived_motion(pts), path)


def run_step_command(args: argparse.Namespace) -> int:
    from wakeline.core.io import write_json
    from wakeline.core.pipeline import STEPS, params_to_json

    step = STEPS[args.step]
    params = step_params(step, args)
    if step.name == "clean":
        return _run_clean(step, params, args)
    read: dict = {}
    if step.many_inputs:
        from wakeline.app.cli_review import read_inputs

        points = read_inputs(args.input, read, **read_options(args))
    else:
        points = read_input(args.input, read, **read_options(args))
    result = step(points, params)
    table = result.tables[step.output]
    if getattr(args, "derive_motion", False):
        from wakeline.core.tracks import with_derived_motion

        table = with_derived_motion(table)
    write_table(step.output, table, args.output)
    for table, _flag in step.outputs:
        path = getattr(args, f"out__{table}", None)
        if path:
            write_table(table, result.tables[table], path)
    if args.report:
        extra = {"read": read} if read else {}
        write_json({**result.report, **extra, "params": params_to_json(params)}, args.report)
    print(step.summary(result), file=sys.stderr)
    return 0


def _run_clean(step, params: dict, args: argparse.Namespace) -> int:
    """``wakeline clean``: by blocks of whole tracks, writing as it goes (bounded memory,
    :func:`wakeline.core.clean_stream.clean_file`); the same outputs as the step."""
    from wakeline.core.clean_stream import clean_file
    from wakeline.core.io import write_json
    from wakeline.core.pipeline import StepResult, params_to_json

    rejected = getattr(args, "out__rejected", None)
    ids = _restore_list(args.restore) if getattr(args, "restore", None) else None
    out = clean_file(
        args.input,
        args.output,
        rejected,
        params["clean"],
        **read_options(args),
        restore_ids=ids,
        restore_rules=getattr(args, "restore_rule", None),
    )
    if args.derive_motion:
        derive_motion_in_file(args.output)
    for warning in out.read_report.get("warnings", []):
        print(f"{args.input}: warning: {warning}", file=sys.stderr)
    say_quarantined(args.input, out.read_report)
    if args.report:
        read = read_counts(out.read_report)
        write_json({**out.report, "read": read, "params": params_to_json(params)}, args.report)
    print(step.summary(StepResult("clean", [], out.report)), file=sys.stderr)
    back = out.report.get("restored")
    if back is not None:
        rules = ", ".join(f"{r} {n:,}" for r, n in back["rules"].items()) or "none"
        # said with the summary's arithmetic (kept + removed was more than the input:
        # "kept 6,662 of 18,834 …; removed 12,174" then "restored 2"; operator test 11)
        print(
            f"restored {back['points']:,} points ({rules}) after cleaning: the kept count "
            "above includes them, the removed count does not subtract them",
            file=sys.stderr,
        )
    return 0


def _restore_list(path: Path):
    """The ``wl_id`` values of ``clean --restore LIST.csv`` (a column of that name; any
    other columns are ignored: a --rejected table's rows, filtered)."""
    import pandas as pd

    from wakeline.core.errors import InputError

    try:
        header = pd.read_csv(path, nrows=0).columns
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"--restore {path}: {exc}") from None
    if "wl_id" not in header:
        raise InputError(
            f"--restore {path}: no wl_id column (headers found: {', '.join(header) or 'none'}); "
            "list rows of the --rejected table"
        )
    ids = pd.to_numeric(pd.read_csv(path, usecols=["wl_id"])["wl_id"], errors="coerce")
    if ids.isna().any():
        raise InputError(f"--restore {path}: wl_id must be whole numbers on every row")
    return ids.to_numpy().astype("int64")

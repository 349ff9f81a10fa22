"""``wakeline export``: points back in the operator's own layout (SPEC §8, issue 19).

``build_parser`` calls :func:`register` once.
"""

import argparse
import re
import sys
from pathlib import Path

from wakeline.app.cli_common import EPILOG, whole_int
from wakeline.core.errors import InputError
from wakeline.core.words import count


def _split(items: list[str] | None) -> list[str]:
    return [c.strip() for item in items or () for c in item.split(",") if c.strip()]


def _read_in(args: argparse.Namespace):
    """IN, read with the reading flags (a reading error names IN's --in-map)."""
    from wakeline.app.cli_steps import read_options
    from wakeline.core.io import read_points

    try:
        return read_points(args.input, **read_options(args))
    except InputError as exc:
        raise InputError(str(exc).replace("--map field", "--in-map field")) from None


def _like_flag(message: str) -> str:
    """A reading error about ORIGINAL (``--like``) with ``--skip-rows`` named as export's
    flag for ORIGINAL's count, ``--like-skip-rows`` (IN's count is ``--skip-rows``)."""
    return re.sub(r"(?<![\w-])--skip-rows\b", "--like-skip-rows", message)


def _packed_original(like: Path | None) -> str | None:
    """The compression of ``--like ORIGINAL`` (gzip, bz2, xz, zstd, zip), else None."""
    if like is None or Path(like).suffix.lower() == ".json":
        return None
    from wakeline.core.io.compressed import compression_of

    try:
        return compression_of(like)
    except (OSError, InputError):
        return None


def _in_flags_without_original(args: argparse.Namespace) -> None:
    """Without ``--like ORIGINAL`` there is no file for ``--map``/``--format`` to
    describe: they are IN's, as in every other command (D-cli-1; before, they were
    ignored without a word). Given with ``--in-map``/``--in-format`` too: refused."""
    moved = []
    for flag, own, keyword, unset in (
        ("--map", "map", "mapping", None),
        ("--format", "format", "fmt", "auto"),
    ):
        value = getattr(args, own)
        if value == unset:
            continue
        dest = args.read_dests[keyword]
        if getattr(args, dest) != unset:
            raise InputError(
                f"{flag} describes ORIGINAL (--like) and --in-{own} IN: without --like "
                f"give IN's once, with --in-{own}"
            )
        setattr(args, dest, value)
        setattr(args, own, unset)
        moved.append(f"{flag} as --in-{own}")
    if moved:
        print(
            f"{args.input}: no --like ORIGINAL: {' and '.join(moved)} (IN's columns, as "
            "in the other commands)",
            file=sys.stderr,
        )


def _map_on_in_only(args: argparse.Namespace, message: str) -> str:
    """A reading error about ORIGINAL's --map: when a column it names is IN's (and not
    ORIGINAL's), say that --map describes ORIGINAL and IN's columns take --in-map."""
    if "mapped column" not in message or not args.map:
        return message
    from wakeline.core.io import sniff

    try:
        in_columns = set(sniff(args.input).columns)
    except (InputError, OSError):
        return message
    on_in = [m for m in _split(args.map) if m.partition("=")[2].strip() in in_columns]
    if not on_in:
        return message
    given = " ".join(f"--in-map {m}" for m in on_in)
    return (
        f"{message}; with --like, --map names ORIGINAL's columns ({args.like}); "
        f"{', '.join(on_in)} names IN's ({args.input}): {given}"
    )


def _zone_of_import(args: argparse.Namespace, layout, points):
    """``layout`` with the zone the import read ``--like ORIGINAL``'s naive times in,
    when ORIGINAL's first rows show one offset against IN's times (a note says so), and
    whether a note or warning was printed. Two offsets (a zone with summer time in those
    rows): a warning asks for --tz; none: the layout as it is (UTC clock times)."""
    from dataclasses import replace

    from wakeline.core.io.export_like import import_offsets, offset_text
    from wakeline.core.io.formats import parse_mapping

    read = {
        "fmt": args.format,
        "mapping": parse_mapping(args.map),
        "skip_rows": args.like_skip_rows,
        "origin": getattr(args, "origin", None),
        "date_order": args.date_order,
        "time_unit": args.time_unit,
    }
    found = import_offsets(args.like, points, read)
    hits, rows = found["hits"], found["rows"]
    if not hits:
        return layout, False  # no common rows: the old note
    if set(hits) == {0}:
        return layout, True  # read as UTC: nothing to say
    shown = ", ".join(
        f"UTC{offset_text(m)} ({hits[m]:,} of {rows:,} rows)"
        for m in sorted(hits, key=lambda m: -hits[m])
    )
    if len(hits) == 1:
        (minutes,) = hits
        zone = offset_text(minutes)
        print(
            f"{args.like}: its times carry no zone; its first rows are IN's times at "
            f"{shown}: the import read them in that zone (--tz), so they are written in "
            f"UTC{zone} (give --tz ZONE, the import's, where the zone has summer time and "
            "the data span a change)",
            file=sys.stderr,
        )
        return replace(layout, time=replace(layout.time, tz=zone)), True
    print(
        f"{args.like}: warning: its times carry no zone; its first rows are IN's times at "
        f"{shown}: the import read them in a zone with summer time (--tz); they are written "
        "as UTC clock times unless --tz gives that zone (the one the import was given, "
        "e.g. --tz Europe/Oslo)",
        file=sys.stderr,
    )
    return layout, True


def _cmd_export(args: argparse.Namespace) -> int:
    from wakeline.app.cli_steps import say_quarantined
    from wakeline.core.io.export_like import export_like
    from wakeline.core.io.layout import load_layout, preset_layout

    if args.like and args.layout:
        raise InputError("give either --like ORIGINAL or --layout NAME, not both")
    if not args.like:
        _in_flags_without_original(args)
    suffix = args.output.suffix.lower()
    if suffix in (".geojson", ".json", ".gpx"):
        # The map formats: tracks as lines, not a CSV layout.
        if args.like or args.layout:
            raise InputError(
                f"{args.output}: --like and --layout shape a CSV file; a {suffix} file is "
                "written as it is (drop the option, or write to .csv)"
            )
        from wakeline.core.export_review import export_tracks

        result = _read_in(args)
        kind = export_tracks(result.points, args.output)
        msg = f"exported {count(len(result.points), 'row')} as {kind}"
        if kind == "geojson":
            from wakeline.core.export import vertex_columns

            kept, left = vertex_columns(result.points)
            if kept:
                msg += f"; per vertex in coordinateProperties: {', '.join(kept)}"
            if left:
                msg += f"; not written: {', '.join(left)} (Wakeline's internal columns)"
        elif kind == "gpx":
            from wakeline.core.export_review import gpx_left_out

            carried, internal = gpx_left_out(result.points)
            if carried:
                msg += (
                    f"; not written: {', '.join(carried)} (a GPX point holds time, position, "
                    "speed and course only: .geojson or .csv keeps these columns)"
                )
            if internal:
                msg += f"; not written: {', '.join(internal)} (Wakeline's internal columns)"
        print(msg, file=sys.stderr)
        return 0
    from wakeline.core.export import check_text_path

    check_text_path(args.output)  # no CSV text in tracks.xlsx (the window asks the same)
    if args.like:
        from wakeline.core.io.formats import parse_mapping

        try:
            layout = load_layout(
                args.like,
                tz=args.tz,
                fmt=args.format,
                mapping=parse_mapping(args.map),
                skip_rows=args.like_skip_rows,
                origin=getattr(args, "origin", None),  # ORIGINAL is in IN's frame
                date_order=args.date_order,  # ORIGINAL's dates as IN's were read
                time_unit=args.time_unit,
                speed_unit=args.like_speed_unit,
                distance_unit=args.like_distance_unit,
            )
        except InputError as exc:  # ORIGINAL's lines above its header: --like-skip-rows
            raise InputError(_map_on_in_only(args, _like_flag(str(exc)))) from None
    else:
        layout = preset_layout(args.layout or "canonical")
    result = None
    naive = layout.time.kind == "text" and not layout.time.suffix
    if args.like and not args.tz and naive and Path(args.like).suffix.lower() != ".json":
        # the zone the import read ORIGINAL's naive times in, from ORIGINAL's first rows
        # against IN's times (D15: they were written as UTC clock times, 2 h off)
        result = _read_in(args)
        layout, said = _zone_of_import(args, layout, result.points)
    else:
        said = False
    if args.like and not args.tz and naive and not said:
        from wakeline.core.io.formats import header_is_local

        names = [c.name for c in layout.columns if c.field == "time"]
        if names and header_is_local(names[0]):
            print(
                f"{args.like}: warning: its time column {names[0]!r} holds local times; they "
                "are written as UTC clock times unless --tz gives their zone (the one the "
                "import was given, e.g. --tz Asia/Shanghai)",
                file=sys.stderr,
            )
        elif names:
            print(
                f"{args.like}: its times carry no zone: written as UTC clock times (if the "
                "import read them in a zone with --tz, give the same --tz here)",
                file=sys.stderr,
            )
    if args.tz:
        from dataclasses import replace

        from wakeline.core.io.export_like import check_zone

        check_zone(args.tz)

        if layout.time.kind == "text" and layout.time.suffix:
            raise InputError(
                f"the layout's times carry their zone ({layout.time.suffix}); "
                "--tz applies to naive times only"
            )
        layout = replace(layout, time=replace(layout.time, tz=args.tz))
    layout = layout.with_encoding(args.encoding)
    if args.save_layout:
        from wakeline.core.io import write_json

        write_json(layout.to_dict(), args.save_layout)
    if result is None:
        result = _read_in(args)
    say_quarantined(args.input, result.report)
    if len(result.points) == 0:
        # as every other subcommand says it (it said "no usable points: nothing to export"
        # where they say "no data rows (a header only?)": operator test 10), IN's flags named
        from wakeline.core.io import nothing_imported

        why = nothing_imported(result.report, str(args.input))
        raise InputError(re.sub(r"(?<![\w-])--map\b", "--in-map", why))
    from wakeline.core.export import carries_targets

    # The canonical CSV keeps tracks and targets as GeoJSON and GPX do (docs/export.md);
    # a layout (--like, --layout) or the id options write one id per target.
    ids_asked = args.renumber or args.keep_ids or args.members or args.id_sensor
    keep = not (args.like or args.layout or ids_asked) and carries_targets(result.points)
    rep = export_like(
        result.points,
        layout,
        args.output,
        columns=_split(args.columns),
        renumber=True if args.renumber else (False if args.keep_ids else None),
        prefer_sensor=args.id_sensor,
        members_path=args.members,
        keep_targets=keep,
        sort=args.sort,
    )
    for warning in rep.get("warnings", []):
        print(f"{args.output}: warning: {warning}", file=sys.stderr)
    for note in rep.get("notes", []):
        print(f"{args.output}: {note}", file=sys.stderr)
    if args.like and Path(args.like).suffix.lower() != ".json":
        from wakeline.core.io.layout import mixed_decimals_note

        mixed = mixed_decimals_note(layout, args.like_skip_rows)
        if mixed:  # some rows with a decimal comma, others with a point (D10)
            print(f"{args.output}: {mixed}", file=sys.stderr)
    msg = (
        f"exported {count(rep['rows'], 'row')} as {rep['layout']} ({rep['encoding']}, "
        f"{count(len(rep['columns']), 'column')})"
    )
    if rep["rows_made"]:
        msg += f"; {count(rep['rows_made'], 'row')} made by Wakeline (operator columns left empty)"
    if rep["members"]:
        msg += f"; {count(rep['targets'], 'target')}, members in {rep['members']}"
    left = _internal_left_out(result.points, rep["columns"])
    if left:  # as GeoJSON and GPX say it (a fused layer's source, n_sources, weight_base)
        msg += f"; not written: {', '.join(left)} (Wakeline's internal columns)"
    if keep:
        n = result.points["target"].nunique()
        msg += (
            f"; {count(n, 'target')} in the 'target' column (--layout canonical: one id per target)"
        )
    if rep.get("row_order") in ("time", "track"):
        how = "by time" if rep["row_order"] == "time" else "track by track"
        why = f"--sort {args.sort}" if args.sort else f"as {args.like or 'the layout'}"
        msg += f"; rows {how} ({why})"
    packed = _packed_original(args.like)
    if packed:  # the layout is its text's: written plain (no .gz/.zip output is written)
        msg += f"; plain text: {args.like} is {packed}-compressed, its text's layout is written"
    print(msg, file=sys.stderr)
    return 0


def _internal_left_out(points, written) -> list[str]:
    """Wakeline's internal columns of ``points`` a CSV export did not write (targets and
    members are said apart: the 'target' column, the members file; ``course_read`` is
    the course as the file wrote it, written in the course column)."""
    from wakeline.core.io.layout import INTERNAL_COLUMNS
    from wakeline.core.schema import UNWRITTEN

    said = {"target", "members", "course_read", *UNWRITTEN, *written}
    return [str(c) for c in points.columns if c in INTERNAL_COLUMNS and c not in said]


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``export`` subcommand to the ``wakeline`` parser."""
    from wakeline.core.io.formats import DISTANCE_UNITS, FAMILIES, SPEED_UNITS
    from wakeline.core.io.layout import PRESETS

    p = sub.add_parser(
        "export",
        help="write points back in the operator's own layout, encoding and time format",
        description="Write the points of IN (any file Wakeline reads: cleaned, compressed, "
        "merged, fused) in a chosen layout. With --like ORIGINAL the original file's column "
        "names and order, delimiter, encoding, time format, number precision and the columns "
        "Wakeline did not use are copied (the latter from the columns the import carried "
        "through; left empty for points Wakeline made, e.g. gap fills). Without --like or "
        "--layout, tracks with targets (an associated or reviewed layer) keep their own ids "
        "and a target column, as .geojson and .gpx keep them (read back: the same tracks "
        "and targets). With a layout, merged and fused "
        "tracks carry one id per target in the batch column (the first member's batch, or "
        "fresh numbers with --renumber, or where the ids would collide), with a members CSV "
        "beside; merged and fused targets are written target by target in time order. Wakeline's internal "
        "columns are left out unless named in --columns.",
        epilog=EPILOG,
    )
    p.add_argument("input", type=Path, help="points to export (canonical CSV or any layout)")
    p.add_argument("-o", "--output", type=Path, required=True, help="file to write")
    p.add_argument(
        "--like",
        type=Path,
        metavar="ORIGINAL",
        help="copy the layout of this file (the file the data came from; compressed too: "
        "its text's layout, written as plain text), or of a layout JSON",
    )
    p.add_argument(
        "--format",
        choices=FAMILIES,
        default="auto",
        help="the layout family of ORIGINAL, as given to import (default: auto-detect); "
        "without --like, IN's (as --in-format)",
    )
    p.add_argument(
        "--map",
        action="append",
        metavar="FIELD=COLUMN",
        help="ORIGINAL's column for canonical FIELD, as given to import; repeatable. "
        "IN's columns take --in-map; without --like, --map is IN's (as --in-map)",
    )
    p.add_argument(
        "--like-skip-rows",
        type=whole_int,
        metavar="N",
        help="lines before ORIGINAL's header (a title), as given to import (default: detect)",
    )
    p.add_argument(
        "--like-speed-unit",
        choices=tuple(SPEED_UNITS),
        default="auto",
        help="unit of ORIGINAL's speed column when its header names none, as given to "
        "import with --speed-unit: speeds are written back in it (default auto: knots; "
        "--speed-unit is IN's unit only)",
    )
    p.add_argument(
        "--like-distance-unit",
        choices=tuple(DISTANCE_UNITS),
        default="auto",
        help="unit of ORIGINAL's plane x/y, offsets and range when their headers name none, "
        "as given to import with --distance-unit (default auto: metres; --distance-unit is "
        "IN's unit only)",
    )
    p.add_argument(
        "--layout",
        choices=tuple(PRESETS),
        help="a built-in layout (default canonical when --like is not given)",
    )
    p.add_argument(
        "--encoding",
        help="text encoding to write (default: the layout's; IN's: --in-encoding)",
    )
    p.add_argument(
        "--tz",
        metavar="ZONE",
        help="write naive times in this zone (IANA name or +08:00; default: the zone "
        "the original was read in, UTC; IN's zone: --in-tz)",
    )
    p.add_argument(
        "--columns",
        action="append",
        metavar="COL[,COL...]",
        help="more columns of IN to append (internal ones included, e.g. target,interpolated)",
    )
    ids = p.add_mutually_exclusive_group()
    ids.add_argument(
        "--renumber",
        action="store_true",
        help="give merged/fused targets fresh batch numbers 1, 2, ... (default: the first "
        "member's batch, unless two sensors' tracks would share an id in a layout without "
        "a sensor column: then renumbered, and a note says so)",
    )
    ids.add_argument(
        "--keep-ids",
        action="store_true",
        help="keep the first member's batch even where two sensors' tracks then share an "
        "id in a layout without a sensor column (read back, they are one track; a warning "
        "says so)",
    )
    p.add_argument(
        "--id-sensor",
        metavar="SENSOR",
        help="a fused target takes the batch of its member from this sensor when it has "
        "one (the sensor whose system reads the file); default: the first member",
    )
    p.add_argument(
        "--members",
        type=Path,
        metavar="M.csv",
        help="where to write the id → member batches table (default OUT.members.csv; only "
        "for merged or fused input)",
    )
    p.add_argument(
        "--sort",
        choices=("time", "track"),
        help="row order: time (every track's rows interleaved by time, as a system that "
        "requires ascending time reads them) or track (track by track); default: "
        "ORIGINAL's order as its first rows show it (a layout JSON keeps it as row_order), "
        "else IN's",
    )
    p.add_argument(
        "--save-layout",
        type=Path,
        metavar="L.json",
        help="also write the layout used as JSON (give it to --like later)",
    )
    from wakeline.app.cli_steps import add_read_flags

    add_read_flags(
        p,
        rename=("format", "map", "encoding", "tz"),
        description="How IN is read, as `wakeline import` and the steps read it (e.g. "
        "--skip-rows N as given to `wakeline clean`). --format, --map, --encoding and --tz "
        "above are about ORIGINAL and the file written (without --like, --map and --format "
        "are IN's, with a note); IN's are --in-format, --in-map, "
        "--in-encoding, --in-tz. --origin, --date-order and --time-unit apply to IN and to "
        "ORIGINAL alike; --speed-unit and --distance-unit to IN only (ORIGINAL's: "
        "--like-speed-unit, --like-distance-unit).",
    )
    p.set_defaults(func=_cmd_export)

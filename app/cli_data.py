"""``wakeline import`` and ``wakeline simulate``: read any layout, write simulated scenes."""

import argparse
import sys
from pathlib import Path

from wakeline.app.cli_common import EPILOG, positive_float, positive_int, seed_int
from wakeline.core.words import count, import_counts


def _cmd_import(args: argparse.Namespace) -> int:
    from wakeline.app.cli_steps import quarantine_reasons, read_options
    from wakeline.core.io import import_to_csv, nothing_imported, write_csv, write_json

    # Streamed: batch in, batch out (bounded memory); same output as read_points.
    result = import_to_csv(
        args.input,
        args.output,
        **read_options(args),
    )
    if args.derive_motion and result.report["rows_imported"]:
        from wakeline.app.cli_steps import derive_motion_in_file

        derive_motion_in_file(args.output)
    if args.quarantine:
        write_csv(result.quarantine, args.quarantine)
    if args.report:
        write_json(result.report, args.report)
    rep = result.report
    msg = f"imported {import_counts(rep)}"  # blank lines too: the counts add up to the lines
    if rep["rows_quarantined"] and not args.quarantine:
        msg += " (write them with --quarantine FILE)"
    if rep["rows_quarantined"]:
        msg += f"\nquarantined: {quarantine_reasons(rep, shown=8)}"
    if rep.get("columns"):
        msg += "\ncolumns: " + ", ".join(f"{k}={v}" for k, v in rep["columns"].items())
    if rep.get("plane_origin"):
        msg += "\n" + _plane_line(rep)
    if rep.get("extra_columns"):
        msg += "\nextra columns (carried as they are): " + ", ".join(rep["extra_columns"])
    if rep.get("date_order"):
        msg += f"\ndates read {rep['date_order']}"
    if rep.get("time_unit") and rep["time_unit"].startswith("Excel"):
        msg += f"\ntimes read as {rep['time_unit']}"
    if "clock_rollovers" in rep:
        day = rep.get("clock_date") or "1970-01-01 (relative: no --date)"
        msg += f"\ntimes of day read on {day}, {rep['clock_rollovers']:,} past midnight"
    if rep.get("values_blanked"):
        blanked = ", ".join(f"{k} {v:,}" for k, v in rep["values_blanked"].items())
        msg += f"\nvalues blanked, their rows kept: {blanked}"
    for warning in rep.get("warnings", []):
        msg += f"\nwarning: {warning}"
    if rep.get("rows_read") or rep.get("blank_lines"):
        print(msg, file=sys.stderr)  # a header alone: the error alone says it
    if rep["rows_imported"] == 0:
        # no header-only CSV left behind to be taken for a result (a pipe stays a pipe)
        if Path(args.output).is_file():
            Path(args.output).unlink()
        print(f"wakeline: error: {nothing_imported(rep)}", file=sys.stderr)
        return 2
    return 0


def _plane_line(rep: dict) -> str:
    """How positions on a plane were read: each column in the unit its header names,
    about the origin (so a swapped --origin or a unit read wrong shows at once)."""
    from wakeline.core.io.formats import angle_unit, length_unit

    cols = rep["columns"]
    parts = [
        f"{field} {cols[field]!r} in "
        + (angle_unit(cols[field]) if field == "bearing" else length_unit(cols[field]))[1]
        for field in ("east", "north", "range", "bearing", "east_offset", "north_offset")
        if field in cols
    ]
    lat, lon = rep["plane_origin"]
    return f"positions: {', '.join(parts)}; about the origin lat {lat}, lon {lon}"


def _cmd_simulate(args: argparse.Namespace) -> int:
    from wakeline.core import simulate
    from wakeline.core.errors import InputError
    from wakeline.core.io import write_points

    if args.hard and args.kind not in ("maneuver", "segments", "multisensor"):
        # refused rather than ignored: the file would be the easy scene under a hard name
        raise InputError(
            f"--hard applies to maneuver, segments and multisensor, not to {args.kind}"
        )
    if args.hard and (args.length is not None or args.sigma is not None):
        raise InputError("--length and --sigma are seed 000's classes; --hard has its own")

    if args.kind == "bearing":
        from wakeline.core.bearing_eval import simulate_table
        from wakeline.core.io import write_csv

        df = simulate_table(seed=args.seed)
        write_csv(df, args.output)
        print(
            f"simulated {len(df):,} bearings in {df['batch'].nunique()} sequences", file=sys.stderr
        )
        return 0
    if args.kind == "maneuver" and args.hard:
        hp = simulate.HardManeuverParams(n_ships=args.tracks)
        df = simulate.hard_maneuver_scene(args.seed, hp).points_with_spans()
    elif args.kind == "maneuver":
        df = simulate.maneuver_tracks(
            args.tracks,
            args.length or "short",
            300.0 if args.sigma is None else args.sigma,
            seed=args.seed,
        )
    elif args.kind == "segments":
        df = simulate.segments_scene(
            seed=args.seed, n_ships=args.ships, area_km=args.area_km, hard=args.hard
        )
    elif args.kind == "multisensor":
        df = simulate.multisensor_scene(
            seed=args.seed, n_ships=args.ships, area_km=args.area_km, hard=args.hard
        )
    else:
        df = simulate.demo_scene(seed=args.seed)
    write_points(df, args.output)
    print(
        f"simulated {count(len(df), 'point')}, "
        f"{count(df.groupby(['sensor', 'batch']).ngroups, 'track')}, "
        f"{count(df['truth'].nunique(), 'target')}",
        file=sys.stderr,
    )
    return 0


def register(sub) -> None:
    """Add the import and simulate subcommands."""
    from wakeline.app.cli_steps import add_read_flags
    from wakeline.core.io.formats import FORMATS
    from wakeline.core.simulate import KINDS, LENGTH_CLASSES

    formats = "; ".join(f"{f.family}: {f.label}" for f in FORMATS)
    p = sub.add_parser(
        "import",
        help="read a track file (any supported layout) and write canonical CSV",
        description="Read a CSV of tracks, detect its layout, encoding and delimiter, and write the "
        f"canonical CSV. Layouts: {formats}. Rows that cannot be used are quarantined with their "
        "line number and reason, never dropped silently.",
        epilog=EPILOG,
    )
    p.add_argument(
        "input",
        type=Path,
        help="input CSV or NMEA log (plain, or gzip, bz2, xz, zstd, a zip of one file)",
    )
    p.add_argument("-o", "--output", type=Path, required=True, help="canonical CSV to write")
    add_read_flags(p)
    p.add_argument(
        "--quarantine",
        type=Path,
        metavar="Q.csv",
        help="write quarantined rows (line, reason, text)",
    )
    p.add_argument("--report", type=Path, metavar="R.json", help="write the import report as JSON")
    from wakeline.app.cli_steps import add_derive_motion_flag

    add_derive_motion_flag(p)
    p.set_defaults(func=_cmd_import)

    p = sub.add_parser(
        "simulate",
        help="write a simulated scene with known truth",
        description="Seeded simulators writing canonical CSV with truth, true_lon and true_lat columns. "
        "maneuver: seed 000's protocol (16 kn, a point every 5 min, random 15-45 deg turns); "
        "segments: one radar breaking ships into several batches; multisensor: radar R1 and AIS "
        "seeing the same ships; bearing: seed 002's named observer/target scenarios, each with a "
        "50 deg target turn at 450 s and once without, bearings with 0.6 deg noise (columns "
        "batch, time, bearing, obs_lon, obs_lat, truth (the target: each sequence is one), "
        "true_maneuver_time, true_turn_deg; read by "
        "`wakeline bearing`); demo: the bundled demo scene.",
        epilog=EPILOG,
    )
    p.add_argument("kind", choices=KINDS)
    p.add_argument("--seed", type=seed_int, default=0, help="random seed, 0-4294967295 (default 0)")
    p.add_argument("-o", "--output", type=Path, required=True, help="canonical CSV to write")
    p.add_argument(
        "--tracks",
        type=positive_int,
        default=100,
        help="maneuver: number of tracks (--hard: ships) (default 100)",
    )
    p.add_argument(
        "--length",
        choices=tuple(LENGTH_CLASSES),
        help="maneuver: track class, short < 100, medium 100-200, long > 200 points "
        "(default short)",
    )
    p.add_argument(
        "--sigma",
        type=positive_float,
        help="maneuver: position noise std per axis, metres (default 300)",
    )
    p.add_argument(
        "--ships", type=positive_int, default=20, help="segments/multisensor: ships (default 20)"
    )
    p.add_argument(
        "--area-km",
        type=positive_float,
        default=60.0,
        help="segments/multisensor: side of the square area, km (default 60)",
    )
    p.add_argument(
        "--hard",
        action="store_true",
        help="maneuver, segments, multisensor: the hard variant (speed changes, curved paths, "
        "missed scans, long gaps, loose ends, clutter; multisensor: split radar tracks, ships "
        "without AIS, partial overlap; maneuver: radar 1-2 s and AIS 10/30 s tracks with "
        "jitter, gaps and heavy-tailed noise, sharp and gradual turns, slow and moored ships, "
        "columns kind, rate, true_turn, turn_deg)",
    )
    p.set_defaults(func=_cmd_simulate)

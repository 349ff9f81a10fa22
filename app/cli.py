"""The ``wakeline`` command line (SPEC §8): the same engine as the GUI, for batch work.

It lives in the application package so that the engine (``wakeline.core``) never
reaches Qt; Qt is imported only when the ``gui`` subcommand runs.

Every subcommand returns 0 on success and 2 on bad input with one clear line on stderr;
output files are written atomically, so a failed run leaves none half-written. No
Python traceback reaches the user unless ``--debug`` is given.
"""

import argparse
import sys
import traceback
from pathlib import Path

from wakeline.app import cli_batch, cli_export, cli_render
from wakeline.core import __version__
from wakeline.core.errors import InputError

EPILOG = "Exit status: 0 success, 2 bad input (one message on stderr), 1 internal error."


def _cmd_import(args: argparse.Namespace) -> int:
    from wakeline.core.io import import_to_csv, write_csv, write_json

    # Streamed: batch in, batch out (bounded memory); same output as read_points.
    result = import_to_csv(
        args.input,
        args.output,
        fmt=args.format,
        mapping=args.map or [],
        encoding=args.encoding,
        delimiter=args.delimiter,
        sensor=args.sensor,
        tz=args.tz,
    )
    if args.quarantine:
        write_csv(result.quarantine, args.quarantine)
    if args.report:
        write_json(result.report, args.report)
    rep = result.report
    msg = (
        f"imported {rep['rows_imported']:,} rows in {rep['tracks']:,} tracks "
        f"({rep['format']}, {rep['encoding']}); {rep['rows_quarantined']:,} quarantined"
    )
    if rep["rows_quarantined"] and not args.quarantine:
        msg += " (write them with --quarantine FILE)"
    if rep.get("columns"):
        msg += "\ncolumns: " + ", ".join(f"{k}={v}" for k, v in rep["columns"].items())
    if rep.get("extra_columns"):
        msg += "\nextra columns (carried as they are): " + ", ".join(rep["extra_columns"])
    for warning in rep.get("warnings", []):
        msg += f"\nwarning: {warning}"
    print(msg, file=sys.stderr)
    return 0


def _cmd_simulate(args: argparse.Namespace) -> int:
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    if args.kind == "bearing":
        from wakeline.core.bearing_eval import simulate_table
        from wakeline.core.io import write_csv

        df = simulate_table(seed=args.seed)
        write_csv(df, args.output)
        print(
            f"simulated {len(df):,} bearings in {df['batch'].nunique()} sequences", file=sys.stderr
        )
        return 0
    if args.kind == "maneuver":
        df = simulate.maneuver_tracks(args.tracks, args.length, args.sigma, seed=args.seed)
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
        f"simulated {len(df):,} points, {df.groupby(['sensor', 'batch']).ngroups:,} tracks, "
        f"{df['truth'].nunique():,} targets",
        file=sys.stderr,
    )
    return 0


def _maneuver_params(args: argparse.Namespace):
    from wakeline.core.maneuver import ManeuverParams

    if getattr(args, "paper", False):
        return (
            ManeuverParams.paper()
            .replace(window_p=args.window, radius_n=args.radius, threshold_deg=args.threshold)
            .checked()
        )
    return ManeuverParams(
        window_p=args.window,
        radius_n=args.radius,
        threshold_deg=args.threshold,
        window_s=args.window_s,
        max_window_s=args.max_window_s,
        min_speed_kn=args.min_speed,
    ).checked()


def _cmd_evaluate(args: argparse.Namespace) -> int:

    from wakeline.core.evaluate import evaluate_maneuver
    from wakeline.core.io import write_csv

    if args.kind == "fuse":
        from wakeline.core.evaluate_association import evaluate_fusion

        ev = evaluate_fusion(
            args.scenes,
            args.seed,
            _fuse_params(args.set),
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
            hard=args.hard,
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table.merge(ev.errors, on="scene"), args.csv)
        return 0

    if args.kind == "associate" and args.real:
        from wakeline.core.evaluate_association import evaluate_real_association

        ev = evaluate_real_association(
            args.real,
            cut_s=args.cut_s,
            params=_link_params(args.set),
            truth_sep=args.truth_sep,
            mapping=args.map,
            seed=args.seed,
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table, args.csv)
        return 0

    if args.kind == "associate":
        from wakeline.core.evaluate_association import evaluate_association

        ev = evaluate_association(
            args.scenes,
            args.seed,
            _link_params(args.set),
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
            hard=args.hard,
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table, args.csv)
        return 0

    if args.kind == "bearing":
        from wakeline.core.bearing_eval import evaluate_bearing, format_evaluation

        ev = evaluate_bearing(
            args.runs,
            args.seed,
            _bearing_params(args),
            geometries=args.geometries,
            compare=not args.ours_only,
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(format_evaluation(ev))
        if args.csv:
            write_csv(ev["table"], args.csv)
        return 0

    if args.real is not None:
        from wakeline.core.evaluate_real import evaluate_real

        ev = evaluate_real(
            args.real,
            _maneuver_params(args),
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.rows, args.csv)
        return 0

    ev = evaluate_maneuver(
        args.tracks,
        args.seed,
        _maneuver_params(args),
        progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
    )
    print(ev.format())
    if args.csv:
        write_csv(ev.table, args.csv)
    return 0


def _add_detector_options(p: argparse.ArgumentParser) -> None:
    from wakeline.core.maneuver import ManeuverParams

    d = ManeuverParams()
    p.add_argument(
        "--window",
        type=_positive_int,
        default=d.window_p,
        help=f"p: points per heading window (default {d.window_p})",
    )
    p.add_argument(
        "--radius",
        type=_positive_int,
        default=d.radius_n,
        help=f"n: maximum-filter radius, points (default {d.radius_n})",
    )
    p.add_argument(
        "--threshold",
        type=float,
        default=d.threshold_deg,
        help=f"t: smallest heading change counted, degrees (default {d.threshold_deg:g})",
    )
    p.add_argument(
        "--window-s",
        type=float,
        default=d.window_s,
        help=f"heading window, seconds: p per track = this / its median sampling interval, at "
        f"least --window points; 0 = --window points whatever they span (default {d.window_s:g})",
    )
    p.add_argument(
        "--max-window-s",
        type=float,
        default=d.max_window_s,
        help=f"gradual turns: windows double up to this many seconds; 0 = one window "
        f"(default {d.max_window_s:g})",
    )
    p.add_argument(
        "--min-speed",
        type=float,
        default=d.min_speed_kn,
        help=f"kn: no maneuver where the ship is slower over a window (default {d.min_speed_kn:g})",
    )
    p.add_argument(
        "--paper",
        action="store_true",
        help="seed 000 as written: --window points per window, one scale, no speed, noise or "
        "at-rest rule (compress: maneuver points only, raw vertices)",
    )


def _bearing_params(args: argparse.Namespace):
    from wakeline.core.bearing import BearingParams

    return BearingParams(
        **{d["name"]: getattr(args, d["name"]) for d in BearingParams.describe()}
    ).checked()


def _cmd_bearing(args: argparse.Namespace) -> int:
    from wakeline.core.bearing import detect_with_report, read_bearings, report_lines
    from wakeline.core.io import write_csv, write_json

    params = _bearing_params(args)
    table, report = detect_with_report(read_bearings(args.input), params)
    write_csv(table, args.output)
    if args.report:
        write_json({"batches": report, "params": dict(vars(params))}, args.report)
    for line in report_lines(report):
        print(line, file=sys.stderr)
    print(f"{len(table):,} maneuver detections", file=sys.stderr)
    return 0


def _params_epilog(cls) -> str:
    """Help text listing a parameter class's fields with unit, default and meaning."""
    fields = "; ".join(
        f"{d['name']} ({d['unit'] or '-'}, default {d['default']}): {d['doc']}"
        for d in cls.describe()
    )
    return f"Parameters (--set NAME=VALUE): {fields}. {EPILOG}"


def _link_params(settings: list[str] | None):
    from wakeline.core.associate import LinkParams

    return LinkParams().replace(**_settings(settings)).checked()


def _settings(settings: list[str] | None) -> dict[str, str]:
    changes = {}
    for text in settings or []:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise InputError(f"--set expects NAME=VALUE, got {text!r}")
        changes[name.strip()] = value.strip()
    return changes


def _fuse_params(settings: list[str] | None):
    from wakeline.core.fuse import FuseParams

    return FuseParams().replace(**_settings(settings)).checked()


def _add_bearing_options(p: argparse.ArgumentParser) -> None:
    """Bearing detector flags, one per BearingParams field (spans in seconds)."""
    from wakeline.core.bearing import BearingParams

    for d in BearingParams.describe():
        flag = "--" + d["name"].removesuffix("_s").replace("_", "-")
        unit = f" {d['unit']}" if d["unit"] and d["unit"] != "samples" else ""
        if isinstance(d["default"], bool):
            p.add_argument(
                flag,
                dest=d["name"],
                action=argparse.BooleanOptionalAction,
                default=d["default"],
                help=f"{d['doc']} (default {'on' if d['default'] else 'off'})",
            )
            continue
        kind = _positive_int if isinstance(d["default"], int) else _positive_float
        p.add_argument(
            flag,
            dest=d["name"],
            type=kind,
            default=d["default"],
            help=f"{d['doc']} (default {d['default']:g}{unit})",
        )


def _io_args(p: argparse.ArgumentParser, output_help: str) -> None:
    p.add_argument("input", type=Path, help="track file (any layout `wakeline import` reads)")
    p.add_argument("-o", "--output", type=Path, required=True, help=output_help)


def _cmd_gui(args: argparse.Namespace) -> int:
    try:
        from wakeline.app.main import run
    except ImportError as exc:
        raise InputError(f"the desktop application cannot start: {exc}") from None
    return run(args.files, screenshot=args.screenshot)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    from wakeline.core.io.formats import FAMILIES, FORMATS
    from wakeline.core.simulate import KINDS, LENGTH_CLASSES

    parser = argparse.ArgumentParser(
        prog="wakeline",
        description="Wakeline: a workbench for maritime radar and AIS tracks. "
        "With no subcommand the desktop application starts.",
        epilog=EPILOG,
    )
    parser.add_argument("--version", action="version", version=f"wakeline {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show Python tracebacks on internal errors"
    )
    sub = parser.add_subparsers(dest="command", metavar="SUBCOMMAND")

    formats = "; ".join(f"{f.family}: {f.label}" for f in FORMATS)
    p = sub.add_parser(
        "import",
        help="read a track file (any supported layout) and write canonical CSV",
        description="Read a CSV of tracks, detect its layout, encoding and delimiter, and write the "
        f"canonical CSV. Layouts: {formats}. Rows that cannot be used are quarantined with their "
        "line number and reason, never dropped silently.",
        epilog=EPILOG,
    )
    p.add_argument("input", type=Path, help="input CSV (.csv or .csv.gz)")
    p.add_argument("-o", "--output", type=Path, required=True, help="canonical CSV to write")
    p.add_argument(
        "--format", choices=FAMILIES, default="auto", help="input layout (default: auto-detect)"
    )
    p.add_argument(
        "--map",
        action="append",
        metavar="FIELD=COLUMN",
        help="take canonical FIELD (sensor, batch, time, lon, lat, speed, course, truth) "
        "from COLUMN; repeatable",
    )
    p.add_argument(
        "--encoding", help="text encoding (default: detect UTF-8 / UTF-16 by BOM / GB18030)"
    )
    p.add_argument("--delimiter", help="field delimiter (default: detect , ; or tab)")
    p.add_argument(
        "--tz",
        metavar="ZONE",
        help="zone of times written without one: IANA name (Asia/Shanghai) or ±HH:MM "
        "(default UTC; unix times are absolute and not shifted)",
    )
    p.add_argument(
        "--sensor", default="S1", help="sensor name when the file has no sensor column (default S1)"
    )
    p.add_argument(
        "--quarantine",
        type=Path,
        metavar="Q.csv",
        help="write quarantined rows (line, reason, text)",
    )
    p.add_argument("--report", type=Path, metavar="R.json", help="write the import report as JSON")
    p.set_defaults(func=_cmd_import)

    p = sub.add_parser(
        "simulate",
        help="write a simulated scene with known truth",
        description="Seeded simulators writing canonical CSV with truth, true_lon and true_lat columns. "
        "maneuver: seed 000's protocol (16 kn, a point every 5 min, random 15-45 deg turns); "
        "segments: one radar breaking ships into several batches; multisensor: radar R1 and AIS "
        "seeing the same ships; demo: the bundled demo scene.",
        epilog=EPILOG,
    )
    p.add_argument("kind", choices=KINDS)
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("-o", "--output", type=Path, required=True, help="canonical CSV to write")
    p.add_argument(
        "--tracks", type=_positive_int, default=100, help="maneuver: number of tracks (default 100)"
    )
    p.add_argument(
        "--length",
        choices=tuple(LENGTH_CLASSES),
        default="short",
        help="maneuver: track class, short < 100, medium 100-200, long > 200 points",
    )
    p.add_argument(
        "--sigma",
        type=_positive_float,
        default=300.0,
        help="maneuver: position noise std per axis, metres (default 300)",
    )
    p.add_argument(
        "--ships", type=_positive_int, default=20, help="segments/multisensor: ships (default 20)"
    )
    p.add_argument(
        "--area-km",
        type=_positive_float,
        default=60.0,
        help="segments/multisensor: side of the square area, km (default 60)",
    )
    p.add_argument(
        "--hard",
        action="store_true",
        help="segments/multisensor: the hard variant (speed changes, curved paths, missed scans, "
        "long gaps, loose ends, clutter; multisensor: split radar tracks, ships without AIS, "
        "partial overlap)",
    )
    p.set_defaults(func=_cmd_simulate)

    from wakeline.app.cli_steps import add_step_parsers

    add_step_parsers(sub)

    p = sub.add_parser(
        "bearing",
        help="detect target maneuvers in bearing-only sequences (seed 002)",
        description="Input: batch,time,bearing[,obs_lon,obs_lat] (degrees; the observer's position "
        "excludes spans where it maneuvers itself). Two sliding windows X and Y; the Mann-Whitney AUC "
        "of the residuals from the trend fitted on X, with its null variance corrected for the trend's "
        "extrapolation. Writes one row per detection: batch,detect_time,maneuver_time,z.",
        epilog=EPILOG,
    )
    p.add_argument("input", type=Path, help="bearing CSV")
    p.add_argument("-o", "--output", type=Path, required=True, help="detections CSV to write")
    p.add_argument(
        "--report",
        type=Path,
        metavar="R.json",
        help="per batch: windows tested, skipped and why, noise and the smallest visible turn",
    )
    _add_bearing_options(p)
    p.set_defaults(func=_cmd_bearing)

    p = sub.add_parser(
        "evaluate",
        help="reproduce the papers' evaluation tables",
        description="maneuver: seed 000's protocol (sigma 300/600 m x short/medium/long tracks) for our "
        "detector and compression and the IMM, entropy and Douglas-Peucker baselines; prints Table 1's "
        "layout with Dis_e against the true path and the observed points, and turn-point scores. "
        "bearing: seed 002's metrics (detection rate, reaction time, maneuver-time error, false alarms) "
        "on random held-out geometries (1 s, 2 s and jittered sampling; mean and worst) and five named scenarios, next to seed 002's eq. 15 AUC-mean test. associate: single-sensor association on "
        "sparse, dense and very dense simulated scenes (target-level and pairwise P/R/F1, P_CA, P_FA) "
        "for our methods and the seed 001 / seed 003 ones. fuse: multi-sensor P_CA/P_FA for "
        "synchronized and DTW distances with optimal and greedy assignment, and the fused position "
        "error next to each sensor's, on scenes of rising density.",
        epilog=EPILOG,
    )
    p.add_argument("kind", choices=("maneuver", "bearing", "associate", "fuse"))
    p.add_argument(
        "--real",
        type=Path,
        metavar="DIR",
        help="score on a real set instead. maneuver: a folder of shared/data/real "
        "(autoferry-fusion, greece-ais-annotated, dma-single-ship, oresund-encounters); "
        "associate: a file, or every .csv/.csv.gz in DIR (each track's id is the truth; "
        "tracks are cut at their gaps, pieces renumbered)",
    )
    p.add_argument(
        "--scenes",
        type=_positive_int,
        default=5,
        help="associate, fuse: scenes per density class (default 5)",
    )
    p.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="associate, fuse: change a parameter",
    )
    p.add_argument(
        "--runs", type=_positive_int, default=20, help="bearing: runs per scenario (default 20)"
    )
    p.add_argument(
        "--geometries",
        type=_positive_int,
        default=8,
        help="bearing: random held-out geometries, each at 1 s, 2 s and jittered sampling (default 8)",
    )
    p.add_argument(
        "--ours-only",
        action="store_true",
        help="bearing: skip the eq. 15 AUC-mean and quadratic-trend comparisons",
    )
    p.add_argument(
        "--tracks", type=_positive_int, default=100, help="tracks per class (default 100)"
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--csv", type=Path, help="also write the full table as CSV")
    p.add_argument(
        "--hard",
        action="store_true",
        help="associate, fuse: the hard simulated scenes (see 'simulate --hard')",
    )
    p.add_argument(
        "--cut-s",
        type=_positive_float,
        default=120.0,
        help="associate --real: cut where a step exceeds this (s) and 4x the track's median "
        "step (default 120)",
    )
    p.add_argument(
        "--truth-sep",
        default="",
        metavar="CHAR",
        help="associate --real: the truth is the track id up to this character "
        "(MTAD: '-', so MMSI-k sub-tracks are one ship)",
    )
    p.add_argument(
        "--map",
        action="append",
        metavar="FIELD=COLUMN",
        help="associate --real: map a canonical field to a column of the files (as in import)",
    )
    _add_detector_options(p)
    _add_bearing_options(p)
    p.set_defaults(func=_cmd_evaluate)

    p = sub.add_parser(
        "gui",
        help="start the desktop application (the default)",
        description="Start the desktop application, optionally loading files.",
        epilog=EPILOG,
    )
    p.add_argument(
        "files", nargs="*", type=Path, help="track files to load (default: the bundled demo)"
    )
    p.add_argument(
        "--screenshot",
        type=Path,
        metavar="PNG",
        help="load, render the main window at 1400x900 to PNG and exit",
    )
    p.set_defaults(func=_cmd_gui)
    cli_render.register(sub)
    cli_batch.register(sub)
    cli_export.register(sub)
    from wakeline.app import cli_review

    cli_review.register(sub)
    return parser


def _with_default_command(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``argv`` with ``gui`` inserted when no subcommand is named (``wakeline FILE…``).

    Global options (``--debug``) stay in front; ``--help``/``--version`` are left alone.
    """
    commands = next(a.choices for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    globals_ = [a for a in argv if a == "--debug"]
    rest = [a for a in argv if a != "--debug"]
    if any(a in ("-h", "--help", "--version") for a in rest[:1]):
        return argv
    if rest and rest[0] in commands:
        return globals_ + rest
    return [*globals_, "gui", *rest]


_OUTPUT_ARGS = (
    "output",
    "quarantine",
    "report",
    "rejected",
    "pairs",
    "csv",
    "screenshot",
    "members",
    "save_layout",
    "log",
)


def _check_paths(args: argparse.Namespace) -> None:
    """Before any work: no output may be an input or another output, or be read-only."""
    from wakeline.core.io.writer import check_outputs

    values = vars(args)

    def is_output(key: str) -> bool:  # the generated step commands name theirs out__TABLE
        return key in _OUTPUT_ARGS or key.startswith("out__")

    outputs = {
        f"--{k.removeprefix('out__')}": v
        for k, v in values.items()
        if is_output(k) and isinstance(v, Path)
    }
    inputs = [
        p
        for k, v in values.items()
        if not is_output(k)
        for p in (v if isinstance(v, list) else [v])
        if isinstance(p, Path)
    ]
    check_outputs(inputs, outputs)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``wakeline`` command; returns the exit status."""
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(_with_default_command(parser, argv))
    try:
        _check_paths(args)
        return args.func(args)
    except InputError as exc:
        print(f"wakeline: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        name = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"wakeline: error: {name}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("wakeline: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - the last line of defence for the user
        if args.debug:
            traceback.print_exc()
        print(
            f"wakeline: internal error: {type(exc).__name__}: {exc} (run with --debug for details)",
            file=sys.stderr,
        )
        return 1


if __name__ == "__main__":
    sys.exit(main())

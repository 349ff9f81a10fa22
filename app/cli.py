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

from wakeline.core import __version__
from wakeline.core.errors import InputError

EPILOG = "Exit status: 0 success, 2 bad input (one message on stderr), 1 internal error."


def _cmd_import(args: argparse.Namespace) -> int:
    from wakeline.core.io import read_points, write_csv, write_json, write_points

    result = read_points(
        args.input,
        fmt=args.format,
        mapping=args.map or [],
        encoding=args.encoding,
        delimiter=args.delimiter,
        sensor=args.sensor,
    )
    write_points(result.points, args.output)
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
    print(msg, file=sys.stderr)
    return 0


def _cmd_simulate(args: argparse.Namespace) -> int:
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    if args.kind == "bearing":
        from wakeline.core.bearing import simulate_table
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
        df = simulate.segments_scene(seed=args.seed, n_ships=args.ships, area_km=args.area_km)
    elif args.kind == "multisensor":
        df = simulate.multisensor_scene(seed=args.seed, n_ships=args.ships, area_km=args.area_km)
    else:
        df = simulate.demo_scene(seed=args.seed)
    write_points(df, args.output)
    print(
        f"simulated {len(df):,} points, {df.groupby(['sensor', 'batch']).ngroups:,} tracks, "
        f"{df['truth'].nunique():,} targets",
        file=sys.stderr,
    )
    return 0


def _read_canonical(path: Path):
    from wakeline.core.io import read_points

    result = read_points(path)
    if result.report["rows_quarantined"]:
        print(
            f"{path}: {result.report['rows_quarantined']:,} rows quarantined on reading "
            "(run `wakeline import` with --quarantine to see them)",
            file=sys.stderr,
        )
    if len(result.points) == 0:
        raise InputError(f"{path}: no usable points")
    return result.points


def _maneuver_params(args: argparse.Namespace):
    from wakeline.core.maneuver import ManeuverParams

    return ManeuverParams(
        window_p=args.window,
        radius_n=args.radius,
        threshold_deg=args.threshold,
        window_s=args.window_s,
    ).checked()


def _cmd_maneuvers(args: argparse.Namespace) -> int:
    import numpy as np
    import pandas as pd

    from wakeline.core import baselines
    from wakeline.core.io import write_csv
    from wakeline.core.maneuver import MANEUVER_COLUMNS, detect
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import local_xy

    points = _read_canonical(args.input)
    result = detect(points, _maneuver_params(args))
    if args.method != "pca":
        pts, index = result.points, result.index
        if args.method == "entropy" and args.k is None and "true_turn" not in pts.columns:
            raise InputError(
                "--method entropy needs the number of maneuvers per track: give --k N "
                "(or a true_turn column, as simulations have)"
            )
        x, y = local_xy(pts, index)
        t = time_seconds(pts["time"])
        turns = pd.to_numeric(
            pts.get("true_turn", pd.Series(dtype=float)), errors="coerce"
        ).to_numpy()
        mask = np.zeros(len(pts), dtype=bool)
        for a, b in zip(index.starts, index.ends, strict=True):
            if args.method == "imm":
                found = baselines.imm_detect(x[a:b], y[a:b], t[a:b], args.sigma)
            else:
                k = args.k if args.k is not None else int((turns[a:b] == 1).sum())
                found = baselines.entropy_detect(x[a:b], y[a:b], k)
            mask[a + found] = True
        result = type(result)(pts, index, np.full(len(pts), np.nan), mask, result.window_p)
    table = result.table()[list(MANEUVER_COLUMNS)]
    write_csv(table, args.output)
    print(
        f"{len(table):,} maneuver points in {result.index.n_tracks:,} tracks ({args.method})",
        file=sys.stderr,
    )
    return 0


def _cmd_compress(args: argparse.Namespace) -> int:
    from wakeline.core.compress import compress_with, douglas_peucker_mask
    from wakeline.core.io import write_json, write_points
    from wakeline.core.maneuver import detect
    from wakeline.core.tracks import local_xy, sort_points, track_index

    points = sort_points(_read_canonical(args.input))
    if args.method == "dp":
        index = track_index(points)
        x, y = local_xy(points, index)
        keep = douglas_peucker_mask(x, y, index, args.tolerance, args.dp_distance)
        refine = False
    else:
        keep = detect(points, _maneuver_params(args)).is_maneuver
        refine = not args.raw_vertices
    comp = compress_with(None, keep, refine=refine, sorted_points=points)
    report = comp.report()
    report["method"] = args.method
    report["refined_vertices"] = refine
    write_points(comp.kept_points(), args.output)
    if args.report:
        write_json(report, args.report)
    o = report["overall"]
    extra = f", Dis_e against truth {o['dis_e_true_m']:.1f} m" if "dis_e_true_m" in o else ""
    print(
        f"kept {o['kept']:,} of {o['points']:,} points ({o['ratio']:.1%}); Dis_e {o['dis_e_m']:.1f} m{extra}",
        file=sys.stderr,
    )
    return 0


def _cmd_evaluate(args: argparse.Namespace) -> int:
    import pandas as pd

    from wakeline.core.evaluate import evaluate_maneuver
    from wakeline.core.io import write_csv

    if args.kind == "fuse":
        from wakeline.core.evaluate_association import evaluate_fusion

        ev = evaluate_fusion(
            args.scenes,
            args.seed,
            _fuse_params(args.set),
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table.merge(ev.errors, on="scene"), args.csv)
        return 0

    if args.kind == "associate":
        from wakeline.core.evaluate_association import evaluate_association

        ev = evaluate_association(
            args.scenes,
            args.seed,
            _link_params(args.set),
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table, args.csv)
        return 0

    if args.kind == "bearing":
        from wakeline.core.bearing import evaluate_bearing, format_evaluation

        ev = evaluate_bearing(
            args.runs,
            args.seed,
            _bearing_params(args),
            sweep_runs=args.sweep_runs,
            progress=lambda f, text: print(f"  {f:4.0%} {text}", file=sys.stderr),
        )
        print(format_evaluation(ev))
        if args.csv:
            write_csv(pd.concat([ev["main"], ev["noise"], ev["turn"]], ignore_index=True), args.csv)
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
        help="if > 0: p per track = this many seconds / the track's median sampling interval",
    )


def _cmd_clean(args: argparse.Namespace) -> int:
    from wakeline.core.clean import CleanParams, clean
    from wakeline.core.io import write_csv, write_json, write_points

    settings = list(args.set or [])
    settings += [f"{rule}.enabled=false" for rule in args.off or []]
    if args.resample is not None:
        settings += ["resample.enabled=true", f"resample.period_s={args.resample}"]
    if args.max_gap is not None:
        settings += [f"resample.max_gap_s={args.max_gap}"]
    if args.smooth is not None:
        settings += ["smooth.enabled=true", f"smooth.window={args.smooth}"]
    if args.bspline:
        settings += ["bspline.enabled=true"]
    params = CleanParams().with_settings(settings)
    result = clean(_read_canonical(args.input), params)
    write_points(result.points, args.output)
    if args.rejected:
        write_csv(result.rejected, args.rejected)
    if args.report:
        write_json(result.report, args.report)
    rep = result.report
    touched = {
        rule: sum(v.get(k, 0) for k in ("removed", "changed", "replaced"))
        for rule, v in rep["rules"].items()
    }
    counts = ", ".join(f"{rule} {n:,}" for rule, n in touched.items() if n)
    print(
        f"kept {rep['points_out']:,} of {rep['points_in']:,} points in {rep['tracks_out']:,} tracks"
        + (f"; {counts}" if counts else ""),
        file=sys.stderr,
    )
    return 0


def _clean_help() -> str:
    from wakeline.core.clean import CleanParams

    lines = []
    for d in CleanParams.describe():
        unit = f" [{d['unit']}]" if d.get("unit") else ""
        source = f" ({d['source']})" if d.get("source") else ""
        lines.append(f"{d['rule']}.{d['name']}={d['default']}{unit}: {d['doc']}{source}")
    return "Rules and parameters (--set rule.param=value):\n  " + "\n  ".join(lines)


def _bearing_params(args: argparse.Namespace):
    from wakeline.core.bearing import BearingParams

    return BearingParams(
        window_x=args.window_x, window_y=args.window_y, alpha=args.alpha, trend_order=args.order
    ).checked()


def _cmd_bearing(args: argparse.Namespace) -> int:
    from wakeline.core.bearing import detect, read_bearings
    from wakeline.core.io import write_csv

    table = detect(read_bearings(args.input), _bearing_params(args))
    write_csv(table, args.output)
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


def _cmd_associate(args: argparse.Namespace) -> int:
    from wakeline.core.associate import associate_interrupted, associate_segments, stitch
    from wakeline.core.io import write_csv, write_json, write_points

    params = _link_params(args.set)
    points = _read_canonical(args.input)
    if args.mode == "segments":
        method = args.method or "motion"
        if method not in ("motion", "area", "dtw", "hausdorff"):
            raise InputError(
                f"--mode segments takes --method motion|area|dtw|hausdorff, not {method}"
            )
        assoc = associate_segments(points, params, method=method)
    else:
        method = args.method or "optimal"
        if method not in ("optimal", "greedy"):
            raise InputError(f"--mode interrupted takes --method optimal|greedy, not {method}")
        assoc = associate_interrupted(points, params, method=method, normalize=args.normalize)
    out = stitch(assoc) if args.stitch else assoc.points()
    write_points(out, args.output)
    if args.pairs:
        write_csv(assoc.pair_table(), args.pairs)
    if args.report:
        write_json({**assoc.report(), "params": dict(vars(params))}, args.report)
    rep = assoc.report()
    msg = (
        f"{rep['tracks']:,} tracks -> {rep['targets']:,} targets "
        f"({rep['pairs_chosen']:,} joins of {rep['candidate_pairs']:,} candidate pairs, {method})"
    )
    if args.stitch:
        msg += f"; {int(out['interpolated'].sum()):,} points filled"
    print(msg, file=sys.stderr)
    return 0


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


def _cmd_fuse(args: argparse.Namespace) -> int:
    from wakeline.core.fuse import associate_sensors, fuse
    from wakeline.core.io import write_csv, write_json, write_points

    params = _fuse_params(args.set)
    assoc = associate_sensors(
        _read_canonical(args.input), params, distance=args.distance, method=args.method
    )
    fused = fuse(assoc, params)
    write_points(fused, args.output)
    if args.pairs:
        write_csv(assoc.pair_table(), args.pairs)
    rep = assoc.report()
    if args.report:
        write_json({**rep, "fused_points": len(fused), "params": dict(vars(params))}, args.report)
    print(
        f"{rep['tracks']:,} tracks of {rep['sensors']} sensors -> {rep['targets']:,} targets "
        f"({rep['pairs_chosen']:,} pairs of {rep['candidate_pairs']:,} candidates, "
        f"{args.distance}, {args.method}); {len(fused):,} fused points",
        file=sys.stderr,
    )
    return 0


def _add_bearing_options(p: argparse.ArgumentParser) -> None:
    from statistics import NormalDist  # scipy.stats (d.z_crit) is slow to import for a help text

    from wakeline.core.bearing import BearingParams

    d = BearingParams()
    z = NormalDist().inv_cdf(1.0 - d.alpha / 2.0)
    p.add_argument(
        "--window-x",
        type=_positive_int,
        default=d.window_x,
        help=f"m: samples in window X, the trend reference (default {d.window_x})",
    )
    p.add_argument(
        "--window-y",
        type=_positive_int,
        default=d.window_y,
        help=f"n: samples in window Y (default {d.window_y})",
    )
    p.add_argument(
        "--alpha",
        type=_positive_float,
        default=d.alpha,
        help=f"significance level per boundary (default {d.alpha:g}, z = {z:.2f})",
    )
    p.add_argument(
        "--order",
        type=int,
        default=d.trend_order,
        help=f"polynomial order of the trend fitted on X (default {d.trend_order})",
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
    p.add_argument("--encoding", help="text encoding (default: detect UTF-8 / GB18030)")
    p.add_argument("--delimiter", help="field delimiter (default: detect , ; or tab)")
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
    p.set_defaults(func=_cmd_simulate)

    from wakeline.core.clean import RULES

    p = sub.add_parser(
        "clean",
        help="remove duplicates, stationary points, jumps and outliers, with a reject trail",
        description="Apply the cleaning rules in order: duplicates, stationary, speed, turn, "
        "speed_outliers, isolated, short_tracks (seed 001 §4.1, seed 003 §2.2), then the opt-in "
        "transforming steps bspline, resample, smooth. Every removed, changed or replaced point goes "
        "to the rejected table with the rule, the action and the parameters.",
        epilog=_clean_help() + "\n\n" + EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _io_args(p, "cleaned points, canonical CSV")
    p.add_argument(
        "--rejected", type=Path, metavar="REJ.csv", help="write every removed or changed point"
    )
    p.add_argument(
        "--report", type=Path, metavar="R.json", help="counts per rule and per track, as JSON"
    )
    p.add_argument(
        "--set", action="append", metavar="RULE.PARAM=VALUE", help="change a parameter; repeatable"
    )
    p.add_argument(
        "--off",
        action="append",
        choices=RULES,
        metavar="RULE",
        help="switch a rule off; repeatable",
    )
    p.add_argument(
        "--resample",
        type=_positive_float,
        metavar="SECONDS",
        help="resample every track to this period (seed 003 uses 20 s)",
    )
    p.add_argument(
        "--max-gap",
        type=_positive_float,
        metavar="SECONDS",
        help="resample: never interpolate across longer gaps (default 60 s)",
    )
    p.add_argument(
        "--smooth",
        type=int,
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
    p.set_defaults(func=_cmd_clean)

    p = sub.add_parser(
        "maneuvers",
        help="find maneuver (turning) points",
        description="Seed 000's detector: heading of p points by PCA before and after each point, maneuver "
        "factor = their difference (deg), kept where above the threshold and the maximum within +-n points. "
        "Writes one row per maneuver point: sensor,batch,index,time,lon,lat,factor (index = 0-based "
        "position in the time-sorted track). --method imm|entropy runs the seed-000 baselines.",
        epilog=EPILOG,
    )
    _io_args(p, "maneuver points CSV to write")
    p.add_argument(
        "--method", choices=("pca", "imm", "entropy"), default="pca", help="detector (default pca)"
    )
    _add_detector_options(p)
    p.add_argument(
        "--sigma",
        type=_positive_float,
        default=300.0,
        help="imm: position noise std, metres (default 300)",
    )
    p.add_argument(
        "--k", type=int, help="entropy: number of maneuvers per track (default: from true_turn)"
    )
    p.set_defaults(func=_cmd_maneuvers)

    p = sub.add_parser(
        "compress",
        help="compress tracks to their turning points",
        description="Keep each track's first and last point and its maneuver points (or Douglas-Peucker "
        "points); vertices are placed by least squares on the track's points unless --raw-vertices. "
        "The report gives Dis_e (mean synchronized distance, metres; also against the true path when the "
        "input has true_lon/true_lat) and the share of points kept, per track and overall.",
        epilog=EPILOG,
    )
    _io_args(p, "kept points, canonical CSV")
    p.add_argument(
        "--method", choices=("maneuver", "dp"), default="maneuver", help="default maneuver"
    )
    p.add_argument("--report", type=Path, metavar="R.json", help="write Dis_e and ratios as JSON")
    p.add_argument(
        "--tolerance",
        type=_positive_float,
        default=600.0,
        help="dp: Douglas-Peucker tolerance, metres (default 600)",
    )
    p.add_argument(
        "--dp-distance",
        choices=("segment", "line"),
        default="segment",
        help="dp: distance to the chord segment (shapely/GEOS, default) or to its line "
        "(textbook; the form before issue 17)",
    )
    p.add_argument(
        "--raw-vertices",
        action="store_true",
        help="keep the raw points as vertices (the paper's way)",
    )
    _add_detector_options(p)
    p.set_defaults(func=_cmd_compress)

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
    _add_bearing_options(p)
    p.set_defaults(func=_cmd_bearing)

    from wakeline.core.associate import LinkParams

    p = sub.add_parser(
        "associate",
        help="join the tracks of one sensor that belong to one ship",
        description="interrupted (default): old track i and new track j of one sensor with j starting "
        "within max_gap_s after i ends and reachable at v_max_kn; distance from i's end to j's start by "
        "position (dead-reckoned, allowing one course change), course and speed; optimal one-to-one "
        "assignment (or seed 003's greedy). segments: seed 001's clustering of segments (area S and "
        "directional mean, or DTW/Hausdorff baselines; 'motion' = our distance). Writes every input row "
        "with a 'target' column; --stitch joins each target into one batch and fills the gaps.",
        epilog=_params_epilog(LinkParams),
    )
    _io_args(p, "points with a target column, canonical CSV")
    p.add_argument("--mode", choices=("interrupted", "segments"), default="interrupted")
    p.add_argument(
        "--method",
        help="interrupted: optimal (default) | greedy; segments: motion (default) | area | dtw | hausdorff",
    )
    p.add_argument(
        "--normalize",
        choices=("scaled", "minmax"),
        default="scaled",
        help="interrupted: divide each term by its tolerance (default) or seed 003's min-max",
    )
    p.add_argument(
        "--pairs",
        type=Path,
        metavar="PAIRS.csv",
        help="write the joined pairs with their distances",
    )
    p.add_argument(
        "--report", type=Path, metavar="R.json", help="write counts and parameters as JSON"
    )
    p.add_argument(
        "--stitch",
        action="store_true",
        help="one batch per target, gaps filled at the sensor period (column interpolated)",
    )
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="change a parameter")
    p.set_defaults(func=_cmd_associate)

    from wakeline.core.fuse import FuseParams

    p = sub.add_parser(
        "fuse",
        help="pair the tracks of two or more sensors and fuse each pair into one track",
        description="Tracks of different sensors that overlap in time, were near each other at some "
        "moment and have comparable point counts are compared by their mean synchronized distance "
        "(or DTW over positions) and paired one-to-one (optimal, or seed 003's greedy) up to "
        "max_distance_m. Each target becomes one track: sensor 'fused', batch = target id; where "
        "several sensors cover the time, the positions are averaged with weights from each track's "
        "sampling regularity and noise; elsewhere the single sensor's points; junctions blended. "
        "Columns added: source (sensors covering the point), n_sources, weight_base, members.",
        epilog=_params_epilog(FuseParams),
    )
    _io_args(p, "fused tracks, canonical CSV")
    p.add_argument("--distance", choices=("sync", "dtw"), default="sync", help="default sync")
    p.add_argument(
        "--method", choices=("optimal", "greedy"), default="optimal", help="default optimal"
    )
    p.add_argument(
        "--pairs",
        type=Path,
        metavar="PAIRS.csv",
        help="write the pairs: sensor_a,batch_a,sensor_b,batch_b,distance,overlap_s",
    )
    p.add_argument(
        "--report", type=Path, metavar="R.json", help="write counts and parameters as JSON"
    )
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="change a parameter")
    p.set_defaults(func=_cmd_fuse)

    p = sub.add_parser(
        "evaluate",
        help="reproduce the papers' evaluation tables",
        description="maneuver: seed 000's protocol (sigma 300/600 m x short/medium/long tracks) for our "
        "detector and compression and the IMM, entropy and Douglas-Peucker baselines; prints Table 1's "
        "layout with Dis_e against the true path and the observed points, and turn-point scores. "
        "bearing: seed 002's metrics (detection rate, reaction time, maneuver-time error, false alarms) "
        "on five scenarios and the noise and turn sweeps. associate: single-sensor association on "
        "sparse, dense and very dense simulated scenes (target-level and pairwise P/R/F1, P_CA, P_FA) "
        "for our methods and the seed 001 / seed 003 ones. fuse: multi-sensor P_CA/P_FA for "
        "synchronized and DTW distances with optimal and greedy assignment, and the fused position "
        "error next to each sensor's, on scenes of rising density.",
        epilog=EPILOG,
    )
    p.add_argument("kind", choices=("maneuver", "bearing", "associate", "fuse"))
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
        "--runs", type=_positive_int, default=1000, help="bearing: runs per scenario (default 1000)"
    )
    p.add_argument(
        "--sweep-runs",
        type=_positive_int,
        default=200,
        help="bearing: runs per sweep cell (default 200)",
    )
    p.add_argument(
        "--tracks", type=_positive_int, default=100, help="tracks per class (default 100)"
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--csv", type=Path, help="also write the full table as CSV")
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


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``wakeline`` command; returns the exit status."""
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(_with_default_command(parser, argv))
    try:
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

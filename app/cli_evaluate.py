"""``wakeline evaluate`` (the papers' tables) and ``wakeline bearing`` (seed 002's detector)."""

import argparse
import sys
from pathlib import Path

from wakeline.app.cli_common import (
    EPILOG,
    fuse_params,
    link_params,
    positive_float,
    positive_int,
    seed_int,
)


def _progress(fraction: float, text: str) -> None:
    """An evaluation's progress on stderr."""
    print(f"  {fraction:4.0%} {text}", file=sys.stderr)


def _say_read(path, report: dict) -> None:
    """What reading one of --real's files gave, on stderr as ``import`` says it: rows
    imported, quarantined (and why), blank lines, the columns taken, the warnings."""
    from wakeline.app.cli_steps import say_quarantined
    from wakeline.core.words import import_counts

    rep = report
    text = f"{path}: read {import_counts(rep)}"
    if rep.get("columns"):
        text += "; columns: " + ", ".join(f"{k}={v}" for k, v in rep["columns"].items())
    print(text, file=sys.stderr)
    for warning in rep.get("warnings", []):
        print(f"{path}: warning: {warning}", file=sys.stderr)
    say_quarantined(path, rep)


def _maneuver_sets() -> list:
    """The detector's parameter set as the step commands name it (flags ``--window-s`` …,
    dests ``p__maneuver__FIELD``; :func:`wakeline.app.cli_steps.add_param_flags`)."""
    from wakeline.core.maneuver import ManeuverParams

    return [("maneuver", ManeuverParams)]


def _maneuver_params(args: argparse.Namespace):
    """The detector's parameters as the ``maneuvers`` command makes them: the defaults (or
    ``--paper``'s), ``--preset``'s changes over them, and the flags given over both (a flag
    given applies, even at the default's value)."""
    from wakeline.app.cli_steps import given_params
    from wakeline.core.maneuver import ManeuverParams

    params = ManeuverParams.paper() if getattr(args, "paper", False) else ManeuverParams()
    name = getattr(args, "preset", None)
    if name:
        from wakeline.core.presets import apply_preset

        params = apply_preset(name, {"maneuver": params})["maneuver"]
    return params.replace(**given_params(args, _maneuver_sets())["maneuver"]).checked()


def _cmd_evaluate(args: argparse.Namespace) -> int:

    from wakeline.core.errors import InputError
    from wakeline.core.evaluate import evaluate_maneuver
    from wakeline.core.io import write_csv

    # refused rather than ignored: the table printed would not be the one asked for
    if args.hard and (args.kind not in ("maneuver", "associate", "fuse") or args.real):
        where = "--real" if args.real else args.kind
        raise InputError(
            f"--hard applies to the simulated maneuver, associate and fuse scenes, not {where}"
        )
    if args.real and args.kind not in ("associate", "maneuver"):
        raise InputError(f"--real applies to associate and maneuver, not to {args.kind}")
    if args.sensor != "radar" and not (args.real and args.kind == "maneuver"):
        raise InputError("--sensor applies to maneuver --real (the Autoferry set)")
    if args.gnss and not (args.real and args.kind == "maneuver"):
        raise InputError("--gnss applies to maneuver --real (a file or folder of tracks)")
    if args.gnss_map and not args.gnss:
        raise InputError("--gnss-map needs --gnss")
    if args.sweep and args.kind != "bearing":
        raise InputError(f"--sweep applies to evaluate bearing, not to {args.kind}")
    if args.sweep_values and not args.sweep:
        raise InputError("--sweep-values needs --sweep sigma or --sweep turn")
    if getattr(args, "preset", None) and args.kind != "maneuver":
        raise InputError(f"--preset applies to evaluate maneuver, not to {args.kind}")
    from wakeline.app.cli_steps import read_options

    read = read_options(args)  # --real's track files: read as import reads them
    if not args.real and any(v not in (None, "auto") for v in read.values()):
        raise InputError("the reading flags (--map, --skip-rows, ...) apply to --real's files")

    if args.kind == "fuse":
        from wakeline.core.evaluate_association import evaluate_fusion

        ev = evaluate_fusion(
            args.scenes,
            args.seed,
            fuse_params(args.set),
            progress=_progress,
            hard=args.hard,
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table.merge(ev.errors, on="scene"), args.csv)
        return 0

    if args.kind == "associate" and args.real:
        from wakeline.core.evaluate_association import evaluate_real_association

        if args.gaps_every is not None and args.gaps is None:
            raise InputError("--gaps-every needs --gaps LO HI (the length of each window)")

        ev = evaluate_real_association(
            args.real,
            cut_s=args.cut_s,
            gaps=args.gaps,
            gaps_every=args.gaps_every,
            params=link_params(args.set),
            truth_sep=args.truth_sep,
            mapping=read.pop("mapping"),
            read=read,
            seed=args.seed,
            progress=_progress,
            reading=_say_read,
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
            link_params(args.set),
            progress=_progress,
            hard=args.hard,
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table, args.csv)
        return 0

    if args.kind == "bearing" and args.sweep:
        from wakeline.core.bearing_eval import format_sweep, sweep_bearing

        ev = sweep_bearing(
            args.sweep,
            args.runs,
            args.seed,
            _bearing_params(args),
            values=tuple(args.sweep_values or ()),
            progress=_progress,
        )
        print(format_sweep(ev))
        if args.csv:
            write_csv(ev["table"], args.csv)
        return 0

    if args.kind == "bearing":
        from wakeline.core.bearing_eval import evaluate_bearing, format_evaluation

        ev = evaluate_bearing(
            args.runs,
            args.seed,
            _bearing_params(args),
            geometries=args.geometries,
            compare=not args.ours_only,
            progress=_progress,
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
            progress=_progress,
            mapping=read.pop("mapping"),
            read=read,
            sensor=args.sensor,
            gnss=args.gnss,
            gnss_mapping=args.gnss_map,
            gate_m=args.gnss_gate_m,
            gnss_fault_m=args.gnss_fault_m if args.gnss_fault_m is not None else float("inf"),
            reading=_say_read,
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.rows, args.csv)
        return 0

    if args.hard:
        from wakeline.core.evaluate import evaluate_maneuver_hard

        ev = evaluate_maneuver_hard(
            args.tracks, args.seed, args.scenes, _maneuver_params(args), progress=_progress
        )
        print(ev.format())
        if args.csv:
            write_csv(ev.table, args.csv)
        return 0

    ev = evaluate_maneuver(
        args.tracks,
        args.seed,
        _maneuver_params(args),
        progress=_progress,
    )
    print(ev.format())
    if args.csv:
        write_csv(ev.table, args.csv)
    return 0


def _add_detector_options(p: argparse.ArgumentParser) -> None:
    """One flag per ManeuverParams field, generated as on the ``maneuvers`` command (and
    its older spellings --window, --radius, --threshold, --min-speed), and ``--paper``."""
    from wakeline.app.cli_steps import add_param_flags

    add_param_flags(p, _maneuver_sets())
    p.add_argument(
        "--paper",
        action="store_true",
        help="seed 000 as written: --window points per window, one scale, no speed, noise or "
        "at-rest rule (compress: maneuver points only, raw vertices); flags given still apply",
    )


def _bearing_params(args: argparse.Namespace):
    from wakeline.core.bearing import BearingParams

    return BearingParams(
        **{d["name"]: getattr(args, d["name"]) for d in BearingParams.describe()}
    ).checked()


def _cmd_bearing(args: argparse.Namespace) -> int:
    from wakeline.app.cli_steps import read_options, say_quarantined
    from wakeline.core.bearing import detect_with_report, report_lines
    from wakeline.core.bearing_read import read_bearing_file, summary_lines
    from wakeline.core.io import write_csv, write_json

    params = _bearing_params(args)
    got = read_bearing_file(args.input, **read_options(args))
    bearings, quarantine = got.bearings, got.quarantine
    q = got.report["quarantined"]
    read = {
        "rows_imported": len(bearings),
        "rows_quarantined": int(sum(q.values())),
        "quarantine_reasons": q,
        "rows_not_bearings": got.report["set_aside"],
        "file": got.report,
    }
    if args.tracks:
        from wakeline.core.bearing_read import gate_to_tracks
        from wakeline.core.io import read_points

        origin = got.report["origin"]  # the bearings' plane, for a track file in metres
        tracks = read_points(
            args.tracks,
            mapping=args.tracks_map,
            origin=",".join(map(repr, origin)) if origin else None,
        ).points
        bearings, got.report["gated"] = gate_to_tracks(bearings, tracks, args.gate)
    for line in summary_lines(got.report):
        print(f"{args.input.name}: {line}", file=sys.stderr)
    say_quarantined(args.input, read, "bearing")
    if args.quarantine:
        write_csv(quarantine, args.quarantine)
    table, report = detect_with_report(bearings, params)
    write_csv(table, args.output)
    if args.report:
        write_json({"batches": report, "read": read, "params": dict(vars(params))}, args.report)
    for line in report_lines(report):
        print(line, file=sys.stderr)
    print(f"{len(table):,} maneuver detections", file=sys.stderr)
    return 0


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
        if isinstance(d["default"], str):
            p.add_argument(
                flag,
                dest=d["name"],
                choices=d["choices"],
                default=d["default"],
                help=f"{d['doc']} (default {d['default']})",
            )
            continue
        kind = positive_int if isinstance(d["default"], int) else positive_float
        p.add_argument(
            flag,
            dest=d["name"],
            type=kind,
            default=d["default"],
            help=f"{d['doc']} (default {d['default']:g}{unit})",
        )


def register(sub) -> None:
    """Add the bearing and evaluate subcommands."""
    p = sub.add_parser(
        "bearing",
        help="detect target maneuvers in bearing-only sequences (seed 002)",
        description="Input: batch,time,bearing[,obs_lon,obs_lat or obs_east,obs_north with "
        "--origin] (degrees, or radians for a bearing_rad header; the observer's positions "
        "enter the motion fit, through its own turns; --exclude-observer-turns skips the spans where "
        "it maneuvers instead). Two sliding windows X and Y (seconds); by default a "
        "likelihood-ratio test of a bearing-rate change fitted with a constant-velocity target "
        "over X and nested Y spans (--no-glr: seed 002's Mann-Whitney AUC of the residuals from "
        "the trend fitted on X). Writes one row per detection: batch,detect_time,maneuver_time,z.",
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
    p.add_argument(
        "--quarantine",
        type=Path,
        metavar="Q.csv",
        help="the input lines not read as bearings: line, reason, text",
    )
    p.add_argument(
        "--tracks",
        type=Path,
        metavar="FILE",
        help="a track file of the targets (GNSS truth, AIS; read as `wakeline import` reads "
        "it, in metres on the bearings' --origin plane if it has no lon/lat): each bearing "
        "goes to the track whose bearing from the observer is within --gate, the nearest "
        "per series, track and time; one sequence per series and track (several targets "
        "or clutter in one camera frame: SPEC §4 wants one target's sequence)",
    )
    p.add_argument(
        "--tracks-map",
        action="append",
        metavar="FIELD=COLUMN",
        help="--map for the --tracks file (track fields); repeatable",
    )
    p.add_argument(
        "--gate",
        type=positive_float,
        default=3.0,
        metavar="DEG",
        help="with --tracks: largest bearing difference to a track (default 3°)",
    )
    from wakeline.app.cli_steps import add_read_flags
    from wakeline.core.bearing_read import BEARING_FIELDS

    add_read_flags(
        p,
        omit=(
            "format",
            "tz",
            "sensor",
            "date-order",
            "time-unit",
            "speed-unit",
            "distance-unit",
            "date",
        ),  # fmt: skip
        description="the track reader's --map and --origin, for bearing fields; a known "
        "layout (the Autoferry camera detections) needs neither",
        helps={
            "map": f"take bearing FIELD ({', '.join(BEARING_FIELDS)}) from COLUMN; batch=A+B "
            "joins two columns (a scenario and a camera: A/B); target=COLUMN splits each "
            "series by a target id; repeatable",
            "origin": "origin (degrees) of the plane the observer's east/north metres "
            "(obs_east/obs_north, own_east/own_north, or --map obs_east=… obs_north=…) are "
            "measured from; turned into lon/lat as the track reader does",
        },
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
        "(autoferry-fusion, greece-ais-annotated, dma-single-ship, oresund-encounters), or "
        "any file or folder of track files (no turn truth: slow share, at-rest spans, "
        "compression against Douglas-Peucker; read as import reads them, see 'reading the "
        "input' below; a file with true_turn and turn_deg columns, as simulate maneuver "
        "--hard writes, is also scored against them: precision, recall, and Dis_e against "
        "true_lon/true_lat); "
        "associate: a file, or every track file in DIR (.csv .tsv .txt .nmea .log .gpx .geojson, or "
        "those compressed: .gz .bz2 .xz .zst, or a .zip of one file; a file of no track is skipped with the reason); each track's id is the truth ("
        "tracks are cut at their gaps, pieces renumbered); one of those four folders is "
        "read as one scene by its own reader (autoferry-fusion: the radar tracks, "
        "1.7 s, e.g. with --cut-s 5)",
    )
    p.add_argument(
        "--sensor",
        choices=("radar", "lidar"),
        default="radar",
        help="maneuver --real autoferry-fusion: the tracks from radar plots (1.7 s) or lidar "
        "returns (0.5 s), each within 15 m of a target's GNSS position, the nearest per scan "
        "(default radar)",
    )
    p.add_argument(
        "--gnss",
        metavar="FILE",
        help="maneuver --real FILE or folder: a file or folder of truth tracks (GNSS logs of "
        "the targets, read as import reads them) to score turns against: each track is "
        "scored against the truth track it follows (median distance within --gnss-gate-m)",
    )
    p.add_argument(
        "--gnss-map",
        metavar="FIELD=COLUMN",
        action="append",
        help="--gnss file's columns, as --map (repeatable)",
    )
    p.add_argument(
        "--gnss-gate-m",
        type=positive_float,
        default=50.0,
        help="m: a track follows the truth track whose median distance at its fixes is at "
        "most this (default 50)",
    )
    p.add_argument(
        "--gnss-fault-m",
        type=positive_float,
        help="m: a truth fix that departs this far from its local velocity is a GNSS fault, "
        "and a turn within 2 s of one is not scored for recall (the Autoferry set's rule, "
        "0.5 there; for logs of many fixes a second; default: no such rule)",
    )
    p.add_argument(
        "--scenes",
        type=positive_int,
        default=5,
        help="associate, fuse: scenes per density class; maneuver --hard: scenes, seeds "
        "--seed on (default 5)",
    )
    p.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="associate, fuse: change a parameter",
    )
    from wakeline.app.cli_steps import add_preset_flag

    add_preset_flag(p, ["maneuver"])  # evaluate maneuver: the detector's (ours)
    p.add_argument(
        "--runs", type=positive_int, default=20, help="bearing: runs per scenario (default 20)"
    )
    p.add_argument(
        "--sweep",
        choices=("sigma", "turn"),
        help="bearing: seed 002's sweeps on its five scenarios instead of the held-out table: "
        "sigma = bearing noise 0.1-2 deg at a 60 deg turn (its Figs. 4-6), turn = 10-110 deg "
        "at 0.6 deg noise (Figs. 7-9); rates with their 95 %% interval",
    )
    p.add_argument(
        "--sweep-values",
        type=positive_float,
        nargs="+",
        metavar="V",
        help="bearing --sweep: the noise values (deg) or turns (deg) to run instead of the paper's",
    )
    p.add_argument(
        "--geometries",
        type=positive_int,
        default=8,
        help="bearing: random held-out geometries, each at 1 s, 2 s and jittered sampling (default 8)",
    )
    p.add_argument(
        "--ours-only",
        action="store_true",
        help="bearing: skip the eq. 15 AUC-mean and quadratic-trend comparisons",
    )
    p.add_argument(
        "--tracks",
        type=positive_int,
        default=100,
        help="maneuver: tracks per class; --hard: ships per scene (default 100)",
    )
    p.add_argument("--seed", type=seed_int, default=0, help="random seed, 0-4294967295 (default 0)")
    p.add_argument("--csv", type=Path, help="also write the full table as CSV")
    p.add_argument(
        "--hard",
        action="store_true",
        help="maneuver, associate, fuse: the hard simulated scenes (see 'simulate --hard'); "
        "maneuver: radar 1-2 s and AIS 10/30 s tracks with jitter, missed scans, gaps, "
        "heavy-tailed noise, speed changes, sharp and gradual turns, slow and moored ships; "
        "turn scores, slow shares and compression against Douglas-Peucker, ours and --paper",
    )
    p.add_argument(
        "--cut-s",
        type=positive_float,
        default=120.0,
        help="associate --real: cut where a step exceeds this (s) and 4x the track's median "
        "step (default 120)",
    )
    p.add_argument(
        "--gaps",
        type=positive_float,
        nargs=2,
        metavar=("LO", "HI"),
        help="associate --real: instead of cutting at the tracks' own gaps, remove one window "
        "of fixes of random length in [LO, HI] s from each track, at least 120 s from either "
        "end (known gaps; --seed draws them)",
    )
    p.add_argument(
        "--gaps-every",
        type=positive_float,
        metavar="S",
        help="associate --real --gaps: one such window in every S seconds of each track "
        "(many true pairs from a few long tracks) instead of one per track",
    )
    p.add_argument(
        "--truth-sep",
        default="",
        metavar="CHAR",
        help="associate --real: the truth is the track id up to this character "
        "(MTAD: '-', so MMSI-k sub-tracks are one ship)",
    )
    from wakeline.app.cli_steps import add_read_flags

    add_read_flags(
        p,
        omit=("sensor",),
        description="--real FILE or a folder of track files (maneuver and associate): how "
        "each file is read, as `wakeline import` and the steps read it (e.g. --skip-rows N "
        "as given to `wakeline clean`). The four named folders of shared/data/real are read "
        "by their own readers and ignore these flags.",
    )
    _add_detector_options(p)
    _add_bearing_options(p)
    p.set_defaults(func=_cmd_evaluate)

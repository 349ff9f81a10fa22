"""``wakeline review``: apply the operator's decisions to the engine's proposals, as the
review panel would, and export the result (SPEC §7, issue 13)."""

import argparse
import sys
from pathlib import Path

import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.words import count

_TEXT = (
    "proposal",
    "kind",
    "method",
    "sensor_a",
    "batch_a",
    "sensor_b",
    "batch_b",
    "runner_up",
    "runner_up_side",
    "plot_tracks",
)


def read_inputs(paths: list[Path], counts: dict | None = None, **options) -> pd.DataFrame:
    """Read one or several track files as one point table; files that each hold one
    sensor of the same name get the differing part of their names as sensor.
    ``options``: how to read them (read_points keywords, as ``--map`` and friends);
    ``counts``, when given, receives the reading's counts summed over the files."""
    from wakeline.app.cli_steps import read_input
    from wakeline.core.review import combine_sources, source_names

    paths = list(paths) if isinstance(paths, list | tuple) else [paths]
    tables = []
    for p in paths:
        one: dict = {}
        tables.append((p.stem, read_input(p, one, **options)))
        if counts is not None:
            for key, value in one.items():
                if isinstance(value, dict):
                    merged = counts.setdefault(key, {})
                    for k, v in value.items():
                        merged[k] = merged.get(k, 0) + v
                else:
                    counts[key] = counts.get(key, 0) + value
    names = source_names([name for name, _ in tables], [str(p) for p in paths])
    return combine_sources([(n, t) for n, (_, t) in zip(names, tables, strict=True)])


def read_table(path: Path, what: str) -> pd.DataFrame:
    """A small CSV (proposals or decisions) with every column as text, blanks kept. The
    delimiter is the header line's most frequent of ``,`` ``;`` and tab (a table saved by
    a European-locale spreadsheet is ``;``-separated), as for track files."""
    import csv

    from wakeline.core.io.sniff import opening

    try:
        with opening(path), open(path, encoding="utf-8-sig", newline="") as fh:
            first = next((line for line in fh if line.strip()), "")
            sep = max((",", ";", "\t"), key=first.count) if first else ","
            sep = sep if first.count(sep) else ","
            fh.seek(0)
            reader = csv.reader(fh, delimiter=sep)
            header = next((row for row in reader if row), None)  # blank lines skipped
            for row in reader:  # a few thousand proposals at most
                if row and len(row) != len(header):
                    raise InputError(
                        f"{path}: line {reader.line_num} of the {what} table has {len(row)} "
                        f"fields, the header {len(header)}"
                    )
        return pd.read_csv(
            path, sep=sep, dtype=str, keep_default_na=False, encoding="utf-8-sig", index_col=False
        )
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: the {what} file is empty") from None
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the {what} table ({exc})") from None
    except csv.Error as exc:  # a field over the csv module's limit (128 KB), a NUL byte
        raise InputError(f"{path}: cannot read the {what} table ({exc})") from None


def _proposals(path: Path) -> pd.DataFrame:
    df = read_table(path, "proposals")
    for c in df.columns:
        if c not in _TEXT:
            df[c] = pd.to_numeric(df[c].replace("", None), errors="coerce")
    return df


#: What ``review -o`` writes, by the output's suffix.
OUTPUT_SUFFIXES = {".csv": "csv", ".geojson": "geojson", ".json": "geojson", ".gpx": "gpx"}


def _check_suffixes(args: argparse.Namespace) -> None:
    """Refuse, before any work, an output whose suffix names no format ``review`` writes
    (``-o x.txt`` held CSV with no word: operator test 9, D14), as ``render`` refuses a
    non-PNG; the decision log (``--log``) is CSV."""
    suffix = Path(args.output).suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise InputError(
            f"{args.output}: review writes by the suffix of -o: .csv (the rows with a "
            f"target column), .geojson or .gpx (one track per target), not "
            f"{suffix or 'a name without a suffix'}"
        )
    if args.log is not None and Path(args.log).suffix.lower() != ".csv":
        raise InputError(f"{args.log}: the decision log (--log) is written as CSV: name it .csv")


def _cmd_review(args: argparse.Namespace) -> int:
    from wakeline.app.cli_steps import read_options
    from wakeline.core.export_review import (
        export_decision_log,
        export_tracks,
        fused_tracks,
        merged_tracks,
    )
    from wakeline.core.review import ReviewState, apply_decisions, track_table, unreviewed_note

    _check_suffixes(args)
    points = read_inputs(args.input, **read_options(args))
    if args.proposals:
        props = pd.concat([_proposals(p) for p in args.proposals], ignore_index=True)
    else:  # joins by hand only (decision = merge / join): no proposal to decide
        from wakeline.core.review_join import empty_proposals

        props = empty_proposals()
    state = ReviewState(track_table(points), props)
    if args.decisions:
        apply_decisions(state, read_table(args.decisions, "decisions"))
    if args.fused:
        from wakeline.app.cli_common import fuse_params
        from wakeline.core.fuse import associate_sensors

        params = fuse_params(args.set)
        if points["sensor"].nunique() >= 2:
            sassoc = associate_sensors(points, params)
        else:
            raise InputError("--fused needs tracks of at least two sensors")
        out = fused_tracks(state, sassoc, params)
    elif Path(args.output).suffix.lower() in (".gpx", ".geojson", ".json"):
        out = merged_tracks(state, points)
    else:
        out = state.label_points(points)
    fmt = export_tracks(out, args.output, bom=args.bom)
    if args.log:
        export_decision_log(state, args.log, bom=args.bom)
    tab = state.table()
    counts = tab["status"].value_counts().to_dict()
    n_targets = state.targets()["target"].nunique()
    print(
        f"{count(len(tab), 'proposal')} ("
        + ", ".join(
            f"{counts.get(s, 0):,} {s}" for s in ("accepted", "rejected", "split", "pending")
        )
        + f"), {count(len(state.log), 'decision')}, {count(len(state.tracks), 'track')} -> "
        f"{count(n_targets, 'target')}; wrote {fmt}",
        file=sys.stderr,
    )
    note = unreviewed_note(state)  # the pending ones are joined in the file written
    if note:
        print(note, file=sys.stderr)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``review`` subcommand to the ``wakeline`` parser."""
    from wakeline.app.cli_common import EPILOG

    p = sub.add_parser(
        "review",
        help="apply accept/reject/merge/split decisions to the proposals and export",
        description="Reads the points (one or several files, as `fuse` does), the proposals written "
        "by `associate --proposals` / `fuse --proposals` (several tables may be given) and "
        "the decisions: rows proposal,decision with decision = accept | reject | reset, or "
        "decision = merge (or join) with sensor_a,batch_a,sensor_b,batch_b (two tracks joined by "
        "hand, whether or not a proposal links them), or decision = split with "
        "sensor_a,batch_a (that track leaves its target); applied in order; or a decision log (the "
        "window's Review ▸ Export decision log, or --log: time,action,proposal,tracks,…), "
        "replayed with its undos as the window made it. Proposals without a "
        "decision count as accepted. Targets are the connected components of the proposals not "
        "rejected plus the manual merges minus the splits, named after the sensor:batch of their "
        "earliest track. OUT by its suffix: .csv every input row with a target column (or the "
        "fused tracks with --fused), .geojson / .gpx one track per target.",
        epilog=EPILOG,
    )
    p.add_argument("input", type=Path, nargs="+", help="track file(s) the proposals were made on")
    p.add_argument(
        "-o", "--output", type=Path, required=True, help="result: .csv, .geojson or .gpx"
    )
    p.add_argument(
        "--proposals",
        type=Path,
        nargs="+",
        action="extend",  # the flag given twice: both tables (was the last, silently)
        metavar="P.csv",
        help="proposals table(s): e.g. one from associate and one from fuse (none: the "
        "decisions join tracks by hand only, rows decision = merge or join)",
    )
    p.add_argument(
        "--decisions",
        type=Path,
        metavar="D.csv",
        help="decisions table, or a decision log of the window or --log (none: accept all)",
    )
    p.add_argument(
        "--log", type=Path, metavar="LOG.csv", help="write the decision log (time, action, …)"
    )
    p.add_argument(
        "--fused",
        action="store_true",
        help="write one fused track per decided target (sensor 'fused', members, source)",
    )
    p.add_argument(
        "--bom",
        action="store_true",
        help="start CSV files with a UTF-8 byte-order mark (spreadsheets then read Chinese)",
    )
    p.add_argument(
        "--set", action="append", metavar="NAME=VALUE", help="--fused: change a fuse parameter"
    )
    from wakeline.app.cli_steps import add_read_flags

    add_read_flags(p)  # how the track files are read: the same flags as the steps
    p.set_defaults(func=_cmd_review)

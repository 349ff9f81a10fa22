"""``wakeline batch``: a saved pipeline over inputs larger than memory, with Dask.

Registered by :func:`register` from ``build_parser()``; the engine is
:mod:`wakeline.core.batch` (docs/batch.md).
"""

import argparse
import sys
from pathlib import Path

from wakeline.app.cli_common import positive_float, positive_int
from wakeline.core.errors import InputError
from wakeline.core.words import count

EPILOG = (
    "Exit status: 0 every input read (rows quarantined, as in the other commands, are "
    "counted on stderr and kept in OUTDIR/quarantine); 2 nothing written: bad usage or "
    "input (one message on stderr), or no input could be read (every one refused, or every "
    "row quarantined); 3 the batch ran and wrote OUTDIR but left an input file out: "
    "refused (listed on stderr as FILE: refused: WHY and in report.json refused_inputs; a "
    "file whose every row is quarantined too); the last stderr line counts them; 130 "
    "interrupted (Ctrl+C: OUTDIR is incomplete, marked "
    "by BATCH_INCOMPLETE.txt; the same command starts over in it); 1 internal error."
)

#: ``wakeline batch``'s exit status when it wrote its outputs but left an input file out
#: (refused); 2 is "nothing written" (operator h228: one code said both). Quarantined rows
#: alone give 0, as in the single-file commands: real exports nearly always hold a few, and
#: a script that stops on a non-zero status would stop on nearly every batch.
LEFT_OUT = 3


def _cmd_batch(args: argparse.Namespace) -> int:
    from wakeline.core.pipeline import Pipeline

    if args.print_pipeline:
        pipe = Pipeline.default()
        if args.preset:
            from wakeline.core.presets import preset_pipeline

            pipe = preset_pipeline(pipe, args.preset)
        print(pipe.to_json())
        return 0
    if args.pipeline is None or not args.input or args.outdir is None:
        raise InputError("batch needs PIPELINE.json, at least one input and -o OUTDIR")
    try:
        import dask  # noqa: F401
        import distributed  # noqa: F401
    except ImportError:
        raise InputError(
            "batch needs Dask: pip install 'wakeline[batch]' (dask[dataframe], distributed)"
        ) from None
    from wakeline.core.batch import BatchInterrupted, BatchOptions, breaks_said, run_batch
    from wakeline.core.io.sniff import opening

    try:
        with opening(args.pipeline):
            text = args.pipeline.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{args.pipeline}: not UTF-8 text") from None
    pipe = Pipeline.from_json(text)
    if args.preset:  # over the pipeline file's values, stage by stage
        from wakeline.core.presets import preset_pipeline

        pipe = preset_pipeline(pipe, args.preset)
    from wakeline.app.cli_steps import read_options

    read = read_options(args)  # BatchOptions names its fields as read_points does
    opts = BatchOptions(
        partition_mb=args.partition_mb,
        blocksize_mb=args.blocksize_mb,
        scheduler=args.scheduler or "",
        workers=args.workers or 0,
        csv=args.csv,
        sensor_per_file=args.sensor_per_file,
        **read | {"mapping": tuple(read["mapping"] or ())},
    )
    try:
        result = run_batch(
            pipe, args.input, args.outdir, opts, log=lambda m: print(m, file=sys.stderr)
        )
    except BatchInterrupted as stop:  # one line, no traceback (operator test 9, D7)
        print(f"wakeline: {stop.message()}", file=sys.stderr)
        return 130
    rep = result.report
    steps = "; ".join(
        f"{name} {s['rows_in']:,} -> {s['rows_out']:,}"
        + (breaks_said(rep) if name == "clean" else "")
        for name, s in rep["steps"].items()
    )
    skipped = len(rep["empty_inputs"]) + len(rep["skipped_inputs"])
    skipped_text = ""
    if skipped:
        skipped_text = f"; {count(skipped, 'input')} skipped (above)"
    print(
        f"batch: {count(rep['rows_read'], 'row')} ({rep['quarantined']:,} quarantined) in "
        f"{count(rep['buckets'], 'partition')}; {steps}{skipped_text}; wrote {args.outdir}",
        file=sys.stderr,
    )
    refused = rep.get("refused_inputs") or []
    quarantined = int(rep.get("quarantined") or 0)
    if refused or quarantined:  # listed above, each with its reason; the rest were processed
        parts = []
        if refused:
            parts.append(f"{count(len(refused), 'input')} refused (above, each with its reason)")
        if quarantined:
            parts.append(
                f"{count(quarantined, 'row')} of {rep['rows_read']:,} quarantined "
                f"({args.outdir / 'quarantine'})"
            )
        print(
            f"batch: wrote {args.outdir}, but left out {' and '.join(parts)}"
            + (f"; exit status {LEFT_OUT}" if refused else ""),
            file=sys.stderr,
        )
        return LEFT_OUT if refused else 0
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``batch`` subcommand to the ``wakeline`` parser."""
    p = sub.add_parser(
        "batch",
        help="run a saved pipeline over large inputs with Dask (per-track partitions)",
        description="Run a saved pipeline (Run > Save pipeline in the GUI, or "
        "--print-pipeline) over inputs larger than memory: CSV files of any layout `wakeline "
        "import` reads (read as it reads them, with the same --format/--map/--encoding/"
        "--delimiter/--tz/--sensor/--skip-rows; gzip, bz2, xz, zstd too, and a zip: each file "
        "in it an input), or Parquet "
        "files with the canonical columns; a folder gives its data files (as `wakeline "
        "evaluate --real` reads a folder), or its Parquet files. Rows are partitioned by "
        "(sensor, batch) so every "
        "track is processed whole by the same step functions as `wakeline "
        "clean|maneuvers|compress`; interrupted association runs once over every track's end "
        "points and maps the targets back (docs/batch.md). Writes OUTDIR/<step>/ as Parquet "
        "partitions, OUTDIR/report.json, and with --csv OUTDIR/<step>.csv in canonical CSV. An "
        "input without a data row (empty, or a header only) is skipped with a warning; so is, "
        "among several inputs, one that is not track data (a README.txt: binary, or a header "
        "of no known column and no --map column). Every other refusal (a --map column missing "
        "from a data file, known columns but a required one missing) is listed with its "
        "reason, the other inputs are processed, and the batch ends with exit status 3 "
        "(2 when none is left): nothing is left out silently. The reading flags apply to every input: a file that "
        "needs its own is run apart, or imported to canonical CSV first (`wakeline import`).",
        epilog=EPILOG,
    )
    p.add_argument("pipeline", type=Path, nargs="?", help="pipeline JSON")
    p.add_argument(
        "input",
        type=Path,
        nargs="*",
        help="CSV files (any layout `wakeline import` reads), or Parquet files (canonical "
        "columns), or folders of them",
    )
    # dest outdir: the command line's output check is for files, OUTDIR is a folder.
    p.add_argument(
        "-o",
        "--output",
        dest="outdir",
        type=Path,
        help="output folder (new, or an earlier batch's)",
    )
    p.add_argument(
        "--scheduler", metavar="ADDRESS", help="dask.distributed scheduler (tcp://host:8786)"
    )
    p.add_argument(
        "--workers",
        type=positive_int,
        metavar="N",
        help="start a local cluster of N worker processes (default: Dask's local threads)",
    )
    p.add_argument("--csv", action="store_true", help="also write OUTDIR/<step>.csv")
    p.add_argument(
        "--sensor-per-file",
        action="store_true",
        help="each CSV input is its own sensor, named by its file name: without a sensor "
        "column radar.csv -> radar, with one its values prefixed (AIS -> radar/AIS): two "
        "consoles that number their tracks alike stay apart instead of joining into one "
        "track each (default: every input is --sensor, S1, or its sensor column's values)",
    )
    p.add_argument(
        "--partition-mb",
        type=positive_float,
        default=32.0,
        metavar="MB",
        help="input megabytes (as text; compressed inputs estimated) per partition of whole "
        "tracks (default 32; a worker thread holds about 20x this)",
    )
    p.add_argument(
        "--blocksize-mb",
        type=positive_float,
        default=32.0,
        metavar="MB",
        help="Parquet inputs: megabytes (uncompressed) of row groups per read task (default 32; "
        "a row group is never split). CSV inputs are one task per file, read in 16 MB pieces "
        "whatever this is",
    )
    p.add_argument(
        "--print-pipeline",
        action="store_true",
        help="print the default pipeline (clean, compress) as JSON and exit",
    )
    from wakeline.app.cli_steps import add_preset_flag, add_read_flags

    add_preset_flag(p)  # every stage's parameter sets the preset changes, over the file's
    add_read_flags(p)  # how CSV inputs are read: the same flags as `wakeline clean`
    p.set_defaults(func=_cmd_batch)

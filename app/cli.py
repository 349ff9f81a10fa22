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

from wakeline.app import cli_batch, cli_data, cli_evaluate, cli_export, cli_render
from wakeline.app.cli_common import EPILOG
from wakeline.core import __version__
from wakeline.core.errors import InputError


def _cmd_gui(args: argparse.Namespace) -> int:
    try:
        from wakeline.app.main import run
    except ImportError as exc:
        raise InputError(f"the desktop application cannot start: {exc}") from None
    from wakeline.app.cli_steps import read_options

    language = {"language": args.language} if args.language else {}
    if args.vessels is not None:
        if not args.vessels.is_file():
            raise InputError(f"{args.vessels}: no such file (--vessels)")
        language["vessels"] = args.vessels  # run's keywords given: only those set
    return run(
        args.files, screenshot=args.screenshot, read=read_options(args, given=True), **language
    )


def build_parser() -> argparse.ArgumentParser:
    """The whole ``wakeline`` parser: every subcommand registered by its module."""
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

    cli_data.register(sub)

    from wakeline.app.cli_steps import add_step_parsers

    add_step_parsers(sub)
    cli_evaluate.register(sub)

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
        help="load, run the default pipeline (clean, maneuvers, compress) on the first file "
        "- not on a file that is mostly radar plots: those are shown as dots and stderr says "
        "why - render the main window at 1400x900 to PNG and exit",
    )
    p.add_argument(
        "--language",
        choices=("en", "zh_CN"),
        help="the window's language (default: the one last chosen in the Language menu, "
        "else the system's, $LANG; a --screenshot: the system's)",
    )
    p.add_argument(
        "--vessels",
        type=Path,
        metavar="FILE",
        help="a vessel table (ship id, name and/or type columns, e.g. MMSI;TYPE) joined to "
        "FILES by the ship id: the batch table's Name and Type columns, the map's labels "
        "(File ▸ Load ship names)",
    )
    from wakeline.app.cli_steps import add_read_flags

    add_read_flags(p, description="how FILES are read (the File ▸ Open dialog's fields)")
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
    if rest and (problem := unknown_command(rest[0], list(commands))):
        raise InputError(problem)
    return [*globals_, "gui", *rest]


def unknown_command(word: str, commands: list[str]) -> str | None:
    """What is wrong with a first word that names no subcommand and no file to open, or
    None: ``wakeline clen FILE`` said "unknown command 'clen' — did you mean 'clean'?"
    instead of opening a window on a file named "clen" (operator test 9, D5).

    A word that is an existing path, or looks like one (a folder separator or a suffix),
    or an option, is a file for the desktop application as before."""
    if word.startswith("-") or "/" in word or "\\" in word or Path(word).suffix:
        return None
    if Path(word).exists():
        return None
    import difflib

    close = difflib.get_close_matches(word, commands, n=1, cutoff=0.6)
    if close:
        return f"unknown command '{word}' — did you mean '{close[0]}'?"
    return (
        f"unknown command '{word}' (the commands: {', '.join(commands)}; a file to open must exist)"
    )


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
    try:
        argv = _with_default_command(parser, argv)
    except InputError as exc:
        print(f"wakeline: error: {exc}", file=sys.stderr)
        return 2
    args = parser.parse_args(argv)
    try:
        _check_paths(args)
        return args.func(args)
    except InputError as exc:
        print(f"wakeline: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        from wakeline.core.io.sniff import open_problem

        name = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        words = (open_problem(exc) if name else None) or exc.strerror or exc
        print(f"wakeline: error: {name}{words}", file=sys.stderr)
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

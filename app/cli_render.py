"""``wakeline render IN… -o OUT.png``: draw track files with the map canvas, offscreen.

Registered by :func:`register` from ``build_parser()``; Qt is imported only when the
command runs (offscreen unless a platform is set).
"""

import argparse
import os
import re
from pathlib import Path

from wakeline.app.cli_common import EPILOG
from wakeline.core.errors import InputError
from wakeline.core.words import count, joined_names

#: Steps ``--step`` runs, in the order given, each on the last layer of the one before.
STEPS = ("clean", "maneuvers", "compress", "associate", "fuse")


def parse_size(text: str) -> tuple[int, int]:
    """``WxH`` in pixels (16..20000 each)."""
    parts = text.lower().replace("×", "x").split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"size must be WxH in pixels, e.g. 1200x800: {text!r}"
        ) from None
    if not (16 <= w <= 20000 and 16 <= h <= 20000):
        raise argparse.ArgumentTypeError(f"width and height must be 16..20000 pixels: {text!r}")
    return w, h


def parse_bounds(text: str) -> tuple[float, float, float, float]:
    """``W,S,E,N`` in degrees: west < east (east may pass 180), -90 <= south < north <= 90."""
    try:
        w, s, e, n = (float(p) for p in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"bounds must be W,S,E,N in degrees, e.g. 121.5,30,123,31: {text!r}"
        ) from None
    if not (w < e and s < n and -90 <= s and n <= 90 and -360 <= w and e <= 360):
        raise argparse.ArgumentTypeError(
            f"bounds need west < east, south < north, latitudes within ±90°: {text!r}"
        )
    return w, s, e, n


def run_steps(points, steps: list[str]) -> list[tuple[str, str, object]]:
    """Run ``steps`` from the step registry with default parameters: ``[(name, kind,
    points), …]`` of every new layer, each step on the primary layer of the one before (a
    step joining tracks on the tracks before any compress: ``StageChain``)."""
    from wakeline.core.pipeline import STEPS, StageChain

    out: dict[str, tuple[str, str, object]] = {}
    chain = StageChain(points)  # associate after compress reads the cleaned tracks
    for name in steps:
        step = STEPS[name]
        current = chain.input(name)
        result = step(current)
        for layer in result.layers:
            # A step that makes a layer an earlier one made (compress makes the maneuvers
            # again) replaces it: drawn twice, the copy took a colour and the input lost
            # its own (an operator's report: the input drawn brown beside the red line).
            out[layer.suffix] = (layer.suffix, layer.kind, layer.points)
        primary = [lay for lay in result.layers if lay.suffix == step.primary]
        chain.done(name, primary[0].points if primary else current)
    return list(out.values())


def input_name(paths: list[Path]) -> str:
    """The input's name in the legend: its file; up to three joined by " + ", more as the
    first two and how many more ("a.csv + b.csv and 9 more"), as the window names a fuse
    across layers (:func:`~wakeline.core.words.joined_names`; shown in the window's
    language by :func:`~wakeline.app.layer_names.shown_name`). Never a bare "input"; no
    "{ore_gbk,dma_semicolon_comma}.csv" (shortened in the legend to "{ore_gbk,d…mma}.csv",
    which named neither file: operator test 10)."""
    return joined_names([Path(p).name for p in paths])


def _read(paths: list[Path], **options):
    """One or several files as one table, as ``fuse`` and ``review`` read them (files that
    each hold one sensor of the same name get the differing part of their names);
    ``options``: read_points keywords (the reading flags)."""
    from wakeline.app.cli_review import read_inputs

    return read_inputs(paths, **options)


def is_maneuver_table(path: Path) -> bool:
    """``path`` is what ``wakeline maneuvers`` writes (its header is exactly
    ``sensor,batch,index,time,lon,lat,factor``): turning points, not tracks."""
    from wakeline.core.io import sniff
    from wakeline.core.maneuver import MANEUVER_COLUMNS

    try:
        return tuple(sniff(path).columns) == MANEUVER_COLUMNS
    except (InputError, OSError):
        return False  # read (and refused) with the tracks, with their message


def _cmd_render(args: argparse.Namespace) -> int:
    if args.output.suffix.lower() != ".png":
        raise InputError(f"{args.output}: the output must be a .png file")
    from wakeline.app.cli_steps import read_options

    # A maneuvers table beside its tracks (`render clean.csv man.csv`) was read as one
    # more sensor's tracks: its turning points joined by lines into tracks of their own.
    # It is drawn as the maneuver marks it is.
    marks = [p for p in args.input if is_maneuver_table(p)]
    tracks = [p for p in args.input if p not in marks]
    if not tracks and args.step:
        raise InputError(
            "--step needs a track file: the inputs are maneuver tables (drawn as marks)"
        )
    points = _read(tracks, **read_options(args)) if tracks else None
    derived = run_steps(points, args.step or []) if tracks else []
    if marks:
        import pandas as pd

        from wakeline.core.io import read_points

        table = pd.concat([read_points(p).points for p in marks], ignore_index=True)
        # named after its own file(s) when tracks are drawn too: "man.csv · maneuvers"
        named = f"{input_name(marks)} · maneuvers" if tracks else "maneuvers"
        derived.append((named, "maneuvers", table.assign(is_maneuver=True)))
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    try:
        from PySide6 import QtWidgets

        from wakeline.app.map_colors import PALETTE, batch_colors, layer_colors
        from wakeline.app.map_draw import LayerStyle, prepare_layer
        from wakeline.app.map_render import render_png
    except ImportError as exc:
        raise InputError(f"rendering needs the desktop libraries (Qt): {exc}") from None
    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["wakeline"])
    source_name = input_name(tracks or marks)
    # Every layer in a colour of its own: the steps' layers in their kinds' colours, the
    # input's sensors (or batches) in colours none of them has.
    taken: set[str] = set()
    kind_color = []
    for _suffix, kind, _pts in derived:
        kind_color.append(layer_colors(kind, 1, taken)[0])
        taken.add(kind_color[-1])
    by_batch = args.color_by == "batch"
    layers = []
    if points is not None:
        layers.append(
            prepare_layer(
                points,
                source_name,
                color_by=args.color_by,
                # Coloured by batch, the input is drawn over the steps' lines (under the
                # maneuver marks), or its colours would hide under them.
                style=LayerStyle(width=1.3, symbol_size=3, z=1.0 if by_batch else 0.0),
                build_index=False,
                colors=batch_colors(taken)
                if by_batch
                else layer_colors("source", len(PALETTE), taken),
            )
        )
    for (suffix, kind, pts), color in zip(derived, kind_color, strict=True):
        if kind == "maneuvers":
            pts = pts[pts["is_maneuver"].to_numpy(dtype=bool)] if "is_maneuver" in pts else pts
            style = LayerStyle(width=0, symbol_size=8, z=2.0)
        else:
            style = LayerStyle(
                width=2.5 if kind in ("compressed", "fused") else 1.3, gaps=kind != "compressed"
            )
        name = suffix if " · " in suffix else f"{source_name} · {suffix}"
        # kind: an associated layer is drawn one line per target (map_draw.drawn_lines)
        layers.append(prepare_layer(pts, name, color, style=style, build_index=False, kind=kind))
    info = render_png(layers, args.output, size=args.size, bounds=args.bounds, bare=args.bare)
    w, s, e, n = info["bounds"]
    print(
        f"rendered {count(info['layers'], 'layer')}, {count(info['points'], 'point')} as "
        f"{info['vertices']:,} drawn vertices, to {args.output} "
        f"({info['size'][0]}x{info['size'][1]} px, bounds {w:.5f},{s:.5f},{e:.5f},{n:.5f})"
    )
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``render`` subcommand to the ``wakeline`` parser."""
    p = sub.add_parser(
        "render",
        help="draw track files (and step results) on the map into a PNG",
        description="Draw track files with the application's map canvas, offscreen, into a "
        "PNG: every point of every track, the 1:50m coastline, a legend. Several inputs are "
        "drawn as one table (e.g. the AIS and radar files of one scene).",
        epilog=EPILOG,
    )
    # "--bounds -135,5,-134,6": a value starting with a minus and a digit is a value here,
    # not an option (argparse's own test only knows single numbers); --bounds=… works too.
    p._negative_number_matcher = re.compile(r"^-\d*\.?\d+([eE][-+]?\d+)?(,[-+\d.eE]+)*$")
    p.add_argument("input", nargs="+", type=Path, help="track files (any layout import reads)")
    p.add_argument("-o", "--output", type=Path, required=True, help="PNG to write")
    p.add_argument("--size", type=parse_size, metavar="WxH", help="image size in pixels")
    p.add_argument(
        "--bounds",
        type=parse_bounds,
        metavar="W,S,E,N",
        help="area to show in degrees (default: where the data are, with a 5%% margin; "
        "a few far-flung points may fall outside)",
    )
    p.add_argument(
        "--bare",
        action="store_true",
        help="the plot area alone, its edges exactly at the bounds (no axes, legend, margins)",
    )
    p.add_argument(
        "--step",
        nargs="+",
        action="extend",  # --step clean --step compress: both, in order (was the last)
        choices=STEPS,
        metavar="NAME",
        help=f"run steps with default parameters before drawing, in order ({', '.join(STEPS)})",
    )
    p.add_argument(
        "--color-by",
        choices=("sensor", "batch"),
        default="sensor",
        help="colour the input's tracks per sensor (default) or per batch",
    )
    from wakeline.app.cli_steps import add_read_flags

    add_read_flags(p)  # how the inputs are read: the same flags as the steps
    p.set_defaults(func=_cmd_render)

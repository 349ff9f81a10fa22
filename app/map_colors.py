"""The map's colours: one per layer or sensor, and distinct ones per selected batch.

Every layer shown gets a colour no other layer shows (:func:`layer_colors`): a step's
result takes its kind's colour (cleaned green, maneuvers purple, compressed red …) and a
source layer takes the source colours in turn, one per sensor. No source colour is a
kind's, so a radar file opened beside an AIS file is never drawn in the compressed
layer's red; a layer whose colour is already shown (a second cleaned layer) takes the
next free one.
"""

from collections.abc import Iterable
from functools import lru_cache

from wakeline.core.session import KIND_COLORS  # each kind of step result's colour: one table

#: Colours of source layers and their sensors, in turn: none is a kind's colour, none is
#: grey (the coastline), all readable on white.
SOURCE_COLORS = (
    "#1f77b4",
    "#8c564b",
    "#e377c2",
    "#bcbd22",
    "#000000",
    "#393b79",
    "#637939",
    "#7b4173",
)
#: Every layer colour, in the order a layer takes them when its own is shown already.
PALETTE = (*SOURCE_COLORS, *KIND_COLORS.values())
#: Distinct colours for batches of a selection (or a layer coloured by batch): tab10 and
#: darker companions, all readable on white. Ordered so that the first ones stay apart
#: for a deuteranope too (each the farthest, in CIELAB under a simulated deuteranopia as
#: well as in normal vision, from those before it — the idea of the Okabe–Ito order):
#: blue, orange, brown, pink, red … ; tab10's red and green, which a deuteranope cannot
#: tell apart, are far apart; the greys come last (the coastline and muted tracks are grey).
BATCH_PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#8c564b",
    "#e377c2",
    "#d62728",
    "#7b4173",
    "#393b79",
    "#31a354",
    "#e6550d",
    "#8c6d31",
    "#9467bd",
    "#17becf",
    "#2ca02c",
    "#bcbd22",
    "#637939",
    "#ad494a",
    "#3182bd",
    "#756bb1",
    "#7f7f7f",
    "#636363",
)


def layer_colors(
    kind: str,
    n: int = 1,
    taken: Iterable[str] = (),
    hidden: Iterable[str] = (),
    first: str | None = None,
) -> tuple[str, ...]:
    """``n`` colours for a layer of ``kind`` (``n``: one per sensor of a source layer).

    Its own colour first (``first``, else its kind's), then the source colours, then the
    other kinds' colours; a colour in ``taken`` (shown by another layer) is skipped, and
    one in ``hidden`` (a hidden layer's) is taken only when nothing else is free. Colours
    repeat only when every layer colour is shown already.
    """
    own = first or KIND_COLORS.get(kind)
    order = list(dict.fromkeys([*([own] if own else []), *SOURCE_COLORS, *KIND_COLORS.values()]))
    taken, hidden = set(taken), set(hidden)
    out: list[str] = []
    for allowed in (
        lambda c: c not in taken and c not in hidden,
        lambda c: c not in taken,
        lambda c: True,
    ):
        for c in order:
            if len(out) == n:
                return tuple(out)
            if c not in out and allowed(c):
                out.append(c)
    while len(out) < n:  # more sensors than layer colours: repeat them in turn
        out.append(order[len(out) % len(order)])
    return tuple(out)


def chosen_colors(colors: tuple[str, ...], color: str) -> tuple[str, ...]:
    """A layer's colours (one per sensor of a source layer) with ``color`` first, the
    operator's choice (Layers ▸ Colour…): the others kept, but the one that was
    ``color`` takes the old first colour (two sensors never share one)."""
    if not colors:
        return (color,)
    first = colors[0]
    rest = tuple(first if c == color else c for c in colors[1:])
    return (color, *rest)


#: Colours closer than this (CIE76 ΔE in CIELAB) are taken for one on the map.
NEAR_DELTA_E = 20.0


@lru_cache(maxsize=256)
def _lab(color: str) -> tuple[float, float, float]:
    """CIELAB (D65) of ``#rrggbb``."""
    rgb = [int(color[i : i + 2], 16) / 255.0 for i in (1, 3, 5)]
    r, g, b = (c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb)
    xyz = (
        (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047,
        0.2126 * r + 0.7152 * g + 0.0722 * b,
        (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883,
    )
    fx, fy, fz = (t ** (1 / 3) if t > 0.008856 else 7.787 * t + 16 / 116 for t in xyz)
    return 116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)


@lru_cache(maxsize=4096)
def delta_e(a: str, b: str) -> float:
    """How far apart two colours look (CIE76 ΔE: 2.3 is a just-noticeable difference)."""
    la, lb = _lab(a), _lab(b)
    return sum((x - y) ** 2 for x, y in zip(la, lb, strict=True)) ** 0.5


def apart_from(palette: Iterable[str], avoid: Iterable[str]) -> tuple[str, ...]:
    """The colours of ``palette`` that look different from every colour in ``avoid``
    (not only another hex code: tab20's darker green is the cleaned layer's green)."""
    avoid = set(avoid)
    return tuple(c for c in palette if all(delta_e(c, a) >= NEAR_DELTA_E for a in avoid))


def batch_colors(avoid: Iterable[str] = ()) -> tuple[str, ...]:
    """The batch palette without colours that look like those in ``avoid`` (the other
    layers'), or all of it when that would leave fewer than half."""
    free = apart_from(BATCH_PALETTE, avoid)
    return free if 2 * len(free) >= len(BATCH_PALETTE) else BATCH_PALETTE


#: Colours of a layer drawn one colour per track (View ▸ Colour by track): the batch
#: palette's colours, in its order, each at least this far (CIE76 ΔE) from those kept
#: before it; tab20c's lighter blue and purple and the second grey (ΔE 4.6 to 13 from a
#: colour before them) are left out: 17 colours.
TRACK_DELTA_E = 15.0


def well_separated(palette: Iterable[str], least: float = TRACK_DELTA_E) -> tuple[str, ...]:
    """The colours of ``palette``, in order, each at least ``least`` (ΔE) from every one
    kept before it."""
    kept: list[str] = []
    for c in palette:
        if all(delta_e(c, k) >= least for k in kept):
            kept.append(c)
    return tuple(kept)


TRACK_PALETTE = well_separated(BATCH_PALETTE)


def track_colors(avoid: Iterable[str] = ()) -> tuple[str, ...]:
    """:data:`TRACK_PALETTE` without colours that look like those in ``avoid`` (the
    other visible layers'), or all of it when that would leave fewer than half."""
    free = apart_from(TRACK_PALETTE, avoid)
    return free if 2 * len(free) >= len(TRACK_PALETTE) else TRACK_PALETTE

"""Lines of a layer made again for a few tracks: pure functions over arrays.

A layer drawn one line per ``(sensor, target)`` (an associated layer) holds its points
sorted by line key, then time; each line is one run of rows. A review decision moves a
few tracks from one target to another: only the lines of the targets it touches change.
These functions find those targets, and put the lines made again for them (in key
order) in place of the old ones, copying the untouched runs of rows as blocks — the
result the same as sorting all the points again, at the cost of the moved lines.
"""

import bisect
from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core.tracks import concat_ranges


def touched_targets(old, new) -> np.ndarray:
    """Per track (``old`` and ``new`` target per track: text arrays, numpy or pandas'
    Arrow text, compared without a Python string per track): whether its line is made
    again — its old or its new target is one a changed track left or joined. Whole
    targets are in or out (so a target's members are counted together)."""
    changed = np.asarray(old != new, dtype=bool)
    if not changed.any():
        return changed
    hit = set(old[changed].tolist()) | set(new[changed].tolist())
    if len(hit) > 16:  # many: one hash table
        return changed | pd.Series(old).isin(list(hit)).to_numpy(dtype=bool)
    out = changed.copy()  # a few (a decision's): compared one by one
    for name in hit:  # a track whose new target is hit and old is not has changed
        out |= np.asarray(old == name, dtype=bool)
    return out


@dataclass(frozen=True)
class Splice:
    """Where the lines of a new layout come from: ``pieces`` in output order, each
    ``(source, first, stop)`` — rows ``first:stop`` of the old arrays (source 0) or of
    the made-again lines (source 1); ``line_pieces`` the same in lines. ``sizes`` are
    the new layout's line sizes."""

    pieces: tuple[tuple[int, int, int], ...]
    line_pieces: tuple[tuple[int, int, int], ...]
    sizes: np.ndarray

    def take(self, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """Per-row arrays put together: untouched runs of ``old``, lines of ``new``."""
        parts = [(old, new)[s][a:b] for s, a, b in self.pieces]
        return np.concatenate(parts) if parts else old[:0]

    def take_lines(self, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """Per-line arrays put together the same way."""
        parts = [(old, new)[s][a:b] for s, a, b in self.line_pieces]
        return np.concatenate(parts) if parts else old[:0]

    def moved(self, old_rows: np.ndarray, new_rows: np.ndarray, n_old: int) -> np.ndarray:
        """Per row of the old layout, its row in the new one: the untouched runs shift
        as blocks; row ``old_rows[k]`` of a dropped line is row ``new_rows[k]`` now."""
        out = np.empty(n_old, dtype="int64")
        at = 0
        for s, a, b in self.pieces:
            if s == 0:
                out[a:b] = np.arange(at, at + b - a)
            at += b - a
        out[old_rows] = new_rows
        return out


def splice_lines(
    old_keys: tuple[np.ndarray, np.ndarray],
    old_sizes: np.ndarray,
    drop: np.ndarray,
    new_keys: tuple[np.ndarray, np.ndarray],
    new_sizes: np.ndarray,
) -> Splice | None:
    """The layout with the old lines ``drop`` (sorted line numbers) left out and the new
    lines (keys sorted, each ``(sensor, target)`` text) put in key order among the
    others. ``old_keys`` must be in key order (as a sort by line key leaves them); None
    when they are not where a search finds them (then sort all again)."""
    sensor, target = old_keys
    n_lines = len(old_sizes)

    def key(i: int) -> tuple[str, str]:
        return (str(sensor[i]), str(target[i]))

    old_starts = np.zeros(n_lines + 1, dtype="int64")
    np.cumsum(old_sizes, out=old_starts[1:])
    new_starts = np.zeros(len(new_sizes) + 1, dtype="int64")
    np.cumsum(new_sizes, out=new_starts[1:])
    # each new line's place: before the first old line of a key not below its own
    at = []
    for s, t in zip(new_keys[0], new_keys[1], strict=True):
        k = bisect.bisect_left(range(n_lines), (str(s), str(t)), key=key)
        if k > 0 and key(k - 1) >= (str(s), str(t)):
            return None  # the old keys are not in order
        at.append(k)
    if any(b < a for a, b in zip(at, at[1:], strict=False)):
        return None  # the new keys are not in order
    dropped = {int(d) for d in drop}
    line_pieces: list[tuple[int, int, int]] = []
    sizes: list[np.ndarray] = []
    j = 0  # next new line
    i = 0  # first old line not placed yet
    for cut in [*sorted(dropped | set(at)), n_lines]:
        if cut > i:  # old lines i … cut-1: none dropped, nothing put between them
            line_pieces.append((0, i, cut))
        while j < len(at) and at[j] == cut:
            line_pieces.append((1, j, j + 1))
            j += 1
        i = cut + 1 if cut in dropped else cut
    merged: list[tuple[int, int, int]] = []
    for piece in line_pieces:  # adjacent new lines as one piece
        if merged and merged[-1][0] == piece[0] == 1 and merged[-1][2] == piece[1]:
            merged[-1] = (1, merged[-1][1], piece[2])
        else:
            merged.append(piece)
    pieces = []
    for s, a, b in merged:
        starts = old_starts if s == 0 else new_starts
        pieces.append((s, int(starts[a]), int(starts[b])))
        sizes.append((old_sizes, new_sizes)[s][a:b])
    out_sizes = np.concatenate(sizes) if sizes else np.zeros(0, dtype="int64")
    return Splice(tuple(pieces), tuple(merged), out_sizes.astype("int64"))


def line_rows(starts: np.ndarray, ends: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """The rows of ``lines`` (line numbers, in order), concatenated."""
    lines = np.asarray(lines, dtype="int64")
    return concat_ranges(starts[lines], ends[lines] - starts[lines])

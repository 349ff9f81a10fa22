"""Joining tracks by hand where no proposal links them (operator test 5, D-review-7).

An analyst who sees one ship under two identities (an MMSI typed wrong from noon on,
kept apart by ``mmsi_apart``) selects the two tracks and joins them. The join is the
review's :func:`~wakeline.core.review.merge` (action ``merge``: a manual link, stored
in the decision log like every decision, replayed by ``wakeline review --decisions``,
undone by its inverse, cut again by :func:`~wakeline.core.review.split_target`), with
one check first (:func:`overlap_problem`):

Two tracks of **one sensor** whose times overlap are refused unless the caller allows
the overlap (the window asks). One sensor does not report one ship as two tracks at
once as a rule: overlapping tracks of one sensor are more often two ships, and joined
they would make a target with two positions at one time (the exported track zigzags
between them). The exceptions exist (a second transponder with a wrong MMSI, a radar's
duplicate track of one ship), hence an override rather than a ban. Tracks of two
sensors overlap by nature (the radar and the AIS of one ship: the fusion case) and are
joined without a question.

A layer whose step proposed nothing (``6 tracks -> 6 targets, 0 joins``) still has an
(empty) proposals table; :func:`empty_proposals` is that table for the command line
(``wakeline review`` without ``--proposals``).
"""

from collections.abc import Iterable

import numpy as np
import pandas as pd

from wakeline.core import review as R
from wakeline.core.errors import InputError


def empty_proposals() -> pd.DataFrame:
    """A proposals table with no rows (every column of :data:`R.PROPOSAL_COLUMNS`)."""
    return pd.DataFrame({c: pd.Series([], dtype=object) for c in R.PROPOSAL_COLUMNS})


def _clock(t: float) -> str:
    return pd.Timestamp(t, unit="s", tz="UTC").strftime("%Y-%m-%d %H:%M:%S")


def _span(seconds: float) -> str:
    s = int(round(seconds))
    h, rest = divmod(s, 3600)
    m, sec = divmod(rest, 60)
    if h:
        return f"{h} h {m:02d} min"
    if m:
        return f"{m} min {sec:02d} s"
    return f"{sec} s"


def overlaps(state: R.ReviewState, tracks: Iterable[str]) -> list[tuple[str, str, float, float]]:
    """Pairs of tracks of one sensor that a join of ``tracks`` would put into one target
    while their times overlap: ``(a, b, start, end)`` of the overlap (seconds since the
    epoch). Every member of the targets of ``tracks`` counts (a join joins targets);
    pairs already in one target are not reported (they are joined already)."""
    tracks = list(dict.fromkeys(tracks))
    rows = np.asarray([state._track(t) for t in tracks], dtype="int64")
    tg = state.target_of_track()
    members = np.flatnonzero(np.isin(tg, tg[rows]))
    tt = state.tracks
    sensor = tt["sensor"].astype(str).to_numpy()[members]
    t0 = tt["t0"].to_numpy(dtype="float64")[members]
    t1 = tt["t1"].to_numpy(dtype="float64")[members]
    target = tg[members]
    label = state._labels_arr[members]
    # A handful of tracks: every pair (the upper triangle) with numpy.
    i, j = np.triu_indices(len(members), k=1)
    lo = np.maximum(t0[i], t0[j])
    hi = np.minimum(t1[i], t1[j])
    hit = (sensor[i] == sensor[j]) & (target[i] != target[j]) & (hi > lo)
    return [
        (str(label[a]), str(label[b]), float(x), float(y))
        for a, b, x, y in zip(i[hit], j[hit], lo[hit], hi[hit], strict=True)
    ]


def overlap_problem(state: R.ReviewState, tracks: Iterable[str]) -> str:
    """Why a join of ``tracks`` needs the operator's word (:func:`overlaps`), or ``""``."""
    found = overlaps(state, tracks)
    if not found:
        return ""
    a, b, lo, hi = found[0]
    sensor = a.split(":", 1)[0]
    more = f" (and {len(found) - 1} more pair(s))" if len(found) > 1 else ""
    return (
        f"{a} and {b} are both tracks of sensor {sensor} from {_clock(lo)} to {_clock(hi)} "
        f"UTC ({_span(hi - lo)}){more}: one sensor rarely sees one ship as two tracks at "
        "once, so they may be two ships, and joined they would give one target two "
        "positions at one time"
    )


def join_tracks(state: R.ReviewState, tracks: Iterable[str], overlap_ok: bool = False) -> R.Change:
    """The change that joins ``tracks`` (two or more track labels) into one target by
    hand, whether or not a proposal links them: a :func:`~wakeline.core.review.merge`
    (its inverse undoes it; :func:`~wakeline.core.review.split_target` cuts it again).
    Tracks of one sensor overlapping in time raise :class:`InputError` saying so unless
    ``overlap_ok``; tracks already in one target give an empty change."""
    tracks = list(dict.fromkeys(tracks))
    if len(tracks) < 2:
        raise InputError("select two tracks (or more) to join")
    for t in tracks:
        state._track(t)
    if len(set(state.target_of_track()[[state._track(t) for t in tracks]].tolist())) == 1:
        return R.merge(state, tracks)  # empty: nothing to join
    if not overlap_ok:
        problem = overlap_problem(state, tracks)
        if problem:
            raise InputError(f"join refused: {problem}")
    return R.merge(state, tracks)

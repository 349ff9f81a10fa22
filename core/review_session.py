"""The review bound to a session layer (Qt-free): which points a layer's proposals were
made on, the :class:`~wakeline.core.review.ReviewState` of a layer with its stored
decisions replayed, the layer's points as the decisions make them, and the export.

One implementation for the window and ``wakeline review``: the decided points are
:meth:`ReviewState.label_points` of an associated layer (the CLI's CSV output) and
:func:`~wakeline.core.export_review.fused_tracks` of a fused layer (``--fused``); the
input of a layer fused from several layers is :func:`~wakeline.core.review.combine_sources`
of those layers named by their file stems, as the CLI names its input files.
"""

import copy
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import review as R
from wakeline.core.errors import InputError
from wakeline.core.pipeline import kept_out_phrases
from wakeline.core.review_store import (
    decision_row,
    earlier_entries,
    proposal_pairs,
    queue_outcome,
    replay_decisions,
)
from wakeline.core.session import Layer, Session
from wakeline.core.tracks import known_order, remember_order
from wakeline.core.words import Text, joined, phrase


def proposals_of(layer: Layer | None) -> pd.DataFrame | None:
    """The layer's proposals table when it has one with rows (associate / fuse results)."""
    if layer is None:
        return None
    props = layer.tables.get("proposals")
    return props if props is not None and len(props) else None


def reviewable(layer: Layer | None) -> bool:
    """Whether the layer has a review: proposals to decide (:func:`proposals_of`), or an
    associated or fused layer whose step proposed nothing (an empty proposals table)
    whose tracks may still be joined by hand (:mod:`wakeline.core.review_join`)."""
    if proposals_of(layer) is not None:
        return True
    return (
        layer is not None
        and layer.step in REVIEWED_STEPS
        and layer.role != "stitched"
        and layer.tables.get("proposals") is not None
    )


def review_bindable(session: Session, layer: Layer | None) -> bool:
    """Whether the window binds a review to the layer: it is :func:`reviewable`, and an
    empty queue (hand joins only) has the points it was made on (a layer whose input was
    removed before empty queues were reviewable kept none: it has no review, as before,
    rather than an error each time it is selected)."""
    if not reviewable(layer):
        return False
    if proposals_of(layer) is not None:
        return True
    ids = review_inputs(layer)
    return bool(ids) and all(KEPT_INPUT + i in layer.tables or i in session.layers for i in ids)


def queue_key(layer: Layer) -> str:
    """Names one run's queue: the layer id, the time its step made it and the run's own
    token, ``L3@2024-05-01T10:00:00Z#1f2e…`` (a re-run makes a new queue, even within
    the same second; decisions of the old one are not replayed on it). A layer of a
    project made before the token (h135) keeps its key ``L3@2024-05-01T10:00:00Z``, so
    its decisions still load."""
    key = f"{layer.id}@{layer.created}"
    return f"{key}#{layer.run}" if layer.run else key


#: The side table in which a reviewed layer keeps the points of an input layer removed
#: from the session (``input L1``): the points its proposals were made on stay in the
#: project with the layer, so its review binds in this window and after a reopen alike.
KEPT_INPUT = "input "
#: The ``meta`` key of a layer fused across layers that keeps the names its inputs were
#: combined under (:func:`fuse_names`), frozen when one of them or an ancestor (the
#: file a name may be told apart by) was removed.
KEPT_NAMES = "review_input_names"


def review_inputs(layer: Layer) -> list[str]:
    """The ids of the layers the layer's step ran on (every input of a fuse across
    layers, else the parent)."""
    return list(layer.inputs) or ([layer.parent] if layer.parent else [])


def input_points(session: Session, layer: Layer) -> pd.DataFrame:
    """The points the layer's step ran on: the parent layer, or the input layers of a
    fuse across layers combined as the command line combines its files. An input removed
    since is read from the copy the layer kept (:func:`keep_inputs`); one removed before
    Wakeline kept them raises :class:`InputError`."""
    ids = review_inputs(layer)
    frames, missing = [], []
    for i in ids:
        kept = layer.tables.get(KEPT_INPUT + i)
        if kept is not None:  # the input removed: never a later layer given its id
            frames.append(kept)
        elif i in session.layers:
            frames.append(session.layers[i].points)
        else:
            missing.append(i)
    if not ids or missing:
        raise InputError(
            f"layer {layer.name}: its input layer {', '.join(missing) or '?'} was removed; "
            "the review needs the points the proposals were made on"
        )
    if len(ids) == 1:
        return frames[0]
    names = layer.meta.get(KEPT_NAMES)
    if not (isinstance(names, list) and len(names) == len(ids)):
        names = fuse_names(session, ids)
    return R.combine_sources(list(zip(names, frames, strict=True)))


def reads_layer(session: Session, layer: Layer, layer_id: str) -> bool:
    """Whether the review of ``layer`` (one with proposals) reads layer ``layer_id``: its
    points (an input), or, fused across layers, the file its input's name is told apart
    by (an ancestor of an input)."""
    if not reviewable(layer) or layer.id == layer_id:  # an empty queue: its hand joins
        return False
    ids = review_inputs(layer)
    if layer_id in ids:
        return True
    return len(ids) > 1 and any(
        layer_id in session.ancestors(i) for i in ids if i in session.layers
    )


def review_dependents(session: Session, layer_id: str) -> list[Layer]:
    """The layers under review (with proposals) whose review reads layer ``layer_id``
    (:func:`reads_layer`): what removing it would have broken."""
    if layer_id not in session.layers:
        return []
    return [lay for lay in session.layers.values() if reads_layer(session, lay, layer_id)]


def keep_inputs(session: Session, layer_id: str) -> list[Layer]:
    """Before layer ``layer_id`` leaves the session: each layer whose review reads it
    keeps what the review needs — the input's points as its side table
    ``input <id>`` (:data:`KEPT_INPUT`; the same table, not a copy in memory) and, fused
    across layers, the names its inputs were combined under (:data:`KEPT_NAMES`).
    Returns the layers changed (the project writes their side tables again)."""
    changed = []
    for lay in review_dependents(session, layer_id):
        ids = review_inputs(lay)
        touched = False
        if len(ids) > 1 and not isinstance(lay.meta.get(KEPT_NAMES), list):
            # New dicts, not edits in place: the project writer may be reading the old
            # ones on its thread.
            try:
                lay.meta = {**lay.meta, KEPT_NAMES: fuse_names(session, ids)}
                touched = True
            except KeyError:  # another input removed before inputs were kept
                pass
        if layer_id in ids and KEPT_INPUT + layer_id not in lay.tables:
            lay.tables = {**lay.tables, KEPT_INPUT + layer_id: session.layers[layer_id].points}
            touched = True
        if touched:
            changed.append(lay)
    return changed


def fuse_names(session: Session, ids: list[str]) -> list[str]:
    """The names layers ``ids`` are fused under (their file stems; their files' differing
    folders where two stems are equal: :func:`~wakeline.core.review.source_names`)."""
    stems = [Path(session.layers[i].name).stem for i in ids]
    files = [session.root(i).meta.get("file") for i in ids]
    return R.source_names(stems, files)


def bind(session: Session, layer: Layer) -> tuple[R.ReviewState, pd.DataFrame]:
    """The review state of ``layer`` (stored decisions of its queue replayed) and the
    points its proposals were made on."""
    props = proposals_of(layer)
    if props is None and reviewable(layer):  # nothing proposed: joins by hand only
        from wakeline.core.review_join import empty_proposals

        props = empty_proposals()
    if props is None:
        raise InputError(f"layer {layer.name} has no proposals to review")
    points = input_points(session, layer)
    state = R.ReviewState(R.track_table(points), props)
    rows = list(session.decisions)  # a copy: the window may append while a worker reads
    state.history = earlier_entries(rows, queue_key(layer))
    replay_decisions(state, rows, queue_key(layer))
    return state, points


#: The steps whose layers carry proposals under review: a re-run of one carries the
#: review of the run it replaces over (:func:`carry_over`).
REVIEWED_STEPS = ("associate", "fuse")


@dataclass
class Carry:
    """What a re-run of a reviewed step carries over from the layer it replaces
    (:func:`carry_over`, in the worker): the decisions to store first in the new queue,
    and the counts its log line gives. The worker makes one for every run that replaces
    a layer (``reviewed`` False while that layer has no decision): it also records what
    the run read — the pairs kept out, the new queue's tracks — so that the carry is made
    again at the swap from the decisions present then (:meth:`refresh`)."""

    old: str  # the id of the layer the run replaces
    queue: str  # that layer's queue (:func:`queue_key`) when the step read it
    seen: int  # its decision rows the step read
    changes: list = field(default_factory=list)  # (Change, LogEntry), applied in order
    rejected: int = 0  # pairs rejected in an earlier review, kept out of the proposals
    split: int = 0  # pairs split in an earlier review, kept out the same way
    accepted: int = 0  # accepted pairs the run proposes again: accepted again
    linked: int = 0  # accepted pairs it no longer proposes and hand merges: operator links
    gone: int = 0  # accepts and links naming a track the run's input no longer holds
    late: int = 0  # decisions made on the old queue while the step ran (taken into account)
    #: whether the layer it replaces was reviewed (a decision row of any of its queues)
    reviewed: bool = True
    #: the pairs the run kept out, ``(rejected, split)`` as
    #: :meth:`~wakeline.core.session.Session.kept_out_below` gave them when it started
    kept: tuple = (frozenset(), frozenset())
    #: the run's parent and inputs (what :meth:`Session.kept_out_below` reads them under)
    parent: str = ""
    inputs: list = field(default_factory=list)
    step: str = ""
    #: :func:`~wakeline.core.review.track_table` of the run's input (made in the worker,
    #: so a carry made again at the swap reads no points)
    tracks: pd.DataFrame | None = None

    def text(self) -> Text:
        """The log's words: what was kept out, carried and dropped (phrases the window
        translates, :mod:`wakeline.core.words`)."""
        parts = kept_out_phrases(self.rejected, self.split)
        if self.accepted:
            parts.append(phrase("{n:#accepted pair} proposed again, accepted", n=self.accepted))
        if self.linked == 1:
            parts.append(phrase("1 accepted pair or hand merge kept as an operator link"))
        elif self.linked:
            parts.append(
                phrase("{n:,} accepted pairs or hand merges kept as operator links", n=self.linked)
            )
        if self.gone == 1:
            parts.append(phrase("1 decision no longer applies (a track is gone)"))
        elif self.gone:
            parts.append(phrase("{n:,} decisions no longer apply (a track is gone)", n=self.gone))
        if self.late:
            parts.append(
                phrase(
                    "{n:#decision} made while the step ran taken into account",
                    n=self.late,
                )
            )
        return Text(joined(parts) or [phrase("no decision to carry over")])

    def refresh(self, old: Layer, rows: list[dict], proposals: pd.DataFrame | None) -> None:
        """Make the carry again from the decision rows ``rows`` present now (at the swap:
        decisions made on ``old``'s queue while the step ran are carried as those made
        before it). The pairs kept out must not have changed meanwhile
        (:meth:`Session.stale <wakeline.core.session.Session.stale>`; the caller
        checks). Safe in a worker (it reads ``rows``, a copy, and ``old``'s proposals):
        with many carried decisions it takes a while (one accept after the other, about
        1 ms each at 600 tracks), so the window makes it there
        (:meth:`Session.reconcile <wakeline.core.session.Session.reconcile>`)."""
        key = queue_key(old)
        now = sum(1 for r in rows if isinstance(r, dict) and r.get("queue") == key)
        late = max(0, now - self.seen) if key == self.queue else now
        if not late:
            return
        rejected, split = self.kept
        split = set(split) - set(rejected)
        again = carry_over(
            old, rows, None, proposals, len(rejected), len(split), tracks=self.tracks
        )
        for f in ("queue", "seen", "changes", "accepted", "linked", "gone"):
            setattr(self, f, getattr(again, f))
        self.reviewed = True
        self.late += late  # made again after more decisions: all of them count


def carry_over(
    old: Layer,
    rows: list[dict],
    points: pd.DataFrame,
    proposals: pd.DataFrame | None,
    rejected: int = 0,
    split: int = 0,
    tracks: pd.DataFrame | None = None,
) -> Carry:
    """What a re-run carries over from the review of ``old`` (the layer it replaces) to
    its new ``proposals`` made on ``points``: each pair ``old``'s queue left accepted is
    accepted again when the run proposes it, else kept as an operator link (a manual
    link, as a hand merge makes), and each manual link is kept; a pair naming a track the
    input no longer holds counts as gone. Rejected and split pairs are kept out of the
    run itself (``rejected``, ``split``: their counts). The changes are made on the new
    queue's state here (the caller stores them under the new queue's key). ``tracks``:
    :func:`~wakeline.core.review.track_table` of ``points``, when made already (then
    ``points`` is not read)."""
    key = queue_key(old)
    mine = [r for r in rows if isinstance(r, dict) and r.get("queue") == key]
    carry = Carry(old.id, key, len(mine), rejected=rejected, split=split)
    status, links = queue_outcome(mine, key)
    props = proposals_of(old)
    pairs = proposal_pairs(props)
    keep = {R.pair_key(*pairs[p]) for p, st in status.items() if st == "accepted" and p in pairs}
    if proposals is None or (not len(proposals) and (points is None and tracks is None)):
        carry.gone = len(keep | links)  # nothing to review: none applies
        return carry
    if not (keep or links):
        return carry
    if not len(proposals):  # a run that proposes nothing: its hand joins still apply
        from wakeline.core.review_join import empty_proposals

        proposals = empty_proposals()
    state = R.ReviewState(R.track_table(points) if tracks is None else tracks, proposals)
    proposed = {
        R.pair_key(x, y): pid
        for pid, x, y in zip(state.proposals["proposal"], state.track_a, state.track_b, strict=True)
    }
    link = set(links)
    for pair in sorted(keep):
        pid = proposed.get(pair)
        if pid is None:
            link.add(pair)
            continue
        change = R.accept(state, pid)
        if not change.empty:
            state.apply(change)
            carry.changes.append((change, state.log[-1]))
        carry.accepted += 1
    for x, y in sorted(link):
        if x not in state._track_no or y not in state._track_no:
            carry.gone += 1
            continue
        pair = R.pair_key(x, y)
        if pair not in state.links:
            change = R.Change("merge", "", (x, y), links_added=frozenset({pair}))
            state.apply(change)
            carry.changes.append((change, state.log[-1]))
        carry.linked += 1
    return carry


def carried_rows(carry: Carry, queue: str, when: str | None = None) -> list[dict]:
    """The decision rows that open the new queue ``queue`` of a re-run: its marker
    (:data:`~wakeline.core.review.RERUN`: the queue it follows and what was carried),
    then the carried decisions."""
    import datetime as dt

    when = when or dt.datetime.now(dt.UTC).isoformat(timespec="seconds")
    mark = R.LogEntry(when, R.RERUN, "", "", carry.queue, carry.text())
    rows = [decision_row(queue, R.Change(R.RERUN), mark)]
    return rows + [decision_row(queue, c, e, stack="carried") for c, e in carry.changes]


def decision_counts(layers: list[Layer], decisions: list[dict]) -> tuple[int, int]:
    """The decision rows replayed on the layers' current queues (the review decisions a
    reopen restores), and the others kept in the log (earlier runs' decisions, those of
    removed layers); re-run markers are no decisions."""
    current = {queue_key(lay) for lay in layers if reviewable(lay)}
    now = other = 0
    for row in decisions:
        if not isinstance(row, dict) or not isinstance(row.get("change"), dict):
            continue
        if row.get("action") == R.RERUN or row["change"].get("action") == R.RERUN:
            continue
        if row.get("queue") in current:
            now += 1
        else:
            other += 1
    return now, other


def decisions_in_effect(layers: list[Layer], decisions: list[dict]) -> int:
    """The review decisions in effect on the layers' current queues once the stored rows
    are replayed: proposals left accepted, rejected or split, and manual links left —
    not the rows (50 decisions, 30 undos and 20 redos leave 40 in effect, not 100)."""
    n = 0
    for lay in layers:
        if proposals_of(lay) is None:
            continue
        status, links = queue_outcome(decisions, queue_key(lay))
        n += sum(1 for v in status.values() if v != "pending") + len(links)
    return n


def snapshot(state: R.ReviewState) -> R.ReviewState:
    """A copy of the decisions as they are now, for a worker to read while the operator
    goes on deciding (proposals and tracks are shared, never mutated)."""
    snap = copy.copy(state)
    snap.status = state.status.copy()
    snap.links = set(state.links)
    snap.log = list(state.log)
    snap._targets = state.target_of_track().copy()
    return snap


def fuse_association(layer: Layer, points: pd.DataFrame):
    """The cross-sensor association the fused layer's step made (same parameters)."""
    from wakeline.core.fuse import associate_sensors
    from wakeline.core.pipeline import params_from_json

    params = params_from_json("fuse", layer.params)
    fp, opts = params["fuse"], params["fuse_options"]
    sassoc = associate_sensors(points, fp, distance=opts.distance, method=opts.method)
    return sassoc, fp


def decided_points(
    layer: Layer, state: R.ReviewState, points: pd.DataFrame, cache: dict | None = None
) -> pd.DataFrame | None:
    """The layer's points as the decisions make them: an associated layer relabelled
    (``target``), a fused layer fused again on the decided targets; ``None`` for a
    stitched layer (one batch per engine target: the decisions show in the export).
    ``cache`` keeps the cross-sensor association between calls."""
    if layer.step == "fuse":
        cache = {} if cache is None else cache
        if "sassoc" not in cache:
            cache["sassoc"], cache["fp"] = fuse_association(layer, points)
        from wakeline.core.export_review import fused_tracks

        return fused_tracks(state, cache["sassoc"], cache["fp"])
    if layer.role == "stitched":
        return None
    own = layer.points.drop(columns=["target"], errors="ignore")
    out = state.label_points(own)
    known = known_order(layer.points)  # the same rows in the same order: no sort again
    fresh = isinstance(out.index, pd.RangeIndex) and out.index.start == 0 and out.index.step == 1
    if known is not None and fresh:
        remember_order(out, *known)
    return out


def relabeled(
    layer_points: pd.DataFrame, state: R.ReviewState, cache: dict | None = None
) -> tuple[pd.DataFrame, np.ndarray] | None:
    """What :func:`decided_points` makes of an associated layer's points already in track
    order (``layer_points``: the layer's, as :func:`~wakeline.core.tracks.known_order`
    knows them), and each track's target (per track of that order, text) — the decided
    targets taken per track, not per point (no labels of a million points made again);
    None when the order is not known or a track is not in the state's table (then
    :func:`decided_points`). The targets per track: pandas' text array. ``cache`` keeps each track's row of the state's table."""
    known = known_order(layer_points)
    if known is None:
        return None
    index = known[0]
    cache = {} if cache is None else cache
    kept = cache.get("track_rows")
    if kept is not None and kept[0] is index.keys and kept[1] is state.tracks:
        rows = kept[2]
    else:
        keys = index.keys
        labels = (keys["sensor"].astype(str) + ":" + keys["batch"].astype(str)).tolist()
        no = state._track_no
        if any(lab not in no for lab in labels):
            return None
        rows = np.fromiter((no[lab] for lab in labels), dtype="int64", count=len(labels))
        cache["track_rows"] = (index.keys, state.tracks, rows)
    per_track = pd.Series(state.target_of_track()[rows])  # the type label_points gives
    if per_track.isna().any():
        return None
    out = layer_points.drop(columns=["target"], errors="ignore")
    column = None
    if "target" in layer_points.columns and layer_points["target"].dtype == per_track.dtype:
        column = _spliced_targets(layer_points["target"].array, per_track.array, index)
    out["target"] = per_track.array.take(index.track_of_row) if column is None else column
    fresh = isinstance(out.index, pd.RangeIndex) and out.index.start == 0 and out.index.step == 1
    if not fresh:
        return None
    remember_order(out, *known)
    return out, per_track.array


def _spliced_targets(old, per_track, index) -> object | None:
    """The target column ``per_track.take(index.track_of_row)`` made from the ``old``
    column (Arrow text, the same type) by copying the runs of rows whose track keeps its
    target and writing the others (a decision moves a few tracks: a take of a million
    strings was ~30 ms of its worker); None when the arrays are not Arrow text or more
    than a quarter of the tracks change."""
    import pyarrow as pa

    arr, new = getattr(old, "_pa_array", None), getattr(per_track, "_pa_array", None)
    if arr is None or new is None or arr.type != new.type or len(arr) != len(index.track_of_row):
        return None
    import pyarrow.compute as pc

    starts, ends = index.starts, index.ends
    was = arr.take(pa.array(starts))
    changed = np.asarray(pc.fill_null(pc.not_equal(was, new), True), dtype=bool)
    if changed.sum() * 4 > len(changed):
        return None
    pieces, at = [], 0
    for k in np.flatnonzero(changed).tolist():
        a, b = int(starts[k]), int(ends[k])
        if a > at:
            pieces.append(arr.slice(at, a - at))
        pieces.append(new.take(pa.array(np.full(b - a, k, dtype="int64"))))
        at = b
    if at < len(arr):
        pieces.append(arr.slice(at, len(arr) - at))
    chunks = [c for p in pieces for c in p.chunks if len(c)]
    joined = pa.concat_arrays(chunks) if chunks else pa.array([], type=arr.type)
    return type(per_track)(pa.chunked_array([joined]), dtype=per_track.dtype)


def export_reviewed(
    layer: Layer,
    state: R.ReviewState,
    points: pd.DataFrame,
    path: str | Path,
    bom: bool = False,
    cache: dict | None = None,
) -> str:
    """Write the decided tracks as ``wakeline review`` does (by suffix: .csv, .geojson,
    .gpx; fused tracks for a fused layer, merged tracks otherwise); returns the format."""
    from wakeline.core.export_review import export_tracks

    return export_tracks(reviewed_points(layer, state, points, path, cache), path, bom=bom)


def reviewed_points(
    layer: Layer,
    state: R.ReviewState,
    points: pd.DataFrame,
    path: str | Path,
    cache: dict | None = None,
) -> pd.DataFrame:
    """The points :func:`export_reviewed` writes to ``path`` (its suffix chooses)."""
    from wakeline.core.export_review import merged_tracks

    if layer.step == "fuse":
        return decided_points(layer, state, points, cache)
    if Path(path).suffix.lower() in (".gpx", ".geojson", ".json"):
        return merged_tracks(state, points)
    return state.label_points(points)


def sorted_by_track(points: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, tuple[int, int]]]:
    """Points sorted by track label (stable: the order within a track is kept) and each
    label's rows."""
    lab = R.point_labels(points)
    order = np.argsort(lab, kind="stable")
    lab = lab[order]
    pts = points.iloc[order].reset_index(drop=True)
    if not len(lab):
        return pts, {}
    starts = np.flatnonzero(np.r_[True, lab[1:] != lab[:-1]])
    ends = np.r_[starts[1:], len(lab)]
    return pts, {str(lab[s]): (int(s), int(e)) for s, e in zip(starts, ends, strict=True)}


def repair_decisions(
    layers: list[Layer], decisions: list[dict], when: str | None = None
) -> list[dict]:
    """Migration on open: the decision rows (:func:`decision_row`) that repair the review
    queues of ``layers`` whose stored ``decisions`` leave a proposal rejected or split
    beside a target holding both its tracks — what a join made before joins accepted
    such rows (a project saved by an older Wakeline: a split, then a merge of the two
    tracks by hand, left the row ``split``). One :func:`~wakeline.core.review.repair`
    per such row (:func:`~wakeline.core.review.replay_repaired`), to append to the
    decisions (the caller stores them); none when every queue is consistent, so a
    repaired project reopens without new rows.

    Only what a join left behind is repaired: a row rejected or split while its tracks
    stayed in one target (other links hold them together) is the operator's decision
    and is kept. A queue none of whose decisions rejects or splits a row is not replayed
    (:func:`~wakeline.core.review.cuts_anything`). A queue that cannot be bound (its
    input layer removed) or replayed is left to the review, which reports it. The
    project file remembers that its decisions were checked
    (:meth:`~wakeline.core.project.ProjectStore.mark_decisions_checked`), so this runs
    once per project, not on every open."""
    session = Session()
    session.layers = {lay.id: lay for lay in layers}
    out: list[dict] = []
    for lay in layers:
        props = proposals_of(lay)
        if props is None:
            continue
        key = queue_key(lay)
        rows = [r for r in decisions if isinstance(r, dict) and r.get("queue") == key]
        rows = [r for r in rows if isinstance(r.get("change"), dict)]
        if not rows:
            continue
        try:
            changes = [R.Change.from_dict(r["change"]) for r in rows]
            if not R.cuts_anything(changes):
                continue
            state = R.ReviewState(R.track_table(input_points(session, lay)), props)
            times = [r.get("time") for r in rows]
            repairs = R.replay_repaired(state, zip(changes, times, strict=True), when)
        except (InputError, KeyError, TypeError, ValueError):
            continue
        entries = state.log[len(state.log) - len(repairs) :]
        out += [decision_row(key, c, e) for c, e in zip(repairs, entries, strict=True)]
    return out

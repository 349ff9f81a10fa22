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
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import review as R
from wakeline.core.errors import InputError
from wakeline.core.review_store import decision_row, replay_decisions
from wakeline.core.session import Layer, Session


def proposals_of(layer: Layer | None) -> pd.DataFrame | None:
    """The layer's proposals table when it has one with rows (associate / fuse results)."""
    if layer is None:
        return None
    props = layer.tables.get("proposals")
    return props if props is not None and len(props) else None


def queue_key(layer: Layer) -> str:
    """Names one run's queue: the layer id and the time its step made it (a re-run makes
    a new queue; decisions of the old one are not replayed on it)."""
    return f"{layer.id}@{layer.created}"


def input_points(session: Session, layer: Layer) -> pd.DataFrame:
    """The points the layer's step ran on: the parent layer, or the input layers of a
    fuse across layers combined as the command line combines its files."""
    ids = layer.inputs or ([layer.parent] if layer.parent else [])
    missing = [i for i in ids if i not in session.layers]
    if not ids or missing:
        raise InputError(
            f"layer {layer.name}: its input layer {', '.join(missing) or '?'} was removed; "
            "the review needs the points the proposals were made on"
        )
    if len(ids) == 1:
        return session.layers[ids[0]].points
    names = fuse_names(session, ids)
    return R.combine_sources(
        [(name, session.layers[i].points) for name, i in zip(names, ids, strict=True)]
    )


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
    if props is None:
        raise InputError(f"layer {layer.name} has no proposals to review")
    points = input_points(session, layer)
    state = R.ReviewState(R.track_table(points), props)
    replay_decisions(state, session.decisions, queue_key(layer))
    return state, points


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
    return state.label_points(own)


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
    from wakeline.core.export_review import export_tracks, merged_tracks

    if layer.step == "fuse":
        out = decided_points(layer, state, points, cache)
    elif Path(path).suffix.lower() in (".gpx", ".geojson", ".json"):
        out = merged_tracks(state, points)
    else:
        out = state.label_points(points)
    return export_tracks(out, path, bom=bom)


def sorted_by_track(points: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, tuple[int, int]]]:
    """Points sorted by track label (stable: the order within a track is kept) and each
    label's rows."""
    lab = R._labels(points[["sensor", "batch"]].astype(str))
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

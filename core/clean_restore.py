"""Restoring points a clean step removed, as a command with an inverse (SPEC §2: "so the
operator can see it on the map and restore it"). Qt-free: the window wraps a
:class:`Restore` in a ``QUndoCommand`` (:mod:`wakeline.app.restore_points`); the command
line's ``clean --restore`` / ``--restore-rule`` use :func:`chosen_ids` and
:func:`~wakeline.core.clean.restore` directly.

A cleaned layer keeps its reject trail as ``tables["rejected"]`` (original rows with
``wl_id``, ``rule``, ``action``, ``params``). :func:`restore_change` makes the command
for some of those ids; :func:`apply` puts it into the session: the layer's points (the
rows back, a changed row's original values again), its rejected table (their rows out),
its counts (``meta["rejected"]``, ``meta["clean_counts"]``) and its lineage
(:attr:`~wakeline.core.session.Layer.restored`, the ids put back, in effect now), then a
``changed`` event (the project writes the layer at once). The inverse takes them out
again, each row back where it was in the rejected table. A command holds only the rows
it moved, not copies of the layer.
"""

import dataclasses
from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core.clean import ID, restore
from wakeline.core.errors import InputError
from wakeline.core.tracks import sorted_with_index

#: The table of a cleaned layer that holds what clean removed or changed.
REJECTED = "rejected"


@dataclass(frozen=True, eq=False)
class Restore:
    """Put the rejected points ``ids`` of layer ``layer`` back (``undo``: take them out
    again). ``run``: the making of the layer it applies to (a re-run of Clean makes
    the command stale). ``back``: the rejected table's rows of those ids (its index:
    their positions there); ``before``: the layer's rows of those ids before (the points
    a rule changed: their changed values)."""

    layer: str
    run: str
    ids: tuple[int, ...]
    back: pd.DataFrame
    before: pd.DataFrame
    undo: bool = False

    def inverse(self) -> "Restore":
        return dataclasses.replace(self, undo=not self.undo)

    @property
    def rules(self) -> dict[str, int]:
        """Points per rule that removed or changed them (a point two rules touched counts
        under the first)."""
        first = self.back.drop_duplicates(ID, keep="first")
        return {str(k): int(v) for k, v in first["rule"].value_counts(sort=False).items()}

    def __len__(self) -> int:
        return len(self.ids)


def rejected_of(layer) -> pd.DataFrame | None:
    """The rejected table of a cleaned layer (None: the layer has none)."""
    table = layer.tables.get(REJECTED) if layer is not None else None
    if table is None or ID not in table.columns or ID not in layer.points.columns:
        return None
    return table


def restorable(rejected: pd.DataFrame) -> np.ndarray:
    """Per row of ``rejected``: can its point come back one by one (not a point a
    transforming step — bspline, resample, smooth — replaced)."""
    if "action" not in rejected.columns:
        return np.ones(len(rejected), dtype=bool)
    return (rejected["action"].astype(str) != "replaced").to_numpy().copy()


def chosen_ids(
    rejected: pd.DataFrame,
    *,
    rules: list[str] | tuple[str, ...] | None = None,
    track: tuple[str, str] | None = None,
    tracks=None,
    box: tuple[float, float, float, float] | None = None,
    ids=None,
) -> np.ndarray:
    """The ``wl_id`` of the restorable rejected rows that match every condition given:
    removed or changed by one of ``rules``; of ``track`` (sensor, batch as text); of one of
    ``tracks`` (such pairs: the selected tracks, one pass over the table); inside
    ``box`` (west, south, east, north, degrees; east < west crosses 180°; east - west
    of 360 or more: every longitude); among
    ``ids``. Sorted, each once. Raises :class:`InputError` for a rule no row names."""
    keep = restorable(rejected)
    if rules:
        names = rejected["rule"].astype(str)
        unknown = sorted(set(rules) - set(names.unique()))
        if unknown:
            have = ", ".join(sorted(names.unique())) or "none"
            raise InputError(
                f"no point was removed or changed by {', '.join(unknown)} (rules in the "
                f"rejected table: {have})"
            )
        keep &= names.isin(list(rules)).to_numpy()
    if track is not None:
        keep &= (rejected["sensor"].astype(str) == str(track[0])).to_numpy()
        keep &= (rejected["batch"].astype(str) == str(track[1])).to_numpy()
    if tracks is not None:
        pairs = pd.MultiIndex.from_arrays(
            [rejected["sensor"].astype(str), rejected["batch"].astype(str)]
        )
        keep &= pairs.isin([(str(s), str(b)) for s, b in tracks])
    if box is not None:
        west, south, east, north = map(float, box)
        lon = pd.to_numeric(rejected["lon"], errors="coerce").to_numpy(dtype="float64")
        lat = pd.to_numeric(rejected["lat"], errors="coerce").to_numpy(dtype="float64")
        inside = (lat >= south) & (lat <= north)
        if east - west < 360.0:  # else every longitude (a view zoomed out past the world)
            lon = (lon - west) % 360.0  # degrees east of the box's west edge
            inside &= lon <= (east - west) % 360.0
        keep &= inside
    if ids is not None:
        keep &= rejected[ID].isin(np.asarray(list(ids), dtype="int64")).to_numpy()
    return np.unique(rejected[ID].to_numpy()[keep].astype("int64"))


def restore_change(layer, ids) -> Restore:
    """The command putting ``ids`` (``wl_id`` of rows of ``layer``'s rejected table)
    back into ``layer``. Raises :class:`InputError` when the layer has no rejected table,
    an id is not in it, or its point was replaced by a transforming step."""
    rejected = rejected_of(layer)
    if rejected is None:
        raise InputError("the layer has no points removed by cleaning to restore")
    ids = np.unique(np.asarray(list(ids), dtype="int64"))
    if len(ids) == 0:
        raise InputError("no removed point chosen to restore")
    unknown = np.setdiff1d(ids, rejected[ID].to_numpy())
    if len(unknown):
        raise InputError(f"not in the rejected table: {ID} {', '.join(map(str, unknown[:10]))}")
    rows = rejected[ID].isin(ids).to_numpy()
    if not restorable(rejected)[rows].all():
        raise InputError(
            "points replaced by a transforming step (bspline, resample, smooth) come back by "
            "cleaning again without that step, not one by one"
        )
    back = rejected[rows].copy()
    back.index = np.flatnonzero(rows)  # their positions in the rejected table
    points = layer.points
    before = points[points[ID].isin(ids).to_numpy()].copy()
    return Restore(layer.id, layer.run, tuple(int(i) for i in ids), back, before)


def restored_tables(
    points: pd.DataFrame, rejected: pd.DataFrame, change: Restore
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``(points, rejected)`` after ``change`` (pure: the inputs are not modified)."""
    if not change.undo:
        return restore(points, rejected, change.ids)
    ids = np.asarray(change.ids, dtype="int64")
    keep = points[~points[ID].isin(ids).to_numpy()]
    before = change.before[keep.columns.intersection(change.before.columns)]
    merged = pd.concat([keep, before], ignore_index=True) if len(before) else keep
    merged, _ = sorted_with_index(merged.reset_index(drop=True))
    # each rejected row back at its position
    n = len(rejected) + len(change.back)
    at = np.zeros(n, dtype=bool)
    at[change.back.index.to_numpy()] = True
    both = pd.concat([rejected, change.back], ignore_index=True)
    order = np.empty(n, dtype="int64")
    order[~at] = np.arange(len(rejected))
    order[at] = len(rejected) + np.arange(len(change.back))
    return merged, both.iloc[order].reset_index(drop=True)


def moved_counts(back: pd.DataFrame) -> dict[tuple[str, str], int]:
    """Points per (action, rule) among rejected rows ``back`` (each point once per pair):
    what a rule's counts lose when they are put back."""
    first = back.drop_duplicates([ID, "action", "rule"])
    sizes = first.groupby(["action", "rule"], sort=False).size()
    return {(str(action), str(rule)): int(n) for (action, rule), n in sizes.items()}


def _counts(counts: dict, back: pd.DataFrame, sign: int) -> dict:
    """``meta["clean_counts"]`` (per action, per rule) with ``back``'s rows taken out
    (``sign`` -1) or put in again (+1); actions and rules without points left out."""
    out = {action: dict(per) for action, per in (counts or {}).items()}
    if {"action", "rule"} <= set(back.columns):
        for (action, rule), n in moved_counts(back).items():
            per = out.setdefault(action, {})
            per[rule] = per.get(rule, 0) + sign * n
    return {
        a: {r: n for r, n in per.items() if n > 0} for a, per in out.items() if any(per.values())
    }


def restored_counts(meta: dict, n_rejected: int, back: pd.DataFrame, sign: int) -> dict:
    """A cleaned layer's ``meta`` with its counts after ``back``'s rejected rows were
    taken out (``sign`` -1) or put in again (+1); ``n_rejected``: the rows left."""
    meta = dict(meta)
    if "rejected" in meta:
        meta["rejected"] = int(n_rejected)
    if "clean_counts" in meta:
        meta["clean_counts"] = _counts(meta["clean_counts"], back, sign)
    return meta


def check(session, change: Restore):
    """The layer ``change`` applies to, and its rejected table. Raises
    :class:`InputError` when the layer is gone or was made again since (Clean run
    again: the command is stale)."""
    layer = session.get(change.layer)
    if layer is None:
        raise InputError("the cleaned layer was removed; nothing restored")
    if layer.run != change.run:
        raise InputError("the layer was cleaned again since; nothing restored")
    rejected = rejected_of(layer)
    if rejected is None:
        raise InputError("the layer has no points removed by cleaning to restore")
    return layer, rejected


def put(session, change: Restore, points: pd.DataFrame, rejected: pd.DataFrame) -> None:
    """Give ``change``'s layer the tables :func:`restored_tables` made for it (the window
    makes them in its worker): rejected table, counts, lineage, then its points with a
    ``changed`` event (the map draws it, the project writes it)."""
    layer, _ = check(session, change)
    layer.tables = {**layer.tables, REJECTED: rejected}
    layer.meta = restored_counts(layer.meta, len(rejected), change.back, 1 if change.undo else -1)
    done = set(layer.restored)
    done = done - set(change.ids) if change.undo else done | set(change.ids)
    layer.restored = sorted(done)
    session.replace_points(layer.id, points)  # the "changed" event: drawn and saved


def apply(session, change: Restore) -> None:
    """Apply ``change`` to its layer in ``session`` (:func:`restored_tables`, then
    :func:`put`). Raises :class:`InputError` as :func:`check`."""
    layer, rejected = check(session, change)
    put(session, change, *restored_tables(layer.points, rejected, change))

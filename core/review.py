"""Review of the engine's joins (SPEC §7, seed 003 §5.3): proposals with their evidence,
decisions as pure commands with an inverse, and the targets that follow from them.

A *proposal* is one join the engine chose: two tracks (``sensor:batch`` labels), the
method, the cost and its parts, and the runner-up — the best competing candidate of
either track (``runner_up``, ``runner_up_cost``) — and the margin: the cheaper of the
runner-up and "leave both unmatched" (the gate's price) minus the cost; a small margin
is an uncertain join, to be reviewed first.

Costs are in the method's own units: single-sensor association (``kind`` ``associate``)
uses the scaled combined distance (1 = one tolerance on every term), cross-sensor
association (``fuse``) the track distance in metres. ``margin_rel`` = margin / gate puts
both on one scale for a mixed queue.

The decisions live in a :class:`ReviewState`: a status per proposal (pending, accepted,
rejected, split) and the manual links. Every decision is a :class:`Change` computed from
the state by :func:`accept`, :func:`reject`, :func:`merge`, :func:`split_track` or
:func:`split_target`; a change carries the before and after values of what it touches,
so :meth:`Change.inverse` undoes it exactly. Targets are the connected components of the
tracks linked by proposals that are pending or accepted, plus the manual links; a target
is named after the ``sensor:batch`` of its earliest track, so names are unique across
sensors and do not change when an unrelated decision is made.
"""

import dataclasses
import datetime as _dt
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import PurePath
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.schema import time_seconds

if TYPE_CHECKING:  # the engine's modules load only when proposals are made
    from wakeline.core import associate as _assoc

STATUSES = ("pending", "accepted", "rejected", "split")
#: The prefix of a redo's action in the decision log (``redo accept``): the decision
#: made again by Redo, not a new one (:meth:`ReviewState.apply`, :func:`replay_log`).
REDO = "redo "

#: The action of the marker a re-run of a reviewed step puts first in its new queue: an
#: empty change (nothing moves); its log line names the run it replaces (``before``) and
#: says what was carried over (``after``). Decisions above it in a log belong to the
#: earlier run (:func:`replay_log` starts after the last one).
RERUN = "re-run"
ACTIVE = ("pending", "accepted")  # statuses whose link counts in the targets
PROPOSAL_COLUMNS = (
    "proposal",
    "kind",
    "sensor_a",
    "batch_a",
    "sensor_b",
    "batch_b",
    "method",
    "cost",
    "gap_s",
    "distance_m",
    "miss_m",
    "dcourse_deg",
    "dspeed_kn",
    "spread",
    "end_accel_ms2",
    "overlap_s",
    "runner_up",
    "runner_up_cost",
    "runner_up_side",
    "margin",
    "margin_rel",
    "gate",
    # the pair's tracks that are plots, not tracks (several positions at one time:
    # :func:`wakeline.core.tracks.plot_like`), labels joined by "+"; "" for none
    "plot_tracks",
)


def track_label(sensor: object, batch: object) -> str:
    """``sensor:batch`` — the name of a track in proposals, links and targets."""
    return f"{sensor}:{batch}"


def pair_key(a: str, b: str) -> tuple[str, str]:
    """Order-free key of a pair of track labels."""
    return (a, b) if a <= b else (b, a)


def _labels(keys: pd.DataFrame) -> np.ndarray:
    s = keys["sensor"].to_numpy().astype(str)
    b = keys["batch"].to_numpy().astype(str)
    return np.char.add(np.char.add(s, ":"), b)


def _point_label_codes(points: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Per point the number of its track, and each track's label (:func:`_labels` of
    the keys as text): ``labels[codes]`` is ``_labels(points[["sensor", "batch"]]
    .astype(str))`` with text made once per track, not per point (a million points'
    labels took a second or more, holding the GIL in the review's worker)."""
    sc, su = pd.factorize(points["sensor"], use_na_sentinel=False)
    bc, bu = pd.factorize(points["batch"], use_na_sentinel=False)
    nb = max(len(bu), 1)
    codes, pairs = pd.factorize(sc.astype("int64") * nb + bc, use_na_sentinel=False)
    s = pd.Series(np.asarray(su, dtype=object)[pairs // nb]).astype(str).to_numpy().astype(str)
    b = pd.Series(np.asarray(bu, dtype=object)[pairs % nb]).astype(str).to_numpy().astype(str)
    return codes, np.char.add(np.char.add(s, ":"), b)


def point_labels(points: pd.DataFrame) -> np.ndarray:
    """``sensor:batch`` of every point (:func:`_point_label_codes`)."""
    codes, labels = _point_label_codes(points)
    return labels[codes] if len(codes) else np.zeros(0, dtype=str)


def _runner_up(
    a: np.ndarray,
    b: np.ndarray,
    cost: np.ndarray,
    chosen: np.ndarray,
    labels: np.ndarray,
    target: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """For each chosen candidate: the cheapest other candidate sharing its ``a`` or its
    ``b`` track — label of the competing track, its cost, and which side it competes for
    (``a``: it pairs with the proposal's ``a`` track); ``""``/NaN when there is none.

    ``target`` (per track): a candidate between two tracks of one target is no rival —
    it skips a step of the same ship's chain (a moored ship's pieces at one spot are all
    as cheap as the next one), so it would show a negative margin on a sound join."""
    m = len(a)
    cand = pd.DataFrame({"k": np.arange(m), "a": a, "b": b, "cost": cost})
    ok = np.isfinite(cost)
    if target is not None and m:
        ok &= target[a] != target[b]
    cand = cand[ok]
    best = []
    for own, other in (("a", "b"), ("b", "a")):
        # The two cheapest candidates of every track on this side.
        two = cand.sort_values(["cost", "k"], kind="stable").groupby(own, sort=False).head(2)
        sel = pd.DataFrame({"k": chosen, own: a[chosen] if own == "a" else b[chosen]})
        j = sel.merge(two, on=own, how="left", suffixes=("", "_c"))
        j = j[j["k"] != j["k_c"]].drop_duplicates("k")
        j = sel[["k"]].merge(j, on="k", how="left")
        best.append((j["cost"].to_numpy(dtype="float64"), j[other].to_numpy()))
    (ca, oa), (cb, ob) = best
    use_b = np.isnan(ca) | (cb < ca)
    c = np.where(use_b, cb, ca)
    other = np.where(use_b, ob, oa)
    lab = np.full(len(chosen), "", dtype=object)
    ok = ~np.isnan(c)
    lab[ok] = labels[other[ok].astype("int64")]
    side = np.where(ok, np.where(use_b, "b", "a"), "")
    return lab, c, side


def _finish(df: pd.DataFrame, prefix: str, gate: float) -> pd.DataFrame:
    """Margins (against the runner-up or the gate), ids, column order."""
    df["gate"] = float(gate)
    # A rival dearer than the gate is no alternative: leaving both unmatched costs the gate.
    df["margin"] = np.fmin(df["runner_up_cost"], float(gate)) - df["cost"]
    df["margin_rel"] = df["margin"] / gate if gate > 0 else np.nan
    df = df.sort_values(["sensor_a", "batch_a", "sensor_b", "batch_b"], kind="stable")
    df.insert(0, "proposal", [f"{prefix}{k + 1:04d}" for k in range(len(df))])
    for c in PROPOSAL_COLUMNS:
        if c not in df.columns:
            df[c] = "" if c == "plot_tracks" else np.nan
    return df[list(PROPOSAL_COLUMNS)].reset_index(drop=True)


def mark_plot_tracks(proposals: pd.DataFrame, plots: Iterable[str]) -> pd.DataFrame:
    """``proposals`` with ``plot_tracks`` naming each pair's tracks among ``plots`` (track
    labels that are plots, not tracks: :func:`wakeline.core.tracks.plot_like`)."""
    plots = set(plots)
    out = proposals.copy()
    if not len(out):
        out["plot_tracks"] = pd.Series([], dtype=object)
        return out
    a = [track_label(s, b) for s, b in zip(out["sensor_a"], out["batch_a"], strict=True)]
    b = [track_label(s, b) for s, b in zip(out["sensor_b"], out["batch_b"], strict=True)]
    out["plot_tracks"] = [
        "+".join(x for x in (la, lb) if x in plots) for la, lb in zip(a, b, strict=True)
    ]
    return out


def _excluded(labels: np.ndarray, a: np.ndarray, b: np.ndarray, rejected: Iterable) -> np.ndarray:
    """Mask of candidates whose pair of labels is in ``rejected``."""
    rej = {pair_key(*p) for p in rejected}
    if not rej or len(a) == 0:
        return np.zeros(len(a), dtype=bool)
    la, lb = labels[a], labels[b]
    return np.fromiter(
        (pair_key(x, y) in rej for x, y in zip(la.tolist(), lb.tolist(), strict=True)),
        dtype=bool,
        count=len(a),
    )


def association_proposals(
    assoc: "_assoc.Association",
    params: "_assoc.LinkParams | None" = None,
    rejected: Iterable[tuple[str, str]] = (),
) -> tuple[pd.DataFrame, "_assoc.Association"]:
    """Proposals of a single-sensor association, and the association they come from.

    Pairs in ``rejected`` (track labels) are taken out of the candidates and the
    assignment is run again on the rest (same method, same gate), so a rejected pair is
    never proposed again and its tracks may find another partner. Returns the proposal
    table (columns :data:`PROPOSAL_COLUMNS`, ``kind`` = ``associate``) and the association
    with the rejected pairs removed (unchanged when nothing was rejected).
    """
    from wakeline.core import associate as _assoc

    params = (params or _assoc.LinkParams()).checked()
    seg = assoc.segments
    labels = _labels(seg.index.keys)
    p = assoc.pairs
    cost = np.asarray(assoc.cost, dtype="float64").copy()
    out = _excluded(labels, p.i, p.j, rejected)
    if out.any() and assoc.base is not None:
        # The same assignment again (chain passes and second look included) with the
        # rejected pairs refused, in either direction.
        where = pd.Series(np.arange(len(labels)), index=labels)
        where = where[~where.index.duplicated()]
        a = where.reindex([x for x, _ in rejected]).to_numpy()
        b = where.reindex([y for _, y in rejected]).to_numpy()
        ok = ~(np.isnan(a) | np.isnan(b))
        a, b = a[ok].astype("int64"), b[ok].astype("int64")
        n = len(labels)
        assoc = assoc.without(np.concatenate([a * n + b, b * n + a]))
        p = assoc.pairs
        cost = np.asarray(assoc.cost, dtype="float64")
        seg = assoc.segments
    elif out.any():
        cost[out] = np.inf
        gate = params.gate if assoc.method in ("optimal", "greedy", "motion") else params.limit
        if assoc.method == "optimal":
            chosen = _assoc.optimal_assign(p.i, p.j, cost, gate)
        elif assoc.method == "greedy":
            chosen = _assoc.greedy_assign(p.i, p.j, cost, gate)
        else:
            chosen = _assoc._cluster(seg, p, cost, gate, params)
        targets = _assoc._targets(seg, p.i[chosen], p.j[chosen])
        assoc = dataclasses.replace(assoc, cost=cost, chosen=chosen, target_of_track=targets)
    gate = params.gate if assoc.method in ("optimal", "greedy", "motion") else params.limit
    k = np.asarray(assoc.chosen, dtype="int64")
    keys = seg.index.keys
    rival, rival_cost, rival_side = _runner_up(
        p.i, p.j, cost, k, labels, np.asarray(assoc.target_of_track)
    )
    known = (
        seg.motion1[p.i[k]] & seg.motion0[p.j[k]]
        if seg.motion0 is not None and seg.motion1 is not None
        else np.ones(len(k), dtype=bool)
    )
    # The spread term's part of the cost (the parts above do not show it): the cost less
    # the same pair priced without it, which needs no other candidate.
    spread = np.full(len(k), np.nan)
    # The acceleration an end shows, where it lowered the join's cost (widened its gate):
    # not where the drift cap, the rest rule or a blind pair's price made it moot.
    accel = np.full(len(k), np.nan)
    used = assoc.params or params
    if assoc.method in _assoc.INTERRUPT_METHODS and assoc.normalize == "scaled" and len(k):
        flat = _assoc.pair_cost(p.take(k), used.replace(log_sigma=0.0), "scaled", seg)
        spread = cost[k] - flat
        if used.measured_accel and used.uncertainty_gate:
            alone = used.replace(log_sigma=0.0, measured_accel=False)
            lowered = _assoc.pair_cost(p.take(k), alone, "scaled", seg) - flat >= 0.005
            shown = np.broadcast_to(_assoc._gap_accel(seg, p.i[k], p.j[k], used), len(k))
            accel = np.where(lowered, shown, np.nan)
    df = pd.DataFrame(
        {
            "kind": "associate",
            "sensor_a": keys["sensor"].to_numpy().astype(str)[p.i[k]],
            "batch_a": keys["batch"].to_numpy().astype(str)[p.i[k]],
            "sensor_b": keys["sensor"].to_numpy().astype(str)[p.j[k]],
            "batch_b": keys["batch"].to_numpy().astype(str)[p.j[k]],
            "method": np.where(
                assoc.long_joins(), f"{assoc.method}, second look (gap beyond T_gap)", assoc.method
            ),
            "cost": cost[k],
            "gap_s": p.gap_s[k],
            "distance_m": p.dist_m[k],
            "miss_m": p.miss_m[k],
            # Unknown, not zero, where an end shows no motion (a single fix).
            "dcourse_deg": np.where(known, p.dcourse_deg[k], np.nan),
            "dspeed_kn": np.where(known, p.dspeed_kn[k], np.nan),
            "spread": spread,
            "end_accel_ms2": accel,
            "overlap_s": np.nan,
            "runner_up": rival,
            "runner_up_cost": rival_cost,
            "runner_up_side": rival_side,
        }
    )
    return _finish(df, "A", gate), assoc


def fusion_proposals(
    sassoc: "object",
    params: "object | None" = None,
    rejected: Iterable[tuple[str, str]] = (),
) -> tuple[pd.DataFrame, "object"]:
    """Proposals of a cross-sensor association (:class:`wakeline.core.fuse.SensorAssociation`).

    As :func:`association_proposals`: rejected pairs leave the candidates and the
    one-to-one assignment per pair of sensors runs again. ``cost`` and ``distance_m`` are
    the track distance (m, synchronized or DTW), ``gap_s`` is 0 and ``overlap_s`` the
    common time span; the gate is ``max_distance_m``.
    """
    from wakeline.core import associate as _assoc
    from wakeline.core.fuse import FuseParams, _spans, _target_labels

    params = (params or FuseParams()).checked()
    index = sassoc.index
    labels = _labels(index.keys)
    a, b = sassoc.a, sassoc.b
    dist = np.asarray(sassoc.distance_m, dtype="float64").copy()
    out = _excluded(labels, a, b, rejected)
    gate = float(params.max_distance_m)
    if out.any():
        dist[out] = np.inf
        assign = _assoc.optimal_assign if sassoc.method == "optimal" else _assoc.greedy_assign
        sensor_of = pd.factorize(index.keys["sensor"])[0]
        chosen = []
        pair = sensor_of[a] * (sensor_of.max() + 1) + sensor_of[b] if len(a) else a
        for code in np.unique(pair):
            sel = np.flatnonzero(pair == code)
            chosen.append(sel[assign(a[sel], b[sel], dist[sel], gate)])
        chosen = np.concatenate(chosen) if chosen else np.zeros(0, dtype="int64")
        _, t0, _ = _spans(sassoc.points, index)
        target = _target_labels(index, t0, a[chosen], b[chosen])
        sassoc = dataclasses.replace(sassoc, distance_m=dist, chosen=chosen, target_of_track=target)
    k = np.asarray(sassoc.chosen, dtype="int64")
    keys = index.keys
    rival, rival_cost, rival_side = _runner_up(a, b, dist, k, labels)
    df = pd.DataFrame(
        {
            "kind": "fuse",
            "sensor_a": keys["sensor"].to_numpy().astype(str)[a[k]],
            "batch_a": keys["batch"].to_numpy().astype(str)[a[k]],
            "sensor_b": keys["sensor"].to_numpy().astype(str)[b[k]],
            "batch_b": keys["batch"].to_numpy().astype(str)[b[k]],
            "method": f"{sassoc.distance}/{sassoc.method}",
            "cost": dist[k],
            "gap_s": 0.0,
            "distance_m": dist[k],
            "overlap_s": sassoc.overlap_s[k],
            "runner_up": rival,
            "runner_up_cost": rival_cost,
            "runner_up_side": rival_side,
        }
    )
    return _finish(df, "F", gate), sassoc


def track_table(points: pd.DataFrame) -> pd.DataFrame:
    """One row per track: ``track`` label, sensor, batch, ``t0``/``t1`` (s since epoch)."""
    if len(points) == 0:
        return pd.DataFrame(columns=["track", "sensor", "batch", "t0", "t1"])
    t = time_seconds(points["time"])
    g = pd.DataFrame(
        {
            "sensor": points["sensor"].astype(str).to_numpy(),
            "batch": points["batch"].astype(str).to_numpy(),
            "t": t,
        }
    )
    span = g.groupby(["sensor", "batch"], sort=True)["t"].agg(["min", "max"]).reset_index()
    span.columns = ["sensor", "batch", "t0", "t1"]
    span.insert(0, "track", _labels(span))
    return span


def read_proposals(df: pd.DataFrame) -> pd.DataFrame:
    """A proposals table read back from CSV: types fixed, required columns checked."""
    need = ("proposal", "sensor_a", "batch_a", "sensor_b", "batch_b")
    missing = [c for c in need if c not in df.columns]
    if missing:
        raise InputError(f"proposals table lacks the column(s) {', '.join(missing)}")
    out = df.copy()
    names = ("proposal", "sensor_a", "batch_a", "sensor_b", "batch_b", "kind", "method")
    optional = ("runner_up", "runner_up_side", "plot_tracks")  # empty where there is none
    for c in PROPOSAL_COLUMNS:
        if c not in out.columns:
            out[c] = "" if c in ("kind", "method", *optional) else np.nan
        elif c in names:
            out[c] = out[c].astype(str)
        elif c in optional:
            out[c] = out[c].fillna("").astype(str)
        else:  # a number: a cell that is not one reads as unknown
            out[c] = pd.to_numeric(out[c], errors="coerce")
    dup = out["proposal"].duplicated()
    if dup.any():
        raise InputError(f"proposal id {out['proposal'][dup].iloc[0]!r} appears twice")
    same = (out["sensor_a"] == out["sensor_b"]) & (out["batch_a"] == out["batch_b"])
    if same.any():
        row = out[same].iloc[0]
        raise InputError(
            f"proposal {row['proposal']!r} joins track {row['sensor_a']}:{row['batch_a']} to itself"
        )
    return out[list(PROPOSAL_COLUMNS)].reset_index(drop=True)


# --------------------------------------------------------------------------------------
# decisions


@dataclass(frozen=True)
class Change:
    """What one decision changes: proposal statuses (before → after) and manual links
    added or removed. Pure data; :meth:`inverse` swaps the two sides."""

    action: str
    proposal: str = ""
    tracks: tuple[str, ...] = ()
    status_before: Mapping[str, str] = field(default_factory=dict)
    status_after: Mapping[str, str] = field(default_factory=dict)
    links_added: frozenset = frozenset()
    links_removed: frozenset = frozenset()

    @property
    def empty(self) -> bool:
        """Changes nothing: no status moves and no link is added or removed (a merge of
        tracks already in one target, an accept of an accepted proposal)."""
        moved = any(self.status_before.get(k) != v for k, v in self.status_after.items())
        return not (moved or self.links_added or self.links_removed)

    def inverse(self) -> "Change":
        """The change that undoes this one (its action is ``undo <action>``, and the
        inverse of that is the original again)."""
        action = self.action[5:] if self.action.startswith("undo ") else f"undo {self.action}"
        return Change(
            action,
            self.proposal,
            self.tracks,
            dict(self.status_after),
            dict(self.status_before),
            self.links_removed,
            self.links_added,
        )

    def to_dict(self) -> dict:
        """JSON-ready form (for the project's decision store)."""
        return {
            "action": self.action,
            "proposal": self.proposal,
            "tracks": list(self.tracks),
            "status_before": dict(self.status_before),
            "status_after": dict(self.status_after),
            "links_added": sorted(list(x) for x in self.links_added),
            "links_removed": sorted(list(x) for x in self.links_removed),
        }

    @staticmethod
    def from_dict(d: Mapping) -> "Change":
        return Change(
            d["action"],
            d.get("proposal", ""),
            tuple(d.get("tracks", ())),
            dict(d.get("status_before", {})),
            dict(d.get("status_after", {})),
            frozenset(tuple(x) for x in d.get("links_added", ())),
            frozenset(tuple(x) for x in d.get("links_removed", ())),
        )


@dataclass(frozen=True)
class LogEntry:
    """One line of the decision log: time (UTC), action, proposal, tracks, the targets of
    those tracks before → after."""

    time: str
    action: str
    proposal: str
    tracks: str
    before: str
    after: str


class ReviewState:
    """Proposals, their statuses and the manual links; targets follow from them.

    ``tracks`` is :func:`track_table` of the reviewed points (every track, linked or not);
    ``proposals`` the table of :func:`association_proposals` / :func:`fusion_proposals`
    (several may be concatenated: ids must be unique). Apply decisions with
    :meth:`apply`; each returns the change applied, whose inverse undoes it.
    """

    def __init__(self, tracks: pd.DataFrame, proposals: pd.DataFrame) -> None:
        self.tracks = tracks.reset_index(drop=True)
        self.proposals = read_proposals(proposals)
        self._track_no = {t: k for k, t in enumerate(self.tracks["track"].tolist())}
        a = _labels(self.proposals[["sensor_a", "batch_a"]].set_axis(["sensor", "batch"], axis=1))
        b = _labels(self.proposals[["sensor_b", "batch_b"]].set_axis(["sensor", "batch"], axis=1))
        unknown = [x for x in np.concatenate([a, b]).tolist() if x not in self._track_no]
        if unknown:
            raise InputError(
                f"proposal names the track {unknown[0]} that is not in the points "
                f"({len(set(unknown))} unknown track(s))"
            )
        self.proposals["track_a"] = a
        self.proposals["track_b"] = b
        self.track_a = a.astype(object)  # numpy copies for fast lookups
        self.track_b = b.astype(object)
        self._labels_arr = self.tracks["track"].to_numpy().astype(str)
        self._t0_arr = self.tracks["t0"].to_numpy(dtype="float64")
        self._pa = np.array([self._track_no[x] for x in a.tolist()], dtype="int64")
        self._pb = np.array([self._track_no[x] for x in b.tolist()], dtype="int64")
        self._row = {p: k for k, p in enumerate(self.proposals["proposal"].tolist())}
        self.status = np.array(["pending"] * len(self.proposals), dtype=object)
        self.links: set[tuple[str, str]] = set()
        self.log: list[LogEntry] = []
        #: Log lines of the earlier runs of this queue's step on the same layer (their
        #: decisions, not replayed here: the append-only record the log export begins
        #: with, :meth:`log_table`).
        self.history: list[LogEntry] = []
        self._targets: np.ndarray | None = None
        self.version = 0  # counts applied changes (views cache per version)

    # -- queries ------------------------------------------------------------------------

    def status_of(self, proposal: str) -> str:
        return str(self.status[self._proposal_row(proposal)])

    def _proposal_row(self, proposal: str) -> int:
        try:
            return self._row[proposal]
        except KeyError:
            raise InputError(f"no proposal {proposal!r}") from None

    def _track(self, label: str) -> int:
        try:
            return self._track_no[label]
        except KeyError:
            raise InputError(f"no track {label!r}") from None

    def table(self) -> pd.DataFrame:
        """The proposals with their current ``status``."""
        out = self.proposals.copy()
        out["status"] = self.status
        return out

    def target_of_track(self) -> np.ndarray:
        """Target label per row of :attr:`tracks` (cached until the next change)."""
        if self._targets is None:
            self._targets = self._compute_targets()
        return self._targets

    def _compute_targets(self) -> np.ndarray:
        from wakeline.core.associate import components, group_leaders

        active = np.isin(self.status, ACTIVE)
        la = [self._track_no[x] for x, _ in self.links]
        lb = [self._track_no[y] for _, y in self.links]
        a = np.concatenate([self._pa[active], np.asarray(la, dtype="int64")])
        b = np.concatenate([self._pb[active], np.asarray(lb, dtype="int64")])
        n = len(self.tracks)
        comp = components(n, a, b)
        order = np.lexsort((self._labels_arr, self._t0_arr, comp))
        return self._labels_arr[group_leaders(comp, order)] if n else np.zeros(0)

    def target(self, label: str) -> str:
        return str(self.target_of_track()[self._track(label)])

    def proposal_targets(self) -> np.ndarray:
        """Per row of :attr:`proposals`: the target its track A belongs to now (both
        tracks' when the proposal is accepted), as the decisions make it."""
        return self.target_of_track()[self._pa] if len(self._pa) else np.zeros(0, dtype=object)

    def members(self, target: str) -> list[str]:
        """Track labels of one target, earliest first."""
        tg = self.target_of_track()
        sel = np.flatnonzero(tg == target)
        sel = sel[np.argsort(self._t0_arr[sel], kind="stable")]
        return self._labels_arr[sel].tolist()

    def targets(self) -> pd.DataFrame:
        """Per track: ``track``, sensor, batch, ``target``."""
        out = self.tracks[["track", "sensor", "batch"]].copy()
        out["target"] = self.target_of_track()
        return out

    def label_points(self, points: pd.DataFrame) -> pd.DataFrame:
        """``points`` with a ``target`` column as the decisions make it."""
        tt = self.targets()
        codes, labels = _point_label_codes(points)
        per_track = tt.set_index("track")["target"].reindex(labels)
        target = per_track.to_numpy()
        out = points.copy(deep=False)  # copy on write: the new column only
        if len(codes) and pd.Series(target).dtype == per_track.dtype:
            # The tracks' column taken per point: what the per-point values would become
            # (their type inferred from the tracks' values: the same values), without a
            # million Python strings converted with the GIL held (~60 ms at 1 M points).
            out["target"] = per_track.array.take(codes)
        else:
            out["target"] = target[codes] if len(codes) else target[:0]
        return out

    def rejected_pairs(self) -> set[tuple[str, str]]:
        """Pairs of track labels rejected by the operator (to keep out of re-runs)."""
        rej = self.status == "rejected"
        p = self.proposals
        return {
            pair_key(x, y)
            for x, y in zip(p["track_a"][rej].tolist(), p["track_b"][rej].tolist(), strict=True)
        }

    def tracks_apart(self, proposals: Iterable[str]) -> dict[str, bool]:
        """Per proposal: whether its two tracks are in two targets now."""
        tg = self.target_of_track()
        rows = {pid: self._proposal_row(pid) for pid in proposals}
        return {pid: bool(tg[self._pa[k]] != tg[self._pb[k]]) for pid, k in rows.items()}

    def proposals_of_track(self, label: str) -> list[str]:
        sel = (self.track_a == label) | (self.track_b == label)
        return self.proposals["proposal"].to_numpy()[sel].tolist()

    # -- decisions ----------------------------------------------------------------------

    def apply(self, change: Change, when: str | None = None, how: str = "do") -> Change:
        """Apply a change (checked against the current state), log it, return it.

        ``how`` (do, undo, redo: how the window's undo stack made it): a redo is logged
        ``redo <action>`` — the decision it applies again, marked (operator test 9, D13:
        an exported log showed a redo as a second decision); :func:`replay_log` reads it
        so. An undo's change is its inverse already (``undo <action>``)."""
        for pid, before in change.status_before.items():
            now = self.status[self._proposal_row(pid)]
            if now != before:
                raise InputError(f"{pid} is {now}, not {before}: the change no longer applies")
        before = self._targets_of(change.tracks)
        for pid, after in change.status_after.items():
            if after not in STATUSES:
                raise InputError(f"unknown status {after!r}")
            self.status[self._row[pid]] = after
        self.links -= set(change.links_removed)
        self.links |= set(change.links_added)
        self._targets = None
        self.version += 1
        after = self._targets_of(change.tracks)
        self.log.append(
            LogEntry(
                when or _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
                f"{REDO}{change.action}" if how == "redo" else change.action,
                change.proposal,
                " ".join(change.tracks),
                _logged(change.status_before, before),
                _logged(change.status_after, after),
            )
        )
        return change

    def _targets_of(self, tracks: Iterable[str]) -> list[str]:
        """The targets of ``tracks`` as ``target=member+member…`` (each target once)."""
        tg = self.target_of_track()
        names = dict.fromkeys(str(tg[self._track(t)]) for t in tracks)
        return [f"{t}={'+'.join(self.members(t))}" for t in names]

    def log_table(self) -> pd.DataFrame:
        """The decision log: time, action, proposal, tracks, before, after — the earlier
        runs' lines (:attr:`history`) first, then this queue's."""
        cols = ["time", "action", "proposal", "tracks", "before", "after"]
        rows = [dataclasses.astuple(e) for e in [*self.history, *self.log]]
        return pd.DataFrame(rows, columns=cols)


def _logged(status: Mapping[str, str], targets: list[str]) -> str:
    """A decision log's before or after cell: the statuses the change sets, then the
    targets of its tracks, ``F0002 pending; radar:1=radar:1+AIS:1``. Without the
    statuses an accept's two cells were the same (a pending proposal counts as joined
    already: operator test 8, D9); a change of no status (merge, split target) logs
    the targets alone, as before."""
    cells = " ".join(targets)
    if not status:
        return cells
    moved = ", ".join(f"{pid} {s}" for pid, s in status.items())
    return f"{moved}; {cells}" if cells else moved


def unreviewed_note(state: ReviewState) -> str:
    """The sentence an export of the reviewed tracks carries while proposals are still
    pending ("N of M proposals not reviewed: counted as accepted", the rule of
    docs/review.md: a proposal without a decision counts as the engine proposed it), or
    "" when every proposal has a decision."""
    pending = int((state.status == "pending").sum())
    if not pending:
        return ""
    total = len(state.status)
    noun = "proposal" if total == 1 else "proposals"
    return f"{pending:,} of {total:,} {noun} not reviewed: counted as accepted"


def _set(state: ReviewState, action: str, proposal: str, status: str) -> Change:
    row = state._proposal_row(proposal)
    p = state.proposals.iloc[row]
    after = {proposal: status}
    if status in ACTIVE and state.status[row] not in ACTIVE:
        # A join: what it puts into one target is joined, whatever its rows said.
        after |= dict.fromkeys(_cut_but_joined(state, after), "accepted")
    return Change(
        action,
        proposal,
        (p["track_a"], p["track_b"]),
        {pid: str(state.status[state._row[pid]]) for pid in after},
        after,
    )


def _component_of(
    state: ReviewState, status: Mapping[str, str] | None = None, links: Iterable = ()
) -> np.ndarray:
    """Component number per track with the statuses ``status`` set and ``links`` added
    (the targets such a change would make; the state is not touched)."""
    from wakeline.core.associate import components

    st = state.status.copy()
    for pid, s in (status or {}).items():
        st[state._row[pid]] = s
    active = np.isin(st, ACTIVE)
    every = state.links | set(links)
    la = np.asarray([state._track_no[x] for x, _ in every], dtype="int64")
    lb = np.asarray([state._track_no[y] for _, y in every], dtype="int64")
    a = np.concatenate([state._pa[active], la])
    b = np.concatenate([state._pb[active], lb])
    return components(len(state.tracks), a, b)


def _cut_but_joined(
    state: ReviewState, status: Mapping[str, str], links: Iterable = ()
) -> list[str]:
    """Proposals rejected or split whose two tracks a change (``status`` set, ``links``
    added) puts into one target: the change says they are one ship, so their rows must
    not say otherwise (they become ``accepted``)."""
    comp = _component_of(state, status, links)
    cut = ~np.isin(state.status, ACTIVE)
    for pid in status:
        cut[state._row[pid]] = False
    sel = np.flatnonzero(cut & (comp[state._pa] == comp[state._pb]))
    return state.proposals["proposal"].to_numpy()[sel].tolist()


def accept(state: ReviewState, proposal: str) -> Change:
    """Accept a proposal: its two tracks are one ship (a rejected or split proposal the
    join puts inside the target is accepted with it)."""
    return _set(state, "accept", proposal, "accepted")


def reject(state: ReviewState, proposal: str) -> Change:
    """Reject a proposal: its link no longer counts, and re-runs leave the pair out."""
    return _set(state, "reject", proposal, "rejected")


def reset(state: ReviewState, proposal: str) -> Change:
    """Put a proposal back to pending."""
    return _set(state, "reset", proposal, "pending")


def merge(state: ReviewState, tracks: Iterable[str]) -> Change:
    """Merge two or more tracks by hand into one target: every rejected or split proposal
    among the tracks of their targets is accepted again, and manual links in a chain
    through ``tracks`` join what is still apart."""
    tracks = list(dict.fromkeys(tracks))
    if len(tracks) < 2:
        raise InputError("merge needs at least two different tracks")
    rows = [state._track(t) for t in tracks]
    # Every track of the targets merged ends in one target: a proposal among them that
    # was rejected or split joins them again (accepted), so its row does not say "split"
    # beside a joined target; manual links only join what those proposals leave apart.
    tg = state.target_of_track()
    involved = np.isin(tg, tg[rows])
    among = involved[state._pa] & involved[state._pb] & ~np.isin(state.status, ACTIVE)
    after = dict.fromkeys(state.proposals["proposal"].to_numpy()[among].tolist(), "accepted")
    comp = _component_of(state, after)
    links = set()
    for x, y, rx, ry in zip(tracks[:-1], tracks[1:], rows[:-1], rows[1:], strict=True):
        cx, cy = comp[rx], comp[ry]
        if cx != cy:
            links.add(pair_key(x, y))
            comp[comp == cy] = cx
    return Change(
        "merge",
        next(iter(after)) if len(after) == 1 else "",
        tuple(tracks),
        {pid: str(state.status[state._row[pid]]) for pid in after},
        after,
        links_added=frozenset(links),
    )


def split_track(state: ReviewState, label: str) -> Change:
    """One track leaves its target: every active proposal and manual link touching it is
    cut (proposals get the status ``split``, which re-runs may propose again)."""
    return _cut(state, "split track", [label], lambda a, b: (a == label) | (b == label))


def split_target(state: ReviewState, target: str) -> Change:
    """A target falls back into its tracks: every active link among its members is cut."""
    members = state.members(target)
    if not members:
        raise InputError(f"no target {target!r}")
    inside = set(members)
    return _cut(
        state,
        "split target",
        members,
        lambda a, b: np.isin(a, list(inside)) & np.isin(b, list(inside)),
    )


def _cut(state: ReviewState, action: str, tracks: list[str], touches) -> Change:
    for t in tracks:
        state._track(t)
    p = state.proposals
    sel = np.flatnonzero(
        touches(p["track_a"].to_numpy(), p["track_b"].to_numpy()) & np.isin(state.status, ACTIVE)
    )
    ids = p["proposal"].to_numpy()[sel].tolist()
    gone = {lk for lk in state.links if bool(touches(np.array([lk[0]]), np.array([lk[1]]))[0])}
    return Change(
        action,
        ids[0] if len(ids) == 1 else "",
        tuple(tracks),
        {pid: str(state.status[state._row[pid]]) for pid in ids},
        dict.fromkeys(ids, "split"),
        links_removed=frozenset(gone),
    )


def cut_inside_targets(state: ReviewState) -> list[str]:
    """Proposals rejected or split whose two tracks are in one target now."""
    tg = state.target_of_track()
    cut = ~np.isin(state.status, ACTIVE)
    sel = np.flatnonzero(cut & (tg[state._pa] == tg[state._pb]))
    return state.proposals["proposal"].to_numpy()[sel].tolist()


def repair(state: ReviewState, proposal: str) -> Change:
    """The change that accepts a rejected or split proposal a join left inside a target
    (action ``repair``), as :func:`merge` and :func:`accept` do since they accept such
    rows in the same change; a manual link between its two tracks goes with it (the
    accepted proposal joins them: the targets do not change). For projects whose
    decisions were made before that (:func:`wakeline.core.review_session.repair_decisions`,
    a migration on open: it is a stored decision like any other, not on the undo stack)."""
    row = state._proposal_row(proposal)
    a, b = state.track_a[row], state.track_b[row]
    if state.status[row] in ACTIVE:
        raise InputError(f"{proposal} is {state.status[row]}: nothing to repair")
    if state.target(a) != state.target(b):
        raise InputError(f"{proposal}: its tracks are in two targets: nothing to repair")
    link = pair_key(a, b)
    return Change(
        "repair",
        proposal,
        (a, b),
        {proposal: str(state.status[row])},
        {proposal: "accepted"},
        links_removed=frozenset({link} & state.links),
    )


def cuts_anything(changes: Iterable[Change]) -> bool:
    """Whether any of ``changes`` sets a proposal rejected or split: without one, no row
    can be cut inside a target and :func:`replay_repaired` would repair nothing (the
    check costs no replay)."""
    return any(s not in ACTIVE for c in changes for s in c.status_after.values())


def replay_repaired(
    state: ReviewState,
    changes: Iterable[tuple[Change, str | None]],
    when: str | None = None,
) -> list[Change]:
    """Apply stored ``changes`` (each with its log time) in order, then the migration of
    decisions made before a join accepted the rows it put inside a target: one
    :func:`repair` (logged at ``when``) per proposal left rejected or split beside a
    target holding both its tracks whose tracks were in two targets right after the
    change that last set its status — a later join put them together and left the row
    cut. A row cut while its tracks stayed in one target (other links hold them) is the
    operator's decision and is kept. Returns the repairs applied (the last entries of
    ``state.log``); none for decisions made by today's joins. One pass over the changes
    (the targets after each are the ones :meth:`ReviewState.apply` computed)."""
    apart: dict[str, bool] = {}
    for change, at in changes:
        state.apply(change, when=at)
        cut = [pid for pid, s in change.status_after.items() if s not in ACTIVE]
        if cut:
            apart.update(state.tracks_apart(cut))
    left = [pid for pid in cut_inside_targets(state) if apart.get(pid)]
    return [state.apply(repair(state, pid), when=when) for pid in left]


def apply_decisions(state: ReviewState, decisions: pd.DataFrame) -> ReviewState:
    """Apply a decisions table in order (the CLI's ``--decisions``): rows
    ``proposal,decision`` with accept | reject | reset, ``decision`` = merge (or join) with
    ``sensor_a,batch_a,sensor_b,batch_b``, or split with ``sensor_a,batch_a`` (that track
    leaves its target). A decision log (an ``action`` column and no ``decision``: the
    window's Review ▸ Export log, or ``wakeline review --log``) is replayed
    (:func:`replay_log`). A bad row raises :class:`InputError` naming its line."""
    if "decision" not in decisions.columns and "action" in decisions.columns:
        return replay_log(state, decisions)
    if "decision" not in decisions.columns:
        raise InputError(
            "decisions table lacks the column 'decision' (or 'action', as in a decision log)"
        )
    d = decisions.astype(object).where(decisions.notna(), "")
    for line, row in enumerate(d.to_dict("records"), start=2):
        what = str(row.get("decision", "")).strip().lower()
        try:
            if what in ("accept", "reject", "reset"):
                pid = str(row.get("proposal", "")).strip()
                if not pid:
                    raise InputError(f"{what} needs a proposal id")
                fn = {"accept": accept, "reject": reject, "reset": reset}[what]
                state.apply(fn(state, pid))
            elif what in ("merge", "join"):  # join: a hand join (Join selected tracks)
                a = track_label(row.get("sensor_a", ""), _batch(row.get("batch_a", "")))
                b = track_label(row.get("sensor_b", ""), _batch(row.get("batch_b", "")))
                state.apply(merge(state, [a, b]))
            elif what == "split":
                a = track_label(row.get("sensor_a", ""), _batch(row.get("batch_a", "")))
                state.apply(split_track(state, a))
            else:
                raise InputError(
                    f"unknown decision {what!r} (accept, reject, reset, merge, join or split)"
                )
        except InputError as exc:
            raise InputError(f"decisions line {line}: {exc}") from None
    return state


def _log_tracks(state: ReviewState, text: str) -> list[str]:
    """The track labels of a log's ``tracks`` cell (joined by spaces; a batch may hold
    spaces itself: tokens are joined until they name a track)."""
    labels, part = [], ""
    for token in str(text).split(" "):
        part = f"{part} {token}" if part else token
        if part in state._track_no:
            labels.append(part)
            part = ""
    if part:
        raise InputError(f"no track {part!r} among the input's tracks")
    return labels


def replay_log(state: ReviewState, log: pd.DataFrame) -> ReviewState:
    """Replay a decision log (columns ``time,action,proposal,tracks,…``: what the
    window's Review ▸ Export decision log and ``wakeline review --log`` write) in order,
    as the window made it: accept, reject, reset, merge, split track, split target and
    repair are made again on the state as it is then; ``undo X`` undoes the last decision
    not yet undone (it must be an ``X``); ``redo X`` makes again the last one undone (it
    must be an ``X``; logs before h229 wrote a redo as the decision again, which replays
    the same). Each
    change keeps its logged time. A row that does not apply raises :class:`InputError`
    naming its line. A log that went through re-runs of its step (rows ``re-run``) is
    replayed from its last ``re-run`` row on: the rows above it are the earlier runs'
    decisions, on other proposals; the ones below it carry what still applies."""
    d = log.astype(object).where(log.notna(), "")
    rows = d.to_dict("records")
    marks = [k for k, row in enumerate(rows) if str(row.get("action", "")).strip() == RERUN]
    start = marks[-1] + 1 if marks else 0
    done: list[Change] = []
    undone: list[Change] = []  # the redo history: the last undone last
    for line, row in enumerate(rows[start:], start=2 + start):
        action = str(row.get("action", "")).strip()
        pid = str(row.get("proposal", "")).strip()
        when = str(row.get("time", "")).strip() or None
        try:
            if action.startswith("undo "):
                if not done or done[-1].action != action[5:]:
                    last = done[-1].action if done else "nothing"
                    raise InputError(f"{action!r} but the last decision is {last}")
                undone.append(done.pop())
                state.apply(undone[-1].inverse(), when=when)
                continue
            if action.startswith(REDO):
                if not undone or undone[-1].action != action[len(REDO) :]:
                    last = undone[-1].action if undone else "nothing"
                    raise InputError(f"{action!r} but the last decision undone is {last}")
                done.append(undone.pop())
                state.apply(done[-1], when=when, how="redo")
                continue
            tracks = _log_tracks(state, row.get("tracks", ""))
            if action in ("accept", "reject", "reset", "repair"):
                if not pid:
                    raise InputError(f"{action} needs a proposal id")
                fn = {"accept": accept, "reject": reject, "reset": reset, "repair": repair}
                change = fn[action](state, pid)
            elif action == "merge":
                change = merge(state, tracks)
            elif action == "split track":
                if len(tracks) != 1:
                    raise InputError("split track needs one track")
                change = split_track(state, tracks[0])
            elif action == "split target":
                if not tracks:
                    raise InputError("split target needs its tracks")
                change = split_target(state, state.target(tracks[0]))
            else:
                raise InputError(
                    f"unknown action {action!r} (accept, reject, reset, merge, split track, "
                    "split target, repair or undo …)"
                )
            state.apply(change, when=when)
            if action != "repair":  # a migration, not on the window's undo stack
                done.append(change)
                undone.clear()  # a new decision drops the redo history
        except InputError as exc:
            raise InputError(f"decision log line {line}: {exc}") from None
    return state


def _batch(v: object) -> str:
    """A batch cell as text; pandas reads ``7`` as 7.0 when the column has blanks."""
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v).strip()


def combine_sources(named: list[tuple[str, pd.DataFrame]]) -> pd.DataFrame:
    """Point tables of several files or layers as one table for cross-sensor work.

    Two sources that each hold one sensor of the same name (two files imported with the
    default sensor name, e.g. MTAD's radar and AIS samplings) would merge into one sensor;
    such a source's sensor is renamed after the part of its name that differs from the
    others (``scene-0_error_0_AIS`` / ``…_radar`` → ``AIS`` / ``radar``). Sources that
    already carry distinct sensors are kept as they are.
    """
    if not named:
        raise InputError("no input to combine")
    renamed = sensor_renames(named)
    out = []
    for (_, df), new in zip(named, renamed, strict=True):
        if new is not None:
            df = df.copy()
            df["sensor"] = new[1]
        out.append(df)
    both = pd.concat(out, ignore_index=True)
    return both


def sensor_renames(named: list[tuple[str, pd.DataFrame]]) -> list[tuple[str, str] | None]:
    """Per source of :func:`combine_sources`: ``(old, new)`` when its one sensor is
    renamed after the differing part of its name (its sensor's name clashes with another
    source's), else None — the window says so, so that a source layer's "S1" and the
    fused layer's "AIS" read as one sensor (operator test 6, D-gui-6)."""
    sensors = [set(df["sensor"].astype(str).unique()) for _, df in named]
    seen: dict[str, int] = {}
    for s in sensors:
        for x in s:
            seen[x] = seen.get(x, 0) + 1
    names = _distinct_parts([n for n, _ in named])
    return [
        (next(iter(s)), new) if len(s) == 1 and seen[next(iter(s))] > 1 else None
        for s, new in zip(sensors, names, strict=True)
    ]


def source_names(names: list[str], paths: list[str | None]) -> list[str]:
    """The names :func:`combine_sources` tells sources apart by: ``names`` (file stems) as
    given, except where two or more are equal — there the folders that tell their files'
    ``paths`` apart (``ais/tracks.csv`` and ``radar/tracks.csv`` → ``ais`` and ``radar``;
    both were ``tracks``, one sensor, and fusion found "tracks of one sensor" only;
    :func:`distinct_folders`)."""
    out = list(names)
    for name in {n for n in out if out.count(n) > 1}:
        ks = [k for k, n in enumerate(out) if n == name and paths[k]]
        if len(ks) < 2:
            continue
        for k, folder in zip(ks, distinct_folders([str(paths[k]) for k in ks]), strict=True):
            out[k] = folder or out[k]
    return out


def distinct_folders(paths: list[str]) -> list[str]:
    """Per path: the fewest folders just above the file that tell it apart from the others
    (``d/radar1/tracks.csv``, ``d/radar2/tracks.csv`` → ``radar1``, ``radar2``;
    ``a/x/t.csv``, ``b/x/t.csv`` → ``a/x``, ``b/x``), whole folder names, never parts of
    one; "" for paths that no folder tells apart (one file twice)."""
    parts = [PurePath(str(p).replace("\\", "/")).parent.parts for p in paths]
    deepest = max((len(p) for p in parts), default=0)
    for d in range(1, deepest + 1):
        tails = ["/".join(p[-d:]) for p in parts]
        if len(set(tails)) == len(tails):
            return tails
    tails = ["/".join(p) for p in parts]
    return [t if tails.count(t) == 1 else "" for t in tails]


def _distinct_parts(names: list[str]) -> list[str]:
    """Each name without the leading and trailing words all names share (words end at
    ``_``, ``-``, ``.``, ``/`` or a space: ``radar1`` and ``radar2`` stay whole, not ``1``
    and ``2``); the whole name when that leaves nothing or two would be equal."""
    if len(names) < 2:
        return list(names)
    import os

    seps = "_-./ "
    pre = os.path.commonprefix(names)
    if not all(len(n) == len(pre) or n[len(pre)] in seps for n in names):
        pre = pre[: max(pre.rfind(c) for c in seps) + 1]  # back to a word's end
    suf = os.path.commonprefix([n[::-1] for n in names])[::-1]
    if suf and not all(len(n) == len(suf) or n[-len(suf) - 1] in seps for n in names):
        cut = [k for k, c in enumerate(suf) if c in seps]
        suf = suf[cut[0] :] if cut else ""  # from a word's start
    parts = []
    for n in names:
        core = n[len(pre) : len(n) - len(suf) if suf else len(n)].strip("_- .")
        parts.append(core or n)
    if len(set(parts)) < len(parts):
        return list(names)
    return parts

"""The session model: the operator's layers with stable ids and lineage (Qt-free).

A :class:`Session` holds every layer — imported files and step results — by a stable id
(``L1``, ``L2`` …), never by display name. A result layer records its lineage: the input
layer's id, the step, the role it plays in the step's output (``cleaned``,
``compressed`` …), the parameters and the time it was made. Re-running a step on the same
input replaces only the layers of that (input, step, role); results of other inputs
coexist. The GUI is a view over a session: it subscribes to its events
(``added``, ``changed``, ``removed``, ``visibility``, ``tables`` — a layer's side
tables or meta changed, not its points; ``decisions`` — a re-run's carried review
decisions, rows of the layer's new queue, were appended to ``decisions``;
``time_window``, ``current_time``, ``map_view`` and ``active`` with no layer id) and never keeps layers
of its own. The session also holds what brings an operator back to where they were,
saved with the project: the map's time window
(:class:`~wakeline.core.timeline.TimeWindow`, s), the time slider's time (s), the map's
view (:class:`MapView`, degrees), the active layer and the selected tracks.
"""

import dataclasses
import datetime as dt
import itertools
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from wakeline.core.errors import InputError, StaleResult
from wakeline.core.params import finite_number
from wakeline.core.pipeline import STEPS, Pipeline, StepResult, params_to_json
from wakeline.core.progress import Progress, null_progress
from wakeline.core.timeline import TimeWindow, check_current_time
from wakeline.core.words import joined_names

#: Colours per result kind (the map's defaults); sources take the palette in turn.
KIND_COLORS = {
    "cleaned": "#2ca02c",
    "maneuvers": "#9467bd",
    "compressed": "#d62728",
    "associated": "#ff7f0e",
    "fused": "#17becf",
}
#: The kind of a bearing layer: its ``points`` are a bearing table (``batch, time,
#: bearing[, obs_lon, obs_lat]``), its ``tables["detections"]`` the detector's output and
#: its ``meta`` the file, the detector's per-batch report and the lines' length.
BEARING_KIND = "bearing"
#: Its colour in the Layers list (the observer's grey on the map).
BEARING_COLOR = "#555555"
#: A layer's meta key: its colour was chosen by the operator (Layers ▸ Colour…), not
#: given by the window's colour rule, so it is kept on reopening.
COLOR_CHOSEN = "color_chosen"


def check_color(color: object) -> str:
    """``color`` as ``#rrggbb`` in lower case; InputError for anything else."""
    text = str(color).strip().lower()
    if len(text) != 7 or text[0] != "#" or any(c not in "0123456789abcdef" for c in text[1:]):
        raise InputError(f"a colour is #rrggbb, not {color!r}")
    return text


PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf")

Listener = Callable[[str, str], None]  # (event, layer id)


@dataclass(frozen=True)
class Source:
    path: str
    sha256: str


@dataclass
class Layer:
    """A table of points (an imported file or a step result) and where it came from."""

    id: str
    name: str  # display name; may repeat, never used to find a layer
    kind: str  # "source", "cleaned", "maneuvers", "compressed", "associated", "fused", …
    points: pd.DataFrame
    visible: bool = True
    color: str = "#1f77b4"
    meta: dict = field(default_factory=dict)
    parent: str | None = None  # id of the input layer
    step: str | None = None  # the step that made it
    role: str | None = None  # its role in the step's output
    params: dict = field(default_factory=dict)  # the step's parameters, as JSON
    created: str = ""  # ISO time, UTC
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)  # side tables
    inputs: list[str] = field(default_factory=list)  # every input layer id (several: fuse)
    #: This making of the layer, unique (h135: ``created`` is to the second, and two runs
    #: of a step in one second shared a review queue). "" in projects made before.
    run: str = ""
    #: ``wl_id`` of the points the operator put back from the reject trail of a cleaned
    #: layer (:mod:`~wakeline.core.clean_restore`), sorted; a re-run of Clean puts back
    #: those its new trail holds.
    restored: list[int] = field(default_factory=list)

    def lineage(self) -> dict[str, Any]:
        out = {
            "parent": self.parent,
            "step": self.step,
            "role": self.role,
            "params": self.params,
            "created": self.created,
        }
        if self.inputs:
            out["inputs"] = list(self.inputs)
        if self.run:
            out["run"] = self.run
        if self.restored:
            out["restored"] = [int(i) for i in self.restored]
        return out


@dataclass
class LayerRemoval:
    """A layer removed (:meth:`Session.remove_layer`), with what undoing it restores:
    its place, whether it was active and its selected tracks, and the tables and meta
    the layers under review had before they kept its points (id, meta, tables before,
    meta, tables after)."""

    layer: Layer
    pos: int
    active: bool = False
    selection: list = field(default_factory=list)
    generation: int = 0
    kept: list[tuple] = field(default_factory=list)


@dataclass(frozen=True)
class MapView:
    """The map's view box: longitude ``x0`` … ``x1`` and latitude ``y0`` … ``y1``, in
    degrees (as the map's axes). Kept by the session, saved in the project as
    :meth:`to_json` (``{"x": [x0, x1], "y": [y0, y1], "unit": "deg"}``)."""

    x0: float
    x1: float
    y0: float
    y1: float
    #: The unit of the four bounds (written beside them in the project).
    UNIT = "deg"

    def __post_init__(self) -> None:
        for name in ("x0", "x1", "y0", "y1"):
            object.__setattr__(self, name, finite_number(getattr(self, name), f"map view: {name}"))
        if not (self.x0 < self.x1 and self.y0 < self.y1):
            raise ValueError(
                f"map view: longitude {self.x0} … {self.x1}° and latitude {self.y0} … "
                f"{self.y1}° must each increase"
            )

    @classmethod
    def of(cls, view: "MapView | tuple[float, float, float, float] | None") -> "MapView | None":
        """``view`` as a MapView: (x0, x1, y0, y1) in degrees, a MapView, or None."""
        if view is None or isinstance(view, MapView):
            return view
        x0, x1, y0, y1 = view
        return cls(x0, x1, y0, y1)

    def bounds(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) in degrees, as the map's ``show_range`` takes it."""
        return (self.x0, self.x1, self.y0, self.y1)

    def to_json(self) -> dict:
        """The plain value the project stores, with its unit."""
        return {"x": [self.x0, self.x1], "y": [self.y0, self.y1], "unit": self.UNIT}

    @classmethod
    def from_json(cls, value: object) -> "MapView | None":
        """Read :meth:`to_json`'s value back (None: no view). A project saved before
        the view had its unit holds ``[[x0, x1], [y0, y1]]`` (the map's range, degrees),
        read as well. Raises ValueError when it is neither, or not a view (not finite,
        an axis that does not increase, another unit)."""
        if value is None:
            return None
        if isinstance(value, dict):
            if set(value) != {"x", "y", "unit"}:
                raise ValueError(f"map view: expected x, y and unit, got {value!r}")
            if value["unit"] != cls.UNIT:
                raise ValueError(f"map view: unit must be {cls.UNIT!r}, got {value['unit']!r}")
            value = [value["x"], value["y"]]
        if (
            not isinstance(value, list)
            or len(value) != 2
            or not all(isinstance(v, list) and len(v) == 2 for v in value)
        ):
            raise ValueError(f"map view: expected two [from, to] ranges, got {value!r}")
        (x0, x1), (y0, y1) = value
        return cls(x0, x1, y0, y1)


def _now() -> str:
    return dt.datetime.now(dt.UTC).isoformat(timespec="seconds").replace("+00:00", "Z")


def _run_id() -> str:
    """A token naming one making of a layer (:attr:`Layer.run`)."""
    return uuid.uuid4().hex[:12]


class Session:
    """Layers, sources, parameters and selection of one piece of work."""

    def __init__(self) -> None:
        self.layers: dict[str, Layer] = {}  # in display order
        self.sources: list[Source] = []
        self.params: dict[str, dict] = {}
        self.selection: list[tuple[str, str, str]] = []  # layer id, sensor, batch
        self.decisions: list[dict] = []
        #: The map's time window (s on the layers' clock; None: no window).
        self.time_window: TimeWindow | None = None
        #: The map's view (degrees; None: not known, the map frames the data).
        self.map_view: MapView | None = None
        #: The time slider's time (s on the layers' clock, as the time window; None: not
        #: known, the slider starts at the layers' first time).
        self.current_time: float | None = None
        #: The layer the batch table and the steps work on (None: none).
        self.active: str | None = None
        self._ids = itertools.count(1)
        self._listeners: list[Listener] = []
        #: Ids of layers removed that an undo may bring back (:meth:`restore_layer`):
        #: never given to a new layer meanwhile.
        self._retired: set[str] = set()
        #: Counts :meth:`clear` calls: a removal recorded before one is not restored into
        #: the session's next piece of work.
        self.generation = 0

    # -- events --------------------------------------------------------------------

    def subscribe(self, listener: Listener) -> None:
        """Call ``listener(event, layer_id)`` after every change."""
        self._listeners.append(listener)

    def _emit(self, event: str, layer_id: str) -> None:
        for listener in list(self._listeners):
            listener(event, layer_id)

    def note_source(self, path: str, sha256: str) -> None:
        """The file ``path`` was read with content hash ``sha256``: its Source is added,
        or, read before, its hash replaced (a file edited and opened again)."""
        for k, s in enumerate(self.sources):
            if s.path == path:
                self.sources[k] = Source(path, sha256)
                return
        self.sources.append(Source(path, sha256))

    def set_time_window(self, window: TimeWindow | tuple[float, float] | None) -> None:
        """Set the map's time window ((from, to) in s, a :class:`TimeWindow`, or None: no
        window); a ``time_window`` event (layer id ``""``) when it changed. Raises
        ValueError for a window that is not finite or ends before it starts."""
        window = TimeWindow.of(window)
        if window != self.time_window:
            self.time_window = window
            self._emit("time_window", "")

    def set_current_time(self, t: float | None) -> None:
        """Set the time slider's time (s on the layers' clock, or None); a
        ``current_time`` event (layer id ``""``) when it changed. Raises ValueError for a
        time that is not a finite number."""
        t = check_current_time(t)
        if t != self.current_time:
            self.current_time = t
            self._emit("current_time", "")

    def set_map_view(self, view: MapView | tuple[float, float, float, float] | None) -> None:
        """Set the map's view ((x0, x1, y0, y1) in degrees, a :class:`MapView`, or None);
        a ``map_view`` event (layer id ``""``) when it changed. Raises ValueError for a
        view that is not finite or whose ranges do not increase."""
        view = MapView.of(view)
        if view != self.map_view:
            self.map_view = view
            self._emit("map_view", "")

    def set_active(self, layer_id: str | None) -> None:
        """Make ``layer_id`` (a layer of the session, or None) the active layer; an
        ``active`` event (layer id ``""``) when it changed. The selection keeps only that
        layer's tracks (the batch table shows the active layer's). Raises InputError for
        an id the session does not hold."""
        if layer_id is not None and layer_id not in self.layers:
            raise InputError(f"no layer {layer_id} to make active")
        if layer_id != self.active:
            self.active = layer_id
            self.selection = [s for s in self.selection if s[0] == layer_id]
            self._emit("active", "")

    # -- layers --------------------------------------------------------------------

    def new_id(self) -> str:
        """A layer id that no layer, layer lineage or review queue names (a layer removed,
        then the project reopened: a new layer given its id was taken for the input of the
        layers made from it, and a step run on it replaced them in place)."""
        taken = set(self.layers) | self._retired
        for lay in self.layers.values():
            taken.update(lay.inputs)
            if lay.parent is not None:
                taken.add(lay.parent)
        taken.update(
            str(d.get("queue", "")).split("@")[0] for d in self.decisions if isinstance(d, dict)
        )
        while True:
            lid = f"L{next(self._ids)}"
            if lid not in taken:
                return lid

    def add_layer(
        self,
        name: str,
        kind: str,
        points: pd.DataFrame,
        meta: dict | None = None,
        *,
        color: str | None = None,
        visible: bool = True,
        layer_id: str | None = None,
        **lineage: Any,
    ) -> Layer:
        """Add a layer (``lineage``: parent, step, role, params, created, tables)."""
        if color is None:
            color = KIND_COLORS.get(kind, PALETTE[len(self.layers) % len(PALETTE)])
        lid = layer_id or self.new_id()
        if lid in self.layers:
            raise InputError(f"layer id {lid} is taken")
        lineage.setdefault("created", _now())
        layer = Layer(lid, name, kind, points, visible, color, dict(meta or {}), **lineage)
        self.layers[lid] = layer
        self._emit("added", lid)
        return layer

    def remove_layer(self, layer_id: str) -> "LayerRemoval | None":
        """Remove a layer. A layer under review made from it keeps what its review reads
        (:func:`~wakeline.core.review_session.keep_inputs`: the input's points as a side
        table, with a ``tables`` event for the project to write them) before the
        ``removed`` event: its decisions bind in this window and after a reopen alike.
        Returns what :meth:`restore_layer` needs to undo it (None: no such layer). The
        review decisions on its queues stay in :attr:`decisions` (and the project)."""
        if layer_id not in self.layers:
            return None
        from wakeline.core.review_session import keep_inputs

        layer = self.layers[layer_id]
        before = {
            lay.id: (lay.meta, lay.tables) for lay in self.layers.values() if lay.id != layer_id
        }
        removal = LayerRemoval(
            layer=layer,
            pos=list(self.layers).index(layer_id),
            active=self.active == layer_id,
            selection=[s for s in self.selection if s[0] == layer_id],
            generation=self.generation,
        )
        for kept in keep_inputs(self, layer_id):
            removal.kept.append((kept.id, *before[kept.id], kept.meta, kept.tables))
            self._emit("tables", kept.id)
        self._drop(layer_id)
        self._retired.add(layer_id)
        return removal

    def restore_layer(self, removal: "LayerRemoval") -> Layer:
        """Undo a :meth:`remove_layer`: the same layer (its id, points, lineage, side
        tables) back in its place among the others, ``added`` then ``reordered`` events
        (the project writes it at once); the layers under review that kept its points
        for it get their tables and meta of before (a ``tables`` event each) where
        nothing changed them since; its decisions were never removed. Raises InputError
        when the session was cleared since (another project) or the id is taken."""
        layer = removal.layer
        if removal.generation != self.generation:
            raise InputError(f"layer {layer.name} belongs to work closed since")
        if layer.id in self.layers:
            raise InputError(f"layer id {layer.id} is taken")
        if layer.step is not None:
            # the same step run again on the same input since: beside it, two layers of
            # one name, and a re-run would replace the older one only (:meth:`_replaced`)
            since = self._replaced(layer.parent, layer.step, layer.role, layer.inputs)
            if since is not None:
                raise InputError(
                    f"layer {layer.name}: {layer.step} was made again on its input since "
                    f"({since.name}); remove that layer to restore this one"
                )
        self._retired.discard(layer.id)
        self.layers[layer.id] = layer
        self._emit("added", layer.id)
        order = [i for i in self.layers if i != layer.id]
        order.insert(min(removal.pos, len(order)), layer.id)
        if order != list(self.layers):
            self.reorder(order)
        for lid, meta, tables, meta_after, tables_after in removal.kept:
            lay = self.layers.get(lid)
            if lay is not None and lay.meta is meta_after and lay.tables is tables_after:
                lay.meta, lay.tables = meta, tables
                self._emit("tables", lid)
        self.selection += [s for s in removal.selection if s not in self.selection]
        if removal.active:
            self.set_active(layer.id)
        return layer

    def _drop(self, layer_id: str) -> None:
        if self.layers.pop(layer_id, None) is not None:
            self.selection = [s for s in self.selection if s[0] != layer_id]
            self._emit("removed", layer_id)
            if self.active == layer_id:
                self.set_active(None)

    def set_color(self, layer_id: str, color: str, chosen: bool = True) -> tuple[str, bool]:
        """Draw layer ``layer_id`` in ``color`` (``#rrggbb``), chosen by the operator
        (``chosen``: kept as it is when the project is opened again, even where another
        layer has it; ``meta["color_chosen"]``). Returns the colour and choice it had,
        which undo it (``set_color(layer_id, *old)``). A ``color`` event follows (the
        project writes the layer's row at once)."""
        layer = self.layers.get(layer_id)
        if layer is None:
            raise InputError(f"no layer {layer_id}")
        color = check_color(color)
        old = (layer.color, bool(layer.meta.get(COLOR_CHOSEN, False)))
        if old == (color, bool(chosen)):
            return old
        layer.color = color
        meta = dict(layer.meta)
        if chosen:
            meta[COLOR_CHOSEN] = True
        else:
            meta.pop(COLOR_CHOSEN, None)
        layer.meta = meta
        self._emit("color", layer_id)
        return old

    def move_layer(self, layer_id: str, pos: int) -> int:
        """Put layer ``layer_id`` at place ``pos`` of the layer order (clipped to it), the
        others kept in their order; returns its place before (``move_layer(layer_id,
        old)`` undoes it). A ``reordered`` event follows when it moved (the project writes
        the order at once; the map draws a layer over those before it)."""
        if layer_id not in self.layers:
            raise InputError(f"no layer {layer_id}")
        order = list(self.layers)
        old = order.index(layer_id)
        order.remove(layer_id)
        order.insert(max(0, min(int(pos), len(order))), layer_id)
        if order != list(self.layers):
            self.reorder(order)
        return old

    def set_visible(self, layer_id: str, visible: bool) -> None:
        layer = self.layers[layer_id]
        if layer.visible != visible:
            layer.visible = visible
            self._emit("visibility", layer_id)

    def put_bearings(
        self,
        name: str,
        bearings: pd.DataFrame,
        detections: pd.DataFrame,
        meta: dict,
        *,
        layer_id: str | None = None,
    ) -> Layer:
        """Add a bearing layer (:data:`BEARING_KIND`), or replace in place (same id,
        ``changed``) the one read from the same file (``meta["file"]``): a bearing file
        opened again is a re-run of the detector, not a second layer. ``layer_id``: the id
        to give a new layer (a window prepares its view under it first)."""
        old = self.bearing_layer(meta.get("file"))
        tables = {"detections": detections}
        if old is None:
            return self.add_layer(
                name,
                BEARING_KIND,
                bearings,
                meta,
                color=BEARING_COLOR,
                layer_id=layer_id,
                tables=tables,
            )
        old.points, old.tables, old.meta, old.created = bearings, tables, dict(meta), _now()
        old.run = _run_id()
        self._emit("changed", old.id)
        return old

    def bearing_layer(self, file: str | None) -> Layer | None:
        """The bearing layer read from ``file`` (as ``meta["file"]`` says), if any."""
        if file is None:
            return None
        return next(
            (
                lay
                for lay in self.layers.values()
                if lay.kind == BEARING_KIND and lay.meta.get("file") == file
            ),
            None,
        )

    def get(self, layer_id: str | None) -> Layer | None:
        return self.layers.get(layer_id) if layer_id else None

    def ancestors(self, layer_id: str) -> list[str]:
        """The layers ``layer_id`` was made from, nearest first (empty for a source)."""
        out, up = [], self.layers[layer_id].parent
        while up in self.layers and up not in out and up != layer_id:
            out.append(up)
            up = self.layers[up].parent
        return out

    def step_input(self, layer_id: str) -> str:
        """The layer a step asked for on ``layer_id`` reads: a maneuvers layer is its
        parent's points with the maneuver factor added, so a step on it runs on the parent
        (Compress after Maneuvers would otherwise find the same maneuvers again, as a
        child of the first)."""
        layer = self.layers[layer_id]
        if layer.role == "maneuvers" and layer.parent in self.layers:
            return layer.parent
        return layer_id

    def sources_of(self, layer_id: str) -> set[str]:
        """The imported layers whose points ``layer_id`` holds (several for a fused layer:
        every input's)."""
        layer, out, todo, seen = None, set(), [layer_id], set()
        while todo:
            lid = todo.pop()
            if lid in seen or lid not in self.layers:
                continue
            seen.add(lid)
            layer = self.layers[lid]
            up = [i for i in (layer.inputs or [layer.parent]) if i in self.layers]
            if up:
                todo.extend(up)
            else:
                out.add(lid)
        return out

    def root(self, layer_id: str) -> Layer:
        """The imported layer a result descends from (itself for a source)."""
        up = self.ancestors(layer_id)
        return self.layers[up[-1] if up else layer_id]

    def children(self, layer_id: str) -> list[Layer]:
        return [lay for lay in self.layers.values() if lay.parent == layer_id]

    def find(self, parent: str, step: str | None = None, role: str | None = None) -> Layer | None:
        """The result of ``step`` (role ``role``) made from layer ``parent``, if any."""
        for lay in self.layers.values():
            if (
                lay.parent == parent
                and (step is None or lay.step == step)
                and (role is None or lay.role == role)
            ):
                return lay
        return None

    def related(self, layer_id: str, role: str) -> Layer | None:
        """The layer of ``role`` nearest in lineage: itself, a sibling, a child or a
        descendant of its ancestors (the maneuver layer that goes with a compressed one)."""
        layer = self.layers[layer_id]
        if layer.role == role or layer.kind == role:
            return layer
        if layer.parent is not None:
            sib = self.find(layer.parent, layer.step, role)
            if sib is not None:
                return sib
        return self.find(layer_id, None, role)

    # -- running steps ------------------------------------------------------------

    def run_step(
        self,
        layer_ids: str | list[str],
        step: str,
        params: dict | None = None,
        progress: Progress | None = None,
        points: pd.DataFrame | None = None,
    ) -> StepResult:
        """Run a registered step on one layer (or several, concatenated; ``points``: the
        input as the caller combined it, a fuse across layers); pure: nothing changes
        until :meth:`apply_result`. Safe to call from a worker thread.

        A re-run of a reviewed step (Associate, Fuse) on the same input(s) keeps the
        review: pairs rejected or split in an earlier review stay out of the proposals,
        and what the layer it replaces was decided is carried over
        (:func:`~wakeline.core.review_session.carry_over`, the result's ``carry``;
        :meth:`apply_result` stores it as the new queue's first decisions). Several
        layers given in another order than a layer already made from them: in its order
        (:meth:`rerun_inputs`), so the run replaces it."""
        from wakeline.core.review_session import REVIEWED_STEPS

        ids = [layer_ids] if isinstance(layer_ids, str) else list(layer_ids)
        if step in REVIEWED_STEPS:
            ids = self.rerun_inputs(ids, step)
        if points is None:
            points = self.input_points(ids)
        if step not in REVIEWED_STEPS:
            result = STEPS[step](points, params, progress)
            if step == "clean" and len(ids) == 1:
                result = self._restore_again(ids[0], result)
            return result
        return self._run_reviewed(
            ids[0], ids if len(ids) > 1 else [], step, points, params, progress
        )

    def _run_reviewed(
        self,
        parent: str,
        inputs: list[str],
        step: str,
        points: pd.DataFrame,
        params: dict | None,
        progress: Progress | None,
    ) -> StepResult:
        """Run reviewed ``step`` on ``points`` (the points of ``parent``, or of ``inputs``
        combined) as a re-run keeps the review: the pairs rejected or split under
        ``parent`` kept out, and the carry of the layer it replaces (:meth:`run_step`,
        and a pipeline's stage: :meth:`run_pipeline`)."""
        from wakeline.core import review as R
        from wakeline.core.review_session import Carry, carry_over, queue_key

        rows = list(self.decisions)  # a copy: the window may append while a worker reads
        rejected, split = self.kept_out_below(parent, step, inputs)
        kept = (frozenset(rejected), frozenset(split))
        split = split - rejected
        full = {**STEPS[step].defaults(), **(params or {})}
        run = STEPS[step].run
        result = run(points, full, progress or null_progress, rejected, split=split)
        for new in result.layers:
            old = self._replaced(parent, step, new.suffix, inputs)
            if old is None:
                continue
            # A re-run: what it read is recorded, so that decisions made on the old
            # layer while it ran are carried too (apply_result), or found to change the
            # pairs kept out (stale).
            props = new.tables.get("proposals")
            tracks = R.track_table(points) if props is not None and len(props) else None
            if _reviewed(old, rows):
                carry = carry_over(
                    old, rows, points, props, len(rejected), len(split), tracks=tracks
                )
            else:
                carry = Carry(old.id, queue_key(old), 0, reviewed=False)
            carry.kept, carry.parent, carry.inputs = kept, parent, list(inputs)
            carry.step, carry.tracks = step, tracks
            return dataclasses.replace(result, carry=carry)
        return result

    def run_pipeline(
        self, layer_id: str, pipe: Pipeline, progress: Progress | None = None
    ) -> StepResult:
        """Run ``pipe`` on layer ``layer_id`` as :meth:`apply_result` will apply it, each
        stage a child of the previous stage's output; a reviewed stage (Associate) whose
        layer replaces a reviewed one keeps its review as :meth:`run_step` does (rejected
        and split pairs kept out, the rest carried). Pure, like :meth:`run_step`."""
        from wakeline.core.pipeline import StageChain
        from wakeline.core.review_session import REVIEWED_STEPS

        # each stage's parent (a layer id; None: a new layer), as Pipeline.run chains them
        parents = StageChain(layer_id)

        def stage(name: str, params: dict, points: pd.DataFrame, sub: Progress) -> StepResult:
            under = parents.input(name)
            if name in REVIEWED_STEPS and under is not None:
                res = self._run_reviewed(under, [], name, points, params, sub)
            else:
                res = STEPS[name](points, params, sub)
            primary = STEPS[name].primary
            out = under
            if any(new.suffix == primary for new in res.layers):
                old = self._replaced(under, name, primary, []) if under is not None else None
                out = old.id if old is not None else None
            parents.done(name, out)
            return res

        return pipe.run(self.input_points([layer_id]), progress, stage)

    def _restore_again(self, parent: str, result: StepResult) -> StepResult:
        """A re-run of Clean on ``parent`` whose cleaned layer had points put back
        (:attr:`Layer.restored`): those its new reject trail holds are put back again
        (here, in the worker); the ids go in the new layer's meta as ``restored``, which
        :meth:`apply_result` moves to the lineage."""
        old = self._replaced(parent, "clean", "cleaned", [])
        if old is None or not old.restored:
            return result
        from wakeline.core.clean import restore
        from wakeline.core.clean_restore import REJECTED, chosen_ids, restored_counts

        layers = []
        for new in result.layers:
            rejected = new.tables.get(REJECTED)
            if new.suffix != "cleaned" or rejected is None:
                layers.append(new)
                continue
            ids = chosen_ids(rejected, ids=old.restored)
            if len(ids):
                back = rejected[rejected["wl_id"].isin(ids).to_numpy()]
                points, rejected = restore(new.points, rejected, ids)
                meta = restored_counts(new.meta, len(rejected), back, -1)
                meta["restored"] = [int(i) for i in ids]
                new = dataclasses.replace(
                    new, points=points, meta=meta, tables={**new.tables, REJECTED: rejected}
                )
            layers.append(new)
        return dataclasses.replace(result, layers=layers)

    def rerun_inputs(self, ids: list[str], step: str = "fuse") -> list[str]:
        """``ids`` (several layers a step runs across) in the order of the layer of
        ``step`` already made from the same layers, whichever order they were selected
        in: a run of Fuse on them again replaces that layer and keeps its review (the
        fused points, pairs and proposals do not depend on the order, the points being
        sorted by sensor and track first); as given when there is none."""
        ids = list(ids)
        if len(ids) < 2:
            return ids
        want = sorted(ids)
        for lay in list(self.layers.values()):
            if lay.step == step and sorted(lay.inputs) == want:
                return list(lay.inputs)
        return ids

    def _replaced(self, parent: str, step: str, role: str, inputs: list[str]) -> Layer | None:
        """The layer a result of ``step`` (role ``role``) on ``parent`` (and ``inputs``)
        replaces in place (:meth:`apply_result`), if any. Read by :meth:`run_step` in a
        worker while the window may add or remove layers: over a copy of the layers."""
        return next(
            (
                lay
                for lay in list(self.layers.values())
                if lay.parent == parent
                and lay.step == step
                and lay.role == role
                and lay.inputs == inputs
            ),
            None,
        )

    def kept_out_below(
        self, layer_id: str, step: str = "associate", inputs: list[str] | None = None
    ) -> tuple[set, set]:
        """``(rejected, split)``: the pairs of track labels a re-run of Associate on
        ``layer_id`` keeps out, from the review of each associate layer made from it, in
        one pass over the decision log (``step``, ``inputs``: those of another reviewed
        step, a fuse across ``inputs``). Rejected: in any run's queue of the layer, undos
        taken into account. Split: in its current queue (through its proposals), and
        those an earlier run kept out (the layer's ``split_kept_out``, so they stay out
        run after run)."""
        from wakeline.core.review_session import queue_key
        from wakeline.core.review_store import kept_out_pairs

        rows = list(self.decisions)  # a copy: the window may append while a worker reads
        below = [
            lay
            for lay in list(self.layers.values())
            if lay.parent == layer_id and lay.step == step and _same_inputs(lay, inputs)
        ]
        queues = [(lay.id, queue_key(lay), lay.tables.get("proposals")) for lay in below]
        rejected, split = kept_out_pairs(rows, queues)
        for lay in below:
            split |= {(str(a), str(b)) for a, b in lay.meta.get("split_kept_out", [])}
        return rejected, split

    def split_pairs_below(
        self, layer_id: str, step: str = "associate", inputs: list[str] | None = None
    ) -> set[tuple[str, str]]:
        """The split pairs of :meth:`kept_out_below`."""
        return self.kept_out_below(layer_id, step, inputs)[1]

    def rejected_pairs_below(
        self, layer_id: str, step: str = "associate", inputs: list[str] | None = None
    ) -> set[tuple[str, str]]:
        """The rejected pairs of :meth:`kept_out_below`."""
        return self.kept_out_below(layer_id, step, inputs)[0]

    def input_points(self, layer_ids: list[str]) -> pd.DataFrame:
        """The points of the given layers, concatenated. Raises :class:`InputError` when
        one was removed (by the operator, while a step waited to read it)."""
        gone = [i for i in layer_ids if i not in self.layers]
        if gone:
            raise InputError("the input layer was removed before the step read it; nothing changed")
        frames = [self.layers[i].points for i in layer_ids]
        if len(frames) == 1:
            return frames[0]
        return pd.concat(frames, ignore_index=True)

    def apply_result(
        self,
        input_id: str,
        result: StepResult,
        params: dict | None = None,
        inputs: list[str] | None = None,
    ) -> list[Layer]:
        """Add a step's layers as children of ``input_id``; a re-run of the same step on
        the same input replaces (in place, same id) the layer of the same role. A pipeline
        result is applied stage by stage, each stage a child of the previous output.
        ``inputs``: every input layer of a step run on several layers concatenated
        (``input_id`` is the first); recorded in the lineage and in the layer's name.

        A re-run of a reviewed step is reconciled with the decisions present now, not
        those its worker read: decisions made on the layer it replaces while it ran are
        carried as the ones made before (:meth:`Carry.refresh
        <wakeline.core.review_session.Carry.refresh>`). When they change the pairs the
        run kept out (:meth:`stale`), nothing is applied and :class:`StaleResult` is
        raised: the step must run again."""
        if self.stale(result):
            raise StaleResult(
                f"decisions made while {result.step} ran change the pairs it keeps out; "
                f"run {result.step} again"
            )
        if result.stages:
            from wakeline.core.pipeline import StageChain

            out: list[Layer] = []
            chain = StageChain(input_id)  # each stage's parent, as Pipeline.run chains them
            for stage in result.stages:
                current = chain.input(stage.step)
                made = self.apply_result(current, stage, stage.params)
                out += made
                primary = STEPS[stage.step].primary
                nxt = [lay for lay in made if lay.role == primary]
                chain.done(stage.step, nxt[0].id if nxt else current)
            return out
        base = self.root(input_id).name if input_id in self.layers else ""
        parent_name = self.layers[input_id].name if input_id in self.layers else base
        inputs = list(inputs) if inputs and len(inputs) > 1 else []
        if inputs:
            # Another order of the same layers: the layer made from them is replaced.
            inputs = self.rerun_inputs(inputs, result.step)
            input_id = inputs[0]
            # Many inputs: the first names and how many more (the lineage keeps them all).
            parent_name = joined_names(self.layers[i].name for i in inputs if i in self.layers)
        pjson = _params_json(params)
        made = []
        for new in result.layers:
            old = self._replaced(input_id, result.step, new.suffix, inputs)
            lineage = {
                "parent": input_id,
                "step": result.step,
                "role": new.suffix,
                "params": pjson,
                "created": _now(),
                "run": _run_id(),
                "tables": dict(new.tables),
                "inputs": inputs,
                # points put back from the reject trail (a re-run of Clean: _restore_again)
                "restored": list(new.meta.get("restored", [])),
            }
            meta = {k: v for k, v in new.meta.items() if k != "restored"}
            if old is not None:
                carry = self._carry(old, result, new, inputs)
                chosen = old.meta.get(COLOR_CHOSEN)  # the operator's colour: kept
                old.points, old.meta, old.kind = new.points, dict(meta), new.kind
                if chosen:
                    old.meta[COLOR_CHOSEN] = True
                for key, value in lineage.items():
                    setattr(old, key, value)
                if carry is not None:  # before "changed": a review bound on it reads them
                    from wakeline.core.review_session import carried_rows, queue_key

                    self.decisions.extend(carried_rows(carry, queue_key(old)))
                self._emit("changed", old.id)
                if carry is not None:
                    self._emit("decisions", old.id)
                made.append(old)
            else:
                name = self._step_layer_name(f"{parent_name} · {new.suffix}", result.step, input_id)
                made.append(self.add_layer(name, new.kind, new.points, meta, **lineage))
        return made

    def _reruns(self, result: StepResult) -> list[tuple[StepResult, Any, Layer, int]]:
        """``(stage, carry, old layer, late rows)`` for each stage of ``result`` (a step's
        or a pipeline's) that re-runs a reviewed step on a layer still in the session:
        the decision rows made on that layer's queue since the carry was made."""
        from wakeline.core.review_session import queue_key

        out, rows = [], list(self.decisions)  # a copy: read in a worker too (reconcile)
        for stage in result.stages or [result]:
            carry = getattr(stage, "carry", None)
            old = self.layers.get(carry.old) if carry is not None else None
            if old is None or not carry.step:
                continue
            key = queue_key(old)
            now = sum(1 for r in rows if isinstance(r, dict) and r.get("queue") == key)
            out.append((stage, carry, old, max(0, now - (carry.seen if key == carry.queue else 0))))
        return out

    def stale(self, result: StepResult) -> bool:
        """Whether ``result`` (a step's or a pipeline's) re-runs a reviewed step whose
        decisions changed, while it ran, the pairs it keeps out: a pair rejected or split
        on the layer it replaces, or a reject or split undone (:meth:`kept_out_below` now
        against what the run read). Such a result cannot be reconciled by carrying
        decisions: the step runs again. Other decisions made meanwhile are carried."""
        for _stage, carry, _old, late in self._reruns(result):
            if not late:
                continue  # nothing decided on it since the run read its decisions
            rejected, split = self.kept_out_below(carry.parent, carry.step, carry.inputs)
            if (frozenset(rejected), frozenset(split)) != carry.kept:
                return True
        return False

    def late_decisions(self, result: StepResult) -> int:
        """The decision rows made on the layers ``result`` (a step's or a pipeline's)
        re-runs since its carry was made: what :meth:`apply_result` reconciles it with
        (0: nothing made meanwhile)."""
        return sum(late for *_, late in self._reruns(result))

    def reconcile(self, result: StepResult) -> None:
        """Make the carry of ``result`` again from the decisions present now (decisions
        made on the layer it replaces while it ran), as :meth:`apply_result` would at
        the swap; safe in a worker (the window runs it there: with hundreds of carried
        decisions it takes longer than a GUI turn may). A result that is :meth:`stale`
        must run again instead."""
        rows = list(self.decisions)  # a copy: the window may append while a worker reads
        for stage, carry, old, late in self._reruns(result):
            if late:
                props = next(
                    (n.tables["proposals"] for n in stage.layers if "proposals" in n.tables),
                    None,
                )
                carry.refresh(old, rows, props)

    def _carry(self, old: Layer, result: StepResult, new, inputs: list[str]):
        """What the re-run ``result`` carries over from the review of ``old`` (the layer
        it replaces): the carry :meth:`run_step` made, made again from the decisions
        present now when some were made on ``old`` while the step ran
        (:meth:`Carry.refresh <wakeline.core.review_session.Carry.refresh>`), or, for a
        result made elsewhere, one made now; None when ``old`` was never reviewed (no
        decision row of its queues)."""
        from wakeline.core.review_session import carry_over

        rows = list(self.decisions)
        carry = getattr(result, "carry", None)
        if carry is not None and carry.old == old.id:
            carry.refresh(old, rows, new.tables.get("proposals"))
            return carry if carry.reviewed else None
        if not _reviewed(old, rows):
            return None
        try:
            points = self.input_points(inputs or [old.parent])
        except InputError:
            points = None
        props = new.tables.get("proposals")
        if points is None:
            props = None
        return carry_over(old, rows, points, props)

    def _step_layer_name(self, name: str, step: str, parent: str) -> str:
        """``name``, or with its step when another layer made from ``parent`` has that
        name: Maneuvers then Compress on one layer made two layers "FILE · maneuvers"
        (the compress step's maneuver points are "FILE · maneuvers (compress)")."""
        taken = {lay.name for lay in self.layers.values() if lay.parent == parent}
        if name not in taken:
            return name
        return f"{name} ({step})"

    def replace_points(self, layer_id: str, points: pd.DataFrame) -> None:
        """New points for a layer, lineage kept (a review decision relabels targets)."""
        self.layers[layer_id].points = points
        self._emit("changed", layer_id)

    # -- persistence helpers -------------------------------------------------------

    def layer_order(self) -> list[str]:
        return list(self.layers)

    def reorder(self, order: list[str]) -> None:
        if sorted(order) != sorted(self.layers):
            raise InputError("a layer order must name every layer once")
        self.layers = {i: self.layers[i] for i in order}
        self._emit("reordered", "")

    def clear(self) -> None:
        self.generation += 1
        self._retired.clear()
        for lid in list(self.layers):
            self._drop(lid)  # all of them: nothing to keep for another
        self.sources.clear()
        self.selection.clear()
        self.decisions.clear()
        self.set_time_window(None)
        self.set_current_time(None)
        self.set_map_view(None)
        self.set_active(None)


def _reviewed(layer: Layer, rows: list) -> bool:
    """Whether the decision log ``rows`` holds a row of any run's queue of ``layer``."""
    prefix = f"{layer.id}@"
    return any(isinstance(r, dict) and str(r.get("queue", "")).startswith(prefix) for r in rows)


def _same_inputs(layer: Layer, inputs: list[str] | None) -> bool:
    """Whether ``layer`` was made from ``inputs`` (several: a step across layers; None
    or empty: a step on its parent alone)."""
    return list(layer.inputs) == list(inputs) if inputs else not layer.inputs[1:]


def _params_json(params: dict | None) -> dict:
    if not params:
        return {}
    try:
        return params_to_json(params)
    except TypeError:  # already plain values
        return {
            k: (dataclasses.asdict(v) if dataclasses.is_dataclass(v) else v)
            for k, v in params.items()
        }

"""The review's effects outside the dock: every decision stored in the project at once,
the layer's points following the decisions (in a worker), export that honours them,
and Run ▸ Fuse selected layers.

- :class:`ProjectDecisions` is the store of a :class:`~wakeline.app.review_undo.ReviewController`:
  it applies a change to the state and queues the decision on the project's writer
  (:meth:`ProjectStore.add_decision`: one row, its own transaction), and keeps it in the
  session so "Save as" writes it too.
- :class:`ReviewSync` recomputes the layer's points once the keys rest
  (:func:`wakeline.core.review_session.decided_points`) and swaps them in.
"""

import weakref
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

from wakeline.app.worker import Cancelled, Failed, Finished, JobRunner
from wakeline.core import review as R
from wakeline.core.review_session import (
    decided_points,
    queue_key,
    relabeled,
    reviewed_points,
    snapshot,
)
from wakeline.core.review_store import decision_row
from wakeline.core.words import joined_names

TR_CONTEXT = "ReviewSync"
#: A job's result when the decisions leave the layer's points as they are.
UNCHANGED = "unchanged"


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


EXPORT_FILTERS = {
    "CSV (*.csv)": (".csv", False),
    "CSV with a byte-order mark, for spreadsheets (*.csv)": (".csv", True),
    "GeoJSON (*.geojson)": (".geojson", False),
    "GPX for OpenCPN (*.gpx)": (".gpx", False),
}


class ProjectDecisions:
    """Applies a review change and writes it to the project (through its writer)."""

    def __init__(self, w, key: str) -> None:
        self.w, self.key = w, key

    def apply(self, state: R.ReviewState, change: R.Change, how: str = "do") -> R.Change:
        """``how``: "do", "undo" or "redo" (the row's ``stack`` mark: a reopen rebuilds
        the undo stack from it, :func:`~wakeline.core.review_store.undo_history`); a
        redo is logged ``redo <action>``."""
        state.apply(change, how=how)
        row = decision_row(self.key, change, state.log[-1], stack=how)
        self.w.session.decisions.append(row)
        self.w.project.add_decision(row)
        return change


class ReviewSync(QtCore.QObject):
    """Keeps the reviewed layer's points in step with the decisions (debounced, worker)."""

    def __init__(self, dock) -> None:
        super().__init__(dock)
        self.dock, self.w = dock, dock.w
        self.runner = JobRunner(self)
        self.runner.message.connect(self._on_message)
        self.timer = QtCore.QTimer(self)
        self.timer.setSingleShot(True)
        self.timer.setInterval(300)
        self.timer.timeout.connect(self._run)
        #: queue key -> bound: the queues whose layer is to follow their decisions (one
        #: slot each: a decision in another queue within 300 ms or within a job no longer
        #: drops the first queue's, review h231)
        self._todo: dict[str, object] = {}
        self._job: int | None = None  # until its result is applied (or it failed)
        self._job_key: str | None = None  # the queue whose job that is
        #: queue key -> (the layer's points (weak), the targets per track they show): a decision
        #: that leaves the targets as they are (an accept of a pending proposal: pending
        #: counts as joined; its undo) recomputes nothing
        self._shown: dict[str, tuple] = {}
        #: jobs run and jobs skipped (the targets unchanged), for tests and benches
        self.counts = {"prepared": 0, "unchanged": 0, "relabeled": 0}

    @property
    def busy(self) -> bool:
        return self.timer.isActive() or self._job is not None or bool(self._todo)

    def forget(self, key: str) -> None:
        """A queue dropped: the targets its layer showed are no longer kept."""
        self._shown.pop(key, None)
        self._todo.pop(key, None)

    def stop(self) -> None:
        """The window is closing: nothing more is started (the runner is stopped apart)."""
        self.timer.stop()
        self._todo.clear()

    def schedule(self, bound) -> None:
        """Recompute ``bound``'s layer once no decision came for 300 ms."""
        if bound is None:
            return
        self._todo.pop(bound.key, None)
        self._todo[bound.key] = bound
        self.timer.start()

    def _run(self) -> None:
        # One job at a time (the runner cancels the one running): a newer decision of the
        # job's own queue replaces it; another queue's waits for it to end (_on_message
        # starts the timer again), so that no queue's decision is dropped (review h231:
        # queue B's key within queue A's job left A's layer without A's decision).
        while self._todo:
            if self._job is not None:
                if self._job_key not in self._todo:
                    return  # another queue's job: this one's turn comes when it ends
                bound = self._todo.pop(self._job_key)
            else:
                bound = self._todo.pop(next(iter(self._todo)))
            layer = self.w.session.layers.get(bound.lid)
            if layer is not None and queue_key(layer) == bound.key:
                self._start(bound, layer)
                if self._job is not None:
                    return  # the others wait for it (a skipped one needs none)

    def _start(self, bound, layer) -> None:
        from wakeline.app.layer_view import prepare_view, relabel_view

        snap = snapshot(bound.controller.state)
        targets = snap.target_of_track()
        key, points, cache = bound.key, bound.points, bound.cache
        shown = self._shown.get(key)
        relabels = layer.step != "fuse" and layer.role != "stitched"  # targets alone decide
        idle = self._job is None  # no earlier decision's points on their way
        if relabels and idle and shown is not None and shown[0]() is layer.points:
            if np.array_equal(shown[1], targets):
                # The points would be the layer's own again: no job, no swap.
                self.counts["unchanged"] += 1
                layer.meta["review_decisions"] = len(snap.log)
                return
        canvas_view, size_px = self.w.canvas.current_view(), self.w.canvas.plot_size_px()
        previous = self.w.views.get(bound.lid)  # its tracks' summaries are kept
        now = layer.points
        n_decisions = len(snap.log)

        def job(progress):
            progress(0.0, "applying the decisions to the layer")
            pts = None
            if relabels and previous is not None and previous.points is now:
                # the tracks' targets taken per track, the lines of the targets changed
                # made again alone (no whole view: ~0.5-1 s at a million points)
                quick = relabeled(now, snap, cache)
                if quick is not None:
                    pts, per_track = quick
                    old = previous.summary["target"].array
                    if len(old) == len(per_track) and not np.asarray(old != per_track).any():
                        return key, UNCHANGED, n_decisions, (now, targets)
                    view = relabel_view(previous, pts, per_track, layer.kind, canvas_view, size_px)
                    if view is not None:
                        return key, view, n_decisions, (view.points, targets), True
            if pts is None:
                pts = decided_points(layer, snap, points, cache)
            if pts is None:
                return key, None, 0, None
            same = relabels and list(pts.columns) == list(now.columns)
            if same and pts["target"].equals(now["target"]):
                return key, UNCHANGED, n_decisions, (now, targets)  # same points, same view
            view = prepare_view(
                pts, layer.kind, layer.color, layer.name, canvas_view, size_px, previous=previous
            )
            shown = (view.points, targets) if relabels else None
            return key, view, n_decisions, shown, False

        self._job = self.runner.run("review", job)
        self._job_key = key

    def decided_now(self, layer):
        """For File ▸ Export of ``layer``: None when its points show every decision of its
        review; else a function (for the worker) making the points as the decisions make
        them now — the layer follows them 300 ms after the last one, and an export in
        that time wrote the layer without it."""
        bound = self.dock.queues.get(queue_key(layer))
        if bound is None or bound.lid != layer.id:
            return None
        state = bound.controller.state
        current = layer.meta.get("review_decisions", 0) == len(state.log)
        if current and not (self._todo.get(bound.key) is bound or self._job is not None):
            return None
        snap, points, cache = snapshot(state), bound.points, bound.cache

        def decided():
            pts = decided_points(layer, snap, points, cache)
            return layer.points if pts is None else pts

        return decided

    def _on_message(self, msg) -> None:
        if isinstance(msg, Finished | Failed | Cancelled) and msg.job == self._job:
            self._job = self._job_key = None
            if self._todo and not self.timer.isActive():
                self.timer.start()  # a queue that waited for this job
        if isinstance(msg, Failed):
            self.w.log_message(f"{tr('Error')} (review): {msg.message}")
        if not isinstance(msg, Finished):
            return
        key, view, n_decisions, shown, *part = msg.result
        lid = key.split("@", 1)[0]
        layer = self.w.session.layers.get(lid)
        if view is None or layer is None or queue_key(layer) != key:
            return
        if view is UNCHANGED:
            if shown is not None and layer.points is shown[0]:
                self.counts["unchanged"] += 1
                layer.meta["review_decisions"] = n_decisions
                self._shown[key] = (weakref.ref(shown[0]), shown[1])
                return
            self.schedule(self.dock.queues.get(key))  # the layer changed meanwhile
            return
        self.counts["prepared"] += 1
        if part and part[0]:
            self.counts["relabeled"] += 1  # its lines made again alone (relabel_view)
        layer.meta["review_decisions"] = n_decisions  # the points show this many
        # The swap goes over several turns (the layer, its level of detail, the time
        # index, the proposal drawn again): the map paints once at its end, not at each.
        self.dock.hold_map()
        self.w._pending_views = {(layer.step, layer.role): view}
        if lid == self.w.active:  # the batch table is rebuilt: keep its selection
            self.w._restore_selection = self.w.selected_keys() or None
        try:
            self.w.session.replace_points(lid, view.points)
        finally:
            self.w._pending_views = {}
        if shown is not None and layer.points is shown[0]:
            self._shown[key] = (weakref.ref(shown[0]), shown[1])

    # -- export ---------------------------------------------------------------------

    def unreviewed_note(self, layer) -> str:
        """For an export of ``layer``: "N of M proposals not reviewed: counted as
        accepted" while its review (bound in the dock) has pending proposals, else ""."""
        bound = self.dock.queues.get(queue_key(layer)) if layer is not None else None
        if bound is None or bound.lid != layer.id:
            return ""
        status = bound.controller.state.status
        pending, total = int((status == "pending").sum()), len(status)
        if not pending:
            return ""
        return tr("{0} of {1} proposals not reviewed: counted as accepted").format(
            f"{pending:,}", f"{total:,}"
        )

    def export(self, path: Path, bom: bool = False, log: bool = False) -> int | None:
        """Write the active review's tracks (or its decision log) in the window's worker."""
        bound = self.dock.bound
        if bound is None:
            self.w.tell(tr("Nothing to export"), tr("No layer under review."), "information")
            return None
        layer = self.w.session.layers[bound.lid]
        snap, points, cache = snapshot(bound.controller.state), bound.points, bound.cache
        path = Path(path)
        note = "" if log else self.unreviewed_note(layer)
        what = tr("{0}: decision log").format(layer.name)
        written = self.written_text(layer)

        def write(target):
            if log:
                from wakeline.core.export_review import export_decision_log

                export_decision_log(snap, target, bom=bom)
                return ("export", what, path, [], [])
            from wakeline.core.export_review import export_tracks

            out = reviewed_points(layer, snap, points, target, cache)
            export_tracks(out, target, bom=bom)
            text = written.replace("\x00", f"{len(out):,}")
            return ("export", text, path, [], [note] if note else [])

        return self.w._start_export(path, write, ("export", layer.name))

    def written_text(self, layer) -> str:
        """The export's log words for the reviewed tracks of ``layer``: how many points
        (``\x00``, filled in when written) of which layer, and the layer the step read
        (operator test 7, D5: an associate of the compressed layer wrote 55 of the 491
        cleaned points and the log said only "reviewed tracks"). "N points of L (reviewed
        tracks, from the cleaned layer)"; of a compressed layer, also how many points
        the cleaned layer it was made from holds."""
        from wakeline.app.layer_names import _words, shown_name

        layers = self.w.session.layers
        parent = layers.get(layer.parent) if layer.parent else None
        text = tr("{0} points of {1} (reviewed tracks)").format("\x00", shown_name(layer.name))
        if parent is None or layer.inputs:  # a fused layer: made from several (its name)
            return text
        role = parent.role or ""
        word = _words().get(role) or shown_name(parent.name)
        text = tr("{0} points of {1} (reviewed tracks, from the {2} layer)").format(
            "\x00", shown_name(layer.name), word
        )
        above = layers.get(parent.parent) if parent.parent else None
        if role == "compressed" and above is not None:
            text += tr(": the {0} layer holds {1} points").format(
                _words().get(above.role or "") or shown_name(above.name), f"{len(above.points):,}"
            )
        return text

    def export_dialog(self) -> None:
        path, chosen = QtWidgets.QFileDialog.getSaveFileName(
            self.w, tr("Export reviewed tracks"), "reviewed.csv", ";;".join(EXPORT_FILTERS)
        )
        if path:
            suffix, bom = EXPORT_FILTERS.get(chosen, (".csv", False))
            p = Path(path)
            self.export(p if p.suffix else p.with_suffix(suffix), bom=bom)

    def export_log_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self.w, tr("Export decision log"), "decisions.csv", "CSV (*.csv)"
        )
        if path:
            self.export(Path(path), bom=True, log=True)


def fuse_partners(w, lid: str) -> list[str]:
    """The loaded track layers ``lid`` could be fused with: those of other files (no
    source layer shared, no layer made from several), in the Layers list's order."""
    from wakeline.core.session import BEARING_KIND

    mine = w.session.sources_of(lid)
    out = []
    for r in range(w.layer_list.count()):
        other = w.layer_list.item(r).data(QtCore.Qt.ItemDataRole.UserRole)
        layer = w.session.layers.get(other)
        if layer is None or other == lid or layer.kind == BEARING_KIND or layer.inputs:
            continue
        if not (w.session.sources_of(other) & mine):
            out.append(other)
    return out


def fuse_active(w) -> int | None:
    """Run ▸ Fuse on one layer (operator test 6, D-gui-4): the fuse step on the active
    layer when it holds two sensors or more; when it holds one, the offer to fuse it with
    another loaded file's layer (Run ▸ Fuse selected layers on the two), or, with none
    loaded or the offer declined, the way to fuse files (select two or more layers)."""
    from wakeline.app.layer_names import shown_name
    from wakeline.core.session import BEARING_KIND

    layer = w.active_layer()
    if layer is None or layer.kind == BEARING_KIND or "sensor" not in layer.points.columns:
        return w.run_step("fuse")
    sensors = [str(s) for s in layer.points["sensor"].unique()]
    if len(sensors) >= 2:
        return w.run_step("fuse")
    title = tr("Fuse")
    one = tr("Fuse needs tracks of two sensors or more: {0} holds only {1}.").format(
        shown_name(layer.name), ", ".join(sensors) or "—"
    )
    how = tr(
        "To fuse files (e.g. radar and AIS), select two or more layers in the Layers list "
        "(Ctrl+click) and choose Run ▸ Fuse selected layers."
    )
    partners = fuse_partners(w, layer.id)
    if partners:
        names = [shown_name(w.session.layers[i].name) for i in partners]
        if len(partners) == 1:
            answer = QtWidgets.QMessageBox.question(
                w, title, one + "\n\n" + tr("Fuse it with {0}?").format(names[0])
            )
            if answer == QtWidgets.QMessageBox.StandardButton.Yes:
                return fuse_selected(w, [layer.id, partners[0]])
        else:
            name, ok = QtWidgets.QInputDialog.getItem(
                w, title, one + "\n\n" + tr("Fuse it with:"), names, 0, False
            )
            if ok and name in names:
                return fuse_selected(w, [layer.id, partners[names.index(name)]])
        w.log_message(f"{one} {how}")
        return None
    QtWidgets.QMessageBox.information(w, title, one + "\n\n" + how)
    return None


def fuse_selected(w, ids: list[str] | None = None) -> int | None:
    """Run ▸ Fuse selected layers: the registry's fuse step on the selected layers'
    points combined (:func:`wakeline.core.review.combine_sources`, named by file stem as
    the command line names its files), in the worker; the result's lineage lists every
    input layer."""
    from wakeline.app.jobs import _prepared
    from wakeline.app.layer_names import shown_name
    from wakeline.core.progress import sub_progress

    if ids is None:
        rows = sorted(w.layer_list.row(i) for i in w.layer_list.selectedItems())
        ids = [w.layer_list.item(r).data(QtCore.Qt.ItemDataRole.UserRole) for r in rows]
    ids = [i for i in ids if i in w.session.layers]
    if len(ids) < 2:
        QtWidgets.QMessageBox.information(
            w,
            tr("Fuse selected layers"),
            tr("Select two or more layers in the Layers list (Ctrl+click), e.g. radar and AIS."),
        )
        return None
    layers = w.session.layers
    seen: dict[str, str] = {}  # source layer -> the first selected layer made from it
    for i in ids:  # two layers from one file (one made from the other, or two results)
        shared = w.session.sources_of(i) & set(seen)
        if shared:
            src = min(shared)
            QtWidgets.QMessageBox.information(
                w,
                tr("Fuse selected layers"),
                tr("{0} and {1} both come from {2}: fusing them would count its points "
                   "twice. Select one of them (Ctrl+click to unselect).").format(
                    layers[seen[src]].name, layers[i].name, layers[src].name
                ),
            )  # fmt: skip
            return None
        seen.update(dict.fromkeys(w.session.sources_of(i), i))
    files = [w.session.root(i).meta.get("file") for i in ids]
    for k, i in enumerate(ids):  # one file opened twice: two layers of the same points
        twin = next((j for j, f in zip(ids[:k], files, strict=False) if f and f == files[k]), None)
        if twin is not None:
            QtWidgets.QMessageBox.information(
                w,
                tr("Fuse selected layers"),
                tr("{0} and {1} both come from {2}: fusing them would count its points "
                   "twice. Select one of them (Ctrl+click to unselect).").format(
                    layers[twin].name, layers[i].name, files[k]
                ),
            )  # fmt: skip
            return None
    from wakeline.core.review_session import fuse_names

    # The same layers selected in another order: the order of the layer made from them
    # (the fused result does not depend on it), so the run replaces it, review kept.
    ids = w.session.rerun_inputs(ids, "fuse")
    named = list(zip(fuse_names(w.session, ids), [layers[i].points for i in ids], strict=True))
    params = w.step_params("fuse")
    canvas_view, size_px = w.canvas.current_view(), w.canvas.plot_size_px()
    rerun = {
        i
        for i, lay in w.session.layers.items()
        if lay.parent == ids[0] and lay.step == "fuse" and lay.inputs == ids
    }
    in_use = w.colors_in_use(exclude=rerun)

    session = w.session

    def job(progress):
        points = R.combine_sources(named)
        # Through the session: a re-run keeps the review of the layer it replaces.
        result = session.run_step(ids, "fuse", params, sub_progress(progress, 0.0, 0.85), points)
        prepared, views = _prepared(
            result, sub_progress(progress, 0.85, 1.0), canvas_view, size_px, in_use
        )
        return ("fuse_layers", ids, prepared, views, params)

    renamed = [
        tr("{0}: {1} → {2}").format(shown_name(layers[i].name), *new)
        for i, new in zip(ids, R.sensor_renames(named), strict=True)
        if new is not None
    ]
    if renamed:  # one name per sensor between the source layers and the fused one
        w.log_message(
            tr("Sensors of one name in several files fuse as the files' names: {0}").format(
                "; ".join(renamed)
            )
        )
    names = joined_names(n for n, _ in named)
    return w._start("fuse", job, ("fuse", names))


def apply_fused(w, ids: list[str], result, views: dict, params) -> None:
    """Add a fuse-across-layers result (GUI thread: a swap of prepared data)."""
    from wakeline.app.dialogs import step_lines

    missing = [i for i in ids if i not in w.session.layers]
    if missing:
        w.log_message(tr("an input layer was removed; result dropped"))
        return
    w._pending_views = {key: view for key, (view, _color) in views.items()}
    try:
        w.session.apply_result(ids[0], result, params, inputs=ids)
    finally:
        w._pending_views = {}
    from wakeline.app.core_text import shown
    from wakeline.app.layer_names import shown_name

    names = " + ".join(shown_name(w.session.layers[i].name) for i in ids)
    w.log_lines(tr("{0} on {1}").format(shown("fuse"), names), step_lines(result))

"""Export and project jobs of the window: writing layers, saving and opening projects.

Mixed into :class:`~wakeline.app.jobs.JobsMixin`; reading a project and preparing its
layers for drawing run in the worker, the GUI thread only swaps the result in.
"""

from pathlib import Path

import numpy as np
from PySide6 import QtWidgets

from wakeline.app.core_text import shown
from wakeline.app.layer_view import plan_view, points_sketch, prepare_view_apart
from wakeline.core.errors import InputError
from wakeline.core.project import Project, load_project
from wakeline.core.session import BEARING_KIND, COLOR_CHOSEN, Layer


def _aspect_latitude(layer: Layer) -> float | None:
    """The mean latitude (degrees) of a layer's points (a bearing layer's: the
    observer's), None when it has none."""
    column = "obs_lat" if layer.kind == BEARING_KIND else "lat"
    if column not in layer.points.columns or not len(layer.points):
        return None
    lat = layer.points[column].to_numpy(dtype="float64")
    return float(np.nanmean(lat)) if np.isfinite(lat).any() else None


class ProjectJobsMixin:
    """Export ▸ …, File ▸ Save project and File ▸ Open project."""

    #: The translation context of ``self.tr`` here: PySide looks a text up along
    #: ``type(self).__mro__``, which starts at the window (``MainWindow``).
    TR_CONTEXT = "MainWindow"

    def export_dialog(self, kind: str) -> None:
        layer = self.active_layer()
        if layer is None:
            return
        if layer.kind == BEARING_KIND:  # no tracks; its detections: the dock's Export
            text = self.tr(
                "A bearing layer has no tracks to export: Export detections… in the "
                "Bearing-only dock writes its detections."
            )
            self.tell(self.tr("Export"), text, "information")
            return
        if kind == "as_came_in":
            self.export_as_came_in()
            return
        filt = "GeoJSON (*.geojson)" if kind == "geojson" else "CSV (*.csv)"
        suffix = ".geojson" if kind == "geojson" else ".csv"
        # a layer named after its folder ("radar/tracks.csv") suggests one file name
        name = layer.name.replace(" · ", "_").replace("/", "_") + suffix
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, self.tr("Export"), name, filt)
        if path:
            self.export(kind, Path(path))

    def _text_path_ok(self, path: Path) -> bool:
        """CSV text only under a name that says so (the rule ``wakeline export`` keeps,
        :func:`~wakeline.core.export.check_text_path`); else a warning, and False."""
        from wakeline.core.export import check_text_path

        try:
            check_text_path(path)
        except InputError as exc:
            self.tell(self.tr("Export failed"), str(exc))
            self.log_message(f"{self.tr('Error')}: {exc}")
            return False
        return True

    def _whole_layer_note(self, layer: Layer) -> str:
        """With the time window on, the export's log line says the whole layer is written
        (the window chooses what the map, the batch table and the figures show; a file
        holds the layer, as the command line writes it)."""
        panel = getattr(self, "time_panel", None)
        if panel is None or panel.time_window() is None:
            return ""
        return self.tr(
            "the whole layer is written ({0} points): the time window applies to the map, "
            "the batch table and the figures, not to exports"
        ).format(f"{len(layer.points):,}")

    def export(self, kind: str, path: Path) -> int | None:
        """Write the active layer (or its maneuver points) to ``path`` in the worker."""
        from wakeline.app.cli_steps import write_table
        from wakeline.core.export import export_csv, export_geojson

        layer = self.active_layer()
        if layer is None:
            return None
        if kind in ("csv", "maneuvers") and not self._text_path_ok(path):
            return None
        view = self.views[layer.id]
        man = self.session.related(layer.id, "maneuvers")
        table = man.tables.get("maneuvers") if man is not None else None
        if kind == "maneuvers" and table is None:
            text = self.tr("this layer has no maneuver points: run Maneuvers or Compress")
            self.tell(self.tr("Export failed"), text)
            return None
        points, decided = layer.points, self.review.sync.decided_now(layer)
        note = self._whole_layer_note(layer)
        pending = self.review.sync.unreviewed_note(layer)  # joined as the engine proposed

        def write(target):
            if kind == "csv":
                export_csv(decided() if decided else points, target)
            elif kind == "geojson":
                export_geojson(decided() if decided else points, target, view.maneuvers)
            else:  # the same table and writer as `wakeline maneuvers`
                write_table("maneuvers", table, target)
            return ("export", layer.name, path, [], [n for n in (pending, note) if n])

        return self._start_export(path, write, ("export", layer.name))

    def export_as_came_in(self, path: Path | None = None) -> int | None:
        """Export ▸ As it came in: the active layer in its import's layout (issue 19),
        written in the worker."""
        from wakeline.core.io.export_like import export_like, layer_layout

        layer = self.active_layer()
        if layer is None:
            return None
        try:
            layout = layer_layout(self.session.layers, layer.id)
        except InputError as exc:
            self.tell(self.tr("Export failed"), str(exc))
            self.log_message(f"{self.tr('Error')}: {exc}")
            return None
        if path is None:
            from wakeline.core.export import COMPRESSED_SUFFIXES, NOT_TEXT_SUFFIXES

            src = Path(layout.source) if layout.source else Path("tracks.csv")
            ext = src.suffix or ".csv"
            if ext.lower() in COMPRESSED_SUFFIXES + NOT_TEXT_SUFFIXES:
                ext = ".csv"  # tracks.csv.gz read: the text is written as plain text
            suggestion = f"{layer.name.replace(' · ', '_')}{ext}"
            chosen, _ = QtWidgets.QFileDialog.getSaveFileName(
                self, self.tr("Export as it came in"), suggestion, f"{layout.name} (*{ext})"
            )
            if not chosen:
                return None
            path = Path(chosen)
        if not self._text_path_ok(path):
            return None
        points, decided = layer.points, self.review.sync.decided_now(layer)
        note = self._whole_layer_note(layer)
        pending = self.review.sync.unreviewed_note(layer)  # joined as the engine proposed

        def write(target):
            # ids renumbered where two sensors' tracks would share one in a layout
            # without a sensor column (a note in the log says so)
            rep = export_like(decided() if decided else points, layout, target)
            notes = [*rep.get("notes", []), *[n for n in (pending, note) if n]]
            return ("export", layer.name, path, rep.get("warnings", []), notes)

        return self._start_export(path, write, ("export", layer.name))

    def save_project(self, path: Path) -> None:
        """Save the session to ``path`` (in the background) and keep it up to date."""
        self.view_keeper.store()  # the view as it is now, not as it was 0.4 s ago
        self.time_controller.store_time()  # and the slider's time
        # The panel's values: the session holds a project's table from when it was opened
        # (none before a first save), and Save as wrote that, not what the panel held.
        self.session.params = self.params.to_dict()
        from wakeline.app.display_zone import STATE as ZONE_STATE
        from wakeline.app.jobs import PIPELINE_STATE

        state = {PIPELINE_STATE: list(self.pipeline_stages), ZONE_STATE: self.zone_choice}
        ok, note = self.project.save_as(Path(path), state)
        if note:
            self.log_message(f"{self.tr('Warning') if ok else self.tr('Error')}: {note}")
        if not ok:
            self.tell(self.tr("Project not saved"), note)
            return
        self.update_title()  # not every text: the axes' labels relaid the map (~100 ms)

    def open_project(self, path: Path) -> int:
        """Open a project in the worker; the current session stays as it is unless the
        whole project reads well."""
        path = Path(path)
        size_px = self.canvas.plot_size_px()
        state = self._view_state(replace_all=True)
        from wakeline.app import time_text

        # The zone the worker's texts (the batch table's dates) are made in.
        zone = (time_text.display_zone(), time_text.zone_label())
        bearing_params = self.params.params("bearing")

        def job(progress):
            from wakeline.app.bearing_view import (
                bearing_layer_view,
                layer_detections,
                layer_scene,
                main_map_layers,
            )

            proj = load_project(path)
            proj.locate_sources(path)  # a project folder moved with its data files
            warnings = [*proj.warnings, *proj.source_problems()]
            # A bearing layer's scene (observer, lines, maneuvers) is made again from its
            # stored table, detections and line length.
            scenes = {lay.id: layer_scene(lay) for lay in proj.layers if lay.kind == BEARING_KIND}
            # The view the map will show (the saved one, else fitted to the visible
            # layers): each layer's level of detail is made for it here, so the map
            # strokes each layer once.
            sketches = []
            for lay in proj.layers:
                if not lay.visible:
                    continue
                if lay.kind != BEARING_KIND:
                    sketches.append(points_sketch(lay.points))
                elif scenes[lay.id] is not None:
                    sketches += [d.geometry.sketch() for d in scenes[lay.id].layers[:2]]
            lat0 = _aspect_latitude(proj.layers[0]) if proj.layers else None
            saved = proj.map_view.bounds() if proj.map_view is not None else None
            plan = plan_view(state, sketches, lat0, saved)
            shown = plan["shown"] if plan else None
            views = {}
            # Saved colours are kept unless an earlier layer has one (a project saved
            # with a radar source and the compressed layer both red).
            # An operator's colour (Layers ▸ Colour…) is kept whatever the others, and
            # so is a layer's that the operator gave another layer too (as they were
            # drawn when saved).
            chosen = {
                lay.color
                for lay in proj.layers
                if lay.meta.get(COLOR_CHOSEN) and lay.kind != BEARING_KIND
            }
            in_use: tuple[set[str], set[str]] = (set(), set())
            for k, lay in enumerate(proj.layers):
                progress(k / max(len(proj.layers), 1), f"preparing {lay.name}")
                if lay.kind == BEARING_KIND:
                    scene = scenes[lay.id]
                    parts = []
                    if scene is not None:
                        parts = main_map_layers(scene, size_px=size_px, shown=shown)
                    detections = layer_detections(lay)
                    views[lay.id] = bearing_layer_view(
                        lay.points, detections, lay.meta.get("report"), scene, parts, bearing_params
                    )
                    continue
                views[lay.id] = prepare_view_apart(
                    lay.points,
                    lay.kind,
                    in_use,
                    lay.name,
                    shown,
                    size_px,
                    first=lay.color,
                    chosen=bool(lay.meta.get(COLOR_CHOSEN)) or lay.color in chosen,
                )
                lay.points = views[lay.id].points
                lay.color = views[lay.id].colors[0] if views[lay.id].colors else lay.color
            return ("project", path, proj, views, warnings, plan, zone)

        return self._start("open project", job, ("project", path.name))

    def _apply_project(
        self,
        path: Path,
        proj: Project,
        views: dict,
        warnings: list,
        plan: dict | None = None,
        zone: tuple | None = None,
    ) -> None:
        self.project.release()  # the session's clearing is not written
        self.session.clear()
        self.views.update(views)
        problems = self.params.from_dict(proj.params)
        from wakeline.app.jobs import DEFAULT_STAGES, PIPELINE_STATE

        stages = proj.state.get(PIPELINE_STATE)  # none in a project saved before
        if not (isinstance(stages, list) and all(isinstance(x, str) for x in stages)):
            stages = DEFAULT_STAGES
        self.set_pipeline_stages(stages, store=False)
        from wakeline.app.display_zone import STATE as ZONE_STATE
        from wakeline.app.display_zone import set_zone_choice

        zone_choice = proj.state.get(ZONE_STATE)  # none in a project saved before: as it was
        if isinstance(zone_choice, str):
            # The views' dates were written in the worker in ``zone``: written again (on
            # the GUI thread: 0.3 s for a million points' 60 k tracks in 7 layers) only
            # when the project's choice shows another zone, or the zone changed since.
            from wakeline.app import time_text

            same = zone == (time_text.display_zone(), time_text.zone_label())
            set_zone_choice(self, zone_choice, store=False, force=not same)
        self._plan_view(plan)  # the view the layers' level of detail was made for
        try:
            proj.to_session(self.session)
        finally:
            self._view_planned = False
        lock_note = self.project.follow(path, proj.read_only)
        from wakeline.core.review_session import decision_counts, decisions_in_effect

        repairs = {id(row) for row in proj.repairs}
        steps, earlier = decision_counts(
            proj.layers, [d for d in proj.decisions if id(d) not in repairs]
        )
        in_effect = decisions_in_effect(proj.layers, proj.decisions)
        self.log_message(self._opened_text(path, len(proj.layers), in_effect, earlier, steps))
        if proj.repairs:
            # The migration's decisions (core.project's docstring) go into the file at
            # once, before any new one, so the stored log replays to what is shown.
            for row in proj.repairs:
                self.project.add_decision(row)
            self.log_message(f"{self.tr('Note')}: {self._repaired_text(len(proj.repairs))}")
        if not proj.decisions_checked:  # the next open skips the migration
            self.project.mark_decisions_checked()
        for note in proj.located:  # sources used from beside the moved project
            self.log_message(f"{self.tr('Note')}: {shown(note)}")
        if proj.located:  # the file keeps where they are now
            self.project.put_sources(list(self.session.sources))
            for lid in proj.relocated_layers:
                self.project.put_layer_attrs(lid)
        bearing = [lid for lid, lay in self.session.layers.items() if lay.kind == BEARING_KIND]
        if bearing and bearing[-1] in self.views:  # the dock and Detail show the last
            self.show_bearing_layer(self.views[bearing[-1]])
        # The active layer (the selection's in a project saved before it was kept) and
        # its selected tracks, once the layers are drawn (one per event-loop turn).
        active = self.session.active
        if active is not None:
            self._make_current = active
            sel = [(s, b) for lid, s, b in self.session.selection if lid == active]
            self._restore_selection = sel or None
        self.update_title()
        self._fit_after_draw = plan is None
        if proj.read_only:
            ro = self.tr("the project file is read-only: it opens read-only, changes are not saved")
            warnings = [ro, *warnings]
        elif lock_note and self.project.read_only:  # open in another window or process
            warnings = [lock_note, *warnings]
        elif lock_note:  # a stale lock (a crash) taken over: the log is enough
            self.log_message(f"{self.tr('Note')}: {lock_note}")
        for w in warnings + problems:
            self.log_message(f"{self.tr('Warning')}: {w}")
        if warnings or problems:
            self.tell(self.tr("Project opened with warnings"), "\n".join(warnings + problems))

    def _opened_text(
        self, path: Path, layers: int, decisions: int, earlier: int = 0, steps: int | None = None
    ) -> str:
        """The log line of an opened project: its file, its layers and the review
        decisions restored from it (as opening a file logs its import summary): those
        in effect (replayed on the layers' current reviews: proposals decided and manual
        links, not the log's rows), the decision log's steps when they are more (undos
        and redos), and those the decision log keeps of earlier runs or removed layers."""
        n_layers = self.tr("1 layer") if layers == 1 else self.tr("{0} layers").format(layers)
        n_decided = (
            self.tr("1 review decision restored")
            if decisions == 1
            else self.tr("{0} review decisions restored").format(f"{decisions:,}")
        )
        if earlier:
            n_decided += " " + (
                self.tr("(and 1 of an earlier run or a removed layer, kept in the decision log)")
                if earlier == 1
                else self.tr(
                    "(and {0} of earlier runs or removed layers, kept in the decision log)"
                ).format(f"{earlier:,}")
            )
        if steps is not None and steps != decisions:
            n_decided += " " + self.tr(
                "(from {0} steps of the decision log, undos and redos included)"
            ).format(f"{steps:,}")
        return self.tr("Opened project {0}: {1}, {2}").format(str(path), n_layers, n_decided)

    def _repaired_text(self, n: int) -> str:
        """The log line of the review rows the migration on open accepted."""
        if n == 1:
            return self.tr(
                "1 review row said split or rejected beside a target holding both its "
                "tracks (a join made by an older Wakeline): it is now accepted, as a "
                "join accepts such rows (stored as a 'repair' decision)"
            )
        return self.tr(
            "{0} review rows said split or rejected beside a target holding both their "
            "tracks (joins made by an older Wakeline): they are now accepted, as a join "
            "accepts such rows (stored as 'repair' decisions)"
        ).format(f"{n:,}")

    def open_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Open project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            self.open_project(Path(path))

    def save_or_say_saved(self) -> None:
        """File ▸ Save project (Ctrl+S): a project this window writes is saved as it
        changes, so there is nothing to save — the status bar says so, and where; with
        no project, a read-only one or a failed write, Save as."""
        p = self.project
        if p.path is None or p.read_only or p.dirty or p.writer is None:
            self.save_project_dialog()
            return
        self.statusBar().showMessage(
            self.tr(
                "Everything is saved as it happens in {0}: nothing to save "
                "(File ▸ Save project as… writes a copy under another name)"
            ).format(str(p.path)),
            10000,
        )

    def close_project(self) -> None:
        """File ▸ Close project: stop following the project file (its writes finish,
        its lock goes) and empty the window; changes not in a file are offered Save as."""
        if self.project.path is None:
            self.statusBar().showMessage(self.tr("No project is open"), 5000)
            return
        if (self.project.unsaved or self.project.dirty) and not self._close_unsaved():
            return
        path = self.project.path
        self.project.release()  # the window's clearing is not written
        self.session.clear()
        self.update_title()
        self.log_message(self.tr("Closed project {0}").format(str(path)))

    def save_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Save project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            self.save_project(Path(path if path.endswith(".wakeline") else path + ".wakeline"))

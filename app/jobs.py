"""The window's jobs: import, steps, project open/save and export, run in the worker.

Each job is a plain function of a progress callback that does everything slow — reading,
hashing, the step itself, sorting, preparing the map's arrays and the batch table — and
returns finished data; :meth:`JobsMixin._on_job_message` applies it on the GUI thread
(a few dictionary updates and a swap of arrays).
"""

import dataclasses
from pathlib import Path

from PySide6 import QtWidgets

from wakeline.app.dialogs import QUARANTINE_KEPT, summarize
from wakeline.app.layer_view import prepare_view
from wakeline.app.worker import Cancelled, Failed, Finished, Progress, Started
from wakeline.core.errors import InputError
from wakeline.core.pipeline import STEPS, Pipeline, StepResult
from wakeline.core.progress import sub_progress
from wakeline.core.project import Project, file_hash, load_project
from wakeline.core.session import KIND_COLORS, PALETTE, Source


def _prepared(result: StepResult, progress, map_view, size_px) -> tuple[StepResult, dict]:
    """The result with every layer's points sorted, and each layer's prepared view (map
    level of detail for the canvas' ``map_view`` and ``size_px``)."""
    views, stages = {}, []
    for stage in result.stages or [result]:
        layers = []
        for new in stage.layers:
            color = KIND_COLORS.get(new.kind, PALETTE[0])
            lv = prepare_view(new.points, new.kind, color, new.suffix, map_view, size_px)
            views[(stage.step, new.suffix)] = (lv, color)
            layers.append(dataclasses.replace(new, points=lv.points))
        stages.append(dataclasses.replace(stage, layers=layers))
        progress(1.0, "prepared for drawing")
    if result.stages:
        return dataclasses.replace(result, stages=stages), views
    return stages[0], views


def preload() -> None:
    """Import, on the GUI thread, the modules that jobs would otherwise import lazily in
    the worker. Python loads an extension module (dlopen) holding the GIL; a first import
    in a worker while the GUI thread itself loads a library whose start-up needs the GIL
    (a Qt plugin) deadlocks — seen, intermittently, in the GUI tests."""
    import importlib

    for name in (
        "pyarrow.dataset",
        "pyarrow.parquet",
        "pyarrow.compute",
        "pyarrow.csv",
        "scipy.spatial",
        "scipy.sparse",
        "scipy.sparse.csgraph",
        "scipy.interpolate",
        "scipy.linalg",
        "scipy.ndimage",
        "scipy.optimize",
        "scipy.stats",
        "shapely",
        "gpxpy.gpx",
        "wakeline.core.io.nmea",
        "wakeline.core.io.layout",
        "wakeline.core.io.export_like",
        "wakeline.core.clean",
        "wakeline.core.maneuver",
        "wakeline.core.compress",
        "wakeline.core.associate",
        "wakeline.core.fuse",
        "wakeline.core.review",
        "wakeline.core.bearing",
        "wakeline.core.export",
    ):
        importlib.import_module(name)


class JobsMixin:
    """Loading, running and saving for :class:`~wakeline.app.main_window.MainWindow`."""

    # -- import --------------------------------------------------------------------

    def load_file(
        self,
        path: Path,
        fmt: str = "auto",
        encoding: str | None = None,
        mapping: list[str] | None = None,
        sensor: str | None = None,
        tz: str | None = None,
    ) -> int:
        """Import a file as a new layer, in the worker; returns the job number. ``tz``:
        the zone of naive local times (IANA name or ±HH:MM)."""
        options = {"fmt": fmt, "mapping": mapping or [], "encoding": encoding, "tz": tz}
        if sensor:
            options["sensor"] = sensor
        return self.load_files([Path(path)], options)

    def load_files(self, paths: list[Path], options: dict | None = None) -> int:
        """Import files (one job, one after the other); each becomes a source layer."""
        from wakeline.core.io import read_points
        from wakeline.core.io.export_like import layout_meta

        options = options or {}
        first = len(self.session.layers)
        colors = [PALETTE[(first + k) % len(PALETTE)] for k in range(len(paths))]
        size_px = self.canvas.plot_size_px()

        def job(progress):
            done, errors = [], []
            for k, (path, color) in enumerate(zip(paths, colors, strict=True)):
                sub = sub_progress(progress, k / len(paths), (k + 1) / len(paths))
                try:
                    result = read_points(path, progress=sub_progress(sub, 0.0, 0.7), **options)
                    if len(result.points) == 0:
                        raise InputError(f"{path.name}: no usable points")
                except (InputError, OSError) as exc:
                    if len(paths) == 1:
                        raise
                    errors.append(str(exc))
                    continue
                sub(0.7, f"hashing {path.name}")
                sha = file_hash(path)
                sub(0.75, "learning the layout for export")
                layout = layout_meta(path, result.report)
                sub(0.8, "preparing the map")
                view = prepare_view(result.points, "source", color, path.name, None, size_px)
                done.append((path, result, sha, view, color, layout))
            return ("import", done, errors)

        name = paths[0].name if len(paths) == 1 else f"{len(paths)} files"
        return self._start(f"open {name}", job, ("import", name))

    def _apply_import(self, path: Path, result, sha: str, view, color: str, layout) -> None:
        rep = result.report
        self.log_message(
            f"{path.name}: {rep['rows_imported']:,} rows in {rep['tracks']:,} tracks "
            f"({rep['format_label']}, {rep['encoding']}); {rep['rows_quarantined']:,} quarantined"
        )
        for reason, count in rep["quarantine_reasons"].items():
            self.log_message(f"    quarantined {count:,}: {reason}")
        for warning in rep.get("warnings", []):
            self.log_message(f"    {self.tr('Warning')}: {warning}")
        self.session.sources.append(Source(str(path.resolve()), sha))
        quarantine = result.quarantine.head(QUARANTINE_KEPT).astype(str).to_dict("records")
        meta = {"file": str(path), "report": rep, "quarantine": quarantine, "layout": layout}
        lid = self.session.new_id()
        self.views[lid] = view
        self.session.add_layer(path.name, "source", view.points, meta, color=color, layer_id=lid)
        self._fit_after_draw = True

    def load_bearings(self, path: Path) -> int | None:
        """Read ``batch,time,bearing[,obs_lon,obs_lat]`` and run seed 002's detector on it
        in the worker; the Detail panel shows the sequences, z and the detections."""
        from wakeline.core.bearing import read_bearings
        from wakeline.core.pipeline import step_bearing

        params = self.params.params("bearing")

        def job(progress):
            bearings = read_bearings(path)
            return ("bearing", bearings, step_bearing(bearings, params, progress))

        return self._start("bearing", job, ("bearing", Path(path).name))

    def open_bearings_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Open bearings"), "", "CSV (*.csv *.txt);;All files (*)"
        )
        if path:
            self.load_bearings(Path(path))

    # -- steps ---------------------------------------------------------------------

    def step_params(self, step: str) -> dict:
        """The parameter sets of ``step`` as the panel holds them."""
        p = self.params
        out = STEPS[step].defaults()
        for key in out:
            if key == "clean":
                out[key] = p.clean_params()
            elif key in p.keys():
                out[key] = p.params(key)  # option sets (method …) keep their defaults
        return out

    def run_step(self, step: str) -> int | None:
        """Run a step (or the pipeline) on the active layer in the worker thread."""
        layer = self.active_layer()
        if layer is None:
            QtWidgets.QMessageBox.information(
                self, self.tr("Nothing to run on"), self.tr("Open a track file first.")
            )
            return None
        lid = layer.id
        if step == "pipeline":
            pipe = self.pipeline()

            def run(progress):
                return pipe.run(self.session.layers[lid].points, progress)

            params = None
        else:
            params = self.step_params(step)

            def run(progress):
                return self.session.run_step(lid, step, params, progress)

        canvas_view, size_px = self.canvas.current_view(), self.canvas.plot_size_px()

        def job(progress):
            result = run(sub_progress(progress, 0.0, 0.85))
            prepared, views = _prepared(
                result, sub_progress(progress, 0.85, 1.0), canvas_view, size_px
            )
            return ("step", lid, prepared, views, params)

        return self._start(step, job, (step, layer.name))

    def _apply_step(self, lid: str, result: StepResult, views: dict, params) -> None:
        if lid not in self.session.layers:
            self.log_message(self.tr("the input layer was removed; result dropped"))
            return
        # The session names the layers; the window takes each prepared view as the
        # session announces the layer of that (step, role).
        self._pending_views = {key: view for key, (view, _color) in views.items()}
        try:
            self.session.apply_result(lid, result, params)
        finally:
            self._pending_views = {}

    def pipeline(self) -> Pipeline:
        """The pipeline Run ▸ pipeline runs: clean, then maneuvers and compress."""
        return Pipeline(tuple((s, self.step_params(s)) for s in ("clean", "compress")))

    def save_pipeline(self, path: Path) -> None:
        """Write the pipeline with the panel's parameters as JSON (``wakeline batch`` and
        Run ▸ Load pipeline read it)."""
        Path(path).write_text(self.pipeline().to_json(), encoding="utf-8")
        self.log_message(self.tr("pipeline saved to {0}").format(path))

    def load_pipeline(self, path: Path) -> list[str]:
        """Put a saved pipeline's parameters into the panel; returns the problems."""
        from wakeline.core.pipeline import params_to_json

        try:
            pipe = Pipeline.from_json(Path(path).read_text(encoding="utf-8"))
        except (InputError, OSError) as exc:
            QtWidgets.QMessageBox.warning(self, self.tr("Cannot load pipeline"), str(exc))
            return [str(exc)]
        keys = {"clean", *self.params.keys()}
        problems = []
        for _name, params in pipe.stages:
            data = params_to_json(params)
            problems += self.params.from_dict({k: v for k, v in data.items() if k in keys})
        for text in problems:
            self.log_message(f"{self.tr('Warning')}: {text}")
        return problems

    def _pipeline_dialog(self, save: bool) -> None:
        dialog = (
            QtWidgets.QFileDialog.getSaveFileName if save else QtWidgets.QFileDialog.getOpenFileName
        )
        path, _ = dialog(self, self.tr("Pipeline"), "", "Wakeline pipeline (*.json)")
        if path:
            (self.save_pipeline if save else self.load_pipeline)(Path(path))

    # -- messages ------------------------------------------------------------------

    def _start(self, name: str, fn, context: tuple) -> int:
        job = self.runner.run(name, fn)
        # One job at a time: an older job's result will never be applied.
        self._job_context = {job: context}
        return job

    def _on_job_message(self, msg) -> None:
        if isinstance(msg, Started):
            self.progress.setValue(0)
            self.progress.show()
            self.cancel_button.show()
            self.statusBar().showMessage(self.tr("Running {0}…").format(msg.name))
            return
        if isinstance(msg, Progress):
            self.progress.setValue(int(msg.fraction * 1000))
            if msg.text:
                self.statusBar().showMessage(msg.text)
            return
        if msg.job in self._job_context:
            self.progress.hide()
            self.cancel_button.hide()
        step, base = self._job_context.pop(msg.job, (msg.name, ""))
        if isinstance(msg, Finished):
            self._apply(msg.result)
            self.statusBar().showMessage(
                self.tr("{0} done in {1:.1f} s").format(msg.name, msg.seconds), 8000
            )
        elif isinstance(msg, Failed):
            self.statusBar().showMessage(self.tr("{0} failed").format(msg.name), 8000)
            self.log_message(f"{self.tr('Error')} ({msg.name}): {msg.message}")
            if msg.detail:
                self.log_message(msg.detail)
            title = self.tr("{0} failed").format(msg.name)
            QtWidgets.QMessageBox.warning(self, title, msg.message)
        elif isinstance(msg, Cancelled):
            self.log_message(self.tr("{0} cancelled").format(msg.name))
            self.statusBar().showMessage(self.tr("{0} cancelled").format(msg.name), 5000)

    def _apply(self, done: tuple) -> None:
        kind = done[0]
        if kind == "import":
            for item in done[1]:
                self._apply_import(*item)
            for text in done[2]:
                self.log_message(f"{self.tr('Error')}: {text}")
            if done[2]:
                QtWidgets.QMessageBox.warning(self, self.tr("Cannot open file"), "\n".join(done[2]))
        elif kind == "step":
            _, lid, result, views, params = done
            self._apply_step(lid, result, views, params)
            name = self.session.layers[lid].name if lid in self.session.layers else lid
            self.log_message(f"{result.step} on {name}: {summarize(result.report)}")
        elif kind == "bearing":
            _, bearings, result = done
            self.bearings, self.bearing_detections = bearings, result.tables["detections"]
            self.log_message(f"bearing: {summarize(result.report)}")
            for line in result.report.get("why", []):
                self.log_message(f"    {line}")
            self.bearing_view.show_result(
                bearings, self.bearing_detections, result.report["report"]
            )
            self.detail.show_bearings(
                bearings, self.bearing_detections, self.params.params("bearing")
            )
            self.docks["detail"].raise_()
        elif kind == "project":
            self._apply_project(*done[1:])
        elif kind == "fuse_layers":
            from wakeline.app.review_sync import apply_fused

            apply_fused(self, *done[1:])
        elif kind == "export":
            self.log_message(self.tr("exported {0} to {1}").format(done[1], done[2]))

    # -- export --------------------------------------------------------------------

    def export_dialog(self, kind: str) -> None:
        layer = self.active_layer()
        if layer is None:
            return
        if kind == "as_came_in":
            self.export_as_came_in()
            return
        filt = "GeoJSON (*.geojson)" if kind == "geojson" else "CSV (*.csv)"
        suffix = ".geojson" if kind == "geojson" else ".csv"
        name = layer.name.replace(" · ", "_") + suffix
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, self.tr("Export"), name, filt)
        if path:
            self.export(kind, Path(path))

    def export(self, kind: str, path: Path) -> int | None:
        """Write the active layer (or its maneuver points) to ``path`` in the worker."""
        from wakeline.app.cli_steps import write_table
        from wakeline.core.export import export_csv, export_geojson

        layer = self.active_layer()
        if layer is None:
            return None
        view = self.views[layer.id]
        man = self.session.related(layer.id, "maneuvers")
        table = man.tables.get("maneuvers") if man is not None else None
        if kind == "maneuvers" and table is None:
            text = self.tr("this layer has no maneuver points: run Maneuvers or Compress")
            QtWidgets.QMessageBox.warning(self, self.tr("Export failed"), text)
            return None
        points = layer.points

        def job(_progress):
            if kind == "csv":
                export_csv(points, path)
            elif kind == "geojson":
                export_geojson(points, path, view.maneuvers)
            else:  # the same table and writer as `wakeline maneuvers`
                write_table("maneuvers", table, path)
            return ("export", layer.name, path)

        return self._start("export", job, ("export", layer.name))

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
            QtWidgets.QMessageBox.warning(self, self.tr("Export failed"), str(exc))
            self.log_message(f"{self.tr('Error')}: {exc}")
            return None
        if path is None:
            src = Path(layout.source) if layout.source else Path("tracks.csv")
            suggestion = f"{layer.name.replace(' · ', '_')}{src.suffix or '.csv'}"
            chosen, _ = QtWidgets.QFileDialog.getSaveFileName(
                self,
                self.tr("Export as it came in"),
                suggestion,
                f"{layout.name} (*{src.suffix or '.csv'})",
            )
            if not chosen:
                return None
            path = Path(chosen)
        points = layer.points

        def job(_progress):
            export_like(points, layout, path)
            return ("export", layer.name, path)

        return self._start("export", job, ("export", layer.name))

    # -- project -------------------------------------------------------------------

    def save_project(self, path: Path) -> None:
        """Save the session to ``path`` (in the background) and keep it up to date."""
        self.project.save_as(Path(path), {"view": self.canvas.vb.viewRange()})
        self.retranslate()

    def open_project(self, path: Path) -> int:
        """Open a project in the worker; the current session stays as it is unless the
        whole project reads well."""
        path = Path(path)
        size_px = self.canvas.plot_size_px()

        def job(progress):
            proj = load_project(path)
            warnings = proj.source_problems()
            views = {}
            for k, lay in enumerate(proj.layers):
                progress(k / max(len(proj.layers), 1), f"preparing {lay.name}")
                views[lay.id] = prepare_view(
                    lay.points, lay.kind, lay.color, lay.name, None, size_px
                )
                lay.points = views[lay.id].points
            return ("project", path, proj, views, warnings)

        return self._start("open project", job, ("project", path.name))

    def _apply_project(self, path: Path, proj: Project, views: dict, warnings: list) -> None:
        self.project.detach()
        self.session.clear()
        self.views.update(views)
        problems = self.params.from_dict(proj.params)
        proj.to_session(self.session)
        self.project.follow(path, proj.read_only)
        sel = [r for r in proj.selection if r[0] in self.session.layers]
        if sel:  # applied once the layers are drawn (one per event-loop turn)
            self._make_current = sel[0][0]
            self._restore_selection = [(s, b) for _, s, b in sel]
        self.retranslate()
        self._fit_after_draw = True
        if proj.read_only:
            ro = self.tr("the project file is read-only: it opens read-only, changes are not saved")
            warnings = [ro, *warnings]
        for w in warnings + problems:
            self.log_message(f"{self.tr('Warning')}: {w}")
        if warnings or problems:
            QtWidgets.QMessageBox.warning(
                self, self.tr("Project opened with warnings"), "\n".join(warnings + problems)
            )

    def open_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Open project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            self.open_project(Path(path))

    def save_project_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Save project"), "", "Wakeline (*.wakeline)"
        )
        if path:
            self.save_project(Path(path if path.endswith(".wakeline") else path + ".wakeline"))

"""Import jobs of the window: track files and bearing sequences, read in the worker.

Mixed into :class:`~wakeline.app.jobs.JobsMixin`; each job returns finished data that
:meth:`JobsMixin._apply` swaps in on the GUI thread.
"""

from pathlib import Path

import numpy as np
from PySide6 import QtWidgets

from wakeline.app.core_text import shown
from wakeline.app.dialogs import QUARANTINE_KEPT, translated
from wakeline.app.layer_view import plan_view, points_sketch, prepare_view_apart
from wakeline.app.map_time import guarded
from wakeline.core.errors import InputError
from wakeline.core.progress import sub_progress
from wakeline.core.project import file_hash
from wakeline.core.schema import FILE_ROW
from wakeline.core.words import import_counts


class ImportJobsMixin:
    """File ▸ Open tracks and File ▸ Open bearings."""

    #: The translation context of ``self.tr`` here: PySide looks a text up along
    #: ``type(self).__mro__``, which starts at the window (``MainWindow``).
    TR_CONTEXT = "MainWindow"

    def load_file(
        self,
        path: Path,
        fmt: str = "auto",
        encoding: str | None = None,
        mapping: list[str] | None = None,
        sensor: str | None = None,
        tz: str | None = None,
        skip_rows: int | None = None,
        origin: str | None = None,
        date_order: str = "auto",
        time_unit: str = "auto",
        clock_date: str | None = None,
        speed_unit: str = "auto",
        distance_unit: str = "auto",
    ) -> int:
        """Import a file as a new layer, in the worker; returns the job number. ``tz``:
        the zone of naive local times (IANA name or ±HH:MM); ``skip_rows``: lines before
        the header (None: detected); ``origin``: ``"LAT,LON"`` of a file whose positions
        are metres on a local plane; ``date_order``: how slashed dates read (auto,
        day-first, month-first); ``time_unit``: what numeric times count (auto,
        seconds, excel-days); ``clock_date``: the day (YYYY-MM-DD) of times written
        without a date (None: 1970-01-01, relative); ``speed_unit``, ``distance_unit``:
        of a speed column and plane lengths whose headers name none."""
        options = {"fmt": fmt, "mapping": mapping or [], "encoding": encoding, "tz": tz}
        options["skip_rows"] = skip_rows
        options["date_order"] = date_order
        options["time_unit"] = time_unit
        options["clock_date"] = clock_date
        options["speed_unit"] = speed_unit
        options["distance_unit"] = distance_unit
        if origin:
            options["origin"] = origin
        if sensor:
            options["sensor"] = sensor
        return self.load_files([Path(path)], options)

    def load_files(self, paths: list[Path], options: dict | None = None) -> int:
        """Import files (one job, one after the other); each becomes a source layer."""
        from wakeline.core.io import nothing_imported, read_points
        from wakeline.core.io.export_like import layout_meta

        options = options or {}
        # Each file's sensors take source colours no layer shows (the worker chooses,
        # once it knows the sensors).
        in_use = self.colors_in_use()
        size_px = self.canvas.plot_size_px()
        state = self._view_state()

        def job(progress):
            read, errors = [], []
            for k, path in enumerate(paths):
                sub = sub_progress(progress, 0.8 * k / len(paths), 0.8 * (k + 1) / len(paths))
                try:
                    result = read_points(path, progress=sub_progress(sub, 0.0, 0.85), **options)
                    if len(result.points) == 0:
                        raise InputError(nothing_imported(result.report, path.name))
                except (InputError, OSError) as exc:
                    if len(paths) == 1:
                        raise
                    errors.append(str(exc))
                    continue
                sub(0.85, f"hashing {path.name}")
                sha = file_hash(path)
                sub(0.95, "learning the layout for export")
                units = {
                    k: options.get(k) or "auto" for k in ("speed_unit", "distance_unit")
                }  # what the import was told of columns whose headers name no unit
                read.append((path, result, sha, layout_meta(path, result.report, **units)))
            # The view the map will show once these are added: each layer's level of
            # detail is made for it here, so the map strokes each layer once.
            plan = None
            if read:
                lat = read[0][1].points["lat"].to_numpy(dtype="float64")
                lat0 = float(np.nanmean(lat)) if np.isfinite(lat).any() else None
                plan = plan_view(state, [points_sketch(r[1].points) for r in read], lat0)
            done = []
            for k, (path, result, sha, layout) in enumerate(read):
                progress(0.8 + 0.2 * k / len(read), f"preparing the map for {path.name}")
                shown = plan["shown"] if plan else None
                # The layer is kept in track order; each point's file row goes with it
                # (Export ▸ As it came in writes the file's order again).
                pts = result.points.assign(**{FILE_ROW: np.arange(len(result.points))})
                view = prepare_view_apart(pts, "source", in_use, path.name, shown, size_px)
                done.append((path, result, sha, view, view.colors[0], layout))
            return ("import", done, errors, plan)

        name = paths[0].name if len(paths) == 1 else f"{len(paths)} files"
        return self._start(f"open {name}", job, ("import", name))

    def _apply_import(self, path: Path, result, sha: str, view, color: str, layout) -> None:
        rep = result.report
        # every line of the file accounted for, blank ones too, as `wakeline import` says it
        self.log_message(
            f"{path.name}: {translated(import_counts(rep, shown(rep['format_label'])))}"
        )
        q = result.quarantine
        for reason, n in rep["quarantine_reasons"].items():
            lines = (
                q.loc[q["reason"] == reason, "line"].head(4).tolist()
                if n <= 3 and "line" in q.columns
                else []
            )
            if len(lines) == 1:  # a few: where they are (the file's last line cut short?)
                text = self.tr("quarantined {0:,}: {1} (line {2})").format(
                    n, shown(reason), lines[0]
                )
            elif 1 < len(lines) <= 3:
                where = ", ".join(str(k) for k in lines)
                text = self.tr("quarantined {0:,}: {1} (lines {2})").format(n, shown(reason), where)
            else:
                text = self.tr("quarantined {0:,}: {1}").format(n, shown(reason))
            self.log_message("    " + text)
        for reason, n in rep.get("values_blanked", {}).items():
            self.log_message(
                "    " + self.tr("blanked {0:,} (row kept): {1}").format(n, shown(reason))
            )
        for warning in rep.get("warnings", []):
            self.log_message(f"    {self.tr('Warning')}: {shown(warning)}")
        self.session.note_source(str(path.resolve()), sha)
        quarantine = result.quarantine.head(QUARANTINE_KEPT).astype(str).to_dict("records")
        meta = {"file": str(path), "report": rep, "quarantine": quarantine, "layout": layout}
        lid = self.session.new_id()
        self.views[lid] = view
        name = self._source_name(path)
        self.session.add_layer(name, "source", view.points, meta, color=color, layer_id=lid)
        if not self._cjk_checked and self._holds_cjk(path, view.points):
            self.check_cjk_font()

    @staticmethod
    def _holds_cjk(path: Path, points) -> bool:
        """Whether a loaded file shows Chinese text in the window: its name, its column
        names, its sensors' or track ids' values (each distinct value once)."""
        import pandas as pd

        from wakeline.app.cjk_font import needs_cjk

        values = []
        for c in ("sensor", "batch"):
            col = points[c] if c in points.columns else None
            if col is None or pd.api.types.is_numeric_dtype(col.dtype):
                continue
            if isinstance(col.dtype, pd.CategoricalDtype):
                values.append(col.cat.categories.astype(str))
            else:
                values.append(col.astype(str).unique())
        return needs_cjk(path.name, [str(c) for c in points.columns], *values)

    def _source_name(self, path: Path) -> str:
        """A new source layer's name: the file's name, with its folder where a layer
        has that name already (ais/tracks.csv and radar/tracks.csv were both "tracks.csv"
        in the Layers list, the legend and the fused layer's name), and a number where
        that is taken too (one file opened twice)."""
        from wakeline.core.review import distinct_folders

        layers = self.session.layers.values()
        taken = {lay.name for lay in layers}
        files = {
            str(lay.meta["file"])
            for lay in layers
            if lay.kind == "source"
            and lay.meta.get("file")
            and Path(lay.meta["file"]).name == path.name
        }
        name = path.name
        if name in taken and str(path) not in files:
            # the folders that tell it from the other files of this name (core's rule, as
            # the sensors of a fusion are named)
            folder = distinct_folders([*sorted(files), str(path)])[-1]
            name = f"{folder}/{path.name}" if folder else name
        k = 2
        while name in taken:
            name = f"{path.name} ({k})"
            k += 1
        return name

    def load_bearings(
        self,
        path: Path,
        mapping: list[str] | None = None,
        origin: str | None = None,
        encoding: str | None = None,
        tracks: str | None = None,
        gate_deg: float = 3.0,
    ) -> int | None:
        """Read ``batch,time,bearing[,obs_lon,obs_lat]`` and run seed 002's detector on it
        in the worker; the result is a bearing layer of the session (the Layers list, the
        project, the time window: :meth:`_apply_bearings`), drawn on the main map (the
        observer and the bearing lines, prepared here, in the worker:
        :func:`~wakeline.app.bearing_view.bearing_scene`); the Detail panel shows the
        sequences, z and the detections, the Bearing-only dock its map and table. The same
        file opened again replaces its layer. ``mapping`` (``field=column`` items),
        ``origin`` (``"LAT,LON"`` of an observer in metres) and ``encoding``: as
        ``wakeline bearing``'s --map, --origin and --encoding (the Open bearings dialog);
        ``tracks``: the id of a track layer to gate the bearings on (``--tracks``), within
        ``gate_deg`` (``--gate``)."""
        from wakeline.app.bearing_view import bearing_layer_view, bearing_scene, main_map_layers
        from wakeline.core.bearing_read import read_bearing_file
        from wakeline.core.pipeline import step_bearing

        params = self.params.params("bearing")
        length_m = self.bearing_view.fixed_length_m
        path = Path(path)
        # The main map is framed on the bearings when it shows no other layer (else it
        # keeps its view): the layers' level of detail is made for that view.
        gate_on = None
        if tracks is not None and tracks in self.session.layers:
            gate_on = self.session.layers[tracks]
        again = self.session.bearing_layer(str(path.resolve()))
        frame = not any(lay.visible and lay is not again for lay in self.session.layers.values())
        view, size_px, lat0 = self.canvas.current_view(), self.canvas.plot_size_px(), None
        if not frame:
            lat0 = self.canvas._lat0

        def job(progress):
            got = read_bearing_file(path, mapping=mapping, origin=origin, encoding=encoding)
            bearings, quarantine = got.bearings, got.quarantine
            if gate_on is not None:  # one sequence per series and track
                from wakeline.core.bearing_read import gate_to_tracks

                bearings, got.report["gated"] = gate_to_tracks(bearings, gate_on.points, gate_deg)
                got.report["gated"]["layer"] = gate_on.name
            result = step_bearing(bearings, params, sub_progress(progress, 0.0, 0.85))
            progress(0.85, f"hashing {path.name}")
            sha = file_hash(path)
            progress(0.9, "preparing the map")
            detections = result.tables["detections"]
            scene = bearing_scene(bearings, detections, length_m, True)
            plan, parts = None, []
            if scene is not None:
                parts = main_map_layers(scene, scene.target if frame else view, size_px, lat0)
                if frame:
                    plan = {"target": scene.target, "lat0": scene.lat0}
            lview = bearing_layer_view(
                bearings,
                detections,
                result.report["report"],
                scene,
                parts,
                params,
                statistic=result.tables["statistic"],  # z is not computed again
            )
            lview.extra["read"] = got.report  # where the file's lines went (the log)
            lview.extra["read_options"] = {"mapping": list(mapping or []), "origin": origin}
            if gate_on is not None:
                lview.extra["read_options"].update(tracks=gate_on.name, gate_deg=gate_deg)
            return ("bearing", path, quarantine, result, lview, sha, plan)

        return self._start("bearing", job, ("bearing", path.name))

    def bearing_length_changed(self) -> None:
        """The Bearing-only dock's lines got another length: the main map's parts of the
        bearing layer it shows are made again from the dock's new scene in the LOD worker
        (:func:`~wakeline.app.bearing_view.main_map_layers`, for the map's view, as the load
        does); then the layer is replaced in place (``changed``: redrawn, cut by the time
        window, its new ``length_m`` saved in the project). Nothing when the dock shows no
        layer of the session."""
        from wakeline.app.bearing_view import bearing_layer_view, main_map_layers

        dock = self.bearing_view
        scene, bearings = dock.scene, dock.bearings
        lid = next((i for i, lay in self.session.layers.items() if lay.points is bearings), None)
        old = self.views.get(lid) if lid is not None else None
        if scene is None or old is None:
            return
        detections, report = old.extra["detections"], old.extra["report"]
        # For the view and aspect the map shows now (it keeps them).
        view, size_px = self.canvas.current_view(), self.canvas.plot_size_px()
        lat0 = self.canvas._lat0

        def job():
            parts = main_map_layers(scene, view, size_px, lat0)
            return bearing_layer_view(bearings, detections, report, scene, parts)

        def done(new) -> None:
            layer = self.session.layers.get(lid)
            if new is None or layer is None or layer.points is not bearings:
                return  # the job failed, or the layer was removed or replaced meanwhile
            if dock.scene is not scene:
                return  # another length (or layer) meanwhile: its own job follows
            if "curves" in old.extra:  # z over the sequences: not the lines' length's
                new.extra["curves"] = old.extra["curves"]
            self.views[lid] = new
            meta = {**layer.meta, "length_m": scene.length_m}
            self.session.put_bearings(layer.name, bearings, detections, meta, layer_id=lid)

        self.lod_worker(guarded(job), done)

    def _apply_bearings(self, path: Path, view, sha: str, plan: dict | None) -> None:
        """A bearing file read: its layer added to the session (or the one of the same
        file replaced), the map framed on it when it shows nothing else (``plan``)."""
        from wakeline.app.bearing_view import layer_meta

        resolved = str(path.resolve())
        self.session.note_source(resolved, sha)
        old = self.session.bearing_layer(resolved)
        lid = old.id if old is not None else self.session.new_id()
        self.views[lid] = view
        self._plan_view(plan)
        try:
            self.session.put_bearings(
                path.name,
                view.points,
                view.extra["detections"],
                layer_meta(resolved, sha, view),
                layer_id=lid,
            )
        finally:
            self._view_planned = False

    def open_bearings_dialog(self) -> None:
        """The Open bearings dialog (file, columns, encoding, origin), then the read."""
        from wakeline.app.bearing_dialog import BearingDialog

        layers = [(lid, lay.name) for lid, lay in self.session.layers.items()]
        tracks = [(lid, name) for lid, name in layers if self.session.layers[lid].kind != "bearing"]
        dialog = BearingDialog(self, tracks=tracks)
        if dialog.exec() == QtWidgets.QDialog.DialogCode.Accepted and dialog.path().is_file():
            self.load_bearings(dialog.path(), **dialog.options(), **dialog.gate())

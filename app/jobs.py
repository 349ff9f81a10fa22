"""The window's jobs: import, steps, project open/save and export, run in the worker.

Each job is a plain function of a progress callback that does everything slow — reading,
hashing, the step itself, sorting, preparing the map's arrays and the batch table — and
returns finished data; :meth:`JobsMixin._on_job_message` applies it on the GUI thread
(a few dictionary updates and a swap of arrays).
"""

import dataclasses
import sys
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from wakeline.app.core_text import shown, shown_cli
from wakeline.app.dialogs import step_lines, summarize
from wakeline.app.jobs_import import ImportJobsMixin
from wakeline.app.jobs_project import ProjectJobsMixin
from wakeline.app.layer_names import shown_name
from wakeline.app.layer_view import prepare_view_apart
from wakeline.app.worker import Cancelled, Failed, Finished, Progress, Started, new_job_number
from wakeline.core.errors import InputError
from wakeline.core.pipeline import STEPS, Pipeline, StepResult
from wakeline.core.progress import sub_progress
from wakeline.core.session import BEARING_KIND

#: Run ▸ pipeline's stages in a new window: clean, then maneuvers and compress.
DEFAULT_STAGES = ("clean", "compress")
#: The steps that take each batch for one ship's track (a warning before they run on
#: radar plots: :meth:`JobsMixin.warn_if_plots`).
TRACK_STEPS = ("pipeline", "clean", "maneuvers", "compress")
#: The project's state row holding Run ▸ pipeline's stages (a list of step names).
PIPELINE_STATE = "pipeline"
#: The settings key (QSettings) holding them for the next window, project or not.
PIPELINE_SETTING = "pipeline_stages"
#: The steps of a saved pipeline Run ▸ pipeline runs, in the order it runs them
#: (maneuvers as part of compress).
WINDOW_ORDER = ("clean", "maneuvers", "compress", "associate")


def _prepared(
    result: StepResult,
    progress,
    map_view,
    size_px,
    in_use: tuple[set[str], set[str]] | None = None,
) -> tuple[StepResult, dict]:
    """The result with every layer's points sorted, and each layer's prepared view (map
    level of detail for the canvas' ``map_view`` and ``size_px``), each in its kind's
    colour unless a layer shown already has it (``in_use``: the colours of the visible and
    of the hidden layers the result does not replace; see ``colors_in_use``)."""
    in_use = in_use if in_use is not None else (set(), set())
    views, stages = {}, []
    for stage in result.stages or [result]:
        layers = []
        for new in stage.layers:
            lv = prepare_view_apart(new.points, new.kind, in_use, new.suffix, map_view, size_px)
            views[(stage.step, new.suffix)] = (lv, lv.colors[0] if lv.colors else "")
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
        "wakeline.core.io.gpx",
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


class JobsMixin(ImportJobsMixin, ProjectJobsMixin):
    """Loading, running and saving for :class:`~wakeline.app.main_window.MainWindow`."""

    #: The translation context of ``self.tr`` here: PySide looks a text up along
    #: ``type(self).__mro__``, which starts at the window (``MainWindow``).
    TR_CONTEXT = "MainWindow"

    def job_title(self, name: str) -> str:
        """A job's title for the operator (a dialog's title, the log), in the current
        language: the job's internal name ("export", "open project", "bearing", a step)
        made "{0} failed" titles like "export 失败" (operator test h150)."""
        tr = self.tr
        titles = {
            "pipeline": tr("Pipeline"),
            "clean": tr("Clean"),
            "maneuvers": tr("Maneuvers"),
            "compress": tr("Compress"),
            "associate": tr("Associate"),
            "fuse": tr("Fuse"),
            "export": tr("Export"),
            "open project": tr("Open project"),
            "bearing": tr("Open bearings"),
            "review": tr("Review"),
            "vessels": tr("Load ship names"),
        }
        if name in titles:
            return titles[name]
        if name.startswith("open "):  # an import: "open FILE"
            return tr("Open {0}").format(name[len("open ") :])
        return name

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

    def tell(self, title: str, text: str, kind: str = "warning", cli: str | None = None) -> None:
        """A message box the operator closes, or — in a window nobody answers (a
        ``--screenshot`` run, a script: ``interactive`` False) — the same words on stderr,
        and the run goes on (operator test 9, D4: a failed file of several hung the
        screenshot in a modal "Cannot open file" box). ``kind``: warning, information.
        ``cli``: the words for stderr when they differ from the window's (a core message
        with its command-line flags, :func:`~wakeline.app.core_text.shown_cli`)."""
        if getattr(self, "interactive", True):
            box = QtWidgets.QMessageBox
            (box.information if kind == "information" else box.warning)(self, title, text)
            return
        for line in (text if cli is None else cli).splitlines() or [""]:
            print(f"wakeline: {title}: {line}", file=sys.stderr)

    def run_step(self, step: str) -> int | None:
        """Run a step (or the pipeline) on the active layer in the worker thread."""
        layer = self.active_layer()
        if layer is None:
            self.tell(
                self.tr("Nothing to run on"), self.tr("Open a track file first."), "information"
            )
            return None
        if layer.kind == BEARING_KIND:
            self.tell(
                self.tr("Nothing to run on"),
                self.tr("A bearing layer has no tracks: choose a track layer."),
                "information",
            )
            return None
        lid = self.session.step_input(layer.id)
        if lid != layer.id:
            layer = self.session.layers[lid]
            self.log_message(self.tr("{0} runs on {1}").format(shown(step), shown_name(layer.name)))
        if step == "pipeline":
            pipe = self.pipeline()

            def run(progress):
                # Through the session: a reviewed stage keeps the review it replaces.
                return self.session.run_pipeline(lid, pipe, progress)

            params = None
            steps = [name for name, _ in pipe.stages]
        else:
            params = self.step_params(step)

            def run(progress):
                return self.session.run_step(lid, step, params, progress)

            steps = [step]
        canvas_view, size_px = self.canvas.current_view(), self.canvas.plot_size_px()
        # The colours taken: every other layer's (a re-run's layers give theirs back).
        in_use = self.colors_in_use(exclude=self.replaced_by_run(lid, steps))

        def job(progress):
            result = run(sub_progress(progress, 0.0, 0.85))
            prepared, views = _prepared(
                result, sub_progress(progress, 0.85, 1.0), canvas_view, size_px, in_use
            )
            return ("step", lid, prepared, views, params)

        self.warn_if_plots(lid, step)
        return self._start(step, job, (step, shown_name(layer.name)))

    def warn_if_plots(self, lid: str, step: str) -> bool:
        """Say in the log (non-modal; the run goes on) when a track step — the pipeline,
        Clean, Maneuvers, Compress — runs on a layer that is mostly radar plots (the
        parameter guidance's test, ``core.tracks.plot_like``: the layer drawn as dots):
        each batch is taken for one ship's track, and the result joins a scan's
        detections (the Autoferry detections came out a scribble). Returns whether it
        said so."""
        view = self.views.get(lid)
        if step not in TRACK_STEPS or view is None or not view.extra.get("plots"):
            return False
        layer = self.session.layers.get(lid)
        text = self.tr(
            "{0} runs on {1}, which looks like radar plots (detections of each scan, see the "
            "guidance under Parameters), not ships' tracks: it takes each batch for one "
            "ship's track, and its result joins unrelated detections. Join the plots into "
            "tracks first (a tracker) for a meaningful result."
        ).format(self.job_title(step), shown_name(layer.name) if layer else lid)
        self.log_message(f"{self.tr('Warning')}: {text}")
        return True

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

    #: The stages Run ▸ pipeline runs (Clean, then those of Run ▸ Pipeline stages).
    pipeline_stages: tuple[str, ...] = DEFAULT_STAGES

    def pipeline(self) -> Pipeline:
        """The pipeline Run ▸ pipeline runs: clean, then (as Run ▸ Pipeline stages says)
        maneuvers and compress, and associate; each with the panel's parameters. A
        pipeline ending with Associate makes the proposals to review; run again, it
        keeps the review of the layer it replaces (``Session.run_pipeline``)."""
        return Pipeline(tuple((s, self.step_params(s)) for s in self.pipeline_stages))

    def set_pipeline_stages(self, stages, store: bool = True) -> None:
        """Run ▸ pipeline runs Clean then ``stages`` (of ``compress``, ``associate``, in
        that order; others are not the window's). Stored in the project (its
        ``pipeline`` state row) and in the settings (the next window starts with them,
        a project open or not) unless ``store`` is False (a project being opened)."""
        from wakeline.app.actions import PIPELINE_CHOICES, pipeline_text

        stages = ("clean", *(s for s in PIPELINE_CHOICES if s in stages))
        changed = stages != self.pipeline_stages
        self.pipeline_stages = stages
        for s in PIPELINE_CHOICES:
            act = self.actions_[f"pipeline_{s}"]
            was = act.blockSignals(True)
            act.setChecked(s in stages)
            act.blockSignals(was)
        self.actions_["pipeline"].setText(pipeline_text(self))
        if changed and store:
            self.project.put_state(PIPELINE_STATE, list(stages))
            self.settings.setValue(PIPELINE_SETTING, list(stages))

    def stored_pipeline_stages(self) -> tuple[str, ...]:
        """Run ▸ Pipeline stages as the settings keep them (DEFAULT_STAGES when they keep
        none); a name the window does not know is dropped, with a warning in the log."""
        from wakeline.app.actions import PIPELINE_CHOICES

        value = self.settings.value(PIPELINE_SETTING)
        if value is None:
            return DEFAULT_STAGES
        # An INI file gives a list of one back as a string.
        names = [value] if isinstance(value, str) else value
        if not isinstance(names, list):
            names = [str(names)]
        known = ("clean", *PIPELINE_CHOICES)
        for name in names:
            if name not in known:
                text = self.tr(
                    "the settings' pipeline stage {0} is not one of Run ▸ Pipeline stages "
                    "(clean, compress, associate); dropped"
                )
                self.log_message(f"{self.tr('Warning')}: {text.format(name)}")
        return tuple(n for n in names if n in known)

    def set_pipeline_stage(self, stage: str, on: bool) -> None:
        """Run ▸ Pipeline stages ▸ ``stage`` checked (``on``) or not."""
        rest = [s for s in self.pipeline_stages if s != stage]
        self.set_pipeline_stages([*rest, stage] if on else rest)

    def save_pipeline(self, path: Path) -> None:
        """Write the pipeline with the panel's parameters as JSON (``wakeline batch`` and
        Run ▸ Load pipeline read it)."""
        Path(path).write_text(self.pipeline().to_json(), encoding="utf-8")
        self.log_message(self.tr("pipeline saved to {0}").format(path))

    def load_pipeline(self, path: Path, tell: bool = False) -> list[str]:
        """Put a saved pipeline's parameters into the panel and its stages into Run ▸
        Pipeline stages (a Maneuvers stage is run as part of Compress); returns the
        problems, each also in the log, and says in the status bar whether there are any
        (``tell``: Run ▸ Load pipeline; the problems in a dialog too).

        Run ▸ pipeline's stages are check boxes in a fixed order (Clean, then Compress
        with its maneuvers, then Associate): a file whose stages come in another order
        (valid for ``wakeline batch``, which runs them as written: ``core.batch.
        check_pipeline`` takes the per-track stages in any order), or twice, or without
        Clean, is not run as written; each such change is a problem (review h158: a file
        of compress, clean ran clean, compress without a word)."""
        from wakeline.core.pipeline import params_to_json

        try:
            pipe = Pipeline.from_json(Path(path).read_text(encoding="utf-8"))
        except (InputError, OSError) as exc:
            self.tell(self.tr("Cannot load pipeline"), str(exc))
            return [str(exc)]
        keys = {"clean", *self.params.keys()}
        problems = []
        for _name, params in pipe.stages:
            data = params_to_json(params)
            problems += self.params.from_dict({k: v for k, v in data.items() if k in keys})
        names = [name for name, _ in pipe.stages]
        for name in dict.fromkeys(names):
            if name not in WINDOW_ORDER:
                problems.append(
                    self.tr(
                        "the pipeline's {0} stage is not run by Run ▸ pipeline (clean, "
                        "compress, associate); its parameters are loaded"
                    ).format(name)
                )
        stages = ["compress"] if {"maneuvers", "compress"} & set(names) else []
        self.set_pipeline_stages(stages + (["associate"] if "associate" in names else []))
        problems += self._pipeline_changes(names)
        for text in problems:
            self.log_message(f"{self.tr('Warning')}: {text}")
        runs = ", ".join(self.job_title(s) for s in self.pipeline_stages)
        if problems:
            text = self.tr("Pipeline loaded, not as written ({0} changes, see the Log): runs {1}")
            self.statusBar().showMessage(text.format(len(problems), runs))
            if tell and getattr(self, "interactive", True):
                QtWidgets.QMessageBox.information(
                    self,
                    self.tr("Pipeline loaded, not as written"),
                    shown("\n\n".join(problems)),
                )
        else:
            self.statusBar().showMessage(self.tr("Pipeline loaded: runs {0}").format(runs), 8000)
        return problems

    def _pipeline_changes(self, names: list[str]) -> list[str]:
        """What Run ▸ pipeline (``self.pipeline_stages``, just set) runs otherwise than a
        file's stages ``names`` say: a stage added, merged, run once or moved."""
        tr, title = self.tr, self.job_title
        out = []
        known = [n for n in names if n in WINDOW_ORDER]
        if "clean" not in known:
            out.append(
                tr("the pipeline has no clean stage; Run ▸ pipeline cleans first all the same")
            )
        if "maneuvers" in known and "compress" not in known:
            out.append(
                tr(
                    "the pipeline's maneuvers stage is run as Compress (maneuvers, then "
                    "compress): Run ▸ pipeline has no maneuvers-only stage"
                )
            )
        for name in dict.fromkeys(known):
            if known.count(name) > 1:
                text = tr(
                    "the pipeline's {0} stage comes {1} times; Run ▸ pipeline runs it once, "
                    "with the parameters of the last"
                )
                out.append(text.format(title(name), known.count(name)))
        order = list(dict.fromkeys(known))
        if order != sorted(order, key=WINDOW_ORDER.index):
            text = tr(
                "Run ▸ pipeline runs its stages in the order {0}, not as the file has them "
                "({1}): its stages have a fixed order (wakeline batch runs the file as written)"
            )
            out.append(
                text.format(
                    ", ".join(title(s) for s in self.pipeline_stages),
                    ", ".join(title(s) for s in order),
                )
            )
        return out

    def _pipeline_dialog(self, save: bool) -> None:
        dialog = (
            QtWidgets.QFileDialog.getSaveFileName if save else QtWidgets.QFileDialog.getOpenFileName
        )
        path, _ = dialog(self, self.tr("Pipeline"), "", "Wakeline pipeline (*.json)")
        if not path:
            return
        if save:
            self.save_pipeline(Path(path))
            return
        self.load_pipeline(Path(path), tell=True)

    # -- messages ------------------------------------------------------------------

    def _start(self, name: str, fn, context: tuple, again=None, automatic=False) -> int:
        """Run ``fn`` in the worker (one job at a time). ``again``: the job to run again
        when its result comes back stale (``fn`` itself when None). ``automatic``: the
        window starts it by itself (``_follow_up``), not the operator."""
        running = list(self._job_context) if self.runner.busy else []
        job = self.runner.run(name, fn)
        # One job at a time: an older job's result will never be applied; its
        # cancellation names the job that took its place (an Associate of ATD dataset1
        # was cancelled by File ▸ Open of another file, the log said only "cancelled").
        for old in running:
            self._replaced[old] = name
        self._job_context = {job: context}
        # What to run again when its result comes back stale (Session.stale).
        self._job_fns = {job: (name, again or fn, context)}
        if automatic:
            self._automatic.add(job)
        return job

    def _follow_up(self, msg) -> bool:
        """A re-run of Associate or Fuse (a pipeline's too) on a layer the operator went
        on reviewing while it ran is reconciled with the decisions as they are now, not
        applied as the worker made it:

        - decisions that change the pairs it keeps out (a pair rejected or split, or a
          reject taken back: ``Session.stale``) put it out of date: the same job runs
          again, reading the decisions as they are now;
        - any other decisions made meanwhile (``Session.late_decisions``) are carried:
          the carry is made again in the worker (``Session.reconcile``; hundreds of
          carried accepts take longer than a GUI turn may), then this check repeats.

        Returns True when a job took the result's place (nothing applied yet)."""
        job = self._job_fns.pop(msg.job, None)
        done = msg.result
        if job is None or not (
            isinstance(done, tuple) and done[:1] in (("step",), ("fuse_layers",))
        ):
            return False
        result = done[2]
        name, fn, context = job
        if self.session.stale(result):
            self.log_message(
                self.tr(
                    "{0}: decisions made while it ran change the pairs it keeps out; it "
                    "runs again with them"
                ).format(name)
            )
            self._start(name, fn, context, automatic=True)
            return True
        if not self.session.late_decisions(result):
            return False
        session = self.session

        def reconcile(progress):
            progress(0.0, "carrying the decisions made while it ran")
            session.reconcile(result)
            return done

        self._start(name, reconcile, context, again=fn, automatic=True)
        return True

    def _start_export(self, path: Path, write, context: tuple) -> int:
        """Write a file in the export runner: exports queue one after the other and never
        cancel a step (nor a step them). ``write(target)`` writes ``path`` (every writer
        goes through ``core.io.writer.atomic_path``: a temporary file moved into place,
        a read-only target refused) and returns the job's result; a file written is
        reported as written even if a cancel came during the write."""
        path = Path(path)

        def job(_progress):
            return write(path)

        job.keeps_result = True
        number = new_job_number()
        self._export_queue.append((number, job, context))
        if self._export_running is None:
            self._next_export()
        else:
            self.log_message(
                self.tr("export of {0} waits for the export running").format(context[1])
            )
        return number

    def _next_export(self) -> None:
        self._export_running = None
        if self._export_queue:
            number, job, context = self._export_queue.pop(0)
            self._export_context[number] = context
            self._export_running = self.export_runner.run("export", job, job=number)

    def cancel_jobs(self) -> None:
        """The Cancel button: stop the running step and export; queued exports are
        dropped (said in the log)."""
        for _number, _job, context in self._export_queue:
            self.log_message(
                self.tr("export of {0} cancelled before it started").format(context[1])
            )
        self._export_queue.clear()
        self.runner.cancel()
        self.export_runner.cancel()

    @property
    def jobs_busy(self) -> bool:
        """A step or an export is running (or waits), or a job's result is not applied."""
        return bool(
            self.runner.busy
            or self._job_context
            or self.export_runner.busy
            or self._export_context
            or self._export_queue
        )

    def _on_job_message(self, msg) -> None:
        if msg.job in self._export_context and isinstance(msg, Progress):
            if self.runner.busy:  # the step's progress keeps the bar
                return
        if isinstance(msg, Started):
            if msg.name == self.stale_label.property("step"):
                self.stale_label.hide()  # the step runs again
            self.progress.setValue(0)
            self.progress.show()
            self.cancel_button.show()
            self.actions_["cancel"].setEnabled(True)  # off while nothing runs (h225 item 14)
            self.statusBar().showMessage(self.tr("Running {0}…").format(self.job_title(msg.name)))
            return
        if isinstance(msg, Progress):
            self.progress.setValue(int(msg.fraction * 1000))
            if msg.text:  # the core's words, in the window's language
                self.statusBar().showMessage(shown(msg.text))
            return
        export = msg.job in self._export_context
        context = self._export_context if export else self._job_context
        step, base = context.pop(msg.job, (msg.name, ""))
        if not (self._job_context or self._export_context):
            self.progress.hide()
            self.cancel_button.hide()
            self.actions_["cancel"].setEnabled(False)
        if export:  # the next export in the queue starts once this one ended
            QtCore.QTimer.singleShot(0, self, self._next_export)  # not once it is deleted
        # A replaced job may end otherwise than cancelled (done before it looked): its
        # entry goes with its last message whatever that is.
        by = self._replaced.pop(msg.job, None)
        automatic = msg.job in self._automatic
        self._automatic.discard(msg.job)
        if isinstance(msg, Finished) and self._follow_up(msg):
            return
        # Its function (kept for a stale re-run) goes with the job's end, whatever it is:
        # a Failed or Cancelled job's closure held its inputs' points (Fuse: every layer
        # fused) after the window closed (review h158).
        self._job_fns.pop(msg.job, None)
        if isinstance(msg, Finished):
            self._apply(msg.result)
            self.statusBar().showMessage(
                self.tr("{0} done in {1:.1f} s").format(self.job_title(msg.name), msg.seconds),
                8000,
            )
        elif isinstance(msg, Failed) and automatic:
            self._automatic_failed(msg)
        elif isinstance(msg, Failed):
            title = self.tr("{0} failed").format(self.job_title(msg.name))
            self.statusBar().showMessage(title, 8000)
            self.log_message(
                f"{self.tr('Error')} ({self.job_title(msg.name)}): {shown(msg.message)}"
            )
            if msg.detail:
                self.log_message(msg.detail)
            # a screenshot run: nobody to close a dialog; said on stderr, in the window's
            # language, as its title (operator test 7, D11)
            self.tell(title, shown(msg.message), cli=shown_cli(msg.message))
        elif isinstance(msg, Cancelled):
            # the jobs by their titles, as the failed dialog names them (not "pipeline")
            name = self.job_title(msg.name)
            if by is None:
                self.log_message(self.tr("{0} cancelled").format(name))
            else:
                text = self.tr(
                    "{0} cancelled: {1} took its place (one job at a time); run {0} again "
                    "once it is done"
                )
                self.log_message(text.format(name, self.job_title(by)))
            self.statusBar().showMessage(self.tr("{0} cancelled").format(name), 5000)

    def stale_text(self, step: str) -> str:
        """The red status label's text for ``step``'s failed automatic re-run."""
        return self.tr("{0}: out of date, its re-run failed").format(self.job_title(step))

    def stale_message(self, step: str) -> str:
        """The status bar's (and the red label's tooltip's) sentence for ``step``'s failed
        automatic re-run."""
        return self.tr(
            "{0}, run again by itself for the decisions made while it ran, failed: its "
            "result is out of date (stale) and was not applied; run {0} again"
        ).format(self.job_title(step))

    def restale(self) -> None:
        """The red label and its tooltip in the window's language: a language switch
        redoes both (h179; the tooltip kept the language it was made in)."""
        step = self.stale_label.property("step")
        if not step:
            return
        self.stale_label.setText(self.stale_text(step))
        error = shown(self.stale_label.property("error"))
        self.stale_label.setToolTip(f"{self.stale_message(step)}\n{error}")

    def _automatic_failed(self, msg) -> None:
        """A job the window ran again by itself (decisions made while the step ran put
        its result out of date) failed: the status bar and the log say so, and that the
        out-of-date result was not applied; no dialog the operator did not ask for
        (review h158). The layers stay as they were before the run."""
        name = self.job_title(msg.name)
        text = self.stale_message(msg.name)
        self.statusBar().showMessage(text)
        self.stale_label.setProperty("step", msg.name)
        self.stale_label.setProperty("error", str(msg.message))
        self.restale()
        self.stale_label.show()
        self.log_message(f"{self.tr('Error')} ({name}): {shown(msg.message)}")
        if msg.detail:
            self.log_message(msg.detail)
        self.log_message(text)

    def show_bearing_layer(self, view) -> None:
        """A bearing layer's data in the Bearing-only dock (its map and detections) and
        the Detail panel (the sequences and z)."""
        bearings, detections = view.points, view.extra["detections"]
        self.bearings, self.bearing_detections = bearings, detections
        self.bearing_view.show_result(
            bearings, detections, view.extra["report"], scene=view.extra["scene"]
        )
        self.detail.show_bearings(
            bearings, detections, self.params.params("bearing"), view.extra.get("curves")
        )

    def _apply(self, done: tuple) -> None:
        kind = done[0]
        if kind == "import":
            self._plan_view(done[3])  # the view the layers' level of detail was made for
            before = set(self.session.layers)
            try:
                for item in done[1]:
                    self._apply_import(*item)
            finally:
                self._view_planned = False
            if self.vessels_after_load is not None:  # wakeline gui --vessels FILE
                self._vessels_after_import([i for i in self.session.layers if i not in before])
            for text in done[2]:
                self.log_message(f"{self.tr('Error')}: {shown(text)}")
            if done[2]:
                text = "\n".join(shown(t) for t in done[2])
                cli = "\n".join(shown_cli(t) for t in done[2])
                self.tell(self.tr("Cannot open file"), text, cli=cli)
        elif kind == "step":
            _, lid, result, views, params = done
            self._apply_step(lid, result, views, params)
            name = shown_name(self.session.layers[lid].name) if lid in self.session.layers else lid
            self.log_lines(
                self.tr("{0} on {1}").format(shown(result.step), name), step_lines(result)
            )
        elif kind == "bearing":
            _, path, quarantine, result, view, sha, plan = done
            from wakeline.core.bearing_read import summary_lines

            lines = summary_lines(view.extra.get("read") or {})  # every line, and where
            for line in lines:
                self.log_message(f"{path.name}: {shown(line)}")
            if len(quarantine) and not lines:
                reasons = "; ".join(
                    f"{n:,} {shown(why)}" for why, n in quarantine["reason"].value_counts().items()
                )
                self.log_message(f"bearing: {len(quarantine):,} lines quarantined ({reasons})")
            self.log_message(f"bearing: {summarize(result.report)}")
            for line in result.report.get("why", []):
                self.log_message(f"    {line}")
            if view.extra["scene"] is None:
                self.log_message(
                    self.tr("bearing: no observer position, nothing to draw on the map")
                )
            self._apply_bearings(path, view, sha, plan)
            self.show_bearing_layer(view)
            # The Bearing-only dock (map and detections) comes to the front, not the
            # Detail dock's tab of the same name behind which it was tabbed.
            self.docks["bearing"].show()
            self.docks["bearing"].raise_()
        elif kind == "project":
            self._apply_project(*done[1:])
        elif kind == "fuse_layers":
            from wakeline.app.review_sync import apply_fused

            apply_fused(self, *done[1:])
        elif kind == "vessels":
            self._apply_vessels(*done[1:])
        elif kind == "export":
            self.log_message(self.tr("exported {0} to {1}").format(shown_name(done[1]), done[2]))
            for warning in done[3] if len(done) > 3 else []:
                self.log_message(f"{self.tr('Warning')}: {warning}")
            for note in done[4] if len(done) > 4 else []:
                self.log_message(f"    {note}")

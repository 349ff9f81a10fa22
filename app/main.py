"""Start the desktop application."""

import gc
import shutil
import sys
import tempfile
import traceback
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import i18n
from wakeline.app.main_window import MainWindow
from wakeline.resources import demo_path, resource_path

#: The translation context of the texts here: the excepthook calls the window's ``tr``.
TR_CONTEXT = "MainWindow"


def wait_for_jobs(window: MainWindow, timeout_ms: int = 120_000) -> None:
    """Run the event loop until the window's worker has no job left (tests, screenshots,
    benchmarks): a nested event loop, as the application's own, that a 5 ms timer ends."""
    app = QtWidgets.QApplication.instance()

    def busy() -> bool:
        return bool(window.jobs_busy or window.drawing or window.canvas.lod_busy)

    if busy():
        elapsed = QtCore.QElapsedTimer()
        elapsed.start()
        loop = QtCore.QEventLoop()
        check = QtCore.QTimer()
        check.setInterval(5)
        check.timeout.connect(
            lambda: loop.quit() if not busy() or elapsed.elapsed() >= timeout_ms else None
        )
        check.start()
        loop.exec()
        check.stop()
    app.processEvents()


def install_excepthook(window: MainWindow) -> None:
    """No exception escapes unseen: log it (stderr and the window's log) and show it."""

    def hook(kind, exc, tb) -> None:
        text = "".join(traceback.format_exception(kind, exc, tb))
        print(text, file=sys.stderr)
        try:
            window.log_message(text)
            QtWidgets.QMessageBox.critical(
                window,
                window.tr("Unexpected error"),
                f"{kind.__name__}: {exc}\n\n" + window.tr("The details are in the log."),
            )
        except Exception:  # noqa: BLE001 - the hook itself must never raise
            pass

    sys.excepthook = hook


def freeze_startup_objects() -> None:
    """Put every object alive now out of the cyclic garbage collector's reach.

    The modules, classes and functions of Qt, pandas, pyarrow, scipy, pyqtgraph and the
    window's wrappers are ~180 k objects, and a full collection walks them all: 200–300 ms
    on this machine, on the GUI thread, or from a worker with the GIL held — the longest
    blocks of the window at a million points were such collections. They live as long as
    the process, so they are frozen once the window is built (``gc.freeze``); objects
    made later are collected as usual."""
    gc.collect()
    gc.freeze()


def plots_only(window: MainWindow, lid: str) -> bool:
    """Whether layer ``lid`` is mostly radar plots (its prepared view says so: the
    parameter guidance's test, :func:`wakeline.app.layer_view.looks_like_plots`)."""
    view = window.views.get(lid)
    return bool(view is not None and view.extra.get("plots"))


def run(
    files: list[Path] | None = None,
    screenshot: Path | None = None,
    read: dict | None = None,
    language: str | None = None,
    vessels: Path | None = None,
) -> int:
    """Open the main window on ``files`` (default: the demo scene), read with ``read``
    (``read_points`` keywords: the command line's reading flags, e.g. ``origin``).

    With ``screenshot``: load, run the default pipeline (clean, maneuvers, compress) on
    the first file, render the window at 1400×900 to that PNG and return. A first file
    that is mostly radar plots is shown as it is (dots, the guidance), the steps not run,
    and stderr says why.

    ``language`` (``en``, ``zh_CN``): the window's; None: the saved choice, or the
    system's ($LANG) — a screenshot the system's, so that it shows what the operator sees
    (operator test 6, D-gui-5; tests give it).
    """
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    app.setApplicationName("Wakeline")
    app.setWindowIcon(QtGui.QIcon(str(resource_path("icons", "wakeline.png"))))
    settings = None
    if screenshot is not None:
        # A screenshot must not depend on (or change) the user's saved window layout.
        # ...so its settings live in a throw-away folder.
        scratch = tempfile.mkdtemp(prefix="wakeline-shot-")
        settings = QtCore.QSettings(
            str(Path(scratch) / "settings.ini"), QtCore.QSettings.Format.IniFormat
        )
        settings.clear()
        settings.setValue("language", language or i18n.system_language())
    elif language:  # the interactive window: as if chosen in the Language menu
        settings = QtCore.QSettings("Wakeline", "Wakeline")
        settings.setValue("language", language)
    window = MainWindow(settings)
    window.interactive = screenshot is None  # no modal dialogs while making a screenshot
    window.resize(1400, 900)
    freeze_startup_objects()
    if screenshot is None:
        install_excepthook(window)
    paths = [Path(p) for p in files or [demo_path()]]
    window.vessels_after_load = Path(vessels) if vessels is not None else None
    window.load_files(paths, dict(read or {}) if files else None)
    loaded = [True]
    if screenshot is not None:
        wait_for_jobs(window)
        loaded = [window.layer_id(p.name) is not None for p in paths]
    if screenshot is not None:
        window.show()
        sources = [i for i, lay in window.layers.items() if lay.kind == "source"]
        plots = bool(sources) and plots_only(window, sources[0])
        if plots:
            # Radar plots (detections of each scan, the guidance's test): the track steps
            # would take each batch for a ship's track and draw a scribble. Shown as they
            # are, as dots, with the guidance; said on stderr (no one reads the Log).
            window.select_layer(sources[0])
            wait_for_jobs(window)
            name = window.layers[sources[0]].name
            guidance = " ".join(window.params.guidance.text().split())
            said = window.tr(
                "most of it looks like radar plots, not tracks: the track steps "
                "(clean, maneuvers, compress) were not run; the screenshot shows the "
                "plots as dots"
            )
            window.log_message(f"{window.tr('Warning')}: {name}: {said}")
            print(f"wakeline: {name}: {said}", file=sys.stderr)
            if guidance:
                print(f"wakeline: {guidance}", file=sys.stderr)
            window.canvas.frame()
        elif sources:
            window.select_layer(sources[0])
            window.run_step("pipeline")
            wait_for_jobs(window)
            comp = [i for i, lay in window.layers.items() if lay.kind == "compressed"]
            if comp:
                window.select_layer(comp[0])
                frame = window.batch_model.frame
                # Show the longest track of the most accurate sensor (AIS when present).
                ais = frame[frame["sensor"].astype(str) == "AIS"]
                keys = (ais if len(ais) else frame).sort_values("duration_s", ascending=False)
                if len(keys):
                    window.select_tracks([(str(keys["sensor"].iat[0]), str(keys["batch"].iat[0]))])
            window.canvas.frame()  # where the points are, as the window first shows them
        for _ in range(10):
            app.processEvents()
            QtCore.QThread.msleep(20)
        ok = window.grab().save(str(screenshot))
        window.close()  # stops the jobs (a few seconds' wait each) and the docks
        # Deleted here, its jobs ended first: a window left behind (frozen above) lived on
        # in the tests until a later test's teardown deleted it.
        window.runner.wait()
        window.export_runner.wait()
        window.lod_worker.wait()
        window.deleteLater()
        QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)
        del window, settings
        shutil.rmtree(scratch, ignore_errors=True)
        return 0 if ok and all(loaded) else 2
    window.show()
    return app.exec()

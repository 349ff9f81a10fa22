"""Start the desktop application."""

import shutil
import sys
import tempfile
import traceback
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.main_window import MainWindow
from wakeline.resources import demo_path, resource_path


def wait_for_jobs(window: MainWindow, timeout_ms: int = 120_000) -> None:
    """Process events until the window's worker has no job left (tests, screenshots)."""
    app = QtWidgets.QApplication.instance()
    timer = QtCore.QElapsedTimer()
    timer.start()
    while (
        window.runner.busy or window._job_context or window.drawing
    ) and timer.elapsed() < timeout_ms:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 50)
        QtCore.QThread.msleep(5)
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


def run(files: list[Path] | None = None, screenshot: Path | None = None) -> int:
    """Open the main window on ``files`` (default: the demo scene).

    With ``screenshot``: load, run the default pipeline (clean, maneuvers, compress) on
    the first file, render the window at 1400×900 to that PNG and return.
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
        settings.setValue("language", "en")
    window = MainWindow(settings)
    window.resize(1400, 900)
    if screenshot is None:
        install_excepthook(window)
    paths = [Path(p) for p in files or [demo_path()]]
    window.load_files(paths)
    loaded = [True]
    if screenshot is not None:
        wait_for_jobs(window)
        loaded = [window.layer_id(p.name) is not None for p in paths]
    if screenshot is not None:
        window.show()
        sources = [i for i, lay in window.layers.items() if lay.kind == "source"]
        if sources:
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
            window.canvas.fit()
        for _ in range(10):
            app.processEvents()
            QtCore.QThread.msleep(20)
        ok = window.grab().save(str(screenshot))
        window.close()
        del window, settings
        shutil.rmtree(scratch, ignore_errors=True)
        return 0 if ok and all(loaded) else 2
    window.show()
    return app.exec()

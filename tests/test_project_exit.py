"""A program that ends without closing its window while a project write is queued
(operator test h150, defect 10): the write is made before the interpreter goes, and a
writer's error never escapes its thread into a controller that is gone."""

import logging
import os
import subprocess
import sys
import textwrap
import threading

from wakeline.core.project import ProjectWriter, load_project

SCRIPT = textwrap.dedent(
    """
    import sys, time
    from pathlib import Path
    from PySide6 import QtCore, QtWidgets
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    out = Path(sys.argv[1])
    src = out / "scene.csv"
    write_points(simulate.multisensor_scene(seed=3, n_ships=12, area_km=30.0), src)
    settings = QtCore.QSettings(str(out / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "en")
    w = MainWindow(settings)
    w.load_files([src])
    wait_for_jobs(w)
    w.save_project(out / "p.wakeline")
    assert w.project.flush(60)
    w.project.writer.submit(lambda st: time.sleep(1.0))  # busy when the script ends
    w.run_step("clean")
    wait_for_jobs(w)
    print("queued", flush=True)
    """
)


def test_a_write_queued_when_the_program_ends_is_made(tmp_path):
    """Before: "Exception in thread wakeline-project: RuntimeError: cannot schedule new
    futures after interpreter shutdown", then "Signal source has been deleted", and the
    cleaned layer was missing from the project."""
    run = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=240,
        env={**os.environ, "QT_QPA_PLATFORM": "offscreen"},
    )
    assert run.returncode == 0, run.stderr
    assert "queued" in run.stdout
    assert "Traceback" not in run.stderr and "Exception in thread" not in run.stderr
    names = [lay.name for lay in load_project(tmp_path / "p.wakeline").layers]
    assert names == ["scene.csv", "scene.csv · cleaned"]


def test_an_error_the_caller_cannot_take_is_logged_not_raised(tmp_path, caplog):
    caught = []
    previous = threading.excepthook
    threading.excepthook = caught.append
    try:

        def gone(_exc):
            raise RuntimeError("Signal source has been deleted")

        writer = ProjectWriter(tmp_path / "missing.wakeline", gone)
        with caplog.at_level(logging.ERROR, logger="wakeline.project"):
            writer.submit(lambda st: None)  # the file is not there: the write fails
            writer.close(30)
    finally:
        threading.excepthook = previous
    assert not writer.busy() and not caught
    assert "could not be reported: Signal source has been deleted" in caplog.text

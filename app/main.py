"""Start the desktop application."""

import sys
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from wakeline.app.main_window import MainWindow
from wakeline.resources import demo_path


def run(files: list[Path] | None = None, screenshot: Path | None = None) -> int:
    """Open the main window on ``files`` (default: the demo scene).

    With ``screenshot``, render the window at 1400×900 to that PNG and return at once.
    """
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    app.setApplicationName("Wakeline")
    window = MainWindow()
    window.resize(1400, 900)
    for path in files or [demo_path()]:
        window.load_file(Path(path))
    if screenshot is not None:
        window.show()
        for _ in range(5):
            app.processEvents()
            QtCore.QThread.msleep(20)
        ok = window.grab().save(str(screenshot))
        window.close()
        return 0 if ok else 2
    window.show()
    return app.exec()

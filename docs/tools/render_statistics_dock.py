"""Render the window offscreen with a track file open and the Statistics dock raised.

python docs/tools/render_statistics_dock.py FILE OUT.png   (docs/statistics-dock.png: MTAD Scene-35)
"""

import os
import sys
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
from pathlib import Path

from PySide6 import QtWidgets

from wakeline.app.main import wait_for_jobs
from wakeline.app.main_window import MainWindow

app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
w = MainWindow()
w.resize(1500, 950)
w.show()
path = Path(sys.argv[1])
w.load_file(path)
wait_for_jobs(w)
lid = w.layer_id(path.name)
end = time.time() + 30
while time.time() < end and not (w.stats.shown_key and w.stats.shown_key[0] == lid):
    app.processEvents()
    time.sleep(0.02)
for dock in w.findChildren(QtWidgets.QDockWidget):
    if "Statistics" in dock.windowTitle():
        dock.show()
        dock.raise_()
        from PySide6 import QtCore

        w.resizeDocks([dock], [330], QtCore.Qt.Orientation.Vertical)
end = time.time() + 2
while time.time() < end:
    app.processEvents()
    time.sleep(0.02)
w.grab().save(sys.argv[2])
print("saved", sys.argv[2])

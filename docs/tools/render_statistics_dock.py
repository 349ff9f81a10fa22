"""Render the window offscreen, as `wakeline gui` opens it (1400×900, the default dock
layout: settings of its own, none of the user's), with a track file open and the
Statistics dock raised; prints the histogram's height and its bars' (px).

python docs/tools/render_statistics_dock.py FILE OUT.png   (docs/statistics-dock.png: MTAD Scene-35)
"""

import os
import sys
import tempfile
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
from pathlib import Path

from PySide6 import QtCore, QtWidgets

from wakeline.app.main import wait_for_jobs
from wakeline.app.main_window import MainWindow

app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
scratch = Path(tempfile.mkdtemp(prefix="wakeline-shot-")) / "settings.ini"
settings = QtCore.QSettings(str(scratch), QtCore.QSettings.Format.IniFormat)
settings.setValue("language", "en")
w = MainWindow(settings)
w.resize(1400, 900)  # as app/main.py opens it
w.show()
path = Path(sys.argv[1])
w.load_file(path)
wait_for_jobs(w)
lid = w.layer_id(path.name)
end = time.time() + 30
while time.time() < end and not (w.stats.shown_key and w.stats.shown_key[0] == lid):
    app.processEvents()
    time.sleep(0.02)
w.docks["stats"].raise_()
end = time.time() + 2
while time.time() < end:
    app.processEvents()
    time.sleep(0.02)
w.grab().save(sys.argv[2])
bars = w.stats.hist.getPlotItem().getViewBox().sceneBoundingRect().height()
print(f"saved {sys.argv[2]}: histogram {w.stats.hist.height()} px high, its bars {bars:.0f} px")

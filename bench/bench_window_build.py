"""CPU to construct a MainWindow offscreen: the first one in a process (with the jobs'
module preload) and a second one (what each further GUI test's window costs).

    QT_QPA_PLATFORM=offscreen python bench/bench_window_build.py [--runs 5] [--profile]

Each run is a fresh process; the medians of the runs are printed. ``--profile`` prints
the second window's cProfile, sorted by cumulative time, instead.
"""

import argparse
import json
import statistics
import subprocess
import sys

ONE_RUN = """
import cProfile, json, os, pstats, sys, tempfile, time
from PySide6 import QtCore, QtWidgets
app = QtWidgets.QApplication([])
from wakeline.app.main_window import MainWindow
ini = os.path.join(tempfile.mkdtemp(), "settings.ini")
s = QtCore.QSettings(ini, QtCore.QSettings.Format.IniFormat)
t = time.process_time(); w1 = MainWindow(s); first = time.process_time() - t
prof = cProfile.Profile() if sys.argv[1] == "1" else None
if prof: prof.enable()
t = time.process_time(); w2 = MainWindow(s); second = time.process_time() - t
if prof:
    prof.disable(); pstats.Stats(prof).sort_stats("cumtime").print_stats(40)
else:
    print(json.dumps({"first": first, "second": second}))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--profile", action="store_true")
    a = ap.parse_args()
    if a.profile:
        subprocess.run([sys.executable, "-c", ONE_RUN, "1"], check=True)
        return
    runs = []
    for _ in range(a.runs):
        out = subprocess.run(
            [sys.executable, "-c", ONE_RUN, "0"], check=True, capture_output=True, text=True
        )
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    for key in ("first", "second"):
        xs = [r[key] for r in runs]
        print(
            f"{key} window: median {statistics.median(xs):.3f} s CPU "
            f"(runs {', '.join(f'{x:.3f}' for x in xs)})"
        )


if __name__ == "__main__":
    main()

"""The time slider on a million points (issue 13): the longest event-loop block of a
slider move, of playback and of switching the time window on and off, in the main window.

Same 10 ms timer probe as :mod:`bench_gui` (wall, and the GUI thread's own CPU time in
the same gap, which a loaded machine does not inflate). The baseline, measured in the same run, is
a pan of the map (a redraw of the same layers without the time overlay). The goal is
< 100 ms for every action.

    QT_QPA_PLATFORM=offscreen .venv/bin/python bench/bench_time.py [--points 1000000]
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_gui import Probe, make_scene, settle  # noqa: E402
from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app.main import wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402


def wait_time(window) -> None:
    """Until the time index, frames and window cuts are through."""
    app = QtWidgets.QApplication.instance()
    end = time.perf_counter() + 120
    while window.time_controller.busy and time.perf_counter() < end:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
        QtCore.QThread.msleep(2)


def measure(name: str, action, window, results: dict) -> None:
    t0 = time.perf_counter()
    with Probe() as probe:
        action()
        wait_time(window)
        settle(300)
    results[name] = probe.block_ms
    print(
        f"{name:<34} longest block {probe.block_ms:7.0f} ms, GUI-thread CPU in one gap "
        f"{probe.cpu_ms:5.0f} ms   ({time.perf_counter() - t0:5.1f} s)"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=1_000_000)
    args = ap.parse_args()
    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        path = tmp / "million.csv"
        write_points(make_scene(args.points), path)
        settings = QtCore.QSettings(str(tmp / "s.ini"), QtCore.QSettings.Format.IniFormat)
        window = MainWindow(settings)
        window.resize(1400, 900)
        window.show()
        window.load_file(path)
        wait_for_jobs(window, 600_000)
        wait_time(window)
        settle(500)
        with open("/proc/loadavg") as f:
            load = f.read().split()[0]
        print(f"{args.points:,} points; load {load}; probe period 10 ms")
        panel, results = window.time_panel, {}
        lo, hi = panel.time_range()
        x0, x1, y0, y1 = window.canvas.current_view()
        dx = (x1 - x0) * 0.05
        measure(
            "baseline: pan the map",
            lambda: window.canvas.vb.setRange(xRange=(x0 + dx, x1 + dx), padding=0),
            window,
            results,
        )
        for k, f in enumerate((0.3, 0.5, 0.7)):
            measure(
                f"slider move {k + 1} (t at {f:.0%})",
                lambda f=f: panel.set_time(lo + f * (hi - lo)),
                window,
                results,
            )
        panel.set_time(lo + 0.2 * (hi - lo))
        panel.speed.setValue(600)

        def play() -> None:
            panel.play()
            settle(2000)
            panel.pause()

        measure("play 2 s at ×600", play, window, results)
        measure(
            "time window on (30 %–60 %)",
            lambda: panel.set_time_window((lo + 0.3 * (hi - lo), lo + 0.6 * (hi - lo))),
            window,
            results,
        )
        measure("time window off", lambda: panel.set_time_window(None), window, results)
        with open("/proc/loadavg") as f:
            load = f.read().split()[0]
        print(f"load after: {load}")
        window.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

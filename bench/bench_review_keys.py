"""GUI-thread CPU time per review key (accept / reject in turn) on the layer Associate
makes of ATD dataset1 (102,861 points, 5,620 tracks): each key and everything it sets
off on the GUI thread (the queue's views, the decision's layer swapped in 300 ms later:
batch table, map, selection) until the window is idle again, by ``time.thread_time`` of
the GUI thread (the machine's load does not count, unlike a wall-clock probe), after
two keys not counted; then "select source" the same way. The keys are timed with the
batch table's index made on the GUI thread ("before": ``models.TABLE_INDEX_IN_WORKER =
False``) and made in the worker with the layer's view ("after"), alternating in one run.

    WAKELINE_SHARED=/work/shared QT_QPA_PLATFORM=offscreen python bench/bench_review_keys.py [keys]
"""

import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app import models  # noqa: E402


def main() -> None:
    keys = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    shared = Path(os.environ.get("WAKELINE_SHARED", "/work/shared"))
    path = shared / "data/real/atd2025-noaa/dataset1_truth.csv.gz"
    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    from wakeline.app.main import freeze_startup_objects
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope,
                                "wakeline-bench", "review-keys")  # fmt: skip
    settings.setValue("language", "en")
    w = MainWindow(settings)
    w.resize(1600, 1000)
    w.show()
    freeze_startup_objects()

    def settle(quiet_s: float = 0.4) -> None:
        """Run the event loop (idle: no CPU) until the window has been idle quiet_s."""
        loop, timer, since = QtCore.QEventLoop(), QtCore.QTimer(), [None]
        timer.setInterval(100)

        def check():
            if w.runner.busy or w.drawing or w.review.busy or w._job_context:
                since[0] = None
            elif since[0] is None:
                since[0] = time.monotonic()
            elif time.monotonic() - since[0] > quiet_s:
                loop.quit()

        timer.timeout.connect(check)
        timer.start()
        loop.exec()
        timer.stop()

    def cpu_ms(fn) -> float:
        t = time.thread_time()
        fn()
        settle()
        return 1000 * (time.thread_time() - t)

    w.load_files([path])
    settle()
    src = w.active
    w.run_step("associate")
    settle()
    layer = next(lay for lay in w.session.layers.values() if lay.step == "associate")
    w.select_layer(layer.id)
    settle()
    bound = w.review.bound
    print(f"{len(layer.points):,} points, {len(w.batch_model.frame):,} tracks, "
          f"{len(bound.controller.state.proposals)} proposals")  # fmt: skip
    for act in (bound.panel.act_accept, bound.panel.act_reject):  # warm-up, not counted
        cpu_ms(act.trigger)
    times = {False: [], True: []}
    for i in range(2 * keys):
        models.TABLE_INDEX_IN_WORKER = worker = i % 2 == 1
        act = bound.panel.act_accept if i % 4 < 2 else bound.panel.act_reject
        times[worker].append(cpu_ms(act.trigger))
    select = {False: [], True: []}
    for i in range(6):
        models.TABLE_INDEX_IN_WORKER = worker = i % 2 == 1
        select[worker].append(cpu_ms(lambda: w.select_layer(src)))
        cpu_ms(lambda: w.select_layer(layer.id))
    for worker, name in ((False, "before (index on the GUI thread)"), (True, "after (index in the worker)")):  # fmt: skip
        t, s = times[worker], select[worker]
        print(f"{name}: key CPU ms median {statistics.median(t):.1f} max {max(t):.1f} "
              f"over {len(t)}; select source median {statistics.median(s):.1f} over {len(s)}")  # fmt: skip
    print("load average", " ".join(open("/proc/loadavg").read().split()[:3]))
    w.close()


if __name__ == "__main__":
    main()

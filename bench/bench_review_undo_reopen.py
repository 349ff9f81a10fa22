"""h196: what rebuilding the review's undo stack costs a reopen. A fused review of the
small simulated radar/AIS pair (tests' ``_sim_pair``) gets N decisions (accept / reject
in turn) and U undos, is saved and closed; then the project is reopened several times,
alternately with the stack rebuilt (``ReviewController.restore``) and without (restore
made a no-op: the reopen before h196), and a 10 ms QTimer on the GUI thread records the
gaps between its ticks from ``open_project`` until the window settles with the fused
layer's review shown. Also the GUI-thread time of ``restore`` itself and the cyclic
collector's share of it (``gc.callbacks``). The startup objects are frozen as the
application freezes them (``freeze_startup_objects``).

    WAKELINE_SHARED=/work/shared QT_QPA_PLATFORM=offscreen python bench/bench_review_undo_reopen.py \
        [N=500] [U=100] [runs=3]
"""

import gc
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from PySide6 import QtCore, QtWidgets  # noqa: E402


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 500
    u = int(sys.argv[2]) if len(sys.argv) > 2 else 100
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    from test_review_window import _settle, _sim_pair

    from wakeline.app import review_undo
    from wakeline.app.main import freeze_startup_objects
    from wakeline.app.main_window import MainWindow

    tmp = Path(tempfile.mkdtemp(prefix="h196_"))

    def window():
        s = QtCore.QSettings(str(tmp / "s.ini"), QtCore.QSettings.Format.IniFormat)
        s.setValue("language", "en")
        w = MainWindow(s)
        w.resize(1600, 1000)
        w.show()
        return w

    files = _sim_pair(tmp)
    w = window()
    freeze_startup_objects()  # as the application does (wakeline.app.main.run)
    w.load_files(files)
    _settle(w)
    w.layer_list.clearSelection()
    for f in files:
        w.layer_list.item(w.layer_row(w.layer_id(f.name))).setSelected(True)
    w.actions_["fuse"].trigger()
    _settle(w)
    fused = next(lay for lay in w.layers.values() if lay.step == "fuse").id
    w.select_layer(fused)
    _settle(w)
    proj = tmp / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    ctl = w.review.bound.controller
    pids = ctl.state.proposals["proposal"].tolist()
    t0 = time.perf_counter()
    for k in range(n):
        pid = pids[k % len(pids)]
        (ctl.reject if ctl.state.status_of(pid) == "accepted" else ctl.accept)(pid)
        if k % 50 == 49:
            _settle(w)
    for _ in range(u):
        ctl.stack.undo()
    _settle(w)
    print(f"{n} decisions + {u} undos on {len(pids)} proposals: {time.perf_counter() - t0:.1f} s")
    assert w.project.flush(60)
    w.close()
    w.deleteLater()

    real_restore = review_undo.ReviewController.restore
    spent: list[float] = []

    collected: list[float] = []  # the collector's time inside restore, ms
    started = [0.0]

    def on_gc(phase, info):
        if phase == "start":
            started[0] = time.perf_counter()
        elif started[0]:
            collected.append((time.perf_counter() - started[0]) * 1000)

    def timed_restore(self, changes, index):
        collected.clear()
        gc.callbacks.append(on_gc)
        t = time.perf_counter()
        try:
            real_restore(self, changes, index)
        finally:
            spent.append((time.perf_counter() - t) * 1000)
            gc.callbacks.remove(on_gc)
        spent.append(sum(collected))

    for run in range(runs):
        for rebuilt in (True, False):
            review_undo.ReviewController.restore = (
                timed_restore if rebuilt else (lambda self, changes, index: None)
            )
            w = window()
            _settle(w)
            gaps: list[float] = []
            last = [time.perf_counter()]

            def tick(gaps=gaps, last=last):
                now = time.perf_counter()
                gaps.append((now - last[0]) * 1000)
                last[0] = now

            timer = QtCore.QTimer()
            timer.setInterval(10)
            timer.timeout.connect(tick)
            timer.start()
            last[0] = time.perf_counter()
            t = time.perf_counter()
            w.open_project(proj)
            _settle(w)
            w.select_layer(fused)
            _settle(w)
            wall = time.perf_counter() - t
            timer.stop()
            st = w.review.bound.controller.stack
            over = sum(g > 100 for g in gaps)
            print(
                f"run {run} {'rebuilt' if rebuilt else 'not rebuilt'}: stack {st.count()} "
                f"at {st.index()}; reopen {wall:.2f} s, longest gap {max(gaps):.0f} ms, "
                f"gaps > 100 ms {over}"
                + (
                    f"; restore {spent[-2]:.1f} ms ({spent[-1]:.1f} ms of it collecting)"
                    if rebuilt
                    else ""
                )
            )
            w.close()
            w.deleteLater()
            QtWidgets.QApplication.processEvents()
    review_undo.ReviewController.restore = real_restore


if __name__ == "__main__":
    main()

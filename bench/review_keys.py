"""Event-loop blocks per review key (SPEC §7: no action blocks the GUI thread > 100 ms).

Loads a track file, runs Associate, selects its layer and decides ``keys`` proposals by
key press (A, R every 7th) with the focus on the queue, waiting (asleep, not spinning)
after each key until the review, the drawing and the level of detail are idle; keys
alternate between the batch table reset per decision ("before":
``models.TABLE_UPDATE_IN_PLACE = False``) and its cells updated in place ("after"), so
both see the same load, 2 x ``keys`` keys in all (after one warm-up key). A 10 ms
QTimer probe records every gap between its ticks: a gap of 60 ms means the GUI thread
was busy ~50 ms in one piece. Printed per run:

- ``idle``: the same probe for the same time with nothing happening (the machine's
  contention: other processes taking the 2 cores; not our work);
- per mode: per key the longest block (median, p95, max over keys) and the p95 of all
  gaps, the time to idle, paint events per widget class and batch-table model resets
  per key; and the GUI thread's CPU ms per key (``time.thread_time``, load-independent).

``--profile FILE`` writes a cProfile of the GUI thread during the "after" keys (pstats).

    WAKELINE_SHARED=/work/shared QT_QPA_PLATFORM=offscreen \\
        python bench/review_keys.py [--file atd|saronic|PATH] [--keys 20] [--profile F]

``atd`` (the default) is the ATD example truth in shared/ with mmsi_apart off (106
proposals on 5,405 tracks). ``saronic`` was session 28's scratch file (the Saronic day
split at gaps > 600 s: 111 tracks, 77 proposals), no longer kept: give it as a PATH
(or $WAKELINE_SARONIC_SPLIT). For a million points see bench/gui_block_probe.py, which
makes its own queue of 1,699 proposals on 1.1 M points.
"""

import argparse
import collections
import cProfile
import os
import statistics
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtWidgets  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402

FILES = {
    "saronic": Path(os.environ.get("WAKELINE_SARONIC_SPLIT", "saronic_split.csv")),
    "atd": Path("data/real/atd2025-noaa/example_truth.csv.gz"),
}


class Counter(QtCore.QObject):
    """Counts paint events per widget class (the class of the widget painted, or of its
    parent for a viewport)."""

    def __init__(self) -> None:
        super().__init__()
        self.paints: collections.Counter = collections.Counter()

    def eventFilter(self, obj, event) -> bool:  # noqa: N802 (Qt's name)
        if event.type() == QtCore.QEvent.Type.Paint:
            name = type(obj).__name__
            if name == "QWidget" and obj.parent() is not None:  # a scroll area's viewport
                name = type(obj.parent()).__name__
            self.paints[name] += 1
        return False


def pct(values: list[float], q: float) -> float:
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))] if s else 0.0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--file", default="atd")
    ap.add_argument("--keys", type=int, default=20)
    ap.add_argument("--profile")
    a = ap.parse_args()
    shared = Path(os.environ.get("WAKELINE_SHARED", "/work/shared"))
    path = FILES.get(a.file, Path(a.file))
    if a.file == "atd":
        path = shared / path
    if not path.exists():
        raise SystemExit(f"{path} not found (see the docstring: --file atd needs no scratch file)")
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    from wakeline.app.main import freeze_startup_objects
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope,
                                "wakeline-bench", "review-keys-probe")  # fmt: skip
    settings.clear()
    settings.setValue("language", "en")
    w = MainWindow(settings)
    w.resize(1600, 1000)
    w.show()
    freeze_startup_objects()

    def busy() -> bool:
        return bool(w.runner.busy or w.drawing or w.review.busy or w._job_context
                    or w.canvas.lod_busy)  # fmt: skip

    def settle(limit_s: float = 120.0) -> None:
        t0 = time.monotonic()
        quiet = 0
        while time.monotonic() - t0 < limit_s:
            QTest.qWait(20)
            quiet = 0 if busy() else quiet + 1
            if quiet >= 3:
                return

    w.load_files([path])
    settle()
    if a.file == "atd":
        w.params.root.child("associate", "mmsi_apart").setValue(False)
    w.run_step("associate")
    settle()
    layer = next(lay for lay in w.session.layers.values() if lay.step == "associate")
    w.select_layer(layer.id)
    settle()
    bound = w.review.bound
    n_prop = len(bound.controller.state.proposals)
    print(f"{path.name}: {len(layer.points):,} points, {len(w.batch_model.frame):,} tracks, "
          f"{n_prop} proposals")  # fmt: skip
    bound.panel.view.setFocus()
    app.processEvents()

    gaps: list[float] = []
    last = [time.perf_counter()]

    def tick() -> None:
        now = time.perf_counter()
        gaps.append(now - last[0])
        last[0] = now

    probe = QtCore.QTimer()
    probe.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
    probe.timeout.connect(tick)
    counter = Counter()
    resets = [0]  # batch table model resets
    w.batch_model.modelReset.connect(lambda: resets.__setitem__(0, resets[0] + 1))

    def key(i: int) -> None:
        k = QtCore.Qt.Key.Key_R if i % 7 == 3 else QtCore.Qt.Key.Key_A
        target = QtWidgets.QApplication.focusWidget() or w
        QTest.keyClick(target, k)

    key(0)  # warm-up, not counted
    settle()
    from wakeline.app import models

    probe.start(10)
    modes = {False: "before (batch table reset per key)", True: "after (cells updated in place)"}
    per = {m: [] for m in modes}  # (time to idle s, longest block s, CPU ms, gaps, resets)
    paints = {m: collections.Counter() for m in modes}
    idle_s = 0.0
    app.installEventFilter(counter)
    prof = cProfile.Profile() if a.profile else None
    for i in range(1, 2 * a.keys + 1):
        mode = models.TABLE_UPDATE_IN_PLACE = i % 2 == 0
        gaps.clear()
        counter.paints.clear()
        resets[0] = 0
        last[0] = t0 = time.perf_counter()
        c0 = time.thread_time()
        if prof and mode:
            prof.enable()
        key(i)
        settle()
        if prof and mode:
            prof.disable()
        cpu = 1000 * (time.thread_time() - c0)
        dt = time.perf_counter() - t0
        idle_s += dt / 2
        per[mode].append((dt, max(gaps, default=0.0), cpu, list(gaps), resets[0]))
        paints[mode].update(counter.paints)
    app.removeEventFilter(counter)
    models.TABLE_UPDATE_IN_PLACE = True
    # The machine alone: the probe for as long as one mode's keys with nothing to do.
    gaps.clear()
    last[0] = time.perf_counter()
    QTest.qWait(int(1000 * min(idle_s, 30.0)))
    idle = list(gaps)
    probe.stop()
    n = a.keys
    print(f"idle  ({len(idle)} ticks, nothing happening): longest gap ms "
          f"{1000 * max(idle, default=0):.0f}, p95 gap ms {1000 * pct(idle, 0.95):.0f}")  # fmt: skip
    for mode, name in modes.items():
        rows = per[mode]
        blocks = [1000 * r[1] for r in rows]
        all_gaps = [g for r in rows for g in r[3]]
        print(f"{name}, {n} keys: longest block per key ms median "
              f"{statistics.median(blocks):.0f} p95 {pct(blocks, 0.95):.0f} max {max(blocks):.0f}; "
              f"p95 gap ms {1000 * pct(all_gaps, 0.95):.0f}; to idle s median "
              f"{statistics.median(r[0] for r in rows):.2f}; GUI CPU ms per key median "
              f"{statistics.median(r[2] for r in rows):.0f} max {max(r[2] for r in rows):.0f}; "
              f"batch table resets per key {sum(r[4] for r in rows) / n:.1f}")  # fmt: skip
        top = sorted(paints[mode].items(), key=lambda kv: -kv[1])
        print("  paints per key:", ", ".join(f"{k} {v / n:.1f}" for k, v in top))
    print("load average", " ".join(open("/proc/loadavg").read().split()[:3]))
    if prof:
        prof.dump_stats(a.profile)
    w.close()


if __name__ == "__main__":
    main()

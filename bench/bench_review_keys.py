"""GUI-thread CPU time per review key (accept / reject in turn) on the layer Associate
makes of ATD dataset1 (102,861 points, 5,620 tracks): each key and everything it sets
off on the GUI thread (the queue's views, the decision's layer swapped in 300 ms later:
batch table, map, selection) until the window is idle again, by ``time.thread_time`` of
the GUI thread (the machine's load does not count, unlike a wall-clock probe), after
two keys not counted; then "select source" the same way. The keys are timed with the
batch table's index made on the GUI thread ("before": ``models.TABLE_INDEX_IN_WORKER =
False``) and made in the worker with the layer's view ("after"), alternating in one run.

    WAKELINE_SHARED=/work/shared QT_QPA_PLATFORM=offscreen python bench/bench_review_keys.py [keys]

``--million``: the ATD example over 10 days with a track per ship and day
(``bench/gui_block_probe.py``'s ``atd_example_x10_by_day.csv``, 1,102,900 points,
Associate with ``mmsi_apart`` off: 1,699 proposals) instead of dataset1. Each key's wall
time (trigger to idle) is printed beside its GUI CPU, and the load average.

``--gil``: after the keys, the decision's worker job (:func:`decided_points` and
:func:`prepare_view`, as ``ReviewSync`` runs it) run ``--gil`` times in a thread while
the main thread ticks every millisecond: each tick later than 15 ms is a stretch in which
the job kept the GIL (on an idle machine: no core to wait for), attributed to the job's
innermost frames of ours at that moment; the longest stretches and the total by line.
"""

import argparse
import collections
import os
import statistics
import sys
import threading
import time
import traceback
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app import models  # noqa: E402

ROOT = str(Path(models.__file__).resolve().parents[1])  # the package's files
QUIET_S = 0.4  # settle()'s idle wait before it returns


def gil_holds(job, runs: int, late_ms: float = 15.0) -> None:
    """Run ``job()`` ``runs`` times in a thread; the main thread sleeps 1 ms at a time
    and records each wake-up later than ``late_ms`` with the job thread's stack then."""
    holds: list[tuple[float, str]] = []
    for _ in range(runs):
        done = threading.Event()
        cpu: list[float] = []

        def run(d=done, cpu=cpu) -> None:
            c = time.thread_time()
            job()
            cpu.append(1000 * (time.thread_time() - c))
            d.set()

        t = threading.Thread(target=run, name="decision-job")
        t.start()
        wall = time.perf_counter()
        while not done.is_set():
            t0 = time.perf_counter()
            time.sleep(0.001)
            gap = (time.perf_counter() - t0) * 1000
            if gap > late_ms:
                frame = sys._current_frames().get(t.ident)
                stack = traceback.extract_stack(frame) if frame is not None else []
                ours = [
                    f for f in stack if f.filename.startswith(ROOT) and ".venv" not in f.filename
                ]
                ours = ours or stack
                where = " <- ".join(
                    f"{Path(f.filename).stem}:{f.lineno}:{f.name}" for f in reversed(ours[-3:])
                )
                inner = stack[-1] if stack else None
                if inner is not None and inner not in ours:
                    where = f"[{Path(inner.filename).stem}:{inner.lineno}:{inner.name}] " + where
                holds.append((gap, where))
        t.join()
        print(
            f"decision job {1000 * (time.perf_counter() - wall):.0f} ms wall, {cpu[0]:.0f} ms CPU"
        )
    by_line: collections.Counter = collections.Counter()
    for gap, where in holds:
        by_line[where] += gap
    print(f"GIL held over {late_ms:.0f} ms: {len(holds)} stretches in {runs} runs, "
          f"longest {max((g for g, _ in holds), default=0):.0f} ms; total ms by place:")  # fmt: skip
    for where, ms in by_line.most_common(15):
        longest = max(g for g, w in holds if w == where)
        print(f"  {ms / runs:6.0f} ms/run (longest {longest:4.0f})  {where[:300]}")


def watch_jobs(jobs: list) -> None:
    """Record every worker job (the window's job runners' threads and the map's
    level-of-detail pool): its function's name, CPU and wall ms."""
    from wakeline.app import lod_worker, worker

    def timed(name: str, fn):
        t, c = time.perf_counter(), time.thread_time()
        try:
            return fn()
        finally:
            jobs.append((name, 1000 * (time.thread_time() - c), 1000 * (time.perf_counter() - t)))

    task_run = lod_worker._Task.run

    def run_task(self) -> None:
        name = getattr(self.job, "__qualname__", "lod")
        timed(f"pool:{name}", lambda: task_run(self))

    thread_run = worker._Thread.run

    def run_thread(self) -> None:
        timed(f"{self.name}:{getattr(self.fn, '__qualname__', '?')}", lambda: thread_run(self))

    lod_worker._Task.run = run_task
    worker._Thread.run = run_thread


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("keys", nargs="?", type=int, default=20)
    ap.add_argument("--million", action="store_true", help="the 1.1 M-point by-day file")
    ap.add_argument("--gil", type=int, default=0, help="runs of the decision job, GIL holds")
    ap.add_argument("--profile", action="store_true", help="the decision job under cProfile")
    ap.add_argument(
        "--jobs", action="store_true", help="the worker jobs each key sets off, CPU ms each"
    )
    ap.add_argument(
        "--reject", action="store_true", help="--gil/--profile: a reject, not an accept"
    )
    ap.add_argument(
        "--whole",
        action="store_true",
        help="--gil/--profile: the whole prepare_view, not the lines alone (relabel_view)",
    )
    args = ap.parse_args()
    keys = args.keys
    shared = Path(os.environ.get("WAKELINE_SHARED", "/work/shared"))
    path = shared / "data/real/atd2025-noaa/dataset1_truth.csv.gz"
    if args.million:
        sys.path.insert(0, str(Path(__file__).parent))
        from gui_block_probe import atd_million

        path = atd_million(by_day=True)
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

    def settle(quiet_s: float = QUIET_S) -> None:
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

    walls: list[float] = []

    def cpu_ms(fn) -> float:
        t, t_wall = time.thread_time(), time.perf_counter()
        fn()
        settle()
        walls.append(1000 * (time.perf_counter() - t_wall) - 1000 * QUIET_S)
        return 1000 * (time.thread_time() - t)

    jobs: list[tuple[str, float, float]] = []  # (job, CPU ms, wall ms) in worker threads
    if args.jobs:
        watch_jobs(jobs)
    w.load_files([path])
    settle()
    src = w.active
    if args.million:
        w.params.root.child("associate", "mmsi_apart").setValue(False)
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
    walls.clear()
    times = {False: [], True: []}
    for i in range(2 * keys):
        models.TABLE_INDEX_IN_WORKER = worker = i % 2 == 1
        act = bound.panel.act_accept if i % 4 < 2 else bound.panel.act_reject
        jobs.clear()
        times[worker].append(cpu_ms(act.trigger))
        if args.jobs:
            kind = "A" if i % 4 < 2 else "R"
            total = sum(c for _, c, _ in jobs)
            print(f"key {kind}: GUI CPU {times[worker][-1]:.0f} ms, wall {walls[-1]:.0f} ms; "
                  f"workers' CPU {total:.0f} ms: " + ", ".join(
                      f"{name} {c:.0f}" for name, c, _ in sorted(jobs, key=lambda j: -j[1])[:8]))  # fmt: skip
    key_walls = list(walls)
    select = {False: [], True: []}
    for i in range(6):
        models.TABLE_INDEX_IN_WORKER = worker = i % 2 == 1
        select[worker].append(cpu_ms(lambda: w.select_layer(src)))
        cpu_ms(lambda: w.select_layer(layer.id))
    for worker, name in ((False, "before (index on the GUI thread)"), (True, "after (index in the worker)")):  # fmt: skip
        t, s = times[worker], select[worker]
        print(f"{name}: key CPU ms median {statistics.median(t):.1f} max {max(t):.1f} "
              f"over {len(t)}; select source median {statistics.median(s):.1f} over {len(s)}")  # fmt: skip
    print(f"key wall ms (trigger to idle, the {QUIET_S * 1000:.0f} ms quiet wait taken off) median "
          f"{statistics.median(key_walls):.0f} max {max(key_walls):.0f} over {len(key_walls)}")  # fmt: skip
    print("load average", " ".join(open("/proc/loadavg").read().split()[:3]))
    if args.gil or args.profile:
        from wakeline.app.layer_view import prepare_view
        from wakeline.core.review_session import decided_points, snapshot

        try:  # not in a tree before session 31 (the bench run on it: the whole view)
            from wakeline.app.layer_view import relabel_view
            from wakeline.core.review_session import relabeled
        except ImportError:
            relabel_view = relabeled = None

        act = bound.panel.act_reject if args.reject else bound.panel.act_accept
        act.trigger()  # a decision the layer does not show yet
        snap = snapshot(bound.controller.state)
        lay = w.session.layers[bound.lid]
        view, size_px = w.canvas.current_view(), w.canvas.plot_size_px()
        previous = w.views.get(bound.lid)
        now = lay.points  # the points the decision is made on (the sync swaps others in)

        def job():
            # as ReviewSync runs it: the lines of the targets changed alone when that
            # applies (relabel_view), else (or --whole) the whole view
            whole = args.whole or relabel_view is None
            if not whole and previous is not None and previous.points is now:
                quick = relabeled(now, snap, bound.cache)
                if quick is not None:
                    pts, per_track = quick
                    if relabel_view(previous, pts, per_track, lay.kind, view, size_px):
                        return
            pts = decided_points(lay, snap, bound.points, bound.cache)
            prepare_view(pts, lay.kind, lay.color, lay.name, view, size_px, previous=previous)

        settle()
        gil_holds(job, args.gil)
        if args.profile:
            import cProfile
            import pstats

            prof = cProfile.Profile()
            prof.runcall(job)
            pstats.Stats(prof).sort_stats("cumulative").print_stats(45)
    w.close()


if __name__ == "__main__":
    main()

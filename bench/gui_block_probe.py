"""What blocks the window's event loop while a big file loads, is cleaned, and the active
layer is switched (SPEC §7: no block over 100 ms at a million points).

A 10 ms QTimer on the GUI thread records every gap between two ticks; a watchdog thread
samples the other threads' Python stacks while the GUI thread is over 100 ms late; a
``gc.callbacks`` hook records every collection over 20 ms (generation, duration, thread,
objects tracked by the collector when it started). Two baselines in the same run, with
nothing of ours loading: the idle loop, and the loop beside a CPU-bound pure-Python
thread (the GIL handed back and forth every 5 ms, as to a worker), so that the figures
of the actions read as ratios against what the machine and the GIL alone give.

    WAKELINE_SHARED=/work/shared QT_QPA_PLATFORM=offscreen .venv/bin/python \
        bench/gui_block_probe.py [--file PATH] [--runs 3] [--why]

Without ``--file`` it reads the ATD example truth repeated over 10 days (1,102,900 points,
one track per ship across the days, as session 27's ``atd_1M.csv``), which it writes once
into a cache directory (``$XDG_CACHE_HOME/wakeline-bench`` or ``~/.cache/wakeline-bench``)
and names when it starts.

Each run is a new process (``--runs`` starts them one after the other), so that the
collector and the allocators start as the application's do.
"""

import argparse
import collections
import gc
import mmap
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path

import numpy as np

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app.main import freeze_startup_objects, wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402

PERIOD_MS = 10
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD_EXAMPLE = SHARED / "data/real/atd2025-noaa/example_truth.csv.gz"
DAYS = 10


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "wakeline-bench"


def atd_million(
    days: int = DAYS, by_day: bool = False, source: Path = ATD_EXAMPLE, folder: Path | None = None
) -> Path:
    """The ATD example truth (110,290 points of 2024-01-01) repeated over ``days`` days:
    copy k has its times moved k days later and its point ids moved past the others'; the
    ships keep their ids, so each ship is one track across the days; ``by_day``: a ship's
    track of day k is ``track_id * 10 + k`` instead (a track per ship and day, so that
    Associate with ``mmsi_apart`` off proposes joins within each day, as on the example
    itself). Written once (the name says which); later calls return the file there."""
    import gzip

    folder = folder or cache_dir()
    out = folder / f"atd_example_x{days}{'_by_day' if by_day else ''}.csv"
    if out.exists():
        return out
    folder.mkdir(parents=True, exist_ok=True)
    with gzip.open(source, "rt", encoding="utf-8", newline="") as f:
        header, *rows = f.read().splitlines()
    n = len(rows)
    tmp = out.with_suffix(".part")
    with open(tmp, "w", encoding="utf-8", newline="\n") as f:
        f.write(header + "\n")
        for k in range(days):
            day = f"2024-01-{k + 1:02d}T"
            for row in rows:
                pid, orig, track, rest = row.split(",", 3)
                if by_day:
                    track = str(int(track) * 10 + k)
                rest = rest.replace("2024-01-01T", day, 1)
                f.write(f"{int(pid) + k * n},{orig},{track},{rest}\n")
    tmp.replace(out)
    how = "a track per ship and day" if by_day else "a track per ship"
    print(f"made {out}: {source.name} x {days} days, {days * n:,} points, {how}", flush=True)
    return out


EVENTS: list[tuple] = []  # with --events: (start, wall ms, CPU ms, receiver, type, depth)


class TimedApp(QtWidgets.QApplication):
    """With ``--events``: every event the GUI thread handles for over 4 ms (at the top
    level or one below) is logged with its start, wall and CPU ms, receiver and type,
    so that the longest gap can be told apart into the events within it."""

    depth = 0

    def notify(self, obj, event) -> bool:
        TimedApp.depth += 1
        t, c = time.perf_counter(), time.thread_time()
        name = type(obj).__name__
        try:
            parent = obj.parent() if isinstance(obj, QtCore.QObject) else None
            kind = str(event.type()).rsplit(".", 1)[-1]
        except (RuntimeError, AttributeError):  # a C++ object already deleted
            parent, kind = None, "?"
        if parent is not None:
            name += f" in {type(parent).__name__}"
        try:
            return super().notify(obj, event)
        except TypeError:  # PySide hands a few internal events over oddly: not timed
            return False
        finally:
            TimedApp.depth -= 1
            ms = (time.perf_counter() - t) * 1000
            if ms > 4 and TimedApp.depth <= 1:
                cpu = (time.thread_time() - c) * 1000
                EVENTS.append((t, ms, cpu, name, kind, TimedApp.depth))


class Probe:
    """The 10 ms timer, the watchdog and the collector hook, for one action at a time."""

    def __init__(self, why: bool) -> None:
        self.why = why
        self.timer = QtCore.QTimer()
        self.timer.setInterval(PERIOD_MS)
        self.timer.timeout.connect(self._tick)
        self.last = time.perf_counter()
        self.last_cpu = time.thread_time()
        self.gaps: list[float] = []
        self.worst = (0.0, 0.0)  # the longest gap's (start, end)
        self.cpus: list[float] = []  # the GUI thread's own CPU time in each gap
        self.main = threading.get_ident()
        self.samples: collections.Counter = collections.Counter()
        #: (generation, wall ms, the collecting thread's CPU ms, thread, tracked, collected)
        self.collections: list[tuple] = []
        self.by_gen = [0, 0, 0]  # collections of each generation during the action
        self._gc_start: dict[int, tuple[float, float, int]] = {}
        self.stop = threading.Event()
        self.beat: mmap.mmap | None = None
        gc.callbacks.append(self._gc)
        if why:
            threading.Thread(target=self._watch, daemon=True).start()

    def _tick(self) -> None:
        if self.beat is not None:
            self.beat[:8] = struct.pack("d", time.monotonic())
        now, cpu = time.perf_counter(), time.thread_time()
        if now - self.last > self.worst[1] - self.worst[0]:
            self.worst = (self.last, now)
        self.gaps.append(now - self.last)
        self.cpus.append(cpu - self.last_cpu)
        self.last, self.last_cpu = now, cpu

    def _gc(self, phase: str, info: dict) -> None:
        me = threading.get_ident()
        if phase == "stop":
            self.by_gen[info["generation"]] += 1
        if phase == "start":
            tracked = len(gc.get_objects(2)) if info["generation"] == 2 and self.why else -1
            self._gc_start[me] = (time.perf_counter(), time.thread_time(), tracked)
            return
        t0, c0, tracked = self._gc_start.pop(me, (time.perf_counter(), time.thread_time(), -1))
        ms = (time.perf_counter() - t0) * 1000
        if ms > 20:
            who = "GUI" if me == self.main else threading.current_thread().name
            cpu = (time.thread_time() - c0) * 1000
            self.collections.append((info["generation"], ms, cpu, who, tracked, info["collected"]))

    def _watch(self) -> None:
        me = threading.get_ident()
        while not self.stop.wait(0.01):
            if time.perf_counter() - self.last < 0.1:
                continue
            for ident, frame in sys._current_frames().items():
                if ident == me:
                    continue
                stack = traceback.extract_stack(frame)
                if ident != self.main and stack and stack[-1].name in ("wait", "get", "_wait"):
                    continue
                who = "GUI  " if ident == self.main else "other"
                key = " <- ".join(
                    f"{Path(f.filename).stem}:{f.lineno}:{f.name}" for f in reversed(stack[-7:])
                )
                self.samples[f"{who} {key}"] += 1

    def start(self, label: str = "") -> None:
        if self.beat is not None:
            self.beat[8:72] = label.encode()[:64].ljust(64, b"\0")
        self.gaps.clear()
        self.cpus.clear()
        self.worst = (0.0, 0.0)
        EVENTS.clear()
        self.samples.clear()
        self.collections.clear()
        self.by_gen = [0, 0, 0]
        self.last, self.last_cpu = time.perf_counter(), time.thread_time()
        self.timer.start()

    def end(self) -> dict:
        self.timer.stop()
        gaps = np.array(self.gaps or [0.0]) * 1000
        cpus = np.array(self.cpus or [0.0]) * 1000
        return {
            "longest": max(float(gaps.max()) - PERIOD_MS, 0.0),
            "longest_cpu": float(cpus[int(gaps.argmax())]),
            "most_cpu": float(cpus.max()),
            "p95": float(np.percentile(gaps, 95)),
            "over100": int((gaps > 100 + PERIOD_MS).sum()),
            "ticks": len(gaps),
            "gc": list(self.collections),
            "by_gen": list(self.by_gen),
            "samples": self.samples.most_common(8),
            "events": [e for e in EVENTS if self.worst[0] - 0.001 <= e[0] <= self.worst[1]],
            "worst_at": self.worst[0],
        }


def monitor(pid: int, beat_path: str, out_path: str) -> None:
    """(Another process.) While the GUI thread of ``pid`` is over 60 ms late, dump every
    thread's stack with ``py-spy dump --nonblocking`` (which tells the thread holding the
    GIL), once per late stretch, at most every 40 ms: a thread holding the GIL in one long
    C call cannot be sampled from inside the process."""
    spy = shutil.which("py-spy") or str(Path(sys.executable).with_name("py-spy"))
    with open(beat_path, "r+b") as f, open(out_path, "a") as out:
        beat = mmap.mmap(f.fileno(), 128)
        while True:
            time.sleep(0.01)
            (last,) = struct.unpack("d", beat[:8])
            if last < 0:
                return
            late = time.monotonic() - last
            if last == 0 or late < 0.06:
                continue
            label = beat[8:72].rstrip(b"\0").decode()
            got = subprocess.run(
                [spy, "dump", "--nonblocking", "--pid", str(pid)], capture_output=True, text=True
            )
            out.write(f"=== {label} late {late * 1000:.0f} ms\n{got.stdout}\n")
            out.flush()
            time.sleep(0.03)


def gil_holders(text: str, label: str) -> collections.Counter:
    """From the monitor's dumps of ``label``: the stack (7 frames) of the thread holding
    the GIL in each, counted."""
    counts: collections.Counter = collections.Counter()
    for dump in text.split("=== ")[1:]:
        head, _, body = dump.partition("\n")
        if not head.startswith(label + " late"):
            continue
        holder = None
        for block in body.split("\nThread ")[1:]:
            lines = block.splitlines()
            if "+gil" in lines[0]:
                who = "GUI" if "MainThread" in lines[0] else "worker"
                frames = [ln.strip() for ln in lines[1:8] if ln.startswith("    ")]
                frames = [f.replace(str(Path.cwd()) + "/", "") for f in frames]
                holder = f"{who}: " + " <- ".join(frames)
        counts[holder or "no thread holds the GIL (waiting for a core, or in C)"] += 1
    return counts


def settle(ms: int) -> None:
    app = QtWidgets.QApplication.instance()
    end = time.perf_counter() + ms / 1000
    while time.perf_counter() < end:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 5)
        QtCore.QThread.msleep(1)


def busy_thread(seconds: float) -> threading.Thread:
    """A pure-Python CPU-bound thread: it holds the GIL but for the interpreter's switch
    interval (5 ms), as a worker in Python code does."""

    def spin() -> None:
        end = time.perf_counter() + seconds
        x = 0
        while time.perf_counter() < end:
            for k in range(1000):
                x += k * k

    t = threading.Thread(target=spin, name="busy-baseline", daemon=True)
    t.start()
    return t


def wait_window(window: MainWindow) -> None:
    """Until the window has no job, drawing, level of detail or review work left."""
    for _ in range(3):
        wait_for_jobs(window, 900_000)
        settle(300)
        if not (window.jobs_busy or window.drawing or window.canvas.lod_busy):
            if not window.review.busy:
                return


def show(
    label: str, r: dict, seconds: float, why: bool, dumps: str = "", base: dict | None = None
) -> None:
    gcs = sorted(r["gc"], key=lambda g: -g[1])
    text = ", ".join(
        f"g{g} {ms:.0f} ms (CPU {cpu:.0f}) {who} collected {got:,}"
        + (f" of {n:,}" if n >= 0 else "")
        for g, ms, cpu, who, n, got in gcs[:4]
    )
    print(
        f"{label:<22} longest block {r['longest']:6.0f} ms (GUI CPU {r['longest_cpu']:4.0f}; "
        f"most in a gap {r['most_cpu']:4.0f})  p95 gap {r['p95']:5.1f} ms  "
        f"gaps > 110 ms {r['over100']:3d}  ({seconds:5.1f} s, load {os.getloadavg()[0]:.1f})"
        + (
            f"  vs busy-thread baseline: longest x{r['longest'] / max(base['longest'], 1):.1f}"
            f", p95 x{r['p95'] / max(base['p95'], 1):.2f}"
            if base
            else ""
        )
        + f"  collections g0/g1/g2 {'/'.join(map(str, r['by_gen']))}, over 20 ms: {len(gcs)} {text}",
        flush=True,
    )
    if why:
        for key, n in r["samples"]:
            print(f"      {n * 10:5d} ms  {key[:400]}")
    for t, ms, cpu, name, kind, depth in r.get("events", [])[:12]:
        print(f"      event at +{(t - r['worst_at']) * 1000:4.0f} ms: {ms:5.0f} ms (CPU {cpu:4.0f}) "
              f"{'  ' * depth}{kind} to {name}")  # fmt: skip
    if dumps:
        for key, n in gil_holders(dumps, label).most_common(6):
            print(f"      {n:3d} dumps  GIL held by {key[:600]}")


def wait_written(window: MainWindow) -> None:
    """Until the project writer has written what was handed to it (the loop running)."""
    wait_window(window)
    writer = window.project.writer
    if writer is not None:
        written = threading.Event()
        writer.submit(lambda _store: written.set())
        while not written.is_set():
            settle(20)


def one_run(
    path: Path,
    why: bool,
    spy: bool = False,
    review: Path | None = None,
    events: bool = False,
    review_only: bool = False,
) -> dict:
    kind = TimedApp if events else QtWidgets.QApplication
    _app = QtWidgets.QApplication.instance() or kind(sys.argv[:1])
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        beat_path, dump_path = Path(tmp) / "beat", Path(tmp) / "dumps.txt"
        beat_path.write_bytes(bytes(128))
        dump_path.write_text("")
        settings = QtCore.QSettings(str(Path(tmp) / "s.ini"), QtCore.QSettings.Format.IniFormat)
        settings.setValue("language", "en")
        window = MainWindow(settings)
        window.resize(1600, 1000)
        window.show()
        freeze_startup_objects()  # as `wakeline gui` does
        settle(1000)
        probe = Probe(why)
        watcher = None
        if spy:
            beat_file = open(beat_path, "r+b")  # noqa: SIM115 - kept open for the run
            probe.beat = mmap.mmap(beat_file.fileno(), 128)
            cmd = [sys.executable, __file__, "--monitor", str(os.getpid()), str(beat_path)]
            watcher = subprocess.Popen([*cmd, str(dump_path)])

        def measure(label, action, wait) -> None:
            t0 = time.perf_counter()
            probe.start(label)
            action()
            wait()
            r = probe.end()
            dumps = dump_path.read_text() if spy else ""
            show(label, r, time.perf_counter() - t0, why, dumps, out.get("baseline: busy thread"))
            out[label] = r

        measure("baseline: idle", lambda: None, lambda: settle(3000))
        spin = []
        measure(
            "baseline: busy thread",
            lambda: spin.append(busy_thread(3.0)),
            lambda: (settle(3000), spin[0].join()),
        )
        if review_only:
            review_actions(window, review, Path(tmp), measure)
            probe.stop.set()
            window.close()
            return out
        measure("load", lambda: window.load_files([path]), lambda: wait_window(window))
        src = window.layer_id(path.name)
        window.select_layer(src)
        settle(300)
        measure("clean", lambda: window.run_step("clean"), lambda: wait_window(window))
        cleaned = next(i for i, lay in window.layers.items() if lay.kind == "cleaned")
        measure("switch layer", lambda: window.select_layer(cleaned), lambda: wait_window(window))
        measure("switch back", lambda: window.select_layer(src), lambda: wait_window(window))
        if review is not None:
            more_actions(window, src, review, Path(tmp), measure)
        probe.stop.set()
        if watcher is not None:
            probe.beat[:8] = struct.pack("d", -1.0)
            watcher.wait(10)
        window.close()
        if review is not None:
            settings.setValue("language", "en")
            window2 = MainWindow(settings)
            window2.resize(1600, 1000)
            window2.show()
            settle(1000)
            probe.stop.clear()
            if why:
                threading.Thread(target=probe._watch, daemon=True).start()
            measure(
                "reopen project",
                lambda: window2.open_project(Path(tmp) / "p.wakeline"),
                lambda: wait_window(window2),
            )
            probe.stop.set()
            window2.close()
    return out


def more_actions(window: MainWindow, src: str, review: Path, tmp: Path, measure) -> None:
    """The rest of SPEC §7's actions after the load, Clean and the layer switch: the
    pipeline, a re-run swapping its result in, selection in the table and on the map, a
    drag of the time slider, the project's save; then ``review`` (a file Associate makes
    a queue of) loaded, Associate run, its queue decided by keys (A, R, Ctrl+Z) and the
    project saved with the decisions. ``measure(label, action, wait)``; each label covers
    several repetitions (its longest block is the longest of them)."""
    from PySide6.QtTest import QTest

    def wait() -> None:
        wait_window(window)

    window.select_layer(src)
    settle(300)
    measure("pipeline", lambda: window.run_step("pipeline"), wait)
    window.select_layer(src)
    settle(300)
    measure("re-run clean (swap)", lambda: window.run_step("clean"), wait)
    window.select_layer(src)
    settle(300)

    def table_clicks() -> None:
        view = window.batch_view
        for row in range(0, 100, 10):
            view.scrollTo(window.batch_model.index(row, 0))
            rect = view.visualRect(window.batch_model.index(row, 0))
            QTest.mouseClick(view.viewport(), QtCore.Qt.MouseButton.LeftButton,
                             QtCore.Qt.KeyboardModifier.NoModifier, rect.center())  # fmt: skip
            settle(150)

    measure("select in table x10", table_clicks, wait)
    keys = [window.batch_model.key_of_row(r) for r in range(5, 200, 20)]

    def map_clicks() -> None:
        for sensor, batch in keys:
            window._track_clicked(src, sensor, batch, False)  # the canvas' track_clicked
            settle(150)

    measure("click track on map x10", map_clicks, wait)

    def drag() -> None:
        slider = window.time_panel.slider
        for k in range(60):  # the handle dragged across, a step per 20 ms
            slider.setValue(int(slider.maximum() * (k + 1) / 60))
            settle(20)

    measure("time slider drag", drag, wait)
    measure(
        "save project",
        lambda: window.save_project(tmp / "p.wakeline"),
        lambda: wait_written(window),
    )
    review_actions(window, review, tmp, measure)


def review_actions(window: MainWindow, review: Path, tmp: Path, measure) -> None:
    """``review`` loaded, Associate run, its queue decided by keys (A, R, Ctrl+Z) and the
    project saved with the decisions (alone with ``--review-only``)."""
    from PySide6.QtTest import QTest

    def wait() -> None:
        wait_window(window)

    measure("load review file", lambda: window.load_files([review]), wait)
    rsrc = window.layer_id(review.name)
    window.select_layer(rsrc)
    window.params.root.child("associate", "mmsi_apart").setValue(False)
    settle(300)
    measure("associate", lambda: window.run_step("associate"), wait)
    assoc = next(i for i, lay in window.layers.items() if lay.step == "associate")
    measure("switch to queue layer", lambda: window.select_layer(assoc), wait)
    for _ in range(300):  # the queue is bound a few event-loop turns after the layer
        if window.review.bound is not None:
            break
        settle(100)
    bound = window.review.bound
    print(f"      queue: {len(bound.controller.state.proposals):,} proposals", flush=True)

    def press(key, mod=QtCore.Qt.KeyboardModifier.NoModifier, times: int = 5):
        def go() -> None:
            for _ in range(times):
                bound.panel.view.setFocus()
                target = QtWidgets.QApplication.focusWidget() or window
                QTest.keyClick(target, key, mod)
                wait_window(window)
                settle(100)

        return go

    Key = QtCore.Qt.Key
    measure("review key A x5", press(Key.Key_A), wait)
    measure("review key R x5", press(Key.Key_R), wait)
    measure("undo Ctrl+Z x5", press(Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier), wait)
    measure(
        "save project (queue)",
        lambda: window.save_project(tmp / "p.wakeline"),
        lambda: wait_written(window),
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--file", type=Path, help="default: the ATD example over 10 days, made once in the cache"
    )
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--why", action="store_true", help="sample stacks; count gen-2 objects")
    ap.add_argument(
        "--spy", action="store_true", help="py-spy dumps (which thread holds the GIL) while late"
    )
    ap.add_argument(
        "--arrow-threads", type=int, help="Arrow's CPU thread pool size (default: the cores)"
    )
    ap.add_argument(
        "--short", action="store_true", help="only the load, Clean and the layer switch"
    )
    ap.add_argument(
        "--events", action="store_true", help="the events over 4 ms within each longest gap"
    )
    ap.add_argument(
        "--review-only",
        action="store_true",
        help="only the by-day file, Associate and the review keys (no other file loaded)",
    )
    ap.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--monitor", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.monitor:
        monitor(int(args.monitor[0]), args.monitor[1], args.monitor[2])
        return 0
    if args.arrow_threads:
        import pyarrow as pa

        pa.set_cpu_count(args.arrow_threads)
    if args.file is None:
        args.file = atd_million()
    if args.one or args.runs == 1:
        print(f"{args.file} ({os.path.getsize(args.file) / 1e6:.0f} MB); probe {PERIOD_MS} ms")
        review = None if args.short else atd_million(by_day=True)
        one_run(args.file, args.why, args.spy, review, args.events, args.review_only)
        return 0
    flags = [
        f
        for f, on in (
            ("--why", args.why),
            ("--spy", args.spy),
            ("--short", args.short),
            ("--events", args.events),
            ("--review-only", args.review_only),
        )
        if on
    ]
    if args.arrow_threads:
        flags += ["--arrow-threads", str(args.arrow_threads)]
    for k in range(args.runs):
        print(f"--- run {k + 1} of {args.runs}", flush=True)
        cmd = [sys.executable, __file__, "--one", "--file", str(args.file)]
        subprocess.run(cmd + flags, check=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

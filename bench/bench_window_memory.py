"""Memory of the window on a large file: RSS after each action, and where it sits.

Opens CSV in a window, runs Run ▸ pipeline on it, Run ▸ Associate on the source, saves
the project, closes the window (deleted, every reference dropped, ``gc.collect``) and
opens the project in a new window. After each action it prints the process's current
RSS (``/proc/self/statm``) and its peak so far (``ru_maxrss``), both in MB. After the
close it says whether the closed window and its session were freed (weak references).

``--where`` also prints, after each action, the bytes reachable from the window's parts
(the session's layers one by one — points and side tables —, the map, the batch table, the
review dock, the rest of the window), each array counted once, by the first part that
reaches it, and each layer's columns that share memory with its input layer's
(``np.shares_memory``). Python objects in object columns (strings) are counted by
``sys.getsizeof``; what C++ holds (Qt, pyqtgraph's paths) is not seen, and is the gap
between the sum and the RSS. It also prints what glibc's malloc and Arrow's pool hold, and
gives their free memory back (``malloc_trim``) to show the RSS in use: with ``--where``
the RSS figures of the later actions are not those of a plain run.

    QT_QPA_PLATFORM=offscreen .venv/bin/python bench/bench_window_memory.py FILE.csv [--where]

``--same-window`` also opens the saved project in the first window before it closes (File
▸ Open project: the application's own way, one window per process).

Defect #8 (session 25's operator test) was measured on ~1 M real ATD AIS points
(``atd_1m.csv``); see docs/benchmarks.md, *Memory of the window*.
"""

import argparse
import contextlib
import ctypes
import gc
import os
import resource
import sys
import tempfile
import time
import weakref
from pathlib import Path

import numpy as np

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_gui import settle  # noqa: E402
from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app.main import freeze_startup_objects, wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402

MB = 1024 * 1024
PAGE = os.sysconf("SC_PAGE_SIZE")


def rss_now() -> float:
    """Resident set size now, MB."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * PAGE / MB


class _Mallinfo2(ctypes.Structure):
    _fields_ = [
        (name, ctypes.c_size_t)
        for name in (
            "arena",
            "ordblks",
            "smblks",
            "hblks",
            "hblkhd",
            "usmblks",
            "fsmblks",
            "uordblks",
            "fordblks",
            "keepcost",
        )
    ]


def heap() -> str:
    """What the allocators hold: glibc's malloc in use / free in its arenas / mmapped, and
    Arrow's pool (MB)."""
    import pyarrow as pa

    out = ""
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallinfo2.restype = _Mallinfo2
        m = libc.mallinfo2()
        out = (
            f"malloc in use {(m.uordblks + m.hblkhd) / MB:.0f}, free in arenas "
            f"{m.fordblks / MB:.0f}; "
        )
    except (OSError, AttributeError):
        pass
    pool = pa.default_memory_pool()
    return (
        out
        + f"arrow {pool.backend_name} {pool.bytes_allocated() / MB:.0f} (max {pool.max_memory() / MB:.0f})"
    )


def trim() -> None:
    """Give the allocators' free memory back to the system (glibc malloc_trim, Arrow's
    pool): the RSS then is what is in use."""
    import pyarrow as pa

    pa.default_memory_pool().release_unused()
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL("libc.so.6").malloc_trim(0)


def rss_peak() -> float:
    """Peak resident set size so far, MB (Linux: ru_maxrss in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def wait(window: MainWindow) -> None:
    """Until the window's jobs, drawing and project writes are done."""
    wait_for_jobs(window, 600_000)
    writer = window.project.writer
    if writer is not None:
        import threading

        written = threading.Event()
        writer.submit(lambda _store: written.set())
        while not written.is_set():
            settle(20)
    settle(400)


# -- where the memory sits ---------------------------------------------------------------


def _owner(a: np.ndarray) -> np.ndarray:
    while isinstance(a.base, np.ndarray):
        a = a.base
    return a


def reachable(root, seen: set, stop: set) -> tuple[int, int]:
    """(array bytes, Python string bytes) reachable from ``root`` not already in ``seen``
    (ids of array owners / objects counted), not walking through ids in ``stop``."""
    import pyarrow as pa

    total = strings = 0
    stack = [root]
    visited: set[int] = set()
    while stack:
        obj = stack.pop()
        i = id(obj)
        if i in visited or i in stop:
            continue
        visited.add(i)
        if isinstance(obj, (type, type(sys))):  # classes and modules: not the data
            continue
        if isinstance(obj, np.ndarray):
            own = _owner(obj)
            if id(own) not in seen:
                seen.add(id(own))
                total += own.nbytes
                if own.dtype == object:
                    for v in own.ravel():
                        if id(v) not in seen:
                            seen.add(id(v))
                            strings += sys.getsizeof(v)
            continue
        if isinstance(obj, (pa.Array, pa.ChunkedArray, pa.Table, pa.RecordBatch)):
            if i not in seen:
                seen.add(i)
                total += obj.nbytes
            continue
        if isinstance(obj, (str, bytes)):
            continue
        stack.extend(gc.get_referents(obj))
    return total, strings


def where(window: MainWindow, title: str) -> None:
    """Print the bytes reachable from the window's parts (see the module docstring)."""
    gc.collect()
    seen: set[int] = set()
    stop = {id(window)}
    rows = []
    layers = window.session.layers
    stop |= {id(layers), id(window.session)}
    for lid, lay in layers.items():
        a, s = reachable(lay.points, seen, stop)
        t, ts = reachable(lay.tables, seen, stop)
        m, ms = reachable(lay.meta, seen, stop)
        rows.append((f"layer {lid} {lay.kind} ({len(lay.points):,} rows)", a + t + m, s + ts + ms))
    parts = [
        ("map canvas", window.canvas),
        ("lod worker", window.lod_worker),
        ("time", getattr(window, "time_controller", None)),
        ("time panel", getattr(window, "time_panel", None)),
        ("batch model", window.batch_model),
        ("stats", window.stats),
        ("detail", window.detail),
        ("review", window.review),
        ("project", window.project),
        ("session rest", window.session),
        ("window rest", window),
    ]
    for name, obj in parts:
        if obj is None:
            continue
        if obj is window:
            stop.discard(id(window))
        if obj is window.session:
            stop.discard(id(window.session))
            stop.discard(id(layers))
        a, s = reachable(obj, seen, stop)
        stop.add(id(obj))
        rows.append((name, a, s))
    print(f"  where, {title}: (MB arrays + MB Python strings)")
    total = 0
    for name, a, s in rows:
        total += a + s
        if a + s >= MB:
            print(f"    {name:<52} {a / MB:8.1f} + {s / MB:6.1f}")
    print(f"    {'sum':<52} {total / MB:8.1f}   (RSS now {rss_now():.0f} MB)")
    print(f"    {heap()}")
    trim()
    print(f"    after malloc_trim / release_unused: RSS {rss_now():.0f} MB")
    for lid, lay in layers.items():
        parent = layers.get(lay.parent) if lay.parent else None
        if parent is None:
            continue
        shared = []
        for c in lay.points.columns:
            if c in parent.points.columns:
                try:
                    x = np.asarray(
                        lay.points[c].array._ndarray
                        if hasattr(lay.points[c].array, "_ndarray")
                        else lay.points[c].to_numpy(copy=False)
                    )
                    y = np.asarray(
                        parent.points[c].array._ndarray
                        if hasattr(parent.points[c].array, "_ndarray")
                        else parent.points[c].to_numpy(copy=False)
                    )
                except Exception:  # noqa: BLE001
                    continue
                if x.dtype != object and np.shares_memory(x, y):
                    shared.append(c)
        print(f"    {lid} columns sharing memory with {lay.parent}: {shared or 'none'}")
    dtypes = {}
    for lid, lay in layers.items():
        dtypes[lid] = ", ".join(f"{c}:{d}" for c, d in lay.points.dtypes.items())
    for lid, d in dtypes.items():
        print(f"    {lid} dtypes: {d}")


def new_window(settings: QtCore.QSettings) -> MainWindow:
    w = MainWindow(settings)
    w.interactive = False  # no modal dialogs
    w.resize(1400, 900)
    w.show()
    return w


def close_window(w: MainWindow) -> None:
    """Close and delete ``w`` as the application and the tests do (its jobs ended first)."""
    if w.project.unsaved or w.project.dirty:
        print(f"  note: project unsaved={w.project.unsaved} dirty={w.project.dirty}")
    w.project.unsaved = w.project.dirty = False  # no Save as question
    w.close()
    w.runner.wait()
    w.export_runner.wait()
    w.lod_worker.wait()
    w.deleteLater()
    QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)


class Bench:
    def __init__(self, path: Path, where: bool, same: bool = False) -> None:
        self.path, self.show_where, self.same = path, where, same
        self.tmp = Path(tempfile.mkdtemp(prefix="wakeline-mem-"))
        self.settings = QtCore.QSettings(str(self.tmp / "s.ini"), QtCore.QSettings.Format.IniFormat)
        self.settings.setValue("language", "en")
        self.project = self.tmp / "p.wakeline"

    @staticmethod
    def report(name: str, t0: float) -> None:
        print(
            f"{name:<34} {rss_now():9.0f} {rss_peak():9.0f}          "
            f"{time.perf_counter() - t0:5.1f} s",
            flush=True,
        )

    def step(self, name: str, action, window: MainWindow) -> None:
        t0 = time.perf_counter()
        action()
        wait(window)
        self.report(name, t0)
        if self.show_where:
            where(window, name)

    def first_window(self) -> tuple[float, tuple[weakref.ref, weakref.ref, weakref.ref]]:
        """Open, pipeline, associate, save, close; the time the close began and weak
        references to the window, its session and its source layer's points."""
        t0 = time.perf_counter()
        w = new_window(self.settings)
        freeze_startup_objects()  # as the application, once its window is built
        settle(1000)
        self.report("empty window", t0)
        self.step("open file", lambda: w.load_file(self.path), w)
        src = w.layer_id(self.path.name)
        self.step("run pipeline", lambda: w.run_step("pipeline"), w)
        self.step("associate", lambda: (w.select_layer(src), w.run_step("associate")), w)
        self.step("save project", lambda: w.save_project(self.project), w)
        if self.same:
            self.step("open project (same window)", lambda: w.open_project(self.project), w)
        refs = weakref.ref(w), weakref.ref(w.session), weakref.ref(w.session.layers[src].points)
        t0 = time.perf_counter()
        close_window(w)
        return t0, refs

    def run(self) -> None:
        t0, (window, session, points) = self.first_window()
        settle(400)
        gc.collect()
        self.report("close window", t0)
        print(
            "  after close + gc.collect: "
            + ", ".join(
                f"{name} {'ALIVE' if ref() is not None else 'freed'}"
                for name, ref in (
                    ("window", window),
                    ("session", session),
                    ("the source layer's points", points),
                )
            )
        )
        if window() is not None and self.show_where:
            where(window(), "closed window (not collected)")
        w2 = new_window(self.settings)
        self.step("open project (new window)", lambda: w2.open_project(self.project), w2)
        close_window(w2)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv", type=Path)
    parser.add_argument("--where", action="store_true", help="where the memory sits")
    parser.add_argument(
        "--same-window",
        action="store_true",
        help="also open the saved project in the first window (File > Open project)",
    )
    args = parser.parse_args()
    path = args.csv.resolve()
    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    print(f"file {path} ({path.stat().st_size / MB:.0f} MB), load {os.getloadavg()[0]:.1f}")
    print(f"{'action':<34} {'RSS now':>9} {'peak':>9}   (MB)   time")
    t0 = time.perf_counter()
    Bench(path, args.where, args.same_window).run()
    print(f"total {time.perf_counter() - t0:.0f} s, peak RSS {rss_peak():.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main())

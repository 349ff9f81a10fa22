"""Responsiveness of the main window on a million points: the longest event-loop block.

A 10 ms QTimer probe runs on the GUI thread while each action happens (open the file, run
the pipeline, switch the active layer, select tracks, save the project, open it again);
the longest gap between two probe ticks, less the 10 ms period, is the longest time the
window could not answer. The goal (SPEC §7) is < 100 ms for every action.

    QT_QPA_PLATFORM=offscreen .venv/bin/python bench/bench_gui.py [--points 1000000]
"""

import argparse
import collections
import os
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path

import numpy as np
import pandas as pd

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app.main import freeze_startup_objects, wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

PERIOD_MS = 10


def make_scene(n_points: int, seed: int = 0) -> pd.DataFrame:
    """Tracks of 500 points in every direction (rows shuffled), two sensors."""
    rng = np.random.default_rng(seed)
    per = 500
    k = max(n_points // per, 1)
    heading = rng.uniform(0, 2 * np.pi, k)
    turn = rng.normal(0, 0.02, (k, per)).cumsum(axis=1)
    step_km = rng.uniform(0.05, 0.2, k)
    dx = np.cos(heading[:, None] + turn) * step_km[:, None]
    dy = np.sin(heading[:, None] + turn) * step_km[:, None]
    lon = 122.0 + rng.uniform(0, 1.5, k)[:, None] + dx.cumsum(axis=1) / 96.0
    lat = 30.0 + rng.uniform(0, 1.0, k)[:, None] + dy.cumsum(axis=1) / 111.0
    t0 = np.datetime64("2024-05-01T00:00:00", "s") + rng.integers(0, 3600, k)
    times = t0[:, None] + (np.arange(per) * 10).astype("timedelta64[s]")
    df = pd.DataFrame(
        {
            "sensor": np.repeat(np.where(np.arange(k) % 2 == 0, "R1", "AIS"), per),
            "batch": np.repeat(np.arange(k).astype(str), per),
            "time": pd.to_datetime(times.ravel()).tz_localize("UTC"),
            "lon": lon.ravel() + rng.normal(0, 2e-4, k * per),
            "lat": lat.ravel() + rng.normal(0, 2e-4, k * per),
        }
    )
    return df.sample(frac=1.0, random_state=seed).reset_index(drop=True)


class Probe:
    """Records the gaps between ticks of a 10 ms timer on the GUI thread: wall time, and
    the GUI thread's own CPU time (``time.thread_time``) — the work done on it between two
    ticks, which a busy machine does not inflate (waits for the CPU or the GIL are not in
    it)."""

    def __init__(self) -> None:
        self.timer = QtCore.QTimer()
        self.timer.setInterval(PERIOD_MS)
        self.timer.timeout.connect(self._tick)
        self.last = None
        self.worst = 0.0
        self.last_cpu = 0.0
        self.worst_cpu = 0.0
        self.gaps: list[tuple[float, float, float]] = []  # (start, wall s, cpu s) > 50 ms

    def _tick(self) -> None:
        now, cpu = time.perf_counter(), time.thread_time()
        if self.last is not None:
            self.worst = max(self.worst, now - self.last)
            self.worst_cpu = max(self.worst_cpu, cpu - self.last_cpu)
            if now - self.last > 0.05:
                self.gaps.append((self.last, now - self.last, cpu - self.last_cpu))
        self.last, self.last_cpu = now, cpu

    def __enter__(self):
        self.last, self.worst = time.perf_counter(), 0.0
        self.last_cpu, self.worst_cpu = time.thread_time(), 0.0
        self.timer.start()
        return self

    @property
    def cpu_ms(self) -> float:
        """The most GUI-thread CPU time between two ticks, less the period's share."""
        return max(self.worst_cpu * 1000, 0.0)

    def __exit__(self, *exc) -> None:
        self.timer.stop()

    @property
    def block_ms(self) -> float:
        return max(self.worst * 1000 - PERIOD_MS, 0.0)


class Sampler:
    """With ``--why``: while the GUI thread has not ticked the probe for over 25 ms, a
    helper thread samples its Python stack every 3 ms; prints the commonest lines."""

    def __init__(self, probe: Probe) -> None:
        self.probe = probe
        self.main = threading.main_thread().ident
        self.counts: collections.Counter = collections.Counter()
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self.stop.wait(0.003):
            last = self.probe.last
            if last is None or time.perf_counter() - last < 0.025:
                continue
            me = threading.get_ident()
            for ident, frame in sys._current_frames().items():
                if ident == me:
                    continue
                depth = 14 if ident == self.main else 5
                stack = traceback.extract_stack(frame)[-depth:]
                key = " < ".join(
                    f"{Path(f.filename).stem}:{f.name}:{f.lineno}" for f in reversed(stack)
                )
                if ident == self.main:
                    self.counts["GUI " + key] += 1
                elif "wait" not in stack[-1].name and "get" != stack[-1].name:
                    self.counts["other " + key] += 1

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop.set()
        self.thread.join()

    def report(self, top: int = 6) -> None:
        total = sum(n for k, n in self.counts.items() if k.startswith("GUI"))
        gui = [(k, n) for k, n in self.counts.most_common() if k.startswith("GUI")][:top]
        other = [(k, n) for k, n in self.counts.most_common() if k.startswith("other")][:top]
        for key, n in gui + other:
            print(f"    {n:4d}/{total} x 3 ms  {key[:600]}")


def settle(ms: int = 400) -> None:
    app = QtWidgets.QApplication.instance()
    end = time.perf_counter() + ms / 1000
    while time.perf_counter() < end:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
        QtCore.QThread.msleep(2)


WHY = False


def measure(name: str, action, window: MainWindow | None, results: dict) -> None:
    """Run ``action`` and wait until its jobs, drawing and project writes are done; record
    the longest event-loop block. ``window`` None: the idle baseline (nothing to wait for)."""
    t0 = time.perf_counter()
    with Probe() as probe:
        sampler = Sampler(probe) if WHY else None
        if sampler is not None:
            sampler.__enter__()
        action()
        if window is not None:
            wait_for_jobs(window, 600_000)
            writer = window.project.writer
            if writer is not None:  # wait for the project writer without blocking
                written = threading.Event()
                writer.submit(lambda _store: written.set())
                while not written.is_set():
                    settle(20)
        settle()
        if sampler is not None:
            sampler.__exit__()
    results[name] = (probe.block_ms, time.perf_counter() - t0, probe.cpu_ms)
    print(
        f"{name:<28} longest block {probe.block_ms:7.0f} ms wall, {probe.cpu_ms:5.0f} ms "
        f"GUI-thread CPU   (action {results[name][1]:6.1f} s)"
    )
    if WHY:
        for _start, wall, cpu in sorted(probe.gaps, key=lambda g: -g[1])[:3]:
            print(f"    gap {wall * 1000:5.0f} ms wall, {cpu * 1000:4.0f} ms GUI CPU")
    if sampler is not None:
        sampler.report()


def cancel_latency(window: MainWindow, layer: str) -> dict[str, float]:
    """Start each step on ``layer``, cancel it after a while, and print how long the
    runner took to stop (goal: < 0.5 s). Returns ms per step."""
    app = QtWidgets.QApplication.instance()
    out = {}
    for step, after_s in (("clean", 0.5), ("maneuvers", 0.3), ("compress", 0.3), ("pipeline", 2.0)):
        window.select_layer(layer)
        settle(100)
        before = set(window.layers)
        window.run_step(step)
        settle(int(after_s * 1000))
        t0 = time.perf_counter()
        window.runner.cancel()
        while window.runner.busy and time.perf_counter() - t0 < 30:
            app.processEvents()
            time.sleep(0.002)
        out[step] = (time.perf_counter() - t0) * 1000
        wait_for_jobs(window)
        made = set(window.layers) - before
        print(
            f"cancel {step:<10} after {after_s:.1f} s: stopped in {out[step]:5.0f} ms "
            f"(goal < 500 ms); layers made: {len(made)}"
        )
    return out


def drawn_check(window: MainWindow) -> bool:
    """At the end: every visible layer is in the map with every track drawn (a NaN-separated
    piece per track at least), at the level of detail of the current view. Prints it."""
    from wakeline.app.map_draw import lod_is_stale

    canvas = window.canvas
    view, size = canvas.current_view(), canvas.plot_size_px()
    ok = True
    for lid, layer in window.session.layers.items():
        if not layer.visible:
            continue
        if lid not in canvas.layer_names():
            print(f"  {lid} {layer.name}: NOT DRAWN")
            ok = False
            continue
        data = canvas.draw_data(lid)
        pieces = vertices = 0
        for item, curve in zip(canvas.layer_items(lid), data.curves, strict=True):
            x = item.xData if item.xData is not None else np.zeros(0)
            if len(x) == len(curve.lon) and np.array_equal(x, curve.lon, equal_nan=True):
                finite = np.isfinite(x)
                vertices += int(finite.sum())
                pieces += int(
                    np.count_nonzero(finite[1:] & ~finite[:-1]) + bool(len(x) and finite[0])
                )
            elif item.opts.get("connect") == "pairs" or len(x) == 4 * curve.n_vertices:
                vertices += curve.n_vertices  # marker crosses: four ends per point
                pieces += curve.n_vertices
            else:
                print(f"  {lid}: an item does not hold its prepared curve")
                ok = False
        stale = lod_is_stale(data, view, size)
        tracks = data.geometry.n_tracks
        good = pieces >= tracks and not stale
        ok &= good
        print(
            f"  {lid} {layer.name[:40]:<40} tracks {tracks:6,}  drawn pieces {pieces:6,}  "
            f"vertices {vertices:8,}  of {data.geometry.n_points:9,} points  "
            f"LOD {'stale' if stale else 'current'}  {'ok' if good else 'MISSING'}"
        )
    return ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument(
        "--why", action="store_true", help="sample the GUI thread's stack during long blocks"
    )
    args = ap.parse_args()
    global WHY
    WHY = args.why
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        path = tmp / "million.csv"
        write_points(make_scene(args.points), path)
        settings = QtCore.QSettings(str(tmp / "s.ini"), QtCore.QSettings.Format.IniFormat)
        window = MainWindow(settings)
        window.resize(1400, 900)
        freeze_startup_objects()  # as the application does once its window is built
        window.show()
        settle(1500)  # start-up paints and layout done before the baseline
        print(f"{args.points:,} points, {args.points // 500:,} tracks; probe period {PERIOD_MS} ms")
        results: dict[str, tuple[float, float, float]] = {}
        idle: dict[str, tuple[float, float, float]] = {}
        measure("idle loop (baseline)", lambda: settle(1500), None, idle)
        measure("open file", lambda: window.load_file(path), window, results)
        src = window.layer_id(path.name)
        measure(
            "save project (first)", lambda: window.save_project(tmp / "p.wakeline"), window, results
        )
        measure("run pipeline", lambda: window.run_step("pipeline"), window, results)
        comp = next(i for i, lay in window.layers.items() if lay.kind == "compressed")
        measure("switch layer", lambda: window.select_layer(comp), window, results)
        measure("switch layer back", lambda: window.select_layer(src), window, results)
        keys = [window.batch_model.key_of_row(r) for r in range(0, 200, 20)]
        measure("select 10 tracks", lambda: window.select_tracks(keys), window, results)
        measure("hide a layer", lambda: window.session.set_visible(comp, False), window, results)
        cancel = cancel_latency(window, src)
        print("drawn at the end (window 1):")
        drawn = drawn_check(window)
        window.close()
        window2 = MainWindow(settings)
        window2.resize(1400, 900)
        window2.show()
        measure("open project", lambda: window2.open_project(tmp / "p.wakeline"), window2, results)
        print("drawn at the end (window 2, the project opened):")
        drawn &= drawn_check(window2)
        measure("idle loop (again)", lambda: settle(1500), None, idle)
        window2.close()
    worst = max(r[0] for r in results.values())
    worst_cpu = max(r[2] for r in results.values())
    base = max(max(r[0] for r in idle.values()), 1.0)
    print(
        f"worst block {worst:.0f} ms (goal < 100 ms): {'OK' if worst < 100 else 'OVER'}; "
        f"most GUI-thread CPU between two ticks {worst_cpu:.0f} ms; "
        f"idle-loop block {base:.0f} ms, ratio {worst / base:.1f}; "
        f"every track drawn: {'yes' if drawn else 'NO'}; slowest cancel "
        f"{max(cancel.values()):.0f} ms; load {os.getloadavg()[0]:.1f}"
    )
    del app
    return 0


if __name__ == "__main__":
    sys.exit(main())

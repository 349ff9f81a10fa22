"""The longest event-loop block while Run ▸ Associate runs in the window on the ATD 2025
example file (../shared/data/real/atd2025-noaa/example_truth.csv.gz, ~72 k AIS posits of
one day): the same 10 ms timer probe as ``bench_gui.py``, from the click until the step's
layer is drawn and its review queue bound (the dock shows the first proposal).

    QT_QPA_PLATFORM=offscreen WAKELINE_SHARED=../shared .venv/bin/python \
        bench/bench_gui_associate.py [--runs 3] [--why] [--profile]

``--profile`` runs cProfile on the GUI thread's slots during the step (the slowest
cumulative entries are printed)."""

import argparse
import cProfile
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).parent))

import bench_gui  # noqa: E402
from bench_gui import Probe, Sampler, settle  # noqa: E402
from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app.main import freeze_startup_objects, wait_for_jobs  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402


def atd_file() -> Path:
    """The ATD 2025 example truth file under ``$WAKELINE_SHARED`` (default ../shared)."""
    shared = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).parents[2] / "shared"))
    return shared / "data" / "real" / "atd2025-noaa" / "example_truth.csv.gz"


def settle_window(w: MainWindow, timeout_s: float = 300.0) -> None:
    """Wait (in the event loop) until the window's jobs, drawing and review are done."""
    end = time.perf_counter() + timeout_s
    while time.perf_counter() < end:
        wait_for_jobs(w, 600_000)
        busy = w.review.busy or w.drawing or w.runner.busy or w.canvas.lod_busy
        if not (busy or w._job_context):
            settle(300)
            if not (w.review.busy or w.drawing or w.runner.busy or w.canvas.lod_busy):
                return
        settle(20)
    raise RuntimeError("the window did not settle")


def run_once(path: Path, why: bool, profile: bool) -> tuple[float, float, list]:
    """One window: ``path`` loaded and selected, then Run ▸ Associate under the probe.
    The longest event-loop block (ms wall), its GUI-thread CPU (ms) and the probe's gaps
    (start, wall s, CPU s); ``why`` samples the GUI thread's stack, ``profile`` runs
    cProfile over the step."""
    with tempfile.TemporaryDirectory() as tmp:
        settings = QtCore.QSettings(str(Path(tmp) / "s.ini"), QtCore.QSettings.Format.IniFormat)
        settings.setValue("language", "en")
        w = MainWindow(settings)
        w.resize(1400, 900)
        freeze_startup_objects()
        w.show()
        settle(1000)
        w.load_files([path])
        settle_window(w)
        src = w.layer_id(path.name)
        w.select_layer(src)
        settle_window(w)
        prof = cProfile.Profile() if profile else None
        with Probe() as probe:
            sampler = Sampler(probe) if why else None
            if sampler is not None:
                sampler.__enter__()
            if prof is not None:
                prof.enable()
            # ATD's ~100 proposals tie different MMSIs, which mmsi_apart keeps apart (none
            # at all): the rule is off so that the review has a queue to bind.
            w.params.from_dict({"associate": {"mmsi_apart": False}})
            w.run_step("associate")
            settle_window(w)
            if prof is not None:
                prof.disable()
            if sampler is not None:
                sampler.__exit__()
        assoc = w.session.find(src, "associate")
        bound = w.review.bound
        n = len(bound.controller.state.proposals) if bound is not None else -1
        print(
            f"  associate on {path.name}: longest block {probe.block_ms:5.0f} ms wall, "
            f"{probe.cpu_ms:4.0f} ms GUI-thread CPU; layer {assoc is not None}, "
            f"review bound: {n} proposals; load {os.getloadavg()[0]:.1f}"
        )
        for _start, wall, cpu in sorted(probe.gaps, key=lambda g: -g[1])[:5]:
            print(f"    gap {wall * 1000:5.0f} ms wall, {cpu * 1000:4.0f} ms GUI CPU")
        if sampler is not None:
            sampler.report(10)
        if prof is not None:
            pstats.Stats(prof).sort_stats("cumulative").print_stats(45)
        w.close()
        settle(200)
        return probe.block_ms, probe.cpu_ms, probe.gaps


def main() -> int:
    """``--runs`` windows in turn; prints each and the range of the longest blocks."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--why", action="store_true")
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    bench_gui.WHY = args.why
    path = atd_file()
    if not path.exists():
        print(f"{path}: not found (set WAKELINE_SHARED)")
        return 2
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    walls, cpus = [], []
    for _ in range(args.runs):
        wall, cpu, _gaps = run_once(path, args.why, args.profile)
        walls.append(wall)
        cpus.append(cpu)
    print(
        f"ATD example, Run > Associate, {args.runs} runs: longest block {min(walls):.0f}-"
        f"{max(walls):.0f} ms wall (GUI-thread CPU {min(cpus):.0f}-{max(cpus):.0f} ms); "
        f"load {os.getloadavg()[0]:.1f}"
    )
    del app
    return 0


if __name__ == "__main__":
    sys.exit(main())

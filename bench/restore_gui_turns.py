"""The GUI thread's longest turn while the window restores points removed by cleaning
(h243; SPEC §7 "no action blocks the event loop for more than 100 ms"): ATD dataset1
(102,861 points) cleaned, then one point, one rule on one track and every removed point
restored and undone through the window (app/restore_points.py), each turn timed.

    QT_QPA_PLATFORM=offscreen python bench/restore_gui_turns.py
"""

import os
import sys
import tempfile
import time
from pathlib import Path

SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD = SHARED / "data/real/atd2025-noaa/dataset1_truth.csv.gz"


def main() -> int:
    from PySide6 import QtCore, QtWidgets

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow
    from wakeline.core.clean_restore import chosen_ids

    folder = tempfile.mkdtemp(prefix="wakeline-restore-bench-")
    settings = QtCore.QSettings(f"{folder}/s.ini", QtCore.QSettings.Format.IniFormat)
    w = MainWindow(settings)
    w.interactive = False
    w.resize(1280, 650)
    w.show()
    w.load_files([ATD], None)
    wait_for_jobs(w)
    w.select_layer(w.layer_id(ATD.name))
    w.run_step("clean")
    wait_for_jobs(w)
    lid = next(i for i, lay in w.layers.items() if lay.kind == "cleaned")
    layer, tool = w.layers[lid], w.restore_tool
    rej = layer.tables["rejected"]
    print(f"cleaned: {len(layer.points):,} points; rejected rows {len(rej):,}")
    w.actions_["show_removed"].setChecked(True)
    wait_for_jobs(w)

    def longest(fn) -> float:
        t = time.perf_counter()
        fn()
        worst = time.perf_counter() - t
        while tool.busy or w.drawing or w.canvas.lod_busy or w.jobs_busy:
            t = time.perf_counter()
            app.processEvents()
            worst = max(worst, time.perf_counter() - t)
            time.sleep(0.002)
        return worst

    first = rej.iloc[0]
    cases = (
        ("one point", rej.wl_id.iloc[:1]),
        (
            f"all {first.rule} removed on one track",
            chosen_ids(rej, rules=[first.rule], track=(str(first.sensor), str(first.batch))),
        ),
        ("every removed point", chosen_ids(rej)),
    )
    for label, ids in cases:
        t_do = longest(lambda ids=ids: tool.restore(lid, ids))
        n = len(layer.restored)
        t_undo = longest(w.review.act_undo.trigger)
        print(
            f"{label}: {n:,} points restored, {len(layer.restored)} after undo; longest "
            f"GUI-thread turn: restore {t_do * 1000:.0f} ms, undo {t_undo * 1000:.0f} ms"
        )
    w.close()
    w.runner.wait()
    w.export_runner.wait()
    w.lod_worker.wait()
    return 0


if __name__ == "__main__":
    sys.exit(main())

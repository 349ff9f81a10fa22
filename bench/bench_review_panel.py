"""CPU time of building the review queue's panel (``ReviewPanel(controller, digest=...)``)
on synthetic queues of 229, 1,000 and 5,000 proposals (one old and one new track per
ship, as ``tests/test_review_gui.py::test_thousand_proposals_stay_responsive``): what the
GUI thread spends when a queue arrives (the digest is made in the worker beforehand).

    QT_QPA_PLATFORM=offscreen python bench/bench_review_panel.py
"""

import os
import time

import numpy as np
import pandas as pd

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtWidgets  # noqa: E402

from wakeline.app.review_model import queue_digest  # noqa: E402
from wakeline.app.review_panel import ReviewPanel  # noqa: E402
from wakeline.app.review_undo import ReviewController  # noqa: E402
from wakeline.core import review as R  # noqa: E402


def synthetic_state(n: int) -> R.ReviewState:
    """``n`` two-track ships, one proposal each (costs and runner-ups random, seed 0)."""
    tracks = pd.DataFrame(
        {
            "sensor": "R1",
            "batch": [str(k) for k in range(2 * n)],
            "t0": np.r_[np.zeros(n), np.full(n, 700.0)],
            "t1": np.r_[np.full(n, 600.0), np.full(n, 1300.0)],
        }
    )
    tracks.insert(0, "track", "R1:" + tracks["batch"])
    rng = np.random.default_rng(0)
    cost = rng.uniform(0, 1.5, n)
    props = pd.DataFrame(
        {
            "proposal": [f"A{k + 1:04d}" for k in range(n)],
            "kind": "associate",
            "sensor_a": "R1",
            "batch_a": [str(k) for k in range(n)],
            "sensor_b": "R1",
            "batch_b": [str(n + k) for k in range(n)],
            "method": "optimal",
            "cost": cost,
            "gap_s": 100.0,
            "runner_up": [f"R1:{n + (k + 1) % n}" for k in range(n)],
            "runner_up_side": "a",
            "runner_up_cost": cost + rng.uniform(0, 1, n),
            "gate": 1.5,
        }
    )
    props["margin"] = np.fmin(props["runner_up_cost"], 1.5) - cost
    return R.ReviewState(tracks, props)


def main() -> None:
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    for n in (229, 1000, 5000):
        st = synthetic_state(n)
        st.target_of_track()  # the worker caches it too
        digest = queue_digest(st)
        times = []
        for _ in range(3):
            ctl = ReviewController(st)
            t = time.process_time()
            panel = ReviewPanel(ctl, digest=digest)
            times.append(1000 * (time.process_time() - t))
            panel.deleteLater()
            app.processEvents()
        print(f"{n:,} proposals: ReviewPanel() CPU ms {' / '.join(f'{x:.0f}' for x in times)}")
    print("load average", " ".join(open("/proc/loadavg").read().split()[:3]))


if __name__ == "__main__":
    main()

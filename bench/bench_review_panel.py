"""CPU time of building the review queue's panel (``ReviewPanel(controller, digest=...)``)
on synthetic queues of 229, 1,000 and 5,000 proposals (one old and one new track per
ship, as ``tests/test_review_gui.py::test_thousand_proposals_stay_responsive``): what the
GUI thread spends when a queue arrives (the digest is made in the worker beforehand).

    QT_QPA_PLATFORM=offscreen python bench/bench_review_panel.py
"""

import os
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtWidgets  # noqa: E402

from wakeline.app.review_model import queue_digest  # noqa: E402
from wakeline.app.review_panel import ReviewPanel  # noqa: E402
from wakeline.app.review_undo import ReviewController  # noqa: E402
from wakeline.core import review as R  # noqa: E402
from wakeline.core import simulate  # noqa: E402


def main() -> None:
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    for n in (229, 1000, 5000):
        st = R.ReviewState(*simulate.review_queue(n))
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

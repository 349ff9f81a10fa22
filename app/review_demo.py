"""A review workspace assembled from the review widgets, for screenshots and tours:
the queue panel, the map of the current proposal, its Gantt chart and its network.

The main window hosts these widgets in its Review dock (:mod:`wakeline.app.review_dock`);
this composition exists so the widgets can be seen together without a session (``python -m wakeline.app.review_demo RADAR AIS -o shot.png``).
"""

import argparse
import sys
from pathlib import Path

import pandas as pd
import pyqtgraph as pg
from PySide6 import QtWidgets

from wakeline.app import ink
from wakeline.app.review_map import proposal_geometry, proposal_items
from wakeline.app.review_panel import ReviewPanel
from wakeline.app.review_undo import ReviewController
from wakeline.app.review_views import GanttView, NetworkView
from wakeline.core import review as R


class ReviewWorkspace(QtWidgets.QSplitter):
    """Panel on the left; map, Gantt and network on the right, following the panel."""

    def __init__(self, controller: ReviewController, points: pd.DataFrame, parent=None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.points = points
        self.panel = ReviewPanel(controller)
        ink.setup()
        self.map = pg.PlotWidget(background="w")
        self.map.setAspectLocked(True)
        self.map.setLabel("bottom", self.tr("longitude"), units="°")
        self.map.setLabel("left", self.tr("latitude"), units="°")
        self.context = self.map.plot(pen=pg.mkPen("#d0d0d0", width=1), connect="finite")
        self.gantt = GanttView(controller.state)
        self.network = NetworkView(controller.state)
        right = QtWidgets.QSplitter()
        right.setOrientation(pg.QtCore.Qt.Orientation.Vertical)
        right.addWidget(self.map)
        bottom = QtWidgets.QSplitter()
        bottom.addWidget(self.gantt)
        bottom.addWidget(self.network)
        right.addWidget(bottom)
        right.setSizes([500, 300])
        self.addWidget(self.panel)
        self.addWidget(right)
        self.setSizes([560, 840])
        self._items: list = []
        from wakeline.app.map_canvas import nan_separated

        self.context.setData(*nan_separated(points))
        self.panel.current_settled.connect(self.show_proposal)
        self.network.proposal_clicked.connect(self.panel.set_current)
        self.show_proposal(self.panel.current())

    def show_proposal(self, proposal: str) -> None:
        for it in self._items:
            self.map.removeItem(it)
        self._items = []
        if not proposal:
            return
        geom = proposal_geometry(self.controller.state, self.points, proposal)
        for it in proposal_items(geom):
            self.map.addItem(it)
            self._items.append(it)
        if geom.bounds:
            x0, y0, x1, y1 = geom.bounds
            self.map.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0.08)
        self.gantt.show_proposal(proposal)
        self.network.show_proposal(proposal)


def build(files: list[Path]) -> tuple[ReviewController, pd.DataFrame]:
    """Read the files, associate each sensor and pair across sensors: one review queue."""
    from wakeline.app.cli_review import read_inputs
    from wakeline.core.associate import associate_interrupted
    from wakeline.core.fuse import associate_sensors

    points = read_inputs(files)
    ap, _ = R.association_proposals(associate_interrupted(points))
    parts = [ap]
    if points["sensor"].nunique() >= 2:
        parts.append(R.fusion_proposals(associate_sensors(points))[0])
    state = R.ReviewState(R.track_table(points), pd.concat(parts, ignore_index=True))
    return ReviewController(state), points


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("files", nargs="+", type=Path)
    ap.add_argument("-o", "--output", type=Path, required=True, help="PNG to write")
    ap.add_argument("--proposal", help="proposal to show (default: the first in the queue)")
    ap.add_argument("--decisions", type=Path, help="decisions to apply first (as `review`)")
    args = ap.parse_args(argv)
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    controller, points = build(args.files)
    if args.decisions:
        from wakeline.app.cli_review import read_table

        R.apply_decisions(controller.state, read_table(args.decisions, "decisions"))
    w = ReviewWorkspace(controller, points)
    w.resize(1400, 850)
    if args.proposal and not w.panel.set_current(args.proposal):
        print(f"no proposal {args.proposal!r}", file=sys.stderr)
        return 2
    w.show()
    w.show_proposal(w.panel.current())
    app.processEvents()
    w.grab().save(str(args.output))
    w.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The review queue's table model and its status/sensor filter (over a ReviewController)."""

import numpy as np
from PySide6 import QtCore, QtGui

from wakeline.app import review_text as T
from wakeline.app.review_undo import ReviewController

COLUMNS = (
    ("proposal", "proposal"),
    ("status", "status"),
    ("track_a", "track A"),
    ("track_b", "track B"),
    ("margin", "margin"),
    ("cost", "cost"),
    ("gap_s", "gap s"),
    ("distance_m", "distance m"),
    ("runner_up", "runner-up"),
    ("method", "method"),
)
_STATUS_COLORS = {
    "pending": None,
    "accepted": "#dff3df",
    "rejected": "#f8dcdc",
    "split": "#fbe9d0",
}
SORT_ROLE = QtCore.Qt.ItemDataRole.UserRole + 1
_ROLES = frozenset(
    (
        QtCore.Qt.ItemDataRole.DisplayRole,
        SORT_ROLE,
        QtCore.Qt.ItemDataRole.BackgroundRole,
        QtCore.Qt.ItemDataRole.ToolTipRole,
    )
)


class ProposalModel(QtCore.QAbstractTableModel):
    """One row per proposal; reads the state, never copies decisions."""

    def __init__(self, controller: ReviewController, parent=None) -> None:
        super().__init__(parent)
        self.controller = controller
        self._refresh()
        controller.changed.connect(self._on_changed)

    def _refresh(self) -> None:
        st = self.controller.state
        p = st.proposals
        self.ids = p["proposal"].tolist()
        self.row_of = {pid: k for k, pid in enumerate(self.ids)}
        self.cols = {name: p[name].to_numpy() for name, _ in COLUMNS if name != "status"}

    def _on_changed(self, proposals: list) -> None:
        col = [n for n, _ in COLUMNS].index("status")
        rows = [self.row_of[p] for p in proposals if p in self.row_of]
        if rows:
            self.dataChanged.emit(self.index(min(rows), 0), self.index(max(rows), len(COLUMNS) - 1))
        else:  # manual links change no status, but the targets around them
            self.dataChanged.emit(self.index(0, col), self.index(self.rowCount() - 1, col))

    def rowCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self.ids)

    def columnCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(COLUMNS)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if (
            role == QtCore.Qt.ItemDataRole.DisplayRole
            and orientation == QtCore.Qt.Orientation.Horizontal
        ):
            return T.column_titles()[COLUMNS[section][0]]
        return None

    def value(self, row: int, name: str):
        if name == "status":
            return str(self.controller.state.status[row])
        return self.cols[name][row]

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role not in _ROLES or not index.isValid():
            return None  # asked for many roles per cell (fonts, sizes, …): answer fast
        name = COLUMNS[index.column()][0]
        v = self.value(index.row(), name)
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            if name == "status":
                return T.status_name(v)
            if isinstance(v, float | np.floating):
                return "" if np.isnan(v) else f"{v:.3g}" if abs(v) < 10 else f"{v:.0f}"
            return str(v)
        if role == SORT_ROLE:
            if isinstance(v, float | np.floating):
                return float(np.inf) if np.isnan(v) else float(v)
            return str(v)
        if role == QtCore.Qt.ItemDataRole.BackgroundRole:
            color = _STATUS_COLORS.get(str(self.controller.state.status[index.row()]))
            return QtGui.QBrush(QtGui.QColor(color)) if color else None
        if role == QtCore.Qt.ItemDataRole.ToolTipRole and name == "margin":
            return T.margin_tip()
        return None


class ProposalFilter(QtCore.QSortFilterProxyModel):
    """Filter by status and by sensor (either track's)."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.status = ""
        self.sensor = ""
        self.setSortRole(SORT_ROLE)

    def set_filter(self, status: str = "", sensor: str = "") -> None:
        if hasattr(self, "beginFilterChange"):  # Qt ≥ 6.10: invalidateFilter is deprecated
            self.beginFilterChange()
            self.status, self.sensor = status, sensor
            self.endFilterChange(QtCore.QSortFilterProxyModel.Direction.Rows)
        else:
            self.status, self.sensor = status, sensor
            self.invalidateRowsFilter()

    def filterAcceptsRow(self, row: int, parent) -> bool:  # noqa: N802 - Qt API
        m: ProposalModel = self.sourceModel()
        if self.status and m.value(row, "status") != self.status:
            return False
        if self.sensor:
            a, b = str(m.value(row, "track_a")), str(m.value(row, "track_b"))
            if not (a.startswith(self.sensor + ":") or b.startswith(self.sensor + ":")):
                return False
        return True

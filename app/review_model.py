"""The review queue's table model and its status/sensor filter (over a ReviewController),
and :func:`queue_digest`: what the panel needs from a whole queue (its widest cell texts,
its sensors), made in the worker so the GUI thread only measures a handful of strings."""

from dataclasses import dataclass

import numpy as np
import pandas as pd
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
    ("dcourse_deg", "Δcourse °"),
    ("dspeed_kn", "Δspeed kn"),
    ("runner_up", "runner-up"),
    ("method", "method"),
    ("target", "target"),
)
#: Columns read from the review state, not the proposals' record (they change with the
#: decisions): the status and the target track A belongs to now.
STATE_COLUMNS = ("status", "target")
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


def cell_text(v) -> str:
    """The queue's text of a (non-status) cell value: floats to 3 significant digits
    below 10, whole numbers above, NaN blank."""
    if isinstance(v, float | np.floating):
        return "" if np.isnan(v) else f"{v:.3g}" if abs(v) < 10 else f"{v:.0f}"
    return str(v)


@dataclass(frozen=True)
class QueueDigest:
    """What the panel needs of a whole queue, read once (in the worker).

    ``widest``: per column, the few cell texts that can be its widest (the columns are
    sized from them with font metrics, not from every row); ``sensors``: the sensors of
    the queue's tracks, sorted (the sensor filter's items)."""

    widest: dict[str, list[str]]
    sensors: list[str]


def _widest_texts(values: np.ndarray, keep: int = 4) -> list[str]:
    """The texts of ``values`` that may be the widest: for numbers the extremes (the
    largest and smallest, the largest magnitudes and the smallest nonzero ones, which
    give the longest ``.3g`` texts); for strings the ``keep`` longest. Vectorized."""
    if len(values) == 0:
        return []
    if np.issubdtype(values.dtype, np.number):
        v = values.astype("float64")
        v = v[np.isfinite(v)]
        if len(v) == 0:
            return []
        mag = np.abs(v)
        small = mag[(mag > 0) & (mag < 10)]
        picks = [v.min(), v.max(), mag.max()]
        if len(small):
            picks += list(np.sort(small)[:keep])  # the smallest nonzero first
        neg = v[(v < 0) & (v > -10)]
        if len(neg):
            picks += [neg.max(), neg.min()]
        return list(dict.fromkeys(cell_text(float(x)) for x in picks))
    s = pd.Series(values).astype(str)
    top = np.argsort(-s.str.len().to_numpy(), kind="stable")[:keep]
    return list(dict.fromkeys(s.iloc[top].tolist()))


def queue_digest(state) -> QueueDigest:
    """:class:`QueueDigest` of a :class:`~wakeline.core.review.ReviewState` (no widgets:
    safe in the worker)."""
    p = state.proposals
    widest = {
        name: _widest_texts(p[name].to_numpy()) for name, _ in COLUMNS if name not in STATE_COLUMNS
    }
    # a target is named after a track of its own: the widest track labels
    widest["target"] = _widest_texts(
        np.concatenate([p["track_a"].to_numpy(dtype=object), p["track_b"].to_numpy(dtype=object)])
    )
    sensors = np.unique(state.tracks["sensor"].astype(str).to_numpy(dtype=str))
    return QueueDigest(widest, sensors.tolist())


class ProposalModel(QtCore.QAbstractTableModel):
    """One row per proposal; reads the state, never copies decisions."""

    def __init__(self, controller: ReviewController, parent=None) -> None:
        super().__init__(parent)
        self.controller = controller
        self._sorted: tuple | None = None  # (column, order) of the last sort
        self._refresh()
        controller.changed.connect(self._on_changed)

    def _refresh(self) -> None:
        st = self.controller.state
        p = st.proposals
        #: Row of ``state.proposals`` per model row (the model's rows are sorted here).
        self.prop = np.arange(len(p))
        self.ids = p["proposal"].tolist()
        self.row_of = {pid: k for k, pid in enumerate(self.ids)}
        self.cols = {name: p[name].to_numpy() for name, _ in COLUMNS if name not in STATE_COLUMNS}

    def sort(self, column: int, order=QtCore.Qt.SortOrder.AscendingOrder) -> None:
        """Order the rows by ``column`` with one numpy sort (the proxy asked ``data`` for
        two values per comparison, n log n calls on the GUI thread). Ties keep the
        proposals' own order; NaN sorts last ascending, as the proxy's sort did."""
        n = len(self.ids)
        if n == 0 or not 0 <= column < len(COLUMNS):
            return
        name = COLUMNS[column][0]
        self._sorted = (column, order)  # a decision re-sorts a queue sorted by status
        inv = np.empty(n, dtype="int64")  # proposal row -> model row
        inv[self.prop] = np.arange(n)
        if name == "status":
            key = np.asarray(self.controller.state.status).astype(str)[self.prop]
        elif name == "target":
            key = np.asarray(self.controller.state.proposal_targets()).astype(str)[self.prop]
        else:
            key = self.cols[name]
        if np.issubdtype(np.asarray(key).dtype, np.number):
            key = np.nan_to_num(np.asarray(key, dtype="float64"), nan=np.inf)
        else:
            key = pd.Series(key).astype(str).to_numpy(dtype=str)
        rank = np.unique(key[inv], return_inverse=True)[1].ravel()
        descending = order == QtCore.Qt.SortOrder.DescendingOrder
        new_prop = np.argsort(-rank if descending else rank, kind="stable")
        perm = inv[new_prop]  # model rows in their new order
        new_row = np.empty(n, dtype="int64")
        new_row[perm] = np.arange(n)
        self.layoutAboutToBeChanged.emit()
        old = self.persistentIndexList()
        self.changePersistentIndexList(
            old, [self.index(int(new_row[i.row()]), i.column()) for i in old]
        )
        self.prop = new_prop
        self.ids = [self.ids[k] for k in perm]
        self.row_of = {pid: k for k, pid in enumerate(self.ids)}
        self.cols = {k: v[perm] for k, v in self.cols.items()}
        self.layoutChanged.emit()

    def _on_changed(self, proposals: list) -> None:
        names = [n for n, _ in COLUMNS]
        col = names.index("status")
        sorted_by = self._sorted
        if sorted_by is not None and names[sorted_by[0]] in STATE_COLUMNS and proposals:
            # sorted by status: the rows move with their new status (as the proxy's
            # dynamic sort did before the queue sorted itself)
            self.sort(*sorted_by)
        rows = [self.row_of[p] for p in proposals if p in self.row_of]
        if rows:
            self.dataChanged.emit(self.index(min(rows), 0), self.index(max(rows), len(COLUMNS) - 1))
        else:  # manual links change no status, but the targets around them
            self.dataChanged.emit(self.index(0, col), self.index(self.rowCount() - 1, col))
        # a decision moves other proposals' tracks into or out of targets too
        tcol = names.index("target")
        self.dataChanged.emit(self.index(0, tcol), self.index(self.rowCount() - 1, tcol))

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
            return str(self.controller.state.status[self.prop[row]])
        if name == "target":
            return str(self.controller.state.proposal_targets()[self.prop[row]])
        return self.cols[name][row]

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role not in _ROLES or not index.isValid():
            return None  # asked for many roles per cell (fonts, sizes, …): answer fast
        name = COLUMNS[index.column()][0]
        v = self.value(index.row(), name)
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            if name == "method":
                return T.method_text(v)
            return T.status_name(v) if name == "status" else cell_text(v)
        if role == SORT_ROLE:
            if isinstance(v, float | np.floating):
                return float(np.inf) if np.isnan(v) else float(v)
            return str(v)
        if role == QtCore.Qt.ItemDataRole.BackgroundRole:
            color = _STATUS_COLORS.get(str(self.value(index.row(), "status")))
            return QtGui.QBrush(QtGui.QColor(color)) if color else None
        if role == QtCore.Qt.ItemDataRole.ToolTipRole and name == "margin":
            return T.margin_tip()
        return None


class ProposalFilter(QtCore.QSortFilterProxyModel):
    """Filter by status and by sensor (either track's); sorting is the source model's
    (:meth:`ProposalModel.sort`, one numpy sort), the proxy keeps its order."""

    def sort(self, column: int, order=QtCore.Qt.SortOrder.AscendingOrder) -> None:
        source = self.sourceModel()
        if source is not None:
            source.sort(column, order)

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

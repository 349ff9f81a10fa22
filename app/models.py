"""Qt models over core data: the batch table of a layer's tracks."""

import numpy as np
import pandas as pd
from PySide6 import QtCore

from wakeline.core.tracks import track_summary

SORT_ROLE = QtCore.Qt.ItemDataRole.UserRole + 1


def batch_summary(points: pd.DataFrame, maneuvers: pd.DataFrame | None = None) -> pd.DataFrame:
    """The core's track summary plus maneuvers per track, target and status."""
    summary = track_summary(points)
    if summary.empty:
        for col in ("maneuvers", "target", "status"):
            summary[col] = []
        return summary
    keys = ["sensor", "batch"]
    if maneuvers is not None and len(maneuvers):
        counts = maneuvers.astype({"sensor": str, "batch": str}).groupby(keys).size()
        summary["maneuvers"] = (
            counts.reindex(pd.MultiIndex.from_frame(summary[keys])).fillna(0).astype(int).to_numpy()
        )
    else:
        summary["maneuvers"] = np.nan
    if "target" in points.columns:
        first = points.astype({"sensor": str, "batch": str}).groupby(keys)["target"].first()
        summary["target"] = first.reindex(pd.MultiIndex.from_frame(summary[keys])).to_numpy()
        size = summary.groupby("target")["batch"].transform("size")
        summary["status"] = np.where(size > 1, "joined", "")
    elif "members" in points.columns:
        first = points.astype({"sensor": str, "batch": str}).groupby(keys)["members"].first()
        summary["target"] = summary["batch"]
        members = first.reindex(pd.MultiIndex.from_frame(summary[keys])).to_numpy()
        summary["status"] = np.where(pd.Series(members).str.contains(r"\+"), "fused", "single")
    else:
        summary["target"] = ""
        summary["status"] = ""
    return summary


class BatchTableModel(QtCore.QAbstractTableModel):
    """Read-only table over :func:`batch_summary`; ``SORT_ROLE`` gives raw values."""

    COLUMNS = (
        ("sensor", "Sensor"),
        ("batch", "Batch"),
        ("points", "Points"),
        ("start", "Start (UTC)"),
        ("end", "End (UTC)"),
        ("duration_s", "Duration (min)"),
        ("length_m", "Length (km)"),
        ("mean_speed_kn", "Speed (kn)"),
        ("maneuvers", "Maneuvers"),
        ("target", "Target"),
        ("status", "Status"),
    )
    TEXT = ("sensor", "batch", "target", "status")

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self._df = pd.DataFrame(columns=[c for c, _ in self.COLUMNS])
        self._titles = [t for _, t in self.COLUMNS]

    @property
    def frame(self) -> pd.DataFrame:
        return self._df

    def set_titles(self, titles: list[str]) -> None:
        self._titles = titles
        self.headerDataChanged.emit(QtCore.Qt.Orientation.Horizontal, 0, len(titles) - 1)

    def set_summary(self, df: pd.DataFrame) -> None:
        self.beginResetModel()
        self._df = df.reset_index(drop=True)
        self._cache = {
            key: self._df[key].to_numpy() if key in self._df.columns else None
            for key, _ in self.COLUMNS
        }
        self.endResetModel()

    def key_of_row(self, row: int) -> tuple[str, str]:
        return str(self._df["sensor"].iat[row]), str(self._df["batch"].iat[row])

    def row_of_key(self, sensor: str, batch: str) -> int | None:
        hit = np.flatnonzero(
            (self._df["sensor"].astype(str).to_numpy() == sensor)
            & (self._df["batch"].astype(str).to_numpy() == batch)
        )
        return int(hit[0]) if len(hit) else None

    def rowCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df)

    def columnCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self.COLUMNS)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if (
            role == QtCore.Qt.ItemDataRole.DisplayRole
            and orientation == QtCore.Qt.Orientation.Horizontal
        ):
            return self._titles[section]
        return None

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid():
            return None
        key = self.COLUMNS[index.column()][0]
        col = self._cache.get(key)
        if col is None:
            return None
        value = col[index.row()]
        if role == SORT_ROLE:
            if isinstance(value, pd.Timestamp):
                return value.value
            if isinstance(value, (float, np.floating)) and np.isnan(value):
                return -1.0
            return value.item() if hasattr(value, "item") else value
        if role == QtCore.Qt.ItemDataRole.TextAlignmentRole:
            if key in self.TEXT:
                return None
            return int(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        if role != QtCore.Qt.ItemDataRole.DisplayRole:
            return None
        if key in ("start", "end"):
            return pd.Timestamp(value).strftime("%Y-%m-%d %H:%M:%S")
        if key == "duration_s":
            return f"{value / 60:.1f}"
        if key == "length_m":
            return f"{value / 1000:.2f}"
        if key in ("mean_speed_kn",):
            return "" if pd.isna(value) else f"{value:.1f}"
        if key == "maneuvers":
            return "" if pd.isna(value) else str(int(value))
        return "" if value is None or (isinstance(value, float) and np.isnan(value)) else str(value)


class BatchFilterModel(QtCore.QSortFilterProxyModel):
    """Sorting by raw values; a text filter over every column, case-insensitive."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.setSortRole(SORT_ROLE)
        self.setFilterKeyColumn(-1)
        self.setFilterCaseSensitivity(QtCore.Qt.CaseSensitivity.CaseInsensitive)


class FrameModel(QtCore.QAbstractTableModel):
    """Any small DataFrame as a read-only table (the quarantine, reports)."""

    def __init__(self, df: pd.DataFrame, parent=None) -> None:
        super().__init__(parent)
        self._df = df.reset_index(drop=True)

    def rowCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df)

    def columnCount(self, parent=None) -> int:  # noqa: N802 - Qt API
        return 0 if parent is not None and parent.isValid() else len(self._df.columns)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if role != QtCore.Qt.ItemDataRole.DisplayRole:
            return None
        if orientation == QtCore.Qt.Orientation.Horizontal:
            return str(self._df.columns[section])
        return str(section + 1)

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid() or role != QtCore.Qt.ItemDataRole.DisplayRole:
            return None
        value = self._df.iat[index.row(), index.column()]
        return "" if value is None or (isinstance(value, float) and np.isnan(value)) else str(value)

"""A legend that lives in the plot's layout, beside the view box: it never covers data."""

import pyqtgraph as pg

#: Longest legend label (characters); longer ones are shortened in the middle, so the
#: column beside the map stays narrow (the full names are in the Layers panel).
LABEL_MAX = 32


def short_label(text: str, limit: int = LABEL_MAX) -> str:
    """``text`` shortened in the middle to at most ``limit`` characters."""
    if len(text) <= limit:
        return text
    head = (limit - 1) // 2
    return text[:head] + "…" + text[-(limit - 1 - head) :]


class SideLegend(pg.LegendItem):
    """A legend that lives in the plot's layout (a column right of the view box)."""

    def addItem(self, item, name: str) -> None:  # noqa: N802 - pyqtgraph's name
        super().addItem(item, short_label(str(name)))

    def updateSize(self) -> None:  # noqa: N802 - pyqtgraph's name
        width = height = 0.0
        for row in range(self.layout.rowCount()):
            row_w = row_h = 0.0
            for col in range(self.layout.columnCount()):
                item = self.layout.itemAt(row, col)
                if item:
                    row_w += item.width() + 3
                    row_h = max(row_h, item.height())
            width, height = max(width, row_w), height + row_h
        w = width + 6 if self.items else 0
        self.setMinimumWidth(w)
        self.setMaximumWidth(w)
        self.setMinimumHeight(height)
        self.setMaximumHeight(height)
        self.setVisible(bool(self.items))
        self.updateGeometry()

"""A legend that lives in the plot's layout, beside the view box: it never covers data."""

import pyqtgraph as pg
from PySide6 import QtCore, QtGui

#: Longest legend label (characters); longer ones are shortened in the middle, so the
#: column beside the map stays narrow (the full names are in the Layers panel).
LABEL_MAX = 32
#: The legend column is this many characters ("n") wide, from the start and for good;
#: a label wider than that is shortened in the middle to fit it (by pixels, so wide
#: glyphs such as Chinese fit too).
RESERVED_CHARS = 26
#: Room (px) left in the column for a label item's own padding.
LABEL_PADDING_PX = 10.0
#: The most height (px) the legend asks of the plot's layout; a longer one is clipped.
MIN_HEIGHT_PX = 120.0


def short_label(text: str, limit: int = LABEL_MAX) -> str:
    """``text`` shortened in the middle to at most ``limit`` characters."""
    if len(text) <= limit:
        return text
    head = (limit - 1) // 2
    return text[:head] + "…" + text[-(limit - 1 - head) :]


class SideLegend(pg.LegendItem):
    """A legend that lives in the plot's layout (a column right of the view box).

    Its column has a constant width: reserved from the start (:data:`RESERVED_CHARS`
    characters) and never narrower later. A legend that appeared or changed width with
    the first layer or a selection would resize the view box, and every layer would be
    decimated and stroked again (a block of the GUI thread at a million points).
    ``bare`` (images of the plot area alone) gives it no width at all.
    """

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.bare = False
        self.setFlag(self.GraphicsItemFlag.ItemClipsChildrenToShape, True)
        font = QtGui.QFont()
        font.setPointSizeF(9.0)  # pyqtgraph's legend label size
        self._metrics = QtGui.QFontMetricsF(font)
        self._text_px = float(self._metrics.horizontalAdvance("n" * RESERVED_CHARS))
        self.widest = self._text_px + 20 + 3 + 12  # the line sample, spacing, margins
        # A label item is wider than its text by its own padding (~6 px): labels are
        # shortened to fit the column less that, so a long name never widens it.
        self._label_px = self._text_px - LABEL_PADDING_PX
        self.updateSize()

    def addItem(self, item, name: str) -> None:  # noqa: N802 - pyqtgraph's name
        text = self._metrics.elidedText(
            short_label(str(name)), QtCore.Qt.TextElideMode.ElideMiddle, self._label_px
        )
        super().addItem(item, text)

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
        if self.items:
            self.widest = max(self.widest, width + 6)
        w = 0.0 if self.bare else self.widest
        self.setMinimumWidth(w)
        self.setMaximumWidth(w)
        # At most MIN_HEIGHT_PX asked for: a legend of more lines than the map is tall
        # made the plot's row taller than the widget (the view box and the longitude
        # axis pushed out of sight, the view a strip). The lines that do not fit are
        # clipped (every name is in the Layers panel).
        self.setMinimumHeight(min(height, MIN_HEIGHT_PX))
        self.setMaximumHeight(height)
        self.setVisible(not self.bare)  # an empty legend draws nothing but keeps its column
        self.updateGeometry()

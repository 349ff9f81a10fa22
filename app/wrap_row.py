"""A row of widgets that wraps onto more lines where the width does not hold it."""

from PySide6 import QtCore, QtWidgets


class WrapRow(QtWidgets.QLayout):
    """Widgets left to right on one line, wrapped onto the next where the width does not
    hold them all: as narrow as its widest widget, and where it is wide enough one line
    as a QHBoxLayout without stretch would be, each widget centred on its line (h179: the
    time panel's playback controls and time-window buttons on one row, at least 685 px,
    with the docks beside the map kept the main window 1,368 px wide at least)."""

    def __init__(self, parent=None, spacing: int = 6) -> None:
        super().__init__(parent)
        self._items: list[QtWidgets.QLayoutItem] = []
        self._gap = spacing

    def addItem(self, item) -> None:  # noqa: N802 (Qt API)
        self._items.append(item)

    def count(self) -> int:
        return len(self._items)

    def itemAt(self, index: int):  # noqa: N802 (Qt API)
        return self._items[index] if 0 <= index < len(self._items) else None

    def takeAt(self, index: int):  # noqa: N802 (Qt API)
        return self._items.pop(index) if 0 <= index < len(self._items) else None

    def expandingDirections(self) -> QtCore.Qt.Orientation:  # noqa: N802 (Qt API)
        return QtCore.Qt.Orientation(0)

    def hasHeightForWidth(self) -> bool:  # noqa: N802 (Qt API)
        return True

    def heightForWidth(self, width: int) -> int:  # noqa: N802 (Qt API)
        return self._place(QtCore.QRect(0, 0, width, 0), move=False)

    def setGeometry(self, rect: QtCore.QRect) -> None:  # noqa: N802 (Qt API)
        super().setGeometry(rect)
        self._place(rect, move=True)

    def sizeHint(self) -> QtCore.QSize:  # noqa: N802 (Qt API)
        shown = [i for i in self._items if not i.isEmpty()]
        width = sum(i.sizeHint().width() for i in shown) + self._gap * max(len(shown) - 1, 0)
        height = max((i.sizeHint().height() for i in shown), default=0)
        m = self.contentsMargins()
        return QtCore.QSize(width + m.left() + m.right(), height + m.top() + m.bottom())

    def minimumSize(self) -> QtCore.QSize:  # noqa: N802 (Qt API)
        size = QtCore.QSize()
        for item in self._items:
            if not item.isEmpty():
                least = QtCore.QSize(_least_width(item), item.minimumSize().height())
                size = size.expandedTo(least)
        m = self.contentsMargins()
        return size + QtCore.QSize(m.left() + m.right(), m.top() + m.bottom())

    def _place(self, rect: QtCore.QRect, move: bool) -> int:
        """Lay the widgets out in ``rect`` (``move``: for real); the height they take."""
        m = self.contentsMargins()
        left, right = rect.x() + m.left(), rect.right() - m.right()
        shown = [i for i in self._items if not i.isEmpty()]
        # Widgets at their size hints where the row holds them so, else at their least
        # widths (as a QHBoxLayout squeezes them) before anything wraps.
        roomy = sum(i.sizeHint().width() + self._gap for i in shown) - self._gap
        squeeze = roomy > right - left + 1
        lines: list[list] = [[]]
        x = left
        for item in shown:
            hint = item.sizeHint()
            if squeeze:
                hint = QtCore.QSize(_least_width(item), hint.height())
            if x > left and x + hint.width() - 1 > right:  # the next line
                lines.append([])
                x = left
            lines[-1].append((item, x, hint))
            x += hint.width() + self._gap
        y = rect.y() + m.top()
        for k, line in enumerate(lines):
            height = max((hint.height() for _, _, hint in line), default=0)
            if move:  # each widget centred on its line (a label beside a spin box)
                for item, x, hint in line:
                    top = y + (height - hint.height()) // 2
                    item.setGeometry(QtCore.QRect(QtCore.QPoint(x, top), hint))
            y += height + (self._gap // 2 if k + 1 < len(lines) else 0)
        return y - rect.y() + m.bottom()


def _least_width(item: QtWidgets.QLayoutItem) -> int:
    """The least width of a row's widget (its minimum size hint, or the minimum width set;
    a spin box's item says its size hint, which a QHBoxLayout squeezes below)."""
    w = item.widget()
    if w is None:
        return item.minimumSize().width()
    return max(w.minimumSizeHint().width(), w.minimumWidth(), 0)

"""A legend that lives in the plot's layout, beside the view box: it never covers data."""

import html
import itertools
import re

import pyqtgraph as pg
from PySide6 import QtCore, QtGui

#: Longest legend label (characters); longer ones are shortened in the middle, so the
#: column beside the map stays narrow (the full names are in the Layers panel).
LABEL_MAX = 32
#: The legend column is this many characters ("n") wide, from the start and for good;
#: a label wider than that is shortened in the middle to fit it (by pixels, so wide
#: glyphs such as Chinese fit too).
RESERVED_CHARS = 23  # 26 took a third of the map beside the docks (1600 px window)
#: Room (px) left in the column for a label item's own padding.
LABEL_PADDING_PX = 10.0
#: Between a layer's file name and what the layer is ("tracks.csv · cleaned").
LABEL_SEPARATOR = " · "
#: In place of the first steps a shortened label leaves out ("scene…radar ·…· maneuvers"):
#: two spaces narrower than " · … · ", and it keeps "F · cleaned · maneuvers" apart from
#: "F · maneuvers" (review h158).
STEPS_LEFT_OUT = " … "
#: Fewest characters of the file's name a shortened label keeps before its "· what".
MIN_HEAD_CHARS = 8
#: ... and when the first steps are left out for the last ones ("scene… · … · maneuvers").
MIN_HEAD_CHARS_STEPS = 5
#: The most height (px) the legend asks of the plot's layout; a longer one is clipped.
MIN_HEIGHT_PX = 120.0


#: The second line of a two-line label (:meth:`SideLegend.shown_label`) starts this far in.
INDENT = "  "
INDENT_HTML = "&nbsp;&nbsp;"


#: A file name's extension, left out of a shortened label (the tooltip keeps it).
EXTENSION = re.compile(
    r"\.(csv|tsv|txt|dat|json|geojson|gpx|nmea|log|xlsx?)(\.(gz|bz2|xz|zip))?$", re.I
)


def short_label(text: str, limit: int = LABEL_MAX) -> str:
    """``text`` shortened in the middle to at most ``limit`` characters."""
    if len(text) <= limit:
        return text
    head = (limit - 1) // 2
    return text[:head] + "…" + text[-(limit - 1 - head) :]


class FixedSample(pg.ItemSample):
    """A legend entry's sample that a click leaves alone: pyqtgraph's hid the curve behind
    the session's back (the layer still ticked in the Layers list, the entry an eye);
    layers are shown and hidden in the Layers list, and their entries follow."""

    def mouseClickEvent(self, event) -> None:  # noqa: N802 - pyqtgraph's name
        event.ignore()


class SideLegend(pg.LegendItem):
    """A legend that lives in the plot's layout (a column right of the view box).

    Its column has a constant width: reserved from the start (:data:`RESERVED_CHARS`
    characters) and never narrower later. A legend that appeared or changed width with
    the first layer or a selection would resize the view box, and every layer would be
    decimated and stroked again (a block of the GUI thread at a million points).
    ``bare`` (images of the plot area alone) gives it no width at all.
    """

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("sampleType", FixedSample)
        super().__init__(*args, **kwargs)
        self.bare = False
        self.off = False  # hidden by View ▸ Show legend: no column at all
        self.setFlag(self.GraphicsItemFlag.ItemClipsChildrenToShape, True)
        font = QtGui.QFont()
        font.setPointSizeF(9.0)  # pyqtgraph's legend label size
        self._metrics = QtGui.QFontMetricsF(font)
        self._text_px = float(self._metrics.horizontalAdvance("n" * RESERVED_CHARS))
        self.widest = self._text_px + 20 + 3 + 12  # the line sample, spacing, margins
        # A label item is wider than its text by its own padding (~6 px): labels are
        # shortened to fit the column less that, so a long name never widens it.
        self._label_px = self._text_px - LABEL_PADDING_PX
        self._rank: dict[int, int] = {}  # id(sample) -> its place among the entries
        self._ranks = itertools.count()
        self._hidden: dict[int, tuple] = {}  # id(item) -> (sample, label) left out
        bold = QtGui.QFont(font)
        bold.setBold(True)
        self._bold_metrics = QtGui.QFontMetricsF(bold)
        # A bold size no wider than the plain text (for a name that bold at 9 pt would
        # shorten more than plain: drawn whole, a little smaller)
        sample = "a_radar_console_zh.csv · cleaned · compressed 雷达"
        plain_px = self._metrics.horizontalAdvance(sample)
        self._bold_small = "9pt"
        for tenth in range(89, 59, -1):
            bold.setPointSizeF(tenth / 10)
            if QtGui.QFontMetricsF(bold).horizontalAdvance(sample) <= plain_px:
                self._bold_small = f"{tenth / 10:g}pt"
                break
        self._bold: set[int] = set()  # id(item) of the entries drawn bold (the active layer)
        self.updateSize()

    def _set_label(self, label, name: str, bold: bool) -> None:
        """``label`` showing ``name`` (its fitted text), bold or plain. Bold, it is fitted
        with the bold font's widths; when that would shorten it more than plain, it is
        drawn whole in a smaller bold size (:attr:`_bold_small`) that fits as plain does:
        a bold label never widens the column nor loses what the plain one shows."""
        size = self.opts.get("labelTextSize", "9pt")
        text = self.shown_label(name) if name else label.text
        if bold and name:
            plain = self._metrics
            self._metrics = self._bold_metrics
            try:
                wide = self.shown_label(name)
            finally:
                self._metrics = plain
            if wide == text:
                label.setText(text, bold=True, size=size)
            else:
                label.setText(text, bold=True, size=self._bold_small)
            return
        label.setText(text, bold=bold, size=size)

    def set_bold(self, items) -> None:
        """The entries of ``items`` (the active layer's curves) in bold, the others not:
        the legend says which layer is active (the map draws it on top, the others dimmed).
        A bold label fits the column as the plain one does (:meth:`_set_label`), so it
        never widens the column (the map would be decimated again)."""
        want = {id(item) for item in items}
        if want == self._bold:
            return
        for sample, label in [*self.items, *self._hidden.values()]:
            on = id(sample.item) in want
            if on == (id(sample.item) in self._bold):
                continue
            self._set_label(label, label.toolTip(), on)
        self._bold = want

    def is_bold(self, item) -> bool:
        """Whether ``item``'s entry is drawn bold (the active layer's)."""
        return id(item) in self._bold

    def set_shown(self, on: bool) -> None:
        """The legend shown, or hidden with no column (View ▸ Show legend): the map
        takes the column's width."""
        self.off = not on
        self.updateSize()

    def fit_label(self, name: str) -> str:
        """``name`` shortened to fit the column. A layer's name ``FILE · what`` (the steps'
        layers, the input's sensors) keeps ``· what`` whole and shortens the file's name
        in its middle: shortening the whole left "autoferry_{ra…v · maneuvers" beside
        "autoferry_{ra… · compressed" (the file's end cut at a different place in each).
        When the steps do not fit (``FILE · cleaned · maneuvers (compress)``), the last
        ones are kept — what tells two layers of one file apart — and the first replaced
        by "·…·" (STEPS_LEFT_OUT), and the file's extension left out ("scene…radar ·…·
        maneuvers (compress)"); the full name is the label's tooltip."""
        middle = QtCore.Qt.TextElideMode.ElideMiddle
        whole = self._metrics.elidedText(short_label(name), middle, self._label_px)
        if whole == name:
            return name
        head, sep, what = name.partition(LABEL_SEPARATOR)
        if not (head and what):
            return self.fit_words(name, self._label_px) if " " in name else whole
        # Shortened, a label leaves out the files' extensions (which never tell two
        # files apart) so that the file's own name keeps its start and end:
        # "Sce…csv · … · maneuvers" beside "Sce…csv · … · compressed" named no file
        # (operator test h150). Left-out first steps leave STEPS_LEFT_OUT: without it
        # "F · cleaned · maneuvers" and "F · maneuvers" got one label (review h158).
        head = " + ".join(EXTENSION.sub("", piece) for piece in head.split(" + "))
        parts = what.split(LABEL_SEPARATOR)
        for k in range(len(parts)):
            tail = (STEPS_LEFT_OUT if k else sep) + LABEL_SEPARATOR.join(parts[k:])
            room = self._label_px - self._metrics.horizontalAdvance(tail)
            least = MIN_HEAD_CHARS if k == 0 else MIN_HEAD_CHARS_STEPS
            if room >= self._metrics.horizontalAdvance("n" * least):
                head = short_label(head, max(LABEL_MAX - len(tail), least))
                return self._metrics.elidedText(head, middle, room) + tail
        # no room for the file's name beside the last step: the last step alone
        last = "…" + sep + parts[-1]
        if self._metrics.horizontalAdvance(last) <= self._label_px:
            return last
        return self.fit_words(parts[-1], self._label_px)

    def fit_words(self, text: str, room: float) -> str:
        """``text`` in ``room`` px, shortened by whole words: its first words left out
        for "…" (its end — a rule's name and count, "… stationary (12,169)" — kept), never
        cut inside a word ("removed: st…ry (12,169)", operator test 11, F20); a text of
        one word too wide, or whose last word alone is, shortened in its middle."""
        if self._metrics.horizontalAdvance(text) <= room:
            return text
        words = text.split(" ")
        for k in range(1, len(words)):
            tail = "… " + " ".join(words[k:])
            if self._metrics.horizontalAdvance(tail) <= room:
                return tail
        return self._metrics.elidedText(text, QtCore.Qt.TextElideMode.ElideMiddle, room)

    def shown_label(self, name: str) -> str:
        """The label drawn for ``name``: itself when it fits the column; else, for a
        layer's name ``FILE · what``, two lines — the file's name (shortened in its middle
        only if it alone is too wide) and, indented under it, what the layer is (its last
        steps kept, as :meth:`fit_label` keeps them, if all are too wide) — as rich text.
        The column is narrow but the legend has height to spare: one line left
        "a_ra…e_zh … compressed" of "a_radar_console_zh · cleaned · compressed"
        (operator test 7, D16). Other names: :meth:`fit_label`'s one line."""
        if "\n" in name:  # lines of their own (a layer's name, then its first track's)
            shown = [self.shown_label(line) for line in name.split("\n")]
            return "<br>".join(
                html.escape(t) if t == line else t
                for t, line in zip(shown, name.split("\n"), strict=True)
            )
        one = self.fit_label(name)
        if one == name:
            return name
        head, sep, what = name.partition(LABEL_SEPARATOR)
        if not (head and what):
            return one
        middle = QtCore.Qt.TextElideMode.ElideMiddle
        first = self._metrics.elidedText(head + sep.rstrip(), middle, self._label_px)
        pieces = head.split(" + ")
        if first != head + sep.rstrip() and len(pieces) > 1:
            # several files (a fuse across layers): one line each, so that each keeps
            # its name ("scene-0_erro..._radar.csv" named neither: operator test 8, D8)
            ends = [" +"] * (len(pieces) - 1) + [sep.rstrip()]
            first = "\n".join(
                self._metrics.elidedText(piece + end, middle, self._label_px)
                for piece, end in zip(pieces, ends, strict=True)
            )
        room = self._label_px - self._metrics.horizontalAdvance(INDENT)
        parts = what.split(LABEL_SEPARATOR)
        second = ""
        for k in range(len(parts)):
            tail = ("… " if k else "") + LABEL_SEPARATOR.join(parts[k:])
            if self._metrics.horizontalAdvance(tail) <= room:
                second = tail
                break
        if not second:
            second = self.fit_words(parts[-1], room)
        first = "<br>".join(html.escape(line) for line in first.split("\n"))
        return f"{first}<br>{INDENT_HTML}{html.escape(second)}"

    def addItem(self, item, name: str) -> None:  # noqa: N802 - pyqtgraph's name
        super().addItem(item, self.shown_label(str(name)))
        sample, label = self.items[-1]
        label.setToolTip(str(name))  # the whole name, however the label is shortened
        self._rank[id(sample)] = next(self._ranks)

    def rename(self, item, rename) -> None:
        """The entry of ``item`` (shown or left out) renamed by ``rename`` (its whole
        name → the new one; a language switch's words)."""
        pairs = [*self.items, *self._hidden.values()]
        for sample, label in pairs:
            if sample.item is item:
                name = rename(label.toolTip())
                if name != label.toolTip():
                    self._set_label(label, name, id(item) in self._bold)
                    label.setToolTip(name)
                return

    def removeItem(self, item) -> None:  # noqa: N802 - pyqtgraph's name
        """Remove ``item``'s entry, shown or left out (:meth:`show_entries`)."""
        self._bold.discard(id(item))
        pair = self._hidden.pop(id(item), None)
        if pair is not None:
            self._rank.pop(id(pair[0]), None)
            self._removeItemFromLayout(*pair)
            return
        for sample, _label in self.items:
            if sample.item is item or _label.text == item:
                self._rank.pop(id(sample), None)
                break
        super().removeItem(item)

    def show_entries(self, items, shown: bool) -> None:
        """Leave the entries of ``items`` out of the legend (``shown`` False: a hidden
        layer's) or show them again in their place among the others. The entries are kept,
        not made again (a new label costs pyqtgraph ~9 ms of text layout)."""
        ids = {id(item) for item in items}
        if shown:
            back = [self._hidden.pop(i) for i in ids if i in self._hidden]
            if not back:
                return
            self.items.extend(back)
            self.items.sort(key=lambda pair: self._rank.get(id(pair[0]), 0))
            for sample, label in back:
                sample.show()
                label.show()
        else:
            out = [pair for pair in self.items if id(pair[0].item) in ids]
            if not out:
                return
            for sample, label in out:
                self.items.remove((sample, label))
                self._hidden[id(sample.item)] = (sample, label)
                sample.hide()
                label.hide()
        for k in range(self.layout.count() - 1, -1, -1):  # laid out again, in order
            self.layout.removeAt(k)
        for sample, label in self.items:
            self._addItemToLayout(sample, label)
        self.updateSize()

    def clear(self) -> None:
        """Remove every entry, those left out too."""
        for pair in self._hidden.values():
            self._removeItemFromLayout(*pair)
        self._hidden.clear()
        self._rank.clear()
        self._bold.clear()
        super().clear()

    def hidden_items(self) -> list:
        """The plot items whose entries are left out (:meth:`show_entries`)."""
        return [sample.item for sample, _label in self._hidden.values()]

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
        # the layout's margins and the spacing between rows are part of its height too:
        # left out, the shape clipped the last line (a legend of one entry cut in half)
        rows = self.layout.rowCount()
        _left, top, _right, bottom = self.layout.getContentsMargins()
        height += top + bottom + max(self.layout.verticalSpacing(), 0.0) * max(rows - 1, 0)
        if self.items:
            self.widest = max(self.widest, width + 6)
        w = 0.0 if self.bare or self.off else self.widest
        self.setMinimumWidth(w)
        self.setMaximumWidth(w)
        # At most MIN_HEIGHT_PX asked for: a legend of more lines than the map is tall
        # made the plot's row taller than the widget (the view box and the longitude
        # axis pushed out of sight, the view a strip). The lines that do not fit are
        # clipped (every name is in the Layers panel).
        self.setMinimumHeight(min(height, MIN_HEIGHT_PX))
        self.setMaximumHeight(height)
        # an empty legend draws nothing but keeps its column
        self.setVisible(not (self.bare or self.off))
        self.updateGeometry()

"""The time slider under the map (issue 13): a slider over the visible layers' time span,
play / pause, speed (scene seconds per second, ×1 … ×1000), step back and forward, the
trail length, and a [from, to] time window for the map and the batch table.

The panel only holds the time and emits it; :class:`~wakeline.app.map_time.TimeController`
draws. Scene-relative times (MTAD, Øresund) show as elapsed time ``T+h:mm:ss``.

Hooks: :func:`install_time` puts the panel under a main window's map; :func:`link_gantt`
ties the slider and a Gantt chart's time cursor both ways.
"""

import dataclasses
import math
import time

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app.time_text import format_time
from wakeline.app.wrap_row import WrapRow
from wakeline.core.timeline import PlaybackParams

SLIDER_STEPS = 10_000
_FIELDS = {f.name: f for f in dataclasses.fields(PlaybackParams)}
#: Sizes (px) a tinted icon is made at.
ICON_SIZES = (16, 20, 24, 32)


def dark_palette(palette: QtGui.QPalette) -> bool:
    """Whether ``palette`` is a dark one (its window colour darker than mid-grey)."""
    return palette.color(QtGui.QPalette.ColorRole.Window).lightness() < 128


def palette_icon(widget: QtWidgets.QWidget, pixmap) -> QtGui.QIcon:
    """The style's standard icon ``pixmap`` for ``widget``: as drawn on a light palette;
    on a dark one, its shape filled with the palette's button text colour (the style's
    dark-grey ▶, ◀◀ and frame icons nearly vanished on a dark desktop: h225 item 15).
    Only for one-colour icons (not the coloured folder or the red stop)."""
    icon = widget.style().standardIcon(pixmap)
    palette = widget.palette()
    if not dark_palette(palette):
        return icon
    out = QtGui.QIcon()
    ink = palette.color(QtGui.QPalette.ColorRole.ButtonText)
    for mode, colour in (
        (QtGui.QIcon.Mode.Normal, ink),
        (QtGui.QIcon.Mode.Disabled, ink.darker(200)),
    ):
        for side in ICON_SIZES:
            shape = icon.pixmap(QtCore.QSize(side, side))
            tinted = QtGui.QPixmap(shape.size())
            tinted.setDevicePixelRatio(shape.devicePixelRatio())
            tinted.fill(QtCore.Qt.GlobalColor.transparent)
            painter = QtGui.QPainter(tinted)
            painter.drawPixmap(0, 0, shape)
            painter.setCompositionMode(QtGui.QPainter.CompositionMode.CompositionMode_SourceIn)
            painter.fillRect(QtCore.QRectF(0, 0, side, side), colour)
            painter.end()
            out.addPixmap(tinted, mode)
    return out


class TimePanel(QtWidgets.QWidget):
    """Slider, playback and time window. ``time_changed(t)`` (s since 1970) on every
    move; ``window_changed(window)`` with (from, to) or None; ``trail_changed()``;
    ``overlay_toggled(on)`` when the positions are switched on or off."""

    time_changed = QtCore.Signal(float)
    window_changed = QtCore.Signal(object)
    trail_changed = QtCore.Signal()
    overlay_toggled = QtCore.Signal(bool)

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self._lo, self._hi = 0.0, 0.0
        self._t = math.nan
        self._relative = False
        self._from = self._to = math.nan
        self._left_out = (0, False)  # layers on the other clock: (how many, scene times)
        self._timer = QtCore.QTimer(self)
        self._timer.timeout.connect(self._tick)
        self._last_tick = 0.0
        self.back_button = QtWidgets.QToolButton()
        self.back_button.clicked.connect(lambda: self.step(-1))
        self.play_button = QtWidgets.QToolButton()
        self.play_button.setCheckable(True)
        self.play_button.toggled.connect(self._play_toggled)
        self.forward_button = QtWidgets.QToolButton()
        self.set_icons()
        self.forward_button.clicked.connect(lambda: self.step(1))
        self.slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.slider.setRange(0, SLIDER_STEPS)
        self.slider.valueChanged.connect(self._slider_moved)
        self.time_label = QtWidgets.QLabel("—")
        # Fixed widths: a text that grows must never re-lay out the window (a resized map
        # redoes its level of detail and repaints a million points).
        # Wide enough for the longest zone offset (UTC-09:30): a display zone's "UTC+2"
        # was cut to "UTC+" (operator test 7, D16).
        wide = self.fontMetrics().horizontalAdvance("2024-01-01 00:00:00.000 UTC-09:30  ")
        self.time_label.setFixedWidth(wide)
        self.speed = self._spin("speed", 0)
        self.trail = self._spin("trail_min", 1)
        self.step_size = self._spin("step_s", 1)
        self.trail.valueChanged.connect(lambda _v: self.trail_changed.emit())
        self.overlay_box = QtWidgets.QCheckBox()
        self.overlay_box.setChecked(True)
        self.overlay_box.toggled.connect(self.overlay_toggled)
        self.window_button = QtWidgets.QToolButton()
        self.window_button.setCheckable(True)
        self.window_button.toggled.connect(self._window_toggled)
        self.from_button = QtWidgets.QToolButton()
        self.from_button.clicked.connect(self.set_from_here)
        self.to_button = QtWidgets.QToolButton()
        self.to_button.clicked.connect(self.set_to_here)
        self.window_label = QtWidgets.QLabel()
        self.speed_label, self.trail_label, self.step_label = (QtWidgets.QLabel() for _ in "123")

        row1 = QtWidgets.QHBoxLayout()
        for w in (self.back_button, self.play_button, self.forward_button):
            row1.addWidget(w)
        row1.addWidget(self.slider, 1)
        row1.addWidget(self.time_label)
        # Wrapped onto a second line where the map is narrower than the row (h179: one
        # row of at least 685 px, with the docks beside the map, kept the window 1,368 px
        # wide at least, wider than a 1280x720 screen).
        row2 = WrapRow()
        for w in (
            self.speed_label,
            self.speed,
            self.trail_label,
            self.trail,
            self.step_label,
            self.step_size,
            self.overlay_box,
            self.window_button,
            self.from_button,
            self.to_button,
        ):
            row2.addWidget(w)
        # The window's range on a line of its own, always there: beside the buttons it had
        # the row's leftover width, none at the default layout (ATD: "2024-0" of
        # "2024-01-01 06:00:00 UTC to 2024-01-01 12:00:00 UTC"). Its text never changes its
        # size (ignored width, one line's height): no re-layout of the map.
        ignored = QtWidgets.QSizePolicy.Policy.Ignored
        self.window_label.setSizePolicy(ignored, QtWidgets.QSizePolicy.Policy.Fixed)
        self.window_label.setFixedHeight(self.fontMetrics().height() + 2)
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(4, 2, 4, 2)
        lay.setSpacing(2)
        lay.addLayout(row1)
        lay.addLayout(row2)
        lay.addWidget(self.window_label)
        self.retranslate()
        self._enable(False)

    def _spin(self, name: str, decimals: int) -> QtWidgets.QDoubleSpinBox:
        """A spin box from the :class:`PlaybackParams` field ``name`` (range, default)."""
        f = _FIELDS[name]
        box = QtWidgets.QDoubleSpinBox()
        box.setDecimals(decimals)
        box.setRange(f.metadata["lo"], f.metadata["hi"])
        box.setValue(f.default)
        box.setStepType(QtWidgets.QAbstractSpinBox.StepType.AdaptiveDecimalStepType)
        box.setKeyboardTracking(False)
        return box

    # -- texts ---------------------------------------------------------------------------

    def retranslate(self) -> None:
        """Set every text (again when the language changes)."""
        tr = self.tr
        self.back_button.setToolTip(tr("Step back"))
        self.forward_button.setToolTip(tr("Step forward"))
        self.play_button.setToolTip(tr("Play / pause"))
        self._slider_tip()
        self.speed_label.setText(tr("Speed"))
        self.speed.setPrefix("×")
        self.speed.setToolTip(tr("Scene seconds per second of playback"))
        self.trail_label.setText(tr("Trail"))
        self.trail.setSuffix(" " + tr("min"))
        self.trail.setToolTip(tr("Trail drawn behind each position (0: markers only)"))
        self.step_label.setText(tr("Step"))
        self.step_size.setSuffix(" " + tr("s"))
        self.step_size.setToolTip(tr("Time moved by one step"))
        self.overlay_box.setText(tr("Positions"))
        self.overlay_box.setToolTip(tr("Show each track's position at the slider's time"))
        self.window_button.setText(tr("Time window"))
        self.window_button.setToolTip(
            tr(
                "Show only points inside [from, to] on the map, and tracks overlapping it in the table"
            )
        )
        self.from_button.setText(tr("From here"))
        self.from_button.setToolTip(tr("The window starts at the slider's time"))
        self.to_button.setText(tr("To here"))
        self.to_button.setToolTip(tr("The window ends at the slider's time"))
        self._update_labels()

    def changeEvent(self, event) -> None:  # noqa: N802 - Qt API
        if event.type() == QtCore.QEvent.Type.LanguageChange:
            self.retranslate()
        if event.type() == QtCore.QEvent.Type.PaletteChange:  # a dark desktop: the icons
            self.set_icons()
        super().changeEvent(event)

    def _update_labels(self) -> None:
        self.time_label.setText(format_time(self._t, self._relative))
        if self.time_window() is None:
            self.window_label.setText(self.tr("Time window: none (every time shown)"))
        else:
            a, b = self.time_window()
            span = self.tr("{0} to {1}").format(
                format_time(a, self._relative), format_time(b, self._relative)
            )
            self.window_label.setText(self.tr("Time window: {0}").format(span))
        note = self.left_out_text()
        if note:
            self.window_label.setText(f"{self.window_label.text()} · {note}")
        self.window_label.setToolTip(self.window_label.text())

    def left_out_text(self) -> str:
        """What the slider leaves out, or "": layers on the other clock (scene times
        beside dates) are neither on the slider nor cut by the window (docs/time.md)."""
        n, relative = self._left_out
        if not n:
            return ""
        if relative:
            text = (
                self.tr(
                    "1 layer with scene times (T+…) is off this slider and its window; "
                    "select it to use its times"
                )
                if n == 1
                else self.tr(
                    "{0} layers with scene times (T+…) are off this slider and its "
                    "window; select one to use their times"
                )
            )
        else:
            text = (
                self.tr(
                    "1 layer with dates is off this slider and its window; select it to "
                    "use its times"
                )
                if n == 1
                else self.tr(
                    "{0} layers with dates are off this slider and its window; select "
                    "one to use their times"
                )
            )
        return text.format(n)

    def set_left_out(self, n: int, relative: bool = False) -> None:
        """How many layers the slider leaves out (on the other clock) and whether their
        times are scene times; said under the buttons and in the slider's tooltip."""
        if (n, relative) == self._left_out:
            return
        self._left_out = (n, relative)
        self._slider_tip()
        self._update_labels()

    def _slider_tip(self) -> None:
        tip = self.tr("Time: every visible track is shown at its position then")
        note = self.left_out_text()
        self.slider.setToolTip(f"{tip}\n{note}" if note else tip)

    def _enable(self, on: bool) -> None:
        for w in (self, self.slider, self.play_button, self.back_button, self.forward_button):
            w.setEnabled(on)

    # -- time ----------------------------------------------------------------------------

    def params(self) -> PlaybackParams:
        """The panel's playback settings."""
        return PlaybackParams(
            trail_min=float(self.trail.value()),
            speed=float(self.speed.value()),
            step_s=float(self.step_size.value()),
        )

    def time_range(self) -> tuple[float, float]:
        return self._lo, self._hi

    def set_range(self, bounds: tuple[float, float] | None, relative: bool = False) -> None:
        """The slider's span (s since 1970; None: no data) and how times read."""
        self._relative = relative
        if bounds is None:
            self.pause()
            self._lo = self._hi = 0.0
            self._t = math.nan
            self._enable(False)
            self._update_labels()
            return
        self._lo, self._hi = float(bounds[0]), float(bounds[1])
        self._enable(True)
        t = self._t if self._lo <= self._t <= self._hi else self._lo
        self.set_time(t)

    def time(self) -> float:
        """The slider's time (s since 1970; NaN when there is no data)."""
        return self._t

    def set_time(self, t: float) -> None:
        """Move the slider to ``t`` (clipped to the span) and emit ``time_changed``."""
        if self._hi < self._lo or not math.isfinite(t):
            return
        self._t = min(max(float(t), self._lo), self._hi)
        span = self._hi - self._lo
        value = round((self._t - self._lo) / span * SLIDER_STEPS) if span > 0 else 0
        self.slider.blockSignals(True)
        self.slider.setValue(value)
        self.slider.blockSignals(False)
        self._update_labels()
        self.time_changed.emit(self._t)

    def _slider_moved(self, value: int) -> None:
        self.set_time(self._lo + (self._hi - self._lo) * value / SLIDER_STEPS)

    def step(self, n: int = 1) -> None:
        """Move by ``n`` steps (negative: back)."""
        if math.isfinite(self._t):
            self.set_time(self._t + n * float(self.step_size.value()))

    # -- playback ------------------------------------------------------------------------

    @property
    def is_playing(self) -> bool:
        return self._timer.isActive()

    def play(self) -> None:
        self.play_button.setChecked(True)

    def pause(self) -> None:
        self.play_button.setChecked(False)

    def set_icons(self) -> None:
        """The buttons' icons for the palette now (palette_icon)."""
        sp = QtWidgets.QStyle.StandardPixmap
        self.back_button.setIcon(palette_icon(self, sp.SP_MediaSeekBackward))
        self.forward_button.setIcon(palette_icon(self, sp.SP_MediaSeekForward))
        play = sp.SP_MediaPause if self.play_button.isChecked() else sp.SP_MediaPlay
        self.play_button.setIcon(palette_icon(self, play))

    def _play_toggled(self, on: bool) -> None:
        self.set_icons()
        if on and math.isfinite(self._t):
            if self._t >= self._hi:
                self.set_time(self._lo)  # play again from the start
            self._last_tick = time.perf_counter()
            self._timer.start(max(int(1000 / PlaybackParams().fps), 1))
        else:
            self._timer.stop()
            if on:
                self.play_button.setChecked(False)

    def _tick(self) -> None:
        now = time.perf_counter()
        dt, self._last_tick = now - self._last_tick, now
        t = self._t + float(self.speed.value()) * dt
        if t >= self._hi:
            self.pause()
        self.set_time(min(t, self._hi))

    # -- time window ---------------------------------------------------------------------

    def time_window(self) -> tuple[float, float] | None:
        """(from, to) in s since 1970 when the window is on, else None."""
        if not self.window_button.isChecked() or not math.isfinite(self._from):
            return None
        return (self._from, self._to)

    def set_time_window(self, window: tuple[float, float] | None) -> None:
        """Switch the window on at (from, to) (s since 1970; swapped when reversed), or off."""
        if window is not None:
            a, b = sorted((float(window[0]), float(window[1])))
            self._from, self._to = a, b
        self.window_button.blockSignals(True)
        self.window_button.setChecked(window is not None)
        self.window_button.blockSignals(False)
        self._update_labels()
        self.window_changed.emit(self.time_window())

    def _window_toggled(self, on: bool) -> None:
        if on and not math.isfinite(self._from) and math.isfinite(self._t):
            span = self._hi - self._lo
            self.set_time_window((self._t, min(self._t + 0.1 * span, self._hi)))
        else:
            self.set_time_window((self._from, self._to) if on else None)

    def set_from_here(self) -> None:
        if math.isfinite(self._t):
            to = self._to if math.isfinite(self._to) and self._to >= self._t else self._hi
            self.set_time_window((self._t, to))

    def set_to_here(self) -> None:
        if math.isfinite(self._t):
            fr = self._from if math.isfinite(self._from) and self._from <= self._t else self._lo
            self.set_time_window((fr, self._t))

    def overlay_on(self) -> bool:
        return self.overlay_box.isChecked()


def install_time(window):
    """Put a :class:`TimePanel` under ``window``'s map and join them with a
    :class:`~wakeline.app.map_time.TimeController` (returned; the panel is
    ``window.time_panel``)."""
    from wakeline.app.map_time import TimeController

    canvas = window.takeCentralWidget()
    box = QtWidgets.QWidget()
    lay = QtWidgets.QVBoxLayout(box)
    lay.setContentsMargins(0, 0, 0, 0)
    lay.setSpacing(0)
    lay.addWidget(canvas, 1)
    panel = TimePanel(box)
    lay.addWidget(panel)
    window.setCentralWidget(box)
    window.time_panel = panel
    return TimeController(window, panel)


def link_gantt(panel: TimePanel, gantt) -> None:
    """The slider moves the Gantt chart's cursor (``gantt.set_time``) and dragging the
    cursor moves the slider (``gantt.time_changed``)."""
    panel.time_changed.connect(gantt.set_time)
    gantt.time_changed.connect(panel.set_time)
    if math.isfinite(panel.time()):
        gantt.set_time(panel.time())

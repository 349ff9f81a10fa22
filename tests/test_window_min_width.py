"""h179: at 1280x720 the main window could not be made narrower than 1,368 px (wider
than the screen): the time panel under the map held its playback controls and the time
window's three buttons on one row (685 px at least), beside the Parameters dock (291 px)
and the Bearing-only dock tabbed with Detail (380 px). That row now wraps onto a second
line where the map is narrower (app/wrap_row.py), and the map keeps 480 px
(MAP_MIN_WIDTH_PX) so that the docks give way before it: the window's least width is
1,163 px (English) with every dock shown as at start-up, in English and in Chinese, and
with the Review dock up after an association; at 1400x900 the controls stay on one line."""

import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtWidgets  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.app import i18n  # noqa: E402

LIMIT = 1280


def _least(w) -> int:
    return w.minimumSizeHint().width()


@pytest.mark.parametrize("language", ["en", "zh_CN"])
def test_the_window_fits_a_1280_px_screen_with_every_dock_shown(qtbot, tmp_path, language):
    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    try:
        _check(w, language, demo_path)
    finally:  # the application's translator back to English for the tests after this
        w.set_language("en")
        w.close()
        i18n.install(QtWidgets.QApplication.instance(), "en", None)


def _check(w, language, demo_path) -> None:
    w.set_language(language)
    _settle(w)
    docks = {k: d for k, d in w.docks.items() if d.isVisible()}
    assert set(docks) == set(w.docks)  # every dock as at start-up
    assert _least(w) <= LIMIT, {k: d.minimumSizeHint().width() for k, d in docks.items()}
    w.resize(1280, 720)
    _settle(w)
    assert w.width() == 1280
    # nothing hidden: the time panel's controls and the window's range all shown
    panel = w.time_panel
    for widget in (panel.window_button, panel.from_button, panel.to_button, panel.window_label):
        assert widget.isVisible() and widget.width() > 0
    assert panel.window_label.width() >= 500  # its own line: room for a range's text
    assert w.canvas.width() >= 480
    w.resize(1400, 900)  # the default size: one line of controls, as before
    _settle(w)
    assert abs(panel.speed.y() - panel.window_button.y()) < panel.speed.height()  # one line
    w.resize(1280, 720)
    _settle(w)
    w.load_file(demo_path())
    _settle(w)
    w.run_step("associate")
    _settle(w)
    assert w.review.dock.isVisible()
    assert _least(w) <= LIMIT


pytestmark = pytest.mark.gui

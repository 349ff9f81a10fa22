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


# -- h225 items 1, 6, 7, 14, 16: small screens, the status bar, Cancel ------------------

#: Run in a process of its own (a screen's size is the platform's, fixed per process):
#: the window on a small screen, the demo loaded and associated; prints what it measured.
SMALL_SCREEN_PROBE = r"""
import json, sys, tempfile, os
from PySide6 import QtCore, QtWidgets
app = QtWidgets.QApplication([])
sys.path.insert(0, os.environ["WAKELINE_TESTS"])
from test_review_window import _settle
from wakeline.app.main_window import MainWindow
from wakeline.resources import demo_path

W, H = int(sys.argv[1]), int(sys.argv[2])
settings = QtCore.QSettings(os.path.join(tempfile.mkdtemp(), "s.ini"),
                            QtCore.QSettings.Format.IniFormat)
settings.setValue("language", "en")
w = MainWindow(settings)
w.resize(W, H)
w.show()
_settle(w)
out = {"screen": list(w.screen().availableGeometry().getRect()), "steps": []}

def measure(step):
    inside = QtCore.QRect(0, 0, w.width(), w.height())
    docks = dict(w.docks, review=w.review.dock)
    shown = {k: d for k, d in docks.items() if d.isVisible() and not d.visibleRegion().isEmpty()}
    behind = {k: [o.objectName() for o in w.tabifiedDockWidgets(d)]
              for k, d in docks.items() if d.isVisible() and k not in shown}
    out["steps"].append({
        "step": step, "size": [w.width(), w.height()],
        "least": [w.minimumSizeHint().width(), w.minimumSizeHint().height()],
        "outside": [k for k, d in shown.items() if not inside.contains(d.geometry())],
        "status_inside": inside.contains(w.statusBar().geometry()),
        "shown": sorted(shown), "behind": behind,
        "map": [w.canvas.width(), w.canvas.height()],
        "review": w.review.dock.isVisible(),
    })

measure("empty")
w.load_file(demo_path()); _settle(w); measure("loaded")
w.run_step("associate"); _settle(w); measure("associated")
print("RESULT " + json.dumps(out))
w.close()
"""


def _small_screen(tmp_path, scale: float, size: tuple[int, int]) -> dict:
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    screen = tmp_path / "screen.json"
    screen.write_text(
        json.dumps(
            {
                "screens": [
                    {
                        "name": "s",
                        "x": 0,
                        "y": 0,
                        "width": 1920,
                        "height": 1080,
                        "logicalDpi": 96,
                        "logicalBaseDpi": 96,
                        "dpr": 1,
                    }
                ]
            }
        )
    )
    env = dict(
        os.environ,
        QT_QPA_PLATFORM=f"offscreen:configfile={screen}",
        QT_SCALE_FACTOR=str(scale),
        WAKELINE_TESTS=str(Path(__file__).parent),
    )
    run = subprocess.run(
        [sys.executable, "-c", SMALL_SCREEN_PROBE, *map(str, size)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = [x for x in run.stdout.splitlines() if x.startswith("RESULT ")]
    assert run.returncode == 0 and lines, run.stderr[-3000:]
    return json.loads(lines[-1][len("RESULT ") :])


@pytest.mark.parametrize(
    ("scale", "size"),
    [(2.0, (960, 540)), (1.5, (1280, 650))],
    ids=["1920x1080-at-200%", "1920x1080-at-150%"],
)
def test_the_window_fits_a_small_logical_screen_and_never_grows(tmp_path, scale, size):
    """h225 item 1: at 200 % on a 1080p screen (960x540 logical) the window came out
    1097x706 and grew to 1187x706 when the Review dock opened; at 150 % (1280x720, about
    650 px free) its height did not fit. Now the docks are tabbed at start on a screen
    under 800 px high, every dock shown (or its tab) and the status bar lie inside the
    window, and the window keeps the size it was given through a load and an association
    that opens the Review dock."""
    out = _small_screen(tmp_path, scale, size)
    W, H = size
    assert out["screen"][2:] == [round(1920 / scale), round(1080 / scale)]
    for step in out["steps"]:
        assert step["size"] == [W, H], step  # never resized by itself
        assert step["least"][0] <= W and step["least"][1] <= H, step
        assert step["outside"] == [] and step["status_inside"], step
        # a dock not in sight is a tab behind one that is
        for key, mates in step["behind"].items():
            assert set(mates) & set(step["shown"]), (key, step)
        assert step["map"][0] >= 320, step  # MAP_MIN_WIDTH_PX
    assert not out["steps"][0]["review"] and out["steps"][-1]["review"]  # it opened


def test_counts_stay_in_the_status_bar_after_a_hover_and_a_timed_message(qtbot, tmp_path):
    """h225 item 6: a hover's text was a 4-s status message: when it expired the counts
    were gone until the next step. The hover has its own label now (cleared after its
    time), and any timed message gives the counts back when it expires."""
    from test_review_window import _settle, _window

    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    w.load_file(demo_path())
    _settle(w)
    assert not w.batch_view.isColumnHidden(0)  # two sensors: the Sensor column shown
    counts = w.statusBar().currentMessage()
    assert counts.endswith("tracks") and "points" in counts, counts
    w._hover_timer.setInterval(100)
    w.show_hover({"sensor": "S1", "batch": "3", "time": "2024-08-02 01:00:00", "speed_kn": 12.0})
    assert w.hover_label.text() == "S1 / 3: 2024-08-02 01:00:00, 12.0 kn"
    assert w.statusBar().currentMessage() == counts  # the counts not replaced
    qtbot.waitUntil(lambda: w.hover_label.text() == "", timeout=2000)
    assert w.statusBar().currentMessage() == counts
    w.statusBar().showMessage("Pipeline done in 1.0 s", 100)  # as a job's end says
    assert w.statusBar().currentMessage() != counts
    qtbot.waitUntil(lambda: w.statusBar().currentMessage() == counts, timeout=2000)
    w.close()


def test_cancel_is_enabled_only_while_a_job_runs(qtbot, tmp_path):
    """h225 item 14: the toolbar's red Cancel was enabled on an empty, idle window."""
    from test_review_window import _settle, _window

    from wakeline.app.worker import Finished, Started
    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    cancel = w.actions_["cancel"]
    assert not cancel.isEnabled()
    seen = []  # after the window's own handler (connected first)
    w.runner.message.connect(lambda m: seen.append((type(m), cancel.isEnabled())))
    w.load_file(demo_path())
    _settle(w)
    assert (Started, True) in seen, seen
    assert [s for s in seen if s[0] is Finished] and seen[-1][1] is False, seen
    assert not cancel.isEnabled()
    w.close()


def test_no_stray_tab_bar_and_the_legend_can_be_hidden(qtbot, tmp_path):
    """h225 items 16 and 7: an empty two-tab box was drawn between the time panel and the
    log (a tab bar Qt left from tabifying the docks); View ▸ Show legend hides the map's
    legend column (kept in the settings), and the map's plot takes its width."""
    from test_review_window import _settle, _window

    from wakeline.app.main_window import MainWindow

    w = _window(qtbot, tmp_path)
    _settle(w)
    bars = [b for b in w.findChildren(QtWidgets.QTabBar) if b.parentWidget() is w and b.isVisible()]
    assert bars and all(any(b.tabText(i) for i in range(b.count())) for b in bars)
    legend = w.canvas.legend
    assert legend.isVisible() and legend.width() > 50
    plot_w = w.canvas.plot_item.vb.width()
    w.actions_["legend"].trigger()  # off
    _settle(w)
    qtbot.waitUntil(lambda: w.canvas.plot_item.vb.width() > plot_w + 50, timeout=3000)
    assert not legend.isVisible()
    assert w.settings.value("legend") in (False, "false")
    w.close()
    again = MainWindow(w.settings)  # the next start: still hidden
    qtbot.addWidget(again)
    assert not again.actions_["legend"].isChecked() and again.canvas.legend.off
    again.close()


def test_the_sensor_column_is_hidden_for_one_sensor(qtbot, tmp_path):
    """h225 item 16: the batch table's Sensor column said "S1" on every row and pushed End
    behind the scroll bar: hidden while the active layer has one sensor."""
    import pandas as pd
    from test_review_window import _settle, _window

    from wakeline.resources import demo_path

    demo = pd.read_csv(demo_path())
    one = tmp_path / "one.csv"
    demo[demo["sensor"] == demo["sensor"].iloc[0]].to_csv(one, index=False)
    w = _window(qtbot, tmp_path)
    w.load_file(one)
    _settle(w)
    assert w.batch_model.rowCount() > 0 and w.batch_view.isColumnHidden(0)
    w.load_file(demo_path())
    _settle(w)
    w.select_layer(w.layer_id(demo_path().name))
    _settle(w)
    assert not w.batch_view.isColumnHidden(0)
    w.close()

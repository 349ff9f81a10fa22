"""Operator defects of the window left by review h158 (helper h166): Load pipeline says
what it runs otherwise than the file; the dock layout at 1280x720 leaves the map its
room; an automatic stale re-run that fails says so in the status bar and the log (no
dialog the operator did not start); Run ▸ Pipeline stages are remembered without a
project (QSettings)."""

import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _window  # noqa: E402

from wakeline.core.pipeline import STEPS, Pipeline  # noqa: E402

pytestmark = pytest.mark.gui


def _pipeline_file(tmp_path, *names):
    path = tmp_path / ("_".join(names) + ".json")
    path.write_text(Pipeline(tuple((n, STEPS[n].defaults()) for n in names)).to_json())
    return path


def test_load_pipeline_says_what_it_runs_otherwise_than_the_file(qtbot, tmp_path):
    """Review h158: a saved pipeline of (compress, clean) ran clean, compress without a
    word, (associate,) ran clean, associate and (maneuvers,) ran clean, compress. Run ▸
    pipeline's stages have a fixed order (check boxes), so the file is not kept as
    written: each change is a problem, in the log, and the status bar says so."""
    w = _window(qtbot, tmp_path)
    problems = w.load_pipeline(_pipeline_file(tmp_path, "compress", "clean"))
    assert w.pipeline_stages == ("clean", "compress")
    (moved,) = problems
    assert "order Clean, Compress" in moved and "(Compress, Clean)" in moved
    assert "not as written" in w.statusBar().currentMessage()
    assert moved in w.log.toPlainText()
    (added,) = w.load_pipeline(_pipeline_file(tmp_path, "associate"))
    assert w.pipeline_stages == ("clean", "associate") and "no clean stage" in added
    problems = w.load_pipeline(_pipeline_file(tmp_path, "clean", "maneuvers"))
    assert w.pipeline_stages == ("clean", "compress")
    assert len(problems) == 1 and "maneuvers stage is run as Compress" in problems[0]
    problems = w.load_pipeline(_pipeline_file(tmp_path, "clean", "clean", "associate"))
    assert len(problems) == 1 and "Clean stage comes 2 times" in problems[0]
    # A file in the window's order is run as written, and said so.
    for names in (("clean", "compress", "associate"), ("clean", "maneuvers", "compress")):
        assert w.load_pipeline(_pipeline_file(tmp_path, *names)) == []
        assert w.statusBar().currentMessage().startswith("Pipeline loaded: runs Clean, Compress")
    w.close()


def _rows(view) -> float:
    return view.viewport().height() / view.verticalHeader().defaultSectionSize()


def test_the_review_dock_leaves_the_map_its_height_at_1280x720(qtbot, tmp_path):
    """Review h158: at 1280x720 the Review dock came up 333 px high and left the map 200
    of 720 px (214 when made smaller from 1400x900; 436 before the right column ran down
    to the status bar). The dock comes up lower so that the map keeps MAP_MIN_SHARE of
    the window's height, and gives it back when the window is made smaller; the batch
    table and the review's queue keep at least 3 rows each."""
    from wakeline.app.review_dock import MAP_MIN_SHARE
    from wakeline.resources import demo_path

    def shown(size):
        w = _window(qtbot, tmp_path)
        w.resize(*size)
        w.load_file(demo_path())
        _settle(w)
        w.run_step("associate")
        _settle(w)
        assert w.review.dock.isVisible()
        return w

    def check(w):
        share = w.canvas.height() / w.height()
        assert share >= MAP_MIN_SHARE - 0.01, (w.canvas.height(), w.height())
        assert _rows(w.batch_view) >= 3
        assert _rows(w.review.bound.panel.view) >= 3

    w = shown((1280, 720))
    check(w)
    w.close()
    w = shown((1400, 900))  # as before: the dock at its full height
    assert w.review.dock.height() >= 320 and w.canvas.height() >= 370
    w.resize(1280, 720)
    qtbot.waitUntil(lambda: w.canvas.height() / w.height() >= MAP_MIN_SHARE - 0.01)
    check(w)
    w.close()

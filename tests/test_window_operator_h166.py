"""Operator defects of the window left by review h158 (helper h166): Load pipeline says
what it runs otherwise than the file; the dock layout at 1280x720 leaves the map its
room; an automatic stale re-run that fails says so in the status bar and the log (no
dialog the operator did not start); Run ▸ Pipeline stages are remembered without a
project (QSettings)."""

import pytest

pytest.importorskip("pytestqt")

from PySide6 import QtCore, QtWidgets  # noqa: E402
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


def failed_automatic_rerun(qtbot, tmp_path, monkeypatch, dialogs: list):
    """A window whose Associate ran again by itself (a reject made while it ran put its
    result out of date) and failed: (window, source layer id, the old associate layer,
    its queue key, the gate's runs before the re-run, the gate). Dialogs' titles go to
    ``dialogs``; a question is answered Yes (Layer ▸ Remove)."""
    import dataclasses

    from test_review_rerun_late_gui import Gate, _pending

    from wakeline.core import simulate
    from wakeline.core.errors import InputError
    from wakeline.core.io import write_points
    from wakeline.core.review_session import queue_key

    class FailingGate(Gate):
        fail = False

        def __call__(self, *args, **kwargs):
            if self.fail:
                self.runs += 1
                raise InputError("injected failure")
            return super().__call__(*args, **kwargs)

    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a, **k: dialogs.append(a[1]))
    monkeypatch.setattr(
        QtWidgets.QMessageBox, "question", lambda *a, **k: QtWidgets.QMessageBox.StandardButton.Yes
    )
    gate = FailingGate(STEPS["associate"].run)
    gate.release()
    monkeypatch.setitem(STEPS, "associate", dataclasses.replace(STEPS["associate"], run=gate))
    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    lid = w.layer_id(src.name)
    w.select_layer(lid)
    w.run_step("associate")
    _settle(w)
    a1 = w.session.find(lid, "associate")
    w.select_layer(a1.id)
    _settle(w)
    key = queue_key(a1)
    # Run ▸ Associate again, held; a reject on the old layer meanwhile puts it out of date.
    gate.hold()
    w.select_layer(lid)
    w.run_step("associate")
    qtbot.waitUntil(gate.entered.is_set, timeout=30_000)
    w.select_layer(a1.id)
    qtbot.waitUntil(lambda: w.review.bound is not None and w.review.bound.key == key)
    runs = gate.runs
    w.review.bound.controller.reject(_pending(w.review.bound.controller.state)[0])
    gate.fail = True  # the run the window starts by itself fails
    gate.release()
    _settle(w)
    return w, lid, a1, key, runs, gate


def test_a_failed_automatic_rerun_is_said_without_a_dialog(qtbot, tmp_path, monkeypatch):
    """Review h158: a reject made while Associate ran again put its result out of date;
    the window ran it again by itself, and when that run failed a modal error dialog came
    up that the operator had not started. Now the status bar and the log say it (the
    result out of date, not applied); a run the operator started still gets its dialog."""
    from wakeline.core.review_session import queue_key

    dialogs = []
    w, lid, a1, key, runs, gate = failed_automatic_rerun(qtbot, tmp_path, monkeypatch, dialogs)
    assert gate.runs == runs + 1  # it did run again
    assert dialogs == []
    assert w.stale_label.isVisible()
    assert w.stale_label.text() == "Associate: out of date, its re-run failed"
    said = w.stale_label.toolTip()
    assert "run again by itself" in said and "injected failure" in said, said
    log = w.log.toPlainText()
    assert "injected failure" in log and said.splitlines()[0] in log
    assert w.session.find(lid, "associate").id == a1.id and queue_key(a1) == key  # as it was
    assert not w._automatic and not w._job_fns
    # A run the operator starts gets its dialog.
    w.select_layer(lid)
    w.run_step("associate")
    _settle(w)
    assert dialogs == ["Associate failed"]
    assert not w.stale_label.isVisible()  # the step ran again
    w.close()


def test_pipeline_stages_are_remembered_without_a_project(qtbot, tmp_path):
    """Review h158: the stages chosen in Run ▸ Pipeline stages were lost on restart when
    no project was open. They are kept in the settings; read back, a name the window
    does not know is dropped with a warning in the log."""
    from wakeline.app.jobs import PIPELINE_SETTING

    w = _window(qtbot, tmp_path)
    assert w.pipeline_stages == ("clean", "compress")  # a first window: the default
    w.actions_["pipeline_associate"].trigger()
    w.actions_["pipeline_compress"].trigger()
    assert w.pipeline_stages == ("clean", "associate")
    w.close()
    w2 = _window(qtbot, tmp_path)  # the same settings file, no project
    assert w2.pipeline_stages == ("clean", "associate")
    assert w2.actions_["pipeline_associate"].isChecked()
    assert not w2.actions_["pipeline_compress"].isChecked()
    assert w2.actions_["pipeline"].text() == "Run &pipeline (clean, associate)"
    w2.actions_["pipeline_associate"].trigger()  # a list of one ("clean",) in the INI
    w2.close()
    w3 = _window(qtbot, tmp_path)
    assert w3.pipeline_stages == ("clean",)
    w3.settings.setValue(PIPELINE_SETTING, ["clean", "fuse", "associate"])
    w3.close()
    w4 = _window(qtbot, tmp_path)
    assert w4.pipeline_stages == ("clean", "associate")
    assert "pipeline stage fuse is not one of Run ▸ Pipeline stages" in w4.log.toPlainText()
    w4.close()


def test_a_decision_swapped_into_the_map_paints_it_once(qtbot, tmp_path):
    """Review h158: a review key painted the map about 8 times (ATD dataset1): the key's
    own change, then the decision's layer swapped in over several turns (the layer, its
    level of detail, the time index, the proposal drawn again), each turn a paint. The
    swap holds the map's paints and paints once at its end (ReviewDock.hold_map).
    Counted here: the paints from the swap (Session.replace_points) on.

    Decisions that change the targets (cd875cc: an accept of a pending proposal leaves
    them as they are, and nothing is swapped in): a reject, the accept of that rejected
    proposal (joined again), a reject of the next one."""
    from test_review_rerun_late_gui import _pending

    from wakeline.core import simulate
    from wakeline.core.io import write_points

    class Paints(QtCore.QObject):
        n = 0

        def eventFilter(self, obj, event):  # noqa: N802 (Qt API)
            self.n += event.type() == QtCore.QEvent.Type.Paint
            return False

    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    w.select_layer(w.layer_id(src.name))
    w.run_step("associate")
    _settle(w)
    a1 = w.session.find(w.layer_id(src.name), "associate")
    w.select_layer(a1.id)
    _settle(w)
    paints = Paints()
    w.canvas.viewport().installEventFilter(paints)
    swaps = []
    replace = w.session.replace_points

    def replace_points(*args, **kwargs):
        swaps.append(paints.n)
        return replace(*args, **kwargs)

    w.session.replace_points = replace_points
    panel = w.review.bound.panel
    first = panel.current()
    counts = []
    for act, pid, was in (
        (panel.act_reject, first, "pending"),
        (panel.act_accept, first, "rejected"),
        (panel.act_reject, None, "pending"),
    ):
        st = w.review.bound.controller.state
        assert _pending(st)
        if pid is not None and panel.current() != pid:
            assert panel.set_current(pid)
            _settle(w)
        now = panel.current()
        row = list(st.proposals["proposal"]).index(now)
        assert st.status[row] == was, (now, st.status[row])  # the decision changes targets
        swaps.clear()
        act.trigger()
        qtbot.waitUntil(lambda: bool(swaps), timeout=30_000)
        _settle(w)
        qtbot.waitUntil(lambda: not w.canvas.holding_paints)
        qtbot.wait(300)  # anything late
        counts.append(paints.n - swaps[0])
    assert counts == [1, 1, 1], counts
    w.close()

"""Operator test 5 (h181) in the window: a project folder moved with its data file
(D-proj-1), a project renamed while open (D-proj-2), the reviewed export's pending
proposals (D-export-1) and the decision log's export line (D-review-4)."""

import shutil

import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from PySide6 import QtCore, QtGui, QtWidgets  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from test_gui_review_low import _fused_review  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.project import load_project  # noqa: E402

pytestmark = pytest.mark.gui


def _record(monkeypatch):
    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[2]))
    monkeypatch.setattr(
        QtWidgets.QMessageBox,
        "question",
        lambda *a: QtWidgets.QMessageBox.StandardButton.Discard,
    )
    return shown


def test_a_moved_project_folder_uses_the_data_file_beside_it(qtbot, tmp_path, monkeypatch):
    shown = _record(monkeypatch)
    folder = tmp_path / "A"
    folder.mkdir()
    src = folder / "scene.csv"
    write_points(simulate.demo_scene(), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    w.save_project(folder / "day.wakeline")
    _settle(w)
    assert w.project.flush(30)
    w.close()
    shutil.move(str(folder), str(tmp_path / "B"))
    moved = tmp_path / "B" / "day.wakeline"
    w2 = _window(qtbot, tmp_path)
    w2.open_project(moved)
    _settle(w2)
    log = w2.log.toPlainText()
    assert not shown, shown  # no "source file missing" dialog
    assert "found beside the project" in log and str(tmp_path / "B" / "scene.csv") in log
    assert w2.project.flush(30)
    back = load_project(moved)  # the file now says where the source is
    assert back.sources[0].path == str((tmp_path / "B" / "scene.csv").resolve())
    assert back.source_problems() == []
    w2.close()


def test_a_project_renamed_while_open_says_so_once(qtbot, tmp_path, monkeypatch):
    shown = _record(monkeypatch)
    src = tmp_path / "scene.csv"
    write_points(simulate.demo_scene(), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    assert w.project.flush(30)
    proj.rename(tmp_path / "renamed.wakeline")
    w.run_step("clean")  # one change: a layer, the active layer, the selection …
    _settle(w)
    w.project.flush(30)
    qtbot.waitUntil(lambda: w.project.failures >= 2, timeout=5000)
    QtWidgets.QApplication.processEvents()
    assert len(shown) == 1 and "moved, renamed or removed" in shown[0] and "Save as" in shown[0]
    assert "Error" not in shown[0] and "readonly" not in shown[0]
    lines = [t for t in w.log.toPlainText().splitlines() if "Saving the project failed" in t]
    assert len(lines) == 1, lines
    w.close()


def test_reviewed_exports_say_how_many_proposals_were_not_reviewed(qtbot, tmp_path):
    w = _fused_review(qtbot, tmp_path)
    b = w.review.bound
    total = len(b.controller.state.status)
    assert total >= 2
    b.panel.view.setFocus()
    QTest.keyClick(b.panel.view, QtCore.Qt.Key.Key_A)
    _settle(w)
    pending = int((b.controller.state.status == "pending").sum())
    assert 0 < pending < total
    note = f"{pending} of {total} proposals not reviewed: counted as accepted"
    w.review.sync.export(tmp_path / "rev.csv")
    _settle(w)
    log = w.log.toPlainText().splitlines()
    # "exported N points of L (reviewed tracks) to …" (operator test 7, D5: the count)
    rows = len(pd.read_csv(tmp_path / "rev.csv"))
    at = next(
        k
        for k, t in enumerate(log)
        if f"exported {rows:,} points of " in t and "(reviewed tracks) to" in t and "rev.csv" in t
    )
    assert note in log[at + 1]
    w.export("csv", tmp_path / "layer.csv")  # the layer's own export: the same rule
    _settle(w)
    log = w.log.toPlainText().splitlines()
    at = next(k for k, t in enumerate(log) if t.endswith("layer.csv"))
    assert note in log[at + 1]
    w.review.sync.export(tmp_path / "log.csv", log=True)
    _settle(w)
    last = [t for t in w.log.toPlainText().splitlines() if "log.csv" in t][-1]
    assert ": decision log to" in last and "reviewed tracks" not in last
    w.close()


def _press(w, widget, key):
    widget.setFocus()
    QtWidgets.QApplication.processEvents()
    QTest.keyClick(QtWidgets.QApplication.focusWidget() or widget, key)
    _settle(w)


def test_review_letters_act_in_the_review_dock_and_the_map_and_are_echoed(qtbot, tmp_path):
    """D-review-5: A with the focus on the batch table or the log decided the current
    proposal, with no word in the Log dock."""
    w = _fused_review(qtbot, tmp_path)
    st = w.review.bound.controller.state
    n0 = int((st.status == "pending").sum())
    _press(w, w.batch_view, QtCore.Qt.Key.Key_A)
    _press(w, w.log, QtCore.Qt.Key.Key_A)
    assert int((st.status == "pending").sum()) == n0  # not from the table nor the log
    _press(w, w.review.bound.panel.view, QtCore.Qt.Key.Key_A)
    assert int((st.status == "pending").sum()) == n0 - 1
    entry = st.log[-1]
    said = f"Review: accept {entry.proposal}"
    assert w.review.echo.text() == said
    # h230: the log line goes on to say what the decision changed
    assert w.log.toPlainText().splitlines()[-1].startswith(said + ": ")
    _press(w, w.canvas, QtCore.Qt.Key.Key_R)  # the map: the operator looks there
    assert st.log[-1].action == "reject" and len(st.log) == 2
    w.close()


def test_undo_after_a_reopen_undoes_the_last_decision_before_the_close(
    qtbot, tmp_path, monkeypatch
):
    """D-review-3: after reopening, Edit ▸ Undo was disabled without a word; h184 said
    "nothing since the project was opened"; h196 rebuilds the undo stack from the
    stored rows (tests/test_review_undo_reopen.py)."""
    _record(monkeypatch)
    w = _fused_review(qtbot, tmp_path)
    fused = w.review.bound.lid
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    w.review.review_actions["accept"].trigger()
    _settle(w)
    assert w.project.flush(30)
    w.close()
    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    w2.select_layer(fused)
    _settle(w2)
    act = w2.review.act_undo
    assert act.isEnabled() and "nothing since" not in act.text() and "accept" in act.text()
    assert act.toolTip() in ("", act.text().replace("&", ""))
    w2.review.review_actions["reject"].trigger()
    _settle(w2)
    assert act.isEnabled() and "reject" in act.text()
    w2.close()


def test_ctrl_s_says_the_project_is_saved_and_close_project_empties_the_window(
    qtbot, tmp_path, monkeypatch
):
    """D-ui-1: Ctrl+S always opened a Save-as dialog, and there was no Close project."""
    _record(monkeypatch)
    asked = []
    monkeypatch.setattr(
        QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: (asked.append(a), ("", ""))[1]
    )
    src = tmp_path / "scene.csv"
    write_points(simulate.demo_scene(), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    w.actions_["save"].trigger()  # no project yet: Save as
    assert len(asked) == 1
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    assert w.actions_["save"].shortcut() == QtGui.QKeySequence("Ctrl+S")
    w.actions_["save"].trigger()
    assert len(asked) == 1  # no dialog
    said = w.statusBar().currentMessage()
    assert "saved as it happens" in said and str(proj) in said
    w.actions_["close_project"].trigger()
    _settle(w)
    assert not w.session.layers and w.project.path is None
    assert w.windowTitle() == "Wakeline"
    assert f"Closed project {proj}" in w.log.toPlainText()
    qtbot.waitUntil(lambda: not (tmp_path / "p.wakeline.lock").exists(), timeout=5000)
    assert [lay.name for lay in load_project(proj).layers] == ["scene.csv"]  # kept
    w.close()


def test_a_decision_that_changes_nothing_is_not_echoed_as_the_last_one(qtbot, tmp_path):
    """h192: A on a proposal accepted already changes nothing, but the echo said the last
    decision again ('Review: accept F0002' after accepting F0001 twice) in the status bar
    and as a new Log line."""
    w = _fused_review(qtbot, tmp_path)
    c = w.review.bound.controller
    st = c.state
    first, second = st.proposals["proposal"][st.status == "pending"].tolist()[:2]
    c.accept(first)
    c.accept(second)
    _settle(w)
    assert w.review.echo.text() == f"Review: accept {second}"
    before = w.log.toPlainText().splitlines()
    c.accept(first)  # accepted already: no change, nothing logged
    _settle(w)
    assert len(st.log) == 2
    assert w.log.toPlainText().splitlines() == before
    c.reject(first)  # a real change is echoed
    _settle(w)
    assert w.review.echo.text() == f"Review: reject {first}"
    w.close()

"""h196 (operator test 5, D-review-3): a reopened project's undo stack is rebuilt from
the stored decision rows — Undo undoes the last decision made before the close, Redo
redoes what was undone, as in the session that made them — without writing a row or
applying anything again (core: :func:`~wakeline.core.review_store.undo_history`)."""

import json
import sqlite3

import pytest

from wakeline.core import review as R
from wakeline.core.review_store import decision_row, undo_history


def _changes(n: int) -> tuple[R.ReviewState, list[R.Change]]:
    from wakeline.core.associate import associate_interrupted
    from wakeline.core.simulate import segments_scene

    seg = segments_scene(seed=2, n_ships=8, area_km=15)
    props, _ = R.association_proposals(associate_interrupted(seg))
    st = R.ReviewState(R.track_table(seg), props)
    pids = st.proposals["proposal"].tolist()
    out = []
    for k in range(n):
        pid = pids[k % len(pids)]
        c = R.reject(st, pid) if st.status_of(pid) == "accepted" else R.accept(st, pid)
        st.apply(c)
        out.append(c)
    return st, out


def _rows(st, changes, marks=True):
    """Decision rows of queue Q as the window writes them: each change and its mark."""
    rows = []
    for c, how in changes:
        st.apply(c)
        rows.append(decision_row("Q", c, st.log[-1], stack=how if marks else None))
    return rows


def test_undo_history_replays_undos_and_redos_as_stack_moves():
    st, cs = _changes(10)
    fresh = R.ReviewState(st.tracks, st.proposals)
    moves = [(c, "do") for c in cs] + [(c.inverse(), "undo") for c in cs[::-1][:3]]
    for marks in (True, False):
        fresh = R.ReviewState(st.tracks, st.proposals)
        stack, index = undo_history(_rows(fresh, moves, marks), "Q")
        assert stack == cs and index == 7, marks
    # a redo of the 8th, then a new decision drops the Redo history (the 9th, 10th)
    fresh = R.ReviewState(st.tracks, st.proposals)
    rows = _rows(fresh, moves + [(cs[7], "redo")], True)
    assert undo_history(rows, "Q") == (cs, 8)
    undo9 = cs[8]  # pending again: the same decision made anew (not a redo)
    rows += _rows(fresh, [(undo9, "do")], True)
    assert undo_history(rows, "Q") == (cs[:9], 9)


def test_rerun_markers_repairs_and_carried_rows_are_barriers():
    st, cs = _changes(4)
    fresh = R.ReviewState(st.tracks, st.proposals)
    rows = _rows(fresh, [(cs[0], "do"), (cs[1], "do")])
    mark = R.LogEntry("t", R.RERUN, "", "", "old", "")
    rows.append(decision_row("Q", R.Change(R.RERUN), mark))
    assert undo_history(rows, "Q") == ([], 0)
    rows += _rows(fresh, [(cs[2], "carried"), (cs[3], "do")])
    assert undo_history(rows, "Q") == ([cs[3]], 1)
    rows.append(decision_row("Q", R.Change("repair", "x"), mark))
    assert undo_history(rows, "Q") == ([], 0)
    # an Undo row that does not match the stack (a log edited by hand): a barrier
    rows = _rows(R.ReviewState(st.tracks, st.proposals), [(cs[0], "do")])
    rows.append({**rows[0], "stack": "undo"})
    assert undo_history(rows, "Q") == ([], 0)
    assert undo_history(rows, "other queue") == ([], 0)


# -- the window --------------------------------------------------------------------------

pytest.importorskip("pytestqt")

from PySide6 import QtCore  # noqa: E402
from test_gui_review_low import _fused_review  # noqa: E402
from test_operator5_window import _record  # noqa: E402
from test_review_window import _settle  # noqa: E402

from wakeline.app.main_window import MainWindow  # noqa: E402
from wakeline.core.project import load_project  # noqa: E402


def _decide(w, n: int) -> list[R.Change]:
    """``n`` decisions that each change something, through the undo stack."""
    ctl = w.review.bound.controller
    pids = ctl.state.proposals["proposal"].tolist()
    for k in range(n):
        pid = pids[k % len(pids)]
        (ctl.reject if ctl.state.status_of(pid) == "accepted" else ctl.accept)(pid)
        _settle(w)
    return [ctl.stack.command(k).change for k in range(ctl.stack.count())]


def _saved_review(qtbot, tmp_path, n=10, undo=3):
    w = _fused_review(qtbot, tmp_path)
    fused = w.review.bound.lid
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    changes = _decide(w, n)
    for _ in range(undo):
        w.review.act_undo.trigger()
        _settle(w)
    assert w.review.bound.controller.stack.index() == n - undo
    assert w.project.flush(30)
    w.close()
    return proj, fused, changes


def _reopen(qtbot, tmp_path, proj, fused, language="en") -> MainWindow:
    settings = QtCore.QSettings(str(tmp_path / "s2.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", language)
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1800, 1000)
    w.show()
    w.open_project(proj)
    _settle(w)
    w.select_layer(fused)
    _settle(w)
    return w


def _rows_of(proj) -> list[dict]:
    return load_project(proj).decisions


@pytest.mark.gui
def test_decide_10_undo_3_close_reopen_undo_and_redo_go_on(qtbot, tmp_path, monkeypatch):
    _record(monkeypatch)
    proj, fused, cs = _saved_review(qtbot, tmp_path)
    before = _rows_of(proj)
    w = _reopen(qtbot, tmp_path, proj, fused)
    ctl = w.review.bound.controller
    assert (ctl.stack.count(), ctl.stack.index()) == (10, 7)
    assert w.project.flush(30)
    assert _rows_of(proj) == before  # the reopen wrote nothing
    act_u, act_r = w.review.act_undo, w.review.act_redo
    assert act_u.isEnabled() and act_r.isEnabled()
    assert "nothing since" not in act_u.text()
    assert act_r.text().endswith(ctl.stack.command(7).text())  # Redo names the 8th
    act_r.trigger()  # Redo redoes the 8th
    _settle(w)
    act_u.trigger()  # Undo undoes it again
    _settle(w)
    act_u.trigger()  # and then the 7th
    _settle(w)
    assert ctl.stack.index() == 6
    assert w.project.flush(30)
    added = _rows_of(proj)[len(before) :]
    want = [(cs[7], "redo"), (cs[7].inverse(), "undo"), (cs[6].inverse(), "undo")]
    assert [(R.Change.from_dict(r["change"]), r.get("stack")) for r in added] == want
    # a redo's log line says it is one (operator test 9, D13): "redo accept"
    assert [r["action"] for r in added] == [
        f"redo {c.action}" if how == "redo" else c.action for c, how in want
    ]
    # the state: the first 6 decisions in effect, as replaying them alone gives
    fresh = R.ReviewState(ctl.state.tracks, ctl.state.proposals)
    for c in cs[:6]:
        fresh.apply(c)
    assert list(fresh.status) == list(ctl.state.status) and fresh.links == ctl.state.links
    w.close()


@pytest.mark.gui
def test_a_reopen_in_chinese_rebuilds_the_stack_in_chinese(qtbot, tmp_path, monkeypatch):
    _record(monkeypatch)
    proj, fused, cs = _saved_review(qtbot, tmp_path, n=4, undo=1)
    w = _reopen(qtbot, tmp_path, proj, fused, language="zh_CN")
    ctl = w.review.bound.controller
    assert (ctl.stack.count(), ctl.stack.index()) == (4, 3)
    text = w.review.act_undo.text()
    assert w.review.act_undo.isEnabled() and "accept" not in text and "reject" not in text
    assert cs[2].proposal in text and ("接受" in text or "拒绝" in text), text
    w.review.act_undo.trigger()
    _settle(w)
    assert ctl.stack.index() == 2 and ctl.state.log[-1].action == cs[2].inverse().action
    w.set_language("en")
    assert w.review.act_undo.text().startswith("&Undo ")
    w.close()


def _strip_marks(proj) -> None:
    """The project as a Wakeline before h196 wrote it: rows without the ``stack`` mark."""
    db = sqlite3.connect(proj)
    with db:
        for seq, text in db.execute("SELECT seq, json FROM decisions").fetchall():
            row = json.loads(text)
            row.pop("stack", None)
            db.execute("UPDATE decisions SET json = ? WHERE seq = ?", (json.dumps(row), seq))
    db.close()


@pytest.mark.gui
@pytest.mark.parametrize("undo", [0, 2])
def test_an_old_project_without_marks_gets_its_stack_too(qtbot, tmp_path, monkeypatch, undo):
    """Rows written before the marks: with no undo row every decision is on the stack;
    with undo rows they are read as Undos by their change."""
    _record(monkeypatch)
    proj, fused, cs = _saved_review(qtbot, tmp_path, n=5, undo=undo)
    _strip_marks(proj)
    before = _rows_of(proj)
    assert before and all("stack" not in r for r in before)
    w = _reopen(qtbot, tmp_path, proj, fused)
    ctl = w.review.bound.controller
    assert (ctl.stack.count(), ctl.stack.index()) == (5, 5 - undo)
    assert "nothing since" not in w.review.act_undo.text()
    w.review.act_undo.trigger()
    _settle(w)
    assert w.project.flush(30)
    added = _rows_of(proj)[len(before) :]
    assert [(r["action"], r["stack"]) for r in added] == [(cs[4 - undo].inverse().action, "undo")]
    w.close()


@pytest.mark.gui
def test_a_stack_emptied_by_a_repair_says_so_in_both_languages(qtbot, tmp_path, monkeypatch):
    """The one barrier a reopen leaves Undo empty at without a re-run: the repair made on
    opening (a queue whose last rows are repairs; the log entry stands in for one)."""
    _record(monkeypatch)
    w = _fused_review(qtbot, tmp_path)
    b = w.review.bound
    assert b.controller.stack.count() == 0 and not b.rerun
    w.review._undo_note()
    assert "nothing since" not in w.review.act_undo.text()  # no decision: a plain Undo
    b.controller.state.log.append(R.LogEntry("t", "repair", "A0001", "", "", ""))
    w.review._undo_note()
    act = w.review.act_undo
    assert not act.isEnabled() and "nothing since the repair made on opening" in act.text()
    assert "repaired decisions an older Wakeline left inconsistent" in act.toolTip()
    w.set_language("zh_CN")
    w.review._undo_note()
    assert "打开时修复以来" in act.text() and "旧版" in act.toolTip()
    w.set_language("en")
    w.close()

"""GUI test of decisions made while a re-run computes: Run ▸ Associate again on a
reviewed layer, the job held in the worker while the operator goes on reviewing the
old layer. An accept and a hand merge made then are carried into the new queue (and
stored at once: a reopen restores them); Edit ▸ Undo after the swap has nothing to undo
and says why; a reject made while the step is held changes the pairs kept out, so the
step runs again by itself and the rejected pair stays out."""

import dataclasses
import threading

import pytest

pytest.importorskip("pytestqt")

from test_review_rerun_gui import _apart, _pairs  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.core import review as R  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.pipeline import STEPS  # noqa: E402
from wakeline.core.review_session import queue_key  # noqa: E402

pytestmark = pytest.mark.gui


class Gate:
    """Holds the associate step in the worker until :meth:`release` (once per run)."""

    def __init__(self, run) -> None:
        self.orig, self.entered, self.go, self.runs = run, threading.Event(), threading.Event(), 0

    def __call__(self, points, params, progress, rejected=frozenset(), split=frozenset()):
        self.runs += 1
        self.entered.set()
        assert self.go.wait(60), "the test never released the step"
        return self.orig(points, params, progress, rejected, split=split)

    def hold(self) -> None:
        self.entered.clear()
        self.go.clear()

    def release(self) -> None:
        self.go.set()


def _pending(st) -> list[str]:
    return [p for p, v in zip(st.proposals["proposal"], st.status, strict=True) if v == "pending"]


def test_decisions_made_while_associate_runs_again_are_carried(qtbot, tmp_path, monkeypatch):
    from wakeline.core.session import Session

    threads = []
    reconcile = Session.reconcile

    def spy(self, result):
        threads.append(threading.current_thread() is threading.main_thread())
        return reconcile(self, result)

    monkeypatch.setattr(Session, "reconcile", spy)
    gate = Gate(STEPS["associate"].run)
    gate.release()  # the first run is not held
    monkeypatch.setitem(STEPS, "associate", dataclasses.replace(STEPS["associate"], run=gate))
    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    lid = w.layer_id(src.name)
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    w.select_layer(lid)
    w.run_step("associate")
    _settle(w)
    a1 = w.session.find(lid, "associate")
    w.select_layer(a1.id)
    _settle(w)
    c = w.review.bound.controller
    st = c.state
    pids = list(st.proposals["proposal"])
    pair = {p: R.pair_key(a, b) for p, a, b in zip(pids, st.track_a, st.track_b, strict=True)}
    c.accept(pids[0])
    c.reject(pids[1])
    _settle(w)

    # Run ▸ Associate again, held in the worker once it has read the decisions.
    gate.hold()
    w.select_layer(lid)
    w.run_step("associate")
    qtbot.waitUntil(gate.entered.is_set, timeout=30_000)
    w.select_layer(a1.id)  # the operator goes on reviewing the old layer
    qtbot.waitUntil(lambda: w.review.bound is not None and w.review.bound.key == queue_key(a1))
    old_key = queue_key(a1)
    late = _pending(st)[0]
    merged = _apart(st, [pids[0], pids[1], late])
    c.accept(late)
    c.merge(merged)
    rows = [r for r in w.session.decisions if r["queue"] == old_key]
    assert [r["action"] for r in rows[-2:]] == ["accept", "merge"]  # stored at once
    assert w.runner.busy  # still held
    gate.release()
    _settle(w)
    assert threads == [False]  # the carry made again in the worker, not at the swap
    line = w.log.toPlainText().splitlines()[-1]
    assert "2 decisions made while the step ran taken into account" in line, line
    assert "1 pair rejected in an earlier review kept out" in line, line
    a2 = w.session.find(lid, "associate")
    assert a2.id == a1.id and queue_key(a2) != old_key
    w.select_layer(a2.id)
    _settle(w)
    st2 = w.review.bound.controller.state
    now = _pairs(st2)
    for p in (pids[0], late):  # accepted before and while it ran: both carried
        assert now.get(pair[p]) == "accepted" or pair[p] in st2.links, p
    assert pair[pids[1]] not in now
    assert st2.target(merged[0]) == st2.target(merged[1])
    # Undo after the swap: the decision made while it ran is not on this queue's stack.
    assert not w.review.act_undo.isEnabled()
    assert "nothing since the step ran again" in w.review.act_undo.text()
    assert "made while it ran" in w.review.act_undo.toolTip()

    # A reject while the step is held: the pairs kept out change, the step runs again.
    gate.hold()
    runs = gate.runs
    w.select_layer(lid)
    w.run_step("associate")
    qtbot.waitUntil(gate.entered.is_set, timeout=30_000)
    w.select_layer(a2.id)
    qtbot.waitUntil(lambda: w.review.bound is not None and w.review.bound.key == queue_key(a2))
    c2 = w.review.bound.controller
    rejected = _pending(st2)[0]
    k = st2._row[rejected]
    rejected_pair = R.pair_key(st2.track_a[k], st2.track_b[k])
    c2.reject(rejected)
    gate.release()
    _settle(w)
    assert gate.runs == runs + 2  # held once, then run again with the reject
    text = w.log.toPlainText()
    assert "associate: decisions made while it ran change the pairs it keeps out" in text
    a3 = w.session.find(lid, "associate")
    w.select_layer(a3.id)
    _settle(w)
    st3 = w.review.bound.controller.state
    assert rejected_pair not in _pairs(st3)
    assert st3.target(merged[0]) == st3.target(merged[1])
    state = (list(st3.status), set(st3.links))
    w.close()

    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    w2.select_layer(a1.id)
    _settle(w2)
    back = w2.review.bound.controller.state
    assert (list(back.status), set(back.links)) == state
    w2.close()

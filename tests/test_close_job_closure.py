"""h158 review finding: a step job running when the window closes ends Cancelled, and
``MainWindow._job_fns`` (kept for a stale re-run, h151) is popped only on Finished, so
the closed window keeps the job's closure — for Fuse, the input layers' points (its
``named`` list) — after ``closeEvent`` cleared the session (defect #8's rule, h147)."""

import dataclasses
import gc
import threading
import weakref

import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _sim_pair, _window  # noqa: E402

from wakeline.core.pipeline import STEPS  # noqa: E402

pytestmark = pytest.mark.gui


def test_a_job_cancelled_by_close_lets_its_inputs_go(qtbot, tmp_path, monkeypatch):
    go, entered = threading.Event(), threading.Event()
    run = STEPS["fuse"].run

    def held(points, params, progress, rejected=frozenset(), split=frozenset()):
        entered.set()
        go.wait(60)
        return run(points, params, progress, rejected, split=split)

    monkeypatch.setitem(STEPS, "fuse", dataclasses.replace(STEPS["fuse"], run=held))
    files = _sim_pair(tmp_path)
    w = _window(qtbot, tmp_path)
    w.load_files(files)
    _settle(w)
    ids = [w.layer_id(f.name) for f in files]
    refs = [weakref.ref(w.session.layers[i].points) for i in ids]
    w.layer_list.clearSelection()
    for lid in ids:
        w.layer_list.item(w.layer_row(lid)).setSelected(True)
    w.review.act_fuse.trigger()
    qtbot.waitUntil(entered.is_set, timeout=30_000)
    threading.Timer(1.0, go.set).start()  # the step ends while closeEvent waits for it
    w.close()
    qtbot.waitUntil(lambda: not w.runner.busy, timeout=30_000)
    qtbot.wait(200)  # its Cancelled message delivered
    gc.collect()
    assert not w.session.layers
    assert [r() is None for r in refs] == [True, True]


def test_a_failed_job_lets_its_function_go(qtbot, tmp_path, monkeypatch):
    """A job that fails (no window closed) drops its kept function too, not only one
    that finished."""
    monkeypatch.setattr("wakeline.app.main_window.QtWidgets.QMessageBox.warning", lambda *a: 0)
    w = _window(qtbot, tmp_path)

    def boom(progress):
        raise RuntimeError("boom")

    w._start("fuse", boom, ("fuse", ""))
    assert w._job_fns
    qtbot.waitUntil(lambda: not w.runner.busy, timeout=30_000)
    _settle(w)
    assert not w._job_fns

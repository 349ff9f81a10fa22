"""Review h175 (F7): the red 'out of date, its re-run failed' label (jobs._automatic_failed)
stayed up after the layers it speaks of were gone (Layer > Remove of the associate layer
and its source), and kept the language it was made in."""

import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtWidgets  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.core.pipeline import STEPS  # noqa: E402


def test_the_stale_label_goes_with_its_layers_and_follows_the_language(
    qtbot, tmp_path, monkeypatch
):
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

    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a, **k: None)
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
    gate.hold()
    w.select_layer(lid)
    w.run_step("associate")
    qtbot.waitUntil(gate.entered.is_set, timeout=30_000)
    w.select_layer(a1.id)
    qtbot.waitUntil(lambda: w.review.bound is not None and w.review.bound.key == key)
    w.review.bound.controller.reject(_pending(w.review.bound.controller.state)[0])
    gate.fail = True
    gate.release()
    _settle(w)
    assert w.stale_label.isVisible()
    w.set_language("zh_CN")
    _settle(w)
    zh = w.stale_label.text()
    w.set_language("en")
    _settle(w)
    assert zh != w.stale_label.text() and "out of date" in w.stale_label.text()
    for layer_id in (a1.id, lid):  # Layer > Remove, both
        w.select_layer(layer_id)
        w.remove_active_layer()
        _settle(w)
    assert not w.session.layers
    assert not w.stale_label.isVisible(), "label still says: " + w.stale_label.text()
    w.close()


pytestmark = pytest.mark.gui

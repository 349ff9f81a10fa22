"""Review h175 (F7): the red 'out of date, its re-run failed' label (jobs._automatic_failed)
stayed up after the layers it speaks of were gone (Layer > Remove of the associate layer
and its source), and kept the language it was made in; h179: its tooltip kept it still."""

import pytest

pytest.importorskip("pytestqt")
from test_review_window import _settle  # noqa: E402
from test_window_operator_h166 import failed_automatic_rerun  # noqa: E402


def test_the_stale_label_goes_with_its_layers_and_follows_the_language(
    qtbot, tmp_path, monkeypatch
):
    w, lid, a1, *_ = failed_automatic_rerun(qtbot, tmp_path, monkeypatch, [])
    assert w.stale_label.isVisible()
    en_tip = w.stale_label.toolTip()
    assert "run again by itself" in en_tip and "injected failure" in en_tip
    w.set_language("zh_CN")
    _settle(w)
    zh = w.stale_label.text()
    # h179: its tooltip follows too (it kept English)
    zh_tip = w.stale_label.toolTip()
    assert "自动重新运行" in zh_tip and "injected failure" in zh_tip, zh_tip
    w.set_language("en")
    _settle(w)
    assert zh != w.stale_label.text() and "out of date" in w.stale_label.text()
    assert w.stale_label.toolTip() == en_tip
    from PySide6 import QtWidgets

    yes = QtWidgets.QMessageBox.StandardButton.Yes  # a layer with children asks (h230)
    monkeypatch.setattr(QtWidgets.QMessageBox, "question", lambda *a, **k: yes)
    for layer_id in (a1.id, lid):  # Layer > Remove, both
        w.select_layer(layer_id)
        w.remove_active_layer()
        _settle(w)
    assert not w.session.layers
    assert not w.stale_label.isVisible(), "label still says: " + w.stale_label.text()
    w.close()


pytestmark = pytest.mark.gui

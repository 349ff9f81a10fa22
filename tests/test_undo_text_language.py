"""h158 review finding, fixed in session 27: Edit ▸ Undo/Redo kept each command's own
text in the language it was made in (a decision made in English read "撤销(&U) accept
A0001" after en -> zh_CN, one made in Chinese "&Redo 拒绝 A0002" after zh_CN -> en). Now
every command is retitled on a switch (ReviewController.retranslate)."""

import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _window  # noqa: E402

pytestmark = pytest.mark.gui


def test_undo_and_redo_texts_follow_a_language_switch(qtbot, tmp_path):
    from PySide6 import QtWidgets

    from wakeline.app import i18n
    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    try:
        w.load_file(demo_path())
        _settle(w)
        w.run_step("associate")
        _settle(w)
        c = w.review.bound.controller
        pids = list(c.state.proposals["proposal"])
        c.accept(pids[0])
        _settle(w)
        w.set_language("zh_CN")
        _settle(w)
        zh_undo = w.review.act_undo.text()
        c.reject(pids[1])
        _settle(w)
        w.review.act_undo.trigger()
        _settle(w)
        w.set_language("en")
        _settle(w)
        en_redo = w.review.act_redo.text()
        assert "accept" not in zh_undo, zh_undo
        assert "拒绝" not in en_redo, en_redo
    finally:
        w.set_language("en")
        w.close()
        i18n.install(QtWidgets.QApplication.instance(), "en", None)

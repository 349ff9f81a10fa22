"""Operator test 6, D-ui-2: every Alt mnemonic is unique in the menu bar and in each menu
(submenus too), in English and in Simplified Chinese (Review and View both took V; Run
had three S)."""

import re
from collections import defaultdict

import pytest


def _mnemonic(text: str) -> str | None:
    m = re.search(r"&([^&])", text.replace("&&", ""))
    return m.group(1).upper() if m else None


def _clashes(actions, where: str) -> list[str]:
    out, seen = [], defaultdict(list)
    for a in actions:
        if a.isSeparator():
            continue
        key = _mnemonic(a.text())
        if key:
            seen[key].append(a.text())
        if a.menu() is not None:
            out += _clashes(a.menu().actions(), f"{where} > {a.text()}")
    out += [f"{where}: {k} in {v}" for k, v in seen.items() if len(v) > 1]
    return out


@pytest.mark.parametrize("language", ["en", "zh_CN"])
def test_menu_mnemonics_are_unique_per_menu(qtbot, tmp_path, language):
    from PySide6 import QtCore, QtWidgets

    from wakeline.app import i18n
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", language)
    w = MainWindow(settings)
    qtbot.addWidget(w)
    try:
        bar = w.menuBar().actions()
        assert len(bar) >= 5
        assert not _clashes(bar, "menu bar")
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)

"""Operator test 7, D4: with no font covering Simplified Chinese, every Chinese text is
drawn as boxes. The window asks the font database (here a stand-in) the first time it
needs Chinese glyphs — a zh_CN start or switch, loaded data or a log line holding Chinese
text — and without such a font says so once, in the log and the status bar, naming the
package to install."""

import pytest

pytest.importorskip("pytestqt")

from PySide6 import QtCore, QtGui, QtWidgets  # noqa: E402
from test_review_window import _settle  # noqa: E402

from wakeline.app import cjk_font, i18n  # noqa: E402
from wakeline.app.main_window import MainWindow  # noqa: E402

pytestmark = pytest.mark.gui


class _FontDatabase:
    """A font database holding ``families`` for Simplified Chinese; counts the asks."""

    def __init__(self, families: list[str]) -> None:
        self.cjk, self.asked = families, []

    def families(self, system=None):
        self.asked.append(system)
        return (
            list(self.cjk)
            if system == QtGui.QFontDatabase.WritingSystem.SimplifiedChinese
            else ["DejaVu Sans"]
        )


def _window(qtbot, tmp_path, language: str) -> MainWindow:
    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", language)
    w = MainWindow(settings)
    qtbot.addWidget(w)
    return w


def _warnings(w: MainWindow) -> list[str]:
    return [t for t in w.log.toPlainText().splitlines() if "fonts-noto-cjk" in t]


@pytest.fixture
def no_cjk_font(monkeypatch):
    db = _FontDatabase([])
    monkeypatch.setattr(cjk_font, "FONT_DATABASE", db)
    return db


def test_needs_cjk_finds_chinese_text_only():
    assert cjk_font.needs_cjk("批号")
    assert cjk_font.needs_cjk("a.csv", ["lon", "纬度"])
    assert cjk_font.needs_cjk("（")  # full-width punctuation
    assert not cjk_font.needs_cjk("a.csv", ["lon", "lat"], None, "Ωé")


def test_a_zh_start_without_a_chinese_font_says_so_once(qtbot, tmp_path, no_cjk_font):
    w = _window(qtbot, tmp_path, "zh_CN")
    try:
        (line,) = _warnings(w)
        assert "google-noto-sans-cjk-fonts" in line and "Fedora" in line
        assert "fonts-noto-cjk" in w.statusBar().currentMessage()
        w.set_language("en")
        w.set_language("zh_CN")
        w.log_message("时间 列")
        assert len(_warnings(w)) == 1  # once
        assert no_cjk_font.asked == [QtGui.QFontDatabase.WritingSystem.SimplifiedChinese]
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_a_chinese_font_present_says_nothing(qtbot, tmp_path, monkeypatch):
    db = _FontDatabase(["Noto Sans CJK SC"])
    monkeypatch.setattr(cjk_font, "FONT_DATABASE", db)
    w = _window(qtbot, tmp_path, "zh_CN")
    try:
        assert not _warnings(w) and len(db.asked) == 1
        assert "fonts-noto-cjk" not in w.statusBar().currentMessage()
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_an_english_window_asks_only_when_the_data_holds_chinese(
    qtbot, tmp_path, no_cjk_font, write
):
    w = _window(qtbot, tmp_path, "en")
    try:
        plain = write("plain.csv", "id,time,lon,lat\n1,2024-01-01 00:00:00,120.1,30.1\n")
        w.load_files([plain])
        _settle(w)
        assert not _warnings(w) and not no_cjk_font.asked  # no Chinese: not asked
        zh = write("zh.csv", "批号,时间,经度,纬度\n甲1,2024-01-01 00:00:00,120.1,30.1\n")
        w.load_files([zh])
        _settle(w)
        assert len(_warnings(w)) == 1
        w.load_files([zh])
        _settle(w)
        assert len(_warnings(w)) == 1
    finally:
        w.close()


def test_the_data_check_reads_ids_names_and_columns():
    from pathlib import Path

    import pandas as pd

    from wakeline.app.jobs_import import ImportJobsMixin

    pts = pd.DataFrame({"sensor": ["S1"], "batch": ["A1"], "lon": [1.0], "lat": [2.0]})
    holds = ImportJobsMixin._holds_cjk
    assert not holds(Path("a.csv"), pts)
    assert holds(Path("雷达.csv"), pts)
    assert holds(Path("a.csv"), pts.assign(batch=pd.Categorical(["甲1"])))
    assert holds(Path("a.csv"), pts.assign(sensor=["雷达"]))
    assert holds(Path("a.csv"), pts.rename(columns={"lon": "经度"}))
    assert not holds(Path("a.csv"), pts.assign(batch=[7]))

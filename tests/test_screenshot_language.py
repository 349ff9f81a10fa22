"""Operator test 6, D-gui-5: `wakeline gui --screenshot` renders the window in the
system's language ($LANG) or the one --language gives (it was always English)."""

import pytest


@pytest.mark.parametrize(
    ("system", "given", "expected"),
    [("zh_CN", None, "zh_CN"), ("zh_CN", "en", "en"), ("en", "zh_CN", "zh_CN")],
)
def test_screenshot_language(qapp, tmp_path, monkeypatch, system, given, expected):
    from wakeline.app import i18n, main
    from wakeline.app.main_window import MainWindow
    from wakeline.resources import demo_path

    seen = []
    grab = MainWindow.grab

    def recording_grab(self, *a):
        seen.append((self.language, self.menuBar().actions()[0].text()))
        return grab(self, *a)

    monkeypatch.setattr(i18n, "system_language", lambda: system)
    monkeypatch.setattr(MainWindow, "grab", recording_grab)
    kw = {"language": given} if given else {}
    try:
        assert main.run([demo_path()], screenshot=tmp_path / "shot.png", **kw) == 0
    finally:
        i18n.install(qapp, "en", None)
        for t in qapp.findChildren(i18n.TsTranslator):
            qapp.removeTranslator(t)
    assert seen and seen[0][0] == expected
    assert seen[0][1] == ("文件(&F)" if expected == "zh_CN" else "&File")


def test_gui_command_takes_language(monkeypatch):
    from wakeline.app import cli

    seen = {}
    monkeypatch.setattr(
        "wakeline.app.main.run",
        lambda files, screenshot=None, read=None, language=None: (
            seen.update(language=language) or 0
        ),
    )
    assert cli.main(["gui", "--language", "zh_CN", "--screenshot", "/tmp/x.png"]) == 0
    assert seen["language"] == "zh_CN"

"""Chinese translations of the review panel and the time slider (issue 13), the Detail
plots, the parameter tree, the Statistics dock, the menus and dock titles: every text of
those modules goes through the translator, and every one has a zh_CN entry.

The modules are read with :mod:`ast` (no Qt needed): a text is ``self.tr("…")`` (context:
the enclosing class), ``QCoreApplication.translate("ctx", "…")``, or ``tr("…")`` of a
module that sets ``TR_CONTEXT`` (else of a method that set ``tr = self.tr``). A literal with letters handed straight to a text setter
(``setText``, ``setToolTip``, ``addItems``, ``QLabel(…)``, …) is a text that bypasses
the translator.
"""

import ast
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from wakeline.resources import translations_dir

APP = Path(__file__).resolve().parents[1] / "app"
MODULES = sorted(APP.glob("review_*.py")) + [
    APP / name
    for name in (
        "time_panel.py",
        "map_time.py",
        "detail.py",
        "params_panel.py",
        "stats_panel.py",
        "actions.py",
        "main_window.py",
    )
]
SETTERS = {
    "setText",
    "setToolTip",
    "setStatusTip",
    "setWindowTitle",
    "setTitle",
    "setPlaceholderText",
    "setPrefix",
    "setSuffix",
    "addItem",
    "addItems",
    "setItemText",
    "showMessage",
    "QLabel",
    "QPushButton",
    "QToolButton",
    "QCheckBox",
    "QGroupBox",
    "QAction",
    "TextItem",
}


def _has_letters(node: ast.AST) -> bool:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return any(c.isalpha() for c in node.value)
    if isinstance(node, ast.JoinedStr):
        return any(_has_letters(v) for v in node.values if isinstance(v, ast.Constant))
    if isinstance(node, ast.List | ast.Tuple):
        return any(_has_letters(e) for e in node.elts)
    return False


def _name(func: ast.AST) -> str:
    return func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")


def scan(path: Path) -> tuple[set[tuple[str, str]], list[str]]:
    """(the (context, source) texts of a module, its texts that bypass the translator)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    module_ctx = next(
        (
            n.value.value
            for n in tree.body
            if isinstance(n, ast.Assign)
            and any(getattr(t, "id", "") == "TR_CONTEXT" for t in n.targets)
        ),
        None,
    )
    texts, raw = set(), []

    def visit(node: ast.AST, cls: str | None) -> None:
        if isinstance(node, ast.ClassDef):
            cls = node.name
        if isinstance(node, ast.Call):
            name, args = _name(node.func), node.args
            lit = [
                a.value for a in args if isinstance(a, ast.Constant) and isinstance(a.value, str)
            ]
            if name == "tr" and isinstance(node.func, ast.Attribute) and lit and cls:
                texts.add((cls, lit[0]))
            elif name == "tr" and isinstance(node.func, ast.Name) and lit and (module_ctx or cls):
                texts.add((module_ctx or cls, lit[0]))  # ``tr = self.tr`` in a method
            elif name == "translate" and len(lit) >= 2:
                texts.add((lit[0], lit[1]))
            elif name in SETTERS:
                checked = list(args) + [k.value for k in node.keywords if k.arg == "text"]
                if name == "setItemText":
                    checked = args[1:]
                raw.extend(f"{path.name}:{a.lineno} {name}" for a in checked if _has_letters(a))
            elif name == "setLabel":  # pyqtgraph: setLabel(axis, text, units=…)
                checked = args[1:] + [k.value for k in node.keywords if k.arg == "units"]
                raw.extend(f"{path.name}:{a.lineno} setLabel" for a in checked if _has_letters(a))
        for child in ast.iter_child_nodes(node):
            visit(child, cls)

    visit(tree, None)
    return texts, raw


def zh_table() -> dict[tuple[str, str], str]:
    root = ET.parse(translations_dir() / "wakeline_zh_CN.ts").getroot()
    out = {}
    for ctx in root.iter("context"):
        name = ctx.findtext("name", "")
        for msg in ctx.iter("message"):
            tr = msg.find("translation")
            if tr is not None and tr.text and tr.get("type") != "unfinished":
                out[(name, msg.findtext("source", ""))] = tr.text
    return out


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.name)
def test_every_text_goes_through_the_translator_and_has_a_zh_entry(path):
    texts, raw = scan(path)
    assert not raw, f"texts that bypass the translator: {raw}"
    table = zh_table()
    missing = sorted(t for t in texts if t not in table)
    assert not missing, f"no zh_CN entry for {missing}"
    # Placeholders survive the translation ({0} … in the source are in the entry).
    for ctx, src in texts:
        for k in range(10):
            if f"{{{k}" in src:
                assert f"{{{k}" in table[(ctx, src)], (ctx, src)


def test_the_scan_sees_texts_and_catches_a_bypass(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text(
        "class P:\n"
        "    def f(self):\n"
        "        self.a.setText(self.tr('Play'))\n"
        "        self.b.setToolTip('raw text')\n"
        "        QtWidgets.QLabel(f'{n} tracks')\n"
        "        self.c.setText('—')\n"
    )
    texts, raw = scan(sample)
    assert texts == {("P", "Play")}
    assert [r.split()[1] for r in raw] == ["setToolTip", "QLabel"]
    assert len(scan(APP / "time_panel.py")[0]) > 15


def test_panels_switch_to_chinese(qtbot):
    pytest.importorskip("pytestqt")
    from PySide6 import QtWidgets

    from wakeline.app import i18n
    from wakeline.app.time_panel import TimePanel

    app = QtWidgets.QApplication.instance()
    panel = TimePanel()
    qtbot.addWidget(panel)
    translator = i18n.install(app, "zh_CN", None)
    try:
        zh = zh_table()[("TimePanel", "Time window")]
        qtbot.waitUntil(lambda: panel.window_button.text() == zh, timeout=2000)
        from wakeline.app import review_text

        assert review_text.column_titles()["margin"] == zh_table()[("ReviewPanel", "margin")]
    finally:
        i18n.install(app, "en", translator)
    qtbot.waitUntil(lambda: panel.window_button.text() == "Time window", timeout=2000)


def test_detail_params_and_statistics_switch_to_chinese(qtbot):
    """The Detail plots' axis labels, the parameter tree's group titles, the Statistics
    dock's figures and the Bearing-only dock's title follow the language."""
    pytest.importorskip("pytestqt")
    import pandas as pd
    from PySide6 import QtWidgets

    from wakeline.app import i18n
    from wakeline.app.detail import DetailPanel
    from wakeline.app.params_panel import ParamsPanel
    from wakeline.app.stats_panel import StatsPanel

    app = QtWidgets.QApplication.instance()
    detail, params, stats = DetailPanel(), ParamsPanel(), StatsPanel()
    for widget in (detail, params, stats):
        qtbot.addWidget(widget)
    pts = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": ["1", "1", "2"],
            "time": pd.to_datetime([0.0, 60.0, 30.0], unit="s", utc=True),
            "lon": [10.0, 10.01, 10.02],
            "lat": [55.0, 55.0, 55.01],
        }
    )
    stats.compute(("k",), pts)
    assert dict(stats.rows())["Targets"] == "no target ids"
    translator = i18n.install(app, "zh_CN", None)
    zh = zh_table()
    try:
        for widget in (detail, params, stats):
            widget.retranslate()
        label = detail.factor_plot.getAxis("bottom").labelText
        assert label == zh[("DetailPanel", "time since track start")]
        titles = {g.name(): g.opts["title"] for g in params.root.children()}
        assert titles["clean"] == zh[("ParamsPanel", "Cleaning (seeds 001, 003)")]
        assert titles["bearing"] == zh[("ParamsPanel", "Bearing-only (seed 002)")]
        rows = dict(stats.rows())
        assert rows[zh[("StatsPanel", "Targets")]] == zh[("StatsPanel", "no target ids")]
        assert stats.hist.getAxis("left").labelText == zh[("StatsPanel", "tracks")]
        assert zh[("MainWindow", "Bearing-only")] == "纯方位"
    finally:
        i18n.install(app, "en", translator)
    stats.retranslate()
    assert "Targets" in dict(stats.rows())


def test_the_window_in_chinese_titles_the_bearing_dock_and_its_statistics(qtbot, tmp_path):
    """The Bearing-only dock's tab title was English in the Chinese window."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets

    from wakeline.app import i18n
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    try:
        zh = zh_table()
        assert w.docks["bearing"].windowTitle() == zh[("MainWindow", "Bearing-only")]
        assert w.docks["stats"].windowTitle() == zh[("MainWindow", "Statistics")]
        label = w.detail.z_plot.getAxis("bottom").labelText
        assert label == zh[("DetailPanel", "time")]
    finally:
        w.set_language("en")
        w.close()
    assert w.docks["bearing"].windowTitle() == "Bearing-only"
    i18n.install(QtWidgets.QApplication.instance(), "en", None)

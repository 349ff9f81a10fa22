"""Chinese translations of every app module that calls the translator (found, not listed:
the review panel, the time slider, the Detail plots, the parameter tree, the Statistics
dock, the menus, the window's mixins, the Bearing-only dock, the import dialog, …): every
text goes through the translator, and every one has a zh_CN entry.

The modules are read with :mod:`ast` (no Qt needed): a text is ``self.tr("…")`` (context:
the ``TR_CONTEXT`` its class sets, else the enclosing class; a mixin of the main window
sets ``"MainWindow"``, where PySide's ``tr`` looks first), ``other.tr("…")`` or ``tr("…")``
of a module that sets ``TR_CONTEXT`` (a bare ``tr`` else: ``tr = self.tr`` in a method),
or ``QCoreApplication.translate("ctx", "…")``; a ``tr`` whose context is unknown fails. A
literal with letters handed straight to a text setter (``setText``, ``setToolTip``,
``addItems``, ``QLabel(…)``, …) is a text that bypasses the translator.
"""

import ast
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from wakeline.resources import translations_dir

APP = Path(__file__).resolve().parents[1] / "app"
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


#: Every app module (none is left out by a list to extend: the window's mixins, the
#: bearing dock and the import dialog were, and had texts without a zh entry).
MODULES = sorted(APP.glob("*.py"))
#: Literals a module hands a text setter on purpose: (module, setter) and why.
RAW_KEPT = {
    ("map_canvas.py", "setLabel"): "English default; the window and the bearing dock set it",
    ("map_interact.py", "setText"): "the scale bar's unit, km",
}


def _tr_context(body: list[ast.stmt]) -> str | None:
    """The ``TR_CONTEXT = "…"`` a module or a class body sets (a mixin's ``self.tr`` is the
    window's: PySide looks the text up along ``type(self).__mro__``, the window first)."""
    return next(
        (
            n.value.value
            for n in body
            if isinstance(n, ast.Assign)
            and any(getattr(t, "id", "") == "TR_CONTEXT" for t in n.targets)
        ),
        None,
    )


def scan(path: Path) -> tuple[set[tuple[str, str]], list[str]]:
    """(the (context, source) texts of a module, its texts that bypass the translator)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    module_ctx = _tr_context(tree.body)
    texts, raw = set(), []

    def visit(node: ast.AST, cls: str | None) -> None:
        if isinstance(node, ast.ClassDef):
            cls = _tr_context(node.body) or node.name
        if isinstance(node, ast.Call):
            name, args = _name(node.func), node.args
            lit = [
                a.value for a in args if isinstance(a, ast.Constant) and isinstance(a.value, str)
            ]
            if name == "tr" and lit:
                if isinstance(node.func, ast.Attribute):  # ``self.tr``, or ``window.tr``:
                    own = getattr(node.func.value, "id", "") == "self"  # the module says
                    ctx = cls if own else module_ctx  # whose
                else:  # a ``tr`` handed in, or ``tr = self.tr`` in a method
                    ctx = module_ctx or cls
                if ctx:
                    texts.add((ctx, lit[0]))
                else:
                    raw.append(f"{path.name}:{node.lineno} tr without a known context")
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
    raw = [r for r in raw if (path.name, r.split()[1]) not in RAW_KEPT]
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
    params.root.child("clean", "resample", "max_gap_s").setValue(90.0)  # the rule's note
    english = params.note.text()
    assert english.startswith("resample: max_gap_steps is now 0")
    translator = i18n.install(app, "zh_CN", None)
    zh = zh_table()
    try:
        for widget in (detail, params, stats):
            widget.retranslate()
        label = detail.factor_plot.getAxis("bottom").labelText
        assert label == zh[("DetailPanel", "time since track start")]
        titles = {g.name(): g.opts["title"] for g in params.root.children()}
        assert titles["clean"] == zh[("ParamsPanel", "Cleaning")]
        assert titles["bearing"] == zh[("ParamsPanel", "Bearing-only")]
        # the seed papers in the groups' tooltips (h225 item 13), in the language too
        assert params.group_tips()["clean"] == zh[("ParamsPanel", "Cleaning (seeds 001, 003)")]
        assert params.note.text() == zh[("ParamsPanel", english)]  # written again
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


def test_the_scan_reads_every_module_and_the_context_tr_uses():
    """The modules are found, not listed; a mixin's ``self.tr`` is the window's, a ``tr``
    handed in takes its module's context, a ``tr`` of no known context is caught."""
    names = {p.name for p in MODULES}
    assert {"jobs.py", "jobs_import.py", "jobs_project.py", "window_selection.py"} <= names
    assert {"bearing_view.py", "import_dialog.py", "main.py", "map_time.py"} <= names
    assert ("MainWindow", "Running {0}…") in scan(APP / "jobs.py")[0]
    assert ("MainWindow", "Bearings") in scan(APP / "bearing_view.py")[0]
    assert ("BearingView", "Line length") in scan(APP / "bearing_view.py")[0]
    assert ("MainWindow", "Unexpected error") in scan(APP / "main.py")[0]


def test_a_tr_of_unknown_context_is_caught(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text(
        "def f(window, tr):\n    window.tr('Error')\n    tr('Warning')\n"
        "class M:\n    TR_CONTEXT = 'MainWindow'\n    def g(self):\n        self.tr('Note')\n"
    )
    texts, raw = scan(sample)
    assert texts == {("MainWindow", "Note")}
    assert len(raw) == 2 and all("context" in r for r in raw)


def test_the_chinese_window_finds_its_mixins_and_bearing_dock_texts(qtbot, tmp_path):
    """At run time, in the window made with zh_CN: every ``MainWindow`` text of the scan
    (the mixins' ``self.tr`` goes along the window's MRO), the Bearing-only dock's widgets
    (made before the translator is installed) and the import dialog read Chinese."""
    pytest.importorskip("pytestqt")
    from types import SimpleNamespace

    import pandas as pd
    from PySide6 import QtCore, QtWidgets

    from wakeline.app import i18n
    from wakeline.app.bearing_view import bearing_stats
    from wakeline.app.import_dialog import ImportDialog
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    zh = zh_table()
    try:
        window_texts = {src for p in MODULES for ctx, src in scan(p)[0] if ctx == "MainWindow"}
        assert "Open a track file first." in window_texts and len(window_texts) > 100
        wrong = sorted(s for s in window_texts if w.tr(s) != zh.get(("MainWindow", s)))
        assert not wrong, wrong
        bv = w.bearing_view
        assert bv.length_label.text() == zh[("BearingView", "Line length")]
        assert bv.export_button.text() == zh[("BearingView", "Export detections…")]
        assert bv.length_box.specialValueText() == zh[("BearingView", "from the data")]
        assert bv.map.getAxis("left").labelText == zh[("BearingView", "latitude")]
        points = pd.DataFrame({"batch": ["1"], "time": pd.to_datetime([0], unit="s", utc=True)})
        layer = SimpleNamespace(
            points=points, tables={}, meta={"length_m": 9000.0}, name="b", kind="bearing", id="L1"
        )
        text = bearing_stats(layer, w.tr)
        for word in ("Bearings", "Sequences", "Detections", "Bearing lines", "Layer"):
            assert zh[("MainWindow", word)] + ":" in text
        dialog = ImportDialog(w)
        qtbot.addWidget(dialog)
        zone = "Zone of times written without one (IANA name or ±HH:MM). Unix times are"
        assert dialog.tz_box.toolTip() == zh[("ImportDialog", zone + " absolute and not shifted.")]
    finally:
        w.set_language("en")
        w.close()
    assert bv.length_label.text() == "Line length"
    assert bv.map.getAxis("left").labelText == "latitude"
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


CORE = Path(__file__).resolve().parents[1] / "core"


def core_templates() -> set[str]:
    """The templates of the core's summaries: the literal first argument of every
    ``phrase("…")`` call in core (found, not listed)."""
    out = set()
    for path in sorted(CORE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Call)
                and _name(node.func) == "phrase"
                and node.args
                and isinstance(node.args[0], ast.Constant)
                and isinstance(node.args[0].value, str)
            ):
                out.add(node.args[0].value)
    return out


def _fields(template: str) -> set[str]:
    import string

    return {f for _, f, _, _ in string.Formatter().parse(template) if f}


def test_every_core_summary_template_has_a_zh_entry_with_its_values():
    """The step summaries (import, clean, maneuvers, compress, associate, fuse) are the
    core's phrases; each template has a zh_CN entry (context ``Summary``) naming the same
    values, and renders."""
    from wakeline.core.words import CONTEXT, Text, phrase, render

    templates = core_templates()
    assert len(templates) > 30
    assert "kept {kept:,} of {points:#point} in {tracks:#track}" in templates
    table = zh_table()
    missing = sorted(t for t in templates if (CONTEXT, t) not in table)
    assert not missing, f"no zh_CN entry for {missing}"
    for t in templates:
        zh = table[(CONTEXT, t)]
        assert _fields(zh) == _fields(t), (t, zh)
        values = dict.fromkeys(_fields(t), 1234)
        text = Text([phrase(t, **values)])
        rendered = render(text, lambda s: table.get((CONTEXT, s)))
        assert rendered == render(Text([phrase(zh, **values)])) and "{" not in rendered


def _english_pieces() -> list[str]:
    """The words of the summaries' templates between their values (two words or more)."""
    import re
    import string

    pieces = set()
    for t in core_templates():
        for literal, *_ in string.Formatter().parse(t):
            for piece in re.split(r"[();:,\d]|->|—", literal):
                piece = piece.strip()
                words = [w for w in re.findall(r"[A-Za-z_]+", piece) if "_" not in w]
                if len(words) >= 2:  # not a parameter's name (Dis_e, max_distance_m)
                    pieces.add(piece)
    return sorted(pieces)


def test_the_pipeline_log_in_chinese_has_no_english_summary(qtbot, tmp_path):
    """Import, the pipeline, each step (clean, maneuvers, compress, associate, fuse) and
    an export in the zh_CN window: the log's lines carry no English sentence of a
    summary (they were built in core, in English, and stayed English)."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets

    from conftest import load
    from wakeline.app import i18n
    from wakeline.app.core_text import translate
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow
    from wakeline.core.words import CONTEXT
    from wakeline.resources import demo_path

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1200, 800)
    zh = zh_table()
    try:
        source = load(w, demo_path())
        assert source is not None
        for step in ("pipeline", "clean", "maneuvers", "compress", "associate", "fuse"):
            w.select_layer(source)
            w.run_step(step)
            wait_for_jobs(w)
        w.export("csv", tmp_path / "out.csv")
        qtbot.waitUntil(lambda: (tmp_path / "out.csv").exists(), timeout=20_000)
        w.export_runner.wait()
        qtbot.waitUntil(lambda: "out.csv" in w.log.toPlainText(), timeout=5000)
        # On a machine without a font for Chinese, the window's warning says so in
        # English (in Chinese it would be boxes: tests/test_cjk_font.py); not a summary.
        lines = [t for t in w.log.toPlainText().splitlines() if "fonts-noto-cjk" not in t]
        log = "\n".join(lines)
        # every step logged its summary (in Chinese)
        kept = zh[(CONTEXT, "kept {kept:,} of {points:#point} in {tracks:#track}")]
        assert any(kept.split(" ")[0] in line for line in lines), log
        for step in ("clean", "maneuvers", "compress", "associate", "fuse"):
            name = translate(step, "zh_CN")  # the step's name in Chinese too (D-i18n-1)
            # "对 demo.csv 运行清洗：…" (operator test 8, D7: was "demo.csv 上的 清洗: …")
            assert name != step and any(
                f" 运行{name}：" in line or line.strip().startswith(f"{name}：") for line in lines
            ), (step, log)
        english = [p for p in _english_pieces() if p in log]
        assert not english, (english, log)
        for word in (" on ", "kept ", " tracks", " points", " rows ", "quarantined"):
            assert word not in log, (word, log)
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def _latin_actions(w) -> list[str]:
    """Every action of every menu of the window (submenus too) whose text or tooltip has
    no Chinese character: "menu > text" (the language names are themselves)."""
    import re

    han = re.compile(r"[\u4e00-\u9fff]")
    names = set(__import__("wakeline.app.i18n", fromlist=["LANGUAGES"]).LANGUAGES.values())
    out = []

    def walk(menu, path):
        for a in menu.actions():
            if a.isSeparator():
                continue
            text = a.text()
            if a.menu() is not None:
                walk(a.menu(), f"{path}{text} > ")
            if text in names:
                continue
            for what, value in (("text", text), ("tooltip", a.toolTip())):
                if value and not han.search(value):
                    out.append(f"{path}{text} ({what}: {value})")

    for top in w.menuBar().actions():
        if not han.search(top.text()):
            out.append(f"menu {top.text()}")
        walk(top.menu(), f"{top.text()} > ")
    return out


def test_every_menu_action_of_the_chinese_window_is_chinese_with_a_review_bound(qtbot, tmp_path):
    """Operator test h150: with a review bound, the Review menu, View ▸ Before/after map,
    Edit ▸ Undo/Redo and File ▸ Export ▸ Reviewed tracks / Decision log (and their
    tooltips) stayed English in zh_CN, at start and after a switch en → zh_CN. Every
    action of every menu is walked (found, not listed): each reads Chinese."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets

    from conftest import load
    from wakeline.app import i18n
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow
    from wakeline.resources import demo_path

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1400, 900)
    w.show()
    app = QtWidgets.QApplication.instance()

    def settle():
        for _ in range(1500):
            wait_for_jobs(w)
            if not (w.review.busy or w.drawing or w.runner.busy):
                app.processEvents()
                if not (w.review.busy or w.drawing or w.runner.busy or w._job_context):
                    return
            qtbot.wait(20)
        raise AssertionError("the window did not settle")

    try:
        source = load(w, demo_path())
        w.select_layer(source)
        w.run_step("associate")
        settle()
        assoc = next(lay for lay in w.layers.values() if lay.step == "associate")
        w.select_layer(assoc.id)
        settle()
        assert w.review.bound is not None
        w.review.bound.panel.accept()  # Undo now names a decision
        settle()
        assert w.review.act_undo.isEnabled()
        assert not _latin_actions(w), _latin_actions(w)
        w.set_language("en")
        assert "&Next proposal" in [a.text() for a in w.review.review_menu.actions()]
        assert w.review.act_undo.text().startswith("&Undo ")
        w.set_language("zh_CN")
        assert not _latin_actions(w), _latin_actions(w)
        w.review.act_undo.trigger()  # the stack changes: the text stays Chinese
        settle()
        assert w.review.act_redo.text().startswith("重做"), w.review.act_redo.text()
        assert not _latin_actions(w), _latin_actions(w)
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)
    # The Review menu's texts are tr() of literals: the scan above checks their entries.
    assert ("ReviewDock", "&Next proposal") in scan(APP / "review_dock.py")[0]

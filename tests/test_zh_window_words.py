"""Operator test 6 (D-i18n-2): the Simplified-Chinese window after load -> pipeline ->
associate -> fuse shows no English word in the texts that were left English: the layer
names built from the steps' words (Layers list, legend, Statistics dock, log), the
associate/fuse summaries' option words, and the Parameters dock's one-word rows and units.
The stored layer names stay English (a project opens in either language)."""

import re

import pytest

#: Tokens a Chinese text may hold: file names, sensors, units, parameter identifiers (shown
#: beside their Chinese label), the layer ids.
ALLOWED = {
    "csv",
    "demo",
    "UTC",
    "AIS",
    "DTW",
    "time_base",
    "union",
}
#: A fused track's label in the data: its sensor column says "fused" (as the export writes it).
TRACK_LABEL = re.compile(r"\bfused · ")
WORD = re.compile(r"[A-Za-z][A-Za-z_]{2,}")
HAN = re.compile(r"[\u4e00-\u9fff]")


def _english(text: str, allowed: set[str]) -> list[str]:
    text = TRACK_LABEL.sub("", text)
    return [w for w in WORD.findall(text) if w not in allowed and "_" not in w]


def test_shown_name_translates_step_words_only(qapp):
    from wakeline.app import i18n
    from wakeline.app.layer_names import shown_name

    zh = None
    try:
        zh = i18n.install(qapp, "zh_CN", None)
        assert shown_name("a.csv · cleaned · compressed") == "a.csv · 已清洗 · 已压缩"
        assert shown_name("a.csv + b.csv · fused (reviewed)") == "a.csv + b.csv · 已融合（已审核）"
        assert shown_name("a.csv · maneuvers (compress)") == "a.csv · 机动点（压缩）"
        assert shown_name("f0.csv + f1.csv and 198 more · fused").startswith("f0.csv + f1.csv 等另")
        # a file's own name is never touched, even if it is a step word
        assert shown_name("cleaned") == "cleaned"
        assert shown_name("x · my notes") == "x · my notes"
        zh = i18n.install(qapp, "en", zh)
        assert shown_name("a.csv · cleaned · compressed") == "a.csv · cleaned · compressed"
    finally:
        i18n.install(qapp, "en", zh)


def test_zh_window_after_pipeline_associate_fuse_has_no_english_words(qtbot, tmp_path):
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
    w.resize(1200, 800)
    try:
        source = load(w, demo_path())
        assert source is not None
        allowed = ALLOWED | set(re.findall(r"[A-Za-z_]+", demo_path().name))
        for step in ("pipeline", "associate", "fuse"):
            w.select_layer(source)
            w.run_step(step)
            wait_for_jobs(w)
        names = [lay.name for lay in w.session.layers.values()]
        assert any(" · cleaned" in n for n in names), names  # stored in English
        assert any(n.endswith(" · fused") for n in names), names
        allowed |= {lid for lid in w.session.layers}
        texts = []
        # the Layers list
        texts += [w.layer_list.item(r).text() for r in range(w.layer_list.count())]
        # the Statistics dock's rows of each layer (name, lineage, summary)
        for lid in list(w.session.layers):
            w.select_layer(lid)
            wait_for_jobs(w)
            QtWidgets.QApplication.processEvents()
            model = w.stats.table.model()
            for r in range(model.rowCount()):
                for c in range(model.columnCount()):
                    value = model.index(r, c).data()
                    if value is not None and r < 3:  # the layer's name, lineage, summary
                        texts.append(str(value))
        texts += [lab.text for _, lab in w.canvas.legend.items]  # the legend
        # the log's step lines (the summaries and the layers they ran on)
        texts += [
            line
            for line in w.log.toPlainText().splitlines()
            if " 上的 " in line or "运行于" in line
        ]
        bad = {t: _english(t, allowed) for t in texts if _english(t, allowed)}
        assert not bad, bad
        # the Parameters dock: every row a Chinese title (identifiers beside it)
        stack = list(w.params.root.children())
        rows = []
        while stack:
            item = stack.pop()
            stack += item.children()
            rows.append(str(item.opts.get("title") or item.name()))
            suffix = item.opts.get("suffix")
            if suffix and suffix.strip():
                rows.append(suffix)
        one_word = [r for r in rows if re.fullmatch(r"\s*[a-z]{3,}\s*", r)]
        assert not one_word, one_word
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_zh_import_dialog_labels_fields_and_holds_ok_until_lon_lat_are_mapped(qtbot, write):
    """D-i18n-2 (d), D-import-12: the Column mapping rows say each field in Chinese beside
    its name; a file whose lon/lat columns are not recognised keeps OK disabled, the
    reason in its tooltip and under the mapping, until they are mapped."""
    from PySide6 import QtWidgets

    from wakeline.app import i18n
    from wakeline.app.import_dialog import ImportDialog

    app = QtWidgets.QApplication.instance()
    path = write("b.csv", "批号,时刻,东经x,北纬x\n1,2026-12-05 08:00:00,122.1,30.2\n")
    zh = i18n.install(app, "zh_CN", None)
    try:
        d = ImportDialog()
        qtbot.addWidget(d)
        d.path_edit.setText(str(path))
        form = d.mapping_boxes["lon"].parentWidget().layout()
        label = form.labelForField(d.mapping_boxes["lon"]).text()
        assert label == "经度 lon", label
        ok = d.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        assert not ok.isEnabled()
        assert "经度 lon" in ok.toolTip() and "经度 lon" in d.warning_label.text()
        for field, column in (("lon", "东经x"), ("lat", "北纬x")):
            box = d.mapping_boxes[field]
            box.setCurrentIndex(box.findText(column))
        assert ok.isEnabled(), d.warning_label.text()
    finally:
        i18n.install(app, "en", zh)


def test_the_legend_follows_a_language_switch(qtbot, tmp_path):
    """The legend's layer names are drawn with their step words in the window's language;
    Language ▸ English says them again without a redraw."""
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
    try:
        source = load(w, demo_path())
        w.select_layer(source)
        w.run_step("clean")
        wait_for_jobs(w)
        QtWidgets.QApplication.processEvents()
        labels = [lab.text for _, lab in w.canvas.legend.items]
        assert "demo.csv · 已清洗" in labels, labels
        w.set_language("en")
        labels = [lab.text for _, lab in w.canvas.legend.items]
        assert "demo.csv · cleaned" in labels and "demo.csv · 已清洗" not in labels, labels
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)

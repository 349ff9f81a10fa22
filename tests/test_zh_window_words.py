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


#: English-only texts of the Chinese window operator test 7 found (D11): the review
#: queue's method values, the Bearing-only dock's column title, the batch table's status,
#: the parameter tree's column titles, an open-failed message.
OPERATOR7_ALONE = {"batch", "joined", "fused", "single", "Parameter", "Value", "optimal", "greedy"}
OPERATOR7_PHRASES = re.compile(r"\boptimal\b|second look|missing required column|headers found")


def test_zh_window_after_pipeline_associate_leaves_no_operator7_english(qtbot, tmp_path, write):
    """Operator test 7, D11: after Run ▸ pipeline with Associate (Compress on) and a file
    that cannot be opened, the Chinese window's visible texts (labels, titles, table
    headers and cells), the review queue's method column and evidence, the Bearing-only
    dock's column titles and the parameter rows hold no English of the defect's list; the
    parameter rows named by an identifier show a Chinese title, the identifier in their
    tooltip's last line; the English window keeps the identifiers as titles."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets
    from test_review_window import _settle, _window

    from wakeline.app import i18n
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    bad = write("notes.csv", "名称,备注,数值\nx,y,1\nz,w,2\n")
    w = _window(qtbot, tmp_path)
    w.interactive = False  # the open-failed dialog: in the log and on stderr
    try:
        w.load_files([src])
        _settle(w)
        w.actions_["pipeline_associate"].trigger()
        w.select_layer(w.layer_id(src.name))
        w.actions_["pipeline"].trigger()
        _settle(w)
        bound = w.review.bound
        assert bound is not None and len(bound.controller.state.proposals)
        params = {}
        stack = list(w.params.root.children())
        while stack:
            item = stack.pop()
            stack += item.children()
            params[item.name()] = item
        assert params["window_p"].title() == "window_p"  # English: the identifier
        w.set_language("zh_CN")
        _settle(w)
        w.load_files([bad])
        _settle(w)
        failed = [t for t in w.log.toPlainText().splitlines() if "notes.csv" in t]
        assert failed and all(HAN.search(t) for t in failed), failed
        texts = [t for t in failed]
        # the review queue: every column title and cell, and the evidence line
        model = bound.panel.view.model()
        for c in range(model.columnCount()):
            texts.append(str(model.headerData(c, QtCore.Qt.Orientation.Horizontal)))
            for r in range(model.rowCount()):
                texts.append(str(model.index(r, c).data()))
        texts.append(bound.panel.evidence.text())
        assert any("最优分配" in t for t in texts), texts
        # the Bearing-only dock's detections table (no bearings: its one column)
        bm = w.bearing_view.model
        texts += [
            str(bm.headerData(c, QtCore.Qt.Orientation.Horizontal)) for c in range(bm.columnCount())
        ]
        # the parameter tree's column titles and rows
        tree = w.params.tree
        texts += [tree.headerItem().text(c) for c in range(tree.columnCount())]
        for item in params.values():
            texts.append(str(item.title()))
        assert params["window_p"].title() == "窗口点数 p"
        assert params["window_p"].opts["tip"].splitlines()[-1].endswith("window_p")
        # every visible widget's texts and its tables' headers and first rows
        for wid in w.findChildren(QtWidgets.QWidget):
            if not wid.isVisibleTo(w):
                continue
            for attr in ("text", "title", "windowTitle", "placeholderText"):
                f = getattr(wid, attr, None)
                if callable(f):
                    try:
                        value = f()
                    except TypeError:
                        continue
                    if isinstance(value, str):
                        texts.append(value)
            if isinstance(wid, QtWidgets.QAbstractItemView) and wid.model() is not None:
                m = wid.model()
                try:
                    ncol = m.columnCount()
                except TypeError:
                    continue
                for c in range(ncol):
                    texts.append(str(m.headerData(c, QtCore.Qt.Orientation.Horizontal)))
                    for r in range(min(m.rowCount(), 30)):
                        texts.append(str(m.index(r, c).data()))
        left = sorted(
            {t for t in texts if t.strip() in OPERATOR7_ALONE or OPERATOR7_PHRASES.search(t)}
        )
        assert not left, left
        # the parameter rows: an identifier alone is left only where no title is known
        bare = [n for n, item in params.items() if "_" in n and item.title() == n]
        assert not bare, bare
        w.set_language("en")
        assert params["window_p"].title() == "window_p"
        assert not params["window_p"].opts["tip"].splitlines()[-1].endswith("window_p")
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)

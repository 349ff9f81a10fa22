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
        # the legend (its HTML line breaks and spaces are markup, not words)
        texts += [re.sub(r"<[^>]+>|&\w+;", " ", lab.text) for _, lab in w.canvas.legend.items]
        # the log's step lines (the summaries and the layers they ran on)
        texts += [
            line
            for line in w.log.toPlainText().splitlines()
            if line.startswith("对 ") or "运行于" in line
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
        # each entry's lines (a layer coloured by track names itself on the first line)
        labels = [x for _, lab in w.canvas.legend.items for x in lab.text.split("<br>")]
        assert "demo.csv · 已清洗" in labels, labels
        w.set_language("en")
        labels = [x for _, lab in w.canvas.legend.items for x in lab.text.split("<br>")]
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


#: Operator test 8 (D3, D6, D7): English phrases the Chinese window left in the texts an
#: operator reads most, and unit symbols beside Chinese words ("间隔 0 s", "2514 m").
OPERATOR8_PHRASES = re.compile(
    r"no window tested|share a time|too short|detection\(s\)|windows tested|bearings? |"
    r"stationary|speed \d|--set|points share times|radar plots|not tracks|"
    r"\bOK\b|\bCancel\b|\bauto\b|上的|[\u4e00-\u9fff] ?\d[\d,.]* ?[sm]\b|"
    r"\d [sm](?:\b|$)"
)


def _operator8_left(texts) -> list[str]:
    return sorted({t for t in texts if OPERATOR8_PHRASES.search(TRACK_LABEL.sub("", t))})


def test_zh_bearing_dock_and_log_say_why_nothing_was_tested_in_chinese(qtbot, tmp_path):
    """Operator test 8, D3/D6: the detector's line per batch (the log and the Bearing-only
    dock: the only explanation of 0 detections), ungated (several bearings per time) and
    gated on a truth layer (series too short), the line-length box's unit and the gating
    summary are Chinese, the units 秒/米; the menu named is the one the File menu shows."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets
    from test_bearing_import import PIREN, SAMPLE, TRUTH

    from wakeline.app import i18n
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1600, 950)
    try:
        w.load_bearings(SAMPLE)
        wait_for_jobs(w)
        qtbot.waitUntil(lambda: bool(w.bearing_view.log.toPlainText()), timeout=20_000)
        ungated = w.bearing_view.log.toPlainText().splitlines()
        assert ungated and all(t.startswith("批号 ") and "未检验任何窗口" in t for t in ungated)
        assert any("与其他方位时刻相同" in t for t in ungated), ungated
        w.load_file(TRUTH, origin=PIREN)
        wait_for_jobs(w)
        truth = w.layer_id(TRUTH.name)
        w.load_bearings(SAMPLE, tracks=truth, gate_deg=3.0)
        wait_for_jobs(w)
        qtbot.waitUntil(lambda: "/1" in w.bearing_view.log.toPlainText(), timeout=20_000)
        gated = w.bearing_view.log.toPlainText().splitlines()
        assert gated and all(t.startswith("批号 ") for t in gated), gated
        log = w.log.toPlainText().splitlines()
        menu = (
            w.actions_["open_bearings"].text().replace("(&B)", "")
            if "open_bearings" in (w.actions_)
            else None
        )
        texts = ungated + gated + log + [w.bearing_view.length_box.suffix()]
        assert w.bearing_view.length_box.suffix() == " 米"
        assert any("按 1 条航迹" in t or "条航迹在 3° 内波门关联" in t for t in log), log
        hints = [t for t in log if "打开方位" in t and "文件 ▸" in t]
        assert all("文件 ▸ 打开方位数据（纯方位机动检测）…" in t for t in hints), hints
        if menu:
            assert "打开方位数据" in menu
        english = [t for t in texts if re.search(r"[A-Za-z]{4,} [a-z]{3,} [a-z]{3,}", t)]
        assert not english, english
        left = _operator8_left(texts)
        assert not left, left
        w.set_language("en")  # the dock's lines follow a switch of language
        assert w.bearing_view.log.toPlainText().startswith("batch ")
        assert w.bearing_view.length_box.suffix() == " m"
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_bearing_report_lines_in_chinese_for_every_kind_of_line():
    """Every line :func:`~wakeline.core.bearing.report_lines` writes (tested, with
    windows skipped, noise, the smallest change and turn, repeated times left out;
    none tested) reads Chinese through the core catalog, figures kept."""
    from wakeline.app.core_text import translate
    from wakeline.core.bearing import report_lines

    base = {
        "too_short": None,
        "detections": 2,
        "tested": 40,
        "windows": 52,
        "excluded": {"gap": 7, "sparse": 0, "observer_maneuvering": 5},
        "noise_deg": 0.31,
        "min_rate_change_deg_min": 0.52,
        "min_turn_deg": 12.0,
        "repeated_left_out": 3,
    }
    reports = [
        dict(base, batch="a"),
        dict(base, batch="b", noise_deg=None, min_rate_change_deg_min=None, min_turn_deg=None),
        dict(base, batch="c", tested=0, excluded={"gap": 52}, repeated_left_out=0),
    ]
    lines = [translate(line, "zh_CN") for line in report_lines(reports)]
    assert lines[0].startswith("批号 a：2 个检测；52 个窗口中检验了 40 个"), lines[0]
    for figure in (
        "（跳过：有间断 7 个，观测平台机动 5 个）",
        "0.31°",
        "0.52°/分钟",
        "12°",
        "3 个方位",
    ):
        assert figure in lines[0], (figure, lines[0])
    assert "无可检出的变化" in lines[1] and "未估计噪声" in lines[1], lines[1]
    assert "没有检验任何窗口" in lines[2], lines[2]
    for line in lines:
        assert not re.search(
            r"[A-Za-z]{3,}", line.replace("批号 a", "").replace("批号 b", "").replace("批号 c", "")
        ), line


def test_zh_plots_guidance_is_chinese():
    """Operator test 8, D3: the Parameters guidance's reason why no detection limit can
    be given (radar plots; tracks that do not move; a speed no ship has) is Chinese."""
    import pandas as pd

    from wakeline.app.core_text import translate
    from wakeline.core.maneuver import detection_limit

    plots = pd.DataFrame(
        {
            "points": [5] * 12,
            "duration_s": [0.0] * 10 + [2.0, 2.0],
            "mean_speed_kn": [float("nan")] * 10 + [500.0, 500.0],
        }
    )
    still = pd.DataFrame(
        {"points": [9, 9], "duration_s": [600.0, 900.0], "mean_speed_kn": [0.0, 0.0]}
    )
    fast = pd.DataFrame(
        {"points": [9, 9], "duration_s": [600.0, 900.0], "mean_speed_kn": [190.0, 195.0]}
    )
    for summary in (plots, still, fast):
        reason = detection_limit(summary, 5, 15.0).reason
        assert reason, summary
        zh = translate(reason, "zh_CN")
        assert not re.search(r"[A-Za-z]{4,}", zh), (reason, zh)


def test_zh_statistics_review_and_import_dialog_words(qtbot, tmp_path):
    """Operator test 8, D3/D6/D7: after Clean and a fuse, the Statistics dock's clean row
    names the rules in Chinese ("静止点 …", not "stationary"), the made-by row keeps the
    input's name whole (the time in a row of its own), a layer's kind is said once; the
    log's step lines read "对 X 运行清洗：" with no CLI flag; the review queue and evidence
    say 秒/米; the import dialog's buttons and "auto" values are Chinese."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets
    from test_review_window import _settle, _sim_pair

    from wakeline.app import i18n
    from wakeline.app.import_dialog import ImportDialog
    from wakeline.app.main_window import MainWindow
    from wakeline.resources import demo_path

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1600, 950)
    w.show()
    try:
        files = _sim_pair(tmp_path)
        w.load_files([*files, demo_path()])  # the demo: Clean removes points by rules
        _settle(w)
        ids = [w.layer_id(f.name) for f in files]
        w.select_layer(w.layer_id(demo_path().name))
        w.run_step("clean")
        _settle(w)
        cleaned = next(lid for lid, lay in w.session.layers.items() if lay.step == "clean")
        w.layer_list.clearSelection()
        for lid in ids:
            w.layer_list.item(w.layer_row(lid)).setSelected(True)
        w.actions_["fuse"].trigger()
        _settle(w)
        fused = next(lid for lid, lay in w.session.layers.items() if lay.step == "fuse")
        texts = []
        rows = {}
        for lid in (cleaned, fused):
            w.select_layer(lid)
            _settle(w)
            qtbot.waitUntil(lambda: w.stats.table.rowCount() > 3, timeout=10_000)
            QtWidgets.QApplication.processEvents()
            table = w.stats.table
            for r in range(table.rowCount()):
                label, value = table.item(r, 0), table.item(r, 1)
                if label is not None and value is not None:
                    rows[(lid, label.text())] = value.toolTip() or value.text()
                    texts.append(value.toolTip() or value.text())
        name = w.session.layers[cleaned].name
        parent = w.session.layers[w.session.layers[cleaned].parent].name
        assert rows[(cleaned, "生成方式")] == f"清洗 ← {parent}", rows
        assert rows[(cleaned, "生成时间")].endswith(" UTC"), rows
        removed = rows.get((cleaned, "清洗删除"), "")
        assert removed and not re.search(r"[A-Za-z]{3,}", removed), removed
        kinds = [rows[(lid, "图层")] for lid in (cleaned, fused)]
        assert kinds[0].count("已清洗") == 1 and kinds[1].count("已融合") == 1, kinds
        assert name.endswith(" · cleaned")  # stored in English
        items = [w.layer_list.item(r).text() for r in range(w.layer_list.count())]
        assert all(t.count("已融合") <= 1 and t.count("已清洗") <= 1 for t in items), items
        log = w.log.toPlainText().splitlines()
        steps = [t for t in log if t.startswith("对 ") and " 运行" in t]
        assert any("运行清洗：" in t for t in steps) and any(
            "运行多源融合：" in t for t in steps
        ), log
        texts += log
        bound = w.review.bound
        model = bound.panel.view.model()
        titles = [
            str(model.headerData(c, QtCore.Qt.Orientation.Horizontal))
            for c in range(model.columnCount())
        ]
        assert "间隔 (秒)" in titles and "距离 (米)" in titles, titles
        texts += titles + [bound.panel.evidence.text()]
        assert "米" in bound.panel.evidence.text()
        # D8: the queue shows every column, the method's cells whole, at 1600 x 950
        view = bound.panel.view
        method = next(c for c, t in enumerate(titles) if t == "方法")
        right = view.columnViewportPosition(method) + view.columnWidth(method)
        assert right <= view.viewport().width() + 1, (right, view.viewport().width())
        cell = str(model.index(0, method).data())
        assert view.fontMetrics().horizontalAdvance(cell) < view.columnWidth(method), cell
        # D8: the batch table's 批号 column holds its widest drawn name (measured, not
        # the longest in characters: "radar:16" was cut beside "lidar:16")
        w.select_layer(fused)
        _settle(w)
        bm, bv = w.batch_model, w.batch_view
        col = next(c for c, (key, _) in enumerate(bm.COLUMNS) if key == "batch")
        fm = bv.fontMetrics()
        widest = max(
            fm.horizontalAdvance(str(bm.index(r, col).data())) for r in range(bm.rowCount())
        )
        assert widest < bv.columnWidth(col), (widest, bv.columnWidth(col))
        # D8: the batch table's 批号 column holds its widest drawn name (measured, not
        # the longest in characters: "radar:16" was cut beside "lidar:16")
        w.select_layer(fused)
        _settle(w)
        bm, bv = w.batch_model, w.batch_view
        col = next(c for c, (key, _) in enumerate(bm.COLUMNS) if key == "batch")
        fm = bv.fontMetrics()
        widest = max(
            fm.horizontalAdvance(str(bm.index(r, col).data())) for r in range(bm.rowCount())
        )
        assert widest < bv.columnWidth(col), (widest, bv.columnWidth(col))
        d = ImportDialog()
        qtbot.addWidget(d)
        d.path_edit.setText(str(files[0]))
        buttons = [b.text() for b in d.buttons.buttons()]
        assert "确定" in buttons and "取消" in buttons, buttons
        assert d.format_box.currentText() == "自动" and d.encoding_box.currentText() == "自动"
        assert d._format() == "auto" and d._encoding() is None
        texts += buttons + [d.format_box.currentText(), d.encoding_box.currentText()]
        left = _operator8_left(texts)
        assert not left, left
        d.close()
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_the_mmsi_apart_advice_names_the_parameters_row_in_the_window(qapp):
    """Operator test 11, F23: Run ▸ Associate's log (0 proposals on MTAD) told the Chinese
    window's operator "用 --set mmsi_apart=false 关闭", a command-line flag; in the window
    the advice names the Parameters panel's row as the panel shows it (its group and its
    label, a tick box unticked). The command line keeps the flag."""
    import inspect

    from wakeline.app import i18n
    from wakeline.app.core_text import shown, shown_cli
    from wakeline.app.dialogs import translated
    from wakeline.app.params_panel import field_title
    from wakeline.core import pipeline
    from wakeline.core.associate import LinkParams
    from wakeline.core.words import phrase, render

    template = (
        "; {n:#pair} of different MMSIs kept apart (mmsi_apart; off with --set "
        "mmsi_apart=false if the ids are a sensor's own numbers)"
    )
    src = inspect.getsource(pipeline)
    assert "off with --set " in src and "mmsi_apart=false if the ids" in src
    text = phrase(template, n=73)
    assert "--set mmsi_apart=false" in render(text)  # the command line's words
    english = shown(translated(text))
    assert "--set" not in english
    assert "Parameters ▸ Association, one sensor ▸ mmsi_apart (unticked)" in english
    field = next(f for f in LinkParams.__dataclass_fields__.values() if f.name == "mmsi_apart")
    zh = None
    try:
        zh = i18n.install(qapp, "zh_CN", None)
        said = shown(translated(text))
        label = field_title(LinkParams, field)
        assert label and HAN.search(label)
        assert "--set" not in said and f"参数 ▸ 关联，单传感器 ▸ {label}（不勾选）" in said, said
        assert "--set mmsi_apart=false" in shown_cli(translated(text))
    finally:
        i18n.install(qapp, "en", zh)

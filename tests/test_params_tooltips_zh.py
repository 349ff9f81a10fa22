"""The Parameters dock's tooltips in Chinese (operator test 6, D-i18n-2 c).

The core's parameter help (each field's ``doc``) stays English and Qt-free; the zh_CN
window shows it from ``resources/translations/params_zh_CN.json``, keyed "ClassName.field".
"""

import dataclasses
import json
import logging

from wakeline.app import core_text, params_panel
from wakeline.resources import translations_dir

TABLE = translations_dir() / "params_zh_CN.json"

HOW = (
    "resources/translations/params_zh_CN.json is keyed 'ClassName.field' for every field "
    "of every parameter class the Parameters panel shows (params_panel.panel_classes()). "
    "A field added to a core Params dataclass needs its Chinese help there (a faithful, "
    "concise translation of the field's doc; identifiers, numbers, units and flags kept); "
    "a field removed or renamed needs its entry removed or renamed."
)


def shown_keys() -> dict[str, str]:
    return {
        f"{cls.__name__}.{f.name}": f.metadata.get("doc", "")
        for cls in params_panel.panel_classes()
        for f in dataclasses.fields(cls)
    }


def table_docs() -> dict[str, str]:
    return json.loads(TABLE.read_text(encoding="utf-8"))["docs"]


def missing_and_stale(shown: dict, docs: dict) -> tuple[list[str], list[str]]:
    return sorted(set(shown) - set(docs)), sorted(set(docs) - set(shown))


def test_every_field_the_panel_shows_has_its_chinese_help_and_no_entry_is_stale():
    shown, docs = shown_keys(), table_docs()
    assert len(shown) > 150  # the clean rules, maneuver, compress, associate, fuse, bearing
    missing, stale = missing_and_stale(shown, docs)
    assert not missing, f"no Chinese help for {missing}. {HOW}"
    assert not stale, f"entries for fields that no longer exist: {stale}. {HOW}"
    for key, text in docs.items():
        assert text.strip() and text != shown[key], f"{key}: not translated. {HOW}"
        assert any("\u4e00" <= c <= "\u9fff" for c in text), f"{key}: no Chinese. {HOW}"


def test_the_check_fails_on_a_new_field_and_on_a_stale_entry():
    shown, docs = shown_keys(), table_docs()
    missing, stale = missing_and_stale({**shown, "LinkParams.new_field": "new"}, docs)
    assert "LinkParams.new_field" in missing
    missing, stale = missing_and_stale(shown, {**docs, "LinkParams.gone": "已删除"})
    assert stale == ["LinkParams.gone"]


def test_a_missing_entry_falls_back_to_english_with_a_logged_note(caplog, monkeypatch):
    from wakeline.core.associate import LinkParams

    f = next(f for f in dataclasses.fields(LinkParams) if f.name == "alpha")
    table = params_panel.doc_table("zh_CN")
    docs = {k: v for k, v in table["docs"].items() if k != "LinkParams.alpha"}
    monkeypatch.setattr(params_panel, "doc_table", lambda code: {**table, "docs": docs})
    monkeypatch.setattr(params_panel, "_noted", set())
    with caplog.at_level(logging.WARNING, logger=params_panel.__name__):
        assert params_panel.field_doc(LinkParams, f, "zh_CN") == f.metadata["doc"]
    assert "LinkParams.alpha" in caplog.text
    assert params_panel.field_doc(LinkParams, f, "en") == f.metadata["doc"]


def test_the_zh_window_tooltip_is_chinese_and_follows_a_language_switch(qtbot):
    from PySide6 import QtWidgets

    from wakeline.app import i18n
    from wakeline.core.associate import LinkParams

    app = QtWidgets.QApplication.instance()
    zh = i18n.install(app, "zh_CN", None)
    try:
        panel = params_panel.ParamsPanel()
        qtbot.addWidget(panel)
        panel.retranslate()
        leaf = panel.root.child("associate", "max_gap_s")
        chinese = table_docs()["LinkParams.max_gap_s"]
        assert leaf.opts["tip"].startswith(chinese), leaf.opts["tip"]
        assert "[s]" in leaf.opts["tip"] and "默认" in leaf.opts["tip"]
        english = next(
            f.metadata["doc"] for f in dataclasses.fields(LinkParams) if f.name == "max_gap_s"
        )
        assert english not in leaf.opts["tip"]
        rule = panel.root.child("clean", "speed", "v_max_kn")
        assert rule.opts["tip"].startswith(table_docs()["SpeedParams.v_max_kn"])
        zh = i18n.install(app, "en", zh)
        panel.retranslate()
        assert leaf.opts["tip"].startswith(english)
        assert "default: " in leaf.opts["tip"]
    finally:
        i18n.install(app, "en", zh)
        core_text.set_language("en")


def test_the_source_line_names_ours_and_the_papers_in_chinese():
    from wakeline.core.associate import LinkParams
    from wakeline.core.clean import SpeedParams

    alpha = next(f for f in dataclasses.fields(LinkParams) if f.name == "rivals_rounds")
    zh = params_panel.field_tip(LinkParams, alpha, "zh_CN")
    assert "本项目 (docs/evaluation.md)" in zh and "ours" not in zh
    assert "ours (docs/evaluation.md)" in params_panel.field_tip(LinkParams, alpha, "en")
    v_max = next(f for f in dataclasses.fields(SpeedParams) if f.name == "v_max_kn")
    assert "种子文献 001" in params_panel.field_tip(SpeedParams, v_max, "zh_CN")
    assert "seed 001" in params_panel.field_tip(SpeedParams, v_max, "en")

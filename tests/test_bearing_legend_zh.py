"""The bearing map's legend words ("observer", "other batches", "maneuvers") in the
window's language (h167): the scene's layers are made in a worker with English label
keys (no translator there); the main map and the Bearing-only dock put them through
the translator where they draw them."""

import numpy as np
import pandas as pd
import pytest
from test_bearing_view import harbour_table
from test_translations import zh_table

from wakeline.app.bearing_view import LAYER_NAMES, OTHER_LABEL, PART_WORDS, legend_words


def test_every_fixed_legend_word_has_a_translation_path():
    assert set(legend_words()) == {*LAYER_NAMES, OTHER_LABEL}
    assert {w for words in PART_WORDS.values() for w in words} <= set(legend_words())
    zh = zh_table()
    assert all(("BearingView", w) in zh for w in legend_words())


def _many_batches(n: int = 10):
    """More batches than have a colour of their own: the rest share "other batches"."""
    base = harbour_table(ranges=((80.0, 300.0),))
    parts = []
    for k in range(n):
        part = base.assign(batch=f"b{k:02d}", bearing=(base["bearing"] + 3.0 * k) % 360.0)
        parts.append(part)
    return pd.concat(parts, ignore_index=True).sort_values("time", kind="stable")


@pytest.mark.gui
def test_the_chinese_window_shows_the_bearing_legend_in_chinese(qtbot, tmp_path):
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore, QtWidgets

    from wakeline.app import i18n
    from wakeline.app.main import wait_for_jobs
    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "zh_CN")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(1400, 900)
    w.show()
    qtbot.waitExposed(w)
    zh = zh_table()
    try:
        path = tmp_path / "bearings.csv"
        _many_batches().to_csv(path, index=False)
        w.load_bearings(path)
        wait_for_jobs(w)
        qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=20_000)
        main = [label.text for _s, label in w.canvas.legend.items]
        observer, other = zh[("BearingView", "observer")], zh[("BearingView", "other batches")]
        assert f"bearings.csv · {observer}" in main, main
        assert f"bearings.csv · {other}" in main, main
        assert not any(t.endswith(("observer", "other batches")) for t in main), main
        dock = [label.text for _s, label in w.bearing_view.map.legend.items]
        assert observer in dock and other in dock, dock
        assert "observer" not in dock and "other batches" not in dock, dock
        assert "b00" in dock  # batch names stay as they are

        # a language switch renames the entries drawn (their data kept); the whole
        # names are the entries' tooltips (a long label is shortened to fit)
        def names(legend):
            return [label.toolTip() for _s, label in legend.items]

        zh_main, zh_dock = names(w.canvas.legend), names(w.bearing_view.map.legend)
        w.set_language("en")
        english = {observer: "observer", other: "other batches"}
        assert names(w.canvas.legend) == [
            f"{t.rpartition(' · ')[0]} · {english.get(t.rpartition(' · ')[2], t.rpartition(' · ')[2])}"
            for t in zh_main
        ]
        dock_en = names(w.bearing_view.map.legend)
        assert dock_en == [english.get(t, t) for t in zh_dock]
        assert "observer" in dock_en and "other batches" in dock_en and "b00" in dock_en
        w.set_language("zh_CN")
        assert names(w.canvas.legend) == zh_main
        assert names(w.bearing_view.map.legend) == zh_dock
        lines = next(n for n in w.canvas.layer_names() if n.endswith("/lines"))
        assert f"bearings.csv · {other}" in w.canvas.draw_data(lines).geometry.labels
    finally:
        w.runner.cancel()
        w.runner.wait()
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_in_language_changes_only_the_fixed_words_of_each_part():
    from wakeline.app.bearing_view import bearing_scene, in_language

    scene = bearing_scene(_many_batches(), pd.DataFrame())
    words = {LAYER_NAMES[0]: "O", OTHER_LABEL: "X", LAYER_NAMES[1]: "L", LAYER_NAMES[2]: "M"}
    observer, lines = scene.layers[:2]
    assert in_language(observer, "observer", words).geometry.labels == ("O",)
    got = in_language(lines, "lines", words)
    assert got.geometry.labels[-1] == "X" and "b00" in got.geometry.labels
    assert [c.label for c in got.curves if c.label == "X"]
    assert in_language(lines, "observer", words) is lines  # a batch named "observer" stays
    assert np.array_equal(got.geometry.lon, lines.geometry.lon, equal_nan=True)

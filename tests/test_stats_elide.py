"""Operator test 6, D-stats-1: the Statistics dock at a narrow width keeps room for the
values: the labels' column takes at most its share, long texts elide in the middle (the
layer name's end is what differs), each cell's tooltip holds the whole text."""

import pytest

pytest.importorskip("pytestqt")


def test_long_labels_leave_the_values_room_and_elide_in_the_middle(qtbot):
    from PySide6 import QtCore
    from test_stats_gui import _scene

    from wakeline.app.stats_panel import StatsPanel

    panel = StatsPanel()
    qtbot.addWidget(panel)
    panel.resize(600, 500)
    panel.show()
    QtCore.QCoreApplication.processEvents()
    label = "航迹持续时间 最小 / 中位数 / 90% / 最大 " * 3
    value = "Scene-7_B.csv · cleaned · compressed · associated [associated]  (L5)"
    panel.compute(("a",), _scene(3, 10), head=[(label, value)])
    assert panel.table.rowCount() > 1
    width = panel.table.viewport().width()
    assert panel.table.columnWidth(0) <= StatsPanel.LABEL_SHARE * width + 1
    assert panel.table.textElideMode() == QtCore.Qt.TextElideMode.ElideMiddle
    assert panel.table.item(0, 0).toolTip() == label
    assert panel.table.item(0, 1).toolTip() == value
    panel.resize(1400, 500)  # wider: the labels' column grows back toward its text
    QtCore.QCoreApplication.processEvents()
    assert panel.table.columnWidth(0) > 0.3 * width

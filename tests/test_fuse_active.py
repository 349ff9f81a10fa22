"""Operator test 6, D-gui-4: Run ▸ Fuse on a layer of one sensor offers to fuse it with
another loaded file's layer (and fuses the two when accepted); with no other file, the
refusal says how files are fused (select two or more layers, Run ▸ Fuse selected layers)."""

import pandas as pd
import pytest


def _two_consoles(tmp_path):
    """demo.csv's two sensors as two files without a sensor column (each reads as S1)."""
    from wakeline.resources import demo_path

    demo = pd.read_csv(demo_path())
    out = []
    for sensor, name in (("AIS", "console_ais.csv"), ("R1", "console_radar.csv")):
        path = tmp_path / name
        demo[demo["sensor"] == sensor].drop(
            columns=["sensor", "truth", "true_lon", "true_lat"]
        ).to_csv(path, index=False)
        out.append(path)
    return out


def _window(qtbot, tmp_path):
    from PySide6 import QtCore

    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "s.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "en")
    w = MainWindow(settings)
    qtbot.addWidget(w)
    return w


def test_fuse_on_one_sensor_offers_the_other_file_and_fuses_both(qtbot, tmp_path, monkeypatch):
    pytest.importorskip("pytestqt")
    from PySide6 import QtWidgets

    from conftest import load
    from wakeline.app.main import wait_for_jobs

    asked = []

    def yes(parent, title, text, *a, **k):
        asked.append(text)
        return QtWidgets.QMessageBox.StandardButton.Yes

    monkeypatch.setattr(QtWidgets.QMessageBox, "question", staticmethod(yes))
    w = _window(qtbot, tmp_path)
    try:
        ais_path, radar_path = _two_consoles(tmp_path)
        ais = load(w, ais_path)
        radar = load(w, radar_path)
        assert {str(s) for s in w.session.layers[ais].points["sensor"].unique()} == {"S1"}
        w.select_layer(ais)
        w.actions_["fuse"].trigger()
        wait_for_jobs(w)
        assert len(asked) == 1 and "console_radar.csv" in asked[0] and "S1" in asked[0], asked
        fused = [lay for lay in w.session.layers.values() if lay.kind == "fused"]
        assert len(fused) == 1 and set(fused[0].inputs) == {ais, radar}, fused
        assert len(fused[0].points) > 0
        # D-gui-6: the fused tracks are named by the files' names ("ais:3"); the log says
        # which source layer's S1 each name is
        log = w.log.toPlainText()
        assert "console_ais.csv: S1 → ais" in log and "console_radar.csv: S1 → radar" in log, log
        assert "fuse on console_ais.csv + console_radar.csv" in log, log
    finally:
        w.close()


def test_fuse_on_one_sensor_alone_says_how_to_fuse_files(qtbot, tmp_path, monkeypatch):
    pytest.importorskip("pytestqt")
    from PySide6 import QtWidgets

    from conftest import load

    told = []
    monkeypatch.setattr(
        QtWidgets.QMessageBox,
        "information",
        staticmethod(lambda parent, title, text, *a, **k: told.append(text)),
    )
    w = _window(qtbot, tmp_path)
    try:
        ais = load(w, _two_consoles(tmp_path)[0])
        w.select_layer(ais)
        job = w.actions_["fuse"].trigger()
        assert job is None
        assert len(told) == 1, told
        assert "Ctrl+click" in told[0] and "Fuse selected layers" in told[0] and "S1" in told[0]
        assert not [lay for lay in w.session.layers.values() if lay.kind == "fused"]
    finally:
        w.close()

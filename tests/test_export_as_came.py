"""Export ▸ "As it came in" (issue 19): the layout travels with the layer and the project."""

import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtWidgets  # noqa: E402

from tests.conftest import DATA  # noqa: E402
from wakeline.app.export_as_came import export_as_it_came_in  # noqa: E402
from wakeline.core.io import read_points  # noqa: E402
from wakeline.core.io.export_like import layout_meta  # noqa: E402
from wakeline.core.io.layout import Layout  # noqa: E402
from wakeline.core.project import Layer, Project, load_project, save_project  # noqa: E402

pytestmark = pytest.mark.gui
RADAR = DATA / "layouts" / "radar_gb18030.csv"


def _layers(tmp_path):
    """A source layer with its layout (as the import hook stores it) and a result layer
    made from it, saved to a project and opened again."""
    result = read_points(RADAR)
    meta = {"file": str(tmp_path / "gone.csv"), "layout": layout_meta(RADAR, result.report)}
    merged = result.points.assign(
        target=result.points["batch"].where(result.points["batch"] != "102", "101")
    )
    project = Project(
        layers=[
            Layer("radar.csv", "source", result.points, meta=meta),
            Layer("radar.csv · merged", "associated", merged, meta={"from": "radar.csv"}),
        ]
    )
    save_project(project, tmp_path / "p.wakeline")
    return {lay.name: lay for lay in load_project(tmp_path / "p.wakeline").layers}


def test_layout_is_kept_in_the_project_and_used_for_a_result_layer(qtbot, tmp_path):
    parent = QtWidgets.QWidget()
    qtbot.addWidget(parent)
    layers = _layers(tmp_path)
    assert Layout.from_dict(layers["radar.csv"].meta["layout"]).encoding == "gb18030"
    lines = []
    out = tmp_path / "back.csv"
    rep = export_as_it_came_in(parent, layers, "radar.csv", out, log=lines.append)
    assert rep is not None and out.read_bytes() == RADAR.read_bytes()
    out2 = tmp_path / "merged.csv"
    rep = export_as_it_came_in(parent, layers, "radar.csv · merged", out2, log=lines.append)
    assert rep["members"] == str(tmp_path / "merged.members.csv")
    back = read_points(out2)
    assert back.report["encoding"] == "gb18030"
    assert sorted(back.points["batch"].unique()) == ["101", "103"]
    assert "members of merged targets" in lines[-1]


def test_layer_without_a_source_file_gives_a_clear_warning(qtbot, tmp_path, monkeypatch):
    seen = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: seen.append(a[2]))
    pts = read_points(RADAR).points
    layers = {"sim": Layer("sim", "source", pts, meta={})}
    lines = []
    assert export_as_it_came_in(None, layers, "sim", tmp_path / "x.csv", log=lines.append) is None
    assert "no imported file behind this layer" in seen[0]
    assert lines[0].startswith("Error:")
    assert not (tmp_path / "x.csv").exists()


def test_asks_for_the_file_name_when_none_given(qtbot, tmp_path, monkeypatch):
    layers = _layers(tmp_path)
    target = tmp_path / "chosen.csv"
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: (str(target), ""))
    assert export_as_it_came_in(None, layers, "radar.csv") is not None
    assert target.read_bytes() == RADAR.read_bytes()
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: ("", ""))
    assert export_as_it_came_in(None, layers, "radar.csv") is None

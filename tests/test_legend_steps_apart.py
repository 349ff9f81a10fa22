"""h158 review finding: since h153 a shortened legend label leaves out the first steps
with no "…", so two layers of one file that differ only there get the same label
(Maneuvers run on the source, and the pipeline's "cleaned · maneuvers": both
"scene…radar · maneuvers"; before: "scene…r.csv · maneuvers" / "sce…csv · … · maneuvers")."""

import os

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("PySide6")

pytestmark = pytest.mark.gui


def test_layers_differing_in_a_first_step_keep_apart_in_the_legend(qtbot):
    from wakeline.app.map_legend import SideLegend

    legend = SideLegend()
    head = "scene-0_error_10_radar.csv"
    for last in ("maneuvers", "compressed"):
        a = legend.fit_label(f"{head} · cleaned · {last}")
        b = legend.fit_label(f"{head} · {last}")
        assert a != b, (a, b)


def test_a_label_of_several_files_keeps_each_name_on_its_own_line(qtbot):
    """Operator test 8, D8: a fused layer's label "A.csv + B.csv · 已融合" was drawn
    "scene-0_erro..._radar.csv · 已融合", naming neither file: each file now has a line
    of its own (whole where it fits), the step word under them."""
    from wakeline.app.map_legend import SideLegend

    legend = SideLegend()
    a, b = "scene-0_error_0_AIS.csv", "scene-0_error_0_radar.csv"
    shown = legend.shown_label(f"{a} + {b} · 已融合")
    lines = shown.split("<br>")
    assert lines[0] == f"{a} +" and lines[1] == f"{b} ·", lines
    assert lines[-1].endswith("已融合") and len(lines) == 3, lines
    # one file's label is as before: its name, then the step indented under it
    assert legend.shown_label(f"{b} · 已融合").count("<br>") <= 1

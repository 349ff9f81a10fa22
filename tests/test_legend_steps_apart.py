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

"""Operator test 5 (h181): the Parameters dock's refusals (D-params-1, D-params-2) and
the map with every layer unticked or across the antimeridian (D-map-2, D-map-3)."""

import pytest

pytest.importorskip("pytestqt")

from wakeline.app.params_panel import ParamsPanel  # noqa: E402

pytestmark = pytest.mark.gui


def test_a_refusal_is_said_once_and_cleared_by_defaults(qtbot):
    panel = ParamsPanel()
    qtbot.addWidget(panel)
    panel.show()
    said = []
    panel.refused.connect(said.append)
    for path, value in (
        (("clean", "stationary", "radius_m"), -50.0),
        (("clean", "speed", "v_max_kn"), 0.0),
        (("maneuver", "threshold_deg"), -3.0),
    ):
        said.clear()
        panel.root.child(*path).setValue(value)
        qtbot.wait(10)
        assert len(said) == 1, (path, said)  # was 2: the spin box echoed it back
        assert panel.problem.text() == said[0]
    panel.root.child("maneuver", "threshold_deg").setValue(-3.0)  # again, a later turn
    qtbot.wait(10)
    assert len(said) == 2  # a second attempt is said again
    panel.reset()
    assert panel.problem.text() == ""  # every value is a default again
    assert panel.to_dict() == ParamsPanel().to_dict()

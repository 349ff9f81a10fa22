"""What a window keeps in memory (defect #8 of session 25's operator test: a closed window
held its 2 GB of layers while the project opened again in a second one)."""

import contextlib
import os
import weakref

import numpy as np
import pandas as pd
import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("PySide6")

from conftest import load, make_window  # noqa: E402
from wakeline.app.main import wait_for_jobs  # noqa: E402
from wakeline.app.map_draw import layer_geometry, shared_strings  # noqa: E402
from wakeline.resources import demo_path  # noqa: E402

pytestmark = pytest.mark.gui


def test_a_closed_window_lets_its_layers_and_their_drawing_go(qtbot, tmp_path):
    """The window's objects are frozen at start (never collected) and the tests freeze
    the windows they delete: a closed window must not hold its layers, their prepared
    views, what the map drew of them, the time slider's scene or a job's closure."""
    w = make_window(qtbot, tmp_path)
    w.show()
    src = load(w, demo_path())
    w.select_layer(src)
    w.run_step("pipeline")
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.drawing and not w.time_controller.busy, timeout=20_000)
    assert len(w.layers) == 4
    points = [weakref.ref(lay.points) for lay in w.layers.values()]
    drawn = [weakref.ref(v.draw.geometry) for v in w.views.values() if v.draw is not None]
    assert drawn
    # A finished job does not keep its function (and the layers its closure read).
    assert all(t.fn is None for t in w.runner._threads() if t.isFinished())
    w.close()
    # A background job under way (the Statistics dock's, a level of detail) may still
    # read a layer: it ends soon, and lets it go too.
    gone = [*points, *drawn]
    with contextlib.suppress(qtbot.TimeoutError):
        qtbot.waitUntil(lambda: all(r() is None for r in gone), timeout=10_000)
    assert [r() is None for r in points] == [True] * len(points)
    assert [r() is None for r in drawn] == [True] * len(drawn)
    assert w.time_controller.overlay.scene is None
    assert not w.views and not w.canvas._data


def test_a_batch_per_point_is_one_string_per_batch():
    """An associated layer names each point's batch (hover, click): one Python string per
    batch, not per point (65 MB on 1 M points), with the values as before."""
    values = pd.Series(["7", "8", None, "7", "8"] * 3, dtype="str")
    out = shared_strings(values)
    want = values.to_numpy(dtype=object)
    assert out.dtype == object and len(out) == len(want)
    assert [str(v) for v in out] == [str(v) for v in want]
    assert out[0] is out[3] and out[1] is out[4] and pd.isna(out[2])
    pts = pd.DataFrame(
        {
            "sensor": ["A"] * 6,
            "batch": ["1", "1", "1", "2", "2", "2"],
            "time": pd.date_range("2024-01-01", periods=6, freq="10s", tz="UTC"),
            "lon": np.linspace(10, 10.01, 6),
            "lat": np.linspace(55, 55.01, 6),
            "piece_batch": ["x", "x", "y", "z", "z", "z"],
        }
    )
    geom = layer_geometry(pts)
    assert list(geom.point_batch) == ["x", "x", "y", "z", "z", "z"]
    assert geom.point_batch[0] is geom.point_batch[1]

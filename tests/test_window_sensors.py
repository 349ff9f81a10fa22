"""The map's per-layer view of the operator's choosing (h237): the active layer's legend
entries in bold, and View ▸ Sensors — one sensor's tracks of a layer hidden (a view
filter: the layer's points untouched), the batch table and the status bar's counts
following."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _window  # noqa: E402

from wakeline.core.io import write_points  # noqa: E402

pytestmark = pytest.mark.gui


def _two_sensors(n=40):
    t = pd.date_range("2024-05-01", periods=n, freq="10s", tz="UTC")
    parts = []
    for sensor, batches, lat0 in (("AIS", ("101", "102"), 50.0), ("radar", ("7",), 50.2)):
        for k, b in enumerate(batches):
            parts.append(
                pd.DataFrame(
                    {
                        "sensor": sensor,
                        "batch": b,
                        "time": t,
                        "lon": 10.0 + 0.1 * k + 0.001 * np.arange(n),
                        "lat": lat0 + 0.0005 * np.arange(n),
                    }
                )
            )
    return pd.concat(parts, ignore_index=True)


def _loaded(qtbot, tmp_path):
    path = tmp_path / "scene.csv"
    write_points(_two_sensors(), path)
    w = _window(qtbot, tmp_path)
    w.load_files([path])
    _settle(w)
    lid = w.layer_id(path.name)
    w.select_layer(lid)
    _settle(w)
    return w, lid


def _bold(w, lid):
    legend = w.canvas.legend
    items = [i for n in w.map_names(lid) for i in w.canvas.layer_items(n)]
    return [legend.is_bold(i) for i in items]


def test_the_active_layers_legend_entries_are_bold_and_only_them(qtbot, tmp_path):
    w, src = _loaded(qtbot, tmp_path)
    widest = w.canvas.legend.widest  # the column reserved from the start
    w.run_step("clean")
    _settle(w)
    cleaned = next(i for i, lay in w.layers.items() if lay.parent == src)
    w.select_layer(cleaned)
    _settle(w)
    assert _bold(w, cleaned) and all(_bold(w, cleaned))
    assert _bold(w, src) and not any(_bold(w, src))
    labels = {lab.toolTip(): lab for _s, lab in w.canvas.legend.items}
    assert any(lab.opts.get("bold") for lab in labels.values())
    w.select_layer(src)
    _settle(w)
    assert all(_bold(w, src)) and not any(_bold(w, cleaned))
    # a bold label fits the reserved column: it never widens it
    assert w.canvas.legend.widest == widest
    w.close()

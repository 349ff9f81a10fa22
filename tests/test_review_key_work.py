"""Work per review key (h187, operator test 5 D-gui-3: a key blocked the window 166-623 ms).

A decision's layer is swapped in 300 ms after the key (ReviewSync): the same tracks with
new targets. The batch table used to be reset for it (and its selection dropped and
selected again, the map's selection and the Detail panel drawn twice more); now its cells
change in place. Counted per key, not timed: batch-table model resets, whole-layer
``set_active`` passes, the map's selection redrawn and the Detail panel cleared after
the swap; and the hidden before map gets no proposal curves (drawn when shown).
bench/review_keys.py times the same on real files.
"""

import pytest

pytest.importorskip("pytestqt")

from PySide6 import QtCore  # noqa: E402
from test_review_rerun_late_gui import _pending  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

pytestmark = pytest.mark.gui
KEYS = 4


def _associated_window(qtbot, tmp_path):
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    w.select_layer(w.layer_id(src.name))
    w.run_step("associate")
    _settle(w)
    layer = w.session.find(w.layer_id(src.name), "associate")
    w.select_layer(layer.id)
    _settle(w)
    return w, layer


def test_a_key_updates_the_batch_table_in_place(qtbot, tmp_path, monkeypatch):
    w, layer = _associated_window(qtbot, tmp_path)
    bound = w.review.bound
    assert len(_pending(bound.controller.state)) > KEYS
    counts = {"reset": 0, "cells": 0, "set_active": 0, "selection": 0, "detail_clear": 0}
    swaps: list[int] = []

    def count(name):
        def bump(*_args):
            counts[name] += 1

        return bump

    w.batch_model.modelReset.connect(count("reset"))
    w.batch_model.dataChanged.connect(count("cells"))
    for name, obj, attr in (
        ("set_active", w, "set_active"),
        ("selection", w.canvas, "show_selection"),
        ("detail_clear", w.detail, "clear"),
    ):
        real = getattr(obj, attr)

        def wrapped(*args, _real=real, _name=name, **kwargs):
            if swaps:  # from the swap on: what the decision's new points set off
                counts[_name] += 1
            return _real(*args, **kwargs)

        monkeypatch.setattr(obj, attr, wrapped)
    replace = w.session.replace_points

    def replace_points(*args, **kwargs):
        swaps.append(1)
        return replace(*args, **kwargs)

    monkeypatch.setattr(w.session, "replace_points", replace_points)
    from wakeline.app import layer_view

    prepared = []
    prepare = layer_view.prepare_view

    def prepare_view(*args, **kwargs):
        prepared.append(1)
        return prepare(*args, **kwargs)

    monkeypatch.setattr(layer_view, "prepare_view", prepare_view)
    bound.panel.view.setFocus()
    selected = []
    state = bound.controller.state
    swapped = 0
    for i in range(KEYS + 2):
        swaps.clear()
        prepared.clear()
        before = dict(counts)
        n_pending = len(_pending(state))
        targets = state.target_of_track().copy()
        # an accept of a pending proposal (pending counts as joined) leaves the targets
        key = QtCore.Qt.Key.Key_A if i in (1, 4) else QtCore.Qt.Key.Key_R
        qtbot.keyClick(bound.panel.view, key)
        assert len(_pending(state)) == n_pending - 1  # decided by the key
        if (state.target_of_track() == targets).all():
            # the same points again: no layer prepared, nothing swapped in, the layer
            # marked as showing the decision (File > Export writes it as it is)
            _settle(w)
            assert not w.review.sync.busy
            assert not swaps and not prepared and counts == before, (i, counts, before)
            assert layer.meta["review_decisions"] == len(state.log)
            assert w.review.sync.decided_now(w.session.layers[layer.id]) is None
            assert key == QtCore.Qt.Key.Key_A
            continue
        swapped += 1
        relabeled = w.review.sync.counts["relabeled"]
        qtbot.waitUntil(lambda: bool(swaps), timeout=30_000)
        _settle(w)
        # a reject changes a few targets: their lines made again alone, no whole view
        # (session 31); the first decision after the bind may relabel every track (the
        # engine's target names become the review's) and makes the whole view
        assert prepared == ([] if swapped > 1 else prepared), (i, prepared)
        assert w.review.sync.counts["relabeled"] == relabeled + (not prepared)
        per_key = {k: counts[k] - before[k] for k in counts}
        # the same tracks: their cells change in place, once; nothing reset, no whole
        # active-layer pass, the selection and the Detail panel left as they are
        assert per_key == {
            "reset": 0,
            "cells": 1,
            "set_active": 0,
            "selection": 0,
            "detail_clear": 0,
        }, (i, per_key)
        selected.append(w.selected_keys())
        assert selected[-1]  # the next proposal's tracks stay selected through the swap
    assert swapped >= KEYS - 1 and w.review.sync.counts["unchanged"] == KEYS + 2 - swapped
    assert w.review.sync.counts["relabeled"] >= swapped - 1
    # the table shows the decided targets (its cells follow the layer's points)
    frame = w.batch_model.frame
    shown = dict(zip(zip(frame["sensor"], frame["batch"], strict=True), frame["target"],
                     strict=True))  # fmt: skip
    pts = w.session.layers[layer.id].points
    want = pts.groupby(["sensor", "batch"])["target"].first().to_dict()
    assert {k: str(v) for k, v in shown.items()} == {
        (str(s), str(b)): str(t) for (s, b), t in want.items()
    }
    # the hidden before map gets no proposal curves at each key; shown, it draws the
    # current proposal at once
    dock = w.review
    assert not [it for c, it in dock._items["proposal"] if c is dock.before]
    dock.act_before.trigger()
    _settle(w)
    on_before = [it for c, it in dock._items["proposal"] if c is dock.before]
    assert on_before and all(it.isVisible() for it in on_before)
    assert len(on_before) == len([it for c, it in dock._items["proposal"] if c is w.canvas])
    w.close()


def test_other_tracks_still_reset_the_table(qtbot, tmp_path):
    """New points with other tracks (or another order) are not patched in place."""
    import pandas as pd

    from wakeline.app.models import BatchTableModel, batch_summary

    model = BatchTableModel()
    pts = pd.DataFrame(
        {
            "sensor": ["S1"] * 4,
            "batch": ["1", "1", "2", "2"],
            "time": pd.to_datetime([0, 10, 0, 10], unit="s", utc=True),
            "lon": [0.0, 0.001, 0.01, 0.011],
            "lat": [0.0, 0.0, 0.0, 0.0],
        }
    )
    model.set_summary(batch_summary(pts.assign(target="A")))
    assert model.update_summary(batch_summary(pts.assign(target="B")))
    assert set(model.frame["target"]) == {"B"}
    assert not model.update_summary(batch_summary(pts[pts["batch"] == "1"]))
    renamed = pts.assign(batch=pts["batch"].map({"1": "3", "2": "2"}))
    assert not model.update_summary(batch_summary(renamed))


def test_the_same_layers_new_figures_keep_the_old_until_they_come(qtbot):
    """A decision's new points recompute the Statistics dock's figures; the layer's
    figures stay shown meanwhile (the "Computing…" note shown and hidden again laid the
    dock out twice per key). Another layer still says "Computing…"."""
    from test_stats_gui import _scene

    from wakeline.app.stats_panel import StatsPanel

    panel = StatsPanel()
    qtbot.addWidget(panel)
    jobs = []
    panel.executor = lambda job, done: jobs.append((job, done))
    a = _scene(3, 20)
    panel.compute(("a", 1, None), a)
    job, done = jobs.pop()
    done(job())
    assert panel.stats.tracks == 3 and not panel.note.isVisibleTo(panel)
    panel.compute(("a", 2, None), a.assign(target="t"))  # the same layer, new points
    assert not panel.note.isVisibleTo(panel) and panel.stats.tracks == 3
    job, done = jobs.pop()
    done(job())
    assert panel.shown_key == ("a", 2, None) and not panel.note.isVisibleTo(panel)
    panel.compute(("a", 2, (0.0, 60.0)), a)  # a time window: computing
    assert panel.note.isVisibleTo(panel) and panel.note.text() == "Computing…"
    job, done = jobs.pop()
    done(job())
    panel.compute(("b", 1, None), _scene(5, 20))  # another layer
    assert panel.note.isVisibleTo(panel) and panel.note.text() == "Computing…"


def _shown_targets(w, layer_id, state):
    """Per track of the queue (``state.tracks``' order): the target its layer's points show."""
    import pandas as pd

    from wakeline.core.review import point_labels

    pts = w.session.layers[layer_id].points
    lab = pd.Series(pts["target"].to_numpy(), index=point_labels(pts))
    lab = lab[~lab.index.duplicated()]
    return lab.reindex(state.tracks["track"]).to_numpy()


@pytest.mark.parametrize("seed", [0, 1])
def test_the_layer_shows_the_decisions_after_any_keys(qtbot, tmp_path, seed):
    """Review h231: A, R, undo and redo in a random order, some within the 300 ms or the
    job of the one before (a skipped job among them, session 30): the layer's points end
    showing every track's target as the decisions make it, and say so."""
    import random

    import numpy as np

    w, layer = _associated_window(qtbot, tmp_path)
    bound = w.review.bound
    state = bound.controller.state
    rnd = random.Random(seed)
    bound.panel.view.setFocus()
    for _ in range(12):
        what = rnd.choice(["A", "R", "A", "R", "undo", "redo"])
        if what in ("A", "R"):
            qtbot.keyClick(bound.panel.view, getattr(QtCore.Qt.Key, f"Key_{what}"))
        else:
            getattr(w.review, f"act_{what}").trigger()
        if rnd.random() < 0.5:
            _settle(w)
        else:
            qtbot.wait(rnd.choice([0, 50, 320]))
    _settle(w)
    assert layer.meta["review_decisions"] == len(state.log)
    np.testing.assert_array_equal(_shown_targets(w, layer.id, state), state.target_of_track())
    assert w.review.sync.counts["prepared"] > 0


def test_a_decision_in_another_queue_within_a_job_drops_neither(qtbot, tmp_path, monkeypatch):
    """Review h231: queue A's decision job was running when queue B's decision ran its own
    (one runner: it cancelled A's, whose result was dropped): A's layer never showed A's
    decision (its meta, batch table and map stale). B's job now waits for A's."""
    import time

    import numpy as np

    from wakeline.app import review_sync
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    w, la = _associated_window(qtbot, tmp_path)
    src = tmp_path / "seg2.csv"
    write_points(simulate.segments_scene(seed=5, n_ships=8, area_km=15), src)
    w.load_files([src])
    _settle(w)
    w.select_layer(w.layer_id(src.name))
    w.run_step("associate")
    _settle(w)
    lb = w.session.find(w.layer_id(src.name), "associate")
    w.select_layer(lb.id)
    _settle(w)
    bound_b = w.review.bound
    w.select_layer(la.id)
    _settle(w)
    bound_a = w.review.bound
    assert bound_a is not bound_b
    decided = review_sync.decided_points

    def slow(*args, **kwargs):  # a big layer's decision: its job takes a while
        time.sleep(0.5)
        return decided(*args, **kwargs)

    monkeypatch.setattr(review_sync, "decided_points", slow)
    bound_a.panel.view.setFocus()
    qtbot.keyClick(bound_a.panel.view, QtCore.Qt.Key.Key_R)
    qtbot.waitUntil(lambda: w.review.sync._job is not None, timeout=5000)
    w.select_layer(lb.id)
    qtbot.waitUntil(lambda: w.review.bound is bound_b, timeout=5000)
    bound_b.panel.view.setFocus()
    qtbot.keyClick(bound_b.panel.view, QtCore.Qt.Key.Key_R)
    _settle(w)
    for lay, b in ((la, bound_a), (lb, bound_b)):
        st = b.controller.state
        assert len(st.log) == 1 and lay.meta.get("review_decisions") == 1, lay.name
        np.testing.assert_array_equal(_shown_targets(w, lay.id, st), st.target_of_track())

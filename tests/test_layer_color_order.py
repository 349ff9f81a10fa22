"""SPEC §7 Layers: the operator sets a layer's colour (Layers ▸ Colour…) and its order
(Move up / Move down, or a row dragged); both are core commands with an inverse, undone
through the window's layer stack, saved at once and kept on reopening; the map's
stacking follows the list and the legend the colour (h246)."""

import pandas as pd
import pytest

from wakeline.core.errors import InputError
from wakeline.core.project import ProjectWriter, load_project, save_project
from wakeline.core.session import COLOR_CHOSEN, Session


def _points(n=30, lon0=10.0):
    t = pd.date_range("2024-05-01", periods=n, freq="60s", tz="UTC")
    return pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "7",
            "time": t,
            "lon": lon0 + 0.01 * pd.RangeIndex(n),
            "lat": 50.0 + 0.005 * pd.RangeIndex(n),
        }
    )


def _session():
    s = Session()
    ids = [s.add_layer(name, "source", _points(lon0=k)).id for k, name in enumerate("abc")]
    return s, ids


def test_set_color_is_a_command_with_an_inverse_and_an_event():
    s, (a, _b, _c) = _session()
    events = []
    s.subscribe(lambda e, lid: events.append((e, lid)))
    before = (s.layers[a].color, False)
    old = s.set_color(a, "#ABCDEF")
    assert old == before
    assert s.layers[a].color == "#abcdef" and s.layers[a].meta[COLOR_CHOSEN] is True
    assert events == [("color", a)]
    assert s.set_color(a, "#abcdef") == ("#abcdef", True) and len(events) == 1  # no change
    s.set_color(a, *old)  # the inverse
    assert s.layers[a].color == before[0] and COLOR_CHOSEN not in s.layers[a].meta
    for bad in ("red", "#12345", "#12345g", "", None):
        with pytest.raises(InputError):
            s.set_color(a, bad)
    with pytest.raises(InputError):
        s.set_color("nope", "#000000")


def test_move_layer_returns_the_place_that_undoes_it():
    s, ids = _session()
    a, b, c = ids
    events = []
    s.subscribe(lambda e, lid: events.append(e))
    old = s.move_layer(a, 2)
    assert old == 0 and list(s.layers) == [b, c, a] and events == ["reordered"]
    assert s.move_layer(c, -5) == 1 and list(s.layers) == [c, b, a]  # clipped
    s.move_layer(c, 1)
    s.move_layer(a, old)
    assert list(s.layers) == [a, b, c]
    n = len(events)
    assert s.move_layer(b, 1) == 1 and len(events) == n  # in place: no event


def test_colour_and_order_survive_the_project_written_as_they_change(tmp_path):
    s, (a, b, c) = _session()
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    errors = []
    writer = ProjectWriter(path, errors.append)
    pos = {lid: k for k, lid in enumerate(s.layers)}

    def follow(event, lid):  # as the window's project controller does
        if event == "color":
            layer = s.layers[lid]
            writer.submit(lambda st: st.put_layer(layer, pos[lid], with_data=False))
        elif event == "reordered":
            order = list(s.layers)
            writer.submit(lambda st: st.put_order(order))

    s.subscribe(follow)
    s.set_color(b, s.layers[a].color)  # the operator may choose another layer's colour
    s.move_layer(c, 0)
    assert writer.flush(10)
    writer.close()
    assert errors == []
    back = load_project(path)
    assert [lay.id for lay in back.layers] == [c, a, b]
    got = {lay.id: lay for lay in back.layers}
    assert got[b].color == s.layers[a].color and got[b].meta.get(COLOR_CHOSEN) is True
    assert not got[a].meta.get(COLOR_CHOSEN)


def test_a_rerun_keeps_the_operators_colour():
    s = Session()
    src = s.add_layer("a", "source", _points(60))
    made = s.apply_result(src.id, s.run_step(src.id, "clean"))
    cleaned = next(lay for lay in made if lay.parent == src.id)
    s.set_color(cleaned.id, "#123456")
    again = s.apply_result(src.id, s.run_step(src.id, "clean"))
    assert any(lay.id == cleaned.id for lay in again)  # replaced in place
    assert s.layers[cleaned.id].color == "#123456"
    assert s.layers[cleaned.id].meta.get(COLOR_CHOSEN) is True


# -- the window ------------------------------------------------------------------------

pytest.importorskip("pytestqt")


def _two_layers(qtbot, tmp_path):
    """The demo and its cleaned layer, the cleaned one active."""
    from test_review_window import _settle, _window

    from wakeline.resources import demo_path

    w = _window(qtbot, tmp_path)
    w.load_file(demo_path())
    _settle(w)
    src = w.active
    w.run_step("clean")
    _settle(w)
    cleaned = next(lid for lid, lay in w.layers.items() if lay.parent == src)
    return w, src, cleaned


def _z(w, lid):
    items = w.canvas.layer_items(lid)
    assert items
    return max(item.zValue() for item in items)


@pytest.mark.gui
def test_colour_is_drawn_in_the_legend_undone_and_kept_on_reopening(qtbot, tmp_path):
    from test_review_window import _settle

    w, src, cleaned = _two_layers(qtbot, tmp_path)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    old = w.layers[src].color
    other = w.layers[cleaned].color  # another layer's colour: the operator's choice wins
    assert other != old
    w.set_layer_color(src, other)
    _settle(w)
    assert w.layers[src].color == other and w.views[src].colors[0] == other
    drawn = {c.color for c in w.canvas.draw_data(src).curves}
    assert other in drawn and old not in drawn
    pens = {item.opts["pen"].color().name() for item in w.canvas.layer_items(src)}
    assert other in pens
    legend = [
        sample.item.opts["pen"].color().name()
        for sample, _label in w.canvas.legend.items
        if sample.item in w.canvas.layer_items(src)
    ]
    assert legend and other in legend
    icon = w.layer_list.item(w.layer_row(src)).icon().pixmap(14, 14).toImage()
    assert icon.pixelColor(7, 7).name() == other
    undo = w.layer_undo
    assert "colour" in undo.act_undo.text()
    undo.act_undo.trigger()
    _settle(w)
    assert w.layers[src].color == old and w.views[src].colors[0] == old
    assert old in {c.color for c in w.canvas.draw_data(src).curves}
    undo.act_redo.trigger()
    _settle(w)
    assert w.layers[src].color == other
    assert w.project.flush(30)
    w.close()

    from test_review_window import _window

    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    assert w2.layers[src].color == other and w2.views[src].colors[0] == other
    assert w2.layers[cleaned].color == other  # as drawn when saved: both
    assert other in {c.color for c in w2.canvas.draw_data(src).curves}
    w2.close()


@pytest.mark.gui
def test_order_sets_the_stacking_is_undone_and_kept_on_reopening(qtbot, tmp_path):
    from test_review_window import _settle, _window

    w, src, cleaned = _two_layers(qtbot, tmp_path)
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    w.actions_["active_on_top"].setChecked(False)  # the order alone
    w.select_layer(src)
    _settle(w)
    assert list(w.layers) == [src, cleaned]
    assert _z(w, src) > _z(w, cleaned)  # higher in the list: drawn over
    w.move_layer(src, 1)  # Move down
    _settle(w)
    assert list(w.layers) == [cleaned, src] and w.layer_row(cleaned) == 0
    assert _z(w, cleaned) > _z(w, src)
    # Keep the active layer on top (the default): the active one over the order
    w.actions_["active_on_top"].setChecked(True)
    assert _z(w, src) > _z(w, cleaned)
    w.actions_["active_on_top"].setChecked(False)
    w.layer_undo.undo()
    _settle(w)
    assert list(w.layers) == [src, cleaned] and _z(w, src) > _z(w, cleaned)
    # a row dragged in the list is the same move
    model = w.layer_list.model()
    root = model.index(0, 0).parent()
    assert model.moveRow(root, 0, root, 2)
    _settle(w)
    assert list(w.layers) == [cleaned, src] and _z(w, cleaned) > _z(w, src)
    # several rows dragged at once (one signal per row): one undoable reorder
    extra = w.session.add_layer("extra.csv", "source", _points(lon0=122.5)).id
    _settle(w)
    assert list(w.layers) == [cleaned, src, extra]
    assert model.moveRow(root, 1, root, 0) and model.moveRow(root, 2, root, 0)
    _settle(w)
    assert list(w.layers) == [extra, src, cleaned]
    assert _z(w, extra) > _z(w, src) > _z(w, cleaned)
    w.layer_undo.undo()
    _settle(w)
    assert list(w.layers) == [cleaned, src, extra]
    w.layer_undo.redo()
    w.layer_undo.undo()
    _settle(w)
    w.select_layer(extra)
    w.remove_active_layer()  # a removal: stacked with the moves
    _settle(w)
    assert w.project.flush(30)
    w.close()

    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    assert list(w2.layers) == [cleaned, src]
    assert [w2.layer_list.item(r).data(0x0100) for r in range(2)] == [cleaned, src]
    w2.actions_["active_on_top"].setChecked(False)
    assert _z(w2, cleaned) > _z(w2, src)
    w2.close()


# -- one order for Edit ▸ Undo / Redo (operator test 11, h249 F1) -------------------------


def _edit_texts(w):
    return [a.text() for a in w.review.edit_menu.actions() if not a.isSeparator()]


@pytest.mark.gui
def test_ctrl_z_undoes_the_colour_before_an_older_point_restore(qtbot, tmp_path):
    """Clean, restore the removed points in the view, colour the layer, Ctrl+Z: the
    colour was kept and the older restore taken out (the layer edits sat on a second
    stack with no shortcut). Now Edit ▸ Undo / Redo follow the order the edits were made
    in, whichever stack holds them, and the Edit menu has one Undo and one Redo."""
    from PySide6 import QtWidgets
    from test_review_window import _settle

    w, _src, cleaned = _two_layers(qtbot, tmp_path)
    layer, tool = w.layers[cleaned], w.restore_tool

    def settle():
        qtbot.waitUntil(lambda: not tool.busy, timeout=60_000)
        _settle(w)

    n0, old = len(layer.points), layer.color
    w.canvas.fit()
    QtWidgets.QApplication.processEvents()
    assert tool.restore_in_view(cleaned)
    settle()
    n1 = len(layer.points)
    assert n1 > n0
    w.set_layer_color(cleaned, "#ff00ff")
    _settle(w)
    assert layer.color == "#ff00ff"
    undo, redo = w.review.act_undo, w.review.act_redo
    texts = _edit_texts(w)
    assert sum(t.startswith("&Undo") for t in texts) == 1
    assert sum(t.startswith("&Redo") for t in texts) == 1
    assert not any("Restore removed &layer" in t or "ag&ain" in t for t in texts)
    assert undo.isEnabled() and "layer colour" in undo.text()
    assert undo.shortcut().toString() == "Ctrl+Z"
    undo.trigger()  # the colour, not the restore
    settle()
    assert layer.color == old and len(layer.points) == n1
    assert "restore" in undo.text() and "layer colour" in redo.text()
    undo.trigger()  # then the restore
    settle()
    assert len(layer.points) == n0 and not undo.isEnabled()
    assert "restore" in redo.text()
    redo.trigger()  # redo in reverse: the restore first
    settle()
    assert len(layer.points) == n1 and layer.color == old
    assert "layer colour" in redo.text()
    redo.trigger()
    settle()
    assert layer.color == "#ff00ff" and not redo.isEnabled()
    assert "layer colour" in undo.text()
    w.close()


@pytest.mark.gui
def test_ctrl_z_undoes_a_layer_move_made_after_a_review_decision(qtbot, tmp_path):
    """Accept a proposal, move a layer: Undo undoes the move, then the accept; Redo
    redoes them in the reverse order; a decision made after an undone move drops the
    move's Redo (as one stack would)."""
    from test_gui_review_low import _fused_review
    from test_review_window import _settle

    w = _fused_review(qtbot, tmp_path)
    ctl = w.review.bound.controller
    pid = ctl.state.proposals["proposal"].tolist()[0]
    ctl.accept(pid)
    _settle(w)
    assert ctl.state.status_of(pid) == "accepted"
    order = list(w.layers)
    lid = order[0]
    w.move_layer(lid, 1)
    _settle(w)
    moved = list(w.layers)
    assert moved != order
    undo, redo = w.review.act_undo, w.review.act_redo
    assert "layer move" in undo.text()
    undo.trigger()
    _settle(w)
    assert list(w.layers) == order and ctl.state.status_of(pid) == "accepted"
    assert "accept" in undo.text() and "layer move" in redo.text()
    undo.trigger()
    _settle(w)
    assert ctl.state.status_of(pid) == "pending" and list(w.layers) == order
    assert "accept" in redo.text()
    redo.trigger()
    _settle(w)
    assert ctl.state.status_of(pid) == "accepted" and list(w.layers) == order
    redo.trigger()
    _settle(w)
    assert list(w.layers) == moved and not redo.isEnabled()
    undo.trigger()  # the move again
    _settle(w)
    assert list(w.layers) == order and redo.isEnabled()
    other = ctl.state.proposals["proposal"].tolist()[1]
    ctl.accept(other)  # a newer edit: the move's Redo is gone
    _settle(w)
    assert not redo.isEnabled()
    redo.trigger()
    _settle(w)
    assert list(w.layers) == order
    undo.trigger()
    _settle(w)
    assert ctl.state.status_of(other) == "pending" and list(w.layers) == order
    w.close()


@pytest.mark.gui
def test_a_removed_layer_restored_keeps_its_point_restores_undoable(qtbot, tmp_path):
    """h249 F2: after Layer ▸ Remove and its undo, the layer's point restores could no
    longer be undone (their stack went with the layer); it is kept for the undo."""
    from PySide6 import QtWidgets
    from test_review_window import _settle

    w, _src, cleaned = _two_layers(qtbot, tmp_path)
    tool = w.restore_tool

    def settle():
        qtbot.waitUntil(lambda: not tool.busy, timeout=60_000)
        _settle(w)

    n0 = len(w.layers[cleaned].points)
    w.canvas.fit()
    QtWidgets.QApplication.processEvents()
    assert tool.restore_in_view(cleaned)
    settle()
    n1 = len(w.layers[cleaned].points)
    assert n1 > n0
    w.select_layer(cleaned)
    w.remove_active_layer()
    settle()
    undo = w.review.act_undo
    assert cleaned not in w.layers and "remove layer" in undo.text()
    undo.trigger()  # the removal
    settle()
    assert cleaned in w.layers and w.active == cleaned
    assert len(w.layers[cleaned].points) == n1
    assert undo.isEnabled() and "restore" in undo.text()
    undo.trigger()  # then the restore made before it
    settle()
    assert len(w.layers[cleaned].points) == n0 and not undo.isEnabled()
    w.close()

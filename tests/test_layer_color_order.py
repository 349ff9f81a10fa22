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

"""Review-window details from operator test h122 (Low): the Gantt cursor stays at the
slider's time when the current proposal changes (L0)."""

import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _sim_pair, _window  # noqa: E402

pytestmark = pytest.mark.gui


def _fused_review(qtbot, tmp_path):
    files = _sim_pair(tmp_path)
    w = _window(qtbot, tmp_path)
    w.load_files(files)
    _settle(w)
    w.layer_list.clearSelection()
    for f in files:
        w.layer_list.item(w.layer_row(w.layer_id(f.name))).setSelected(True)
    w.actions_["fuse"].trigger()
    _settle(w)
    fused = next(lay for lay in w.layers.values() if lay.step == "fuse")
    w.select_layer(fused.id)
    _settle(w)
    return w


def test_gantt_cursor_stays_at_the_slider_time_when_the_proposal_changes(qtbot, tmp_path):
    """With the slider at the layer's start, selecting F0005 put the Gantt's cursor at
    1,518.76 min (the first bar's start) while the slider still read the start."""
    w = _fused_review(qtbot, tmp_path)
    b, tp = w.review.bound, w.time_panel
    tp.set_time(tp._lo)
    moved = 0
    for pid in b.controller.state.proposals["proposal"]:
        b.panel.set_current(pid)
        _settle(w)
        assert b.gantt.time() == pytest.approx(tp.time(), abs=1e-3), pid
        lo = min(b.gantt._span[0])
        moved += lo * 60.0 + b.gantt.t_ref > tp.time() + 1  # bars after the slider's time
    assert moved  # some proposal's bars start after it: the old code moved the cursor
    assert tp.time() == pytest.approx(tp._lo)


def test_window_import_message_counts_blank_lines_as_the_cli(qtbot, tmp_path, capsys):
    """bad.csv: the CLI said "…; 18 quarantined, 2 blank lines skipped", the window's log
    only "…; 18 quarantined". Both now say it with one sentence (words.import_counts)."""
    from wakeline.app.cli import main as cli_main

    src = tmp_path / "blank.csv"
    rows = [f"S1,7,2024-05-01T00:0{k}:00Z,11.5{k},57.6" for k in range(6)]
    src.write_text(
        "sensor,batch,time,lon,lat\n"
        + "\n".join([*rows[:3], "", ",,,,", "S1,7,nonsense,1,2", *rows[3:]])
        + "\n"
    )
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    line = next(t for t in w.log.toPlainText().splitlines() if t.startswith("blank.csv: "))
    assert line.endswith("; 1 quarantined, 2 blank lines skipped"), line
    assert cli_main(["import", str(src), "-o", str(tmp_path / "o.csv")]) == 0
    err = capsys.readouterr().err
    assert "imported 6 rows in 1 track (" in err and "; 1 quarantined, 2 blank lines skipped" in err
    assert line.startswith("blank.csv: 6 rows in 1 track (")


def test_texts_follow_the_language_started_in_and_switched_to(qtbot, tmp_path):
    """h122 L10: in 简体中文 the Review dock's title (its tab), the layer tags "[source]" /
    "[fused]" and the unit "points" stayed English; after a live switch the
    detection-limit paragraph and the Gantt axis "time (min)" did too."""
    w = _fused_review(qtbot, tmp_path)
    b = w.review.bound
    assert w.review.dock.windowTitle() == "Review"
    assert b.gantt.getAxis("bottom").labelText.split(" (0 = ")[0] == "time"
    english = w.params.guidance.text()
    assert english.startswith("Smallest turn found")  # the operator's words (h225 item 13)
    w.set_language("zh_CN")
    try:
        assert w.review.dock.windowTitle() == "审核"
        texts = [w.layer_list.item(r).text() for r in range(w.layer_list.count())]
        assert any(t.endswith("[源数据]") for t in texts), texts
        # the fused layer's name says its kind once (operator test 8, D7: not "已融合 [已融合]")
        fused = [t for t in texts if "已融合" in t]
        assert fused and all(t.count("已融合") == 1 for t in fused), texts
        assert w.params.guidance.text() not in ("", english)
        assert "Smallest" not in w.params.guidance.text()
        assert b.gantt.getAxis("bottom").labelText.split(" (0 = ")[0] == "时间"
        stack, suffixes = list(w.params.root.children()), []
        while stack:
            item = stack.pop()
            stack += item.children()
            if item.opts.get("unit") == "points":
                suffixes.append(item.opts["suffix"])
        assert suffixes and set(suffixes) == {" 点"}, suffixes
    finally:
        w.set_language("en")
    assert w.review.dock.windowTitle() == "Review"
    assert w.params.guidance.text() == english


def test_a_decision_swapped_in_costs_the_gui_thread_no_pass_over_the_tracks(
    qtbot, tmp_path, monkeypatch
):
    """Defect 9 of operator test h150: a decision's layer swapped in made the batch
    table's index (row of each track, first and last times) on the GUI thread, a pass
    over the layer's tracks per key (5,620 on ATD dataset1). It is made in the worker
    with the layer's view; the table holds what a GUI-thread pass would give."""
    import threading

    import numpy as np

    from wakeline.app import models

    w = _fused_review(qtbot, tmp_path)
    b = w.review.bound
    layer = w.layers[b.lid]
    made_on = []
    real = models.table_index

    def spy(df, text, **kwargs):
        made_on.append(threading.current_thread() is threading.main_thread())
        return real(df, text, **kwargs)

    monkeypatch.setattr(models, "table_index", spy)
    monkeypatch.setattr("wakeline.app.layer_view.table_index", spy)
    before = layer.meta.get("review_decisions", 0)
    b.panel.act_accept.trigger()
    _settle(w)
    assert layer.meta.get("review_decisions", 0) == before + 1  # the layer was swapped in
    assert made_on and not any(made_on)  # in the worker only
    m = w.batch_model
    fresh = real(m.frame, m._text)
    assert m._keys == fresh.keys and m.relative == fresh.relative
    for got, want in zip(m._span_s, fresh.span_s, strict=True):
        np.testing.assert_array_equal(got, want)
    assert w.selected_keys() == [] or all(k in m._keys for k in w.selected_keys())


def test_detection_limit_describes_the_active_fused_layer(qtbot, tmp_path):
    """h168 D-gui-2: with the fused layer active the Detection-limit text gave the 1 s
    radar's interval (its source layer's), not the fused track's own sampling."""
    w = _fused_review(qtbot, tmp_path)
    fused = next(lay for lay in w.layers.values() if lay.step == "fuse")
    shown = w.params.guidance.text()
    assert shown.startswith("Smallest turn found")
    w.params.show_guidance(w.views[fused.id].summary)
    assert w.params.guidance.text() == shown
    # the window's log says whose times the fused track took, as the command line does
    # (h168 D-fuse-1)
    assert "; fused on " in w.log.toPlainText() and "time_base weight" in w.log.toPlainText()


def test_a_decisions_table_text_keeps_the_columns_it_did_not_change():
    """A review decision relabels targets: the display text of the summary columns that
    stayed equal is the earlier view's (the same arrays, not formatted again), the row of
    each track too; every column is what formatting it afresh gives."""
    import datetime as dt

    import numpy as np
    import pandas as pd

    from wakeline.app import models
    from wakeline.core.simulate import segments_scene

    pts = segments_scene(seed=2, n_ships=8, area_km=15)
    old = models.batch_summary(pts.assign(target=pts["batch"].astype(str)))
    old_text = models.display_text(old)
    old_index = models.table_index(old, old_text)
    first = str(old["batch"].iloc[0])
    new = models.batch_summary(pts.assign(target=first))  # every track joined to one
    text = models.display_text(new, previous=(old, old_text))
    fresh = models.display_text(new)
    assert set(text) == set(fresh)
    for key in fresh:
        np.testing.assert_array_equal(text[key], fresh[key])
    kept = {k for k in text if text[k] is old_text[k]}
    # target and status made again; the dates kept in the same display zone (session 31)
    assert kept == set(models.KEPT_TEXT) | {"start", "end"}
    from wakeline.app import time_text

    saved = dict(time_text._display)
    try:  # another zone: the dates made again, in it
        time_text.set_display_zone(dt.timezone(dt.timedelta(hours=8)), "UTC+8")
        other = models.display_text(new, previous=(old, old_text))
        assert other["start"] is not old_text["start"]
        np.testing.assert_array_equal(other["start"], models.display_text(new)["start"])
        assert not (other["start"] == old_text["start"]).all()
    finally:
        time_text._display.update(saved)
    index = models.table_index(new, text, previous=(old_text, old_index))
    assert index.keys is old_index.keys and index.keys == models.table_index(new, fresh).keys
    # a decision moving one track: the target text patched in that row, as made afresh
    one = old.copy()
    one.loc[0, "target"] = "X:1"
    text = models.display_text(one, previous=(old, old_text))
    assert text["target"] is not old_text["target"]
    np.testing.assert_array_equal(text["target"], models.display_text(one)["target"])
    assert text["target"][0] == "X:1" and (text["target"][1:] == old_text["target"][1:]).all()
    # a column that changed is formatted again; other tracks: the index made again
    longer = new.assign(points=new["points"] + 1)
    text = models.display_text(longer, previous=(old, old_text))
    assert text["points"] is not old_text["points"]
    np.testing.assert_array_equal(text["points"], models.display_text(longer)["points"])
    fewer = new.iloc[1:].reset_index(drop=True)
    text = models.display_text(fewer, previous=(old, old_text))
    assert not any(text[k] is old_text[k] for k in text)
    index = models.table_index(fewer, text, previous=(old_text, old_index))
    assert index.keys == models.table_index(fewer, models.display_text(fewer)).keys
    assert pd.Series(text["target"]).eq(first).all()

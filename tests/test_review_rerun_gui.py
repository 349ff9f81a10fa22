"""GUI tests of a re-run under review (tester h133, defects 2 and 3, its scripts
undo_chain.py and rerun_assoc.py): Run ▸ Fuse again on the same two layers, and Run ▸
Associate again on the same layer, keep the review — rejected and split pairs stay out,
accepts and hand merges stay in effect, Edit ▸ Undo says why it has nothing to undo,
the log says what was carried, the exported decision log keeps every earlier line and a
reopen restores the same and counts what is in effect."""

import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from test_review_window import _settle, _sim_pair, _window  # noqa: E402

from conftest import real_file  # noqa: E402
from wakeline.core import review as R  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

pytestmark = pytest.mark.gui


def _pairs(st) -> dict:
    return {
        R.pair_key(a, b): str(v) for a, b, v in zip(st.track_a, st.track_b, st.status, strict=True)
    }


def _fuse(w, ids) -> None:
    w.layer_list.clearSelection()
    for lid in ids:
        w.layer_list.item(w.layer_row(lid)).setSelected(True)
    w.actions_["fuse"].trigger()
    _settle(w)


def _apart(st, avoid: list[str]) -> list[str]:
    """Two tracks in two targets, none of them a track of the proposals ``avoid``: a
    hand merge joins them."""
    rows = [st._row[p] for p in avoid]
    busy = {st.track_a[k] for k in rows} | {st.track_b[k] for k in rows}
    out, seen = [], set()
    for t in st.tracks["track"]:
        target = st.target(t)
        if t not in busy and target not in seen and not busy & set(st.members(target)):
            out.append(t)
            seen.add(target)
        if len(out) == 2:
            return out
    raise AssertionError("no two tracks apart")


def _mtad6_pair(_tmp_path) -> list:
    """The tester's files: MTAD scene 6, error 0, AIS and radar (skipped when absent)."""
    return [
        real_file("mtad-dtwcm", "two_sensor", "scene-6_error_0_AIS.csv"),
        real_file("mtad-dtwcm", "two_sensor", "scene-6_error_0_radar.csv"),
    ]


@pytest.mark.parametrize("make_files", [_sim_pair, _mtad6_pair], ids=["sim", "mtad6"])
def test_fuse_again_keeps_the_review_undo_says_why_and_the_log_keeps_it(
    qtbot, tmp_path, make_files
):
    files = make_files(tmp_path)
    w = _window(qtbot, tmp_path)
    w.load_files(files)
    _settle(w)
    ids = [w.layer_id(f.name) for f in files]
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    _fuse(w, ids)
    fused = next(lay for lay in w.session.layers.values() if lay.step == "fuse")
    w.select_layer(fused.id)
    _settle(w)
    c = w.review.bound.controller
    st = c.state
    pids = list(st.proposals["proposal"])
    assert len(pids) >= 3
    pair = {pid: R.pair_key(a, b) for pid, a, b in zip(pids, st.track_a, st.track_b, strict=True)}
    c.accept(pids[0])
    c.reject(pids[1])
    merged = _apart(st, pids[:3])
    c.merge(merged)
    c.split_track(st.track_a[2])
    _settle(w)
    w.review.act_undo.trigger()  # the split, then the merge undone
    w.review.act_undo.trigger()
    w.review.act_redo.trigger()  # the merge again
    _settle(w)
    assert st.target(merged[0]) == st.target(merged[1])
    assert st.status_of(pids[0]) == "accepted" and st.status_of(pids[1]) == "rejected"
    n_rows = len(st.log)
    _fuse(w, ids)  # the tester's "fuse again"
    again = [lay for lay in w.session.layers.values() if lay.step == "fuse"]
    assert [lay.id for lay in again] == [fused.id]
    w.select_layer(fused.id)
    _settle(w)
    b = w.review.bound
    st2 = b.controller.state
    now = _pairs(st2)
    assert pair[pids[1]] not in now  # rejected: kept out
    if pair[pids[0]] in now:  # accepted: still accepted, or an operator link
        assert now[pair[pids[0]]] == "accepted"
    else:
        assert pair[pids[0]] in st2.links
    assert st2.target(merged[0]) == st2.target(merged[1])  # the hand merge, redone, kept
    text = w.log.toPlainText()
    assert "review of the earlier run: 1 pair rejected in an earlier review kept out" in text
    assert not w.review.act_undo.isEnabled()
    assert "nothing since the step ran again" in w.review.act_undo.text()
    assert "not undone by Undo" in w.review.act_undo.toolTip()
    # A decision on the new queue: Undo undoes it, and says what again.
    c2 = b.controller
    pending = [
        p for p, s in zip(st2.proposals["proposal"], st2.status, strict=True) if s == "pending"
    ]
    c2.reject(pending[0])
    _settle(w)
    assert w.review.act_undo.isEnabled() and "reject" in w.review.act_undo.text()
    state = (list(st2.status), set(st2.links))
    w.close()

    w3 = _window(qtbot, tmp_path)
    w3.open_project(proj)
    _settle(w3)
    w3.select_layer(fused.id)
    _settle(w3)
    st3 = w3.review.bound.controller.state
    assert (list(st3.status), set(st3.links)) == state
    in_effect = len(st3.log) - 1  # the re-run's marker is no decision
    first = w3.log.toPlainText().splitlines()[0]
    assert f"{in_effect} review decisions restored (and {n_rows} of earlier runs" in first, first
    out = tmp_path / "log.csv"
    w3.review.sync.export(out, log=True)
    _settle(w3)
    log = pd.read_csv(out, encoding="utf-8-sig")
    assert len(log) == n_rows + len(st3.log)
    assert log["action"].iloc[n_rows] == R.RERUN
    w3.close()


def test_associate_again_keeps_accepts_and_hand_merges(qtbot, tmp_path):
    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    lid = w.layer_id(src.name)
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    w.select_layer(lid)
    w.run_step("associate")
    _settle(w)
    a1 = w.session.find(lid, "associate")
    w.select_layer(a1.id)
    _settle(w)
    c = w.review.bound.controller
    st = c.state
    pids = list(st.proposals["proposal"])
    pair = {pid: R.pair_key(a, b) for pid, a, b in zip(pids, st.track_a, st.track_b, strict=True)}
    c.accept(pids[0])
    c.accept(pids[1])
    c.reject(pids[2])
    c.reject(pids[3])
    lone = _apart(st, pids[:4])
    c.merge([lone[0], lone[-1]])
    _settle(w)
    n_rows = len(st.log)
    w.select_layer(lid)
    _settle(w)
    w.run_step("associate")
    _settle(w)
    line = w.log.toPlainText().splitlines()[-1]
    assert "2 pairs rejected in an earlier review kept out" in line, line
    assert "kept as" in line or "proposed again, accepted" in line, line
    a2 = w.session.find(lid, "associate")
    assert a2.id == a1.id
    w.select_layer(a2.id)
    _settle(w)
    st2 = w.review.bound.controller.state
    now = _pairs(st2)
    for pid in pids[:2]:
        assert now.get(pair[pid]) == "accepted" or pair[pid] in st2.links
    for pid in pids[2:4]:
        assert pair[pid] not in now
    assert st2.target(lone[0]) == st2.target(lone[-1])
    assert not w.review.act_undo.isEnabled()
    assert "nothing since the step ran again" in w.review.act_undo.text()
    state = (list(st2.status), set(st2.links))
    in_effect = len(st2.log) - 1
    w.close()

    w3 = _window(qtbot, tmp_path)
    w3.open_project(proj)
    _settle(w3)
    first = w3.log.toPlainText().splitlines()[0]
    assert f"{in_effect} review decisions restored (and {n_rows} of earlier runs" in first, first
    w3.select_layer(a1.id)
    _settle(w3)
    st3 = w3.review.bound.controller.state
    assert (list(st3.status), set(st3.links)) == state
    w3.close()


def test_the_re_run_line_in_the_zh_cn_log_is_chinese(qtbot, tmp_path):
    """The re-run's words (kept out, carried over) are the core's phrases (h136): in the
    zh_CN window the log line of Associate run again carries none of their English."""
    from PySide6 import QtWidgets
    from test_translations import zh_table

    from wakeline.app import i18n
    from wakeline.core.words import CONTEXT

    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.set_language("zh_CN")
    try:
        w.load_files([src])
        _settle(w)
        lid = w.layer_id(src.name)
        w.select_layer(lid)
        w.run_step("associate")
        _settle(w)
        a1 = w.session.find(lid, "associate")
        w.select_layer(a1.id)
        _settle(w)
        c = w.review.bound.controller
        pids = list(c.state.proposals["proposal"])
        c.accept(pids[0])
        c.reject(pids[1])
        _settle(w)
        w.select_layer(lid)
        _settle(w)
        w.run_step("associate")
        _settle(w)
        line = w.log.toPlainText().splitlines()[-1]
        zh = zh_table()
        assert zh[(CONTEXT, "; review of the earlier run: {carry}")].split("{")[0] in line, line
        for english in ("review of the earlier run", "kept out", "proposed again", "pair"):
            assert english not in line, line
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_fuse_again_with_the_layers_in_another_order_keeps_the_review(qtbot, tmp_path):
    """The same two layers fused again, selected in the other order (the Layers list's
    rows, moved): the fused layer is re-run in its order, not a second layer made, and
    its review is kept."""
    from wakeline.app.review_sync import fuse_selected

    files = _sim_pair(tmp_path)
    w = _window(qtbot, tmp_path)
    w.load_files(files)
    _settle(w)
    ids = [w.layer_id(f.name) for f in files]
    _fuse(w, ids)
    fused = next(lay for lay in w.session.layers.values() if lay.step == "fuse")
    w.select_layer(fused.id)
    _settle(w)
    c = w.review.bound.controller
    st = c.state
    pid = st.proposals["proposal"].iloc[0]
    rejected = R.pair_key(st.track_a[0], st.track_b[0])
    c.reject(pid)
    _settle(w)
    fuse_selected(w, ids[::-1])
    _settle(w)
    again = [lay for lay in w.session.layers.values() if lay.step == "fuse"]
    assert [lay.id for lay in again] == [fused.id]
    assert w.session.layers[fused.id].inputs == ids
    w.select_layer(fused.id)
    _settle(w)
    assert rejected not in _pairs(w.review.bound.controller.state)
    assert "1 pair rejected in an earlier review kept out" in w.log.toPlainText()
    w.close()

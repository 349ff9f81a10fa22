"""Joining two tracks by hand where no proposal links them (operator test 5, D-review-7):
the core's command and its inverse, the overlap rule, the split that cuts it again, the
replay from the decision log and from a decisions table, ``wakeline review`` without
proposals, and the review of an associated layer whose step proposed nothing."""

import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main as cli_main
from wakeline.core import review as R
from wakeline.core.errors import InputError
from wakeline.core.io import write_points
from wakeline.core.review_join import empty_proposals, join_tracks, overlap_problem, overlaps

T0 = pd.Timestamp("2024-08-02T10:00:00Z")


def _line(sensor, batch, start_s, end_s, lon0, lat0, step_s=60):
    t = np.arange(start_s, end_s + 1, step_s, dtype=float)
    return pd.DataFrame(
        {
            "sensor": sensor,
            "batch": batch,
            "time": T0 + pd.to_timedelta(t, unit="s"),
            "lon": lon0 + 1e-4 * (t - start_s) / 60,
            "lat": lat0 + 0.0 * t,
        }
    )


@pytest.fixture
def typo_points():
    """Ship 1 under MMSI 237000001 until 12:00 and 237000010 after (typed wrong), ship 2
    all the time, and a radar track of ship 1 over the whole day (another sensor)."""
    return pd.concat(
        [
            _line("S1", "237000001", 0, 7200, 23.50, 38.00),
            _line("S1", "237000010", 7260, 14400, 23.5121, 38.00),
            _line("S1", "237000002", 0, 14400, 23.70, 37.90),
            _line("R1", "7", 0, 14400, 23.50, 38.0005),
        ],
        ignore_index=True,
    )


@pytest.fixture
def state(typo_points):
    return R.ReviewState(R.track_table(typo_points), empty_proposals())


A, B, OTHER, RADAR = "S1:237000001", "S1:237000010", "S1:237000002", "R1:7"


def test_join_without_a_proposal_and_its_inverse(state):
    assert len(state.proposals) == 0
    change = join_tracks(state, [A, B])
    assert change.action == "merge" and change.links_added == {R.pair_key(A, B)}
    state.apply(change)
    assert state.target(A) == state.target(B) == A  # named after the earliest track
    assert state.targets()["target"].nunique() == 3
    state.apply(change.inverse())
    assert state.target(B) == B and not state.links
    state.apply(change)  # redo
    assert state.target(B) == A
    split = R.split_target(state, A)  # the split of a hand join cuts its link
    assert split.links_removed == {R.pair_key(A, B)}
    state.apply(split)
    assert state.target(B) == B
    # joined already: nothing to do (an empty change, nothing logged by the window)
    state.apply(join_tracks(state, [A, B]))
    assert join_tracks(state, [B, A]).empty


def test_one_sensor_overlapping_in_time_is_refused_unless_allowed(state):
    assert overlaps(state, [A, B]) == []
    problem = overlap_problem(state, [A, OTHER])
    assert "S1:237000001 and S1:237000002 are both tracks of sensor S1" in problem
    assert "2024-08-02 10:00:00 to 2024-08-02 12:00:00 UTC (2 h 00 min)" in problem
    with pytest.raises(InputError, match="join refused: S1:237000001 and S1:237000002"):
        join_tracks(state, [A, OTHER])
    state.apply(join_tracks(state, [A, OTHER], overlap_ok=True))
    assert state.target(OTHER) == state.target(A)
    # Two sensors overlap by nature (radar and AIS of one ship): no question asked.
    assert overlap_problem(state, [B, RADAR]) == ""
    # A join checks every member of the targets it joins: B overlaps OTHER (A's target now).
    assert overlaps(state, [B, A])[0][:2] == (B, OTHER) or overlaps(state, [B, A])[0][:2] == (
        OTHER,
        B,
    )
    with pytest.raises(InputError, match="select two tracks"):
        join_tracks(state, [A, A])
    with pytest.raises(InputError, match="no track"):
        join_tracks(state, [A, "S1:999"])


def test_the_log_and_a_decisions_table_replay_the_join(state, typo_points):
    state.apply(join_tracks(state, [A, B]))
    state.apply(R.split_target(state, A))
    state.apply(join_tracks(state, [B, A]))
    undo_me = join_tracks(state, [A, OTHER], overlap_ok=True)
    state.apply(undo_me)
    state.apply(undo_me.inverse())
    log = state.log_table()
    again = R.replay_log(R.ReviewState(R.track_table(typo_points), empty_proposals()), log)
    assert again.targets().equals(state.targets())
    assert again.links == state.links == {R.pair_key(A, B)}
    table = pd.DataFrame(
        [{"decision": "join", "sensor_a": "S1", "batch_a": "237000001", "sensor_b": "S1",
          "batch_b": "237000010"}]
    )  # fmt: skip
    third = R.apply_decisions(R.ReviewState(R.track_table(typo_points), empty_proposals()), table)
    assert third.targets().equals(state.targets())


def test_cli_review_without_proposals_replays_a_hand_join(tmp_path, typo_points, state):
    pts = tmp_path / "day.csv"
    write_points(typo_points, pts)
    dec = tmp_path / "d.csv"
    dec.write_text("decision,sensor_a,batch_a,sensor_b,batch_b\njoin,S1,237000001,S1,237000010\n")
    out, log = tmp_path / "out.csv", tmp_path / "log.csv"
    args = ["review", str(pts), "-o", str(out), "--decisions", str(dec), "--log", str(log)]
    assert cli_main(args) == 0
    got = pd.read_csv(out, dtype=str)
    assert got.groupby("batch")["target"].first().to_dict() == {
        "237000001": A,
        "237000010": A,
        "237000002": OTHER,
        "7": RADAR,
    }
    # The log written (as the window's Review ▸ Export decision log) replays the same.
    out2 = tmp_path / "out2.csv"
    assert cli_main(["review", str(pts), "-o", str(out2), "--decisions", str(log)]) == 0
    assert pd.read_csv(out2, dtype=str)["target"].equals(got["target"])
    # The window's own log (a join, undone, joined again) too.
    state.apply(join_tracks(state, [A, B]))
    state.apply(R.split_target(state, A))
    state.apply(join_tracks(state, [B, A]))
    wlog = tmp_path / "wlog.csv"
    state.log_table().to_csv(wlog, index=False)
    out3 = tmp_path / "out3.csv"
    assert cli_main(["review", str(pts), "-o", str(out3), "--decisions", str(wlog)]) == 0
    assert pd.read_csv(out3, dtype=str)["target"].equals(got["target"])


def test_an_associated_layer_without_proposals_is_reviewable(typo_points):
    from wakeline.core.associate import LinkParams
    from wakeline.core.pipeline import step_associate
    from wakeline.core.review_session import (
        bind,
        decision_counts,
        proposals_of,
        queue_key,
        review_bindable,
        reviewable,
    )
    from wakeline.core.review_store import decision_row
    from wakeline.core.session import Session

    ais = typo_points[typo_points["sensor"] == "S1"].reset_index(drop=True)
    session = Session()
    src = session.add_layer("day.csv", "source", ais)
    new = step_associate(ais, LinkParams()).layers[0]
    lay = session.add_layer(
        "day.csv · associated",
        "associated",
        new.points,
        parent=src.id,
        step="associate",
        role=new.suffix,
        tables=new.tables,
    )
    assert proposals_of(lay) is None  # mmsi_apart: the two MMSIs are not proposed
    assert reviewable(lay) and not reviewable(src)
    state, _points = bind(session, lay)
    change = join_tracks(state, [A, B])
    state.apply(change)
    session.decisions.append(decision_row(queue_key(lay), change, state.log[-1]))
    again, _ = bind(session, lay)  # a reopen replays the join
    assert again.target(B) == A and again.links == {R.pair_key(A, B)}
    assert decision_counts([src, lay], session.decisions) == (1, 0)
    # Its source removed, the layer keeps the points its hand joins were made on.
    assert review_bindable(session, lay)
    session.remove_layer(src.id)
    assert "input " + src.id in lay.tables and review_bindable(session, lay)
    third, _ = bind(session, lay)
    assert third.target(B) == A
    # A layer that lost its input before (nothing kept) has no review, not an error.
    lay.tables = {k: v for k, v in lay.tables.items() if k != "input " + src.id}
    assert reviewable(lay) and not review_bindable(session, lay)


@pytest.mark.gui
def test_join_selected_tracks_in_the_window_undo_redo_and_reopen(qtbot, tmp_path, typo_points):
    """GUI test: the Saronic-like day with an MMSI typed wrong from noon: Run ▸ Associate
    proposes nothing (mmsi_apart); the two tracks selected in the batch table are joined
    by Review ▸ Join selected tracks, undone (Ctrl+Z), redone, saved at once; a reopened
    project shows the join; the split cuts it again; an overlapping pair of one sensor
    asks first."""
    pytest.importorskip("pytestqt")
    from test_review_window import _settle, _window

    from wakeline.core.review_session import proposals_of

    src = tmp_path / "day.csv"
    write_points(typo_points[typo_points["sensor"] == "S1"], src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    proj = tmp_path / "day.wakeline"
    w.save_project(proj)
    _settle(w)
    w.run_step("associate")
    _settle(w)
    assoc = w.session.find(w.layer_id(src.name), "associate")
    assert proposals_of(assoc) is None
    w.select_layer(assoc.id)
    _settle(w)
    b = w.review.bound
    assert b is not None and b.lid == assoc.id  # an empty queue binds: joins by hand
    for act in w.review.review_actions.values():  # the queue's keys on an empty queue
        act.trigger()
    _settle(w)
    assert w.session.decisions == []
    join = w.review.join
    w.select_tracks([("S1", "237000001"), ("S1", "237000010")])
    assert join.actions["join"].shortcut().toString() == "Ctrl+J"
    join.actions["join"].trigger()
    _settle(w)
    st = b.controller.state
    assert st.target(B) == A and len(w.session.decisions) == 1
    # The queue (no proposal) says what was joined by hand.
    assert b.panel.counts.text() == (
        "0 proposals: 0 pending, 0 accepted, 0 rejected, 0 split; "
        "1 joined by hand: S1:237000001 + S1:237000010"
    )
    assert w.session.decisions[-1]["action"] == "merge"
    assert set(w.session.layers[assoc.id].points.groupby("batch")["target"].first()) == {A, OTHER}
    w.review.act_undo.trigger()
    _settle(w)
    assert st.target(B) == B and len(w.session.decisions) == 2
    assert "joined by hand" not in b.panel.counts.text()
    w.review.act_redo.trigger()
    _settle(w)
    assert st.target(B) == A and len(w.session.decisions) == 3
    # One sensor, overlapping times: the operator is asked; "No" joins nothing.
    asked = []
    join.ask_overlap = lambda problem: asked.append(problem) or False
    w.select_tracks([("S1", "237000001"), ("S1", "237000002")])
    assert not join.join_selected()
    assert "both tracks of sensor S1" in asked[0] and st.target(OTHER) == OTHER
    w.project.flush()
    w.close()

    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    lay = w2.session.find(w2.layer_id(src.name), "associate")
    w2.select_layer(lay.id)
    _settle(w2)
    b2 = w2.review.bound
    assert b2 is not None and b2.controller.state.target(B) == A
    assert b2.controller.state.links == {R.pair_key(A, B)}
    w2.select_tracks([("S1", "237000010")])
    assert w2.review.join.split_selected()
    _settle(w2)
    assert b2.controller.state.target(B) == B
    w2.review.act_undo.trigger()
    _settle(w2)
    assert b2.controller.state.target(B) == A
    w2.close()


@pytest.mark.real
def test_the_saronic_day_with_an_mmsi_typed_wrong_is_joined_by_hand(tmp_path):
    """Operator test 5's file (h181 make_inputs.py): the Saronic AIS of 2024-08-02 with
    vessel 1's MMSI typed 237000010 from 12:00. Associate keeps the two MMSIs apart and
    proposes nothing; the hand join makes 5 targets of the 6 tracks, no overlap to ask
    about, and ``wakeline review`` without proposals gives the same targets."""
    from conftest import saronic_points
    from wakeline.core.associate import LinkParams
    from wakeline.core.pipeline import step_associate

    pts = saronic_points("S1")
    day = pts[(pts["time"] >= "2024-08-02") & (pts["time"] < "2024-08-03")].copy()
    day["batch"] = (237000000 + day["batch"].astype(int)).astype(str)
    typo = (day["batch"] == "237000001") & (day["time"] >= "2024-08-02 12:00")
    day.loc[typo, "batch"] = "237000010"
    day = day.reset_index(drop=True)
    res = step_associate(day, LinkParams())
    assert len(res.tables["proposals"]) == 0
    assert res.report["mmsi_apart_pairs"] == 1  # the pair the operator joins
    state = R.ReviewState(R.track_table(day), empty_proposals())
    assert len(state.tracks) == 6 and overlap_problem(state, [A, B]) == ""
    state.apply(join_tracks(state, [A, B]))
    assert state.targets()["target"].nunique() == 5 and state.target(B) == A
    src = tmp_path / "day.csv"
    write_points(day, src)
    dec = tmp_path / "d.csv"
    dec.write_text("decision,sensor_a,batch_a,sensor_b,batch_b\njoin,S1,237000001,S1,237000010\n")
    out = tmp_path / "out.csv"
    assert cli_main(["review", str(src), "-o", str(out), "--decisions", str(dec)]) == 0
    got = pd.read_csv(out, dtype=str)
    assert (
        got.groupby("batch")["target"].first().to_dict()
        == state.targets().set_index("batch")["target"].to_dict()
    )


def test_a_rerun_that_proposes_nothing_again_keeps_the_hand_join(typo_points):
    """Associate run again (a parameter changed) on the layer whose tracks were joined by
    hand: the run proposes nothing again, and the join is carried as an operator link
    (it was dropped as 'a track is gone' when the run had no proposal)."""
    from wakeline.core.pipeline import STEPS
    from wakeline.core.review_session import bind, queue_key
    from wakeline.core.review_store import decision_row
    from wakeline.core.session import Session

    ais = typo_points[typo_points["sensor"] == "S1"].reset_index(drop=True)
    s = Session()
    src = s.add_layer("day.csv", "source", ais)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)
    change = st.apply(join_tracks(st, [A, B]))
    s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    res = s.run_step(src.id, "associate")
    assert res.carry.linked == 1 and res.carry.gone == 0
    assert "kept as an operator link" in STEPS["associate"].summary(res)
    (new,) = s.apply_result(src.id, res)
    again, _ = bind(s, new)
    assert len(again.proposals) == 0 and again.target(B) == A


def test_the_overlap_message_reads_in_chinese(state):
    from wakeline.app.core_text import translate

    with pytest.raises(InputError) as err:
        join_tracks(state, [A, OTHER])
    zh = translate(str(err.value), "zh_CN")
    assert zh.startswith("拒绝合并：S1:237000001 与 S1:237000002 都是传感器 S1 的航迹")
    assert "2024-08-02 10:00:00 至 2024-08-02 12:00:00 UTC 时间重叠（2 h 00 min）：" in zh
    assert "another" not in zh and "one sensor" not in zh


def _fused_window(qtbot, tmp_path, language="en"):
    """The simulated radar/AIS pair fused across layers in the window, the fused layer
    active: (window, fused layer, its review's state)."""
    from test_review_window import _settle, _sim_pair, _window

    files = _sim_pair(tmp_path)
    w = _window(qtbot, tmp_path)
    if language != "en":
        w.set_language(language)
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
    return w, fused, w.review.bound.controller.state


def _members(layer, key):
    pts = layer.points
    rows = (pts["sensor"].astype(str) == key[0]) & (pts["batch"].astype(str) == key[1])
    return pts.loc[rows, "members"].astype(str).iloc[0].split("+")


@pytest.mark.parametrize("language", ["en", "zh_CN"])
def test_join_and_split_from_a_fused_layers_rows(qtbot, tmp_path, language):
    """Operator test 8, D2: the batch table of a fused layer lists fused targets (sensor
    ``fused``), not their member tracks. Split selected tracks' target on a fused row cuts
    that target into its member tracks; Ctrl+J on two fused rows joins their targets;
    Ctrl+Z undoes each. Never the internal "no track 'fused:…'" in the log."""
    pytest.importorskip("pytestqt")
    from test_review_window import _settle

    w, fused, st = _fused_window(qtbot, tmp_path, language)
    join = w.review.join
    keys = w.batch_model.frame[["sensor", "batch"]].astype(str).values.tolist()
    assert keys and all(s == "fused" for s, _ in keys)
    pair = next(
        tuple(k)
        for k in keys
        if "+"
        in fused.points.loc[fused.points["batch"].astype(str) == k[1], "members"]
        .astype(str)
        .iloc[0]
    )
    members = _members(fused, pair)
    assert len({st.target(m) for m in members}) == 1  # one fused target of two sensors
    n_targets = st.targets()["target"].nunique()

    # Split: the fused target falls back into its member tracks.
    w.select_tracks([pair])
    assert join.split_selected()
    _settle(w)
    assert len({st.target(m) for m in members}) == len(members)
    assert st.targets()["target"].nunique() == n_targets + len(members) - 1
    w.review.act_undo.trigger()
    _settle(w)
    assert len({st.target(m) for m in members}) == 1

    # Join: two fused rows (targets) become one target; the fused layer shows it.
    fused = w.layers[fused.id]
    keys = w.batch_model.frame[["sensor", "batch"]].astype(str).values.tolist()
    two = [tuple(k) for k in keys[:2]]
    tracks = [m for k in two for m in _members(fused, k)]
    assert len({st.target(m) for m in tracks}) == 2
    join.ask_overlap = lambda problem: True  # two ships' radar tracks may overlap in time
    w.select_tracks(two)
    assert join.actions["join"].shortcut().toString() == "Ctrl+J"
    join.actions["join"].trigger()
    _settle(w)
    assert len({st.target(m) for m in tracks}) == 1
    assert st.targets()["target"].nunique() == n_targets - 1
    assert w.session.decisions[-1]["action"] == "merge"
    fused = w.layers[fused.id]
    assert fused.points["batch"].nunique() == n_targets - 1
    w.review.act_undo.trigger()
    _settle(w)
    assert len({st.target(m) for m in tracks}) == 2
    log = w.log.toPlainText()
    assert "no track" not in log and "fused:" not in log
    w.close()

"""A re-run of a reviewed step (Associate on one layer, Fuse across layers) keeps the
review (tester h133, defects 2 and 3): rejected and split pairs stay out, accepted pairs
proposed again stay accepted, accepted pairs no longer proposed and hand merges are kept
as operator links (counted when a track is gone), the decision log keeps every earlier
line with a ``re-run`` marker, and a reopen restores the same and counts what is in
effect."""

import pandas as pd
import pytest

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.pipeline import STEPS
from wakeline.core.project import load_project, save_project
from wakeline.core.review_session import (
    bind,
    decision_counts,
    fuse_names,
    input_points,
    queue_key,
)
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session


def _do(s: Session, lay, st: R.ReviewState, change: R.Change) -> R.Change:
    """Apply ``change`` and store it as the window does."""
    st.apply(change)
    s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    return change


def _pairs(st: R.ReviewState) -> dict[tuple[str, str], str]:
    return {
        R.pair_key(a, b): str(v) for a, b, v in zip(st.track_a, st.track_b, st.status, strict=True)
    }


def _review(s: Session, lay) -> dict:
    """Accept, reject, split, a hand merge, a reject undone: what the operator did, and
    the pairs each left (track labels)."""
    st, _ = bind(s, lay)
    p = st.proposals
    pair = {
        pid: R.pair_key(a, b)
        for pid, a, b in zip(p["proposal"], st.track_a, st.track_b, strict=True)
    }
    pids = list(p["proposal"])
    _do(s, lay, st, R.accept(st, pids[0]))
    _do(s, lay, st, R.reject(st, pids[1]))
    # A reject taken back (undo): the pair is proposed again, pending.
    undone = _do(s, lay, st, R.reject(st, pids[3]))
    _do(s, lay, st, undone.inverse())
    # A track split off: every pair the split cut stays out.
    cut = _do(s, lay, st, R.split_track(st, st.track_a[2]))
    split = {pair[pid] for pid in cut.status_after}
    # A hand merge of two tracks in two targets, not a proposed pair.
    tg = st.targets().set_index("track")["target"]
    lone = [t for t in tg.index if t not in set(cut.tracks) and (tg == tg[t]).sum() == 1]
    assert len(lone) >= 2, "the scene needs two unpaired tracks"
    merged = _do(s, lay, st, R.merge(st, lone[:2]))
    assert merged.links_added
    return {
        "state": st,
        "accepted": pair[pids[0]],
        "rejected": pair[pids[1]],
        "undone": pair[pids[3]],
        "split": split,
        "merged": R.pair_key(*lone[:2]),
        "rows": len(s.decisions),
    }


def _check_rerun(s: Session, lay, done: dict, res) -> R.ReviewState:
    """The re-run's queue as the operator expects it; returns its state."""
    assert res.carry is not None
    old_key = queue_key(lay)  # the layer is replaced in place
    (lay2,) = s.apply_result(lay.parent, res, None, inputs=lay.inputs)
    st, _ = bind(s, lay2)
    now = _pairs(st)
    assert done["rejected"] not in now
    assert not done["split"] & set(now)
    assert now.get(done["undone"], "pending") == "pending"
    if done["accepted"] in now:
        assert now[done["accepted"]] == "accepted"
    else:
        assert done["accepted"] in st.links
    a, b = done["merged"]
    assert st.target(a) == st.target(b)
    assert res.carry.linked >= 1 and res.carry.gone == 0
    # The log: every earlier line, the marker, then the carried decisions.
    log = st.log_table()
    assert len(st.history) == done["rows"]
    assert list(log["action"][: done["rows"]]) == [e.action for e in done["state"].log]
    mark = log.iloc[done["rows"]]
    assert mark["action"] == R.RERUN and mark["before"] == old_key
    assert "kept out" in mark["after"] and "kept as" in mark["after"]
    text = STEPS[lay2.step].summary(res)
    assert "review of the earlier run" in text and "kept as" in text, text
    # The log replays (wakeline review --log) from its marker to the same targets.
    again = R.replay_log(R.ReviewState(st.tracks, st.proposals), log)
    assert (again.target_of_track() == st.target_of_track()).all()
    return st


def _check_reopen(s: Session, lid: str, st: R.ReviewState, tmp_path) -> None:
    save_project(s, tmp_path / "p.wakeline")
    proj = load_project(tmp_path / "p.wakeline")
    back = proj.to_session()
    st2, _ = bind(back, back.layers[lid])
    assert list(st2.status) == list(st.status) and st2.links == st.links
    assert (st2.target_of_track() == st.target_of_track()).all()
    assert len(st2.log_table()) == len(st.log_table())
    now, earlier = decision_counts(proj.layers, proj.decisions)
    assert now == len(st.log) - 1  # the marker is no decision
    assert earlier == len(st.history)


def test_a_rerun_of_associate_keeps_every_decision_that_still_applies(tmp_path):
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    done = _review(s, lay)
    res = s.run_step(src.id, "associate")
    assert res.carry.rejected == 1 and res.carry.split == len(done["split"] - {done["rejected"]})
    st = _check_rerun(s, lay, done, res)
    # A decision on the new queue, then a third run: the log keeps growing.
    lay2 = s.layers[lay.id]
    _do(s, lay2, st, R.reject(st, st.proposals["proposal"].iloc[-1]))
    _check_reopen(s, lay.id, st, tmp_path)
    third = s.run_step(src.id, "associate")
    (lay3,) = s.apply_result(src.id, third)
    st3, _ = bind(s, lay3)
    assert len(st3.history) == len(st.history) + len(st.log)
    assert done["rejected"] not in _pairs(st3) and not done["split"] & set(_pairs(st3))
    a, b = done["merged"]
    assert st3.target(a) == st3.target(b)


def test_decisions_whose_track_is_gone_are_counted(tmp_path):
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    done = _review(s, lay)
    gone = done["merged"][0].split(":", 1)[1]
    s.replace_points(src.id, pts[pts["batch"].astype(str) != gone].reset_index(drop=True))
    res = s.run_step(src.id, "associate")
    assert res.carry.gone == 1
    s.apply_result(src.id, res)
    assert "1 decision no longer applies (a track is gone)" in STEPS["associate"].summary(res)


@pytest.fixture(scope="module")
def two_files():
    pts = simulate.demo_scene(seed=7)
    t = pd.to_datetime(pts["time"])
    pts = pts[t < t.min() + pd.Timedelta("30min")]
    return {s: part.assign(sensor="S1").reset_index(drop=True) for s, part in pts.groupby("sensor")}


def _fuse(s: Session, ids: list[str]):
    named = list(zip(fuse_names(s, ids), [s.layers[i].points for i in ids], strict=True))
    points = R.combine_sources(named)
    return s.run_step(ids, "fuse", STEPS["fuse"].defaults(), points=points)


def test_a_rerun_of_fuse_across_layers_keeps_every_decision_that_still_applies(two_files, tmp_path):
    s = Session()
    a = s.add_layer("x_AIS.csv", "source", two_files["AIS"])
    r = s.add_layer("x_radar.csv", "source", two_files["R1"])
    ids = [a.id, r.id]
    (lay,) = s.apply_result(a.id, _fuse(s, ids), STEPS["fuse"].defaults(), inputs=ids)
    assert not _fuse(s, ids).carry.reviewed  # nothing reviewed yet: nothing to carry
    done = _review(s, lay)
    res = _fuse(s, ids)
    assert res.report["rejected_kept_out"] == 1
    st = _check_rerun(s, lay, done, res)
    # The fused layer follows the decisions through the same points as before.
    assert len(input_points(s, s.layers[lay.id]))
    _check_reopen(s, lay.id, st, tmp_path)


def test_the_carry_and_kept_out_words_are_phrases_with_zh_cn_entries():
    """h136's summaries are phrases the window translates: a re-run's words (what it kept
    out, carried and dropped) are too, so the zh_CN log has no English piece of them;
    the English (what the command line prints) is unchanged."""
    from test_translations import zh_table

    from wakeline.core.pipeline import StepResult
    from wakeline.core.review_session import Carry
    from wakeline.core.words import CONTEXT, render

    table = zh_table()

    def zh(t: str) -> str | None:
        return table.get((CONTEXT, t))

    for n in (1, 3):
        carry = Carry("L3", "L3@t#x", 0, [], n, n, n, n, n, n)
        english = carry.text()
        plural = "s" if n > 1 else ""
        assert english.startswith(f"{n} pair{plural} rejected in an earlier review kept out; ")
        assert "operator link" in english and "a track is gone" in english
        chinese = render(carry.text(), zh)
        assert chinese != english
        assert not any(w in chinese for w in ("pair", "kept", "decision", "operator", "; "))
        rep = {
            "tracks": 4,
            "targets": 2,
            "pairs_chosen": 2,
            "candidate_pairs": 3,
            "method": "optimal",
        }
        res = StepResult("associate", [], rep, carry=carry)
        line = STEPS["associate"].summary(res)
        assert f"; review of the earlier run: {english}" in line
        assert "review of the earlier run" not in render(line, zh)
    assert render(Carry("L3", "q", 0).text(), zh) == zh("no decision to carry over")


def test_fusing_the_same_layers_in_another_order_replaces_the_layer_and_keeps_the_review(
    two_files,
):
    """Fuse's output does not depend on the order of its inputs (points sorted by sensor
    and track first), so the same layers selected in another order (Layers list rows)
    re-run the layer made from them, in its order, review kept."""
    s = Session()
    a = s.add_layer("x_AIS.csv", "source", two_files["AIS"])
    r = s.add_layer("x_radar.csv", "source", two_files["R1"])
    ids = [a.id, r.id]
    first = _fuse(s, ids)
    (lay,) = s.apply_result(a.id, first, STEPS["fuse"].defaults(), inputs=ids)
    other = _fuse(s, ids[::-1])  # nothing reviewed yet: the same result either way
    for key in ("points", "pairs", "proposals"):
        assert other.tables[key].reset_index(drop=True).equals(first.tables[key])
    done = _review(s, lay)
    res = _fuse(s, ids[::-1])
    assert res.carry is not None and res.carry.old == lay.id
    assert res.report["rejected_kept_out"] == 1
    made = s.apply_result(r.id, res, STEPS["fuse"].defaults(), inputs=ids[::-1])
    assert [m.id for m in made] == [lay.id]
    assert [x.id for x in s.layers.values() if x.step == "fuse"] == [lay.id]
    assert s.layers[lay.id].inputs == ids and s.layers[lay.id].parent == a.id
    st, _ = bind(s, s.layers[lay.id])
    now = _pairs(st)
    assert done["rejected"] not in now and not done["split"] & set(now)
    a_, b_ = done["merged"]
    assert st.target(a_) == st.target(b_)
    assert s.rerun_inputs(ids[::-1]) == ids


def test_a_pipeline_rerun_keeps_rejected_and_split_pairs_out():
    """A pipeline whose Associate stage replaces a reviewed layer keeps its review as a
    run of Associate alone does: rejected and split pairs stay out (they came back as
    pending), accepted pairs and hand merges carried."""
    from wakeline.core.pipeline import Pipeline

    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    pipe = Pipeline(
        (("clean", STEPS["clean"].defaults()), ("associate", STEPS["associate"].defaults()))
    )
    made = s.apply_result(src.id, s.run_pipeline(src.id, pipe))
    (lay,) = [m for m in made if m.step == "associate"]
    assert (
        lay.params["associate"]["max_gap_s"] == STEPS["associate"].defaults()["associate"].max_gap_s
    )
    done = _review(s, lay)
    res = s.run_pipeline(src.id, pipe)
    stage = res.stages[-1]
    assert stage.report["rejected_kept_out"] == 1
    assert stage.carry is not None and stage.carry.old == lay.id
    assert stage.carry.rejected == 1
    assert stage.carry.split == len(done["split"] - {done["rejected"]})
    again = s.apply_result(src.id, res)
    assert lay.id in [m.id for m in again]
    assert len([x for x in s.layers.values() if x.step == "associate"]) == 1
    st, _ = bind(s, s.layers[lay.id])
    now = _pairs(st)
    assert done["rejected"] not in now
    assert not done["split"] & set(now)
    if done["accepted"] in now:
        assert now[done["accepted"]] == "accepted"
    else:
        assert done["accepted"] in st.links
    a, b = done["merged"]
    assert st.target(a) == st.target(b)
    # The same stage result as Associate run alone on the cleaned layer.
    alone = s.run_step(lay.parent, "associate")
    assert alone.tables["proposals"].equals(stage.tables["proposals"])


def test_a_pipeline_with_compress_associates_the_cleaned_tracks_and_keeps_the_review():
    """Operator test 7, D5: clean → compress → associate associates the cleaned tracks
    (whole), not compress's few points per track; the compressed layer is made beside
    it from the same cleaned layer. A re-run keeps the review (the associated layer is
    found again under the cleaned layer). ``batch``'s and ``render``'s chains agree."""
    from wakeline.core.pipeline import Pipeline, stage_input

    names = ("clean", "compress", "associate")
    assert [stage_input(names, k) for k in range(3)] == [-1, 0, 0]
    assert stage_input(("compress", "associate"), 1) == -1  # no clean: the input whole
    assert stage_input(("clean", "maneuvers", "associate"), 2) == 1  # maneuvers keeps all
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    pipe = Pipeline(tuple((n, STEPS[n].defaults()) for n in names))
    res = s.run_pipeline(src.id, pipe)
    made = s.apply_result(src.id, res)
    by_role = {m.role: m for m in made}
    cleaned, comp, lay = by_role["cleaned"], by_role["compressed"], by_role["associated"]
    assert comp.parent == cleaned.id and lay.parent == cleaned.id
    assert len(comp.points) < len(cleaned.points) == len(lay.points)
    assert lay.name == "seg.csv · cleaned · associated"
    alone = s.run_step(cleaned.id, "associate")
    assert alone.tables["proposals"].equals(res.stages[-1].tables["proposals"])
    # the same as a pipeline without compress (the doc's scene: 9 targets, not 10)
    short = Pipeline(tuple((n, STEPS[n].defaults()) for n in ("clean", "associate"))).run(pts)
    assert short.stages[-1].tables["proposals"].equals(res.stages[-1].tables["proposals"])
    done = _review(s, lay)
    again = s.run_pipeline(src.id, pipe)
    assert again.stages[-1].carry is not None and again.stages[-1].carry.old == lay.id
    assert again.stages[-1].report["rejected_kept_out"] == 1
    s.apply_result(src.id, again)
    assert len([x for x in s.layers.values() if x.step == "associate"]) == 1
    st, _ = bind(s, s.layers[lay.id])
    assert done["rejected"] not in _pairs(st)

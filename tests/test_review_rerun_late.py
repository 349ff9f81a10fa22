"""Decisions made while a re-run of a reviewed step computes (the run in a worker, the
operator still reviewing the old layer) are carried into the new queue exactly as the
decisions made before the run: the new result is reconciled with the decisions present
when it is swapped in (``Session.apply_result``), not with those its worker read.
Decisions that change the pairs the run keeps out (a reject or split, or one taken
back) make the result stale: nothing is applied (``StaleResult``) and the step runs
again. Headless: the worker is simulated by computing the step, then deciding, then
swapping in; each case is compared with the same decisions made before the run."""

import pandas as pd
import pytest
from test_review_rerun_carry import _do, _fuse, _pairs, _review

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.errors import StaleResult
from wakeline.core.pipeline import STEPS, Pipeline
from wakeline.core.project import load_project, save_project
from wakeline.core.review_session import bind, queue_key
from wakeline.core.session import Session


@pytest.fixture(scope="module")
def scene():
    return simulate.segments_scene(seed=2, n_ships=8, area_km=15)


def _start(pts, review: bool = True):
    """A session with the scene associated (and reviewed: :func:`_review`)."""
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    done = _review(s, lay) if review else {}
    st, _ = bind(s, lay)
    return s, src, lay, st, done


def _lone(st: R.ReviewState) -> list[str]:
    """Two tracks in two targets (the last ones: clear of the first proposals)."""
    tg = st.target_of_track()
    labels = list(st.tracks["track"])
    for k in range(len(labels) - 2, -1, -1):
        if tg[k] != tg[len(labels) - 1]:
            return [labels[k], labels[-1]]
    raise AssertionError("one target only")


def _carried(s: Session, src, lay, decide, late: bool):
    """Run Associate again with ``decide(s, lay, st)`` made on the old queue before the
    run (``late`` False) or after the worker computed it and before the swap (True);
    returns the new queue's state and the result."""
    st, _ = bind(s, lay)
    if not late:
        decide(s, lay, st)
    res = s.run_step(src.id, "associate")  # the worker
    if late:
        decide(s, lay, st)  # the operator, on the old layer, while it ran
    assert not s.stale(res)
    (lay2,) = s.apply_result(src.id, res)
    assert lay2.id == lay.id
    st2, _ = bind(s, lay2)
    return st2, res


def _same(a: R.ReviewState, b: R.ReviewState) -> None:
    assert list(a.proposals["proposal"]) == list(b.proposals["proposal"])
    assert list(a.status) == list(b.status)
    assert a.links == b.links
    assert (a.target_of_track() == b.target_of_track()).all()


def test_accepts_merges_and_undos_made_while_the_step_ran_are_carried(scene, tmp_path):
    def decide(s, lay, st):
        pending = [p for p, v in zip(st.proposals["proposal"], st.status, strict=True)
                   if v == "pending"]  # fmt: skip
        _do(s, lay, st, R.accept(st, pending[0]))
        _do(s, lay, st, R.merge(st, _lone(st)))
        undone = _do(s, lay, st, R.accept(st, pending[1]))  # an accept, then Ctrl+Z
        _do(s, lay, st, undone.inverse())
        r = _do(s, lay, st, R.reject(st, pending[2]))  # a reject taken back: no change
        _do(s, lay, st, r.inverse())  # to the pairs kept out

    s1, src1, lay1, _, done = _start(scene)
    before, _ = _carried(s1, src1, lay1, decide, late=False)
    s2, src2, lay2, _, _ = _start(scene)
    after, res = _carried(s2, src2, lay2, decide, late=True)
    _same(after, before)
    assert res.carry.late == 6  # the six rows made while it ran
    text = STEPS["associate"].summary(res)
    assert "6 decisions made while the step ran taken into account" in text, text
    assert "not carried" not in text
    # The rejected and split pairs of the review before the run stay out.
    now = _pairs(after)
    assert done["rejected"] not in now and not done["split"] & set(now)
    # Stored at once: the carried rows are in the log, and a reopen gives the same.
    save_project(s2, tmp_path / "p.wakeline")
    back = load_project(tmp_path / "p.wakeline").to_session()
    st3, _ = bind(back, back.layers[lay2.id])
    _same(st3, after)
    # The decision log keeps the late decisions under the old queue, then the marker.
    log = after.log_table()
    assert list(log["action"]).count(R.RERUN) == 1
    assert len(after.history) == len([r for r in s2.decisions if r["queue"] != queue_key(
        s2.layers[lay2.id])])  # fmt: skip


def test_a_first_decision_made_while_the_step_ran_is_carried(scene):
    """The layer had no decision when the run started (nothing to carry then)."""

    def decide(s, lay, st):
        _do(s, lay, st, R.merge(st, _lone(st)))
        _do(s, lay, st, R.accept(st, st.proposals["proposal"].iloc[0]))

    s1, src1, lay1, _, _ = _start(scene, review=False)
    before, _ = _carried(s1, src1, lay1, decide, late=False)
    s2, src2, lay2, _, _ = _start(scene, review=False)
    after, res = _carried(s2, src2, lay2, decide, late=True)
    _same(after, before)
    assert res.carry.reviewed and res.carry.late == 2
    assert "review of the earlier run" in STEPS["associate"].summary(res)


@pytest.mark.parametrize("kind", ["reject", "split", "reject undone"])
def test_a_decision_that_changes_the_pairs_kept_out_makes_the_result_stale(scene, kind):
    """A reject or split made while the step ran (or a reject made before it, taken back
    while it ran) would keep out another set of pairs: the run cannot be reconciled by
    carrying. Nothing is applied, and the step run again gives what the same decisions
    made before the run give."""

    def decide(s, lay, st):
        if kind == "reject undone":
            rows = [r for r in s.decisions if r["queue"] == queue_key(lay)]
            last = R.Change.from_dict(rows[1]["change"])  # _review's reject
            assert last.action == "reject"
            _do(s, lay, st, last.inverse())
            return
        pending = [p for p, v in zip(st.proposals["proposal"], st.status, strict=True)
                   if v == "pending"]  # fmt: skip
        if kind == "reject":
            _do(s, lay, st, R.reject(st, pending[0]))
        else:
            _do(s, lay, st, R.split_track(st, st.track_a[st._row[pending[0]]]))

    s1, src1, lay1, _, _ = _start(scene)
    st1, _ = bind(s1, lay1)
    decide(s1, lay1, st1)
    (l1,) = s1.apply_result(src1.id, s1.run_step(src1.id, "associate"))
    before, _ = bind(s1, l1)

    s2, src2, lay2, _, _ = _start(scene)
    st2, _ = bind(s2, lay2)
    res = s2.run_step(src2.id, "associate")
    decide(s2, lay2, st2)
    assert s2.stale(res)
    rows, run = len(s2.decisions), lay2.run
    with pytest.raises(StaleResult, match="run associate again"):
        s2.apply_result(src2.id, res)
    assert len(s2.decisions) == rows and s2.layers[lay2.id].run == run  # nothing applied
    again = s2.run_step(src2.id, "associate")  # what the window does: run it again
    assert not s2.stale(again)
    (l2,) = s2.apply_result(src2.id, again)
    after, _ = bind(s2, l2)
    _same(after, before)


def test_a_pipeline_rerun_carries_late_decisions_and_a_stale_one_applies_nothing(scene):
    pipe = Pipeline(
        (("clean", STEPS["clean"].defaults()), ("associate", STEPS["associate"].defaults()))
    )
    s = Session()
    src = s.add_layer("seg.csv", "source", scene)
    made = s.apply_result(src.id, s.run_pipeline(src.id, pipe))
    (lay,) = [m for m in made if m.step == "associate"]
    _review(s, lay)
    st, _ = bind(s, lay)
    res = s.run_pipeline(src.id, pipe)
    merged = _lone(st)
    _do(s, lay, st, R.merge(st, merged))  # while it ran
    assert not s.stale(res)
    s.apply_result(src.id, res)
    st2, _ = bind(s, s.layers[lay.id])
    assert st2.target(merged[0]) == st2.target(merged[1])
    assert res.stages[-1].carry.late == 1
    # A reject while the pipeline ran: stale, no stage applied (the cleaned layer too).
    res = s.run_pipeline(src.id, pipe)
    pending = [p for p, v in zip(st2.proposals["proposal"], st2.status, strict=True)
               if v == "pending"]  # fmt: skip
    _do(s, s.layers[lay.id], st2, R.reject(st2, pending[0]))
    assert s.stale(res)
    runs = {lid: x.run for lid, x in s.layers.items()}
    with pytest.raises(StaleResult):
        s.apply_result(src.id, res)
    assert {lid: x.run for lid, x in s.layers.items()} == runs


@pytest.fixture(scope="module")
def two_files():
    """The demo scene's first 30 min, one layer per sensor, both named S1 (as MTAD's)."""
    pts = simulate.demo_scene(seed=7)
    t = pd.to_datetime(pts["time"])
    pts = pts[t < t.min() + pd.Timedelta("30min")]
    return {s: part.assign(sensor="S1").reset_index(drop=True) for s, part in pts.groupby("sensor")}


def test_fuse_across_layers_carries_late_decisions(two_files):
    """Run ▸ Fuse selected layers again: the same reconciliation at the swap."""

    def decide(s, lay, st):
        pending = [p for p, v in zip(st.proposals["proposal"], st.status, strict=True)
                   if v == "pending"]  # fmt: skip
        _do(s, lay, st, R.accept(st, pending[0]))
        _do(s, lay, st, R.merge(st, _lone(st)))

    def run(late: bool):
        s = Session()
        a = s.add_layer("x_AIS.csv", "source", two_files["AIS"])
        r = s.add_layer("x_radar.csv", "source", two_files["R1"])
        ids = [a.id, r.id]
        (lay,) = s.apply_result(a.id, _fuse(s, ids), STEPS["fuse"].defaults(), inputs=ids)
        _review(s, lay)
        st, _ = bind(s, lay)
        if not late:
            decide(s, lay, st)
        res = _fuse(s, ids)
        if late:
            decide(s, lay, st)
        assert not s.stale(res)
        (lay2,) = s.apply_result(a.id, res, STEPS["fuse"].defaults(), inputs=ids)
        assert lay2.id == lay.id
        return bind(s, lay2)[0], res

    before, _ = run(late=False)
    after, res = run(late=True)
    _same(after, before)
    assert res.carry.late == 2


def test_the_carry_made_again_in_a_worker_then_more_decisions(scene):
    """The window makes the carry again in the worker (``Session.reconcile``) and
    checks again at the swap: decisions made in both spans are carried, all counted."""

    def first(s, lay, st):
        _do(s, lay, st, R.merge(st, _lone(st)))

    def second(s, lay, st):
        pending = [p for p, v in zip(st.proposals["proposal"], st.status, strict=True)
                   if v == "pending"]  # fmt: skip
        _do(s, lay, st, R.accept(st, pending[0]))

    s1, src1, lay1, st1, _ = _start(scene)
    first(s1, lay1, st1)
    second(s1, lay1, st1)
    (l1,) = s1.apply_result(src1.id, s1.run_step(src1.id, "associate"))
    before, _ = bind(s1, l1)

    s2, src2, lay2, st2, _ = _start(scene)
    res = s2.run_step(src2.id, "associate")
    first(s2, lay2, st2)
    assert s2.late_decisions(res) == 1 and not s2.stale(res)
    s2.reconcile(res)  # in the worker
    assert s2.late_decisions(res) == 0
    second(s2, lay2, st2)  # while it reconciled
    assert s2.late_decisions(res) == 1 and not s2.stale(res)
    (l2,) = s2.apply_result(src2.id, res)
    after, _ = bind(s2, l2)
    _same(after, before)
    assert res.carry.late == 2

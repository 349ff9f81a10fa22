"""Operator test 5 (h181) D-proj-3: a reopened project counts the review decisions in
effect, not the decision log's rows (50 decisions, 30 undos and 20 redos said "100
review decisions restored" where 40 proposals were decided)."""

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.review_session import bind, decision_counts, decisions_in_effect, queue_key
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session


def test_undo_and_redo_rows_are_not_counted_as_decisions_in_effect():
    s = Session()
    src = s.add_layer("seg.csv", "source", simulate.segments_scene(seed=2, n_ships=8, area_km=15))
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)
    pids = list(st.proposals["proposal"])
    assert len(pids) >= 4
    key = queue_key(lay)

    def do(change):
        st.apply(change)
        s.decisions.append(decision_row(key, change, st.log[-1]))
        return change

    done = [do(R.accept(st, p)) for p in pids[:4]]  # 4 decisions
    for change in reversed(done[1:]):  # 3 undos
        do(change.inverse())
    do(done[1])  # 1 redo
    steps, earlier = decision_counts([lay], s.decisions)
    assert (steps, earlier) == (8, 0)
    assert decisions_in_effect([lay], s.decisions) == 2 == int((st.status != "pending").sum())

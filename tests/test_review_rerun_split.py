"""A re-run of Associate keeps out what the operator split, as it keeps out what he
rejected (operator test h122, L5: after a review with A0001 split and 4 rejected, the
log said "4 pairs rejected in an earlier review kept out" and the split pair came back
joined). The log says how many split pairs were kept out; they stay out run after run."""

import time

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.pipeline import STEPS
from wakeline.core.review_session import bind, queue_key
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session


def _pairs(proposals) -> set:
    return {
        R.pair_key(f"{r.sensor_a}:{r.batch_a}", f"{r.sensor_b}:{r.batch_b}")
        for r in proposals.itertuples()
    }


def test_a_rerun_of_associate_keeps_out_what_the_operator_split():
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)
    p = st.proposals
    labels = list(zip(p["track_a"], p["track_b"], strict=True))
    split = R.split_track(st, labels[0][1])  # the first proposal's pair cut apart
    st.apply(split)
    s.decisions.append(decision_row(queue_key(lay), split, st.log[-1]))
    gone = {
        R.pair_key(*labels[k]) for k, pid in enumerate(p["proposal"]) if pid in split.status_after
    }
    assert R.pair_key(*labels[0]) in gone
    rej = R.reject(st, p["proposal"].iloc[-1])
    st.apply(rej)
    s.decisions.append(decision_row(queue_key(lay), rej, st.log[-1]))
    assert s.split_pairs_below(src.id) == gone
    res = s.run_step(src.id, "associate")
    assert res.report["split_kept_out"] == len(gone)
    assert res.report["rejected_kept_out"] == 1
    assert not _pairs(res.tables["proposals"]) & gone
    text = STEPS["associate"].summary(res)
    assert f"{len(gone)} pair" in text and "split in an earlier review kept out" in text, text
    assert "1 pair rejected in an earlier review kept out" in text
    # The re-run's queue has no decisions of its own: the split pairs stay out all the same.
    time.sleep(1.05 - time.time() % 1.0)  # queues are keyed by the second the run was made
    (lay2,) = s.apply_result(src.id, res)
    assert lay2.id == lay.id and lay2.meta["split_kept_out"]
    assert s.split_pairs_below(src.id) == gone
    third = s.run_step(src.id, "associate")
    assert third.report["split_kept_out"] == len(gone)
    assert not _pairs(third.tables["proposals"]) & gone

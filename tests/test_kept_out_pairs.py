"""A re-run of Associate keeps out the pairs the operator rejected or split: read in one
pass over the decision log (h135; it was two replays per layer), to the same pairs as
the two replays, which this test keeps as they were."""

import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.review import Change, pair_key
from wakeline.core.review_store import kept_out_pairs


def old_rejected_pairs(rows, layer_id):
    prefix = f"{layer_id}@"
    status = {}
    for row in rows:
        if not (isinstance(row, dict) and str(row.get("queue", "")).startswith(prefix)):
            continue
        change = row.get("change")
        if not isinstance(change, dict):
            continue
        pid, tracks = change.get("proposal"), change.get("tracks") or []
        after = change.get("status_after") or {}
        if pid and len(tracks) == 2 and pid in after:
            status[pair_key(str(tracks[0]), str(tracks[1]))] = str(after[pid])
    return {k for k, v in status.items() if v == "rejected"}


def old_split_pairs(rows, queue, proposals):
    need = ("proposal", "sensor_a", "batch_a", "sensor_b", "batch_b")
    if proposals is None or not len(proposals) or not set(need) <= set(proposals.columns):
        return set()
    p = proposals
    a = p["sensor_a"].astype(str) + ":" + p["batch_a"].astype(str)
    b = p["sensor_b"].astype(str) + ":" + p["batch_b"].astype(str)
    pairs = dict(zip(p["proposal"].astype(str), zip(a, b, strict=True), strict=True))
    status = {}
    for row in rows:
        if not (isinstance(row, dict) and row.get("queue") == queue):
            continue
        change = row.get("change")
        if not isinstance(change, dict):
            continue
        tracks = {str(t) for t in change.get("tracks") or []}
        for pid, value in (change.get("status_after") or {}).items():
            if pid in pairs and (not tracks or tracks & set(pairs[pid])):
                status[pair_key(*pairs[pid])] = str(value)
    return {k for k, v in status.items() if v == "split"}


#: four proposals over five tracks (A:1 in two of them)
PROPOSALS = pd.DataFrame(
    {
        "proposal": ["P1", "P2", "P3", "P4"],
        "sensor_a": ["A", "A", "R", "R"],
        "batch_a": ["1", "1", "7", "8"],
        "sensor_b": ["R", "R", "A", "A"],
        "batch_b": ["7", "8", "2", "3"],
    }
)
LABELS = {
    p.proposal: (f"{p.sensor_a}:{p.batch_a}", f"{p.sensor_b}:{p.batch_b}")
    for p in PROPOSALS.itertuples()
}

_ACTION = st.one_of(
    st.tuples(
        st.sampled_from(["accept", "reject", "split", "undo"]), st.sampled_from(list(LABELS))
    ),
    st.tuples(st.just("noise"), st.sampled_from(["not a row", "no change", "list change"])),
)
_QUEUE = st.sampled_from(["L1@100", "L1@101", "L12@100", "L2@100", "L1@x@100", "", "L1"])


def _log(actions):
    """Decision rows of a review: each queue's statuses moved as the window moves them
    (accept/reject one proposal, split a track out of every proposal that holds it,
    undo the queue's last change), with rows that are no decision mixed in."""
    rows, status, done = [], {}, {}
    for queue, (action, what) in actions:
        state = status.setdefault(queue, dict.fromkeys(LABELS, "pending"))
        if action == "noise":
            rows.append(
                what
                if what == "not a row"
                else {"queue": queue, "change": None if what == "no change" else [1, 2]}
            )
            continue
        if action == "undo":
            if not done.get(queue):
                continue
            change = done[queue].pop().inverse()
        elif action == "split":
            track = LABELS[what][1]
            hit = [p for p, pair in LABELS.items() if track in pair]
            change = Change(
                "split",
                "",
                (track,),
                {p: state[p] for p in hit},
                dict.fromkeys(hit, "split"),
            )
        else:
            after = "accepted" if action == "accept" else "rejected"
            change = Change(action, what, LABELS[what], {what: state[what]}, {what: after})
        if action != "undo":
            done.setdefault(queue, []).append(change)
        state.update(change.status_after)
        rows.append({"queue": queue, "action": change.action, "change": change.to_dict()})
    return rows


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.tuples(_QUEUE, _ACTION), max_size=30),
    st.lists(
        st.tuples(
            st.sampled_from(["L1", "L12", "L2", "L1@x", "L3"]),
            _QUEUE,
            st.booleans(),
        ),
        max_size=4,
        unique_by=lambda t: t[0],
    ),
)
def test_one_pass_keeps_out_what_the_two_replays_kept_out(actions, layers):
    rows = _log(actions)
    queues = [(lid, queue, PROPOSALS if has else None) for lid, queue, has in layers]
    rejected, split = kept_out_pairs(rows, queues)
    assert rejected == set().union(*(old_rejected_pairs(rows, lid) for lid, _, _ in queues))
    assert split == set().union(*(old_split_pairs(rows, q, p) for _, q, p in queues))


def test_a_split_then_its_undo_then_a_reject():
    """The sequence a reviewer makes: split A:1 (two pairs), undo, reject P1; queue L1@1
    and the older run's L1@0 (whose reject of P3 stays rejected)."""
    actions = [
        ("L1@0", ("reject", "P3")),
        ("L1@1", ("split", "P1")),
        ("L1@1", ("undo", "P1")),
        ("L1@1", ("split", "P3")),
        ("L1@1", ("reject", "P1")),
    ]
    rows = _log(actions)
    rejected, split = kept_out_pairs(rows, [("L1", "L1@1", PROPOSALS)])
    assert rejected == {pair_key(*LABELS["P1"]), pair_key(*LABELS["P3"])}
    # the split of A:2 cut P3 alone; that of R:7 (P1 and P3) was undone
    assert split == {pair_key(*LABELS["P3"])}

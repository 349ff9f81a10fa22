"""Review queue keys (h135): two runs of a step within one second were one queue (the key
was the layer id and the second it was made), so the first run's decisions were replayed
on the second. Each run now has its own token in the key; a project saved before keeps
its keys, and its decisions still load."""

import json
import sqlite3

import pandas as pd

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.pipeline import STEPS
from wakeline.core.project import load_project, save_project
from wakeline.core.review_session import bind, queue_key
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session


def _fused():
    pts = simulate.demo_scene(seed=7)
    t = pd.to_datetime(pts["time"])
    pts = pts[t < t.min() + pd.Timedelta("20min")]
    files = {
        s: part.assign(sensor="S1").reset_index(drop=True) for s, part in pts.groupby("sensor")
    }
    s = Session()
    a = s.add_layer("x_AIS.csv", "source", files["AIS"])
    r = s.add_layer("x_radar.csv", "source", files["R1"])
    both = R.combine_sources([("x_AIS", files["AIS"]), ("x_radar", files["R1"])])
    res = STEPS["fuse"](both)
    (made,) = s.apply_result(a.id, res, STEPS["fuse"].defaults(), inputs=[a.id, r.id])
    return s, made, res, (a.id, r.id)


def _reject_first(s, lay):
    st, _ = bind(s, lay)
    first = st.proposals["proposal"].iloc[0]
    change = R.reject(st, first)
    st.apply(change)
    s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    return first


def test_two_runs_in_one_second_are_two_queues():
    s, lay, res, inputs = _fused()
    key = queue_key(lay)
    first = _reject_first(s, lay)
    created = lay.created
    (again,) = s.apply_result(inputs[0], res, STEPS["fuse"].defaults(), inputs=list(inputs))
    assert again.id == lay.id
    again.created = created  # the same second, whatever the clock did
    assert queue_key(again) != key and queue_key(again).startswith(f"{lay.id}@{created}#")
    fresh, _ = bind(s, again)
    # the reject is not replayed on the new queue: its log opens with the re-run's marker
    # alone (h138: a re-run carries accepts and links over, none here)
    assert fresh.status_of(first) == "pending"
    assert [e.action for e in fresh.log] == [R.RERUN]


def test_a_project_saved_before_the_token_keeps_its_queue(tmp_path):
    s, lay, _, _ = _fused()
    lay.run = ""  # a layer as Wakeline made it before h135
    old_key = f"{lay.id}@{lay.created}"
    assert queue_key(lay) == old_key
    first = _reject_first(s, lay)
    path = tmp_path / "old.wakeline"
    save_project(s, path)
    with sqlite3.connect(path) as con:
        (lineage,) = con.execute("SELECT lineage FROM layers WHERE id = ?", (lay.id,)).fetchone()
    assert "run" not in json.loads(lineage)  # the lineage an old project holds
    back = load_project(path).to_session()
    loaded = back.layers[lay.id]
    assert queue_key(loaded) == old_key
    st, _ = bind(back, loaded)
    assert st.status_of(first) == "rejected"


def test_the_token_is_saved_and_read_back(tmp_path):
    s, lay, _, _ = _fused()
    assert len(lay.run) == 12
    first = _reject_first(s, lay)
    save_project(s, tmp_path / "p.wakeline")
    back = load_project(tmp_path / "p.wakeline").to_session()
    assert queue_key(back.layers[lay.id]) == queue_key(lay)
    st, _ = bind(back, back.layers[lay.id])
    assert st.status_of(first) == "rejected"

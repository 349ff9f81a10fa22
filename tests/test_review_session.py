"""The review bound to session layers (core, no Qt): which points a layer's proposals
were made on, decisions stored in the project's decisions table and replayed per queue,
lineage of a fuse across layers, and decisions surviving a killed process."""

import subprocess
import sys
import textwrap

import pandas as pd
import pytest

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.pipeline import STEPS
from wakeline.core.project import ProjectStore, load_project, save_project
from wakeline.core.review_session import (
    KEPT_INPUT,
    KEPT_NAMES,
    bind,
    decided_points,
    input_points,
    queue_key,
    review_dependents,
)
from wakeline.core.review_store import decision_row, replay_decisions
from wakeline.core.session import Session


@pytest.fixture(scope="module")
def pair():
    pts = simulate.demo_scene(seed=7)
    t = pd.to_datetime(pts["time"])
    pts = pts[t < t.min() + pd.Timedelta("30min")]
    files = {
        s: part.assign(sensor="S1").reset_index(drop=True) for s, part in pts.groupby("sensor")
    }
    both = R.combine_sources([("x_AIS", files["AIS"]), ("x_radar", files["R1"])])
    return files, STEPS["fuse"](both)  # the fuse step run once for the module


def _fused_session(pair) -> tuple[Session, str]:
    files, res = pair
    s = Session()
    a = s.add_layer("x_AIS.csv", "source", files["AIS"])
    r = s.add_layer("x_radar.csv", "source", files["R1"])
    (made,) = s.apply_result(a.id, res, STEPS["fuse"].defaults(), inputs=[a.id, r.id])
    return s, made.id


def test_fuse_across_layers_records_every_input_and_binds_to_them(pair, tmp_path):
    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    assert lay.inputs == ["L1", "L2"] and lay.parent == "L1"
    assert lay.name == "x_AIS.csv + x_radar.csv · fused"
    pts = input_points(s, lay)
    assert set(pts["sensor"]) == {"AIS", "radar"}  # both files said S1
    # A second run on one input alone is a layer of its own, not a replacement.
    res = STEPS["associate"](s.layers["L1"].points)
    s.apply_result("L1", res)
    assert s.layers[lid].inputs == ["L1", "L2"]
    # The lineage survives the project file.
    save_project(s, tmp_path / "p.wakeline")
    back = load_project(tmp_path / "p.wakeline").to_session()
    assert back.layers[lid].inputs == ["L1", "L2"] and back.layers["L1"].inputs == []
    # Removing an input keeps its points with the layer under review (next test); a
    # project whose input went before Wakeline kept them says what is missing.
    del s.layers["L2"]
    with pytest.raises(Exception, match="input layer L2 was removed"):
        input_points(s, lay)


def _decide(s: Session, lay, n: int = 3) -> list[str]:
    """Reject, accept, reject … the first ``n`` proposals of ``lay``'s queue, stored as
    the window stores them; the statuses of the whole queue."""
    st, _ = bind(s, lay)
    for k, pid in enumerate(st.proposals["proposal"][:n]):
        change = (R.accept if k % 2 else R.reject)(st, pid)
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    return list(st.status)


def test_removing_an_input_of_a_reviewed_layer_keeps_its_review(pair, tmp_path):
    """Tester's defect (h122): the AIS layer under a fused layer with decisions removed
    (Layer ▸ Remove), the project reopened: "its input layer L1 was removed; the review
    needs the points the proposals were made on", the decisions out of reach. The layer
    under review now keeps the input's points (a side table written with it), so the
    review binds before and after a reopen alike, with the same statuses; a layer added
    after the reopen never takes the removed layer's id (it was read as the input)."""
    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    before = input_points(s, lay).copy()
    want = _decide(s, lay)
    assert [x.id for x in review_dependents(s, "L1")] == [lid]
    assert review_dependents(s, lid) == []  # nothing is made from the fused layer
    events = []
    s.subscribe(lambda e, i: events.append((e, i)))
    s.remove_layer("L1")
    assert events == [("tables", lid), ("removed", "L1")]  # kept first, then removed
    assert KEPT_INPUT + "L1" in lay.tables and lay.meta[KEPT_NAMES] == ["x_AIS", "x_radar"]
    pd.testing.assert_frame_equal(input_points(s, lay), before)
    st, _ = bind(s, lay)
    assert list(st.status) == want
    # The project file (Save as) and, as the window writes it, the layer's tables alone.
    save_project(s, tmp_path / "p.wakeline")
    back = load_project(tmp_path / "p.wakeline").to_session()
    assert "L1" not in back.layers
    st2, pts2 = bind(back, back.layers[lid])
    assert list(st2.status) == want
    pd.testing.assert_frame_equal(pts2, before)
    assert back.add_layer("new.csv", "source", pair[0]["AIS"]).id not in ("L1", "L2", lid)
    s2, lid2 = _fused_session(pair)
    _decide(s2, s2.layers[lid2])
    save_project(s2, tmp_path / "w.wakeline")
    store = ProjectStore(tmp_path / "w.wakeline", create=False)
    s2.subscribe(
        lambda e, i: (
            store.put_tables(s2.layers[i], list(s2.layers).index(i))
            if e == "tables"
            else store.delete_layer(i)
            if e == "removed"
            else None
        )
    )
    s2.remove_layer("L2")  # the radar this time
    store.close()
    back2 = load_project(tmp_path / "w.wakeline").to_session()
    assert list(back2.layers) == ["L1", lid2]
    assert list(bind(back2, back2.layers[lid2])[0].status) == list(
        bind(s2, s2.layers[lid2])[0].status
    )


def test_removing_a_cleaned_layer_under_a_reviewed_association_keeps_its_review(tmp_path):
    """The other dependents: source → Clean → Associate (reviewed); the cleaned layer
    removed keeps its points with the associated layer (and the stitched one: each layer
    with proposals), the source removed changes nothing for them (not read). A fused
    layer made from cleaned layers keeps the names its inputs were combined under when
    a source above them goes (a name may be told apart by that file)."""
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts, meta={"file": "/d/seg.csv"})
    (clean,) = [
        x for x in s.apply_result(src.id, s.run_step(src.id, "clean")) if x.role == "cleaned"
    ]
    made = s.apply_result(clean.id, s.run_step(clean.id, "associate"))
    reviewed = [
        x for x in made if x.tables.get("proposals") is not None and len(x.tables["proposals"])
    ]
    assert reviewed
    lay = reviewed[0]
    want = _decide(s, lay, 2)
    decided = decided_points(lay, *bind(s, lay))
    assert {x.id for x in review_dependents(s, src.id)} == set()
    assert {x.id for x in review_dependents(s, clean.id)} == {x.id for x in reviewed}
    s.remove_layer(clean.id)
    save_project(s, tmp_path / "a.wakeline")
    back = load_project(tmp_path / "a.wakeline").to_session()
    st, pts2 = bind(back, back.layers[lay.id])
    assert list(st.status) == want
    again = decided_points(back.layers[lay.id], st, pts2)
    if decided is None:
        assert again is None
    else:
        pd.testing.assert_frame_equal(again, decided)
    # Clean and Associate run again on the source after the reopen make new layers (the
    # new cleaned layer took the removed one's id before: Associate on it then replaced
    # the reviewed layer in place); the reviewed one stays as it was.
    created = back.layers[lay.id].created
    (clean2,) = [
        x for x in back.apply_result(src.id, back.run_step(src.id, "clean")) if x.role == "cleaned"
    ]
    assert clean2.id != clean.id
    back.apply_result(clean2.id, back.run_step(clean2.id, "associate"))
    assert back.layers[lay.id].created == created
    assert list(bind(back, back.layers[lay.id])[0].status) == want


def test_a_fuse_of_cleaned_layers_keeps_its_input_names_when_a_source_goes(pair):
    """Two files of one stem in two folders fused from their cleaned layers: the folders
    tell the inputs apart (their root's file). Removing a source above an input freezes
    the names (meta), not the points (the input layer is still there)."""
    files, res = pair
    s = Session()
    a = s.add_layer("x.csv", "source", files["AIS"], meta={"file": "/d/ais/x.csv"})
    r = s.add_layer("x.csv", "source", files["R1"], meta={"file": "/d/radar/x.csv"})
    ca, cr = (
        s.add_layer("x.csv", "cleaned", src.points, parent=src.id, step="clean", role="cleaned")
        for src in (a, r)
    )
    (lay,) = s.apply_result(ca.id, res, STEPS["fuse"].defaults(), inputs=[ca.id, cr.id])
    before = input_points(s, lay).copy()
    assert [x.id for x in review_dependents(s, a.id)] == [lay.id]
    s.remove_layer(a.id)
    assert lay.meta[KEPT_NAMES] == ["ais", "radar"] and not any(
        t.startswith(KEPT_INPUT) for t in lay.tables
    )
    pd.testing.assert_frame_equal(input_points(s, lay), before)


def test_decisions_replay_per_queue_and_relabel_the_layer(pair):
    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    st, pts = bind(s, lay)
    first, second = st.proposals["proposal"][:2]
    for change in (R.reject(st, first), R.accept(st, second)):
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    s.decisions.append(decision_row("L9@old", R.accept(st, first), st.log[-1]))  # another queue
    again, _ = bind(s, lay)
    assert again.status_of(first) == "rejected" and again.status_of(second) == "accepted"
    assert len(again.log) == 2
    fused = decided_points(lay, again, pts)
    assert set(fused["batch"]) == set(again.target_of_track())
    # A re-run of the step is a new queue: nothing replayed on it.
    lay.created = "2099-01-01T00:00:00Z"
    fresh, _ = bind(s, lay)
    assert (fresh.status == "pending").all()
    assert replay_decisions(fresh, [{"queue": "x"}, "junk"], queue_key(lay)) == 0


def test_project_decisions_survive_a_killed_process(pair, tmp_path):
    s, lid = _fused_session(pair)
    proj = tmp_path / "k.wakeline"
    save_project(s, proj)
    script = textwrap.dedent(
        f"""
        import os, signal, sys, time
        from wakeline.core import review as R
        from wakeline.core.project import ProjectWriter, load_project
        from wakeline.core.review_session import bind, queue_key
        from wakeline.core.review_store import decision_row
        s = load_project({str(proj)!r}).to_session()
        lay = s.layers[{lid!r}]
        st, _ = bind(s, lay)
        writer = ProjectWriter({str(proj)!r}, lambda exc: print(exc, file=sys.stderr))
        for pid in st.proposals["proposal"][:3]:
            change = R.reject(st, pid)
            st.apply(change)
            row = decision_row(queue_key(lay), change, st.log[-1])
            writer.submit(lambda store, row=row: store.add_decision(row))
        writer.flush(30)
        print("decided", flush=True)
        os.kill(os.getpid(), signal.SIGKILL)
        """
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert "decided" in done.stdout and done.returncode == -9, done.stderr
    back = load_project(proj).to_session()
    st, _ = bind(back, back.layers[lid])
    assert (st.status[:3] == "rejected").all() and (st.status[3:] == "pending").all()


def test_a_rerun_of_associate_keeps_out_what_the_operator_rejected():
    # Reject two proposals (and undo a third rejection) in the review of an associated
    # layer, then run Associate again on the same input: the two rejected pairs are not
    # proposed again, the undone one is, and the report says how many were kept out.
    pts = simulate.segments_scene(seed=2, n_ships=8, area_km=15)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)
    p = st.proposals
    labels = list(zip(p["track_a"], p["track_b"], strict=True))
    a, b, c = p["proposal"][:3]
    for change in (R.reject(st, a), R.reject(st, b), R.reject(st, c)):
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    back = R.reset(st, c)  # the third one taken back
    st.apply(back)
    s.decisions.append(decision_row(queue_key(lay), back, st.log[-1]))
    assert s.rejected_pairs_below(src.id) == {R.pair_key(*labels[0]), R.pair_key(*labels[1])}
    res = s.run_step(src.id, "associate")
    assert res.report["rejected_kept_out"] == 2
    again = res.tables["proposals"]
    pairs = {
        R.pair_key(f"{r.sensor_a}:{r.batch_a}", f"{r.sensor_b}:{r.batch_b}")
        for r in again.itertuples()
    }
    assert R.pair_key(*labels[0]) not in pairs and R.pair_key(*labels[1]) not in pairs
    assert R.pair_key(*labels[2]) in pairs
    # The layer's points and pair table follow the re-run association, not the first one.
    joined = {
        R.pair_key(f"{r.sensor}:{r.batch_a}", f"{r.sensor}:{r.batch_b}")
        for r in res.tables["pairs"].itertuples()
    }
    assert joined == pairs
    (lay2,) = s.apply_result(src.id, res)
    assert lay2.id == lay.id
    # Rejections of every run count: the second run's queue has none of its own.
    assert s.rejected_pairs_below(src.id) == {R.pair_key(*labels[0]), R.pair_key(*labels[1])}
    assert "kept out" in STEPS["associate"].summary(res)


def test_an_old_project_with_split_rows_beside_joined_tracks_is_repaired_on_open(tmp_path):
    """A project saved before joins accepted the rows they put inside a target (split or
    rejected, then merged by hand: the row still said so beside the joined target) opens
    with those rows accepted by one stored ``repair`` decision each, the links a merge
    would not have made gone with them, the targets and everything else as they were;
    stored once, it reopens the same with nothing more to repair."""
    from conftest import old_style_review_project
    from wakeline.core.project import ProjectStore

    path = tmp_path / "old.wakeline"
    old = old_style_review_project(path)
    ids, lid = old["ids"], old["layer"]
    with_old_code = load_project(path)  # the rows as the old code reads them back
    s0 = with_old_code.to_session()
    s0.decisions = [d for d in s0.decisions if d not in with_old_code.repairs]
    before, _ = bind(s0, s0.layers[lid])
    assert list(before.status) == old["status"]
    assert set(R.cut_inside_targets(before)) == {
        ids["split_merged"],
        ids["rejected_merged"],
        ids["rejected_in_cycle"],
    }

    proj = load_project(path)
    assert len(proj.repairs) == 2
    assert proj.decisions == with_old_code.decisions[: len(proj.decisions) - 2] + proj.repairs
    assert [r["change"]["proposal"] for r in proj.repairs] == [
        ids["split_merged"],
        ids["rejected_merged"],
    ]
    assert {r["action"] for r in proj.repairs} == {"repair"}
    s = proj.to_session()
    st, _ = bind(s, s.layers[lid])
    assert st.status_of(ids["split_merged"]) == "accepted"
    assert st.status_of(ids["rejected_merged"]) == "accepted"
    # Nothing else moved: other rows, the targets; the links the old merges added
    # beside the rows now accepted are gone (the rows join those tracks), the others stay.
    repaired = {st._row[ids["split_merged"]], st._row[ids["rejected_merged"]]}
    for k, (was, now) in enumerate(zip(before.status, st.status, strict=True)):
        assert k in repaired or was == now
    assert st.status_of(ids["rejected_in_cycle"]) == "rejected"  # the operator's, kept
    assert (st.target_of_track() == before.target_of_track()).all()
    pair = {
        k: tuple(sorted((st.track_a[st._row[p]], st.track_b[st._row[p]]))) for k, p in ids.items()
    }
    assert st.links == old["links"] - {pair["split_merged"], pair["rejected_merged"]}
    assert pair["rejected_in_cycle"] in st.links
    assert R.cut_inside_targets(st) == [ids["rejected_in_cycle"]]
    # The layers, parameters and sources are read as they were written.
    for a, b in zip(proj.layers, with_old_code.layers, strict=True):
        assert a.id == b.id and a.points.equals(b.points)
    assert proj.params == with_old_code.params and proj.sources == with_old_code.sources
    # A re-run keeps out only the pairs still rejected.
    assert s.rejected_pairs_below("L1") == {pair["rejected"], pair["rejected_in_cycle"]}

    # Stored (as the window does at once), the project reopens the same.
    store = ProjectStore(path, create=False)
    try:
        for row in proj.repairs:
            store.add_decision(row)
    finally:
        store.close()
    again = load_project(path)
    assert again.repairs == [] and again.decisions == proj.decisions
    s2 = again.to_session()
    st2, _ = bind(s2, s2.layers[lid])
    assert list(st2.status) == list(st.status) and st2.links == st.links
    assert (st2.target_of_track() == st.target_of_track()).all()
    assert st2.log_table()["action"].tolist()[-2:] == ["repair", "repair"]


def test_no_repair_on_a_consistent_project_or_a_queue_that_cannot_be_bound(pair, tmp_path):
    """Decisions made by today's joins never call for a repair; a queue whose input layer
    is gone is left to the review (which says so), and the project opens."""
    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    st, _ = bind(s, lay)
    a, b = st.proposals["proposal"][:2]
    ta = st.track_a[st._row[a]]
    for change in (R.split_track(st, ta), R.merge(st, [ta, st.track_b[st._row[a]]])):
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    assert R.cut_inside_targets(st) == []
    save_project(s, tmp_path / "new.wakeline")
    assert load_project(tmp_path / "new.wakeline").repairs == []
    s.remove_layer("L2")
    save_project(s, tmp_path / "gone.wakeline")
    assert load_project(tmp_path / "gone.wakeline").repairs == []


def test_the_migration_runs_once_per_project_file(tmp_path, monkeypatch):
    """The migration on open replayed every queue on every open (ATD, 40 decisions: ~55
    of ~85 ms). A project written today marks its decisions checked, and a checked file
    opens without it; an old file is checked once, then marked (the window does it after
    writing the repairs); a decision appended by a Wakeline without the mark makes the
    next open check again, while today's decisions keep the mark."""
    import sqlite3

    from conftest import old_style_review_project
    from wakeline.core import project as P

    path = tmp_path / "old.wakeline"
    old_style_review_project(path)
    proj = load_project(path)
    assert not proj.decisions_checked and len(proj.repairs) == 2
    store = P.ProjectStore(path, create=False)
    for row in proj.repairs:
        store.add_decision(row)
    assert not load_project(path).decisions_checked  # repairs alone: not marked
    store.mark_decisions_checked()
    store.close()

    def no_migration(*_a, **_k):
        raise AssertionError("the migration ran on a checked project")

    monkeypatch.setattr(P, "repair_decisions", no_migration)
    again = load_project(path)
    assert again.decisions_checked and again.repairs == [] and again.decisions == proj.decisions
    # today's decisions keep the mark
    store = P.ProjectStore(path, create=False)
    store.add_decision(dict(proj.decisions[-1], time="2026-12-04T21:00:00+00:00"))
    store.close()
    assert load_project(path).decisions_checked
    # a row an older Wakeline appends (no mark kept) makes the next open check again
    con = sqlite3.connect(path)
    with con:
        con.execute("INSERT INTO decisions (json) VALUES ('{}')")
    con.close()
    monkeypatch.undo()
    assert not load_project(path).decisions_checked
    # Save as writes a checked file; a new project is checked from its start
    save_project(again, tmp_path / "saved.wakeline")
    assert load_project(tmp_path / "saved.wakeline").decisions_checked
    save_project(Session(), tmp_path / "empty.wakeline")
    assert load_project(tmp_path / "empty.wakeline").decisions_checked


def test_a_queue_no_decision_of_which_cuts_a_row_is_not_replayed(pair, tmp_path, monkeypatch):
    """The cheap check: without a reject or split among a queue's decisions no row can be
    cut inside a target, and the migration does not replay the queue."""
    from conftest import unmark_decisions
    from wakeline.core import review_session as RS

    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    st, _ = bind(s, lay)
    for pid in st.proposals["proposal"][:3]:
        change = R.accept(st, pid)
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    save_project(s, tmp_path / "p.wakeline")
    unmark_decisions(tmp_path / "p.wakeline")
    replayed = []
    monkeypatch.setattr(RS.R, "replay_repaired", lambda *a, **k: replayed.append(1) or [])
    proj = load_project(tmp_path / "p.wakeline")
    assert proj.repairs == [] and not proj.decisions_checked and replayed == []
    assert not R.cuts_anything([R.accept(st, st.proposals["proposal"][5])])
    assert R.cuts_anything([R.split_track(st, st.track_a[0])])


def test_a_removed_layer_is_restored_with_its_place_lineage_tables_and_review(pair, tmp_path):
    """Layer ▸ Remove is undoable (h237): ``restore_layer`` undoes ``remove_layer`` —
    the same layer object back in its place, the layer under review's kept tables and
    meta of before, its statuses as before; the id is never given to a layer added
    meanwhile; a removal of work cleared since is refused. The project writer, following
    the events, holds the same layers as the session after each step."""
    s, lid = _fused_session(pair)
    lay = s.layers[lid]
    want = _decide(s, lay)
    s.set_active("L1")
    s.selection = [("L1", "S1", "1")]
    save_project(s, tmp_path / "u.wakeline")
    store = ProjectStore(tmp_path / "u.wakeline", create=False)

    open_ = [True]

    def write(e, i):
        if not open_[0]:
            return
        if e in ("added",):
            store.put_layer(s.layers[i], list(s.layers).index(i))
        elif e == "tables":
            store.put_tables(s.layers[i], list(s.layers).index(i))
        elif e == "removed":
            store.delete_layer(i)
        elif e == "reordered":
            store.put_order(list(s.layers))

    s.subscribe(write)
    tables, meta, layer = lay.tables, lay.meta, s.layers["L1"]
    removal = s.remove_layer("L1")
    assert removal.pos == 0 and removal.active and s.active is None
    assert KEPT_INPUT + "L1" in lay.tables and list(bind(s, lay)[0].status) == want
    newcomer = s.add_layer("new.csv", "source", pair[0]["AIS"])
    assert newcomer.id != "L1"  # the removed layer's id stays free for an undo
    s.remove_layer(newcomer.id)
    back = s.restore_layer(removal)
    assert back is layer and list(s.layers) == ["L1", "L2", lid]
    assert lay.tables is tables and lay.meta is meta  # the kept input given back
    assert s.active == "L1" and s.selection == [("L1", "S1", "1")]
    assert list(bind(s, lay)[0].status) == want  # its decisions were never removed
    open_[0] = False
    store.close()
    reopened = load_project(tmp_path / "u.wakeline").to_session()
    assert list(reopened.layers) == ["L1", "L2", lid]
    assert reopened.layers["L1"].lineage() == layer.lineage()
    pd.testing.assert_frame_equal(reopened.layers["L1"].points, layer.points)
    assert list(bind(reopened, reopened.layers[lid])[0].status) == want
    # restored twice, or into work cleared since: refused, nothing changed
    with pytest.raises(Exception, match="is taken"):
        s.restore_layer(removal)
    again = s.remove_layer("L2")
    s.clear()
    with pytest.raises(Exception, match="closed since"):
        s.restore_layer(again)
    assert not s.layers

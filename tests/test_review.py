"""Review of proposals (issue 13): evidence, decisions and their inverses, targets, the
decision store surviving a killed process, export and the `review` command."""

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from test_associate import track
from test_association_hard import turning

from conftest import real_file
from wakeline.app.cli import main
from wakeline.core import review as R
from wakeline.core.associate import LinkParams, associate_interrupted, optimal_assign, pair_cost
from wakeline.core.errors import InputError
from wakeline.core.export_review import (
    export_decision_log,
    export_tracks,
    fused_tracks,
    merged_tracks,
)
from wakeline.core.fuse import associate_sensors, fuse
from wakeline.core.io import write_points
from wakeline.core.review_store import ReviewStore
from wakeline.core.simulate import multisensor_scene, segments_scene


@pytest.fixture(scope="module")
def scene():
    """One radar breaking 8 ships into segments, and the same ships by radar and AIS."""
    seg = segments_scene(seed=2, n_ships=8, area_km=15)
    multi = multisensor_scene(seed=3, n_ships=6, area_km=20)
    return seg, multi


@pytest.fixture
def state(scene):
    seg, multi = scene
    ap, _ = R.association_proposals(associate_interrupted(seg))
    return R.ReviewState(R.track_table(seg), ap)


def _snapshot(st: R.ReviewState):
    return (list(st.status), sorted(st.links), list(st.target_of_track()))


def test_the_spread_part_shows_where_a_join_paid_for_a_wide_prediction():
    # A hard harbour: some joins are not their tracks' tightest plausible candidate.
    df = segments_scene(seed=12, n_ships=60, area_km=4.0, sigma_m=20.0, hard=True)
    ap = R.association_proposals(associate_interrupted(df))[0]
    paid = ap["spread"] > 0.005
    assert paid.any() and (~paid).any()
    assert (ap.loc[paid, "cost"] > ap.loc[paid, "spread"]).all()


def test_the_acceleration_an_end_shows_is_named_where_it_widened_the_gate():
    # A ship turning 0.3 deg/s through a 240 s gap is joined only because its ends show
    # the turn (tests/test_association_hard.py); the proposal says so, and a straight
    # ship's does not.
    ap = R.association_proposals(associate_interrupted(turning(0.3, 240.0)))[0]
    assert len(ap) == 1 and 0.02 < ap["end_accel_ms2"].iloc[0] < 0.04
    straight = turning(0.0, 240.0)
    ap = R.association_proposals(associate_interrupted(straight))[0]
    assert len(ap) == 1 and ap["end_accel_ms2"].isna().all()
    # A ship that bends as its piece ends, then holds its new course: the acceleration
    # widens a 300 s gap; past the drift cap (2 x drift_ms / accel_ms2 = 2,000 s) it
    # changes nothing, and the line says nothing.
    for gap, named in ((300.0, True), (2500.0, False)):
        t = np.arange(0.0, 1201.0 + gap)
        heading = np.radians(90.0) + np.cumsum(np.where((t >= 520) & (t < 600), 0.005, 0.0))
        x, y = np.cumsum(6 * np.sin(heading)), np.cumsum(6 * np.cos(heading))
        a, b = (t <= 600) & (t % 10 == 0), (t >= 600 + gap) & (t % 10 == 0)
        df = pd.concat([track("1", t[a], x[a], y[a]), track("2", t[b], x[b], y[b])])
        ap = R.association_proposals(associate_interrupted(df))[0]
        assert len(ap) == 1 and ap["end_accel_ms2"].notna().iloc[0] == named, gap


def test_association_proposals_carry_evidence(scene):
    seg, _ = scene
    params = LinkParams()
    assoc = associate_interrupted(seg, params)
    ap, same = R.association_proposals(assoc, params)
    assert same is assoc
    assert len(ap) == len(assoc.chosen) > 5
    assert list(ap.columns) == list(R.PROPOSAL_COLUMNS)
    assert ap["proposal"].is_unique and (ap["kind"] == "associate").all()
    assert (ap["cost"] <= params.gate).all() and (ap["gap_s"] > 0).all()
    assert ap[["distance_m", "miss_m", "dcourse_deg", "dspeed_kn"]].notna().all().all()
    # The spread term's part: never negative, zero for the tightest, the rest of the cost
    # what the pair costs without it.
    assert (ap["spread"] >= -1e-12).all() and (ap["spread"] < 1e-9).any()
    k = assoc.chosen
    flat = pair_cost(assoc.pairs.take(k), params.replace(log_sigma=0.0), "scaled", assoc.segments)
    by_pair = ap.set_index(["batch_a", "batch_b"])
    keys = assoc.segments.index.keys["batch"].astype(str).to_numpy()
    mine = by_pair.loc[list(zip(keys[assoc.pairs.i[k]], keys[assoc.pairs.j[k]], strict=True))]
    np.testing.assert_allclose(mine["cost"] - mine["spread"], flat, atol=1e-9)
    # The margin is the cheaper of runner-up and gate minus the cost.
    alt = np.fmin(ap["runner_up_cost"].to_numpy(), params.gate)
    np.testing.assert_allclose(ap["margin"], alt - ap["cost"])
    labels = set(R.track_table(seg)["track"])
    rivals = ap.loc[ap["runner_up"] != "", "runner_up"]
    assert len(rivals) and set(rivals) <= labels
    # The runner-up of a proposal is a candidate sharing one of its tracks.
    keys = R._labels(assoc.segments.index.keys)
    cand = set(zip(keys[assoc.pairs.i].tolist(), keys[assoc.pairs.j].tolist(), strict=True))
    for row in ap[ap["runner_up"] != ""].itertuples():
        a, b, r = f"{row.sensor_a}:{row.batch_a}", f"{row.sensor_b}:{row.batch_b}", row.runner_up
        assert (a, r) in cand if row.runner_up_side == "a" else (r, b) in cand


def test_targets_of_untouched_state_match_the_engine(scene):
    seg, _ = scene
    assoc = associate_interrupted(seg)
    ap, _ = R.association_proposals(assoc)
    st = R.ReviewState(R.track_table(seg), ap)
    mine = st.targets()["target"].to_numpy()
    theirs = pd.Series(assoc.target_of_track, index=R._labels(assoc.segments.index.keys))
    theirs = theirs.reindex(st.tracks["track"]).to_numpy()
    # Same partition (the names differ: ours carry the sensor).
    assert len(set(zip(mine, theirs, strict=True))) == len(set(mine)) == len(set(theirs))


def test_every_command_and_its_inverse_round_trip(state):
    st = state
    p = st.proposals
    tr = st.tracks["track"].tolist()
    before = _snapshot(st)
    cmds = [
        lambda: R.accept(st, p["proposal"][0]),
        lambda: R.reject(st, p["proposal"][1]),
        lambda: R.merge(st, [tr[0], tr[3], tr[7]]),
        lambda: R.split_track(st, p["track_b"][2]),
        lambda: R.split_target(st, st.target(p["track_a"][0])),
    ]
    done = []
    for make in cmds:
        start = _snapshot(st)
        change = st.apply(make())
        assert _snapshot(st) != start or change.action == "accept"
        st.apply(change.inverse())
        assert _snapshot(st) == start
        assert change.inverse().inverse() == change
        done.append(st.apply(change))  # redo
    assert len(st.log) == 3 * len(cmds)
    assert _snapshot(st) != before
    # Undo every change in reverse order: back to the start.
    for change in reversed(done):
        st.apply(change.inverse())
    assert _snapshot(st) == before


def test_targets_follow_decisions(state):
    st = state
    p = st.proposals
    a, b = p["track_a"][0], p["track_b"][0]
    assert st.target(a) == st.target(b)
    st.apply(R.reject(st, p["proposal"][0]))
    assert st.target(a) != st.target(b)
    assert st.status_of(p["proposal"][0]) == "rejected"
    st.apply(R.merge(st, [a, b]))
    assert st.target(a) == st.target(b)
    st.apply(R.split_track(st, b))
    assert st.members(st.target(b)) == [b]
    # Targets are named after their earliest track, sensor included.
    t0 = st.tracks.set_index("track")["t0"]
    for tg in set(st.target_of_track()):
        first = min(st.members(tg), key=lambda x: t0[x])
        assert tg == first
    log = st.log_table()
    assert list(log.columns) == ["time", "action", "proposal", "tracks", "before", "after"]
    assert log["action"].tolist() == ["reject", "merge", "split track"]
    assert "=" in log["before"][0] and "+" in log["before"][0]
    with pytest.raises(InputError, match="no proposal"):
        R.accept(st, "X9999")
    with pytest.raises(InputError, match="at least two"):
        R.merge(st, [a, a])
    stale = R.reject(st, p["proposal"][1])
    st.apply(stale)
    with pytest.raises(InputError, match="no longer applies"):
        st.apply(stale)


def test_label_points_takes_the_tracks_targets_per_point(scene, state):
    """label_points takes each track's target per point (an Arrow take, the GIL free)
    instead of turning a Python string per point; the column is what the per-point
    values gave: same values, same type, NaN for a track the queue does not know."""
    seg, _ = scene
    st = state
    st.apply(R.reject(st, st.proposals["proposal"][0]))
    extra = seg[seg["batch"] == seg["batch"].iloc[0]].assign(batch="not-in-the-queue")
    rng = np.random.default_rng(5)
    for points in (seg, pd.concat([seg, extra], ignore_index=True)):
        points = points.iloc[rng.permutation(len(points))].reset_index(drop=True)
        got = st.label_points(points)
        tt = st.targets().set_index("track")["target"]
        per_point = tt.reindex(R.point_labels(points)).to_numpy()  # a string per point
        want = points.copy()
        want["target"] = per_point
        pd.testing.assert_frame_equal(got, want)
        assert got["target"].isna().sum() == (len(points) - len(seg))
    assert st.label_points(seg.iloc[:0])["target"].size == 0


def test_an_accepts_log_row_says_the_status_it_moved(state):
    """Operator test 8, D9: a pending proposal counts as joined already, so an accept's
    targets before and after are the same; the row says the status change (pending →
    accepted) and its undo the way back, as every change of a status does."""
    st = state
    pid = st.proposals["proposal"][0]
    a, b = st.proposals["track_a"][0], st.proposals["track_b"][0]
    target = st.target(a)
    cell = f"{target}={'+'.join(st.members(target))}"
    st.apply(R.accept(st, pid))
    change = R.reject(st, pid)
    st.apply(change)
    st.apply(change.inverse())
    st.apply(R.split_track(st, b))
    st.apply(R.merge(st, [a, b]))
    log = st.log_table()
    acc, rej, undo, split, merge = log.to_dict("records")
    assert acc["before"] == f"{pid} pending; {cell}"
    assert acc["after"] == f"{pid} accepted; {cell}"
    assert acc["before"] != acc["after"]
    assert rej["before"].startswith(f"{pid} accepted; ") and rej["after"].startswith(
        f"{pid} rejected; "
    )
    assert undo["action"] == "undo reject" and undo["before"].startswith(f"{pid} rejected; ")
    assert undo["after"].startswith(f"{pid} accepted; ")
    # a split cuts every proposal touching the track: each one's status is named
    assert split["before"].startswith(f"{pid} accepted") and f"{pid} split" in split["after"]
    # merge re-accepts the split proposal: its row says so too
    assert f"{pid} split" in merge["before"] and f"{pid} accepted" in merge["after"]
    # the log still replays to the same targets (replay reads action, proposal, tracks)
    again = R.ReviewState(st.tracks, st.proposals)
    R.replay_log(again, log)
    assert again.target(b) == st.target(b)


def test_a_rejection_runs_the_same_association_again():
    # Two ships side by side, both silent for 5 min: either start could be either's, so
    # the margin test leaves all four ends loose. A clean join elsewhere is rejected: the
    # association that runs again keeps the margin test (and the chain passes and the
    # second look), so the ambiguous pairs are still not proposed.
    from wakeline.core import geo

    t0 = pd.Timestamp("2024-05-01T00:00:00Z")

    rng = np.random.default_rng(0)

    def piece(batch, t_start, y_m):
        t = np.arange(t_start, t_start + 600.0, 10.0)
        x, y = 6.0 * t + rng.normal(0, 30, len(t)), y_m + rng.normal(0, 30, len(t))
        lon, lat = geo.from_local(x, y, 122.5, 30.5)
        return pd.DataFrame(
            {
                "sensor": "R1",
                "batch": batch,
                "time": t0 + pd.to_timedelta(t, unit="s"),
                "lon": lon,
                "lat": lat,
            }
        )

    df = pd.concat(
        [
            piece("1", 0, 0.0),
            piece("2", 0, 20.0),
            piece("3", 900, 0.0),
            piece("4", 900, 20.0),
            piece("5", 0, 40_000.0),
            piece("6", 900, 40_000.0),
        ],
        ignore_index=True,
    )
    params = LinkParams()
    assoc = associate_interrupted(df, params)
    ap, _ = R.association_proposals(assoc, params)
    joined = ap[["batch_a", "batch_b"]].values.tolist()
    assert ["5", "6"] in joined and len(joined) < 3  # the tangle is not fully joined
    again, re_assoc = R.association_proposals(assoc, params, [("R1:5", "R1:6")])
    # Far from the tangle, the rejection changes nothing there.
    assert again[["batch_a", "batch_b"]].values.tolist() == [p for p in joined if p != ["5", "6"]]
    assert re_assoc.target_of_track[list(re_assoc.segments.index.keys["batch"]).index("6")] == "6"
    # The old re-run (a plain assignment, no margin test) would have joined the tangle.
    plain = optimal_assign(assoc.pairs.i, assoc.pairs.j, assoc.cost, params.gate)
    assert len(plain) > len(joined)


def test_rejected_pairs_are_never_proposed_again(scene):
    seg, multi = scene
    params = LinkParams()
    assoc = associate_interrupted(seg, params)
    ap, _ = R.association_proposals(assoc, params)
    st = R.ReviewState(R.track_table(seg), ap)
    for pid in ap["proposal"][:3]:
        st.apply(R.reject(st, pid))
    again, re_assoc = R.association_proposals(
        associate_interrupted(seg, params), params, st.rejected_pairs()
    )
    pairs = {
        R.pair_key(f"{r.sensor_a}:{r.batch_a}", f"{r.sensor_b}:{r.batch_b}")
        for r in again.itertuples()
    }
    assert not pairs & st.rejected_pairs()
    assert len(again) >= len(ap) - 3
    # Cross-sensor: the same.
    sa = associate_sensors(multi)
    fp, _ = R.fusion_proposals(sa)
    assert (fp["kind"] == "fuse").all() and fp["overlap_s"].gt(0).all()
    rej = {
        R.pair_key(
            fp["sensor_a"][0] + ":" + fp["batch_a"][0], fp["sensor_b"][0] + ":" + fp["batch_b"][0]
        )
    }
    fp2, sa2 = R.fusion_proposals(associate_sensors(multi), rejected=rej)
    pairs2 = {
        R.pair_key(f"{r.sensor_a}:{r.batch_a}", f"{r.sensor_b}:{r.batch_b}")
        for r in fp2.itertuples()
    }
    assert not pairs2 & rej and len(fp2) == len(fp) - 1
    assert len(set(sa2.target_of_track)) == len(set(sa.target_of_track)) + 1


_CHILD = r"""
import sys, time
import pandas as pd
from wakeline.core import review as R
from wakeline.core.review_store import ReviewStore
props = pd.read_csv(sys.argv[2], dtype={c: str for c in ("proposal", "sensor_a", "batch_a", "sensor_b", "batch_b", "runner_up", "runner_up_side")}, keep_default_na=False)
tracks = pd.read_csv(sys.argv[3], dtype={"sensor": str, "batch": str})
st = R.ReviewState(tracks, props)
store = ReviewStore(sys.argv[1])
store.save_queue(st, {"run": "test"})
store.apply(st, R.reject(st, props["proposal"][0]))
store.apply(st, R.merge(st, [tracks["track"][0], tracks["track"][1]]))
ch = store.apply(st, R.accept(st, props["proposal"][1]))
store.apply(st, ch.inverse())  # undo
print("decided", flush=True)
time.sleep(60)
"""


def test_decisions_survive_a_killed_process(scene, tmp_path):
    seg, _ = scene
    ap, _ = R.association_proposals(associate_interrupted(seg))
    tracks = R.track_table(seg)
    ap.to_csv(tmp_path / "p.csv", index=False)
    tracks.to_csv(tmp_path / "t.csv", index=False)
    db = tmp_path / "project.wakeline"
    proc = subprocess.Popen(
        [sys.executable, "-c", _CHILD, str(db), str(tmp_path / "p.csv"), str(tmp_path / "t.csv")],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout.readline().strip() == "decided"
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(10)
        proc.stdout.close()
    with ReviewStore(db) as store:
        assert store.decision_count() == 4
        assert store.params() == {"run": "test"}
        st = store.load()
    # The same decisions made here give the same state.
    mine = R.ReviewState(tracks, ap)
    mine.apply(R.reject(mine, ap["proposal"][0]))
    mine.apply(R.merge(mine, [tracks["track"][0], tracks["track"][1]]))
    ch = mine.apply(R.accept(mine, ap["proposal"][1]))
    mine.apply(ch.inverse())
    assert _snapshot(st) == _snapshot(mine)
    assert st.log_table()["action"].tolist() == ["reject", "merge", "accept", "undo accept"]
    # Rejected, then its two tracks merged by hand: the merge took it back (accepted).
    assert st.status_of(ap["proposal"][0]) == "accepted"
    assert not st.links


def test_review_tables_survive_a_project_save_by_rename(state, tmp_path):
    from wakeline.core.review_store import copy_review

    old, new = tmp_path / "p.wakeline", tmp_path / "p.new"
    with ReviewStore(old) as store:
        store.save_queue(state)
        store.apply(state, R.reject(state, state.proposals["proposal"][0]))
    assert copy_review(old, new) == 1
    with ReviewStore(new) as store:
        assert store.load().status_of(state.proposals["proposal"][0]) == "rejected"
    assert copy_review(tmp_path / "absent", new) == 0


def test_review_store_load_repairs_an_old_stores_rows_once(state, tmp_path):
    """ReviewStore.load (the review demo's store) did not migrate: a row rejected, then
    its tracks merged by hand by an older Wakeline (a manual link, the row left
    ``rejected``), stayed rejected beside one target. It gets the project's repair: one
    ``repair`` decision, applied, logged and written at once; the store is then marked
    checked and reloads with nothing more to repair."""
    import sqlite3

    from wakeline.core.review_store import CHECKED

    db = tmp_path / "old.wakeline"
    pid = state.proposals["proposal"][0]
    a, b = state.track_a[0], state.track_b[0]
    with ReviewStore(db) as store:
        store.save_queue(state)
        store.apply(state, R.reject(state, pid))
        old_merge = R.Change("merge", "", (a, b), links_added=frozenset({R.pair_key(a, b)}))
        store.apply(state, old_merge)  # as the old merge stored it
    assert R.cut_inside_targets(state) == [pid]
    con = sqlite3.connect(db)
    with con:
        con.execute("DELETE FROM review_meta WHERE key = ?", (CHECKED,))  # an old store
    con.close()
    with ReviewStore(db) as store:
        st = store.load()
        assert store.decision_count() == 3
    assert st.status_of(pid) == "accepted" and not st.links
    assert st.log_table()["action"].tolist() == ["reject", "merge", "repair"]
    assert (st.target_of_track() == state.target_of_track()).all()
    with ReviewStore(db) as store:
        again = store.load()
        assert store.decision_count() == 3
    assert _snapshot(again) == _snapshot(st)
    # today's store: the same rows marked checked (as recorded) are replayed, not repaired
    with ReviewStore(tmp_path / "new.wakeline") as store:
        fresh = R.ReviewState(state.tracks, state.proposals)
        store.save_queue(fresh)
        store.apply(fresh, R.reject(fresh, pid))
        store.apply(fresh, old_merge)
        assert store.load().status_of(pid) == "rejected" and store.decision_count() == 2


def test_store_reports_a_bad_file(tmp_path):
    bad = tmp_path / "x.wakeline"
    bad.write_bytes(b"not a database at all" * 100)
    with pytest.raises(InputError, match="not a usable project"):
        ReviewStore(bad)


def test_a_fused_target_keeps_one_name_pending_accepted_and_reopened(scene):
    """h168 D-review-2: a fused target was "T0001" while its proposal was pending (the
    engine's name) and "RADAR1:17" once accepted (the review's): both now name it after
    its earliest track."""
    _, multi = scene
    sa = associate_sensors(multi)
    fp, _ = R.fusion_proposals(sa)
    st = R.ReviewState(R.track_table(multi), fp)
    engine = fuse(sa)
    pending = fused_tracks(st, sa)
    assert set(engine["batch"]) == set(pending["batch"]) == set(st.target_of_track())
    pid = fp["proposal"][0]
    st.apply(R.accept(st, pid))
    assert set(fused_tracks(st, sa)["batch"]) == set(engine["batch"])


def test_export_honours_decisions(scene, tmp_path):
    gpxpy = pytest.importorskip("gpxpy")
    _, multi = scene
    sa = associate_sensors(multi)
    fp, _ = R.fusion_proposals(sa)
    st = R.ReviewState(R.track_table(multi), fp)
    st.apply(R.reject(st, fp["proposal"][0]))
    fused = fused_tracks(st, sa)
    assert fused["batch"].nunique() == st.targets()["target"].nunique()
    assert set(fused["batch"]) == set(st.target_of_track())
    merged = merged_tracks(st, multi)
    assert len(merged) == len(multi) and (merged["sensor"] == "merged").all()
    # each row's own sensor kept beside source_track (a sensor may hold a ':')
    own = merged["source_track"].str.split(":", n=1).str[0]
    assert (merged["source_sensor"] == own).all()
    assert set(merged["source_sensor"]) == set(multi["sensor"].astype(str))
    export_tracks(fused, tmp_path / "f.gpx")
    g = gpxpy.parse((tmp_path / "f.gpx").read_text(encoding="utf-8"))
    assert len(g.tracks) == fused["batch"].nunique()
    assert sum(len(t.segments[0].points) for t in g.tracks) == len(fused)
    export_tracks(merged, tmp_path / "m.geojson")
    gj = json.loads((tmp_path / "m.geojson").read_text(encoding="utf-8"))
    # one feature per member track, with its target (h186: every format alike)
    assert {f["properties"]["target"] for f in gj["features"]} == set(st.target_of_track())
    assert len(gj["features"]) == multi.groupby(["sensor", "batch"]).ngroups
    named = merged.assign(members="船" + merged["members"])
    export_tracks(named, tmp_path / "m.csv", bom=True)
    raw = (tmp_path / "m.csv").read_bytes()
    assert raw.startswith(b"\xef\xbb\xbf") and "船".encode() in raw
    export_decision_log(st, tmp_path / "log.csv")
    log = pd.read_csv(tmp_path / "log.csv")
    assert log["action"].tolist() == ["reject"] and log["proposal"][0] == fp["proposal"][0]
    with pytest.raises(InputError, match="unknown export format"):
        export_tracks(merged, tmp_path / "m.kml")


def test_cli_review_matches_the_core_session(scene, tmp_path, capsys):
    seg, multi = scene
    radar = tmp_path / "seg.csv"
    write_points(seg, radar)
    assert (
        main(
            [
                "associate",
                str(radar),
                "-o",
                str(tmp_path / "a.csv"),
                "--proposals",
                str(tmp_path / "ap.csv"),
            ]
        )
        == 0
    )
    ap = pd.read_csv(tmp_path / "ap.csv", dtype=str, keep_default_na=False)
    for col in (
        "proposal",
        "sensor_a",
        "batch_a",
        "sensor_b",
        "batch_b",
        "cost",
        "gap_s",
        "distance_m",
        "margin",
    ):
        assert col in ap.columns
    tr = R.track_table(seg)["track"].tolist()
    sa, ba = tr[0].split(":")
    sb, bb = tr[5].split(":")
    sc, bc = ap["sensor_b"][3], ap["batch_b"][3]
    (tmp_path / "d.csv").write_text(
        "proposal,decision,sensor_a,batch_a,sensor_b,batch_b\n"
        f"{ap['proposal'][0]},reject,,,,\n{ap['proposal'][1]},accept,,,,\n"
        f",merge,{sa},{ba},{sb},{bb}\n,split,{sc},{bc},,\n",
        encoding="utf-8",
    )
    out = tmp_path / "out.csv"
    assert (
        main(
            [
                "review",
                str(radar),
                "-o",
                str(out),
                "--proposals",
                str(tmp_path / "ap.csv"),
                "--decisions",
                str(tmp_path / "d.csv"),
                "--log",
                str(tmp_path / "log.csv"),
            ]
        )
        == 0
    )
    assert "decisions" in capsys.readouterr().err
    got = pd.read_csv(out, dtype={"batch": str, "target": str})
    # The same decisions as commands in a session.
    st = R.ReviewState(
        R.track_table(seg),
        R.read_proposals(
            pd.read_csv(
                tmp_path / "ap.csv",
                dtype={"batch_a": str, "batch_b": str, "runner_up": str},
                keep_default_na=False,
            )
        ),
    )
    st.apply(R.reject(st, ap["proposal"][0]))
    st.apply(R.accept(st, ap["proposal"][1]))
    st.apply(R.merge(st, [tr[0], tr[5]]))
    st.apply(R.split_track(st, f"{sc}:{bc}"))
    want = st.targets().set_index("track")["target"]
    lab = got["sensor"].astype(str) + ":" + got["batch"]
    assert (got["target"].to_numpy() == want.reindex(lab).to_numpy()).all()
    assert len(pd.read_csv(tmp_path / "log.csv")) == 4
    # Bad decisions: exit 2 with the line.
    (tmp_path / "bad.csv").write_text("proposal,decision\nA0001,maybe\n", encoding="utf-8")
    assert (
        main(
            [
                "review",
                str(radar),
                "-o",
                str(out),
                "--proposals",
                str(tmp_path / "ap.csv"),
                "--decisions",
                str(tmp_path / "bad.csv"),
            ]
        )
        == 2
    )
    assert "line 2" in capsys.readouterr().err
    ap_csv = str(tmp_path / "ap.csv")
    assert main(["review", str(radar), "-o", str(out), "--proposals", ap_csv, ap_csv]) == 2
    assert "appears twice" in capsys.readouterr().err
    # The flag given twice reads both tables (operator test: the first was dropped).
    twice = ["--proposals", ap_csv, "--proposals", ap_csv]
    assert main(["review", str(radar), "-o", str(out), *twice]) == 2
    assert "appears twice" in capsys.readouterr().err
    # A decisions row with a field too many, a proposal joining a track to itself: each
    # one clear message (fuzzing: "unknown decision ''", and the self-join accepted).
    (tmp_path / "extra.csv").write_text("proposal,decision\nA0001,accept,x\n", encoding="utf-8")
    argv = ["review", str(radar), "-o", str(out), "--proposals", ap_csv]
    assert main([*argv, "--decisions", str(tmp_path / "extra.csv")]) == 2
    assert "line 2 of the decisions table has 3 fields, the header 2" in capsys.readouterr().err
    # Lines, not records: a quoted note over two lines before the bad row; a field over
    # the csv module's 128 KB limit is a message, not an internal error.
    (tmp_path / "ml.csv").write_text(
        'proposal,decision\nA0001,"accept\nlater"\n\nA0002,reject,x\n', encoding="utf-8"
    )
    assert main([*argv, "--decisions", str(tmp_path / "ml.csv")]) == 2
    assert "line 5 of the decisions table has 3 fields" in capsys.readouterr().err
    (tmp_path / "big.csv").write_text(f"proposal,decision\nA0001,{'x' * 200_000}\n")
    assert main([*argv, "--decisions", str(tmp_path / "big.csv")]) == 2
    assert "cannot read the decisions table (field larger" in capsys.readouterr().err
    selfjoin = pd.read_csv(ap_csv, dtype=str, keep_default_na=False).head(1)
    selfjoin["sensor_b"], selfjoin["batch_b"] = selfjoin["sensor_a"], selfjoin["batch_a"]
    selfjoin.to_csv(tmp_path / "self.csv", index=False)
    assert (
        main(["review", str(radar), "-o", str(out), "--proposals", str(tmp_path / "self.csv")]) == 2
    )
    assert "to itself" in capsys.readouterr().err


def test_fuse_takes_one_file_per_sensor(scene, tmp_path, capsys):
    _, multi = scene
    files = []
    for name, part in multi.groupby("sensor"):
        f = tmp_path / f"scene_{name}.csv"
        write_points(part.assign(sensor="S1"), f)  # both files name their sensor S1
        files.append(str(f))
    out = tmp_path / "fused.csv"
    assert main(["fuse", *files, "-o", str(out), "--proposals", str(tmp_path / "fp.csv")]) == 0
    fp = pd.read_csv(tmp_path / "fp.csv", dtype=str)
    assert set(fp["sensor_a"]) | set(fp["sensor_b"]) == {"AIS", "R1"}
    assert len(fp) >= 4
    fused = pd.read_csv(out)
    assert fused["members"].str.contains(r"\+").any()
    assert main(["fuse", files[0], "-o", str(out)]) == 2
    assert "two sensors" in capsys.readouterr().err


def test_combine_sources_names():
    assert R._distinct_parts(["scene-0_error_0_AIS", "scene-0_error_0_radar"]) == ["AIS", "radar"]
    assert R._distinct_parts(["a", "a"]) == ["a", "a"]
    # whole words, never parts of one (review of session 21: radar1/radar2 became 1 / 2)
    assert R._distinct_parts(["radar1", "radar2"]) == ["radar1", "radar2"]
    assert R._distinct_parts(["run_radar1_x", "run_radar2_x"]) == ["radar1", "radar2"]
    assert R.distinct_folders(["d/radar1/tracks.csv", "d/radar2/tracks.csv"]) == [
        "radar1",
        "radar2",
    ]
    assert R.distinct_folders(["a/x/t.csv", "b/x/t.csv"]) == ["a/x", "b/x"]
    assert R.distinct_folders(["t.csv", "t.csv"]) == ["", ""]  # one file twice
    assert R.source_names(
        ["tracks", "tracks", "o"], ["d/radar1/tracks.csv", "d/radar2/tracks.csv", "o.csv"]
    ) == ["radar1", "radar2", "o"]
    a = pd.DataFrame({"sensor": ["X"], "batch": ["1"]})
    b = pd.DataFrame({"sensor": ["Y"], "batch": ["1"]})
    assert R.combine_sources([("f1", a), ("f2", b)])["sensor"].tolist() == ["X", "Y"]


@pytest.mark.real
def test_mtad_two_files_fuse_review_export(tmp_path, capsys):
    ais = real_file("mtad-dtwcm", "two_sensor", "scene-7_error_0_AIS.csv")
    radar = real_file("mtad-dtwcm", "two_sensor", "scene-7_error_0_radar.csv")
    fp_csv = tmp_path / "fp.csv"
    assert (
        main(
            [
                "fuse",
                str(ais),
                str(radar),
                "-o",
                str(tmp_path / "f.csv"),
                "--proposals",
                str(fp_csv),
            ]
        )
        == 0
    )
    fp = pd.read_csv(fp_csv, dtype=str)
    assert len(fp) == 6 and set(fp["sensor_a"]) == {"AIS"} and set(fp["sensor_b"]) == {"radar"}
    (tmp_path / "d.csv").write_text(
        f"proposal,decision\n{fp['proposal'][0]},reject\n", encoding="utf-8"
    )
    gpx = tmp_path / "out.gpx"
    assert (
        main(
            [
                "review",
                str(ais),
                str(radar),
                "-o",
                str(gpx),
                "--fused",
                "--proposals",
                str(fp_csv),
                "--decisions",
                str(tmp_path / "d.csv"),
            ]
        )
        == 0
    )
    assert "7 targets" in capsys.readouterr().err
    assert gpx.read_text(encoding="utf-8").count("<trk>") == 7


def test_course_and_speed_are_unknown_between_single_fixes():
    # Two single fixes 300 s apart: a join priced on reachability alone. Its evidence
    # must not claim Δcourse 0° and Δspeed 0 kn: neither end shows its motion.
    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    df = pd.DataFrame(
        {
            "sensor": "R1",
            "batch": ["1", "2"],
            "time": [t0, t0 + pd.Timedelta(seconds=300)],
            "lon": [122.5, 122.51],
            "lat": [30.5, 30.5],
        }
    )
    ap, _ = R.association_proposals(associate_interrupted(df))
    assert len(ap) == 1
    assert np.isnan(ap["dcourse_deg"][0]) and np.isnan(ap["dspeed_kn"][0])
    assert ap["gap_s"][0] == pytest.approx(300.0)


def test_a_moored_ships_chain_shows_no_negative_margin():
    # The pieces of a moored ship lie at one spot: a join skipping a step of the chain is
    # as cheap as the step itself, and as the runner-up it gave sound joins margins of
    # -0.04 to -0.0006 (found by a review). A candidate within one target is no rival.
    from test_associate import _moored

    df = _moored(1, {"A": (0.0, 0.0), "B": (400.0, 0.0)}, True)
    props, _ = R.association_proposals(associate_interrupted(df))
    assert len(props) == 10
    assert (props["margin"] > 0).all()
    truth = df.groupby("batch")["truth"].first()
    rival = props["runner_up"].str.split(":").str[1]
    mine = props["batch_a"].where(props["runner_up_side"] == "a", props["batch_b"])
    has = rival.notna() & (rival != "")
    assert (truth[rival[has]].to_numpy() != truth[mine[has]].to_numpy()).all()


def test_proposals_read_back_take_a_cell_that_is_no_number_as_unknown():
    # A hand-edited or foreign proposals CSV: text in a number column reads as NaN (the
    # evidence line then leaves it out) instead of failing when the evidence is shown.
    df = pd.DataFrame(
        {
            "proposal": ["A0001"],
            "sensor_a": ["R"],
            "batch_a": ["1"],
            "sensor_b": ["R"],
            "batch_b": ["2"],
            "cost": ["0.4"],
            "gap_s": ["n/a"],
            "spread": [""],
        }
    )
    out = R.read_proposals(df)
    assert out["cost"].iloc[0] == 0.4
    assert np.isnan(out["gap_s"].iloc[0]) and np.isnan(out["spread"].iloc[0])
    assert np.isnan(out["end_accel_ms2"].iloc[0])


def test_proposal_pieces_across_the_antimeridian_stay_continuous():
    # a piece crossing 180° was a line across the whole world, and the view zoomed to it
    from wakeline.app.review_map import _continuous

    lon = np.array([179.8, 179.95, -179.9, -179.7])
    out = _continuous(lon)
    assert np.all(np.diff(out) > 0) and out[-1] == pytest.approx(180.3)
    assert _continuous(np.array([5.0]))[0] == 5.0


def test_a_proposal_across_the_antimeridian_is_drawn_in_its_layers_band():
    """MTAD scene 7 moved so 180° lies between the first points of AIS:1 and radar:1
    (proposal AIS:1 → radar:1): each piece was continuous from its own first point, so
    the two tracks lay 360° apart (the view zoomed to −200…200°), and off the band its
    layer is drawn in. Now the pieces are in the layer's band ([0, 360) here, as the map
    and the demo's context draw the points), however the geometry is made: from the
    whole table (the review demo), from the members' points with the layer's band (the
    dock before its arrays), or from the dock's arrays."""
    from conftest import MTAD7_AIS1_START, MTAD7_RADAR1_START, mtad_on_180
    from wakeline.app.map_draw import nan_separated
    from wakeline.app.review_dock import track_arrays
    from wakeline.app.review_map import proposal_geometry, proposal_members, tracks_geometry
    from wakeline.core.review_session import sorted_by_track

    pts = mtad_on_180(0.5 * (MTAD7_AIS1_START + MTAD7_RADAR1_START))
    props = R.fusion_proposals(associate_sensors(pts))[0]
    state = R.ReviewState(R.track_table(pts), props)
    (pid,) = [
        p for p, a, b in zip(props["proposal"], state.track_a, state.track_b, strict=True)
        if {a, b} == {"AIS:1", "radar:1"}
    ]  # fmt: skip
    geom = proposal_geometry(state, pts, pid)
    lon = np.concatenate([p.lon for p in geom.pieces])
    assert 179.5 < lon.min() and lon.max() < 180.5  # one band, about 180°
    x0, _, x1, _ = geom.bounds
    assert x1 - x0 < 0.5  # was ~360
    context, _ = nan_separated(pts)  # the demo's grey context, the map's band
    assert np.nanmin(context) - 1e-9 <= lon.min() and lon.max() <= np.nanmax(context) + 1e-9
    members = proposal_members(state, pid)
    lab = pts["sensor"].astype(str) + ":" + pts["batch"].astype(str)
    before = proposal_geometry(state, pts[lab.isin(members)], pid, lon_west=0.0)
    sorted_pts, ranges = sorted_by_track(pts)
    t, alon, alat, west = track_arrays(sorted_pts, ranges)
    assert west == 0.0
    arrays = tracks_geometry(
        state, pid, {m: (t[slice(*ranges[m])], alon[slice(*ranges[m])], alat[slice(*ranges[m])]) for m in members}, lon_west=west
    )  # fmt: skip
    for g in (before, arrays):
        assert [p.track for p in g.pieces] == [p.track for p in geom.pieces]
        for a, b in zip(g.pieces, geom.pieces, strict=True):
            assert np.allclose(a.lon, b.lon) and np.allclose(a.lat, b.lat)

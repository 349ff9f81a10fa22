"""Review widgets (issue 13), offscreen: the queue panel and its keyboard flow, undo and
redo through QUndoStack, the Gantt chart, the candidate network, the map geometry of a
proposal, the store behind the controller, and 1,000 proposals staying responsive."""

import time

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtCore, QtWidgets  # noqa: E402

from wakeline.app import review_text as T  # noqa: E402
from wakeline.app.review_demo import ReviewWorkspace  # noqa: E402
from wakeline.app.review_demo import main as demo_main  # noqa: E402
from wakeline.app.review_map import (  # noqa: E402
    MUTED,
    PAIR_COLORS,
    proposal_geometry,
    proposal_items,
)
from wakeline.app.review_model import COLUMNS, cell_text  # noqa: E402
from wakeline.app.review_panel import ReviewPanel  # noqa: E402
from wakeline.app.review_undo import ReviewController  # noqa: E402
from wakeline.app.review_views import GanttView, NetworkView  # noqa: E402
from wakeline.core import review as R  # noqa: E402
from wakeline.core.associate import associate_interrupted  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.review_store import ReviewStore  # noqa: E402
from wakeline.core.simulate import review_queue, segments_scene  # noqa: E402

pytestmark = pytest.mark.gui


@pytest.fixture(scope="module")
def scene():
    pts = segments_scene(seed=2, n_ships=8, area_km=15)
    ap, _ = R.association_proposals(associate_interrupted(pts))
    return pts, ap


@pytest.fixture
def controller(scene):
    pts, ap = scene
    return ReviewController(R.ReviewState(R.track_table(pts), ap))


@pytest.fixture
def panel(qtbot, controller):
    p = ReviewPanel(controller)
    qtbot.addWidget(p)
    p.resize(700, 500)
    p.show()
    p.view.setFocus()
    return p


def _key(qtbot, panel, key, mod=QtCore.Qt.KeyboardModifier.NoModifier):
    qtbot.keyClick(panel.view, key, mod)


def test_keyboard_flow_and_undo(qtbot, panel, controller):
    st = controller.state
    texts = {a.text() for a in panel.actions}
    assert {
        "Next proposal",
        "Previous proposal",
        "Accept",
        "Reject",
        "Split track",
        "Merge",
    } <= texts
    assert all(not a.shortcut().isEmpty() for a in panel.actions)
    panel.sort_box.setCurrentIndex(2)  # by id
    first = panel.current()
    assert first == "A0001"
    _key(qtbot, panel, QtCore.Qt.Key.Key_A)
    assert st.status_of(first) == "accepted"
    second = panel.current()
    assert second != first  # moved on
    _key(qtbot, panel, QtCore.Qt.Key.Key_R)
    assert st.status_of(second) == "rejected"
    _key(qtbot, panel, QtCore.Qt.Key.Key_K)
    assert panel.current() == second
    _key(qtbot, panel, QtCore.Qt.Key.Key_J)
    _key(qtbot, panel, QtCore.Qt.Key.Key_S)  # track B leaves its target
    pid = panel.current()
    b = st.proposals.set_index("proposal").loc[pid, "track_b"]
    assert st.members(st.target(b)) == [b]
    # Fix one by hand: merge the rejected pair back.
    panel.set_current(second)
    _key(qtbot, panel, QtCore.Qt.Key.Key_M)
    a2, b2 = st.proposals.set_index("proposal").loc[second, ["track_a", "track_b"]]
    assert st.target(a2) == st.target(b2)
    assert controller.stack.count() == 4
    # Undo the merge: apart again; redo: together.
    _key(qtbot, panel, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert st.target(a2) != st.target(b2)
    panel.act_redo.trigger()
    assert st.target(a2) == st.target(b2)
    for _ in range(4):
        panel.act_undo.trigger()
    assert set(st.status) == {"pending"} and not st.links
    assert [e.action for e in st.log][-4:] == [
        "undo merge",
        "undo split track",
        "undo reject",
        "undo accept",
    ]


def test_queue_sorts_and_filters(qtbot, panel, controller):
    st = controller.state
    margins = st.proposals["margin"].to_numpy()
    panel.sort_box.setCurrentIndex(0)
    assert panel.current() in st.proposals["proposal"][margins == margins.min()].tolist() or True
    top = panel.model.ids[panel.proxy.mapToSource(panel.proxy.index(0, 0)).row()]
    assert st.proposals.set_index("proposal").loc[top, "margin"] == margins.min()
    panel.sort_box.setCurrentIndex(1)
    top = panel.model.ids[panel.proxy.mapToSource(panel.proxy.index(0, 0)).row()]
    assert st.proposals.set_index("proposal").loc[top, "cost"] == st.proposals["cost"].max()
    controller.reject("A0003")
    controller.reject("A0004")
    panel.status_box.setCurrentText("rejected")
    assert panel.proxy.rowCount() == 2
    panel.status_box.setCurrentText("pending")
    assert panel.proxy.rowCount() == len(st.proposals) - 2
    panel.status_box.setCurrentText("all")
    panel.sensor_box.setCurrentText("nope") if False else panel.sensor_box.setCurrentIndex(1)
    assert panel.proxy.rowCount() == len(st.proposals)  # one sensor: all its proposals
    assert "2 rejected" in panel.counts.text()
    assert panel.set_current("A0003") and "A0003" in panel.evidence.text()


def test_gantt_and_network_show_the_members(qtbot, controller):
    st = controller.state
    # A proposal whose target has 3 or more tracks and a runner-up nearby.
    tg = pd.Series(st.target_of_track()).value_counts()
    big = tg.index[0]
    assert tg.iloc[0] >= 3
    members = st.members(big)
    pid = st.proposals_of_track(members[1])[0]
    gantt = GanttView(st)
    net = NetworkView(st)
    for w in (gantt, net):
        qtbot.addWidget(w)
        w.resize(500, 400)
        w.show()
    gantt.show_proposal(pid)
    assert gantt.members == members and gantt.rows[: len(members)] == members
    gantt.set_time(float(st.tracks["t0"].mean()))
    assert abs(gantt.time() - float(st.tracks["t0"].mean())) < 1e-6
    with qtbot.waitSignal(gantt.time_changed):
        gantt.cursor.setValue(gantt.cursor.value() + 1.0)
    net.show_proposal(pid)
    assert set(members) <= set(net.pos)
    # Minutes are labelled as minutes on any span (not "kmin" on days of data).
    gantt.setXRange(0, 5000, padding=0)
    axis = gantt.getAxis("bottom")
    assert axis.autoSIPrefixScale == 1.0 and "kmin" not in axis.labelString()
    edges = net.edges
    assert pid in set(edges["proposal"])
    # Click the middle of another proposal's edge: that proposal is chosen.
    other = [p for p in edges["proposal"][~edges["kind"].isin(["runner-up", "manual"])] if p != pid]
    target = other[0] if other else pid
    x, y = net.edge_midpoint(target)
    assert net.edge_at(x, y) == target
    vb = net.getPlotItem().getViewBox()
    scene_pt = vb.mapViewToScene(QtCore.QPointF(x, y))
    widget_pt = net.mapFromScene(scene_pt)
    with qtbot.waitSignal(net.proposal_clicked) as sig:
        qtbot.mouseClick(net.viewport(), QtCore.Qt.MouseButton.LeftButton, pos=widget_pt)
    assert sig.args == [target]


@pytest.mark.parametrize("size", [(300, 260), (500, 400), (260, 420)])
def test_network_names_stay_inside_the_view(qtbot, controller, size):
    """Operator test: on the ATD AIS in a narrow Review dock the candidate network cut
    its track names at the left and right edges ("…378113585"): the view was a fixed
    ±1.6 around the circle and the names are pixels. Every name is now whole in view,
    after a resize too."""
    st = controller.state
    pid = st.proposals["proposal"].iloc[0]
    net = NetworkView(st)
    qtbot.addWidget(net)
    net.resize(*size)
    net.show()
    qtbot.waitExposed(net)
    net.show_proposal(pid)
    for step in (size, (size[0] - 60, size[1])):
        net.resize(*step)
        QtWidgets.QApplication.processEvents()
        QtWidgets.QApplication.processEvents()
        view = net.getPlotItem().getViewBox().sceneBoundingRect().adjusted(-1, -1, 1, 1)
        names = [t for t in net._names.items if t.isVisible() and t.toPlainText()]
        assert names
        for t in names:
            assert view.contains(t.sceneBoundingRect()), (
                t.toPlainText(),
                t.sceneBoundingRect(),
                view,
            )


def test_map_geometry_of_a_proposal(scene, controller):
    pts, ap = scene
    st = controller.state
    # the longest gap whose predicted path bends off the straight connector (one on its
    # line is left out: the connector's dashes alone, test below)
    rows = (ap.iloc[int(k)] for k in np.argsort(-ap["gap_s"].to_numpy()))
    row = next(r for r in rows if proposal_geometry(st, pts, r["proposal"]).predicted is not None)
    geom = proposal_geometry(st, pts, row["proposal"])
    names = [p.track for p in geom.pieces]
    assert set(names) == set(st.members(st.target(f"{row['sensor_a']}:{row['batch_a']}")))
    # The proposal's two tracks in the pair's colours (old, new); other members muted.
    ta, tb = (f"{row[f'sensor_{k}']}:{row[f'batch_{k}']}" for k in "ab")
    colors = {p.track: p.color for p in geom.pieces if not p.context}
    assert colors == {ta: PAIR_COLORS[0], tb: PAIR_COLORS[1]}
    assert {p.color for p in geom.pieces if p.context} <= {MUTED}
    given = {ta: "#9467bd", tb: "#8c564b"}
    recoloured = proposal_geometry(st, pts, row["proposal"], given)
    assert {p.track: p.color for p in recoloured.pieces if not p.context} == given
    a = pts[(pts["sensor"] == row["sensor_a"]) & (pts["batch"] == row["batch_a"])].sort_values(
        "time"
    )
    b = pts[(pts["sensor"] == row["sensor_b"]) & (pts["batch"] == row["batch_b"])].sort_values(
        "time"
    )
    lon, lat = geom.predicted
    assert np.allclose([lon[0], lat[0]], [a["lon"].iloc[-1], a["lat"].iloc[-1]], atol=1e-6)
    assert np.allclose([lon[-1], lat[-1]], [b["lon"].iloc[0], b["lat"].iloc[0]], atol=1e-6)
    assert np.allclose(geom.connector[0], [a["lon"].iloc[-1], b["lon"].iloc[0]])
    items = proposal_items(geom)
    assert len(items) == 2 * len(geom.pieces) + 2
    # A rejected proposal still shows both of its tracks.
    controller.reject(row["proposal"])
    geom = proposal_geometry(st, pts, row["proposal"])
    assert {row["sensor_a"] + ":" + row["batch_a"], row["sensor_b"] + ":" + row["batch_b"]} <= {
        p.track for p in geom.pieces
    }


def test_gui_session_gives_the_cli_targets(scene, controller):
    pts, ap = scene
    st = controller.state
    tr = st.tracks["track"].tolist()
    controller.reject(ap["proposal"][0])
    controller.accept(ap["proposal"][1])
    controller.merge([tr[0], tr[5]])
    controller.split_track(ap["track_b"][3] if "track_b" in ap else st.proposals["track_b"][3])
    sb, bb = st.proposals["track_b"][3].split(":")
    d = pd.DataFrame(
        {
            "proposal": [ap["proposal"][0], ap["proposal"][1], "", ""],
            "decision": ["reject", "accept", "merge", "split"],
            "sensor_a": ["", "", tr[0].split(":")[0], sb],
            "batch_a": ["", "", tr[0].split(":")[1], bb],
            "sensor_b": ["", "", tr[5].split(":")[0], ""],
            "batch_b": ["", "", tr[5].split(":")[1], ""],
        }
    )
    cli = R.apply_decisions(R.ReviewState(R.track_table(pts), ap), d)
    assert (cli.target_of_track() == st.target_of_track()).all()


def test_controller_writes_every_decision_and_reopens(scene, tmp_path, qtbot):
    pts, ap = scene
    db = tmp_path / "p.wakeline"
    store = ReviewStore(db)
    ctl = ReviewController(R.ReviewState(R.track_table(pts), ap), store)
    store.save_queue(ctl.state)
    ctl.accept("A0001")
    ctl.reject("A0002")
    ctl.stack.undo()
    # three tracks of three targets (tracks of one target merged change nothing)
    tg = ctl.state.target_of_track()
    firsts = pd.Series(ctl.state.tracks["track"].to_numpy()).groupby(tg).first()[:3].tolist()
    ctl.merge(firsts)
    assert store.decision_count() == 4
    n = ctl.stack.count()
    ctl.merge(firsts)  # again: nothing to change, no step to undo, nothing written
    ctl.accept("A0001")
    assert store.decision_count() == 4 and ctl.stack.count() == n
    want = ctl.state.target_of_track().copy()
    store.close()
    with ReviewStore(db) as again:
        st = again.load()
    assert (st.target_of_track() == want).all()
    assert st.status_of("A0001") == "accepted" and st.status_of("A0002") == "pending"
    panel = ReviewPanel(ReviewController(st))
    qtbot.addWidget(panel)
    assert "1 accepted" in panel.counts.text()


def test_queue_columns_are_sized_without_reading_every_row(qtbot, controller, monkeypatch):
    """The columns are sized from the digest's few widest texts (font metrics), not by
    resizeColumnsToContents asking the model for 200 rows x 10 columns on the GUI thread
    (97-306 ms when ATD's proposals arrived); the widths still fit the widest texts."""
    from wakeline.app.review_model import ProposalModel, queue_digest

    asked = []
    real = ProposalModel.data

    def counting(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            asked.append(index.row())
        return real(self, index, role)

    monkeypatch.setattr(ProposalModel, "data", counting)
    digest = queue_digest(controller.state)
    p = ReviewPanel(controller, digest=digest)
    qtbot.addWidget(p)
    assert len(asked) <= 10  # before: every column of every row (precision 200)
    fm = p.view.fontMetrics()
    st = controller.state
    for col, name in ((2, "track_a"), (3, "track_b"), (0, "proposal")):
        widest = max(st.proposals[name].astype(str), key=fm.horizontalAdvance)
        assert widest in digest.widest[name]
        assert p.view.columnWidth(col) >= fm.horizontalAdvance(widest)
    head = p.view.horizontalHeader()
    assert p.view.columnWidth(4) >= head.fontMetrics().horizontalAdvance("margin")
    assert digest.sensors == sorted(set(st.tracks["sensor"].astype(str)))


def test_queue_sorts_with_numpy_not_by_asking_the_model(qtbot, controller, monkeypatch):
    """Sorting the queue is one numpy sort in the model: the proxy's sort asked ``data``
    for two values per comparison (n log n calls on the GUI thread: 0.5 s at 5,000
    proposals). The order is the proxy's: NaN last ascending, ties in the proposals'
    order; the current proposal stays current."""
    from wakeline.app.review_model import SORT_ROLE, ProposalModel

    asked = []
    real = ProposalModel.data

    def counting(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role == SORT_ROLE:
            asked.append(index.row())
        return real(self, index, role)

    monkeypatch.setattr(ProposalModel, "data", counting)
    panel = ReviewPanel(controller)
    qtbot.addWidget(panel)
    st = controller.state
    p = st.proposals.reset_index(drop=True)
    shown = lambda: [panel.current_at(r) for r in range(panel.proxy.rowCount())]  # noqa: E731
    panel.set_current(p["proposal"].iat[3])
    for col, name, desc in ((5, "cost", True), (4, "margin", False), (3, "track_b", True)):
        panel.view.sortByColumn(
            col, QtCore.Qt.SortOrder.DescendingOrder if desc else QtCore.Qt.SortOrder.AscendingOrder
        )
        key = p[name].fillna(np.inf) if p[name].dtype.kind == "f" else p[name].astype(str)
        rank = key.rank(method="dense").to_numpy()
        ref = p["proposal"].to_numpy()[np.argsort(-rank if desc else rank, kind="stable")]
        assert shown() == ref.tolist(), name
        assert panel.current() == p["proposal"].iat[3]  # the current row moved with it
        evidence = panel.evidence.text()
        assert p["proposal"].iat[3] in evidence
    assert asked == []  # before: the proxy's comparisons, thousands of calls
    controller.reject(p["proposal"].iat[3])
    panel.status_box.setCurrentText("rejected")
    assert shown() == [p["proposal"].iat[3]]


def test_queue_shows_target_dcourse_dspeed_sortable_with_a_column_menu(qtbot, controller):
    """SPEC §7: the merge-review table has the target, Δcourse and Δspeed (units in the
    titles; values from the core's proposal record, sorted as numbers; the target as the
    decisions make it). Less needed columns are hidden by default and the header's
    right-click menu shows them."""
    from wakeline.app.review_panel import HIDDEN_BY_DEFAULT

    names = [n for n, _ in COLUMNS]
    panel = ReviewPanel(controller)
    qtbot.addWidget(panel)
    st = controller.state
    p = st.proposals.reset_index(drop=True)
    head = panel.view.horizontalHeader()
    titles = {
        name: panel.proxy.headerData(col, QtCore.Qt.Orientation.Horizontal)
        for col, name in enumerate(names)
    }
    assert titles["dcourse_deg"] == "Δcourse °" and titles["dspeed_kn"] == "Δspeed kn"
    assert titles["target"] == "target"
    # the target right after the status on screen
    assert head.visualIndex(names.index("target")) == head.visualIndex(names.index("status")) + 1
    m = panel.model
    for name in ("dcourse_deg", "dspeed_kn"):
        assert p[name].notna().any()
        col = names.index(name)
        for r in range(m.rowCount()):
            want = p.set_index("proposal")[name][m.ids[r]]
            assert m.data(m.index(r, col)) == (cell_text(float(want)))
        # sorted as numbers, NaN last, ties in the proposals' order
        panel.view.sortByColumn(col, QtCore.Qt.SortOrder.AscendingOrder)
        shown = [panel.current_at(r) for r in range(panel.proxy.rowCount())]
        key = p[name].astype(float).fillna(np.inf).to_numpy()
        assert shown == p["proposal"].to_numpy()[np.argsort(key, kind="stable")].tolist()
    tcol = names.index("target")
    for r in range(m.rowCount()):
        a = p.set_index("proposal")["track_a"][m.ids[r]]
        assert m.data(m.index(r, tcol)) == st.target(a)
    # a decision changes targets: the column follows
    pid = p["proposal"].iat[0]
    a, b = p["track_a"].iat[0], p["track_b"].iat[0]
    controller.reject(pid)
    row = m.row_of[pid]
    assert m.data(m.index(row, tcol)) == st.target(a) and st.target(a) != st.target(b)
    controller.accept(pid)
    assert m.data(m.index(m.row_of[pid], tcol)) == st.target(b)
    # hidden by default, shown from the header's menu, the choice kept for the next queue
    assert set(HIDDEN_BY_DEFAULT) == {"distance_m", "runner_up"}
    hidden = {n for c, n in enumerate(names) if panel.view.isColumnHidden(c)}
    assert hidden == set(HIDDEN_BY_DEFAULT)
    narrow = panel.table_width()
    menu = panel.column_menu()
    acts = {a.text(): a for a in menu.actions()}
    assert [a.text() for a in menu.actions()][:3] == [
        titles["proposal"],
        titles["status"],
        "target",
    ]
    assert not acts[titles["proposal"]].isEnabled()
    assert not acts[titles["runner_up"]].isChecked() and acts[titles["method"]].isChecked()
    try:
        acts[titles["runner_up"]].setChecked(True)
        assert not panel.view.isColumnHidden(names.index("runner_up"))
        assert panel.table_width() == narrow + panel.view.columnWidth(names.index("runner_up"))
        other = ReviewPanel(controller)
        qtbot.addWidget(other)
        assert not other.view.isColumnHidden(names.index("runner_up"))
        assert other.view.isColumnHidden(names.index("distance_m"))
    finally:
        panel.show_column("runner_up", False)
    assert ReviewPanel.hidden_columns == set(HIDDEN_BY_DEFAULT)


def _rows_agree_with_the_core(panel) -> None:
    """Every row's status is the core's, and a row saying rejected or split never sits
    beside a target holding both its tracks (the evidence line names that target)."""
    st = panel.controller.state
    m = panel.model
    col = [n for n, _ in COLUMNS].index("status")
    tracks = st.proposals.set_index("proposal")[["track_a", "track_b"]]
    for r, pid in enumerate(m.ids):  # the model's rows (in its own sort order since h104)
        status = st.status_of(pid)
        assert m.data(m.index(r, col)) == T.status_name(status), pid
        a, b = tracks.loc[pid]
        joined = st.target(a) == st.target(b)
        assert joined == (status in R.ACTIVE), (pid, status, st.target(a), st.target(b))
    pid = panel.current()
    assert f"({T.status_name(st.status_of(pid))})" in panel.evidence.text()


def test_row_status_follows_split_merge_accept_reject_in_any_order(scene, tmp_path, qtbot):
    pts, ap = scene
    db = tmp_path / "p.wakeline"
    store = ReviewStore(db)
    ctl = ReviewController(R.ReviewState(R.track_table(pts), ap), store)
    store.save_queue(ctl.state)
    panel = ReviewPanel(ctl)
    qtbot.addWidget(panel)
    acts = {
        "split": panel.act_split,
        "merge": panel.act_merge,
        "accept": panel.act_accept,
        "reject": panel.act_reject,
    }
    walks = {  # proposal: the keys pressed on it, in order
        "A0001": ["split", "merge"],
        "A0002": ["merge", "split"],
        "A0003": ["accept", "split"],
        "A0004": ["reject", "merge"],
        "A0005": ["split", "merge", "reject", "merge", "split", "accept"],
    }
    want = {"A0001": "accepted", "A0002": "split", "A0003": "split", "A0004": "accepted"}
    done = 0
    for pid, steps in walks.items():
        for step in steps:
            assert panel.set_current(pid)
            n = ctl.stack.count()
            acts[step].trigger()  # S, M, A, R
            done += ctl.stack.count() - n
            _rows_agree_with_the_core(panel)
        if pid in want:
            assert ctl.state.status_of(pid) == want[pid], pid
    final = list(ctl.state.status)
    for _ in range(done):
        panel.act_undo.trigger()
        _rows_agree_with_the_core(panel)
    assert set(ctl.state.status) == {"pending"} and not ctl.state.links
    for _ in range(done):
        panel.act_redo.trigger()
        _rows_agree_with_the_core(panel)
    assert list(ctl.state.status) == final
    store.close()
    with ReviewStore(db) as again:  # the project reopened
        reopened = ReviewPanel(ReviewController(again.load()))
    qtbot.addWidget(reopened)
    assert list(reopened.controller.state.status) == final
    _rows_agree_with_the_core(reopened)


def test_thousand_proposals_stay_responsive(qtbot):
    n = 1000
    # 1000 two-track ships: old track k, new track k, one proposal each.
    tracks, props = review_queue(n)
    t = time.perf_counter()
    st = R.ReviewState(tracks, props)
    ctl = ReviewController(st)
    panel = ReviewPanel(ctl)
    gantt, net = GanttView(st), NetworkView(st)
    for w in (panel, gantt, net):
        qtbot.addWidget(w)
    panel.current_settled.connect(gantt.show_proposal)
    panel.current_settled.connect(net.show_proposal)
    panel.show()
    panel.activateWindow()
    panel.view.setFocus()
    qtbot.waitUntil(panel.view.hasFocus, timeout=2000)
    build_s = time.perf_counter() - t
    t = time.perf_counter()
    steps = 40
    for _ in range(steps):
        qtbot.keyClick(panel.view, QtCore.Qt.Key.Key_A)
    per_step_ms = 1000 * (time.perf_counter() - t) / steps
    # The views follow once the keys rest: one redraw of Gantt and network.
    t = time.perf_counter()
    with qtbot.waitSignal(panel.current_settled, timeout=5000):
        pass
    redraw_ms = 1000 * (time.perf_counter() - t) - panel.settle_ms
    print(
        f"1,000 proposals: build {build_s:.2f} s, accept + next {per_step_ms:.1f} ms per key, "
        f"Gantt + network redraw {redraw_ms:.0f} ms"
    )
    assert (st.status == "accepted").sum() == steps
    assert gantt.rows and set(net.pos) >= set(gantt.members)
    assert build_s < 10 and per_step_ms < 100  # a shared 2-core machine: generous bounds


def test_workspace_renders(scene, tmp_path, qtbot):
    pts, _ = scene
    f = tmp_path / "radar.csv"
    write_points(pts, f)
    out = tmp_path / "shot.png"
    assert demo_main([str(f), "-o", str(out)]) == 0
    assert out.stat().st_size > 10_000
    ctl = ReviewController(
        R.ReviewState(R.track_table(pts), R.association_proposals(associate_interrupted(pts))[0])
    )
    w = ReviewWorkspace(ctl, pts)
    qtbot.addWidget(w)
    w.network.proposal_clicked.emit("A0002")
    assert w.panel.current() == "A0002"


@pytest.mark.real
def test_operator_reviews_an_mtad_pair_end_to_end(qtbot, tmp_path):
    """Two files (radar, AIS) → associate + fuse proposals → every proposal decided by
    keyboard → one fixed by hand and undone → close → reopen → export."""
    from conftest import real_file
    from wakeline.app.review_demo import build
    from wakeline.core.export_review import export_decision_log, export_tracks, merged_tracks

    radar = real_file("mtad-dtwcm", "two_sensor", "scene-6_error_0_radar.csv")
    ais = real_file("mtad-dtwcm", "two_sensor", "scene-6_error_0_AIS.csv")
    ctl, points = build([radar, ais])
    st = ctl.state
    assert set(st.tracks["sensor"]) == {"AIS", "radar"} and len(st.proposals) >= 10
    db = tmp_path / "review.wakeline"
    ctl.store = ReviewStore(db)
    ctl.store.save_queue(st)
    panel = ReviewPanel(ctl)
    qtbot.addWidget(panel)
    panel.show()
    panel.activateWindow()
    panel.view.setFocus()
    qtbot.waitUntil(panel.view.hasFocus, timeout=2000)
    panel.sort_box.setCurrentIndex(2)
    for k in range(len(st.proposals)):  # reject every fifth, accept the rest
        key = QtCore.Qt.Key.Key_R if k % 5 == 0 else QtCore.Qt.Key.Key_A
        qtbot.keyClick(panel.view, key)
    assert "pending" not in set(st.status)
    rejected = st.proposals["proposal"][st.status == "rejected"].tolist()
    # Fix one by hand: the first rejected pair merged again, then undone.
    panel.set_current(rejected[0])
    qtbot.keyClick(panel.view, QtCore.Qt.Key.Key_M)
    a, b = st.proposals.set_index("proposal").loc[rejected[0], ["track_a", "track_b"]]
    assert st.target(a) == st.target(b)
    panel.act_undo.trigger()
    assert st.target(a) != st.target(b)
    want = st.target_of_track().copy()
    n_decisions = ctl.store.decision_count()
    assert n_decisions == len(st.proposals) + 2
    ctl.store.close()
    with ReviewStore(db) as store:
        again = store.load()
    assert (again.target_of_track() == want).all()
    assert list(again.status) == list(st.status)
    export_tracks(merged_tracks(again, points), tmp_path / "out.gpx")
    export_tracks(again.label_points(points), tmp_path / "out.csv", bom=True)
    export_decision_log(again, tmp_path / "log.csv")
    log = pd.read_csv(tmp_path / "log.csv")
    assert len(log) == n_decisions and log["action"].iloc[-1] == "undo merge"
    assert (tmp_path / "out.gpx").read_text(encoding="utf-8").count("<trk>") == len(set(want))


def test_gantt_labels_stay_inside_a_narrow_chart(qtbot, controller):
    """Operator test (ATD dataset1 in a 350-px Gantt dock): the label of a member that
    starts first ("▶ S1:338219317") ran off the chart's left edge; the time axis now
    leaves room for every label, also after the chart is resized."""
    st = controller.state
    gantt = GanttView(st)
    qtbot.addWidget(gantt)
    gantt.resize(330, 260)
    gantt.show()
    qtbot.waitExposed(gantt)
    vb = gantt.getViewBox()

    def clipped() -> list[str]:
        QtWidgets.QApplication.processEvents()
        gantt.grab()  # paint: the labels take their place for this view
        left = vb.sceneBoundingRect().left()
        return [
            t.textItem.toPlainText()
            for t in gantt._labels.items[: gantt._labels.used]
            if t.sceneBoundingRect().left() < left - 0.5
        ]

    for pid in st.proposals["proposal"][:5]:
        gantt.show_proposal(pid)
        assert not clipped(), pid
    gantt.resize(240, 260)
    assert not clipped()


def test_gantt_keeps_the_operators_zoom_when_resized(qtbot, controller):
    """Review of session 21: every resize fitted the time axis again, so a dock or
    splitter move threw away the operator's pan or zoom. It fits again only while the
    range is the one it set."""
    st = controller.state
    gantt = GanttView(st)
    qtbot.addWidget(gantt)
    gantt.resize(330, 260)
    gantt.show()
    qtbot.waitExposed(gantt)
    gantt.show_proposal(st.proposals["proposal"].iloc[0])
    vb = gantt.getViewBox()
    lo, hi = vb.viewRange()[0]
    vb.setXRange(lo + 0.25 * (hi - lo), hi - 0.25 * (hi - lo), padding=0)  # zoomed in
    zoomed = vb.viewRange()[0]
    gantt.resize(300, 260)
    QtWidgets.QApplication.processEvents()
    assert np.allclose(vb.viewRange()[0], zoomed)
    gantt.show_proposal(st.proposals["proposal"].iloc[-1])  # another proposal: fitted
    assert not np.allclose(vb.viewRange()[0], zoomed)


def test_a_queue_sorted_by_status_moves_a_row_when_its_status_changes(qtbot, controller):
    """The queue sorts itself since session 21 (one numpy sort), and lost the proxy's
    dynamic sort: sorted by status, an accepted row stayed among the pending ones."""
    panel = ReviewPanel(controller)
    qtbot.addWidget(panel)
    col = [n for n, _ in COLUMNS].index("status")
    panel.view.sortByColumn(col, QtCore.Qt.SortOrder.AscendingOrder)
    shown = lambda: [panel.current_at(r) for r in range(panel.proxy.rowCount())]  # noqa: E731
    last = shown()[-1]
    controller.accept(last)  # "accepted" sorts before "pending"
    assert shown()[0] == last
    controller.stack.undo()
    assert shown()[-1] == last


def _overlaps(items) -> list:
    rects = [(t.toPlainText(), t.sceneBoundingRect()) for t in items]
    return [
        (a, b) for k, (a, ra) in enumerate(rects) for b, rb in rects[k + 1 :] if ra.intersects(rb)
    ]


@pytest.mark.parametrize("size", [(175, 250), (300, 260), (500, 400)])
def test_network_labels_do_not_overlap(qtbot, controller, size):
    """Operator test 4 (D-review-1): on Saronic split at gaps, proposal A0009 in the
    Review dock's network view (about 175 × 250 px beside the Gantt chart) drew its edge
    costs and track names on top of each other ("S1:200", "1.16", "0.167 0.00662"). The
    labels are laid out in pixels now: a cost moves beside its edge or is left out (the
    queue has it, and the edge's tooltip); no two shown labels' boxes meet. The proposal
    with the most tracks around it; its own cost always shown."""
    st = controller.state
    net = NetworkView(st)
    qtbot.addWidget(net)
    net.resize(*size)
    net.show()
    qtbot.waitExposed(net)
    pid = max(st.proposals["proposal"], key=lambda p: len(net._nodes(p, 2)[1]))
    assert len(net._nodes(pid, 2)[1]) >= 5
    net.show_proposal(pid)
    QtWidgets.QApplication.processEvents()
    names = [t for t in net._names.items if t.isVisible() and t.toPlainText()]
    costs = [t for t in net._costs.items if t.isVisible() and t.toPlainText()]
    assert costs and names
    k = st._row[pid]
    own = f"{float(st.proposals['cost'].iloc[k]):.3g}"
    assert own in [t.toPlainText() for t in costs]
    assert {st.track_a[k], st.track_b[k]} <= {t.toPlainText() for t in names}
    assert _overlaps(names + costs) == []
    # Each cost stays by its edge: its box's centre within a box's size of the line.
    vb = net.getPlotItem().getViewBox()
    for _rank, item, where, _anchor in net._plan:
        if len(where) == 4 and item.isVisible():
            a = vb.mapViewToScene(QtCore.QPointF(where[0], where[1]))
            b = vb.mapViewToScene(QtCore.QPointF(where[2], where[3]))
            c = item.sceneBoundingRect().center()
            d = np.array([b.x() - a.x(), b.y() - a.y()])
            u = np.clip(np.dot([c.x() - a.x(), c.y() - a.y()], d) / max(d @ d, 1e-9), 0, 1)
            miss = np.hypot(a.x() + u * d[0] - c.x(), a.y() + u * d[1] - c.y())
            box = item.sceneBoundingRect()
            assert miss <= box.width() + box.height(), (item.toPlainText(), miss)
    # Hovering the proposal's edge names it and its cost.
    x, y = net.edge_midpoint(pid)
    net._hover(net.getPlotItem().getViewBox().mapViewToScene(QtCore.QPointF(x, y)))
    assert pid in net.toolTip() and own in net.toolTip()


def test_the_evidence_marks_a_pair_of_plots_and_the_mark_survives_a_project(scene, qtbot, tmp_path):
    """Operator test 8, D1: the review showed the Autoferry plot pairs as comfortable
    joins (margins 731-876 of 1,000) and said nothing of plots."""
    pts, ap = scene
    pid = ap["proposal"].iat[0]
    a = R.track_label(ap["sensor_a"].iat[0], ap["batch_a"].iat[0])
    marked = R.mark_plot_tracks(ap, [a])
    assert marked["plot_tracks"].iat[0] == a and (marked["plot_tracks"].iloc[1:] == "").all()
    state = R.ReviewState(R.track_table(pts), marked)
    path = tmp_path / "q.wakeline"
    with ReviewStore(path) as store:
        store.save_queue(state)
    with ReviewStore(path) as store:
        state = store.load()
    assert state.proposals["plot_tracks"].iat[0] == a
    panel = ReviewPanel(ReviewController(state))
    qtbot.addWidget(panel)
    assert panel.set_current(pid)
    assert "plots, not tracks" in panel.evidence.text() and a in panel.evidence.text()
    other = ap["proposal"].iat[1]
    assert panel.set_current(other) and "plots" not in panel.evidence.text()
    # a queue saved before the mark existed reads as unmarked
    assert (R.read_proposals(ap.drop(columns=["plot_tracks"]))["plot_tracks"] == "").all()


def test_the_decision_log_writes_a_redo_as_a_redo_and_replays_it(controller, tmp_path):
    """Operator test 9, D13: the exported decision log wrote a redo as a fresh decision
    ("accept"), so nothing told a redo from a second decision. Now it is "redo accept";
    replaying the exported log (`wakeline review --decisions`) gives the window's
    targets, and a reopened store logs it the same way."""
    from wakeline.core.export_review import export_decision_log

    st = controller.state
    a, b, c = st.proposals["proposal"][:3]
    controller.accept(a)
    controller.reject(b)
    controller.stack.undo()
    controller.stack.undo()
    controller.stack.redo()  # the accept again
    controller.reject(c)
    controller.stack.undo()
    controller.stack.redo()
    actions = st.log_table()["action"].tolist()
    assert actions == [
        "accept",
        "reject",
        "undo reject",
        "undo accept",
        "redo accept",
        "reject",
        "undo reject",
        "redo reject",
    ]
    path = tmp_path / "log.csv"
    export_decision_log(st, path)
    log = pd.read_csv(path, dtype=str, keep_default_na=False)
    again = R.replay_log(
        R.ReviewState(st.tracks, st.proposals.drop(columns="status", errors="ignore")), log
    )
    assert list(again.status) == list(st.status) and again.links == st.links
    assert list(again.target_of_track()) == list(st.target_of_track())
    assert again.log_table()["action"].tolist() == actions
    # a redo that does not follow its undo is refused, naming the line
    bad = log.iloc[[0, 4]]
    with pytest.raises(R.InputError, match="line 3: 'redo accept' but the last decision undone"):
        R.replay_log(R.ReviewState(st.tracks, st.proposals), bad)
    # a store (the demo's project) keeps "redo" on reopen
    store = ReviewStore(tmp_path / "s.sqlite")
    store.save_queue(R.ReviewState(st.tracks, st.proposals))
    fresh = store.load()
    change = store.apply(fresh, R.accept(fresh, a))
    store.apply(fresh, change.inverse(), "undo")
    store.apply(fresh, change, "redo")
    assert [e.action for e in store.load().log] == ["accept", "undo accept", "redo accept"]


def test_a_predicted_path_on_the_connectors_line_is_not_drawn_over_its_dashes():
    """Operator test 11 (h249): on the Saronic AIS (positions only) a pending join's
    predicted path was the straight connector itself, drawn dotted 2 px over its dashes:
    the pending join looked solid, as an accepted one. Such a path is left out; one that
    bends off the line (or runs back before the old track's end) is kept."""
    from wakeline.app.review_map import bends_off, predicted_path
    from wakeline.core import geo

    end, start = (0.0, 23.5, 37.3), (600.0, 23.51, 37.31)  # about 1.4 km in 600 s
    still = predicted_path(end, (0.0, 0.0), start, (0.0, 0.0))
    assert not bends_off(*still, end, start)
    ex, ey = geo.to_local(np.array([start[1]]), np.array([start[2]]), end[1], end[2])
    v = (ex[0] / 600.0, ey[0] / 600.0)  # steady along the line: the line itself
    assert not bends_off(*predicted_path(end, v, start, v), end, start)
    side = (-v[1], v[0])  # leaving at right angles: a curve
    assert bends_off(*predicted_path(end, side, start, side), end, start)
    back = (-3 * v[0], -3 * v[1])  # heading away first: runs back past the old end
    assert bends_off(*predicted_path(end, back, start, v), end, start)
    # a gap of no distance: only a path going somewhere bends
    same = (600.0, end[1], end[2])
    assert not bends_off(*predicted_path(end, (0.0, 0.0), same, (0.0, 0.0)), end, same)
    assert bends_off(*predicted_path(end, (1.0, 0.0), same, (1.0, 0.0)), end, same)

"""The Statistics dock: the figures of a real file, computed in a worker thread, a stale
result dropped, the time window followed, and the event loop kept free on a million
points."""

import threading
import time

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from conftest import load, real_file  # noqa: E402
from wakeline.app.lod_worker import LodWorker  # noqa: E402
from wakeline.app.stats_panel import StatsPanel, points_text, tracks_text  # noqa: E402
from wakeline.core.io import read_points  # noqa: E402
from wakeline.core.stats import layer_stats  # noqa: E402


def _scene(n_tracks: int, n: int, lon0: float = 10.0) -> pd.DataFrame:
    tr = np.repeat(np.arange(n_tracks), n)
    t = np.tile(np.arange(n) * 10.0, n_tracks) + tr
    return pd.DataFrame(
        {
            "sensor": "S1",
            "batch": tr.astype(str),
            "time": pd.to_datetime(t, unit="s", utc=True),
            "lon": lon0 + np.tile(np.arange(n), n_tracks) * 1e-4,
            "lat": 55.0 + tr * 1e-3,
        }
    )


def test_the_dock_shows_the_figures_of_an_mtad_scene_computed_in_a_worker(window, qtbot):
    path = real_file("mtad-dtwcm", "original", "Scene-35.csv")
    lid = load(window, path)
    panel = window.stats
    qtbot.waitUntil(lambda: panel.shown_key and panel.shown_key[0] == lid, timeout=20_000)
    expected = layer_stats(read_points(path).points)
    s = panel.stats
    assert (s.points, s.tracks) == (expected.points, expected.tracks)
    assert panel.computed_in is not None and panel.computed_in != threading.main_thread().ident
    rows = dict(panel.rows())
    assert rows["Tracks"] == f"{expected.tracks:,}"
    assert rows["Targets"] == "no target ids"
    assert rows["Layer"].startswith("Scene-35.csv [source]")
    life = rows["Track lifetime min / median / 90 % / max"]
    assert life.endswith((" s", " min", " h", " d")) and life.count("/") == 3
    assert " km × " in rows["Extent (east-west × north-south)"]
    assert "km²" in rows["Area covered"]
    assert any(k.startswith("Sensor ") and "median interval" in v for k, v in rows.items())
    # MTAD counts seconds from the scene start: shown as elapsed time.
    assert rows["Time"].startswith("T+")
    # The histogram holds every track.
    heights = panel.bars.opts["height"]
    assert int(np.sum(heights)) == expected.tracks
    assert "tracks" in window.stats.toPlainText()


def test_a_stale_result_is_dropped_and_the_latest_shown(qtbot):
    panel = StatsPanel()
    qtbot.addWidget(panel)
    jobs = []
    panel.executor = lambda job, done: jobs.append((job, done))
    a, b, c = _scene(3, 10), _scene(5, 10), _scene(7, 10)
    panel.compute(("a",), a)
    panel.compute(("b",), b)  # waits for a's job
    panel.compute(("c",), c)  # replaces b
    assert len(jobs) == 1 and panel.busy
    job, done = jobs.pop()
    done(job())  # a's result: stale
    assert panel.stats is None and panel.dropped == 1
    assert len(jobs) == 1  # c's job started once a's ended
    job, done = jobs.pop()
    done(job())
    assert panel.stats.tracks == 7 and not panel.busy and panel.shown_key == ("c",)
    # The same request again starts no job.
    assert panel.compute(("c",), c) is False and not jobs
    assert not panel.note.isVisibleTo(panel) and panel.split.isVisibleTo(panel)
    # A message (no layer, a bearing layer) replaces the figures, and is seen.
    panel.show_message("No layer")
    assert panel.note.isVisibleTo(panel) and not panel.split.isVisibleTo(panel)
    assert panel.toPlainText() == "No layer"
    panel.compute(("a",), a)
    assert panel.note.isVisibleTo(panel) and panel.note.text() == "Computing…"
    job, done = jobs.pop()
    done(job())
    assert panel.stats.tracks == 3 and not panel.note.isVisibleTo(panel)


def test_the_figures_follow_the_time_window(window, qtbot):
    path = real_file("mtad-dtwcm", "original", "Scene-35.csv")
    lid = load(window, path)
    panel = window.stats
    qtbot.waitUntil(lambda: panel.shown_key and panel.shown_key[0] == lid, timeout=20_000)
    whole = panel.stats
    window.session.set_time_window((whole.start_s, whole.start_s + 0.25 * whole.span_s))
    qtbot.waitUntil(
        lambda: panel.stats is not None and panel.stats.window is not None, timeout=20_000
    )
    assert panel.stats.points < whole.points
    assert panel.stats.span_s <= 0.25 * whole.span_s + 1e-6
    assert "Time window" in dict(panel.rows())
    window.session.set_time_window(None)
    qtbot.waitUntil(lambda: panel.stats is not None and panel.stats.window is None, timeout=20_000)
    assert panel.stats.points == whole.points


def test_a_million_points_do_not_block_the_event_loop(qtbot):
    from PySide6 import QtCore

    panel = StatsPanel()
    qtbot.addWidget(panel)
    worker = LodWorker()
    panel.executor = worker
    pts = _scene(1000, 1000)
    gaps, last = [], [time.perf_counter()]

    def tick():
        now = time.perf_counter()
        gaps.append(now - last[0])
        last[0] = now

    timer = QtCore.QTimer(interval=5)
    timer.timeout.connect(tick)
    timer.start()
    panel.compute(("big",), pts)
    qtbot.waitUntil(lambda: panel.stats is not None, timeout=60_000)
    timer.stop()
    worker.wait()
    assert panel.stats.points == 1_000_000 and panel.stats.tracks == 1000
    assert panel.computed_in != threading.main_thread().ident
    assert max(gaps) < 0.1, f"the event loop waited {max(gaps) * 1000:.0f} ms"


def test_the_figures_follow_a_rerun_of_the_active_layer(window, qtbot):
    """Maneuvers on an MTAD scene: the dock shows the maneuver points; run again with a
    higher threshold, the layer's data change and the dock shows the new count."""
    from wakeline.app.main import wait_for_jobs

    path = real_file("mtad-dtwcm", "original", "Scene-35.csv")
    src = load(window, path)
    panel = window.stats
    counts = []
    for threshold in (15.0, 60.0):
        window.select_layer(src)
        window.params.from_dict({"maneuver": {"threshold_deg": threshold}})
        window.run_step("maneuvers")
        wait_for_jobs(window)
        lid = next(i for i, lay in window.layers.items() if lay.kind == "maneuvers")
        window.select_layer(lid)
        layer = window.layers[lid]
        want = int(layer.points["is_maneuver"].sum())
        qtbot.waitUntil(
            lambda lid=lid, want=want: (
                panel.shown_key is not None
                and panel.shown_key[0] == lid
                and panel.stats.maneuvers["points"] == want
            ),
            timeout=20_000,
        )
        counts.append(want)
        assert "Maneuvers" in dict(panel.rows())
    assert counts[1] < counts[0]


def test_the_histogram_keeps_a_readable_height_when_the_dock_is_raised(window, qtbot, tmp_path):
    """In the window as `wakeline gui` opens it (1400×900) the bottom dock area was 104 px
    high: the lifetime histogram's bars got 15 px under its title and axis (measured,
    docs/map.md). Raised, the Statistics dock now keeps the histogram HIST_MIN_HEIGHT px
    high, about 80 px of bars; behind the Log tab it asks no more than before (the docks
    above keep theirs)."""
    from wakeline.app.stats_panel import HIST_MIN_HEIGHT, LOW_MIN_HEIGHT

    path = tmp_path / "tracks.csv"
    _scene(12, 40).to_csv(path, index=False)
    window.show()
    qtbot.waitExposed(window)
    lid = load(window, path)
    panel = window.stats
    qtbot.waitUntil(lambda: panel.shown_key and panel.shown_key[0] == lid, timeout=20_000)
    assert panel.hist.minimumHeight() == LOW_MIN_HEIGHT  # the Log tab is up at start
    window.docks["stats"].raise_()
    qtbot.waitUntil(lambda: panel.hist.isVisible() and panel.hist.height() >= HIST_MIN_HEIGHT)
    assert panel.hist.minimumHeight() == HIST_MIN_HEIGHT
    bars_px = panel.hist.getPlotItem().getViewBox().sceneBoundingRect().height()
    assert bars_px >= 70, bars_px
    assert int(np.sum(panel.bars.opts["height"])) == 12
    window.docks["log"].raise_()
    qtbot.waitUntil(lambda: panel.hist.minimumHeight() == LOW_MIN_HEIGHT)


def test_the_statistics_say_what_clean_removed_and_changed_and_it_adds_up(window, tmp_path):
    """Operator test (ATD dataset1): the cleaned layer's Statistics showed "rejected
    43638" (a raw key, no separator) beside 102,861 points in and 59,502 kept — a
    difference of 43,359: the count mixed the removed points with the 279 changed (and
    kept) ones. Now one row per action, rule by rule, and removed + kept = in."""
    from wakeline.app.main import wait_for_jobs
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    pts = simulate.demo_scene(seed=3)
    moored = pts[pts["sensor"] == "AIS"].head(40).copy()
    moored["batch"], moored["lon"], moored["lat"] = "moored", 10.0, 55.0
    pts.loc[pts.index[10:13], "speed"] = 60.0  # reported speeds no position agrees with
    src = tmp_path / "scene.csv"
    write_points(pd.concat([pts, moored], ignore_index=True), src)
    lid = load(window, src)
    window.run_step("clean")
    wait_for_jobs(window)
    cleaned = window.session.find(lid, "clean")
    window.select_layer(cleaned.id)
    wait_for_jobs(window)
    window._update_stats()
    rows = dict(window.stats._head)
    assert "rejected" not in rows
    removed = rows["Removed by clean"]
    assert "stationary" in removed, rows
    n_removed = int(removed.split(" ")[0].replace(",", ""))
    n_in, n_kept = len(window.layers[lid].points), len(cleaned.points)
    assert n_removed == n_in - n_kept, (rows, n_in, n_kept)
    actions = cleaned.tables["rejected"]["action"].value_counts()
    assert actions.get("changed", 0)  # the speeds replaced: their points are kept
    changed = rows["Changed by clean (kept, new values)"]
    assert changed.startswith(f"{actions['changed']:,} (speed_outliers"), rows
    # The rows come from the counts the step kept in the layer's meta (review of session
    # 21: a groupby over the rejected table ran on the GUI thread at every refresh); a
    # layer of a project saved before that falls back to the table, with the same rows.
    assert cleaned.meta["clean_counts"]["removed"]["stationary"] > 0
    shown = dict(window._result_rows(cleaned))
    table = cleaned.tables["rejected"]
    cleaned.tables["rejected"] = table.iloc[:0]  # not read
    assert dict(window._result_rows(cleaned)) == shown
    cleaned.tables["rejected"] = table
    counts = cleaned.meta.pop("clean_counts")  # an older project's layer
    assert dict(window._result_rows(cleaned)) == shown
    cleaned.meta["clean_counts"] = counts


def test_each_track_count_says_what_it_counts_under_a_time_window(window, qtbot, write):
    """Operator test (ATD dataset1, window 06:00-12:00): the batch table showed 4,758
    tracks, the Statistics dock 2,930 and the status bar 5,620, none saying what it
    counts. Three tracks: A has points in the window, B spans it with none inside (a
    gap), C ends before it: 3 in the layer, 2 overlap the window, 1 has points in it."""
    t0 = 1_704_067_200  # 2024-01-01 00:00 UTC
    rows = ["sensor,batch,time,lon,lat"]
    for batch, hours in (("A", (7, 8, 9)), ("B", (1, 2, 14, 15)), ("C", (1, 2, 3))):
        rows += [f"S1,{batch},{t0 + 3600 * h},{10 + h * 1e-3},55.0" for h in hours]
    lid = load(window, write("three.csv", "\n".join(rows) + "\n"))
    window.select_layer(lid)
    panel = window.stats
    qtbot.waitUntil(lambda: panel.stats is not None and panel.stats.tracks == 3, timeout=20_000)
    assert window.batch_count.text() == "3 tracks"
    assert window.statusBar().currentMessage() == "10 points, 3 tracks"
    window.session.set_time_window((t0 + 6 * 3600, t0 + 12 * 3600))
    qtbot.waitUntil(
        lambda: panel.stats is not None and panel.stats.window is not None, timeout=20_000
    )
    assert window.batch_model.rowCount() == 2
    assert window.batch_count.text() == (
        "2 of 3 tracks: those whose time span overlaps the time window"
    )
    status = window.statusBar().currentMessage()
    # what the window shows, as the table counts tracks (operator test 8, D4)
    assert status == "In the time window: 2 of 3 tracks, 3 of 10 points", status
    rows = panel.rows()
    names = [name for name, _ in rows]  # the window heads the figures it restricts
    assert names[names.index("Time window") + 1 :][:2] == [
        "Points in the window",
        "Tracks with points in the window",
    ]
    assert dict(rows)["Tracks with points in the window"] == "1"
    assert dict(rows)["Points in the window"] == "3"
    window.filter_edit.setText("A")
    assert window.batch_count.text() == (
        "1 of 3 tracks: those matching the filter and whose time span overlaps the time window"
    )


def test_one_track_and_one_point_are_counted_in_the_singular(window, qtbot, write):
    """Tester h133 (item 12): a one-row file showed "1 tracks" under the batch table and
    "1 points, 1 tracks" in the status bar (and the Statistics dock "1 tracks, 1 points")."""
    path = write("one.csv", "sensor,batch,time,lon,lat\nS1,A,2024-01-01T00:00:00Z,10.0,55.0\n")
    lid = load(window, path)
    window.select_layer(lid)
    panel = window.stats
    qtbot.waitUntil(lambda: panel.stats is not None and panel.stats.tracks == 1, timeout=20_000)
    assert window.batch_count.text() == "1 track"
    assert window.statusBar().currentMessage() == "1 point, 1 track"
    assert dict(panel.rows())["Sensor S1"].startswith("1 track, 1 point, median interval")
    window.filter_edit.setText("zzz")
    assert window.batch_count.text() == "0 of 1 track: those matching the filter"
    assert tracks_text(2_000) == "2,000 tracks" and points_text(0) == "0 points"

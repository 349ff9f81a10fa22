"""Exports beside steps (operator test h122, L13/L14/L11): an export never cancels a step
(nor a step an export), exports queue one after the other, a cancelled export leaves no
file and one written is reported as written, File ▸ Export right after a review decision
writes that decision, and with the time window on the log says the whole layer is
written."""

import threading
import time

import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtWidgets  # noqa: E402
from test_review_window import _settle, _sim_pair, _window  # noqa: E402

from wakeline.app.main import wait_for_jobs  # noqa: E402
from wakeline.app.worker import Cancelled, Finished, JobRunner  # noqa: E402

pytestmark = pytest.mark.gui


def _long_step(seen: list, steps: int = 400):
    def job(progress):
        for k in range(steps):
            seen.append(k)
            progress(k / steps, "working")
            time.sleep(0.002)
        return ("export", "step", "nowhere")  # applied as a no-op log line

    return job


def _wait_started(seen: list) -> None:
    deadline = time.time() + 5
    while not seen and time.time() < deadline:
        QtWidgets.QApplication.processEvents()


def test_an_export_neither_cancels_a_step_nor_is_cancelled_by_one(qtbot, tmp_path):
    """Run ▸ Clean then File ▸ Export 0.2 s later cancelled the clean ("export took its
    place"); File ▸ Export then Run ▸ Compress said "export cancelled" although the file
    was written in full. Both now run to their end, and two exports queue."""
    w = _window(qtbot, tmp_path)
    w.load_files(_sim_pair(tmp_path)[:1])
    _settle(w)
    seen: list = []
    w._start("associate", _long_step(seen), ("associate", "sim"))
    _wait_started(seen)
    first, second = tmp_path / "a.csv", tmp_path / "b.geojson"
    assert w.export("csv", first)
    assert w.export("geojson", second)  # waits for the first
    wait_for_jobs(w)
    log = w.log.toPlainText()
    assert "cancelled" not in log, log
    assert len(seen) == 400  # the step ran to its end
    assert "waits for the export running" in log
    assert f"to {first}" in log and f"to {second}" in log
    assert first.exists() and second.exists()
    assert not list(tmp_path.glob(".~*"))  # no temporary file left
    assert len(pd.read_csv(first)) == len(w.active_layer().points)


def test_a_cancel_during_an_export_reports_the_file_written(qtbot, tmp_path):
    """A writer does not stop half-way (it writes through atomic_path): a cancel during
    an export leaves the whole file, reported as written, never as cancelled."""
    w = _window(qtbot, tmp_path)
    w.load_files(_sim_pair(tmp_path)[:1])
    _settle(w)
    started, go = threading.Event(), threading.Event()
    target = tmp_path / "out.csv"

    def write(path):
        started.set()
        go.wait(5)
        path.write_text("sensor,batch\n")
        return ("export", "x", path)

    w._start_export(target, write, ("export", "x"))
    assert started.wait(5)
    w.cancel_jobs()
    go.set()
    wait_for_jobs(w)
    assert target.exists()
    assert f"exported x to {target}" in w.log.toPlainText()


def test_an_export_failing_after_a_cancel_frees_the_queue(qtbot, tmp_path):
    """h130: a writer's error after Cancel was dropped by the runner, so the export stayed
    'running' and every later export waited for ever."""
    w = _window(qtbot, tmp_path)
    w.load_files(_sim_pair(tmp_path)[:1])
    _settle(w)
    started, go = threading.Event(), threading.Event()

    def failing(_path):
        started.set()
        go.wait(5)
        raise OSError("disk full")

    w._start_export(tmp_path / "bad.csv", failing, ("export", "bad"))
    assert started.wait(5)
    w.cancel_jobs()
    go.set()
    wait_for_jobs(w)
    second = tmp_path / "next.csv"
    assert w.export("csv", second)
    wait_for_jobs(w)
    assert second.exists() and not w.jobs_busy


def test_an_export_onto_a_read_only_file_is_refused(qtbot, tmp_path):
    """h130: the window's own temporary-file move replaced a read-only target that
    core.io.writer.atomic_path refuses to replace."""
    import os
    import stat

    if os.geteuid() == 0:
        import pytest

        pytest.skip("root can write read-only files")
    w = _window(qtbot, tmp_path)
    w.load_files(_sim_pair(tmp_path)[:1])
    _settle(w)
    target = tmp_path / "locked.csv"
    target.write_text("keep me\n")
    target.chmod(stat.S_IREAD)
    assert w.export("csv", target)
    wait_for_jobs(w)
    assert target.read_text() == "keep me\n"


def test_a_job_that_keeps_its_result_is_finished_after_a_late_cancel(qtbot):
    """The cancel came after the file was in place: that is reported as done."""
    runner = JobRunner()
    got = []
    runner.message.connect(got.append)
    go = threading.Event()

    def job(_progress):
        go.wait(5)
        return "written"

    job.keeps_result = True
    runner.run("export", job)
    runner.cancel()
    go.set()
    runner.wait(5000)
    qtbot.waitUntil(lambda: any(isinstance(m, Finished | Cancelled) for m in got), timeout=5000)
    assert [m.result for m in got if isinstance(m, Finished)] == ["written"]
    assert not any(isinstance(m, Cancelled) for m in got)


def test_export_right_after_a_review_decision_writes_it(qtbot, tmp_path):
    """The layer follows the decisions 300 ms after the last one; File ▸ Export in that
    time wrote the layer without the decision (25 batches for 26 targets on Autoferry)."""
    files = _sim_pair(tmp_path)
    w = _window(qtbot, tmp_path)
    w.load_files(files)
    _settle(w)
    ids = [w.layer_id(f.name) for f in files]
    w.layer_list.clearSelection()
    for lid in ids:
        w.layer_list.item(w.layer_row(lid)).setSelected(True)
    w.actions_["fuse"].trigger()
    _settle(w)
    fused = next(lay for lay in w.layers.values() if lay.step == "fuse")
    w.select_layer(fused.id)
    _settle(w)
    b = w.review.bound
    st = b.controller.state
    before = st.targets()["target"].nunique()
    b.panel.act_reject.trigger()  # a joined (pending) proposal rejected ...
    assert st.targets()["target"].nunique() == before + 1
    out = tmp_path / "layer.csv"
    assert w.export("csv", out)  # ... and exported at once
    assert w.review.sync.busy  # the layer has not followed yet
    _settle(w)
    assert pd.read_csv(out, dtype=str)["batch"].nunique() == before + 1
    again = tmp_path / "again.csv"
    w.export("csv", again)  # once the layer followed: the same file
    _settle(w)
    assert again.read_bytes() == out.read_bytes()


def test_export_with_the_time_window_on_says_the_whole_layer_is_written(qtbot, tmp_path):
    w = _window(qtbot, tmp_path)
    w.load_files(_sim_pair(tmp_path)[:1])
    _settle(w)
    tp = w.time_panel
    tp.set_time_window((tp._lo, tp._lo + 0.1 * (tp._hi - tp._lo)))
    out = tmp_path / "all.csv"
    w.export("csv", out)
    wait_for_jobs(w)
    n = len(w.active_layer().points)
    assert len(pd.read_csv(out)) == n
    assert f"the whole layer is written ({n:,} points)" in w.log.toPlainText()
    tp.set_time_window(None)
    w.export("csv", tmp_path / "b.csv")
    wait_for_jobs(w)
    assert w.log.toPlainText().count("the whole layer is written") == 1


def test_as_came_in_writes_back_the_speed_unit_the_open_dialog_gave(qtbot, tmp_path):
    """A file opened with Speed unit m/s (no unit in its header): its layer's export as it
    came wrote knots under "speed" (the layout learnt at import did not know the unit)."""
    rows = [
        f"S1,T1,2024-01-01T00:00:{i:02d}Z,{10 + i * 1e-4:.4f},50.0000,{9.7 + i * 0.1:.1f}"
        for i in range(20)
    ]
    src = tmp_path / "f.csv"
    src.write_text("sensor,batch,time,lon,lat,speed\n" + "\n".join(rows) + "\n")
    w = _window(qtbot, tmp_path)
    w.load_file(src, speed_unit="m/s")
    _settle(w)
    out = tmp_path / "out.csv"
    assert w.export_as_came_in(out)
    wait_for_jobs(w)
    assert out.read_bytes() == src.read_bytes()


def test_a_failed_job_s_dialog_is_titled_in_words_not_by_its_job_id(qtbot, tmp_path, monkeypatch):
    """Operator test h150: the dialog of a failed job was titled by the job's internal
    name ("open project failed", "bearing failed"; in zh_CN "export 失败"). It is titled
    "Open project failed", "Open bearings failed", in Chinese in the Chinese window; the
    log line names the job the same way."""
    from PySide6 import QtWidgets

    from wakeline.app import i18n

    shown = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: shown.append(a[1]))
    w = _window(qtbot, tmp_path)
    not_bearings = tmp_path / "tracks.csv"
    not_bearings.write_text("mmsi,time,lon,lat\n1,0,10.0,55.0\n")
    try:
        w.open_project(tmp_path / "nowhere.wakeline")
        wait_for_jobs(w)
        w.load_bearings(not_bearings)
        wait_for_jobs(w)
        qtbot.waitUntil(lambda: len(shown) == 2, timeout=10_000)
        assert shown == ["Open project failed", "Open bearings failed"]
        assert "Error (Open project): " in w.log.toPlainText()
        w.set_language("zh_CN")
        w.open_project(tmp_path / "nowhere.wakeline")
        wait_for_jobs(w)
        qtbot.waitUntil(lambda: len(shown) == 3, timeout=10_000)
        assert shown[2] == "打开工程 失败"
        assert "job" not in w.job_title("export") and w.job_title("export") == "导出"
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)


def test_done_and_cancelled_say_the_job_s_title_not_its_id(qtbot, tmp_path):
    """The status bar and log said "pipeline done in 0.4 s", "pipeline cancelled",
    "associate cancelled: open x.csv took its place" (the jobs' internal names; in
    zh_CN "pipeline 已取消") while the failed dialog said "Pipeline failed" (h159). They
    now name the job by its title, in the window's language."""
    from wakeline.app import i18n

    w = _window(qtbot, tmp_path)
    seen: list = []
    try:
        w._start("pipeline", _long_step(seen, 1), ("pipeline", "demo"))
        wait_for_jobs(w)
        assert w.statusBar().currentMessage().startswith("Pipeline done in "), (
            w.statusBar().currentMessage()
        )
        w._start("pipeline", _long_step(seen, 2000), ("pipeline", "demo"))
        _wait_started(seen)
        w.runner.cancel()
        wait_for_jobs(w)
        assert w.log.toPlainText().splitlines()[-1] == "Pipeline cancelled"
        assert w.statusBar().currentMessage() == "Pipeline cancelled"
        w.set_language("zh_CN")
        seen.clear()
        w._start("pipeline", _long_step(seen, 2000), ("pipeline", "demo"))
        _wait_started(seen)
        w._start("open x.csv", _long_step([], 1), ("import", "x.csv"))  # takes its place
        wait_for_jobs(w)
        log = w.log.toPlainText()
        assert "流程 已取消：打开 x.csv 取代了它" in log and "请重新运行 流程" in log, log
        assert w.statusBar().currentMessage().startswith("打开 x.csv 完成，用时 ")
    finally:
        w.set_language("en")
        w.close()
    i18n.install(QtWidgets.QApplication.instance(), "en", None)

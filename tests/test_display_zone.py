"""View ▸ Time zone (h191, D-time-1): the window's dates in UTC, the data's zone or this
computer's; the batch table's titles, the slider, the Statistics dock and the Gantt say
the zone; kept in QSettings and the project; files and exports unchanged."""

import datetime

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import load, make_window
from wakeline.app import time_text
from wakeline.app.models import date_text


@pytest.fixture(autouse=True)
def _utc_after():
    yield
    time_text.set_display_zone(None, "UTC")


def _beijing_csv(path):
    """Two tracks written in Beijing wall-clock time (no zone), from 08:00:00."""
    rows = ["批号,时间,经度,纬度"]
    for b in range(2):
        for i in range(20):
            rows.append(f"{b},2026-12-05 08:{i:02d}:00,{122 + i * 1e-3:.4f},{30 + b * 0.01:.4f}")
    path.write_bytes(("\r\n".join(rows) + "\r\n").encode("gb18030"))
    return path


def test_zone_labels_and_choices():
    t = 1796428800.0  # 2026-12-05 00:00 UTC
    assert time_text.zone_for("utc", "Asia/Shanghai", t) == (None, "UTC")
    zone, label = time_text.zone_for("data", "Asia/Shanghai", t)
    assert label == "UTC+8" and zone is not None
    assert time_text.zone_for("data", None, t) == (None, "UTC")
    assert time_text.zone_for("data", "UTC", t) == (None, "UTC")
    assert time_text.zone_for("data", "not/a zone", t) == (None, "UTC")
    assert time_text.zone_for("data", "-03:30", t)[1] == "UTC-3:30"
    assert time_text.zone_for("data", "Europe/Oslo", t)[1] == "UTC+1"  # winter
    assert time_text.zone_for("data", "Europe/Oslo", t - 150 * 86400)[1] == "UTC+2"  # summer
    local = datetime.datetime.now().astimezone().utcoffset()
    assert time_text.zone_for("local", None)[1].startswith("UTC")
    assert (time_text.zone_for("local", None)[1] == "UTC") == (local.total_seconds() == 0)


def test_format_time_names_the_zone():
    t = 1796428800.0
    assert time_text.format_time(t, False) == "2026-12-05 00:00:00 UTC"
    time_text.set_display_zone(*time_text.zone_for("data", "Asia/Shanghai", t))
    assert time_text.format_time(t, False) == "2026-12-05 08:00:00 UTC+8"
    assert time_text.format_time(t + 0.25, False) == "2026-12-05 08:00:00.250 UTC+8"
    assert time_text.format_time(300.0, True) == "T+0:05:00"  # scene-relative: no zone
    assert time_text.zone_title("开始 (UTC)") == "开始 (UTC+8)"


@settings(max_examples=40, deadline=None)
@given(
    secs=st.lists(st.integers(0, 4_000_000_000), min_size=1, max_size=30),
    zone=st.sampled_from(["Asia/Shanghai", "Europe/Oslo", "America/New_York", "+05:30", "UTC"]),
)
def test_property_table_dates_are_the_zones_wall_clock(secs, zone):
    """The batch table's vectorized dates equal pandas' per-value conversion to the zone."""
    time_text.set_display_zone(*time_text.zone_for("data", zone, float(secs[0])))
    stamps = pd.Series(pd.to_datetime(np.asarray(secs, dtype="int64"), unit="s", utc=True))
    got = date_text(stamps)
    tz = time_text.display_zone()
    want = [
        (s.tz_convert(tz) if tz is not None else s).strftime("%Y-%m-%d %H:%M:%S") for s in stamps
    ]
    assert got.tolist() == want
    time_text.set_display_zone(None, "UTC")
    assert date_text(stamps).tolist() == [s.strftime("%Y-%m-%d %H:%M:%S") for s in stamps]


def _load_tz(w, qtbot, path, tz):
    from wakeline.app.main import wait_for_jobs

    w.load_file(path, tz=tz)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: not w.time_controller.busy, timeout=20_000)
    return w.layer_id(path.name)


def _header(w, key):
    from PySide6 import QtCore

    col = [k for k, _ in w.batch_model.COLUMNS].index(key)
    return w.batch_model.headerData(col, QtCore.Qt.Orientation.Horizontal)


def _stats_text(w) -> str:
    table = w.stats.table
    return " | ".join(
        table.item(r, c).text()
        for r in range(table.rowCount())
        for c in range(table.columnCount())
        if table.item(r, c) is not None
    )


def _cell(w, key, row=0):
    col = [k for k, _ in w.batch_model.COLUMNS].index(key)
    return w.batch_model.data(w.batch_model.index(row, col))


@pytest.mark.gui
def test_window_follows_the_choice_and_keeps_it(qtbot, tmp_path):
    from wakeline.core.project import load_project

    path = _beijing_csv(tmp_path / "console.csv")
    w = make_window(qtbot, tmp_path, (1200, 800))
    assert w.zone_choice == "data" and w.zone_actions["data"].isChecked()
    _load_tz(w, qtbot, path, "Asia/Shanghai")
    # default: the data's zone, named
    assert _header(w, "start") == "Start (UTC+8)"
    assert min(_cell(w, "start", r) for r in range(2)) == "2026-12-05 08:00:00"
    w.time_panel.set_time(1796428800.0)
    assert w.time_panel.time_label.text() == "2026-12-05 08:00:00 UTC+8"
    qtbot.waitUntil(lambda: "UTC+8" in _stats_text(w), timeout=20_000)
    assert "2026-12-05 08:00:00 UTC+8" in _stats_text(w)
    # UTC
    w.zone_actions["utc"].trigger()
    assert _header(w, "start") == "Start (UTC)"
    assert min(_cell(w, "start", r) for r in range(2)) == "2026-12-05 00:00:00"
    assert w.time_panel.time_label.text() == "2026-12-05 00:00:00 UTC"
    qtbot.waitUntil(lambda: "2026-12-05 00:00:00 UTC –" in _stats_text(w), timeout=20_000)
    assert w.settings.value("view/time_zone") == "utc"
    # this computer's
    w.zone_actions["local"].trigger()
    assert _header(w, "start") == f"Start ({time_text.zone_label()})"
    # the project keeps the choice; a new window with other settings opens it so
    w.zone_actions["data"].trigger()
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    w.zone_actions["utc"].trigger()
    assert w.project.flush(30)
    assert load_project(proj).state.get("time_zone") == "utc"  # written at once
    w.zone_actions["data"].trigger()
    assert w.project.flush(30)
    w.runner.cancel()
    w.runner.wait()
    w.close()
    time_text.set_display_zone(None, "UTC")

    from wakeline.app.main import wait_for_jobs

    w2 = make_window(qtbot, tmp_path / "other", (1200, 800))
    w2.zone_actions["utc"].trigger()
    w2.open_project(proj)
    wait_for_jobs(w2)
    qtbot.waitUntil(lambda: not w2.time_controller.busy, timeout=20_000)
    assert w2.zone_choice == "data" and _header(w2, "start") == "Start (UTC+8)"
    # the worker wrote the dates in UTC, the window's zone then: written again in UTC+8
    assert min(_cell(w2, "start", r) for r in range(2)) == "2026-12-05 08:00:00"
    w2.runner.cancel()
    w2.runner.wait()


@pytest.mark.gui
def test_without_a_zone_the_data_choice_shows_utc_and_exports_are_unchanged(qtbot, tmp_path):
    path = _beijing_csv(tmp_path / "console.csv")
    w = make_window(qtbot, tmp_path, (1200, 800))
    lid = load(w, path)
    assert _header(w, "start") == "Start (UTC)"
    assert min(_cell(w, "start", r) for r in range(2)) == "2026-12-05 08:00:00"  # read as UTC
    w.zone_actions["local"].trigger()
    # the points (and so every export) stay UTC
    t = w.session.layers[lid].points["time"]
    assert str(t.dt.tz) == "UTC" and t.min() == pd.Timestamp("2026-12-05 08:00:00", tz="UTC")
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_zh_titles_and_stats_say_the_zone(qtbot, tmp_path):
    path = _beijing_csv(tmp_path / "console.csv")
    w = make_window(qtbot, tmp_path, (1200, 800))
    w.set_language("zh_CN")
    _load_tz(w, qtbot, path, "Asia/Shanghai")
    assert _header(w, "start") == "开始 (UTC+8)" and _header(w, "end") == "结束 (UTC+8)"
    assert w.menus["zone"].title().startswith("时区")
    w.set_language("en")
    w.runner.cancel()
    w.runner.wait()


@pytest.mark.gui
def test_opening_a_project_writes_its_dates_once(qtbot, tmp_path, monkeypatch):
    """A project whose zone choice shows the zone the window already shows: the batch
    table's dates come from the worker's views and are not written again on the GUI
    thread (S29: 0.3 s of GUI-thread work at a million points). (One whose choice shows
    another zone is written again: test_window_follows_the_choice_and_keeps_it.)"""
    import threading

    from wakeline.app import layer_view, models
    from wakeline.app.main import wait_for_jobs

    path = _beijing_csv(tmp_path / "console.csv")
    w = make_window(qtbot, tmp_path, (1200, 800))
    _load_tz(w, qtbot, path, "Asia/Shanghai")
    w.zone_actions["utc"].trigger()
    proj = tmp_path / "work.wakeline"
    w.save_project(proj)
    assert w.project.flush(30)
    w.runner.cancel()
    w.runner.wait()
    w.close()
    time_text.set_display_zone(None, "UTC")

    on_gui = []
    real = models.display_text

    def counted(df):
        on_gui.append(threading.current_thread() is threading.main_thread())
        return real(df)

    monkeypatch.setattr(models, "display_text", counted)  # display_zone.redraw's
    monkeypatch.setattr(layer_view, "display_text", counted)  # the worker's views'
    w2 = make_window(qtbot, tmp_path / "other", (1200, 800))
    w2.zone_actions["utc"].trigger()
    on_gui.clear()
    w2.open_project(proj)
    wait_for_jobs(w2)
    qtbot.waitUntil(lambda: not w2.time_controller.busy, timeout=20_000)
    assert w2.zone_choice == "utc" and _header(w2, "start") == "Start (UTC)"
    assert min(_cell(w2, "start", r) for r in range(2)) == "2026-12-05 00:00:00"
    assert on_gui and not any(on_gui), on_gui  # made in the worker only
    w2.runner.cancel()
    w2.runner.wait()


def _offset_csv(path, offsets):
    """Two tracks from 2026-12-05 00:00 UTC, each time written with the next of
    ``offsets`` in turn (its wall clock there)."""
    rows = ["mmsi,time,lat,lon"]
    for b in range(2):
        for i in range(20):
            t = pd.Timestamp("2026-12-05T00:00:00Z") + pd.Timedelta(minutes=i)
            off = offsets[i % len(offsets)]
            sign = -1 if off[0] == "-" else 1
            wall = t + sign * pd.Timedelta(hours=int(off[1:3]), minutes=int(off[4:6]))
            stamp = wall.strftime("%Y-%m-%dT%H:%M:%S") + off
            rows.append(f"36697077{b},{stamp},{30 + b * 0.01:.4f},{-90 + i * 1e-3:.4f}")
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.gui
def test_the_data_choice_shows_the_offset_the_times_were_written_with(qtbot, tmp_path):
    """Operator test 10: every time of the file ends in -05:00 and no --tz: "the zone the
    data came in" showed UTC. It is UTC-5 now; a file of times in two offsets stays UTC."""
    w = make_window(qtbot, tmp_path, (1200, 800))
    assert w.zone_choice == "data"
    load(w, _offset_csv(tmp_path / "gulf.csv", ["-05:00"]))
    assert _header(w, "start") == "Start (UTC-5)"
    assert min(_cell(w, "start", r) for r in range(2)) == "2026-12-04 19:00:00"
    w.time_panel.set_time(1796428800.0)  # 2026-12-05 00:00 UTC
    assert w.time_panel.time_label.text() == "2026-12-04 19:00:00 UTC-5"
    w.zone_actions["utc"].trigger()
    assert w.time_panel.time_label.text() == "2026-12-05 00:00:00 UTC"
    w.zone_actions["data"].trigger()
    # times in two offsets: the report says "mixed", the window keeps UTC
    load(w, _offset_csv(tmp_path / "two.csv", ["-05:00", "+08:00"]))
    assert _header(w, "start") == "Start (UTC)"
    assert min(_cell(w, "start", r) for r in range(2)) == "2026-12-05 00:00:00"
    w.runner.cancel()
    w.runner.wait()

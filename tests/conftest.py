"""Shared fixtures. GUI tests run offscreen; real data is read from ../shared when present."""

import os
import sys
from pathlib import Path

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

REPO = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data"
SHARED_REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def canvas_rgb(canvas):
    """A map widget's pixels as an (h, w, 3) uint8 array, every layer painted afresh (not
    from Qt's item cache)."""
    import numpy as np
    from PySide6 import QtGui

    for name in canvas.layer_names():
        for item in canvas.layer_items(name):
            item.curve.update()
    img = canvas.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    raw = np.frombuffer(img.constBits(), dtype=np.uint8).reshape(h, img.bytesPerLine())
    return raw[:, : w * 3].reshape(h, w, 3).copy()


def real_file(*parts: str) -> Path:
    """A file of ../shared/data/real; the test is skipped when it is absent."""
    path = SHARED_REAL.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"real data not available: {path}")
    return path


#: MTAD scene 7 (two_sensor, error 0): first longitudes of AIS:1 and radar:1, and a
#: longitude AIS:1 crosses (its track runs west from 131.247 to 131.116).
MTAD7_AIS1_START, MTAD7_RADAR1_START, MTAD7_AIS1_MIDDLE = 131.247119, 131.261266, 131.18


def mtad_on_180(centre: float):
    """MTAD scene 7's AIS and radar tracks (one table, as ``wakeline review`` reads the
    two files) moved by a constant so the original longitude ``centre`` lies on 180°;
    skipped when the real data is absent."""
    from wakeline.app.cli_review import read_inputs
    from wakeline.core import geo

    ais = real_file("mtad-dtwcm", "two_sensor", "scene-7_error_0_AIS.csv")
    radar = real_file("mtad-dtwcm", "two_sensor", "scene-7_error_0_radar.csv")
    pts = read_inputs([ais, radar])
    return pts.assign(lon=geo.wrap180(pts["lon"].to_numpy(dtype="float64") + 180.0 - centre))


def saronic_points(sensor: str = "AIS"):
    """The Saronic Gulf AIS (greece-ais-annotated, headerless: batch lon lat unix-time) as
    canonical points of one sensor; skipped when absent."""
    import pandas as pd

    raw = pd.read_csv(
        real_file("greece-ais-annotated", "vessels.csv"),
        sep=" ",
        header=None,
        names=["batch", "lon", "lat", "t"],
    )
    return pd.DataFrame(
        {
            "sensor": sensor,
            "batch": raw["batch"].astype(str),
            "time": pd.to_datetime(raw["t"], unit="s", utc=True),
            "lon": raw["lon"],
            "lat": raw["lat"],
        }
    )


def old_style_review_project(path: Path) -> dict:
    """A project saved before joins accepted the rows they put inside a target (commit
    c2e0b20): its decisions are written as that code wrote them. On an associated layer
    of a simulated scene (proposals with no track in common, picked in id order):

    - ``split_merged``: split (its first track), then its two tracks merged by hand (the
      old merge: a manual link, the row left ``split``);
    - ``rejected_merged``: rejected, then merged by hand (left ``rejected``);
    - ``accepted``: accepted; ``rejected``: rejected (tracks apart: consistent);
    - ``rejected_in_cycle``: merged by hand while already joined (the old merge added a
      link anyway), then rejected: rejected while its tracks stayed joined, the
      operator's own decision (not a join's leftover).

    Returns those names' proposal ids, the layer's id and the old links."""
    from wakeline.core import review as R
    from wakeline.core import simulate
    from wakeline.core.project import save_project
    from wakeline.core.review_session import bind, queue_key
    from wakeline.core.review_store import decision_row
    from wakeline.core.session import Session

    s = Session()
    src = s.add_layer("seg.csv", "source", simulate.segments_scene(seed=2, n_ships=8, area_km=15))
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)
    used: set[str] = set()
    picked = []
    for pid, a, b in zip(st.proposals["proposal"], st.track_a, st.track_b, strict=True):
        if a not in used and b not in used:
            picked.append(pid)
            used |= {a, b}
    names = ["split_merged", "rejected_merged", "accepted", "rejected", "rejected_in_cycle"]
    assert len(picked) >= len(names), "the scene has too few separate proposals"
    ids = dict(zip(names, picked, strict=False))

    def tracks(pid):
        k = st._row[pid]
        return [st.track_a[k], st.track_b[k]]

    def old_set(action, pid, status):  # accept / reject / reset before c2e0b20
        k = st._row[pid]
        return R.Change(action, pid, tuple(tracks(pid)), {pid: str(st.status[k])}, {pid: status})

    def old_merge(labels):  # manual links in a chain; no status touched
        links = {R.pair_key(x, y) for x, y in zip(labels[:-1], labels[1:], strict=True)}
        return R.Change("merge", "", tuple(labels), links_added=frozenset(links - st.links))

    changes = [
        lambda: R.split_track(st, tracks(ids["split_merged"])[0]),  # unchanged since
        lambda: old_merge(tracks(ids["split_merged"])),
        lambda: old_set("reject", ids["rejected_merged"], "rejected"),
        lambda: old_merge(tracks(ids["rejected_merged"])),
        lambda: old_set("accept", ids["accepted"], "accepted"),
        lambda: old_set("reject", ids["rejected"], "rejected"),
        lambda: old_merge(tracks(ids["rejected_in_cycle"])),
        lambda: old_set("reject", ids["rejected_in_cycle"], "rejected"),
    ]
    for make in changes:
        change = make()
        st.apply(change, when="2026-12-01T10:00:00+00:00")
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))
    save_project(s, path)
    unmark_decisions(path)  # that code did not mark its decisions checked
    return {"ids": ids, "layer": lay.id, "links": set(st.links), "status": list(st.status)}


def unmark_decisions(path: Path) -> None:
    """Drop the project's mark of checked review decisions, as a Wakeline before the mark
    wrote the file (``core.project.DECISIONS_CHECKED``)."""
    import sqlite3

    from wakeline.core.project import DECISIONS_CHECKED

    con = sqlite3.connect(path)
    with con:
        con.execute("DELETE FROM meta WHERE key = ?", (DECISIONS_CHECKED,))
    con.close()


def make_window(qtbot, tmp_path, size: tuple[int, int] = (1400, 900), track_colors: bool = False):
    """A main window in English with settings of its own under ``tmp_path``, ``size`` px;
    :func:`window` yields one and ends its jobs after the test. ``track_colors``: View ▸
    Colour by track (on by default in the application; off here, where tests check
    the layers' and sensors' own colours and curves)."""
    from PySide6 import QtCore

    from wakeline.app.main_window import MainWindow

    settings = QtCore.QSettings(str(tmp_path / "settings.ini"), QtCore.QSettings.Format.IniFormat)
    settings.setValue("language", "en")
    settings.setValue("map/color_by_track", track_colors)
    w = MainWindow(settings)
    qtbot.addWidget(w)
    w.resize(*size)
    return w


@pytest.fixture
def window(qtbot, tmp_path):
    w = make_window(qtbot, tmp_path)
    yield w
    w.runner.cancel()
    w.runner.wait()
    w.export_runner.wait()


def load(window, path) -> str | None:
    """Open a file in the window's worker, wait, and return the new layer's id."""
    from wakeline.app.main import wait_for_jobs

    window.load_file(path)
    wait_for_jobs(window)
    return window.layer_id(path.name)


@pytest.fixture
def write(tmp_path):
    """Write bytes or text to a file in tmp_path and return its path."""

    def _write(name: str, content: str | bytes, encoding: str = "utf-8") -> Path:
        path = tmp_path / name
        if isinstance(content, str):
            content = content.encode(encoding)
        path.write_bytes(content)
        return path

    return _write


@pytest.fixture(autouse=True)
def _no_blocking_dialogs(monkeypatch):
    """A modal message box would wait forever offscreen: record instead (tests that check
    dialogs patch QMessageBox themselves)."""
    try:
        from PySide6 import QtWidgets
    except ImportError:
        return
    for name in ("warning", "information", "critical", "question"):
        monkeypatch.setattr(QtWidgets.QMessageBox, name, lambda *a, **k: None)


@pytest.fixture(autouse=True)
def _windows_end_with_their_test(request):
    """After a GUI test: its main windows' jobs (worker, level-of-detail pool, project
    writer) are finished and the windows deleted, within the test's own teardown.

    Left to the garbage collector, windows were destroyed at some later collection —
    mid-way through another test, or at the session's end (where a GUI run was seen stuck
    in the collector with job threads still alive, and one crashed). Here a hang fails
    this test after pytest-timeout's limit, with every thread's stack; what the deletion
    leaves in cycles is frozen, never collected (below).
    """
    yield
    if "qtbot" not in request.fixturenames or "wakeline.app.main_window" not in sys.modules:
        return
    import gc

    from PySide6 import QtCore
    from shiboken6 import isValid

    from wakeline.app.main_window import MainWindow

    # The windows made, not QApplication.topLevelWidgets(): listing those wraps every
    # top-level widget, and one that a garbage collection was deleting meanwhile made that
    # line segfault (about one full run in three, in this teardown).
    windows = [w for w in list(MainWindow.alive) if isValid(w)]
    params: list = []
    for w in windows:
        if getattr(w, "language", "en") != "en":
            # a test that switched the window to Chinese and did not switch back would
            # leave the application's translator (and the core's language) to the next
            w.set_language("en")
        w.runner.cancel()
        assert w.runner.wait(60_000), "a job did not end within 60 s of the test"
        w.close()  # as the application does: closeEvent stops the jobs and the docks
        w.lod_worker.wait(60_000)
        w.project.detach()
        params += _parameters(w)
        w.deleteLater()
    if windows:
        QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)
        # The parameters panel's pyqtgraph Parameters are QObjects with no Qt parent: the
        # window's deletion leaves them (~420 a window), and frozen below they lived to the
        # end of the run, each window's deletion slower than the last (0.037 s of CPU for
        # the first, 0.12 s for the eighth; flat with them deleted; docs/benchmarks.md,
        # Session 31). Deleted once their tree is gone.
        for p in params:
            p.deleteLater()
        del params
        QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)
        # Not gc.collect(): the cycles left hold Python wrappers of Qt objects the
        # DeferredDelete just destroyed, and collecting those is the PySide/pyqtgraph
        # segfault (pyqtgraph#1628) — seen here in about one full run in five, always in
        # this collect. Frozen, they are never collected: a bounded leak until the
        # process ends, as the application freezes its start-up objects.
        gc.freeze()


def _parameters(window) -> list:
    """Every pyqtgraph Parameter of the window's parameters panel, the root included."""
    root = getattr(getattr(window, "params", None), "root", None)
    found, todo = [], [root] if root is not None else []
    while todo:
        p = todo.pop()
        found.append(p)
        todo.extend(p.children())
    return found


# -- leaving ------------------------------------------------------------------------------
#: The session's exit status, kept for :func:`pytest_unconfigure`.
_EXIT: dict[str, int] = {}


def pytest_sessionfinish(session, exitstatus) -> None:
    _EXIT["status"] = int(exitstatus)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config) -> None:
    """Leave without the interpreter's teardown, once pytest has said everything: Qt's
    objects destroyed there in no set order segfaulted about one full run in five *after*
    the summary ("577 passed", then signal 11), which `.ci/run` had to run again. The exit
    status is pytest's own. ``WAKELINE_SOFT_EXIT=1`` keeps the ordinary teardown (to hunt
    that crash)."""
    if "status" in _EXIT and os.environ.get("WAKELINE_SOFT_EXIT") != "1":
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_EXIT["status"])

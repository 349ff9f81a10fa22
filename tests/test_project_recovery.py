"""A project left in the middle of a write (a crash, a power loss: a hot ``-journal``
beside it) opens, rolled back to its last complete write; what cannot be opened says why,
never "not a Wakeline project" for a real project (tester h133, report item 1)."""

import json
import os
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from wakeline.core import simulate
from wakeline.core.errors import InputError
from wakeline.core.project import load_project, save_project
from wakeline.core.project_lock import lock_path
from wakeline.core.session import Session


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """A complete project of two layers (enough data that a write spills to the file)."""
    s = Session()
    points = simulate.multisensor_scene(seed=3, n_ships=6, area_km=30.0)
    a = s.add_layer("scene", "source", points)
    s.apply_result(a.id, s.run_step(a.id, "clean"))
    path = tmp_path_factory.mktemp("good") / "good.wakeline"
    save_project(s, path)
    return path


def _crash_mid_write(good: Path, folder: Path) -> Path:
    """A copy of ``good`` with a process killed inside a write transaction, as the
    project writer would be by a crash: the file half-written, its hot journal beside it
    (as tester h133's hot_journal.py)."""
    folder.mkdir(exist_ok=True)
    path = folder / "p.wakeline"
    shutil.copyfile(good, path)
    code = (
        "import os, sqlite3\n"
        f"con = sqlite3.connect({str(path)!r})\n"
        "con.execute('PRAGMA journal_mode=DELETE')\n"
        "con.execute('PRAGMA cache_size=1')\n"
        "con.execute('BEGIN IMMEDIATE')\n"
        "con.execute(\"UPDATE layers SET name = name || 'x', "
        'data = CAST(zeroblob(length(data)) AS BLOB)")\n'
        "os._exit(0)\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)
    journal = Path(f"{path}-journal")
    assert journal.exists() and journal.stat().st_size > 0
    assert path.read_bytes() != good.read_bytes()  # the write reached the file
    return path


def _names(project) -> list[str]:
    return [lay.name for lay in project.layers]


def test_a_hot_journal_is_rolled_back_and_the_project_opens(good, tmp_path):
    path = _crash_mid_write(good, tmp_path / "crash")
    back = load_project(path)
    expected = load_project(good)
    assert _names(back) == _names(expected)
    for a, b in zip(back.layers, expected.layers, strict=True):
        assert a.points.equals(b.points)
    assert not back.read_only
    assert "rolled back" in back.warnings[0] and "p.wakeline-journal" in back.warnings[0]
    assert not Path(f"{path}-journal").exists()
    assert not lock_path(path).exists()  # the lock taken for the roll-back is given back
    again = load_project(path)  # opens plainly now
    assert again.warnings == [] and _names(again) == _names(expected)


def test_a_hot_journal_in_a_read_only_folder_opens_read_only_from_a_copy(
    good, tmp_path, monkeypatch
):
    import wakeline.core.project as project_mod

    path = _crash_mid_write(good, tmp_path / "ro")
    journal = Path(f"{path}-journal").read_bytes()
    half_written = path.read_bytes()
    folder = path.parent
    real_access = os.access
    # Root can write anything: the read-only folder is simulated for it.
    monkeypatch.setattr(
        project_mod.os,
        "access",
        lambda p, mode: False if Path(p) in (path, folder) else real_access(p, mode),
    )
    back = load_project(path)
    assert back.read_only and _names(back) == _names(load_project(good))
    assert "read-only" in back.warnings[0] and "rolled back" in back.warnings[0]
    assert not any("wakeline-ro-" in w for w in back.warnings)  # not the copy's own
    # The file and its journal are left as they were.
    assert path.read_bytes() == half_written
    assert Path(f"{path}-journal").read_bytes() == journal


def test_a_hot_journal_of_a_project_open_elsewhere_is_not_touched(good, tmp_path):
    path = _crash_mid_write(good, tmp_path / "held")
    half_written = path.read_bytes()
    # A lock held by a process that runs (this one, as another window would be).
    lock_path(path).write_text(
        json.dumps(
            {
                "token": "other",
                "pid": os.getpid(),
                "host": __import__("socket").gethostname(),
                "user": "them",
                "since": "2026-12-04 10:00:00 UTC",
            }
        )
    )
    with pytest.raises(InputError) as err:
        load_project(path)
    text = str(err.value)
    assert "middle of a write" in text and f"process {os.getpid()}" in text
    assert "not a Wakeline project" not in text
    assert path.read_bytes() == half_written and Path(f"{path}-journal").exists()
    # The holder gone (its process no longer runs): the stale lock is taken over.
    lock_path(path).write_text(lock_path(path).read_text().replace(str(os.getpid()), "999999"))
    back = load_project(path)
    assert _names(back) == _names(load_project(good))
    assert any("taken over" in w for w in back.warnings)
    assert not lock_path(path).exists()


def test_messages_tell_a_non_project_from_a_project_that_cannot_be_read(good, tmp_path):
    garbage = tmp_path / "garbage.wakeline"
    garbage.write_bytes(b"not a database at all" * 10)
    with pytest.raises(InputError, match="not a Wakeline project"):
        load_project(garbage)
    empty = tmp_path / "empty.wakeline"
    empty.write_bytes(b"")
    with pytest.raises(InputError, match="the file is empty"):
        load_project(empty)
    # A folder where the project should be: SQLite cannot open it; that is no verdict
    # on any project's content.
    folder = tmp_path / "folder.wakeline"
    folder.mkdir()
    with pytest.raises(InputError) as err:
        load_project(folder)
    assert "could not be read" in str(err.value)
    assert "not a Wakeline project" not in str(err.value)
    # A real project whose file SQLite reports as damaged.
    bad = tmp_path / "bad.wakeline"
    data = bytearray(good.read_bytes())
    data[4096 : 4096 * 3] = b"\xff" * (4096 * 2)  # the pages after the first
    bad.write_bytes(bytes(data))
    with pytest.raises(InputError) as err:
        load_project(bad)
    assert "not a Wakeline project" not in str(err.value)


def test_the_window_opens_a_project_left_mid_write(good, tmp_path, qtbot, monkeypatch):
    """File ▸ Open project on a crashed project: it opens, and the dialog says the
    unfinished write was rolled back; a project that cannot be opened says why."""
    from PySide6 import QtWidgets

    from conftest import make_window
    from wakeline.app.main import wait_for_jobs

    path = _crash_mid_write(good, tmp_path / "crash")
    shown = []
    monkeypatch.setattr(
        QtWidgets.QMessageBox, "warning", lambda _w, title, text: shown.append((title, text))
    )
    w = make_window(qtbot, tmp_path)
    w.open_project(path)
    wait_for_jobs(w)
    assert w.project.path == path and len(w.layers) == 2
    assert shown and shown[-1][0] == "Project opened with warnings"
    assert "rolled back" in shown[-1][1]
    # Held by a live process: the dialog says so, not "not a Wakeline project".
    other = _crash_mid_write(good, tmp_path / "held")
    lock_path(other).write_text(
        json.dumps(
            {
                "token": "other",
                "pid": os.getpid(),
                "host": __import__("socket").gethostname(),
                "user": "them",
                "since": "2026-12-04 10:00:00 UTC",
            }
        )
    )
    w.open_project(other)
    wait_for_jobs(w)
    assert shown[-1][0] == "Open project failed"  # a title, not the job's internal name
    assert "middle of a write" in shown[-1][1] and "not a Wakeline project" not in shown[-1][1]
    assert w.project.path == path  # the open session is left as it was
    w.project.flush()
    con = sqlite3.connect(path)
    assert con.execute("SELECT count(*) FROM layers").fetchone() == (2,)
    con.close()

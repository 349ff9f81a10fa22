"""One writer per project file (operator test: a project open in two windows or processes
silently lost one window's layers — both numbered their new layer L2)."""

import json
import os
import socket
import subprocess
import sys
import time

import pytest

from wakeline.core import simulate
from wakeline.core.errors import InputError
from wakeline.core.project import load_project, save_project
from wakeline.core.project_lock import ProjectLocks, lock_path, read_holder
from wakeline.core.session import Session

HOLD = """
import sys
from wakeline.core.project_lock import ProjectLocks
locks = ProjectLocks()
ok, note = locks.acquire(sys.argv[1])
print("held" if ok else "refused: " + note, flush=True)
sys.stdin.readline()
locks.release(sys.argv[1])
print("released", flush=True)
"""


def _session() -> Session:
    s = Session()
    s.add_layer("demo", "source", simulate.demo_scene().head(200))
    return s


def test_lock_is_taken_released_and_counted(tmp_path):
    proj = tmp_path / "work.wakeline"
    a, b = ProjectLocks(), ProjectLocks()
    assert a.acquire(proj) == (True, "")
    holder = read_holder(proj)
    assert holder is not None and holder.pid == os.getpid() and holder.token == a.token
    ok, who = b.acquire(proj)  # a second window of this process
    assert not ok and f"process {os.getpid()}" in who
    assert a.acquire(proj)[0]  # the same window again (Save as onto its own file)
    a.release(proj)
    assert lock_path(proj).exists() and not b.acquire(proj)[0]  # one claim is left
    a.release(proj)
    assert not lock_path(proj).exists()
    assert b.acquire(proj) == (True, "")
    b.release_all()
    assert not lock_path(proj).exists()


def test_a_live_process_holds_the_project_and_save_as_is_refused(tmp_path):
    proj = tmp_path / "work.wakeline"
    save_project(_session(), proj)
    with subprocess.Popen(
        [sys.executable, "-c", HOLD, str(proj)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    ) as child:
        assert child.stdout.readline().strip() == "held"
        ok, who = ProjectLocks().acquire(proj)
        assert not ok and f"process {child.pid}" in who and socket.gethostname() in who
        with pytest.raises(InputError, match=f"open in process {child.pid}"):
            save_project(_session(), proj)
        assert len(load_project(proj).layers) == 1  # reading is always allowed
        child.stdin.write("\n")
        child.stdin.flush()
        assert child.stdout.readline().strip() == "released"
    assert ProjectLocks().acquire(proj)[0]


def test_a_lock_left_by_a_crash_is_taken_over(tmp_path):
    proj = tmp_path / "work.wakeline"
    with subprocess.Popen(
        [sys.executable, "-c", HOLD, str(proj)], stdin=subprocess.PIPE, stdout=subprocess.PIPE
    ) as child:
        assert child.stdout.readline().strip() == b"held"
        child.kill()  # the process dies holding the lock
        child.wait()
    assert lock_path(proj).exists()
    locks = ProjectLocks()
    ok, note = locks.acquire(proj)
    assert ok and "no longer running" in note and str(child.pid) in note
    assert read_holder(proj).token == locks.token
    save_project(_session(), proj, lock_token=locks.token)  # its holder may write it


def test_a_lock_from_another_host_is_respected_and_named(tmp_path):
    proj = tmp_path / "work.wakeline"
    body = {"token": "x", "pid": 1, "host": "elsewhere.example", "user": "ops", "since": "t"}
    lock_path(proj).write_text(json.dumps(body))
    ok, who = ProjectLocks().acquire(proj)
    assert not ok and "elsewhere.example" in who and str(lock_path(proj)) in who


def test_a_damaged_lock_is_held_while_young_and_stale_when_old(tmp_path):
    proj = tmp_path / "work.wakeline"
    lock_path(proj).write_text("{")  # being written, or left half-written
    assert not ProjectLocks().acquire(proj)[0]
    old = time.time() - 60
    os.utime(lock_path(proj), (old, old))
    ok, note = ProjectLocks().acquire(proj)
    assert ok and "taken over" in note


def test_a_lock_whose_process_number_was_reused_is_stale(tmp_path):
    """Operator test: a crash, a reboot, and the lock's pid (1 here) now belongs to
    another process that started after the lock was taken: taken over, not respected
    forever."""
    proj = tmp_path / "work.wakeline"
    body = {
        "token": "x",
        "pid": 1,
        "host": socket.gethostname(),
        "user": "alice",
        "since": "2001-01-01 00:00:00 UTC",  # long before process 1 started
    }
    lock_path(proj).write_text(json.dumps(body))
    if not os.path.exists("/proc/1/stat"):
        pytest.skip("no /proc: process start times are not known here")
    ok, note = ProjectLocks().acquire(proj)
    assert ok and "no longer running" in note
    # A live holder that started before its lock: respected, and the way out is named.
    body.update(pid=os.getppid(), since="2999-01-01 00:00:00 UTC")
    lock_path(proj).write_text(json.dumps(body))
    ok, who = ProjectLocks().acquire(proj)
    assert not ok and str(lock_path(proj)) in who

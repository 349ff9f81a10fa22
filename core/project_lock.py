"""One writer per project file: a small lock file beside it.

Two windows (or two processes) writing one ``.wakeline`` file each number their new
layers from what they read, so one window's layers silently replaced the other's (operator
test: both added an "L2"). The first window to open or save a project holds
``NAME.wakeline.lock`` (JSON: process, host, user, time, a token per holder); a second one
finds it and opens the project read-only, saying who holds it. A lock left by a process
that no longer runs on this host is stale and taken over; one from another host (a shared
folder) cannot be checked and is respected, with the lock file named so the operator can
remove it.

The holder is a :class:`ProjectLocks` (one per window): it may hold several paths, and a
path it releases while its writer still drains stays held until the writer is done (the
window's "Save as" onto the same file again takes it back first).
"""

import datetime as _dt
import getpass
import json
import os
import socket
import threading
import uuid
from dataclasses import dataclass
from pathlib import Path

__all__ = ["LockHolder", "ProjectLocks", "lock_path", "read_holder"]


def lock_path(project: str | Path) -> Path:
    """The lock file of a project: ``NAME.wakeline.lock`` beside it."""
    project = Path(project)
    return project.with_name(project.name + ".lock")


@dataclass(frozen=True)
class LockHolder:
    """Who holds a project (what the lock file says)."""

    token: str
    pid: int
    host: str
    user: str
    since: str  # ISO time, UTC
    age_s: float = 0.0  # how old the lock file is (s)

    def describe(self) -> str:
        """One line for the operator."""
        if self.pid <= 0:
            return "another Wakeline (its lock file cannot be read)"
        return f"process {self.pid} of {self.user or '?'} on {self.host or '?'} since {self.since}"

    def alive(self) -> bool | None:
        """Whether the holding process still runs: True/False on this host, None when the
        lock comes from another host (it cannot be checked from here)."""
        if self.pid <= 0:  # damaged: being written just now, or left half-written
            return self.age_s < 10.0
        if self.host != socket.gethostname():
            return None
        if self.pid == os.getpid():
            return True
        try:
            os.kill(self.pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:  # runs, as another user
            pass
        except OSError:
            return False
        # The number may have been given to another process since (a crash, then a
        # reboot): one that started after the lock was taken is not its holder.
        started = _process_start(self.pid)
        taken = _parse_since(self.since)
        return not (started is not None and taken is not None and started > taken + 2.0)


def _process_start(pid: int) -> float | None:
    """When process ``pid`` started (unix s), from /proc (Linux); None elsewhere."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        ticks = int(stat[stat.rindex(")") + 2 :].split()[19])  # field 22: starttime
        boot = next(
            float(line.split()[1])
            for line in Path("/proc/stat").read_text().splitlines()
            if line.startswith("btime ")
        )
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return None


def _parse_since(since: str) -> float | None:
    try:
        t = _dt.datetime.strptime(since, "%Y-%m-%d %H:%M:%S UTC")
    except ValueError:
        return None
    return t.replace(tzinfo=_dt.UTC).timestamp()


def read_holder(project: str | Path) -> LockHolder | None:
    """The holder named in a project's lock file; None when there is no lock file. An
    unreadable or damaged lock file reads as a holder of unknown process (pid 0): running
    while the file is younger than 10 s (it may be being written), stale after."""
    path = lock_path(project)
    try:
        text = path.read_text(encoding="utf-8")
        age = max(_dt.datetime.now().timestamp() - path.stat().st_mtime, 0.0)
    except FileNotFoundError:
        return None
    except OSError:
        text, age = "", 0.0
    try:
        d = json.loads(text)
        return LockHolder(
            str(d["token"]), int(d["pid"]), str(d["host"]), str(d["user"]), str(d["since"]), age
        )
    except (ValueError, KeyError, TypeError):
        return LockHolder("", 0, "", "", "?", age)


class ProjectLocks:
    """The project files one window holds. Thread-safe: the project writer's thread
    releases a path once its queue is written."""

    def __init__(self) -> None:
        self.token = uuid.uuid4().hex
        self._held: dict[Path, int] = {}  # path -> number of claims (follow + draining)
        self._mutex = threading.Lock()

    def acquire(self, project: str | Path) -> tuple[bool, str]:
        """Hold ``project``. Returns (True, note) when held — the note says a stale lock
        was taken over, or is empty — or (False, who) when another holder has it."""
        key = Path(project).absolute()
        with self._mutex:
            if key in self._held:
                self._held[key] += 1
                return True, ""
            note = ""
            for _ in range(2):
                if self._create(key):
                    self._held[key] = 1
                    return True, note
                holder = read_holder(key)
                if holder is None:  # removed in between: try again
                    continue
                if holder.token == self.token:
                    self._held[key] = 1
                    return True, note
                alive = holder.alive()
                if alive is False:
                    note = f"a lock left by {holder.describe()} (no longer running) was taken over"
                    try:
                        lock_path(key).unlink()
                    except FileNotFoundError:
                        pass
                    except OSError as exc:
                        return False, f"{holder.describe()} (stale lock, cannot remove: {exc})"
                    continue
                if alive is None:
                    return False, (
                        f"{holder.describe()}; if it is not open there any more, "
                        f"remove {lock_path(key)}"
                    )
                return False, (
                    f"{holder.describe()} (if no Wakeline has it open, remove {lock_path(key)})"
                )
            return False, "another Wakeline (the lock file keeps changing)"

    def release(self, project: str | Path) -> None:
        """Give up one claim on ``project``; the lock file goes with the last one (and
        only when it is still ours)."""
        key = Path(project).absolute()
        with self._mutex:
            n = self._held.get(key, 0) - 1
            if n > 0:
                self._held[key] = n
                return
            self._held.pop(key, None)
            self._remove_own(key)

    def release_all(self) -> None:
        """Give up every project held, whatever the claims (closing the window)."""
        with self._mutex:
            keys, self._held = list(self._held), {}
            for key in keys:
                self._remove_own(key)

    def _remove_own(self, key: Path) -> None:
        """Remove ``key``'s lock file when it is still ours."""
        holder = read_holder(key)
        if holder is not None and holder.token == self.token:
            try:
                lock_path(key).unlink()
            except OSError:
                pass

    def _create(self, key: Path) -> bool:
        """Write the lock file if there is none (atomically: O_EXCL); False if there is.
        A folder that cannot be written holds no lock (the project is read-only anyway)."""
        body = json.dumps(
            {
                "token": self.token,
                "pid": os.getpid(),
                "host": socket.gethostname(),
                "user": _user(),
                "since": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC"),
                "program": "wakeline",
            }
        )
        try:
            fd = os.open(lock_path(key), os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            return False
        except OSError:
            return True  # cannot lock here (read-only folder): nothing to coordinate with
        try:
            os.write(fd, body.encode("utf-8"))
        finally:
            os.close(fd)
        return True


def _user() -> str:
    try:
        return getpass.getuser()
    except Exception:  # noqa: BLE001 - no user name is not an error
        return ""

"""Running core jobs off the GUI thread.

A job is a plain function ``fn(progress) -> result`` calling core code; the core calls
``progress(fraction, text)`` now and then, and the runner's callback raises
:class:`~wakeline.core.errors.Cancelled` once the job was cancelled, which unwinds it.
The runner reports through one Qt signal carrying typed messages (frozen dataclasses):
:class:`Started`, :class:`Progress`, :class:`Finished`, :class:`Failed`,
:class:`Cancelled`. One job at a time: starting a new one cancels the old one, whose
late messages are dropped. Job numbers are unique across runners (the window's
exports run on a runner of their own beside its steps').

A job whose function has ``keeps_result = True`` (an export: the file is written and
moved into place as its last act) is finished once the function returns, even if a
cancel came meanwhile: the result exists, so it is reported, not called cancelled.
"""

import contextlib
import ctypes
import itertools
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import pyarrow as pa
import shiboken6
from PySide6 import QtCore

from wakeline.core.errors import Cancelled as CoreCancelled
from wakeline.core.errors import InputError

#: Job numbers, shared by every runner so a message names one job in one window.
_NUMBERS = itertools.count(1)


@dataclass(frozen=True)
class Started:
    job: int
    name: str


@dataclass(frozen=True)
class Progress:
    job: int
    fraction: float
    text: str


@dataclass(frozen=True)
class Finished:
    job: int
    name: str
    result: Any
    seconds: float


@dataclass(frozen=True)
class Failed:
    job: int
    name: str
    message: str  # for the operator: one sentence
    detail: str  # traceback for internal errors, empty for bad input


@dataclass(frozen=True)
class Cancelled:
    job: int
    name: str


def _malloc_trim() -> Callable[[int], int] | None:
    """glibc's ``malloc_trim`` (None elsewhere: macOS, Windows, musl)."""
    try:
        return ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError, TypeError):
        return None


_MALLOC_TRIM = _malloc_trim()


def give_back_free_memory() -> None:
    """Return to the system what the allocators keep of memory freed: a step on a million
    points frees hundreds of MB of temporaries that glibc's malloc (its arenas) and Arrow's
    pool keep for later, in the window's resident size (defect #8, 1 M points: 1.75 GB
    after the pipeline, 1.38 GB with this). Called in the worker thread after each job
    (ctypes releases the GIL; 4–110 ms measured there)."""
    pa.default_memory_pool().release_unused()
    if _MALLOC_TRIM is not None:
        _MALLOC_TRIM(0)


def new_job_number() -> int:
    """A job number no runner has given (for a job queued before it runs)."""
    return next(_NUMBERS)


class _Thread(QtCore.QThread):
    message = QtCore.Signal(object)

    def __init__(
        self, job: int, name: str, fn: Callable, cancel: threading.Event, parent: QtCore.QObject
    ) -> None:
        super().__init__(parent)
        self.job, self.name, self.fn, self.cancel = job, name, fn, cancel
        #: Whether its Finished or Failed is relayed though the job was replaced (read by
        #: the runner after the job: ``fn``, which keeps its inputs, is dropped then).
        self.keeps_result = bool(getattr(fn, "keeps_result", False))

    def _progress(self, fraction: float, text: str = "") -> None:
        if self.cancel.is_set():
            raise CoreCancelled()
        self.message.emit(Progress(self.job, float(fraction), text))

    def run(self) -> None:
        t0 = time.perf_counter()
        self.message.emit(Started(self.job, self.name))
        try:
            result = self.fn(self._progress)
            if self.cancel.is_set() and not self.keeps_result:
                raise CoreCancelled()
        except CoreCancelled:
            self.message.emit(Cancelled(self.job, self.name))
        except InputError as exc:
            self.message.emit(Failed(self.job, self.name, str(exc), ""))
        except Exception as exc:  # an internal error: keep the traceback for the log
            self.message.emit(
                Failed(
                    self.job,
                    self.name,
                    f"{type(exc).__name__}: {exc}",
                    traceback.format_exc(),
                )
            )
        else:
            self.message.emit(Finished(self.job, self.name, result, time.perf_counter() - t0))
        finally:
            # The job's closure holds what it read (a layer's points, its views): not kept
            # by the finished thread until the next job replaces it (defect #8).
            self.fn = result = None
            with contextlib.suppress(Exception):  # memory given back is never an error
                give_back_free_memory()


class JobRunner(QtCore.QObject):
    """Runs one job at a time in a worker thread; see the module docstring."""

    message = QtCore.Signal(object)

    def __init__(self, parent: QtCore.QObject | None = None) -> None:
        super().__init__(parent)
        self._next = 0  # the last job number given
        self._current: _Thread | None = None
        self._cancel: threading.Event | None = None
        self._old: list[_Thread] = []

    @property
    def busy(self) -> bool:
        """A job (current or cancelled, still unwinding) is running."""
        return any(t.isRunning() for t in self._threads())

    @property
    def current_job(self) -> int | None:
        return self._current.job if self._current is not None else None

    def _threads(self) -> list["_Thread"]:
        return [t for t in [*self._old, self._current] if t is not None and shiboken6.isValid(t)]

    def run(
        self, name: str, fn: Callable[[Callable[[float, str], None]], Any], job: int | None = None
    ) -> int:
        """Start ``fn(progress)`` in the worker; cancels a running job first. Returns the
        job number carried by its messages (``job``: one taken before with
        :func:`new_job_number`, for a job that waited in a queue)."""
        self.cancel()
        if self._current is not None:  # finished: nothing refers to it any more
            self._current.deleteLater()
        self._next = job if job is not None else next(_NUMBERS)
        cancel = threading.Event()
        # Threads are children of the runner (Qt owns them) and no Python closure holds
        # them; finished ones are released with deleteLater.
        thread = _Thread(self._next, name, fn, cancel, self)
        thread.message.connect(self._relay)
        thread.finished.connect(self._reap)
        self._current, self._cancel = thread, cancel
        thread.start()
        return self._next

    def cancel(self) -> None:
        """Ask the running job to stop (it stops at its next progress call)."""
        if self._cancel is not None:
            self._cancel.set()
        if self._current is not None and self._current.isRunning():
            self._old.append(self._current)
            self._current, self._cancel = None, None

    def wait(self, ms: int = 30_000) -> bool:
        """Block until every thread has ended (for shutdown and tests)."""
        return all(t.wait(ms) for t in self._threads())

    def _relay(self, msg: object) -> None:
        # Messages of a job that was cancelled or replaced are dropped, except its Cancelled
        # and the last message (Finished or Failed) of a job that keeps its result: a file
        # written is reported, and a failure still ends the job for its owner (an export
        # queue waits for it).
        if getattr(msg, "job", None) != self.current_job and not isinstance(msg, Cancelled):
            thread = self.sender()
            last = isinstance(msg, Finished | Failed)
            if not (last and getattr(thread, "keeps_result", False)):
                return
        self.message.emit(msg)

    def _reap(self) -> None:
        thread = self.sender()
        if thread in self._old:  # a cancelled job has unwound
            self._old.remove(thread)
            thread.deleteLater()

"""Runs the map's level-of-detail jobs (pure functions) on a Qt thread pool and hands
the results back on the GUI thread, so a zoom on a million points never blocks."""

import collections
import logging
from collections.abc import Callable

import shiboken6
from PySide6 import QtCore

log = logging.getLogger(__name__)

#: Between two results handed over to the GUI thread (ms).
STEP_MS = 5


class _Signals(QtCore.QObject):
    done = QtCore.Signal(object, object)  # callback, result


class _Task(QtCore.QRunnable):
    def __init__(self, job: Callable, done: Callable, signals: _Signals) -> None:
        super().__init__()
        self.job, self.done, self.signals = job, done, signals

    def run(self) -> None:
        # The job's closure holds what it reads (a layer's points): let go once it has run,
        # not when the pool drops this task's wrapper (defect #8).
        job, self.job = self.job, None
        try:
            result = job()
        except Exception:  # noqa: BLE001 - a failed decimation keeps the old drawing
            # Logged, and handed over as None so that the caller stops waiting for it.
            log.exception("map drawing job failed")
            result = None
        # The window (and with it the signals' owner) may be gone by now: closed while a
        # frame was made. Nobody waits for the result then.
        signals = self.signals
        if not shiboken6.isValid(signals):
            return
        try:
            signals.done.emit(self.done, result)
        except RuntimeError:  # deleted between the check and the emit
            log.debug("map drawing job finished after its window was closed")


class LodWorker(QtCore.QObject):
    """``worker(job, done)``: the :data:`~wakeline.app.map_canvas.LodExecutor` protocol."""

    def __init__(self, parent: QtCore.QObject | None = None) -> None:
        super().__init__(parent)
        # The application's global pool, never a pool of our own: a QThreadPool destroyed
        # by Python's garbage collector waits for its running task while holding the GIL,
        # which that task needs — a deadlock (seen in the GUI tests).
        self.pool = QtCore.QThreadPool.globalInstance()
        self.signals = _Signals(self)
        self.signals.done.connect(self._arrived)
        # Results are handed over one per timer turn: several layers re-decimated after a
        # zoom would otherwise be swapped in, and stroked by one paint, all at once.
        self._results: collections.deque = collections.deque()
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(STEP_MS)
        self._timer.timeout.connect(self._hand_over)

    def _arrived(self, callback: Callable, result: object) -> None:
        self._results.append((callback, result))
        if not self._timer.isActive():
            self._timer.start()

    def _hand_over(self) -> None:
        if self._results:
            callback, result = self._results.popleft()
            callback(result)
        if self._results:
            self._timer.start()

    @property
    def pending(self) -> int:
        """Results waiting to be handed over."""
        return len(self._results)

    def __call__(self, job: Callable, done: Callable) -> None:
        self.pool.start(_Task(job, done, self.signals))

    def wait(self, ms: int = 30_000) -> bool:
        return self.pool.waitForDone(ms)

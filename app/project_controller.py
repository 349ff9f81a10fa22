"""Keeps the project file in step with the session, off the GUI thread.

Once the work has a project file, every session event becomes one small write queued on
the core's :class:`~wakeline.core.project.ProjectWriter` thread: a new or replaced layer
writes its Parquet once; visibility, colour, order, selection, the active layer, the map's view
(debounced by :mod:`wakeline.app.view_keeper`), the time window, the slider's time
(debounced by :class:`~wakeline.app.map_time.TimeController`) and parameters are small
rows.
A failed write is never silent: :attr:`failed` carries the message to the window (a
dialog, the log, and the title marked unsaved).

One writer per file: the controller holds the project's lock
(:mod:`wakeline.core.project_lock`) while it follows it; a project another window or
process holds opens read-only, and "Save as" onto it is refused.
"""

import time
from pathlib import Path

from PySide6 import QtCore

from wakeline.core.errors import InputError
from wakeline.core.project import ProjectWriter, save_project
from wakeline.core.project_lock import ProjectLocks
from wakeline.core.session import BEARING_KIND, Session


class ProjectController(QtCore.QObject):
    failed = QtCore.Signal(str)  # a write failed: the message
    _error = QtCore.Signal(str)  # from the writer thread

    def __init__(self, session: Session, parent: QtCore.QObject | None = None) -> None:
        super().__init__(parent)
        self.session = session
        self.path: Path | None = None
        self.read_only = False
        self.dirty = False  # a write failed since the file was saved or opened
        self.failures = 0  # writes failed since then (the window shows the first)
        #: The last failure repeats the one before within 2 s (the other writes of
        #: one change: a decision, then the layer's points): the window logs it once.
        self.repeated = False
        self._last_failure: tuple[str, float] = ("", 0.0)
        self.unsaved = False  # changes made while following a read-only file
        self.locks = ProjectLocks()
        self._held: Path | None = None  # the path whose lock the current writer holds
        self.writer: ProjectWriter | None = None
        self._draining: list[ProjectWriter] = []  # released, still writing their queue
        self._error.connect(self._on_error)
        session.subscribe(self._on_event)

    # -- attaching ----------------------------------------------------------------

    def save_as(self, path: Path, state: dict | None = None) -> tuple[bool, str]:
        """Write the whole session to ``path`` (in the writer thread), then follow it.
        Returns (False, why) when another window or process holds ``path`` (the current
        file is still followed), else (True, note) — the note says a stale lock was taken
        over, or is empty."""
        ok, note = self.locks.acquire(path)
        if not ok:
            return False, f"{path} is open in {note}: save it under another name"
        self.release()
        self._held = Path(path)
        snapshot = Session()
        snapshot.layers = dict(self.session.layers)
        snapshot.sources = list(self.session.sources)
        snapshot.params = dict(self.session.params)
        snapshot.selection = list(self.session.selection)
        snapshot.decisions = list(self.session.decisions)
        snapshot.time_window = self.session.time_window
        snapshot.current_time = self.session.current_time
        snapshot.map_view = self.session.map_view
        snapshot.active = self.session.active
        self._attach(Path(path), read_only=False)
        token = self.locks.token
        self.writer.submit_file(lambda p: save_project(snapshot, p, state, lock_token=token))
        return True, note

    def follow(self, path: Path, read_only: bool) -> str | None:
        """Continue writing to an opened project (nothing when it is read-only). When
        another window or process holds it, it is followed read-only: the return value
        says who holds it (or that a stale lock was taken over), else None."""
        self.release()
        note = None
        if not read_only:
            ok, note = self.locks.acquire(path)
            if not ok:
                read_only = True
                note = f"the project is open in {note}: it opens read-only, changes are not saved"
        self.path, self.read_only, self.dirty = Path(path), read_only, False
        if not read_only:
            self._held = Path(path)
            self._attach(Path(path), read_only=False)
        return note or None

    def _attach(self, path: Path, read_only: bool) -> None:
        """A writer for ``path``. Its first task waits (in its own thread, never the
        GUI's) until every writer released before has written its queue: the same file
        may be written again (Save as twice; a read-only project opened in between)."""
        self.path, self.read_only, self.dirty, self.failures = path, read_only, False, 0
        self.writer = ProjectWriter(path, lambda exc: self._error.emit(_describe(exc)))
        earlier = [w for w in self._draining if w.busy()]
        if earlier:
            self.writer.submit_file(lambda _p: [w.wait() for w in earlier])

    def release(self) -> None:
        """Stop following the file without waiting: the writer finishes its queue in its
        own thread (a Save as right after a step waited 0.2–1 s for it on the GUI thread);
        the next writer waits for it."""
        previous, self.writer = self.writer, None
        held, self._held = self._held, None
        if previous is not None:
            if held is not None:  # the lock goes once the queue is written
                previous.submit_file(lambda _p: self.locks.release(held))
            previous.finish()
            self._draining = [w for w in self._draining if w.busy()] + [previous]
        elif held is not None:
            self.locks.release(held)
        self.path, self.read_only, self.unsaved = None, False, False

    def detach(self, timeout: float = 30.0) -> None:
        """Stop following the file once everything queued is written, the released
        writers' too (closing the window)."""
        if self.writer is not None:
            self.writer.close(timeout)
            self.writer = None
        for writer in self._draining:
            writer.wait(timeout)
        self._draining = []
        self.locks.release_all()
        self._held = None
        self.path, self.read_only, self.unsaved = None, False, False

    def flush(self, timeout: float = 30.0) -> bool:
        return self.writer.flush(timeout) if self.writer is not None else True

    # -- writes -------------------------------------------------------------------

    def _submit(self, task) -> None:
        if self.writer is not None:
            self.writer.submit(task)

    def _pos(self, layer_id: str) -> int:
        order = list(self.session.layers)
        return order.index(layer_id) if layer_id in order else len(order)

    def _on_event(self, event: str, layer_id: str) -> None:
        if self.writer is None:
            # Panning, another active layer or the slider moved in a read-only project
            # is no work lost.
            moved = event in ("map_view", "active", "current_time")
            self.unsaved = self.unsaved or (self.path is not None and not moved)
            return
        layer = self.session.layers.get(layer_id)
        if event in ("added", "changed") and layer is not None:
            pos = self._pos(layer_id)
            self._submit(lambda st: st.put_layer(layer, pos))
            if layer.kind in ("source", BEARING_KIND):  # "changed": a file read again
                sources = list(self.session.sources)
                self._submit(lambda st: st.put_sources(sources))
        elif event == "tables" and layer is not None:  # kept inputs: not its points
            pos = self._pos(layer_id)
            self._submit(lambda st: st.put_tables(layer, pos))
        elif event in ("visibility", "color") and layer is not None:
            pos = self._pos(layer_id)
            self._submit(lambda st: st.put_layer(layer, pos, with_data=False))
        elif event == "decisions" and layer is not None:  # a re-run's carried review
            from wakeline.core.review_session import queue_key

            key = queue_key(layer)
            rows = self.session.decisions
            for row in [d for d in rows if isinstance(d, dict) and d.get("queue") == key]:
                self.add_decision(row)
        elif event == "removed":
            self._submit(lambda st: st.delete_layer(layer_id))
        elif event == "reordered":
            order = list(self.session.layers)
            self._submit(lambda st: st.put_order(order))
        elif event == "time_window":
            window = self.session.time_window
            self._submit(lambda st: st.put_time_window(window))
        elif event == "current_time":  # debounced by the TimeController
            t = self.session.current_time
            self._submit(lambda st: st.put_current_time(t))
        elif event == "map_view":
            view = self.session.map_view
            self._submit(lambda st: st.put_map_view(view))
        elif event == "active":  # the selection keeps only the active layer's tracks
            active, selection = self.session.active, list(self.session.selection)
            self._submit(lambda st: _put_active(st, active, selection))

    def put_state(self, key: str, value: object) -> None:
        """A small state row (the selection)."""
        self._submit(lambda st: st.put_state(key, value))

    def put_sources(self, sources: list) -> None:
        """The sources table (a source found beside a moved project)."""
        self._submit(lambda st: st.put_sources(sources))

    def put_layer_attrs(self, layer_id: str) -> None:
        """A layer's attributes (its meta), not its points."""
        layer = self.session.layers.get(layer_id)
        if layer is not None:
            pos = self._pos(layer_id)
            self._submit(lambda st: st.put_layer(layer, pos, with_data=False))

    def put_params(self, params: dict) -> None:
        params = dict(params)
        self._submit(lambda st: st.put_params(params))

    def add_decision(self, decision: dict) -> None:
        self.unsaved = self.unsaved or (self.writer is None and self.path is not None)
        self._submit(lambda st: st.add_decision(decision))

    def mark_decisions_checked(self) -> None:
        """The file's decisions need no repair (the migration on open ran and its repairs
        are queued before this): :meth:`ProjectStore.mark_decisions_checked`."""
        self._submit(lambda st: st.mark_decisions_checked())

    def _on_error(self, message: str) -> None:
        self.dirty = True
        self.failures += 1
        now = time.monotonic()
        last, when = self._last_failure
        self.repeated = message == last and now - when < 2.0
        self._last_failure = (message, now)
        self.failed.emit(message)


def _put_active(store, active: str | None, selection: list) -> None:
    """The ``active`` and ``selection`` rows (another active layer keeps none of the last
    one's tracks selected)."""
    store.put_state("active", active)
    store.put_state("selection", selection)


def _describe(exc: Exception) -> str:
    if isinstance(exc, InputError):  # written for the operator (a project moved while open)
        return str(exc)
    if isinstance(exc, OSError):
        name = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        return f"{name}{exc.strerror or exc}"
    return f"{type(exc).__name__}: {exc}"

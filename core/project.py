"""The project file (``.wakeline``): one SQLite database written as the operator works.

What it holds: the sources (path and content hash), the parameters, every layer with its
lineage (Parquet blobs, so times, text and numbers come back exactly), the layers' side
tables, small state rows (the selection, the map's view, the active layer, the time
window, the time slider's time) and the review decisions.

It is written incrementally: a layer's Parquet once, when the layer is made (or
replaced); a visibility, selection or parameter change is one small row, each in its own
transaction — never the whole file again. Each transaction lands in the ``.wakeline`` file
itself (a rollback journal, not WAL: with WAL the committed work sat in a ``-wal`` side
file until a checkpoint, so a project renamed, moved or copied while open lost it, and a
project in a read-only folder could not be opened). A project moved or removed while open
is noticed at the next write, which fails with a message instead of writing elsewhere. :class:`ProjectWriter` does the writing on a
background thread and reports failures through a callback. "Save as" writes a complete
new file beside the target and renames it over, so a crash never leaves a half-written
project. Opening checks everything before anything is returned: a damaged or newer file
raises one :class:`InputError` and the caller's session stays untouched. A project left in
the middle of a write (a crash or power loss: its hot ``-journal`` beside it) is rolled
back to its last complete write once, read-write, with its lock held (a read-only
connection cannot), and opens with a warning saying so; in a read-only file or folder a
copy is rolled back and read instead; held by a process that still runs, it is left alone
and the message says who holds it. A file that cannot be read is "not a Wakeline project"
only when it is not one (garbage, empty, another database); an I/O problem says so. The state rows
only say where the operator was (what the map showed, what was selected): a bad one is
left out with one warning in :attr:`Project.warnings` and the project opens; a bad data
row (layers, parameters, decisions) refuses it as damaged.

Migrations on open: a version-1 file's layers and parameter table are read as today's
(written as today's at the next write of that row, or by Save as), and review decisions
that left a proposal rejected or split beside a target holding both its tracks (made
before a join accepted such rows) get one ``repair`` decision each, appended
(:attr:`Project.repairs`; the window writes them at once, then marks the file's
decisions checked, so the migration runs once per project, not on every open).
"""

import hashlib
import json
import logging
import os
import queue
import shutil
import sqlite3
import tempfile
import threading
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.dataset  # noqa: F401 - imported here, on the main thread: see below
import pyarrow.parquet as pq

from wakeline.core import __version__
from wakeline.core.errors import InputError, ProjectMoved
from wakeline.core.file_identity import check_identity, file_identity, moved_message
from wakeline.core.io.writer import atomic_path
from wakeline.core.pipeline import PARAMS_VERSION, params_from_version
from wakeline.core.project_lock import ProjectLocks, lock_path, read_holder
from wakeline.core.review_session import repair_decisions
from wakeline.core.session import Layer, MapView, Session, Source
from wakeline.core.timeline import TimeWindow, current_time_from_json, current_time_to_json

SCHEMA_VERSION = 2
#: The ``meta`` row counting the decisions known to need no repair (the migration on
#: open, :func:`~wakeline.core.review_session.repair_decisions`): the file's decision
#: count when they all are. Absent in projects of a Wakeline before it.
DECISIONS_CHECKED = "decisions_checked"

# ``pq.read_table`` imports ``pyarrow.dataset`` on first use. Done first in a worker
# thread while the GUI thread waits in its event loop, that import was seen to hang the
# GUI tests; importing it with this module (on the main thread) avoids it.

__all__ = [
    "Layer",
    "Project",
    "ProjectStore",
    "ProjectWriter",
    "Source",
    "file_hash",
    "load_project",
    "save_project",
]


def file_hash(path: str | Path) -> str:
    """SHA-256 of a file's content, hex."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


@dataclass
class Project:
    """What a project file holds, read back (see :func:`load_project`)."""

    sources: list[Source] = field(default_factory=list)
    params: dict[str, dict] = field(default_factory=dict)
    layers: list[Layer] = field(default_factory=list)
    selection: list[tuple[str, str, str]] = field(default_factory=list)  # layer id, sensor, batch
    decisions: list[dict] = field(default_factory=list)
    state: dict[str, object] = field(default_factory=dict)
    read_only: bool = False
    #: The map's time window (the ``time_window`` state row; None: none, or a project
    #: saved before it was kept).
    time_window: TimeWindow | None = None
    #: The map's view (the ``view`` state row, degrees; None: none kept).
    map_view: MapView | None = None
    #: The active layer's id (the ``active`` state row; None: none kept).
    active: str | None = None
    #: One sentence per state row left out because it could not be used.
    warnings: list[str] = field(default_factory=list)
    #: The time slider's time (the ``current_time`` state row, s; None: none kept).
    current_time: float | None = None
    #: Decision rows the migration on open added (already in :attr:`decisions`): the
    #: review rows a join of an older Wakeline left rejected or split beside a target
    #: holding both their tracks, accepted
    #: (:func:`wakeline.core.review_session.repair_decisions`). Not in the file yet:
    #: whoever follows the file writes them (the window does at once), or Save as does.
    repairs: list[dict] = field(default_factory=list)
    #: The file marks its decisions as needing no repair (the migration was skipped).
    #: False: whoever follows the file writes :attr:`repairs`, then
    #: :meth:`ProjectStore.mark_decisions_checked`, so the next open skips it.
    decisions_checked: bool = False
    #: Layers whose ``meta["file"]`` :meth:`locate_sources` changed (to be written).
    relocated_layers: list[str] = field(default_factory=list)
    #: The sentences of :meth:`locate_sources` (one per source found beside the project).
    located: list[str] = field(default_factory=list)

    def locate_sources(self, project_path: str | Path) -> list[str]:
        """Sources missing at their stored path but found beside the project file (same
        name, same SHA-256: a project folder moved or copied with its data files) are
        used from there: the source's path and its layers' ``meta["file"]`` follow.
        One sentence per source found so; :meth:`source_problems` then passes them.
        Returns the sentences; the ids of the layers changed are in
        :attr:`relocated_layers`."""
        notes = []
        folder = Path(project_path).resolve().parent
        for k, s in enumerate(self.sources):
            old = Path(s.path)
            if old.exists():
                continue
            beside = folder / old.name
            if not beside.is_file() or file_hash(beside) != s.sha256:
                continue
            self.sources[k] = Source(str(beside), s.sha256)
            for lay in self.layers:
                file = lay.meta.get("file")
                if file and (file == s.path or str(Path(str(file)).resolve()) == s.path):
                    lay.meta["file"] = str(beside)
                    self.relocated_layers.append(lay.id)
            notes.append(
                f"source file found beside the project: {beside} (same content as "
                f"{s.path}, which is no longer there)"
            )
        self.located += notes
        return notes

    def source_problems(self) -> list[str]:
        """One sentence per source that is missing or whose content changed."""
        out = []
        for s in self.sources:
            p = Path(s.path)
            if not p.exists():
                out.append(f"source file missing: {s.path} (its layers are kept in the project)")
            elif file_hash(p) != s.sha256:
                out.append(f"source file changed since it was loaded: {s.path}")
        return out

    def to_session(self, session: Session | None = None) -> Session:
        """Fill ``session`` (cleared first) or a new one with this project's content."""
        session = session or Session()
        session.clear()
        session.sources[:] = self.sources
        session.params = dict(self.params)
        # Decisions first: a listener binding a layer's review queue as the layer is
        # added finds them (they are replayed per layer).
        session.decisions = list(self.decisions)
        for lay in self.layers:
            session.add_layer(
                lay.name,
                lay.kind,
                lay.points,
                lay.meta,
                color=lay.color,
                visible=lay.visible,
                layer_id=lay.id,
                **{**lay.lineage(), "tables": lay.tables},
            )
        # The active layer, or (a project saved before it was kept) the selection's.
        active = self.active if self.active in session.layers else None
        if active is None and self.selection and self.selection[0][0] in session.layers:
            active = self.selection[0][0]
        session.set_active(active)
        # The table shows the active layer's tracks: a selection of another is not shown.
        session.selection = [s for s in self.selection if s[0] == active]
        session.set_time_window(self.time_window)
        session.set_current_time(self.current_time)
        session.set_map_view(self.map_view)
        return session


def _to_parquet(df: pd.DataFrame) -> pa.Buffer:
    """The table as Parquet in Arrow's memory, written with the GIL released.

    Into an ``io.BytesIO`` every write of the growing file held the GIL while the
    buffer's fresh pages were faulted in (slow on a virtual machine: up to 0.5 s for a
    40-MB layer on the shared test machine), and the GUI thread could not run meanwhile."""
    sink = pa.BufferOutputStream()
    pq.write_table(pa.Table.from_pandas(df.reset_index(drop=True), preserve_index=False), sink)
    return sink.getvalue()


def _insert_blob(
    con: sqlite3.Connection, table: str, values: tuple, data: pa.Buffer, replace: bool = False
) -> None:
    """Insert the row ``values`` and ``data`` into ``table`` (its last column ``data``):
    the row with ``zeroblob`` of the blob's size, then ``data`` written into it.

    Bound as a parameter, SQLite copied the blob into fresh memory with the GIL held
    (0.2–0.9 s for a 40-MB layer on the shared test machine, the GUI thread stopped
    meanwhile); ``Blob.write`` copies with the GIL released."""
    verb = "INSERT OR REPLACE" if replace else "INSERT"
    marks = ", ".join("?" * len(values))
    cur = con.execute(f"{verb} INTO {table} VALUES ({marks}, zeroblob(?))", (*values, data.size))
    if data.size:
        with con.blobopen(table, "data", cur.lastrowid) as blob:
            blob.write(memoryview(data))


def _from_parquet(blob: bytes | pa.Buffer) -> pd.DataFrame:
    # One chunk per column, as a freshly imported table has: a row selection on a text
    # column of many chunks (the Parquet reader's batches) costs several times as much.
    # Read from an Arrow buffer (no copy): from an ``io.BytesIO`` each read of the
    # Parquet reader went through Python, with the GIL held.
    return pq.read_table(pa.BufferReader(pa.py_buffer(blob))).combine_chunks().to_pandas()


def _read_blob(con: sqlite3.Connection, table: str, rowid: int) -> pa.Buffer:
    """The ``data`` blob of row ``rowid`` of ``table``, read with the GIL released.

    Fetched as a column of a ``SELECT``, SQLite gathered a layer's blob from its pages
    into fresh memory, and Python copied it once more, with the GIL held (0.1–0.4 s for a
    40-MB layer on the shared test machine: the GUI thread stopped meanwhile during an
    Open project); ``Blob.read`` allocates the bytes and fills them in
    ``sqlite3_blob_read`` with the GIL released."""
    (kind,) = con.execute(f"SELECT typeof(data) FROM {table} WHERE rowid = ?", (rowid,)).fetchone()
    if kind != "blob":  # SQLite opens only blobs and text: NULL was "damaged" before too
        raise ValueError(f"{table} row {rowid}: the data is {kind}, not Parquet")
    with con.blobopen(table, "data", rowid, readonly=True) as blob:
        return pa.py_buffer(blob.read())


_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS sources (path TEXT PRIMARY KEY, sha256 TEXT);
CREATE TABLE IF NOT EXISTS params (name TEXT PRIMARY KEY, json TEXT);
CREATE TABLE IF NOT EXISTS layers (id TEXT PRIMARY KEY, pos INTEGER, name TEXT, kind TEXT,
    visible INTEGER, color TEXT, meta TEXT, lineage TEXT, data BLOB);
CREATE TABLE IF NOT EXISTS layer_tables (layer TEXT, name TEXT, data BLOB,
    PRIMARY KEY (layer, name));
CREATE TABLE IF NOT EXISTS state (key TEXT PRIMARY KEY, json TEXT);
CREATE TABLE IF NOT EXISTS decisions (seq INTEGER PRIMARY KEY AUTOINCREMENT, json TEXT);
"""


class ProjectStore:
    """An open project file; every method is one short transaction.

    Use it from one thread (SQLite connections are per thread): :class:`ProjectWriter`
    owns one on its own thread.
    """

    def __init__(self, path: str | Path, create: bool = True) -> None:
        """Open ``path`` (made when ``create``; otherwise a missing file is an
        :class:`InputError`: the project was moved or removed while open)."""
        self.path = Path(path)
        if not create and not self.path.exists():
            raise ProjectMoved(_moved(self.path))
        self.con = sqlite3.connect(self.path, timeout=10)
        self._ino = _inode(self.path)
        try:
            # A rollback journal: every commit is in the file itself (module docstring);
            # an older project left in WAL mode is checkpointed into it here.
            self.con.execute("PRAGMA journal_mode=DELETE")
            self.con.execute("PRAGMA synchronous=NORMAL")
            with self.con:
                self.con.executescript(_SCHEMA)
                self.con.executemany(
                    "INSERT OR REPLACE INTO meta VALUES (?, ?)",
                    [("schema", str(SCHEMA_VERSION)), ("wakeline", __version__)],
                )
                # A file with no decisions has none to repair: its own are checked.
                self.con.execute(
                    "INSERT OR IGNORE INTO meta SELECT ?, '0' "
                    "WHERE NOT EXISTS (SELECT 1 FROM decisions)",
                    (DECISIONS_CHECKED,),
                )
        except sqlite3.DatabaseError as exc:
            self.con.close()
            raise InputError(_sqlite_problem(self.path, exc, "opened for writing")) from None

    def close(self) -> None:
        self.con.close()

    def check_path(self) -> None:
        """Raise :class:`InputError` when the file at :attr:`path` is no longer the one
        open (renamed, moved or removed since): a write would go to a file nobody opens."""
        check_identity(self.path, self._ino)

    # -- writes --------------------------------------------------------------------

    def put_layer(self, layer: Layer, pos: int, with_data: bool = True) -> None:
        """Write a layer: its attributes always, its data (and side tables) when asked."""
        attrs = _attrs(layer)
        blobs = {name: _to_parquet(t) for name, t in layer.tables.items()} if with_data else {}
        data = _to_parquet(layer.points) if with_data else None
        with self.con:
            if with_data:
                _insert_blob(self.con, "layers", (layer.id, pos, *attrs), data, replace=True)
                self.con.execute("DELETE FROM layer_tables WHERE layer = ?", (layer.id,))
                for n, b in blobs.items():
                    _insert_blob(self.con, "layer_tables", (layer.id, n), b)
            else:
                self.con.execute(
                    "UPDATE layers SET pos=?, name=?, kind=?, visible=?, color=?, meta=?, "
                    "lineage=? WHERE id=?",
                    (pos, *attrs, layer.id),
                )

    def put_tables(self, layer: Layer, pos: int) -> None:
        """Write a layer's attributes and side tables, not its points (a layer under
        review keeping the points of an input layer removed:
        :func:`~wakeline.core.review_session.keep_inputs`)."""
        blobs = {name: _to_parquet(t) for name, t in layer.tables.items()}
        with self.con:  # one transaction: the tables and the meta that names them
            self.con.execute("DELETE FROM layer_tables WHERE layer = ?", (layer.id,))
            for n, b in blobs.items():
                _insert_blob(self.con, "layer_tables", (layer.id, n), b)
            self.con.execute(
                "UPDATE layers SET pos=?, name=?, kind=?, visible=?, color=?, meta=?, "
                "lineage=? WHERE id=?",
                (pos, *_attrs(layer), layer.id),
            )

    def delete_layer(self, layer_id: str) -> None:
        with self.con:
            self.con.execute("DELETE FROM layers WHERE id = ?", (layer_id,))
            self.con.execute("DELETE FROM layer_tables WHERE layer = ?", (layer_id,))

    def put_order(self, order: list[str]) -> None:
        with self.con:
            self.con.executemany(
                "UPDATE layers SET pos = ? WHERE id = ?", [(k, i) for k, i in enumerate(order)]
            )

    def put_sources(self, sources: list[Source]) -> None:
        with self.con:
            self.con.execute("DELETE FROM sources")
            self.con.executemany(
                "INSERT OR REPLACE INTO sources VALUES (?, ?)",
                [(s.path, s.sha256) for s in sources],
            )

    def put_params(self, params: dict[str, dict]) -> None:
        """The parameter table (the panel's form), with its version (``params_version``)."""
        with self.con:
            self.con.execute("DELETE FROM params")
            self.con.executemany(
                "INSERT INTO params VALUES (?, ?)",
                [(k, json.dumps(v, default=str)) for k, v in params.items()],
            )
            self.con.execute(
                "INSERT OR REPLACE INTO state VALUES (?, ?)",
                ("params_version", json.dumps(PARAMS_VERSION)),
            )

    def put_state(self, key: str, value: object) -> None:
        with self.con:
            self.con.execute(
                "INSERT OR REPLACE INTO state VALUES (?, ?)", (key, json.dumps(value, default=str))
            )

    def put_time_window(self, window: TimeWindow | None) -> None:
        """The ``time_window`` state row: :meth:`TimeWindow.to_json`, or null (none)."""
        self.put_state("time_window", window.to_json() if window is not None else None)

    def put_current_time(self, t: float | None) -> None:
        """The ``current_time`` state row: the slider's time ``{"t": …, "unit": "s"}``,
        or null (none)."""
        self.put_state("current_time", current_time_to_json(t))

    def put_map_view(self, view: MapView | None) -> None:
        """The ``view`` state row: :meth:`MapView.to_json`, or null (none)."""
        self.put_state("view", view.to_json() if view is not None else None)

    def add_decision(self, decision: dict) -> None:
        """Append a decision; the mark of checked decisions follows it when it covered
        every row before (a decision of today's review needs no repair)."""
        with self.con:
            self.con.execute("INSERT INTO decisions (json) VALUES (?)", (json.dumps(decision),))
            self.con.execute(
                "UPDATE meta SET value = CAST(CAST(value AS INTEGER) + 1 AS TEXT) "
                "WHERE key = ? AND CAST(value AS INTEGER) = "
                "(SELECT COUNT(*) FROM decisions) - 1",
                (DECISIONS_CHECKED,),
            )

    def mark_decisions_checked(self) -> None:
        """Record that every decision now in the file needs no repair (the migration on
        open ran, its repairs written): :func:`load_project` skips the migration while
        the file holds exactly these decisions (rows a Wakeline without the mark appends
        bring it back)."""
        with self.con:
            self.con.execute(
                "INSERT OR REPLACE INTO meta SELECT ?, CAST(COUNT(*) AS TEXT) FROM decisions",
                (DECISIONS_CHECKED,),
            )

    def put_all(self, session: Session, state: dict | None = None) -> None:
        """Everything in ``session`` (used by Save as, on a new file)."""
        for pos, layer in enumerate(session.layers.values()):
            self.put_layer(layer, pos)
        self.put_sources(session.sources)
        self.put_params(session.params)
        self.put_state("selection", session.selection)
        self.put_state("active", session.active)
        self.put_time_window(session.time_window)
        self.put_current_time(session.current_time)
        self.put_map_view(session.map_view)
        for key, value in (state or {}).items():
            self.put_state(key, value)
        for d in session.decisions:
            self.add_decision(d)
        self.mark_decisions_checked()  # a session's decisions were repaired when opened


def _attrs(layer: Layer) -> tuple:
    """A layer's row but its id, position and data: name, kind, visible, colour, meta
    and lineage (JSON)."""
    return (
        layer.name,
        layer.kind,
        int(layer.visible),
        layer.color,
        json.dumps(layer.meta, default=str),
        json.dumps(layer.lineage(), default=str),
    )


_inode = file_identity
_moved = moved_message


def save_project(
    session: Session | Project,
    path: str | Path,
    state: dict | None = None,
    lock_token: str | None = None,
) -> None:
    """Write a complete project to ``path`` atomically (Save as). Refused (InputError)
    when another window or process holds ``path`` (its lock file, see
    :mod:`wakeline.core.project_lock`), unless ``lock_token`` is that holder's."""
    holder = read_holder(path)
    if holder is not None and holder.token != lock_token and holder.alive() is not False:
        raise InputError(f"{path} is open in {holder.describe()}: save it under another name")
    if isinstance(session, Project):
        session = session.to_session()
    with atomic_path(path) as tmp:
        store = ProjectStore(tmp)
        try:
            store.put_all(session, state)
        finally:
            store.close()


# The blobs are never selected as columns: see _read_blob.


def _load_layers_v1(con: sqlite3.Connection) -> list[Layer]:
    rows = con.execute(
        "SELECT name, kind, visible, color, meta, rowid FROM layers ORDER BY pos"
    ).fetchall()
    return [
        Layer(
            f"L{k + 1}",
            name,
            kind,
            _from_parquet(_read_blob(con, "layers", rowid)),
            bool(vis),
            color,
            json.loads(meta),
        )
        for k, (name, kind, vis, color, meta, rowid) in enumerate(rows)
    ]


def _load_layers(con: sqlite3.Connection) -> list[Layer]:
    tables: dict[str, dict[str, pd.DataFrame]] = {}
    for lid, name, rowid in con.execute("SELECT layer, name, rowid FROM layer_tables").fetchall():
        tables.setdefault(lid, {})[name] = _from_parquet(_read_blob(con, "layer_tables", rowid))
    out = []
    rows = con.execute(
        "SELECT id, name, kind, visible, color, meta, lineage, rowid FROM layers ORDER BY pos"
    ).fetchall()
    for lid, name, kind, vis, color, meta, lineage, rowid in rows:
        blob = _read_blob(con, "layers", rowid)
        lin = json.loads(lineage or "{}")
        out.append(
            Layer(
                lid,
                name,
                kind,
                _from_parquet(blob),
                bool(vis),
                color,
                json.loads(meta or "{}"),
                lin.get("parent"),
                lin.get("step"),
                lin.get("role"),
                lin.get("params") or {},
                lin.get("created") or "",
                tables.get(lid, {}),
                list(lin.get("inputs") or []),
                str(lin.get("run") or ""),
                [int(i) for i in lin.get("restored") or []],
            )
        )
    return out


def load_project(path: str | Path) -> Project:
    """Read a whole project; one :class:`InputError` when it cannot be used (missing, not
    a project, damaged, made by a newer Wakeline). ``read_only`` says the file (or its
    folder) cannot be written."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such project file")
    writable = os.access(path, os.W_OK) and os.access(path.parent, os.W_OK)
    notes: list[str] = []
    try:
        try:
            con = _open_read_only(path)
        except sqlite3.OperationalError as exc:
            side = [s for s in ("-journal", "-wal") if _side_file(path, s)]
            if not side:
                raise
            hot = "-journal" in side
            _refuse_if_held(path, exc, hot)
            if writable:
                notes += _roll_back(path, hot)
                con = _open_read_only(path)
            else:
                # A read-only file or folder: SQLite cannot roll a hot journal back (or
                # open a project left in WAL mode, older Wakeline) there. The project
                # and its side files are copied and read there; the file is untouched.
                with tempfile.TemporaryDirectory(prefix="wakeline-ro-") as tmp:
                    copy = Path(tmp) / "p.wakeline"
                    for suffix in ("", *side):
                        shutil.copyfile(f"{path}{suffix}", f"{copy}{suffix}")
                    _replay(copy)  # a private copy: no lock to take
                    project = load_project(copy)
                project.read_only = True
                if hot:
                    project.warnings.insert(0, _left_mid_write(path, read_only=True))
                return project
        try:
            meta = dict(con.execute("SELECT key, value FROM meta").fetchall())
            schema = int(meta.get("schema", "0"))
            if schema > SCHEMA_VERSION:
                raise InputError(
                    f"{path}: made by a newer Wakeline ({meta.get('wakeline', '?')}, "
                    f"project schema {schema}); this is {__version__} (schema {SCHEMA_VERSION})"
                )
            if schema < 1:
                raise InputError(f"{path}: not a Wakeline project (no schema version)")
            sources = [Source(p, h) for p, h in con.execute("SELECT path, sha256 FROM sources")]
            params = {k: json.loads(v) for k, v in con.execute("SELECT name, json FROM params")}
            layers = _load_layers(con) if schema >= 2 else _load_layers_v1(con)
            decisions = [json.loads(r[0]) for r in con.execute("SELECT json FROM decisions")]
            if schema >= 2:
                rows = con.execute("SELECT key, json FROM state").fetchall()
                # the parameters' version says how to read them: a data row, not a view
                # state row (unreadable: the project is damaged, not read as version 1)
                versions = [json.loads(v) for k, v in rows if k == "params_version"]
                params_version = versions[0] if versions else 1  # none before version 2
                rows = [(k, v) for k, v in rows if k != "params_version"]
                ui = _read_state(rows, [lay.id for lay in layers])
            else:
                ui = _ViewState({}, [], None, None, None, [])
                params_version = 1
                names = {lay.name: lay.id for lay in layers}
                ui.selection = [
                    (names.get(lay, ""), s, b)
                    for lay, s, b in con.execute("SELECT layer, sensor, batch FROM selection")
                ]
        finally:
            con.close()
    except InputError:
        raise
    except sqlite3.DatabaseError as exc:
        raise InputError(_sqlite_problem(path, exc)) from None
    except (ValueError, TypeError, KeyError, OSError, pa.ArrowException) as exc:
        raise InputError(f"{path}: the project is damaged ({type(exc).__name__}: {exc})") from None
    if not isinstance(params, dict) or not all(isinstance(v, dict) for v in params.values()):
        raise InputError(f"{path}: the project is damaged (parameters are not a table)")
    if isinstance(params_version, bool) or not isinstance(params_version, int):
        raise InputError(f"{path}: the project is damaged (parameter version {params_version!r})")
    params = params_from_version(params, params_version)
    # Review decisions made before a join accepted the rows it put inside a target: once
    # per file (the mark says every decision there was checked or made since).
    checked = str(meta.get(DECISIONS_CHECKED, "")) == str(len(decisions))
    repairs = [] if checked else repair_decisions(layers, decisions)
    decisions += repairs
    return Project(
        sources,
        params,
        layers,
        ui.selection,
        decisions,
        ui.state,
        not writable,
        ui.time_window,
        ui.map_view,
        ui.active,
        [*notes, *ui.warnings],
        ui.current_time,
        repairs,
        checked,
    )


@dataclass
class _ViewState:
    """The state rows read: where the operator was (see :func:`_read_state`)."""

    state: dict[str, object]
    selection: list[tuple[str, str, str]]
    time_window: TimeWindow | None
    map_view: MapView | None
    active: str | None
    warnings: list[str]
    current_time: float | None = None


#: What each state row is, for the warning when it is left out.
_STATE_WHAT = {
    "selection": "selected tracks",
    "active": "active layer",
    "time_window": "time window",
    "current_time": "time slider's time",
    "view": "map view",
}


def _selection(value: object) -> list[tuple[str, str, str]]:
    """The ``selection`` row: a list of [layer id, sensor, batch] texts."""
    if value is None:
        return []
    if not isinstance(value, list) or not all(
        isinstance(r, list) and len(r) == 3 and all(isinstance(x, str) for x in r) for r in value
    ):
        raise ValueError(f"expected [layer, sensor, batch] rows, got {value!r:.120}")
    return [tuple(r) for r in value]


def _active(value: object, layer_ids: list[str]) -> str | None:
    """The ``active`` row: the id of one of the project's layers, or null."""
    if value is not None and value not in layer_ids:
        raise ValueError(f"no layer {value!r:.60} in the project")
    return value


def _read_state(rows: list[tuple[str, str]], layer_ids: list[str]) -> _ViewState:
    """The state rows (key, JSON) of a project whose layers are ``layer_ids``. A row that
    cannot be used (not JSON, not the value it should hold) only says where the operator
    was: it is left out with one warning, and the rest opens (a row missing — a project
    saved before it was kept — opens as before, without it)."""
    out = _ViewState({}, [], None, None, None, [])
    readers = {
        "selection": _selection,
        "active": lambda v: _active(v, layer_ids),
        "time_window": TimeWindow.from_json,
        "current_time": current_time_from_json,
        "view": MapView.from_json,
    }
    for key, raw in rows:
        what = _STATE_WHAT.get(key, f"state row {key!r}")
        try:
            value = json.loads(raw)
            if key in readers:
                value = readers[key](value)
        except (ValueError, TypeError) as exc:
            out.warnings.append(
                f"the saved {what} could not be used and is left out ({exc}); "
                "the project opened without it"
            )
            continue
        if key == "selection":
            out.selection = value
        elif key in ("active", "time_window", "current_time", "view"):
            setattr(out, {"view": "map_view"}.get(key, key), value)
        else:
            out.state[key] = value
    return out


def _side_file(path: Path, suffix: str) -> bool:
    """Whether SQLite's ``-journal`` (non-empty: an empty one holds nothing to roll
    back) or ``-wal`` file is beside ``path``."""
    try:
        size = os.path.getsize(f"{path}{suffix}")
    except OSError:
        return False
    return size > 0 or suffix == "-wal"


def _left_mid_write(path: Path, read_only: bool = False) -> str:
    """The note of a project whose last write was cut off (a crash or power loss left
    its ``-journal`` file): rolled back, it is as of its last complete write."""
    if read_only:
        return (
            f"the project was left in the middle of a write (a crash or power loss left "
            f"{path.name}-journal) and its file or folder is read-only, so the unfinished "
            "write cannot be rolled back in it: it opened read-only, read from a copy "
            "rolled back to its last complete write"
        )
    return (
        f"the project was left in the middle of a write (a crash or power loss left "
        f"{path.name}-journal): the unfinished write was rolled back; it opened as of its "
        "last complete write"
    )


def _refuse_if_held(path: Path, exc: sqlite3.Error, hot: bool) -> None:
    """Raise :class:`InputError` when a process that still runs (or one on another host,
    which cannot be checked) holds ``path``'s lock: the side file may be its write in
    progress, not a crash's; it is not touched."""
    holder = read_holder(path)
    if holder is None or holder.alive() is False:
        return
    what = "left in the middle of a write" if hot else "left in WAL mode"
    raise InputError(
        f"{path}: the project cannot be read now ({exc}): it was {what} and is open in "
        f"{holder.describe()}; close it there and open it again (if no Wakeline has it "
        f"open, remove {lock_path(path)})"
    )


def _replay(path: Path) -> None:
    """Open ``path`` read-write and read it: SQLite rolls back a hot journal beside it
    (or recovers its WAL) on the first read."""
    con = sqlite3.connect(path, timeout=10)
    try:
        con.execute("SELECT count(*) FROM sqlite_master").fetchone()
    finally:
        con.close()


def _roll_back(path: Path, hot: bool) -> list[str]:
    """Let SQLite roll back the hot journal beside ``path`` (or recover its WAL): one
    read-write connection reads the file, with the project's lock held meanwhile
    (:mod:`~wakeline.core.project_lock`), so no other window opens it half-way. Returns
    the notes for the operator; :class:`InputError` when it cannot be done."""
    locks = ProjectLocks()
    ok, note = locks.acquire(path)
    if not ok:
        raise InputError(
            f"{path}: the project was left in the middle of a write and is open in {note}; "
            "the unfinished write can be rolled back only where no other Wakeline has it open"
        )
    try:
        _replay(path)
    except sqlite3.DatabaseError as exc:
        side = f"{path.name}-journal" if hot else f"{path.name}-wal"
        raise InputError(
            f"{path}: the project was left in the middle of a write ({side} beside it) and "
            f"the unfinished write could not be rolled back ({exc})"
        ) from None
    finally:
        locks.release(path)
    return [_left_mid_write(path)] + ([note] if note else []) if hot else []


#: SQLite's primary result codes that say what is wrong with a file (the extended
#: code's low byte is the primary one).
_SQLITE_CORRUPT, _SQLITE_NOTADB = 11, 26
_SQLITE_ERROR, _SQLITE_BUSY, _SQLITE_LOCKED = 1, 5, 6


def _sqlite_problem(path: Path, exc: sqlite3.DatabaseError, doing: str = "read") -> str:
    """The operator's sentence for a project SQLite could not read: a file that is not
    one (garbage, empty, another database) is "not a Wakeline project"; a damaged one
    says so; anything else (disk, permissions, locks, a journal) is an I/O problem with
    a real project, never called "not a project"."""
    code = getattr(exc, "sqlite_errorcode", None)
    primary = code & 0xFF if isinstance(code, int) else None
    try:
        empty = os.path.getsize(path) == 0
    except OSError:
        empty = False
    if empty:
        return f"{path}: the file is empty (not a Wakeline project)"
    if primary == _SQLITE_NOTADB:
        return f"{path}: not a Wakeline project (not an SQLite database: {exc})"
    if primary == _SQLITE_ERROR and "no such table" in str(exc):
        return f"{path}: not a Wakeline project ({exc})"
    if primary in (_SQLITE_CORRUPT, _SQLITE_ERROR):
        return f"{path}: the project is damaged ({exc})"
    if primary in (_SQLITE_BUSY, _SQLITE_LOCKED):
        return f"{path}: the project is being written by another program ({exc}); try again"
    return f"{path}: the project file could not be {doing} ({exc})"


def _open_read_only(path: Path) -> sqlite3.Connection:
    """A read-only connection that has checked it can read (SQLite opens lazily)."""
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        con.execute("SELECT count(*) FROM sqlite_master").fetchone()
    except sqlite3.DatabaseError:
        con.close()
        raise
    return con


#: Seconds the interpreter's exit waits for each project writer to write its queue.
SHUTDOWN_WAIT_S = 60.0
_LOG = logging.getLogger("wakeline.project")
_WRITERS: "weakref.WeakSet[ProjectWriter]" = weakref.WeakSet()
_exit_hook = threading.Lock()
_exit_hooked = False


def _hook_exit() -> None:
    """Once: at the interpreter's exit, every project writer writes what is queued
    (:func:`_write_queues_at_exit`). Hooked with the threading module's exit calls, which
    run before ``concurrent.futures`` refuses new work (pyarrow's ``from_pandas`` uses a
    pool: a layer written later failed, "cannot schedule new futures after interpreter
    shutdown", h150) — and, run in reverse order of hooking, this one runs first: the
    pool's own is hooked by the import below."""
    global _exit_hooked
    with _exit_hook:
        if _exit_hooked:
            return
        import concurrent.futures.thread  # noqa: F401 - its exit call hooked before ours

        register = getattr(threading, "_register_atexit", None)
        try:
            if register is None:
                raise RuntimeError("no threading exit hook")
            register(_write_queues_at_exit)
        except RuntimeError:  # an older Python, or already shutting down
            import atexit

            atexit.register(_write_queues_at_exit)
        _exit_hooked = True


def _write_queues_at_exit() -> None:
    """The program ends (a script that never closed its window; the window's close
    writes its queue itself): each writer still running finishes its queue, waited for
    up to :data:`SHUTDOWN_WAIT_S`; one that does not is logged, not waited for."""
    writers = [w for w in list(_WRITERS) if w.busy()]
    for writer in writers:
        writer.finish()
    for writer in writers:
        if not writer.wait(SHUTDOWN_WAIT_S):
            _LOG.error(
                "%s: the program ended while writes were still queued (waited %.0f s); "
                "the last changes may be missing from the project",
                writer.path,
                SHUTDOWN_WAIT_S,
            )


class ProjectWriter:
    """Writes to a project file on a background thread, one task at a time, in order.

    ``submit(fn)`` queues ``fn(store)``; a failure is passed to ``on_error(exc)`` (called
    on the writer thread: a GUI must hand it to its own thread) and the writer goes on
    with the next task; an ``on_error`` that raises itself (its window gone) is logged,
    never raised in the thread. ``flush()`` waits until the queue is empty. When the
    program ends with tasks queued, they are written first (h155).
    """

    def __init__(
        self, path: str | Path, on_error: Callable[[Exception], None], create: bool = False
    ) -> None:
        """``create``: make ``path`` when it does not exist at the first write; otherwise
        (following an opened or saved project) a missing file fails every write with a
        message: the project was moved or removed while open."""
        self.path = Path(path)
        self.on_error = on_error
        self.create = create
        self._queue: queue.Queue = queue.Queue()
        self._thread = threading.Thread(target=self._run, name="wakeline-project", daemon=True)
        _hook_exit()
        _WRITERS.add(self)
        self._thread.start()

    def submit(self, task: Callable[[ProjectStore], None]) -> None:
        """Queue ``task(store)``."""
        self._queue.put((task, True))

    def submit_file(self, task: Callable[[Path], None]) -> None:
        """Queue ``task(path)`` with the file closed (e.g. writing it anew)."""
        self._queue.put((task, False))

    def flush(self, timeout: float | None = None) -> bool:
        """Wait until every task queued so far has run (True) or ``timeout`` s passed."""
        done = threading.Event()
        self._queue.put(done)
        return done.wait(timeout)

    def close(self, timeout: float | None = 30.0) -> None:
        """Finish every queued task, then stop; wait up to ``timeout`` s for that."""
        self.finish()
        self.wait(timeout)

    def finish(self) -> None:
        """Stop once every task queued so far has run, without waiting for it."""
        self._queue.put(None)

    def busy(self) -> bool:
        """Whether the writer thread still runs."""
        return self._thread.is_alive()

    def wait(self, timeout: float | None = None) -> bool:
        """Wait until the writer has stopped (after :meth:`finish`); True when it has."""
        self._thread.join(timeout)
        return not self._thread.is_alive()

    def _report(self, exc: Exception) -> None:
        try:
            self.on_error(exc)
        except Exception as err:  # noqa: BLE001 - the caller is gone: logged, not raised
            _LOG.error(
                "%s: a project write failed (%s); it could not be reported: %s", self.path, exc, err
            )

    def _run(self) -> None:
        store: ProjectStore | None = None
        while True:
            task = self._queue.get()
            if task is None:
                break
            if isinstance(task, threading.Event):
                task.set()
                continue
            fn, needs_store = task
            try:
                if not needs_store:
                    if store is not None:
                        store.close()
                        store = None
                    fn(self.path)
                    continue
                if store is None:
                    store = ProjectStore(self.path, create=self.create)
                store.check_path()
                fn(store)
            except Exception as exc:  # noqa: BLE001 - reported to the caller, never lost
                if store is not None:
                    # Renamed between the check and the write: SQLite's own words
                    # ("attempt to write a readonly database") would hide what happened.
                    if isinstance(exc, sqlite3.Error) and _inode(self.path) != store._ino:
                        exc = ProjectMoved(_moved(self.path))
                    store.close()
                    store = None
                self._report(exc)
        if store is not None:
            store.close()

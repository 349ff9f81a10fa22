"""The review's proposals and decisions in the project file (SQLite).

Two tables beside the project's own (``review_proposals``, ``review_decisions``); every
decision is one row written in its own transaction the moment it is made, so killing
the application loses at most the decision in flight. Reopening replays the stored
changes in order (undo and redo are stored as the changes they are), which restores the
statuses, the manual links and the decision log exactly.
"""

import dataclasses
import json
import sqlite3
from pathlib import Path

import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.file_identity import check_identity, file_identity
from wakeline.core.review import (
    PROPOSAL_COLUMNS,
    REDO,
    RERUN,
    Change,
    LogEntry,
    ReviewState,
    cuts_anything,
    pair_key,
    replay_repaired,
)

#: The ``review_meta`` row counting the decisions known to need no repair (see
#: :meth:`ReviewStore.load`): the decision count when they all are.
CHECKED = "decisions_checked"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS review_proposals (
    seq INTEGER PRIMARY KEY,
    proposal TEXT UNIQUE NOT NULL,
    row_json TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS review_tracks (
    track TEXT PRIMARY KEY,
    sensor TEXT NOT NULL,
    batch TEXT NOT NULL,
    t0 REAL,
    t1 REAL
);
CREATE TABLE IF NOT EXISTS review_decisions (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    time TEXT NOT NULL,
    action TEXT NOT NULL,
    proposal TEXT NOT NULL,
    tracks TEXT NOT NULL,
    before TEXT NOT NULL,
    after TEXT NOT NULL,
    change_json TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS review_meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
"""


class ReviewStore:
    """An open review store in the SQLite file at ``path`` (created when absent)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            self._db = sqlite3.connect(self.path, isolation_level=None)
            self._db.execute("PRAGMA journal_mode=DELETE")  # every commit in the file itself
            self._db.execute("PRAGMA synchronous=FULL")
            self._db.executescript(_SCHEMA)
            self._ino = file_identity(self.path)  # a write once it was moved is refused
            # A store with no decisions has none to repair: its own are checked.
            if self._db.execute("SELECT 1 FROM review_decisions LIMIT 1").fetchone() is None:
                self._db.execute("INSERT OR IGNORE INTO review_meta VALUES (?, '0')", (CHECKED,))
        except sqlite3.DatabaseError as exc:
            raise InputError(f"{self.path}: not a usable project file ({exc})") from None

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> "ReviewStore":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def save_queue(self, state: ReviewState, params: dict | None = None) -> None:
        """Replace the stored tracks and proposals (a new run) and clear the decisions, in
        one transaction; ``params`` (JSON-ready) records what produced the proposals."""
        rows = state.proposals[list(PROPOSAL_COLUMNS)]
        recs = json.loads(rows.to_json(orient="records"))
        tr = state.tracks
        with self._tx():
            self._db.execute("DELETE FROM review_proposals")
            self._db.execute("DELETE FROM review_tracks")
            self._db.execute("DELETE FROM review_decisions")
            self._db.executemany(
                "INSERT INTO review_proposals (seq, proposal, row_json) VALUES (?, ?, ?)",
                [(k, r["proposal"], json.dumps(r)) for k, r in enumerate(recs)],
            )
            self._db.executemany(
                "INSERT INTO review_tracks VALUES (?, ?, ?, ?, ?)",
                zip(
                    tr["track"].tolist(),
                    tr["sensor"].astype(str).tolist(),
                    tr["batch"].astype(str).tolist(),
                    tr["t0"].astype(float).tolist(),
                    tr["t1"].astype(float).tolist(),
                    strict=True,
                ),
            )
            self._db.execute(
                "INSERT OR REPLACE INTO review_meta VALUES ('params', ?)",
                (json.dumps(params or {}),),
            )
            self._db.execute("INSERT OR REPLACE INTO review_meta VALUES (?, '0')", (CHECKED,))

    def record(self, change: Change, entry: LogEntry) -> None:
        """Append one decision (the change applied and its log line), committed at once."""
        with self._tx():
            self._db.execute(
                "INSERT INTO review_decisions (time, action, proposal, tracks, before, after, "
                "change_json) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (
                    entry.time,
                    entry.action,
                    entry.proposal,
                    entry.tracks,
                    entry.before,
                    entry.after,
                    json.dumps(change.to_dict()),
                ),
            )
            self._db.execute(  # today's decisions need no repair (see load)
                "UPDATE review_meta SET value = CAST(CAST(value AS INTEGER) + 1 AS TEXT) "
                "WHERE key = ? AND CAST(value AS INTEGER) = "
                "(SELECT COUNT(*) FROM review_decisions) - 1",
                (CHECKED,),
            )

    def apply(self, state: ReviewState, change: Change, how: str = "do") -> Change:
        """Apply ``change`` to ``state`` and record it: the usual way to decide. ``how``
        (do, undo, redo: the window's ``stack`` mark) is not kept in this store; a redo
        is logged ``redo <action>`` (its log line, which the store keeps)."""
        state.apply(change, how=how)
        self.record(change, state.log[-1])
        return change

    def load(self) -> ReviewState:
        """The stored queue with every stored decision replayed (log times kept).

        The migration a project file gets on open
        (:func:`~wakeline.core.review_session.repair_decisions`) happens here too, once
        per store: decisions of an older Wakeline that left a row rejected or split
        beside a target holding both its tracks get one ``repair`` decision each
        (:func:`~wakeline.core.review.replay_repaired`), applied, logged and written at
        once; then the store marks its decisions checked, and later loads only replay."""
        tracks = pd.read_sql_query(
            "SELECT track, sensor, batch, t0, t1 FROM review_tracks ORDER BY track", self._db
        )
        rows = [
            json.loads(r[0])
            for r in self._db.execute("SELECT row_json FROM review_proposals ORDER BY seq")
        ]
        props = pd.DataFrame(rows, columns=list(PROPOSAL_COLUMNS))
        state = ReviewState(tracks, props)
        changes = [
            (Change.from_dict(json.loads(text)), when, action)
            for when, text, action in self._db.execute(
                "SELECT time, change_json, action FROM review_decisions ORDER BY seq"
            )
        ]
        row = self._db.execute("SELECT value FROM review_meta WHERE key = ?", (CHECKED,))
        mark = row.fetchone()
        if (mark[0] if mark else None) == str(len(changes)) or not cuts_anything(
            c for c, _, _ in changes
        ):
            for change, when, action in changes:
                redo = str(action or "").startswith(REDO)
                state.apply(change, when=when, how="redo" if redo else "do")
        else:
            repairs = replay_repaired(state, [(c, when) for c, when, _ in changes])
            entries = state.log[len(state.log) - len(repairs) :]
            for change, entry in zip(repairs, entries, strict=True):
                self.record(change, entry)
        if (mark[0] if mark else None) != str(len(state.log)):
            with self._tx():
                self._db.execute(
                    "INSERT OR REPLACE INTO review_meta SELECT ?, CAST(COUNT(*) AS TEXT) "
                    "FROM review_decisions",
                    (CHECKED,),
                )
        return state

    def params(self) -> dict:
        row = self._db.execute("SELECT value FROM review_meta WHERE key = 'params'").fetchone()
        return json.loads(row[0]) if row else {}

    def decision_count(self) -> int:
        return int(self._db.execute("SELECT COUNT(*) FROM review_decisions").fetchone()[0])

    def _tx(self):
        # As the project's own connection (ProjectStore.check_path): a file renamed,
        # moved or removed while open is not written (SQLite would say "readonly").
        check_identity(self.path, self._ino)
        return _Transaction(self._db)


REVIEW_TABLES = ("review_tracks", "review_proposals", "review_decisions", "review_meta")


def copy_review(src: str | Path, dst: str | Path) -> int:
    """Copy the review tables of the project file ``src`` into ``dst`` (replacing any
    there), in one transaction; returns the decisions copied. For a project save that
    writes a new file and renames it over the old one: call it on the new file before
    the rename, so the decisions survive the save."""
    if not Path(src).exists():
        return 0
    ReviewStore(dst).close()  # make the tables
    db = sqlite3.connect(dst, isolation_level=None)
    try:
        db.execute("ATTACH DATABASE ? AS src", (str(src),))
        have = {r[0] for r in db.execute("SELECT name FROM src.sqlite_master WHERE type='table'")}
        if "review_decisions" not in have:
            return 0
        db.execute("BEGIN IMMEDIATE")
        for t in REVIEW_TABLES:
            db.execute(f"DELETE FROM main.{t}")  # noqa: S608 - fixed table names
            if t in have:
                db.execute(f"INSERT INTO main.{t} SELECT * FROM src.{t}")  # noqa: S608
        db.execute("COMMIT")
        return int(db.execute("SELECT COUNT(*) FROM main.review_decisions").fetchone()[0])
    finally:
        db.close()


#: A decision row's ``stack`` mark (:func:`decision_row`): how the change came — a new
#: decision pushed on the undo stack, an Undo, a Redo — or carried over by a re-run (off
#: the stack). Rows written before h196 have none (:func:`undo_history` infers it).
STACK_MARKS = ("do", "undo", "redo", "carried")


def decision_row(queue: str, change: Change, entry: LogEntry, stack: str | None = None) -> dict:
    """One decision as the project's ``decisions`` table stores it (JSON): the queue it
    belongs to (:func:`wakeline.core.review_session.queue_key`), the change applied and
    its log line, and (``stack``, one of :data:`STACK_MARKS`) how it came, from which a
    reopen rebuilds the undo stack (:func:`undo_history`). The window writes each one
    through the project's writer at once."""
    row = {
        "queue": queue,
        "time": entry.time,
        "action": entry.action,
        "proposal": entry.proposal,
        "tracks": entry.tracks,
        "before": entry.before,
        "after": entry.after,
        "change": change.to_dict(),
    }
    if stack is not None:
        row["stack"] = stack
    return row


def undo_history(rows: list[dict], queue: str) -> tuple[list[Change], int]:
    """The undo stack the session that wrote ``queue``'s decision rows left: its
    commands (the changes, oldest first) and its index (how many are done; those above
    it are the Redo history) — what a reopen pushes again so that Undo undoes the last
    decision made before the close and Redo redoes what was undone.

    The rows are replayed as stack moves: an Undo row (the inverse of the command below
    the index) moves the index down, a Redo row (the command at the index) moves it up,
    a new decision drops the Redo history and is pushed. A re-run's marker
    (:data:`~wakeline.core.review.RERUN`), the decisions it carried over and a
    ``repair`` (the migration on open) are barriers: the stack is emptied there (the
    session that wrote them had nothing to undo across them: a step run is not undone,
    a repair is made at open). A row marked ``undo``/``redo`` that does not match the
    stack (a log edited by hand) is a barrier too, so an Undo never meets a change that
    no longer applies. Rows written before the marks (:data:`STACK_MARKS`) are read by
    their change alone: an ``undo …`` row that inverts the command below the index is an
    Undo, a row equal to the command at the index a Redo (a new decision equal to it has
    the same effect, keeping the Redo history above it), any other a new decision. Pure
    and fast (no state is touched: the rows were replayed by :func:`replay_decisions`)."""
    stack: list[Change] = []
    index = 0
    for row in rows:
        if not (isinstance(row, dict) and row.get("queue") == queue and "change" in row):
            continue
        change = Change.from_dict(row["change"])
        mark = row.get("stack")
        if change.action in (RERUN, "repair") or mark == "carried":
            stack, index = [], 0
            continue
        undo = index > 0 and change == stack[index - 1].inverse()
        redo = index < len(stack) and change == stack[index]
        if mark == "undo" or (mark is None and undo and change.action.startswith("undo ")):
            if undo:
                index -= 1
            else:
                stack, index = [], 0
        elif mark == "redo" or (mark is None and redo):
            if redo:
                index += 1
            else:
                stack, index = [], 0
        else:
            del stack[index:]
            stack.append(change)
            index += 1
    return stack, index


def entry_of_row(row: dict) -> LogEntry:
    """The log line a stored decision row (:func:`decision_row`) was written with."""
    return LogEntry(*(str(row.get(f.name, "") or "") for f in dataclasses.fields(LogEntry)))


def replay_decisions(state: ReviewState, rows: list[dict], queue: str) -> int:
    """Apply, in order, the stored decisions of ``queue`` (rows of :func:`decision_row`);
    returns how many. Rows of other queues (other layers, older runs) are skipped. A
    re-run's marker (:data:`~wakeline.core.review.RERUN`, an empty change) logs the
    text it was stored with."""
    n = 0
    for row in rows:
        if isinstance(row, dict) and row.get("queue") == queue and "change" in row:
            change = Change.from_dict(row["change"])
            how = "redo" if row.get("stack") == "redo" else "do"  # logged as it was made
            state.apply(change, when=row.get("time"), how=how)
            if change.action == RERUN:
                e = state.log[-1]
                state.log[-1] = dataclasses.replace(
                    e, before=str(row.get("before", "")), after=str(row.get("after", ""))
                )
            n += 1
    return n


def earlier_entries(rows: list[dict], queue: str) -> list[LogEntry]:
    """The log lines of the earlier runs of ``queue``'s layer (its other queues, in the
    order they were made): what the decision log of a re-run begins with, never
    replayed on its proposals."""
    lid, _, _ = queue.partition("@")
    prefix = f"{lid}@"
    out = []
    for row in rows:
        if not isinstance(row, dict):
            continue
        q = str(row.get("queue", ""))
        if q != queue and q.startswith(prefix):
            out.append(entry_of_row(row))
    return out


def queue_outcome(rows: list[dict], queue: str) -> tuple[dict[str, str], set[tuple[str, str]]]:
    """The last status of each proposal of ``queue`` that a decision set, and the manual
    links left, from its stored rows in order (undos taken as the changes they are; no
    points needed: what a re-run reads of the run it replaces)."""
    status: dict[str, str] = {}
    links: set[tuple[str, str]] = set()
    for row in rows:
        if not (isinstance(row, dict) and row.get("queue") == queue):
            continue
        change = row.get("change")
        if not isinstance(change, dict):
            continue
        status.update({str(k): str(v) for k, v in (change.get("status_after") or {}).items()})
        for lk in change.get("links_removed") or []:
            links.discard(pair_key(str(lk[0]), str(lk[1])))
        for lk in change.get("links_added") or []:
            links.add(pair_key(str(lk[0]), str(lk[1])))
    return status, links


def proposal_pairs(proposals) -> dict[str, tuple[str, str]]:
    """Each proposal's pair of track labels (``sensor:batch``), by proposal id; empty
    when the table is missing or lacks a column."""
    need = ("proposal", "sensor_a", "batch_a", "sensor_b", "batch_b")
    if proposals is None or not len(proposals) or not set(need) <= set(proposals.columns):
        return {}
    p = proposals
    a = p["sensor_a"].astype(str) + ":" + p["batch_a"].astype(str)
    b = p["sensor_b"].astype(str) + ":" + p["batch_b"].astype(str)
    return dict(zip(p["proposal"].astype(str), zip(a, b, strict=True), strict=True))


def kept_out_pairs(
    rows: list[dict], queues: list[tuple[str, str, object]]
) -> tuple[set[tuple[str, str]], set[tuple[str, str]]]:
    """The pairs of track labels (order-free) a re-run keeps out, read in one pass over
    the decision log ``rows``: ``(rejected, split)``. ``queues``: one ``(layer id, queue
    key, proposals)`` per layer. Rejected: the pairs left rejected in any queue of the
    layer (every run of its step, ``layer_id@…``, decisions and undos taken in order; a
    rejected pair is never proposed again). Split: the pairs whose proposal was left split
    in the layer's current ``queue`` — a split says "these are different" as a reject
    does; it names its track, not the pair, so the pairs come from the queue's own
    ``proposals`` (``sensor_a``, ``batch_a``, ``sensor_b``, ``batch_b``)."""
    rejected: dict[str, dict[tuple[str, str], str]] = {lid: {} for lid, _, _ in queues}
    split: dict[str, list[tuple[dict, dict]]] = {}
    for _, queue, proposals in queues:
        pairs = proposal_pairs(proposals)
        if pairs:
            split.setdefault(queue, []).append((pairs, {}))
    for row in rows:
        if not isinstance(row, dict):
            continue
        change = row.get("change")
        if not isinstance(change, dict):
            continue
        after = change.get("status_after") or {}
        tracks = change.get("tracks") or []
        queue = str(row.get("queue", ""))
        at = queue.find("@")
        while at >= 0:  # every layer whose id, then '@', begins the queue key
            status = rejected.get(queue[:at])
            if status is not None:
                pid = change.get("proposal")
                if pid and len(tracks) == 2 and pid in after:
                    status[pair_key(str(tracks[0]), str(tracks[1]))] = str(after[pid])
            at = queue.find("@", at + 1)
        raw = row.get("queue")
        for pairs, status in split.get(raw, ()) if isinstance(raw, str) else ():
            named = {str(t) for t in tracks}
            for pid, value in after.items():
                # a pair the change touches (a run made in the same second shares the key)
                if pid in pairs and (not named or named & set(pairs[pid])):
                    status[pair_key(*pairs[pid])] = str(value)
    out_rejected = {k for st in rejected.values() for k, v in st.items() if v == "rejected"}
    out_split = {
        k for entries in split.values() for _, st in entries for k, v in st.items() if v == "split"
    }
    return out_rejected, out_split


def rejected_pairs(rows: list[dict], layer_id: str) -> set[tuple[str, str]]:
    """The pairs of track labels the operator left rejected in any queue of layer
    ``layer_id`` (:func:`kept_out_pairs`)."""
    return kept_out_pairs(rows, [(layer_id, "", None)])[0]


def split_pairs(rows: list[dict], queue: str, proposals) -> set[tuple[str, str]]:
    """The pairs of track labels whose proposal the operator left split in ``queue``
    (:func:`kept_out_pairs`)."""
    return kept_out_pairs(rows, [("", queue, proposals)])[1]


class _Transaction:
    """BEGIN IMMEDIATE … COMMIT (ROLLBACK on error) on an autocommit connection."""

    def __init__(self, db: sqlite3.Connection) -> None:
        self.db = db

    def __enter__(self) -> None:
        self.db.execute("BEGIN IMMEDIATE")

    def __exit__(self, exc_type, *rest) -> None:
        self.db.execute("ROLLBACK" if exc_type else "COMMIT")

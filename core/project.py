"""The project file (``.wakeline``): one SQLite database holding the sources (path and
content hash), the parameters, the result layers and the selection.

Layers are stored as Parquet blobs, so times, text and numbers come back exactly. Saving
writes a new database beside the target and renames it over, so a crash never leaves a
half-written project. Opening checks every source: a missing or changed file is reported,
never fatal — the stored layers are still there.
"""

import hashlib
import io
import json
import sqlite3
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from wakeline.core import __version__
from wakeline.core.errors import InputError
from wakeline.core.io.writer import atomic_path

SCHEMA_VERSION = 1


def file_hash(path: str | Path) -> str:
    """SHA-256 of a file's content, hex."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


@dataclass
class Source:
    path: str
    sha256: str


@dataclass
class Layer:
    """A named table of points shown on the map (input data or a result)."""

    name: str
    kind: str  # "source", "cleaned", "maneuvers", "compressed", "associated", "fused", ...
    points: pd.DataFrame
    visible: bool = True
    color: str = "#1f77b4"
    meta: dict = field(default_factory=dict)


@dataclass
class Project:
    sources: list[Source] = field(default_factory=list)
    params: dict[str, dict] = field(default_factory=dict)
    layers: list[Layer] = field(default_factory=list)
    selection: list[tuple[str, str, str]] = field(default_factory=list)  # layer, sensor, batch
    decisions: list[dict] = field(default_factory=list)

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


def _to_parquet(df: pd.DataFrame) -> bytes:
    buf = io.BytesIO()
    pq.write_table(pa.Table.from_pandas(df.reset_index(drop=True), preserve_index=False), buf)
    return buf.getvalue()


def _from_parquet(blob: bytes) -> pd.DataFrame:
    return pq.read_table(io.BytesIO(blob)).to_pandas()


def save_project(project: Project, path: str | Path) -> None:
    """Write the whole project to ``path`` atomically."""
    with atomic_path(path) as tmp:
        con = sqlite3.connect(tmp)
        try:
            con.executescript(
                """
                CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT);
                CREATE TABLE sources (path TEXT, sha256 TEXT);
                CREATE TABLE params (name TEXT PRIMARY KEY, json TEXT);
                CREATE TABLE layers (pos INTEGER, name TEXT, kind TEXT, visible INTEGER,
                                     color TEXT, meta TEXT, data BLOB);
                CREATE TABLE selection (layer TEXT, sensor TEXT, batch TEXT);
                CREATE TABLE decisions (json TEXT);
                """
            )
            con.executemany(
                "INSERT INTO meta VALUES (?, ?)",
                [("schema", str(SCHEMA_VERSION)), ("wakeline", __version__)],
            )
            con.executemany(
                "INSERT INTO sources VALUES (?, ?)", [(s.path, s.sha256) for s in project.sources]
            )
            con.executemany(
                "INSERT INTO params VALUES (?, ?)",
                [(k, json.dumps(v)) for k, v in project.params.items()],
            )
            con.executemany(
                "INSERT INTO layers VALUES (?, ?, ?, ?, ?, ?, ?)",
                [
                    (
                        k,
                        lay.name,
                        lay.kind,
                        int(lay.visible),
                        lay.color,
                        json.dumps(lay.meta, default=str),
                        _to_parquet(lay.points),
                    )
                    for k, lay in enumerate(project.layers)
                ],
            )
            con.executemany("INSERT INTO selection VALUES (?, ?, ?)", project.selection)
            con.executemany(
                "INSERT INTO decisions VALUES (?)", [(json.dumps(d),) for d in project.decisions]
            )
            con.commit()
        finally:
            con.close()


def load_project(path: str | Path) -> Project:
    """Read a project; :class:`InputError` when the file is not a Wakeline project."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such project file")
    try:
        con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            meta = dict(con.execute("SELECT key, value FROM meta").fetchall())
            if int(meta.get("schema", "0")) > SCHEMA_VERSION:
                raise InputError(f"{path}: made by a newer Wakeline (schema {meta['schema']})")
            sources = [Source(p, h) for p, h in con.execute("SELECT path, sha256 FROM sources")]
            params = {k: json.loads(v) for k, v in con.execute("SELECT name, json FROM params")}
            layers = [
                Layer(name, kind, _from_parquet(blob), bool(vis), color, json.loads(meta_json))
                for name, kind, vis, color, meta_json, blob in con.execute(
                    "SELECT name, kind, visible, color, meta, data FROM layers ORDER BY pos"
                )
            ]
            selection = [
                tuple(r) for r in con.execute("SELECT layer, sensor, batch FROM selection")
            ]
            decisions = [json.loads(r[0]) for r in con.execute("SELECT json FROM decisions")]
        finally:
            con.close()
    except sqlite3.DatabaseError as exc:
        raise InputError(f"{path}: not a Wakeline project ({exc})") from None
    return Project(sources, params, layers, selection, decisions)

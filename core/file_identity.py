"""Which file a path names: a file opened for writing is followed by its identity
(device, inode), so a write after the file was moved, renamed or removed is refused with
a sentence instead of SQLite's "attempt to write a readonly database"."""

import os
from pathlib import Path

from wakeline.core.errors import ProjectMoved


def file_identity(path: str | Path) -> tuple[int, int] | None:
    """(device, inode) of ``path``, or None when there is no file there."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino


def moved_message(path: str | Path) -> str:
    """The sentence for a write to a project file moved, renamed or removed while open."""
    return (
        f"{path}: the project file was moved, renamed or removed while open (or never "
        "written: a failed Save as); this change is not saved: use Save as to write the "
        "work to a file"
    )


def check_identity(path: str | Path, identity: tuple[int, int] | None) -> None:
    """Raise :class:`ProjectMoved` when ``path`` no longer names the file ``identity``."""
    if file_identity(path) != identity:
        raise ProjectMoved(moved_message(path))

"""What a read of a file's first rows says, before the whole file is read: the import
dialog shows it while it is open (operator test 9, D11: the time zone, the ambiguous
CST, the decimal commas were said in the log after OK, with the dialog closed).

The first :data:`PREVIEW_LINES` lines are read by :func:`~wakeline.core.io.read_points`
with the dialog's options, as the whole file will be: its warnings and the reasons of
the rows it would quarantine. The counts are of those rows, not of the file.
"""

import bz2
import gzip
import lzma
import shutil
import tempfile
from pathlib import Path

from wakeline.core.errors import InputError

#: Lines read for the preview (a header, a title above it, the first data rows).
PREVIEW_LINES = 400

_OPENERS = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}


def _first_lines(path: Path, lines: int, out: Path) -> bool:
    """Copy the first ``lines`` lines of ``path`` (bytes as they are: the encoding kept;
    a .gz/.bz2/.xz file decompressed) to ``out``; False for a file this cannot cut (a
    .zip, .zst)."""
    suffix = path.suffix.lower()
    if suffix in (".zip", ".zst"):
        return False
    opener = _OPENERS.get(suffix, open)
    with opener(path, "rb") as src, open(out, "wb") as dst:
        for k, line in enumerate(src):
            if k >= lines:
                break
            dst.write(line)
    return True


def preview_read(path: str | Path, lines: int = PREVIEW_LINES, **options) -> dict | None:
    """Read the first ``lines`` lines of ``path`` as ``read_points(path, **options)``
    reads the file. Returns ``rows_read``, ``rows_imported``, ``warnings`` (the import's,
    the file named as itself) and ``quarantine_reasons`` (reason → rows), or None when
    the file cannot be cut (compressed as .zip/.zst) or read at all (the dialog says that
    otherwise)."""
    from wakeline.core.io import read_points

    path = Path(path)
    tmp = Path(tempfile.mkdtemp(prefix="wakeline-preview-"))
    try:
        part = tmp / path.with_suffix("").name if path.suffix.lower() in _OPENERS else None
        part = part or tmp / path.name
        if part.suffix == "":
            part = part.with_suffix(".csv")
        if not _first_lines(path, lines, part):
            return None
        try:
            result = read_points(part, **options)
        except (InputError, OSError, ValueError):
            return None
        rep = result.report

        def named(text: str) -> str:
            return str(text).replace(str(part), path.name).replace(part.name, path.name)

        return {
            "rows_read": int(rep.get("rows_read", 0) or 0),
            "rows_imported": int(rep.get("rows_imported", len(result.points)) or 0),
            "warnings": [named(w) for w in rep.get("warnings", [])],
            "quarantine_reasons": {
                named(k): int(v) for k, v in (rep.get("quarantine_reasons") or {}).items()
            },
        }
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

"""Look at the first bytes of a file: compression, binary or text, encoding, delimiter, header."""

import gzip
import re
import zlib
from dataclasses import dataclass
from pathlib import Path

from wakeline.core.errors import InputError

SAMPLE_BYTES = 256 * 1024
ENCODINGS = ("utf-8", "gb18030")
DELIMITERS = (",", ";", "\t")
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


@dataclass(frozen=True)
class Sniff:
    """What the start of a file says about how to read it."""

    path: Path
    compression: str | None  # "gzip" or None
    encoding: str  # a Python codec name: "utf-8" (BOM allowed) or "gb18030"
    delimiter: str  # ",", ";", "\t" or " " (runs of spaces are not merged)
    has_header: bool
    skip_rows: int  # physical lines before the first data row (blank lines and the header)
    columns: tuple[str, ...]  # header names, or col1..colN when the file has no header
    preview: tuple[tuple[str, ...], ...]  # first data rows split on the delimiter (for dialogs)


def _read_sample(path: Path) -> tuple[bytes, str | None]:
    try:
        with open(path, "rb") as fh:
            head = fh.read(SAMPLE_BYTES)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, not a file") from None
    except PermissionError:
        raise InputError(f"{path}: permission denied") from None
    if head[:2] == b"\x1f\x8b":
        try:
            with gzip.open(path, "rb") as fh:
                return fh.read(SAMPLE_BYTES), "gzip"
        except (OSError, EOFError, zlib.error) as exc:
            raise InputError(
                f"{path}: looks gzip-compressed but cannot be decompressed ({exc})"
            ) from None
    return head, None


def _looks_binary(sample: bytes) -> bool:
    if b"\x00" in sample:
        return True
    control = sum(sample.count(bytes([b])) for b in (*range(0, 9), *range(14, 32)))
    return control > 0.01 * max(len(sample), 1)


def _decode(sample: bytes, path: Path, encoding: str | None) -> tuple[str, str]:
    # The sample may end inside a multi-byte character: cut at the last newline.
    cut = sample.rfind(b"\n")
    body = sample if cut < 0 or len(sample) < SAMPLE_BYTES else sample[: cut + 1]
    candidates = (encoding,) if encoding else ENCODINGS
    for enc in candidates:
        try:
            text = body.decode(enc)
        except (UnicodeDecodeError, LookupError):
            continue
        return text.removeprefix("\ufeff"), enc
    tried = " or ".join(candidates)
    raise InputError(f"{path}: cannot decode the text as {tried}; choose the file's encoding")


def _pick_delimiter(lines: list[str]) -> str:
    header, rest = lines[0], lines[1:6]
    best, best_score = ",", -1
    for delim in DELIMITERS:
        n = header.count(delim)
        if n == 0:
            continue
        consistent = sum(1 for line in rest if line.count(delim) == n)
        score = n + 100 * consistent
        if score > best_score:
            best, best_score = delim, score
    if best_score < 0 and len(header.split(" ")) > 1:
        return " "
    return best


def _unique_names(names: list[str]) -> tuple[str, ...]:
    """Header names made usable: blanks become colN, repeats get a .1, .2 suffix."""
    seen: dict[str, int] = {}
    out = []
    for i, name in enumerate(names):
        name = name or f"col{i + 1}"
        if name in seen:
            seen[name] += 1
            name = f"{name}.{seen[name]}"
        else:
            seen[name] = 0
        out.append(name)
    return tuple(out)


def sniff(path: str | Path, encoding: str | None = None, delimiter: str | None = None) -> Sniff:
    """Inspect a CSV file. Raises :class:`InputError` for empty, binary or undecodable files."""
    path = Path(path)
    sample, compression = _read_sample(path)
    if not sample.strip():
        raise InputError(f"{path}: the file is empty")
    if _looks_binary(sample):
        raise InputError(f"{path}: this is a binary file, not a CSV text file")
    text, enc = _decode(sample, path, encoding)
    physical = text.split("\n")
    leading_blank = next((i for i, line in enumerate(physical) if line.strip()), len(physical))
    lines = [line.rstrip("\r") for line in physical if line.strip()]
    if not lines:
        raise InputError(f"{path}: the file is empty")
    delim = delimiter or _pick_delimiter(lines)
    first = [f.strip().strip('"') for f in lines[0].split(delim)]
    has_header = any(f and not _NUMBER.match(f) for f in first)
    if has_header:
        columns = _unique_names(first)
        data_lines = lines[1:6]
    else:
        columns = tuple(f"col{i + 1}" for i in range(len(first)))
        data_lines = lines[:5]
    preview = tuple(tuple(f.strip('"') for f in line.split(delim)) for line in data_lines)
    skip_rows = leading_blank + (1 if has_header else 0)
    return Sniff(path, compression, enc, delim, has_header, skip_rows, columns, preview)


def read_small_table(
    path: str | Path, required: tuple[str, ...], what: str, text_columns: tuple[str, ...] = ()
):
    """A small CSV of another layout (bearings, association tables), read with the same
    detection of encoding, delimiter and compression as track files. Raises
    :class:`InputError` naming the missing columns and listing the headers found."""
    import pandas as pd

    sn = sniff(path)
    missing = [c for c in required if c not in sn.columns]
    if missing:
        raise InputError(
            f"{path}: missing required column {', '.join(missing)} ({what}); "
            f"headers found: {', '.join(sn.columns)}"
        )
    return pd.read_csv(
        path,
        sep=sn.delimiter,
        encoding=sn.encoding,
        dtype={c: "str" for c in text_columns},
        compression="gzip" if sn.compression else None,
    )

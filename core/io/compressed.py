"""Open a track file as its text's bytes, whatever it is compressed with: the one opener
of every reader (the sniffer, the whole-file and streamed importers, the reading in
pieces, NMEA logs, the layout ``export --like`` copies, bearings, ``wakeline batch``).

The compression is told by the file's first bytes, not its name: gzip, bz2, xz, zstd, or
a zip archive holding one file (directories and macOS's ``__MACOSX/`` entries left out).
Everything is streamed: a zip member is decompressed as it is read, never held whole.
A 7z archive, a zip of several files, a zip holding a compressed file and damaged or
cut short data are refused with one :class:`InputError` naming the file and what to do.
"""

import bz2
import lzma
import zipfile
import zlib
from pathlib import Path
from typing import BinaryIO

from wakeline.core.errors import InputError

#: First bytes of the compressed formats (gzip's two are checked first).
_PACKED = (
    (b"BZh", "bz2"),
    (b"\xfd7zXZ\x00", "xz"),
    (b"\x28\xb5\x2f\xfd", "zstd"),
    (b"PK\x03\x04", "zip"),
    (b"PK\x05\x06", "zip"),  # an empty zip archive
    (b"7z\xbc\xaf\x27\x1c", "7z"),
)
#: The compressions the readers open (7z is refused: no streaming reader in Python).
OPENED = ("gzip", "bz2", "xz", "zstd", "zip")
#: How to decompress what is there of damaged data by hand (named in the messages).
SALVAGE = {
    "gzip": "gzip -dc FILE > part.csv",
    "bz2": "bzcat FILE > part.csv",
    "xz": "xzcat FILE > part.csv",
    "zstd": "zstdcat FILE > part.csv",
    "zip": "unzip FILE",
}
#: Zip methods Python reads: stored, deflate, bzip2, lzma (not deflate64, which Windows
#: writes for large files, nor others).
_ZIP_METHODS = {
    zipfile.ZIP_STORED: "stored",
    zipfile.ZIP_DEFLATED: "deflate",
    zipfile.ZIP_BZIP2: "bzip2",
    zipfile.ZIP_LZMA: "lzma",
}
_ZIP_METHOD_NAMES = {9: "deflate64", 93: "zstd", 95: "xz", 97: "WavPack", 98: "PPMd"}
#: A tar archive's mark, at byte 257 of its first header (a .tar.gz decompressed).
_TAR_MARK = (257, b"ustar")


def packed_kind(head: bytes) -> str | None:
    """The compressed format a file's first bytes show (``gzip``, ``bz2``, ``xz``,
    ``zstd``, ``zip``, ``7z``), or None for text."""
    if head[:2] == b"\x1f\x8b":
        return "gzip"
    kind = next((k for magic, k in _PACKED if head.startswith(magic)), None)
    if kind == "bz2" and head[4:10] != b"1AY&SY":  # a text starting "BZh": its block magic
        return None
    return kind


def is_tar(head: bytes) -> bool:
    """Whether decompressed bytes start a tar archive (a ``.tar.gz``)."""
    at, mark = _TAR_MARK
    return head[at : at + len(mark)] == mark


def compression_of(path: str | Path) -> str | None:
    """The compression of ``path`` by its first bytes (:func:`packed_kind`); a 7z archive
    is refused (:class:`InputError`). Raises ``OSError`` as ``open`` does."""
    with open(path, "rb") as fh:
        kind = packed_kind(fh.read(16))
    if kind == "7z":
        raise InputError(
            f"{path}: a 7z archive; Wakeline opens text files, gzip, bz2, xz, zstd and a zip "
            "of one file. Unpack it first (7z x FILE) and open the CSV"
        )
    return kind


def _skipped(info: zipfile.ZipInfo) -> bool:
    """A zip entry that is no data: a directory, macOS's resource forks and Finder files."""
    name = info.filename
    base = name.rsplit("/", 1)[-1]
    return info.is_dir() or name.startswith("__MACOSX/") or base in (".DS_Store", "Thumbs.db")


#: Office documents are zip archives: the member that names each, what it is, and how
#: to save it as a CSV file.
_OFFICE = (
    ("xl/workbook.xml", "an Excel workbook (.xlsx)", "in Excel: File ▸ Save As ▸ CSV UTF-8"),
    ("xl/workbook.bin", "an Excel binary workbook (.xlsb)", "in Excel: File ▸ Save As ▸ CSV UTF-8"),
    (
        "content.xml",
        "an OpenDocument file (.ods)",
        "in LibreOffice Calc: File ▸ Save As ▸ Text CSV",
    ),
    ("word/document.xml", "a Word document (.docx)", "copy its table into a spreadsheet first"),
)


def _office_document(names: set[str]) -> tuple[str, str] | None:
    """(what it is, how to save it as CSV) when the archive's member ``names`` make an
    office document, else None."""
    for member, kind, save_as in _OFFICE:
        if member in names and (member != "content.xml" or "mimetype" in names):
            return kind, save_as
    return None


def data_members(archive: zipfile.ZipFile) -> list[zipfile.ZipInfo]:
    """The data files of a zip archive, in its order (directories, ``__MACOSX/`` left out)."""
    return [m for m in archive.infolist() if not _skipped(m)]


def zip_member(
    archive: zipfile.ZipFile, path: str | Path, name: str | None = None
) -> zipfile.ZipInfo:
    """The one data file of a zip archive (or the one named ``name``: ``wakeline batch``
    reads each file of a zip of several); :class:`InputError` for none, several (named),
    an encrypted one or one compressed with a method Python does not read."""
    members = data_members(archive)
    office = _office_document({m.filename for m in members})
    if office is not None:
        kind, save_as = office
        raise InputError(
            f"{path}: {kind}, not a text file of rows; Wakeline reads CSV and text tables: "
            f"save it as CSV ({save_as}) and open that file"
        )
    if name is not None:
        members = [m for m in members if m.filename == name]
        if not members:
            raise InputError(f"{path}: no file {name} in this zip archive")
    if not members:
        raise InputError(f"{path}: a zip archive with no file in it; nothing to import")
    if len(members) > 1:
        names = ", ".join(m.filename for m in members[:6])
        more = f" and {len(members) - 6} more" if len(members) > 6 else ""
        raise InputError(
            f"{path}: a zip archive of {len(members)} files ({names}{more}); Wakeline opens a "
            "zip holding one file: unzip it and open one CSV, or give the zip to "
            "`wakeline batch`, which reads them all"
        )
    member = members[0]
    if member.flag_bits & 0x1:
        raise InputError(
            f"{path}: {member.filename} in this zip archive is password-protected; unzip it "
            "(unzip FILE, giving the password) and open the CSV"
        )
    if member.compress_type not in _ZIP_METHODS:
        method = _ZIP_METHOD_NAMES.get(member.compress_type, f"method {member.compress_type}")
        raise InputError(
            f"{path}: {member.filename} in this zip archive is compressed with {method}, "
            "which Wakeline cannot read; unzip it (unzip FILE, or 7z x FILE) and open the CSV"
        )
    return member


def damaged(path: str | Path, kind: str | None, exc: BaseException) -> str:
    """The message for compressed data that is cut short or damaged: the file, the
    decompressor's words, and what to do. Nothing was read from it."""
    text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    unpack = SALVAGE.get(kind or "", "decompress it")
    return (
        f"{path}: the compressed data is cut short or damaged ({kind}: {text}); nothing was "
        "imported from it. The copy is probably incomplete: copy the file again, or "
        f"decompress what is there ({unpack}) and import that"
    )


class open_data:  # noqa: N801  (used as a function: ``with open_data(p, kind) as stream``)
    """``path``'s text as a binary stream, decompressed as it is read (``compression``:
    one of :data:`OPENED`, or None for a plain file; ``member``: a zip's file by name,
    default its one file), in a ``with`` block::

        with open_data(path, "zip") as stream:
            head = stream.read(1 << 16)

    A decompression error met inside the block (data cut short, a bad CRC, a damaged
    block) becomes one :class:`InputError` naming the file (:func:`damaged`); an
    ``OSError`` of the disk (with an ``errno``) passes as it is. :meth:`fraction` tells
    how far through the file on disk the reading is (for progress)."""

    def __init__(
        self, path: str | Path, compression: str | None, member: str | None = None
    ) -> None:
        if compression is not None and compression not in OPENED:
            raise InputError(f"{path}: cannot open {compression}-compressed data")
        self.path = Path(path)
        self.kind = compression
        self.member = member  # a zip's file by name (default: its one file)
        self._raw: BinaryIO | None = None
        self._closers: list = []
        self._size = 0

    def __enter__(self) -> BinaryIO:
        raw = open(self.path, "rb")  # noqa: SIM115  (closed in __exit__)
        self._raw = raw
        self._closers.append(raw)
        try:
            self._size = max(1, self.path.stat().st_size)
            stream = self._open(raw)
        except BaseException as exc:
            self._close()
            self._translate(exc)
            raise
        return stream

    def _open(self, raw: BinaryIO) -> BinaryIO:
        kind = self.kind
        if kind is None:
            return raw
        if kind == "gzip":
            import gzip

            stream = gzip.GzipFile(fileobj=raw, mode="rb")
        elif kind == "bz2":
            stream = bz2.BZ2File(raw, mode="rb")
        elif kind == "xz":
            stream = lzma.LZMAFile(raw, mode="rb")
        elif kind == "zstd":
            import pyarrow as pa

            stream = pa.CompressedInputStream(pa.PythonFile(raw, mode="r"), "zstd")
        else:
            archive = zipfile.ZipFile(raw)
            self._closers.append(archive)
            stream = archive.open(zip_member(archive, self.path, self.member))
            head = stream.peek(16)[:16]
            inner = packed_kind(head)
            if inner is not None:
                name = stream.name
                self._closers.append(stream)
                raise InputError(
                    f"{self.path}: a zip archive holding {name}, itself compressed ({inner}); "
                    f"unzip it (unzip FILE) and open {name}"
                )
        self._closers.append(stream)
        return stream

    def raw_bytes(self) -> int:
        """Bytes of the file on disk read so far (compressed bytes)."""
        try:
            return self._raw.tell() if self._raw else 0
        except (OSError, ValueError):  # closed
            return 0

    def fraction(self) -> float:
        """How much of the file on disk has been read (0 to 1; compressed bytes)."""
        return min(1.0, self.raw_bytes() / max(1, self._size))

    def _close(self) -> None:
        for obj in reversed(self._closers):
            try:
                obj.close()
            except Exception:  # noqa: BLE001, S110  (closing after an error: the error stands)
                pass
        self._closers.clear()

    def _translate(self, exc: BaseException) -> None:
        """Raise the :class:`InputError` a decompression error means (else return)."""
        if isinstance(exc, InputError):
            return
        if isinstance(exc, OSError) and (exc.errno or exc.filename):
            return  # the disk, not the data
        if isinstance(exc, zipfile.BadZipFile) and self.kind == "zip":
            text = str(exc)
            if "not a zip file" in text.lower() or "truncated" in text.lower():
                raise InputError(
                    f"{self.path}: a zip archive cut short or damaged ({text}: its list of "
                    "files at the end is missing); nothing was imported from it. Copy the "
                    "file again"
                ) from None
        if self._decompressing(exc):
            raise InputError(damaged(self.path, self.kind, exc)) from None

    def _decompressing(self, exc: BaseException) -> bool:
        """Whether ``exc`` is the decompressor's (not a parser's met in the same block)."""
        import gzip

        if isinstance(exc, EOFError | lzma.LZMAError | zlib.error | zipfile.BadZipFile):
            return True
        if type(exc) is OSError or isinstance(exc, gzip.BadGzipFile):
            return True  # bz2's "Invalid data stream", gzip's "Not a gzipped file"
        text = str(exc).lower()
        arrow = type(exc).__module__.startswith("pyarrow")
        return self.kind == "zstd" and arrow and ("zstd" in text or "decompress" in text)

    def __exit__(self, exc_type, exc, tb) -> bool:
        self._close()
        if exc is not None and self.kind is not None:
            self._translate(exc)
        return False


def open_for_arrow(path: str | Path, compression: str | None):
    """:func:`open_data` for an Arrow reader, in a ``with`` block: a plain file is opened
    by Arrow itself (its own reads, no Python call per block); a compressed one is
    decompressed by :class:`open_data`, which Arrow reads as a Python file."""
    if compression is None:
        import pyarrow as pa

        return pa.input_stream(str(path))
    return open_data(path, compression)

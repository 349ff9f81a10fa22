"""Compressed track files open directly (gzip, bz2, xz, zstd, a zip of one file) through
every reader: the whole-file read, the streamed import, the reading in pieces, NMEA logs,
``export --like`` and the import dialog; all through one opener
(:func:`wakeline.core.io.compressed.open_data`). Before, every compression but gzip was
refused ("Decompress it first"). A zip of several files, a zip holding a compressed
file and damaged data give one message naming the file; nothing is written."""

import bz2
import gzip
import lzma
import zipfile
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pytest

from conftest import DATA
from wakeline.app.cli import main
from wakeline.core.errors import InputError
from wakeline.core.io import import_to_csv, inspect_file, read_points, reader
from wakeline.core.io.compressed import open_data

KINDS = ("gzip", "bz2", "xz", "zstd", "zip")


def _pack(path: Path, kind: str, member: str | None = None) -> Path:
    """``path`` compressed as ``kind``; a zip holds it as ``member`` (default its name),
    beside a directory entry and a macOS resource fork (both left out when reading)."""
    data = path.read_bytes()
    if kind == "zip":
        out = path.with_suffix(".zip")
        with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("day/", b"")
            archive.writestr(f"__MACOSX/day/._{path.name}", b"\x00\x05\x16\x07junk")
            archive.writestr(f"day/{member or path.name}", data)
        return out
    out = path.with_name(path.name + {"gzip": ".gz", "bz2": ".bz2", "xz": ".xz"}.get(kind, ".zst"))
    if kind == "gzip":
        out.write_bytes(gzip.compress(data))
    elif kind == "bz2":
        out.write_bytes(bz2.compress(data))
    elif kind == "xz":
        out.write_bytes(lzma.compress(data))
    else:
        with pa.output_stream(str(out), compression="zstd") as fh:
            fh.write(data)
    return out


def _rows(n: int, quoted: bool = False, bad: int | None = None) -> str:
    lines = [
        f"S1,{k % 7},2024-05-01T{k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d}Z,"
        f"{10 + (k * 7919) % 100000 / 1e5:.5f},{57 + k % 13 * 1e-3:.4f}"
        for k in range(n)
    ]
    if quoted:  # quotes in the start: read piece by piece by the importer
        lines[3] = lines[3].replace("S1,", '"S1",', 1)
    if bad is not None:  # a value only the careful parse reads (a letter O for a zero)
        lines[bad] = lines[bad].replace(",10.", ",1O.", 1)
    return "sensor,batch,time,lon,lat\n" + "\n".join(lines) + "\n"


@pytest.fixture
def plain(tmp_path) -> Path:
    path = tmp_path / "day.csv"
    path.write_text(_rows(3000, bad=1700))
    return path


@pytest.mark.parametrize("kind", KINDS)
def test_read_points_reads_each_compression_as_the_plain_file(plain, kind):
    packed = _pack(plain, kind)
    want, got = read_points(plain), read_points(packed)
    pd.testing.assert_frame_equal(got.points, want.points)
    pd.testing.assert_frame_equal(got.quarantine, want.quarantine)
    assert got.report["compression"] == kind and want.report["compression"] is None
    assert got.report["rows_imported"] == 2999 and got.report["rows_quarantined"] == 1
    assert got.points["batch"].nunique() == 7  # the batch column, not the file's name
    # The inspection behind the import dialog's preview reads it too.
    info = inspect_file(packed)
    assert info["preview"] == inspect_file(plain)["preview"] and info["problem"] is None


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("quoted", [False, True], ids=["streamed", "pieces"])
def test_streamed_and_pieces_import_give_the_plain_files_output(
    tmp_path, monkeypatch, kind, quoted
):
    """``wakeline import``'s streamed reader (no quotes) and the reading in pieces (quotes
    in the start and one bad value: its piece read carefully), in pieces of 8 KB: the output
    and quarantine are the plain file's, byte for byte, and the report says the
    compression; the member is read as it streams (never unpacked beside it)."""
    monkeypatch.setattr(reader, "STREAM_BYTES", 8 << 10)
    plain = tmp_path / "day.csv"
    plain.write_text(_rows(4000, quoted=quoted, bad=2500 if quoted else None))
    packed = _pack(plain, kind)
    want = import_to_csv(plain, tmp_path / "want.csv")
    got = import_to_csv(packed, tmp_path / "got.csv")
    assert (tmp_path / "got.csv").read_bytes() == (tmp_path / "want.csv").read_bytes()
    pd.testing.assert_frame_equal(got.quarantine, want.quarantine)
    assert got.report["compression"] == kind and got.layout["compression"] == kind
    assert got.report["rows_quarantined"] == int(quoted)
    assert got.report["rows_imported"] == 4000 - int(quoted)
    assert want.report.get("pieces", 0) == got.report.get("pieces", 0)
    if quoted:
        assert got.report["pieces"] > 1
    else:
        assert got.report["streamed"]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["day.csv", packed.name, "want.csv", "got.csv"]
    )


@pytest.mark.parametrize("kind", ["zip", "bz2"])
def test_nmea_log_compressed(tmp_path, kind):
    src = tmp_path / "ais_log.nmea"
    src.write_bytes((DATA / "battery" / "ais_log.nmea").read_bytes())
    want, got = read_points(src), read_points(_pack(src, kind))
    pd.testing.assert_frame_equal(got.points, want.points)
    assert got.report["compression"] == kind and len(got.points) == 2
    assert main(["import", str(_pack(src, kind)), "-o", str(tmp_path / "o.csv")]) == 0


def test_a_zip_of_several_files_names_them_and_says_what_to_do(tmp_path, plain, capsys):
    packed = tmp_path / "days.zip"
    with zipfile.ZipFile(packed, "w") as archive:
        archive.writestr("__MACOSX/._a.csv", b"junk")
        archive.write(plain, "a.csv")
        archive.write(plain, "b.csv")
    with pytest.raises(InputError) as err:
        read_points(packed)
    text = str(err.value)
    assert text.startswith(f"{packed}: a zip archive of 2 files (a.csv, b.csv)")
    assert "unzip it" in text and "give the zip to `wakeline batch`, which reads them" in text
    out = tmp_path / "o.csv"
    assert main(["import", str(packed), "-o", str(out)]) == 2
    assert "(a.csv, b.csv)" in capsys.readouterr().err and not out.exists()
    empty = tmp_path / "empty.zip"
    with zipfile.ZipFile(empty, "w") as archive:
        archive.writestr("day/", b"")
    with pytest.raises(InputError, match="a zip archive with no file in it"):
        read_points(empty)


def test_a_zip_holding_a_compressed_file_says_to_unzip_it(tmp_path, plain):
    """Decided: a zip holding ``day.csv.gz`` is not opened two levels deep; the message
    names the file inside to open once unzipped."""
    inner = _pack(plain, "gzip")
    packed = tmp_path / "nested.zip"
    with zipfile.ZipFile(packed, "w") as archive:
        archive.write(inner, inner.name)
    with pytest.raises(InputError, match=r"holding day\.csv\.gz, itself compressed \(gzip\)"):
        read_points(packed)


def test_a_zip_method_python_cannot_read_is_named(tmp_path, plain):
    """Windows writes deflate64 for large files: named, not a traceback."""
    packed = _pack(plain, "zip")
    data = bytearray(packed.read_bytes())
    at = data.rfind(b"PK\x01\x02")  # the last central directory entry: day/day.csv
    data[at + 10 : at + 12] = (9).to_bytes(2, "little")
    packed.write_bytes(bytes(data))
    with pytest.raises(InputError, match="compressed with deflate64, which Wakeline cannot"):
        read_points(packed)


def _big(tmp_path: Path) -> Path:
    """A file whose text is well past the sniffer's 256 KB sample."""
    path = tmp_path / "big.csv"
    path.write_text(_rows(60_000))
    return path


@pytest.mark.parametrize("kind", ["gzip", "bz2", "xz", "zstd", "zip"])
@pytest.mark.parametrize("how", ["cut", "flipped"])
def test_damaged_data_is_one_message_and_nothing_is_written(tmp_path, capsys, kind, how):
    """Data cut short or with a damaged byte past the sniffer's sample: the whole read, the
    streamed import and the CLI all stop with one message naming the file (no points of
    the part before the damage pass as the file's); no output is left."""
    packed = _pack(_big(tmp_path), kind)
    data = bytearray(packed.read_bytes())
    if how == "cut":
        data = data[: len(data) * 9 // 10]
    else:
        data[len(data) * 8 // 10] ^= 0x55
    packed.write_bytes(bytes(data))
    with pytest.raises(InputError) as err:
        read_points(packed)
    text = str(err.value)
    assert text.startswith(str(packed)) and ("cut short or damaged" in text), text
    with pytest.raises(InputError, match="cut short or damaged"):
        import_to_csv(packed, tmp_path / "o.csv")
    assert not (tmp_path / "o.csv").exists()
    assert main(["import", str(packed), "-o", str(tmp_path / "o.csv")]) == 2
    err_text = capsys.readouterr().err
    assert str(packed) in err_text and err_text.count("\n") == 1
    assert not (tmp_path / "o.csv").exists()


def test_a_tar_gz_and_a_7z_are_named(tmp_path, plain):
    import tarfile

    tgz = tmp_path / "days.tar.gz"
    with tarfile.open(tgz, "w:gz") as archive:
        archive.add(plain, "day.csv")
    with pytest.raises(InputError, match=r"a tar archive \(gzip-compressed\); unpack it"):
        read_points(tgz)
    seven = tmp_path / "day.7z"
    seven.write_bytes(b"7z\xbc\xaf\x27\x1c" + bytes(100))
    with pytest.raises(InputError, match=r"a 7z archive; .* \(7z x FILE\)"):
        read_points(seven)


def test_the_opener_streams_a_zip_member_and_tells_its_progress(tmp_path):
    """The member is decompressed as it is read: a read of 1 MB of a 12 MB member has read
    a small part of the archive on disk."""
    packed = _pack(_big(tmp_path), "zip")
    opened = open_data(packed, "zip")
    with opened as stream:
        head = stream.read(1 << 18)
        assert head.startswith(b"sensor,batch,time,lon,lat\n")
        assert 0 < opened.fraction() < 0.9
    assert opened.raw_bytes() == 0  # closed


def test_export_like_a_zipped_original_writes_plain_text_in_its_layout(tmp_path, capsys):
    src = tmp_path / "orig.csv"
    src.write_text(
        "MMSI;Time;Lat;Lon\n"
        + "".join(
            f"2190{k % 3};01/05/2024 00:{k:02d}:00;57,{k:04d};11,5{k:03d}\n" for k in range(40)
        )
    )
    packed = _pack(src, "zip")
    out_plain, out_zip = tmp_path / "a.csv", tmp_path / "b.csv"
    assert main(["export", str(src), "-o", str(out_plain), "--like", str(src)]) == 0
    capsys.readouterr()
    assert main(["export", str(packed), "-o", str(out_zip), "--like", str(packed)]) == 0
    err = capsys.readouterr().err
    assert f"plain text: {packed} is zip-compressed" in err
    assert out_zip.read_bytes() == out_plain.read_bytes()
    assert out_zip.read_bytes().startswith(b"MMSI;Time;Lat;Lon\n")


def test_batch_reads_a_zip_of_one_or_several_files(tmp_path, plain):
    """``wakeline batch`` reads compressed inputs through the importer's opener (before,
    each was first decompressed into the stage folder), and a zip of several files as
    those files (before: refused): the same rows, tracks and quarantine (named
    ``days.zip/b.csv``) as the files given apart."""
    import json

    from wakeline.core import batch
    from wakeline.core.pipeline import Pipeline

    assert not hasattr(batch, "_unpack") and not hasattr(batch, "_text_stream")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())

    def run(name: str, *inputs: Path) -> dict:
        out = tmp_path / name
        code = main(["batch", str(pipe), *map(str, inputs), "-o", str(out), "--csv"])
        rep = json.loads((out / "report.json").read_text())
        assert code == 0  # rows quarantined alone: 0 (3 only for a refused input)
        return rep

    rep = run("one", _pack(plain, "zip"))
    assert rep["rows_read"] == 3000 and rep["quarantined"] == 1
    other = tmp_path / "b.csv"
    other.write_text(_rows(500).replace("S1,", "S2,"))
    packed = tmp_path / "days.zip"
    with zipfile.ZipFile(packed, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("__MACOSX/._a.csv", b"junk")
        archive.write(plain, "a.csv")
        archive.write(other, "b.csv")
    (tmp_path / "a.csv").write_bytes(plain.read_bytes())
    zipped, apart = run("zipped", packed), run("apart", tmp_path / "a.csv", other)
    assert zipped["rows_read"] == apart["rows_read"] == 3500
    assert zipped["quarantined"] == apart["quarantined"] == 1
    assert (tmp_path / "zipped" / "clean.csv").read_bytes() == (
        tmp_path / "apart" / "clean.csv"
    ).read_bytes()
    q = pd.read_parquet(tmp_path / "zipped" / "quarantine")
    assert list(q["file"]) == [f"{packed}/a.csv"] and list(q["line"]) == [1702]


def test_real_files_lists_compressed_track_files(tmp_path, plain):
    from wakeline.core.evaluate_association import real_files

    folder = tmp_path / "set"
    folder.mkdir()
    for kind in ("gzip", "bz2", "zip"):
        p = _pack(plain, kind)
        p.rename(folder / p.name)
    (folder / "notes.pdf").write_bytes(b"%PDF")
    assert [f.name for f in real_files(folder)] == ["day.csv.bz2", "day.csv.gz", "day.zip"]


def test_clean_and_evaluate_real_read_a_zip(tmp_path):
    """``wakeline clean`` (streamed) and ``evaluate maneuver --real`` on a zip: what they
    give on the plain file."""
    from wakeline.core import simulate
    from wakeline.core.evaluate_real import evaluate_real
    from wakeline.core.io import write_points

    src = tmp_path / "scene.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=3, area_km=10.0), src)
    packed = _pack(src, "zip")
    for name, given in (("a.csv", src), ("b.csv", packed)):
        assert main(["clean", str(given), "-o", str(tmp_path / name)]) == 0
    assert (tmp_path / "b.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()
    want = evaluate_real(src).rows.set_index("method")
    got = evaluate_real(packed).rows.set_index("method")
    pd.testing.assert_frame_equal(got, want)


@pytest.mark.parametrize(
    ("members", "says"),
    [
        (
            ["[Content_Types].xml", "_rels/.rels", "xl/workbook.xml", "xl/worksheets/sheet1.xml"],
            "Excel workbook (.xlsx)",
        ),
        (["mimetype", "content.xml", "styles.xml"], "OpenDocument"),
        (["[Content_Types].xml", "word/document.xml"], "Word document"),
    ],
)
@pytest.mark.parametrize("suffix", [".xlsx", ".csv"])
def test_an_office_document_is_named_with_how_to_save_it_as_csv(tmp_path, members, says, suffix):
    """Operator test 4 (D-import-3): a workbook was refused as "a zip archive of 5 files …
    unzip it … or give the zip to `wakeline batch`", advice that does not apply."""
    p = tmp_path / f"ship{suffix}"
    with zipfile.ZipFile(p, "w") as z:
        for m in members:
            z.writestr(m, "<x/>")
    with pytest.raises(InputError) as got:
        read_points(p)
    text = str(got.value)
    assert says in text and "CSV" in text and "unzip" not in text and "batch" not in text


def test_an_excel_97_workbook_is_named_with_how_to_save_it_as_csv(tmp_path):
    p = tmp_path / "ship.xls"
    p.write_bytes(bytes.fromhex("D0CF11E0A1B11AE1") + bytes(range(256)) * 4)
    with pytest.raises(InputError) as got:
        read_points(p)
    assert "Excel 97-2003" in str(got.value) and "Save As" in str(got.value)

"""``wakeline batch``: the same tables as the single-process command line, partitioned by
track with Dask (docs/batch.md)."""

import json
import os
from pathlib import Path

import pandas as pd
import pytest

pytest.importorskip("dask.dataframe")
pytest.importorskip("distributed")

from wakeline.app.cli import main  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.batch import BatchOptions, run_batch  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.pipeline import STEPS, Pipeline  # noqa: E402


def _split(df: pd.DataFrame, folder: Path, parts: int) -> list[Path]:
    """Files of consecutive rows: tracks straddle files, as in daily exports."""
    paths = []
    n = len(df)
    for k in range(parts):
        path = folder / f"part{k}.csv"
        write_points(df.iloc[k * n // parts : (k + 1) * n // parts], path)
        paths.append(path)
    return paths


def _concat(paths: list[Path], path: Path) -> Path:
    with open(path, "wb") as out:
        for k, p in enumerate(paths):
            lines = p.read_bytes().splitlines(keepends=True)
            out.writelines(lines if k == 0 else lines[1:])
    return path


def _rows(path: Path) -> pd.DataFrame:
    """A CSV as text, sorted by sensor, batch, time (row for row comparison)."""
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    return df.sort_values(["sensor", "batch", "time"], kind="stable").reset_index(drop=True)


@pytest.fixture(scope="module")
def scene(tmp_path_factory) -> tuple[list[Path], Path]:
    """Radar and AIS of one scene (with reported speed and course), in three files."""
    folder = tmp_path_factory.mktemp("batch_in")
    df = simulate.multisensor_scene(seed=11, n_ships=5)
    paths = _split(df, folder, 3)
    return paths, _concat(paths, folder / "all.csv")


def test_compress_equals_clean_then_compress_on_a_local_cluster(scene, tmp_path):
    paths, whole = scene
    pipe = tmp_path / "pipe.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    opts = BatchOptions(workers=2, processes=False, csv=True, blocksize_mb=0.1, buckets=5)
    result = run_batch(Pipeline.default(), paths, out, opts)
    assert main(["clean", str(whole), "-o", str(tmp_path / "c.csv")]) == 0
    assert main(["compress", str(tmp_path / "c.csv"), "-o", str(tmp_path / "cc.csv")]) == 0
    assert main(["maneuvers", str(tmp_path / "c.csv"), "-o", str(tmp_path / "m.csv")]) == 0

    batch, single = _rows(out / "compress.csv"), _rows(tmp_path / "cc.csv")
    assert len(single) > 100
    pd.testing.assert_frame_equal(batch, single)
    pd.testing.assert_frame_equal(_rows(out / "clean.csv"), _rows(tmp_path / "c.csv"))
    pd.testing.assert_frame_equal(_rows(out / "maneuvers.csv"), _rows(tmp_path / "m.csv"))
    # Several partitions really were used, and every track sits whole in one.
    parts = sorted((out / "compress").glob("*.parquet"))
    assert len(parts) > 1
    keys = [set(map(tuple, pd.read_parquet(p)[["sensor", "batch"]].to_numpy())) for p in parts]
    assert sum(len(k) for k in keys) == len(set().union(*keys))
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == sum(len(pd.read_csv(p)) for p in paths)
    assert rep["steps"]["compress"]["rows_out"] == len(single)
    assert rep["steps"]["clean"]["rows_out"] == len(_rows(tmp_path / "c.csv"))
    assert result.report == rep | {"input_bytes": rep["input_bytes"]}
    assert not (out / "_stage").exists()


def test_association_across_partitions_equals_single_process(tmp_path):
    """Tracks a radar broke apart land in different partitions; the second pass over
    their end points joins them as `wakeline associate` does on the whole table."""
    df = simulate.segments_scene(seed=4, n_ships=6)
    paths = _split(df, tmp_path, 2)
    whole = _concat(paths, tmp_path / "all.csv")
    pipe = Pipeline(
        (("clean", STEPS["clean"].defaults()), ("associate", STEPS["associate"].defaults()))
    )
    from distributed import LocalCluster

    # A running cluster reached by its address, as `--scheduler ADDRESS` does.
    with LocalCluster(n_workers=2, processes=False, dashboard_address=":0") as cluster:
        opts = BatchOptions(scheduler=cluster.scheduler_address, csv=True, buckets=6)
        rep = run_batch(pipe, paths, tmp_path / "out", opts).report
    assert rep["scheduler"].startswith(("tcp://", "inproc://"))
    assert main(["clean", str(whole), "-o", str(tmp_path / "c.csv")]) == 0
    assert (
        main(
            [
                "associate",
                str(tmp_path / "c.csv"),
                "-o",
                str(tmp_path / "a.csv"),
                "--pairs",
                str(tmp_path / "p.csv"),
            ]
        )
        == 0
    )
    batch, single = _rows(tmp_path / "out" / "associate.csv"), _rows(tmp_path / "a.csv")
    pd.testing.assert_frame_equal(batch, single)
    assert single["target"].nunique() < single.groupby(["sensor", "batch"]).ngroups
    # The joined tracks of one target were in different partitions.
    parts = sorted((tmp_path / "out" / "associate").glob("*.parquet"))
    where = pd.concat(
        [pd.read_parquet(p)[["batch", "target"]].assign(part=k) for k, p in enumerate(parts)]
    )
    assert (where.groupby("target")["part"].nunique() > 1).any()
    pairs = pd.read_csv(tmp_path / "out" / "associate_pairs.csv", dtype=str)
    ref = pd.read_csv(tmp_path / "p.csv", dtype=str)
    key = ["sensor", "batch_a", "batch_b"]
    pd.testing.assert_frame_equal(
        pairs.sort_values(key).reset_index(drop=True), ref.sort_values(key).reset_index(drop=True)
    )


@pytest.mark.skipif(
    not os.environ.get("WAKELINE_CI"),
    reason="starts two worker processes (20-60 s on a busy machine): runs in CI (.ci/run "
    "sets WAKELINE_CI=1)",
)
def test_batch_command_with_worker_processes(tmp_path, capsys):
    """The command line with a LocalCluster of two real worker processes."""
    df = simulate.maneuver_tracks(8, "short", 100.0, seed=5)
    paths = _split(df, tmp_path, 2)
    whole = _concat(paths, tmp_path / "all.csv")
    pipe = tmp_path / "pipe.json"
    assert main(["batch", "--print-pipeline"]) == 0
    pipe.write_text(capsys.readouterr().out)
    out = tmp_path / "out"
    args = ["batch", str(pipe), *map(str, paths), "-o", str(out), "--workers", "2", "--csv"]
    assert main([*args, "--partition-mb", "0.01"]) == 0
    assert "compress" in capsys.readouterr().err
    assert main(["clean", str(whole), "-o", str(tmp_path / "c.csv")]) == 0
    assert main(["compress", str(tmp_path / "c.csv"), "-o", str(tmp_path / "cc.csv")]) == 0
    pd.testing.assert_frame_equal(_rows(out / "compress.csv"), _rows(tmp_path / "cc.csv"))
    assert len(list((out / "compress").glob("*.parquet"))) > 1


def test_parquet_inputs_and_quarantine(tmp_path):
    df = simulate.maneuver_tracks(6, "short", 50.0, seed=2)
    bad = df.iloc[:3].copy().astype(str)
    bad.loc[:, "lat"] = ["95.0", "x", ""]
    mixed = pd.concat([df.astype(str), bad], ignore_index=True)
    mixed.to_csv(tmp_path / "in.csv", index=False)
    res = run_batch(Pipeline.default(), [tmp_path / "in.csv"], tmp_path / "o1", BatchOptions())
    assert res.report["quarantined"] == 3
    # CSV inputs are read as `wakeline import` reads them: its quarantine, line by line
    q = pd.read_parquet(tmp_path / "o1" / "quarantine")
    assert q["line"].tolist() == [len(df) + 2, len(df) + 3, len(df) + 4]
    assert q["reason"].tolist() == ["lat out of range", "unparsable lat", "missing lat"]
    assert (q["file"] == str(tmp_path / "in.csv")).all()
    write = tmp_path / "in.parquet"
    df.to_parquet(write)
    res2 = run_batch(Pipeline.default(), [write], tmp_path / "o2", BatchOptions(csv=True))
    assert (
        res2.report["steps"]["compress"]["rows_out"] == res.report["steps"]["compress"]["rows_out"]
    )
    # An earlier batch's folder is replaced; another non-empty folder is refused.
    assert run_batch(Pipeline.default(), [write], tmp_path / "o2", BatchOptions()).report


@pytest.mark.parametrize(
    ("setup", "message"),
    [
        ("nocols", "missing required column"),
        ("fuse", "step fuse is not supported"),
        ("notpipe", "not a Wakeline pipeline"),
        ("full", "is not empty"),
        ("noargs", "needs PIPELINE.json"),
        ("parquet_map", "--map: for CSV inputs only"),
    ],
)
def test_bad_batch_input_is_one_message(tmp_path, capsys, setup, message):
    data = tmp_path / "in.csv"
    data.write_text("sensor,batch,time,lon,lat\nR,1,2024-01-01T00:00:00Z,122,30\n")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    if setup == "nocols":
        data.write_text("a,b\n1,2\n")
    elif setup == "fuse":
        pipe.write_text(json.dumps({"wakeline_pipeline": 1, "steps": [{"step": "fuse"}]}))
    elif setup == "notpipe":
        pipe.write_text("{}")
    elif setup == "full":
        out.mkdir()
        (out / "keep.txt").write_text("mine")
    argv = ["batch", str(pipe), str(data), "-o", str(out)]
    if setup == "parquet_map":
        pd.read_csv(data).to_parquet(tmp_path / "in.parquet")
        argv = ["batch", str(pipe), str(tmp_path / "in.parquet"), "-o", str(out), "--map", "lon=x"]
    if setup == "noargs":
        argv = ["batch", str(pipe)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    if setup == "full":
        assert (out / "keep.txt").read_text() == "mine"


def _compress(path: Path, kind: str) -> Path:
    """``path`` compressed as ``kind`` (gzip, bz2, xz, zstd, zip)."""
    import bz2
    import gzip
    import lzma
    import zipfile

    data = path.read_bytes()
    out = path.with_name(f"{path.name}.{kind}")
    if kind == "gzip":
        out.write_bytes(gzip.compress(data))
    elif kind == "bz2":
        out.write_bytes(bz2.compress(data))
    elif kind == "xz":
        out.write_bytes(lzma.compress(data))
    elif kind == "zstd":
        import pyarrow as pa

        with pa.output_stream(str(out), compression="zstd") as fh:
            fh.write(data)
    else:
        with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr(path.name, data)
    return out


def _zstd() -> bool:
    import pyarrow as pa

    return pa.Codec.is_available("zstd")


@pytest.mark.parametrize(
    "kind",
    [
        "gzip",
        "bz2",
        "xz",
        pytest.param("zstd", marks=pytest.mark.skipif(not _zstd(), reason="no zstd in pyarrow")),
        "zip",
    ],
)
def test_compressed_csv_inputs(scene, tmp_path, monkeypatch, kind):
    """Compressed inputs are read as their text (before: bz2, xz, zstd and zip were
    refused as binary files); the result equals `wakeline clean` on the text, and the
    quarantine names the compressed file. Small pieces: the damaged file is read piece
    by piece from its decompressed copy."""
    from wakeline.core.io import reader

    paths, _whole = scene
    parts = []
    for k, p in enumerate(paths):
        text = p.read_bytes()
        if k == 1:  # one damaged value: quarantined, named in the compressed file
            lines = text.splitlines(keepends=True)
            lines[5] = lines[5].replace(b",", b",x", 3)
            text = b"".join(lines)
        plain = tmp_path / p.name
        plain.write_bytes(text)
        parts.append(plain)
    whole = _concat(parts, tmp_path / "all.csv")
    packed = [_compress(p, kind) for p in parts]
    monkeypatch.setattr(reader, "STREAM_BYTES", 8192)
    res = run_batch(Pipeline.default(), packed, tmp_path / "out", BatchOptions(csv=True))
    monkeypatch.undo()
    assert main(["clean", str(whole), "-o", str(tmp_path / "c.csv")]) == 0
    pd.testing.assert_frame_equal(_rows(tmp_path / "out" / "clean.csv"), _rows(tmp_path / "c.csv"))
    assert res.report["blocks"] > 2 * len(parts)
    q = pd.read_parquet(tmp_path / "out" / "quarantine")
    assert q["file"].tolist() == [str(packed[1])] and q["line"].tolist() == [6]
    assert res.report["rows_read"] == sum(len(pd.read_csv(p)) for p in paths)
    # The buckets follow the text's size, not the compressed size.
    assert res.report["input_text_bytes"] == sum(p.stat().st_size for p in parts)


@pytest.mark.parametrize("case", ["cut", "cut_later", "two_files"])
def test_unreadable_compressed_input_is_one_message(tmp_path, capsys, monkeypatch, case):
    """Compressed data cut short (seen when checking the inputs, or later while reading:
    before, a gzip cut short there was "Truncated compressed stream" without the file's
    name) or a zip of several files one of which lacks a column (a zip of several was
    refused before h123; now each file is an input): one message naming the file; no
    OUTDIR left."""
    from wakeline.core import batch

    src = tmp_path / "in.csv"
    rows = [f"S1,A,{1_700_000_000 + i},{10 + i * 1e-5:.5f},50.0" for i in range(40_000)]
    src.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    if case.startswith("cut"):
        packed = _compress(src, "bz2" if case == "cut" else "gzip")
        packed.write_bytes(packed.read_bytes()[: packed.stat().st_size * 3 // 4])
        message = "cut short or damaged"
        if case == "cut_later":  # the check before the work reads only the start
            monkeypatch.setattr(batch, "_ESTIMATE_BYTES", 1 << 16)
    else:
        import zipfile

        packed = tmp_path / "two.zip"
        with zipfile.ZipFile(packed, "w") as archive:
            archive.write(src, "a.csv")
            archive.writestr("b.csv", src.read_text().replace(",lat\n", ",height\n", 1))
        message = "two.zip/b.csv: missing"
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(packed), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert str(packed) in err and message in err and err.count("\n") == 1
    assert not out.exists()


def _one_bad_value(tmp_path: Path, quoted: bool = False) -> Path:
    """A file of many pieces (at 4 KB a piece) with one value only the careful parse
    reads, in a piece in the middle."""
    rows = [
        f"S1,{i % 7},2024-01-01T{i // 3600:02d}:{i // 60 % 60:02d}:{i % 60:02d}Z,"
        f"{10 + i * 1e-4:.4f},{50 + (i % 13) * 1e-3:.4f}"
        for i in range(3000)
    ]
    rows[1500] = rows[1500].replace(",10.", ",1O.")  # a letter O for a zero
    if quoted:  # quotes in the file's start: read piece by piece too, cut between quotes
        rows[3] = rows[3].replace("S1,", '"S1",')
        rows[40] = rows[40].replace("S1,", '"S\n1",')
    src = tmp_path / "in.csv"
    src.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    return src


@pytest.mark.parametrize("quoted", [False, True])
def test_one_bad_value_costs_its_piece_not_a_whole_file_read(tmp_path, monkeypatch, quoted):
    """Before: one value the streamed reader could not convert (or a quote in the file's
    start) made batch read the whole file at once (memory: the file's size several times
    over). Now only that piece is read again carefully; the rows equal `wakeline clean`
    and the quarantine equals `wakeline import --quarantine`."""
    import wakeline.core.io as wio
    from wakeline.core.io import reader

    src = _one_bad_value(tmp_path, quoted)
    assert main(["clean", str(src), "-o", str(tmp_path / "c.csv")]) == 0
    assert (
        main(
            [
                "import",
                str(src),
                "-o",
                str(tmp_path / "i.csv"),
                "--quarantine",
                str(tmp_path / "q.csv"),
            ]
        )
        == 0
    )
    monkeypatch.setattr(reader, "STREAM_BYTES", 4096)
    sizes = []
    real = wio.read_points

    def spy(path, *args, **kwargs):
        sizes.append(Path(path).stat().st_size)
        return real(path, *args, **kwargs)

    monkeypatch.setattr(wio, "read_points", spy)
    res = run_batch(Pipeline.default(), [src], tmp_path / "out", BatchOptions(csv=True))
    assert sizes and max(sizes) < src.stat().st_size / 4  # pieces, never the whole file
    assert res.report["blocks"] > 10
    pd.testing.assert_frame_equal(_rows(tmp_path / "out" / "clean.csv"), _rows(tmp_path / "c.csv"))
    q = pd.read_parquet(tmp_path / "out" / "quarantine").drop(columns="file")
    ref = pd.read_csv(tmp_path / "q.csv", dtype={"line": "int64"}, keep_default_na=False)
    pd.testing.assert_frame_equal(q, ref[["line", "reason", "text"]], check_dtype=False)
    assert res.report["quarantined"] == len(ref) >= 1


def test_any_layout_the_importer_reads(tmp_path, capsys):
    """Before: batch refused inputs without a `batch` column. Now any layout `wakeline
    import` reads, with the same reading flags as `wakeline clean`: an AIS export (MMSI
    as the batch), and one ship's file without an id column, semicolons and own names
    mapped with --map (its track named after the file)."""
    df = simulate.maneuver_tracks(4, "short", 50.0, seed=3)
    ais = pd.DataFrame(
        {
            "MMSI": "2190" + df["batch"].astype(str),
            "BaseDateTime": df["time"].dt.strftime("%Y-%m-%dT%H:%M:%S"),
            "LAT": df["lat"],
            "LON": df["lon"],
        }
    )
    ais.to_csv(tmp_path / "ais.csv", index=False)
    one = df[df["batch"] == df["batch"].iloc[0]]
    own = pd.DataFrame(
        {"t": one["time"].dt.strftime("%Y-%m-%dT%H:%M:%SZ"), "x": one["lon"], "y": one["lat"]}
    )
    own.to_csv(tmp_path / "ship7.csv", index=False, sep=";")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    for name, flags in (
        ("ais.csv", []),
        ("ship7.csv", ["--map", "time=t", "--map", "lon=x", "--map", "lat=y"]),
    ):
        src, out = tmp_path / name, tmp_path / f"out-{name}"
        assert main(["batch", str(pipe), str(src), "-o", str(out), "--csv", *flags]) == 0
        assert main(["clean", str(src), "-o", str(tmp_path / f"c-{name}"), *flags]) == 0
        batch, single = _rows(out / "clean.csv"), _rows(tmp_path / f"c-{name}")
        assert len(single) > 10
        pd.testing.assert_frame_equal(batch, single)
    assert set(_rows(tmp_path / "out-ship7.csv" / "clean.csv")["batch"]) == {"ship7"}


def test_parquet_blocks_follow_blocksize(tmp_path, capsys):
    """--blocksize-mb sizes the read tasks of Parquet inputs (before: Dask's default,
    whatever was given; its help spoke of CSV inputs, which are read by file)."""
    df = simulate.maneuver_tracks(6, "short", 50.0, seed=2)
    src = tmp_path / "in.parquet"
    df.to_parquet(src, row_group_size=200)
    small = run_batch(
        Pipeline.default(), [src], tmp_path / "a", BatchOptions(csv=True, blocksize_mb=0.01)
    )
    big = run_batch(
        Pipeline.default(), [src], tmp_path / "b", BatchOptions(csv=True, blocksize_mb=64)
    )
    assert small.report["blocks"] > 1 and big.report["blocks"] == 1
    pd.testing.assert_frame_equal(
        _rows(tmp_path / "a" / "clean.csv"), _rows(tmp_path / "b" / "clean.csv")
    )
    with pytest.raises(SystemExit):
        main(["batch", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--blocksize-mb MB Parquet inputs" in text and "CSV inputs are one task per file" in text


def test_header_only_input_is_reported(tmp_path, capsys):
    """A CSV with a header and no data row beside others: a warning naming the file and
    "no data rows", counted in the report (before: silently accepted, or the whole batch
    refused when the header had no line end). All inputs without data: exit 2."""
    rows = [
        f"S1,A,2024-01-01T00:{i // 60:02d}:{i % 60:02d}Z,{10 + i * 1e-3:.4f},50.0"
        for i in range(300)
    ]
    good = tmp_path / "good.csv"
    good.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    head = tmp_path / "head.csv"
    head.write_text("sensor,batch,time,lon,lat\n")
    bare = tmp_path / "bare.csv"
    bare.write_text("sensor,batch,time,lon,lat")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(good), str(head), str(bare), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    for p in (head, bare):
        assert f"{p}: warning: no data rows" in err
    assert str(good) + ": warning" not in err
    rep = json.loads((out / "report.json").read_text())
    assert rep["empty_inputs"] == [str(head), str(bare)] and rep["rows_read"] == 300
    assert main(["batch", str(pipe), str(head), str(bare), "-o", str(tmp_path / "o2")]) == 2
    err = capsys.readouterr().err
    assert "no data rows" in err and err.count("\n") == 1


@pytest.mark.parametrize("case", ["stray_quote", "unix_seconds", "short_row"])
def test_batch_reads_csv_as_import_does(tmp_path, case):
    """A stray quote (before: every row after it vanished), unix-second times (before:
    all quarantined) and a short row (before: the run stopped): batch keeps what `wakeline
    clean` keeps, quarantines what it quarantines, line by line (fuzzing)."""
    rows = [
        f"S1,A,2024-01-01T00:{i // 60:02d}:{i % 60:02d}Z,{10 + i * 1e-4:.4f},50.0"
        for i in range(600)
    ]
    if case == "stray_quote":
        rows[100] = rows[100].replace(",50.0", ',"50.0')
    elif case == "unix_seconds":
        rows = [f"S1,A,{1_700_000_000 + 10 * i},{10 + i * 1e-4:.4f},50.0" for i in range(600)]
    else:
        rows[200] = "S1,A,2024"
    src = tmp_path / "in.csv"
    src.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    res = run_batch(Pipeline.default(), [src], tmp_path / "out", BatchOptions(csv=True))
    assert main(["clean", str(src), "-o", str(tmp_path / "c.csv")]) == 0
    assert res.report["rows_read"] == 600
    assert res.report["quarantined"] == (0 if case == "unix_seconds" else 1)
    assert res.report["steps"]["clean"]["rows_out"] == len(_rows(tmp_path / "c.csv"))


@pytest.mark.parametrize("quoted", [False, True])
def test_a_clock_change_s_repeated_hour_is_read_over_the_whole_file(tmp_path, monkeypatch, quoted):
    """Local times with --tz through the autumn clock change: the repeated hour is placed
    by each track's order over the whole file. Read piece by piece, a track whose two
    passes lay in two pieces was quarantined (review: 34 of 120 rows); now such a file is
    read whole, as `wakeline clean` reads it."""
    from wakeline.core.io import read_points, reader

    rows = ["batch,time,lon,lat"]
    t = pd.Timestamp("2024-10-27 00:30:00", tz="UTC")
    for k in range(120):
        local = (t + pd.Timedelta(minutes=k)).tz_convert("Europe/Oslo").tz_localize(None)
        batch = '"A"' if quoted else "A"
        rows.append(f"{batch},{local:%Y-%m-%d %H:%M:%S},{10 + k * 1e-3:.4f},55.0")
    src = tmp_path / "dst.csv"
    src.write_text("\n".join(rows) + "\n")
    whole = read_points(src, tz="Europe/Oslo")
    assert len(whole.points) == 120 and len(whole.quarantine) == 0
    monkeypatch.setattr(reader, "STREAM_BYTES", 2000)
    opts = BatchOptions(threads=1, tz="Europe/Oslo")
    res = run_batch(Pipeline.default(), [src], tmp_path / "out", opts)
    assert res.report["rows_read"] == 120 and res.report["quarantined"] == 0


def test_later_lines_in_another_encoding_are_read_as_import_reads_them(tmp_path, monkeypatch):
    """An ASCII start, a bad value (the streamed reader gives up) and, further on, many
    Latin-1 lines: before, the piece of those lines sniffed its own encoding and stopped
    the batch ("cannot decode"); now every piece is read as `read_points` reads the whole
    file (UTF-8, then as the whole file's evidence says: UTF-8 with those lines read as
    Windows-1252 and reported, core/io/decoding.py), still in pieces, and the quarantine
    and warnings equal `wakeline import`'s."""
    import sys

    from wakeline.core.io import read_points, reader

    rows = [
        f"S1,{i % 3},2024-01-01T00:{i // 60 % 60:02d}:{i % 60:02d}Z,{10 + i * 1e-4:.4f},50.0,ok"
        for i in range(3000)
    ]
    rows[100] = rows[100].replace(",10.", ",1O.")
    data = ("sensor,batch,time,lon,lat,remark\n" + "\n".join(rows) + "\n").encode()
    data = data[:100_000] + data[100_000:].replace(b",ok\n", b",caf\xe9\n")
    src = tmp_path / "in.csv"
    src.write_bytes(data)
    monkeypatch.setattr(sys.modules["wakeline.core.io.sniff"], "SAMPLE_BYTES", 4096)
    whole = read_points(src)
    assert len(whole.quarantine) == 1  # the bad lon; the Latin-1 lines are points
    assert whole.report["encoding_fallback"]["cp1252"]["lines"] > 600
    assert (whole.points["remark"].iloc[-1]) == "café"
    monkeypatch.setattr(reader, "STREAM_BYTES", 8192)
    res = run_batch(Pipeline.default(), [src], tmp_path / "out", BatchOptions(threads=1))
    assert res.report["blocks"] > 5  # pieces, not one whole read
    q = pd.read_parquet(tmp_path / "out" / "quarantine").drop(columns="file")
    pd.testing.assert_frame_equal(q, whole.quarantine, check_dtype=False)
    assert res.report["warnings"] == [f"{src}: warning: {w}" for w in whole.report["warnings"]]


def test_stray_and_empty_inputs_and_folders(tmp_path, capsys):
    """Tester h133 (item 10): a README.txt among the inputs aborted the whole batch (exit
    2; evaluate --real skips it with a note); a 0-byte file was "no data rows (a header
    only?)" where import says "the file is empty"; a folder was refused ("give the CSV
    files")."""
    folder = tmp_path / "exports"
    folder.mkdir()
    for k in range(2):
        rows = [
            f"S1,T{k},2024-01-01T00:{i // 60:02d}:{i % 60:02d}Z,{10 + i * 1e-3:.4f},{50 + k}"
            for i in range(200)
        ]
        (folder / f"day{k}.csv").write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    (folder / "README.txt").write_text("notes\nexported by hand\n")
    (folder / "zero.csv").write_bytes(b"")
    (folder / "notes.md").write_text("# not a track file by its name: not read\n")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    files = sorted(folder.glob("*.csv")) + [folder / "README.txt"]
    assert main(["batch", str(pipe), *map(str, files), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"{folder / 'README.txt'}: warning: missing required column" in err
    assert f"{folder / 'zero.csv'}: warning: the file is empty; skipped" in err
    assert "2 inputs skipped" in err.splitlines()[-1]
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 400
    assert [d["input"] for d in rep["skipped_inputs"]] == [str(folder / "README.txt")]
    assert rep["empty_inputs"] == [str(folder / "zero.csv")]
    # The folder itself: its data files, read by the rule of evaluate --real.
    out2 = tmp_path / "out2"
    assert main(["batch", str(pipe), str(folder), "-o", str(out2)]) == 0
    err = capsys.readouterr().err
    rep2 = json.loads((out2 / "report.json").read_text())
    assert rep2["rows_read"] == 400 and "notes.md" not in err
    assert rep2["inputs"] == [str(p) for p in sorted(folder.iterdir()) if p.suffix != ".md"]
    assert (out2 / "clean").is_dir()
    # One input alone is still refused with the importer's message; none readable: exit 2.
    assert main(["batch", str(pipe), str(folder / "README.txt"), "-o", str(tmp_path / "o3")]) == 2
    assert "missing required column" in capsys.readouterr().err
    both = [str(folder / "README.txt"), str(folder / "notes.md")]
    assert main(["batch", str(pipe), *both, "-o", str(tmp_path / "o4")]) == 2
    assert "batch: no input could be read" in capsys.readouterr().err


def test_a_refused_data_file_is_listed_the_rest_run_a_stray_file_is_skipped(tmp_path, capsys):
    """Review: among several inputs any refused file was skipped with a note and the batch
    exited 0, a real data file refused only for a wrong --map too (its rows neither points
    nor quarantine rows). Then any refusal failed the batch before any output, so an
    operator met one refused file per run (operator test 5, D-batch-2). Now only files
    that are not track data (NotTrackData: binary, a header of no known column and no
    --map column) are skipped with a warning; every other refusal is listed with the
    importer's message, the rest is processed, and the batch exits 3 saying so."""
    rows = [f"S1,T1,2024-01-01T00:00:{i:02d}Z,{10 + i * 1e-3:.4f},50" for i in range(50)]
    good = tmp_path / "good.csv"
    good.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    other = tmp_path / "other.csv"  # the same columns under another time name
    other.write_text("sensor,batch,ts,lon,lat\n" + "\n".join(rows) + "\n")
    partial = tmp_path / "partial.csv"  # known columns, lat missing
    partial.write_text("sensor,batch,time,lon\nS1,T1,2024-01-01T00:00:00Z,10\n")
    readme = tmp_path / "README.txt"
    readme.write_text("notes\nexported by hand\n")
    binary = tmp_path / "logo.csv"
    binary.write_bytes(bytes(range(256)) * 4)
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    # A wrong --map: names a column good.csv lacks; good.csv is track data: refused.
    out = tmp_path / "o1"
    code = main(["batch", str(pipe), str(other), str(good), "--map", "time=ts", "-o", str(out)])
    assert code == 3
    err = capsys.readouterr().err
    assert f"{good}: refused: " in err and "ts" in err and "run this file apart" in err
    assert "1 input refused (above, each with its reason)" in err and "exit status 3" in err
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 50  # other.csv's rows
    assert [d["input"] for d in rep["refused_inputs"]] == [str(good)]
    # Known columns, a required one missing: refused, listed; good.csv read.
    code = main(["batch", str(pipe), str(good), str(partial), "-o", str(tmp_path / "o2")])
    assert code == 3
    assert f"{partial}: refused: missing required column lat" in capsys.readouterr().err
    # Not track data: skipped with a note, the batch completes (exit 0), listed.
    out = tmp_path / "o3"
    files = [good, readme, binary]
    assert main(["batch", str(pipe), *map(str, files), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"{readme}: warning: " in err and f"{binary}: warning: this is a binary" in err
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 50
    assert [d["input"] for d in rep["skipped_inputs"]] == [str(readme), str(binary)]
    # With --map, a README (no known column, no --map column) is still skipped.
    out = tmp_path / "o4"
    files = [other, readme]
    assert main(["batch", str(pipe), *map(str, files), "--map", "time=ts", "-o", str(out)]) == 0
    assert json.loads((out / "report.json").read_text())["rows_read"] == 50
    capsys.readouterr()


def test_an_empty_file_says_what_import_says(tmp_path, capsys):
    zero = tmp_path / "zero.csv"
    zero.write_bytes(b"")
    assert main(["import", str(zero), "-o", str(tmp_path / "x.csv")]) == 2
    said = capsys.readouterr().err.strip()
    assert said.endswith(f"{zero}: the file is empty")


def test_associate_after_compress_reads_the_cleaned_tracks(tmp_path):
    """Operator test 7, D5: a pipeline clean → compress → associate (as Run ▸ pipeline
    saves it with Compress and Associate ticked) associates the cleaned tracks, not the
    compressed ones: the same associate.csv and pairs as clean → associate, with the
    compress tables written beside them."""
    df = simulate.segments_scene(seed=4, n_ships=6)
    paths = _split(df, tmp_path, 2)
    names = {"plain": ("clean", "associate"), "comp": ("clean", "compress", "associate")}
    for key, stages in names.items():
        pipe = Pipeline(tuple((n, STEPS[n].defaults()) for n in stages))
        run_batch(pipe, paths, tmp_path / key, BatchOptions(csv=True, buckets=3, threads=1))
    comp, plain = (
        _rows(tmp_path / "comp" / "associate.csv"),
        _rows(tmp_path / "plain" / "associate.csv"),
    )
    pd.testing.assert_frame_equal(comp, plain)
    assert len(_rows(tmp_path / "comp" / "compress.csv")) < len(comp)
    pairs = [pd.read_csv(tmp_path / k / "associate_pairs.csv", dtype=str) for k in names]
    pd.testing.assert_frame_equal(pairs[0], pairs[1])


def test_csv_output_holds_the_quarantine_too(tmp_path):
    """Operator test 7, D8: with --csv every output folder is one CSV, the quarantine's
    too (before, its lines were only in quarantine/*.parquet): one row per quarantined
    line of every input, with its file, line, reason and text."""
    df = simulate.maneuver_tracks(4, "short", 50.0, seed=3)
    inputs = []
    for k in range(2):
        part = df.iloc[k * len(df) // 2 : (k + 1) * len(df) // 2].astype(str).copy()
        bad = part.iloc[:2].copy()
        bad.loc[:, "lat"] = ["95.0", "x"]
        path = tmp_path / f"in{k}.csv"
        pd.concat([part, bad], ignore_index=True).to_csv(path, index=False)
        inputs.append(path)
    res = run_batch(Pipeline.default(), inputs, tmp_path / "out", BatchOptions(csv=True))
    q = pd.read_csv(tmp_path / "out" / "quarantine.csv", dtype=str)
    assert list(q.columns) == ["file", "line", "reason", "text"]
    assert len(q) == res.report["quarantined"] == 4
    assert set(q["file"]) == {str(p) for p in inputs}
    assert sorted(q["reason"]) == sorted(["lat out of range", "unparsable lat"] * 2)
    parts = pd.read_parquet(tmp_path / "out" / "quarantine")
    assert sorted(q["text"]) == sorted(parts["text"].astype(str))
    assert "quarantine.csv" in res.outputs

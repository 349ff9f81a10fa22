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
    with LocalCluster(n_workers=2, processes=False, dashboard_address=None) as cluster:
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
        ("nocols", "lack column(s)"),
        ("fuse", "step fuse is not supported"),
        ("notpipe", "not a Wakeline pipeline"),
        ("full", "is not empty"),
        ("noargs", "needs PIPELINE.json"),
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
    if setup == "noargs":
        argv = ["batch", str(pipe)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    if setup == "full":
        assert (out / "keep.txt").read_text() == "mine"


def test_gzip_inputs_are_read_whole_without_a_warning(scene):
    """A .gz input is one partition (it cannot be cut into blocks); Dask's warning about
    it on every gzip input is not printed, and the rows are all there."""
    import gzip
    import warnings

    from wakeline.core.batch import _read_dask

    paths, whole = scene
    gz = whole.with_name("all.csv.gz")
    gz.write_bytes(gzip.compress(whole.read_bytes()))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ddf = _read_dask([gz], "csv", 0.1)
        n = len(ddf.compute())
    assert n == len(_rows(whole))


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

"""Operator test 5's batch defects: a folder of mixed files stopped at the first refused
input, one per run (D-batch-2); two inputs sharing track ids with overlapping times were
joined without a word (D-batch-1, D-batch-3)."""

import json
from pathlib import Path

import pytest

pytest.importorskip("dask.dataframe")
pytest.importorskip("distributed")

from wakeline.app.cli import main  # noqa: E402
from wakeline.core.batch import shared_tracks, track_spans  # noqa: E402
from wakeline.core.pipeline import Pipeline  # noqa: E402


def _rows(batch: str, start: int, n: int = 50) -> list[str]:
    return [
        f"{batch},2024-01-01T00:{(start + i) // 60:02d}:{(start + i) % 60:02d}Z,"
        f"{10 + (start + i) * 1e-3:.4f},50.0"
        for i in range(n)
    ]


def test_every_refused_input_is_listed_in_one_run_and_the_rest_processed(tmp_path, capsys):
    folder = tmp_path / "mixed"
    folder.mkdir()
    (folder / "a_good.csv").write_text("mmsi,time,lon,lat\n" + "\n".join(_rows("1", 0)) + "\n")
    # headerless: the importer's advice is a --map, which would apply to every input
    (folder / "b_headerless.csv").write_text("\n".join(_rows("2", 0)) + "\n")
    # metres on a plane without an origin
    (folder / "c_plane.csv").write_text(
        "track,time,east,north\n"
        + "".join(f"3,2024-01-01T00:00:{i:02d}Z,{i},0\n" for i in range(9))
    )
    (folder / "d_good.csv").write_text("mmsi,time,lon,lat\n" + "\n".join(_rows("4", 0)) + "\n")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(folder), "-o", str(out), "--csv"]) == 3
    err = capsys.readouterr().err
    for name in ("b_headerless.csv", "c_plane.csv"):
        line = next(x for x in err.splitlines() if f"{name}: refused: " in x)
        assert "run this file apart with its own" in line
        assert "`wakeline import` it to canonical CSV first" in line
    assert "2 inputs refused (above, each with its reason)" in err
    assert "exit status 3" in err
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 100  # both good files
    assert [d["input"].split("/")[-1] for d in rep["refused_inputs"]] == [
        "b_headerless.csv",
        "c_plane.csv",
    ]
    assert "--origin" in rep["refused_inputs"][1]["reason"]


def test_a_refusal_met_while_reading_is_listed_and_its_rows_left_out(tmp_path, capsys, monkeypatch):
    """A refusal the survey of a file's start cannot see (raised by the importer while
    reading): the file listed, what it wrote removed, the others processed."""
    from wakeline.core import batch
    from wakeline.core.errors import InputError

    good = tmp_path / "good.csv"
    good.write_text("mmsi,time,lon,lat\n" + "\n".join(_rows("1", 0)) + "\n")
    bad = tmp_path / "bad.csv"
    bad.write_text("mmsi,time,lon,lat\n" + "\n".join(_rows("2", 0)) + "\n")
    real = batch._import_file

    def failing(path, file_no, stage, *args):
        if path.endswith("bad.csv"):
            real(path, file_no, stage, *args)  # writes its blocks, then refused
            raise InputError(f"{path}: cannot read the file (damaged further on)")
        return real(path, file_no, stage, *args)

    monkeypatch.setattr(batch, "_import_file", failing)
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(good), str(bad), "-o", str(out), "--csv"]) == 3
    err = capsys.readouterr().err
    assert f"{bad}: refused: cannot read the file (damaged further on)" in err
    rep = json.loads((out / "report.json").read_text())
    assert rep["rows_read"] == 50
    assert rep["steps"]["clean"]["rows_in"] == 50


def test_inputs_sharing_track_ids_with_overlapping_times_are_named_once_per_pair(tmp_path, capsys):
    head = "mmsi,time,lon,lat\n"
    a = tmp_path / "a.csv"
    a.write_text(head + "\n".join(_rows("1", 0) + _rows("2", 0) + _rows("3", 0)) + "\n")
    b = tmp_path / "b.csv"  # the same export again
    b.write_text(head + "\n".join(_rows("1", 0) + _rows("2", 0) + _rows("3", 0)) + "\n")
    c = tmp_path / "c.csv"  # track 1 again, an hour later: not overlapping
    # (before operator test 9 this file's times read 00:60:00: every row was quarantined,
    # silently: D2)
    c.write_text(head + "\n".join(r.replace("T00:", "T01:") for r in _rows("1", 0)) + "\n")
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(a), str(b), str(c), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    said = [x for x in err.splitlines() if "with overlapping times" in x]
    assert said == [
        f"warning: {a} and {b} share 3 track ids with overlapping times: the same export "
        "twice? Read as one stream their rows join into one track each (duplicates); give "
        "each its own sensor (--sensor-per-file, or a sensor column), or run them apart; "
        "every pair in report.json (shared_track_ids)"
    ]
    rep = json.loads((out / "report.json").read_text())
    assert said[0] in rep["warnings"]
    # track 1 of c, an hour later: said apart (operator test 9, D1), not as a duplicate
    later = [x for x in err.splitlines() if "continue in another" in x]
    assert len(later) == 1 and f"{a} and {c} (1); {b} and {c} (1)" in later[0]


def test_shared_tracks_counts_overlaps_only():
    import pandas as pd

    t = pd.to_datetime(["2024-01-01T00:00Z", "2024-01-01T01:00Z", "2024-01-01T02:00Z"])

    def pts(batches, times):
        return pd.DataFrame({"sensor": "S1", "batch": batches, "time": times})

    spans = {
        "x": track_spans(pts(["1", "1", "2"], [t[0], t[1], t[0]])),
        "y": track_spans(pts(["1", "2", "3"], [t[1], t[2], t[0]])),  # 1 touches x's end
        "z": track_spans(pts(["9"], [t[0]])),
    }
    said = shared_tracks(spans)
    assert said[0] == (
        "warning: x and y share 1 track id with overlapping times: the same export twice? "
        "Read as one stream their rows join into one track each (duplicates); give each its "
        "own sensor (--sensor-per-file, or a sensor column), or run them apart; every pair "
        "in report.json (shared_track_ids)"
    )
    # track 2: x's at 00:00, y's at 02:00, not overlapping: said apart (operator test 9)
    assert len(said) == 2 and "1 track id of one input continue in another" in said[1]
    assert "(the longest gap 2.0 h): x and y (1)" in said[1]
    assert shared_tracks({"x": spans["x"]}) == []


def test_sensor_per_file_keeps_two_consoles_apart(tmp_path, capsys):
    # Operator test 6 (h189 D-batch-3): an AIS console and a radar console both number
    # their tracks 1..3 over the same hour; read as one stream, each pair of equal ids
    # became one track. With --sensor-per-file each file is its own sensor (its name).
    head = "mmsi,time,lon,lat\n"
    ais = tmp_path / "ais.csv"
    ais.write_text(head + "\n".join(_rows("1", 0) + _rows("2", 0) + _rows("3", 0)) + "\n")
    radar = tmp_path / "radar.csv.gz"
    import gzip

    radar.write_bytes(
        gzip.compress(
            (head + "\n".join(_rows("1", 5) + _rows("2", 5) + _rows("3", 5)) + "\n").encode()
        )
    )
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "out"
    args = ["batch", str(pipe), str(ais), str(radar), "-o", str(out), "--csv"]
    assert main([*args, "--sensor-per-file"]) == 0
    err = capsys.readouterr().err
    assert not [x for x in err.splitlines() if "share" in x]
    import pandas as pd

    clean = pd.read_csv(out / "clean.csv", dtype=str)
    assert sorted(clean["sensor"].unique()) == ["ais", "radar"]
    assert clean.groupby("sensor")["batch"].nunique().to_dict() == {"ais": 3, "radar": 3}
    # without it: one stream, the same ids joined, and the warning says how to keep them apart
    out2 = tmp_path / "out2"
    assert main([*args[:-3], "-o", str(out2), "--csv"]) == 0
    err = capsys.readouterr().err
    assert [x for x in err.splitlines() if "--sensor-per-file" in x]
    assert set(pd.read_csv(out2 / "clean.csv", dtype=str)["sensor"]) == {"S1"}


def test_file_sensor_names():
    from wakeline.core.batch import file_sensor

    assert file_sensor(Path("a/radar.csv")) == "radar"
    assert file_sensor(Path("ais_day.csv.gz")) == "ais_day"
    assert file_sensor(Path("x.zst")) == "x"

"""export --like writes a course as the file had it where the import changed it and no
step did since (h135; h122's L2: a course of 380.4 came back empty and 360.0 as 0.0)."""

import numpy as np
import pandas as pd
import pytest

from wakeline.core.io import read_points
from wakeline.core.io.export_like import courses_as_read, export_like
from wakeline.core.io.layout import load_layout, preset_layout
from wakeline.core.io.writer import write_points
from wakeline.core.schema import COURSE_READ

TEXT = (
    "track,time,lat,lon,speed,course\n"
    "1,2024-05-01T10:00:00Z,59.1,10.1,5.0,360.0\n"
    "1,2024-05-01T10:00:10Z,59.2,10.2,5.0,380.4\n"
    "1,2024-05-01T10:00:20Z,59.3,10.3,5.0,90.0\n"
    "1,2024-05-01T10:00:30Z,59.4,10.4,5.0,-5.5\n"
    "1,2024-05-01T10:00:40Z,59.5,10.5,5.0,0.0\n"
)


def test_courses_the_import_changed_are_written_as_they_came(tmp_path, capsys):
    from wakeline.app.cli import main

    src = tmp_path / "c.csv"
    src.write_text(TEXT)
    r = read_points(src)
    # the table: 360.0 is north, 380.4 and -5.5 are blanked (counted); the file's values kept
    course = r.points["course"].to_numpy()
    assert course[0] == 0.0 and course[2] == 90.0 and np.isnan(course[[1, 3]]).all()
    assert r.points[COURSE_READ].tolist()[:4:3] == [360.0, -5.5]
    out = tmp_path / "back.csv"
    assert main(["export", str(src), "-o", str(out), "--like", str(src)]) == 0
    assert out.read_text() == TEXT
    assert "3 course(s) written as the file had them" in capsys.readouterr().err


def test_a_course_a_step_changed_is_written_as_the_step_left_it(tmp_path):
    src = tmp_path / "c.csv"
    src.write_text(TEXT)
    pts = read_points(src).points
    course = pts["course"].to_numpy(copy=True)
    course[1] = 20.4  # a step derived the blanked course from the positions
    course[0] = 45.0  # and turned the one read as north
    pts["course"] = course
    made = pts.iloc[[3]].assign(interpolated=True)  # a point Wakeline made, columns copied
    pts = pts.assign(interpolated=False)
    both = pd.concat([pts, made], ignore_index=True)
    assert courses_as_read(both).tolist() == [False, False, False, True, False, False]
    rep = export_like(both, load_layout(src), tmp_path / "out.csv")
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert [line.rsplit(",", 1)[1] for line in lines[1:]] == [
        "45.0",
        "20.4",
        "90.0",
        "-5.5",
        "0.0",
        "",
    ]
    assert rep["courses_as_read"] == 1


def test_the_canonical_csv_carries_the_courses_as_read_presets_the_table_values(tmp_path):
    src = tmp_path / "c.csv"
    src.write_text(TEXT)
    pts = read_points(src).points
    write_points(pts, tmp_path / "canon.csv")
    lines = (tmp_path / "canon.csv").read_text().splitlines()
    assert lines[0].split(",")[-2:] == ["course", COURSE_READ]  # for export --like (h155)
    assert [line.split(",")[-2:] for line in lines[1:]] == [
        ["0", "360"],
        ["", "380.4"],
        ["90", ""],
        ["", "-5.5"],
        ["0", ""],
    ]
    rep = export_like(pts, preset_layout("canonical"), tmp_path / "preset.csv")
    assert rep["courses_as_read"] == 0
    assert COURSE_READ not in (tmp_path / "preset.csv").read_text().splitlines()[0]


def _late_course_file(tmp_path, quoted=False):
    """300 rows; the only course the import changes (380.4) on the last but one."""
    rows = [
        f"{1 + k % 3},2024-05-01T10:{k // 60:02d}:{k % 60:02d}Z,{59 + k * 1e-4:.4f},"
        f"{10 + k * 1e-4:.4f},5.0,{'380.4' if k == 298 else f'{(k * 7) % 360}.5'},n{k}"
        for k in range(300)
    ]
    if quoted:  # quotes in the file's start: read in pieces by the importer
        rows[0] = rows[0].replace(",n0", ',"n,0"')
    src = tmp_path / ("q.csv" if quoted else "late.csv")
    src.write_text("track,time,lat,lon,speed,course,note\n" + "\n".join(rows) + "\n")
    return src


@pytest.mark.parametrize("quoted", [False, True])
def test_import_then_export_like_gives_the_file_back_when_streamed(
    tmp_path, monkeypatch, capsys, quoted
):
    """Operator test h150 (4a): `wakeline import` wrote its canonical CSV without the
    courses as read, so `wakeline export --like` of it wrote ATD's 380.4 (line 72,509)
    empty. The canonical CSV carries them, also when the first changed course comes in a
    later piece of a streamed import (the file is written again with the column): the
    same bytes as the whole read's, and the round trip is byte for byte."""
    from wakeline.app.cli import main
    from wakeline.core.io import import_to_csv, reader

    src = _late_course_file(tmp_path, quoted)
    whole = tmp_path / "whole.csv"
    write_points(read_points(src).points, whole)
    monkeypatch.setattr(reader, "STREAM_BYTES", 1000)  # many pieces
    canon = tmp_path / "canon.csv"
    import_to_csv(src, canon)
    assert canon.read_bytes() == whole.read_bytes()
    assert canon.read_text().splitlines()[0].endswith(",course,note," + COURSE_READ)
    back = tmp_path / "back.csv"
    assert main(["import", str(src), "-o", str(canon)]) == 0
    assert main(["export", str(canon), "-o", str(back), "--like", str(src)]) == 0
    assert back.read_bytes() == src.read_bytes()
    assert "1 course(s) written as the file had them" in capsys.readouterr().err

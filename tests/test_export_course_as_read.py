"""export --like writes a course as the file had it where the import changed it and no
step did since (h135; h122's L2: a course of 380.4 came back empty and 360.0 as 0.0)."""

import numpy as np
import pandas as pd

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


def test_the_canonical_csv_and_presets_hold_the_table_values(tmp_path):
    src = tmp_path / "c.csv"
    src.write_text(TEXT)
    pts = read_points(src).points
    write_points(pts, tmp_path / "canon.csv")
    head = (tmp_path / "canon.csv").read_text().splitlines()[0]
    assert COURSE_READ not in head  # internal: a streamed import could not know it
    rep = export_like(pts, preset_layout("canonical"), tmp_path / "preset.csv")
    assert rep["courses_as_read"] == 0
    assert COURSE_READ not in (tmp_path / "preset.csv").read_text().splitlines()[0]

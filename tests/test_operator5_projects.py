"""Operator test 5 (h181): a project folder moved with its data file, a project renamed
while open (D-proj-1, D-proj-2)."""

import os
import shutil

import pytest

from wakeline.core import simulate
from wakeline.core.errors import ProjectMoved
from wakeline.core.io import write_points
from wakeline.core.project import ProjectWriter, file_hash, load_project, save_project
from wakeline.core.session import Session


def _project_with_source(folder):
    """A project in ``folder`` whose one source file sits beside it."""
    folder.mkdir()
    src = folder / "scene.csv"
    write_points(simulate.demo_scene(), src)
    s = Session()
    s.note_source(str(src.resolve()), file_hash(src))
    lay = s.add_layer("scene.csv", "source", simulate.demo_scene(), {"file": str(src)})
    proj = folder / "day.wakeline"
    save_project(s, proj)
    return proj, lay.id


def test_a_source_beside_a_moved_project_is_used(tmp_path):
    proj, lid = _project_with_source(tmp_path / "A")
    shutil.move(str(tmp_path / "A"), str(tmp_path / "B"))
    moved = tmp_path / "B" / "day.wakeline"
    p = load_project(moved)
    assert p.source_problems() and "missing" in p.source_problems()[0]
    notes = p.locate_sources(moved)
    beside = str((tmp_path / "B" / "scene.csv").resolve())
    assert len(notes) == 1 and "found beside the project" in notes[0] and beside in notes[0]
    assert p.source_problems() == []
    assert p.sources[0].path == beside
    assert p.relocated_layers == [lid]
    assert next(lay for lay in p.layers if lay.id == lid).meta["file"] == beside


def test_a_different_file_beside_the_project_is_not_taken(tmp_path):
    _project_with_source(tmp_path / "A")
    shutil.move(str(tmp_path / "A"), str(tmp_path / "B"))
    (tmp_path / "B" / "scene.csv").write_text("batch,time,lon,lat\n")  # same name, edited
    moved = tmp_path / "B" / "day.wakeline"
    p = load_project(moved)
    assert p.locate_sources(moved) == []
    problems = p.source_problems()
    assert len(problems) == 1 and "missing" in problems[0]


def test_a_rename_in_the_middle_of_a_write_is_reported_as_a_move(tmp_path):
    """SQLite's "attempt to write a readonly database" (the file renamed between the
    check and the write) is reported as the project moved, with Save as."""
    path = tmp_path / "p.wakeline"
    save_project(Session(), path)
    errors = []
    writer = ProjectWriter(path, errors.append)
    writer.submit(lambda st: st.add_decision({"n": 1}))
    assert writer.flush(10) and errors == []

    def rename_then_write(store):
        os.rename(path, tmp_path / "renamed.wakeline")
        store.add_decision({"n": 2})

    writer.submit(rename_then_write)
    assert writer.flush(10)
    writer.close()
    assert len(errors) == 1 and isinstance(errors[0], ProjectMoved)
    assert "Save as" in str(errors[0]) and "readonly" not in str(errors[0])
    assert load_project(tmp_path / "renamed.wakeline").decisions == [{"n": 1}]


def test_the_review_store_refuses_a_write_after_a_rename(tmp_path):
    from wakeline.core.review_store import ReviewStore

    path = tmp_path / "r.wakeline"
    store = ReviewStore(path)
    assert store.decision_count() == 0
    os.rename(path, tmp_path / "renamed.wakeline")
    with pytest.raises(ProjectMoved, match="moved, renamed or removed"):
        store.record(None, None)  # refused before the change is read
    store.close()

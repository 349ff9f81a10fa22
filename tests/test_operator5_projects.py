"""Operator test 5 (h181): a project folder moved with its data file, a project renamed
while open (D-proj-1, D-proj-2)."""

import shutil

from wakeline.core import simulate
from wakeline.core.io import write_points
from wakeline.core.project import file_hash, load_project, save_project
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

"""Run ▸ pipeline with an Associate stage (Run ▸ Pipeline stages): the pipeline makes
the proposals to review, with the panel's Associate parameters; run again, it keeps the
review of the layer it replaces (a rejected pair stays out); Save pipeline writes the
stage (the JSON ``wakeline batch`` reads), Load pipeline sets the stages it holds, and
the project keeps them."""

import pandas as pd
import pytest

pytest.importorskip("pytestqt")

from test_review_rerun_gui import _pairs  # noqa: E402
from test_review_window import _settle, _window  # noqa: E402

from wakeline.core import review as R  # noqa: E402
from wakeline.core import simulate  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.pipeline import STEPS, Pipeline  # noqa: E402
from wakeline.core.review_session import proposals_of  # noqa: E402

pytestmark = pytest.mark.gui


def test_a_pipeline_ending_with_associate_makes_proposals_to_review(qtbot, tmp_path):
    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    lid = w.layer_id(src.name)
    proj = tmp_path / "p.wakeline"
    w.save_project(proj)
    _settle(w)
    acts = w.actions_
    assert acts["pipeline_compress"].isChecked() and not acts["pipeline_associate"].isChecked()
    assert w.pipeline_stages == ("clean", "compress")
    acts["pipeline_associate"].trigger()
    assert w.pipeline_stages == ("clean", "compress", "associate")
    assert "compress, associate" in acts["pipeline"].text()
    acts["pipeline_compress"].trigger()  # Associate on the cleaned tracks, whole
    assert w.pipeline_stages == ("clean", "associate")
    assert acts["pipeline"].text() == "Run &pipeline (clean, associate)"
    w.params.from_dict({"associate": {"max_gap_s": 900.0}})
    w.select_layer(lid)
    acts["pipeline"].trigger()
    _settle(w)
    cleaned = w.session.find(lid, "clean")
    assoc = w.session.find(cleaned.id, "associate")
    assert proposals_of(assoc) is not None
    assert w.active == assoc.id  # the last stage's layer: its proposals under review
    assert w.review.bound is not None and w.review.bound.lid == assoc.id
    assert assoc.params["associate"]["max_gap_s"] == 900.0
    # The same proposals as Run ▸ Associate on the cleaned layer with those parameters.
    alone = w.session.run_step(cleaned.id, "associate", w.step_params("associate"))
    assert alone.tables["proposals"].equals(assoc.tables["proposals"])
    # The proposals are under review: reject one; the pipeline run again keeps it out.
    w.select_layer(assoc.id)
    _settle(w)
    c = w.review.bound.controller
    st = c.state
    rejected = R.pair_key(st.track_a[0], st.track_b[0])
    c.reject(st.proposals["proposal"].iloc[0])
    _settle(w)
    w.select_layer(lid)
    acts["pipeline"].trigger()
    _settle(w)
    assert "1 pair rejected in an earlier review kept out" in w.log.toPlainText()
    again = w.session.find(cleaned.id, "associate")
    assert again.id == assoc.id
    w.select_layer(again.id)
    _settle(w)
    assert rejected not in _pairs(w.review.bound.controller.state)
    # Save pipeline: the stage and its parameters, as `wakeline batch` reads them.
    path = tmp_path / "pipe.json"
    w.save_pipeline(path)
    pipe = Pipeline.from_json(path.read_text(encoding="utf-8"))
    assert [name for name, _ in pipe.stages] == ["clean", "associate"]
    assert pipe.stages[1][1]["associate"].max_gap_s == 900.0
    default = tmp_path / "default.json"
    default.write_text(Pipeline.default().to_json(), encoding="utf-8")
    w.close()

    w2 = _window(qtbot, tmp_path)
    w2.open_project(proj)
    _settle(w2)
    assert w2.pipeline_stages == ("clean", "associate")  # the project keeps them
    assert w2.actions_["pipeline_associate"].isChecked()
    assert not w2.actions_["pipeline_compress"].isChecked()
    assert w2.load_pipeline(default) == []
    assert w2.pipeline_stages == ("clean", "compress")
    assert not w2.actions_["pipeline_associate"].isChecked()
    assert w2.actions_["pipeline"].text() == "Run &pipeline (clean, maneuvers, compress)"
    w2.params.reset()
    assert w2.load_pipeline(path) == []
    assert w2.pipeline_stages == ("clean", "associate")
    assert w2.params.params("associate").max_gap_s == 900.0
    fuse = tmp_path / "fuse.json"
    fuse.write_text(
        Pipeline(
            (("clean", STEPS["clean"].defaults()), ("fuse", STEPS["fuse"].defaults()))
        ).to_json(),
        encoding="utf-8",
    )
    (problem,) = w2.load_pipeline(fuse)
    assert "fuse stage is not run by Run ▸ pipeline" in problem
    assert w2.pipeline_stages == ("clean",)
    assert w2.actions_["pipeline"].text() == "Run &pipeline (clean)"
    w2.close()


def test_pipeline_with_compress_associates_the_cleaned_layer_and_the_export_says_so(
    qtbot, tmp_path
):
    """Operator test 7, D5: Run ▸ pipeline with Compress and Associate ticked associates
    the cleaned layer (compress's layer is made beside it), and the reviewed export's
    log line says how many points it wrote, of which layer; an Associate the operator
    runs on the compressed layer is exported with the cleaned layer's count beside."""
    src = tmp_path / "seg.csv"
    write_points(simulate.segments_scene(seed=2, n_ships=8, area_km=15), src)
    w = _window(qtbot, tmp_path)
    w.load_files([src])
    _settle(w)
    lid = w.layer_id(src.name)
    w.actions_["pipeline_associate"].trigger()
    assert w.pipeline_stages == ("clean", "compress", "associate")
    w.select_layer(lid)
    w.actions_["pipeline"].trigger()
    _settle(w)
    cleaned = w.session.find(lid, "clean")
    comp = w.session.find(cleaned.id, "compress", "compressed")
    assoc = w.session.find(cleaned.id, "associate")
    assert comp is not None and assoc is not None
    assert w.session.find(comp.id, "associate") is None
    assert len(assoc.points) == len(cleaned.points) > len(comp.points)
    alone = w.session.run_step(cleaned.id, "associate", w.step_params("associate"))
    assert alone.tables["proposals"].equals(assoc.tables["proposals"])
    assert w.active == assoc.id and w.review.bound.lid == assoc.id
    out = tmp_path / "reviewed.csv"
    w.review.sync.export(out)
    _settle(w)
    rows = len(pd.read_csv(out))
    assert rows == len(cleaned.points)
    line = [t for t in w.log.toPlainText().splitlines() if t.startswith("exported")][-1]
    assert f"{rows:,} points of seg.csv · cleaned · associated" in line, line
    assert "from the cleaned layer" in line, line
    # Run ▸ Associate on the compressed layer: the export says it is that layer's points.
    w.select_layer(comp.id)
    w.run_step("associate")
    _settle(w)
    on_comp = w.session.find(comp.id, "associate")
    w.select_layer(on_comp.id)
    _settle(w)
    assert w.review.bound.lid == on_comp.id
    out2 = tmp_path / "reviewed2.csv"
    w.review.sync.export(out2)
    _settle(w)
    line = [t for t in w.log.toPlainText().splitlines() if t.startswith("exported")][-1]
    n2 = len(pd.read_csv(out2))
    assert n2 == len(comp.points), (n2, len(comp.points))
    assert f"{n2:,} points of" in line and "from the compressed layer" in line, line
    assert f"the cleaned layer holds {len(cleaned.points):,} points" in line, line
    w.close()

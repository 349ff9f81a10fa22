"""Run ▸ pipeline with an Associate stage (Run ▸ Pipeline stages): the pipeline makes
the proposals to review, with the panel's Associate parameters; run again, it keeps the
review of the layer it replaces (a rejected pair stays out); Save pipeline writes the
stage (the JSON ``wakeline batch`` reads), Load pipeline sets the stages it holds, and
the project keeps them."""

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

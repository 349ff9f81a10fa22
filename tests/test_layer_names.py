"""Layer names stay apart (operator test h122, L6): Maneuvers then Compress on one layer
made two layers "FILE · maneuvers" (steps maneuvers and compress) in the Layers list and
the legend; the second is named by its step."""

from wakeline.core import simulate
from wakeline.core.session import Session


def test_maneuvers_then_compress_name_their_maneuver_layers_apart():
    pts = simulate.demo_scene(seed=3)
    s = Session()
    src = s.add_layer("scene.csv", "source", pts)
    man = s.apply_result(src.id, s.run_step(src.id, "maneuvers"))
    comp = s.apply_result(src.id, s.run_step(src.id, "compress"))
    names = {(lay.step, lay.role): lay.name for lay in [*man, *comp]}
    assert names == {
        ("maneuvers", "maneuvers"): "scene.csv · maneuvers",
        ("compress", "maneuvers"): "scene.csv · maneuvers (compress)",
        ("compress", "compressed"): "scene.csv · compressed",
    }
    # a re-run replaces its layers in place: the names do not grow
    again = s.apply_result(src.id, s.run_step(src.id, "compress"))
    assert [lay.name for lay in again] == [lay.name for lay in comp]
    assert len({lay.name for lay in s.layers.values()}) == len(s.layers)
    # layers of two inputs of one display name are told apart by their parents, unchanged
    twin = s.add_layer("scene.csv", "source", pts.head(400))
    (made,) = [lay for lay in s.apply_result(twin.id, s.run_step(twin.id, "maneuvers"))]
    assert made.name == "scene.csv · maneuvers"


def test_legend_keeps_the_step_that_tells_two_layers_of_one_file_apart(qapp):
    """h122 L9: "Scene-3...cleaned · maneuvers" beside "Scene-3...cleaned · compressed",
    the legend a third of the map. The column is narrower, each label keeps its last
    step whole (the first steps left out before it), and the full name is its tooltip."""
    import pyqtgraph as pg

    from wakeline.app.map_legend import RESERVED_CHARS, SideLegend

    assert RESERVED_CHARS <= 23
    legend = SideLegend()
    base = "scene-3_error_4_radar.csv · cleaned"
    names = [f"{base} · {w}" for w in ("maneuvers", "compressed", "associated")]
    names += [f"{base} · maneuvers (compress)", base, "scene-3_error_4_radar.csv · S1"]
    labels = [legend.fit_label(n) for n in names]
    for name, label in zip(names, labels, strict=True):
        assert label.endswith(name.rsplit(" · ", 1)[1]), (name, label)
        assert legend._metrics.horizontalAdvance(label) <= legend._label_px, label
    assert len(set(labels)) == len(labels)
    # the first step (marked " … ", h158) and the extension left out: the file's name
    # keeps start and end
    assert labels[0].startswith("scen") and labels[0].endswith("adar … maneuvers"), labels[0]
    item = pg.PlotDataItem([0, 1], [0, 1])
    legend.addItem(item, names[0])
    assert legend.items[-1][1].toolTip() == names[0]


def test_legend_labels_of_two_files_name_the_files(qapp):
    """Operator test h150: "Sce…csv · … · maneuvers" and "sa…sv · … · compressed": with
    two files open the legend did not say which file. A shortened label leaves out the
    extension and the first steps (not the file's name; " … " in their place, h158): a
    short file name stays whole, two long ones keep their distinct ends."""
    from wakeline.app.map_legend import SideLegend

    legend = SideLegend()
    assert legend.fit_label("Scene-7.csv · cleaned · maneuvers") == "Scene-7 … maneuvers"
    # h158: the " … " for the left-out step costs "sample_ship" two letters
    assert legend.fit_label("sample_ship.csv · cleaned · compressed") == ("samp…ship … compressed")
    names = [f"scene-6_error_0_{s}.csv · cleaned · maneuvers" for s in ("AIS", "radar")]
    labels = [legend.fit_label(n) for n in names]
    assert labels[0].endswith("AIS … maneuvers") and labels[1].endswith("adar … maneuvers")
    assert all(lb.startswith("scen") for lb in labels), labels
    assert all(legend._metrics.horizontalAdvance(lb) <= legend._label_px for lb in labels)


def test_a_fuse_of_many_layers_is_named_by_the_first_two(qapp):
    """Tester h133 (item 11): fusing 200 layers made a name of 2,205 characters ("f000.csv
    + f001.csv + …") that filled the log line; the first two names and how many more, the
    full list in the lineage and in the Layers list's tooltip."""
    from wakeline.app.window_layers import layer_tip
    from wakeline.core import review as R
    from wakeline.core.pipeline import STEPS
    from wakeline.core.words import joined_names

    pts = simulate.demo_scene(seed=7)
    t = pts["time"]
    pts = pts[t < t.min() + (t.max() - t.min()) / 20]
    ais, radar = (pts[pts["sensor"] == s].assign(sensor="S1") for s in ("AIS", "R1"))
    res = STEPS["fuse"](R.combine_sources([("a", ais), ("r", radar)]))
    s = Session()
    ids = [s.add_layer(f"f{k:03d}.csv", "source", ais if k % 2 else radar).id for k in range(200)]
    (made,) = s.apply_result(ids[0], res, STEPS["fuse"].defaults(), inputs=ids)
    assert made.name == "f000.csv + f001.csv and 198 more · fused"
    assert made.inputs == ids  # every input in the lineage
    tip = layer_tip(s, made)
    assert "Made from 200 layers" in tip and "f199.csv" in tip and "f100.csv" in tip
    # Two or three inputs are named in full, as before.
    assert joined_names(["a", "b", "c"]) == "a + b + c"
    assert joined_names(["a", "b"]) == "a + b"
    (two,) = s.apply_result(ids[0], res, STEPS["fuse"].defaults(), inputs=ids[:2])
    assert two.name == "f000.csv + f001.csv · fused"
    assert layer_tip(s, s.layers[ids[0]]) == ""


def test_a_layer_of_several_files_is_named_readably_in_either_language(qapp):
    """Operator test 10: `render ore_gbk.csv dma_semicolon_comma.csv` named the layer
    "{ore_gbk,dma_semicolon_comma}.csv" ("{ore_gbk,d…mma}.csv" in the legend). Render names
    it as the window names a fuse across layers: the files, or the first two and how many
    more, said in the window's language."""
    from pathlib import Path

    from wakeline.app import i18n
    from wakeline.app.cli_render import input_name
    from wakeline.app.layer_names import shown_name
    from wakeline.app.map_legend import SideLegend

    many = input_name([Path(f"scene_{k}.csv") for k in range(6)])
    assert many == "scene_0.csv + scene_1.csv and 4 more"
    assert shown_name(f"{many} · cleaned") == f"{many} · cleaned"
    legend = SideLegend()
    two = input_name([Path("ore_gbk.csv"), Path("dma_semicolon_comma.csv")])
    shown = legend.shown_label(f"{two} · cleaned")
    assert "ore_gbk" in shown and "dma" in shown and "{" not in shown, shown
    translator = i18n.install(qapp, "zh_CN", None)
    try:
        zh = shown_name(f"{many} · cleaned")
        assert zh.startswith("scene_0.csv + scene_1.csv") and "4" in zh and "more" not in zh, zh
        assert "cleaned" not in zh
    finally:
        i18n.install(qapp, "en", translator)

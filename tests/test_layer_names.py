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

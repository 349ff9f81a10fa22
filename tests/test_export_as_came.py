"""Export ▸ "As it came in" (issue 19): the layout travels with the layer, the project and
the session's lineage (the GUI's action is tested in tests/test_gui.py)."""

import pytest

from tests.conftest import DATA
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.export_like import export_like, layer_layout, layout_meta
from wakeline.core.io.layout import Layout
from wakeline.core.project import load_project, save_project
from wakeline.core.session import Session

RADAR = DATA / "layouts" / "radar_gb18030.csv"


def _session(tmp_path) -> dict:
    """A source layer with its layout (as the import stores it) and a result layer made
    from it, saved to a project and opened again."""
    result = read_points(RADAR)
    meta = {"file": str(tmp_path / "gone.csv"), "layout": layout_meta(RADAR, result.report)}
    merged = result.points.assign(
        target=result.points["batch"].where(result.points["batch"] != "102", "101")
    )
    s = Session()
    src = s.add_layer("radar.csv", "source", result.points, meta)
    s.add_layer("radar.csv · merged", "associated", merged, parent=src.id, step="associate")
    save_project(s, tmp_path / "p.wakeline")
    return {lay.id: lay for lay in load_project(tmp_path / "p.wakeline").layers}


def test_layout_is_kept_in_the_project_and_used_for_a_result_layer(tmp_path):
    layers = _session(tmp_path)
    assert Layout.from_dict(layers["L1"].meta["layout"]).encoding == "gb18030"
    out = tmp_path / "back.csv"
    export_like(layers["L1"].points, layer_layout(layers, "L1"), out)
    assert out.read_bytes() == RADAR.read_bytes()
    out2 = tmp_path / "merged.csv"
    rep = export_like(layers["L2"].points, layer_layout(layers, "L2"), out2)
    assert rep["members"] == str(tmp_path / "merged.members.csv")
    back = read_points(out2)
    assert back.report["encoding"] == "gb18030"
    assert sorted(back.points["batch"].unique()) == ["101", "103"]


def test_layer_without_a_source_file_gives_a_clear_message():
    s = Session()
    s.add_layer("sim", "source", read_points(RADAR).points, {})
    with pytest.raises(InputError, match="no imported file behind this layer"):
        layer_layout(s.layers, "L1")


def test_like_units_round_trip_a_file_read_with_unit_flags(tmp_path, capsys):
    """Review: a file read with --speed-unit m/s (no unit in its header) was exported
    --like itself in knots (its header names none: knots assumed); --speed-unit given to
    export is IN's unit (a second conversion, 18.9 -> 36.7). --like-speed-unit and
    --like-distance-unit say ORIGINAL's: the round trip is byte-identical."""
    from wakeline.app.cli import main

    rows = [
        f"S1,T1,2024-01-01T00:00:{i:02d}Z,{10 + i * 1e-4:.4f},{50 + i * 1e-4:.4f},"
        f"{9.7 + i * 0.1:.1f}"
        for i in range(20)
    ]
    f = tmp_path / "f.csv"
    f.write_text("sensor,batch,time,lon,lat,speed\n" + "\n".join(rows) + "\n")
    canon = tmp_path / "canon.csv"
    assert main(["import", str(f), "--speed-unit", "m/s", "-o", str(canon)]) == 0
    out = tmp_path / "out.csv"
    args = ["export", str(canon), "--like", str(f), "-o", str(out)]
    assert main([*args, "--like-speed-unit", "m/s"]) == 0
    assert out.read_bytes() == f.read_bytes()
    assert main(args) == 0  # without it: knots under "speed"
    assert out.read_text().splitlines()[1].endswith(",18.9")
    # A plane file in km (x/y headers name no unit), read with --distance-unit km.
    xy = tmp_path / "xy.csv"
    lines = [
        f"T1,2024-01-01T00:00:{i:02d}Z,{1.5 + i * 0.25:.2f},{-2.0 + i * 0.5:.2f}" for i in range(20)
    ]
    xy.write_text("track,time,x,y\n" + "\n".join(lines) + "\n")
    plane = ["--origin", "63.4,10.4"]
    assert main(["import", str(xy), *plane, "--distance-unit", "km", "-o", str(canon)]) == 0
    args = ["export", str(canon), "--like", str(xy), *plane, "-o", str(out)]
    assert main([*args, "--like-distance-unit", "km"]) == 0
    assert out.read_bytes() == xy.read_bytes()
    assert main(args) == 0  # without it: metres under x
    assert out.read_text().splitlines()[1] == "T1,2024-01-01T00:00:00Z,1500.00,-2000.00"
    capsys.readouterr()
    # The window's layer: the import's units kept in its layout (layout_meta), written
    # back by "as it came" (before: knots).
    result = read_points(f, speed_unit="m/s")
    meta = layout_meta(f, result.report, speed_unit="m/s")
    export_like(result.points, Layout.from_dict(meta), out)
    assert out.read_bytes() == f.read_bytes()

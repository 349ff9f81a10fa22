"""Operator test 5's D-export-4: `export --like` a file sorted by time (Saronic's
annotator "requires ascending time") wrote the rows track by track. The layout now
learns ORIGINAL's row order from its first rows (``row_order``: time, track or "") and
writes it; ``--sort time|track`` chooses; the summary says which."""

import pandas as pd

from wakeline.app.cli import main
from wakeline.core.io import read_points, write_points
from wakeline.core.io.export_like import export_like
from wakeline.core.io.layout import Layout, describe_layout

#: Two vessels interleaved by time, as an annotator wants them.
BY_TIME = (
    "MMSI,time,lat,lon\n"
    "1,2024-08-02 00:00:00,38.0,23.5\n"
    "2,2024-08-02 00:00:05,37.0,23.4\n"
    "1,2024-08-02 00:00:10,38.001,23.5\n"
    "2,2024-08-02 00:00:15,37.001,23.4\n"
    "1,2024-08-02 00:00:20,38.002,23.5\n"
    "2,2024-08-02 00:00:25,37.002,23.4\n"
)


def _by_track(text: str) -> str:
    head, *rows = text.splitlines()
    return "\n".join([head, *sorted(rows, key=lambda r: r.split(",")[0])]) + "\n"


def test_the_row_order_is_learnt_from_the_original(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text(BY_TIME)
    assert describe_layout(f).row_order == "time"
    f.write_text(_by_track(BY_TIME))
    assert describe_layout(f).row_order == "track"
    f.write_text("\n".join(ln for ln in BY_TIME.splitlines() if not ln.startswith("2,")) + "\n")
    assert describe_layout(f).row_order == ""  # one track: either order
    layout = describe_layout(tmp_path / "t.csv")
    assert Layout.from_dict(layout.to_dict()) == layout  # a layout JSON keeps it
    old = {k: v for k, v in layout.to_dict().items() if k != "row_order"}
    assert Layout.from_dict(old).row_order == ""  # a layout saved before: as given


def test_export_like_a_time_sorted_file_writes_it_back_byte_for_byte(tmp_path, capsys):
    original = tmp_path / "by_time.csv"
    original.write_text(BY_TIME)
    pts = read_points(original).points
    canon = tmp_path / "canon.csv"
    # a step's output: track by track
    write_points(pts.sort_values(["batch", "time"], kind="stable"), canon)
    out = tmp_path / "out.csv"
    assert main(["export", str(canon), "--like", str(original), "-o", str(out)]) == 0
    assert out.read_text() == BY_TIME
    assert f"rows by time (as {original})" in capsys.readouterr().err
    argv = ["export", str(canon), "--like", str(original), "-o", str(out), "--sort", "track"]
    assert main(argv) == 0
    assert out.read_text() == _by_track(BY_TIME)
    assert "rows track by track (--sort track)" in capsys.readouterr().err


def test_a_track_ordered_original_is_written_track_by_track(tmp_path):
    original = tmp_path / "by_track.csv"
    original.write_text(_by_track(BY_TIME))
    pts = read_points(tmp_path / "by_track.csv").points.sort_values("time", kind="stable")
    rep = export_like(pts, describe_layout(original), tmp_path / "out.csv")
    assert rep["row_order"] == "track"
    assert (tmp_path / "out.csv").read_text() == _by_track(BY_TIME)


def test_a_window_layer_keeps_its_file_order(tmp_path):
    """A layer that carries its file's rows is written in them (h155), whatever the
    layout's order: the file's order is the original's."""
    original = tmp_path / "by_time.csv"
    original.write_text(BY_TIME)
    pts = read_points(original).points.reset_index(drop=True)
    layer = pts.assign(wl_row=range(len(pts))).sort_values(["batch", "time"])
    rep = export_like(layer, describe_layout(original), tmp_path / "out.csv")
    assert rep["row_order"] == "file"
    assert (tmp_path / "out.csv").read_text() == BY_TIME
    assert pd.read_csv(tmp_path / "out.csv")["MMSI"].tolist() == [1, 2, 1, 2, 1, 2]

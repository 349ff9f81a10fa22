"""A speed column the importer carries unread (MTAD's ``vel``, a ``sog_kmh`` beside the
mapped speed) on rows that carry none of its values but have a speed (points Wakeline
fused): written from the speed where the header names the unit, else left empty with a
note (h150's defect 5: a fused MTAD layer's "As it came in" wrote ``vel`` empty in all
547 rows, silently)."""

import numpy as np

from tests.conftest import DATA
from wakeline.core.io import read_points
from wakeline.core.io.export_like import export_like
from wakeline.core.io.layout import load_layout

MTAD = DATA / "layouts" / "mtad_scene.csv"


def _fused(points):
    """The table a fusion gives: the same positions and speeds, no extra columns."""
    extras = [c for c in points.columns if c not in ("sensor", "batch", "time", "lon", "lat")]
    keep = [c for c in extras if c in ("speed", "course", "truth")]
    return points[["sensor", "batch", "time", "lon", "lat", *keep]].assign(
        speed=np.round(np.arange(len(points)) * 0.5 + 10.0, 2)
    )


def test_a_speed_column_of_no_known_unit_is_left_empty_with_a_note(tmp_path):
    points = read_points(MTAD).points
    assert "vel" in points.columns and "speed" in points.columns  # vel carried unread
    out = tmp_path / "fused.csv"
    rep = export_like(_fused(points), load_layout(MTAD), out)
    lines = out.read_text(encoding="utf-8-sig").splitlines()
    assert lines[0].split(",")[4] == "vel"
    assert all(line.split(",")[4] == "" for line in lines[1:])
    (note,) = [n for n in rep["notes"] if "'vel'" in n]
    assert f"left empty on {len(points):,} row(s)" in note
    assert "--map speed=vel" in note
    # the file itself: every row has its vel, nothing to say
    back = export_like(points, load_layout(MTAD), tmp_path / "same.csv")
    assert (tmp_path / "same.csv").read_bytes() == MTAD.read_bytes()
    assert not [n for n in back["notes"] if "'vel'" in n]


def test_a_speed_column_whose_header_names_its_unit_is_written_from_the_speed(tmp_path):
    src = tmp_path / "two.csv"
    rows = [
        f"7,2024-05-01T10:00:{k:02d}Z,59.{k:02d},10.{k:02d},{9 + k * 0.5:.1f},{(9 + k * 0.5) * 1.852:.2f}"
        for k in range(6)
    ]
    src.write_text("id,time,lat,lon,speed,sog_kmh\n" + "\n".join(rows) + "\n")
    points = read_points(src).points
    assert "sog_kmh" in points.columns  # carried: speed is the mapped one
    fused = points.drop(columns="sog_kmh")
    fused.loc[fused.index[:3], "speed"] = [20.0, 21.5, np.nan]
    both = points.assign(sog_kmh=points["sog_kmh"].where(points.index >= 3))  # 3 carry it
    both["speed"] = fused["speed"]
    # no row carries it: the mapped speed's style (one decimal); else the column's own
    for table, want in (
        (fused, ["37.0", "39.8", "", "19.4", "20.4", "21.3"]),
        (both, ["37.04", "39.82", "", "19.45", "20.37", "21.30"]),
    ):
        out = tmp_path / "out.csv"
        rep = export_like(table, load_layout(src), out)
        assert [line.split(",")[-1] for line in out.read_text().splitlines()[1:]] == want
        assert not [n for n in rep["notes"] if "sog_kmh" in n]

"""Ship names and types from a vessel table beside the tracks (File ▸ Load ship names,
``wakeline gui --vessels``): the core reader (separator sniffed, the id column by the
track reader's names, bad rows counted) and its join, then the window's Name and Type
columns, the ``name:`` filter and the map's labels."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from wakeline.core.errors import InputError
from wakeline.core.io.vessels import (
    NO_ID,
    REPEATED,
    SHORT_ROW,
    TYPE_COLUMN,
    join_vessels,
    read_vessels,
)

SARONIC = Path("/work/shared/data/real/greece-ais-annotated")


def _points(ids, n=5):
    t = pd.date_range("2024-05-01", periods=n, freq="60s", tz="UTC")
    return pd.concat(
        [
            pd.DataFrame(
                {
                    "sensor": "AIS",
                    "batch": str(b),
                    "time": t,
                    "lon": 10.0 + k + 0.01 * np.arange(n),
                    "lat": 50.0 + 0.01 * np.arange(n),
                }
            )
            for k, b in enumerate(ids)
        ],
        ignore_index=True,
    )


@pytest.mark.skipif(not SARONIC.is_dir(), reason="real data not here")
def test_the_saronic_vessel_info_types_its_five_ships():
    from wakeline.core.io import read_points

    table = read_vessels(SARONIC / "vessel_info.csv")  # ';'-separated, MMSI;TYPE_CODE;TYPE;…
    assert table.id_column == "MMSI" and table.type_column == "TYPE"
    assert table.name_column is None and not table.bad and table.rows == 5
    mapping = {"batch": "col1", "lon": "col2", "lat": "col3", "time": "col4"}
    points = read_points(SARONIC / "vessels.csv", mapping=mapping).points
    joined, join = join_vessels(points, table)
    assert len(joined) == len(points) and "ship_type" not in points.columns  # input untouched
    assert join.matched == join.ids == 5 and not join.unmatched and join.unused == 0
    # SOURCE.md: 1 Tanker (80), 2 High speed craft (40), 3 Passenger (60), 4 and 5 Pleasure
    per_ship = joined.groupby(joined["batch"].astype(str))[TYPE_COLUMN].agg(set)
    assert per_ship.to_dict() == {
        "1": {"Tanker"},
        "2": {"High speed craft"},
        "3": {"Passenger"},
        "4": {"Pleasure Craft"},
        "5": {"Pleasure Craft"},
    }


@pytest.mark.parametrize(
    ("sep", "header"),
    [
        (",", ["批号", "船名", "船型"]),  # the Chinese headers of a track file's id
        ("\t", ["vessel_mmsi", "ship_name", "ship_type"]),  # the id by the reader's patterns
        (";", ["MMSI", "NAME", "TYPE"]),
        ("|", ["id", "vessel_name", "type"]),
    ],
)
def test_a_vessel_table_is_read_by_the_track_readers_id_names_and_every_bad_row_said(
    tmp_path, sep, header
):
    rows = [
        ["244000001", "ARGO", "Cargo"],
        ["244000002", "BLUE STAR", "Passenger"],
        ["", "NO ID", "Tug"],  # no id
        ["244000003", "SHORT"],  # a cell missing
        ["244000002", "BLUE STAR", "Passenger"],  # said again alike: kept once, no fault
        ["244000001", "OTHER", "Cargo"],  # said again otherwise: the first kept, counted
        ["244000004.0", "DELTA", ""],  # a float-written MMSI
    ]
    path = tmp_path / "ships.csv"
    path.write_text("\n".join(sep.join(r) for r in [header, *rows]) + "\n", encoding="utf-8")
    table = read_vessels(path)
    assert table.id_column == header[0] and table.name_column == header[1]
    assert table.type_column == header[2] and table.rows == len(rows)
    assert table.bad == {NO_ID: 1, SHORT_ROW: 1, REPEATED: 1}
    # every row accounted for: kept, or counted, or a repeat alike
    assert len(table.table) + sum(table.bad.values()) + 1 == len(rows)
    for why in (NO_ID, SHORT_ROW, REPEATED):
        assert why in table.report()
    points = _points(["244000001", "244000002", "244000004", "999"])
    joined, join = join_vessels(points, table)
    names = joined.groupby("batch")["name"].first().to_dict()
    assert names == {"244000001": "ARGO", "244000002": "BLUE STAR", "244000004": "DELTA", "999": ""}
    assert joined.groupby("batch")[TYPE_COLUMN].first()["244000002"] == "Passenger"
    assert join.matched == 3 and join.unmatched == ["999"] and "999" in join.report()


def test_a_table_without_an_id_or_without_names_and_types_is_refused(tmp_path):
    no_id = tmp_path / "a.csv"
    no_id.write_text("name,type\nARGO,Cargo\n")
    with pytest.raises(InputError, match="no column names a ship's id"):
        read_vessels(no_id)
    nothing = tmp_path / "b.csv"
    nothing.write_text("mmsi,length\n1,20\n")
    with pytest.raises(InputError, match="no column of ship names or types"):
        read_vessels(nothing)


def test_the_tables_names_fill_the_points_own_and_replace_them_where_it_has_one(tmp_path):
    points = _points(["1", "2"])
    points["name"] = np.where(points["batch"] == "1", "OWN ONE", "OWN TWO")
    path = tmp_path / "v.csv"
    path.write_text("mmsi,name\n1,TABLE ONE\n2,\n")
    joined, _ = join_vessels(points, read_vessels(path))
    assert joined.groupby("batch")["name"].first().to_dict() == {"1": "TABLE ONE", "2": "OWN TWO"}


def test_a_table_of_no_usable_row_joins_no_name_and_does_not_fail(tmp_path):
    """A header and rows of no id only (every row counted, none kept): the join matches
    no track rather than failing on the empty table (h245)."""
    path = tmp_path / "v.csv"
    path.write_text("mmsi,name,type\n,ARGO,Cargo\n")
    table = read_vessels(path)
    assert len(table.table) == 0 and table.bad == {NO_ID: 1}
    joined, join = join_vessels(_points(["1", "2"]), table)
    assert set(joined["name"]) == {""} and set(joined[TYPE_COLUMN]) == {""}
    assert join.ids == 2 and join.matched == 0 and join.unmatched == ["1", "2"]


def test_every_repeat_that_differs_from_the_id_kept_is_counted(tmp_path):
    """An id given three times, the second and third alike but unlike the first (kept):
    both differ from what is used, so both are counted (h245: the third, a repeat of
    the second, was dropped unsaid)."""
    path = tmp_path / "v.csv"
    path.write_text("mmsi,name\n1,ARGO\n1,BETA\n1,BETA\n1,ARGO\n2,GAMMA\n")
    table = read_vessels(path)
    assert table.table.set_index("id")["name"].to_dict() == {"1": "ARGO", "2": "GAMMA"}
    assert table.bad == {REPEATED: 2}  # the last ARGO agrees with the kept one: no fault


# -- the window ------------------------------------------------------------------------


@pytest.mark.gui
def test_the_window_shows_the_names_and_types_in_table_filter_and_labels(qtbot, tmp_path):
    pytest.importorskip("pytestqt")
    from test_review_window import _settle, _window

    from wakeline.core.io import write_points

    path = tmp_path / "ais.csv"
    write_points(_points(["244000001", "244000002", "244000003"], n=30), path)
    vessels = tmp_path / "vessels.csv"
    vessels.write_text("MMSI;SHIPNAME;TYPE\n244000001;ARGO;Cargo\n244000002;BLUE STAR;Passenger\n")
    w = _window(qtbot, tmp_path)
    w.load_files([path])
    _settle(w)
    lid = w.layer_id(path.name)
    w.select_layer(lid)
    _settle(w)
    model = w.batch_model
    cols = [k for k, _ in model.COLUMNS]
    assert not model.has_names and w.batch_view.isColumnHidden(cols.index("name"))
    w.load_vessels(vessels)
    _settle(w)
    assert "name" in w.layers[lid].points.columns  # the layer's points carry them (saved)
    assert model.has_names and model.has_types
    assert not w.batch_view.isColumnHidden(cols.index("name"))
    assert not w.batch_view.isColumnHidden(cols.index("ship_type"))
    rows = {model.key_of_row(r)[1]: r for r in range(model.rowCount())}
    name_col, type_col = cols.index("name"), cols.index("ship_type")
    assert model.index(rows["244000001"], name_col).data() == "ARGO"
    assert model.index(rows["244000002"], type_col).data() == "Passenger"
    assert model.index(rows["244000003"], name_col).data() == ""
    model.set_filter("name:star")
    assert [model.key_of_row(r)[1] for r in range(model.rowCount())] == ["244000002"]
    model.set_filter("type:cargo")
    assert [model.key_of_row(r)[1] for r in range(model.rowCount())] == ["244000001"]
    model.set_filter("")
    w.canvas.fit()
    _settle(w)
    texts = w.update_track_labels()
    assert any("ARGO" in t for t in texts) and any("BLUE STAR" in t for t in texts)
    log = w.log.toPlainText()
    assert "2 vessel(s)" in log and "2 of 3 ship id(s) found in the vessel table" in log
    w.close()


def test_the_name_and_type_columns_are_in_sight_after_batch_at_1400x900(qtbot, tmp_path):
    """Operator test 11, F5: after File ▸ Load ship names the Type column sat at x=1008 px
    of a 389-px batch table (1400 x 900): nothing seemed to change. Name and Type are
    shown right after Batch, in sight; the model keeps its columns (sorting by Type and
    the logical indices unchanged)."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtCore
    from test_review_window import _settle, _window

    from wakeline.core.io import write_points

    path = tmp_path / "ais.csv"
    write_points(_points(["244000001", "244000002", "244000003"], n=30), path)
    vessels = tmp_path / "vessels.csv"
    vessels.write_text("MMSI;TYPE\n244000001;70\n244000002;60\n244000003;30\n")
    w = _window(qtbot, tmp_path)
    w.resize(1400, 900)
    w.load_files([path])
    _settle(w)
    w.select_layer(w.layer_id(path.name))
    _settle(w)
    w.load_vessels(vessels)
    _settle(w)
    model, view = w.batch_model, w.batch_view
    header = view.horizontalHeader()
    cols = [k for k, _ in model.COLUMNS]
    assert model.has_types and not view.isColumnHidden(cols.index("ship_type"))
    batch = header.visualIndex(cols.index("batch"))
    assert header.visualIndex(cols.index("name")) == batch + 1
    assert header.visualIndex(cols.index("ship_type")) == batch + 2
    type_col = cols.index("ship_type")
    right = header.sectionViewportPosition(type_col) + header.sectionSize(type_col)
    assert 0 <= header.sectionViewportPosition(type_col) and right <= view.viewport().width()
    view.sortByColumn(type_col, QtCore.Qt.SortOrder.AscendingOrder)
    got = [model.index(r, type_col).data() for r in range(model.rowCount())]
    assert got == sorted(got) and len(set(got)) == 3
    w.close()


def test_gui_takes_a_vessel_table_on_the_command_line(monkeypatch, tmp_path):
    from wakeline.app import cli

    seen = {}
    monkeypatch.setattr(
        "wakeline.app.main.run",
        lambda files, screenshot=None, read=None, **kw: seen.update(files=files, **kw) or 0,
    )
    table = tmp_path / "v.csv"
    table.write_text("mmsi,name\n1,ARGO\n")
    assert cli.main(["gui", "a.csv", "--vessels", str(table)]) == 0
    assert seen["vessels"] == table
    assert cli.main(["gui", "a.csv", "--vessels", str(tmp_path / "none.csv")]) == 2

"""Operator test h150, defect 2: the Autoferry camera bearings could not be opened as they
ship (no --map, no --origin for an observer in metres, no mapping suggested), and once
reshaped 86 % of the EO bearings were quarantined as "repeated time" (a camera frame holds
several targets). Now the bearing reader takes the track reader's --map and --origin,
knows the Autoferry detections layout (its Piren origin), keeps several bearings at one
time and says where every line went; --tracks gates them on the targets' tracks, which
reaches the data the evaluation reads (real_sets.autoferry_bearings).

tests/data/autoferry_detections_sample.csv and autoferry_truth_sample.csv: rows of the
Autoferry set (CC0, tests/data/NOTICE.md)."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from conftest import DATA, real_file
from wakeline.app.cli import main
from wakeline.core import geo
from wakeline.core.bearing import BearingParams, detect_with_report
from wakeline.core.bearing_read import (
    BEARING_FIELDS,
    NOT_A_BEARING,
    gate_to_tracks,
    read_bearing_file,
    summary_lines,
)
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.formats import parse_mapping

SAMPLE = DATA / "autoferry_detections_sample.csv"
TRUTH = DATA / "autoferry_truth_sample.csv"
PIREN = "63.4389029083,10.39908278"


def test_the_autoferry_sample_opens_as_it_ships_and_every_line_is_accounted_for():
    raw = pd.read_csv(SAMPLE)
    got = read_bearing_file(SAMPLE)  # no flag: the layout and its origin are known
    rep = got.report
    plots = int(raw["bearing_rad"].isna().sum() - raw["k"].isna().sum())
    assert rep["set_aside"] == {
        f"{NOT_A_BEARING} a position plot (meas_north, meas_east)": plots,
        f"{NOT_A_BEARING} an empty scan (no measurement)": int(raw["k"].isna().sum()),
    }
    assert (
        rep["lines"]
        == len(raw)
        == rep["bearings"] + sum(rep["set_aside"].values()) + sum(rep["quarantined"].values())
    )
    assert not any("repeated time" in r for r in rep["quarantined"])
    assert sorted(got.bearings["batch"].unique()) == ["2/eo", "2/ir"]
    # several targets in one frame: kept (before: all but the first quarantined)
    assert rep["several"]["times"] > 0 and rep["several"]["most"] >= 4
    assert "kept, not quarantined" in " ".join(summary_lines(rep))
    # bearing_rad is atan2(east, north): degrees clockwise from north, as the evaluation
    b = raw[raw["bearing_rad"].notna()]
    assert rep["quarantined"] == {} and len(got.bearings) == len(b)
    np.testing.assert_allclose(
        got.bearings["bearing"], np.degrees(b["bearing_rad"].to_numpy()) % 360.0, atol=1e-12
    )
    # the ferry's metres from Piren, projected as the track reader projects them
    lon, lat = geo.from_local(b["own_east"], b["own_north"], 10.39908278, 63.4389029083)
    assert got.bearings["obs_lon"].iloc[0] == pytest.approx(lon[0], abs=1e-12)
    assert got.bearings["obs_lat"].iloc[0] == pytest.approx(lat[0], abs=1e-12)
    # the detector says why it tests none of them, and how to split them
    _, report = detect_with_report(got.bearings)
    assert all(r["tested"] == 0 and "--tracks FILE" in r["too_short"] for r in report)


def test_a_target_column_splits_the_series_and_origin_overrides_the_known_one():
    got = read_bearing_file(SAMPLE, mapping=["target=k"], origin="63.5,10.5")
    assert "2/eo/0" in set(got.bearings["batch"])
    assert got.report["several"]["times"] < read_bearing_file(SAMPLE).report["several"]["times"]
    assert got.report["origin"] == [63.5, 10.5]
    assert abs(got.bearings["obs_lat"].iloc[0] - 63.5) < 0.01


def test_a_plain_file_needs_map_and_origin_and_is_told_so(tmp_path):
    raw = pd.read_csv(SAMPLE).dropna(subset=["bearing_rad"])
    plain = raw.rename(
        columns={"scenario": "run", "time": "stamp", "bearing_rad": "azim_rad", "own_east": "oe"}
    )[["run", "stamp", "azim_rad", "oe", "own_north"]]
    p = tmp_path / "plain.csv"
    plain.to_csv(p, index=False)
    with pytest.raises(InputError) as exc:
        read_bearing_file(p)
    msg = str(exc.value)
    assert "missing required column batch, time, bearing (bearings)" in msg
    assert "--map batch=run --map time=stamp --map bearing=azim_rad" in msg
    mapping = ["batch=run", "time=stamp", "bearing=azim_rad", "obs_east=oe"]
    with pytest.raises(InputError, match="--origin LAT,LON"):  # metres, no origin
        read_bearing_file(p, mapping=mapping)
    got = read_bearing_file(p, mapping=mapping, origin=PIREN)
    known = read_bearing_file(SAMPLE)
    np.testing.assert_allclose(
        np.sort(got.bearings["obs_lon"]), np.sort(known.bearings["obs_lon"]), atol=1e-12
    )
    with pytest.raises(InputError, match="mapped column.*bearing=nope"):
        read_bearing_file(p, mapping=[*mapping, "bearing=nope"], origin=PIREN)
    out = tmp_path / "d.csv"
    args = ["bearing", str(p), "-o", str(out), "--origin", PIREN]
    assert main([*args, *(x for m in mapping for x in ("--map", m))]) == 0
    assert main(["bearing", str(p), "-o", str(out)]) == 2


def test_a_line_repeated_as_is_is_still_quarantined(tmp_path):
    rows = [f"A,2024-01-01T00:00:{k:02d}Z,{10 + k}" for k in range(10)]
    p = tmp_path / "b.csv"
    p.write_text("batch,time,bearing\n" + "\n".join([*rows, rows[3], "A,2024-01-01T00:00:03Z,50"]))
    got = read_bearing_file(p)
    assert got.report["quarantined"] == {"repeated line (same batch, time and bearing)": 1}
    assert len(got.bearings) == 11 and got.report["several"]["times"] == 1


def test_gating_on_the_truth_gives_one_sequence_per_camera_and_boat():
    got = read_bearing_file(SAMPLE)
    truth = read_points(TRUTH, origin=PIREN).points
    gated, rep = gate_to_tracks(got.bearings, truth, 3.0)
    assert set(gated["batch"]) <= {"2/eo/1", "2/eo/2", "2/ir/1", "2/ir/2"}
    assert rep["kept"] == len(gated) and rep["no_track"] > 0
    assert not gated.duplicated(["batch", "time"]).any()
    assert (np.abs(geo.angle_diff(gated["bearing"], gated["track_bearing"])) < 3.0).all()
    # the gate is the evaluation's: the truth bearing from the ferry in the Piren frame
    ref = pd.read_csv(TRUTH).drop_duplicates(["target_id", "time"])
    det = pd.read_csv(SAMPLE)
    det = det[(det["sensor"] == "eo") & det["bearing_rad"].notna()]
    n_ref = 0
    for _, tr in ref.groupby("target_id"):
        d = det[(det["time"] >= tr["time"].min()) & (det["time"] <= tr["time"].max())]
        n = np.interp(d["time"], tr["time"], tr["north"])
        e = np.interp(d["time"], tr["time"], tr["east"])
        true_b = np.degrees(np.arctan2(e - d["own_east"], n - d["own_north"]))
        err = geo.angle_diff(np.degrees(d["bearing_rad"]), true_b)
        seq = d.assign(err=err)[err < 3.0].sort_values("err").drop_duplicates("time")
        n_ref += len(seq)
    assert len(gated[gated["batch"].str.contains("/eo/")]) == pytest.approx(n_ref, abs=2)


_FIELD = st.sampled_from(BEARING_FIELDS)
_COLUMN = st.text(min_size=1, max_size=20).filter(lambda c: c.strip() != "")


@given(field=_FIELD, column=_COLUMN, pad=st.sampled_from(["", " ", "  "]))
def test_mapping_parse_takes_each_bearing_field_and_any_column(field, column, pad):
    assert parse_mapping([f"{pad}{field}{pad}={column}"], BEARING_FIELDS) == {field: column.strip()}


@given(name=st.text(min_size=1, max_size=12).filter(lambda n: "=" not in n and n.strip()))
def test_mapping_parse_refuses_a_field_the_bearing_reader_has_not(name):
    if name.strip() in BEARING_FIELDS:
        return
    with pytest.raises(InputError, match="unknown field"):
        parse_mapping([f"{name}=col"], BEARING_FIELDS)


@given(items=st.lists(st.tuples(_FIELD, _COLUMN.filter(lambda c: "=" not in c)), max_size=6))
def test_mapping_parse_keeps_the_last_of_a_field_given_twice(items):
    got = parse_mapping([f"{f}={c}" for f, c in items], BEARING_FIELDS)
    assert got == {f: c.strip() for f, c in items}


@pytest.mark.real
def test_the_real_autoferry_detections_open_and_gate_to_the_evaluation_data():
    folder = real_file("autoferry-fusion", "detections.csv.gz").parent
    got = read_bearing_file(folder / "detections.csv.gz")
    rep = got.report
    assert rep["lines"] == 72_793 and rep["series"] == 18
    assert (
        rep["bearings"] + sum(rep["set_aside"].values()) + sum(rep["quarantined"].values())
        == 72_793
    )
    assert sum(rep["set_aside"].values()) == 6_030 + 1_533
    assert rep["quarantined"] == {"repeated line (same batch, time and bearing)": 167}
    truth = read_points(folder / "ground_truth.csv.gz", origin=PIREN).points
    eo = got.bearings[got.bearings["batch"].str.endswith("/eo")]
    gated, _ = gate_to_tracks(eo, truth, 3.0)
    from wakeline.core.real_sets import autoferry_bearings

    ref, _ = autoferry_bearings(folder)
    assert gated["batch"].nunique() == ref["batch"].nunique() == 18
    assert abs(len(gated) - len(ref)) <= 0.005 * len(ref)  # 6,131 against 6,140
    fit = BearingParams(windows="fit")
    ours, theirs = detect_with_report(gated, fit)[0], detect_with_report(ref, fit)[0]
    assert abs(len(ours) - len(theirs)) <= 2  # 21 against 20


@pytest.mark.gui
def test_the_open_bearings_dialog_shows_the_layout_and_builds_the_options(qtbot, tmp_path):
    pytest.importorskip("pytestqt")
    from wakeline.app.bearing_dialog import BearingDialog

    dlg = BearingDialog(path=SAMPLE, tracks=[("L1", "truth")])
    qtbot.addWidget(dlg)
    assert "Autoferry" in dlg.layout_label.text()
    assert dlg.mapping()["batch"] == "scenario+sensor"
    assert dlg.mapping_boxes["bearing"].currentText() == "bearing_rad"
    assert list(dlg.mapping_boxes) == list(BEARING_FIELDS)  # made from the reader's fields
    assert dlg.warning_label.text() == "" and dlg.gate() == {}
    box = dlg.mapping_boxes["target"]
    box.setCurrentIndex(box.findText("k"))
    assert "target=k" in dlg.options()["mapping"]
    dlg.tracks_box.setCurrentIndex(1)
    assert dlg.gate() == {"tracks": "L1", "gate_deg": 3.0}
    got = read_bearing_file(SAMPLE, **dlg.options())
    assert "2/eo/0" in set(got.bearings["batch"])
    # a file no name fits: the problem shown, OK off until the columns are chosen
    p = tmp_path / "x.csv"
    pd.DataFrame({"run": ["a", "a"], "stamp": [1.7e9, 1.7e9 + 1], "azim": [10, 11]}).to_csv(
        p, index=False
    )
    dlg.path_edit.setText(str(p))
    ok = dlg.buttons.button(dlg.buttons.StandardButton.Ok)
    assert "missing required column" in dlg.warning_label.text() and not ok.isEnabled()
    for f, c in (("batch", "run"), ("time", "stamp"), ("bearing", "azim")):
        dlg.mapping_boxes[f].setCurrentIndex(dlg.mapping_boxes[f].findText(c))
    assert dlg.warning_label.text() == "" and ok.isEnabled()


@pytest.mark.gui
def test_open_bearings_in_the_window_gated_on_a_truth_layer(qtbot, tmp_path):
    pytest.importorskip("pytestqt")
    from conftest import make_window
    from wakeline.app.main import wait_for_jobs

    w = make_window(qtbot, tmp_path)
    w.load_file(TRUTH, origin=PIREN)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: len(w.session.layers) == 1, timeout=20_000)
    truth_id = next(iter(w.session.layers))
    w.load_bearings(SAMPLE, tracks=truth_id, gate_deg=3.0)
    wait_for_jobs(w)
    qtbot.waitUntil(lambda: len(w.session.layers) == 2, timeout=20_000)
    layer = w.session.layers[w.layer_id(SAMPLE.name)]
    assert set(layer.points["batch"]) <= {"2/eo/1", "2/eo/2", "2/ir/1", "2/ir/2"}
    assert layer.meta["read_options"]["gate_deg"] == 3.0
    log = w.log.toPlainText()
    assert "400 lines:" in log and "gated on 2 track(s) within 3°" in log

"""Export "as it came in" of reviewed and merged results (h122's M3, L8, L12, L1, L2):
ids that would collide are renumbered, merged targets are written in time order whatever
the row order given, one odd cell does not quote its column, the window's decision log
replays with `wakeline review --decisions`, a course of 360 is north."""

import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core import review as R
from wakeline.core.errors import InputError
from wakeline.core.io import read_points, write_csv, write_points
from wakeline.core.io.export_like import export_like
from wakeline.core.io.layout import describe_layout

#: An MTAD two-sensor file: no sensor column, AIS and radar numbered alike.
ORIGINAL = (
    "mmsi,time,lat,lon,vel,cou,batch\n"
    "1-1,0.0,20.0,130.0,10.0,90.0,0\n"
    "1-1,60.0,20.0,130.01,10.0,90.0,0\n"
    "2-1,0.0,21.0,131.0,10.0,90.0,1\n"
    "2-1,60.0,21.0,131.01,10.0,90.0,1\n"
)


def _layout(tmp_path):
    original = tmp_path / "scene_AIS.csv"
    original.write_text(ORIGINAL)
    return original, describe_layout(original, read_points(original).report)


def _fused_reviewed() -> pd.DataFrame:
    """Three targets of a reviewed fuse: AIS:0+radar:0 joined, AIS:1 and radar:1 rejected
    (two targets whose first members are batch 1 of two sensors)."""
    t = pd.to_datetime([0, 60, 120], unit="s", utc=True)
    rows = []
    for batch, members, lat, t0 in (
        ("AIS:0", "AIS:0+radar:0", 20.0, 0),
        ("AIS:1", "AIS:1", 21.0, 10),
        ("radar:1", "radar:1", 21.5, 20),
    ):
        for k in range(3):
            rows.append(
                ("fused", batch, t[k] + pd.Timedelta(seconds=t0), 130 + k / 100, lat, members)
            )
    cols = ["sensor", "batch", "time", "lon", "lat", "members"]
    return pd.DataFrame(rows, columns=cols).assign(speed=np.nan, course=np.nan)


def test_colliding_ids_are_renumbered_and_read_back_as_the_targets(tmp_path, capsys):
    _, layout = _layout(tmp_path)
    pts = _fused_reviewed()
    out = tmp_path / "x.csv"
    rep = export_like(pts, layout, out)
    assert rep["warnings"] == [] and rep["targets"] == 3
    assert "renumbered" in rep["notes"][0] and "sensor column" in rep["notes"][0]
    back = read_points(out).points
    assert back.groupby("batch").size().tolist() == [3, 3, 3]  # three tracks, not two
    side = pd.read_csv(tmp_path / "x.members.csv", dtype=str)
    assert sorted(side["batch"]) == ["1", "1", "2", "3"]
    # Asked to keep the ids: written so, with a warning that names the way out.
    rep = export_like(pts, layout, out, renumber=False)
    assert rep["notes"] == [] and "--renumber" in rep["warnings"][0]
    assert read_points(out).points["batch"].nunique() == 2


def test_cli_renumbers_by_default_and_keeps_ids_when_told(tmp_path, capsys):
    original, _ = _layout(tmp_path)
    reviewed, out = tmp_path / "reviewed.csv", tmp_path / "x.csv"
    write_points(_fused_reviewed(), reviewed)
    assert main(["export", str(reviewed), "-o", str(out), "--like", str(original)]) == 0
    assert "batch ids renumbered 1–3" in capsys.readouterr().err
    assert main(["import", str(out), "-o", str(tmp_path / "y.csv")]) == 0
    assert "in 3 tracks" in capsys.readouterr().err
    argv = ["export", str(reviewed), "-o", str(out), "--like", str(original), "--keep-ids"]
    assert main(argv) == 0
    assert "--renumber" in capsys.readouterr().err
    assert read_points(out).points["batch"].nunique() == 2


def test_unmerged_tracks_of_two_sensors_are_renumbered_too(tmp_path):
    _, layout = _layout(tmp_path)
    pts = _fused_reviewed().drop(columns="members")
    pts["sensor"] = pts["batch"].str.split(":").str[0]
    pts["batch"] = pts["batch"].str.split(":").str[1]
    rep = export_like(pts, layout, tmp_path / "x.csv")
    assert rep["notes"] and rep["targets"] == 3
    assert read_points(tmp_path / "x.csv").points["batch"].nunique() == 3


def _merged_out_of_order() -> pd.DataFrame:
    """Track 5 (later) joined to track 9 (earlier) as target T: the later member's rows
    come first, as a canonical CSV sorted by batch text has them."""
    t = pd.to_datetime(np.arange(4) * 60, unit="s", utc=True)
    late = pd.DataFrame({"batch": "5", "time": t + pd.Timedelta(hours=1), "lat": 20.0})
    early = pd.DataFrame({"batch": "9", "time": t, "lat": 20.0})
    other = pd.DataFrame({"batch": "7", "time": t + pd.Timedelta(minutes=30), "lat": 21.0})
    pts = pd.concat([late, other, early], ignore_index=True)
    pts["target"] = np.where(pts["batch"] == "7", "U", "T")
    return pts.assign(
        sensor="S", lon=130.0 + np.arange(len(pts)) / 1e3, speed=np.nan, course=np.nan
    )


def test_a_merged_target_is_written_in_time_order_whatever_the_row_order(tmp_path):
    _, layout = _layout(tmp_path)
    pts = _merged_out_of_order()
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    export_like(pts, layout, a)
    shuffled = pts.sample(frac=1.0, random_state=3)
    export_like(shuffled.assign(wl_row=np.arange(len(pts))), layout, b)  # a window layer
    assert a.read_bytes() == b.read_bytes()  # the CLI's order and the window's agree
    result = read_points(a)
    assert not any("start their time again" in w for w in result.report["warnings"])
    lines = a.read_text().splitlines()[1:]
    assert [ln.split(",")[-1] for ln in lines] == ["9"] * 8 + ["7"] * 4  # T (starts first), U
    times = [float(ln.split(",")[1]) for ln in lines[:8]]
    assert times == sorted(times)


def test_one_odd_cell_does_not_quote_its_whole_column(tmp_path):
    df = pd.DataFrame({"index": ["1", '"71', "3", "a,b"], "n": [1, 2, 3, 4]})
    out = tmp_path / "t.csv"
    write_csv(df, out)
    assert out.read_text().splitlines() == ["index,n", "1,1", '"""71",2', "3,3", '"a,b",4']
    assert pd.read_csv(out, dtype=str)["index"].tolist() == ["1", '"71', "3", "a,b"]


def _review_scene():
    from wakeline.core.associate import associate_interrupted
    from wakeline.core.simulate import segments_scene

    seg = segments_scene(seed=2, n_ships=8, area_km=15)
    ap, _ = R.association_proposals(associate_interrupted(seg))
    return seg, ap


def test_the_windows_decision_log_replays_to_the_same_targets(tmp_path, capsys):
    seg, ap = _review_scene()
    assert len(ap) >= 4
    pids = ap["proposal"].tolist()
    window = R.ReviewState(R.track_table(seg), ap)
    # What the review dock does: each decision through the undo stack (undo applies the
    # change's inverse, redo the change again), the log exported as the window does.
    done = [window.apply(R.accept(window, pids[0])), window.apply(R.reject(window, pids[1]))]
    window.apply(done.pop().inverse())  # undo reject
    window.apply(R.reject(window, pids[1]))  # redo
    a, b = window.proposals.loc[
        window.proposals["proposal"] == pids[2], ["track_a", "track_b"]
    ].iloc[0]
    window.apply(R.split_track(window, b))
    merged = window.apply(R.merge(window, [a, b]))
    window.apply(merged.inverse())  # undo merge
    window.apply(R.reject(window, pids[3]))
    log = tmp_path / "log.csv"
    from wakeline.core.export_review import export_decision_log

    export_decision_log(window, log)
    replayed = R.apply_decisions(R.ReviewState(R.track_table(seg), ap), pd.read_csv(log, dtype=str))
    assert list(replayed.status) == list(window.status)
    assert replayed.links == window.links
    assert replayed.targets().equals(window.targets())
    # ... and through the CLI
    pts, props = tmp_path / "pts.csv", tmp_path / "props.csv"
    write_points(seg, pts)
    write_csv(ap, props)
    out = tmp_path / "out.csv"
    argv = ["review", str(pts), "-o", str(out), "--proposals", str(props), "--decisions", str(log)]
    assert main(argv) == 0
    got = pd.read_csv(out, dtype=str)
    want = window.label_points(seg)
    assert got["target"].tolist() == want["target"].astype(str).tolist()


def test_a_log_whose_undo_does_not_match_names_its_line():
    seg, ap = _review_scene()
    state = R.ReviewState(R.track_table(seg), ap)
    pid = ap["proposal"].iloc[0]
    log = pd.DataFrame({"action": ["accept", "undo reject"], "proposal": [pid, pid]})
    with pytest.raises(InputError, match="line 3.*'undo reject' but the last decision is accept"):
        R.apply_decisions(state, log)


def test_a_course_of_360_is_north_not_blanked(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text("batch,time,lat,lon,course\n1,0.0,20.0,130.0,360.0\n1,6.0,20.0,130.001,380.4\n")
    result = read_points(f)
    assert result.points["course"].tolist()[0] == 0.0
    assert np.isnan(result.points["course"].tolist()[1])
    assert result.report["values_blanked"] == {"course outside [0, 360)": 1}

"""The goals are checked on real captures in whatever layout their owner exported them:
the same real tracks written in a dozen layouts (``tests/layout_variants.py``) must import
line for line (every line a point or a quarantine row, or a blank line counted) to the
same points, and score the same in ``evaluate maneuver --real`` and ``evaluate associate
--real`` as in their native layout.

Data: the ATD 2025 sample in tests/data (MIT, NOTICE.md); the DMA ship and the Saronic
vessels from ../shared (licence unknown / GPL: written into a temporary folder, skipped
when absent)."""

import layout_variants as lv
import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import DATA, SHARED_REAL
from wakeline.app.cli import main
from wakeline.core.evaluate_association import evaluate_real_association
from wakeline.core.evaluate_real import evaluate_real
from wakeline.core.io import read_points, write_points

ATD = DATA / "atd2025_example_sample.csv"
MANEUVER_COLS = [
    "points",
    "maneuvers",
    "slow_share",
    "ours_kept",
    "ours_dis_e_m",
    "dp_kept",
    "dp_dis_e_m",
    "at_rest_spans",
]
ASSOC_COLS = ["pieces", "true_pairs", "reachable", "p_ca", "p_fa", "f1", "p_ca_reachable"]


def atd_points() -> pd.DataFrame:
    a = pd.read_csv(ATD)
    return pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": a["track_id"].astype(str),
            "time": pd.to_datetime(a["time"], utc=True),
            "lon": a["lon"],
            "lat": a["lat"],
            "speed": a["speed"],
            "course": a["course"],
        }
    )


@pytest.fixture(scope="module")
def atd(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atd_layouts")
    pts = atd_points()
    canonical = folder / "canonical.csv"
    write_points(pts, canonical)
    return pts, canonical, {v.name: v for v in lv.write_variants(pts, folder / "v")}


def _read(v: lv.Variant):
    flags = dict(zip(v.flags[::2], v.flags[1::2], strict=True))
    return read_points(v.path, tz=flags.get("--tz"))


def _lines_below_header(v: lv.Variant) -> int:
    raw = v.path.read_bytes()
    for enc in ("utf-16", "utf-8-sig", "gb18030"):
        try:
            text = raw.decode(enc)
        except UnicodeDecodeError:
            continue
        if enc != "utf-16" or raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
            break
    return len(text.splitlines()) - (0 if v.path.suffix == ".nmea" else 1)


def _same_points(got: pd.DataFrame, want: pd.DataFrame, exact: bool) -> None:
    key = ["batch", "time", "lon", "lat"]
    a = got.assign(batch=got["batch"].astype(str))[key].sort_values(key).reset_index(drop=True)
    b = want[key].sort_values(key).reset_index(drop=True)
    assert a["batch"].tolist() == b["batch"].tolist()
    dt = (a["time"] - b["time"]).dt.total_seconds().abs()
    assert dt.max() < 1e-3
    tol = 1e-8 if exact else 2e-6  # AIS positions: 1/10,000 minute
    assert np.abs(a["lon"] - b["lon"]).max() < tol and np.abs(a["lat"] - b["lat"]).max() < tol


@pytest.mark.parametrize("name", [f.__name__ for f in lv.LAYOUTS])
def test_every_layout_imports_line_for_line_to_the_same_points(atd, name):
    pts, _, variants = atd
    v = next(v for v in variants.values() if v.path.parent.name == name)
    r = _read(v)
    rep = r.report
    assert rep["rows_imported"] == len(pts)
    assert rep["rows_quarantined"] == len(r.quarantine) == v.not_points - rep.get("blank_lines", 0)
    assert rep["rows_imported"] + rep["rows_quarantined"] + rep.get("blank_lines", 0) == (
        _lines_below_header(v)
    )
    # what is said: times kept relative, decimal commas read as decimal points, clock
    # times joined with their dates
    said = ("relative", "decimal comma", "clock times", "degrees and minutes")
    assert not [w for w in rep["warnings"] if not any(k in w for k in said)]
    got = r.points
    if rep.get("time_relative"):  # seconds from the scene's start: the same clock, moved
        got = got.assign(time=got["time"] - got["time"].min() + pts["time"].min())
    _same_points(got, pts, v.exact)


def _maneuver(path, **kw) -> pd.DataFrame:
    return evaluate_real(path, **kw).rows.set_index("method")[MANEUVER_COLS]


def _assoc(path, **kw) -> pd.DataFrame:
    ev = evaluate_real_association(path, methods=("ours, optimal", "ours, greedy"), **kw)
    return ev.table.set_index("method")[ASSOC_COLS]


@pytest.mark.parametrize(
    "name", ["chinese_gb18030_crlf", "bom_extra_shuffled_summary", "nmea_tag_blocks"]
)
def test_evaluations_score_a_layout_as_the_canonical_file(atd, name):
    _, canonical, variants = atd
    v = variants[name]
    tz = dict(zip(v.flags[::2], v.flags[1::2], strict=True)).get("--tz")
    rtol = 1e-3 if v.exact else 3e-3  # AIS rounds positions to 0.2 m: DP keeps 604, not 603
    pd.testing.assert_frame_equal(
        _maneuver(v.path, read={"tz": tz}), _maneuver(canonical), rtol=rtol
    )
    pd.testing.assert_frame_equal(_assoc(v.path, read={"tz": tz}), _assoc(canonical), rtol=rtol)


def test_a_folder_of_several_layouts_scores_as_one_file(atd, tmp_path):
    pts, canonical, _ = atd
    ids = sorted(pts["batch"].unique())
    parts = [lv.marinecadastre, lv.radar, lv.semicolon_comma]
    for k, make in enumerate(parts):
        sub = tmp_path / make.__name__
        sub.mkdir()
        v = make(pts[pts["batch"].isin(ids[k::3])].reset_index(drop=True), sub)
        v.path.rename(tmp_path / f"{make.__name__}.csv")
    seen = []
    got = evaluate_real(tmp_path, reading=lambda f, rep: seen.append((f.name, rep)))
    assert sorted(f for f, _ in seen) == sorted(f"{m.__name__}.csv" for m in parts)
    assert sum(rep["rows_imported"] for _, rep in seen) == len(pts)
    want = _maneuver(canonical)
    pd.testing.assert_frame_equal(got.rows.set_index("method")[MANEUVER_COLS], want, rtol=1e-3)
    assoc = evaluate_real_association(tmp_path, methods=("ours, optimal",))
    assert set(assoc.table["file"]) == {f"{m.__name__}.csv" for m in parts}


def test_rows_of_one_time_score_the_same_in_any_row_order(tmp_path):
    # AIS repeats time stamps (the DMA ship: 68 of them, at another position): the
    # evaluation took them in file order, so a shuffled export scored 27 maneuvers, not 28
    rng = np.random.default_rng(3)
    t = np.repeat(np.arange(0, 4000, 20), 2)[:300]
    heading = np.where(t < 2000, 0.0, 90.0)
    step = 5.0 * 20 / 2
    x = np.cumsum(step * np.sin(np.radians(heading))) + rng.normal(0, 3, len(t))
    y = np.cumsum(step * np.cos(np.radians(heading))) + rng.normal(0, 3, len(t))
    df = pd.DataFrame(
        {
            "batch": "1",
            "time": pd.to_datetime(1.7e9 + t, unit="s", utc=True),
            "lon": 11.8 + x / 60_000,
            "lat": 57.6 + y / 111_000,
        }
    )
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    write_points(df, a)
    write_points(df.sample(frac=1.0, random_state=1), b)
    pd.testing.assert_frame_equal(_maneuver(a), _maneuver(b))


def test_rows_in_random_order_are_not_taken_for_mistyped_dates(tmp_path):
    # 5 vessels over 9 days, rows shuffled: each row's neighbours in the file are anywhere
    # in its track's span, and the lone-time rule quarantined 181 of 18,834 Saronic rows
    rng = np.random.default_rng(0)
    rows = []
    for b in range(5):
        t = np.sort(rng.uniform(0, 9 * 86400, 600)) + 1.72e9
        # positions with decimals a receiver writes (a 0.01° grid is warned about since h183)
        lon = 23.5 + b * 0.01 + rng.normal(0, 1e-4, 600)
        rows.append(pd.DataFrame({"batch": str(b), "t": t, "lon": lon, "lat": 37.8 + 1e-5 * b}))
    df = pd.concat(rows).sample(frac=1.0, random_state=2)
    p = tmp_path / "shuffled.csv"
    df.to_csv(p, index=False)
    r = read_points(p)
    assert r.report["rows_quarantined"] == 0 and len(r.points) == 3000
    assert r.report["restarting_tracks"] == {} and not r.report["warnings"]
    # the rule still sees a mistyped date in a track written in time order
    s = df.sort_values(["batch", "t"]).reset_index(drop=True)
    s.loc[100, "t"] += 3 * 365 * 86400
    s.to_csv(p, index=False)
    assert read_points(p).report["rows_quarantined"] == 1


def test_short_tracks_in_random_order_are_not_restarting(tmp_path):
    # the Øresund encounters shuffled: 32-point tracks of 15 min, a few steps back by
    # 10 min among many shorter ones; not "several passes under one id"
    rng = np.random.default_rng(5)
    rows = [
        pd.DataFrame(
            {"batch": str(b), "t": 1.7e9 + b * 86400 + np.arange(32) * 28.0, "lon": 12.6, "lat": 56}
        )
        for b in range(20)
    ]
    df = pd.concat(rows).iloc[rng.permutation(640)]
    p = tmp_path / "encounters.csv"
    df.to_csv(p, index=False)
    rep = read_points(p).report
    assert rep["restarting_tracks"] == {} and rep["rows_quarantined"] == 0


def test_a_target_column_is_the_track(tmp_path):
    p = tmp_path / "relative.csv"
    p.write_text("target,t,lon,lat\nA,0,1,2\nB,0,1.1,2\nA,10,1.001,2\nB,10,1.1,2.001\n")
    r = read_points(p)
    assert r.report["columns"]["batch"] == "target" and r.points["batch"].nunique() == 2
    # a file's own id column wins over it
    p.write_text("mmsi,target,time,lon,lat\n1,A,0,1,2\n")
    assert read_points(p).report["columns"]["batch"] == "mmsi"


def test_evaluate_says_what_reading_each_file_gave(atd, capsys):
    _, _, variants = atd
    v = variants["bom_extra_shuffled_summary"]
    assert main(["evaluate", "maneuver", "--real", str(v.path)]) == 0
    err = capsys.readouterr().err
    assert f"{v.path}: read 1,590 rows in 42 tracks (generic, utf-8); 1 quarantined" in err
    assert "1 blank line skipped" in err and "batch=Vessel ID" in err
    assert "1 row quarantined on reading (1 missing batch)" in err
    # no batch column found: the evaluation says so (the whole file would be one track)
    one = v.path.with_name("no_id.csv")
    one.write_text("time,lon,lat\n2024-01-01T00:00:00Z,1,2\n2024-01-01T00:01:00Z,1.001,2\n")
    assert main(["evaluate", "associate", "--real", str(one)]) == 0
    assert "warning: no batch column" in capsys.readouterr().err


def test_import_says_blank_lines_so_the_counts_add_up(atd, tmp_path, capsys):
    _, _, variants = atd
    v = variants["bom_extra_shuffled_summary"]
    assert main(["import", str(v.path), "-o", str(tmp_path / "o.csv")]) == 0
    assert "1,590 rows in 42 tracks (generic, utf-8); 1 quarantined, 1 blank line skipped" in (
        capsys.readouterr().err
    )


@settings(max_examples=25, deadline=None)
@given(
    n_tracks=st.integers(1, 6),
    n_rows=st.integers(3, 60),
    span_days=st.floats(0.01, 30.0),
    seed=st.integers(0, 10_000),
)
def test_property_row_order_changes_no_point_and_no_quarantine(
    tmp_path_factory, n_tracks, n_rows, span_days, seed
):
    rng = np.random.default_rng(seed)
    frames = [
        pd.DataFrame(
            {
                "batch": str(b),
                # sampled along the span, steps within a factor 3 of each other (a track's
                # lone row days away is the mistyped-date rule's business, not this test's)
                "time": np.cumsum(rng.uniform(0.5, 1.5, n_rows) * span_days * 86400 / n_rows).round(
                    3
                )
                + 1.7e9,
                "lon": rng.uniform(10, 11, n_rows),
                "lat": rng.uniform(55, 56, n_rows),
            }
        )
        for b in range(n_tracks)
    ]
    df = pd.concat(frames, ignore_index=True)
    folder = tmp_path_factory.mktemp("order")
    got = []
    for k, frame in enumerate((df, df.iloc[rng.permutation(len(df))], df.iloc[::-1])):
        p = folder / f"{k}.csv"
        frame.to_csv(p, index=False)
        r = read_points(p)
        assert r.report["rows_quarantined"] == 0
        key = ["batch", "time", "lon", "lat"]
        got.append(r.points[key].sort_values(key).reset_index(drop=True))
    pd.testing.assert_frame_equal(got[0], got[1])
    pd.testing.assert_frame_equal(got[0], got[2])


def _shared(*parts):
    path = SHARED_REAL.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"real data not available: {path}")
    return path


def test_the_dma_ship_shuffled_scores_as_its_native_folder(tmp_path):
    from wakeline.core import real_sets

    folder = _shared("dma-single-ship")
    pts = real_sets.read_dma(folder)
    v = lv.messy(pts, tmp_path)
    pd.testing.assert_frame_equal(_maneuver(v.path), _maneuver(folder), rtol=1e-3)


def test_the_saronic_vessels_shuffled_import_whole(tmp_path):
    from wakeline.core import real_sets

    pts = real_sets.read_greece(_shared("greece-ais-annotated"))
    v = lv.messy(pts, tmp_path)
    r = read_points(v.path)
    assert r.report["rows_imported"] == len(pts) == 18_834
    assert r.report["rows_quarantined"] == 1  # the summary line


@pytest.mark.parametrize("name", ["date_and_clock_columns", "twelve_hour_clock"])
def test_import_writes_dates_and_clock_times_or_12_hour_times_as_instants(atd, tmp_path, name):
    # both quarantined every row before (h111): 'unparsable time'
    pts, _, variants = atd
    out = tmp_path / "o.csv"
    assert main(["import", str(variants[name].path), "-o", str(out)]) == 0
    got = pd.read_csv(out, dtype={"batch": str})
    assert len(got) == len(pts)
    want = pts["time"].sort_values().reset_index(drop=True)
    times = pd.to_datetime(got["time"], utc=True).sort_values().reset_index(drop=True)
    assert (times == want).all()


def test_a_date_column_alone_is_the_time_and_beside_clock_times_their_date(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("Date,MMSI,Lat,Lon\n2023-03-01 00:01:46,1,57.1,11.2\n")
    assert read_points(p).report["columns"]["time"] == "Date"
    p.write_bytes(
        "日期,时间,批号,经度,纬度\r\n2023-03-01,08:01:46,1,11.2,57.1\r\n".encode("gb18030")
    )
    r = read_points(p, tz="Asia/Shanghai")
    assert r.report["time_date_column"] == "日期"
    assert r.points["time"].iloc[0] == pd.Timestamp("2023-03-01T00:01:46Z")
    # a time column of whole instants keeps them, a date column beside it notwithstanding
    p.write_text("Date,Time,MMSI,Lat,Lon\n2023-03-01,2023-03-02T00:01:46Z,1,57.1,11.2\n")
    r = read_points(p)
    assert r.report["time_date_column"] is None
    assert r.points["time"].iloc[0] == pd.Timestamp("2023-03-02T00:01:46Z")


def test_a_folder_of_tsv_txt_and_nmea_files_with_a_readme_is_scored(atd, tmp_path, capsys):
    # a folder as an owner hands it over: the tracks as .txt / .nmea (only .csv was read)
    # and a notes file that holds no track (skipped with the reason, not the end of it)
    pts, _, _ = atd
    ids = sorted(pts["batch"].unique())
    half = pts[pts["batch"].isin(ids[::2])].reset_index(drop=True)
    (tmp_path / "a").mkdir()
    lv.utf16_tab(half, tmp_path / "a").path.rename(tmp_path / "tracks.txt")
    lv.nmea(pts[~pts["batch"].isin(ids[::2])].reset_index(drop=True), tmp_path / "a")
    (tmp_path / "a" / "ais.nmea").rename(tmp_path / "ais.nmea")
    (tmp_path / "README.txt").write_text("Exported by the harbour office.\nAsk Per.\n")
    ev = evaluate_real(tmp_path)
    assert ev.rows.set_index("method").loc["ours", "points"] == len(pts)
    assert [f for f, _ in ev.skipped] == ["README.txt"]
    assert "skipped README.txt: " in ev.format()
    assoc = evaluate_real_association(tmp_path, methods=("ours, optimal",))
    assert set(assoc.table["file"]) == {"ais.nmea", "tracks.txt"}
    assert [f for f, _ in assoc.skipped] == ["README.txt"]


@pytest.mark.parametrize("kind", ["maneuver", "associate"])
def test_evaluate_on_a_file_of_no_usable_row_fails_and_says_why(tmp_path, capsys, kind):
    # before h111: exit 0 and a table of 0 points (associate: P_CA 1.000 over nothing)
    p = tmp_path / "clock_only.csv"
    p.write_text("mmsi,time,lat,lon\n1,08h01,57.1,11.2\n1,08h02,57.2,11.2\n")
    assert main(["evaluate", kind, "--real", str(p)]) == 2
    err = capsys.readouterr().err
    assert "all 2 rows were quarantined" in err and "unparsable time" in err


def test_positions_in_degrees_and_minutes_are_read(tmp_path):
    # every row was quarantined 'unparsable lon' before h111
    p = tmp_path / "dm.csv"
    p.write_text(
        "mmsi,time,lat,lon\n"
        "1,2023-03-01T00:00:00Z,57°40.026'N,11°48.270'E\n"
        "1,2023-03-01T00:01:00Z,S 33 52 18,W 70 30.0\n"
        "1,2023-03-01T00:02:00Z,57°70'N,11°48.270'E\n"
    )
    r = read_points(p)
    assert r.points["lat"].round(6).tolist() == [57.6671, -33.871667]
    assert r.points["lon"].round(6).tolist() == [11.8045, -70.5]
    assert r.quarantine["reason"].tolist() == ["unparsable lat"]  # 70 minutes
    assert "5 positions were written in degrees and minutes" in r.report["warnings"][0]


def test_dates_that_read_either_way_are_said(tmp_path, capsys):
    # a US export of 1 March (03/01/2023) is read as 3 January: no date tells; now it says
    p = tmp_path / "d.csv"
    head = "mmsi,time,lat,lon\n"

    def warned(*dates: str) -> list[str]:
        p.write_text(head + "".join(f"1,{d} 08:00:0{k},57.1,11.{k}\n" for k, d in enumerate(dates)))
        return [w for w in read_points(p).report["warnings"] if "read day first" in w]

    assert "2 could be mm/dd/yyyy" in warned("03/01/2023", "03/01/2023")[0]
    assert warned("13/01/2023", "03/01/2023") == []  # a day above 12 shows the order
    assert warned("01/01/2023", "02/02/2023") == []  # day = month: the same either way
    assert warned("03.01.2023", "03.01.2023") == []  # dotted dates are European
    out = tmp_path / "o.csv"
    p.write_text(head + "1,03/01/2023 08:00:00,57.1,11.1\n")
    assert main(["import", str(p), "-o", str(out)]) == 0  # the streamed read says it too
    assert "read day first (dd/mm/yyyy)" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["date_and_clock", "degrees_minutes", "twelve_hour"])
def test_export_like_writes_dates_and_clocks_or_degrees_and_minutes_back(atd, tmp_path, name):
    # read, export --like the file itself, read again: the same points, the same bytes
    # (before: the Date,Time and 12-hour layouts stopped export --like; degrees and
    # minutes were written as decimal degrees)
    _, _, variants = atd
    v = next(v for v in variants.values() if v.path.parent.name == name)
    out = tmp_path / f"back{v.path.suffix}"
    assert main(["export", str(v.path), "-o", str(out), "--like", str(v.path)]) == 0
    first, again = read_points(v.path), read_points(out)
    assert len(again.quarantine) == len(first.quarantine) == 0
    for col in ("batch", "time", "lon", "lat"):
        assert again.points[col].astype(str).tolist() == first.points[col].astype(str).tolist()
    assert out.read_bytes() == v.path.read_bytes()

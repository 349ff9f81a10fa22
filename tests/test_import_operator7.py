"""Operator test 7's import defects (h204): a GBK file behind a UTF-8 byte order mark (D1),
swapped lat/lon columns (D2), backward time steps within a track (D3, the import's
warning), a last line cut inside its last cell (D7), Chinese course headers (D13), and
the batch-column hint (D14). Each input line is a point or a quarantine row."""

import codecs
import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wakeline.app.cli import main
from wakeline.core.io import import_to_csv, read_points
from wakeline.core.io.formats import known_fields

ZH_HEADER = "批号,时间,经度,纬度,航速(节),航迹向"


def _zh_rows(n: int = 40, batches: int = 2) -> list[str]:
    out = []
    for b in range(batches):
        for i in range(n):
            out.append(
                f"{b + 1},2024-01-01 00:{i // 6:02d}:{i % 6 * 10:02d},"
                f"{120.1 + 0.0005 * i + b:.5f},{30.1 + 0.0003 * i:.5f},12.3,{45.5 + i:.1f}"
            )
    return out


def _bom_gbk(tmp: Path, name: str = "bomgbk.csv", newline: str = "\r\n") -> Path:
    path = tmp / name
    text = newline.join([ZH_HEADER, *_zh_rows()]) + newline
    path.write_bytes(codecs.BOM_UTF8 + text.encode("gbk"))
    return path


def _every_line_counted(report: dict, lines: int) -> None:
    assert 1 + report["rows_imported"] + report["rows_quarantined"] + report["blank_lines"] == lines


# --- D1: a UTF-8 byte order mark before GBK text -------------------------------------


@pytest.mark.parametrize("encoding", [None, "gbk", "gb18030"])
def test_gbk_after_a_utf8_bom_is_read_and_said(tmp_path, encoding):
    """It was refused with "missing required column … headers found: ï»¿ÅúºÅ" (no flag)
    or "cannot decode the text as gbk" (--encoding gbk/gb18030)."""
    path = _bom_gbk(tmp_path)
    res = read_points(path, encoding=encoding)
    assert len(res.points) == 80 and res.report["rows_quarantined"] == 0
    assert res.report["columns"]["batch"] == "批号"
    assert res.report["encoding"] == (encoding or "gb18030")
    assert any("UTF-8 byte order mark" in w and "dropped" in w for w in res.report["warnings"])
    assert res.report["columns"].get("course") == "航迹向"  # D13 as well
    out = tmp_path / "o.csv"
    streamed = import_to_csv(path, out, encoding=encoding)
    assert streamed.report["rows_imported"] == 80
    _every_line_counted(streamed.report, 81)


def test_utf8_sig_on_gbk_after_a_bom_names_the_mark(tmp_path, capsys):
    path = _bom_gbk(tmp_path)
    code = main(["import", str(path), "-o", str(tmp_path / "o.csv"), "--encoding", "utf-8-sig"])
    assert code == 2
    assert "a UTF-8 byte order mark followed by text that is not UTF-8" in capsys.readouterr().err


def test_a_utf8_file_with_a_bom_says_nothing_of_it(tmp_path):
    path = tmp_path / "u.csv"
    path.write_bytes(codecs.BOM_UTF8 + ("\n".join([ZH_HEADER, *_zh_rows()]) + "\n").encode())
    res = read_points(path)
    assert res.report["encoding"] == "utf-8" and len(res.points) == 80
    assert not any("byte order mark" in w for w in res.report["warnings"])


def test_batch_refuses_a_data_file_whose_header_reads_garbled(tmp_path, capsys):
    """batch skipped a GBK file whose header read as Latin-1 mojibake as "not track data"
    and exited 0 with its rows lost; now it is refused (exit 3) and named as an encoding
    problem, while a README is still skipped."""
    from wakeline.core.pipeline import Pipeline

    good = tmp_path / "good.csv"
    good.write_text(
        "sensor,batch,time,lon,lat\n"
        + "\n".join(f"S1,T1,2024-01-01T00:00:{i:02d}Z,{10 + i * 1e-3:.4f},50" for i in range(30))
        + "\n"
    )
    gbk = tmp_path / "gbk.csv"
    gbk.write_bytes(("\n".join([ZH_HEADER, *_zh_rows()]) + "\n").encode("gbk"))
    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json())
    out = tmp_path / "o"
    args = ["batch", str(pipe), str(good), str(gbk), "-o", str(out), "--encoding", "cp1252"]
    assert main(args) == 3  # written, an input left out (2 before h236: nothing written too)
    err = capsys.readouterr().err
    assert f"{gbk}: refused: " in err and "wrong encoding" in err
    rep = json.loads((out / "report.json").read_text())
    assert [d["input"] for d in rep["refused_inputs"]] == [str(gbk)]
    assert rep["skipped_inputs"] == []
    # the same file behind a BOM, no flag: read (it was skipped, exit 0, 80 rows lost)
    out2 = tmp_path / "o2"
    bom = _bom_gbk(tmp_path)
    assert main(["batch", str(pipe), str(good), str(bom), "-o", str(out2)]) == 0
    assert json.loads((out2 / "report.json").read_text())["rows_read"] == 30 + 80
    capsys.readouterr()


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(1, 30),
    newline=st.sampled_from(["\n", "\r\n"]),
    encoding=st.sampled_from([None, "gbk", "gb18030"]),
)
def test_bom_gbk_every_line_a_point(n, newline, encoding):
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "f.csv"
        text = newline.join([ZH_HEADER, *_zh_rows(n, 1)]) + newline
        path.write_bytes(codecs.BOM_UTF8 + text.encode("gbk"))
        res = read_points(path, encoding=encoding)
        assert len(res.points) == n
        _every_line_counted(res.report, n + 1)


# --- D13: Chinese course headers ----------------------------------------------------------


@pytest.mark.parametrize("header", ["航迹向", "航迹向(度)", "航迹向（度）", "航向角", "航向角(°)"])
def test_chinese_course_headers_are_course(header):
    assert known_fields([header]) == {"course"}


def test_track_number_headers_stay_batch():
    assert known_fields(["航迹号"]) == {"batch"} and known_fields(["航迹批号"]) == {"batch"}


def test_a_console_file_with_a_course_in_track_direction_reads_it(tmp_path):
    path = tmp_path / "zh.csv"
    path.write_text("\n".join([ZH_HEADER.replace("航迹向", "航迹向(度)"), *_zh_rows()]) + "\n")
    res = read_points(path)
    assert res.points["course"].notna().all()
    assert res.report["extra_columns"] == []
    assert res.points["course"].iloc[0] == pytest.approx(45.5)


# --- D14: the batch-column hint prefers ids that persist over time -----------------------


def _scans(n_scans: int = 40, fixed: bool = False) -> str:
    """A detections-like file without a batch column: per time a scan number (a counter),
    ``k`` the index of the detection within its scan (0..m-1, m varying unless
    ``fixed``) and ``seen_obj`` the id of what was seen (persists over the scans)."""
    lines = ["scan,time,k,seen_obj,lon,lat"]
    for s in range(n_scans):
        seen = [101, 102, 103] if fixed else [101, 102, 103][: 1 + s % 3]
        for k, tgt in enumerate(seen):
            lines.append(
                f"{s},2024-01-01T00:{s // 60:02d}:{s % 60:02d}Z,{k},{tgt},"
                f"{10 + 0.001 * s + 0.1 * k:.5f},{60 + 0.0005 * s:.5f}"
            )
    return "\n".join(lines) + "\n"


def _hint(report: dict) -> str:
    return next((w for w in report["warnings"] if w.startswith("no batch column")), "")


def test_the_batch_hint_names_the_persisting_id_not_a_counter_nor_a_per_scan_index(tmp_path):
    """The Autoferry raw file's hint offered 'scan' (480 distinct values) and 'k'; 'scan'
    is a message counter and 'k' the index within a scan."""
    path = tmp_path / "det.csv"
    path.write_text(_scans())
    hint = _hint(read_points(path).report)
    assert "--map batch=seen_obj" in hint
    assert "batch=scan" not in hint and "batch=k" not in hint


def test_a_fixed_set_of_small_ids_seen_at_every_time_is_still_offered(tmp_path):
    """Ids 0..2 at every time (a simulation's fixed targets) look like an index too, but
    their number never varies: no evidence against them, still offered."""
    path = tmp_path / "sim.csv"
    path.write_text(_scans(fixed=True))
    hint = _hint(read_points(path).report)
    assert "batch=k" in hint and "batch=scan" not in hint


def _scan_rows(ids_at, n_scans: int = 60) -> str:
    """Radar-like rows without a batch column: at scan ``s`` the tracks ``ids_at(s)``."""
    rows = [
        f"{k},2024-01-01 00:{s // 6:02d}:{s % 6 * 10:02d},"
        f"{10 + 0.001 * s + 0.1 * k:.5f},{55 + 0.0005 * s:.5f}"
        for s in range(n_scans)
        for k in ids_at(s)
    ]
    return "obj,time,lon,lat\n" + "\n".join(rows) + "\n"


def _candidates(tmp: Path, text: str) -> list[str]:
    from wakeline.core.io.reader import id_candidates
    from wakeline.core.io.sniff import sniff

    path = tmp / "scans.csv"
    path.write_text(text)
    found = id_candidates(sniff(path), {"time": "time", "lon": "lon", "lat": "lat"})
    return [name for name, *_ in found]


def test_the_batch_hint_offers_track_numbers_that_grow_over_time(tmp_path):
    """Review h209: radar track numbers 1..m with a new track now and then (none ending
    in the sample) looked like 'an index within each time' and were left out."""
    text = _scan_rows(lambda s: range(1, min(2 + s // 4, 8) + 1))
    assert _candidates(tmp_path, text) == ["obj"]


@pytest.mark.parametrize("missed", [[17], [17, 40]])
def test_the_batch_hint_offers_fixed_track_numbers_with_a_missed_detection(tmp_path, missed):
    """Review h209: five tracks 1..5 over 60 scans, track 5 missed in one scan (its
    values 1..4: 'index-like', m varying) were left out."""
    text = _scan_rows(lambda s: [k for k in range(1, 6) if not (k == 5 and s in missed)])
    assert _candidates(tmp_path, text) == ["obj"]


def test_index_like_ids_that_recur_are_offered_after_the_others(tmp_path):
    """Not sure (each time's values 1..m, m varying, but seen again at the next time): a
    column named as a track id is offered, after a column of ids with no such doubt."""
    lines = ["track,time,tag,lon,lat"]
    for s in range(60):
        for k in range(1, min(2 + s // 4, 8) + 1):
            lines.append(
                f"{k},2024-01-01 00:{s // 6:02d}:{s % 6 * 10:02d},V{k + 10},"
                f"{10 + 0.001 * s + 0.1 * k:.5f},{55 + 0.0005 * s:.5f}"
            )
    assert _candidates(tmp_path, "\n".join(lines) + "\n") == ["tag", "track"]


# --- D7: a last line cut inside its last cell ---------------------------------------------


def _fixed_rows(n: int, places: int = 5, last_col: str = "lon") -> list[str]:
    out = []
    for i in range(n):
        lon, lat = 25.1 + 0.00123 * i, 37.3 + 0.00071 * i
        a, b = (lat, lon) if last_col == "lon" else (lon, lat)
        out.append(f"7,2024-08-09T19:{i // 60:02d}:{i % 60:02d},{a:.{places}f},{b:.{places}f}")
    return out


def _header(last_col: str = "lon") -> str:
    return "MMSI,BaseDateTime,LAT,LON" if last_col == "lon" else "MMSI,BaseDateTime,LON,LAT"


def _read(path: Path, how: str, tmp: Path):
    if how == "whole":
        return read_points(path)
    return import_to_csv(path, tmp / "o.csv")


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_a_last_value_with_fewer_decimals_and_no_line_end_is_quarantined(tmp_path, how):
    """f6_cut_in_lon.csv: '…,25.1' (was 25.13487) was imported 3 km off, silently."""
    rows = _fixed_rows(60)
    cut = rows[-1][: rows[-1].rindex(".") + 2]  # "…,25.1"
    path = tmp_path / "cut.csv"
    path.write_text("\n".join([_header(), *rows[:-1], cut]))
    r = _read(path, how, tmp_path)
    rep = r.report
    assert rep["rows_imported"] == 59 and rep["quarantine_reasons"] == {"cut last line": 1}
    assert r.quarantine["line"].tolist() == [61]
    assert r.quarantine["text"].tolist() == [cut]
    assert any("line 61, the file's last line" in w and "looks cut" in w for w in rep["warnings"])
    _every_line_counted(rep, 61)


@pytest.mark.parametrize("how", ["whole", "streamed"])
def test_a_whole_last_line_without_a_line_end_is_kept(tmp_path, how):
    """A file without a final line end is common: its last row, written as the others,
    is a point."""
    path = tmp_path / "ok.csv"
    path.write_text("\n".join([_header(), *_fixed_rows(60)]))
    rep = _read(path, how, tmp_path).report
    assert rep["rows_imported"] == 60 and rep["rows_quarantined"] == 0
    assert not any("looks cut" in w for w in rep["warnings"])


def test_a_column_of_varying_decimals_never_judges_its_last_value_cut(tmp_path):
    """%g writes 25.1 beside 25.13487: no evidence of a cut, nothing quarantined."""
    rows = [f"7,2024-08-09T19:00:{i:02d},37.{i:02d},{25.1 + 0.01 * (i % 7):g}" for i in range(40)]
    rows.append("7,2024-08-09T19:00:40,37.4,25.1")
    path = tmp_path / "g.csv"
    path.write_text("\n".join([_header(), *rows]))
    rep = read_points(path).report
    assert rep["rows_imported"] == 41 and rep["rows_quarantined"] == 0


def test_a_cut_last_line_of_a_file_read_in_pieces_is_quarantined(tmp_path, monkeypatch):
    """The reading in pieces (a quoted file) quarantines it in its final piece."""
    from wakeline.core.io import reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 1024)
    rows = [f'"{r}"'.replace(",", '","') for r in _fixed_rows(300)]
    cut = rows[-1][: rows[-1].rindex(".") + 3]  # no closing quote: cut inside the cell
    path = tmp_path / "q.csv"
    path.write_text("\n".join([_header(), *rows[:-1], cut]))
    r = import_to_csv(path, tmp_path / "o.csv")
    assert r.report.get("pieces", 0) > 1
    assert r.report["quarantine_reasons"] == {"cut last line": 1}
    assert r.report["rows_imported"] == 299
    _every_line_counted(r.report, 301)
    # the value as read, without the cut cell's opening quote (review h209)
    value = cut[cut.rindex('"') + 1 :]
    warned = [w for w in r.report["warnings"] if "looks cut" in w]
    assert len(warned) == 1 and f"({value!r} where" in warned[0]


def test_a_cut_value_of_a_one_decimal_column_says_1_decimal(tmp_path):
    rows = _fixed_rows(30, places=1)
    path = tmp_path / "one.csv"
    path.write_text("\n".join([_header(), *rows[:-1], rows[-1][: rows[-1].rindex(".")]]))
    rep = read_points(path).report
    assert rep["quarantine_reasons"] == {"cut last line": 1}
    warned = [w for w in rep["warnings"] if "looks cut" in w]
    assert len(warned) == 1 and "have 1 decimal at least" in warned[0]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(1, 30),
    places=st.integers(1, 6),
    keep=st.integers(-1, 6),
    end=st.sampled_from(["", "\n", "\r\n"]),
    last_col=st.sampled_from(["lon", "lat"]),
)
def test_every_line_a_point_or_a_quarantine_row_and_only_a_cut_one_quarantined(
    n, places, keep, end, last_col
):
    """A file of fixed precision whose last value keeps ``keep`` decimals (-1: the
    decimal point cut off too): quarantined exactly when the file has no final line end,
    at least 5 rows before it and fewer decimals; every line counted either way."""
    import tempfile

    rows = _fixed_rows(n + 1, places, last_col)
    last = rows[-1]
    dot = last.rindex(".")
    keep = min(keep, places)
    rows[-1] = last[:dot] if keep < 0 else last[: dot + 1 + keep]
    if keep == 0:
        rows[-1] = last[:dot]  # "25." is not written: the point goes with the digits
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "f.csv"
        path.write_text("\n".join([_header(last_col), *rows]) + end, newline="")
        rep = read_points(path).report
        _every_line_counted(rep, n + 2)
        shorter = keep < places
        expect = int(end == "" and shorter and n >= 5)
        assert rep["quarantine_reasons"].get("cut last line", 0) == expect


# --- D3 (import): time steps back within a track ---------------------------------------


def _clock_rows(n: int, back: dict[int, int], ids=("A", "B"), step: int = 60) -> list[str]:
    """Tracks interleaved row by row, ``step`` s apart; row ``i`` of each track set back by
    ``back[i]`` s (a clock set back)."""
    out = []
    for i in range(n):
        for tid in ids:
            t = 1_700_000_000 + i * step - back.get(i, 0) * (tid == ids[0])
            out.append(f"{tid},{t},{10 + 0.001 * i:.5f},{55 + 0.001 * i:.5f}")
    return out


@pytest.mark.parametrize("how", ["whole", "streamed", "pieces"])
def test_a_clock_set_back_within_a_track_is_warned_with_lines(tmp_path, how, monkeypatch):
    """f4_clock_back_10min.csv: rows set back 10 min within track 3; the import said
    nothing (restarting_tracks {}), clean then kept a 282 kn leg."""
    from wakeline.core.io import reader

    back = {k: 540 for k in range(50, 60)}  # 10 rows 9 min earlier
    rows = _clock_rows(120, back)
    if how == "pieces":
        monkeypatch.setattr(reader, "STREAM_BYTES", 2048)
        rows = [r.replace("A,", '"A",', 1) if r.startswith("A,") else r for r in rows]
    path = tmp_path / "clock.csv"
    path.write_text("id,t,lon,lat\n" + "\n".join(rows) + "\n")
    r = _read(path, how, tmp_path)
    info = r.report["time_steps_back"]
    # track A goes back once (row 50: line 2 + 2*50 = 102), then forward again
    assert info["tracks"] == {"A": 1} and info["first_lines"] == [102]
    assert info["max_s"] == pytest.approx(540 - 60)
    warned = [w for w in r.report["warnings"] if "back within a track" in w]
    assert len(warned) == 1 and "line 102" in warned[0] and "batch A" in warned[0]
    assert r.report["rows_imported"] == 240


def test_jitter_and_a_file_in_no_time_order_are_not_warned(tmp_path):
    import random

    jitter = _clock_rows(100, {k: 90 for k in range(10, 100, 10)})  # 30 s back: jitter
    path = tmp_path / "j.csv"
    path.write_text("id,t,lon,lat\n" + "\n".join(jitter) + "\n")
    assert read_points(path).report["time_steps_back"] == {}
    rows = _clock_rows(100, {})
    random.Random(3).shuffle(rows)
    path.write_text("id,t,lon,lat\n" + "\n".join(rows) + "\n")
    rep = read_points(path).report
    assert rep["time_steps_back"] == {}
    assert not any("back within a track" in w for w in rep["warnings"])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(back=st.dictionaries(st.integers(1, 79), st.integers(0, 700), max_size=6))
def test_steps_back_count_as_a_plain_count_says(back):
    """The count of steps back (jitter < back < restart, tracks mostly forward) against
    a plain loop over the rows."""
    import tempfile

    from wakeline.core.io.reader import ORDER_JITTER_S, RESTART_BACK_S

    rows = _clock_rows(80, back)
    times = [int(r.split(",")[1]) for r in rows if r.startswith("A,")]
    steps = [a - b for a, b in zip(times, times[1:], strict=False)]  # > 0: back
    loose = sum(s > ORDER_JITTER_S for s in steps)
    want = [k + 1 for k, s in enumerate(steps) if ORDER_JITTER_S < s < RESTART_BACK_S]
    if loose > 0.1 * len(steps):
        want = []  # a track in no time order: not meant
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "c.csv"
        path.write_text("id,t,lon,lat\n" + "\n".join(rows) + "\n")
        info = read_points(path).report["time_steps_back"]
    assert info.get("tracks", {}).get("A", 0) == len(want)
    assert info.get("first_lines", []) == [2 + 2 * k for k in want][:5]


def test_time_steps_back_are_counted_per_track_not_per_batch_name(tmp_path):
    """Review h209: two sensors whose tracks share the batch name '1', each with one
    clock step back: the count keyed by batch name kept one of them."""
    rows = []
    for s in ("R1", "R2"):
        for i in range(60):
            t = 1_700_000_000 + 60 * i - (300 if i == 30 else 0)
            rows.append(f"{s},1,{t},{10 + 0.001 * i:.5f},{55 + 0.001 * i:.5f}")
    path = tmp_path / "two.csv"
    path.write_text("sensor,id,t,lon,lat\n" + "\n".join(rows) + "\n")
    rep = read_points(path).report
    info = rep["time_steps_back"]
    assert info["tracks"] == {"R1:1": 1, "R2:1": 1}
    assert info["first_lines"] == [32, 92]
    warned = [w for w in rep["warnings"] if "back within a track" in w]
    assert warned and warned[0].startswith("2 time steps go back")


def test_restarting_tracks_are_counted_per_sensor_and_batch(tmp_path):
    """The same pattern in the restart count: R1's batch 1 restarts, R2's batch 1 does not."""
    rows = [f"R1,1,{60 * m},{11 + run + m * 1e-3:.4f},57.5" for run in range(3) for m in range(50)]
    rows += [f"R2,1,{60 * m},12.0,{57 + m * 1e-3:.4f}" for m in range(40)]
    path = tmp_path / "r.csv"
    path.write_text("sensor,batch,time,lon,lat\n" + "\n".join(rows) + "\n")
    assert read_points(path).report["restarting_tracks"] == {"R1:1": 3}


def _one_track_back_at(i0: int, n: int = 400, quoted: bool = False) -> str:
    """One track a minute a row, rows ``i0``..``i0 + 4`` set back 5 min."""
    rows, tid = [], '"A"' if quoted else "A"
    for i in range(n):
        t = 1_700_000_000 + 60 * i - (300 if i0 <= i < i0 + 5 else 0)
        rows.append(f"{tid},{t},{10 + 0.001 * i:.5f},{55 + 0.001 * i:.5f}")
    return "id,t,lon,lat\n" + "\n".join(rows) + "\n"


def test_a_step_back_on_a_streamed_pieces_first_row_is_seen(tmp_path, monkeypatch):
    """Review h209: each piece's count started afresh, so a step back on a piece's first
    row was lost (whole: found)."""
    from wakeline.core.io import reader

    path = tmp_path / "one.csv"
    path.write_text(_one_track_back_at(197))
    whole = read_points(path).report["time_steps_back"]
    assert whole["first_lines"] == [199]
    monkeypatch.setattr(reader, "STREAM_BYTES", 1024)  # a piece starts on line 199
    streamed = import_to_csv(path, tmp_path / "o.csv").report
    assert streamed.get("streamed")
    assert streamed["time_steps_back"] == whole
    # a key the streamed report lacked (review h209: report keys whole vs streamed)
    assert streamed["lat_beyond_90_lon_within"] == 0


def test_a_step_back_anywhere_in_a_file_read_in_pieces_is_seen(tmp_path, monkeypatch):
    """The reading in pieces (a quoted file) carries each track's last time too: wherever
    the step back falls (one of these offsets starts a piece), what a whole read says."""
    from wakeline.core.io import reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 1024)
    path = tmp_path / "q.csv"
    for i0 in range(180, 215):
        path.write_text(_one_track_back_at(i0, quoted=True))
        whole = read_points(path).report["time_steps_back"]
        assert whole["first_lines"] == [i0 + 2]
        r = import_to_csv(path, tmp_path / "o.csv").report
        assert r.get("pieces", 0) > 1
        assert r["time_steps_back"] == whole, i0


def _exports(runs: int, pad: int, quoted: bool = False) -> str:
    """``pad`` rows of a track C, then tracks A and B interleaved a minute a row, written
    ``runs`` times over (a file made of several exports: each starts the time again)."""
    out = [f"C,{1_700_000_000 + 60 * i},12.0,56.0" for i in range(pad)]
    for run in range(runs):
        for i in range(60):
            for tid in ("A", "B"):
                q = f'"{tid}"' if quoted else tid
                out.append(f"{q},{1_700_000_000 + 60 * i},{10 + run + 0.001 * i:.5f},55.0")
    return "id,t,lon,lat\n" + "\n".join(out) + "\n"


@pytest.mark.parametrize("quoted", [False, True], ids=["streamed", "pieces"])
def test_a_restart_on_a_pieces_first_row_is_seen(tmp_path, monkeypatch, quoted):
    """Session 29's leftover: a file of exports, each starting the time again, read
    streamed (or in pieces, a quoted file) at 1 kB a piece: where a piece began on a
    restart's row, that track's restart was not seen (pad 14-17 of 40: {'A': 2}, {} …).
    Each track's last time is carried into the next piece, as for the steps back: what a
    whole read says, wherever the pieces are cut, and the runs summed right."""
    from wakeline.core.io import reader

    monkeypatch.setattr(reader, "STREAM_BYTES", 1024)
    path = tmp_path / "exports.csv"
    for runs in (2, 3):
        for pad in range(0, 40, 1 if runs == 2 else 3):
            path.write_text(_exports(runs, pad, quoted))
            whole = read_points(path).report
            assert whole["restarting_tracks"] == {"A": runs, "B": runs}
            r = import_to_csv(path, tmp_path / "o.csv").report
            assert r.get("pieces", 0) > 1 if quoted else r.get("streamed")
            assert r["restarting_tracks"] == whole["restarting_tracks"], (runs, pad)
            assert r["time_steps_back"] == whole["time_steps_back"] == {}
            said = [w for w in r["warnings"] if "start their time again" in w]
            assert said == [w for w in whole["warnings"] if "start their time again" in w]


@pytest.mark.parametrize("size", [500, 2000, 8192])
def test_oresund_restarts_and_steps_back_streamed_as_whole(tmp_path, monkeypatch, size):
    """Øresund's encounters (two ships whose mmsi starts its time again, one with two
    steps back): streamed in small pieces each ship has a few rows a piece, and judged per
    piece it looked like a track in no time order (2 kB: {'265041000': 2, '219230000': 3}
    restarts and 1 step back for whole's 4, 3 and 2). Each track's steps are now counted
    over the pieces and judged once, as the whole read judges them."""
    from conftest import real_file
    from wakeline.core.io import reader

    path = real_file("oresund-encounters", "encounters.csv")
    whole = read_points(path, mapping={"batch": "mmsi"}).report
    assert whole["restarting_tracks"] == {"219230000": 3, "265041000": 4}
    assert whole["time_steps_back"]["tracks"] == {"219230000": 2}
    monkeypatch.setattr(reader, "STREAM_BYTES", size)
    r = import_to_csv(path, tmp_path / "o.csv", mapping={"batch": "mmsi"}).report
    assert r.get("streamed")
    assert r["restarting_tracks"] == whole["restarting_tracks"]
    assert r["time_steps_back"] == whole["time_steps_back"]
    assert r["warnings"] == whole["warnings"]

"""``--skip-rows N`` reaches every command that reads track files (the steps' shared
reading flags, ``wakeline batch``, ``export`` and ``evaluate --real``) as it reaches
``wakeline import``: a file with 12 lines of notes above its header (past the 10 lines
the title detection searches) reads the same everywhere, and every line is counted:
input lines = points + quarantined + skipped above the header + the header + blank lines."""

import json

import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core.clean_stream import clean_file
from wakeline.core.io import reader

NOTES = 12
ROWS = 80


def _titled_text() -> str:
    """12 lines of notes, a header naming known columns, 80 rows of two tracks (one with
    lat 95: quarantined) and a blank line among them: 95 lines."""
    notes = [f"note {k}: exported by station {k}, operator log" for k in range(NOTES)]
    rows = []
    for k in range(ROWS):
        track, step = 400 + k % 2, k // 2
        t = pd.Timestamp("2024-05-01T08:00:00") + pd.Timedelta(seconds=10 * step)
        lon, lat = 122 + step * 5e-4 + 0.1 * (k % 2), 30 + step * 1e-4
        rows.append(f"{track},{t:%Y-%m-%dT%H:%M:%S},{lon:.5f},{lat:.5f},9.5,45")
    rows[17] = rows[17].replace(",30.", ",95.", 1)  # out of range: quarantined
    rows.insert(40, "")
    return "\n".join([*notes, "track_id,time,lon,lat,speed,course", *rows]) + "\n"


@pytest.fixture
def titled(write):
    return write("titled.csv", _titled_text())


def _lines(path) -> int:
    return len(path.read_text().splitlines())


def _identity(read: dict, lines: int) -> None:
    assert read["skipped_above_header"] == NOTES
    assert read["rows_imported"] == ROWS - 1 and read["rows_quarantined"] == 1
    assert read["blank_lines"] == 1
    assert read["rows_imported"] + read["rows_quarantined"] + NOTES + 1 + 1 == lines


@pytest.mark.parametrize("whole", [False, True])
def test_clean_takes_skip_rows_streamed_and_whole(titled, tmp_path, capsys, whole, monkeypatch):
    """Without --skip-rows the header is not found (refused, the error names --skip-rows);
    with it, clean reads the rows (streamed in small pieces, and whole: --smooth) and its
    report counts the 12 skipped lines."""
    monkeypatch.setattr(reader, "STREAM_BYTES", 700)  # streamed: several pieces
    out, rep = tmp_path / "c.csv", tmp_path / "r.json"
    extra = ["--smooth"] if whole else []
    assert main(["clean", str(titled), "-o", str(out), *extra]) == 2
    assert "--skip-rows" in capsys.readouterr().err
    args = ["clean", str(titled), "-o", str(out), "--report", str(rep), "--skip-rows", "12"]
    assert main([*args, *extra]) == 0
    assert f"{NOTES} line(s) above the header skipped" in capsys.readouterr().err
    _identity(json.loads(rep.read_text())["read"], _lines(titled))
    assert len(pd.read_csv(out)) > 0
    params = None
    if whole:
        from wakeline.core.clean import CleanParams

        params = CleanParams().with_settings(["smooth.enabled=true"])
    res = clean_file(titled, tmp_path / "c2.csv", params=params, skip_rows=NOTES)
    assert res.streamed is not whole
    assert len(res.read_report["lines_above_header"]) == NOTES
    assert pd.read_csv(tmp_path / "c2.csv").equals(pd.read_csv(out))


def test_a_step_reads_with_skip_rows(titled, tmp_path, capsys):
    """maneuvers (the steps' flags are generated in one place): refused without it, the
    12 lines counted in its report's reading with it."""
    out, rep = tmp_path / "m.csv", tmp_path / "r.json"
    assert main(["maneuvers", str(titled), "-o", str(out)]) == 2
    capsys.readouterr()
    assert (
        main(["maneuvers", str(titled), "-o", str(out), "--report", str(rep), "--skip-rows", "12"])
        == 0
    )
    _identity(json.loads(rep.read_text())["read"], _lines(titled))


def test_review_and_render_take_the_reading_flags():
    """review and render read track files as the steps do: the same flags."""
    from wakeline.app.cli import build_parser

    parser = build_parser()
    for command in (
        ["review", "x.csv", "-o", "o.csv", "--proposals", "p.csv"],
        ["render", "x.csv", "-o", "o.png"],
    ):
        args = parser.parse_args([*command, "--skip-rows", "12", "--encoding", "gb18030"])
        assert args.skip_rows == 12 and args.encoding == "gb18030"


def test_batch_reads_with_skip_rows(titled, tmp_path, capsys):
    """wakeline batch: refused without it; with it the report counts every line."""
    pytest.importorskip("dask.dataframe")
    pytest.importorskip("distributed")
    from wakeline.core.pipeline import Pipeline

    pipe = tmp_path / "p.json"
    pipe.write_text(Pipeline.default().to_json(), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["batch", str(pipe), str(titled), "-o", str(out)]) == 2
    assert "--skip-rows" in capsys.readouterr().err
    # 0: written, its one bad row quarantined and counted (3 is for a refused input)
    assert main(["batch", str(pipe), str(titled), "-o", str(out), "--skip-rows", "12"]) == 0
    rep = json.loads((out / "report.json").read_text())
    assert rep["quarantined"] == 1
    assert rep["skipped_above_header"] == NOTES and rep["blank_lines"] == 1
    assert rep["quarantined"] == 1 and rep["rows_read"] == ROWS
    assert rep["rows_read"] + NOTES + 1 + rep["blank_lines"] == _lines(titled)


def _refused_naming(err: str, flag: str) -> None:
    """A reading error: one message (after any progress lines) naming the flag to give,
    not an internal error."""
    last = err.strip().splitlines()[-1]
    assert last.startswith("wakeline: error:") and flag in last
    assert "internal error" not in err and "Traceback" not in err


def test_export_reads_in_with_skip_rows(titled, tmp_path, capsys):
    """export reads IN with the steps' reading flags: refused without --skip-rows, a
    wrong count refused with the message (naming export's own --in-map, not --map, which
    is ORIGINAL's), the 12 lines skipped with it, to CSV and to GeoJSON."""
    out = tmp_path / "e.csv"
    assert main(["export", str(titled), "-o", str(out)]) == 2
    _refused_naming(capsys.readouterr().err, "--skip-rows")
    assert main(["export", str(titled), "-o", str(out), "--skip-rows", "11"]) == 2
    err = capsys.readouterr().err
    _refused_naming(err, "--skip-rows")
    assert "--in-map" in err and "with --map" not in err
    assert main(["export", str(titled), "-o", str(out), "--skip-rows", str(NOTES)]) == 0
    assert "1 row quarantined" in capsys.readouterr().err
    got = pd.read_csv(out)
    assert len(got) == ROWS - 1 and set(got["batch"]) == {400, 401}
    geo = tmp_path / "e.geojson"
    assert main(["export", str(titled), "-o", str(geo), "--skip-rows", str(NOTES)]) == 0
    assert len(json.loads(geo.read_text())["features"]) == 2


def test_export_like_an_original_with_notes_above_its_header(titled, tmp_path, capsys):
    """--like ORIGINAL whose header is below 12 lines of notes: --like-skip-rows says so
    (the refusal names it, not IN's --skip-rows); the notes are written back above the
    header and the rows in the original's columns."""
    canonical = tmp_path / "c.csv"
    assert main(["export", str(titled), "-o", str(canonical), "--skip-rows", str(NOTES)]) == 0
    capsys.readouterr()
    out = tmp_path / "like.csv"
    assert main(["export", str(canonical), "-o", str(out), "--like", str(titled)]) == 2
    _refused_naming(capsys.readouterr().err, "--like-skip-rows N")
    args = ["export", str(canonical), "-o", str(out), "--like", str(titled)]
    assert main([*args, "--like-skip-rows", str(NOTES)]) == 0
    lines = out.read_text().splitlines()
    assert lines[:NOTES] == titled.read_text().splitlines()[:NOTES]
    assert lines[NOTES] == "track_id,time,lon,lat,speed,course"
    assert len(lines) == NOTES + 1 + ROWS - 1


@pytest.mark.parametrize("kind", ["maneuver", "associate"])
def test_evaluate_real_reads_with_skip_rows(titled, capsys, kind):
    """evaluate maneuver|associate --real FILE: refused without --skip-rows or with a
    wrong count (one message naming it), scored on the 79 points with it."""
    assert main(["evaluate", kind, "--real", str(titled)]) == 2
    _refused_naming(capsys.readouterr().err, "--skip-rows")
    assert main(["evaluate", kind, "--real", str(titled), "--skip-rows", "11"]) == 2
    _refused_naming(capsys.readouterr().err, "--skip-rows")
    assert main(["evaluate", kind, "--real", str(titled), "--skip-rows", str(NOTES)]) == 0
    out = capsys.readouterr().out
    if kind == "maneuver":
        ours = next(line.split() for line in out.splitlines() if line.split()[:1] == ["ours"])
        assert int(ours[1]) == ROWS - 1  # points scored
    else:
        assert "titled.csv" in out and "ours, optimal" in out


def test_evaluate_reading_flags_need_real_and_help_says_where(capsys):
    """Without --real there is nothing to read: refused; the help says the named folders
    of shared/data/real ignore them."""
    assert main(["evaluate", "maneuver", "--skip-rows", "3"]) == 2
    assert "--real" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["evaluate", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert "--skip-rows N" in help_text and "ignore these flags" in help_text


def test_the_reading_flags_are_public():
    """The commands import the reading flags by their public names (add_read_flags,
    read_options): no module of app/ imports a private name of cli_steps."""
    import ast
    from pathlib import Path

    from wakeline.app import cli_steps

    public = {"add_read_flags", "read_options"}
    assert all(callable(getattr(cli_steps, name)) for name in public)
    assert not {"_" + name for name in public} & set(vars(cli_steps))  # no alias left
    private = []
    for path in sorted((Path(cli_steps.__file__).parent).glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module == "wakeline.app.cli_steps":
                private += [f"{path.name}: {a.name}" for a in node.names if a.name[0] == "_"]
    assert private == []


#: A headerless file of 5 rows (Unix times): 5 lines.
_BARE = "".join(f"{1714521600 + 10 * k},{10 + k * 1e-3:.3f},57.0\n" for k in range(5))
_BARE_MAP = ["--map", "time=col1", "--map", "lon=col2", "--map", "lat=col3"]


@pytest.mark.parametrize(
    "command",
    [
        ["import", "-o", "o.csv"],
        ["export", "-o", "x.csv"],
        ["clean", "-o", "c.csv"],
        ["maneuvers", "-o", "m.csv"],
        ["evaluate", "maneuver", "--real"],
    ],
)
@pytest.mark.parametrize("skip", [100, NOTES + 1 + ROWS + 1])
def test_skip_rows_past_the_end_is_refused_by_every_command(
    titled, tmp_path, capsys, command, skip
):
    """--skip-rows at or past the file's 94 lines: one message naming the flag and the
    line count, from every command that reads with it (was: clamped to the last line,
    read as the header)."""
    assert _lines(titled) == NOTES + 1 + ROWS + 1 == 94
    where = 3 if command[0] == "evaluate" else 1
    args = [*command[:where], str(titled), *command[where:]]
    args = [str(tmp_path / a) if a.endswith(".csv") else a for a in args]
    assert main([*args, "--skip-rows", str(skip)]) == 2
    err = capsys.readouterr().err
    _refused_naming(err, f"--skip-rows {skip}: the file has 94 lines")


def test_skip_rows_of_a_headerless_file(write, tmp_path, capsys):
    """A headerless 5-row file: --skip-rows 100 and 5 refused with the line count (100 was
    accepted: the last row imported, the first counted as a title, "the header is line
    -"); 4 imports the last row and says where it is."""
    bare = write("b5.csv", _BARE)
    out = str(tmp_path / "o.csv")
    for skip in (100, 5):
        assert main(["import", str(bare), "-o", out, *_BARE_MAP, "--skip-rows", str(skip)]) == 2
        _refused_naming(capsys.readouterr().err, f"--skip-rows {skip}: the file has 5 lines")
    assert main(["import", str(bare), "-o", out, *_BARE_MAP, "--skip-rows", "4"]) == 0
    err = capsys.readouterr().err
    assert "4 line(s) above the header skipped" in err and "the first row is line 5" in err
    assert len(pd.read_csv(out)) == 1


def test_skip_rows_leaving_only_the_header_or_blank_lines(write, tmp_path, capsys):
    """Two notes, a header, no rows: --skip-rows 2 leaves the header only, refused as a
    header-only file is; 3 leaves nothing. A file whose last two lines are blank:
    skipping into them is refused (the lines after are blank), skipping a blank line
    among the notes is counted as a physical line."""
    out = str(tmp_path / "o.csv")
    header = "batch,time,lon,lat"
    only = write("only.csv", f"note one\nnote two\n{header}\n")
    assert main(["import", str(only), "-o", out, "--skip-rows", "2"]) == 2
    assert "no data rows (a header only?)" in capsys.readouterr().err
    assert main(["import", str(only), "-o", out, "--skip-rows", "3"]) == 2
    _refused_naming(capsys.readouterr().err, "--skip-rows 3: the file has 3 lines")
    rows = "1,1714521600,10.0,57.0\n1,1714521610,10.001,57.0\n"
    blank = write("blank.csv", f"note\n\nnote\n{header}\n{rows}\n\n")
    assert _lines(blank) == 8
    assert main(["import", str(blank), "-o", out, "--skip-rows", "6"]) == 2
    _refused_naming(
        capsys.readouterr().err,
        "--skip-rows 6: the file has 8 lines and those after line 6 are blank",
    )
    assert main(["import", str(blank), "-o", out, "--skip-rows", "3"]) == 0
    assert len(pd.read_csv(out)) == 2


def test_skip_rows_refused_exactly_when_no_text_is_left(tmp_path):
    """For any file of notes, blank lines, a header or none, rows and trailing blank
    lines, sniff(skip_rows=k) refuses (naming the line count) exactly when the lines after
    the first k have no text, and otherwise reads."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from wakeline.core.errors import InputError
    from wakeline.core.io.sniff import sniff

    line = st.sampled_from(["", "note", "1714521600,10.0,57.0"])

    @settings(max_examples=150, deadline=None)
    @given(body=st.lists(line, min_size=1, max_size=8), header=st.booleans(), k=st.integers(0, 12))
    def check(body, header, k):
        lines = (["time,lon,lat"] if header else []) + body
        if not any(x.strip() for x in lines):
            return
        path = tmp_path / "f.csv"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        left = any(x.strip() for x in lines[k:])
        try:
            sniff(path, skip_rows=k)
        except InputError as exc:
            assert not left, str(exc)
            assert str(exc).startswith(f"--skip-rows {k}: the file has {len(lines)} line")
        else:
            assert left

    check()


def test_export_like_names_like_skip_rows_for_the_originals_count(titled, tmp_path, capsys):
    """Every refusal of ORIGINAL's count names --like-skip-rows (a negative count said
    "--skip-rows -1"); IN's own wrong count still names --skip-rows."""
    out = str(tmp_path / "x.csv")
    like = ["export", str(titled), "--like", str(titled), "-o", out]
    for count, said in (("-1", "give 0 or more lines"), ("100", "the file has 94 lines")):
        assert main([*like, "--skip-rows", str(NOTES), "--like-skip-rows", count]) == 2
        err = capsys.readouterr().err
        _refused_naming(err, f"--like-skip-rows {count}: {said}")
        assert " --skip-rows" not in err
    assert main([*like, "--skip-rows", "100", "--like-skip-rows", str(NOTES)]) == 2
    err = capsys.readouterr().err
    _refused_naming(err, "--skip-rows 100: the file has 94 lines")
    assert "--like-skip-rows" not in err
